//! Pattern repeating (Fanuc's G73, GSK's, Haas's): the whole finishing shape, from the cycle's
//! start point, cut `d` times, each time shifted by the finishing allowance plus a share of the
//! relief that falls from all of it on the first pass to none on the last; each pass ends with a
//! rapid to the next pass's shifted start, the last with a rapid back to the start point.
//! docs/dialects/turning-cycles.md.

use crate::diag::{Code, Diagnostic, Result};
use crate::toolpath::{Motion, MotionKind};
use crate::turning::contour::{at_line, pieces, Frame, TOL};
use crate::turning::{Along, Pattern, Shape};
use crate::units::Vec2;

/// The most passes one pattern cycle may take.
pub const MAX_PASSES: u32 = 10_000;

/// The moves of a pattern-repeating cycle, passes numbered from 1, each tagged with `line`.
pub fn moves(cycle: &Pattern, line: u32) -> Result<Vec<Motion>> {
    check(cycle, line)?;
    let d = cycle.passes;
    let mut out = Vec::with_capacity((cycle.contour.segments.len() + 1) * d as usize + 1);
    // Any frame will do: it only checks the arcs.
    let frame = Frame {
        along: Along::Z,
        infeed: -1.0,
        cut: -1.0,
    };
    for k in 1..=d {
        // Pass k of d: the relief's share (d − k)/(d − 1): all of it first, none last.
        let share = if d == 1 {
            0.0
        } else {
            f64::from(d - k) / f64::from(d - 1)
        };
        let shift = Vec2::new(
            cycle.allowance_x + cycle.relief_x * share,
            cycle.allowance_z + cycle.relief_z * share,
        );
        let from = cycle.start.plus(shift);
        let rapid = |to| Motion {
            kind: MotionKind::Rapid,
            to,
            pass: k,
            line,
        };
        let at = out.last().map_or(cycle.start, |m: &Motion| m.to);
        if at.distance(from) > TOL.get() {
            out.push(rapid(from));
        }
        let path = pieces(frame, from, &cycle.contour.segments, shift)?;
        for (i, p) in path.iter().enumerate() {
            // The first block brings the tool to the shape, as the program's G00 (see the page).
            out.push(if i == 0 {
                rapid(p.seg.to)
            } else {
                p.motion(k, line)
            });
        }
    }
    out.push(Motion {
        kind: MotionKind::Rapid,
        to: cycle.start,
        pass: d,
        line,
    });
    Ok(out)
}

fn check(cycle: &Pattern, line: u32) -> Result<()> {
    if cycle.passes == 0 || cycle.passes > MAX_PASSES {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            at_line(line),
            format!(
                "PS0062: the number of divisions d is {}: it must be 1 to {MAX_PASSES}",
                cycle.passes
            ),
        ));
    }
    let values = [
        cycle.relief_x,
        cycle.relief_z,
        cycle.allowance_x,
        cycle.allowance_z,
        cycle.start.x,
        cycle.start.z,
    ];
    if values.iter().any(|v| !v.is_finite()) {
        return Err(Diagnostic::error(
            Code::BadNumber,
            at_line(line),
            "the cycle's start point, relief or finishing allowance is not a finite number",
        ));
    }
    if cycle.contour.start.distance(cycle.start) > TOL.get() {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the finishing shape does not start at the cycle's start point",
        ));
    }
    match cycle.contour.segments.first() {
        None => Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the finishing shape has no block",
        )),
        Some(s) if matches!(s.shape, Shape::Arc { .. }) => Err(Diagnostic::error(
            Code::Geometry,
            at_line(s.line),
            "PS0065: the first block of the finishing shape must be G00 or G01, not an arc",
        )),
        Some(_) => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::turning::{Contour, Segment};
    use crate::units::Pos;

    fn seg(x: f64, z: f64, line: u32) -> Segment {
        Segment {
            to: Pos::new(x, z),
            shape: Shape::Line,
            line,
        }
    }

    /// A casting turned in 3 passes: start X60 Z5 (radius 30), shape N10 G0 X20 Z2 (radius 10),
    /// N20 G1 Z−20, N30 G2 X40 Z−30 R10 (centre X40… radius: (20, −20)), N40 G1 Z−40, N50 X60;
    /// relief Δi 4 (radius), Δk 2; allowance U0.4 (radius 0.2) W0.1.
    fn casting() -> Pattern {
        let start = Pos::new(30.0, 5.0);
        Pattern {
            start,
            relief_x: 4.0,
            relief_z: 2.0,
            passes: 3,
            allowance_x: 0.2,
            allowance_z: 0.1,
            contour: Contour {
                start,
                segments: vec![
                    seg(10.0, 2.0, 10),
                    seg(10.0, -20.0, 20),
                    Segment {
                        to: Pos::new(20.0, -30.0),
                        shape: Shape::Arc {
                            centre: Pos::new(20.0, -20.0),
                            clockwise: true,
                        },
                        line: 30,
                    },
                    seg(20.0, -40.0, 40),
                    seg(30.0, -40.0, 50),
                ],
            },
        }
    }

    #[test]
    fn three_passes_divide_the_relief() {
        let m = moves(&casting(), 7).unwrap();
        // Shifts: pass 1 share 2/2 → (0.2 + 4, 0.1 + 2) = (4.2, 2.1); pass 2 share 1/2 →
        // (2.2, 1.1); pass 3 share 0 → (0.2, 0.1).
        let mut want: Vec<(u32, char, f64, f64)> = Vec::new();
        for (k, (sx, sz)) in [(1, (4.2, 2.1)), (2, (2.2, 1.1)), (3, (0.2, 0.1))] {
            want.push((k, 'R', 30.0 + sx, 5.0 + sz)); // to the shifted start
            want.push((k, 'R', 10.0 + sx, 2.0 + sz)); // N10, as G00
            want.push((k, 'F', 10.0 + sx, -20.0 + sz));
            want.push((k, 'A', 20.0 + sx, -30.0 + sz));
            want.push((k, 'F', 20.0 + sx, -40.0 + sz));
            want.push((k, 'F', 30.0 + sx, -40.0 + sz));
        }
        want.push((3, 'R', 30.0, 5.0));
        assert_eq!(m.len(), want.len());
        for (got, w) in m.iter().zip(&want) {
            let kind = match got.kind {
                MotionKind::Rapid => 'R',
                MotionKind::Feed => 'F',
                MotionKind::Arc { centre, clockwise } => {
                    // The arc's centre moves with the pass: (20, −20) + shift.
                    assert!(clockwise);
                    assert!((centre.x - (w.2 - 20.0 + 20.0)).abs() < 1e-9);
                    assert!((centre.z - (w.3 + 30.0 - 20.0)).abs() < 1e-9);
                    'A'
                }
                _ => '?',
            };
            assert_eq!((got.pass, kind), (w.0, w.1), "{got:?} vs {w:?}");
            assert!((got.to.x - w.2).abs() < 1e-9 && (got.to.z - w.3).abs() < 1e-9);
            assert_eq!(got.line, 7);
        }
    }

    #[test]
    fn one_pass_is_at_the_allowance() {
        let mut c = casting();
        c.passes = 1;
        let m = moves(&c, 7).unwrap();
        // Only the last pass: shift (0.2, 0.1); the first move goes to X30.2 Z5.1.
        assert!((m[0].to.x - 30.2).abs() < 1e-9 && (m[0].to.z - 5.1).abs() < 1e-9);
        assert_eq!(m.len(), 7);
    }

    #[test]
    fn no_pass_is_ps0062_and_an_arc_first_is_ps0065() {
        let mut c = casting();
        c.passes = 0;
        let e = moves(&c, 7).unwrap_err();
        assert!(e.message.starts_with("PS0062"), "{}", e.message);
        assert_eq!(e.span.line, 7);
        let mut c = casting();
        c.contour.segments[0].shape = Shape::Arc {
            centre: Pos::new(20.0, 3.5),
            clockwise: false,
        };
        let e = moves(&c, 7).unwrap_err();
        assert!(e.message.starts_with("PS0065"), "{}", e.message);
        assert_eq!(e.span.line, 10);
    }
}
