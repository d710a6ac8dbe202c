//! Thread milling by helical interpolation (seed 004, Centroid TB029 "Thread Milling").
//!
//! The seed's technique, step by step, for an internal thread (a bore at the minor diameter) and
//! an external one (a cylinder at the major diameter):
//!
//! 1. rapid to the thread centre (internal) or to a point outside the cylinder at least half a tool
//!    diameter clear of it (external);
//! 2. feed to the starting height (the bottom when milling bottom-up, the top when top-down);
//! 3. cutter compensation on, on the side TB029 gives ([`directions`]);
//! 4. a straight move (never an arc: compensation starts on a line) to the start point on the major
//!    (internal) or minor (external) diameter;
//! 5. 360° helical moves, each rising or falling one pitch, G2 top-down and G3 bottom-up for a
//!    right-hand thread; left-hand threads reverse both the compensation and the arc direction;
//! 6. as many turns as the length × threads per inch asks.
//!
//! TB029's tips are rules here: every turn's absolute Z is computed from the exact pitch and rounded
//! once when written, never accumulated from a rounded increment; full circles are written as centre
//! (I/J) and end point, never end point and radius.
//!
//! Beyond the seed (docs/milling.md gives the reasons):
//! * a tangential arc lead-in and lead-out (the default) instead of the radial move of step 4; the
//!   lead arcs climb or fall with the helix so the tool meets the thread in phase;
//! * several constant-area radial passes, `R_k = R_crest ± h·√(k/N)`;
//! * the tool-centre path when compensation is off (`--comp none`);
//! * arc-feed compensation: the requested feed is the feed at the cutting edge, the programmed F on
//!   an arc is `F·(D − d)/D` (internal) or `F·(D + d)/D` (external) with D the diameter the edge cuts
//!   and d the tool diameter, when F drives the tool centre;
//! * multi-tooth tools: N teeth one pitch apart cut N pitches per turn, so the helix needs
//!   `⌈(L − (N − 1)·P) / P⌉` turns.
//!
//! Everything is millimetres inside; [`post`] writes program units.

pub mod motion;
pub mod post;
pub mod profile;
pub mod readback;
pub mod recognise;
pub mod request;

pub use request::{Milling, Request, Warning};

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::thread::standard::StandardThread;
use profile::FeedReference;

/// Hand of the thread.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Hand {
    Right,
    Left,
}

impl Hand {
    /// `right-hand`, `left-hand`.
    pub fn name(self) -> &'static str {
        match self {
            Hand::Right => "right-hand",
            Hand::Left => "left-hand",
        }
    }
}

/// Which way the helix runs along Z.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Direction {
    TopDown,
    BottomUp,
}

/// Cutter compensation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Comp {
    /// The program describes the thread contour; the control offsets the tool (G41/G42, the side
    /// from [`directions`]).
    Controller,
    /// The program is the tool-centre path.
    Off,
}

pub use crate::thread::standard::Surface as Side;

/// G41 (tool left of the path) or G42 (right).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum CompSide {
    Left,
    Right,
}

impl CompSide {
    pub fn code(self) -> &'static str {
        match self {
            CompSide::Left => "G41",
            CompSide::Right => "G42",
        }
    }
}

/// How the tool reaches the start of the helix.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum LeadIn {
    /// A quarter-circle tangent to the helix, climbing with it (the default).
    Arc,
    /// TB029 step 4: a straight radial move to the start point.
    Radial,
}

/// TB029's direction table: (arc clockwise?, compensation side) for a thread side, hand and
/// direction.
///
/// * Internal, right hand: bottom-up G41 + G3; top-down G42 + G2 (TB029 internal steps 3 and 5).
/// * External, right hand: bottom-up G42 + G3; top-down G41 + G2 (TB029 external steps 3 and 5).
/// * Left hand: "reverse all the cutter compensation and arc directions" (TB029 tip 4).
pub fn directions(side: Side, hand: Hand, direction: Direction) -> (bool, CompSide) {
    let up = direction == Direction::BottomUp;
    let (mut cw, mut left) = match side {
        Side::Internal => (!up, up),
        Side::External => (!up, !up),
    };
    if hand == Hand::Left {
        cw = !cw;
        left = !left;
    }
    (
        cw,
        if left {
            CompSide::Left
        } else {
            CompSide::Right
        },
    )
}

/// The direction that mills climb (G41 with a clockwise spindle): right-hand internal threads
/// bottom-up, right-hand external threads top-down, and the reverse for left-hand threads.
pub fn climb(side: Side, hand: Hand) -> Direction {
    [Direction::BottomUp, Direction::TopDown]
        .into_iter()
        .find(|&d| directions(side, hand, d).1 == CompSide::Left)
        .expect("one direction of the two is G41")
}

/// What to mill.
#[derive(Clone, Debug)]
pub struct MillSpec {
    pub thread: StandardThread,
    pub side: Side,
    pub hand: Hand,
    /// Thread length along Z, from `start_z` down (mm).
    pub length: f64,
    /// Cutting diameter of the tool (mm).
    pub tool_diameter: f64,
    /// Thread-form teeth on the tool, one pitch apart.
    pub teeth: u32,
    /// `None`: climb milling ([`climb`]).
    pub direction: Option<Direction>,
    /// Radial passes.
    pub passes: u32,
    /// Thread starts (1: single-start); each turn advances starts × pitch.
    pub starts: u32,
    pub comp: Comp,
    /// Thread axis (mm).
    pub center: (f64, f64),
    /// Top of the thread (mm): the part surface for an internal thread.
    pub start_z: f64,
    /// Height above `start_z` for rapid moves (mm).
    pub clearance: f64,
    /// Feed at the cutting edge (mm/min).
    pub feed: f64,
    pub lead_in: LeadIn,
    /// What F drives under compensation (from the controller profile).
    pub comp_feed: FeedReference,
}

/// A point (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct P3 {
    pub x: f64,
    pub y: f64,
    pub z: f64,
}

impl P3 {
    pub const fn new(x: f64, y: f64, z: f64) -> P3 {
        P3 { x, y, z }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum MoveKind {
    Rapid,
    Feed,
    /// A circular or helical arc in XY about `center`; a full circle when it ends where it starts.
    Arc {
        center: (f64, f64),
        cw: bool,
    },
}

/// One move (mm). `comp` is the compensation in force during the move: the first move with it on
/// is the start-up move (G41/G42), the first move with it off again the cancel move (G40).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Move {
    pub kind: MoveKind,
    pub to: P3,
    /// Programmed feed (mm/min); 0 for rapids.
    pub feed: f64,
    pub comp: Option<CompSide>,
    /// Radial pass (1-based).
    pub pass: u32,
}

/// A complete milling plan: the moves and what they were computed from.
#[derive(Clone, Debug, Serialize)]
pub struct Plan {
    pub thread: String,
    pub class: String,
    pub side: Side,
    pub hand: Hand,
    pub direction: Direction,
    /// Helix arcs clockwise (G2)?
    pub cw: bool,
    pub comp: Comp,
    pub comp_side: CompSide,
    pub pitch: f64,
    pub lead: f64,
    pub starts: u32,
    pub tpi: Option<f64>,
    /// Radius of the crest the cut starts from: the bore (internal) or the cylinder (external).
    pub crest_radius: f64,
    /// Radius of the finished thread root: the major (internal) or minor (external) diameter / 2.
    pub final_radius: f64,
    /// Contour radius of each pass.
    pub pass_radii: Vec<f64>,
    pub tool_radius: f64,
    pub teeth: u32,
    /// Full helical turns per pass.
    pub turns: u32,
    /// TB029 step 6: length × threads per inch (length / pitch), before rounding up.
    pub seed_count: f64,
    pub top_z: f64,
    pub bottom_z: f64,
    pub lowest_z: f64,
    pub clearance_z: f64,
    /// Requested feed at the cutting edge and the F programmed on the last pass's helix.
    pub edge_feed: f64,
    pub helix_feed: f64,
    pub center: (f64, f64),
    /// How far the tool's top tooth rises above `top_z` at the top of the helix (mm), from the
    /// extra fraction of a turn and the teeth above the bottom one.
    pub flute_overhang: f64,
    /// A taper thread: the change of the contour radius per mm going down (+1/32 external,
    /// −1/32 internal on a 1:16 taper); `crest_radius`, `final_radius` and `pass_radii` are then
    /// at `top_z`. 0 for a parallel thread.
    pub taper: f64,
    /// The lead-in asked for was an arc but the thread is tapered: it is entered radially.
    pub radial_for_taper: bool,
    pub moves: Vec<Move>,
}

impl Plan {
    /// Checks worth a warning, in `units`: lead arcs below the thread bottom, teeth of a
    /// multi-tooth tool above the thread top.
    pub fn warnings(&self, units: crate::units::Units) -> Vec<String> {
        let u = |mm: f64| units.from_mm(mm);
        let un = units.name();
        let mut w = Vec::new();
        if self.lowest_z < self.bottom_z - 1e-9 {
            w.push(format!(
                "the tool goes down to Z {:.4}, {:.4} {un} below the thread bottom Z {:.4} ({}): leave that much room under the thread",
                u(self.lowest_z),
                u(self.bottom_z - self.lowest_z),
                u(self.bottom_z),
                if self.direction == Direction::BottomUp { "the lead-in climbs in from below" } else { "the lead-out continues down" }
            ));
        }
        if self.radial_for_taper {
            w.push(
                "a taper thread is entered and left radially (TB029 step 4): an arc lead-in cannot follow the cone".to_string(),
            );
        }
        if self.teeth > 1 && self.flute_overhang > self.pitch + 1e-9 {
            w.push(format!(
                "--teeth: the {} teeth span {:.4} {un}; the top tooth cuts {:.4} {un} above the thread top: keep that height clear",
                self.teeth,
                u(f64::from(self.teeth - 1) * self.pitch),
                u(self.flute_overhang)
            ));
        }
        w
    }
}

/// External lead arcs are split into this many arcs, each ending in phase with the helix: the
/// largest axial error between the joints, inside the stock, falls from about 1.5 % of the pitch
/// for one arc to about 0.1 % for four (docs/milling.md).
pub const EXTERNAL_LEAD_PIECES: u32 = 4;

/// A lead-in/lead-out pair of arcs about one centre (tool-centre radius `a`).
#[derive(Clone, Copy, Debug)]
struct LeadArcs {
    a: f64,
    m: (f64, f64),
    cw: bool,
    pieces: u32,
    theta_in: f64,
    theta_s: f64,
    theta_out: f64,
    feed: f64,
}

/// More radial passes than this is a typing error, not a plan.
pub const MAX_PASSES: u32 = 1000;
/// More helical moves in one program than this is a typing error, not a plan.
pub const MAX_HELIX_ARCS: u64 = 1_000_000;
/// More turns per pass than this is a typing error (a 10 m thread of 0.25 mm pitch).
pub const MAX_TURNS: u32 = 40_000;

fn flag_error(flag: &str, message: String) -> Diagnostic {
    Diagnostic::error(
        Code::OutOfRange,
        Span::default(),
        format!("{flag}: {message}"),
    )
}

/// Builds the moves for `spec`. `comp_entry_longer_than_radius` is the LinuxCNC rule, checked.
pub fn plan(spec: &MillSpec) -> Result<Plan> {
    check_flags(spec)?;
    let t = &spec.thread;
    let limits = t.limits(spec.side);
    let r_t = spec.tool_diameter / 2.0;
    let contour = contour(spec, &limits)?;
    check_tool_fits(spec, r_t, &contour)?;
    let direction = spec
        .direction
        .unwrap_or_else(|| climb(spec.side, spec.hand));
    let count = helix_count(spec)?;
    let h = Helix::new(spec, &contour, &count, direction);
    let pass_radii = pass_radii(spec, &contour, h.inward);

    let mut moves = Vec::new();
    let mut helix_feed = h.edge_feed;
    for (k, &r) in pass_radii.iter().enumerate() {
        let one = PassPath::new(&h, k as u32 + 1, r);
        helix_feed = one.f_helix;
        h.every_start(&one.lay_out(), &mut moves);
    }

    let lowest_z = moves.iter().map(|m| m.to.z).fold(f64::INFINITY, f64::min);
    check_finite(&moves)?;
    Ok(Plan {
        thread: t.name.clone(),
        class: limits.class.to_string(),
        side: spec.side,
        hand: spec.hand,
        direction,
        cw: h.cw,
        comp: spec.comp,
        comp_side: h.comp_side,
        pitch: t.pitch,
        lead: count.lead,
        starts: spec.starts,
        tpi: t.tpi,
        crest_radius: contour.crest,
        final_radius: contour.root,
        pass_radii,
        tool_radius: r_t,
        teeth: spec.teeth,
        turns: count.turns,
        seed_count: spec.length / t.pitch,
        top_z: h.top,
        bottom_z: h.bottom,
        lowest_z,
        clearance_z: h.clearance_z,
        edge_feed: h.edge_feed,
        helix_feed,
        center: spec.center,
        flute_overhang: count.flute_overhang,
        taper: contour.slope,
        radial_for_taper: contour.slope != 0.0 && spec.lead_in == LeadIn::Arc,
        moves,
    })
}

/// Decides whether the numbers given on the command line can make a plan at all: a positive
/// length, tool diameter and feed, at least one tooth, 1 to [`MAX_PASSES`] passes, a clearance
/// of zero or more, and a finite centre and start Z; the first flag that fails is the error.
fn check_flags(spec: &MillSpec) -> Result<()> {
    let finite = |v: f64| v.is_finite();
    if !(finite(spec.length) && spec.length > 0.0) {
        return Err(flag_error(
            "--length",
            format!("the thread length must be positive, not {}", spec.length),
        ));
    }
    if !(finite(spec.tool_diameter) && spec.tool_diameter > 0.0) {
        return Err(flag_error(
            "--tool-diameter",
            format!(
                "the tool diameter must be positive, not {}",
                spec.tool_diameter
            ),
        ));
    }
    if spec.teeth == 0 {
        return Err(flag_error(
            "--teeth",
            "a tool has at least one tooth".into(),
        ));
    }
    if spec.passes == 0 || spec.passes > MAX_PASSES {
        return Err(flag_error(
            "--passes",
            format!("between 1 and {MAX_PASSES} passes, not {}", spec.passes),
        ));
    }
    if !(finite(spec.feed) && spec.feed > 0.0) {
        return Err(flag_error(
            "--feed",
            format!("the feed must be positive, not {}", spec.feed),
        ));
    }
    if !(finite(spec.clearance) && spec.clearance >= 0.0) {
        return Err(flag_error(
            "--clearance",
            format!("the clearance must be zero or more, not {}", spec.clearance),
        ));
    }
    for (flag, v) in [
        ("--center", spec.center.0),
        ("--center", spec.center.1),
        ("--start-z", spec.start_z),
    ] {
        if !finite(v) {
            return Err(flag_error(flag, format!("{v} is not a number")));
        }
    }
    Ok(())
}

/// The radii the cut runs between, at the top of the thread, and how they change going down.
struct Contour {
    /// The crest the cut starts from: the bore (internal) or the cylinder (external).
    crest: f64,
    /// The finished thread root.
    root: f64,
    /// Change of the contour radius per mm going down; 0 for a parallel thread.
    slope: f64,
}

/// Decides the crest and root radii from the thread's limits of size, and for a taper thread
/// from its gauge dimensions at the top of the thread; an error when a limit is missing.
fn contour(spec: &MillSpec, limits: &crate::thread::standard::Limits) -> Result<Contour> {
    let t = &spec.thread;
    let missing = |what: &str| {
        Diagnostic::error(
            Code::Geometry,
            Span::default(),
            format!("{} has no {what} limit to mill to", t.name),
        )
    };
    // Internal: from the bore (the minor diameter, at its smallest) out to the major diameter at
    // its smallest, TB029's "1.0000" for a one-inch thread. External: from the cylinder (major at
    // its largest) in to the rounded-root/UNR minor at its largest, TB029's 0.8492" for 1"-8.
    let (crest, root) = match spec.side {
        Side::Internal => (
            limits.minor.min.ok_or_else(|| missing("minor"))? / 2.0,
            limits.major.min.ok_or_else(|| missing("major"))? / 2.0,
        ),
        Side::External => (
            limits.major.max.ok_or_else(|| missing("major"))? / 2.0,
            limits.minor.max.ok_or_else(|| missing("minor"))? / 2.0,
        ),
    };
    // A taper thread (NPT, ISO 7-1 R/Rc): crest and root are cones, 1:16 on diameter, given here
    // at the top of the thread (`start_z`), which is the face the standard measures from (the
    // small end of an external thread, the opening of an internal one); the radius then changes
    // by `slope` per mm going down: an external thread grows, an internal one shrinks.
    let (crest, root, slope) = match t.taper {
        Some(tp) => {
            let k = tp.diameter_per_length / 2.0;
            let (crest_gauge, grow, depth) = match spec.side {
                Side::External => (tp.gauge_major_diameter / 2.0, 1.0, t.external_depth),
                Side::Internal => (
                    tp.gauge_pitch_diameter - tp.gauge_major_diameter / 2.0,
                    -1.0,
                    t.internal_depth,
                ),
            };
            let c = crest_gauge - grow * k * tp.gauge_plane_from_face(spec.side);
            let r = match spec.side {
                Side::External => c - depth,
                Side::Internal => c + depth,
            };
            (c, r, grow * k)
        }
        None => (crest, root, 0.0),
    };
    Ok(Contour { crest, root, slope })
}

/// Decides whether the tool fits an internal thread's bore over the whole length (a taper bore
/// narrows going down); an external thread always takes the tool.
fn check_tool_fits(spec: &MillSpec, r_t: f64, contour: &Contour) -> Result<()> {
    let crest = contour.crest;
    if spec.side == Side::Internal && r_t >= crest - contour.slope.abs() * spec.length {
        return Err(flag_error(
            "--tool-diameter",
            format!(
                "a {} tool does not fit the {} bore (minor diameter {:.4}): the tool must be smaller than the hole",
                spec.tool_diameter,
                spec.thread.name,
                2.0 * crest
            ),
        )
        .with_hint("choose a smaller thread mill; tool diameter ≈ 0.7 × the minor diameter is usual"));
    }
    Ok(())
}

/// How far the helix advances per turn and how many turns it makes per pass.
struct Count {
    /// One lead per turn: the pitch times the number of starts.
    lead: f64,
    /// The turns before rounding to a whole number (at least 1), and rounded.
    turns_f: f64,
    turns: u32,
    /// How far the top tooth rises above the thread top at the top of the helix.
    flute_overhang: f64,
}

/// Decides the helix's lead and its turns per pass (the teeth of a multi-tooth tool cut
/// `teeth − 1` pitches more per turn), refusing a starts count outside 1 to 100 and a plan of
/// more than [`MAX_TURNS`] turns or [`MAX_HELIX_ARCS`] helical moves.
fn helix_count(spec: &MillSpec) -> Result<Count> {
    let pitch = spec.thread.pitch;
    if spec.starts == 0 || spec.starts > 100 {
        return Err(flag_error(
            "--starts",
            format!("between 1 and 100 starts, not {}", spec.starts),
        ));
    }
    // The helix advances one lead per turn: the pitch times the number of starts.
    let lead = pitch * f64::from(spec.starts);
    let span = f64::from(spec.teeth - 1) * pitch;
    let turns_f = ((spec.length - span) / lead - 1e-9).ceil().max(1.0);
    if turns_f > f64::from(MAX_TURNS) {
        return Err(flag_error(
            "--length",
            format!(
                "{} mm of thread is {turns_f} turns per pass, more than {MAX_TURNS}",
                spec.length
            ),
        ));
    }
    let turns = turns_f as u32;
    if u64::from(turns) * u64::from(spec.passes) * u64::from(spec.starts) > MAX_HELIX_ARCS {
        return Err(Diagnostic::error(
            Code::TooManyPasses,
            Span::default(),
            format!(
                "--passes: {} passes of {turns} turns is more than {MAX_HELIX_ARCS} helical moves",
                spec.passes
            ),
        ));
    }
    // The top tooth reaches (teeth − 1)·P above the bottom tooth: above --start-z when the tool's
    // teeth span more than the thread.
    let flute_overhang = (span + turns_f * lead - spec.length).max(0.0);
    Ok(Count {
        lead,
        turns_f,
        turns,
        flute_overhang,
    })
}

/// Decides the contour radius of each radial pass: constant chip area, `R_k = R_crest ±
/// h·√(k/N)`, the last pass exactly on the root.
fn pass_radii(spec: &MillSpec, contour: &Contour, inward: f64) -> Vec<f64> {
    let (crest, root) = (contour.crest, contour.root);
    let depth = (root - crest).abs();
    let mut pass_radii: Vec<f64> = (1..=spec.passes)
        .map(|k| crest + inward * depth * (f64::from(k) / f64::from(spec.passes)).sqrt())
        .collect();
    if let Some(last) = pass_radii.last_mut() {
        *last = root;
    }
    pass_radii
}

/// Decides whether every move's point is finite; the first one that is not is the error.
fn check_finite(moves: &[Move]) -> Result<()> {
    if let Some(bad) = moves
        .iter()
        .find(|m| !(m.to.x.is_finite() && m.to.y.is_finite() && m.to.z.is_finite()))
    {
        return Err(Diagnostic::error(
            Code::Geometry,
            Span::default(),
            format!("pass {} computes a point that is not finite", bad.pass),
        ));
    }
    Ok(())
}

/// What every pass shares: the thread's axis and senses, the helix's heights, the tool, and how
/// feed and compensation apply.
struct Helix {
    side: Side,
    lead_in: LeadIn,
    starts: u32,
    /// Helix arcs clockwise (G2)? And the compensation side.
    cw: bool,
    comp_side: CompSide,
    /// +1 when the helix turns counter-clockwise.
    sigma: f64,
    /// Milling bottom-up, and the sign of Z along the helix (+1 up).
    up: bool,
    s_z: f64,
    /// +1 when depth grows outward from the axis (internal), −1 inward (external).
    inward: f64,
    crest: f64,
    slope: f64,
    lead: f64,
    turns: u32,
    top: f64,
    bottom: f64,
    /// Where the helix starts and ends (Z), and the height of the rapids.
    z_start: f64,
    z_end: f64,
    clearance_z: f64,
    cx: f64,
    cy: f64,
    /// Tool radius.
    r_t: f64,
    comp_on: bool,
    /// Offset from the tool centre to the programmed contour: outward for internal threads,
    /// inward for external ones (on the helix); toward the lead arc's centre on the lead arcs.
    off: f64,
    /// How far the tool stays clear of the stock where it goes down and up.
    clear: f64,
    edge_feed: f64,
    /// F drives the tool centre when the program is the centre path, and under compensation on
    /// controls that keep F at the centre: then arcs are scaled so the edge sees `edge_feed`.
    scale_arcs: bool,
}

impl Helix {
    /// Decides the senses of the helix (TB029's table), its heights and how the feed and the
    /// compensation apply.
    fn new(spec: &MillSpec, contour: &Contour, count: &Count, direction: Direction) -> Helix {
        let (cw, comp_side) = directions(spec.side, spec.hand, direction);
        let sigma = if cw { -1.0 } else { 1.0 }; // +1 counter-clockwise
        let up = direction == Direction::BottomUp;
        let s_z = if up { 1.0 } else { -1.0 };
        let inward = match spec.side {
            Side::Internal => 1.0, // depth grows outward from the axis
            Side::External => -1.0,
        };
        let (lead, turns_f) = (count.lead, count.turns_f);
        let top = spec.start_z;
        let bottom = spec.start_z - spec.length;
        let (z_start, z_end) = if up {
            (bottom, bottom + turns_f * lead)
        } else {
            (bottom + turns_f * lead, bottom)
        };
        let clearance_z = top.max(z_start).max(z_end) + spec.clearance;
        let (cx, cy) = spec.center;
        let r_t = spec.tool_diameter / 2.0;
        let comp_on = spec.comp == Comp::Controller;
        Helix {
            side: spec.side,
            lead_in: spec.lead_in,
            starts: spec.starts,
            cw,
            comp_side,
            sigma,
            up,
            s_z,
            inward,
            crest: contour.crest,
            slope: contour.slope,
            lead,
            turns: count.turns,
            top,
            bottom,
            z_start,
            z_end,
            clearance_z,
            cx,
            cy,
            r_t,
            comp_on,
            off: if comp_on { r_t } else { 0.0 },
            clear: (0.5 * r_t).max(0.5),
            edge_feed: spec.feed,
            scale_arcs: !comp_on || spec.comp_feed == FeedReference::Centre,
        }
    }

    /// The contour radius at height `z` of a pass whose radius at the top of the thread is
    /// `r_top` (a taper changes it along the helix).
    fn rad_at(&self, r_top: f64, z: f64) -> f64 {
        r_top + self.slope * (self.top - z)
    }

    /// Decides the programmed F on an arc whose tool centre runs at `centre_r` while the edge
    /// cuts at `edge_r`: scaled so the edge sees the requested feed when F drives the centre.
    fn arc_feed(&self, centre_r: f64, edge_r: f64) -> f64 {
        if self.scale_arcs {
            self.edge_feed * centre_r / edge_r
        } else {
            self.edge_feed
        }
    }

    /// Decides the lead arcs of a pass whose contour radius at the helix start is `r` and whose
    /// tool centre runs at `a_c`, or none for a radial entry.
    ///
    /// In tool-centre terms: radius a about m; S (the helix start) at angle `theta_s` about m,
    /// the lead-in start a quarter turn before it, the lead-out end a quarter turn after.
    /// Internal: internally tangent with a = A/2, so the lead circle passes through the thread
    /// axis and the angle about the axis is exactly half the angle about m (inscribed angle
    /// theorem): a Z linear along the arc is the helix's own phase at every point. External:
    /// externally tangent and turning the other way; its start clears the cylinder
    /// (a_c + a = crest + r_t + clear). There the phase is not linear in the arc angle, so the
    /// arc is split into EXTERNAL_LEAD_PIECES arcs, each ending exactly in phase. An arc lead-out
    /// cannot follow the cone (its circle is the start's): a taper is entered and left radially
    /// (TB029 step 4).
    fn lead_arcs(&self, r: f64, a_c: f64) -> Option<LeadArcs> {
        let (cx, cy, cw, r_t) = (self.cx, self.cy, self.cw, self.r_t);
        let lead_in = if self.slope != 0.0 {
            LeadIn::Radial
        } else {
            self.lead_in
        };
        match lead_in {
            LeadIn::Radial => None,
            LeadIn::Arc => {
                let quarter = std::f64::consts::FRAC_PI_2;
                let (a, m, theta_s, arc_cw, pieces) = match self.side {
                    Side::Internal => (a_c / 2.0, (cx + a_c / 2.0, cy), 0.0, cw, 1),
                    Side::External => {
                        let a = (self.crest - r) + self.clear;
                        (
                            a,
                            (cx + a_c + a, cy),
                            std::f64::consts::PI,
                            !cw,
                            EXTERNAL_LEAD_PIECES,
                        )
                    }
                };
                let turn = if arc_cw { -quarter } else { quarter };
                Some(LeadArcs {
                    a,
                    m,
                    cw: arc_cw,
                    pieces,
                    theta_in: theta_s - turn,
                    theta_s,
                    theta_out: theta_s + turn,
                    feed: self.arc_feed(a, a + r_t),
                })
            }
        }
    }

    /// Phase (in turns, signed along the helix) of the tool centre at angle `theta` about the
    /// lead arcs' centre.
    fn phase_at(&self, l: &LeadArcs, theta: f64) -> f64 {
        let x = l.m.0 + l.a * theta.cos() - self.cx;
        let y = l.m.1 + l.a * theta.sin() - self.cy;
        self.sigma * y.atan2(x) / std::f64::consts::TAU
    }

    /// The programmed point at angle `theta` on the lead arcs.
    fn prog_at(&self, l: &LeadArcs, theta: f64) -> (f64, f64) {
        (
            l.m.0 + (l.a + self.off) * theta.cos(),
            l.m.1 + (l.a + self.off) * theta.sin(),
        )
    }

    /// Decides the phases at the joints of a lead, counted outward from S (index 0 = S). Beyond
    /// the thread the angle about the axis of an external lead arc turns back; Z is held there
    /// instead of reversing (the running extreme), which changes nothing where the tool is in the
    /// material.
    fn outward_phases(&self, l: &LeadArcs, theta_end: f64) -> Vec<f64> {
        let mut v = vec![0.0];
        let mut extreme = 0.0f64;
        for k in 1..=l.pieces {
            let theta = l.theta_s + (theta_end - l.theta_s) * f64::from(k) / f64::from(l.pieces);
            let p = self.phase_at(l, theta);
            if p.abs() > extreme.abs() {
                extreme = p;
            }
            v.push(extreme);
        }
        v
    }

    /// Appends the moves of one pass for every start. Multi-start threads: start j is start 0
    /// turned about the axis so that its groove lies j pitches further along (angle
    /// −hand·360°·j/starts, hand +1 when counter-clockwise rises); Z is unchanged, so every start
    /// keeps the exact bottom and absolute Z.
    fn every_start(&self, one: &[Move], moves: &mut Vec<Move>) {
        let (cx, cy) = (self.cx, self.cy);
        let rising_ccw = (self.sigma > 0.0) == self.up;
        for j in 0..self.starts {
            let angle = if rising_ccw { -1.0 } else { 1.0 } * std::f64::consts::TAU * f64::from(j)
                / f64::from(self.starts);
            let (sn, cs) = angle.sin_cos();
            let rot = |x: f64, y: f64| {
                let (dx, dy) = (x - cx, y - cy);
                (cx + dx * cs - dy * sn, cy + dx * sn + dy * cs)
            };
            for m in one {
                let (x, y) = rot(m.to.x, m.to.y);
                let kind = match m.kind {
                    MoveKind::Arc { center, cw } => MoveKind::Arc {
                        center: rot(center.0, center.1),
                        cw,
                    },
                    other => other,
                };
                moves.push(Move {
                    kind,
                    to: P3::new(x, y, m.to.z),
                    ..*m
                });
            }
        }
    }
}

/// The lead arcs of a pass with where they run: the helix phase at each joint of the lead-in
/// and of the lead-out, counted outward from the helix start, and the programmed points where
/// the lead-in starts and the lead-out ends.
struct Leads {
    arcs: LeadArcs,
    in_ph: Vec<f64>,
    out_ph: Vec<f64>,
    entry: (f64, f64),
    exit: (f64, f64),
}

/// The moves of one pass so far.
struct PassMoves {
    pass: u32,
    list: Vec<Move>,
}

impl PassMoves {
    /// Appends one move of this pass.
    fn push(&mut self, kind: MoveKind, to: P3, feed: f64, comp: Option<CompSide>) {
        self.list.push(Move {
            kind,
            to,
            feed,
            comp,
            pass: self.pass,
        })
    }
}

/// One radial pass of the first start: its radii and feed, its lead arcs, and its moves so far.
struct PassPath<'h> {
    h: &'h Helix,
    /// The pass's contour radius at the top of the thread (a taper changes it along the helix).
    r_top: f64,
    /// The programmed start point of the helix.
    s_prog: (f64, f64),
    /// The programmed F on the helix.
    f_helix: f64,
    /// The compensation in force while cutting.
    on: Option<CompSide>,
    leads: Option<Leads>,
    moves: PassMoves,
}

impl<'h> PassPath<'h> {
    /// Decides the radii of pass `pass` (contour radius `r_top` at the top of the thread), its
    /// helix feed and its lead arcs.
    fn new(h: &'h Helix, pass: u32, r_top: f64) -> PassPath<'h> {
        let r = h.rad_at(r_top, h.z_start);
        // Tool-centre radius of the helix.
        let a_c = r - h.inward * h.r_t;
        let prog_r = a_c + h.inward * h.off;
        // Arc feed: the edge cuts at radius r, the centre runs at a_c.
        let f_helix = h.arc_feed(a_c, r);
        let leads = h.lead_arcs(r, a_c).map(|l| Leads {
            in_ph: h.outward_phases(&l, l.theta_in),
            out_ph: h.outward_phases(&l, l.theta_out),
            entry: h.prog_at(&l, l.theta_in),
            exit: h.prog_at(&l, l.theta_out),
            arcs: l,
        });
        PassPath {
            h,
            r_top,
            s_prog: (h.cx + prog_r, h.cy),
            f_helix,
            on: h.comp_on.then_some(h.comp_side),
            leads,
            moves: PassMoves {
                pass,
                list: Vec::new(),
            },
        }
    }

    /// The moves of the pass, in order: approach, lead-in, full turns, lead-out, departure.
    fn lay_out(mut self) -> Vec<Move> {
        self.approach();
        self.turns();
        self.depart();
        self.moves.list
    }

    /// Decides where the pass starts and ends in XY (tool centre before compensation starts):
    /// the axis for an internal thread; outside the cylinder for an external one, beside the
    /// lead arcs' ends or clear of the crest.
    fn approach_and_leave(&self) -> ((f64, f64), (f64, f64)) {
        let h = self.h;
        let (cx, cy) = (h.cx, h.cy);
        let ell = h.r_t + h.clear;
        match h.side {
            Side::Internal => ((cx, cy), (cx, cy)),
            Side::External => match &self.leads {
                Some(l) => {
                    let (qi, qo) = (l.entry, l.exit);
                    ((qi.0 + ell, qi.1), (qo.0 + ell, qo.1))
                }
                None => {
                    let x = cx + h.crest + h.r_t + h.clear;
                    ((x, cy), (x, cy))
                }
            },
        }
    }

    /// TB029 steps 1–4: rapid above the approach point, feed to the starting height, then
    /// compensation on along a straight move to the lead-in start (and the lead-in arcs to the
    /// helix start) or straight to the start point.
    fn approach(&mut self) {
        let h = self.h;
        let (z_start, s_z, lead) = (h.z_start, h.s_z, h.lead);
        let z_in = self.leads.as_ref().map_or(z_start, |l| {
            let v = &l.in_ph;
            z_start + s_z * v[v.len() - 1] * lead
        });
        let (approach, _) = self.approach_and_leave();
        let on = self.on;
        self.moves.push(
            MoveKind::Rapid,
            P3::new(approach.0, approach.1, h.clearance_z),
            0.0,
            None,
        );
        self.moves.push(
            MoveKind::Feed,
            P3::new(approach.0, approach.1, z_in),
            h.edge_feed,
            None,
        );
        let Some(leads) = &self.leads else {
            let s_prog = self.s_prog;
            self.moves.push(
                MoveKind::Feed,
                P3::new(s_prog.0, s_prog.1, z_start),
                h.edge_feed,
                on,
            );
            return;
        };
        let (l, q) = (&leads.arcs, leads.entry);
        self.moves
            .push(MoveKind::Feed, P3::new(q.0, q.1, z_in), h.edge_feed, on);
        for i in 1..=l.pieces {
            let theta = l.theta_in + (l.theta_s - l.theta_in) * f64::from(i) / f64::from(l.pieces);
            let (x, y) = if i == l.pieces {
                self.s_prog
            } else {
                h.prog_at(l, theta)
            };
            let ph = leads.in_ph[(l.pieces - i) as usize];
            let z = z_start + s_z * ph * lead;
            self.moves.push(
                MoveKind::Arc {
                    center: l.m,
                    cw: l.cw,
                },
                P3::new(x, y, z),
                l.feed,
                on,
            );
        }
    }

    /// TB029 steps 5–6: full turns, each Z from the exact pitch. On a taper each turn is
    /// `TAPER_ARCS_PER_TURN` arcs whose ends lie on the cone, each about the centre on its
    /// chord's bisector nearest the axis (so both ends are exactly on its circle).
    fn turns(&mut self) {
        let h = self.h;
        let (cx, cy) = (h.cx, h.cy);
        for turn in 1..=h.turns {
            let z = h.z_start + h.s_z * f64::from(turn) * h.lead;
            if h.slope == 0.0 {
                self.moves.push(
                    MoveKind::Arc {
                        center: (cx, cy),
                        cw: h.cw,
                    },
                    P3::new(self.s_prog.0, self.s_prog.1, z),
                    self.f_helix,
                    self.on,
                );
                continue;
            }
            let n = TAPER_ARCS_PER_TURN;
            for k in 1..=n {
                let (x0, y0, _) = self.taper_point(turn, k - 1);
                let (x1, y1, z1) = self.taper_point(turn, k);
                self.moves.push(
                    MoveKind::Arc {
                        center: bisector_centre((x0, y0), (x1, y1), (cx, cy)),
                        cw: h.cw,
                    },
                    P3::new(x1, y1, if k == n { z } else { z1 }),
                    self.f_helix,
                    self.on,
                );
            }
        }
    }

    /// Decides the programmed point `k` quarter-turns (of `TAPER_ARCS_PER_TURN`) into turn
    /// `turn` of a taper helix: on the cone at its exact height.
    fn taper_point(&self, turn: u32, k: u32) -> (f64, f64, f64) {
        let h = self.h;
        let n = TAPER_ARCS_PER_TURN;
        let f = f64::from(turn - 1) + f64::from(k) / f64::from(n);
        let zk = h.z_start + h.s_z * f * h.lead;
        let rk = h.rad_at(self.r_top, zk) - h.inward * h.r_t + h.inward * h.off;
        let ang = h.sigma * std::f64::consts::TAU * f64::from(k) / f64::from(n);
        (h.cx + rk * ang.cos(), h.cy + rk * ang.sin(), zk)
    }

    /// The lead-out arcs (if any), compensation off on the way back to the leave point, and the
    /// rapid up.
    fn depart(&mut self) {
        let h = self.h;
        let (z_end, s_z, lead) = (h.z_end, h.s_z, h.lead);
        let on = self.on;
        let (_, leave) = self.approach_and_leave();
        let z_out = self.leads.as_ref().map_or(z_end, |l| {
            let v = &l.out_ph;
            z_end + s_z * v[v.len() - 1] * lead
        });
        if let Some(leads) = &self.leads {
            let (l, q) = (&leads.arcs, leads.exit);
            for i in 1..=l.pieces {
                let theta =
                    l.theta_s + (l.theta_out - l.theta_s) * f64::from(i) / f64::from(l.pieces);
                let (x, y) = if i == l.pieces {
                    q
                } else {
                    h.prog_at(l, theta)
                };
                let ph = leads.out_ph[i as usize];
                let z = z_end + s_z * ph * lead;
                self.moves.push(
                    MoveKind::Arc {
                        center: l.m,
                        cw: l.cw,
                    },
                    P3::new(x, y, z),
                    l.feed,
                    on,
                );
            }
        }
        self.moves.push(
            MoveKind::Feed,
            P3::new(leave.0, leave.1, z_out),
            h.edge_feed,
            None,
        );
        self.moves.push(
            MoveKind::Rapid,
            P3::new(leave.0, leave.1, h.clearance_z),
            0.0,
            None,
        );
    }
}

/// Arcs per helical turn on a taper thread. A quarter-turn arc whose ends lie on the cone strays
/// from the conical helix between them by about (Δr)²/(8r) with Δr the radius change over the
/// arc (P/128 on a 1:16 taper): 0.03 µm for 1/2-14 NPT (docs/milling.md).
pub const TAPER_ARCS_PER_TURN: u32 = 4;

/// The centre of the circle through `a` and `b` nearest `axis`: on the chord's perpendicular
/// bisector, at the foot of the perpendicular from the axis.
fn bisector_centre(a: (f64, f64), b: (f64, f64), axis: (f64, f64)) -> (f64, f64) {
    let m = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
    let d = (-(b.1 - a.1), b.0 - a.0);
    let len2 = d.0 * d.0 + d.1 * d.1;
    if len2 == 0.0 {
        return axis;
    }
    let t = ((axis.0 - m.0) * d.0 + (axis.1 - m.1) * d.1) / len2;
    (m.0 + t * d.0, m.1 + t * d.1)
}

/// Checks a plan against a controller's rules: LinuxCNC refuses a compensation entry (or exit) move
/// no longer than the tool radius.
pub fn profile_checks(plan: &Plan, profile: &profile::MillProfile) -> Result<()> {
    if !profile.comp_entry_longer_than_radius || plan.comp != Comp::Controller {
        return Ok(());
    }
    let mut prev: Option<&Move> = None;
    for m in &plan.moves {
        if let Some(p) = prev {
            let toggles = p.comp.is_some() != m.comp.is_some();
            let len = (m.to.x - p.to.x).hypot(m.to.y - p.to.y);
            if toggles && len <= plan.tool_radius {
                return Err(Diagnostic::error(
                    Code::Geometry,
                    Span::default(),
                    format!(
                        "{}: the compensation {} move of pass {} is {len:.4} mm long, not longer than the tool radius {:.4} mm",
                        profile.name,
                        if m.comp.is_some() { "entry" } else { "exit" },
                        m.pass,
                        plan.tool_radius
                    ),
                )
                .with_hint("use --comp none (tool-centre path) or a smaller tool"));
            }
        }
        prev = Some(m);
    }
    Ok(())
}
