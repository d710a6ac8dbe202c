//! A macro line as the front ends read it: blanks and comments taken out, letters in upper case,
//! each character keeping its column in the source line (so that every diagnostic still points
//! at the text as written).

use crate::diag::{Code, Diagnostic, Span};

use super::text::TextLine;

/// The characters of a line a front end reads.
pub struct Squeezed<'t> {
    pub line: TextLine<'t>,
    chars: Vec<u8>,
    /// Column (0-based byte offset in the line) of each character.
    cols: Vec<u32>,
    /// Whether the line begins with `/` (block delete).
    pub block_delete: bool,
    /// Whether the line is a `%` delimiter.
    pub percent: bool,
}

impl<'t> Squeezed<'t> {
    /// Squeezes a line: comments `( … )` and everything after `;` go, and so do blanks (both
    /// front ends ignore them outside comments: LinuxCNC everywhere, Fanuc between the parts of a
    /// macro statement).
    pub fn new(line: TextLine<'t>) -> Result<Squeezed<'t>, Diagnostic> {
        let text = line.text;
        let mut chars = Vec::with_capacity(text.len());
        let mut cols = Vec::with_capacity(text.len());
        let mut i = 0;
        while i < text.len() {
            match text[i] {
                b' ' | b'\t' | b'\r' | 0x0c => i += 1,
                b'(' => match memchr::memchr(b')', &text[i + 1..]) {
                    Some(close) => i += close + 2,
                    None => {
                        return Err(Diagnostic::error(
                            Code::Syntax,
                            line.span(i, text.len() - i),
                            "comment is not closed",
                        )
                        .with_hint("close the comment with `)` on the same line"))
                    }
                },
                b';' => break,
                c => {
                    chars.push(c.to_ascii_uppercase());
                    cols.push(i as u32);
                    i += 1;
                }
            }
        }
        let mut s = Squeezed {
            line,
            chars,
            cols,
            block_delete: false,
            percent: false,
        };
        if s.chars.first() == Some(&b'/') {
            s.block_delete = true;
        }
        s.percent = s.chars == b"%";
        Ok(s)
    }

    pub fn len(&self) -> usize {
        self.chars.len()
    }

    /// The character at `i`, or 0 past the end.
    #[inline]
    pub fn at(&self, i: usize) -> u8 {
        self.chars.get(i).copied().unwrap_or(0)
    }

    /// Whether the characters at `i` are `word` (upper case).
    pub fn starts_with(&self, i: usize, word: &[u8]) -> bool {
        self.chars.get(i..i + word.len()) == Some(word)
    }

    /// The span of the characters `from..to` (at least one character; the end of the line when
    /// `from` is past it).
    pub fn span(&self, from: usize, to: usize) -> Span {
        let n = self.cols.len();
        if n == 0 {
            return self.line.span(self.line.text.len(), 0);
        }
        if from >= n {
            let end = self.cols[n - 1] as usize + 1;
            return self.line.span(end, 0);
        }
        let start = self.cols[from] as usize;
        let last = self.cols[to.clamp(from + 1, n) - 1] as usize;
        self.line.span(start, last + 1 - start)
    }

    /// The source text of the characters `from..to`, as written (blanks and all).
    pub fn source(&self, from: usize, to: usize) -> &'t [u8] {
        let s = self.span(from, to);
        let start = (s.column as usize).saturating_sub(1);
        &self.line.text[start..(start + s.len as usize).min(self.line.text.len())]
    }

    /// An error at the characters `from..to`.
    pub fn error(&self, from: usize, to: usize, msg: impl Into<String>) -> Diagnostic {
        Diagnostic::error(Code::Syntax, self.span(from, to), msg)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::interp::text::Text;

    #[test]
    fn blanks_and_comments_go_columns_stay() {
        let t = Text::new(b"  o100 if [#1 gt 2] (x) ; rest\n".to_vec(), 3, 10);
        let s = Squeezed::new(t.line(0)).unwrap();
        assert_eq!(&s.chars, b"O100IF[#1GT2]");
        assert_eq!(s.span(4, 6), Span::new(17, 2, 3, 8));
        assert_eq!(s.source(6, 13), b"[#1 gt 2]");
        assert!(!s.block_delete);
        let t = Text::new(b"G0 (open".to_vec(), 1, 0);
        assert!(Squeezed::new(t.line(0)).is_err());
    }
}
