//! `threadcut mill`'s options as one value, and what they make: the standard thread looked up, the
//! plan checked against the milling profile, the warnings, and the writers. The command line's
//! flags and the Python package's keywords fill a [`Request`] (each finding the profile its own
//! way: a built-in name, a file); both then call [`Request::prepare`], so that they mill the same
//! program from the same options.

use std::io::{self, Write};

use super::post::{self, Options};
use super::profile::MillProfile;
use super::{Comp, Direction, Hand, LeadIn, MillSpec, Plan, Side};
use crate::diag::{Code, Diagnostic, Result, Span};
use crate::thread::standard;
use crate::units::Units;

/// The rapid-move height above the thread's top when none is given (mm).
pub const DEFAULT_CLEARANCE_MM: f64 = 5.0;

/// What to mill, lengths in the program's units ([`Request::units`], by default the thread's
/// own: mm for metric, inch for Unified).
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// A standard thread's name (`M10x1.5`, `M12-6H`, `1/2-13 UNC-2B`).
    pub thread: String,
    pub side: Side,
    pub hand: Hand,
    /// Thread length, down from `start_z`.
    pub length: f64,
    /// Cutting diameter of the thread mill.
    pub tool_diameter: f64,
    /// Thread-form teeth on the tool, one pitch apart.
    pub teeth: u32,
    /// `None`: the climb-milling direction ([`super::climb`]).
    pub direction: Option<Direction>,
    /// Radial passes of equal chip area.
    pub passes: u32,
    /// Thread starts.
    pub starts: u32,
    pub comp: Comp,
    /// The thread's axis, `(X, Y)`.
    pub center: (f64, f64),
    /// Top of the thread.
    pub start_z: f64,
    /// Feed at the cutting edge, per minute.
    pub feed: f64,
    pub lead_in: LeadIn,
    /// Height above `start_z` for rapid moves; `None`: [`DEFAULT_CLEARANCE_MM`].
    pub clearance: Option<f64>,
    /// Program units; `None`: the thread's own.
    pub units: Option<Units>,
    /// The offset register of G41/G42 (the D word).
    pub d_register: Option<u32>,
    /// The milling controller's profile.
    pub profile: MillProfile,
}

impl Request {
    /// A request with the command's defaults: right hand, one tooth, one pass, one start,
    /// controller compensation, the axis at X0 Y0, the top at Z0, an arc lead-in, the climb
    /// direction, the default clearance, the thread's units, no D register.
    pub fn new(
        thread: &str,
        side: Side,
        length: f64,
        tool_diameter: f64,
        feed: f64,
        profile: MillProfile,
    ) -> Request {
        Request {
            thread: thread.to_string(),
            side,
            hand: Hand::Right,
            length,
            tool_diameter,
            teeth: 1,
            direction: None,
            passes: 1,
            starts: 1,
            comp: Comp::Controller,
            center: (0.0, 0.0),
            start_z: 0.0,
            feed,
            lead_in: LeadIn::Arc,
            clearance: None,
            units: None,
            d_register: None,
            profile,
        }
    }

    /// The thread looked up, the plan made and checked against the controller's rules. The
    /// errors name the command line's flags (`--length`), as the plan's own do.
    pub fn prepare(&self) -> Result<Milling> {
        let profile = self.profile.clone();
        let thread = standard::lookup(&self.thread)?;
        let (given_ext, given_int) = (thread.external.is_some(), thread.internal.is_some());
        if given_ext != given_int && given_ext != (self.side == Side::External) {
            let class = thread
                .external
                .or(thread.internal)
                .map(|l| l.class.to_string())
                .unwrap_or_default();
            return Err(Diagnostic::error(
                Code::Conflict,
                Span::default(),
                format!(
                    "--thread `{}` names class {class}, which is for {} threads, but --{} was given",
                    self.thread,
                    side_name(if given_ext {
                        Side::External
                    } else {
                        Side::Internal
                    }),
                    side_name(self.side)
                ),
            ));
        }
        let units = self.units.unwrap_or(thread.units);
        let mut warnings = Vec::new();
        if self.comp == Comp::Controller && profile.comp_needs_d && self.d_register.is_none() {
            // Legal on the control (G41/G42 keep the D in force), but worth a word before it runs.
            warnings.push(Warning {
                message: format!(
                    "no --d-register: {} writes G41/G42 without D, so the tool-radius offset in force is used",
                    profile.name
                ),
                hint: Some("name it with --d-register N, or use --comp none".to_string()),
            });
        }
        let spec = MillSpec {
            thread,
            side: self.side,
            hand: self.hand,
            length: units.to_mm(self.length),
            tool_diameter: units.to_mm(self.tool_diameter),
            teeth: self.teeth,
            direction: self.direction,
            passes: self.passes,
            starts: self.starts,
            comp: self.comp,
            center: (units.to_mm(self.center.0), units.to_mm(self.center.1)),
            start_z: units.to_mm(self.start_z),
            clearance: self
                .clearance
                .map_or(DEFAULT_CLEARANCE_MM, |c| units.to_mm(c)),
            feed: units.to_mm(self.feed),
            lead_in: self.lead_in,
            comp_feed: profile.comp_feed,
        };
        let plan = super::plan(&spec)?;
        super::profile_checks(&plan, &profile)?;
        warnings.extend(plan.warnings(units).into_iter().map(|message| Warning {
            message,
            hint: None,
        }));
        let options = Options {
            units,
            d_register: if self.comp == Comp::Controller {
                self.d_register
            } else {
                None
            },
        };
        Ok(Milling {
            plan,
            profile,
            options,
            warnings,
        })
    }
}

fn side_name(side: Side) -> &'static str {
    match side {
        Side::External => "external",
        Side::Internal => "internal",
    }
}

/// A prepared milling program: the plan, the profile it is written for, the output options and
/// what is worth a warning (said before the program is used; none of them stops it).
#[derive(Clone, Debug)]
pub struct Milling {
    pub plan: Plan,
    pub profile: MillProfile,
    pub options: Options,
    pub warnings: Vec<Warning>,
}

/// A finding about the program worth a word before it runs, and what to do about it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    pub message: String,
    pub hint: Option<String>,
}

impl Milling {
    /// `threadcut mill`: the G-code program ([`post::write_gcode`]).
    pub fn write_gcode(&self, out: &mut dyn Write) -> io::Result<()> {
        post::write_gcode(out, &self.plan, &self.profile, self.options)
    }

    /// `threadcut mill --format jsonl`: the plan's facts ([`post::plan_json`]) on the first line,
    /// then one object per move ([`post::write_jsonl`]).
    pub fn write_jsonl(&self, out: &mut dyn Write) -> io::Result<()> {
        let units = self.options.units;
        serde_json::to_writer(&mut *out, &post::plan_json(&self.plan, units))
            .map_err(io::Error::other)?;
        writeln!(out)?;
        post::write_jsonl(out, &self.plan, units)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn m10_nut() -> Request {
        let centroid = MillProfile::built_in("centroid").unwrap();
        Request::new("M10x1.5", Side::Internal, 12.0, 6.0, 300.0, centroid)
    }

    #[test]
    fn defaults_mill_the_thread_in_its_own_units() {
        let m = m10_nut().prepare().unwrap();
        assert_eq!(m.options.units, Units::Mm);
        assert_eq!(m.plan.pitch, 1.5);
        let mut out = Vec::new();
        m.write_gcode(&mut out).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(text.contains("G3") || text.contains("G2"), "{text}");
        // Centroid needs a D word with G41/G42: the request gave none.
        assert!(m.warnings[0]
            .message
            .starts_with("no --d-register: centroid"));
        assert_eq!(
            m.warnings[0].hint.as_deref(),
            Some("name it with --d-register N, or use --comp none")
        );
    }

    #[test]
    fn a_tool_wider_than_the_bore_is_refused() {
        // M10x1.5 internal: the bore is the minor diameter D1 = 10 − 1.0825·1.5 = 8.376 mm.
        let mut r = m10_nut();
        r.tool_diameter = 9.0;
        let e = r.prepare().unwrap_err();
        assert!(
            e.message.starts_with(
                "--tool-diameter: a 9 tool does not fit the M10x1.5 bore (minor diameter 8.3760)"
            ),
            "{}",
            e.message
        );
    }

    #[test]
    fn the_profile_writes_the_program() {
        let mut r = m10_nut();
        r.profile = MillProfile::built_in("linuxcnc-mill").unwrap();
        let mut out = Vec::new();
        r.prepare().unwrap().write_gcode(&mut out).unwrap();
        // LinuxCNC's arcs take I/J relative to the start only under G91.1, which its profile
        // writes once after the units word.
        assert!(String::from_utf8(out).unwrap().contains("G91.1"));
    }

    #[test]
    fn a_class_for_the_other_side_is_a_conflict() {
        let mut r = m10_nut();
        r.thread = "M10x1.5-6g".into();
        let e = r.prepare().unwrap_err();
        assert_eq!(e.code, Code::Conflict);
        assert!(e
            .message
            .contains("class 6g, which is for external threads, but --internal"));
    }

    #[test]
    fn inch_units_convert_the_lengths() {
        let mut r = m10_nut();
        r.units = Some(Units::Inch);
        r.length = 0.5;
        r.tool_diameter = 0.25;
        r.feed = 12.0;
        r.d_register = Some(1);
        let m = r.prepare().unwrap();
        // The D register is named; the arc lead-in below the bottom is said in inches.
        assert_eq!(m.warnings.len(), 1, "{:?}", m.warnings);
        assert!(m.warnings[0]
            .message
            .contains("inch below the thread bottom Z -0.5000"));
        let mut out = Vec::new();
        m.write_jsonl(&mut out).unwrap();
        let first: serde_json::Value =
            serde_json::from_str(String::from_utf8(out).unwrap().lines().next().unwrap()).unwrap();
        assert_eq!(first["kind"], "plan");
        assert_eq!(first["units"], "inch");
        // 1.5 mm pitch in inches.
        assert!((first["pitch"].as_f64().unwrap() - 1.5 / 25.4).abs() < 1e-12);
    }
}
