//! A streaming line reader: one reused buffer, so memory does not grow with the file.

use std::io::BufRead;

use super::lexer::{
    letter_slot, lex_buffered_line, lex_line_syntax, BufferedLine, LineShape, Syntax, Word,
    WordIndex, WordSummary, FAST_WORDS,
};
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
    /// The input just before this line that is still in the reader's buffer: the ends of the
    /// lines handed out before it (`raw` follows these bytes directly), back to the last time the
    /// reader read more input. A caller can write a run of lines it passes through unchanged with
    /// one write from here (see [`Reader::may_read`]).
    pub before: &'a [u8],
    /// Which letters and G codes the words have, in brief (from the lexer). [`has_g`](Line::has_g)
    /// and the dialects' prefilters trust it: code that builds a `Line` itself sets it with
    /// [`WordSummary::of`]`(words)`.
    pub summary: WordSummary,
    /// Where each letter's last word is in `words` ([`unique_word`](Line::unique_word)).
    pub(crate) index: &'a WordIndex,
}

impl<'a> Line<'a> {
    /// This line with `words` in place of its own (the words a dialect read from a line in its
    /// own syntax), its text, place and shape kept; `index` is filled here.
    pub fn with_words<'b>(&'b self, words: &'b [Word], index: &'b mut WordIndex) -> Line<'b>
    where
        'a: 'b,
    {
        *index = [0; 32];
        super::lexer::index_words(words, index);
        Line {
            words,
            summary: WordSummary::of(words),
            index,
            ..*self
        }
    }
}

impl Line<'_> {
    #[inline]
    pub fn word(&self, letter: u8) -> Option<&Word> {
        self.words.iter().find(|w| w.letter == letter)
    }

    /// Whether the line has a `G` word with this code (codes ×10: `G32` is 320, `G33.1` is 331).
    #[inline]
    pub fn has_g(&self, code: u16) -> bool {
        // Most lines have no G code but G0–G3: the summary says so without a look at the words.
        self.summary.may_have_g(code)
            && self
                .words
                .iter()
                .any(|w| w.letter == b'G' && is_g_code(w.value, code))
    }

    /// Whether no letter begins two words of the line: then [`unique_word`](Line::unique_word)
    /// finds every word.
    #[inline(always)]
    pub fn letters_unique(&self) -> bool {
        self.summary.letters() == self.words.len()
    }

    /// The word this letter begins, in a line whose letters are unique
    /// ([`letters_unique`](Line::letters_unique)); `None` where the line has no such word. Found
    /// through the lexer's index rather than by looking through the words.
    #[inline(always)]
    pub fn unique_word(&self, letter: u8) -> Option<&Word> {
        debug_assert!(self.letters_unique());
        if self.summary.has_letter(letter) {
            self.words.get(self.index[letter_slot(letter)] as usize)
        } else {
            None
        }
    }

    /// A span covering the whole line, for diagnostics about the block rather than one word.
    #[inline]
    pub fn span(&self) -> Span {
        Span::new(self.offset, self.text.len() as u32, self.number, 1)
    }
}

/// A G or M code as an exact integer ×10, or `None` if it has more than one decimal.
#[inline]
pub fn g_code(value: f64) -> Option<u16> {
    if !(0.0..6553.5).contains(&value) {
        return None;
    }
    let scaled = value * 10.0;
    // Rounds to the nearest integer in floating point (adding 1.5 × 2^52 leaves no fraction bits),
    // so that the test below needs no conversion to an integer and back. Only a value within 1e-6
    // of an integer passes it, and for those this is the rounding a `+ 0.5` and cast would give.
    let rounded = (scaled + ROUND) - ROUND;
    if (rounded - scaled).abs() > 1e-6 {
        return None;
    }
    Some(rounded as u16)
}

const ROUND: f64 = 6_755_399_441_055_744.0;

/// `g_code(value) == Some(code)`, without converting to an integer.
#[inline]
pub fn is_g_code(value: f64, code: u16) -> bool {
    (0.0..6553.5).contains(&value) && (f64::from(code) - value * 10.0).abs() <= 1e-6
}

/// How much input is read at a time; the buffer grows beyond this only for a line that does not
/// fit, and never beyond [`MAX_LINE_BYTES`] plus its terminator. Twice the 64 KiB buffers the
/// command line reads and writes through: a request this large bypasses a `BufReader` of that size
/// (no second copy of the input), and a run of pass-through lines written from it bypasses the
/// `BufWriter` (docs/performance.md).
const CHUNK: usize = 1 << 17;

pub struct Reader<R> {
    source: R,
    /// Input read ahead of the lines handed out: the unconsumed part is `buf[start..end]`. Lines
    /// are lexed in place; a line cut off by the end is moved to the front before reading more.
    buf: Vec<u8>,
    start: usize,
    end: usize,
    /// One past the last `\n` in `buf[..end]`: the fast path only sees whole lines, so its input
    /// always ends with a line end (see `lex_buffered_line`).
    complete: usize,
    /// The source has nothing more.
    eof: bool,
    /// The words of a line the reference lexer read.
    words: Vec<Word>,
    /// The words of a line the fast path read (a fixed array: no length or capacity to keep).
    fast_words: [Word; FAST_WORDS],
    /// Where each letter's word is, for the line handed out last (either lexer).
    index: WordIndex,
    line_no: u32,
    offset: u64,
    done: bool,
    syntax: Syntax,
    /// The input consumed so far is still in the buffer, from its first byte (`buf[0]` is the
    /// input's first byte), for the macro interpreter: see [`keep_prefix`](Self::keep_prefix).
    keeping: bool,
    keep_limit: usize,
}

impl<R: BufRead> Reader<R> {
    pub fn new(source: R) -> Reader<R> {
        Reader {
            source,
            buf: Vec::new(),
            start: 0,
            end: 0,
            complete: 0,
            eof: false,
            words: Vec::with_capacity(16),
            fast_words: [Word::EMPTY; FAST_WORDS],
            index: [0; 32],
            line_no: 0,
            offset: 0,
            done: false,
            syntax: Syntax::default(),
            keeping: false,
            keep_limit: 0,
        }
    }

    /// Keeps the input from its start while at most `limit` bytes of it have been consumed: a
    /// program that turns out to have control flow may jump back into it. Nothing is copied for
    /// it: the buffer is made `limit` and a read larger at once (zeroed pages the system hands
    /// out as they are touched), and the consumed input stays where it was read until the buffer
    /// is full or more than `limit` bytes were consumed; from then on the buffer is used as
    /// always.
    /// Called before the first line is read (otherwise nothing is kept).
    pub(crate) fn keep_prefix(&mut self, limit: usize) {
        if self.offset > 0 || self.end > 0 {
            return;
        }
        self.buf = vec![0; limit + CHUNK];
        self.keeping = true;
        self.keep_limit = limit;
    }

    /// The program from the line at `from` (an offset of the line just handed out, still in the
    /// buffer) to the end of the input, read whole, with the input kept before it when all of it
    /// was ([`keep_prefix`](Self::keep_prefix)): the bytes and the offset of their first byte.
    /// `Ok(None)` when the part from `from` on is longer than `cap` bytes.
    pub(crate) fn take_rest(
        &mut self,
        from: u64,
        cap: usize,
    ) -> std::io::Result<Option<(Vec<u8>, u64)>> {
        let back = (self.offset - from) as usize;
        let at = self.start - back;
        // Where the kept beginning still starts the buffer, the text starts at the input's start.
        let kept = self.keeping && at <= self.keep_limit;
        let first = if kept { 0 } else { at };
        let base = if kept { 0 } else { from };
        self.keeping = false;
        let mut bytes = Vec::with_capacity(self.end - first + CHUNK);
        let rest_from = at - first;
        bytes.extend_from_slice(&self.buf[first..self.end]);
        self.start = self.end;
        if !self.eof {
            // The rest, up to one byte past the cap (to tell a longer program), as it comes:
            // `read_to_end` grows the vector as needed, whatever the size of each read.
            let room = (cap + 1).saturating_sub(bytes.len() - rest_from) as u64;
            let mut rest = std::io::Read::take(&mut self.source, room);
            std::io::Read::read_to_end(&mut rest, &mut bytes)?;
            self.eof = true;
        }
        self.done = true;
        if bytes.len() - rest_from > cap {
            return Ok(None);
        }
        Ok(Some((bytes, base)))
    }

    /// Hands the rest of the input, unread, to `f` in pieces (the lines after a program's end,
    /// which no one runs); returns how many line ends it held.
    pub(crate) fn pass_rest<E: From<std::io::Error>>(
        &mut self,
        mut f: impl FnMut(&[u8]) -> Result<(), E>,
    ) -> Result<usize, E> {
        let mut lines = 0;
        loop {
            let piece = &self.buf[self.start..self.end];
            lines += memchr::memchr_iter(b'\n', piece).count();
            if !piece.is_empty() {
                f(piece)?;
            }
            self.start = self.end;
            if self.eof {
                break;
            }
            self.start = 0;
            self.end = 0;
            self.complete = 0;
            if self.buf.len() < CHUNK {
                self.buf.resize(CHUNK, 0);
            }
            let read = loop {
                match self.source.read(&mut self.buf[..]) {
                    Ok(n) => break n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                    Err(e) => return Err(e.into()),
                }
            };
            self.end = read;
            self.eof = read == 0;
        }
        self.done = true;
        Ok(lines)
    }

    /// Reads every line as a controller writes it: its [`Syntax`], which a dialect states in its
    /// [`Conventions::syntax`](super::Conventions::syntax). The fast path takes only lines that
    /// read the same whatever the syntax.
    pub fn with_syntax(mut self, syntax: Syntax) -> Reader<R> {
        self.syntax = syntax;
        self
    }

    /// Bytes consumed so far.
    pub fn offset(&self) -> u64 {
        self.offset
    }

    /// Whether the input read so far is still kept from its start ([`keep_prefix`](Self::keep_prefix)).
    pub(crate) fn keeping_prefix(&self) -> bool {
        self.keeping
    }

    /// The number of the last line handed out (0 before the first).
    pub fn line_number(&self) -> u32 {
        self.line_no
    }

    /// Consumes the next `len` bytes, `lines` whole lines that were read elsewhere (a look
    /// ahead, `program::ahead`), without lexing them. Like lines handed out, they count as
    /// `pending`: bytes right before the next line, which `pass` gets (the earlier pending bytes
    /// first) before the reader reads more input and so drops them from its buffer.
    pub(crate) fn skip<E: From<std::io::Error> + From<Diagnostic>>(
        &mut self,
        len: u64,
        lines: u32,
        pending: &mut usize,
        mut pass: impl FnMut(&[u8]) -> Result<(), E>,
    ) -> Result<(), E> {
        let mut left = len;
        // Each round consumes at least one byte or reads more input: bounded by `len`, and by
        // the input's end (an error: the look ahead read more than there is).
        while left > 0 {
            if self.start == self.end {
                if self.eof || self.done {
                    return Err(std::io::Error::other(
                        "internal error: the lines read ahead are not in the input",
                    )
                    .into());
                }
                if *pending > 0 {
                    pass(&self.buf[self.start - *pending..self.start])?;
                    *pending = 0;
                }
                // (Which of the lines the failed read falls in is not known here: the error
                // names the first line not yet read.)
                let (line, offset) = (self.line_no + 1, self.offset);
                self.refill().map_err(|e| cannot_read(line, offset, &e))?;
                continue;
            }
            let n = left.min((self.end - self.start) as u64) as usize;
            self.start += n;
            self.offset += n as u64;
            *pending += n;
            left -= n as u64;
        }
        self.line_no += lines;
        Ok(())
    }

    /// Whether the next [`next_line`](Self::next_line) may read more input. Reading more drops
    /// the lines already handed out from the buffer: a caller that writes runs of them later (from
    /// [`Line::before`] or [`handed_out`](Self::handed_out)) writes them before that call.
    #[inline(always)]
    pub fn may_read(&self) -> bool {
        // A `\n` lies ahead in the buffer whenever `start < complete`: the next line (or the
        // error it is) is then found without reading.
        !self.done && self.start >= self.complete
    }

    /// The last `n` bytes handed out (the ends of the lines read so far), if they are still in the
    /// buffer: they are until the reader reads more input.
    pub fn handed_out(&self, n: usize) -> Option<&[u8]> {
        self.buf.get(self.start.checked_sub(n)?..self.start)
    }

    /// The next line, lexed. `None` at the end of the input.
    #[inline(always)]
    pub fn next_line(&mut self) -> Option<Result<Line<'_>, Diagnostic>> {
        if self.done {
            return None;
        }
        if let Some(l) = self.lex_in_buffer() {
            return Some(Ok(self.take_fast_line(&l)));
        }
        self.next_line_by_reference()
    }

    /// The next line, lexed by the reference lexer ([`lex_line_syntax`]) whatever it holds: for a
    /// caller that took the lines the fast path reads with
    /// [`next_plain_line`](Self::next_plain_line) already (the two lexers give the same words).
    #[inline(never)]
    pub fn next_line_by_reference(&mut self) -> Option<Result<Line<'_>, Diagnostic>> {
        if self.done {
            return None;
        }
        let line_no = self.line_no + 1;
        let offset = self.offset;
        // Everything else: find the whole line (reading more input if needed) and lex it with
        // the reference lexer.
        let raw_len = match self.line_end(line_no, offset) {
            Ok(Some(len)) => len,
            Ok(None) => {
                self.done = true;
                return None;
            }
            Err(e) => {
                self.done = true;
                return Some(Err(e));
            }
        };
        let raw = &self.buf[self.start..self.start + raw_len];
        let mut text_len = raw.len();
        if raw.last() == Some(&b'\n') {
            text_len -= 1;
            if text_len > 0 && raw[text_len - 1] == b'\r' {
                text_len -= 1;
            }
        }
        match lex_line_syntax(
            &raw[..text_len],
            line_no,
            offset,
            &mut self.words,
            &self.syntax,
        ) {
            Ok(shape) => {
                let summary = WordSummary::of(&self.words);
                super::lexer::index_words(&self.words, &mut self.index);
                Some(Ok(self.take_line(shape, summary, text_len, raw_len, None)))
            }
            Err(_) if self.syntax.hand_over_unread => {
                // The dialect reads the line's own syntax (and reports its errors).
                self.words.clear();
                let shape = LineShape {
                    unread: true,
                    ..LineShape::default()
                };
                Some(Ok(self.take_line(
                    shape,
                    WordSummary::default(),
                    text_len,
                    raw_len,
                    None,
                )))
            }
            Err(e) => {
                // The line is consumed: a caller may go on with the next one.
                self.take_line(
                    LineShape::default(),
                    WordSummary::default(),
                    text_len,
                    raw_len,
                    None,
                );
                Some(Err(e))
            }
        }
    }

    /// The next line if it is one that the lexer's fast path reads where it lies in the buffer
    /// (most lines are); `None` for every other line and at the end, which
    /// [`next_line`](Self::next_line) then reads. The same line `next_line` would give, handed out
    /// without the `Result` around it (a lighter value for a caller's loop to take apart).
    #[inline(always)]
    pub fn next_plain_line(&mut self) -> Option<Line<'_>> {
        if self.done {
            return None;
        }
        let l = self.lex_in_buffer()?;
        Some(self.take_fast_line(&l))
    }

    /// Gives back the line of `raw_len` bytes that [`next_plain_line`](Self::next_plain_line)
    /// has just handed out: the next call reads it again. (For `program`'s run loop, which looks at
    /// a line before deciding to read it another way; only right after that call, hence not public.)
    #[inline(always)]
    pub(crate) fn put_back(&mut self, raw_len: usize) {
        debug_assert!(raw_len <= self.start && self.line_no > 0);
        self.start -= raw_len;
        self.offset -= raw_len as u64;
        self.line_no -= 1;
    }

    /// Fast path: a plain line wholly in the buffer is lexed where it lies, its end found on the
    /// way. (A letter with a number right after it is never a bare flag, and `lex_buffered_line`
    /// leaves every other letter to the reference lexer.)
    #[inline(always)]
    fn lex_in_buffer(&mut self) -> Option<BufferedLine> {
        lex_buffered_line(
            self.buf.get(self.start..self.complete).unwrap_or_default(),
            self.line_no + 1,
            self.offset,
            &mut self.fast_words,
            &mut self.index,
            self.syntax.parens_not_comments,
        )
    }

    /// Consumes the line the fast path lexed.
    #[inline(always)]
    fn take_fast_line(&mut self, l: &BufferedLine) -> Line<'_> {
        self.take_line(l.shape, l.summary, l.text_len, l.raw_len, Some(l.words))
    }

    /// Consumes the line of `raw_len` bytes at the front of the buffer.
    #[inline(always)]
    fn take_line(
        &mut self,
        shape: LineShape,
        summary: WordSummary,
        text_len: usize,
        raw_len: usize,
        fast_words: Option<usize>,
    ) -> Line<'_> {
        let start = self.start;
        self.start += raw_len;
        self.line_no += 1;
        let offset = self.offset;
        self.offset += raw_len as u64;
        let (before, rest) = self.buf.split_at(start);
        let raw = &rest[..raw_len];
        Line {
            number: self.line_no,
            offset,
            text: &raw[..text_len],
            raw,
            words: match fast_words {
                Some(n) => &self.fast_words[..n],
                None => &self.words,
            },
            shape,
            before,
            summary,
            index: &self.index,
        }
    }

    /// The length of the next line, terminator included, once it is wholly in the buffer; `None`
    /// at the end of the input.
    fn line_end(&mut self, line_no: u32, offset: u64) -> Result<Option<usize>, Diagnostic> {
        // A line (terminator included) may have MAX_LINE_BYTES + 2 bytes: `\r\n` after the limit.
        const LIMIT: usize = MAX_LINE_BYTES + 2;
        let too_long = || {
            Diagnostic::error(
                Code::Input,
                Span::new(offset, 1, line_no, 1),
                format!("line {line_no} is longer than {MAX_LINE_BYTES} bytes"),
            )
            .with_hint("is this a G-code file? Lines end with a newline")
        };
        let mut searched = 0;
        loop {
            let available = &self.buf[self.start..self.end];
            if let Some(i) = memchr::memchr(b'\n', &available[searched..]) {
                let len = searched + i + 1;
                return if len > LIMIT {
                    Err(too_long())
                } else {
                    Ok(Some(len))
                };
            }
            searched = available.len();
            if available.len() >= LIMIT {
                return Err(too_long());
            }
            if self.eof {
                return Ok((!available.is_empty()).then_some(available.len()));
            }
            self.refill()
                .map_err(|e| cannot_read(line_no, offset, &e))?;
        }
    }

    /// Moves the unconsumed input to the front of the buffer and reads more after it.
    fn refill(&mut self) -> std::io::Result<()> {
        // The kept beginning stays in place while the buffer has room after it; a read that
        // would need more is the end of keeping it.
        let keep_in_place =
            self.keeping && self.start <= self.keep_limit && self.end < self.buf.len();
        if self.start > 0 && !keep_in_place {
            self.keeping = false;
            self.buf.copy_within(self.start..self.end, 0);
            self.end -= self.start;
            self.complete = self.complete.saturating_sub(self.start);
            self.start = 0;
        }
        if self.end == self.buf.len() {
            // Full: only a line longer than the buffer gets here. Grow towards the line limit.
            let len = (self.buf.len() * 2).clamp(CHUNK, MAX_LINE_BYTES + 2 + CHUNK);
            self.buf.resize(len, 0);
        }
        // At most a chunk a read, also into the larger buffer of a kept beginning: a caller that
        // counts what was read (a progress bar) sees the input come in steps.
        let stop = (self.end + CHUNK).min(self.buf.len());
        let read = loop {
            match self.source.read(&mut self.buf[self.end..stop]) {
                Ok(n) => break n,
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            }
        };
        // Only the new bytes are searched, so that a source handing out a few bytes at a time
        // costs no more than one reading a lot.
        if let Some(i) = memchr::memrchr(b'\n', &self.buf[self.end..self.end + read]) {
            self.complete = self.end + i + 1;
        }
        self.end += read;
        self.eof = read == 0;
        Ok(())
    }
}

/// The input could not be read at line `line_no`.
fn cannot_read(line_no: u32, offset: u64, e: &std::io::Error) -> Diagnostic {
    Diagnostic::error(
        Code::Input,
        Span::new(offset, 0, line_no, 1),
        format!("cannot read the input: {e}"),
    )
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

    /// A source that hands out at most `step` bytes a read, so that lines straddle reads.
    struct Trickle<'a> {
        data: &'a [u8],
        step: usize,
    }

    impl std::io::Read for Trickle<'_> {
        fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
            let n = self.step.min(out.len()).min(self.data.len());
            out[..n].copy_from_slice(&self.data[..n]);
            self.data = &self.data[n..];
            Ok(n)
        }
    }

    impl BufRead for Trickle<'_> {
        fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
            Ok(&self.data[..self.step.min(self.data.len())])
        }
        fn consume(&mut self, n: usize) {
            self.data = &self.data[n..];
        }
    }

    type Lexed = (
        u32,
        u64,
        Vec<u8>,
        Vec<u8>,
        Result<(Vec<Word>, LineShape, WordSummary), Diagnostic>,
    );

    /// What the reader gives for every line. `before` and `handed_out` must be the input right
    /// before the line and right after the last one: `input` is the whole input, to check them.
    fn read_all(source: impl BufRead, syntax: Syntax, input: &[u8]) -> Vec<Lexed> {
        let mut r = Reader::new(source).with_syntax(syntax);
        let mut got = vec![];
        let mut last = 0;
        loop {
            let here = r.offset() as usize;
            let may_read = r.may_read();
            // The most bytes still handed out (`handed_out(n)` is there for every n up to it).
            let kept = {
                let (mut lo, mut hi) = (0, here);
                while lo < hi {
                    let mid = (lo + hi).div_ceil(2);
                    if r.handed_out(mid).is_some() {
                        lo = mid;
                    } else {
                        hi = mid - 1;
                    }
                }
                lo
            };
            for n in [0, kept / 2, kept] {
                assert_eq!(r.handed_out(n), Some(&input[here - n..here]));
            }
            assert_eq!(r.handed_out(kept + 1), None);
            let Some(l) = r.next_line() else { break };
            got.push(match l {
                Ok(l) => {
                    last = l.number;
                    check_index(&l);
                    let at = l.offset as usize;
                    assert_eq!(l.before, &input[at - l.before.len()..at]);
                    if !may_read {
                        // Nothing was read: what was handed out is still there.
                        assert_eq!(l.before.len(), kept);
                    }
                    (
                        l.number,
                        l.offset,
                        l.text.to_vec(),
                        l.raw.to_vec(),
                        Ok((l.words.to_vec(), l.shape, l.summary)),
                    )
                }
                Err(e) => {
                    last += 1;
                    (last, 0, vec![], vec![], Err(e))
                }
            });
        }
        got
    }

    /// The line's word index: each letter's last word, whichever lexer read the line; and
    /// `unique_word` finds each word of a line whose letters are unique.
    fn check_index(l: &Line) {
        for w in l.words {
            let last = l.words.iter().rposition(|v| v.letter == w.letter).unwrap();
            assert_eq!(
                l.index[letter_slot(w.letter)] as usize,
                last,
                "{:?}",
                l.text
            );
        }
        let unique =
            (1..l.words.len()).all(|i| l.words[..i].iter().all(|v| v.letter != l.words[i].letter));
        assert_eq!(l.letters_unique(), unique, "{:?}", l.text);
        if unique {
            for w in l.words {
                assert_eq!(l.unique_word(w.letter), Some(w));
            }
        }
    }

    /// What the reader gives when the caller asks `next_plain_line` first, as `drive` does: the
    /// lines `put_back` picks (by their number) are given back and read again, and every line the
    /// fast path does not read is read with `next_line_by_reference`.
    fn read_plain_first(
        source: impl BufRead,
        syntax: Syntax,
        put_back: impl Fn(u32) -> bool,
    ) -> Vec<Lexed> {
        let mut r = Reader::new(source).with_syntax(syntax);
        let mut got = vec![];
        let mut last = 0;
        loop {
            if let Some(l) = r.next_plain_line() {
                if put_back(l.number) {
                    let len = l.raw.len();
                    r.put_back(len);
                } else {
                    last = l.number;
                    check_index(&l);
                    got.push((
                        l.number,
                        l.offset,
                        l.text.to_vec(),
                        l.raw.to_vec(),
                        Ok((l.words.to_vec(), l.shape, l.summary)),
                    ));
                    continue;
                }
            }
            let l = match r.next_line_by_reference() {
                Some(l) => l,
                None => break,
            };
            got.push(match l {
                Ok(l) => {
                    last = l.number;
                    (
                        l.number,
                        l.offset,
                        l.text.to_vec(),
                        l.raw.to_vec(),
                        Ok((l.words.to_vec(), l.shape, l.summary)),
                    )
                }
                Err(e) => {
                    last += 1;
                    (last, 0, vec![], vec![], Err(e))
                }
            });
        }
        got
    }

    /// The same, line by line with the reference lexer: split at `\n`, drop the terminator. Under
    /// `hand_over_unread`, a line the lexer refuses comes without words, marked unread.
    fn reference(src: &[u8], syntax: Syntax) -> Vec<Lexed> {
        let mut got = vec![];
        let mut offset = 0u64;
        for (i, raw) in src.split_inclusive(|&b| b == b'\n').enumerate() {
            let mut text = raw.strip_suffix(b"\n").unwrap_or(raw);
            if raw.ends_with(b"\n") {
                text = text.strip_suffix(b"\r").unwrap_or(text);
            }
            let mut words = vec![];
            let n = i as u32 + 1;
            got.push(
                match lex_line_syntax(text, n, offset, &mut words, &syntax) {
                    Ok(shape) => {
                        let summary = WordSummary::of(&words);
                        (
                            n,
                            offset,
                            text.to_vec(),
                            raw.to_vec(),
                            Ok((words, shape, summary)),
                        )
                    }
                    Err(_) if syntax.hand_over_unread => {
                        let shape = LineShape {
                            unread: true,
                            ..LineShape::default()
                        };
                        (
                            n,
                            offset,
                            text.to_vec(),
                            raw.to_vec(),
                            Ok((vec![], shape, WordSummary::default())),
                        )
                    }
                    Err(e) => (n, 0, vec![], vec![], Err(e)),
                },
            );
            offset += raw.len() as u64;
        }
        got
    }

    proptest::proptest! {
        /// The reader's fast path (lexing in its buffer, finding the line end on the way) gives
        /// exactly what the reference lexer gives for each line, errors included, however the
        /// input is cut into reads, and a line given back is read again the same.
        #[test]
        fn buffered_lexing_is_the_reference(
            text in proptest::collection::vec(
                proptest::sample::select(b"GXZUWPCNF0123456789.-+ \t\r\n\n\n();%/#eg$\xc3".to_vec()),
                0..300,
            ),
            step in 1usize..40,
            flags in proptest::bool::ANY,
            blanks in proptest::bool::ANY,
            sinumerik in proptest::bool::ANY,
        ) {
            // Bare flags (OmniTurn); blanks that mean nothing and nested comments refused
            // (LinuxCNC); parentheses that are no comments and unreadable lines handed over
            // (Sinumerik); or none of them.
            let syntax = Syntax {
                bare: if flags { b"PC" } else { b"" },
                blanks_anywhere: blanks && !flags,
                nested_comment_error: blanks && !flags,
                parens_not_comments: sinumerik && !flags && !blanks,
                hand_over_unread: sinumerik && !flags && !blanks,
            };
            let want = reference(&text, syntax);
            proptest::prop_assert_eq!(read_all(&text[..], syntax, &text), want.clone());
            proptest::prop_assert_eq!(read_all(Trickle { data: &text, step }, syntax, &text), want.clone());
            let none = |_| false;
            let some = |n: u32| n % 3 == 1;
            proptest::prop_assert_eq!(read_plain_first(&text[..], syntax, none), want.clone());
            proptest::prop_assert_eq!(read_plain_first(&text[..], syntax, some), want.clone());
            proptest::prop_assert_eq!(
                read_plain_first(Trickle { data: &text, step }, syntax, some),
                want
            );
        }
    }

    #[test]
    fn lines_across_reads_and_longer_than_the_buffer() {
        let long = format!("G1 X1 ({})\r\n", "c".repeat(3 * CHUNK));
        let src = format!("G0 X10 Z5\n{long}G1 Z-2.5 (FACE)\nU-0.4 ; rest\nM30");
        let want = reference(src.as_bytes(), Syntax::default());
        assert_eq!(want.len(), 5);
        assert_eq!(
            read_all(src.as_bytes(), Syntax::default(), src.as_bytes()),
            want
        );
        for step in [1, 7, 4096, CHUNK - 3, CHUNK + 5] {
            let trickle = Trickle {
                data: src.as_bytes(),
                step,
            };
            assert_eq!(
                read_all(trickle, Syntax::default(), src.as_bytes()),
                want,
                "step {step}"
            );
        }
    }

    #[test]
    fn line_length_limit() {
        // A line of MAX_LINE_BYTES bytes with `\r\n` is read; one byte more is refused, with or
        // without a terminator.
        let ok = format!("({})\r\nG0 X1\n", "c".repeat(MAX_LINE_BYTES - 2));
        let got = read_all(ok.as_bytes(), Syntax::default(), ok.as_bytes());
        assert_eq!(got.len(), 2);
        assert!(got.iter().all(|l| l.4.is_ok()));
        for tail in ["\r\n", ""] {
            let bad = format!("G0 X1\n({}){tail}", "c".repeat(MAX_LINE_BYTES));
            let mut r = Reader::new(bad.as_bytes());
            assert!(r.next_line().unwrap().is_ok());
            let e = r.next_line().unwrap().err().unwrap();
            assert_eq!((e.code, e.span.line, e.span.start), (Code::Input, 2, 6));
            assert!(r.next_line().is_none());
        }
    }

    #[test]
    fn over_long_line_is_refused() {
        let src = vec![b'X'; MAX_LINE_BYTES + 10];
        let mut r = Reader::new(&src[..]);
        let e = r.next_line().unwrap().err().unwrap();
        assert_eq!(e.code, Code::Input);
    }

    #[test]
    fn g_code_tests_agree() {
        // `is_g_code` and the rounding in `g_code` against the plain definition: the nearest
        // integer of value × 10, if it lies within 1e-6.
        let reference = |v: f64| -> Option<u16> {
            if !(0.0..6553.5).contains(&v) {
                return None;
            }
            let tenths = (v * 10.0 + 0.5) as u16;
            ((f64::from(tenths) - v * 10.0).abs() <= 1e-6).then_some(tenths)
        };
        let mut values = vec![
            0.0, -0.0, 1.0, 33.1, 78.0, 6553.4, 6553.49, 6553.5, 1.25, 0.05,
        ];
        for k in 0..65536u32 {
            let t = f64::from(k) / 10.0;
            values.extend([t, t + 4e-8, t - 4e-8, t + 2e-7, t + 0.05, t + 1e-3]);
        }
        values.extend([f64::NAN, f64::INFINITY, -1.0, 1e300, 5e-324]);
        for v in values {
            let want = reference(v);
            assert_eq!(g_code(v), want, "{v}");
            for code in [0, 10, 320, 331, 780, 65534, 65535] {
                assert_eq!(is_g_code(v, code), want == Some(code), "{v} {code}");
            }
            if let Some(c) = want {
                assert!(is_g_code(v, c), "{v}");
            }
        }
    }

    #[test]
    fn word_summaries() {
        // The line after a first one, so that the lexer's fast path reads it (the first line of
        // an input comes before anything is buffered and goes the reference way).
        let summary = |text: &str| {
            let src = format!("(first)\n{text}");
            let mut r = Reader::new(src.as_bytes());
            assert!(r.next_line().unwrap().is_ok());
            let l = r.next_line().unwrap().unwrap();
            assert_eq!(l.summary, WordSummary::of(l.words), "{text}");
            l.summary
        };
        let s = summary("N10 G01 x1.5 Z-2 f0.1\n");
        for (letter, has) in [
            (b'N', true),
            (b'G', true),
            (b'X', true),
            (b'Z', true),
            (b'F', true),
            (b'U', false),
            (b'A', false),
            (b'$', false),
            (b'x', false),
        ] {
            assert_eq!(s.has_letter(letter), has, "{}", letter as char);
        }
        // G0–G3 as whole numbers are the plain motion codes; anything else is "other".
        for (text, other) in [
            ("G0 G1 G2 G3 G00 G03 G+2 X1", false),
            ("X1 Z2 ; G78", false),
            ("G1 (G78) X1", false),
            ("G4 X1", true),
            ("G1.0 X1", true),
            ("G1. X1", true),
            ("G-0 X1", true),
            ("G-1", true),
            ("G3.5", true),
            ("g78 P1", true),
            ("G1 G78 X1", true),
            ("G 78 X1", true),
            ("G76 X1 $1", true),
        ] {
            let s = summary(&format!("{text}\n"));
            assert_eq!(s.other_g(), other, "{text}");
            assert_eq!(s.may_have_g(780), other, "{text}");
            assert!(s.may_have_g(10) == s.has_letter(b'G'), "{text}");
        }
        assert!(summary("G76 X1 $1\n").has_letter(b'$'));
        assert_eq!(summary("(only a comment)\n"), WordSummary::default());
    }

    #[test]
    fn g_codes_as_tenths() {
        assert_eq!(g_code(33.1), Some(331));
        assert_eq!(g_code(0.0), Some(0));
        assert_eq!(g_code(1.25), None);
        assert_eq!(g_code(-1.0), None);
    }

    /// The beginning a reader keeps for a jump back: while at most `limit` bytes were consumed
    /// the rest handed to the interpreter starts at the input's first byte; past the limit it
    /// starts at the line handed over. Reads stay a chunk at most (a progress bar sees them).
    #[test]
    fn a_kept_beginning_stays_in_place_up_to_its_limit() {
        let line = b"G1 X1.234 Z-5.678 F0.2\n"; // 23 bytes
        let src: Vec<u8> = line.repeat(20_000); // 460,000 bytes: several chunks
        for step in [7, 4096, CHUNK, 3 * CHUNK] {
            for (limit, want_base) in [(300_000usize, 0u64), (100_000, 1)] {
                let mut r = Reader::new(Trickle { data: &src, step });
                r.keep_prefix(limit);
                // The line at offset 200,008 (line 8,697): within the first limit, past the second.
                let mut offset = 0;
                while let Some(l) = r.next_line() {
                    let l = l.unwrap();
                    if l.number == 8_697 {
                        offset = l.offset;
                        break;
                    }
                }
                assert_eq!(offset, 8_696 * 23);
                let (bytes, base) = r.take_rest(offset, 1 << 20).unwrap().unwrap();
                let base_want = if want_base == 0 { 0 } else { offset };
                assert_eq!(base, base_want, "step {step} limit {limit}");
                assert_eq!(
                    &bytes[..],
                    &src[base as usize..],
                    "step {step} limit {limit}"
                );
            }
        }
        // Reads into the kept beginning's buffer take a chunk at most.
        struct Counting<'a>(&'a [u8], usize);
        impl std::io::Read for Counting<'_> {
            fn read(&mut self, out: &mut [u8]) -> std::io::Result<usize> {
                self.1 = self.1.max(out.len());
                let n = out.len().min(self.0.len());
                out[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        impl BufRead for Counting<'_> {
            fn fill_buf(&mut self) -> std::io::Result<&[u8]> {
                Ok(self.0)
            }
            fn consume(&mut self, n: usize) {
                self.0 = &self.0[n..];
            }
        }
        let mut source = Counting(&src, 0);
        let mut r = Reader::new(&mut source);
        r.keep_prefix(1 << 20);
        while r.next_line().is_some() {}
        drop(r);
        assert!(source.1 <= CHUNK, "{}", source.1);
    }
}
