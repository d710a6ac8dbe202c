//! A streaming line reader: one reused buffer, so memory does not grow with the file.

use std::io::{BufRead, Read};

use super::lexer::{lex_line_with, LineShape, Word};
use crate::diag::{Code, Diagnostic, Span};

/// Lines longer than this are refused rather than buffered whole.
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// One lexed line. `raw` keeps the line terminator so that pass-through output is byte for byte.
pub struct Line<'a> {
    pub number: u32,
    pub offset: u64,
    /// The line without its terminator (`\n` or `\r\n`).
    pub text: &'a [u8],
    /// The line exactly as read, terminator included.
    pub raw: &'a [u8],
    pub words: &'a [Word],
    pub shape: LineShape,
}

impl Line<'_> {
    pub fn word(&self, letter: u8) -> Option<&Word> {
        self.words.iter().find(|w| w.letter == letter)
    }

    /// Whether the line has a `G` word with this code (codes ×10: `G32` is 320, `G33.1` is 331).
    pub fn has_g(&self, code: u16) -> bool {
        self.words
            .iter()
            .any(|w| w.letter == b'G' && g_code(w.value) == Some(code))
    }

    /// A span covering the whole line, for diagnostics about the block rather than one word.
    pub fn span(&self) -> Span {
        Span::new(self.offset, self.text.len() as u32, self.number, 1)
    }
}

/// A G or M code as an exact integer ×10, or `None` if it has more than one decimal.
pub fn g_code(value: f64) -> Option<u16> {
    if !(0.0..6553.5).contains(&value) {
        return None;
    }
    // A cast truncates; adding a half rounds the non-negative value without a libm call.
    let scaled = value * 10.0;
    let tenths = (scaled + 0.5) as u16;
    if (f64::from(tenths) - scaled).abs() > 1e-6 {
        return None;
    }
    Some(tenths)
}

pub struct Reader<R> {
    source: R,
    /// Holds a line only when it straddles the source's buffer; most lines are lexed in place.
    buf: Vec<u8>,
    words: Vec<Word>,
    line_no: u32,
    offset: u64,
    /// Bytes of the previous line still to be consumed from the source's buffer.
    pending: usize,
    done: bool,
    bare: &'static [u8],
}

impl<R: BufRead> Reader<R> {
    pub fn new(source: R) -> Reader<R> {
        Reader {
            source,
            buf: Vec::with_capacity(256),
            words: Vec::with_capacity(16),
            line_no: 0,
            offset: 0,
            pending: 0,
            done: false,
            bare: b"",
        }
    }

    /// Lets these letters stand without a number (see [`lex_line_with`](super::lexer::lex_line_with)).
    pub fn with_bare_letters(mut self, bare: &'static [u8]) -> Reader<R> {
        self.bare = bare;
        self
    }

    /// Bytes consumed so far.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// The next line, lexed. `None` at the end of the input.
    pub fn next_line(&mut self) -> Option<Result<Line<'_>, Diagnostic>> {
        if self.done {
            return None;
        }
        self.source.consume(std::mem::take(&mut self.pending));
        let line_no = self.line_no + 1;
        let offset = self.offset;
        let io_error = |e: std::io::Error| {
            Diagnostic::error(
                Code::Input,
                Span::new(offset, 0, line_no, 1),
                format!("cannot read the input: {e}"),
            )
        };
        // Fast path: the whole line sits in the source's buffer; lex it there without copying.
        let in_place = match self.source.fill_buf() {
            Err(e) => {
                self.done = true;
                return Some(Err(io_error(e)));
            }
            Ok([]) => {
                self.done = true;
                return None;
            }
            Ok(available) => memchr::memchr(b'\n', available).map(|i| i + 1),
        };
        let raw: &[u8] = match in_place {
            Some(len) if len <= MAX_LINE_BYTES + 1 => {
                self.pending = len;
                &self.source.fill_buf().expect("filled above")[..len]
            }
            _ => {
                self.buf.clear();
                let limit = (MAX_LINE_BYTES + 2) as u64;
                if let Err(e) = (&mut self.source)
                    .take(limit)
                    .read_until(b'\n', &mut self.buf)
                {
                    self.done = true;
                    return Some(Err(io_error(e)));
                }
                if self.buf.last() != Some(&b'\n') && self.buf.len() as u64 >= limit {
                    self.done = true;
                    return Some(Err(Diagnostic::error(
                        Code::Input,
                        Span::new(offset, 1, line_no, 1),
                        format!("line {line_no} is longer than {MAX_LINE_BYTES} bytes"),
                    )
                    .with_hint("is this a G-code file? Lines end with a newline")));
                }
                &self.buf
            }
        };
        self.line_no = line_no;
        self.offset += raw.len() as u64;
        let mut text_len = raw.len();
        if raw.last() == Some(&b'\n') {
            text_len -= 1;
            if text_len > 0 && raw[text_len - 1] == b'\r' {
                text_len -= 1;
            }
        }
        let text = &raw[..text_len];
        match lex_line_with(text, line_no, offset, &mut self.words, self.bare) {
            Ok(shape) => Some(Ok(Line {
                number: line_no,
                offset,
                text,
                raw,
                words: &self.words,
                shape,
            })),
            Err(e) => Some(Err(e)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_keep_raw_bytes_and_numbers() {
        let src = b"G0 X10\r\nG32 Z-5 F2\nM30";
        let mut r = Reader::new(&src[..]);
        let l = r.next_line().unwrap().unwrap();
        assert_eq!(
            (l.number, l.text, l.raw),
            (1, &b"G0 X10"[..], &b"G0 X10\r\n"[..])
        );
        let l = r.next_line().unwrap().unwrap();
        assert_eq!(l.number, 2);
        assert!(l.has_g(320));
        assert_eq!(l.offset, 8);
        let l = r.next_line().unwrap().unwrap();
        assert_eq!(l.raw, b"M30");
        assert!(r.next_line().is_none());
    }

    #[test]
    fn over_long_line_is_refused() {
        let src = vec![b'X'; MAX_LINE_BYTES + 10];
        let mut r = Reader::new(&src[..]);
        let e = r.next_line().unwrap().err().unwrap();
        assert_eq!(e.code, Code::Input);
    }

    #[test]
    fn g_codes_as_tenths() {
        assert_eq!(g_code(33.1), Some(331));
        assert_eq!(g_code(0.0), Some(0));
        assert_eq!(g_code(1.25), None);
        assert_eq!(g_code(-1.0), None);
    }
}
