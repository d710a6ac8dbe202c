//! The blank a thread is cut in, as far as the program and the options say where it is, and what
//! `check` assumes where they do not (docs/simulation.md, "The blank").
//!
//! * Its surface: the stock's diameter when given (`--stock-diameter`); otherwise the thread's
//!   crest (the stock is turned to the crest before threading): a cycle's crest line, the crest
//!   the caller gave for a thread written as moves, else that thread's first pass (the blank
//!   reaches at least that far: the first pass cuts something).
//! * Its face on the side where the thread starts: `--stock-start` when given; otherwise Z0 when
//!   the thread runs toward −Z from a start point at or in front of Z0 and ends behind it (on
//!   almost every lathe program Z0 is the part's face); otherwise not known, and the blank is
//!   taken to begin at the tool's start point (which the program has put clear of the part), with
//!   no run-up judged.
//! * For a thread that runs toward +Z out through Z0, the blank ends at Z0.

use crate::thread::{Job, Side};
use crate::units::{Pos, Resolution, Tolerance, Units};

/// Where a boundary of the blank comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Known {
    /// The user gave it.
    Given,
    /// Inferred: Z0 as the face; the crest as the stock.
    Assumed,
    /// Not known: the start point, or the first pass, stands in for it.
    Unknown,
}

/// The blank in the XZ plane: between the face `z_face` and the thread's end, from the surface
/// into the part.
#[derive(Clone, Copy, Debug)]
pub struct Blank {
    pub side: Side,
    /// Z of the face where the thread starts, and of the blank's end along the thread.
    pub z_face: f64,
    pub z_end: f64,
    /// The surface's radius at `z_face` and at `z_end`.
    pub x_face: f64,
    pub x_end: f64,
    /// Stock above the crest line (mm, at the thread's start), for the section.
    pub stock_above: f64,
    /// +1 when the thread runs toward −Z, −1 toward +Z.
    pub backward: f64,
    pub face: Known,
    pub surface: Known,
    /// The program's units, for messages.
    pub units: Units,
    /// Lengths along Z (the face, run-ups, a rapid along the axis) within this are the same: one
    /// increment of the program's resolution.
    pub z_tol: Tolerance,
    /// Radii (the surface) within this are the same: one increment of the written X.
    pub x_tol: Tolerance,
}

impl Blank {
    /// The blank of `job`'s thread, whose toolpath starts at `start`. `stock_diameter` and
    /// `stock_start` are the user's, in program units; `crest_known` says whether the job's crest
    /// is the thread's crest (a cycle's, or one the user gave) or only its first pass. Points
    /// within the program's `resolution` of a boundary are on it (a start point written at the
    /// crest does not enter the blank).
    pub fn new(
        job: &Job,
        start: Pos,
        stock_diameter: Option<f64>,
        stock_start: Option<f64>,
        crest_known: bool,
        resolution: Resolution,
    ) -> Blank {
        let g = &job.geometry;
        let units = job.units;
        let (z_tol, x_tol) = (resolution.length(), resolution.x());
        let dz = g.crest_end.z - g.crest_start.z;
        let backward = if dz < 0.0 { 1.0 } else { -1.0 };
        let (z_face, face) = match stock_start {
            Some(z) => (units.to_mm(z), Known::Given),
            None if dz < 0.0 && !z_tol.lt(start.z, 0.0) && z_tol.lt(g.crest_end.z, 0.0) => {
                (0.0, Known::Assumed)
            }
            None => (start.z, Known::Unknown),
        };
        // A thread that runs out through Z0 toward +Z ends at the face.
        let z_end = if stock_start.is_none()
            && dz > 0.0
            && z_tol.gt(g.crest_end.z, 0.0)
            && z_tol.lt(z_face, 0.0)
        {
            0.0
        } else {
            g.crest_end.z
        };
        let crest_at = |z: f64| {
            if dz == 0.0 {
                g.crest_start.x
            } else {
                g.crest_start.x + (g.crest_end.x - g.crest_start.x) * (z - g.crest_start.z) / dz
            }
        };
        let (x_face, x_end, surface) = match stock_diameter {
            Some(d) => {
                let r = units.to_mm(d) / 2.0;
                (r, r, Known::Given)
            }
            None => (
                crest_at(z_face),
                crest_at(z_end),
                if crest_known {
                    Known::Assumed
                } else {
                    Known::Unknown
                },
            ),
        };
        let stock_above = (x_face - crest_at(z_face)) * g.side.outward().x;
        Blank {
            side: g.side,
            z_face,
            z_end,
            x_face,
            x_end,
            stock_above,
            backward,
            face,
            surface,
            units,
            z_tol,
            x_tol,
        }
    }

    /// Both boundaries were given by the user: a rapid move into the blank is a fact.
    pub fn given(&self) -> bool {
        self.face == Known::Given && self.surface == Known::Given
    }

    /// What the blank rests on, for messages: `the part's face assumed at Z0 and the blank at the
    /// crest (Ø30)`.
    pub fn assumptions(&self) -> Option<String> {
        let show = |mm: f64| super::length(self.units, mm);
        let dia = |r: f64| format!("Ø{}", show(2.0 * r.abs()));
        let face = match self.face {
            Known::Given => None,
            Known::Assumed => Some("the part's face assumed at Z0".to_string()),
            Known::Unknown => Some(format!(
                "the part's face not known (taken at the start point's Z{})",
                show(self.z_face)
            )),
        };
        let surface = match self.surface {
            Known::Given => None,
            Known::Assumed => Some(format!(
                "the blank assumed turned to the thread's crest ({})",
                dia(self.x_face)
            )),
            Known::Unknown => Some(format!(
                "the crest not known (the blank taken to reach the first pass, {})",
                dia(self.x_face)
            )),
        };
        match (face, surface) {
            (None, None) => None,
            (Some(a), None) | (None, Some(a)) => Some(a),
            (Some(a), Some(b)) => Some(format!("{a} and {b}")),
        }
    }

    /// The blank as a convex quadrilateral in (z, x), shrunk by the resolution (`z_tol` at the
    /// face and the end, `x_tol` at the surface): half-planes `a·z + b·x ≤ c`.
    fn half_planes(&self) -> [(f64, f64, f64); 4] {
        let (ez, eps) = (self.z_tol.get(), self.x_tol.get());
        let (z0, z1) = (self.z_face.min(self.z_end), self.z_face.max(self.z_end));
        // The surface line x = x_face + k·(z − z_face).
        let k = if self.z_end != self.z_face {
            (self.x_end - self.x_face) / (self.z_end - self.z_face)
        } else {
            0.0
        };
        let norm = (1.0 + k * k).sqrt();
        // External: x ≤ surface, x ≥ 0. Internal: x ≥ surface, x ≤ a far bound.
        let (surface, far) = match self.side {
            Side::External => (
                (
                    -k / norm,
                    1.0 / norm,
                    (self.x_face - k * self.z_face) / norm - eps,
                ),
                (0.0, -1.0, -eps),
            ),
            Side::Internal => (
                (
                    k / norm,
                    -1.0 / norm,
                    -(self.x_face - k * self.z_face) / norm - eps,
                ),
                (0.0, 1.0, self.x_face.max(self.x_end) + 1e4),
            ),
            // The blank is modelled for turned threads only: for a face thread no point lies
            // inside (0 ≤ −1), so no rapid is reported as entering it (docs/simulation.md).
            Side::FaceFront | Side::FaceBack => ((0.0, 0.0, -1.0), (0.0, 0.0, -1.0)),
        };
        [(-1.0, 0.0, -z0 - ez), (1.0, 0.0, z1 - ez), surface, far]
    }

    /// Whether a rapid move from `a` to `b` runs into the blank's interior. A move that starts
    /// inside (the tool at the end of its thread move, in the groove it has just cut) may only
    /// leave straight outward, along X; one that starts outside must not enter.
    pub fn entered_by(&self, a: Pos, b: Pos) -> bool {
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (pa, pb, c) in self.half_planes() {
            let fa = pa * a.z + pb * a.x - c;
            let d = pa * (b.z - a.z) + pb * (b.x - a.x);
            if d == 0.0 {
                if fa > 0.0 {
                    return false;
                }
            } else {
                let t = -fa / d;
                if d < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        if t0 >= t1 {
            return false;
        }
        let starts_inside = t0 <= 0.0;
        if starts_inside {
            let outward = (b.x - a.x) * self.side.outward().x;
            let along = (b.z - a.z).abs();
            return !(self.z_tol.is_zero(along) && outward > 0.0);
        }
        true
    }

    /// How far `z` lies before the face, along the thread (negative: inside the blank).
    pub fn before_face(&self, z: f64) -> f64 {
        (z - self.z_face) * self.backward
    }
}
