//! Pipe threads: NPT (ASME B1.20.1), ISO 7-1 (R, Rc, Rp; "BSPT") and ISO 228-1 (G; "BSPP").
//!
//! NPT, computed in inch from ASME B1.20.1 §3 and Table 2 (D = outside diameter of the pipe,
//! p = 1/n):
//! * `E0 = D − (0.05·D + 1.1)·p` (pitch diameter at the small end), `E1 = E0 + 0.0625·L1`
//!   (at the gauge plane, L1 tabulated), `L2 = (0.80·D + 6.8)·p`, `E2 = E0 + 0.0625·L2`;
//!   pitch diameters to 5 decimals, lengths to 4, a tie to the even digit (3": E0 3.340625 →
//!   3.34062, 4": 4.334375 → 4.33438, as Table 2 prints);
//! * `H = 0.866025·p`, `h = 0.800·p`, crest and root truncated 0.033·p to the Table 1 maximum;
//!   gauging ±1 turn at the gauge plane (±p/16 on the pitch diameter); V = 3.47·p; L3 = 3·p.
//!
//! ISO 7-1 and ISO 228-1 share the Whitworth-form diameters (mm): the major diameter is
//! tabulated (the inch sizes of BS 21 × 25.4 to 0.001 mm), `h = 0.640327·P` rounded to 0.001 mm,
//! `d2 = d − h`, `d1 = d − 2h` (ISO 7-1 Table 1, ISO 228-1 Table 1). ISO 7-1's gauge lengths and
//! their tolerances, the useful thread lengths, and ISO 228-1's tolerances are tabulated.

use super::gauge::Taper;
use super::profile::{Edge, Profile};
use super::{
    bad_name, fill, round_half_even, Basic, Class, Family, Limits, ParallelClass, Range, Result,
    Series, StandardThread, Surface,
};
use crate::units::{Units, MM_PER_INCH};

// ---------------------------------------------------------------------------------------------
// NPT
// ---------------------------------------------------------------------------------------------

/// An NPT size: (name, outside diameter of the pipe D, threads per inch, L1), inch. ASME B1.20.1
/// Table 2.
const NPT: &[(&str, f64, f64, f64)] = &[
    ("1/16", 0.3125, 27.0, 0.160),
    ("1/8", 0.405, 27.0, 0.1615),
    ("1/4", 0.540, 18.0, 0.2278),
    ("3/8", 0.675, 18.0, 0.240),
    ("1/2", 0.840, 14.0, 0.320),
    ("3/4", 1.050, 14.0, 0.339),
    ("1", 1.315, 11.5, 0.400),
    ("1-1/4", 1.660, 11.5, 0.420),
    ("1-1/2", 1.900, 11.5, 0.420),
    ("2", 2.375, 11.5, 0.436),
    ("2-1/2", 2.875, 8.0, 0.682),
    ("3", 3.500, 8.0, 0.766),
    ("3-1/2", 4.000, 8.0, 0.821),
    ("4", 4.500, 8.0, 0.844),
    ("5", 5.563, 8.0, 0.937),
    ("6", 6.625, 8.0, 0.958),
    ("8", 8.625, 8.0, 1.063),
    ("10", 10.750, 8.0, 1.210),
    ("12", 12.750, 8.0, 1.360),
    ("14", 14.000, 8.0, 1.562),
    ("16", 16.000, 8.0, 1.812),
    ("18", 18.000, 8.0, 2.000),
    ("20", 20.000, 8.0, 2.125),
    ("24", 24.000, 8.0, 2.375),
];

/// Maximum truncation of crest and root by threads per inch (inch), ASME B1.20.1 Table 1; the
/// minimum is 0.033·p.
const NPT_TRUNCATION_MAX: &[(f64, f64)] = &[
    (27.0, 0.0036),
    (18.0, 0.0049),
    (14.0, 0.0056),
    (11.5, 0.0063),
    (8.0, 0.0078),
];

/// Length of the vanish thread by threads per inch (inch), ASME B1.20.1 Table 2 ("3.47
/// threads"; the printed lengths are 3.4696·p to the digit: 14 tpi 0.2478, not 3.47/14 → 0.2479).
const NPT_VANISH: &[(f64, f64)] = &[
    (27.0, 0.1285),
    (18.0, 0.1928),
    (14.0, 0.2478),
    (11.5, 0.3017),
    (8.0, 0.4337),
];

/// The computed NPT quantities of one size (inch).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NptData {
    pub od: f64,
    pub tpi: f64,
    pub p: f64,
    pub e0: f64,
    pub e1: f64,
    pub l1: f64,
    pub l2: f64,
    pub e2: f64,
    /// Height of the truncated thread, 0.8·p.
    pub h: f64,
    pub truncation_min: f64,
    pub truncation_max: f64,
    pub vanish: f64,
    pub l3: f64,
    /// Overall length of the external thread, L4 = L2 + V (to 4 decimals from the printed L2 and
    /// V: 1/2-14 0.5337 + 0.2478 = 0.7815).
    pub l4: f64,
}

fn npt_data(od: f64, tpi: f64, l1: f64) -> NptData {
    let p = 1.0 / tpi;
    let e0 = od - (0.05 * od + 1.1) * p;
    let l2 = (0.80 * od + 6.8) * p;
    let r5 = |v: f64| round_half_even(v, 5);
    let r4 = |v: f64| round_half_even(v, 4);
    let vanish = NPT_VANISH
        .iter()
        .find(|(n, _)| (n - tpi).abs() < 1e-9)
        .map_or(r4(3.47 * p), |&(_, v)| v);
    NptData {
        od,
        tpi,
        p,
        e0: r5(e0),
        e1: r5(e0 + 0.0625 * l1),
        l1,
        l2: r4(l2),
        e2: r5(e0 + 0.0625 * l2),
        h: r5(0.8 * p),
        truncation_min: r4(0.033 * p),
        truncation_max: NPT_TRUNCATION_MAX
            .iter()
            .find(|(n, _)| (n - tpi).abs() < 1e-9)
            .map_or(0.0, |&(_, f)| f),
        vanish,
        l3: r4(3.0 * p),
        l4: r4(r4(l2) + vanish),
    }
}

/// The NPT data of a thread looked up by name (inch).
pub fn npt(t: &StandardThread) -> Option<NptData> {
    let tpi = t.tpi?;
    NPT.iter()
        .find(|(n, _, _, _)| t.name == npt_name(n, tpi))
        .map(|&(_, od, tpi, l1)| npt_data(od, tpi, l1))
}

fn npt_name(size: &str, tpi: f64) -> String {
    format!("{size}-{} NPT", super::trim(tpi))
}

/// `1/2-14 NPT`, `1/2 NPT`, `1-1/4-11.5 NPT`, `1 1/4 NPT`.
pub fn lookup_npt(text: &str) -> Result<StandardThread> {
    let upper = text.to_ascii_uppercase();
    let at = upper.find("NPT").unwrap_or(upper.len());
    let head = text[..at].trim().trim_end_matches('-').trim();
    let tail = text[at + 3.min(text.len() - at)..].trim();
    if !tail.is_empty() {
        return Err(bad_name(
            text,
            format!(
                "`{tail}`: NPT threads have one class (gauged ±1 turn); write e.g. `1/2-14 NPT`"
            ),
        ));
    }
    let (size, tpi) = split_size_tpi(head);
    let norm = norm_size(size);
    let Some(&(name, od, n, l1)) = NPT.iter().find(|(s, _, _, _)| *s == norm) else {
        return Err(super::unknown(
            text,
            "no ASME B1.20.1 NPT size of that name",
            None,
        ));
    };
    if let Some(tpi) = tpi {
        if (tpi - n).abs() > 1e-9 {
            return Err(bad_name(
                text,
                format!(
                    "NPT {name} has {} threads per inch, not {tpi}",
                    super::trim(n)
                ),
            ));
        }
    }
    let d = npt_data(od, n, l1);
    let p = MM_PER_INCH / n;
    let mm = |v: f64| v * MM_PER_INCH;
    let h_sharp = super::H_PER_P * d.p;
    let taper = Taper {
        diameter_per_length: 1.0 / 16.0,
        gauge_length: mm(d.l1),
        external_position_tolerance: p,
        internal_position_tolerance: p,
        internal_gauge_plane: 0.0,
        gauge_pitch_diameter: mm(d.e1),
        gauge_major_diameter: mm(d.e1 + h_sharp - (d.truncation_min + d.truncation_max)),
        small_end_pitch_diameter: mm(d.e0),
        effective_length: mm(d.l2),
        effective_end_pitch_diameter: mm(d.e2),
        vanish_length: mm(d.vanish),
        wrench_makeup: mm(d.l3),
        overall_length: mm(d.l4),
        // ASME B1.20.1 Table 1: taper on the pitch line 3/4 in/ft, +1/8 −1/16 in/ft.
        taper_tolerance: Some((1.0 / 16.0 / 12.0, 1.0 / 8.0 / 12.0)),
    };
    let mut t = StandardThread {
        name: npt_name(name, n),
        family: Family::Npt,
        series: Series::Npt,
        units: Units::Inch,
        pitch: p,
        tpi: Some(n),
        basic: Basic {
            major: mm(d.e1 + h_sharp),
            pitch_diameter: mm(d.e1),
            minor: mm(d.e1 - h_sharp),
            fundamental_height: mm(h_sharp),
        },
        external_depth: mm(d.h),
        internal_depth: mm(d.h),
        external: None,
        internal: None,
        profile: Profile {
            angle_deg: 60.0,
            flank_angle_deg: 30.0,
            fundamental_height: mm(h_sharp),
            external_crest: truncated(&d),
            external_root: truncated(&d),
            internal_crest: truncated(&d),
            internal_root: truncated(&d),
        },
        taper: Some(taper),
    };
    fill(&mut t, None, text)?;
    Ok(t)
}

fn truncated(d: &NptData) -> Edge {
    Edge::Truncated {
        min: d.truncation_min * MM_PER_INCH,
        max: d.truncation_max * MM_PER_INCH,
    }
}

/// NPT limits at the gauge plane (inch, then mm): the pitch diameter E1 ± one turn (p/16), the
/// major and minor diameters of the truncated form around it.
pub(super) fn npt_limits(t: &StandardThread, class: Class) -> std::result::Result<Limits, String> {
    let Class::Pipe { side } = class else {
        return Err("an NPT thread has no tolerance class (it is gauged ±1 turn)".into());
    };
    let d = npt(t).ok_or("not a tabulated NPT size")?;
    let turn = d.p / 16.0;
    let h = super::H_PER_P * d.p;
    let r4 = |v: f64| round_half_even(v, 4);
    let r5 = |v: f64| round_half_even(v, 5);
    let pitch = Range::both(r5(d.e1 - turn), r5(d.e1 + turn));
    // The crest of one thread is the root of the other: the same limits on both sides.
    let major = Range::both(
        r4(d.e1 - turn + h - 2.0 * d.truncation_max),
        r4(d.e1 + turn + h - 2.0 * d.truncation_min),
    );
    let minor = Range::both(
        r4(d.e1 - turn - h + 2.0 * d.truncation_min),
        r4(d.e1 + turn - h + 2.0 * d.truncation_max),
    );
    Ok(Limits {
        class,
        side,
        deviation: 0.0,
        major: major.to_mm(),
        pitch: pitch.to_mm(),
        minor: minor.to_mm(),
    })
}

// ---------------------------------------------------------------------------------------------
// ISO 7-1 and ISO 228-1
// ---------------------------------------------------------------------------------------------

/// A Whitworth-form pipe size (mm): designation, threads per inch, major (gauge) diameter.
/// ISO 228-1 Table 1 (all sizes); ISO 7-1 uses the sizes marked in [`ISO7`].
const PIPE_SIZES: &[(&str, f64, f64)] = &[
    ("1/16", 28.0, 7.723),
    ("1/8", 28.0, 9.728),
    ("1/4", 19.0, 13.157),
    ("3/8", 19.0, 16.662),
    ("1/2", 14.0, 20.955),
    ("5/8", 14.0, 22.911),
    ("3/4", 14.0, 26.441),
    ("7/8", 14.0, 30.201),
    ("1", 11.0, 33.249),
    ("1-1/8", 11.0, 37.897),
    ("1-1/4", 11.0, 41.910),
    ("1-1/2", 11.0, 47.803),
    ("1-3/4", 11.0, 53.746),
    ("2", 11.0, 59.614),
    ("2-1/4", 11.0, 65.710),
    ("2-1/2", 11.0, 75.184),
    ("2-3/4", 11.0, 81.534),
    ("3", 11.0, 87.884),
    ("3-1/2", 11.0, 100.330),
    ("4", 11.0, 113.030),
    ("4-1/2", 11.0, 125.730),
    ("5", 11.0, 138.430),
    ("5-1/2", 11.0, 151.130),
    ("6", 11.0, 163.830),
];

/// ISO 7-1 Table 1 (mm): size, basic gauge length, ±T1/2 (external gauge length), ±T2/2
/// (internal gauge plane), useful thread length of the external thread for the basic gauge
/// length, and the tolerances in turns (T1/2, T2/2) from which Rp's diameter tolerance follows.
const ISO7: &[(&str, f64, f64, f64, f64, f64, f64)] = &[
    ("1/16", 4.0, 0.9, 1.1, 6.5, 1.0, 1.25),
    ("1/8", 4.0, 0.9, 1.1, 6.5, 1.0, 1.25),
    ("1/4", 6.0, 1.3, 1.7, 9.7, 1.0, 1.25),
    ("3/8", 6.4, 1.3, 1.7, 10.1, 1.0, 1.25),
    ("1/2", 8.2, 1.8, 2.3, 13.2, 1.0, 1.25),
    ("3/4", 9.5, 1.8, 2.3, 14.5, 1.0, 1.25),
    ("1", 10.4, 2.3, 2.9, 16.8, 1.0, 1.25),
    ("1-1/4", 12.7, 2.3, 2.9, 19.1, 1.0, 1.25),
    ("1-1/2", 12.7, 2.3, 2.9, 19.1, 1.0, 1.25),
    ("2", 15.9, 2.3, 2.9, 23.4, 1.0, 1.25),
    ("2-1/2", 17.5, 3.5, 3.5, 26.7, 1.5, 1.5),
    ("3", 20.6, 3.5, 3.5, 29.8, 1.5, 1.5),
    ("4", 25.4, 3.5, 3.5, 35.8, 1.5, 1.5),
    ("5", 28.6, 3.5, 3.5, 40.1, 1.5, 1.5),
    ("6", 28.6, 3.5, 3.5, 40.1, 1.5, 1.5),
];

/// Whitworth-form constants: the parallel form (ISO 228-1, BS 84) and the taper form (ISO 7-1).
pub const WHITWORTH_FUNDAMENTAL: f64 = 0.960_491;
pub const WHITWORTH_DEPTH: f64 = 0.640_327;
pub const WHITWORTH_RADIUS: f64 = 0.137_329;
/// ISO 7-1 taper form: H = 0.960237·P, r = 0.137278·P (h is the same 0.640327·P).
pub const TAPER_H: f64 = 0.960_237;
pub const TAPER_R: f64 = 0.137_278;

/// The diameters of a pipe size (mm): d, d2, d1, h, P.
fn pipe_diameters(d: f64, tpi: f64) -> (f64, f64, f64, f64, f64) {
    let p = MM_PER_INCH / tpi;
    let h = super::round_to(WHITWORTH_DEPTH * p, 3);
    let r3 = |v: f64| super::round_to(v, 3);
    (d, r3(d - h), r3(d - 2.0 * h), h, p)
}

fn whitworth_profile(p: f64, taper: bool) -> Profile {
    let (hh, r) = if taper {
        (TAPER_H, TAPER_R)
    } else {
        (WHITWORTH_FUNDAMENTAL, WHITWORTH_RADIUS)
    };
    let round = Edge::Round { radius: r * p };
    Profile {
        angle_deg: 55.0,
        flank_angle_deg: 27.5,
        fundamental_height: hh * p,
        external_crest: round,
        external_root: round,
        internal_crest: round,
        internal_root: round,
    }
}

/// Splits `1/2-14` / `1-1/4` / `1 1/4` into the size and an optional thread count (a trailing
/// `-N` whose N is a plain number after a size that already has its fraction).
fn split_size_tpi(head: &str) -> (&str, Option<f64>) {
    if let Some((a, b)) = head.rsplit_once('-') {
        if !b.contains('/') && !a.trim().is_empty() {
            if let Some(n) = super::number(b) {
                return (a.trim(), Some(n));
            }
        }
    }
    (head.trim(), None)
}

/// `1 1/4`, `1-1/4`, `1.1/4` → `1-1/4`.
pub(super) fn norm_size(size: &str) -> String {
    let s = size.trim();
    if s.starts_with(['-', '.']) || s.ends_with(['-', '.']) || s.contains("--") {
        // Not a size: left as written, it matches none.
        return s.to_string();
    }
    let parts: Vec<&str> = s.split([' ', '-', '.']).filter(|p| !p.is_empty()).collect();
    parts.join("-")
}

fn pipe_size(text: &str, size: &str) -> Result<(&'static str, f64, f64)> {
    let norm = norm_size(size);
    PIPE_SIZES
        .iter()
        .find(|(s, _, _)| *s == norm)
        .copied()
        .ok_or_else(|| super::unknown(text, "no pipe-thread size of that name", None))
}

/// `R1/2`, `Rc1/2`, `Rp 1-1/2`.
pub fn lookup_iso7(text: &str) -> Result<StandardThread> {
    let t = text.trim();
    let upper = t.to_ascii_uppercase();
    let (series, rest) = if upper.starts_with("RC") {
        (Series::Rc, &t[2..])
    } else if upper.starts_with("RP") {
        (Series::Rp, &t[2..])
    } else {
        (Series::R, &t[1..])
    };
    let (name, tpi, d) = pipe_size(text, rest)?;
    let Some(&(_, gl, t1, t2, useful, _, _)) = ISO7.iter().find(|r| r.0 == name) else {
        return Err(super::unknown(text, "no ISO 7-1 size of that name", None));
    };
    let (d, d2, d1, h, p) = pipe_diameters(d, tpi);
    let side = if series == Series::R {
        Surface::External
    } else {
        Surface::Internal
    };
    let tapered = series != Series::Rp;
    let taper = tapered.then_some(Taper {
        diameter_per_length: 1.0 / 16.0,
        gauge_length: gl,
        external_position_tolerance: t1,
        internal_position_tolerance: t2,
        // ISO 7-1:1994, 3.3 note 4 (as quoted in issue 27): half a pitch behind the face.
        internal_gauge_plane: p / 2.0,
        gauge_pitch_diameter: d2,
        gauge_major_diameter: d,
        small_end_pitch_diameter: d2 - gl / 16.0,
        effective_length: useful,
        effective_end_pitch_diameter: d2 + (useful - gl) / 16.0,
        vanish_length: 0.0,
        wrench_makeup: 0.0,
        overall_length: 0.0,
        taper_tolerance: None,
    });
    let mut th = StandardThread {
        name: format!("{}{}", series.name(), name),
        family: Family::Bspt,
        series,
        units: Units::Mm,
        pitch: p,
        tpi: Some(tpi),
        basic: Basic {
            major: d,
            pitch_diameter: d2,
            minor: d1,
            fundamental_height: if tapered {
                TAPER_H
            } else {
                WHITWORTH_FUNDAMENTAL
            } * p,
        },
        external_depth: h,
        internal_depth: h,
        external: None,
        internal: None,
        profile: whitworth_profile(p, tapered),
        taper,
    };
    fill(&mut th, Some(Class::Pipe { side }), text)?;
    Ok(th)
}

/// ISO 7-1 limits (mm): R and Rc at their gauge plane (the pitch diameter ± T1/2 or ± T2/2 on a
/// 1:16 taper; major and minor move with it), Rp parallel with its diameter tolerance ±(T2/2 in
/// turns)·P/16 (0.071, 0.104, 0.142, 0.180, 0.216 mm).
pub(super) fn iso7_limits(t: &StandardThread, class: Class) -> std::result::Result<Limits, String> {
    let Class::Pipe { side } = class else {
        return Err("an ISO 7-1 thread has no tolerance class".into());
    };
    let size = t
        .name
        .trim_start_matches(|c: char| c.is_ascii_alphabetic())
        .to_string();
    let row = ISO7
        .iter()
        .find(|r| r.0 == size)
        .ok_or("not a tabulated ISO 7-1 size")?;
    let (d, d2, d1) = (t.basic.major, t.basic.pitch_diameter, t.basic.minor);
    // Rp: a tabulated diameter tolerance. R, Rc: the gauge plane's position tolerance on the
    // 1:16 taper, exact (ISO 7-1 tabulates the lengths, not these diameters).
    let tol = if t.series == Series::Rp {
        super::round_to(row.6 * t.pitch / 16.0, 3)
    } else {
        let position = match side {
            Surface::External => row.2,
            Surface::Internal => row.3,
        };
        position / 16.0
    };
    Ok(Limits {
        class,
        side,
        deviation: 0.0,
        major: Range::both(d - tol, d + tol),
        pitch: Range::both(d2 - tol, d2 + tol),
        minor: Range::both(d1 - tol, d1 + tol),
    })
}

/// ISO 228-1 tolerances (mm) by threads per inch and size: TD2 (= class A Td2), TD1.
fn iso228_tolerances(tpi: f64, d: f64) -> (f64, f64) {
    match tpi as u32 {
        28 => (0.107, 0.282),
        19 => (0.125, 0.445),
        14 => (0.142, 0.541),
        _ if d < 60.0 => (0.180, 0.640),
        _ => (0.217, 0.640),
    }
}

/// `G1/2` (internal), `G1/2-A`, `G1/2 B`, `G 1-1/2A`.
pub fn lookup_iso228(text: &str) -> Result<StandardThread> {
    let t = text.trim();
    let mut rest = t[1..].trim();
    let mut grade = ParallelClass::Internal;
    let upper = rest.to_ascii_uppercase();
    if upper.ends_with('A') || upper.ends_with('B') {
        grade = if upper.ends_with('A') {
            ParallelClass::A
        } else {
            ParallelClass::B
        };
        rest = rest[..rest.len() - 1]
            .trim_end()
            .trim_end_matches('-')
            .trim_end();
    }
    let (name, tpi, d) = pipe_size(text, rest)?;
    let (d, d2, d1, h, p) = pipe_diameters(d, tpi);
    let mut th = StandardThread {
        name: format!("G{name}"),
        family: Family::Bspp,
        series: Series::G,
        units: Units::Mm,
        pitch: p,
        tpi: Some(tpi),
        basic: Basic {
            major: d,
            pitch_diameter: d2,
            minor: d1,
            fundamental_height: WHITWORTH_FUNDAMENTAL * p,
        },
        external_depth: h,
        internal_depth: h,
        external: None,
        internal: None,
        profile: whitworth_profile(p, false),
        taper: None,
    };
    fill(&mut th, Some(Class::Parallel { grade }), text)?;
    Ok(th)
}

/// ISO 228-1 limits (mm): internal D2 +TD2, D1 +TD1, D min; external d −Td (= 2·TD2), d2 −Td2
/// (class A = TD2, class B = 2·TD2), d1 max.
pub(super) fn iso228_limits(
    t: &StandardThread,
    class: Class,
) -> std::result::Result<Limits, String> {
    let Class::Parallel { grade } = class else {
        return Err("an ISO 228-1 thread takes class A or B (external) or none (internal)".into());
    };
    let (d, d2, d1) = (t.basic.major, t.basic.pitch_diameter, t.basic.minor);
    let (td2, td1) = iso228_tolerances(t.tpi.unwrap_or(0.0), d);
    let r3 = |v: f64| super::round_to(v, 3);
    Ok(match grade {
        ParallelClass::Internal => Limits {
            class,
            side: Surface::Internal,
            deviation: 0.0,
            major: Range {
                min: Some(d),
                max: None,
            },
            pitch: Range::both(d2, r3(d2 + td2)),
            minor: Range::both(d1, r3(d1 + td1)),
        },
        ParallelClass::A | ParallelClass::B => {
            let k = if grade == ParallelClass::A { 1.0 } else { 2.0 };
            Limits {
                class,
                side: Surface::External,
                deviation: 0.0,
                major: Range::both(r3(d - 2.0 * td2), d),
                pitch: Range::both(r3(d2 - k * td2), d2),
                minor: Range {
                    min: None,
                    max: Some(d1),
                },
            }
        }
    })
}

/// Every pipe thread's canonical name.
pub fn known_names() -> Vec<String> {
    let mut v: Vec<String> = NPT.iter().map(|&(s, _, n, _)| npt_name(s, n)).collect();
    for s in ["R", "Rc", "Rp"] {
        v.extend(ISO7.iter().map(|r| format!("{s}{}", r.0)));
    }
    for &(s, _, _) in PIPE_SIZES {
        v.push(format!("G{s}"));
        v.push(format!("G{s}-A"));
        v.push(format!("G{s}-B"));
    }
    v
}
