//! Sinumerik's block syntax beyond address words: the lines the shared lexer hands over unread
//! ([`Syntax::hand_over_unread`](crate::gcode::Syntax)). A block is a sequence of
//!
//! - address words, as the shared lexer reads them (`G33`, `X-10.5`, `N20`);
//! - assignments `NAME=operand` (`SF=90`, `R1=2.5`, `LIMS=3000`, `X=R1`, `T="THREAD"`);
//! - keywords (`DIAMON`, `STOPRE`);
//! - calls `NAME(arguments)` (`CYCLE97(2,,0,-30,…)`, `MSG("…")`);
//! - a declaration `DEF REAL NAME=operand, …`;
//!
//! and a `;` comment. Parentheses are not comments. An operand is a number, an R parameter
//! (`R12`), a name declared with `DEF`, a string, or one of these with a sign: threadcut does not
//! evaluate expressions, functions or system variables, and says so at the character where one
//! begins (SINUMERIK 840D sl Programming Manual, Fundamentals, "Arithmetic parameters R",
//! "Definition of user data (DEF)").

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::lexer::{lex_word, show};
use crate::gcode::Word;

/// One element of a block, in the order written.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Item {
    /// An address word: a letter and a number.
    Word(Word),
    /// `NAME=operand` (`NAME` upper case; a single letter for an address given by an operand,
    /// such as `X=R1`).
    Assign {
        name: String,
        /// The whole assignment.
        span: Span,
        value: Operand,
    },
    /// A word of its own: `DIAMON`, `STOPRE`.
    Keyword { name: String, span: Span },
    /// `NAME(arguments)`; an empty argument is `None`.
    Call {
        name: String,
        /// The name.
        span: Span,
        args: Vec<Option<Operand>>,
        /// Where each argument is written (the place of an empty one: its comma).
        arg_spans: Vec<Span>,
    },
    /// `DEF type name[=operand], …`.
    Def {
        /// `REAL` or `INT`.
        kind: String,
        vars: Vec<(String, Span, Option<Operand>)>,
    },
    /// A `%_N_…` program header line.
    Header,
    /// A jump label, `NAME:`.
    Label,
}

/// An operand as written; its value depends on the parameters set before it.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Operand {
    Number {
        value: f64,
        span: Span,
    },
    /// `R<n>`, negated when written `-R<n>`.
    R {
        n: u32,
        negative: bool,
        span: Span,
    },
    /// A name declared with `DEF`, negated when written `-NAME`.
    Name {
        name: String,
        negative: bool,
        span: Span,
    },
    Text {
        text: String,
        span: Span,
    },
}

impl Operand {
    pub fn span(&self) -> Span {
        match self {
            Operand::Number { span, .. }
            | Operand::R { span, .. }
            | Operand::Name { span, .. }
            | Operand::Text { span, .. } => *span,
        }
    }
}

/// Reads one block. `offset` and `line_no` place the spans.
pub(super) fn parse(text: &[u8], line_no: u32, offset: u64) -> Result<Vec<Item>> {
    let mut p = Parser {
        text,
        line_no,
        offset,
        i: 0,
    };
    p.block()
}

struct Parser<'t> {
    text: &'t [u8],
    line_no: u32,
    offset: u64,
    i: usize,
}

fn is_ident_start(b: u8) -> bool {
    b.is_ascii_alphabetic() || b == b'_' || b == b'$'
}

fn is_ident(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'$'
}

/// Characters that continue an operand into an expression.
fn is_operator(b: u8) -> bool {
    matches!(
        b,
        b'+' | b'-' | b'*' | b'/' | b'<' | b'>' | b'=' | b'[' | b'('
    )
}

impl Parser<'_> {
    fn span(&self, at: usize, len: usize) -> Span {
        Span::new(
            self.offset + at as u64,
            len.min(u32::MAX as usize) as u32,
            self.line_no,
            at as u32 + 1,
        )
    }

    fn peek(&self) -> Option<u8> {
        self.text.get(self.i).copied()
    }

    fn skip_blanks(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t' | b'\r' | 0x0c)) {
            self.i += 1;
        }
    }

    fn block(&mut self) -> Result<Vec<Item>> {
        let mut items = Vec::new();
        self.skip_blanks();
        if self.peek() == Some(b'%') {
            // `%_N_NAME_MPF`: the program's name, as the control's file header writes it.
            return Ok(vec![Item::Header]);
        }
        if self.peek() == Some(b'/') {
            // Block delete: the block runs unless the operator skips it.
            self.i += 1;
        }
        loop {
            self.skip_blanks();
            let Some(c) = self.peek() else { break };
            match c {
                b';' => break,
                b':' => {
                    // A main block number, `:10`.
                    self.i += 1;
                    while self.peek().is_some_and(|b| b.is_ascii_digit()) {
                        self.i += 1;
                    }
                }
                c if is_ident_start(c) => {
                    let item = self.item()?;
                    if let Item::Keyword { name, .. } = &item {
                        if name == "DEF" {
                            items.push(self.def()?);
                            continue;
                        }
                        // Program flow (`WHILE R1<3`, `IF R1>2 GOTOB M1`, `FOR R1=1 TO 3`): the
                        // dialect refuses the keyword itself; what follows it is not read.
                        if super::FLOW.contains(&name.as_str()) {
                            items.push(item);
                            break;
                        }
                    }
                    items.push(item);
                }
                b'#' => {
                    return Err(self.unexpected(self.i).with_hint(
                        "`#` variables are Fanuc's Custom Macro B, not Sinumerik's language (its variables are R parameters and DEF names, which threadcut reads as values; its program flow is refused): a program written for a Fanuc-style control is read with --controller fanuc",
                    ));
                }
                b'(' => {
                    return Err(self
                        .unexpected(self.i)
                        .with_hint("on Sinumerik, comments begin with `;`: `(` only opens the parameters of a call"));
                }
                _ => return Err(self.unexpected(self.i)),
            }
        }
        Ok(items)
    }

    fn unexpected(&self, at: usize) -> Diagnostic {
        // The whole (possibly invalid) UTF-8 character, so that a caret covers it.
        let want = match self.text.get(at) {
            Some(0xc0..=0xdf) => 2,
            Some(0xe0..=0xef) => 3,
            Some(0xf0..=0xf7) => 4,
            _ => 1,
        };
        let end = (at + want).min(self.text.len());
        Diagnostic::error(
            Code::Syntax,
            self.span(at, end.saturating_sub(at).max(1)),
            format!(
                "unexpected character `{}`",
                show(&self.text[at.min(end)..end])
            ),
        )
        .with_hint("expected an address word, an assignment, a call or `;`")
    }

    /// An address word, an assignment, a keyword or a call, starting at a letter.
    fn item(&mut self) -> Result<Item> {
        let start = self.i;
        let mut j = start;
        while self.text.get(j).is_some_and(|b| b.is_ascii_alphabetic()) {
            j += 1;
        }
        let next = self.text.get(j).copied();
        let starts_number = matches!(next, Some(b'0'..=b'9' | b'.' | b'+' | b'-'));
        if j == start + 1 && starts_number {
            // A letter and a number: an address word, unless `=` follows (`R1=`, `X1=`, `S1=`).
            let mut words = Vec::with_capacity(1);
            let end = lex_word(self.text, start, self.line_no, self.offset, &mut words)?;
            let word = words[0];
            let mut k = end;
            while matches!(self.text.get(k), Some(b' ' | b'\t')) {
                k += 1;
            }
            if self.text.get(k) == Some(&b'=') {
                let digits = &self.text[start + 1..end];
                if !digits.iter().all(u8::is_ascii_digit) {
                    return Err(self.unexpected(k));
                }
                let name = String::from_utf8_lossy(&self.text[start..end]).to_ascii_uppercase();
                self.i = k + 1;
                let value = self.operand()?;
                return Ok(Item::Assign {
                    name,
                    span: self.span(start, self.i - start),
                    value,
                });
            }
            self.i = end;
            return Ok(Item::Word(word));
        }
        // A name: letters, digits, `_`, `$`.
        while self.text.get(j).copied().is_some_and(is_ident) {
            j += 1;
        }
        let name = String::from_utf8_lossy(&self.text[start..j]).to_ascii_uppercase();
        let name_span = self.span(start, j - start);
        self.i = j;
        self.skip_blanks();
        match self.peek() {
            Some(b':') if j > start + 1 => {
                self.i += 1;
                Ok(Item::Label)
            }
            Some(b'=') => {
                self.i += 1;
                let value = self.operand()?;
                Ok(Item::Assign {
                    name,
                    span: self.span(start, self.i - start),
                    value,
                })
            }
            Some(b'(') => {
                self.i += 1;
                let (args, arg_spans) = self.arguments(&name, name_span)?;
                Ok(Item::Call {
                    name,
                    span: name_span,
                    args,
                    arg_spans,
                })
            }
            _ => {
                if j == start + 1 && !name.starts_with('$') {
                    // A lone letter: an address without its number.
                    return Err(Diagnostic::error(
                        Code::Syntax,
                        name_span,
                        format!("malformed word `{name}`: a number was expected after the letter"),
                    )
                    .with_hint("a word is one letter followed by a number, such as `X-12.5`, or an assignment such as `X=R1`"));
                }
                Ok(Item::Keyword {
                    name,
                    span: name_span,
                })
            }
        }
    }

    /// The arguments of a call, after its `(`, up to and including its `)`.
    #[allow(clippy::type_complexity)]
    fn arguments(
        &mut self,
        name: &str,
        name_span: Span,
    ) -> Result<(Vec<Option<Operand>>, Vec<Span>)> {
        // Room for a threading cycle's parameters (CYCLE97 has 16) without growing.
        let mut args = Vec::with_capacity(16);
        let mut spans = Vec::with_capacity(16);
        loop {
            self.skip_blanks();
            match self.peek() {
                None | Some(b';') => {
                    return Err(Diagnostic::error(
                        Code::Syntax,
                        name_span,
                        format!("the parameters of {name} are not closed"),
                    )
                    .with_hint("close them with `)` on the same line"))
                }
                Some(b',') => {
                    args.push(None);
                    spans.push(self.span(self.i, 1));
                    self.i += 1;
                    continue;
                }
                Some(b')') => {
                    // `NAME()` has no arguments; `NAME(a,)` ends with an empty one.
                    if !args.is_empty() || self.text[..self.i].trim_ascii_end().ends_with(b",") {
                        args.push(None);
                        spans.push(self.span(self.i, 1));
                    }
                    self.i += 1;
                    return Ok((args, spans));
                }
                Some(_) => {
                    let op = self.operand()?;
                    spans.push(op.span());
                    args.push(Some(op));
                    self.skip_blanks();
                    match self.peek() {
                        Some(b',') => self.i += 1,
                        Some(b')') => {
                            self.i += 1;
                            return Ok((args, spans));
                        }
                        None | Some(b';') => {
                            return Err(Diagnostic::error(
                                Code::Syntax,
                                name_span,
                                format!("the parameters of {name} are not closed"),
                            )
                            .with_hint("close them with `)` on the same line"))
                        }
                        Some(_) => return Err(self.expression(self.i)),
                    }
                }
            }
        }
    }

    /// `DEF type name[=operand], …` after the `DEF`.
    fn def(&mut self) -> Result<Item> {
        self.skip_blanks();
        let at = self.i;
        while self.peek().is_some_and(|b| b.is_ascii_alphabetic()) {
            self.i += 1;
        }
        let kind = String::from_utf8_lossy(&self.text[at..self.i]).to_ascii_uppercase();
        if !matches!(kind.as_str(), "REAL" | "INT") {
            return Err(Diagnostic::error(
                Code::Unsupported,
                self.span(at, (self.i - at).max(1)),
                format!("DEF {kind}: threadcut reads REAL and INT variables only"),
            ));
        }
        let mut vars = Vec::new();
        loop {
            self.skip_blanks();
            let start = self.i;
            if !self.peek().is_some_and(is_ident_start) {
                return Err(self.unexpected(self.i.min(self.text.len().saturating_sub(1))));
            }
            while self.peek().is_some_and(is_ident) {
                self.i += 1;
            }
            let name = String::from_utf8_lossy(&self.text[start..self.i]).to_ascii_uppercase();
            let span = self.span(start, self.i - start);
            self.skip_blanks();
            let value = if self.peek() == Some(b'=') {
                self.i += 1;
                Some(self.operand()?)
            } else {
                None
            };
            vars.push((name, span, value));
            self.skip_blanks();
            match self.peek() {
                Some(b',') => self.i += 1,
                None | Some(b';') => break,
                Some(_) => return Err(self.expression(self.i)),
            }
        }
        Ok(Item::Def { kind, vars })
    }

    /// A number, an R parameter, a declared name or a string, with an optional sign; nothing
    /// that continues it into an expression.
    fn operand(&mut self) -> Result<Operand> {
        self.skip_blanks();
        let start = self.i;
        let negative = match self.peek() {
            Some(b'-') => {
                self.i += 1;
                true
            }
            Some(b'+') => {
                self.i += 1;
                false
            }
            _ => false,
        };
        let signed = self.i > start;
        let op = match self.peek() {
            Some(b'0'..=b'9' | b'.') => {
                let at = self.i;
                while self.peek().is_some_and(|b| b.is_ascii_digit() || b == b'.') {
                    self.i += 1;
                }
                let digits = &self.text[at..self.i];
                let value = std::str::from_utf8(digits)
                    .ok()
                    .filter(|t| t.bytes().filter(|&b| b == b'.').count() <= 1)
                    .filter(|t| t.bytes().any(|b| b.is_ascii_digit()))
                    .and_then(|t| t.parse::<f64>().ok())
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        Diagnostic::error(
                            Code::Syntax,
                            self.span(at, self.i - at),
                            format!("`{}` is not a number", show(digits)),
                        )
                    })?;
                Operand::Number {
                    value: if negative { -value } else { value },
                    span: self.span(start, self.i - start),
                }
            }
            Some(b'"') if !signed => {
                self.i += 1;
                let at = self.i;
                let close = memchr::memchr(b'"', &self.text[at..]).ok_or_else(|| {
                    Diagnostic::error(
                        Code::Syntax,
                        self.span(start, 1),
                        "the string is not closed",
                    )
                    .with_hint("close it with `\"` on the same line")
                })?;
                self.i = at + close + 1;
                Operand::Text {
                    text: String::from_utf8_lossy(&self.text[at..at + close]).into_owned(),
                    span: self.span(start, self.i - start),
                }
            }
            Some(c) if is_ident_start(c) => {
                let at = self.i;
                while self.peek().is_some_and(is_ident) {
                    self.i += 1;
                }
                let name = String::from_utf8_lossy(&self.text[at..self.i]).to_ascii_uppercase();
                let span = self.span(start, self.i - start);
                if self.peek() == Some(b'(') || self.peek() == Some(b'[') {
                    return Err(self.function(&name, span));
                }
                if name.starts_with('$') {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        span,
                        format!("{name}: threadcut does not read the control's system variables"),
                    )
                    .with_hint(
                        "write the value as a number or an R parameter set earlier in the program",
                    ));
                }
                match name.strip_prefix('R').map(|d| d.parse::<u32>()) {
                    Some(Ok(n)) if name[1..].bytes().all(|b| b.is_ascii_digit()) => {
                        Operand::R { n, negative, span }
                    }
                    _ => Operand::Name {
                        name,
                        negative,
                        span,
                    },
                }
            }
            _ => return Err(self.expression(self.i.min(self.text.len()))),
        };
        // Directly after the operand (blanks allowed): no operator.
        let mut k = self.i;
        while matches!(self.text.get(k), Some(b' ' | b'\t')) {
            k += 1;
        }
        if self.text.get(k).copied().is_some_and(is_operator) {
            return Err(self.expression(k));
        }
        Ok(op)
    }

    fn function(&self, name: &str, span: Span) -> Diagnostic {
        let hint = match name {
            "IC" | "AC" => {
                "write G91 (incremental) or G90 (absolute) in the block instead of IC(…)/AC(…)"
            }
            _ => "write the value as a number or an R parameter set earlier in the program",
        };
        Diagnostic::error(
            Code::Unsupported,
            span,
            format!("{name}(…): threadcut does not evaluate Sinumerik functions or expressions"),
        )
        .with_hint(hint)
    }

    fn expression(&self, at: usize) -> Diagnostic {
        let len = if at < self.text.len() { 1 } else { 0 };
        let what = if at < self.text.len() {
            format!("`{}`", show(&self.text[at..at + 1]))
        } else {
            "the end of the line".to_string()
        };
        Diagnostic::error(
            Code::Unsupported,
            self.span(at.min(self.text.len()), len),
            format!(
                "{what} where an operand ends: threadcut does not evaluate Sinumerik expressions"
            ),
        )
        .with_hint("write a number, an R parameter or a DEF variable set earlier in the program")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn items(text: &str) -> Vec<Item> {
        parse(text.as_bytes(), 1, 0).unwrap_or_else(|e| panic!("{text}: {}", e.message))
    }

    fn error(text: &str) -> Diagnostic {
        parse(text.as_bytes(), 1, 0).unwrap_err()
    }

    #[test]
    fn words_assignments_keywords_and_calls() {
        let got = items("N30 G33 Z-30 K1.5 SF=90 ; first start");
        assert_eq!(got.len(), 5);
        assert!(matches!(&got[3], Item::Word(w) if w.letter == b'K' && w.value == 1.5));
        match &got[4] {
            Item::Assign { name, value, span } => {
                assert_eq!(name, "SF");
                assert!(matches!(value, Operand::Number { value, .. } if *value == 90.0));
                assert_eq!((span.column, span.len), (19, 5));
            }
            other => panic!("{other:?}"),
        }
        let got = items("R1=2.5 R2=-R1 X1=0 DIAMON T=\"THREAD_EXT\"");
        assert!(
            matches!(&got[1], Item::Assign { name, value: Operand::R { n: 1, negative: true, .. }, .. } if name == "R2")
        );
        assert!(matches!(&got[2], Item::Assign { name, .. } if name == "X1"));
        assert!(matches!(&got[3], Item::Keyword { name, .. } if name == "DIAMON"));
        assert!(
            matches!(&got[4], Item::Assign { value: Operand::Text { text, .. }, .. } if text == "THREAD_EXT")
        );
    }

    #[test]
    fn call_arguments_keep_their_places() {
        let got = items("CYCLE97(1.5,,0,-20, R3 ,40)");
        let Item::Call {
            name,
            args,
            arg_spans,
            ..
        } = &got[0]
        else {
            panic!("{got:?}")
        };
        assert_eq!(name, "CYCLE97");
        assert_eq!(args.len(), 6);
        assert!(args[1].is_none());
        assert!(matches!(args[4], Some(Operand::R { n: 3, .. })));
        // `R3` at column 21; the empty second argument at its comma (column 13).
        assert_eq!(arg_spans[4].column, 21);
        assert_eq!(arg_spans[1].column, 13);
        let Item::Call { args, .. } = &items("MSG()")[0] else {
            panic!()
        };
        assert!(args.is_empty());
        let Item::Call { args, .. } = &items("CYCLE97(1,)")[0] else {
            panic!()
        };
        assert_eq!(args.len(), 2);
    }

    #[test]
    fn declarations() {
        let got = items("DEF REAL PITCH=1.5, DEPTH");
        let Item::Def { kind, vars } = &got[0] else {
            panic!("{got:?}")
        };
        assert_eq!(kind, "REAL");
        assert_eq!(vars.len(), 2);
        assert!(vars[1].2.is_none());
    }

    #[test]
    fn expressions_and_comments_in_parentheses_are_refused_where_they_begin() {
        let e = error("R1=R2*2");
        assert_eq!((e.code, e.span.column), (Code::Unsupported, 6));
        let e = error("X=IC(5)");
        assert_eq!((e.code, e.span.column), (Code::Unsupported, 3));
        assert!(e.hint.unwrap().contains("G91"));
        let e = error("G0 X10 (approach)");
        assert_eq!((e.code, e.span.column), (Code::Syntax, 8));
        let e = error("CYCLE97(1.5,,0");
        assert!(e.message.contains("not closed"), "{}", e.message);
        let e = error("R1=$AA_IM[X]");
        assert_eq!(e.code, Code::Unsupported);
        let e = error("G0 X");
        assert!(e.message.contains("number was expected"), "{}", e.message);
    }
}
