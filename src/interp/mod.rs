//! The macro interpreter: programs with control flow (subroutines and subprograms, loops,
//! conditions, parameters and expressions), run the way the control runs them.
//!
//! A straight-line program never comes here: `program`'s run loop streams it. When that loop meets
//! a line of control flow, it hands the rest of the program to this module, which compiles it
//! once ([`compile`]: statements and expressions parsed into flat instructions with jumps, see
//! [`code`]) and runs it ([`vm`]), handing every executed block back to the run loop as a line
//! whose words carry evaluated values and whose spans point at the source text. Two front ends
//! feed the one evaluator: LinuxCNC's o-words and parameters ([`ngc`]) and Fanuc's Custom Macro B
//! ([`fanuc`], which GSK shares with its own `G65 H` operations), and Sinumerik's NC language
//! ([`sinumerik`]: R parameters, labels, structured flow, PROC subprograms in the same file). The dialect says which
//! ([`crate::dialect::Dialect::macros`]); this module knows no controller by name.
//!
//! Every run is bounded: a number of executed blocks (`--max-blocks`), a budget of expression
//! steps, call depths as the controls limit them, bracket nesting, and the size of the program
//! held in memory ([`MAX_PROGRAM_BYTES`]). The design: docs/architecture.md, "The interpreter".

pub(crate) mod code;
pub(crate) mod expr;
pub(crate) mod fanuc;
pub mod library;
pub(crate) mod ngc;
pub(crate) mod scan;
pub(crate) mod sinumerik;
pub mod text;
pub(crate) mod vm;

pub use expr::Lang;
pub use text::{Text, TextLine};
pub(crate) use vm::{Context, Host, Outcome};

use std::collections::HashMap;

use crate::diag::FILE_SPACING;
use crate::gcode::lexer::WordIndex;
use crate::gcode::{Line, LineShape, Word, WordSummary};
use library::{FileNames, Library, Missing, Wanted};

/// The line a host executes for a block the interpreter ran: its words evaluated, `index` filled
/// from them ([`crate::gcode::lexer::index_words`]), its shape from the run's context.
pub fn executed_line<'l>(
    text: TextLine<'l>,
    words: &'l [Word],
    block_delete: bool,
    ctx: &Context,
    index: &'l WordIndex,
) -> Line<'l> {
    Line {
        number: text.number,
        offset: text.offset,
        text: text.text,
        raw: text.raw,
        words,
        shape: LineShape {
            block_delete,
            percent: false,
            unread: ctx.unread,
        },
        before: &[],
        summary: WordSummary::of(words),
        index,
    }
}

/// A control's macro language, as its dialect describes it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Syntax {
    pub lang: Lang,
    /// How deep calls nest: LinuxCNC's subroutine levels with the main program counted
    /// (o-word calls), or the Fanuc-style subprogram nesting (M98).
    pub max_call_depth: u32,
    /// How deep Fanuc macro calls (G65) nest.
    pub max_macro_depth: u32,
    /// `G65 Hm P#i Q#j R#k` is an operation (GSK), not a macro call (Fanuc).
    pub g65_operations: bool,
    /// `M98` takes the call count in L (Fanuc); without, only packed in P (`P00031000`, GSK).
    pub m98_l_word: bool,
    /// `M97 P… L…` calls the block with that sequence number in the same program as a
    /// subprogram (Haas's local subprogram call).
    pub m97_local_calls: bool,
    /// `M99 P…` jumps to that sequence number in the program it is in, without returning, and
    /// `[condition] M99 P…` jumps when the condition holds (Haas); otherwise `M99 P…` returns to
    /// the caller's block of that number (Fanuc).
    pub m99_p_jumps: bool,
    /// `#10000`–`#10999` are common variables too (Haas's NGC numbering of its general-purpose
    /// variables), besides `#100`–`#199` and `#500`–`#999`.
    pub wide_commons: bool,
    /// Names a block may hold that are the dialect's words, not calls of subprograms (Sinumerik's
    /// keywords and the calls of its cycles): a line of them is no reason to interpret.
    pub plain_names: &'static [&'static [&'static str]],
    /// Cycle calls whose first argument names the contour they turn: a subprogram (`"NAME"`) or
    /// a section of the same program between two labels (`"START:END"`), which the interpreter
    /// runs as the cycle's profile (Sinumerik's CYCLE95; [`Host::profile_end`](vm::Host) at its
    /// end).
    pub profile_calls: &'static [&'static str],
}

impl Syntax {
    /// LinuxCNC's o-words: subroutines and control flow, parameters, expressions (o-code.adoc);
    /// calls nest ten levels, the main program counted (INTERP_SUB_ROUTINE_LEVELS). The lathe's
    /// and the mill's LinuxCNC share it.
    pub const O_WORDS: Syntax = Syntax {
        lang: Lang::Ngc,
        max_call_depth: 10,
        max_macro_depth: 0,
        g65_operations: false,
        m98_l_word: false,
        m97_local_calls: false,
        m99_p_jumps: false,
        wide_commons: false,
        plain_names: &[],
        profile_calls: &[],
    };

    /// Fanuc's Custom Macro B with Fanuc's nesting (four levels of M98, four of G65), G65 a
    /// call, M98's count in L: the base the Fanuc-style controls state their differences from.
    pub const MACRO_B: Syntax = Syntax {
        lang: Lang::MacroB,
        max_call_depth: 4,
        max_macro_depth: 4,
        g65_operations: false,
        m98_l_word: true,
        m97_local_calls: false,
        m99_p_jumps: false,
        wide_commons: false,
        plain_names: &[],
        profile_calls: &[],
    };
}

/// What a run may take.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Executed blocks and statements, the program's whole run (`--max-blocks`).
    pub max_blocks: u64,
}

impl Default for Limits {
    fn default() -> Limits {
        Limits {
            max_blocks: 1_000_000,
        }
    }
}

/// The largest program the interpreter holds in memory (the part from its first line of control
/// flow on): far more than any program written with macros, and a bound on what a run costs.
pub const MAX_PROGRAM_BYTES: usize = 16 << 20;

/// How much of a program's plain beginning the run loop keeps, for Fanuc-style programs whose
/// `GOTO` may jump back into it (a `GOTO 10` to an `N10` before the first macro statement).
pub const PREFIX_KEPT: usize = 1 << 20;

/// What the run loop does with a line it read as a plain block.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// A plain block: streamed.
    No,
    /// A call, a return or a numbered program: the interpreter takes over from this line.
    Interpret,
    /// The main program ends after this block (M2, M30): later lines are not run.
    End,
}

impl Syntax {
    /// Whether a line the lexer refused is written in this macro language (the interpreter then
    /// takes over from it; otherwise the lexer's error stands).
    pub fn looks_like_macro(&self, text: &[u8]) -> bool {
        match self.lang {
            Lang::Ngc => ngc::looks_like_macro(text),
            Lang::MacroB => fanuc::looks_like_macro(text),
            Lang::Sinumerik => {
                sinumerik::looks_like_macro(text, self.plain_names)
                    || sinumerik::profile_call(text, self.profile_calls).is_some()
            }
        }
    }

    /// What a lexed line is to the interpreter. Cheap for most lines (the word summary answers).
    #[inline]
    pub fn control(&self, line: &Line) -> Control {
        if line.shape.unread {
            // A line in the control's own syntax (Sinumerik's): program flow, a label, a call by
            // name or an expression take the interpreter.
            return if self.looks_like_macro(line.text) {
                Control::Interpret
            } else {
                Control::No
            };
        }
        // (Sinumerik's address words are none of the interpreter's: its calls are names, and
        // `L10` alone in its block — with its block number and a repeat count `P` — the numbered
        // subprogram L10.)
        if self.lang == Lang::Sinumerik {
            let l = line.words.iter().filter(|w| w.letter == b'L').count();
            let others = line
                .words
                .iter()
                .any(|w| !matches!(w.letter, b'L' | b'N' | b'P'));
            return if l == 1 && !others {
                Control::Interpret
            } else {
                Control::No
            };
        }
        if !line.summary.may_be_control() {
            return Control::No;
        }
        self.control_words(line)
    }

    /// (Whole codes compare exactly as doubles: no rounding on the way, which the fast path would
    /// pay for on every M and G line.)
    #[inline(always)]
    fn control_words(&self, line: &Line) -> Control {
        let mut end = false;
        for w in line.words {
            let v = w.value;
            match w.letter {
                b'M' => match self.m_code(v) {
                    Control::Interpret => return Control::Interpret,
                    Control::End => end = true,
                    Control::No => {}
                },
                b'G' if v == 65.0 && self.lang == Lang::MacroB => return Control::Interpret,
                b'O' if self.lang == Lang::Ngc => return Control::Interpret,
                _ => {}
            }
        }
        if end {
            Control::End
        } else {
            Control::No
        }
    }

    /// What an M code is to the interpreter: a call or a return (M98, M99, and M97 where the
    /// control has local subprograms), the program's end (M2, M30), or nothing.
    #[inline(always)]
    fn m_code(&self, v: f64) -> Control {
        if v == 98.0 || v == 99.0 || (v == 97.0 && self.m97_local_calls) {
            Control::Interpret
        } else if v == 2.0 || v == 30.0 {
            Control::End
        } else {
            Control::No
        }
    }
}

/// Compiles a program's text (held from some line on) for `syntax`. Never fails: a line that
/// cannot run becomes an instruction that raises its error when the run reaches it, as the
/// control raises it.
pub(crate) fn compile(text: Text, syntax: &Syntax, lexer: crate::gcode::Syntax) -> code::Code {
    match syntax.lang {
        Lang::Ngc => ngc::compile(text, lexer),
        Lang::MacroB => fanuc::compile(text, syntax, lexer),
        Lang::Sinumerik => sinumerik::compile(text, syntax, lexer),
    }
}

/// The most files a program's calls may read (each at most [`MAX_PROGRAM_BYTES`]).
pub const MAX_FILES: usize = 64;

/// A program and the programs its calls found in other files.
pub(crate) struct Linked {
    /// The main text's code first, then each file's, in the order they were found.
    pub units: Vec<code::Code>,
    /// Where a call to a program its own text does not hold goes: the unit and the first
    /// instruction, or what was looked for.
    pub external: HashMap<Wanted, Result<(u32, u32), Missing>>,
}

/// What a program's calls need from outside it: the dialect's file names for a wanted program,
/// and the library that has the files.
pub(crate) struct Linker<'a> {
    pub names: &'a dyn Fn(&Wanted) -> FileNames,
    pub library: Option<&'a Library>,
    pub syntax: &'a Syntax,
    pub lexer: crate::gcode::Syntax,
}

impl Linker<'_> {
    /// Finds, for every call whose program is written as a number or a name and is not in the
    /// calling text, the program in the library (and the programs those call, to
    /// [`MAX_FILES`] files). A program not found is an error only when its call runs.
    pub(crate) fn link(&self, main: code::Code) -> Linked {
        let mut linked = Linked {
            units: vec![main],
            external: HashMap::new(),
        };
        let mut files: HashMap<u32, u32> = HashMap::new();
        let mut u = 0;
        while u < linked.units.len() {
            for wanted in static_calls(&linked.units[u]) {
                if linked.external.contains_key(&wanted) {
                    continue;
                }
                if let Some(at) = defined(&linked.units, &wanted) {
                    linked.external.insert(wanted, Ok(at));
                    continue;
                }
                let names = (self.names)(&wanted);
                let Some(library) = self.library.filter(|_| !names.names.is_empty()) else {
                    continue;
                };
                let found = library.0.find(&names).and_then(|found| {
                    let unit = self.unit_of(&mut linked, &mut files, found)?;
                    entry_of(&linked.units[unit as usize], &wanted)
                        .map(|entry| (unit, entry))
                        .ok_or_else(|| Missing {
                            tried: Vec::new(),
                            problem: Some(format!(
                                "the file does not hold {}",
                                what(linked.units[0].lang, &wanted)
                            )),
                        })
                });
                linked.external.insert(wanted, found);
            }
            u += 1;
        }
        linked
    }

    /// The unit of a file found: compiled the first time.
    fn unit_of(
        &self,
        linked: &mut Linked,
        files: &mut HashMap<u32, u32>,
        found: library::Found,
    ) -> Result<u32, Missing> {
        if let Some(u) = files.get(&found.file) {
            return Ok(*u);
        }
        if linked.units.len() > MAX_FILES || found.file == 0 {
            return Err(Missing {
                tried: vec![found.name],
                problem: Some(format!(
                    "a program's calls read at most {MAX_FILES} other files"
                )),
            });
        }
        let text = Text::new(found.text, 1, u64::from(found.file) * FILE_SPACING);
        linked.units.push(compile(text, self.syntax, self.lexer));
        let u = linked.units.len() as u32 - 1;
        files.insert(found.file, u);
        Ok(u)
    }
}

/// How a wanted program is named in messages.
pub(crate) fn what(lang: Lang, wanted: &Wanted) -> String {
    match (lang, wanted) {
        (Lang::MacroB, Wanted::Number(n)) => format!("program O{n:04}"),
        (_, Wanted::Number(n)) => format!("o{n}"),
        (Lang::Sinumerik, Wanted::Name(s)) => format!("subprogram {s}"),
        (_, Wanted::Name(s)) => format!("o<{s}> sub"),
    }
}

/// The programs a text's calls name by a number or a name as written.
fn static_calls(code: &code::Code) -> Vec<Wanted> {
    use code::CallTarget;
    let mut out = Vec::new();
    for call in &code.calls {
        let wanted = match (&call.target, code.lang) {
            (CallTarget::Program { number, packed }, Lang::MacroB) => {
                match code.exprs.constant(*number) {
                    Some(p) if p >= 0.0 && p.fract() == 0.0 && p < 1e8 => {
                        let p = p as u32;
                        Wanted::Number(if *packed && p > 9999 { p % 10_000 } else { p })
                    }
                    _ => continue,
                }
            }
            (CallTarget::Name(id), Lang::Ngc | Lang::Sinumerik) => {
                Wanted::Name(code.exprs.name(*id).to_string())
            }
            (CallTarget::Number(e), Lang::Ngc) => match code.exprs.constant(*e) {
                Some(v) if v >= 0.0 && v.fract() == 0.0 && v < 1e9 => {
                    Wanted::Name(format!("{}", v as u64))
                }
                _ => continue,
            },
            _ => continue,
        };
        if !out.contains(&wanted) {
            out.push(wanted);
        }
    }
    out
}

/// Where a text defines a wanted program: the program with that number, or the subroutine
/// with that name.
fn defined_in(code: &code::Code, wanted: &Wanted) -> Option<u32> {
    match wanted {
        Wanted::Number(n) => code
            .programs
            .iter()
            .find(|p| p.number == Some(*n))
            .map(|p| p.first),
        Wanted::Name(s) => code
            .exprs
            .find(s)
            .and_then(|id| code.subs.get(&id).copied()),
    }
}

fn defined(units: &[code::Code], wanted: &Wanted) -> Option<(u32, u32)> {
    units
        .iter()
        .enumerate()
        .find_map(|(u, code)| Some((u as u32, defined_in(code, wanted)?)))
}

/// The first instruction of a wanted program in the file found for it: the program or the
/// subroutine it defines, or a Fanuc file's only program when it has no number (a file stored
/// by its name only, `9010.nc` holding the blocks without `O9010`), or a Sinumerik file's
/// first block when no PROC names it.
fn entry_of(code: &code::Code, wanted: &Wanted) -> Option<u32> {
    defined_in(code, wanted).or_else(|| match wanted {
        Wanted::Number(_) => code
            .programs
            .first()
            .filter(|p| p.number.is_none())
            .map(|p| p.first),
        // A Sinumerik subprogram file without a PROC line: the file is the subprogram, named
        // by its file's name (`BAR_CENTR.SPF`), from its first block to its M17 or RET.
        Wanted::Name(_) if code.lang == Lang::Sinumerik => Some(0),
        Wanted::Name(_) => None,
    })
}

/// Runs a compiled program from line number `from` (the first line of control flow; the lines
/// before it have run already).
pub(crate) fn run<H: Host>(
    linked: &Linked,
    syntax: &Syntax,
    limits: Limits,
    from: u32,
    host: &mut H,
) -> Result<Outcome, H::Error> {
    let code = &linked.units[0];
    let start = code
        .text
        .index_of(from)
        .and_then(|i| code.line_inst.get(i).copied())
        .unwrap_or(code.insts.len() as u32);
    vm::Vm::new(linked, *syntax, limits).run(start, host)
}
