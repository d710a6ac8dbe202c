//! Milling controller profiles: TOML files in `profiles/`, compiled in.
//!
//! A milling program needs different facts from a lathe profile (`machine::Machine`): the cutter
//! compensation words and their rules, what F means under compensation, the block that sets up
//! the modal state. So milling has its own small profile struct rather than optional fields on
//! the lathe `Machine` (whose `dialect` would name a lathe reader that does not exist for these
//! controllers).

use serde::{Deserialize, Serialize};

use crate::machine::CommentStyle;

/// Built-in milling profiles, by name (listed beside the lathe's, in [`crate::machine`], so that
/// a profile given to the wrong kind of command can be named).
pub use crate::machine::MILL_BUILT_IN as BUILT_IN;

/// Which point F drives while cutter compensation is on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum FeedReference {
    /// F is the speed of the tool centre (so threadcut scales arc feeds to give the requested
    /// feed at the cutting edge).
    Centre,
    /// F is the speed along the programmed contour (no scaling under compensation).
    Contour,
}

#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MillProfile {
    pub name: String,
    #[serde(default)]
    pub description: String,
    /// Decimals of X, Y, Z, I, J in mm and in inch programs.
    pub decimals_mm: u32,
    pub decimals_inch: u32,
    /// Decimals of F in mm/min and in/min.
    pub feed_decimals_mm: u32,
    pub feed_decimals_inch: u32,
    #[serde(default)]
    pub trailing_zeros: bool,
    pub comment: CommentStyle,
    /// Words written once after the units word (plane, absolute, feed per minute, comp off …).
    pub preamble: Vec<String>,
    /// G41/G42 need a D word naming the offset register.
    pub comp_needs_d: bool,
    /// The compensation entry move must be longer than the tool radius (LinuxCNC).
    #[serde(default)]
    pub comp_entry_longer_than_radius: bool,
    /// What F means under compensation.
    pub comp_feed: FeedReference,
    /// Words that end the program, if any.
    #[serde(default)]
    pub end: Vec<String>,
    /// The language the control reads (`dialect::mill::language`: "fanuc", "haas",
    /// "linuxcnc", "centroid"), for reading its programs.
    pub language: String,
    /// Where G28 and G30 leave the programmed point (mm, in the work coordinate system at
    /// power-on), axis by axis; an axis not stated is unknown after the return.
    #[serde(default)]
    pub reference: Option<MillReference>,
}

/// Where the reference returns leave the tool.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MillReference {
    #[serde(default)]
    pub g28: Axes,
    #[serde(default)]
    pub g30: Axes,
}

/// X, Y, Z each stated or not (mm).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axes {
    pub x: Option<f64>,
    pub y: Option<f64>,
    pub z: Option<f64>,
}

impl MillProfile {
    pub fn built_in(name: &str) -> Option<MillProfile> {
        BUILT_IN
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, text)| MillProfile::from_toml(text).expect("built-in profiles are tested"))
    }

    pub fn from_toml(text: &str) -> Result<MillProfile, toml::de::Error> {
        toml::from_str(text)
    }

    pub fn names() -> Vec<&'static str> {
        BUILT_IN.iter().map(|(n, _)| *n).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_built_in_profile_parses_under_its_name() {
        for (name, text) in BUILT_IN {
            let p = MillProfile::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(&p.name, name);
        }
    }

    #[test]
    fn unknown_keys_are_refused() {
        let text = format!("{}\ncolour = 1\n", BUILT_IN[0].1);
        assert!(MillProfile::from_toml(&text).is_err());
    }
}
