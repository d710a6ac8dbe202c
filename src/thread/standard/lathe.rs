//! A taper thread on the lathe: where its crest and root lie along a cycle's Z travel, so that a
//! controller's taper word can be computed (the dialect's `TaperWord::value`) for the thread's length
//! and position.

use serde::Serialize;

use super::{StandardThread, Surface};
use crate::diag::{Code, Diagnostic, Result, Span};

/// Where the thread is cut (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Placement {
    pub side: Surface,
    /// Z of the reference face: the small end (the pipe's end) of an external thread, the opening
    /// of an internal one.
    pub face_z: f64,
    /// Z where the cycle starts, outside the part (the run-up).
    pub start_z: f64,
    /// Length of thread from the face into the part.
    pub length: f64,
}

/// A taper thread's cycle: its Z travel and its crest and root at both ends (mm, X as radius).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TaperCycle {
    pub start_z: f64,
    pub end_z: f64,
    pub crest_start_x: f64,
    pub crest_end_x: f64,
    pub root_start_x: f64,
    pub root_end_x: f64,
    /// Radial thread depth.
    pub depth: f64,
    /// Radius at the start minus radius at the end (the same for crest and root).
    pub radial_change: f64,
}

impl TaperCycle {
    /// The crest's radius at `z` (mm), on the cone through the cycle's ends.
    pub fn crest_at(&self, z: f64) -> f64 {
        let dz = self.end_z - self.start_z;
        if dz == 0.0 {
            return self.crest_start_x;
        }
        self.crest_start_x + (self.crest_end_x - self.crest_start_x) * (z - self.start_z) / dz
    }
}

/// The cycle of a taper thread placed at `at`: the crest is the major diameter of an external
/// thread (the minor of an internal one) at the gauge plane, carried along the 1:16 taper over the
/// whole Z travel, run-up included; the root lies the thread height below it.
pub fn taper_cycle(t: &StandardThread, at: &Placement) -> Result<TaperCycle> {
    let bad = |m: String| Diagnostic::error(Code::OutOfRange, Span::default(), m);
    let Some(tp) = t.taper else {
        return Err(bad(format!("{} is not a taper thread", t.name)));
    };
    let finite = [at.face_z, at.start_z, at.length]
        .iter()
        .all(|v| v.is_finite());
    if !finite || at.length <= 0.0 || at.start_z == at.face_z {
        return Err(bad(
            "the cycle needs a positive length and a start Z off the face".to_string(),
        ));
    }
    // Into the part is away from the start point.
    let dir = if at.start_z > at.face_z { -1.0 } else { 1.0 };
    let end_z = at.face_z + dir * at.length;
    let k = tp.diameter_per_length / 2.0;
    let s = |z: f64| (z - at.face_z) * dir;
    let pd_gauge = tp.gauge_pitch_diameter;
    let (crest_gauge, grow, depth) = match at.side {
        // The external crest (major) grows into the part from the small end.
        Surface::External => (tp.gauge_major_diameter / 2.0, 1.0, t.external_depth),
        // The internal crest (minor) shrinks into the part from the opening; the form is
        // symmetric about the pitch line.
        Surface::Internal => (
            pd_gauge - tp.gauge_major_diameter / 2.0,
            -1.0,
            t.internal_depth,
        ),
    };
    let gauge_s = tp.gauge_plane_from_face(at.side);
    let crest = |z: f64| crest_gauge + grow * k * (s(z) - gauge_s);
    let into = match at.side {
        Surface::External => -1.0,
        Surface::Internal => 1.0,
    };
    let (cs, ce) = (crest(at.start_z), crest(end_z));
    Ok(TaperCycle {
        start_z: at.start_z,
        end_z,
        crest_start_x: cs,
        crest_end_x: ce,
        root_start_x: cs + into * depth,
        root_end_x: ce + into * depth,
        depth,
        radial_change: cs - ce,
    })
}
