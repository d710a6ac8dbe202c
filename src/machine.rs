//! Machine profiles are data: TOML files, with built-in defaults per controller. They hold what the
//! program text does not: X on diameter or radius, the input resolution and decimal-point
//! convention, controller parameters, machine limits and the output format.

use serde::{Deserialize, Serialize};

use crate::units::Units;

/// Built-in profiles, by name. Each is a TOML file under `profiles/`.
pub const BUILT_IN: &[(&str, &str)] = &[
    ("gsk980", include_str!("../profiles/gsk980.toml")),
    ("omniturn", include_str!("../profiles/omniturn.toml")),
    ("ab9", include_str!("../profiles/ab9.toml")),
    ("fanuc", include_str!("../profiles/fanuc.toml")),
    ("fanuc15", include_str!("../profiles/fanuc15.toml")),
    ("fanuc-b", include_str!("../profiles/fanuc-b.toml")),
    ("haas", include_str!("../profiles/haas.toml")),
    ("linuxcnc", include_str!("../profiles/linuxcnc.toml")),
    ("sinumerik", include_str!("../profiles/sinumerik.toml")),
];

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum IncrementSystem {
    /// 0.001 mm / 0.0001 inch.
    Isb,
    /// 0.0001 mm / 0.00001 inch.
    Isc,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DecimalPoint {
    /// `X10` means 10 program units.
    Calculator,
    /// `X10` means 10 least input increments (0.010 mm on ISB).
    LeastIncrement,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum CommentStyle {
    /// `(text)`
    Paren,
    /// `; text`
    Semicolon,
    /// No comments in the output.
    None,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputFormat {
    pub comment: CommentStyle,
    /// Write `X62.400` rather than `X62.4`.
    #[serde(default)]
    pub trailing_zeros: bool,
}

#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Largest lead the controller accepts (mm/rev).
    pub max_lead_mm: Option<f64>,
    /// Largest synchronised axis feed (mm/min).
    pub max_feed_mm_per_min: Option<f64>,
    /// Servo time constant T1 (s) of the synchronised axis, for the run-up a thread needs
    /// (`check`; 0.033 s when absent, the usual value the Fanuc manuals quote).
    #[serde(default)]
    pub servo_time_constant_s: Option<f64>,
    /// Lead error accepted at the thread's start, as a fraction (`check`; 0.01 when absent).
    #[serde(default)]
    pub thread_lead_error: Option<f64>,
}

/// GSK parameters 5129–5145 as the seed numbers them (§5 of the English text).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GskParameters {
    pub p5129: u8,
    pub p5130: u8,
    pub p5131: u8,
    pub p5140: f64,
    pub p5141: f64,
    pub p5142: u8,
    pub p5143: u8,
    pub p5144: u8,
    pub p5145: u8,
}

/// OmniTurn G33 controller data (seed 002), in inches: the three feed modes are normal, G35 and
/// G35F2, in that order.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OmniTurnParameters {
    /// Largest lead K per mode (".2\" max. For larger see G35"; G35 up to 1\", G35F2 up to 2\").
    pub max_lead_in: [f64; 3],
    /// Output resolution per mode (.00005\", .00025\", .0005\").
    pub resolution_in: [f64; 3],
    /// Fastest slide feed (ipm): S × K above it draws a warning ("the maximum feed rate of the
    /// slide is 300 ipm").
    pub max_slide_ipm: f64,
    /// Z run-up the slide needs to reach threading speed (about half a ball-screw revolution; the
    /// seed advises starting at least .1" away).
    pub runup_in: f64,
}

/// What `E` means on an Allen-Bradley 9/Series thread block: an AMP (machine parameter) choice.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum EWord {
    ThreadsPerInch,
    InchesPerThread,
}

/// Allen-Bradley 9/Series G78 AMP values the program does not carry (seed 003 is cut off before
/// the tool-infeed pages; docs/dialects/allen-bradley-g78.md gives the source of each default).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AbParameters {
    pub e_word: EWord,
    /// Pull-out (chamfer) length along Z in leads; 0: none.
    pub chamfer_leads: f64,
    /// Pull-out angle from the Z axis (degrees, 1–89).
    pub chamfer_angle_deg: f64,
    /// Smallest rough cut (inch, radius) for the constant-amount infeeds P1/P2.
    pub min_cut_in: f64,
    /// Radial stock left for the finishing passes (inch).
    pub finish_allowance_in: f64,
    /// Passes at full depth after the rough passes.
    pub finish_passes: u32,
}

/// Fanuc's G-code systems for lathes (the "G code list" of the lathe manuals; parameter bits, B and
/// C are options): which G numbers thread, set coordinates and select units. `docs/dialects/fanuc.md`
/// has the table.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GCodeSystem {
    /// G32 thread, G92 threading cycle, G50 coordinates, U/W incremental, G20/G21 units.
    #[default]
    A,
    /// G33 thread, G78 threading cycle, G92 coordinates, G90/G91 distance, G20/G21 units.
    B,
    /// As B, but G21 is the threading cycle, G70/G71 the units and G72–G78 the multiple
    /// repetitive cycles (G78: the multiple threading cycle).
    C,
}

/// Fanuc parameters of the threading cycles G92/G76 (Fanuc numbering, threading-notes §c.3, §e).
/// Lengths in mm (radius).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FanucParameters {
    /// The G-code system (A when absent).
    #[serde(default)]
    pub gcode_system: GCodeSystem,
    /// Chamfer (thread pull-out) amount for G92/G76 in 0.1 lead, 0–127.
    pub p5130: u8,
    /// Chamfer angle for G92/G76 in degrees, 1–89; 0 means 45.
    pub p5131: u8,
    /// G76 minimum cut Δdmin (mm).
    pub p5140: f64,
    /// G76 finishing allowance d (mm).
    pub p5141: f64,
    /// G76 finishing repetitions m.
    pub p5142: u8,
    /// G76 tool-tip angle a (degrees).
    pub p5143: u8,
}

/// The Haas lathe settings that govern its threading cycles (G76, G92), in inches as the Haas
/// settings pages give them. `docs/dialects/haas.md` gives the source of each.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HaasSettings {
    /// Setting 86, thread finish allowance (radius): the G76 finishing pass removes it.
    pub finish_allowance_in: f64,
    /// Setting 95, thread chamfer size, in leads ("number of threads"); 0: no chamfer.
    pub chamfer_leads: f64,
    /// Setting 96, thread chamfer angle (degrees, from the Z axis).
    pub chamfer_angle_deg: f64,
    /// Setting 99, thread minimum cut (radius).
    pub min_cut_in: f64,
}

/// LinuxCNC settings that are not in the program.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinuxCncSettings {
    /// Number of spindles ([TRAJ]SPINDLES); `$` must be below it.
    pub spindles: u8,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Machine {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Which dialect reads and writes this machine's programs.
    pub dialect: String,
    pub diameter_x: bool,
    /// Units at power-on (G20/G21 change them).
    pub units: Units,
    pub increment_system: IncrementSystem,
    pub decimal_point: DecimalPoint,
    pub output: OutputFormat,
    #[serde(default)]
    pub limits: Limits,
    pub gsk: Option<GskParameters>,
    #[serde(default)]
    pub omniturn: Option<OmniTurnParameters>,
    #[serde(default)]
    pub ab9: Option<AbParameters>,
    #[serde(default)]
    pub fanuc: Option<FanucParameters>,
    #[serde(default)]
    pub linuxcnc: Option<LinuxCncSettings>,
    #[serde(default)]
    pub haas: Option<HaasSettings>,
}

impl Machine {
    pub fn built_in(name: &str) -> Option<Machine> {
        BUILT_IN
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, text)| Machine::from_toml(text).expect("built-in profiles are tested"))
    }

    /// The names of the built-in profiles, in the order of [`BUILT_IN`].
    pub fn names() -> Vec<&'static str> {
        BUILT_IN.iter().map(|(n, _)| *n).collect()
    }

    /// A built-in profile by name; the error names the built-in ones.
    pub fn named(name: &str) -> Result<Machine, String> {
        Machine::built_in(name).ok_or_else(|| {
            format!(
                "unknown controller `{name}` (built in: {})",
                Machine::names().join(", ")
            )
        })
    }

    pub fn from_toml(text: &str) -> Result<Machine, toml::de::Error> {
        toml::from_str(text)
    }

    /// Decimals of the input resolution in `units` (ISB: 3 mm / 4 inch; ISC: one more).
    pub fn decimals(&self, units: Units) -> u32 {
        let base = match units {
            Units::Mm => 3,
            Units::Inch => 4,
        };
        match self.increment_system {
            IncrementSystem::Isb => base,
            IncrementSystem::Isc => base + 1,
        }
    }

    /// The least input increment in `units`.
    pub fn resolution(&self, units: Units) -> f64 {
        10f64.powi(-(self.decimals(units) as i32))
    }

    /// What a number written without a decimal point is worth, in program units.
    pub fn no_point_scale(&self, units: Units) -> f64 {
        match self.decimal_point {
            DecimalPoint::Calculator => 1.0,
            DecimalPoint::LeastIncrement => self.resolution(units),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_profile_parses() {
        for (name, text) in BUILT_IN {
            let m = Machine::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(&m.name, name);
        }
    }

    #[test]
    fn resolution_follows_increment_system() {
        let mut m = Machine::built_in("gsk980").unwrap();
        assert_eq!(m.decimals(Units::Mm), 3);
        assert_eq!(m.decimals(Units::Inch), 4);
        m.increment_system = IncrementSystem::Isc;
        assert_eq!(m.resolution(Units::Mm), 1e-4);
    }

    #[test]
    fn named_profiles_and_the_error_that_lists_them() {
        assert_eq!(Machine::named("haas").unwrap().name, "haas");
        let e = Machine::named("gsk").unwrap_err();
        assert!(
            e.starts_with("unknown controller `gsk` (built in: gsk980, "),
            "{e}"
        );
        assert_eq!(Machine::names().len(), BUILT_IN.len());
    }

    #[test]
    fn unknown_keys_are_refused() {
        let text = BUILT_IN[0]
            .1
            .replace("diameter_x = true", "diameter_x = true\ncolour = 1");
        assert!(Machine::from_toml(&text).is_err());
    }
}
