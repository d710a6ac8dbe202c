//! The threading tool's form in the axial section: a V of the included angle whose lowest point is
//! the tool's setting point, with a sharp, rounded (nose radius) or flat tip.
//!
//! Section coordinates: `u` is the lateral (+Z) position, `v` the depth below the crest line (into
//! the material). A tool placed at `(u0, d)` has its lowest point at depth `d` on the line `u = u0`:
//! that is the point the control drives along the pass (the tool is touched off on it).

use serde::Serialize;

use crate::diag::{Code, Diagnostic, Result, Span};

/// Segments used to flatten a nose radius. The chord error of a 0.2 mm nose over 120° in 24
/// segments is r·(1 − cos(5°/2)) ≈ 0.2 µm, and the lost area well below 0.01 % of a chip.
pub const NOSE_SEGMENTS: usize = 24;

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
        let t = self.slope();
        let half = (self.angle_deg / 2.0).to_radians();
        let mut pts = Vec::with_capacity(NOSE_SEGMENTS + 5);
        // The flanks at the top, from the tool's apex.
        let apex = d + self.apex_below_lowest();
        let top_half = (apex - top) * t;
        pts.push((u0 - top_half, top));
        match self.tip {
            Tip::Sharp => pts.push((u0, d)),
            Tip::Flat { width } if width > 0.0 => {
                pts.push((u0 - width / 2.0, d));
                pts.push((u0 + width / 2.0, d));
            }
            Tip::Flat { .. } => pts.push((u0, d)),
            Tip::Radius { radius } if radius > 0.0 => {
                // Centre above the lowest point; the arc runs from the left tangent point
                // (angle π − α from +u, v downward) through the bottom (π/2) to the right one (α).
                let c = (u0, d - radius);
                let from = std::f64::consts::PI - half;
                let to = half;
                for i in 0..=NOSE_SEGMENTS {
                    let a = from + (to - from) * i as f64 / NOSE_SEGMENTS as f64;
                    pts.push((c.0 + radius * a.cos(), c.1 + radius * a.sin()));
                }
            }
            Tip::Radius { .. } => pts.push((u0, d)),
        }
        pts.push((u0 + top_half, top));
        pts
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
