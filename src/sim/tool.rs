//! The threading tool's form in the axial section: a V of the included angle whose lowest point is
//! the tool's setting point, with a sharp, rounded (nose radius) or flat tip.
//!
//! Section coordinates: `u` is the lateral (+Z) position, `v` the depth below the crest line (into
//! the material). A tool placed at `(u0, d)` has its lowest point at depth `d` on the line `u = u0`:
//! that is the point the control drives along the pass (the tool is touched off on it).

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result, Span};

/// The largest distance (mm) between a nose radius and the chord polygon that stands for it in the
/// boolean operations: 0.5 µm, half the 0.001 mm input resolution of the controls threadcut reads.
/// The number of chords follows from it and the radius ([`NosePolygon`]).
pub const NOSE_TOLERANCE: f64 = 0.5e-3;

/// The most chords a nose is flattened into, whatever its radius: reached only by radii of
/// hundreds of millimetres (≈ 600 mm at the widest arc), far beyond any threading tool, where the
/// outline may then stray further than [`NOSE_TOLERANCE`] (see [`NosePolygon::deviation`]).
pub const NOSE_SEGMENTS_MAX: usize = 1024;

/// A nose arc flattened into `segments` chords of equal angle `theta`, with the same area as the
/// arc: the end vertices are the tangent points on the flanks (radius r, so the flanks stay
/// exact), the inner vertices lie on a slightly larger radius `rho`, chosen so that the fan of
/// triangles from the centre has the sector's area. So a chip that takes the whole nose has the
/// exact area, and the outline is within [`NOSE_TOLERANCE`] of the arc everywhere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NosePolygon {
    pub segments: usize,
    /// Angle of each chord seen from the centre (radians).
    pub theta: f64,
    /// Radius of the inner vertices (mm).
    pub rho: f64,
    /// Largest distance between the polygon and the arc (mm).
    pub deviation: f64,
}

impl NosePolygon {
    /// The coarsest polygon within [`NOSE_TOLERANCE`] of an arc of `radius` spanning `span`
    /// radians (π − the included angle), at least 2 chords.
    pub fn new(radius: f64, span: f64) -> NosePolygon {
        // The inner vertices stand out by ≈ r·θ²/12·n/(n − 1), at least 2/3 of the chord sagitta
        // r·(1 − cos(θ/2)) ≈ r·θ²/8; so at least √(2/3) ≈ 0.82 of the count the sagitta alone
        // would need is needed: count up from 0.75 of it.
        let guess = if radius > NOSE_TOLERANCE {
            let theta = 2.0 * (1.0 - NOSE_TOLERANCE / radius).acos();
            (0.75 * span / theta).floor() as usize
        } else {
            2
        };
        let mut n = guess.clamp(2, NOSE_SEGMENTS_MAX);
        loop {
            let poly = NosePolygon::with_segments(radius, span, n);
            if poly.deviation <= NOSE_TOLERANCE || n >= NOSE_SEGMENTS_MAX {
                return poly;
            }
            n += 1;
        }
    }

    /// The area-preserving polygon of `n ≥ 2` chords.
    pub fn with_segments(radius: f64, span: f64, n: usize) -> NosePolygon {
        let r = radius;
        let theta = span / n as f64;
        let (s, c) = theta.sin_cos();
        // Fan area with two end triangles ½·r·ρ·sin θ and n − 2 inner ones ½·ρ²·sin θ equals the
        // sector's ½·r²·n·θ: (n − 2)·ρ² + 2·r·ρ − r²·nθ/sin θ = 0, solved without cancellation.
        let k = n as f64 * theta / s;
        let m = (n - 2) as f64;
        let rho = r * k / (1.0 + (1.0 + m * k).sqrt());
        // Deviation: the inner vertices stand out by ρ − r; the inner chords dip to ρ·cos(θ/2),
        // the end chords (from r to ρ) to r·ρ·sin θ / |chord|.
        let end_chord = (r * r + rho * rho - 2.0 * r * rho * c).sqrt();
        let end_dip = if end_chord > 0.0 {
            r - r * rho * s / end_chord
        } else {
            0.0
        };
        let mut deviation = end_dip;
        if n > 2 {
            deviation = deviation.max(r - rho * (theta / 2.0).cos());
        }
        deviation = deviation.max(rho - r);
        NosePolygon {
            segments: n,
            theta,
            rho,
            deviation,
        }
    }

    /// The polygon's vertices from the start angle `from` (radians, from +u with v downward)
    /// toward decreasing angles, around `centre`.
    fn vertices(&self, centre: (f64, f64), radius: f64, from: f64, pts: &mut Vec<(f64, f64)>) {
        for i in 0..=self.segments {
            let rad = if i == 0 || i == self.segments {
                radius
            } else {
                self.rho
            };
            let a = from - self.theta * i as f64;
            pts.push((centre.0 + rad * a.cos(), centre.1 + rad * a.sin()));
        }
    }
}

/// The tip of the tool.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum Tip {
    /// A sharp point.
    Sharp,
    /// A nose radius (mm) tangent to both flanks.
    Radius { radius: f64 },
    /// A flat of this width (mm) across the tip, perpendicular to the infeed.
    Flat { width: f64 },
}

/// A threading tool as the section sees it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tool {
    /// Included angle between the flanks (degrees).
    pub angle_deg: f64,
    pub tip: Tip,
}

impl Tool {
    pub const fn sharp(angle_deg: f64) -> Tool {
        Tool {
            angle_deg,
            tip: Tip::Sharp,
        }
    }

    /// The form tool that cuts a standard thread's groove in one plunge: the groove's included
    /// angle and its root — a flat tip as wide as a flat root (the 29° Acme and 30° trapezoidal
    /// forms), a nose radius for a round root (the 55° Whitworth and pipe forms), sharp
    /// otherwise.
    pub fn for_groove(groove: &crate::thread::standard::Groove) -> Tool {
        use crate::thread::standard::Edge;
        Tool {
            angle_deg: 2.0 * groove.flank_angle_deg,
            tip: match groove.root {
                Edge::Flat { width } => Tip::Flat { width },
                Edge::Round { radius } => Tip::Radius { radius },
                Edge::Sharp | Edge::Truncated { .. } => Tip::Sharp,
            },
        }
    }

    /// Refuses tools that have no sensible outline.
    pub fn validate(&self, span: Span) -> Result<()> {
        if !(self.angle_deg > 0.0 && self.angle_deg < 180.0) {
            return Err(Diagnostic::error(
                Code::OutOfRange,
                span,
                format!(
                    "tool angle {}° cannot be simulated: the included angle must lie between 0° and 180°",
                    self.angle_deg
                ),
            ));
        }
        let bad = match self.tip {
            Tip::Sharp => None,
            Tip::Radius { radius } => (!(radius >= 0.0 && radius.is_finite()))
                .then(|| format!("nose radius {radius} must be a finite length of 0 or more")),
            Tip::Flat { width } => (!(width >= 0.0 && width.is_finite()))
                .then(|| format!("tip flat {width} must be a finite length of 0 or more")),
        };
        match bad {
            Some(msg) => Err(Diagnostic::error(Code::OutOfRange, span, msg)),
            None => Ok(()),
        }
    }

    /// tan of the half angle: lateral run of a flank per unit of depth.
    pub fn slope(&self) -> f64 {
        (self.angle_deg / 2.0).to_radians().tan()
    }

    /// How far below its lowest point the tool's flanks, extended, would meet: sharp 0; nose
    /// radius r: `r/sin α − r`; flat w: `w/(2·tan α)`.
    pub fn apex_below_lowest(&self) -> f64 {
        let half = (self.angle_deg / 2.0).to_radians();
        match self.tip {
            Tip::Sharp => 0.0,
            Tip::Radius { radius } => radius / half.sin() - radius,
            Tip::Flat { width } => width / 2.0 / half.tan(),
        }
    }

    /// The chord polygon that stands for the nose radius in the boolean operations, if there is
    /// one.
    pub fn nose_polygon(&self) -> Option<NosePolygon> {
        match self.tip {
            Tip::Radius { radius } if radius > 0.0 => {
                let half = (self.angle_deg / 2.0).to_radians();
                Some(NosePolygon::new(radius, std::f64::consts::PI - 2.0 * half))
            }
            _ => None,
        }
    }

    /// The tool's form with its trigonometry worked out once, for repeated queries.
    pub fn form(&self) -> Form {
        let half = (self.angle_deg / 2.0).to_radians();
        let (radius, half_flat) = match self.tip {
            Tip::Sharp => (0.0, 0.0),
            Tip::Radius { radius } => (radius, 0.0),
            Tip::Flat { width } => (0.0, width / 2.0),
        };
        Form {
            t: half.tan(),
            radius,
            arc_half_width: radius * half.cos(),
            arc_height: radius * (1.0 - half.sin()),
            apex: self.apex_below_lowest(),
            half_flat,
        }
    }

    /// The lateral interval `[left, right]` the tool occupies at depth `v` when placed at
    /// `(u0, d)`, or `None` if the tool does not reach that depth.
    pub fn span_at(&self, u0: f64, d: f64, v: f64) -> Option<(f64, f64)> {
        self.form().span_at(u0, d, v)
    }

    /// The depth of the tool's lower edge at lateral position `u` when placed at `(u0, d)`
    /// (smaller further from the tip; negative above the crest line).
    pub fn bottom_at(&self, u0: f64, d: f64, u: f64) -> f64 {
        self.form().bottom_at(u0, d, u)
    }

    /// The tool's outline placed at `(u0, d)`: from the top of the left flank down round the tip and
    /// up the right flank; the closing edge runs across the top at depth `top` (which must lie above
    /// the material).
    pub fn outline(&self, u0: f64, d: f64, top: f64) -> Vec<(f64, f64)> {
        let mut pts = Vec::new();
        self.template().place(u0, d, top, &mut pts);
        pts
    }

    /// The outline's shape worked out once (the nose's chords included), to be placed pass after
    /// pass.
    pub fn template(&self) -> Template {
        let half = (self.angle_deg / 2.0).to_radians();
        let mut tip = Vec::new();
        match self.tip {
            Tip::Flat { width } if width > 0.0 => {
                tip.push((-width / 2.0, 0.0));
                tip.push((width / 2.0, 0.0));
            }
            Tip::Radius { radius } if radius > 0.0 => {
                // Centre r above the lowest point; the arc runs from the left tangent point
                // (angle π − α from +u, v downward) through the bottom (π/2) to the right one (α).
                let from = std::f64::consts::PI - half;
                NosePolygon::new(radius, from - half).vertices(
                    (0.0, -radius),
                    radius,
                    from,
                    &mut tip,
                );
            }
            _ => tip.push((0.0, 0.0)),
        }
        Template {
            t: half.tan(),
            apex: self.apex_below_lowest(),
            tip,
        }
    }
}

/// A tool's outline relative to its lowest point, for placing it again and again.
#[derive(Clone, Debug, PartialEq)]
pub struct Template {
    t: f64,
    apex: f64,
    /// The tip's vertices from left to right, relative to the lowest point.
    tip: Vec<(f64, f64)>,
}

impl Template {
    /// The outline placed at `(u0, d)` with its top at `top`, into `pts` (cleared first).
    pub fn place(&self, u0: f64, d: f64, top: f64, pts: &mut Vec<(f64, f64)>) {
        pts.clear();
        // The flanks at the top, from the tool's apex.
        let top_half = (d + self.apex - top) * self.t;
        pts.push((u0 - top_half, top));
        pts.extend(self.tip.iter().map(|&(u, v)| (u0 + u, d + v)));
        pts.push((u0 + top_half, top));
    }
}

/// A tool's form, precomputed: what [`Tool::span_at`] and [`Tool::bottom_at`] need.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Form {
    /// tan of the half angle.
    pub t: f64,
    pub radius: f64,
    /// Half the lateral extent of the nose arc, r·cos α.
    pub arc_half_width: f64,
    /// Height of the nose arc above the lowest point, r·(1 − sin α).
    pub arc_height: f64,
    /// See [`Tool::apex_below_lowest`].
    pub apex: f64,
    pub half_flat: f64,
}

impl Form {
    pub fn span_at(&self, u0: f64, d: f64, v: f64) -> Option<(f64, f64)> {
        if v > d {
            return None;
        }
        let half = if self.radius > 0.0 && v >= d - self.arc_height {
            let dy = self.radius - (d - v);
            (self.radius * self.radius - dy * dy).max(0.0).sqrt()
        } else {
            (d + self.apex - v) * self.t
        };
        Some((u0 - half, u0 + half))
    }

    pub fn bottom_at(&self, u0: f64, d: f64, u: f64) -> f64 {
        let off = (u - u0).abs();
        if self.radius > 0.0 && off <= self.arc_half_width {
            d - self.radius + (self.radius * self.radius - off * off).max(0.0).sqrt()
        } else {
            d + self.apex - off / self.t
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nose_apex_and_spans() {
        let tool = Tool {
            angle_deg: 60.0,
            tip: Tip::Radius { radius: 0.1 },
        };
        // r/sin 30° − r = 0.1.
        assert!((tool.apex_below_lowest() - 0.1).abs() < 1e-12);
        // Lowest point: zero width.
        let (l, r) = tool.span_at(0.0, 1.0, 1.0).unwrap();
        assert!(l.abs() < 1e-12 && r.abs() < 1e-12);
        // On the flank, 0.5 above the lowest point: (1.1 − 0.5)·tan 30°.
        let (_, r) = tool.span_at(0.0, 1.0, 0.5).unwrap();
        assert!((r - 0.6 * 30f64.to_radians().tan()).abs() < 1e-12);
        assert!(tool.span_at(0.0, 1.0, 1.01).is_none());
        // bottom_at inverts span_at on the flank and on the arc.
        for v in [0.2, 0.5, 0.97, 0.999] {
            let (_, r) = tool.span_at(0.3, 1.0, v).unwrap();
            assert!((tool.bottom_at(0.3, 1.0, r) - v).abs() < 1e-9, "{v}");
        }
    }

    /// Area of a closed polygon (shoelace), sign dropped.
    fn area(pts: &[(f64, f64)]) -> f64 {
        let n = pts.len();
        let twice: f64 = (0..n)
            .map(|i| {
                let (a, b) = (pts[i], pts[(i + 1) % n]);
                a.0 * b.1 - b.0 * a.1
            })
            .sum();
        twice.abs() / 2.0
    }

    #[test]
    fn nose_polygon_keeps_the_area_and_the_tolerance() {
        use std::f64::consts::PI;
        for angle in [29.0, 55.0, 60.0, 80.0, 120.0] {
            for r in [1e-4, 0.01, 0.05, 0.1, 0.2, 0.4, 0.8, 2.0] {
                let tool = Tool {
                    angle_deg: angle,
                    tip: Tip::Radius { radius: r },
                };
                let poly = tool.nose_polygon().unwrap();
                assert!(poly.deviation <= NOSE_TOLERANCE, "{angle}° r {r}: {poly:?}");
                // The next coarser polygon would not do (unless already at the minimum of 2).
                let half = (angle / 2.0f64).to_radians();
                let span = PI - 2.0 * half;
                if poly.segments > 2 {
                    let coarser = NosePolygon::with_segments(r, span, poly.segments - 1);
                    assert!(coarser.deviation > NOSE_TOLERANCE, "{angle}° r {r}");
                }
                // The outline's area is the rounded V's: the V to the extended apex, (h + c)²·t
                // with c = r/sin α − r, less the corner between apex and arc, r²/t − r²·(π/2 − α).
                let (d, top) = (1.0, -1.0);
                let t = half.tan();
                let c = r / half.sin() - r;
                let exact = (d - top + c).powi(2) * t - (r * r / t - r * r * (PI / 2.0 - half));
                let got = area(&tool.outline(0.0, d, top));
                assert!(
                    (got - exact).abs() < 1e-12,
                    "{angle}° r {r}: {got} vs {exact}"
                );
                // Every outline vertex on the nose lies within the tolerance of the arc, and every
                // chord's midpoint too.
                let o = tool.outline(0.0, d, top);
                let centre = (0.0, d - r);
                let dist = |p: (f64, f64)| (p.0 - centre.0).hypot(p.1 - centre.1) - r;
                for w in o[1..o.len() - 1].windows(2) {
                    let mid = ((w[0].0 + w[1].0) / 2.0, (w[0].1 + w[1].1) / 2.0);
                    assert!(dist(w[0]).abs() <= NOSE_TOLERANCE + 1e-15);
                    assert!(dist(mid).abs() <= NOSE_TOLERANCE + 1e-15);
                }
            }
        }
        // A 0.2 mm nose on a 60° tool: 13 chords (24 before the polygon kept the area).
        let tool = Tool {
            angle_deg: 60.0,
            tip: Tip::Radius { radius: 0.2 },
        };
        assert_eq!(tool.nose_polygon().unwrap().segments, 13);
    }

    #[test]
    fn outline_of_a_flat_tip_is_a_trapezoid() {
        let tool = Tool {
            angle_deg: 60.0,
            tip: Tip::Flat { width: 0.2 },
        };
        let o = tool.outline(0.0, 1.0, -1.0);
        assert_eq!(o.len(), 4);
        let t = 30f64.to_radians().tan();
        assert!((o[0].0 + (0.1 + 2.0 * t)).abs() < 1e-12);
    }

    #[test]
    fn bad_tools_are_refused() {
        assert!(Tool::sharp(0.0).validate(Span::default()).is_err());
        assert!(Tool::sharp(180.0).validate(Span::default()).is_err());
        let t = Tool {
            angle_deg: 60.0,
            tip: Tip::Radius { radius: -0.1 },
        };
        assert!(t.validate(Span::default()).is_err());
    }
}
