//! The material's outline: closed rings on the grid, each edge with where it came from; the
//! boolean cut that keeps those origins, and the simplification that keeps the outline small.
//!
//! Rings run counter-clockwise around material and clockwise around holes in (x, z), so the
//! material always lies left of an edge.

use i_overlay::core::extract::BooleanExtractionBuffer;
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay::{IntOverlayOptions, Overlay};
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::core::solver::Solver;
use i_overlay::i_float::int::point::IntPoint;

use super::{Origin, GRID};

pub type Point = IntPoint<i32>;

/// One closed ring: `origins[i]` is the origin of the edge from `pts[i]` to `pts[i + 1]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Ring {
    pub pts: Vec<Point>,
    pub origins: Vec<Origin>,
}

impl Ring {
    /// The edges as (start, end, origin).
    pub fn edges(&self) -> impl Iterator<Item = (Point, Point, Origin)> + '_ {
        let n = self.pts.len();
        // The next vertex without a division (`% n` cost more than the rest of a crossing test).
        (0..n).map(move |i| {
            let next = if i + 1 == n { 0 } else { i + 1 };
            (self.pts[i], self.pts[next], self.origins[i])
        })
    }
}

/// A box on the grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    pub min: Point,
    pub max: Point,
}

impl Bounds {
    pub fn of<'a>(pts: impl IntoIterator<Item = &'a Point>) -> Option<Bounds> {
        let mut it = pts.into_iter();
        let first = *it.next()?;
        Some(it.fold(
            Bounds {
                min: first,
                max: first,
            },
            |b, p| Bounds {
                min: Point::new(b.min.x.min(p.x), b.min.y.min(p.y)),
                max: Point::new(b.max.x.max(p.x), b.max.y.max(p.y)),
            },
        ))
    }

    pub fn overlaps(&self, o: &Bounds) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
    }

    pub fn contains(&self, p: Point, margin: i32) -> bool {
        p.x >= self.min.x - margin
            && p.x <= self.max.x + margin
            && p.y >= self.min.y - margin
            && p.y <= self.max.y + margin
    }
}

/// A result edge this close (grid steps) to an edge of the cutter or of the old outline lies on it.
const ON_EDGE: f64 = 2.0;

/// The boolean engine with its buffers, kept from one cut to the next. Every vertex of the input
/// is kept in the output, so that an edge's origin can be found from its ends.
pub struct Engine {
    overlay: Overlay<i32>,
    buf: BooleanExtractionBuffer<i32>,
}

impl Engine {
    pub fn new() -> Engine {
        Engine {
            overlay: Overlay::new_custom(
                64,
                IntOverlayOptions::keep_all_points(),
                Solver::default(),
            ),
            buf: BooleanExtractionBuffer::default(),
        }
    }

    /// The rings of `material` with `op` applied against `cutter` (its pieces convex and
    /// counter-clockwise, their union the cutter).
    fn run(
        &mut self,
        material: &[Ring],
        cutter: &[Vec<Point>],
        rule: OverlayRule,
    ) -> Vec<Vec<Point>> {
        let subj: Vec<&[Point]> = material.iter().map(|r| r.pts.as_slice()).collect();
        let clip: Vec<&[Point]> = cutter.iter().map(|c| c.as_slice()).collect();
        self.overlay.reinit_with_subj_and_clip(&subj, &clip);
        match self.overlay.build_graph_view(FillRule::NonZero) {
            Some(graph) => graph
                .extract_shapes(rule, &mut self.buf)
                .into_iter()
                .flatten()
                .collect(),
            None if rule == OverlayRule::Difference => {
                material.iter().map(|r| r.pts.clone()).collect()
            }
            None => Vec::new(),
        }
    }

    /// material − cutter, each new edge with its origin: `made` where it lies on the cutter's
    /// boundary (the surface this cut leaves), else the origin of the old edge it lies on.
    pub fn cut(&mut self, material: &[Ring], cutter: &[Vec<Point>], made: Origin) -> Vec<Ring> {
        let rest = self.run(material, cutter, OverlayRule::Difference);
        let old = OldEdges::new(material);
        let cut = CutterEdges::new(cutter);
        rest.into_iter()
            .map(|pts| {
                let n = pts.len();
                let origins = (0..n)
                    .map(|i| {
                        let (a, b) = (pts[i], pts[(i + 1) % n]);
                        // A surface the cutter only runs along keeps its origin: the
                        // edges found from their ends first.
                        old.by_ends(a, b)
                            .or_else(|| cut.holds(a, b).then_some(made))
                            .unwrap_or_else(|| old.nearest(a, b))
                    })
                    .collect();
                Ring { pts, origins }
            })
            .collect()
    }

    /// material ∩ cutter: the chip, without origins.
    pub fn chip(&mut self, material: &[Ring], cutter: &[Vec<Point>]) -> Vec<Vec<Point>> {
        self.run(material, cutter, OverlayRule::Intersect)
    }
}

/// The old outline's edges, found by their ends.
/// An edge of the old outline by one of its ends: that end, the other end, its origin.
type EdgeAt = ((i32, i32), (Point, Origin));

struct OldEdges<'m> {
    material: &'m [Ring],
    /// Each edge by its start, and by its end, sorted by that point (outlines are small: a
    /// sorted table beats hashing them on every cut).
    by_start: Vec<EdgeAt>,
    by_end: Vec<EdgeAt>,
}

impl<'m> OldEdges<'m> {
    fn new(material: &'m [Ring]) -> OldEdges<'m> {
        let n: usize = material.iter().map(|r| r.pts.len()).sum();
        let (mut by_start, mut by_end) = (Vec::with_capacity(n), Vec::with_capacity(n));
        for (a, b, o) in material.iter().flat_map(Ring::edges) {
            by_start.push(((a.x, a.y), (b, o)));
            by_end.push(((b.x, b.y), (a, o)));
        }
        by_start.sort_unstable_by_key(|e| e.0);
        by_end.sort_unstable_by_key(|e| e.0);
        OldEdges {
            material,
            by_start,
            by_end,
        }
    }

    fn find(table: &[EdgeAt], p: Point) -> Option<(Point, Origin)> {
        table
            .binary_search_by_key(&(p.x, p.y), |e| e.0)
            .ok()
            .map(|i| table[i].1)
    }

    /// The origin of the old edge that the result edge `a` → `b` is part of, found from its
    /// ends: the old edge leaving `a` or reaching `b` along the same line.
    fn by_ends(&self, a: Point, b: Point) -> Option<Origin> {
        if let Some((end, o)) = Self::find(&self.by_start, a) {
            if along(a, end, b) {
                return Some(o);
            }
        }
        if let Some((start, o)) = Self::find(&self.by_end, b) {
            if along(b, start, a) {
                return Some(o);
            }
        }
        None
    }

    /// The origin of the old edge nearest the midpoint of `a` → `b` (an old edge cut at both
    /// ends by the cutter).
    fn nearest(&self, a: Point, b: Point) -> Origin {
        let m = mid(a, b);
        self.material
            .iter()
            .flat_map(Ring::edges)
            .map(|(p, q, o)| (segment_distance(m, p, q), o))
            .min_by(|x, y| x.0.total_cmp(&y.0))
            .map_or(Origin::Unknown, |(_, o)| o)
    }
}

/// The cutter's edges, piece by piece with each piece's box.
struct CutterEdges<'c> {
    pieces: Vec<(Bounds, &'c [Point])>,
    all: Option<Bounds>,
}

impl<'c> CutterEdges<'c> {
    fn new(cutter: &'c [Vec<Point>]) -> CutterEdges<'c> {
        let pieces: Vec<(Bounds, &[Point])> = cutter
            .iter()
            .filter_map(|c| Some((Bounds::of(c)?, c.as_slice())))
            .collect();
        let all = Bounds::of(pieces.iter().flat_map(|(b, _)| [&b.min, &b.max]));
        CutterEdges { pieces, all }
    }

    /// Whether the edge `a` → `b` lies on the cutter's boundary (its midpoint and both ends on
    /// one of the pieces' edges).
    fn holds(&self, a: Point, b: Point) -> bool {
        let m = mid(a, b);
        let near = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
        let (mx, my) = near(m);
        let margin = ON_EDGE.ceil() as i32;
        if !self
            .all
            .is_some_and(|bx| bx.contains(Point::new(mx, my), margin))
        {
            return false;
        }
        self.pieces
            .iter()
            .filter(|(bx, _)| bx.contains(Point::new(mx, my), margin))
            .any(|(_, c)| {
                let n = c.len();
                (0..n).any(|i| {
                    let (p, q) = (c[i], c[(i + 1) % n]);
                    segment_distance(m, p, q) <= ON_EDGE
                        && segment_distance(float(a), p, q) <= ON_EDGE
                        && segment_distance(float(b), p, q) <= ON_EDGE
                })
            })
    }
}

/// Whether `b` lies on the ray from `a` through `end` (within [`ON_EDGE`] of its line).
fn along(a: Point, end: Point, b: Point) -> bool {
    let (ux, uy) = (f64::from(end.x - a.x), f64::from(end.y - a.y));
    let (wx, wy) = (f64::from(b.x - a.x), f64::from(b.y - a.y));
    let len = ux.hypot(uy);
    len > 0.0 && (ux * wy - uy * wx).abs() <= ON_EDGE * len && ux * wx + uy * wy > 0.0
}

pub fn float(p: Point) -> (f64, f64) {
    (f64::from(p.x), f64::from(p.y))
}

fn mid(a: Point, b: Point) -> (f64, f64) {
    (
        (f64::from(a.x) + f64::from(b.x)) / 2.0,
        (f64::from(a.y) + f64::from(b.y)) / 2.0,
    )
}

/// Distance (grid steps) from `p` to the segment `a`–`b`.
pub fn segment_distance(p: (f64, f64), a: Point, b: Point) -> f64 {
    crate::sim::segment_distance(p, float(a), float(b))
}

/// Twice the signed area of a ring (grid steps², counter-clockwise positive).
pub fn twice_area(pts: &[Point]) -> i128 {
    let n = pts.len();
    (0..n)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % n]);
            i128::from(a.x) * i128::from(b.y) - i128::from(b.x) * i128::from(a.y)
        })
        .sum()
}

/// Simplifies the outline within `eps` grid steps: a vertex between two edges of one origin that
/// lies within `eps` of the line through its neighbours goes, and so does the tip of a spike
/// whose neighbours are within `eps` of each other; a ring thinner than `2·eps` (twice its area
/// over its perimeter, its mean width) goes whole. Each ring is walked at most until a full turn
/// passes without a removal, so the work is bounded by its length times its removals.
pub fn simplify(rings: &mut Vec<Ring>, eps: f64) {
    for r in rings.iter_mut() {
        simplify_ring(r, eps);
    }
    rings.retain(|r| {
        if r.pts.len() < 3 {
            return false;
        }
        let perimeter: f64 = r
            .edges()
            .map(|(a, b, _)| f64::from(b.x - a.x).hypot(f64::from(b.y - a.y)))
            .sum();
        let area = twice_area(&r.pts).unsigned_abs() as f64 / 2.0;
        2.0 * area / perimeter >= 2.0 * eps
    });
}

fn simplify_ring(r: &mut Ring, eps: f64) {
    let mut i = 0;
    let mut since_removal = 0;
    while r.pts.len() > 3 && since_removal <= r.pts.len() {
        let n = r.pts.len();
        i %= n;
        let prev = (i + n - 1) % n;
        let (a, b, c) = (r.pts[prev], r.pts[i], r.pts[(i + 1) % n]);
        let (ux, uy) = (f64::from(c.x - a.x), f64::from(c.y - a.y));
        let (wx, wy) = (f64::from(b.x - a.x), f64::from(b.y - a.y));
        let len = ux.hypot(uy);
        let spike = len <= eps;
        let straight = r.origins[prev] == r.origins[i] && (ux * wy - uy * wx).abs() <= eps * len;
        if spike || straight {
            // The edge a → c keeps a → b's origin.
            r.pts.remove(i);
            r.origins.remove(i);
            since_removal = 0;
            i = i.saturating_sub(1);
        } else {
            i += 1;
            since_removal += 1;
        }
    }
}

/// The x (mm) where the outline crosses the line z = `z` (mm), sorted: between the first and
/// the second, the third and the fourth, … lies material.
pub fn crossings_at_z(rings: &[Ring], z: f64) -> Vec<f64> {
    let y = z / GRID;
    let mut xs: Vec<f64> = rings
        .iter()
        .flat_map(Ring::edges)
        .filter_map(|(a, b, _)| {
            let (ay, by) = (f64::from(a.y), f64::from(b.y));
            // Half-open: a vertex on the line counts once.
            if (ay <= y) == (by <= y) {
                return None;
            }
            let k = (y - ay) / (by - ay);
            Some((f64::from(a.x) + k * f64::from(b.x - a.x)) * GRID)
        })
        .collect();
    xs.sort_by(f64::total_cmp);
    xs
}

/// Where the outline crosses the line z = `z` (mm): each radius (mm) with the origin of the edge
/// crossing there, sorted by radius.
pub fn surfaces_at_z(rings: &[Ring], z: f64) -> Vec<(f64, Origin)> {
    let y = z / GRID;
    let mut xs: Vec<(f64, Origin)> = rings
        .iter()
        .flat_map(Ring::edges)
        .filter_map(|(a, b, o)| Some((crossing_x(a, b, y)?, o)))
        .collect();
    xs.sort_by(|p, q| p.0.total_cmp(&q.0));
    xs
}

/// Where the outline crosses the line x = `x` (mm): each z (mm) with the origin of the edge
/// crossing there, sorted by z.
pub fn surfaces_at_x(rings: &[Ring], x: f64) -> Vec<(f64, Origin)> {
    let gx = x / GRID;
    let mut zs: Vec<(f64, Origin)> = rings
        .iter()
        .flat_map(Ring::edges)
        .filter_map(|(a, b, o)| {
            let (ax, bx) = (f64::from(a.x), f64::from(b.x));
            if (ax <= gx) == (bx <= gx) {
                return None;
            }
            let k = (gx - ax) / (bx - ax);
            Some(((f64::from(a.y) + k * f64::from(b.y - a.y)) * GRID, o))
        })
        .collect();
    zs.sort_by(|p, q| p.0.total_cmp(&q.0));
    zs
}

/// The first crossing of the line z = `z` (mm) met going from radius `from` (mm) away from the
/// axis (toward it with `inward`), with its origin: what [`surfaces_at_z`] gives searched from
/// `from`, found in one look at the edges without collecting or sorting them. `check` asks this
/// for thousands of Z a thread (`Part::surface_beyond`), where the vector and its sort cost most
/// of the time (docs/performance.md, "Issue 28").
///
/// The same crossing as the sorted search, ties included: the radius is computed by the same
/// expression; the sort is by `total_cmp` and stable (equal radii keep the edges' order), so the
/// search away from the axis takes the least radius above `from` that comes first among the
/// edges, and the search toward it, which runs from the end, the greatest below `from` that comes
/// last.
///
/// With `slabs` (built from these rings) only the edges of the band holding `z` are looked at:
/// the others cannot cross it, and those that do come in the same order.
pub fn surface_beyond(
    rings: &[Ring],
    slabs: Option<&Slabs>,
    z: f64,
    from: f64,
    inward: bool,
) -> Option<(f64, Origin)> {
    let y = z / GRID;
    let mut best: Option<(f64, Origin)> = None;
    each_edge_at(rings, slabs, y, |ring, i| {
        let n = ring.pts.len();
        let (a, b) = (ring.pts[i], ring.pts[if i + 1 == n { 0 } else { i + 1 }]);
        if let Some(x) = crossing_x(a, b, y) {
            let better = match best {
                None => true,
                Some((bx, _)) if inward => x.total_cmp(&bx) != std::cmp::Ordering::Less,
                Some((bx, _)) => x.total_cmp(&bx) == std::cmp::Ordering::Less,
            };
            let beyond = if inward { x < from } else { x > from };
            if beyond && better {
                best = Some((x, ring.origins[i]));
            }
        }
    });
    best
}

/// Calls `look(ring, i)` for every edge `i` of `rings` that may cross the line at `y` (grid
/// steps), in [`Ring::edges`]' order: with `slabs` (built from these rings) only the edges of the
/// band holding `y`, else every edge.
fn each_edge_at(rings: &[Ring], slabs: Option<&Slabs>, y: f64, mut look: impl FnMut(&Ring, usize)) {
    match slabs {
        Some(slabs) => {
            for &(r, i) in slabs.at(y) {
                look(&rings[r as usize], i as usize);
            }
        }
        // By index: the flattened iterator cost more than the crossing tests themselves.
        None => {
            for ring in rings {
                for i in 0..ring.pts.len() {
                    look(ring, i);
                }
            }
        }
    }
}

/// The least and the greatest radius (mm) where the outline crosses the line z = `z` (mm).
pub fn extent_at_z(rings: &[Ring], slabs: Option<&Slabs>, z: f64) -> Option<(f64, f64)> {
    let y = z / GRID;
    let mut extent: Option<(f64, f64)> = None;
    each_edge_at(rings, slabs, y, |ring, i| {
        let n = ring.pts.len();
        let (a, b) = (ring.pts[i], ring.pts[if i + 1 == n { 0 } else { i + 1 }]);
        if let Some(x) = crossing_x(a, b, y) {
            extent = Some(extent.map_or((x, x), |(lo, hi)| (lo.min(x), hi.max(x))));
        }
    });
    extent
}

/// Whether the point (grid steps) lies in the material (non-zero winding), looking only at the
/// edges of the band holding `p` when `slabs` (built from these rings) are given.
pub fn inside(rings: &[Ring], slabs: Option<&Slabs>, p: (f64, f64)) -> bool {
    let mut winding = 0i32;
    each_edge_at(rings, slabs, p.1, |ring, i| {
        let n = ring.pts.len();
        let (a, b) = (
            float(ring.pts[i]),
            float(ring.pts[if i + 1 == n { 0 } else { i + 1 }]),
        );
        if (a.1 <= p.1) != (b.1 <= p.1) {
            let x = a.0 + (p.1 - a.1) / (b.1 - a.1) * (b.0 - a.0);
            if x > p.0 {
                winding += if b.1 > a.1 { 1 } else { -1 };
            }
        }
    });
    winding != 0
}

/// The outline's edges by band: between two consecutive heights (grid z) of its vertices, the
/// edges that cross that band, in [`Ring::edges`]' order. An edge from `a` to `b` crosses the
/// line at `y` when `min(a.y, b.y) ≤ y < max(a.y, b.y)` (the test of [`crossing_x`]); for `y`
/// in the band [Yₖ, Yₖ₊₁) of the sorted distinct heights that is `min ≤ Yₖ < max`, since both
/// ends are among the heights. Below the lowest height and from the highest on, no edge
/// crosses. `check` asks for the surface at thousands of Z along each thread
/// (docs/performance.md, "Issue 28"); the bands make each look a binary search and the few
/// edges there instead of every edge.
#[derive(Clone, Debug)]
pub struct Slabs {
    heights: Vec<i32>,
    /// Band k's edges are `edges[starts[k]..starts[k + 1]]`.
    starts: Vec<usize>,
    edges: Vec<(u32, u32)>,
}

impl Slabs {
    /// Outlines with more edges than this are looked at edge by edge (the bands could hold the
    /// square of the edges).
    pub const MAX_EDGES: usize = 256;

    /// The bands of `rings`, or `None` for an outline over [`Slabs::MAX_EDGES`] edges.
    pub fn new(rings: &[Ring]) -> Option<Slabs> {
        let count: usize = rings.iter().map(|r| r.pts.len()).sum();
        if count > Slabs::MAX_EDGES {
            return None;
        }
        let mut heights: Vec<i32> = rings
            .iter()
            .flat_map(|r| r.pts.iter().map(|p| p.y))
            .collect();
        heights.sort_unstable();
        heights.dedup();
        let mut starts = Vec::with_capacity(heights.len());
        let mut edges = Vec::new();
        // Bounded: bands × edges, at most MAX_EDGES².
        for &h in heights.iter().take(heights.len().saturating_sub(1)) {
            starts.push(edges.len());
            for (r, ring) in rings.iter().enumerate() {
                let n = ring.pts.len();
                for i in 0..n {
                    let (a, b) = (
                        ring.pts[i].y,
                        ring.pts[if i + 1 == n { 0 } else { i + 1 }].y,
                    );
                    if a.min(b) <= h && h < a.max(b) {
                        edges.push((r as u32, i as u32));
                    }
                }
            }
        }
        starts.push(edges.len());
        Some(Slabs {
            heights,
            starts,
            edges,
        })
    }

    /// The edges that may cross the line at `y` (grid steps), in the outline's order.
    fn at(&self, y: f64) -> &[(u32, u32)] {
        // The bands whose lower height is at most y (none for a NaN).
        let k = self.heights.partition_point(|&h| f64::from(h) <= y);
        if k == 0 || k >= self.heights.len() {
            return &[];
        }
        &self.edges[self.starts[k - 1]..self.starts[k]]
    }
}

/// Where the edge from `a` to `b` crosses the line at `y` (grid steps): its radius in mm, as
/// [`surfaces_at_z`] computes it.
#[inline(always)]
fn crossing_x(a: Point, b: Point, y: f64) -> Option<f64> {
    let (ay, by) = (f64::from(a.y), f64::from(b.y));
    if (ay <= y) == (by <= y) {
        return None;
    }
    let k = (y - ay) / (by - ay);
    Some((f64::from(a.x) + k * f64::from(b.x - a.x)) * GRID)
}

/// The z (mm) where the outline crosses the line x = `x` (mm), sorted.
pub fn crossings_at_x(rings: &[Ring], x: f64) -> Vec<f64> {
    let gx = x / GRID;
    let mut zs: Vec<f64> = rings
        .iter()
        .flat_map(Ring::edges)
        .filter_map(|(a, b, _)| {
            let (ax, bx) = (f64::from(a.x), f64::from(b.x));
            if (ax <= gx) == (bx <= gx) {
                return None;
            }
            let k = (gx - ax) / (bx - ax);
            Some((f64::from(a.y) + k * f64::from(b.y - a.y)) * GRID)
        })
        .collect();
    zs.sort_by(f64::total_cmp);
    zs
}

/// Whether cutting `cutter` (convex pieces) out of `material` would remove nothing: no edge of
/// the material passes through the open inside of a piece, and no piece lies in the material.
/// The boolean engine is then not run: a tool that only runs along a surface leaves it as it
/// was, origin and all (see [`Engine::cut`]). Exact on the grid: an edge that only touches a
/// piece's boundary does not enter it.
pub fn removes_nothing(
    material: &[Ring],
    slabs: Option<&Slabs>,
    extent: &Bounds,
    cutter: &[Vec<Point>],
) -> bool {
    cutter.iter().all(|piece| {
        let area = twice_area(piece);
        if area == 0 {
            return true;
        }
        let Some(bounds) = Bounds::of(piece) else {
            return true;
        };
        if !bounds.overlaps(extent) {
            return true;
        }
        let sign: i64 = if area > 0 { 1 } else { -1 };
        let enters = material.iter().any(|ring| {
            ring.edges().any(|(a, b, _)| {
                let edge = Bounds::of([&a, &b]).expect("two points");
                edge.overlaps(&bounds) && enters_convex(piece, sign, a, b)
            })
        });
        if enters {
            return false;
        }
        // No edge enters: the piece lies wholly in the material or wholly outside it.
        let n = piece.len() as f64;
        let (sx, sy) = piece.iter().fold((0.0, 0.0), |(x, y), p| {
            (x + f64::from(p.x), y + f64::from(p.y))
        });
        !inside(material, slabs, (sx / n, sy / n))
    })
}

/// Whether the segment `a`–`b` passes through the open inside of the convex `piece` (its
/// vertices counter-clockwise when `sign` is 1, clockwise when −1): the stretch of the segment
/// strictly inside every edge's half-plane is longer than a point.
fn enters_convex(piece: &[Point], sign: i64, a: Point, b: Point) -> bool {
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    let n = piece.len();
    for i in 0..n {
        let (v, w) = (piece[i], piece[if i + 1 == n { 0 } else { i + 1 }]);
        let (ex, ey) = (i64::from(w.x - v.x), i64::from(w.y - v.y));
        let cross = |px: i64, py: i64| sign * (ex * py - ey * px);
        // f(t) = n0 + t·d: positive strictly inside this edge's half-plane.
        let n0 = cross(i64::from(a.x - v.x), i64::from(a.y - v.y));
        let d = cross(i64::from(b.x - a.x), i64::from(b.y - a.y));
        if d == 0 {
            if n0 <= 0 {
                return false;
            }
        } else {
            let t = -(n0 as f64) / d as f64;
            if d > 0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t1 - t0 <= 1e-12 {
                return false;
            }
        }
    }
    t1 - t0 > 1e-12
}

/// The distance (grid steps) from `p` to the nearest edge, with that edge.
pub fn nearest_edge(rings: &[Ring], p: (f64, f64)) -> Option<(f64, Point, Point, Origin)> {
    rings
        .iter()
        .flat_map(Ring::edges)
        .map(|(a, b, o)| {
            (
                crate::sim::segment_distance_sq(p, float(a), float(b)),
                a,
                b,
                o,
            )
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(d2, a, b, o)| (d2.sqrt(), a, b, o))
}

/// Whether some edge lies within `d` (grid steps) of `p`.
pub fn near_edge(rings: &[Ring], p: (f64, f64), d: f64) -> bool {
    let d2 = d * d;
    rings
        .iter()
        .flat_map(Ring::edges)
        .any(|(a, b, _)| crate::sim::segment_distance_sq(p, float(a), float(b)) <= d2)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ring(pts: &[(i32, i32)], o: Origin) -> Ring {
        Ring {
            pts: pts.iter().map(|&(x, y)| Point::new(x, y)).collect(),
            origins: vec![o; pts.len()],
        }
    }

    #[test]
    fn simplify_merges_collinear_edges_of_one_origin_only() {
        // A square 0..100 with an extra vertex at (50, 0) on its bottom edge (one origin): it goes.
        let o = Origin::Unknown;
        let mut rings = vec![ring(&[(0, 0), (50, 0), (100, 0), (100, 100), (0, 100)], o)];
        simplify(&mut rings, 5.0);
        assert_eq!(rings[0].pts.len(), 4);
        // With two origins on the bottom edge it stays.
        let mut r = ring(&[(0, 0), (50, 0), (100, 0), (100, 100), (0, 100)], o);
        r.origins[1] = Origin::Cut(super::super::Cut {
            line: 3,
            pass: 0,
            kind: super::super::CutKind::Feed,
        });
        let mut rings = vec![r];
        simplify(&mut rings, 5.0);
        assert_eq!(rings[0].pts.len(), 5);
        // A ring 2 steps thick (mean width 2·200/204 ≈ 1.96 < 2·5) is a sliver: it goes.
        let mut rings = vec![ring(&[(0, 0), (100, 0), (100, 2), (0, 2)], o)];
        simplify(&mut rings, 5.0);
        assert!(rings.is_empty());
    }

    #[test]
    fn removes_nothing_only_when_no_material_lies_in_the_cutter() {
        // Material: the square 0..100 × 0..100 (grid steps).
        let m = vec![ring(
            &[(0, 0), (100, 0), (100, 100), (0, 100)],
            Origin::Unknown,
        )];
        let piece = |pts: &[(i32, i32)]| vec![pts.iter().map(|&(x, y)| Point::new(x, y)).collect()];
        let extent = Bounds::of(m.iter().flat_map(|r| &r.pts)).expect("a square");
        let slabs = Slabs::new(&m);
        // The same answer edge by edge and band by band.
        let nothing = |c: &[Vec<Point>]| {
            let banded = removes_nothing(&m, slabs.as_ref(), &extent, c);
            assert_eq!(banded, removes_nothing(&m, None, &extent, c));
            banded
        };
        // Along the right side, touching it over its length: nothing removed.
        assert!(nothing(&piece(&[
            (100, 0),
            (150, 0),
            (150, 100),
            (100, 100)
        ])));
        // Clockwise, the same.
        assert!(nothing(&piece(&[
            (100, 100),
            (150, 100),
            (150, 0),
            (100, 0)
        ])));
        // Touching at one corner only: nothing.
        assert!(nothing(&piece(&[(100, 100), (150, 100), (150, 150)])));
        // One step into the right side: material goes.
        assert!(!nothing(&piece(&[
            (99, 0),
            (150, 0),
            (150, 100),
            (99, 100)
        ])));
        // Wholly inside (no edge enters it): material goes.
        assert!(!nothing(&piece(&[(10, 10), (20, 10), (20, 20), (10, 20)])));
        // Wholly around the square: material goes.
        assert!(!nothing(&piece(&[
            (-10, -10),
            (200, -10),
            (200, 200),
            (-10, 200)
        ])));
        // Far away, and a flat piece: nothing.
        assert!(nothing(&piece(&[(300, 0), (400, 0), (400, 50)])));
        assert!(nothing(&piece(&[(10, 10), (20, 20), (30, 30)])));
    }

    #[test]
    fn crossings_and_inside() {
        // Material 0..10 (x) × −5..0 (z) in grid steps of 0.1 µm: a ring of 10 µm × 5 µm.
        let rings = vec![ring(
            &[(0, -50), (100, -50), (100, 0), (0, 0)],
            Origin::Unknown,
        )];
        let xs = crossings_at_z(&rings, -2.0 * GRID);
        assert_eq!(xs.len(), 2);
        assert!((xs[1] - 100.0 * GRID).abs() < 1e-12);
        assert!(inside(&rings, None, (50.0, -20.0)));
        assert!(!inside(&rings, None, (150.0, -20.0)));
    }
}
