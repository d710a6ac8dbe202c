//! A standard thread as `threadcut thread --json` writes it (and the Python package's
//! `threadcut.thread`): values in the standard's own units, the limits of the sides the name asks
//! for.

use serde_json::{json, Value};

use super::{Edge, Family, Limits, StandardThread};

impl StandardThread {
    /// `{name, family, series, units, pitch, pitch_mm, tpi, basic, thread_height, turning_infeed,
    /// external, internal, wires}` (`wires`: [`super::wires::Wires::to_json`] with the best wire), and for the forms other than ISO metric and Unified also `profile`
    /// and `taper`. Lengths are in the standard's units ([`StandardThread::units`]); `pitch_mm`
    /// is the pitch in mm.
    pub fn to_json(&self) -> Value {
        let u = self.units;
        // Basic values and lengths (tabulated to 0.0001 in / 0.001 mm by the standards: NPT E1
        // 0.77843, BSW minor 0.3933) without the mm → inch conversion noise (0.7784300000000001).
        let n = |mm: f64| json!((u.from_mm(mm) * 1e10).round() / 1e10);
        // Limits are tabulated values (0.001 mm, 0.0001 in): strip the mm → inch conversion noise.
        let o =
            |mm: Option<f64>| mm.map_or(Value::Null, |x| json!((u.from_mm(x) * 1e6).round() / 1e6));
        let limits = |l: &Limits| {
            json!({
                "class": l.class.to_string(),
                "deviation": (u.from_mm(l.deviation) * 1e6).round() / 1e6,
                "major": {"min": o(l.major.min), "max": o(l.major.max)},
                "pitch": {"min": o(l.pitch.min), "max": o(l.pitch.max)},
                "minor": {"min": o(l.minor.min), "max": o(l.minor.max)},
            })
        };
        let mut v = json!({
            "name": self.name,
            "family": self.family,
            "series": self.series,
            "units": u,
            "pitch": n(self.pitch),
            "pitch_mm": self.pitch,
            "tpi": self.tpi,
            "basic": {
                "major": n(self.basic.major),
                "pitch_diameter": n(self.basic.pitch_diameter),
                "minor": n(self.basic.minor),
                "fundamental_height": n(self.basic.fundamental_height),
            },
            "thread_height": {"external": n(self.external_depth), "internal": n(self.internal_depth)},
            "turning_infeed": {"external": n(self.external_depth), "internal": n(self.internal_depth)},
            "external": self.external.as_ref().map(limits),
            "internal": self.internal.as_ref().map(limits),
        });
        v["wires"] = self.wires(None).to_json(u);
        if matches!(self.family, Family::Metric | Family::Unified) {
            // GO / NOT GO gauge sizes of each side named (ISO 1502, ASME B1.2).
            let pairs = |l: &Limits| {
                super::gauges::gauges(l)
                    .iter()
                    .map(|g| {
                        json!({"gauge": g.gauge, "diameter": g.diameter, "go": o(Some(g.go)), "not_go": o(Some(g.not_go))})
                    })
                    .collect::<Vec<_>>()
            };
            v["gauges"] = json!({
                "external": self.external.as_ref().map(pairs),
                "internal": self.internal.as_ref().map(pairs),
            });
        }
        if self.family == Family::Trapezoidal {
            // ISO 2904's a_c and the external minor diameter d3 (`basic.minor` is D1).
            let ac = super::trapezoidal::crest_clearance(self.pitch);
            v["basic"]["crest_clearance"] = n(ac);
            v["basic"]["external_minor"] = n(self.basic.major - 2.0 * self.external_depth);
        }
        if !matches!(self.family, Family::Metric | Family::Unified) {
            let e = |e: &Edge| match *e {
                Edge::Sharp => json!({"kind": "sharp"}),
                Edge::Flat { width } => json!({"kind": "flat", "width": n(width)}),
                Edge::Round { radius } => json!({"kind": "round", "radius": n(radius)}),
                Edge::Truncated { min, max } => {
                    json!({"kind": "truncated", "min": n(min), "max": n(max)})
                }
            };
            let p = &self.profile;
            v["profile"] = json!({
                "angle_deg": p.angle_deg,
                "flank_angle_deg": p.flank_angle_deg,
                "fundamental_height": n(p.fundamental_height),
                "external": {"crest": e(&p.external_crest), "root": e(&p.external_root)},
                "internal": {"crest": e(&p.internal_crest), "root": e(&p.internal_root)},
            });
            v["taper"] = self.taper.as_ref().map_or(Value::Null, |tp| {
                json!({
                    "diameter_per_length": tp.diameter_per_length,
                    "gauge_length": n(tp.gauge_length),
                    "gauge_pitch_diameter": n(tp.gauge_pitch_diameter),
                    "gauge_major_diameter": n(tp.gauge_major_diameter),
                    "small_end_pitch_diameter": n(tp.small_end_pitch_diameter),
                    "effective_length": n(tp.effective_length),
                    "effective_end_pitch_diameter": n(tp.effective_end_pitch_diameter),
                    "vanish_length": n(tp.vanish_length),
                    "wrench_makeup": n(tp.wrench_makeup),
                    "overall_length": n(tp.overall_length),
                    "external_position_tolerance": n(tp.external_position_tolerance),
                    "internal_position_tolerance": n(tp.internal_position_tolerance),
                    "internal_gauge_plane": n(tp.internal_gauge_plane),
                })
            });
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::super::lookup;

    #[test]
    fn metric_thread_in_mm_with_the_named_side_only() {
        let v = lookup("M10x1.5-6g").unwrap().to_json();
        assert_eq!(v["units"], "mm");
        assert_eq!(v["pitch"], 1.5);
        // ISO 724: d2 = d − 0.6495·P = 9.026 mm.
        assert!((v["basic"]["pitch_diameter"].as_f64().unwrap() - 9.026).abs() < 5e-4);
        assert_eq!(v["external"]["class"], "6g");
        // es(g) = −(15 + 11·1.5) µm = −0.032 mm (ISO 965-1).
        assert_eq!(v["external"]["deviation"], -0.032);
        assert!(v["internal"].is_null());
        assert!(v.get("profile").is_none());
    }

    #[test]
    fn unified_thread_in_inches() {
        let v = lookup("1/2-13 UNC-2A").unwrap().to_json();
        assert_eq!(v["units"], "inch");
        assert_eq!(v["tpi"], 13.0);
        assert!((v["pitch"].as_f64().unwrap() - 1.0 / 13.0).abs() < 1e-9);
        // ASME B1.1: 1/2-13 UNC-2A major diameter max = 0.5000 − the 2A allowance 0.0015 in.
        assert_eq!(v["external"]["major"]["max"], 0.4985);
        assert_eq!(v["external"]["deviation"], -0.0015);
    }

    #[test]
    fn taper_pipe_thread_has_its_form_and_gauge_plane() {
        let v = lookup("1/2-14 NPT").unwrap().to_json();
        assert_eq!(v["profile"]["angle_deg"], 60.0);
        // ASME B1.20.1: taper 1:16 on diameter.
        assert_eq!(v["taper"]["diameter_per_length"], 1.0 / 16.0);
    }
}
