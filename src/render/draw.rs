//! What the pictures share: a map from the model to the page, points and numbers written for SVG,
//! text escaped, and what a picture left out said in words. Below both the threads' panels
//! ([`super::svg`]) and the part's ([`super::part`]).

use std::fmt::Write;

/// What a picture of the threads numbered `drawn` (ascending) of `total` leaves out:
/// `threads 1–50 of 20000 drawn, 19950 left out`.
pub fn left_out(drawn: &[usize], total: usize) -> String {
    let which = match (drawn.first(), drawn.last()) {
        (Some(a), Some(b)) if a == b => format!("thread {a} of {total}"),
        (Some(a), Some(b)) if b - a + 1 == drawn.len() => format!("threads {a}–{b} of {total}"),
        (Some(_), Some(_)) => format!("{} of {total} threads", drawn.len()),
        _ => format!("none of {total} threads"),
    };
    format!(
        "{which} drawn, {} left out",
        total.saturating_sub(drawn.len())
    )
}

/// A linear map from model coordinates to the page.
#[derive(Clone, Copy)]
pub(super) struct Map {
    /// Page x = ox + sx·a, page y = oy + sy·b.
    pub(super) ox: f64,
    pub(super) sx: f64,
    pub(super) oy: f64,
    pub(super) sy: f64,
}

impl Map {
    pub(super) fn at(&self, a: f64, b: f64) -> (f64, f64) {
        (self.ox + self.sx * a, self.oy + self.sy * b)
    }
}

pub(super) fn points(map: &Map, pts: &[(f64, f64)]) -> String {
    let mut out = String::with_capacity(pts.len() * 16);
    for (i, &(a, b)) in pts.iter().enumerate() {
        let (x, y) = map.at(a, b);
        if i > 0 {
            out.push(' ');
        }
        let _ = write!(out, "{x:.2},{y:.2}");
    }
    out
}

/// A number for a label: up to `decimals` decimals, no trailing zeros or point.
pub(super) fn num(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        &s
    };
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}

/// Escapes text for XML.
pub(super) fn text(t: &str) -> String {
    t.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
}
