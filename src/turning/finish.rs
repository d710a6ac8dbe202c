//! Finishing (Fanuc's G70, GSK's, Haas's): the finishing shape once, from the cycle's start
//! point, then back to it at rapid. docs/dialects/turning-cycles.md.

use crate::diag::{Code, Diagnostic, Result};
use crate::toolpath::{Motion, MotionKind};
use crate::turning::contour::{at_line, pieces, Frame, TOL};
use crate::turning::{Along, Finish, Shape};
use crate::units::Vec2;

/// The moves of a finishing cycle (pass 1), each tagged with `line`.
pub fn moves(cycle: &Finish, line: u32) -> Result<Vec<Motion>> {
    if !cycle.start.is_finite() {
        return Err(Diagnostic::error(
            Code::BadNumber,
            at_line(line),
            "the cycle's start point is not a finite number",
        ));
    }
    if cycle.contour.start.distance(cycle.start) > TOL.get() {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the finishing shape does not start at the cycle's start point",
        ));
    }
    if cycle.contour.segments.is_empty() {
        return Err(Diagnostic::error(
            Code::Geometry,
            at_line(line),
            "the finishing shape has no block",
        ));
    }
    // Any frame will do: it only checks the arcs.
    let frame = Frame {
        along: Along::Z,
        infeed: -1.0,
        cut: -1.0,
    };
    let path = pieces(
        frame,
        cycle.start,
        &cycle.contour.segments,
        Vec2::new(0.0, 0.0),
    )?;
    let mut out = Vec::with_capacity(path.len() + 1);
    for (i, p) in path.iter().enumerate() {
        // The first block brings the tool to the shape, as the program's G00 (see the page).
        let first_line = i == 0 && matches!(p.seg.shape, Shape::Line);
        out.push(if first_line {
            Motion {
                kind: MotionKind::Rapid,
                to: p.seg.to,
                pass: 1,
                line,
            }
        } else {
            p.motion(1, line)
        });
    }
    out.push(Motion {
        kind: MotionKind::Rapid,
        to: cycle.start,
        pass: 1,
        line,
    });
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::turning::{Contour, Segment};
    use crate::units::Pos;

    #[test]
    fn follows_lines_and_arcs_and_returns_to_the_start() {
        // G70 from X52 Z2 (radius 26): N10 G0 X16 (radius 8), N20 G1 X20 Z0 (chamfer to radius
        // 10), N30 Z−15, N40 X28 (radius 14), N50 G3 X36 Z−19 R4 (centre radius 14, Z−19),
        // N60 G1 Z−30, N70 X52.
        let start = Pos::new(26.0, 2.0);
        let line = |x, z, n| Segment {
            to: Pos::new(x, z),
            shape: Shape::Line,
            line: n,
        };
        let arc = Segment {
            to: Pos::new(18.0, -19.0),
            shape: Shape::Arc {
                centre: Pos::new(14.0, -19.0),
                clockwise: false,
            },
            line: 50,
        };
        let f = Finish {
            start,
            offsets: None,
            contour: Contour {
                start,
                segments: vec![
                    line(8.0, 2.0, 10),
                    line(10.0, 0.0, 20),
                    line(10.0, -15.0, 30),
                    line(14.0, -15.0, 40),
                    arc,
                    line(18.0, -30.0, 60),
                    line(26.0, -30.0, 70),
                ],
            },
        };
        let m = moves(&f, 9).unwrap();
        let kinds: Vec<_> = m.iter().map(|m| m.kind).collect();
        assert_eq!(
            kinds,
            [
                MotionKind::Rapid,
                MotionKind::Feed,
                MotionKind::Feed,
                MotionKind::Feed,
                MotionKind::Arc {
                    centre: Pos::new(14.0, -19.0),
                    clockwise: false
                },
                MotionKind::Feed,
                MotionKind::Feed,
                MotionKind::Rapid,
            ]
        );
        let ends: Vec<_> = m.iter().map(|m| (m.to.x, m.to.z)).collect();
        assert_eq!(
            ends,
            [
                (8.0, 2.0),
                (10.0, 0.0),
                (10.0, -15.0),
                (14.0, -15.0),
                (18.0, -19.0),
                (18.0, -30.0),
                (26.0, -30.0),
                (26.0, 2.0),
            ]
        );
        assert!(m.iter().all(|m| m.pass == 1 && m.line == 9));
    }

    #[test]
    fn an_arc_off_its_circle_names_its_line() {
        let start = Pos::new(26.0, 2.0);
        let f = Finish {
            start,
            offsets: None,
            contour: Contour {
                start,
                segments: vec![Segment {
                    to: Pos::new(10.0, 0.0),
                    shape: Shape::Arc {
                        centre: Pos::new(0.0, 0.0),
                        clockwise: true,
                    },
                    line: 12,
                }],
            },
        };
        let e = moves(&f, 9).unwrap_err();
        assert_eq!((e.code, e.span.line), (Code::Geometry, 12));
    }
}
