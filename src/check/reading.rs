//! What a machinist will read off the thread a program cuts, for `passes` (issue 27, item 2): the
//! pitch diameter the final passes leave with the tool's form, the measurement over three wires
//! of that pitch diameter (an external parallel thread), and, with a standard thread named, its
//! class's window and the change of the final depth that brings the thread to the window's
//! middle. `check --thread` states the same in its note ([`super::standard::what_is_measured`]).
//!
//! All sizes are millimetres; the thread's form comes from the tool: its angle as the cycle states
//! it (or the standard's), its tip as given (or the standard's root form, said as assumed).

use super::measure::{measure, target};
use crate::sim::{Tip, Tool};
use crate::thread::standard::wires::{best_wire, over_wires, OverWires};
use crate::thread::standard::{Profile, StandardThread, Surface};
use crate::thread::Side;
use crate::threads::{Origin, Thread};

/// The measurement over wires of one pitch diameter (mm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OverWire {
    /// The wire measured over: the one given, else the best wire of the tool's angle.
    pub wire: f64,
    /// Whether `wire` is the best wire (none was given).
    pub best: bool,
    pub m: OverWires,
}

/// A class's window on what is measured (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct Window {
    /// The class as users write it: `6g`, `2A`.
    pub class: String,
    pub pitch_diameter: (f64, f64),
    /// M over the same wire at the window's two ends (an external thread).
    pub over_wires: Option<(f64, f64)>,
    /// The change of the final depth on the radius that brings the pitch diameter to the
    /// window's middle: positive deeper.
    pub deeper: f64,
}

/// What the thread a program cuts measures.
#[derive(Clone, Debug, PartialEq)]
pub struct Reading {
    pub pitch_diameter: f64,
    pub over_wires: Option<OverWire>,
    pub window: Option<Window>,
    /// What the reading assumes (the tip, the angle), for the note beside it.
    pub assumed: Vec<String>,
}

/// The thread `t` cuts, as it will be measured, with the tool's `tip` (mm) where given, the
/// standard `thread` where named and the `wire` one owns (mm). `Err`: why it cannot be said
/// (a face or taper thread, an unknown crest, a tool form not known).
pub fn reading(
    t: &Thread,
    tip: Option<Tip>,
    thread: Option<&StandardThread>,
    wire: Option<f64>,
) -> Result<Reading, String> {
    let job = &t.job;
    let g = &job.geometry;
    let side = match g.side {
        Side::External => Surface::External,
        Side::Internal => Surface::Internal,
        Side::FaceFront | Side::FaceBack => {
            return Err("a face thread has no pitch diameter to measure over wires".into())
        }
    };
    if g.taper().abs() > 1e-9 {
        return Err("a taper thread is gauged at its gauge plane: check --thread with an NPT, R or Rc thread states its stand-off".into());
    }
    if job.lead.dlead != 0.0 {
        return Err("a variable lead has no one pitch to measure over wires".into());
    }
    if !t.crest_known() {
        return Err(
            "the crest is not known, so neither is the depth the pitch diameter lies at".into(),
        );
    }
    let target = match thread {
        Some(s) => Some(target(s, side)?),
        None => None,
    };
    let mut assumed = Vec::new();
    let stated = job.tool_angle_deg > 0.0 && matches!(t.origin, Origin::Cycle);
    let angle =
        match (&target, stated) {
            (_, true) => job.tool_angle_deg,
            (Some(target), false) => {
                assumed.push(format!(
                    "the {}° of the thread's form (the program states no angle)",
                    super::number(target.angle_deg)
                ));
                target.angle_deg
            }
            (None, false) => return Err(
                "the program states no tool angle: name the thread (--thread) to take its form's"
                    .into(),
            ),
        };
    let tip = match (tip, &target) {
        (Some(tip), _) => tip,
        (None, Some(target)) => {
            assumed.push("the standard's root form at the tool's tip (--nose-radius or --tip-flat give the real tip)".into());
            target.root_tool
        }
        (None, None) => {
            return Err("the tool's tip is not known: give --nose-radius or --tip-flat".into())
        }
    };
    let pitch = job.lead.lead / f64::from(job.lead.starts.max(1));
    let Some(pd) = measure(
        t,
        &Tool {
            angle_deg: angle,
            tip,
        },
        pitch,
    )
    .pitch_diameter
    else {
        return Err("the groove is nowhere half a pitch wide: no pitch diameter".into());
    };
    // The wires touch the flanks the tool cut: its angle's profile (only the flank angle counts).
    let mut profile = Profile::sixty(pitch);
    profile.angle_deg = angle;
    profile.flank_angle_deg = angle / 2.0;
    let lead = job.lead.lead;
    let over = (side == Surface::External).then(|| {
        let w = wire.unwrap_or_else(|| best_wire(&profile, pitch));
        OverWire {
            wire: w,
            best: wire.is_none(),
            m: over_wires(&profile, pitch, lead, pd, w),
        }
    });
    let window = target.and_then(|target| {
        let (lo, hi) = (target.limits.pitch.min?, target.limits.pitch.max?);
        let middle = (lo + hi) / 2.0;
        Some(Window {
            class: target.class_name(),
            pitch_diameter: (lo, hi),
            over_wires: over.map(|o| {
                let m = |e: f64| over_wires(&profile, pitch, lead, e, o.wire).corrected;
                (m(lo), m(hi))
            }),
            // Deeper moves an external pitch diameter down 2 per 1 of depth, an internal one up.
            deeper: match side {
                Surface::External => (pd - middle) / 2.0,
                Surface::Internal => (middle - pd) / 2.0,
            },
        })
    });
    Ok(Reading {
        pitch_diameter: pd,
        over_wires: over,
        window,
        assumed,
    })
}
