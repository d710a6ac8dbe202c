//! Pictures of what a program does. Everything here reads the model's results (the pass table,
//! the simulated section, the toolpath) and writes text; nothing computes motion.

pub mod svg;

pub use svg::{svg, CyclePlot};

use std::io::BufRead;

use crate::machine::Machine;
use crate::program::{self, Error, Event, Summary};
use crate::sim::{self, check::tip_in_mm, Tip, Tool};
use crate::thread::{Job, Pass};
use crate::toolpath::{self, Toolpath};

/// `threadcut plot`: every cycle of a program, its pass diagram and XZ toolpath, as one SVG, with
/// the tool's tip given in program units.
pub fn program_svg<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
) -> Result<(String, Summary), Error> {
    program_svg_with(input, machine, tip, &program::Options::default())
}

/// [`program_svg`] with the run's options: a program with control flow draws every cycle it
/// executes.
pub fn program_svg_with<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
    options: &program::Options,
) -> Result<(String, Summary), Error> {
    let mut cycles: Vec<(Job, Vec<Pass>, sim::Section, Toolpath)> = Vec::new();
    let summary = program::run_with(input, machine, options, |_, ev| {
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
    Ok((svg(&plots), summary))
}
