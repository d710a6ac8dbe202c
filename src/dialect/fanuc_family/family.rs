//! The family's reader as one value: a member's words ([`Flavour`]), the cycle parameters the
//! first G76 block rewrites ([`ThreadParameters`]), the G-code system, the modal state of G92 and of
//! a run of thread moves; and what every cycle of the family reads alike (the lead, the end point,
//! the pull-out).

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::modal::Vocabulary;
use crate::gcode::{Conventions, Line, Modal, Word, WordSummary};
use crate::machine::{FanucParameters, GCodeSystem, Machine};
use crate::thread::{tan_deg, Exit, Side};
use crate::units::{Pos, Tolerance, Units};

use super::codes::{g_name, GCodes};
use super::contour::TurningState;
use crate::dialect::one_block;

/// Parameters of the threading cycles. The first G76 block rewrites them, as on the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadParameters {
    /// The pull-out's length in leads (Fanuc 5130 ÷ 10, Haas Setting 95); 0: none.
    pub chamfer_leads: f64,
    /// Its angle from the Z axis, degrees (Fanuc 5131, 0 read as 45; Haas Setting 96).
    pub chamfer_angle_deg: f64,
    /// 5140: Δdmin (mm, radius).
    pub min_cut_mm: f64,
    /// 5141: d (mm, radius).
    pub allowance_mm: f64,
    /// 5142: m.
    pub finish_passes: u32,
    /// 5143: a (degrees); the one-block G76's tool angle when the block has no A.
    pub tool_angle: u32,
}

impl ThreadParameters {
    /// Fanuc's parameters 5130, 5131, 5140–5143 (GSK numbers them the same).
    pub fn fanuc(
        p5130: u8,
        p5131: u8,
        p5140: f64,
        p5141: f64,
        p5142: u8,
        p5143: u8,
    ) -> ThreadParameters {
        ThreadParameters {
            chamfer_leads: f64::from(p5130) * 0.1,
            chamfer_angle_deg: if p5131 == 0 { 45.0 } else { f64::from(p5131) },
            min_cut_mm: p5140,
            allowance_mm: p5141,
            finish_passes: u32::from(p5142),
            tool_angle: u32::from(p5143),
        }
    }

    /// A Fanuc profile's `[fanuc]` table.
    pub fn of_fanuc(p: &FanucParameters) -> ThreadParameters {
        ThreadParameters::fanuc(p.p5130, p.p5131, p.p5140, p.p5141, p.p5142, p.p5143)
    }
}

/// The multiple threading cycle's form.
#[derive(Clone, Copy, Debug)]
pub enum G76Form {
    /// Fanuc 0i/30i standard format, GSK: `G76 P(m)(r)(a) Q(Δdmin) R(d)` then `G76 X Z R P Q F`.
    TwoBlock,
    /// FS15 format, Haas: `G76 X Z I K D F A P Q` in these words.
    OneBlock(one_block::G76Words),
}

/// What a member of the family adds to the common words, and how its manuals name things.
#[derive(Clone, Copy, Debug)]
pub struct Flavour {
    /// The controller's name on jobs.
    pub controller: &'static str,
    /// GSK's G92 words: J/K (tail-out, short and long axis) and L (starts).
    pub gsk_g92_words: bool,
    /// The single-pass cycle's taper word: `R` (Fanuc standard format), `I` (FS15 format, Haas).
    pub taper_letter: u8,
    /// `Q` on the thread move and the single-pass cycle shifts the thread's start angle.
    pub start_angle: bool,
    /// Haas's `F(E)`: E is the lead as F is; elsewhere E is refused.
    pub e_is_lead: bool,
    /// GSK's first G71/G72/G73 block takes F, S and T beside its own words ("G71 U(Δd) R(e) F S
    /// T", GSK 980TDi/988T manuals); Fanuc's takes them on the second block only.
    pub turning_fst_first: bool,
    pub g76: G76Form,
    /// What messages call the setting of the pull-out, e.g. "the chamfer (parameter 5130)".
    pub chamfer_name: &'static str,
    /// … and of the finishing allowance, e.g. "the finishing allowance d".
    pub allowance_name: &'static str,
    /// The controller's G codes in a G-code system (the modal reader's alarm for any other code,
    /// and the alarm on a block of another control's form).
    pub vocabulary: fn(GCodeSystem) -> &'static Vocabulary,
}

impl Flavour {
    /// Fanuc's standard program format (and GSK's G76/G92), with the member's G codes.
    pub const fn fanuc(
        controller: &'static str,
        vocabulary: fn(GCodeSystem) -> &'static Vocabulary,
    ) -> Flavour {
        Flavour {
            controller,
            gsk_g92_words: false,
            taper_letter: b'R',
            start_angle: true,
            e_is_lead: false,
            turning_fst_first: false,
            g76: G76Form::TwoBlock,
            chamfer_name: "the chamfer (parameter 5130)",
            allowance_name: "the finishing allowance d",
            vocabulary,
        }
    }
}

/// The modal state of G92: the values a following block without a G code repeats.
#[derive(Clone, Copy, Debug)]
pub(super) struct G92Modal {
    pub(super) end_z: f64,
    pub(super) taper: f64,
    /// The start angle of the last pass (not repeated: Q is not modal), and its line.
    pub(super) phase_deg: f64,
    pub(super) phase_line: u32,
}

/// The shared reader. A dialect offers it every line first.
pub struct FanucFamily {
    pub flavour: Flavour,
    pub params: ThreadParameters,
    pub codes: GCodes,
    /// The controller's G codes in its G-code system (the flavour's, for `codes.system`).
    pub vocabulary: &'static Vocabulary,
    /// Haas's M23/M24: the pull-out of G76/G92 is cut (M23, the default) or not (M24).
    pub chamfer_on: bool,
    /// Least input increment in mm and in inch (for P(k), Q(Δd), Q(Δdmin)).
    pub(super) increment: [f64; 2],
    pub(super) g92: Option<G92Modal>,
    /// The start angle of the synchronised run in progress, from the `Q` of its first plain
    /// thread move, while it is not 0: the moves that continue the run carry it.
    pub(super) run_phase: Option<f64>,
    /// The letters whose words make any line the family's business (a [`WordSummary`] mask).
    pub(super) letters: u32,
    /// The turning cycles' state: their first blocks' values, a modal box cycle, a contour being
    /// read, the contours read.
    pub(super) turning: TurningState,
    /// The one-block G71/G72/G73's settings (Haas's): `None` where they are not read (FS15's).
    pub one_block_turning: Option<OneBlockTurning>,
}

/// What the one-block stock removal (`G71/G72 P Q U W D F [I K] [R1]`) takes from the machine:
/// the retract after each cut (Haas's Setting 73, mm) and whether the profile's value is assumed.
#[derive(Clone, Copy, Debug)]
pub struct OneBlockTurning {
    pub retract_mm: f64,
    pub assumed: bool,
}

impl FanucFamily {
    /// The taper word of the member's cycles: `R` in Fanuc's standard format (the two-block G76 and
    /// G92), `I` in the FS15 format and on Haas (the one-block G76 and G92), a radius, X at the
    /// cycle's start minus X at its end either way.
    pub fn taper_word(&self) -> crate::dialect::TaperWord {
        let r = self.flavour.taper_letter == b'R';
        let cycles = match (self.codes.system, r) {
            (GCodeSystem::A, true) => "G76 (second block) / G92 R(i)",
            (GCodeSystem::A, false) => "G76 / G92 I(i)",
            (GCodeSystem::B, true) => "G76 (second block) / G78 R(i)",
            (GCodeSystem::B, false) => "G76 / G78 I(i)",
            (GCodeSystem::C, true) => "G78 (second block) / G21 R(i)",
            (GCodeSystem::C, false) => "G78 / G21 I(i)",
        };
        crate::dialect::TaperWord {
            cycles,
            letter: self.flavour.taper_letter as char,
            start_minus_end: true,
            radius: true,
        }
    }

    pub fn new(
        flavour: Flavour,
        params: ThreadParameters,
        codes: GCodes,
        machine: &Machine,
    ) -> FanucFamily {
        FanucFamily {
            flavour,
            params,
            codes,
            vocabulary: (flavour.vocabulary)(codes.system),
            chamfer_on: true,
            increment: [
                machine.resolution(Units::Mm),
                machine.resolution(Units::Inch),
            ],
            g92: None,
            run_phase: None,
            turning: TurningState::default(),
            one_block_turning: None,
            // E: a lead or an exponent to refuse; Q: a start angle.
            letters: WordSummary::letter_mask(if flavour.start_angle { b"EQ" } else { b"E" }),
        }
    }

    /// Whether the family reads even a line of plain words: while a single-pass cycle is modal (a
    /// block of axis words repeats it) or a run of thread moves begun with a start angle goes on.
    #[inline(always)]
    pub fn in_progress(&self) -> bool {
        self.g92.is_some() | self.run_phase.is_some() | self.turning_in_progress()
    }

    /// Whether a member's `read` may act on `line`: the family's blocks ([`wants`](Self::wants)),
    /// a block with an E word (a lead where the member reads one, refused as an exponent
    /// elsewhere), and the member's own blocks (`own_block`), which have a G code other than
    /// G0–G3 or one of the member's `own_letters` (a [`WordSummary`] mask). Most lines have no G
    /// code but G0–G3 and none of these letters: one test of the summary answers for them
    /// (docs/performance.md, "Reader after issue 13").
    #[inline(always)]
    pub fn prefilter(
        &self,
        line: &Line,
        own_letters: u32,
        own_block: impl FnOnce(&Line) -> bool,
    ) -> bool {
        if !line.summary.other_g_or_any(self.letters | own_letters) {
            return self.in_progress();
        }
        self.prefilter_words(line, own_block)
    }

    /// [`prefilter`](Self::prefilter) for the lines the summary's one test does not answer: kept
    /// out of line, so that the test itself is inlined into the run loop.
    #[inline(never)]
    pub(super) fn prefilter_words(
        &self,
        line: &Line,
        own_block: impl FnOnce(&Line) -> bool,
    ) -> bool {
        self.wants(line) || line.summary.has_letter(b'E') || own_block(line)
    }

    /// Whether [`read`](Self::read) may act on `line`: a G76 or G92 block, any block while a G92
    /// is modal (a block of axis words repeats it; a motion code cancels it), a block with a `Q`
    /// where Q is a start angle (a thread move's Q), and any block while a run of thread moves
    /// begun with a start angle goes on.
    #[inline]
    pub fn wants(&self, line: &Line) -> bool {
        self.g92.is_some()
            || self.run_phase.is_some()
            || (self.flavour.start_angle && line.summary.has_letter(b'Q'))
            || self.turning_in_progress()
            || self.codes.has_cycle(line)
    }

    /// The pull-out of a pass for lead `lead` (mm), as the parameters (and M23/M24) give it.
    pub(super) fn chamfer(&self, lead: f64, tol: Tolerance) -> Exit {
        let p = &self.params;
        let length = p.chamfer_leads * lead;
        if !self.chamfer_on || !tol.gt(length, 0.0) {
            return Exit::Straight;
        }
        Exit::PullOut {
            start_before: length,
            length,
            outward: length * tan_deg(p.chamfer_angle_deg),
        }
    }

    /// The parameters as the one-block G76 takes them.
    pub fn one_block_setup(&self) -> one_block::Setup {
        let p = &self.params;
        one_block::Setup {
            controller: self.flavour.controller,
            allowance: p.allowance_mm,
            allowance_name: self.flavour.allowance_name,
            min_cut: p.min_cut_mm,
            finish_passes: p.finish_passes,
            tool_angle: f64::from(p.tool_angle),
            pull_out: self.chamfer_on.then_some(one_block::PullOut {
                leads: p.chamfer_leads,
                angle_deg: p.chamfer_angle_deg,
            }),
            pull_out_name: self.flavour.chamfer_name,
        }
    }

    /// Whether `line` is a thread move (the dialect's thread-move code on it, or a block of axis
    /// words under a modal thread move), where an E word may be a lead.
    pub fn threads(&self, conv: &Conventions, line: &Line, modal: &Modal) -> bool {
        line.has_g(conv.thread_move)
            || (modal.motion == crate::gcode::MotionMode::Thread
                && !line.words.iter().any(|w| w.letter == b'G'))
    }

    pub(super) fn multiple_name(&self) -> String {
        g_name(self.codes.multiple)
    }

    /// A count of least input increments, written without a decimal point, in mm.
    pub(super) fn increments(
        &self,
        modal: &Modal,
        w: &Word,
        name: &str,
        what: &str,
    ) -> Result<f64> {
        // A computed value (`Q#1`) is the count itself; it must be a whole number.
        if (w.has_dot && !w.is_computed()) || w.value.fract() != 0.0 {
            return Err(Diagnostic::error(
                Code::Syntax,
                w.span,
                format!("{name} is written without a decimal point, in least input increments"),
            )
            .with_hint(if modal.units == Units::Inch {
                format!(
                    "{what}: write 0.05 inch as {} on this machine",
                    (0.05 / self.increment[1]).round()
                )
            } else {
                format!(
                    "{what}: write 1.2 mm as {} on this machine",
                    (1.2 / self.increment[0]).round()
                )
            }));
        }
        if w.value < 0.0 {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                w.span,
                format!("{name}={} must not be negative", w.value),
            ));
        }
        let inc = self.increment[(modal.units == Units::Inch) as usize];
        Ok(modal.units.to_mm(w.value * inc))
    }

    /// The cycle's lead: F (or a TPI word), modal from an earlier thread block; Haas's E as F.
    pub(super) fn lead(
        &self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        cycle: &str,
    ) -> Result<f64> {
        if let Some(e) = line.word(b'E') {
            if !self.flavour.e_is_lead {
                return Err(Diagnostic::error(
                    Code::Unsupported,
                    e.span,
                    format!(
                        "E on {cycle} means threads per inch or a precise lead depending on the series"
                    ),
                )
                .with_hint("write the lead with F"));
            }
            if let Some(f) = line.word(b'F') {
                let later = if e.span.start > f.span.start { e } else { f };
                return Err(Diagnostic::error(
                    Code::Conflict,
                    later.span,
                    format!("F and E in one {cycle} block: the lead is given by either F or E"),
                ));
            }
            let lead = one_block::positive(modal, e, "the lead")?;
            modal.lead = Some(lead);
            return Ok(lead);
        }
        modal.read_lead(conv, line.words)?;
        if let Some(f) = line.word(b'F') {
            modal.f_word = Some(modal.value(f));
        }
        modal.lead.ok_or_else(|| {
            Diagnostic::error(
                Code::MissingWord,
                span,
                format!("{cycle} has no lead: F is missing"),
            )
            .with_hint("F is modal: write it on this block or on an earlier thread block")
        })
    }

    pub(super) fn endpoints(
        &self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        cycle: &str,
    ) -> Result<(Pos, Pos)> {
        if line.word(b'X').or(line.word(b'U')).is_none()
            || line.word(b'Z').or(line.word(b'W')).is_none()
        {
            return Err(Diagnostic::error(
                Code::MissingWord,
                span,
                format!("{cycle} needs the thread end point: X (or U) and Z (or W)"),
            ));
        }
        let a = thread_start(modal, span, cycle)?;
        Ok((a, modal.target(conv, line, a)?))
    }

    pub(super) fn check_exit(
        &self,
        exit: &Exit,
        travel_z: f64,
        units: Units,
        tol: Tolerance,
        span: Span,
    ) -> Result<()> {
        if let Exit::PullOut { length, .. } = *exit {
            if !tol.lt(length, travel_z.abs()) {
                return Err(geometry(
                    span,
                    format!(
                        "{} {} is not shorter than the thread ({} along Z)",
                        self.flavour.chamfer_name,
                        units.from_mm(length),
                        units.show(travel_z.abs())
                    ),
                )
                .with_hint(format!("lower {}", self.flavour.chamfer_name)));
            }
        }
        Ok(())
    }
}

/// Where a threading cycle (G76, G92) starts: its pass table does not depend on it
/// ([`crate::dialect::start_point_unstated`]).
pub(super) fn thread_start(modal: &mut Modal, span: Span, cycle: &str) -> Result<Pos> {
    crate::dialect::start_point_unstated(
        modal,
        span,
        cycle,
        "position the tool with G00 X.. Z.. before the cycle",
    )
}

pub(super) fn start_point(modal: &Modal, span: Span, cycle: &str) -> Result<Pos> {
    crate::dialect::start_point(
        modal,
        span,
        cycle,
        "position the tool with G00 X.. Z.. before the cycle",
    )
}

/// External when the start point is above `reference` (cut toward −X), internal when below; the
/// same X at the program's resolution cannot tell.
pub(super) fn side_of(a: Pos, reference: Pos, x_tol: Tolerance, span: Span) -> Result<Side> {
    match x_tol.sign(a.x - reference.x) {
        1 => Ok(Side::External),
        -1 => Ok(Side::Internal),
        _ => Err(geometry(
            span,
            "the start point's X equals the thread's X: cannot tell an external from an internal thread",
        )),
    }
}

pub(super) fn geometry(span: Span, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error(Code::Geometry, span, msg)
}

pub(super) fn alarm_missing(span: Span, name: &str, word: &str, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("{name} alarm (PS0062): {word} is missing; it gives {what}"),
    )
    .with_hint(format!("{word} has no default on the second {name} block"))
}

pub(super) fn pull_out(j: f64, k: f64, length: Tolerance) -> Exit {
    if length.gt(j, 0.0) && length.gt(k, 0.0) {
        Exit::PullOut {
            start_before: k,
            length: k,
            outward: j,
        }
    } else {
        Exit::Straight
    }
}
