//! The part as the program makes it, drawn (issue 23, "See it"): the stock's outline dashed, the
//! part's final outline filled (the surfaces the program cut drawn dark), each thread's teeth as
//! a zigzag between its crest and its root, and every rapid move that runs into material as a
//! red line (orange where it rests on an assumed stock) with a marker where it enters and its
//! line number. The picture reads a [`PartPicture`], made by the caller from what `check` found
//! (`commands`): this module computes nothing about the part.
//!
//! Bounded for big programs: at most [`MAX_HITS_DRAWN`] rapids and [`MAX_OUTLINE_POINTS`]
//! outline vertices are drawn, and the picture says what it left out.

use std::fmt::Write;

use crate::part::{CutKind, Known, Origin, Stock};
use crate::units::{Pos, Units};

use super::draw::{num, text, Map};

/// Rapids into material drawn at most (the first ones, in program order).
pub const MAX_HITS_DRAWN: usize = 100;
/// Outline vertices drawn at most (rings after the one that would pass it are left out).
pub const MAX_OUTLINE_POINTS: usize = 50_000;

/// The panel: x, width, height; its row is [`PART_ROW`] tall.
const X0: f64 = 20.0;
const W: f64 = 1060.0;
const H: f64 = 400.0;
/// The part's row, title included.
pub const PART_ROW: f64 = 460.0;
/// One axis's scale is at most this many times the other's (a long slender part stays legible).
const MAX_STRETCH: f64 = 4.0;
/// Teeth drawn along a thread: one zigzag every this many pixels.
const TOOTH_PX: f64 = 6.0;

/// A thread's teeth region (mm, X a radius): crest and root, each from the face to the end.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TeethBand {
    pub line: u32,
    pub crest: (Pos, Pos),
    pub root: (Pos, Pos),
}

/// A rapid move that runs into material (mm, X a radius), entering it at `at`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    pub line: u32,
    pub from: Pos,
    pub to: Pos,
    pub at: Pos,
    /// A fact (an error), else it rests on an assumed stock (a warning).
    pub error: bool,
}

/// What the part picture shows.
#[derive(Clone, Debug, PartialEq)]
pub struct PartPicture {
    pub stock: Option<Stock>,
    /// The outline's rings, each vertex with the origin of the edge leaving it.
    pub outline: Vec<Vec<(Pos, Origin)>>,
    pub teeth: Vec<TeethBand>,
    pub hits: Vec<Hit>,
    /// Whether `hits` is all there were (false: the check kept only the first ones).
    pub hits_complete: bool,
    /// The units of the labels.
    pub units: Units,
}

impl PartPicture {
    /// Whether the program cut anything from the part (a feed or arc move, a turning cycle).
    pub fn cut_anything(&self) -> bool {
        self.outline.iter().flatten().any(|(_, o)| is_cut(o))
    }

    /// Whether a stock was given or assumed (its diameter known).
    pub fn stock_known(&self) -> bool {
        self.stock
            .is_some_and(|s| s.diameter.known != Known::Unknown)
    }

    /// Whether the picture has something to show: a cut, a stock or a rapid into material.
    pub fn worth_drawing(&self) -> bool {
        self.cut_anything() || self.stock_known() || !self.hits.is_empty()
    }
}

fn is_cut(o: &Origin) -> bool {
    matches!(o, Origin::Cut(c) if c.kind != CutKind::Thread)
}

/// The part picture alone (`plot --part`).
pub fn svg(p: &PartPicture) -> String {
    let mut body = String::new();
    panel(&mut body, p, 0.0);
    let height = PART_ROW + 10.0;
    let mut s = String::with_capacity(body.len() + 512);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="1100" height="{height:.0}" viewBox="0 0 1100 {height:.0}" font-family="DejaVu Sans, sans-serif" font-size="12">"#
    );
    let _ = writeln!(
        s,
        r#"<rect x="0" y="0" width="1100" height="{height:.0}" fill="white"/>"#
    );
    s.push_str(&body);
    s.push_str("</svg>\n");
    s
}

/// The extent the panel shows (mm): what the program cut, the threads, the rapids that hit, and
/// the stock's dimensions that are known; everything, when none of those is there.
fn extent(p: &PartPicture) -> (f64, f64, f64, f64) {
    // A cut's end on a boundary of the stock that is not known (a bar of a size not given) says
    // nothing of the part: that boundary is only where the model stops.
    let unknown_edge = |a: Pos| {
        p.stock.is_some_and(|s| {
            let near = |u: f64, v: f64| (u - v).abs() < 1e-6;
            (s.diameter.known == Known::Unknown && near(a.x, s.diameter.value / 2.0))
                || (s.length.known == Known::Unknown && near(a.z, s.face.value - s.length.value))
        })
    };
    let mut pts: Vec<Pos> = Vec::new();
    for ring in &p.outline {
        for (i, (a, o)) in ring.iter().enumerate() {
            if is_cut(o) {
                let b = ring[(i + 1) % ring.len()].0;
                pts.extend([*a, b].into_iter().filter(|q| !unknown_edge(*q)));
            }
        }
    }
    for t in &p.teeth {
        pts.extend([t.crest.0, t.crest.1, t.root.0, t.root.1]);
    }
    for h in p.hits.iter().take(MAX_HITS_DRAWN) {
        pts.extend([h.from, h.to]);
    }
    if let Some(s) = p.stock {
        let known = |d: crate::part::Dim| d.known != Known::Unknown;
        let z = if known(s.face) {
            Some(s.face.value)
        } else {
            None
        };
        if known(s.diameter) {
            let r = s.diameter.value / 2.0;
            pts.push(Pos::new(r, z.unwrap_or(0.0)));
            pts.push(Pos::new(0.0, z.unwrap_or(0.0)));
        }
        if let (Some(z), true) = (z, known(s.length)) {
            pts.push(Pos::new(0.0, z - s.length.value));
        }
    }
    if pts.is_empty() {
        pts.extend(p.outline.iter().flatten().map(|(a, _)| *a));
    }
    if pts.is_empty() {
        return (-1.0, 1.0, 0.0, 1.0);
    }
    let (mut z_lo, mut z_hi, mut x_lo, mut x_hi) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for a in pts {
        z_lo = z_lo.min(a.z);
        z_hi = z_hi.max(a.z);
        x_lo = x_lo.min(a.x);
        x_hi = x_hi.max(a.x);
    }
    // The axis is in view: a part is read from its centre line.
    (z_lo, z_hi, x_lo.min(0.0), x_hi)
}

/// The map from model (Z, X) to the page for a panel whose top is at `y`, with the pixels per mm
/// along Z and X.
fn frame(p: &PartPicture, y: f64) -> (Map, f64, f64) {
    let (z_lo, z_hi, x_lo, x_hi) = extent(p);
    let (dz, dx) = ((z_hi - z_lo).max(1e-3), (x_hi - x_lo).max(1e-3));
    let (z_lo, z_hi) = (z_lo - 0.05 * dz, z_hi + 0.05 * dz);
    let (x_lo, x_hi) = (x_lo - 0.08 * dx, x_hi + 0.12 * dx);
    let inner_w = W - 20.0;
    let inner_h = H - 70.0;
    let (mut sz, mut sx) = (inner_w / (z_hi - z_lo), inner_h / (x_hi - x_lo));
    // True scale where the part's proportions allow, else each axis stretched at most
    // MAX_STRETCH times the other.
    sz = sz.min(sx * MAX_STRETCH);
    sx = sx.min(sz * MAX_STRETCH);
    let (used_w, used_h) = (sz * (z_hi - z_lo), sx * (x_hi - x_lo));
    let ox = X0 + 10.0 + (inner_w - used_w) / 2.0 - sz * z_lo;
    let oy = y + 24.0 + (inner_h + used_h) / 2.0 + sx * x_lo;
    (
        Map {
            ox,
            sx: sz,
            oy,
            sy: -sx,
        },
        sz,
        sx,
    )
}

/// The part panel, its title at `y`.
pub fn panel(s: &mut String, p: &PartPicture, y: f64) {
    let _ = writeln!(
        s,
        r#"<text x="{X0:.0}" y="{:.2}" font-size="15" font-weight="bold">The part as the program makes it</text>"#,
        y + 24.0
    );
    let top = y + 40.0;
    let (map, sz, sx) = frame(p, top);
    let _ = writeln!(
        s,
        r##"<rect x="{X0:.2}" y="{top:.2}" width="{W:.2}" height="{H:.2}" fill="none" stroke="#999"/>"##
    );
    let _ = writeln!(
        s,
        r#"<clipPath id="part-panel"><rect x="{X0:.2}" y="{top:.2}" width="{W:.2}" height="{H:.2}"/></clipPath>"#
    );
    s.push_str("<g clip-path=\"url(#part-panel)\">\n");
    let left_out = outline(s, p, &map);
    stock(s, p, &map);
    axis(s, &map);
    for t in &p.teeth {
        teeth(s, t, &map);
    }
    let drawn = hits(s, p, &map);
    s.push_str("</g>\n");
    captions(s, p, (sz, sx), top, (left_out, drawn));
}

/// The stock's outline, dashed, where its diameter is given or assumed.
fn stock(s: &mut String, p: &PartPicture, map: &Map) {
    let Some(st) = p.stock.filter(|_| p.stock_known()) else {
        return;
    };
    let (r, b) = (st.diameter.value / 2.0, st.bore.value / 2.0);
    let (z0, z1) = (st.face.value, st.face.value - st.length.value);
    let pts = [(z0, b), (z0, r), (z1, r), (z1, b)];
    let _ = writeln!(
        s,
        r##"<polygon points="{}" fill="none" stroke="#777" stroke-width="1" stroke-dasharray="6 4"/>"##,
        super::draw::points(map, &pts)
    );
}

/// The centre line.
fn axis(s: &mut String, map: &Map) {
    let (_, y) = map.at(0.0, 0.0);
    let _ = writeln!(
        s,
        r##"<line x1="{X0:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="#444" stroke-width="0.6" stroke-dasharray="12 3 2 3"/>"##,
        X0 + W
    );
}

/// The part's outline, filled, and the surfaces the program cut drawn dark; with the rings left
/// out (beyond [`MAX_OUTLINE_POINTS`]).
fn outline(s: &mut String, p: &PartPicture, map: &Map) -> usize {
    let mut fill = String::new();
    let mut cuts = String::new();
    let mut points = 0;
    let mut left_out = 0;
    for ring in &p.outline {
        if ring.len() < 2 {
            continue;
        }
        if points + ring.len() > MAX_OUTLINE_POINTS {
            left_out += 1;
            continue;
        }
        points += ring.len();
        for (i, (a, o)) in ring.iter().enumerate() {
            let (x, y) = map.at(a.z, a.x);
            let _ = write!(fill, "{}{x:.2},{y:.2}", if i == 0 { "M" } else { "L" });
            if is_cut(o) {
                let b = ring[(i + 1) % ring.len()].0;
                let (x2, y2) = map.at(b.z, b.x);
                let _ = write!(cuts, "M{x:.2},{y:.2}L{x2:.2},{y2:.2}");
            }
        }
        fill.push('Z');
    }
    if !fill.is_empty() {
        let _ = writeln!(
            s,
            r##"<path d="{fill}" fill="#c9d6e3" fill-rule="evenodd" stroke="#8aa" stroke-width="0.6"/>"##
        );
    }
    if !cuts.is_empty() {
        let _ = writeln!(
            s,
            r##"<path d="{cuts}" fill="none" stroke="#1f3f66" stroke-width="1.4"/>"##
        );
    }
    left_out
}

/// A thread's teeth: a zigzag between its crest and its root, one tooth every [`TOOTH_PX`].
fn teeth(s: &mut String, t: &TeethBand, map: &Map) {
    let (c0, c1) = (
        map.at(t.crest.0.z, t.crest.0.x),
        map.at(t.crest.1.z, t.crest.1.x),
    );
    let len = (c1.0 - c0.0).hypot(c1.1 - c0.1);
    let n = ((len / TOOTH_PX).round() as usize).clamp(2, 400);
    let lerp = |a: Pos, b: Pos, k: f64| Pos::new(a.x + (b.x - a.x) * k, a.z + (b.z - a.z) * k);
    let mut pts = Vec::with_capacity(n + 1);
    for i in 0..=n {
        let k = i as f64 / n as f64;
        let on = if i % 2 == 0 { t.crest } else { t.root };
        let a = lerp(on.0, on.1, k);
        pts.push((a.z, a.x));
    }
    let _ = writeln!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#222" stroke-width="0.9"/>"##,
        super::draw::points(map, &pts)
    );
    // Above the crest's middle (below it for an internal thread's, whose material is outside).
    let mid = lerp(t.crest.0, t.crest.1, 0.5);
    let (x, y) = map.at(mid.z, mid.x);
    let dy = if t.root.0.x > t.crest.0.x { 12.0 } else { -4.0 };
    let _ = writeln!(
        s,
        r##"<text x="{x:.2}" y="{:.2}" font-size="10" fill="#222" text-anchor="middle">thread, line {}</text>"##,
        y + dy,
        t.line
    );
}

/// The rapids into material: a red line (orange on an assumed stock), a marker where it enters,
/// its line number. The first [`MAX_HITS_DRAWN`]; how many were drawn.
fn hits(s: &mut String, p: &PartPicture, map: &Map) -> usize {
    let drawn = p.hits.len().min(MAX_HITS_DRAWN);
    for h in &p.hits[..drawn] {
        let colour = if h.error { "#d00" } else { "#e08000" };
        let (a, b, e) = (
            map.at(h.from.z, h.from.x),
            map.at(h.to.z, h.to.x),
            map.at(h.at.z, h.at.x),
        );
        let _ = writeln!(
            s,
            r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{colour}" stroke-width="1.6" class="rapid-hit"/>"#,
            a.0, a.1, b.0, b.1
        );
        let _ = writeln!(
            s,
            r#"<circle cx="{:.2}" cy="{:.2}" r="4" fill="none" stroke="{colour}" stroke-width="1.6"/>"#,
            e.0, e.1
        );
        let _ = writeln!(
            s,
            r#"<text x="{:.2}" y="{:.2}" font-size="11" font-weight="bold" fill="{colour}">line {}</text>"#,
            e.0 + 6.0,
            e.1 - 6.0,
            h.line
        );
    }
    drawn
}

/// The caption (what each mark means, both scales) and what was left out.
fn captions(s: &mut String, p: &PartPicture, (sz, sx): (f64, f64), top: f64, left: (usize, usize)) {
    let u = p.units;
    let stock = match p.stock {
        Some(st) if st.diameter.known == Known::Given => {
            format!(
                "dashed: the stock Ø{} as given",
                num(u.from_mm(st.diameter.value), 4)
            )
        }
        Some(st) if st.diameter.known == Known::Assumed => {
            format!(
                "dashed: the stock Ø{} as assumed",
                num(u.from_mm(st.diameter.value), 4)
            )
        }
        _ => "the stock's size is not given (--stock-diameter)".to_string(),
    };
    let captions = [
        format!(
            "{stock}; filled: the part, dark where the program cut it; zigzag: a thread's teeth (crest to root)"
        ),
        format!(
            "red: a rapid move into material, circled where it enters (orange: into stock only assumed); Z → {:.2} px/{}, X radius ↑ {:.2} px/{}",
            sz * u.scale(),
            u.name(),
            sx * u.scale(),
            u.name()
        ),
    ];
    for (i, c) in captions.iter().enumerate() {
        let _ = writeln!(
            s,
            r#"<text x="{:.2}" y="{:.2}" font-size="11">{}</text>"#,
            X0 + 6.0,
            top + H - 22.0 + 14.0 * i as f64,
            text(c)
        );
    }
    let (rings, drawn) = left;
    let mut notes = Vec::new();
    if drawn < p.hits.len() || !p.hits_complete {
        let total = if p.hits_complete {
            p.hits.len().to_string()
        } else {
            format!("more than {}", p.hits.len())
        };
        notes.push(format!(
            "the first {drawn} of {total} rapids into material drawn"
        ));
    }
    if rings > 0 {
        notes.push(format!(
            "{rings} of the outline's rings left out (more than {MAX_OUTLINE_POINTS} points)"
        ));
    }
    let status = match (p.hits.len(), p.hits_complete) {
        (0, _) => "no rapid move runs into material".to_string(),
        (n, true) => crate::text::count(
            n,
            "rapid move runs into material",
            "rapid moves run into material",
        ),
        (n, false) => format!("more than {n} rapid moves run into material"),
    };
    notes.insert(0, status);
    let _ = writeln!(
        s,
        r##"<text x="{:.2}" y="{:.2}" font-size="12" fill="{}" text-anchor="end">{}</text>"##,
        X0 + W,
        top - 16.0,
        if p.hits.is_empty() { "#222" } else { "#b00" },
        text(&notes.join("; "))
    );
}
