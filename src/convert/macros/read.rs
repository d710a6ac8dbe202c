//! A macro program read line by line into statements, with its expressions as trees: the
//! interpreter's own scanner and expression parser read them (so a conversion reads exactly what
//! a run reads), and the trees are rebuilt here from the parser's postfix steps.

use crate::diag::{Code, Diagnostic, Span};
use crate::interp::expr::{read_name, read_number, BinOp, Exprs, Func, Lang, Op, Parser};
use crate::interp::scan::Squeezed;
use crate::interp::Text;

/// An expression, as a tree.
#[derive(Clone, Debug, PartialEq)]
pub enum Ex {
    Num(f64),
    /// A numbered variable: `#n`, or a computed number `#[…]`.
    Var(Box<Ex>),
    /// LinuxCNC's `#<name>`.
    Named(String),
    Neg(Box<Ex>),
    Bin(BinOp, Box<Ex>, Box<Ex>),
    Fun(Func, Box<Ex>),
    /// `ATAN[y]/[x]` (Fanuc also `ATAN[y,x]`).
    Atan2(Box<Ex>, Box<Ex>),
    /// Fanuc's `POW[a,b]`.
    Pow2(Box<Ex>, Box<Ex>),
    /// LinuxCNC's `EXISTS[#<name>]`.
    Exists(String),
}

/// A word of a block: its letter, a number as written or an expression, and where its letter is.
#[derive(Clone, Debug)]
pub struct Word {
    pub letter: u8,
    pub value: Val,
    /// A number written with a decimal point.
    pub dot: bool,
    pub span: Span,
}

#[derive(Clone, Debug)]
pub enum Val {
    Lit(f64),
    Expr(Ex),
}

/// A variable a statement writes.
#[derive(Clone, Debug, PartialEq)]
pub enum Var {
    Num(i64),
    Named(String),
}

/// `#n = value`.
#[derive(Clone, Debug)]
pub struct Set {
    pub var: Var,
    pub value: Ex,
    pub span: Span,
}

/// LinuxCNC's o-word keywords, in LinuxCNC's order of trial: the interpreter's own table.
pub(crate) use crate::interp::ngc::Keyword as Kw;
use crate::interp::ngc::KEYWORDS;

/// What a line is.
#[derive(Clone, Debug)]
pub enum St {
    /// Nothing but comments (or nothing).
    Blank,
    Percent,
    /// A Fanuc-style program number on its own: `O1000`.
    Header(u32),
    /// A block of words (a call, a return and the program's end are blocks too).
    Block(Vec<Word>),
    Set(Vec<Set>),
    IfGoto(Ex, u32),
    IfThen(Ex, Set),
    While(Ex, u8),
    End(u8),
    Goto(u32),
    /// A LinuxCNC o-word line.
    O {
        name: String,
        kw: Kw,
        arg: Option<Ex>,
        args: Vec<Ex>,
    },
}

/// One line, read.
#[derive(Clone, Debug)]
pub struct Stmt {
    /// The line's number in the file (1-based).
    pub number: u32,
    /// Its sequence number (`N10`), the target of a GOTO.
    pub label: Option<u32>,
    pub st: St,
    /// The line's comments, in order, without their delimiters.
    pub comments: Vec<String>,
    /// The line's statement, for errors.
    pub span: Span,
}

/// Reads every line of `text` in the macro language `syntax` describes.
pub fn program(text: &[u8], syntax: &crate::interp::Syntax) -> Result<Vec<Stmt>, Diagnostic> {
    let lang = syntax.lang;
    let text = Text::new(text.to_vec(), 1, 0);
    let mut exprs = Exprs::default();
    let mut out = Vec::with_capacity(text.len());
    for i in 0..text.len() {
        let line = text.line(i);
        let s = Squeezed::new(line)?;
        let comments = comments_of(line.text);
        let span = s.span(0, s.len());
        let (label, st) = if s.len() == 0 {
            (None, St::Blank)
        } else if s.percent {
            (None, St::Percent)
        } else if s.block_delete {
            return Err(unsupported(
                span,
                "a block-delete line (`/`) in a macro program: threadcut keeps a program's structure only for lines that always run".into(),
            ));
        } else {
            match lang {
                Lang::MacroB => match macro_b(&s, &mut exprs)? {
                    (label, St::Block(w)) if syntax.g65_operations => (label, operation(w, span)?),
                    r => r,
                },
                Lang::Ngc => ngc(&s, &mut exprs)?,
                Lang::Sinumerik => {
                    return Err(unsupported(
                        span,
                        "Sinumerik's NC language is not translated into another macro language"
                            .into(),
                    ))
                }
            }
        };
        out.push(Stmt {
            number: line.number,
            label,
            st,
            comments,
            span,
        });
    }
    Ok(out)
}

pub fn unsupported(span: Span, msg: String) -> Diagnostic {
    Diagnostic::error(Code::Unsupported, span, msg)
}

/// The comments of a line: `( … )` groups and a `;` tail.
fn comments_of(text: &[u8]) -> Vec<String> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < text.len() {
        match text[i] {
            b'(' => {
                let close = text[i + 1..]
                    .iter()
                    .position(|&c| c == b')')
                    .map_or(text.len(), |c| i + 1 + c);
                out.push(
                    String::from_utf8_lossy(&text[i + 1..close])
                        .trim()
                        .to_string(),
                );
                i = close + 1;
            }
            b';' => {
                out.push(String::from_utf8_lossy(&text[i + 1..]).trim().to_string());
                break;
            }
            _ => i += 1,
        }
    }
    out.retain(|c| !c.is_empty());
    out
}

/// A Fanuc Custom Macro B line.
fn macro_b(s: &Squeezed, exprs: &mut Exprs) -> Result<(Option<u32>, St), Diagnostic> {
    let mut k = 0;
    let mut label = None;
    if s.at(0) == b'N' && s.at(1).is_ascii_digit() {
        let (v, _, end) = read_number(s, 1, Lang::MacroB)?;
        label = Some(v as u32);
        k = end;
        if k == s.len() {
            return Ok((label, St::Blank));
        }
    }
    let lang = Lang::MacroB;
    let st = if s.at(k) == b'#' {
        St::Set(vec![set(s, &mut k, exprs, lang)?])
    } else if s.starts_with(k, b"IF[") {
        k += 2;
        let cond = tree(exprs, |p| p.bracketed(&mut k), s, lang)?;
        if s.starts_with(k, b"GOTO") {
            k += 4;
            St::IfGoto(cond, whole_number(s, &mut k)?)
        } else if s.starts_with(k, b"THEN#") {
            k += 4;
            St::IfThen(cond, set(s, &mut k, exprs, lang)?)
        } else {
            return Err(s.error(k, k + 1, "IF [condition] is followed by GOTO n or THEN"));
        }
    } else if s.starts_with(k, b"WHILE[") {
        k += 5;
        let cond = tree(exprs, |p| p.bracketed(&mut k), s, lang)?;
        if !s.starts_with(k, b"DO") {
            return Err(s.error(k, k + 1, "WHILE [condition] is followed by DOm"));
        }
        k += 2;
        St::While(cond, whole_number(s, &mut k)? as u8)
    } else if s.starts_with(k, b"END") && s.at(k + 3).is_ascii_digit() {
        k += 3;
        St::End(whole_number(s, &mut k)? as u8)
    } else if s.starts_with(k, b"GOTO") {
        k += 4;
        St::Goto(whole_number(s, &mut k)?)
    } else if s.at(k) == b'O' && s.at(k + 1).is_ascii_digit() {
        k += 1;
        St::Header(whole_number(s, &mut k)?)
    } else {
        St::Block(words(s, &mut k, exprs, lang)?.0)
    };
    if k < s.len() {
        return Err(s.error(k, s.len(), "a macro statement and NC words in one block"));
    }
    Ok((label, st))
}

/// A LinuxCNC line.
fn ngc(s: &Squeezed, exprs: &mut Exprs) -> Result<(Option<u32>, St), Diagnostic> {
    let mut k = 0;
    if s.at(0) == b'N' && s.at(1).is_ascii_digit() {
        let (_, _, end) = read_number(s, 1, Lang::Ngc)?;
        k = end;
    }
    if s.at(k) == b'O' {
        return oword(s, k, exprs).map(|st| (None, st));
    }
    let (words, sets) = words(s, &mut k, exprs, Lang::Ngc)?;
    let st = match (words.is_empty(), sets.is_empty()) {
        (_, true) => St::Block(words),
        (true, false) => St::Set(sets),
        (false, false) => {
            return Err(unsupported(
                s.span(0, s.len()),
                "parameter settings and words in one line: LinuxCNC sets the parameters after the line's words are read, which threadcut does not carry into another macro language".into(),
            )
            .with_hint("set the parameters in a line of their own"))
        }
    };
    Ok((None, st))
}

fn oword(s: &Squeezed, mut k: usize, exprs: &mut Exprs) -> Result<St, Diagnostic> {
    let at = k;
    k += 1;
    let name =
        match s.at(k) {
            b'<' => read_name(s, &mut k)?,
            b'0'..=b'9' => whole_number(s, &mut k)?.to_string(),
            _ => return Err(unsupported(
                s.span(at, k + 1),
                "a computed o-word name: threadcut translates o-words named by a number or <name>"
                    .into(),
            )),
        };
    let Some(&(word, kw)) = KEYWORDS.iter().find(|(w, _)| s.starts_with(k, w)) else {
        return Err(s.error(k, k + 1, "Unknown word starting with o"));
    };
    k += word.len();
    let lang = Lang::Ngc;
    let mut arg = None;
    let mut args = Vec::new();
    if kw == Kw::Call {
        while s.at(k) == b'[' {
            args.push(tree(exprs, |p| p.bracketed(&mut k), s, lang)?);
        }
    } else if s.at(k) == b'[' {
        arg = Some(tree(exprs, |p| p.bracketed(&mut k), s, lang)?);
    }
    if k < s.len() {
        return Err(s.error(k, s.len(), "words after an o-word"));
    }
    Ok(St::O {
        name,
        kw,
        arg,
        args,
    })
}

/// The words of a block (and LinuxCNC's parameter settings in it).
fn words(
    s: &Squeezed,
    k: &mut usize,
    exprs: &mut Exprs,
    lang: Lang,
) -> Result<(Vec<Word>, Vec<Set>), Diagnostic> {
    let mut words = Vec::new();
    let mut sets = Vec::new();
    while *k < s.len() {
        let c = s.at(*k);
        if c == b'#' && lang == Lang::Ngc {
            sets.push(set(s, k, exprs, lang)?);
            continue;
        }
        if !c.is_ascii_uppercase() {
            return Err(s.error(*k, *k + 1, format!("`{}` cannot begin a word", c as char)));
        }
        let from = *k;
        *k += 1;
        let (c1, c2) = (s.at(*k), s.at(*k + 1));
        let plain = c1.is_ascii_digit()
            || c1 == b'.'
            || (matches!(c1, b'+' | b'-') && (c2.is_ascii_digit() || c2 == b'.'));
        let mut dot = false;
        let value = if plain {
            let (v, has_dot, end) = read_number(s, *k, lang)?;
            *k = end;
            dot = has_dot;
            Val::Lit(v)
        } else {
            Val::Expr(tree(exprs, |p| p.value(k), s, lang)?)
        };
        words.push(Word {
            letter: c,
            value,
            dot,
            span: s.span(from, *k),
        });
    }
    Ok((words, sets))
}

/// `#n = value` (`#<name> = value` in LinuxCNC).
fn set(s: &Squeezed, k: &mut usize, exprs: &mut Exprs, lang: Lang) -> Result<Set, Diagnostic> {
    let from = *k;
    *k += 1;
    let var = if s.at(*k) == b'<' && lang == Lang::Ngc {
        Var::Named(read_name(s, k)?)
    } else if s.at(*k).is_ascii_digit() {
        Var::Num(whole_number(s, k)? as i64)
    } else {
        return Err(unsupported(
            s.span(from, *k + 1),
            "a variable whose number is computed (`#[…]=`, `##1=`): threadcut maps variables by their number and cannot map one known only when the program runs".into(),
        ));
    };
    if s.at(*k) != b'=' {
        return Err(s.error(*k, *k + 1, "`=` expected after the variable"));
    }
    *k += 1;
    let value = match lang {
        Lang::Ngc => tree(exprs, |p| p.value(k), s, lang)?,
        _ => tree(exprs, |p| p.bare(k), s, lang)?,
    };
    Ok(Set {
        var,
        value,
        span: s.span(from, *k),
    })
}

fn whole_number(s: &Squeezed, k: &mut usize) -> Result<u32, Diagnostic> {
    let (v, _, end) = read_number(s, *k, Lang::MacroB)?;
    if v.fract() != 0.0 || !(0.0..=99_999_999.0).contains(&v) {
        return Err(s.error(*k, end, "a whole number expected"));
    }
    *k = end;
    Ok(v as u32)
}

/// Parses with the interpreter's parser, then rebuilds the tree from its postfix steps.
fn tree(
    exprs: &mut Exprs,
    parse: impl FnOnce(&mut Parser) -> Result<crate::interp::expr::Expr, Diagnostic>,
    s: &Squeezed,
    lang: Lang,
) -> Result<Ex, Diagnostic> {
    let e = parse(&mut Parser::new(s, exprs, lang))?;
    let mut stack: Vec<Ex> = Vec::new();
    let bad = || s.error(0, s.len(), "an expression threadcut cannot rebuild");
    for (op, _) in exprs.steps(e) {
        let node = match *op {
            Op::Num(v) => Ex::Num(v),
            Op::Var => Ex::Var(Box::new(stack.pop().ok_or_else(bad)?)),
            Op::Named(i) => Ex::Named(exprs.name(i).to_string()),
            Op::Exists(i) => Ex::Exists(exprs.name(i).to_string()),
            Op::Neg => Ex::Neg(Box::new(stack.pop().ok_or_else(bad)?)),
            Op::Fun(f) => Ex::Fun(f, Box::new(stack.pop().ok_or_else(bad)?)),
            Op::Bin(b) => {
                let r = stack.pop().ok_or_else(bad)?;
                let l = stack.pop().ok_or_else(bad)?;
                Ex::Bin(b, Box::new(l), Box::new(r))
            }
            Op::Atan2 | Op::Pow2 => {
                let r = Box::new(stack.pop().ok_or_else(bad)?);
                let l = Box::new(stack.pop().ok_or_else(bad)?);
                if *op == Op::Atan2 {
                    Ex::Atan2(l, r)
                } else {
                    Ex::Pow2(l, r)
                }
            }
        };
        stack.push(node);
    }
    match (stack.pop(), stack.is_empty()) {
        (Some(e), true) => Ok(e),
        _ => Err(bad()),
    }
}

/// GSK's `G65 Hm P#i Q#j R#k` as the statement it is: a setting (H01–H05, H21, H22, H27,
/// H31–H33) or a jump (H80–H86); a block without G65 stays a block.
fn operation(words: Vec<Word>, span: Span) -> Result<St, Diagnostic> {
    let is_g65 = words
        .iter()
        .any(|w| w.letter == b'G' && matches!(w.value, Val::Lit(v) if v == 65.0));
    if !is_g65 {
        return Ok(St::Block(words));
    }
    let value = |letter: u8| {
        words
            .iter()
            .find(|w| w.letter == letter)
            .map(|w| match &w.value {
                Val::Lit(v) => Ex::Num(*v),
                Val::Expr(e) => e.clone(),
            })
    };
    let h = match value(b'H') {
        Some(Ex::Num(h)) => h as u32,
        _ => return Err(unsupported(span, "G65 without its operation H".into())),
    };
    let (j, k) = (
        value(b'Q').unwrap_or(Ex::Num(0.0)),
        value(b'R').unwrap_or(Ex::Num(0.0)),
    );
    let bin = |op: BinOp, a: Ex, b: Ex| Ex::Bin(op, Box::new(a), Box::new(b));
    let jump = |op: BinOp| -> Result<St, Diagnostic> {
        match value(b'P') {
            Some(Ex::Num(p)) => Ok(St::IfGoto(bin(op, j.clone(), k.clone()), p as u32)),
            _ => Err(unsupported(
                span,
                "a jump's P is its sequence number, written as a number".into(),
            )),
        }
    };
    let computed = match h {
        1 => j.clone(),
        2 => bin(BinOp::Add, j.clone(), k.clone()),
        3 => bin(BinOp::Sub, j.clone(), k.clone()),
        4 => bin(BinOp::Mul, j.clone(), k.clone()),
        5 => bin(BinOp::Div, j.clone(), k.clone()),
        21 => Ex::Fun(Func::Sqrt, Box::new(j.clone())),
        22 => Ex::Fun(Func::Abs, Box::new(j.clone())),
        27 => Ex::Fun(
            Func::Sqrt,
            Box::new(bin(
                BinOp::Add,
                bin(BinOp::Mul, j.clone(), j.clone()),
                bin(BinOp::Mul, k.clone(), k.clone()),
            )),
        ),
        31..=33 => {
            let f = [Func::Sin, Func::Cos, Func::Tan][(h - 31) as usize];
            bin(BinOp::Mul, j.clone(), Ex::Fun(f, Box::new(k.clone())))
        }
        80 => {
            return match value(b'P') {
                Some(Ex::Num(p)) => Ok(St::Goto(p as u32)),
                _ => Err(unsupported(span, "a jump's P is its sequence number, written as a number".into())),
            }
        }
        81 => return jump(BinOp::Eq),
        82 => return jump(BinOp::Ne),
        83 => return jump(BinOp::Gt),
        84 => return jump(BinOp::Lt),
        85 => return jump(BinOp::Ge),
        86 => return jump(BinOp::Le),
        _ => {
            return Err(unsupported(
                span,
                format!("G65 H{h:02}: threadcut translates GSK's operations H01–H05, H21, H22, H27, H31–H33 and H80–H86"),
            )
            .with_hint("--flatten writes the executed program instead"))
        }
    };
    let var = match value(b'P') {
        Some(Ex::Var(n)) => match *n {
            Ex::Num(n) => Var::Num(n as i64),
            _ => {
                return Err(unsupported(
                    span,
                    "P#i names the variable set by its number".into(),
                ))
            }
        },
        _ => {
            return Err(unsupported(
                span,
                "the operation needs P#i, the variable it sets".into(),
            ))
        }
    };
    Ok(St::Set(vec![Set {
        var,
        value: computed,
        span,
    }]))
}
