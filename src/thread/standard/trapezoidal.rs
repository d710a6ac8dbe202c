//! ISO metric trapezoidal threads (Tr): ISO 2901 profile, ISO 2902 diameter–pitch plan, ISO 2903
//! tolerances, ISO 2904 basic dimensions (the same as DIN 103).
//!
//! * Profile (ISO 2901, 30°): `H1 = 0.5·P`, crest clearance `ac` = 0.15 (P 1.5), 0.25 (P 2–5),
//!   0.5 (P 6–12), 1 (P 14–44); `h3 = H4 = H1 + ac`; `d2 = D2 = d − 0.5·P`, `D1 = d − P`,
//!   `d3 = d − 2·h3`, `D4 = d + 2·ac`; root radii `R1 ≤ 0.5·ac`, `R2 ≤ ac`.
//! * Tolerances (ISO 2903, built on ISO 965-1): pitch-diameter grades 7, 8, 9 as ISO 965-1's
//!   `Td2(6) = 90·P^0.4·d^0.1` × 1.25, 1.6, 2 (external) or × 1.7, 2.12, 2.65 (internal), each
//!   rounded to the nearest R40 value (by difference, see [`r40`]); fundamental deviations
//!   `es(e) = −(50 + 11P)` rounded to R40, `es(c)` from ISO 2903's table ([`C_DEVIATION`]; `H`: 0); the crest diameters in grade 4 (`Td(4) = 0.63·Td(6)`, `TD1(4) = 0.63·TD1(6)`, R40);
//!   the external minor diameter `d3` in position h with `Td3 = 1.25·Td2 + |es|` (whole µm, a half
//!   up); the internal major diameter `D4` has a minimum only.

use super::profile::{Edge, Profile};
use super::{
    bad_name, fill, grade_factor, iso_range, round_to, trim, unknown, Basic, Class, Family, Limits,
    Range, Result, Series, StandardThread, Surface, ISO_RANGES, ISO_TD_6_TABLE, TD2_GRADES,
};
use crate::units::Units;

/// ISO 2902 general plan (d: pitches, the first the preferred one), with DIN 103's P 3 for
/// Tr16–Tr20; diameters 8–300 mm, columns 1–3 (the table as reproduced in F-M-S's "ISO
/// Trapezoidal screw threads Tr" sheet, scribd.com/document/415160259: normal, coarse, fine).
const PLAN: &[(f64, &[f64])] = &[
    (8.0, &[1.5]),
    (9.0, &[2.0, 1.5]),
    (10.0, &[2.0, 1.5]),
    (11.0, &[3.0, 2.0]),
    (12.0, &[3.0, 2.0]),
    (14.0, &[3.0, 2.0]),
    (16.0, &[4.0, 3.0, 2.0]),
    (18.0, &[4.0, 3.0, 2.0]),
    (20.0, &[4.0, 3.0, 2.0]),
    (22.0, &[5.0, 8.0, 3.0]),
    (24.0, &[5.0, 8.0, 3.0]),
    (26.0, &[5.0, 8.0, 3.0]),
    (28.0, &[5.0, 8.0, 3.0]),
    (30.0, &[6.0, 10.0, 3.0]),
    (32.0, &[6.0, 10.0, 3.0]),
    (34.0, &[6.0, 10.0, 3.0]),
    (36.0, &[6.0, 10.0, 3.0]),
    (38.0, &[7.0, 10.0, 3.0]),
    (40.0, &[7.0, 10.0, 3.0]),
    (42.0, &[7.0, 10.0, 3.0]),
    (44.0, &[7.0, 12.0, 3.0]),
    (46.0, &[8.0, 12.0, 3.0]),
    (48.0, &[8.0, 12.0, 3.0]),
    (50.0, &[8.0, 12.0, 3.0]),
    (52.0, &[8.0, 12.0, 3.0]),
    (55.0, &[9.0, 14.0, 3.0]),
    (60.0, &[9.0, 14.0, 3.0]),
    (65.0, &[10.0, 16.0, 4.0]),
    (70.0, &[10.0, 16.0, 4.0]),
    (75.0, &[10.0, 16.0, 4.0]),
    (80.0, &[10.0, 16.0, 4.0]),
    (85.0, &[12.0, 18.0, 4.0]),
    (90.0, &[12.0, 18.0, 4.0]),
    (95.0, &[12.0, 18.0, 4.0]),
    (100.0, &[12.0, 20.0, 4.0]),
    (105.0, &[12.0, 20.0, 4.0]),
    (110.0, &[12.0, 20.0, 4.0]),
    (115.0, &[14.0, 22.0, 6.0]),
    (120.0, &[14.0, 22.0, 6.0]),
    (125.0, &[14.0, 22.0, 6.0]),
    (130.0, &[14.0, 22.0, 6.0]),
    (135.0, &[14.0, 24.0, 6.0]),
    (140.0, &[14.0, 24.0, 6.0]),
    (145.0, &[14.0, 24.0, 6.0]),
    (150.0, &[16.0, 24.0, 6.0]),
    (155.0, &[16.0, 24.0, 6.0]),
    (160.0, &[16.0, 28.0, 6.0]),
    (165.0, &[16.0, 28.0, 6.0]),
    (170.0, &[16.0, 28.0, 6.0]),
    (175.0, &[16.0, 28.0, 8.0]),
    (180.0, &[18.0, 28.0, 8.0]),
    (185.0, &[18.0, 32.0, 8.0]),
    (190.0, &[18.0, 32.0, 8.0]),
    (195.0, &[18.0, 32.0, 8.0]),
    (200.0, &[18.0, 32.0, 8.0]),
    (210.0, &[20.0, 36.0, 8.0]),
    (220.0, &[20.0, 36.0, 8.0]),
    (230.0, &[20.0, 36.0, 8.0]),
    (240.0, &[22.0, 36.0, 8.0]),
    (250.0, &[22.0, 40.0, 12.0]),
    (260.0, &[22.0, 40.0, 12.0]),
    (270.0, &[24.0, 40.0, 12.0]),
    (280.0, &[24.0, 40.0, 12.0]),
    (290.0, &[24.0, 44.0, 12.0]),
    (300.0, &[24.0, 44.0, 12.0]),
];

/// Crest clearance ac (ISO 2901).
pub fn crest_clearance(p: f64) -> f64 {
    if p <= 1.5 {
        0.15
    } else if p <= 5.0 {
        0.25
    } else if p <= 12.0 {
        0.5
    } else {
        1.0
    }
}

/// Td3 values where the published tables depart from `1.25·Td2 + |es|` rounded a half up (µm):
/// (pitch, grade, position, value). P 1.5, 7e: 1.25·170 + 67 = 279.5, printed 279 (Tr8x1.5,
/// Tr9x1.5, Tr10x1.5 d3 min 5.921, 6.921, 7.921), while P 2, 7e: 1.25·190 + 71 = 308.5 is printed
/// 309 (Tr9x2 … Tr20x2 d3 min x.191, x.179).
const TD3_TABLE: &[(f64, u8, char, f64)] = &[(1.5, 7, 'e', 279.0)];

fn name(d: f64, p: f64) -> String {
    format!("Tr{}x{}", trim(d), trim(p))
}

/// Every Tr thread of the plan.
pub fn known_names() -> Vec<String> {
    PLAN.iter()
        .flat_map(|&(d, ps)| ps.iter().map(move |&p| name(d, p)))
        .collect()
}

fn parse_class(s: &str) -> Option<Class> {
    let b = s.trim().as_bytes();
    if b.len() != 2 {
        return None;
    }
    let grade = (b[0] as char).to_digit(10)? as u8;
    // ISO 2903 has no position E, C or h: `7E` (a drawing in capitals) is 7e, `7h` is 7H.
    let position = match b[1] as char {
        'c' | 'C' => 'c',
        'e' | 'E' => 'e',
        'h' | 'H' => 'H',
        _ => return None,
    };
    Some(Class::Trapezoidal { grade, position })
}

/// `Tr20x4`, `Tr20x4-7e`, `TR 20 x 4 - 8H`, `Tr20` (the preferred pitch).
pub fn lookup(text: &str) -> Result<StandardThread> {
    let body = text.trim()[2..].trim();
    let (size, class) = match body.split_once('-') {
        Some((s, c)) => {
            let class = parse_class(c).ok_or_else(|| {
                bad_name(
                    text,
                    format!(
                        "`{}` is not an ISO 2903 class (write 7e, 8e, 7H, 8H, 8c …)",
                        c.trim()
                    ),
                )
            })?;
            (s, Some(class))
        }
        None => (body, None),
    };
    let size: String = size.chars().filter(|c| !c.is_whitespace()).collect();
    let (d_text, p_text) = match size.find(['x', 'X', '×']) {
        Some(i) => {
            let sep = size[i..].chars().next().map_or(1, char::len_utf8);
            (&size[..i], Some(&size[i + sep..]))
        }
        None => (size.as_str(), None),
    };
    let d = super::number(d_text)
        .ok_or_else(|| unknown(text, "not a trapezoidal thread name", None))?;
    let row = PLAN.iter().find(|(pd, _)| (pd - d).abs() < 1e-9);
    let p = match p_text {
        Some(t) => {
            super::number(t).ok_or_else(|| unknown(text, "not a trapezoidal thread name", None))?
        }
        None => row.map(|r| r.1[0]).ok_or_else(|| {
            unknown(
                text,
                "no ISO 2902 trapezoidal thread of that diameter",
                Some((d, 0.0)),
            )
        })?,
    };
    if !row.is_some_and(|r| r.1.iter().any(|&q| (q - p).abs() < 1e-9)) {
        return Err(unknown(
            text,
            "no ISO 2902 trapezoidal thread of that diameter and pitch",
            Some((d, p)),
        ));
    }
    let ac = crest_clearance(p);
    let h3 = 0.5 * p + ac;
    let mut t = StandardThread {
        name: name(d, p),
        family: Family::Trapezoidal,
        series: Series::Tr,
        units: Units::Mm,
        pitch: p,
        tpi: None,
        basic: Basic {
            major: d,
            pitch_diameter: d - 0.5 * p,
            minor: d - p,
            fundamental_height: 1.866 * p,
        },
        external_depth: h3,
        internal_depth: h3,
        external: None,
        internal: None,
        profile: profile(p),
        taper: None,
    };
    fill(&mut t, class, text)?;
    Ok(t)
}

/// ISO 2901's design profile: crests flat (0.366·P at the basic profile), roots flat with radii
/// up to 0.5·ac (external) and ac (internal).
fn profile(p: f64) -> Profile {
    let t = 15f64.to_radians().tan();
    let ac = crest_clearance(p);
    // Width of the thread at the basic crest: half a pitch at the pitch line (0.25·P below it).
    let crest = 0.5 * p - 2.0 * t * 0.25 * p;
    // The space at the root, h3 below the crest.
    let root = 0.5 * p - 2.0 * t * (0.25 * p + ac);
    Profile {
        angle_deg: 30.0,
        flank_angle_deg: 15.0,
        fundamental_height: 1.866 * p,
        external_crest: Edge::Flat { width: crest },
        external_root: Edge::Flat { width: root },
        internal_crest: Edge::Flat { width: crest },
        internal_root: Edge::Flat { width: root },
    }
}

/// The R40 value (ISO 3) nearest in ratio among the values as printed (…, 160, 170, 180, 190 …).
/// ISO 2903's tables round this way: Td2(6) for 11.2 < d ≤ 22.4, P 3 is 184.1 µm, tabulated 180
/// (Tr12x3 … Tr16x3 7e: d2 tolerance 224 = 1.25·180), nearer to the printed 180 than to 190,
/// although nearer to the exact 10^(91/40) = 188.4 than to 10^(90/40) = 177.8; and 1.25·132 =
/// 165 goes to 170 (Tr8x1.5 7e: 7.183/7.013), nearer to it in ratio than to 160.
fn r40(um: f64) -> f64 {
    let k = (40.0 * um.log10()).floor() as i32;
    let lo = super::round_r40(10f64.powf((f64::from(k) + 0.01) / 40.0));
    let hi = super::round_r40(10f64.powf((f64::from(k) + 1.01) / 40.0));
    let (lo, hi) = if lo > um {
        (
            super::round_r40(10f64.powf((f64::from(k) - 0.99) / 40.0)),
            lo,
        )
    } else if hi < um {
        (
            hi,
            super::round_r40(10f64.powf((f64::from(k) + 2.01) / 40.0)),
        )
    } else {
        (lo, hi)
    };
    if um / lo <= hi / um {
        lo
    } else {
        hi
    }
}

/// ISO 965-1's grade-6 tolerances, the base of ISO 2903's grades (µm).
fn td2_6(d: f64, p: f64) -> Option<f64> {
    let (lo, hi) = ISO_RANGES[iso_range(d)?];
    Some(r40(90.0 * p.powf(0.4) * (lo * hi).sqrt().powf(0.1)))
}

fn td_6(p: f64) -> f64 {
    ISO_TD_6_TABLE
        .iter()
        .find(|&&(tp, _)| (tp - p).abs() < 1e-9)
        .map_or_else(|| r40(180.0 * p.powf(2.0 / 3.0) - 3.15 / p.sqrt()), |r| r.1)
}

fn td1_6(p: f64) -> f64 {
    r40(230.0 * p.powf(0.7))
}

/// Fundamental deviation es of position c (µm) by pitch, ISO 2903 Table 1. Not the ISO 965-1
/// style `100 + 11P` (125 µm at P 2): obliczenia.icad.pl's ISO 2903 calculator prints Tr10x2-8c
/// es −150 µm, d2 8.850/8.614. The other pitches are the table as recalled (an R40 progression,
/// twice position e up to P 7); no public copy of the whole table was found.
const C_DEVIATION: &[(f64, f64)] = &[
    (1.5, 140.0),
    (2.0, 150.0),
    (3.0, 170.0),
    (4.0, 190.0),
    (5.0, 212.0),
    (6.0, 236.0),
    (7.0, 250.0),
    (8.0, 265.0),
    (9.0, 280.0),
    (10.0, 300.0),
    (12.0, 335.0),
    (14.0, 355.0),
    (16.0, 375.0),
    (18.0, 400.0),
    (20.0, 425.0),
    (22.0, 450.0),
    (24.0, 475.0),
    (28.0, 500.0),
    (32.0, 530.0),
    (36.0, 560.0),
    (40.0, 600.0),
    (44.0, 630.0),
];

/// Fundamental deviation es of position e (µm) by pitch, ISO 2903 Table 1 as recalled (and recalled
/// alike, independently, twice). The ISO 965-1 style `50 + 11P` rounded to R40 gives the same values
/// up to P 7 (71 … 125 µm) and then drifts away from the table (P 8: 140 against 132; P 44: 530
/// against 315): past P 7 the table is about half of position c's deviation.
const E_DEVIATION: &[(f64, f64)] = &[
    (1.5, 67.0),
    (2.0, 71.0),
    (3.0, 85.0),
    (4.0, 95.0),
    (5.0, 106.0),
    (6.0, 118.0),
    (7.0, 125.0),
    (8.0, 132.0),
    (9.0, 140.0),
    (10.0, 150.0),
    (12.0, 160.0),
    (14.0, 180.0),
    (16.0, 190.0),
    (18.0, 200.0),
    (20.0, 212.0),
    (22.0, 224.0),
    (24.0, 236.0),
    (28.0, 250.0),
    (32.0, 265.0),
    (36.0, 280.0),
    (40.0, 300.0),
    (44.0, 315.0),
];

/// The internal minor-diameter tolerance TD1 (grade 4, µm) by pitch, ISO 2903 as recalled. It is
/// `0.63 · 230 · P^0.7` rounded once to R40 at every pitch but P 10 and 12 (730 → 710, 828 → 800);
/// rounding twice (grade 6 first, as `td1_6` does for ISO 965-1) gives 750 and 950 at P 10 and 14,
/// which the table does not print.
const TD1_TABLE: &[(f64, f64)] = &[
    (1.5, 190.0),
    (2.0, 236.0),
    (3.0, 315.0),
    (4.0, 375.0),
    (5.0, 450.0),
    (6.0, 500.0),
    (7.0, 560.0),
    (8.0, 630.0),
    (9.0, 670.0),
    (10.0, 710.0),
    (12.0, 800.0),
    (14.0, 900.0),
    (16.0, 1000.0),
    (18.0, 1120.0),
    (20.0, 1180.0),
    (22.0, 1250.0),
    (24.0, 1320.0),
    (28.0, 1500.0),
    (32.0, 1600.0),
    (36.0, 1800.0),
    (40.0, 1900.0),
    (44.0, 2000.0),
];

/// The value of `table` at pitch `p`.
fn at_pitch(table: &[(f64, f64)], p: f64) -> Option<f64> {
    table
        .iter()
        .find(|&&(tp, _)| (tp - p).abs() < 1e-9)
        .map(|&(_, v)| v)
}

fn deviation(position: char, p: f64) -> Option<f64> {
    match position {
        'e' => Some(-at_pitch(E_DEVIATION, p).unwrap_or_else(|| r40(50.0 + 11.0 * p))),
        'c' => at_pitch(C_DEVIATION, p).map(|v| -v),
        'H' => Some(0.0),
        _ => None,
    }
}

/// ISO 2903 internal pitch-diameter grades 7, 8, 9: `TD2 = k·Td2(6)` (ISO 965-1's 1.7 and 2.12,
/// and 2.65 = 1.32·2 for grade 9; the coarse classes 8c/9H).
const INTERNAL_GRADES: &[(u8, f64)] = &[(7, 1.7), (8, 2.12), (9, 2.65)];

/// The pitch-diameter tolerance (mm) of class `class` for diameter `d` and pitch `p` (mm), as
/// [`limits`] computes it.
pub(super) fn pitch_tolerance(d: f64, p: f64, class: Class) -> Option<f64> {
    let Class::Trapezoidal { grade, position } = class else {
        return None;
    };
    let table = if position == 'H' {
        INTERNAL_GRADES
    } else {
        TD2_GRADES
    };
    Some(r40(td2_6(d, p)? * grade_factor(grade, table)?) / 1000.0)
}

pub(super) fn limits(t: &StandardThread, class: Class) -> std::result::Result<Limits, String> {
    let Class::Trapezoidal { grade, position } = class else {
        return Err("a trapezoidal thread takes an ISO 2903 class such as 7e or 7H".into());
    };
    let (d, p) = (t.basic.major, t.pitch);
    let es = deviation(position, p)
        .ok_or_else(|| format!("`{position}` is not an ISO 2903 position (c, e, H)"))?;
    let td2_6 = td2_6(d, p).ok_or("the diameter lies outside ISO 2903's ranges")?;
    let ac = crest_clearance(p);
    let um = |v: f64| v / 1000.0;
    let r3 = |v: f64| round_to(v, 3);
    let d2 = d - 0.5 * p;
    if position == 'H' {
        let f = grade_factor(grade, INTERNAL_GRADES).ok_or_else(|| {
            format!("ISO 2903 has internal pitch-diameter grades 7, 8 and 9, not {grade}")
        })?;
        let td2 = r40(td2_6 * f);
        let td1 = at_pitch(TD1_TABLE, p).unwrap_or_else(|| r40(td1_6(p) * 0.63));
        Ok(Limits {
            class,
            side: Surface::Internal,
            deviation: 0.0,
            major: Range {
                min: Some(r3(d + 2.0 * ac)),
                max: None,
            },
            pitch: Range::both(r3(d2), r3(d2 + um(td2))),
            minor: Range::both(r3(d - p), r3(d - p + um(td1))),
        })
    } else {
        let f = grade_factor(grade, TD2_GRADES)
            .filter(|_| grade >= 7)
            .ok_or_else(|| {
                format!("ISO 2903 has external pitch-diameter grades 7, 8 and 9, not {grade}")
            })?;
        let td2 = r40(td2_6 * f);
        let td = r40(td_6(p) * 0.63);
        let td3 = TD3_TABLE
            .iter()
            .find(|&&(tp, g, pos, _)| (tp - p).abs() < 1e-9 && g == grade && pos == position)
            .map_or_else(|| (1.25 * td2 + es.abs() + 0.5).floor(), |r| r.3);
        let d3 = d - 2.0 * (0.5 * p + ac);
        let d2max = d2 + um(es);
        Ok(Limits {
            class,
            side: Surface::External,
            deviation: um(es),
            major: Range::both(r3(d - um(td)), r3(d)),
            pitch: Range::both(r3(d2max - um(td2)), r3(d2max)),
            minor: Range::both(r3(d3 - um(td3)), r3(d3)),
        })
    }
}
