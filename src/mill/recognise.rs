//! Threads that are milled, recognised in a machining centre's motion (issue 24, item 2).
//!
//! A helix is a run of consecutive circular moves about one axis, at one radius, in one
//! direction, whose normal axis advances: each turn's advance is its lead. Runs about the same
//! axis with the same lead and hand are the passes of one thread — each radius a radial pass,
//! each phase of the helix along the axis a start. Anything between runs (the entry, the lead-in
//! and lead-out arcs about other centres, retracts, rapids) belongs to no run; a run about
//! another axis, a tool change, or a different lead or hand ends the thread.
//!
//! What follows from a thread's runs, each fact with how it is known:
//! * the hand: a helix that advances along its axis while turning counter-clockwise seen from
//!   that axis' positive end is right-handed (the right-hand rule), so G3 rising and G2 falling
//!   in G17 are right-hand threads (TB029: "G2 top-down and G3 bottom-up for a right-hand
//!   thread", seed 004);
//! * the side (internal or external): given; else from the compensation (G41 keeps the tool left
//!   of the path: inside a counter-clockwise circle, the wall of a bore); else from where the
//!   tool came from before the first run (nearer the axis than the helix: inside a bore); else
//!   from the passes' radii (growing outward: a bore opened up);
//! * the diameters: under compensation the programmed path is the finished contour (an internal
//!   thread's major diameter, an external one's minor); without it, the tool-centre path plus
//!   (internal) or less (external) the cutter's radius, when the cutter's diameter is known;
//! * climb or conventional: with the spindle clockwise (M3), a cutter going round counter-
//!   clockwise inside a bore, or clockwise outside a cylinder, climbs.

use serde::Serialize;

use super::motion::{Comp, MillKind, MillMotion, Plane, Rotation};
use super::{Direction, Hand, Side};

/// A run shorter than this many turns is an entry or exit arc, not a thread.
const MIN_TURNS: f64 = 0.99;

/// What recognition may be told.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    /// Positions within this (mm) are the same: the program's resolution.
    pub eps: f64,
    /// `--internal` / `--external`.
    pub side: Option<Side>,
    /// The cutter's cutting diameter (mm): `--tool-diameter`, a tool table, a D register's value.
    pub tool_diameter: Option<f64>,
    /// Thread-form teeth on the cutter, one pitch apart (a comb); 1 for a single-profile cutter.
    pub teeth: u32,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            eps: 0.001,
            side: None,
            tool_diameter: None,
            teeth: 1,
        }
    }
}

/// How a fact about a milled thread is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Known {
    /// Given with the command (`--internal`, `--tool-diameter`).
    Given,
    /// From the cutter compensation's side and the arcs' direction.
    Compensation,
    /// From where the tool came from before the helix.
    Entry,
    /// From the radii of the passes (growing outward: a bore).
    Passes,
}

/// The side of the material (internal or external) as each source tells it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Sides {
    pub given: Option<Side>,
    pub compensation: Option<Side>,
    pub entry: Option<Side>,
    pub passes: Option<Side>,
}

impl Sides {
    /// The side, from the first source that tells it: given, the entry (where the tool came
    /// from is where the material is not), the compensation, the passes. Compensation comes after
    /// the entry because it is what a program gets wrong: `check` then names it.
    pub fn decided(&self) -> Option<(Side, Known)> {
        [
            (self.given, Known::Given),
            (self.entry, Known::Entry),
            (self.compensation, Known::Compensation),
            (self.passes, Known::Passes),
        ]
        .into_iter()
        .find_map(|(s, k)| s.map(|s| (s, k)))
    }
}

/// One run of helical moves: a radial pass of one start.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Helix {
    /// The programmed radius (mm) where the run begins, and where it ends (the same but on a
    /// tapered thread's spiral).
    pub radius: f64,
    pub radius_end: f64,
    /// Where the normal axis begins and ends (mm).
    pub from: f64,
    pub to: f64,
    /// Turns made (sweep / 360°).
    pub turns: f64,
    /// Each arc of the run, in order: its advance per turn is the same on a good program.
    pub arcs: Vec<Turn>,
    /// The normal-axis position the helix has at angle 0 of the plane's first axis, modulo the
    /// lead (mm): the start it cuts.
    pub phase: f64,
    /// Which start that is (1-based, in the order first cut).
    pub start_index: u32,
    /// The cutter's diameter when the run began (mm), if known.
    pub cutter: Option<f64>,
    pub clockwise: bool,
    pub comp: Comp,
    /// The feed programmed on the run's first arc.
    pub feed: crate::mill::motion::Feed,
    pub rotation: Rotation,
    pub tool: Option<u32>,
    /// Source lines of the first and last arc.
    pub lines: (u32, u32),
    /// Where the tool came from before the run: the start of the last move that was not part of
    /// a helix (the entry's start).
    #[serde(skip)]
    pub came_from: Option<[f64; 3]>,
    /// The move just before the run (the entry: a straight move or a lead-in arc) and just after
    /// it (the exit).
    #[serde(skip)]
    pub entry: Option<MillMotion>,
    #[serde(skip)]
    pub exit: Option<MillMotion>,
    /// Where the run's first arc begins and its last ends.
    #[serde(skip)]
    pub start: [f64; 3],
    #[serde(skip)]
    pub end: [f64; 3],
}

/// One arc of a helix.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Turn {
    /// Along the axis (mm, signed) and in turns (sweep / 360°).
    pub advance: f64,
    pub turns: f64,
    pub line: u32,
}

impl Turn {
    pub fn lead(&self) -> f64 {
        self.advance.abs() / self.turns
    }
}

impl Helix {
    /// The advance per turn over the whole run.
    /// The lead most of the run's turns have: the median of its arcs' (weighted by their turns),
    /// so that one arc off the lead does not move it.
    pub fn lead(&self) -> f64 {
        let mut leads: Vec<(f64, f64)> = self.arcs.iter().map(|a| (a.lead(), a.turns)).collect();
        leads.sort_by(|a, b| a.0.total_cmp(&b.0));
        let half = leads.iter().map(|l| l.1).sum::<f64>() / 2.0;
        let mut seen = 0.0;
        for (lead, turns) in &leads {
            seen += turns;
            if seen >= half {
                return *lead;
            }
        }
        (self.to - self.from).abs() / self.turns
    }
}

/// A thread made of helices about one axis.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MilledThread {
    pub plane: Plane,
    /// The axis' position on the plane's two axes (mm): X and Y in G17.
    pub axis: [f64; 2],
    /// Advance per turn (mm).
    pub lead: f64,
    pub starts: u32,
    /// `lead / starts` (mm).
    pub pitch: f64,
    pub hand: Hand,
    pub direction: Direction,
    pub side: Option<(Side, Known)>,
    /// What each way of knowing the side says.
    pub sides: Sides,
    /// Climb milling (else conventional), when the spindle's rotation is known.
    pub climb: Option<bool>,
    /// The runs in program order.
    pub helices: Vec<Helix>,
    /// The thread's extent along its axis (mm), the teeth of a comb above the programmed point
    /// included.
    pub from: f64,
    pub to: f64,
    /// The diameter the last pass cuts (an internal thread's major diameter, an external one's
    /// minor), when it follows (compensation, or the cutter's diameter).
    pub root_diameter: Option<f64>,
}

impl MilledThread {
    /// The distinct radii, in the order first cut: the radial passes.
    pub fn pass_radii(&self, eps: f64) -> Vec<f64> {
        let mut radii: Vec<f64> = Vec::new();
        for h in &self.helices {
            if !radii.iter().any(|r| (r - h.radius).abs() <= eps) {
                radii.push(h.radius);
            }
        }
        radii
    }
}

/// Finds milled threads in a stream of moves: push every move, then [`Recogniser::finish`].
pub struct Recogniser {
    options: Options,
    /// The run being built.
    run: Option<Helix>,
    run_key: Option<RunKey>,
    /// The thread being built.
    thread: Option<Building>,
    /// Where the tool was before the current non-helix moves began (the entry's start).
    last_off_helix: Option<[f64; 3]>,
    /// The move pushed before the current one.
    prev: Option<MillMotion>,
}

/// What every arc of one run shares.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RunKey {
    plane: Plane,
    axis: [f64; 2],
    radius: f64,
    clockwise: bool,
    /// The normal axis' direction of travel: +1 or −1.
    rising: f64,
}

struct Building {
    key: RunKey,
    helices: Vec<Helix>,
}

impl Recogniser {
    pub fn new(options: Options) -> Recogniser {
        Recogniser {
            options,
            run: None,
            run_key: None,
            thread: None,
            last_off_helix: None,
            prev: None,
        }
    }

    /// The cutter's diameter from the next move on (a tool change, a D register's value).
    pub fn set_tool_diameter(&mut self, d: Option<f64>) {
        self.options.tool_diameter = d;
    }

    /// One move; returns a thread that this move showed to be complete.
    pub fn push(&mut self, m: &MillMotion) -> Option<MilledThread> {
        let done = self.take(m);
        self.prev = Some(*m);
        done
    }

    fn take(&mut self, m: &MillMotion) -> Option<MilledThread> {
        let Some((key, end_radius, sweep)) = self.helical(m) else {
            let done = self.end_run(Some(m));
            if self.run.is_none() {
                self.last_off_helix = Some(m.from);
            }
            let tool_changed = self
                .thread
                .as_ref()
                .and_then(|t| t.helices.last())
                .is_some_and(|h| h.tool != m.state.tool);
            return done.or_else(|| tool_changed.then(|| self.take_thread()).flatten());
        };
        let eps = self.options.eps;
        let same_run = self
            .run_key
            .is_some_and(|k| same_key(&k, &key, eps) && self.continues(m));
        let mut done = None;
        if !same_run {
            done = self.end_run(Some(m));
            self.start_run(m, key);
        }
        let (_, _, n) = key.plane.axes();
        // The next arc of the run begins at the radius this one ends on.
        if let Some(k) = &mut self.run_key {
            k.radius = end_radius;
        }
        let run = self.run.as_mut().expect("a run was started");
        run.radius_end = end_radius;
        run.end = m.to;
        let turns = sweep.abs() / std::f64::consts::TAU;
        run.turns += turns;
        run.to = m.to[n];
        run.arcs.push(Turn {
            advance: m.to[n] - m.from[n],
            turns,
            line: m.line,
        });
        run.lines.1 = m.line;
        done
    }

    /// The threads still being built (the last run may end one and begin another).
    pub fn finish(mut self) -> Vec<MilledThread> {
        let done = self.end_run(None);
        done.into_iter().chain(self.take_thread()).collect()
    }

    /// An arc that advances along its normal axis: its run's key (with the radius it begins on),
    /// the radius it ends on, and its sweep.
    fn helical(&self, m: &MillMotion) -> Option<(RunKey, f64, f64)> {
        let MillKind::Arc {
            centre,
            plane,
            clockwise,
            ..
        } = m.kind
        else {
            return None;
        };
        let (radius, sweep) = m.sweep(self.options.eps)?;
        let (a, b, n) = plane.axes();
        let advance = m.to[n] - m.from[n];
        if advance.abs() <= self.options.eps || radius <= self.options.eps {
            return None;
        }
        let key = RunKey {
            plane,
            axis: [centre[a], centre[b]],
            radius,
            clockwise,
            rising: advance.signum(),
        };
        let end_radius = (m.to[a] - centre[a]).hypot(m.to[b] - centre[b]);
        Some((key, end_radius, sweep))
    }

    /// The arc begins where the run ended.
    fn continues(&self, m: &MillMotion) -> bool {
        let Some(run) = &self.run else { return false };
        let Some(key) = self.run_key else {
            return false;
        };
        let (_, _, n) = key.plane.axes();
        (m.from[n] - run.to).abs() <= self.options.eps
    }

    fn start_run(&mut self, m: &MillMotion, key: RunKey) {
        let (a, b, n) = key.plane.axes();
        let angle = (m.from[b] - key.axis[1]).atan2(m.from[a] - key.axis[0]);
        self.run_key = Some(key);
        self.run = Some(Helix {
            radius: key.radius,
            radius_end: key.radius,
            from: m.from[n],
            to: m.from[n],
            turns: 0.0,
            arcs: Vec::new(),
            phase: 0.0,
            start_index: 1,
            cutter: self.options.tool_diameter,
            clockwise: key.clockwise,
            comp: m.state.comp,
            feed: m.state.feed,
            rotation: m.state.rotation,
            tool: m.state.tool,
            lines: (m.line, m.line),
            came_from: self.last_off_helix,
            entry: self.prev,
            exit: None,
            start: m.from,
            end: m.from,
        });
        // The phase is fixed once the run's lead is known (end_run); keep the start's angle in
        // it meanwhile.
        if let Some(run) = &mut self.run {
            run.phase = angle;
        }
    }

    /// Ends the current run: it joins the thread being built, or ends that thread and starts
    /// another (returned).
    fn end_run(&mut self, next: Option<&MillMotion>) -> Option<MilledThread> {
        let mut run = self.run.take()?;
        run.exit = next.copied();
        let key = self.run_key.take().expect("a run has its key");
        if run.turns < MIN_TURNS {
            // A lead-in or lead-out arc, or a ramp: part of the way in or out, not a thread.
            self.last_off_helix = Some(run.start);
            return None;
        }
        let lead = run.lead();
        // Along the helix z = z0 + h·lead·(θ − θ0)/2π with h = +1 when the normal axis rises
        // as the angle grows (counter-clockwise): the value at θ = 0 is the start it cuts.
        let ccw = if key.clockwise { -1.0 } else { 1.0 };
        let h = ccw * key.rising;
        let at_zero = run.from - h * lead * run.phase / std::f64::consts::TAU;
        run.phase = at_zero.rem_euclid(lead);
        let eps = self.options.eps;
        let joins = self.thread.as_ref().is_some_and(|t| {
            let first = &t.helices[0];
            same_axis(&t.key, &key, eps)
                && (first.lead() - lead).abs() <= eps * 2.0
                && hand_of(&t.key) == hand_of(&key)
                && first.tool == run.tool
        });
        let done = if joins { None } else { self.take_thread() };
        self.last_off_helix = Some(run.end);
        match &mut self.thread {
            Some(t) => t.helices.push(run),
            None => {
                self.thread = Some(Building {
                    key,
                    helices: vec![run],
                })
            }
        }
        done
    }

    fn take_thread(&mut self) -> Option<MilledThread> {
        let b = self.thread.take()?;
        Some(describe(b, &self.options))
    }
}

fn same_axis(k: &RunKey, other: &RunKey, eps: f64) -> bool {
    k.plane == other.plane
        && (k.axis[0] - other.axis[0]).abs() <= eps
        && (k.axis[1] - other.axis[1]).abs() <= eps
}

fn same_key(k: &RunKey, other: &RunKey, eps: f64) -> bool {
    same_axis(k, other, eps)
        && (k.radius - other.radius).abs() <= eps
        && k.clockwise == other.clockwise
        && k.rising == other.rising
}

fn hand_of(k: &RunKey) -> Hand {
    let ccw = !k.clockwise;
    if ccw == (k.rising > 0.0) {
        Hand::Right
    } else {
        Hand::Left
    }
}

/// A thread's facts from its runs.
fn describe(b: Building, o: &Options) -> MilledThread {
    let key = b.key;
    let mut helices = b.helices;
    let lead = helices[0].lead();
    let starts = count_starts(&mut helices, lead, o.eps);
    let pitch = lead / f64::from(starts);
    let direction = if key.rising > 0.0 {
        Direction::BottomUp
    } else {
        Direction::TopDown
    };
    let sides = side_of(&helices, &key, o);
    let side = sides.decided();
    let (lo, hi) = helices.iter().fold((f64::MAX, f64::MIN), |(lo, hi), h| {
        (lo.min(h.from.min(h.to)), hi.max(h.from.max(h.to)))
    });
    let comb = f64::from(o.teeth.max(1) - 1) * pitch;
    let last = helices.last().expect("a thread has a run");
    let root_diameter = side.and_then(|(s, _)| root_of(last, s, o));
    let climb = side.and_then(|(s, _)| climbs(s, key.clockwise, last.rotation));
    MilledThread {
        plane: key.plane,
        axis: key.axis,
        lead,
        starts,
        pitch,
        hand: hand_of(&key),
        direction,
        side,
        climb,
        from: hi + comb,
        to: lo,
        root_diameter,
        sides,
        helices,
    }
}

/// Distinct phases of the helices along the axis, modulo the lead.
/// Each helix's start (1-based, in the order first cut), and how many there are.
fn count_starts(helices: &mut [Helix], lead: f64, eps: f64) -> u32 {
    let mut phases: Vec<f64> = Vec::new();
    for h in helices {
        let close = |p: &f64| {
            let d = (p - h.phase).rem_euclid(lead);
            d.min(lead - d) <= eps * 4.0
        };
        let k = match phases.iter().position(close) {
            Some(k) => k,
            None => {
                phases.push(h.phase);
                phases.len() - 1
            }
        };
        h.start_index = u32::try_from(k + 1).unwrap_or(u32::MAX);
    }
    u32::try_from(phases.len()).unwrap_or(u32::MAX).max(1)
}

fn side_of(helices: &[Helix], key: &RunKey, o: &Options) -> Sides {
    let first = &helices[0];
    let ccw = !key.clockwise;
    let compensation = match first.comp {
        Comp::Left { .. } if ccw => Some(Side::Internal),
        Comp::Left { .. } => Some(Side::External),
        Comp::Right { .. } if ccw => Some(Side::External),
        Comp::Right { .. } => Some(Side::Internal),
        Comp::Off => None,
    };
    let outward = |inward: bool| {
        if inward {
            Side::Internal
        } else {
            Side::External
        }
    };
    let entry = first.came_from.and_then(|p| {
        let (a, b, _) = key.plane.axes();
        let r = (p[a] - key.axis[0]).hypot(p[b] - key.axis[1]);
        ((r - first.radius).abs() > o.eps).then(|| outward(r < first.radius))
    });
    let (r0, r1) = (first.radius, helices[helices.len() - 1].radius);
    let passes = ((r1 - r0).abs() > o.eps).then(|| outward(r1 > r0));
    Sides {
        given: o.side,
        compensation,
        entry,
        passes,
    }
}

/// The diameter the helix cuts: the path itself under compensation, else the tool centre's
/// radius plus (a bore) or less (a cylinder) the cutter's radius.
fn root_of(h: &Helix, side: Side, o: &Options) -> Option<f64> {
    match h.comp {
        Comp::Left { .. } | Comp::Right { .. } => Some(2.0 * h.radius),
        Comp::Off => {
            let d = h.cutter.or(o.tool_diameter)?;
            Some(match side {
                Side::Internal => 2.0 * h.radius + d,
                Side::External => 2.0 * h.radius - d,
            })
        }
    }
}

/// Climb milling: with the spindle clockwise (M3), counter-clockwise inside a bore, clockwise
/// round a cylinder; the reverse with M4.
fn climbs(side: Side, clockwise: bool, rotation: Rotation) -> Option<bool> {
    let climb_m3 = match side {
        Side::Internal => !clockwise,
        Side::External => clockwise,
    };
    match rotation {
        Rotation::Cw => Some(climb_m3),
        Rotation::Ccw => Some(!climb_m3),
        Rotation::Stopped => None,
    }
}

/// Every milled thread of a sequence of moves.
pub fn threads<'a>(
    moves: impl IntoIterator<Item = &'a MillMotion>,
    o: Options,
) -> Vec<MilledThread> {
    let mut r = Recogniser::new(o);
    let mut out: Vec<MilledThread> = moves.into_iter().filter_map(|m| r.push(m)).collect();
    out.extend(r.finish());
    out
}

/// Moves for tests: straight lines and helices built by hand.
#[cfg(test)]
pub(crate) mod testing {
    use super::*;
    use crate::mill::motion::{Feed, State};

    pub fn state(comp: Comp) -> State {
        State {
            feed: Feed::PerMinute(100.0),
            rpm: Some(1000.0),
            rotation: Rotation::Cw,
            tool: Some(1),
            length_offset: Some(1),
            comp,
            units: crate::units::Units::Mm,
        }
    }

    pub fn line(from: [f64; 3], to: [f64; 3], comp: Comp) -> MillMotion {
        MillMotion {
            kind: MillKind::Feed,
            from,
            to,
            state: state(comp),
            line: 0,
        }
    }

    /// Full turns about (cx, cy) at radius r from z0, `advance` per turn (signed).
    pub fn helix(
        c: [f64; 2],
        r: f64,
        z0: f64,
        advance: f64,
        turns: u32,
        cw: bool,
        comp: Comp,
    ) -> Vec<MillMotion> {
        (0..turns)
            .map(|k| {
                let z = z0 + advance * f64::from(k);
                MillMotion {
                    kind: MillKind::Arc {
                        centre: [c[0], c[1], z],
                        plane: Plane::Xy,
                        clockwise: cw,
                        turns: 0,
                    },
                    from: [c[0] + r, c[1], z],
                    to: [c[0] + r, c[1], z + advance],
                    state: state(comp),
                    line: 10 + k,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{helix, line, state};
    use super::*;
    use crate::mill::profile::MillProfile;
    use crate::mill::readback::{self, SegKind};
    use crate::mill::request::Request;
    use crate::units::Units;

    #[test]
    fn an_internal_thread_milled_bottom_up_without_compensation() {
        // M20x2.5 with a 12 mm cutter: the tool centre at R = (20 − 12)/2 = 4, entered from the
        // axis; four G3 turns rising 2.5 each from Z-10.
        let mut moves = vec![line([0.0, 0.0, -10.0], [4.0, 0.0, -10.0], Comp::Off)];
        moves.extend(helix([0.0, 0.0], 4.0, -10.0, 2.5, 4, false, Comp::Off));
        let o = Options {
            tool_diameter: Some(12.0),
            ..Options::default()
        };
        let t = threads(&moves, o);
        assert_eq!(t.len(), 1);
        let t = &t[0];
        assert!((t.lead - 2.5).abs() < 1e-9 && t.starts == 1 && (t.pitch - 2.5).abs() < 1e-9);
        assert_eq!(t.hand, Hand::Right, "G3 rising: right hand");
        assert_eq!(t.direction, Direction::BottomUp);
        assert_eq!(t.side, Some((Side::Internal, Known::Entry)));
        assert_eq!(t.climb, Some(true), "G3 inside a bore with M3 climbs");
        assert!((t.root_diameter.unwrap() - 20.0).abs() < 1e-9, "2·4 + 12");
        assert!((t.from - 0.0).abs() < 1e-9 && (t.to + 10.0).abs() < 1e-9);
        assert_eq!(t.helices[0].lines, (10, 13));
    }

    #[test]
    fn hand_from_the_arc_direction_and_the_advance() {
        // G2 falling: right hand (top-down); G2 rising and G3 falling: left hand.
        for (cw, adv, hand) in [
            (true, -1.5, Hand::Right),
            (true, 1.5, Hand::Left),
            (false, -1.5, Hand::Left),
            (false, 1.5, Hand::Right),
        ] {
            let t = threads(
                &helix([5.0, 5.0], 3.0, 0.0, adv, 3, cw, Comp::Off),
                Options::default(),
            );
            assert_eq!(t.len(), 1);
            assert_eq!(t[0].hand, hand, "cw {cw} advance {adv}");
            assert!((t[0].lead - 1.5).abs() < 1e-9);
            assert_eq!(t[0].axis, [5.0, 5.0]);
        }
    }

    #[test]
    fn the_side_from_the_compensation() {
        // G41 keeps the tool left of the path: inside a counter-clockwise circle (a bore), outside
        // a clockwise one. The path is then the finished contour: its diameter is the root.
        let left = Comp::Left { d: Some(4) };
        let t = threads(
            &helix([0.0, 0.0], 10.0, -10.0, 2.5, 4, false, left),
            Options::default(),
        );
        assert_eq!(t[0].side, Some((Side::Internal, Known::Compensation)));
        assert!((t[0].root_diameter.unwrap() - 20.0).abs() < 1e-9);
        let t = threads(
            &helix([0.0, 0.0], 8.5, 0.0, -2.5, 4, true, left),
            Options::default(),
        );
        assert_eq!(t[0].side, Some((Side::External, Known::Compensation)));
        assert_eq!(t[0].climb, Some(true), "G2 round a cylinder with M3 climbs");
        let right = Comp::Right { d: None };
        let t = threads(
            &helix([0.0, 0.0], 8.5, 0.0, 2.5, 4, false, right),
            Options::default(),
        );
        assert_eq!(t[0].side, Some((Side::External, Known::Compensation)));
        assert_eq!(
            t[0].climb,
            Some(false),
            "G3 round a cylinder with M3: conventional"
        );
    }

    #[test]
    fn an_external_thread_entered_from_outside_with_the_cutter_known() {
        // Minor diameter 17 with a 10 mm cutter: centre radius 8.5 + 5 = 13.5; entered from X20.
        let mut moves = vec![line([20.0, 0.0, 0.0], [13.5, 0.0, 0.0], Comp::Off)];
        moves.extend(helix([0.0, 0.0], 13.5, 0.0, -2.0, 5, true, Comp::Off));
        let o = Options {
            tool_diameter: Some(10.0),
            ..Options::default()
        };
        let t = &threads(&moves, o)[0];
        assert_eq!(t.side, Some((Side::External, Known::Entry)));
        assert!(
            (t.root_diameter.unwrap() - 17.0).abs() < 1e-9,
            "2·13.5 − 10"
        );
    }

    #[test]
    fn unequal_turns_are_kept_for_the_check() {
        let mut moves = helix([0.0, 0.0], 4.0, -10.0, 2.5, 3, false, Comp::Off);
        // The third turn rises 2.4: a wrong Z on one block.
        moves[2].to[2] = moves[2].from[2] + 2.4;
        let t = &threads(&moves, Options::default())[0];
        let l = &t.helices[0].arcs;
        assert_eq!(l.len(), 3);
        assert!((l[0].lead() - 2.5).abs() < 1e-9 && (l[2].lead() - 2.4).abs() < 1e-9);
    }

    #[test]
    fn two_holes_are_two_threads_and_a_plain_circle_is_none() {
        let mut moves = helix([0.0, 0.0], 4.0, -10.0, 2.5, 4, false, Comp::Off);
        moves.push(line([4.0, 0.0, 0.0], [50.0, 0.0, 0.0], Comp::Off));
        // A circle without advance (a chamfer or a bore interpolated): not a thread.
        let mut flat = helix([50.0, 0.0], 4.0, -1.0, 0.0, 1, false, Comp::Off);
        flat[0].to[2] = -1.0;
        moves.extend(flat);
        moves.extend(helix([50.0, 0.0], 4.0, -10.0, 2.5, 4, false, Comp::Off));
        let t = threads(&moves, Options::default());
        assert_eq!(t.len(), 2);
        assert_eq!(t[1].axis, [50.0, 0.0]);
    }

    /// `threadcut mill`'s program read back (the small reader) as the recogniser's moves.
    fn milled(r: &Request) -> (crate::mill::Plan, Vec<MilledThread>) {
        let m = r.prepare().expect("a valid request");
        let mut out = Vec::new();
        m.write_gcode(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        let p = readback::read(&text).unwrap();
        let to_mm = |v: [f64; 3]| v.map(|x| p.units.unwrap_or(Units::Mm).to_mm(x));
        let moves: Vec<MillMotion> = p
            .segments
            .iter()
            .map(|s| {
                let (from, to) = (to_mm(s.from), to_mm(s.to));
                let comp = match s.comp {
                    None => Comp::Off,
                    Some(crate::mill::CompSide::Left) => Comp::Left { d: None },
                    Some(crate::mill::CompSide::Right) => Comp::Right { d: None },
                };
                let kind = match s.kind {
                    SegKind::Rapid => MillKind::Rapid,
                    SegKind::Feed => MillKind::Feed,
                    SegKind::Arc { center, cw } => {
                        let c = to_mm([center[0], center[1], s.from[2]]);
                        MillKind::Arc {
                            centre: c,
                            plane: Plane::Xy,
                            clockwise: cw,
                            turns: 0,
                        }
                    }
                };
                MillMotion {
                    kind,
                    from,
                    to,
                    state: state(comp),
                    line: s.line as u32,
                }
            })
            .collect();
        let decimals = match m.options.units {
            Units::Mm => m.profile.decimals_mm,
            Units::Inch => m.profile.decimals_inch,
        };
        let eps = m.options.units.to_mm(10f64.powi(-(decimals as i32)));
        let o = Options {
            eps,
            tool_diameter: Some(m.plan.tool_radius * 2.0),
            teeth: m.plan.teeth,
            side: None,
        };
        (m.plan, threads(&moves, o))
    }

    #[test]
    fn threadcut_mill_programs_read_back_as_the_thread_asked_for() {
        use crate::mill::Comp as MComp;
        let names = ["M20x2.5", "M12x1.75", "1/2-13 UNC", "M8x1.25-LH"];
        for (k, name) in names.iter().enumerate() {
            for side in [Side::Internal, Side::External] {
                for (passes, starts, comp) in [
                    (1, 1, MComp::Controller),
                    (3, 2, MComp::Off),
                    (2, 1, MComp::Off),
                ] {
                    let tool = if name.starts_with("M8") { 5.0 } else { 8.0 };
                    let tool = if name.contains("UNC") {
                        tool / 25.4
                    } else {
                        tool
                    };
                    let mut r = Request::new(
                        name,
                        side,
                        if name.contains("UNC") { 0.75 } else { 16.0 },
                        tool,
                        300.0,
                        MillProfile::built_in(["fanuc-mill", "centroid", "linuxcnc-mill"][k % 3])
                            .unwrap(),
                    );
                    if name.ends_with("LH") {
                        r.thread = name.trim_end_matches("-LH").to_string();
                        r.hand = Hand::Left;
                    }
                    r.passes = passes;
                    r.starts = starts;
                    r.comp = comp;
                    let (plan, t) = milled(&r);
                    let what = format!("{name} {side:?} passes {passes} starts {starts} {comp:?}");
                    assert_eq!(t.len(), 1, "{what}: {t:#?}");
                    let t = &t[0];
                    let eps = 0.01;
                    assert!(
                        (t.lead - plan.lead).abs() < eps,
                        "{what}: lead {} vs {}",
                        t.lead,
                        plan.lead
                    );
                    assert_eq!(t.starts, plan.starts, "{what}");
                    assert!((t.pitch - plan.pitch).abs() < eps, "{what}");
                    assert_eq!(t.hand, plan.hand, "{what}");
                    assert_eq!(t.direction, plan.direction, "{what}");
                    assert_eq!(t.side.map(|s| s.0), Some(plan.side), "{what}");
                    assert_eq!(t.pass_radii(eps).len(), plan.pass_radii.len(), "{what}");
                    let root = 2.0 * plan.final_radius;
                    assert!(
                        (t.root_diameter.unwrap() - root).abs() < eps,
                        "{what}: root {:?} vs {root}",
                        t.root_diameter
                    );
                    assert_eq!(t.helices.len() as u32, passes * starts, "{what}");
                    let last_start = t.helices.iter().map(|h| h.start_index).max();
                    assert_eq!(last_start, Some(starts), "{what}");
                }
            }
        }
    }
}
