//! The LinuxCNC (RS274/NGC) front end: o-word subroutines and control flow, numbered and named
//! parameters, `[ … ]` expressions in every word. Reading rules and error texts follow LinuxCNC's
//! documentation (docs/src/gcode/o-code.adoc, overview.adoc) and its interpreter; each choice is
//! a row of docs/dialects/linuxcnc-interp.md.

use crate::diag::{Code as DiagCode, Diagnostic};
use crate::gcode::{lex_line_syntax, Word};

use super::code::{
    Assign, Block, BlockWord, Call, CallKind, CallTarget, Code, Inst, ProgramInfo, Target,
    WordValue,
};
use super::expr::{read_name, read_number, Expr, Lang, Parser};
use super::scan::Squeezed;
use super::text::{Text, TextLine};

/// LinuxCNC passes up to 30 arguments (INTERP_SUB_PARAMS).
const MAX_ARGS: usize = 30;

/// An o-word's name: `o<name>`, `o123`, or a computed number (`o[#1]`, for calls only).
enum OName {
    Named(String),
    Computed(Expr),
}

/// LinuxCNC's o-word keywords (`convert::macros` reads them too).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Keyword {
    Sub,
    Endsub,
    Call,
    Do,
    While,
    Repeat,
    If,
    Elseif,
    Else,
    Endif,
    Break,
    Continue,
    Endwhile,
    Endrepeat,
    Return,
}

/// In LinuxCNC's order of trial (read_o): a longer keyword before its prefix.
pub(crate) const KEYWORDS: [(&[u8], Keyword); 15] = [
    (b"SUB", Keyword::Sub),
    (b"ENDSUB", Keyword::Endsub),
    (b"CALL", Keyword::Call),
    (b"DO", Keyword::Do),
    (b"WHILE", Keyword::While),
    (b"REPEAT", Keyword::Repeat),
    (b"IF", Keyword::If),
    (b"ELSEIF", Keyword::Elseif),
    (b"ELSE", Keyword::Else),
    (b"ENDIF", Keyword::Endif),
    (b"BREAK", Keyword::Break),
    (b"CONTINUE", Keyword::Continue),
    (b"ENDWHILE", Keyword::Endwhile),
    (b"ENDREPEAT", Keyword::Endrepeat),
    (b"RETURN", Keyword::Return),
];

/// Where an o-word line's parts are (indices into its squeezed characters) and its keyword.
struct OLine {
    line: usize,
    kw: Keyword,
    o_at: usize,
    name_end: usize,
    kw_end: usize,
}

/// What follows an o-word's keyword.
enum Arg {
    None,
    One(Expr),
    List(Vec<Expr>),
}

/// A construct open while compiling.
enum Open {
    Sub {
        name: u32,
        skip: u32,
        line: usize,
        inst: u32,
    },
    If {
        name: String,
        pending: Option<u32>,
        ends: Vec<u32>,
        has_else: bool,
        line: usize,
        inst: u32,
    },
    While {
        name: String,
        start: u32,
        breaks: Vec<u32>,
        line: usize,
    },
    Do {
        name: String,
        start: u32,
        breaks: Vec<u32>,
        continues: Vec<u32>,
        line: usize,
        inst: u32,
    },
    Repeat {
        name: String,
        top: u32,
        breaks: Vec<u32>,
        line: usize,
        inst: u32,
    },
}

impl Open {
    fn name<'a>(&'a self, code: &'a Code) -> &'a str {
        match self {
            Open::Sub { name, .. } => code.exprs.name(*name),
            Open::If { name, .. }
            | Open::While { name, .. }
            | Open::Do { name, .. }
            | Open::Repeat { name, .. } => name,
        }
    }

    fn what(&self) -> (&'static str, &'static str) {
        match self {
            Open::Sub { .. } => ("sub", "endsub"),
            Open::If { .. } => ("if", "endif"),
            Open::While { .. } => ("while", "endwhile"),
            Open::Do { .. } => ("do", "while"),
            Open::Repeat { .. } => ("repeat", "endrepeat"),
        }
    }

    fn line_and_inst(&self) -> (usize, u32) {
        match self {
            Open::Sub { line, inst, .. }
            | Open::If { line, inst, .. }
            | Open::Do { line, inst, .. }
            | Open::Repeat { line, inst, .. } => (*line, *inst),
            Open::While { line, start, .. } => (*line, *start),
        }
    }
}

struct Compiler {
    code: Code,
    open: Vec<Open>,
    /// Something other than a blank line or `%` came already.
    begun: bool,
    lexed: Vec<Word>,
}

/// Compiles a LinuxCNC program.
pub fn compile(text: Text, lexer: crate::gcode::Syntax) -> Code {
    let mut c = Compiler {
        code: Code::new(Lang::Ngc, text, lexer),
        open: Vec::new(),
        begun: false,
        lexed: Vec::new(),
    };
    for i in 0..c.code.text.len() {
        c.code.start_line(i);
        c.line(i);
    }
    c.finish();
    c.code
}

impl Compiler {
    fn line(&mut self, i: usize) {
        let Compiler { code, lexed, .. } = self;
        let line = code.text.line(i);
        // Most lines are plain blocks the lexer reads.
        let lexed_line = lex_line_syntax(line.text, line.number, line.offset, lexed, &code.lexer);
        let owned = lexed_line.is_err().then(|| line.text.to_vec());
        let (number, offset) = (line.number, line.offset);
        match lexed_line {
            Ok(shape) => {
                // `%` delimits the program; as in the streamed run it ends nothing (M2 does).
                if shape.percent {
                    return;
                }
                if self.lexed.is_empty() {
                    return;
                }
                if let [o] = self.lexed[..] {
                    if o.letter == b'O' {
                        self.numbered_program(i, o);
                        return;
                    }
                }
                self.begun = true;
                let end = ends_program(&self.lexed);
                let numbered = self.lexed.iter().any(|w| {
                    w.letter == b'O' || (w.letter == b'M' && (w.value == 98.0 || w.value == 99.0))
                });
                if numbered {
                    let block = Block {
                        words: self.lexed.iter().map(literal).collect(),
                        assigns: Vec::new(),
                        block_delete: shape.block_delete,
                    };
                    if let Err(d) = self.numbered_call(i, block, end) {
                        self.code.fail(i, d);
                    }
                    return;
                }
                self.code.emit(i, Inst::Plain);
                if end {
                    self.code.emit(i, Inst::End);
                }
            }
            Err(lex_error) => {
                self.begun = true;
                let text = owned.unwrap_or_default();
                let line = TextLine {
                    number,
                    offset,
                    text: &text,
                    raw: &text,
                };
                if let Err(d) = self.macro_line(i, line) {
                    // A line neither reads: LinuxCNC's own message where the macro reader has
                    // one, else the lexer's.
                    let d = if d.code == DiagCode::Syntax && !looks_like_macro(line.text) {
                        lex_error
                    } else {
                        d
                    };
                    self.code.fail(i, d);
                }
            }
        }
    }

    fn macro_line(&mut self, i: usize, line: TextLine) -> Result<(), Diagnostic> {
        let s = Squeezed::new(line)?;
        let mut k = 0;
        if s.at(k) == b'/' {
            k += 1;
        }
        // A line number: N and a whole number.
        if s.at(k) == b'N' && s.at(k + 1).is_ascii_digit() {
            k += 1;
            while s.at(k).is_ascii_digit() || s.at(k) == b'.' {
                k += 1;
            }
        }
        if s.at(k) == b'O' {
            return self.oword(i, &s, k);
        }
        let block = self.block(&s, k)?;
        let end = block.words.iter().any(|w| {
            w.letter == b'M'
                && matches!(w.value, WordValue::Lit { value, .. } if value == 2.0 || value == 30.0)
        });
        if block.words.iter().any(|w| {
            w.letter == b'M'
                && matches!(w.value, WordValue::Lit { value, .. } if value == 98.0 || value == 99.0)
        }) {
            return self.numbered_call(i, block, end);
        }
        let b = self.code.blocks.len() as u32;
        self.code.blocks.push(block);
        self.code.emit(i, Inst::Block(b));
        if end {
            self.code.emit(i, Inst::End);
        }
        Ok(())
    }

    /// A bare `o123`: the main program's number when it comes first, else the start of a
    /// Fanuc-style numbered subprogram (o-code.adoc, "Fanuc-Style Numbered Programs").
    fn numbered_program(&mut self, i: usize, o: Word) {
        if o.value < 0.0 || o.value.fract() != 0.0 {
            self.code.fail(
                i,
                Diagnostic::error(DiagCode::Syntax, o.span, "Non integer value for integer"),
            );
            return;
        }
        let n = o.value as u32;
        if !self.begun && self.code.programs.is_empty() {
            self.begun = true;
            self.code.programs.push(ProgramInfo {
                number: Some(n),
                first: 0,
                end: 0,
                labels: Default::default(),
            });
            return;
        }
        self.begun = true;
        if let Some(open) = self.open.last() {
            let (what, _) = open.what();
            let l = self.code.text.line(open.line_and_inst().0).number;
            self.code.fail(
                i,
                Diagnostic::error(
                    DiagCode::Syntax,
                    o.span,
                    format!("o{n} (a numbered program) inside the o-word {what} of line {l}"),
                ),
            );
            return;
        }
        if self.code.programs.is_empty() {
            self.code.programs.push(ProgramInfo {
                number: None,
                first: 0,
                end: 0,
                labels: Default::default(),
            });
        }
        self.code.emit(i, Inst::NextProgram);
        if self.code.programs.iter().any(|p| p.number == Some(n)) {
            self.code.fail(
                i,
                Diagnostic::error(
                    DiagCode::Conflict,
                    o.span,
                    format!("redefining sub: o|{n}| already defined"),
                ),
            );
            return;
        }
        let first = self.code.here();
        self.code.programs.push(ProgramInfo {
            number: Some(n),
            first,
            end: first,
            labels: Default::default(),
        });
    }

    /// A block with `M98 P… [L…]` (a call of a numbered program) or `M99` (its return); the
    /// block's other words run first.
    fn numbered_call(&mut self, i: usize, mut block: Block, end: bool) -> Result<(), Diagnostic> {
        if let Some(o) = block.words.iter().find(|w| w.letter == b'O') {
            return Err(Diagnostic::error(
                DiagCode::Syntax,
                o.span,
                "an o-word must begin its line",
            ));
        }
        let is = |w: &BlockWord, code: f64| {
            w.letter == b'M' && matches!(w.value, WordValue::Lit { value, .. } if value == code)
        };
        let m98 = block.words.iter().position(|w| is(w, 98.0));
        let m99 = block.words.iter().position(|w| is(w, 99.0));
        let (at, call) = match (m98, m99) {
            (Some(a), None) => (a, true),
            (None, Some(a)) => (a, false),
            _ => {
                let w = &block.words[m99.unwrap_or(0)];
                return Err(Diagnostic::error(
                    DiagCode::Conflict,
                    w.span,
                    "Two M codes used from same modal group",
                ));
            }
        };
        let span = block.words.remove(at).span;
        let mut take = |letter: u8| {
            block
                .words
                .iter()
                .position(|w| w.letter == letter)
                .map(|k| block.words.remove(k))
        };
        let p = if call { take(b'P') } else { None };
        let l = if call { take(b'L') } else { None };
        if !block.words.is_empty() {
            let b = self.code.blocks.len() as u32;
            self.code.blocks.push(block);
            self.code.emit(i, Inst::Block(b));
        }
        let mut expr = |w: BlockWord| match w.value {
            WordValue::Expr(e) => e,
            WordValue::Lit { value, .. } => self.code.exprs.number(value, w.span),
        };
        if call {
            let Some(p) = p else {
                return Err(Diagnostic::error(
                    DiagCode::MissingWord,
                    span,
                    "Found 'm98' code with no P-word",
                ));
            };
            let number = expr(p);
            let count = l.map(&mut expr);
            let c = self.code.calls.len() as u32;
            self.code.calls.push(Call {
                kind: CallKind::M98,
                target: CallTarget::Program {
                    number,
                    packed: false,
                },
                args: Vec::new(),
                arg_letters: Vec::new(),
                arg_no_point: Vec::new(),
                count,
                span,
            });
            self.code.emit(i, Inst::Call(c));
        } else {
            if self.open.iter().any(|o| matches!(o, Open::Sub { .. })) {
                return Err(Diagnostic::error(
                    DiagCode::Syntax,
                    span,
                    "Found 'M99' instead of 'O endsub' after 'O sub'",
                ));
            }
            self.code.emit(
                i,
                Inst::Return {
                    value: None,
                    to_label: None,
                },
            );
        }
        if end {
            self.code.emit(i, Inst::End);
        }
        Ok(())
    }

    /// Words and parameter settings.
    fn block(&mut self, s: &Squeezed, mut k: usize) -> Result<Block, Diagnostic> {
        let mut block = Block {
            block_delete: s.block_delete,
            ..Block::default()
        };
        while k < s.len() {
            let c = s.at(k);
            if c == b'#' {
                block.assigns.push(self.setting(s, &mut k)?);
                continue;
            }
            if !(c.is_ascii_uppercase() || c == b'$') || c == b'O' {
                return Err(if c == b'O' {
                    s.error(k, k + 1, "an o-word must begin its line")
                } else {
                    s.error(k, k + 1, "Bad character used")
                });
            }
            let from = k;
            k += 1;
            let value = self.value(s, &mut k)?;
            block.words.push(BlockWord {
                letter: c,
                value,
                span: s.span(from, k),
            });
        }
        Ok(block)
    }

    /// A word's value: a plain number kept as written, anything else an expression.
    fn value(&mut self, s: &Squeezed, k: &mut usize) -> Result<WordValue, Diagnostic> {
        let c = s.at(*k);
        let c1 = s.at(*k + 1);
        let plain = c.is_ascii_digit()
            || c == b'.'
            || (matches!(c, b'+' | b'-') && (c1.is_ascii_digit() || c1 == b'.'));
        if plain {
            let letter_col = s.span(*k - 1, *k).column;
            let (value, has_dot, end) = read_number(s, *k, Lang::Ngc)?;
            let skip = s.span(*k, end).column - letter_col - 1;
            *k = end;
            return Ok(WordValue::Lit {
                value,
                has_dot,
                skip,
            });
        }
        let e = Parser::new(s, &mut self.code.exprs, Lang::Ngc).value(k)?;
        Ok(WordValue::Expr(e))
    }

    /// `#n=value`, `#[…]=value`, `#<name>=value`.
    fn setting(&mut self, s: &Squeezed, k: &mut usize) -> Result<Assign, Diagnostic> {
        let from = *k;
        *k += 1;
        let target = if s.at(*k) == b'<' {
            let name = read_name(s, k)?;
            Target::Named(self.code.exprs.intern(name))
        } else {
            // The number: any value that is a whole number (`#[1+2]=…`, `##1=…`).
            let e = Parser::new(s, &mut self.code.exprs, Lang::Ngc).value(k)?;
            Target::Number(e)
        };
        if s.at(*k) != b'=' {
            return Err(s.error(*k, *k + 1, "Equal sign missing in parameter setting"));
        }
        *k += 1;
        let value = Parser::new(s, &mut self.code.exprs, Lang::Ngc).value(k)?;
        Ok(Assign {
            target,
            value,
            span: s.span(from, *k),
        })
    }

    /// An o-word line: its name, keyword and arguments are read here, then the construct it opens,
    /// continues or closes is compiled by the keyword's own method.
    fn oword(&mut self, i: usize, s: &Squeezed, mut k: usize) -> Result<(), Diagnostic> {
        let o_at = k;
        k += 1;
        let name = match s.at(k) {
            b'<' => OName::Named(read_name(s, &mut k)?),
            b'0'..=b'9' => {
                let (v, dot, end) = read_number(s, k, Lang::Ngc)?;
                if dot && v.fract() != 0.0 {
                    return Err(s.error(k, end, "Non integer value for integer"));
                }
                k = end;
                OName::Named(format!("{}", v as i64))
            }
            _ => OName::Computed(Parser::new(s, &mut self.code.exprs, Lang::Ngc).value(&mut k)?),
        };
        let name_end = k;
        let Some(&(word, kw)) = KEYWORDS.iter().find(|(w, _)| s.starts_with(k, w)) else {
            if k >= s.len() {
                return Err(s.error(
                    o_at,
                    name_end,
                    "a numbered program's o-word stands alone on its line",
                ));
            }
            return Err(s.error(k, s.len(), "Unknown control command in o word"));
        };
        k += word.len();
        let o = OLine {
            line: i,
            kw,
            o_at,
            name_end,
            kw_end: k,
        };
        let what = match kw {
            Keyword::If => "if",
            Keyword::Elseif => "elseif",
            Keyword::While => "while",
            _ => "repeat",
        };
        let arg = match kw {
            Keyword::Call => Arg::List(self.args(s, &mut k)?),
            Keyword::Endsub | Keyword::Return if s.at(k) == b'[' => {
                Arg::One(Parser::new(s, &mut self.code.exprs, Lang::Ngc).bracketed(&mut k)?)
            }
            Keyword::If | Keyword::Elseif | Keyword::While | Keyword::Repeat => {
                Arg::One(self.condition(s, &mut k, what)?)
            }
            _ => Arg::None,
        };
        self.end_of_oword(s, k)?;
        let (name, arg) = match (name, arg) {
            (OName::Named(n), Arg::List(args)) => {
                let id = self.code.exprs.intern(n);
                return self.call(i, s, o_at, o.kw_end, CallTarget::Name(id), args);
            }
            (OName::Computed(e), Arg::List(args)) => {
                return self.call(i, s, o_at, o.kw_end, CallTarget::Number(e), args);
            }
            (OName::Computed(_), _) => {
                return Err(s.error(
                    o_at + 1,
                    name_end,
                    "only a call may compute its o-word's number",
                ))
            }
            (OName::Named(n), arg) => (n, arg),
        };
        let one = match arg {
            Arg::One(e) => Some(e),
            _ => None,
        };
        match kw {
            Keyword::Sub => self.sub(s, &o, name),
            Keyword::Endsub | Keyword::Return => self.sub_end(s, &o, &name, one),
            Keyword::If => self.open_if(s, &o, name, one.expect("a condition")),
            Keyword::Elseif | Keyword::Else => self.else_branch(s, &o, &name, one),
            Keyword::Endif => self.endif(s, &o, &name),
            Keyword::While => self.while_line(s, &o, name, one.expect("a condition")),
            Keyword::Endwhile => self.endwhile(s, &o, &name),
            Keyword::Do => self.open_do(s, &o, name),
            Keyword::Repeat => self.repeat(s, &o, name, one.expect("a count")),
            Keyword::Endrepeat => self.endrepeat(s, &o, &name),
            Keyword::Break | Keyword::Continue => self.leave_or_continue(s, &o, &name),
            Keyword::Call => unreachable!("calls returned above"),
        }
    }

    /// `oN sub`: the body is jumped over where it is defined, and entered by its calls.
    fn sub(&mut self, s: &Squeezed, o: &OLine, name: String) -> Result<(), Diagnostic> {
        if let Some(&Open::Sub {
            name: outer, skip, ..
        }) = self.open.iter().find(|x| matches!(x, Open::Sub { .. }))
        {
            let outer = self.code.exprs.name(outer).to_string();
            let e = s.error(o.o_at, o.kw_end, "Nested subroutine definition")
                .with_hint(format!("o{name} sub is inside the definition of o{outer}: end that one with o{outer} endsub first"));
            // LinuxCNC finds it as it reads past the outer definition: so does the run.
            self.code.fail_at(skip, e.clone());
            return Err(e);
        }
        let id = self.code.exprs.intern(name.clone());
        let skip = self.code.emit(o.line, Inst::Jump(0));
        if let Some(&first) = self.code.subs.get(&id) {
            let before = self.code.line_number(first.saturating_sub(1));
            let e = s.error(
                o.o_at,
                o.kw_end,
                format!("redefining sub: o|{name}| already defined in line {before}"),
            );
            self.code.fail_at(skip, e);
        } else {
            self.code.subs.insert(id, self.code.here());
        }
        self.open.push(Open::Sub {
            name: id,
            skip,
            line: o.line,
            inst: skip,
        });
        Ok(())
    }

    /// `oN endsub [value]`, `oN return [value]`.
    fn sub_end(
        &mut self,
        s: &Squeezed,
        o: &OLine,
        name: &str,
        value: Option<Expr>,
    ) -> Result<(), Diagnostic> {
        let word = if o.kw == Keyword::Endsub {
            "endsub"
        } else {
            "return"
        };
        let Some(sub_at) = self
            .open
            .iter()
            .rposition(|x| matches!(x, Open::Sub { .. }))
        else {
            return Err(s.error(
                o.o_at,
                o.kw_end,
                format!("not in a subroutine definition: 'o{name} {word}'"),
            ));
        };
        let sub_name = self.open[sub_at].name(&self.code).to_string();
        if sub_name != name {
            return Err(s.error(
                o.o_at,
                o.name_end,
                format!("o{name} {word} is inside o{sub_name} sub: it must name o{sub_name}"),
            ));
        }
        self.code.emit(
            o.line,
            Inst::Return {
                value,
                to_label: None,
            },
        );
        if o.kw == Keyword::Endsub {
            // Constructs left open inside the subroutine.
            while self.open.len() > sub_at + 1 {
                let inner = self.open.pop().expect("an open construct");
                self.unclosed(inner);
            }
            let Some(Open::Sub { skip, .. }) = self.open.pop() else {
                unreachable!("found above")
            };
            let after = self.code.here();
            self.code.patch(skip, after);
        }
        Ok(())
    }

    fn open_if(
        &mut self,
        s: &Squeezed,
        o: &OLine,
        name: String,
        cond: Expr,
    ) -> Result<(), Diagnostic> {
        self.local_name_free(s, o.o_at, o.name_end, &name)?;
        let at = self.code.emit(o.line, Inst::JumpUnless { cond, target: 0 });
        self.open.push(Open::If {
            name,
            pending: Some(at),
            ends: Vec::new(),
            has_else: false,
            line: o.line,
            inst: at,
        });
        Ok(())
    }

    /// `oN elseif [c]` (`cond`), `oN else`: the branch before jumps to the endif; the failed
    /// condition before lands here.
    fn else_branch(
        &mut self,
        s: &Squeezed,
        o: &OLine,
        name: &str,
        cond: Option<Expr>,
    ) -> Result<(), Diagnostic> {
        let here = self.code.here();
        let top = self.matching(
            s,
            o.o_at,
            o.name_end,
            name,
            |x| matches!(x, Open::If { .. }),
            "'if'",
        )?;
        let Open::If {
            pending,
            ends,
            has_else,
            ..
        } = &mut self.open[top]
        else {
            unreachable!("matched an if")
        };
        if *has_else {
            let word = if cond.is_some() { "elseif" } else { "else" };
            return Err(s.error(
                o.o_at,
                o.kw_end,
                format!("o{name} {word} after o{name} else"),
            ));
        }
        ends.push(here);
        let failed = pending.take();
        self.code.emit(o.line, Inst::Jump(0));
        if let Some(p) = failed {
            let to = self.code.here();
            self.code.patch(p, to);
        }
        match cond {
            Some(cond) => {
                let at = self.code.emit(o.line, Inst::JumpUnless { cond, target: 0 });
                if let Some(Open::If { pending, .. }) = self.open.last_mut() {
                    *pending = Some(at);
                }
            }
            None => {
                if let Some(Open::If { has_else, .. }) = self.open.last_mut() {
                    *has_else = true;
                }
            }
        }
        Ok(())
    }

    fn endif(&mut self, s: &Squeezed, o: &OLine, name: &str) -> Result<(), Diagnostic> {
        self.matching(
            s,
            o.o_at,
            o.name_end,
            name,
            |x| matches!(x, Open::If { .. }),
            "'if'",
        )?;
        let Some(Open::If { pending, ends, .. }) = self.open.pop() else {
            unreachable!("matched an if")
        };
        let after = self.code.emit(o.line, Inst::Nop);
        for at in pending.into_iter().chain(ends) {
            self.code.patch(at, after);
        }
        Ok(())
    }

    /// `oN while [c]`: the end of an `oN do` loop, or the start of a while loop.
    fn while_line(
        &mut self,
        s: &Squeezed,
        o: &OLine,
        name: String,
        cond: Expr,
    ) -> Result<(), Diagnostic> {
        if matches!(self.open.last(), Some(Open::Do { name: n, .. }) if *n == name) {
            let Some(Open::Do {
                start,
                breaks,
                continues,
                ..
            }) = self.open.pop()
            else {
                unreachable!("checked above")
            };
            let test = self.code.here();
            for c in continues {
                self.code.patch(c, test);
            }
            self.code.emit(
                o.line,
                Inst::JumpIf {
                    cond,
                    target: start,
                },
            );
            let after = self.code.here();
            for b in breaks {
                self.code.patch(b, after);
            }
            return Ok(());
        }
        self.local_name_free(s, o.o_at, o.name_end, &name)?;
        let start = self.code.emit(o.line, Inst::JumpUnless { cond, target: 0 });
        self.open.push(Open::While {
            name,
            start,
            breaks: vec![start],
            line: o.line,
        });
        Ok(())
    }

    fn endwhile(&mut self, s: &Squeezed, o: &OLine, name: &str) -> Result<(), Diagnostic> {
        self.matching(
            s,
            o.o_at,
            o.name_end,
            name,
            |x| matches!(x, Open::While { .. }),
            "while",
        )?;
        let Some(Open::While { start, breaks, .. }) = self.open.pop() else {
            unreachable!("matched a while")
        };
        self.code.emit(o.line, Inst::Jump(start));
        let after = self.code.here();
        for b in breaks {
            self.code.patch(b, after);
        }
        Ok(())
    }

    fn open_do(&mut self, s: &Squeezed, o: &OLine, name: String) -> Result<(), Diagnostic> {
        self.local_name_free(s, o.o_at, o.name_end, &name)?;
        let start = self.code.emit(o.line, Inst::Nop);
        self.open.push(Open::Do {
            name,
            start,
            breaks: Vec::new(),
            continues: Vec::new(),
            line: o.line,
            inst: start,
        });
        Ok(())
    }

    fn repeat(
        &mut self,
        s: &Squeezed,
        o: &OLine,
        name: String,
        count: Expr,
    ) -> Result<(), Diagnostic> {
        self.local_name_free(s, o.o_at, o.name_end, &name)?;
        let slot = self.code.repeat_slots;
        self.code.repeat_slots += 1;
        let inst = self.code.emit(o.line, Inst::RepeatStart { count, slot });
        let top = self.code.emit(o.line, Inst::RepeatTest { slot, exit: 0 });
        self.open.push(Open::Repeat {
            name,
            top,
            breaks: vec![top],
            line: o.line,
            inst,
        });
        Ok(())
    }

    fn endrepeat(&mut self, s: &Squeezed, o: &OLine, name: &str) -> Result<(), Diagnostic> {
        self.matching(
            s,
            o.o_at,
            o.name_end,
            name,
            |x| matches!(x, Open::Repeat { .. }),
            "repeat",
        )?;
        let Some(Open::Repeat { top, breaks, .. }) = self.open.pop() else {
            unreachable!("matched a repeat")
        };
        self.code.emit(o.line, Inst::Jump(top));
        let after = self.code.here();
        for b in breaks {
            self.code.patch(b, after);
        }
        Ok(())
    }

    /// `oN break` (to after the loop) and `oN continue` (to its condition).
    fn leave_or_continue(&mut self, s: &Squeezed, o: &OLine, name: &str) -> Result<(), Diagnostic> {
        let top = self.matching(
            s,
            o.o_at,
            o.name_end,
            name,
            |x| matches!(x, Open::While { .. } | Open::Do { .. }),
            "while/do",
        )?;
        let at = self.code.here();
        match (&mut self.open[top], o.kw) {
            (Open::While { breaks, .. } | Open::Do { breaks, .. }, Keyword::Break) => {
                breaks.push(at);
                self.code.emit(o.line, Inst::Jump(0));
            }
            (Open::While { start, .. }, _) => {
                let start = *start;
                self.code.emit(o.line, Inst::Jump(start));
            }
            (Open::Do { continues, .. }, _) => {
                continues.push(at);
                self.code.emit(o.line, Inst::Jump(0));
            }
            _ => unreachable!("matched a while or do"),
        }
        Ok(())
    }

    fn call(
        &mut self,
        i: usize,
        s: &Squeezed,
        from: usize,
        to: usize,
        target: CallTarget,
        args: Vec<Expr>,
    ) -> Result<(), Diagnostic> {
        let c = self.code.calls.len() as u32;
        self.code.calls.push(Call {
            kind: CallKind::OWord,
            target,
            args,
            arg_letters: Vec::new(),
            arg_no_point: Vec::new(),
            count: None,
            span: s.span(from, to),
        });
        self.code.emit(i, Inst::Call(c));
        Ok(())
    }

    /// `[a] [b] …` after `call`.
    fn args(&mut self, s: &Squeezed, k: &mut usize) -> Result<Vec<Expr>, Diagnostic> {
        let mut args = Vec::new();
        while s.at(*k) == b'[' {
            if args.len() == MAX_ARGS {
                return Err(s.error(*k, *k + 1, "Too many subroutine parameters"));
            }
            args.push(Parser::new(s, &mut self.code.exprs, Lang::Ngc).bracketed(k)?);
        }
        Ok(args)
    }

    fn condition(&mut self, s: &Squeezed, k: &mut usize, what: &str) -> Result<Expr, Diagnostic> {
        if s.at(*k) != b'[' {
            return Err(s.error(*k, *k + 1, format!("Left bracket missing after '{what}'")));
        }
        Parser::new(s, &mut self.code.exprs, Lang::Ngc).bracketed(k)
    }

    fn end_of_oword(&self, s: &Squeezed, k: usize) -> Result<(), Diagnostic> {
        if k < s.len() {
            return Err(s.error(k, s.len(), "words after an o-word")
                .with_hint("LinuxCNC leaves other words on an o-word line undefined: write them on a line of their own"));
        }
        Ok(())
    }

    /// The innermost open construct, which must be `pred` and carry `name`.
    fn matching(
        &mut self,
        s: &Squeezed,
        o_at: usize,
        name_end: usize,
        name: &str,
        pred: impl Fn(&Open) -> bool,
        what: &str,
    ) -> Result<usize, Diagnostic> {
        let code = &self.code;
        // Break and continue may sit in an if inside the loop: look past other constructs, but
        // not out of the current subroutine.
        let scope_start = self
            .open
            .iter()
            .rposition(|o| matches!(o, Open::Sub { .. }))
            .map_or(0, |p| p + 1);
        let looking_for_loop = what == "while/do";
        // A break or continue names the innermost loop of that name; with none, the innermost
        // construct of that name is what LinuxCNC's label table finds (and refuses).
        let found = self.open[scope_start..]
            .iter()
            .rposition(|o| o.name(code) == name && (pred(o) || !looking_for_loop))
            .or_else(|| {
                self.open[scope_start..]
                    .iter()
                    .rposition(|o| looking_for_loop && o.name(code) == name)
            });
        match found {
            Some(p) if pred(&self.open[scope_start + p]) => {
                if !looking_for_loop {
                    // Constructs opened inside and not closed before this line: each fails
                    // where it begins.
                    let closing = format!(
                        "{} (line {})",
                        String::from_utf8_lossy(s.source(o_at, s.len())),
                        s.line.number
                    );
                    while self.open.len() > scope_start + p + 1 {
                        let inner = self.open.pop().expect("an inner construct");
                        let (open, close) = inner.what();
                        let name = inner.name(&self.code).to_string();
                        let (line, inst) = inner.line_and_inst();
                        let d = Diagnostic::error(
                            DiagCode::Syntax,
                            self.code.text.line(line).whole(),
                            format!("o{name} {open} has no o{name} {close} before {closing}"),
                        );
                        self.code.fail_at(inst, d);
                    }
                }
                Ok(scope_start + p)
            }
            Some(p) => {
                let o = &self.open[scope_start + p];
                let line = code.text.line(o.line_and_inst().0).number;
                // LinuxCNC quotes the line as written (`settings->linetext`).
                Err(s.error(
                    o_at,
                    name_end,
                    format!(
                        "no matching {what} label: '{}' (found '{}' in line {line})",
                        String::from_utf8_lossy(s.source(o_at, s.len())).trim_end(),
                        o.what().0
                    ),
                ))
            }
            None => Err(s.error(
                o_at,
                name_end,
                format!(
                    "undefined O-word label: '{}'",
                    String::from_utf8_lossy(s.source(o_at, s.len())).trim_end()
                ),
            )),
        }
    }

    /// A control-flow label may not be opened twice at once in the same scope.
    fn local_name_free(
        &self,
        s: &Squeezed,
        o_at: usize,
        name_end: usize,
        name: &str,
    ) -> Result<(), Diagnostic> {
        let scope_start = self
            .open
            .iter()
            .rposition(|o| matches!(o, Open::Sub { .. }))
            .map_or(0, |p| p + 1);
        if let Some(o) = self.open[scope_start..]
            .iter()
            .find(|o| o.name(&self.code) == name)
        {
            let line = self.code.text.line(o.line_and_inst().0).number;
            return Err(s.error(
                o_at,
                name_end,
                format!("duplicate O-word label - already defined in line {line}: 'o{name}'"),
            ));
        }
        Ok(())
    }

    /// A construct the file leaves open: its first line fails when it runs.
    fn unclosed(&mut self, o: Open) {
        let (open, close) = o.what();
        let name = o.name(&self.code).to_string();
        let (line, inst) = o.line_and_inst();
        let l = self.code.text.line(line);
        let d = Diagnostic::error(
            DiagCode::Syntax,
            l.whole(),
            format!("o{name} {open} has no o{name} {close}"),
        )
        .with_hint(format!("close it with o{name} {close}"));
        self.code.fail_at(inst, d);
    }

    fn finish(&mut self) {
        while let Some(o) = self.open.pop() {
            self.unclosed(o);
        }
        let here = self.code.here();
        if let Some(p) = self.code.programs.last_mut() {
            p.end = here;
        }
    }
}

/// Whether a block ends the program (M2, M30).
fn ends_program(words: &[Word]) -> bool {
    words
        .iter()
        .any(|w| w.letter == b'M' && (w.value == 2.0 || w.value == 30.0))
}

/// A lexed word as a block word.
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

/// Whether a line the lexer refuses is written in LinuxCNC's macro syntax: a parameter, an
/// expression, or an o-word.
pub fn looks_like_macro(text: &[u8]) -> bool {
    let mut in_comment = false;
    let mut first = None;
    for &b in text {
        match b {
            b'(' => in_comment = true,
            b')' => in_comment = false,
            b';' if !in_comment => break,
            b'#' | b'[' if !in_comment => return true,
            b' ' | b'\t' | b'\r' => {}
            _ if !in_comment && first.is_none() => first = Some(b),
            _ => {}
        }
    }
    // An o-word begins its line (after an optional block delete and line number).
    let t: Vec<u8> = text
        .iter()
        .copied()
        .filter(|b| !matches!(b, b' ' | b'\t'))
        .map(|b| b.to_ascii_uppercase())
        .collect();
    let mut k = 0;
    if t.get(k) == Some(&b'/') {
        k += 1;
    }
    if t.get(k) == Some(&b'N') {
        k += 1;
        while t.get(k).is_some_and(|b| b.is_ascii_digit() || *b == b'.') {
            k += 1;
        }
    }
    let _ = first;
    t.get(k) == Some(&b'O')
        && t.get(k + 1)
            .is_some_and(|b| b.is_ascii_digit() || *b == b'<')
}
