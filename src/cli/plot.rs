//! `threadcut plot FILE -o out.svg`: each cycle's pass diagram and XZ toolpath, in one SVG.

use std::path::Path;
use std::process::ExitCode;

use threadcut::program::{self, Event};
use threadcut::render::{self, CyclePlot};
use threadcut::sim::{self, check::tip_in_mm, Tool};
use threadcut::thread::{Job, Pass};
use threadcut::toolpath::{self, Toolpath};

use super::{load_machine, open_input, output, warn, Failure, MachineArgs, ToolArgs};

pub fn run(
    file: &Path,
    machine: &MachineArgs,
    out: &Path,
    tool: &ToolArgs,
) -> Result<ExitCode, Failure> {
    let machine = load_machine(machine)?;
    let tip = tool.tip()?;
    let input = open_input(file)?;
    let summary = output::write(file, Some(out), |w| {
        let mut cycles: Vec<(Job, Vec<Pass>, sim::Section, Toolpath)> = Vec::new();
        let summary = program::run(input, &machine, |_, ev| {
            if let Event::Cycle { job, .. } = ev {
                let passes = job.passes()?;
                let path = toolpath::build_with(&job, &passes)?;
                let tool = Tool {
                    angle_deg: job.tool_angle_deg,
                    tip: tip_in_mm(tip, job.units),
                };
                let section = sim::section(&job, &passes, &tool, 0.0)?;
                cycles.push((*job, passes, section, path));
            }
            Ok(())
        })?;
        let plots: Vec<CyclePlot> = cycles
            .iter()
            .map(|(job, passes, section, path)| CyclePlot {
                job,
                passes,
                section,
                path,
                diameter_x: machine.diameter_x,
            })
            .collect();
        w.write_all(render::svg(&plots).as_bytes())?;
        Ok(summary)
    })?;
    warn(file, &summary);
    Ok(ExitCode::SUCCESS)
}
