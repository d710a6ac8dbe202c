//! `check --thread NAME`: the thread a program cuts, measured from its final passes and the tool's
//! form, judged against the named standard thread's class limits (docs/simulation.md, "Judging
//! against a standard").
//!
//! * **Measured** from the final passes (those at the final depth): the root diameter (external:
//!   minor, the lowest point reached; internal: major), the pitch diameter (where the groove they
//!   leave is half a pitch wide, from the tool's true form), the flank angles (as `sim` measures
//!   them, between 20 % and 60 % of the depth) and the lead.
//! * **Facts and assumptions**: the root and the lead follow from the program alone, so they are
//!   judged as facts (errors). The pitch diameter depends on the tool's tip: with `--nose-radius`
//!   or `--tip-flat` it is a fact too; without, the tool is assumed to have the standard's own root
//!   form (external: a nose radius of H/6, the rounded root of the basic profile; internal: a flat
//!   of P/8), which cuts the basic pitch diameter at the basic depth, and a finding is a warning
//!   that names it. Flank angles are judged where the cycle states its tool angle.
//! * **Every form**: [`Target`] ([`super::measure`]) holds what a form contributes (its angle and root tool, from its
//!   `Profile`; its limits on one side). A taper pipe thread (NPT, ISO 7-1 R/Rc) is judged at its
//!   gauge plane ([`super::taper`]); a tapered cut named against a parallel standard is an error.

use crate::diag::{Code, Diagnostic, Span};
use crate::sim::{Tip, Tool};
use crate::thread::standard::Surface;
use crate::thread::Side;
use crate::threads::Thread;
use crate::units::Units;

use super::measure::{measure, Judging, Measured, Target};
use super::{length, Note};

/// Flank angles within this of the standard's half angle (degrees) pass: ISO 965-1 and ASME B1.1
/// set no flank-angle tolerance of their own for the product, so threadcut flags a tool of another
/// angle, not the groove's measuring noise.
pub const FLANK_TOLERANCE_DEG: f64 = 0.5;

/// Judges one thread against the target; findings at the thread's block, notes for what was
/// assumed.
pub fn judge(t: &Thread, j: &Judging, out: &mut Vec<Diagnostic>, notes: &mut Vec<Note>) {
    let target = j.target;
    let job = &t.job;
    let span = job.span;
    let g = &job.geometry;
    let side = match g.side {
        Side::External => Surface::External,
        Side::Internal => Surface::Internal,
        Side::FaceFront | Side::FaceBack => {
            notes.push(Note::new(
                span,
                format!(
                    "a face thread is not judged against {} (standard threads are turned)",
                    target.name
                ),
            ));
            return;
        }
    };
    let tapered = g.taper().abs() > j.resolution;
    if tapered && target.thread.taper.is_none() {
        let per_length = 2.0 * g.taper().abs() / g.side.along(g.travel()).abs().max(1e-9);
        out.push(
            Diagnostic::error(
                Code::OutOfClass,
                span,
                format!(
                    "the thread is tapered ({per_length:.5} on diameter per unit length), and {} is a parallel thread",
                    target.name
                ),
            )
            .with_hint("a taper pipe thread is NPT, R or Rc; a parallel one is cut without a taper word"),
        );
        return;
    }
    let lead_checked = judge_lead(t, target, j.resolution, out);
    // The tool: the cycle's angle where it states one, the standard's otherwise; its tip as given,
    // or the standard's root form.
    let stated_angle =
        job.tool_angle_deg > 0.0 && matches!(t.origin, crate::threads::Origin::Cycle);
    let angle = if stated_angle {
        job.tool_angle_deg
    } else {
        target.angle_deg
    };
    let tip = j.tip.unwrap_or(target.root_tool);
    let m = measure(
        t,
        &Tool {
            angle_deg: angle,
            tip,
        },
        target.thread.pitch,
    );
    // A taper thread is judged at its gauge plane: its diameters move there.
    let gauge = match &target.thread.taper {
        Some(taper) => {
            let Some(gauge) = super::taper::judge(t, j, taper, side, &m, out, notes) else {
                judge_flanks(t, j, stated_angle, angle, side, m, out);
                return;
            };
            Some(gauge)
        }
        None => None,
    };
    let m = match &gauge {
        Some(gauge) => Measured {
            crest: m.crest + gauge.shift,
            root: m.root + gauge.shift,
            pitch_diameter: m.pitch_diameter.map(|pd| pd + gauge.shift),
            ..m
        },
        None => m,
    };
    let at = Cut {
        t,
        j,
        side,
        m,
        at_crest: match (&gauge, t.crest_known()) {
            (Some(_), true) => format!(
                "from the crest (Ø{} at the gauge plane)",
                length(target.thread.units, m.crest)
            ),
            (None, true) => format!("from the crest (Ø{})", length(target.thread.units, m.crest)),
            (_, false) => "below its first pass (the crest is not known)".to_string(),
        },
    };
    match &gauge {
        // The gauge plane rests on the face: a root judged there on an assumed face is a warning.
        Some(gauge) if !gauge.face_given => {
            let mut root = Vec::new();
            at.root(&mut root);
            out.extend(root.into_iter().map(|d| Diagnostic {
                severity: crate::diag::Severity::Warning,
                code: Code::OutOfClassAssumed,
                message: format!("{} (assumed: the part's face at Z0)", d.message),
                ..d
            }));
        }
        _ => at.root(out),
    }
    at.crest(out);
    if gauge.is_none() {
        at.pitch_diameter(&describe_tip(tip, target.thread.units), out);
    }
    if stated_angle {
        at.flanks(angle, out);
    }
    let unit = target.thread.units.name();
    let mut said = vec![match &gauge {
        Some(gauge) => format!("judged against {} {}", target.name, gauge.summary),
        None => format!("judged against {}", target.name),
    }];
    if j.tip.is_none() {
        said.push(format!(
            "the pitch diameter with {} (assumed: the standard's root form; --nose-radius or --tip-flat give the real tip)",
            describe_tip(tip, target.thread.units)
        ));
    }
    if !stated_angle {
        said.push(format!(
            "a {}° tool assumed (the program states none)",
            super::number(angle)
        ));
    }
    if !lead_checked {
        said.push("the lead not judged".into());
    }
    if let (Some(pd), None) = (m.pitch_diameter, &gauge) {
        said.push(format!(
            "cut: pitch diameter {}, {} diameter {} {unit}",
            at.show(pd),
            if side == Surface::External {
                "minor"
            } else {
                "major"
            },
            at.show(m.root)
        ));
        if let Some(measured) = what_is_measured(target, side, pd, j.wire) {
            said.push(measured);
        }
    }
    notes.push(Note::new(span, said.join("; ")));
}

/// What the machinist will read off the thread the program cuts: for an external thread the
/// measurement over wires (`wire`, else the best wire; H28's formula with the lead angle) next to
/// the class's window, and for both sides the change of the final depth that brings the pitch
/// diameter to the middle of the class's window. `None` when the class has no two-sided window.
pub fn what_is_measured(
    target: &Target,
    side: Surface,
    pd: f64,
    wire: Option<f64>,
) -> Option<String> {
    use crate::thread::standard::wires::over_wires;
    let t = target.thread;
    let (lo, hi) = (target.limits.pitch.min?, target.limits.pitch.max?);
    let u = t.units;
    let unit = u.name();
    let class = target.class_name();
    // Deeper moves an external thread's pitch diameter down 2 per 1 of depth, an internal one's up.
    let middle = (lo + hi) / 2.0;
    let deeper = match side {
        Surface::External => (pd - middle) / 2.0,
        Surface::Internal => (middle - pd) / 2.0,
    };
    let change = if deeper.abs() < 5e-7 {
        "it is at the window's middle".to_string()
    } else {
        format!(
            "{} {} {unit} {} (on the radius) brings it to the window's middle",
            if deeper > 0.0 { "cutting" } else { "stopping" },
            length(u, deeper.abs()),
            if deeper > 0.0 { "deeper" } else { "shallower" },
        )
    };
    let wires = t.wires(wire);
    let m_of = |e: f64| over_wires(&t.profile, t.pitch, t.pitch, e, wires.wire).corrected;
    Some(match side {
        Surface::External => format!(
            "over {} wires this program gives M = {} {unit}, {class} allows {}–{} (M with the lead angle, NBS H28); {change}",
            length(u, wires.wire),
            length(u, m_of(pd)),
            length(u, m_of(lo)),
            length(u, m_of(hi)),
        ),
        Surface::Internal => format!(
            "{class} allows a pitch diameter of {}–{} {unit}; {change}",
            length(u, lo),
            length(u, hi),
        ),
    })
}

/// The flank angles alone, where the rest cannot be judged (a taper thread whose gauge plane
/// cannot be placed).
fn judge_flanks(
    t: &Thread,
    j: &Judging,
    stated_angle: bool,
    angle: f64,
    side: Surface,
    m: Measured,
    out: &mut Vec<Diagnostic>,
) {
    if stated_angle {
        let at = Cut {
            t,
            j,
            side,
            m,
            at_crest: String::new(),
        };
        at.flanks(angle, out);
    }
}

/// One thread as measured, with what judging it needs.
struct Cut<'a> {
    t: &'a Thread,
    j: &'a Judging<'a>,
    side: Surface,
    m: Measured,
    /// Where the depths are measured from, for messages.
    at_crest: String,
}

impl Cut<'_> {
    /// A diameter in the standard's units.
    fn show(&self, mm: f64) -> String {
        length(self.j.target.thread.units, mm)
    }

    /// The root (external: minor; internal: major) against its limit: a fact, whatever the tool.
    fn root(&self, out: &mut Vec<Diagnostic>) {
        let (target, m, tol) = (self.j.target, &self.m, self.j.resolution);
        let (bad, limit, name, sign) = match self.side {
            Surface::External => match target.limits.minor.max {
                Some(max) if m.root > max + tol => (
                    format!("{} > {} max", self.show(m.root), self.show(max)),
                    max,
                    "minor",
                    1.0,
                ),
                _ => return,
            },
            Surface::Internal => match target.limits.major.min {
                Some(min) if m.root < min - tol => (
                    format!("{} < {} min", self.show(m.root), self.show(min)),
                    min,
                    "major",
                    -1.0,
                ),
                _ => return,
            },
        };
        out.push(
            Diagnostic::error(
                Code::OutOfClass,
                self.t.job.span,
                format!(
                    "{name} diameter {bad} for {}: the passes reach {} deep {}, {} needs at least {}",
                    target.name,
                    self.show(m.depth),
                    self.at_crest,
                    target.class_name(),
                    self.show(m.depth + sign * (m.root - limit) / 2.0)
                ),
            )
            .with_hint(format!(
                "cut deeper: the root is {} the standard's {} {name} diameter",
                if sign > 0.0 { "above" } else { "below" },
                if sign > 0.0 { "largest" } else { "smallest" }
            )),
        );
    }

    /// A cycle's crest outside the class's crest diameter (and not its basic value, which a
    /// program commonly measures from): the part, turned to the thread's crest, is not where the
    /// cycle measures its depths from.
    fn crest(&self, out: &mut Vec<Diagnostic>) {
        let (target, m, tol) = (self.j.target, &self.m, self.j.resolution);
        if !(self.t.crest_known() && matches!(self.t.origin, crate::threads::Origin::Cycle)) {
            return;
        }
        let (range, name, basic) = match self.side {
            Surface::External => (target.limits.major, "major", target.thread.basic.major),
            Surface::Internal => (target.limits.minor, "minor", target.thread.basic.minor),
        };
        let above = m.crest > range.max.unwrap_or(basic).max(basic) + tol;
        let below = m.crest < range.min.unwrap_or(basic).min(basic) - tol;
        if !(above || below) {
            return;
        }
        let limits = match (range.min, range.max) {
            (Some(a), Some(b)) => format!("{}–{}", self.show(a), self.show(b)),
            (Some(a), None) => format!("at least {}", self.show(a)),
            (None, Some(b)) => format!("at most {}", self.show(b)),
            (None, None) => String::new(),
        };
        out.push(
            Diagnostic::warning(
                Code::OutOfClassAssumed,
                self.t.job.span,
                format!(
                    "the cycle's crest Ø{} is not a {name} diameter of {} ({limits} {}): on a part turned to the thread's {name} diameter the cycle's depths are measured from a crest the part does not have{}",
                    self.show(m.crest),
                    target.name,
                    target.thread.units.name(),
                    if (self.side == Surface::External) == above {
                        ", and its first passes cut air"
                    } else {
                        ""
                    }
                ),
            )
            .with_hint("check the cycle's thread height (P(k), K) against its final X"),
        );
    }

    /// The pitch diameter against its limits: a fact with the tool given, else an assumption.
    fn pitch_diameter(&self, tool_words: &str, out: &mut Vec<Diagnostic>) {
        let (target, m, tol) = (self.j.target, &self.m, self.j.resolution);
        let unit = target.thread.units.name();
        let (code, make): (Code, fn(Code, Span, String) -> Diagnostic) = if self.j.tip.is_some() {
            (Code::OutOfClass, Diagnostic::error)
        } else {
            (Code::OutOfClassAssumed, Diagnostic::warning)
        };
        let assumed = if self.j.tip.is_some() {
            String::new()
        } else {
            format!(" (with {tool_words}: assumed, the standard's root form)")
        };
        let Some(pd) = m.pitch_diameter else {
            out.push(make(
                code,
                self.t.job.span,
                format!(
                    "the groove is nowhere half a pitch ({} {unit}) wide: no pitch diameter for {}{assumed}",
                    self.show(target.thread.pitch / 2.0),
                    target.name
                ),
            ));
            return;
        };
        let (lo, hi) = (target.limits.pitch.min, target.limits.pitch.max);
        let bad = match (lo, hi) {
            (_, Some(hi)) if pd > hi + tol => format!("{} > {} max", self.show(pd), self.show(hi)),
            (Some(lo), _) if pd < lo - tol => format!("{} < {} min", self.show(pd), self.show(lo)),
            _ => return,
        };
        // Deeper moves an external thread's pitch diameter down 2 per 1, an internal one's up.
        let sign = if self.side == Surface::External {
            1.0
        } else {
            -1.0
        };
        let need = |limit: f64| m.depth + sign * (pd - limit) / 2.0;
        let range = match (lo, hi) {
            (Some(lo), Some(hi)) => {
                let (a, b) = (need(hi), need(lo));
                format!("{}–{}", self.show(a.min(b)), self.show(a.max(b)))
            }
            (Some(l), None) | (None, Some(l)) => format!("about {}", self.show(need(l))),
            (None, None) => String::new(),
        };
        out.push(
            make(
                code,
                self.t.job.span,
                format!(
                    "pitch diameter {bad} for {}: the passes reach {} deep {}, {} needs {range}{assumed}",
                    target.name,
                    self.show(m.depth),
                    self.at_crest,
                    target.class_name(),
                ),
            )
            .with_hint(if self.j.tip.is_some() {
                format!("cut to a depth of {range} {unit}")
            } else {
                "give the tool's tip (--nose-radius or --tip-flat) to judge the pitch diameter as a fact".to_string()
            }),
        );
    }

    /// The flank angles against the thread's half angle, where the cycle states its tool.
    fn flanks(&self, angle: f64, out: &mut Vec<Diagnostic>) {
        let (target, m) = (self.j.target, &self.m);
        let half = target.angle_deg / 2.0;
        let worst = (m.flank_left_deg - half)
            .abs()
            .max((m.flank_right_deg - half).abs());
        if worst <= FLANK_TOLERANCE_DEG {
            return;
        }
        out.push(
            Diagnostic::error(
                Code::OutOfClass,
                self.t.job.span,
                format!(
                    "flank angles {:.1}° and {:.1}° (the cycle's {}° tool) for {}, whose flanks are {}° ± {}° ({}° thread)",
                    m.flank_left_deg,
                    m.flank_right_deg,
                    super::number(angle),
                    target.name,
                    super::number(half),
                    FLANK_TOLERANCE_DEG,
                    super::number(target.angle_deg)
                ),
            )
            .with_hint("the cycle's tool angle must be the thread's angle"),
        );
    }
}

/// The lead against the standard's pitch: a fact. `false` when it could not be judged.
fn judge_lead(t: &Thread, target: &Target, resolution: f64, out: &mut Vec<Diagnostic>) -> bool {
    let job = &t.job;
    if job.lead.dlead != 0.0 {
        return false;
    }
    let want = target.thread.pitch * f64::from(job.lead.starts.max(1));
    let got = job.lead.lead;
    let units = job.units;
    // A lead within half a least increment of the standard's is the best the program can write.
    if (got - want).abs() <= resolution / 2.0 + 1e-12 {
        return true;
    }
    let length_z = t.job.geometry.side.along(t.job.geometry.travel()).abs();
    let turns = length_z / got;
    let drift = (got - want).abs() * turns;
    let half = (target.angle_deg / 2.0).to_radians();
    let show = |mm: f64| length(units, mm);
    out.push(
        Diagnostic::error(
            Code::OutOfClass,
            job.span,
            format!(
                "lead {} {} ≠ {} {} for {}: over the thread's {} {} the error adds up to {} (about {} on the pitch diameter)",
                show(got),
                units.name(),
                show(want),
                units.name(),
                target.name,
                show(length_z),
                units.name(),
                show(drift),
                show(drift / half.tan())
            ),
        )
        .with_hint(match target.thread.tpi {
            Some(tpi) => format!(
                "{} threads per inch is a lead of {} {}",
                super::number(tpi),
                show(want),
                units.name()
            ),
            None => "program the standard's pitch as the lead".to_string(),
        }),
    );
    true
}

fn describe_tip(tip: Tip, units: Units) -> String {
    match tip {
        Tip::Sharp => "a sharp tool".into(),
        Tip::Radius { radius } => format!(
            "a nose radius of {} {}",
            length(units, radius),
            units.name()
        ),
        Tip::Flat { width } => format!("a tip flat of {} {}", length(units, width), units.name()),
    }
}
