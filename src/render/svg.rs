//! One deterministic SVG per program: for each cycle, the pass diagram (the groove's section with
//! each pass's chip filled in its colour, its tool outline, its area) and the XZ toolpath (rapid
//! moves dashed, feeds solid, thread moves bold, pass numbers).
//!
//! The text is written by hand with fixed decimals, so the same program always gives the same
//! bytes (snapshot tests rely on it).

use std::fmt::Write;

pub use super::draw::left_out;
use super::draw::{num, points, text, Map};
use crate::sim::{Section, Tool};
use crate::thread::{Job, Pass};
use crate::toolpath::{MotionKind, Toolpath};
use crate::units::Pos;

/// What one cycle's picture is made of.
pub struct CyclePlot<'a> {
    pub job: &'a Job,
    pub passes: &'a [Pass],
    pub section: &'a Section,
    pub path: &'a Toolpath,
    /// The program writes X as a diameter (for the axis caption).
    pub diameter_x: bool,
    /// What the thread is, for the title: `fanuc cycle`, `5 single-pass cycles as one thread …`.
    pub what: String,
}

const WIDTH: f64 = 1100.0;
const ROW: f64 = 470.0;
const TOP: f64 = 40.0;
/// The section panel, the legend, the toolpath panel: x, width; all panels are PANEL_H tall.
const SECTION_X: f64 = 20.0;
const SECTION_W: f64 = 420.0;
const LEGEND_X: f64 = 455.0;
const PATH_X: f64 = 650.0;
const PATH_W: f64 = 430.0;
const PANEL_H: f64 = 380.0;
/// Legend rows that fit beside the section panel.
const LEGEND_ROWS: usize = 25;
/// Pass labels closer than this (px) to the last one drawn are left out.
const LABEL_GAP: f64 = 11.0;

/// Twenty distinct colours ("tab10", then its lighter companions), cycled by pass number.
const PALETTE: [&str; 20] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf", "#6baed6", "#fdae6b", "#74c476", "#fc9272", "#bcbddc", "#c49c94",
    "#f7b6d2", "#bdbdbd", "#dbdb8d", "#9edae5",
];

fn colour(pass: u32) -> &'static str {
    PALETTE[(pass.max(1) as usize - 1) % PALETTE.len()]
}

/// A picture larger than this (bytes) gets no further thread: the threads after the one that
/// would pass it are left out, and the picture says so. One thread alone stays well below it: see
/// [`MAX_PATH_PASSES`].
pub const MAX_SVG_BYTES: usize = 4_000_000;

/// A thread with more passes than this has the toolpath and the tool outline of one pass in `k`
/// drawn (its finishing passes always), so that one thread's picture stays under about 2 MB even
/// at the planner's 10,000 passes; every chip is still filled in.
pub const MAX_PATH_PASSES: usize = 400;

/// The whole picture.
pub fn svg(cycles: &[CyclePlot]) -> String {
    let numbers: Vec<usize> = (1..=cycles.len()).collect();
    picture(cycles, &numbers, cycles.len()).0
}

/// The picture of `cycles`, which are the threads numbered `numbers` (1-based, in program order)
/// of the `total` the program has; with how many of `cycles` were drawn (all, unless the picture
/// reached [`MAX_SVG_BYTES`]). Threads left out are stated at the bottom of the picture.
pub fn picture(cycles: &[CyclePlot], numbers: &[usize], total: usize) -> (String, usize) {
    picture_with(cycles, numbers, total, None)
}

/// [`picture`] with the part the program makes drawn above the threads
/// ([`super::part::panel`]).
pub fn picture_with(
    cycles: &[CyclePlot],
    numbers: &[usize],
    total: usize,
    part: Option<&super::part::PartPicture>,
) -> (String, usize) {
    let mut body = String::new();
    let top = match part {
        Some(p) => {
            super::part::panel(&mut body, p, 0.0);
            super::part::PART_ROW
        }
        None => 0.0,
    };
    let mut drawn = 0;
    for (i, c) in cycles.iter().enumerate() {
        let mut one = String::with_capacity(16_384);
        cycle(&mut one, c, top + ROW * i as f64);
        if (drawn > 0 || part.is_some()) && body.len() + one.len() > MAX_SVG_BYTES {
            break;
        }
        body.push_str(&one);
        drawn += 1;
    }
    let note = (drawn < total).then(|| left_out(&numbers[..drawn], total));
    let rows = if part.is_some() {
        drawn as f64
    } else {
        drawn.max(1) as f64
    };
    let height = top + ROW * rows + 10.0 + if note.is_some() { 30.0 } else { 0.0 };
    let mut s = String::with_capacity(body.len() + 1024);
    // Writing into a String cannot fail.
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH:.0}" height="{height:.0}" viewBox="0 0 {WIDTH:.0} {height:.0}" font-family="DejaVu Sans, sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="{WIDTH:.0}" height="{height:.0}" fill="white"/>"#
    );
    if total == 0 && part.is_none() {
        let _ = writeln!(
            s,
            r#"<text x="20" y="40" font-size="16">no thread in this program</text>"#
        );
    }
    s.push_str(&body);
    if let Some(note) = note {
        let _ = writeln!(
            s,
            r##"<text x="20" y="{:.2}" font-size="15" fill="#b00">{}</text>"##,
            top + ROW * rows + 20.0,
            text(&note)
        );
    }
    s.push_str("</svg>\n");
    (s, drawn)
}

/// One pass in this many has its toolpath and tool outline drawn ([`MAX_PATH_PASSES`]).
fn stride(c: &CyclePlot) -> usize {
    stride_of(c.passes)
}

fn stride_of(passes: &[crate::thread::Pass]) -> usize {
    passes.len().div_ceil(MAX_PATH_PASSES).max(1)
}

/// Whether pass `n` (0: moves outside any pass) has its toolpath and tool outline drawn: every
/// pass of a thread of at most [`MAX_PATH_PASSES`]; of a longer one, one pass in
/// [`stride`] and every finishing pass but one that repeats a finishing pass before it in place
/// (a spring pass, drawn exactly over it: a cycle run again thousands of times at full depth).
/// The first finishing pass is drawn even where it repeats the last rough pass, which may not be.
fn shown(c: &CyclePlot, n: u32) -> bool {
    shown_of(c.passes, n)
}

fn shown_of(passes: &[crate::thread::Pass], n: u32) -> bool {
    let k = stride_of(passes);
    if k == 1 || n == 0 || (n as usize - 1).is_multiple_of(k) {
        return true;
    }
    let i = n as usize - 1;
    match passes.get(i) {
        None => true,
        Some(p) if p.kind == crate::thread::PassKind::Finish => {
            let before = i.checked_sub(1).and_then(|j| passes.get(j));
            !before.is_some_and(|b| {
                b.kind == crate::thread::PassKind::Finish
                    && b.depth == p.depth
                    && b.offset == p.offset
                    && b.start == p.start
            })
        }
        Some(_) => false,
    }
}

fn cycle(s: &mut String, c: &CyclePlot, y0: f64) {
    let job = c.job;
    let u = job.units;
    let sec = c.section;
    let rough = c
        .passes
        .iter()
        .filter(|p| p.kind == crate::thread::PassKind::Rough)
        .count();
    let title = format!(
        "line {}: {}, {}, lead {} {}, depth {} {}",
        job.line,
        c.what,
        crate::text::rough_and_finishing(rough, c.passes.len() - rough),
        num(u.from_mm(job.lead.lead), 4),
        u.name(),
        num(u.from_mm(job.geometry.depth), 4),
        u.name()
    ) + &match stride(c) {
        1 => String::new(),
        k => format!("; toolpath and tool of 1 pass in {k} drawn"),
    };
    let _ = writeln!(
        s,
        r#"<text x="{SECTION_X:.0}" y="{:.2}" font-size="15" font-weight="bold">{}</text>"#,
        y0 + 24.0,
        text(&title)
    );
    section_panel(s, c, y0 + TOP);
    legend(s, sec, y0 + TOP, u);
    path_panel(s, c, y0 + TOP);
}

fn section_panel(s: &mut String, c: &CyclePlot, y: f64) {
    let sec = c.section;
    let tool: &Tool = &sec.tool;
    let form = tool.form();
    let top = -sec.stock_above.max(0.0);
    let deepest = sec
        .passes
        .iter()
        .map(|p| p.depth)
        .fold(c.job.geometry.depth, f64::max);
    // Horizontal extent: every tool outline where it crosses the top of the blank.
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &sec.passes {
        if let Some((l, r)) = form.span_at(p.offset, p.depth, top) {
            lo = lo.min(l);
            hi = hi.max(r);
        }
    }
    if !lo.is_finite() {
        (lo, hi) = (-1.0, 1.0);
    }
    let margin_v = 0.08 * (deepest - top).max(1e-3);
    let (v_lo, v_hi) = (top - margin_v, deepest + margin_v);
    let margin_u = 0.05 * (hi - lo).max(1e-3);
    let (lo, hi) = (lo - margin_u, hi + margin_u);
    let inner_h = PANEL_H - 40.0;
    let scale = (SECTION_W / (hi - lo)).min(inner_h / (v_hi - v_lo));
    // Centre the drawing in the panel.
    let ox = SECTION_X + (SECTION_W - scale * (hi - lo)) / 2.0 - scale * lo;
    let oy = y + 20.0 + (inner_h - scale * (v_hi - v_lo)) / 2.0 - scale * v_lo;
    let map = Map {
        ox,
        sx: scale,
        oy,
        sy: scale,
    };
    let _ = writeln!(
        s,
        r##"<rect x="{SECTION_X:.2}" y="{y:.2}" width="{SECTION_W:.2}" height="{PANEL_H:.2}" fill="none" stroke="#999"/>"##
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" font-weight="bold">Pass diagram: axial section of the groove (true scale)</text>"#,
        SECTION_X + 6.0,
        y + 15.0
    );
    // The blank: from its surface down past the deepest pass.
    let blank = [(lo, top), (hi, top), (hi, v_hi), (lo, v_hi)];
    let _ = writeln!(
        s,
        r##"<polygon points="{}" fill="#e6e6e6" stroke="none"/>"##,
        points(&map, &blank)
    );
    // Each pass's chip, filled in its colour.
    for p in &sec.passes {
        for contour in &p.chip {
            let _ = writeln!(
                s,
                r#"<polygon points="{}" fill="{}" fill-opacity="0.55" stroke="none"/>"#,
                points(&map, contour),
                colour(p.n)
            );
        }
    }
    // The crest line.
    let (x1, yc) = map.at(lo, 0.0);
    let (x2, _) = map.at(hi, 0.0);
    let _ = writeln!(
        s,
        r##"<line x1="{x1:.2}" y1="{yc:.2}" x2="{x2:.2}" y2="{yc:.2}" stroke="#555" stroke-dasharray="2 3"/>"##
    );
    // Each pass's tool outline (flanks and tip, below the blank's top).
    for p in sec.passes.iter().filter(|p| shown(c, p.n)) {
        let outline = tool.outline(p.offset, p.depth, top);
        let _ = writeln!(
            s,
            r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="1"/>"#,
            points(&map, &outline),
            colour(p.n)
        );
    }
    // The target form, dashed, where the groove was judged.
    let target = tool.outline(sec.groove.form.centre, sec.groove.form.depth_target, top);
    let _ = writeln!(
        s,
        r#"<polyline points="{}" fill="none" stroke="black" stroke-width="1.2" stroke-dasharray="5 3"/>"#,
        points(&map, &target)
    );
    // Pass numbers at the tips, skipping ones that would overlap.
    let mut last: Option<(f64, f64)> = None;
    for p in sec.passes.iter().filter(|p| shown(c, p.n)) {
        let (x, yy) = map.at(p.offset, p.depth);
        if last.is_some_and(|(lx, ly)| (lx - x).hypot(ly - yy) < LABEL_GAP) {
            continue;
        }
        last = Some((x, yy));
        // Dark, not the pass colour: the label sits on the pass's own chip.
        let _ = writeln!(
            s,
            r##"<text x="{:.2}" y="{:.2}" font-size="10" fill="#222">{}</text>"##,
            x + 4.0,
            yy + 3.0,
            p.n
        );
    }
    let g = &sec.groove;
    let u = c.job.units;
    let caption = format!(
        "dashed: target form; depth {}, flanks {:.2}°/{:.2}°, ridge {} {}",
        num(u.from_mm(g.form.depth_reached), 5),
        g.form.flank_angle_left_deg,
        g.form.flank_angle_right_deg,
        num(u.from_mm(g.form.ridge), 5),
        u.name()
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" font-size="11">{}</text>"#,
        SECTION_X + 6.0,
        y + PANEL_H - 8.0,
        text(&caption)
    );
}

/// Legend columns: x offsets from LEGEND_X and their anchors.
const COLUMNS: [(f64, &str); 4] = [
    (32.0, "end"),
    (95.0, "end"),
    (142.0, "end"),
    (150.0, "start"),
];

fn legend_row(s: &mut String, y: f64, cells: [&str; 4], extra: &str) {
    for ((dx, anchor), cell) in COLUMNS.iter().zip(cells) {
        let _ = writeln!(
            s,
            r#"<text x="{:.2}" y="{y:.2}" text-anchor="{anchor}"{extra}>{}</text>"#,
            LEGEND_X + dx,
            text(cell)
        );
    }
}

fn legend(s: &mut String, sec: &Section, y: f64, units: crate::units::Units) {
    let area_unit = match units {
        crate::units::Units::Mm => "mm²",
        crate::units::Units::Inch => "in²",
    };
    legend_row(
        s,
        y + 15.0,
        ["pass", area_unit, "share", "flank"],
        r#" font-weight="bold" font-size="11""#,
    );
    let k = units.scale() * units.scale();
    // Square inches are 645 times smaller numbers than square millimetres.
    let area_decimals = match units {
        crate::units::Units::Mm => 5,
        crate::units::Units::Inch => 7,
    };
    for (i, p) in sec.passes.iter().take(LEGEND_ROWS).enumerate() {
        let yy = y + 32.0 + 13.5 * i as f64;
        let _ = writeln!(
            s,
            r#"<rect x="{LEGEND_X:.2}" y="{:.2}" width="10" height="10" fill="{}"/>"#,
            yy - 9.0,
            colour(p.n)
        );
        legend_row(
            s,
            yy,
            [
                &p.n.to_string(),
                &format!("{:.*}", area_decimals, p.area / k),
                &format!("{:.1}%", p.share * 100.0),
                p.flank.name(),
            ],
            r#" font-size="11""#,
        );
    }
    if sec.passes.len() > LEGEND_ROWS {
        let _ = writeln!(
            s,
            r#"<text x="{:.2}" y="{:.2}" font-size="11">… {} more</text>"#,
            LEGEND_X + 14.0,
            y + 32.0 + 13.5 * LEGEND_ROWS as f64,
            crate::text::count(sec.passes.len() - LEGEND_ROWS, "pass", "passes")
        );
    }
}

/// The toolpath panel's scale: the map from model (Z, X) to the page, the pixels per mm along
/// each axis, and the padded extent of the model the panel shows.
struct PathFrame {
    map: Map,
    /// Pixels per mm along Z (page x) and along X (page y, upward).
    sz: f64,
    sx: f64,
    z_lo: f64,
    x_lo: f64,
    x_hi: f64,
}

impl PathFrame {
    /// Where a model point lands on the page.
    fn at(&self, p: Pos) -> (f64, f64) {
        self.map.at(p.z, p.x)
    }
}

/// Decides the toolpath panel's scale for a panel whose top is at `y`: the extent of every move,
/// the start point and the thread's crest ends, padded, with each axis filling the panel.
fn path_frame(c: &CyclePlot, y: f64) -> PathFrame {
    let path = c.path;
    let mut pts: Vec<Pos> = vec![path.start];
    pts.extend(path.motions.iter().map(|m| m.to));
    let g = &c.job.geometry;
    pts.push(g.crest_start);
    pts.push(g.crest_end);
    let (mut z_lo, mut z_hi, mut x_lo, mut x_hi) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in &pts {
        z_lo = z_lo.min(p.z);
        z_hi = z_hi.max(p.z);
        x_lo = x_lo.min(p.x);
        x_hi = x_hi.max(p.x);
    }
    let (dz, dx) = ((z_hi - z_lo).max(1e-3), (x_hi - x_lo).max(1e-3));
    let (z_lo, z_hi) = (z_lo - 0.06 * dz, z_hi + 0.06 * dz);
    let (x_lo, x_hi) = (x_lo - 0.1 * dx, x_hi + 0.1 * dx);
    let inner_h = PANEL_H - 50.0;
    // Z to the right, X up; each axis fills the panel (the caption states both scales).
    let sz = PATH_W / (z_hi - z_lo);
    let sx = inner_h / (x_hi - x_lo);
    let map = Map {
        ox: PATH_X - sz * z_lo,
        sx: sz,
        oy: y + 22.0 + inner_h + sx * x_lo,
        sy: -sx,
    };
    PathFrame {
        map,
        sz,
        sx,
        z_lo,
        x_lo,
        x_hi,
    }
}

/// Decides the outline of the blank in the toolpath panel: below (external) or above (internal)
/// the crest line over the thread's length, reaching the panel's edge `x_lo` or `x_hi`; for a
/// face thread, behind the face over the thread's radial extent, one thread depth deep.
fn path_blank(g: &crate::thread::Geometry, x_lo: f64, x_hi: f64) -> [(f64, f64); 4] {
    match g.side {
        crate::thread::Side::External | crate::thread::Side::Internal => {
            let far = if g.side == crate::thread::Side::External {
                x_lo
            } else {
                x_hi
            };
            [
                (g.crest_start.z, g.crest_start.x),
                (g.crest_end.z, g.crest_end.x),
                (g.crest_end.z, far),
                (g.crest_start.z, far),
            ]
        }
        crate::thread::Side::FaceFront | crate::thread::Side::FaceBack => {
            let depth = g.side.infeed().z * g.depth;
            [
                (g.crest_start.z, g.crest_start.x),
                (g.crest_end.z, g.crest_end.x),
                (g.crest_end.z + depth, g.crest_end.x),
                (g.crest_start.z + depth, g.crest_start.x),
            ]
        }
    }
}

/// The XZ toolpath panel, its top at `y`: frame, title, blank, moves and captions.
fn path_panel(s: &mut String, c: &CyclePlot, y: f64) {
    let frame = path_frame(c, y);
    let _ = writeln!(
        s,
        r##"<rect x="{PATH_X:.2}" y="{y:.2}" width="{PATH_W:.2}" height="{PANEL_H:.2}" fill="none" stroke="#999"/>"##
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" font-weight="bold">XZ toolpath</text>"#,
        PATH_X + 6.0,
        y + 15.0
    );
    let blank = path_blank(&c.job.geometry, frame.x_lo, frame.x_hi);
    let _ = writeln!(
        s,
        r##"<polygon points="{}" fill="#e6e6e6" stroke="#bbb"/>"##,
        points(&frame.map, &blank)
    );
    path_moves(s, c, &frame);
    path_captions(s, c, &frame, y);
}

/// Draws the drawn passes' moves in their colours (rapids dashed, feeds thin, thread moves bold)
/// and decides which passes get their number: at the start of a pass's first thread move, unless
/// it would sit within [`LABEL_GAP`] of the last number drawn.
fn path_moves(s: &mut String, c: &CyclePlot, frame: &PathFrame) {
    let mut last_label: Option<(f64, f64)> = None;
    let mut labelled_pass = 0;
    for (from, m) in c.path.segments().filter(|(_, m)| shown(c, m.pass)) {
        let (a, b) = (frame.at(from), frame.at(m.to));
        let colour = colour(m.pass);
        let style = match m.kind {
            MotionKind::Rapid => "stroke-width=\"0.8\" stroke-dasharray=\"4 3\"",
            MotionKind::Feed => "stroke-width=\"1\"",
            MotionKind::Thread { .. } => "stroke-width=\"2.4\"",
            MotionKind::Arc { .. } => "stroke-width=\"1\"",
        };
        let _ = writeln!(
            s,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{colour}" {style}/>"#,
            a.0, a.1, b.0, b.1
        );
        // The pass number at the start of each pass's first thread move.
        if matches!(m.kind, MotionKind::Thread { .. }) && m.pass != labelled_pass {
            labelled_pass = m.pass;
            if last_label.is_some_and(|(lx, ly)| (lx - a.0).hypot(ly - a.1) < LABEL_GAP) {
                continue;
            }
            last_label = Some(a);
            let _ = writeln!(
                s,
                r#"<text x="{:.2}" y="{:.2}" font-size="10" fill="{colour}" text-anchor="end">{}</text>"#,
                a.0 - 3.0,
                a.1 + 3.0,
                m.pass
            );
        }
    }
}

/// Draws the start point, the caption with both scales, and the labels that let the picture be
/// read without a grid: the Z of the thread's ends and the start point's radius and Z.
fn path_captions(s: &mut String, c: &CyclePlot, frame: &PathFrame, y: f64) {
    let path = c.path;
    let units = c.job.units;
    let g = &c.job.geometry;
    let (sx0, sy0) = frame.at(path.start);
    let _ = writeln!(
        s,
        r#"<circle cx="{sx0:.2}" cy="{sy0:.2}" r="3" fill="black"/>"#
    );
    let x_name = if c.diameter_x {
        "radius (program: diameter)"
    } else {
        "radius"
    };
    let caption = format!(
        "Z → {:.1} px/{}, X {} ↑ {:.1} px/{}; bold: thread",
        frame.sz * units.scale(),
        units.name(),
        x_name,
        frame.sx * units.scale(),
        units.name()
    );
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" font-size="11">{}</text>"#,
        PATH_X + 6.0,
        y + PANEL_H - 8.0,
        text(&caption)
    );
    // The thread's ends and the start point, so the picture can be read without a grid.
    let lbl = |v: f64| num(units.from_mm(v), 3);
    let (_, bottom) = frame.map.at(frame.z_lo, frame.x_lo);
    for (z, anchor) in [(g.crest_start.z, "middle"), (g.crest_end.z, "middle")] {
        let (x, _) = frame.map.at(z, frame.x_lo);
        let _ = writeln!(
            s,
            r#"<text x="{x:.2}" y="{:.2}" font-size="10" text-anchor="{anchor}">Z{}</text>"#,
            bottom - 3.0,
            lbl(z)
        );
    }
    let _ = writeln!(
        s,
        r#"<text x="{:.2}" y="{:.2}" font-size="10" text-anchor="end">start r{} Z{}</text>"#,
        sx0 - 5.0,
        sy0 - 5.0,
        lbl(path.start.x),
        lbl(path.start.z)
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::thread::{Pass, PassKind};
    use crate::units::Pos;

    fn pass(n: u32, kind: PassKind, depth: f64) -> Pass {
        Pass {
            n,
            kind,
            depth,
            increment: 0.0,
            offset: 0.0,
            start: Pos::new(10.0, 5.0),
            area: 0.0,
            share: 0.0,
        }
    }

    #[test]
    fn a_spring_pass_is_drawn_once_and_full_depth_always() {
        // 624 rough passes, the last at full depth, then a finishing pass in the same place (no
        // finishing allowance) and two spring passes: 627 passes, one in two drawn.
        let mut passes: Vec<Pass> = (1..=624)
            .map(|n| pass(n, PassKind::Rough, f64::from(n) / 624.0))
            .collect();
        for n in 625..=627 {
            passes.push(pass(n, PassKind::Finish, 1.0));
        }
        assert_eq!(stride_of(&passes), 2);
        // The last rough pass falls between the drawn ones; the first finishing pass, at the same
        // place, is drawn; the spring passes over it are not.
        assert!(!shown_of(&passes, 624));
        assert!(shown_of(&passes, 625));
        assert!(!shown_of(&passes, 626));
        // (627 is one of the one in two.)
        assert!(shown_of(&passes, 627));
        // A finishing pass elsewhere is drawn.
        passes[626].depth = 1.01;
        assert!(shown_of(&passes, 627));
        passes[625].depth = 1.02;
        assert!(shown_of(&passes, 626));
    }
}
