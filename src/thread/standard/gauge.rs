//! Taper pipe threads at their gauge plane: the plane where the standard fixes the pitch
//! diameter, how far it lies from the part's end, how far it may move, and the judgement of a cut
//! thread there.
//!
//! * ASME B1.20.1 (NPT): the gauge plane of an external thread lies L1 from its small end (the
//!   pipe's end), where the pitch diameter is E1; an internal thread has E1 at its opening (the L1
//!   plug gauge enters flush). Both are gauged "±1 turn" (§3.2, Table 2): the gauge plane may lie
//!   one pitch either way, which on a 1:16 taper is ±P/16 on the pitch diameter.
//! * ISO 7-1: the gauge diameter lies at the gauge length from the small end of R (tolerance
//!   ±T1/2) and half a pitch inside the opening of Rc (±T2/2; ISO 7-1:1994, 3.3 note 4 as quoted
//!   in issue 27; JIS B 0203:1999, which otherwise adopts ISO 7-1 unchanged, states that it keeps
//!   its own position, at the face, docs/standard-threads.md); Rp is parallel with a diameter
//!   tolerance.
//!
//! [`judge_taper`] takes what a program cuts (the pitch-diameter line along Z and where the part's
//! reference face is) and says where the gauge would stand.

use serde::Serialize;

use super::{Range, StandardThread, Surface};
use crate::diag::{Code, Diagnostic, Result, Span};

/// The taper and the gauge plane of a taper thread (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Taper {
    /// Change of diameter per unit of length: 1/16 for NPT and ISO 7-1.
    pub diameter_per_length: f64,
    /// Distance of the external thread's gauge plane from its small end: L1 (NPT), the basic gauge
    /// length (ISO 7-1).
    pub gauge_length: f64,
    /// How far the gauge plane may lie from its basic position (±, mm), external and internal.
    pub external_position_tolerance: f64,
    pub internal_position_tolerance: f64,
    /// Distance of the internal thread's gauge plane inside its opening: 0 (NPT: the L1 plug
    /// gauge enters flush), half a pitch (ISO 7-1 Rc).
    pub internal_gauge_plane: f64,
    /// Pitch diameter at the gauge plane: E1 (NPT), d2 at the gauge plane (ISO 7-1).
    pub gauge_pitch_diameter: f64,
    /// Major diameter at the gauge plane (the ISO 7-1 "gauge diameter"; NPT: of the sharp V less
    /// the mean truncation, informative).
    pub gauge_major_diameter: f64,
    /// Pitch diameter at the external thread's small end: E0 (NPT); d2 − gauge length/16 (ISO).
    pub small_end_pitch_diameter: f64,
    /// Length of the effective (NPT L2) or useful (ISO 7-1, for the basic gauge length) external
    /// thread, from the small end.
    pub effective_length: f64,
    /// NPT: pitch diameter at L2 (E2).
    pub effective_end_pitch_diameter: f64,
    /// Length of the vanish (washout) thread beyond the effective length (NPT V = 3.47P); 0 when
    /// the standard gives none.
    pub vanish_length: f64,
    /// Wrench make-up length beyond hand-tight engagement (NPT L3 = 3P); 0 when none is given.
    pub wrench_makeup: f64,
    /// Overall length of the external thread, effective plus vanish thread (NPT L4 = L2 + V,
    /// ASME B1.20.1 Table 2); 0 when the standard gives none.
    pub overall_length: f64,
    /// The tolerance on the taper itself, in diameter per length: (below, above) the basic
    /// 1/16 (NPT: −1/16 and +1/8 inch per foot); `None` when the standard leaves it to gauging.
    pub taper_tolerance: Option<(f64, f64)>,
}

impl Taper {
    /// The gauge plane's distance from the part's reference face, into the part: the small end of
    /// an external thread (L1 / gauge length), the opening of an internal one
    /// ([`Taper::internal_gauge_plane`]: 0 for NPT, P/2 for ISO 7-1).
    pub fn gauge_plane_from_face(&self, side: Surface) -> f64 {
        match side {
            Surface::External => self.gauge_length,
            Surface::Internal => self.internal_gauge_plane,
        }
    }

    /// The gauge plane's position tolerance on a side (±, mm).
    pub fn position_tolerance(&self, side: Surface) -> f64 {
        match side {
            Surface::External => self.external_position_tolerance,
            Surface::Internal => self.internal_position_tolerance,
        }
    }

    /// The pitch diameter's tolerance at the gauge plane (±, diameter, mm): the position
    /// tolerance times the taper.
    pub fn pitch_diameter_tolerance(&self, side: Surface) -> f64 {
        self.position_tolerance(side) * self.diameter_per_length
    }

    /// Basic pitch diameter at `distance` from the face into the part: it grows from an external
    /// thread's small end and shrinks from an internal thread's opening.
    pub fn pitch_diameter_at(&self, side: Surface, distance: f64) -> f64 {
        let from_gauge = distance - self.gauge_plane_from_face(side);
        match side {
            Surface::External => self.gauge_pitch_diameter + from_gauge * self.diameter_per_length,
            Surface::Internal => self.gauge_pitch_diameter - from_gauge * self.diameter_per_length,
        }
    }
}

/// What a program cuts, for [`judge_taper`] (mm, Z along the lathe's axis).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TaperCut {
    pub side: Surface,
    /// Z of the reference face: the small end of an external thread (the pipe's end), the opening
    /// of an internal one.
    pub face_z: f64,
    /// Which way along Z the thread runs into the part from the face: +1 or −1.
    pub into_part: f64,
    /// Pitch diameter of the cut thread at the face.
    pub pitch_diameter_at_face: f64,
    /// Change of the cut pitch diameter per mm into the part (an external taper grows: +1/16; an
    /// internal one shrinks: −1/16).
    pub taper: f64,
    /// Length of full-form thread from the face into the part.
    pub length: f64,
    /// The cut thread's pitch (lead of one start).
    pub pitch: f64,
    /// The program's least increment on a diameter (mm): a pitch diameter within it of a limit is
    /// at the limit (0: judged exactly).
    pub resolution: f64,
}

/// What a finding of [`judge_taper`] is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TaperCheck {
    /// The pitch diameter at the gauge plane (where the gauge stands).
    PitchDiameter,
    /// The taper itself.
    Taper,
    /// The pitch.
    Pitch,
    /// The thread's length against the gauge plane and the effective thread.
    Length,
}

/// One finding of [`judge_taper`]; `error` when the thread is outside the standard.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TaperFinding {
    pub error: bool,
    pub check: TaperCheck,
    pub message: String,
}

/// Where the gauge stands on a cut taper thread.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TaperJudgement {
    /// Z of the gauge plane (basic position).
    pub gauge_plane_z: f64,
    /// The cut pitch diameter there, and the standard's limits there.
    pub pitch_diameter: f64,
    pub basic: f64,
    pub limits: Range,
    /// How far from its basic position the gauge would stand (turns; positive: an oversize
    /// thread, the ring gauge stops short of / the plug gauge goes past its basic step).
    pub standoff_turns: f64,
    /// The standard's ± limit on the standoff (turns).
    pub allowed_turns: f64,
    /// The cut taper (diameter per length, signed into the part as the standard's).
    pub taper: f64,
    pub findings: Vec<TaperFinding>,
}

impl TaperJudgement {
    pub fn ok(&self) -> bool {
        self.findings.iter().all(|f| !f.error)
    }
}

/// Judges a cut taper thread at its gauge plane: its pitch diameter there against the standard's
/// (±1 turn for NPT, ±T1/2 or ±T2/2 for ISO 7-1), its taper (NPT's taper tolerance), its pitch,
/// and whether the thread reaches past the gauge plane and is as long as the standard's effective
/// (useful) thread. Errors: a thread that is not a taper standard, or a `cut` that is not finite.
pub fn judge_taper(t: &StandardThread, cut: &TaperCut) -> Result<TaperJudgement> {
    let Some(taper) = t.taper else {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            Span::default(),
            format!("{} is not a taper thread: it has no gauge plane", t.name),
        ));
    };
    let finite = [
        cut.face_z,
        cut.into_part,
        cut.pitch_diameter_at_face,
        cut.taper,
        cut.length,
        cut.pitch,
    ]
    .iter()
    .all(|v| v.is_finite());
    if !finite || cut.into_part.abs() != 1.0 {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            Span::default(),
            "the cut thread's measures are not finite (or its direction is not ±1)".to_string(),
        ));
    }
    let side = cut.side;
    let sign = match side {
        Surface::External => 1.0,
        Surface::Internal => -1.0,
    };
    let at = taper.gauge_plane_from_face(side);
    let gauge_plane_z = cut.face_z + cut.into_part * at;
    let pd = cut.pitch_diameter_at_face + cut.taper * at;
    let basic = taper.gauge_pitch_diameter;
    let tol = taper.pitch_diameter_tolerance(side);
    let limits = Range::both(basic - tol, basic + tol);
    let per_turn = taper.diameter_per_length * t.pitch;
    let standoff_turns = (pd - basic) / per_turn;
    let allowed_turns = taper.position_tolerance(side) / t.pitch;
    let mut findings = Vec::new();
    let mm = |v: f64| format!("{v:.4}");
    if (pd - basic).abs() > tol + cut.resolution.max(0.0) + 1e-9 {
        findings.push(TaperFinding {
            error: true,
            check: TaperCheck::PitchDiameter,
            message: format!(
                "pitch diameter {} at the gauge plane (Z{}) is {} the {} {} for {}: the gauge would stand {:+.2} turns from its basic position (±{:.2} allowed)",
                mm(pd),
                mm(gauge_plane_z),
                if pd > basic { "above" } else { "below" },
                if pd > basic { "maximum" } else { "minimum" },
                mm(if pd > basic { basic + tol } else { basic - tol }),
                t.name,
                standoff_turns,
                allowed_turns
            ),
        });
    }
    // The taper: the standard's 1/16 on diameter, growing into an external part's thread.
    let nominal = sign * taper.diameter_per_length;
    let measured = cut.taper;
    match taper.taper_tolerance {
        Some((below, above)) => {
            let (lo, hi) = (
                taper.diameter_per_length - below,
                taper.diameter_per_length + above,
            );
            let m = sign * measured;
            if m < lo - 1e-12 || m > hi + 1e-12 {
                findings.push(TaperFinding {
                    error: true,
                    check: TaperCheck::Taper,
                    message: format!(
                        "taper {:.5} on diameter per unit length is outside {:.5} to {:.5} for {}",
                        m, lo, hi, t.name
                    ),
                });
            }
        }
        None => {
            if (measured - nominal).abs() > 1e-6 {
                findings.push(TaperFinding {
                    error: true,
                    check: TaperCheck::Taper,
                    message: format!(
                        "taper {:.5} on diameter per unit length is not the standard's {:.5} for {}",
                        sign * measured,
                        taper.diameter_per_length,
                        t.name
                    ),
                });
            }
        }
    }
    if (cut.pitch - t.pitch).abs() > 1e-6 {
        findings.push(TaperFinding {
            error: true,
            check: TaperCheck::Pitch,
            message: format!(
                "pitch {} is not the standard's {} for {}",
                mm(cut.pitch),
                mm(t.pitch),
                t.name
            ),
        });
    }
    if cut.length + 1e-9 < at {
        findings.push(TaperFinding {
            error: true,
            check: TaperCheck::Length,
            message: format!(
                "the thread is {} long and ends before its gauge plane ({} from the face)",
                mm(cut.length),
                mm(at)
            ),
        });
    } else if side == Surface::External && cut.length + 1e-9 < taper.effective_length {
        findings.push(TaperFinding {
            error: false,
            check: TaperCheck::Length,
            message: format!(
                "the full-form thread is {} long, shorter than the standard's {} for {}",
                mm(cut.length),
                mm(taper.effective_length),
                t.name
            ),
        });
    }
    Ok(TaperJudgement {
        gauge_plane_z,
        pitch_diameter: pd,
        basic,
        limits,
        standoff_turns,
        allowed_turns,
        taper: cut.taper,
        findings,
    })
}
