//! CYCLE97, Sinumerik's thread-cutting cycle, lowered into the shared [`Job`]:
//!
//! ```text
//! CYCLE97(PIT, MPIT, SPL, FPL, DM1, DM2, APP, ROP, TDEP, FAL, IANG, NSP, NRC, NID, VARI, NUMT, _VRT)
//! ```
//!
//! Every rule below is a row of `docs/dialects/sinumerik.md` with its source and the test that
//! pins it.

use crate::diag::{Code, Diagnostic, Result, Span};
use crate::gcode::{Line, Modal};
use crate::thread::standard::iso_coarse_pitch;
use crate::thread::{
    DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassPlan, Retract,
    ReturnPath, Side, StartIndexing,
};
use crate::units::Pos;

/// The parameters, in the order of the call.
pub(super) const NAMES: [&str; 17] = [
    "PIT", "MPIT", "SPL", "FPL", "DM1", "DM2", "APP", "ROP", "TDEP", "FAL", "IANG", "NSP", "NRC",
    "NID", "VARI", "NUMT", "_VRT",
];

const PIT: usize = 0;
const MPIT: usize = 1;
const SPL: usize = 2;
const FPL: usize = 3;
const DM1: usize = 4;
const DM2: usize = 5;
const APP: usize = 6;
const ROP: usize = 7;
const TDEP: usize = 8;
const FAL: usize = 9;
const IANG: usize = 10;
const NSP: usize = 11;
const NRC: usize = 12;
const NID: usize = 13;
const VARI: usize = 14;
const NUMT: usize = 15;
const VRT: usize = 16;

/// The lift-off above the thread's diameter when `_VRT` is 0 or left out: 1 mm whatever the
/// system of units (840D sl Programming Manual, Job planning, 02/2011, p. 811, `_VRT`: "0 = intern
/// wird ein Abhebweg von 1 mm unabhängig vom Maßsystem inch/metrisch verwendet").
const DEFAULT_LIFT_MM: f64 = 1.0;

/// The included angle threadcut assumes for chip areas: CYCLE97 does not know its tool.
const TOOL_ANGLE_DEG: f64 = 60.0;

/// A CYCLE97 call: each parameter's value (program units, as written) and where it is written;
/// `None` for a parameter left empty or left out (the cycle reads it as 0).
pub(super) struct Call {
    /// The cycle's name in the block.
    pub name: Span,
    pub args: [Option<(f64, Span)>; 17],
}

impl Call {
    fn value(&self, i: usize) -> f64 {
        self.args[i].map_or(0.0, |(v, _)| v)
    }

    /// Where parameter `i` is written, or the cycle's name when it is not.
    fn span(&self, i: usize) -> Span {
        self.args[i].map_or(self.name, |(_, s)| s)
    }

    fn error(&self, i: usize, code: Code, message: String) -> Diagnostic {
        Diagnostic::error(code, self.span(i), message)
    }

    /// A parameter that counts something: a whole number, at least `min`.
    fn count(&self, i: usize, min: u32, what: &str) -> Result<u32> {
        let v = self.value(i);
        if v.fract() != 0.0 || v < f64::from(min) || v > f64::from(u32::MAX) {
            return Err(self.error(
                i,
                Code::OutOfRange,
                format!(
                    "{} {} is not a {what}: a whole number, at least {min}",
                    NAMES[i], v
                ),
            ));
        }
        Ok(v as u32)
    }

    /// A length written without a sign (APP, ROP, TDEP, FAL, _VRT).
    fn unsigned(&self, i: usize) -> Result<f64> {
        let v = self.value(i);
        if v < 0.0 {
            return Err(self
                .error(
                    i,
                    Code::OutOfRange,
                    format!("{} {} is negative", NAMES[i], v),
                )
                .with_hint("CYCLE97 takes this length without a sign"));
        }
        Ok(v)
    }
}

/// What CYCLE97 needs from the program around it.
pub(super) struct State {
    /// Whether a tool offset (a cutting edge D) is active.
    pub offset_active: bool,
}

/// Reads a CYCLE97 call into a job, raising the cycle's alarms and threadcut's own errors at
/// the parameter they concern.
pub(super) fn lower(
    call: &Call,
    line: &Line,
    modal: &Modal,
    state: &State,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Job> {
    if !state.offset_active {
        return Err(Diagnostic::error(
            Code::Conflict,
            call.name,
            "CYCLE97 alarm 61000 \"No tool offset active\"",
        )
        .with_hint("select a cutting edge (D1) before the cycle: D0 deselects the tool offset"));
    }
    let units = modal.units;
    // Programmed lengths compare at the program's resolution (docs/dialects/README.md): one
    // increment of the written value (DM1 and DM2 are diameters whatever X's mode).
    let tol = modal.resolution().length();
    let lead = pitch(call, modal)?;
    let side = machining_type(call)?;
    let constant_area = call.value(VARI) >= 3.0;
    let outline = Outline::read(call, modal)?;
    let lengths = Lengths::read(call, modal)?;
    let passes = Passes::read(call)?;
    let lift = lift(call, modal)?;
    // DM1 and DM2 as written: even one increment between them is a taper the program states.
    let infeed = infeed(call, outline.length(), outline.r1 != outline.r2, warnings)?;
    let path = outline.path(&lengths, &infeed, side, lift);
    let law = depth_law(constant_area, lengths.tdep - lengths.fal, passes.nrc);
    super::super::lead_warning(
        lead,
        path.z1 - path.z0,
        units,
        tol,
        call.span(PIT),
        "check PIT (the lead, in program units)",
        warnings,
    );
    let start = start_point(call, modal, &path.retract, warnings);
    Ok(Job {
        line: line.number,
        span: call.name,
        controller: "sinumerik",
        units,
        start,
        geometry: Geometry {
            crest_start: path.crest_start,
            crest_end: path.crest_end,
            depth: lengths.tdep,
            side,
        },
        lead: Lead {
            starts: passes.numt,
            phase_deg: passes.nsp,
            indexing: StartIndexing::Angle,
            ..Lead::constant(lead)
        },
        plan: PassPlan {
            law,
            finish_allowance: lengths.fal,
            // The finishing allowance in one cut, then NID idle passes at full depth.
            finish_passes: 1 + passes.nid,
        },
        infeed,
        finish_at: FinishPosition::Axis,
        tool_angle_deg: TOOL_ANGLE_DEG,
        entry: Entry::Direct,
        exit: Exit::Straight,
        retract: path.retract,
        return_path: ReturnPath::BoxAtRetract,
    })
}

/// The side from VARI: 1 and 3 external, 2 and 4 internal, anything else alarm 61002.
fn machining_type(call: &Call) -> Result<Side> {
    match call.value(VARI) {
        v if v == 1.0 || v == 3.0 => Ok(Side::External),
        v if v == 2.0 || v == 4.0 => Ok(Side::Internal),
        v => {
            Err(call
                .error(
                    VARI,
                    Code::OutOfRange,
                    format!("CYCLE97 alarm 61002 \"Machining type incorrectly defined\": VARI {v}"),
                )
                .with_hint("VARI is 1 (external, constant infeed), 2 (internal, constant infeed), 3 (external, constant cutting cross-section) or 4 (internal, constant cutting cross-section)"))
        }
    }
}

/// The programmed thread, in mm: Z of its start (SPL) and end (FPL), its radii there (DM1, DM2).
struct Outline {
    spl: f64,
    fpl: f64,
    r1: f64,
    r2: f64,
}

impl Outline {
    /// Reads SPL, FPL, DM1 and DM2: each diameter must be positive, FPL must differ from SPL,
    /// and the taper may be at most 45° (steeper is a face thread, which threadcut does not read).
    fn read(call: &Call, modal: &Modal) -> Result<Outline> {
        let units = modal.units;
        let mm = |v: f64| units.to_mm(v);
        let tol = modal.resolution().length();
        // Geometry, in mm: Z of the thread's start and end, radii there.
        let (spl, fpl) = (mm(call.value(SPL)), mm(call.value(FPL)));
        let diameter = |i: usize| -> Result<f64> {
            let v = call.value(i);
            if !tol.gt(mm(v), 0.0) {
                return Err(call
                    .error(
                        i,
                        Code::OutOfRange,
                        format!("{} {} is not a thread diameter", NAMES[i], v),
                    )
                    .with_hint("DM1 and DM2 are the thread's diameters at SPL and FPL (an internal thread's: the tap-hole diameter)"));
            }
            Ok(mm(v) / 2.0)
        };
        let (r1, r2) = (diameter(DM1)?, diameter(DM2)?);
        let length = fpl - spl;
        if tol.is_zero(length) {
            return Err(call.error(
                FPL,
                Code::Geometry,
                format!(
                    "FPL {} equals SPL: the thread has no length",
                    call.value(FPL)
                ),
            ));
        }
        if tol.gt((r2 - r1).abs(), length.abs()) {
            return Err(call
                .error(
                    DM2,
                    Code::Unsupported,
                    format!(
                        "DM1 {} and DM2 {} over {} along Z make a taper steeper than 45°: CYCLE97 then cuts a face thread, which threadcut does not read",
                        call.value(DM1),
                        call.value(DM2),
                        units.show(length.abs())
                    ),
                )
                .with_hint("threadcut reads CYCLE97's longitudinal threads (a taper angle of 45° or less)"));
        }
        Ok(Outline { spl, fpl, r1, r2 })
    }

    /// FPL − SPL: the thread's signed length along Z.
    fn length(&self) -> f64 {
        self.fpl - self.spl
    }

    /// The path the cycle cuts: from the run-in path APP before SPL to the run-out path ROP past
    /// FPL, along the taper line through (SPL, DM1) and (FPL, DM2), and its start point.
    fn path(&self, lengths: &Lengths, infeed: &Infeed, side: Side, lift: f64) -> Path {
        let Outline { spl, fpl, r1, r2 } = *self;
        let length = self.length();
        let dir = length.signum();
        let slope = (r2 - r1) / length;
        let radius_at = |z: f64| r1 + slope * (z - spl);
        let (z0, z1) = (spl - dir * lengths.app, fpl + dir * lengths.rop);
        // Flank infeed: the full-depth passes run on the programmed thread; shallower ones start
        // behind, by (TDEP − depth)·tan(IANG).
        let full_offset = infeed.axis(lengths.tdep);
        let crest_start = Pos::new(radius_at(z0), z0 - full_offset);
        let crest_end = Pos::new(radius_at(z1), z1 - full_offset);
        // The start point: the lift-off above the thread's outermost crest (its innermost, inside),
        // at the start of the run-in path.
        let outward = side.outward().x;
        let crest_out = if outward > 0.0 {
            radius_at(z0).max(radius_at(z1))
        } else {
            radius_at(z0).min(radius_at(z1))
        };
        let retract = Retract {
            x: crest_out + outward * lift,
            z: z0,
        };
        Path {
            z0,
            z1,
            crest_start,
            crest_end,
            retract,
        }
    }
}

/// Where the cycle cuts, in mm: Z at the start of the run-in path and the end of the run-out
/// path, the crest there, and the start point.
struct Path {
    z0: f64,
    z1: f64,
    crest_start: Pos,
    crest_end: Pos,
    retract: Retract,
}

/// The lengths written without a sign, in mm: the run-in and run-out paths, the thread depth
/// and the finishing allowance.
struct Lengths {
    app: f64,
    rop: f64,
    tdep: f64,
    fal: f64,
}

impl Lengths {
    /// Reads APP, ROP, TDEP and FAL (none negative): TDEP must not be 0, FAL must be smaller
    /// than TDEP.
    fn read(call: &Call, modal: &Modal) -> Result<Lengths> {
        let mm = |v: f64| modal.units.to_mm(v);
        let tol = modal.resolution().length();
        let (app, rop) = (mm(call.unsigned(APP)?), mm(call.unsigned(ROP)?));
        let tdep = mm(call.unsigned(TDEP)?);
        if tol.is_zero(tdep) {
            return Err(call.error(
                TDEP,
                Code::MissingWord,
                "TDEP, the thread depth, is 0 or missing".into(),
            ));
        }
        let fal = mm(call.unsigned(FAL)?);
        if !tol.lt(fal, tdep) {
            return Err(call.error(
                FAL,
                Code::Geometry,
                format!(
                    "the finishing allowance FAL {} is not smaller than the thread depth TDEP {}",
                    call.value(FAL),
                    call.value(TDEP)
                ),
            ));
        }
        Ok(Lengths {
            app,
            rop,
            tdep,
            fal,
        })
    }
}

/// The counts of the cycle's passes and turns, and the start angle.
struct Passes {
    nrc: u32,
    nid: u32,
    numt: u32,
    nsp: f64,
}

impl Passes {
    /// Reads NRC (at least 1), NID and NUMT (0 counts as 1 turn), then NSP, a start angle from 0
    /// to below 360°.
    fn read(call: &Call) -> Result<Passes> {
        let nrc = call.count(NRC, 1, "number of roughing cuts")?;
        let nid = call.count(NID, 0, "number of idle passes")?;
        let numt = call.count(NUMT, 0, "number of thread turns")?.max(1);
        let nsp = call.value(NSP);
        if !(0.0..360.0).contains(&nsp) {
            return Err(call
                .error(
                    NSP,
                    Code::OutOfRange,
                    format!("NSP {nsp} is not a start angle"),
                )
                .with_hint(
                    "NSP is the spindle angle of the first thread turn's start, 0 to 359.9999 degrees",
                ));
        }
        Ok(Passes {
            nrc,
            nid,
            numt,
            nsp,
        })
    }
}

/// The lift-off in mm from `_VRT` (no sign): 1 mm when 0 or left out.
fn lift(call: &Call, modal: &Modal) -> Result<f64> {
    Ok(match modal.units.to_mm(call.unsigned(VRT)?) {
        v if modal.resolution().length().gt(v, 0.0) => v,
        _ => DEFAULT_LIFT_MM,
    })
}

/// The depth law of the rough cuts from VARI: constant infeed (1, 2) or constant cutting
/// cross-section (3, 4), over NRC cuts of `rough` (TDEP − FAL).
fn depth_law(constant_area: bool, rough: f64, nrc: u32) -> DepthLaw {
    if constant_area {
        // Constant cutting cross-section: d_n = (TDEP − FAL)·√(n/NRC).
        DepthLaw::Power {
            first: rough / f64::from(nrc).sqrt(),
            degression: 2.0,
            min_step: 0.0,
        }
    } else {
        // Constant infeed: NRC equal steps.
        DepthLaw::Power {
            first: rough / f64::from(nrc),
            degression: 1.0,
            min_step: 0.0,
        }
    }
}

/// Where the tool stands before the cycle; when that is not known, a warning, and the cycle's
/// start point instead.
fn start_point(
    call: &Call,
    modal: &Modal,
    retract: &Retract,
    warnings: &mut Vec<Diagnostic>,
) -> Pos {
    match modal.position.known() {
        Some(p) => p,
        None => {
            warnings.push(
                Diagnostic::warning(
                    Code::UnknownPosition,
                    call.name,
                    format!(
                        "the tool's {} before CYCLE97 {} not known: its G0 to the cycle's start point is shown from that start point",
                        modal.position.unknown_axes().join(" and "),
                        if modal.position.unknown_axes().len() == 1 { "is" } else { "are" }
                    ),
                )
                .with_hint("position the tool with G0 X.. Z.. before the cycle to see the whole approach"),
            );
            Pos::new(retract.x, retract.z)
        }
    }
}

/// The lead in mm from PIT or MPIT (alarm 61001 when neither or both-and-different).
fn pitch(call: &Call, modal: &Modal) -> Result<f64> {
    let alarm = |i: usize, detail: String| {
        call.error(
            i,
            Code::OutOfRange,
            format!("CYCLE97 alarm 61001 \"Thread pitch incorrectly defined\": {detail}"),
        )
        .with_hint("program the lead in PIT (program units, without a sign), or the size of an ISO metric coarse thread M3 to M60 in MPIT")
    };
    let (pit, mpit) = (call.value(PIT), call.value(MPIT));
    if pit < 0.0 {
        return Err(alarm(PIT, format!("PIT {pit} is negative")));
    }
    let from_size = if mpit != 0.0 {
        match iso_coarse_pitch(mpit).filter(|_| (3.0..=60.0).contains(&mpit)) {
            Some(p) => Some(p),
            None => {
                return Err(alarm(
                    MPIT,
                    format!("MPIT {mpit} is not an ISO metric coarse thread size from M3 to M60"),
                ))
            }
        }
    } else {
        None
    };
    let from_pit = (pit != 0.0).then(|| modal.units.to_mm(pit));
    match (from_pit, from_size) {
        (None, None) => Err(alarm(PIT, "PIT and MPIT are both empty or 0".to_string())),
        (Some(p), None) | (None, Some(p)) => Ok(p),
        (Some(p), Some(q)) => {
            // The same pitch within the program's resolution (0.0001 mm or 0.00001 inch).
            let tolerance = modal.units.to_mm(match modal.units {
                crate::units::Units::Mm => 1e-4,
                crate::units::Units::Inch => 1e-5,
            }) / 2.0;
            if (p - q).abs() <= tolerance {
                Ok(q)
            } else {
                Err(alarm(
                    MPIT,
                    format!(
                        "PIT {pit} and MPIT {mpit} (M{mpit}: pitch {q} mm) contradict each other"
                    ),
                ))
            }
        }
    }
}

/// The infeed from IANG's value and sign: 0 radial; positive along one flank; negative
/// alternating on both flanks, except on a taper, where the cycle infeeds along one flank.
fn infeed(call: &Call, length: f64, taper: bool, warnings: &mut Vec<Diagnostic>) -> Result<Infeed> {
    let iang = call.value(IANG);
    if iang == 0.0 {
        return Ok(Infeed::Radial);
    }
    let angle = iang.abs();
    if angle >= 90.0 {
        return Err(call.error(
            IANG,
            Code::OutOfRange,
            format!("IANG {iang}: the infeed angle must be below 90°"),
        ));
    }
    if angle > TOOL_ANGLE_DEG / 2.0 {
        warnings.push(
            Diagnostic::warning(
                Code::Suspicious,
                call.span(IANG),
                format!("IANG {iang} is more than half the flank angle of a 60° insert"),
            )
            .with_hint("infeed along the flanks at most half the tool's flank angle (30° for ISO metric and unified threads)"),
        );
    }
    // Deeper passes move in the cutting direction: the leading edge cuts, the trailing edge
    // follows the rear flank.
    let flank = if length < 0.0 {
        Flank::Right
    } else {
        Flank::Left
    };
    Ok(if iang > 0.0 || taper {
        Infeed::Flank {
            flank,
            angle_deg: angle,
        }
    } else {
        let second = match flank {
            Flank::Left => Flank::Right,
            _ => Flank::Left,
        };
        Infeed::Alternating {
            first: flank,
            second,
            angle_deg: angle,
        }
    })
}

/// The CYCLE97 calls that may express `job` (the read-back check decides): the thread from SPL to
/// FPL without run-in or run-out paths (APP = ROP = 0), the crest diameters DM1/DM2 at its ends,
/// TDEP and FAL from the job's depth and allowance, NRC the number of rough cuts whose equal
/// steps (VARI 1/2) or equal areas (VARI 3/4) the job's law makes, NID its further finishing
/// passes, IANG its flank angle (negative: alternating), NSP its start angle, NUMT its starts,
/// `_VRT` the lift of its start point above the crest.
pub(super) fn native(
    machine: &crate::machine::Machine,
    job: &Job,
) -> Vec<std::result::Result<Vec<String>, String>> {
    match words(job) {
        Ok(w) => w
            .nrc
            .iter()
            .map(|&nrc| Ok(vec![w.call(machine, job, nrc)]))
            .collect(),
        Err(why) => vec![Err(why)],
    }
}

/// The words of a CYCLE97 call other than NRC, in mm; the NRC that may fit.
struct Words {
    spl: f64,
    fpl: f64,
    iang: f64,
    vari: u32,
    lift: f64,
    nrc: Vec<u32>,
}

impl Words {
    fn call(&self, machine: &crate::machine::Machine, job: &Job, nrc: u32) -> String {
        let u = job.units;
        let g = &job.geometry;
        let nd = machine.decimals(u);
        let tz = machine.output.trailing_zeros;
        let len = |mm: f64| crate::post::number(u.from_mm(mm), nd, tz);
        let lead_digits = if u == crate::units::Units::Inch { 5 } else { 4 };
        format!(
            "CYCLE97({},,{},{},{},{},0,0,{},{},{},{},{},{},{},{},{})",
            crate::post::number(u.from_mm(job.lead.lead), lead_digits, tz),
            len(self.spl),
            len(self.fpl),
            len(2.0 * g.crest_start.x),
            len(2.0 * g.crest_end.x),
            len(g.depth),
            len(job.plan.finish_allowance),
            crate::post::number(self.iang, 4, tz),
            crate::post::number(job.lead.phase_deg, 4, tz),
            nrc,
            job.plan.finish_passes - 1,
            self.vari,
            job.lead.starts,
            len(self.lift)
        )
    }
}

/// The call's words, or the property of the job CYCLE97 cannot express.
fn words(job: &Job) -> std::result::Result<Words, String> {
    let g = &job.geometry;
    if g.side.is_face() {
        return Err("threadcut writes CYCLE97's longitudinal threads only".into());
    }
    if job.entry != Entry::Direct {
        return Err("CYCLE97 has no entry ramp".into());
    }
    if job.exit != Exit::Straight {
        return Err(
            "CYCLE97 ends every pass at the end of its run-out, straight, and this job pulls out"
                .into(),
        );
    }
    if job.lead.dlead != 0.0 {
        return Err("CYCLE97 cuts a constant lead".into());
    }
    if job.lead.starts > 1 && job.lead.indexing != StartIndexing::Angle {
        return Err("CYCLE97 cuts each start whole, reached by turning the spindle (NUMT), and this job cuts every start at each depth".into());
    }
    if job.plan.finish_passes == 0 {
        return Err(
            "CYCLE97 always ends with a finishing cut at TDEP, and this job has none".into(),
        );
    }
    let box_at_start = job.return_path == ReturnPath::Box
        && job.retract
            == (Retract {
                x: job.start.x,
                z: job.start.z,
            });
    if job.return_path != ReturnPath::BoxAtRetract && !box_at_start {
        return Err("CYCLE97 retracts to its start point after every pass and stays there, and this job does not".into());
    }
    let full_offset = job.infeed.axis(g.depth);
    let (z0, z1) = (g.crest_start.z + full_offset, g.crest_end.z + full_offset);
    if (job.retract.z - z0).abs() > 1e-9 {
        return Err(
            "CYCLE97 returns along Z to the start of the thread, and this job elsewhere".into(),
        );
    }
    let length = z1 - z0;
    let (r1, r2) = (g.crest_start.x, g.crest_end.x);
    if (r2 - r1).abs() > length.abs() {
        return Err("CYCLE97 cuts a taper of 45° or less along Z".into());
    }
    let outward = g.side.outward().x;
    let crest_out = if outward > 0.0 {
        r1.max(r2)
    } else {
        r1.min(r2)
    };
    let lift = (job.retract.x - crest_out) * outward;
    if lift <= 0.0 {
        return Err("CYCLE97's start point lies outside the thread's crest (by _VRT), and this job's retract does not".into());
    }
    let (leading, trailing) = if length < 0.0 {
        (Flank::Right, Flank::Left)
    } else {
        (Flank::Left, Flank::Right)
    };
    let iang = match job.infeed {
        Infeed::Radial => 0.0,
        Infeed::Flank { flank, angle_deg } if flank == leading && angle_deg < 90.0 => angle_deg,
        Infeed::Alternating {
            first,
            second,
            angle_deg,
        } if first == leading && second == trailing && r1 == r2 && angle_deg < 90.0 => -angle_deg,
        _ => return Err("CYCLE97 infeeds straight in, along the leading flank (IANG > 0) or alternately from it (IANG < 0, cylinders only), and this job otherwise".into()),
    };
    if job.plan.finish_allowance > 0.0
        && job.finish_at != FinishPosition::Axis
        && !matches!(job.infeed, Infeed::Radial)
    {
        return Err("CYCLE97 cuts its finishing passes on the groove's axis".into());
    }
    let rough = g.depth - job.plan.finish_allowance;
    let whole =
        |v: f64| ((v - v.round()).abs() < 1e-6 && v.round() >= 1.0).then(|| v.round() as u32);
    let (vari, nrc) = match job.plan.law {
        DepthLaw::Power {
            first,
            degression,
            min_step,
        } if degression == 1.0 && min_step == 0.0 => (1, whole(rough / first)),
        DepthLaw::Power {
            first,
            degression: 2.0,
            ..
        } => (3, whole((rough / first).powi(2))),
        _ => (0, None),
    };
    let Some(nrc) = nrc else {
        return Err("CYCLE97 divides TDEP − FAL into NRC cuts of equal depth or of equal area, the last exactly at TDEP − FAL, and this job's depths follow another law".into());
    };
    let vari = vari + if g.side == Side::Internal { 1 } else { 0 };
    Ok(Words {
        spl: z0,
        fpl: z1,
        iang,
        vari,
        lift,
        nrc: vec![nrc],
    })
}
