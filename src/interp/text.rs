//! The text of a program held in memory for the interpreter: its bytes and where each line lies.

use crate::diag::Span;

/// A program's text from some line on (the first line the run loop still had, or the whole
/// program): the bytes and a table of lines. Line numbers and byte offsets are the input's own.
pub struct Text {
    bytes: Vec<u8>,
    /// Number of the first line held.
    first_line: u32,
    /// Offset in the input of the first byte held.
    base: u64,
    /// Each line: where it starts in `bytes`, the length of its text and of its terminator.
    lines: Vec<LineAt>,
}

#[derive(Clone, Copy)]
struct LineAt {
    start: u32,
    text_len: u32,
    end_len: u8,
}

/// One line of a [`Text`].
#[derive(Clone, Copy)]
pub struct TextLine<'t> {
    /// 1-based line number in the input.
    pub number: u32,
    /// Byte offset of the line in the input.
    pub offset: u64,
    /// The line without its terminator.
    pub text: &'t [u8],
    /// The line as read, terminator included.
    pub raw: &'t [u8],
}

impl TextLine<'_> {
    /// The span of `len` bytes at byte `at` of the line.
    pub fn span(&self, at: usize, len: usize) -> Span {
        Span::new(
            self.offset + at as u64,
            len.min(u32::MAX as usize) as u32,
            self.number,
            at as u32 + 1,
        )
    }

    /// A span covering the whole line.
    pub fn whole(&self) -> Span {
        self.span(0, self.text.len())
    }
}

impl Text {
    /// `bytes` start at line `first_line`, at offset `base` of the input. (At most 4 GiB: the
    /// interpreter refuses programs far smaller than that.)
    pub fn new(bytes: Vec<u8>, first_line: u32, base: u64) -> Text {
        let mut lines = Vec::new();
        let mut start = 0usize;
        while start < bytes.len() {
            let end = memchr::memchr(b'\n', &bytes[start..]).map_or(bytes.len(), |i| start + i + 1);
            let raw = &bytes[start..end];
            let mut text_len = raw.len();
            if raw.last() == Some(&b'\n') {
                text_len -= 1;
                if text_len > 0 && raw[text_len - 1] == b'\r' {
                    text_len -= 1;
                }
            }
            lines.push(LineAt {
                start: start as u32,
                text_len: text_len as u32,
                end_len: (raw.len() - text_len) as u8,
            });
            start = end;
        }
        Text {
            bytes,
            first_line,
            base,
            lines,
        }
    }

    /// How many lines are held.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// The `i`th line held (0-based).
    pub fn line(&self, i: usize) -> TextLine<'_> {
        let l = self.lines[i];
        let start = l.start as usize;
        let text_end = start + l.text_len as usize;
        TextLine {
            number: self.first_line + i as u32,
            offset: self.base + start as u64,
            text: &self.bytes[start..text_end],
            raw: &self.bytes[start..text_end + usize::from(l.end_len)],
        }
    }

    /// The index of line number `number`, if it is held.
    pub fn index_of(&self, number: u32) -> Option<usize> {
        let i = number.checked_sub(self.first_line)? as usize;
        (i < self.lines.len()).then_some(i)
    }

    /// The bytes from line index `i` to the end.
    pub fn bytes_from(&self, i: usize) -> &[u8] {
        match self.lines.get(i) {
            Some(l) => &self.bytes[l.start as usize..],
            None => &[],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_numbers_offsets_and_terminators() {
        let t = Text::new(b"G0 X1\r\n\nM30".to_vec(), 5, 100);
        assert_eq!(t.len(), 3);
        let l = t.line(0);
        assert_eq!(
            (l.number, l.offset, l.text, l.raw),
            (5, 100, &b"G0 X1"[..], &b"G0 X1\r\n"[..])
        );
        let l = t.line(1);
        assert_eq!(
            (l.number, l.offset, l.text, l.raw),
            (6, 107, &b""[..], &b"\n"[..])
        );
        let l = t.line(2);
        assert_eq!((l.number, l.text, l.raw), (7, &b"M30"[..], &b"M30"[..]));
        assert_eq!(t.index_of(6), Some(1));
        assert_eq!(t.index_of(4), None);
        assert_eq!(t.bytes_from(1), b"\nM30");
        assert_eq!(l.span(1, 2), Span::new(109, 2, 7, 2));
    }
}
