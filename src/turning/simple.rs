//! The motion of the single box cycles (G90 along Z, G94 along X) and the peck cycles (G74 along
//! Z, G75 along X), as Fanuc's lathe manuals draw them (`docs/dialects/fanuc.md`, "Turning
//! cycles"): every dialect that has them reads its words into [`BoxCycle`] or [`Peck`].
//!
//! Box cycle (along Z; along X the axes trade places):
//!
//! ```text
//! 1 rapid  to (end.x + taper, start.z)      in X to where the cut starts
//! 2 feed   to (end.x, end.z)                along Z (a cone when taper ≠ 0)
//! 3 feed   to (start.x, end.z)              out in X
//! 4 rapid  to (start.x, start.z)            back in Z
//! ```
//!
//! Peck cycle (along Z, columns across X; along X the axes trade places): in each column, feeds of
//! `peck` toward `end.z`, each followed by a rapid retract of `retract`, the last feed to `end.z`;
//! at the bottom a rapid relief of `relief` across, a rapid back to `start.z`, a rapid across to the
//! next column, `shift` further toward `end.x` (the last column at `end.x`); after the last column,
//! a rapid back across to the start point.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::toolpath::{Motion, MotionKind};
use crate::units::Pos;

use super::{Along, BoxCycle, Peck};

/// The most moves a peck cycle may make (its pecks and columns are counted from its words: a
/// tiny peck on a long hole is refused rather than run for ever).
pub const MAX_PECK_MOVES: usize = 1_000_000;

/// Lengths below this (mm) are taken as zero when columns and pecks are counted (far below any
/// control's least input increment, 0.0001 mm).
const EPS: f64 = 1e-9;

/// (along, across) coordinates of a point: Z and X for a cycle along Z.
fn split(along: Along, p: Pos) -> (f64, f64) {
    match along {
        Along::Z => (p.z, p.x),
        Along::X => (p.x, p.z),
    }
}

/// The point of (along, across) coordinates.
fn join(along: Along, a: f64, c: f64) -> Pos {
    match along {
        Along::Z => Pos::new(c, a),
        Along::X => Pos::new(a, c),
    }
}

/// The four moves of a box cycle.
pub fn box_moves(b: &BoxCycle, line: u32) -> Vec<Motion> {
    let m = |kind, to| Motion {
        kind,
        to,
        pass: 1,
        line,
    };
    // In the cycle's own frame: `a` along the cut, `c` across (the depth's axis).
    let (sa, sc) = split(b.along, b.start);
    let (ea, ec) = split(b.along, b.end);
    vec![
        m(MotionKind::Rapid, join(b.along, sa, ec + b.taper)),
        m(MotionKind::Feed, join(b.along, ea, ec)),
        m(MotionKind::Feed, join(b.along, ea, sc)),
        m(MotionKind::Rapid, join(b.along, sa, sc)),
    ]
}

/// The stations from `from` to `to` in steps of at most `step` (`from` excluded, `to` included):
/// the last step is what remains. `None` when there would be more than `max`.
fn stations(from: f64, to: f64, step: f64, max: usize) -> Option<Vec<f64>> {
    let span = to - from;
    if span.abs() <= EPS {
        return Some(Vec::new());
    }
    let n = (span.abs() / step - EPS).ceil().max(1.0);
    if !n.is_finite() || n > max as f64 {
        return None;
    }
    let dir = span.signum();
    let n = n as usize;
    Some(
        (1..=n)
            .map(|i| {
                if i == n {
                    to
                } else {
                    from + dir * step * i as f64
                }
            })
            .collect(),
    )
}

/// The moves of a peck cycle. `span` places the error of a cycle with too many moves.
pub fn peck_moves(p: &Peck, line: u32, span: Span) -> Result<Vec<Motion>> {
    let too_many = || {
        Diagnostic::error(
            Code::OutOfRange,
            span,
            format!(
                "the peck cycle would make more than {MAX_PECK_MOVES} moves: its peck or shift is too small for its length"
            ),
        )
    };
    let (sa, sc) = split(p.along, p.start);
    let (ea, ec) = split(p.along, p.end);
    // Pecks must be positive where the cycle moves along its axis (the dialect's alarm).
    let pecks = if p.peck > EPS {
        stations(sa, ea, p.peck, MAX_PECK_MOVES).ok_or_else(too_many)?
    } else {
        vec![ea]
    };
    let mut columns = vec![sc];
    if p.shift > EPS {
        columns.extend(stations(sc, ec, p.shift, MAX_PECK_MOVES).ok_or_else(too_many)?);
    }
    if columns.len().saturating_mul(pecks.len() * 2 + 3) > MAX_PECK_MOVES {
        return Err(too_many());
    }
    let dir = (ea - sa).signum();
    let mut out = Vec::with_capacity(columns.len() * (pecks.len() * 2 + 3) + 1);
    let mut m = |kind, a, c| {
        out.push(Motion {
            kind,
            to: join(p.along, a, c),
            pass: 1,
            line,
        })
    };
    for (i, &c) in columns.iter().enumerate() {
        if i > 0 {
            m(MotionKind::Rapid, sa, c);
        }
        for (k, &a) in pecks.iter().enumerate() {
            m(MotionKind::Feed, a, c);
            if k + 1 < pecks.len() && p.retract > EPS {
                m(MotionKind::Rapid, a - dir * p.retract, c);
            }
        }
        let relieved = c + p.relief;
        if p.relief.abs() > EPS {
            m(MotionKind::Rapid, ea, relieved);
        }
        m(MotionKind::Rapid, sa, relieved);
    }
    if columns.len() > 1 || p.relief.abs() > EPS {
        m(MotionKind::Rapid, sa, sc);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moves(m: &[Motion]) -> Vec<(char, f64, f64)> {
        m.iter()
            .map(|m| {
                let k = match m.kind {
                    MotionKind::Rapid => 'R',
                    MotionKind::Feed => 'F',
                    _ => '?',
                };
                (k, m.to.x, m.to.z)
            })
            .collect()
    }

    fn assert_moves(got: &[Motion], want: &[(char, f64, f64)]) {
        let got = moves(got);
        assert_eq!(got.len(), want.len(), "{got:?}");
        for (g, w) in got.iter().zip(want) {
            assert_eq!(g.0, w.0, "{got:?}");
            assert!(
                (g.1 - w.1).abs() < 1e-9 && (g.2 - w.2).abs() < 1e-9,
                "{g:?} ≠ {w:?} in {got:?}"
            );
        }
    }

    #[test]
    fn a_box_cycle_along_z_with_a_taper() {
        // G90 X40. Z-30. R-2. F0.2 from X50. Z2. (diameters): start r25 Z2, end r20 Z-30; the cut
        // starts at X = 20 + (−2) = 18 (Ø36) and runs to r20 Z-30, out to r25, back to Z2.
        let b = BoxCycle {
            along: Along::Z,
            start: Pos::new(25.0, 2.0),
            end: Pos::new(20.0, -30.0),
            taper: -2.0,
        };
        assert_moves(
            &box_moves(&b, 7),
            &[
                ('R', 18.0, 2.0),
                ('F', 20.0, -30.0),
                ('F', 25.0, -30.0),
                ('R', 25.0, 2.0),
            ],
        );
    }

    #[test]
    fn a_box_cycle_along_x() {
        // G94 X20. Z-3. F0.2 from X60. Z2.: in Z to -3, across to r10, out to Z2, back to r30.
        let b = BoxCycle {
            along: Along::X,
            start: Pos::new(30.0, 2.0),
            end: Pos::new(10.0, -3.0),
            taper: 0.0,
        };
        assert_moves(
            &box_moves(&b, 7),
            &[
                ('R', 30.0, -3.0),
                ('F', 10.0, -3.0),
                ('F', 10.0, 2.0),
                ('R', 30.0, 2.0),
            ],
        );
        // With a taper (Z at the cut's start minus Z at its end): the cut starts at Z -3 + 1.5.
        let t = BoxCycle { taper: 1.5, ..b };
        assert_eq!(box_moves(&t, 7)[0].to, Pos::new(30.0, -1.5));
    }

    #[test]
    fn a_peck_drilling_cycle_in_one_column() {
        // G74 R0.5 / G74 Z-10. Q4000 F0.1 from X0 Z1: 11 mm in pecks of 4: to -3, -7, then -10 (the
        // remainder, 3); a retract of 0.5 after each but the last; back to Z1.
        let p = Peck {
            along: Along::Z,
            start: Pos::new(0.0, 1.0),
            end: Pos::new(0.0, -10.0),
            peck: 4.0,
            shift: 0.0,
            retract: 0.5,
            relief: 0.0,
        };
        assert_moves(
            &peck_moves(&p, 3, Span::default()).unwrap(),
            &[
                ('F', 0.0, -3.0),
                ('R', 0.0, -2.5),
                ('F', 0.0, -7.0),
                ('R', 0.0, -6.5),
                ('F', 0.0, -10.0),
                ('R', 0.0, 1.0),
            ],
        );
    }

    #[test]
    fn a_face_groove_in_columns_with_a_relief() {
        // From r20 Z1 to r14 Z-5; pecks of 3 (to -2, then -5), shifts of 2.5 toward −X (columns
        // 20, 17.5, 15, then 14: the remainder 1), retract 0.5, relief 0.2 toward +X.
        let p = Peck {
            along: Along::Z,
            start: Pos::new(20.0, 1.0),
            end: Pos::new(14.0, -5.0),
            peck: 3.0,
            shift: 2.5,
            retract: 0.5,
            relief: 0.2,
        };
        let got = peck_moves(&p, 3, Span::default()).unwrap();
        let mut want = vec![];
        for (i, c) in [20.0, 17.5, 15.0, 14.0].into_iter().enumerate() {
            if i > 0 {
                want.push(('R', c, 1.0));
            }
            want.extend([
                ('F', c, -2.0),
                ('R', c, -1.5),
                ('F', c, -5.0),
                ('R', c + 0.2, -5.0),
                ('R', c + 0.2, 1.0),
            ]);
        }
        want.push(('R', 20.0, 1.0));
        assert_eq!(want.len(), 24);
        assert_moves(&got, &want);
    }

    #[test]
    fn a_grooving_cycle_along_x() {
        // G75: from r25 Z-10 to r15 Z-14; pecks of 4 in X (21, 17, 15), shifts of 3 toward −Z
        // (columns -10, -13, -14), retract 1, no relief.
        let p = Peck {
            along: Along::X,
            start: Pos::new(25.0, -10.0),
            end: Pos::new(15.0, -14.0),
            peck: 4.0,
            shift: 3.0,
            retract: 1.0,
            relief: 0.0,
        };
        let got = peck_moves(&p, 3, Span::default()).unwrap();
        let mut want = vec![];
        for (i, z) in [-10.0, -13.0, -14.0].into_iter().enumerate() {
            if i > 0 {
                want.push(('R', 25.0, z));
            }
            want.extend([
                ('F', 21.0, z),
                ('R', 22.0, z),
                ('F', 17.0, z),
                ('R', 18.0, z),
                ('F', 15.0, z),
                ('R', 25.0, z),
            ]);
        }
        want.push(('R', 25.0, -10.0));
        assert_moves(&got, &want);
    }

    #[test]
    fn a_peck_too_small_for_its_length_is_refused() {
        let p = Peck {
            along: Along::Z,
            start: Pos::new(0.0, 1.0),
            end: Pos::new(0.0, -1000.0),
            peck: 1e-4,
            shift: 0.0,
            retract: 0.0,
            relief: 0.0,
        };
        let e = peck_moves(&p, 3, Span::default()).unwrap_err();
        assert!(e.message.contains("more than"), "{}", e.message);
    }
}
