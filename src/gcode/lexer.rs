//! A byte-level lexer for one line of G-code.
//!
//! It represents what was written, not what the machine will do: letters, numbers (exact `f64` plus the
//! raw lexeme, so digit-packed words like GSK's `P020545` and the "no decimal point" conventions can be
//! decoded by the dialect), comments, `N` numbers, `/` block delete and `%`. A hand-written lexer is
//! the fastest choice measured on this machine kind (see `docs/performance.md`) and keeps spans exact.

use crate::diag::{Code, Diagnostic, Span};

/// One address word, such as `X-12.5`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Word {
    /// The address letter, upper case.
    pub letter: u8,
    /// The value, parsed exactly (correctly rounded).
    pub value: f64,
    /// Whether the number was written with a decimal point.
    pub has_dot: bool,
    /// Blanks between the letter and the number (mostly none). The number's lexeme is the rest of
    /// the span after them: it is kept this way rather than as its own offset and length, which
    /// the span already implies, because every word of a file is written (docs/performance.md).
    raw_skip: u32,
    /// The whole word (letter and number).
    pub span: Span,
}

impl Word {
    /// A placeholder for buffers of words.
    pub const EMPTY: Word = Word {
        letter: 0,
        value: 0.0,
        has_dot: false,
        raw_skip: 0,
        span: Span::new(0, 0, 0, 0),
    };

    /// A letter written without a number (OmniTurn's `P`, `C` and `O` flags on G33). Only letters a
    /// dialect declares in its [`Syntax::bare`] can be bare; their value reads as 0.
    pub fn is_bare(&self) -> bool {
        self.raw_len() == 0
    }

    /// A word whose value the macro interpreter ([`crate::interp`]) computed from what follows the
    /// letter (a parameter, an expression): `span` covers the letter and what follows it, which
    /// [`raw`](Word::raw) gives back as written (`[#1*2]`, for messages). Its value is a value, not
    /// a count of least increments: it reads as written with a decimal point (the Fanuc macro rule,
    /// docs/dialects/fanuc.md). A dialect that decodes a word's digits (a packed `P`) reads a
    /// computed word from its value ([`is_computed`](Word::is_computed)).
    pub fn computed(letter: u8, value: f64, span: Span) -> Word {
        Word {
            letter,
            value,
            has_dot: true,
            raw_skip: COMPUTED,
            span,
        }
    }

    /// A word the macro interpreter read as a plain number in a line the lexer does not take
    /// (`X10` beside `Z#1`): as [`lex_line`] would give it, the number's lexeme starting `skip`
    /// bytes after the letter.
    pub fn literal(letter: u8, value: f64, has_dot: bool, span: Span, skip: u32) -> Word {
        Word {
            letter,
            value,
            has_dot,
            raw_skip: skip & !COMPUTED,
            span,
        }
    }

    /// Whether the value was computed by the macro interpreter ([`computed`](Word::computed)).
    pub fn is_computed(&self) -> bool {
        self.raw_skip & COMPUTED != 0
    }

    /// Byte offset of the number's lexeme within the line (after the letter and any blanks).
    pub fn raw_start(&self) -> usize {
        // The span's column is the letter's offset plus one.
        self.span.column as usize + (self.raw_skip & !COMPUTED) as usize
    }

    /// Length of the number's lexeme in bytes.
    pub fn raw_len(&self) -> usize {
        (self.span.len as usize).saturating_sub(1 + (self.raw_skip & !COMPUTED) as usize)
    }

    /// The number exactly as written, e.g. `020545` for `P020545`.
    pub fn raw<'a>(&self, line: &'a [u8]) -> &'a [u8] {
        let start = self.raw_start();
        &line[start..start + self.raw_len()]
    }

    /// A word whose value a dialect worked out itself from its own syntax (Sinumerik's
    /// `X=R1`): `span` covers the whole text (letter, `=` and operand) and its lexeme is what
    /// follows the `=`. The value counts as written with a decimal point.
    pub(crate) fn assigned(letter: u8, value: f64, span: Span) -> Word {
        Word {
            letter: letter.to_ascii_uppercase(),
            value,
            has_dot: true,
            raw_skip: 1,
            span,
        }
    }
}

/// The top bit of a word's `raw_skip`: the word was computed by the macro interpreter.
const COMPUTED: u32 = 1 << 31;

/// Which words a line has, in brief: gathered by the lexer on its way through the line, so that
/// a caller can tell that a line has no `G78` (or no `E` word) without looking at its words.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct WordSummary {
    /// Bit `letter & 31` for each letter `A`–`Z` that begins a word (`A` is bit 1, `Z` bit 26), bit
    /// 0 for `$`, and bit 31 for a `G` word other than the plain motion codes (as
    /// [`other_g`](WordSummary::other_g) says).
    bits: u32,
}

const OTHER_G: u32 = 1 << 31;

impl WordSummary {
    /// The summary of these words.
    pub fn of(words: &[Word]) -> WordSummary {
        let bits = words.iter().fold(0, |bits, w| {
            let letter = if w.letter == b'$' {
                1
            } else {
                1 << (w.letter & 31)
            };
            bits | letter | other_g_bit(w.letter, w.value, w.has_dot)
        });
        WordSummary { bits }
    }

    /// Whether some word begins with this letter (upper case, or `$`). `false` for anything else.
    #[inline(always)]
    pub fn has_letter(&self, letter: u8) -> bool {
        let bit = match letter {
            b'A'..=b'Z' => 1 << (letter & 31),
            b'$' => 1,
            _ => 0,
        };
        self.bits & bit != 0
    }

    /// How many different letters begin words. As many as there are words: no letter is written
    /// twice.
    #[inline(always)]
    pub fn letters(&self) -> usize {
        (self.bits & !OTHER_G).count_ones() as usize
    }

    /// Whether some `G` word is other than 0, 1, 2 or 3 written as a whole number without a decimal
    /// point or a minus sign (`G0`–`G3`, the plain motion codes, also as `G01`; `G1.0` and `G-0`
    /// count as other). `false` promises that every `G` word is `G0`, `G1`, `G2` or `G3`.
    #[inline(always)]
    pub fn other_g(&self) -> bool {
        self.bits & OTHER_G != 0
    }

    /// Whether some `G` word is other than `G0`–`G3` ([`other_g`](WordSummary::other_g)) or some
    /// word begins with one of `letters` (a mask from [`letter_mask`](WordSummary::letter_mask)):
    /// one test where a caller needs these answers only when one of them is yes.
    #[inline(always)]
    pub fn other_g_or_any(&self, letters: u32) -> bool {
        self.bits & (OTHER_G | letters) != 0
    }

    /// The mask of these letters (upper case, `A`–`Z`) for
    /// [`other_g_or_any`](WordSummary::other_g_or_any); other bytes add nothing.
    pub const fn letter_mask(letters: &[u8]) -> u32 {
        let mut mask = 0;
        let mut i = 0;
        while i < letters.len() {
            if letters[i].is_ascii_uppercase() {
                mask |= 1 << (letters[i] & 31);
            }
            i += 1;
        }
        mask
    }

    /// Whether some word begins with `M` or `O`, or some `G` word is other than G0–G3: the lines
    /// a macro interpreter looks at more closely (`M98`, `M99`, `M30`, `G65`), one test for all.
    #[inline(always)]
    pub fn may_be_control(&self) -> bool {
        self.bits & (1 << (b'M' & 31) | 1 << (b'O' & 31) | OTHER_G) != 0
    }

    /// Whether the line may have a `G` word with this code (×10, as
    /// [`g_code`](super::reader::g_code) gives it). `false` is certain; `true` means "look".
    #[inline(always)]
    pub fn may_have_g(&self, code: u16) -> bool {
        if matches!(code, 0 | 10 | 20 | 30) {
            self.has_letter(b'G')
        } else {
            self.other_g()
        }
    }
}

/// [`WordSummary`]'s bit 31 for a word: a `G` word that is not 0, 1, 2 or 3 written as a whole
/// number without a decimal point or a minus sign. Branch-free and without a float comparison: it
/// runs on every word.
#[inline(always)]
fn other_g_bit(letter: u8, value: f64, has_dot: bool) -> u32 {
    u32::from((letter == b'G') & !is_plain_motion(value, has_dot)) << 31
}

/// Whether a `G` word's number is 0, 1, 2 or 3 written as a whole number without a decimal point
/// or a minus sign: one of the plain motion codes, which [`WordSummary::other_g`] leaves out.
#[inline(always)]
pub(crate) fn is_plain_motion(value: f64, has_dot: bool) -> bool {
    // Non-negative doubles order as their bits do; a negative one (-0 too) has the sign bit set.
    // Without a decimal point the number is a whole number.
    !has_dot & (value.to_bits() <= THREE_BITS)
}

const THREE_BITS: u64 = 3.0f64.to_bits();

/// Where a word's letter is kept in a [`WordIndex`]: as in [`WordSummary`], `A`–`Z` at 1–26 and
/// `$` at 0 (a word's letter is always one of these).
#[inline(always)]
pub(crate) fn letter_slot(letter: u8) -> usize {
    usize::from(letter & 31) & usize::from(letter != b'$').wrapping_neg()
}

/// For each letter, the position in the line's words of the last word it begins: filled by the
/// lexer (one store a word) so that a caller can go straight to a word instead of looking through
/// the line. Only the entries of letters the line's [`WordSummary`] shows are meaningful; the others
/// are left from earlier lines.
pub type WordIndex = [u32; 32];

/// Fills `index` for `words`: each letter's last word (the lexer's own lines, and lines built
/// from words read otherwise: the interpreter's blocks, a dialect's own syntax).
#[inline(always)]
pub(crate) fn index_words(words: &[crate::gcode::Word], index: &mut WordIndex) {
    for (at, w) in words.iter().enumerate() {
        // A line has fewer than 2^32 words: it is at most MAX_LINE_BYTES long.
        index[letter_slot(w.letter)] = at as u32;
    }
}

/// What a line holds besides its words.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LineShape {
    /// A leading `/`: the block is skipped when block delete is switched on.
    pub block_delete: bool,
    /// The line is a `%` program delimiter.
    pub percent: bool,
    /// The line holds more than address words (Sinumerik's calls, assignments and named words) and
    /// was handed out without words, for the dialect to read from [`Line::text`](super::Line::text).
    /// Only under [`Syntax::hand_over_unread`]; never set otherwise.
    pub unread: bool,
}

/// How a controller writes its lines, where that differs from RS274/Fanuc. A dialect states it
/// once, in its [`Conventions::syntax`](super::Conventions::syntax), and the reader lexes every line
/// with it. The default is RS274's: every letter takes a number, a blank ends a number, `(` opens a
/// comment that ends at the first `)`, and a line that is not address words is an error.
///
/// The reader's fast path reads only lines that every syntax reads alike (it looks at
/// [`parens_not_comments`](Syntax::parens_not_comments) alone, and only on a `(`); everything
/// else is the reference lexer's ([`lex_line_syntax`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Syntax {
    /// Letters that may stand alone, without a number (flags such as OmniTurn's `G33 … P C O`). A
    /// bare letter is followed by the end of the line, a blank, a comment or another letter;
    /// [`Word::is_bare`] tells it from a letter with a value.
    pub bare: &'static [u8],
    /// Blanks (spaces, tabs, carriage returns) mean nothing anywhere outside comments, inside
    /// numbers and between a sign and its digits too: `G 7 6 P2 . 5` is `G76 P2.5` (LinuxCNC
    /// drops them before it reads a line). Elsewhere a blank ends a number, and a number after it
    /// is an error.
    pub blanks_anywhere: bool,
    /// A `(` inside a comment is an error (LinuxCNC: "Nested comment found"); elsewhere a comment
    /// ends at the first `)`.
    pub nested_comment_error: bool,
    /// `(` is not a comment (Sinumerik: comments begin with `;`, and parentheses belong to calls
    /// such as `CYCLE97(…)`): the lexers treat it as any other character they cannot read.
    pub parens_not_comments: bool,
    /// A line the word lexer cannot read is handed out without words and with
    /// [`LineShape::unread`] set, rather than as an error: the dialect reads its own syntax from
    /// the line's text (and reports the errors in it). The reader's business: to
    /// [`lex_line_syntax`] such a line is an error as always.
    pub hand_over_unread: bool,
}

/// Lexes one line (without its line terminator) into `words`, which is cleared first and reused so
/// that streaming a file allocates nothing per block. RS274's syntax ([`Syntax::default`]).
///
/// `offset` is the byte offset of the line in the whole input and `line_no` its 1-based number.
pub fn lex_line(
    line: &[u8],
    line_no: u32,
    offset: u64,
    words: &mut Vec<Word>,
) -> Result<LineShape, Diagnostic> {
    lex_line_syntax(line, line_no, offset, words, &Syntax::default())
}

/// As [`lex_line`], read as a controller's `syntax` says: the reference lexer, which the reader's
/// fast path agrees with on every line it takes.
pub fn lex_line_syntax(
    line: &[u8],
    line_no: u32,
    offset: u64,
    words: &mut Vec<Word>,
    syntax: &Syntax,
) -> Result<LineShape, Diagnostic> {
    words.clear();
    let mut shape = LineShape::default();
    let mut i = 0;
    let n = line.len();
    while i < n {
        let c = line[i];
        match CLASS[c as usize] {
            LETTER => {
                // `$` (LinuxCNC's spindle word) is a letter too, and has no lower case.
                let letter = c.to_ascii_uppercase();
                // Fast path: a number follows the letter directly and is short enough for
                // `fast_number`; everything else (blanks after the letter, bare flags, errors, very
                // long numbers, a number that may go on after a blank) goes through `word_slow`,
                // which is the reference behaviour. A number right after the letter also means the
                // letter is not a bare flag.
                let fast = fast_number(line, i + 1)
                    .filter(|&(_, _, end)| !syntax.blanks_anywhere || !continues(line, end));
                if let Some((value, has_dot, end)) = fast {
                    words.push(Word {
                        letter,
                        value,
                        has_dot,
                        raw_skip: 0,
                        span: span_at(offset, line_no, i, end - i),
                    });
                    i = end;
                } else {
                    i = word_slow(line, i, line_no, offset, words, syntax)?;
                }
            }
            BLANK => i += 1,
            SEMICOLON => break,
            OPEN if syntax.parens_not_comments => {
                other_byte(line, i, line_no, offset, words.is_empty(), &mut shape)?;
                i += 1;
            }
            OPEN => match memchr::memchr(b')', &line[i + 1..]) {
                Some(close) => {
                    if syntax.nested_comment_error {
                        if let Some(inner) = memchr::memchr(b'(', &line[i + 1..i + 1 + close]) {
                            return Err(nested_comment(span_at(offset, line_no, i + 1 + inner, 1)));
                        }
                    }
                    i += close + 2
                }
                None => return Err(unclosed_comment(span_at(offset, line_no, i, n - i))),
            },
            _ => {
                other_byte(line, i, line_no, offset, words.is_empty(), &mut shape)?;
                i += 1;
            }
        }
    }
    Ok(shape)
}

/// A line lexed straight out of the reader's buffer by [`lex_buffered_line`].
pub(crate) struct BufferedLine {
    pub shape: LineShape,
    /// How many words [`lex_buffered_line`] wrote.
    pub words: usize,
    pub summary: WordSummary,
    /// Length of the line without its terminator (`\n` or `\r\n`).
    pub text_len: usize,
    /// Length of the line with its terminator.
    pub raw_len: usize,
}

/// Lexes the line at the start of `input`, a buffer holding that line and possibly more, finding
/// its end (`\n`) in the same pass instead of searching for it first.
///
/// This is only a fast path: it returns `None` for anything that is not a plain line of short
/// words, blanks and closed comments ending in `\n` inside `input` (a line cut off by the end of
/// the buffer, `%`, `/`, blanks after a letter, bare flags, long numbers, every error). The caller
/// then finds the line's end and calls [`lex_line_syntax`], the reference. When it returns a line,
/// `words` and the shape are exactly what [`lex_line_syntax`] gives for the line's text: `\r` is a
/// blank to both, and every number stops at `\r` or `\n` as it stops at the end of the text.
/// How many words a line may have for [`lex_buffered_line`]; a line with more goes the reference way.
pub(crate) const FAST_WORDS: usize = 32;

#[inline(always)]
pub(crate) fn lex_buffered_line(
    input: &[u8],
    line_no: u32,
    offset: u64,
    words: &mut [Word; FAST_WORDS],
    index: &mut WordIndex,
    parens_not_comments: bool,
) -> Option<BufferedLine> {
    // The reader hands over whole lines only; the numbers below rely on the final line end.
    if input.last() != Some(&b'\n') {
        return None;
    }
    let mut i = 0;
    let mut count = 0;
    // The summary is gathered on the way: a bit per letter, and whether a G word is other than
    // G0–G3 (see `WordSummary`).
    let mut letters = 0u32;
    let mut other_g = false;
    loop {
        let c = *input.get(i)?;
        // Tested in the order of how often they come: a word, the end of the line, the rest. The
        // letter test is arithmetic rather than a table look-up so that it stays a plain branch
        // (a multi-way jump on the byte's class mispredicts far more often).
        if (c | 0x20).wrapping_sub(b'a') < 26 {
            // `input` ends with `\n` (checked above), which is not this letter: `i + 1` is in it.
            let (value, has_dot, end) = number::<true>(input, i + 1)?;
            let letter = c & !0x20;
            letters |= 1 << (letter & 31);
            if letter == b'G' {
                other_g |= !is_plain_motion(value, has_dot);
            }
            // `number` takes at most 15 digits, a sign and a point: no length overflows.
            *words.get_mut(count)? = Word {
                letter,
                value,
                has_dot,
                raw_skip: 0,
                span: Span::new(offset + i as u64, (end - i) as u32, line_no, i as u32 + 1),
            };
            index[usize::from(letter & 31)] = count as u32;
            count += 1;
            // Words are mostly separated by one blank: step over it here.
            i = end + usize::from(input.get(end) == Some(&b' '));
        } else if c == b'\n' {
            return Some(buffered_line(input, i, count, letters, other_g));
        } else if CLASS[c as usize] == BLANK {
            i += 1;
        } else if c == b'(' {
            // Not a comment on every controller (`Syntax`): then the reference way.
            if parens_not_comments {
                return None;
            }
            // The comment must close before the line ends; a `(` inside it is for the reference
            // lexer to judge (an error where the syntax says so).
            let close = i + 1 + memchr::memchr3(b')', b'\n', b'(', &input[i + 1..])?;
            if input[close] != b')' {
                return None;
            }
            i = close + 1;
        } else if c == b';' {
            let newline = i + 1 + memchr::memchr(b'\n', &input[i + 1..])?;
            return Some(buffered_line(input, newline, count, letters, other_g));
        } else {
            return None;
        }
    }
}

/// The line ending with the `\n` at `newline`.
#[inline(always)]
fn buffered_line(
    input: &[u8],
    newline: usize,
    words: usize,
    letters: u32,
    other_g: bool,
) -> BufferedLine {
    let text_len = if newline > 0 && input[newline - 1] == b'\r' {
        newline - 1
    } else {
        newline
    };
    BufferedLine {
        shape: LineShape::default(),
        summary: WordSummary {
            bits: letters | u32::from(other_g) << 31,
        },
        words,
        text_len,
        raw_len: newline + 1,
    }
}

/// The span of `len` bytes at byte `i` of a line.
#[inline(always)]
fn span_at(offset: u64, line_no: u32, i: usize, len: usize) -> Span {
    Span::new(
        offset + i as u64,
        len.min(u32::MAX as usize) as u32,
        line_no,
        i as u32 + 1,
    )
}

/// Byte classes of the lexer's main loop: one table load instead of a chain of comparisons.
const OTHER: u8 = 0;
const BLANK: u8 = 1;
const LETTER: u8 = 2;
const OPEN: u8 = 3;
const SEMICOLON: u8 = 4;
/// Only [`lex_buffered_line`] sees line ends; to [`lex_line_syntax`] a stray `\n` is an error.
const NEWLINE: u8 = 5;

static CLASS: [u8; 256] = {
    let mut t = [OTHER; 256];
    let mut b = 0;
    while b < 256 {
        t[b] = match b as u8 {
            b' ' | b'\t' | b'\r' | 0x0c => BLANK,
            // `$` is LinuxCNC's spindle-selection word (`G76 … $1`).
            b'a'..=b'z' | b'A'..=b'Z' | b'$' => LETTER,
            b'(' => OPEN,
            b';' => SEMICOLON,
            b'\n' => NEWLINE,
            _ => OTHER,
        };
        b += 1;
    }
    t
};

/// Whether a number that ends at `end` goes on after blanks (a digit or a decimal point follows
/// them), where blanks mean nothing ([`Syntax::blanks_anywhere`]).
fn continues(line: &[u8], end: usize) -> bool {
    line[end..]
        .iter()
        .find(|&&b| !is_blank(b))
        .is_some_and(|b| matches!(b, b'0'..=b'9' | b'.'))
}

/// A blank to [`Syntax::blanks_anywhere`]: what LinuxCNC drops before reading a line.
fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r')
}

#[cold]
fn nested_comment(span: Span) -> Diagnostic {
    Diagnostic::error(Code::Syntax, span, "Nested comment found")
        .with_hint("a comment ends at the first `)`: close it before opening another")
}

#[cold]
fn unclosed_comment(span: Span) -> Diagnostic {
    Diagnostic::error(Code::Syntax, span, "comment is not closed")
        .with_hint("close the comment with `)` on the same line")
}

/// `%`, `/` and everything that is an error. Returns after a byte that was accepted.
#[cold]
#[inline(never)]
fn other_byte(
    line: &[u8],
    i: usize,
    line_no: u32,
    offset: u64,
    no_words: bool,
    shape: &mut LineShape,
) -> Result<(), Diagnostic> {
    let c = line[i];
    match c {
        b'%' if no_words => {
            shape.percent = true;
            Ok(())
        }
        b'/' if no_words && !shape.block_delete => {
            shape.block_delete = true;
            Ok(())
        }
        b'#' | b'[' | b'=' => Err(Diagnostic::error(
            Code::Unsupported,
            span_at(offset, line_no, i, 1),
            format!(
                "`{}`: macro variables and expressions are not supported",
                c as char
            ),
        )
        .with_hint("expand the macro on the controller, or write plain values")),
        _ => {
            let len = utf8_len(&line[i..]);
            Err(Diagnostic::error(
                Code::Syntax,
                span_at(offset, line_no, i, len),
                format!("unexpected character `{}`", show(&line[i..i + len])),
            )
            .with_hint("expected an address letter, a comment or the end of the line"))
        }
    }
}

/// A number starting right at `at` that Clinger's fast path converts exactly: `[+-]digits[.digits]`
/// with 1 to 15 digits, not followed by a second decimal point.
/// Returns the value, whether it has a decimal point, and one past its last byte; `None` for
/// anything else (which [`lex_number`] then handles, errors included).
#[inline(always)]
fn fast_number(line: &[u8], at: usize) -> Option<(f64, bool, usize)> {
    // Where the input ends with a byte that stops every loop below (as the reader's buffer does:
    // it is cut after a line end), the loops need no bounds checks of their own.
    let terminated = at < line.len()
        && line
            .last()
            .is_some_and(|&b| !matches!(b, b'0'..=b'9' | b'.' | b'+' | b'-'));
    if terminated {
        number::<true>(line, at)
    } else {
        number::<false>(line, at)
    }
}

/// The byte at `i`; `None` past the end unless `TERMINATED`.
#[inline(always)]
fn byte_at<const TERMINATED: bool>(line: &[u8], i: usize) -> Option<u8> {
    if TERMINATED {
        // SAFETY: `number::<true>` is only called with `at < line.len()` and a last byte that is
        // no digit, point or sign (`fast_number` checks both; `lex_buffered_line` checks that its
        // input ends with `\n` and starts numbers only after a letter, which is not that `\n`).
        // It reads `at`, and reads `i + 1` only after the byte at `i` was a sign, a digit or a
        // point, which the last byte is not: so `i + 1 < line.len()` too. Every index read is in
        // bounds. (Measured: these checks cost about a tenth of the whole pass-through time; see
        // docs/performance.md.)
        Some(unsafe { *line.get_unchecked(i) })
    } else {
        line.get(i).copied()
    }
}

#[inline(always)]
fn number<const TERMINATED: bool>(line: &[u8], at: usize) -> Option<(f64, bool, usize)> {
    let mut i = at;
    let first = byte_at::<TERMINATED>(line, i)?;
    let negative = first == b'-';
    if negative || first == b'+' {
        i += 1;
    }
    let int_start = i;
    let mut mantissa: u64 = 0;
    while let Some(b) = byte_at::<TERMINATED>(line, i) {
        // (The digit as u64 from the start: no separate widening in this loop.)
        let d = u64::from(b).wrapping_sub(u64::from(b'0'));
        if d > 9 {
            break;
        }
        mantissa = mantissa.wrapping_mul(10).wrapping_add(d);
        i += 1;
    }
    let mut digits = i - int_start;
    let has_dot = byte_at::<TERMINATED>(line, i) == Some(b'.');
    let mut frac_digits = 0;
    if has_dot {
        i += 1;
        let frac_start = i;
        while let Some(b) = byte_at::<TERMINATED>(line, i) {
            let d = u64::from(b).wrapping_sub(u64::from(b'0'));
            if d > 9 {
                break;
            }
            mantissa = mantissa.wrapping_mul(10).wrapping_add(d);
            i += 1;
        }
        frac_digits = i - frac_start;
        digits += frac_digits;
        if byte_at::<TERMINATED>(line, i) == Some(b'.') {
            return None;
        }
    }
    // 1 to 15 digits: no wrap-around above, and the mantissa (below 10^15 < 2^53) is an exact
    // double. Longer numbers are rare and go the reference way.
    if digits.wrapping_sub(1) >= 15 {
        return None;
    }
    // Clinger's fast path: both operands are exact doubles (frac_digits <= 15), so one division
    // rounds correctly. (The mask only spares a bounds check: frac_digits < 32 already. The
    // conversion goes through i64, which holds the mantissa, because the signed one is a single
    // instruction.)
    let v = mantissa as i64 as f64;
    // A whole number needs no division (most G, M, N and T words; measured: docs/performance.md).
    let v = if has_dot {
        v / POW10_32[frac_digits & 31]
    } else {
        v
    };
    Some((if negative { -v } else { v }, has_dot, i))
}

/// `POW10` padded to 32 entries for [`fast_number`]'s masked index (only the first 20 are used).
const POW10_32: [f64; 32] = {
    let mut t = [1.0; 32];
    let mut k = 0;
    while k < POW10.len() {
        t[k] = POW10[k];
        k += 1;
    }
    t
};

/// One word the reference way: blanks after the letter, bare flags, long numbers and every error.
/// Returns the index after the word.
#[cold]
#[inline(never)]
fn word_slow(
    line: &[u8],
    i: usize,
    line_no: u32,
    offset: u64,
    words: &mut Vec<Word>,
    syntax: &Syntax,
) -> Result<usize, Diagnostic> {
    let letter = line[i].to_ascii_uppercase();
    if syntax.bare.contains(&letter) && !starts_number(&line[i + 1..]) {
        words.push(Word {
            letter,
            value: 0.0,
            has_dot: false,
            raw_skip: 0,
            span: span_at(offset, line_no, i, 1),
        });
        return Ok(i + 1);
    }
    let lexed = if syntax.blanks_anywhere {
        lex_number_blanks(line, i + 1)
    } else {
        lex_number(line, i + 1)
    };
    let number = lexed.map_err(|(at, len, what)| {
        Diagnostic::error(
            Code::Syntax,
            span_at(offset, line_no, at, len),
            format!(
                "malformed word `{}`: {what}",
                show(&line[i..(at + len).max(i + 1)])
            ),
        )
        .with_hint("a word is one letter followed by a number, such as `X-12.5`")
    })?;
    let word_span = span_at(offset, line_no, i, number.end - i);
    if !number.value.is_finite() {
        return Err(Diagnostic::error(
            Code::BadNumber,
            word_span,
            format!(
                "the value of `{}` is too large to be a coordinate",
                show(&line[i..number.end.min(i + 24)])
            ),
        ));
    }
    words.push(Word {
        letter,
        value: number.value,
        has_dot: number.has_dot,
        raw_skip: (number.start - i - 1) as u32,
        span: word_span,
    });
    Ok(number.end)
}

/// Lexes the one address word whose letter is at `line[i]` (the reference way, errors included)
/// and appends it to `words`; returns the index after it. For a dialect that reads its own syntax
/// around address words (Sinumerik).
pub(crate) fn lex_word(
    line: &[u8],
    i: usize,
    line_no: u32,
    offset: u64,
    words: &mut Vec<Word>,
) -> Result<usize, Diagnostic> {
    word_slow(line, i, line_no, offset, words, &Syntax::default())
}

/// Whether a number follows (after blanks): a digit, a sign or a decimal point.
fn starts_number(rest: &[u8]) -> bool {
    rest.iter()
        .find(|&&b| b != b' ' && b != b'\t')
        .is_some_and(|b| matches!(b, b'0'..=b'9' | b'+' | b'-' | b'.'))
}

/// Lexes `[+-]digits[.digits]` starting at `at` (just after the letter).
struct Number {
    value: f64,
    has_dot: bool,
    /// Where the lexeme starts (after any blanks between letter and number).
    start: usize,
    /// One past its last byte.
    end: usize,
}

/// Returns the number, or the offending position, length and what was wrong.
fn lex_number(line: &[u8], at: usize) -> Result<Number, (usize, usize, &'static str)> {
    let n = line.len();
    let mut i = at;
    // Blanks between a letter and its number are legal in RS274 (`X 10`).
    while i < n && (line[i] == b' ' || line[i] == b'\t') {
        i += 1;
    }
    let start = i;
    let negative = match line.get(i) {
        Some(b'-') => {
            i += 1;
            true
        }
        Some(b'+') => {
            i += 1;
            false
        }
        _ => false,
    };
    // Digits accumulate into a u64; beyond 19 digits, or past 2^53, the slow path below takes over.
    let mut mantissa: u64 = 0;
    let int_start = i;
    while i < n && line[i].is_ascii_digit() {
        mantissa = mantissa
            .wrapping_mul(10)
            .wrapping_add(u64::from(line[i] - b'0'));
        i += 1;
    }
    let mut digits = (i - int_start) as u32;
    let mut frac_digits = 0u32;
    let has_dot = i < n && line[i] == b'.';
    if has_dot {
        i += 1;
        let frac_start = i;
        while i < n && line[i].is_ascii_digit() {
            mantissa = mantissa
                .wrapping_mul(10)
                .wrapping_add(u64::from(line[i] - b'0'));
            i += 1;
        }
        frac_digits = (i - frac_start) as u32;
        digits += frac_digits;
        if i < n && line[i] == b'.' {
            return Err((i, 1, "a second decimal point"));
        }
    }
    if digits == 0 {
        return match line.get(i) {
            Some(b'-') | Some(b'+') => Err((i, 1, "a second sign")),
            Some(_) => Err((i, 1, "a number was expected after the letter")),
            None => Err((at - 1, 1, "a number was expected after the letter")),
        };
    }
    let value = if digits <= 19 && mantissa <= 1 << 53 && frac_digits <= 22 {
        // Clinger's fast path: both operands are exact doubles, so one division rounds correctly.
        let v = mantissa as f64 / POW10[frac_digits as usize];
        if negative {
            -v
        } else {
            v
        }
    } else {
        // Rare: very long numbers. The standard library parses them correctly rounded.
        std::str::from_utf8(&line[start..i])
            .ok()
            .and_then(|t| t.parse::<f64>().ok())
            .unwrap_or(f64::INFINITY)
    };
    Ok(Number {
        value,
        has_dot,
        start,
        end: i,
    })
}

/// [`lex_number`] where blanks mean nothing ([`Syntax::blanks_anywhere`]): the number's bytes
/// with the blanks among them dropped, read as one number. Positions in errors and in the result
/// are the line's.
fn lex_number_blanks(line: &[u8], at: usize) -> Result<Number, (usize, usize, &'static str)> {
    // The bytes of the number (signs, then digits and decimal points) and where each one lies,
    // after a stand-in for the letter, so that `lex_number` reads them from index 1 as it reads a
    // line after its letter.
    let mut text = vec![b'L'];
    let mut place = vec![at - 1];
    let mut i = at;
    let mut signs = true;
    while i < line.len() {
        let b = line[i];
        let part = match b {
            b'+' | b'-' => signs,
            b'0'..=b'9' | b'.' => {
                signs = false;
                true
            }
            _ => is_blank(b),
        };
        if !part {
            break;
        }
        if !is_blank(b) {
            text.push(b);
            place.push(i);
        }
        i += 1;
    }
    if text.len() == 1 {
        // No number: the same errors as `lex_number`, at the byte that is not one.
        return Err(match line.get(i) {
            Some(_) => (i, 1, "a number was expected after the letter"),
            None => (at - 1, 1, "a number was expected after the letter"),
        });
    }
    // One past the number's last byte; the blanks after it belong to what follows.
    let end = place[place.len() - 1] + 1;
    let mapped = |k: usize| place.get(k).copied().unwrap_or(end);
    match lex_number(&text, 1) {
        Ok(n) => Ok(Number {
            value: n.value,
            has_dot: n.has_dot,
            start: mapped(n.start),
            end: mapped(n.end),
        }),
        Err((k, len, what)) => Err((mapped(k), len, what)),
    }
}

const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Length of the (possibly invalid) UTF-8 character at the start of `bytes`, so a caret covers it whole.
fn utf8_len(bytes: &[u8]) -> usize {
    let want = match bytes[0] {
        0xc0..=0xdf => 2,
        0xe0..=0xef => 3,
        0xf0..=0xf7 => 4,
        _ => 1,
    };
    let mut len = 1;
    while len < want && len < bytes.len() && (bytes[len] & 0xc0) == 0x80 {
        len += 1;
    }
    len
}

/// Bytes shown in a message: UTF-8 where valid, escapes elsewhere.
pub fn show(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes)
        .chars()
        .flat_map(|c| {
            if c.is_control() {
                c.escape_default().collect::<Vec<_>>()
            } else {
                vec![c]
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lex(s: &str) -> Result<Vec<(char, f64, bool)>, Diagnostic> {
        let mut words = Vec::new();
        lex_line(s.as_bytes(), 1, 0, &mut words)?;
        Ok(words
            .iter()
            .map(|w| (w.letter as char, w.value, w.has_dot))
            .collect())
    }

    #[test]
    fn words_values_and_decimal_points() {
        assert_eq!(
            lex("N10 G0X-12.5 z.25(comment)F3;rest").unwrap(),
            vec![
                ('N', 10.0, false),
                ('G', 0.0, false),
                ('X', -12.5, true),
                ('Z', 0.25, true),
                ('F', 3.0, false)
            ]
        );
    }

    #[test]
    fn raw_lexeme_keeps_leading_zeros() {
        let line = b"G78 P020545 Q0.15";
        let mut words = Vec::new();
        lex_line(line, 1, 0, &mut words).unwrap();
        assert_eq!(words[1].raw(line), b"020545");
        assert_eq!(words[1].value, 20545.0);
        // Blanks between the letter and the number are not part of the lexeme, nor of a bare
        // flag's (which has none); the span covers the whole word.
        let line = b"G33 X 1.5 P Z\t-2";
        lex_line_syntax(line, 1, 0, &mut words, &bare(b"P")).unwrap();
        let raw: Vec<&[u8]> = words.iter().map(|w| w.raw(line)).collect();
        assert_eq!(raw, [&b"33"[..], b"1.5", b"", b"-2"]);
        let spans: Vec<(u32, u32)> = words.iter().map(|w| (w.span.column, w.span.len)).collect();
        assert_eq!(spans, [(1, 3), (5, 5), (11, 1), (13, 4)]);
        assert!(words[2].is_bare() && !words[1].is_bare());
        assert_eq!((words[1].raw_start(), words[1].raw_len()), (6, 3));
    }

    #[test]
    fn values_are_correctly_rounded() {
        for text in [
            "0.1",
            "123.4567",
            "-0.000001",
            "99999.99999",
            "1234567.123456789",
        ] {
            let v = lex(&format!("X{text}")).unwrap()[0].1;
            assert_eq!(v, text.parse::<f64>().unwrap(), "{text}");
        }
    }

    proptest::proptest! {
        /// Every number the lexer takes has the correctly rounded value of its text, on the fast
        /// path (up to 19 digits) and off it, and keeps its lexeme.
        #[test]
        fn numbers_are_exact(
            sign in proptest::sample::select(vec!["", "-", "+"]),
            int in "[0-9]{0,22}",
            frac in proptest::option::of("[0-9]{0,22}"),
        ) {
            let text = match &frac {
                Some(f) => format!("{sign}{int}.{f}"),
                None => format!("{sign}{int}"),
            };
            let line = format!("X{text} Z1");
            let mut words = Vec::new();
            let digits = int.len() + frac.as_ref().map_or(0, |f| f.len());
            match lex_line(line.as_bytes(), 1, 0, &mut words) {
                Ok(_) => {
                    let want: f64 = text.parse().unwrap();
                    proptest::prop_assert_eq!(words[0].value.to_bits(), want.to_bits());
                    proptest::prop_assert_eq!(words[0].raw(line.as_bytes()), text.as_bytes());
                    proptest::prop_assert_eq!(words[0].has_dot, frac.is_some());
                    proptest::prop_assert_eq!(words[1].value, 1.0);
                }
                Err(e) => proptest::prop_assert!(digits == 0, "{text}: {}", e.message),
            }
        }
    }

    #[test]
    fn spans_point_at_the_word() {
        let mut words = Vec::new();
        lex_line(b"  G32 X10", 7, 100, &mut words).unwrap();
        assert_eq!(words[1].span, Span::new(106, 3, 7, 7));
    }

    #[test]
    fn malformed_numbers_are_errors_with_columns() {
        let e = lex("G0 X1.2.3").unwrap_err();
        assert_eq!((e.code, e.span.column), (Code::Syntax, 8));
        let e = lex("G0 X--1").unwrap_err();
        assert_eq!(e.code, Code::Syntax);
        assert!(e.message.contains("second sign"), "{}", e.message);
        let e = lex("G0 X").unwrap_err();
        assert!(e.message.contains("number was expected"), "{}", e.message);
        let e = lex("G0 X1 (open").unwrap_err();
        assert_eq!(e.span.column, 7);
        let e = lex(&format!("X1{}", "0".repeat(400))).unwrap_err();
        assert_eq!(e.code, Code::BadNumber);
    }

    #[test]
    fn bare_letters_only_where_declared() {
        let line = b"G33X.212Z-.5I.012K.05PC O(flags) C27";
        let mut words = Vec::new();
        lex_line_syntax(line, 1, 0, &mut words, &bare(b"PCO")).unwrap();
        let got: Vec<(char, f64, bool)> = words
            .iter()
            .map(|w| (w.letter as char, w.value, w.is_bare()))
            .collect();
        assert_eq!(
            got[5..],
            [
                ('P', 0.0, true),
                ('C', 0.0, true),
                ('O', 0.0, true),
                ('C', 27.0, false)
            ]
        );
        assert_eq!(words[6].span, Span::new(22, 1, 1, 23));
        // Without the declaration a bare letter stays an error; a declared letter with a lone
        // sign is still malformed.
        assert!(lex_line(line, 1, 0, &mut words).is_err());
        assert!(lex_line_syntax(b"G33 P-", 1, 0, &mut words, &bare(b"P")).is_err());
    }

    /// A syntax whose only difference from RS274 is these bare letters (OmniTurn's).
    fn bare(letters: &'static [u8]) -> Syntax {
        Syntax {
            bare: letters,
            ..Syntax::default()
        }
    }

    /// LinuxCNC's reading rules.
    const BLANKS: Syntax = Syntax {
        bare: b"",
        blanks_anywhere: true,
        nested_comment_error: true,
        parens_not_comments: false,
        hand_over_unread: false,
    };

    /// Letter, value, decimal point, column and length of each word.
    type Lexed = Vec<(char, f64, bool, u32, u32)>;

    fn lex_blanks(s: &str) -> Result<Lexed, Diagnostic> {
        let mut words = Vec::new();
        lex_line_syntax(s.as_bytes(), 1, 0, &mut words, &BLANKS)?;
        Ok(words
            .iter()
            .map(|w| {
                (
                    w.letter as char,
                    w.value,
                    w.has_dot,
                    w.span.column,
                    w.span.len,
                )
            })
            .collect())
    }

    #[test]
    fn blanks_anywhere_inside_words_and_numbers() {
        // `G 7 6 P2 . 5` is `G76 P2.5`; the span covers the word with its blanks.
        assert_eq!(
            lex_blanks("G 7 6 P2 . 5 Z - 3 0").unwrap(),
            vec![
                ('G', 76.0, false, 1, 5),
                ('P', 2.5, true, 7, 6),
                ('Z', -30.0, false, 14, 7)
            ]
        );
        // Tabs and carriage returns too; a number goes on after them.
        assert_eq!(
            lex_blanks("X1\t2 .\r5\tK1").unwrap(),
            vec![('X', 12.5, true, 1, 8), ('K', 1.0, false, 10, 2)]
        );
        // LinuxCNC's documentation: "G0X +0. 12 34Y 7" is "G0 x+0.1234 Y7".
        assert_eq!(
            lex_blanks("G0X +0. 12 34Y 7").unwrap(),
            vec![
                ('G', 0.0, false, 1, 2),
                ('X', 0.1234, true, 3, 11),
                ('Y', 7.0, false, 14, 3)
            ]
        );
        // The lexeme keeps what was written.
        let line = b"P 2 . 5";
        let mut words = Vec::new();
        lex_line_syntax(line, 1, 0, &mut words, &BLANKS).unwrap();
        assert_eq!(words[0].raw(line), b"2 . 5");
        // Blanks inside a comment are the comment's; a comment ends a number.
        assert_eq!(
            lex_blanks("X1 ( a  b ) Z2").unwrap(),
            vec![('X', 1.0, false, 1, 2), ('Z', 2.0, false, 13, 2)]
        );
        let e = lex_blanks("X1 (c) 2").unwrap_err();
        assert_eq!((e.code, e.span.column), (Code::Syntax, 8));
        // A sign only before the digits; a second decimal point at its own column.
        let e = lex_blanks("X1 - 2").unwrap_err();
        assert_eq!(e.span.column, 4);
        let e = lex_blanks("P2 . 5 .").unwrap_err();
        assert_eq!(e.span.column, 8);
        assert!(e.message.contains("second decimal point"), "{}", e.message);
        let e = lex_blanks("G0 X  ").unwrap_err();
        assert!(e.message.contains("number was expected"), "{}", e.message);
        // Without the rule a blank ends the number, and what follows is no word.
        assert!(lex("G 7 6").is_err());
        assert_eq!(
            lex("G 76 X1").unwrap(),
            vec![('G', 76.0, false), ('X', 1.0, false)]
        );
    }

    #[test]
    fn a_comment_inside_a_comment() {
        let e = lex_blanks("G0 (outer (inner) X1").unwrap_err();
        assert_eq!((e.code, e.span.column), (Code::Syntax, 11));
        assert_eq!(e.message, "Nested comment found");
        // Elsewhere the comment ends at its first `)`.
        assert_eq!(
            lex("G0 (outer (inner) X1").unwrap(),
            vec![('G', 0.0, false), ('X', 1.0, false)]
        );
    }

    #[test]
    fn parentheses_are_comments_unless_the_syntax_says_otherwise() {
        let mut words = Vec::new();
        let line = b"G0 X10 (approach) Z5";
        lex_line(line, 1, 0, &mut words).unwrap();
        assert_eq!(words.len(), 3);
        let sinumerik = Syntax {
            parens_not_comments: true,
            hand_over_unread: true,
            ..Syntax::default()
        };
        let e = lex_line_syntax(line, 1, 0, &mut words, &sinumerik).unwrap_err();
        assert_eq!((e.code, e.span.column), (Code::Syntax, 8));
        // `;` comments are comments under both.
        lex_line_syntax(b"G0 X10 ; (approach)", 1, 0, &mut words, &sinumerik).unwrap();
        assert_eq!(words.len(), 2);
    }

    #[test]
    fn block_delete_and_percent() {
        let mut words = Vec::new();
        let shape = lex_line(b"/N5 G0 X1", 1, 0, &mut words).unwrap();
        assert!(shape.block_delete);
        let shape = lex_line(b"%", 1, 0, &mut words).unwrap();
        assert!(shape.percent);
    }

    #[test]
    fn garbage_is_an_error_not_a_panic() {
        let mut words = Vec::new();
        let e = lex_line(&[b'G', b'0', 0xff, 0xfe], 3, 0, &mut words).unwrap_err();
        assert_eq!((e.span.line, e.span.column), (3, 3));
        let e = lex_line("X1 é".as_bytes(), 1, 0, &mut words).unwrap_err();
        assert!(e.message.contains('é'));
    }
}
