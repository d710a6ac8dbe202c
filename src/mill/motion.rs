//! A machining centre's motion, machine-neutral: what a milling program makes the programmed point
//! do, move by move, in millimetres, absolute in the work coordinate system the program selected
//! (its G52/G92 shifts applied; the work offsets' own values are the machine's, not known here).
//!
//! The milling reader makes these; thread recognition (a helix about one axis, a tapping cycle)
//! and every view of a milling program read them. Under cutter compensation the moves are the
//! programmed contour, not the tool centre: [`Comp`] says which.

use serde::Serialize;

/// A point: X, Y, Z (mm).
pub type P3 = [f64; 3];

/// The plane of circular motion (G17, G18, G19).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Plane {
    /// G17: arcs in X–Y, the helix advancing along Z.
    Xy,
    /// G18: arcs in Z–X, advancing along Y.
    Zx,
    /// G19: arcs in Y–Z, advancing along X.
    Yz,
}

impl Plane {
    /// The indices of the plane's first and second axes (as G2/G3 sweep them) and of the axis
    /// normal to it.
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::Xy => (0, 1, 2),
            Plane::Zx => (2, 0, 1),
            Plane::Yz => (1, 2, 0),
        }
    }
}

/// How one move runs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "lowercase")]
pub enum MillKind {
    Rapid,
    Feed,
    /// A circular move in `plane` about `centre` (its normal coordinate is the start's), clockwise
    /// (G2) seen from the positive normal axis, or counter-clockwise (G3); a helix when the
    /// normal axis moves too. `turns` full turns are made before the last, partial one (LinuxCNC's
    /// `P` minus one; 0 for Fanuc-family arcs).
    Arc {
        centre: P3,
        plane: Plane,
        clockwise: bool,
        turns: u32,
    },
    /// A spindle-synchronised straight move: `lead` mm per spindle revolution along the move
    /// (LinuxCNC G33/G33.1, a rigid-tapping cycle's feed in and out).
    Sync {
        lead: f64,
    },
}

/// The feed in force.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "mode", content = "value", rename_all = "kebab-case")]
pub enum Feed {
    /// G94: mm per minute.
    PerMinute(f64),
    /// G95: mm per revolution.
    PerRev(f64),
    /// No F word yet (or an inverse-time feed, G93, which states no rate along the path).
    Unknown,
}

/// The spindle's rotation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Rotation {
    /// M3: clockwise seen from the spindle looking at the work (a right-hand tap cuts going in).
    Cw,
    /// M4.
    Ccw,
    /// M5, or never started.
    Stopped,
}

/// Cutter radius compensation in force.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(tag = "side", rename_all = "lowercase")]
pub enum Comp {
    /// G40: the moves are the tool centre's.
    Off,
    /// G41: the tool left of the path (looking along the motion), the D register named if any.
    Left { d: Option<u32> },
    /// G42.
    Right { d: Option<u32> },
}

/// The machine's state a move runs under.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct State {
    pub feed: Feed,
    /// Spindle speed (rpm) last programmed, if any.
    pub rpm: Option<f64>,
    pub rotation: Rotation,
    /// The tool in the spindle (the T word of the last tool change), if stated.
    pub tool: Option<u32>,
    /// The tool-length offset register in force (G43 H), if any.
    pub length_offset: Option<u32>,
    pub comp: Comp,
    /// The units the program is written in at the move (G20/G21): its words' resolution, and the
    /// units its messages are given in.
    pub units: crate::units::Units,
}

/// One move of a milling program.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MillMotion {
    #[serde(flatten)]
    pub kind: MillKind,
    /// Where the move starts and ends (mm, absolute).
    pub from: P3,
    pub to: P3,
    pub state: State,
    /// Source line (1-based).
    pub line: u32,
}

/// A tapping cycle as programmed, once for each hole it taps (Fanuc/Haas G84, G74, G84.2,
/// G84.3; LinuxCNC G84, G74 and G33.1): what tapping recognition needs, besides the moves.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TapCycle {
    /// The hole's position on the plane and where the tap starts (mm, absolute).
    pub position: P3,
    /// The R level (where the feed starts and the tap returns), along the drilling axis (mm).
    pub r: f64,
    /// The bottom (mm).
    pub bottom: f64,
    /// The feed as programmed, with its mode (G94 mm/min, G95 mm/rev).
    pub feed: Feed,
    /// The spindle speed programmed (rpm).
    pub rpm: Option<f64>,
    /// The spindle's rotation going in (as the cycle drives it: M4 for a left-hand tap).
    pub rotation: Rotation,
    /// Rigid (spindle and feed synchronised: M29, G84.2, G33.1, a control that taps rigidly)
    /// or floating.
    pub rigid: bool,
    /// The peck depth Q, if any (mm).
    pub peck: Option<f64>,
    /// The dwell P at the bottom and at R, if any (seconds).
    pub dwell: Option<f64>,
    /// The cycle's G code ×10 (G84 = 840, G84.2 = 842, G33.1 = 331); 0 for a lathe's tap written
    /// as synchronised moves (G32, G33) on the centre line.
    pub code: u16,
    /// Source line (1-based).
    pub line: u32,
}

impl MillMotion {
    /// An arc's radius at its start in its plane, and the signed sweep (radians, positive
    /// counter-clockwise seen from the normal axis), full turns included; `None` for other moves.
    /// A start equal to the end (within `eps`) is a full circle.
    pub fn sweep(&self, eps: f64) -> Option<(f64, f64)> {
        let MillKind::Arc {
            centre,
            plane,
            clockwise,
            turns,
        } = self.kind
        else {
            return None;
        };
        let (a, b, _) = plane.axes();
        let (sa, sb) = (self.from[a] - centre[a], self.from[b] - centre[b]);
        let (ea, eb) = (self.to[a] - centre[a], self.to[b] - centre[b]);
        let radius = sa.hypot(sb);
        let tau = std::f64::consts::TAU;
        let mut d = eb.atan2(ea) - sb.atan2(sa);
        let closed = (sa - ea).hypot(sb - eb) <= eps;
        if clockwise {
            d = if closed {
                -tau
            } else {
                d.rem_euclid(tau) - tau
            };
        } else {
            d = if closed { tau } else { d.rem_euclid(tau) };
        }
        let extra = f64::from(turns) * tau;
        Some((radius, if clockwise { d - extra } else { d + extra }))
    }
}

impl TapCycle {
    /// The cycle's code as written: `G84`, `G84.2`, `G33.1`; a lathe's tap written as
    /// synchronised moves on the centre line (code 0) is named as such.
    pub fn code_name(&self) -> String {
        if self.code == 0 {
            "the tap on the centre line".to_string()
        } else if self.code.is_multiple_of(10) {
            format!("G{}", self.code / 10)
        } else {
            format!("G{}.{}", self.code / 10, self.code % 10)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arc(from: P3, to: P3, centre: P3, clockwise: bool, turns: u32) -> MillMotion {
        MillMotion {
            kind: MillKind::Arc {
                centre,
                plane: Plane::Xy,
                clockwise,
                turns,
            },
            from,
            to,
            state: State {
                feed: Feed::Unknown,
                rpm: None,
                rotation: Rotation::Stopped,
                tool: None,
                length_offset: None,
                comp: Comp::Off,
                units: crate::units::Units::Mm,
            },
            line: 1,
        }
    }

    #[test]
    fn sweeps_of_quarter_full_and_extra_turns() {
        use std::f64::consts::{FRAC_PI_2, TAU};
        // From (10, 0) to (0, 10) about the origin: a quarter turn counter-clockwise (G3), three
        // quarters clockwise (G2).
        let (r, s) = arc([10., 0., 0.], [0., 10., -1.], [0.; 3], false, 0)
            .sweep(1e-9)
            .unwrap();
        assert!((r - 10.0).abs() < 1e-12 && (s - FRAC_PI_2).abs() < 1e-12);
        let (_, s) = arc([10., 0., 0.], [0., 10., -1.], [0.; 3], true, 0)
            .sweep(1e-9)
            .unwrap();
        assert!((s + 3.0 * FRAC_PI_2).abs() < 1e-12);
        // The end on the start: one full turn; two more with turns = 2.
        let (_, s) = arc([10., 0., 0.], [10., 0., -2.], [0.; 3], true, 2)
            .sweep(1e-9)
            .unwrap();
        assert!((s + 3.0 * TAU).abs() < 1e-12);
    }
}
