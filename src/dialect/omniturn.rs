//! OmniTurn lathe controls: the G33 threading cycle (seed 002).
//!
//! ```text
//! G33 Xn Zn In Kn [An] [C[n]] [P] [O]
//! G72 / G73            diameter / radius mode (X, I and A follow it); G73 at power-on
//! G35 | G35F2 ; G92 X Z     coarse leads up to 1" / 2"      G36 ; G92 X Z     back to .2"
//! ```
//! Every decision on an ambiguity of the seed is a row of `docs/dialects/omniturn-g33.md`.

use std::io::{self, Write};

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::dialect::lexicon::{self, Code as C, Function as F, Lexicon, ToolForm};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::{Machine, OmniTurnParameters};
use crate::post::{self, Format};
use crate::thread::{
    DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, Pass, PassPlan,
    Retract, ReturnPath, Side,
};
use crate::toolpath::Toolpath;
use crate::units::{Pos, Units, MM_PER_INCH};

use super::{all_but, Dialect, Read};

/// What an OmniTurn's codes mean, from seed 002 (`docs/dialects/omniturn-g33.md`,
/// `docs/translation.md`): G0/G1, G90, G94/G95, G72/G73 diameter and radius, G35/G36 (the coarse
/// lead modes, carried by the cycles' jobs) with the G92 that restates the position after them,
/// `T4` (the tool with its own offset), inch only, feed per minute at power-on (the seed's `T4F300`
/// is 300 ipm: its largest feed per revolution is 2"), M codes as ISO 6983-1 assigns them (the
/// seed writes none). G33 is the threading cycle: there is no plain synchronised move. No
/// reference return is documented (`reference: None`): the OmniTurn's posts send the tool home
/// with a rapid to a position given in program coordinates, as a conversion does with the target
/// profile's `[reference] g28` (`docs/dialects/omniturn-g33.md`).
pub static LEXICON: Lexicon = Lexicon {
    codes: &[
        &[
            (C::G(0), F::Rapid),
            (C::G(10), F::Feed),
            (C::G(720), F::Diameter),
            (C::G(730), F::Radius),
            (C::G(350), F::CycleSetting),
            (C::G(360), F::CycleSetting),
        ],
        &[(C::G(900), F::Absolute)],
        lexicon::G94_G95,
        lexicon::ISO_M,
    ],
    tool: ToolForm::Single,
    dwell: None,
    spindle_limit: None,
    reference: None,
    restates_position: true,
    program_number: false,
    sequence_numbers: false,
    delimiters: false,
    power_on_feed: F::FeedPerMinute,
    thread_words: b"",
    thread_settings: &[],
    only_units: Some(Units::Inch),
    pause_spindle: lexicon::PauseSpindle::BuilderDecides,
};

/// The G codes of an OmniTurn control. The seed documents only G33, G35, G36, G72, G73, G90, G92,
/// G94 and G95, so every whole code G0–G99 is accepted except the threading codes of other controls
/// (G32, G34, G76, G78): those are refused with the hint naming the controllers that have them
/// (docs/dialects/omniturn-g33.md, "Vocabulary").
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "omniturn",
    alarm: "OmniTurn: invalid G code",
    g_codes: &all_but(&[GCode::thread(G33, b"XZIKACPO")], &[320, 340, 760, 780]),
    foreign: &[],
    others: super::others_with,
};

const G33: u16 = 330;
const G72: u16 = 720;
const G73: u16 = 730;
const G35: u16 = 350;
const G36: u16 = 360;
const G92: u16 = 920;

/// C written alone: "This defaults to 29°".
pub const DEFAULT_INFEED_ANGLE: f64 = 29.0;
/// "The maximum angle is 30° (based on standard 60° tool geometry) the min is 0°."
pub const MAX_INFEED_ANGLE: f64 = 30.0;
/// The tool the seed assumes ("standard 60° tool geometry"), for chip areas.
pub const TOOL_ANGLE: f64 = 60.0;
/// "The tool will back away from the starting position plus 3 times the amount of I."
pub const RETRACT_TIMES_I: f64 = 3.0;

/// The IPR feed modes: their index into the profile's `max_lead_in` and `resolution_in`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeedMode {
    Normal = 0,
    G35 = 1,
    G35F2 = 2,
}

impl FeedMode {
    pub fn name(self) -> &'static str {
        match self {
            FeedMode::Normal => "normal feed mode (G36)",
            FeedMode::G35 => "G35",
            FeedMode::G35F2 => "G35F2",
        }
    }
}

pub struct OmniTurn {
    conv: Conventions,
    machine: Machine,
    params: OmniTurnParameters,
    /// G72 (diameter) in force; mirrors the modal state for the output format.
    diameter: bool,
    mode: FeedMode,
    /// Where the tool stood when G35 was first used (G36 must find it there again).
    coarse_from: Option<Pos>,
    /// A G35/G36 line waits for its `G92 X Z` companion: the mode line's span and name.
    pending_g92: Option<(Span, &'static str)>,
    /// The last S word (rpm), for the slide-speed check.
    rpm: Option<f64>,
}

/// The built-in OmniTurn data when a profile has no `[omniturn]` table.
pub fn default_parameters() -> OmniTurnParameters {
    Machine::built_in("omniturn")
        .and_then(|m| m.omniturn)
        .expect("the omniturn profile has an [omniturn] table")
}

impl OmniTurn {
    pub fn new(machine: &Machine) -> OmniTurn {
        OmniTurn {
            conv: Conventions {
                uw_incremental: false,
                g90_g91_distance: true,
                diameter_x: machine.diameter_x,
                thread_move: G33,
                lead_letter: b'K',
                lead_along_path: false,
                tpi_letter: 0,
                set_position: G92,
                canned_cycles: &[],
                unmodelled: &[],
                units_codes: crate::gcode::modal::G20_G21,
                positions: crate::gcode::modal::PositionCodes::FANUC,
                syntax: crate::gcode::lexer::Syntax {
                    bare: b"PCO",
                    ..crate::gcode::lexer::Syntax::default()
                },
            },
            machine: machine.clone(),
            params: machine.omniturn.clone().unwrap_or_else(default_parameters),
            diameter: machine.diameter_x,
            mode: FeedMode::Normal,
            coarse_from: None,
            pending_g92: None,
            rpm: None,
        }
    }

    fn resolution_in(&self) -> f64 {
        self.params.resolution_in[self.mode as usize]
    }

    /// The line after G35/G36 "must be a G92XnZn, where XnZn are the current working coordinates".
    fn check_companion(&mut self, line: &Line, modal: &Modal) -> Result<()> {
        let Some((at, name)) = self.pending_g92 else {
            return Ok(());
        };
        let expected = || {
            modal.position.known().map_or(String::new(), |p| {
                format!(
                    " (the tool is at X{} Z{})",
                    post::number(modal.x_from_mm(p.x), 5, false),
                    post::number(modal.units.from_mm(p.z), 5, false)
                )
            })
        };
        let is_g92 = line.has_g(G92) && line.word(b'X').is_some() && line.word(b'Z').is_some();
        if !is_g92 {
            return Err(Diagnostic::error(
                Code::MissingWord,
                line.span(),
                format!(
                    "the block after {name} (line {}) must be G92 X.. Z.. with the current coordinates",
                    at.line
                ),
            )
            .with_hint(format!("write G92 X.. Z..{} on the line after {name}", expected())));
        }
        if let Some(p) = modal.position.known() {
            let target = modal.target(&self.conv, line, p)?;
            let res = modal.resolution();
            for (letter, want, got, tol) in [
                (b'X', p.x, target.x, res.x()),
                (b'Z', p.z, target.z, res.length()),
            ] {
                if !tol.eq(want, got) {
                    let w = line.word(letter).expect("checked above");
                    return Err(Diagnostic::error(
                        Code::Conflict,
                        w.span,
                        format!(
                            "{}{} is not the current coordinate: G92 after {name} must restate where the tool is{}",
                            letter as char,
                            post::number(modal.value(w), 5, false),
                            expected()
                        ),
                    )
                    .with_hint("a different value would shift every later coordinate"));
                }
            }
        }
        self.pending_g92 = None;
        Ok(())
    }

    /// G35 / G35F2 / G36: "must be on a line by itself".
    fn read_mode_line(
        &mut self,
        line: &Line,
        modal: &Modal,
        code: u16,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<()> {
        let g = line
            .words
            .iter()
            .find(|w| w.letter == b'G' && g_code(w.value) == Some(code))
            .expect("the caller found it");
        let name = if code == G36 { "G36" } else { "G35" };
        if let Some(other) = line
            .words
            .iter()
            .find(|w| w.span != g.span && w.letter != b'N' && !(code == G35 && w.letter == b'F'))
        {
            return Err(Diagnostic::error(
                Code::Conflict,
                other.span,
                format!("{name} must be on a line by itself"),
            )
            .with_hint(format!(
                "write {name} alone (G35F2 for leads up to 2\"), then G92 X.. Z.. on the next line"
            )));
        }
        let new_mode = if code == G36 {
            match self.mode {
                FeedMode::Normal => warnings.push(Diagnostic::warning(
                    Code::Suspicious,
                    g.span,
                    "G36 with no coarse feed mode (G35) active",
                )),
                _ => {
                    if let (Some(from), Some(at)) = (self.coarse_from, modal.position.known()) {
                        let res = modal.resolution();
                        if !res.x().eq(from.x, at.x) || !res.length().eq(from.z, at.z) {
                            return Err(Diagnostic::error(
                                Code::Geometry,
                                g.span,
                                format!(
                                    "G36 with the tool at X{} Z{}: it must first return to X{} Z{}, where G35 was used",
                                    post::number(modal.x_from_mm(at.x), 5, false),
                                    post::number(modal.units.from_mm(at.z), 5, false),
                                    post::number(modal.x_from_mm(from.x), 5, false),
                                    post::number(modal.units.from_mm(from.z), 5, false)
                                ),
                            ));
                        }
                    }
                }
            }
            self.coarse_from = None;
            FeedMode::Normal
        } else {
            let mode = match line.word(b'F') {
                None => FeedMode::G35,
                Some(f) if !f.is_bare() && f.value == 2.0 => FeedMode::G35F2,
                Some(f) => {
                    return Err(Diagnostic::error(
                        Code::OutOfRange,
                        f.span,
                        format!(
                        "G35F{}: the coarse modes are G35 (leads up to 1\") and G35F2 (up to 2\")",
                        crate::gcode::lexer::show(f.raw(line.text))
                    ),
                    ))
                }
            };
            if self.coarse_from.is_none() {
                self.coarse_from = modal.position.known();
            }
            mode
        };
        self.mode = new_mode;
        self.pending_g92 = Some((
            g.span,
            if new_mode == FeedMode::G35F2 {
                "G35F2"
            } else {
                name
            },
        ));
        Ok(())
    }

    /// G33 as the seed reads it: the words, the cycle's errors in order, the path from the tool
    /// to X Z, the slide's limits as warnings, then the job.
    fn read_cycle(
        &mut self,
        line: &Line,
        modal: &Modal,
        g33: Span,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        let words = G33Words::read(line, g33)?;
        let step = g33_step(modal, words.i)?;
        let k_in = g33_lead_in(modal, words.k)?;
        self.check_lead_fits(line, modal, words.k, k_in)?;
        let lead = k_in * MM_PER_INCH;
        let taper = g33_taper(line, modal)?;
        let infeed_angle = g33_infeed_angle(line)?;
        let single = line.word(b'O').is_some();
        let pull_out = line.word(b'P').is_some();
        let path = G33Path::read(&self.conv, line, modal, g33, taper, words.x)?;
        let axial_dir = path.axial_dir();
        self.warn_limits(
            modal, line, words.k, k_in, path.start, axial_dir, g33, warnings,
        );
        Ok(G33Cycle {
            line: line.number,
            span: g33,
            units: modal.units,
            path,
            taper,
            lead,
            step,
            single,
            pull_out,
            infeed: g33_infeed(infeed_angle, axial_dir),
        }
        .job())
    }

    /// K within the largest lead of the feed mode in force (G35, G35F2 or neither); the hint
    /// names the mode that would cut it, if any.
    fn check_lead_fits(&self, line: &Line, modal: &Modal, k: &Word, k_in: f64) -> Result<()> {
        let length = modal.resolution().length();
        let max = self.params.max_lead_in[self.mode as usize];
        if length.gt(k_in * MM_PER_INCH, max * MM_PER_INCH) {
            let fits = [FeedMode::G35, FeedMode::G35F2].into_iter().find(|m| {
                !length.gt(
                    k_in * MM_PER_INCH,
                    self.params.max_lead_in[*m as usize] * MM_PER_INCH,
                )
            });
            let hint = match fits {
                Some(FeedMode::G35F2) => format!(
                    "put G35F2 on a line by itself before the cycle, then G92 X.. Z.. with the current position (leads up to {}\")",
                    self.params.max_lead_in[2]
                ),
                Some(_) => format!(
                    "put G35 on a line by itself before the cycle, then G92 X.. Z.. with the current position (leads up to {}\")",
                    self.params.max_lead_in[1]
                ),
                None => format!(
                    "no OmniTurn feed mode cuts a lead above {}\"",
                    self.params.max_lead_in[2]
                ),
            };
            return Err(Diagnostic::error(
                Code::OutOfRange,
                k.span,
                format!(
                    "K{} is above the {}\" largest lead of {}",
                    crate::gcode::lexer::show(k.raw(line.text)),
                    max,
                    self.mode.name()
                ),
            )
            .with_hint(hint));
        }
        Ok(())
    }

    /// The seed's machine limits: 300 ipm of slide, and the run-up the slide needs.
    #[allow(clippy::too_many_arguments)]
    fn warn_limits(
        &self,
        modal: &Modal,
        line: &Line,
        k: &Word,
        k_in: f64,
        start: Pos,
        axial_dir: f64,
        g33: Span,
        warnings: &mut Vec<Diagnostic>,
    ) {
        let rpm = line
            .word(b'S')
            .filter(|s| !s.is_bare())
            .map(|s| s.value)
            .or(self.rpm);
        if let Some(rpm) = rpm {
            let ipm = rpm * k_in;
            if ipm > self.params.max_slide_ipm {
                warnings.push(
                    Diagnostic::warning(
                        Code::MachineLimit,
                        k.span,
                        format!(
                            "S{rpm} × K{k_in} = {ipm:.1} ipm is faster than the slide's {} ipm",
                            self.params.max_slide_ipm
                        ),
                    )
                    .with_hint(format!(
                        "slow the spindle to S{} or less",
                        (self.params.max_slide_ipm / k_in).floor()
                    )),
                );
            }
        }
        // Z0 is the part's face in every seed example; the run-up is the start's distance in front
        // of it, against the cutting direction.
        let runup = modal.units.from_mm(-start.z * axial_dir);
        let runup_in = if modal.units == Units::Inch {
            runup
        } else {
            runup / MM_PER_INCH
        };
        if runup_in < self.params.runup_in {
            warnings.push(
                Diagnostic::warning(
                    Code::MachineLimit,
                    g33,
                    format!(
                        "the cycle starts {}\" in front of Z0 (taken as the part's face): the slide needs about {}\" to reach threading speed",
                        post::number(runup_in, 5, false),
                        self.params.runup_in
                    ),
                )
                .with_hint("start further from the face, or slow the spindle until the thread gauge goes on"),
            );
        }
    }
}

/// The words G33 must have, after the block's own checks: only G33's letters, no other code
/// with it but G72/G73, P and O bare flags, then X, Z, I and K each present with a value.
struct G33Words<'l> {
    /// X: the X of the final pass.
    x: &'l Word,
    /// I: the amount removed after the first pass.
    i: &'l Word,
    /// K: the lead, inches per revolution.
    k: &'l Word,
}

impl<'l> G33Words<'l> {
    /// Reads the block's words in the cycle's order of errors: foreign letters, other codes,
    /// P or O with a value, then X, Z, I, K missing or without a value.
    fn read(line: &'l Line, g33: Span) -> Result<G33Words<'l>> {
        super::only_words(line, b"GNXZIKACPOS", "G33", "X Z I K A C P O")?;
        // The mode codes may share the block: they set how X and I are read.
        super::alone_in_block(line, g33, "G33", &[G72, G73])?;
        for flag in [b'P', b'O'] {
            if let Some(w) = line.word(flag).filter(|w| !w.is_bare()) {
                return Err(Diagnostic::error(
                    Code::Syntax,
                    w.span,
                    format!("{} is a flag on G33 and takes no value", flag as char),
                )
                .with_hint(format!("write {} alone", flag as char)));
            }
        }
        let x = g33_word(line, g33, b'X', "the X of the final pass")?;
        g33_word(line, g33, b'Z', "the Z of the end of the thread")?;
        let i = g33_word(line, g33, b'I', "the amount removed after the first pass")?;
        let k = g33_word(line, g33, b'K', "the lead, inches per revolution")?;
        Ok(G33Words { x, i, k })
    }
}

/// A word G33 needs: an error when it is missing (at G33) or written without a value (at the word).
fn g33_word<'l>(line: &'l Line, g33: Span, letter: u8, what: &str) -> Result<&'l Word> {
    match line.word(letter) {
        Some(w) if w.is_bare() => Err(Diagnostic::error(
            Code::Syntax,
            w.span,
            format!("{} needs a value: {what}", letter as char),
        )),
        Some(w) => Ok(w),
        None => Err(Diagnostic::error(
            Code::MissingWord,
            g33,
            format!("G33 needs {}: {what}", letter as char),
        )),
    }
}

/// An X amount (I, A) in mm: a diameter in G72, a radius in G73 (seed: "defined as the diameter
/// removal in diameter mode").
fn x_amount(modal: &Modal, v: f64) -> f64 {
    let r = if modal.diameter_x { v / 2.0 } else { v };
    modal.units.to_mm(r)
}

/// I, the amount removed after the first pass, in mm: it must be positive.
fn g33_step(modal: &Modal, i: &Word) -> Result<f64> {
    let i_value = modal.value(i);
    if !modal.resolution().x().gt(x_amount(modal, i_value), 0.0) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            i.span,
            format!("I{i_value}: the amount removed after the first pass must be positive"),
        ));
    }
    Ok(x_amount(modal, i_value))
}

/// K, the lead, in inches per revolution: it must be positive.
fn g33_lead_in(modal: &Modal, k: &Word) -> Result<f64> {
    let k_in = modal.units.to_mm(modal.value(k)) / MM_PER_INCH;
    if !modal.resolution().length().gt(k_in * MM_PER_INCH, 0.0) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            k.span,
            format!("K{}: the lead must be positive", modal.value(k)),
        ));
    }
    Ok(k_in)
}

/// A, the X travel over the whole Z travel, in mm (0 when left out): it needs a value.
fn g33_taper(line: &Line, modal: &Modal) -> Result<f64> {
    match line.word(b'A') {
        Some(a) if a.is_bare() => Err(Diagnostic::error(
            Code::Syntax,
            a.span,
            "A needs a value: the X travel over the whole Z travel",
        )),
        Some(a) => Ok(x_amount(modal, modal.value(a))),
        None => Ok(0.0),
    }
}

/// C, the infeed angle: none without C, 29° for C alone, else 0 to 30 degrees.
fn g33_infeed_angle(line: &Line) -> Result<Option<f64>> {
    match line.word(b'C') {
        None => Ok(None),
        Some(c) if c.is_bare() => Ok(Some(DEFAULT_INFEED_ANGLE)),
        Some(c) => {
            let v = c.value;
            if !(0.0..=MAX_INFEED_ANGLE).contains(&v) {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    c.span,
                    format!("C{v}: the infeed angle must be 0 to {MAX_INFEED_ANGLE} degrees"),
                )
                .with_hint("C alone means 29°"));
            }
            Ok(Some(v))
        }
    }
}

/// The infeed: radial without C; along the leading flank with it (deeper passes move in the
/// cutting direction).
fn g33_infeed(angle: Option<f64>, axial_dir: f64) -> Infeed {
    match angle {
        None => Infeed::Radial,
        // Deeper passes move in the cutting direction: the leading flank cuts.
        Some(angle_deg) => Infeed::Flank {
            flank: if axial_dir < 0.0 {
                Flank::Right
            } else {
                Flank::Left
            },
            angle_deg,
        },
    }
}

/// Where G33 cuts: from the tool (the first pass) to X Z (the final pass's end).
struct G33Path {
    start: Pos,
    end: Pos,
    side: Side,
}

impl G33Path {
    /// Decides the path and the side: the start must be known, Z must move, A must move X by
    /// less than Z moves, and the final X must differ from the start's (outside: external).
    fn read(
        conv: &Conventions,
        line: &Line,
        modal: &Modal,
        g33: Span,
        taper: f64,
        x: &Word,
    ) -> Result<G33Path> {
        let units = modal.units;
        let res = modal.resolution();
        let (x_tol, length) = (res.x(), res.length());
        let start = super::start_point(
            modal,
            g33,
            "G33",
            "position the tool at the first pass with X.. Z.. before the cycle",
        )?;
        let end = modal.target(conv, line, start)?;
        let geometry_error = |msg: String| Diagnostic::error(Code::Geometry, g33, msg);
        let travel_z = end.z - start.z;
        if length.is_zero(travel_z) {
            return Err(geometry_error(
                "Z is where the tool stands: the thread has no length".into(),
            ));
        }
        if !length.lt(taper.abs(), travel_z.abs()) {
            return Err(geometry_error(format!(
                "the taper A moves X {} over {} of Z: G33 threads along Z",
                units.show(taper.abs()),
                units.show(travel_z.abs())
            )));
        }
        let side = Side::of_cut(start.x, end.x, x_tol).ok_or_else(|| {
            Diagnostic::error(
                Code::Geometry,
                x.span,
                "the final X equals the start X: no depth to cut, and no way to tell an external from an internal thread",
            )
            .with_hint("start the tool at the first pass, outside the final X (inside it for an internal thread)")
        })?;
        Ok(G33Path { start, end, side })
    }

    /// The cutting direction along Z: +1 or -1.
    fn axial_dir(&self) -> f64 {
        (self.end.z - self.start.z).signum()
    }
}

/// A G33 that passed every check, in mm, ready to lower into the shared model.
struct G33Cycle {
    line: u32,
    span: Span,
    units: Units,
    path: G33Path,
    taper: f64,
    lead: f64,
    /// I: the amount removed after the first pass.
    step: f64,
    /// O: one pass only, at the final X.
    single: bool,
    /// P: pull out at the end of each pass.
    pull_out: bool,
    infeed: Infeed,
}

impl G33Cycle {
    /// The job: the passes shrink from I (one pass with O), the retract 3 × I outside the start,
    /// a box return.
    fn job(self) -> Job {
        let G33Path { start, end, side } = self.path;
        let step = self.step;
        Job {
            line: self.line,
            span: self.span,
            controller: "omniturn",
            units: self.units,
            start,
            geometry: Geometry {
                crest_start: start,
                crest_end: Pos::new(start.x + self.taper, end.z),
                depth: (start.x - end.x).abs(),
                side,
            },
            lead: Lead::constant(self.lead),
            plan: if self.single {
                PassPlan {
                    law: DepthLaw::Explicit { depths: vec![] },
                    finish_allowance: 0.0,
                    finish_passes: 1,
                }
            } else {
                PassPlan {
                    law: DepthLaw::FromStart {
                        step,
                        degression: 2.0,
                    },
                    finish_allowance: 0.0,
                    finish_passes: 0,
                }
            },
            infeed: self.infeed,
            finish_at: FinishPosition::Axis,
            tool_angle_deg: TOOL_ANGLE,
            entry: Entry::Direct,
            exit: Exit::ToRetract {
                run_on: if self.pull_out { 1.0 } else { 0.0 },
            },
            retract: Retract {
                x: start.x + side.outward().x * RETRACT_TIMES_I * step,
                z: start.z,
            },
            return_path: ReturnPath::Box,
        }
    }
}

impl Dialect for OmniTurn {
    /// G33 A: the X travel over the whole Z travel, end minus start, written as X is
    /// (docs/dialects/omniturn-g33.md).
    fn taper_word(&self) -> Option<super::TaperWord> {
        Some(super::TaperWord {
            cycles: "G33 A",
            letter: 'A',
            start_minus_end: false,
            radius: false,
        })
    }
    fn name(&self) -> &'static str {
        "omniturn"
    }

    /// `read` acts on the block after a G35/G36 (the G92 check), on S, and on G72, G73, G21, G35,
    /// G36 and G33; nothing else.
    #[inline]
    fn prefilter(&self, line: &Line) -> bool {
        // The lexer's summary answers for most lines without a look at the words: none of these
        // G codes is G0–G3.
        self.pending_g92.is_some()
            || line.summary.has_letter(b'S')
            || line.summary.has_letter(b'E')
            || (line.summary.other_g()
                && line.words.iter().any(|w| {
                    w.letter == b'G'
                        && matches!(g_code(w.value), Some(G72 | G73 | 210 | G35 | G36 | G33))
                }))
    }

    fn at_rest(&self) -> bool {
        self.pending_g92.is_none()
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
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        if line.words.is_empty() {
            return Ok(Read::Plain);
        }
        self.check_companion(line, modal)?;
        // OmniTurn has no E word: `X.5e-1` is a number with an exponent, which G-code has not.
        super::refuse_exponent(line)?;
        let mut cycle = None;
        for w in line.words.iter().filter(|w| w.letter == b'G') {
            match g_code(w.value) {
                Some(G72) => {
                    modal.diameter_x = true;
                    self.diameter = true;
                }
                Some(G73) => {
                    modal.diameter_x = false;
                    self.diameter = false;
                }
                Some(210) => {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        w.span,
                        "G21: the OmniTurn seed documents inch programming only",
                    )
                    .with_hint("program in inches (G20)"))
                }
                Some(c @ (G35 | G36)) => {
                    self.read_mode_line(line, modal, c, warnings)?;
                    return Ok(Read::Plain);
                }
                Some(G33) => cycle = Some(w.span),
                _ => {}
            }
        }
        if let Some(g33) = cycle {
            let job = self.read_cycle(line, modal, g33, warnings)?;
            if let Some(s) = line.word(b'S').filter(|s| !s.is_bare()) {
                self.rpm = Some(s.value);
            }
            return Ok(Read::Cycle(Box::new(job)));
        }
        if let Some(s) = line.word(b'S') {
            self.rpm = Some(s.value);
        }
        Ok(Read::Plain)
    }

    fn format(&self) -> Format {
        Format {
            diameter_x: self.diameter,
            ..Format::lathe(&self.machine, "G33", 'K')
        }
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        self.native_g33(job)
    }

    /// Positions and leads are written on the grid of the feed mode the lead needs ("Resolution
    /// limits … .00005\" normal, .00025\" G35, .0005\" G35F2").
    fn output_step(&self, lead_mm: f64, units: Units) -> Option<f64> {
        let mode = self
            .mode_for(lead_mm / MM_PER_INCH)
            .unwrap_or(FeedMode::G35F2);
        Some(units.from_mm(self.params.resolution_in[mode as usize] * MM_PER_INCH))
    }

    /// OmniTurn has no plain synchronised move: G33 is always the cycle. Its documented single-pass
    /// option O ("can be used to have greater control over the amount to be removed with each
    /// pass") writes any pass at depth > 0 exactly, from the same start point. The pass at the
    /// start point itself cannot be an O pass (its direction of retraction would be undefined), so
    /// passes 1 and 2 are written as a regular G33 whose X is pass 2's: it cuts exactly those two.
    fn write_cycle(
        &self,
        out: &mut dyn Write,
        job: &Job,
        passes: &[Pass],
        _path: &Toolpath,
    ) -> Option<io::Result<()>> {
        Some(self.write_single_passes(out, job, passes))
    }
}

impl OmniTurn {
    /// The feed mode whose largest lead holds `lead_in` (inch), if one does.
    fn mode_for(&self, lead_in: f64) -> Option<FeedMode> {
        [FeedMode::Normal, FeedMode::G35, FeedMode::G35F2]
            .into_iter()
            .find(|m| lead_in <= self.params.max_lead_in[*m as usize] + 1e-12)
    }

    /// The G33 cycle that expresses `job`, with the coarse feed mode it needs around it (`G35`
    /// or `G35F2` and the `G92` that restates the start point, `G36` and `G92` after: the cycle
    /// ends where it began, where G35 was used). The words follow the reader
    /// ([`OmniTurn::read_cycle`]): the first pass at the start point, then `I·√(n−1)` deeper to
    /// X; the retract 3·I beyond the start; C the flank angle of a leading-flank infeed; P the
    /// 45° pull-out; O a single pass at X.
    fn native_g33(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        let g = &job.geometry;
        if job.units != Units::Inch {
            return Err("OmniTurn programs are written in inches".into());
        }
        if g.side.is_face() {
            return Err("G33 threads along Z, and this is a face thread".into());
        }
        if job.lead.dlead != 0.0 {
            return Err("G33 cuts a constant lead".into());
        }
        if job.lead.phase_deg != 0.0 || job.lead.starts != 1 {
            return Err(
                "G33 cuts one start from the spindle's index (each further start is a G33 of its own, from a start point shifted along Z)".into(),
            );
        }
        if job.entry != Entry::Direct
            || job.return_path != ReturnPath::Box
            || g.crest_start != job.start
            || job.retract.z != job.start.z
        {
            return Err(
                "G33 cuts its first pass from the tool's position and returns there along Z after every pass, and this job does not".into(),
            );
        }
        let pull_out = match job.exit {
            Exit::ToRetract { run_on: 0.0 } => false,
            Exit::ToRetract { run_on: 1.0 } => true,
            _ => {
                return Err(
                    "G33 ends every pass at Z and leaves for its retract point straight out or pulling out at 45° (P), and this job's exit differs".into(),
                )
            }
        };
        let outward = g.side.outward().x;
        let beyond = (job.retract.x - job.start.x) * outward;
        let (i_radius, single) = match &job.plan.law {
            DepthLaw::FromStart { step, degression }
                if *degression == 2.0
                    && job.plan.finish_passes == 0
                    && job.plan.finish_allowance == 0.0 =>
            {
                (*step, false)
            }
            DepthLaw::Explicit { depths }
                if depths.is_empty()
                    && job.plan.finish_passes == 1
                    && job.plan.finish_allowance == 0.0 =>
            {
                (beyond / RETRACT_TIMES_I, true)
            }
            _ => {
                return Err(
                    "G33 cuts its first pass at the start point, then each pass I·√(n−1) deeper to X (or one pass at X with O), and this job's depths follow another law".into(),
                )
            }
        };
        if i_radius <= 0.0 || (beyond - RETRACT_TIMES_I * i_radius).abs() > 1e-9 {
            return Err(
                "G33 retracts to 3·I beyond its start point after every pass, and this job elsewhere".into(),
            );
        }
        let travel = job.geometry.crest_end.z - job.start.z;
        let leading = if travel < 0.0 {
            Flank::Right
        } else {
            Flank::Left
        };
        let c = match job.infeed {
            Infeed::Radial => None,
            Infeed::Flank { flank, angle_deg }
                if flank == leading && (0.0..=MAX_INFEED_ANGLE).contains(&angle_deg) =>
            {
                Some(angle_deg)
            }
            _ => {
                return Err(
                    "G33 infeeds straight in, or along the leading flank at C 0 to 30°, and this job otherwise".into(),
                )
            }
        };
        let lead_in = job.lead.lead / MM_PER_INCH;
        let mode = self.mode_for(lead_in).ok_or_else(|| {
            format!(
                "OmniTurn's largest lead is {} inch (G35F2), and this job's is {} inch",
                self.params.max_lead_in[FeedMode::G35F2 as usize],
                post::number(lead_in, 5, false)
            )
        })?;
        let step = self.params.resolution_in[mode as usize];
        let tz = self.machine.output.trailing_zeros;
        let x_amount = |radius_mm: f64| {
            let v = radius_mm / MM_PER_INCH;
            if self.machine.diameter_x {
                v * 2.0
            } else {
                v
            }
        };
        let grid = |v: f64| post::number_on_grid(v, step, tz);
        let x_end = job.start.x + g.side.infeed().x * g.depth;
        let mut cycle = format!(
            "G33 X{} Z{} I{} K{}",
            grid(x_amount(x_end)),
            grid(g.crest_end.z / MM_PER_INCH),
            grid(x_amount(i_radius)),
            grid(lead_in)
        );
        let taper = g.crest_end.x - g.crest_start.x;
        if taper != 0.0 {
            cycle.push_str(&format!(" A{}", grid(x_amount(taper))));
        }
        if let Some(c) = c {
            cycle.push_str(&format!(" C{}", post::number(c, 3, false)));
        }
        if pull_out {
            cycle.push_str(" P");
        }
        if single {
            cycle.push_str(" O");
        }
        let here = format!(
            "G92 X{} Z{}",
            grid(x_amount(job.start.x)),
            grid(job.start.z / MM_PER_INCH)
        );
        Ok(match mode {
            FeedMode::Normal => vec![cycle],
            coarse => vec![
                if coarse == FeedMode::G35 {
                    "G35"
                } else {
                    "G35F2"
                }
                .to_string(),
                here.clone(),
                cycle,
                "G36".to_string(),
                here,
            ],
        })
    }

    fn write_single_passes(
        &self,
        out: &mut dyn Write,
        job: &Job,
        passes: &[Pass],
    ) -> io::Result<()> {
        let units = job.units;
        let step = self.resolution_in()
            * if units == Units::Inch {
                1.0
            } else {
                MM_PER_INCH
            };
        let tz = self.machine.output.trailing_zeros;
        let x_amount = |radius_mm: f64| {
            let v = units.from_mm(radius_mm);
            if self.diameter {
                v * 2.0
            } else {
                v
            }
        };
        let grid = |v: f64| post::number_on_grid(v, step, tz);
        let i_radius = (job.retract.x - job.start.x).abs() / RETRACT_TIMES_I;
        let mut tail = format!(
            " Z{} I{} K{}",
            grid(units.from_mm(job.geometry.crest_end.z)),
            grid(x_amount(i_radius)),
            grid(units.from_mm(job.lead.lead))
        );
        let taper = job.geometry.crest_end.x - job.geometry.crest_start.x;
        if taper != 0.0 {
            tail.push_str(&format!(" A{}", grid(x_amount(taper))));
        }
        if let Infeed::Flank { angle_deg, .. } = job.infeed {
            tail.push_str(&format!(" C{}", post::number(angle_deg, 3, false)));
        }
        if matches!(job.exit, Exit::ToRetract { run_on } if run_on > 0.0) {
            tail.push_str(" P");
        }
        let comment = |out: &mut dyn Write, text: &str| -> io::Result<()> {
            match self.format().comment(text) {
                Some(c) => writeln!(out, "{c}"),
                None => Ok(()),
            }
        };
        // A single-pass cycle is already one O pass; a full cycle's first two passes are one G33.
        let rest = match passes {
            [only] if only.kind == crate::thread::PassKind::Finish => {
                comment(out, "threadcut: the single pass O as written")?;
                writeln!(out, "G33 X{}{tail} O", grid(x_amount(only.start.x)))?;
                return Ok(());
            }
            [a, b, rest @ ..] => {
                comment(
                    out,
                    &format!(
                        "threadcut: passes {} and {} as one G33 from the start point",
                        a.n, b.n
                    ),
                )?;
                // Reading this G33 back gives pass 1 at the start and pass 2 at min(I, X): X must
                // not lie deeper than the written I, or a sliver third pass appears. So X is pass
                // 2's point on the grid, pulled back toward the start when rounding would put it
                // beyond the written I.
                let start = x_amount(job.start.x);
                let pass2 = x_amount(b.start.x);
                let deeper = (pass2 - start).signum();
                let i_written = (x_amount(i_radius) / step).round() * step;
                let nearest = (pass2 / step).round() * step;
                let x2 = if (nearest - start).abs() <= i_written + 1e-12 {
                    nearest
                } else {
                    let target = (start + deeper * i_written) / step;
                    if deeper < 0.0 {
                        (target - 1e-9).ceil() * step
                    } else {
                        (target + 1e-9).floor() * step
                    }
                };
                writeln!(out, "G33 X{}{tail}", grid(x2))?;
                rest
            }
            _ => passes,
        };
        for p in rest {
            comment(
                out,
                &format!(
                    "threadcut: pass {} as a G33 O single pass from the start point",
                    p.n
                ),
            )?;
            writeln!(out, "G33 X{}{tail} O", grid(x_amount(p.start.x)))?;
        }
        Ok(())
    }
}
