//! Sinumerik's statements: jumps to labels, the structures that open and close (IF, WHILE, FOR,
//! LOOP, REPEAT), PROC and RET, DEF, and calls of the file's PROCs by name.

use crate::diag::{Code as DiagCode, Diagnostic, Span};

use super::super::code::{Assign, Block, Call, CallKind, CallTarget, Inst, Target};
use super::super::expr::{BinOp, Expr, Op};
use super::super::text::Text;
use super::cursor::{r_number, Cursor, ExprReader};
use super::{jump_direction, jump_word, Compiler, Direction, Fixup, Open, Opened, Unit};

type R<T> = Result<T, Diagnostic>;

/// A loop's variable: an R parameter or a DEF variable.
#[derive(Clone, Copy)]
enum Var {
    R(u32),
    Name(u32),
}

/// The label after a jump word that ends at `e`, and where the label ends.
pub(super) fn label_word(cur: &mut Cursor, word: &str, e: usize) -> R<(String, usize)> {
    cur.i = e;
    match cur.peek_name() {
        Some((label, _, end)) => {
            cur.i = end;
            Ok((label, end))
        }
        None => {
            let at = cur.i;
            Err(cur
                .error(
                    e - word.len(),
                    at.max(e),
                    format!("{word} needs a label: {word} NAME"),
                )
                .with_hint("a label is a name (two characters or more) or a block number N…"))
        }
    }
}

/// Sinumerik's alarm for a structure that does not nest.
fn nesting(span: Span, msg: String) -> Diagnostic {
    Diagnostic::error(
        DiagCode::Syntax,
        span,
        format!("{msg} (alarm 12640, invalid nesting of control structures)"),
    )
}

impl Compiler {
    /// A statement of the language, if the line begins with one (`word`, ending at `e`).
    pub(super) fn flow(&mut self, i: usize, cur: &mut Cursor, word: &str, e: usize) -> R<bool> {
        let k = cur.i;
        let span = cur.span(k, e);
        match word {
            "IF" => {
                cur.i = e;
                self.if_statement(i, cur, span)?;
            }
            "ELSE" | "ENDIF" | "ENDWHILE" | "ENDFOR" | "ENDLOOP" => {
                cur.i = e;
                self.close(i, word, span)?;
            }
            "WHILE" => {
                cur.i = e;
                let top = self.code.here();
                let cond = ExprReader::new(cur, &mut self.code.exprs).expr()?;
                let jump = self.code.emit(i, Inst::JumpUnless { cond, target: 0 });
                self.opened(Open::While { top, jump }, jump, span);
            }
            "UNTIL" => {
                cur.i = e;
                self.until(i, cur, span)?;
            }
            "FOR" => {
                cur.i = e;
                self.for_statement(i, cur, span)?;
            }
            "LOOP" | "REPEAT" | "REPEATB" => {
                cur.i = e;
                if word != "LOOP" && !cur.done() {
                    return self.repeat_section(i, cur, word, span);
                }
                let top = self.code.emit(i, Inst::Nop);
                let what = if word == "LOOP" {
                    Open::Loop { top }
                } else {
                    Open::Repeat { top }
                };
                self.opened(what, top, span);
            }
            "GOTOF" | "GOTOB" | "GOTO" | "GOTOC" => {
                let direction = jump_direction(word).expect("a jump word");
                let (label, end) = label_word(cur, word, e)?;
                self.end_of_statement(cur)?;
                self.jump(i, Inst::Jump(0), label, cur.span(k, end), direction);
            }
            "PROC" => {
                cur.i = e;
                self.proc_line(i, cur)?;
            }
            "RET" => {
                cur.i = e;
                self.end_of_statement(cur)?;
                self.ret(i);
            }
            "DEF" => {
                cur.i = e;
                self.def(i, cur, span)?;
            }
            "CALL" => {
                cur.i = e;
                self.call(i, cur)?;
            }
            // The declaration of a subprogram's parameters: its PROC line says them again. (A
            // subprogram only declared is called as any other, and is not found in this file.)
            "EXTERN" => {}
            _ => return Ok(false),
        }
        Ok(true)
    }

    fn end_of_statement(&self, cur: &mut Cursor) -> R<()> {
        if cur.done() {
            return Ok(());
        }
        let at = cur.i;
        Err(cur.error(
            at,
            at + 1,
            "the statement ends here: nothing may follow it in its block",
        ))
    }

    fn opened(&mut self, what: Open, inst: u32, span: Span) {
        self.open.push(Opened { what, inst, span });
    }

    /// `IF cond GOTOF label` (and the other jumps), or `IF cond` opening IF … ELSE … ENDIF.
    fn if_statement(&mut self, i: usize, cur: &mut Cursor, span: Span) -> R<()> {
        let cond = ExprReader::new(cur, &mut self.code.exprs).expr()?;
        if cur.done() {
            let jump = self.code.emit(i, Inst::JumpUnless { cond, target: 0 });
            self.opened(
                Open::If {
                    jump,
                    else_jump: None,
                },
                jump,
                span,
            );
            return Ok(());
        }
        let word_at = cur.i;
        let direction = cur
            .peek_name()
            .and_then(|(w, _, e)| jump_direction(&w).map(|d| (d, e)));
        let Some((direction, e)) = direction else {
            return Err(cur
                .error(
                    word_at,
                    word_at + 1,
                    "GOTOF, GOTOB, GOTO or GOTOC expected after IF's condition",
                )
                .with_hint("IF cond GOTOF LABEL jumps; IF cond alone opens IF … ELSE … ENDIF"));
        };
        let word = jump_word(direction);
        let (label, end) = label_word(cur, word, e)?;
        self.end_of_statement(cur)?;
        self.jump(
            i,
            Inst::JumpIf { cond, target: 0 },
            label,
            cur.span(word_at, end),
            direction,
        );
        Ok(())
    }

    /// A jump to a label, looked up when the whole program is read.
    pub(super) fn jump(&mut self, i: usize, inst: Inst, label: String, span: Span, d: Direction) {
        let at = self.code.emit(i, inst);
        self.fixups.push(Fixup {
            at,
            label,
            direction: d,
            line: i,
            unit: self.units.len() - 1,
            word: jump_word(d),
            span,
        });
    }

    /// ELSE and the ends of structures.
    fn close(&mut self, i: usize, word: &str, span: Span) -> R<()> {
        let top = self.open.pop();
        let what = top.as_ref().map(|o| &o.what);
        match (word, what) {
            (
                "ELSE",
                Some(Open::If {
                    jump,
                    else_jump: None,
                }),
            ) => {
                let (jump, opened) = (*jump, top.expect("an IF"));
                let skip = self.code.emit(i, Inst::Jump(0));
                let here = self.code.here();
                self.code.patch(jump, here);
                self.open.push(Opened {
                    what: Open::If {
                        jump,
                        else_jump: Some(skip),
                    },
                    ..opened
                });
            }
            ("ENDIF", Some(Open::If { jump, else_jump })) => {
                let here = self.code.here();
                self.code.patch(else_jump.unwrap_or(*jump), here);
            }
            ("ENDWHILE", Some(Open::While { top, jump })) => {
                let (top, jump) = (*top, *jump);
                self.code.emit(i, Inst::Jump(top));
                let here = self.code.here();
                self.code.patch(jump, here);
            }
            ("ENDFOR", Some(Open::For { top, jump, step })) => {
                let (top, jump) = (*top, *jump);
                let b = self.code.blocks.len() as u32;
                self.code.blocks.push(Block {
                    words: Vec::new(),
                    assigns: vec![step.clone()],
                    block_delete: false,
                });
                self.code.emit(i, Inst::Block(b));
                self.code.emit(i, Inst::Jump(top));
                let here = self.code.here();
                self.code.patch(jump, here);
            }
            ("ENDLOOP", Some(Open::Loop { top })) => {
                self.code.emit(i, Inst::Jump(*top));
            }
            _ => {
                // What this end does not close stays open: its own end may come.
                if let Some(o) = top {
                    self.open.push(o);
                }
                return Err(nesting(
                    span,
                    format!("{word} without the structure it ends"),
                ));
            }
        }
        Ok(())
    }

    /// `UNTIL cond`: back to REPEAT while the condition is false.
    fn until(&mut self, i: usize, cur: &mut Cursor, span: Span) -> R<()> {
        let top = match self.open.last() {
            Some(Opened {
                what: Open::Repeat { top },
                ..
            }) => *top,
            _ => return Err(nesting(span, "UNTIL without REPEAT".to_string())),
        };
        self.open.pop();
        let cond = ExprReader::new(cur, &mut self.code.exprs).expr()?;
        self.end_of_statement(cur)?;
        self.code.emit(i, Inst::JumpUnless { cond, target: top });
        Ok(())
    }

    /// `FOR var = start TO end`: the variable counts up by 1 while it is at most `end`.
    fn for_statement(&mut self, i: usize, cur: &mut Cursor, span: Span) -> R<()> {
        let Some((name, k, e)) = cur.peek_name() else {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "FOR needs its variable: FOR R1=1 TO 10"));
        };
        let var_span = cur.span(k, e);
        let var = match r_number(&name) {
            Some(n) => Var::R(n),
            None if self.declared(&name) => Var::Name(self.code.exprs.intern(name.clone())),
            None => return Err(undeclared_here(&name, var_span)),
        };
        cur.i = e;
        if !cur.eat(b'=') {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "`=` expected: FOR R1=1 TO 10"));
        }
        let start = ExprReader::new(cur, &mut self.code.exprs).expr()?;
        if !cur.eat_name("TO") {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "TO expected: FOR R1=1 TO 10"));
        }
        // The test: var <= end (the end read again on each turn).
        let mark = self.code.exprs.mark();
        self.push_var(var, var_span);
        ExprReader::new(cur, &mut self.code.exprs).chain()?;
        self.code.exprs.push(Op::Bin(BinOp::Le), var_span);
        let cond = self.code.exprs.since(mark);
        self.end_of_statement(cur)?;
        let target = self.target(var, var_span);
        self.assigns(
            i,
            vec![Assign {
                target: target.clone(),
                value: start,
                span,
            }],
        );
        let top = self.code.here();
        let jump = self.code.emit(i, Inst::JumpUnless { cond, target: 0 });
        let mark = self.code.exprs.mark();
        self.push_var(var, var_span);
        self.code.exprs.push(Op::Num(1.0), var_span);
        self.code.exprs.push(Op::Bin(BinOp::Add), var_span);
        let value = self.code.exprs.since(mark);
        let step = Assign {
            target,
            value,
            span,
        };
        self.opened(Open::For { top, jump, step }, jump, span);
        Ok(())
    }

    fn push_var(&mut self, var: Var, span: Span) {
        match var {
            Var::R(n) => {
                self.code.exprs.push(Op::Num(f64::from(n)), span);
                self.code.exprs.push(Op::Var, span);
            }
            Var::Name(id) => self.code.exprs.push(Op::Named(id), span),
        }
    }

    fn target(&mut self, var: Var, span: Span) -> Target {
        match var {
            Var::R(n) => Target::Number(self.code.exprs.number(f64::from(n), span)),
            Var::Name(id) => Target::Named(id),
        }
    }

    fn declared(&self, name: &str) -> bool {
        self.units.last().is_some_and(|u| u.declared.contains(name))
    }

    /// A block of settings alone.
    fn assigns(&mut self, i: usize, assigns: Vec<Assign>) {
        let b = self.code.blocks.len() as u32;
        self.code.blocks.push(Block {
            words: Vec::new(),
            assigns,
            block_delete: false,
        });
        self.code.emit(i, Inst::Block(b));
    }

    /// RET: a subprogram returns; in the main program, the program ends.
    fn ret(&mut self, i: usize) {
        let inst = if self.units.last().is_some_and(|u| u.is_proc) {
            Inst::Return {
                value: None,
                to_label: None,
            }
        } else {
            Inst::End
        };
        self.code.emit(i, inst);
    }

    /// `DEF REAL A=1, B, C=R1*2` (REAL, INT, BOOL): the names become the program's variables,
    /// 0 unless given a value; an INT's value is rounded.
    fn def(&mut self, i: usize, cur: &mut Cursor, span: Span) -> R<()> {
        let Some((kind, _, e)) = cur.peek_name() else {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "DEF needs a type: DEF REAL NAME"));
        };
        if !matches!(kind.as_str(), "REAL" | "INT" | "BOOL") {
            return Err(Diagnostic::error(
                DiagCode::Unsupported,
                span,
                format!("DEF {kind}: threadcut keeps REAL, INT and BOOL variables"),
            ));
        }
        cur.i = e;
        let mut assigns = Vec::new();
        loop {
            let Some((name, k, e)) = cur.peek_name() else {
                let at = cur.i;
                return Err(cur.error(at, at + 1, "a variable's name expected here"));
            };
            let name_span = cur.span(k, e);
            cur.i = e;
            if cur.next_char(e).0 == b'[' {
                return Err(Diagnostic::error(
                    DiagCode::Unsupported,
                    name_span,
                    format!("{name}[…]: threadcut does not keep arrays"),
                ));
            }
            let mark = self.code.exprs.mark();
            if cur.eat(b'=') {
                ExprReader::new(cur, &mut self.code.exprs).chain()?;
                if kind == "INT" {
                    self.code
                        .exprs
                        .push(Op::Fun(super::super::expr::Func::Round), name_span);
                }
            } else {
                self.code.exprs.push(Op::Num(0.0), name_span);
            }
            let value = self.code.exprs.since(mark);
            let id = self.code.exprs.intern(name.clone());
            self.unit().declared.insert(name);
            assigns.push(Assign {
                target: Target::Declare(id),
                value,
                span: cur.span(k, cur.i),
            });
            if !cur.eat(b',') {
                break;
            }
        }
        self.end_of_statement(cur)?;
        self.assigns(i, assigns);
        Ok(())
    }

    /// `PROC NAME(REAL A, INT B) …`: the previous program ends here, a subprogram begins.
    fn proc_line(&mut self, i: usize, cur: &mut Cursor) -> R<()> {
        self.close_structures();
        self.code.emit(i, Inst::NextProgram);
        self.units.push(Unit::new(true));
        let Some((name, k, e)) = cur.peek_name() else {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "PROC needs the subprogram's name"));
        };
        cur.i = e;
        let id = self.code.exprs.intern(name.clone());
        if self.code.subs.contains_key(&id) {
            return Err(Diagnostic::error(
                DiagCode::Conflict,
                cur.span(k, e),
                format!("PROC {name} is defined twice in this file"),
            ));
        }
        let params = if cur.eat(b'(') {
            self.parameters(cur)?
        } else {
            Vec::new()
        };
        // (SAVE, DISPLOF and the other attributes after the parameters change nothing
        // threadcut follows, except SAVE: docs/dialects/sinumerik.md.)
        self.code.subs.insert(id, self.code.here());
        self.code.params.insert(id, params);
        Ok(())
    }

    /// PROC's parameters after its `(`, up to its `)`: `REAL A, INT B` (by value).
    fn parameters(&mut self, cur: &mut Cursor) -> R<Vec<u32>> {
        let mut ids = Vec::new();
        if cur.eat(b')') {
            return Ok(ids);
        }
        loop {
            let Some((kind, k, e)) = cur.peek_name() else {
                let at = cur.i;
                return Err(cur.error(at, at + 1, "a parameter expected here: REAL NAME"));
            };
            if kind == "VAR" {
                return Err(Diagnostic::error(
                    DiagCode::Unsupported,
                    cur.span(k, e),
                    "VAR: threadcut passes parameters by value only, not by reference",
                ));
            }
            if !matches!(kind.as_str(), "REAL" | "INT" | "BOOL") {
                return Err(Diagnostic::error(
                    DiagCode::Unsupported,
                    cur.span(k, e),
                    format!("{kind}: threadcut keeps REAL, INT and BOOL parameters"),
                ));
            }
            cur.i = e;
            let Some((name, _, e)) = cur.peek_name() else {
                let at = cur.i;
                return Err(cur.error(at, at + 1, "the parameter's name expected here"));
            };
            cur.i = e;
            ids.push(self.code.exprs.intern(name.clone()));
            self.unit().declared.insert(name);
            if cur.eat(b')') {
                return Ok(ids);
            }
            if !cur.eat(b',') {
                let at = cur.i;
                return Err(cur.error(at, at + 1, "`,` or `)` expected here"));
            }
        }
    }

    /// `NAME`, `NAME(a, b)`, `CALL NAME`, each with an optional repeat count `P n` / `P=n`.
    pub(super) fn call(&mut self, i: usize, cur: &mut Cursor) -> R<()> {
        let quoted = cur.eat(b'"');
        let Some((name, k, e)) = cur.peek_name() else {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "the subprogram's name expected here"));
        };
        cur.i = e;
        if quoted && !cur.eat(b'"') {
            let at = cur.i;
            return Err(cur.error(at, at + 1, "`\"` expected: CALL \"NAME\""));
        }
        let span = cur.span(k, e);
        let mut args = Vec::new();
        if cur.eat(b'(') && !cur.eat(b')') {
            loop {
                args.push(ExprReader::new(cur, &mut self.code.exprs).expr()?);
                if cur.eat(b')') {
                    break;
                }
                if !cur.eat(b',') {
                    let at = cur.i;
                    return Err(cur.error(at, at + 1, "`,` or `)` expected here"));
                }
            }
        }
        let count = self.repeat_count(cur)?;
        self.end_of_statement(cur)?;
        let id = self.code.exprs.intern(name);
        let c = self.code.calls.len() as u32;
        self.code.calls.push(Call {
            kind: CallKind::Proc,
            target: CallTarget::Name(id),
            args,
            arg_letters: Vec::new(),
            arg_no_point: Vec::new(),
            count,
            span,
        });
        self.code.emit(i, Inst::Call(c));
        Ok(())
    }

    /// `P3` or `P=R1` after a call: how many times it runs.
    fn repeat_count(&mut self, cur: &mut Cursor) -> R<Option<Expr>> {
        let Some((word, k, e)) = cur.peek_name() else {
            return Ok(None);
        };
        if word == "P" {
            cur.i = e;
            if !cur.eat(b'=') {
                let at = cur.i;
                return Err(cur.error(at, at + 1, "`=` expected: P=n"));
            }
            return ExprReader::new(cur, &mut self.code.exprs).expr().map(Some);
        }
        match word.strip_prefix('P').and_then(|d| d.parse::<u32>().ok()) {
            Some(n) => {
                cur.i = e;
                Ok(Some(self.code.exprs.number(f64::from(n), cur.span(k, e))))
            }
            None => Ok(None),
        }
    }

    /// Structures still open where a program ends: each opening statement fails.
    pub(super) fn close_structures(&mut self) {
        for o in std::mem::take(&mut self.open) {
            let word = match o.what {
                Open::If { .. } => "IF without ENDIF",
                Open::While { .. } => "WHILE without ENDWHILE",
                Open::For { .. } => "FOR without ENDFOR",
                Open::Loop { .. } => "LOOP without ENDLOOP",
                Open::Repeat { .. } => "REPEAT without UNTIL",
            };
            self.code.fail_at(o.inst, nesting(o.span, word.to_string()));
        }
    }

    /// Every jump's label, looked up in the jump's own program.
    pub(super) fn resolve_jumps(&mut self) {
        for f in std::mem::take(&mut self.fixups) {
            let lines = self.units[f.unit].labels.get(&f.label);
            let forward = || lines.and_then(|l| l.iter().find(|&&n| n > f.line)).copied();
            let backward = || {
                lines
                    .and_then(|l| l.iter().rev().find(|&&n| n <= f.line))
                    .copied()
            };
            let found = match f.direction {
                Direction::Forward => forward(),
                Direction::Backward => backward(),
                Direction::Both { .. } => forward().or_else(backward),
            };
            let target = match found {
                Some(line) => self.code.line_inst[line],
                None if f.direction == (Direction::Both { quiet: true }) => f.at + 1,
                None => {
                    let (word, label) = (f.word, &f.label);
                    let place = match f.direction {
                        Direction::Forward => "after this block",
                        Direction::Backward => "before this block",
                        Direction::Both { .. } => "anywhere",
                    };
                    let d = Diagnostic::error(
                        DiagCode::MissingWord,
                        f.span,
                        format!("{word} {label}: there is no label {label} {place} in this program (alarm 14080, jump destination not found)"),
                    )
                    .with_hint(format!("a label is written `{label}:` at the start of a block of the same program (or subprogram)"));
                    self.code.fail_at(f.at, d);
                    continue;
                }
            };
            match &mut self.code.insts[f.at as usize] {
                Inst::JumpIf { target: t, .. } | Inst::Jump(t) => *t = target,
                _ => {}
            }
        }
    }
}

/// A `REPEAT`/`REPEATB` whose section is looked up when the whole program is read.
pub(super) struct SectionFixup {
    call: u32,
    start: String,
    /// REPEAT's second label (the section's last block), if written.
    end: Option<String>,
    /// REPEATB: the one block with the label.
    single: bool,
    line: usize,
    unit: usize,
    span: Span,
    /// The word that asks for the section (REPEAT, or the cycle reading it as its contour).
    word: String,
}

/// The first instruction of text line `line`, or the end of the program after its last.
fn line_start(code: &super::super::code::Code, text: &Text, line: usize) -> u32 {
    if line < text.len() {
        code.line_inst[line]
    } else {
        code.insts.len() as u32
    }
}

impl Compiler {
    /// `REPEAT LABEL P=n` (from the label back before this block to it), `REPEAT START END P=n`
    /// (from START to END, END's block included), `REPEATB LABEL P=n` (the block with LABEL).
    fn repeat_section(&mut self, i: usize, cur: &mut Cursor, word: &str, span: Span) -> R<bool> {
        let e = cur.i;
        let (start, _) = label_word(cur, word, e)?;
        let mut end = None;
        if let Some((name, _, e)) = cur.peek_name() {
            let count_word = name == "P"
                || name
                    .strip_prefix('P')
                    .is_some_and(|d| d.parse::<u32>().is_ok());
            if !count_word {
                end = Some(name);
                cur.i = e;
            }
        }
        let count = self.repeat_count(cur)?;
        self.end_of_statement(cur)?;
        if word == "REPEATB" && end.is_some() {
            return Err(Diagnostic::error(
                DiagCode::Syntax,
                span,
                "REPEATB repeats one block: it takes one label",
            ));
        }
        let c = self.code.calls.len() as u32;
        self.code.calls.push(Call {
            kind: CallKind::Section,
            target: CallTarget::Section { first: 0, end: 0 },
            args: Vec::new(),
            arg_letters: Vec::new(),
            arg_no_point: Vec::new(),
            count,
            span,
        });
        self.code.emit(i, Inst::Call(c));
        self.sections.push(SectionFixup {
            call: c,
            start,
            end,
            single: word == "REPEATB",
            line: i,
            unit: self.units.len() - 1,
            span,
            word: "REPEAT".into(),
        });
        Ok(true)
    }

    /// After a cycle's block, the call that reads its contour (`value`, the cycle's first
    /// argument, at `span`): the subprogram `NAME`, or the section `START:END` of this program
    /// (END's block included), run as the cycle's profile.
    pub(super) fn profile_call(&mut self, i: usize, cycle: &str, value: &str, span: Span) -> R<()> {
        let c = self.code.calls.len() as u32;
        let (kind, target) = match value.split_once(':') {
            Some((start, end)) => {
                let (start, end) = (start.trim(), end.trim());
                if start.is_empty() || end.is_empty() {
                    return Err(Diagnostic::error(
                        DiagCode::Syntax,
                        span,
                        format!("{cycle}: \"{value}\" names no section: write \"START:END\", two labels of this program"),
                    ));
                }
                self.sections.push(SectionFixup {
                    call: c,
                    start: start.to_string(),
                    end: Some(end.to_string()),
                    single: false,
                    line: i,
                    unit: self.units.len() - 1,
                    span,
                    word: cycle.to_string(),
                });
                (CallKind::Section, CallTarget::Section { first: 0, end: 0 })
            }
            None if value.is_empty() => {
                return Err(Diagnostic::error(
                    DiagCode::MissingWord,
                    span,
                    format!("{cycle}: the contour's name is empty: name its subprogram, or write \"START:END\""),
                ))
            }
            None => (CallKind::Proc, CallTarget::Name(self.code.exprs.intern(value.to_string()))),
        };
        self.code.calls.push(Call {
            kind,
            target,
            args: Vec::new(),
            arg_letters: Vec::new(),
            arg_no_point: Vec::new(),
            count: None,
            span,
        });
        self.code.emit(i, Inst::Call(c));
        self.code.profiles.push(c);
        Ok(())
    }

    /// Every REPEAT's section, in its own program: the start label looked for backward (then
    /// forward), the end label forward from it.
    pub(super) fn resolve_sections(&mut self) {
        for f in std::mem::take(&mut self.sections) {
            let labels = &self.units[f.unit].labels;
            let find = |label: &str, pick: &dyn Fn(&usize) -> bool, last: bool| {
                let lines = labels.get(label)?;
                if last {
                    lines.iter().rev().find(|n| pick(n)).copied()
                } else {
                    lines.iter().find(|n| pick(n)).copied()
                }
            };
            let here = f.line;
            let start = find(&f.start, &|&n| n < here, true)
                .or_else(|| find(&f.start, &|&n| n > here, false));
            let missing = |label: &str| {
                Diagnostic::error(
                    DiagCode::MissingWord,
                    f.span,
                    format!("{}: there is no label {label} in this program (alarm 14080, jump destination not found)", f.word),
                )
            };
            let Some(start) = start else {
                self.code.fail_at(self.call_inst(f.call), missing(&f.start));
                continue;
            };
            let last = match (&f.end, f.single) {
                (Some(end), _) => match find(end, &|&n| n >= start, false) {
                    Some(n) => n,
                    None => {
                        self.code.fail_at(self.call_inst(f.call), missing(end));
                        continue;
                    }
                },
                (None, true) => start,
                (None, false) => here.saturating_sub(1),
            };
            let first = line_start(&self.code, &self.code.text, start);
            let end = line_start(&self.code, &self.code.text, last + 1);
            let call_at = self.call_inst(f.call);
            if end <= first || (first <= call_at && call_at < end) {
                let d = Diagnostic::error(
                    DiagCode::Syntax,
                    f.span,
                    format!(
                        "{0}: the section holds no block, or holds the {0} itself",
                        f.word
                    ),
                );
                self.code.fail_at(call_at, d);
                continue;
            }
            self.code.calls[f.call as usize].target = CallTarget::Section { first, end };
        }
    }

    /// The instruction of call `c`.
    fn call_inst(&self, c: u32) -> u32 {
        self.code
            .insts
            .iter()
            .position(|inst| matches!(inst, Inst::Call(k) if *k == c))
            .unwrap_or(0) as u32
    }
}

fn undeclared_here(name: &str, span: Span) -> Diagnostic {
    Diagnostic::error(
        DiagCode::MissingWord,
        span,
        format!("{name} is not an R parameter or a variable declared before (alarm 12550, name not defined)"),
    )
    .with_hint(format!("declare it with `DEF INT {name}` first"))
}
