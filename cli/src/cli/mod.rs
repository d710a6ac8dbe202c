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

use threadcut::commands::{self, Source};
use threadcut::diag::Diagnostic;
use threadcut::machine::Machine;
use threadcut::program::{Error, Summary};

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

    /// The tip when one of the flags gives it.
    fn given_tip(&self) -> Result<Option<threadcut::sim::Tip>, Failure> {
        if self.nose_radius.is_none() && self.tip_flat.is_none() {
            return Ok(None);
        }
        self.tip().map(Some)
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
    },
    /// Report what the program will do wrong: controller alarms, rapid moves into the blank,
    /// feed and lead limits, run-up and run-out, depth and form, and with --thread the thread
    /// against its class. Every assumption is stated. Exit status 2 on any error.
    Check {
        /// The program: G-code, or APT/CL (`.apt`, `.cl`, or a CL statement first).
        file: PathBuf,
        #[command(flatten)]
        machine: MachineArgs,
        /// Diameter of the blank (program units); default: the thread's crest is assumed.
        #[arg(long, value_name = "D")]
        stock_diameter: Option<f64>,
        /// Z of the blank's face on the thread's start side (program units); default: Z0 is
        /// assumed when the thread runs into the part through it.
        #[arg(long, value_name = "Z", allow_negative_numbers = true)]
        stock_start: Option<f64>,
        #[command(flatten)]
        tool: ToolArgs,
        /// Judge the thread cut against a standard thread's class limits (`M50x2-6g`,
        /// `"1/2-13 UNC-2A"`; any name `threadcut thread` knows).
        #[arg(long, value_name = "NAME")]
        thread: Option<String>,
        /// Text (diagnostics, notes, summary) or JSON (`[{file, line, column, level, code,
        /// message, hint}]`).
        #[arg(long, value_enum, default_value = "text")]
        format: check::Format,
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
        /// For a taper thread: the taper word of this lathe controller's threading cycle, for
        /// the thread placed by --face-z, --start-z and --length.
        #[arg(long, short = 'c')]
        controller: Option<String>,
        /// The internal thread (with --controller; default: the external one).
        #[arg(long, requires = "controller")]
        internal: bool,
        /// Z of the part's face: the small end of an external taper thread, the opening of an
        /// internal one (the thread's units; default 0).
        #[arg(long, allow_negative_numbers = true, requires = "controller")]
        face_z: Option<f64>,
        /// Z where the cycle starts (default: 3 pitches outside the face).
        #[arg(long, allow_negative_numbers = true, requires = "controller")]
        start_z: Option<f64>,
        /// Thread length from the face (default: the standard's effective/useful thread).
        #[arg(long, requires = "controller")]
        length: Option<f64>,
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
        Command::Thread {
            name,
            json,
            list,
            controller,
            internal,
            face_z,
            start_z,
            length,
        } => {
            let cycle = controller.map(|c| mill::CycleArgs {
                controller: c,
                internal,
                face_z,
                start_z,
                length,
            });
            mill::thread(name.as_deref(), json, list, cycle)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Controllers => {
            let mut out = io::stdout().lock();
            for c in commands::controllers() {
                let (name, description) = (c.name, &c.description);
                match c.kind {
                    commands::Kind::Lathe => writeln!(out, "{name:<12} {description}"),
                    commands::Kind::Mill => writeln!(out, "{name:<14} (mill) {description}"),
                }
                .map_err(io_failure)?;
            }
            Ok(ExitCode::SUCCESS)
        }
        Command::Expand {
            file,
            machine,
            output,
            format,
        } => {
            let mut input = open_input(&file)?;
            let apt = post::is_apt(&file, &mut input);
            // APT/CL written as JSON lines needs no controller; posted to G-code it does.
            let machine = if apt && matches!(format, ExpandFormat::Jsonl) {
                None
            } else {
                Some(load_machine(&machine)?)
            };
            let source = match (apt, &machine) {
                (false, Some(m)) => Source::Gcode(m),
                _ => Source::Apt(machine.as_ref()),
            };
            let format = match format {
                ExpandFormat::Gcode => commands::ExpandFormat::Gcode,
                ExpandFormat::Jsonl => commands::ExpandFormat::Jsonl,
            };
            let summary = output::write(&file, output.as_deref(), |out| {
                commands::expand(input, source, format, out)
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
        } => {
            let load = |name: &str| {
                load_machine(&MachineArgs {
                    controller: Some(name.to_string()),
                    machine: None,
                })
            };
            let (from, to) = (load(&from)?, load(&to)?);
            let input = open_input(&file)?;
            let summary = output::write(&file, output.as_deref(), |out| {
                convert::convert(input, out, &from, &to)
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
            thread,
            format,
        } => check::run(
            &file,
            &machine,
            &check::Args {
                stock_diameter,
                stock_start,
                tool: &tool,
                thread: thread.as_deref(),
                format,
            },
        ),
        Command::Plot {
            file,
            machine,
            output,
            tool,
        } => plot::run(&file, &machine, &output, &tool),
        Command::Passes {
            file,
            machine,
            json,
            output,
            tool,
        } => {
            let mut input = open_input(&file)?;
            // APT/CL needs no controller; G-code is read by the controller's dialect.
            let machine = if post::is_apt(&file, &mut input) {
                None
            } else {
                Some(load_machine(&machine)?)
            };
            let source = machine.as_ref().map_or(Source::Apt(None), Source::Gcode);
            let tip = tool.tip()?;
            let run = output::write(&file, output.as_deref(), |out| {
                if json {
                    commands::passes_json(input, source, tip, out)
                } else {
                    passes::text(input, source, tip, out)
                }
            })?;
            warn(&file, &run.summary);
            if run.threads == 0 {
                no_thread(&file, &commands::thread_codes(source));
            }
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

/// A program with no thread: said on standard error, naming what the controller threads with.
fn no_thread(file: &Path, codes: &str) {
    eprintln!(
        "threadcut: {}: {}",
        file.display(),
        commands::no_thread(codes)
    );
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
    match &args.controller {
        Some(name) => Machine::named(name).map_err(Failure::Usage),
        None => Err(Failure::Usage(format!(
            "name the controller with --controller (built in: {}) or a profile with --machine",
            Machine::names().join(", ")
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
