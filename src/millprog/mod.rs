//! The milling reader: a machining-centre program streamed into its motion
//! ([`crate::mill::motion::MillMotion`]) and its tapping cycles
//! ([`crate::mill::motion::TapCycle`]), in constant memory for a straight-line program; a program
//! with control flow (Custom Macro B, LinuxCNC o-words) is run by the interpreter from its first
//! line of control flow, every executed block coming back to the same reading.
//!
//! Decisions: docs/milling.md, "Reading milling programs".

mod arc;
mod cycles;
mod dispatch;
pub mod output;
mod state;

use std::io::BufRead;

use crate::diag::{Code, Diagnostic, Span};
use crate::dialect::mill::{language, MillLanguage};
use crate::gcode::lexer::{index_words, WordIndex};
use crate::gcode::{Conventions, Modal, Reader, Word};
use crate::interp::{self, Control, Text};
use crate::mill::motion::{MillMotion, TapCycle};
use crate::mill::profile::MillProfile;
use crate::units::Units;

use state::Mill;

/// What a milling program's reading hands on, in the program's order.
pub trait Sink {
    /// A move; `work` is the work coordinate system in force (×10: G54 = 540, G54.1 = 541).
    fn motion(&mut self, m: &MillMotion, work: u16) -> Result<(), Diagnostic>;
    /// A tapping cycle, before its moves (once a hole).
    fn tap(&mut self, t: &TapCycle) -> Result<(), Diagnostic>;
}

/// How a milling program is read.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    /// Executed blocks at most (a program with control flow).
    pub max_blocks: u64,
    /// Where the tool is before the first line (mm), if known.
    pub start: Option<[f64; 3]>,
    /// The units at power-on.
    pub units: Units,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            max_blocks: 1_000_000,
            start: None,
            units: Units::Mm,
        }
    }
}

/// What was read.
#[derive(Clone, Debug, Default)]
pub struct Summary {
    pub lines: u32,
    pub moves: u64,
    pub taps: u64,
    /// The line the interpreter took over from, if the program has control flow.
    pub interpreted_from: Option<u32>,
}

struct Counting<'s> {
    sink: &'s mut dyn Sink,
    summary: Summary,
}

impl state::Out for Counting<'_> {
    fn motion(&mut self, m: &MillMotion, work: u16) -> Result<(), Diagnostic> {
        self.summary.moves += 1;
        self.sink.motion(m, work)
    }
    fn tap(&mut self, t: &TapCycle) -> Result<(), Diagnostic> {
        self.summary.taps += 1;
        self.sink.tap(t)
    }
}

/// The language of a milling profile.
pub fn language_of(profile: &MillProfile) -> Result<MillLanguage, Diagnostic> {
    language(&profile.language).ok_or_else(|| {
        Diagnostic::error(
            Code::Input,
            Span::new(0, 0, 0, 0),
            format!(
                "the milling profile `{}` names the language `{}`, which threadcut does not read",
                profile.name, profile.language
            ),
        )
        .with_hint("language is one of fanuc, haas, linuxcnc, centroid")
    })
}

/// Reads a milling program, handing every move and tapping cycle to `sink`.
pub fn run<R: BufRead>(
    input: R,
    profile: &MillProfile,
    options: &Options,
    sink: &mut dyn Sink,
) -> Result<Summary, Diagnostic> {
    let lang = language_of(profile)?;
    let mut mill = Mill::new(
        lang,
        profile.reference.clone().unwrap_or_default(),
        options.units,
    );
    if let Some(p) = options.start {
        mill.pos = p.map(Some);
    }
    let mut out = Counting {
        sink,
        summary: Summary::default(),
    };
    let mut reader = Reader::new(input).with_syntax(lang.lexer);
    if lang.macros.is_some_and(|m| m.lang == interp::Lang::MacroB) {
        reader.keep_prefix(interp::PREFIX_KEPT);
    }
    loop {
        let offset = reader.offset();
        let line = match reader.next_line() {
            None => break,
            Some(Ok(line)) => line,
            Some(Err(e)) => {
                // A line the lexer refuses that the macro language reads: the interpreter takes
                // over from it.
                let consumed = (reader.offset() - offset) as usize;
                let text = reader.handed_out(consumed).unwrap_or_default();
                match lang.macros {
                    Some(m) if m.looks_like_macro(text) => {
                        return interpret(reader, (offset, e.span.line), &mut mill, options, out);
                    }
                    _ => return Err(e),
                }
            }
        };
        if lang
            .macros
            .is_some_and(|m| m.control(&line) == Control::Interpret)
        {
            let at = (offset, line.number);
            return interpret(reader, at, &mut mill, options, out);
        }
        out.summary.lines = line.number;
        mill.block(&line, &mut out)?;
        if mill.ended {
            break;
        }
    }
    Ok(out.summary)
}

/// Runs the rest of the program from line `at` with the interpreter.
fn interpret<R: BufRead>(
    mut reader: Reader<R>,
    at: (u64, u32),
    mill: &mut Mill,
    options: &Options,
    mut out: Counting,
) -> Result<Summary, Diagnostic> {
    let syntax = mill.lang.macros.expect("a control with macros");
    let rest = reader
        .take_rest(at.0, interp::MAX_PROGRAM_BYTES)
        .map_err(|e| {
            Diagnostic::error(
                Code::Input,
                Span::new(at.0, 0, at.1, 1),
                format!("cannot read the input: {e}"),
            )
        })?;
    let Some((bytes, base)) = rest else {
        return Err(Diagnostic::error(
            Code::Input,
            Span::new(at.0, 0, at.1, 1),
            format!(
                "the program has control flow from line {} on, and is longer than {} MiB from there",
                at.1,
                interp::MAX_PROGRAM_BYTES >> 20
            ),
        ));
    };
    let first_line = if base == 0 { 1 } else { at.1 };
    let code = interp::compile(Text::new(bytes, first_line, base), &syntax, mill.lang.lexer);
    let files = mill.lang.program_files;
    let names = |w: &interp::library::Wanted| files(w);
    let linked = interp::Linker {
        names: &names,
        library: None,
        syntax: &syntax,
        lexer: mill.lang.lexer,
    }
    .link(code);
    out.summary.interpreted_from = Some(at.1);
    // Only units, modes and the F register are the interpreter's to read here (the position is
    // the mill's: `Host::mill_position`).
    let conv = Conventions {
        uw_incremental: false,
        g90_g91_distance: true,
        diameter_x: false,
        thread_move: 330,
        tpi_letter: b'I',
        lead_letter: b'K',
        lead_along_path: false,
        set_position: 920,
        canned_cycles: &[],
        unmodelled: &[],
        units_codes: crate::gcode::modal::G20_G21,
        positions: crate::gcode::modal::PositionCodes::FANUC,
        syntax: mill.lang.lexer,
    };
    let mut host = Host {
        mill,
        out: &mut out,
        modal: Modal::new(&conv, options.units, [1.0, 1.0]),
    };
    host.sync();
    let limits = interp::Limits {
        max_blocks: options.max_blocks,
    };
    interp::run(&linked, &syntax, limits, at.1, &mut host)?;
    Ok(out.summary)
}

/// The interpreter's host: each executed block read as a streamed line is.
struct Host<'a, 'o> {
    mill: &'a mut Mill,
    out: &'a mut Counting<'o>,
    /// The lathe-shaped modal state the interpreter reads its units and modes from.
    modal: Modal,
}

impl Host<'_, '_> {
    fn sync(&mut self) {
        self.modal.units = self.mill.units;
        self.modal.absolute = self.mill.absolute;
        self.modal.f_word = self.mill.f;
        self.modal.no_point = if self.mill.lang.calculator {
            [1.0, 1.0]
        } else {
            [0.001, 0.0001]
        };
    }
}

impl interp::Host for Host<'_, '_> {
    type Error = Diagnostic;

    fn block(
        &mut self,
        text: interp::text::TextLine<'_>,
        words: &[Word],
        block_delete: bool,
        ctx: &interp::Context,
    ) -> Result<(), Diagnostic> {
        let mut index: WordIndex = [0; 32];
        index_words(words, &mut index);
        let line = interp::executed_line(text, words, block_delete, ctx, &index);
        self.out.summary.lines = self.out.summary.lines.max(line.number);
        self.mill.block(&line, self.out)?;
        self.sync();
        Ok(())
    }

    fn modal(&self) -> &Modal {
        &self.modal
    }

    fn mill_position(&self) -> Option<[Option<f64>; 3]> {
        let m = &*self.mill;
        Some(std::array::from_fn(|a| {
            m.pos[a].map(|v| m.units.from_mm(v - m.local[a] - m.g92[a]))
        }))
    }

    fn resolution(&self, units: Units) -> f64 {
        self.mill.increment(units)
    }

    fn warn(&mut self, _d: Diagnostic) {}

    fn in_calls(&self, mut e: Diagnostic, calls: &[Span]) -> Diagnostic {
        if e.calls.is_empty() {
            e.calls = calls.to_vec();
        }
        e
    }
}

#[cfg(test)]
mod tests;
