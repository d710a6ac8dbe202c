//! One module per controller. Each knows only its own words: it reads its cycles, raises its own
//! alarms, lowers them into the shared [`Job`](crate::thread::Job), and says how its plain moves are
//! written. Everything two controllers share lives in [`thread`](crate::thread).

pub mod allen_bradley;
pub mod fanuc;
pub mod fanuc15;
pub mod fanuc_family;
pub mod gsk;
pub mod haas;
pub mod lexicon;
pub mod linuxcnc;
pub mod mill;
pub mod omniturn;
pub mod one_block;
pub mod sinumerik;

use crate::diag::{Diagnostic, Result, Span};
use crate::gcode::modal::{GCode, Vocabulary};
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
    /// A turning cycle's block: the cycle complete (`Some`), or a block the control does not run
    /// where it stands (`None`): a cycle's block that reads the contour that follows it, and the
    /// blocks of that contour up to its last, where the cycle is complete.
    Turning(Option<Box<crate::turning::TurningJob>>),
    /// A block that is not a threading cycle, which the dialect has applied to the modal state
    /// itself (a block in its own syntax, or one whose move it completes, e.g. with a start
    /// angle): the move it makes, if any. It passes through unchanged, as a `Plain` block does.
    Applied(Option<crate::gcode::PlainMove>),
    /// A line in the dialect's own syntax that the lexer handed over without words
    /// ([`LineShape::unread`](crate::gcode::lexer::LineShape::unread): Sinumerik's assignments and
    /// calls), applied as [`Read::Applied`] is: the move it makes, and the address words the
    /// dialect read from it (`G96 S120 LIMS=2000 M3` gives G96, S120, M3), so that what follows the
    /// reader (the spindle and decimal-point checks) sees the block's words.
    Own {
        mv: Option<crate::gcode::PlainMove>,
        words: Vec<crate::gcode::Word>,
    },
}

/// How a controller's threading cycle takes a taper: the word and its sign and scale, as the
/// dialect reads it (each dialect states its own).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TaperWord {
    /// The cycles that take it and the word, as the manual writes them (`G76/G92 R(i)`).
    pub cycles: &'static str,
    pub letter: char,
    /// The value is X at the cycle's start minus X at its end (Fanuc's R(i)); otherwise the end
    /// minus the start (OmniTurn's A).
    pub start_minus_end: bool,
    /// The value is a radius whatever X's mode; otherwise it is written as X is (a diameter on a
    /// lathe programmed in diameters).
    pub radius: bool,
}

impl TaperWord {
    /// The word's value for a taper thread's cycle (mm; `diameter_x`: the lathe writes X as a
    /// diameter, which words written "as X is" follow).
    pub fn value(
        &self,
        cycle: &crate::thread::standard::lathe::TaperCycle,
        diameter_x: bool,
    ) -> f64 {
        let v = if self.start_minus_end {
            cycle.radial_change
        } else {
            -cycle.radial_change
        };
        if !self.radius && diameter_x {
            2.0 * v
        } else {
            v
        }
    }
}

/// A cycle that takes a taper as the crest diameters at the thread's start and end points rather
/// than as one word (Sinumerik CYCLE97: DM1 at SPL, DM2 at FPL; the run-in APP and run-out ROP lie
/// outside them on the same cone). Diameters whatever X's mode; an internal thread's are its tap
/// hole's (the crest).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub struct TaperDiameters {
    /// The cycle and its words, as the manual writes them (`CYCLE97 DM1/DM2`).
    pub cycles: &'static str,
    /// The word at the thread's start point, and that point's word (`DM1`, `SPL`).
    pub at_start: &'static str,
    pub start_point: &'static str,
    /// … at its end point (`DM2`, `FPL`).
    pub at_end: &'static str,
    pub end_point: &'static str,
    /// The run-in before the start point (`APP`), along the same cone.
    pub run_in: &'static str,
}

/// How a controller's threading cycle takes a taper.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(tag = "form", rename_all = "snake_case")]
pub enum CycleTaper {
    /// One word: the change of X over the cycle's Z travel (Fanuc's R(i), OmniTurn's A, …).
    Word(TaperWord),
    /// The crest diameters at the thread's two ends (Sinumerik's DM1/DM2).
    Diameters(TaperDiameters),
}

pub trait Dialect {
    fn name(&self) -> &'static str;
    fn conventions(&self) -> &Conventions;
    /// The G codes this controller has, with the words of its threading codes: the modal reader
    /// refuses any other code with the controller's alarm, and the hint of that alarm names the
    /// built-in controllers that have it ([`others_with`]).
    fn vocabulary(&self) -> &'static Vocabulary;
    /// What this controller's codes and words mean ([`crate::convert`] reads a block through the
    /// source's lexicon and writes it through the target's).
    fn lexicon(&self) -> &'static lexicon::Lexicon;
    /// The meanings of this controller's codes for conversion: its [`lexicon`](Dialect::lexicon)
    /// with the codes its [`conventions`](Dialect::conventions) give a function (the reference
    /// return, the work systems, the code that sets the position).
    fn meanings(&self) -> lexicon::Meanings {
        lexicon::Meanings::new(self.lexicon(), self.conventions())
    }
    /// A cheap look at a line before [`read`](Dialect::read): `false` promises that `read` would
    /// return `Read::Plain` without changing any state (its own or the modal state) and without a
    /// warning, so the caller may skip it. The default offers every line.
    fn prefilter(&self, _line: &Line) -> bool {
        true
    }
    /// Whether [`prefilter`](Dialect::prefilter) now answers every line as the dialect freshly
    /// opened for the same machine would (nothing of a cycle or a modal block in progress): a
    /// look ahead run with a fresh dialect then takes the same lines as plain (`program::ahead`).
    /// The default, `false`, never lets it.
    fn at_rest(&self) -> bool {
        false
    }
    /// The input has ended (or the program has, at M2/M30): a cycle still waiting for blocks (a
    /// contour's last block) is the control's alarm. The default: nothing waits.
    fn end_of_input(&mut self) -> Result<()> {
        Ok(())
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
    /// The native texts that may express `job`, most telling first: a search over the words whose
    /// values the job leaves open (a radial infeed is any cycle's tool angle 0; a tool angle the
    /// job states only for its chip areas). Each is read back and compared with the job's motion
    /// ([`crate::translate::native`]); an `Err` says which property of the job the cycle cannot
    /// express. The default: [`emit_native`](Dialect::emit_native)'s one proposal.
    fn native_candidates(&self, job: &Job) -> Vec<std::result::Result<Vec<String>, String>> {
        vec![self.emit_native(job)]
    }
    /// The machine settings the native text `native` relies on (values its cycles read from the
    /// control, not from their block), each with its value and whether the profile states it.
    /// The default: none.
    fn settings_read(&self, _native: &[String]) -> Vec<lexicon::Setting> {
        Vec::new()
    }
    /// Every machine setting this controller's native cycles may read ([`Self::settings_read`] of
    /// all of them).
    fn settings(&self) -> Vec<lexicon::Setting> {
        Vec::new()
    }
    /// The step this controller writes positions and leads on where it is coarser than its
    /// profile's resolution and depends on the lead (OmniTurn's feed modes: .00005\" up to a .2\"
    /// lead, .00025\" in G35, .0005\" in G35F2), in `units`. `None`: the profile's resolution,
    /// leads to the lead word's decimals.
    fn output_step(&self, _lead_mm: f64, _units: crate::units::Units) -> Option<f64> {
        None
    }
    /// A line in this controller's own syntax, which the lexer handed over unread
    /// ([`crate::gcode::LineShape::unread`]), as terms conversion understands. `None`: the
    /// controller has no syntax of its own.
    fn terms(&self, _line: &Line) -> Option<Result<Vec<lexicon::Term>>> {
        None
    }
    /// The word that tapers this controller's threading cycle, if it has one (`None` as well for
    /// a cycle that takes two diameters instead: see [`cycle_taper`](Dialect::cycle_taper)).
    fn taper_word(&self) -> Option<TaperWord> {
        None
    }
    /// How this controller's threading cycle takes a taper: its one taper word, or the diameters
    /// at the thread's ends (Sinumerik's CYCLE97); `None` when its cycles cut no taper.
    fn cycle_taper(&self) -> Option<CycleTaper> {
        self.taper_word().map(CycleTaper::Word)
    }
    /// The macro language this controller's programs are written in, if any: which front end of
    /// [`crate::interp`] runs a program that has control flow (subprograms, loops, parameters,
    /// expressions). `None` (the default): every line is a plain block.
    fn macros(&self) -> Option<crate::interp::Syntax> {
        None
    }
    /// The names of the files that may hold a program a call wants and the program's text does
    /// not hold, in the order they are tried in each include directory (LinuxCNC's `name.ngc`,
    /// Fanuc's `O9010`, `O9010.nc`, …). None by default: the control reads no other files.
    fn program_files(
        &self,
        _wanted: &crate::interp::library::Wanted,
    ) -> crate::interp::library::FileNames {
        crate::interp::library::FileNames::default()
    }

    /// The parameters the dialect keeps for the lines it reads itself (Sinumerik's R parameters
    /// and DEF variables, by name: `R1`, `DEPTH`): the interpreter starts from them when it takes
    /// over a program.
    fn parameters(&self) -> Vec<(String, f64)> {
        Vec::new()
    }
    /// A parameter the interpreter set: kept for the lines the dialect reads itself.
    fn set_parameter(&mut self, _name: &str, _value: f64) {}
    // issue 23 (turning cycles with an o-word profile): the interpreter's hand-over.
    /// After [`read`](Dialect::read): the o-word subroutine (its number) whose blocks the last
    /// block takes as its profile (LinuxCNC's G70/G71/G72 `Q`). The interpreter then hands its
    /// blocks to [`profile_block`](Dialect::profile_block) instead of `read`, and calls
    /// [`profile_end`](Dialect::profile_end) when it returns.
    fn profile_call(&mut self) -> Option<f64> {
        None
    }
    /// After a block: whether it asked for the contour the program's next instruction reads (a
    /// call the interpreter compiled as a profile read: Sinumerik's CYCLE95 NPP,
    /// [`crate::interp::Syntax::profile_calls`]); its blocks then come to
    /// [`profile_block`](Dialect::profile_block) until [`profile_end`](Dialect::profile_end).
    fn profile_follows(&mut self) -> bool {
        false
    }
    /// A block of the profile subroutine: read, not executed (the position may follow it, as
    /// the parameters that report it do in LinuxCNC).
    fn profile_block(&mut self, _line: &Line, _modal: &mut Modal) -> Result<()> {
        Ok(())
    }
    /// The profile subroutine returned (at `end`, the block that returned): the cycle it
    /// completes.
    fn profile_end(&mut self, _modal: &mut Modal, _end: Span) -> Result<Read> {
        Ok(Read::Settings)
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

/// The hint of a controller's alarm for a G code it does not have: the other built-in controllers
/// that have `code` with a block of these `letters` (or with other words), but for those whose
/// vocabulary is `except`'s (the one that raised the alarm). Runs only on that error path (it opens
/// every built-in profile).
pub fn others_with(code: u16, letters: &[u8], except: &Vocabulary) -> Option<String> {
    let g = crate::gcode::modal::g_name(code);
    let mut fit: Vec<String> = Vec::new();
    let mut other: Vec<String> = Vec::new();
    for (name, _) in crate::machine::BUILT_IN {
        let Some(machine) = Machine::built_in(name) else {
            continue;
        };
        let Ok(d) = open(&machine) else { continue };
        if std::ptr::eq(d.vocabulary(), except) {
            continue;
        }
        match d.vocabulary().get(code) {
            Some(entry) if entry.takes(letters) => fit.push(name.to_string()),
            Some(entry) => other.push(match entry.words {
                Some(w) => format!("{name} ({g} {})", spaced(w)),
                None => name.to_string(),
            }),
            None => {}
        }
    }
    let written: Vec<u8> = letters
        .iter()
        .copied()
        .filter(|l| !matches!(l, b'G' | b'N'))
        .collect();
    Some(if !fit.is_empty() {
        format!(
            "{} {g} with these words: check the program with {}",
            and_list(&fit, if fit.len() == 1 { "has" } else { "have" }),
            fit.iter()
                .map(|c| format!("--controller {c}"))
                .collect::<Vec<_>>()
                .join(" or ")
        )
    } else if !other.is_empty() {
        format!(
            "{} {g}, but not with {}: no built-in controller reads this block",
            and_list(&other, if other.len() == 1 { "has" } else { "have" }),
            if written.is_empty() {
                "these words".to_string()
            } else {
                spaced(&written)
            }
        )
    } else {
        format!("no built-in controller has {g}")
    })
}

/// `a`, `a and b`, `a, b and c`, then the verb.
fn and_list(items: &[String], verb: &str) -> String {
    let list = match items {
        [] => String::new(),
        [one] => one.clone(),
        [rest @ .., last] => format!("{} and {last}", rest.join(", ")),
    };
    format!("{list} {verb}")
}

/// Letters as `X Z K`.
fn spaced(letters: &[u8]) -> String {
    letters
        .iter()
        .map(|&l| (l as char).to_string())
        .collect::<Vec<_>>()
        .join(" ")
}

/// A block of `code` whose letters do not fit the form this controller reads (a one-block G76 on a
/// control with the two-block G76): the controller's alarm at the code, naming the form it
/// expected (`how`), with [`others_with`]'s hint.
pub(crate) fn foreign_form(
    line: &Line,
    at: Span,
    code: u16,
    vocabulary: &Vocabulary,
    message: String,
    how: &str,
) -> Diagnostic {
    let letters: Vec<u8> = line.words.iter().map(|w| w.letter).collect();
    let others = others_with(code, &letters, vocabulary).unwrap_or_default();
    Diagnostic::error(crate::diag::Code::UnknownCode, at, message)
        .with_hint(format!("{others}; on {}: {how}", vocabulary.controller))
}

/// A code of a vocabulary whose words are not stated (×10).
pub(crate) const fn g(code: u16) -> GCode {
    GCode::plain(code)
}

/// Every whole code G0–G99 but `except`, with `threads`' entries in their places: the vocabulary
/// of a controller whose public documentation lists only part of its codes. Only the codes that
/// other controllers thread with are refused, so that no code the controller may have is an alarm
/// (an excluded code's slot repeats the code before it, so that the list stays sorted).
pub(crate) const fn all_but(threads: &[GCode], except: &[u16]) -> [GCode; 100] {
    let mut out = [GCode::plain(0); 100];
    let mut i = 0;
    while i < 100 {
        let code = i as u16 * 10;
        let mut entry = GCode::plain(code);
        let mut j = 0;
        while j < except.len() {
            if except[j] == code && i > 0 {
                entry = out[i - 1];
            }
            j += 1;
        }
        let mut k = 0;
        while k < threads.len() {
            if threads[k].code == code {
                entry = threads[k];
            }
            k += 1;
        }
        out[i] = entry;
        i += 1;
    }
    out
}

/// How many whole codes `ranges` name (each `(first, last)`, G numbers, inclusive): the length of
/// [`ranges`]' list.
pub(crate) const fn count(ranges: &[(u16, u16)]) -> usize {
    let mut n = 0;
    let mut i = 0;
    while i < ranges.len() {
        n += (ranges[i].1 - ranges[i].0 + 1) as usize;
        i += 1;
    }
    n
}

/// A vocabulary's list from ranges of whole G numbers (`(first, last)`, inclusive, ascending and
/// apart), with `threads`' entries in their places: `N` is [`count`]`(ranges)` (a mismatch stops
/// the build). For a controller whose codes run in long series (work offsets G505–G599) or whose
/// public lists are partial, so that its list is read as the manual's ranges.
pub(crate) const fn ranges<const N: usize>(ranges: &[(u16, u16)], threads: &[GCode]) -> [GCode; N] {
    assert!(count(ranges) == N, "N must be count(ranges)");
    let mut out = [GCode::plain(0); N];
    let mut at = 0;
    let mut i = 0;
    while i < ranges.len() {
        assert!(i == 0 || ranges[i].0 > ranges[i - 1].1, "ranges ascend");
        let mut code = ranges[i].0;
        while code <= ranges[i].1 {
            let mut entry = GCode::plain(code * 10);
            let mut k = 0;
            while k < threads.len() {
                if threads[k].code == code * 10 {
                    entry = threads[k];
                }
                k += 1;
            }
            out[at] = entry;
            at += 1;
            code += 1;
        }
        i += 1;
    }
    out
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

/// Refuses a number written with an exponent (`X1e3`, `Z-2.5E-4`): G-code has none, so the text
/// reads as the number and then an `E` word glued to it, and a block that gives E no meaning
/// would silently move to X1. For controllers whose E is a word of some blocks only (a lead, a
/// lead-in) and that do not otherwise check for unused words: each calls this on the blocks where
/// E means nothing.
pub(crate) fn refuse_exponent(line: &Line) -> Result<()> {
    // Most lines a dialect reads have no E at all: the word summary says so without a look.
    if !line.summary.has_letter(b'E') {
        return Ok(());
    }
    let glued = line.words.windows(2).find(|pair| {
        let (number, e) = (&pair[0], &pair[1]);
        e.letter == b'E'
            && !number.is_bare()
            && number.span.start + u64::from(number.span.len) == e.span.start
            && number
                .raw(line.text)
                .last()
                .is_some_and(|b| b.is_ascii_digit() || *b == b'.')
    });
    match glued {
        Some(pair) => {
            let (number, e) = (&pair[0], &pair[1]);
            let text = crate::gcode::lexer::show(
                &line.text[number.span.column as usize - 1
                    ..e.span.column as usize - 1 + e.span.len as usize],
            );
            Err(Diagnostic::error(
                crate::diag::Code::Syntax,
                Span::new(
                    number.span.start,
                    number.span.len + e.span.len,
                    number.span.line,
                    number.span.column,
                ),
                format!(
                    "`{text}`: G-code numbers have no exponent, and E means nothing on this block"
                ),
            )
            .with_hint(format!(
                "this reads as {}{} and an E word; write the number out in full",
                number.letter as char,
                crate::gcode::lexer::show(number.raw(line.text))
            )))
        }
        None => Ok(()),
    }
}

/// Where a cycle starts: the tool's position, which must be known on both axes (at power-on, after
/// a reference return the profile does not place, and after a move in machine coordinates an axis
/// is not). `hint` says how this controller's program positions the tool.
pub(crate) fn start_point(
    modal: &Modal,
    cycle: Span,
    name: &str,
    hint: &str,
) -> Result<crate::units::Pos> {
    modal
        .position
        .known()
        .ok_or_else(|| unknown_start(modal, cycle, name, "starts where the tool is", hint))
}

/// Where a threading cycle starts whose pass table does not depend on its start point (the depth
/// of each pass from the thread height and the first depth, the X of each pass programmed): as
/// [`start_point`], but a run that allows it ([`Modal::start_unstated`]: `passes` for a cycle shown
/// on its own) takes an unknown axis at [`crate::gcode::modal::UNSTATED_START`] and marks it, and
/// what depends on it (the Z where each pass starts, the retract, the side) is reported not known.
pub(crate) fn start_point_unstated(
    modal: &mut Modal,
    cycle: Span,
    name: &str,
    hint: &str,
) -> Result<crate::units::Pos> {
    modal
        .start_or_unstated()
        .ok_or_else(|| unknown_start(modal, cycle, name, "starts where the tool is", hint))
}

/// The error of a cycle whose start point is not known: it names the axes that are not.
#[cold]
pub(crate) fn unknown_start(
    modal: &Modal,
    cycle: Span,
    name: &str,
    what: &str,
    hint: &str,
) -> Diagnostic {
    let axes = modal.position.unknown_axes();
    Diagnostic::error(
        crate::diag::Code::UnknownPosition,
        cycle,
        format!(
            "{name} {what}, and the tool's {} {} not known here",
            axes.join(" and "),
            if axes.len() == 1 { "is" } else { "are" }
        ),
    )
    .with_hint(format!(
        "{hint}; for a cycle shown without the lines before it, give the start point (--start X,Z)"
    ))
}

/// Warns when one lead is longer than the thread's Z travel: each pass turns the spindle less than
/// once, which is most often a lead written wrong. `hint` is the controller's likely slip.
pub(crate) fn lead_warning(
    lead: f64,
    travel_z: f64,
    units: crate::units::Units,
    length: crate::units::Tolerance,
    span: Span,
    hint: &str,
    warnings: &mut Vec<Diagnostic>,
) {
    if length.gt(lead, travel_z.abs()) {
        warnings.push(
            Diagnostic::warning(
                crate::diag::Code::Suspicious,
                span,
                format!(
                    "the lead {} is longer than the thread ({} along Z): each pass turns the spindle less than once",
                    units.from_mm(lead),
                    units.show(travel_z.abs())
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
        "fanuc15" => work.run(fanuc15::new(machine)),
        "haas" => work.run(haas::Haas::new(machine)),
        "linuxcnc" => work.run(linuxcnc::LinuxCnc::new(machine)),
        "sinumerik" => work.run(sinumerik::Sinumerik::new(machine)),
        other => {
            return Err(format!(
                "profile `{}` names dialect `{other}`, which threadcut does not know (known: gsk, omniturn, allen_bradley, fanuc, fanuc15, haas, linuxcnc, sinumerik)",
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `Vocabulary::get` searches by halving: every built-in controller's list is sorted, and
    /// knows its own threading codes.
    #[test]
    fn every_vocabulary_is_sorted_and_knows_its_thread_codes() {
        for (name, _) in crate::machine::BUILT_IN {
            let d = open(&Machine::built_in(name).unwrap()).unwrap();
            let v = d.vocabulary();
            assert!(
                v.g_codes.windows(2).all(|w| w[0].code <= w[1].code),
                "{name}"
            );
            assert!(v.controller.starts_with(d.name()), "{name}");
            assert!(v.get(0).is_some() && v.get(10).is_some(), "{name}");
            let thread = d.conventions().thread_move;
            assert!(v.get(thread).is_some_and(|g| g.threads), "{name}");
        }
        // What each refuses (the cases) and keeps (fractions by their whole number).
        let known = |c: &str, code: u16| {
            open(&Machine::built_in(c).unwrap())
                .unwrap()
                .vocabulary()
                .get(code)
                .is_some()
        };
        assert!(!known("fanuc", 780) && !known("fanuc", 330) && !known("fanuc", 910));
        assert!(known("fanuc", 71) && known("fanuc", 1120) && known("fanuc", 503));
        assert!(known("gsk980", 780) && known("gsk980", 62));
        assert!(!known("linuxcnc", 320) && known("linuxcnc", 331) && known("linuxcnc", 382));
        assert!(!known("omniturn", 760) && known("omniturn", 720) && known("omniturn", 310));
        assert!(!known("ab9", 320) && !known("ab9", 760) && known("ab9", 780) && known("ab9", 330));
        // Fanuc system B: G33 threads, G78 is the single-pass cycle, G90/G91 and G94/G95 are modes;
        // G32 is system A's.
        assert!(known("fanuc-b", 330) && known("fanuc-b", 780) && known("fanuc-b", 910));
        assert!(known("fanuc-b", 950) && known("fanuc-b", 921) && !known("fanuc-b", 320));
        // FS15: system A's list with the one-block G76.
        assert!(known("fanuc15", 320) && !known("fanuc15", 330) && !known("fanuc15", 780));
        // Haas: its own codes above G99, none of the other controls' threading codes.
        assert!(known("haas", 1540) && known("haas", 1870) && known("haas", 3910));
        assert!(!known("haas", 330) && !known("haas", 340) && !known("haas", 780));
        assert!(known("haas", 950) && known("haas", 50) && known("haas", 1120));
        // Sinumerik: G33 and its own codes; no ISO units, no other thread codes.
        assert!(known("sinumerik", 7000) && known("sinumerik", 6420) && known("sinumerik", 5990));
        assert!(known("sinumerik", 3310) && known("sinumerik", 9730) && known("sinumerik", 920));
        assert!(!known("sinumerik", 200) && !known("sinumerik", 210) && !known("sinumerik", 320));
        assert!(!known("sinumerik", 760) && !known("sinumerik", 780) && !known("sinumerik", 5040));
    }

    /// One table for Fanuc's three G-code systems: in each, the threading entries are exactly the
    /// system's thread move and cycles, with the program format's words; the other codes of the
    /// threading family follow the system (G20/G21 units in A/B, cycles in C).
    #[test]
    fn fanuc_vocabularies_follow_the_g_code_system() {
        use crate::machine::GCodeSystem;
        for system in [GCodeSystem::A, GCodeSystem::B, GCodeSystem::C] {
            let codes = fanuc_family::GCodes::of(system);
            for (v, single, multiple) in [
                (fanuc::vocabulary(system), &b"XZUWRFQ"[..], &b"XZUWRPQF"[..]),
                (
                    fanuc15::vocabulary(system),
                    &b"XZUWIFQ"[..],
                    &b"XZUWIKDFEAPQ"[..],
                ),
            ] {
                let threads: Vec<u16> = v
                    .g_codes
                    .iter()
                    .filter(|g| g.threads)
                    .map(|g| g.code)
                    .collect();
                let mut want = vec![codes.thread_move, codes.single, codes.multiple];
                want.sort();
                assert_eq!(threads, want, "{system:?}");
                assert_eq!(v.get(codes.single).unwrap().words, Some(single));
                assert_eq!(v.get(codes.multiple).unwrap().words, Some(multiple));
                assert!(v.get(codes.set_position).is_some());
                assert!(v.get(codes.units[0]).is_some() && v.get(codes.units[1]).is_some());
                for c in codes.canned {
                    assert!(v.get(*c).is_some(), "{system:?} G{}", c / 10);
                }
            }
        }
        let c = fanuc::vocabulary(GCodeSystem::C);
        // In C: G20 turning, G21 threading, G24 facing cycles; G70/G71 units; G76 drilling.
        assert!(c.get(200).is_some_and(|g| !g.threads) && c.get(210).is_some_and(|g| g.threads));
        assert!(c.get(240).is_some() && c.get(760).is_some_and(|g| !g.threads));
        assert!(c.get(320).is_none() && fanuc::VOCABULARY.get(910).is_none());
    }

    /// A code is judged once: every code a dialect's `PositionCodes` gives a meaning is a code of
    /// its vocabulary (else the meaning could never apply), and the preset of Fanuc's other
    /// G-code systems is no code of this one (G92.1 is B's and C's preset and G92 is A's threading
    /// cycle: system A does not read G92.1 as G92, nor system B G50.3 as G50).
    #[test]
    fn position_codes_are_codes_of_the_vocabulary() {
        for (name, _) in crate::machine::BUILT_IN {
            let d = open(&Machine::built_in(name).unwrap()).unwrap();
            let (v, p) = (d.vocabulary(), &d.conventions().positions);
            let codes = p
                .returns
                .iter()
                .chain(p.stores)
                .map(|(c, _)| *c)
                .chain(p.machine_moves.iter().copied())
                .chain(p.work_systems.iter().copied())
                .chain(p.offset_changes.iter().copied())
                .chain(p.not_moves.iter().copied())
                .chain((p.from_reference != 0).then_some(p.from_reference));
            for c in codes {
                assert!(v.get(c).is_some(), "{name}: G{}", f64::from(c) / 10.0);
            }
        }
        use crate::machine::GCodeSystem;
        assert!(fanuc::vocabulary(GCodeSystem::A).get(921).is_none());
        assert!(fanuc::vocabulary(GCodeSystem::A).get(503).is_some());
        for system in [GCodeSystem::B, GCodeSystem::C] {
            assert!(fanuc::vocabulary(system).get(503).is_none());
            assert!(fanuc15::vocabulary(system).get(503).is_none());
            assert!(fanuc::vocabulary(system).get(921).is_some());
            assert!(
                fanuc::vocabulary(system).get(502).is_some(),
                "G50.2 polygon turning"
            );
        }
        assert!(fanuc15::vocabulary(GCodeSystem::A).get(921).is_none());
    }

    #[test]
    fn the_hint_names_the_controllers_that_have_a_code_with_these_words() {
        assert_eq!(
            others_with(780, b"GXZPQF", &fanuc::VOCABULARY).unwrap(),
            "gsk980 has G78 with these words: check the program with --controller gsk980"
        );
        // ab9's G78 takes K and D but no Q: with K and D only ab9 fits.
        assert_eq!(
            others_with(780, b"GXZKDFAP", &fanuc::VOCABULARY).unwrap(),
            "ab9 has G78 with these words: check the program with --controller ab9"
        );
        assert_eq!(
            others_with(3330, b"G", &fanuc::VOCABULARY).unwrap(),
            "no built-in controller has G333"
        );
    }
}
