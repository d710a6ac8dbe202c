//! A Sinumerik line as the front end reads it: names, numbers and operators at byte positions of
//! the line as written (blanks separate words; `;` begins a comment; parentheses are no
//! comments), and its expressions read into the program's postfix code with Sinumerik's
//! precedence, operators and functions.

use crate::diag::{Code, Diagnostic, Span};

use super::super::expr::{BinOp, Expr, Exprs, Func, Op};
use super::super::text::TextLine;

pub(super) struct Cursor<'t> {
    pub line: TextLine<'t>,
    pub i: usize,
    /// Where the block ends: its comment's `;`, or the end of the line.
    end: usize,
}

impl<'t> Cursor<'t> {
    pub fn new(line: TextLine<'t>) -> Cursor<'t> {
        Cursor {
            line,
            i: 0,
            end: block_end(line.text),
        }
    }

    /// The character at `k`, or 0 at the block's end.
    pub fn at(&self, k: usize) -> u8 {
        if k < self.end {
            self.line.text[k]
        } else {
            0
        }
    }

    pub fn blanks(&mut self) {
        while matches!(self.at(self.i), b' ' | b'\t' | b'\r' | 0x0c) {
            self.i += 1;
        }
    }

    /// Whether only blanks remain.
    pub fn done(&mut self) -> bool {
        self.blanks();
        self.i >= self.end
    }

    pub fn span(&self, from: usize, to: usize) -> Span {
        self.line.span(
            from,
            to.max(from + 1).min(self.line.text.len().max(from + 1)) - from,
        )
    }

    pub fn error(&self, from: usize, to: usize, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error(Code::Syntax, self.span(from, to), msg)
    }

    /// The name at `k` (upper case) and where it ends: letters, digits, `_`, `$`, starting with
    /// a letter, `_` or `$`.
    pub fn name_at(&self, k: usize) -> Option<(String, usize)> {
        let c = self.at(k);
        if !(c.is_ascii_alphabetic() || c == b'_' || c == b'$') {
            return None;
        }
        let mut e = k;
        while matches!(self.at(e), b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'_' | b'$') {
            e += 1;
        }
        let name = String::from_utf8_lossy(&self.line.text[k..e]).to_ascii_uppercase();
        Some((name, e))
    }

    /// The name after the blanks, without moving.
    pub fn peek_name(&mut self) -> Option<(String, usize, usize)> {
        self.blanks();
        self.name_at(self.i).map(|(n, e)| (n, self.i, e))
    }

    /// Takes `word` (a name) when it comes next.
    pub fn eat_name(&mut self, word: &str) -> bool {
        match self.peek_name() {
            Some((n, _, e)) if n == word => {
                self.i = e;
                true
            }
            _ => false,
        }
    }

    /// Takes the character `c` when it comes next.
    pub fn eat(&mut self, c: u8) -> bool {
        self.blanks();
        if self.at(self.i) == c {
            self.i += 1;
            true
        } else {
            false
        }
    }

    /// The first non-blank character from `k` on.
    pub fn next_char(&self, mut k: usize) -> (u8, usize) {
        while matches!(self.at(k), b' ' | b'\t' | b'\r' | 0x0c) {
            k += 1;
        }
        (self.at(k), k)
    }
}

/// Where a line's block ends: at its `;` outside a string.
fn block_end(text: &[u8]) -> usize {
    let mut quoted = false;
    for (k, &c) in text.iter().enumerate() {
        match c {
            b'"' => quoted = !quoted,
            b';' if !quoted => return k,
            _ => {}
        }
    }
    text.len()
}

/// An operator waiting for its right operand.
#[derive(Clone, Copy)]
enum Pending {
    Bin(BinOp),
    /// `DIV`: the quotient, its fraction cut off.
    IntDiv,
}

/// Sinumerik's priorities, highest first: `* / DIV MOD`, `+ -`, AND, XOR, OR, then the
/// comparisons (NOT binds to its operand; the bit operators are not read).
fn priority(p: Pending) -> u8 {
    use BinOp::*;
    match p {
        Pending::IntDiv | Pending::Bin(Mul | Div | Mod | Pow) => 6,
        Pending::Bin(Add | Sub) => 5,
        Pending::Bin(And) => 4,
        Pending::Bin(Xor) => 3,
        Pending::Bin(Or) => 2,
        Pending::Bin(Eq | Ne | Lt | Gt | Le | Ge) => 1,
    }
}

/// How deeply parentheses, signs and NOT may nest in one value.
const MAX_DEPTH: usize = 64;

/// Reads expressions at a cursor into a program's expressions.
pub(super) struct ExprReader<'a, 't> {
    pub c: &'a mut Cursor<'t>,
    pub exprs: &'a mut Exprs,
    depth: usize,
}

type PResult<T> = Result<T, Diagnostic>;

impl<'a, 't> ExprReader<'a, 't> {
    pub fn new(c: &'a mut Cursor<'t>, exprs: &'a mut Exprs) -> ExprReader<'a, 't> {
        ExprReader { c, exprs, depth: 0 }
    }

    /// An expression: values joined by operators, up to what cannot continue it.
    pub fn expr(&mut self) -> PResult<Expr> {
        let mark = self.exprs.mark();
        self.chain()?;
        Ok(self.exprs.since(mark))
    }

    /// Pushes the steps of an expression (to be joined with others by the caller).
    pub fn chain(&mut self) -> PResult<()> {
        let mut pending: Vec<(Pending, Span)> = Vec::new();
        self.atom()?;
        loop {
            let (c, k) = self.c.next_char(self.c.i);
            let Some((op, len)) = self.operator(c, k) else {
                break;
            };
            let span = self.c.span(k, k + len);
            self.c.i = k + len;
            while let Some(&(top, at)) = pending.last() {
                if priority(top) < priority(op) {
                    break;
                }
                self.emit(top, at);
                pending.pop();
            }
            pending.push((op, span));
            self.atom()?;
        }
        while let Some((top, at)) = pending.pop() {
            self.emit(top, at);
        }
        Ok(())
    }

    fn emit(&mut self, p: Pending, span: Span) {
        match p {
            Pending::Bin(b) => self.exprs.push(Op::Bin(b), span),
            Pending::IntDiv => {
                self.exprs.push(Op::Bin(BinOp::Div), span);
                self.exprs.push(Op::Fun(Func::Fix), span);
            }
        }
    }

    /// The binary operator at `k` (whose first character is `c`), and its length.
    fn operator(&self, c: u8, k: usize) -> Option<(Pending, usize)> {
        use BinOp::*;
        let next = self.c.at(k + 1);
        let bin = |b| Some((Pending::Bin(b), 1));
        let two = |b| Some((Pending::Bin(b), 2));
        match (c, next) {
            (b'+', _) => bin(Add),
            (b'-', _) => bin(Sub),
            (b'*', _) => bin(Mul),
            (b'/', _) => bin(Div),
            (b'=', b'=') => two(Eq),
            (b'<', b'>') => two(Ne),
            (b'<', b'=') => two(Le),
            (b'>', b'=') => two(Ge),
            (b'<', b'<') => None,
            (b'<', _) => bin(Lt),
            (b'>', _) => bin(Gt),
            _ => {
                let (name, _) = self.c.name_at(k)?;
                let op = match name.as_str() {
                    "AND" => Pending::Bin(And),
                    "OR" => Pending::Bin(Or),
                    "XOR" => Pending::Bin(Xor),
                    "MOD" => Pending::Bin(Mod),
                    "DIV" => Pending::IntDiv,
                    _ => return None,
                };
                Some((op, name.len()))
            }
        }
    }

    /// One value: a number, an R parameter, a variable, a function, `( … )`, or a sign or NOT
    /// before one of these.
    fn atom(&mut self) -> PResult<()> {
        self.depth += 1;
        let r = if self.depth > MAX_DEPTH {
            let k = self.c.i;
            Err(self.c.error(k, k + 1, "this value nests too deeply"))
        } else {
            self.atom_inner()
        };
        self.depth -= 1;
        r
    }

    fn atom_inner(&mut self) -> PResult<()> {
        self.c.blanks();
        let k = self.c.i;
        match self.c.at(k) {
            b'(' => {
                self.c.i += 1;
                self.chain()?;
                if !self.c.eat(b')') {
                    let at = self.c.i;
                    return Err(self
                        .c
                        .error(at, at + 1, "`)` expected here")
                        .with_hint(format!(
                            "the parenthesis opened at column {} is not closed",
                            k + 1
                        )));
                }
                Ok(())
            }
            c @ (b'-' | b'+') => {
                self.c.i += 1;
                self.atom()?;
                if c == b'-' {
                    self.exprs.push(Op::Neg, self.c.span(k, k + 1));
                }
                Ok(())
            }
            b'0'..=b'9' | b'.' => {
                let v = self.number()?;
                self.exprs.push(Op::Num(v), self.c.span(k, self.c.i));
                Ok(())
            }
            _ => match self.c.name_at(k) {
                Some((name, e)) => self.named(name, k, e),
                None => Err(self
                    .c
                    .error(k, k + 1, "a value was expected here")
                    .with_hint("a number, an R parameter, a DEF variable, a function or `(`")),
            },
        }
    }

    /// A number: digits with a decimal point, and Sinumerik's exponent `EX` (`1.5EX3`).
    fn number(&mut self) -> PResult<f64> {
        let from = self.c.i;
        let mut k = from;
        let mut dot = false;
        let mut digits = 0;
        loop {
            match self.c.at(k) {
                b'0'..=b'9' => digits += 1,
                b'.' if !dot => dot = true,
                _ => break,
            }
            k += 1;
        }
        if digits == 0 {
            return Err(self.c.error(from, k, "a number was expected here"));
        }
        let mut text = String::from_utf8_lossy(&self.c.line.text[from..k]).into_owned();
        if self.c.at(k).eq_ignore_ascii_case(&b'E') && self.c.at(k + 1).eq_ignore_ascii_case(&b'X')
        {
            let mut e = k + 2;
            if matches!(self.c.at(e), b'+' | b'-') {
                e += 1;
            }
            while self.c.at(e).is_ascii_digit() {
                e += 1;
            }
            text.push('e');
            text.push_str(&String::from_utf8_lossy(&self.c.line.text[k + 2..e]));
            k = e;
        }
        let v: f64 = text
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| self.c.error(from, k, "this number cannot be read"))?;
        self.c.i = k;
        Ok(v)
    }

    /// A name in a value: `R12`, `R[…]`, a function, TRUE/FALSE, NOT, or a variable.
    fn named(&mut self, name: String, k: usize, e: usize) -> PResult<()> {
        let span = self.c.span(k, e);
        if let Some(n) = r_number(&name) {
            self.c.i = e;
            self.exprs.push(Op::Num(f64::from(n)), span);
            self.exprs.push(Op::Var, span);
            return Ok(());
        }
        let (after, open) = self.c.next_char(e);
        match name.as_str() {
            "R" if after == b'[' => {
                self.c.i = open + 1;
                self.chain()?;
                if !self.c.eat(b']') {
                    let at = self.c.i;
                    return Err(self.c.error(at, at + 1, "`]` expected here"));
                }
                self.exprs.push(Op::Var, span);
                Ok(())
            }
            "NOT" => {
                self.c.i = e;
                self.atom()?;
                // NOT x: 1 where x is 0, else 0.
                self.exprs.push(Op::Num(0.0), span);
                self.exprs.push(Op::Bin(BinOp::Eq), span);
                Ok(())
            }
            "TRUE" | "FALSE" => {
                self.c.i = e;
                self.exprs
                    .push(Op::Num(if name == "TRUE" { 1.0 } else { 0.0 }), span);
                Ok(())
            }
            _ if after == b'(' => self.function(&name, span, open),
            _ if name.starts_with('$') => Err(Diagnostic::error(
                Code::Unsupported,
                span,
                format!("{name}: threadcut does not read the control's system variables"),
            )),
            _ => {
                self.c.i = e;
                let id = self.exprs.intern(name);
                self.exprs.push(Op::Named(id), span);
                Ok(())
            }
        }
    }

    /// `NAME( … )`, the `(` at `open`.
    fn function(&mut self, name: &str, span: Span, open: usize) -> PResult<()> {
        use Func::*;
        let (f, args) = match name {
            "SIN" => (Some(Sin), 1),
            "COS" => (Some(Cos), 1),
            "TAN" => (Some(Tan), 1),
            "ASIN" => (Some(Asin), 1),
            "ACOS" => (Some(Acos), 1),
            "SQRT" => (Some(Sqrt), 1),
            "ABS" => (Some(Abs), 1),
            "LN" => (Some(Ln), 1),
            "EXP" => (Some(Exp), 1),
            "TRUNC" => (Some(Fix), 1),
            "ROUND" => (Some(Round), 1),
            "POT" => (None, 1),
            "ATAN2" => (None, 2),
            _ => return Err(Diagnostic::error(
                Code::Unsupported,
                span,
                format!("{name}(…): threadcut does not evaluate this function"),
            )
            .with_hint(
                "threadcut evaluates SIN COS TAN ASIN ACOS ATAN2 SQRT ABS POT TRUNC ROUND LN EXP",
            )),
        };
        self.c.i = open + 1;
        for n in 0..args {
            if n > 0 && !self.c.eat(b',') {
                let at = self.c.i;
                return Err(self.c.error(
                    at,
                    at + 1,
                    format!("{name} takes {args} values: `,` expected"),
                ));
            }
            self.chain()?;
        }
        if !self.c.eat(b')') {
            let at = self.c.i;
            return Err(self.c.error(
                at,
                at + 1,
                format!("`)` expected: {name} takes {args} value(s)"),
            ));
        }
        match (f, name) {
            (Some(f), _) => self.exprs.push(Op::Fun(f), span),
            (None, "POT") => {
                // POT(x): the square of x.
                self.exprs.push(Op::Num(2.0), span);
                self.exprs.push(Op::Pow2, span);
            }
            _ => self.exprs.push(Op::Atan2, span),
        }
        Ok(())
    }
}

/// The number of an R parameter written `R<digits>`.
pub(super) fn r_number(name: &str) -> Option<u32> {
    let digits = name.strip_prefix('R')?;
    if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) || digits.len() > 6 {
        return None;
    }
    digits.parse().ok()
}
