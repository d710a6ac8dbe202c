//! `threadcut plot FILE -o out.svg`: each cycle's pass diagram and XZ toolpath, in one SVG.

use std::path::Path;
use std::process::ExitCode;

use threadcut::render;

use super::{
    load_machine, no_thread, open_input, output, post::is_apt, thread_codes, warn, Failure,
    MachineArgs, ToolArgs,
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
    let (apt, codes) = if is_apt(file, &mut input) {
        (None, "THREAD/ON, THREAD/TURN, COUPLE/ON".to_string())
    } else {
        let machine = load_machine(machine)?;
        let codes = thread_codes(&machine);
        (Some(machine), codes)
    };
    let (summary, count) = output::write(file, Some(out), |w| {
        let (svg, summary, count) = match &apt {
            None => render::apt_svg(input, tip)?,
            Some(machine) => render::program_svg(input, machine, tip)?,
        };
        w.write_all(svg.as_bytes())?;
        Ok((summary, count))
    })?;
    warn(file, &summary);
    if count == 0 {
        no_thread(file, &codes);
    }
    Ok(ExitCode::SUCCESS)
}
