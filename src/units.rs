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

    pub fn from_mm(self, mm: f64) -> f64 {
        mm / self.scale()
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
