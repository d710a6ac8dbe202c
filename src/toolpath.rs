//! The toolpath: absolute moves in millimetres (X as a radius). Only [`build`] turns a [`Job`] into
//! motion; every view (expanded G-code, JSON lines, plots, checks) reads this.

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result};
use crate::thread::{Entry, Exit, Job, Lead, Pass, ReturnPath, StartIndexing};
use crate::units::{Pos, Vec2};

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum MotionKind {
    Rapid,
    Feed,
    /// A spindle-synchronised move. `lead` is the travel per revolution along this move's longer
    /// axis (what a G32/G33 F or K word means), `dlead` its change per revolution, `phase_deg` the
    /// spindle angle (degrees after the one-revolution signal) at which the synchronised run this
    /// move belongs to begins: the same for every move of one run (a pass's thread move and its
    /// pull-out), since only the run's first move waits for the signal.
    Thread {
        lead: f64,
        dlead: f64,
        phase_deg: f64,
    },
}

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Motion {
    pub kind: MotionKind,
    pub to: Pos,
    /// Pass number within its cycle (1-based); 0 for moves outside a cycle.
    pub pass: u32,
    /// Source line.
    pub line: u32,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Toolpath {
    pub start: Pos,
    pub motions: Vec<Motion>,
}

impl Toolpath {
    pub fn end(&self) -> Pos {
        self.motions.last().map_or(self.start, |m| m.to)
    }

    /// Each move with the point it starts from.
    pub fn segments(&self) -> impl Iterator<Item = (Pos, &Motion)> {
        let mut at = self.start;
        self.motions.iter().map(move |m| {
            let from = at;
            at = m.to;
            (from, m)
        })
    }
}

/// Builds the motion of a job: for each pass (and each start of a multi-start thread), approach,
/// thread, pull out, retract; then return to the job's start point.
pub fn build(job: &Job) -> Result<Toolpath> {
    let passes = crate::thread::plan::plan_geometry(job)?;
    build_with(job, &passes)
}

/// As [`build`], reusing a pass table already computed.
///
/// The long axis is Z for turned threads and X for face threads ([`crate::thread::Side`]); depth
/// grows along the other axis. With a variable lead (`dlead` ≠ 0) every synchronised move of a pass
/// carries the lead in force where it begins: the lead grows by `dlead` per spindle revolution from
/// `lead` at the pass's start, so after `k` revolutions the tool is `lead·k + dlead·k²/2` along the
/// long axis and the lead there is `√(lead² + 2·dlead·s)` at a distance `s` (G34's convention).
pub fn build_with(job: &Job, passes: &[Pass]) -> Result<Toolpath> {
    let g = &job.geometry;
    let side = g.side;
    let travel = g.travel();
    let long = side.along(travel);
    let axial = long.abs();
    if axial <= 0.0 {
        return Err(Diagnostic::error(
            Code::Geometry,
            job.span,
            format!(
                "the thread has no length along {}",
                if side.is_face() { "X" } else { "Z" }
            ),
        ));
    }
    let along = travel.scale(1.0 / axial); // per mm along the long axis
    let axial_dir = side.lateral().scale(long.signum());
    let outward = side.outward();
    let lead = job.lead.lead;
    let dlead = job.lead.dlead;
    let per_start = passes.len() * 5 + 2;
    let mut motions = Vec::with_capacity(per_start * job.lead.starts as usize + 2);
    let mut push = |kind: MotionKind, to: Pos, pass: u32| {
        motions.push(Motion {
            kind,
            to,
            pass,
            line: job.line,
        })
    };
    // The synchronised move from `from` to `to` of a pass whose thread begins at `origin`, for
    // a start whose moves begin at spindle angle `phase_deg`.
    let thread = |origin: Pos, from: Pos, to: Pos, phase_deg: f64| {
        let s = side.along(from.minus(origin)) * long.signum();
        let here = if dlead != 0.0 && s > 0.0 {
            (lead * lead + 2.0 * dlead * s).sqrt()
        } else {
            lead
        };
        MotionKind::Thread {
            lead: lead_on_move(here, to.minus(from), side.is_face()),
            dlead,
            phase_deg,
        }
    };
    let diagonal = match job.return_path {
        ReturnPath::Box | ReturnPath::BoxAtRetract => None,
        ReturnPath::Diagonal { clearance, end } => Some((clearance, end)),
    };
    if job.return_path == ReturnPath::BoxAtRetract {
        // The cycle's own start point first, from wherever the tool is.
        push(
            MotionKind::Rapid,
            Pos::new(job.retract.x, job.retract.z),
            passes.first().map_or(0, |p| p.n),
        );
    }
    for (pass, s) in pass_order(passes, job.lead) {
        // Starts reached by a shift begin further from the part, so every start keeps its
        // full length; starts reached by the spindle angle begin where the first does.
        let shift = match job.lead.indexing {
            StartIndexing::Shift => axial_dir.scale(-job.lead.start_spacing() * f64::from(s)),
            StartIndexing::Angle => Vec2::new(0.0, 0.0),
        };
        let phase = job.lead.start_phase(s);
        let thread = |origin: Pos, from: Pos, to: Pos| thread(origin, from, to, phase);
        let infeed = pass.start.plus(shift);
        // LinuxCNC: the pass's own retract X, `clearance` outward of its cut X.
        let back_x = diagonal.map(|(clearance, _)| infeed.plus(outward.scale(clearance)).x);
        match job.entry {
            Entry::Direct => {
                if let Some(x) = back_x {
                    push(MotionKind::Rapid, Pos::new(x, infeed.z), pass.n);
                }
                push(MotionKind::Rapid, infeed, pass.n)
            }
            Entry::Ramp {
                outward: up,
                before,
            } => {
                let ramp_start = infeed
                    .plus(outward.scale(up))
                    .plus(axial_dir.scale(-before));
                match back_x {
                    Some(x) => {
                        let back = Pos::new(x, ramp_start.z);
                        push(MotionKind::Rapid, back, pass.n);
                        // Synchronised in to the ramp's start at the ramp's rate along its path.
                        let ramp = infeed.minus(ramp_start);
                        let path_rate = if ramp.z == 0.0 {
                            lead
                        } else {
                            lead * ramp.x.hypot(ramp.z) / ramp.z.abs()
                        };
                        push(
                            MotionKind::Thread {
                                lead: lead_along_long_axis(path_rate, ramp_start.minus(back)),
                                dlead: job.lead.dlead,
                                phase_deg: phase,
                            },
                            ramp_start,
                            pass.n,
                        );
                    }
                    None => push(MotionKind::Rapid, ramp_start, pass.n),
                }
                push(thread(infeed, ramp_start, infeed), infeed, pass.n);
            }
        }
        let end = match job.exit {
            Exit::Straight => {
                let end = infeed.plus(travel);
                push(thread(infeed, infeed, end), end, pass.n);
                end
            }
            Exit::ToRetract { run_on } => {
                if side.is_face() {
                    return Err(Diagnostic::error(
                        Code::Unsupported,
                        job.span,
                        "a pull-out to the retract point is defined for turned threads only",
                    ));
                }
                let dir = long.signum();
                // The pass's own length: from its (offset) infeed point to the programmed end Z.
                let own = (g.crest_end.z + shift.z - infeed.z) * dir;
                if own <= 0.0 {
                    return Err(Diagnostic::error(
                            Code::Geometry,
                            job.span,
                            format!(
                                "pass {} starts at or beyond the thread's end: its infeed offset is longer than the thread",
                                pass.n
                            ),
                        ));
                }
                let end = infeed.plus(along.scale(own));
                push(thread(infeed, infeed, end), end, pass.n);
                // The retract X at the end: as far out as at the start, or further when the
                // thread climbs toward the retract side.
                let climb = (travel.x * outward.x).max(0.0);
                let rx = job.retract.x + outward.x * climb;
                let out = (rx - end.x) * outward.x;
                if run_on > 0.0 && out > 0.0 {
                    let to = Pos::new(rx, end.z + dir * run_on * out);
                    push(thread(infeed, end, to), to, pass.n);
                } else {
                    push(MotionKind::Rapid, Pos::new(rx, end.z), pass.n);
                }
                push(MotionKind::Rapid, Pos::new(rx, job.retract.z), pass.n);
                if rx != job.retract.x {
                    push(
                        MotionKind::Rapid,
                        Pos::new(job.retract.x, job.retract.z),
                        pass.n,
                    );
                }
                continue;
            }
            Exit::PullOut {
                start_before,
                length,
                outward: up,
            }
            | Exit::FeedOut {
                start_before,
                length,
                outward: up,
            } => {
                let begin = infeed.plus(along.scale(axial - start_before));
                let end = infeed
                    .plus(along.scale(axial - start_before + length))
                    .plus(outward.scale(up));
                push(thread(infeed, infeed, begin), begin, pass.n);
                let kind = if matches!(job.exit, Exit::FeedOut { .. }) {
                    MotionKind::Feed
                } else {
                    thread(infeed, begin, end)
                };
                push(kind, end, pass.n);
                end
            }
        };
        match back_x {
            // LinuxCNC: out to the pass's own retract X only; the next pass goes back diagonally.
            Some(x) => push(MotionKind::Rapid, Pos::new(x, end.z), pass.n),
            None => {
                let (level, back) = if side.is_face() {
                    (
                        Pos::new(end.x, job.retract.z),
                        Pos::new(job.retract.x, job.retract.z),
                    )
                } else {
                    (
                        Pos::new(job.retract.x, end.z),
                        Pos::new(job.retract.x, job.retract.z),
                    )
                };
                push(MotionKind::Rapid, level, pass.n);
                push(MotionKind::Rapid, back, pass.n);
            }
        }
    }
    let last = passes.last().map_or(0, |p| p.n);
    let finish = job.end_point();
    if diagonal.is_some() || motions.last().map(|m| m.to) != Some(finish) {
        motions.push(Motion {
            kind: MotionKind::Rapid,
            to: finish,
            pass: last,
            line: job.line,
        });
    }
    let path = Toolpath {
        start: job.start,
        motions,
    };
    if let Some(bad) = path.motions.iter().find(|m| m.to.x < -AXIS_TOLERANCE) {
        return Err(Diagnostic::error(
            Code::Geometry,
            job.span,
            format!(
                "pass {} would cross the spindle axis (a radius of {:.4} mm): the depth is larger than the part's radius",
                bad.pass, bad.to.x
            ),
        ));
    }
    if let Some(bad) = path.motions.iter().find(|m| !m.to.is_finite()) {
        return Err(Diagnostic::error(
            Code::Geometry,
            job.span,
            format!("pass {} computes a point that is not finite", bad.pass),
        ));
    }
    Ok(path)
}

/// The order in which the passes of each start are cut: (pass, start index). Shifted starts are
/// all cut at one depth before the next depth; starts reached by the spindle angle are each cut
/// to full depth before the next ([`StartIndexing`]).
fn pass_order(passes: &[Pass], lead: Lead) -> impl Iterator<Item = (&Pass, u32)> {
    let starts = lead.starts.max(1);
    let n = passes.len() as u64;
    (0..n * u64::from(starts)).map(move |k| match lead.indexing {
        StartIndexing::Shift => (
            &passes[(k / u64::from(starts)) as usize],
            (k % u64::from(starts)) as u32,
        ),
        StartIndexing::Angle => (&passes[(k % n) as usize], (k / n) as u32),
    })
}

/// A radius this far below zero is still the axis (rounding), not a crossing of it.
const AXIS_TOLERANCE: f64 = 1e-9;

/// The lead written on a synchronised move, given `lead` along the job's long axis (Z, or X for a
/// face thread): the same rate per revolution, expressed along the move's own longer axis.
pub fn lead_on_move(lead: f64, d: Vec2, face: bool) -> f64 {
    if face {
        let swapped = Vec2::new(d.z, d.x);
        lead_along_long_axis(lead, swapped)
    } else {
        lead_along_long_axis(lead, d)
    }
}

/// A thread's lead is set along Z; when a move (a steep pull-out, a radial screw-in) travels further
/// in X than in Z, its longer axis is X, and keeping the same Z rate per revolution means X advances
/// `lead·|dx|/|dz|` per revolution. A move with no Z travel advances the lead in X.
pub fn lead_along_long_axis(lead: f64, d: Vec2) -> f64 {
    if d.x.abs() <= d.z.abs() || d.z == 0.0 {
        lead
    } else {
        lead * d.x.abs() / d.z.abs()
    }
}
