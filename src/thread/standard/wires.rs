//! Three-wire measurement of an external thread: the wire sizes that fit its groove and the
//! measurement over wires `M` that a given pitch diameter shows (docs/standard-threads.md, "Three
//! wires").
//!
//! With α the half angle of the thread, P the pitch, L the lead, E the pitch diameter and w the
//! wire's diameter (NBS Handbook H28, the three-wire method, as reproduced in ASME B1.2's appendix
//! and Machinery's Handbook):
//!
//! * best wire `w = P / (2·cos α)`: it touches both flanks on the pitch line;
//! * simple formula `M = E − P·cot α / 2 + w·(1 + cosec α)` (60°: `M = E − 0.866025·P + 3w`);
//! * with the lead angle λ (`tan λ = L / (π·E)`, the wire lying along the helix), H28's series form
//!   `M = E − P·cot α / 2 + w·(1 + cosec α + ½·tan²λ·cos α·cot α)`;
//! * the wires that touch the flanks: the largest touches them where the external thread's crest
//!   begins (a larger one rests on the crest's edges); the smallest still stands above the crest
//!   (the micrometer's anvils must bear on the wires, not on the thread) and clears the root.
//!
//! The geometry is that of the basic profile ([`Profile`]): its fundamental triangle of height H,
//! whose groove is half a pitch wide on the pitch line, H/2 below the sharp crest.

use serde::Serialize;

use super::{Edge, Limits, Profile, StandardThread, Surface};

/// The measurement over three wires at one pitch diameter (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OverWires {
    /// The pitch diameter E.
    pub pitch_diameter: f64,
    /// M by the simple formula.
    pub simple: f64,
    /// M with the lead-angle correction (H28's series form).
    pub corrected: f64,
}

/// A thread's three-wire data for one wire size (mm).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Wires {
    /// The wire measured with: the best wire unless one was given.
    pub wire: f64,
    /// The best wire, touching the flanks on the pitch line.
    pub best: f64,
    /// The smallest and largest wires that touch the flanks.
    pub min: f64,
    pub max: f64,
    /// Whether `wire` lies between `min` and `max`.
    pub fits: bool,
    /// M at the basic pitch diameter.
    pub basic: OverWires,
    /// M at the external class's least (min) and largest (max) pitch diameter, where the thread
    /// has an external class.
    pub limits: Option<(OverWires, OverWires)>,
    /// The class these limits are of.
    pub class: Option<String>,
}

/// tan, cos, sin of the half angle α, and cot α.
struct Angle {
    tan: f64,
    cos: f64,
    sin: f64,
}

impl Angle {
    fn of(p: &Profile) -> Angle {
        let a = p.flank_angle_deg.to_radians();
        Angle {
            tan: a.tan(),
            cos: a.cos(),
            sin: a.sin(),
        }
    }
}

/// The best wire of a form and pitch: `P / (2·cos α)` (mm).
pub fn best_wire(profile: &Profile, pitch: f64) -> f64 {
    pitch / (2.0 * Angle::of(profile).cos)
}

/// M over wires of diameter `wire` at pitch diameter `e` (mm), by both formulas; `lead` is the
/// thread's lead (the pitch for a single start).
pub fn over_wires(profile: &Profile, pitch: f64, lead: f64, e: f64, wire: f64) -> OverWires {
    let a = Angle::of(profile);
    let cot = 1.0 / a.tan;
    let simple = e - pitch * cot / 2.0 + wire * (1.0 + 1.0 / a.sin);
    let tan_lead = lead / (std::f64::consts::PI * e);
    let corrected = simple + wire * 0.5 * tan_lead * tan_lead * a.cos * cot;
    OverWires {
        pitch_diameter: e,
        simple,
        corrected,
    }
}

/// The pitch diameter that shows `m` over wires of diameter `wire` by the corrected formula: the
/// inverse of [`over_wires`] (the lead angle taken at `m`'s own pitch diameter, found by a few
/// fixed-point steps, each changing E by less than 1e-4 of the last).
pub fn pitch_diameter_from(profile: &Profile, pitch: f64, lead: f64, m: f64, wire: f64) -> f64 {
    let mut e = m;
    for _ in 0..8 {
        let at = over_wires(profile, pitch, lead, e, wire);
        e -= at.corrected - m;
    }
    e
}

/// Depth of the end of the straight flank below the sharp crest, and the depth of the crest's top
/// below it, for an external crest of the form (mm).
fn crest_depths(edge: Edge, a: &Angle) -> (f64, f64) {
    match edge {
        Edge::Sharp => (0.0, 0.0),
        Edge::Flat { width } => {
            let t = width / (2.0 * a.tan);
            (t, t)
        }
        // The arc tangent to both flanks: its centre r/sin α below the sharp crest, its tangent
        // points r·cot α along the flanks (r·cot α·cos α deep), its top r above its centre.
        Edge::Round { radius } => (radius / a.tan * a.cos, radius / a.sin - radius),
        // Truncated within limits: the flank may end as early as the largest truncation, the crest
        // stands as high as the smallest.
        Edge::Truncated { min, max } => (max, min),
    }
}

/// Height of the external root's highest point above the groove's sharp apex (mm).
fn root_height(edge: Edge, a: &Angle) -> f64 {
    match edge {
        Edge::Sharp => 0.0,
        Edge::Flat { width } => width / (2.0 * a.tan),
        Edge::Round { radius } => radius / a.sin - radius,
        Edge::Truncated { max, .. } => max,
    }
}

/// The smallest and largest wires that touch the flanks of the basic external profile (mm).
pub fn wire_range(profile: &Profile, pitch: f64) -> (f64, f64) {
    let a = Angle::of(profile);
    let h = profile.fundamental_height;
    let cosec = 1.0 / a.sin;
    let (flank_end, crest_top) = crest_depths(profile.external_crest, &a);
    // A wire of radius r touches a flank r·cos α from its centre along the axis: where the groove
    // is 2·r·cos α wide. The groove is P − 2·y·tan α wide y below the sharp crest.
    let largest = (pitch / 2.0 - flank_end * a.tan) / a.cos;
    // The wire's centre lies r·cosec α above the apex (H below the sharp crest): its top must
    // reach the crest, its bottom clear the root.
    let above_crest = (h - crest_top) / (1.0 + cosec);
    let above_root = root_height(profile.external_root, &a) / (cosec - 1.0);
    (2.0 * above_crest.max(above_root), 2.0 * largest)
}

impl StandardThread {
    /// The three-wire data with `wire` (mm), or with the best wire. The limits are the external
    /// class's (the one the name asks for, else the default class); a thread named only by its
    /// internal class has none (an internal thread is gauged, not measured over wires). A taper
    /// thread's values are at its gauge plane.
    pub fn wires(&self, wire: Option<f64>) -> Wires {
        let p = &self.profile;
        let best = best_wire(p, self.pitch);
        let (min, max) = wire_range(p, self.pitch);
        let w = wire.unwrap_or(best);
        let at = |e: f64| over_wires(p, self.pitch, self.pitch, e, w);
        let external: Option<Limits> = match (self.external, self.internal) {
            (Some(l), _) => Some(l),
            (None, None) => Some(self.limits(Surface::External)),
            (None, Some(_)) => None,
        };
        let limits = external.and_then(|l| Some((at(l.pitch.min?), at(l.pitch.max?))));
        Wires {
            wire: w,
            best,
            min,
            max,
            fits: w >= min - 1e-9 && w <= max + 1e-9,
            basic: at(self.basic.pitch_diameter),
            class: limits.and(external).map(|l| l.class.to_string()),
            limits,
        }
    }
}

/// The formulas [`Wires`] uses, as `threadcut thread` names them.
pub const FORMULAS: &str = "simple: M = E − P·cot α/2 + w·(1 + cosec α); with the lead angle λ (tan λ = L/(π·E)): + w·½·tan²λ·cos α·cot α (NBS Handbook H28's three-wire method, as in ASME B1.2)";

impl Wires {
    /// `{wire, best, min, max, fits, formula, basic, class, limits}` in `units` (M, E and wires
    /// rounded to 1e-6 of the unit); `basic` and each of `limits.min` / `limits.max` is
    /// `{pitch_diameter, simple, corrected}`.
    pub fn to_json(&self, units: crate::units::Units) -> serde_json::Value {
        use serde_json::json;
        let n = |mm: f64| json!((units.from_mm(mm) * 1e6).round() / 1e6);
        let at = |o: &OverWires| {
            json!({
                "pitch_diameter": n(o.pitch_diameter),
                "simple": n(o.simple),
                "corrected": n(o.corrected),
            })
        };
        json!({
            "wire": n(self.wire),
            "best": n(self.best),
            "min": n(self.min),
            "max": n(self.max),
            "fits": self.fits,
            "formula": FORMULAS,
            "basic": at(&self.basic),
            "class": self.class,
            "limits": self.limits.as_ref().map(|(lo, hi)| json!({"min": at(lo), "max": at(hi)})),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::super::lookup;
    use super::*;

    const IN: f64 = 25.4;

    fn near(a: f64, b: f64, tol: f64, what: &str) {
        assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
    }

    /// Metric 60°: the example table of the codingace.net metric over-wires calculator (best wire,
    /// basic pitch diameter, M over wires by the simple formula, to 6 decimals in mm): M8x1.25
    /// 0.721688 / 7.188101 / 8.270633, M10x1.5 0.866025 / 9.025721 / 10.324760, M12x1.75
    /// 1.010363 / 10.863342 / 12.378887.
    #[test]
    fn metric_best_wire_and_m_at_basic_match_the_published_table() {
        for (name, best, e, m) in [
            ("M8x1.25", 0.721688, 7.188101, 8.270633),
            ("M10x1.5", 0.866025, 9.025721, 10.324760),
            ("M12x1.75", 1.010363, 10.863342, 12.378887),
        ] {
            let w = lookup(name).unwrap().wires(None);
            near(w.best, best, 1e-6, name);
            near(w.basic.pitch_diameter, e, 1e-6, name);
            near(w.basic.simple, m, 1e-6, name);
        }
    }

    /// Unified 60°: the neme-s.org three-wire note works 7/16-14 with a 0.045 in wire:
    /// M = D + 3W − 1.5155/N = 0.4375 + 0.135 − 0.1083 = 0.464 in, and gives the best wire
    /// 0.57735/N = 0.041 in and (H28) the largest 1.010363/N and smallest 0.505182/N.
    #[test]
    fn unified_with_a_wire_of_ones_own() {
        let t = lookup("7/16-14 UNC").unwrap();
        let w = t.wires(Some(0.045 * IN));
        near(w.basic.simple / IN, 0.4642, 1e-4, "M over 0.045 wires");
        near(w.best / IN, 0.57735 / 14.0, 1e-6, "best wire");
        near(w.max / IN, 1.010363 / 14.0, 1e-6, "largest wire");
        near(w.min / IN, 0.505182 / 14.0, 1e-6, "smallest wire");
        assert!(w.fits);
        // 1 1/2-6 (Jones, Turning and Boring, US standard form = Unified's 60° basic form) over
        // 0.140 in wires: 1.5 − 1.5155/6 + 3·0.140 = 1.6674 in.
        let t = lookup("1-1/2-6 UNC").unwrap();
        near(
            t.wires(Some(0.140 * IN)).basic.simple / IN,
            1.6674,
            1e-4,
            "1 1/2-6",
        );
    }

    /// Whitworth 55°: Jones (Turning and Boring) gives m = d − 1.6008·p + 3.1657·w, from the major
    /// diameter d = E + 0.640327·p (BS 84): m − E = −0.960473·p + 3.1657·w. 1/2-12 BSW over 0.050 in
    /// wires: −0.960473/12 + 3.1657·0.050 = 0.078246 in above E (0.4466, BS 84's table).
    #[test]
    fn whitworth_constants() {
        let t = lookup("1/2-12 BSW").unwrap();
        let w = t.wires(Some(0.050 * IN));
        near(w.basic.pitch_diameter / IN, 0.4466, 1e-9, "BSW E");
        near(
            (w.basic.simple - w.basic.pitch_diameter) / IN,
            0.078246,
            5e-6,
            "BSW",
        );
        // Best wire P/(2·cos 27.5°) = 0.563691·P.
        near(w.best / IN, 0.563691 / 12.0, 1e-6, "BSW best wire");
    }

    /// Trapezoidal 30° and Acme 29°: best wire 0.517638·P and 0.516450·P (P/(2·cos α)); with the
    /// best wire M = E + P·(1/(2 cos α) · (1 + cosec α) − cot α / 2): hand-computed for Tr40x7,
    /// E 36.5: w = 3.623467, M = 36.5 − 7·3.732051/2 + 3.623467·(1 + 3.863703) = 36.5 − 13.062178
    /// + 17.623467 = 41.061289 mm.
    #[test]
    fn trapezoidal_and_acme_best_wire() {
        let t = lookup("Tr40x7").unwrap();
        let w = t.wires(None);
        near(w.best, 3.623467, 1e-6, "Tr best wire");
        near(w.basic.simple, 41.061289, 1e-6, "Tr M");
        let t = lookup("1-5 ACME-2G").unwrap();
        near(
            t.wires(None).best / IN,
            0.516450 / 5.0,
            1e-6,
            "Acme best wire",
        );
    }

    /// The lead-angle term ½·tan²λ·cos α·cot α·w: hand-computed for 1-5 Acme (E basic 0.9 in,
    /// best wire 0.10329 in): tan λ = 0.2/(π·0.9) = 0.070736; ½·0.0050036·0.968148·3.866713·0.10329
    /// = 0.00096736 in.
    #[test]
    fn lead_angle_correction_is_the_series_term() {
        let t = lookup("1-5 ACME-2G").unwrap();
        let w = t.wires(None);
        let e = w.basic.pitch_diameter / IN;
        near(e, 0.9, 1e-9, "Acme E");
        near(
            (w.basic.corrected - w.basic.simple) / IN,
            0.000_967_36,
            1e-8,
            "correction",
        );
        // The inverse returns E.
        let back = pitch_diameter_from(&t.profile, t.pitch, t.pitch, w.basic.corrected, w.wire);
        near(back, w.basic.pitch_diameter, 1e-9, "inverse");
    }

    /// Each limit of the class gives its own M: M12x1.75-6g, d2 10.679–10.829 (ISO 965-2), best
    /// wire: M = d2 + 0.866025·1.75 = d2 + 1.515544.
    #[test]
    fn class_limits_move_m_one_for_one() {
        let w = lookup("M12x1.75-6g").unwrap().wires(None);
        let (lo, hi) = w.limits.unwrap();
        near(lo.simple, 12.194544, 1e-6, "min");
        near(hi.simple, 12.344544, 1e-6, "max");
        assert_eq!(w.class.as_deref(), Some("6g"));
        assert!(lookup("M12x1.75-6H").unwrap().wires(None).limits.is_none());
    }
}
