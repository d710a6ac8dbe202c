//! General-purpose Acme threads, ASME B1.5 (29°), classes 2G, 3G and 4G, computed in inch:
//!
//! * basic: `h = 0.5·P`, pitch diameter `D − h`, minor `D − P`; flat at the basic crest and root
//!   `0.3707·P`;
//! * clearance at the major and minor diameters 0.020 (10 threads per inch and coarser) or 0.010
//!   (finer);
//! * pitch-diameter allowance of the external thread `0.008·√D` (2G), `0.006·√D` (3G),
//!   `0.004·√D` (4G), and pitch-diameter tolerance (both sides) `0.006·√D + 0.030·√P` (2G),
//!   `0.0028·√D + 0.014·√P` (3G), `0.002·√D + 0.010·√P` (4G), D the nominal size — each rounded
//!   to 0.0001 before use, as the standard's tables are;
//! * major diameter of the external thread and minor diameter of the internal one: tolerance
//!   `0.05·P`, at least 0.005; minor diameter of the external thread: 1.5 × the pitch diameter
//!   tolerance as computed, taken from the *printed* (0.0001) maximum minor diameter (5/8-8 2G:
//!   0.4800 − 1.5·0.01535 = 0.456975 → 0.4570; 1.5 × the rounded 0.0154 would give 0.4569;
//!   3/4-6 2G: 0.5633 − 1.5·0.017444 = 0.537134 → 0.5371, where the unrounded 0.563333 would give
//!   0.5372; 7/16-12 2G 0.3442 − 0.018943 → 0.3253, not 0.3252), with two published values that
//!   follow no single rule kept in [`MINOR_MIN_TABLE`];
//! * limits rounded to 0.0001 inch. The internal major diameter has a minimum only here: no
//!   published maximum was found to check one against.

use super::profile::{Edge, Profile};
use super::{
    bad_name, fill, trim, unknown, Basic, Class, Family, Limits, Range, Result, Series,
    StandardThread, Surface,
};
use crate::units::{Units, MM_PER_INCH};

/// External minor minimum diameters (inch) where the published tables depart from the rule above:
/// (size, threads per inch, class, value). Lew Merrick's "Acme Thread Data Sheets" (from ASME
/// B1.5): 1/4-16 4G prints 0.1722 for the tie 0.17225 (every other tie goes up: 1/4-16 2G 0.16175
/// → 0.1618, 5/8-8 internal minor maximum 0.50625 → 0.5063); 3/8-12 3G prints 0.2730, which the
/// unrounded maximum gives (0.281667 − 0.008634 = 0.27303) and the printed one does not (0.2817 −
/// 0.008634 = 0.27307 → 0.2731), while 7/16-12 2G/3G and 3/4-6 2G need the printed maximum.
const MINOR_MIN_TABLE: &[(f64, f64, u8, f64)] =
    &[(0.25, 16.0, 4, 0.1722), (0.375, 12.0, 3, 0.2730)];

/// The standard series (ASME B1.5 Table 2): size, nominal diameter, threads per inch.
const SERIES: &[(&str, f64, f64)] = &[
    ("1/4", 0.25, 16.0),
    ("5/16", 0.3125, 14.0),
    ("3/8", 0.375, 12.0),
    ("7/16", 0.4375, 12.0),
    ("1/2", 0.5, 10.0),
    ("5/8", 0.625, 8.0),
    ("3/4", 0.75, 6.0),
    ("7/8", 0.875, 6.0),
    ("1", 1.0, 5.0),
    ("1-1/8", 1.125, 5.0),
    ("1-1/4", 1.25, 5.0),
    ("1-3/8", 1.375, 4.0),
    ("1-1/2", 1.5, 4.0),
    ("1-3/4", 1.75, 4.0),
    ("2", 2.0, 4.0),
    ("2-1/4", 2.25, 3.0),
    ("2-1/2", 2.5, 3.0),
    ("2-3/4", 2.75, 3.0),
    ("3", 3.0, 2.0),
    ("3-1/2", 3.5, 2.0),
    ("4", 4.0, 2.0),
    ("4-1/2", 4.5, 2.0),
    ("5", 5.0, 2.0),
];

fn name(size: &str, tpi: f64) -> String {
    format!("{size}-{} ACME", trim(tpi))
}

pub fn known_names() -> Vec<String> {
    SERIES.iter().map(|&(s, _, n)| name(s, n)).collect()
}

/// Rounds to `decimals`, a tie (within 1e-6 of a half unit, far below any printed digit) going up.
fn round_half_up(v: f64, decimals: i32) -> f64 {
    let s = 10f64.powi(decimals);
    let x = v * s;
    let floor = x.floor();
    if (x - floor - 0.5).abs() < 1e-6 {
        (floor + 1.0) / s
    } else {
        x.round() / s
    }
}

/// The clearance at the major and minor diameters (inch).
pub fn clearance(tpi: f64) -> f64 {
    if tpi <= 10.0 {
        0.020
    } else {
        0.010
    }
}

/// Pitch-diameter allowance of the external thread and pitch-diameter tolerance (inch), as
/// computed (not rounded).
pub fn allowance_and_tolerance_exact(d: f64, tpi: f64, grade: u8) -> Option<(f64, f64)> {
    let p = 1.0 / tpi;
    let (a, kd, kp) = match grade {
        2 => (0.008, 0.006, 0.030),
        3 => (0.006, 0.0028, 0.014),
        4 => (0.004, 0.002, 0.010),
        _ => return None,
    };
    Some((a * d.sqrt(), kd * d.sqrt() + kp * p.sqrt()))
}

/// Pitch-diameter allowance of the external thread and pitch-diameter tolerance (inch), rounded
/// to 0.0001 as the standard rounds them before use.
pub fn allowance_and_tolerance(d: f64, tpi: f64, grade: u8) -> Option<(f64, f64)> {
    let p = 1.0 / tpi;
    let (a, kd, kp) = match grade {
        2 => (0.008, 0.006, 0.030),
        3 => (0.006, 0.0028, 0.014),
        4 => (0.004, 0.002, 0.010),
        _ => return None,
    };
    Some((
        round_half_up(a * d.sqrt(), 4),
        round_half_up(kd * d.sqrt() + kp * p.sqrt(), 4),
    ))
}

/// `1/2-10 ACME`, `1/2-10 ACME-2G`, `1-1/4-5 ACME 3G`, `1.750-4 ACME-2G`, `.500-10 ACME`.
pub fn lookup(text: &str) -> Result<StandardThread> {
    let upper = text.to_ascii_uppercase();
    let at = upper.find("ACME").unwrap_or(0);
    let head = text[..at].trim();
    let tail = text[at + 4..].trim().trim_start_matches('-').trim();
    let grade = if tail.is_empty() {
        None
    } else {
        let t = tail.to_ascii_uppercase();
        let g = t
            .strip_suffix('G')
            .and_then(|g| g.parse::<u8>().ok())
            .filter(|g| (2..=4).contains(g))
            .ok_or_else(|| {
                bad_name(
                    text,
                    format!("`{tail}` is not an ASME B1.5 general-purpose class (2G, 3G, 4G)"),
                )
            })?;
        Some(g)
    };
    let head = head.trim_end_matches('-').trim();
    let (size, tpi) = match head.rsplit_once('-') {
        Some((a, b)) if !b.contains('/') => (a.trim(), super::number(b)),
        _ => (head, None),
    };
    let norm = super::pipe::norm_size(size);
    // ASME B1.5 designates by the decimal nominal diameter (`1.750-4 ACME-2G`); the fraction
    // (`1-3/4-4 ACME`) is read too.
    let decimal = size.contains('.').then(|| super::number(size)).flatten();
    let Some(&(sname, d, n)) = SERIES
        .iter()
        .find(|&&(s, sd, _)| s == norm || decimal.is_some_and(|v| (v - sd).abs() < 1e-9))
    else {
        return Err(unknown(text, "no ASME B1.5 Acme size of that name", None));
    };
    if let Some(tpi) = tpi {
        if (tpi - n).abs() > 1e-9 {
            return Err(unknown(
                text,
                "not a thread of the ASME B1.5 general-purpose series",
                Some((d * MM_PER_INCH, MM_PER_INCH / tpi)),
            ));
        }
    }
    let p = 1.0 / n;
    let cl = clearance(n);
    let mm = |v: f64| v * MM_PER_INCH;
    let half = 14.5f64.to_radians().tan();
    let depth = mm(0.5 * p + cl / 2.0);
    let mut t = StandardThread {
        name: name(sname, n),
        family: Family::Acme,
        series: Series::Acme,
        units: Units::Inch,
        pitch: mm(p),
        tpi: Some(n),
        basic: Basic {
            major: mm(d),
            pitch_diameter: mm(d - 0.5 * p),
            minor: mm(d - p),
            fundamental_height: mm(p / (2.0 * half)),
        },
        external_depth: depth,
        internal_depth: depth,
        external: None,
        internal: None,
        profile: Profile {
            angle_deg: 29.0,
            flank_angle_deg: 14.5,
            fundamental_height: mm(p / (2.0 * half)),
            external_crest: Edge::Flat {
                width: mm(0.3707 * p),
            },
            external_root: Edge::Flat {
                width: mm(0.3707 * p - 2.0 * half * cl / 2.0),
            },
            internal_crest: Edge::Flat {
                width: mm(0.3707 * p),
            },
            internal_root: Edge::Flat {
                width: mm(0.3707 * p - 2.0 * half * cl / 2.0),
            },
        },
        taper: None,
    };
    let class = grade.map(|g| Class::Acme {
        grade: g,
        side: Surface::External,
    });
    fill(&mut t, class, text)?;
    if let Some(g) = grade {
        // A class names both sides of an Acme thread.
        fill(
            &mut t,
            Some(Class::Acme {
                grade: g,
                side: Surface::Internal,
            }),
            text,
        )?;
    }
    Ok(t)
}

pub(super) fn limits(t: &StandardThread, class: Class) -> std::result::Result<Limits, String> {
    let Class::Acme { grade, side } = class else {
        return Err("an Acme thread takes an ASME B1.5 class: 2G, 3G or 4G".into());
    };
    let d = t.basic.major / MM_PER_INCH;
    let n = t.tpi.ok_or("an Acme thread carries its threads per inch")?;
    let p = 1.0 / n;
    let (allowance, td2) = allowance_and_tolerance(d, n, grade)
        .ok_or_else(|| format!("ASME B1.5 has no class {grade}G"))?;
    let (_, td2_exact) = allowance_and_tolerance_exact(d, n, grade).unwrap_or((0.0, td2));
    let cl = clearance(n);
    // 0.05·P, at least 0.005, as computed; the limit is rounded once (3/4-6 internal minor
    // maximum 0.583333 + 0.008333 = 0.5917, not 0.5916 from a rounded 0.0083).
    let crest_tol = (0.05 * p).max(0.005);
    // Limits to 0.0001, a tie a half up: 5/8-8 major minimum 0.61875 → 0.6188, internal minor
    // maximum 0.50625 → 0.5063, 1/4-16 2G minor minimum 0.16175 → 0.1618, as published.
    let r4 = |v: f64| round_half_up(v, 4);
    let pd = d - 0.5 * p;
    let l = if side == Surface::External {
        // The maximum minor diameter as printed (0.0001), less 1.5 × the tolerance as computed:
        // 5/8-8 2G 0.4800 − 1.5·0.01535 = 0.456975 → 0.4570 (from the rounded 0.0154: 0.4569);
        // 3/4-6 2G 0.5633 − 0.026165 → 0.5371 (from the unrounded 0.563333: 0.5372).
        let minor_max = r4(d - p - cl);
        let minor_min = MINOR_MIN_TABLE
            .iter()
            .find(|&&(td, tn, g, _)| (td - d).abs() < 1e-9 && (tn - n).abs() < 1e-9 && g == grade)
            .map_or_else(|| r4(minor_max - 1.5 * td2_exact), |r| r.3);
        Limits {
            class,
            side,
            deviation: -allowance,
            major: Range::both(r4(d - crest_tol), r4(d)),
            pitch: Range::both(r4(pd - allowance - td2), r4(pd - allowance)),
            minor: Range::both(minor_min, minor_max),
        }
    } else {
        Limits {
            class,
            side,
            deviation: 0.0,
            major: Range {
                min: Some(r4(d + cl)),
                max: None,
            },
            pitch: Range::both(r4(pd), r4(pd + td2)),
            minor: Range::both(r4(d - p), r4(d - p + crest_tol)),
        }
    };
    Ok(Limits {
        deviation: l.deviation * MM_PER_INCH,
        major: l.major.to_mm(),
        pitch: l.pitch.to_mm(),
        minor: l.minor.to_mm(),
        ..l
    })
}
