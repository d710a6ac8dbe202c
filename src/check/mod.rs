//! `threadcut check`: what a program will do wrong, before the spindle turns. One function,
//! [`check`], serves the command line, the browser page and every later binding, so that they
//! report the same findings for the same program and options.
//!
//! The program streams through its dialect exactly as `expand` does (or through the APT reader), so
//! the controller's own alarms become check errors at their line and column. Every thread the
//! program cuts ([`crate::threads`]: each cycle, and each thread written as plain synchronised
//! moves) is then checked against the blank and the machine ([`cut`]), and, with a standard
//! thread named, against its class limits ([`standard`]).
//!
//! **Facts are errors, assumptions are not.** Where the program and the options do not say where
//! the blank is, `check` infers what it honestly can (Z0 as the part's face, the crest as the
//! stock: [`blank`]) and states each assumption as a [`Note`]; a finding that rests on one is a
//! warning that names it. Errors are for facts: the controller's alarms, a depth not reached, a
//! limit of the machine exceeded, a collision with a blank the user gave, a thread outside its
//! class where nothing was assumed.
//!
//! | check | severity | code |
//! | --- | --- | --- |
//! | the controller's alarm, a G code it does not have | error | its code, E015 |
//! | the groove does not reach the cycle's depth | error | E013 |
//! | a rapid move enters the blank the user gave; any rapid into a thread's teeth, across a surface the program cut or into the stock given ([`whole`]) | error | E011 |
//! | a rapid move enters the blank check assumed, or the bar's face assumed | warning | W008 |
//! | a thread runs into a shoulder the program left or the stock given ([`whole`]) | error | E018 |
//! | lead × spindle speed above the axis limit | error | E012 |
//! | lead above the controller's maximum | error | E014 |
//! | chamfer/tail-out longer than the thread; thread shorter than one lead | error | E007 |
//! | run-up before the blank too short for the feed to settle (δ1) | warning | W003 |
//! | pull-out shorter than the run-out the feed needs to stop (δ2) | warning | W007 |
//! | ridge or pitch-diameter error in the simulated groove, or no section | warning | W004 |
//! | spindle speed unknown, or constant surface speed (G96) | warning | W005 |
//! | an axis or lead word without a decimal point read as least increments | warning | W006 |
//! | `--thread`: root diameter, lead, flank angles (and pitch diameter with the tool given) outside the class; the crest the program turned outside it | error | E016 |
//! | `--thread`: a taper thread's taper outside the standard's; where its gauge stands, with face and tip given | error | E016 |
//! | `--thread`: pitch diameter outside the class with the tool's tip (or a taper thread's face) assumed | warning | W009 |
//! | the spindle stopped (M5, M19, end of program, a stop the manual says stops it), reversed, or another tool, at or between passes of one thread ([`state`]) | error | E017 |
//! | the same, on an assumption (a stop the machine builder decides, M1; the same tool selected again) | warning | W010 |
//! | a milling program ([`milling`]): a milled thread's helix off its lead, out of step, compensated on the wrong side, gouged by its entry ([`milled`]) | error | E019 |
//! | a milled thread's straight entry onto its finished radius | warning | W011 |
//! | a tap's lead off its pitch, its spindle against its hand ([`tapping`]) | error | E020 |
//! | the same on an assumption (a floating holder; a lead just off a standard pitch) | warning | W012 |
//!
//! A finding that repeats on every pass is reported once per thread, naming the passes; one that
//! repeats on several blocks (a dialect's warning on each block of a modal G92) once, naming the
//! lines.

pub mod blank;
pub mod cut;
mod decimal;
mod measure;
pub mod milled;
pub mod milling;
pub mod reading;
pub mod spindle;
pub mod standard;
pub mod state;
mod taper;
pub mod tapping;
pub mod whole;

use std::collections::{HashMap, HashSet};
use std::io::BufRead;

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Severity, Span};
use crate::gcode::MotionMode;
use crate::machine::Machine;
use crate::program::{self, Error, Event};
use crate::sim::Tip;
use crate::thread::standard::StandardThread;
use crate::threads::{Collector, Crest, Found, Move, Setting};
use crate::units::{Pos, Units};

pub use crate::source::Source;
pub use blank::{Blank, Known};
pub use cut::{check_thread, DEFAULT_LEAD_ERROR, DEFAULT_SERVO_TIME_CONSTANT};
pub use reading::{reading, Reading};
pub use spindle::{Rpm, Spindle, SpindleSpeed};
pub use state::State;

/// What the check is told about the part, the tool and the thread.
#[derive(Clone, Debug)]
pub struct Options {
    /// The blank's diameter, in the program's units at each thread; `None`: the thread's crest is
    /// assumed.
    pub stock_diameter: Option<f64>,
    /// Z of the blank's face on the thread's start side, in the program's units; `None`: Z0 is
    /// assumed when the thread runs into the part through it.
    pub stock_start: Option<f64>,
    /// The bar's length from its face toward the chuck (`--stock-length`), program units.
    pub stock_length: Option<f64>,
    /// The diameter of a bore through the bar (`--stock-bore`: a tube, a cored casting), program
    /// units; it is an internal thread's blank where the program does not turn the bore.
    pub stock_bore: Option<f64>,
    /// The tool's tip, its sizes in the program's units at each thread; its angle is the cycle's.
    /// `None`: not given (the section is cut with a sharp tool; judging against a standard assumes
    /// the standard's root form).
    pub tip: Option<Tip>,
    /// The standard thread to judge against (`--thread`).
    pub thread: Option<StandardThread>,
    /// The measuring wires one owns (`--wire`), in the units of [`Options::thread`]: the
    /// measurement over wires the check states is over them; `None`: over the best wire.
    pub wire: Option<f64>,
    /// A program with control flow stops after this many executed blocks (`--max-blocks`; by
    /// default the interpreter's, [`crate::interp::Limits`]).
    pub max_blocks: u64,
    /// Where calls find programs the program's text does not hold (`--include DIR`).
    pub library: Option<crate::interp::library::Library>,
    /// A call of a subroutine the program defines, run instead of its main program (`--call`,
    /// [`program::Options::call`]).
    pub call: Option<String>,
    /// Where the tool is before the program's first line (`--start X,Z`, program units at
    /// power-on): a cycle shown without the lines before it starts there. [`program::Start::At`]
    /// or [`program::Start::Unknown`]: a check judges motion only from a start it is given.
    pub start: program::Start,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            stock_diameter: None,
            stock_start: None,
            stock_length: None,
            stock_bore: None,
            tip: None,
            thread: None,
            wire: None,
            max_blocks: program::Options::default().max_blocks,
            library: None,
            call: None,
            start: program::Start::Unknown,
        }
    }
}

/// Something `check` assumed or could not check, at the thread it concerns.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Note {
    #[serde(skip)]
    pub span: Span,
    pub message: String,
}

impl Note {
    pub fn new(span: Span, message: impl Into<String>) -> Note {
        Note {
            span,
            message: message.into(),
        }
    }
}

/// Everything the check found.
#[derive(Debug, Default)]
pub struct Report {
    pub diagnostics: Vec<Diagnostic>,
    /// What was assumed, and what could not be checked.
    pub notes: Vec<Note>,
    /// Threads checked: cycles, and threads written as plain moves.
    pub threads: u32,
    pub lines: u32,
    /// The program stopped being read at a controller alarm (the last error).
    pub stopped: bool,
    /// The codes the controller threads with (`G32, G76, G92`), for a program with no thread.
    pub thread_codes: String,
    /// The part as the program made it (an empty outline for APT programs).
    pub part: whole::View,
    /// Each thread's blank, in the order the threads were checked.
    pub blanks: Vec<ThreadBlank>,
    /// The program defines subroutines and calls none ([`program::Summary::uncalled`]): it said
    /// so, and has no thread for that reason.
    pub uncalled: bool,
}

/// How a boundary of a thread's blank is known.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Basis {
    /// Measured on the part as the program cut it.
    Measured,
    /// Given in the options (`--stock-diameter`, `--stock-bore`, `--stock-start`).
    Given,
    /// Assumed (the thread's crest as the stock; Z0 as the face).
    Assumed,
    /// Not known (the first pass, or the start point, stands in for it).
    Unknown,
}

/// A thread's blank as `check` took it (program units, X as a diameter): the surface the thread
/// is cut in (its crest) and the face where the part begins, each with how it is known.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ThreadBlank {
    pub line: u32,
    pub crest: f64,
    pub crest_from: Basis,
    pub face: f64,
    pub face_from: Basis,
}

impl Report {
    pub fn errors(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }

    pub fn warnings(&self) -> usize {
        self.diagnostics.len() - self.errors()
    }

    /// The findings as `check --format json` writes them: errors and warnings, then the notes.
    pub fn findings(&self, file: &str) -> Vec<Finding> {
        self.findings_in(&|_| file.to_string())
    }

    /// [`Report::findings`], each named in the file its span lies in (`name_of`: the program's
    /// name for the program's own lines, a called file's for its lines), with the calls a finding
    /// in a called file ran inside.
    pub fn findings_in(&self, name_of: &dyn Fn(&Span) -> String) -> Vec<Finding> {
        let mut out: Vec<Finding> = self
            .diagnostics
            .iter()
            .map(|d| Finding {
                file: name_of(&d.span),
                line: d.span.line,
                column: d.span.column,
                level: match d.severity {
                    Severity::Error => "error",
                    Severity::Warning => "warning",
                },
                code: Some(d.code.as_str()),
                message: d.message.clone(),
                hint: d.hint.clone(),
                called_from: d
                    .calls
                    .iter()
                    .rev()
                    .map(|c| Place {
                        file: name_of(c),
                        line: c.line,
                    })
                    .collect(),
            })
            .collect();
        out.extend(self.notes.iter().map(|n| Finding {
            file: name_of(&n.span),
            line: n.span.line,
            column: n.span.column,
            level: "note",
            code: None,
            message: n.message.clone(),
            hint: None,
            called_from: Vec::new(),
        }));
        out
    }
}

/// One finding of `check --format json`: `{file, line, column, level, code, message, hint}`;
/// `level` is `error`, `warning` or `note` (an assumption), `code` is null for a note; a finding
/// in a called file adds `called_from: [{file, line}]`, innermost call first.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finding {
    pub file: String,
    pub line: u32,
    pub column: u32,
    pub level: &'static str,
    pub code: Option<&'static str>,
    pub message: String,
    pub hint: Option<String>,
    /// For a finding in a called file: the calls it ran inside, innermost first (absent
    /// otherwise).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub called_from: Vec<Place>,
}

/// A line of a file: where a call was made.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Place {
    pub file: String,
    pub line: u32,
}

/// A crest the program turned outside the named thread's class (its major diameter for an
/// external thread, its minor for an internal one), measured at the program's resolution.
struct CrestFinding {
    diameter: f64,
    name: &'static str,
    limits: String,
    thread: String,
    line: u32,
}

impl CrestFinding {
    fn at(self, span: Span, units: Units) -> Diagnostic {
        Diagnostic::error(
            Code::OutOfClass,
            span,
            format!(
                "the crest turned at line {} is Ø{}, outside the {} diameter of {} ({})",
                self.line,
                length(units, self.diameter),
                self.name,
                self.thread,
                self.limits
            ),
        )
        .with_hint("turn the crest within the class's limits before threading")
    }
}

fn crest_outside_class(
    thread: &StandardThread,
    internal: bool,
    diameter_mm: f64,
    line: u32,
    res: crate::units::Resolution,
) -> Option<CrestFinding> {
    let (limits, name) = if internal {
        (thread.internal.as_ref()?.minor, "minor")
    } else {
        (thread.external.as_ref()?.major, "major")
    };
    let tol = res.x();
    let low = limits.min.is_some_and(|min| tol.lt(diameter_mm, min));
    let high = limits.max.is_some_and(|max| tol.lt(max, diameter_mm));
    if !(low || high) {
        return None;
    }
    let show = |v: f64| length(thread.units, thread.units.to_mm(thread.units.from_mm(v)));
    let limits = match (limits.min, limits.max) {
        (Some(a), Some(b)) => format!("{}–{} mm", show(a), show(b)),
        (Some(a), None) => format!("at least {} mm", show(a)),
        (None, Some(b)) => format!("at most {} mm", show(b)),
        (None, None) => String::new(),
    };
    let class = if internal {
        thread.internal.as_ref().map(|l| l.class.to_string())
    } else {
        thread.external.as_ref().map(|l| l.class.to_string())
    };
    Some(CrestFinding {
        diameter: diameter_mm,
        name,
        limits,
        thread: format!("{}-{}", thread.name, class.unwrap_or_default()),
        line,
    })
}

/// Checks a whole program.
pub fn check<R: BufRead>(input: R, source: Source<'_>, opts: &Options) -> Result<Report, Error> {
    match source {
        Source::Gcode(machine) => check_gcode(input, machine, opts),
        Source::Apt(machine) => check_apt(input, machine, opts),
    }
}

/// The crest a thread written as moves is measured from: the stock's diameter, else the named
/// standard thread's basic crest.
fn crest(opts: &Options) -> Option<Crest> {
    match (opts.stock_diameter, &opts.thread) {
        (Some(d), _) => Some(Crest::Stock(d)),
        (None, Some(t)) => Some(Crest::Standard {
            external: t.basic.major,
            internal: t.basic.minor,
        }),
        (None, None) => None,
    }
}

/// A cycle's blank as it ran: the surface and the face the program cut, when it did (the face's
/// Z in program units and the line that faced it).
type CycleBlank = (Option<whole::Measured>, Option<(f64, u32)>);

/// Where findings about a thread go while the program is read.
struct Sink<'a> {
    machine: &'a Machine,
    opts: &'a Options,
    found: Vec<Diagnostic>,
    notes: Vec<Note>,
    threads: u32,
    /// The thread before, for one over the same groove right after it.
    last: Option<state::Last>,
    restart: state::Restart,
    /// The part as the program makes it: the blank at each thread, and every rapid judged.
    whole: whole::Whole,
    /// The blanks of cycles that ran, until the thread reader hands their threads over.
    cycles: Vec<(Span, CycleBlank)>,
    /// A cycle the thread reader handed over as it ran (before [`Sink::cycle`] saw it).
    handed: Option<Span>,
    blanks: Vec<ThreadBlank>,
}

impl<'a> Sink<'a> {
    /// A threading cycle as it runs: its blank is the part as it stands now, and its teeth are
    /// in the part for the moves after it (the thread reader may hand the cycle over later).
    fn cycle(&mut self, job: &crate::thread::Job, diameter_x: bool) {
        if self.handed.take() == Some(job.span) {
            return;
        }
        let Ok(t) = crate::threads::Thread::from_cycle(job.clone(), diameter_x) else {
            return;
        };
        if t.passes.len() <= 1 {
            // A single pass (a modal G92's block) is read with the passes around it.
            return;
        }
        let measured = self.whole.measured(&t);
        let face = self.whole.measured_face(&t);
        let opts = Options {
            stock_diameter: measured.map(|m| m.diameter).or(
                if t.job.geometry.side == crate::thread::Side::Internal {
                    self.opts.stock_bore
                } else {
                    self.opts.stock_diameter
                },
            ),
            stock_start: face.map(|f| f.0).or(self.opts.stock_start),
            ..self.opts.clone()
        };
        self.teeth(&t, &opts);
        if self.cycles.len() >= 64 {
            self.cycles.remove(0);
        }
        self.cycles.push((job.span, (measured, face)));
    }

    /// A thread whose deepest pass does not reach the surface the program turned cuts nothing:
    /// its root lies outside the part (inside the bore for an internal thread) all along it. Where
    /// any material lies beyond the root, the program's or the stock's of unknown size, it may
    /// cut and nothing is said.
    fn cuts_nothing(&mut self, t: &crate::threads::Thread, m: whole::Measured) {
        if m.reaches {
            return;
        }
        let Some(last) = t.passes.iter().max_by(|a, b| a.depth.total_cmp(&b.depth)) else {
            return;
        };
        let units = t.job.units;
        let res = self.machine.program_resolution(units, t.diameter_x);
        let root = 2.0 * last.start.x;
        let surface = units.to_mm(m.diameter);
        let out = t.job.geometry.side.outward().x;
        if (root - surface) * out < -res.x().get() * 2.0 {
            return;
        }
        let by = m.line.map_or(String::new(), |l| format!(" at line {l}"));
        self.found.push(
            Diagnostic::error(
                Code::DepthNotReached,
                t.job.span,
                format!(
                    "the thread cuts nothing: its deepest pass (Ø{}) does not reach the part, which the program turned to Ø{}{by}",
                    length(units, root),
                    length(units, surface),
                ),
            )
            .with_hint("the cycle's crest and depth are for another diameter than the one turned: check its X, I and K against the part"),
        );
    }

    /// The thread's blank under `opts`, at the program's resolution there.
    fn blank(
        &self,
        t: &crate::threads::Thread,
        opts: &Options,
    ) -> (blank::Blank, crate::units::Resolution) {
        let res = self.machine.program_resolution(t.job.units, t.diameter_x);
        let b = blank::Blank::new(
            &t.job,
            t.path.start,
            opts.stock_diameter,
            opts.stock_start,
            t.crest_known(),
            res,
        );
        (b, res)
    }

    /// The thread's blank as the report states it.
    fn blank_of(
        &mut self,
        t: &crate::threads::Thread,
        opts: &Options,
        measured: bool,
        face_measured: bool,
    ) {
        let (b, _) = self.blank(t, opts);
        let from = |k: Known| match k {
            Known::Given => Basis::Given,
            Known::Assumed => Basis::Assumed,
            Known::Unknown => Basis::Unknown,
        };
        let units = t.job.units;
        self.blanks.push(ThreadBlank {
            line: t.job.line,
            crest: units.from_mm(2.0 * b.x_face.abs()),
            crest_from: if measured {
                Basis::Measured
            } else {
                from(b.surface)
            },
            face: units.from_mm(b.z_face),
            face_from: if face_measured {
                Basis::Measured
            } else {
                from(b.face)
            },
        });
    }

    /// The thread's teeth in the part, from its blank.
    fn teeth(&mut self, t: &crate::threads::Thread, opts: &Options) {
        let (blank, res) = self.blank(t, opts);
        self.whole.thread(t, &blank, res.increment_mm());
        self.whole.settle();
    }

    /// The options a thread is checked with: its blank's surface as the program cut it (a note
    /// says so), else the bar (`--stock-diameter`) for an external thread, the bore
    /// (`--stock-bore`) for an internal one.
    fn blank_options(
        &mut self,
        t: &crate::threads::Thread,
        measured: Option<whole::Measured>,
        face: Option<(f64, u32)>,
    ) -> Options {
        let internal = t.job.geometry.side == crate::thread::Side::Internal;
        let given = if internal {
            self.opts.stock_bore
        } else {
            self.opts.stock_diameter
        };
        if let Some(m) = measured {
            let by = m.line.map_or(String::new(), |l| format!(" at line {l}"));
            let bar = given.map_or(String::new(), |d| {
                format!(
                    " (the {} Ø{} given)",
                    if internal { "bore" } else { "bar" },
                    length(Units::Mm, d)
                )
            });
            self.notes.push(Note::new(
                t.job.span,
                format!(
                    "blank: the surface along the thread is Ø{} as the program turned it{by}{bar}",
                    length(Units::Mm, m.diameter),
                ),
            ));
            self.cuts_nothing(t, m);
            if let (Some(thread), Some(line)) = (&self.opts.thread, m.line) {
                let res = self.machine.program_resolution(t.job.units, t.diameter_x);
                let mm = t.job.units.to_mm(m.diameter);
                if let Some(d) = crest_outside_class(thread, internal, mm, line, res) {
                    self.found.push(d.at(t.job.span, t.job.units));
                }
            }
        }
        if let Some((z, line)) = face {
            self.notes.push(Note::new(
                t.job.span,
                format!(
                    "blank: the part's face is at Z{} as the program faced it at line {line}",
                    length(Units::Mm, z)
                ),
            ));
        }
        Options {
            stock_diameter: measured.map(|m| m.diameter).or(given),
            stock_start: face.map(|f| f.0).or(self.opts.stock_start),
            ..self.opts.clone()
        }
    }

    fn new(machine: &'a Machine, opts: &'a Options, restart: state::Restart) -> Sink<'a> {
        Sink {
            machine,
            opts,
            found: Vec::new(),
            notes: Vec::new(),
            threads: 0,
            last: None,
            restart,
            whole: whole::Whole::new(
                whole::StockWords {
                    diameter: opts.stock_diameter,
                    face: opts.stock_start,
                    length: opts.stock_length,
                    bore: opts.stock_bore,
                },
                match opts.tip {
                    Some(Tip::Radius { radius }) => Some(radius),
                    _ => None,
                },
            ),
            cycles: Vec::new(),
            handed: None,
            blanks: Vec::new(),
        }
    }

    fn take(&mut self, f: Found<State>) {
        match f {
            Found::Thread(t, states) => {
                self.threads += 1;
                let spindle = states.first().map(|s| s.spindle).unwrap_or_default();
                // A cycle's blank and teeth were taken when the cycle ran ([`Sink::cycle`]).
                let is_cycle = matches!(t.origin, crate::threads::Origin::Cycle);
                let at_cycle = is_cycle
                    .then(|| {
                        let i = self.cycles.iter().position(|c| c.0 == t.job.span)?;
                        Some(self.cycles.remove(i).1)
                    })
                    .flatten();
                if is_cycle && at_cycle.is_none() {
                    // Handed over as it ran: its blank and teeth are taken here.
                    self.handed = Some(t.job.span);
                }
                let (measured, face) = match at_cycle {
                    Some(mf) => mf,
                    None => (self.whole.measured(&t), self.whole.measured_face(&t)),
                };
                if self.centre_line_tap(&t, &states) {
                    state::judge(&t, &states, &mut self.last, &self.restart, &mut self.found);
                    return;
                }
                let opts = self.blank_options(&t, measured, face);
                check_thread(
                    &t,
                    self.machine,
                    &opts,
                    &spindle,
                    &mut self.found,
                    &mut self.notes,
                );
                if at_cycle.is_none() {
                    self.teeth(&t, &opts);
                }
                self.blank_of(&t, &opts, measured.is_some(), face.is_some());
                state::judge(&t, &states, &mut self.last, &self.restart, &mut self.found);
            }
            Found::Failed { error, .. } => {
                self.threads += 1;
                self.last = None;
                self.found.push(error);
            }
        }
    }
}

impl Sink<'_> {
    /// A thread on the centre line is a tap (issue 24): judged as one (its lead against the named
    /// tap's pitch), not as a turned thread. On a lathe M3 is taken as a right-hand tap's
    /// direction, as Fanuc's lathe tapping cycle turns it (an assumption the note states).
    fn centre_line_tap(&mut self, t: &crate::threads::Thread, states: &[State]) -> bool {
        let res = self
            .machine
            .program_resolution(t.job.units, t.diameter_x)
            .x()
            .get();
        let first = states.first();
        let rpm = first
            .and_then(|s| s.spindle.s)
            .filter(|_| !first.is_some_and(|s| s.spindle.css));
        let rotation = match first.map(|s| s.turning) {
            Some(state::Turning::On {
                dir: state::Direction::Ccw,
                ..
            }) => crate::mill::motion::Rotation::Ccw,
            Some(state::Turning::Off { .. }) => crate::mill::motion::Rotation::Stopped,
            _ => crate::mill::motion::Rotation::Cw,
        };
        let Some(tap) = tapping::centre_line_tap(t, rpm, rotation, res) else {
            return false;
        };
        let target =
            self.opts.thread.as_ref().and_then(|th| {
                measure::target(th, crate::thread::standard::Surface::Internal).ok()
            });
        let units = t.job.units;
        let span = t.job.span;
        let span_of = move |_: u32| span;
        let j = tapping::Judging {
            target: target.as_ref().map(|tg| (tg, crate::mill::Hand::Right)),
            left: None,
            units,
            feed_resolution: units.to_mm(match units {
                Units::Mm => 0.001,
                Units::Inch => 0.0001,
            }),
            span_of: &span_of,
        };
        tapping::judge(&tap, &j, &mut self.found, &mut self.notes);
        self.notes.push(Note::new(
            span,
            "a thread on the centre line is taken as a tap held in the turret; M3 taken as a right-hand tap's direction, as the Fanuc family's lathe tapping cycle turns it",
        ));
        true
    }
}

fn check_gcode<R: BufRead>(input: R, machine: &Machine, opts: &Options) -> Result<Report, Error> {
    let d = crate::dialect::open(machine).map_err(Error::Setup)?;
    let controller = d.name();
    let mut report = Report {
        thread_codes: d.vocabulary().thread_codes(),
        ..Report::default()
    };
    let meanings = d.meanings();
    let mut sink = Sink::new(machine, opts, state::Restart::of(&meanings));
    let mut machine_state = state::Reader::new(&meanings, d.conventions().set_position);
    let mut decimals = decimal::DecimalWords::new(machine);
    let mut collector: Collector<State> = Collector::new(crest(opts));
    let mut unknown_starts = Vec::new();
    let run = program::Options {
        max_blocks: opts.max_blocks,
        library: opts.library.clone(),
        call: opts.call.clone(),
        // A start the check is not given is not assumed: the motion from it is not known.
        start: match opts.start {
            program::Start::Unstated => program::Start::Unknown,
            given => given,
        },
        ..program::Options::default()
    };
    let mut work_system = None;
    let result = program::run_with(input, machine, &run, |modal, ev| {
        let setting = Setting {
            units: modal.units,
            diameter_x: modal.diameter_x,
            controller,
        };
        // Another work coordinate system: another setup (the part turned round, the sub-spindle),
        // whose coordinates the part so far does not share.
        if work_system
            .replace(modal.work_system)
            .is_some_and(|w| w != modal.work_system)
        {
            sink.whole.new_setup();
        }
        let mut take = |f| sink.take(f);
        match ev {
            Event::Plain { line, mv } => {
                machine_state.before(line);
                if let Some(dw) = decimals.as_mut() {
                    dw.line(line, modal.units, modal.motion == MotionMode::Thread);
                }
                let at = move_span(line);
                let now = || machine_state.now(at);
                if let Some(w) = collector.plain(line, mv, setting, now, &mut take) {
                    unknown_starts.push(w);
                }
                if let Some(mv) = &mv {
                    sink.whole
                        .plain(mv, at, whole_at(modal), collector.is_reading());
                }
                machine_state.after(line);
            }
            // A turning cycle's blocks: their words, as a cycle's; no thread. Its moves cut the
            // part the blank at a later thread is taken from.
            Event::Settings { line } | Event::Turning { line, .. } => {
                machine_state.before(line);
                if let Some(dw) = decimals.as_mut() {
                    dw.line(line, modal.units, true);
                }
                if let Event::Turning { job: Some(job), .. } = &ev {
                    sink.whole.turning(job, job.span, whole_at(modal));
                }
                machine_state.after(line);
            }
            Event::Cycle { line, job, .. } => {
                machine_state.before(line);
                if let Some(dw) = decimals.as_mut() {
                    dw.line(line, modal.units, true);
                }
                let at = job.span;
                // The thread being read before the cycle is handed over first (its teeth are in
                // the part before the cycle's, for the rapids made while it was read).
                let copy = (*job).clone();
                let mut take = |f| sink.take(f);
                collector.cycle(*job, modal.diameter_x, || machine_state.now(at), &mut take);
                sink.cycle(&copy, modal.diameter_x);
                machine_state.after(line);
            }
        }
        Ok(())
    });
    collector.finish(&mut |f| sink.take(f));
    let mut called_from = None;
    match result {
        Ok(summary) => {
            report.lines = summary.lines;
            report.uncalled = !summary.uncalled.is_empty();
            let mut summary = summary;
            report.diagnostics = std::mem::take(&mut summary.warnings);
            called_from = Some(summary);
        }
        Err(Error::Input(alarm)) => {
            report.stopped = true;
            report.diagnostics.push(alarm);
        }
        Err(e) => return Err(e),
    }
    report.part = sink.whole.view();
    if let Some((span, note)) = sink.whole.stock_note() {
        sink.notes.push(Note::new(span, note));
    }
    report.diagnostics.extend(unknown_starts);
    if let Some(w) = decimals.and_then(decimal::DecimalWords::finding) {
        report.diagnostics.push(w);
    }
    let mut report = finish(report, sink);
    // A finding about a line of a called file names the calls it ran inside, as an error raised
    // there does ("called from line 11 of MAIN.MPF").
    if let Some(summary) = called_from {
        for d in report.diagnostics.iter_mut().filter(|d| d.calls.is_empty()) {
            if let Some(calls) = summary.calls_at(d.span) {
                d.calls = calls.to_vec();
            }
        }
    }
    Ok(report)
}

fn check_apt<R: BufRead>(
    input: R,
    machine: Option<&Machine>,
    opts: &Options,
) -> Result<Report, Error> {
    // Without a machine: no limits, the usual 0.001 mm / 0.0001 inch resolution.
    let neutral;
    let machine = match machine {
        Some(m) => m,
        None => {
            let mut m = Machine::built_in("fanuc")
                .ok_or_else(|| Error::Setup("the built-in profiles are missing".to_string()))?;
            m.name = "apt".into();
            m.limits = Default::default();
            neutral = m;
            &neutral
        }
    };
    let mut report = Report {
        thread_codes: crate::apt::THREAD_STATEMENTS.into(),
        ..Report::default()
    };
    let lexicon = crate::dialect::open(machine)
        .map_err(Error::Setup)?
        .meanings();
    let mut sink = Sink::new(
        machine,
        opts,
        state::Restart("SPINDL/n,CLW or SPINDL/n,CCLW".into()),
    );
    let mut machine_state = state::Reader::new(&lexicon, 0);
    let mut collector: Collector<State> = Collector::new(crest(opts));
    let mut at: Option<Pos> = None;
    let result = crate::apt::run(input, |interp, ev| {
        let mut take = |f| sink.take(f);
        match ev {
            crate::apt::Event::Spindle(s) => machine_state.apt_spindle(s),
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
                    collector.motion(mv, setting, false, || machine_state.now(mv.span), &mut take);
                }
            }
            crate::apt::Event::Cycle(job) => {
                let at = job.span;
                collector.cycle(*job, false, || machine_state.now(at), &mut take);
            }
            crate::apt::Event::End => collector.boundary(&mut take),
            _ => {}
        }
        at = interp.position();
        Ok(())
    });
    collector.finish(&mut |f| sink.take(f));
    match result {
        Ok(summary) => {
            report.lines = summary.lines;
            report.uncalled = !summary.uncalled.is_empty();
            report.diagnostics = summary.warnings;
        }
        Err(Error::Input(alarm)) => {
            report.stopped = true;
            report.diagnostics.push(alarm);
        }
        Err(e) => return Err(e),
    }
    Ok(finish(report, sink))
}

/// The report with the threads' findings, repeats merged, in line order.
fn finish(mut report: Report, mut sink: Sink) -> Report {
    report.threads = sink.threads;
    report.diagnostics.extend(sink.found);
    report.diagnostics.append(&mut sink.whole.found);
    report.blanks = sink.blanks;
    report.diagnostics = merge_repeats(std::mem::take(&mut report.diagnostics));
    report
        .diagnostics
        .sort_by_key(|d| (d.span.line, d.span.column, d.severity != Severity::Error));
    report.notes = merge_notes(sink.notes);
    report
}

/// One note for a message said of several threads (the same assumption for every thread of a
/// long program), naming the other lines.
fn merge_notes(notes: Vec<Note>) -> Vec<Note> {
    // Found by message and line in hash sets: a long program has a note for each of thousands
    // of threads, and looking through the list for each was quadratic.
    let mut out: Vec<(Note, Vec<u32>)> = Vec::with_capacity(notes.len());
    let mut index: HashMap<String, usize> = HashMap::new();
    let mut named: HashSet<(usize, u32)> = HashSet::new();
    for n in notes {
        match index.get(&n.message) {
            Some(&i) => {
                let (o, lines) = &mut out[i];
                if o.span.line != n.span.line && named.insert((i, n.span.line)) {
                    lines.push(n.span.line);
                }
            }
            None => {
                index.insert(n.message.clone(), out.len());
                out.push((n, Vec::new()));
            }
        }
    }
    out.into_iter()
        .map(|(mut n, lines)| {
            if !lines.is_empty() {
                let shown: Vec<String> = lines.iter().take(8).map(u32::to_string).collect();
                n.message.push_str(&format!(
                    " (also for the thread{} at line{} {}{})",
                    if lines.len() == 1 { "" } else { "s" },
                    if lines.len() == 1 { "" } else { "s" },
                    shown.join(", "),
                    if lines.len() > 8 { ", …" } else { "" }
                ));
            }
            n
        })
        .collect()
}

/// One finding for a message repeated on several blocks (a dialect's warning on each block of a
/// modal G92), naming the other lines.
fn merge_repeats(diags: Vec<Diagnostic>) -> Vec<Diagnostic> {
    let mut out: Vec<(Diagnostic, Vec<u32>)> = Vec::with_capacity(diags.len());
    let mut index: HashMap<(Code, Severity, String), usize> = HashMap::new();
    // A line a loop runs again is listed once (and the first finding's own line not at all).
    let mut listed: std::collections::HashSet<(usize, u32)> = std::collections::HashSet::new();
    for d in diags {
        let key = (d.code, d.severity, d.message.clone());
        match index.get(&key) {
            Some(&i) => {
                if d.span.line != out[i].0.span.line && listed.insert((i, d.span.line)) {
                    out[i].1.push(d.span.line);
                }
            }
            None => {
                index.insert(key, out.len());
                out.push((d, Vec::new()));
            }
        }
    }
    out.into_iter()
        .map(|(mut d, lines)| {
            if !lines.is_empty() {
                let shown: Vec<String> = lines.iter().take(8).map(u32::to_string).collect();
                d.message.push_str(&format!(
                    " (also on line{} {}{})",
                    if lines.len() == 1 { "" } else { "s" },
                    shown.join(", "),
                    if lines.len() > 8 { ", …" } else { "" }
                ));
            }
            d
        })
        .collect()
}

/// The units, X mode and resolution a move of the part is read at.
fn whole_at(modal: &crate::gcode::Modal) -> whole::At {
    whole::At {
        units: modal.units,
        diameter_x: modal.diameter_x,
        tolerance: modal.resolution().increment_mm(),
    }
}

/// Where a move is written: its G word, else the block's first word (as the thread reader has it).
fn move_span(line: &crate::gcode::Line) -> Span {
    line.words
        .iter()
        .find(|w| w.letter == b'G')
        .or(line.words.first())
        .map_or(line.span(), |w| w.span)
}

/// Passes as `pass 3`, `passes 1–4`, `passes 1, 3, 5–8`.
pub fn passes_list(passes: &[u32]) -> String {
    let mut sorted = passes.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    if sorted.len() == 1 {
        return format!("pass {}", sorted[0]);
    }
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < sorted.len() {
        let mut j = i;
        while j + 1 < sorted.len() && sorted[j + 1] == sorted[j] + 1 {
            j += 1;
        }
        parts.push(match j - i {
            0 => sorted[i].to_string(),
            1 => format!("{}, {}", sorted[i], sorted[j]),
            _ => format!("{}–{}", sorted[i], sorted[j]),
        });
        i = j + 1;
    }
    format!("passes {}", parts.join(", "))
}

/// A number for a message (an angle, a count): up to 4 decimals, no trailing zeros.
pub fn number(v: f64) -> String {
    length(Units::Mm, v)
}

/// A length for a message: program units, up to 4 decimals, no trailing zeros.
pub fn length(units: Units, mm: f64) -> String {
    units.show(mm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_are_listed_as_ranges() {
        assert_eq!(passes_list(&[3]), "pass 3");
        assert_eq!(passes_list(&[1, 2, 3, 4]), "passes 1–4");
        assert_eq!(passes_list(&[5, 1, 3, 6, 7, 8]), "passes 1, 3, 5–8");
        assert_eq!(passes_list(&[2, 3]), "passes 2, 3");
    }

    /// A Sinumerik block with a setting in it (`LIMS=`) is read in the dialect's own syntax: the
    /// spindle words on it count as on any other block. The speed is the same in both programs,
    /// so are the findings: without the block's words the first would say "no spindle speed".
    #[test]
    fn spindle_words_on_a_sinumerik_block_with_a_setting_count() {
        let machine = crate::machine::Machine::built_in("sinumerik").unwrap();
        let program = |spindle: &str| {
            format!(
                "G18 G90 G95 DIAMON\nT1 D1\n{spindle}\nG0 X30 Z10\nCYCLE97(2.5,,0,-30,20,20,5,2,1.534,0.05,29,0,8,1,3,1)\nM30\n"
            )
        };
        let codes = |spindle: &str| -> Vec<(crate::diag::Code, String)> {
            let text = program(spindle);
            check(
                text.as_bytes(),
                Source::Gcode(&machine),
                &Options::default(),
            )
            .unwrap()
            .diagnostics
            .into_iter()
            .map(|d| (d.code, d.message))
            .collect()
        };
        assert_eq!(codes("G97 S400 LIMS=2000 M3"), codes("G97 S400 M3"));
        assert!(
            codes("G97 S400 M3").is_empty(),
            "{:?}",
            codes("G97 S400 M3")
        );
        let css = codes("G96 S120 LIMS=2000 M3");
        assert_eq!(css, codes("G96 S120 M3"));
        assert!(css[0].1.contains("constant surface speed (G96)"), "{css:?}");
    }
}

#[cfg(test)]
mod proptests {
    use super::*;

    /// Blocks of every kind the check reads: plain and thread moves, cycles of each controller,
    /// spindle words, tool changes, words without decimal points, and errors.
    const WORDS: &[&str] = &[
        "G0 X40. Z5.",
        "G0 X40 Z5",
        "G00 X29.2",
        "G32 Z-30. F2.",
        "G32 Z-30 F2",
        "G32 X33. Z-32.",
        "G33 Z-20 K1.5",
        "Z5.",
        "X28.7",
        "G1 Z-3 F0.1",
        "G97 S800 M3",
        "G96 S150",
        "G50 S2000",
        "T0303",
        "M30",
        "G92 X29.2 Z-30. F2.",
        "G76 P020060 Q100 R0.05",
        "G76 X27.546 Z-30. P1227 Q400 F2.",
        "G76 X27.5 Z-30 K1.2 D0.4 F2 A60",
        "G78 P020545 Q0.15 R0.5",
        "G78 X16 Z-20 P1.2 Q0.3 F2",
        "G78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1",
        "G33X.212Z-.5I.012K.05PC",
        "G76 P2.5 Z-30 I-1.0 J0.3 K1.5335",
        "G20",
        "G21",
        "G0 X1.2.3",
        "G55.5",
        "G04 X1000",
    ];

    proptest::proptest! {
        /// `check` never panics, whatever the blocks, the controller and the options; its findings
        /// have places and its JSON parses.
        #[test]
        fn check_never_panics(
            lines in proptest::collection::vec(proptest::sample::select(WORDS), 0..30),
            which in 0usize..crate::machine::BUILT_IN.len(),
            stock in proptest::option::of(10.0f64..80.0),
            face in proptest::option::of(-10.0f64..10.0),
            thread in proptest::option::of(proptest::sample::select(vec!["M30x2-6g", "M24x1.5-6H", "3/4-10 UNC-2A"])),
            nose in proptest::option::of(0.0f64..0.5),
        ) {
            let machine = Machine::built_in(crate::machine::BUILT_IN[which].0).unwrap();
            let src = lines.join("\n");
            let opts = Options {
                stock_diameter: stock,
                stock_start: face,
                tip: nose.map(|radius| Tip::Radius { radius }),
                thread: thread.map(|n| crate::thread::standard::lookup(n).unwrap()),
                ..Options::default()
            };
            if let Ok(report) = check(src.as_bytes(), Source::Gcode(&machine), &opts) {
                let json = serde_json::to_string(&report.findings("p.nc")).unwrap();
                proptest::prop_assert!(serde_json::from_str::<serde_json::Value>(&json).is_ok());
                for d in &report.diagnostics {
                    proptest::prop_assert!(d.span.line <= lines.len() as u32 + 1, "{d:?}");
                }
            }
        }
    }
}
