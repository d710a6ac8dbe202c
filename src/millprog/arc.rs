//! G2/G3: the centre from I J K (from the start, or absolute under LinuxCNC's G90.1) or from R
//! (negative: the longer arc), the normal axis moving linearly (a helix), LinuxCNC's P turns; the
//! controls' radius checks.

use crate::diag::{Code, Diagnostic};
use crate::dialect::mill::RadiusCheck;
use crate::gcode::{Line, Word};
use crate::mill::motion::{MillKind, MillMotion, P3};
use crate::units::Units;

use super::state::{known, span_of, unknown_axis, whole, Mill, Out, Result};

/// The centre words of a plane's two axes (G17 I J, G18 K I, G19 J K), in the order of
/// [`crate::mill::motion::Plane::axes`].
fn centre_letters(a: usize, b: usize) -> [u8; 2] {
    let l = [b'I', b'J', b'K'];
    [l[a], l[b]]
}

pub(crate) fn arc(
    mill: &mut Mill,
    line: &Line,
    clockwise: bool,
    g: Option<&Word>,
    out: &mut dyn Out,
) -> Result<()> {
    let (a, b, _) = mill.plane.axes();
    let to = mill.end_point(line)?;
    let gspan = span_of(line, g);
    let Some(from) = known(mill.pos) else {
        let w = line
            .words
            .iter()
            .find(|w| w.letter == b'G')
            .or(line.words.first());
        return Err(match w {
            Some(w) => unknown_axis(w, "an arc (which starts where the tool is)"),
            None => Diagnostic::error(Code::UnknownPosition, gspan, "an arc's start is not known"),
        });
    };
    let end = known(to).expect("an arc's start is known, so is its end");
    let turns = turns(mill, line)?;
    let r = line.word(b'R');
    let letters = centre_letters(a, b);
    let ij = [line.word(letters[0]), line.word(letters[1])];
    let centre = match (r, ij) {
        (Some(r), [None, None]) => r_centre(mill, r, from, end, clockwise)?,
        (None, [Some(_), _] | [_, Some(_)]) => {
            let c = ij_centre(mill, ij, from, a, b);
            check_radius(mill, line, ij, from, end, c, a, b)?;
            c
        }
        (Some(r), _) => {
            return Err(Diagnostic::error(
                Code::Conflict,
                r.span,
                "an arc given both by R and by its centre (I J K): which one?",
            ))
        }
        (None, _) => {
            return Err(Diagnostic::error(
                Code::MissingWord,
                gspan,
                format!(
                    "{}: {} or R is needed in this plane",
                    mill.lang.alarms.no_centre,
                    letters.map(|l| (l as char).to_string()).join(" and ")
                ),
            )
            .with_hint("G17 takes I and J, G18 I and K, G19 J and K"))
        }
    };
    let mut c = from;
    c[a] = centre[a];
    c[b] = centre[b];
    let m = MillMotion {
        kind: MillKind::Arc {
            centre: c,
            plane: mill.plane,
            clockwise,
            turns,
        },
        from,
        to: end,
        state: mill.state(),
        line: line.number,
    };
    mill.pos = to;
    out.motion(&m, mill.work)
}

/// LinuxCNC's P: the number of turns (P1 the arc alone); full turns before the last are P − 1.
fn turns(mill: &Mill, line: &Line) -> Result<u32> {
    let Some(p) = line.word(b'P') else {
        return Ok(0);
    };
    if !mill.lang.arc_turns {
        return Err(Diagnostic::error(
            Code::Unsupported,
            p.span,
            format!("{} does not take P on an arc", mill.lang.control),
        ));
    }
    let v = whole(p)?;
    if v == 0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            p.span,
            format!("{}: P is the number of turns", mill.lang.alarms.turns),
        ));
    }
    Ok(v - 1)
}

fn ij_centre(mill: &Mill, ij: [Option<&Word>; 2], from: P3, a: usize, b: usize) -> P3 {
    let mut c = from;
    for (k, axis) in [a, b].into_iter().enumerate() {
        let v = ij[k].map_or(0.0, |w| mill.mm(w));
        c[axis] = if mill.centre_absolute {
            v + mill.local[axis] + mill.g92[axis]
        } else {
            from[axis] + v
        };
    }
    c
}

/// The centre of an R arc: the shorter arc for R > 0, the longer for R < 0, clockwise or not as
/// seen from the positive normal axis.
fn r_centre(mill: &Mill, r: &Word, from: P3, end: P3, clockwise: bool) -> Result<P3> {
    let (a, b, _) = mill.plane.axes();
    let radius = mill.mm(r);
    let (da, db) = (end[a] - from[a], end[b] - from[b]);
    let chord = da.hypot(db);
    let eps = mill.units.to_mm(mill.increment(mill.units)) / 2.0;
    if chord <= eps {
        return Err(Diagnostic::error(
            Code::Geometry,
            r.span,
            format!(
                "{}: an arc by R ends where it starts",
                mill.lang.alarms.r_full_circle
            ),
        )
        .with_hint("write a full circle with its centre (I J K)"));
    }
    let half = chord / 2.0;
    // LinuxCNC allows no more than its TINY (1e-12 of R); the Fanuc family half an increment.
    let tol = if mill.lang.radius == RadiusCheck::LinuxCnc {
        radius.abs() * 1e-12
    } else {
        eps
    };
    if half > radius.abs() + tol {
        return Err(Diagnostic::error(
            Code::Geometry,
            r.span,
            format!(
                "{}: R {:.4} mm is shorter than half the distance between the arc's ends ({:.4} mm)",
                mill.lang.alarms.r_too_small,
                radius.abs(),
                half
            ),
        ));
    }
    let h = (radius * radius - half * half).max(0.0).sqrt();
    // Left of the chord (counter-clockwise from it) is (−db, da); a clockwise arc of less than
    // half a circle has its centre on the right.
    let (la, lb) = (-db / chord, da / chord);
    let side = if clockwise { -1.0 } else { 1.0 } * if radius < 0.0 { -1.0 } else { 1.0 };
    let mut c = from;
    c[a] = from[a] + da / 2.0 + side * h * la;
    c[b] = from[b] + db / 2.0 + side * h * lb;
    Ok(c)
}

/// The radii to the start and to the end, as the control compares them.
#[allow(clippy::too_many_arguments)]
fn check_radius(
    mill: &Mill,
    line: &Line,
    ij: [Option<&Word>; 2],
    from: P3,
    end: P3,
    c: P3,
    a: usize,
    b: usize,
) -> Result<()> {
    let r1 = (from[a] - c[a]).hypot(from[b] - c[b]);
    let r2 = (end[a] - c[a]).hypot(end[b] - c[b]);
    let span = ij[0].or(ij[1]).map_or(line.span(), |w| w.span);
    let units = mill.units;
    let (p1, p2) = (units.from_mm(r1), units.from_mm(r2));
    let abs_err = (p1 - p2).abs();
    let bad = match mill.lang.radius {
        RadiusCheck::Increments(k) => abs_err > k * mill.increment(units) + 1e-12,
        RadiusCheck::LinuxCnc => {
            let tolerance =
                2.0 * std::f64::consts::SQRT_2 * if units == Units::Inch { 0.001 } else { 0.01 };
            let rel = abs_err / p1.max(p2);
            abs_err > tolerance * 100.0 || (rel > 0.001 && abs_err > tolerance)
        }
    };
    if !bad {
        return Ok(());
    }
    Err(Diagnostic::error(
        Code::Geometry,
        span,
        format!(
            "{}: the arc's end is {p2:.4} {u} from its centre, its start {p1:.4} {u}",
            mill.lang.alarms.radius,
            u = units.name()
        ),
    )
    .with_hint(if mill.centre_absolute {
        "under G90.1 I J K are the centre itself: the end point must lie on the same circle"
    } else {
        "I J K give the centre from the start point: the end point must lie on the same circle"
    }))
}
