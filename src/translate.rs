//! Writing a job for a target controller: as the target's native cycle when some choice of its
//! words expresses exactly the same motion, otherwise as plain moves with a comment saying which
//! property of the job the native cycle cannot express.
//!
//! "Exactly the same" is checked, never assumed: the target's dialect proposes candidates
//! ([`Dialect::native_candidates`]: a search over the words whose values the job leaves open, such
//! as the tool angle of a radial infeed), each is read back by threadcut's own reader for the
//! target, built into a toolpath, and compared move by move with the job's toolpath within the
//! target's output resolution. The first that matches is written.

use std::io::{self, Write};

use crate::diag::{Code, Diagnostic};
use crate::dialect::lexicon::{Function, Known, Setting};
use crate::dialect::{self, Dialect, Read};
use crate::gcode::{Modal, MotionMode, Reader};
use crate::machine::Machine;
use crate::post;
use crate::thread::Job;
use crate::toolpath::{self, Motion, MotionKind, Toolpath};
use crate::units::Units;

mod drift;
pub use drift::{DriftRule, LeadDrift, Limit};

/// How a job was written.
#[derive(Debug, PartialEq)]
pub enum Written {
    Native,
    /// Plain moves, and why the native cycle was not used.
    Plain(String),
}

/// Writes `job` for `target` with the default limit of the lead's drift ([`write_job_with`]).
pub fn write_job(
    out: &mut dyn Write,
    target: &Machine,
    job: &Job,
) -> Result<Written, crate::program::Error> {
    write_job_with(out, target, job, &DriftRule::new(job.units)).map(|(w, _)| w)
}

/// Which machine settings a native cycle may rely on ([`Dialect::settings_read`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SettingsRule {
    /// Any value the profile holds (the same machine's program written back, a post).
    Any,
    /// None that threadcut assumed ([`Known::Assumed`]): a conversion's native cycle relies only
    /// on settings the target profile states or on the control's factory defaults.
    NotAssumed,
}

/// What [`write_job_for`] did: how the job was written, the lead's drift where it drifts, and the
/// machine settings the native cycle written relies on.
#[derive(Debug)]
pub struct Outcome {
    pub written: Written,
    pub drift: Option<LeadDrift>,
    pub settings: Vec<Setting>,
}

/// Writes `job` for `target`: its native cycle when a candidate reads back as the job's motion,
/// else plain moves after a comment with the reason. Where the units change, a comment states
/// the lead in both. The lead written in the target's words
/// drifts over the thread's length ([`lead_rounding`]): where it drifts at all, a comment states
/// the drift and its pitch-diameter equivalent before the cycle and the drift is returned (the
/// caller warns); beyond the rule's limit ([`LeadDrift`]) it is refused, an error at the job's
/// block. Refused too when the target has no plain synchronised move to fall back on (its
/// threading code is always the cycle) or its plain moves cannot state the job's start angle.
pub fn write_job_with(
    out: &mut dyn Write,
    target: &Machine,
    job: &Job,
    rule: &DriftRule,
) -> Result<(Written, Option<LeadDrift>), crate::program::Error> {
    write_job_for(out, target, job, rule, SettingsRule::Any).map(|o| (o.written, o.drift))
}

/// [`write_job_with`], with the settings a native cycle may rely on (`settings`), saying which
/// ones the cycle written relies on.
pub fn write_job_for(
    out: &mut dyn Write,
    target: &Machine,
    job: &Job,
    rule: &DriftRule,
    settings: SettingsRule,
) -> Result<Outcome, crate::program::Error> {
    let path = toolpath::build(job)?;
    let d = dialect::open(target).map_err(crate::program::Error::Setup)?;
    let drift = LeadDrift::judge(lead_rounding(target, d.as_ref(), job), job, rule);
    if drift.over() {
        return Err(drift.refusal(target, job).into());
    }
    let note = if drift.drifts() {
        Some(drift.comment(rule))
    } else if rule.source_units != job.units {
        let r = &drift.rounding;
        Some(format!(
            "threadcut: in {}: {}",
            r.units.name(),
            r.describe(rule.source_units)
        ))
    } else {
        None
    };
    // The motion first, so that nothing is written for a job refused.
    let mut motion = Vec::new();
    let (written, relied) = write_motion(&mut motion, target, d.as_ref(), job, &path, settings)?;
    if let Some(c) = note.and_then(|n| d.format().comment(&n)) {
        writeln!(out, "{c}")?;
    }
    out.write_all(&motion)?;
    Ok(Outcome {
        written,
        drift: drift.drifts().then_some(drift),
        settings: relied,
    })
}

/// The job's native cycle (and the settings it relies on), or plain moves after the reason, or a
/// refusal.
fn write_motion(
    out: &mut dyn Write,
    target: &Machine,
    d: &dyn Dialect,
    job: &Job,
    path: &Toolpath,
    settings: SettingsRule,
) -> Result<(Written, Vec<Setting>), crate::program::Error> {
    let reason = match native_with(target, d, job, path, settings) {
        Ok(lines) => {
            for l in &lines {
                writeln!(out, "{l}")?;
            }
            return Ok((Written::Native, d.settings_read(&lines)));
        }
        Err(why) => why,
    };
    let format = d.format();
    if !d.meanings().has(Function::Thread) {
        return Err(Diagnostic::error(
            Code::Unsupported,
            job.span,
            format!(
                "{} has no plain synchronised move ({} is always its threading cycle), and its cycle cannot cut this thread: {reason}",
                target.name, format.thread
            ),
        )
        .with_hint("convert to a controller with a plain thread move (G32, G33), or reprogram the thread with this controller's cycle")
        .into());
    }
    post::expressible(&format, job)?;
    if let Some(c) = format.comment(&format!(
        "threadcut: plain moves, not the native cycle: {reason}"
    )) {
        writeln!(out, "{c}")?;
    }
    post::write_moves(out, &format, job.units, path)?;
    Ok((Written::Plain(reason), Vec::new()))
}

/// The first of the target's native candidates for `job` that reads back as `expected` (the
/// job's toolpath), or the reason none does: the first candidate's (each dialect lists its most
/// telling candidate first).
pub fn native(
    target: &Machine,
    d: &dyn Dialect,
    job: &Job,
    expected: &Toolpath,
) -> Result<Vec<String>, String> {
    native_with(target, d, job, expected, SettingsRule::Any)
}

/// [`native`], skipping a candidate that relies on a setting `settings` does not allow.
fn native_with(
    target: &Machine,
    d: &dyn Dialect,
    job: &Job,
    expected: &Toolpath,
    settings: SettingsRule,
) -> Result<Vec<String>, String> {
    let mut reason = None;
    for candidate in d.native_candidates(job) {
        let why = match candidate {
            Ok(lines) if settings == SettingsRule::NotAssumed && assumed(d, &lines).is_some() => {
                assumed(d, &lines).unwrap_or_default()
            }
            Ok(lines) => match verify(target, job, expected, &lines) {
                Ok(()) => return Ok(lines),
                Err(why) => why,
            },
            Err(why) => why,
        };
        reason.get_or_insert(why);
    }
    Err(reason.unwrap_or_else(|| format!("{} has no native threading cycle", d.name())))
}

/// Why a native text cannot be written when it relies on settings threadcut assumed: `G76 reads
/// Setting 86 and Setting 99 from the machine, and the target profile does not state them`.
fn assumed(d: &dyn Dialect, lines: &[String]) -> Option<String> {
    let names: Vec<&str> = d
        .settings_read(lines)
        .into_iter()
        .filter(|s| s.known == Known::Assumed)
        .map(|s| s.name)
        .collect();
    if names.is_empty() {
        return None;
    }
    let code = lines
        .first()
        .and_then(|l| l.split_whitespace().next())
        .unwrap_or("the cycle");
    Some(format!(
        "{code} reads {} from the machine, and the target profile does not state {}: threadcut's values would be assumed",
        names.join(" and "),
        if names.len() == 1 { "it" } else { "them" }
    ))
}

/// How far a lead written in the target's words drifts from the job's over the thread.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LeadRounding {
    /// The job's lead and the lead as written, in the job's units.
    pub lead: f64,
    pub written: f64,
    /// The thread's length along its axis (the job's units).
    pub length: f64,
    /// |written − lead| × length / lead: how far the last turn lands from where it should.
    pub over_length: f64,
    /// The target's output resolution in the job's units (its grid where it has one).
    pub resolution: f64,
    pub units: Units,
}

/// The lead of `job` rounded to the step `target` writes it in (its lead word's decimals, or the
/// grid of a control that has one, [`Dialect::output_step`]), and the drift over the thread.
pub fn lead_rounding(target: &Machine, d: &dyn Dialect, job: &Job) -> LeadRounding {
    let u = job.units;
    let lead = u.from_mm(job.lead.lead);
    let format = d.format();
    let grid = d.output_step(job.lead.lead, u);
    let step = grid
        .unwrap_or_else(|| 10f64.powi(-(format.lead_decimals[(u == Units::Inch) as usize] as i32)));
    let written = (lead / step).round() * step;
    let g = &job.geometry;
    let length = u.from_mm(g.side.along(g.travel()).abs());
    let over_length = if lead > 0.0 {
        (written - lead).abs() * length / lead
    } else {
        0.0
    };
    LeadRounding {
        lead,
        written,
        length,
        over_length,
        resolution: grid.unwrap_or_else(|| target.resolution(u)),
        units: u,
    }
}

impl LeadRounding {
    /// `lead 1.5 mm written as 0.05905 inch: 0.0000051 inch per turn, 0.000068 inch over the
    /// thread's 0.7874 inch`.
    pub fn describe(&self, source_units: Units) -> String {
        let u = self.units;
        let from = source_units.from_mm(u.to_mm(self.lead));
        format!(
            "lead {} {} written as {} {}: {} {} per turn, {} {} over the thread's {} {}",
            post::number(from, 6, false),
            source_units.name(),
            post::number(self.written, 6, false),
            u.name(),
            post::number((self.written - self.lead).abs(), 7, false),
            u.name(),
            post::number(self.over_length, 7, false),
            u.name(),
            post::number(self.length, 4, false),
            u.name()
        )
    }
}

/// Reads `lines` back as `target` would, from the job's start point, and compares the motion
/// (plain moves and cycles alike: a native text may position the tool before its cycle). At least
/// one cycle must be read.
pub fn verify(
    target: &Machine,
    job: &Job,
    expected: &Toolpath,
    lines: &[String],
) -> Result<(), String> {
    let mut d = dialect::open(target)?;
    d.assume_ready();
    let conv = d.conventions().clone();
    let mut modal = Modal::for_machine(&conv, target);
    modal.units = job.units;
    modal.position = crate::gcode::Position::at(job.start);
    let text = lines.join("\n") + "\n";
    let mut reader = Reader::new(text.as_bytes()).with_syntax(conv.syntax);
    let mut warnings = Vec::new();
    let mut got = Toolpath {
        start: job.start,
        motions: Vec::new(),
    };
    let mut cycles = 0;
    let name = lines
        .iter()
        .find_map(|l| l.split_whitespace().find(|w| !w.starts_with('N')))
        .map(|w| w.split('(').next().unwrap_or(w).to_string())
        .unwrap_or_default();
    let unreadable = |m: &str| format!("{name} does not read back: {m}");
    while let Some(line) = reader.next_line() {
        let line = line.map_err(|e| unreadable(&e.message))?;
        let mv = match d.read(&line, &mut modal, &mut warnings) {
            Ok(Read::Cycle(back)) => {
                cycles += 1;
                modal.position = crate::gcode::Position::at(back.end_point());
                let path = toolpath::build(&back).map_err(|e| e.message)?;
                got.motions.extend(path.motions);
                None
            }
            Ok(Read::Settings) => None,
            // A threading cycle's native text has no turning cycle in it.
            Ok(Read::Turning(_)) => return Err(unreadable("it reads as a turning cycle")),
            Ok(Read::Applied(mv) | Read::Own { mv, .. }) => mv,
            Ok(Read::Plain) => modal
                .apply(&conv, &line)
                .map_err(|e| unreadable(&e.message))?,
            Err(e) => return Err(unreadable(&e.message)),
        };
        if let Some(mv) = mv {
            got.motions.push(Motion {
                kind: match mv.mode {
                    MotionMode::Rapid => MotionKind::Rapid,
                    MotionMode::Thread => MotionKind::Thread {
                        lead: mv.lead.unwrap_or(0.0),
                        dlead: 0.0,
                        phase_deg: mv.phase_deg,
                    },
                    _ => MotionKind::Feed,
                },
                to: mv.to,
                pass: 0,
                line: line.number,
            });
        }
    }
    if cycles == 0 {
        return Err(format!("{name} holds no cycle"));
    }
    same_motion(expected, &got, tolerance(target, d.as_ref(), job))
        .map_err(|why| format!("{name} would move otherwise: {why}"))
}

/// Half the output resolution, in mm: X is written on diameter on most lathes, so the radius may
/// differ by half a diameter increment; leads get their own resolution, or the control's grid
/// where it writes everything on one ([`Dialect::output_step`]).
fn tolerance(target: &Machine, d: &dyn Dialect, job: &Job) -> (f64, f64) {
    let units = job.units;
    let grid = d.output_step(job.lead.lead, units);
    let pos = units.to_mm(grid.unwrap_or_else(|| target.resolution(units))) * 0.5 + 1e-9;
    let lead_digits = if units == Units::Inch { 5 } else { 4 };
    let lead_step = grid.unwrap_or(10f64.powi(-lead_digits));
    let lead = units.to_mm(lead_step) * 0.5 + 1e-9;
    (pos, lead)
}

/// Compares two toolpaths move by move; the first difference is the reason. A move that ends where
/// it starts is no motion and is left out on both sides (a cycle's rapid to a start point the tool
/// is already at).
pub fn same_motion(
    a: &Toolpath,
    b: &Toolpath,
    (pos_tol, lead_tol): (f64, f64),
) -> Result<(), String> {
    let moving = |p: &Toolpath| -> Vec<Motion> {
        p.segments()
            .filter(|(from, m)| from.distance(m.to) > 1e-12)
            .map(|(_, m)| *m)
            .collect()
    };
    let (a, b) = (moving(a), moving(b));
    if a.len() != b.len() {
        return Err(format!(
            "reading it back gives {} moves instead of {}",
            b.len(),
            a.len()
        ));
    }
    for (i, (ma, mb)) in a.iter().zip(&b).enumerate() {
        let kinds_match = match (ma.kind, mb.kind) {
            (MotionKind::Rapid, MotionKind::Rapid) | (MotionKind::Feed, MotionKind::Feed) => true,
            (
                MotionKind::Thread {
                    lead: la,
                    dlead: da,
                    phase_deg: pa,
                },
                MotionKind::Thread {
                    lead: lb,
                    dlead: db,
                    phase_deg: pb,
                },
            ) => (la - lb).abs() <= lead_tol && (da - db).abs() <= lead_tol && same_angle(pa, pb),
            _ => false,
        };
        if !kinds_match {
            return Err(format!(
                "move {} differs in kind, lead or start angle when read back",
                i + 1
            ));
        }
        if (ma.to.x - mb.to.x).abs() > pos_tol || (ma.to.z - mb.to.z).abs() > pos_tol {
            return Err(format!(
                "move {} ends {:.4} mm away when read back",
                i + 1,
                ma.to.distance(mb.to)
            ));
        }
    }
    Ok(())
}

/// Start angles closer than this are the same (degrees): half the coarsest resolution a
/// start-angle word is written in ([`StartAngleUnit::Milli`], Fanuc's and Haas's `Q` in 0.001°),
/// so that every written angle reads back as itself; Sinumerik's `SF=` (0.0001°) is finer. Far
/// below anything a spindle encoder resolves (0.0005° is 0.008 µm along a 6 mm lead).
pub const PHASE_TOLERANCE_DEG: f64 = 0.0005 + 1e-9;

/// Whether two spindle angles (degrees) are the same, modulo a turn: 359.9999° written as `Q0`
/// or `SF=0` is the angle it was.
pub fn same_angle(a: f64, b: f64) -> bool {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d) <= PHASE_TOLERANCE_DEG
}

/// Convenience for tests: write to a string.
pub fn job_to_string(
    target: &Machine,
    job: &Job,
) -> Result<(String, Written), crate::program::Error> {
    let mut buf = Vec::new();
    let w = write_job(&mut buf, target, job)?;
    Ok((
        String::from_utf8(buf).map_err(|e| io::Error::new(io::ErrorKind::InvalidData, e))?,
        w,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::toolpath::Motion;
    use crate::units::Pos;

    fn path(phase_deg: f64) -> Toolpath {
        Toolpath {
            start: Pos::new(10.0, 2.0),
            motions: vec![Motion {
                kind: MotionKind::Thread {
                    lead: 2.0,
                    dlead: 0.0,
                    phase_deg,
                },
                to: Pos::new(10.0, -20.0),
                pass: 1,
                line: 1,
            }],
        }
    }

    #[test]
    fn start_angles_are_compared_modulo_a_turn() {
        let tol = (1e-6, 1e-6);
        assert!(same_motion(&path(0.0), &path(0.0), tol).is_ok());
        assert!(same_motion(&path(359.99999), &path(0.0), tol).is_ok());
        assert!(same_motion(&path(0.0004), &path(359.9999), tol).is_ok());
        assert!(same_motion(&path(120.0), &path(120.0004), tol).is_ok());
        assert!(same_motion(&path(120.0), &path(120.001), tol).is_err());
        assert!(same_motion(&path(180.0), &path(0.0), tol).is_err());
    }

    /// Every start-angle word reads back as the angle it was written from.
    #[test]
    fn the_start_angle_tolerance_covers_every_words_rounding() {
        use crate::post::AngleUnit;
        for unit in [AngleUnit::Millidegrees, AngleUnit::Degrees { decimals: 4 }] {
            assert!(
                unit.resolution_deg() / 2.0 <= PHASE_TOLERANCE_DEG,
                "{unit:?}"
            );
        }
        assert!(PHASE_TOLERANCE_DEG < AngleUnit::Millidegrees.resolution_deg());
    }
}
