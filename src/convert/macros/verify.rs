//! The check every structural translation passes: the source program and the converted one run
//! through threadcut's interpreters, and their motion compared move by move at the output's
//! resolution.

use crate::gcode::MotionMode;
use crate::machine::Machine;
use crate::program::{self, Error, Event};
use crate::toolpath::{self, MotionKind};
use crate::units::{Pos, Units};

/// A move: rapid or not, its lead (mm) when it is a thread move, where it starts and ends (mm).
#[derive(Clone, Copy, Debug)]
pub struct Move {
    pub rapid: bool,
    pub lead: Option<f64>,
    pub from: Pos,
    pub to: Pos,
}

/// Every move `text` makes on `machine`, moves of no length left out.
pub fn motion(
    text: &[u8],
    machine: &Machine,
    options: &program::Options,
) -> Result<Vec<Move>, Error> {
    let mut moves = Vec::new();
    program::run_with(text, machine, options, |_, ev| {
        match ev {
            Event::Plain { mv: Some(mv), .. } => moves.push(Move {
                rapid: mv.mode == MotionMode::Rapid,
                lead: mv.lead,
                from: Pos::new(mv.from.x.unwrap_or(mv.to.x), mv.from.z.unwrap_or(mv.to.z)),
                to: mv.to,
            }),
            Event::Cycle { job, .. } => {
                for (from, mo) in toolpath::build(&job)?.segments() {
                    moves.push(Move {
                        rapid: mo.kind == MotionKind::Rapid,
                        lead: match mo.kind {
                            MotionKind::Thread { lead, .. } => Some(lead),
                            _ => None,
                        },
                        from,
                        to: mo.to,
                    });
                }
            }
            _ => {}
        }
        Ok(())
    })?;
    moves.retain(|m| m.from.distance(m.to) > 1e-12);
    Ok(moves)
}

/// Half the coarsest resolution of the two controls, in mm: a value the source computes is
/// rounded to its control's increment, the same expression on the target to the target's.
pub fn tolerance(from: &Machine, to: &Machine) -> f64 {
    [Units::Mm, Units::Inch]
        .into_iter()
        .flat_map(|u| [u.to_mm(from.resolution(u)), u.to_mm(to.resolution(u))])
        .fold(0.0, f64::max)
        * 0.5
        + 1e-9
}

/// The first difference between two motions, within `tol` (mm).
pub fn differs(a: &[Move], b: &[Move], tol: f64) -> Option<String> {
    if a.len() != b.len() {
        return Some(format!("{} moves instead of {}", b.len(), a.len()));
    }
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        let lead = match (x.lead, y.lead) {
            (None, None) => true,
            (Some(p), Some(q)) => (p - q).abs() <= tol,
            _ => false,
        };
        let d = x.to.minus(y.to);
        if x.rapid != y.rapid || !lead || d.x.abs() > tol || d.z.abs() > tol {
            return Some(format!(
                "move {} ends at X{:.4} Z{:.4}{}, the source's at X{:.4} Z{:.4}{}",
                i + 1,
                y.to.x,
                y.to.z,
                y.lead.map_or(String::new(), |l| format!(" (lead {l:.5})")),
                x.to.x,
                x.to.z,
                x.lead.map_or(String::new(), |l| format!(" (lead {l:.5})")),
            ));
        }
    }
    None
}
