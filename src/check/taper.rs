//! `check --thread` for a taper pipe thread (NPT, ISO 7-1 R and Rc): judged at its gauge plane
//! (docs/simulation.md, "Taper threads at their gauge plane"), by the standard's own judgement
//! ([`judge_taper`]).
//!
//! * **What the program cuts**: the pitch diameter measured at the thread's start (as for a
//!   parallel thread, [`super::measure::measure`]) carried along the cycle's crest line — the
//!   groove's section is the same all along a lathe taper, only shifted — so the pitch diameter
//!   at any Z, and the taper (its change per length into the part).
//! * **The reference face**: the gauge plane lies at a distance from the part's end (an external
//!   thread's small end, an internal thread's opening): `--stock-start` when given, else the face
//!   `check` assumed (Z0), else not known — then only the taper is judged, and a note says why.
//! * **Facts and assumptions**: the taper follows from the program alone (an error when outside).
//!   Where the gauge stands depends on the face and on the tool's tip: an error only when both were
//!   given, else a warning naming what was assumed. A thread that ends before its gauge plane is
//!   as sure as its face; one shorter than the standard's effective thread is a warning.
//! * **Resolution**: a taper within one least increment on the diameter over the cycle's travel of
//!   the standard's 1:16 is the standard's (the program cannot write it closer), and a pitch
//!   diameter within one increment of a limit is at the limit.

use crate::diag::{Code, Diagnostic};
use crate::thread::standard::gauge::Taper;
use crate::thread::standard::{judge_taper, Surface, TaperCheck, TaperCut, TaperJudgement};
use crate::thread::Exit;
use crate::threads::{Origin, Thread};
use crate::units::Units;

use super::measure::{Judging, Measured, Target};
use super::{length, Note};

/// Where the gauge stands, for the rest of the judging: the measurements move there.
pub struct Gauge {
    /// The change of every diameter from the thread's start to the gauge plane (mm).
    pub shift: f64,
    /// The part's face was given (`--stock-start`), not assumed.
    pub face_given: bool,
    /// What the note says of the gauge plane.
    pub summary: String,
}

/// The cut thread's pitch line: its diameter at `z0`, its change per mm of Z.
struct Lines {
    z0: f64,
    pd0: f64,
    per_z: f64,
}

impl Lines {
    fn pd_at(&self, z: f64) -> f64 {
        self.pd0 + self.per_z * (z - self.z0)
    }
}

/// Judges `t`, whose target is a taper thread with gauge data `taper`, at its gauge plane.
/// Findings go to `out`; `None` when the gauge plane cannot be placed (the face is not known, or
/// the groove has no pitch diameter), after a note or a finding that says so.
pub fn judge(
    t: &Thread,
    j: &Judging,
    taper: &Taper,
    side: Surface,
    m: &Measured,
    out: &mut Vec<Diagnostic>,
    notes: &mut Vec<Note>,
) -> Option<Gauge> {
    let target = j.target;
    let job = &t.job;
    let g = &job.geometry;
    let units = target.thread.units;
    let show = |mm: f64| length(units, mm);
    let travel = g.crest_end.z - g.crest_start.z;
    if travel.abs() < 1e-9 {
        return None;
    }
    // Into the part is the way the thread runs.
    let into = travel.signum();
    let per_z = 2.0 * (g.crest_end.x - g.crest_start.x) / travel;
    // The taper as the standard reckons it (diameter per length into the part), at the standard's
    // value when the program cannot write it closer.
    let nominal = match side {
        Surface::External => taper.diameter_per_length,
        Surface::Internal => -taper.diameter_per_length,
    };
    let cut_taper = per_z * into;
    let snap = 2.0 * j.resolution / travel.abs();
    let cut_taper = if (cut_taper - nominal).abs() <= snap + 1e-12 {
        nominal
    } else {
        cut_taper
    };
    let Some(pd0) = m.pitch_diameter else {
        // The groove is nowhere half a pitch wide: the parallel path's finding says so.
        judge_taper_only(t, j, cut_taper, out);
        return None;
    };
    // The pitch diameter is measured at the groove's centre, which a flank infeed moves along Z
    // from the crest line's start (offsets are +Z).
    let lines = Lines {
        z0: g.crest_start.z + m.pitch_centre,
        pd0,
        per_z,
    };
    let Some(face) = j.face else {
        notes.push(Note::new(
            job.span,
            format!(
                "the part's face is not known: {} is not judged at its gauge plane (--stock-start names the face the thread enters)",
                target.name
            ),
        ));
        judge_taper_only(t, j, cut_taper, out);
        return None;
    };
    // The full-form thread ends where a cycle's pull-out begins.
    let end = match (job.exit, &t.origin) {
        (Exit::PullOut { start_before, .. }, Origin::Cycle) => {
            g.crest_end.z - into * start_before.max(0.0)
        }
        _ => g.crest_end.z,
    };
    let cut = TaperCut {
        side,
        face_z: face.z,
        into_part: into,
        pitch_diameter_at_face: lines.pd_at(face.z),
        taper: cut_taper,
        length: ((end - face.z) * into).max(0.0),
        pitch: target.thread.pitch,
        resolution: j.resolution,
    };
    let judged = match judge_taper(target.thread, &cut) {
        Ok(judged) => judged,
        Err(e) => {
            out.push(Diagnostic {
                span: job.span,
                ..e
            });
            return None;
        }
    };
    let assumed = assumptions(face.given, j.tip.is_some());
    for f in &judged.findings {
        let fact = match f.check {
            TaperCheck::Taper => true,
            TaperCheck::PitchDiameter => assumed.is_empty(),
            TaperCheck::Length => face.given && f.error,
            // The lead is judged with the program's resolution by the parallel path.
            TaperCheck::Pitch => continue,
        };
        let message = message(f.check, &judged, &cut, taper, target, units, f.error);
        out.push(finding(fact, job.span, message, &assumed, f.check));
    }
    let face_said = if face.given {
        format!("the face at Z{}", length(job.units, face.z))
    } else {
        format!("the face at Z{}, assumed", length(job.units, face.z))
    };
    let summary = format!(
        "at its gauge plane Z{} ({} from {face_said}): pitch diameter {} (basic {}), the gauge {:+.2} turns ({}{} {}) from its basic position (±{:.2} allowed), taper {:.5} on diameter",
        length(job.units, judged.gauge_plane_z),
        show(taper.gauge_plane_from_face(side)),
        show(judged.pitch_diameter),
        show(judged.basic),
        judged.standoff_turns,
        if judged.standoff_turns < 0.0 { "-" } else { "+" },
        show((judged.standoff_turns * target.thread.pitch).abs()),
        target.thread.units.name(),
        judged.allowed_turns,
        judged.taper.abs(),
    );
    Some(Gauge {
        shift: lines.pd_at(judged.gauge_plane_z) - pd0,
        face_given: face.given,
        summary,
    })
}

/// The taper alone, when the gauge plane cannot be placed: a fact either way.
fn judge_taper_only(t: &Thread, j: &Judging, cut_taper: f64, out: &mut Vec<Diagnostic>) {
    let target = j.target;
    let g = &t.job.geometry;
    let cut = TaperCut {
        side: target.side,
        face_z: g.crest_start.z,
        into_part: (g.crest_end.z - g.crest_start.z).signum(),
        pitch_diameter_at_face: target.limits.pitch.min.unwrap_or(0.0),
        taper: cut_taper,
        length: f64::MAX / 4.0,
        pitch: target.thread.pitch,
        resolution: j.resolution,
    };
    let Some(taper) = target.thread.taper else {
        return;
    };
    if let Ok(judged) = judge_taper(target.thread, &cut) {
        for f in judged
            .findings
            .iter()
            .filter(|f| f.check == TaperCheck::Taper)
        {
            let message = message(
                f.check,
                &judged,
                &cut,
                &taper,
                target,
                target.thread.units,
                f.error,
            );
            out.push(finding(true, t.job.span, message, "", f.check));
        }
    }
}

/// What a finding at the gauge plane rests on that was assumed, for its message.
fn assumptions(face_given: bool, tip_given: bool) -> String {
    let mut said = Vec::new();
    if !face_given {
        said.push("the part's face at Z0 (--stock-start gives it)");
    }
    if !tip_given {
        said.push(
            "the tool's tip of the standard's root form (--nose-radius or --tip-flat give it)",
        );
    }
    said.join("; ")
}

/// An error for a fact; for an assumption a warning that names it.
fn finding(
    fact: bool,
    span: crate::diag::Span,
    message: String,
    assumed: &str,
    check: TaperCheck,
) -> Diagnostic {
    let hint = match check {
        TaperCheck::PitchDiameter => "cut deeper for a ring gauge that stops short (external) or a plug gauge that goes too far (internal); shallower for the other way",
        TaperCheck::Taper => "the cycle's taper word (R, I, …) must give 1:16 on diameter over its Z travel: `threadcut thread NAME --controller C` computes it",
        TaperCheck::Length | TaperCheck::Pitch => "check the thread's end Z and the part's face",
    };
    if fact {
        Diagnostic::error(Code::OutOfClass, span, message).with_hint(hint)
    } else {
        let message = if assumed.is_empty() {
            message
        } else {
            format!("{message} (assumed: {assumed})")
        };
        Diagnostic::warning(Code::OutOfClassAssumed, span, message).with_hint(hint)
    }
}

/// A finding's message in the standard's units.
fn message(
    check: TaperCheck,
    judged: &TaperJudgement,
    cut: &TaperCut,
    taper: &Taper,
    target: &Target,
    units: Units,
    error: bool,
) -> String {
    let show = |mm: f64| length(units, mm);
    let unit = units.name();
    let name = &target.name;
    match check {
        TaperCheck::PitchDiameter => {
            let above = judged.pitch_diameter > judged.basic;
            let limit = if above {
                judged.limits.max
            } else {
                judged.limits.min
            };
            format!(
                "pitch diameter {} {unit} at the gauge plane {} the {} {} for {name}: the gauge would stand {:+.2} turns from its basic position (±{:.2} allowed)",
                show(judged.pitch_diameter),
                if above { "is above" } else { "is below" },
                if above { "maximum" } else { "minimum" },
                limit.map_or_else(String::new, show),
                judged.standoff_turns,
                judged.allowed_turns
            )
        }
        TaperCheck::Taper => format!(
            "taper {:.5} on diameter per unit length for {name}, whose taper is {:.5} (1:16){}",
            judged.taper.abs(),
            taper.diameter_per_length,
            match taper.taper_tolerance {
                Some((below, above)) => format!(
                    ", {:.5} to {:.5} allowed",
                    taper.diameter_per_length - below,
                    taper.diameter_per_length + above
                ),
                None => String::new(),
            }
        ),
        TaperCheck::Length if error => format!(
            "the full-form thread is {} {unit} long and ends before the gauge plane of {name}, {} {unit} from the face",
            show(cut.length),
            show(taper.gauge_plane_from_face(cut.side))
        ),
        TaperCheck::Length => format!(
            "the full-form thread is {} {unit} long, shorter than the effective thread of {name} ({} {unit})",
            show(cut.length),
            show(taper.effective_length)
        ),
        TaperCheck::Pitch => format!("the pitch is not the pitch of {name}"),
    }
}
