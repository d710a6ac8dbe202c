//! `threadcut check`: what a program will do wrong, before the spindle turns.
//!
//! The program streams through its dialect exactly as `expand` does, so the controller's own alarms
//! become check errors (with their line and column); then every cycle's [`Toolpath`] and simulated
//! [`Section`](super::Section) are checked against the blank and the machine:
//!
//! | check | severity | code |
//! | --- | --- | --- |
//! | the groove does not reach the thread's depth | error | E013 |
//! | a rapid move enters the blank (or moves in it other than straight out) | error | E011 |
//! | lead × spindle speed above the axis limit | error | E012 |
//! | lead above the controller's maximum | error | E014 |
//! | chamfer/tail-out longer than the thread | error | E007 |
//! | thread shorter than one lead | error | E007 |
//! | run-up before the blank too short for the feed to settle | warning | W003 |
//! | ridge or pitch-diameter error in the simulated groove, or no section | warning | W004 |
//! | spindle speed unknown, or constant surface speed (G96) | warning | W005 |
//!
//! Nothing here knows a controller: spindle words are read as the Fanuc family writes them (S, G96,
//! G97, S on the set-position block as the G96 speed clamp), which every dialect threadcut reads
//! shares.

use std::io::BufRead;

use crate::diag::{Code, Diagnostic, Severity};
use crate::gcode::reader::g_code;
use crate::gcode::Line;
use crate::machine::Machine;
use crate::program::{self, Error, Event};
use crate::thread::{Exit, Job, Side};
use crate::toolpath::{self, MotionKind, Toolpath};
use crate::units::{Pos, Units};

use super::{section, Tip, Tool};

/// The usual servo time constant of a lathe's Z axis (s): Fanuc's manuals quote 0.033 s.
pub const DEFAULT_SERVO_TIME_CONSTANT: f64 = 0.033;
/// The lead error accepted where the thread starts (1 %).
pub const DEFAULT_LEAD_ERROR: f64 = 0.01;
/// A rapid move that stays within this distance (mm) of the blank's surface does not enter it.
pub const CLEARANCE_TOLERANCE: f64 = 1e-6;

/// What the check assumes about the part and the tool.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CheckOptions {
    /// The blank's diameter, in the program's units at each cycle; `None`: the blank is the crest
    /// line of the cycle.
    pub stock_diameter: Option<f64>,
    /// Z of the blank's face on the thread's start side, in the program's units; `None`: the
    /// blank begins where the thread begins.
    pub stock_start: Option<f64>,
    /// The tool's tip, its sizes in the program's units at each cycle; its angle is the cycle's.
    pub tip: Tip,
    /// A program with control flow stops after this many executed blocks (`--max-blocks`).
    pub max_blocks: u64,
}

impl Default for CheckOptions {
    fn default() -> CheckOptions {
        CheckOptions {
            stock_diameter: None,
            stock_start: None,
            tip: Tip::Sharp,
            max_blocks: program::Options::default().max_blocks,
        }
    }
}

/// Everything the check found.
#[derive(Debug, Default)]
pub struct CheckReport {
    pub diagnostics: Vec<Diagnostic>,
    pub cycles: u32,
    pub lines: u32,
    /// The program stopped being read at a controller alarm (the last error).
    pub stopped: bool,
}

impl CheckReport {
    pub fn errors(&self) -> usize {
        self.diagnostics.iter().filter(|d| d.is_error()).count()
    }

    pub fn warnings(&self) -> usize {
        self.diagnostics.len() - self.errors()
    }
}

/// The spindle as the program has set it.
#[derive(Clone, Copy, Debug, Default)]
struct Spindle {
    /// S as last programmed (rpm under G97, surface speed under G96).
    s: Option<f64>,
    /// G96 constant surface speed is on.
    css: bool,
    /// The G96 speed clamp (S on the set-position block), rpm.
    clamp: Option<f64>,
}

impl Spindle {
    fn read(&mut self, line: &Line, set_position: u16) {
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

    /// Spindle speed (rpm) with the tool at radius `r` (mm).
    fn rpm(&self, units: Units, r: f64) -> Option<f64> {
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
}

/// Checks a whole program.
pub fn check<R: BufRead>(
    input: R,
    machine: &Machine,
    opts: &CheckOptions,
) -> Result<CheckReport, Error> {
    let set_position = crate::dialect::open(machine)
        .map_err(Error::Setup)?
        .conventions()
        .set_position;
    let mut report = CheckReport::default();
    let mut spindle = Spindle::default();
    let mut found = Vec::new();
    let run = program::Options {
        max_blocks: opts.max_blocks,
        ..program::Options::default()
    };
    let result = program::run_with(input, machine, &run, |_, ev| {
        match ev {
            Event::Plain { line, .. } | Event::Settings { line } => {
                spindle.read(line, set_position)
            }
            Event::Cycle { line, job, .. } => {
                spindle.read(line, set_position);
                check_cycle(&job, machine, opts, &spindle, &mut found);
            }
        }
        Ok(())
    });
    match result {
        Ok(summary) => {
            report.cycles = summary.cycles;
            report.lines = summary.lines;
            report.diagnostics = summary.warnings;
        }
        Err(Error::Input(alarm)) => {
            report.stopped = true;
            report.diagnostics.push(alarm);
        }
        Err(e) => return Err(e),
    }
    report.diagnostics.extend(found);
    report
        .diagnostics
        .sort_by_key(|d| (d.span.line, d.span.column, d.severity != Severity::Error));
    Ok(report)
}

/// All checks of one cycle.
pub fn check_cycle(
    job: &Job,
    machine: &Machine,
    opts: &CheckOptions,
    spindle_state: &impl SpindleSpeed,
    out: &mut Vec<Diagnostic>,
) {
    let span = job.span;
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    let g = &job.geometry;
    let axial = g.travel().z.abs();
    let lead = job.lead.lead;
    if let Some(max) = machine.limits.max_lead_mm {
        if lead > max {
            out.push(
                Diagnostic::error(
                    Code::LeadLimit,
                    span,
                    format!(
                        "the lead {} is beyond this controller's maximum {} ({})",
                        show(lead),
                        show(max),
                        units.name()
                    ),
                )
                .with_hint("check F: a lead written without its decimal point?"),
            );
        }
    }
    if axial < lead {
        out.push(
            Diagnostic::error(
                Code::Geometry,
                span,
                format!(
                    "the thread is {} long, shorter than one lead ({}): the tool turns less than one revolution along it",
                    show(axial),
                    show(lead)
                ),
            )
            .with_hint("check the thread's end Z and the lead"),
        );
    }
    if let Exit::PullOut { start_before, .. } = job.exit {
        if start_before >= axial {
            out.push(Diagnostic::error(
                Code::Geometry,
                span,
                format!(
                    "the chamfer (tail-out) starts {} before the thread's end, but the thread is only {} long",
                    show(start_before),
                    show(axial)
                ),
            ));
        }
    }
    let passes = match job.passes() {
        Ok(p) => p,
        Err(e) => return out.push(e),
    };
    let path = match toolpath::build_with(job, &passes) {
        Ok(p) => p,
        Err(e) => return out.push(e),
    };
    let blank = Blank::new(job, opts);
    if blank.before_face(blank.z_end) >= 0.0 {
        out.push(Diagnostic::error(
            Code::Geometry,
            span,
            format!(
                "the blank's face (Z{}) lies at or past the thread's end (Z{}): there is nothing to cut",
                show(blank.z_face),
                show(blank.z_end)
            ),
        ).with_hint("--stock-start names the face on the side where the thread starts"));
        return;
    }
    let tool = Tool {
        angle_deg: job.tool_angle_deg,
        tip: tip_in_mm(opts.tip, units),
    };
    match section(job, &passes, &tool, blank.stock_above) {
        Ok(sec) => form_checks(job, machine, &sec.groove, out),
        // The machine can still run the cycle; only the depth and form checks are lost.
        Err(e) => out.push(Diagnostic {
            code: Code::Form,
            severity: Severity::Warning,
            message: format!(
                "the groove cannot be simulated, so its depth and form are not checked: {}",
                e.message
            ),
            ..e
        }),
    }
    rapid_checks(job, &path, &blank, out);
    spindle_checks(job, machine, &path, &blank, spindle_state, out);
}

/// What the check needs of the spindle; the streaming check keeps it from the program's words.
pub trait SpindleSpeed {
    /// Spindle speed (rpm) with the tool at radius `r` (mm), if known.
    fn rpm_at(&self, units: Units, r: f64) -> Option<f64>;
    /// Constant surface speed is on.
    fn css(&self) -> bool;
}

impl SpindleSpeed for Spindle {
    fn rpm_at(&self, units: Units, r: f64) -> Option<f64> {
        self.rpm(units, r)
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

/// The blank in the XZ plane: between the face `z_face` and the thread's end, from the crest line
/// (or the stock's surface) into the part.
struct Blank {
    side: Side,
    /// Z of the face where the thread starts, and of the thread's end.
    z_face: f64,
    z_end: f64,
    /// The surface's radius at `z_face` and at `z_end`.
    x_face: f64,
    x_end: f64,
    /// Stock above the crest line (mm, at the thread's start), for the section.
    stock_above: f64,
    /// +1 when the thread runs toward −Z, −1 toward +Z.
    backward: f64,
}

impl Blank {
    fn new(job: &Job, opts: &CheckOptions) -> Blank {
        let g = &job.geometry;
        let units = job.units;
        let z_face = opts.stock_start.map_or(g.crest_start.z, |z| units.to_mm(z));
        let crest_at = |z: f64| {
            let dz = g.crest_end.z - g.crest_start.z;
            g.crest_start.x + (g.crest_end.x - g.crest_start.x) * (z - g.crest_start.z) / dz
        };
        let (x_face, x_end) = match opts.stock_diameter {
            Some(d) => {
                let r = units.to_mm(d) / 2.0;
                (r, r)
            }
            None => (crest_at(z_face), g.crest_end.x),
        };
        let stock_above = (x_face - crest_at(z_face)) * g.side.outward().x;
        Blank {
            side: g.side,
            z_face,
            z_end: g.crest_end.z,
            x_face,
            x_end,
            stock_above,
            backward: (g.crest_start.z - g.crest_end.z).signum(),
        }
    }

    /// The blank as a convex quadrilateral in (z, x), shrunk by `CLEARANCE_TOLERANCE`: half-planes
    /// `a·z + b·x ≤ c`.
    fn half_planes(&self) -> [(f64, f64, f64); 4] {
        let eps = CLEARANCE_TOLERANCE;
        let (z0, z1) = (self.z_face.min(self.z_end), self.z_face.max(self.z_end));
        // The surface line x = x_face + k·(z − z_face).
        let k = if self.z_end != self.z_face {
            (self.x_end - self.x_face) / (self.z_end - self.z_face)
        } else {
            0.0
        };
        let norm = (1.0 + k * k).sqrt();
        // External: x ≤ surface, x ≥ 0. Internal: x ≥ surface, x ≤ a far bound.
        let (surface, far) = match self.side {
            Side::External => (
                (
                    -k / norm,
                    1.0 / norm,
                    (self.x_face - k * self.z_face) / norm - eps,
                ),
                (0.0, -1.0, -eps),
            ),
            Side::Internal => (
                (
                    k / norm,
                    -1.0 / norm,
                    -(self.x_face - k * self.z_face) / norm - eps,
                ),
                (0.0, 1.0, self.x_face.max(self.x_end) + 1e4),
            ),
            // The blank is modelled for turned threads only: for a face thread no point lies
            // inside (0 ≤ −1), so no rapid is reported as entering it (docs/simulation.md).
            Side::FaceFront | Side::FaceBack => ((0.0, 0.0, -1.0), (0.0, 0.0, -1.0)),
        };
        [(-1.0, 0.0, -z0 - eps), (1.0, 0.0, z1 - eps), surface, far]
    }

    /// Whether a rapid move from `a` to `b` runs into the blank's interior. A move that starts
    /// inside (the tool at the end of its thread move, in the groove it has just cut) may only
    /// leave straight outward, along X; one that starts outside must not enter.
    fn entered_by(&self, a: Pos, b: Pos) -> bool {
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        for (pa, pb, c) in self.half_planes() {
            let fa = pa * a.z + pb * a.x - c;
            let d = pa * (b.z - a.z) + pb * (b.x - a.x);
            if d == 0.0 {
                if fa > 0.0 {
                    return false;
                }
            } else {
                let t = -fa / d;
                if d < 0.0 {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
        }
        if t0 >= t1 {
            return false;
        }
        let starts_inside = t0 <= 0.0;
        if starts_inside {
            let outward = (b.x - a.x) * self.side.outward().x;
            let along = (b.z - a.z).abs();
            return !(along <= CLEARANCE_TOLERANCE && outward > 0.0);
        }
        true
    }

    /// How far `z` lies before the face, along the thread (negative: inside the blank).
    fn before_face(&self, z: f64) -> f64 {
        (z - self.z_face) * self.backward
    }
}

fn form_checks(job: &Job, machine: &Machine, g: &super::GrooveReport, out: &mut Vec<Diagnostic>) {
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    let resolution = units.to_mm(machine.resolution(units));
    if g.depth_reached < g.depth_target - crate::thread::plan::DEPTH_TOLERANCE {
        out.push(Diagnostic::error(
            Code::DepthNotReached,
            job.span,
            format!(
                "the passes reach {} deep, the thread needs {} (radius)",
                show(g.depth_reached),
                show(g.depth_target)
            ),
        ));
    }
    if g.ridge > resolution {
        out.push(
            Diagnostic::warning(
                Code::Form,
                job.span,
                format!(
                    "a ridge {} high is left standing between passes; the groove's centre is {} deep",
                    show(g.ridge),
                    show(g.depth_at_axis)
                ),
            )
            .with_hint("finish on the groove's axis, or add a finishing pass there"),
        );
    }
    if let Some(e) = g.pitch_diameter_error {
        if e.abs() > resolution {
            out.push(
                Diagnostic::warning(
                    Code::Form,
                    job.span,
                    format!(
                        "the groove is cut {} at the pitch line: the pitch diameter comes out {} {} (diameter)",
                        if (e < 0.0) == (job.geometry.side == Side::External) { "wide" } else { "narrow" },
                        show(e.abs()),
                        if e < 0.0 { "under size" } else { "over size" }
                    ),
                )
                .with_hint("the passes do not finish on one groove axis (alternating infeed finishing off the axis?)"),
            );
        }
    }
}

fn rapid_checks(job: &Job, path: &Toolpath, blank: &Blank, out: &mut Vec<Diagnostic>) {
    let units = job.units;
    let x_word = |x: f64| length(units, x);
    let bad: Vec<_> = path
        .segments()
        .filter(|(from, m)| m.kind == MotionKind::Rapid && blank.entered_by(*from, m.to))
        .collect();
    if let Some((from, m)) = bad.first() {
        let more = bad.len() - 1;
        out.push(
            Diagnostic::error(
                Code::Collision,
                job.span,
                format!(
                    "pass {}: a rapid move from (radius {}, Z{}) to (radius {}, Z{}) runs through the blank{}",
                    m.pass,
                    x_word(from.x),
                    x_word(from.z),
                    x_word(m.to.x),
                    x_word(m.to.z),
                    if more > 0 {
                        format!(" ({more} more rapid moves do too)")
                    } else {
                        String::new()
                    }
                ),
            )
            .with_hint("start the cycle clear of the part: its start point must lie outside the blank, and flank infeed shifts each pass's start along Z"),
        );
    }
}

fn spindle_checks(
    job: &Job,
    machine: &Machine,
    path: &Toolpath,
    blank: &Blank,
    spindle: &impl SpindleSpeed,
    out: &mut Vec<Diagnostic>,
) {
    let units = job.units;
    let show = |mm: f64| length(units, mm);
    let threads: Vec<_> = path
        .segments()
        .filter_map(|(from, m)| match m.kind {
            MotionKind::Thread { lead, .. } => Some((from, m, lead)),
            _ => None,
        })
        .collect();
    let Some(&(first_from, _, _)) = threads.first() else {
        return;
    };
    if spindle.rpm_at(units, first_from.x).is_none() {
        out.push(
            Diagnostic::warning(
                Code::Spindle,
                job.span,
                "no spindle speed (S) is programmed before this cycle: the synchronised feed and the run-up were not checked",
            )
            .with_hint("program the spindle speed (G97 S..) before the cycle"),
        );
        return;
    }
    if spindle.css() {
        out.push(
            Diagnostic::warning(
                Code::Spindle,
                job.span,
                "the thread is cut under constant surface speed (G96): the spindle speed changes with X from pass to pass",
            )
            .with_hint("cut threads at a constant spindle speed: G97 S.."),
        );
    }
    // Synchronised feed: lead × rpm along each move's long axis.
    if let Some(max) = machine.limits.max_feed_mm_per_min {
        let worst = threads
            .iter()
            .filter_map(|&(from, m, lead)| {
                let r = from.x.abs().min(m.to.x.abs());
                spindle
                    .rpm_at(units, r)
                    .map(|rpm| (lead * rpm, rpm, m.pass))
            })
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((feed, rpm, pass)) = worst {
            if feed > max {
                out.push(
                    Diagnostic::error(
                        Code::FeedLimit,
                        job.span,
                        format!(
                            "pass {pass}: the synchronised feed is {:.0} mm/min (lead {} × {:.0} rpm), above the machine's {:.0} mm/min",
                            feed, show_lead(units, feed / rpm), rpm, max
                        ),
                    )
                    .with_hint(format!(
                        "lower the spindle speed to {:.0} rpm or less",
                        (max / (feed / rpm)).floor()
                    )),
                );
            }
        }
    }
    // Run-up: each pass's synchronised motion starts from rest; its lead is within the accepted
    // error only after δ1 = T1·V·(−1 − ln a), V = lead·rpm/60 (Fanuc's "incorrect threaded
    // length", the HUST manual's S1 = S·F/1800·(−1 − ln A)).
    let t1 = machine
        .limits
        .servo_time_constant_s
        .unwrap_or(DEFAULT_SERVO_TIME_CONSTANT);
    let a = machine
        .limits
        .thread_lead_error
        .unwrap_or(DEFAULT_LEAD_ERROR);
    let factor = -1.0 - a.ln();
    let mut worst: Option<(f64, f64, u32)> = None;
    for (i, &(from, m, lead)) in threads.iter().enumerate() {
        // The first synchronised move of each pass (and of each start) begins from rest.
        let starts_from_rest = i == 0 || threads[i - 1].1.to != from;
        if !starts_from_rest {
            continue;
        }
        let Some(rpm) = spindle.rpm_at(units, from.x) else {
            continue;
        };
        let needed = t1 * lead * rpm / 60.0 * factor;
        let available = blank.before_face(from.z);
        let short = needed - available;
        if short > CLEARANCE_TOLERANCE && worst.is_none_or(|w| short > w.0 - w.1) {
            worst = Some((needed, available, m.pass));
        }
    }
    if let Some((needed, available, pass)) = worst {
        out.push(
            Diagnostic::warning(
                Code::RunUp,
                job.span,
                format!(
                    "pass {pass}: {} but the synchronised feed needs {} {} of run-up to settle within {}% of the lead (servo time constant {t1} s)",
                    if available > CLEARANCE_TOLERANCE {
                        format!("the thread move starts {} {} before the blank", show(available), units.name())
                    } else if available < -CLEARANCE_TOLERANCE {
                        format!("the thread move starts {} {} inside the blank", show(-available), units.name())
                    } else {
                        "the thread move starts at the blank's face".to_string()
                    },
                    show(needed),
                    units.name(),
                    a * 100.0
                ),
            )
            .with_hint(format!(
                "start the cycle {} {} further from the part's face, or lower the spindle speed (--stock-start gives the face if it is not where the thread starts)",
                show(needed - available),
                units.name()
            )),
        );
    }
}

/// A tip whose sizes are in program units, in millimetres.
pub fn tip_in_mm(tip: Tip, units: Units) -> Tip {
    match tip {
        Tip::Sharp => Tip::Sharp,
        Tip::Radius { radius } => Tip::Radius {
            radius: units.to_mm(radius),
        },
        Tip::Flat { width } => Tip::Flat {
            width: units.to_mm(width),
        },
    }
}

fn show_lead(units: Units, lead: f64) -> String {
    length(units, lead)
}

/// A length for a message: program units, up to 4 decimals, no trailing zeros.
fn length(units: Units, mm: f64) -> String {
    let s = format!("{:.4}", units.from_mm(mm));
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.to_string()
    }
}
