//! Line endings: a program written with CRLF gets CRLF on the lines threadcut writes into it.
//!
//! The input's line ending is the ending of its first line ([`LineEnding::of`]); lines copied from
//! the input keep their own bytes, and the lines threadcut generates (an expanded cycle, a
//! converted block, a posted program) take the input's ending through [`Writer`]. `expand` wraps
//! only its generated lines, so that the copied lines of its fast path pass through untouched
//! (docs/performance.md).

use std::io::{self, BufRead, Write};

/// How a program ends its lines.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LineEnding {
    /// `\n` (Unix), and the ending of a program that has no complete first line.
    #[default]
    Lf,
    /// `\r\n` (DOS, Windows, most controllers' own editors).
    CrLf,
}

impl LineEnding {
    /// The ending of the first line in `head` (the start of a program); [`LineEnding::Lf`] when
    /// `head` holds no complete line.
    pub fn of(head: &[u8]) -> LineEnding {
        match memchr::memchr(b'\n', head) {
            Some(i) if i > 0 && head[i - 1] == b'\r' => LineEnding::CrLf,
            _ => LineEnding::Lf,
        }
    }

    /// The ending of the input's first line, looked at without consuming anything (within the
    /// reader's buffer: a first line longer than it counts as [`LineEnding::Lf`]).
    pub fn peek(input: &mut impl BufRead) -> io::Result<LineEnding> {
        Ok(LineEnding::of(input.fill_buf()?))
    }

    pub fn as_str(self) -> &'static str {
        match self {
            LineEnding::Lf => "\n",
            LineEnding::CrLf => "\r\n",
        }
    }
}

/// Writes through to `inner`, turning every `\n` that does not follow a `\r` into `\r\n` when the
/// ending is CRLF (bytes that already end in `\r\n`, such as copied lines, are left as they are);
/// with LF it only passes the bytes on.
pub struct Writer<W: Write> {
    inner: W,
    ending: LineEnding,
    /// The last byte written was `\r`.
    after_cr: bool,
}

impl<W: Write> Writer<W> {
    pub fn new(inner: W, ending: LineEnding) -> Writer<W> {
        Writer {
            inner,
            ending,
            after_cr: false,
        }
    }

    pub fn into_inner(self) -> W {
        self.inner
    }
}

impl<W: Write> Write for Writer<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        if self.ending == LineEnding::Lf || buf.is_empty() {
            return self.inner.write(buf);
        }
        let mut rest = buf;
        while let Some(i) = memchr::memchr(b'\n', rest) {
            let before_cr = if i > 0 {
                rest[i - 1] == b'\r'
            } else {
                self.after_cr
            };
            if before_cr {
                self.inner.write_all(&rest[..=i])?;
            } else {
                self.inner.write_all(&rest[..i])?;
                self.inner.write_all(b"\r\n")?;
            }
            self.after_cr = false;
            rest = &rest[i + 1..];
        }
        if !rest.is_empty() {
            self.inner.write_all(rest)?;
            self.after_cr = rest.last() == Some(&b'\r');
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_line_decides() {
        assert_eq!(LineEnding::of(b"G0 X1\r\nG1 X2\n"), LineEnding::CrLf);
        assert_eq!(LineEnding::of(b"G0 X1\nG1 X2\r\n"), LineEnding::Lf);
        assert_eq!(LineEnding::of(b"\r\n"), LineEnding::CrLf);
        assert_eq!(LineEnding::of(b"\n"), LineEnding::Lf);
        assert_eq!(LineEnding::of(b"G0 X1"), LineEnding::Lf);
        assert_eq!(LineEnding::of(b""), LineEnding::Lf);
    }

    fn through(ending: LineEnding, pieces: &[&[u8]]) -> Vec<u8> {
        let mut w = Writer::new(Vec::new(), ending);
        for p in pieces {
            w.write_all(p).unwrap();
        }
        w.into_inner()
    }

    #[test]
    fn crlf_lines_are_written_with_crlf_once() {
        let crlf = LineEnding::CrLf;
        assert_eq!(through(crlf, &[b"G0 X1\nG1 X2\n"]), b"G0 X1\r\nG1 X2\r\n");
        // Already CRLF (a copied line), also when the CR and the LF come in two writes.
        assert_eq!(through(crlf, &[b"G0 X1\r\n"]), b"G0 X1\r\n");
        assert_eq!(through(crlf, &[b"G0 X1\r", b"\nG1"]), b"G0 X1\r\nG1");
        assert_eq!(through(crlf, &[b"\n", b"\n"]), b"\r\n\r\n");
        assert_eq!(through(crlf, &[b"a\r", b"b\n"]), b"a\rb\r\n");
        assert_eq!(
            through(LineEnding::Lf, &[b"G0 X1\nG1\r\n"]),
            b"G0 X1\nG1\r\n"
        );
    }
}
