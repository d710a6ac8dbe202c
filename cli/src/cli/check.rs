//! `threadcut check FILE`: the program's errors and warnings, compiler style, with line:column, and
//! what was assumed; or `--format json`. Exit status 2 when there is an error, 0 otherwise.
//! G-code and APT/CL alike: both go through the library's one check function.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use threadcut::check::{self, Options, Report, Source};
use threadcut::commands::with_stock;
use threadcut::thread::standard;

use super::{
    failure, input, load_machine, mill::usage, not_empty, output, post::is_apt, render, Failure,
    MachineArgs, ReportFormat, ToolArgs,
};

/// `check`'s options as the command line gives them.
pub struct Args<'a> {
    /// The stock given on the command line (the profile's `[stock]` fills the rest).
    pub stock: threadcut::machine::Stock,
    pub tool: &'a ToolArgs,
    pub thread: Option<&'a str>,
    /// `--wire`: the measuring wire one owns, in the thread's units.
    pub wire: Option<f64>,
    pub format: ReportFormat,
    pub output: Option<&'a Path>,
    /// The run's options (`--max-blocks`).
    pub run: &'a threadcut::program::Options,
}

pub fn run(file: &Path, machine: &MachineArgs, args: &Args) -> Result<ExitCode, Failure> {
    let thread = match args.thread {
        Some(name) => Some(standard::lookup(name).map_err(usage)?),
        None => None,
    };
    if let Some(w) = args.wire {
        if !(w.is_finite() && w > 0.0) {
            return Err(Failure::Usage(format!(
                "--wire {w}: a measuring wire's diameter is a positive length (the thread's units)"
            )));
        }
    }
    let opts = Options {
        tip: args.tool.given_tip()?,
        thread,
        wire: args.wire,
        max_blocks: args.run.max_blocks,
        library: args.run.library.clone(),
        call: args.run.call.clone(),
        start: args.run.start,
        ..Options::default()
    };
    let (mut input, content) = input::open(file)?;
    let report = if is_apt(file, &mut input) {
        let machine = match (&machine.controller, &machine.machine) {
            (None, None) => None,
            _ => Some(load_machine(machine)?),
        };
        let opts = with_stock(opts, args.stock, machine.as_ref());
        check::check(input, Source::Apt(machine.as_ref()), &opts)
    } else {
        let machine = load_machine(machine)?;
        let opts = with_stock(opts, args.stock, Some(&machine));
        check::check(input, Source::Gcode(&machine), &opts)
    }
    .map_err(|e| failure(file, e))?;
    not_empty(file, &content)?;
    if report.threads == 0 && !report.stopped && !report.uncalled {
        super::no_thread(file, &report.thread_codes);
    }
    print(file, args.format, args.output, &report)
}

/// Writes a report as the format asks; exit status 2 when it holds an error.
pub fn print(
    file: &Path,
    format: ReportFormat,
    to: Option<&Path>,
    report: &Report,
) -> Result<ExitCode, Failure> {
    output::write(file, to, |out| {
        match format {
            ReportFormat::Json => {
                let findings = report.findings_in(&|span| render::file_of(file, span));
                serde_json::to_writer_pretty(&mut *out, &findings)
                    .map_err(|e| failure(file, std::io::Error::from(e).into()))?;
                writeln!(out).map_err(|e| failure(file, e.into()))?;
            }
            ReportFormat::Jsonl => {
                for f in report.findings_in(&|span| render::file_of(file, span)) {
                    serde_json::to_writer(&mut *out, &f)
                        .map_err(|e| failure(file, std::io::Error::from(e).into()))?;
                    writeln!(out).map_err(|e| failure(file, e.into()))?;
                }
            }
            ReportFormat::Text => {
                write_text(out, file, report).map_err(|e| failure(file, e.into()))?
            }
        }
        Ok(())
    })?;
    Ok(if report.errors() > 0 {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}

fn write_text(out: &mut dyn Write, file: &Path, report: &Report) -> std::io::Result<()> {
    for d in &report.diagnostics {
        write!(out, "{}", render::diagnostic(file, d))?;
    }
    for n in &report.notes {
        writeln!(
            out,
            "note: {}:{}: {}",
            render::file_of(file, &n.span),
            n.span.line,
            n.message
        )?;
    }
    let (errors, warnings) = (report.errors(), report.warnings());
    let plural = |n: usize| if n == 1 { "" } else { "s" };
    writeln!(
        out,
        "{}: {} error{}, {} warning{} in {} thread{}{}",
        file.display(),
        errors,
        plural(errors),
        warnings,
        plural(warnings),
        report.threads,
        plural(report.threads as usize),
        match report.diagnostics.iter().rev().find(|d| d.is_error()) {
            _ if !report.stopped => "",
            // A motion threadcut does not follow is its own limit, not the control's.
            Some(d) if d.code == threadcut::diag::Code::Unsupported => {
                " (checking stopped: the program is not read past its last error)"
            }
            _ => " (checking stopped at the controller's alarm)",
        }
    )
}
