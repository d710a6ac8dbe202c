//! A macro program's statements arranged as its structure: the main program and its
//! subprograms, each a tree of loops, conditions, calls and the lines between them. Fanuc's
//! `GOTO`s become structure where they have one: a forward `IF […] GOTO n` skips the blocks
//! before `N n` (a condition around them), a backward one to an `N n` before it repeats them (a
//! loop tested at its end); any other `GOTO` is refused at its line.

use crate::diag::{Diagnostic, Span};
use crate::interp::fanuc::argument_slots;
use crate::interp::Syntax;

use super::read::{unsupported, Ex, Kw, Set, St, Stmt, Val, Word};

/// A condition, and whether the branch runs when it does not hold.
#[derive(Clone, Debug)]
pub struct Cond {
    pub ex: Ex,
    pub negated: bool,
}

#[derive(Clone, Debug)]
pub enum Node {
    /// A line written as the conversion of its block (or its comments).
    Line(usize),
    Set(usize, Vec<Set>),
    While {
        at: usize,
        cond: Cond,
        body: Vec<Node>,
        end: usize,
    },
    /// A loop tested at its end.
    DoWhile {
        at: usize,
        body: Vec<Node>,
        cond: Cond,
        test: usize,
    },
    If {
        at: usize,
        cond: Cond,
        then: Vec<Node>,
        els: Vec<Node>,
    },
    Repeat {
        at: usize,
        count: Ex,
        body: Vec<Node>,
    },
    /// A call: the subprogram, the arguments by local variable number (#1 = 1), how many times.
    Call {
        at: usize,
        sub: String,
        args: Vec<(u8, Ex)>,
        count: Option<Ex>,
        /// Fanuc's M98: the subprogram shares the caller's local variables.
        shares_locals: bool,
    },
    Return(usize),
}

impl Node {
    /// The node's first line.
    pub fn line(&self) -> usize {
        match self {
            Node::Line(i) | Node::Set(i, _) | Node::Return(i) => *i,
            Node::While { at, .. }
            | Node::DoWhile { at, .. }
            | Node::If { at, .. }
            | Node::Repeat { at, .. }
            | Node::Call { at, .. } => *at,
        }
    }
}

/// A subprogram: its name (`1000` for O1000 or `o1000`, `N100` for a Haas local subprogram,
/// `thread` for `o<thread>`), its first and last lines and its body.
#[derive(Clone, Debug)]
pub struct Sub {
    pub name: String,
    pub at: usize,
    pub body: Vec<Node>,
    pub end: usize,
}

#[derive(Clone, Debug, Default)]
pub struct Shape {
    pub main: Vec<Node>,
    pub subs: Vec<Sub>,
}

/// The letters of words a call block may carry besides its call.
fn call_words(words: &[Word], keep: &[u8]) -> Result<(), Diagnostic> {
    match words
        .iter()
        .find(|w| !keep.contains(&w.letter) && w.letter != b'N')
    {
        Some(w) => Err(unsupported(
            w.span,
            format!(
                "`{}` in a call's block: threadcut translates a call written in a block of its own",
                w.letter as char
            ),
        )),
        None => Ok(()),
    }
}

fn lit(words: &[Word], letter: u8) -> Option<(f64, Span)> {
    words.iter().find_map(|w| match w.value {
        Val::Lit(v) if w.letter == letter => Some((v, w.span)),
        _ => None,
    })
}

fn has_code(words: &[Word], letter: u8, code: f64) -> bool {
    words
        .iter()
        .any(|w| w.letter == letter && matches!(w.value, Val::Lit(v) if v == code))
}

/// Whether a block ends the main program (M2, M30).
pub fn ends_program(st: &St) -> bool {
    matches!(st, St::Block(w) if has_code(w, b'M', 2.0) || has_code(w, b'M', 30.0))
}

/// Reads a Fanuc-style program's structure.
pub fn macro_b(stmts: &[Stmt], syntax: &Syntax) -> Result<Shape, Diagnostic> {
    let end = stmts
        .iter()
        .position(|s| ends_program(&s.st))
        .unwrap_or(stmts.len().saturating_sub(1));
    let f = Fanuc { stmts, syntax };
    let main = f.seq(0, end + 1, None)?;
    // Subprograms: each O number, and each sequence number a local call (M97) names.
    let locals: Vec<u32> = stmts
        .iter()
        .filter_map(|s| match &s.st {
            St::Block(w) if syntax.m97_local_calls && has_code(w, b'M', 97.0) => {
                lit(w, b'P').map(|(p, _)| p as u32)
            }
            _ => None,
        })
        .collect();
    let starts: Vec<(usize, String)> = (end + 1..stmts.len())
        .filter_map(|i| match (&stmts[i].st, stmts[i].label) {
            (St::Header(n), _) => Some((i, n.to_string())),
            (_, Some(n)) if locals.contains(&n) => Some((i, format!("N{n}"))),
            _ => None,
        })
        .collect();
    let mut subs = Vec::new();
    for (k, (at, name)) in starts.iter().enumerate() {
        let next = starts.get(k + 1).map_or(stmts.len(), |s| s.0);
        let Some(last) = (*at..next).rev().find(|&i| is_m99(&stmts[i].st)) else {
            return Err(unsupported(
                stmts[*at].span,
                format!("subprogram {name} has no M99 before the next one"),
            ));
        };
        // A local subprogram begins at its sequence number's line, which may hold a block.
        let label_only = matches!(stmts[*at].st, St::Blank);
        let first = if name.starts_with('N') && !label_only {
            *at
        } else {
            at + 1
        };
        let body = f.seq(first, last, None)?;
        subs.push(Sub {
            name: name.clone(),
            at: *at,
            body,
            end: last,
        });
    }
    if let Some(i) = (end + 1..stmts.len()).find(|&i| {
        !matches!(stmts[i].st, St::Blank | St::Percent)
            && !subs.iter().any(|s| (s.at..=s.end).contains(&i))
    }) {
        return Err(unsupported(
            stmts[i].span,
            format!(
                "line {} follows the program's end and belongs to no subprogram: nothing runs it",
                stmts[i].number
            ),
        ));
    }
    Ok(Shape { main, subs })
}

fn is_m99(st: &St) -> bool {
    matches!(st, St::Block(w) if has_code(w, b'M', 99.0))
}

struct Fanuc<'a> {
    stmts: &'a [Stmt],
    syntax: &'a Syntax,
}

impl Fanuc<'_> {
    /// The nodes of lines `a..b`; `looped`: the line whose loop is being read (its label is not
    /// a loop's top again).
    fn seq(&self, a: usize, b: usize, looped: Option<usize>) -> Result<Vec<Node>, Diagnostic> {
        let mut out = Vec::new();
        let mut i = a;
        while i < b {
            if let (Some(n), true) = (self.stmts[i].label, looped != Some(i)) {
                let back = (i..b)
                    .rev()
                    .find(|&k| matches!(self.stmts[k].st, St::IfGoto(_, t) if t == n));
                if let Some(k) = back {
                    let St::IfGoto(c, _) = &self.stmts[k].st else {
                        unreachable!()
                    };
                    out.push(Node::DoWhile {
                        at: i,
                        body: self.seq(i, k, Some(i))?,
                        cond: Cond {
                            ex: c.clone(),
                            negated: false,
                        },
                        test: k,
                    });
                    i = k + 1;
                    continue;
                }
            }
            i = self.one(i, b, &mut out)?;
        }
        Ok(out)
    }

    /// The statement at `i` (and what it encloses); the next line to read.
    fn one(&self, i: usize, b: usize, out: &mut Vec<Node>) -> Result<usize, Diagnostic> {
        let s = &self.stmts[i];
        match &s.st {
            St::Blank | St::Percent | St::Header(_) => out.push(Node::Line(i)),
            St::Block(words) => out.push(self.block(i, words)?),
            St::Set(sets) => out.push(Node::Set(i, sets.clone())),
            St::IfThen(c, set) => out.push(Node::If {
                at: i,
                cond: Cond {
                    ex: c.clone(),
                    negated: false,
                },
                then: vec![Node::Set(i, vec![set.clone()])],
                els: Vec::new(),
            }),
            St::While(c, m) => {
                let Some(end) =
                    (i + 1..b).find(|&k| matches!(self.stmts[k].st, St::End(e) if e == *m))
                else {
                    return Err(unsupported(
                        s.span,
                        format!("WHILE … DO{m} without its END{m} in the same program or loop"),
                    ));
                };
                out.push(Node::While {
                    at: i,
                    cond: Cond {
                        ex: c.clone(),
                        negated: false,
                    },
                    body: self.seq(i + 1, end, None)?,
                    end,
                });
                return Ok(end + 1);
            }
            St::End(m) => {
                return Err(unsupported(
                    s.span,
                    format!("END{m} without its WHILE … DO{m}"),
                ))
            }
            St::IfGoto(c, n) => {
                let Some(j) = (i + 1..b).find(|&k| self.stmts[k].label == Some(*n)) else {
                    return Err(self.other_goto(i, *n));
                };
                let cond = Cond {
                    ex: c.clone(),
                    negated: true,
                };
                // `IF [c] GOTO a … GOTO b / N a … / N b`: a condition with two branches.
                if let St::Goto(m) = self.stmts[j - 1].st {
                    if let Some(k) = (j + 1..b).find(|&k| self.stmts[k].label == Some(m)) {
                        out.push(Node::If {
                            at: i,
                            cond,
                            then: self.seq(i + 1, j - 1, None)?,
                            els: self.seq(j, k, None)?,
                        });
                        return Ok(k);
                    }
                }
                out.push(Node::If {
                    at: i,
                    cond,
                    then: self.seq(i + 1, j, None)?,
                    els: Vec::new(),
                });
                return Ok(j);
            }
            St::Goto(n) => return Err(self.other_goto(i, *n)),
            St::O { .. } => return Err(unsupported(s.span, "an o-word in a Fanuc program".into())),
        }
        Ok(i + 1)
    }

    fn other_goto(&self, i: usize, n: u32) -> Diagnostic {
        unsupported(
            self.stmts[i].span,
            format!(
                "GOTO {n} on line {} is neither a forward skip over blocks of the same loop nor a loop back to an N{n} before it: threadcut translates only those",
                self.stmts[i].number
            ),
        )
        .with_hint("--flatten writes the executed program instead")
    }

    /// A block: a call, a return, or a block to convert.
    fn block(&self, i: usize, words: &[Word]) -> Result<Node, Diagnostic> {
        let span = self.stmts[i].span;
        let number = |letter: u8| -> Result<u32, Diagnostic> {
            match lit(words, letter) {
                Some((v, _)) if v >= 0.0 && v.fract() == 0.0 => Ok(v as u32),
                _ => Err(unsupported(
                    span,
                    format!(
                        "the call needs {} as a number written in it",
                        letter as char
                    ),
                )),
            }
        };
        let count = || {
            words
                .iter()
                .find(|w| w.letter == b'L')
                .map(|w| match &w.value {
                    Val::Lit(v) => Ex::Num(*v),
                    Val::Expr(e) => e.clone(),
                })
        };
        if has_code(words, b'M', 98.0) {
            call_words(words, b"MPL")?;
            let p = number(b'P')?;
            let (sub, packed) = if p > 9999 || !self.syntax.m98_l_word {
                (
                    p % 10000,
                    (p / 10000 > 0).then_some(Ex::Num((p / 10000) as f64)),
                )
            } else {
                (p, None)
            };
            return Ok(Node::Call {
                at: i,
                sub: sub.to_string(),
                args: Vec::new(),
                count: packed.or_else(count),
                shares_locals: true,
            });
        }
        if self.syntax.m97_local_calls && has_code(words, b'M', 97.0) {
            call_words(words, b"MPL")?;
            return Ok(Node::Call {
                at: i,
                sub: format!("N{}", number(b'P')?),
                args: Vec::new(),
                count: count(),
                shares_locals: true,
            });
        }
        if has_code(words, b'G', 65.0) {
            return self.g65(i, words, number(b'P')?, count());
        }
        if has_code(words, b'M', 99.0) {
            call_words(words, b"M")?;
            return Ok(Node::Return(i));
        }
        Ok(Node::Line(i))
    }
}

impl Fanuc<'_> {
    /// `G65 P… L… arguments`: each argument to its local variable (specifications I and II).
    fn g65(&self, i: usize, words: &[Word], p: u32, count: Option<Ex>) -> Result<Node, Diagnostic> {
        if self.syntax.g65_operations {
            return Err(unsupported(
                self.stmts[i].span,
                "G65 Hm P#i Q#j R#k, a macro operation threadcut does not translate".into(),
            )
            .with_hint("--flatten writes the executed program instead"));
        }
        let arguments: Vec<&Word> = words
            .iter()
            .filter(|w| !matches!(w.letter, b'G' | b'P' | b'L' | b'N'))
            .collect();
        let letters: Vec<(u8, Span)> = arguments.iter().map(|w| (w.letter, w.span)).collect();
        let mut args = Vec::new();
        for (w, slot) in arguments.iter().zip(argument_slots(&letters)) {
            if slot == 0 {
                return Err(unsupported(
                    w.span,
                    format!("{} is not an argument of G65", w.letter as char),
                ));
            }
            let e = match &w.value {
                // M S T H D are read as whole numbers; the others in least increments.
                Val::Lit(_) if !w.dot && !b"MSTHD".contains(&w.letter) => {
                    return Err(unsupported(w.span, format!(
                        "G65's argument {} without a decimal point: Custom Macro B reads it in the machine's least input increments",
                        w.letter as char
                    )).with_hint("write the argument with its decimal point (`A1.`)"))
                }
                Val::Lit(v) => Ex::Num(*v),
                Val::Expr(e) => e.clone(),
            };
            args.retain(|(s, _): &(u8, Ex)| *s != slot);
            args.push((slot, e));
        }
        args.sort_by_key(|a| a.0);
        Ok(Node::Call {
            at: i,
            sub: p.to_string(),
            args,
            count,
            shares_locals: false,
        })
    }
}

/// Reads a LinuxCNC program's structure.
pub fn ngc(stmts: &[Stmt]) -> Result<Shape, Diagnostic> {
    let mut r = Ngc {
        stmts,
        i: 0,
        subs: Vec::new(),
    };
    let (main, _) = r.seq(None, true)?;
    Ok(Shape { main, subs: r.subs })
}

struct Ngc<'a> {
    stmts: &'a [Stmt],
    i: usize,
    subs: Vec<Sub>,
}

/// An o-word line's parts.
fn oline(st: &St) -> Option<(&str, Kw, Option<&Ex>, &[Ex])> {
    match st {
        St::O {
            name,
            kw,
            arg,
            args,
        } => Some((name, *kw, arg.as_ref(), args)),
        _ => None,
    }
}

impl Ngc<'_> {
    /// Lines until an o-word that closes `open` (its name): that line's index, or the end of the
    /// file at the top level.
    fn seq(&mut self, open: Option<&str>, top: bool) -> Result<(Vec<Node>, usize), Diagnostic> {
        let mut out = Vec::new();
        while self.i < self.stmts.len() {
            let i = self.i;
            let s = &self.stmts[i];
            let Some((name, kw, arg, args)) = oline(&s.st) else {
                out.push(match &s.st {
                    St::Set(sets) => Node::Set(i, sets.clone()),
                    _ => Node::Line(i),
                });
                self.i += 1;
                continue;
            };
            let closes = matches!(
                kw,
                Kw::Endsub | Kw::Endwhile | Kw::Endif | Kw::Else | Kw::Elseif | Kw::Endrepeat
            ) || (kw == Kw::While && open == Some(name) && self.closing_do(name));
            if closes {
                if open != Some(name) {
                    return Err(unsupported(
                        s.span,
                        format!("o{name} closes a construct that is not open"),
                    ));
                }
                return Ok((out, i));
            }
            self.i += 1;
            let node = self.construct(i, name, kw, arg, args, top)?;
            out.extend(node);
        }
        match open {
            Some(name) => Err(unsupported(
                self.stmts.last().map_or(Span::default(), |s| s.span),
                format!("o{name} is not closed"),
            )),
            None => Ok((out, self.stmts.len())),
        }
    }

    /// Whether the `while` of `name` ends a `do` (rather than opening a loop): the `do` of that
    /// name is what is open.
    fn closing_do(&self, name: &str) -> bool {
        (0..self.i)
            .rev()
            .find_map(|k| match oline(&self.stmts[k].st) {
                Some((n, Kw::Do, ..)) if n == name => Some(true),
                Some((n, Kw::While, ..)) if n == name => Some(false),
                _ => None,
            })
            == Some(true)
    }

    fn cond(&self, i: usize, arg: Option<&Ex>) -> Result<Cond, Diagnostic> {
        match arg {
            Some(e) => Ok(Cond {
                ex: e.clone(),
                negated: false,
            }),
            None => Err(unsupported(
                self.stmts[i].span,
                "a condition `[…]` expected".into(),
            )),
        }
    }

    /// The construct an o-word opens (or a call, a return).
    fn construct(
        &mut self,
        i: usize,
        name: &str,
        kw: Kw,
        arg: Option<&Ex>,
        args: &[Ex],
        top: bool,
    ) -> Result<Option<Node>, Diagnostic> {
        let span = self.stmts[i].span;
        Ok(Some(match kw {
            Kw::Sub => {
                if !top {
                    return Err(unsupported(
                        span,
                        "a subroutine defined inside another construct".into(),
                    ));
                }
                self.sub(i, name)?;
                return Ok(None);
            }
            Kw::While => {
                let cond = self.cond(i, arg)?;
                let (body, end) = self.seq(Some(name), false)?;
                self.close(end, Kw::Endwhile)?;
                Node::While {
                    at: i,
                    cond,
                    body,
                    end,
                }
            }
            Kw::Do => {
                let (body, test) = self.seq(Some(name), false)?;
                self.close(test, Kw::While)?;
                let cond = self.cond(test, self.stmts[test].st_arg())?;
                Node::DoWhile {
                    at: i,
                    body,
                    cond,
                    test,
                }
            }
            Kw::If => self.if_chain(i, name, arg)?,
            Kw::Repeat => {
                let count = self.cond(i, arg)?.ex;
                let (body, end) = self.seq(Some(name), false)?;
                self.close(end, Kw::Endrepeat)?;
                Node::Repeat { at: i, count, body }
            }
            Kw::Call => Node::Call {
                at: i,
                sub: name.to_string(),
                args: args
                    .iter()
                    .enumerate()
                    .map(|(k, e)| ((k + 1) as u8, e.clone()))
                    .collect(),
                count: None,
                shares_locals: false,
            },
            Kw::Return if arg.is_none() => Node::Return(i),
            Kw::Return => return Err(unsupported(
                span,
                "return with a value: a subroutine's return value has no twin in Custom Macro B"
                    .into(),
            )),
            Kw::Break | Kw::Continue => {
                return Err(unsupported(
                    span,
                    format!(
                        "o{name} {}: threadcut does not translate break and continue yet",
                        if kw == Kw::Break { "break" } else { "continue" }
                    ),
                )
                .with_hint("--flatten writes the executed program instead"))
            }
            _ => {
                return Err(unsupported(
                    span,
                    format!("o{name} closes a construct that is not open"),
                ))
            }
        }))
    }

    /// A subroutine's definition, to its `endsub`.
    fn sub(&mut self, i: usize, name: &str) -> Result<(), Diagnostic> {
        let (body, end) = self.seq(Some(name), false)?;
        self.close(end, Kw::Endsub)?;
        if self.stmts[end].st_arg().is_some() {
            return Err(unsupported(
                self.stmts[end].span,
                "endsub with a value: a subroutine's return value has no twin in Custom Macro B"
                    .into(),
            ));
        }
        self.subs.push(Sub {
            name: name.to_string(),
            at: i,
            body,
            end,
        });
        Ok(())
    }

    /// `if`, its `elseif`s and `else`, to `endif`.
    fn if_chain(&mut self, i: usize, name: &str, arg: Option<&Ex>) -> Result<Node, Diagnostic> {
        let cond = self.cond(i, arg)?;
        let (then, at) = self.seq(Some(name), false)?;
        self.i = at + 1;
        let els = match oline(&self.stmts[at].st).map(|o| o.1) {
            Some(Kw::Endif) => Vec::new(),
            Some(Kw::Else) => {
                let (els, end) = self.seq(Some(name), false)?;
                self.close(end, Kw::Endif)?;
                els
            }
            Some(Kw::Elseif) => {
                let arg = self.stmts[at].st_arg();
                vec![self.if_chain(at, name, arg)?]
            }
            _ => {
                return Err(unsupported(
                    self.stmts[at].span,
                    format!("o{name} if is closed by another o-word"),
                ))
            }
        };
        Ok(Node::If {
            at: i,
            cond,
            then,
            els,
        })
    }

    /// The line `end` must be `kw`; reading goes on after it.
    fn close(&mut self, end: usize, kw: Kw) -> Result<(), Diagnostic> {
        match oline(&self.stmts[end].st) {
            Some((_, k, ..)) if k == kw => {
                self.i = end + 1;
                Ok(())
            }
            _ => Err(unsupported(
                self.stmts[end].span,
                "this o-word closes another construct".into(),
            )),
        }
    }
}

impl Stmt {
    /// An o-word line's bracketed value.
    fn st_arg(&self) -> Option<&Ex> {
        oline(&self.st).and_then(|o| o.2)
    }
}

/// Every line of `nodes` written as a block's conversion.
pub fn walk(nodes: &[Node], out: &mut Vec<usize>) {
    for n in nodes {
        match n {
            Node::Line(i) => out.push(*i),
            Node::While { body, .. } | Node::DoWhile { body, .. } | Node::Repeat { body, .. } => {
                walk(body, out)
            }
            Node::If { then, els, .. } => {
                walk(then, out);
                walk(els, out)
            }
            _ => {}
        }
    }
}
