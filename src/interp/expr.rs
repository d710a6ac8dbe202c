//! Expressions: parsed once into postfix code (no recursion when they are evaluated, however long
//! an operator chain is), evaluated by one small stack machine. Both macro languages share it;
//! [`Lang`] selects where they differ (operator names and precedence, functions, vacant
//! variables, rounding and comparison rules, the controls' error texts).

use crate::diag::{Code, Diagnostic, Span};

use super::scan::Squeezed;

/// Which macro language an expression is written in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Lang {
    /// RS274/NGC (LinuxCNC): `**`, logical AND/OR/XOR at the lowest precedence, comparisons with
    /// LinuxCNC's tolerance of 1e-6, uninitialised numbered parameters read as 0.
    Ngc,
    /// Fanuc Custom Macro B (and GSK): AND with the multiplications, OR/XOR with the additions,
    /// bitwise on whole numbers; the vacant value `#0`; FIX/FUP towards/away from zero.
    MacroB,
    /// Sinumerik's NC language: R parameters and DEF variables, parentheses, `==`/`<>`, the
    /// comparisons below AND/XOR/OR (which are logical), relative equality, angles in degrees
    /// (docs/dialects/sinumerik.md, "Program flow").
    Sinumerik,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Mod,
    Pow,
    Eq,
    Ne,
    Gt,
    Ge,
    Lt,
    Le,
    And,
    Or,
    Xor,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    /// One-argument ATAN (Fanuc `ATAN[x]`).
    Atan,
    Sqrt,
    Abs,
    Exp,
    Ln,
    Round,
    Fix,
    Fup,
    Bin,
    Bcd,
}

/// One step of an expression's postfix code.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    Num(f64),
    /// A numbered variable whose number is on the stack.
    Var,
    /// A named parameter (index into the program's names) and whether it is global (`#<_x>`).
    Named(u32),
    /// `EXISTS[#<name>]`.
    Exists(u32),
    Neg,
    Bin(BinOp),
    Fun(Func),
    /// Two-argument arctangent (`ATAN[y]/[x]`).
    Atan2,
    /// Fanuc's `POW[a,b]`.
    Pow2,
}

/// An expression: a range of the program's postfix code.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Expr {
    start: u32,
    end: u32,
}

/// All expressions of a program, and the names of its named parameters.
#[derive(Default)]
pub struct Exprs {
    ops: Vec<(Op, Span)>,
    pub names: Vec<String>,
    name_index: std::collections::HashMap<String, u32>,
}

impl Exprs {
    /// The span of an expression's last step (its outermost operation, or its only value).
    pub fn span(&self, e: Expr) -> Span {
        self.ops[e.end as usize - 1].1
    }

    /// The index of a name already interned.
    pub fn find(&self, name: &str) -> Option<u32> {
        self.name_index.get(name).copied()
    }

    pub fn name(&self, i: u32) -> &str {
        &self.names[i as usize]
    }

    pub fn intern(&mut self, name: String) -> u32 {
        if let Some(&i) = self.name_index.get(&name) {
            return i;
        }
        let i = self.names.len() as u32;
        self.name_index.insert(name.clone(), i);
        self.names.push(name);
        i
    }

    /// The postfix steps of an expression, with where each was written (a conversion rebuilds
    /// the expression's tree from them).
    pub fn steps(&self, e: Expr) -> &[(Op, Span)] {
        &self.ops[e.start as usize..e.end as usize]
    }

    /// The expression's value when it is a number as written (a call's `P9010`).
    pub fn constant(&self, e: Expr) -> Option<f64> {
        match self.ops[e.start as usize..e.end as usize] {
            [(Op::Num(v), _)] => Some(v),
            _ => None,
        }
    }

    /// Where the next step goes: with [`since`](Exprs::since), an expression a front end writes
    /// step by step ([`push`](Exprs::push)).
    pub fn mark(&self) -> u32 {
        self.ops.len() as u32
    }

    pub fn push(&mut self, op: Op, span: Span) {
        self.ops.push((op, span));
    }

    /// The steps pushed since `mark`, as one expression.
    pub fn since(&self, mark: u32) -> Expr {
        Expr {
            start: mark,
            end: self.ops.len() as u32,
        }
    }

    /// A single number as an expression (for words the front ends write themselves).
    pub fn number(&mut self, v: f64, span: Span) -> Expr {
        let start = self.ops.len() as u32;
        self.ops.push((Op::Num(v), span));
        Expr {
            start,
            end: start + 1,
        }
    }
}

/// How deeply brackets may nest. Fanuc allows five levels (alarm PS0118); LinuxCNC sets no limit
/// of its own, threadcut 64 (a line nested deeper is refused rather than risk the stack).
pub fn max_nesting(lang: Lang) -> usize {
    match lang {
        Lang::Ngc => 64,
        Lang::MacroB | Lang::Sinumerik => 5,
    }
}

fn precedence(lang: Lang, op: BinOp) -> u8 {
    use BinOp::*;
    match (lang, op) {
        (_, Pow) => 6,
        (_, Mul | Div | Mod) => 5,
        (Lang::MacroB, And) => 5,
        (_, Add | Sub) => 4,
        (Lang::MacroB, Or | Xor) => 4,
        (_, Eq | Ne | Gt | Ge | Lt | Le) => 3,
        (Lang::Ngc, And | Or | Xor) => 2,
        // (Sinumerik's expressions are read by its own front end, with its own precedence.)
        (Lang::Sinumerik, And | Or | Xor) => 2,
    }
}

/// Reads expressions out of a squeezed line into a program's [`Exprs`].
pub struct Parser<'a, 's> {
    pub s: &'a Squeezed<'s>,
    pub exprs: &'a mut Exprs,
    pub lang: Lang,
    /// Brackets open.
    depth: usize,
    /// Values being read inside one another (brackets, signs, `#`).
    atoms: usize,
}

/// How deeply values may nest inside one another, brackets, signs and `#` together.
const MAX_ATOM_DEPTH: usize = 256;

type PResult<T> = Result<T, Diagnostic>;

impl<'a, 's> Parser<'a, 's> {
    pub fn new(s: &'a Squeezed<'s>, exprs: &'a mut Exprs, lang: Lang) -> Parser<'a, 's> {
        Parser {
            s,
            exprs,
            lang,
            depth: 0,
            atoms: 0,
        }
    }

    fn push(&mut self, op: Op, from: usize, to: usize) {
        let span = self.s.span(from, to);
        self.exprs.ops.push((op, span));
    }

    fn begin(&self) -> u32 {
        self.exprs.ops.len() as u32
    }

    fn done(&self, start: u32) -> Expr {
        Expr {
            start,
            end: self.exprs.ops.len() as u32,
        }
    }

    /// A bracketed expression `[ … ]` at `*i`.
    pub fn bracketed(&mut self, i: &mut usize) -> PResult<Expr> {
        let start = self.begin();
        self.bracket(i)?;
        Ok(self.done(start))
    }

    /// An expression without brackets around it, up to the end of the line or a character that
    /// cannot continue it (Fanuc's `#1=#2+1`, `#1=ATAN[1]/[2]`).
    pub fn bare(&mut self, i: &mut usize) -> PResult<Expr> {
        let start = self.begin();
        self.chain(i, None)?;
        Ok(self.done(start))
    }

    /// A word's value (what follows its letter): a number, a parameter, a bracketed expression,
    /// a sign before one of these, or (LinuxCNC) a function.
    pub fn value(&mut self, i: &mut usize) -> PResult<Expr> {
        let start = self.begin();
        self.atom(i)?;
        Ok(self.done(start))
    }

    fn bracket(&mut self, i: &mut usize) -> PResult<()> {
        let open = *i;
        if self.s.at(open) != b'[' {
            return Err(self.s.error(open, open + 1, "`[` expected"));
        }
        self.depth += 1;
        if self.depth > max_nesting(self.lang) {
            return Err(self.s.error(
                open,
                open + 1,
                match self.lang {
                    Lang::MacroB | Lang::Sinumerik => {
                        "brackets nested more than five deep (alarm PS0118)".to_string()
                    }
                    Lang::Ngc => {
                        format!("brackets nested more than {} deep", max_nesting(self.lang))
                    }
                },
            ));
        }
        *i += 1;
        self.chain(i, Some(open))?;
        self.depth -= 1;
        Ok(())
    }

    /// Values joined by binary operators (left to right within a precedence level), ending at
    /// `]` when `open` is the bracket's position, else at the end of what can be an expression.
    fn chain(&mut self, i: &mut usize, open: Option<usize>) -> PResult<()> {
        // Operators waiting for their right operand, with their positions (shunting-yard).
        let mut pending: Vec<(BinOp, usize, usize)> = Vec::new();
        self.atom(i)?;
        loop {
            let at = *i;
            let c = self.s.at(at);
            if c == b']' {
                match open {
                    Some(_) => {
                        *i += 1;
                        break;
                    }
                    None => break,
                }
            }
            if c == 0 {
                if let Some(o) = open {
                    return Err(self.unclosed(o));
                }
                break;
            }
            let Some((op, len)) = self.operator(at) else {
                if let Some(o) = open {
                    return Err(match self.lang {
                        // LinuxCNC's `read_operation`: a letter that begins one of its
                        // operator names, not followed by the rest of one, is named.
                        Lang::Ngc => match c.to_ascii_lowercase() {
                            l @ (b'a' | b'e' | b'g' | b'l' | b'm' | b'n' | b'o' | b'x') => {
                                self.s.error(
                                    at,
                                    at + 1,
                                    format!("Unknown operation name starting with {}", l as char),
                                )
                            }
                            _ => self.s.error(at, at + 1, "Unknown operation"),
                        },
                        Lang::MacroB | Lang::Sinumerik => self
                            .s
                            .error(
                                at,
                                at + 1,
                                "an operator or `]` expected here (alarm PS0114)",
                            )
                            .with_hint(format!(
                                "the expression opened at column {} is not closed here",
                                self.s.span(o, o + 1).column
                            )),
                    });
                }
                break;
            };
            *i += len;
            while let Some(&(top, from, to)) = pending.last() {
                if precedence(self.lang, top) >= precedence(self.lang, op) {
                    self.push(Op::Bin(top), from, to);
                    pending.pop();
                } else {
                    break;
                }
            }
            pending.push((op, at, at + len));
            self.atom(i)?;
        }
        while let Some((top, from, to)) = pending.pop() {
            self.push(Op::Bin(top), from, to);
        }
        Ok(())
    }

    fn unclosed(&self, open: usize) -> Diagnostic {
        match self.lang {
            Lang::Ngc => self.s.error(open, self.s.len(), "Unclosed expression"),
            Lang::MacroB | Lang::Sinumerik => self.s.error(
                open,
                self.s.len(),
                "the expression is not closed with `]` (alarm PS0114)",
            ),
        }
    }

    /// The binary operator at `at`, and how many characters it takes.
    fn operator(&self, at: usize) -> Option<(BinOp, usize)> {
        use BinOp::*;
        let s = self.s;
        Some(match s.at(at) {
            b'+' => (Add, 1),
            b'-' => (Sub, 1),
            b'/' => (Div, 1),
            b'*' if self.lang == Lang::Ngc && s.at(at + 1) == b'*' => (Pow, 2),
            b'*' => (Mul, 1),
            _ => {
                const NAMES: [(&[u8], BinOp); 10] = [
                    (b"MOD", Mod),
                    (b"AND", And),
                    (b"XOR", Xor),
                    (b"OR", Or),
                    (b"EQ", Eq),
                    (b"NE", Ne),
                    (b"GT", Gt),
                    (b"GE", Ge),
                    (b"LT", Lt),
                    (b"LE", Le),
                ];
                let (name, op) = NAMES.iter().find(|(n, _)| s.starts_with(at, n))?;
                (*op, name.len())
            }
        })
    }

    /// One value: a number, `#…`, `[…]`, a function, or a sign before one of these.
    fn atom(&mut self, i: &mut usize) -> PResult<()> {
        // Signs and `#`s nest without brackets (`--#1`, `###1`): their depth is bounded too, so
        // that no line (up to a megabyte) can exhaust the stack.
        self.atoms += 1;
        let r = if self.atoms > MAX_ATOM_DEPTH {
            Err(self.s.error(*i, *i + 1, "this value nests too deeply"))
        } else {
            self.atom_inner(i)
        };
        self.atoms -= 1;
        r
    }

    fn atom_inner(&mut self, i: &mut usize) -> PResult<()> {
        let at = *i;
        let c = self.s.at(at);
        match c {
            b'[' => self.bracket(i),
            b'#' => self.variable(i),
            b'+' | b'-' => {
                let next = self.s.at(at + 1);
                if next.is_ascii_digit() || next == b'.' {
                    self.number(i)
                } else {
                    *i += 1;
                    self.atom(i)?;
                    if c == b'-' {
                        self.push(Op::Neg, at, at + 1);
                    }
                    Ok(())
                }
            }
            b'0'..=b'9' | b'.' => self.number(i),
            b'A'..=b'Z' => self.function(i),
            0 => Err(match self.lang {
                Lang::Ngc => self
                    .s
                    .error(at, at + 1, "No characters found in reading real value"),
                Lang::MacroB | Lang::Sinumerik => {
                    self.s
                        .error(at, at + 1, "a value is missing here (alarm PS0114)")
                }
            }),
            _ => Err(match self.lang {
                Lang::Ngc => self.s.error(at, at + 1, "Bad number format"),
                Lang::MacroB | Lang::Sinumerik => self.s.error(
                    at,
                    at + 1,
                    format!("`{}` cannot start a value (alarm PS0114)", c as char),
                ),
            }),
        }
    }

    /// `[+-]digits[.digits]`, parsed exactly.
    fn number(&mut self, i: &mut usize) -> PResult<()> {
        let (v, _, end) = read_number(self.s, *i, self.lang)?;
        self.push(Op::Num(v), *i, end);
        *i = end;
        Ok(())
    }

    /// `#n`, `#[…]`, `##n`, `#<name>`.
    fn variable(&mut self, i: &mut usize) -> PResult<()> {
        let at = *i;
        *i += 1;
        if self.s.at(*i) == b'<' && self.lang == Lang::Ngc {
            let name = read_name(self.s, i)?;
            let id = self.exprs.intern(name);
            self.push(Op::Named(id), at, *i);
            return Ok(());
        }
        // The number: a value (LinuxCNC reads any real value and requires a whole number).
        match self.s.at(*i) {
            b'[' | b'#' => self.atom(i)?,
            b'0'..=b'9' => self.number(i)?,
            b'+' | b'-' if self.lang == Lang::Ngc => self.atom(i)?,
            _ => {
                return Err(match self.lang {
                    Lang::Ngc => self.s.error(at, *i + 1, "Bad number format"),
                    Lang::MacroB | Lang::Sinumerik => self.s.error(
                        at,
                        *i + 1,
                        "`#` must be followed by a variable number or `[` (alarm PS0114)",
                    ),
                })
            }
        }
        self.push(Op::Var, at, *i);
        Ok(())
    }

    /// A function: `NAME[…]`, `ATAN[…]/[…]` (and Fanuc's `ATAN[a,b]`, `POW[a,b]`), `EXISTS[#<name>]`.
    fn function(&mut self, i: &mut usize) -> PResult<()> {
        let at = *i;
        let mut end = at;
        while self.s.at(end).is_ascii_uppercase() {
            end += 1;
        }
        let name = &self.s_chars(at, end);
        use Func::*;
        let f = match name.as_slice() {
            b"SIN" => Some(Sin),
            b"COS" => Some(Cos),
            b"TAN" => Some(Tan),
            b"ASIN" => Some(Asin),
            b"ACOS" => Some(Acos),
            b"ATAN" => None,
            b"SQRT" => Some(Sqrt),
            b"ABS" => Some(Abs),
            b"EXP" => Some(Exp),
            b"LN" => Some(Ln),
            b"ROUND" => Some(Round),
            b"FIX" => Some(Fix),
            b"FUP" => Some(Fup),
            b"BIN" if self.lang == Lang::MacroB => Some(Bin),
            b"BCD" if self.lang == Lang::MacroB => Some(Bcd),
            b"EXISTS" if self.lang == Lang::Ngc => return self.exists(i, end),
            b"POW" if self.lang == Lang::MacroB => return self.pow(i, end),
            _ => {
                return Err(match self.lang {
                    Lang::Ngc => self.s.error(
                        at,
                        end.max(at + 1),
                        "Unknown word where unary operation could be",
                    ),
                    Lang::MacroB | Lang::Sinumerik => self.s.error(
                        at,
                        end.max(at + 1),
                        format!(
                            "`{}` is not a macro function (alarm PS0114)",
                            String::from_utf8_lossy(name)
                        ),
                    ),
                })
            }
        };
        if self.s.at(end) != b'[' {
            return Err(match self.lang {
                Lang::Ngc => self.s.error(
                    end,
                    end + 1,
                    "Left bracket missing after unary operation name",
                ),
                Lang::MacroB | Lang::Sinumerik => self.s.error(
                    end,
                    end + 1,
                    "`[` must follow the function's name (alarm PS0114)",
                ),
            });
        }
        *i = end;
        match f {
            Some(f) => {
                self.bracket(i)?;
                self.push(Op::Fun(f), at, end);
            }
            None => self.atan(i, at, end)?,
        }
        Ok(())
    }

    fn s_chars(&self, from: usize, to: usize) -> Vec<u8> {
        (from..to).map(|k| self.s.at(k)).collect()
    }

    /// `ATAN[y]/[x]`; on Fanuc also `ATAN[y,x]` and one-argument `ATAN[x]`.
    fn atan(&mut self, i: &mut usize, at: usize, end: usize) -> PResult<()> {
        if self.lang == Lang::MacroB && self.comma_pair(i)? {
            self.push(Op::Atan2, at, end);
            return Ok(());
        }
        self.bracket(i)?;
        if self.s.at(*i) != b'/' || self.s.at(*i + 1) != b'[' {
            if self.lang == Lang::MacroB {
                self.push(Op::Fun(Func::Atan), at, end);
                return Ok(());
            }
            return Err(if self.s.at(*i) != b'/' {
                self.s
                    .error(*i, *i + 1, "Slash missing after first atan argument")
            } else {
                self.s
                    .error(*i + 1, *i + 2, "Left bracket missing after slash with atan")
            });
        }
        *i += 1;
        self.bracket(i)?;
        self.push(Op::Atan2, at, end);
        Ok(())
    }

    /// Fanuc's `[a,b]`: two expressions separated by a comma. `Ok(false)` (nothing read) when the
    /// bracket holds no top-level comma.
    fn comma_pair(&mut self, i: &mut usize) -> PResult<bool> {
        let open = *i;
        let mut depth = 0usize;
        let mut k = open;
        let comma = loop {
            match self.s.at(k) {
                b'[' => depth += 1,
                b']' => {
                    depth -= 1;
                    if depth == 0 {
                        break None;
                    }
                }
                b',' if depth == 1 => break Some(k),
                0 => break None,
                _ => {}
            }
            k += 1;
        };
        let Some(_) = comma else { return Ok(false) };
        self.depth += 1;
        if self.depth > max_nesting(self.lang) {
            return Err(self.s.error(
                open,
                open + 1,
                "brackets nested more than five deep (alarm PS0118)",
            ));
        }
        *i = open + 1;
        self.chain_until_comma(i)?;
        if self.s.at(*i) != b',' {
            return Err(self.s.error(*i, *i + 1, "`,` expected (alarm PS0114)"));
        }
        *i += 1;
        self.chain(i, Some(open))?;
        self.depth -= 1;
        Ok(true)
    }

    /// An expression ending at a `,` (not consumed).
    fn chain_until_comma(&mut self, i: &mut usize) -> PResult<()> {
        let mut pending: Vec<(BinOp, usize, usize)> = Vec::new();
        self.atom(i)?;
        loop {
            let at = *i;
            if self.s.at(at) == b',' {
                break;
            }
            let Some((op, len)) = self.operator(at) else {
                return Err(self.s.error(at, at + 1, "`,` expected (alarm PS0114)"));
            };
            *i += len;
            while let Some(&(top, from, to)) = pending.last() {
                if precedence(self.lang, top) >= precedence(self.lang, op) {
                    self.push(Op::Bin(top), from, to);
                    pending.pop();
                } else {
                    break;
                }
            }
            pending.push((op, at, at + len));
            self.atom(i)?;
        }
        while let Some((top, from, to)) = pending.pop() {
            self.push(Op::Bin(top), from, to);
        }
        Ok(())
    }

    fn pow(&mut self, i: &mut usize, end: usize) -> PResult<()> {
        let at = *i;
        *i = end;
        if self.s.at(end) != b'[' || !self.comma_pair(i)? {
            return Err(self
                .s
                .error(at, end, "POW takes two values: POW[a,b] (alarm PS0114)"));
        }
        self.push(Op::Pow2, at, end);
        Ok(())
    }

    /// `EXISTS[#<name>]`.
    fn exists(&mut self, i: &mut usize, end: usize) -> PResult<()> {
        let at = *i;
        let mut k = end;
        if self.s.at(k) != b'[' {
            return Err(self
                .s
                .error(k, k + 1, "Left bracket missing after unary operation name"));
        }
        k += 1;
        if self.s.at(k) != b'#' || self.s.at(k + 1) != b'<' {
            return Err(self
                .s
                .error(k, k + 1, "Expected # reading parameter")
                .with_hint("EXISTS takes one named parameter: EXISTS[#<name>]"));
        }
        k += 1;
        let name = read_name(self.s, &mut k)?;
        if self.s.at(k) != b']' {
            return Err(self
                .s
                .error(k, k + 1, "Expected ] reading bracketed parameter"));
        }
        k += 1;
        let id = self.exprs.intern(name);
        self.push(Op::Exists(id), at, k);
        *i = k;
        Ok(())
    }
}

/// A number at `at`: `[+-]digits[.digits]`, with at least one digit; its value (correctly
/// rounded), whether it has a decimal point, and where it ends.
pub fn read_number(s: &Squeezed, at: usize, lang: Lang) -> PResult<(f64, bool, usize)> {
    let mut k = at;
    if matches!(s.at(k), b'+' | b'-') {
        k += 1;
    }
    let digits_from = k;
    let mut dot = false;
    let mut digits = 0;
    loop {
        match s.at(k) {
            b'0'..=b'9' => digits += 1,
            b'.' if !dot => dot = true,
            b'.' => {
                return Err(match lang {
                    Lang::Ngc => s.error(
                        at,
                        k + 1,
                        format!(
                            "bad number format (trailing characters) parsing '{}'",
                            String::from_utf8_lossy(s.source(at, k + 1))
                        ),
                    ),
                    Lang::MacroB | Lang::Sinumerik => {
                        s.error(k, k + 1, "a second decimal point (alarm PS0114)")
                    }
                })
            }
            _ => break,
        }
        k += 1;
    }
    if digits == 0 {
        return Err(match lang {
            Lang::Ngc => s.error(at, k.max(at + 1), "Bad number format"),
            Lang::MacroB | Lang::Sinumerik => {
                s.error(at, k.max(at + 1), "a number was expected (alarm PS0114)")
            }
        });
    }
    let text: String = (at..k).map(|j| s.at(j) as char).collect();
    let v: f64 = text
        .parse()
        .map_err(|_| s.error(at, k, "Bad number format"))?;
    if !v.is_finite() || (digits_from..k).count() > 400 {
        return Err(Diagnostic::error(
            Code::BadNumber,
            s.span(at, k),
            "this number is too large",
        ));
    }
    Ok((v, dot, k))
}

/// A LinuxCNC parameter name `<…>` at `*i` (blanks were already taken out; names are case
/// insensitive): the name in lower case, `*i` after the `>`.
pub fn read_name(s: &Squeezed, i: &mut usize) -> PResult<String> {
    let open = *i;
    let mut k = open + 1;
    let mut name = String::new();
    loop {
        match s.at(k) {
            b'>' => break,
            0 => return Err(s.error(open, k, "Named parameter not terminated")),
            c => name.push(c.to_ascii_lowercase() as char),
        }
        k += 1;
    }
    *i = k + 1;
    Ok(name)
}

/// Where an expression's variables come from: the interpreter's parameter storage.
pub trait Vars {
    /// The value of numbered variable `n` (already checked to be a whole number), `None` when
    /// vacant (Fanuc only).
    fn get(&mut self, n: i64, span: Span) -> Result<Option<f64>, Diagnostic>;
    /// The value of a named parameter.
    fn named(&mut self, name: u32, span: Span) -> Result<f64, Diagnostic>;
    /// Whether a named parameter exists.
    fn exists(&mut self, name: u32) -> bool;
}

/// The number a numbered variable's index expression gives: a whole number (LinuxCNC accepts
/// values within 0.0001 of one, as its `read_integer_value` does; Fanuc rounds).
pub fn whole(lang: Lang, v: Option<f64>, span: Span) -> Result<i64, Diagnostic> {
    let Some(v) = v else {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            span,
            "the variable number is vacant (alarm PS0115)",
        ));
    };
    match lang {
        Lang::Ngc => {
            let f = v.floor();
            let n = if v - f > 0.9999 {
                v.ceil()
            } else if v - f > 0.0001 {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    span,
                    "Non integer value for integer",
                ));
            } else {
                f
            };
            if n.abs() > 1e15 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    span,
                    "Parameter number out of range",
                ));
            }
            Ok(n as i64)
        }
        Lang::MacroB | Lang::Sinumerik => {
            let n = v.round();
            if n.abs() > 1e15 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    span,
                    "variable number out of range (alarm PS0115)",
                ));
            }
            Ok(n as i64)
        }
    }
}

/// What evaluation may cost: every step counts against the run's budget, so that no program
/// (however long its lines, however often they run) keeps the interpreter busy for long.
pub struct Budget {
    pub steps_left: u64,
}

impl Exprs {
    /// Evaluates `e`. `None` is Fanuc's vacant value (only [`Lang::MacroB`] has one).
    pub fn eval(
        &self,
        e: Expr,
        lang: Lang,
        vars: &mut dyn Vars,
        stack: &mut Vec<Option<f64>>,
        budget: &mut Budget,
    ) -> Result<Option<f64>, Diagnostic> {
        stack.clear();
        let ops = &self.ops[e.start as usize..e.end as usize];
        budget.steps_left = budget.steps_left.saturating_sub(ops.len() as u64);
        for &(op, span) in ops {
            let v = match op {
                Op::Num(v) => Some(v),
                Op::Var => {
                    let n = stack.pop().flatten();
                    let n = whole(lang, n, span)?;
                    vars.get(n, span)?
                }
                Op::Named(id) => Some(vars.named(id, span)?),
                Op::Exists(id) => Some(if vars.exists(id) { 1.0 } else { 0.0 }),
                Op::Neg => stack.pop().flatten().map(|v| -v).or(match lang {
                    // -#0 is vacant made negative: 0 in arithmetic, and stays vacant.
                    Lang::MacroB => None,
                    Lang::Ngc | Lang::Sinumerik => Some(0.0),
                }),
                Op::Bin(b) => {
                    let r = stack.pop().flatten();
                    let l = stack.pop().flatten();
                    binary(lang, b, l, r, span)?
                }
                Op::Fun(f) => {
                    let a = stack.pop().flatten();
                    unary(lang, f, a, span)?
                }
                Op::Atan2 => {
                    let x = stack.pop().flatten().unwrap_or(0.0);
                    let y = stack.pop().flatten().unwrap_or(0.0);
                    let deg = y.atan2(x).to_degrees();
                    Some(match lang {
                        // Fanuc (parameter NAT = 0): 0 to 360 degrees.
                        Lang::MacroB if deg < 0.0 => deg + 360.0,
                        _ => deg,
                    })
                }
                Op::Pow2 => {
                    let b = stack.pop().flatten().unwrap_or(0.0);
                    let a = stack.pop().flatten().unwrap_or(0.0);
                    if a < 0.0 && b.fract() != 0.0 {
                        return Err(argument(
                            span,
                            "POW of a negative number to a fractional power",
                        ));
                    }
                    Some(a.powf(b))
                }
            };
            if let Some(v) = v {
                check_finite(lang, v, span)?;
            }
            stack.push(v);
        }
        Ok(stack.pop().flatten())
    }
}

fn check_finite(lang: Lang, v: f64, span: Span) -> Result<(), Diagnostic> {
    if v.is_finite() {
        return Ok(());
    }
    Err(Diagnostic::error(
        Code::OutOfRange,
        span,
        match (lang, v.is_nan()) {
            (Lang::Ngc, true) => "Calculation resulted in 'not a number'",
            (Lang::Ngc, false) => "Calculation resulted in 'infinity'",
            (Lang::MacroB, _) => "calculated data overflow (alarm PS0111)",
            (Lang::Sinumerik, _) => "the calculation overflows (no finite number)",
        },
    ))
}

fn argument(span: Span, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::OutOfRange,
        span,
        format!("{what} (alarm PS0119, argument value out of range)"),
    )
}

fn binary(
    lang: Lang,
    op: BinOp,
    l: Option<f64>,
    r: Option<f64>,
    span: Span,
) -> Result<Option<f64>, Diagnostic> {
    use BinOp::*;
    let truth = |b: bool| Some(if b { 1.0 } else { 0.0 });
    // Fanuc: a vacant value is 0 in arithmetic; EQ/NE tell it from 0.
    if lang == Lang::MacroB && matches!(op, Eq | Ne) {
        let same = match (l, r) {
            (None, None) => true,
            (None, Some(_)) | (Some(_), None) => false,
            (Some(a), Some(b)) => a == b,
        };
        return Ok(truth(same == (op == Eq)));
    }
    let (a, b) = (l.unwrap_or(0.0), r.unwrap_or(0.0));
    if lang == Lang::Sinumerik {
        return sinumerik_binary(op, a, b, span).map(Some);
    }
    const TOLERANCE_EQUAL: f64 = 1e-6;
    Ok(match op {
        Add => Some(a + b),
        Sub => Some(a - b),
        Mul => Some(a * b),
        Div => {
            if b == 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    span,
                    match lang {
                        Lang::Ngc => "Attempt to divide by zero",
                        Lang::MacroB => "division by zero (alarm PS0112)",
                        Lang::Sinumerik => "division by zero (alarm 14051, arithmetic error)",
                    },
                ));
            }
            Some(a / b)
        }
        Mod => match lang {
            // LinuxCNC: fmod, made positive.
            Lang::Ngc => {
                let m = a % b;
                Some(if m < 0.0 { m + b.abs() } else { m })
            }
            // Fanuc: the remainder of the whole numbers, with the dividend's sign.
            Lang::MacroB | Lang::Sinumerik => {
                let (a, b) = (a.round(), b.round());
                if b == 0.0 {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        span,
                        "division by zero in MOD (alarm PS0112)",
                    ));
                }
                Some(a % b)
            }
        },
        Pow => {
            if a < 0.0 && b.floor() != b {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    span,
                    "Attempt to raise negative to non integer power",
                ));
            }
            Some(a.powf(b))
        }
        Eq => truth((a - b).abs() < TOLERANCE_EQUAL),
        Ne => truth((a - b).abs() >= TOLERANCE_EQUAL),
        Lt => truth(a < b),
        Gt => truth(a > b),
        Le => match lang {
            Lang::Ngc => truth((a - b).abs() < TOLERANCE_EQUAL || a <= b),
            Lang::MacroB | Lang::Sinumerik => truth(a <= b),
        },
        Ge => match lang {
            Lang::Ngc => truth((a - b).abs() < TOLERANCE_EQUAL || a >= b),
            Lang::MacroB | Lang::Sinumerik => truth(a >= b),
        },
        And | Or | Xor => match lang {
            Lang::Ngc => {
                let (p, q) = (a != 0.0, b != 0.0);
                truth(match op {
                    And => p && q,
                    Or => p || q,
                    _ => p != q,
                })
            }
            // Fanuc: bitwise on the whole numbers (on the 0 and 1 of conditions: logical).
            Lang::MacroB | Lang::Sinumerik => {
                let (p, q) = (bits(a, span)?, bits(b, span)?);
                Some(match op {
                    And => p & q,
                    Or => p | q,
                    _ => p ^ q,
                } as f64)
            }
        },
    })
}

/// Sinumerik's arithmetic on two values: MOD keeps the dividend's sign, AND/OR/XOR are logical,
/// and the comparisons test relative equality (12 significant digits: "the comparison commands
/// do not check for absolute equality, but rather for relative equality").
fn sinumerik_binary(op: BinOp, a: f64, b: f64, span: Span) -> Result<f64, Diagnostic> {
    use BinOp::*;
    let truth = |t: bool| if t { 1.0 } else { 0.0 };
    let equal = a == b || (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
    let zero = || {
        Diagnostic::error(
            Code::OutOfRange,
            span,
            "division by zero (alarm 14051, arithmetic error)",
        )
    };
    Ok(match op {
        Add => a + b,
        Sub => a - b,
        Mul => a * b,
        Div if b == 0.0 => return Err(zero()),
        Div => a / b,
        Mod if b == 0.0 => return Err(zero()),
        Mod => a % b,
        Pow => a.powf(b),
        Eq => truth(equal),
        Ne => truth(!equal),
        Lt => truth(a < b && !equal),
        Gt => truth(a > b && !equal),
        Le => truth(a < b || equal),
        Ge => truth(a > b || equal),
        And => truth(a != 0.0 && b != 0.0),
        Or => truth(a != 0.0 || b != 0.0),
        Xor => truth((a != 0.0) != (b != 0.0)),
    })
}

fn bits(v: f64, span: Span) -> Result<i64, Diagnostic> {
    let n = v.round();
    if n.abs() > 2f64.powi(31) {
        return Err(argument(
            span,
            "AND, OR and XOR work on whole numbers below 2^31",
        ));
    }
    Ok(n as i64)
}

pub(crate) fn unary(
    lang: Lang,
    f: Func,
    a: Option<f64>,
    span: Span,
) -> Result<Option<f64>, Diagnostic> {
    use Func::*;
    let x = a.unwrap_or(0.0);
    let ngc = lang == Lang::Ngc;
    let err = |ngc_msg: &str, fanuc: &str| {
        if ngc {
            Diagnostic::error(Code::OutOfRange, span, ngc_msg)
        } else if lang == Lang::Sinumerik {
            Diagnostic::error(
                Code::OutOfRange,
                span,
                format!("{fanuc} (alarm 14051, arithmetic error)"),
            )
        } else {
            argument(span, fanuc)
        }
    };
    let v = match f {
        Sin => x.to_radians().sin(),
        Cos => x.to_radians().cos(),
        Tan => x.to_radians().tan(),
        Asin => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(err(
                    "Argument to asin out of range",
                    "ASIN of a value outside -1..1",
                ));
            }
            let d = x.asin().to_degrees();
            // Fanuc (NAT = 0): 270 to 90 degrees.
            if !ngc && d < 0.0 {
                d + 360.0
            } else {
                d
            }
        }
        Acos => {
            if !(-1.0..=1.0).contains(&x) {
                return Err(err(
                    "Argument to acos out of range",
                    "ACOS of a value outside -1..1",
                ));
            }
            x.acos().to_degrees()
        }
        Atan => {
            let d = x.atan().to_degrees();
            if !ngc && d < 0.0 {
                d + 360.0
            } else {
                d
            }
        }
        Sqrt => {
            if x < 0.0 {
                return Err(err(
                    "Negative argument to sqrt",
                    "SQRT of a negative number",
                ));
            }
            x.sqrt()
        }
        Abs => x.abs(),
        Exp => x.exp(),
        Ln => {
            if x <= 0.0 {
                return Err(err(
                    "Zero or negative argument to ln",
                    "LN of zero or a negative number",
                ));
            }
            x.ln()
        }
        // Half away from zero (LinuxCNC casts x ± 0.5; Fanuc rounds off).
        Round => x.round(),
        Fix => {
            if ngc {
                x.floor()
            } else {
                x.trunc()
            }
        }
        Fup => {
            if ngc {
                x.ceil()
            } else if x < 0.0 {
                x.floor()
            } else {
                x.ceil()
            }
        }
        Bin => {
            // BCD to binary: each decimal digit of the value is a nibble.
            let n = bits(x, span)?;
            if n < 0 {
                return Err(argument(span, "BIN of a negative number"));
            }
            let (mut n, mut out, mut scale) = (n, 0i64, 1i64);
            while n > 0 {
                let d = n & 0xf;
                if d > 9 {
                    return Err(argument(span, "BIN of a value that is no BCD number"));
                }
                out += d * scale;
                scale *= 10;
                n >>= 4;
            }
            out as f64
        }
        Bcd => {
            let n = bits(x, span)?;
            if n < 0 {
                return Err(argument(span, "BCD of a negative number"));
            }
            let (mut n, mut out, mut shift) = (n, 0i64, 0);
            while n > 0 {
                out |= (n % 10) << shift;
                shift += 4;
                n /= 10;
            }
            out as f64
        }
    };
    Ok(Some(v))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::text::Text;

    struct NoVars(Vec<Option<f64>>);

    impl Vars for NoVars {
        fn get(&mut self, n: i64, span: Span) -> Result<Option<f64>, Diagnostic> {
            self.0
                .get(n as usize)
                .copied()
                .ok_or_else(|| Diagnostic::error(Code::OutOfRange, span, "no such variable"))
        }
        fn named(&mut self, _: u32, span: Span) -> Result<f64, Diagnostic> {
            Err(Diagnostic::error(Code::OutOfRange, span, "no names"))
        }
        fn exists(&mut self, _: u32) -> bool {
            false
        }
    }

    fn eval(lang: Lang, src: &str, vars: Vec<Option<f64>>) -> Result<Option<f64>, Diagnostic> {
        let t = Text::new(src.as_bytes().to_vec(), 1, 0);
        let s = Squeezed::new(t.line(0))?;
        let mut exprs = Exprs::default();
        let mut i = 0;
        let e = Parser::new(&s, &mut exprs, lang).bare(&mut i)?;
        assert_eq!(i, s.len(), "{src}: read to the end");
        let mut budget = Budget {
            steps_left: u64::MAX,
        };
        exprs.eval(e, lang, &mut NoVars(vars), &mut Vec::new(), &mut budget)
    }

    fn ngc(src: &str) -> f64 {
        eval(Lang::Ngc, src, vec![Some(0.0), Some(3.0), Some(2.0)])
            .unwrap()
            .unwrap()
    }

    fn fanuc(src: &str) -> Option<f64> {
        eval(Lang::MacroB, src, vec![None, Some(3.0), Some(2.0), None]).unwrap()
    }

    #[test]
    fn linuxcnc_precedence_is_its_documented_table() {
        // overview.adoc: [2.0 / 3 * 1.5 - 5.5 / 11.0] is 0.5.
        assert!((ngc("[2.0 / 3 * 1.5 - 5.5 / 11.0]") - 0.5).abs() < 1e-15);
        assert_eq!(ngc("[1 + 2 * 3 ** 2]"), 19.0);
        // Left to right within a level, ** too.
        assert_eq!(ngc("[2 ** 3 ** 2]"), 64.0);
        assert_eq!(ngc("[1 + 1 EQ 2 AND 3 GT 2]"), 1.0);
        assert_eq!(ngc("[-#1 * 2]"), -6.0);
        assert_eq!(ngc("[#1+2]"), 5.0);
        assert_eq!(ngc("#[1+1]"), 2.0);
        assert_eq!(ngc("##2"), 2.0);
        assert_eq!(ngc("[7 mod -3]"), 1.0);
        assert_eq!(ngc("[-7 mod 3]"), 2.0);
        assert_eq!(ngc("[fix[-2.8]]"), -3.0);
        assert_eq!(ngc("[fup[-2.8]]"), -2.0);
        assert_eq!(ngc("[round[-2.5]]"), -3.0);
        assert_eq!(ngc("[atan[1]/[-1]]"), 135.0);
        assert_eq!(ngc("[1.0000001 EQ 1]"), 1.0);
        assert_eq!(ngc("[1.0000001 GT 1]"), 1.0);
        assert_eq!(ngc("[1 LE 0.9999999]"), 1.0);
        assert!((ngc("[sin[30]]") - 0.5).abs() < 1e-15);
        assert_eq!(ngc("[sqrt[16] + abs[-2]]"), 6.0);
    }

    #[test]
    fn linuxcnc_errors_carry_its_wording_and_columns() {
        let e = eval(Lang::Ngc, "[1 / [2 - 2]]", vec![]).unwrap_err();
        assert_eq!(e.message, "Attempt to divide by zero");
        assert_eq!(e.span.column, 4);
        let e = eval(Lang::Ngc, "[sqrt[-1]]", vec![]).unwrap_err();
        assert_eq!(e.message, "Negative argument to sqrt");
        assert_eq!(
            eval(Lang::Ngc, "[1 + 2", vec![]).unwrap_err().message,
            "Unclosed expression"
        );
        assert_eq!(
            eval(Lang::Ngc, "[atan[1]]", vec![]).unwrap_err().message,
            "Slash missing after first atan argument"
        );
        assert_eq!(
            eval(Lang::Ngc, "[foo[1]]", vec![]).unwrap_err().message,
            "Unknown word where unary operation could be"
        );
        assert_eq!(
            eval(Lang::Ngc, "[#1.5]", vec![]).unwrap_err().message,
            "Non integer value for integer"
        );
        assert_eq!(
            eval(Lang::Ngc, "[[-1] ** 0.5]", vec![])
                .unwrap_err()
                .message,
            "Attempt to raise negative to non integer power"
        );
        let deep = format!("{}1{}", "[".repeat(70), "]".repeat(70));
        assert!(eval(Lang::Ngc, &deep, vec![]).is_err());
        // rs274 (LinuxCNC 2.9) names the letter an operator name could begin with.
        let e = eval(Lang::Ngc, "[2 MUL 3]", vec![]).unwrap_err();
        assert_eq!(
            (e.message.as_str(), e.span.column),
            ("Unknown operation name starting with m", 4)
        );
        assert_eq!(
            eval(Lang::Ngc, "[2 XX 3]", vec![]).unwrap_err().message,
            "Unknown operation name starting with x"
        );
        assert_eq!(
            eval(Lang::Ngc, "[2 ? 3]", vec![]).unwrap_err().message,
            "Unknown operation"
        );
    }

    #[test]
    fn fanuc_operators_functions_and_vacant_values() {
        // AND with the multiplications, OR with the additions: 1 + 2 AND 3 is 1 + (2 AND 3).
        assert_eq!(fanuc("1+2AND3"), Some(3.0));
        assert_eq!(fanuc("#1+#2*2"), Some(7.0));
        assert_eq!(fanuc("FIX[-1.2]"), Some(-1.0));
        assert_eq!(fanuc("FUP[-1.2]"), Some(-2.0));
        assert_eq!(fanuc("FUP[1.2]"), Some(2.0));
        assert_eq!(fanuc("ATAN[-1]/[-1]"), Some(225.0));
        assert_eq!(fanuc("ATAN[1,1]"), Some(45.0));
        assert_eq!(fanuc("POW[2,10]"), Some(1024.0));
        assert_eq!(fanuc("BCD[12]"), Some(18.0));
        assert_eq!(fanuc("BIN[18]"), Some(12.0));
        assert_eq!(fanuc("7MOD3"), Some(1.0));
        // Vacant: #0 and unset #3. Copying keeps it vacant; arithmetic reads it as 0.
        assert_eq!(fanuc("#0"), None);
        assert_eq!(fanuc("#3"), None);
        assert_eq!(fanuc("#3*5"), Some(0.0));
        assert_eq!(fanuc("#3+#3"), Some(0.0));
        assert_eq!(fanuc("[#3EQ#0]"), Some(1.0));
        assert_eq!(fanuc("[#3EQ0]"), Some(0.0));
        assert_eq!(fanuc("[#3GE0]"), Some(1.0));
        // Exact comparison (the manual warns of the error; threadcut adds no tolerance).
        assert_eq!(fanuc("[1.0000001EQ1]"), Some(0.0));
        let e = eval(Lang::MacroB, "#1/[#2-2]", vec![None, Some(1.0), Some(2.0)]).unwrap_err();
        assert!(e.message.contains("PS0112"), "{}", e.message);
        assert!(eval(Lang::MacroB, "[[[[[[1]]]]]]", vec![]).is_err());
        assert_eq!(
            eval(Lang::MacroB, "[[[[[1]]]]]", vec![]).unwrap(),
            Some(1.0)
        );
    }

    #[test]
    fn sinumerik_compares_by_relative_equality_and_its_logic_is_logical() {
        let span = Span::new(0, 1, 1, 1);
        let op = |b, x, y| sinumerik_binary(b, x, y, span).unwrap();
        // 0.1 + 0.2 is not 0.3 in doubles, but equal to 12 digits; 1 and 1.0000001 are not.
        assert_eq!(op(BinOp::Eq, 0.1 + 0.2, 0.3), 1.0);
        assert_eq!(op(BinOp::Ge, 0.3, 0.1 + 0.2), 1.0);
        assert_eq!(op(BinOp::Lt, 0.3, 0.1 + 0.2), 0.0);
        assert_eq!(op(BinOp::Eq, 1.0000001, 1.0), 0.0);
        assert_eq!(op(BinOp::Gt, 1.0000001, 1.0), 1.0);
        assert_eq!(op(BinOp::And, 2.0, 5.0), 1.0);
        assert_eq!(op(BinOp::Xor, 2.0, 0.0), 1.0);
        assert_eq!(op(BinOp::Mod, -7.0, 3.0), -1.0);
        assert!(sinumerik_binary(BinOp::Div, 1.0, 0.0, span).is_err());
    }

    #[test]
    fn long_chains_do_not_recurse() {
        let src = format!("[1{}]", "+1".repeat(200_000));
        assert_eq!(ngc(&src), 200_001.0);
        // Signs and `#` nest without brackets: bounded, an error rather than a stack overflow.
        for deep in [
            format!("{}1", "-".repeat(500_000)),
            format!("{}1", "#".repeat(500_000)),
            format!("{}#1", "-#".repeat(300_000)),
        ] {
            let e = eval(Lang::Ngc, &deep, vec![]).unwrap_err();
            assert_eq!(e.message, "this value nests too deeply");
            assert!(eval(Lang::MacroB, &deep, vec![]).is_err());
        }
        assert_eq!(ngc("--2"), 2.0);
    }
}
