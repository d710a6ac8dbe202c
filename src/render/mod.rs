//! Pictures of what a program does. Everything here reads the model's results (the pass table,
//! the simulated section, the toolpath) and writes text; nothing computes motion.

mod draw;
pub mod milled;
pub mod part;
pub mod svg;

pub use part::PartPicture;
pub use svg::{svg, CyclePlot};

use std::io::BufRead;

use crate::machine::Machine;
use crate::program::{self, Error, Summary};
use crate::sim::{self, tip_in_mm, Tip, Tool};
use crate::threads::{self, Thread};

/// Which threads of a program a picture draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Selection {
    /// Only this thread (1-based, in program order).
    pub only: Option<usize>,
    /// Otherwise the first this many.
    pub max: usize,
}

/// The threads a picture draws unless told otherwise: about 14 kB of SVG each for a usual cycle.
pub const MAX_PLOTTED: usize = 50;

impl Default for Selection {
    fn default() -> Selection {
        Selection {
            only: None,
            max: MAX_PLOTTED,
        }
    }
}

impl Selection {
    fn wants(&self, number: usize, kept: usize) -> bool {
        match self.only {
            Some(n) => number == n,
            None => kept < self.max,
        }
    }
}

/// A program's picture and what it holds.
#[derive(Debug)]
pub struct Plot {
    pub svg: String,
    pub summary: Summary,
    /// Every thread the program has.
    pub threads: usize,
    /// The threads drawn: number (1-based, in program order) and the line each starts on.
    pub drawn: Vec<(usize, u32)>,
}

/// `threadcut plot`: every thread of a G-code program (cycles, and threads written as plain
/// moves), its pass diagram and XZ toolpath, as one SVG, with the tool's tip given in program
/// units; with the run's summary and the number of threads the program has. At most
/// [`MAX_PLOTTED`] threads are drawn ([`program_plot`] chooses).
pub fn program_svg<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
) -> Result<(String, Summary, usize), Error> {
    program_svg_with(input, machine, tip, &program::Options::default())
}

/// [`program_svg`] with the run's options: a program with control flow draws every thread it
/// executes (a cycle run three times is three threads).
pub fn program_svg_with<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
    options: &program::Options,
) -> Result<(String, Summary, usize), Error> {
    let p = program_plot_with(input, machine, tip, Selection::default(), options)?;
    Ok((p.svg, p.summary, p.threads))
}

/// [`program_svg`] with the threads to draw chosen: the picture says which threads it leaves out.
/// Only the threads drawn are kept in memory.
pub fn program_plot<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
    selection: Selection,
) -> Result<Plot, Error> {
    program_plot_with(input, machine, tip, selection, &program::Options::default())
}

/// [`program_plot`] with the run's options.
pub fn program_plot_with<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
    selection: Selection,
    options: &program::Options,
) -> Result<Plot, Error> {
    program_plot_part(input, machine, tip, selection, options, None)
}

/// [`program_plot_with`] with the part the program makes drawn above the threads.
pub fn program_plot_part<R: BufRead>(
    input: R,
    machine: &Machine,
    tip: Tip,
    selection: Selection,
    options: &program::Options,
    part: Option<&PartPicture>,
) -> Result<Plot, Error> {
    let mut found = Vec::new();
    let mut total = 0;
    let summary = threads::each_gcode_with(input, machine, None, options, |t| {
        total += 1;
        if selection.wants(total, found.len()) {
            found.push((total, t));
        }
        Ok(())
    })?;
    plot(found, total, summary, tip, part)
}

/// What [`program_plot_part`] draws with the default [`Selection`], from threads read elsewhere:
/// `first`, the program's first threads (at most [`MAX_PLOTTED`]), of `total`.
pub fn first_threads_svg(
    first: &[Thread],
    total: usize,
    tip: Tip,
    part: Option<&PartPicture>,
) -> Result<String, Error> {
    let first = &first[..first.len().min(MAX_PLOTTED)];
    let numbers: Vec<usize> = (1..=first.len()).collect();
    Ok(threads_picture(first, &numbers, total, tip, part)?.0)
}

/// `threadcut plot` on an APT/CL program.
pub fn apt_svg<R: BufRead>(input: R, tip: Tip) -> Result<(String, Summary, usize), Error> {
    let p = apt_plot(input, tip, Selection::default())?;
    Ok((p.svg, p.summary, p.threads))
}

/// [`apt_svg`] with the threads to draw chosen.
pub fn apt_plot<R: BufRead>(input: R, tip: Tip, selection: Selection) -> Result<Plot, Error> {
    let mut found = Vec::new();
    let mut total = 0;
    let summary = threads::each_apt(input, |t| {
        total += 1;
        if selection.wants(total, found.len()) {
            found.push((total, t));
        }
        Ok(())
    })?;
    plot(found, total, summary, tip, None)
}

fn plot(
    found: Vec<(usize, Thread)>,
    total: usize,
    summary: Summary,
    tip: Tip,
    part: Option<&PartPicture>,
) -> Result<Plot, Error> {
    let (numbers, threads): (Vec<usize>, Vec<Thread>) = found.into_iter().unzip();
    let (svg, drawn) = threads_picture(&threads, &numbers, total, tip, part)?;
    Ok(Plot {
        svg,
        summary,
        threads: total,
        drawn: numbers
            .iter()
            .zip(&threads)
            .take(drawn)
            .map(|(n, t)| (*n, t.job.line))
            .collect(),
    })
}

/// The SVG of these threads. A cycle whose tool angle is 0° (a radial infeed) is drawn with a 60°
/// tool, as `check` cuts its section.
pub fn threads_svg(found: &[Thread], tip: Tip) -> Result<String, Error> {
    let numbers: Vec<usize> = (1..=found.len()).collect();
    Ok(threads_picture(found, &numbers, found.len(), tip, None)?.0)
}

/// [`threads_svg`] of the threads numbered `numbers` of `total`, saying which are left out; with
/// how many were drawn ([`svg::picture`]).
fn threads_picture(
    found: &[Thread],
    numbers: &[usize],
    total: usize,
    tip: Tip,
    part: Option<&PartPicture>,
) -> Result<(String, usize), Error> {
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
    Ok(svg::picture_with(&plots, numbers, total, part))
}
