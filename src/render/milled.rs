//! `plot` of a milling program: each milled thread in a row of two panels — the helix seen along
//! its axis (every pass's circle, the entry and exit moves) and from the side (the helices drawn
//! turn by turn against the axis, with the thread's section: the teeth the last pass leaves, one
//! pitch apart, at its root).

use std::f64::consts::TAU;
use std::fmt::Write;

use super::draw::{num, points, text, Map};
use crate::mill::motion::{MillKind, MillMotion};
use crate::mill::recognise::{Helix, MilledThread};
use crate::mill::Side;

const WIDTH: f64 = 1100.0;
const ROW: f64 = 460.0;
const PANEL: f64 = 400.0;
/// Points per turn of a drawn helix.
const STEPS: usize = 48;

/// The picture of every milled thread; `tool_angle` is the cutter's included angle (degrees),
/// for the teeth drawn in the section.
pub fn svg(threads: &[MilledThread], tool_angle: f64) -> String {
    let height = ROW * threads.len().max(1) as f64 + 10.0;
    let mut s = String::new();
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH:.0}" height="{height:.0}" viewBox="0 0 {WIDTH:.0} {height:.0}" font-family="DejaVu Sans, sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="{WIDTH:.0}" height="{height:.0}" fill="white"/>"#
    );
    if threads.is_empty() {
        let _ = writeln!(
            s,
            r#"<text x="20" y="40" font-size="16">no milled thread in this program</text>"#
        );
    }
    for (i, t) in threads.iter().enumerate() {
        row(&mut s, t, tool_angle, ROW * i as f64);
    }
    s.push_str("</svg>\n");
    s
}

fn row(s: &mut String, t: &MilledThread, tool_angle: f64, y0: f64) {
    let _ = writeln!(
        s,
        r#"<text x="20" y="{:.2}" font-size="14">line {}: lead {}, {} start(s), {} passes about ({}, {})</text>"#,
        y0 + 22.0,
        t.helices[0].lines.0,
        num(t.lead, 4),
        t.starts,
        t.pass_radii(1e-6).len(),
        num(t.axis[0], 3),
        num(t.axis[1], 3)
    );
    along_axis(s, t, 20.0, y0 + 40.0);
    from_side(s, t, tool_angle, 40.0 + PANEL, y0 + 40.0);
}

/// The plane seen along the axis: each pass's circle, the entries and exits.
fn along_axis(s: &mut String, t: &MilledThread, x0: f64, y0: f64) {
    let reach = t
        .helices
        .iter()
        .flat_map(|h| [h.radius, h.radius_end])
        .fold(0.0, f64::max)
        * 1.3
        + 1e-9;
    let scale = PANEL / (2.0 * reach);
    let map = Map {
        ox: x0 + PANEL / 2.0 - scale * t.axis[0],
        sx: scale,
        oy: y0 + PANEL / 2.0 + scale * t.axis[1],
        sy: -scale,
    };
    frame(s, x0, y0, "along the axis");
    for h in &t.helices {
        let pts: Vec<(f64, f64)> = (0..=STEPS)
            .map(|k| {
                let th = TAU * k as f64 / STEPS as f64;
                (
                    t.axis[0] + h.radius * th.cos(),
                    t.axis[1] + h.radius * th.sin(),
                )
            })
            .collect();
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#1f5fa8" stroke-width="1"/>"##,
            points(&map, &pts)
        );
        for m in [h.entry, h.exit].into_iter().flatten() {
            let pts = plane_points(t, &m);
            let _ = writeln!(
                s,
                r##"<polyline points="{}" fill="none" stroke="#c07000" stroke-width="1.2"/>"##,
                points(&map, &pts)
            );
        }
    }
    let (cx, cy) = map.at(t.axis[0], t.axis[1]);
    let _ = writeln!(
        s,
        r##"<path d="M{:.2},{cy:.2}H{:.2}M{cx:.2},{:.2}V{:.2}" stroke="#888" stroke-dasharray="4 3"/>"##,
        cx - 8.0,
        cx + 8.0,
        cy - 8.0,
        cy + 8.0
    );
}

/// A move drawn in the plane (an arc sampled, a line as its ends).
fn plane_points(t: &MilledThread, m: &MillMotion) -> Vec<(f64, f64)> {
    let (a, b, _) = t.plane.axes();
    match (m.kind, m.sweep(1e-9)) {
        (MillKind::Arc { centre, .. }, Some((r, sweep))) => {
            let start = (m.from[b] - centre[b]).atan2(m.from[a] - centre[a]);
            (0..=STEPS)
                .map(|k| {
                    let th = start + sweep * k as f64 / STEPS as f64;
                    (centre[a] + r * th.cos(), centre[b] + r * th.sin())
                })
                .collect()
        }
        _ => vec![(m.from[a], m.from[b]), (m.to[a], m.to[b])],
    }
}

/// From the side: each helix over its turns (the plane's first axis across, the axis up), and the
/// section's teeth at the last pass's root.
fn from_side(s: &mut String, t: &MilledThread, tool_angle: f64, x0: f64, y0: f64) {
    let reach = t.helices.iter().map(|h| h.radius).fold(0.0, f64::max) * 1.3 + 1e-9;
    let (lo, hi) = (t.to.min(t.from), t.to.max(t.from));
    let span = (hi - lo).max(1e-9);
    let width = WIDTH - x0 - 20.0;
    let scale = (width / (2.0 * reach)).min(0.9 * PANEL / span);
    let map = Map {
        ox: x0 + width / 2.0 - scale * t.axis[0],
        sx: scale,
        oy: y0 + PANEL / 2.0 + scale * (lo + hi) / 2.0,
        sy: -scale,
    };
    frame_wide(
        s,
        x0,
        y0,
        "from the side: the helices, and the section the last pass leaves",
    );
    for h in &t.helices {
        let _ = writeln!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#1f5fa8" stroke-width="0.8"/>"##,
            points(&map, &side_points(t, h))
        );
    }
    teeth(s, t, tool_angle, &map);
    let _ = writeln!(
        s,
        r##"<text x="{:.2}" y="{:.2}" fill="#555">Z{} to Z{}</text>"##,
        x0 + 6.0,
        y0 + PANEL - 6.0,
        num(t.from, 3),
        num(t.to, 3)
    );
}

/// A helix seen from the side: the plane's first axis against the normal axis, turn by turn.
fn side_points(t: &MilledThread, h: &Helix) -> Vec<(f64, f64)> {
    let (a, b, _) = t.plane.axes();
    let start = (h.start[b] - t.axis[1]).atan2(h.start[a] - t.axis[0]);
    let dir = if h.clockwise { -1.0 } else { 1.0 };
    let steps = ((h.turns * STEPS as f64).ceil() as usize).clamp(2, 200_000);
    (0..=steps)
        .map(|k| {
            let f = k as f64 / steps as f64;
            let th = start + dir * TAU * h.turns * f;
            let r = h.radius + (h.radius_end - h.radius) * f;
            (t.axis[0] + r * th.cos(), h.from + (h.to - h.from) * f)
        })
        .collect()
}

/// The teeth the last pass leaves, on the right of the axis: a groove of the cutter's angle at the
/// root, one pitch apart, over the thread's length.
fn teeth(s: &mut String, t: &MilledThread, tool_angle: f64, map: &Map) {
    let Some(last) = t.helices.last() else { return };
    let Some((side, _)) = t.side else { return };
    let root = t.root_diameter.map_or(last.radius, |d| d / 2.0);
    let half = (tool_angle.to_radians() / 2.0).tan();
    // The groove is open half a pitch wide at the pitch line: from the root a depth of
    // (P/2)/(2·tan(angle/2)) each way, drawn to a full-width V of depth P/(2·tan(angle/2)).
    let depth = t.pitch / (2.0 * half);
    let out = match side {
        Side::Internal => -1.0,
        Side::External => 1.0,
    };
    let (lo, hi) = (t.to.min(t.from), t.to.max(t.from));
    let n = ((hi - lo) / t.pitch).ceil() as usize;
    let mut pts = Vec::with_capacity(2 * n + 2);
    for k in 0..=n.min(20_000) {
        let z = lo + t.pitch * k as f64;
        pts.push((t.axis[0] + root, z));
        pts.push((t.axis[0] + root + out * depth, z + t.pitch / 2.0));
    }
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#222" stroke-width="1.2"/>"##,
        points(map, &pts)
    );
}

fn frame(s: &mut String, x0: f64, y0: f64, title: &str) {
    let _ = writeln!(
        s,
        r##"<rect x="{x0:.2}" y="{y0:.2}" width="{PANEL:.0}" height="{PANEL:.0}" fill="none" stroke="#ccc"/><text x="{:.2}" y="{:.2}" fill="#555">{}</text>"##,
        x0 + 6.0,
        y0 + 16.0,
        text(title)
    );
}

fn frame_wide(s: &mut String, x0: f64, y0: f64, title: &str) {
    let w = WIDTH - x0 - 20.0;
    let _ = writeln!(
        s,
        r##"<rect x="{x0:.2}" y="{y0:.2}" width="{w:.0}" height="{PANEL:.0}" fill="none" stroke="#ccc"/><text x="{:.2}" y="{:.2}" fill="#555">{}</text>"##,
        x0 + 6.0,
        y0 + 16.0,
        text(title)
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mill::motion::Comp;
    use crate::mill::recognise::testing::{helix, line};
    use crate::mill::recognise::{threads, Options};

    #[test]
    fn draws_each_helix_its_entry_and_the_teeth() {
        let g41 = Comp::Left { d: None };
        let mut moves = vec![line([0.0, 0.0, -10.0], [10.0, 0.0, -10.0], g41)];
        moves.extend(helix([0.0, 0.0], 10.0, -10.0, 2.5, 4, false, g41));
        let t = threads(&moves, Options::default());
        let svg = svg(&t, 60.0);
        assert!(
            svg.contains("line 10: lead 2.5, 1 start(s), 1 passes about (0, 0)"),
            "{svg}"
        );
        // One circle, one entry, one helix from the side, one row of teeth.
        assert_eq!(svg.matches("<polyline").count(), 4);
        // The teeth: 10 / 2.5 = 4 pitches, 5 crests and 5 roots.
        let teeth = svg.lines().find(|l| l.contains("#222")).unwrap();
        assert_eq!(teeth.matches(',').count(), 10);
        assert!(svg.contains("Z0 to Z-10"));
        assert!(super::svg(&[], 60.0).contains("no milled thread"));
    }
}
