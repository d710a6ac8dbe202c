//! Whitworth-form threads, BS 84 (55°, rounded crests and roots): BSW (coarse) and BSF (fine),
//! computed in inch.
//!
//! * Form: `H = 0.960491·p`, thread depth `h = 0.640327·p` (= 2/3·H), crest and root radius
//!   `r = 0.137329·p`; effective diameter `D − h`, minor `D − 2h` (BS 84 clause 4).
//! * Tolerances (BS 84 Annex B, as Machinery's Handbook tabulates them):
//!   `T = 0.002·∛D + 0.003·√L + 0.005·√p` with the length of engagement L = D; external
//!   ("bolts") close / medium / free: effective `2/3·T`, `T`, `3/2·T`; major `+ 0.01·√p` on the
//!   effective tolerance; minor `2/3·T + 0.013·√p` (close) or `T + 0.02·√p` / `3/2·T + 0.02·√p`;
//!   internal ("nuts") medium / normal: effective `T`, `3/2·T`; minor `0.2·p + 0.004` (26 threads
//!   per inch and finer), `+ 0.005` (24, 22), `+ 0.007` (20 and coarser); no allowance; limits
//!   and tolerances to 0.0001 inch.

use super::pipe::{WHITWORTH_DEPTH, WHITWORTH_FUNDAMENTAL, WHITWORTH_RADIUS};
use super::profile::{Edge, Profile};
use super::{
    bad_name, fill, round_to, trim, unknown, Basic, Class, Family, Limits, Range, Result, Series,
    StandardThread, Surface, WhitworthClass,
};
use crate::units::{Units, MM_PER_INCH};

/// BSW: size, major diameter, threads per inch (BS 84 Table 1).
const BSW: &[(&str, f64, f64)] = &[
    ("1/8", 0.125, 40.0),
    ("3/16", 0.1875, 24.0),
    ("1/4", 0.25, 20.0),
    ("5/16", 0.3125, 18.0),
    ("3/8", 0.375, 16.0),
    ("7/16", 0.4375, 14.0),
    ("1/2", 0.5, 12.0),
    ("9/16", 0.5625, 12.0),
    ("5/8", 0.625, 11.0),
    ("11/16", 0.6875, 11.0),
    ("3/4", 0.75, 10.0),
    ("7/8", 0.875, 9.0),
    ("1", 1.0, 8.0),
    ("1-1/8", 1.125, 7.0),
    ("1-1/4", 1.25, 7.0),
    ("1-1/2", 1.5, 6.0),
    ("1-3/4", 1.75, 5.0),
    ("2", 2.0, 4.5),
    ("2-1/4", 2.25, 4.0),
    ("2-1/2", 2.5, 4.0),
    ("2-3/4", 2.75, 3.5),
    ("3", 3.0, 3.5),
    ("3-1/4", 3.25, 3.25),
    ("3-1/2", 3.5, 3.25),
    ("3-3/4", 3.75, 3.0),
    ("4", 4.0, 3.0),
    ("4-1/2", 4.5, 2.875),
    ("5", 5.0, 2.75),
    ("5-1/2", 5.5, 2.625),
    ("6", 6.0, 2.5),
];

/// BSF (BS 84 Table 2).
const BSF: &[(&str, f64, f64)] = &[
    ("3/16", 0.1875, 32.0),
    ("7/32", 0.21875, 28.0),
    ("1/4", 0.25, 26.0),
    ("9/32", 0.28125, 26.0),
    ("5/16", 0.3125, 22.0),
    ("3/8", 0.375, 20.0),
    ("7/16", 0.4375, 18.0),
    ("1/2", 0.5, 16.0),
    ("9/16", 0.5625, 16.0),
    ("5/8", 0.625, 14.0),
    ("11/16", 0.6875, 14.0),
    ("3/4", 0.75, 12.0),
    ("7/8", 0.875, 11.0),
    ("1", 1.0, 10.0),
    ("1-1/8", 1.125, 9.0),
    ("1-1/4", 1.25, 9.0),
    ("1-3/8", 1.375, 8.0),
    ("1-1/2", 1.5, 8.0),
    ("1-5/8", 1.625, 8.0),
    ("1-3/4", 1.75, 7.0),
    ("2", 2.0, 7.0),
    ("2-1/4", 2.25, 6.0),
    ("2-1/2", 2.5, 6.0),
    ("2-3/4", 2.75, 6.0),
    ("3", 3.0, 5.0),
    ("3-1/4", 3.25, 5.0),
    ("3-1/2", 3.5, 4.5),
    ("3-3/4", 3.75, 4.5),
    ("4", 4.0, 4.5),
    ("4-1/4", 4.25, 4.0),
];

fn name(size: &str, tpi: f64, series: Series) -> String {
    format!("{size}-{} {}", trim(tpi), series.name())
}

pub fn known_names() -> Vec<String> {
    let mut v: Vec<String> = BSW
        .iter()
        .map(|&(s, _, n)| name(s, n, Series::Bsw))
        .collect();
    v.extend(BSF.iter().map(|&(s, _, n)| name(s, n, Series::Bsf)));
    v
}

fn parse_class(s: &str) -> Option<WhitworthClass> {
    match s.trim().to_ascii_lowercase().as_str() {
        "close" => Some(WhitworthClass::Close),
        "medium" => Some(WhitworthClass::Medium),
        "free" => Some(WhitworthClass::Free),
        "normal" => Some(WhitworthClass::Normal),
        _ => None,
    }
}

/// `1/2-12 BSW`, `1/2 BSW`, `1/2-16 BSF-close`, `1/2 BSW normal`.
pub fn lookup(text: &str) -> Result<StandardThread> {
    let upper = text.to_ascii_uppercase();
    let (at, series) = match upper.find("BSW") {
        Some(i) => (i, Series::Bsw),
        None => (upper.find("BSF").unwrap_or(0), Series::Bsf),
    };
    let head = text[..at].trim().trim_end_matches('-').trim();
    let tail = text[at + 3..].trim().trim_start_matches('-').trim();
    let class = if tail.is_empty() {
        None
    } else {
        Some(parse_class(tail).ok_or_else(|| {
            bad_name(
                text,
                format!(
                    "`{tail}` is not a BS 84 class (close, medium, free; nuts: medium, normal)"
                ),
            )
        })?)
    };
    let (size, tpi) = match head.rsplit_once('-') {
        Some((a, b)) if !b.contains('/') => (a.trim(), super::number(b)),
        _ => (head, None),
    };
    let norm = super::pipe::norm_size(size);
    let table = if series == Series::Bsw { BSW } else { BSF };
    let Some(&(sname, d, n)) = table.iter().find(|(s, _, _)| *s == norm) else {
        return Err(unknown(text, "no BS 84 size of that name", None));
    };
    if let Some(tpi) = tpi {
        if (tpi - n).abs() > 1e-9 {
            return Err(unknown(
                text,
                "no BSW or BSF thread of that size and pitch",
                Some((d * MM_PER_INCH, MM_PER_INCH / tpi)),
            ));
        }
    }
    let p = 1.0 / n;
    let mm = |v: f64| v * MM_PER_INCH;
    let h = WHITWORTH_DEPTH * p;
    let round = Edge::Round {
        radius: mm(WHITWORTH_RADIUS * p),
    };
    let mut t = StandardThread {
        name: name(sname, n, series),
        family: Family::Whitworth,
        series,
        units: Units::Inch,
        pitch: mm(p),
        tpi: Some(n),
        basic: Basic {
            major: mm(d),
            pitch_diameter: mm(round_to(d - h, 4)),
            minor: mm(round_to(d - 2.0 * h, 4)),
            fundamental_height: mm(WHITWORTH_FUNDAMENTAL * p),
        },
        external_depth: mm(h),
        internal_depth: mm(h),
        external: None,
        internal: None,
        profile: Profile {
            angle_deg: 55.0,
            flank_angle_deg: 27.5,
            fundamental_height: mm(WHITWORTH_FUNDAMENTAL * p),
            external_crest: round,
            external_root: round,
            internal_crest: round,
            internal_root: round,
        },
        taper: None,
    };
    match class {
        None => fill(&mut t, None, text)?,
        Some(WhitworthClass::Medium) => {
            for side in [Surface::External, Surface::Internal] {
                fill(
                    &mut t,
                    Some(Class::Whitworth {
                        grade: WhitworthClass::Medium,
                        side,
                    }),
                    text,
                )?;
            }
        }
        Some(grade) => {
            let side = if grade == WhitworthClass::Normal {
                Surface::Internal
            } else {
                Surface::External
            };
            fill(&mut t, Some(Class::Whitworth { grade, side }), text)?;
        }
    }
    Ok(t)
}

pub(super) fn limits(t: &StandardThread, class: Class) -> std::result::Result<Limits, String> {
    let Class::Whitworth { grade, side } = class else {
        return Err("a Whitworth thread takes a BS 84 class: close, medium, free or normal".into());
    };
    let d = t.basic.major / MM_PER_INCH;
    let n = t
        .tpi
        .ok_or("a Whitworth thread carries its threads per inch")?;
    let p = 1.0 / n;
    let tt = 0.002 * d.cbrt() + 0.003 * d.sqrt() + 0.005 * p.sqrt();
    let r4 = |v: f64| round_to(v, 4);
    let (de, dm) = (
        t.basic.pitch_diameter / MM_PER_INCH,
        t.basic.minor / MM_PER_INCH,
    );
    let l = match (side, grade) {
        (Surface::External, WhitworthClass::Normal) | (Surface::Internal, WhitworthClass::Free) => {
            return Err(format!(
                "BS 84 has no {} class {} thread",
                grade.name(),
                if side == Surface::External {
                    "external"
                } else {
                    "internal"
                }
            ))
        }
        (Surface::External, g) => {
            let k = match g {
                WhitworthClass::Close => 2.0 / 3.0,
                WhitworthClass::Free => 1.5,
                _ => 1.0,
            };
            let minor_extra = if g == WhitworthClass::Close {
                0.013
            } else {
                0.02
            };
            Limits {
                class,
                side,
                deviation: 0.0,
                major: Range::both(r4(d - (k * tt + 0.01 * p.sqrt())), d),
                pitch: Range::both(r4(de - k * tt), de),
                minor: Range::both(r4(dm - (k * tt + minor_extra * p.sqrt())), dm),
            }
        }
        (Surface::Internal, g) => {
            let k = match g {
                WhitworthClass::Close => 2.0 / 3.0,
                WhitworthClass::Normal => 1.5,
                _ => 1.0,
            };
            let minor_extra = if n >= 26.0 {
                0.004
            } else if n >= 22.0 {
                0.005
            } else {
                0.007
            };
            Limits {
                class,
                side,
                deviation: 0.0,
                major: Range {
                    min: Some(d),
                    max: None,
                },
                pitch: Range::both(de, r4(de + k * tt)),
                minor: Range::both(dm, r4(dm + 0.2 * p + minor_extra)),
            }
        }
    };
    Ok(Limits {
        major: l.major.to_mm(),
        pitch: l.pitch.to_mm(),
        minor: l.minor.to_mm(),
        ..l
    })
}
