//! Streams a whole program through a dialect, line by line, in constant memory: blocks that are not
//! threading cycles pass through byte for byte; each cycle becomes a [`Job`] and then motion.

use std::io::{self, BufRead, Write};

use serde::Serialize;

use crate::diag::Diagnostic;
use crate::dialect::{self, Read};
use crate::gcode::{Line, Modal, MotionMode, PlainMove, Reader};
use crate::machine::Machine;
use crate::post::{self, json_num};
use crate::thread::{Job, Pass, PassKind};
use crate::toolpath::{self, Motion, MotionKind};
use crate::units::Units;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: the program, with its place.
    #[error("{0}")]
    Input(Diagnostic),
    /// The output could not be written.
    #[error("cannot write the output: {0}")]
    Io(#[from] io::Error),
    /// The machine profile cannot be used.
    #[error("{0}")]
    Setup(String),
}

impl From<Diagnostic> for Error {
    fn from(d: Diagnostic) -> Error {
        Error::Input(d)
    }
}

/// What happened on one line.
pub enum Event<'a, 'l> {
    /// A block that is not part of a threading cycle, with the move it makes, if any.
    Plain {
        line: &'a Line<'l>,
        mv: Option<PlainMove>,
    },
    /// A cycle block that only sets values.
    Settings { line: &'a Line<'l> },
    /// A complete cycle, with the dialect that read it (for its own way of writing it).
    Cycle {
        line: &'a Line<'l>,
        job: Box<Job>,
        dialect: &'a dyn dialect::Dialect,
    },
}

/// What a run found besides its output.
#[derive(Debug, Default)]
pub struct Summary {
    pub lines: u32,
    pub cycles: u32,
    pub warnings: Vec<Diagnostic>,
}

/// Runs `input` through the machine's dialect, handing every line to `sink` with the modal state
/// as it stands after the line.
pub fn run<R: BufRead>(
    input: R,
    machine: &Machine,
    mut sink: impl FnMut(&Modal, Event) -> Result<(), Error>,
) -> Result<Summary, Error> {
    let mut dialect = dialect::open(machine).map_err(Error::Setup)?;
    let conv = dialect.conventions().clone();
    let mut modal = Modal::new(
        &conv,
        machine.units,
        [
            machine.no_point_scale(Units::Mm),
            machine.no_point_scale(Units::Inch),
        ],
    );
    let mut reader = Reader::new(input).with_bare_letters(dialect.bare_letters());
    let mut summary = Summary::default();
    while let Some(line) = reader.next_line() {
        let line = line?;
        summary.lines = line.number;
        // Most lines are not the dialect's business: its prefilter says so without `read` (which
        // would return `Read::Plain` and leave everything as it is).
        if !dialect.prefilter(&line) {
            match modal.apply(&conv, &line) {
                Ok(mv) => sink(&modal, Event::Plain { line: &line, mv })?,
                Err(e) => return Err(e.into()),
            }
            continue;
        }
        let before = summary.warnings.len();
        match dialect.read(&line, &mut modal, &mut summary.warnings)? {
            Read::Plain => match modal.apply(&conv, &line) {
                Ok(mv) => sink(&modal, Event::Plain { line: &line, mv })?,
                Err(e) => return Err(e.into()),
            },
            Read::Settings => sink(&modal, Event::Settings { line: &line })?,
            Read::Cycle(job) => {
                summary.cycles += 1;
                // Fanuc-style cycles end where they started; LinuxCNC's G76 at its Z end.
                modal.position = Some(job.end_point());
                sink(
                    &modal,
                    Event::Cycle {
                        line: &line,
                        job,
                        dialect: &*dialect,
                    },
                )?;
            }
        }
        for w in &mut summary.warnings[before..] {
            if w.span.line == 0 {
                w.span = line.span();
            }
        }
    }
    Ok(summary)
}

/// Every cycle of a program, for tests and library users (holds them all in memory).
pub fn jobs<R: BufRead>(input: R, machine: &Machine) -> Result<Vec<Job>, Error> {
    let mut jobs = Vec::new();
    run(input, machine, |_, ev| {
        if let Event::Cycle { job, .. } = ev {
            jobs.push(*job);
        }
        Ok(())
    })?;
    Ok(jobs)
}

/// `threadcut expand`: the program with each cycle replaced by plain moves in the controller's own
/// format. Other lines are copied byte for byte.
pub fn expand_gcode<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    machine: &Machine,
) -> Result<Summary, Error> {
    let d = dialect::open(machine).map_err(Error::Setup)?;
    let format = d.format();
    let distance_words = d.conventions().g90_g91_distance;
    // The pass-through arm is kept small so that it is inlined into `run`'s loop; the rest is in
    // `expand_event`.
    run(input, machine, |modal, ev| match ev {
        Event::Plain { line, .. } => Ok(out.write_all(line.raw)?),
        // Rebuilt rather than passed on, so that the plain arm never needs the event in memory.
        Event::Settings { line } => expand_event(
            out,
            &format,
            distance_words,
            modal,
            Event::Settings { line },
        ),
        Event::Cycle { line, job, dialect } => expand_event(
            out,
            &format,
            distance_words,
            modal,
            Event::Cycle { line, job, dialect },
        ),
    })
}

/// `expand_gcode` for the lines that are part of a cycle.
#[inline(never)]
fn expand_event(
    out: &mut dyn Write,
    base_format: &post::Format,
    distance_words: bool,
    modal: &Modal,
    ev: Event,
) -> Result<(), Error> {
    // X as the program writes it at this point (LinuxCNC's G7/G8 change it mid-program).
    let format = post::Format {
        diameter_x: modal.diameter_x,
        ..base_format.clone()
    };
    match ev {
        Event::Plain { line, .. } => out.write_all(line.raw)?,
        Event::Settings { line } => {
            if let Some(c) = format.comment(&format!(
                "threadcut: line {} sets the cycle that follows",
                line.number
            )) {
                writeln!(out, "{c}")?;
            }
        }
        Event::Cycle { line, job, dialect } => {
            post::expressible(&format, &job)?;
            // Motion needs no chip areas.
            let passes = crate::thread::plan::plan_geometry(&job)?;
            let path = toolpath::build_with(&job, &passes)?;
            let rough = passes.iter().filter(|p| p.kind == PassKind::Rough).count();
            if let Some(c) = format.comment(&format!(
                "threadcut: {} cycle of line {} as {} rough and {} finishing passes",
                job.controller,
                line.number,
                rough,
                passes.len() - rough
            )) {
                writeln!(out, "{c}")?;
            }
            match dialect.write_cycle(out, &job, &passes, &path) {
                // The controller's own form is a cycle too: it leaves the modal state as the
                // original cycle does.
                Some(written) => written?,
                None => {
                    // The moves are absolute: under incremental distance mode, switch to G90
                    // around them.
                    let incremental = distance_words && !modal.absolute;
                    if incremental {
                        writeln!(out, "G90")?;
                    }
                    post::write_moves(out, &format, job.units, &path)?;
                    if incremental {
                        writeln!(out, "G91")?;
                    }
                    restore_modal_state(out, &format, modal, &path)?;
                }
            }
        }
    }
    Ok(())
}

/// After an expansion the output's modal state must match what the original program has after its
/// cycle: the motion mode of before the cycle (a cycle is one-shot) and the F register.
fn restore_modal_state(
    out: &mut dyn Write,
    format: &post::Format,
    modal: &Modal,
    path: &toolpath::Toolpath,
) -> io::Result<()> {
    let mut block = String::new();
    match modal.motion {
        MotionMode::Feed => block.push_str(format.feed),
        MotionMode::ArcCw => block.push_str("G2"),
        MotionMode::ArcCcw => block.push_str("G3"),
        MotionMode::Thread => block.push_str(format.thread),
        MotionMode::Rapid | MotionMode::Cycle => {}
    }
    let last_lead = path.motions.iter().rev().find_map(|m| match m.kind {
        MotionKind::Thread { lead, .. } => Some(lead),
        _ => None,
    });
    // Only where the lead word is F does a thread move change the F register.
    let last_lead = last_lead.filter(|_| format.lead_letter == 'F');
    if let (Some(f), Some(lead)) = (modal.f_word, last_lead) {
        let digits = format.lead_decimals[(modal.units == Units::Inch) as usize];
        let want = post::number(f, digits, format.trailing_zeros);
        if want != post::number(modal.units.from_mm(lead), digits, format.trailing_zeros) {
            if !block.is_empty() {
                block.push(' ');
            }
            block.push('F');
            block.push_str(&want);
        }
    }
    if !block.is_empty() {
        writeln!(out, "{block}")?;
    }
    Ok(())
}

/// `threadcut expand --format jsonl`: one JSON object per motion, program units, X as a radius.
pub fn expand_jsonl<R: BufRead>(
    input: R,
    out: &mut dyn Write,
    machine: &Machine,
) -> Result<Summary, Error> {
    run(input, machine, |modal, ev| {
        match ev {
            Event::Plain { line, mv: Some(mv) } => {
                let units = modal.units;
                let m = |kind| Motion {
                    kind,
                    to: mv.to,
                    pass: 0,
                    line: line.number,
                };
                let text = match mv.mode {
                    MotionMode::Rapid => post::motion_json(&m(MotionKind::Rapid), units),
                    MotionMode::Feed => post::motion_json(&m(MotionKind::Feed), units),
                    MotionMode::Thread => post::motion_json(
                        &m(MotionKind::Thread {
                            // Already along the move's longer axis (`Modal::apply`).
                            lead: mv.lead.unwrap_or(0.0),
                            dlead: 0.0,
                            phase_deg: 0.0,
                        }),
                        units,
                    ),
                    MotionMode::ArcCw | MotionMode::ArcCcw => format!(
                        r#"{{"kind":"arc","x":{},"z":{},"cw":{},"pass":0,"line":{}}}"#,
                        json_num(units.from_mm(mv.to.x)),
                        json_num(units.from_mm(mv.to.z)),
                        mv.mode == MotionMode::ArcCw,
                        line.number
                    ),
                    MotionMode::Cycle => return Ok(()),
                };
                writeln!(out, "{text}")?;
            }
            Event::Cycle { job, .. } => {
                for m in &toolpath::build(&job)?.motions {
                    writeln!(out, "{}", post::motion_json(m, job.units))?;
                }
            }
            _ => {}
        }
        Ok(())
    })
}

/// One row of `threadcut passes`, in program units, X as the program writes it.
#[derive(Debug, Serialize)]
pub struct PassRow {
    pub n: u32,
    pub kind: PassKind,
    pub depth: f64,
    pub increment: f64,
    pub x: f64,
    pub z: f64,
    pub area: f64,
    pub share: f64,
}

/// The pass table of a job, as rows in the program's units.
pub fn pass_rows(job: &Job, passes: &[Pass], diameter_x: bool) -> Vec<PassRow> {
    let u = job.units;
    passes
        .iter()
        .map(|p| PassRow {
            n: p.n,
            kind: p.kind,
            depth: u.from_mm(p.depth),
            increment: u.from_mm(p.increment),
            x: u.from_mm(p.start.x) * if diameter_x { 2.0 } else { 1.0 },
            z: u.from_mm(p.start.z),
            area: p.area / (u.scale() * u.scale()),
            share: p.share,
        })
        .collect()
}

/// One cycle of `threadcut passes --json`: the pass rows and the simulated columns (`sim_area`,
/// `sim_share`, `cutting_flank`, `chip_thickness`; null where the section could not be simulated).
pub fn passes_json(
    job: &Job,
    rows: &[PassRow],
    section: Option<&crate::sim::Section>,
) -> serde_json::Value {
    let sims = section.map(|s| s.passes.as_slice());
    let sim = |i: usize| sims.and_then(|s| s.get(i));
    let area_scale = job.units.scale() * job.units.scale();
    let rows: Vec<serde_json::Value> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut v = serde_json::to_value(r).unwrap_or_default();
            if let Some(o) = v.as_object_mut() {
                let s = sim(i);
                o.insert("sim_area".into(), s.map(|s| s.area / area_scale).into());
                o.insert("sim_share".into(), s.map(|s| s.share).into());
                o.insert("cutting_flank".into(), s.map(|s| s.flank.name()).into());
                o.insert(
                    "chip_thickness".into(),
                    s.map(|s| job.units.from_mm(s.max_thickness)).into(),
                );
            }
            v
        })
        .collect();
    serde_json::json!({
        "line": job.line,
        "controller": job.controller,
        "units": job.units,
        "passes": rows,
    })
}
