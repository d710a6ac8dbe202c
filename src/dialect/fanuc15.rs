//! Fanuc lathe controls set to the FS15 program format (Series 15-T; 16i/18i/0i with the FS15 tape
//! format): the one-block `G76 X(U) Z(W) I K D F A P Q` (`super::one_block`, the cycle Haas and
//! Allen-Bradley copy) and `G92 X(U) Z(W) I F Q` with an `I` taper; otherwise as `fanuc` (G-code
//! systems, G32 with Q, parameters 5130–5143). Sources and decisions: `docs/dialects/fanuc.md`,
//! "FS15 program format".

use crate::gcode::modal::Vocabulary;
use crate::machine::{GCodeSystem, Machine};

use super::fanuc::{Fanuc, ALARM};
use super::fanuc_family::{self, Flavour, G76Form, GCodes, ThreadWords};
use super::one_block::G76Words;

/// The one-block G76's words in the FS15 format. E is read only to refuse it (its meaning depends
/// on the series); A and Q take Fanuc's usual number forms; K0/D0 draw Fanuc's cycle alarm.
pub const G76_WORDS: G76Words = G76Words {
    letters: b"GNXZUWIKDFEAPQ",
    format: "X(U) Z(W) I(taper) K(height) D(first depth) F(lead) A(tool angle) P(infeed 1-4) Q(start angle)",
    e_is_lead: false,
    no_point_a: false,
    alarm: Some("PS0062"),
};

/// The threading codes' words in the FS15 format: G32 (G33) `X Z U W F Q`, the one-block G76 (G78
/// in system C) [`G76_WORDS`], G92 (G78, G21) `X Z U W I F Q`.
const WORDS: ThreadWords = ThreadWords {
    thread_move: b"XZUWFQ",
    single: b"XZUWIFQ",
    multiple: b"XZUWIKDFEAPQ",
};

/// The G codes of a Fanuc control in the FS15 program format: the same G code list as the
/// standard format's (`super::fanuc::VOCABULARY`), in G-code system A, B or C; the threading
/// codes take the FS15 words.
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "fanuc15",
    alarm: ALARM,
    g_codes: &fanuc_family::g_codes(GCodeSystem::A, &WORDS),
    foreign: GCodes::of(GCodeSystem::A).foreign,
    others: super::others_with,
};
/// … in G-code system B.
pub static VOCABULARY_B: Vocabulary = Vocabulary {
    controller: "fanuc15 (G-code system B)",
    alarm: ALARM,
    g_codes: &fanuc_family::g_codes(GCodeSystem::B, &WORDS),
    foreign: GCodes::of(GCodeSystem::B).foreign,
    others: super::others_with,
};
/// … in G-code system C.
pub static VOCABULARY_C: Vocabulary = Vocabulary {
    controller: "fanuc15 (G-code system C)",
    alarm: ALARM,
    g_codes: &fanuc_family::g_codes(GCodeSystem::C, &WORDS),
    foreign: GCodes::of(GCodeSystem::C).foreign,
    others: super::others_with,
};

/// The vocabulary of the FS15 format in `system`.
pub fn vocabulary(system: GCodeSystem) -> &'static Vocabulary {
    match system {
        GCodeSystem::A => &VOCABULARY,
        GCodeSystem::B => &VOCABULARY_B,
        GCodeSystem::C => &VOCABULARY_C,
    }
}

/// The FS15 format's words on Fanuc's family reader.
pub const fn flavour() -> Flavour {
    Flavour {
        taper_letter: b'I',
        g76: G76Form::OneBlock(G76_WORDS),
        allowance_name: "the finishing allowance (parameter 5141)",
        ..Flavour::fanuc("fanuc15", vocabulary)
    }
}

/// A Fanuc control reading the FS15 program format.
pub fn new(machine: &Machine) -> Fanuc {
    Fanuc::with_flavour(machine, flavour())
}
