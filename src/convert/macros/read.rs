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

/// LinuxCNC's o-word keywords.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kw {
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

/// In LinuxCNC's order of trial: a longer keyword before its prefix.
const KEYWORDS: [(&[u8], Kw); 15] = [
    (b"SUB", Kw::Sub),
    (b"ENDSUB", Kw::Endsub),
    (b"CALL", Kw::Call),
    (b"DO", Kw::Do),
    (b"WHILE", Kw::While),
    (b"REPEAT", Kw::Repeat),
    (b"IF", Kw::If),
    (b"ELSEIF", Kw::Elseif),
    (b"ELSE", Kw::Else),
    (b"ENDIF", Kw::Endif),
    (b"BREAK", Kw::Break),
    (b"CONTINUE", Kw::Continue),
    (b"ENDWHILE", Kw::Endwhile),
    (b"ENDREPEAT", Kw::Endrepeat),
    (b"RETURN", Kw::Return),
];

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

/// Reads every line of `text` in the macro language `lang`.
pub fn program(text: &[u8], lang: Lang) -> Result<Vec<Stmt>, Diagnostic> {
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
                Lang::MacroB => macro_b(&s, &mut exprs)?,
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
                out.push(String::from_utf8_lossy(&text[i + 1..close]).trim().to_string());
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
    let name = match s.at(k) {
        b'<' => read_name(s, &mut k)?,
        b'0'..=b'9' => whole_number(s, &mut k)?.to_string(),
        _ => {
            return Err(unsupported(
                s.span(at, k + 1),
                "a computed o-word name: threadcut translates o-words named by a number or <name>"
                    .into(),
            ))
        }
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
            return Err(s.error(
                *k,
                *k + 1,
                format!("`{}` cannot begin a word", c as char),
            ));
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
