//! Streams a whole program through a dialect, line by line, in constant memory: blocks that are not
//! threading cycles pass through byte for byte; each cycle becomes a [`Job`] and then motion.

use std::io::{self, BufRead, Write};

use serde::Serialize;

use crate::diag::Diagnostic;
use crate::dialect::{self, Read};
use crate::eol::{self, LineEnding};
use crate::gcode::{Conventions, Line, Modal, MotionMode, PlainMove, Reader};
use crate::interp::{Control, Lang};
use crate::machine::Machine;
use crate::post::{self, json_num};
use crate::thread::{Job, Pass, PassKind};
use crate::toolpath::{self, Motion, MotionKind};
use crate::turning::TurningJob;
use crate::units::Units;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: the program, with its place.
    #[error("{0}")]
    Input(Diagnostic),
    /// The output could not be written.
    #[error("cannot write the output: {0}")]
    Io(#[from] io::Error),
    /// The machine profile cannot be used.
    #[error("{0}")]
    Setup(String),
}

impl From<Diagnostic> for Error {
    fn from(d: Diagnostic) -> Error {
        Error::Input(d)
    }
}

/// What happened on one line.
pub enum Event<'a, 'l> {
    /// A block that is not part of a threading cycle, with the move it makes, if any.
    Plain {
        line: &'a Line<'l>,
        mv: Option<PlainMove>,
    },
    /// A cycle block that only sets values.
    Settings { line: &'a Line<'l> },
    /// A complete cycle, with the dialect that read it (for its own way of writing it).
    Cycle {
        line: &'a Line<'l>,
        job: Box<Job>,
        dialect: &'a dyn dialect::Dialect,
    },
    /// A turning cycle's block: the cycle complete (`job`), or a block the control does not run
    /// where it stands (`None`: the cycle's block that reads the contour that follows, and that
    /// contour's blocks). A cycle with a contour is complete at the contour's last block, which
    /// is then `line` (`job.line` is the cycle's own); the tool is back at the cycle's start point
    /// after it.
    Turning {
        line: &'a Line<'l>,
        job: Option<Box<TurningJob>>,
        dialect: &'a dyn dialect::Dialect,
    },
}

impl<'a, 'l> Event<'a, 'l> {
    /// The line of the event.
    pub fn line(&self) -> &'a Line<'l> {
        match self {
            Event::Plain { line, .. }
            | Event::Settings { line }
            | Event::Cycle { line, .. }
            | Event::Turning { line, .. } => line,
        }
    }
}

pub mod ahead;
mod interpreted;

pub use interpreted::{write_executed_block, Output, Where};

/// What a run found besides its output.
#[derive(Debug, Default)]
pub struct Summary {
    pub lines: u32,
    pub cycles: u32,
    pub warnings: Vec<Diagnostic>,
    /// The line from which the macro interpreter ran the program (its first line of control
    /// flow), if it had any.
    pub interpreted_from: Option<u32>,
    /// Blocks and statements the interpreter executed.
    pub executed: u64,
    /// The subroutines a program defines when it calls none of them (a subroutine file, run
    /// without `Options::call`): none of them ran.
    pub uncalled: Vec<String>,
    /// For each line of a called file that ran (by its offset, `diag::FILE_SPACING` and up), the
    /// calls it first ran inside, outermost first: a finding made later about the line (a
    /// thread's, by `check`) names them as an error raised there does.
    pub called_from: std::collections::BTreeMap<u64, Vec<crate::diag::Span>>,
}

impl Summary {
    /// The calls the line holding `span` ran inside, when it is a line of a called file.
    pub fn calls_at(&self, span: crate::diag::Span) -> Option<&[crate::diag::Span]> {
        if span.file() == 0 {
            return None;
        }
        self.called_from
            .range(..=span.start)
            .next_back()
            .filter(|(offset, _)| {
                **offset / crate::diag::FILE_SPACING == span.start / crate::diag::FILE_SPACING
            })
            .map(|(_, calls)| calls.as_slice())
    }
}

/// How a program is run.
#[derive(Clone, Debug, PartialEq)]
pub struct Options {
    /// The interpreter stops a program after this many executed blocks (`--max-blocks`).
    pub max_blocks: u64,
    /// `expand`: write the executed program as straight-line code (loops unrolled, calls inlined,
    /// expressions evaluated) instead of the program's own text (`--flatten`).
    pub flatten: bool,
    /// Where calls find programs the program's text does not hold (`--include DIR`): none by
    /// default.
    pub library: Option<crate::interp::library::Library>,
    /// Runs this call of a subroutine or program the input defines instead of the input's own
    /// main program (`--call 'o<thread> call [20] [2.5]'`, `--call 'G65 P9010 A20.'`): the call
    /// is read as the line after the input's last, then the program ends (M2).
    pub call: Option<String>,
    /// Where the tool is before the program's first line (`--start X,Z`).
    pub start: Start,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            max_blocks: crate::interp::Limits::default().max_blocks,
            flatten: false,
            library: None,
            call: None,
            start: Start::Unknown,
        }
    }
}

/// Where the tool is before the program's first line.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Start {
    /// Not known, as at power-on: a cycle that starts where the tool is refuses to start before
    /// the program has placed the tool.
    #[default]
    Unknown,
    /// At (`x`, `z`), as the program writes them at power-on: the profile's units, X on diameter
    /// where the control's X is (`--start X,Z`).
    At { x: f64, z: f64 },
    /// Not known, and a threading cycle whose pass table does not depend on its start point
    /// (Fanuc-family G76 and G92, the one-block G76, GSK's G78) is read all the same: the axes it
    /// took unknown are marked ([`Modal::assumed`]), and what depends on them is reported not
    /// known (`passes` for a cycle shown without the lines before it).
    Unstated,
}

impl Start {
    /// The modal state at the program's first line under this start.
    pub fn apply(self, modal: &mut Modal) {
        match self {
            Start::Unknown => {}
            Start::At { x, z } => modal.place(x, z),
            Start::Unstated => modal.start_unstated = true,
        }
    }
}

/// Runs `input` through the machine's dialect, handing every line to `sink` with the modal state
/// as it stands after the line.
pub fn run<R: BufRead>(
    input: R,
    machine: &Machine,
    sink: impl FnMut(&Modal, Event) -> Result<(), Error>,
) -> Result<Summary, Error> {
    run_with(input, machine, &Options::default(), sink)
}

/// [`run`] with options. A program with control flow is run by the interpreter: `sink` sees every
/// executed block, in the order the control executes them (a cycle run three times comes three
/// times), each with its source line.
pub fn run_with<R: BufRead>(
    input: R,
    machine: &Machine,
    options: &Options,
    sink: impl FnMut(&Modal, Event) -> Result<(), Error>,
) -> Result<Summary, Error> {
    drive(input, machine, options, EverySink(sink))
}

/// [`run_with`] for a caller that needs more than the events ([`Output`]): the text of a program
/// the interpreter runs, and the lines after a program's end.
pub fn run_output<R: BufRead, O: Output>(
    input: R,
    machine: &Machine,
    options: &Options,
    output: &mut O,
) -> Result<Summary, Error> {
    drive(input, machine, options, interpreted::OutputSink(output))
}

/// Where [`drive`] hands the lines.
trait Sink {
    /// Plain lines are not handed to [`event`](Sink::event): their bytes come to
    /// [`pass`](Sink::pass) instead, in runs of consecutive lines (`expand` copies them unchanged,
    /// and one write per run costs far less than one per line).
    const BATCH: bool;
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error>;
    /// The bytes of consecutive plain lines, in order; every plain line exactly once.
    fn pass(&mut self, bytes: &[u8]) -> Result<(), Error>;
    /// The rest of the input after the program's end (M2, M30), which is not run.
    fn unrun(&mut self, _bytes: &[u8]) -> Result<(), Error> {
        Ok(())
    }
    /// The interpreter runs the program from line `line` on.
    fn interpreting(&mut self, _line: u32) -> Result<(), Error> {
        Ok(())
    }
    /// A block the interpreter executed.
    fn interpreted(
        &mut self,
        modal: &Modal,
        ev: Event,
        _ctx: &interpreted::Where,
    ) -> Result<(), Error> {
        self.event(modal, ev)
    }
    /// The interpreter ran to the end: the program's text, from the line it took over
    /// (`text.line(from)`) on.
    fn interpreted_end(&mut self, _text: &crate::interp::Text, _from: usize) -> Result<(), Error> {
        Ok(())
    }
    /// The interpreter set a parameter the dialect reads in lines of its own (Sinumerik's `R7`,
    /// a DEF name).
    fn parameter(&mut self, _name: &str, _value: f64) -> Result<(), Error> {
        Ok(())
    }
    /// Plain lines read ahead ([`ahead`]), for a batching sink.
    fn ahead(&mut self) -> Option<&mut dyn ahead::Ahead> {
        None
    }
}

/// Every line to one closure ([`run`]).
struct EverySink<F>(F);

impl<F: FnMut(&Modal, Event) -> Result<(), Error>> Sink for EverySink<F> {
    const BATCH: bool = false;
    #[inline(always)]
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error> {
        (self.0)(modal, ev)
    }
    fn pass(&mut self, _: &[u8]) -> Result<(), Error> {
        Ok(())
    }
}

/// [`run`]'s loop. With a batching sink, `pending` counts the bytes of the plain lines read but
/// not yet passed on; they lie in the reader's buffer right before the next line, and are passed
/// on before anything else is written, before the reader may read more input (which drops them
/// from its buffer) and before an error returns (so that the output up to the error is what it
/// would be line by line).
fn drive<R: BufRead, S: Sink>(
    input: R,
    machine: &Machine,
    options: &Options,
    sink: S,
) -> Result<Summary, Error> {
    if let Some(call) = &options.call {
        let (text, start) = with_call(input, call)?;
        return dialect::open_with(
            machine,
            Drive {
                input: text.as_slice(),
                machine,
                options,
                sink,
                start: Some(start),
            },
        )
        .map_err(Error::Setup)?;
    }
    dialect::open_with(
        machine,
        Drive {
            input,
            machine,
            options,
            sink,
            start: None,
        },
    )
    .map_err(Error::Setup)?
}

/// The input with `call` as the line after its last, and the program's end after it (`M2`,
/// which ends a program on every control with subprograms); the call's line number.
fn with_call<R: BufRead>(input: R, call: &str) -> Result<(Vec<u8>, u32), Error> {
    let limit = crate::interp::MAX_PROGRAM_BYTES;
    let mut text = Vec::new();
    std::io::Read::read_to_end(&mut input.take(limit as u64 + 1), &mut text)?;
    if text.len() > limit || call.len() > limit {
        return Err(Error::Setup(format!(
            "a program run by a call is held in memory: at most {} MiB",
            limit >> 20
        )));
    }
    if !text.is_empty() && text.last() != Some(&b'\n') {
        text.push(b'\n');
    }
    let line = memchr::memchr_iter(b'\n', &text).count() as u32 + 1;
    // One line: a line break in the call would shift what follows.
    let call = call.replace(['\r', '\n'], " ");
    text.extend_from_slice(call.trim().as_bytes());
    text.extend_from_slice(b"\nM2\n");
    Ok((text, line))
}

/// What a run is given, besides its input and sink.
struct Run<'m> {
    machine: &'m Machine,
    options: &'m Options,
    start: Option<u32>,
}

/// [`drive`]'s arguments, waiting for the dialect.
struct Drive<'m, R, S> {
    input: R,
    machine: &'m Machine,
    options: &'m Options,
    sink: S,
    /// Where the interpreter starts ([`Options::call`]'s line), instead of streaming from line 1.
    start: Option<u32>,
}

impl<R: BufRead, S: Sink> dialect::WithDialect for Drive<'_, R, S> {
    type Output = Result<Summary, Error>;
    fn run<D: dialect::Dialect + 'static>(self, dialect: D) -> Result<Summary, Error> {
        let run = Run {
            machine: self.machine,
            options: self.options,
            start: self.start,
        };
        drive_with(self.input, &run, self.sink, dialect)
    }
}

/// [`drive`] with the dialect's own type.
///
/// A program with control flow is found out where its first line of control flow comes (a line
/// the lexer refuses that is the dialect's macro syntax, a call, a return): the rest of the
/// program goes to the interpreter from that line on, with the modal state as it stands there
/// (docs/architecture.md, "The interpreter"). A program's end (M2, M30) ends the run; the lines
/// after it are not run.
fn drive_with<R: BufRead, S: Sink, D: dialect::Dialect>(
    input: R,
    run: &Run,
    mut sink: S,
    mut dialect: D,
) -> Result<Summary, Error> {
    let (machine, options) = (run.machine, run.options);
    let conv = dialect.conventions().clone();
    let mut modal = Modal::for_machine(&conv, machine);
    options.start.apply(&mut modal);
    // A G code the controller does not have is its alarm.
    modal.vocabulary = Some(dialect.vocabulary());
    let mut reader = Reader::new(input).with_syntax(conv.syntax);
    let macros = dialect.macros();
    if macros.is_some_and(|m| m.lang != Lang::Ngc) {
        // A Fanuc-style GOTO (a Sinumerik GOTOB) may jump back to a plain line before the first
        // macro statement.
        reader.keep_prefix(crate::interp::PREFIX_KEPT);
    }
    let mut summary = Summary::default();
    if let Some(start) = run.start {
        // A call of a subroutine the input defines: the interpreter runs it from the call's line,
        // nothing of the input's own flow before.
        let Some(syntax) = macros else {
            return Err(Error::Setup(
                "a call (--call) needs a controller with subprograms: this one has none".into(),
            ));
        };
        let switch = interpreted::Switch {
            offset: 0,
            line: 1,
            start,
            syntax,
        };
        return interpreted::switch(
            reader, switch, machine, options, dialect, modal, sink, summary,
        );
    }
    let mut pending = 0usize;
    let mut seam = match sink.ahead() {
        Some(ahead) if S::BATCH => ahead.first_seam(),
        _ => u64::MAX,
    };
    loop {
        if reader.offset() >= seam {
            seam = at_seam(
                &mut reader,
                &mut sink,
                &dialect,
                &mut modal,
                &mut summary,
                &mut pending,
            )?;
        }
        // Most lines are plain lines that the reader's fast path lexes and that are none of the
        // dialect's business (its prefilter says so without `read`, which would return
        // `Read::Plain` and leave everything as it is): this loop takes them as long as they come.
        // Nothing else happens in it, so that the line stays in registers. (A dialect with
        // macros also sends the lines that may be calls or a program's end the general way: one
        // test of the word summary.)
        while let Some(line) = reader.next_plain_line() {
            if dialect.prefilter(&line)
                || macros
                    .as_ref()
                    .is_some_and(|m| m.control(&line) != Control::No)
            {
                // Read again below, the general way.
                let len = line.raw.len();
                reader.put_back(len);
                break;
            }
            summary.lines = line.number;
            plain_line(&line, &mut modal, &conv, &mut sink, &mut pending)?;
            if reader.offset() >= seam {
                break;
            }
        }
        if reader.offset() >= seam {
            continue;
        }
        if S::BATCH && pending > 0 && reader.may_read() {
            sink.pass(handed_out(&reader, pending, 0)?)?;
            pending = 0;
        }
        let offset = reader.offset();
        // Not the fast path again: it has just said no, or it read a line for the dialect, which
        // is rare enough to be read again the reference way.
        let line = match reader.next_line_by_reference() {
            Some(Ok(line)) => line,
            Some(Err(e)) => {
                // The line in error has been consumed; the run ends before it, or the
                // interpreter takes over from it.
                let consumed = (reader.offset() - offset) as usize;
                if S::BATCH && pending > 0 {
                    sink.pass(handed_out(&reader, pending, consumed)?)?;
                }
                if let Some(syntax) = macros {
                    let text = reader.handed_out(consumed).unwrap_or_default();
                    if syntax.looks_like_macro(text) {
                        let switch = interpreted::Switch {
                            offset,
                            line: e.span.line,
                            start: e.span.line,
                            syntax,
                        };
                        return interpreted::switch(
                            reader, switch, machine, options, dialect, modal, sink, summary,
                        );
                    }
                }
                return Err(e.into());
            }
            None => break,
        };
        summary.lines = line.number;
        if let Some(syntax) = macros {
            match syntax.control(&line) {
                Control::No => {}
                Control::Interpret => {
                    flush_before(&mut sink, line.before, &mut pending)?;
                    let switch = interpreted::Switch {
                        offset: line.offset,
                        line: line.number,
                        start: line.number,
                        syntax,
                    };
                    return interpreted::switch(
                        reader, switch, machine, options, dialect, modal, sink, summary,
                    );
                }
                Control::End => {
                    if !dialect.prefilter(&line) {
                        plain_line(&line, &mut modal, &conv, &mut sink, &mut pending)?;
                    } else {
                        dialect_line(
                            line,
                            &mut dialect,
                            &mut modal,
                            &conv,
                            &mut sink,
                            &mut summary,
                            &mut pending,
                        )?;
                    }
                    if S::BATCH && pending > 0 {
                        sink.pass(handed_out(&reader, pending, 0)?)?;
                    }
                    dialect.end_of_input()?;
                    let unrun = reader.pass_rest(|b| sink.unrun(b))?;
                    summary.lines += unrun as u32;
                    return Ok(summary);
                }
            }
        }
        // Most lines are not the dialect's business: its prefilter says so without `read` (which
        // would return `Read::Plain` and leave everything as it is).
        if !dialect.prefilter(&line) {
            plain_line(&line, &mut modal, &conv, &mut sink, &mut pending)?;
        } else {
            dialect_line(
                line,
                &mut dialect,
                &mut modal,
                &conv,
                &mut sink,
                &mut summary,
                &mut pending,
            )?;
        }
    }
    if S::BATCH && pending > 0 {
        sink.pass(handed_out(&reader, pending, 0)?)?;
    }
    dialect.end_of_input()?;
    Ok(summary)
}

/// The run at a seam of the lines read ahead ([`ahead`]): takes the lines read from here when its
/// dialect is at rest and its state is the one the look ahead assumed. The next seam.
#[cold]
#[inline(never)]
fn at_seam<R: BufRead, S: Sink, D: dialect::Dialect>(
    reader: &mut Reader<R>,
    sink: &mut S,
    dialect: &D,
    modal: &mut Modal,
    summary: &mut Summary,
    pending: &mut usize,
) -> Result<u64, Error> {
    let offset = reader.offset();
    let Some(ahead) = sink.ahead() else {
        return Ok(u64::MAX);
    };
    let at_rest = dialect.at_rest();
    let (taken, next) = ahead.at(offset, modal, at_rest);
    // (While the reader keeps the program's beginning for a jump back, it reads as ever: when it
    // stops keeping it depends on when it reads more, which a skip would move.)
    match taken {
        Some(t) if at_rest && t.bytes > 0 && !reader.keeping_prefix() && t.entry.same(modal) => {
            reader.skip(t.bytes, t.lines, pending, |b| sink.pass(b))?;
            *modal = t.exit;
            summary.lines = reader.line_number();
            Ok(next)
        }
        // Asked again at the next line, at the latest.
        _ => Ok(next.max(offset + 1)),
    }
}

/// A line that is no cycle's: its modal state, and its bytes to the sink.
#[inline(always)]
fn plain_line<S: Sink>(
    line: &Line,
    modal: &mut Modal,
    conv: &Conventions,
    sink: &mut S,
    pending: &mut usize,
) -> Result<(), Error> {
    // A batching sink copies the line and needs only the state after it.
    let applied = if S::BATCH {
        modal.advance(conv, line)
    } else {
        modal.apply(conv, line)
    };
    match applied {
        Ok(mv) => {
            if S::BATCH {
                *pending += line.raw.len();
                Ok(())
            } else {
                sink.event(modal, Event::Plain { line, mv })
            }
        }
        Err(e) => {
            flush_before(sink, line.before, pending)?;
            Err(e.into())
        }
    }
}

/// A line the dialect's prefilter wants: the dialect reads it. Not inlined: the run loop stays
/// small, and the lines it takes itself stay in registers (docs/performance.md).
#[inline(never)]
fn dialect_line<S: Sink, D: dialect::Dialect>(
    line: Line,
    dialect: &mut D,
    modal: &mut Modal,
    conv: &Conventions,
    sink: &mut S,
    summary: &mut Summary,
    pending: &mut usize,
) -> Result<(), Error> {
    let before = summary.warnings.len();
    let read = dialect.read(&line, modal, &mut summary.warnings);
    if S::BATCH && !matches!(read, Ok(Read::Plain | Read::Applied(_) | Read::Own { .. })) {
        flush_before(sink, line.before, pending)?;
    }
    match read? {
        Read::Plain => plain_line(&line, modal, conv, sink, pending)?,
        Read::Applied(mv) => {
            if S::BATCH {
                *pending += line.raw.len();
            } else {
                sink.event(modal, Event::Plain { line: &line, mv })?;
            }
        }
        Read::Own { mv, words } => {
            if S::BATCH {
                *pending += line.raw.len();
            } else {
                let mut index = [0; 32];
                let own = line.with_words(&words, &mut index);
                sink.event(modal, Event::Plain { line: &own, mv })?;
            }
        }
        Read::Settings => sink.event(modal, Event::Settings { line: &line })?,
        Read::Cycle(job) => {
            summary.cycles += 1;
            // Fanuc-style cycles end where they started; LinuxCNC's G76 at its Z end.
            modal.cycle_ended(job.end_point());
            sink.event(
                modal,
                Event::Cycle {
                    line: &line,
                    job,
                    dialect,
                },
            )?;
            modal.assumed = [false; 2];
        }
        Read::Turning(job) => {
            if let Some(job) = &job {
                summary.cycles += 1;
                // Every turning cycle ends at its start point.
                modal.position = crate::gcode::Position::at(job.end_point());
            }
            sink.event(
                modal,
                Event::Turning {
                    line: &line,
                    job,
                    dialect,
                },
            )?;
        }
    }
    for w in &mut summary.warnings[before..] {
        if w.span.line == 0 {
            w.span = line.span();
        }
    }
    Ok(())
}

/// Passes on the pending plain lines, which end where `before` (a line's
/// [`before`](Line::before)) ends.
#[cold]
fn flush_before<S: Sink>(sink: &mut S, before: &[u8], pending: &mut usize) -> Result<(), Error> {
    if S::BATCH && *pending > 0 {
        let run = before
            .len()
            .checked_sub(*pending)
            .and_then(|from| before.get(from..))
            .ok_or_else(lost_run)?;
        *pending = 0;
        sink.pass(run)?;
    }
    Ok(())
}

/// The `pending` bytes handed out before the last `skip` bytes.
fn handed_out<R: BufRead>(reader: &Reader<R>, pending: usize, skip: usize) -> Result<&[u8], Error> {
    reader
        .handed_out(pending + skip)
        .map(|b| &b[..pending])
        .ok_or_else(lost_run)
}

/// Cannot happen: `drive` passes the pending lines on before the reader may drop them.
#[cold]
fn lost_run() -> Error {
    Error::Io(io::Error::other(
        "internal error: lines to copy left the read buffer",
    ))
}

/// Every cycle of a program, for tests and library users (holds them all in memory).
pub fn jobs<R: BufRead>(input: R, machine: &Machine) -> Result<Vec<Job>, Error> {
    let mut jobs = Vec::new();
    run(input, machine, |_, ev| {
        if let Event::Cycle { job, .. } = ev {
            jobs.push(*job);
        }
        Ok(())
    })?;
    Ok(jobs)
}

/// `threadcut expand`: the program with each cycle replaced by plain moves in the controller's own
/// format. Other lines are copied byte for byte.
pub fn expand_gcode<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    machine: &Machine,
) -> Result<Summary, Error> {
    expand_gcode_with(input, out, machine, &Options::default())
}

/// [`expand_gcode`] with options. A program with control flow keeps its text: each cycle block
/// is replaced in place when every run of it expands to the same moves, and is an error
/// otherwise; with [`Options::flatten`] the executed program is written as straight-line code.
pub fn expand_gcode_with<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    machine: &Machine,
    options: &Options,
) -> Result<Summary, Error> {
    expand_gcode_to(input, &mut post::Now(out), machine, options)
}

/// [`expand_gcode_with`] into a writer that may write each cycle's moves later, in their place
/// ([`post::MovesOut`]): the command formats them on a second thread.
pub fn expand_gcode_to<R: BufRead>(
    input: R,
    out: &mut dyn post::MovesOut,
    machine: &Machine,
    options: &Options,
) -> Result<Summary, Error> {
    expand_gcode_ahead(input, out, machine, options, None)
}

/// [`expand_gcode_to`] taking plain lines read ahead ([`ahead`]): the command reads a later part
/// of a long program on its second core. The output and the errors are those of
/// [`expand_gcode_to`].
pub fn expand_gcode_ahead<'o, R: BufRead>(
    mut input: R,
    out: &'o mut dyn post::MovesOut,
    machine: &Machine,
    options: &Options,
    ahead: Option<&'o mut dyn ahead::Ahead>,
) -> Result<Summary, Error> {
    let d = dialect::open(machine).map_err(Error::Setup)?;
    // The lines an expansion writes end as the program's first line does (CRLF in, CRLF out);
    // copied lines keep their own bytes.
    let ending = LineEnding::peek(&mut input)?;
    let format = d.format();
    let distance_words = d.conventions().g90_g91_distance;
    let keeps_prefix = d.macros().is_some_and(|m| m.lang != Lang::Ngc);
    drive(
        input,
        machine,
        options,
        ExpandSink {
            out,
            format,
            distance_words,
            ending,
            interp: interpreted::ExpandState::new(options.flatten, keeps_prefix),
            ahead,
        },
    )
}

/// `expand_gcode`'s output: plain lines are copied in runs, cycles expanded.
struct ExpandSink<'o> {
    out: &'o mut dyn post::MovesOut,
    format: post::Format,
    distance_words: bool,
    ending: LineEnding,
    /// What the interpreter's part of the run needs (and the expansions of the cycles before it
    /// that a jump may run again).
    interp: interpreted::ExpandState,
    ahead: Option<&'o mut dyn ahead::Ahead>,
}

impl ExpandSink<'_> {
    /// `ev` expanded to the output, as this run writes it.
    fn write_event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error> {
        expand_ending(
            self.out,
            &self.format,
            self.distance_words,
            self.ending,
            modal,
            ev,
        )
    }

    /// `ev` expanded into `buf` instead, as [`write_event`](Self::write_event) would write it.
    fn event_text(&self, buf: &mut Vec<u8>, modal: &Modal, ev: Event) -> Result<(), Error> {
        expand_ending(
            buf,
            &self.format,
            self.distance_words,
            self.ending,
            modal,
            ev,
        )
    }
}

impl Sink for ExpandSink<'_> {
    const BATCH: bool = true;
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error> {
        if self.interp.records_prefix() {
            return interpreted::expand_recorded(self, modal, ev);
        }
        self.write_event(modal, ev)
    }
    #[inline(always)]
    fn pass(&mut self, bytes: &[u8]) -> Result<(), Error> {
        Ok(self.out.write_all(bytes)?)
    }
    fn unrun(&mut self, bytes: &[u8]) -> Result<(), Error> {
        Ok(self.out.write_all(bytes)?)
    }
    fn interpreting(&mut self, line: u32) -> Result<(), Error> {
        self.interp.start(line);
        Ok(())
    }
    fn interpreted(
        &mut self,
        modal: &Modal,
        ev: Event,
        ctx: &interpreted::Where,
    ) -> Result<(), Error> {
        interpreted::expand_interpreted(self, modal, ev, ctx)
    }
    fn interpreted_end(&mut self, text: &crate::interp::Text, from: usize) -> Result<(), Error> {
        interpreted::expand_end(self, text, from)
    }
    fn ahead(&mut self) -> Option<&mut dyn ahead::Ahead> {
        match &mut self.ahead {
            Some(a) => Some(&mut **a),
            None => None,
        }
    }
    fn parameter(&mut self, name: &str, value: f64) -> Result<(), Error> {
        // `--flatten` copies the lines the dialect reads itself as written: the values they read
        // are written before them (`R7=90`), so that the straight-line program reads the same.
        if self.interp.flatten {
            let value = if value == 0.0 { 0.0 } else { value };
            let mut out = eol::Writer::new(&mut *self.out, self.ending);
            writeln!(out, "{name}={value}")?;
        }
        Ok(())
    }
}

/// [`expand_event`] with the generated lines ending as the program's lines do.
fn expand_ending(
    out: &mut dyn post::MovesOut,
    format: &post::Format,
    distance_words: bool,
    ending: LineEnding,
    modal: &Modal,
    ev: Event,
) -> Result<(), Error> {
    match ending {
        LineEnding::Lf => expand_event(out, format, distance_words, modal, ev),
        LineEnding::CrLf => expand_event(
            &mut eol::Writer::new(out, LineEnding::CrLf),
            format,
            distance_words,
            modal,
            ev,
        ),
    }
}

/// `expand_gcode` for the lines that are part of a cycle.
#[inline(never)]
fn expand_event(
    out: &mut dyn post::MovesOut,
    base_format: &post::Format,
    distance_words: bool,
    modal: &Modal,
    ev: Event,
) -> Result<(), Error> {
    // X as the program writes it at this point (LinuxCNC's G7/G8 change it mid-program).
    let format = post::Format {
        diameter_x: modal.diameter_x,
        ..base_format.clone()
    };
    match ev {
        Event::Plain { line, .. } => out.write_all(line.raw)?,
        Event::Settings { line } => {
            if let Some(c) = format.comment(&format!(
                "threadcut: line {} sets the cycle that follows",
                line.number
            )) {
                writeln!(out, "{c}")?;
            }
        }
        Event::Cycle { line, job, dialect } => {
            post::expressible(&format, &job)?;
            // Motion needs no chip areas.
            let passes = crate::thread::plan::plan_geometry(&job)?;
            let path = toolpath::build_with(&job, &passes)?;
            let rough = passes.iter().filter(|p| p.kind == PassKind::Rough).count();
            // Built without `format!` (its machinery cost more than the cycle's plan).
            let mut text = String::with_capacity(96);
            text.push_str("threadcut: ");
            text.push_str(job.controller);
            text.push_str(" cycle of line ");
            crate::text::push_decimal(&mut text, u64::from(line.number));
            text.push_str(" as ");
            crate::text::push_rough_and_finishing(&mut text, rough, passes.len() - rough);
            if let Some(mut c) = format.comment(&text) {
                c.push('\n');
                out.write_all(c.as_bytes())?;
            }
            match dialect.write_cycle(out, &job, &passes, &path) {
                // The controller's own form is a cycle too: it leaves the modal state as the
                // original cycle does.
                Some(written) => written?,
                None => {
                    // The moves are absolute: under incremental distance mode, switch to G90
                    // around them.
                    let incremental = distance_words && !modal.absolute;
                    if incremental {
                        writeln!(out, "G90")?;
                    }
                    let last_lead = last_lead(&path);
                    out.moves(post::Moves {
                        format: format.clone(),
                        units: job.units,
                        path,
                    })?;
                    if incremental {
                        writeln!(out, "G91")?;
                    }
                    restore_modal_state(out, &format, modal, last_lead)?;
                }
            }
        }
        Event::Turning { line, job, .. } => {
            expand_turning(out, &format, distance_words, modal, line, job.as_deref())?
        }
    }
    Ok(())
}

/// `expand_gcode` for a turning cycle's block. A block the control does not run where it stands
/// (the cycle's block that reads a contour, the contour's blocks) is written as a comment (or left
/// out where the controller has none), so that the expanded program does not run it either; at
/// the block that completes the cycle, its moves follow (`docs/dialects/fanuc.md`, "Turning
/// cycles").
fn expand_turning(
    out: &mut dyn Write,
    format: &post::Format,
    distance_words: bool,
    modal: &Modal,
    line: &Line,
    job: Option<&TurningJob>,
) -> Result<(), Error> {
    let text = String::from_utf8_lossy(line.text);
    let own = job.is_some_and(|j| j.line == line.number);
    if !own {
        let note = format!("threadcut: not run here: {}", text.trim());
        if let Some(c) = format.comment(&note) {
            writeln!(out, "{c}")?;
        }
    }
    let Some(job) = job else {
        return Ok(());
    };
    let moves = job.moves()?;
    let note = format!(
        "threadcut: {} turning cycle of line {} as {}",
        job.controller,
        job.line,
        crate::text::count(moves.len(), "move", "moves")
    );
    if let Some(c) = format.comment(&note) {
        writeln!(out, "{c}")?;
    }
    let path = toolpath::Toolpath {
        start: job.start(),
        motions: moves,
    };
    let incremental = distance_words && !modal.absolute;
    if incremental {
        writeln!(out, "G90")?;
    }
    post::write_moves(out, format, job.units, &path)?;
    if incremental {
        writeln!(out, "G91")?;
    }
    // The motion mode of before the cycle (a box cycle stays modal: the program's next block of
    // axis words repeats it, as the original does — the expanded text has none to repeat).
    let mode = match modal.motion {
        MotionMode::Feed => Some(format.feed),
        MotionMode::ArcCw => Some("G2"),
        MotionMode::ArcCcw => Some("G3"),
        MotionMode::Thread => Some(format.thread),
        MotionMode::Rapid | MotionMode::Cycle => None,
    };
    if let Some(m) = mode {
        writeln!(out, "{m}")?;
    }
    Ok(())
}

/// After an expansion the output's modal state must match what the original program has after its
/// cycle: the motion mode of before the cycle (a cycle is one-shot) and the F register.
fn restore_modal_state(
    out: &mut dyn Write,
    format: &post::Format,
    modal: &Modal,
    last_lead: Option<f64>,
) -> io::Result<()> {
    let mut block = String::new();
    match modal.motion {
        MotionMode::Feed => block.push_str(format.feed),
        MotionMode::ArcCw => block.push_str("G2"),
        MotionMode::ArcCcw => block.push_str("G3"),
        MotionMode::Thread => block.push_str(format.thread),
        MotionMode::Rapid | MotionMode::Cycle => {}
    }
    // Only where the lead word is F does a thread move change the F register.
    let last_lead = last_lead.filter(|_| format.lead_letter == 'F');
    if let (Some(f), Some(lead)) = (modal.f_word, last_lead) {
        let digits = format.lead_decimals[(modal.units == Units::Inch) as usize];
        let want = post::number(f, digits, format.trailing_zeros);
        if want != post::number(modal.units.from_mm(lead), digits, format.trailing_zeros) {
            if !block.is_empty() {
                block.push(' ');
            }
            block.push('F');
            block.push_str(&want);
        }
    }
    if !block.is_empty() {
        writeln!(out, "{block}")?;
    }
    Ok(())
}

/// The lead of a path's last thread move.
fn last_lead(path: &toolpath::Toolpath) -> Option<f64> {
    path.motions.iter().rev().find_map(|m| match m.kind {
        MotionKind::Thread { lead, .. } => Some(lead),
        _ => None,
    })
}

/// `threadcut expand --format jsonl`: one JSON object per motion, program units, X as a radius.
pub fn expand_jsonl<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    machine: &Machine,
) -> Result<Summary, Error> {
    expand_jsonl_with(input, out, machine, &Options::default())
}

/// [`expand_jsonl`] with options: a program with control flow lists the motion of its execution.
pub fn expand_jsonl_with<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    machine: &Machine,
    options: &Options,
) -> Result<Summary, Error> {
    run_with(input, machine, options, |modal, ev| {
        match ev {
            Event::Plain { line, mv: Some(mv) } => {
                let units = modal.units;
                let m = |kind| Motion {
                    kind,
                    to: mv.to,
                    pass: 0,
                    line: line.number,
                };
                let mut text = match mv.mode {
                    MotionMode::Rapid => post::motion_json(&m(MotionKind::Rapid), units),
                    MotionMode::Feed => post::motion_json(&m(MotionKind::Feed), units),
                    MotionMode::Thread => post::motion_json(
                        &m(MotionKind::Thread {
                            // Already along the move's longer axis (`Modal::apply`).
                            lead: mv.lead.unwrap_or(0.0),
                            dlead: 0.0,
                            phase_deg: mv.phase_deg,
                        }),
                        units,
                    ),
                    MotionMode::ArcCw | MotionMode::ArcCcw => format!(
                        r#"{{"kind":"arc","x":{},"z":{},"cw":{},"pass":0,"line":{}}}"#,
                        json_num(units.from_mm(mv.to.x)),
                        json_num(units.from_mm(mv.to.z)),
                        mv.mode == MotionMode::ArcCw,
                        line.number
                    ),
                    MotionMode::Cycle => return Ok(()),
                };
                // A move whose start is not known (the first positioning of a program, a move
                // after a reference return) ends at a known point: it is reported, and says which
                // axes of its start are unknown (docs/dialects/README.md, "Where the tool is").
                let unknown = mv.from.unknown_axes();
                if !unknown.is_empty() {
                    text.pop();
                    text.push_str(r#","start_unknown":["#);
                    for (i, axis) in unknown.iter().enumerate() {
                        if i > 0 {
                            text.push(',');
                        }
                        text.push('"');
                        text.push_str(&axis.to_ascii_lowercase());
                        text.push('"');
                    }
                    text.push_str("]}");
                }
                writeln!(out, "{text}")?;
            }
            Event::Cycle { job, .. } => {
                for m in &toolpath::build(&job)?.motions {
                    writeln!(out, "{}", post::motion_json(m, job.units))?;
                }
            }
            Event::Turning { job: Some(job), .. } => {
                for m in &job.moves()? {
                    writeln!(out, "{}", post::motion_json(m, job.units))?;
                }
            }
            _ => {}
        }
        Ok(())
    })
}

/// One row of `threadcut passes`, in program units, X as the program writes it.
#[derive(Debug, Serialize)]
pub struct PassRow {
    pub n: u32,
    pub kind: PassKind,
    pub depth: f64,
    pub increment: f64,
    pub x: f64,
    pub z: f64,
    pub area: f64,
    pub share: f64,
}

/// The pass table of a job, as rows in the program's units.
pub fn pass_rows(job: &Job, passes: &[Pass], diameter_x: bool) -> Vec<PassRow> {
    let u = job.units;
    passes
        .iter()
        .map(|p| PassRow {
            n: p.n,
            kind: p.kind,
            depth: u.from_mm(p.depth),
            increment: u.from_mm(p.increment),
            x: u.from_mm(p.start.x) * if diameter_x { 2.0 } else { 1.0 },
            z: u.from_mm(p.start.z),
            area: p.area / (u.scale() * u.scale()),
            share: p.share,
        })
        .collect()
}

/// One cycle of `threadcut passes --json`: the pass rows and the simulated columns (`sim_area`,
/// `sim_share`, `cutting_flank`, `chip_thickness`; null where the section could not be simulated).
pub fn passes_json(
    job: &Job,
    rows: &[PassRow],
    section: Option<&crate::sim::Section>,
) -> serde_json::Value {
    let sims = section.map(|s| s.passes.as_slice());
    let sim = |i: usize| sims.and_then(|s| s.get(i));
    let area_scale = job.units.scale() * job.units.scale();
    let rows: Vec<serde_json::Value> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut v = serde_json::to_value(r).unwrap_or_default();
            if let Some(o) = v.as_object_mut() {
                let s = sim(i);
                o.insert("sim_area".into(), s.map(|s| s.area / area_scale).into());
                o.insert("sim_share".into(), s.map(|s| s.share).into());
                o.insert("cutting_flank".into(), s.map(|s| s.flank.name()).into());
                o.insert(
                    "chip_thickness".into(),
                    s.map(|s| job.units.from_mm(s.max_thickness)).into(),
                );
            }
            v
        })
        .collect();
    serde_json::json!({
        "line": job.line,
        "controller": job.controller,
        "units": job.units,
        "passes": rows,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `expand_gcode` as it was before plain lines were batched: one write per plain line.
    fn expand_line_by_line(src: &[u8], machine: &Machine) -> (Vec<u8>, String) {
        let d = dialect::open(machine).unwrap();
        let format = d.format();
        let distance_words = d.conventions().g90_g91_distance;
        let mut out = eol::Writer::new(Vec::new(), LineEnding::of(src));
        let end = run(src, machine, |modal, ev| match ev {
            Event::Plain { line, .. } => Ok(out.write_all(line.raw)?),
            ev => expand_event(&mut out, &format, distance_words, modal, ev),
        });
        (out.into_inner(), format!("{end:?}"))
    }

    /// A CRLF program comes out CRLF: copied lines as they are, generated lines with CRLF too.
    #[test]
    fn generated_lines_end_as_the_program_does() {
        let machine = Machine::built_in("gsk980").unwrap();
        let src = "G0 X80 Z10\r\nG78 P020045 Q0.15 R0.5\r\nG78 X60 Z-60 P3 Q1.8 F3\r\nM30\r\n";
        let (out, end) = expand_batched(src.as_bytes(), &machine);
        assert!(end.starts_with("Ok"), "{end}");
        let text = String::from_utf8(out).unwrap();
        assert_eq!(text.matches("G32").count(), 4, "{text}");
        assert_eq!(
            text.matches('\n').count(),
            text.matches("\r\n").count(),
            "{text:?}"
        );
        assert!(!text.contains("\r\r"), "{text:?}");
        // LF stays LF.
        let (out, _) = expand_batched(src.replace("\r\n", "\n").as_bytes(), &machine);
        assert!(!out.contains(&b'\r'));
    }

    fn expand_batched(source: impl BufRead, machine: &Machine) -> (Vec<u8>, String) {
        let mut out = Vec::new();
        let end = expand_gcode(source, &mut out, machine);
        (out, format!("{end:?}"))
    }

    /// A source that hands out at most `step` bytes a read, so that the reader reads often and
    /// runs of plain lines end at every kind of place.
    struct Trickle<'a> {
        data: &'a [u8],
        step: usize,
    }

    impl io::Read for Trickle<'_> {
        fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
            let n = self.step.min(out.len()).min(self.data.len());
            out[..n].copy_from_slice(&self.data[..n]);
            self.data = &self.data[n..];
            Ok(n)
        }
    }

    impl BufRead for Trickle<'_> {
        fn fill_buf(&mut self) -> io::Result<&[u8]> {
            Ok(&self.data[..self.step.min(self.data.len())])
        }
        fn consume(&mut self, n: usize) {
            self.data = &self.data[n..];
        }
    }

    const WORDS: &[&str] = &[
        "G0 X20 Z2",
        "G1 Z-3 F0.1",
        "U-0.4 W-1 ; c",
        "(comment)",
        "G04 X0.5",
        "T0101 M08",
        "G20",
        "G21",
        "G91",
        "G90",
        "",
        "%",
        "/N5 G0 X30",
        // Cycles of each dialect (with and without the block before them).
        "G78 P020545 Q0.15 R0.5",
        "G78 X16 Z-20 P1.2 Q0.3 F2",
        "G76 P020060 Q100 R0.05",
        "G76 X27.546 Z-30. P1227 Q400 F2.",
        "G92 X29.2 Z-30. F2.",
        "G78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1",
        "G33X.212Z-.5I.012K.05PC",
        "G76 P2.5 Z-30 I-1.0 J0.3 K1.5335",
        // The one-block G76 (FS15, Haas), start angles, Haas's chamfer switch, system B's G78/G33.
        "G76 X27.546 Z-30. K1.227 D0.4 F2. A60 P2 Q90000",
        "G92 X29.2 Z-30. I-0.5 F2. Q180000",
        "X28.6 Q180000",
        "G32 Z-3 F1 Q90000",
        "M24",
        "M23 M8",
        "G78 X29.2 Z-30. F2.",
        "G33 Z-2 F1 Q45000",
        // Errors of the lexer, of the modal state and of the dialects.
        "G0 X1.2.3",
        "G1 X2 U3",
        "G78 X16 Z-20 Q0.3 F2",
        "G0 X@1",
    ];

    proptest::proptest! {
        /// Batching the plain lines changes nothing: the output (up to an error, too) and the
        /// result are those of one write per line, for every controller and however the input
        /// arrives.
        #[test]
        fn batched_output_is_line_by_line_output(
            lines in proptest::collection::vec(proptest::sample::select(WORDS), 0..40),
            crlf in proptest::bool::ANY,
            last_newline in proptest::bool::ANY,
            step in 1usize..64,
            which in 0usize..crate::machine::BUILT_IN.len(),
        ) {
            let machine = Machine::built_in(crate::machine::BUILT_IN[which].0).unwrap();
            let mut src = String::from("G0 X40 Z5\n");
            for l in &lines {
                src.push_str(l);
                src.push_str(if crlf { "\r\n" } else { "\n" });
            }
            if !last_newline {
                src.push_str("M30");
            }
            let want = expand_line_by_line(src.as_bytes(), &machine);
            proptest::prop_assert_eq!(&expand_batched(src.as_bytes(), &machine), &want);
            let trickle = Trickle { data: src.as_bytes(), step };
            proptest::prop_assert_eq!(&expand_batched(trickle, &machine), &want);
        }
    }

    #[test]
    fn batched_output_across_many_buffers() {
        // Longer than several read buffers, with cycles and a failing line far in.
        let mut src = String::from("G0 X80 Z10\n");
        for i in 0..40_000 {
            src.push_str(&format!("G1 X{}.5 W-0.25 (pass {i})\n", 20 + i % 50));
            if i % 9_000 == 0 {
                src.push_str(
                    "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n",
                );
            }
        }
        let machine = Machine::built_in("gsk980").unwrap();
        let want = expand_line_by_line(src.as_bytes(), &machine);
        assert!(want.1.starts_with("Ok"), "{}", want.1);
        assert_eq!(expand_batched(src.as_bytes(), &machine), want);
        src.push_str("G0 X1.2.3\nG0 X1\n");
        let want = expand_line_by_line(src.as_bytes(), &machine);
        assert!(want.1.starts_with("Err"), "{}", want.1);
        assert_eq!(expand_batched(src.as_bytes(), &machine), want);
    }
}
