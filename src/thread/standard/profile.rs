//! Thread forms: the included angle, the shapes of crest and root, and the groove an external
//! thread's maximum-material profile leaves between two crests (what a form tool cuts and what the
//! simulation is judged against).

use serde::Serialize;

use super::{Limits, H_PER_P};

/// The shape of a crest or a root.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Edge {
    /// The fundamental triangle's corner.
    Sharp,
    /// A flat of this width along the axis (mm).
    Flat { width: f64 },
    /// An arc of this radius tangent to both flanks (mm).
    Round { radius: f64 },
    /// Truncated from the sharp corner by a radial height between `min` and `max` (mm), flat or
    /// rounded (ASME B1.20.1 §2.4: "a radius form is acceptable, as long as the crests and roots
    /// lie within the limits").
    Truncated { min: f64, max: f64 },
}

/// A thread form (symmetric: both flanks at half the included angle from the radial direction).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Profile {
    /// Included angle between the flanks (degrees).
    pub angle_deg: f64,
    /// Flank angle from the radial direction (degrees): half the included angle.
    pub flank_angle_deg: f64,
    /// Height of the fundamental triangle H (mm).
    pub fundamental_height: f64,
    /// Basic (design) shapes, external thread first.
    pub external_crest: Edge,
    pub external_root: Edge,
    pub internal_crest: Edge,
    pub internal_root: Edge,
}

impl Profile {
    /// ISO 68-1 / ASME B1.1 60° form: crests flat P/8 (external) and P/4 (internal), the external
    /// root rounded to R = H/6 (ISO 965-1 d3), the internal root flat P/8.
    pub fn sixty(p: f64) -> Profile {
        Profile {
            angle_deg: 60.0,
            flank_angle_deg: 30.0,
            fundamental_height: H_PER_P * p,
            external_crest: Edge::Flat { width: p / 8.0 },
            external_root: Edge::Round {
                radius: H_PER_P * p / 6.0,
            },
            internal_crest: Edge::Flat { width: p / 4.0 },
            internal_root: Edge::Flat { width: p / 8.0 },
        }
    }

    /// tan of the flank angle: lateral run of a flank per unit of depth.
    pub fn slope(&self) -> f64 {
        self.flank_angle_deg.to_radians().tan()
    }
}

/// The space between two crests of a thread at maximum material, in the axial section: `u` along
/// the axis (0 on the groove's centre), `v` the depth below the crest line (the major diameter of
/// an external thread, the minor diameter of an internal one). Its flanks pass through the pitch
/// line, where the groove is half a pitch wide.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Groove {
    pub pitch: f64,
    pub flank_angle_deg: f64,
    /// Depth of the pitch line below the crest line (mm).
    pub pitch_line_depth: f64,
    /// Depth of the root (mm): the turning infeed to the maximum-material root.
    pub depth: f64,
    /// The root's shape: a flat (its width follows from the rest) or a radius.
    pub root: Edge,
}

impl Groove {
    /// The groove of one side's limits at maximum material: an external thread from its largest
    /// major diameter down to its largest minor diameter, through its largest pitch diameter; an
    /// internal one from its smallest minor up to its smallest major, through its smallest pitch
    /// diameter. `None` when the limits leave the root open (no maximum minor / minimum major).
    pub fn at_maximum_material(limits: &Limits, pitch: f64, profile: &Profile) -> Option<Groove> {
        use super::Surface;
        let (crest, pd, root) = match limits.side {
            Surface::External => (limits.major.max?, limits.pitch.max?, limits.minor.max?),
            Surface::Internal => (limits.minor.min?, limits.pitch.min?, limits.major.min?),
        };
        let root_edge = match limits.side {
            Surface::External => profile.external_root,
            Surface::Internal => profile.internal_root,
        };
        let mut g = Groove {
            pitch,
            flank_angle_deg: profile.flank_angle_deg,
            pitch_line_depth: (crest - pd).abs() / 2.0,
            depth: (crest - root).abs() / 2.0,
            root: root_edge,
        };
        if !matches!(g.root, Edge::Round { .. }) {
            g.root = Edge::Flat {
                width: g.width_at(g.depth).max(0.0),
            };
        }
        Some(g)
    }

    /// tan of the flank angle.
    pub fn slope(&self) -> f64 {
        self.flank_angle_deg.to_radians().tan()
    }

    /// The width between the flank lines at depth `v` (mm).
    pub fn width_at(&self, v: f64) -> f64 {
        self.pitch / 2.0 + 2.0 * self.slope() * (self.pitch_line_depth - v)
    }

    /// The groove's outline from the left crest corner (depth 0) down the left flank, across the
    /// root and up to the right crest corner, centred on `u = centre`. A round root is drawn with
    /// chords no more than `tolerance` from the arc.
    pub fn outline(&self, centre: f64, tolerance: f64) -> Vec<(f64, f64)> {
        let t = self.slope();
        let top = self.width_at(0.0) / 2.0;
        let mut pts = vec![(centre - top, 0.0)];
        match self.root {
            Edge::Round { radius } if radius > 0.0 => {
                // The arc tangent to both flanks, its lowest point at the root depth.
                let alpha = self.flank_angle_deg.to_radians();
                let cv = self.depth - radius;
                let span = std::f64::consts::PI - 2.0 * alpha;
                let theta = 2.0 * (1.0 - (tolerance / radius).min(1.0)).acos();
                let n = ((span / theta.max(1e-6)).ceil() as usize).clamp(2, 4096);
                for i in 0..=n {
                    // From the left tangent point (angle π − α, v downward) to the right one (α).
                    let a = std::f64::consts::PI - alpha - span * i as f64 / n as f64;
                    pts.push((centre + radius * a.cos(), cv + radius * a.sin()));
                }
            }
            _ => {
                let half = (top - self.depth * t).max(0.0);
                pts.push((centre - half, self.depth));
                pts.push((centre + half, self.depth));
            }
        }
        pts.push((centre + top, 0.0));
        pts
    }
}
