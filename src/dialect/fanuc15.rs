//! Fanuc lathe controls set to the FS15 program format (Series 15-T; 16i/18i/0i with the FS15 tape
//! format): the one-block `G76 X(U) Z(W) I K D F A P Q` (`super::one_block`, the cycle Haas and
//! Allen-Bradley copy) and `G92 X(U) Z(W) I F Q` with an `I` taper; otherwise as `fanuc` (G-code
//! systems, G32 with Q, parameters 5130–5143). Sources and decisions: `docs/dialects/fanuc.md`,
//! "FS15 program format".

use crate::machine::Machine;

use super::fanuc::Fanuc;
use super::fanuc_family::{Flavour, G76Form};
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

/// The FS15 format's words on Fanuc's family reader.
pub const fn flavour() -> Flavour {
    Flavour {
        taper_letter: b'I',
        g76: G76Form::OneBlock(G76_WORDS),
        allowance_name: "the finishing allowance (parameter 5141)",
        ..Flavour::fanuc("fanuc15")
    }
}

/// A Fanuc control reading the FS15 program format.
pub fn new(machine: &Machine) -> Fanuc {
    Fanuc::with_flavour(machine, flavour())
}
