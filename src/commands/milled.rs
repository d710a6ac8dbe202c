//! `passes` on a milling program: each milled thread (`mill::recognise`) with its radial passes,
//! as text and JSON.

use serde::Serialize;

use crate::check::length;
use crate::mill::motion::{Comp, Feed, Plane, Rotation, TapCycle};
use crate::mill::recognise::{Known, MilledThread};
use crate::mill::{Direction, Hand, Side};
use crate::units::Units;

/// One milled thread as `passes --format json` writes it.
#[derive(Serialize)]
pub struct MilledJson<'a> {
    /// The line of its first helical move.
    pub line: u32,
    pub plane: Plane,
    /// The axis on the plane's two axes (mm).
    pub axis: [f64; 2],
    pub lead: f64,
    pub starts: u32,
    pub pitch: f64,
    pub hand: Hand,
    pub direction: Direction,
    pub side: Option<Side>,
    /// How the side is known: `given`, `compensation`, `entry`, `passes`.
    pub side_from: Option<Known>,
    pub climb: Option<bool>,
    /// The diameter the last pass cuts (internal: major; external: minor), when it follows.
    pub root_diameter: Option<f64>,
    /// The thread's extent along its axis (mm).
    pub from: f64,
    pub to: f64,
    pub passes: Vec<PassJson<'a>>,
}

/// One helix: a radial pass of one start.
#[derive(Serialize)]
pub struct PassJson<'a> {
    pub n: u32,
    pub start: u32,
    pub radius: f64,
    /// The diameter this pass cuts, when it follows.
    pub diameter: Option<f64>,
    pub from: f64,
    pub to: f64,
    pub turns: f64,
    pub clockwise: bool,
    pub comp: &'a Comp,
    pub lines: [u32; 2],
}

/// The JSON of one thread; `tool_diameter` gives each pass's diameter without compensation.
pub fn json(t: &MilledThread, tool_diameter: Option<f64>) -> MilledJson<'_> {
    MilledJson {
        line: t.helices[0].lines.0,
        plane: t.plane,
        axis: t.axis,
        lead: t.lead,
        starts: t.starts,
        pitch: t.pitch,
        hand: t.hand,
        direction: t.direction,
        side: t.side.map(|s| s.0),
        side_from: t.side.map(|s| s.1),
        climb: t.climb,
        root_diameter: t.root_diameter,
        from: t.from,
        to: t.to,
        passes: t
            .helices
            .iter()
            .zip(1..)
            .map(|(h, n)| PassJson {
                n,
                start: h.start_index,
                radius: h.radius,
                diameter: diameter(t, h.radius, &h.comp, h.cutter.or(tool_diameter)),
                from: h.from,
                to: h.to,
                turns: h.turns,
                clockwise: h.clockwise,
                comp: &h.comp,
                lines: [h.lines.0, h.lines.1],
            })
            .collect(),
    }
}

/// The diameter a helix of this radius cuts: its own under compensation, the tool centre's ± the
/// cutter's diameter otherwise.
fn diameter(t: &MilledThread, radius: f64, comp: &Comp, tool: Option<f64>) -> Option<f64> {
    match comp {
        Comp::Left { .. } | Comp::Right { .. } => Some(2.0 * radius),
        Comp::Off => {
            let d = tool?;
            match t.side?.0 {
                Side::Internal => Some(2.0 * radius + d),
                Side::External => Some(2.0 * radius - d),
            }
        }
    }
}

/// The text table of one thread, in the program's units.
pub fn text(t: &MilledThread, tool_diameter: Option<f64>, units: Units) -> String {
    let u = |mm: f64| length(units, mm);
    let plane = match t.plane {
        Plane::Xy => ("G17", "X", "Y"),
        Plane::Zx => ("G18", "Z", "X"),
        Plane::Yz => ("G19", "Y", "Z"),
    };
    let side = match t.side {
        Some((s, how)) => format!(
            "{} ({})",
            match s {
                Side::Internal => "internal",
                Side::External => "external",
            },
            match how {
                Known::Given => "given",
                Known::Compensation => "from the compensation",
                Known::Entry => "from the entry",
                Known::Passes => "from the passes",
            }
        ),
        None => "internal or external not known".into(),
    };
    let mut s = format!(
        "line {}: milled thread about {}{} {}{} ({}), {side}, {}, {}{}; lead {}, {}, pitch {} ({})\n",
        t.helices[0].lines.0,
        plane.1,
        u(t.axis[0]),
        plane.2,
        u(t.axis[1]),
        plane.0,
        match t.hand {
            Hand::Right => "right-hand",
            Hand::Left => "left-hand",
        },
        match t.direction {
            Direction::BottomUp => "bottom-up",
            Direction::TopDown => "top-down",
        },
        match t.climb {
            Some(true) => ", climb",
            Some(false) => ", conventional",
            None => "",
        },
        u(t.lead),
        crate::text::count(t.starts as usize, "start", "starts"),
        u(t.pitch),
        units.name()
    );
    s += "pass  start      radius    diameter        from          to   turns  lines\n";
    for (h, n) in t.helices.iter().zip(1..) {
        let d = diameter(t, h.radius, &h.comp, h.cutter.or(tool_diameter)).map_or("-".into(), u);
        s += &format!(
            "{n:>4}  {:>5}  {:>10}  {:>10}  {:>10}  {:>10}  {:>6.3}  {}-{}\n",
            h.start_index,
            u(h.radius),
            d,
            u(h.from),
            u(h.to),
            h.turns,
            h.lines.0,
            h.lines.1
        );
    }
    s
}

/// One tapping cycle as a line of text, in the program's units.
pub fn tap_text(t: &TapCycle, units: Units) -> String {
    let u = |mm: f64| length(units, mm);
    let code = t.code_name();
    let lead = match t.feed {
        Feed::PerRev(f) => Some(f),
        Feed::PerMinute(f) => t.rpm.filter(|&s| s > 0.0).map(|s| f / s),
        Feed::Unknown => None,
    };
    format!(
        "line {}: {code} tap at X{} Y{} from Z{} to Z{}, {}, lead {} per turn, spindle {}{}",
        t.line,
        u(t.position[0]),
        u(t.position[1]),
        u(t.r),
        u(t.bottom),
        if t.rigid { "rigid" } else { "floating" },
        lead.map_or("not known (no S)".into(), u),
        match t.rotation {
            Rotation::Cw => "M3",
            Rotation::Ccw => "M4",
            Rotation::Stopped => "stopped",
        },
        t.peck.map_or(String::new(), |q| format!(", peck {}", u(q)))
    )
}
