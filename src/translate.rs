//! Writing a job for a target controller: as the target's native cycle when that cycle expresses
//! exactly the same motion, otherwise as plain moves with a comment saying why.
//!
//! "Exactly the same" is checked, never assumed: the native text is read back by threadcut's own
//! reader for the target, built into a toolpath, and compared move by move with the job's toolpath
//! within the target's output resolution.

use std::io::{self, Write};

use crate::dialect::{self, Read};
use crate::gcode::{Modal, Reader};
use crate::machine::Machine;
use crate::post;
use crate::thread::Job;
use crate::toolpath::{self, MotionKind, Toolpath};
use crate::units::Units;

/// How a job was written.
#[derive(Debug, PartialEq)]
pub enum Written {
    Native,
    /// Plain moves, and why the native cycle was not used.
    Plain(String),
}

/// Writes `job` for `target`.
pub fn write_job(
    out: &mut dyn Write,
    target: &Machine,
    job: &Job,
) -> Result<Written, crate::program::Error> {
    let path = toolpath::build(job)?;
    let d = dialect::open(target).map_err(crate::program::Error::Setup)?;
    let format = d.format();
    let reason = match d.emit_native(job) {
        Ok(lines) => match verify(target, job, &path, &lines) {
            Ok(()) => {
                for l in &lines {
                    writeln!(out, "{l}")?;
                }
                return Ok(Written::Native);
            }
            Err(why) => why,
        },
        Err(why) => why,
    };
    post::expressible(&format, job)?;
    if let Some(c) = format.comment(&format!(
        "threadcut: plain moves, not the native cycle: {reason}"
    )) {
        writeln!(out, "{c}")?;
    }
    post::write_moves(out, &format, job.units, &path)?;
    Ok(Written::Plain(reason))
}

/// Reads `lines` back as `target` would, from the job's start point, and compares the motion.
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
    let mut read_back = None;
    while let Some(line) = reader.next_line() {
        let line =
            line.map_err(|e| format!("the native cycle does not read back: {}", e.message))?;
        match d.read(&line, &mut modal, &mut warnings) {
            Ok(Read::Cycle(job)) => read_back = Some(job),
            Ok(Read::Settings | Read::Applied(_)) => {}
            Ok(Read::Plain) => {
                modal
                    .apply(&conv, &line)
                    .map_err(|e| format!("the native cycle does not read back: {}", e.message))?;
            }
            Err(e) => {
                return Err(format!(
                    "the native cycle does not read back: {}",
                    e.message
                ))
            }
        }
    }
    let back = read_back.ok_or("the native text holds no cycle")?;
    let got = toolpath::build(&back).map_err(|e| e.message)?;
    same_motion(expected, &got, tolerance(target, job.units))
}

/// Half the output resolution, in mm: X is written on diameter on most lathes, so the radius may
/// differ by half a diameter increment; leads get their own resolution.
fn tolerance(target: &Machine, units: Units) -> (f64, f64) {
    let pos = units.to_mm(target.resolution(units)) * 0.5 + 1e-9;
    let lead_digits = if units == Units::Inch { 5 } else { 4 };
    let lead = units.to_mm(10f64.powi(-lead_digits)) * 0.5 + 1e-9;
    (pos, lead)
}

/// Compares two toolpaths move by move; the first difference is the reason.
pub fn same_motion(
    a: &Toolpath,
    b: &Toolpath,
    (pos_tol, lead_tol): (f64, f64),
) -> Result<(), String> {
    if a.motions.len() != b.motions.len() {
        return Err(format!(
            "reading it back gives {} moves instead of {}",
            b.motions.len(),
            a.motions.len()
        ));
    }
    for (i, (ma, mb)) in a.motions.iter().zip(&b.motions).enumerate() {
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
