//! `threadcut check FILE`: the program's errors and warnings, compiler style, with line:column.
//! Exit status 2 when there is an error, 0 otherwise.

use std::io::Write;
use std::path::Path;
use std::process::ExitCode;

use threadcut::sim::check::{self, CheckOptions};

use super::{
    failure, io_failure, load_machine, open_input, render, Failure, MachineArgs, ToolArgs,
};

pub fn run(
    file: &Path,
    machine: &MachineArgs,
    stock_diameter: Option<f64>,
    stock_start: Option<f64>,
    tool: &ToolArgs,
    options: &threadcut::program::Options,
) -> Result<ExitCode, Failure> {
    let machine = load_machine(machine)?;
    let input = open_input(file)?;
    let opts = CheckOptions {
        stock_diameter,
        stock_start,
        tip: tool.tip()?,
        max_blocks: options.max_blocks,
    };
    let report = check::check(input, &machine, &opts).map_err(|e| failure(file, e))?;
    let mut out = std::io::stdout().lock();
    for d in &report.diagnostics {
        write!(out, "{}", render::diagnostic(file, d)).map_err(io_failure)?;
    }
    let (errors, warnings) = (report.errors(), report.warnings());
    writeln!(
        out,
        "{}: {} error{}, {} warning{} in {} cycle{}{}",
        file.display(),
        errors,
        if errors == 1 { "" } else { "s" },
        warnings,
        if warnings == 1 { "" } else { "s" },
        report.cycles,
        if report.cycles == 1 { "" } else { "s" },
        if report.stopped {
            " (checking stopped at the controller's alarm)"
        } else {
            ""
        }
    )
    .map_err(io_failure)?;
    Ok(if errors > 0 {
        ExitCode::from(2)
    } else {
        ExitCode::SUCCESS
    })
}
