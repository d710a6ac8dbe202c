//! Allen-Bradley 9/Series (8520) lathe controls: the G78 multipass thread-cutting routine (seed 003,
//! manual chapter 25, p. 25-21; the tool-infeed pages that follow are missing from every public
//! copy, see `shared/reference/threading-notes.md` §a).
//!
//! ```text
//! G78 X__ Z__ K__ D__ F__|E__ A__ P__ I__ ;
//! ```
//! Every decision on an ambiguity of the seed is a row of `docs/dialects/allen-bradley-g78.md`.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::modal::{GCode, Vocabulary};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::{AbParameters, EWord, Machine};
use crate::post::{self, Format};
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan,
    Retract, ReturnPath, Side,
};
use crate::units::{Pos, MM_PER_INCH};

use super::{Dialect, Read};

const G33: u16 = 330;
const G78: u16 = 780;
const G92: u16 = 920;

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
    others: super::others_with,
};

/// "It must be entered as an integer value from 0 to 120".
pub const MAX_TOOL_ANGLE: f64 = 120.0;
/// The tool assumed for chip areas when A0 (plunge infeed) says nothing of the tool's angle.
pub const PLUNGE_TOOL_ANGLE: f64 = 60.0;

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
        let units = modal.units;
        let positive = |w: &Word, what: &str| -> Result<f64> {
            let v = modal.value(w);
            if v <= 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.span,
                    format!(
                        "{}{v}: {what} is unsigned and must be above zero",
                        w.letter as char
                    ),
                ));
            }
            Ok(units.to_mm(v))
        };
        let height = positive(
            line.word(b'K')
                .ok_or_else(|| missing("K: the thread height (root to top, radius)"))?,
            "the thread height K",
        )?;
        let first = positive(
            line.word(b'D')
                .ok_or_else(|| missing("D: the depth of the first pass (radius)"))?,
            "the first depth D",
        )?;
        let whole = |w: &Word, lo: f64, hi: f64, what: &str| -> Result<f64> {
            if w.value.fract() != 0.0 || w.value < lo || w.value > hi {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.span,
                    format!(
                        "{}{}: {what} must be a whole number from {lo} to {hi}",
                        w.letter as char, w.value
                    ),
                ));
            }
            Ok(w.value)
        };
        let tool_angle = match line.word(b'A') {
            Some(a) => whole(a, 0.0, MAX_TOOL_ANGLE, "the tool angle A")?,
            None => 0.0, // "Not programming a value for A is the same as A0."
        };
        let infeed_type = whole(
            line.word(b'P').ok_or_else(|| {
                missing("P: the tool infeed, 1 to 4").with_hint(
                    "P1/P2 constant amount, single/alternating edges; P3/P4 constant depth, single/alternating edges",
                )
            })?,
            1.0,
            4.0,
            "the tool infeed P",
        )? as u8;
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
                let lead = positive(f, "the lead F")?;
                modal.f_word = Some(modal.value(f));
                lead
            }
            (None, None) => {
                return Err(missing("the lead: F (in the active units) or E (inch)"));
            }
        };
        let taper = line.word(b'I').map_or(0.0, |i| modal.length_mm(i));
        let start = super::start_point(
            modal,
            g78,
            "G78",
            "position the tool at the cycle's start point before G78",
        )?;
        let end = modal.target(&self.conv, line, start)?;
        self.lower(
            &Cycle {
                span: g78,
                line: line.number,
                start,
                end,
                taper,
                height,
                first,
                tool_angle,
                infeed_type,
                lead,
            },
            modal,
            warnings,
        )
    }

    /// The validated words as a machine-neutral job.
    fn lower(&self, c: &Cycle, modal: &Modal, warnings: &mut Vec<Diagnostic>) -> Result<Job> {
        let units = modal.units;
        let geometry_error = |msg: String| Diagnostic::error(Code::Geometry, c.span, msg);
        let travel_z = c.end.z - c.start.z;
        if travel_z == 0.0 {
            return Err(geometry_error(
                "Z is the start point's Z: the thread has no length".into(),
            ));
        }
        if c.taper.abs() >= travel_z.abs() {
            return Err(geometry_error(format!(
                "the taper I changes the radius by {} over {} of Z: G78 threads along Z",
                units.from_mm(c.taper.abs()),
                units.from_mm(travel_z.abs())
            )));
        }
        // "I … added to the X parameter to determine the start-point of the threading pass."
        let root_start = Pos::new(c.end.x + c.taper, c.start.z);
        let side = Side::of_cut(c.start.x, root_start.x).ok_or_else(|| {
            geometry_error(
                "the start point's X is the thread's root: cannot tell an external from an internal thread"
                    .into(),
            )
        })?;
        let outward = side.outward().x;
        let crest_x = root_start.x + outward * c.height;
        if (c.start.x - crest_x) * outward < 0.0 {
            return Err(geometry_error(format!(
                "the start point X{} lies inside the thread (its top is at X{}): the return between passes would cut through it",
                post::number(modal.x_from_mm(c.start.x), 4, false),
                post::number(modal.x_from_mm(crest_x), 4, false)
            ))
            .with_hint("start G78 from a point clear of the top of the thread"));
        }
        let p = &self.params;
        let allowance = units_in(p.finish_allowance_in);
        if allowance >= c.height {
            return Err(geometry_error(format!(
                "the AMP finishing allowance {}\" is not smaller than the thread height K",
                p.finish_allowance_in
            )));
        }
        let axial_dir = travel_z.signum();
        let half = c.tool_angle / 2.0;
        // Single edge: deeper passes move in the cutting direction, so the leading edge cuts, and
        // the full-depth pass lands on the programmed start Z and ends on the programmed Z.
        let leading = if axial_dir < 0.0 {
            Flank::Right
        } else {
            Flank::Left
        };
        let trailing = if axial_dir < 0.0 {
            Flank::Left
        } else {
            Flank::Right
        };
        let infeed = match (c.tool_angle == 0.0, c.infeed_type) {
            (true, _) => Infeed::Radial,
            (false, 1 | 3) => Infeed::Flank {
                flank: leading,
                angle_deg: half,
            },
            (false, _) => Infeed::Alternating {
                first: leading,
                second: trailing,
                angle_deg: half,
            },
        };
        let law = if c.infeed_type <= 2 {
            DepthLaw::Power {
                first: c.first,
                degression: 2.0,
                min_step: units_in(p.min_cut_in),
            }
        } else {
            DepthLaw::Power {
                first: c.first,
                degression: 1.0,
                min_step: 0.0,
            }
        };
        let shift = infeed.axis(c.height);
        let crest_start = Pos::new(crest_x, c.start.z - shift);
        let crest_end = Pos::new(c.end.x + outward * c.height, c.end.z - shift);
        let exit = if p.chamfer_leads > 0.0 {
            if !(p.chamfer_angle_deg > 0.0 && p.chamfer_angle_deg < 90.0) {
                return Err(geometry_error(format!(
                    "the AMP pull-out angle {}° must lie between 0 and 90",
                    p.chamfer_angle_deg
                )));
            }
            let length = p.chamfer_leads * c.lead;
            if length >= travel_z.abs() {
                return Err(geometry_error(format!(
                    "the AMP pull-out ({} leads = {}) is not shorter than the thread ({})",
                    p.chamfer_leads,
                    units.from_mm(length),
                    units.from_mm(travel_z.abs())
                )));
            }
            Exit::PullOut {
                start_before: length,
                length,
                outward: length * tan_deg(p.chamfer_angle_deg),
            }
        } else {
            Exit::Straight
        };
        if c.first >= c.height {
            warnings.push(Diagnostic::warning(
                Code::Suspicious,
                c.span,
                format!(
                    "the first depth D {} is not smaller than the thread height K {}: the whole thread is cut in one pass",
                    units.from_mm(c.first),
                    units.from_mm(c.height)
                ),
            ));
        }
        Ok(Job {
            line: c.line,
            span: c.span,
            controller: "ab9",
            units,
            start: c.start,
            geometry: Geometry {
                crest_start,
                crest_end,
                depth: c.height,
                side,
            },
            lead: Lead::constant(c.lead),
            plan: PassPlan {
                law,
                finish_allowance: allowance,
                finish_passes: p.finish_passes,
            },
            infeed,
            finish_at: FinishPosition::Axis,
            tool_angle_deg: if c.tool_angle == 0.0 {
                PLUNGE_TOOL_ANGLE
            } else {
                c.tool_angle
            },
            entry: Entry::Direct,
            exit,
            retract: Retract {
                x: c.start.x,
                z: c.start.z,
            },
            return_path: ReturnPath::Box,
        })
    }
}

/// Inches to mm (AMP values are kept in inches).
fn units_in(v: f64) -> f64 {
    v * MM_PER_INCH
}

/// A G78 block's values in the model's terms (mm, radius, absolute).
struct Cycle {
    span: Span,
    line: u32,
    start: Pos,
    end: Pos,
    taper: f64,
    height: f64,
    first: f64,
    tool_angle: f64,
    infeed_type: u8,
    lead: f64,
}

impl Dialect for AllenBradley {
    fn name(&self) -> &'static str {
        "ab9"
    }

    /// `read` acts on G78 and on E (E with F, or E as a G33 lead); nothing else.
    #[inline]
    fn prefilter(&self, line: &Line) -> bool {
        // The lexer's summary answers for most lines without a look at the words.
        line.summary.has_letter(b'E') || line.has_g(G78)
    }

    fn conventions(&self) -> &Conventions {
        &self.conv
    }

    fn vocabulary(&self) -> &'static Vocabulary {
        &VOCABULARY
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
        Ok(Read::Plain)
    }

    fn format(&self) -> Format {
        Format::lathe(&self.machine, "G33", 'F')
    }
}
