//! The Fanuc family's threading cycles, shared by every controller that copies them (Fanuc 0i/30i
//! system A, GSK 980TDi): the single-pass box cycle G92 and the two-block multiple-pass cycle G76
//! (`shared/reference/threading-notes.md` §c.1, §c.3, §e).
//!
//! ```text
//! G92 X(U) Z(W) [R(i)] F(L) ;                     one pass; modal: a following `X..` repeats it
//! G76 P(m)(r)(a) Q(Δdmin) R(d) ;                   first block: rewrites parameters 5142/5130/5143, 5140, 5141
//! G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L) ;             second block: the cycle
//! ```
//! P(k), Q(Δd) and Q(Δdmin) are counts of least input increments, written without a decimal point,
//! whatever the machine's decimal-point setting. Each decision is a row of `docs/dialects/fanuc.md`.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::reader::g_code;
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::Machine;
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan,
    Retract, ReturnPath, Side,
};
use crate::units::{Pos, Units};

use super::{only_words, Read};

const G76: u16 = 760;
const G92: u16 = 920;

/// Tool-tip angles the first G76 block accepts (Fanuc: 80, 60, 55, 30, 29 and 0 degrees).
pub const TOOL_ANGLES: [u32; 6] = [80, 60, 55, 30, 29, 0];

/// G codes that end a modal G92 (group 01 and the other turning cycles), ×10.
const CANCELS_G92: &[u16] = &[
    0, 10, 20, 30, 320, 330, 340, 700, 710, 720, 730, 740, 750, 760, 780, 900, 940,
];

/// Parameters of the threading cycles. The first G76 block rewrites them, as on the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThreadParameters {
    /// 5130: chamfer amount in 0.1 lead (0: no chamfer).
    pub chamfer_tenths: u32,
    /// 5131: chamfer angle in degrees (0 reads as 45).
    pub chamfer_angle: u32,
    /// 5140: Δdmin (mm, radius).
    pub min_cut_mm: f64,
    /// 5141: d (mm, radius).
    pub allowance_mm: f64,
    /// 5142: m.
    pub finish_passes: u32,
    /// 5143: a (degrees).
    pub tool_angle: u32,
}

impl ThreadParameters {
    fn chamfer_angle_deg(&self) -> f64 {
        if self.chamfer_angle == 0 {
            45.0
        } else {
            f64::from(self.chamfer_angle)
        }
    }

    /// The pull-out of a pass for lead `lead` (mm): `r·0.1·L` along Z at the chamfer angle.
    fn chamfer(&self, lead: f64) -> Exit {
        let length = f64::from(self.chamfer_tenths) * 0.1 * lead;
        if length <= 0.0 {
            return Exit::Straight;
        }
        Exit::PullOut {
            start_before: length,
            length,
            outward: length * tan_deg(self.chamfer_angle_deg()),
        }
    }
}

/// What a member of the family adds to the common words.
#[derive(Clone, Copy, Debug)]
pub struct Flavour {
    /// The controller's name on jobs.
    pub controller: &'static str,
    /// GSK's G92 words: J/K (tail-out, short and long axis) and L (starts).
    pub gsk_g92_words: bool,
}

/// The modal state of G92: the values a following block without a G code repeats.
#[derive(Clone, Copy, Debug)]
struct G92Modal {
    end_z: f64,
    taper: f64,
}

/// The shared reader. A dialect offers it every line first.
pub struct FanucFamily {
    pub flavour: Flavour,
    pub params: ThreadParameters,
    /// Least input increment in mm and in inch (for P(k), Q(Δd), Q(Δdmin)).
    increment: [f64; 2],
    g92: Option<G92Modal>,
}

impl FanucFamily {
    pub fn new(flavour: Flavour, params: ThreadParameters, machine: &Machine) -> FanucFamily {
        FanucFamily {
            flavour,
            params,
            increment: [
                machine.resolution(Units::Mm),
                machine.resolution(Units::Inch),
            ],
            g92: None,
        }
    }

    /// Whether [`read`](Self::read) may act on `line`: a G76 or G92 block, or any block while a G92
    /// is modal (a block of axis words repeats it; a motion code cancels it).
    #[inline]
    pub fn wants(&self, line: &Line) -> bool {
        self.g92.is_some() || line.has_g(G76) || line.has_g(G92)
    }

    /// Reads `line` if it is a G76 or G92 block (or a block repeating a modal G92); `None` otherwise.
    pub fn read(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Option<Read>> {
        // No allocation: this runs on every line.
        let gs = || {
            line.words
                .iter()
                .filter(|w| w.letter == b'G')
                .map(|w| (w, g_code(w.value)))
        };
        let cycle = gs()
            .find(|(_, c)| matches!(c, Some(G76) | Some(G92)))
            .map(|(w, c)| (w, c.expect("matched")));
        let Some((gword, code)) = cycle else {
            if gs().any(|(_, c)| c.is_some_and(|c| CANCELS_G92.contains(&c))) {
                self.g92 = None;
            }
            // A repeat is a block of axis words alone: any G code (a dwell `G4 X1.`, `G50 X..`) makes
            // the block something else.
            let moves = gs().next().is_none()
                && line
                    .words
                    .iter()
                    .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
            return match self.g92 {
                Some(m) if moves => {
                    let job = self.read_g92(conv, line, modal, line.span(), Some(m), warnings)?;
                    Ok(Some(Read::Cycle(Box::new(job))))
                }
                _ => Ok(None),
            };
        };
        super::alone_in_block(line, gword.span, &format!("G{}", code / 10), &[])?;
        let second = line
            .words
            .iter()
            .any(|w| matches!(w.letter, b'X' | b'Z' | b'U' | b'W'));
        if code == G92 {
            if !second {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    gword.span,
                    "G92 needs the thread end point: X (or U) and Z (or W)",
                )
                .with_hint(
                    "this dialect reads G92 as the thread-cutting cycle (G-code system A)",
                ));
            }
            let job = self.read_g92(conv, line, modal, gword.span, None, warnings)?;
            return Ok(Some(Read::Cycle(Box::new(job))));
        }
        self.g92 = None;
        if second {
            let job = self.read_g76_second(conv, line, modal, gword.span, warnings)?;
            Ok(Some(Read::Cycle(Box::new(job))))
        } else {
            self.read_g76_first(line, modal)?;
            Ok(Some(Read::Settings))
        }
    }

    /// A count of least input increments, written without a decimal point, in mm.
    fn increments(&self, modal: &Modal, w: &Word, name: &str, what: &str) -> Result<f64> {
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

    fn read_g76_first(&mut self, line: &Line, modal: &Modal) -> Result<()> {
        only_words(
            line,
            b"GNPQR",
            "the first G76 block",
            "P(m)(r)(a) Q(Δdmin) R(d)",
        )?;
        let mut p = self.params;
        if let Some(w) = line.word(b'P') {
            let (m, r, a) = unpack_p(line, w)?;
            p.finish_passes = m;
            p.chamfer_tenths = r;
            p.tool_angle = a;
        }
        if let Some(q) = line.word(b'Q') {
            p.min_cut_mm =
                self.increments(modal, q, "Q(Δdmin)", "the minimum depth of cut (radius)")?;
        }
        if let Some(r) = line.word(b'R') {
            let v = modal.length_mm(r);
            if v < 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    r.span,
                    format!(
                        "R(d)={} is negative: the finishing allowance is a radial stock",
                        r.value
                    ),
                ));
            }
            p.allowance_mm = v;
        }
        self.params = p;
        Ok(())
    }

    fn read_g76_second(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        g76: Span,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        let letters: &[u8] = if conv.tpi_letter == b'I' {
            b"GNXZUWRPQFIE"
        } else {
            b"GNXZUWRPQFE"
        };
        only_words(
            line,
            letters,
            "the second G76 block",
            "X(U) Z(W) R(i) P(k) Q(Δd) F(L)",
        )?;
        let height = match line.word(b'P') {
            Some(w) => self.increments(modal, w, "P(k)", "the thread height (radius)")?,
            None => return Err(alarm_missing(g76, "P(k)", "the thread height (radius)")),
        };
        let first = match line.word(b'Q') {
            Some(w) => self.increments(modal, w, "Q(Δd)", "the depth of the first cut (radius)")?,
            None => {
                return Err(alarm_missing(
                    g76,
                    "Q(Δd)",
                    "the depth of the first cut (radius)",
                ))
            }
        };
        for (w, v, name) in [
            (line.word(b'P'), height, "P(k)"),
            (line.word(b'Q'), first, "Q(Δd)"),
        ] {
            if v <= 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.map_or(g76, |w| w.span),
                    format!("G76 alarm (PS0062): {name} must be greater than 0"),
                ));
            }
        }
        let taper = line.word(b'R').map_or(0.0, |r| modal.length_mm(r));
        let lead = self.lead(conv, line, modal, g76, "G76")?;
        let (a, end) = self.endpoints(conv, line, modal, g76, "G76")?;
        let p = self.params;
        if p.allowance_mm >= height {
            return Err(Diagnostic::error(
                Code::Geometry,
                g76,
                format!(
                    "the finishing allowance d {} is not smaller than the thread height P(k) {}",
                    modal.units.from_mm(p.allowance_mm),
                    modal.units.from_mm(height)
                ),
            ));
        }
        // C: the root at the thread start (X of the end point plus the taper, Z of the start point).
        let c = Pos::new(end.x + taper, a.z);
        let side = side_of(a, c, g76)?;
        let travel_z = end.z - a.z;
        if travel_z == 0.0 {
            return Err(geometry(
                g76,
                "the thread end Z equals the start point's Z: the thread has no length",
            ));
        }
        if taper.abs() > travel_z.abs() {
            return Err(geometry(
                g76,
                format!(
                    "the taper R(i) changes X by more than the thread's Z length ({} > {} mm, radius)",
                    taper.abs(),
                    travel_z.abs()
                ),
            ));
        }
        let crest_c = c.plus(side.outward().scale(height));
        if (a.x - crest_c.x) * side.outward().x < 0.0 {
            return Err(geometry(
                g76,
                "the start point lies inside the thread (between crest and root): the return along Z would cut through it",
            )
            .with_hint("start the cycle from a point clear of the crest"));
        }
        let half = f64::from(p.tool_angle) / 2.0;
        // Single-edge infeed: deeper passes move in the cutting direction along the flank at a/2, so
        // the leading edge cuts and the trailing edge follows the groove; the full-depth pass runs
        // from the start point's Z to the programmed end Z.
        let flank = if travel_z < 0.0 {
            Flank::Right
        } else {
            Flank::Left
        };
        let infeed = if p.tool_angle == 0 {
            Infeed::Radial
        } else {
            Infeed::Flank {
                flank,
                angle_deg: half,
            }
        };
        let full_offset = infeed.axis(height);
        let crest_start = Pos::new(crest_c.x, a.z - full_offset);
        let crest_end = Pos::new(crest_c.x - taper, end.z - full_offset);
        let exit = p.chamfer(lead);
        check_exit(&exit, travel_z, modal.units, g76)?;
        super::lead_warning(lead, travel_z, modal.units, g76, "check F", warnings);
        Ok(Job {
            line: line.number,
            span: g76,
            controller: self.flavour.controller,
            units: modal.units,
            start: a,
            geometry: Geometry {
                crest_start,
                crest_end,
                depth: height,
                side,
            },
            lead: Lead::constant(lead),
            plan: PassPlan {
                law: DepthLaw::Power {
                    first,
                    degression: 2.0,
                    min_step: p.min_cut_mm,
                },
                finish_allowance: p.allowance_mm,
                finish_passes: p.finish_passes,
            },
            infeed,
            finish_at: FinishPosition::Axis,
            tool_angle_deg: f64::from(p.tool_angle),
            entry: Entry::Direct,
            exit,
            retract: Retract { x: a.x, z: a.z },
            return_path: ReturnPath::Box,
        })
    }

    fn read_g92(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        repeat: Option<G92Modal>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        // E is read only to refuse it with its own message.
        let mut letters: Vec<u8> = b"GNXZUWRFE".to_vec();
        if conv.tpi_letter != 0 {
            letters.push(conv.tpi_letter);
        }
        if self.flavour.gsk_g92_words {
            letters.extend_from_slice(b"JKL");
        }
        only_words(
            line,
            &letters,
            "a G92 block",
            if self.flavour.gsk_g92_words {
                "X(U) Z(W) R(i) F(L) or I(threads per inch), J K L"
            } else {
                "X(U) Z(W) R(i) F(L)"
            },
        )?;
        let lead = self.lead(conv, line, modal, span, "G92")?;
        let a = start_point(modal, span, "G92")?;
        let mut end = modal.target(conv, line, a)?;
        let has_z = line.word(b'Z').or(line.word(b'W')).is_some();
        let has_x = line.word(b'X').or(line.word(b'U')).is_some();
        match repeat {
            Some(m) if !has_z => end.z = m.end_z,
            _ if !has_z || !has_x => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    span,
                    "G92 needs the thread end point: X (or U) and Z (or W)",
                ))
            }
            _ => {}
        }
        let taper = match line.word(b'R') {
            Some(r) => modal.length_mm(r),
            None => repeat.map_or(0.0, |m| m.taper),
        };
        self.g92 = Some(G92Modal {
            end_z: end.z,
            taper,
        });
        let travel_z = end.z - a.z;
        if travel_z == 0.0 {
            return Err(geometry(
                span,
                "the thread end Z equals the start point's Z: the thread has no length",
            ));
        }
        // The cut starts at the end X plus the taper; the pull-out rises toward the start point's X.
        let cut_start = Pos::new(end.x + taper, a.z);
        let side = side_of(a, end, span)?;
        if (a.x - cut_start.x) * side.outward().x <= 0.0 {
            return Err(geometry(
                span,
                format!(
                    "R(i) {} puts the thread's start beyond the start point's X: when R's sign differs from U's, |R| must not exceed |U/2|",
                    modal.units.from_mm(taper)
                ),
            ));
        }
        let (exit, starts) = if self.flavour.gsk_g92_words {
            self.gsk_tail(line, modal, lead)?
        } else {
            (self.params.chamfer(lead), 1)
        };
        check_exit(&exit, travel_z, modal.units, span)?;
        super::lead_warning(lead, travel_z, modal.units, span, "check F", warnings);
        Ok(Job {
            line: line.number,
            span,
            controller: self.flavour.controller,
            units: modal.units,
            start: a,
            geometry: Geometry {
                crest_start: cut_start,
                crest_end: Pos::new(end.x, end.z),
                depth: 0.0,
                side,
            },
            lead: Lead {
                starts,
                ..Lead::constant(lead)
            },
            plan: PassPlan {
                law: DepthLaw::Explicit { depths: vec![] },
                finish_allowance: 0.0,
                finish_passes: 1,
            },
            infeed: Infeed::Radial,
            finish_at: FinishPosition::Axis,
            tool_angle_deg: f64::from(self.params.tool_angle),
            entry: Entry::Direct,
            exit,
            retract: Retract { x: a.x, z: a.z },
            return_path: ReturnPath::Box,
        })
    }

    /// GSK's G92 tail-out J (short axis) and K (long axis) in the block's own words, and L starts
    /// (threading-notes §c.1–c.2): J alone means K = J, K alone means J = K, J = 0 means none;
    /// neither: parameters 5130/5131.
    fn gsk_tail(&self, line: &Line, modal: &Modal, lead: f64) -> Result<(Exit, u32)> {
        let j = line.word(b'J').map(|w| modal.length_mm(w));
        let k = line.word(b'K').map(|w| modal.length_mm(w));
        for w in [line.word(b'J'), line.word(b'K')].into_iter().flatten() {
            if w.value < 0.0 {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.span,
                    format!(
                        "{}{} is negative: the tail-out is unsigned",
                        w.letter as char, w.value
                    ),
                ));
            }
        }
        let exit = match (j, k) {
            (None, None) => self.params.chamfer(lead),
            (Some(j), None) | (Some(j), Some(0.0)) => pull_out(j, j),
            (None, Some(k)) => pull_out(k, k),
            (Some(j), Some(k)) => pull_out(j, k),
        };
        let starts = match line.word(b'L') {
            None => 1,
            Some(l) if l.value.fract() == 0.0 && (1.0..=99.0).contains(&l.value) => l.value as u32,
            Some(l) => {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    l.span,
                    format!(
                        "L{} is out of range: the number of starts is 1 to 99",
                        l.value
                    ),
                ))
            }
        };
        Ok((exit, starts))
    }

    fn lead(
        &self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        cycle: &str,
    ) -> Result<f64> {
        if let Some(e) = line.word(b'E') {
            return Err(Diagnostic::error(
                Code::Unsupported,
                e.span,
                format!(
                    "E on {cycle} means threads per inch or a precise lead depending on the series"
                ),
            )
            .with_hint("write the lead with F"));
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

    fn endpoints(
        &self,
        conv: &Conventions,
        line: &Line,
        modal: &Modal,
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
        let a = start_point(modal, span, cycle)?;
        Ok((a, modal.target(conv, line, a)?))
    }
}

fn pull_out(j: f64, k: f64) -> Exit {
    if j > 0.0 && k > 0.0 {
        Exit::PullOut {
            start_before: k,
            length: k,
            outward: j,
        }
    } else {
        Exit::Straight
    }
}

fn start_point(modal: &Modal, span: Span, cycle: &str) -> Result<Pos> {
    super::start_point(
        modal,
        span,
        cycle,
        "position the tool with G00 X.. Z.. before the cycle",
    )
}

/// External when the start point is above `reference` (cut toward −X), internal when below.
fn side_of(a: Pos, reference: Pos, span: Span) -> Result<Side> {
    if a.x > reference.x {
        Ok(Side::External)
    } else if a.x < reference.x {
        Ok(Side::Internal)
    } else {
        Err(geometry(
            span,
            "the start point's X equals the thread's X: cannot tell an external from an internal thread",
        ))
    }
}

fn check_exit(exit: &Exit, travel_z: f64, units: Units, span: Span) -> Result<()> {
    if let Exit::PullOut { length, .. } = *exit {
        if length >= travel_z.abs() {
            return Err(geometry(
                span,
                format!(
                    "the chamfer {} is not shorter than the thread ({} along Z)",
                    units.from_mm(length),
                    units.from_mm(travel_z.abs())
                ),
            )
            .with_hint("lower the chamfer amount (G76 P(r), parameter 5130)"));
        }
    }
    Ok(())
}

fn geometry(span: Span, msg: impl Into<String>) -> Diagnostic {
    Diagnostic::error(Code::Geometry, span, msg)
}

/// P(m)(r)(a): three two-digit fields, leading zeros may be omitted (`P21060` is m 02, r 10, a 60).
fn unpack_p(line: &Line, p: &Word) -> Result<(u32, u32, u32)> {
    let packed = super::packed_p(
        line,
        p,
        "G76",
        "P021060 is 2 finishing passes, a chamfer of 1.0 lead, a 60° tool",
    )?;
    let [m, r, a] = packed.fields;
    if !(1..=99).contains(&m) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            p.span,
            format!("P(m)={m:02}: the number of finishing passes must be 01 to 99"),
        ));
    }
    if !TOOL_ANGLES.contains(&a) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            p.span,
            format!("P(a)={a:02}: the tool-tip angle must be 80, 60, 55, 30, 29 or 00"),
        ));
    }
    Ok((m, r, a))
}

fn alarm_missing(span: Span, word: &str, what: &str) -> Diagnostic {
    Diagnostic::error(
        Code::MissingWord,
        span,
        format!("G76 alarm (PS0062): {word} is missing; it gives {what}"),
    )
    .with_hint(format!("{word} has no default on the second G76 block"))
}

/// The two G76 blocks that express `job`, when G76 can (the read-back check decides in the end).
pub fn native_g76(machine: &Machine, job: &Job) -> std::result::Result<Vec<String>, String> {
    let g = &job.geometry;
    if job.return_path != ReturnPath::Box
        || job.retract
            != (Retract {
                x: job.start.x,
                z: job.start.z,
            })
    {
        return Err(
            "G76 retracts to the start point's X and returns to its Z after every pass, and this job does not".into(),
        );
    }
    if job.entry != Entry::Direct {
        return Err("G76 has no entry ramp".into());
    }
    if job.lead.dlead != 0.0 || job.lead.starts != 1 {
        return Err("G76 cuts one start of a constant lead".into());
    }
    if !(1..=99).contains(&job.plan.finish_passes) {
        return Err("G76 has 1 to 99 finishing passes".into());
    }
    let (first, min_cut) = match job.plan.law {
        DepthLaw::Power {
            first,
            degression: 2.0,
            min_step,
        } => (first, min_step),
        _ => return Err("G76 cuts the constant-area law d·√n only".into()),
    };
    let a = job.tool_angle_deg;
    let angle = TOOL_ANGLES
        .iter()
        .copied()
        .find(|&t| f64::from(t) == a)
        .ok_or_else(|| format!("G76's tool angle is 80, 60, 55, 30, 29 or 0, not {a}"))?;
    let lead = job.lead.lead;
    let r = match job.exit {
        Exit::Straight => 0,
        Exit::PullOut { length, .. } => {
            let tenths = length / (0.1 * lead);
            if (tenths - tenths.round()).abs() > 1e-6 || tenths.round() > 99.0 {
                return Err("G76's chamfer is a whole number of tenths of a lead, 0 to 99".into());
            }
            tenths.round() as u32
        }
        Exit::ToRetract { .. } | Exit::FeedOut { .. } => {
            return Err(
                "G76's chamfer is a synchronised pull-out ending at the thread's end".into(),
            )
        }
    };
    let u = job.units;
    let inc = machine.resolution(u);
    let count = |mm: f64| format!("{}", (u.from_mm(mm) / inc).round() as i64);
    let nd = machine.decimals(u);
    let num = |mm: f64| crate::post::number(u.from_mm(mm), nd, false);
    // The full-depth pass runs from the start Z to the programmed end.
    let full_offset = job.infeed.axis(g.depth);
    let root_end = Pos::new(
        g.crest_end.x + g.side.infeed().x * g.depth,
        g.crest_end.z + full_offset,
    );
    let x_end = if machine.diameter_x {
        root_end.x * 2.0
    } else {
        root_end.x
    };
    let mut second = format!(
        "G76 X{} Z{}",
        crate::post::number(u.from_mm(x_end), nd, false),
        num(root_end.z)
    );
    if g.taper() != 0.0 {
        second.push_str(&format!(" R{}", num(g.taper())));
    }
    second.push_str(&format!(
        " P{} Q{} F{}",
        count(g.depth),
        count(first),
        crate::post::number(u.from_mm(lead), if u == Units::Inch { 5 } else { 4 }, false)
    ));
    Ok(vec![
        format!(
            "G76 P{:02}{r:02}{angle:02} Q{} R{}",
            job.plan.finish_passes,
            count(min_cut),
            num(job.plan.finish_allowance)
        ),
        second,
    ])
}

/// The G92 block that expresses a single-pass `job`, when G92 can.
/// `tail_words`: GSK writes the pull-out as J (short axis) and K (long axis) on the block; Fanuc
/// takes it from parameters 5130/5131.
pub fn native_g92(
    machine: &Machine,
    job: &Job,
    tail_words: bool,
) -> std::result::Result<Vec<String>, String> {
    let g = &job.geometry;
    let single = g.depth == 0.0
        && job.plan.finish_passes == 1
        && matches!(&job.plan.law, DepthLaw::Explicit { depths } if depths.is_empty());
    if !single {
        return Err("not a single pass".into());
    }
    if job.return_path != ReturnPath::Box || job.entry != Entry::Direct || job.lead.dlead != 0.0 {
        return Err("G92 has no entry ramp or variable lead".into());
    }
    let u = job.units;
    let nd = machine.decimals(u);
    let num = |mm: f64| crate::post::number(u.from_mm(mm), nd, false);
    let x = if machine.diameter_x {
        g.crest_end.x * 2.0
    } else {
        g.crest_end.x
    };
    let mut block = format!(
        "G92 X{} Z{}",
        crate::post::number(u.from_mm(x), nd, false),
        num(g.crest_end.z)
    );
    if g.taper() != 0.0 {
        block.push_str(&format!(" R{}", num(g.taper())));
    }
    if tail_words {
        match job.exit {
            Exit::Straight => block.push_str(" J0"),
            Exit::PullOut {
                start_before,
                length,
                outward,
            } if start_before == length => {
                block.push_str(&format!(" J{} K{}", num(outward), num(length)))
            }
            Exit::PullOut { .. } | Exit::ToRetract { .. } | Exit::FeedOut { .. } => {
                return Err("G92's tail-out is synchronised and ends at the thread's end".into())
            }
        }
        if job.lead.starts > 1 {
            block.push_str(&format!(" L{}", job.lead.starts));
        }
    } else if job.lead.starts != 1 {
        return Err("G92 cuts one start".into());
    }
    block.push_str(&format!(
        " F{}",
        crate::post::number(
            u.from_mm(job.lead.lead),
            if u == Units::Inch { 5 } else { 4 },
            false
        )
    ));
    Ok(vec![block])
}
