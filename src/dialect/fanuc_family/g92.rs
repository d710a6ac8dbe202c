//! The single-pass threading cycle G92 (G78 in system B, G21 in C): read (a block of axis words
//! repeats it while it is modal), and written back for a target.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::{Conventions, Line, Modal};
use crate::machine::Machine;
use crate::thread::{
    DepthLaw, Entry, Exit, FinishPosition, Geometry, Infeed, Job, Lead, PassPlan, Retract,
    ReturnPath, StartIndexing,
};
use crate::units::{Pos, Units};

use super::codes::{g_name, GCodes};
use super::family::*;
use super::start_angle;
use crate::dialect::only_words;

impl FanucFamily {
    pub(super) fn read_g92(
        &mut self,
        conv: &Conventions,
        line: &Line,
        modal: &mut Modal,
        span: Span,
        repeat: Option<G92Modal>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<Job> {
        let f = self.flavour;
        let name = g_name(self.codes.single);
        let (letters, format) = self.g92_words(conv);
        only_words(line, &letters, &format!("a {name} block"), &format)?;
        let lead = self.lead(conv, line, modal, span, &name)?;
        let a = thread_start(modal, span, &name)?;
        let mut end = modal.target(conv, line, a)?;
        let has_z = line.word(b'Z').or(line.word(b'W')).is_some();
        let has_x = line.word(b'X').or(line.word(b'U')).is_some();
        match repeat {
            Some(m) if !has_z => end.z = m.end_z,
            _ if !has_z || !has_x => {
                return Err(Diagnostic::error(
                    Code::MissingWord,
                    span,
                    format!("{name} needs the thread end point: X (or U) and Z (or W)"),
                ))
            }
            _ => {}
        }
        let taper = match line.word(f.taper_letter) {
            Some(r) => modal.length_mm(r),
            None => repeat.map_or(0.0, |m| m.taper),
        };
        let phase_deg = self.g92_start_angle(line, span, repeat, warnings)?;
        self.g92 = Some(G92Modal {
            end_z: end.z,
            taper,
            phase_deg,
            phase_line: line.number,
        });
        let res = modal.resolution();
        let (x_tol, length) = (res.x(), res.length());
        let travel_z = end.z - a.z;
        if length.is_zero(travel_z) {
            return Err(geometry(
                span,
                "the thread end Z equals the start point's Z: the thread has no length",
            ));
        }
        // The cut starts at the end X plus the taper; the pull-out rises toward the start point's X.
        let cut_start = Pos::new(end.x + taper, a.z);
        let side = side_of(a, end, x_tol, span)?;
        if !x_tol.gt((a.x - cut_start.x) * side.outward().x, 0.0) {
            let t = f.taper_letter as char;
            return Err(geometry(
                span,
                format!(
                    "{t}(i) {} puts the thread's start beyond the start point's X: when {t}'s sign differs from U's, |{t}| must not exceed |U/2|",
                    modal.units.from_mm(taper)
                ),
            ));
        }
        let (exit, starts) = if f.gsk_g92_words {
            self.gsk_tail(line, modal, lead)?
        } else {
            (self.chamfer(lead, length), 1)
        };
        self.check_exit(&exit, travel_z, modal.units, length, span)?;
        crate::dialect::lead_warning(
            lead,
            travel_z,
            modal.units,
            length,
            span,
            "check F",
            warnings,
        );
        Ok(Job {
            line: line.number,
            span,
            controller: f.controller,
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
                phase_deg,
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

    /// The single-pass cycle's words on this controller (E is read only to refuse it with its own
    /// message, except where it is the lead), and the hint that lists them.
    pub(super) fn g92_words(&self, conv: &Conventions) -> (Vec<u8>, String) {
        let f = self.flavour;
        let mut letters: Vec<u8> = b"GNXZUWFE".to_vec();
        letters.push(f.taper_letter);
        let mut format = format!("X(U) Z(W) {}(i) F(L)", f.taper_letter as char);
        if conv.tpi_letter != 0 {
            letters.push(conv.tpi_letter);
        }
        if f.gsk_g92_words {
            letters.extend_from_slice(b"JKL");
            format.push_str(" or I(threads per inch), J K L");
        }
        if f.start_angle {
            letters.push(b'Q');
            format.push_str(" Q(start angle)");
        }
        (letters, format)
    }

    /// The pass's start angle: its own Q, else 0 — Q is not modal, and a repeat without one after
    /// a pass that had one draws a warning (the usual slip on a second start).
    pub(super) fn g92_start_angle(
        &self,
        line: &Line,
        span: Span,
        repeat: Option<G92Modal>,
        warnings: &mut Vec<Diagnostic>,
    ) -> Result<f64> {
        if let Some(q) = line.word(b'Q').filter(|_| self.flavour.start_angle) {
            return start_angle::read(q);
        }
        if let Some(m) = repeat.filter(|m| m.phase_deg != 0.0) {
            warnings.push(
                Diagnostic::warning(
                    Code::Suspicious,
                    span,
                    format!(
                        "this pass starts at 0°: the start angle Q{} of line {} is not modal",
                        crate::post::start_angle_count(m.phase_deg),
                        m.phase_line
                    ),
                )
                .with_hint("repeat Q on every pass of a start other than the first"),
            );
        }
        Ok(0.0)
    }

    /// GSK's G92 tail-out J (short axis) and K (long axis) in the block's own words, and L starts
    /// (threading-notes §c.1–c.2): J alone means K = J, K alone means J = K, J = 0 means none;
    /// neither: parameters 5130/5131.
    pub(super) fn gsk_tail(&self, line: &Line, modal: &Modal, lead: f64) -> Result<(Exit, u32)> {
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
        let length = modal.resolution().length();
        let exit = match (j, k) {
            (None, None) => self.chamfer(lead, length),
            (Some(j), None) => pull_out(j, j, length),
            (Some(j), Some(k)) if length.is_zero(k) => pull_out(j, j, length),
            (None, Some(k)) => pull_out(k, k, length),
            (Some(j), Some(k)) => pull_out(j, k, length),
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
}

/// The candidates of a control with a single-pass and a multiple-pass cycle, the one that fits the
/// job's number of passes first (so that its reason is the one given when none reads back).
pub fn single_or_multiple(
    single: std::result::Result<Vec<String>, String>,
    multiple: Vec<std::result::Result<Vec<String>, String>>,
    job: &Job,
) -> Vec<std::result::Result<Vec<String>, String>> {
    if is_single_pass(job) {
        std::iter::once(single).chain(multiple).collect()
    } else {
        multiple
            .into_iter()
            .chain(std::iter::once(single))
            .collect()
    }
}

/// One pass at the crest line: what a single-pass cycle (G92) cuts.
pub fn is_single_pass(job: &Job) -> bool {
    job.geometry.depth == 0.0
        && job.plan.finish_passes == 1
        && matches!(&job.plan.law, DepthLaw::Explicit { depths } if depths.is_empty())
}

/// The G92 block (G78 in system B, G21 in C) that expresses a single-pass `job`, when G92 can.
/// GSK writes the pull-out as J (short axis) and K (long axis) on the block (`gsk_g92_words`);
/// the others take it from their parameters. The taper and start-angle words are the flavour's.
pub fn native_g92(
    machine: &Machine,
    codes: &GCodes,
    flavour: &Flavour,
    job: &Job,
) -> std::result::Result<Vec<String>, String> {
    let name = g_name(codes.single);
    let tail_words = flavour.gsk_g92_words;
    let g = &job.geometry;
    if !is_single_pass(job) {
        return Err(format!(
            "{name} cuts one pass, and this job cuts {}",
            crate::text::count(job.passes().map_or(0, |p| p.len()), "pass", "passes")
        ));
    }
    if job.return_path != ReturnPath::Box || job.entry != Entry::Direct || job.lead.dlead != 0.0 {
        return Err(format!("{name} has no entry ramp or variable lead"));
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
        "{name} X{} Z{}",
        crate::post::number(u.from_mm(x), nd, false),
        num(g.crest_end.z)
    );
    if g.taper() != 0.0 {
        block.push_str(&format!(
            " {}{}",
            flavour.taper_letter as char,
            num(g.taper())
        ));
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
                return Err(format!(
                    "{name}'s tail-out is synchronised and ends at the thread's end"
                ))
            }
        }
        if job.lead.starts > 1 {
            if job.lead.indexing != StartIndexing::Shift {
                return Err(format!(
                    "{name}'s L reaches further starts by a shift along Z, and this job reaches them by the spindle angle, each start whole"
                ));
            }
            block.push_str(&format!(" L{}", job.lead.starts));
        }
    } else if job.lead.starts != 1 {
        return Err(format!("{name} cuts one start (a start angle Q shifts it)"));
    }
    if job.lead.phase_deg != 0.0 && !flavour.start_angle {
        return Err(format!("{name} has no start angle on this controller"));
    }
    block.push_str(&format!(
        " F{}",
        crate::post::number(
            u.from_mm(job.lead.lead),
            if u == Units::Inch { 5 } else { 4 },
            false
        )
    ));
    if job.lead.phase_deg != 0.0 {
        block.push_str(&format!(
            " Q{}",
            crate::post::start_angle_count(job.lead.phase_deg)
        ));
    }
    Ok(vec![block])
}
