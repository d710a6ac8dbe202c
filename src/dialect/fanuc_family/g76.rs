//! The multiple threading cycle G76 (G78 in system C) in Fanuc's standard format: its two blocks
//! read (the first rewrites the parameters, the second is the cycle), and written back for a target.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::modal::Vocabulary;
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::Machine;
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan,
    Retract, ReturnPath, Side, StartIndexing,
};
use crate::units::{Pos, Tolerance, Units};

use super::codes::{g_name, GCodes};
use super::family::*;
use crate::dialect::only_words;

impl FanucFamily {
    pub(super) fn read_g76_first(&mut self, line: &Line, modal: &Modal) -> Result<()> {
        let name = self.multiple_name();
        only_words(
            line,
            b"GNPQR",
            &format!("the first {name} block"),
            "P(m)(r)(a) Q(Δdmin) R(d)",
        )?;
        let mut p = self.params;
        if let Some(w) = line.word(b'P') {
            let (m, r, a) = unpack_p(line, w, &name)?;
            p.finish_passes = m;
            p.chamfer_leads = f64::from(r) * 0.1;
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

    pub(super) fn read_g76_second(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        g76: Span,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        let name = self.multiple_name();
        let letters: &[u8] = if conv.tpi_letter == b'I' {
            b"GNXZUWRPQFIE"
        } else {
            b"GNXZUWRPQFE"
        };
        only_words(
            line,
            letters,
            &format!("the second {name} block"),
            "X(U) Z(W) R(i) P(k) Q(Δd) F(L)",
        )?;
        let (height, first) = self.second_block_depths(line, modal, g76, &name)?;
        let res = modal.resolution();
        let (x_tol, length) = (res.x(), res.length());
        let taper = line.word(b'R').map_or(0.0, |r| modal.length_mm(r));
        let lead = self.lead(conv, line, modal, g76, &name)?;
        let (a, end) = self.endpoints(conv, line, modal, g76, &name)?;
        let p = self.params;
        if !length.lt(p.allowance_mm, height) {
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
        let (side, crest_c, travel_z) = thread_place(a, end, taper, height, x_tol, length, g76)?;
        let infeed = single_edge_infeed(p.tool_angle, travel_z);
        let full_offset = infeed.axis(height);
        let crest_start = Pos::new(crest_c.x, a.z - full_offset);
        let crest_end = Pos::new(crest_c.x - taper, end.z - full_offset);
        let exit = self.chamfer(lead, length);
        self.check_exit(&exit, travel_z, modal.units, length, g76)?;
        crate::dialect::lead_warning(
            lead,
            travel_z,
            modal.units,
            length,
            g76,
            "check F",
            warnings,
        );
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

    /// The second block's P(k) and Q(Δd): the thread height and the depth of the first cut (mm,
    /// radius), each required (PS0062 when missing) and greater than 0.
    fn second_block_depths(
        &self,
        line: &Line,
        modal: &Modal,
        g76: Span,
        name: &str,
    ) -> Result<(f64, f64)> {
        let height = match line.word(b'P') {
            Some(w) => self.increments(modal, w, "P(k)", "the thread height (radius)")?,
            None => {
                return Err(alarm_missing(
                    g76,
                    name,
                    "P(k)",
                    "the thread height (radius)",
                ))
            }
        };
        let first = match line.word(b'Q') {
            Some(w) => self.increments(modal, w, "Q(Δd)", "the depth of the first cut (radius)")?,
            None => {
                return Err(alarm_missing(
                    g76,
                    name,
                    "Q(Δd)",
                    "the depth of the first cut (radius)",
                ))
            }
        };
        let length = modal.resolution().length();
        for (w, v, word) in [
            (line.word(b'P'), height, "P(k)"),
            (line.word(b'Q'), first, "Q(Δd)"),
        ] {
            if !length.gt(v, 0.0) {
                return Err(Diagnostic::error(
                    Code::OutOfRange,
                    w.map_or(g76, |w| w.span),
                    format!("{name} alarm (PS0062): {word} must be greater than 0"),
                ));
            }
        }
        Ok((height, first))
    }
}

/// Where the thread lies, from the start point `a`, the end point and the taper R(i): its side
/// (the start point against C, the root at the thread's start: X of the end point plus the taper,
/// Z of the start point), the crest above C, and the Z travel; a thread without length, a taper
/// steeper than 45° and a start point inside the thread are refused.
fn thread_place(
    a: Pos,
    end: Pos,
    taper: f64,
    height: f64,
    x_tol: Tolerance,
    length: Tolerance,
    g76: Span,
) -> Result<(Side, Pos, f64)> {
    // C: the root at the thread start (X of the end point plus the taper, Z of the start point).
    let c = Pos::new(end.x + taper, a.z);
    let side = side_of(a, c, x_tol, g76)?;
    let travel_z = end.z - a.z;
    if length.is_zero(travel_z) {
        return Err(geometry(
            g76,
            "the thread end Z equals the start point's Z: the thread has no length",
        ));
    }
    if length.gt(taper.abs(), travel_z.abs()) {
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
    // A start point within the resolution of the crest is on the crest.
    if x_tol.lt((a.x - crest_c.x) * side.outward().x, 0.0) {
        return Err(geometry(
        g76,
        "the start point lies inside the thread (between crest and root): the return along Z would cut through it",
        )
        .with_hint("start the cycle from a point clear of the crest"));
    }
    Ok((side, crest_c, travel_z))
}

/// The infeed of a tool of included angle `tool_angle` (degrees; 0: radial). Single-edge infeed:
/// deeper passes move in the cutting direction along the flank at a/2, so the leading edge cuts
/// and the trailing edge follows the groove; the full-depth pass runs from the start point's Z to
/// the programmed end Z.
fn single_edge_infeed(tool_angle: u32, travel_z: f64) -> Infeed {
    let flank = if travel_z < 0.0 {
        Flank::Right
    } else {
        Flank::Left
    };
    if tool_angle == 0 {
        Infeed::Radial
    } else {
        Infeed::Flank {
            flank,
            angle_deg: f64::from(tool_angle) / 2.0,
        }
    }
}

/// Tool-tip angles the first G76 block accepts (Fanuc: 80, 60, 55, 30, 29 and 0 degrees).
pub const TOOL_ANGLES: [u32; 6] = [80, 60, 55, 30, 29, 0];

/// A one-block G76's words (K thread height, D first cut, A tool angle: Fanuc's FS15 program
/// format, Haas) on a two-block control: the control's alarm at the word, the form it reads, and
/// the built-in controllers whose vocabulary has the code with the block's words
/// ([`crate::dialect::others_with`]: every controller that declares a one-block G76 is named).
pub(super) fn one_block_words_on_two_block(
    line: &Line,
    vocabulary: &Vocabulary,
    code: u16,
    name: &str,
) -> Result<()> {
    match line
        .words
        .iter()
        .find(|w| matches!(w.letter, b'K' | b'D' | b'A'))
    {
        Some(w) => Err(crate::dialect::foreign_form(
            line,
            w.span,
            code,
            vocabulary,
            format!(
                "{} is a word of the one-block {name} (X Z I K D F A P Q: Fanuc's FS15 program format, Haas), and {} reads {name} in two blocks",
                w.letter as char, vocabulary.controller
            ),
            &format!("{name} P(m)(r)(a) Q(Δdmin) R(d), then {name} X(U) Z(W) R(i) P(k) Q(Δd) F(L)"),
        )),
        None => Ok(()),
    }
}

/// P(m)(r)(a): three two-digit fields, leading zeros may be omitted (`P21060` is m 02, r 10, a 60).
pub(super) fn unpack_p(line: &Line, p: &Word, name: &str) -> Result<(u32, u32, u32)> {
    let packed = crate::dialect::packed_p(
        line,
        p,
        name,
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

/// The two G76 blocks (G78 in system C) that may express `job`, one per choice of the words the
/// job leaves open (the read-back check decides): the tool angle `a` is chosen for the infeed the
/// job makes, not copied from the tool the job names for its chip areas — a radial infeed is `a`
/// 0 whatever the tool, a single-flank infeed at θ is the angle 2θ of the list. `params` are the
/// target's (the chamfer's angle is its parameter 5131, which no block rewrites).
pub fn g76_candidates(
    machine: &Machine,
    codes: &GCodes,
    params: &ThreadParameters,
    job: &Job,
) -> Vec<std::result::Result<Vec<String>, String>> {
    match g76_words(codes, params, job) {
        Ok((angles, r)) => angles
            .into_iter()
            .map(|a| Ok(g76_text(machine, codes, job, a, r)))
            .collect(),
        Err(why) => vec![Err(why)],
    }
}

/// The first of [`g76_candidates`].
pub fn native_g76(
    machine: &Machine,
    codes: &GCodes,
    params: &ThreadParameters,
    job: &Job,
) -> std::result::Result<Vec<String>, String> {
    g76_candidates(machine, codes, params, job).remove(0)
}

/// The tool angles whose infeed is the job's, and the chamfer's r; or the property of the job the
/// cycle cannot express.
pub(super) fn g76_words(
    codes: &GCodes,
    params: &ThreadParameters,
    job: &Job,
) -> std::result::Result<(Vec<u32>, u32), String> {
    let name = g_name(codes.multiple);
    let g = &job.geometry;
    if g.side.is_face() {
        return Err(format!("{name} threads along Z, and this is a face thread"));
    }
    if job.lead.phase_deg != 0.0
        || (job.lead.starts > 1 && job.lead.indexing == StartIndexing::Angle)
    {
        return Err(format!(
            "the two-block {name} has no start angle: its Q is the first depth"
        ));
    }
    crate::dialect::one_block::box_return_direct_entry(job, &name)?;
    if job.lead.dlead != 0.0 || job.lead.starts != 1 {
        return Err(format!("{name} cuts one start of a constant lead"));
    }
    if !(1..=99).contains(&job.plan.finish_passes) {
        return Err(format!(
            "{name} cuts 1 to 99 finishing passes, and this job cuts {}",
            crate::text::count(
                job.plan.finish_passes as usize,
                "finishing pass",
                "finishing passes"
            )
        ));
    }
    if !matches!(job.plan.law, DepthLaw::Power { degression, .. } if degression == 2.0) {
        return Err(format!(
            "{name} cuts the constant-area law d·√n (each cut at least Δdmin), and this job's depths follow another law"
        ));
    }
    let lead = job.lead.lead;
    let r = match job.exit {
        Exit::Straight => 0,
        Exit::PullOut {
            start_before,
            length,
            outward,
        } if start_before == length => {
            let tenths = length / (0.1 * lead);
            if (tenths - tenths.round()).abs() > 1e-6 || tenths.round() > 99.0 {
                return Err(format!(
                    "{name}'s chamfer is a whole number of tenths of a lead, 0 to 99, and this job's pull-out is {} leads long",
                    crate::post::number(length / lead, 4, false)
                ));
            }
            let angle = tan_deg(params.chamfer_angle_deg);
            if (outward - length * angle).abs() > 1e-6 {
                return Err(format!(
                    "{name}'s chamfer runs at parameter 5131's angle ({}° from Z), and this job's pull-out at {}°",
                    params.chamfer_angle_deg,
                    crate::post::number(outward.atan2(length).to_degrees(), 3, false)
                ));
            }
            tenths.round() as u32
        }
        Exit::PullOut { .. } | Exit::ToRetract { .. } | Exit::FeedOut { .. } => {
            return Err(format!(
                "{name}'s chamfer is a synchronised pull-out ending at the thread's end, and this job's exit is not"
            ))
        }
    };
    let leading = if g.side.along(g.travel()) < 0.0 {
        Flank::Right
    } else {
        Flank::Left
    };
    let angles: Vec<u32> = match job.infeed {
        Infeed::Radial => vec![0],
        Infeed::Flank { flank, angle_deg } if flank == leading => {
            let fits: Vec<u32> = TOOL_ANGLES
                .iter()
                .copied()
                .filter(|&a| (f64::from(a) / 2.0 - angle_deg).abs() < 1e-9)
                .collect();
            if fits.is_empty() {
                return Err(format!(
                    "{name} infeeds along the flank at half its tool angle a (80, 60, 55, 30, 29 or 0), and this job at {}°",
                    crate::post::number(angle_deg, 4, false)
                ));
            }
            if job.plan.finish_allowance > 0.0 && job.finish_at == FinishPosition::LastRough {
                return Err(format!(
                    "{name} cuts its finishing passes at the full-depth flank position, and this job at the last rough pass's"
                ));
            }
            fits
        }
        Infeed::Flank { .. } => {
            return Err(format!(
                "{name} infeeds along the leading flank (the tool moves toward the thread's end as it goes deeper), and this job along the trailing one"
            ))
        }
        Infeed::Alternating { .. } => {
            return Err(format!(
                "the two-block {name} infeeds along one flank, and this job alternates between flanks"
            ))
        }
    };
    Ok((angles, r))
}

/// The two blocks with tool angle `angle` and chamfer `r`.
pub(super) fn g76_text(
    machine: &Machine,
    codes: &GCodes,
    job: &Job,
    angle: u32,
    r: u32,
) -> Vec<String> {
    let name = g_name(codes.multiple);
    let g = &job.geometry;
    let (first, min_cut) = match job.plan.law {
        DepthLaw::Power {
            first, min_step, ..
        } => (first, min_step),
        _ => (0.0, 0.0),
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
        "{name} X{} Z{}",
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
        crate::post::number(
            u.from_mm(job.lead.lead),
            if u == Units::Inch { 5 } else { 4 },
            false
        )
    ));
    vec![
        format!(
            "{name} P{:02}{r:02}{angle:02} Q{} R{}",
            job.plan.finish_passes,
            count(min_cut),
            num(job.plan.finish_allowance)
        ),
        second,
    ]
}
