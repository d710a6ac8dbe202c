//! Judging a milled thread (issue 24, item 4): the helix itself (every turn the same lead,
//! passes about one axis advancing alike, compensation on the side that removes material, entry
//! and exit arcs clear of the finished thread) and, with `--thread`, the thread it makes against
//! the class (pitch, hand, the root the cutter reaches, the pitch diameter with the tool's form).
//! Facts are errors; what rests on an assumption is a warning that names it.

use super::measure::{pitch_diameter_at_root, Target};
use super::{length, Note};
use crate::diag::{Code, Diagnostic, Span};
use crate::mill::motion::{MillKind, MillMotion};
use crate::mill::recognise::{Helix, Known, MilledThread};
use crate::mill::{Direction, Hand, Side};
use crate::sim::{Tip, Tool};
use crate::thread::standard::Surface;
use crate::units::Units;

/// What judging a milled thread is told besides the thread.
pub struct Judging<'a> {
    /// `--thread NAME`, with the hand its name states (`…-LH`).
    pub target: Option<(&'a Target<'a>, Hand)>,
    /// The tool's tip as given (`--tip-flat`, `--nose-radius`).
    pub tip: Option<Tip>,
    /// The program's least increment (mm).
    pub resolution: f64,
    /// Program units, for messages.
    pub units: Units,
    /// The measuring wire one owns (mm).
    pub wire: Option<f64>,
    /// Where a line is written.
    pub span_of: &'a dyn Fn(u32) -> Span,
    /// What F drives under cutter compensation (the profile's `comp_feed`).
    pub feed_reference: crate::mill::profile::FeedReference,
}

/// Every finding about one milled thread; `before` is the thread milled just before it.
pub fn judge(
    t: &MilledThread,
    before: Option<&MilledThread>,
    j: &Judging,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let at = (j.span_of)(t.helices[0].lines.0);
    even_turns(t, j, out);
    same_lead_as_before(t, before, j, out);
    compensation_side(t, at, out);
    entries(t, j, out);
    if let Some((target, hand)) = j.target {
        against_class(t, target, hand, j, at, out, notes);
    }
    notes.push(Note::new(at, summary(t, j)));
    if let Some(n) = edge_feed(t, j) {
        notes.push(Note::new(
            (j.span_of)(t.helices.last().map_or(0, |h| h.lines.0)),
            n,
        ));
    }
}

/// The feed at the cutting edge of the last pass against the F programmed, where F drives the
/// tool centre (without compensation, or a control whose F is the centre's under it): the edge
/// runs on the thread's root, at F·R_root / R_centre — faster inside a bore, slower round a
/// cylinder (the arc-feed compensation `threadcut mill` applies, docs/milling.md).
fn edge_feed(t: &MilledThread, j: &Judging) -> Option<String> {
    use crate::mill::motion::Feed;
    use crate::mill::profile::FeedReference;
    let h = t.helices.last()?;
    let Feed::PerMinute(f) = h.feed else {
        return None;
    };
    let root = t.root_diameter? / 2.0;
    let (side, _) = t.side?;
    let centre = match h.comp {
        crate::mill::motion::Comp::Off => h.radius,
        _ if j.feed_reference == FeedReference::Contour => return None,
        // The path is the contour: the centre is a cutter's radius inside (a bore) or outside.
        _ => {
            let r = h.cutter? / 2.0;
            match side {
                Side::Internal => h.radius - r,
                Side::External => h.radius + r,
            }
        }
    };
    if centre <= 0.0 {
        return None;
    }
    let u = j.units;
    let per_min = |mm: f64| format!("{} {}/min", length(u, mm), u.name());
    Some(format!(
        "the helix's F{} at line {} drives the tool centre (radius {}); the cutting edge on the root Ø{} runs at {} (×{})",
        length(u, f),
        h.lines.0,
        length(u, centre),
        length(u, 2.0 * root),
        per_min(f * root / centre),
        super::number(root / centre)
    ))
}

/// A turn whose advance differs from the thread's lead by more than the program can write.
fn even_turns(t: &MilledThread, j: &Judging, out: &mut Vec<Diagnostic>) {
    let tol = 1.5 * j.resolution;
    let wrong: Vec<_> = t
        .helices
        .iter()
        .flat_map(|h| h.arcs.iter())
        .filter(|a| (a.advance.abs() - t.lead * a.turns).abs() > tol)
        .collect();
    let Some(first) = wrong.first() else { return };
    let u = j.units;
    let others = match wrong.len() {
        1 => String::new(),
        n => format!(" ({} more turns off the lead)", n - 1),
    };
    out.push(
        Diagnostic::error(
            Code::Helix,
            (j.span_of)(first.line),
            format!(
                "this arc advances {} over {} turn{}, {} per turn, and the thread's lead is {}: its flanks leave the helix{others}",
                length(u, first.advance.abs()),
                super::number(first.turns),
                if (first.turns - 1.0).abs() < 1e-9 { "" } else { "s" },
                length(u, first.lead()),
                length(u, t.lead)
            ),
        )
        .with_hint("write each turn's Z from the thread's start and the lead (TB029: computed, never accumulated from a rounded increment)"),
    );
}

/// Passes about the same axis with another lead: the thread cut twice, out of step.
fn same_lead_as_before(
    t: &MilledThread,
    before: Option<&MilledThread>,
    j: &Judging,
    out: &mut Vec<Diagnostic>,
) {
    let Some(b) = before else { return };
    let same_axis = b.plane == t.plane
        && (b.axis[0] - t.axis[0]).abs() <= j.resolution
        && (b.axis[1] - t.axis[1]).abs() <= j.resolution;
    if !same_axis || (b.lead - t.lead).abs() <= 2.0 * j.resolution && b.hand == t.hand {
        return;
    }
    let u = j.units;
    out.push(Diagnostic::error(
        Code::Helix,
        (j.span_of)(t.helices[0].lines.0),
        format!(
            "this helix advances {} per turn ({}), and the passes before it about the same axis {} per turn ({}, line {}): the thread is cut twice, out of step",
            length(u, t.lead),
            t.hand.name(),
            length(u, b.lead),
            b.hand.name(),
            b.helices[0].lines.0
        ),
    ));
}

/// Compensation that puts the cutter on the other side of the path than the material.
fn compensation_side(t: &MilledThread, at: Span, out: &mut Vec<Diagnostic>) {
    let s = t.sides;
    let Some(comp) = s.compensation else { return };
    let other = [
        (s.given, "given (--internal/--external)"),
        (s.entry, "where the tool came in from"),
        (s.passes, "the passes' radii"),
    ]
    .into_iter()
    .find_map(|(side, how)| side.filter(|&x| x != comp).map(|x| (x, how)));
    let Some((side, how)) = other else { return };
    let h = &t.helices[0];
    let code = if h.clockwise { "G2" } else { "G3" };
    let g4x = match h.comp {
        crate::mill::motion::Comp::Left { .. } => "G41",
        _ => "G42",
    };
    // The cutter inside the circle (G41 with G3, G42 with G2) is an internal thread's side.
    let inside = comp == Side::Internal;
    out.push(
        Diagnostic::error(
            Code::Helix,
            at,
            format!(
                "{g4x} with {code} keeps the cutter {} the programmed circle, as for an {} thread, and the thread is {} ({how}): the compensation is on the wrong side and cuts the wall a cutter's diameter from the contour",
                if inside { "inside" } else { "outside" },
                side_name(comp),
                side_name(side)
            ),
        )
        .with_hint("an internal thread milled with G3 takes G41, with G2 G42; an external one the reverse (TB029)"),
    );
}

/// The entry and exit of each pass: an arc that reaches past the finished thread gouges it; a
/// straight move onto the finished radius leaves a mark.
fn entries(t: &MilledThread, j: &Judging, out: &mut Vec<Diagnostic>) {
    let Some((side, _)) = t.side else { return };
    let last_radius = t.helices.last().map_or(0.0, |h| h.radius);
    for h in &t.helices {
        for m in [h.entry, h.exit].into_iter().flatten() {
            if let Some(d) = gouge(t, side, last_radius, &m, j) {
                out.push(d);
                return;
            }
        }
    }
    let finished = t
        .helices
        .iter()
        .filter(|h| (h.radius - last_radius).abs() <= j.resolution);
    for h in finished {
        let Some(m) = h.entry.filter(|m| straight_onto(m, h)) else {
            continue;
        };
        out.push(
            Diagnostic::warning(
                Code::HelixAssumed,
                (j.span_of)(m.line),
                "a straight move onto the finished thread's radius: where it meets the flank the cutter dwells and leaves a mark (assumed: no spring pass follows)",
            )
            .with_hint("enter along an arc tangent to the helix (threadcut mill's default lead-in), or take the last pass twice"),
        );
        return;
    }
}

/// An entry or exit arc (about another centre) that reaches beyond the thread's root.
fn gouge(
    t: &MilledThread,
    side: Side,
    root: f64,
    m: &MillMotion,
    j: &Judging,
) -> Option<Diagnostic> {
    let MillKind::Arc { centre, plane, .. } = m.kind else {
        return None;
    };
    let (_, sweep) = m.sweep(j.resolution)?;
    let (a, b, _) = plane.axes();
    let r0 = (m.from[a] - centre[a]).hypot(m.from[b] - centre[b]);
    let start = (m.from[b] - centre[b]).atan2(m.from[a] - centre[a]);
    let far = (0..=64)
        .map(|k| {
            let th = start + sweep * f64::from(k) / 64.0;
            let (x, y) = (centre[a] + r0 * th.cos(), centre[b] + r0 * th.sin());
            (x - t.axis[0]).hypot(y - t.axis[1])
        })
        .fold(
            if side == Side::Internal {
                0.0
            } else {
                f64::MAX
            },
            |acc, r| {
                if side == Side::Internal {
                    acc.max(r)
                } else {
                    acc.min(r)
                }
            },
        );
    let past = match side {
        Side::Internal => far - root,
        Side::External => root - far,
    };
    (past > j.resolution).then(|| {
        Diagnostic::error(
            Code::Helix,
            (j.span_of)(m.line),
            format!(
                "this arc reaches {} from the thread's axis, {} past the finished thread's radius {}: it gouges the thread",
                length(j.units, far),
                length(j.units, past),
                length(j.units, root)
            ),
        )
        .with_hint("a lead-in arc's radius is at most half the thread's (internal), and it must end tangent to the helix")
    })
}

/// A straight feed that ends on the helix's start, coming along the radius.
fn straight_onto(m: &MillMotion, h: &Helix) -> bool {
    matches!(m.kind, MillKind::Feed)
        && m.to
            .iter()
            .zip(h.start.iter())
            .all(|(a, b)| (a - b).abs() < 1e-6)
}

/// Pitch, hand, root and pitch diameter against the class.
fn against_class(
    t: &MilledThread,
    target: &Target,
    hand: Hand,
    j: &Judging,
    at: Span,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) {
    let u = j.units;
    let pitch = target.thread.pitch;
    if (t.pitch - pitch).abs() > 1.5 * j.resolution {
        out.push(Diagnostic::error(
            Code::OutOfClass,
            at,
            format!(
                "the helix advances {} per turn with {}: a pitch of {}, and {} has {}",
                length(u, t.lead),
                crate::text::count(t.starts as usize, "start", "starts"),
                length(u, t.pitch),
                target.name,
                length(u, pitch)
            ),
        ));
        return;
    }
    if t.hand != hand {
        out.push(Diagnostic::error(
            Code::OutOfClass,
            at,
            format!(
                "the helix is {} ({} {}), and {} is {}",
                t.hand.name(),
                if t.helices[0].clockwise { "G2" } else { "G3" },
                match t.direction {
                    Direction::BottomUp => "rising",
                    Direction::TopDown => "falling",
                },
                target.name,
                hand.name()
            ),
        ));
    }
    let Some((side, how)) = t.side else {
        notes.push(Note::new(at, "the thread's diameters are not judged: whether it is internal or external is not known (--internal, --external)"));
        return;
    };
    let surface = match side {
        Side::Internal => Surface::Internal,
        Side::External => Surface::External,
    };
    if target.side != surface {
        notes.push(Note::new(
            at,
            format!(
                "the thread is {} ({}), and {} is a class of {} threads: not judged",
                side_name(side),
                known_name(how),
                target.name,
                side_name(if target.side == Surface::Internal {
                    Side::Internal
                } else {
                    Side::External
                })
            ),
        ));
        return;
    }
    let Some(root) = t.root_diameter else {
        notes.push(Note::new(at, "the thread's diameters are not judged: the cutter's diameter is not known (--tool-diameter)"));
        return;
    };
    root_against_class(root, target, surface, j, at, out);
    let tool = Tool {
        angle_deg: target.angle_deg,
        tip: j.tip.unwrap_or(target.root_tool),
    };
    let Some(pd) = pitch_diameter_at_root(root, surface, &tool, pitch) else {
        return;
    };
    let (lo, hi) = (target.limits.pitch.min, target.limits.pitch.max);
    let outside =
        lo.is_some_and(|l| pd < l - j.resolution) || hi.is_some_and(|h| pd > h + j.resolution);
    if outside {
        let msg = format!(
            "the pitch diameter the cutter makes is {} and {} allows {}–{} {}",
            length(u, pd),
            target.name,
            lo.map_or("…".into(), |l| length(u, l)),
            hi.map_or("…".into(), |h| length(u, h)),
            u.name()
        );
        out.push(match j.tip {
            Some(_) => Diagnostic::error(Code::OutOfClass, at, msg),
            None => Diagnostic::warning(
                Code::OutOfClassAssumed,
                at,
                format!("{msg} (assumed: the tooth's tip is the standard's root form; --tip-flat or --nose-radius give the real one)"),
            ),
        });
    }
    if let Some(m) = super::standard::what_is_measured(target, surface, pd, j.wire) {
        notes.push(Note::new(at, m));
    }
}

/// The root the cutter reaches against the class: an internal thread's major diameter has a
/// minimum, an external one's minor diameter (d3) a maximum.
fn root_against_class(
    root: f64,
    target: &Target,
    side: Surface,
    j: &Judging,
    at: Span,
    out: &mut Vec<Diagnostic>,
) {
    let u = j.units;
    let l = &target.limits;
    let bad = match side {
        Surface::Internal => l.major.min.filter(|&m| root < m - j.resolution).map(|m| {
            format!(
                "the major diameter the cutter reaches is {}, below the {} minimum of {}",
                length(u, root),
                target.name,
                length(u, m)
            )
        }),
        Surface::External => l.minor.max.filter(|&m| root > m + j.resolution).map(|m| {
            format!(
                "the minor diameter the cutter reaches is {}, above the {} maximum of {}",
                length(u, root),
                target.name,
                length(u, m)
            )
        }),
    };
    if let Some(msg) = bad {
        out.push(Diagnostic::error(Code::OutOfClass, at, msg));
    }
}

/// The note that says what was recognised.
fn summary(t: &MilledThread, j: &Judging) -> String {
    let u = j.units;
    let radii = t.pass_radii(j.resolution);
    let mut s = format!(
        "milled thread about X{} Y{}: lead {}, {}, {}, {}, {} from Z{} to Z{}",
        length(u, t.axis[0]),
        length(u, t.axis[1]),
        length(u, t.lead),
        crate::text::count(t.starts as usize, "start", "starts"),
        t.hand.name(),
        match t.direction {
            Direction::BottomUp => "bottom-up",
            Direction::TopDown => "top-down",
        },
        crate::text::count(radii.len(), "radial pass", "radial passes"),
        length(u, t.from),
        length(u, t.to),
    );
    match t.side {
        Some((side, how)) => s += &format!("; {} ({})", side_name(side), known_name(how)),
        None => s += "; internal or external not known",
    }
    if let Some(root) = t.root_diameter {
        let what = match t.side {
            Some((Side::Internal, _)) => "major",
            _ => "minor",
        };
        s += &format!("; {what} diameter cut {}", length(u, root));
    }
    match t.climb {
        Some(true) => s += "; climb milling",
        Some(false) => s += "; conventional milling",
        None => s += "; the spindle's direction not known (climb or conventional)",
    }
    s
}

fn side_name(s: Side) -> &'static str {
    match s {
        Side::Internal => "internal",
        Side::External => "external",
    }
}

fn known_name(k: Known) -> &'static str {
    match k {
        Known::Given => "as given",
        Known::Compensation => "from the compensation",
        Known::Entry => "from where the tool came in",
        Known::Passes => "from the passes' radii",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::check::measure::target;
    use crate::mill::motion::Comp;
    use crate::mill::recognise::testing::{helix, line};
    use crate::mill::recognise::{threads, Options};
    use crate::thread::standard::lookup;

    fn span_of(line: u32) -> Span {
        Span::at_line(line)
    }

    /// Findings (code, line) and notes of the threads in `moves`, judged against `name`.
    fn judged(
        moves: &[MillMotion],
        name: Option<(&str, Hand)>,
        o: Options,
    ) -> (Vec<(Code, u32)>, Vec<String>) {
        let ts = threads(moves, o);
        assert!(!ts.is_empty(), "no thread recognised");
        let std = name.map(|(n, _)| lookup(n).unwrap());
        let mut out = Vec::new();
        let mut notes = Vec::new();
        let mut before = None;
        for t in &ts {
            let surface = match t.side.map(|s| s.0) {
                Some(Side::External) => Surface::External,
                _ => Surface::Internal,
            };
            let tg = std.as_ref().map(|s| target(s, surface).unwrap());
            let j = Judging {
                target: tg.as_ref().zip(name.map(|n| n.1)),
                tip: None,
                resolution: 0.001,
                units: Units::Mm,
                wire: None,
                span_of: &span_of,
                feed_reference: crate::mill::profile::FeedReference::Centre,
            };
            judge(t, before, &j, &mut out, &mut notes);
            before = Some(t);
        }
        (
            out.iter().map(|d| (d.code, d.span.line)).collect(),
            notes.into_iter().map(|n| n.message).collect(),
        )
    }

    const G41: Comp = Comp::Left { d: Some(4) };

    #[test]
    fn a_good_internal_thread_under_compensation() {
        // M20x2.5-6H milled on its major diameter Ø20 under G41 with G3 rising: the root at the
        // 6H minimum, and with the standard's root flat P/8 = 0.3125 the pitch diameter is
        // 20 − 2·(1.25 − 0.3125)/(2·tan 30°) = 18.3762, the basic D2 (6H: TD2 0.224, 18.376–18.6).
        let mut moves = vec![line([0.0, 0.0, -20.0], [10.0, 0.0, -20.0], G41)];
        moves.extend(helix([0.0, 0.0], 10.0, -20.0, 2.5, 8, false, G41));
        let (found, notes) = judged(
            &moves,
            Some(("M20x2.5-6H", Hand::Right)),
            Options::default(),
        );
        assert_eq!(
            found,
            [(Code::HelixAssumed, 0)],
            "only the straight entry's mark: {notes:?}"
        );
        let all = notes.join("\n");
        assert!(
            all.contains("lead 2.5, 1 start, right-hand, bottom-up, 1 radial pass from Z0 to Z-20"),
            "{all}"
        );
        assert!(
            all.contains(
                "internal (from where the tool came in); major diameter cut 20; climb milling"
            ),
            "{all}"
        );
        assert!(
            all.contains("6H allows a pitch diameter of 18.376–18.6 mm"),
            "{all}"
        );
    }

    #[test]
    fn a_root_short_of_the_class_and_a_wrong_pitch_and_hand() {
        let moves = helix([0.0, 0.0], 9.9, -20.0, 2.5, 8, false, G41);
        // Ø19.8 < 20 (6H's major minimum): an error; the pitch diameter 18.176 < 18.376 rests on
        // the tip assumed: a warning.
        let (found, _) = judged(
            &moves,
            Some(("M20x2.5-6H", Hand::Right)),
            Options::default(),
        );
        assert_eq!(
            found,
            [(Code::OutOfClass, 10), (Code::OutOfClassAssumed, 10)]
        );
        let (found, _) = judged(
            &moves,
            Some(("M20x1.5-6H", Hand::Right)),
            Options::default(),
        );
        assert_eq!(found, [(Code::OutOfClass, 10)], "pitch 2.5 against 1.5");
        let moves = helix([0.0, 0.0], 10.0, -20.0, 2.5, 8, false, G41);
        let (found, _) = judged(&moves, Some(("M20x2.5-6H", Hand::Left)), Options::default());
        assert_eq!(
            found,
            [(Code::OutOfClass, 10)],
            "a right-hand helix for a left-hand thread"
        );
    }

    #[test]
    fn a_turn_off_the_lead_and_passes_out_of_step() {
        let mut moves = helix([0.0, 0.0], 10.0, -20.0, 2.5, 8, false, G41);
        // Line 14: the fifth turn rises 2.45 (a rounded increment accumulated).
        moves[4].to[2] -= 0.05;
        for m in &mut moves[5..] {
            m.from[2] -= 0.05;
            m.to[2] -= 0.05;
        }
        let (found, _) = judged(&moves, None, Options::default());
        assert_eq!(found, [(Code::Helix, 14)]);
        // A second pass about the same axis at lead 2.4: cut out of step.
        let mut moves = helix([0.0, 0.0], 9.8, -20.0, 2.5, 8, false, G41);
        moves.push(line([9.8, 0.0, 0.0], [9.8, 0.0, -20.0], G41));
        let mut second = helix([0.0, 0.0], 10.0, -20.0, 2.4, 8, false, G41);
        for m in &mut second {
            m.line += 20;
        }
        moves.extend(second);
        let (found, _) = judged(&moves, None, Options::default());
        assert_eq!(found, [(Code::Helix, 30)]);
    }

    #[test]
    fn compensation_on_the_wrong_side() {
        // The tool comes in from the axis (a bore) and G42 with G3 keeps it outside the circle.
        let g42 = Comp::Right { d: Some(4) };
        let mut moves = vec![line([0.0, 0.0, -20.0], [10.0, 0.0, -20.0], g42)];
        moves.extend(helix([0.0, 0.0], 10.0, -20.0, 2.5, 8, false, g42));
        let (found, _) = judged(&moves, None, Options::default());
        assert_eq!(found[0], (Code::Helix, 10));
    }

    #[test]
    fn a_lead_in_arc_past_the_thread_gouges_it() {
        // Internal, R10 under G41. A lead-in arc of radius √34 = 5.831 about (5, 3), from
        // (5 − 5.831, 3) to the helix's start (10, 0).
        let entry = MillMotion {
            kind: MillKind::Arc {
                centre: [5.0, 3.0, -20.0],
                plane: crate::mill::motion::Plane::Xy,
                clockwise: false,
                turns: 0,
            },
            from: [5.0 - 34f64.sqrt(), 3.0, -20.5],
            to: [10.0, 0.0, -20.0],
            state: line([0.0; 3], [0.0; 3], G41).state,
            line: 9,
        };
        // Counter-clockwise it sweeps from 180° down round the bottom (through (5, −2.831), 5.75
        // from the axis) to −31°: its farthest point from the axis is its end, R10, on the root.
        let mut moves = vec![entry];
        moves.extend(helix([0.0, 0.0], 10.0, -20.0, 2.5, 8, false, G41));
        let (found, _) = judged(&moves, None, Options::default());
        assert!(found.is_empty(), "{found:?}");
        // Clockwise it goes round the top, through the ray from the axis through its centre
        // (31°): (10, 6), |(5, 3)| + 5.831 = 11.662 from the axis, 1.662 past the root.
        let mut gouging = moves.clone();
        if let MillKind::Arc { clockwise, .. } = &mut gouging[0].kind {
            *clockwise = true;
        }
        let (found, _) = judged(&gouging, None, Options::default());
        assert_eq!(found, [(Code::Helix, 9)]);
    }
}
