//! GO and NOT GO limit gauges of a class: which gauge checks which diameter, and the size at
//! which it does (docs/standard-threads.md, "Gauges").
//!
//! ISO 1502 (metric) and ASME B1.2 (Unified) check an external thread with a GO screw ring gauge
//! at its maximum-material pitch diameter (the largest) and a NOT GO screw ring gauge at its
//! least-material one (the smallest), and its major diameter with plain GO / NOT GO gauges at the
//! largest / smallest major diameter; an internal thread with a GO screw plug at the smallest pitch
//! diameter, a NOT GO screw plug at the largest, and its minor diameter with plain plugs at the
//! smallest / largest minor diameter. The sizes given here are these product limits, the sizes
//! the gauges embody; the gauge makers' own tolerances and wear allowances (ISO 1502's T, Z and W
//! values, B1.2's gage tolerances) lie inside them and are not applied.

use serde::Serialize;

use super::{Limits, Surface};

/// One pair of limit gauges (mm).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct GaugePair {
    /// `"thread ring"`, `"plain ring"`, `"thread plug"`, `"plain plug"`.
    pub gauge: &'static str,
    /// The diameter it checks: `"pitch"`, `"major"` or `"minor"`.
    pub diameter: &'static str,
    /// The GO gauge's size: the maximum-material limit.
    pub go: f64,
    /// The NOT GO gauge's size: the least-material limit.
    pub not_go: f64,
}

/// The limit gauges of one side's class: thread gauges for the pitch diameter, plain gauges for
/// the crest diameter (external: major; internal: minor). A diameter without both limits has no
/// pair.
pub fn gauges(l: &Limits) -> Vec<GaugePair> {
    let pair = |gauge, diameter, go: Option<f64>, not_go: Option<f64>| {
        Some(GaugePair {
            gauge,
            diameter,
            go: go?,
            not_go: not_go?,
        })
    };
    match l.side {
        Surface::External => [
            pair("thread ring", "pitch", l.pitch.max, l.pitch.min),
            pair("plain ring", "major", l.major.max, l.major.min),
        ],
        Surface::Internal => [
            pair("thread plug", "pitch", l.pitch.min, l.pitch.max),
            pair("plain plug", "minor", l.minor.min, l.minor.max),
        ],
    }
    .into_iter()
    .flatten()
    .collect()
}

#[cfg(test)]
mod tests {
    use super::super::lookup;
    use super::*;

    /// M10x1.5: 6g d2 9.026 − 0.032 = 8.994 max, 8.994 − 0.132 = 8.862 min; d 9.968 / 9.732
    /// (ISO 965-2's limits, which the gauges embody); 6H D2 9.026 / 9.206, D1 8.376 / 8.676.
    #[test]
    fn metric_go_is_maximum_material() {
        let t = lookup("M10x1.5").unwrap();
        let e = gauges(&t.external.unwrap());
        assert_eq!(e.len(), 2);
        let close = |a: f64, b: f64| (a - b).abs() < 5e-4;
        assert!(close(e[0].go, 8.994) && close(e[0].not_go, 8.862), "{e:?}");
        assert!(close(e[1].go, 9.968) && close(e[1].not_go, 9.732), "{e:?}");
        let i = gauges(&t.internal.unwrap());
        assert!(close(i[0].go, 9.026) && close(i[0].not_go, 9.206), "{i:?}");
        assert!(close(i[1].go, 8.376) && close(i[1].not_go, 8.676), "{i:?}");
    }

    /// A gauge maker's published chart of GO / NOT GO pitch diameters (Westport, "Standard Pitch
    /// Diameter Chart - Metric", westportcorp.com/blogs/thread-ring-gages; X-tolerance gauges,
    /// their sizes at the product limits), rows M6x1, M8x1.25, M10x1.5, M10x1.25 (mm): GO ring
    /// 6g, NOT GO ring 6g, GO plug 6H, NOT GO plug 6H.
    #[test]
    fn metric_thread_gauges_match_a_makers_chart() {
        for (name, go_ring, nogo_ring, go_plug, nogo_plug) in [
            ("M6x1", 5.324, 5.212, 5.350, 5.500),
            ("M8x1.25", 7.160, 7.042, 7.188, 7.348),
            ("M10x1.5", 8.994, 8.862, 9.026, 9.206),
            ("M10x1.25", 9.160, 9.042, 9.188, 9.348),
        ] {
            let t = lookup(name).unwrap();
            let close = |a: f64, b: f64| (a - b).abs() < 5e-4;
            let e = gauges(&t.limits(Surface::External));
            let i = gauges(&t.limits(Surface::Internal));
            assert!(
                close(e[0].go, go_ring) && close(e[0].not_go, nogo_ring),
                "{name}: {e:?}"
            );
            assert!(
                close(i[0].go, go_plug) && close(i[0].not_go, nogo_plug),
                "{name}: {i:?}"
            );
        }
    }

    /// A published Unified ring-gauge chart (go / not go pitch diameters of 2A and 3A, in; the
    /// "thread ring gauge specification" page, maybellehectorlolss1.web.app, quoting a gauge
    /// maker's table): 5/8-11 UNC 2A .5644 / .5589, 3A .5660 / .5619. (Its 9/16-24 UNEF rows,
    /// NOT GO .5303 (2A) and .5325 (3A), are 0.0001 above threadcut's B1.1 formula values .5302 /
    /// .5324: not verified, docs/standard-threads.md "Gauges".)
    #[test]
    fn unified_ring_gauges_match_a_published_chart() {
        for (name, go, not_go) in [
            ("5/8-11 UNC-2A", 0.5644, 0.5589),
            ("5/8-11 UNC-3A", 0.5660, 0.5619),
        ] {
            let t = lookup(name).unwrap();
            let e = gauges(&t.external.unwrap());
            let close = |a: f64, b: f64| (a / 25.4 - b).abs() < 5e-5;
            assert!(
                close(e[0].go, go) && close(e[0].not_go, not_go),
                "{name}: {e:?}"
            );
        }
    }

    /// 1/2-13 UNC-2A (ASME B1.1): pitch 0.4485 / 0.4435, major 0.4985 / 0.4876 in.
    #[test]
    fn unified_2a() {
        let t = lookup("1/2-13 UNC-2A").unwrap();
        let e = gauges(&t.external.unwrap());
        let close = |a: f64, b: f64| (a / 25.4 - b).abs() < 5e-5;
        assert!(
            close(e[0].go, 0.4485) && close(e[0].not_go, 0.4435),
            "{e:?}"
        );
        assert!(
            close(e[1].go, 0.4985) && close(e[1].not_go, 0.4876),
            "{e:?}"
        );
    }
}
