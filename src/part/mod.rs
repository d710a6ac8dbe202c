//! The part, as the program makes it: the material of an axisymmetric part in the XZ half-plane
//! (X ≥ 0 a radius, Z along the axis, mm), from the stock, cut by every feed move.
//!
//! The material is a set of closed rings on an integer grid of [`GRID`] mm, cut with the same
//! exact boolean engine as the thread's section ([`crate::sim`]). Every edge of the outline keeps
//! where it came from ([`Origin`]): the stock as given, the stock as assumed, or the program line
//! that cut it and how (a feed move, an arc, a thread pass). After each cut the outline is
//! simplified within the program's resolution, so its size stays bounded on long programs.
//!
//! Rapids never cut: [`Part::rapid_hits`] says where one would enter material and what it hits.
//! The model and its decisions are described in docs/simulation.md, "The part".

mod outline;
pub mod sweep;

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::sim::{clip_half, signed_area};
use crate::toolpath::{Motion, MotionKind};
use crate::units::{Pos, Units};

use outline::{Bounds, Engine, Point, Ring};
use sweep::{Reach, Sweeper};

/// The grid (mm) the booleans run on: 0.1 µm, a tenth of the finest resolution the controls
/// threadcut reads write (0.001 mm; 0.0001 inch is 2.54 µm).
pub const GRID: f64 = 1e-4;

/// The largest coordinate (mm) the part holds: the grid's i32 coordinates reach ±107 m, and the
/// boolean engine wants them within ±2^30; 10 m leaves room for any lathe.
pub const MAX_COORD: f64 = 10_000.0;

/// How far (mm) a tool's body reaches beyond the stock: out of the material, whatever it is.
const BEYOND: f64 = 1.0;

/// Samples along a rapid between two crossings of the outline, to find how deep it runs.
const DEPTH_SAMPLES: usize = 5;
/// Points along a rapid at which the material it runs through is looked up
/// ([`Part::rapid_inside`]).
pub const INSIDE_SAMPLES: usize = 32;

/// Whether a dimension of the stock was given, assumed, or is not known at all (the model then
/// holds material there so that cuts have something to remove, and claims nothing about it).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Known {
    Given,
    Assumed,
    Unknown,
}

/// One dimension of the stock (mm), given or assumed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Dim {
    pub value: f64,
    pub known: Known,
}

impl Dim {
    pub fn given(value: f64) -> Dim {
        Dim {
            value,
            known: Known::Given,
        }
    }

    pub fn assumed(value: f64) -> Dim {
        Dim {
            value,
            known: Known::Assumed,
        }
    }

    pub fn unknown(value: f64) -> Dim {
        Dim {
            value,
            known: Known::Unknown,
        }
    }

    /// The given value, else the assumed one.
    pub fn given_or(given: Option<f64>, assumed: f64) -> Dim {
        given.map_or(Dim::assumed(assumed), Dim::given)
    }
}

/// The stock: a bar (or tube) of `diameter`, whose face is at Z `face`, `length` long toward −Z,
/// with a bore of `bore` (0: none). All mm, diameters as diameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stock {
    pub diameter: Dim,
    pub face: Dim,
    pub length: Dim,
    pub bore: Dim,
}

impl Stock {
    /// Refuses a stock the part cannot hold: a bore not inside the bar, no length, a value not a
    /// number or beyond [`MAX_COORD`].
    pub fn validate(&self) -> Result<()> {
        let bad = |what: String| Err(Diagnostic::error(Code::Geometry, Span::default(), what));
        let dims = [
            ("diameter", self.diameter),
            ("face", self.face),
            ("length", self.length),
            ("bore", self.bore),
        ];
        for (name, d) in dims {
            if !d.value.is_finite() || d.value.abs() > MAX_COORD {
                return bad(format!(
                    "the stock's {name} ({}) is not a length the part can hold (at most {MAX_COORD} mm)",
                    d.value
                ));
            }
        }
        if self.diameter.value <= 0.0 || self.length.value <= 0.0 {
            return bad("the stock needs a diameter and a length above 0".into());
        }
        if self.bore.value < 0.0 || self.bore.value >= self.diameter.value {
            return bad(format!(
                "the stock's bore Ø{} must lie inside its diameter Ø{}",
                self.bore.value, self.diameter.value
            ));
        }
        if (self.face.value - self.length.value).abs() > MAX_COORD {
            return bad("the stock's end lies beyond what the part can hold".into());
        }
        Ok(())
    }
}

/// Which surface of the stock an edge is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum StockEdge {
    /// The bar's outside diameter.
    Outside,
    /// The face (the +Z end).
    Face,
    /// The far end (toward the chuck).
    End,
    /// The bore's wall.
    Bore,
    /// The axis of a solid bar: no surface.
    Axis,
}

/// How a program line cut a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CutKind {
    /// A straight feed move (turning, facing, boring).
    Feed,
    /// A circular feed move.
    Arc,
    /// An arc whose centre the program does not give, cut as its chord.
    Chord,
    /// A thread pass.
    Thread,
}

/// A program line's cut.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Cut {
    pub line: u32,
    /// The pass of its cycle (0 outside a cycle).
    pub pass: u32,
    pub kind: CutKind,
}

/// Where an edge of the outline came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "from", rename_all = "lowercase")]
pub enum Origin {
    Stock {
        edge: StockEdge,
        known: Known,
    },
    Cut(Cut),
    /// Swept by the body of the tool of this line's cut, away from where its nose passed: the
    /// material behind it is the stock's (as well known as the stock is), not a surface the
    /// program cut.
    Cleared(Cut),
    /// Never on an outline the part made (a fallback the tests rule out).
    Unknown,
}

/// The tool's body behind its nose, which removes what the nose passes under.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Body {
    /// A turning or boring tool: its body reaches away from the axis (toward it in a bore) and
    /// toward +Z (its end cutting edge), so a move along Z takes the material outside the path
    /// and a facing move toward the axis takes the material in front of it.
    Turning,
    /// A threading or grooving tool: its body reaches only away from the axis (toward it in a
    /// bore), as wide as its nose.
    Radial,
    /// A drill or a tool that enters along the axis: its body reaches only toward +Z, as wide as
    /// its nose (for a drill, its radius, the programmed point on its axis).
    Axial,
}

/// The cutting tool: its nose radius (mm; 0 for a point) and its body. The moves give the
/// programmed point, as without nose compensation (G40): for a turning tool the imaginary tip
/// (the nose's centre `r` outward and `r` toward +Z of it), for a radial tool its lowest point
/// (the centre `r` outward of it).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tool {
    pub nose_radius: f64,
    pub body: Body,
}

impl Tool {
    pub fn point(body: Body) -> Tool {
        Tool {
            nose_radius: 0.0,
            body,
        }
    }

    /// The nose centre's offset from the programmed point; `internal`: the tool works in a bore.
    fn centre_offset(&self, internal: bool) -> (f64, f64) {
        let r = self.nose_radius;
        let dx = if internal { -r } else { r };
        match self.body {
            Body::Turning => (dx, r),
            Body::Radial => (dx, 0.0),
            Body::Axial => (0.0, 0.0),
        }
    }
}

/// The kind of surface a rapid hits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Surface {
    /// A surface along Z: an outside diameter, or a bore's wall (`bore`), of this diameter (mm).
    Diameter { diameter: f64, bore: bool },
    /// A surface along X at this Z (mm).
    Face { z: f64 },
    /// A taper or an arc, this diameter (mm) where it is hit.
    Slope { diameter: f64 },
}

/// Where a rapid enters material and what it hits.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Hit {
    /// The first point in the material (mm, X a radius).
    pub at: Pos,
    pub origin: Origin,
    pub surface: Surface,
    /// How the stock's diameter is known (what a cleared surface's material rests on).
    pub stock_diameter: Known,
}

impl Hit {
    /// Whether the surface is the stock's alone, and how its dimension is known: `None` when the
    /// program cut it (a fact: material lies behind it, whatever the stock).
    pub fn stock_only(&self) -> Option<Known> {
        match self.origin {
            Origin::Stock { known, .. } => Some(known),
            Origin::Cleared(_) => Some(self.stock_diameter),
            _ => None,
        }
    }

    /// The hit in words, numbers in `units` (diameters as diameters): "the thread's root
    /// Ø16.933 at Z-10 (line 12)".
    pub fn describe(&self, units: Units) -> String {
        let n = |mm: f64| number(units.from_mm(mm), units);
        let z = n(self.at.z);
        let what = match self.surface {
            Surface::Diameter { diameter, bore } => {
                let d = n(diameter);
                match (self.origin, bore) {
                    (Origin::Cut(c), _) if c.kind == CutKind::Thread => {
                        format!("the thread's root Ø{d} at Z{z}")
                    }
                    (Origin::Stock { .. }, false) => format!("the stock's outside Ø{d} at Z{z}"),
                    (Origin::Stock { .. }, true) => format!("the stock's bore Ø{d} at Z{z}"),
                    (_, false) => format!("the turned diameter Ø{d} at Z{z}"),
                    (_, true) => format!("the bore wall Ø{d} at Z{z}"),
                }
            }
            Surface::Face { z } => {
                let z = n(z);
                match self.origin {
                    Origin::Stock {
                        edge: StockEdge::End,
                        ..
                    } => format!("the stock's end at Z{z}"),
                    Origin::Stock { .. } => format!("the stock's face at Z{z}"),
                    Origin::Cut(c) if c.kind == CutKind::Thread => {
                        format!("the thread's groove wall at Z{z}")
                    }
                    _ => format!("the face at Z{z}"),
                }
            }
            Surface::Slope { diameter } => {
                let d = n(diameter);
                match self.origin {
                    Origin::Cut(c) if c.kind == CutKind::Thread => {
                        format!("the thread's root Ø{d} at Z{z}")
                    }
                    Origin::Stock { .. } => format!("the stock at Ø{d}, Z{z}"),
                    _ => format!("the profile at Ø{d}, Z{z}"),
                }
            }
        };
        match self.origin {
            Origin::Cut(c) => format!("{what} (cut at line {})", c.line),
            Origin::Cleared(c) => format!(
                "{what} (where the tool of line {} passed above it; the stock's diameter {})",
                c.line,
                match self.stock_diameter {
                    Known::Given => "as given",
                    Known::Assumed => "as assumed",
                    Known::Unknown => "not known",
                }
            ),
            Origin::Stock { known, .. } => format!(
                "{what} ({})",
                match known {
                    Known::Given => "stock as given",
                    Known::Assumed => "stock as assumed",
                    Known::Unknown => "stock not known",
                }
            ),
            Origin::Unknown => what,
        }
    }
}

/// A number as a program writes it: 3 decimals in mm, 4 in inches, trailing zeros dropped.
fn number(v: f64, units: Units) -> String {
    let digits = if units == Units::Inch { 4 } else { 3 };
    let s = format!("{v:.digits$}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// The material's radii at one Z (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Radii {
    /// The outermost material.
    pub outer: f64,
    /// Where the material begins from the axis, when it does not reach it (a bore).
    pub bore: Option<f64>,
}

/// Material a path meets beyond the depth it should cut at ([`Part::shoulder`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Shoulder {
    /// Where along Z the path first meets it (mm).
    pub z: f64,
    /// The area of the material beyond the depth that the move would take (mm², in the
    /// half-section).
    pub area: f64,
    pub line: u32,
    pub pass: u32,
    /// The surface of the part the material lies behind (where the chip begins).
    pub origin: Origin,
}

/// The part: its material, the tolerance and the stock it started from (and the boolean
/// engine's buffers, kept from one cut to the next).
pub struct Part {
    rings: Vec<Ring>,
    /// The outline's edges by band of Z, built when first asked for after a change of `rings`
    /// (`outline::Slabs`; `None` inside: an outline too large for them).
    slabs: std::cell::OnceCell<Option<outline::Slabs>>,
    stock: Stock,
    tolerance: f64,
    reach: (f64, f64),
    engine: Engine,
}

impl Clone for Part {
    fn clone(&self) -> Part {
        Part {
            rings: self.rings.clone(),
            slabs: std::cell::OnceCell::new(),
            stock: self.stock,
            tolerance: self.tolerance,
            reach: self.reach,
            engine: Engine::new(),
        }
    }
}

impl std::fmt::Debug for Part {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Part")
            .field("stock", &self.stock)
            .field("tolerance", &self.tolerance)
            .field("outline", &self.outline())
            .finish()
    }
}

fn to_grid(x: f64, z: f64) -> Point {
    Point::new((x / GRID).round() as i32, (z / GRID).round() as i32)
}

fn to_pos(p: (f64, f64)) -> Pos {
    Pos::new(p.0 * GRID, p.1 * GRID)
}

impl Part {
    /// The stock's half-section (minus the bore), at `tolerance` (mm, the program's resolution;
    /// at least a few grid steps).
    pub fn new(stock: &Stock, tolerance: f64) -> Result<Part> {
        stock.validate()?;
        let tolerance = if tolerance.is_finite() {
            tolerance.max(10.0 * GRID)
        } else {
            0.001
        };
        let (outer, inner) = (stock.diameter.value / 2.0, stock.bore.value / 2.0);
        let (face, end) = (stock.face.value, stock.face.value - stock.length.value);
        let o = |edge, d: Dim| Origin::Stock {
            edge,
            known: d.known,
        };
        let inner_edge = if inner > 0.0 {
            o(StockEdge::Bore, stock.bore)
        } else {
            Origin::Stock {
                edge: StockEdge::Axis,
                known: Known::Given,
            }
        };
        let ring = Ring {
            pts: vec![
                to_grid(inner, end),
                to_grid(outer, end),
                to_grid(outer, face),
                to_grid(inner, face),
            ],
            origins: vec![
                o(StockEdge::End, stock.length),
                o(StockEdge::Outside, stock.diameter),
                o(StockEdge::Face, stock.face),
                inner_edge,
            ],
        };
        Ok(Part {
            rings: vec![ring],
            slabs: std::cell::OnceCell::new(),
            stock: *stock,
            tolerance,
            reach: (outer + BEYOND, face + BEYOND),
            engine: Engine::new(),
        })
    }

    pub fn stock(&self) -> &Stock {
        &self.stock
    }

    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The vertices of the outline: its size.
    pub fn vertex_count(&self) -> usize {
        self.rings.iter().map(|r| r.pts.len()).sum()
    }

    /// The outline's rings (mm), each vertex with the origin of the edge that leaves it. Material
    /// lies left of each edge in (x, z) with X as the first axis: outer rings run
    /// counter-clockwise there, holes clockwise.
    pub fn outline(&self) -> Vec<Vec<(Pos, Origin)>> {
        self.rings
            .iter()
            .map(|r| {
                r.pts
                    .iter()
                    .zip(&r.origins)
                    .map(|(p, o)| (to_pos(outline::float(*p)), *o))
                    .collect()
            })
            .collect()
    }

    /// Removes what the tool sweeps along the feed move from `from` to `motion.to`: a straight
    /// feed or thread move, or an arc about its centre. Rapids cut nothing (see
    /// [`rapid_hits`](Part::rapid_hits)). A move with a coordinate beyond [`MAX_COORD`] is
    /// refused.
    pub fn cut(&mut self, from: Pos, motion: &Motion, tool: &Tool) -> Result<()> {
        let internal = self.in_bore(from, motion.to);
        self.cut_oriented(from, motion, tool, internal)
    }

    /// [`cut`](Part::cut) with the side the tool works on stated (`internal`: in a bore, its body
    /// reaching toward the axis), for a move whose side the program says (a turning cycle's
    /// contour, a chain of moves that retracts toward the axis) rather than the model.
    pub fn cut_oriented(
        &mut self,
        from: Pos,
        motion: &Motion,
        tool: &Tool,
        internal: bool,
    ) -> Result<()> {
        match cut_kind(motion) {
            Some(kind) => self.cut_as(from, motion, tool, kind, internal, true),
            None => Ok(()),
        }
    }

    /// [`cut_oriented`](Part::cut_oriented) that marks no surface as the program's: everything it
    /// removes is cleared, its material the stock's — for a tool whose width the program does not
    /// state (a grooving, parting or drilling tool), so that the walls of its slot are not facts.
    pub fn clear_oriented(
        &mut self,
        from: Pos,
        motion: &Motion,
        tool: &Tool,
        internal: bool,
    ) -> Result<()> {
        match cut_kind(motion) {
            Some(kind) => self.cut_as(from, motion, tool, kind, internal, false),
            None => Ok(()),
        }
    }

    /// Cuts a circular move whose centre the program does not give as its chord, from `from` to
    /// `motion.to`, marking the surface as a chord ([`CutKind::Chord`]).
    pub fn cut_chord(&mut self, from: Pos, motion: &Motion, tool: &Tool) -> Result<()> {
        let straight = Motion {
            kind: MotionKind::Feed,
            ..*motion
        };
        let internal = self.in_bore(from, motion.to);
        self.cut_as(from, &straight, tool, CutKind::Chord, internal, true)
    }

    fn cut_as(
        &mut self,
        from: Pos,
        motion: &Motion,
        tool: &Tool,
        kind: CutKind,
        internal: bool,
        mark: bool,
    ) -> Result<()> {
        let pieces = self.sweep(from, motion, tool, internal)?;
        let cut = Cut {
            line: motion.line,
            pass: motion.pass,
            kind,
        };
        // What the body sweeps is cleared; where the nose passed becomes the program's surface
        // below. A thread's cut is the thread's all through.
        let made = if kind == CutKind::Thread {
            Origin::Cut(cut)
        } else {
            Origin::Cleared(cut)
        };
        let Some(cutter) = Bounds::of(pieces.iter().flatten()) else {
            return Ok(());
        };
        let Some(material) = Bounds::of(self.rings.iter().flat_map(|r| &r.pts)) else {
            return Ok(());
        };
        if !cutter.overlaps(&material) {
            return Ok(());
        }
        let untouched = outline::removes_nothing(&self.rings, self.slabs(), &material, &pieces);
        if untouched && (kind == CutKind::Thread || !mark) {
            return Ok(());
        }
        let mut rings = if untouched {
            self.rings.clone()
        } else {
            let mut rings = self.engine.cut(&self.rings, &pieces, made);
            outline::simplify(&mut rings, self.tolerance / 2.0 / GRID);
            rings
        };
        if kind != CutKind::Thread && mark {
            // Only where the nose passed is the surface the program's: the rest of what the body
            // swept is cleared, its material the stock's.
            let trace = self.trace(from, motion, tool, internal);
            for ring in &mut rings {
                mark_trace(ring, &trace, tool.nose_radius, self.tolerance, cut);
            }
        }
        if rings != self.rings {
            self.rings = rings;
            self.slabs = std::cell::OnceCell::new();
        }
        Ok(())
    }

    /// The path of the nose's centre along one move (mm): its ends, or the points of its arc.
    fn trace(&self, from: Pos, motion: &Motion, tool: &Tool, internal: bool) -> Vec<Pos> {
        let (dx, dz) = tool.centre_offset(internal);
        let shift = |p: Pos| Pos::new(p.x + dx, p.z + dz);
        match motion.kind {
            MotionKind::Arc { centre, clockwise } => sweep::arc_points(
                shift(from),
                shift(motion.to),
                shift(centre),
                clockwise,
                self.tolerance,
            ),
            _ => vec![shift(from), shift(motion.to)],
        }
    }

    /// The convex pieces the tool sweeps along one move.
    fn sweep(
        &self,
        from: Pos,
        motion: &Motion,
        tool: &Tool,
        internal: bool,
    ) -> Result<Vec<Vec<Point>>> {
        let to = motion.to;
        let fits = |p: Pos| p.is_finite() && p.x.abs() <= MAX_COORD && p.z.abs() <= MAX_COORD;
        let r = tool.nose_radius;
        let centre = match motion.kind {
            MotionKind::Arc { centre, .. } => Some(centre),
            _ => None,
        };
        if !fits(from)
            || !fits(to)
            || centre.is_some_and(|c| !fits(c))
            || !(0.0..=100.0).contains(&r)
        {
            return Err(Diagnostic::error(
                Code::Geometry,
                Span::new(0, 0, motion.line, 1),
                format!(
                    "the move to X{} Z{} lies beyond what the part model holds (±{MAX_COORD} mm), or the nose radius {r} mm is not one",
                    to.x, to.z
                ),
            ));
        }
        let (dx, dz) = tool.centre_offset(internal);
        let shift = |p: Pos| Pos::new(p.x + dx, p.z + dz);
        let sweeper = Sweeper {
            tool,
            reach: Reach {
                x_ray: if internal { -BEYOND } else { self.reach.0 },
                z_ray: self.reach.1,
                inward: internal,
            },
            tolerance: self.tolerance,
        };
        let mut pieces = Vec::new();
        match motion.kind {
            MotionKind::Arc { centre, clockwise } => sweeper.arc(
                shift(from),
                shift(to),
                shift(centre),
                clockwise,
                &mut pieces,
            ),
            _ => sweeper.line(shift(from), shift(to), &mut pieces),
        }
        Ok(pieces)
    }

    /// Whether the tool moving from `a` to `b` works in a bore: somewhere along the move the
    /// material at its Z does not reach the axis, and the tool is nearer the bore than the
    /// outside (below the middle of the material's extent there).
    pub fn in_bore(&self, a: Pos, b: Pos) -> bool {
        (0..=4).any(|i| {
            let k = f64::from(i) / 4.0;
            let p = Pos::new(a.x + k * (b.x - a.x), a.z + k * (b.z - a.z));
            outline::extent_at_z(&self.rings, self.slabs(), p.z).is_some_and(|(inner, outer)| {
                inner > self.tolerance / 2.0 && p.x < (inner + outer) / 2.0
            })
        })
    }

    /// Points of the rapid from `from` to `to` that lie in material deeper than half the
    /// tolerance, after it first leaves any material it starts in, each with the nearest surface
    /// (its distance, mm, and origin): the material a rapid runs through, whatever surface it
    /// came in by. At most [`INSIDE_SAMPLES`] points, evenly along it.
    pub fn rapid_inside(&self, from: Pos, to: Pos) -> Vec<(Pos, f64, Origin)> {
        let deep = self.tolerance / 2.0 / GRID;
        let mut out = Vec::new();
        let mut leading = true;
        for i in 0..=INSIDE_SAMPLES {
            let k = i as f64 / INSIDE_SAMPLES as f64;
            let p = Pos::new(from.x + k * (to.x - from.x), from.z + k * (to.z - from.z));
            let g = (p.x / GRID, p.z / GRID);
            let inside = outline::inside(&self.rings, self.slabs(), g);
            if !inside {
                leading = false;
                continue;
            }
            if leading {
                continue;
            }
            if let Some((d, _, _, o)) = outline::nearest_edge(&self.rings, g) {
                if d > deep {
                    out.push((p, d * GRID, o));
                }
            }
        }
        out
    }

    /// [`rapid_entries`](Part::rapid_entries) for a rapid that may start inside material the
    /// model holds (a gap it does not know of: a groove cut wider than the model's tool, a hole
    /// drilled to a size not given): judged from where it leaves that material, so that only an
    /// entry from the air into material is a hit.
    pub fn rapid_enters(&self, from: Pos, to: Pos) -> Vec<Hit> {
        let mut hits = self.rapid_entries(from, to);
        if hits
            .first()
            .is_some_and(|h| h.at.distance(from) <= self.tolerance / 2.0)
        {
            hits.remove(0);
        }
        hits
    }

    /// The first point where the rapid from `from` to `to` enters material deeper than half the
    /// tolerance (a rapid that only touches a surface, or grazes it within the resolution, hits
    /// nothing), with the surface it crosses there.
    pub fn rapid_hits(&self, from: Pos, to: Pos) -> Option<Hit> {
        self.rapid_entries(from, to).into_iter().next()
    }

    /// Every point where the rapid from `from` to `to` enters material deeper than half the
    /// tolerance, in order along it, each with the surface it crosses there (one that starts in
    /// material has its first entry at its start).
    pub fn rapid_entries(&self, from: Pos, to: Pos) -> Vec<Hit> {
        let (a, b) = ((from.x / GRID, from.z / GRID), (to.x / GRID, to.z / GRID));
        let mut ts = vec![0.0, 1.0];
        for (p, q, _) in self.rings.iter().flat_map(Ring::edges) {
            if let Some(t) = crossing(a, b, outline::float(p), outline::float(q)) {
                ts.push(t);
            }
        }
        ts.sort_by(f64::total_cmp);
        ts.dedup();
        let deep = self.tolerance / 2.0 / GRID;
        let at = |t: f64| (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
        let mut hits = Vec::new();
        let mut was_inside = false;
        for w in ts.windows(2) {
            let (t0, t1) = (w[0], w[1]);
            let inside = (1..=DEPTH_SAMPLES).any(|i| {
                let p = at(t0 + (t1 - t0) * i as f64 / (DEPTH_SAMPLES + 1) as f64);
                outline::inside(&self.rings, self.slabs(), p)
                    && !outline::near_edge(&self.rings, p, deep)
            });
            if inside && !was_inside {
                let entry = at(t0);
                if let Some((_, p, q, origin)) = outline::nearest_edge(&self.rings, entry) {
                    hits.push(Hit {
                        stock_diameter: self.stock.diameter.known,
                        at: to_pos(entry),
                        origin,
                        surface: self.surface(p, q, entry),
                    });
                }
            }
            was_inside = inside;
        }
        hits
    }

    /// What kind of surface the edge `p` → `q` is, at the point `at` (grid steps).
    fn surface(&self, p: Point, q: Point, at: (f64, f64)) -> Surface {
        let (dx, dz) = (f64::from(q.x - p.x), f64::from(q.y - p.y));
        let len = dx.hypot(dz);
        let d = 2.0 * at.0 * GRID;
        if dx.abs() <= 1e-3 * len {
            // Material lies left of the edge: inward for an edge toward +Z.
            Surface::Diameter {
                diameter: 2.0 * f64::from(p.x + q.x) / 2.0 * GRID,
                bore: dz < 0.0,
            }
        } else if dz.abs() <= 1e-3 * len {
            Surface::Face {
                z: f64::from(p.y + q.y) / 2.0 * GRID,
            }
        } else {
            Surface::Slope { diameter: d }
        }
    }

    /// The material's radii at `z` (mm): the outermost, and the bore's when the material does not
    /// reach the axis; `None` where there is no material.
    pub fn radius_at(&self, z: f64) -> Option<Radii> {
        let xs = outline::crossings_at_z(&self.rings, z);
        let (first, last) = (*xs.first()?, *xs.last()?);
        Some(Radii {
            outer: last,
            bore: (first > self.tolerance / 2.0).then_some(first),
        })
    }

    /// The outermost surface at `z` (mm): its radius and where it came from; with `inner`, the
    /// innermost instead (a bore's wall, or the axis).
    pub fn surface_at(&self, z: f64, inner: bool) -> Option<(f64, Origin)> {
        let xs = outline::surfaces_at_z(&self.rings, z);
        if inner {
            xs.first().copied()
        } else {
            xs.last().copied()
        }
    }

    /// The first surface at `z` (mm) met going from radius `from` away from the axis (toward it
    /// with `inward`): the outside of the material `from` lies in (a thread's root lies in its
    /// blank), not of material beyond a gap.
    pub fn surface_beyond(&self, z: f64, from: f64, inward: bool) -> Option<(f64, Origin)> {
        outline::surface_beyond(&self.rings, self.slabs(), z, from, inward)
    }

    /// The greatest value of `f` on the outline between `z_lo` and `z_hi` (mm), for an `f`
    /// linear in x and z along each edge (given the edge's origin): it is reached at an end of an
    /// edge cut to the band, so only those are looked at. `None`: no material in the band.
    pub fn greatest_in_band(
        &self,
        z_lo: f64,
        z_hi: f64,
        f: impl Fn(Pos, Origin) -> f64,
    ) -> Option<f64> {
        let (lo, hi) = (z_lo / GRID, z_hi / GRID);
        let at = |a: (f64, f64), b: (f64, f64), y: f64| {
            let k = (y - a.1) / (b.1 - a.1);
            to_pos((a.0 + (b.0 - a.0) * k, y))
        };
        let mut best: Option<f64> = None;
        for ring in &self.rings {
            for (a, b, o) in ring.edges() {
                let (a, b) = (outline::float(a), outline::float(b));
                let (a, b) = if a.1 <= b.1 { (a, b) } else { (b, a) };
                if b.1 < lo || a.1 > hi {
                    continue;
                }
                let start = if a.1 < lo { at(a, b, lo) } else { to_pos(a) };
                let end = if b.1 > hi { at(a, b, hi) } else { to_pos(b) };
                let v = f(start, o).max(f(end, o));
                best = Some(best.map_or(v, |m| m.max(v)));
            }
        }
        best
    }

    /// The outline's edges by band, built when first asked for after a change.
    fn slabs(&self) -> Option<&outline::Slabs> {
        self.slabs
            .get_or_init(|| outline::Slabs::new(&self.rings))
            .as_ref()
    }

    /// Where the material begins on the face side (the largest Z of any material, mm).
    pub fn face_z(&self) -> Option<f64> {
        self.rings
            .iter()
            .flat_map(|r| &r.pts)
            .map(|p| f64::from(p.y) * GRID)
            .max_by(f64::total_cmp)
    }

    /// The face at radius `x` (mm): the largest Z of material there and where that surface came
    /// from.
    pub fn face_surface_at(&self, x: f64) -> Option<(f64, Origin)> {
        outline::surfaces_at_x(&self.rings, x).last().copied()
    }

    /// Where the material begins on the face side at radius `x` (mm).
    pub fn face_at(&self, x: f64) -> Option<f64> {
        outline::crossings_at_x(&self.rings, x).last().copied()
    }

    /// Whether the moves from `from` (a thread's passes) meet material more than `depth` (mm)
    /// beyond the programmed point, away from the axis (toward it in a bore): the first move that
    /// does, with where along Z it first meets it and the area it would take there. Each move
    /// cuts before the next is judged, on a copy: the part itself does not change.
    pub fn shoulder(
        &self,
        from: Pos,
        motions: &[Motion],
        tool: &Tool,
        depth: f64,
    ) -> Result<Option<Shoulder>> {
        self.shoulder_oriented(from, motions, tool, depth, None)
    }

    /// [`shoulder`](Part::shoulder) with the side stated (`Some(true)`: an internal thread's
    /// passes, whatever the model says about a bore it may not know).
    pub fn shoulder_oriented(
        &self,
        from: Pos,
        motions: &[Motion],
        tool: &Tool,
        depth: f64,
        side: Option<bool>,
    ) -> Result<Option<Shoulder>> {
        let mut part = self.clone();
        let mut at = from;
        for m in motions {
            let start = at;
            at = m.to;
            if m.kind == MotionKind::Rapid {
                continue;
            }
            let internal = side.unwrap_or_else(|| part.in_bore(start, m.to));
            let pieces = part.sweep(start, m, tool, internal)?;
            let chip = part.engine.chip(&part.rings, &pieces);
            let limit = if internal {
                start.x.min(m.to.x) - depth
            } else {
                start.x.max(m.to.x) + depth
            };
            // Beyond the limit (mm; positive away from the path).
            let beyond = |p: (f64, f64), by: f64| {
                let x = p.0 * GRID;
                if internal {
                    limit - by - x
                } else {
                    x - limit - by
                }
            };
            let (mut area, mut zs) = (0.0, Vec::new());
            for c in &chip {
                let pts: Vec<(f64, f64)> = c.iter().map(|&p| outline::float(p)).collect();
                area += signed_area(&clip_half(&pts, |p| beyond(p, 0.0))) * GRID * GRID;
                // Where it lies along Z, from what lies a tolerance beyond (the chip's edge along
                // the limit itself has no area).
                let clear = clip_half(&pts, |p| beyond(p, self.tolerance));
                zs.extend(clear);
            }
            if area.abs() > self.tolerance * self.tolerance && !zs.is_empty() {
                let toward_minus_z = m.to.z < start.z;
                let first = zs
                    .into_iter()
                    .reduce(|a, b| {
                        if (toward_minus_z && b.1 > a.1) || (!toward_minus_z && b.1 < a.1) {
                            b
                        } else {
                            a
                        }
                    })
                    .unwrap_or((start.x / GRID, start.z / GRID));
                // The surface the chip lies behind: the outline's edge nearest where it begins.
                let origin =
                    outline::nearest_edge(&part.rings, first).map_or(Origin::Unknown, |e| e.3);
                return Ok(Some(Shoulder {
                    z: first.1 * GRID,
                    area: area.abs(),
                    line: m.line,
                    pass: m.pass,
                    origin,
                }));
            }
            part.cut_oriented(start, m, tool, internal)?;
        }
        Ok(None)
    }
}

/// How a move cuts: `None` for a rapid, which cuts nothing.
fn cut_kind(motion: &Motion) -> Option<CutKind> {
    match motion.kind {
        MotionKind::Rapid => None,
        MotionKind::Feed => Some(CutKind::Feed),
        MotionKind::Thread { .. } => Some(CutKind::Thread),
        MotionKind::Arc { .. } => Some(CutKind::Arc),
    }
}

/// Marks as `cut`'s the stretches of the ring's edges the nose ran along: an edge that the body
/// only cleared, or the stock's own surface (a facing pass at the face), lying at the nose's radius
/// from a segment of the nose's centre path (`trace`, mm) over more than the tolerance. An edge
/// longer than that stretch is split at its ends, so that what lies beyond keeps its origin.
fn mark_trace(ring: &mut Ring, trace: &[Pos], nose: f64, tolerance: f64, cut: Cut) {
    let (r, tol) = (nose / GRID, tolerance / GRID);
    let n = ring.pts.len();
    let mut pts = Vec::with_capacity(n + 4);
    let mut origins = Vec::with_capacity(n + 4);
    for i in 0..n {
        let (p, q, o) = (ring.pts[i], ring.pts[(i + 1) % n], ring.origins[i]);
        let markable = match o {
            Origin::Cleared(_) => true,
            Origin::Stock { edge, .. } => edge != StockEdge::Axis,
            _ => false,
        };
        let stretch = if markable {
            trace
                .windows(2)
                .find_map(|w| along_trace(p, q, w[0], w[1], r, tol))
        } else {
            None
        };
        pts.push(p);
        origins.push(o);
        let Some((t0, t1)) = stretch else {
            continue;
        };
        let at = |t: f64| {
            let (fp, fq) = (outline::float(p), outline::float(q));
            Point::new(
                (fp.0 + t * (fq.0 - fp.0)).round() as i32,
                (fp.1 + t * (fq.1 - fp.1)).round() as i32,
            )
        };
        // p → a keeps its origin, a → b is the cut's, b → q keeps its origin.
        let len = (outline::float(q).0 - outline::float(p).0)
            .hypot(outline::float(q).1 - outline::float(p).1);
        if t0 * len > tol {
            pts.push(at(t0));
            origins.push(Origin::Cut(cut));
        } else {
            *origins.last_mut().expect("pushed above") = Origin::Cut(cut);
        }
        if (1.0 - t1) * len > tol {
            pts.push(at(t1));
            origins.push(o);
        }
    }
    ring.pts = pts;
    ring.origins = origins;
}

/// The stretch (parameters along `p` → `q`, grid steps) of the edge that lies at distance `r`
/// from the segment `a`–`b` (mm) within `tol` and overlaps it by more than `tol`.
fn along_trace(p: Point, q: Point, a: Pos, b: Pos, r: f64, tol: f64) -> Option<(f64, f64)> {
    let (a, b) = ((a.x / GRID, a.z / GRID), (b.x / GRID, b.z / GRID));
    let (dx, dz) = (b.0 - a.0, b.1 - a.1);
    let len = dx.hypot(dz);
    if len <= tol {
        return None;
    }
    let (fp, fq) = (outline::float(p), outline::float(q));
    let off = |v: (f64, f64)| ((v.0 - a.0) * dz - (v.1 - a.1) * dx).abs() / len;
    if (off(fp) - r).abs() > tol || (off(fq) - r).abs() > tol {
        return None;
    }
    // Positions along the segment's direction.
    let s = |v: (f64, f64)| ((v.0 - a.0) * dx + (v.1 - a.1) * dz) / len;
    let (sp, sq) = (s(fp), s(fq));
    if (sq - sp).abs() <= tol {
        return None;
    }
    let (lo, hi) = (sp.min(sq).max(0.0), sp.max(sq).min(len));
    if hi - lo <= tol {
        return None;
    }
    // Back to parameters along p → q.
    let t = |sv: f64| ((sv - sp) / (sq - sp)).clamp(0.0, 1.0);
    let (t0, t1) = (t(lo), t(hi));
    Some((t0.min(t1), t0.max(t1)))
}

/// The parameter along `a` → `b` where it meets the segment `p`–`q`, if it does.
fn crossing(a: (f64, f64), b: (f64, f64), p: (f64, f64), q: (f64, f64)) -> Option<f64> {
    let (rx, ry) = (b.0 - a.0, b.1 - a.1);
    let (sx, sy) = (q.0 - p.0, q.1 - p.1);
    let den = rx * sy - ry * sx;
    if den == 0.0 {
        return None;
    }
    let (wx, wy) = (p.0 - a.0, p.1 - a.1);
    let t = (wx * sy - wy * sx) / den;
    let u = (wx * ry - wy * rx) / den;
    ((0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)).then_some(t)
}

#[cfg(test)]
mod tests;
