//! Judging a tapping cycle (issue 24, item 3): the lead the machine feeds per spindle turn —
//! F / S under feed per minute, F under feed per revolution — against the tap's pitch, the
//! spindle's direction against the tap's hand, and a spindle that is not turning at all.
//!
//! A rigid tap follows the feed exactly: a lead that is not the tap's pitch drags its flanks
//! through the thread it cuts (a stripped thread, a broken tap). A floating holder takes up a
//! small difference in its spring, so there the finding rests on how much it takes: a warning.
//! The limit is the lead drift rule of translation (docs/translation.md): what the difference
//! adds up to over the tapped depth, as a pitch-diameter error (× cot of the half flank angle),
//! beyond a quarter of the class's pitch-diameter tolerance.

use super::measure::Target;
use super::{length, Note};
use crate::diag::{Code, Diagnostic, Span};
use crate::mill::motion::{Feed, Rotation, TapCycle};
use crate::mill::Hand;
use crate::thread::standard::Family;
use crate::units::Units;

/// What judging a tapping cycle is told besides the cycle.
pub struct Judging<'a> {
    /// `--thread NAME`, with the hand its name states.
    pub target: Option<(&'a Target<'a>, Hand)>,
    /// The cycle's code cuts a left-hand thread (G74, G84.3); `None` when the spindle's
    /// direction decides (G33.1).
    pub left: Option<bool>,
    pub units: Units,
    /// The F word's least increment (mm per minute or per revolution).
    pub feed_resolution: f64,
    pub span_of: &'a dyn Fn(u32) -> Span,
}

/// Every finding about one tapping cycle.
pub fn judge(t: &TapCycle, j: &Judging, out: &mut Vec<Diagnostic>, notes: &mut Vec<Note>) {
    let at = (j.span_of)(t.line);
    let name = t.code_name();
    if t.rotation == Rotation::Stopped {
        out.push(
            Diagnostic::error(
                Code::MachineState,
                at,
                format!("{name} taps with the spindle stopped (no M3 or M4 since the last M5, M19 or the program's start)"),
            )
            .with_hint("start the spindle (M3 for a right-hand tap) before the cycle"),
        );
        return;
    }
    let hand = match j.left {
        Some(true) => Hand::Left,
        Some(false) => Hand::Right,
        None if t.rotation == Rotation::Ccw => Hand::Left,
        None => Hand::Right,
    };
    direction(t, j, hand, at, out);
    let Some(lead) = lead_of(t) else {
        out.push(Diagnostic::error(
            Code::Tapping,
            at,
            format!("{name} with no spindle speed: under feed per minute its lead is F / S, and S is not programmed"),
        ));
        return;
    };
    let u = j.units;
    let place = if t.code == 0 {
        String::new()
    } else {
        format!(
            " at X{} Y{}",
            length(u, t.position[0]),
            length(u, t.position[1])
        )
    };
    let mut said = format!(
        "{name}{place}: {} tap, lead {} per turn ({}), {}",
        match hand {
            Hand::Right => "right-hand",
            Hand::Left => "left-hand",
        },
        length(u, lead),
        match t.feed {
            Feed::PerMinute(f) => format!(
                "F{} / S{}",
                length(u, f),
                super::number(t.rpm.unwrap_or(0.0))
            ),
            _ => "F per revolution".to_string(),
        },
        if t.rigid { "rigid" } else { "floating holder" }
    );
    match j.target {
        Some((target, named)) => {
            if named != hand {
                out.push(Diagnostic::error(
                    Code::Tapping,
                    at,
                    format!(
                        "{name} cuts a {} thread and {} is {}",
                        hand.name(),
                        target.name,
                        named.name()
                    ),
                ));
            }
            against_pitch(t, j, lead, target, at, out);
        }
        None => {
            if let Some(d) = near_a_pitch(t, j, lead, at) {
                out.push(d);
            }
            said += " (the tap's pitch is not named: --thread)";
        }
    }
    notes.push(Note::new(at, said));
}

/// The spindle's direction against the tap's hand: going in, a right-hand tap turns clockwise
/// (M3), a left-hand one counter-clockwise (M4). The Fanuc family's manuals: before G84 the
/// spindle is turned clockwise with an M code, before G74 counter-clockwise.
fn direction(t: &TapCycle, j: &Judging, hand: Hand, at: Span, out: &mut Vec<Diagnostic>) {
    let Some(left) = j.left else { return };
    let wants = if left { Rotation::Ccw } else { Rotation::Cw };
    if t.rotation != wants {
        out.push(
            Diagnostic::error(
                Code::Tapping,
                at,
                format!(
                    "{} is a {} tapping cycle and the spindle turns {} ({}): the tap screws in backwards",
                    t.code_name(),
                    hand.name(),
                    match t.rotation {
                        Rotation::Cw => "clockwise",
                        _ => "counter-clockwise",
                    },
                    if t.rotation == Rotation::Cw { "M3" } else { "M4" }
                ),
            )
            .with_hint(if left {
                "G74 (and G84.3) tap with M4 in force"
            } else {
                "G84 (and G84.2) tap with M3 in force"
            }),
        );
    }
}

/// The machine's lead per spindle turn.
fn lead_of(t: &TapCycle) -> Option<f64> {
    match t.feed {
        Feed::PerRev(f) => Some(f),
        Feed::PerMinute(f) => t.rpm.filter(|&s| s > 0.0).map(|s| f / s),
        Feed::Unknown => None,
    }
}

/// The lead against the named tap's pitch, by what the difference adds up to over the depth.
fn against_pitch(
    t: &TapCycle,
    j: &Judging,
    lead: f64,
    target: &Target,
    at: Span,
    out: &mut Vec<Diagnostic>,
) {
    let pitch = target.thread.pitch;
    let depth = (t.r - t.bottom).abs();
    // Over `depth` the tap turns depth / lead times; each turn it is fed lead − pitch more than
    // its own thread carries it.
    let drift = depth / lead * (lead - pitch).abs();
    let cot = 1.0 / (target.angle_deg.to_radians() / 2.0).tan();
    let limit = target
        .limits
        .pitch
        .min
        .zip(target.limits.pitch.max)
        .map(|(lo, hi)| (hi - lo) / 4.0);
    let over = match limit {
        Some(l) => drift * cot > l,
        None => (lead - pitch).abs() > j.feed_resolution,
    };
    if !over {
        return;
    }
    let u = j.units;
    let msg = format!(
        "{} feeds {} per spindle turn and {} has a pitch of {}: over the {} tapped the feed {} {} {} the tap ({} on the pitch diameter{})",
        t.code_name(),
        length(u, lead),
        target.name,
        length(u, pitch),
        length(u, depth),
        if lead > pitch { "runs" } else { "falls" },
        length(u, drift),
        if lead > pitch { "ahead of" } else { "behind" },
        length(u, drift * cot),
        limit.map_or(String::new(), |l| format!(", a quarter of the class's tolerance is {}", length(u, l)))
    );
    let hint = match t.feed {
        Feed::PerMinute(_) => format!(
            "F = pitch × S: F{}",
            length(u, pitch * t.rpm.unwrap_or(0.0))
        ),
        _ => format!(
            "F = the pitch under feed per revolution: F{}",
            length(u, pitch)
        ),
    };
    out.push(if t.rigid {
        Diagnostic::error(Code::Tapping, at, msg).with_hint(hint)
    } else {
        Diagnostic::warning(
            Code::TappingAssumed,
            at,
            format!("{msg} (assumed: the floating holder does not take it up)"),
        )
        .with_hint(hint)
    });
}

/// Without a named tap: a lead a little off a standard pitch (within 3 %, not within the F word's
/// increment) is most likely a wrong F or S.
fn near_a_pitch(t: &TapCycle, j: &Judging, lead: f64, at: Span) -> Option<Diagnostic> {
    let (pitch, family) = nearest_pitch(lead)?;
    let off = (lead - pitch).abs();
    if off <= j.feed_resolution.max(1e-9) * 1.5 || off > 0.03 * pitch {
        return None;
    }
    let u = j.units;
    Some(Diagnostic::warning(
        Code::TappingAssumed,
        at,
        format!(
            "{} feeds {} per spindle turn, {:.1} % off the {} pitch {} (assumed: the tap is that pitch; --thread names it)",
            t.code_name(),
            length(u, lead),
            100.0 * off / pitch,
            match family {
                Family::Unified => "Unified",
                _ => "ISO metric",
            },
            length(u, pitch)
        ),
    ))
}

/// The standard pitch nearest a lead (mm): ISO 261's pitches and the Unified series' threads per
/// inch (ASME B1.1's UNC, UNF, UNEF and 8-, 12-, 16-UN).
fn nearest_pitch(lead: f64) -> Option<(f64, Family)> {
    const ISO: [f64; 21] = [
        0.2, 0.25, 0.3, 0.35, 0.4, 0.45, 0.5, 0.6, 0.7, 0.75, 0.8, 1.0, 1.25, 1.5, 1.75, 2.0, 2.5,
        3.0, 3.5, 4.0, 4.5,
    ];
    let metric = ISO.iter().map(|&p| (p, Family::Metric));
    const TPI: [f64; 26] = [
        80.0, 72.0, 64.0, 56.0, 48.0, 44.0, 40.0, 36.0, 32.0, 28.0, 24.0, 20.0, 18.0, 16.0, 14.0,
        13.0, 12.0, 11.0, 10.0, 9.0, 8.0, 7.0, 6.0, 5.0, 4.5, 4.0,
    ];
    let unified = TPI.iter().map(|&n| (25.4 / n, Family::Unified));
    metric
        .chain(unified)
        .min_by(|a, b| (a.0 - lead).abs().total_cmp(&(b.0 - lead).abs()))
}

/// A lathe's tap on the centre line: a thread whose synchronised moves all lie on X0 (a tap
/// held in the turret, fed with G32/G33 and backed out with the spindle reversed), as the
/// milling reader's cycles give it: its first synchronised move's depth, lead per turn (G32's F
/// is the lead), speed and the spindle's direction going in. `None` for any other thread.
pub fn centre_line_tap(
    t: &crate::threads::Thread,
    rpm: Option<f64>,
    rotation: Rotation,
    resolution_mm: f64,
) -> Option<TapCycle> {
    use crate::toolpath::MotionKind;
    let mut syncs = t.path.segments().filter_map(|(from, m)| match m.kind {
        MotionKind::Thread { lead, .. } => Some((from, m, lead)),
        _ => None,
    });
    let (from, first, lead) = syncs.next()?;
    let on_axis = |x: f64| x.abs() <= resolution_mm;
    let all_on_axis = on_axis(from.x)
        && on_axis(first.to.x)
        && syncs.all(|(f, m, _)| on_axis(f.x) && on_axis(m.to.x));
    (all_on_axis && (first.to.z - from.z).abs() > resolution_mm).then_some(TapCycle {
        position: [0.0, 0.0, from.z],
        r: from.z,
        bottom: first.to.z,
        feed: Feed::PerRev(lead),
        rpm,
        rotation,
        rigid: true,
        peck: None,
        dwell: None,
        code: 0,
        line: first.line,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::measure::target;
    use crate::thread::standard::{lookup, Surface};

    fn span_of(line: u32) -> Span {
        Span::at_line(line)
    }

    fn tap(feed: Feed, rpm: Option<f64>, rotation: Rotation, code: u16, rigid: bool) -> TapCycle {
        TapCycle {
            position: [10.0, 20.0, 2.0],
            r: 2.0,
            bottom: -18.0,
            feed,
            rpm,
            rotation,
            rigid,
            peck: None,
            dwell: None,
            code,
            line: 7,
        }
    }

    fn found(
        t: &TapCycle,
        name: Option<(&str, Hand)>,
        left: Option<bool>,
    ) -> (Vec<Code>, Vec<String>, Vec<String>) {
        let std = name.map(|(n, _)| lookup(n).unwrap());
        let tg = std.as_ref().map(|s| target(s, Surface::Internal).unwrap());
        let j = Judging {
            target: tg.as_ref().zip(name.map(|n| n.1)),
            left,
            units: Units::Mm,
            feed_resolution: 0.001,
            span_of: &span_of,
        };
        let (mut out, mut notes) = (Vec::new(), Vec::new());
        judge(t, &j, &mut out, &mut notes);
        (
            out.iter().map(|d| d.code).collect(),
            out.into_iter().map(|d| d.message).collect(),
            notes.into_iter().map(|n| n.message).collect(),
        )
    }

    #[test]
    fn feed_equal_to_pitch_times_speed_is_right() {
        // M10x1.5 at S800: F = 1.5 × 800 = 1200 mm/min.
        let t = tap(
            Feed::PerMinute(1200.0),
            Some(800.0),
            Rotation::Cw,
            840,
            true,
        );
        let (codes, _, notes) = found(&t, Some(("M10x1.5-6H", Hand::Right)), Some(false));
        assert!(codes.is_empty());
        assert!(
            notes[0].contains("right-hand tap, lead 1.5 per turn (F1200 / S800), rigid"),
            "{notes:?}"
        );
        // Under feed per revolution F is the lead itself.
        let t = tap(Feed::PerRev(1.5), Some(800.0), Rotation::Cw, 840, true);
        assert!(found(&t, Some(("M10x1.5-6H", Hand::Right)), Some(false))
            .0
            .is_empty());
    }

    #[test]
    fn the_classic_broken_tap_feed_off_the_pitch() {
        // F1190 at S800: 1.4875 per turn. Over the 20 mm tapped: 20 / 1.4875 × 0.0125 = 0.1681
        // behind the tap, × cot 30° = 0.2911 on the pitch diameter; 6H's TD2 for M10x1.5 is
        // 0.180, a quarter 0.045: an error (rigid), a warning with a floating holder.
        let t = tap(
            Feed::PerMinute(1190.0),
            Some(800.0),
            Rotation::Cw,
            840,
            true,
        );
        let (codes, msgs, _) = found(&t, Some(("M10x1.5-6H", Hand::Right)), Some(false));
        assert_eq!(codes, [Code::Tapping]);
        assert!(
            msgs[0].contains("feeds 1.4875 per spindle turn"),
            "{msgs:?}"
        );
        assert!(msgs[0].contains("the feed falls 0.1681 behind the tap (0.2911 on the pitch diameter, a quarter of the class's tolerance is 0.045)"), "{msgs:?}");
        let floating = TapCycle { rigid: false, ..t };
        assert_eq!(
            found(&floating, Some(("M10x1.5-6H", Hand::Right)), Some(false)).0,
            [Code::TappingAssumed]
        );
        // F1199 at S800: 1.49875, 0.0167 over the depth × 1.732 = 0.029 < 0.045: within.
        let t = tap(
            Feed::PerMinute(1199.0),
            Some(800.0),
            Rotation::Cw,
            840,
            true,
        );
        assert!(found(&t, Some(("M10x1.5-6H", Hand::Right)), Some(false))
            .0
            .is_empty());
    }

    #[test]
    fn spindle_direction_hand_and_a_stopped_spindle() {
        let t = tap(
            Feed::PerMinute(1200.0),
            Some(800.0),
            Rotation::Ccw,
            840,
            true,
        );
        let (codes, msgs, _) = found(&t, None, Some(false));
        assert_eq!(codes, [Code::Tapping]);
        assert!(msgs[0].contains(
            "G84 is a right-hand tapping cycle and the spindle turns counter-clockwise (M4)"
        ));
        // G74 under M4 is a left-hand tap: named M10x1.5-LH it is right; named right-hand not.
        let t = tap(
            Feed::PerMinute(1200.0),
            Some(800.0),
            Rotation::Ccw,
            740,
            true,
        );
        assert!(found(&t, Some(("M10x1.5-6H", Hand::Left)), Some(true))
            .0
            .is_empty());
        assert_eq!(
            found(&t, Some(("M10x1.5-6H", Hand::Right)), Some(true)).0,
            [Code::Tapping]
        );
        // G33.1: the spindle decides the hand.
        let t = tap(Feed::PerRev(1.5), Some(800.0), Rotation::Ccw, 331, true);
        let (codes, _, notes) = found(&t, None, None);
        assert!(
            codes.is_empty() && notes[0].contains("G33.1 at X10 Y20: left-hand tap"),
            "{notes:?}"
        );
        let t = tap(
            Feed::PerMinute(1200.0),
            Some(800.0),
            Rotation::Stopped,
            840,
            true,
        );
        assert_eq!(found(&t, None, Some(false)).0, [Code::MachineState]);
        let t = tap(Feed::PerMinute(1200.0), None, Rotation::Cw, 840, true);
        assert_eq!(found(&t, None, Some(false)).0, [Code::Tapping]);
    }

    #[test]
    fn without_a_named_tap_a_lead_just_off_a_standard_pitch_is_a_warning() {
        // F1180 at S800 = 1.475, 1.7 % off 1.5.
        let t = tap(
            Feed::PerMinute(1180.0),
            Some(800.0),
            Rotation::Cw,
            840,
            true,
        );
        let (codes, msgs, _) = found(&t, None, Some(false));
        assert_eq!(codes, [Code::TappingAssumed]);
        assert!(
            msgs[0].contains("1.7 % off the ISO metric pitch 1.5"),
            "{msgs:?}"
        );
        // 1/4-20 at S500: F 635 mm/min is 1.27 exactly: nothing.
        let t = tap(Feed::PerMinute(635.0), Some(500.0), Rotation::Cw, 840, true);
        assert!(found(&t, None, Some(false)).0.is_empty());
    }
}
