//! `threadcut plot FILE [-o out.svg]`: the part the program makes (where it cuts anything, a
//! stock is given or a rapid runs into material), then each thread's pass diagram and XZ
//! toolpath, in one SVG; at most [`render::MAX_PLOTTED`] threads, or the one `--cycle N` names,
//! and what was left out said in the picture and on standard error. `--part`: the part alone.

use std::path::Path;
use std::process::ExitCode;

use threadcut::check;
use threadcut::commands::{plot_program, with_stock, PartPlot, Source};
use threadcut::render::{self, Selection};

use super::{
    input, lib, load_machine, no_thread, not_empty, output, post::is_apt, render as say,
    thread_codes, warn, Failure, MachineArgs, ToolArgs,
};

/// `plot`'s options as the command line gives them.
pub struct Args<'a> {
    pub out: Option<&'a Path>,
    pub cycle: Option<usize>,
    /// The part alone (`--part`).
    pub part: bool,
    pub tool: &'a ToolArgs,
    /// The stock given on the command line (the profile's `[stock]` fills the rest).
    pub stock: threadcut::machine::Stock,
    pub run: &'a threadcut::program::Options,
}

pub fn run(file: &Path, machine: &MachineArgs, args: &Args) -> Result<ExitCode, Failure> {
    let (out, cycle, options) = (args.out, args.cycle, args.run);
    let tip = args.tool.tip()?;
    let replay = input::Replay::new(file)?;
    let (mut reader, content) = replay.first(file)?;
    // APT/CL needs no controller; G-code is read by the controller's dialect.
    let (apt, codes) = if is_apt(file, &mut reader) {
        (None, threadcut::commands::APT_THREAD_STATEMENTS.to_string())
    } else {
        let machine = load_machine(machine)?;
        let codes = thread_codes(&machine);
        (Some(machine), codes)
    };
    let selection = Selection {
        only: cycle,
        ..Selection::default()
    };
    let part = PartPlot {
        check: with_stock(
            check::Options {
                tip: args.tool.given_tip()?,
                ..check::Options::default()
            },
            args.stock,
            apt.as_ref(),
        ),
        alone: args.part,
    };
    let plot = output::write(file, out, |w| {
        let plot = match &apt {
            None if args.part => Err(Failure::Usage(format!(
                "--part: {} is an APT/CL file, and the part is drawn for G-code programs",
                input::display(file)
            )))?,
            None => render::apt_plot(reader, tip, selection),
            Some(machine) => plot_program(
                input::readings(&replay, reader),
                Source::Gcode(machine),
                tip,
                selection,
                options,
                &part,
            ),
        }
        .map_err(lib(file))?;
        not_empty(file, &content)?;
        if let Some(n) = cycle.filter(|n| *n > plot.threads) {
            return Err(Failure::Usage(format!(
                "--cycle {n}: {} has {}",
                input::display(file),
                threadcut::text::count(plot.threads, "thread", "threads")
            )));
        }
        w.write_all(plot.svg.as_bytes())
            .map_err(|e| lib(file)(e.into()))?;
        Ok(plot)
    })?;
    warn(file, &plot.summary);
    if args.part {
        return Ok(ExitCode::SUCCESS);
    }
    if plot.threads == 0 {
        // (A file of subroutines was told so among the warnings.)
        if plot.summary.uncalled.is_empty() {
            no_thread(file, &codes);
        }
    } else if cycle.is_none() && plot.drawn.len() < plot.threads {
        let numbers: Vec<usize> = plot.drawn.iter().map(|(n, _)| *n).collect();
        let lines = match (plot.drawn.first(), plot.drawn.last()) {
            (Some((_, a)), Some((_, b))) if a == b => format!(" (line {a})"),
            (Some((_, a)), Some((_, b))) => format!(" (lines {a}–{b})"),
            _ => String::new(),
        };
        eprint!(
            "{}",
            say::warning(&format!(
                "{}: {}{lines}\n  = help: `--cycle N` draws the program's Nth thread alone",
                input::display(file),
                render::svg::left_out(&numbers, plot.threads)
            ))
        );
    }
    Ok(ExitCode::SUCCESS)
}
