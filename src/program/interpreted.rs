//! The run loop's side of a program with control flow: handing the rest of the program to the
//! interpreter, executing the blocks it hands back exactly as streamed lines are executed (the
//! dialect, then the modal state), and what `expand` writes for such a program.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::io::{BufRead, Write};

use crate::diag::{Code, Diagnostic};
use crate::dialect::{self, Read};
use crate::gcode::lexer::{index_words, WordIndex};
use crate::gcode::{Conventions, Line, LineShape, Modal, Position, Reader, Word, WordSummary};
use crate::interp::{self, Syntax, Text};
use crate::machine::Machine;
use crate::thread::Job;
use crate::units::Units;

use super::{Error, Event, ExpandSink, Options, Sink, Summary};

/// Where an executed block of an interpreted program runs.
pub struct Where<'a> {
    /// The lines of the calls it runs inside, outermost first.
    pub callers: &'a [u32],
    /// The block is its source line exactly as written: its text may be copied as it is (else
    /// its words carry computed values, or the line held words of the interpreter's).
    pub verbatim: bool,
}

/// What a run hands to a caller that needs more than the events (`convert`).
pub trait Output {
    /// A line of the program (see [`super::run`]).
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error>;
    /// The input after the program's end (M2, M30): not run, handed over as it is.
    fn unrun(&mut self, _text: &[u8]) -> Result<(), Error> {
        Ok(())
    }
    /// The program has control flow: the interpreter runs it from line `line` on.
    fn interpreting(&mut self, _line: u32) -> Result<(), Error> {
        Ok(())
    }
    /// A block the interpreter executed.
    fn interpreted(&mut self, modal: &Modal, ev: Event, _at: &Where) -> Result<(), Error> {
        self.event(modal, ev)
    }
    /// The interpreter ran to the end: the program's text, from the line it took over
    /// (`text.line(from)`) to the end of the input.
    fn interpreted_end(&mut self, _text: &Text, _from: usize) -> Result<(), Error> {
        Ok(())
    }
}

/// An [`Output`] as the run loop's sink.
pub(super) struct OutputSink<'o, O>(pub &'o mut O);

impl<O: Output> Sink for OutputSink<'_, O> {
    const BATCH: bool = false;
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error> {
        self.0.event(modal, ev)
    }
    fn pass(&mut self, _: &[u8]) -> Result<(), Error> {
        Ok(())
    }
    fn unrun(&mut self, bytes: &[u8]) -> Result<(), Error> {
        self.0.unrun(bytes)
    }
    fn interpreting(&mut self, line: u32) -> Result<(), Error> {
        self.0.interpreting(line)
    }
    fn interpreted(&mut self, modal: &Modal, ev: Event, at: &Where) -> Result<(), Error> {
        self.0.interpreted(modal, ev, at)
    }
    fn interpreted_end(&mut self, text: &Text, from: usize) -> Result<(), Error> {
        self.0.interpreted_end(text, from)
    }
}

/// Where the run loop hands over: the first line of control flow.
pub(super) struct Switch {
    /// Offset of the line's first byte.
    pub offset: u64,
    pub line: u32,
    /// The line the run starts at: `line`, or the line of a call the run was given
    /// ([`super::Options::call`]).
    pub start: u32,
    pub syntax: Syntax,
}

/// Runs the rest of the program, from the switch line on, with the interpreter: the program's
/// text is read whole (from the line on, and the lines before it that the reader kept), compiled
/// once, and run with the modal and dialect state as the run loop leaves them.
#[allow(clippy::too_many_arguments)]
pub(super) fn switch<R: BufRead, S: Sink, D: dialect::Dialect>(
    mut reader: Reader<R>,
    at: Switch,
    machine: &Machine,
    options: &Options,
    dialect: D,
    modal: Modal,
    mut sink: S,
    mut summary: Summary,
) -> Result<Summary, Error> {
    let here = Diagnostic::error(
        Code::Input,
        crate::diag::Span::new(at.offset, 0, at.line, 1),
        "",
    );
    let rest = reader
        .take_rest(at.offset, interp::MAX_PROGRAM_BYTES)
        .map_err(|e| Diagnostic {
            message: format!("cannot read the input: {e}"),
            ..here.clone()
        })?;
    let Some((bytes, base)) = rest else {
        return Err(Diagnostic {
            message: format!(
                "the program has control flow from line {} on, and is longer than {} MiB from there",
                at.line,
                interp::MAX_PROGRAM_BYTES >> 20
            ),
            ..here
        }
        .with_hint("threadcut holds a program it interprets in memory, up to this size")
        .into());
    };
    let first_line = if base == 0 { 1 } else { at.line };
    let lexer = dialect.conventions().syntax;
    let code = interp::compile(Text::new(bytes, first_line, base), &at.syntax, lexer);
    let names = |w: &interp::library::Wanted| dialect.program_files(w);
    let linked = interp::Linker {
        names: &names,
        library: options.library.as_ref(),
        syntax: &at.syntax,
        lexer,
    }
    .link(code);
    summary.interpreted_from = Some(at.line);
    sink.interpreting(at.line)?;
    let conv = dialect.conventions().clone();
    let mut host = RunHost {
        dialect,
        modal,
        conv,
        sink,
        summary,
        machine,
        profile: None,
        call: None,
    };
    let limits = interp::Limits {
        max_blocks: options.max_blocks,
    };
    let outcome = interp::run(&linked, &at.syntax, limits, at.start, &mut host)?;
    host.dialect.end_of_input()?;
    let RunHost {
        mut sink,
        mut summary,
        ..
    } = host;
    summary.executed = outcome.executed;
    if outcome.calls == 0 {
        uncalled(&linked.units[0], &mut summary);
    }
    let text = &linked.units[0].text;
    let from = text.index_of(at.line).unwrap_or(0);
    sink.interpreted_end(text, from)?;
    Ok(summary)
}

/// A program that defines subroutines and calls none of them (a subroutine file as a GUI calls
/// it): said, with how to run one.
fn uncalled(code: &interp::code::Code, summary: &mut Summary) {
    let mut names: Vec<String> = code
        .subs
        .keys()
        .map(|id| code.exprs.name(*id).to_string())
        .collect();
    if names.is_empty() {
        return;
    }
    names.sort();
    let first = code
        .subs
        .values()
        .min()
        // (The instruction before a body is its `sub` line's.)
        .map(|&pc| {
            code.text
                .line(code.inst_line[pc.saturating_sub(1) as usize] as usize)
                .whole()
        })
        .unwrap_or_default();
    // Each language names its subroutines and calls them its own way.
    let sinumerik = code.lang == interp::Lang::Sinumerik;
    let listed: Vec<String> = names
        .iter()
        .map(|n| {
            if sinumerik {
                format!("PROC {n}")
            } else {
                format!("o<{n}>")
            }
        })
        .collect();
    let call = if sinumerik {
        format!("--call '{}(arg1, arg2, …)'", names[0])
    } else {
        format!("--call 'o<{}> call [arg1] [arg2] …'", names[0])
    };
    summary.warnings.push(
        Diagnostic::warning(
            Code::Suspicious,
            first,
            format!(
                "the program defines subroutines ({}) and calls none of them",
                listed.join(", ")
            ),
        )
        .with_hint(format!(
            "run one as its GUI calls it, with the values a user would type: {call}"
        )),
    );
    summary.uncalled = names;
}

/// The interpreter's host: executes each block as the run loop executes a line.
struct RunHost<'m, D, S> {
    dialect: D,
    modal: Modal,
    conv: Conventions,
    sink: S,
    summary: Summary,
    machine: &'m Machine,
    // issue 23: while a turning cycle's profile subroutine runs, the cycle block's words.
    profile: Option<Vec<Word>>,
    /// The profile subroutine the last block asked for.
    call: Option<f64>,
}

impl<D: dialect::Dialect, S: Sink> interp::Host for RunHost<'_, D, S> {
    type Error = Error;

    fn block(
        &mut self,
        text: interp::text::TextLine<'_>,
        words: &[Word],
        block_delete: bool,
        ctx: &interp::Context,
    ) -> Result<(), Error> {
        let mut index: WordIndex = [0; 32];
        index_words(words, &mut index);
        if text.offset >= crate::diag::FILE_SPACING && !ctx.calls.is_empty() {
            self.summary
                .called_from
                .entry(text.offset)
                .or_insert_with(|| ctx.calls.to_vec());
        }
        let line = interp::executed_line(text, words, block_delete, ctx, &index);
        let at = Where {
            callers: ctx.callers,
            verbatim: ctx.verbatim,
        };
        self.summary.lines = self.summary.lines.max(line.number);
        // issue 23: a profile's block is read by the dialect, not executed.
        if self.profile.is_some() {
            return Ok(self.dialect.profile_block(&line, &mut self.modal)?);
        }
        if !self.dialect.prefilter(&line) {
            let mv = self.modal.apply(&self.conv, &line)?;
            return self
                .sink
                .interpreted(&self.modal, Event::Plain { line: &line, mv }, &at);
        }
        let before = self.summary.warnings.len();
        let read = self
            .dialect
            .read(&line, &mut self.modal, &mut self.summary.warnings)?;
        for w in &mut self.summary.warnings[before..] {
            if w.span.line == 0 {
                w.span = line.span();
            }
            if w.calls.is_empty() {
                w.calls = ctx.calls.to_vec();
            }
        }
        // issue 23: the block takes a subroutine as its profile.
        if let Some(q) = self.dialect.profile_call() {
            self.call = Some(q);
            self.profile = Some(words.to_vec());
        } else if self.dialect.profile_follows() {
            self.profile = Some(words.to_vec());
        }
        match read {
            Read::Plain => {
                let mv = self.modal.apply(&self.conv, &line)?;
                self.sink
                    .interpreted(&self.modal, Event::Plain { line: &line, mv }, &at)
            }
            // A block the dialect applied itself (a thread move with its start angle): a plain
            // block with the move it made, as the streamed run passes it on.
            Read::Applied(mv) => {
                self.sink
                    .interpreted(&self.modal, Event::Plain { line: &line, mv }, &at)
            }
            Read::Own { mv, words } => {
                let mut index = [0; 32];
                let own = line.with_words(&words, &mut index);
                self.sink
                    .interpreted(&self.modal, Event::Plain { line: &own, mv }, &at)
            }
            Read::Settings => {
                self.sink
                    .interpreted(&self.modal, Event::Settings { line: &line }, &at)
            }
            Read::Cycle(job) => {
                self.summary.cycles += 1;
                self.modal.cycle_ended(job.end_point());
                let done = self.sink.interpreted(
                    &self.modal,
                    Event::Cycle {
                        line: &line,
                        job,
                        dialect: &self.dialect,
                    },
                    &at,
                );
                self.modal.assumed = [false; 2];
                done
            }
            Read::Turning(job) => {
                if let Some(job) = &job {
                    self.summary.cycles += 1;
                    self.modal.position = Position::at(job.end_point());
                }
                self.sink.interpreted(
                    &self.modal,
                    Event::Turning {
                        line: &line,
                        job,
                        dialect: &self.dialect,
                    },
                    &at,
                )
            }
        }
    }

    fn modal(&self) -> &Modal {
        &self.modal
    }

    fn resolution(&self, units: Units) -> f64 {
        self.machine.resolution(units)
    }

    fn warn(&mut self, d: Diagnostic) {
        self.summary.warnings.push(d);
    }

    fn in_calls(&self, mut e: Error, calls: &[crate::diag::Span]) -> Error {
        if let Error::Input(d) = &mut e {
            if d.calls.is_empty() {
                d.calls = calls.to_vec();
            }
        }
        e
    }

    fn parameters(&self) -> Vec<(String, f64)> {
        self.dialect.parameters()
    }

    fn set_parameter(&mut self, name: &str, value: f64) -> Result<(), Error> {
        self.dialect.set_parameter(name, value);
        self.sink.parameter(name, value)
    }

    // issue 23: a turning cycle's profile subroutine (LinuxCNC's G7x Q).
    fn profile_call(&mut self) -> Option<f64> {
        self.call.take()
    }

    fn profile_end(
        &mut self,
        text: interp::text::TextLine<'_>,
        end: interp::text::TextLine<'_>,
    ) -> Result<(), Error> {
        let read = self.dialect.profile_end(&mut self.modal, end.whole())?;
        // The dialect has set where the cycle leaves the tool.
        let Read::Turning(Some(job)) = read else {
            return Ok(());
        };
        self.summary.cycles += 1;
        let words = self.profile.take().unwrap_or_default();
        let mut index: WordIndex = [0; 32];
        index_words(&words, &mut index);
        let line = Line {
            number: text.number,
            offset: text.offset,
            text: text.text,
            raw: text.raw,
            words: &words,
            shape: LineShape {
                block_delete: false,
                percent: false,
                unread: false,
            },
            before: &[],
            summary: WordSummary::of(&words),
            index: &index,
        };
        let at = Where {
            callers: &[],
            verbatim: false,
        };
        self.sink.interpreted(
            &self.modal,
            Event::Turning {
                line: &line,
                job: Some(job),
                dialect: &self.dialect,
            },
            &at,
        )
    }
}

/// `expand`'s state for a program with control flow.
pub(super) struct ExpandState {
    pub(super) flatten: bool,
    /// While the beginning of a Fanuc-style program streams: what each cycle's expansion was
    /// made from, for a jump back that runs the cycle again (it must expand the same).
    prefix: Option<HashMap<u32, Recorded>>,
    /// The line the interpreter took over.
    from: Option<u32>,
    /// Each cycle line the interpreter ran: its expansion, how often it ran and where first.
    runs: HashMap<u32, Expansion>,
    /// The buffer a recorded block other than a threading cycle is expanded into for its
    /// digest, kept from one block to the next.
    scratch: Vec<u8>,
}

/// A streamed cycle of the program's beginning, as recorded for a jump back.
enum Recorded {
    /// A threading cycle whose text the output does not keep: its job and the modal state it was
    /// expanded in, from which its expansion is made again when a jump back runs it (a page that
    /// shows the first lines of a long program does not format the rest). 504 bytes and two
    /// allocations a cycle, against a digest's 8: only where the text is not formatted anyway.
    Cycle { modal: Box<Modal>, job: Box<Job> },
    /// Any other block, or a cycle whose text the output keeps: a digest of its expansion.
    Digest(u64),
}

struct Expansion {
    bytes: Vec<u8>,
    count: u32,
    first: String,
}

impl ExpandState {
    pub(super) fn new(flatten: bool, keeps_prefix: bool) -> ExpandState {
        ExpandState {
            flatten,
            prefix: keeps_prefix.then(HashMap::new),
            from: None,
            runs: HashMap::new(),
            scratch: Vec::new(),
        }
    }

    /// Whether cycles must be recorded while the program's beginning streams.
    #[inline]
    pub(super) fn records_prefix(&self) -> bool {
        self.prefix.is_some() && self.from.is_none()
    }

    pub(super) fn start(&mut self, line: u32) {
        self.from = Some(line);
    }
}

fn digest(bytes: &[u8]) -> u64 {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    bytes.hash(&mut h);
    h.finish()
}

/// A streamed cycle of a Fanuc-style program's beginning: expanded as always, and recorded while
/// the reader keeps the lines for a jump back (by a digest of its expansion, or a threading
/// cycle whose text the output does not keep by what it is made from).
pub(super) fn expand_recorded(
    sink: &mut ExpandSink,
    modal: &Modal,
    ev: Event,
) -> Result<(), Error> {
    let line = (ev.line().number, ev.line().offset);
    if line.1 >= interp::PREFIX_KEPT as u64 {
        sink.interp.prefix = None;
    }
    // A threading cycle is recorded by what it is made from where its text is not kept (it is
    // then not even formatted); where it is, a digest of the text costs less than the record.
    let by_text = sink.out.keeps_text();
    let digested = match (&ev, &mut sink.interp.prefix) {
        (Event::Cycle { job, .. }, Some(p)) if !by_text => {
            let first = Recorded::Cycle {
                modal: Box::new(modal.clone()),
                job: job.clone(),
            };
            p.insert(line.0, first);
            false
        }
        (_, p) => p.is_some(),
    };
    if !digested {
        return sink.write_event(modal, ev);
    }
    let mut buf = std::mem::take(&mut sink.interp.scratch);
    buf.clear();
    sink.event_text(&mut buf, modal, ev)?;
    if let Some(p) = &mut sink.interp.prefix {
        p.insert(line.0, Recorded::Digest(digest(&buf)));
    }
    sink.out.write_all(&buf)?;
    sink.interp.scratch = buf;
    Ok(())
}

/// A block the interpreter executed, for `expand`.
pub(super) fn expand_interpreted(
    sink: &mut ExpandSink,
    modal: &Modal,
    ev: Event,
    at: &Where,
) -> Result<(), Error> {
    if sink.interp.flatten {
        return match ev {
            Event::Plain { line, .. } => {
                write_executed_block(
                    &mut crate::eol::Writer::new(&mut *sink.out, sink.ending),
                    line,
                    at.verbatim,
                    modal,
                )?;
                Ok(())
            }
            ev => sink.write_event(modal, ev),
        };
    }
    let (line, start) = match &ev {
        Event::Plain { .. } => return Ok(()),
        Event::Settings { line } => (line.number, None),
        Event::Cycle { line, job, .. } => (line.number, Some(job.start)),
        Event::Turning { line, job, .. } => (line.number, job.as_ref().map(|j| j.start())),
    };
    let span = ev.line().span();
    let mut place = describe(at, start, modal);
    computed_words(&mut place, ev.line());
    // The line and the dialect a recorded cycle of the beginning is expanded again with.
    let again = match &ev {
        Event::Cycle { line, dialect, .. } => Some((*line, *dialect)),
        _ => None,
    };
    let mut buf = Vec::new();
    sink.event_text(&mut buf, modal, ev)?;
    let from = sink.interp.from.unwrap_or(0);
    if line < from {
        // A cycle of the streamed beginning, run again by a jump back.
        let same = match (
            sink.interp.prefix.as_ref().and_then(|p| p.get(&line)),
            again,
        ) {
            (Some(Recorded::Digest(d)), _) => *d == digest(&buf),
            (Some(Recorded::Cycle { modal, job }), Some((line, dialect))) => {
                let mut first = Vec::new();
                sink.event_text(
                    &mut first,
                    modal,
                    Event::Cycle {
                        line,
                        job: job.clone(),
                        dialect,
                    },
                )?;
                first == buf
            }
            _ => false,
        };
        if same {
            return Ok(());
        }
        return Err(differs(
            span,
            line,
            "its run before the program's first macro statement",
            &format!("a later run {place}"),
        ));
    }
    match sink.interp.runs.get_mut(&line) {
        None => {
            sink.interp.runs.insert(
                line,
                Expansion {
                    bytes: buf,
                    count: 1,
                    first: place,
                },
            );
            Ok(())
        }
        Some(e) => {
            e.count += 1;
            if e.bytes == buf {
                return Ok(());
            }
            Err(differs(
                span,
                line,
                &format!("its first run {}", e.first),
                &format!("run {} {place}", e.count),
            ))
        }
    }
}

/// Where a run of a cycle happened, for a message: the call it ran in and its start point.
fn describe(at: &Where, start: Option<crate::units::Pos>, modal: &Modal) -> String {
    let mut s = match at.callers.last() {
        Some(call) => format!("(called at line {call}"),
        None => "(in the main program".to_string(),
    };
    if let Some(p) = start {
        s.push_str(&format!(
            ", starting at X{} Z{}",
            shown(modal.x_from_mm(p.x)),
            shown(modal.units.from_mm(p.z))
        ));
    }
    s.push(')');
    s
}

/// Adds the values the run gave the line's computed words (`X#6 = 23.249`) to a description.
fn computed_words(place: &mut String, line: &Line) {
    let words: Vec<String> = line
        .words
        .iter()
        .filter(|w| w.is_computed())
        .map(|w| {
            format!(
                "{}{} = {}",
                w.letter as char,
                String::from_utf8_lossy(w.raw(line.text)),
                shown(w.value)
            )
        })
        .collect();
    if !words.is_empty() {
        place.pop();
        place.push_str(&format!(", with {})", words.join(", ")));
    }
}

/// A number for a message: up to four decimals, no trailing zeros or point.
fn shown(v: f64) -> String {
    let s = crate::post::number(v, 4, false);
    s.strip_suffix('.').map(str::to_string).unwrap_or(s)
}

fn differs(span: crate::diag::Span, line: u32, first: &str, other: &str) -> Error {
    Diagnostic::error(
        Code::Conflict,
        span,
        format!(
            "the cycle of line {line} does not expand to the same moves every time it runs: {first} and {other} differ"
        ),
    )
    .with_hint("expand replaces a cycle in place only when every run of it makes the same moves; --flatten writes the executed program as straight-line code")
    .into()
}

/// The interpreter ran to the end: `expand` writes the program's text from the line it took
/// over, each cycle line replaced by its expansion (the straight-line part before it was written
/// as it streamed). With `--flatten` everything was written as it ran.
pub(super) fn expand_end(sink: &mut ExpandSink, text: &Text, from: usize) -> Result<(), Error> {
    if sink.interp.flatten {
        // A tape's closing `%`, which the run does not reach.
        let last = (0..text.len())
            .rev()
            .map(|i| text.line(i))
            .find(|l| !l.text.iter().all(u8::is_ascii_whitespace));
        if let Some(l) = last.filter(|l| l.text.trim_ascii() == b"%") {
            sink.out.write_all(b"%")?;
            sink.out.write_all(sink.ending.as_str().as_bytes())?;
            let _ = l;
        }
        return Ok(());
    }
    for i in from..text.len() {
        let line = text.line(i);
        match sink.interp.runs.get(&line.number) {
            Some(e) => sink.out.write_all(&e.bytes)?,
            None => sink.out.write_all(line.raw)?,
        }
    }
    Ok(())
}

/// A block of the executed program, as straight-line code: the line as written when it is a
/// plain line (`verbatim`), else its words with their values (`--flatten`).
pub fn write_executed_block(
    out: &mut dyn Write,
    line: &Line,
    verbatim: bool,
    modal: &Modal,
) -> std::io::Result<()> {
    if verbatim {
        out.write_all(line.raw)?;
        if !line.raw.ends_with(b"\n") {
            out.write_all(b"\n")?;
        }
        return Ok(());
    }
    let mut text = Vec::with_capacity(line.words.len() * 8);
    for (k, w) in line.words.iter().enumerate() {
        if k > 0 {
            text.push(b' ');
        }
        text.push(w.letter);
        if w.is_computed() {
            text.extend_from_slice(flat_number(w.letter, w.value, modal).as_bytes());
        } else {
            text.extend_from_slice(w.raw(line.text));
        }
    }
    text.push(b'\n');
    out.write_all(&text)
}

/// A computed value as a word's number: whole numbers without a decimal point where that means
/// the same (codes and counts, and every word on a machine that reads numbers as written), else
/// with one, so that a least-increment machine reads a length, not a count of increments.
fn flat_number(letter: u8, v: f64, modal: &Modal) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    let calculator = modal.no_point[(modal.units == Units::Inch) as usize] == 1.0;
    let integer_letter = matches!(
        letter,
        b'G' | b'M' | b'N' | b'O' | b'T' | b'S' | b'P' | b'Q' | b'L' | b'H' | b'D'
    );
    if v.fract() == 0.0 && (calculator || integer_letter) {
        return format!("{v}");
    }
    let s = format!("{v}");
    if s.contains('.') {
        s
    } else {
        s + "."
    }
}
