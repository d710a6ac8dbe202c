//! `threadcut plot FILE -o out.svg`: each cycle's pass diagram and XZ toolpath, in one SVG.

use std::path::Path;
use std::process::ExitCode;

use threadcut::commands::{self, Source};

use super::{
    load_machine, no_thread, open_input, output, post::is_apt, warn, Failure, MachineArgs, ToolArgs,
};

pub fn run(
    file: &Path,
    machine: &MachineArgs,
    out: &Path,
    tool: &ToolArgs,
) -> Result<ExitCode, Failure> {
    let tip = tool.tip()?;
    let mut input = open_input(file)?;
    // APT/CL needs no controller; G-code is read by the controller's dialect.
    let machine = if is_apt(file, &mut input) {
        None
    } else {
        Some(load_machine(machine)?)
    };
    let source = machine.as_ref().map_or(Source::Apt(None), Source::Gcode);
    let run = output::write(file, Some(out), |w| {
        let (svg, run) = commands::plot_svg(input, source, tip)?;
        w.write_all(svg.as_bytes())?;
        Ok(run)
    })?;
    warn(file, &run.summary);
    if run.threads == 0 {
        no_thread(file, &commands::thread_codes(source));
    }
    Ok(ExitCode::SUCCESS)
}
