//! A macro program's structure written in the target's macro language: variables mapped by
//! number (named and unmatched ones to free common variables, said at the top), expressions in
//! the target's syntax, loops, conditions, subprograms and calls in the target's forms, and each
//! block as its conversion's text ([`super::fit`]).

use std::collections::{BTreeMap, BTreeSet, HashMap};

use crate::diag::{Diagnostic, Span};
use crate::interp::expr::{BinOp, Func, Lang};
use crate::interp::Syntax;

use super::fit::Piece;
use super::read::{unsupported, Ex, Set, St, Stmt, Var};
use super::shape::{Cond, Node, Shape, Sub};

/// What the writer needs besides the structure.
pub struct Emit<'a> {
    pub stmts: &'a [Stmt],
    pub from: Lang,
    pub to: Lang,
    from_syntax: Syntax,
    to_syntax: Syntax,
    /// Whether each side's position variable reads X as a diameter (Custom Macro B's #5001 on a
    /// diameter machine; LinuxCNC's #5420 is the radius).
    diameters: (bool, bool),
    /// Each run line's converted text, as pieces.
    pub blocks: &'a super::Blocks,
    /// A comment in the target's style.
    pub comment: &'a dyn Fn(&str) -> String,
    vars: BTreeMap<String, String>,
    notes: Vec<String>,
    used: BTreeSet<i64>,
    labels: u32,
    used_labels: BTreeSet<u32>,
    /// Subprogram names in the target.
    subs: BTreeMap<(String, Option<u32>), String>,
    /// The subprograms written once for each call: the calls' lines.
    copies: HashMap<String, Vec<u32>>,
    /// The call whose copy of a subprogram is being written.
    copy: Option<u32>,
    /// Each subprogram's first and last lines.
    ranges: BTreeMap<String, (usize, usize)>,
    out: String,
    depth: usize,
    /// WHILE loops open (Fanuc's DO numbers).
    loops: u8,
    /// The subprogram being written.
    current: Option<String>,
}

/// Common variables both languages have, in the order they are taken for a name.
fn commons() -> impl Iterator<Item = i64> {
    (500..=999).chain(100..=199)
}

impl<'a> Emit<'a> {
    pub fn new(
        stmts: &'a [Stmt],
        from_syntax: Syntax,
        to_syntax: Syntax,
        blocks: &'a super::Blocks,
        comment: &'a dyn Fn(&str) -> String,
        diameters: (bool, bool),
    ) -> Emit<'a> {
        let mut used = BTreeSet::new();
        let mut used_labels = BTreeSet::new();
        for s in stmts {
            used_labels.extend(s.label);
            collect_numbers(&s.st, &mut used);
        }
        Emit {
            stmts,
            from: from_syntax.lang,
            to: to_syntax.lang,
            from_syntax,
            to_syntax,
            diameters: (
                diameters.0 && from_syntax.lang == Lang::MacroB,
                diameters.1 && to_syntax.lang == Lang::MacroB,
            ),
            blocks,
            comment,
            vars: BTreeMap::new(),
            notes: Vec::new(),
            used,
            labels: 0,
            used_labels,
            subs: BTreeMap::new(),
            copies: HashMap::new(),
            copy: None,
            ranges: BTreeMap::new(),
            out: String::new(),
            depth: 0,
            loops: 0,
            current: None,
        }
    }

    /// The whole program.
    pub fn program(
        mut self,
        shape: &Shape,
        copies: &HashMap<String, Vec<u32>>,
    ) -> Result<String, Diagnostic> {
        self.copies = copies.clone();
        self.name_subs(shape)?;
        // The lines that begin the main program (`%`, its number, comments) stay first.
        let lead = shape
            .main
            .iter()
            .take_while(|n| matches!(n, Node::Line(i) if matches!(self.stmts[*i].st, St::Blank | St::Percent | St::Header(_))))
            .count();
        let (head, rest) = shape.main.split_at(lead);
        self.nodes(head)?;
        let head_text = std::mem::take(&mut self.out);
        let percent = head
            .iter()
            .any(|n| matches!(n, Node::Line(i) if matches!(self.stmts[*i].st, St::Percent)));
        if self.to == Lang::Ngc {
            for s in &shape.subs {
                self.sub(s)?;
            }
            self.nodes(rest)?;
        } else {
            self.nodes(rest)?;
            for s in &shape.subs {
                self.sub(s)?;
            }
        }
        let mut text = head_text;
        for n in &self.notes {
            text.push_str(&(self.comment)(n));
            text.push('\n');
        }
        text.push_str(&self.out);
        if percent {
            let first = head
                .iter()
                .find_map(|n| match n {
                    Node::Line(i) if matches!(self.stmts[*i].st, St::Percent) => {
                        self.blocks.get(&(*i, None)).map(|p| pieces_plain(p))
                    }
                    _ => None,
                })
                .unwrap_or_else(|| "%\n".into());
            text.push_str(&first);
        }
        Ok(text)
    }

    fn name_subs(&mut self, shape: &Shape) -> Result<(), Diagnostic> {
        // The numbers taken: the subprograms' and every program number the text holds.
        let mut numbers: BTreeSet<u32> = shape
            .subs
            .iter()
            .filter_map(|s| s.name.parse().ok())
            .collect();
        numbers.extend(self.stmts.iter().filter_map(|s| match s.st {
            St::Header(n) => Some(n),
            _ => None,
        }));
        let mut free = (1000..9000).filter(|n| !numbers.contains(n));
        for s in &shape.subs {
            let first = match (self.to, s.name.parse::<u32>()) {
                (Lang::Ngc, Ok(n)) => Some(n.to_string()),
                (Lang::Ngc, Err(_)) => Some(match s.name.strip_prefix('N') {
                    Some(n) if !numbers.contains(&n.parse().unwrap_or(0)) => n.to_string(),
                    _ => format!("<{}>", s.name.to_ascii_lowercase()),
                }),
                (_, Ok(n)) if n <= 9999 => Some(n.to_string()),
                _ => None,
            };
            let copies: Vec<Option<u32>> = match self.copies.get(&s.name) {
                Some(callers) => callers.iter().map(|c| Some(*c)).collect(),
                None => vec![None],
            };
            for (k, copy) in copies.into_iter().enumerate() {
                let name = match (&first, k) {
                    (Some(n), 0) => n.clone(),
                    _ => free.next().map(|n| n.to_string()).ok_or_else(|| {
                        unsupported(self.stmts[s.at].span, "no free program number".into())
                    })?,
                };
                self.subs.insert((s.name.clone(), copy), name);
            }
            self.ranges.insert(s.name.clone(), (s.at, s.end));
        }
        Ok(())
    }

    fn line(&mut self, text: &str, at: Option<usize>) {
        let mut parts: Vec<String> = Vec::new();
        if let Some(i) = at {
            parts.extend(self.stmts[i].comments.iter().map(|c| (self.comment)(c)));
        }
        // LinuxCNC leaves a comment on an o-word's line undefined (o-code.adoc): it goes on the
        // line before.
        let oword = text.starts_with('o') && self.to == Lang::Ngc;
        if oword && !parts.is_empty() {
            self.out.push_str(&"  ".repeat(self.depth));
            self.out.push_str(&parts.join(" "));
            self.out.push('\n');
            parts.clear();
        }
        if !text.is_empty() {
            parts.insert(0, text.to_string());
        }
        if self.to == Lang::Ngc && !parts.is_empty() {
            self.out.push_str(&"  ".repeat(self.depth));
        }
        self.out.push_str(&parts.join(" "));
        self.out.push('\n');
    }

    /// The nodes in order; an error without a place (an expression's) is put at its node's
    /// line.
    fn nodes(&mut self, nodes: &[Node]) -> Result<(), Diagnostic> {
        for n in nodes {
            self.node(n).map_err(|mut d| {
                if d.span.line == 0 {
                    d.span = self.stmts[n.line()].span;
                }
                d
            })?;
        }
        Ok(())
    }

    fn node(&mut self, n: &Node) -> Result<(), Diagnostic> {
        match n {
            Node::Line(i) => self.block(*i),
            Node::Set(i, sets) => {
                let texts = sets
                    .iter()
                    .map(|s| self.set(s))
                    .collect::<Result<Vec<_>, _>>()?;
                self.line(&texts.join(" "), Some(*i));
                Ok(())
            }
            Node::While {
                at,
                cond,
                body,
                end,
            } => self.while_loop(*at, cond, body, *end),
            Node::DoWhile {
                at,
                body,
                cond,
                test,
            } => self.do_while(*at, body, cond, *test),
            Node::If {
                at,
                cond,
                then,
                els,
            } => self.if_node(*at, cond, then, els),
            Node::Repeat { at, count, body } => self.repeat(*at, count, body),
            Node::Call { .. } => self.call(n),
            Node::Return(i) => {
                let text = match (&self.current, self.to) {
                    (Some(s), Lang::Ngc) => format!("o{s} return"),
                    _ => "M99".to_string(),
                };
                self.line(&text, Some(*i));
                Ok(())
            }
        }
    }

    /// A line's converted text (or its comments, for a line with nothing to run).
    fn block(&mut self, i: usize) -> Result<(), Diagnostic> {
        let s = &self.stmts[i];
        if let Some(pieces) = self
            .blocks
            .get(&(i, self.copy))
            .or_else(|| self.blocks.get(&(i, None)))
        {
            let mut text = String::new();
            for p in pieces {
                match p {
                    Piece::Text(t) => text.push_str(t),
                    Piece::Expr { ex, a, b } => text.push_str(&self.scaled(ex, *a, *b)?),
                }
            }
            let indent = if self.to == Lang::Ngc {
                "  ".repeat(self.depth)
            } else {
                String::new()
            };
            for l in text.lines() {
                self.out.push_str(&indent);
                self.out.push_str(l);
                self.out.push('\n');
            }
            return Ok(());
        }
        match &s.st {
            // A sequence number's line of its own: the structure took its place.
            St::Blank if s.comments.is_empty() && s.label.is_some() && self.to == Lang::Ngc => {
                Ok(())
            }
            St::Blank | St::Header(_) if s.comments.is_empty() && s.label.is_none() => {
                self.out.push('\n');
                Ok(())
            }
            St::Blank | St::Header(_) => {
                if let (Some(n), Lang::MacroB) = (s.label, self.to) {
                    self.line(&format!("N{n}"), Some(i));
                } else {
                    let c: Vec<String> = s.comments.iter().map(|c| (self.comment)(c)).collect();
                    let t = c.join(" ");
                    self.line(&t, None);
                }
                Ok(())
            }
            St::Percent => Ok(()),
            _ => Err(unsupported(
                s.span,
                format!(
                    "line {} never runs in this program, so threadcut cannot convert it and verify it: it converts only the blocks a run reaches",
                    s.number
                ),
            )
            .with_hint("--flatten writes the executed program instead")),
        }
    }

    /// `a·expression + b` in the target's syntax, as a word's value.
    fn scaled(&mut self, ex: &Ex, a: f64, b: f64) -> Result<String, Diagnostic> {
        // A radius doubled back to the diameter it was halved from: `[#1/2]` × 2 is `#1`.
        if let (2.0, Ex::Bin(BinOp::Div, inner, two)) = (a, ex) {
            if **two == Ex::Num(2.0) {
                return self.scaled(inner, 1.0, b);
            }
        }
        let e = self.ex(ex)?;
        let simple = matches!(ex, Ex::Var(_) | Ex::Named(_) | Ex::Num(_));
        let mut t = match a {
            1.0 if simple => e,
            1.0 => format!("[{e}]"),
            0.5 => format!("[{}/2]", self.operand(ex)?),
            _ => format!("[{}*{}]", self.operand(ex)?, num(a)),
        };
        if b != 0.0 {
            let inner = t
                .strip_prefix('[')
                .and_then(|t| t.strip_suffix(']'))
                .map(str::to_string);
            let base = if a == 1.0 && !simple {
                self.operand(ex)?
            } else {
                inner.unwrap_or(t)
            };
            t = if b > 0.0 {
                format!("[{base}+{}]", num(b))
            } else {
                format!("[{base}-{}]", num(-b))
            };
        }
        Ok(t)
    }

    fn set(&mut self, s: &Set) -> Result<String, Diagnostic> {
        let v = self.var(&s.var, s.span)?;
        let e = self.ex(&s.value)?;
        Ok(match self.to {
            Lang::Ngc => {
                let e = if matches!(s.value, Ex::Bin(..) | Ex::Pow2(..)) {
                    format!("[{e}]")
                } else {
                    e
                };
                format!("{v} = {e}")
            }
            _ => format!("{v}={e}"),
        })
    }

    /// A variable in the target's numbering.
    fn var(&mut self, v: &Var, span: Span) -> Result<String, Diagnostic> {
        let (key, shown) = match v {
            Var::Num(n) => {
                if let Some(t) = self.twin(*n, span)? {
                    return Ok(t);
                }
                (format!("#{n}"), format!("#{n}"))
            }
            Var::Named(name) if self.to == Lang::Ngc => return Ok(format!("#<{name}>")),
            Var::Named(name) => (format!("#<{name}>"), format!("#<{name}>")),
        };
        if let Some(t) = self.vars.get(&key) {
            return Ok(t.clone());
        }
        let Some(n) = commons().find(|n| !self.used.contains(n)) else {
            return Err(unsupported(
                span,
                format!("no free common variable for {shown}"),
            ));
        };
        self.used.insert(n);
        let t = format!("#{n}");
        self.notes.push(format!("{shown} IS {t}"));
        self.vars.insert(key, t.clone());
        Ok(t)
    }

    /// The target's variable of the same number, `None` when it must be given a free common
    /// variable, an error when it has none.
    fn twin(&self, n: i64, span: Span) -> Result<Option<String>, Diagnostic> {
        let same = Ok(Some(format!("#{n}")));
        let wide = |s: &Syntax| s.lang == Lang::MacroB && s.wide_commons;
        if let Some(axis) = position_axis(self.from, n) {
            return Ok(Some(self.position(axis)));
        }
        match (self.from, self.to, n) {
            (_, _, 1..=30 | 100..=199 | 500..=999) => same,
            // Within Custom Macro B every number is the same variable, but for the wide commons
            // of a control that has them.
            (Lang::MacroB, Lang::MacroB, 10000..=10999) if wide(&self.to_syntax) => same,
            (Lang::MacroB, Lang::MacroB, 10000..=10999) => Ok(None),
            (Lang::MacroB, Lang::MacroB, _) => same,
            (Lang::MacroB, _, 31..=33) => Err(unsupported(span, format!("#{n}, a local variable of Custom Macro B: LinuxCNC's subroutine parameters are #1–#30"))),
            (Lang::MacroB, _, 10000..=10999) if wide(&self.from_syntax) => Ok(None),
            (Lang::Ngc, _, 31..=5000) => Ok(None),
            (Lang::MacroB, _, 0) => Err(unsupported(span, "#0, the vacant value: LinuxCNC has no vacant value (its unset parameters read 0)".into())),
            _ => Err(unsupported(span, format!("#{n}, a system variable: threadcut translates only the variables a program keeps its values in"))),
        }
    }

    /// The target's variable of the tool's position on an axis (0: X, 1: Z), scaled where the
    /// two read X differently: Custom Macro B's #5001/#5002 (X as the program writes it, Z) and
    /// LinuxCNC's #5420/#5422 (X as a radius, Z).
    fn position(&self, axis: usize) -> String {
        let var = match (self.to, axis) {
            (Lang::Ngc, 0) => "#5420",
            (Lang::Ngc, _) => "#5422",
            (_, 0) => "#5001",
            _ => "#5002",
        };
        match (axis, self.diameters) {
            (0, (true, false)) => format!("[{var}*2]"),
            (0, (false, true)) => format!("[{var}/2]"),
            _ => var.to_string(),
        }
    }

    fn ex(&mut self, e: &Ex) -> Result<String, Diagnostic> {
        let span = Span::default();
        Ok(match e {
            Ex::Num(v) => num(*v),
            Ex::Var(n) => match &**n {
                Ex::Num(v) if v.fract() == 0.0 => self.var(&Var::Num(*v as i64), span)?,
                _ => return Err(unsupported(span, "a variable whose number is computed (`#[…]`): threadcut maps variables by their number and cannot map one known only when the program runs".into())),
            },
            Ex::Named(name) => self.var(&Var::Named(name.clone()), span)?,
            Ex::Neg(x) => format!("-{}", self.operand(x)?),
            Ex::Bin(op, l, r) => self.binary(*op, l, r)?,
            Ex::Fun(f, x) => self.function(*f, x)?,
            Ex::Atan2(y, x) => format!("ATAN[{}]/[{}]", self.ex(y)?, self.ex(x)?),
            Ex::Pow2(a, b) => self.binary(BinOp::Pow, a, b)?,
            Ex::Exists(name) => {
                return Err(unsupported(span, format!("EXISTS[#<{name}>]: Custom Macro B has no test whether a variable exists")))
            }
        })
    }

    /// An operand of `op`: bracketed when it is an operation that binds less tightly (or as
    /// tightly, on the right), or a comparison or logical operation.
    fn side(&mut self, op: BinOp, e: &Ex, right: bool) -> Result<String, Diagnostic> {
        let arithmetic = |o: BinOp| match o {
            BinOp::Mul | BinOp::Div => Some(5),
            BinOp::Add | BinOp::Sub => Some(4),
            _ => None,
        };
        if let (Ex::Bin(inner, ..), Some(p)) = (e, arithmetic(op)) {
            if let Some(q) = arithmetic(*inner) {
                if q > p || (q == p && !right) {
                    return self.ex(e);
                }
            }
        }
        self.operand(e)
    }

    /// An expression as an operand: bracketed unless it is one value.
    fn operand(&mut self, e: &Ex) -> Result<String, Diagnostic> {
        let t = self.ex(e)?;
        Ok(match e {
            Ex::Bin(..) | Ex::Neg(_) | Ex::Pow2(..) => format!("[{t}]"),
            _ => t,
        })
    }

    fn binary(&mut self, op: BinOp, l: &Ex, r: &Ex) -> Result<String, Diagnostic> {
        let (a, b) = (self.side(op, l, false)?, self.side(op, r, true)?);
        use BinOp::*;
        let name = match op {
            Add => "+",
            Sub => "-",
            Mul => "*",
            Div => "/",
            Pow if self.to == Lang::Ngc => "**",
            Pow => return Ok(format!("POW[{},{}]", self.ex(l)?, self.ex(r)?)),
            Mod => " MOD ",
            Eq => " EQ ",
            Ne => " NE ",
            Gt => " GT ",
            Ge => " GE ",
            Lt => " LT ",
            Le => " LE ",
            And | Or | Xor if self.from != self.to && !(is_condition(l) && is_condition(r)) => {
                return Err(unsupported(Span::default(), "AND, OR or XOR on values other than conditions: Custom Macro B's are bitwise, LinuxCNC's logical".into()))
            }
            And => " AND ",
            Or => " OR ",
            Xor => " XOR ",
        };
        Ok(format!("{a}{name}{b}"))
    }

    fn function(&mut self, f: Func, x: &Ex) -> Result<String, Diagnostic> {
        use Func::*;
        let name = match f {
            Sin => "SIN",
            Cos => "COS",
            Tan => "TAN",
            Asin => "ASIN",
            Acos => "ACOS",
            Atan if self.to == Lang::Ngc => return Ok(format!("ATAN[{}]/[1]", self.ex(x)?)),
            Atan => "ATAN",
            Sqrt => "SQRT",
            Abs => "ABS",
            Exp => "EXP",
            Ln => "LN",
            Round => "ROUND",
            Fix => "FIX",
            Fup => "FUP",
            Bin | Bcd => {
                return Err(unsupported(
                    Span::default(),
                    "BIN/BCD, conversions for the PMC's signals: LinuxCNC has none".into(),
                ))
            }
        };
        Ok(format!("{name}[{}]", self.ex(x)?))
    }

    /// A condition in brackets, true when the branch runs.
    fn cond(&mut self, c: &Cond) -> Result<String, Diagnostic> {
        let t = self.cond_inner(&c.ex, c.negated)?;
        Ok(format!("[{t}]"))
    }

    fn cond_inner(&mut self, e: &Ex, negated: bool) -> Result<String, Diagnostic> {
        use BinOp::*;
        let cmp = |op: BinOp| matches!(op, Eq | Ne | Gt | Ge | Lt | Le);
        match e {
            Ex::Bin(op, l, r) if negated && cmp(*op) => {
                let flipped = match op {
                    Eq => Ne,
                    Ne => Eq,
                    Gt => Le,
                    Le => Gt,
                    Ge => Lt,
                    _ => Ge,
                };
                self.binary(flipped, l, r)
            }
            Ex::Bin(op @ (And | Or), l, r) if negated && is_condition(l) && is_condition(r) => {
                let (a, b) = (self.cond_inner(l, true)?, self.cond_inner(r, true)?);
                let joined = if *op == And { "OR" } else { "AND" };
                Ok(format!("[{a}] {joined} [{b}]"))
            }
            _ if !negated && is_condition(e) => self.ex(e),
            _ if !negated => Ok(format!("{} NE 0", self.operand(e)?)),
            _ if !is_condition(e) => Ok(format!("{} EQ 0", self.operand(e)?)),
            _ if self.to == Lang::Ngc => Ok(format!("[{}] EQ 0", self.ex(e)?)),
            _ => Err(unsupported(
                Span::default(),
                "a condition threadcut cannot turn into its opposite in Custom Macro B".into(),
            )),
        }
    }

    fn label(&mut self) -> u32 {
        loop {
            self.labels += 1;
            let n = match self.to {
                Lang::Ngc => 100 + self.labels,
                _ => 9000 + self.labels,
            };
            let taken =
                self.used_labels.contains(&n) || self.subs.values().any(|s| s == &n.to_string());
            if !taken {
                return n;
            }
        }
    }

    fn open(&mut self, text: &str, at: usize) {
        self.line(text, Some(at));
        self.depth += 1;
    }

    fn close(&mut self, text: &str, at: Option<usize>) {
        self.depth -= 1;
        self.line(text, at);
    }

    fn while_loop(
        &mut self,
        at: usize,
        cond: &Cond,
        body: &[Node],
        end: usize,
    ) -> Result<(), Diagnostic> {
        let c = self.cond(cond)?;
        if self.to == Lang::Ngc {
            let o = self.label();
            self.open(&format!("o{o} while {c}"), at);
            self.nodes(body)?;
            self.close(&format!("o{o} endwhile"), Some(end));
            return Ok(());
        }
        if self.loops == 3 {
            return Err(unsupported(
                self.stmts[at].span,
                "a fourth loop inside three: Custom Macro B's WHILE nests three deep (DO1–DO3)"
                    .into(),
            ));
        }
        self.loops += 1;
        let m = self.loops;
        self.open(&format!("WHILE {c} DO{m}"), at);
        self.nodes(body)?;
        self.close(&format!("END{m}"), Some(end));
        self.loops -= 1;
        Ok(())
    }

    fn do_while(
        &mut self,
        at: usize,
        body: &[Node],
        cond: &Cond,
        test: usize,
    ) -> Result<(), Diagnostic> {
        let c = self.cond(cond)?;
        let n = self.label();
        if self.to == Lang::Ngc {
            self.open(&format!("o{n} do"), at);
            self.nodes(body)?;
            self.close(&format!("o{n} while {c}"), Some(test));
        } else {
            self.line(&format!("N{n}"), None);
            self.nodes(body)?;
            self.line(&format!("IF {c} GOTO{n}"), Some(test));
        }
        Ok(())
    }

    fn if_node(
        &mut self,
        at: usize,
        cond: &Cond,
        then: &[Node],
        els: &[Node],
    ) -> Result<(), Diagnostic> {
        if self.to == Lang::Ngc {
            let c = self.cond(cond)?;
            let o = self.label();
            self.open(&format!("o{o} if {c}"), at);
            self.nodes(then)?;
            if !els.is_empty() {
                self.close(&format!("o{o} else"), None);
                self.depth += 1;
                self.nodes(els)?;
            }
            self.close(&format!("o{o} endif"), None);
            return Ok(());
        }
        if let ([set], true) = (sets_of(then), els.is_empty()) {
            let c = self.cond(cond)?;
            let s = self.set(set)?;
            self.line(&format!("IF {c} THEN {s}"), Some(at));
            return Ok(());
        }
        let skip = self.cond(&Cond {
            ex: cond.ex.clone(),
            negated: !cond.negated,
        })?;
        let n = self.label();
        self.line(&format!("IF {skip} GOTO{n}"), Some(at));
        self.nodes(then)?;
        if els.is_empty() {
            self.line(&format!("N{n}"), None);
        } else {
            let m = self.label();
            self.line(&format!("GOTO{m}"), None);
            self.line(&format!("N{n}"), None);
            self.nodes(els)?;
            self.line(&format!("N{m}"), None);
        }
        Ok(())
    }

    fn repeat(&mut self, at: usize, count: &Ex, body: &[Node]) -> Result<(), Diagnostic> {
        if let [Node::Call {
            at: c,
            sub,
            args,
            count: None,
            shares_locals,
        }] = body
        {
            return self.call(&Node::Call {
                at: *c,
                sub: sub.clone(),
                args: args.clone(),
                count: Some(count.clone()),
                shares_locals: *shares_locals,
            });
        }
        if self.to == Lang::Ngc {
            let o = self.label();
            let n = self.ex(count)?;
            self.open(&format!("o{o} repeat [{n}]"), at);
            self.nodes(body)?;
            self.close(&format!("o{o} endrepeat"), None);
            return Ok(());
        }
        Err(unsupported(
            self.stmts[at].span,
            "a repeat around more than one call: threadcut writes repeat as a call's L count only"
                .into(),
        ))
    }

    fn call(&mut self, n: &Node) -> Result<(), Diagnostic> {
        let Node::Call {
            at,
            sub,
            args,
            count,
            shares_locals,
        } = n
        else {
            return Ok(());
        };
        let span = self.stmts[*at].span;
        let caller = Some(self.stmts[*at].number);
        let Some(name) = self
            .subs
            .get(&(sub.clone(), caller))
            .or_else(|| self.subs.get(&(sub.clone(), None)))
            .cloned()
        else {
            return Err(unsupported(
                span,
                format!("the subprogram {sub} this line calls is not in the program"),
            ));
        };
        let times = match count {
            Some(Ex::Num(v)) if *v == 1.0 => None,
            Some(e) => Some(self.ex(e)?),
            None => None,
        };
        if self.to == Lang::Ngc {
            if *shares_locals && self.sub_sets_locals(sub) {
                return Err(unsupported(span, format!("M98 runs subprogram {sub} with the caller's local variables #1–#33, and it sets some: LinuxCNC restores #1–#30 when its subroutine returns")).with_hint("--flatten writes the executed program instead"));
            }
            return self.ngc_call(*at, &name, args, times);
        }
        // M98 where the control has no G65 call, or where the source's call shares the caller's
        // local variables too (M98, Haas's M97).
        if self.to_syntax.g65_operations
            || self.to_syntax.max_macro_depth == 0
            || self.to_syntax.m97_local_calls
            || (*shares_locals && args.is_empty())
        {
            return self.m98(*at, &name, args, times);
        }
        self.g65(*at, &name, args, times)
    }

    /// `oN call [#1] [#2] …`, in a repeat for a count; an argument left out is passed as 0.
    fn ngc_call(
        &mut self,
        at: usize,
        name: &str,
        args: &[(u8, Ex)],
        times: Option<String>,
    ) -> Result<(), Diagnostic> {
        let last = args.iter().map(|a| a.0).max().unwrap_or(0);
        if last > 30 {
            return Err(unsupported(
                self.stmts[at].span,
                format!("an argument for #{last}: LinuxCNC passes #1–#30"),
            ));
        }
        let mut text = format!("o{name} call");
        for slot in 1..=last {
            let v = match args.iter().find(|a| a.0 == slot) {
                Some((_, e)) => self.ex(e)?,
                None => "0".into(),
            };
            text.push_str(&format!(" [{v}]"));
        }
        match times {
            None => self.line(&text, Some(at)),
            Some(t) => {
                let o = self.label();
                self.open(&format!("o{o} repeat [{t}]"), at);
                self.line(&text, None);
                self.close(&format!("o{o} endrepeat"), None);
            }
        }
        Ok(())
    }

    /// `G65 P… L… A… B…`: each argument by its letter of specification I, or all of them in
    /// specification II (A B C, then I J K repeated) when one has no letter of its own there.
    fn g65(
        &mut self,
        at: usize,
        name: &str,
        args: &[(u8, Ex)],
        times: Option<String>,
    ) -> Result<(), Diagnostic> {
        const SPEC_ONE: &[u8; 27] = b"_ABCIJKDEF_H_M___QRSTUVWXYZ";
        let mut text = format!("G65 P{name}");
        if let Some(t) = &times {
            text.push_str(&format!(" L{}", bracketed(t)));
        }
        let one = args
            .iter()
            .all(|(slot, _)| SPEC_ONE.get(*slot as usize).is_some_and(|l| *l != b'_'));
        for (k, (slot, e)) in args.iter().enumerate() {
            let letter = match (one, *slot as usize) {
                (true, s) => SPEC_ONE[s],
                (false, s @ 1..=3) if s == k + 1 => b"ABC"[s - 1],
                (false, s @ 4..=33) if s == k + 1 => b"IJK"[(s - 4) % 3],
                _ => {
                    return Err(unsupported(
                        self.stmts[at].span,
                        format!(
                        "the argument for #{slot}: G65's letters cannot pass it with the others"
                    ),
                    ))
                }
            };
            // A number with its decimal point: without, Custom Macro B would read it in least
            // input increments.
            let v = match e {
                Ex::Num(v) if v.fract() == 0.0 => format!("{}.", num(*v)),
                _ => self.ex(e)?,
            };
            text.push_str(&format!(" {}{}", letter as char, bracketed(&v)));
        }
        self.line(&text, Some(at));
        Ok(())
    }

    /// A call on a control without G65 calls, or to a subprogram of the same file on Haas: the
    /// arguments set in the caller's local variables, which M98's and M97's subprogram shares,
    /// then `M98 P…` (the count packed in P where the control has no L) or Haas's `M97 P…`.
    fn m98(
        &mut self,
        at: usize,
        name: &str,
        args: &[(u8, Ex)],
        times: Option<String>,
    ) -> Result<(), Diagnostic> {
        let span = self.stmts[at].span;
        for (slot, e) in args {
            let v = self.ex(e)?;
            self.line(&format!("#{slot}={v}"), None);
        }
        let number: u32 = name
            .parse()
            .map_err(|_| unsupported(span, "a subprogram without a number".into()))?;
        let m97 = self.to_syntax.m97_local_calls;
        let text = match times {
            None if m97 => format!("M97 P{number}"),
            Some(t) if m97 => format!("M97 P{number} L{}", bracketed(&t)),
            None => format!("M98 P{number}"),
            Some(t) if self.to_syntax.m98_l_word => format!("M98 P{number} L{}", bracketed(&t)),
            Some(t) => match t.parse::<u32>() {
                Ok(l) if (1..=9999).contains(&l) && number <= 9999 => format!("M98 P{}", l * 10000 + number),
                _ => return Err(unsupported(span, "a call count that is not a number from 1 to 9999: this control packs it in M98's P".into())),
            },
        };
        self.line(&text, Some(at));
        Ok(())
    }

    /// Whether a subprogram's lines set a local variable (#1–#33): LinuxCNC's call hands the
    /// subroutine the caller's #1–#30 but restores them on return ("Parameters from #N+1 to #30
    /// have the same value as in the calling context. On return from the subroutine, the values
    /// of parameters #1 through #30 … will be restored"), so a subprogram that only reads them
    /// runs the same.
    fn sub_sets_locals(&self, sub: &str) -> bool {
        let Some(&(at, end)) = self.ranges.get(sub) else {
            return false;
        };
        let local = |s: &Set| matches!(s.var, Var::Num(1..=33));
        self.stmts[at..=end].iter().any(|s| match &s.st {
            St::Set(sets) => sets.iter().any(local),
            St::IfThen(_, set) => local(set),
            _ => false,
        })
    }

    /// A subprogram: once, or once for each line that calls it.
    fn sub(&mut self, s: &Sub) -> Result<(), Diagnostic> {
        let copies: Vec<Option<u32>> = match self.copies.get(&s.name) {
            Some(callers) => callers.iter().map(|c| Some(*c)).collect(),
            None => vec![None],
        };
        for copy in copies {
            self.copy = copy;
            let name = self.subs[&(s.name.clone(), copy)].clone();
            let note = copy.map(|c| format!("{} for the call on line {c}", self.source_name(s)));
            self.sub_copy(s, name, note)?;
        }
        self.copy = None;
        Ok(())
    }

    /// The subprogram's name in the source's words.
    fn source_name(&self, s: &Sub) -> String {
        match (self.from, s.name.parse::<u32>()) {
            (Lang::Ngc, Ok(n)) => format!("o{n}"),
            (Lang::Ngc, Err(_)) => format!("o<{}>", s.name),
            (_, Ok(n)) => format!("O{n}"),
            _ => s.name.clone(),
        }
    }

    /// One copy of a subprogram, `note` saying which call it is for.
    fn sub_copy(&mut self, s: &Sub, name: String, note: Option<String>) -> Result<(), Diagnostic> {
        self.current = Some(name.clone());
        if self.to == Lang::Ngc {
            if let Some(n) = &note {
                self.line(&(self.comment)(n), None);
            }
            self.open(&format!("o{name} sub"), s.at);
            self.nodes(&s.body)?;
            self.close(&format!("o{name} endsub"), Some(s.end));
        } else {
            let note = match (note, s.name.parse::<u32>()) {
                (Some(n), _) => format!(" {}", (self.comment)(&n)),
                (None, Ok(_)) => String::new(),
                (None, Err(_)) => format!(" {}", (self.comment)(&format!("o<{}>", s.name))),
            };
            // Haas: a local subprogram, at its sequence number after M30 ("M97 … call a
            // subroutine referenced by a line number (N) within the same program"); M98 and G65
            // call a program of the control's list.
            let head = if self.to_syntax.m97_local_calls {
                "N"
            } else {
                "O"
            };
            self.out.push_str(&format!("{head}{name}{note}"));
            for c in &self.stmts[s.at].comments {
                self.out.push(' ');
                self.out.push_str(&(self.comment)(c));
            }
            self.out.push('\n');
            self.nodes(&s.body)?;
            self.line("M99", Some(s.end));
        }
        self.current = None;
        Ok(())
    }
}

fn sets_of(nodes: &[Node]) -> &[Set] {
    match nodes {
        [Node::Set(_, sets)] => sets,
        _ => &[],
    }
}

/// A value as a word's or argument's: bracketed unless it is a number or one variable.
fn bracketed(t: &str) -> String {
    if t.starts_with('#')
        && !t[1..]
            .contains(|c: char| !c.is_ascii_alphanumeric() && c != '<' && c != '>' && c != '_')
        || t.parse::<f64>().is_ok()
    {
        t.to_string()
    } else {
        format!("[{t}]")
    }
}

/// The axis a position variable reads (0: X, 1: Z): Custom Macro B's #5001/#5002 (#5041/#5042),
/// LinuxCNC's #5420/#5422.
fn position_axis(lang: Lang, n: i64) -> Option<usize> {
    match (lang, n) {
        (Lang::MacroB, 5001 | 5041) | (Lang::Ngc, 5420) => Some(0),
        (Lang::MacroB, 5002 | 5042) | (Lang::Ngc, 5422) => Some(1),
        _ => None,
    }
}

/// Whether an expression is a condition (a comparison, or conditions joined).
fn is_condition(e: &Ex) -> bool {
    use BinOp::*;
    match e {
        Ex::Bin(Eq | Ne | Gt | Ge | Lt | Le, ..) => true,
        Ex::Bin(And | Or | Xor, l, r) => is_condition(l) && is_condition(r),
        _ => false,
    }
}

/// A number as an expression writes it: whole numbers without a decimal point.
pub fn num(v: f64) -> String {
    if v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v}")
    }
}

fn pieces_plain(p: &[Piece]) -> String {
    p.iter()
        .map(|p| match p {
            Piece::Text(t) => t.clone(),
            Piece::Expr { .. } => String::new(),
        })
        .collect()
}

/// Every variable number a statement names (so that free ones can be found).
fn collect_numbers(st: &St, used: &mut BTreeSet<i64>) {
    fn walk(e: &Ex, used: &mut BTreeSet<i64>) {
        match e {
            Ex::Var(n) => {
                if let Ex::Num(v) = &**n {
                    used.insert(*v as i64);
                }
                walk(n, used)
            }
            Ex::Neg(x) | Ex::Fun(_, x) => walk(x, used),
            Ex::Bin(_, a, b) | Ex::Atan2(a, b) | Ex::Pow2(a, b) => {
                walk(a, used);
                walk(b, used)
            }
            _ => {}
        }
    }
    let set = |s: &Set, used: &mut BTreeSet<i64>| {
        if let Var::Num(n) = s.var {
            used.insert(n);
        }
        walk(&s.value, used);
    };
    match st {
        St::Set(sets) => sets.iter().for_each(|s| set(s, used)),
        St::IfThen(c, s) => {
            walk(c, used);
            set(s, used)
        }
        St::IfGoto(c, _) | St::While(c, _) => walk(c, used),
        St::Block(words) => words.iter().for_each(|w| {
            if let super::read::Val::Expr(e) = &w.value {
                walk(e, used)
            }
        }),
        St::O { arg, args, .. } => {
            arg.iter().chain(args).for_each(|e| walk(e, used));
        }
        _ => {}
    }
}
