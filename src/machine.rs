//! Machine profiles are data: TOML files, with built-in defaults per controller. They hold what the
//! program text does not: X on diameter or radius, the input resolution and decimal-point
//! convention, controller parameters, machine limits and the output format.

use std::collections::BTreeMap;

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

/// Built-in milling profiles, by name (the milling profile reader takes them from here).
pub const MILL_BUILT_IN: &[(&str, &str)] = &[
    ("centroid", include_str!("../profiles/centroid.toml")),
    ("fanuc-mill", include_str!("../profiles/fanuc-mill.toml")),
    ("haas-mill", include_str!("../profiles/haas-mill.toml")),
    (
        "linuxcnc-mill",
        include_str!("../profiles/linuxcnc-mill.toml"),
    ),
];

/// The two kinds of built-in profile: lathe controllers ([`BUILT_IN`]) and milling controllers
/// ([`MILL_BUILT_IN`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProfileKind {
    Lathe,
    Mill,
}

impl ProfileKind {
    /// The built-in profile names of this kind.
    pub fn names(self) -> Vec<&'static str> {
        let table = match self {
            ProfileKind::Lathe => BUILT_IN,
            ProfileKind::Mill => MILL_BUILT_IN,
        };
        table.iter().map(|(n, _)| *n).collect()
    }

    fn other(self) -> ProfileKind {
        match self {
            ProfileKind::Lathe => ProfileKind::Mill,
            ProfileKind::Mill => ProfileKind::Lathe,
        }
    }
}

/// Why a name given for a built-in profile names none of the kind wanted.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum NameError {
    /// The name is a built-in profile of the other kind (`centroid` given to a lathe command).
    OtherKind {
        name: &'static str,
        kind: ProfileKind,
    },
    /// No built-in profile has that name; the nearest name of the kind wanted, if one is near.
    Unknown { suggestion: Option<&'static str> },
}

/// The built-in profile of `kind` that `name` means: names compare without regard to ASCII case
/// (`GSK980` is `gsk980`). A name of the other kind, or none at all, is a [`NameError`].
pub fn built_in_name(name: &str, kind: ProfileKind) -> Result<&'static str, NameError> {
    let find = |k: ProfileKind| {
        k.names()
            .into_iter()
            .find(|n| n.eq_ignore_ascii_case(name.trim()))
    };
    if let Some(n) = find(kind) {
        return Ok(n);
    }
    if let Some(n) = find(kind.other()) {
        return Err(NameError::OtherKind {
            name: n,
            kind: kind.other(),
        });
    }
    Err(NameError::Unknown {
        suggestion: nearest_name(name, &kind.names()),
    })
}

/// The name among `names` nearest `given`: one that begins with it or that it begins with
/// (`gsk` → `gsk980`, `fanuc0i` → `fanuc`), else the most similar by Jaro-Winkler if similar
/// enough (`linuxnc` → `linuxcnc`); none for an unrelated word.
fn nearest_name(given: &str, names: &[&'static str]) -> Option<&'static str> {
    /// Below this Jaro-Winkler similarity two names are unrelated (`gsk` and `haas` score 0).
    const SIMILAR: f64 = 0.8;
    let key: String = given
        .trim()
        .chars()
        .filter(|c| c.is_ascii_alphanumeric())
        .map(|c| c.to_ascii_lowercase())
        .collect();
    if key.is_empty() {
        return None;
    }
    let plain = |n: &str| -> String { n.chars().filter(|c| c.is_ascii_alphanumeric()).collect() };
    let by_prefix = names
        .iter()
        .filter(|n| {
            let p = plain(n);
            p.starts_with(&key) || key.starts_with(&p)
        })
        .max_by_key(|n| {
            // The longest common prefix wins (`fanuc15x` → `fanuc15`, not `fanuc`).
            plain(n)
                .bytes()
                .zip(key.bytes())
                .take_while(|(a, b)| a == b)
                .count()
        });
    if let Some(n) = by_prefix {
        return Some(n);
    }
    names
        .iter()
        .map(|n| (strsim::jaro_winkler(&key, &plain(n)), *n))
        .filter(|(score, _)| *score >= SIMILAR)
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n)
}

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
    /// Whether Settings 86, 95, 96 and 99 above are threadcut's assumed values (the built-in
    /// profile's) rather than the machine's: a conversion then writes no cycle whose passes
    /// depend on Settings 86 and 99 (the one-block G76), and states the factory defaults of 95 and
    /// 96 its G92 relies on. A profile that states its machine's values leaves it out (false).
    #[serde(default)]
    pub thread_settings_assumed: bool,
    /// Setting 73, G71/G72 retract: the retract after each roughing cut of the one-block G71 and
    /// G72 (inch, radius). Absent: the profile does not state it, and those cycles are refused.
    #[serde(default)]
    pub roughing_retract_in: Option<f64>,
    /// Whether `roughing_retract_in` is an assumed value (the built-in profile's: Haas's public
    /// pages do not state the factory default), said in a warning at each cycle that uses it.
    #[serde(default)]
    pub roughing_retract_assumed: bool,
}

/// LinuxCNC settings that are not in the program.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LinuxCncSettings {
    /// Number of spindles ([TRAJ]SPINDLES); `$` must be below it.
    pub spindles: u8,
}

/// One point of the machine in program coordinates, axis by axis: an axis left out is not known.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisPoint {
    /// X as the program writes it at power-on: a diameter where `diameter_x` is true.
    #[serde(default)]
    pub x: Option<f64>,
    #[serde(default)]
    pub z: Option<f64>,
}

/// Where the reference returns leave the tool, in the program's coordinates at power-on (the
/// profile's `units`, X as `diameter_x` says). A program's coordinates depend on its work offset:
/// state these only for a machine whose programs run in one known coordinate system. Without
/// them, an axis that returns to a reference point is not known afterwards.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReferencePoints {
    /// The first reference point (`G28`, and LinuxCNC's `G28` stored position).
    #[serde(default)]
    pub g28: AxisPoint,
    /// The second reference point (`G30`; on Fanuc `G30 P2`, its default).
    #[serde(default)]
    pub g30: AxisPoint,
}

/// The stock this machine's programs are cut from, where the command does not say
/// (`[stock]`): each value in the profile's `units` (the program's units at power-on), the
/// diameters as diameters whatever `diameter_x` says. A value the command gives wins
/// ([`Stock::over`]). Absent values are not known, as when the command gives none.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stock {
    /// The bar's diameter (`--stock-diameter`).
    #[serde(default)]
    pub diameter: Option<f64>,
    /// Z of the bar's face (`--stock-start`).
    #[serde(default)]
    pub face: Option<f64>,
    /// The bar's length from its face toward the chuck (`--stock-length`).
    #[serde(default)]
    pub length: Option<f64>,
    /// The diameter of a bore through the bar (`--stock-bore`).
    #[serde(default)]
    pub bore: Option<f64>,
}

impl Stock {
    /// These values where given, else `base`'s, value by value (the command line over the
    /// profile).
    pub fn over(self, base: Stock) -> Stock {
        Stock {
            diameter: self.diameter.or(base.diameter),
            face: self.face.or(base.face),
            length: self.length.or(base.length),
            bore: self.bore.or(base.bore),
        }
    }

    /// Whether any value is given.
    pub fn any(&self) -> bool {
        self.diameter.is_some()
            || self.face.is_some()
            || self.length.is_some()
            || self.bore.is_some()
    }
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
    /// Where reference returns leave the tool (absent: nowhere the program can know).
    #[serde(default)]
    pub reference: Option<ReferencePoints>,
    /// The stock its programs are cut from, where the command does not give it (absent: not
    /// known).
    #[serde(default)]
    pub stock: Option<Stock>,
    /// Directories where calls find programs a program does not hold (issue 25), searched after
    /// the command's `--include` directories; a relative one is relative to the profile file's
    /// directory (the command line resolves them: the library reads no files).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub include: Vec<String>,
    /// The tools this machine's turret holds by name (`[tools]`, `THREAD_EXT_60 = "T0101"`): a
    /// program converted for this machine calls a named tool by its number, and a numbered tool
    /// by its name where this machine calls tools by name (docs/translation.md, "Tools by name").
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub tools: BTreeMap<String, String>,
}

impl Machine {
    pub fn built_in(name: &str) -> Option<Machine> {
        BUILT_IN
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, text)| Machine::from_toml(text).expect("built-in profiles are tested"))
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

    /// The program's resolution in `units`, with X written as `diameter_x` says.
    pub fn program_resolution(&self, units: Units, diameter_x: bool) -> crate::units::Resolution {
        crate::units::Resolution::new(self.resolution(units), units, diameter_x)
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
    fn built_in_names_ignore_case_and_name_the_other_kind() {
        assert_eq!(built_in_name("GSK980", ProfileKind::Lathe), Ok("gsk980"));
        assert_eq!(built_in_name("Fanuc-B", ProfileKind::Lathe), Ok("fanuc-b"));
        assert_eq!(built_in_name("CENTROID", ProfileKind::Mill), Ok("centroid"));
        assert_eq!(
            built_in_name("centroid", ProfileKind::Lathe),
            Err(NameError::OtherKind {
                name: "centroid",
                kind: ProfileKind::Mill
            })
        );
        assert_eq!(
            built_in_name("Haas", ProfileKind::Mill),
            Err(NameError::OtherKind {
                name: "haas",
                kind: ProfileKind::Lathe
            })
        );
        let suggestion = |n: &str, k| match built_in_name(n, k) {
            Err(NameError::Unknown { suggestion }) => suggestion,
            other => panic!("{n}: {other:?}"),
        };
        assert_eq!(suggestion("GSK", ProfileKind::Lathe), Some("gsk980"));
        assert_eq!(suggestion("gsk-980", ProfileKind::Lathe), Some("gsk980"));
        assert_eq!(suggestion("linuxnc", ProfileKind::Lathe), Some("linuxcnc"));
        assert_eq!(suggestion("fanuc0i", ProfileKind::Lathe), Some("fanuc"));
        assert_eq!(
            suggestion("sinumerik840d", ProfileKind::Lathe),
            Some("sinumerik")
        );
        assert_eq!(
            suggestion("centroid-m", ProfileKind::Mill),
            Some("centroid")
        );
        assert_eq!(suggestion("mazak", ProfileKind::Lathe), None);
        assert_eq!(suggestion("", ProfileKind::Lathe), None);
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
    fn reference_points_are_optional_axis_by_axis() {
        let text = format!(
            "{}\n[reference]\ng28 = {{ x = 250.0, z = 120.5 }}\ng30 = {{ z = 80.0 }}\n",
            BUILT_IN[0].1
        );
        let m = Machine::from_toml(&text).unwrap();
        let r = m.reference.unwrap();
        assert_eq!((r.g28.x, r.g28.z), (Some(250.0), Some(120.5)));
        assert_eq!((r.g30.x, r.g30.z), (None, Some(80.0)));
        assert!(Machine::from_toml(&text.replace("g30", "g31")).is_err());
        assert!(Machine::from_toml(&text.replace("z = 80.0", "y = 80.0")).is_err());
        assert_eq!(Machine::built_in("fanuc").unwrap().reference, None);
    }

    /// `[stock]` is optional value by value; the command line's values win over it one by one.
    #[test]
    fn stock_is_optional_and_the_command_line_wins() {
        let text = format!(
            "{}\n[stock]\ndiameter = 25.0\nface = 0.5\nbore = 8.0\n",
            BUILT_IN[0].1
        );
        let m = Machine::from_toml(&text).unwrap();
        let s = m.stock.unwrap();
        assert_eq!(
            (s.diameter, s.face, s.length, s.bore),
            (Some(25.0), Some(0.5), None, Some(8.0))
        );
        let given = Stock {
            diameter: Some(30.0),
            length: Some(120.0),
            ..Stock::default()
        };
        let both = given.over(s);
        assert_eq!(
            (both.diameter, both.face, both.length, both.bore),
            (Some(30.0), Some(0.5), Some(120.0), Some(8.0))
        );
        assert!(!Stock::default().any() && both.any());
        assert!(Machine::from_toml(&text.replace("bore =", "hole =")).is_err());
        assert_eq!(Machine::built_in("fanuc").unwrap().stock, None);
    }

    #[test]
    fn unknown_keys_are_refused() {
        let text = BUILT_IN[0]
            .1
            .replace("diameter_x = true", "diameter_x = true\ncolour = 1");
        assert!(Machine::from_toml(&text).is_err());
    }
}
