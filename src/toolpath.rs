//! The toolpath: absolute moves in millimetres (X as a radius). Only [`build`] turns a [`Job`] into
//! motion; every view (expanded G-code, JSON lines, plots, checks) reads this.

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result};
use crate::thread::{Entry, Exit, Job, Pass, ReturnPath};
use crate::units::{Pos, Vec2};

#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum MotionKind {
    Rapid,
    Feed,
    /// A spindle-synchronised move. `lead` is the travel per revolution along this move's longer
    /// axis (what a G32/G33 F or K word means), `dlead` its change per revolution, `phase_deg` the
    /// spindle angle at which it starts.
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
pub fn build_with(job: &Job, passes: &[Pass]) -> Result<Toolpath> {
    let g = &job.geometry;
    let travel = g.travel();
    let axial = travel.z.abs();
    if axial <= 0.0 {
        return Err(Diagnostic::error(
            Code::Geometry,
            job.span,
            "the thread has no length along Z",
        ));
    }
    let along = Vec2::new(travel.x / axial, travel.z / axial); // per mm of axial travel
    let axial_dir = travel.z.signum();
    let outward = g.side.outward();
    let lead = job.lead.lead;
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
    let thread = |from: Pos, to: Pos| MotionKind::Thread {
        lead: lead_along_long_axis(lead, to.minus(from)),
        dlead: job.lead.dlead,
        phase_deg: 0.0,
    };
    let diagonal = match job.return_path {
        ReturnPath::Box => None,
        ReturnPath::Diagonal { clearance, end } => Some((clearance, end)),
    };
    for pass in passes {
        for s in 0..job.lead.starts {
            // Further starts begin further from the part, so every start keeps its full length.
            let shift = Vec2::new(0.0, -axial_dir * job.lead.start_spacing() * f64::from(s));
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
                        .plus(Vec2::new(0.0, -axial_dir * before));
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
                                    phase_deg: 0.0,
                                },
                                ramp_start,
                                pass.n,
                            );
                        }
                        None => push(MotionKind::Rapid, ramp_start, pass.n),
                    }
                    push(thread(ramp_start, infeed), infeed, pass.n);
                }
            }
            let end = match job.exit {
                Exit::Straight => {
                    let end = infeed.plus(travel);
                    push(thread(infeed, end), end, pass.n);
                    end
                }
                Exit::PullOut {
                    start_before,
                    length,
                    outward: up,
                } => {
                    let begin = infeed.plus(along.scale(axial - start_before));
                    let end = infeed
                        .plus(along.scale(axial - start_before + length))
                        .plus(outward.scale(up));
                    push(thread(infeed, begin), begin, pass.n);
                    push(thread(begin, end), end, pass.n);
                    end
                }
            };
            match back_x {
                Some(x) => push(MotionKind::Rapid, Pos::new(x, end.z), pass.n),
                None => {
                    push(MotionKind::Rapid, Pos::new(job.retract.x, end.z), pass.n);
                    push(
                        MotionKind::Rapid,
                        Pos::new(job.retract.x, job.retract.z),
                        pass.n,
                    );
                }
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
    if let Some(bad) = path.motions.iter().find(|m| !m.to.is_finite()) {
        return Err(Diagnostic::error(
            Code::Geometry,
            job.span,
            format!("pass {} computes a point that is not finite", bad.pass),
        ));
    }
    Ok(path)
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
