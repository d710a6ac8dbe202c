//! One module per controller. Each knows only its own words: it reads its cycles, raises its own
//! alarms, lowers them into the shared [`Job`](crate::thread::Job), and says how its plain moves are
//! written. Everything two controllers share lives in [`thread`](crate::thread).

pub mod allen_bradley;
pub mod fanuc;
pub mod fanuc_family;
pub mod gsk;
pub mod linuxcnc;
pub mod omniturn;

use crate::diag::{Diagnostic, Result, Span};
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::Machine;
use crate::post::Format;
use crate::thread::{Job, Pass};
use crate::toolpath::Toolpath;

/// What a line turned out to be.
pub enum Read {
    /// Not a threading cycle: the shared modal reader handles it and it passes through unchanged.
    Plain,
    /// Part of a cycle that produces no motion yet (GSK's first G78 block).
    Settings,
    /// A complete cycle.
    Cycle(Box<Job>),
}

pub trait Dialect {
    fn name(&self) -> &'static str;
    fn conventions(&self) -> &Conventions;
    /// A cheap look at a line before [`read`](Dialect::read): `false` promises that `read` would
    /// return `Read::Plain` without changing any state (its own or the modal state) and without a
    /// warning, so the caller may skip it. The default offers every line.
    fn prefilter(&self, _line: &Line) -> bool {
        true
    }
    /// Offers a line to the dialect. Warnings go to `warnings`; alarms are errors.
    fn read(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read>;
    /// How plain moves are written for this controller.
    fn format(&self) -> Format;
    /// The job as this controller's native cycle (lines without terminators), or why it cannot be.
    /// Callers never trust this text alone: [`crate::translate`] reads it back and compares motion.
    /// Called before [`crate::translate::verify`] reads a native cycle back without the program around
    /// it: a dialect that checks machine state set elsewhere in a program (LinuxCNC's spindle) assumes
    /// it is ready.
    fn assume_ready(&mut self) {}
    fn emit_native(&self, _job: &Job) -> std::result::Result<Vec<String>, String> {
        Err(format!(
            "{} has no native threading cycle in threadcut",
            self.name()
        ))
    }
    /// The macro language this controller's programs are written in, if any: which front end of
    /// [`crate::interp`] runs a program that has control flow (subprograms, loops, parameters,
    /// expressions). `None` (the default): every line is a plain block.
    fn macros(&self) -> Option<crate::interp::Syntax> {
        None
    }
    /// Letters this controller writes without a number (flags such as OmniTurn's `P`, `C`, `O`).
    fn bare_letters(&self) -> &'static [u8] {
        b""
    }
    /// Writes an expanded cycle in a form of the controller's own, for a controller that has no
    /// plain synchronised move. `None` (the default): the cycle is written as plain moves in
    /// [`format`](Dialect::format).
    fn write_cycle(
        &self,
        _out: &mut dyn std::io::Write,
        _job: &Job,
        _passes: &[Pass],
        _path: &Toolpath,
    ) -> Option<std::io::Result<()>> {
        None
    }
}

/// Refuses the first word of `line` whose letter is not in `allowed`, naming the block and its words:
/// every controller's cycle blocks accept a fixed set of words.
pub(crate) fn only_words(line: &Line, allowed: &[u8], block: &str, format: &str) -> Result<()> {
    match line.words.iter().find(|w| !allowed.contains(&w.letter)) {
        Some(w) => Err(Diagnostic::error(
            crate::diag::Code::Unsupported,
            w.span,
            format!("{} is not a word of {block}", w.letter as char),
        )
        .with_hint(format!("its words are {format}"))),
        None => Ok(()),
    }
}

/// Refuses a G code that shares the block of the cycle word at `cycle` (`name`, e.g. "G78"), except
/// the codes in `allowed` (×10, as [`g_code`](crate::gcode::reader::g_code) gives them).
pub(crate) fn alone_in_block(line: &Line, cycle: Span, name: &str, allowed: &[u16]) -> Result<()> {
    let other = line.words.iter().find(|w| {
        w.letter == b'G'
            && w.span != cycle
            && !crate::gcode::reader::g_code(w.value).is_some_and(|c| allowed.contains(&c))
    });
    match other {
        Some(w) => Err(Diagnostic::error(
            crate::diag::Code::Conflict,
            w.span,
            format!("G{} shares a block with {name}", w.value),
        )
        .with_hint(format!("write {name} in a block of its own"))),
        None => Ok(()),
    }
}

/// Where a cycle starts: the tool's position, which must be known (at power-on and after a reference
/// return it is not). `hint` says how this controller's program positions the tool.
pub(crate) fn start_point(
    modal: &Modal,
    cycle: Span,
    name: &str,
    hint: &str,
) -> Result<crate::units::Pos> {
    modal.position.ok_or_else(|| {
        Diagnostic::error(
            crate::diag::Code::UnknownPosition,
            cycle,
            format!("{name} starts where the tool is, and the tool's position is not known here"),
        )
        .with_hint(hint)
    })
}

/// Warns when one lead is longer than the thread's Z travel: each pass turns the spindle less than
/// once, which is most often a lead written wrong. `hint` is the controller's likely slip.
pub(crate) fn lead_warning(
    lead: f64,
    travel_z: f64,
    units: crate::units::Units,
    span: Span,
    hint: &str,
    warnings: &mut Vec<Diagnostic>,
) {
    if lead > travel_z.abs() {
        warnings.push(
            Diagnostic::warning(
                crate::diag::Code::Suspicious,
                span,
                format!(
                    "the lead {} is longer than the thread ({} along Z): each pass turns the spindle less than once",
                    units.from_mm(lead),
                    units.from_mm(travel_z.abs())
                ),
            )
            .with_hint(hint),
        );
    }
}

/// A word that packs three two-digit fields, `P(m)(r)(a)` (Fanuc's G76 and GSK's G78 first blocks;
/// leading zeros may be left out): the fields and where each pair is written.
pub(crate) struct PackedP {
    pub fields: [u32; 3],
    spans: [Span; 3],
}

impl PackedP {
    /// Where field `i` is written: its two digits, or the whole word when they were left out.
    pub fn span(&self, i: usize) -> Span {
        self.spans[i]
    }
}

/// Reads a `P(m)(r)(a)` word of `block`'s first block; `example` is the hint's worked example.
pub(crate) fn packed_p(line: &Line, p: &Word, block: &str, example: &str) -> Result<PackedP> {
    if p.is_computed() {
        return computed_packed_p(p, block, example);
    }
    let raw = p.raw(line.text);
    let digits = raw.strip_prefix(b"+").unwrap_or(raw);
    if p.has_dot || digits.first() == Some(&b'-') || digits.len() > 6 {
        return Err(Diagnostic::error(
            crate::diag::Code::Syntax,
            p.span,
            format!(
                "P{} is not P(m)(r)(a): the first {block} block packs three two-digit fields",
                crate::gcode::lexer::show(raw)
            ),
        )
        .with_hint(format!(
            "write six digits without a decimal point: {example}"
        )));
    }
    let v = p.value as u32;
    let missing = 6 - digits.len();
    let sign = raw.len() - digits.len();
    let span = |pair: usize| match (pair * 2).checked_sub(missing) {
        Some(at) => Span::new(
            p.span.start + 1 + (sign + at) as u64,
            2.min(digits.len() - at) as u32,
            p.span.line,
            p.span.column + 1 + (sign + at) as u32,
        ),
        None => p.span,
    };
    Ok(PackedP {
        fields: [v / 10_000, (v / 100) % 100, v % 100],
        spans: [span(0), span(1), span(2)],
    })
}

/// A `P(m)(r)(a)` word whose value the macro interpreter computed (`P#1`): the fields are read from
/// the value, a whole number from 0 to 999999 (as the written digits would be, leading zeros
/// left out); the spans are the whole word's.
fn computed_packed_p(p: &Word, block: &str, example: &str) -> Result<PackedP> {
    if !(0.0..1_000_000.0).contains(&p.value) || p.value.fract() != 0.0 {
        return Err(Diagnostic::error(
            crate::diag::Code::Syntax,
            p.span,
            format!(
                "P is {}, not P(m)(r)(a): the first {block} block packs three two-digit fields",
                p.value
            ),
        )
        .with_hint(format!(
            "the value must be a whole number of up to six digits: {example}"
        )));
    }
    let v = p.value as u32;
    Ok(PackedP {
        fields: [v / 10_000, (v / 100) % 100, v % 100],
        spans: [p.span; 3],
    })
}

/// The dialect a machine profile names.
pub fn open(machine: &Machine) -> std::result::Result<Box<dyn Dialect>, String> {
    open_with(machine, Boxed)
}

/// Work that is compiled for each dialect's own type, so that the dialect's calls in it can be
/// inlined: the line-by-line run loop (`program`), where a dynamic call on every line costs more
/// than the call itself (the loop's state is saved around it).
pub trait WithDialect {
    type Output;
    fn run<D: Dialect + 'static>(self, dialect: D) -> Self::Output;
}

/// [`open`], handing the dialect to `work` as its own type.
pub fn open_with<W: WithDialect>(
    machine: &Machine,
    work: W,
) -> std::result::Result<W::Output, String> {
    Ok(match machine.dialect.as_str() {
        "gsk" => work.run(gsk::Gsk::new(machine)),
        "omniturn" => work.run(omniturn::OmniTurn::new(machine)),
        "allen_bradley" => work.run(allen_bradley::AllenBradley::new(machine)),
        "fanuc" => work.run(fanuc::Fanuc::new(machine)),
        "linuxcnc" => work.run(linuxcnc::LinuxCnc::new(machine)),
        other => {
            return Err(format!(
                "profile `{}` names dialect `{other}`, which threadcut does not know (known: gsk, omniturn, allen_bradley, fanuc, linuxcnc)",
                machine.name
            ))
        }
    })
}

struct Boxed;

impl WithDialect for Boxed {
    type Output = Box<dyn Dialect>;
    fn run<D: Dialect + 'static>(self, dialect: D) -> Box<dyn Dialect> {
        Box::new(dialect)
    }
}
