//! Allen-Bradley 9/Series (8520) lathe controls: the G78 multipass thread-cutting routine (seed 003,
//! manual chapter 25, p. 25-21; the tool-infeed pages that follow are missing from every public
//! copy, see `shared/reference/threading-notes.md` §a).
//!
//! ```text
//! G78 X__ Z__ K__ D__ F__|E__ A__ P__ I__ ;
//! ```
//! The cycle is the one-block cycle of Fanuc's FS15 format (`super::one_block`, shared with Haas's
//! and FS15's G76); this module reads Allen-Bradley's own words. Every decision on an ambiguity of
//! the seed is a row of `docs/dialects/allen-bradley-g78.md`.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::dialect::lexicon::{self, Code as C, Function as F, Lexicon, ToolForm};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::{AbParameters, EWord, Machine};
use crate::post::Format;
use crate::thread::Job;
use crate::units::MM_PER_INCH;

use super::{one_block, Dialect, Read};

const G33: u16 = 330;
const G78: u16 = 780;
const G92: u16 = 920;

/// What a 9/Series lathe's codes mean, from the pages of its user manual (8520-LUM) that public
/// copies hold (`docs/translation.md`): G20/G21 and G33/G78 (chapter 25), G90/G91 (14-9), G94/G95
/// (18-4), G41/G42/G40 (21-5), the T-word's format 2 `T` tool + two-digit offset (20-3), G92 setting
/// the position; G0–G3, G96/G97 and M0–M30 as ISO 6983-1 assigns them (the manual's lists are not
/// public). No dwell, spindle-limit or reference-return word is known: G28 is the 7300-compatible
/// thread cycle on this control (`reference: None`; a conversion writes a return as a rapid to the
/// target profile's `[reference] g28`, `docs/dialects/allen-bradley-g78.md`). Feed per revolution
/// at power-on is assumed (an AMP setting).
pub static LEXICON: Lexicon = Lexicon {
    codes: &[
        lexicon::MOTION,
        lexicon::G20_G21,
        &[(C::G(330), F::Thread)],
        lexicon::COMPENSATION,
        lexicon::G90_G91,
        lexicon::G94_G95,
        lexicon::SPINDLE_MODES,
        lexicon::ISO_M,
    ],
    tool: ToolForm::Combined { digits: 2 },
    dwell: None,
    spindle_limit: None,
    reference: None,
    restates_position: false,
    program_number: false,
    sequence_numbers: true,
    delimiters: false,
    power_on_feed: F::FeedPerRevolution,
    thread_words: b"FE",
    thread_settings: &[],
    only_units: None,
    pause_spindle: lexicon::PauseSpindle::BuilderDecides,
};

/// The G codes of an Allen-Bradley 9/Series lathe. The seed's chapter (25, thread cutting) names
/// G33, G34, G35 and G78 and the 7300-compatible G28/G29; the rest of the manual's list is not in
/// public copies, so every whole code G0–G99 is accepted except the threading codes of other controls
/// that this chapter does not list (G32, G76): docs/dialects/allen-bradley-g78.md, "Vocabulary".
pub static VOCABULARY: Vocabulary = Vocabulary {
    controller: "ab9",
    alarm: "9/Series: invalid G code",
    g_codes: &super::all_but(
        &[
            GCode::thread(G33, b"XZUWFEQ"),
            GCode::thread(G78, b"XZUWKDFEAPI"),
        ],
        &[320, 760],
    ),
    foreign: &[],
    others: super::others_with,
};

/// "It must be entered as an integer value from 0 to 120"; A0's chip areas assume a 60° tool.
pub use super::one_block::{MAX_TOOL_ANGLE, PLUNGE_TOOL_ANGLE};

pub struct AllenBradley {
    conv: Conventions,
    machine: Machine,
    params: AbParameters,
}

/// The built-in AMP values when a profile has no `[ab9]` table.
pub fn default_parameters() -> AbParameters {
    Machine::built_in("ab9")
        .and_then(|m| m.ab9)
        .expect("the ab9 profile has an [ab9] table")
}

impl AllenBradley {
    pub fn new(machine: &Machine) -> AllenBradley {
        let params = machine.ab9.clone().unwrap_or_else(default_parameters);
        AllenBradley {
            conv: Conventions {
                uw_incremental: false,
                g90_g91_distance: true,
                diameter_x: machine.diameter_x,
                thread_move: G33,
                lead_letter: b'F',
                lead_along_path: false,
                tpi_letter: if params.e_word == EWord::ThreadsPerInch {
                    b'E'
                } else {
                    0
                },
                set_position: G92,
                canned_cycles: &[],
                unmodelled: &[],
                units_codes: crate::gcode::modal::G20_G21,
                positions: crate::gcode::modal::PositionCodes::FANUC,
                syntax: crate::gcode::lexer::Syntax::default(),
            },
            machine: machine.clone(),
            params,
        }
    }

    /// The lead (mm per revolution) of E: "the number of threads per inch or inches per thread
    /// (determined in AMP) regardless of whether inch or metric mode is active".
    fn e_lead(&self, e: &Word) -> Result<f64> {
        if e.value <= 0.0 {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                e.span,
                format!("E{}: E is unsigned and must be above zero", e.value),
            ));
        }
        Ok(match self.params.e_word {
            EWord::ThreadsPerInch => MM_PER_INCH / e.value,
            EWord::InchesPerThread => e.value * MM_PER_INCH,
        })
    }

    fn read_cycle(
        &self,
        line: &Line,
        modal: &mut Modal,
        g78: Span,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        super::only_words(line, b"GNXZKDFEAPI", "G78", "X Z K D F|E A P I")?;
        super::alone_in_block(line, g78, "G78", &[])?;
        let missing =
            |what: &str| Diagnostic::error(Code::MissingWord, g78, format!("G78 needs {what}"));
        if line.word(b'X').is_none() {
            return Err(missing("X: the root of the thread at its end"));
        }
        if line.word(b'Z').is_none() {
            return Err(missing("Z: the end of the threading pass"));
        }
        let height = one_block::positive(
            modal,
            line.word(b'K')
                .ok_or_else(|| missing("K: the thread height (root to top, radius)"))?,
            "the thread height K",
        )?;
        let first = one_block::positive(
            modal,
            line.word(b'D')
                .ok_or_else(|| missing("D: the depth of the first pass (radius)"))?,
            "the first depth D",
        )?;
        let tool_angle = match line.word(b'A') {
            Some(a) => one_block::whole(a, 0.0, MAX_TOOL_ANGLE, "the tool angle A")?,
            None => 0.0, // "Not programming a value for A is the same as A0."
        };
        // P has no default in the Allen-Bradley text: threadcut does not guess an infeed.
        let infeed = one_block::infeed(line.word(b'P'), None, || {
            missing("P: the tool infeed, 1 to 4")
        })?;
        let lead = match (line.word(b'E'), line.word(b'F')) {
            (Some(e), Some(f)) => {
                let later = if e.span.start > f.span.start { e } else { f };
                return Err(Diagnostic::error(
                    Code::Conflict,
                    later.span,
                    "E and F in one G78 block: the lead is given by either E or F",
                )
                .with_hint("keep E (always inch) or F (lead in the active units)"));
            }
            (Some(e), None) => self.e_lead(e)?,
            (None, Some(f)) => {
                let lead = one_block::positive(modal, f, "the lead F")?;
                modal.f_word = Some(modal.value(f));
                lead
            }
            (None, None) => {
                return Err(missing("the lead: F (in the active units) or E (inch)"));
            }
        };
        let taper = line.word(b'I').map_or(0.0, |i| modal.length_mm(i));
        // Its pass table does not depend on the start point (the shared one-block lowering, as
        // FS15's and Haas's G76): a cycle shown on its own still has it (`passes`).
        let start = super::start_point_unstated(
            modal,
            g78,
            "G78",
            "position the tool at the cycle's start point before G78",
        )?;
        let end = modal.target(&self.conv, line, start)?;
        one_block::lower(
            &one_block::Cycle {
                span: g78,
                line: line.number,
                start,
                end,
                taper,
                height,
                first,
                tool_angle,
                infeed,
                lead,
                phase_deg: 0.0,
            },
            &self.setup(),
            modal,
            warnings,
        )
    }

    /// The AMP values, as the shared one-block cycle takes them.
    fn setup(&self) -> one_block::Setup {
        let p = &self.params;
        one_block::Setup {
            controller: "ab9",
            allowance: units_in(p.finish_allowance_in),
            allowance_name: "the AMP finishing allowance",
            min_cut: units_in(p.min_cut_in),
            finish_passes: p.finish_passes,
            // "Not programming a value for A is the same as A0."
            tool_angle: 0.0,
            pull_out: Some(one_block::PullOut {
                leads: p.chamfer_leads,
                angle_deg: p.chamfer_angle_deg,
            }),
            pull_out_name: "the AMP pull-out",
        }
    }
}

/// Inches to mm (AMP values are kept in inches).
fn units_in(v: f64) -> f64 {
    v * MM_PER_INCH
}

impl Dialect for AllenBradley {
    /// G78 I: the root's radius at the thread start minus at its end (docs/dialects/allen-bradley-g78.md).
    fn taper_word(&self) -> Option<super::TaperWord> {
        Some(super::TaperWord {
            cycles: "G78 I",
            letter: 'I',
            start_minus_end: true,
            radius: true,
        })
    }
    fn name(&self) -> &'static str {
        "ab9"
    }

    /// `read` acts on G78 and on E (E with F, or E as a G33 lead); nothing else.
    #[inline]
    fn prefilter(&self, line: &Line) -> bool {
        // The lexer's summary answers for most lines without a look at the words.
        line.summary.has_letter(b'E') || line.has_g(G78)
    }

    fn at_rest(&self) -> bool {
        true
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
        let cycle = line
            .words
            .iter()
            .find(|w| w.letter == b'G' && g_code(w.value) == Some(G78));
        if let Some(g78) = cycle {
            let job = self.read_cycle(line, modal, g78.span, warnings)?;
            return Ok(Read::Cycle(Box::new(job)));
        }
        // A single-pass G33 takes its lead from E or F, never both.
        if let (Some(e), Some(f)) = (line.word(b'E'), line.word(b'F')) {
            let later = if e.span.start > f.span.start { e } else { f };
            return Err(Diagnostic::error(
                Code::Conflict,
                later.span,
                "E and F in one block: the lead is given by either E or F",
            ));
        }
        if self.params.e_word == EWord::InchesPerThread && line.has_g(G33) {
            if let Some(e) = line.word(b'E') {
                modal.lead = Some(self.e_lead(e)?);
            }
        }
        // E is the lead of G33 (and of a block of axis words under a modal G33) and of G78.
        let threads = line.has_g(G33)
            || (modal.motion == crate::gcode::MotionMode::Thread
                && !line.words.iter().any(|w| w.letter == b'G'));
        if !threads {
            super::refuse_exponent(line)?;
        }
        Ok(Read::Plain)
    }

    fn format(&self) -> Format {
        Format::lathe(&self.machine, "G33", 'F')
    }

    fn emit_native(&self, job: &Job) -> std::result::Result<Vec<String>, String> {
        self.native_candidates(job).remove(0)
    }

    /// G78, the one-block cycle FS15's and Haas's G76 share, with every choice of A and P that
    /// gives the job's infeed; its finishing allowance, passes, minimum cut and pull-out are the
    /// AMP values of the profile, and it has no start angle.
    fn native_candidates(&self, job: &Job) -> Vec<std::result::Result<Vec<String>, String>> {
        one_block::g76_candidates(&self.machine, "G78", &self.setup(), false, job)
    }
}
