//! Cross-section simulation: the axial section of one groove, cut pass by pass.
//!
//! The section is drawn in the plane through the thread's axis, in coordinates `u` (lateral, +Z,
//! the pass table's `offset`) and `v` (depth below the crest line, the pass table's `depth`). The
//! material is the blank: everything from its surface (the crest line, or `stock_above` above it)
//! down. Each pass places the tool's outline with its lowest point at `(offset, depth)`; the chip is
//! material ∩ tool, and the material left is material − tool. Both come from one boolean graph of
//! `i_overlay`, on an integer grid of [`GRID`] mm so that the results are exact for the grid and
//! the same on every machine.
//!
//! The section is the same for every controller: it reads only the [`Job`] and its pass table, and
//! it is the same for every start of a multi-start thread (each start cuts its own groove).

pub mod tool;

use i_overlay::core::extract::BooleanExtractionBuffer;
use i_overlay::core::fill_rule::FillRule;
use i_overlay::core::overlay::Overlay;
use i_overlay::core::overlay_rule::OverlayRule;
use i_overlay::i_float::int::point::IntPoint;
use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result};
use crate::thread::{Job, Pass, Side};

pub use tool::{Tip, Tool};

/// A tip whose sizes are in program units, in millimetres.
pub fn tip_in_mm(tip: Tip, units: crate::units::Units) -> Tip {
    match tip {
        Tip::Sharp => Tip::Sharp,
        Tip::Radius { radius } => Tip::Radius {
            radius: units.to_mm(radius),
        },
        Tip::Flat { width } => Tip::Flat {
            width: units.to_mm(width),
        },
    }
}

/// The groove's edges at depth `v` after `cuts` (offset, depth) with a tool of this form: the
/// outermost tool edges that reach `v`, or `None` if none does.
pub fn groove_edges(cuts: &[(f64, f64)], form: &tool::Form, v: f64) -> Option<(f64, f64)> {
    cuts.iter()
        .filter_map(|&(u0, d)| form.span_at(u0, d, v))
        .fold(None, |acc: Option<(f64, f64)>, (l, r)| match acc {
            None => Some((l, r)),
            Some((a, b)) => Some((a.min(l), b.max(r))),
        })
}

/// The grid (mm) on which the boolean operations run: 1 nm.
pub const GRID: f64 = 1e-6;
const SCALE: f64 = 1.0 / GRID;
/// The largest section coordinate (mm) the grid holds with room to spare (i32 at 1 nm: ±2147 mm;
/// the overlay engine wants headroom).
pub const MAX_COORD: f64 = 500.0;
/// Vertices of the material this close (grid steps) to the line through their neighbours are
/// dropped after each pass ([`straighten`]).
const STRAIGHT: i32 = 1;
/// Chips smaller than this (mm²) are no chip: grid noise on a spring pass.
pub const AREA_EPSILON: f64 = 1e-9;
/// A chip edge this close (mm) to the tool's outline lies on the cutting edge.
const ON_TOOL: f64 = 1e-5;
/// Bisections stop when the interval is this narrow (mm): far below any machine's resolution.
const BISECTION_WIDTH: f64 = 1e-10;
/// Below this share of the chip, a side of the tool is not counted as cutting.
pub const FLANK_SHARE_MIN: f64 = 0.25;

/// Which cutting edge of the tool removes the chip. `Left` is the tool's −Z edge, `Right` its
/// +Z edge: a flank infeed that rides down the groove's left flank (its infeed point moving toward
/// +Z) cuts with the tool's right edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CuttingFlank {
    /// No chip (a spring pass).
    None,
    Left,
    Right,
    Both,
}

impl CuttingFlank {
    pub fn name(self) -> &'static str {
        match self {
            CuttingFlank::None => "none",
            CuttingFlank::Left => "left",
            CuttingFlank::Right => "right",
            CuttingFlank::Both => "both",
        }
    }
}

/// What one pass cuts.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassSim {
    pub n: u32,
    /// Lateral position (u) and depth (v) of the tool's lowest point.
    pub offset: f64,
    pub depth: f64,
    /// Chip cross-section (mm²).
    pub area: f64,
    /// Share of the total area (0..1).
    pub share: f64,
    /// The part of the chip on the tool's −Z side of its axis (0..1).
    pub left_share: f64,
    pub flank: CuttingFlank,
    /// The largest chip thickness: the largest distance from the surface the earlier passes left to
    /// this pass's cutting edge (mm).
    pub max_thickness: f64,
    /// The chip's outline(s) in section coordinates (u, v), for plots.
    #[serde(skip)]
    pub chip: Vec<Vec<(f64, f64)>>,
}

/// The final groove against the target form: the groove one radial plunge of the same tool to the
/// full depth on the groove's axis would cut (the cycle's depth and angle).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GrooveReport {
    /// What follows from the passes and the tool alone (its fields stand beside the others in
    /// JSON).
    #[serde(flatten)]
    pub form: GrooveForm,
    /// Material removed outside the target form (mm²).
    pub overcut_area: f64,
    /// Material left inside the target form (mm²).
    pub left_in_form: f64,
}

/// The part of a [`GrooveReport`] that follows from the passes and the tool alone, without the
/// material's simulation ([`groove`], what `check` judges).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GrooveForm {
    /// Lateral position of the groove's axis as the infeed law places it.
    pub axis: f64,
    /// Where the groove's centre ended up (at the pitch line, else half way down); the target
    /// form is placed here, since a groove shifted along the thread's axis is the same thread.
    pub centre: f64,
    /// The cycle's thread depth.
    pub depth_target: f64,
    /// Deepest point cut, anywhere.
    pub depth_reached: f64,
    /// Depth cut on the groove's centre line.
    pub depth_at_axis: f64,
    /// Angles of the groove's flanks from the radial direction (degrees), measured between 20 % and
    /// 60 % of the depth reached; the target is half the tool angle.
    pub flank_angle_left_deg: f64,
    pub flank_angle_right_deg: f64,
    /// Depth of the pitch line, where the target groove is half a pitch wide; `None` when the
    /// target groove is narrower than half a pitch even at the crest.
    pub pitch_line_depth: Option<f64>,
    /// Error of the pitch diameter (diameter, mm) from a groove wider (or narrower) than the target
    /// at the pitch line: negative means an external thread's pitch diameter is undersize.
    pub pitch_diameter_error: Option<f64>,
    /// Height of the highest ridge left standing between neighbouring passes' tips (mm).
    pub ridge: f64,
}

/// The simulated section of one cycle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Section {
    pub tool: Tool,
    /// Stock above the crest line (mm, negative when the blank is below it).
    pub stock_above: f64,
    pub passes: Vec<PassSim>,
    pub total_area: f64,
    pub groove: GrooveReport,
    /// The material left after the last pass: its contours in section coordinates (u, v).
    #[serde(skip)]
    pub material: Vec<Vec<(f64, f64)>>,
}

type Contour = Vec<IntPoint<i32>>;
type Shapes = Vec<Vec<Contour>>;

/// What [`section`] reports of the groove's form that follows from the passes and the tool alone
/// ([`GrooveForm`]), with the same refusals, and without simulating the material: `check` judges
/// only these.
pub fn groove(job: &Job, passes: &[Pass], tool: &Tool, stock_above: f64) -> Result<GrooveForm> {
    extent(job, passes, tool, stock_above)?;
    Ok(groove_form(job, passes, tool))
}

/// Where a section is simulated: the blank's top, the tool's top, the bottom and the lateral
/// limits (mm, section coordinates), or the refusal of a section too large for the grid.
struct Extent {
    blank_top: f64,
    tool_top: f64,
    bottom: f64,
    u_lo: f64,
    u_hi: f64,
}

fn extent(job: &Job, passes: &[Pass], tool: &Tool, stock_above: f64) -> Result<Extent> {
    tool.validate(job.span)?;
    let too_big = |what: &str| {
        Diagnostic::error(
            Code::Geometry,
            job.span,
            format!("the thread's section is too large to simulate ({what} beyond {MAX_COORD} mm)"),
        )
    };
    if !stock_above.is_finite() || stock_above.abs() > MAX_COORD {
        return Err(too_big("stock"));
    }
    let t = tool.slope();
    let total = job.geometry.depth;
    let deepest = passes.iter().map(|p| p.depth).fold(total, f64::max);
    let apex = tool.apex_below_lowest().max(0.0);
    let blank_top = -stock_above;
    let tool_top = blank_top.min(0.0) - 1.0;
    let bottom = deepest + apex + 1.0;
    let tip_half = match tool.tip {
        Tip::Flat { width } => width / 2.0,
        _ => 0.0,
    };
    let reach = (bottom - tool_top) * t + tip_half + 1.0;
    let (lo, hi) = passes
        .iter()
        .map(|p| p.offset)
        .chain([job.infeed.axis(total)])
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), u| {
            (a.min(u), b.max(u))
        });
    let (u_lo, u_hi) = (lo - reach, hi + reach);
    let fits = |x: f64| x.is_finite() && x.abs() <= MAX_COORD;
    if ![u_lo, u_hi, bottom, tool_top].into_iter().all(fits) {
        return Err(too_big("a coordinate"));
    }
    Ok(Extent {
        blank_top,
        tool_top,
        bottom,
        u_lo,
        u_hi,
    })
}

/// Simulates the passes of `job` with `tool`; `stock_above` is the blank's surface above the
/// crest line (mm; 0: the blank is the crest line).
pub fn section(job: &Job, passes: &[Pass], tool: &Tool, stock_above: f64) -> Result<Section> {
    let Extent {
        blank_top,
        tool_top,
        bottom,
        u_lo,
        u_hi,
    } = extent(job, passes, tool, stock_above)?;
    let form = tool.form();
    let blank = contour(&[
        (u_lo, blank_top),
        (u_hi, blank_top),
        (u_hi, bottom),
        (u_lo, bottom),
    ]);
    let mut material: Shapes = vec![vec![blank.clone()]];
    let mut engine = Engine::new();
    let mut sims = Vec::with_capacity(passes.len());
    let template = tool.template();
    let mut outline = Vec::new();
    for p in passes {
        template.place(p.offset, p.depth, tool_top, &mut outline);
        let cutter = vec![vec![contour(&outline)]];
        let (chip, rest) = engine.cut(&material, &cutter);
        let area = shapes_area(&chip);
        let (left_share, flank, max_thickness) = if area > AREA_EPSILON {
            let left = chip
                .iter()
                .flatten()
                .map(|c| clipped_area(c, p.offset))
                .sum::<f64>();
            let left_share = (left / area).clamp(0.0, 1.0);
            let flank = if left_share < FLANK_SHARE_MIN {
                CuttingFlank::Right
            } else if left_share > 1.0 - FLANK_SHARE_MIN {
                CuttingFlank::Left
            } else {
                CuttingFlank::Both
            };
            let inside = Inside::new(tool, &form, p.offset, p.depth, tool_top);
            (left_share, flank, thickness(&chip, &inside))
        } else {
            (0.0, CuttingFlank::None, 0.0)
        };
        sims.push(PassSim {
            n: p.n,
            offset: p.offset,
            depth: p.depth,
            area,
            share: 0.0,
            left_share,
            flank,
            max_thickness,
            chip: chip
                .iter()
                .flatten()
                .map(|c| c.iter().map(|&p| to_float(p)).collect())
                .collect(),
        });
        material = rest;
        for c in material.iter_mut().flatten() {
            straighten(c);
        }
    }
    let total_area: f64 = sims.iter().map(|s| s.area).sum();
    for s in &mut sims {
        s.share = if total_area > AREA_EPSILON {
            s.area / total_area
        } else {
            0.0
        };
    }
    let end = Final {
        blank: &blank,
        material: &material,
        total_area,
        tool_top,
    };
    let groove = groove_report(job, passes, tool, &mut engine, &end);
    Ok(Section {
        tool: *tool,
        stock_above,
        passes: sims,
        total_area,
        groove,
        material: material
            .iter()
            .flatten()
            .map(|c| c.iter().map(|&p| to_float(p)).collect())
            .collect(),
    })
}

/// How far the groove the passes left lies from a target form (mm): the largest distance, either
/// way, between the material's surface below the crest line (`v > 0`, within the target's
/// lateral extent widened by `margin`) and the target's outline (a polyline in section
/// coordinates, such as [`crate::thread::standard::Groove::outline`] placed at
/// [`GrooveReport::centre`]). Distances are measured to segments, so a polyline sampled finely
/// enough stands for the true form; the material's vertices and edge midpoints are sampled.
pub fn profile_deviation(section: &Section, target: &[(f64, f64)], margin: f64) -> f64 {
    let (lo, hi) = target
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            (a.min(p.0), b.max(p.0))
        });
    let below = |p: (f64, f64)| p.1 > AREA_EPSILON && p.0 >= lo - margin && p.0 <= hi + margin;
    let to_polyline = |p: (f64, f64), line: &[(f64, f64)]| {
        line.windows(2)
            .map(|w| segment_distance(p, w[0], w[1]))
            .fold(f64::INFINITY, f64::min)
    };
    let mut surface: Vec<((f64, f64), (f64, f64))> = Vec::new();
    for c in &section.material {
        let n = c.len();
        for i in 0..n {
            let (a, b) = (c[i], c[(i + 1) % n]);
            if below(a) || below(b) {
                surface.push((a, b));
            }
        }
    }
    let mut worst: f64 = 0.0;
    for &(a, b) in &surface {
        let mid = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
        for p in [a, mid, b] {
            if below(p) {
                worst = worst.max(to_polyline(p, target));
            }
        }
    }
    for w in target.windows(2) {
        for k in 0..=8 {
            let f = f64::from(k) / 8.0;
            let p = (
                w[0].0 + f * (w[1].0 - w[0].0),
                w[0].1 + f * (w[1].1 - w[0].1),
            );
            if p.1 <= AREA_EPSILON {
                continue;
            }
            let d = surface
                .iter()
                .map(|&(a, b)| segment_distance(p, a, b))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
    }
    worst
}

/// Distance from `p` to the segment `a`–`b`.
pub(crate) fn segment_distance(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    segment_distance_sq(p, a, b).sqrt()
}

/// The square of [`segment_distance`] (for comparisons: no root taken).
pub(crate) fn segment_distance_sq(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let k = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (p.0 - a.0 - k * dx, p.1 - a.1 - k * dy);
    ex * ex + ey * ey
}

fn contour(points: &[(f64, f64)]) -> Contour {
    points
        .iter()
        .map(|&(u, v)| IntPoint::new((u * SCALE).round() as i32, (v * SCALE).round() as i32))
        .collect()
}

fn to_float(p: IntPoint<i32>) -> (f64, f64) {
    (f64::from(p.x) * GRID, f64::from(p.y) * GRID)
}

/// The boolean engine with its buffers, kept from one pass to the next.
struct Engine {
    overlay: Overlay<i32>,
    buf: BooleanExtractionBuffer<i32>,
}

impl Engine {
    fn new() -> Engine {
        Engine {
            overlay: Overlay::new(64),
            buf: BooleanExtractionBuffer::default(),
        }
    }

    /// material ∩ tool alone.
    fn intersect(&mut self, material: &Shapes, cutter: &Shapes) -> Shapes {
        self.overlay.reinit_with_subj_and_clip(material, cutter);
        match self.overlay.build_graph_view(FillRule::NonZero) {
            Some(graph) => graph.extract_shapes(OverlayRule::Intersect, &mut self.buf),
            None => Vec::new(),
        }
    }

    /// material ∩ tool and material − tool from one graph.
    fn cut(&mut self, material: &Shapes, cutter: &Shapes) -> (Shapes, Shapes) {
        self.overlay.reinit_with_subj_and_clip(material, cutter);
        match self.overlay.build_graph_view(FillRule::NonZero) {
            Some(graph) => (
                graph.extract_shapes(OverlayRule::Intersect, &mut self.buf),
                graph.extract_shapes(OverlayRule::Difference, &mut self.buf),
            ),
            None => (Vec::new(), material.clone()),
        }
    }
}

/// Drops the vertices of a contour that lie within [`STRAIGHT`] grid steps of the line through
/// their neighbours: at the grid's resolution they are on a straight edge. They come from a flank
/// infeed, whose tool slides its flank along the flank the last pass cut: the two rounded edges
/// are nearly collinear and cross back and forth, and each pass would add slivers a nanometre wide
/// along the flank that every later pass has to cut again.
fn straighten(c: &mut Contour) {
    let eps2 = i128::from(STRAIGHT) * i128::from(STRAIGHT);
    let mut i = 0;
    let mut since_removal = 0;
    while c.len() > 3 && since_removal <= c.len() {
        let n = c.len();
        i %= n;
        let (a, b, d) = (c[(i + n - 1) % n], c[i], c[(i + 1) % n]);
        let (ux, uy) = (i128::from(d.x - a.x), i128::from(d.y - a.y));
        let (wx, wy) = (i128::from(b.x - a.x), i128::from(b.y - a.y));
        let cross = ux * wy - uy * wx;
        if cross * cross <= eps2 * (ux * ux + uy * uy) {
            c.remove(i);
            since_removal = 0;
            i = i.saturating_sub(1);
        } else {
            i += 1;
            since_removal += 1;
        }
    }
}

/// Area (mm²) of shapes whose outer contours run counter-clockwise and holes clockwise, computed
/// exactly on the grid.
fn shapes_area(shapes: &Shapes) -> f64 {
    let twice: i128 = shapes
        .iter()
        .flatten()
        .map(|c| {
            let n = c.len();
            (0..n)
                .map(|i| {
                    let (a, b) = (c[i], c[(i + 1) % n]);
                    i128::from(a.x) * i128::from(b.y) - i128::from(b.x) * i128::from(a.y)
                })
                .sum::<i128>()
        })
        .sum();
    (twice as f64 / 2.0 * GRID * GRID).abs()
}

/// Signed area of a contour's part with u ≤ `at`, in the sign convention that makes
/// [`shapes_area`] positive (outer contours counter-clockwise).
fn clipped_area(c: &Contour, at: f64) -> f64 {
    let pts: Vec<(f64, f64)> = c.iter().map(|&p| to_float(p)).collect();
    signed_area(&clip_half(&pts, |p| at - p.0))
}

/// The part of a polygon where the affine function `side` is ≥ 0 (Sutherland–Hodgman). For a
/// non-convex polygon the result may run back and forth along the line, but its signed area is
/// still the area of the part.
pub(crate) fn clip_half(pts: &[(f64, f64)], side: impl Fn((f64, f64)) -> f64) -> Vec<(f64, f64)> {
    let n = pts.len();
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(n + 2);
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        let (sa, sb) = (side(a), side(b));
        if sa >= 0.0 {
            out.push(a);
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            let k = sa / (sa - sb);
            out.push((a.0 + k * (b.0 - a.0), a.1 + k * (b.1 - a.1)));
        }
    }
    out
}

/// Shoelace area of a closed polygon, positive for counter-clockwise in (u, v).
pub(crate) fn signed_area(pts: &[(f64, f64)]) -> f64 {
    let m = pts.len();
    let twice: f64 = (0..m)
        .map(|i| {
            let (a, b) = (pts[i], pts[(i + 1) % m]);
            a.0 * b.1 - b.0 * a.1
        })
        .sum();
    twice / 2.0
}

/// How deep a point lies inside a tool placed at `(u0, d)`: its distance to the tool's outline,
/// worked out from the tool's true form (flanks, a round nose, a flat, and the closing edge across
/// the top at `top`), not from the chord polygon. The tool is convex, so the distance from an
/// inside point is the least over its supporting lines: the two flanks, the top, the flat; and for
/// a nose, the tangent lines of the arc, whose least is `r − |p − c|` when p lies in the arc's
/// wedge below the centre c (else the arc's end tangent, a flank, is the nearest).
struct Inside {
    u0: f64,
    /// Depth of the flanks' meeting point, `d + apex`.
    apex: f64,
    t: f64,
    cos_a: f64,
    top: f64,
    /// Depth of a flat tip.
    flat: Option<f64>,
    /// Centre (depth) and radius of a nose.
    nose: Option<(f64, f64)>,
}

impl Inside {
    fn new(tool: &Tool, form: &tool::Form, u0: f64, d: f64, top: f64) -> Inside {
        let half = (tool.angle_deg / 2.0).to_radians();
        Inside {
            u0,
            apex: d + form.apex,
            t: form.t,
            cos_a: half.cos(),
            top,
            flat: (form.half_flat > 0.0).then_some(d),
            nose: (form.radius > 0.0).then_some((d - form.radius, form.radius)),
        }
    }

    /// Distance from a point inside the tool to its outline (negative outside).
    fn depth(&self, p: (f64, f64)) -> f64 {
        let x = (p.0 - self.u0).abs();
        let mut min = ((self.apex - p.1) * self.t - x) * self.cos_a;
        min = min.min(p.1 - self.top);
        if let Some(bottom) = self.flat {
            min = min.min(bottom - p.1);
        }
        if let Some((cv, r)) = self.nose {
            let dv = p.1 - cv;
            if dv > 0.0 && dv >= x * self.t {
                min = min.min(r - (x * x + dv * dv).sqrt());
            }
        }
        min
    }
}

/// The largest distance from the chip's old-surface side to the cutting edge, sampled at the
/// vertices and midpoints of the chip's edges that do not lie on the tool.
fn thickness(chip: &Shapes, inside: &Inside) -> f64 {
    let mut max: f64 = 0.0;
    for c in chip.iter().flatten() {
        let n = c.len();
        for i in 0..n {
            let (a, b) = (to_float(c[i]), to_float(c[(i + 1) % n]));
            let mid = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
            if inside.depth(mid) <= ON_TOOL {
                continue;
            }
            for p in [a, mid, b] {
                max = max.max(inside.depth(p));
            }
        }
    }
    max
}

/// The state after the last pass.
struct Final<'a> {
    /// The blank's rectangle, on the grid.
    blank: &'a Contour,
    material: &'a Shapes,
    total_area: f64,
    tool_top: f64,
}

/// The groove's form as the passes and the tool give it, without the material ([`groove`]).
fn groove_form(job: &Job, passes: &[Pass], tool: &Tool) -> GrooveForm {
    let total = job.geometry.depth;
    let axis = job.infeed.axis(total);
    let form = tool.form();
    let t = form.t;
    let cuts: Vec<(f64, f64)> = passes.iter().map(|p| (p.offset, p.depth)).collect();
    let depth_reached = cuts.iter().map(|c| c.1).fold(0.0, f64::max);
    let envelope = |u: f64| {
        cuts.iter()
            .map(|&(u0, d)| form.bottom_at(u0, d, u))
            .fold(f64::NEG_INFINITY, f64::max)
    };
    // The groove's edges at depth v: the outermost tool edges that reach it.
    let edges = |v: f64| groove_edges(&cuts, &form, v);
    let (va, vb) = (0.2 * depth_reached, 0.6 * depth_reached);
    let (flank_angle_left_deg, flank_angle_right_deg) = match (edges(va), edges(vb)) {
        (Some((la, ra)), Some((lb, rb))) if vb > va => (
            ((lb - la) / (vb - va)).atan().to_degrees(),
            ((ra - rb) / (vb - va)).atan().to_degrees(),
        ),
        _ => (0.0, 0.0),
    };
    // Pitch line: where the target groove (the tool at full depth on the axis) is half a pitch wide.
    let pitch = job.lead.start_spacing();
    let target_width = |v: f64| form.span_at(axis, total, v).map_or(0.0, |(l, r)| r - l);
    let pitch_line_depth = if pitch > 0.0 && target_width(0.0) >= pitch / 2.0 {
        let (mut a, mut b) = (0.0, total);
        while b - a > BISECTION_WIDTH {
            let m = (a + b) / 2.0;
            if target_width(m) >= pitch / 2.0 {
                a = m;
            } else {
                b = m;
            }
        }
        Some(a)
    } else {
        None
    };
    let pitch_diameter_error = pitch_line_depth.map(|v| {
        let actual = edges(v).map_or(0.0, |(l, r)| r - l);
        let excess = actual - target_width(v);
        // A wider groove makes an external thread's pitch diameter smaller and an internal one's
        // larger; a face thread is cut into the part like an external one.
        let sign = match job.geometry.side {
            Side::External | Side::FaceFront | Side::FaceBack => -1.0,
            Side::Internal => 1.0,
        };
        sign * excess / t
    });
    let ridge = ridge_height(&cuts, &form);
    // Where the groove actually is: its centre at the pitch line (else half way down). A thread
    // shifted bodily along its axis is still the same thread, so the form is judged there.
    let centre =
        edges(pitch_line_depth.unwrap_or(0.5 * depth_reached)).map_or(axis, |(l, r)| (l + r) / 2.0);
    let depth_at_axis = envelope(centre).max(0.0);
    GrooveForm {
        axis,
        centre,
        depth_target: total,
        depth_reached,
        depth_at_axis,
        flank_angle_left_deg,
        flank_angle_right_deg,
        pitch_line_depth,
        pitch_diameter_error,
        ridge,
    }
}

/// The groove the passes leave, against the target form.
fn groove_report(
    job: &Job,
    passes: &[Pass],
    tool: &Tool,
    engine: &mut Engine,
    cut: &Final,
) -> GrooveReport {
    let f = groove_form(job, passes, tool);
    let total = job.geometry.depth;
    // Overcut = removed − (removed ∩ target) = total − (target ∩ blank − target ∩ material).
    // The target is convex and the blank a rectangle: target ∩ blank is the target clipped to it.
    let target = contour(&tool.outline(f.centre, total, cut.tool_top));
    let (lo, hi) = (to_float(cut.blank[0]), to_float(cut.blank[2]));
    let mut in_blank: Vec<(f64, f64)> = target.iter().map(|&p| to_float(p)).collect();
    in_blank = clip_half(&in_blank, |p| p.0 - lo.0);
    in_blank = clip_half(&in_blank, |p| hi.0 - p.0);
    in_blank = clip_half(&in_blank, |p| p.1 - lo.1);
    in_blank = clip_half(&in_blank, |p| hi.1 - p.1);
    let in_blank = signed_area(&in_blank).abs();
    let left_in_form = shapes_area(&engine.intersect(cut.material, &vec![vec![target]]));
    let overcut_area = (cut.total_area - (in_blank - left_in_form)).max(0.0);
    GrooveReport {
        form: f,
        overcut_area,
        left_in_form,
    }
}

/// The highest ridge left standing between tips: the most the groove's bottom dips below the
/// shallower of the deepest points on either side of it.
///
/// Every tool outline is the same shape translated, and that shape is a V widened by a disk (nose)
/// or a segment (flat), so one outline lies inside another exactly when its V does: the cone test
/// `d_i − |u_k − u_i|/t ≥ d_k`. Between neighbouring outlines that no other one contains, the
/// bottom is the higher of the two, and its lowest point is where they cross.
fn ridge_height(cuts: &[(f64, f64)], form: &tool::Form) -> f64 {
    let mut sorted: Vec<(f64, f64)> = cuts.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    let covers = |a: (f64, f64), b: (f64, f64)| a.1 - (a.0 - b.0).abs() / form.t >= b.1;
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(sorted.len());
    for tip in sorted {
        if kept.last().is_some_and(|&last| covers(last, tip)) {
            continue;
        }
        while kept.last().is_some_and(|&last| covers(tip, last)) {
            kept.pop();
        }
        kept.push(tip);
    }
    let n = kept.len();
    let mut left_peak = vec![0.0_f64; n];
    let mut right_peak = vec![0.0_f64; n];
    for i in 0..n {
        left_peak[i] = kept[i].1.max(if i > 0 { left_peak[i - 1] } else { 0.0 });
        let j = n - 1 - i;
        right_peak[j] = kept[j].1.max(if i > 0 { right_peak[j + 1] } else { 0.0 });
    }
    let mut ridge: f64 = 0.0;
    for i in 1..n {
        let ((ua, da), (ub, db)) = (kept[i - 1], kept[i]);
        let (mut a, mut b) = (ua, ub);
        while b - a > BISECTION_WIDTH {
            let m = (a + b) / 2.0;
            if form.bottom_at(ua, da, m) > form.bottom_at(ub, db, m) {
                a = m;
            } else {
                b = m;
            }
        }
        let valley = form.bottom_at(ua, da, a).max(form.bottom_at(ub, db, a));
        ridge = ridge.max(left_peak[i - 1].min(right_peak[i]) - valley.max(0.0));
    }
    ridge.max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ridge_between_two_sharp_tips() {
        // t = tan 45° = 1 (90° tool): tips 1 deep at u = 0 and u = 1 meet at depth 0.5.
        let r = ridge_height(&[(0.0, 1.0), (1.0, 1.0)], &Tool::sharp(90.0).form());
        assert!((r - 0.5).abs() < 1e-9, "{r}");
        // Unequal tips: the ridge is measured from the shallower one: 0.8 − 0.4.
        let r = ridge_height(&[(0.0, 1.0), (1.0, 0.8)], &Tool::sharp(90.0).form());
        assert!((r - 0.4).abs() < 1e-9, "{r}");
        // One tip inside the other's V: no ridge.
        let r = ridge_height(&[(0.0, 1.0), (0.1, 0.5)], &Tool::sharp(90.0).form());
        assert!(r.abs() < 1e-12, "{r}");
    }

    /// Distance from `p` to the segment `a`–`b`.
    fn to_segment(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let k = (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
        (p.0 - a.0 - k * dx).hypot(p.1 - a.1 - k * dy)
    }

    #[test]
    fn depth_inside_is_the_distance_to_the_true_outline() {
        use std::f64::consts::PI;
        let (u0, d, top) = (0.3, 1.0, -1.0);
        let tips = [
            (55.0, Tip::Radius { radius: 0.2 }),
            (60.0, Tip::Radius { radius: 0.05 }),
            (29.0, Tip::Radius { radius: 0.3 }),
            (60.0, Tip::Flat { width: 0.15 }),
            (60.0, Tip::Sharp),
        ];
        for (angle, tip) in tips {
            let tool = Tool {
                angle_deg: angle,
                tip,
            };
            let half = (angle / 2.0f64).to_radians();
            // The outline as pieces: its straight edges, and for a nose the arc from the left
            // tangent point (angle π − α, v downward) to the right one (α).
            let o = tool.outline(u0, d, top);
            let (first, last) = (o[0], o[o.len() - 1]);
            let (edges, arc) = match tip {
                Tip::Radius { radius } => {
                    let c = (u0, d - radius);
                    let at = |a: f64| (c.0 + radius * a.cos(), c.1 + radius * a.sin());
                    let (tl, tr) = (at(PI - half), at(half));
                    (
                        vec![(first, tl), (tr, last), (last, first)],
                        Some((c, radius)),
                    )
                }
                _ => {
                    let n = o.len();
                    ((0..n).map(|i| (o[i], o[(i + 1) % n])).collect(), None)
                }
            };
            let truth = |p: (f64, f64)| {
                let mut m = edges
                    .iter()
                    .map(|&(a, b)| to_segment(p, a, b))
                    .fold(f64::INFINITY, f64::min);
                if let Some((c, r)) = arc {
                    let a = (p.1 - c.1).atan2(p.0 - c.0);
                    if (half..=PI - half).contains(&a) {
                        m = m.min((r - (p.0 - c.0).hypot(p.1 - c.1)).abs());
                    }
                }
                m
            };
            let form = tool.form();
            let inside = Inside::new(&tool, &form, u0, d, top);
            for i in 0..=80 {
                for j in 1..80 {
                    let v = top + (d - top) * f64::from(i) / 80.0;
                    let Some((l, r)) = form.span_at(u0, d, v) else {
                        continue;
                    };
                    let u = l + (r - l) * f64::from(j) / 80.0;
                    let (a, b) = (inside.depth((u, v)), truth((u, v)));
                    assert!((a - b).abs() < 1e-12, "{tip:?} ({u}, {v}): {a} vs {b}");
                }
            }
        }
    }

    #[test]
    fn straighten_drops_only_vertices_within_a_grid_step_of_a_line() {
        let p = |x, y| IntPoint::new(x, y);
        // A 3 mm flank at 45° with a vertex 0.7 nm off it: dropped; 2.1 nm off it: kept.
        let square = |dy| {
            vec![
                p(0, 0),
                p(1_000_000, 1_000_000 + dy),
                p(3_000_000, 3_000_000),
                p(3_000_000, 4_000_000),
                p(0, 4_000_000),
            ]
        };
        let mut c = square(1);
        straighten(&mut c);
        assert_eq!(c, [square(0)[0], square(0)[2], square(0)[3], square(0)[4]]);
        let mut c = square(3);
        straighten(&mut c);
        assert_eq!(c, square(3));
        // A nose chord's vertex (0.2 mm radius, 13 chords) stands µm off its neighbours' line.
        let tool = Tool {
            angle_deg: 60.0,
            tip: Tip::Radius { radius: 0.2 },
        };
        let mut o = contour(&tool.outline(0.0, 1.0, -1.0));
        let n = o.len();
        straighten(&mut o);
        assert_eq!(o.len(), n);
    }

    #[test]
    fn clipped_area_of_a_square() {
        let sq = contour(&[(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.0, 1.0)]);
        assert!((clipped_area(&sq, 0.5) - 0.5).abs() < 1e-9);
        assert!((clipped_area(&sq, 3.0) - 2.0).abs() < 1e-9);
    }
}
