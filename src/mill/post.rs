//! Writing a milling plan: G-code in a profile's format, or JSON lines. Every coordinate is
//! rounded once, from its absolute value (TB029 tip 1); I/J are measured from the start point as
//! written, so the control's centre is the true centre to within half a least increment.

use std::io::{self, Write};

use serde_json::json;

use super::profile::MillProfile;
use super::Side;
use super::{CompSide, MoveKind, Plan};
use crate::machine::CommentStyle;
use crate::post::{json_num, number};
use crate::text::count;
use crate::units::Units;

/// Output choices that are not in the profile.
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub units: Units,
    /// The D register for G41/G42 (`None`: no D word).
    pub d_register: Option<u32>,
}

fn comment(profile: &MillProfile, text: &str) -> Option<String> {
    let clean: String = text.chars().filter(|c| !matches!(c, '(' | ')')).collect();
    match profile.comment {
        CommentStyle::Paren => Some(format!("({clean})")),
        CommentStyle::Semicolon => Some(format!("; {clean}")),
        CommentStyle::None => None,
    }
}

/// The header lines describing the plan (without comment markers).
pub fn summary(plan: &Plan, units: Units) -> Vec<String> {
    let u = |mm: f64| units.from_mm(mm);
    let d = if units == Units::Inch { 4 } else { 3 };
    let un = units.name();
    let side = match plan.side {
        Side::Internal => "internal",
        Side::External => "external",
    };
    let dir = match plan.direction {
        super::Direction::TopDown => "top-down",
        super::Direction::BottomUp => "bottom-up",
    };
    let comp = match plan.comp {
        super::Comp::Controller => format!(
            "{} cutter compensation, program on the thread contour",
            plan.comp_side.code()
        ),
        super::Comp::Off => "no compensation, program is the tool-centre path".to_string(),
    };
    let mut lines = vec![
        format!(
            "threadcut mill: {} {side} {}, {}-hand, {dir}, {}, {comp}",
            plan.thread,
            plan.class,
            match plan.hand {
                super::Hand::Right => "right",
                super::Hand::Left => "left",
            },
            if plan.cw { "G2" } else { "G3" }
        ),
        format!(
            "from the {} diameter {:.d$} to the {} diameter {:.d$} {un}, {}, tool diameter {:.d$}, {}",
            if plan.side == Side::Internal { "bore" } else { "stock" },
            2.0 * u(plan.crest_radius),
            if plan.side == Side::Internal { "major" } else { "minor" },
            2.0 * u(plan.final_radius),
            count(plan.pass_radii.len(), "radial pass", "radial passes"),
            2.0 * u(plan.tool_radius),
            count(plan.teeth as usize, "tooth", "teeth")
        ),
        format!(
            "pitch {:.6} {un}, {}, lead {:.6} {un}, {} per pass and start; {} = {:.4}",
            u(plan.pitch),
            count(plan.starts as usize, "start", "starts"),
            u(plan.lead),
            count(plan.turns as usize, "full turn", "full turns"),
            // TB029 step 6 counts turns as length × threads per inch; a metric thread has a pitch.
            if plan.tpi.is_some() {
                "length × threads per inch"
            } else {
                "length / pitch"
            },
            plan.seed_count
        ),
        format!(
            "thread Z {:.d$} to {:.d$}, lowest tool Z {:.d$}, clearance Z {:.d$}",
            u(plan.top_z),
            u(plan.bottom_z),
            u(plan.lowest_z),
            u(plan.clearance_z)
        ),
        format!(
            "feed at the cutting edge {:.2} {un}/min, helix F {:.2} on the last pass",
            u(plan.edge_feed),
            u(plan.helix_feed)
        ),
    ];
    if plan.taper != 0.0 {
        lines.push(format!(
            "taper 1:16 on diameter: the diameters above are at Z {:.d$}; the radius {} {:.6} {un} per {un} going down, {:.6} {un} per turn ({} arcs a turn)",
            u(plan.top_z),
            if plan.taper > 0.0 { "grows" } else { "shrinks" },
            plan.taper.abs(),
            u(plan.taper.abs() * plan.lead),
            super::TAPER_ARCS_PER_TURN
        ));
    }
    lines.push("tool, spindle and work offset are the program's: this block only moves".into());
    lines
}

/// The G-code program.
pub fn write_gcode(
    out: &mut dyn Write,
    plan: &Plan,
    profile: &MillProfile,
    opts: Options,
) -> io::Result<()> {
    let units = opts.units;
    let (nd, fd) = match units {
        Units::Mm => (profile.decimals_mm, profile.feed_decimals_mm),
        Units::Inch => (profile.decimals_inch, profile.feed_decimals_inch),
    };
    let tz = profile.trailing_zeros;
    let num = |mm: f64| number(units.from_mm(mm), nd, tz);
    for line in summary(plan, units) {
        if let Some(c) = comment(profile, &line) {
            writeln!(out, "{c}")?;
        }
    }
    writeln!(out, "{}", if units == Units::Inch { "G20" } else { "G21" })?;
    for p in &profile.preamble {
        writeln!(out, "{p}")?;
    }
    // The position as written (rounded strings and their values).
    let mut at: [Option<String>; 3] = [None, None, None];
    let mut at_v = [0.0f64; 3];
    let mut feed: Option<String> = None;
    let mut comp: Option<CompSide> = None;
    let mut pass = 0;
    let mut line = String::with_capacity(80);
    for m in &plan.moves {
        if m.pass != pass {
            pass = m.pass;
            let r = plan.pass_radii[(pass - 1) as usize];
            if let Some(c) = comment(
                profile,
                &format!(
                    "pass {pass} of {}: thread radius {}",
                    plan.pass_radii.len(),
                    num(r)
                ),
            ) {
                writeln!(out, "{c}")?;
            }
        }
        line.clear();
        match (comp, m.comp) {
            (None, Some(side)) => {
                match opts.d_register {
                    Some(d) => line.push_str(&format!("{} D{d} ", side.code())),
                    None if profile.comp_needs_d => {
                        // G41/G42 without D keeps the offset register in force: say so where the
                        // machinist reads the program.
                        if let Some(c) = comment(
                            profile,
                            "no D word: the tool-radius offset in force is used; set it to the thread mill's radius",
                        ) {
                            writeln!(out, "{c}")?;
                        }
                        line.push_str(side.code());
                        line.push(' ');
                    }
                    None => {
                        line.push_str(side.code());
                        line.push(' ');
                    }
                }
            }
            (Some(_), None) => line.push_str("G40 "),
            _ => {}
        }
        comp = m.comp;
        let words = [num(m.to.x), num(m.to.y), num(m.to.z)];
        let start = at_v;
        match m.kind {
            MoveKind::Rapid | MoveKind::Feed => {
                line.push_str(if m.kind == MoveKind::Rapid {
                    "G0"
                } else {
                    "G1"
                });
                for (i, w) in words.iter().enumerate() {
                    if at[i].as_deref() != Some(w.as_str()) {
                        line.push(' ');
                        line.push(['X', 'Y', 'Z'][i]);
                        line.push_str(w);
                    }
                }
            }
            MoveKind::Arc { center, cw } => {
                line.push_str(if cw { "G2" } else { "G3" });
                for (i, w) in words.iter().enumerate() {
                    line.push(' ');
                    line.push(['X', 'Y', 'Z'][i]);
                    line.push_str(w);
                }
                // I/J from the start point as written (TB029 tip 2: centre and end point).
                let i = units.from_mm(center.0) - start[0];
                let j = units.from_mm(center.1) - start[1];
                line.push_str(" I");
                line.push_str(&number(i, nd, tz));
                line.push_str(" J");
                line.push_str(&number(j, nd, tz));
            }
        }
        if m.kind != MoveKind::Rapid {
            let f = number(units.from_mm(m.feed), fd, tz);
            if feed.as_deref() != Some(f.as_str()) {
                line.push_str(" F");
                line.push_str(&f);
                feed = Some(f);
            }
        }
        for (i, w) in words.into_iter().enumerate() {
            at_v[i] = w.parse().unwrap_or(f64::NAN);
            at[i] = Some(w);
        }
        line.push('\n');
        out.write_all(line.as_bytes())?;
    }
    for e in &profile.end {
        writeln!(out, "{e}")?;
    }
    Ok(())
}

/// One JSON object per move, program units, unrounded:
/// `{"kind":"arc","x":…,"y":…,"z":…,"i":…,"j":…,"cw":true,"f":…,"pass":1,"comp":"left"}`;
/// rapids and feeds carry `x y z` (and `f`). `i`/`j` run from the move's start to the centre.
pub fn write_jsonl(out: &mut dyn Write, plan: &Plan, units: Units) -> io::Result<()> {
    let u = |mm: f64| json_num(units.from_mm(mm));
    let mut from: Option<super::P3> = None;
    for m in &plan.moves {
        let comp = match m.comp {
            Some(CompSide::Left) => "\"left\"",
            Some(CompSide::Right) => "\"right\"",
            None => "null",
        };
        let head = format!(r#""x":{},"y":{},"z":{}"#, u(m.to.x), u(m.to.y), u(m.to.z));
        let text = match m.kind {
            MoveKind::Rapid => format!(r#"{{"kind":"rapid",{head},"pass":{}}}"#, m.pass),
            MoveKind::Feed => format!(
                r#"{{"kind":"feed",{head},"f":{},"pass":{},"comp":{comp}}}"#,
                u(m.feed),
                m.pass
            ),
            MoveKind::Arc { center, cw } => {
                let s = from.expect("an arc follows a move");
                format!(
                    r#"{{"kind":"arc",{head},"i":{},"j":{},"cw":{cw},"f":{},"pass":{},"comp":{comp}}}"#,
                    u(center.0 - s.x),
                    u(center.1 - s.y),
                    u(m.feed),
                    m.pass
                )
            }
        };
        writeln!(out, "{text}")?;
        from = Some(m.to);
    }
    Ok(())
}

/// The summary as JSON, for `--format jsonl` consumers that want the plan's facts first.
pub fn plan_json(plan: &Plan, units: Units) -> serde_json::Value {
    let u = |mm: f64| units.from_mm(mm);
    json!({
        "kind": "plan",
        "thread": plan.thread,
        "class": plan.class,
        "side": plan.side,
        "hand": plan.hand,
        "direction": plan.direction,
        "cw": plan.cw,
        "comp": plan.comp,
        "comp_side": plan.comp_side,
        "units": units,
        "pitch": u(plan.pitch),
        "lead": u(plan.lead),
        "starts": plan.starts,
        "turns": plan.turns,
        "pass_radii": plan.pass_radii.iter().map(|&r| u(r)).collect::<Vec<_>>(),
        "tool_radius": u(plan.tool_radius),
        "center": [u(plan.center.0), u(plan.center.1)],
        "top_z": u(plan.top_z),
        "bottom_z": u(plan.bottom_z),
        "lowest_z": u(plan.lowest_z),
    })
}
