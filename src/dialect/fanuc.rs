//! Fanuc 0i/30i-class lathe controls (`shared/reference/threading-notes.md` §e) in G-code system A,
//! B or C (the profile's `[fanuc] gcode_system`): the thread move G32 (G33 in B and C, read by the
//! shared modal reader, its start angle Q checked here), the single-pass cycle G92 (G78, G21) and
//! the two-block G76 (G78 in C), read by [`super::fanuc_family`], which GSK, Haas and the FS15
//! program format ([`super::fanuc15`]) share. Decisions: `docs/dialects/fanuc.md`.

use crate::diag::{Diagnostic, Result};
use crate::gcode::modal::Vocabulary;
use crate::gcode::{Conventions, Line, Modal};
use crate::machine::{FanucParameters, GCodeSystem, Machine};
use crate::post::Format;
use crate::thread::Job;

use super::fanuc_family::{
    self, FanucFamily, Flavour, G76Form, GCodes, ThreadParameters, ThreadWords,
};
use super::{one_block, Dialect, Read};

/// The threading codes' words in Fanuc's standard program format: G32 (G33) `X Z U W F Q`, the
/// two-block G76 (G78 in system C) `P Q R` then `X Z U W R P Q F`, G92 (G78, G21) `X Z U W R F Q`.
const WORDS: ThreadWords = ThreadWords {
    thread_move: b"XZUWFQ",
    single: b"XZUWRFQ",
    multiple: b"XZUWRPQF",
};

/// The G codes of a Fanuc 0i/30i lathe control in G-code system A, B or C (the operator's
/// manual's G code list: `docs/dialects/fanuc.md`, "Vocabulary"; one table for the three
/// systems, [`fanuc_family::g_codes`]). Not in system A: G33 (system A threads with G32), G78
/// (GSK's cycle, and systems B/C's G92), G91 (U/W are the incremental words).
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "fanuc",
    alarm: ALARM,
    g_codes: &fanuc_family::g_codes(GCodeSystem::A, &WORDS),
    foreign: GCodes::of(GCodeSystem::A).foreign,
    others: super::others_with,
};
/// … in G-code system B.
pub static VOCABULARY_B: Vocabulary = Vocabulary {
    controller: "fanuc (G-code system B)",
    alarm: ALARM,
    g_codes: &fanuc_family::g_codes(GCodeSystem::B, &WORDS),
    foreign: GCodes::of(GCodeSystem::B).foreign,
    others: super::others_with,
};
/// … in G-code system C.
pub static VOCABULARY_C: Vocabulary = Vocabulary {
    controller: "fanuc (G-code system C)",
    alarm: ALARM,
    g_codes: &fanuc_family::g_codes(GCodeSystem::C, &WORDS),
    foreign: GCodes::of(GCodeSystem::C).foreign,
    others: super::others_with,
};

/// A Fanuc control's alarm for a G code it does not have.
pub const ALARM: &str = "alarm PS0010 (improper G-code)";

/// The vocabulary of the standard program format in `system`.
pub fn vocabulary(system: GCodeSystem) -> &'static Vocabulary {
    match system {
        GCodeSystem::A => &VOCABULARY,
        GCodeSystem::B => &VOCABULARY_B,
        GCodeSystem::C => &VOCABULARY_C,
    }
}

/// A Fanuc-family control whose words are Fanuc's own: the standard program format (`fanuc`) or
/// the FS15 format (`fanuc15`), as its [`Flavour`] says.
pub struct Fanuc {
    conv: Conventions,
    machine: Machine,
    family: FanucFamily,
}

/// The built-in parameter values when a profile has no `[fanuc]` table.
pub fn default_parameters() -> FanucParameters {
    Machine::built_in("fanuc")
        .and_then(|m| m.fanuc)
        .expect("the fanuc profile has a [fanuc] table")
}

impl Fanuc {
    /// The standard program format: the two-block G76.
    pub fn new(machine: &Machine) -> Fanuc {
        Fanuc::with_flavour(machine, Flavour::fanuc("fanuc", vocabulary))
    }

    /// A Fanuc control whose program format is `flavour`'s.
    pub fn with_flavour(machine: &Machine, flavour: Flavour) -> Fanuc {
        let p = machine.fanuc.clone().unwrap_or_else(default_parameters);
        let codes = GCodes::of(p.gcode_system);
        Fanuc {
            conv: codes.conventions(machine),
            family: FanucFamily::new(flavour, ThreadParameters::of_fanuc(&p), codes, machine),
            machine: machine.clone(),
        }
    }
}

impl Dialect for Fanuc {
    /// G76 (second block) and G92 R(i): the radius at the start point minus at the end point,
    /// signed (docs/dialects/fanuc.md).
    fn taper_word(&self) -> Option<super::TaperWord> {
        Some(self.family.taper_word())
    }
    fn name(&self) -> &'static str {
        self.family.flavour.controller
    }

    fn conventions(&self) -> &Conventions {
        &self.conv
    }

    fn vocabulary(&self) -> &'static Vocabulary {
        self.family.vocabulary
    }

    fn lexicon(&self) -> &'static crate::dialect::lexicon::Lexicon {
        fanuc_family::lexicon(self.family.codes.system)
    }

    /// The family's blocks (cycle blocks, any block while the single-pass cycle is modal, blocks
    /// with a start angle Q) and blocks with an E word (a lead on thread moves, an exponent to
    /// refuse elsewhere).
    #[inline(always)]
    fn prefilter(&self, line: &Line) -> bool {
        self.family.prefilter(line, 0, |_| false)
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
        match self.family.read(&self.conv, line, modal, warnings)? {
            Some(read) => Ok(read),
            None => {
                // E is a lead word on thread moves (its meaning depends on the series); nowhere
                // else.
                if !self.family.threads(&self.conv, line, modal) {
                    super::refuse_exponent(line)?;
                }
                Ok(Read::Plain)
            }
        }
    }

    fn program_files(
        &self,
        wanted: &crate::interp::library::Wanted,
    ) -> crate::interp::library::FileNames {
        fanuc_family::program_files(wanted)
    }

    fn macros(&self) -> Option<crate::interp::Syntax> {
        // Custom Macro B: subprograms (M98) nest four levels deep, and macro calls (G65) four
        // levels apart from them (Fanuc 16i/18i operator's manual, custom macro "call nesting";
        // alarm 077); M98 takes its count in L or packed in P (docs/dialects/fanuc.md).
        Some(crate::interp::Syntax::MACRO_B)
    }

    fn format(&self) -> Format {
        Format {
            start_angle: self
                .family
                .flavour
                .start_angle
                .then_some(fanuc_family::START_ANGLE_Q),
            ..Format::lathe(&self.machine, self.family.codes.thread_move_name(), 'F')
        }
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        self.native_candidates(job).remove(0)
    }

    /// The single-pass cycle for a single pass, the multiple-pass cycle (two-block or one-block,
    /// as the program format has it) with every choice of its open words; the other one after.
    fn native_candidates(&self, job: &Job) -> Vec<std::result::Result<Vec<String>, String>> {
        let f = &self.family;
        let single = fanuc_family::native_g92(&self.machine, &f.codes, &f.flavour, job);
        let multiple = match f.flavour.g76 {
            G76Form::TwoBlock => {
                fanuc_family::g76_candidates(&self.machine, &f.codes, &f.params, job)
            }
            G76Form::OneBlock(_) => one_block::g76_candidates(
                &self.machine,
                &format!("G{}", f.codes.multiple / 10),
                &f.one_block_setup(),
                true,
                job,
            ),
        };
        fanuc_family::single_or_multiple(single, multiple, job)
    }
}
