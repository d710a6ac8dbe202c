//! The one-block multiple-pass thread cycle of Fanuc's FS15 program format, which Haas's `G76` and
//! (by inference, `docs/dialects/allen-bradley-g78.md`) Allen-Bradley's `G78` copy word for word:
//!
//! ```text
//! G76 X(U) Z(W) I K D F A P Q        Fanuc FS15 format, Haas (Haas also writes E for F)
//! G78 X Z I K D F|E A P              Allen-Bradley 9/Series
//! ```
//! X Z: the root at the thread's end; I: the radius at the start minus the radius at the end; K:
//! the thread height; D: the first depth (both radii); A: the tool's included angle; P1–P4: the
//! infeed (`Infeed`); Q: the start angle. What the block does not carry — finishing allowance,
//! minimum cut, finishing passes, the pull-out — each controller keeps in its own parameters
//! (`Setup`). This module holds what the three controllers share: the words' common checks
//! (each dialect calls those of its own words) and the lowering of a cycle into the model. The
//! Fanuc-family reader of the whole `G76` block is [`read_g76`]; Allen-Bradley's `G78` has its own.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::{Conventions, Line, Modal, Word};
use crate::machine::Machine;
use crate::post;
use crate::thread::{
    tan_deg, DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed as ModelInfeed, Job,
    Lead, PassPlan, Retract, ReturnPath, Side,
};
use crate::units::{Pos, Tolerance, Units};

/// The largest tool angle A (FS15: "0-120"; Haas: "0 to 120 degrees"; Allen-Bradley: "an integer
/// value from 0 to 120").
pub const MAX_TOOL_ANGLE: f64 = 120.0;

/// The tool assumed for chip areas when A0 (plunge infeed) says nothing of the tool's angle.
pub const PLUNGE_TOOL_ANGLE: f64 = 60.0;

/// P1–P4: "cutting amount constant, single edge / alternating, depth constant, single edge /
/// alternating" (FS15; Haas: "P1: single edge cutting, cutting amount constant …").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Infeed(u8);

impl Infeed {
    /// P1, the FS15 and Haas default.
    pub const SINGLE_EDGE_CONSTANT_AMOUNT: Infeed = Infeed(1);

    /// The P word's number, 1 to 4.
    pub fn number(self) -> u8 {
        self.0
    }

    /// P2 and P4 cut on both edges, alternating.
    pub fn alternating(self) -> bool {
        self.0.is_multiple_of(2)
    }

    /// P3 and P4 cut the same depth every pass; P1 and P2 the same chip area.
    pub fn constant_depth(self) -> bool {
        self.0 >= 3
    }

    /// The infeed with these properties.
    pub fn of(alternating: bool, constant_depth: bool) -> Infeed {
        Infeed(1 + u8::from(alternating) + 2 * u8::from(constant_depth))
    }
}

/// One cycle in the model's terms: mm, X as a radius, absolute.
#[derive(Clone, Copy, Debug)]
pub struct Cycle {
    pub span: Span,
    pub line: u32,
    /// Where the tool stands: the start and end of every pass's box.
    pub start: Pos,
    /// X Z: the root at the thread's end.
    pub end: Pos,
    /// I: the root's radius at the start minus at the end.
    pub taper: f64,
    /// K.
    pub height: f64,
    /// D.
    pub first: f64,
    /// A: included angle (degrees); 0 is a plunge.
    pub tool_angle: f64,
    pub infeed: Infeed,
    pub lead: f64,
    /// Q (degrees).
    pub phase_deg: f64,
}

/// A synchronised pull-out at the end of every pass, as a controller's parameters give it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PullOut {
    /// Its length along Z, in leads.
    pub leads: f64,
    /// Its angle from the Z axis (degrees).
    pub angle_deg: f64,
}

/// What the controller keeps outside the block, with the names its messages give them.
#[derive(Clone, Copy, Debug)]
pub struct Setup {
    pub controller: &'static str,
    /// Radial stock the finishing passes remove (mm).
    pub allowance: f64,
    /// e.g. "Setting 86 (thread finish allowance)".
    pub allowance_name: &'static str,
    /// The smallest rough increment of P1/P2 (mm).
    pub min_cut: f64,
    /// Passes at full depth after the rough passes.
    pub finish_passes: u32,
    /// The tool angle when the block has no A (degrees; 0: a plunge).
    pub tool_angle: f64,
    /// `None`: the pass leaves the thread straight.
    pub pull_out: Option<PullOut>,
    /// e.g. "the thread chamfer (Settings 95 and 96)".
    pub pull_out_name: &'static str,
}

/// A radius word that is unsigned and above zero (K, D), in mm.
/// Zero is a value within the program's resolution of it.
pub fn positive(modal: &Modal, w: &Word, what: &str) -> Result<f64> {
    let v = modal.value(w);
    if !modal.resolution().length().gt(modal.units.to_mm(v), 0.0) {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            w.span,
            format!(
                "{}{}: {what} is unsigned and must be above zero",
                w.letter as char, w.value
            ),
        ));
    }
    Ok(modal.units.to_mm(v))
}

/// A word that must be a whole number from `lo` to `hi`.
pub fn whole(w: &Word, lo: f64, hi: f64, what: &str) -> Result<f64> {
    if w.value.fract() != 0.0 || w.value < lo || w.value > hi {
        return Err(Diagnostic::error(
            Code::OutOfRange,
            w.span,
            format!(
                "{}{}: {what} must be a whole number from {lo} to {hi}",
                w.letter as char, w.value
            ),
        ));
    }
    Ok(w.value)
}

/// A word written without a decimal point, as the controller's manual asks (Haas's A and Q).
pub fn without_point(w: &Word, what: &str, example: &str) -> Result<()> {
    if w.has_dot {
        return Err(Diagnostic::error(
            Code::Syntax,
            w.span,
            format!(
                "{} ({what}) is written without a decimal point",
                w.letter as char
            ),
        )
        .with_hint(format!("for example {example}")));
    }
    Ok(())
}

/// The P word: 1 to 4, or `default` when it is absent (`None`: P is required, and its absence is
/// `missing`).
pub fn infeed(
    p: Option<&Word>,
    default: Option<Infeed>,
    missing: impl FnOnce() -> Diagnostic,
) -> Result<Infeed> {
    match (p, default) {
        (Some(p), _) => Ok(Infeed(whole(p, 1.0, 4.0, "the tool infeed P")? as u8)),
        (None, Some(d)) => Ok(d),
        (None, None) => Err(missing().with_hint(
            "P1/P2 constant amount, single/alternating edges; P3/P4 constant depth, single/alternating edges",
        )),
    }
}

/// The validated cycle as a machine-neutral job. Each pass: rapid to its infeed point, thread
/// parallel to the root line to Z (or the pull-out), rapid out to the start X, rapid back to the
/// start Z; the finishing passes at K; the tool ends at the start point.
pub fn lower(c: &Cycle, s: &Setup, modal: &Modal, warnings: &mut Vec<Diagnostic>) -> Result<Job> {
    let units = modal.units;
    // Programmed values compare at the program's resolution (docs/dialects/README.md).
    let res = modal.resolution();
    let (x_tol, length) = (res.x(), res.length());
    let geometry_error = |msg: String| Diagnostic::error(Code::Geometry, c.span, msg);
    let travel_z = c.end.z - c.start.z;
    if length.is_zero(travel_z) {
        return Err(geometry_error(
            "Z is the start point's Z: the thread has no length".into(),
        ));
    }
    if !length.lt(c.taper.abs(), travel_z.abs()) {
        return Err(geometry_error(format!(
            "the taper I changes the radius by {} over {} of Z: the cycle threads along Z",
            units.show(c.taper.abs()),
            units.show(travel_z.abs())
        )));
    }
    // I is "added to the X parameter to determine the start-point of the threading pass".
    let root_start = Pos::new(c.end.x + c.taper, c.start.z);
    let side = Side::of_cut(c.start.x, root_start.x, x_tol).ok_or_else(|| {
        geometry_error(
            "the start point's X is the thread's root: cannot tell an external from an internal thread"
                .into(),
        )
    })?;
    let outward = side.outward().x;
    let crest_x = root_start.x + outward * c.height;
    // A start point within the resolution of the top of the thread is on it.
    if x_tol.lt((c.start.x - crest_x) * outward, 0.0) {
        return Err(geometry_error(format!(
            "the start point X{} lies inside the thread (its top is at X{}): the return between passes would cut through it",
            post::number(modal.x_from_mm(c.start.x), 4, false),
            post::number(modal.x_from_mm(crest_x), 4, false)
        ))
        .with_hint("start the cycle from a point clear of the top of the thread"));
    }
    if !length.lt(s.allowance, c.height) {
        return Err(geometry_error(format!(
            "{} {} is not smaller than the thread height K {}",
            s.allowance_name,
            units.from_mm(s.allowance),
            units.from_mm(c.height)
        )));
    }
    let infeed = model_infeed(c.tool_angle, c.infeed, travel_z);
    let law = if c.infeed.constant_depth() {
        DepthLaw::Power {
            first: c.first,
            degression: 1.0,
            min_step: 0.0,
        }
    } else {
        DepthLaw::Power {
            first: c.first,
            degression: 2.0,
            min_step: s.min_cut,
        }
    };
    // The full-depth passes run exactly to (X, Z) from the start Z; shallower single-edge passes
    // sit back against the cutting direction by (K − d)·tan(A/2).
    let shift = infeed.axis(c.height);
    let crest_start = Pos::new(crest_x, c.start.z - shift);
    let crest_end = Pos::new(c.end.x + outward * c.height, c.end.z - shift);
    let exit = pull_out(c, s, units, travel_z, length)?;
    if !length.lt(c.first, c.height) {
        warnings.push(Diagnostic::warning(
            Code::Suspicious,
            c.span,
            format!(
                "the first depth D {} is not smaller than the thread height K {}: the whole thread is cut in one pass",
                units.from_mm(c.first),
                units.from_mm(c.height)
            ),
        ));
    }
    super::lead_warning(c.lead, travel_z, units, length, c.span, "check F", warnings);
    Ok(Job {
        line: c.line,
        span: c.span,
        controller: s.controller,
        units,
        start: c.start,
        geometry: Geometry {
            crest_start,
            crest_end,
            depth: c.height,
            side,
        },
        lead: Lead {
            phase_deg: c.phase_deg,
            ..Lead::constant(c.lead)
        },
        plan: PassPlan {
            law,
            finish_allowance: s.allowance,
            finish_passes: s.finish_passes,
        },
        infeed,
        finish_at: FinishPosition::Axis,
        tool_angle_deg: if c.tool_angle == 0.0 {
            PLUNGE_TOOL_ANGLE
        } else {
            c.tool_angle
        },
        entry: Entry::Direct,
        exit,
        retract: Retract {
            x: c.start.x,
            z: c.start.z,
        },
        return_path: ReturnPath::Box,
    })
}

/// Single edge: deeper passes move in the cutting direction, so the leading edge cuts; P2/P4
/// alternate about the full-depth position. A0 is a plunge whatever P says.
fn model_infeed(tool_angle: f64, p: Infeed, travel_z: f64) -> ModelInfeed {
    let (leading, trailing) = if travel_z < 0.0 {
        (Flank::Right, Flank::Left)
    } else {
        (Flank::Left, Flank::Right)
    };
    let half = tool_angle / 2.0;
    match (tool_angle == 0.0, p.alternating()) {
        (true, _) => ModelInfeed::Radial,
        (false, false) => ModelInfeed::Flank {
            flank: leading,
            angle_deg: half,
        },
        (false, true) => ModelInfeed::Alternating {
            first: leading,
            second: trailing,
            angle_deg: half,
        },
    }
}

fn pull_out(
    c: &Cycle,
    s: &Setup,
    units: Units,
    travel_z: f64,
    tolerance: Tolerance,
) -> Result<Exit> {
    let Some(p) = s.pull_out.filter(|p| p.leads > 0.0) else {
        return Ok(Exit::Straight);
    };
    let error = |msg: String| Diagnostic::error(Code::Geometry, c.span, msg);
    if !(p.angle_deg > 0.0 && p.angle_deg < 90.0) {
        return Err(error(format!(
            "the angle of {} ({}°) must lie between 0 and 90",
            s.pull_out_name, p.angle_deg
        )));
    }
    let length = p.leads * c.lead;
    if !tolerance.lt(length, travel_z.abs()) {
        return Err(error(format!(
            "{} ({} leads = {}) is not shorter than the thread ({})",
            s.pull_out_name,
            p.leads,
            units.from_mm(length),
            units.show(travel_z.abs())
        )));
    }
    Ok(Exit::PullOut {
        start_before: length,
        length,
        outward: length * tan_deg(p.angle_deg),
    })
}

/// The words of a Fanuc-family one-block `G76` (FS15 format, Haas) that differ between controllers.
#[derive(Clone, Copy, Debug)]
pub struct G76Words {
    /// Every letter the block may carry.
    pub letters: &'static [u8],
    /// The hint that lists them.
    pub format: &'static str,
    /// Haas's `F(E)`: E is the lead as F is. Otherwise E is refused (its meaning on Fanuc depends
    /// on the series).
    pub e_is_lead: bool,
    /// A and Q must be written without a decimal point (Haas: "Do not use a decimal point").
    pub no_point_a: bool,
    /// The alarm number K0 or D0 draws, where the manual gives one (Fanuc: "PS0062").
    pub alarm: Option<&'static str>,
}

/// A Fanuc-family one-block `G76` (X(U) Z(W) I K D F A P Q): the words as `words` allows them,
/// the rest from `setup`. The caller ([`super::fanuc_family`]) has checked that no other G code
/// shares the block.
#[allow(clippy::too_many_arguments)]
pub fn read_g76(
    conv: &Conventions,
    line: &Line,
    modal: &mut Modal,
    g76: Span,
    name: &str,
    words: &G76Words,
    setup: &Setup,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Job> {
    // The end point first: a block without one is most often the other G76 form, which the hint
    // names (its other words would draw a less helpful error).
    if line.word(b'X').or(line.word(b'U')).is_none()
        || line.word(b'Z').or(line.word(b'W')).is_none()
    {
        return Err(Diagnostic::error(
            Code::MissingWord,
            g76,
            format!(
                "{name} needs the thread's end: X (or U) and Z (or W), the root at the end of the thread"
            ),
        )
        .with_hint(two_block_hint(line, name)));
    }
    // (The family reader has checked the block's other G codes.)
    super::only_words(
        line,
        words.letters,
        &format!("a one-block {name}"),
        words.format,
    )?;
    let missing = |word: &str, what: &str| {
        Diagnostic::error(
            Code::MissingWord,
            g76,
            format!("{name} needs {word}: {what}"),
        )
    };
    let radius = |w: &Word, what: &str| -> Result<f64> {
        positive(modal, w, what).map_err(|e| match words.alarm {
            Some(number) => Diagnostic {
                message: format!("{name} alarm ({number}): {}", e.message),
                ..e
            },
            None => e,
        })
    };
    let height = radius(
        line.word(b'K')
            .ok_or_else(|| missing("K", "the thread height (radius)"))?,
        "the thread height K",
    )?;
    let first = radius(
        line.word(b'D')
            .ok_or_else(|| missing("D", "the depth of the first pass (radius)"))?,
        "the first depth D",
    )?;
    let tool_angle = match line.word(b'A') {
        Some(a) => {
            if words.no_point_a {
                without_point(a, "the tool angle", "A60")?;
            }
            whole(a, 0.0, MAX_TOOL_ANGLE, "the tool angle A")?
        }
        None => setup.tool_angle,
    };
    // P1 when P is absent (FS15: "default when P omitted"; Haas: "*P Single Edge Cutting").
    let infeed = infeed(
        line.word(b'P'),
        Some(Infeed::SINGLE_EDGE_CONSTANT_AMOUNT),
        || Diagnostic::error(Code::MissingWord, g76, format!("{name} needs P")),
    )?;
    let lead = lead(line, modal, g76, name, words.e_is_lead)?;
    let phase_deg = match line.word(b'Q') {
        Some(q) => super::fanuc_family::start_angle::read(q)?,
        None => 0.0,
    };
    let taper = line.word(b'I').map_or(0.0, |i| modal.length_mm(i));
    let start = super::start_point_unstated(
        modal,
        g76,
        name,
        &format!("position the tool at the cycle's start point (G00 X.. Z..) before {name}"),
    )?;
    let end = modal.target(conv, line, start)?;
    lower(
        &Cycle {
            span: g76,
            line: line.number,
            start,
            end,
            taper,
            height,
            first,
            tool_angle,
            infeed,
            lead,
            phase_deg,
        },
        setup,
        modal,
        warnings,
    )
}

/// A G76 without X/Z on a one-block control: most often the first block of the two-block form.
fn two_block_hint(line: &Line, name: &str) -> String {
    let two_block = line.word(b'K').is_none()
        && line.word(b'D').is_none()
        && (line.word(b'P').is_some() || line.word(b'R').is_some());
    if two_block {
        format!("this looks like the first block of the two-block {name} (Fanuc's standard format, GSK: {name} P(m)(r)(a) Q(Δdmin) R(d)); this controller reads {name} in one block — read the program with --controller fanuc")
    } else {
        format!("write {name} X.. Z.. K.. D.. F.. in one block")
    }
}

/// F (or Haas's E) on the block: the lead in the active units. The cycle's lead is required on
/// its own block: the F register may hold a feed rate by then.
fn lead(line: &Line, modal: &mut Modal, g76: Span, name: &str, e_is_lead: bool) -> Result<f64> {
    let (f, e) = (line.word(b'F'), line.word(b'E'));
    let word = match (f, e) {
        (Some(f), Some(e)) if e_is_lead => {
            let later = if e.span.start > f.span.start { e } else { f };
            return Err(Diagnostic::error(
                Code::Conflict,
                later.span,
                format!("F and E in one {name} block: the lead is given by either F or E"),
            ));
        }
        (_, Some(e)) if !e_is_lead => {
            return Err(Diagnostic::error(
                Code::Unsupported,
                e.span,
                format!(
                    "E on {name} means threads per inch or a precise lead depending on the series"
                ),
            )
            .with_hint("write the lead with F"))
        }
        (Some(w), _) | (None, Some(w)) => w,
        (None, None) => {
            return Err(Diagnostic::error(
                Code::MissingWord,
                g76,
                format!("{name} has no lead: F is missing"),
            )
            .with_hint(format!("write the lead on the {name} block itself")))
        }
    };
    let lead = positive(modal, word, "the lead")?;
    if word.letter == b'F' {
        modal.f_word = Some(modal.value(word));
    }
    modal.lead = Some(lead);
    Ok(lead)
}

/// The one-block cycle (`G76`, Allen-Bradley's `G78`) that may express `job` on a machine whose
/// parameters are `setup`, one per choice of the tool angle A and infeed P that gives the job's
/// infeed (the read-back check decides): a radial infeed is A0, a flank at θ is A = 2θ with P1/P3
/// (one edge) or P2/P4 (alternating), constant area or constant depth as the job's law.
/// `start_angle`: the block takes Q.
pub fn g76_candidates(
    machine: &Machine,
    name: &str,
    setup: &Setup,
    start_angle: bool,
    job: &Job,
) -> Vec<std::result::Result<Vec<String>, String>> {
    match choices(name, setup, start_angle, job) {
        Ok((first, list)) => list
            .into_iter()
            .map(|(a, p)| Ok(vec![text(machine, name, job, first, a, p)]))
            .collect(),
        Err(why) => vec![Err(why)],
    }
}

/// The first of [`g76_candidates`].
pub fn native_g76(
    machine: &Machine,
    name: &str,
    setup: &Setup,
    job: &Job,
) -> std::result::Result<Vec<String>, String> {
    g76_candidates(machine, name, setup, true, job).remove(0)
}

/// The first depth D and the (A, P) choices, or the property of the job the cycle cannot express.
fn choices(
    name: &str,
    setup: &Setup,
    start_angle: bool,
    job: &Job,
) -> std::result::Result<(f64, Vec<(u32, Infeed)>), String> {
    let g = &job.geometry;
    if g.side.is_face() {
        return Err(format!("{name} threads along Z, and this is a face thread"));
    }
    box_return_direct_entry(job, name)?;
    if job.lead.dlead != 0.0 || job.lead.starts != 1 {
        return Err(if start_angle {
            format!("{name} cuts one start of a constant lead (a start angle Q shifts it)")
        } else {
            format!("{name} cuts one start of a constant lead")
        });
    }
    if job.lead.phase_deg != 0.0 && !start_angle {
        return Err(format!("{name} has no start angle"));
    }
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9;
    if !close(job.plan.finish_allowance, setup.allowance)
        || job.plan.finish_passes != setup.finish_passes
    {
        return Err(format!(
            "{name} takes its finishing allowance and passes from the machine ({}: {} mm, {}), and this job has {} mm, {}",
            setup.allowance_name,
            post::number(setup.allowance, 4, false).trim_end_matches('.'),
            crate::text::count(setup.finish_passes as usize, "finishing pass", "finishing passes"),
            post::number(job.plan.finish_allowance, 4, false).trim_end_matches('.'),
            crate::text::count(job.plan.finish_passes as usize, "finishing pass", "finishing passes")
        ));
    }
    let (first, constant_depth) = match job.plan.law {
        DepthLaw::Power {
            first,
            degression: 2.0,
            ..
        } => (first, false),
        DepthLaw::Power {
            first,
            degression,
            min_step,
        } if degression == 1.0 && min_step == 0.0 => (first, true),
        _ => {
            return Err(format!(
                "{name} cuts a constant area (d·√n, the machine's minimum cut) or a constant depth only"
            ))
        }
    };
    let pull_out = s_pull_out(setup, job.lead.lead);
    if !same_exit(&job.exit, &pull_out) {
        return Err(match setup.pull_out.filter(|p| p.leads > 0.0) {
            Some(p) => format!(
                "{name}'s pull-out is {} ({} leads at {}° from Z), and this job's exit differs",
                setup.pull_out_name, p.leads, p.angle_deg
            ),
            None => format!(
                "{name} ends every pass straight at Z ({} is 0), and this job pulls out",
                setup.pull_out_name
            ),
        });
    }
    if job.finish_at != FinishPosition::Axis
        && setup.allowance > 0.0
        && !matches!(job.infeed, ModelInfeed::Radial)
    {
        return Err(format!("{name} finishes on the groove's axis"));
    }
    let travel = g.side.along(g.travel());
    let (leading, trailing) = if travel < 0.0 {
        (Flank::Right, Flank::Left)
    } else {
        (Flank::Left, Flank::Right)
    };
    let whole = |half: f64| -> std::result::Result<u32, String> {
        let a = 2.0 * half;
        if (a - a.round()).abs() > 1e-9 || a.round() > MAX_TOOL_ANGLE {
            return Err(format!(
                "{name}'s tool angle A is a whole number of degrees up to 120, and this job infeeds at {}° (a {}° tool)",
                post::number(half, 4, false),
                post::number(a, 4, false)
            ));
        }
        Ok(a.round() as u32)
    };
    let list = match job.infeed {
        ModelInfeed::Radial => vec![(0, Infeed::of(false, constant_depth))],
        ModelInfeed::Flank { flank, angle_deg } if flank == leading => {
            vec![(whole(angle_deg)?, Infeed::of(false, constant_depth))]
        }
        ModelInfeed::Alternating {
            first,
            second,
            angle_deg,
        } if first == leading && second == trailing => {
            vec![(whole(angle_deg)?, Infeed::of(true, constant_depth))]
        }
        _ => {
            return Err(format!(
                "{name} infeeds along the leading flank (P1/P3) or alternately on both (P2/P4), starting on the leading one, and this job otherwise"
            ))
        }
    };
    Ok((first, list))
}

/// The exit a setup's pull-out gives for `lead`.
fn s_pull_out(setup: &Setup, lead: f64) -> Exit {
    match setup.pull_out.filter(|p| p.leads > 0.0) {
        None => Exit::Straight,
        Some(p) => {
            let length = p.leads * lead;
            Exit::PullOut {
                start_before: length,
                length,
                outward: length * tan_deg(p.angle_deg),
            }
        }
    }
}

fn same_exit(a: &Exit, b: &Exit) -> bool {
    let close = |x: f64, y: f64| (x - y).abs() <= 1e-9;
    match (a, b) {
        (Exit::Straight, Exit::Straight) => true,
        (
            Exit::PullOut {
                start_before: s1,
                length: l1,
                outward: o1,
            },
            Exit::PullOut {
                start_before: s2,
                length: l2,
                outward: o2,
            },
        ) => close(*s1, *s2) && close(*l1, *l2) && close(*o1, *o2),
        _ => false,
    }
}

/// The block with tool angle `angle` and infeed `p`.
fn text(machine: &Machine, name: &str, job: &Job, first: f64, angle: u32, p: Infeed) -> String {
    let g = &job.geometry;
    let u = job.units;
    let nd = machine.decimals(u);
    let num = |mm: f64| post::number(u.from_mm(mm), nd, false);
    let full_offset = job.infeed.axis(g.depth);
    let root_end = Pos::new(
        g.crest_end.x + g.side.infeed().x * g.depth,
        g.crest_end.z + full_offset,
    );
    let x_end = if machine.diameter_x {
        root_end.x * 2.0
    } else {
        root_end.x
    };
    let mut block = format!(
        "{name} X{} Z{}",
        post::number(u.from_mm(x_end), nd, false),
        num(root_end.z)
    );
    if g.taper() != 0.0 {
        block.push_str(&format!(" I{}", num(g.taper())));
    }
    block.push_str(&format!(
        " K{} D{} F{} A{angle} P{}",
        num(g.depth),
        num(first),
        post::number(
            u.from_mm(job.lead.lead),
            if u == Units::Inch { 5 } else { 4 },
            false
        ),
        p.number()
    ));
    if job.lead.phase_deg != 0.0 {
        block.push_str(&format!(
            " Q{}",
            post::start_angle_count(job.lead.phase_deg)
        ));
    }
    block
}

/// What a box-returning cycle written in one or two blocks cannot express: a retract other than
/// the start point's X followed by a return to its Z, or an entry ramp (`name`: the cycle, for the
/// reason given).
pub(crate) fn box_return_direct_entry(job: &Job, name: &str) -> std::result::Result<(), String> {
    if job.return_path != ReturnPath::Box
        || job.retract
            != (Retract {
                x: job.start.x,
                z: job.start.z,
            })
    {
        return Err(
            format!("{name} retracts to the start point's X and returns to its Z after every pass, and this job does not"),
        );
    }
    if job.entry != Entry::Direct {
        return Err(format!("{name} has no entry ramp"));
    }
    Ok(())
}
