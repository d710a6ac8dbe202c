//! The hole-machining (canned) cycles G73, G74, G81–G86, G89, the tapping codes, and
//! LinuxCNC's G33.1, executed as their moves; each tap also as a [`TapCycle`].
//!
//! Every hole: positioning on the plane (at the current level), a rapid to R, the cycle's body,
//! the return (G98: the initial level, G99: R). Only in G17 (the drilling axis Z).

use crate::diag::{Code, Diagnostic};
use crate::dialect::mill::Alarms;
use crate::gcode::{Line, Word};
use crate::mill::motion::{Feed, MillKind, Plane, Rotation, TapCycle};

use super::state::{g_name, known, span_of, unknown_axis, whole, Mill, Out, Result};

/// One hole's levels (mm, work coordinates along Z).
struct Levels {
    r: f64,
    bottom: f64,
    clear: f64,
}

pub(crate) fn cycle(
    mill: &mut Mill,
    line: &Line,
    code: u16,
    g: Option<&Word>,
    out: &mut dyn Out,
) -> Result<()> {
    let gspan = span_of(line, g);
    if matches!(code, 760 | 870 | 880) {
        return Err(Diagnostic::error(
            Code::Unsupported,
            gspan,
            format!(
                "{} is not read: its moves depend on the machine's parameters (the shift direction of the fine boring and back boring cycles, G88's manual retract)",
                g_name(code)
            ),
        ));
    }
    if mill.plane != Plane::Xy {
        return Err(Diagnostic::error(
            Code::Unsupported,
            gspan,
            format!(
                "{} outside G17: threadcut reads canned cycles drilling along Z only",
                g_name(code)
            ),
        ));
    }
    read_words(mill, line, code, gspan)?;
    let repeats = match line.word(mill.lang.cycles.repeat) {
        // Fanuc's K takes 0 to 9999 ("K: number of repeats"); the others no more in practice.
        Some(w) if w.value > 9999.0 => {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                w.span,
                format!("{}{}: at most 9999 repeats", w.letter as char, w.value),
            ))
        }
        Some(w) => whole(w)?,
        None => 1,
    };
    let z_now = mill.pos[2];
    let level = mill.cycle.level.or(z_now).ok_or_else(|| {
        Diagnostic::error(
            Code::UnknownPosition,
            gspan,
            format!(
                "{}: the tool's Z (the initial level) is not known here",
                g_name(code)
            ),
        )
        .with_hint("position Z with an absolute move before the cycle")
    })?;
    mill.cycle.level = Some(level);
    let levels = levels(mill, level);
    let mut target = mill.pos;
    for k in 0..repeats {
        for (axis, letter) in [b'X', b'Y'].iter().enumerate() {
            if let Some(w) = line.word(*letter) {
                let v = mill.mm(w);
                target[axis] = Some(if mill.absolute {
                    v + mill.local[axis] + mill.g92[axis]
                } else {
                    mill.pos[axis].ok_or_else(|| unknown_axis(w, "an incremental hole position"))?
                        + v
                });
            } else if k == 0 && target[axis].is_none() {
                return Err(Diagnostic::error(
                    Code::UnknownPosition,
                    gspan,
                    format!(
                        "{}: the hole's {} is not known",
                        g_name(code),
                        *letter as char
                    ),
                ));
            }
        }
        hole(mill, line, code, [target[0], target[1]], &levels, out)?;
    }
    Ok(())
}

/// R, Z, Q, P of the block, kept modal; R and Z needed by the first hole.
fn read_words(mill: &mut Mill, line: &Line, code: u16, gspan: crate::diag::Span) -> Result<()> {
    if let Some(w) = line.word(b'R') {
        mill.cycle.r = Some(mill.mm(w));
    }
    if let Some(w) = line.word(b'Z') {
        mill.cycle.z = Some(mill.mm(w));
    }
    if let Some(w) = line.word(b'Q') {
        let q = mill.mm(w);
        if q <= 0.0 && matches!(code, 730 | 830) {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                w.span,
                format!("{}: Q (the peck depth) must be positive", g_name(code)),
            ));
        }
        mill.cycle.q = Some(q.abs());
    }
    if let Some(w) = line.word(b'P') {
        // LinuxCNC's P is seconds; the Fanuc family's a whole number of milliseconds, or
        // seconds when written with a decimal point.
        let s = if mill.lang.calculator && !mill.lang.cycles.m29_rigid || w.has_dot {
            w.value
        } else {
            w.value / 1000.0
        };
        mill.cycle.p = Some(s);
    }
    let missing = |alarm: &str, letter: char| {
        Diagnostic::error(
            Code::MissingWord,
            gspan,
            Alarms::with_code(alarm, &g_name(code)),
        )
        .with_hint(format!("write {letter} on the cycle's first block"))
    };
    let alarms = mill.lang.alarms;
    if mill.cycle.r.is_none() {
        return Err(missing(alarms.cycle_no_r, 'R'));
    }
    if mill.cycle.z.is_none() {
        return Err(missing(alarms.cycle_no_z, 'Z'));
    }
    if matches!(code, 730 | 830) && mill.cycle.q.is_none() {
        return Err(missing(alarms.cycle_no_q, 'Q'));
    }
    if let (Some(alarm), true) = (alarms.cycle_no_p, matches!(code, 820 | 860 | 890)) {
        if mill.cycle.p.is_none() {
            return Err(missing(alarm, 'P'));
        }
    }
    if let Some(spec) = mill.lang.cycles.taps.iter().find(|t| t.code == code) {
        tap_spindle(mill, spec.left, code, gspan)?;
    }
    Ok(())
}

/// A tapping cycle's spindle, where the control checks it: turning, and the tap's way.
fn tap_spindle(mill: &Mill, left: bool, code: u16, span: crate::diag::Span) -> Result<()> {
    let alarms = mill.lang.alarms;
    let against = if left { Rotation::Cw } else { Rotation::Ccw };
    let alarm = match mill.rotation {
        Rotation::Stopped => alarms.tap_spindle_stopped,
        r if r == against => alarms.tap_spindle_reversed,
        _ => None,
    };
    let Some(alarm) = alarm else {
        return Ok(());
    };
    let dir = if left {
        "clockwise"
    } else {
        "counterclockwise"
    };
    Err(Diagnostic::error(
        Code::Spindle,
        span,
        Alarms::with_code(alarm, &g_name(code)).replace("{dir}", dir),
    )
    .with_hint(if left {
        "a left-hand tap (G74) runs in with M4"
    } else {
        "a right-hand tap (G84) runs in with M3"
    }))
}

/// R, the bottom and the return level of a hole: in G91 R from the initial level and Z from R.
fn levels(mill: &Mill, level: f64) -> Levels {
    let (r, z) = (mill.cycle.r.unwrap_or(0.0), mill.cycle.z.unwrap_or(0.0));
    let shift = mill.local[2] + mill.g92[2];
    let (r, bottom) = if mill.absolute {
        (r + shift, z + shift)
    } else {
        (level + r, level + r + z)
    };
    let clear = if mill.cycle.initial { level.max(r) } else { r };
    Levels { r, bottom, clear }
}

fn hole(
    mill: &mut Mill,
    line: &Line,
    code: u16,
    xy: [Option<f64>; 2],
    lv: &Levels,
    out: &mut dyn Out,
) -> Result<()> {
    let n = line.number;
    let linuxcnc = mill.lang.cycles.linuxcnc_moves;
    let z = match mill.pos[2] {
        Some(z) if linuxcnc => Some(z.max(lv.clear)),
        z => z,
    };
    mill.rapid_to([xy[0], xy[1], z], n, out)?;
    mill.rapid_to([xy[0], xy[1], Some(lv.r)], n, out)?;
    let at = |z: f64| [xy[0], xy[1], Some(z)];
    let feed = |m: &mut Mill, z: f64, out: &mut dyn Out| m.straight(MillKind::Feed, at(z), n, out);
    match code {
        810 | 820 | 860 => {
            feed(mill, lv.bottom, out)?;
            mill.rapid_to(at(lv.clear), n, out)
        }
        850 | 890 => {
            feed(mill, lv.bottom, out)?;
            // Fanuc: out at feed to R, then (G98) a rapid to the initial level; so LinuxCNC's
            // G85, while its G89 feeds out to the return level (rs274).
            match (linuxcnc, code) {
                (true, 890) => feed(mill, lv.clear, out),
                _ => {
                    feed(mill, lv.r, out)?;
                    mill.rapid_to(at(lv.clear), n, out)
                }
            }
        }
        730 | 830 => peck(mill, code, &at, lv, n, out),
        _ => tap(mill, line, code, xy, lv, out),
    }
}

/// G73 (a short retract after each peck) and G83 (back to R, then down to just above the last
/// depth).
fn peck(
    mill: &mut Mill,
    code: u16,
    at: &dyn Fn(f64) -> [Option<f64>; 3],
    lv: &Levels,
    n: u32,
    out: &mut dyn Out,
) -> Result<()> {
    let q = mill.cycle.q.unwrap_or(1.0);
    let cyc = mill.lang.cycles;
    let mut depth = lv.r;
    // Bounded: each peck goes Q deeper, Q > 0.
    let pecks = ((lv.r - lv.bottom) / q).ceil().max(1.0);
    if pecks > 100_000.0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            crate::diag::Span::new(0, 0, n, 1),
            format!("{}: more than 100000 pecks", g_name(code)),
        ));
    }
    while depth > lv.bottom + 1e-9 {
        let next = (depth - q).max(lv.bottom);
        mill.straight(MillKind::Feed, at(next), n, out)?;
        depth = next;
        if depth <= lv.bottom + 1e-9 {
            break;
        }
        if code == 730 {
            mill.rapid_to(at(depth + cyc.g73_retract_mm), n, out)?;
        } else {
            mill.rapid_to(at(lv.r), n, out)?;
            mill.rapid_to(at(depth + cyc.g83_clearance_mm), n, out)?;
        }
    }
    mill.rapid_to(at(lv.clear), n, out)
}

/// A tapping cycle: in at feed (synchronised when rigid), the spindle reversed, out to R; the
/// event first.
fn tap(
    mill: &mut Mill,
    line: &Line,
    code: u16,
    xy: [Option<f64>; 2],
    lv: &Levels,
    out: &mut dyn Out,
) -> Result<()> {
    let n = line.number;
    let spec = mill
        .lang
        .cycles
        .taps
        .iter()
        .find(|t| t.code == code)
        .copied()
        .expect("a tapping code of the control");
    let rigid = spec.rigid || mill.m29;
    let state = mill.state();
    let at = |z: f64| [xy[0], xy[1], Some(z)];
    let position = known(at(lv.r)).expect("the hole's position is known");
    out.tap(&TapCycle {
        position,
        r: lv.r,
        bottom: lv.bottom,
        feed: state.feed,
        rpm: state.rpm,
        rotation: state.rotation,
        rigid,
        peck: mill.cycle.q,
        dwell: mill.cycle.p,
        code,
        line: n,
    })?;
    let kind = if rigid {
        MillKind::Sync {
            lead: lead(mill, line, state.feed, state.rpm)?,
        }
    } else {
        MillKind::Feed
    };
    mill.straight(kind, at(lv.bottom), n, out)?;
    let turning = mill.rotation;
    mill.rotation = reverse(turning);
    // LinuxCNC feeds out to the return level; Fanuc to R, then a rapid.
    let back = if mill.lang.cycles.linuxcnc_moves {
        lv.clear
    } else {
        lv.r
    };
    mill.straight(kind, at(back), n, out)?;
    mill.rotation = turning;
    mill.rapid_to(at(lv.clear), n, out)
}

fn reverse(r: Rotation) -> Rotation {
    match r {
        Rotation::Cw => Rotation::Ccw,
        Rotation::Ccw => Rotation::Cw,
        Rotation::Stopped => Rotation::Stopped,
    }
}

/// A rigid tap's lead: F/S under feed per minute, F under feed per revolution.
fn lead(mill: &Mill, line: &Line, feed: Feed, rpm: Option<f64>) -> Result<f64> {
    match (feed, rpm) {
        (Feed::PerRev(f), _) => Ok(f),
        (Feed::PerMinute(f), Some(s)) if s > 0.0 => Ok(f / s),
        _ => Err(Diagnostic::error(
            Code::MissingWord,
            line.span(),
            format!(
                "rigid tapping needs a feed and a spindle speed (the lead is F/S): {}",
                if mill.rpm.is_none() {
                    "no S is programmed"
                } else {
                    "no F is programmed"
                }
            ),
        )
        .with_hint("program S (and M29 S on Fanuc) and F before the tapping cycle")),
    }
}

/// LinuxCNC's G33.1: in to the end point synchronised with the spindle (K: distance per
/// revolution), the spindle reversed, back to the start.
pub(crate) fn g33_1(mill: &mut Mill, line: &Line, g: &Word, out: &mut dyn Out) -> Result<()> {
    let k = line.word(b'K').ok_or_else(|| {
        Diagnostic::error(
            Code::MissingWord,
            g.span,
            "K word missing with G33.1 (the tap's lead)",
        )
    })?;
    let lead = mill.mm(k);
    if lead <= 0.0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            k.span,
            "G33.1: K (the lead) must be positive",
        ));
    }
    if mill.rotation == Rotation::Stopped {
        return Err(Diagnostic::error(
            Code::Spindle,
            g.span,
            "Spindle not turning in G33.1",
        ));
    }
    let start = mill.pos;
    let Some(from) = known(start) else {
        return Err(unknown_axis(g, "G33.1 (which returns to its start)"));
    };
    let to = mill.end_point(line)?;
    let end = known(to).expect("known start, known end");
    let state = mill.state();
    out.tap(&TapCycle {
        position: from,
        r: from[2],
        bottom: end[2],
        feed: Feed::PerRev(lead),
        rpm: state.rpm,
        rotation: state.rotation,
        rigid: true,
        peck: None,
        dwell: None,
        code: 331,
        line: line.number,
    })?;
    let kind = MillKind::Sync { lead };
    mill.straight(kind, to, line.number, out)?;
    let turning = mill.rotation;
    mill.rotation = reverse(turning);
    mill.straight(kind, start, line.number, out)?;
    mill.rotation = turning;
    Ok(())
}
