//! The thread a program cuts, measured from its final passes and the tool's form ([`measure`]),
//! and what a standard form contributes to judging it ([`Target`]) — shared by the judging of a
//! parallel thread ([`super::standard`]) and of a taper thread at its gauge plane
//! ([`super::taper`]).

use crate::sim::{groove_edges, Tip, Tool};
use crate::thread::standard::{Edge, Limits, StandardThread, Surface};
use crate::threads::Thread;

/// The depths (fractions of the depth reached) between which flank angles are measured, as `sim`
/// does.
const FLANK_BAND: (f64, f64) = (0.2, 0.6);
/// Passes within this depth (mm) of the deepest are the final passes: far below any control's
/// resolution, far above rounding.
const FINAL_DEPTH_TOLERANCE: f64 = 1e-6;
/// Bisections stop when the interval is this narrow (mm).
const BISECTION_WIDTH: f64 = 1e-10;

/// What a standard form contributes to the judging, on one side.
#[derive(Clone, Debug)]
pub struct Target<'a> {
    pub thread: &'a StandardThread,
    pub side: Surface,
    pub limits: Limits,
    /// The thread's included angle (degrees).
    pub angle_deg: f64,
    /// The tool that cuts the basic profile at the basic depth (mm), assumed when none is given.
    pub root_tool: Tip,
    /// Name with class, as users write it: `M50x2-6g`.
    pub name: String,
}

impl Target<'_> {
    /// The class as messages name it: `6g`, `2A`; a pipe thread's one class by the thread's name.
    pub fn class_name(&self) -> String {
        match self.limits.class {
            crate::thread::standard::Class::Pipe { .. } => self.thread.name.clone(),
            class => class.to_string(),
        }
    }
}

/// The target on `side`, or why the thread cannot be judged there (a class of the other side).
pub fn target(thread: &StandardThread, side: Surface) -> Result<Target<'_>, String> {
    let (mine, other) = match side {
        Surface::External => (thread.external, thread.internal),
        Surface::Internal => (thread.internal, thread.external),
    };
    let limits = match (mine, other) {
        (Some(l), _) => l,
        (None, None) => thread.limits(side),
        (None, Some(o)) => {
            return Err(format!(
                "{}-{} is a class of {} threads, and the program cuts an {} thread",
                thread.name,
                o.class,
                side_name(o.side),
                side_name(side)
            ))
        }
    };
    // The basic profile's root on this side (ISO 68-1 / ASME B1.1: the external root rounded
    // with H/6, to d3; the internal root a flat of P/8; the other forms' own roots): the tool that
    // cuts the basic profile at the basic depth.
    let root = match side {
        Surface::External => thread.profile.external_root,
        Surface::Internal => thread.profile.internal_root,
    };
    let angle_deg = angle_of(thread);
    let root_tool = root_tip(root, thread.profile.slope());
    Ok(Target {
        thread,
        side,
        limits,
        angle_deg,
        root_tool,
        // A taper pipe thread has one class per side: users write its name alone.
        name: match limits.class {
            crate::thread::standard::Class::Pipe { .. } => thread.name.clone(),
            class => format!("{}-{class}", thread.name),
        },
    })
}

/// A standard thread's included angle (degrees).
pub fn angle_of(thread: &StandardThread) -> f64 {
    thread.profile.angle_deg
}

/// The tool tip that cuts a root of this shape; `slope` is tan of the flank angle. A truncated
/// root (NPT: a flat or a radius between two truncations) is cut with the flat of the mean
/// truncation.
fn root_tip(root: Edge, slope: f64) -> Tip {
    match root {
        Edge::Sharp => Tip::Sharp,
        Edge::Flat { width } => Tip::Flat { width },
        Edge::Round { radius } => Tip::Radius { radius },
        Edge::Truncated { min, max } => Tip::Flat {
            width: (min + max) * slope,
        },
    }
}

fn side_name(s: Surface) -> &'static str {
    match s {
        Surface::External => "external",
        Surface::Internal => "internal",
    }
}

/// The thread a program cuts, measured (mm, diameters).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measured {
    /// The crest's diameter the depths are measured from.
    pub crest: f64,
    /// The deepest pass below the crest.
    pub depth: f64,
    /// External: the minor diameter; internal: the major diameter.
    pub root: f64,
    /// Where the groove is half a pitch wide; `None` when it is nowhere (far too shallow, or a
    /// tool wider than half a pitch at its tip).
    pub pitch_diameter: Option<f64>,
    /// Where along the thread (the passes' lateral coordinate, +Z of the crest line's start, mm)
    /// the groove's centre lies at the pitch diameter: a taper thread's pitch diameter is measured
    /// there.
    pub pitch_centre: f64,
    pub flank_left_deg: f64,
    pub flank_right_deg: f64,
}

/// Measures `t`'s final groove with `tool` (sizes in mm), the pitch being `pitch` (mm).
pub fn measure(t: &Thread, tool: &Tool, pitch: f64) -> Measured {
    let g = &t.job.geometry;
    let out = g.side.outward().x;
    let crest_r = g.crest_start.x;
    let form = tool.form();
    // The thread is what the final passes leave: the passes at the final depth (a groove's other
    // passes lie inside their form unless they leave a ridge or an overcut, which `check`'s form
    // findings report).
    let depth = t
        .passes
        .iter()
        .map(|p| p.depth)
        .fold(f64::NEG_INFINITY, f64::max);
    let cuts: Vec<(f64, f64)> = t
        .passes
        .iter()
        .filter(|p| p.depth >= depth - FINAL_DEPTH_TOLERANCE)
        .map(|p| (p.offset, p.depth))
        .collect();
    let width = |v: f64| groove_edges(&cuts, &form, v).map_or(0.0, |(l, r)| r - l);
    // The groove narrows with depth: bisect for width = P/2 between well above the crest and the
    // deepest point.
    let (mut a, mut b) = (-(depth.abs() + 4.0 * pitch), depth);
    let pitch_diameter = if width(a) >= pitch / 2.0 && width(b) <= pitch / 2.0 {
        while b - a > BISECTION_WIDTH {
            let m = (a + b) / 2.0;
            if width(m) >= pitch / 2.0 {
                a = m;
            } else {
                b = m;
            }
        }
        Some(2.0 * (crest_r - out * a))
    } else {
        None
    };
    let centre_at = if pitch_diameter.is_some() { a } else { depth };
    let pitch_centre = groove_edges(&cuts, &form, centre_at).map_or_else(
        || cuts.iter().map(|c| c.0).sum::<f64>() / cuts.len().max(1) as f64,
        |(l, r)| (l + r) / 2.0,
    );
    let (va, vb) = (FLANK_BAND.0 * depth, FLANK_BAND.1 * depth);
    let (flank_left_deg, flank_right_deg) = match (
        groove_edges(&cuts, &form, va),
        groove_edges(&cuts, &form, vb),
    ) {
        (Some((la, ra)), Some((lb, rb))) if vb > va => (
            ((lb - la) / (vb - va)).atan().to_degrees(),
            ((ra - rb) / (vb - va)).atan().to_degrees(),
        ),
        _ => (tool.angle_deg / 2.0, tool.angle_deg / 2.0),
    };
    Measured {
        crest: 2.0 * crest_r,
        depth,
        root: 2.0 * (crest_r - out * depth),
        pitch_diameter,
        pitch_centre,
        flank_left_deg,
        flank_right_deg,
    }
}

/// What the judging is told about the program besides its thread.
pub struct Judging<'a> {
    pub target: &'a Target<'a>,
    /// The tool's tip as the user gave it (mm), if given.
    pub tip: Option<Tip>,
    /// The program's least input increment (mm): diameters within it of a limit are at the limit.
    pub resolution: f64,
    /// The part's face the thread enters (a taper thread's gauge plane is placed from it); `None`:
    /// not known.
    pub face: Option<Face>,
    /// The measuring wire one owns (mm); `None`: the best wire.
    pub wire: Option<f64>,
}

/// The part's face on the side where the thread starts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// Z (mm).
    pub z: f64,
    /// The user gave it (`--stock-start`); otherwise `check` assumed it.
    pub given: bool,
}

/// The pitch diameter of the groove a form tool cuts with its tip on the diameter `root` (an
/// external thread's minor, an internal one's major) in one plunge: where the groove is half a
/// pitch wide. `None` when it is nowhere (a tip wider than half a pitch).
pub fn pitch_diameter_at_root(root: f64, side: Surface, tool: &Tool, pitch: f64) -> Option<f64> {
    let form = tool.form();
    // A crest well above the groove: 4 pitches outside the root.
    let depth = 4.0 * pitch;
    let cut = [(0.0, depth)];
    let width = |v: f64| groove_edges(&cut, &form, v).map_or(0.0, |(l, r)| r - l);
    let (mut a, mut b) = (0.0, depth);
    if width(a) < pitch / 2.0 || width(b) > pitch / 2.0 {
        return None;
    }
    while b - a > BISECTION_WIDTH {
        let m = (a + b) / 2.0;
        if width(m) >= pitch / 2.0 {
            a = m;
        } else {
            b = m;
        }
    }
    // From the root, the pitch line lies `depth − a` toward the crest.
    let up = depth - a;
    Some(match side {
        Surface::External => root + 2.0 * up,
        Surface::Internal => root - 2.0 * up,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::Tip;

    #[test]
    fn the_pitch_diameter_of_a_plunged_groove() {
        // A sharp 60° tool: the groove is P/2 wide at (P/2)/(2·tan 30°) = 0.4330·P above the tip.
        // External, root Ø17 with P = 2.5: PD = 17 + 2·1.0825 = 19.1651.
        let pd = pitch_diameter_at_root(17.0, Surface::External, &Tool::sharp(60.0), 2.5).unwrap();
        assert!((pd - (17.0 + 2.0 * 1.25 / (2.0 * 30f64.to_radians().tan()))).abs() < 1e-6);
        // Internal with a flat of P/8 = 0.3125: the width grows from 0.3125 at the root, so P/2 is
        // reached (1.25 − 0.3125)/(2·tan 30°) = 0.8119 above it. Root Ø20: PD = 20 − 1.6238.
        let flat = Tool {
            angle_deg: 60.0,
            tip: Tip::Flat { width: 0.3125 },
        };
        let pd = pitch_diameter_at_root(20.0, Surface::Internal, &flat, 2.5).unwrap();
        let up = (1.25 - 0.3125) / (2.0 * 30f64.to_radians().tan());
        assert!((pd - (20.0 - 2.0 * up)).abs() < 1e-6, "{pd}");
        // A flat wider than half the pitch: no pitch diameter.
        let wide = Tool {
            angle_deg: 60.0,
            tip: Tip::Flat { width: 1.5 },
        };
        assert!(pitch_diameter_at_root(20.0, Surface::Internal, &wide, 2.5).is_none());
    }
}
