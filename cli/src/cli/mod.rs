//! Command-line interface: argument parsing, input and output files, rendering of diagnostics.

mod check;
mod convert;
mod mill;
mod output;
mod passes;
mod plot;
mod post;
mod render;

use std::fs::File;
use std::io::{self, BufRead, BufReader, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};

use threadcut::diag::Diagnostic;
use threadcut::machine::{Machine, BUILT_IN};
use threadcut::program::{self, Error, Event, Summary};

#[derive(Parser)]
#[command(
    name = "threadcut",
    version,
    about = "Exact pass-by-pass motion for CNC thread-cutting cycles"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(clap::Args)]
struct MachineArgs {
    /// Built-in controller profile (see `threadcut controllers`).
    #[arg(long, short = 'c')]
    controller: Option<String>,
    /// Machine profile (TOML); overrides --controller.
    #[arg(long)]
    machine: Option<PathBuf>,
}

/// The tool's tip for the simulated section (sharp when neither is given); the angle is the cycle's.
#[derive(clap::Args)]
struct ToolArgs {
    /// Nose radius of the tool (program units).
    #[arg(long, value_name = "R", conflicts_with = "tip_flat")]
    nose_radius: Option<f64>,
    /// Width of a flat tip (program units).
    #[arg(long, value_name = "W")]
    tip_flat: Option<f64>,
}

impl ToolArgs {
    fn tip(&self) -> Result<threadcut::sim::Tip, Failure> {
        use threadcut::sim::Tip;
        let check = |name: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(v)
            } else {
                Err(Failure::Usage(format!(
                    "--{name} {v}: expected a length of 0 or more"
                )))
            }
        };
        Ok(match (self.nose_radius, self.tip_flat) {
            (Some(r), _) => Tip::Radius {
                radius: check("nose-radius", r)?,
            },
            (None, Some(w)) => Tip::Flat {
                width: check("tip-flat", w)?,
            },
            (None, None) => Tip::Sharp,
        })
    }
}

/// How a program with control flow (subroutines, loops, parameters) is run.
#[derive(clap::Args, Clone, Copy)]
struct RunArgs {
    /// Stop a program with control flow after N executed blocks (an endless loop ends with an
    /// error naming it).
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    max_blocks: u64,
}

impl RunArgs {
    fn options(&self, flatten: bool) -> Result<program::Options, Failure> {
        if self.max_blocks == 0 {
            return Err(Failure::Usage(
                "--max-blocks 0: expected at least 1".to_string(),
            ));
        }
        Ok(program::Options {
            max_blocks: self.max_blocks,
            flatten,
        })
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum ExpandFormat {
    /// The program with each cycle replaced by plain moves in the controller's format.
    Gcode,
    /// One JSON object per motion, program units, X as a radius.
    Jsonl,
}

#[derive(Subcommand)]
enum Command {
    /// Replace each threading cycle by plain moves (G0/G32 …); other blocks pass through unchanged.
    Expand {
        /// The program (`-` for standard input).
        file: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// Output file (`-` or absent: standard output). Written whole or not at all.
        #[arg(long, short = 'o')]
        output: Option<PathBuf>,
        #[arg(long, value_enum, default_value = "gcode")]
        format: ExpandFormat,
        /// A program with control flow: write the executed program as straight-line code (loops
        /// unrolled, calls inlined, expressions evaluated) instead of keeping its text.
        #[arg(long)]
        flatten: bool,
        #[command(flatten)]
        run: RunArgs,
    },
    /// Print each cycle's pass table: depth, increment, infeed point, chip area.
    Passes {
        file: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// JSON instead of a table.
        #[arg(long)]
        json: bool,
        #[arg(long, short = 'o')]
        output: Option<PathBuf>,
        #[command(flatten)]
        tool: ToolArgs,
        #[command(flatten)]
        run: RunArgs,
    },
    /// Report what the program will do wrong: controller alarms, rapid moves into the blank,
    /// feed and lead limits, run-up, depth and form. Exit status 2 on any error.
    Check {
        file: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// Diameter of the blank (program units); default: the cycle's crest line.
        #[arg(long, value_name = "D")]
        stock_diameter: Option<f64>,
        /// Z of the blank's face on the thread's start side (program units); default: where
        /// the thread starts.
        #[arg(long, value_name = "Z", allow_negative_numbers = true)]
        stock_start: Option<f64>,
        #[command(flatten)]
        tool: ToolArgs,
        #[command(flatten)]
        run: RunArgs,
    },
    /// Draw each cycle's pass diagram and XZ toolpath into one SVG.
    Plot {
        file: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// The SVG file to write (`-`: standard output).
        #[arg(long, short = 'o')]
        output: PathBuf,
        #[command(flatten)]
        tool: ToolArgs,
        #[command(flatten)]
        run: RunArgs,
    },
    /// Post an APT/CL file (THREAD, COUPLE, GOTO …) to a controller: native threading cycles where
    /// they reproduce the toolpath exactly, plain moves otherwise.
    Post {
        /// The CL file (`-` for standard input).
        file: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// Output file (`-` or absent: standard output). Written whole or not at all.
        #[arg(long, short = 'o')]
        output: Option<PathBuf>,
    },
    /// Rewrite a program for another controller: each threading cycle as the target's native cycle
    /// when reading it back gives the same motion, otherwise as plain moves with a comment saying why.
    Convert {
        file: PathBuf,
        /// The controller the program is written for (a built-in profile name).
        #[arg(long)]
        from: String,
        /// The controller to write for (a built-in profile name).
        #[arg(long)]
        to: String,
        #[arg(long, short = 'o')]
        output: Option<PathBuf>,
        /// A program with control flow: write the executed program as straight-line code (needed
        /// to convert such a program to another controller's language).
        #[arg(long)]
        flatten: bool,
        #[command(flatten)]
        run: RunArgs,
    },
    /// List the built-in controller profiles.
    Controllers,
    /// Print a standard thread's diameters (min/max), thread height and turning infeed depth:
    /// ISO metric (`M10`, `M10x1.25-6g`, `M8-4g6g`, `M12-6H`) or Unified (`"1/2-13 UNC-2A"`,
    /// `"#10-32 UNF"`). Without a class both sides are given (6g/6H, 2A/2B).
    Thread {
        /// The thread's name.
        name: Option<String>,
        /// JSON (values in the standard's units) instead of a table.
        #[arg(long)]
        json: bool,
        /// List every thread threadcut knows.
        #[arg(long, conflicts_with = "name")]
        list: bool,
    },
    /// Mill a standard thread by helical interpolation (Centroid TB029): a complete block of G2/G3
    /// full circles with absolute Z per turn, cutter compensation and lead-in/out.
    Mill(mill::MillArgs),
}

pub fn main() -> ExitCode {
    let cli = Cli::parse();
    match run(cli) {
        Ok(code) => code,
        Err(Failure::Quiet) => ExitCode::SUCCESS,
        Err(Failure::Usage(msg)) => {
            eprintln!("threadcut: {msg}");
            ExitCode::from(2)
        }
        Err(Failure::Input { file, diagnostic }) => {
            eprint!("{}", render::diagnostic(&file, &diagnostic));
            ExitCode::from(2)
        }
        Err(Failure::Other(msg)) => {
            eprintln!("threadcut: {msg}");
            ExitCode::from(1)
        }
    }
}

enum Failure {
    /// The reader of our output went away (`| head`): stop without a word.
    Quiet,
    Usage(String),
    Input {
        file: PathBuf,
        diagnostic: Box<Diagnostic>,
    },
    Other(String),
}

fn failure(file: &Path, e: Error) -> Failure {
    match e {
        Error::Input(d) => Failure::Input {
            file: file.to_owned(),
            diagnostic: Box::new(d),
        },
        Error::Io(e) if e.kind() == io::ErrorKind::BrokenPipe => Failure::Quiet,
        Error::Io(e) => Failure::Other(format!("cannot write the output: {e}")),
        Error::Setup(msg) => Failure::Usage(msg),
    }
}

fn run(cli: Cli) -> Result<ExitCode, Failure> {
    match cli.command {
        Command::Mill(args) => {
            mill::mill(args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Thread { name, json, list } => {
            mill::thread(name.as_deref(), json, list)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Controllers => {
            let mut out = io::stdout().lock();
            for (name, _) in BUILT_IN {
                let m = Machine::built_in(name).expect("built-in profiles parse");
                writeln!(out, "{name:<12} {}", m.description).map_err(io_failure)?;
            }
            for (name, _) in threadcut::mill::profile::BUILT_IN {
                let m = threadcut::mill::profile::MillProfile::built_in(name)
                    .expect("built-in profiles parse");
                writeln!(out, "{name:<14} (mill) {}", m.description).map_err(io_failure)?;
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Expand {
            file,
            machine,
            output,
            format,
            flatten,
            run,
        } => {
            let options = run.options(flatten)?;
            let mut input = open_input(&file)?;
            if post::is_apt(&file, &mut input) {
                match format {
                    ExpandFormat::Jsonl => post::expand_jsonl(&file, input, output.as_deref())?,
                    ExpandFormat::Gcode => {
                        let machine = load_machine(&machine)?;
                        post::post(&file, input, &machine, output.as_deref())?
                    }
                }
                return Ok(ExitCode::SUCCESS);
            }
            let machine = load_machine(&machine)?;
            let summary = output::write(&file, output.as_deref(), |out| match format {
                ExpandFormat::Gcode => program::expand_gcode_with(input, out, &machine, &options),
                ExpandFormat::Jsonl => program::expand_jsonl_with(input, out, &machine, &options),
            })?;
            warn(&file, &summary);
            Ok(ExitCode::SUCCESS)
        }
        Command::Post {
            file,
            machine,
            output,
        } => {
            let machine = load_machine(&machine)?;
            let input = open_input(&file)?;
            post::post(&file, input, &machine, output.as_deref())?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Convert {
            file,
            from,
            to,
            output,
            flatten,
            run,
        } => {
            let options = run.options(flatten)?;
            let load = |name: &str| {
                load_machine(&MachineArgs {
                    controller: Some(name.to_string()),
                    machine: None,
                })
            };
            let (from, to) = (load(&from)?, load(&to)?);
            let input = open_input(&file)?;
            let summary = output::write(&file, output.as_deref(), |out| {
                convert::convert(input, out, &from, &to, &options)
            })?;
            warn(&file, &summary);
            Ok(ExitCode::SUCCESS)
        }
        Command::Check {
            file,
            machine,
            stock_diameter,
            stock_start,
            tool,
            run,
        } => {
            let options = run.options(false)?;
            check::run(
                &file,
                &machine,
                stock_diameter,
                stock_start,
                &tool,
                &options,
            )
        }
        Command::Plot {
            file,
            machine,
            output,
            tool,
            run,
        } => {
            let options = run.options(false)?;
            plot::run(&file, &machine, &output, &tool, &options)
        }
        Command::Passes {
            file,
            machine,
            json,
            output,
            tool,
            run,
        } => {
            let options = run.options(false)?;
            let mut input = open_input(&file)?;
            if post::is_apt(&file, &mut input) {
                post::passes(&file, input, json, output.as_deref(), tool.tip()?)?;
                return Ok(ExitCode::SUCCESS);
            }
            let machine = load_machine(&machine)?;
            let tip = tool.tip()?;
            let summary = output::write(&file, output.as_deref(), |out| {
                passes(input, out, &machine, json, tip, &options)
            })?;
            warn(&file, &summary);
            Ok(ExitCode::SUCCESS)
        }
    }
}

fn io_failure(e: io::Error) -> Failure {
    if e.kind() == io::ErrorKind::BrokenPipe {
        Failure::Quiet
    } else {
        Failure::Other(e.to_string())
    }
}

fn warn(file: &Path, summary: &Summary) {
    for w in &summary.warnings {
        eprint!("{}", render::diagnostic(file, w));
    }
}

fn load_machine(args: &MachineArgs) -> Result<Machine, Failure> {
    if let Some(path) = &args.machine {
        let text = std::fs::read_to_string(path)
            .map_err(|e| Failure::Usage(format!("cannot read {}: {e}", path.display())))?;
        return Machine::from_toml(&text)
            .map_err(|e| Failure::Usage(format!("{}: {e}", path.display())));
    }
    let names = || {
        BUILT_IN
            .iter()
            .map(|(n, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    };
    match &args.controller {
        Some(name) => Machine::built_in(name).ok_or_else(|| {
            Failure::Usage(format!(
                "unknown controller `{name}` (built in: {})",
                names()
            ))
        }),
        None => Err(Failure::Usage(format!(
            "name the controller with --controller (built in: {}) or a profile with --machine",
            names()
        ))),
    }
}

fn open_input(file: &Path) -> Result<Box<dyn BufRead>, Failure> {
    if file.as_os_str() == "-" {
        return Ok(Box::new(BufReader::with_capacity(1 << 16, io::stdin())));
    }
    let f = File::open(file)
        .map_err(|e| Failure::Usage(format!("cannot open {}: {e}", file.display())))?;
    Ok(Box::new(BufReader::with_capacity(1 << 16, f)))
}

/// `threadcut passes` on G-code.
fn passes(
    input: Box<dyn BufRead>,
    out: &mut dyn Write,
    machine: &Machine,
    json: bool,
    tip: threadcut::sim::Tip,
    options: &program::Options,
) -> Result<Summary, Error> {
    let mut writer = passes::PassesWriter::begin(out, json, tip)?;
    let summary = program::run_with(input, machine, options, |modal, ev| {
        let Event::Cycle { job, .. } = ev else {
            return Ok(());
        };
        // X as the program writes it at the cycle (OmniTurn's G72/G73 and LinuxCNC's G7/G8 switch
        // it mid-program).
        let what = format!("{} cycle", job.controller);
        let decimals = machine.decimals(job.units) as usize + 1;
        writer.cycle(out, &job, modal.diameter_x, decimals, &what)
    })?;
    writer.end(out)?;
    Ok(summary)
}
