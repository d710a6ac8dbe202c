//! The Fanuc Custom Macro B front end (Fanuc, GSK with its own `G65 H` operations, Haas with M97,
//! its M99 P jumps and #10000 variables): variables
//! `#1=…`, `IF […] GOTO n`, `IF […] THEN …`, `WHILE […] DOm … ENDm`, `GOTO n`, `M98`/`M99`
//! subprograms and `G65` macro calls to programs held in the same file. Each choice is a row of
//! docs/dialects/fanuc.md (GSK's of docs/dialects/gsk-g78.md).

use std::collections::HashMap;

use crate::diag::{Code as DiagCode, Diagnostic, Span};
use crate::gcode::{lex_line_syntax, Word};

use super::code::{
    Assign, Block, BlockWord, Call, CallKind, CallTarget, Code, Inst, MacroOp, ProgramInfo, Target,
    WordValue,
};
use super::expr::{read_number, Expr, Lang, Parser};
use super::scan::Squeezed;
use super::text::{Text, TextLine};
use super::Syntax;

/// The loops of one program: `WHILE … DOm` waiting for their `ENDm`.
struct OpenDo {
    m: u8,
    inst: u32,
    line: usize,
}

struct Compiler<'s> {
    code: Code,
    syntax: &'s Syntax,
    program: u32,
    dos: Vec<OpenDo>,
    /// Something executable came already (an `O` before it is the main program's number).
    begun: bool,
    lexed: Vec<Word>,
}

/// Compiles a Fanuc-style program: the main program, then the programs that follow it.
pub fn compile(text: Text, syntax: &Syntax, lexer: crate::gcode::Syntax) -> Code {
    let mut c = Compiler {
        code: Code::new(Lang::MacroB, text, lexer),
        syntax,
        program: 0,
        dos: Vec::new(),
        begun: false,
        lexed: Vec::new(),
    };
    c.code.programs.push(ProgramInfo {
        number: None,
        first: 0,
        end: 0,
        labels: HashMap::new(),
    });
    for i in 0..c.code.text.len() {
        c.code.start_line(i);
        if let Err(d) = c.line(i) {
            c.code.fail(i, d);
        }
    }
    c.end_program();
    c.code
}

/// What a line is, once read.
enum Statement {
    Nothing,
    Percent,
    Header(u32, Span),
    /// A block the lexer reads, with no word of the interpreter's.
    Plain,
    Block(Block),
    Assign(Assign),
    IfGoto(Expr, Expr),
    IfThen(Expr, Assign),
    While(Option<Expr>, u8, Span),
    End(u8, Span),
    Goto(Expr),
}

impl Compiler<'_> {
    fn line(&mut self, i: usize) -> Result<(), Diagnostic> {
        let Compiler { code, lexed, .. } = self;
        let line = code.text.line(i);
        let lexed_line = lex_line_syntax(line.text, line.number, line.offset, lexed, &code.lexer);
        let owned = lexed_line.is_err().then(|| line.text.to_vec());
        let (number, offset) = (line.number, line.offset);
        let (label, statement) = match lexed_line {
            Ok(shape) if shape.percent => (None, Statement::Percent),
            Ok(shape) => self.lexed_statement(shape.block_delete),
            Err(lex_error) => {
                let text = owned.unwrap_or_default();
                let line = TextLine {
                    number,
                    offset,
                    text: &text,
                    raw: &text,
                };
                let s = Squeezed::new(line)?;
                match self.macro_statement(&s) {
                    Ok(r) => r,
                    Err(d) if d.code == DiagCode::Syntax && !looks_like_macro(line.text) => {
                        return Err(lex_error)
                    }
                    Err(d) => return Err(d),
                }
            }
        };
        if let Some(n) = label {
            let here = self.code.here();
            self.code.programs[self.program as usize]
                .labels
                .entry(n)
                .or_default()
                .push(here);
        }
        self.statement(i, statement)
    }

    /// A line the lexer read: its sequence number, and a plain block unless a word is the
    /// interpreter's (M98, M99, G65, M2, M30, an O number).
    fn lexed_statement(&mut self, block_delete: bool) -> (Option<u32>, Statement) {
        let words = &self.lexed;
        let label = match words.first() {
            Some(w) if w.letter == b'N' && w.value >= 0.0 && w.value.fract() == 0.0 => {
                Some(w.value as u32)
            }
            _ => None,
        };
        if words.is_empty() || (label.is_some() && words.len() == 1) {
            return (label, Statement::Nothing);
        }
        if let Some(o) = words.iter().find(|w| w.letter == b'O') {
            if words.len() == 1 && o.value >= 0.0 && o.value.fract() == 0.0 {
                return (None, Statement::Header(o.value as u32, o.span));
            }
        }
        let m97 = self.syntax.m97_local_calls;
        let control = words.iter().any(|w| {
            (w.letter == b'M'
                && (matches!(w.value as u32, 2 | 30 | 98 | 99) || (m97 && w.value as u32 == 97))
                && w.value.fract() == 0.0)
                || (w.letter == b'G' && w.value == 65.0)
                || w.letter == b'O'
        });
        if !control {
            return (label, Statement::Plain);
        }
        let block = Block {
            words: words
                .iter()
                .map(|w| BlockWord {
                    letter: w.letter,
                    value: WordValue::Lit {
                        value: w.value,
                        has_dot: w.has_dot,
                        skip: (w.raw_start() as u32).saturating_sub(w.span.column),
                    },
                    span: w.span,
                })
                .collect(),
            assigns: Vec::new(),
            block_delete,
        };
        (label, Statement::Block(block))
    }

    /// A line the lexer does not read: a macro statement, or a block with computed words.
    fn macro_statement(&mut self, s: &Squeezed) -> Result<(Option<u32>, Statement), Diagnostic> {
        let mut k = 0;
        if s.at(k) == b'/' {
            k += 1;
        }
        let mut label = None;
        if s.at(k) == b'N' && s.at(k + 1).is_ascii_digit() {
            let (v, dot, end) = read_number(s, k + 1, Lang::MacroB)?;
            if dot {
                return Err(s.error(k, end, "a sequence number is a whole number (alarm PS0114)"));
            }
            label = Some(v as u32);
            k = end;
        }
        let statement = if s.at(k) == b'#' {
            let a = self.assignment(s, &mut k)?;
            Statement::Assign(a)
        } else if s.at(k) == b'[' && self.syntax.m99_p_jumps {
            // Haas's conditional M99: `[condition] M99 P n` jumps to N n when it holds.
            let cond = Parser::new(s, &mut self.code.exprs, Lang::MacroB).bracketed(&mut k)?;
            if !s.starts_with(k, b"M99P") {
                return Err(s.error(
                    k,
                    k + 1,
                    "[condition] is followed by M99 P n (a conditional jump) or begins an IF",
                ));
            }
            k += 4;
            let target = self.goto_target(s, &mut k)?;
            Statement::IfGoto(cond, target)
        } else if s.starts_with(k, b"IF") && s.at(k + 2) == b'[' {
            k += 2;
            let cond = Parser::new(s, &mut self.code.exprs, Lang::MacroB).bracketed(&mut k)?;
            if s.starts_with(k, b"GOTO") {
                k += 4;
                let target = self.goto_target(s, &mut k)?;
                Statement::IfGoto(cond, target)
            } else if s.starts_with(k, b"THEN") {
                k += 4;
                if s.at(k) != b'#' {
                    return Err(s.error(
                        k,
                        k + 1,
                        "THEN takes an assignment: IF [cond] THEN #1=… (alarm PS0114)",
                    ));
                }
                let a = self.assignment(s, &mut k)?;
                Statement::IfThen(cond, a)
            } else {
                return Err(s.error(
                    k,
                    k + 1,
                    "IF [condition] is followed by GOTO n or THEN (alarm PS0114)",
                ));
            }
        } else if s.starts_with(k, b"WHILE") && s.at(k + 5) == b'[' {
            let at = k;
            k += 5;
            let cond = Parser::new(s, &mut self.code.exprs, Lang::MacroB).bracketed(&mut k)?;
            if !s.starts_with(k, b"DO") {
                return Err(s.error(
                    k,
                    k + 1,
                    "WHILE [condition] is followed by DOm (alarm PS0114)",
                ));
            }
            let m = loop_number(s, &mut k, 2)?;
            Statement::While(Some(cond), m, s.span(at, k))
        } else if s.starts_with(k, b"DO") && s.at(k + 2).is_ascii_digit() {
            let at = k;
            let m = loop_number(s, &mut k, 2)?;
            Statement::While(None, m, s.span(at, k))
        } else if s.starts_with(k, b"END") && (s.at(k + 3).is_ascii_digit() || s.at(k + 3) == 0) {
            let at = k;
            let m = loop_number(s, &mut k, 3)?;
            Statement::End(m, s.span(at, k))
        } else if s.starts_with(k, b"GOTO") {
            k += 4;
            let target = self.goto_target(s, &mut k)?;
            Statement::Goto(target)
        } else {
            let block = self.block(s, k)?;
            k = s.len();
            Statement::Block(block)
        };
        if k < s.len() {
            return Err(s
                .error(
                    k,
                    s.len(),
                    "a macro statement and NC words in one block (alarm PS0127)",
                )
                .with_hint("write the NC words in a block of their own"));
        }
        Ok((label, statement))
    }

    fn goto_target(&mut self, s: &Squeezed, k: &mut usize) -> Result<Expr, Diagnostic> {
        if s.at(*k).is_ascii_digit() {
            let (v, _, end) = read_number(s, *k, Lang::MacroB)?;
            let e = self.code.exprs.number(v, s.span(*k, end));
            *k = end;
            return Ok(e);
        }
        Parser::new(s, &mut self.code.exprs, Lang::MacroB).value(k)
    }

    /// `#i = expression`.
    fn assignment(&mut self, s: &Squeezed, k: &mut usize) -> Result<Assign, Diagnostic> {
        let from = *k;
        *k += 1;
        let index = match s.at(*k) {
            b'[' => Parser::new(s, &mut self.code.exprs, Lang::MacroB).bracketed(k)?,
            b'0'..=b'9' => {
                let (v, dot, end) = read_number(s, *k, Lang::MacroB)?;
                if dot {
                    return Err(s.error(
                        *k,
                        end,
                        "a variable number is a whole number (alarm PS0114)",
                    ));
                }
                let e = self.code.exprs.number(v, s.span(*k, end));
                *k = end;
                e
            }
            b'#' => Parser::new(s, &mut self.code.exprs, Lang::MacroB).value(k)?,
            _ => {
                return Err(s.error(
                    from,
                    *k + 1,
                    "`#` must be followed by a variable number (alarm PS0114)",
                ))
            }
        };
        if s.at(*k) != b'=' {
            return Err(s.error(*k, *k + 1, "`=` expected after the variable (alarm PS0114)"));
        }
        *k += 1;
        let value = Parser::new(s, &mut self.code.exprs, Lang::MacroB).bare(k)?;
        Ok(Assign {
            target: Target::Number(index),
            value,
            span: s.span(from, *k),
        })
    }

    /// An NC block whose words may hold variables and expressions.
    fn block(&mut self, s: &Squeezed, mut k: usize) -> Result<Block, Diagnostic> {
        let mut block = Block {
            block_delete: s.block_delete,
            ..Block::default()
        };
        while k < s.len() {
            let c = s.at(k);
            if !c.is_ascii_uppercase() {
                return Err(s.error(
                    k,
                    k + 1,
                    format!("`{}` cannot begin a word (alarm PS0114)", c as char),
                ));
            }
            let from = k;
            k += 1;
            let c1 = s.at(k);
            let c2 = s.at(k + 1);
            let value = if c1.is_ascii_digit()
                || c1 == b'.'
                || (matches!(c1, b'+' | b'-') && (c2.is_ascii_digit() || c2 == b'.'))
            {
                let letter_col = s.span(from, from + 1).column;
                let (value, has_dot, end) = read_number(s, k, Lang::MacroB)?;
                let skip = s.span(k, end).column - letter_col - 1;
                k = end;
                WordValue::Lit {
                    value,
                    has_dot,
                    skip,
                }
            } else if matches!(c1, b'#' | b'[')
                || (matches!(c1, b'+' | b'-') && matches!(c2, b'#' | b'['))
            {
                WordValue::Expr(Parser::new(s, &mut self.code.exprs, Lang::MacroB).value(&mut k)?)
            } else {
                return Err(s.error(
                    from,
                    k + 1,
                    format!(
                    "`{}` must be followed by a number, a variable or [expression] (alarm PS0114)",
                    c as char
                ),
                ));
            };
            block.words.push(BlockWord {
                letter: c,
                value,
                span: s.span(from, k),
            });
        }
        Ok(block)
    }

    fn statement(&mut self, i: usize, st: Statement) -> Result<(), Diagnostic> {
        match st {
            Statement::Nothing => {}
            // `%` delimits programs on a tape; the run ends at M2/M30 (and a main program at the
            // next program's O number), as in the streamed run.
            Statement::Percent => {}
            Statement::Header(n, span) => {
                if !self.begun && self.program == 0 {
                    self.code.programs[0].number = Some(n);
                    return Ok(());
                }
                self.end_program();
                self.code.emit(i, Inst::NextProgram);
                if let Some(other) = self.code.programs.iter().find(|p| p.number == Some(n)) {
                    let before = self.code.line_number(other.first.saturating_sub(1));
                    return Err(Diagnostic::error(
                        DiagCode::Conflict,
                        span,
                        format!("O{n:04} is in the file twice (first at line {before})"),
                    ));
                }
                let first = self.code.here();
                self.code.programs.push(ProgramInfo {
                    number: Some(n),
                    first,
                    end: first,
                    labels: HashMap::new(),
                });
                self.program = self.code.programs.len() as u32 - 1;
            }
            Statement::Plain => {
                self.begun = true;
                self.code.emit(i, Inst::Plain);
            }
            Statement::Block(b) => {
                self.begun = true;
                self.nc_block(i, b)?;
            }
            Statement::Assign(a) => {
                self.begun = true;
                self.emit_block(
                    i,
                    Block {
                        words: Vec::new(),
                        assigns: vec![a],
                        block_delete: false,
                    },
                );
            }
            Statement::IfGoto(cond, target) => {
                self.begun = true;
                self.code.emit(
                    i,
                    Inst::IfGoto {
                        cond,
                        target,
                        program: self.program,
                    },
                );
            }
            Statement::IfThen(cond, a) => {
                self.begun = true;
                let skip = self.code.emit(i, Inst::JumpUnless { cond, target: 0 });
                self.emit_block(
                    i,
                    Block {
                        words: Vec::new(),
                        assigns: vec![a],
                        block_delete: false,
                    },
                );
                let after = self.code.here();
                self.code.patch(skip, after);
            }
            Statement::While(cond, m, span) => {
                self.begun = true;
                if self.dos.len() >= 3 {
                    return Err(Diagnostic::error(
                        DiagCode::OutOfRange,
                        span,
                        "loops nest at most three deep (DO1–DO3, alarm PS0126)",
                    ));
                }
                if self.dos.iter().any(|d| d.m == m) {
                    return Err(Diagnostic::error(
                        DiagCode::Syntax,
                        span,
                        format!("DO{m} inside a loop of the same number (alarm PS0126)"),
                    )
                    .with_hint("nested loops need different numbers: DO1, DO2, DO3"));
                }
                let inst = match cond {
                    Some(cond) => self.code.emit(i, Inst::JumpUnless { cond, target: 0 }),
                    None => self.code.emit(i, Inst::Nop),
                };
                self.dos.push(OpenDo { m, inst, line: i });
            }
            Statement::End(m, span) => {
                self.begun = true;
                match self.dos.last() {
                    Some(d) if d.m == m => {
                        let d = self.dos.pop().expect("checked");
                        self.code.emit(i, Inst::Jump(d.inst));
                        let after = self.code.here();
                        self.code.patch(d.inst, after);
                    }
                    Some(d) => {
                        let line = self.code.text.line(d.line).number;
                        return Err(Diagnostic::error(DiagCode::Syntax, span, format!(
                            "END{m} closes the loop DO{} of line {line}, which ends with END{} (alarm PS0124)",
                            d.m, d.m
                        )));
                    }
                    None => {
                        return Err(Diagnostic::error(
                            DiagCode::Syntax,
                            span,
                            format!("END{m} without WHILE … DO{m} before it (alarm PS0124)"),
                        ))
                    }
                }
            }
            Statement::Goto(target) => {
                self.begun = true;
                self.code.emit(
                    i,
                    Inst::Goto {
                        target,
                        program: self.program,
                    },
                );
            }
        }
        Ok(())
    }

    fn emit_block(&mut self, i: usize, b: Block) {
        let at = self.code.blocks.len() as u32;
        self.code.blocks.push(b);
        self.code.emit(i, Inst::Block(at));
    }

    /// An NC block: the words of the interpreter (M98, M99, G65, M2, M30) become calls, returns
    /// and the end; the other words run as a block first, as the control runs them.
    fn nc_block(&mut self, i: usize, mut b: Block) -> Result<(), Diagnostic> {
        let lit = |w: &BlockWord| match w.value {
            WordValue::Lit { value, .. } if value.fract() == 0.0 && value >= 0.0 => {
                Some(value as u32)
            }
            _ => None,
        };
        let find = |b: &Block, letter: u8, code: u32| {
            b.words
                .iter()
                .position(|w| w.letter == letter && lit(w) == Some(code))
        };
        if let Some(g65) = find(&b, b'G', 65) {
            return self.g65(i, b, g65);
        }
        if let Some(o) = b.words.iter().find(|w| w.letter == b'O') {
            return Err(Diagnostic::error(
                DiagCode::Syntax,
                o.span,
                "a program number O stands alone at the start of its program",
            )
            .with_hint("write O1000 on a line of its own"));
        }
        let m98 = find(&b, b'M', 98);
        let m97 = find(&b, b'M', 97).filter(|_| self.syntax.m97_local_calls);
        let m99 = find(&b, b'M', 99);
        let end = find(&b, b'M', 2).or(find(&b, b'M', 30)).is_some();
        if let Some(at) = m97 {
            if m98.is_some() || m99.is_some() {
                return Err(Diagnostic::error(
                    DiagCode::Conflict,
                    b.words[at].span,
                    "M97 and another call or return in one block",
                ));
            }
            return self.local_call(i, b, at, end);
        }
        if m98.is_none() && m99.is_none() {
            self.emit_block(i, b);
            if end {
                self.code.emit(i, Inst::End);
            }
            return Ok(());
        }
        let (at, is_call) = match (m98, m99) {
            (Some(a), None) => (a, true),
            (None, Some(a)) => (a, false),
            (Some(_), Some(a)) => {
                return Err(Diagnostic::error(
                    DiagCode::Conflict,
                    b.words[a].span,
                    "M98 and M99 in one block",
                ))
            }
            (None, None) => unreachable!(),
        };
        let word_span = b.words[at].span;
        b.words.remove(at);
        let take = |b: &mut Block, letter: u8| {
            b.words
                .iter()
                .position(|w| w.letter == letter)
                .map(|k| b.words.remove(k))
        };
        let p = take(&mut b, b'P');
        let l = if is_call { take(&mut b, b'L') } else { None };
        let to_expr = |c: &mut Self, w: BlockWord| match w.value {
            WordValue::Expr(e) => e,
            WordValue::Lit { value, .. } => c.code.exprs.number(value, w.span),
        };
        // The block's other words run first.
        if !b.words.is_empty() {
            self.emit_block(i, b);
        }
        if is_call {
            let Some(p) = p else {
                return Err(Diagnostic::error(
                    DiagCode::MissingWord,
                    word_span,
                    "M98 needs P, the program to call (alarm PS0076)",
                ));
            };
            if let Some(l) = l.as_ref().filter(|_| !self.syntax.m98_l_word) {
                return Err(Diagnostic::error(DiagCode::Unsupported, l.span, "this control's M98 has no L: the count is packed in P")
                    .with_hint("M98 P00031000 calls O1000 three times: four digits of count, four of program number"));
            }
            let packed = l.is_none();
            let number = to_expr(self, p);
            let count = l.map(|l| to_expr(self, l));
            let c = self.code.calls.len() as u32;
            self.code.calls.push(Call {
                kind: CallKind::M98,
                target: CallTarget::Program { number, packed },
                args: Vec::new(),
                arg_letters: Vec::new(),
                arg_no_point: Vec::new(),
                count,
                span: word_span,
            });
            self.code.emit(i, Inst::Call(c));
        } else if let (Some(p), true) = (p.clone(), self.syntax.m99_p_jumps) {
            // Haas: `M99 P n` jumps to N n in the program it is in, and returns nowhere.
            let target = to_expr(self, p);
            self.code.emit(
                i,
                Inst::Goto {
                    target,
                    program: self.program,
                },
            );
        } else {
            let to_label = p.map(|p| to_expr(self, p));
            self.code.emit(
                i,
                Inst::Return {
                    value: None,
                    to_label,
                },
            );
        }
        if end {
            self.code.emit(i, Inst::End);
        }
        Ok(())
    }

    /// Haas's `M97 P n L k`: calls the block N n of the program it is in as a subprogram, k
    /// times (the same local variables, as M98; it returns at M99). The block's other words run
    /// first.
    fn local_call(
        &mut self,
        i: usize,
        mut b: Block,
        at: usize,
        end: bool,
    ) -> Result<(), Diagnostic> {
        let word_span = b.words[at].span;
        b.words.remove(at);
        let take = |b: &mut Block, letter: u8| {
            b.words
                .iter()
                .position(|w| w.letter == letter)
                .map(|k| b.words.remove(k))
        };
        let p = take(&mut b, b'P');
        let l = take(&mut b, b'L');
        let to_expr = |c: &mut Self, w: BlockWord| match w.value {
            WordValue::Expr(e) => e,
            WordValue::Lit { value, .. } => c.code.exprs.number(value, w.span),
        };
        if !b.words.is_empty() {
            self.emit_block(i, b);
        }
        let Some(p) = p else {
            return Err(Diagnostic::error(
                DiagCode::MissingWord,
                word_span,
                "M97 needs P, the sequence number of the local subprogram to call",
            )
            .with_hint("M97 P1000 calls the block N1000 of the same program; it returns at M99"));
        };
        let label = to_expr(self, p);
        let count = l.map(|l| to_expr(self, l));
        let c = self.code.calls.len() as u32;
        self.code.calls.push(Call {
            kind: CallKind::M98,
            target: CallTarget::Label {
                label,
                program: self.program,
            },
            args: Vec::new(),
            arg_letters: Vec::new(),
            arg_no_point: Vec::new(),
            count,
            span: word_span,
        });
        self.code.emit(i, Inst::Call(c));
        if end {
            self.code.emit(i, Inst::End);
        }
        Ok(())
    }

    /// `G65 P… L… args` (a macro call), or GSK's `G65 Hm P#i Q#j R#k` (an operation).
    fn g65(&mut self, i: usize, mut b: Block, at: usize) -> Result<(), Diagnostic> {
        let g_span = b.words[at].span;
        b.words.remove(at);
        let to_expr = |c: &mut Self, w: &BlockWord| match w.value {
            WordValue::Expr(e) => e,
            WordValue::Lit { value, .. } => c.code.exprs.number(value, w.span),
        };
        if self.syntax.g65_operations {
            return self.macro_op(i, b, g_span);
        }
        if let Some(w) = b
            .words
            .iter()
            .find(|w| matches!(w.letter, b'G' | b'N' | b'O'))
        {
            return Err(Diagnostic::error(
                DiagCode::Syntax,
                w.span,
                format!(
                    "{} cannot be an argument of G65 (alarm PS0129)",
                    w.letter as char
                ),
            ));
        }
        let Some(pk) = b.words.iter().position(|w| w.letter == b'P') else {
            return Err(Diagnostic::error(
                DiagCode::MissingWord,
                g_span,
                "G65 needs P, the macro program to call (alarm PS0076)",
            ));
        };
        let p = b.words.remove(pk);
        let number = to_expr(self, &p);
        let count = match b.words.iter().position(|w| w.letter == b'L') {
            Some(k) => {
                let l = b.words.remove(k);
                Some(to_expr(self, &l))
            }
            None => None,
        };
        let mut args = Vec::new();
        let mut letters = Vec::new();
        let mut no_point = Vec::new();
        for w in &b.words {
            // An argument without a decimal point is read as the machine reads such a number
            // (the run's units decide): remember which were.
            args.push(to_expr(self, w));
            letters.push((w.letter, w.span));
            no_point.push(matches!(w.value, WordValue::Lit { has_dot: false, .. }));
        }
        let c = self.code.calls.len() as u32;
        self.code.calls.push(Call {
            kind: CallKind::G65,
            target: CallTarget::Program {
                number,
                packed: false,
            },
            args,
            arg_letters: letters,
            arg_no_point: no_point,
            count,
            span: g_span,
        });
        self.code.emit(i, Inst::Call(c));
        Ok(())
    }

    /// GSK: `G65 Hm P#i Q#j R#k`.
    fn macro_op(&mut self, i: usize, b: Block, g_span: Span) -> Result<(), Diagnostic> {
        let word = |letter: u8| b.words.iter().find(|w| w.letter == letter);
        let Some(h) = word(b'H') else {
            return Err(Diagnostic::error(DiagCode::MissingWord, g_span, "G65 needs H, the operation: G65 Hm P#i Q#j R#k")
                .with_hint("this control's G65 is a macro operation (its manual's macro command list), not a call"));
        };
        let h_value = match h.value {
            WordValue::Lit { value, .. } if value.fract() == 0.0 && value >= 0.0 => value as u32,
            _ => {
                return Err(Diagnostic::error(
                    DiagCode::Syntax,
                    h.span,
                    "H is the operation's number, written as a number",
                ))
            }
        };
        if let Some(w) = b
            .words
            .iter()
            .find(|w| !matches!(w.letter, b'H' | b'P' | b'Q' | b'R'))
        {
            return Err(Diagnostic::error(
                DiagCode::Unsupported,
                w.span,
                format!("{} is not a word of G65 Hm P#i Q#j R#k", w.letter as char),
            ));
        }
        let value_of = |c: &mut Self, w: Option<&BlockWord>| {
            w.map(|w| match w.value {
                WordValue::Expr(e) => e,
                WordValue::Lit { value, .. } => c.code.exprs.number(value, w.span),
            })
        };
        let jump = (80..=86).contains(&h_value) || h_value == 99;
        // P#i names the variable set (its number, not its value); for jumps P is the sequence
        // number.
        let (dest, p) = if jump {
            (None, value_of(self, word(b'P')))
        } else {
            match word(b'P') {
                Some(w) => match &w.value {
                    WordValue::Expr(_) => {
                        let text = w.span;
                        let dest = self.variable_number(w, text)?;
                        (Some(dest), None)
                    }
                    WordValue::Lit { .. } => {
                        return Err(Diagnostic::error(
                            DiagCode::Syntax,
                            w.span,
                            "P names the variable set: write P#100",
                        ))
                    }
                },
                None => (None, None),
            }
        };
        let q = value_of(self, word(b'Q'));
        let r = value_of(self, word(b'R'));
        let op = self.code.ops.len() as u32;
        self.code.ops.push(MacroOp {
            h: h_value,
            dest,
            p,
            q,
            r,
            span: g_span,
            program: self.program,
        });
        self.code.emit(i, Inst::MacroOp(op));
        Ok(())
    }

    /// The variable number a `P#i` word names: re-read from the word's text.
    fn variable_number(&mut self, w: &BlockWord, span: Span) -> Result<Expr, Diagnostic> {
        let line_index = self
            .code
            .text
            .index_of(span.line)
            .expect("the word's own line");
        let line = self.code.text.line(line_index);
        let s = Squeezed::new(line)?;
        // Find the `#` after the word's letter.
        let col = (span.column as usize).saturating_sub(1);
        let mut k = (0..s.len())
            .find(|&k| s.span(k, k + 1).column as usize > col + 1 && s.at(k) == b'#')
            .ok_or_else(|| {
                Diagnostic::error(
                    DiagCode::Syntax,
                    w.span,
                    "P names the variable set: write P#100",
                )
            })?;
        k += 1;
        match s.at(k) {
            b'[' => Parser::new(&s, &mut self.code.exprs, Lang::MacroB).bracketed(&mut k),
            _ => {
                let (v, _, end) = read_number(&s, k, Lang::MacroB)?;
                Ok(self.code.exprs.number(v, s.span(k, end)))
            }
        }
    }

    /// The current program ends: its loops must be closed.
    fn end_program(&mut self) {
        while let Some(d) = self.dos.pop() {
            let line = self.code.text.line(d.line);
            let e = Diagnostic::error(
                DiagCode::Syntax,
                line.whole(),
                format!(
                    "DO{} has no END{} in its program (alarm PS0124, missing END statement)",
                    d.m, d.m
                ),
            );
            self.code.fail_at(d.inst, e);
        }
        let here = self.code.here();
        if let Some(p) = self.code.programs.get_mut(self.program as usize) {
            p.end = here;
        }
    }
}

/// The `m` of `DOm`/`ENDm` at `*k + skip`: 1, 2 or 3.
fn loop_number(s: &Squeezed, k: &mut usize, skip: usize) -> Result<u8, Diagnostic> {
    let at = *k;
    *k += skip;
    let from = *k;
    while s.at(*k).is_ascii_digit() {
        *k += 1;
    }
    let digits: String = (from..*k).map(|j| s.at(j) as char).collect();
    match digits.parse::<u32>() {
        Ok(m @ 1..=3) => Ok(m as u8),
        _ => Err(s.error(
            at,
            (*k).max(at + skip),
            "the loop number must be 1, 2 or 3 (alarm PS0126)",
        )),
    }
}

/// Which local variable each G65 argument sets (Fanuc's argument specifications I and II): A B
/// C D E F H M Q R S T U V W X Y Z go to #1 #2 #3 #7 #8 #9 #11 #13 #17 … #26; I, J, K to #4 #5 #6
/// for the first set and to #7 … #33 for up to ten sets, a new set beginning when I, J or K comes
/// again or out of order. A later argument for the same variable wins.
pub fn argument_slots(letters: &[(u8, Span)]) -> Vec<u8> {
    let mut set = 0u8;
    let mut last: Option<u8> = None;
    letters
        .iter()
        .map(|&(letter, _)| match letter {
            b'I' | b'J' | b'K' => {
                let pos = letter - b'I';
                if last.is_some_and(|p| pos <= p) {
                    set += 1;
                }
                last = Some(pos);
                (4 + 3 * set.min(9) + pos).min(33)
            }
            b'A' => 1,
            b'B' => 2,
            b'C' => 3,
            b'D' => 7,
            b'E' => 8,
            b'F' => 9,
            b'H' => 11,
            b'M' => 13,
            b'Q' => 17,
            b'R' => 18,
            b'S' => 19,
            b'T' => 20,
            b'U' => 21,
            b'V' => 22,
            b'W' => 23,
            b'X' => 24,
            b'Y' => 25,
            b'Z' => 26,
            _ => 0,
        })
        .collect()
}

/// Whether a line the lexer refuses is written in the macro syntax: a variable, an expression,
/// or a macro keyword.
pub fn looks_like_macro(text: &[u8]) -> bool {
    let mut t = Vec::with_capacity(text.len());
    let mut in_comment = false;
    for &b in text {
        match b {
            b'(' => in_comment = true,
            b')' => in_comment = false,
            b';' if !in_comment => break,
            b' ' | b'\t' | b'\r' => {}
            _ if !in_comment => t.push(b.to_ascii_uppercase()),
            _ => {}
        }
    }
    if t.iter().any(|&b| b == b'#' || b == b'[') {
        return true;
    }
    let mut k = 0;
    if t.get(k) == Some(&b'/') {
        k += 1;
    }
    if t.get(k) == Some(&b'N') {
        k += 1;
        while t.get(k).is_some_and(u8::is_ascii_digit) {
            k += 1;
        }
    }
    let rest = &t[k.min(t.len())..];
    [&b"GOTO"[..], b"WHILE", b"IF", b"END", b"DO"]
        .iter()
        .any(|kw| rest.starts_with(kw))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn slots(letters: &str) -> Vec<u8> {
        let v: Vec<(u8, Span)> = letters
            .bytes()
            .map(|b| (b, Span::new(0, 0, 0, 0)))
            .collect();
        argument_slots(&v)
    }

    #[test]
    fn argument_specification_one_and_two() {
        // Specification I.
        assert_eq!(
            slots("ABCIJKDEFHMQRSTUVWXYZ"),
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 13, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26]
        );
        // Specification II: A B C and sets of I J K.
        assert_eq!(
            slots("ABCIJKIJKIJK"),
            [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]
        );
        assert_eq!(slots("IIII"), [4, 7, 10, 13]);
        assert_eq!(slots("JI"), [5, 7]);
        assert_eq!(slots("IJKIJKIJKIJKIJKIJKIJKIJKIJKIJK")[27..], [31, 32, 33]);
    }

    #[test]
    fn macro_lines_are_told_from_malformed_blocks() {
        assert!(looks_like_macro(b"#100=1"));
        assert!(looks_like_macro(b"N10 WHILE [#1 LT 3] DO1"));
        assert!(looks_like_macro(b"IF[#1EQ2]GOTO10"));
        assert!(looks_like_macro(b"END1"));
        assert!(looks_like_macro(b"GOTO 20"));
        assert!(!looks_like_macro(b"G0 X1.2.3"));
        assert!(!looks_like_macro(b"G0 X1 (#1 in a comment)"));
    }
}
