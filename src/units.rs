//! Units live at the edges: inside threadcut every length is an `f64` in millimetres and every X is a
//! radius. Readers convert inch and diameter values once; writers convert back once.

use serde::{Deserialize, Serialize};

pub const MM_PER_INCH: f64 = 25.4;

/// The program's length unit (G20/G21, APT UNITS).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    Mm,
    Inch,
}

impl Units {
    /// Millimetres in one program unit.
    pub const fn scale(self) -> f64 {
        match self {
            Units::Mm => 1.0,
            Units::Inch => MM_PER_INCH,
        }
    }

    pub fn to_mm(self, value: f64) -> f64 {
        value * self.scale()
    }

    /// `mm / self.scale()`; millimetres without the division (the same value: x / 1 = x), whose
    /// latency the writers of expanded moves wait for three times a move.
    #[inline]
    pub fn from_mm(self, mm: f64) -> f64 {
        match self {
            Units::Mm => mm,
            Units::Inch => mm / MM_PER_INCH,
        }
    }

    /// A length for a message: in these units, up to 4 decimals, no trailing zeros (a
    /// difference of programmed values shows as written: 0.035, not 0.034999999999999996).
    pub fn show(self, mm: f64) -> String {
        let s = format!("{:.4}", self.from_mm(mm));
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".into()
        } else {
            s.to_string()
        }
    }

    pub const fn name(self) -> &'static str {
        match self {
            Units::Mm => "mm",
            Units::Inch => "inch",
        }
    }
}

/// A point in the XZ plane: X is a radius, both in millimetres, absolute.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Pos {
    pub x: f64,
    pub z: f64,
}

impl Pos {
    pub const fn new(x: f64, z: f64) -> Pos {
        Pos { x, z }
    }

    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.z.is_finite()
    }

    /// The displacement from `from` to `self`.
    pub fn minus(self, from: Pos) -> Vec2 {
        Vec2::new(self.x - from.x, self.z - from.z)
    }

    pub fn plus(self, d: Vec2) -> Pos {
        Pos::new(self.x + d.x, self.z + d.z)
    }

    pub fn distance(self, other: Pos) -> f64 {
        self.minus(other).length()
    }
}

/// A displacement in the XZ plane (radius, millimetres). Kept apart from `Pos` on purpose: a
/// position plus a position means nothing.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Vec2 {
    pub x: f64,
    pub z: f64,
}

impl Vec2 {
    pub const fn new(x: f64, z: f64) -> Vec2 {
        Vec2 { x, z }
    }

    pub fn scale(self, k: f64) -> Vec2 {
        Vec2::new(self.x * k, self.z * k)
    }

    pub fn length(self) -> f64 {
        self.x.hypot(self.z)
    }
}

/// Pitch and lead conversions used by every reader.
pub fn lead_from_tpi(threads_per_inch: f64) -> f64 {
    MM_PER_INCH / threads_per_inch
}

/// The program's resolution: one least input increment of the unit system in force (the machine
/// profile's `increment_system`: 0.001 mm or 0.0001 inch on IS-B, a tenth of that on IS-C).
///
/// Every programmed value is a whole number of increments, so two values the program gives or
/// derives (a start point and the crest it computes, a taper and the thread's length) that differ
/// by no more than one increment are the same value to the control: the half-micrometre between
/// `G00 X40` and a crest computed at X40.001 is not "inside the thread". Every comparison of
/// programmed values in threadcut goes through a [`Tolerance`] from here; there are no other
/// epsilons for them (`docs/reliability.md`, "Comparisons at the program's resolution", lists
/// each one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    /// One increment, in mm.
    increment_mm: f64,
    /// X is written as a diameter: one increment of a written X is half an increment of radius.
    diameter_x: bool,
}

/// The share of an increment added to every tolerance so that binary rounding of decimal values
/// (18.4665 + 1.534 is 20.000500000000002, not 20.0005) cannot push an exact difference of one
/// increment over it.
const ROUNDING_SLACK: f64 = 1e-6;

impl Resolution {
    /// `increment` in program units of `units`; `diameter_x` as the program writes X.
    pub fn new(increment: f64, units: Units, diameter_x: bool) -> Resolution {
        Resolution {
            increment_mm: units.to_mm(increment),
            diameter_x,
        }
    }

    /// One increment, in mm.
    pub fn increment_mm(self) -> f64 {
        self.increment_mm
    }

    /// For lengths along Z and for radial amounts the program writes as radii (depths, tapers,
    /// run-outs): one increment.
    pub fn length(self) -> Tolerance {
        Tolerance(self.increment_mm * (1.0 + ROUNDING_SLACK))
    }

    /// For X positions and radial amounts the program writes in X's own convention (mm, radius
    /// inside): one increment of the written value, which is half an increment of radius when X
    /// is a diameter.
    pub fn x(self) -> Tolerance {
        let radius = if self.diameter_x {
            self.increment_mm / 2.0
        } else {
            self.increment_mm
        };
        Tolerance(radius * (1.0 + ROUNDING_SLACK))
    }
}

/// How far apart two values in mm may be and still be the same value (see [`Resolution`]).
#[derive(Clone, Copy, Debug, PartialEq, PartialOrd)]
pub struct Tolerance(f64);

impl Tolerance {
    /// A tolerance of `mm` millimetres.
    pub const fn mm(mm: f64) -> Tolerance {
        Tolerance(mm)
    }

    /// The tolerance in mm.
    pub fn get(self) -> f64 {
        self.0
    }

    /// `a` and `b` are the same value.
    pub fn eq(self, a: f64, b: f64) -> bool {
        (a - b).abs() <= self.0
    }

    /// `v` is zero at this tolerance.
    pub fn is_zero(self, v: f64) -> bool {
        v.abs() <= self.0
    }

    /// `a` lies below `b` by more than the tolerance (so `a <= b` when this is false: `a` is at or
    /// above `b`, at the resolution).
    pub fn lt(self, a: f64, b: f64) -> bool {
        a < b - self.0
    }

    /// `a` lies above `b` by more than the tolerance.
    pub fn gt(self, a: f64, b: f64) -> bool {
        a > b + self.0
    }

    /// The sign of `v`: -1, 0 (within the tolerance of zero) or 1.
    pub fn sign(self, v: f64) -> i8 {
        if self.gt(v, 0.0) {
            1
        } else if self.lt(v, 0.0) {
            -1
        } else {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_increment_apart_is_the_same_value() {
        // GSK: G00 X40 and a crest at X36.933 + 2 × 1.534 = X40.001 (diameters, IS-B mm).
        let r = Resolution::new(0.001, Units::Mm, true);
        let crest = 36.933 / 2.0 + 1.534;
        assert!(r.x().eq(20.0, crest));
        assert!(!r.x().lt(20.0, crest));
        // X39.999: two increments of diameter inside.
        assert!(r.x().lt(39.999 / 2.0, crest));
        // Z and radial lengths: one whole increment.
        assert!(r.length().eq(-30.0, -30.001));
        assert!(!r.length().eq(-30.0, -30.002));
        assert!(r.length().is_zero(0.001) && !r.length().is_zero(0.0011));
        assert_eq!((r.length().sign(-0.0011), r.length().sign(0.0005)), (-1, 0));
        // Inch: 0.0001 in = 0.00254 mm; radius X on this machine.
        let r = Resolution::new(0.0001, Units::Inch, false);
        assert!(r.x().eq(25.4, 25.4 + 0.00254) && r.x().gt(25.4 + 0.0026, 25.4));
    }
}
