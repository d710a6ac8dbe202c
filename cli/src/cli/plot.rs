//! `threadcut plot FILE -o out.svg`: each cycle's pass diagram and XZ toolpath, in one SVG.

use std::path::Path;
use std::process::ExitCode;

use threadcut::render;

use super::{load_machine, open_input, output, warn, Failure, MachineArgs, ToolArgs};

pub fn run(
    file: &Path,
    machine: &MachineArgs,
    out: &Path,
    tool: &ToolArgs,
    options: &threadcut::program::Options,
) -> Result<ExitCode, Failure> {
    let machine = load_machine(machine)?;
    let tip = tool.tip()?;
    let input = open_input(file)?;
    let summary = output::write(file, Some(out), |w| {
        let (svg, summary) = render::program_svg_with(input, &machine, tip, options)?;
        w.write_all(svg.as_bytes())?;
        Ok(summary)
    })?;
    warn(file, &summary);
    Ok(ExitCode::SUCCESS)
}
