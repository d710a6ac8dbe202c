//! A turning cycle's contour: the blocks N(ns)…N(nf) that give the finished shape of G70, G71,
//! G72 and G73 (G72–G75 in system C). The control does not run them where they stand: it reads
//! them for the cycle, and after the cycle goes on after the block N(nf). They are read here as
//! they come (in a streamed program they follow the cycle's block), kept as the program wrote them
//! (each axis absolute, incremental or unchanged), so that a later G70 with the same P and Q
//! rebuilds the shape from its own start point, and turned into a [`Contour`].
//!
//! Decisions (`docs/dialects/fanuc.md`, "Turning cycles"): the blocks between the cycle and
//! N(ns) are not run (the control searches for N(ns) and resumes after N(nf)); a contour of more
//! than [`MAX_CONTOUR_BLOCKS`] blocks is refused; at most [`MAX_CONTOURS`] contours are kept for a
//! later G70.

use std::collections::VecDeque;

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, MotionMode};
use crate::turning::{Contour, Segment, Shape};
use crate::units::{Pos, Tolerance};

/// The most blocks a contour (and the blocks before its N(ns)) may have.
pub const MAX_CONTOUR_BLOCKS: u32 = 10_000;

/// How far (in least input increments) an arc's end may lie from the circle its start and centre
/// give (I/K) before PS0020: the start, the end and I/K are each rounded to the increment, so a
/// correct arc written by a CAM system (or by `expand`) differs by up to about two. The control's
/// own limit is its parameter 3410, which a profile does not state.
pub const ARC_RADIUS_INCREMENTS: f64 = 2.0;

/// The most contours kept for a later G70 (the oldest is forgotten first).
pub const MAX_CONTOURS: usize = 32;

/// One axis of a contour block, as written.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Axis {
    Keep,
    /// Absolute, mm (X a radius).
    Abs(f64),
    /// Incremental, mm (X a radius).
    Inc(f64),
}

impl Axis {
    fn from(self, v: f64) -> f64 {
        match self {
            Axis::Keep => v,
            Axis::Abs(a) => a,
            Axis::Inc(d) => v + d,
        }
    }
}

/// How a block moves.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Line,
    /// An arc with its centre at (I, K) from its start (mm, I a radius).
    Centre {
        cw: bool,
        i: f64,
        k: f64,
    },
    /// An arc of radius R, the shorter of the two.
    Radius {
        cw: bool,
        r: f64,
    },
}

/// A block of a contour, as written.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Block {
    line: u32,
    span: Span,
    x: Axis,
    z: Axis,
    kind: Kind,
}

/// A contour's blocks, as written.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    pub ns: u32,
    pub nf: u32,
    /// The block N(ns) names both axes (Fanuc's type II for G71 and G72).
    pub first_both_axes: bool,
    /// The lines of the blocks N(ns) and N(nf).
    pub lines: (u32, u32),
    blocks: Vec<Block>,
}

impl Written {
    /// The contour from `start`. `tol` is the program's resolution for lengths: an arc whose end
    /// is farther than [`ARC_RADIUS_INCREMENTS`] increments from its circle (I/K), or farther from
    /// its start than 2R, is the control's alarm PS0020.
    pub fn contour(&self, start: Pos, tol: Tolerance, name: &str) -> Result<Contour> {
        let arc_tol = Tolerance::mm(tol.get() * ARC_RADIUS_INCREMENTS);
        let mut p = start;
        let mut segments = Vec::with_capacity(self.blocks.len());
        for b in &self.blocks {
            let to = Pos::new(b.x.from(p.x), b.z.from(p.z));
            let shape = match b.kind {
                Kind::Line => Shape::Line,
                Kind::Centre { cw, i, k } => {
                    let centre = Pos::new(p.x + i, p.z + k);
                    let (r0, r1) = (p.distance(centre), to.distance(centre));
                    if !arc_tol.eq(r0, r1) {
                        return Err(radius_alarm(
                            b.span,
                            name,
                            format!(
                                "the arc's end is {r1:.4} mm from its centre, its start {r0:.4} mm"
                            ),
                        ));
                    }
                    Shape::Arc {
                        centre,
                        clockwise: cw,
                    }
                }
                Kind::Radius { cw, r } => Shape::Arc {
                    centre: centre_of(p, to, r, cw, tol)
                        .map_err(|m| radius_alarm(b.span, name, m))?,
                    clockwise: cw,
                },
            };
            // A block that does not move adds nothing to the shape.
            if to != p || matches!(shape, Shape::Arc { .. }) {
                segments.push(Segment {
                    to,
                    shape,
                    line: b.line,
                });
            }
            p = to;
        }
        Ok(Contour { start, segments })
    }
}

fn radius_alarm(span: Span, name: &str, what: String) -> Diagnostic {
    Diagnostic::error(
        Code::Geometry,
        span,
        format!("alarm PS0020 (over tolerance of radius) in the contour of {name}: {what}"),
    )
}

/// The centre of the arc of radius `r` from `a` to `b` that turns less than half a circle,
/// clockwise (`cw`) with Z to the right and X up, as G2 turns, or counter-clockwise.
pub fn centre_of(
    a: Pos,
    b: Pos,
    r: f64,
    cw: bool,
    tol: Tolerance,
) -> std::result::Result<Pos, String> {
    let chord = a.distance(b);
    if tol.is_zero(chord) {
        return Err("an arc given by R must not end where it starts".into());
    }
    if r.is_nan() || r <= 0.0 {
        return Err(format!(
            "R{r} must be positive: an arc by R turns less than half a circle"
        ));
    }
    let half = chord / 2.0;
    if tol.gt(half, r) {
        return Err(format!(
            "R {r:.4} mm is shorter than half the distance between the arc's ends ({half:.4} mm)"
        ));
    }
    let h = (r * r - half * half).max(0.0).sqrt();
    let mid = Pos::new((a.x + b.x) / 2.0, (a.z + b.z) / 2.0);
    // The unit normal to the right of the chord, in (z, x) with z to the right: (dx, −dz).
    let (dz, dx) = ((b.z - a.z) / chord, (b.x - a.x) / chord);
    let (rz, rx) = (dx, -dz);
    let s = if cw { h } else { -h };
    Ok(Pos::new(mid.x + s * rx, mid.z + s * rz))
}

/// What the cycle reading a contour does with a block.
pub enum Step {
    /// The block is read (or skipped, before N(ns)): the control does not run it here.
    Read,
    /// The block N(nf): the contour is complete.
    Done(Written),
}

/// A contour being read from the blocks that follow its cycle.
pub struct Reading {
    pub ns: u32,
    pub nf: u32,
    /// The cycle's line and span (its errors are placed there).
    pub line: u32,
    pub span: Span,
    /// The G codes a contour block may have (×10): G0–G3 and codes that do not move.
    pub allowed: &'static [u16],
    /// The contour's own modal state: its blocks move the tool in it, not in the program's.
    modal: Modal,
    blocks: Vec<Block>,
    started: Option<(u32, bool)>,
    count: u32,
}

impl Reading {
    /// A contour N(ns)…N(nf) read from the blocks that follow, from the modal state `modal` at
    /// the cycle's start point.
    pub fn new(
        ns: u32,
        nf: u32,
        line: &Line,
        span: Span,
        modal: &Modal,
        allowed: &'static [u16],
    ) -> Reading {
        Reading {
            ns,
            nf,
            line: line.number,
            span,
            allowed,
            modal: modal.clone(),
            blocks: Vec::new(),
            started: None,
            count: 0,
        }
    }

    /// Whether the block N(ns) has come.
    pub fn started(&self) -> bool {
        self.started.is_some()
    }

    /// Reads one block. `name`: the cycle, for messages.
    pub fn block(&mut self, conv: &Conventions, line: &Line, name: &str) -> Result<Step> {
        self.count += 1;
        if self.count > MAX_CONTOUR_BLOCKS {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                self.span,
                format!(
                    "the contour N{}…N{} of {name} runs over more than {MAX_CONTOUR_BLOCKS} blocks",
                    self.ns, self.nf
                ),
            )
            .with_hint(format!(
                "is N{} missing, or is the contour longer than threadcut reads?",
                self.nf
            )));
        }
        let n = line.word(b'N').map(|w| w.value);
        if self.started.is_none() {
            if n != Some(f64::from(self.ns)) {
                // Before N(ns): the control's search passes over it, and it resumes after N(nf).
                return Ok(Step::Read);
            }
            self.started = Some((line.number, false));
        }
        let first = self.blocks.is_empty();
        let block = self.read_block(conv, line, name, first)?;
        if first {
            self.started = Some((line.number, block.x != Axis::Keep && block.z != Axis::Keep));
        }
        self.blocks.push(block);
        if n != Some(f64::from(self.nf)) {
            return Ok(Step::Read);
        }
        let (first_line, both) = self.started.unwrap_or((line.number, false));
        Ok(Step::Done(Written {
            ns: self.ns,
            nf: self.nf,
            first_both_axes: both,
            lines: (first_line, line.number),
            blocks: std::mem::take(&mut self.blocks),
        }))
    }

    fn read_block(
        &mut self,
        conv: &Conventions,
        line: &Line,
        name: &str,
        first: bool,
    ) -> Result<Block> {
        for w in line.words.iter().filter(|w| w.letter == b'G') {
            if !g_code(w.value).is_some_and(|c| self.allowed.contains(&c)) {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    w.span,
                    format!(
                        "alarm PS0066 (improper G-code in G70–G73): G{} in the contour N{}…N{} of {name}",
                        w.value, self.ns, self.nf
                    ),
                )
                .with_hint(format!("a contour's blocks move with G00–G03; cycles, thread moves and coordinate changes are not allowed in them (is the contour's last block, N{}, missing before this one?)", self.nf)));
            }
        }
        let m = &mut self.modal;
        m.apply(conv, line)?;
        let kind = match m.motion {
            MotionMode::Rapid | MotionMode::Feed => Kind::Line,
            MotionMode::ArcCw | MotionMode::ArcCcw => {
                let cw = m.motion == MotionMode::ArcCw;
                match (line.word(b'I'), line.word(b'K'), line.word(b'R')) {
                    (_, _, Some(r)) => Kind::Radius { cw, r: m.length_mm(r) },
                    (None, None, None) => {
                        return Err(Diagnostic::error(
                            Code::MissingWord,
                            line.span(),
                            format!("an arc in the contour of {name} needs its centre (I, K) or its radius R"),
                        ))
                    }
                    (i, k, None) => Kind::Centre {
                        cw,
                        i: i.map_or(0.0, |w| m.length_mm(w)),
                        k: k.map_or(0.0, |w| m.length_mm(w)),
                    },
                }
            }
            _ => {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    line.span(),
                    format!("alarm PS0066 (improper G-code in G70–G73): the contour of {name} moves with G00–G03 only"),
                ))
            }
        };
        if first && !matches!(m.motion, MotionMode::Rapid | MotionMode::Feed) {
            return Err(Diagnostic::error(
                Code::Unsupported,
                line.span(),
                format!("alarm PS0065 (illegal command in G71–G73): the contour's first block N{} of {name} must move with G00 or G01", self.ns),
            ));
        }
        let (mut x, mut z) = (Axis::Keep, Axis::Keep);
        for w in line.words {
            let (axis, inc) = match w.letter {
                b'X' => (&mut x, !m.absolute),
                b'U' if conv.uw_incremental => (&mut x, true),
                b'Z' => (&mut z, !m.absolute),
                b'W' if conv.uw_incremental => (&mut z, true),
                _ => continue,
            };
            let v = if matches!(w.letter, b'X' | b'U') {
                m.x_to_mm(m.value(w))
            } else {
                m.length_mm(w)
            };
            *axis = if inc { Axis::Inc(v) } else { Axis::Abs(v) };
        }
        Ok(Block {
            line: line.number,
            span: line.span(),
            x,
            z,
            kind,
        })
    }
}

/// The contours read so far, for a later G70 (or a second roughing of the same contour).
#[derive(Default)]
pub struct Kept {
    contours: VecDeque<Written>,
}

impl Kept {
    pub fn get(&self, ns: u32, nf: u32) -> Option<&Written> {
        self.contours.iter().find(|c| c.ns == ns && c.nf == nf)
    }

    pub fn keep(&mut self, w: Written) {
        self.contours.retain(|c| (c.ns, c.nf) != (w.ns, w.nf));
        if self.contours.len() == MAX_CONTOURS {
            self.contours.pop_front();
        }
        self.contours.push_back(w);
    }
}

/// The values a first block (G71/G72 `U(Δd) R(e)`, G73 `U(Δi) W(Δk) R(d)`, G74/G75 `R(e)`)
/// rewrites, as the control's parameters 5132/5133, 5135–5137 and 5139 are; `None` until a block
/// sets them (a profile does not state them).
#[derive(Clone, Copy, Debug, Default)]
pub struct FirstBlocks {
    /// Δd, e of G71/G72 (mm).
    pub depth: Option<f64>,
    pub retract: Option<f64>,
    /// Δi, Δk (mm, Δi a radius) and d of G73.
    pub relief_x: Option<f64>,
    pub relief_z: Option<f64>,
    pub passes: Option<u32>,
    /// e of G74/G75 (mm).
    pub peck_retract: Option<f64>,
}

/// A box cycle's modal state: what a following block of axis words repeats.
#[derive(Clone, Copy, Debug)]
pub struct BoxModal {
    pub code: u16,
    pub end: Pos,
    pub taper: f64,
}

/// The turning cycles' state in the family's reader.
#[derive(Default)]
pub struct TurningState {
    pub first: FirstBlocks,
    pub box_modal: Option<BoxModal>,
    /// The contour being read, and the cycle waiting for it.
    pub reading: Option<Box<(Reading, Pending)>>,
    pub kept: Kept,
}

/// A cycle waiting for its contour: everything but the contour.
#[derive(Clone, Debug)]
pub struct Pending {
    pub code: u16,
    pub job: crate::turning::TurningJob,
}
