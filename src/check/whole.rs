//! The whole program's part (issue 23; docs/simulation.md, "The part as the program makes it"):
//! every feed and arc move and every move of a turning cycle cuts it ([`crate::part`]), every
//! thread leaves its teeth in it, and every rapid move of the program — plain blocks and turning
//! cycles alike — is judged against it.
//!
//! * **The stock** is what the options give (`--stock-diameter`, `--stock-start`,
//!   `--stock-length`, `--stock-bore`). Where the diameter is not given, the bar is held as
//!   material of a size not known: cuts have something to remove, and nothing is claimed about
//!   it. With the diameter given and no face, the face is assumed at Z0.
//! * **A cut surface is a fact**: material lies behind every surface the program cut. A rapid
//!   that crosses one into the material behind it is an error; one into stock that was only given
//!   is an error, only assumed a warning, not known nothing.
//! * **A thread's teeth are a fact**: the region between a thread's crest and its root, and as
//!   deep again behind the root, along the blank, is material once the thread is cut. Thread
//!   passes cut nothing from the model (their teeth stay); a rapid into that region is an error.
//! * **Which side a tool works on**, for moves the program writes itself: a turning cycle's
//!   contour says it; a chain of feed moves is in a bore when, after its last move along Z, the
//!   tool leaves toward the axis (the retract of a boring pass), outside when it leaves away from
//!   it; otherwise the model says (material that does not reach the axis around the move). A move
//!   along X alone is a grooving or parting tool's (its body reaches away from the surface only),
//!   a move along the axis a drill's. The tool's nose is `--nose-radius` when given, else a point
//!   one resolution step wide.
//! * **Rapids from inside material** (a place the model does not know was opened: a groove cut
//!   by a tool wider than the model's, a hole drilled to a size not given) are judged from where
//!   they leave it: the model claims nothing about its own gaps.
//!
//! Threads written as moves are the thread reader's ([`crate::threads`]) until it hands them
//! over; while it reads one, a rapid into the stock is judged by the thread's blank
//! ([`super::cut`]), not twice here.

use crate::diag::{Code, Diagnostic, Span};
use crate::gcode::{MotionMode, PlainMove};
use crate::part::{Body, CutKind, Dim, Known, Origin, Part, Stock, StockEdge, Tool};
use crate::thread::Side;
use crate::threads::Thread;
use crate::toolpath::{Motion, MotionKind};
use crate::turning::TurningJob;
use crate::units::{Pos, Units};

use super::blank::{self, Blank};
use super::length;

/// The bar's diameter (mm) when it is not given: larger than any lathe's swing.
const UNKNOWN_DIAMETER: f64 = 2000.0;
/// The bar's length (mm) toward the chuck when it is not given.
const UNKNOWN_LENGTH: f64 = 5000.0;
/// A chain of feed moves longer than this is cut before it ends (memory stays bounded).
const CHAIN_MAX: usize = 256;
/// The threads' teeth kept for the rapids after them (the latest; a long program's early threads
/// are far behind).
const ZONES_MAX: usize = 256;
/// Points along a thread at which its blank's surface is looked up.
const SAMPLES: usize = 16;
/// Even samples along a thread's run where a shoulder is looked for (besides the outline's
/// corners in it).
const SHOULDER_SAMPLES: usize = 64;
/// Rapids kept for judging while a thread written as moves is read.
const PENDING_MAX: usize = 4096;
/// Rapids into material kept for drawing ([`View`]).
pub const VIEW_HITS_MAX: usize = 1000;

/// The stock as the options give it (program units; diameters as diameters).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StockWords {
    pub diameter: Option<f64>,
    pub face: Option<f64>,
    pub length: Option<f64>,
    pub bore: Option<f64>,
}

/// A rapid move that runs into material, for drawing (mm, X a radius).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct RapidHit {
    pub line: u32,
    pub from: Pos,
    pub to: Pos,
    /// Where it enters the material.
    pub at: Pos,
    /// An error (a fact), else a warning (an assumption).
    pub error: bool,
}

/// The region a thread's teeth occupy (mm, X a radius): a quadrilateral from the blank's surface
/// to as deep behind the root as the thread is deep, between the blank's face and the thread's
/// end.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Teeth {
    pub line: u32,
    pub side: Side,
    /// The crest and the root, each from the face to the end.
    pub crest: (Pos, Pos),
    pub root: (Pos, Pos),
    /// The face and the end along Z.
    pub z: (f64, f64),
    #[serde(skip)]
    corners: [Pos; 4],
}

impl Teeth {
    /// Everything but the line is the same.
    fn same_place(&self, o: &Teeth) -> bool {
        self.corners == o.corners
            && self.crest == o.crest
            && self.root == o.root
            && self.z == o.z
            && self.side == o.side
    }
}

/// The part as the program made it, for `plot` and the page: its outline, the threads' teeth and
/// the rapids that run into material.
#[derive(Clone, Debug, Default)]
pub struct View {
    pub stock: Option<Stock>,
    /// The outline's rings (mm), each vertex with the origin of the edge leaving it.
    pub outline: Vec<Vec<(Pos, Origin)>>,
    pub teeth: Vec<Teeth>,
    pub hits: Vec<RapidHit>,
}

/// The surface a thread's blank was measured on.
#[derive(Clone, Copy, Debug)]
pub(super) struct Measured {
    /// Its diameter (program units).
    pub diameter: f64,
    /// The line that cut it, when the program did.
    pub line: Option<u32>,
    /// Whether the part reaches beyond the thread's root somewhere along it (material, known or
    /// not, that its deepest pass cuts).
    pub reaches: bool,
}

/// Where the program's units and resolution stand for a move.
#[derive(Clone, Copy, Debug)]
pub(super) struct At {
    pub units: Units,
    pub diameter_x: bool,
    /// One increment of the program's resolution (mm).
    pub tolerance: f64,
}

/// The part the program makes, and what was found against it.
pub(super) struct Whole {
    stock: StockWords,
    /// The nose radius (program units), when given.
    nose: Option<f64>,
    part: Option<Part>,
    failed: bool,
    chain: Vec<(Pos, Motion)>,
    chain_at: Option<At>,
    teeth: std::collections::VecDeque<Teeth>,
    /// For each of `teeth`, whether a newer one is the same ([`Teeth::same_place`]).
    shadowed: std::collections::VecDeque<bool>,
    hits: Vec<RapidHit>,
    /// Rapids made while the thread reader reads a thread written as moves: judged once it hands
    /// the thread over (its teeth are then in the part), at most [`PENDING_MAX`].
    pending: std::collections::VecDeque<(Pos, Pos, Span, At)>,
    /// What rapids and threads ran into.
    pub found: Vec<Diagnostic>,
    /// Where the program first cut (a feed move or a turning cycle), for the note on the stock.
    first_cut: Option<Span>,
    /// A rapid was judged after the first cut (the note on the stock concerns it).
    judged_after_cut: bool,
    /// Where the last rapid found running into material ended: the move from there is the
    /// tool getting out of it, not another fault.
    crashed_at: Option<Pos>,
}

impl Whole {
    pub fn new(stock: StockWords, nose: Option<f64>) -> Whole {
        Whole {
            stock,
            nose,
            part: None,
            failed: false,
            chain: Vec::new(),
            chain_at: None,
            teeth: std::collections::VecDeque::new(),
            shadowed: std::collections::VecDeque::new(),
            hits: Vec::new(),
            pending: std::collections::VecDeque::new(),
            found: Vec::new(),
            first_cut: None,
            judged_after_cut: false,
            crashed_at: None,
        }
    }

    /// The stock as the part holds it (mm), in the program's `units`.
    fn stock_of(&self, units: Units) -> Stock {
        let w = self.stock;
        let mm = |v: Option<f64>| v.map(|v| units.to_mm(v));
        match mm(w.diameter) {
            Some(d) => Stock {
                diameter: Dim::given(d),
                face: Dim::given_or(mm(w.face), 0.0),
                length: mm(w.length).map_or(Dim::unknown(UNKNOWN_LENGTH), Dim::given),
                bore: mm(w.bore).map_or(Dim::unknown(0.0), Dim::given),
            },
            None => Stock {
                diameter: Dim::unknown(UNKNOWN_DIAMETER),
                face: Dim::unknown(mm(w.face).unwrap_or(0.0)),
                length: mm(w.length).map_or(Dim::unknown(UNKNOWN_LENGTH), Dim::given),
                bore: mm(w.bore).map_or(Dim::unknown(0.0), Dim::given),
            },
        }
    }

    /// The part, made from the stock at the first move (in the program's units then).
    fn part(&mut self, at: At) -> Option<&mut Part> {
        if self.part.is_none() && !self.failed {
            match Part::new(&self.stock_of(at.units), at.tolerance) {
                Ok(p) => self.part = Some(p),
                Err(_) => self.failed = true,
            }
        }
        self.part.as_mut()
    }

    /// The tool for a move: the nose given, else a point — but a grooving, parting or drilling
    /// tool, whose body is no wider than its nose, at least one resolution step wide: the slot
    /// it cuts is where it went, and the rapid out of it runs in that slot, not in material.
    fn tool(&self, at: At, body: Body) -> Tool {
        let nose = self.nose.map_or(0.0, |r| at.units.to_mm(r));
        Tool {
            nose_radius: match body {
                Body::Turning => nose,
                Body::Radial | Body::Axial => nose.max(at.tolerance),
            },
            body,
        }
    }

    /// A plain block's move. Feeds and arcs join the chain being cut; a rapid ends it and is
    /// judged (`reading_thread`: the thread reader holds a thread the rapid may belong to).
    pub fn plain(&mut self, mv: &PlainMove, span: Span, at: At, reading_thread: bool) {
        let Some(from) = mv.from.known() else {
            self.flush(None);
            return;
        };
        let line = span.line;
        let kind = match (mv.mode, mv.centre) {
            (MotionMode::Feed, _) | (MotionMode::ArcCw | MotionMode::ArcCcw, None) => {
                MotionKind::Feed
            }
            (MotionMode::ArcCw, Some(centre)) => MotionKind::Arc {
                centre,
                clockwise: true,
            },
            (MotionMode::ArcCcw, Some(centre)) => MotionKind::Arc {
                centre,
                clockwise: false,
            },
            (MotionMode::Rapid, _) => {
                self.flush(Some(mv.to.x - from.x));
                if reading_thread {
                    if self.pending.len() >= PENDING_MAX {
                        if let Some((a, b, s, w)) = self.pending.pop_front() {
                            self.rapid(a, b, s, w, true);
                        }
                    }
                    self.pending.push_back((from, mv.to, span, at));
                } else {
                    self.settle();
                    self.rapid(from, mv.to, span, at, false);
                }
                return;
            }
            _ => {
                self.flush(None);
                return;
            }
        };
        if self.chain.len() >= CHAIN_MAX {
            self.flush(None);
        }
        self.first_cut.get_or_insert(span);
        self.chain_at = Some(at);
        self.chain.push((
            from,
            Motion {
                kind,
                to: mv.to,
                pass: 0,
                line,
            },
        ));
    }

    /// Cuts the chain of feed moves, on the side its moves say (`leaving`: the X the next rapid
    /// moves by).
    pub fn flush(&mut self, leaving: Option<f64>) {
        let Some(at) = self.chain_at else {
            return;
        };
        let chain = std::mem::take(&mut self.chain);
        let tol = at.tolerance;
        // After the chain's last move along Z, the first move in X says where the tool leaves.
        let last_along_z = chain
            .iter()
            .rposition(|(from, m)| (m.to.z - from.z).abs() > tol);
        let internal = last_along_z.and_then(|i| {
            chain[i + 1..]
                .iter()
                .map(|(from, m)| m.to.x - from.x)
                .chain(leaving)
                .find(|dx| dx.abs() > tol)
                .map(|dx| dx < 0.0)
        });
        for (from, m) in &chain {
            let (dx, dz) = (m.to.x - from.x, m.to.z - from.z);
            let body = if from.x.abs() <= tol && m.to.x.abs() <= tol {
                Body::Axial
            } else if dz.abs() <= tol && dx.abs() > tol && !matches!(m.kind, MotionKind::Arc { .. })
            {
                Body::Radial
            } else {
                Body::Turning
            };
            let tool = self.tool(at, body);
            if let Some(part) = self.part(at) {
                // A move the part refuses (beyond what it holds) leaves it as it was.
                let inside = internal.unwrap_or_else(|| part.in_bore(*from, m.to));
                let _ = if body == Body::Turning {
                    part.cut_oriented(*from, m, &tool, inside)
                } else {
                    part.clear_oriented(*from, m, &tool, inside)
                };
            }
        }
    }

    /// A turning cycle: its feed and arc moves cut the part on the cycle's side, its rapids are
    /// judged.
    pub fn turning(&mut self, job: &TurningJob, span: Span, at: At) {
        self.flush(None);
        self.first_cut.get_or_insert(span);
        let Ok(path) = crate::turning::toolpath(job) else {
            return;
        };
        let body = match job.cycle {
            crate::turning::Cycle::Peck(p) if p.along == crate::turning::Along::Z => Body::Axial,
            crate::turning::Cycle::Peck(_) => Body::Radial,
            _ => Body::Turning,
        };
        let tool = self.tool(at, body);
        let side = job.internal();
        for (from, m) in path.segments() {
            match m.kind {
                MotionKind::Rapid => self.rapid(from, m.to, span, at, false),
                _ => {
                    if let Some(part) = self.part(at) {
                        let inside = side.unwrap_or_else(|| part.in_bore(from, m.to));
                        let _ = if body == Body::Turning {
                            part.cut_oriented(from, m, &tool, inside)
                        } else {
                            part.clear_oriented(from, m, &tool, inside)
                        };
                    }
                }
            }
        }
    }

    /// Judges a rapid move against the threads' teeth and the part.
    fn rapid(&mut self, from: Pos, to: Pos, span: Span, at: At, reading_thread: bool) {
        self.judged_after_cut |= self.first_cut.is_some();
        if self.crashed_at.take() == Some(from) {
            return;
        }
        let units = at.units;
        let show_x = |x: f64| length(units, if at.diameter_x { 2.0 * x } else { x });
        let target = || format!("X{} Z{}", show_x(to.x), length(units, to.z));
        if let Some((t, p)) = self.teeth_hit(from, to, at.tolerance) {
            let root = if t.side == Side::Internal {
                t.root.0.x.max(t.root.1.x)
            } else {
                t.root.0.x.min(t.root.1.x)
            };
            let message = format!(
                "a rapid move to {} runs through the thread cut at line {} (its teeth and root Ø{}, Z{} to Z{}), at X{} Z{}",
                target(),
                t.line,
                length(units, 2.0 * root),
                length(units, t.z.0),
                length(units, t.z.1),
                show_x(p.x),
                length(units, p.z),
            );
            self.report(span, message, true, (from, to, p));
            return;
        }
        let Some(part) = self.part(at) else {
            return;
        };
        // The entries it makes, judged: the first into a surface the program cut, else the
        // first into stock given, else assumed; stock not known says nothing.
        let judged = |h: &crate::part::Hit| match h.origin {
            Origin::Cut(c) if c.kind == CutKind::Thread => None,
            Origin::Cut(_) => Some(2),
            Origin::Stock {
                edge: StockEdge::Axis,
                ..
            } => None,
            Origin::Stock { .. } | Origin::Cleared(_) if !reading_thread => match h.stock_only() {
                Some(Known::Given) => Some(1),
                Some(Known::Assumed) => Some(0),
                _ => None,
            },
            _ => None,
        };
        let entries = part.rapid_enters(from, to);
        let Some((rank, hit)) = entries
            .iter()
            .filter_map(|h| judged(h).map(|r| (r, *h)))
            .fold(
                None,
                |best: Option<(u8, crate::part::Hit)>, (r, h)| match best {
                    Some((b, _)) if b >= r => best,
                    _ => Some((r, h)),
                },
            )
        else {
            self.inside_cut(from, to, span, at);
            return;
        };
        let error = rank > 0;
        let assumed = match hit.origin {
            Origin::Stock {
                edge: StockEdge::Face,
                known: Known::Assumed,
            } => ", with the part's face at Z0 assumed (--stock-start gives it)",
            _ => "",
        };
        let message = format!(
            "a rapid move to {} runs into {}{assumed}",
            target(),
            hit.describe(units)
        );
        self.report(span, message, error, (from, to, hit.at));
    }

    /// A rapid that came in through a surface nothing is known of (the bar's, not given) but
    /// then runs in material whose nearest surface the program cut: material lies behind a cut
    /// surface, so that is a fact too.
    fn inside_cut(&mut self, from: Pos, to: Pos, span: Span, at: At) {
        let Some(part) = self.part.as_ref() else {
            return;
        };
        let found = part
            .rapid_inside(from, to)
            .into_iter()
            .find(|(_, _, o)| matches!(o, Origin::Cut(c) if c.kind != CutKind::Thread));
        let Some((p, depth, Origin::Cut(c))) = found else {
            return;
        };
        let units = at.units;
        let show_x = |x: f64| length(units, if at.diameter_x { 2.0 * x } else { x });
        let message = format!(
            "a rapid move to X{} Z{} runs inside the part: at X{} Z{} it is {} behind the surface cut at line {}",
            show_x(to.x),
            length(units, to.z),
            show_x(p.x),
            length(units, p.z),
            length(units, depth),
            c.line
        );
        self.report(span, message, true, (from, to, p));
    }

    /// Judges the rapids made while a thread was read. Those may be the thread's own (its
    /// approach, retracts and returns), which its blank judges: here they answer only for the
    /// surfaces the program cut and the teeth of threads.
    pub fn settle(&mut self) {
        for (from, to, span, at) in std::mem::take(&mut self.pending) {
            self.rapid(from, to, span, at, true);
        }
    }

    /// A rapid into material: its finding, and the rapid (from, to, where it enters) kept for
    /// drawing.
    fn report(
        &mut self,
        span: Span,
        message: String,
        error: bool,
        (from, to, at): (Pos, Pos, Pos),
    ) {
        self.crashed_at = Some(to);
        let hint = "a rapid cuts nothing: move clear of the part along the surface the tool came in on before crossing it";
        self.found.push(if error {
            Diagnostic::error(Code::Collision, span, message).with_hint(hint)
        } else {
            Diagnostic::warning(Code::CollisionAssumed, span, message).with_hint(hint)
        });
        if self.hits.len() < VIEW_HITS_MAX {
            self.hits.push(RapidHit {
                line: span.line,
                from,
                to,
                at,
                error,
            });
        }
    }

    /// The thread's teeth the rapid from `from` to `to` runs into deeper than half the
    /// tolerance, and where.
    fn teeth_hit(&self, from: Pos, to: Pos, tolerance: f64) -> Option<(&Teeth, Pos)> {
        let (lo, hi) = (
            Pos::new(from.x.min(to.x), from.z.min(to.z)),
            Pos::new(from.x.max(to.x), from.z.max(to.z)),
        );
        let newest = self.teeth.iter().zip(&self.shadowed).rev();
        newest.filter(|(_, &s)| !s).find_map(|(t, _)| {
            // Clear of the teeth's box, clear of the teeth (most rapids are).
            let c = &t.corners;
            if c.iter().all(|p| p.x < lo.x)
                || c.iter().all(|p| p.x > hi.x)
                || c.iter().all(|p| p.z < lo.z)
                || c.iter().all(|p| p.z > hi.z)
            {
                return None;
            }
            let (t0, t1) = clip_convex(c, from, to)?;
            // A rapid from inside the teeth (after one that ran into them) is not judged again.
            if t0 <= 0.0 {
                return None;
            }
            let len = from.distance(to) * (t1 - t0);
            (len > tolerance / 2.0).then(|| {
                let p = Pos::new(from.x + t0 * (to.x - from.x), from.z + t0 * (to.z - from.z));
                (t, p)
            })
        })
    }

    /// The blank's surface along `t`, as the program cut it: the outermost material along the
    /// thread's crest line (the innermost for an internal thread) where the program cut it there
    /// (`None`: the stock's surface stands, or nothing was cut there).
    pub fn measured(&mut self, t: &Thread) -> Option<Measured> {
        self.flush(None);
        let part = self.part.as_ref()?;
        let g = &t.job.geometry;
        let inner = g.side == Side::Internal;
        // The surface where the thread runs: the middle of what lies along it (a chamfer at its
        // start, a relief groove or a shoulder at its end are not its crest).
        let mut reaches = false;
        let mut found: Vec<(f64, Origin)> = (0..=SAMPLES)
            .filter_map(|i| {
                let k = i as f64 / SAMPLES as f64;
                let z = g.crest_start.z + (g.crest_end.z - g.crest_start.z) * k;
                let crest = g.crest_start.x + (g.crest_end.x - g.crest_start.x) * k;
                let root = crest - g.side.outward().x * g.depth;
                // The surface first met going out from the root; where the part lies wholly
                // below the root (the thread cuts air there), the surface below it.
                let beyond = part.surface_beyond(z, root, inner);
                reaches |= beyond.is_some();
                beyond.or_else(|| part.surface_beyond(z, root, !inner).filter(|s| s.0 > 0.0))
            })
            .collect();
        if found.is_empty() {
            return None;
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (r, origin) = found[found.len() / 2];
        let Origin::Cut(c) = origin else {
            return None;
        };
        if c.kind == CutKind::Thread || (inner && r <= part.tolerance()) {
            return None;
        }
        let units = t.job.units;
        // At the program's resolution (the outline's vertices lie on a finer grid).
        let step = part.tolerance();
        let d = (2.0 * r / step).round() * step;
        Some(Measured {
            diameter: units.from_mm(d),
            line: Some(c.line),
            reaches,
        })
    }

    /// The part's face where the thread enters it, when the program cut that face (a facing
    /// move): the largest Z of material at the radii from the thread's root halfway to the axis
    /// (below a chamfer at its start), its Z (program units) and the line that cut it. For a
    /// thread that runs from the face toward −Z.
    pub fn measured_face(&mut self, t: &Thread) -> Option<(f64, u32)> {
        self.flush(None);
        let part = self.part.as_ref()?;
        let g = &t.job.geometry;
        if g.crest_end.z >= g.crest_start.z || g.side != Side::External {
            return None;
        }
        let root = g.crest_start.x - g.depth;
        let (z, origin) = [1.0, 0.9, 0.75, 0.5]
            .iter()
            .filter_map(|k| part.face_surface_at(root * k))
            .max_by(|a, b| a.0.total_cmp(&b.0))?;
        let Origin::Cut(c) = origin else {
            return None;
        };
        if c.kind == CutKind::Thread || z > g.crest_start.z || z < g.crest_end.z {
            return None;
        }
        let step = part.tolerance();
        Some((t.job.units.from_mm((z / step).round() * step), c.line))
    }

    /// The thread's teeth, from its blank, for the rapids after it; and the material its passes
    /// run into beyond their depth (a shoulder or face the program left).
    pub fn thread(&mut self, t: &Thread, blank: &Blank, tolerance: f64) {
        let at = At {
            units: t.job.units,
            diameter_x: t.diameter_x,
            tolerance,
        };
        self.part(at);
        self.shoulder(t, blank, tolerance);
        if blank.face == blank::Known::Unknown || t.passes.is_empty() {
            return;
        }
        let out = blank.side.outward().x;
        let depth = t.passes.iter().map(|p| p.depth).fold(0.0, f64::max);
        if depth <= 0.0 {
            return;
        }
        // The thread ends where its synchronised moves end farthest from the face.
        let mut at = t.path.start;
        let mut far = blank.z_end;
        for m in &t.path.motions {
            if matches!(m.kind, MotionKind::Thread { .. }) {
                for z in [at.z, m.to.z] {
                    if (blank.z_face - z) * blank.backward > (blank.z_face - far) * blank.backward {
                        far = z;
                    }
                }
            }
            at = m.to;
        }
        let blank = Blank {
            x_end: blank.x_face
                + (blank.x_end - blank.x_face) * (far - blank.z_face)
                    / (blank.z_end - blank.z_face).abs().max(1e-12)
                    * (blank.z_end - blank.z_face).signum(),
            z_end: far,
            ..*blank
        };
        let blank = &blank;
        // One resolution step inside the blank all round: a move along its face, its end or its
        // surface (a thread's own retract) runs beside the teeth, not into them.
        let inward = blank.backward * tolerance;
        let (z_face, z_end) = (blank.z_face - inward, blank.z_end + inward);
        if (z_face - z_end) * blank.backward <= 0.0 {
            return;
        }
        let crest = (
            Pos::new(blank.x_face - out * tolerance, z_face),
            Pos::new(blank.x_end - out * tolerance, z_end),
        );
        let g = &t.job.geometry;
        let crest_x = |z: f64| {
            let dz = g.crest_end.z - g.crest_start.z;
            if dz.abs() < 1e-12 {
                g.crest_start.x
            } else {
                g.crest_start.x + (g.crest_end.x - g.crest_start.x) * (z - g.crest_start.z) / dz
            }
        };
        let root = (
            Pos::new(crest_x(z_face) - out * depth, z_face),
            Pos::new(crest_x(z_end) - out * depth, z_end),
        );
        let behind = |p: Pos| Pos::new((p.x - out * depth).max(0.0), p.z);
        let teeth = Teeth {
            line: t.job.line,
            side: blank.side,
            crest,
            root,
            z: (blank.z_face, blank.z_end),
            corners: [crest.0, crest.1, behind(root.1), behind(root.0)],
        };
        if blank.side == Side::Internal {
            self.open_bore(blank, tolerance);
        }
        if self.teeth.len() >= ZONES_MAX {
            self.teeth.pop_front();
            self.shadowed.pop_front();
        }
        // The same teeth again (a program that cuts one thread many times): a rapid finds the
        // newest first, so the older need no look. At most one not yet shadowed is the same.
        let same = self
            .teeth
            .iter()
            .zip(&self.shadowed)
            .rposition(|(old, &shadowed)| !shadowed && old.same_place(&teeth));
        if let Some(i) = same {
            self.shadowed[i] = true;
        }
        self.teeth.push_back(teeth);
        self.shadowed.push_back(false);
    }

    /// An internal thread's bore is a fact, whatever the model knew of the hole (a drill's
    /// diameter is not in the program): the part is opened to the blank's surface along it.
    fn open_bore(&mut self, blank: &Blank, tolerance: f64) {
        let Some(part) = self.part.as_mut() else {
            return;
        };
        let from = Pos::new(blank.x_face, blank.z_face + blank.backward * tolerance);
        // Cut as the thread's: its surfaces are the teeth's business, not a turned surface.
        let m = Motion {
            kind: MotionKind::Thread {
                lead: 0.0,
                dlead: 0.0,
                phase_deg: 0.0,
            },
            to: Pos::new(blank.x_end, blank.z_end),
            pass: 0,
            line: 0,
        };
        let _ = part.cut_oriented(from, &m, &Tool::point(Body::Radial), true);
    }

    /// Material standing beyond the blank's surface where the thread's passes run: a shoulder or
    /// a face the program left, which the passes would meet deeper than their depth. The first
    /// such place from the thread's start, with the chip it would take there.
    fn shoulder(&mut self, t: &Thread, blank: &Blank, tolerance: f64) {
        let Some(part) = self.part.as_ref() else {
            return;
        };
        let inner = blank.side == Side::Internal;
        let out = blank.side.outward().x;
        let (Some(last), Some(run)) = (t.passes.last(), Run::of(t)) else {
            return;
        };
        let surface = |z: f64| blank_surface(blank, z);
        let root = last.start.x;
        let (z_lo, z_hi, toward_minus) = (run.z_lo, run.z_hi, run.toward_minus);
        // No material whose surface is known (the only kind reported) stands a tolerance beyond
        // the blank along the run: no shoulder. The difference is linear along each edge, so its
        // greatest is at an edge's end; half the tolerance, so that rounding in the crossings
        // below cannot make one appear.
        let stock_given = part.stock().diameter.known == Known::Given;
        if part
            .greatest_in_band(z_lo, z_hi, |p, o| {
                if surface_known(o, stock_given) {
                    (p.x - surface(p.z)) * out
                } else {
                    f64::NEG_INFINITY
                }
            })
            .is_none_or(|h| h <= tolerance / 2.0)
        {
            return;
        }
        let z_at = |k: f64| run.z_at(k);
        let k_of = |z: f64| {
            let len = (z_hi - z_lo).max(f64::MIN_POSITIVE);
            if toward_minus {
                (z_hi - z) / len
            } else {
                (z - z_lo) / len
            }
        };
        // Where to look along the run (shares 0..1 from the thread's start): evenly, and at the
        // outline's corners in it, on both sides — a shoulder is a corner of the outline, so
        // however narrow it is found, and the samples stay few whatever the thread's length.
        let mut ks: Vec<f64> = (0..=SHOULDER_SAMPLES)
            .map(|i| i as f64 / SHOULDER_SAMPLES as f64)
            .chain(
                part.outline()
                    .iter()
                    .flatten()
                    .map(|(p, _)| p.z)
                    .filter(|&z| z >= z_lo && z <= z_hi)
                    .flat_map(|z| [k_of(z - tolerance / 4.0), k_of(z + tolerance / 4.0)]),
            )
            .filter(|k| (0.0..=1.0).contains(k))
            .collect();
        ks.sort_by(f64::total_cmp);
        // Material beyond the blank's surface at z, and its surface.
        let beyond = |z: f64| {
            part.surface_beyond(z, root, inner)
                .filter(|(r, _)| (r - surface(z)) * out > tolerance)
        };
        let Some(first) = ks.iter().position(|&k| beyond(z_at(k)).is_some()) else {
            return;
        };
        // The shoulder's face: between the last place clear of it and the first on it.
        let (mut lo, mut hi) = (ks[first.saturating_sub(1)], ks[first]);
        for _ in 0..40 {
            let mid = (lo + hi) / 2.0;
            if beyond(z_at(mid)).is_some() {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let z_face = z_at(hi);
        // What the passes meet beyond it: the highest material up to the thread's end whose
        // surface is known (the program cut it, or the stock was given).
        let Some((r, what)) = ks[first..]
            .iter()
            .map(|&k| z_at(k))
            .chain(std::iter::once(z_face))
            .filter_map(beyond)
            .filter(|&(_, o)| surface_known(o, stock_given))
            .fold(None, |m: Option<(f64, Origin)>, (r, o)| match m {
                Some((b, _)) if (b - r) * out >= 0.0 => m,
                _ => Some((r, o)),
            })
        else {
            return;
        };
        let what = known_surface(what, stock_given).unwrap_or_default();
        let units = t.job.units;
        // At the program's resolution (the outline lies on a finer grid).
        let round = |mm: f64| (mm / tolerance).round() * tolerance;
        let d = |x: f64| length(units, round(2.0 * x));
        let (pass, span) = (t.passes[0].n, t.pass_span(t.passes[0].n));
        self.found.push(
            Diagnostic::error(
                Code::Shoulder,
                span,
                format!(
                    "the thread runs into a shoulder at Z{}: the part stands up to Ø{} beyond it ({what}), above the thread's blank Ø{}; pass {pass} would meet it, and the last pass take a chip {} deep (Ø{} down to the root Ø{})",
                    length(units, round(z_face)),
                    d(r),
                    d(surface(z_face)),
                    length(units, round((r - root) * out)),
                    d(r),
                    d(root),
                ),
            )
            .with_hint("end the thread before the shoulder (its pull-out included) or turn a relief groove for it to run into"),
        );
    }

    /// Another setup begins (another work coordinate system): the part so far is in coordinates
    /// the program no longer uses, so a new part starts from the stock, and the threads' teeth
    /// are left with the old one. What was found stays.
    pub fn new_setup(&mut self) {
        self.flush(None);
        self.settle();
        self.part = None;
        self.failed = false;
        self.teeth.clear();
        self.shadowed.clear();
    }

    /// What was assumed about the stock, where the program cuts: without its diameter the bar
    /// is not known, and only what the program cut is judged.
    pub fn stock_note(&self) -> Option<(Span, String)> {
        if self.stock.diameter.is_some() || !self.judged_after_cut {
            return None;
        }
        self.first_cut.map(|span| {
            (
                span,
                "part: the bar's size is not given (--stock-diameter): rapids are judged against the surfaces the program cut and the threads it cut, not against the bar".to_string(),
            )
        })
    }

    /// What the part looks like now, for drawing.
    pub fn view(&mut self) -> View {
        self.flush(None);
        self.settle();
        View {
            stock: self.part.as_ref().map(|p| *p.stock()),
            outline: self.part.as_ref().map(Part::outline).unwrap_or_default(),
            teeth: self.teeth.iter().cloned().collect(),
            hits: self.hits.clone(),
        }
    }
}

/// Where a thread's passes run along Z (their synchronised moves), and which way from its start.
struct Run {
    z_lo: f64,
    z_hi: f64,
    toward_minus: bool,
}

impl Run {
    fn of(t: &Thread) -> Option<Run> {
        let mut at = t.path.start;
        let mut spans: Vec<(f64, f64)> = Vec::new();
        for m in &t.path.motions {
            if matches!(m.kind, MotionKind::Thread { .. }) {
                spans.push((at.z, m.to.z));
            }
            at = m.to;
        }
        let &(z0, _) = spans.first()?;
        let z_lo = spans
            .iter()
            .map(|s| s.0.min(s.1))
            .fold(f64::INFINITY, f64::min);
        let z_hi = spans
            .iter()
            .map(|s| s.0.max(s.1))
            .fold(f64::NEG_INFINITY, f64::max);
        Some(Run {
            z_lo,
            z_hi,
            toward_minus: (z0 - z_hi).abs() < (z0 - z_lo).abs(),
        })
    }

    /// The Z a share `k` (0..1) of the way along the run from the thread's start.
    fn z_at(&self, k: f64) -> f64 {
        if self.toward_minus {
            self.z_hi - (self.z_hi - self.z_lo) * k
        } else {
            self.z_lo + (self.z_hi - self.z_lo) * k
        }
    }
}

/// The blank's surface (radius, mm) at `z`: the line from its face to its end.
fn blank_surface(blank: &Blank, z: f64) -> f64 {
    let dz = blank.z_end - blank.z_face;
    if dz.abs() < 1e-12 {
        blank.x_face
    } else {
        blank.x_face + (blank.x_end - blank.x_face) * (z - blank.z_face) / dz
    }
}

/// A surface whose material is known, in words: one the program cut, or the stock's as given
/// (`stock_given`: a cleared surface's material is the stock's).
fn known_surface(o: Origin, stock_given: bool) -> Option<String> {
    surface_known(o, stock_given).then(|| match o {
        Origin::Cut(c) => format!("as the program cut it at line {}", c.line),
        _ => "the stock as given".to_string(),
    })
}

/// Whether [`known_surface`] says something of `o`.
fn surface_known(o: Origin, stock_given: bool) -> bool {
    match o {
        Origin::Cut(c) => c.kind != CutKind::Thread,
        Origin::Cleared(_) => stock_given,
        Origin::Stock {
            known: Known::Given,
            edge,
        } => edge != StockEdge::Axis,
        _ => false,
    }
}

/// The parameters (0..1) of the part of the segment `a` → `b` inside the convex polygon `poly`
/// (Cyrus–Beck), if any.
fn clip_convex(poly: &[Pos; 4], a: Pos, b: Pos) -> Option<(f64, f64)> {
    let area: f64 = (0..4)
        .map(|i| {
            let (p, q) = (poly[i], poly[(i + 1) % 4]);
            p.x * q.z - q.x * p.z
        })
        .sum();
    if area.abs() < 1e-12 {
        return None;
    }
    let sign = area.signum();
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let d = (b.x - a.x, b.z - a.z);
    for i in 0..4 {
        let (p, q) = (poly[i], poly[(i + 1) % 4]);
        // Inward normal of the edge p → q.
        let n = (-(q.z - p.z) * sign, (q.x - p.x) * sign);
        let num = n.0 * (a.x - p.x) + n.1 * (a.z - p.z);
        let den = n.0 * d.0 + n.1 * d.1;
        if den.abs() < 1e-15 {
            if num < 0.0 {
                return None;
            }
            continue;
        }
        let t = -num / den;
        if den > 0.0 {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
        if t0 > t1 {
            return None;
        }
    }
    Some((t0, t1))
}
