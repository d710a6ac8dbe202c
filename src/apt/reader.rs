//! A streaming APT/CL statement reader: `MAJOR/arg,arg,…` with `$` continuation and `$$` comments.
//!
//! One statement is held at a time (its tokens and its words), so memory does not grow with the
//! file. Every token keeps its [`Span`] (byte offset, line, column) for diagnostics.

use std::io::{BufRead, Read};

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::reader::MAX_LINE_BYTES;

/// A statement longer than this (over all its continuation lines) is refused.
pub const MAX_STATEMENT_BYTES: usize = 1 << 20;

/// One argument after the slash: a minor word or a number.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    /// A minor word, upper-cased (`ON`, `DEPTH`, `TPI`).
    Word(String),
    Number(f64),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Arg {
    pub value: Value,
    pub span: Span,
}

impl Arg {
    pub fn word(&self) -> Option<&str> {
        match &self.value {
            Value::Word(w) => Some(w),
            Value::Number(_) => None,
        }
    }

    pub fn number(&self) -> Option<f64> {
        match self.value {
            Value::Number(v) => Some(v),
            Value::Word(_) => None,
        }
    }
}

/// One statement: the major word, its arguments and, for `PARTNO`, the text that follows it.
#[derive(Clone, Debug, Default)]
pub struct Statement {
    /// The major word, upper-cased (`GOTO`, `THREAD`, `FINI`).
    pub major: String,
    pub major_span: Span,
    /// Whether a `/` followed the major word.
    pub slash: bool,
    pub args: Vec<Arg>,
    /// `PARTNO` (and `$$` nothing else): the rest of the line, verbatim.
    pub text: String,
    /// The line on which the statement starts.
    pub line: u32,
}

impl Statement {
    /// A span for the statement as a whole (its major word).
    pub fn span(&self) -> Span {
        self.major_span
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Token {
    Slash,
    Comma,
    Word,
    Number(f64),
}

pub struct Reader<R> {
    source: R,
    buf: Vec<u8>,
    line_no: u32,
    offset: u64,
    done: bool,
    statement: Statement,
}

impl<R: BufRead> Reader<R> {
    pub fn new(source: R) -> Reader<R> {
        Reader {
            source,
            buf: Vec::with_capacity(256),
            line_no: 0,
            offset: 0,
            done: false,
            statement: Statement::default(),
        }
    }

    /// Reads one physical line into `buf` (without terminator); `None` at the end.
    fn read_line(&mut self) -> Option<Result<(u32, u64)>> {
        if self.done {
            return None;
        }
        self.buf.clear();
        let limit = (MAX_LINE_BYTES + 2) as u64;
        let read = (&mut self.source)
            .take(limit)
            .read_until(b'\n', &mut self.buf);
        let line_no = self.line_no + 1;
        let offset = self.offset;
        match read {
            Err(e) => {
                self.done = true;
                return Some(Err(Diagnostic::error(
                    Code::Input,
                    Span::new(offset, 0, line_no, 1),
                    format!("cannot read the input: {e}"),
                )));
            }
            Ok(0) => {
                self.done = true;
                return None;
            }
            Ok(_) => {}
        }
        self.line_no = line_no;
        self.offset += self.buf.len() as u64;
        if self.buf.last() == Some(&b'\n') {
            self.buf.pop();
            if self.buf.last() == Some(&b'\r') {
                self.buf.pop();
            }
        } else if self.buf.len() as u64 >= limit {
            self.done = true;
            return Some(Err(Diagnostic::error(
                Code::Input,
                Span::new(offset, 1, line_no, 1),
                format!("line {line_no} is longer than {MAX_LINE_BYTES} bytes"),
            )));
        }
        Some(Ok((line_no, offset)))
    }

    /// The next statement, or `None` at the end of the input.
    pub fn next_statement(&mut self) -> Option<Result<&Statement>> {
        let mut st = std::mem::take(&mut self.statement);
        st.major.clear();
        st.args.clear();
        st.text.clear();
        st.slash = false;
        st.line = 0;
        let mut state = Parse::Major;
        let mut size = 0usize;
        loop {
            let (line_no, offset) = match self.read_line() {
                None => {
                    self.statement = st;
                    return match state {
                        Parse::Major => None,
                        _ => Some(Err(Diagnostic::error(
                            Code::Syntax,
                            Span::new(self.offset, 0, self.line_no, 1),
                            "the file ends inside a statement continued with `$`",
                        ))),
                    };
                }
                Some(Err(e)) => {
                    self.statement = st;
                    return Some(Err(e));
                }
                Some(Ok(l)) => l,
            };
            size += self.buf.len();
            if size > MAX_STATEMENT_BYTES {
                self.statement = st;
                self.done = true;
                return Some(Err(Diagnostic::error(
                    Code::Input,
                    Span::new(offset, 1, line_no, 1),
                    format!("a statement continues past {MAX_STATEMENT_BYTES} bytes"),
                )));
            }
            match lex_into(&self.buf, line_no, offset, &mut st, &mut state) {
                Ok(true) => continue,
                Ok(false) => {}
                Err(e) => {
                    self.statement = st;
                    return Some(Err(e));
                }
            }
            if matches!(state, Parse::Major) {
                continue; // a blank or comment-only line
            }
            if matches!(state, Parse::Arg) && st.slash && !st.args.is_empty() {
                let last = st.args.last().map(|a| a.span).unwrap_or_default();
                self.statement = st;
                return Some(Err(Diagnostic::error(
                    Code::Syntax,
                    last,
                    "a comma at the end of the statement needs another argument",
                )
                .with_hint(
                    "continue a statement on the next line with `$` at the end of the line",
                )));
            }
            if matches!(state, Parse::Arg) && st.slash {
                let span = st.major_span;
                self.statement = st;
                return Some(Err(Diagnostic::error(
                    Code::Syntax,
                    span,
                    "the slash after the major word is followed by no argument",
                )));
            }
            self.statement = st;
            return Some(Ok(&self.statement));
        }
    }
}

/// Where the parser is within a statement.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Parse {
    /// Before the major word.
    Major,
    /// After the major word, before any slash.
    AfterMajor,
    /// Expecting an argument.
    Arg,
    /// After an argument, expecting a comma or the end.
    AfterArg,
}

/// Lexes one line into the statement. Returns whether the line ends with a `$` continuation.
fn lex_into(
    line: &[u8],
    line_no: u32,
    offset: u64,
    st: &mut Statement,
    state: &mut Parse,
) -> Result<bool> {
    // `$$` starts a comment to the end of the line.
    let end = line
        .windows(2)
        .position(|w| w == b"$$")
        .unwrap_or(line.len());
    let text = &line[..end];
    let mut body_end = text.len();
    while body_end > 0 && text[body_end - 1].is_ascii_whitespace() {
        body_end -= 1;
    }
    let continued = body_end > 0 && text[body_end - 1] == b'$';
    if continued {
        body_end -= 1;
    }
    let span_at = |i: usize, len: usize| {
        Span::new(offset + i as u64, len.max(1) as u32, line_no, i as u32 + 1)
    };
    let mut i = 0;
    while i < body_end {
        let c = text[i];
        if c.is_ascii_whitespace() {
            i += 1;
            continue;
        }
        let start = i;
        let token = if c == b'/' {
            i += 1;
            Token::Slash
        } else if c == b',' {
            i += 1;
            Token::Comma
        } else if c.is_ascii_alphabetic() {
            while i < body_end && (text[i].is_ascii_alphanumeric() || text[i] == b'_') {
                i += 1;
            }
            Token::Word
        } else if c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.') {
            i += 1;
            while i < body_end
                && (text[i].is_ascii_digit()
                    || text[i] == b'.'
                    || ((text[i] == b'E' || text[i] == b'e') && i + 1 < body_end)
                    || (matches!(text[i], b'+' | b'-') && matches!(text[i - 1], b'E' | b'e')))
            {
                i += 1;
            }
            let raw = std::str::from_utf8(&text[start..i]).unwrap_or("");
            match raw.parse::<f64>() {
                Ok(v) if v.is_finite() => Token::Number(v),
                _ => {
                    return Err(Diagnostic::error(
                        Code::Syntax,
                        span_at(start, i - start),
                        format!(
                            "`{}` is not a number",
                            String::from_utf8_lossy(&text[start..i])
                        ),
                    ))
                }
            }
        } else {
            return Err(Diagnostic::error(
                Code::Syntax,
                span_at(start, 1),
                format!(
                    "`{}` has no meaning in an APT/CL statement",
                    String::from_utf8_lossy(&text[start..start + 1])
                ),
            )
            .with_hint(
                "statements are MAJOR/arg,arg,… ; `$` continues a line, `$$` starts a comment",
            ));
        };
        let span = span_at(start, i - start);
        let word = || String::from_utf8_lossy(&text[start..i]).to_ascii_uppercase();
        match (*state, token) {
            (Parse::Major, Token::Word) => {
                st.major = word();
                st.major_span = span;
                st.line = line_no;
                *state = Parse::AfterMajor;
                if st.major == "PARTNO" {
                    // The rest of the line is text, taken verbatim.
                    st.text = String::from_utf8_lossy(&text[i..body_end])
                        .trim()
                        .to_string();
                    return Ok(false);
                }
            }
            (Parse::AfterMajor, Token::Slash) => {
                st.slash = true;
                *state = Parse::Arg;
            }
            (Parse::Arg, Token::Word) => {
                st.args.push(Arg {
                    value: Value::Word(word()),
                    span,
                });
                *state = Parse::AfterArg;
            }
            (Parse::Arg, Token::Number(v)) => {
                st.args.push(Arg {
                    value: Value::Number(v),
                    span,
                });
                *state = Parse::AfterArg;
            }
            (Parse::AfterArg, Token::Comma) => *state = Parse::Arg,
            (Parse::Major, _) => {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    span,
                    "a statement begins with its major word (GOTO, THREAD, PITCH …)",
                ))
            }
            (Parse::AfterMajor, _) => {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    span,
                    format!("`/` must follow the major word {}", st.major),
                ))
            }
            (Parse::Arg, _) => {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    span,
                    "an argument (a word or a number) is missing here",
                ))
            }
            (Parse::AfterArg, _) => {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    span,
                    "arguments are separated by commas",
                ))
            }
        }
    }
    Ok(continued)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all(src: &str) -> Vec<Result<Statement>> {
        let mut r = Reader::new(src.as_bytes());
        let mut out = Vec::new();
        while let Some(s) = r.next_statement() {
            let failed = s.is_err();
            out.push(s.cloned());
            if failed {
                break;
            }
        }
        out
    }

    #[test]
    fn statements_continuations_and_comments() {
        let src = "$$ header\nPARTNO  M20 thread \nGOTO/ 10, 0, -5.5 $$ start\nTHREAD/ON, $\n  DEPTH, 1.2, $ $$ depth\n CUTS,6\nFINI\n";
        let st = all(src);
        assert_eq!(st.len(), 4);
        let p = st[0].as_ref().unwrap();
        assert_eq!(
            (p.major.as_str(), p.text.as_str()),
            ("PARTNO", "M20 thread")
        );
        let g = st[1].as_ref().unwrap();
        assert_eq!(g.major, "GOTO");
        assert_eq!(g.args[2].number(), Some(-5.5));
        assert_eq!((g.args[2].span.line, g.args[2].span.column), (3, 14));
        let t = st[2].as_ref().unwrap();
        assert_eq!(t.line, 4);
        assert_eq!(t.args.len(), 5);
        assert_eq!(t.args[4].number(), Some(6.0));
        assert_eq!((t.args[4].span.line, t.args[4].span.column), (6, 7));
        assert_eq!(st[3].as_ref().unwrap().major, "FINI");
    }

    #[test]
    fn syntax_errors_have_places() {
        let e = all("GOTO/1,,2\n").pop().unwrap().unwrap_err();
        assert_eq!((e.span.line, e.span.column), (1, 8));
        let e = all("GOTO/1.2.3\n").pop().unwrap().unwrap_err();
        assert_eq!(e.code, Code::Syntax);
        let e = all("P1=POINT/1,2\n").pop().unwrap().unwrap_err();
        assert_eq!((e.span.line, e.span.column), (1, 3));
        let e = all("GOTO/1,$\n").pop().unwrap().unwrap_err();
        assert!(e.message.contains("ends inside"), "{e}");
    }

    #[test]
    fn lower_case_is_upper_cased() {
        let st = all("thread/on,depth,1\n");
        let t = st[0].as_ref().unwrap();
        assert_eq!(t.major, "THREAD");
        assert_eq!(t.args[1].word(), Some("DEPTH"));
    }
}
