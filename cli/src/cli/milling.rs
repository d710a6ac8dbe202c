//! `check`, `passes` and `plot` of a machining centre's program (a milling profile named with
//! `--controller`): the library's milling check (`threadcut::check::milling`) composed with the
//! command line's options and output.

use std::path::Path;
use std::process::ExitCode;

use threadcut::check::milling::{self, Milled, ToolSize};
use threadcut::commands::milled;
use threadcut::diag::Diagnostic;
use threadcut::mill::profile::MillProfile;
use threadcut::mill::Side;
use threadcut::sim::Tip;
use threadcut::units::Units;

use super::{check, failure, input, mill::usage, not_empty, output, Failure, ReportFormat};

/// What a milled thread's reading is told on the command line (check, passes, plot).
#[derive(clap::Args, Clone, Debug, Default)]
pub struct MillArgs {
    /// A milling program: the threads are internal (the material outside the helix).
    #[arg(long, conflicts_with = "external")]
    pub internal: bool,
    /// A milling program: the threads are external.
    #[arg(long)]
    pub external: bool,
    /// A milling program: the thread mill's cutting diameter (program units).
    #[arg(long, value_name = "D")]
    pub tool_diameter: Option<f64>,
    /// A milling program: a thread comb's teeth, one pitch apart.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    pub teeth: Option<u32>,
    /// A milling program: a cutter's diameter by its offset register or tool number
    /// (`D16=17.0`, `T5=12`; program units); repeatable.
    #[arg(long = "tool", value_name = "Dn=D|Tn=D")]
    pub tools: Vec<String>,
}

/// The options of a milling program's reading.
pub struct Given<'a> {
    pub mill: &'a MillArgs,
    pub thread: Option<&'a str>,
    pub tip: Option<Tip>,
    /// `--wire`, in the thread's units.
    pub wire: Option<f64>,
    pub max_blocks: u64,
}

fn options(g: &Given) -> Result<milling::Options, Failure> {
    let thread = g
        .thread
        .map(milling::named_thread)
        .transpose()
        .map_err(usage)?;
    let wire = match (g.wire, &thread) {
        (Some(w), _) if !(w.is_finite() && w > 0.0) => {
            return Err(Failure::Usage(format!(
                "--wire {w}: a measuring wire's diameter is a positive length (the thread's units)"
            )))
        }
        (Some(w), Some((t, _))) => Some(t.units.to_mm(w)),
        (w, _) => w,
    };
    let side = match (g.mill.internal, g.mill.external) {
        (true, _) => Some(Side::Internal),
        (_, true) => Some(Side::External),
        _ => None,
    };
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(Failure::Usage(format!(
                "--{name} {v}: expected a positive length (program units)"
            )))
        }
    };
    Ok(milling::Options {
        thread,
        tip: g.tip,
        wire,
        side,
        tool_diameter: g
            .mill
            .tool_diameter
            .map(|d| positive("tool-diameter", d))
            .transpose()?,
        tools: g
            .mill
            .tools
            .iter()
            .map(|t| tool_size(t))
            .collect::<Result<_, _>>()?,
        teeth: g.mill.teeth,
        max_blocks: Some(g.max_blocks),
    })
}

/// `D16=17.0` or `T5=12`.
fn tool_size(text: &str) -> Result<ToolSize, Failure> {
    ToolSize::parse(text).ok_or_else(|| {
        Failure::Usage(format!(
            "--tool {text}: expected a register or tool number and the cutter's diameter, as D16=17.0 or T5=12 (program units)"
        ))
    })
}

/// Reads the program: its milled threads and taps (said on standard error when there are
/// none), or the reader's error.
fn read(
    file: &Path,
    profile: &MillProfile,
    g: &Given,
) -> Result<(milling::Options, Milled), Failure> {
    let o = options(g)?;
    let (reader, content) = input::open(file)?;
    let milled = milling::read(reader, profile, &o).map_err(|d| input_failure(file, d))?;
    not_empty(file, &content)?;
    if milled.threads.is_empty() && milled.taps.is_empty() {
        no_milled_thread(file);
    }
    Ok((o, milled))
}

fn input_failure(file: &Path, d: Diagnostic) -> Failure {
    failure(file, threadcut::program::Error::Input(d))
}

/// `threadcut check` on a milling program.
pub fn check(
    file: &Path,
    profile: &MillProfile,
    g: &Given,
    format: ReportFormat,
    to: Option<&Path>,
) -> Result<ExitCode, Failure> {
    let o = options(g)?;
    let (reader, content) = input::open(file)?;
    let report = milling::check(reader, profile, &o);
    not_empty(file, &content)?;
    if report.threads == 0 && !report.stopped {
        no_milled_thread(file);
    }
    check::print(file, format, to, &report)
}

fn no_milled_thread(file: &Path) {
    eprint!(
        "{}",
        super::render::warning(&format!(
            "no thread found in {}: no helix about one axis and no tapping cycle\n  = help: a milled thread is consecutive G2/G3 arcs about one centre whose Z advances; a tap is G84, G74 or G33.1",
            input::display(file)
        ))
    );
}

/// `threadcut passes` on a milling program: each milled thread's helices, and the taps.
pub fn passes(
    file: &Path,
    profile: &MillProfile,
    g: &Given,
    format: ReportFormat,
    to: Option<&Path>,
) -> Result<ExitCode, Failure> {
    let (_, milled) = read(file, profile, g)?;
    let units = milled.units.unwrap_or(Units::Mm);
    output::write(file, to, |out| {
        let io = |e: std::io::Error| failure(file, e.into());
        match format {
            ReportFormat::Text => {
                for t in &milled.threads {
                    write!(out, "{}", milled::text(t, None, units)).map_err(io)?;
                }
                for t in &milled.taps {
                    writeln!(out, "{}", milled::tap_text(t, units)).map_err(io)?;
                }
            }
            ReportFormat::Json => {
                let threads: Vec<_> = milled
                    .threads
                    .iter()
                    .map(|t| milled::json(t, None))
                    .collect();
                let value = serde_json::json!({ "milled": threads, "taps": milled.taps });
                serde_json::to_writer(&mut *out, &value).map_err(|e| io(e.into()))?;
                writeln!(out).map_err(io)?;
            }
            ReportFormat::Jsonl => {
                for t in &milled.threads {
                    serde_json::to_writer(&mut *out, &milled::json(t, None))
                        .map_err(|e| io(e.into()))?;
                    writeln!(out).map_err(io)?;
                }
                for t in &milled.taps {
                    serde_json::to_writer(&mut *out, t).map_err(|e| io(e.into()))?;
                    writeln!(out).map_err(io)?;
                }
            }
        }
        Ok(())
    })?;
    Ok(ExitCode::SUCCESS)
}

/// `threadcut plot` on a milling program.
pub fn plot(
    file: &Path,
    profile: &MillProfile,
    g: &Given,
    to: Option<&Path>,
) -> Result<ExitCode, Failure> {
    let (o, milled) = read(file, profile, g)?;
    let angle = o.thread.as_ref().map_or(60.0, |(t, _)| t.profile.angle_deg);
    let svg = threadcut::render::milled::svg(&milled.threads, angle);
    output::write(file, to, |out| {
        out.write_all(svg.as_bytes())
            .map_err(|e| failure(file, e.into()))
    })?;
    Ok(ExitCode::SUCCESS)
}
