//! The spindle as the program sets it: S, G96/G97 and the G96 speed clamp, read from the words as
//! the Fanuc family writes them (which every dialect threadcut reads shares), or APT's SPINDL.

use crate::gcode::reader::g_code;
use crate::gcode::Line;
use crate::units::Units;

/// What the checks need of the spindle.
pub trait SpindleSpeed {
    /// Spindle speed (rpm) with the tool at radius `r` (mm), if known.
    fn rpm_at(&self, units: Units, r: f64) -> Option<f64>;
    /// Constant surface speed is on.
    fn css(&self) -> bool;
}

/// The spindle as the program has set it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Spindle {
    /// S as last programmed (rpm under G97, surface speed under G96).
    pub s: Option<f64>,
    /// G96 constant surface speed is on.
    pub css: bool,
    /// The G96 speed clamp (S on the set-position block), rpm.
    pub clamp: Option<f64>,
}

impl Spindle {
    /// Reads a block's spindle words; `set_position` is the dialect's set-position code (×10),
    /// whose S is the G96 clamp.
    pub fn read(&mut self, line: &Line, set_position: u16) {
        let mut clamp_block = false;
        for w in line.words.iter().filter(|w| w.letter == b'G') {
            match g_code(w.value) {
                Some(960) => self.css = true,
                Some(970) => self.css = false,
                Some(c) if c == set_position && c != 0 => clamp_block = true,
                _ => {}
            }
        }
        if let Some(s) = line.word(b'S') {
            if clamp_block {
                self.clamp = Some(s.value);
            } else {
                self.s = Some(s.value);
            }
        }
    }
}

impl SpindleSpeed for Spindle {
    fn rpm_at(&self, units: Units, r: f64) -> Option<f64> {
        let s = self.s?;
        if !self.css {
            return Some(s);
        }
        // Surface speed in m/min (metric) or ft/min (inch programs).
        let per_min_mm = match units {
            Units::Mm => s * 1000.0,
            Units::Inch => s * 304.8,
        };
        if r.abs() < 1e-9 {
            return self.clamp;
        }
        let rpm = per_min_mm / (2.0 * std::f64::consts::PI * r.abs());
        Some(self.clamp.map_or(rpm, |c| rpm.min(c)))
    }

    fn css(&self) -> bool {
        self.css
    }
}

/// A constant spindle speed (rpm), for library users and tests.
pub struct Rpm(pub f64);

impl SpindleSpeed for Rpm {
    fn rpm_at(&self, _: Units, _: f64) -> Option<f64> {
        Some(self.0)
    }
    fn css(&self) -> bool {
        false
    }
}
