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

pub mod post;
pub mod profile;
pub mod readback;
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
    let t = &spec.thread;
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

    let limits = t.limits(spec.side);
    let missing = |what: &str| {
        Diagnostic::error(
            Code::Geometry,
            Span::default(),
            format!("{} has no {what} limit to mill to", t.name),
        )
    };
    let r_t = spec.tool_diameter / 2.0;
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
    if spec.side == Side::Internal && r_t >= crest - slope.abs() * spec.length {
        return Err(flag_error(
            "--tool-diameter",
            format!(
                "a {} tool does not fit the {} bore (minor diameter {:.4}): the tool must be smaller than the hole",
                spec.tool_diameter,
                t.name,
                2.0 * crest
            ),
        )
        .with_hint("choose a smaller thread mill; tool diameter ≈ 0.7 × the minor diameter is usual"));
    }

    let direction = spec
        .direction
        .unwrap_or_else(|| climb(spec.side, spec.hand));
    let (cw, comp_side) = directions(spec.side, spec.hand, direction);
    let sigma = if cw { -1.0 } else { 1.0 }; // +1 counter-clockwise
    let up = direction == Direction::BottomUp;
    let s_z = if up { 1.0 } else { -1.0 };
    let inward = match spec.side {
        Side::Internal => 1.0, // depth grows outward from the axis
        Side::External => -1.0,
    };

    let pitch = t.pitch;
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
    let depth = (root - crest).abs();
    let mut pass_radii: Vec<f64> = (1..=spec.passes)
        .map(|k| crest + inward * depth * (f64::from(k) / f64::from(spec.passes)).sqrt())
        .collect();
    if let Some(last) = pass_radii.last_mut() {
        *last = root;
    }

    let top = spec.start_z;
    let bottom = spec.start_z - spec.length;
    let (z_start, z_end) = if up {
        (bottom, bottom + turns_f * lead)
    } else {
        (bottom + turns_f * lead, bottom)
    };
    let clearance_z = top.max(z_start).max(z_end) + spec.clearance;
    let (cx, cy) = spec.center;
    let comp_on = spec.comp == Comp::Controller;
    // Offset from the tool centre to the programmed contour: outward for internal threads, inward
    // for external ones (on the helix); toward the lead arc's centre on the lead arcs.
    let off = if comp_on { r_t } else { 0.0 };
    let clear = (0.5 * r_t).max(0.5);
    let edge_feed = spec.feed;
    // F drives the tool centre when the program is the centre path, and under compensation on
    // controls that keep F at the centre: then arcs are scaled so the edge sees `edge_feed`.
    let scale_arcs = !comp_on || spec.comp_feed == FeedReference::Centre;

    let mut moves = Vec::new();
    let mut helix_feed = edge_feed;
    for (k, &r) in pass_radii.iter().enumerate() {
        let pass = k as u32 + 1;
        let mut one: Vec<Move> = Vec::new();
        // The contour radius at Z (a taper changes it along the helix), and at the helix start.
        let rad_at = |z: f64| r + slope * (top - z);
        let r = rad_at(z_start);
        // Tool-centre radius of the helix.
        let a_c = r - inward * r_t;
        let prog_r = a_c + inward * off;
        // Arc feed: the edge cuts at radius r, the centre runs at a_c.
        let arc_feed = |centre_r: f64, edge_r: f64| {
            if scale_arcs {
                edge_feed * centre_r / edge_r
            } else {
                edge_feed
            }
        };
        let f_helix = arc_feed(a_c, r);
        helix_feed = f_helix;
        let push = |moves: &mut Vec<Move>, kind, to, feed, comp| {
            moves.push(Move {
                kind,
                to,
                feed,
                comp,
                pass,
            })
        };
        let on = comp_on.then_some(comp_side);
        let s_prog = (cx + prog_r, cy);

        // Lead arcs, in tool-centre terms: radius a about m; S (the helix start) at angle
        // `theta_s` about m, the lead-in start a quarter turn before it, the lead-out end a quarter
        // turn after. Internal: internally tangent with a = A/2, so the lead circle passes through
        // the thread axis and the angle about the axis is exactly half the angle about m (inscribed
        // angle theorem): a Z linear along the arc is the helix's own phase at every point.
        // External: externally tangent and turning the other way; its start clears the cylinder
        // (a_c + a = crest + r_t + clear). There the phase is not linear in the arc angle, so the
        // arc is split into EXTERNAL_LEAD_PIECES arcs, each ending exactly in phase.
        // An arc lead-out cannot follow the cone (its circle is the start's): a taper is entered
        // and left radially (TB029 step 4).
        let lead_in = if slope != 0.0 {
            LeadIn::Radial
        } else {
            spec.lead_in
        };
        let leads = match lead_in {
            LeadIn::Radial => None,
            LeadIn::Arc => {
                let quarter = std::f64::consts::FRAC_PI_2;
                let (a, m, theta_s, arc_cw, pieces) = match spec.side {
                    Side::Internal => (a_c / 2.0, (cx + a_c / 2.0, cy), 0.0, cw, 1),
                    Side::External => {
                        let a = (crest - r) + clear;
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
                    feed: arc_feed(a, a + r_t),
                })
            }
        };
        // Phase (in turns, signed along the helix) of the tool centre at angle theta about m.
        let phase_at = |l: &LeadArcs, theta: f64| {
            let x = l.m.0 + l.a * theta.cos() - cx;
            let y = l.m.1 + l.a * theta.sin() - cy;
            sigma * y.atan2(x) / std::f64::consts::TAU
        };
        let prog_at = |l: &LeadArcs, theta: f64| {
            (
                l.m.0 + (l.a + off) * theta.cos(),
                l.m.1 + (l.a + off) * theta.sin(),
            )
        };
        // Phases at the joints of a lead, counted outward from S (index 0 = S). Beyond the thread
        // the angle about the axis of an external lead arc turns back; Z is held there instead of
        // reversing (the running extreme), which changes nothing where the tool is in the material.
        let outward_phases = |l: &LeadArcs, theta_end: f64| -> Vec<f64> {
            let mut v = vec![0.0];
            let mut extreme = 0.0f64;
            for k in 1..=l.pieces {
                let theta =
                    l.theta_s + (theta_end - l.theta_s) * f64::from(k) / f64::from(l.pieces);
                let p = phase_at(l, theta);
                if p.abs() > extreme.abs() {
                    extreme = p;
                }
                v.push(extreme);
            }
            v
        };
        let in_ph = leads.as_ref().map(|l| outward_phases(l, l.theta_in));
        let out_ph = leads.as_ref().map(|l| outward_phases(l, l.theta_out));
        let z_in = in_ph
            .as_ref()
            .map_or(z_start, |v| z_start + s_z * v[v.len() - 1] * lead);
        let z_out = out_ph
            .as_ref()
            .map_or(z_end, |v| z_end + s_z * v[v.len() - 1] * lead);
        let entry = leads.as_ref().map(|l| prog_at(l, l.theta_in));
        let exit = leads.as_ref().map(|l| prog_at(l, l.theta_out));
        let ell = r_t + clear;
        // Where the pass starts and ends in XY (tool centre before compensation starts).
        let (approach, leave) = match spec.side {
            Side::Internal => ((cx, cy), (cx, cy)),
            Side::External => match (entry, exit) {
                (Some(qi), Some(qo)) => ((qi.0 + ell, qi.1), (qo.0 + ell, qo.1)),
                _ => {
                    let x = cx + crest + r_t + clear;
                    ((x, cy), (x, cy))
                }
            },
        };

        // 1. Rapid above the approach point, 2. feed to the starting height.
        push(
            &mut one,
            MoveKind::Rapid,
            P3::new(approach.0, approach.1, clearance_z),
            0.0,
            None,
        );
        push(
            &mut one,
            MoveKind::Feed,
            P3::new(approach.0, approach.1, z_in),
            edge_feed,
            None,
        );
        // 3.–4. Compensation on along a straight move to the lead-in start or the start point.
        match (&leads, entry) {
            (Some(l), Some(q)) => {
                push(
                    &mut one,
                    MoveKind::Feed,
                    P3::new(q.0, q.1, z_in),
                    edge_feed,
                    on,
                );
                for i in 1..=l.pieces {
                    let theta =
                        l.theta_in + (l.theta_s - l.theta_in) * f64::from(i) / f64::from(l.pieces);
                    let (x, y) = if i == l.pieces {
                        s_prog
                    } else {
                        prog_at(l, theta)
                    };
                    let ph = in_ph.as_ref().map_or(0.0, |v| v[(l.pieces - i) as usize]);
                    let z = z_start + s_z * ph * lead;
                    push(
                        &mut one,
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
            _ => push(
                &mut one,
                MoveKind::Feed,
                P3::new(s_prog.0, s_prog.1, z_start),
                edge_feed,
                on,
            ),
        }
        // 5.–6. Full turns, each Z from the exact pitch. On a taper each turn is
        // `TAPER_ARCS_PER_TURN` arcs whose ends lie on the cone, each about the centre on its
        // chord's bisector nearest the axis (so both ends are exactly on its circle).
        for turn in 1..=turns {
            let z = z_start + s_z * f64::from(turn) * lead;
            if slope == 0.0 {
                push(
                    &mut one,
                    MoveKind::Arc {
                        center: (cx, cy),
                        cw,
                    },
                    P3::new(s_prog.0, s_prog.1, z),
                    f_helix,
                    on,
                );
                continue;
            }
            let n = TAPER_ARCS_PER_TURN;
            let point = |k: u32| {
                let f = f64::from(turn - 1) + f64::from(k) / f64::from(n);
                let zk = z_start + s_z * f * lead;
                let rk = rad_at(zk) - inward * r_t + inward * off;
                let ang = sigma * std::f64::consts::TAU * f64::from(k) / f64::from(n);
                (cx + rk * ang.cos(), cy + rk * ang.sin(), zk)
            };
            for k in 1..=n {
                let (x0, y0, _) = point(k - 1);
                let (x1, y1, z1) = point(k);
                push(
                    &mut one,
                    MoveKind::Arc {
                        center: bisector_centre((x0, y0), (x1, y1), (cx, cy)),
                        cw,
                    },
                    P3::new(x1, y1, if k == n { z } else { z1 }),
                    f_helix,
                    on,
                );
            }
        }
        // Lead-out, compensation off on the way back, rapid up.
        if let (Some(l), Some(q)) = (&leads, exit) {
            for i in 1..=l.pieces {
                let theta =
                    l.theta_s + (l.theta_out - l.theta_s) * f64::from(i) / f64::from(l.pieces);
                let (x, y) = if i == l.pieces { q } else { prog_at(l, theta) };
                let ph = out_ph.as_ref().map_or(0.0, |v| v[i as usize]);
                let z = z_end + s_z * ph * lead;
                push(
                    &mut one,
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
        push(
            &mut one,
            MoveKind::Feed,
            P3::new(leave.0, leave.1, z_out),
            edge_feed,
            None,
        );
        push(
            &mut one,
            MoveKind::Rapid,
            P3::new(leave.0, leave.1, clearance_z),
            0.0,
            None,
        );
        // Multi-start threads: start j is start 0 turned about the axis so that its groove lies
        // j pitches further along (angle −hand·360°·j/starts, hand +1 when counter-clockwise
        // rises); Z is unchanged, so every start keeps the exact bottom and absolute Z.
        let rising_ccw = (sigma > 0.0) == up;
        for j in 0..spec.starts {
            let angle = if rising_ccw { -1.0 } else { 1.0 } * std::f64::consts::TAU * f64::from(j)
                / f64::from(spec.starts);
            let (sn, cs) = angle.sin_cos();
            let rot = |x: f64, y: f64| {
                let (dx, dy) = (x - cx, y - cy);
                (cx + dx * cs - dy * sn, cy + dx * sn + dy * cs)
            };
            for m in &one {
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

    let lowest_z = moves.iter().map(|m| m.to.z).fold(f64::INFINITY, f64::min);
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
    Ok(Plan {
        thread: t.name.clone(),
        class: limits.class.to_string(),
        side: spec.side,
        hand: spec.hand,
        direction,
        cw,
        comp: spec.comp,
        comp_side,
        pitch,
        lead,
        starts: spec.starts,
        tpi: t.tpi,
        crest_radius: crest,
        final_radius: root,
        pass_radii,
        tool_radius: r_t,
        teeth: spec.teeth,
        turns,
        seed_count: spec.length / pitch,
        top_z: top,
        bottom_z: bottom,
        lowest_z,
        clearance_z,
        edge_feed,
        helix_feed,
        center: spec.center,
        flute_overhang,
        taper: slope,
        radial_for_taper: slope != 0.0 && spec.lead_in == LeadIn::Arc,
        moves,
    })
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
