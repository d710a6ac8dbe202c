//! Every thread a program cuts: each threading cycle, and each thread written as plain synchronised
//! moves — hand-written G32 passes, LinuxCNC's G33 K, APT's COUPLE moves, and the passes of
//! single-pass box cycles such as a modal G92 — so that `passes`, `check` and `plot` treat them
//! alike.
//!
//! A **pass** is a chain of consecutive synchronised moves (a thread move, its pull-out, an entry
//! ramp). Consecutive passes with the same lead, along the same axis in the same direction, whose
//! starts and ends each lie within one lead of the first pass's, are **one thread**: the passes of
//! a groove, shifted by flank infeed or backed-off starts. Its depths are measured from the crest
//! when the caller knows it (the stock's diameter, a standard thread's crest), else from the first
//! pass; its lateral offsets from the first pass's start. The moves between passes belong to the
//! thread's toolpath: those up to the return to the thread's start point close a pass, the rest
//! open the next one (as a cycle's box path does). The approach is the last rapid move before the
//! first pass; after the last pass the rapid moves up to the return to the start point follow.
//!
//! Decisions and their tests: `docs/simulation.md`, "Threads written as plain moves".

use std::io::BufRead;

use crate::diag::{Diagnostic, Span};
use crate::gcode::{Line, MotionMode, PlainMove};
use crate::machine::Machine;
use crate::program::{self, Error, Event, Summary};
use crate::thread::{
    area, DepthLaw, Entry, Exit, FinishPosition, Geometry, Infeed, Job, Lead, Pass, PassKind,
    PassPlan, Retract, ReturnPath, Side,
};
use crate::toolpath::{self, Motion, MotionKind, Toolpath};
use crate::units::{Pos, Units};

/// Two leads closer than this (mm per revolution) are the same lead: leads are read from the
/// same words, so real differences are far larger.
pub const LEAD_TOLERANCE: f64 = 1e-6;
/// Two points closer than this (mm) are the same point (the return to a start point).
pub const POINT_TOLERANCE: f64 = 1e-6;
/// The tool angle assumed for a thread written as plain moves, which does not state one: the
/// 60° of ISO metric and Unified threads.
pub const ASSUMED_TOOL_ANGLE: f64 = 60.0;
/// At most this many moves between two passes of one thread: a longer stretch of other work ends
/// the thread (memory stays bounded on long programs).
pub const MAX_BETWEEN: usize = 24;

/// Where a thread's passes come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Origin {
    /// One threading cycle: its job, pass table and toolpath are the cycle's.
    Cycle,
    /// Passes written as plain synchronised moves (or as single-pass cycles, `from_cycles`).
    Moves {
        /// Depths are measured from the crest the caller gave; otherwise from the first pass.
        crest_known: bool,
        /// The passes are the single-pass cycles (a modal G92) of these lines.
        from_cycles: bool,
        first_line: u32,
        last_line: u32,
    },
}

/// One thread of a program.
#[derive(Clone, Debug)]
pub struct Thread {
    /// The model: a cycle's own job, or for passes written as moves one that describes them
    /// (radial infeed, explicit depths: use `passes`, not `job.passes()`).
    pub job: Job,
    pub passes: Vec<Pass>,
    pub path: Toolpath,
    pub origin: Origin,
    /// Where each pass is written (its first synchronised move; a cycle's block for every pass).
    pub pass_spans: Vec<Span>,
    /// X as the program writes it at the thread.
    pub diameter_x: bool,
    /// Passes written after a cycle that continue its thread (a spring pass as a plain move, a
    /// single-pass cycle over the same span): they follow the cycle's passes in `passes`.
    pub extra_passes: u32,
    /// The axes (X, Z) of the start point that were not known (a cycle shown without the lines
    /// before it, read with [`program::Start::Unstated`]): the Z where each pass starts (on Z), the
    /// retract X and the side (on X) are not known. Both false for every other thread.
    pub unknown_start: [bool; 2],
}

impl Thread {
    /// A cycle's thread: its pass table and toolpath.
    pub fn from_cycle(job: Job, diameter_x: bool) -> crate::diag::Result<Thread> {
        let passes = job.passes()?;
        let path = toolpath::build_with(&job, &passes)?;
        let pass_spans = vec![job.span; passes.len()];
        Ok(Thread {
            job,
            passes,
            path,
            origin: Origin::Cycle,
            pass_spans,
            diameter_x,
            extra_passes: 0,
            unknown_start: [false; 2],
        })
    }

    /// Whether depths are measured from a known crest (a cycle's, or one the caller gave).
    pub fn crest_known(&self) -> bool {
        match self.origin {
            Origin::Cycle => true,
            Origin::Moves { crest_known, .. } => crest_known,
        }
    }

    /// The span of pass `n` (1-based).
    pub fn pass_span(&self, n: u32) -> Span {
        let i = (n.max(1) - 1) as usize;
        self.pass_spans
            .get(i)
            .or(self.pass_spans.last())
            .copied()
            .unwrap_or(self.job.span)
    }

    /// How the thread is named in tables and plots: `fanuc cycle`, `G32 passes (lines 8–47)`.
    pub fn describe(&self) -> String {
        match self.origin {
            Origin::Cycle if self.extra_passes > 0 => format!(
                "{} cycle and {} more pass{} after it",
                self.job.controller,
                self.extra_passes,
                if self.extra_passes == 1 { "" } else { "es" }
            ),
            Origin::Cycle => format!("{} cycle", self.job.controller),
            Origin::Moves {
                from_cycles,
                first_line,
                last_line,
                ..
            } => format!(
                "{} {} as one thread ({})",
                self.passes.len(),
                match (from_cycles, self.passes.len()) {
                    (true, 1) => "single-pass cycle",
                    (true, _) => "single-pass cycles",
                    (false, 1) => "synchronised pass",
                    (false, _) => "synchronised passes",
                },
                // A loop runs its passes from the same lines.
                if first_line == last_line {
                    format!("line {first_line}")
                } else {
                    format!("lines {first_line}–{last_line}")
                }
            ),
        }
    }
}

/// A move of the program, for [`Collector::motion`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    pub kind: MotionKind,
    pub from: Pos,
    pub to: Pos,
    pub line: u32,
    /// Where the move is written (its G word, or the block).
    pub span: Span,
}

/// What the program says around a thread: its units, X mode and controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setting {
    pub units: Units,
    pub diameter_x: bool,
    pub controller: &'static str,
}

/// The crest a thread written as moves is measured from, when the caller knows it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Crest {
    /// The stock's diameter, in the program's units at the thread.
    Stock(f64),
    /// A standard thread's crest diameters (mm): the major for an external thread, the minor for
    /// an internal one.
    Standard { external: f64, internal: f64 },
}

/// What the collector hands out: a thread with the caller's context at each of its passes (a
/// cycle's once, for all its passes; then one for each pass written after it; never empty), or a
/// cycle that cannot be planned (its error, at its block).
pub enum Found<C> {
    Thread(Box<Thread>, Vec<C>),
    Failed {
        job: Box<Job>,
        error: Diagnostic,
        ctx: C,
    },
}

/// One pass being read: its synchronised moves and the non-synchronised moves before it.
struct PassMoves {
    before: Vec<Move>,
    chain: Vec<Move>,
}

/// A thread being read.
struct Building<C> {
    /// The caller's context at each pass.
    ctxs: Vec<C>,
    setting: Setting,
    approach: Option<Move>,
    passes: Vec<PassMoves>,
    from_cycles: bool,
    key: Key,
}

/// A cycle's thread that passes written after it may still continue.
struct Open<C> {
    thread: Thread,
    /// The caller's context at the cycle, then at each pass written after it.
    ctxs: Vec<C>,
    key: Key,
    units: Units,
}

/// What makes passes one thread.
#[derive(Clone, Copy, Debug)]
struct Key {
    lead: f64,
    face: bool,
    /// +1 when the thread runs toward + along its long axis.
    dir: f64,
    start: f64,
    end: f64,
    /// The spindle angle the thread starts at (degrees): passes at another angle cut another
    /// start of a multi-start thread, a thread of its own here as a cycle's second start is.
    phase: f64,
}

impl Key {
    fn of(chain: &[Move]) -> Key {
        let main = main_segment(chain);
        let d = main.to.minus(main.from);
        let face = d.x.abs() > d.z.abs();
        let long = |p: Pos| if face { p.x } else { p.z };
        let (lead, phase) = match main.kind {
            MotionKind::Thread {
                lead, phase_deg, ..
            } => (lead, phase_deg),
            _ => (0.0, 0.0),
        };
        let first = chain.first().map_or(main.from, |m| m.from);
        let last = chain.last().map_or(main.to, |m| m.to);
        Key {
            lead,
            face,
            dir: (long(main.to) - long(main.from)).signum(),
            start: long(first),
            end: long(last),
            phase,
        }
    }

    fn same_thread(&self, other: &Key) -> bool {
        (self.lead - other.lead).abs() <= LEAD_TOLERANCE
            && self.face == other.face
            && self.dir == other.dir
            && (self.start - other.start).abs() < self.lead
            && (self.end - other.end).abs() < self.lead
            && crate::translate::same_angle(self.phase, other.phase)
    }
}

/// Where a thread's groove lies, to tell whether a later thread cuts the same groove
/// ([`Thread::first_groove`], [`Thread::last_groove`]): the same lead, axis, direction and start
/// angle, its start and end each within one lead — as passes are joined into one thread.
#[derive(Clone, Copy, Debug)]
pub struct Groove(Key);

impl Groove {
    /// Whether `later` cuts the same groove (its passes would be passes of this thread).
    pub fn same(&self, later: &Groove) -> bool {
        self.0.same_thread(&later.0)
    }
}

impl Thread {
    /// The groove of the thread's first pass.
    pub fn first_groove(&self) -> Option<Groove> {
        let n = self.passes.first()?.n;
        chain_of(&self.path, n).map(|c| Groove(Key::of(&c)))
    }

    /// The groove of the thread's last pass.
    pub fn last_groove(&self) -> Option<Groove> {
        let n = self.passes.last()?.n;
        chain_of(&self.path, n).map(|c| Groove(Key::of(&c)))
    }
}

/// The longest synchronised move of a pass along the axis it mostly travels: the thread itself,
/// not its ramp or pull-out.
fn main_segment(chain: &[Move]) -> Move {
    let travel = |m: &Move| {
        let d = m.to.minus(m.from);
        d.x.abs().max(d.z.abs())
    };
    chain
        .iter()
        .copied()
        .max_by(|a, b| travel(a).total_cmp(&travel(b)))
        .expect("a pass has at least one move")
}

/// Reads a program's moves and cycles, in order, into threads. `C` is the caller's context at a
/// thread's first pass (the spindle speed, for `check`).
pub struct Collector<C> {
    /// The crest when the caller knows it: depths of passes written as moves are measured from it.
    crest: Option<Crest>,
    building: Option<Building<C>>,
    /// The non-synchronised moves since the last pass (only while a thread is being read).
    after: Vec<Move>,
    /// The last non-synchronised move, if nothing synchronised came after it.
    last: Option<Move>,
    chain: Vec<Move>,
    chain_start: Option<(C, Setting, bool)>,
    open: Option<Open<C>>,
    /// The axes of the start not known, of the passes of the thread being read or left open.
    unknown: [bool; 2],
    /// The axes of the next cycle's start not known ([`Collector::start_unknown`]).
    next_unknown: [bool; 2],
}

impl<C: Clone> Collector<C> {
    pub fn new(crest: Option<Crest>) -> Collector<C> {
        Collector {
            crest,
            building: None,
            after: Vec::new(),
            last: None,
            chain: Vec::new(),
            chain_start: None,
            open: None,
            unknown: [false; 2],
            next_unknown: [false; 2],
        }
    }

    /// The axes (X, Z) of the next cycle's start point that were not known
    /// ([`crate::gcode::Modal::assumed`]): its thread says so.
    pub fn start_unknown(&mut self, axes: [bool; 2]) {
        self.next_unknown = axes;
    }

    /// Whether a thread written as moves (or as single-pass cycles) is being read: the moves now
    /// may still belong to its toolpath.
    pub fn is_reading(&self) -> bool {
        self.building.is_some() || !self.chain.is_empty()
    }

    /// A move of the program (or of a single-pass cycle, `from_cycle`). `ctx` gives the caller's
    /// context, asked for when a pass begins.
    pub fn motion(
        &mut self,
        m: Move,
        setting: Setting,
        from_cycle: bool,
        ctx: impl FnOnce() -> C,
        out: &mut dyn FnMut(Found<C>),
    ) {
        if matches!(m.kind, MotionKind::Thread { .. }) {
            if self.chain.is_empty() {
                self.chain_start = Some((ctx(), setting, from_cycle));
            }
            self.chain.push(m);
            return;
        }
        self.end_chain(out);
        self.last = Some(m);
        if self.building.is_some() || self.open.is_some() {
            self.after.push(m);
            if self.after.len() > MAX_BETWEEN {
                self.close(out);
            }
        }
    }

    /// A plain block of a G-code program and its move, if any: a tool change or the program's end
    /// ends the thread being read; a move whose start is not known on an axis it names (the first
    /// positioning, a move after a reference return the profile does not place) comes from where
    /// the program does not say, so it ends the thread being read too, and a synchronised one is
    /// no pass: the warning returned says so.
    pub fn plain(
        &mut self,
        line: &Line,
        mv: Option<PlainMove>,
        setting: Setting,
        ctx: impl FnOnce() -> C,
        out: &mut dyn FnMut(Found<C>),
    ) -> Option<Diagnostic> {
        if ends_thread(line) {
            self.boundary(out);
        }
        let mv = mv?;
        if mv.from.known().is_none() {
            self.boundary(out);
            return (mv.mode == MotionMode::Thread).then(|| thread_from_unknown(line, &mv));
        }
        if let Some(m) = plain_move(line, &mv) {
            self.motion(m, setting, false, ctx, out);
        }
        None
    }

    /// A threading cycle: single-pass cycles (one pass, no depth: a G92) are read as passes, so
    /// that a modal G92's blocks make one thread; any other cycle is a thread of its own.
    pub fn cycle(
        &mut self,
        job: Job,
        diameter_x: bool,
        ctx: impl FnOnce() -> C,
        out: &mut dyn FnMut(Found<C>),
    ) {
        self.end_chain(out);
        let unknown = std::mem::take(&mut self.next_unknown);
        let box_cycle = job.geometry.depth == 0.0
            && matches!(&job.plan.law, DepthLaw::Explicit { depths } if depths.is_empty())
            && job.plan.finish_passes == 1;
        let planned = job
            .passes()
            .and_then(|p| toolpath::build_with(&job, &p).map(|path| (p, path)));
        match planned {
            Ok((passes, path)) => {
                // A single pass (a box cycle; a one-pass cycle that continues a thread) is read as
                // a pass: consecutive ones make one thread, and one after a cycle over the same
                // span continues the cycle's thread.
                let one_pass = passes.len() == 1 && job.lead.starts == 1 && job.lead.dlead == 0.0;
                let continues = one_pass
                    && chain_of(&path, 1).is_some_and(|chain| {
                        let key = Key::of(&chain);
                        self.open.as_ref().is_some_and(|o| o.key.same_thread(&key))
                            || self
                                .building
                                .as_ref()
                                .is_some_and(|b| b.key.same_thread(&key))
                    });
                if one_pass && (box_cycle || continues) {
                    let setting = Setting {
                        units: job.units,
                        diameter_x,
                        controller: job.controller,
                    };
                    let ctx = ctx();
                    for (from, m) in path.segments() {
                        let mv = Move {
                            kind: m.kind,
                            from,
                            to: m.to,
                            line: job.line,
                            span: job.span,
                        };
                        self.motion(mv, setting, box_cycle, || ctx.clone(), out);
                    }
                    // The cycle's path ends back at its start point: its pass is complete.
                    self.end_chain(out);
                    self.unknown = either(self.unknown, unknown);
                    return;
                }
                self.close(out);
                let last = passes.last().map_or(0, |p| p.n);
                let pass_spans = vec![job.span; passes.len()];
                let key = chain_of(&path, last).map(|chain| Key::of(&chain));
                let units = job.units;
                let thread = Thread {
                    job,
                    passes,
                    path,
                    origin: Origin::Cycle,
                    pass_spans,
                    diameter_x,
                    extra_passes: 0,
                    unknown_start: unknown,
                };
                match key {
                    Some(key) => {
                        self.open = Some(Open {
                            thread,
                            ctxs: vec![ctx()],
                            key,
                            units,
                        });
                        self.after.clear();
                        self.last = None;
                    }
                    None => out(Found::Thread(Box::new(thread), vec![ctx()])),
                }
            }
            Err(error) => {
                self.close(out);
                out(Found::Failed {
                    job: Box::new(job),
                    error,
                    ctx: ctx(),
                });
            }
        }
    }

    /// Something that ends a thread: a tool change, the end of the program.
    pub fn boundary(&mut self, out: &mut dyn FnMut(Found<C>)) {
        self.end_chain(out);
        self.close(out);
        self.last = None;
    }

    /// The end of the program.
    pub fn finish(mut self, out: &mut dyn FnMut(Found<C>)) {
        self.boundary(out);
    }

    /// The pass being read is complete: it continues the thread being read, or begins another.
    fn end_chain(&mut self, out: &mut dyn FnMut(Found<C>)) {
        if self.chain.is_empty() {
            return;
        }
        let chain = std::mem::take(&mut self.chain);
        let (ctx, setting, from_cycle) = self.chain_start.take().expect("set with the chain");
        let key = Key::of(&chain);
        if let Some(o) = self.open.as_mut() {
            if o.key.same_thread(&key) && o.units == setting.units {
                let before = std::mem::take(&mut self.after);
                append(&mut o.thread, before, chain);
                o.ctxs.push(ctx);
                return;
            }
        }
        let continues = self.building.as_ref().is_some_and(|b| {
            b.key.same_thread(&key) && b.setting == setting && b.from_cycles == from_cycle
        });
        if continues {
            let before = std::mem::take(&mut self.after);
            if let Some(b) = self.building.as_mut() {
                b.passes.push(PassMoves { before, chain });
                b.ctxs.push(ctx);
            }
            return;
        }
        self.close(out);
        let approach = self.last.filter(|m| {
            m.kind == MotionKind::Rapid && m.to.distance(chain[0].from) <= POINT_TOLERANCE
        });
        self.building = Some(Building {
            ctxs: vec![ctx],
            setting,
            approach,
            passes: vec![PassMoves {
                before: Vec::new(),
                chain,
            }],
            from_cycles: from_cycle,
            key,
        });
        self.after.clear();
    }

    /// The thread being read (or the cycle's thread left open) is complete.
    fn close(&mut self, out: &mut dyn FnMut(Found<C>)) {
        if let Some(mut o) = self.open.take() {
            let after = std::mem::take(&mut self.after);
            let start = o.thread.path.start;
            let n = o.thread.passes.len() as u32;
            if o.thread.extra_passes > 0 {
                settle_appended(&mut o.thread);
                let inward = o.thread.job.geometry.side.infeed();
                for m in &after[..trailing(&after, start, inward)] {
                    o.thread.path.motions.push(Motion {
                        kind: m.kind,
                        to: m.to,
                        pass: n,
                        line: m.line,
                    });
                }
            }
            o.thread.unknown_start = either(o.thread.unknown_start, self.unknown);
            out(Found::Thread(Box::new(o.thread), o.ctxs));
        }
        let unknown = std::mem::take(&mut self.unknown);
        let Some(b) = self.building.take() else {
            self.after.clear();
            return;
        };
        let after = std::mem::take(&mut self.after);
        let thread = build(
            b.passes,
            b.approach,
            after,
            b.setting,
            b.key,
            b.from_cycles,
            self.crest,
        );
        let thread = Thread {
            unknown_start: unknown,
            ..thread
        };
        out(Found::Thread(Box::new(thread), b.ctxs));
    }
}

/// Axis by axis, either not known.
fn either(a: [bool; 2], b: [bool; 2]) -> [bool; 2] {
    [a[0] || b[0], a[1] || b[1]]
}

/// A block that ends a thread being read: a tool change, the end of the program.
pub fn ends_thread(line: &Line) -> bool {
    line.words.iter().any(|w| {
        w.letter == b'T'
            || (w.letter == b'M' && matches!(crate::gcode::reader::g_code(w.value), Some(20 | 300)))
    })
}

/// A plain move as the thread reader takes it: arcs count as feeds. `None` for a canned cycle's
/// words, a thread move without a lead, and a move whose start is not known on an axis it names
/// (see [`Collector::plain`]).
pub fn plain_move(line: &Line, mv: &PlainMove) -> Option<Move> {
    let from = mv.from.known()?;
    let kind = match mv.mode {
        MotionMode::Rapid => MotionKind::Rapid,
        MotionMode::Feed | MotionMode::ArcCw | MotionMode::ArcCcw => MotionKind::Feed,
        MotionMode::Thread => MotionKind::Thread {
            lead: mv.lead?,
            dlead: 0.0,
            // The start angle (Fanuc/Haas Q, Sinumerik SF=): another angle is another start.
            phase_deg: mv.phase_deg,
        },
        MotionMode::Cycle => return None,
    };
    Some(Move {
        kind,
        from,
        to: mv.to,
        line: line.number,
        span: move_span(line),
    })
}

/// Where a move is written: its G word, else the block's first word.
fn move_span(line: &Line) -> Span {
    line.words
        .iter()
        .find(|w| w.letter == b'G')
        .or(line.words.first())
        .map_or(line.span(), |w| w.span)
}

/// The warning for a synchronised move whose start is not known on an axis it names (after a
/// reference return the profile does not place, a move in machine coordinates, at power-on): it
/// cuts from a point the program does not say, so threadcut cannot tell what it cuts.
#[cold]
fn thread_from_unknown(line: &Line, mv: &PlainMove) -> Diagnostic {
    let axes = mv.from.unknown_axes();
    Diagnostic::warning(
        crate::diag::Code::Suspicious,
        move_span(line),
        format!(
            "this synchronised move starts where the tool's {} {} not known: it is not read as a \
             pass, and what it cuts is not checked",
            axes.join(" and "),
            if axes.len() == 1 { "is" } else { "are" }
        ),
    )
    .with_hint("position the tool with G0 X.. Z.. before the thread move")
}

/// Every thread of a G-code program, in order, to `each` (depths from `crest` when given). A
/// cycle that cannot be planned is the run's error, at its block.
pub fn each_gcode<R: BufRead>(
    input: R,
    machine: &Machine,
    crest: Option<Crest>,
    each: impl FnMut(Thread) -> Result<(), Error>,
) -> Result<Summary, Error> {
    each_gcode_with(input, machine, crest, &program::Options::default(), each)
}

/// [`each_gcode`] with the run's options: a program with control flow gives the threads of its
/// execution (a cycle run three times is three threads; passes written as moves inside a loop are
/// read as the loop runs them).
pub fn each_gcode_with<R: BufRead>(
    input: R,
    machine: &Machine,
    crest: Option<Crest>,
    options: &program::Options,
    mut each: impl FnMut(Thread) -> Result<(), Error>,
) -> Result<Summary, Error> {
    let controller = crate::dialect::open(machine).map_err(Error::Setup)?.name();
    let mut collector: Collector<()> = Collector::new(crest);
    let mut queue: Vec<Found<()>> = Vec::new();
    let mut drain = |queue: &mut Vec<Found<()>>| -> Result<(), Error> {
        for f in queue.drain(..) {
            match f {
                Found::Thread(t, _) => each(*t)?,
                Found::Failed { error, .. } => return Err(Error::Input(error)),
            }
        }
        Ok(())
    };
    let mut warnings = Vec::new();
    let mut summary = program::run_with(input, machine, options, |modal, ev| {
        let mut push = |f| queue.push(f);
        match ev {
            Event::Plain { line, mv } => {
                let setting = Setting {
                    units: modal.units,
                    diameter_x: modal.diameter_x,
                    controller,
                };
                if let Some(w) = collector.plain(line, mv, setting, || (), &mut push) {
                    warnings.push(w);
                }
            }
            // A turning cycle is no thread (its moves are not synchronised).
            Event::Settings { .. } | Event::Turning { .. } => {}
            Event::Cycle { job, .. } => {
                collector.start_unknown(modal.assumed);
                collector.cycle(*job, modal.diameter_x, || (), &mut push)
            }
        }
        drain(&mut queue)
    })?;
    collector.finish(&mut |f| queue.push(f));
    drain(&mut queue)?;
    summary.warnings.extend(warnings);
    summary.warnings.sort_by_key(|d| d.span.line);
    Ok(summary)
}

/// Every thread of an APT/CL program, in order, to `each`.
pub fn each_apt<R: BufRead>(
    input: R,
    mut each: impl FnMut(Thread) -> Result<(), Error>,
) -> Result<Summary, Error> {
    let mut collector: Collector<()> = Collector::new(None);
    let mut queue: Vec<Found<()>> = Vec::new();
    let mut drain = |queue: &mut Vec<Found<()>>| -> Result<(), Error> {
        for f in queue.drain(..) {
            match f {
                Found::Thread(t, _) => each(*t)?,
                Found::Failed { error, .. } => return Err(Error::Input(error)),
            }
        }
        Ok(())
    };
    let mut at: Option<Pos> = None;
    let summary = crate::apt::run(input, |interp, ev| {
        let mut push = |f| queue.push(f);
        match ev {
            crate::apt::Event::Move(m) => {
                if let Some(from) = at {
                    let setting = Setting {
                        units: interp.units(),
                        diameter_x: false,
                        controller: "apt",
                    };
                    let mv = Move {
                        kind: m.kind,
                        from,
                        to: m.to,
                        line: m.line,
                        span: Span::new(0, 0, m.line, 1),
                    };
                    collector.motion(mv, setting, false, || (), &mut push);
                }
            }
            crate::apt::Event::Cycle(job) => collector.cycle(*job, false, || (), &mut push),
            crate::apt::Event::End => collector.boundary(&mut push),
            _ => {}
        }
        at = interp.position();
        drain(&mut queue)
    })?;
    collector.finish(&mut |f| queue.push(f));
    drain(&mut queue)?;
    Ok(summary)
}

impl Thread {
    /// What is not known of a thread whose start point was not ([`Thread::unknown_start`]), as a
    /// sentence; `None` when the start is known.
    pub fn start_note(&self) -> Option<String> {
        let [x, z] = self.unknown_start;
        if !x && !z {
            return None;
        }
        let mut unknown = Vec::new();
        if z {
            unknown.push("the Z where each pass starts (the thread's length)");
        }
        if x {
            unknown.push("the X the tool retracts to");
        }
        let axes = match (x, z) {
            (true, true) => "X and Z",
            (true, false) => "X",
            _ => "Z",
        };
        let side = if x {
            "; the thread is read as external (the start X above the thread's X, as the passes' X \
             show): an internal thread needs its start point"
        } else {
            ""
        };
        Some(format!(
            "the start point is not known (the tool's {axes} before the cycle): not known are {}{side}; \
             the depths, increments, lateral offsets and chip areas do not depend on it; \
             give the start point with --start X,Z for the rest",
            unknown.join(" and ")
        ))
    }

    /// The section `passes` cuts for its simulated columns (chip area with the tool's real tip,
    /// share, cutting flank, chip thickness): the thread's own tool angle with `tip` (in program
    /// units). A tool the section cannot draw (a 0° angle, an absurd size) gives `None`, and the
    /// columns stay empty rather than failing a table the controller accepted.
    pub fn simulated(&self, tip: crate::sim::Tip) -> Option<crate::sim::Section> {
        let tool = crate::sim::Tool {
            angle_deg: self.job.tool_angle_deg,
            tip: crate::sim::tip_in_mm(tip, self.job.units),
        };
        crate::sim::section(&self.job, &self.passes, &tool, 0.0).ok()
    }
}

/// One thread as `threadcut passes --json` writes it: the pass rows of
/// [`program::passes_json`] with `source` (`cycle` or `moves`) and `depth_from` (`crest` or
/// `first_pass`).
pub fn passes_json(t: &Thread, section: Option<&crate::sim::Section>) -> serde_json::Value {
    passes_json_first(t, section, usize::MAX)
}

/// [`passes_json`] with the rows of the first `first` passes only (the simulated columns from the
/// section of every pass), and `passes_total` counting them all: a thread of thousands of passes
/// written out as moves, shown in part.
pub fn passes_json_first(
    t: &Thread,
    section: Option<&crate::sim::Section>,
    first: usize,
) -> serde_json::Value {
    let rows = program::pass_rows(&t.job, &t.passes, t.diameter_x);
    let mut v = program::passes_json(&t.job, &rows[..first.min(rows.len())], section);
    if let Some(o) = v.as_object_mut() {
        if first < rows.len() {
            o.insert("passes_total".into(), rows.len().into());
        }
        let source = match t.origin {
            Origin::Cycle => "cycle",
            Origin::Moves { .. } => "moves",
        };
        o.insert("source".into(), source.into());
        if let Some(note) = t.start_note() {
            // The Z where each pass starts is not known: null, never the assumed point's.
            if t.unknown_start[1] {
                if let Some(rows) = o.get_mut("passes").and_then(|p| p.as_array_mut()) {
                    for r in rows.iter_mut().filter_map(|r| r.as_object_mut()) {
                        r.insert("z".into(), serde_json::Value::Null);
                    }
                }
            }
            let axes: Vec<&str> = ["X", "Z"]
                .into_iter()
                .zip(t.unknown_start)
                .filter_map(|(a, unknown)| unknown.then_some(a))
                .collect();
            o.insert(
                "start_unknown".into(),
                serde_json::json!({ "axes": axes, "note": note }),
            );
        }
        o.insert(
            "depth_from".into(),
            if t.crest_known() {
                "crest"
            } else {
                "first_pass"
            }
            .into(),
        );
    }
    v
}

/// The first chain of synchronised moves of pass `n` of a toolpath, as moves.
fn chain_of(path: &Toolpath, n: u32) -> Option<Vec<Move>> {
    let mut chain: Vec<Move> = Vec::new();
    for (from, m) in path.segments() {
        let synced = matches!(m.kind, MotionKind::Thread { .. }) && m.pass == n;
        if synced {
            chain.push(Move {
                kind: m.kind,
                from,
                to: m.to,
                line: m.line,
                span: Span::default(),
            });
        } else if !chain.is_empty() {
            break;
        }
    }
    (!chain.is_empty()).then_some(chain)
}

/// Adds a pass written after a cycle to the cycle's thread: its depth below the cycle's crest
/// line and its offset from the crest's start, its moves to the toolpath. The passes' kinds and
/// chip areas are settled once the thread is complete ([`settle_appended`]): a cycle repeated
/// thousands of times costs no more than a table of as many passes.
fn append(t: &mut Thread, before: Vec<Move>, chain: Vec<Move>) {
    let g = t.job.geometry;
    let face = g.side.is_face();
    let long = |p: Pos| if face { p.x } else { p.z };
    let short = |p: Pos| if face { p.z } else { p.x };
    let outward = if face {
        g.side.outward().z
    } else {
        g.side.outward().x
    };
    let main = main_segment(&chain);
    let dl = long(g.crest_end) - long(g.crest_start);
    let crest_short = |l: f64| {
        if dl == 0.0 {
            short(g.crest_start)
        } else {
            short(g.crest_start)
                + (short(g.crest_end) - short(g.crest_start)) * (l - long(g.crest_start)) / dl
        }
    };
    let depth = (crest_short(long(main.from)) - short(main.from)) * outward;
    let previous = t.passes.last().map_or(0.0, |p| p.depth);
    let n = t.passes.len() as u32 + 1;
    t.passes.push(Pass {
        n,
        kind: PassKind::Rough,
        depth,
        increment: depth - previous,
        offset: long(main.from) - long(g.crest_start),
        start: main.from,
        area: 0.0,
        share: 0.0,
    });
    t.pass_spans.push(chain[0].span);
    t.extra_passes += 1;
    for m in before.iter().chain(&chain) {
        t.path.motions.push(Motion {
            kind: m.kind,
            to: m.to,
            pass: n,
            line: m.line,
        });
    }
}

/// The kinds and chip areas of a thread's passes once passes were appended to it: the passes at
/// the final depth finish the thread, as in a table of passes written as moves.
fn settle_appended(t: &mut Thread) {
    let deepest = t
        .passes
        .iter()
        .map(|p| p.depth)
        .fold(f64::NEG_INFINITY, f64::max);
    for p in &mut t.passes {
        p.kind = if p.depth >= deepest - crate::thread::plan::DEPTH_TOLERANCE {
            PassKind::Finish
        } else {
            PassKind::Rough
        };
    }
    let angle = if t.job.tool_angle_deg > 0.0 {
        t.job.tool_angle_deg
    } else {
        ASSUMED_TOOL_ANGLE
    };
    let cuts: Vec<(f64, f64)> = t
        .passes
        .iter()
        .map(|p| (p.offset, p.depth.max(0.0)))
        .collect();
    let areas = area::chip_areas(&cuts, crate::thread::tan_deg(angle / 2.0));
    let sum: f64 = areas.iter().sum();
    for (p, a) in t.passes.iter_mut().zip(areas) {
        p.area = a;
        p.share = if sum > 0.0 { a / sum } else { 0.0 };
    }
}

/// The moves of `between` that close the pass before them: up to the return to `start`; when the
/// tool never returns there, all but the last (the next pass's approach).
fn closing(between: &[Move], start: Pos) -> usize {
    match between
        .iter()
        .position(|m| m.to.distance(start) <= POINT_TOLERANCE)
    {
        Some(i) => i + 1,
        None => between.len().saturating_sub(1),
    }
}

/// The rapid moves after the last pass that belong to the thread: up to the return to `start`,
/// and none that moves back toward the part (`inward`: the direction of depth, short axis first;
/// that is the next work's approach).
fn trailing(after: &[Move], start: Pos, inward: crate::units::Vec2) -> usize {
    let mut n = 0;
    for m in after.iter().take(4) {
        let d = m.to.minus(m.from);
        let toward_part = d.x * inward.x + d.z * inward.z > POINT_TOLERANCE;
        if m.kind != MotionKind::Rapid || toward_part {
            break;
        }
        n += 1;
        if m.to.distance(start) <= POINT_TOLERANCE {
            break;
        }
    }
    n
}

/// Long and short coordinates: along the thread (Z, or X for a face thread) and across it.
#[derive(Clone, Copy)]
struct Axes {
    face: bool,
}

impl Axes {
    fn long(self, p: Pos) -> f64 {
        if self.face {
            p.x
        } else {
            p.z
        }
    }

    fn short(self, p: Pos) -> f64 {
        if self.face {
            p.z
        } else {
            p.x
        }
    }

    /// The point at these coordinates.
    fn pos(self, long: f64, short: f64) -> Pos {
        if self.face {
            Pos::new(long, short)
        } else {
            Pos::new(short, long)
        }
    }
}

/// The crest line: its short coordinate at a long one.
#[derive(Clone, Copy)]
struct CrestLine {
    at_origin: f64,
    origin: f64,
    slope: f64,
}

impl CrestLine {
    fn at(&self, long: f64) -> f64 {
        self.at_origin + self.slope * (long - self.origin)
    }
}

/// The thread that passes written as moves cut.
fn build(
    passes: Vec<PassMoves>,
    approach: Option<Move>,
    after: Vec<Move>,
    setting: Setting,
    key: Key,
    from_cycles: bool,
    crest: Option<Crest>,
) -> Thread {
    let ax = Axes { face: key.face };
    let mains: Vec<Move> = passes.iter().map(|p| main_segment(&p.chain)).collect();
    let first = mains[0];
    let start = approach.map_or(passes[0].chain[0].from, |m| m.from);
    let outward = outward_sign(ax, &passes, &mains, approach, &after);
    let side = match (ax.face, outward > 0.0) {
        (false, true) => Side::External,
        (false, false) => Side::Internal,
        // Depth grows toward −Z: the usual front face.
        (true, true) => Side::FaceFront,
        (true, false) => Side::FaceBack,
    };
    // The crest line: through the first pass's thread, or at the crest the caller gave.
    let (dl, ds) = (
        ax.long(first.to) - ax.long(first.from),
        ax.short(first.to) - ax.short(first.from),
    );
    let crest_diameter = crest.map(|c| match c {
        Crest::Stock(d) => setting.units.to_mm(d),
        Crest::Standard { external, internal } => {
            if side == Side::Internal {
                internal
            } else {
                external
            }
        }
    });
    let crest_known = crest_diameter.is_some() && !ax.face;
    let line = CrestLine {
        at_origin: match crest_diameter {
            Some(dia) if !ax.face => dia / 2.0,
            _ => ax.short(first.from),
        },
        origin: ax.long(first.from),
        slope: if dl != 0.0 { ds / dl } else { 0.0 },
    };
    let (table, depths) = pass_table(ax, &mains, line, outward);
    let deepest = depths.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    // The reference pass (the last) gives the exit and the thread's length.
    let last_chain = &passes[passes.len() - 1].chain;
    let last_main = mains[mains.len() - 1];
    let chain_end = last_chain[last_chain.len() - 1].to;
    let exit = exit_of(ax, last_chain, last_main, outward);
    let end_long = ax.long(first.from) + ax.long(chain_end) - ax.long(last_main.from);
    // The model's lead is along the long axis; the move's may be along X (a steep taper).
    let lead = match first.kind {
        MotionKind::Thread { lead, .. } if ds.abs() > dl.abs() && ds != 0.0 => {
            lead * dl.abs() / ds.abs()
        }
        MotionKind::Thread { lead, .. } => lead,
        _ => key.lead,
    };
    let motions = toolpath_of(&passes, approach, &after, start, side.infeed());
    let first_line = passes[0].chain[0].line;
    let last_line = motions.last().map_or(first_line, |m| m.line);
    let job = Job {
        line: first_line,
        span: passes[0].chain[0].span,
        controller: setting.controller,
        units: setting.units,
        start,
        geometry: Geometry {
            crest_start: ax.pos(line.origin, line.at(line.origin)),
            crest_end: ax.pos(end_long, line.at(end_long)),
            depth: deepest.max(0.0),
            side,
        },
        lead: Lead {
            phase_deg: key.phase,
            ..Lead::constant(lead)
        },
        plan: PassPlan {
            law: DepthLaw::Explicit { depths },
            finish_allowance: 0.0,
            finish_passes: 0,
        },
        infeed: Infeed::Radial,
        finish_at: FinishPosition::Axis,
        tool_angle_deg: ASSUMED_TOOL_ANGLE,
        entry: Entry::Direct,
        exit,
        retract: Retract {
            x: start.x,
            z: start.z,
        },
        return_path: ReturnPath::Box,
    };
    Thread {
        job,
        passes: table,
        path: Toolpath { start, motions },
        origin: Origin::Moves {
            crest_known,
            from_cycles,
            first_line,
            last_line,
        },
        pass_spans: passes.iter().map(|p| p.chain[0].span).collect(),
        diameter_x: setting.diameter_x,
        extra_passes: 0,
        unknown_start: [false; 2],
    }
}

/// Which way is out of the part (+1: toward + along the short axis): deeper passes go into it, a
/// pull-out leaves it, the move after a pass retracts out of it; the approach comes from outside
/// (last: a LinuxCNC pass approaches its back point, outward of the groove, from the start point).
fn outward_sign(
    ax: Axes,
    passes: &[PassMoves],
    mains: &[Move],
    approach: Option<Move>,
    after: &[Move],
) -> f64 {
    let progression = mains
        .iter()
        .map(|m| ax.short(mains[0].from) - ax.short(m.from))
        .find(|d| d.abs() > POINT_TOLERANCE);
    let first_chain = &passes[0].chain;
    let pull_out = Some(ax.short(first_chain[first_chain.len() - 1].to) - ax.short(mains[0].to));
    let after_first = passes
        .get(1)
        .and_then(|p| p.before.first())
        .or(after.first())
        .map(|m| ax.short(m.to) - ax.short(m.from));
    let from_approach = approach.map(|m| ax.short(m.from) - ax.short(m.to));
    [progression, pull_out, after_first, from_approach]
        .into_iter()
        .flatten()
        .find(|d| d.abs() > POINT_TOLERANCE)
        .map_or(1.0, f64::signum)
}

/// The pass table of the passes whose threads are `mains`: depths below the crest line, offsets
/// from the first pass's start, the passes at the final depth finishing the thread (the first
/// removes what is left, the rest are spring passes, as in a cycle's table), sharp-V chip areas
/// for the assumed tool. Also the depths alone.
fn pass_table(ax: Axes, mains: &[Move], line: CrestLine, outward: f64) -> (Vec<Pass>, Vec<f64>) {
    let depths: Vec<f64> = mains
        .iter()
        .map(|m| (line.at(ax.long(m.from)) - ax.short(m.from)) * outward)
        .collect();
    let deepest = depths.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut table: Vec<Pass> = mains
        .iter()
        .zip(&depths)
        .enumerate()
        .map(|(i, (m, &depth))| Pass {
            n: i as u32 + 1,
            kind: if depth >= deepest - crate::thread::plan::DEPTH_TOLERANCE {
                PassKind::Finish
            } else {
                PassKind::Rough
            },
            depth,
            increment: depth - if i == 0 { 0.0 } else { depths[i - 1] },
            offset: ax.long(m.from) - line.origin,
            start: m.from,
            area: 0.0,
            share: 0.0,
        })
        .collect();
    set_areas(&mut table, ASSUMED_TOOL_ANGLE);
    (table, depths)
}

/// Sharp-V chip areas and shares of a pass table, for a tool of this angle.
fn set_areas(table: &mut [Pass], angle_deg: f64) {
    let cuts: Vec<(f64, f64)> = table.iter().map(|p| (p.offset, p.depth.max(0.0))).collect();
    let areas = area::chip_areas(&cuts, crate::thread::tan_deg(angle_deg / 2.0));
    let sum: f64 = areas.iter().sum();
    for (p, a) in table.iter_mut().zip(areas) {
        p.area = a;
        p.share = if sum > 0.0 { a / sum } else { 0.0 };
    }
}

/// A pass's exit: the synchronised moves after its thread (`main`) are its pull-out.
fn exit_of(ax: Axes, chain: &[Move], main: Move, outward: f64) -> Exit {
    let main_at = chain.iter().position(|m| *m == main).unwrap_or(0);
    let end = chain[chain.len() - 1].to;
    let pull_long = (ax.long(end) - ax.long(main.to)).abs();
    let pull_short = (ax.short(end) - ax.short(main.to)) * outward;
    if main_at + 1 < chain.len() && pull_long > POINT_TOLERANCE {
        Exit::PullOut {
            start_before: pull_long,
            length: pull_long,
            outward: pull_short.max(0.0),
        }
    } else {
        Exit::Straight
    }
}

/// The toolpath of passes written as moves: the approach, each pass (the moves before it that
/// close the previous pass are the previous pass's), then the return after the last.
fn toolpath_of(
    passes: &[PassMoves],
    approach: Option<Move>,
    after: &[Move],
    start: Pos,
    inward: crate::units::Vec2,
) -> Vec<Motion> {
    let mut motions: Vec<Motion> = Vec::new();
    let mut push = |m: &Move, pass: u32| {
        motions.push(Motion {
            kind: m.kind,
            to: m.to,
            pass,
            line: m.line,
        })
    };
    if let Some(a) = approach {
        push(&a, 1);
    }
    for (i, p) in passes.iter().enumerate() {
        let n = i as u32 + 1;
        let split = closing(&p.before, start);
        for m in &p.before[..split] {
            push(m, n.saturating_sub(1).max(1));
        }
        for m in p.before[split..].iter().chain(&p.chain) {
            push(m, n);
        }
    }
    let last = passes.len() as u32;
    for m in &after[..trailing(after, start, inward)] {
        push(m, last);
    }
    motions
}

#[cfg(test)]
mod tests {
    use super::*;

    const MM: Setting = Setting {
        units: Units::Mm,
        diameter_x: true,
        controller: "test",
    };

    fn mv(kind: MotionKind, from: (f64, f64), to: (f64, f64), line: u32) -> Move {
        Move {
            kind,
            from: Pos::new(from.0, from.1),
            to: Pos::new(to.0, to.1),
            line,
            span: Span::new(0, 0, line, 1),
        }
    }

    fn thread_move(lead: f64) -> MotionKind {
        MotionKind::Thread {
            lead,
            dlead: 0.0,
            phase_deg: 0.0,
        }
    }

    /// Box passes (rapid in, thread, rapid out, rapid back) at these radii and start Zs.
    fn passes(c: &mut Collector<()>, out: &mut Vec<Thread>, lead: f64, cuts: &[(f64, f64, f64)]) {
        passes_at(c, out, lead, 0.0, cuts)
    }

    /// … starting at spindle angle `phase` (degrees).
    fn passes_at(
        c: &mut Collector<()>,
        out: &mut Vec<Thread>,
        lead: f64,
        phase: f64,
        cuts: &[(f64, f64, f64)],
    ) {
        let mut push = |f: Found<()>| {
            if let Found::Thread(t, _) = f {
                out.push(*t);
            }
        };
        let mut line = 0;
        let mut l = || {
            line += 1;
            line
        };
        for &(x, z0, z1) in cuts {
            let at = c.last.map_or(Pos::new(20.0, z0), |m| m.to);
            c.motion(
                mv(MotionKind::Rapid, (at.x, at.z), (x, z0), l()),
                MM,
                false,
                || (),
                &mut push,
            );
            let kind = MotionKind::Thread {
                lead,
                dlead: 0.0,
                phase_deg: phase,
            };
            c.motion(mv(kind, (x, z0), (x, z1), l()), MM, false, || (), &mut push);
            c.motion(
                mv(MotionKind::Rapid, (x, z1), (20.0, z1), l()),
                MM,
                false,
                || (),
                &mut push,
            );
            c.motion(
                mv(MotionKind::Rapid, (20.0, z1), (20.0, z0), l()),
                MM,
                false,
                || (),
                &mut push,
            );
        }
    }

    fn finish(c: Collector<()>, out: &mut Vec<Thread>) {
        c.finish(&mut |f| {
            if let Found::Thread(t, _) = f {
                out.push(*t);
            }
        });
    }

    #[test]
    fn passes_with_one_lead_over_one_span_are_one_thread() {
        let mut c = Collector::new(None);
        let mut out = Vec::new();
        // Backed-off starts (0.2, 0.35 further back) with the same end: one thread, depths from
        // the first pass (radius 15): 0, 0.3, 0.55; offsets from its start.
        passes(
            &mut c,
            &mut out,
            2.0,
            &[(15.0, 5.0, -30.0), (14.7, 5.2, -30.0), (14.45, 5.35, -30.0)],
        );
        // Another lead: a second thread.
        passes(
            &mut c,
            &mut out,
            1.5,
            &[(10.0, 5.0, -10.0), (9.8, 5.0, -10.0)],
        );
        // The same lead over another span (more than a lead away): a third.
        passes(&mut c, &mut out, 1.5, &[(10.0, -20.0, -35.0)]);
        finish(c, &mut out);
        assert_eq!(out.len(), 3);
        let t = &out[0];
        assert_eq!(t.job.geometry.side, Side::External);
        let depths: Vec<f64> = t.passes.iter().map(|p| p.depth).collect();
        let offsets: Vec<f64> = t.passes.iter().map(|p| p.offset).collect();
        assert!(
            (depths[1] - 0.3).abs() < 1e-12 && (depths[2] - 0.55).abs() < 1e-12,
            "{depths:?}"
        );
        assert!(
            (offsets[1] - 0.2).abs() < 1e-12 && (offsets[2] - 0.35).abs() < 1e-12,
            "{offsets:?}"
        );
        assert_eq!(t.passes[2].kind, PassKind::Finish);
        assert!(!t.crest_known());
        // The toolpath: approach, then per pass thread, out, back, and the next approach.
        assert_eq!(t.path.start, Pos::new(20.0, 5.0));
        assert_eq!(t.path.motions.len(), 12);
        assert_eq!(out[1].passes.len(), 2);
        assert_eq!(out[2].passes.len(), 1);
    }

    /// The passes of a second start (Fanuc/Haas Q180000, Sinumerik SF=180) over the same span are
    /// a thread of their own, carrying their start angle; 360° is 0°.
    #[test]
    fn passes_at_another_start_angle_are_another_thread() {
        let mut c = Collector::new(None);
        let mut out = Vec::new();
        let cuts = [(15.0, 5.0, -30.0), (14.7, 5.0, -30.0)];
        passes_at(&mut c, &mut out, 3.0, 0.0, &cuts);
        passes_at(&mut c, &mut out, 3.0, 180.0, &cuts);
        passes_at(&mut c, &mut out, 3.0, 540.0, &cuts[1..]);
        finish(c, &mut out);
        assert_eq!(out.len(), 2, "{:?}", out.iter().map(|t| t.passes.len()));
        assert_eq!((out[0].passes.len(), out[1].passes.len()), (2, 3));
        assert_eq!(out[0].job.lead.phase_deg, 0.0);
        assert_eq!(out[1].job.lead.phase_deg, 180.0);
    }

    #[test]
    fn the_crest_when_known_and_internal_threads() {
        // Internal: the passes go up in X. With the stock (the bore) at Ø20 the depths are
        // measured from radius 10.
        let mut c = Collector::new(Some(Crest::Stock(20.0)));
        let mut out = Vec::new();
        let mut push = |f: Found<()>| {
            if let Found::Thread(t, _) = f {
                out.push(*t);
            }
        };
        for (i, x) in [10.3, 10.6, 10.8].into_iter().enumerate() {
            let n = 4 * i as u32;
            c.motion(
                mv(MotionKind::Rapid, (8.0, 3.0), (x, 3.0), n + 1),
                MM,
                false,
                || (),
                &mut push,
            );
            c.motion(
                mv(thread_move(1.5), (x, 3.0), (x, -20.0), n + 2),
                MM,
                false,
                || (),
                &mut push,
            );
            c.motion(
                mv(MotionKind::Rapid, (x, -20.0), (8.0, -20.0), n + 3),
                MM,
                false,
                || (),
                &mut push,
            );
            c.motion(
                mv(MotionKind::Rapid, (8.0, -20.0), (8.0, 3.0), n + 4),
                MM,
                false,
                || (),
                &mut push,
            );
        }
        c.finish(&mut push);
        let t = &out[0];
        assert_eq!(t.job.geometry.side, Side::Internal);
        assert!(t.crest_known());
        let depths: Vec<f64> = t.passes.iter().map(|p| p.depth).collect();
        assert!(
            depths
                .iter()
                .zip([0.3, 0.6, 0.8])
                .all(|(a, b)| (a - b).abs() < 1e-12),
            "{depths:?}"
        );
    }

    #[test]
    fn a_tool_change_ends_a_thread() {
        let mut c = Collector::new(None);
        let mut out = Vec::new();
        passes(&mut c, &mut out, 2.0, &[(15.0, 5.0, -30.0)]);
        c.boundary(&mut |f| {
            if let Found::Thread(t, _) = f {
                out.push(*t);
            }
        });
        passes(&mut c, &mut out, 2.0, &[(14.7, 5.0, -30.0)]);
        finish(c, &mut out);
        assert_eq!(out.len(), 2);
    }
}
