//! The region a tool sweeps along one feed move, as convex polygons on the grid: the nose (a point
//! or a circle) and the body behind it, along a straight move or along each chord of an arc.
//!
//! Coordinates are the grid's: `IntPoint { x: radius, y: z }` in units of [`GRID`](super::GRID).

use i_overlay::i_float::int::point::IntPoint;

use crate::units::Pos;

use super::{to_grid, Body, Tool};

/// The most chords an arc is cut into, whatever its size: reached only by arcs so large that each
/// chord strays further than the tolerance (an arc of radius beyond ≈ 4 m at 0.001 mm).
pub const ARC_CHORDS_MAX: usize = 512;

/// The fewest and most sides of the polygon that stands for the nose.
const NOSE_SIDES_MIN: usize = 8;
const NOSE_SIDES_MAX: usize = 128;

/// Where a tool's body reaches: the ray from the nose away from the axis (toward it in a bore:
/// `inward`) ends at `x_ray` or beyond the move; the ray toward +Z (a turning tool's end edge) at
/// `z_ray` or beyond the move.
#[derive(Clone, Copy, Debug)]
pub struct Reach {
    pub x_ray: f64,
    pub z_ray: f64,
    pub inward: bool,
}

/// What one sweep is built from: the tool, the reach of its body and the tolerance (mm).
pub struct Sweeper<'t> {
    pub tool: &'t Tool,
    pub reach: Reach,
    pub tolerance: f64,
}

impl Sweeper<'_> {
    /// The convex pieces swept along the straight move `a` → `b` (each counter-clockwise in
    /// (x, z)), appended to `out`.
    pub fn line(&self, a: Pos, b: Pos, out: &mut Vec<Vec<IntPoint<i32>>>) {
        let r = self.tool.nose_radius;
        let mut pts = Vec::new();
        if r > 0.0 {
            let n = nose_sides(r, self.tolerance);
            for p in [a, b] {
                for i in 0..n {
                    let t = std::f64::consts::TAU * i as f64 / n as f64;
                    pts.push((p.x + r * t.cos(), p.z + r * t.sin()));
                }
            }
            push_hull(&mut pts, out);
        }
        // The body's rays: a strip as wide as the nose from the nose to the reach, which lies
        // beyond both ends of the move (a move outside the stock reaches further).
        let z_ray = self.reach.z_ray.max(a.z.max(b.z) + r);
        let x_ray = if self.reach.inward {
            self.reach.x_ray.min(a.x.min(b.x) - r)
        } else {
            self.reach.x_ray.max(a.x.max(b.x) + r)
        };
        pts.clear();
        for p in [a, b] {
            pts.extend([(p.x - r, p.z), (p.x + r, p.z)]);
            pts.extend([(p.x - r, z_ray), (p.x + r, z_ray)]);
        }
        if matches!(self.tool.body, Body::Turning | Body::Axial) {
            push_hull(&mut pts, out);
        }
        pts.clear();
        for p in [a, b] {
            pts.extend([(p.x, p.z - r), (p.x, p.z + r)]);
            pts.extend([(x_ray, p.z - r), (x_ray, p.z + r)]);
        }
        if matches!(self.tool.body, Body::Turning | Body::Radial) {
            push_hull(&mut pts, out);
        }
    }

    /// The pieces swept along the arc from `a` to `b` about `centre`, clockwise (seen with Z to
    /// the right and X up) or not: the arc is cut into chords that stray at most half the
    /// tolerance from it, at most [`ARC_CHORDS_MAX`].
    pub fn arc(
        &self,
        a: Pos,
        b: Pos,
        centre: Pos,
        clockwise: bool,
        out: &mut Vec<Vec<IntPoint<i32>>>,
    ) {
        for w in arc_points(a, b, centre, clockwise, self.tolerance).windows(2) {
            self.line(w[0], w[1], out);
        }
    }
}

/// The points of the arc from `a` to `b` about `centre`, `a` and `b` included: chords within half
/// the tolerance of the circle through `a` (bounded by [`ARC_CHORDS_MAX`]). An end point off that
/// circle (a program's centre is within its own tolerance) is reached by the last chord.
pub fn arc_points(a: Pos, b: Pos, centre: Pos, clockwise: bool, tolerance: f64) -> Vec<Pos> {
    // Angles in the (z, x) plane: Z to the right, X up.
    let angle = |p: Pos| (p.x - centre.x).atan2(p.z - centre.z);
    let radius = a.distance(centre);
    let (t0, t1) = (angle(a), angle(b));
    let tau = std::f64::consts::TAU;
    let mut sweep = if clockwise { t0 - t1 } else { t1 - t0 };
    sweep = sweep.rem_euclid(tau);
    if sweep == 0.0 && a != b {
        sweep = tau;
    }
    if a == b {
        // A full circle (an end point on the start with I/K).
        sweep = tau;
    }
    let step = if radius > tolerance / 2.0 {
        2.0 * (1.0 - tolerance / 2.0 / radius).acos()
    } else {
        tau
    };
    let n = ((sweep / step).ceil() as usize).clamp(1, ARC_CHORDS_MAX);
    let dir = if clockwise { -1.0 } else { 1.0 };
    let mut pts = Vec::with_capacity(n + 1);
    pts.push(a);
    for i in 1..n {
        let t = t0 + dir * sweep * i as f64 / n as f64;
        pts.push(Pos::new(
            centre.x + radius * t.sin(),
            centre.z + radius * t.cos(),
        ));
    }
    pts.push(b);
    pts
}

/// The sides of the polygon standing for a nose of radius `r`: its chords stray at most half the
/// tolerance inside the circle.
fn nose_sides(r: f64, tolerance: f64) -> usize {
    if r <= tolerance / 2.0 {
        return NOSE_SIDES_MIN;
    }
    let step = 2.0 * (1.0 - tolerance / 2.0 / r).acos();
    ((std::f64::consts::TAU / step).ceil() as usize).clamp(NOSE_SIDES_MIN, NOSE_SIDES_MAX)
}

/// The convex hull of `pts` (x, z) on the grid, counter-clockwise, when it has an area.
fn push_hull(pts: &mut [(f64, f64)], out: &mut Vec<Vec<IntPoint<i32>>>) {
    let mut grid: Vec<IntPoint<i32>> = pts.iter().map(|&(x, z)| to_grid(x, z)).collect();
    grid.sort_by_key(|p| (p.x, p.y));
    grid.dedup();
    if grid.len() < 3 {
        return;
    }
    let cross = |o: IntPoint<i32>, a: IntPoint<i32>, b: IntPoint<i32>| {
        i64::from(a.x - o.x) * i64::from(b.y - o.y) - i64::from(a.y - o.y) * i64::from(b.x - o.x)
    };
    // Andrew's monotone chain.
    let mut hull: Vec<IntPoint<i32>> = Vec::with_capacity(grid.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &IntPoint<i32>>> = if pass == 0 {
            Box::new(grid.iter())
        } else {
            Box::new(grid.iter().rev())
        };
        for &p in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    if hull.len() >= 3 {
        out.push(hull);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(c: &[IntPoint<i32>]) -> f64 {
        let n = c.len();
        let twice: i64 = (0..n)
            .map(|i| {
                let (a, b) = (c[i], c[(i + 1) % n]);
                i64::from(a.x) * i64::from(b.y) - i64::from(b.x) * i64::from(a.y)
            })
            .sum();
        twice as f64 / 2.0 * super::super::GRID * super::super::GRID
    }

    #[test]
    fn a_point_tool_along_z_sweeps_the_strip_above_its_path() {
        // A point from (15, 2) to (15, -20), the body's ray reaching X25: the rectangle
        // 10 × 22 = 220 mm²; no nose piece, and the +Z ray along a Z move has no area.
        let tool = Tool::point(Body::Turning);
        let s = Sweeper {
            tool: &tool,
            reach: Reach {
                x_ray: 25.0,
                z_ray: 10.0,
                inward: false,
            },
            tolerance: 0.001,
        };
        let mut out = Vec::new();
        s.line(Pos::new(15.0, 2.0), Pos::new(15.0, -20.0), &mut out);
        assert_eq!(out.len(), 1);
        assert!((area(&out[0]) - 220.0).abs() < 1e-6, "{}", area(&out[0]));
    }

    #[test]
    fn a_nose_along_a_line_sweeps_a_stadium() {
        // Radius 1 over 10 mm: 2·10 + π·1² ≈ 23.1416, the polygon within the tolerance (its
        // area short by at most the perimeter × half the tolerance: 2·(10 + π)·0.0005 ≈ 0.013).
        let tool = Tool {
            nose_radius: 1.0,
            body: Body::Radial,
        };
        let s = Sweeper {
            tool: &tool,
            reach: Reach {
                x_ray: 20.0,
                z_ray: 10.0,
                inward: false,
            },
            tolerance: 0.001,
        };
        let mut out = Vec::new();
        s.line(Pos::new(10.0, 0.0), Pos::new(10.0, -10.0), &mut out);
        let stadium = area(&out[0]);
        let exact = 20.0 + std::f64::consts::PI;
        assert!(stadium <= exact && exact - stadium < 0.013, "{stadium}");
    }

    #[test]
    fn arc_points_stay_on_the_circle_and_run_the_right_way() {
        // A quarter circle of radius 5 about (15, 0) from (10, 0) to (15, -5), clockwise: every
        // point on the circle, the middle one at 45° between them, (15 − 5·cos 45°, −5·sin 45°).
        let c = Pos::new(15.0, 0.0);
        let pts = arc_points(Pos::new(10.0, 0.0), Pos::new(15.0, -5.0), c, true, 0.001);
        // The chord angle is 2·acos(1 − 0.0005/5) ≈ 0.02828 rad: ⌈(π/2)/0.02828⌉ = 56 chords.
        assert_eq!(pts.len(), 57);
        for p in &pts {
            assert!((p.distance(c) - 5.0).abs() < 1e-9);
        }
        let mid = pts[28];
        let h = 5.0 * std::f64::consts::FRAC_1_SQRT_2;
        assert!(
            (mid.x - (15.0 - h)).abs() < 1e-9 && (mid.z + h).abs() < 1e-9,
            "{mid:?}"
        );
    }
}
