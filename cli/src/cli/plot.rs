//! `threadcut plot FILE [-o out.svg]`: each thread's pass diagram and XZ toolpath, in one SVG; at
//! most [`render::MAX_PLOTTED`] threads, or the one `--cycle N` names, and what was left out said
//! in the picture and on standard error.

use std::path::Path;
use std::process::ExitCode;

use threadcut::render::{self, Selection};

use super::{
    input, lib, load_machine, no_thread, not_empty, output, post::is_apt, render as say,
    thread_codes, warn, Failure, MachineArgs, ToolArgs,
};

pub fn run(
    file: &Path,
    machine: &MachineArgs,
    out: Option<&Path>,
    cycle: Option<usize>,
    tool: &ToolArgs,
    options: &threadcut::program::Options,
) -> Result<ExitCode, Failure> {
    let tip = tool.tip()?;
    let (mut reader, content) = input::open(file)?;
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
    let plot = output::write(file, out, |w| {
        let plot = match &apt {
            None => render::apt_plot(reader, tip, selection),
            Some(machine) => render::program_plot_with(reader, machine, tip, selection, options),
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
    if plot.threads == 0 {
        no_thread(file, &codes);
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
