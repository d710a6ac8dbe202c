//! The lead's drift over the thread, judged against the thread's tolerance. A lead written in the
//! target's words (its lead word's decimals, or its grid) is not the job's; over the thread the
//! difference accumulates ([`LeadRounding`]). Its effect on the thread is a pitch-diameter
//! equivalent, `drift × cot(α/2)` (ISO 965-1's diametral equivalent of a pitch deviation, `fP =
//! 1.732·|ΔP|` for 60° threads), judged against a quarter of the medium class's pitch-diameter
//! tolerance for the thread's diameter and pitch, or against a limit the caller gives.

use super::LeadRounding;
use crate::diag::{Code, Diagnostic};
use crate::machine::Machine;
use crate::post;
use crate::thread::standard::tolerance::{self, ClassTolerance};
use crate::thread::standard::{Family, Surface};
use crate::thread::{Job, Side};
use crate::units::Units;

/// A drift smaller than this (program units) is no drift: the lead is written as it is.
const NO_DRIFT: f64 = 1e-10;

/// How far the lead may drift.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DriftRule {
    /// The largest drift accepted along the thread, in the units the cycle is written in (the
    /// converted program's: `--max-lead-drift`); `None`: a quarter of the medium class's
    /// pitch-diameter tolerance.
    pub max: Option<f64>,
    /// The units the source gave the lead in (the comment states the lead in them).
    pub source_units: Units,
}

impl DriftRule {
    pub fn new(source_units: Units) -> DriftRule {
        DriftRule {
            max: None,
            source_units,
        }
    }
}

/// What the drift is judged against.
#[derive(Clone, Debug, PartialEq)]
pub enum Limit {
    /// The caller's largest drift along the thread (program units).
    Given(f64),
    /// A quarter of the class's pitch-diameter tolerance; `form` says how the form was assumed.
    Class {
        tolerance: ClassTolerance,
        form: String,
    },
    /// No class is known for the thread (a face thread, a 55° form, a diameter outside the
    /// standard's ranges): the target's output resolution, along the thread.
    Resolution { why: String },
}

/// The lead's drift over one thread and its judgement.
#[derive(Clone, Debug, PartialEq)]
pub struct LeadDrift {
    pub rounding: LeadRounding,
    /// The flank angle the pitch-diameter equivalent is taken at (degrees).
    pub flank_deg: f64,
    /// `drift × cot(flank/2)`, program units.
    pub pitch_diameter: f64,
    pub limit: Limit,
}

impl LeadDrift {
    /// The drift of `rounding` (the lead of `job` as the target writes it) judged by `rule`.
    pub fn judge(rounding: LeadRounding, job: &Job, rule: &DriftRule) -> LeadDrift {
        let family = tolerance::assumed_family(job.tool_angle_deg, job.lead.lead);
        let flank_deg = family.map_or(job.tool_angle_deg, tolerance::flank_angle);
        let pitch_diameter = rounding.over_length / (flank_deg.to_radians() / 2.0).tan();
        let limit = match (rule.max, family) {
            (Some(v), _) => Limit::Given(v),
            (None, Some(f)) => class_limit(job, f),
            (None, None) => Limit::Resolution {
                why: format!(
                    "no class is known here for a {}° form",
                    degrees(job.tool_angle_deg)
                ),
            },
        };
        LeadDrift {
            rounding,
            flank_deg,
            pitch_diameter,
            limit,
        }
    }

    /// Whether the lead drifts at all.
    pub fn drifts(&self) -> bool {
        self.rounding.over_length > NO_DRIFT
    }

    /// The limit in program units, on the quantity it limits (the pitch-diameter equivalent for
    /// a class, the drift along the thread otherwise).
    pub fn limit_value(&self) -> f64 {
        match &self.limit {
            Limit::Given(v) => *v,
            Limit::Class { tolerance, .. } => self.rounding.units.from_mm(tolerance.td2) / 4.0,
            Limit::Resolution { .. } => self.rounding.resolution,
        }
    }

    /// Whether the drift is beyond the limit.
    pub fn over(&self) -> bool {
        let judged = match self.limit {
            Limit::Class { .. } => self.pitch_diameter,
            _ => self.rounding.over_length,
        };
        self.drifts() && judged > self.limit_value() + 1e-12
    }

    /// `0.0425 mm, a quarter of 6g's pitch-diameter tolerance for M30x2, ISO metric assumed from
    /// the 60° tool` (no parentheses: the text goes into a comment).
    fn limit_text(&self) -> String {
        let u = self.rounding.units;
        let value = format!(
            "{} {}",
            post::number(self.limit_value(), 7, false),
            u.name()
        );
        match &self.limit {
            Limit::Given(_) => format!("{value} along the thread, the limit given"),
            Limit::Class { tolerance, form } => format!(
                "{value}, a quarter of {}'s pitch-diameter tolerance for {}, {form}",
                tolerance.class, tolerance.thread
            ),
            Limit::Resolution { why } => {
                format!("{value} along the thread, the output resolution: {why}")
            }
        }
    }

    /// `drifts 0.0001722 inch over the thread's 1.378 inch, 0.0002983 inch on the pitch diameter
    /// at cot 30°`.
    fn amount(&self) -> String {
        let (r, u) = (&self.rounding, self.rounding.units.name());
        format!(
            "drifts {} {u} over the thread's {} {u}, {} {u} on the pitch diameter at cot {}°",
            post::number(r.over_length, 7, false),
            post::number(r.length, 4, false),
            post::number(self.pitch_diameter, 7, false),
            degrees(self.flank_deg / 2.0),
        )
    }

    /// The comment before the cycle: the lead as written, the drift, and the limit it is within.
    pub fn comment(&self, rule: &DriftRule) -> String {
        let r = &self.rounding;
        let from = rule.source_units.from_mm(r.units.to_mm(r.lead));
        format!(
            "threadcut: lead {} {} written as {} {} {}; limit {}",
            post::number(from, 6, false),
            rule.source_units.name(),
            post::number(r.written, 6, false),
            r.units.name(),
            self.amount(),
            self.limit_text()
        )
    }

    /// The warning a conversion gives for a lead that drifts within the limit.
    pub fn warning(&self, job: &Job) -> Diagnostic {
        Diagnostic::warning(
            Code::Suspicious,
            job.span,
            format!(
                "the lead is written as {} {}: it {}; limit {}",
                post::number(self.rounding.written, 6, false),
                self.rounding.units.name(),
                self.amount(),
                self.limit_text()
            ),
        )
    }

    /// The error for a drift beyond the limit.
    pub fn refusal(&self, target: &Machine, job: &Job) -> Diagnostic {
        Diagnostic::error(
            Code::Unsupported,
            job.span,
            format!(
                "{} writes this lead as {} {}: it {}, beyond the limit {}",
                target.name,
                post::number(self.rounding.written, 6, false),
                self.rounding.units.name(),
                self.amount(),
                self.limit_text()
            ),
        )
        .with_hint("the lead cannot be written closer in this controller's words and units: choose a controller that writes it or shorten the thread; `threadcut convert --max-lead-drift` accepts a larger drift (in the converted program's units)")
    }
}

/// A quarter of the medium class's pitch-diameter tolerance of the thread `job` cuts, its form
/// `family`: the nominal diameter is the major one, the crest of an external thread and the root
/// (crest + 2 × depth) of an internal one, at the thread's start; the pitch is the lead divided
/// by the starts.
fn class_limit(job: &Job, family: Family) -> Limit {
    let g = &job.geometry;
    let (surface, d) = match g.side {
        Side::External => (Surface::External, 2.0 * g.crest_start.x),
        Side::Internal => (Surface::Internal, 2.0 * (g.crest_start.x + g.depth)),
        Side::FaceFront | Side::FaceBack => {
            return Limit::Resolution {
                why: "a face thread has no class in the standards".into(),
            }
        }
    };
    let pitch = job.lead.lead / f64::from(job.lead.starts.max(1));
    let angle = degrees(job.tool_angle_deg);
    let flank = tolerance::flank_angle(family);
    let by_lead = if family == Family::Unified {
        " and its lead, a whole number of threads per inch"
    } else {
        ""
    };
    let form = if (flank - job.tool_angle_deg).abs() < 0.5 {
        format!("{} assumed from the {angle}° tool{by_lead}", family.name())
    } else {
        format!(
            "{} assumed: a {}° form, the cycle's tool angle {angle}° naming none{by_lead}",
            family.name(),
            degrees(flank)
        )
    };
    match tolerance::medium_pitch_tolerance(family, surface, d, pitch) {
        Some(tolerance) => Limit::Class { tolerance, form },
        None => Limit::Resolution {
            why: format!(
                "no {} class for a diameter of {} mm",
                family.name(),
                post::number(d, 3, false)
            ),
        },
    }
}

/// An angle in degrees to 0.1°, without a trailing point: `30`, `27.5`.
fn degrees(v: f64) -> String {
    format!("{}", (v * 10.0).round() / 10.0)
}
