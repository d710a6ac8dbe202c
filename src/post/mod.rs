//! Writing: numbers rounded once from absolute values, plain G-code moves in a controller's format,
//! and JSON lines. Readers never write and writers never read the source.

use std::io::{self, Write};

use crate::machine::{CommentStyle, Machine};
use crate::thread::StartIndexing;
use crate::toolpath::{Motion, MotionKind, Toolpath};
use crate::units::{Pos, Units};

/// How a controller writes plain moves.
#[derive(Clone, Debug, PartialEq)]
pub struct Format {
    pub rapid: &'static str,
    pub feed: &'static str,
    /// The synchronised single move (`G32`, `G33`).
    pub thread: &'static str,
    /// The word that carries the lead on a thread move (`F` or `K`).
    pub lead_letter: char,
    /// The variable-lead thread move and the word of its lead change per revolution (Fanuc
    /// `G34 … K`), if the controller has one. Without it a job with a variable lead cannot be
    /// written as plain moves: callers must refuse it (the APT post does).
    pub variable_thread: Option<(&'static str, char)>,
    pub diameter_x: bool,
    /// Decimals of X and Z in mm and in inch programs.
    pub decimals: [u32; 2],
    /// Decimals of the lead word in mm and in inch programs.
    pub lead_decimals: [u32; 2],
    pub trailing_zeros: bool,
    pub comment: CommentStyle,
    /// The lead word is the travel per revolution along the move's path (LinuxCNC's `G33 K`), not
    /// along its longer axis (Fanuc's `G32 F`); the writer converts the model's lead.
    pub lead_along_path: bool,
    /// The lead word of a move that travels further in X than in Z, where it is not
    /// [`lead_letter`](Format::lead_letter) (Sinumerik: `K` is the pitch along Z, `I` along X).
    pub steep_lead_letter: Option<char>,
    /// The word that states the spindle angle at which a synchronised run begins (Fanuc's and
    /// Haas's `G32 … Q`, Sinumerik's `G33 … SF=`), if the controller's plain thread move takes
    /// one. It is written on the first thread move of each run (a thread move after a move of
    /// another kind). `None`: a job with a start angle, or with starts reached by turning the
    /// spindle, cannot be written as plain moves, and callers refuse it ([`expressible`]).
    pub start_angle: Option<StartAngleWord>,
    /// The circular moves, if the controller's plain moves have them (a turning cycle's contour
    /// written as plain moves). `None`: a path with an arc cannot be written.
    pub arc: Option<ArcCodes>,
}

/// How a controller writes a circular move: its codes, the end point as every move's, and the
/// centre as `I` (X, a radius whatever X's mode) and `K` (Z), signed, from the arc's start point
/// to its centre (Fanuc's lathe manuals, "circular interpolation"; the same words on GSK, Haas,
/// LinuxCNC and Sinumerik). I and K are computed from the start point as it was written, so that
/// the control's centre is the written start plus I/K and the arc's end lies on its circle within
/// the output's rounding.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ArcCodes {
    /// Clockwise, with Z to the right and X up (the model's `clockwise`): G2.
    pub cw: &'static str,
    pub ccw: &'static str,
}

impl ArcCodes {
    pub const G2_G3: ArcCodes = ArcCodes {
        cw: "G2",
        ccw: "G3",
    };
}

/// How a controller's thread move states its start angle.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StartAngleWord {
    /// The word as written before its value: `Q`, `SF=`.
    pub name: &'static str,
    pub unit: AngleUnit,
    /// The control keeps the last angle stated (Sinumerik's `SF=` writes setting data 42000
    /// THREAD_START_ANGLE): the word is written on every run, 0 included, so that no angle of an
    /// earlier block carries over. Otherwise the word holds for its block only (Fanuc's and Haas's
    /// `Q`: a run without it starts at 0) and is written where the angle is not 0.
    pub modal: bool,
}

/// The unit and notation of a start-angle word's value.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AngleUnit {
    /// A whole count of 0.001° without a decimal point (Fanuc, Haas: `Q180000` is 180°).
    Millidegrees,
    /// Degrees with a decimal point, to this many decimals (Sinumerik: `SF=180.0000`, 0.0001°).
    Degrees { decimals: u32 },
}

impl AngleUnit {
    /// The smallest step the word writes, in degrees.
    pub fn resolution_deg(self) -> f64 {
        match self {
            AngleUnit::Millidegrees => 0.001,
            AngleUnit::Degrees { decimals } => 10f64.powi(-(decimals as i32)),
        }
    }
}

impl StartAngleWord {
    /// Appends ` Q180000` / ` SF=180.0000`: the angle modulo a turn, rounded once to the word's
    /// resolution (an angle that rounds to 360° is written as 0).
    pub fn push(&self, out: &mut Vec<u8>, phase_deg: f64, trailing_zeros: bool) -> io::Result<()> {
        let phase_deg = finite(phase_deg)?;
        out.push(b' ');
        push_bytes(out, self.name.as_bytes());
        match self.unit {
            AngleUnit::Millidegrees => {
                out.extend_from_slice(start_angle_count(phase_deg).to_string().as_bytes())
            }
            AngleUnit::Degrees { decimals } => {
                let scale = 10f64.powi(decimals as i32);
                let steps = round_half_away(phase_deg.rem_euclid(360.0) * scale);
                let steps = if steps >= 360.0 * scale { 0.0 } else { steps };
                push_number(out, steps / scale, decimals, trailing_zeros);
            }
        }
        Ok(())
    }
}

impl Format {
    /// The common lathe format: positions at the machine's input resolution, leads to 0.0001 mm /
    /// 0.00001 inch (the GSK and Fanuc F ranges).
    pub fn lathe(machine: &Machine, thread: &'static str, lead_letter: char) -> Format {
        Format {
            rapid: "G0",
            feed: "G1",
            thread,
            lead_letter,
            variable_thread: None,
            diameter_x: machine.diameter_x,
            decimals: [machine.decimals(Units::Mm), machine.decimals(Units::Inch)],
            lead_decimals: [4, 5],
            trailing_zeros: machine.output.trailing_zeros,
            comment: machine.output.comment,
            lead_along_path: false,
            steep_lead_letter: None,
            start_angle: None,
            arc: Some(ArcCodes::G2_G3),
        }
    }

    fn digits(&self, units: Units) -> u32 {
        self.decimals[(units == Units::Inch) as usize]
    }

    fn lead_digits(&self, units: Units) -> u32 {
        self.lead_decimals[(units == Units::Inch) as usize]
    }

    /// The X a program in this format writes for a radius in mm.
    pub fn x_word(&self, radius_mm: f64, units: Units) -> f64 {
        let v = units.from_mm(radius_mm);
        if self.diameter_x {
            v * 2.0
        } else {
            v
        }
    }

    /// A comment line, or nothing when the profile writes none.
    pub fn comment(&self, text: &str) -> Option<String> {
        let (open, close) = match self.comment {
            CommentStyle::Paren => ("(", ")"),
            CommentStyle::Semicolon => ("; ", ""),
            CommentStyle::None => return None,
        };
        let mut c = String::with_capacity(open.len() + text.len() + close.len());
        c.push_str(open);
        if text.contains(['(', ')']) {
            c.extend(text.chars().filter(|c| !matches!(c, '(' | ')')));
        } else {
            c.push_str(text);
        }
        c.push_str(close);
        Some(c)
    }
}

/// ` I… K…`: an arc's centre from its start point as written (rounded as the writer rounds it),
/// so that the written start plus I/K is the centre to the output's resolution.
fn push_arc_centre(
    out: &mut Vec<u8>,
    format: &Format,
    units: Units,
    from: Pos,
    centre: Pos,
) -> io::Result<()> {
    let nd = format.digits(units);
    let scale = 10f64.powi(nd as i32);
    let round = |v: f64| (v * scale).round() / scale;
    let per_radius = if format.diameter_x { 2.0 } else { 1.0 };
    let start_x = round(finite(format.x_word(from.x, units))?) / per_radius;
    let start_z = round(finite(units.from_mm(from.z))?);
    let i = finite(units.from_mm(centre.x))? - start_x;
    let k = finite(units.from_mm(centre.z))? - start_z;
    out.extend_from_slice(b" I");
    push_number(out, i, nd, format.trailing_zeros);
    out.extend_from_slice(b" K");
    push_number(out, k, nd, format.trailing_zeros);
    Ok(())
}

/// Formats `value` rounded to `decimals`, always with a decimal point (`10.`, `-0.5`), never with an
/// exponent, never `-0.`. Rounding happens once, here, from the absolute value.
pub fn number(value: f64, decimals: u32, trailing_zeros: bool) -> String {
    let mut s = Vec::with_capacity(16);
    push_number(&mut s, value, decimals, trailing_zeros);
    String::from_utf8(s).expect("ASCII")
}

/// As [`number`], appended to `out` as ASCII bytes without allocating (the expansion's hot path).
pub fn push_number(out: &mut Vec<u8>, value: f64, decimals: u32, trailing_zeros: bool) {
    let mut text = [0u8; 32];
    match write_small(&mut text, 0, value, decimals, trailing_zeros) {
        // A fixed-size copy (inlined, no memmove call) and a truncation.
        Some(len) => {
            let at = out.len();
            out.extend_from_slice(&text);
            out.truncate(at + len);
        }
        None => push_number_wide(
            out,
            round_half_away(value * 10f64.powi(decimals as i32)),
            decimals,
            trailing_zeros,
        ),
    }
}

/// Writes the text of `value` at `buf[at..]`, which must hold 32 bytes from there, when it has
/// fewer than 9.2 × 10¹⁸ increments and at most 15 decimals (every format's), and returns its
/// length; `None` (nothing written that counts) sends the caller to [`push_number_wide`].
///
/// The increments are one integer, split once into the whole part and the fraction (by a constant
/// divisor for each usual count of decimals: a multiplication, not a division); both are written
/// straight into their places, two digits at a time, and the fraction's trailing zeros are dropped
/// afterwards by looking at the written bytes unless they are asked for. The text is written where
/// it is wanted, in the caller's buffer: built on the stack and copied, its bytes were read back
/// wider than they were written, which stalls (docs/performance.md, "LinuxCNC G76 expansion").
#[inline]
fn write_small(
    buf: &mut [u8],
    at: usize,
    value: f64,
    decimals: u32,
    trailing_zeros: bool,
) -> Option<usize> {
    debug_assert!(
        value.is_finite(),
        "non-finite values are rejected before writing"
    );
    let d = decimals as usize;
    let p = *POW10.get(d)?;
    let units = round_half_away(value * p as f64);
    // Below 2⁶³, so that the conversion is one instruction (through i64). The rest goes the wide
    // way, which writes the same text (and a NaN is refused before writing anyway).
    if units.is_nan() || units.abs() >= 9.2e18 {
        return None;
    }
    let magnitude = units.abs() as i64 as u64;
    let (whole, frac) = split_increments(magnitude, units.abs(), d);
    // At most 1 + 19 + 1 bytes: the magnitude has at most 19 digits, and at most d + 1 ≤ 16
    // when its whole part is 0.
    let text: &mut [u8; 32] = (&mut buf[at..at + 32])
        .try_into()
        .expect("a slice of 32 bytes");
    // Never `-0.`: a sign only where some digit is not 0.
    let sign = usize::from(units < 0.0 && magnitude != 0);
    text[0] = b'-';
    let whole_digits = decimal_digits(whole);
    let point = sign + whole_digits;
    write_digits(text, point, whole, whole_digits);
    text[point] = b'.';
    let mut end = point + 1 + d;
    write_digits(text, end, frac, d);
    if !trailing_zeros {
        while end > point + 1 && text[end - 1] == b'0' {
            end -= 1;
        }
    }
    Some(end)
}

/// How many decimal digits `v` has (1 for 0); coordinates mostly have one to three.
#[inline(always)]
fn decimal_digits(v: u64) -> usize {
    if v < 10 {
        1
    } else if v < 100 {
        2
    } else if v < 1000 {
        3
    } else {
        v.ilog10() as usize + 1
    }
}

/// `magnitude` (= `float`, `decimals` ≤ 15) split into its whole part and its last `decimals`
/// digits. Below 2⁵⁰ the whole part is first estimated in floating point, by a multiplication with
/// the reciprocal (off by at most one: the product's relative error is below 2.3 × 10⁻¹⁶, so
/// its absolute error below 2⁵⁰ is under 0.3), and put right by the exact remainder; an integer division by a
/// power of ten that is not known at compile time costs several times as much. Above, the
/// division.
#[inline(always)]
fn split_increments(magnitude: u64, float: f64, decimals: usize) -> (u64, u64) {
    let p = POW10[decimals];
    if magnitude >= 1 << 50 {
        return (magnitude / p, magnitude % p);
    }
    let estimate = (float * RECIPROCALS[decimals]) as u64;
    // At most one too many or too few.
    let rest = magnitude as i64 - (estimate * p) as i64;
    if rest < 0 {
        (estimate - 1, (rest + p as i64) as u64)
    } else if rest >= p as i64 {
        (estimate + 1, rest as u64 - p)
    } else {
        (estimate, rest as u64)
    }
}

/// 10⁻ⁿ, rounded, for [`split_increments`]'s estimates.
const RECIPROCALS: [f64; 16] = {
    let mut t = [1.0; 16];
    let mut i = 1;
    while i < 16 {
        t[i] = 1.0 / POW10[i] as f64;
        i += 1;
    }
    t
};

/// Writes the last `count` decimal digits of `v` so that they end before `end`, two at a time.
#[inline(always)]
fn write_digits(text: &mut [u8; 32], mut end: usize, mut v: u64, mut count: usize) {
    while count >= 2 {
        let pair = (v % 100) as usize * 2;
        v /= 100;
        text[end - 2] = DIGIT_PAIRS[pair];
        text[end - 1] = DIGIT_PAIRS[pair + 1];
        end -= 2;
        count -= 2;
    }
    if count == 1 {
        text[end - 1] = b'0' + (v % 10) as u8;
    }
}

/// "00" to "99".
const DIGIT_PAIRS: [u8; 200] = {
    let mut t = [0u8; 200];
    let mut i = 0;
    while i < 100 {
        t[2 * i] = b'0' + (i / 10) as u8;
        t[2 * i + 1] = b'0' + (i % 10) as u8;
        i += 1;
    }
    t
};

/// `x.round()` (half away from zero) without a libm call: below 2⁵² the fraction `x − trunc(x)` is
/// exact, so the comparison with 0.5 is too; above it every double is already an integer.
fn round_half_away(x: f64) -> f64 {
    if x.abs() >= 4_503_599_627_370_496.0 || x.is_nan() {
        return x;
    }
    let t = x as i64 as f64;
    let f = x - t;
    if f >= 0.5 {
        t + 1.0
    } else if f <= -0.5 {
        t - 1.0
    } else {
        t
    }
}

/// The rare path for values beyond 10¹⁹ increments.
fn push_number_wide(out: &mut Vec<u8>, units: f64, decimals: u32, trailing_zeros: bool) {
    let magnitude = units.abs() as u128;
    let divisor = 10u128.pow(decimals);
    let (whole, frac) = (magnitude / divisor, magnitude % divisor);
    if units < 0.0 && magnitude != 0 {
        out.push(b'-');
    }
    out.extend_from_slice(whole.to_string().as_bytes());
    out.push(b'.');
    if decimals > 0 {
        let f = format!("{:0width$}", frac, width = decimals as usize);
        let f = if trailing_zeros {
            f.as_str()
        } else {
            f.trim_end_matches('0')
        };
        out.extend_from_slice(f.as_bytes());
    }
}

/// Formats `value` rounded once to a multiple of `step` (a controller resolution such as OmniTurn's
/// .00005"), with as many decimals as the step needs.
pub fn number_on_grid(value: f64, step: f64, trailing_zeros: bool) -> String {
    let decimals = (0..=9)
        .find(|&d| {
            let scaled = step * 10f64.powi(d);
            (scaled - scaled.round()).abs() < 1e-9
        })
        .unwrap_or(9) as u32;
    number((value / step).round() * step, decimals, trailing_zeros)
}

/// Whether `format` can write `job`'s moves as plain blocks: a lead that changes every revolution
/// needs the controller's variable-lead move, a start angle other than 0 (or starts reached by
/// turning the spindle) its start-angle word.
pub fn expressible(
    format: &Format,
    job: &crate::thread::Job,
) -> Result<(), crate::diag::Diagnostic> {
    if job.lead.dlead != 0.0 && format.variable_thread.is_none() {
        return Err(crate::diag::Diagnostic::error(
            crate::diag::Code::Unsupported,
            job.span,
            format!(
                "the lead changes by {} mm every revolution, and this controller has no variable-lead move in threadcut",
                job.lead.dlead
            ),
        )
        .with_hint("choose a controller with a variable-lead thread move (G34)"));
    }
    let angle_indexed = job.lead.starts > 1 && job.lead.indexing == StartIndexing::Angle;
    if format.start_angle.is_none() && (job.lead.phase_deg != 0.0 || angle_indexed) {
        return Err(crate::diag::Diagnostic::error(
            crate::diag::Code::Unsupported,
            job.span,
            if angle_indexed {
                format!(
                    "the {} starts of this thread are reached by turning the spindle (360°/{} apart), and this controller's plain thread moves cannot state a start angle in threadcut",
                    job.lead.starts, job.lead.starts
                )
            } else {
                format!(
                    "the thread starts {}° after the spindle's one-revolution signal, and this controller's plain thread moves cannot state a start angle in threadcut",
                    job.lead.phase_deg
                )
            },
        )
        .with_hint("choose a controller whose thread move takes a start angle (Fanuc, Haas: G32 … Q; Sinumerik: G33 … SF=)"));
    }
    Ok(())
}

/// A value about to be written: a non-finite number is refused here, where numbers are written, so
/// that no `NaN` or `inf` can reach a program whatever happened upstream.
pub fn finite(value: f64) -> io::Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("refusing to write the non-finite value {value}"),
        ))
    }
}
/// Powers of ten that are exact as f64.
const POW10: [u64; 16] = {
    let mut t = [1u64; 16];
    let mut i = 1;
    while i < 16 {
        t[i] = t[i - 1] * 10;
        i += 1;
    }
    t
};

/// A cycle's moves as [`write_moves`] writes them, owned: they can be written later and on another
/// thread ([`MovesOut`]).
#[derive(Clone, Debug)]
pub struct Moves {
    pub format: Format,
    pub units: Units,
    pub path: Toolpath,
}

impl Moves {
    /// The moves' text, as [`write_moves`] writes it.
    pub fn write(&self, out: &mut dyn Write) -> io::Result<()> {
        write_moves(out, &self.format, self.units, &self.path)
    }

    /// The lines [`write`](Moves::write) writes, without writing them: one a motion, each ended.
    pub fn lines(&self) -> usize {
        self.path.motions.len()
    }
}

/// Where `expand` writes: bytes, and each cycle's moves in their place among them. A writer may
/// write the moves at once ([`Now`], a `Vec`, a line-ending converter) or hand them on to be
/// written later in the same place: the command formats them on its second core while the library
/// reads on (the library itself stays single-threaded, for wasm32; docs/performance.md, issue 28).
pub trait MovesOut: Write {
    fn moves(&mut self, moves: Moves) -> io::Result<()>;

    /// Whether the text written from here on is kept: `false` for a writer that only counts its
    /// lines (the page's first lines of a long program, past them). `expand` then records a
    /// streamed cycle it may have to compare later by what it is made from, not by its text.
    fn keeps_text(&self) -> bool {
        true
    }
}

/// Any writer as a [`MovesOut`] that writes moves at once.
pub struct Now<W: Write>(pub W);

impl<W: Write> Write for Now<W> {
    #[inline]
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.write(buf)
    }
    #[inline]
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        self.0.write_all(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

impl<W: Write> MovesOut for Now<W> {
    fn moves(&mut self, moves: Moves) -> io::Result<()> {
        moves.write(&mut self.0)
    }
}

impl MovesOut for Vec<u8> {
    fn moves(&mut self, moves: Moves) -> io::Result<()> {
        moves.write(self)
    }
}

impl<W: Write> MovesOut for crate::eol::Writer<W> {
    fn moves(&mut self, moves: Moves) -> io::Result<()> {
        moves.write(self)
    }
}

/// Writes the moves of a toolpath as plain blocks, one per motion.
pub fn write_moves(
    out: &mut dyn Write,
    format: &Format,
    units: Units,
    path: &Toolpath,
) -> io::Result<()> {
    let nd = format.digits(units);
    let ld = format.lead_digits(units);
    let tz = format.trailing_zeros;
    // The whole path's text is built in one buffer and written at once (every 64 KiB): one copy
    // into the writer instead of one per line. The buffer is written at a cursor (`Text`), each
    // number's text straight into its place: a push per byte into a vector cost more than the
    // digits did, and so did assembling each line on the stack first (docs/performance.md).
    let mut text = Text::new(path.motions.len());
    // Moves share coordinates and leads: each is formatted once while it recurs (same text either
    // way). A pass comes back to the X it started from; two leads alternate in a pass (the thread's
    // and the pull-out's along its path).
    let (mut xs, mut zs, mut leads) = (Recent::<3>::new(), Recent::<1>::new(), Recent::<2>::new());
    // Whether the previous move was synchronised: a start angle belongs to a run's first move.
    let mut in_run = false;
    let mut letter = [0u8; 4];
    // The rare words written through a vector (a number too long for the fast formatter, the
    // variable lead, the start angle).
    let mut scratch = Vec::new();
    for (from, m) in path.segments() {
        if text.pos > Text::FLUSH_AT {
            text.flush(out)?;
            // The cached texts lay in what was written out.
            (xs, zs, leads) = (Recent::new(), Recent::new(), Recent::new());
        }
        let (code, lead, dlead) = match m.kind {
            MotionKind::Rapid => (format.rapid, None, None),
            MotionKind::Feed => (format.feed, None, None),
            MotionKind::Thread { lead, dlead, .. } => match format.variable_thread {
                Some((code, letter)) if dlead != 0.0 => (code, Some(lead), Some((letter, dlead))),
                // Never a variable lead as a constant one: callers check first (`expressible`);
                // this is the last guard.
                None if dlead != 0.0 => {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidData,
                        "refusing to write a variable lead as a constant-lead move",
                    ))
                }
                _ => (format.thread, Some(lead), None),
            },
            MotionKind::Arc { clockwise, .. } => match format.arc {
                Some(a) => (if clockwise { a.cw } else { a.ccw }, None, None),
                // Never an arc as a straight move: the last guard.
                None => {
                    return Err(io::Error::new(
                        io::ErrorKind::InvalidData,
                        "refusing to write an arc as a straight move: this controller's plain moves have no arc",
                    ))
                }
            },
        };
        text.put(code.as_bytes());
        text.put(b" X");
        let x = finite(format.x_word(m.to.x, units))?;
        xs.put(&mut text, x, nd, tz);
        text.put(b" Z");
        zs.put(&mut text, finite(units.from_mm(m.to.z))?, nd, tz);
        if let Some(lead) = lead {
            let d = m.to.minus(from);
            let lead = if format.lead_along_path {
                path_lead(lead, d)
            } else {
                lead
            };
            let lead_letter = match format.steep_lead_letter {
                Some(steep) if d.x.abs() > d.z.abs() => steep,
                _ => format.lead_letter,
            };
            text.put_letter(lead_letter, &mut letter);
            leads.put(&mut text, finite(units.from_mm(lead))?, ld, tz);
        }
        if let Some((dlead_letter, dlead)) = dlead {
            text.put(b" ");
            text.put(dlead_letter.encode_utf8(&mut letter).as_bytes());
            scratch.clear();
            push_number(&mut scratch, finite(units.from_mm(dlead))?, ld, tz);
            text.put(&scratch);
        }
        if let MotionKind::Thread { phase_deg, .. } = m.kind {
            if !in_run {
                scratch.clear();
                push_start_angle(&mut scratch, format, phase_deg)?;
                text.put(&scratch);
            }
        }
        if let MotionKind::Arc { centre, .. } = m.kind {
            scratch.clear();
            push_arc_centre(&mut scratch, format, units, from, centre)?;
            text.put(&scratch);
        }
        in_run = matches!(m.kind, MotionKind::Thread { .. });
        text.put(b"\n");
    }
    text.flush(out)
}

/// A path's text: a buffer kept at its full length and written at a cursor, each piece with one
/// copy whose length is known where it is written (a short code, a number's 32-byte window), so
/// that no copy calls `memmove` and no push checks the capacity. What the cursor has passed is
/// the text; what lies beyond it is scratch.
struct Text {
    bytes: Vec<u8>,
    pos: usize,
}

thread_local! {
    /// [`Text`]'s buffer between paths (empty while a path is written, and before the first).
    static TEXT_BUFFER: std::cell::Cell<Vec<u8>> = const { std::cell::Cell::new(Vec::new()) };
}

impl Drop for Text {
    fn drop(&mut self) {
        // A buffer grown far past the usual size (a profile's long codes) is not kept.
        if self.bytes.len() <= 2 * Text::FLUSH_AT {
            TEXT_BUFFER.set(std::mem::take(&mut self.bytes));
        }
    }
}

impl Text {
    /// The text is written out once the cursor has passed this.
    const FLUSH_AT: usize = 1 << 16;

    /// Room for `moves` blocks of a usual length (the buffer grows if they are longer), at most
    /// what is written at once. The buffer is the thread's, reused from path to path: allocating
    /// and zeroing one for each cycle cost 7 % of an expansion's instructions (docs/performance.md).
    fn new(moves: usize) -> Text {
        let mut bytes = TEXT_BUFFER.take();
        let want = moves.saturating_mul(48).min(Text::FLUSH_AT) + 1024;
        if bytes.len() < want {
            bytes.resize(want, 0);
        }
        Text { bytes, pos: 0 }
    }

    #[inline(always)]
    fn put(&mut self, piece: &[u8]) {
        let end = self.pos + piece.len();
        if end > self.bytes.len() {
            // A longer piece than any format writes (a code from a machine profile, say).
            self.bytes.resize(end + 1024, 0);
        }
        self.bytes[self.pos..end].copy_from_slice(piece);
        self.pos = end;
    }

    /// A blank and a word's letter.
    #[inline(always)]
    fn put_letter(&mut self, letter: char, scratch: &mut [u8; 4]) {
        if letter.is_ascii() {
            self.put(&[b' ', letter as u8]);
        } else {
            self.put(b" ");
            self.put(letter.encode_utf8(scratch).as_bytes());
        }
    }

    /// Makes sure that `n` bytes from the cursor lie in the buffer.
    #[inline(always)]
    fn room(&mut self, n: usize) {
        if self.pos + n > self.bytes.len() {
            self.bytes.resize(self.pos + n + 1024, 0);
        }
    }

    fn flush(&mut self, out: &mut dyn Write) -> io::Result<()> {
        out.write_all(&self.bytes[..self.pos])?;
        self.pos = 0;
        Ok(())
    }
}

/// The start angle of a run's first thread move, where the format writes one: always where the
/// control keeps the last angle, else where it is not 0.
fn push_start_angle(out: &mut Vec<u8>, format: &Format, phase_deg: f64) -> io::Result<()> {
    match format.start_angle {
        Some(word) if word.modal || phase_deg != 0.0 => {
            word.push(out, phase_deg, format.trailing_zeros)
        }
        Some(_) => Ok(()),
        // Callers check first (`expressible`); this is the last guard.
        None if phase_deg != 0.0 => Err(io::Error::new(
            io::ErrorKind::InvalidData,
            "refusing to drop a thread's start angle: this controller has no start-angle word",
        )),
        None => Ok(()),
    }
}

/// A start angle (degrees) as the count of 0.001° a Fanuc or Haas `Q` word carries, modulo a
/// turn (0 to 359999).
pub fn start_angle_count(phase_deg: f64) -> u32 {
    (round_half_away(phase_deg.rem_euclid(360.0) * 1000.0) as u32) % 360_000
}

/// Appends a few bytes; for a handful a memmove call costs more than the copy.
fn push_bytes(out: &mut Vec<u8>, bytes: &[u8]) {
    for &b in bytes {
        out.push(b);
    }
}

/// Where a number's text starts in the path's text, and its length.
type TextAt = (usize, usize);

/// The last `N` values formatted for one word, and where their texts lie in the path's text
/// (`None`: a number for the wide path). A new value replaces the oldest. Valid until the text is
/// flushed (`write_moves` then starts afresh).
struct Recent<const N: usize> {
    slots: [(Option<u64>, Option<TextAt>); N],
    oldest: usize,
}

impl<const N: usize> Recent<N> {
    fn new() -> Self {
        Recent {
            slots: [(None, None); N],
            oldest: 0,
        }
    }

    #[inline(always)]
    fn put(&mut self, text: &mut Text, value: f64, decimals: u32, trailing_zeros: bool) {
        text.room(32);
        let bits = Some(value.to_bits());
        let at = match self.slots.iter().find(|slot| slot.0 == bits) {
            // The same text again: one fixed-size copy from where it was written (the bytes past
            // its end are overwritten by what follows).
            Some(&(_, Some((from, len)))) => {
                text.bytes.copy_within(from..from + 32, text.pos);
                text.pos += len;
                return;
            }
            Some(&(_, None)) => None,
            None => {
                let at = write_small(&mut text.bytes, text.pos, value, decimals, trailing_zeros)
                    .map(|len| (text.pos, len));
                self.slots[self.oldest] = (bits, at);
                self.oldest = (self.oldest + 1) % N;
                at
            }
        };
        match at {
            Some((_, len)) => text.pos += len,
            None => {
                let mut wide = Vec::new();
                push_number(&mut wide, value, decimals, trailing_zeros);
                text.put(&wide);
            }
        }
    }
}

/// The travel per revolution along a move's path, from the lead along its longer axis (the model's
/// convention, [`crate::toolpath::lead_along_long_axis`]).
pub fn path_lead(lead: f64, d: crate::units::Vec2) -> f64 {
    let long = d.x.abs().max(d.z.abs());
    if long == 0.0 {
        lead
    } else {
        lead * d.x.hypot(d.z) / long
    }
}

/// The lead along a move's longer axis, from the travel per revolution along its path.
pub fn long_axis_lead(path_lead: f64, d: crate::units::Vec2) -> f64 {
    let len = d.x.hypot(d.z);
    if len == 0.0 {
        path_lead
    } else {
        path_lead * d.x.abs().max(d.z.abs()) / len
    }
}

/// One motion as a JSON object in program units, X as a radius (an arc: `"kind":"arc"` with `"cw"` and
/// its centre `"cx"`, `"cz"`):
/// `{"kind":"thread","x":…,"z":…,"lead":…,"pass":n,"line":l}` (`"dlead"` after `"lead"` when the
/// lead varies, then `"phase"`, the run's start angle in degrees, when it is not 0).
pub fn motion_json(m: &Motion, units: Units) -> String {
    let x = units.from_mm(m.to.x);
    let z = units.from_mm(m.to.z);
    let (lead, dlead, phase_deg) = match m.kind {
        MotionKind::Rapid | MotionKind::Feed => {
            return format!(
                r#"{{"kind":"{}","x":{},"z":{},"pass":{},"line":{}}}"#,
                if m.kind == MotionKind::Rapid {
                    "rapid"
                } else {
                    "feed"
                },
                json_num(x),
                json_num(z),
                m.pass,
                m.line
            )
        }
        MotionKind::Thread {
            lead,
            dlead,
            phase_deg,
        } => (lead, dlead, phase_deg),
        MotionKind::Arc { centre, clockwise } => {
            return format!(
                r#"{{"kind":"arc","x":{},"z":{},"cw":{clockwise},"cx":{},"cz":{},"pass":{},"line":{}}}"#,
                json_num(x),
                json_num(z),
                json_num(units.from_mm(centre.x)),
                json_num(units.from_mm(centre.z)),
                m.pass,
                m.line
            )
        }
    };
    let mut out = format!(
        r#"{{"kind":"thread","x":{},"z":{},"lead":{}"#,
        json_num(x),
        json_num(z),
        json_num(units.from_mm(lead))
    );
    // A variable lead adds `"dlead"` (change of lead per revolution, at the move's start lead).
    if dlead != 0.0 {
        out.push_str(r#","dlead":"#);
        out.push_str(&json_num(units.from_mm(dlead)));
    }
    if phase_deg != 0.0 {
        out.push_str(r#","phase":"#);
        out.push_str(&json_num(phase_deg));
    }
    out.push_str(&format!(r#","pass":{},"line":{}}}"#, m.pass, m.line));
    out
}

/// Shortest round-trip text of a finite f64 (serde_json's), `0` for negative zero.
pub fn json_num(v: f64) -> String {
    let v = if v == 0.0 { 0.0 } else { v };
    serde_json::Number::from_f64(v).map_or_else(|| "null".to_string(), |n| n.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The formatter this module had before the whole part and the fraction were written
    /// separately (digit by digit, least significant first, reversed into place): the reference
    /// the fast one must match byte for byte.
    fn format_small_digit_by_digit(
        value: f64,
        decimals: u32,
        trailing_zeros: bool,
    ) -> Option<String> {
        debug_assert!(
            value.is_finite(),
            "non-finite values are rejected before writing"
        );
        let scale = if (decimals as usize) < POW10.len() {
            POW10[decimals as usize] as f64
        } else {
            10f64.powi(decimals as i32)
        };
        let units = round_half_away(value * scale);
        let negative = units < 0.0;
        if units.abs() >= 1e19 || decimals as usize >= 20 {
            return None;
        }
        let mut v = units.abs() as u64;
        // All digits of the scaled value, least significant first, at least `decimals + 1` of them,
        // two at a time.
        let mut digits = [b'0'; 24];
        let mut n = 0;
        while v >= 100 {
            let pair = (v % 100) as usize * 2;
            v /= 100;
            digits[n] = DIGIT_PAIRS[pair + 1];
            digits[n + 1] = DIGIT_PAIRS[pair];
            n += 2;
        }
        while v != 0 {
            digits[n] = b'0' + (v % 10) as u8;
            v /= 10;
            n += 1;
        }
        let d = decimals as usize;
        n = n.max(d + 1);
        // Drop trailing zeros of the fraction unless asked to keep them.
        let mut low = 0;
        if !trailing_zeros {
            while low < d && digits[low] == b'0' {
                low += 1;
            }
        }
        // The text, most significant first, assembled on the stack and appended at once.
        let mut text = [0u8; 32];
        let mut t = 0;
        if negative && digits[low..n].iter().any(|&b| b != b'0') {
            text[0] = b'-';
            t = 1;
        }
        for i in (d..n).rev() {
            text[t] = digits[i];
            t += 1;
        }
        text[t] = b'.';
        t += 1;
        for i in (low..d).rev() {
            text[t] = digits[i];
            t += 1;
        }
        Some(String::from_utf8(text[..t].to_vec()).unwrap())
    }

    fn small_text(value: f64, decimals: u32, trailing_zeros: bool) -> Option<String> {
        let mut text = [0u8; 32];
        write_small(&mut text, 0, value, decimals, trailing_zeros)
            .map(|len| String::from_utf8(text[..len].to_vec()).unwrap())
    }

    /// The fast formatter's text, or the old formatter's `None` where the fast one leaves a number
    /// to the wide path: from 9.2 × 10¹⁸ increments on (the old one took up to 10¹⁹, the wide path
    /// writes the same text, which `number` is checked for). Below that the fast one must answer.
    fn small_or_wide(value: f64, decimals: u32, trailing_zeros: bool) -> Option<String> {
        let units = round_half_away(value * POW10[decimals as usize] as f64);
        match small_text(value, decimals, trailing_zeros) {
            None if units.abs() >= 9.2e18 => {
                format_small_digit_by_digit(value, decimals, trailing_zeros)
            }
            small => small,
        }
    }

    proptest::proptest! {
        /// The fast formatter writes what the digit-by-digit one wrote, for values of every size
        /// the formats meet, rounding ties and all, and `number` as a whole goes on to the wide
        /// path exactly where it did.
        #[test]
        fn fast_numbers_are_the_digit_by_digit_ones(
            mantissa in -10_000_000_000i64..10_000_000_000,
            exponent in -12i32..8,
            half in proptest::bool::ANY,
            decimals in 0u32..16,
            trailing_zeros in proptest::bool::ANY,
        ) {
            let value = mantissa as f64 * 10f64.powi(exponent) + if half { 0.5 * 10f64.powi(-(decimals as i32)) } else { 0.0 };
            let want = format_small_digit_by_digit(value, decimals, trailing_zeros);
            proptest::prop_assert_eq!(small_or_wide(value, decimals, trailing_zeros), want.clone());
            if let Some(want) = want {
                proptest::prop_assert_eq!(number(value, decimals, trailing_zeros), want);
            }
        }
    }

    /// The estimate and its correction give the integer division's answer at every boundary
    /// between two whole parts (one below, at, one above), for every count of decimals, from small
    /// numbers up to the fast path's end and past it.
    #[test]
    fn increments_split_as_the_division_splits_them() {
        for (d, &p) in POW10.iter().enumerate() {
            let mut wholes: Vec<u64> = (0..2000).collect();
            for k in 0..64 {
                let w = (1u64 << 50) / p;
                wholes.extend([
                    w.saturating_sub(k),
                    w + k,
                    (1u64 << 40) / p + k,
                    (1u64 << 62) / p - k,
                ]);
            }
            for w in wholes {
                for m in [(w * p).saturating_sub(1), w * p, w * p + 1, w * p + p / 2] {
                    assert_eq!(
                        split_increments(m, m as f64, d),
                        (m / p, m % p),
                        "{m} with {d} decimals"
                    );
                }
            }
        }
    }

    #[test]
    fn fast_numbers_at_the_edges() {
        for &(value, decimals) in &[
            (0.0, 0),
            (-0.0, 3),
            (-0.00049, 3),
            (0.0005, 3),
            (9.9995, 3),
            (-9.9995, 3),
            (99.99995, 4),
            (1e18, 0),
            (9.999e18, 0),
            (1e19, 0),
            (-1e19, 0),
            (1e14, 4),
            (123456789012345.6, 4),
            (0.5, 0),
            (-0.5, 0),
            (1.5, 0),
            (2.5, 0),
            (1e-15, 15),
            (7.0, 15),
            (0.1, 15),
            (1.0, 19),
            (3.25, 17),
        ] {
            for tz in [false, true] {
                let want = format_small_digit_by_digit(value, decimals, tz);
                if decimals < 16 {
                    assert_eq!(
                        small_or_wide(value, decimals, tz),
                        want,
                        "{value} {decimals} {tz}"
                    );
                }
                if let Some(want) = want {
                    assert_eq!(number(value, decimals, tz), want, "{value} {decimals} {tz}");
                }
            }
        }
    }

    #[test]
    fn numbers_round_once_and_keep_the_point() {
        assert_eq!(number(10.0, 3, false), "10.");
        assert_eq!(number(62.4, 3, false), "62.4");
        assert_eq!(number(62.4, 3, true), "62.400");
        assert_eq!(number(-0.0004, 3, false), "0.");
        assert_eq!(number(0.0005, 3, false), "0.001");
        assert_eq!(number(-12.5, 0, false), "-13.");
        assert_eq!(number(1e9, 4, false), "1000000000.");
    }

    #[test]
    fn grid_numbers_round_to_the_step() {
        assert_eq!(number_on_grid(0.2200294, 0.00005, false), "0.22005");
        assert_eq!(number_on_grid(0.2200294, 0.00025, false), "0.22");
        assert_eq!(number_on_grid(0.33333, 0.00025, false), "0.33325");
        assert_eq!(number_on_grid(0.33333, 0.0005, true), "0.3335");
        assert_eq!(number_on_grid(-0.5, 0.00005, false), "-0.5");
    }

    #[test]
    fn rounding_matches_f64_round() {
        for x in [
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            4503599627370495.5,
            -4503599627370495.5,
            1e300,
            123456.4999,
            0.0,
            -0.0,
        ] {
            assert_eq!(round_half_away(x), x.round(), "{x}");
        }
        assert_eq!(number(-1234567.891234, 4, true), "-1234567.8912");
        assert_eq!(number(0.0001, 4, false), "0.0001");
        assert_eq!(number(100.0, 4, false), "100.");
    }

    const SF: StartAngleWord = StartAngleWord {
        name: "SF=",
        unit: AngleUnit::Degrees { decimals: 4 },
        modal: true,
    };
    const Q: StartAngleWord = StartAngleWord {
        name: "Q",
        unit: AngleUnit::Millidegrees,
        modal: false,
    };

    #[test]
    fn start_angle_words_round_once_modulo_a_turn() {
        let text = |w: StartAngleWord, deg: f64| {
            let mut out = Vec::new();
            w.push(&mut out, deg, true).unwrap();
            String::from_utf8(out).unwrap()
        };
        assert_eq!(text(Q, 180.0), " Q180000");
        assert_eq!(text(Q, 0.0005), " Q1");
        assert_eq!(text(Q, 359.9996), " Q0");
        assert_eq!(text(SF, 180.0), " SF=180.0000");
        assert_eq!(text(SF, 359.9996), " SF=359.9996");
        assert_eq!(text(SF, 359.99996), " SF=0.0000");
        assert_eq!(text(SF, -90.0), " SF=270.0000");
        assert_eq!(start_angle_count(360.0), 0);
        assert_eq!(start_angle_count(45.0), 45_000);
        let mut out = Vec::new();
        assert!(Q.push(&mut out, f64::NAN, true).is_err());
    }

    /// A word the control keeps is written on every run, 0 included; a word of one block only
    /// where the angle is not 0.
    #[test]
    fn start_angles_on_the_first_move_of_each_run() {
        use crate::units::Pos;
        let m = Machine::built_in("fanuc").unwrap();
        let run = |phase_deg: f64| {
            [
                Motion {
                    kind: MotionKind::Thread {
                        lead: 2.0,
                        dlead: 0.0,
                        phase_deg,
                    },
                    to: Pos::new(10.0, -20.0),
                    pass: 1,
                    line: 1,
                },
                Motion {
                    kind: MotionKind::Rapid,
                    to: Pos::new(10.0, 2.0),
                    pass: 1,
                    line: 1,
                },
            ]
        };
        let path = Toolpath {
            start: Pos::new(10.0, 2.0),
            motions: [run(0.0), run(90.0)].concat(),
        };
        let written = |word: Option<StartAngleWord>| {
            let format = Format {
                start_angle: word,
                ..Format::lathe(&m, "G32", 'F')
            };
            let mut out = Vec::new();
            write_moves(&mut out, &format, Units::Mm, &path)
                .map(|_| String::from_utf8(out).unwrap())
        };
        let lines = |text: String| -> Vec<String> {
            text.lines()
                .filter(|l| l.starts_with("G32"))
                .map(|l| l.split_once(" F").unwrap().1.to_string())
                .collect()
        };
        assert_eq!(lines(written(Some(Q)).unwrap()), ["2.", "2. Q90000"]);
        assert_eq!(lines(written(Some(SF)).unwrap()), ["2. SF=0.", "2. SF=90."]);
        assert!(written(None).is_err(), "a start angle is never dropped");
    }

    #[test]
    fn start_angles_and_the_steep_lead_word() {
        use crate::units::Pos;
        let m = Machine::built_in("sinumerik").unwrap();
        let format = Format {
            steep_lead_letter: Some('I'),
            start_angle: Some(SF),
            ..Format::lathe(&m, "G33", 'K')
        };
        let thread = |x: f64, z: f64, lead: f64| Motion {
            kind: MotionKind::Thread {
                lead,
                dlead: 0.0,
                phase_deg: 120.0,
            },
            to: Pos::new(x, z),
            pass: 1,
            line: 1,
        };
        let path = Toolpath {
            start: Pos::new(10.0, 2.0),
            motions: vec![
                thread(10.0, -20.0, 2.0),
                // A steep pull-out continues the chain: no start angle, I for the X pitch.
                thread(12.0, -21.0, 4.0),
                Motion {
                    kind: MotionKind::Rapid,
                    to: Pos::new(12.0, 2.0),
                    pass: 1,
                    line: 1,
                },
                thread(10.0, -20.0, 2.0),
            ],
        };
        let mut out = Vec::new();
        write_moves(&mut out, &format, Units::Mm, &path).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "G33 X20.000 Z-20.000 K2.0000 SF=120.0000\nG33 X24.000 Z-21.000 I4.0000\nG0 X24.000 Z2.000\nG33 X20.000 Z-20.000 K2.0000 SF=120.0000\n"
        );
    }

    #[test]
    fn json_numbers_are_plain() {
        assert_eq!(json_num(-0.0), "0.0");
        assert_eq!(json_num(1.5), "1.5");
    }

    /// An arc is written with its end point and its centre from its start point as written:
    /// I a radius whatever X's mode, K along Z.
    #[test]
    fn arcs_with_their_centre_from_the_written_start() {
        let m = Machine::built_in("fanuc").unwrap();
        let arc = |to, centre, clockwise| Motion {
            kind: MotionKind::Arc { centre, clockwise },
            to,
            pass: 1,
            line: 1,
        };
        // From r15 Z-20 clockwise about (20, −20) to r20 Z-25: I = 20 − 15 = 5, K = 0; X Ø40.
        // Then counter-clockwise about (20, −30) to r25 Z-30: I = 0, K = −30 − (−25) = −5.
        let path = Toolpath {
            start: Pos::new(15.0, -20.0),
            motions: vec![
                arc(Pos::new(20.0, -25.0), Pos::new(20.0, -20.0), true),
                arc(Pos::new(25.0, -30.0), Pos::new(20.0, -30.0), false),
            ],
        };
        let format = Format::lathe(&m, "G32", 'F');
        let mut out = Vec::new();
        write_moves(&mut out, &format, Units::Mm, &path).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "G2 X40. Z-25. I5. K0.\nG3 X50. Z-30. I0. K-5.\n"
        );
        // A start point off the output's grid: K from the start as written (Z0.0016 is written
        // Z0.002; the centre at Z0.0004 is −0.0016 from it, written −0.002, where the unrounded
        // start would give −0.0012, −0.001).
        let path = Toolpath {
            start: Pos::new(10.0, 0.0016),
            motions: vec![arc(Pos::new(15.0, -2.5), Pos::new(12.5, 0.0004), false)],
        };
        let mut out = Vec::new();
        write_moves(&mut out, &format, Units::Mm, &path).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "G3 X30. Z-2.5 I2.5 K-0.002\n"
        );
        // A controller without arcs refuses them.
        let none = Format {
            arc: None,
            ..format
        };
        assert!(write_moves(&mut Vec::new(), &none, Units::Mm, &path).is_err());
    }
}
