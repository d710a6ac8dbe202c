//! Fanuc 0i/30i-class lathe controls, G-code system A (`shared/reference/threading-notes.md` §e):
//! G32 (single synchronised move, read by the shared modal reader), G92 and the two-block G76 (read
//! by [`super::fanuc_family`], which GSK's G76/G92 share). Decisions: `docs/dialects/fanuc.md`.

use crate::diag::{Diagnostic, Result};
use crate::gcode::{Conventions, Line, Modal};
use crate::machine::{FanucParameters, Machine};
use crate::post::Format;
use crate::thread::Job;

use super::fanuc_family::{self, FanucFamily, Flavour, ThreadParameters};
use super::{Dialect, Read};

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

    fn macros(&self) -> Option<crate::interp::Syntax> {
        // Custom Macro B: subprograms (M98) nest four levels deep, and macro calls (G65) four
        // levels apart from them (Fanuc 16i/18i operator's manual, custom macro "call nesting";
        // alarm 077); M98 takes its count in L or packed in P (docs/dialects/fanuc.md).
        Some(crate::interp::Syntax {
            lang: crate::interp::Lang::MacroB,
            max_call_depth: 4,
            max_macro_depth: 4,
            g65_operations: false,
            m98_l_word: true,
        })
    }

    fn format(&self) -> Format {
        Format::lathe(&self.machine, "G32", 'F')
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        fanuc_family::native_g92(&self.machine, job, false)
            .or_else(|_| fanuc_family::native_g76(&self.machine, job))
    }
}
