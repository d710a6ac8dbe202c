//! The geometry the contour cycles share (stock removal, pattern repeating, finishing): a
//! contour shifted by an allowance, seen in a working frame where the tool feeds in by lowering
//! its height `h` and cuts by raising `t`, and where a horizontal cut line `h = level` meets it.
//! docs/dialects/turning-cycles.md says why each rule is what it is.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::toolpath::{Motion, MotionKind};
use crate::turning::{Along, Segment, Shape};
use crate::units::{Pos, Tolerance, Vec2};

/// Every comparison of the cycles' geometry: half the finest least increment a lathe control
/// takes (IS-C, 0.0001 mm), as a radius. The model carries no resolution (the cycle's values are
/// already whole increments), so this is the one tolerance of the cycles' motion.
pub(crate) const TOL: Tolerance = Tolerance::mm(0.000_05);

/// How far the two ends of an arc may lie from one circle (mm) before the arc is refused: the
/// dialect reads arcs and checks them as its control does; this only stops a contour no control
/// would have accepted from making motion.
const ARC_ENDS: f64 = 0.01;

/// The place of a diagnostic about program line `line` (its column is not known here).
pub(crate) fn at_line(line: u32) -> Span {
    Span::new(0, 0, line, 1)
}

/// A point in the working frame: `t` along the cut, `h` the height above the part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct P {
    pub t: f64,
    pub h: f64,
}

impl P {
    pub const fn new(t: f64, h: f64) -> P {
        P { t, h }
    }
}

/// The working frame of a stock removal: the depth axis (X for passes along Z, Z for passes along
/// X) with the sign of the infeed, the cut axis with the sign of the cut.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Frame {
    pub along: Along,
    /// +1 when the infeed increases the depth axis (an internal G71), −1 when it decreases it.
    pub infeed: f64,
    /// +1 when the cut increases the cut axis, −1 when it decreases it (toward the chuck).
    pub cut: f64,
}

impl Frame {
    pub fn to(self, p: Pos) -> P {
        let (depth, cut) = match self.along {
            Along::Z => (p.x, p.z),
            Along::X => (p.z, p.x),
        };
        P::new(self.cut * cut, -self.infeed * depth)
    }

    pub fn from(self, p: P) -> Pos {
        let depth = -self.infeed * p.h;
        let cut = self.cut * p.t;
        match self.along {
            Along::Z => Pos::new(depth, cut),
            Along::X => Pos::new(cut, depth),
        }
    }

    /// The frame turns a clockwise arc counter-clockwise: the map from (Z, X) to (t, h) has a
    /// negative determinant. (Along Z: t = c·z, h = −i·x, det = −c·i; along X: t = c·x, h = −i·z,
    /// det = c·i.)
    pub fn mirrors(self) -> bool {
        let det = match self.along {
            Along::Z => -self.cut * self.infeed,
            Along::X => self.cut * self.infeed,
        };
        det < 0.0
    }
}

/// An arc in the working frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Arc {
    pub centre: P,
    pub radius: f64,
    /// Counter-clockwise in (t, h), angles measured from +t toward +h.
    pub ccw: bool,
    /// The angle of its start and its signed sweep (positive counter-clockwise).
    pub from_angle: f64,
    pub sweep: f64,
}

impl Arc {
    fn new(from: P, to: P, centre: P, ccw: bool, line: u32) -> Result<Arc> {
        let r1 = (from.t - centre.t).hypot(from.h - centre.h);
        let r2 = (to.t - centre.t).hypot(to.h - centre.h);
        if (r1 - r2).abs() > ARC_ENDS || r1.is_nan() || r1 <= TOL.get() {
            return Err(Diagnostic::error(
                Code::Geometry,
                at_line(line),
                format!(
                    "the arc's ends lie {r1:.4} mm and {r2:.4} mm from its centre: not one circle"
                ),
            ));
        }
        let a1 = (from.h - centre.h).atan2(from.t - centre.t);
        let a2 = (to.h - centre.h).atan2(to.t - centre.t);
        let ccw_sweep = (a2 - a1).rem_euclid(TAU);
        let sweep = if ccw { ccw_sweep } else { ccw_sweep - TAU };
        let sweep = if sweep.abs() * r1 <= TOL.get() || (TAU - sweep.abs()) * r1 <= TOL.get() {
            // Start and end coincide: a full circle, which no turning contour holds.
            return Err(Diagnostic::error(
                Code::Geometry,
                at_line(line),
                "an arc that ends where it starts (a full circle) cannot be part of a turned contour",
            ));
        } else {
            sweep
        };
        Ok(Arc {
            centre,
            radius: (r1 + r2) / 2.0,
            ccw,
            from_angle: a1,
            sweep,
        })
    }

    /// The arc passes through `angle` strictly between its ends (by more than the tolerance
    /// along the arc).
    pub fn passes(&self, angle: f64) -> bool {
        let into = if self.ccw {
            (angle - self.from_angle).rem_euclid(TAU)
        } else {
            (self.from_angle - angle).rem_euclid(TAU)
        };
        let margin = TOL.get() / self.radius;
        into > margin && into < self.sweep.abs() - margin
    }

    /// The arc lies above its centre (a function h(t) on the upper half circle) — for an arc that
    /// does not pass the ends of the horizontal diameter.
    fn upper(&self) -> bool {
        (self.from_angle + self.sweep / 2.0).sin() > 0.0
    }
}

/// One segment of a contour, shifted by the allowance: in the program's frame (to write it) and
/// in the working frame (to cut along it).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Piece {
    pub seg: Segment,
    pub from: P,
    pub to: P,
    pub arc: Option<Arc>,
}

impl Piece {
    /// The motion that follows this piece.
    pub fn motion(&self, pass: u32, line: u32) -> Motion {
        let kind = match self.seg.shape {
            Shape::Line => MotionKind::Feed,
            Shape::Arc { centre, clockwise } => MotionKind::Arc { centre, clockwise },
        };
        Motion {
            kind,
            to: self.seg.to,
            pass,
            line,
        }
    }

    /// The lowest height on the piece.
    pub fn lowest(&self) -> f64 {
        let ends = self.from.h.min(self.to.h);
        match self.arc {
            Some(a) if a.passes(3.0 * FRAC_PI_2) => ends.min(a.centre.h - a.radius),
            _ => ends,
        }
    }

    /// `t` never decreases along the piece.
    pub fn rises_in_t(&self) -> bool {
        let turns = self.arc.is_some_and(|a| a.passes(0.0) || a.passes(PI));
        !turns && !TOL.lt(self.to.t, self.from.t)
    }

    /// `h` never decreases along the piece.
    pub fn rises_in_h(&self) -> bool {
        let turns = self
            .arc
            .is_some_and(|a| a.passes(FRAC_PI_2) || a.passes(3.0 * FRAC_PI_2));
        !turns && !TOL.lt(self.to.h, self.from.h)
    }

    /// Where along `t` the piece lies strictly below `level` (by more than the tolerance), for a
    /// piece along which `t` never decreases: at most two ranges, pushed onto `out` in order.
    pub fn below(&self, level: f64, out: &mut Vec<(f64, f64)>) {
        let (t1, t2) = (self.from.t, self.to.t);
        if t2 - t1 <= TOL.get() {
            return; // a wall across the cut: no width along t
        }
        let mut push = |lo: f64, hi: f64| {
            let (lo, hi) = (lo.max(t1), hi.min(t2));
            if hi - lo > TOL.get() {
                out.push((lo, hi));
            }
        };
        // Below means below by more than the tolerance; a crossing is where the contour meets
        // the level itself.
        let strict = level - TOL.get();
        match self.arc {
            None => {
                let (h1, h2) = (self.from.h, self.to.h);
                match (h1 < strict, h2 < strict) {
                    (true, true) => push(t1, t2),
                    (false, false) => {}
                    (below_first, _) => {
                        let cross = t1 + (level - h1) * (t2 - t1) / (h2 - h1);
                        if below_first {
                            push(t1, cross)
                        } else {
                            push(cross, t2)
                        }
                    }
                }
            }
            Some(a) => {
                let (tc, hc, r) = (a.centre.t, a.centre.h, a.radius);
                // h(t) = hc ± √(r² − (t − tc)²) on the half the arc lies on.
                let width = |gap: f64| (r * r - gap * gap).max(0.0).sqrt();
                if a.upper() {
                    let gap = level - hc;
                    if gap >= r {
                        push(t1, t2);
                    } else if gap > TOL.get() {
                        push(t1, tc - width(gap));
                        push(tc + width(gap), t2);
                    }
                } else {
                    let gap = hc - level;
                    if gap < 0.0 {
                        push(t1, t2);
                    } else if gap < r - TOL.get() {
                        push(tc - width(gap), tc + width(gap));
                    }
                }
            }
        }
    }
}

/// The contour's segments shifted by `shift`, from `start`, in the working frame.
pub(crate) fn pieces(
    frame: Frame,
    start: Pos,
    segments: &[Segment],
    shift: Vec2,
) -> Result<Vec<Piece>> {
    let mut from = start;
    let mut out = Vec::with_capacity(segments.len());
    for seg in segments {
        if !seg.to.is_finite() {
            return Err(not_finite(seg.line));
        }
        let shape = match seg.shape {
            Shape::Line => Shape::Line,
            Shape::Arc { centre, clockwise } => {
                if !centre.is_finite() {
                    return Err(not_finite(seg.line));
                }
                Shape::Arc {
                    centre: centre.plus(shift),
                    clockwise,
                }
            }
        };
        let moved = Segment {
            to: seg.to.plus(shift),
            shape,
            line: seg.line,
        };
        let (a, b) = (frame.to(from), frame.to(moved.to));
        let arc = match shape {
            Shape::Line => None,
            Shape::Arc { centre, clockwise } => Some(Arc::new(
                a,
                b,
                frame.to(centre),
                clockwise == frame.mirrors(),
                seg.line,
            )?),
        };
        out.push(Piece {
            seg: moved,
            from: a,
            to: b,
            arc,
        });
        from = moved.to;
    }
    Ok(out)
}

fn not_finite(line: u32) -> Diagnostic {
    Diagnostic::error(
        Code::BadNumber,
        at_line(line),
        "a contour point is not a finite number",
    )
}

/// Where the cut line `h = level` runs through material, along `t` from `t0` to `t_end`, above a
/// contour along which `t` never decreases: the ranges where the contour lies below the level
/// (before the contour's first point, from `t0`, there is no part: the range is open), merged
/// where they touch. Linear in the number of pieces.
pub(crate) fn open_ranges(pieces: &[Piece], level: f64, t0: f64, t_end: f64) -> Vec<(f64, f64)> {
    let mut raw = Vec::new();
    if let Some(first) = pieces.first() {
        if first.from.t > t0 + TOL.get() {
            raw.push((t0, first.from.t));
        }
    }
    for p in pieces {
        p.below(level, &mut raw);
    }
    let mut out: Vec<(f64, f64)> = Vec::new();
    for (lo, hi) in raw {
        let (lo, hi) = (lo.max(t0), hi.min(t_end));
        if hi - lo <= TOL.get() {
            continue;
        }
        match out.last_mut() {
            Some(last) if lo <= last.1 + TOL.get() => last.1 = last.1.max(hi),
            _ => out.push((lo, hi)),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(x: f64, z: f64) -> Segment {
        Segment {
            to: Pos::new(x, z),
            shape: Shape::Line,
            line: 1,
        }
    }

    const EXTERNAL_G71: Frame = Frame {
        along: Along::Z,
        infeed: -1.0,
        cut: -1.0,
    };

    #[test]
    fn the_frame_maps_back_and_forth() {
        for along in [Along::Z, Along::X] {
            for (infeed, cut) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
                let f = Frame { along, infeed, cut };
                let p = Pos::new(12.5, -30.25);
                assert_eq!(f.from(f.to(p)), p);
            }
        }
        // External G71 toward the chuck: X 10 is height 10... no: h = −(−1)·x = x, t = −z.
        assert_eq!(EXTERNAL_G71.to(Pos::new(10.0, -5.0)), P::new(5.0, 10.0));
        // (t, h) = (−z, x) is (z, x) mirrored once: G2 and G3 swap.
        assert!(EXTERNAL_G71.mirrors());
    }

    #[test]
    fn a_convex_corner_arc_is_the_upper_half_in_the_working_frame() {
        // G3 from X8 Z0 to X10 Z−2 about X8 Z−2 (a corner R2 turning toward the chuck).
        // Working frame: (t, h) = (−z, x): from (0, 8) to (2, 10) about (2, 8): the arc sweeps from
        // angle π to π/2, clockwise in (t, h).
        let seg = Segment {
            to: Pos::new(10.0, -2.0),
            shape: Shape::Arc {
                centre: Pos::new(8.0, -2.0),
                clockwise: false,
            },
            line: 3,
        };
        let p = pieces(
            EXTERNAL_G71,
            Pos::new(8.0, 0.0),
            &[seg],
            Vec2::new(0.0, 0.0),
        )
        .unwrap();
        let a = p[0].arc.unwrap();
        assert!(!a.ccw);
        assert!((a.sweep + FRAC_PI_2).abs() < 1e-12);
        assert!(p[0].rises_in_t() && p[0].rises_in_h());
        // h = 9 meets it where (t − 2)² + 1 = 4: t = 2 − √3 = 0.267949.
        let mut out = Vec::new();
        p[0].below(9.0, &mut out);
        assert_eq!(out.len(), 1);
        assert!((out[0].0 - 0.0).abs() < 1e-12);
        assert!((out[0].1 - (2.0 - 3f64.sqrt())).abs() < 1e-4);
    }

    #[test]
    fn ranges_split_at_a_bump_and_merge_where_they_touch() {
        // External, toward −Z: X5 Z0 → X5 Z−10 → X8 Z−12 → X5 Z−14 → X5 Z−20 (a ridge at X8).
        let segs = [
            line(5.0, -10.0),
            line(8.0, -12.0),
            line(5.0, -14.0),
            line(5.0, -20.0),
        ];
        let p = pieces(EXTERNAL_G71, Pos::new(5.0, 0.0), &segs, Vec2::new(0.0, 0.0)).unwrap();
        // Level 7: the ridge rises above 7 from t = 10 + 2·(2/3) = 11.333 to 14 − 1.333 = 12.667.
        let r = open_ranges(&p, 7.0, -1.0, 20.0);
        assert_eq!(r.len(), 2);
        assert!((r[0].0 + 1.0).abs() < 1e-9 && (r[0].1 - 11.333_333).abs() < 1e-5);
        assert!((r[1].0 - 12.666_667).abs() < 1e-5 && (r[1].1 - 20.0).abs() < 1e-9);
        // Level 9: over the ridge, one range.
        assert_eq!(open_ranges(&p, 9.0, -1.0, 20.0), vec![(-1.0, 20.0)]);
        // Level 5: on the floor, nothing below it.
        assert_eq!(open_ranges(&p, 5.0, 0.0, 20.0), vec![]);
    }
}
