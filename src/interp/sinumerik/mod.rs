//! The Sinumerik front end: R parameters and DEF variables in expressions on every address
//! (`X=R4-R21`), jump labels and `GOTOF`/`GOTOB`/`GOTO`/`GOTOC` (with `IF … GOTOF`),
//! `IF`/`ELSE`/`ENDIF`, `WHILE`, `FOR`, `LOOP`, `REPEAT`/`UNTIL`, and `PROC` subprograms held in
//! the same file, called by name with parameters and a repeat count, ending at `RET`/`M17`. Every
//! decision is a row of docs/dialects/sinumerik.md, "Program flow".
//!
//! A line of the language's statements compiles to the shared instructions; a block of address
//! words with computed values or settings of R parameters and variables to a block of
//! [`code`](super::code); any other line is handed to the dialect as it is written (its cycles,
//! keywords and settings are the dialect's), with the parameters kept in step both ways.

mod cursor;
mod flow;
mod scan;

use std::collections::{HashMap, HashSet};

use crate::diag::{Code as DiagCode, Diagnostic, Span};
use crate::gcode::{lex_line_syntax, Word};

use super::code::{Assign, Block, BlockWord, Code, Inst, Target, WordValue};
use super::expr::Lang;
use super::text::{Text, TextLine};
use super::Syntax;
use cursor::{r_number, Cursor, ExprReader};
use flow::label_word;
pub use scan::{looks_like_macro, profile_call};

/// A program of the file: the main program (lines before the first PROC) or a PROC.
struct Unit {
    is_proc: bool,
    /// Label (`NAME`, or `N<number>` for a block number) → the lines that carry it, in order.
    labels: HashMap<String, Vec<usize>>,
    /// Names declared so far (DEF, the PROC's parameters).
    declared: HashSet<String>,
}

impl Unit {
    fn new(is_proc: bool) -> Unit {
        Unit {
            is_proc,
            labels: HashMap::new(),
            declared: HashSet::new(),
        }
    }
}

/// Which way a jump looks for its label.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Direction {
    /// GOTOF: towards the end of the program.
    Forward,
    /// GOTOB: towards its beginning (the jump's own block included).
    Backward,
    /// GOTO and GOTOC: forward, then backward; GOTOC goes on without an alarm when neither finds
    /// the label.
    Both { quiet: bool },
}

/// A jump whose label is looked up when the whole program is read.
struct Fixup {
    at: u32,
    label: String,
    direction: Direction,
    line: usize,
    unit: usize,
    /// The jump word and its label, as written.
    word: &'static str,
    span: Span,
}

/// A structure open (waiting for its end).
enum Open {
    If { jump: u32, else_jump: Option<u32> },
    While { top: u32, jump: u32 },
    For { top: u32, jump: u32, step: Assign },
    Loop { top: u32 },
    Repeat { top: u32 },
}

struct Opened {
    what: Open,
    /// The opening statement's instruction (replaced by an error if it is never closed).
    inst: u32,
    span: Span,
}

struct Compiler {
    code: Code,
    /// The names PROC defines in this file, and those EXTERN declares.
    procs: HashSet<String>,
    /// The dialect's own names that stand alone in a block (`MSG`, `WORKPIECE`): not calls.
    plain: &'static [&'static [&'static str]],
    /// The cycles whose first argument names their contour ([`Syntax::profile_calls`]).
    profile: &'static [&'static str],
    units: Vec<Unit>,
    fixups: Vec<Fixup>,
    /// The sections REPEAT runs again, looked up when the whole program is read.
    sections: Vec<flow::SectionFixup>,
    open: Vec<Opened>,
    lexed: Vec<Word>,
}

/// Compiles a Sinumerik program: the main program, then the PROCs after it.
pub fn compile(text: Text, syntax: &Syntax, lexer: crate::gcode::Syntax) -> Code {
    let mut c = Compiler {
        code: Code::new(Lang::Sinumerik, text, lexer),
        procs: HashSet::new(),
        plain: syntax.plain_names,
        profile: syntax.profile_calls,
        units: vec![Unit::new(false)],
        fixups: Vec::new(),
        sections: Vec::new(),
        open: Vec::new(),
        lexed: Vec::new(),
    };
    c.collect_procs();
    for i in 0..c.code.text.len() {
        c.code.start_line(i);
        if let Err(d) = c.line(i) {
            c.code.fail(i, d);
        }
    }
    c.close_structures();
    c.resolve_jumps();
    c.resolve_sections();
    c.code
}

impl Compiler {
    /// The names of the PROCs the file defines (calls may come before them).
    fn collect_procs(&mut self) {
        for i in 0..self.code.text.len() {
            let mut cur = Cursor::new(self.code.text.line(i));
            if cur.eat_name("PROC") || cur.eat_name("EXTERN") {
                if let Some((name, _, _)) = cur.peek_name() {
                    self.procs.insert(name);
                }
            }
        }
    }

    fn unit(&mut self) -> &mut Unit {
        self.units.last_mut().expect("the main program")
    }

    fn line(&mut self, i: usize) -> Result<(), Diagnostic> {
        let held = self.code.text.line(i);
        let text = held.text.to_vec();
        let line = TextLine {
            text: &text,
            raw: &text,
            ..held
        };
        let mut cur = Cursor::new(line);
        if cur.done() || cur.at(cur.i) == b'%' {
            return Ok(());
        }
        let block_delete = cur.eat(b'/');
        self.labels(i, &mut cur);
        if cur.done() {
            return Ok(());
        }
        if let Some((value, open, close)) = scan::profile_call(cur.line.text, self.profile) {
            // The cycle's block for the dialect, then its contour read as its profile.
            let cycle = cur.peek_name().map(|n| n.0).unwrap_or_default();
            let span = cur.span(open, close);
            self.block(i, &mut cur, block_delete)?;
            return self.profile_call(i, &cycle, &value, span);
        }
        let Some((word, k, e)) = cur.peek_name() else {
            return self.block(i, &mut cur, block_delete);
        };
        if self.flow(i, &mut cur, &word, e)? {
            return Ok(());
        }
        // A PROC of this file or one EXTERN declares; or a name alone in its block, which
        // Sinumerik calls as a subprogram found by its name (`BAR_CENTR`: `BAR_CENTR.SPF`, a
        // subprogram without parameters needs no declaration).
        let called =
            self.procs.contains(&word) || scan::is_bare_call(cur.line.text, k, e, self.plain);
        if called && cur.next_char(e).0 != b'=' {
            return self.call(i, &mut cur);
        }
        self.block(i, &mut cur, block_delete)
    }

    /// The block number (`N20`, a label `N20` too) and the label (`NAME:`) a line begins with.
    fn labels(&mut self, i: usize, cur: &mut Cursor) {
        if let Some((name, _, e)) = cur.peek_name() {
            let n = name
                .strip_prefix('N')
                .filter(|d| !d.is_empty() && d.bytes().all(|b| b.is_ascii_digit()));
            if let Some(n) = n.and_then(|d| d.parse::<u64>().ok()) {
                self.unit()
                    .labels
                    .entry(format!("N{n}"))
                    .or_default()
                    .push(i);
                cur.i = e;
            }
        }
        if let Some((name, _, e)) = cur.peek_name() {
            let (c, k) = cur.next_char(e);
            if c == b':' && cur.at(k + 1) != b'=' && name.len() >= 2 {
                self.unit().labels.entry(name).or_default().push(i);
                cur.i = k + 1;
            }
        }
    }

    /// A block: address words (some computed), settings of R parameters and variables, a jump at
    /// its end; or, holding the dialect's words, the line as it is written.
    fn block(&mut self, i: usize, cur: &mut Cursor, block_delete: bool) -> Result<(), Diagnostic> {
        let line = cur.line;
        if lex_line_syntax(
            line.text,
            line.number,
            line.offset,
            &mut self.lexed,
            &self.code.lexer,
        )
        .is_ok()
        {
            let ends = ending(&self.lexed);
            self.code.emit(i, Inst::Plain);
            return self.end_block(i, ends);
        }
        let Some(parts) = self.block_parts(cur)? else {
            self.code.emit(i, Inst::Plain);
            return Ok(());
        };
        let ends = ending(&parts.lexed);
        let b = self.code.blocks.len() as u32;
        self.code.blocks.push(Block {
            words: parts.words,
            assigns: parts.assigns,
            block_delete,
        });
        self.code.emit(i, Inst::Block(b));
        if let Some((label, span, direction)) = parts.jump {
            self.jump(i, Inst::Jump(0), label, span, direction);
        }
        self.end_block(i, ends)
    }

    /// After a block with M2, M30 or M17: the main program ends, a subprogram returns.
    fn end_block(&mut self, i: usize, ends: Option<u32>) -> Result<(), Diagnostic> {
        match ends {
            Some(17 | 2 | 30) if self.unit().is_proc => {
                self.code.emit(
                    i,
                    Inst::Return {
                        value: None,
                        to_label: None,
                    },
                );
            }
            // In a main program M17 ends it too; in one called as a subprogram it returns.
            Some(17 | 2 | 30) => {
                self.code.emit(i, Inst::End);
            }
            _ => {}
        }
        Ok(())
    }

    /// The parts of a block in the interpreter's hands; `None` when it holds a word of the
    /// dialect's (a keyword, a call, a setting such as `SF=`).
    fn block_parts(&mut self, cur: &mut Cursor) -> Result<Option<Parts>, Diagnostic> {
        let mut parts = Parts::default();
        let mut computed_at: Option<Span> = None;
        while !cur.done() {
            let k = cur.i;
            let Some((name, e)) = cur.name_at(k) else {
                return Ok(None);
            };
            if let Some(direction) = jump_direction(&name) {
                let (label, label_end) = label_word(cur, &name, e)?;
                parts.jump = Some((label, cur.span(k, label_end), direction));
                if !cur.done() {
                    let at = cur.i;
                    return Err(cur.error(
                        at,
                        at + 1,
                        "the jump ends the block: nothing may follow its label",
                    ));
                }
                break;
            }
            let letter_number = matches!(cur.at(k + 1), b'0'..=b'9' | b'.' | b'-' | b'+');
            let mut end = e;
            if letter_number {
                let mut words = Vec::with_capacity(1);
                end = crate::gcode::lexer::lex_word(
                    cur.line.text,
                    k,
                    cur.line.number,
                    cur.line.offset,
                    &mut words,
                )?;
                let (c, eq) = cur.next_char(end);
                if c != b'=' || cur.at(eq + 1) == b'=' {
                    parts.lexed.push(words[0]);
                    parts.words.push(literal(&words[0]));
                    cur.i = end;
                    continue;
                }
            }
            let name = String::from_utf8_lossy(&cur.line.text[k..end]).to_ascii_uppercase();
            let (c, eq) = cur.next_char(end);
            if c != b'=' || cur.at(eq + 1) == b'=' || cur.next_char(eq + 1).0 == b'"' {
                // A keyword, a call, a comparison or a name given as text (`T="TOOL"`).
                return Ok(None);
            }
            let target = if name.len() == 1 {
                None
            } else if let Some(n) = r_number(&name) {
                let e = self.code.exprs.number(f64::from(n), cur.span(k, end));
                Some(Target::Number(e))
            } else if self
                .units
                .last()
                .is_some_and(|u| u.declared.contains(&name))
            {
                Some(Target::Named(self.code.exprs.intern(name.clone())))
            } else {
                return Ok(None);
            };
            cur.i = eq + 1;
            let value = ExprReader::new(cur, &mut self.code.exprs).expr()?;
            let span = cur.span(k, cur.i);
            match target {
                None => {
                    computed_at.get_or_insert(span);
                    parts.words.push(BlockWord {
                        letter: name.as_bytes()[0],
                        value: WordValue::Expr(value),
                        span,
                    });
                }
                Some(target) => {
                    if let Some(word) = computed_at {
                        return Err(Diagnostic::error(DiagCode::Unsupported, span, format!(
                            "{name}= is set after the computed address at column {}: threadcut sets a block's parameters before it computes its addresses",
                            word.column
                        )).with_hint("write the setting first in the block, or in a block of its own"));
                    }
                    parts.assigns.push(Assign {
                        target,
                        value,
                        span,
                    });
                }
            }
        }
        Ok(Some(parts))
    }
}

/// A block's parts in the interpreter's hands.
#[derive(Default)]
struct Parts {
    words: Vec<BlockWord>,
    /// The words written as numbers (for M2, M17, M30).
    lexed: Vec<Word>,
    assigns: Vec<Assign>,
    /// A jump at the block's end: its label, where it is written, which way it looks.
    jump: Option<(String, Span, Direction)>,
}

/// The jump words and which way they look.
fn jump_direction(name: &str) -> Option<Direction> {
    Some(match name {
        "GOTOF" => Direction::Forward,
        "GOTOB" => Direction::Backward,
        "GOTO" => Direction::Both { quiet: false },
        "GOTOC" => Direction::Both { quiet: true },
        _ => return None,
    })
}

fn jump_word(d: Direction) -> &'static str {
    match d {
        Direction::Forward => "GOTOF",
        Direction::Backward => "GOTOB",
        Direction::Both { quiet: false } => "GOTO",
        Direction::Both { quiet: true } => "GOTOC",
    }
}

/// The M code that ends a program or returns from one (M2, M17, M30), if the block has one.
fn ending(words: &[Word]) -> Option<u32> {
    words
        .iter()
        .find(|w| w.letter == b'M' && matches!(w.value, 2.0 | 17.0 | 30.0))
        .map(|w| w.value as u32)
}

fn literal(w: &Word) -> BlockWord {
    BlockWord {
        letter: w.letter,
        value: WordValue::Lit {
            value: w.value,
            has_dot: w.has_dot,
            skip: (w.raw_start() as u32).saturating_sub(w.span.column),
        },
        span: w.span,
    }
}
