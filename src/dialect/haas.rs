//! Haas lathes (the Haas control; Fanuc-style G-code system A): the one-block multiple-pass cycle
//! `G76 X(U) Z(W) I K D F(E) A P Q` (the FS15 format's cycle, `super::one_block`), the modal
//! single-pass cycle `G92 X(U) Z(W) I F(E) Q`, the thread move `G32 … F Q`, and the settings that
//! govern them: 86 (thread finish allowance), 95 and 96 (thread chamfer size and angle, switched by
//! M23/M24), 99 (thread minimum cut). Sources (Haas's G76, G32 and settings pages) and every
//! inference: `docs/dialects/haas.md`.

use crate::diag::{Code, Diagnostic, Result};
use crate::dialect::lexicon::{self, Code as C, DwellForm, Function as F, Known, Lexicon, Setting};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, MotionMode, PositionCodes, WordSummary};
use crate::machine::{GCodeSystem, HaasSettings, Machine};
use crate::post::{self, Format};
use crate::thread::Job;
use crate::units::MM_PER_INCH;

use super::fanuc_family::{
    self, FanucFamily, Flavour, G76Form, GCodes, OneBlockTurning, ThreadParameters,
};
use super::one_block::{self, G76Words};
use super::{Dialect, Read};

/// M23: "chamfer out of thread" on (the default); M24: off.
const M23: u16 = 230;
const M24: u16 = 240;

/// Haas's G76 words: `F(E)` (E is the lead as F is), A and Q "Do not use a decimal point", and M
/// for the M23/M24 written on the cycle's own block. The manual gives no alarm numbers for K or D.
pub const G76_WORDS: G76Words = G76Words {
    letters: b"GNXZUWIKDFEAPQM",
    format: "X(U) Z(W) I(taper) K(height) D(first depth) F|E(lead) A(tool angle 0-120) P(infeed 1-4) Q(start angle), M23/M24",
    e_is_lead: true,
    no_point_a: true,
    alarm: None,
};

/// Haas on Fanuc's family reader.
pub const FLAVOUR: Flavour = Flavour {
    controller: "haas",
    gsk_g92_words: false,
    taper_letter: b'I',
    start_angle: true,
    e_is_lead: true,
    turning_fst_first: false,
    g76: G76Form::OneBlock(G76_WORDS),
    chamfer_name: "the thread chamfer (Setting 95)",
    allowance_name: "the thread finish allowance (Setting 86)",
    vocabulary,
};

/// Haas's lathe G codes for where the tool is: system A's (`fanuc_family::GCodes`), except that
/// `G28` without axis words returns every axis ("returns all axes … simultaneously to the machine
/// zero position when no axis is specified"), the work offsets are G54–G59 and G110–G129, and
/// `G154 P1`–`P99` selects one of 99 more (each P another offset: taken as a change every time).
pub const POSITIONS: PositionCodes = PositionCodes {
    all_without_axes: true,
    work_systems: &WORK_SYSTEMS,
    offset_changes: &[100, 520, 1540],
    ..GCodes::of(GCodeSystem::A).positions()
};

/// G54–G59 and G110–G129 (×10).
const WORK_SYSTEMS: [u16; 26] = {
    let mut t = [0u16; 26];
    let mut i = 0;
    while i < 6 {
        t[i] = 540 + 10 * i as u16;
        i += 1;
    }
    while i < 26 {
        t[i] = 1100 + 10 * (i as u16 - 6);
        i += 1;
    }
    t
};

/// Haas's lathe G codes, as ranges of whole numbers (Haas's lathe G-code list:
/// `docs/dialects/haas.md`, "Vocabulary"). Generous where the public list may be partial: every
/// code G0–G99 but the threading codes of other controls that Haas does not have (G33, G34, G78),
/// and Haas's own G100–G391 (mirror image, output, look-ahead, servo bar, cylindrical mapping, work offsets
/// G110–G129 and G154, G112/G113, G170–G172 diameter/radius override, G184–G199 tapping and
/// spindle synchronisation, G200, G211/G212, G234, radial canned cycles G241–G249, scaling and
/// dynamic work offsets G250–G255, G266, G268/G269, G390/G391).
const RANGES: &[(u16, u16)] = &[
    (0, 32),
    (35, 77),
    (79, 105),
    (107, 107),
    (110, 129),
    (154, 154),
    (156, 156),
    (165, 165),
    (167, 167),
    (170, 172),
    (184, 184),
    (186, 187),
    (195, 196),
    (198, 200),
    (211, 212),
    (234, 234),
    (241, 251),
    (254, 255),
    (266, 266),
    (268, 269),
    (390, 391),
];

/// What a Haas lathe's codes mean: Fanuc's system A (`docs/dialects/haas.md`), with `G4 P` in
/// seconds (or milliseconds without a decimal point), a bare `G28` returning every axis, `M23`/`M24`
/// (the thread chamfer, carried by the cycles' jobs) and the thread move's lead as F or E.
pub static LEXICON: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::DWELL,
        lexicon::PLANES,
        lexicon::G20_G21,
        &[
            (C::G(320), F::Thread),
            (C::G(500), F::SpindleLimit),
            (C::G(980), F::FeedPerMinute),
            (C::G(990), F::FeedPerRevolution),
            (C::M(23), F::CycleSetting),
            (C::M(24), F::CycleSetting),
        ],
        lexicon::COMPENSATION,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
        lexicon::ORIENT,
    ],
    dwell: Some(DwellForm::PSecondsOrMilliseconds),
    thread_words: b"FEQ",
    pause_spindle: lexicon::PauseSpindle::Stops,
    ..fanuc_family::FANUC_LEXICON
};

/// Haas's G codes; the threading codes with their words: G32 `X Z U W F Q`, the one-block G76
/// [`G76_WORDS`], G92 `X Z U W I F E Q`.
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "haas",
    alarm: "Haas alarm (invalid G code)",
    g_codes: &super::ranges::<{ super::count(RANGES) }>(
        RANGES,
        &[
            GCode::thread(320, b"XZUWFQ"),
            GCode::thread(760, b"XZUWIKDFEAPQM"),
            GCode::thread(920, b"XZUWIFEQ"),
        ],
    ),
    foreign: &[],
    others: super::others_with,
};

/// Haas has one G-code system.
fn vocabulary(_: GCodeSystem) -> &'static Vocabulary {
    &VOCABULARY
}

pub struct Haas {
    conv: Conventions,
    machine: Machine,
    family: FanucFamily,
}

/// The built-in settings when a profile has no `[haas]` table.
pub fn default_settings() -> HaasSettings {
    Machine::built_in("haas")
        .and_then(|m| m.haas)
        .expect("the haas profile has a [haas] table")
}

/// The settings as the family reader's parameters. G76 finishes with one pass at K that removes
/// Setting 86, and with none when Setting 86 is 0 (the last constant-amount pass lands on K); A
/// absent is A0 ("the tool nose angle … 0 to 120").
pub fn parameters(s: &HaasSettings) -> ThreadParameters {
    ThreadParameters {
        chamfer_leads: s.chamfer_leads,
        chamfer_angle_deg: s.chamfer_angle_deg,
        min_cut_mm: s.min_cut_in * MM_PER_INCH,
        allowance_mm: s.finish_allowance_in * MM_PER_INCH,
        finish_passes: u32::from(s.finish_allowance_in > 0.0),
        tool_angle: 0,
    }
}

/// The settings Haas's threading cycles read, with the profile's values: 95 and 96 (the chamfer
/// of G76 and G92, with M23), 86 and 99 (G76's finishing pass and smallest cut). Where the
/// profile's values are threadcut's (`thread_settings_assumed`), 95 and 96 are Haas's factory
/// defaults (1.000 and 45°, the default table docs/dialects/haas.md cites) and 86 and 99 assumed.
fn thread_settings(s: &HaasSettings) -> [(u16, Setting); 4] {
    let (chamfer, pass) = if s.thread_settings_assumed {
        (Known::FactoryDefault, Known::Assumed)
    } else {
        (Known::Stated, Known::Stated)
    };
    let inch = |v: f64| format!("{} in", post::number(v, 4, false).trim_end_matches('.'));
    [
        (
            86,
            Setting {
                name: "Setting 86",
                what: "thread finish allowance",
                value: inch(s.finish_allowance_in),
                known: pass,
            },
        ),
        (
            95,
            Setting {
                name: "Setting 95",
                what: "thread chamfer size",
                value: {
                    let n = post::number(s.chamfer_leads, 3, false);
                    let n = n.trim_end_matches('.');
                    format!("{n} {}", if n == "1" { "lead" } else { "leads" })
                },
                known: chamfer,
            },
        ),
        (
            96,
            Setting {
                name: "Setting 96",
                what: "thread chamfer angle",
                value: format!(
                    "{} deg",
                    post::number(s.chamfer_angle_deg, 3, false).trim_end_matches('.')
                ),
                known: chamfer,
            },
        ),
        (
            99,
            Setting {
                name: "Setting 99",
                what: "thread minimum cut",
                value: inch(s.min_cut_in),
                known: pass,
            },
        ),
    ]
}

impl Haas {
    pub fn new(machine: &Machine) -> Haas {
        let settings = machine.haas.clone().unwrap_or_else(default_settings);
        let codes = GCodes::of(GCodeSystem::A);
        let mut family = FanucFamily::new(FLAVOUR, parameters(&settings), codes, machine);
        family.one_block_turning = settings.roughing_retract_in.map(|r| OneBlockTurning {
            retract_mm: r * MM_PER_INCH,
            assumed: settings.roughing_retract_assumed,
        });
        Haas {
            conv: Conventions {
                positions: POSITIONS,
                ..codes.conventions(machine)
            },
            family,
            machine: machine.clone(),
        }
    }

    /// M23/M24 switch the chamfer of the cycles that follow (and of the block they are on).
    fn chamfer_switch(&mut self, line: &Line) {
        for w in line.words.iter().filter(|w| w.letter == b'M') {
            match g_code(w.value) {
                Some(M23) => self.family.chamfer_on = true,
                Some(M24) => self.family.chamfer_on = false,
                _ => {}
            }
        }
    }

    /// G32's words are X/U Z/W F Q: an E there is refused rather than ignored (F(E) is G76's and
    /// G92's).
    fn thread_move_e(&self, line: &Line, modal: &Modal) -> Result<()> {
        let Some(e) = line.word(b'E') else {
            return Ok(());
        };
        let no_g = !line.words.iter().any(|w| w.letter == b'G');
        if line.has_g(self.family.codes.thread_move) || (no_g && modal.motion == MotionMode::Thread)
        {
            return Err(Diagnostic::error(
                Code::Unsupported,
                e.span,
                "E is not a word of Haas's G32: its lead is F",
            )
            .with_hint("G32 X(U) Z(W) F Q"));
        }
        Ok(())
    }
}

impl Dialect for Haas {
    fn taper_word(&self) -> Option<super::TaperWord> {
        Some(self.family.taper_word())
    }
    fn name(&self) -> &'static str {
        "haas"
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

    /// The family's blocks, and blocks with M23/M24 or an E (a lead on G76/G92, refused on G32
    /// and as an exponent elsewhere). Most M blocks (M3, M8) are not offered: `read` would leave
    /// them as they are.
    #[inline(always)]
    fn prefilter(&self, line: &Line) -> bool {
        self.family
            .prefilter(line, WordSummary::letter_mask(b"M"), |line| {
                line.summary.has_letter(b'M')
                    && line
                        .words
                        .iter()
                        .any(|w| w.letter == b'M' && matches!(g_code(w.value), Some(M23 | M24)))
            })
    }

    fn at_rest(&self) -> bool {
        // The family's prefilter depends on nothing else of its state (its letters and codes
        // are the machine's).
        !self.family.in_progress()
    }

    fn end_of_input(&mut self) -> Result<()> {
        self.family.end_of_input()
    }

    fn read(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        self.chamfer_switch(line);
        self.thread_move_e(line, modal)?;
        match self.family.read(&self.conv, line, modal, warnings)? {
            Some(read) => Ok(read),
            None => {
                // E is a lead on G76 and G92 only (and refused on G32, above): elsewhere an E
                // glued to a number is an exponent.
                super::refuse_exponent(line)?;
                Ok(Read::Plain)
            }
        }
    }

    /// Haas's macros (an option of the control, read here whenever a program uses them): Fanuc's
    /// Custom Macro B (`#` variables, `WHILE … DOm … ENDm`, `IF … GOTO`, `IF … THEN`, `GOTO`, `G65`
    /// with Fanuc's argument letters) with Haas's own subprogram words: `M97 P n L k` calls the
    /// block N n of the same program, `M99 P n` jumps to N n of the program it is in (it does
    /// not return; `[condition] M99 P n` when the condition holds), and `#10000`–`#10999` are
    /// general-purpose variables besides `#100`–`#199` and `#500`–`#999`. Nesting: Fanuc's four
    /// levels of M97/M98 and four of G65 (docs/dialects/haas.md, "Macros").
    fn program_files(
        &self,
        wanted: &crate::interp::library::Wanted,
    ) -> crate::interp::library::FileNames {
        fanuc_family::program_files(wanted)
    }

    fn macros(&self) -> Option<crate::interp::Syntax> {
        Some(crate::interp::Syntax {
            m97_local_calls: true,
            m99_p_jumps: true,
            wide_commons: true,
            ..crate::interp::Syntax::MACRO_B
        })
    }

    fn format(&self) -> Format {
        Format {
            start_angle: Some(fanuc_family::START_ANGLE_Q),
            ..Format::lathe(&self.machine, "G32", 'F')
        }
    }

    /// The cycle is read back with the chamfer on (M23, the power-on state).
    fn assume_ready(&mut self) {
        self.family.chamfer_on = true;
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        self.native_candidates(job).remove(0)
    }

    /// G76 reads Settings 86, 95, 96 and 99; G92 Settings 95 and 96 (its chamfer, on with M23 at
    /// power-on, as the read-back assumes).
    fn settings_read(&self, native: &[String]) -> Vec<Setting> {
        let has = |code: &str| {
            native
                .iter()
                .flat_map(|l| l.split_whitespace())
                .any(|w| w == code)
        };
        let (g76, g92) = (has("G76"), has("G92"));
        let settings = self.machine.haas.clone().unwrap_or_else(default_settings);
        thread_settings(&settings)
            .into_iter()
            .filter(|(n, _)| g76 || (g92 && matches!(n, 95 | 96)))
            .map(|(_, s)| s)
            .collect()
    }

    fn settings(&self) -> Vec<Setting> {
        let settings = self.machine.haas.clone().unwrap_or_else(default_settings);
        thread_settings(&settings)
            .into_iter()
            .map(|(_, s)| s)
            .collect()
    }

    /// G92 for a single pass, the one-block G76 with every choice of its open words (read back
    /// with the chamfer on, M23).
    fn native_candidates(&self, job: &Job) -> Vec<std::result::Result<Vec<String>, String>> {
        let f = &self.family;
        let mut setup = f.one_block_setup();
        setup.pull_out = Some(one_block::PullOut {
            leads: f.params.chamfer_leads,
            angle_deg: f.params.chamfer_angle_deg,
        });
        fanuc_family::single_or_multiple(
            fanuc_family::native_g92(&self.machine, &f.codes, &f.flavour, job),
            one_block::g76_candidates(&self.machine, "G76", &setup, true, job),
            job,
        )
    }
}
