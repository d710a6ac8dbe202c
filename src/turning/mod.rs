//! Turning cycles, machine-neutral: the cycles that turn a part to a contour — stock removal along
//! Z or X (Fanuc's G71/G72, type I and II), pattern repeating (G73), finishing (G70) — the single
//! box cycles (G90 along Z, G94 along X) and the peck cycles (G74 along Z, G75 along X), as every
//! controller that has them states them (Fanuc systems A/B/C, GSK 980TDi, Haas, LinuxCNC 2.9,
//! Sinumerik CYCLE95). A dialect reads its words into a [`TurningJob`]; the motion is made here
//! and nowhere else, as `toolpath` makes a thread's.
//!
//! Coordinates are absolute millimetres, X a radius, as everywhere in the model. A contour is the
//! finished shape as the program's blocks give it (Fanuc's blocks `ns`…`nf`, LinuxCNC's o-word
//! profile), starting at the cycle's start point's first move.

pub mod simple;

use serde::Serialize;

mod contour;
pub mod finish;
pub mod pattern;
pub mod profile_rough;
pub mod removal;
pub mod rough;

use crate::diag::{Result, Span};
use crate::toolpath::{Motion, Toolpath};
use crate::units::{Pos, Units};

/// One piece of a contour: a line or a circular arc to `to`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Segment {
    pub to: Pos,
    pub shape: Shape,
    /// The program line of the block that gave it.
    pub line: u32,
}

/// The shape of a contour segment.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Shape {
    Line,
    /// A circular arc about `centre` (X radius, Z), clockwise as the program's G2 (`clockwise`) or
    /// counter-clockwise as its G3: the direction as written, whatever side of the axis the tool
    /// post is on.
    Arc {
        centre: Pos,
        clockwise: bool,
    },
}

/// The finished shape a cycle turns to: from `start` through each segment in order.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Contour {
    pub start: Pos,
    pub segments: Vec<Segment>,
}

/// The axis the cutting passes of a stock-removal or peck cycle run along.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Along {
    /// Longitudinal passes (G71, G74): the depth of cut is taken in X.
    Z,
    /// Facing passes (G72, G75): the depth of cut is taken in Z.
    X,
}

/// Stock removal to a contour (Fanuc G71/G72, Haas's one-block G71/G72, GSK's, LinuxCNC's
/// G71/G72): passes along one axis, each `depth` deeper, down to the contour plus the finishing
/// allowance, each followed by a retract of `retract`; the last roughing pass may follow the
/// contour's outline.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rough {
    pub along: Along,
    /// The cycle's start point (where the tool is when the cycle begins).
    pub start: Pos,
    /// Δd: the depth of each cut (mm; X radius for G71, Z for G72).
    pub depth: f64,
    /// e: the retract after each cut (mm, away from the part, along the depth's axis).
    pub retract: f64,
    /// The finishing allowance left on the contour: X (radius, signed as programmed: Fanuc's U/2)
    /// and Z (W).
    pub allowance_x: f64,
    pub allowance_z: f64,
    /// Type II: the passes follow pockets (a contour that is not monotonic along the depth axis).
    pub pockets: bool,
    pub contour: Contour,
    // issue 23: how the passes are laid out (added for LinuxCNC's G71/G72).
    pub strategy: Strategy,
    /// A further pass along the contour shifted by this finishing allowance alone (X radius,
    /// Z), after the pass along the outline at `allowance_x`/`allowance_z`: Haas's G71/G72 with
    /// a rough pass allowance I, K (the layers and the first outline stop at the finishing plus
    /// the rough allowance). `None`: no such pass (Fanuc's, GSK's, LinuxCNC's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub then_outline: Option<(f64, f64)>,
}

/// How a stock removal's passes are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Strategy {
    /// Layers along the cutting axis down to the contour shifted by the allowance, then a pass
    /// along the outline (Fanuc's G71/G72 and the family's).
    Layers,
    /// Along an offset profile ([`profile_rough`]): the contour offset normal to itself by
    /// `distance` and shifted by the allowance (in the working frame: passes along Z toward −Z,
    /// the depth decreasing), cut in layers from the start point's side, each ended by a 45°
    /// retract of `retract` in both axes and a rapid back; the tool then follows the offset
    /// contour. `pockets`: which pockets are cut.
    Offset { distance: f64, pockets: Pockets },
}

/// Which pockets an offset-profile roughing cuts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Pockets {
    /// Every pocket, each when the walk along the contour reaches it.
    All,
    /// None: the layers, then the climbing parts of the contour only.
    None,
    /// Only after the first pocket: the first layers are skipped (a cycle with `None` cut
    /// them), from where the contour first climbs.
    AfterFirst,
}

/// Finishing passes at decreasing offsets from the contour: pass k of `passes` (counted down)
/// at (k−1)·(first−last)/passes + last.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FinishOffsets {
    pub first: f64,
    pub last: f64,
    pub passes: f64,
}

/// Pattern repeating (G73): the contour shifted outward by the relief and brought in, in `passes`
/// equal steps, to the contour plus the finishing allowance.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Pattern {
    pub start: Pos,
    /// Δi, Δk: the total relief in X (radius) and Z (mm).
    pub relief_x: f64,
    pub relief_z: f64,
    /// d: the number of passes.
    pub passes: u32,
    pub allowance_x: f64,
    pub allowance_z: f64,
    pub contour: Contour,
}

/// Finishing (G70): the contour once, from the cycle's start point, back to it at the end.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finish {
    pub start: Pos,
    pub contour: Contour,
    // issue 23: LinuxCNC's G70 D E P (None: one pass on the contour).
    pub offsets: Option<FinishOffsets>,
}

/// A single box cycle: G90 (along Z: in X, along Z to `end.z`, out in X, back in Z) or G94 (along
/// X: in Z, along X to `end.x`, out in Z, back in X), with a taper (`taper`: Fanuc's R, X at the
/// start minus X at the end for G90, Z for G94; 0: none).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BoxCycle {
    pub along: Along,
    pub start: Pos,
    pub end: Pos,
    pub taper: f64,
}

/// A peck cycle (G74 along Z, G75 along X): pecks of `peck` with a retract of `retract` after
/// each, to `end`, then shifts of `shift` across (X for G74, Z for G75) to the other end of the
/// groove or hole pattern; `relief` at the bottom of each peck run. `peck`, `shift` and `retract`
/// are lengths (mm, ≥ 0; a `peck` or `shift` of 0: one feed, one column); `relief` is a signed
/// displacement across (mm, + toward +X for G74, +Z for G75): the dialect gives it its direction
/// ([`simple`] has the moves).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Peck {
    pub along: Along,
    pub start: Pos,
    pub end: Pos,
    pub peck: f64,
    pub shift: f64,
    pub retract: f64,
    pub relief: f64,
}

/// Stock removal in even layers with each layer's corner cleaned along the contour, and/or
/// finishing along the contour, from a start point the cycle works out itself (Sinumerik's
/// CYCLE95 without relief cuts): [`removal`] has the moves, docs/dialects/sinumerik.md
/// ("CYCLE95") the sentences and decisions.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Removal {
    pub along: Along,
    /// Machining in a bore (the part's material beyond the contour, away from the axis): the
    /// infeed of a longitudinal removal increases X, a facing one cuts away from the axis.
    pub internal: bool,
    /// Where the tool is when the cycle is called (the cycle moves from it to its own start).
    pub from: Pos,
    /// The largest depth of cut (mm; X radius along Z, Z along X): the depth is divided into
    /// equal layers no deeper than it.
    pub depth: f64,
    /// The lift-off from the contour after each layer, in both axes (mm).
    pub lift: f64,
    /// The finishing allowances left by the roughing: X (radius) and Z, and one on both axes
    /// (all ≥ 0, away from the part).
    pub allowance_x: f64,
    pub allowance_z: f64,
    pub allowance: f64,
    /// Which passes the cycle makes: roughing, finishing, or both (roughing first).
    pub rough: bool,
    pub finish: bool,
    /// The finished contour as programmed (its start is its first point).
    pub contour: Contour,
}

/// A turning cycle of one of the kinds above.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum Cycle {
    Rough(Rough),
    Removal(Removal),
    Pattern(Pattern),
    Finish(Finish),
    Box(BoxCycle),
    Peck(Peck),
}

/// A turning cycle as a dialect read it: the cycle, and where it was written.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TurningJob {
    pub cycle: Cycle,
    /// The program line of the cycle's (last) block, and its span.
    pub line: u32,
    #[serde(skip)]
    pub span: Span,
    pub units: Units,
    pub controller: &'static str,
}

/// The moves of a turning cycle, from its start (absolute mm, X radius): each kind by the module
/// that makes it.
pub fn toolpath(job: &TurningJob) -> Result<Toolpath> {
    let motions = match &job.cycle {
        Cycle::Rough(r) => match r.strategy {
            Strategy::Offset { .. } => return profile_rough::rough(r, job.units, job.span),
            Strategy::Layers => rough::moves(r, job.line)?,
        },
        Cycle::Finish(f) if f.offsets.is_some() => {
            return profile_rough::finish(f, job.units, job.span)
        }
        Cycle::Finish(f) => finish::moves(f, job.line)?,
        Cycle::Removal(r) => removal::moves(r, job.line)?,
        Cycle::Pattern(p) => pattern::moves(p, job.line)?,
        Cycle::Box(b) => simple::box_moves(b, job.line),
        Cycle::Peck(p) => simple::peck_moves(p, job.line, job.span)?,
    };
    Ok(Toolpath {
        start: job.start(),
        motions,
    })
}

impl TurningJob {
    /// The cycle's moves, from its start point (where the tool is when it begins): [`toolpath`].
    pub fn moves(&self) -> Result<Vec<Motion>> {
        toolpath(self).map(|p| p.motions)
    }

    /// Where the tool is when the cycle is done: its start point (every cycle of the model
    /// returns to it), or the start point a stock removal works out ([`removal::start_point`]).
    pub fn end_point(&self) -> Pos {
        match &self.cycle {
            Cycle::Removal(r) => removal::start_point(r).unwrap_or(r.from),
            _ => self.start(),
        }
    }

    /// Whether the cycle works in a bore: its contour (or its end) lies on the axis's side of its
    /// start point, as an internal cycle's does (Fanuc: "U … negative for internal machining";
    /// the sign of U may be 0, the contour's side never is). `None` for a peck along Z (a drill
    /// or a face groove: no side).
    pub fn internal(&self) -> Option<bool> {
        let below = |start: Pos, c: &Contour| {
            let top = c.segments.iter().map(|s| s.to.x).fold(c.start.x, f64::max);
            top > start.x
        };
        match &self.cycle {
            Cycle::Rough(r) => Some(below(r.start, &r.contour)),
            Cycle::Removal(r) => Some(r.internal),
            Cycle::Pattern(p) => Some(below(p.start, &p.contour)),
            Cycle::Finish(f) => Some(below(f.start, &f.contour)),
            Cycle::Box(b) => Some(b.end.x > b.start.x),
            Cycle::Peck(p) => (p.along == Along::X).then_some(p.end.x > p.start.x),
        }
    }

    /// The cycle's start point.
    pub fn start(&self) -> Pos {
        match &self.cycle {
            Cycle::Rough(r) => r.start,
            Cycle::Removal(r) => r.from,
            Cycle::Pattern(p) => p.start,
            Cycle::Finish(f) => f.start,
            Cycle::Box(b) => b.start,
            Cycle::Peck(p) => p.start,
        }
    }
}
