//! Pictures of what a program does. Everything here reads the model's results (the pass table,
//! the simulated section, the toolpath) and writes text; nothing computes motion.

pub mod svg;

pub use svg::{svg, CyclePlot};

use std::io::BufRead;

use crate::machine::Machine;
use crate::program::{Error, Summary};
use crate::sim::{self, tip_in_mm, Tip, Tool};
use crate::threads::{self, Thread};

/// `threadcut plot`: every thread of a G-code program (cycles, and threads written as plain
/// moves), its pass diagram and XZ toolpath, as one SVG, with the tool's tip given in program
/// units; with the run's summary and the number of threads drawn.
pub fn program_svg<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
) -> Result<(String, Summary, usize), Error> {
    let mut found = Vec::new();
    let summary = threads::each_gcode(input, machine, None, |t| {
        found.push(t);
        Ok(())
    })?;
    Ok((threads_svg(&found, tip)?, summary, found.len()))
}

/// `threadcut plot` on an APT/CL program.
pub fn apt_svg<R: BufRead>(input: R, tip: Tip) -> Result<(String, Summary, usize), Error> {
    let mut found = Vec::new();
    let summary = threads::each_apt(input, |t| {
        found.push(t);
        Ok(())
    })?;
    Ok((threads_svg(&found, tip)?, summary, found.len()))
}

/// The SVG of these threads. A cycle whose tool angle is 0° (a radial infeed) is drawn with a 60°
/// tool, as `check` cuts its section.
pub fn threads_svg(found: &[Thread], tip: Tip) -> Result<String, Error> {
    let mut sections = Vec::with_capacity(found.len());
    for t in found {
        let angle = if t.job.tool_angle_deg > 0.0 {
            t.job.tool_angle_deg
        } else {
            60.0
        };
        let tool = Tool {
            angle_deg: angle,
            tip: tip_in_mm(tip, t.job.units),
        };
        let job = crate::thread::Job {
            tool_angle_deg: angle,
            ..t.job.clone()
        };
        sections.push(sim::section(&job, &t.passes, &tool, 0.0)?);
    }
    let plots: Vec<CyclePlot> = found
        .iter()
        .zip(&sections)
        .map(|(t, section)| CyclePlot {
            job: &t.job,
            passes: &t.passes,
            section,
            path: &t.path,
            diameter_x: t.diameter_x,
            what: t.describe(),
        })
        .collect();
    Ok(svg(&plots))
}
