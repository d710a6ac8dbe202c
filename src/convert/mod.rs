//! A program for one controller rewritten for another: dialect → model → dialect.
//!
//! * Every threading cycle is read into the model ([`crate::thread::Job`]) by the source's dialect
//!   and written by [`crate::translate::write_job`]: the target's native cycle when some choice of
//!   its words reads back as the same motion, plain moves with the reason otherwise, or a refusal
//!   naming the target's limit.
//! * Every other block is read through the source's [`Lexicon`](crate::dialect::lexicon::Lexicon) into machine-neutral
//!   meanings ([`block::Block`]: units, feed mode, spindle, tools, positions, …) and written
//!   through the target's ([`write`]). Positions become absolute, in the target profile's X
//!   convention; numbers always carry a decimal point; units the target does not have are
//!   converted (a metric program for the inch-only OmniTurn is written in inches, the lead's
//!   rounding over each thread stated).
//! * The converted program states at its start what the source program relied on: its units,
//!   absolute distances, X on diameter or radius, the ZX plane, its feed mode and rpm, in the
//!   target's words where the target has them.
//!
//! Nothing here names a controller: each dialect states its own lexicon. Decisions and the
//! results over every bundled example: `docs/translation.md`.

pub mod block;
mod macros;
pub mod tools;
mod write;

use std::io::{BufRead, Read, Write};

use crate::diag::{Code, Diagnostic, Span};
use crate::dialect;
use crate::dialect::lexicon::Setting;
use crate::gcode::{Line, Modal};
use crate::interp::Text;
use crate::machine::Machine;
use crate::program::{self, Error, Event, Summary, Where};

use block::Source;

/// What a conversion did besides writing the program.
#[derive(Debug, Default)]
pub struct Report {
    pub summary: Summary,
    /// Cycles written as the target's native cycle.
    pub native: u32,
    /// Cycles written as plain moves: the line of the cycle and why its native cycle was not used.
    pub plain: Vec<(u32, String)>,
    /// The conversion's own warnings (a lead that drifts over its thread), before they join
    /// `summary.warnings`.
    pub warnings: Vec<Diagnostic>,
    /// The machine settings the native cycles written rely on (Haas's Settings 86, 95, 96, 99),
    /// each once: the header lists them.
    pub settings: Vec<Setting>,
}

/// How a program is converted.
#[derive(Clone, Debug, Default)]
pub struct Options {
    /// How the program is run (`--max-blocks`, `--flatten`).
    pub run: program::Options,
    /// The largest drift accepted of a lead written in the target's words, over its thread, in
    /// the units of the converted program (`--max-lead-drift`). `None`: a quarter of the medium
    /// class's pitch-diameter tolerance for the thread, on the drift's pitch-diameter equivalent
    /// (docs/translation.md, "The lead's rounding").
    pub max_lead_drift: Option<f64>,
    /// Named tools and their numbers (`--tool NAME=T0101`, in order), over the target profile's
    /// `[tools]` table ([`tools::ToolMap`]).
    pub tools: Vec<(String, String)>,
}

/// Converts the program `input`, written for `from`, into a program for `to`, written to `out`.
/// Lines end as the input's first line does. With the same profile on both sides the program is
/// copied as it is, after a comment naming the conversion. An error is the first block that
/// cannot be converted, at its word, naming the target's limit (the output up to it has been
/// written).
///
/// A program with control flow (subroutines, loops, parameters) is copied as it is for the same
/// profile; for another controller with a macro language (Custom Macro B, LinuxCNC's o-words) it
/// is translated with its structure and verified by its motion ([`macros`]); for one without, it
/// is an error at its first line of control flow unless `options.run.flatten`, which converts the
/// executed program (every block the interpreter runs, with its computed values), as it does for
/// any target (docs/translation.md, "Programs with control flow", "Macro programs").
pub fn convert<R: BufRead>(
    mut input: R,
    out: &mut dyn Write,
    from: &Machine,
    to: &Machine,
    options: &Options,
) -> Result<Report, Error> {
    if let Some(v) = options
        .max_lead_drift
        .filter(|v| !(v.is_finite() && *v >= 0.0))
    {
        return Err(Error::Input(Diagnostic::error(
            Code::OutOfRange,
            Span::default(),
            format!("maximum lead drift {v}: expected a length of 0 or more, in the converted program's units"),
        )));
    }
    tool_names(options, to)?;
    let ending = crate::eol::LineEnding::peek(&mut input)?;
    let source_dialect = dialect::open(from).map_err(Error::Setup)?;
    let target = dialect::open(to).map_err(Error::Setup)?;
    if from != to && !options.run.flatten {
        if let Some(langs) = macro_languages(source_dialect.as_ref(), target.as_ref()) {
            return structured(input, out, (from, to), options, langs, ending);
        }
    }
    if from == to || target.settings().is_empty() {
        let out = &mut crate::eol::Writer::new(out, ending);
        return run_conversion(input, out, (from, to), options, Mode::Plain)
            .map(|r| r.0)
            .map_err(|e| e.0);
    }
    // A target whose cycles read machine settings: the program is held until the settings its
    // native cycles rely on are known, and the header lists them.
    let mut held = Vec::new();
    let result = run_conversion(
        input,
        &mut crate::eol::Writer::new(&mut held, ending),
        (from, to),
        options,
        Mode::Plain,
    );
    match result {
        Ok(done) => {
            out.write_all(&with_settings(&held, &done, target.as_ref(), ending))?;
            Ok(done.0)
        }
        Err((e, _)) => {
            out.write_all(&held)?;
            Err(e)
        }
    }
}

/// The named tools of the options and the target profile, checked before anything is written.
fn tool_names(options: &Options, to: &Machine) -> Result<tools::ToolMap, Error> {
    tools::ToolMap::new(&options.tools, &to.tools).map_err(|e| {
        Error::Input(
            Diagnostic::error(Code::OutOfRange, Span::default(), e)
                .with_hint("a tool is named with --tool NAME=T0101 or the target profile's [tools] table (docs/translation.md, \"Tools by name\")"),
        )
    })
}

/// The converted text with the line listing the machine settings its native cycles rely on,
/// after the header's comment.
fn with_settings(
    text: &[u8],
    (report, _, header): &Converted,
    target: &dyn dialect::Dialect,
    ending: crate::eol::LineEnding,
) -> Vec<u8> {
    let line = (!report.settings.is_empty())
        .then(|| {
            let list: Vec<String> = report.settings.iter().map(Setting::describe).collect();
            target.format().comment(&format!(
                "threadcut: this program relies on the machine's settings: {}",
                list.join("; ")
            ))
        })
        .flatten();
    with_line_after(text, header.as_deref(), line.as_deref(), ending)
}

/// `text` with `line` inserted after the first line that is `after` (unchanged without both).
fn with_line_after(
    text: &[u8],
    after: Option<&str>,
    line: Option<&str>,
    ending: crate::eol::LineEnding,
) -> Vec<u8> {
    let (Some(after), Some(line)) = (after, line) else {
        return text.to_vec();
    };
    let end = ending.as_str();
    let mut out = Vec::with_capacity(text.len() + line.len() + end.len());
    let mut inserted = false;
    for l in text.split_inclusive(|&b| b == b'\n') {
        out.extend_from_slice(l);
        if !inserted && l.strip_suffix(end.as_bytes()) == Some(after.as_bytes()) {
            out.extend_from_slice(line.as_bytes());
            out.extend_from_slice(end.as_bytes());
            inserted = true;
        }
    }
    out
}

/// The source's and the target's macro languages, when a program with control flow can keep its
/// structure (Custom Macro B and LinuxCNC's o-words, either way).
fn macro_languages(
    source: &dyn dialect::Dialect,
    target: &dyn dialect::Dialect,
) -> Option<(crate::interp::Syntax, crate::interp::Syntax)> {
    use crate::interp::Lang;
    let (s, t) = (source.macros()?, target.macros()?);
    let ok = |l: Lang| matches!(l, Lang::Ngc | Lang::MacroB);
    (ok(s.lang) && ok(t.lang)).then_some((s, t))
}

/// How [`run_conversion`] runs.
enum Mode {
    /// As a straight-line program; a program with control flow is an error at its first line of
    /// it (unless `--flatten`).
    Plain,
    /// As `Plain`, and the run tells whether it stopped at control flow.
    Probe,
    /// The executed program (as `--flatten`), each event's output kept by its line.
    Trace(Tap),
}

/// The output of a traced conversion, measured as it is written.
#[derive(Clone, Default)]
struct Shared(std::rc::Rc<std::cell::RefCell<Vec<u8>>>);

impl Write for Shared {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0.borrow_mut().extend_from_slice(buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// One event's place in a traced output: its line, its words' columns and values, where its
/// output begins.
type Mark = (u32, Vec<(u32, f64)>, usize, Option<u32>);

/// A conversion's report, each line's runs (`Trace`), and the header's comment line.
type Converted = (Report, Option<Runs>, Option<String>);

/// Lines' runs, by line number.
type Runs = std::collections::HashMap<u32, Vec<macros::Run>>;

/// Where each event's output begins.
#[derive(Default)]
struct Tap {
    out: Shared,
    marks: Vec<Mark>,
    /// The line of the call the running block is inside (the innermost).
    caller: Option<u32>,
}

impl Tap {
    fn mark(&mut self, line: &Line) {
        let at = self.out.0.borrow().len();
        let words = line
            .words
            .iter()
            .map(|w| (w.span.column, w.value))
            .collect();
        self.marks.push((line.number, words, at, self.caller));
    }

    /// Each line's runs, the output up to `end` split at the marks.
    fn runs(self, end: usize) -> Runs {
        let buf = self.out.0.borrow();
        let mut runs: Runs = Default::default();
        for (k, (line, words, at, caller)) in self.marks.iter().enumerate() {
            let to = self.marks.get(k + 1).map_or(end, |m| m.2).max(*at);
            let text = String::from_utf8_lossy(&buf[*at..to]).replace("\r\n", "\n");
            runs.entry(*line).or_default().push(macros::Run {
                words: words.clone(),
                text,
                caller: *caller,
            });
        }
        runs
    }
}

/// A program with control flow for a target with another macro language: converted as a
/// straight-line program when it has none; otherwise translated with its structure
/// ([`macros`]), from the conversion of its executed blocks.
fn structured<R: BufRead>(
    mut input: R,
    out: &mut dyn Write,
    (from, to): (&Machine, &Machine),
    options: &Options,
    (syntax, to_syntax): (crate::interp::Syntax, crate::interp::Syntax),
    ending: crate::eol::LineEnding,
) -> Result<Report, Error> {
    let mut text = Vec::new();
    (&mut input)
        .take(crate::interp::MAX_PROGRAM_BYTES as u64 + 1)
        .read_to_end(&mut text)?;
    let mut plain = Vec::new();
    let probe = run_conversion(
        &text[..],
        &mut crate::eol::Writer::new(&mut plain, ending),
        (from, to),
        options,
        Mode::Probe,
    );
    let target = dialect::open(to).map_err(Error::Setup)?;
    match probe {
        Ok(done) => {
            out.write_all(&with_settings(&plain, &done, target.as_ref(), ending))?;
            return Ok(done.0);
        }
        Err((e, false)) => {
            // As a straight-line conversion: the output up to the error.
            out.write_all(&plain)?;
            return Err(e);
        }
        Err((_, true)) => {}
    }
    let tap = Tap::default();
    let shared = tap.out.clone();
    let flat = Options {
        run: program::Options {
            flatten: true,
            ..options.run.clone()
        },
        ..options.clone()
    };
    let (report, runs, _) = run_conversion(
        &text[..],
        &mut shared.clone(),
        (from, to),
        &flat,
        Mode::Trace(tap),
    )
    .map_err(|e| e.0)?;
    let format = target.format();
    let comment = |c: &str| format.comment(c).unwrap_or_default();
    let converted = macros::translate(&macros::Request {
        text: &text,
        from,
        to,
        syntax,
        to_syntax,
        runs: &runs.unwrap_or_default(),
        comment: &comment,
        run: &options.run,
    })?;
    crate::eol::Writer::new(out, ending).write_all(converted.as_bytes())?;
    Ok(report)
}

/// The conversion of `input`; an error says whether the run stopped at control flow (`Probe`).
/// `Trace` gives each line's runs.
fn run_conversion<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    (from, to): (&Machine, &Machine),
    options: &Options,
    mode: Mode,
) -> Result<Converted, (Error, bool)> {
    let plain = |e: Error| (e, false);
    let names = tool_names(options, to).map_err(plain)?;
    let source_dialect = dialect::open(from).map_err(|e| plain(Error::Setup(e)))?;
    let target = dialect::open(to).map_err(|e| plain(Error::Setup(e)))?;
    let conv = source_dialect.conventions().clone();
    let src = Source {
        name: &from.name,
        meanings: source_dialect.meanings(),
        dialect: source_dialect.as_ref(),
        uw_incremental: conv.uw_incremental,
        canned_cycles: conv.canned_cycles,
        paren_comments: !conv.syntax.parens_not_comments,
        declared: Default::default(),
    };
    let side = if from == to {
        // The program as it is, after a comment naming the conversion (after a leading `%`).
        Side::Same {
            out,
            header: target
                .format()
                .comment(&format!("threadcut convert: {} to {}", from.name, to.name)),
        }
    } else {
        Side::Other(Box::new(
            write::Writer::new(
                out,
                from,
                to,
                target.as_ref(),
                &src.meanings,
                write::Choices {
                    max_lead_drift: options.max_lead_drift,
                    names,
                },
            )
            .map_err(plain)?,
        ))
    };
    let (probe, tap) = match mode {
        Mode::Plain => (false, None),
        Mode::Probe => (true, None),
        Mode::Trace(t) => (false, Some(t)),
    };
    let mut conversion = Conversion {
        side,
        src,
        flatten: options.run.flatten,
        unrun: Vec::new(),
        probe,
        stopped_at_flow: false,
        tap,
    };
    let summary = program::run_output(input, from, &options.run, &mut conversion)
        .map_err(|e| (e, conversion.stopped_at_flow))?;
    let runs = conversion.tap.take().map(|t| {
        let end = t.out.0.borrow().len();
        t.runs(end)
    });
    conversion.after_end().map_err(plain)?;
    let (mut report, header) = match conversion.side {
        Side::Other(w) => {
            let header = w.header_comment();
            (w.finish(), header)
        }
        Side::Same { .. } => (Report::default(), None),
    };
    report.summary = summary;
    let own = std::mem::take(&mut report.warnings);
    report.summary.warnings.extend(own);
    Ok((report, runs, header))
}

/// Where the converted program goes.
enum Side<'o, 'm> {
    /// The same profile on both sides: the program's own lines, after the header comment.
    Same {
        out: &'o mut dyn Write,
        header: Option<String>,
    },
    /// Another controller: every block through the lexicons, every cycle through the model.
    Other(Box<write::Writer<'o, 'm>>),
}

/// A conversion's side of a run ([`program::Output`]).
struct Conversion<'o, 'm, 's> {
    side: Side<'o, 'm>,
    src: Source<'s>,
    flatten: bool,
    /// The input after the program's end (M2, M30): not run.
    unrun: Vec<u8>,
    /// A program with control flow may be translated with its structure: the run says so when
    /// it stops there.
    probe: bool,
    stopped_at_flow: bool,
    /// Each event's output, by its line (the structural translation's runs).
    tap: Option<Tap>,
}

impl Conversion<'_, '_, '_> {
    /// The lines after the program's end. The same profile's are copied; for another
    /// controller, blank lines, comments (in the target's comment form) and `%` delimiters are
    /// kept, and a line with words is an error: it is not run, so nothing says what it means
    /// (with `--flatten`, which writes only what runs, it is left out).
    fn after_end(&mut self) -> Result<(), Error> {
        let w = match &mut self.side {
            Side::Same { out, .. } => {
                out.write_all(&self.unrun)?;
                return Ok(());
            }
            Side::Other(w) => w,
        };
        let parens = self.src.paren_comments;
        for raw in self.unrun.split_inclusive(|&b| b == b'\n') {
            let text = block::without_comments(raw, parens);
            match text.trim_ascii() {
                b"" if block::comments(raw, parens).is_empty() => w.blank_line()?,
                b"" => w.comment_only(&block::comments(raw, parens))?,
                b"%" => w.delimiter()?,
                _ if self.flatten => {}
                t => {
                    return Err(Error::Input(
                        Diagnostic::error(
                            Code::Unsupported,
                            Span::default(),
                            format!(
                                "`{}` follows the program's end (M2/M30): it is not run, and threadcut does not rewrite it for {}",
                                String::from_utf8_lossy(t),
                                w.target_name()
                            ),
                        )
                        .with_hint("--flatten writes only what the program runs"),
                    ))
                }
            }
        }
        Ok(())
    }
}

impl program::Output for Conversion<'_, '_, '_> {
    fn event(&mut self, modal: &Modal, ev: Event) -> Result<(), Error> {
        match &mut self.side {
            Side::Same { out, header } => {
                let line = event_line(&ev);
                same_header(out, header, line, self.src.meanings.program_number)?;
                out.write_all(line.raw)?;
                Ok(())
            }
            Side::Other(w) => match ev {
                _ if self.tap.is_some() => {
                    if let Some(t) = &mut self.tap {
                        t.mark(ev.line());
                    }
                    let tap = self.tap.take();
                    let r = self.event(modal, ev);
                    self.tap = tap;
                    r
                }
                Event::Plain { line, mv } => {
                    if line.shape.percent {
                        return w.delimiter();
                    }
                    let b = block::decode(line, &mut self.src, modal)?;
                    w.header_before(line, b.names_program())?;
                    w.plain(line, &b, mv, modal)
                }
                Event::Settings { line } => {
                    w.header_before(line, false)?;
                    w.comment_only(&block::comments(line.text, self.src.paren_comments))
                }
                Event::Cycle { line, job, .. } => {
                    w.header_before(line, false)?;
                    w.cycle(
                        line,
                        *job,
                        &block::comments(line.text, self.src.paren_comments),
                    )
                }
                Event::Turning { line, .. } => Err(turning_not_converted(line)),
            },
        }
    }

    fn unrun(&mut self, text: &[u8]) -> Result<(), Error> {
        self.unrun.extend_from_slice(text);
        Ok(())
    }

    fn interpreting(&mut self, line: u32) -> Result<(), Error> {
        let w = match &self.side {
            Side::Other(w) if !self.flatten => w,
            _ => return Ok(()),
        };
        self.stopped_at_flow = self.probe;
        Err(Error::Input(
            Diagnostic::error(
                Code::Unsupported,
                Span::new(0, 0, line, 1),
                format!(
                    "the program has control flow from line {line} on (subroutines, loops or parameters), which threadcut does not rewrite for {}",
                    w.target_name()
                ),
            )
            .with_hint("--flatten writes the executed program as straight-line code for the target"),
        ))
    }

    fn interpreted(&mut self, modal: &Modal, ev: Event, at: &Where) -> Result<(), Error> {
        if !self.flatten {
            // The same profile's program is copied as it is (interpreted_end); another
            // controller's stopped at `interpreting`.
            return Ok(());
        }
        match &mut self.side {
            Side::Same { out, header } => {
                let line = event_line(&ev);
                same_header(out, header, line, self.src.meanings.program_number)?;
                program::write_executed_block(*out, line, at.verbatim, modal)?;
                Ok(())
            }
            Side::Other(_) => {
                if let Some(t) = &mut self.tap {
                    t.caller = at.callers.last().copied();
                }
                let r = self.event(modal, ev);
                if let Some(t) = &mut self.tap {
                    t.caller = None;
                }
                r
            }
        }
    }

    fn interpreted_end(&mut self, text: &Text, from: usize) -> Result<(), Error> {
        let (Side::Same { out, header }, false) = (&mut self.side, self.flatten) else {
            return Ok(());
        };
        let mut bytes = text.bytes_from(from);
        if let Some(h) = header.take() {
            // A program whose first line is control flow: the header after a leading `%`.
            let first = bytes
                .iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |i| i + 1);
            if bytes[..first].trim_ascii() == b"%" {
                out.write_all(&bytes[..first])?;
                bytes = &bytes[first..];
            }
            // The program number that begins the program stays first.
            let next = bytes
                .iter()
                .position(|&b| b == b'\n')
                .map_or(bytes.len(), |i| i + 1);
            let t = bytes[..next].trim_ascii_start();
            if self.src.meanings.program_number
                && t.first() == Some(&b'O')
                && t.get(1).is_some_and(u8::is_ascii_digit)
            {
                out.write_all(&bytes[..next])?;
                bytes = &bytes[next..];
            }
            writeln!(out, "{h}")?;
        }
        out.write_all(bytes)?;
        Ok(())
    }
}

fn event_line<'a, 'l>(ev: &Event<'a, 'l>) -> &'a Line<'l> {
    ev.line()
}

/// The same profile's header comment, before the first line that is neither a `%` delimiter nor
/// the program number that begins the program (`numbers`: the control numbers programs with O).
fn same_header(
    out: &mut dyn Write,
    header: &mut Option<String>,
    line: &Line,
    numbers: bool,
) -> Result<(), Error> {
    let number_only =
        numbers && !line.words.is_empty() && line.words.iter().all(|w| w.letter == b'O');
    if !line.shape.percent && !number_only {
        if let Some(h) = header.take() {
            writeln!(out, "{h}")?;
        }
    }
    Ok(())
}

/// [`convert`] on a program held in memory: the converted text, or the first block that cannot be
/// converted (a profile that cannot be used is an error without a place).
pub fn convert_text(
    program: &str,
    from: &Machine,
    to: &Machine,
    options: &Options,
) -> Result<String, Diagnostic> {
    let mut out = Vec::new();
    match convert(program.as_bytes(), &mut out, from, to, options) {
        Ok(_) => Ok(String::from_utf8_lossy(&out).into_owned()),
        Err(Error::Input(d)) => Err(d),
        Err(e) => Err(Diagnostic::error(
            Code::Unsupported,
            Span::default(),
            e.to_string(),
        )),
    }
}

/// A turning cycle's block, for a conversion to another controller: not written in this build
/// (a wrong contour would cut the part wrong).
fn turning_not_converted(line: &Line) -> Error {
    Error::Input(
        Diagnostic::error(
            Code::Unsupported,
            line.span(),
            format!(
                "line {} belongs to a turning cycle, a canned cycle other than threading: threadcut does not convert it",
                line.number
            ),
        )
        .with_hint("`threadcut expand` writes the cycle as plain moves, which convert then reads"),
    )
}
