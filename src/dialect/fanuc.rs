//! Fanuc 0i/30i-class lathe controls, G-code system A (`shared/reference/threading-notes.md` §e):
//! G32 (single synchronised move, read by the shared modal reader), G92 and the two-block G76 (read
//! by [`super::fanuc_family`], which GSK's G76/G92 share). Decisions: `docs/dialects/fanuc.md`.

use crate::diag::{Diagnostic, Result};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::{Conventions, Line, Modal};
use crate::machine::{FanucParameters, Machine};
use crate::post::Format;
use crate::thread::Job;

use super::fanuc_family::{self, FanucFamily, Flavour, ThreadParameters};
use super::{g, Dialect, Read};

/// The G codes of a Fanuc 0i/30i lathe control in G-code system A (the operator's manual's G code
/// list: docs/dialects/fanuc.md, "Vocabulary"). A fractional code (G7.1, G12.1, G50.3) is known by
/// its whole number. Not in system A: G33 (system A threads with G32), G78 (GSK's cycle, and
/// systems B/C's G92), G91 (U/W are the incremental words).
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "fanuc",
    alarm: "alarm PS0010 (improper G-code)",
    g_codes: &[
        g(0),
        g(10),
        g(20),
        g(30),
        g(40),
        g(50),
        g(70),
        g(80),
        g(90),
        g(100),
        g(110),
        g(120),
        g(130),
        g(170),
        g(180),
        g(190),
        g(200),
        g(210),
        g(220),
        g(230),
        g(250),
        g(260),
        g(270),
        g(280),
        g(290),
        g(300),
        g(310),
        GCode::thread(320, b"XZUWFQ"),
        g(340),
        g(350),
        g(360),
        g(370),
        g(380),
        g(390),
        g(400),
        g(410),
        g(420),
        g(430),
        g(440),
        g(490),
        g(500),
        g(510),
        g(520),
        g(530),
        g(540),
        g(550),
        g(560),
        g(570),
        g(580),
        g(590),
        g(610),
        g(620),
        g(630),
        g(640),
        g(650),
        g(660),
        g(670),
        g(680),
        g(690),
        g(700),
        g(710),
        g(720),
        g(730),
        g(740),
        g(750),
        GCode::thread(760, b"XZUWRPQF"),
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
        GCode::thread(920, b"XZUWRFQ"),
        g(940),
        g(960),
        g(970),
        g(980),
        g(990),
        g(1070),
        g(1120),
        g(1130),
        g(2500),
        g(2510),
    ],
    others: super::others_with,
};

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
    pub fn new(machine: &Machine) -> Fanuc {
        let p = machine.fanuc.clone().unwrap_or_else(default_parameters);
        let params = ThreadParameters {
            chamfer_tenths: u32::from(p.p5130),
            chamfer_angle: u32::from(p.p5131),
            min_cut_mm: p.p5140,
            allowance_mm: p.p5141,
            finish_passes: u32::from(p.p5142),
            tool_angle: u32::from(p.p5143),
        };
        Fanuc {
            conv: Conventions {
                uw_incremental: true,
                g90_g91_distance: false,
                diameter_x: machine.diameter_x,
                thread_move: 320,
                // E on G32 is TPI on some series and a precise lead on others: not read.
                tpi_letter: 0,
                lead_letter: b'F',
                lead_along_path: false,
                set_position: 500,
                canned_cycles: &[700, 710, 720, 730, 740, 750, 760, 900, 920, 940],
            },
            family: FanucFamily::new(
                Flavour {
                    controller: "fanuc",
                    gsk_g92_words: false,
                    vocabulary: &VOCABULARY,
                },
                params,
                machine,
            ),
            machine: machine.clone(),
        }
    }
}

impl Dialect for Fanuc {
    fn name(&self) -> &'static str {
        "fanuc"
    }

    fn conventions(&self) -> &Conventions {
        &self.conv
    }

    fn vocabulary(&self) -> &'static Vocabulary {
        &VOCABULARY
    }

    /// Only G76/G92 blocks, and any block while a G92 is modal, are the family reader's business.
    #[inline]
    fn prefilter(&self, line: &Line) -> bool {
        self.family.wants(line)
    }

    fn read(
        &mut self,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Read> {
        Ok(self
            .family
            .read(&self.conv, line, modal, warnings)?
            .unwrap_or(Read::Plain))
    }

    fn format(&self) -> Format {
        Format::lathe(&self.machine, "G32", 'F')
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        fanuc_family::native_g92(&self.machine, job, false)
            .or_else(|_| fanuc_family::native_g76(&self.machine, job))
    }
}
