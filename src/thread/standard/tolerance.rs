//! The pitch-diameter tolerance of a thread known only by its diameter, pitch and flank angle (a
//! cycle in a program names no standard): the form assumed from the tool's angle, and the medium
//! class's Td2/TD2 for that diameter and pitch, from the same formulas as the named threads.

use super::{acme, iso_limits, trapezoidal, unified_limits, Class, Family, Series, Surface};
use crate::units::MM_PER_INCH;

/// The form a thread cut with a tool of `tool_angle_deg` is taken to have, with its lead
/// `lead_mm`: 29° Acme, 30° trapezoidal, 60° (and any angle that names no form, a radial infeed's
/// 0 among them) Unified when the lead is a whole number of threads per inch from 1 to 80 to
/// 0.00005 inch (a lead written to 4 decimals: 13 tpi as 0.0769), ISO metric otherwise. No ISO
/// 261 pitch is that close to a whole tpi at or below 80 (0.2 mm is 127 tpi). `None` for 55°
/// (Whitworth: threadcut computes BS 84's classes only for named sizes).
pub fn assumed_family(tool_angle_deg: f64, lead_mm: f64) -> Option<Family> {
    let near = |a: f64| (tool_angle_deg - a).abs() < 0.5;
    if near(29.0) {
        return Some(Family::Acme);
    }
    if near(30.0) {
        return Some(Family::Trapezoidal);
    }
    if near(55.0) {
        return None;
    }
    Some(if whole_tpi(lead_mm).is_some() {
        Family::Unified
    } else {
        Family::Metric
    })
}

/// The whole number of threads per inch a lead (mm) is, to 0.00005 inch, from 1 to 80.
fn whole_tpi(lead_mm: f64) -> Option<f64> {
    let inch = lead_mm / MM_PER_INCH;
    if inch <= 0.0 {
        return None;
    }
    let n = (1.0 / inch).round();
    ((1.0..=80.0).contains(&n) && (inch - 1.0 / n).abs() <= 0.00005 + 1e-12).then_some(n)
}

/// The flank angle of a family's form (degrees).
pub fn flank_angle(family: Family) -> f64 {
    match family {
        Family::Acme => 29.0,
        Family::Trapezoidal => 30.0,
        Family::Whitworth | Family::Bspp | Family::Bspt => 55.0,
        Family::Metric | Family::Unified | Family::Npt => 60.0,
    }
}

/// The medium class of a thread and its pitch-diameter tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct ClassTolerance {
    /// `M30x2`, `0.5-13 UN`, `0.75-6 ACME`, `Tr40x7`: the size as measured on the cycle.
    pub thread: String,
    pub class: Class,
    /// Td2 (external) or TD2 (internal), mm.
    pub td2: f64,
}

/// The pitch-diameter tolerance of the medium class (6g/6H, 2A/2B, 2G, 7e/7H:
/// [`Class::default_for`]) of a `family` thread of nominal (major) diameter `d` and pitch `p`
/// (mm), by the formulas the named threads use (ISO 965-1, ASME B1.1 with the length of
/// engagement of UNC/UNF, ASME B1.5, ISO 2903). `None` where the family has no such formula here
/// or the diameter lies outside its ranges.
pub fn medium_pitch_tolerance(
    family: Family,
    side: Surface,
    d: f64,
    p: f64,
) -> Option<ClassTolerance> {
    let class = Class::default_for(family, side);
    let trim = |v: f64, decimals: i32| {
        let s = 10f64.powi(decimals);
        format!("{}", (v * s).round() / s)
    };
    let inch = d / MM_PER_INCH;
    let tpi = (MM_PER_INCH / p * 1e4).round() / 1e4;
    let (thread, td2) = match family {
        Family::Metric => {
            let l = iso_limits(d, p, class).ok()?;
            (
                format!("M{}x{}", trim(d, 3), trim(p, 4)),
                l.pitch.max? - l.pitch.min?,
            )
        }
        Family::Unified => {
            let l = unified_limits(inch, tpi, Series::Unc, class).ok()?;
            (
                format!("{}-{} UN", trim(inch, 4), trim(tpi, 3)),
                l.pitch.max? - l.pitch.min?,
            )
        }
        Family::Acme => {
            let (_, td2) = acme::allowance_and_tolerance(inch, tpi, 2)?;
            (
                format!("{}-{} ACME", trim(inch, 4), trim(tpi, 3)),
                td2 * MM_PER_INCH,
            )
        }
        Family::Trapezoidal => (
            format!("Tr{}x{}", trim(d, 3), trim(p, 4)),
            trapezoidal::pitch_tolerance(d, p, class)?,
        ),
        _ => return None,
    };
    Some(ClassTolerance { thread, class, td2 })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn um(t: &ClassTolerance) -> f64 {
        (t.td2 * 1000.0 * 10.0).round() / 10.0
    }

    /// The tolerances of named threads: M20x2.5-6g d2 18.334/18.164 (Td2 170 µm: ISO 965-1,
    /// 90·2.5^0.4·√(11.2·22.4)^0.1 = 90·1.4427·1.3182 = 171.2 → R40 170); M20x2.5-6H D2
    /// 18.376/18.600 (1.32·170 = 224.4 → 224); 1/2-13 UNC-2A d2 0.4485/0.4435 (0.0050 in = 127
    /// µm), 2B 0.4500/0.4565 (0.0065 in = 165.1 µm): ASME B1.1's table.
    #[test]
    fn the_medium_classes_of_named_threads() {
        let ext = medium_pitch_tolerance(Family::Metric, Surface::External, 20.0, 2.5).unwrap();
        assert_eq!(
            (ext.thread.as_str(), ext.class.to_string()),
            ("M20x2.5", "6g".into())
        );
        assert_eq!(um(&ext), 170.0);
        let int = medium_pitch_tolerance(Family::Metric, Surface::Internal, 20.0, 2.5).unwrap();
        assert_eq!((int.class.to_string(), um(&int)), ("6H".into(), 224.0));
        let a =
            medium_pitch_tolerance(Family::Unified, Surface::External, 12.7, 25.4 / 13.0).unwrap();
        assert_eq!(
            (a.thread.as_str(), a.class.to_string()),
            ("0.5-13 UN", "2A".into())
        );
        assert_eq!(um(&a), 127.0);
        let b =
            medium_pitch_tolerance(Family::Unified, Surface::Internal, 12.7, 25.4 / 13.0).unwrap();
        assert_eq!((b.class.to_string(), um(&b)), ("2B".into(), 165.1));
    }

    #[test]
    fn the_form_is_assumed_from_the_tool_angle_and_the_lead() {
        assert_eq!(assumed_family(60.0, 2.0), Some(Family::Metric));
        assert_eq!(assumed_family(60.0, 25.4 / 13.0), Some(Family::Unified));
        // 0.0769 inch, 13 tpi as a 4-decimal lead; 0.2 mm is 127 tpi, beyond 80.
        assert_eq!(assumed_family(60.0, 0.0769 * 25.4), Some(Family::Unified));
        assert_eq!(assumed_family(60.0, 0.2), Some(Family::Metric));
        assert_eq!(assumed_family(0.0, 1.5), Some(Family::Metric));
        assert_eq!(assumed_family(29.0, 25.4 / 6.0), Some(Family::Acme));
        assert_eq!(assumed_family(30.0, 7.0), Some(Family::Trapezoidal));
        assert_eq!(assumed_family(55.0, 25.4 / 12.0), None);
    }
}
