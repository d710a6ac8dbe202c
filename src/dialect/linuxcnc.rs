//! LinuxCNC lathes (rs274ngc interpreter): the G76 threading cycle `G76 P Z I J K [R] [Q] [H] [E] [L] [$]`
//! exactly as `shared/reference/linuxcnc-g76.md` describes it, G33 K as the synchronised move, G7/G8
//! diameter/radius mode, G90/G91 distance mode.
//!
//! Where LinuxCNC's code has a bug the notes list, threadcut follows LinuxCNC's documentation; each
//! deviation is a row of `docs/dialects/linuxcnc-g76.md`.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::dialect::lexicon::{
    self, Code as C, DwellForm, Function as F, Lexicon, LimitForm, ReturnForm, ToolForm,
};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal};
use crate::machine::Machine;
use crate::post::Format;
use crate::thread::{
    DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan, Retract,
    ReturnPath, Side,
};
use crate::units::{Pos, Units};

use super::{g, Dialect, Read};

/// What LinuxCNC's codes mean (its G-code and M-code reference; `docs/translation.md`): G7/G8
/// diameter and radius mode, G33 K threads, G43/G49 and `T… M6` for tools, `G4 P` in seconds, the
/// spindle limit as D on G96, G28 returning to the position stored in parameters 5161–5166, feed
/// per minute (G94) at start-up, O words as program flow.
pub static LEXICON: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        &[(C::G(70), F::Diameter), (C::G(80), F::Radius)],
        lexicon::PLANES,
        lexicon::G20_G21,
        &[
            (C::G(330), F::Thread),
            (C::G(430), F::ToolOffset),
            (C::G(490), F::ToolOffsetOff),
        ],
        lexicon::COMPENSATION,
        lexicon::G90_G91,
        lexicon::G94_G95,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
        lexicon::ORIENT,
        &[(C::M(6), F::ToolChange), (C::M(7), F::MistOn)],
    ],
    tool: ToolForm::ChangeAndOffset,
    dwell: Some(DwellForm::PSeconds),
    spindle_limit: Some(LimitForm::OnSurfaceSpeed(b'D')),
    reference: Some(ReturnForm::IncrementalMode),
    restates_position: false,
    program_number: false,
    sequence_numbers: true,
    delimiters: true,
    power_on_feed: F::FeedPerMinute,
    thread_words: b"K",
    thread_settings: &[],
    only_units: None,
    pause_spindle: lexicon::PauseSpindle::Keeps,
};

/// The G codes of LinuxCNC's rs274ngc interpreter (its G-code reference, 2.9/2.10: docs/dialects/linuxcnc-g76.md,
/// "Vocabulary"); a fractional code (G33.1, G38.2, G64 P, G92.1) is known by its whole number.
/// Any other code is LinuxCNC's "Unknown g code used".
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "linuxcnc",
    alarm: "Unknown g code used",
    g_codes: &[
        g(0),
        g(10),
        g(20),
        g(30),
        g(40),
        g(50),
        g(60),
        g(70),
        g(80),
        g(100),
        g(170),
        g(180),
        g(190),
        g(200),
        g(210),
        g(280),
        g(300),
        GCode::thread(330, b"XYZABCUVWK$"),
        g(380),
        g(400),
        g(410),
        g(420),
        g(430),
        g(490),
        g(520),
        g(530),
        g(540),
        g(550),
        g(560),
        g(570),
        g(580),
        g(590),
        g(610),
        g(640),
        g(700),
        g(710),
        g(720),
        g(730),
        g(740),
        GCode::thread(760, b"XYZABCUVWPIJKRQHEL$"),
        g(800),
        g(810),
        g(820),
        g(830),
        g(840),
        g(850),
        g(860),
        g(870),
        g(880),
        g(890),
        g(900),
        g(910),
        g(920),
        g(930),
        g(940),
        g(950),
        g(960),
        g(970),
        g(980),
        g(990),
    ],
    foreign: &[],
    others: super::others_with,
};

mod turning;
mod words;

const G76: u16 = 760;
const G80: u16 = 800;
const G2: u16 = 20;
const G3: u16 = 30;

pub struct LinuxCnc {
    conv: Conventions,
    machine: Machine,
    spindles: u8,
    /// Which spindles turn (M3/M4 on, M5 off).
    turning: Vec<bool>,
    /// The motion mode in force (×10; `None` after G80 and at the start, as LinuxCNC starts in
    /// G80): a later block with axis words and no motion code continues it (another G76).
    motion: Option<u16>,
    cutter_comp: bool,
    /// Active plane ×10 (G17 170, G18 180, G19 190).
    plane: u16,
    /// A G70/G71/G72 reading its profile, and whether its subroutine is still to be called.
    g7x: Option<turning::Pending>,
    g7x_call: bool,
}

impl LinuxCnc {
    pub fn new(machine: &Machine) -> LinuxCnc {
        let spindles = machine.linuxcnc.as_ref().map_or(1, |l| l.spindles.max(1));
        LinuxCnc {
            conv: Conventions {
                uw_incremental: false,
                g90_g91_distance: true,
                diameter_x: machine.diameter_x,
                thread_move: 330,
                tpi_letter: 0,
                lead_letter: b'K',
                lead_along_path: true,
                // G92 sets coordinate offsets: the tool does not move.
                set_position: 920,
                canned_cycles: &[],
                // rs274ngc's other motions (its G-code reference): rigid tapping, probing,
                // splines and the hole-machining canned cycles (in G18 they work along Y).
                unmodelled: &[
                    (50, "cubic spline (G5)"),
                    (51, "quadratic B-spline (G5.1)"),
                    (52, "NURBS block (G5.2)"),
                    (53, "NURBS block's end (G5.3)"),
                    (331, "rigid tapping move (the spindle reverses at its end and the tool returns to its start)"),
                    (380, "probing move (it ends where the probe trips)"),
                    (730, "drilling cycle with chip breaking"),
                    (740, "left-hand tapping cycle"),
                    (810, "drilling cycle"),
                    (820, "drilling cycle with dwell"),
                    (830, "peck drilling cycle"),
                    (840, "right-hand tapping cycle"),
                    (850, "boring cycle"),
                    (860, "boring cycle"),
                    (870, "back boring cycle"),
                    (880, "boring cycle"),
                    (890, "boring cycle with dwell"),
                ],
                units_codes: crate::gcode::modal::G20_G21,
                positions: crate::gcode::modal::PositionCodes::LINUXCNC,
                // LinuxCNC drops blanks and tabs outside comments before it reads a line
                // (`close_and_downcase`), and refuses a comment inside a comment.
                syntax: crate::gcode::lexer::Syntax {
                    blanks_anywhere: true,
                    nested_comment_error: true,
                    ..crate::gcode::lexer::Syntax::default()
                },
            },
            machine: machine.clone(),
            spindles,
            turning: vec![false; usize::from(spindles)],
            motion: None,
            cutter_comp: false,
            plane: 180,
            g7x: None,
            g7x_call: false,
        }
    }

    /// Modal state this dialect keeps itself: G7/G8, plane, cutter compensation, spindles.
    fn track(&mut self, line: &Line, modal: &mut Modal) {
        let selected = line
            .word(b'$')
            .map(|w| w.value)
            .filter(|v| v.fract() == 0.0 && *v >= 0.0 && *v < f64::from(self.spindles))
            .map(|v| v as usize);
        for w in line.words {
            match (w.letter, g_code(w.value)) {
                (b'G', Some(70)) => modal.diameter_x = true,
                (b'G', Some(80)) => modal.diameter_x = false,
                (b'G', Some(c @ (170 | 180 | 190))) => self.plane = c,
                // G90.1: arc centres I/K are absolute (G91.1, incremental, at power-on).
                (b'G', Some(901)) => modal.arc_centre_absolute = true,
                (b'G', Some(911)) => modal.arc_centre_absolute = false,
                (b'G', Some(400)) => self.cutter_comp = false,
                (b'G', Some(410 | 411 | 420 | 421)) => self.cutter_comp = true,
                (b'M', Some(30 | 40)) => match selected {
                    Some(s) => self.turning[s] = true,
                    None => self.turning[0] = true,
                },
                (b'M', Some(50)) => match selected {
                    Some(s) => self.turning[s] = false,
                    None => self.turning.iter_mut().for_each(|t| *t = false),
                },
                (b'M', Some(20 | 300)) => self.turning.iter_mut().for_each(|t| *t = false),
                _ => {}
            }
        }
    }

    /// A G70/G71/G72 block: its words read, its profile subroutine to be called.
    fn read_g7x(&mut self, line: &Line, modal: &mut Modal, code: u16, at: Span) -> Result<Read> {
        if self.plane != 180 {
            return Err(g76_error(
                at,
                Code::Conflict,
                &format!(
                    "G{}.{} can only be used in XZ plane (G18)",
                    code / 10,
                    code % 10
                ),
            ));
        }
        // The cycle's rapid to its start leaves G0 in force while the profile is read.
        let state = (0, modal.arc_centre_absolute, self.cutter_comp);
        let pending = turning::Pending::read(line, modal, code, at, state)?;
        // The cycle's rapid to its start comes first: the profile reads the position from there.
        modal.position = crate::gcode::Position::at(pending.start());
        self.g7x = Some(pending);
        self.g7x_call = true;
        Ok(Read::Applied(None))
    }

    /// LinuxCNC's arc checks in plane XZ, when the arc's start is known; the line's own G20/G21,
    /// G90/G91 and G7/G8 count, as they do in LinuxCNC (modal codes before motion).
    ///
    /// * R (`arc_data_r`): the arc may not end where it starts, and half the chord may not exceed
    ///   `|R|·(1 + 1e-12)` (LinuxCNC's `TINY`; no allowance for the program's resolution, as rs274
    ///   refuses `R0.5` for a chord of 1.0001).
    /// * I/K (`arc_data_ijk`): the centre is the start plus (I, K) — I a radius also in G7 — or
    ///   (I, K) under G90.1; the radii to the start and to the end may differ by at most LinuxCNC's
    ///   default `CENTER_ARC_RADIUS_TOLERANCE` (2·√2·0.01 mm, 2·√2·0.001 inch), or by more when
    ///   that is at most 0.1 % of the larger radius, and never by 100 tolerances.
    fn check_arc(&self, line: &Line, modal: &Modal) -> Result<()> {
        let mut after = modal.clone();
        let Ok(Some(mv)) = after.apply(&self.conv, line) else {
            return Ok(());
        };
        let Some(from) = mv.from.known() else {
            return Ok(());
        };
        if let Some(r) = line.word(b'R') {
            return check_r_arc(&after, r, from, mv.to);
        }
        let (i, k) = (line.word(b'I'), line.word(b'K'));
        let Some(at) = i.or(k) else {
            return Ok(());
        };
        // The centre as the interpreter computes it for every arc (`Modal::arc_centre`).
        let Some(centre) = mv.centre else {
            return Ok(());
        };
        let units = after.units;
        // In program units, as LinuxCNC computes and prints them.
        let p = |q: Pos| (units.from_mm(q.z), units.from_mm(q.x));
        let ((sz, sx), (cz, cx), (ez, ex)) = (p(from), p(centre), p(mv.to));
        let (r1, r2) = ((cx - sx).hypot(cz - sz), (cx - ex).hypot(cz - ez));
        let abs_err = (r1 - r2).abs();
        let rel_err = abs_err / r1.max(r2);
        let tolerance =
            2.0 * std::f64::consts::SQRT_2 * if units == Units::Inch { 0.001 } else { 0.01 };
        if abs_err > tolerance * 100.0 || (rel_err > 0.001 && abs_err > tolerance) {
            return Err(Diagnostic::error(
                Code::Geometry,
                at.span,
                format!(
                    "Radius to end of arc differs from radius to start: start=(Z{sz:.4},X{sx:.4}) \
                     center=(Z{cz:.4},X{cx:.4}) end=(Z{ez:.4},X{ex:.4}) r1={r1:.4} r2={r2:.4} \
                     abs_err={} rel_err={:.4}%",
                    c_general(abs_err, 4),
                    rel_err * 100.0
                ),
            )
            .with_hint("I and K give the centre from the start point (I a radius, also in G7): the end point must lie on the same circle"));
        }
        Ok(())
    }

    /// G76 as LinuxCNC reads it: the words, the control's alarms in its order, then the job.
    fn read_g76(&mut self, line: &Line, modal: &Modal, g76: Span) -> Result<Job> {
        let words = G76Words::read(line, g76)?;
        self.check_g76_state(line, g76)?;
        let depths = G76Depths::read(&words, modal)?;
        let z = self.g76_end_word(line, g76)?;
        let p = words.p;
        let units = modal.units;
        if !modal.resolution().length().gt(units.to_mm(p.value), 0.0) {
            return Err(g76_error(
                p.span,
                Code::OutOfRange,
                &format!("In G76, P (the pitch) must be positive, not {}", p.value),
            ));
        }
        let degression = g76_degression(line)?;
        let drive = G76Drive::read(modal, z, g76)?;
        let taper = drive.taper(line, modal, words.l)?;
        Ok(G76Cycle {
            line: line.number,
            span: g76,
            units,
            lead: units.to_mm(p.value),
            angle: drive.infeed_angle(line),
            drive,
            depths,
            degression,
            spring: words.spring,
            taper,
            l: words.l,
        }
        .job())
    }

    /// The machine state G76 needs, in LinuxCNC's order: a `$` that names a spindle ("Invalid
    /// D-number in G76 cycle"), that spindle turning, no rotary axis words, and cutter radius
    /// compensation off.
    fn check_g76_state(&self, line: &Line, g76: Span) -> Result<()> {
        if let Some(d) = line.word(b'$') {
            if d.value.fract() != 0.0 || d.value < 0.0 || d.value >= f64::from(self.spindles) {
                return Err(g76_error(
                    d.span,
                    Code::OutOfRange,
                    "Invalid D-number in G76 cycle",
                ));
            }
        }
        let spindle = line.word(b'$').map_or(0, |d| d.value as usize);
        if !self.turning[spindle] {
            return Err(g76_error(
                g76,
                Code::Conflict,
                &format!("Chosen spindle ({spindle}) not turning in G76"),
            )
            .with_hint("start the spindle with M3 or M4 before the cycle"));
        }
        if let Some(w) = line
            .words
            .iter()
            .find(|w| matches!(w.letter, b'A' | b'B' | b'C' | b'U' | b'V' | b'W'))
        {
            return Err(g76_error(
                w.span,
                Code::Unsupported,
                "Cannot move rotary axes with G76",
            ));
        }
        if self.cutter_comp {
            return Err(g76_error(
                g76,
                Code::Conflict,
                "Cannot use G76 threading cycle with cutter radius compensation on",
            )
            .with_hint("cancel compensation with G40 first (LinuxCNC itself runs a plain move instead when the radius is not 0; threadcut always refuses)"));
        }
        Ok(())
    }

    /// The Z word that ends the drive line, after the errors LinuxCNC documents but its code
    /// does not raise (deviations, see the docs file): a plane other than G18, an X or Y word;
    /// then a missing Z ("All axes missing with motion code").
    fn g76_end_word<'l>(&self, line: &'l Line, g76: Span) -> Result<&'l crate::gcode::Word> {
        if self.plane != 180 {
            return Err(g76_error(
                g76,
                Code::Unsupported,
                &format!(
                    "G76 cuts in the ZX plane, and the active plane is G{}",
                    self.plane / 10
                ),
            )
            .with_hint(
                "select G18 before the cycle (LinuxCNC's documentation lists this as an error)",
            ));
        }
        if let Some(w) = line.word(b'X').or(line.word(b'Y')) {
            return Err(g76_error(
                w.span,
                Code::Unsupported,
                &format!("{} is not a word of G76: the drive line starts where the tool is", w.letter as char),
            )
            .with_hint("position X with a G0 before the cycle (LinuxCNC's documentation lists other axis words as an error)"));
        }
        line.word(b'Z').ok_or_else(|| {
            g76_error(g76, Code::MissingWord, "All axes missing with motion code")
                .with_hint("G76 needs Z, the end of the drive line")
        })
    }
}

/// A G76 error at `span`, in LinuxCNC's words.
fn g76_error(span: Span, code: Code, msg: &str) -> Diagnostic {
    Diagnostic::error(code, span, msg)
}

/// The words of a G76 block that LinuxCNC reads before anything else.
struct G76Words<'l> {
    /// H: the spring passes.
    spring: u32,
    /// L: which ends taper (bit 0 the entry, bit 1 the exit).
    l: u64,
    /// P: the pitch.
    p: &'l crate::gcode::Word,
    /// I: the thread's offset from the drive line (its sign gives the side).
    i: &'l crate::gcode::Word,
    /// J: the first cut's depth.
    j: &'l crate::gcode::Word,
    /// K: the thread's full depth.
    k: &'l crate::gcode::Word,
}

impl<'l> G76Words<'l> {
    /// Reads H (refusing H-1) and L, then decides whether P ("P word missing with G76") and I, J
    /// and K ("I J or K words missing with G76") are there.
    fn read(line: &'l Line, g76: Span) -> Result<G76Words<'l>> {
        // `words::read` has read H and L as LinuxCNC does (integers, H ≥ -1, L ≥ 0); threadcut
        // also refuses H-1, which LinuxCNC accepts and which skips the full-depth pass (deviation).
        let spring = match line.word(b'H') {
            Some(h) => match words::integer(h)? {
                -1 => return Err(g76_error(h.span, Code::OutOfRange, "Negative h word used")
                    .with_hint("H is the number of spring passes: 0 or more (LinuxCNC accepts H-1 and then never cuts to K; threadcut refuses it)")),
                n => n as u32,
            },
            None => 0,
        };
        let l = line.word(b'L').map_or(Ok(0), words::integer)? as u64;
        let p = match line.word(b'P') {
            Some(p) if p.value != -1.0 => p,
            _ => {
                return Err(
                    g76_error(g76, Code::MissingWord, "P word missing with G76").with_hint(
                        "G76 is modal, but P, I, J and K are not: write them on every G76 block",
                    ),
                )
            }
        };
        let (Some(i), Some(j), Some(k)) = (line.word(b'I'), line.word(b'J'), line.word(b'K'))
        else {
            return Err(g76_error(
                g76,
                Code::MissingWord,
                "I J or K words missing with G76",
            ));
        };
        Ok(G76Words {
            spring,
            l,
            p,
            i,
            j,
            k,
        })
    }
}

/// I, J and K in mm, radii (halved in G7).
struct G76Depths {
    i: f64,
    j: f64,
    k: f64,
}

impl G76Depths {
    /// Converts I, J and K and raises LinuxCNC's alarms on them, at the program's resolution:
    /// I not 0, J greater than 0, K greater than J.
    fn read(words: &G76Words, modal: &Modal) -> Result<G76Depths> {
        let units = modal.units;
        let half = if modal.diameter_x { 0.5 } else { 1.0 };
        let (i, j, k) = (words.i, words.j, words.k);
        let (iv, jv, kv) = (
            units.to_mm(i.value * half),
            units.to_mm(j.value * half),
            units.to_mm(k.value * half),
        );
        // At the program's resolution (LinuxCNC compares these exactly; a value within one
        // increment of another is the same value to threadcut, docs/dialects/linuxcnc-g76.md).
        let x_tol = modal.resolution().x();
        if x_tol.is_zero(iv) {
            return Err(g76_error(
                i.span,
                Code::OutOfRange,
                "In G76, I must not be 0",
            ));
        }
        if !x_tol.gt(jv, 0.0) {
            return Err(g76_error(
                j.span,
                Code::OutOfRange,
                "In G76, J must be greater than 0",
            ));
        }
        if !x_tol.gt(kv, jv) {
            return Err(g76_error(
                k.span,
                Code::OutOfRange,
                "In G76, K must be greater than J",
            ));
        }
        Ok(G76Depths {
            i: iv,
            j: jv,
            k: kv,
        })
    }
}

/// R, the depth degression: 1.0 when left out, refused below 1.0 (LinuxCNC's documentation
/// lists that as an error; its code uses 1.0).
fn g76_degression(line: &Line) -> Result<f64> {
    match line.word(b'R') {
        None => Ok(1.0),
        Some(r) if r.value >= 1.0 => Ok(r.value),
        Some(r) => Err(g76_error(
            r.span,
            Code::OutOfRange,
            &format!(
                "In G76, R (the depth degression) must be at least 1.0, not {}",
                r.value
            ),
        )
        .with_hint(
            "LinuxCNC's documentation lists R below 1.0 as an error; its code silently uses 1.0",
        )),
    }
}

/// The drive line: from where the tool is to Z.
struct G76Drive {
    start: Pos,
    z_end: f64,
}

impl G76Drive {
    /// Decides the drive line: the tool's position must be known, and Z (absolute or, in G91,
    /// from the tool) must differ from the tool's Z.
    fn read(modal: &Modal, z: &crate::gcode::Word, g76: Span) -> Result<G76Drive> {
        let units = modal.units;
        let a = modal.position.known().ok_or_else(|| {
            super::unknown_start(
                modal,
                g76,
                "G76",
                "starts its drive line where the tool is",
                "every pass is placed from the drive line (its X is the drive line's X, I and the \
                 depth), so without the tool's position there is no pass table: position the tool \
                 with G0 X.. Z.. before the cycle",
            )
        })?;
        let z_end = if modal.absolute {
            units.to_mm(z.value)
        } else {
            a.z + units.to_mm(z.value)
        };
        if modal.resolution().length().eq(z_end, a.z) {
            return Err(g76_error(
                z.span,
                Code::Geometry,
                "the drive line has no length: Z equals the current Z",
            ));
        }
        Ok(G76Drive { start: a, z_end })
    }

    /// Along Z: +1 toward larger Z, -1 toward smaller.
    fn dir(&self) -> f64 {
        (self.z_end - self.start.z).signum()
    }

    /// Q, the compound slide angle, mirrored (q = -q) when Z ends above Z start.
    fn infeed_angle(&self, line: &Line) -> f64 {
        let q_word = line.word(b'Q').map_or(0.0, |q| q.value);
        if self.dir() > 0.0 {
            -q_word
        } else {
            q_word
        }
    }

    /// E, the taper length in mm: 0 below the resolution (or negative); with L tapering an end,
    /// refused when longer than half the drive line (a documented error LinuxCNC's code does not
    /// raise).
    fn taper(&self, line: &Line, modal: &Modal, l: u64) -> Result<f64> {
        let units = modal.units;
        let length = modal.resolution().length();
        let (a, z_end) = (self.start, self.z_end);
        // E below the resolution (or negative) is no taper.
        let taper = line
            .word(b'E')
            .map(|e| units.to_mm(e.value))
            .filter(|&e| length.gt(e, 0.0))
            .unwrap_or(0.0);
        if taper > 0.0 && l & 3 != 0 && length.gt(taper, (z_end - a.z).abs() / 2.0) {
            let e = line.word(b'E').expect("taper > 0");
            return Err(g76_error(
                e.span,
                Code::Geometry,
                &format!(
                    "E{} is longer than half the drive line ({} along Z)",
                    e.value,
                    units.show((z_end - a.z).abs())
                ),
            )
            .with_hint(
                "LinuxCNC's documentation lists this as an error; its code runs the ramps anyway",
            ));
        }
        Ok(taper)
    }
}

/// A G76 that passed every check, in mm, ready to lower into the shared model.
struct G76Cycle {
    line: u32,
    span: Span,
    units: Units,
    lead: f64,
    /// Q after mirroring.
    angle: f64,
    drive: G76Drive,
    depths: G76Depths,
    degression: f64,
    spring: u32,
    taper: f64,
    l: u64,
}

impl G76Cycle {
    /// The job: the side from I's sign, the crest I from the drive line, tapered ends where L
    /// asks for them, and a diagonal return to the drive line's end.
    fn job(&self) -> Job {
        let (a, z_end) = (self.drive.start, self.drive.z_end);
        let (iv, h, taper) = (self.depths.i, self.depths.k, self.taper);
        let dir = self.drive.dir();
        let entry_taper = taper > 0.0 && self.l & 1 != 0;
        let exit_taper = taper > 0.0 && self.l & 2 != 0;
        let side = if iv > 0.0 {
            Side::Internal
        } else {
            Side::External
        };
        let crest_x = a.x + side.infeed().x * iv.abs();
        let target_z = z_end + h * self.angle.to_radians().tan();
        Job {
            line: self.line,
            span: self.span,
            controller: "linuxcnc",
            units: self.units,
            start: a,
            geometry: Geometry {
                crest_start: Pos::new(crest_x, a.z + if entry_taper { dir * taper } else { 0.0 }),
                crest_end: Pos::new(crest_x, target_z),
                depth: h,
                side,
            },
            lead: Lead::constant(self.lead),
            plan: PassPlan {
                law: DepthLaw::Power {
                    first: self.depths.j,
                    degression: self.degression,
                    min_step: 0.0,
                },
                finish_allowance: 0.0,
                finish_passes: self.spring,
            },
            infeed: g76_infeed(self.angle),
            finish_at: FinishPosition::Axis,
            // LinuxCNC does not know the tool: chip areas assume a 60° insert.
            tool_angle_deg: 60.0,
            entry: if entry_taper {
                Entry::Ramp {
                    outward: h,
                    before: taper,
                }
            } else {
                Entry::Direct
            },
            exit: if exit_taper {
                Exit::PullOut {
                    start_before: taper,
                    length: taper,
                    outward: h,
                }
            } else {
                Exit::Straight
            },
            retract: Retract { x: a.x, z: a.z },
            return_path: ReturnPath::Diagonal {
                clearance: iv.abs() + h,
                end: Pos::new(a.x, z_end),
            },
        }
    }
}

/// The infeed from the (mirrored) Q: radial at 0, along the right flank when positive, the left
/// when negative.
fn g76_infeed(q: f64) -> Infeed {
    if q == 0.0 {
        Infeed::Radial
    } else if q > 0.0 {
        Infeed::Flank {
            flank: Flank::Right,
            angle_deg: q,
        }
    } else {
        Infeed::Flank {
            flank: Flank::Left,
            angle_deg: -q,
        }
    }
}

impl Dialect for LinuxCnc {
    fn name(&self) -> &'static str {
        "linuxcnc"
    }

    fn conventions(&self) -> &Conventions {
        &self.conv
    }

    fn vocabulary(&self) -> &'static Vocabulary {
        &VOCABULARY
    }

    fn lexicon(&self) -> &'static Lexicon {
        &LEXICON
    }

    fn read(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        _warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        self.track(line, modal);
        // LinuxCNC's reading rules for every block: each letter once, a G and an M code per
        // modal group, no word that no code of the block uses.
        let block = words::read(line)?;
        let motion = words::motion_to_be(&block, self.motion)?;
        words::check_other_codes(&block, line, motion)?;
        if let Some(m) = block.motion() {
            self.motion = (m != G80).then_some(m);
        }
        if block.ends_program() {
            self.motion = Some(10);
        }
        if matches!(motion, Some(G2 | G3)) && self.plane == 180 {
            self.check_arc(line, modal)?;
        }
        if let Some(code @ (700 | 710 | 711 | 712 | 720 | 721 | 722)) = motion {
            let at = block.motion_span().unwrap_or_else(|| line.span());
            return self.read_g7x(line, modal, code, at);
        }
        if motion != Some(G76) {
            return Ok(Read::Plain);
        }
        let g76 = block.motion_span().unwrap_or_else(|| line.span());
        let job = self.read_g76(line, modal, g76)?;
        Ok(Read::Cycle(Box::new(job)))
    }

    fn program_files(
        &self,
        wanted: &crate::interp::library::Wanted,
    ) -> crate::interp::library::FileNames {
        // `o<name> call` of a subroutine the file does not define reads `name.ngc` from the
        // directories of [RS274NGC]SUBROUTINE_PATH, the name as the interpreter reads it (lower
        // case), the file name's case as it is (o-code.adoc, "Calling Files":
        // docs/dialects/linuxcnc.md, "Programs in other files").
        use crate::interp::library::{FileNames, Wanted};
        match wanted {
            Wanted::Name(name) => FileNames {
                names: vec![format!("{name}.ngc")],
                any_case: false,
            },
            Wanted::Number(_) => FileNames::default(),
        }
    }

    fn macros(&self) -> Option<crate::interp::Syntax> {
        Some(crate::interp::Syntax::O_WORDS)
    }

    fn format(&self) -> Format {
        Format {
            lead_decimals: [6, 7],
            lead_along_path: true,
            ..Format::lathe(&self.machine, "G33", 'K')
        }
    }

    fn profile_call(&mut self) -> Option<f64> {
        if !std::mem::take(&mut self.g7x_call) {
            return None;
        }
        self.g7x.as_ref().map(turning::Pending::q)
    }

    fn profile_block(&mut self, line: &Line, modal: &mut Modal) -> Result<()> {
        match self.g7x.as_mut() {
            Some(p) => p.block(line, modal),
            None => Ok(()),
        }
    }

    fn profile_end(&mut self, modal: &mut Modal, end: Span) -> Result<Read> {
        match self.g7x.take() {
            Some(p) => {
                let (job, last) = p.finish(modal, end)?;
                // The cycle's last move leaves its motion mode in force.
                self.motion = Some(last);
                modal.motion = match last {
                    0 => crate::gcode::MotionMode::Rapid,
                    20 => crate::gcode::MotionMode::ArcCw,
                    30 => crate::gcode::MotionMode::ArcCcw,
                    _ => crate::gcode::MotionMode::Feed,
                };
                Ok(Read::Turning(Some(Box::new(job))))
            }
            None => Ok(Read::Settings),
        }
    }

    fn assume_ready(&mut self) {
        self.turning.iter_mut().for_each(|t| *t = true);
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        native_g76(&self.machine, job)
    }
}

/// The G76 block that expresses `job`, when LinuxCNC's G76 can (the read-back check decides).
/// LinuxCNC's `arc_data_r` (see [`LinuxCnc::check_arc`]); `modal` is the state after the line's
/// modal codes.
fn check_r_arc(modal: &Modal, r: &crate::gcode::Word, from: Pos, to: Pos) -> Result<()> {
    if from == to {
        return Err(Diagnostic::error(
            Code::Geometry,
            r.span,
            "Current point same as end point of arc",
        ));
    }
    let half_chord = (to.x - from.x).hypot(to.z - from.z) / 2.0;
    if half_chord / modal.length_mm(r).abs() > 1.0 + 1e-12 {
        let units = modal.units;
        return Err(Diagnostic::error(
            Code::Geometry,
            r.span,
            "Arc radius too small to reach end point",
        )
        .with_hint(format!(
            "half the chord from the start to the end point is {} {}: R must be at least that",
            crate::post::number(units.from_mm(half_chord), 4, false),
            units.name()
        )));
    }
    Ok(())
}

/// C's `%.{digits}g`: `digits` significant digits, trailing zeros dropped, an exponent below
/// 1e-4 and from 10^digits on.
fn c_general(v: f64, digits: i32) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let exp = |v: f64| format!("{:.*e}", (digits - 1) as usize, v);
    // The exponent after rounding to `digits` significant digits.
    let e: i32 = exp(v).split_once('e').unwrap().1.parse().unwrap();
    if e < -4 || e >= digits {
        let text = exp(v);
        let (mantissa, e) = text.split_once('e').unwrap();
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        let e: i32 = e.parse().unwrap();
        return format!("{mantissa}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs());
    }
    let text = format!("{:.*}", (digits - 1 - e) as usize, v);
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

fn native_g76(machine: &Machine, job: &Job) -> std::result::Result<Vec<String>, String> {
    let g = &job.geometry;
    let ReturnPath::Diagonal { clearance, end } = job.return_path else {
        return Err(
            "LinuxCNC's G76 retracts each pass to its own X and ends at the Z end, and this job returns to its start point".into(),
        );
    };
    if g.taper() != 0.0 || job.lead.starts != 1 || job.lead.dlead != 0.0 {
        return Err("LinuxCNC's G76 cuts straight single-start threads of constant lead".into());
    }
    if job.plan.finish_allowance != 0.0 {
        return Err("LinuxCNC's G76 has no finishing allowance".into());
    }
    let DepthLaw::Power {
        first,
        degression,
        min_step,
    } = job.plan.law
    else {
        return Err("LinuxCNC's G76 cuts the depth law J·n^(1/R) only".into());
    };
    if min_step != 0.0 || degression < 1.0 {
        return Err("LinuxCNC's G76 has no minimum cut and R ≥ 1".into());
    }
    let i = clearance - g.depth;
    let q = match job.infeed {
        Infeed::Radial => 0.0,
        Infeed::Flank { flank, angle_deg } => {
            let along = (end.z - job.start.z).signum();
            // Positive Q moves deeper passes in the cutting direction.
            flank.sign() * along * angle_deg
        }
        Infeed::Alternating { .. } => return Err("LinuxCNC's G76 infeeds on one flank".into()),
    };
    let e = match (job.entry, job.exit) {
        (Entry::Direct, Exit::Straight) => None,
        (Entry::Ramp { before, .. }, Exit::Straight) => Some((before, 1)),
        (Entry::Direct, Exit::PullOut { length, .. }) => Some((length, 2)),
        (Entry::Ramp { before, .. }, Exit::PullOut { length, .. }) if before == length => {
            Some((length, 3))
        }
        _ => return Err("LinuxCNC's G76 ramps in and out over the same length E".into()),
    };
    let u = job.units;
    let num = |mm: f64| crate::post::number(u.from_mm(mm), 6, false);
    let signed_i = match g.side {
        Side::External => -i,
        Side::Internal => i,
        Side::FaceFront | Side::FaceBack => return Err("LinuxCNC's G76 cuts along Z only".into()),
    };
    let mut block = format!(
        "G76 P{} Z{} I{} J{} K{}",
        num(job.lead.lead),
        num(end.z),
        num(signed_i),
        num(first),
        num(g.depth)
    );
    if degression != 1.0 {
        block.push_str(&format!(" R{}", crate::post::number(degression, 6, false)));
    }
    if q != 0.0 {
        block.push_str(&format!(" Q{}", crate::post::number(q, 6, false)));
    }
    if job.plan.finish_passes > 0 {
        block.push_str(&format!(" H{}", job.plan.finish_passes));
    }
    if let Some((len, l)) = e {
        block.push_str(&format!(" E{} L{l}", num(len)));
    }
    let _ = machine;
    // The block is written in radius mode and absolute distance: wrap it when the program differs.
    Ok(vec![block])
}

#[cfg(test)]
mod tests {
    use super::c_general;

    #[test]
    fn c_general_is_printf_g() {
        // printf("%.4g") of the same values.
        assert_eq!(c_general(0.02978, 4), "0.02978");
        assert_eq!(c_general(0.21, 4), "0.21");
        assert_eq!(c_general(1.236_067_977, 4), "1.236");
        assert_eq!(c_general(0.002_879_3, 4), "0.002879");
        assert_eq!(c_general(12.5, 4), "12.5");
        assert_eq!(c_general(1234.5, 4), "1234");
        assert_eq!(c_general(12345.0, 4), "1.234e+04");
        assert_eq!(c_general(0.000_012_34, 4), "1.234e-05");
        assert_eq!(c_general(9.99996, 4), "10");
        assert_eq!(c_general(0.0, 4), "0");
    }
}
