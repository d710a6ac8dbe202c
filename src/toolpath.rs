//! The toolpath: absolute moves in millimetres (X as a radius). Only [`build`] turns a [`Job`] into
//! motion; every view (expanded G-code, JSON lines, plots, checks) reads this.

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result};
use crate::thread::{Entry, Exit, Job, Lead, Pass, ReturnPath, Side, StartIndexing};
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
    /// A circular feed move about `centre` (X radius, Z; mm), clockwise as the program's G2
    /// (`clockwise`) or counter-clockwise as its G3: a turning cycle's contour.
    Arc {
        centre: Pos,
        clockwise: bool,
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
    let mut b = Builder::new(job, passes)?;
    if job.return_path == ReturnPath::BoxAtRetract {
        // The cycle's own start point first, from wherever the tool is.
        b.push(
            MotionKind::Rapid,
            Pos::new(job.retract.x, job.retract.z),
            passes.first().map_or(0, |p| p.n),
        );
    }
    for (pass, s) in pass_order(passes, job.lead) {
        let p = b.pass_start(pass, s);
        b.enter(&p);
        if let Some(end) = b.cut(&p)? {
            b.leave(&p, end);
        }
    }
    b.finish(passes)
}

/// What every pass of one job shares while its moves are built: the job, the directions along
/// and across the thread, the lead, and the moves so far.
struct Builder<'a> {
    job: &'a Job,
    side: Side,
    /// The displacement of one pass from its start to its programmed end.
    travel: Vec2,
    /// That displacement along the long axis (signed) and its length.
    long: f64,
    axial: f64,
    /// The travel per mm along the long axis.
    along: Vec2,
    /// The long axis, pointing the way the thread is cut.
    axial_dir: Vec2,
    outward: Vec2,
    lead: f64,
    dlead: f64,
    /// LinuxCNC's return path: how far outward of its cut X each pass backs off.
    back_clearance: Option<f64>,
    motions: Vec<Motion>,
}

/// Where one pass of one start begins: its infeed point, how far that start is shifted along the
/// axis, the spindle angle its synchronised moves begin at, and its own retract X (LinuxCNC).
struct PassStart {
    n: u32,
    infeed: Pos,
    shift: Vec2,
    phase: f64,
    back_x: Option<f64>,
}

impl<'a> Builder<'a> {
    /// Decides the axes of the job, refusing a thread with no length along its long axis.
    fn new(job: &'a Job, passes: &[Pass]) -> Result<Builder<'a>> {
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
        let per_start = passes.len() * 5 + 2;
        let back_clearance = match job.return_path {
            ReturnPath::Box | ReturnPath::BoxAtRetract => None,
            ReturnPath::Diagonal { clearance, .. } => Some(clearance),
        };
        Ok(Builder {
            job,
            side,
            travel,
            long,
            axial,
            along: travel.scale(1.0 / axial), // per mm along the long axis
            axial_dir: side.lateral().scale(long.signum()),
            outward: side.outward(),
            lead: job.lead.lead,
            dlead: job.lead.dlead,
            back_clearance,
            motions: Vec::with_capacity(per_start * job.lead.starts as usize + 2),
        })
    }

    /// Appends one move of pass `pass`, on the job's source line.
    fn push(&mut self, kind: MotionKind, to: Pos, pass: u32) {
        self.motions.push(Motion {
            kind,
            to,
            pass,
            line: self.job.line,
        })
    }

    /// Decides the lead of the synchronised move from `from` to `to` of a pass whose thread
    /// begins at `origin`, for a start whose moves begin at spindle angle `phase_deg`: the lead in
    /// force where the move begins, written along the move's own longer axis.
    fn thread(&self, origin: Pos, from: Pos, to: Pos, phase_deg: f64) -> MotionKind {
        let s = self.side.along(from.minus(origin)) * self.long.signum();
        let here = if self.dlead != 0.0 && s > 0.0 {
            (self.lead * self.lead + 2.0 * self.dlead * s).sqrt()
        } else {
            self.lead
        };
        MotionKind::Thread {
            lead: lead_on_move(here, to.minus(from), self.side.is_face()),
            dlead: self.dlead,
            phase_deg,
        }
    }

    /// Decides where pass `pass` of start `s` begins. Starts reached by a shift begin further
    /// from the part, so every start keeps its full length; starts reached by the spindle angle
    /// begin where the first does.
    fn pass_start(&self, pass: &Pass, s: u32) -> PassStart {
        let lead = self.job.lead;
        let shift = match lead.indexing {
            StartIndexing::Shift => self.axial_dir.scale(-lead.start_spacing() * f64::from(s)),
            StartIndexing::Angle => Vec2::new(0.0, 0.0),
        };
        let infeed = pass.start.plus(shift);
        // LinuxCNC: the pass's own retract X, `clearance` outward of its cut X.
        let back_x = self
            .back_clearance
            .map(|clearance| infeed.plus(self.outward.scale(clearance)).x);
        PassStart {
            n: pass.n,
            infeed,
            shift,
            phase: lead.start_phase(s),
            back_x,
        }
    }

    /// The moves to a pass's infeed point: a rapid straight there, or a rapid to the start of
    /// the entry ramp and the ramp synchronised down to the infeed point.
    fn enter(&mut self, p: &PassStart) {
        let infeed = p.infeed;
        match self.job.entry {
            Entry::Direct => {
                if let Some(x) = p.back_x {
                    self.push(MotionKind::Rapid, Pos::new(x, infeed.z), p.n);
                }
                self.push(MotionKind::Rapid, infeed, p.n)
            }
            Entry::Ramp {
                outward: up,
                before,
            } => {
                let ramp_start = infeed
                    .plus(self.outward.scale(up))
                    .plus(self.axial_dir.scale(-before));
                match p.back_x {
                    Some(x) => {
                        let back = Pos::new(x, ramp_start.z);
                        self.push(MotionKind::Rapid, back, p.n);
                        // Synchronised in to the ramp's start at the ramp's rate along its path.
                        let ramp = infeed.minus(ramp_start);
                        let path_rate = if ramp.z == 0.0 {
                            self.lead
                        } else {
                            self.lead * ramp.x.hypot(ramp.z) / ramp.z.abs()
                        };
                        self.push(
                            MotionKind::Thread {
                                lead: lead_along_long_axis(path_rate, ramp_start.minus(back)),
                                dlead: self.job.lead.dlead,
                                phase_deg: p.phase,
                            },
                            ramp_start,
                            p.n,
                        );
                    }
                    None => self.push(MotionKind::Rapid, ramp_start, p.n),
                }
                let kind = self.thread(infeed, ramp_start, infeed, p.phase);
                self.push(kind, infeed, p.n);
            }
        }
    }

    /// The thread move of a pass and its exit (straight on, a pull-out or a feed-out), with the
    /// point it ends at; `None` when the exit has already taken the tool back to the retract
    /// point.
    fn cut(&mut self, p: &PassStart) -> Result<Option<Pos>> {
        let infeed = p.infeed;
        match self.job.exit {
            Exit::Straight => {
                let end = infeed.plus(self.travel);
                let kind = self.thread(infeed, infeed, end, p.phase);
                self.push(kind, end, p.n);
                Ok(Some(end))
            }
            Exit::ToRetract { run_on } => {
                self.cut_to_retract(p, run_on)?;
                Ok(None)
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
                let begin = infeed.plus(self.along.scale(self.axial - start_before));
                let end = infeed
                    .plus(self.along.scale(self.axial - start_before + length))
                    .plus(self.outward.scale(up));
                let kind = self.thread(infeed, infeed, begin, p.phase);
                self.push(kind, begin, p.n);
                let kind = if matches!(self.job.exit, Exit::FeedOut { .. }) {
                    MotionKind::Feed
                } else {
                    self.thread(infeed, begin, end, p.phase)
                };
                self.push(kind, end, p.n);
                Ok(Some(end))
            }
        }
    }

    /// A turned pass cut to the programmed end Z and pulled out to the retract point (run on
    /// synchronised by `run_on` per unit outward when there is room), then back to it.
    fn cut_to_retract(&mut self, p: &PassStart, run_on: f64) -> Result<()> {
        let job = self.job;
        let infeed = p.infeed;
        if self.side.is_face() {
            return Err(Diagnostic::error(
                Code::Unsupported,
                job.span,
                "a pull-out to the retract point is defined for turned threads only",
            ));
        }
        let dir = self.long.signum();
        // The pass's own length: from its (offset) infeed point to the programmed end Z.
        let own = (job.geometry.crest_end.z + p.shift.z - infeed.z) * dir;
        if own <= 0.0 {
            return Err(Diagnostic::error(
                    Code::Geometry,
                    job.span,
                    format!(
                        "pass {} starts at or beyond the thread's end: its infeed offset is longer than the thread",
                        p.n
                    ),
                ));
        }
        let end = infeed.plus(self.along.scale(own));
        let kind = self.thread(infeed, infeed, end, p.phase);
        self.push(kind, end, p.n);
        // The retract X at the end: as far out as at the start, or further when the thread
        // climbs toward the retract side.
        let climb = (self.travel.x * self.outward.x).max(0.0);
        let rx = job.retract.x + self.outward.x * climb;
        let out = (rx - end.x) * self.outward.x;
        if run_on > 0.0 && out > 0.0 {
            let to = Pos::new(rx, end.z + dir * run_on * out);
            let kind = self.thread(infeed, end, to, p.phase);
            self.push(kind, to, p.n);
        } else {
            self.push(MotionKind::Rapid, Pos::new(rx, end.z), p.n);
        }
        self.push(MotionKind::Rapid, Pos::new(rx, job.retract.z), p.n);
        if rx != job.retract.x {
            self.push(
                MotionKind::Rapid,
                Pos::new(job.retract.x, job.retract.z),
                p.n,
            );
        }
        Ok(())
    }

    /// The way back from a pass's `end`: LinuxCNC out to the pass's own retract X only (the next
    /// pass goes back diagonally); otherwise out to the retract level, then back to the retract
    /// point.
    fn leave(&mut self, p: &PassStart, end: Pos) {
        let retract = self.job.retract;
        match p.back_x {
            Some(x) => self.push(MotionKind::Rapid, Pos::new(x, end.z), p.n),
            None => {
                let (level, back) = if self.side.is_face() {
                    (Pos::new(end.x, retract.z), Pos::new(retract.x, retract.z))
                } else {
                    (Pos::new(retract.x, end.z), Pos::new(retract.x, retract.z))
                };
                self.push(MotionKind::Rapid, level, p.n);
                self.push(MotionKind::Rapid, back, p.n);
            }
        }
    }

    /// The return to the job's end point (when not already there, and always on LinuxCNC's
    /// return path), then the checks on the whole path: no point across the spindle axis, none
    /// not finite.
    fn finish(self, passes: &[Pass]) -> Result<Toolpath> {
        let job = self.job;
        let mut motions = self.motions;
        let last = passes.last().map_or(0, |p| p.n);
        let finish = job.end_point();
        if self.back_clearance.is_some() || motions.last().map(|m| m.to) != Some(finish) {
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
