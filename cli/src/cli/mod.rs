//! Command-line interface: argument parsing, input and output files, rendering of diagnostics.
//!
//! Every message has one form (docs/cli.md): `error[E…]: message` and ` --> file:line:column`
//! with the source line where the program has a place for it, `error: message` where it has not
//! (usage, files, profiles), `warning: …` likewise, each followed by `  = help: …` lines; clap's
//! own errors are rewritten into it. Exit status: 0 done, 1 the output could not be written,
//! 2 bad input or usage (an empty program included).

mod ahead;
mod behind;
mod check;
mod input;
mod lookahead;
mod mill;
mod milling;
mod output;
mod passes;
mod plot;
mod post;
mod render;

use std::io::{self, BufRead, Write};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::OnceLock;

use clap::{Parser, Subcommand, ValueEnum};

use threadcut::diag::Diagnostic;
use threadcut::machine::{built_in_name, Machine, NameError, ProfileKind};
use threadcut::program::{self, Error, Summary};

#[derive(Parser)]
#[command(
    name = "threadcut",
    version,
    about = "Exact pass-by-pass motion for CNC thread-cutting cycles",
    after_help = "Exit status: 0 done, 1 the output could not be written, 2 bad input or usage (an empty program included)."
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

/// The program a command reads.
#[derive(clap::Args)]
struct InputArg {
    /// The program: G-code, or APT/CL (`.apt`, `.cl`, or a CL statement first); `-` reads
    /// standard input. Its line ending (LF or CRLF) is the output's.
    #[arg(value_name = "FILE")]
    file: PathBuf,
}

/// Where a command writes.
#[derive(clap::Args)]
struct OutputArg {
    /// Write to this file instead of standard output (`-` or absent: standard output). A file is
    /// written whole or not at all (a temporary file beside it, renamed at the end).
    #[arg(long, short = 'o', value_name = "OUT")]
    output: Option<PathBuf>,
}

#[derive(clap::Args)]
struct MachineArgs {
    /// Built-in controller profile, any case: gsk980, omniturn, ab9, fanuc, fanuc15, fanuc-b,
    /// haas, linuxcnc, sinumerik (`threadcut controllers` describes them).
    #[arg(long, short = 'c', value_name = "NAME")]
    controller: Option<String>,
    /// Machine profile (a TOML file like those in profiles/); used instead of --controller.
    #[arg(long, value_name = "FILE.toml")]
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

/// The stock the program's part is cut from; each value not given is the machine profile's
/// `[stock]` value, if it has one.
#[derive(clap::Args)]
struct StockArgs {
    /// Diameter of the bar (program units): the part every move of the program cuts; default:
    /// not known (only the surfaces the program cuts are facts; a thread's crest is assumed).
    #[arg(long, value_name = "D")]
    stock_diameter: Option<f64>,
    /// Z of the bar's face (program units); default: Z0 is assumed.
    #[arg(long, value_name = "Z", allow_negative_numbers = true)]
    stock_start: Option<f64>,
    /// Length of the bar from its face toward the chuck (program units); default: not known.
    #[arg(long, value_name = "L")]
    stock_length: Option<f64>,
    /// Diameter of a bore through the bar (a tube; program units); default: none is known.
    #[arg(long, value_name = "D")]
    stock_bore: Option<f64>,
}

impl StockArgs {
    /// The values given, each to be taken over the profile's ([`threadcut::commands::with_stock`]).
    fn given(&self) -> Result<threadcut::machine::Stock, Failure> {
        let check = |name: &str, v: Option<f64>, positive: bool| match v {
            Some(v) if !v.is_finite() || (positive && v <= 0.0) => Err(Failure::Usage(format!(
                "--stock-{name} {v}: expected a length{}",
                if positive { " above 0" } else { "" }
            ))),
            _ => Ok(v),
        };
        Ok(threadcut::machine::Stock {
            diameter: check("diameter", self.stock_diameter, true)?,
            face: check("start", self.stock_start, false)?,
            length: check("length", self.stock_length, true)?,
            bore: check("bore", self.stock_bore, true)?,
        })
    }
}

/// How a program with control flow (subroutines, loops, parameters) is run.
#[derive(clap::Args, Clone)]
struct RunArgs {
    /// Stop a program with control flow after N executed blocks (an endless loop ends with an
    /// error naming it).
    #[arg(long, value_name = "N", default_value_t = 1_000_000)]
    max_blocks: u64,
    /// A directory where calls find programs the program does not hold (LinuxCNC's name.ngc,
    /// Fanuc's O9010, O9010.nc, 9010.nc; repeat it to search several, in order).
    #[arg(long = "include", value_name = "DIR")]
    include: Vec<std::path::PathBuf>,
    /// Run this call of a subroutine the file defines instead of the file's own flow, as a GUI
    /// calls it: `--call 'o<thread> call [20] [2.5]'` (LinuxCNC), `--call 'G65 P9010 A20.'`
    /// (Fanuc).
    #[arg(long = "call", value_name = "CALL")]
    call: Option<String>,
    /// Where the tool is before the program's first line, as the program writes it at power-on
    /// (the profile's units; X on diameter where the control's X is): for a cycle shown without
    /// the lines that position the tool.
    #[arg(long, value_name = "X,Z", value_parser = parse_start, allow_hyphen_values = true)]
    start: Option<(f64, f64)>,
}

/// `--start X,Z`: two finite numbers.
fn parse_start(text: &str) -> Result<(f64, f64), String> {
    let expected = || format!("`{text}`: expected X,Z (two numbers, as --start 40,5)");
    let (x, z) = text.split_once(',').ok_or_else(expected)?;
    let number = |v: &str| {
        v.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .ok_or_else(expected)
    };
    Ok((number(x)?, number(z)?))
}

impl RunArgs {
    fn options(&self, flatten: bool, machine: &MachineArgs) -> Result<program::Options, Failure> {
        if self.max_blocks == 0 {
            return Err(Failure::Usage(
                "--max-blocks 0: expected at least 1".to_string(),
            ));
        }
        Ok(program::Options {
            max_blocks: self.max_blocks,
            flatten,
            library: self.library(machine),
            call: self.call.clone(),
            start: match self.start {
                Some((x, z)) => program::Start::At { x, z },
                None => program::Start::Unknown,
            },
        })
    }

    /// The directories calls search for programs (none: no library): the `--include`
    /// directories in their order, then the profile's `include` (relative to the profile
    /// file's directory). The messages read a called file's lines from the same library.
    fn library(&self, machine: &MachineArgs) -> Option<threadcut::interp::library::Library> {
        let mut dirs = self.include.clone();
        if let Some(path) = &machine.machine {
            // A profile that cannot be read is the command's error, given when it loads it.
            if let Ok(m) = load_machine(machine) {
                let base = path.parent().unwrap_or(std::path::Path::new("."));
                dirs.extend(m.include.iter().map(|d| base.join(d)));
            }
        }
        if dirs.is_empty() {
            return None;
        }
        Some(render::library(&dirs))
    }
}

/// `expand` and `post`: a program, or its motions.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum ProgramFormat {
    /// The program with each cycle replaced by plain moves in the controller's format.
    Gcode,
    /// One JSON object per motion, program units, X as a radius.
    Jsonl,
}

/// `passes` and `check`: a report for people or for programs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum ReportFormat {
    /// Text for people.
    Text,
    /// One JSON document.
    Json,
    /// JSON lines: one object per line (a cycle for `passes`, a finding for `check`).
    Jsonl,
}

/// `thread` and `controllers`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum TextJson {
    /// Text for people.
    Text,
    /// One JSON document.
    Json,
}

/// `plot`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum SvgFormat {
    /// One SVG picture.
    Svg,
}

/// `convert`.
#[derive(Clone, Copy, PartialEq, Eq, ValueEnum)]
enum GcodeFormat {
    /// The program for the target controller.
    Gcode,
}

#[derive(Subcommand)]
enum Command {
    /// Replace each threading cycle by plain moves (G0/G32 …); other blocks pass through unchanged.
    Expand(ExpandArgs),
    /// Print each cycle's pass table: depth, increment, infeed point, chip area.
    Passes(PassesArgs),
    /// Report what the program will do wrong: controller alarms, rapid moves into the blank,
    /// feed and lead limits, run-up and run-out, depth and form, and with --thread the thread
    /// against its class. Every assumption is stated. Exit status 2 on any error.
    Check(CheckArgs),
    /// Draw each thread's pass diagram and XZ toolpath into one SVG: the first 50 threads, or the
    /// one --cycle names; the picture says what was left out (standard error too, unless --cycle chose).
    Plot(PlotArgs),
    /// Post an APT/CL file (THREAD, COUPLE, GOTO …) to a controller: native threading cycles where
    /// they reproduce the toolpath exactly, plain moves otherwise.
    Post(PostArgs),
    /// Rewrite a program for another controller: each threading cycle as the target's native cycle
    /// when some choice of its words reads back as the same motion, otherwise as plain moves with a
    /// comment saying why; the other blocks in the target's words, its units and modes stated at
    /// the start. A block the target cannot express is an error naming the target's limit.
    Convert(ConvertArgs),
    /// List the built-in controller profiles (lathe, then milling).
    Controllers(ControllersArgs),
    /// Print a standard thread's diameters (min/max), thread height and turning infeed depth:
    /// ISO metric (`M10`, `M10x1.25-6g`, `M8-4g6g`, `M12-6H`) or Unified (`"1/2-13 UNC-2A"`,
    /// `"#10-32 UNF"`). Without a class both sides are given (6g/6H, 2A/2B).
    Thread(ThreadArgs),
    /// Mill a standard thread by helical interpolation (Centroid TB029): a complete block of G2/G3
    /// full circles with absolute Z per turn, cutter compensation and lead-in/out.
    Mill(mill::MillArgs),
}

/// The arguments of `threadcut expand`.
#[derive(clap::Args)]
struct ExpandArgs {
    #[command(flatten)]
    input: InputArg,
    #[command(flatten)]
    machine: MachineArgs,
    #[command(flatten)]
    output: OutputArg,
    /// The program (gcode), or one JSON object per motion (jsonl).
    #[arg(long, value_enum, default_value = "gcode")]
    format: ProgramFormat,
    /// A program with control flow: write the executed program as straight-line code (loops
    /// unrolled, calls inlined, expressions evaluated) instead of keeping its text.
    #[arg(long)]
    flatten: bool,
    #[command(flatten)]
    run: RunArgs,
}

/// The arguments of `threadcut passes`.
#[derive(clap::Args)]
struct PassesArgs {
    #[command(flatten)]
    input: InputArg,
    #[command(flatten)]
    machine: MachineArgs,
    /// A table (text), `{"cycles":[…]}` (json) or one cycle object per line (jsonl).
    #[arg(long, value_enum, default_value = "text")]
    format: ReportFormat,
    /// The same as --format json.
    #[arg(long, conflicts_with = "format")]
    json: bool,
    #[command(flatten)]
    output: OutputArg,
    #[command(flatten)]
    tool: ToolArgs,
    /// The stock, for each thread's blank (as `check` takes it).
    #[command(flatten)]
    stock: StockArgs,
    /// State what each thread will measure against this standard thread's class (`M20x2.5-6g`):
    /// the window of the pitch diameter and of the measurement over wires, and the change of the
    /// final depth to its middle. With --nose-radius or --tip-flat alone, the pitch diameter and
    /// the measurement over wires are stated without a class.
    #[arg(long, value_name = "NAME")]
    thread: Option<String>,
    /// The diameter of the measuring wires one owns (the thread's units with --thread, else the
    /// program's): the measurement over wires is over them (default: the best wire).
    #[arg(long, value_name = "D")]
    wire: Option<f64>,
    #[command(flatten)]
    mill: milling::MillArgs,
    #[command(flatten)]
    run: RunArgs,
}

/// The arguments of `threadcut check`.
#[derive(clap::Args)]
struct CheckArgs {
    #[command(flatten)]
    input: InputArg,
    #[command(flatten)]
    machine: MachineArgs,
    #[command(flatten)]
    stock: StockArgs,
    #[command(flatten)]
    tool: ToolArgs,
    /// Judge the thread cut against a standard thread's class limits (`M50x2-6g`,
    /// `"1/2-13 UNC-2A"`; any name `threadcut thread` knows).
    #[arg(long, value_name = "NAME")]
    thread: Option<String>,
    /// With --thread: the diameter of the measuring wires one owns (the thread's units): the
    /// measurement over wires the note states is over them (default: the best wire).
    #[arg(long, value_name = "D", requires = "thread")]
    wire: Option<f64>,
    #[command(flatten)]
    mill: milling::MillArgs,
    /// Text (diagnostics, notes, summary), JSON (`[{file, line, column, level, code,
    /// message, hint}]`) or JSON lines (one finding per line).
    #[arg(long, value_enum, default_value = "text")]
    format: ReportFormat,
    #[command(flatten)]
    output: OutputArg,
    #[command(flatten)]
    run: RunArgs,
}

/// The arguments of `threadcut plot`.
#[derive(clap::Args)]
struct PlotArgs {
    #[command(flatten)]
    input: InputArg,
    #[command(flatten)]
    machine: MachineArgs,
    #[command(flatten)]
    output: OutputArg,
    /// Draw only this thread (1 = the program's first; `threadcut passes` lists them in order).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    cycle: Option<u32>,
    /// Draw only the part the program makes (the stock, the part, the threads' teeth, the rapids
    /// into material), without the threads' panels: for big programs.
    #[arg(long, conflicts_with = "cycle")]
    part: bool,
    /// The picture's format.
    #[arg(long, value_enum, default_value = "svg")]
    format: SvgFormat,
    #[command(flatten)]
    tool: ToolArgs,
    #[command(flatten)]
    stock: StockArgs,
    #[command(flatten)]
    mill: milling::MillArgs,
    #[command(flatten)]
    run: RunArgs,
}

/// The arguments of `threadcut post`.
#[derive(clap::Args)]
struct PostArgs {
    /// The CL file (`-` reads standard input). Its line ending (LF or CRLF) is the output's.
    #[arg(value_name = "FILE")]
    file: PathBuf,
    #[command(flatten)]
    machine: MachineArgs,
    #[command(flatten)]
    output: OutputArg,
    /// The posted program (gcode), or one JSON object per motion (jsonl).
    #[arg(long, value_enum, default_value = "gcode")]
    format: ProgramFormat,
}

/// The arguments of `threadcut convert`.
#[derive(clap::Args)]
struct ConvertArgs {
    #[command(flatten)]
    input: InputArg,
    /// The controller the program is written for (a built-in profile name, any case).
    #[arg(long, value_name = "NAME", required_unless_present = "from_machine")]
    from: Option<String>,
    /// The machine profile (TOML) the program is written for; used instead of --from.
    #[arg(long, value_name = "FILE.toml")]
    from_machine: Option<PathBuf>,
    /// The controller to write for (a built-in profile name, any case).
    #[arg(long, value_name = "NAME", required_unless_present = "to_machine")]
    to: Option<String>,
    /// The machine profile (TOML) to write for; used instead of --to.
    #[arg(long, value_name = "FILE.toml")]
    to_machine: Option<PathBuf>,
    #[command(flatten)]
    output: OutputArg,
    /// The converted program.
    #[arg(long, value_enum, default_value = "gcode")]
    format: GcodeFormat,
    /// A program with control flow: write the executed program as straight-line code (needed
    /// for a controller without a macro language; for one with, the program keeps its
    /// structure without it).
    #[arg(long)]
    flatten: bool,
    /// Run as a LinuxCNC program filter (the INI's `[FILTER]` section: `nc = threadcut convert
    /// --filter --from fanuc --to linuxcnc`, LinuxCNC adding the file's path): the program to
    /// standard output, `FILTER_PROGRESS=N` lines on standard error as the file is read, and on
    /// a refusal the message on standard error and a non-zero exit status, which LinuxCNC shows
    /// (docs/linuxcnc-filter.md).
    #[arg(long, conflicts_with = "output")]
    filter: bool,
    /// The largest drift accepted of a lead the target cannot write exactly, over the thread, in
    /// the converted program's units (the default: a quarter of the thread's medium-class
    /// pitch-diameter tolerance, on the drift's pitch-diameter equivalent).
    #[arg(long, value_name = "VALUE")]
    max_lead_drift: Option<f64>,
    /// A named tool and the number that calls it on the other controller: `--tool
    /// THREAD_EXT_60=T0101` (tool 1, offset 1; `T4`: tool 4 with its own offset), a Sinumerik
    /// `T="THREAD_EXT_60" D1` written `T0101`, and `T0101` written `T="THREAD_EXT_60" D1` for
    /// Sinumerik; repeat it for each tool. It replaces the target profile's `[tools]` entry of
    /// the same name (docs/translation.md, "Tools by name").
    #[arg(long = "tool", value_name = "NAME=T0101", value_parser = tool_argument)]
    tools: Vec<(String, String)>,
    #[command(flatten)]
    run: RunArgs,
}

/// `NAME=T0101`, for `--tool`.
fn tool_argument(spec: &str) -> Result<(String, String), String> {
    threadcut::convert::tools::argument(spec)
}

/// The arguments of `threadcut controllers`.
#[derive(clap::Args)]
struct ControllersArgs {
    /// A list (text) or `[{name, kind, description}]` (json).
    #[arg(long, value_enum, default_value = "text")]
    format: TextJson,
    #[command(flatten)]
    output: OutputArg,
}

/// The arguments of `threadcut thread`.
#[derive(clap::Args)]
struct ThreadArgs {
    /// The thread's name (`threadcut thread --list` lists every one).
    name: Option<String>,
    /// A table (text) or JSON (values in the standard's units).
    #[arg(long, value_enum, default_value = "text")]
    format: TextJson,
    /// The same as --format json.
    #[arg(long, conflicts_with = "format")]
    json: bool,
    /// List every thread threadcut knows.
    #[arg(long, conflicts_with = "name")]
    list: bool,
    /// For a taper thread: the taper word of this lathe controller's threading cycle, for
    /// the thread placed by --face-z, --start-z and --length (any case).
    #[arg(long, short = 'c', value_name = "NAME")]
    controller: Option<String>,
    /// A machine profile (TOML) instead of --controller.
    #[arg(long, value_name = "FILE.toml")]
    machine: Option<PathBuf>,
    /// The internal thread (with --controller; default: the external one).
    #[arg(long)]
    internal: bool,
    /// Z of the part's face: the small end of an external taper thread, the opening of an
    /// internal one (the thread's units; default 0).
    #[arg(long, allow_negative_numbers = true)]
    face_z: Option<f64>,
    /// Z where the cycle starts (default: 3 pitches outside the face).
    #[arg(long, allow_negative_numbers = true)]
    start_z: Option<f64>,
    /// Thread length from the face (default: the standard's effective/useful thread).
    #[arg(long)]
    length: Option<f64>,
    /// The diameter of the measuring wires one owns (the thread's units): the measurement over
    /// wires with them (default: the best wire).
    #[arg(long, value_name = "D")]
    wire: Option<f64>,
    #[command(flatten)]
    output: OutputArg,
}

/// The command being run, for messages that point to another one.
static COMMAND: OnceLock<&'static str> = OnceLock::new();

fn command_name() -> &'static str {
    COMMAND.get().copied().unwrap_or("threadcut")
}

pub fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => return clap_failure(e),
    };
    let _ = COMMAND.set(match &cli.command {
        Command::Expand(_) => "expand",
        Command::Passes(_) => "passes",
        Command::Check(_) => "check",
        Command::Plot(_) => "plot",
        Command::Post(_) => "post",
        Command::Convert(_) => "convert",
        Command::Controllers(_) => "controllers",
        Command::Thread(_) => "thread",
        Command::Mill(_) => "mill",
    });
    match run(cli) {
        Ok(code) => code,
        Err(Failure::Quiet) => ExitCode::SUCCESS,
        Err(Failure::Usage(msg)) => {
            eprint!("{}", render::error(&msg));
            ExitCode::from(2)
        }
        Err(Failure::Input { file, diagnostic }) => {
            eprint!("{}", render::diagnostic(&file, &diagnostic));
            ExitCode::from(2)
        }
        Err(Failure::Other(msg)) => {
            eprint!("{}", render::error(&msg));
            ExitCode::from(1)
        }
    }
}

/// clap's own errors in the one message form: `error: …` and `  = help:`/`  = note:` lines
/// (help and version are printed as clap prints them).
fn clap_failure(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::from(e.exit_code().clamp(0, 255) as u8);
    }
    eprint!("{}", render::clap_error(&e.render().to_string()));
    ExitCode::from(2)
}

enum Failure {
    /// The reader of our output went away (`| head`): stop without a word.
    Quiet,
    /// Bad usage or input without a place in the program (exit status 2): the message, and
    /// `\n  = help: …` lines if any.
    Usage(String),
    Input {
        file: PathBuf,
        diagnostic: Box<Diagnostic>,
    },
    /// The output could not be written (exit status 1).
    Other(String),
}

/// An error writing the output (named by [`output::write`]).
impl From<io::Error> for Failure {
    fn from(e: io::Error) -> Failure {
        io_failure(e)
    }
}

fn failure(file: &Path, e: Error) -> Failure {
    match e {
        Error::Input(d) => Failure::Input {
            file: file.to_owned(),
            diagnostic: Box::new(d),
        },
        Error::Io(e) if e.kind() == io::ErrorKind::BrokenPipe => Failure::Quiet,
        Error::Io(e) => Failure::Other(format!("cannot write the output: {}", reason(&e))),
        Error::Setup(msg) => Failure::Usage(msg),
    }
}

/// The system's reason for an I/O error, without Rust's ` (os error N)` and without the paths
/// of temporary files that crates add: the innermost I/O error's text.
fn reason(e: &io::Error) -> String {
    let mut inner: &io::Error = e;
    let mut source = e.get_ref().map(|s| s as &(dyn std::error::Error + 'static));
    while let Some(s) = source {
        if let Some(io) = s.downcast_ref::<io::Error>() {
            inner = io;
        }
        source = s.source();
    }
    let text = inner.to_string();
    let text = match inner.raw_os_error() {
        Some(code) => text
            .strip_suffix(&format!(" (os error {code})"))
            .map(str::to_string)
            .unwrap_or(text),
        None if inner.get_ref().is_some() => inner.kind().to_string(),
        None => text,
    };
    text
}

/// Runs the command the command line names.
fn run(cli: Cli) -> Result<ExitCode, Failure> {
    match cli.command {
        Command::Mill(args) => {
            mill::mill(args)?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Thread(args) => run_thread(args),
        Command::Controllers(args) => {
            controllers(args.format, args.output.output.as_deref())?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Expand(args) => run_expand(args),
        Command::Post(args) => run_post(args),
        Command::Convert(args) => run_convert(args),
        Command::Check(args) => run_check(args),
        Command::Plot(args) => run_plot(args),
        Command::Passes(args) => run_passes(args),
    }
}

/// `threadcut thread`: a standard thread's data, or the list of every one.
fn run_thread(args: ThreadArgs) -> Result<ExitCode, Failure> {
    let cycle = taper_cycle_args(&args)?;
    let json = args.json || args.format == TextJson::Json;
    mill::thread(
        args.name.as_deref(),
        json,
        args.list,
        cycle,
        args.output.output.as_deref(),
        args.wire,
    )?;
    Ok(ExitCode::SUCCESS)
}

/// Whether `thread` places a taper thread on a lathe cycle: with --controller or --machine it
/// does; the placing flags without either are a usage error.
fn taper_cycle_args(args: &ThreadArgs) -> Result<Option<mill::CycleArgs>, Failure> {
    let placed =
        args.internal || args.face_z.is_some() || args.start_z.is_some() || args.length.is_some();
    match (&args.controller, &args.machine) {
        (None, None) if placed => Err(Failure::Usage(
            "--internal, --face-z, --start-z and --length place a taper thread on a lathe cycle: name the controller with --controller (or --machine)".into(),
        )),
        (None, None) => Ok(None),
        (controller, machine) => Ok(Some(mill::CycleArgs {
            machine: MachineArgs {
                controller: controller.clone(),
                machine: machine.clone(),
            },
            internal: args.internal,
            face_z: args.face_z,
            start_z: args.start_z,
            length: args.length,
        })),
    }
}

/// `threadcut expand`: a G-code program with its cycles as plain moves (or its motions), or an
/// APT/CL file posted (or its motions).
fn run_expand(args: ExpandArgs) -> Result<ExitCode, Failure> {
    if let Some(profile) = milling_profile(&args.machine) {
        return run_expand_mill(&args, &profile);
    }
    let options = args.run.options(args.flatten, &args.machine)?;
    let file = &args.input.file;
    let out = args.output.output.as_deref();
    let (mut reader, content, long) = input::open_long(file)?;
    if post::is_apt(file, &mut reader) {
        match args.format {
            ProgramFormat::Jsonl => post::expand_jsonl(file, reader, &content, out)?,
            ProgramFormat::Gcode => {
                let machine = load_machine(&args.machine)?;
                post::post(file, reader, &content, &machine, out)?
            }
        }
        return Ok(ExitCode::SUCCESS);
    }
    let machine = load_machine(&args.machine)?;
    let summary = output::write_moves(file, out, |out| {
        let summary = match args.format {
            ProgramFormat::Gcode => match long {
                // A long file's later parts are read on the second core (`lookahead`).
                Some(handle) => {
                    let stamp = lookahead::Stamp::of(&handle);
                    let mut look = lookahead::LookAhead::new(handle, machine.clone());
                    let run = program::expand_gcode_ahead(
                        reader,
                        out,
                        &machine,
                        &options,
                        Some(&mut look),
                    );
                    if stamp.is_some_and(|s| !s.unchanged()) {
                        return Err(Failure::Other(format!(
                            "{} changed while it was read: run again once it is written",
                            input::display(file)
                        )));
                    }
                    run
                }
                None => program::expand_gcode_to(reader, out, &machine, &options),
            },
            ProgramFormat::Jsonl => program::expand_jsonl_with(reader, out, &machine, &options),
        }
        .map_err(lib(file))?;
        not_empty(file, &content)?;
        Ok(summary)
    })?;
    warn(file, &summary);
    Ok(ExitCode::SUCCESS)
}

/// What a milling program's reading is told on the command line.
fn milling_given<'a>(
    mill: &'a milling::MillArgs,
    thread: Option<&'a str>,
    tool: &ToolArgs,
    wire: Option<f64>,
    run: &RunArgs,
) -> Result<milling::Given<'a>, Failure> {
    Ok(milling::Given {
        mill,
        thread,
        tip: tool.given_tip()?,
        wire,
        max_blocks: run.max_blocks,
    })
}

/// The milling profile `--controller` names, if it names one.
fn milling_profile(m: &MachineArgs) -> Option<threadcut::mill::profile::MillProfile> {
    if m.machine.is_some() {
        return None;
    }
    let name = built_in_name(m.controller.as_deref()?, ProfileKind::Mill).ok()?;
    threadcut::mill::profile::MillProfile::built_in(name)
}

/// `threadcut expand` on a milling profile: the program's motion (jsonl), or the program
/// flattened into plain moves (gcode).
fn run_expand_mill(
    args: &ExpandArgs,
    profile: &threadcut::mill::profile::MillProfile,
) -> Result<ExitCode, Failure> {
    use threadcut::millprog;
    let file = &args.input.file;
    let (reader, content) = input::open(file)?;
    let options = millprog::Options {
        max_blocks: args.run.max_blocks,
        ..millprog::Options::default()
    };
    let input_error = |d: Diagnostic| failure(file, Error::Input(d));
    output::write(file, args.output.output.as_deref(), |out| {
        match args.format {
            ProgramFormat::Jsonl => {
                let mut sink = millprog::output::Jsonl(out);
                millprog::run(reader, profile, &options, &mut sink)
            }
            ProgramFormat::Gcode => {
                millprog::output::Flat::new(out, profile).and_then(|mut sink| {
                    let summary = millprog::run(reader, profile, &options, &mut sink)?;
                    sink.finish()?;
                    Ok(summary)
                })
            }
        }
        .map_err(input_error)?;
        not_empty(file, &content)?;
        Ok(())
    })?;
    Ok(ExitCode::SUCCESS)
}

/// `threadcut post`: an APT/CL file for a controller (or its motions).
fn run_post(args: PostArgs) -> Result<ExitCode, Failure> {
    let file = &args.file;
    let out = args.output.output.as_deref();
    let (reader, content) = input::open(file)?;
    match args.format {
        ProgramFormat::Gcode => {
            let machine = load_machine(&args.machine)?;
            post::post(file, reader, &content, &machine, out)?;
        }
        ProgramFormat::Jsonl => post::expand_jsonl(file, reader, &content, out)?,
    }
    Ok(ExitCode::SUCCESS)
}

/// `threadcut convert`: a program rewritten from one controller's language to another's.
fn run_convert(args: ConvertArgs) -> Result<ExitCode, Failure> {
    let GcodeFormat::Gcode = args.format;
    let source = MachineArgs {
        controller: args.from,
        machine: args.from_machine,
    };
    let options = threadcut::convert::Options {
        run: args.run.options(args.flatten, &source)?,
        max_lead_drift: args.max_lead_drift,
        tools: args.tools,
    };
    let from = load_machine(&source)?;
    let to = load_machine(&MachineArgs {
        controller: args.to,
        machine: args.to_machine,
    })?;
    let file = &args.input.file;
    if args.filter {
        input::report_as_filter();
    }
    let (mut reader, content) = input::open(file)?;
    // A file that cannot be read says so before anything is written.
    reader.fill_buf().map_err(|e| {
        Failure::Usage(format!(
            "cannot read {}: {}",
            input::display(file),
            reason(&e)
        ))
    })?;
    // The converted program ends its lines as the source does (CRLF in, CRLF out).
    let summary = output::write(file, args.output.output.as_deref(), |out| {
        let report =
            threadcut::convert::convert(reader, out, &from, &to, &options).map_err(lib(file))?;
        not_empty(file, &content)?;
        Ok(report.summary)
    })?;
    warn(file, &summary);
    Ok(ExitCode::SUCCESS)
}

/// `threadcut check`: the program's findings ([`check::run`]).
fn run_check(args: CheckArgs) -> Result<ExitCode, Failure> {
    if let Some(profile) = milling_profile(&args.machine) {
        let given = milling_given(
            &args.mill,
            args.thread.as_deref(),
            &args.tool,
            args.wire,
            &args.run,
        )?;
        let out = args.output.output.as_deref();
        return milling::check(&args.input.file, &profile, &given, args.format, out);
    }
    check::run(
        &args.input.file,
        &args.machine,
        &check::Args {
            stock: args.stock.given()?,
            tool: &args.tool,
            thread: args.thread.as_deref(),
            wire: args.wire,
            format: args.format,
            output: args.output.output.as_deref(),
            run: &args.run.options(false, &args.machine)?,
        },
    )
}

/// `threadcut plot`: the program's threads drawn ([`plot::run`]).
fn run_plot(args: PlotArgs) -> Result<ExitCode, Failure> {
    let SvgFormat::Svg = args.format;
    if let Some(profile) = milling_profile(&args.machine) {
        let given = milling_given(&args.mill, None, &args.tool, None, &args.run)?;
        return milling::plot(
            &args.input.file,
            &profile,
            &given,
            args.output.output.as_deref(),
        );
    }
    plot::run(
        &args.input.file,
        &args.machine,
        &plot::Args {
            out: args.output.output.as_deref(),
            cycle: args.cycle.map(|n| n as usize),
            part: args.part,
            tool: &args.tool,
            stock: args.stock.given()?,
            run: &args.run.options(false, &args.machine)?,
        },
    )
}

/// `threadcut passes`: each cycle's pass table, of a G-code program or an APT/CL file. A G-code
/// program without a thread is said on standard error.
fn run_passes(args: PassesArgs) -> Result<ExitCode, Failure> {
    if let Some(profile) = milling_profile(&args.machine) {
        let given = milling_given(
            &args.mill,
            args.thread.as_deref(),
            &args.tool,
            args.wire,
            &args.run,
        )?;
        let format = if args.json {
            ReportFormat::Json
        } else {
            args.format
        };
        let out = args.output.output.as_deref();
        return milling::passes(&args.input.file, &profile, &given, format, out);
    }
    let mut options = args.run.options(false, &args.machine)?;
    // A cycle shown without the lines before it still has its pass table, where it does not
    // depend on the start point (docs/cli.md, "A cycle on its own").
    if options.start == program::Start::Unknown {
        options.start = program::Start::Unstated;
    }
    let format = if args.json {
        ReportFormat::Json
    } else {
        args.format
    };
    let file = &args.input.file;
    let out = args.output.output.as_deref();
    let replay = input::Replay::new(file)?;
    let (mut reader, content) = replay.first(file)?;
    if post::is_apt(file, &mut reader) {
        post::passes(file, reader, &content, format, out, args.tool.tip()?)?;
        return Ok(ExitCode::SUCCESS);
    }
    let machine = load_machine(&args.machine)?;
    let tip = args.tool.tip()?;
    let check = threadcut::commands::with_stock(
        threadcut::check::Options {
            tip: args.tool.given_tip()?,
            max_blocks: options.max_blocks,
            library: options.library.clone(),
            call: options.call.clone(),
            start: options.start,
            ..threadcut::check::Options::default()
        },
        args.stock.given()?,
        Some(&machine),
    );
    // Each thread's blank, from `check` over the same program.
    let mut blanks =
        threadcut::commands::Blanks::of(reader, threadcut::check::Source::Gcode(&machine), &check);
    let reader = replay
        .again()
        .map_err(|e| Failure::Usage(format!("cannot read {}: {}", file.display(), reason(&e))))?;
    let measuring = measuring(&args, machine.units)?;
    let (summary, count) = output::write(file, out, |out| {
        let writer = passes::PassesWriter::begin(out, format, tip)?;
        let writer = match measuring {
            Some(m) => writer.measuring(m),
            None => writer,
        };
        let done =
            passes(reader, out, writer, &machine, &options, &mut blanks).map_err(lib(file))?;
        not_empty(file, &content)?;
        Ok(done)
    })?;
    warn(file, &summary);
    // A file of subroutines was told so (and how to call one) among the warnings.
    if count == 0 && summary.uncalled.is_empty() {
        no_thread(file, &thread_codes(&machine));
    }
    Ok(ExitCode::SUCCESS)
}

/// What `passes` is to state each thread will measure: with --thread, or a tip given.
fn measuring(
    args: &PassesArgs,
    units: threadcut::units::Units,
) -> Result<Option<passes::Measuring>, Failure> {
    let thread = match &args.thread {
        Some(name) => Some(threadcut::thread::standard::lookup(name).map_err(mill::usage)?),
        None => None,
    };
    let tip = args.tool.given_tip()?;
    if thread.is_none() && tip.is_none() {
        if args.wire.is_some() {
            return Err(Failure::Usage(
                "--wire: the measurement over wires needs the tool's form: give --thread, --nose-radius or --tip-flat".into(),
            ));
        }
        return Ok(None);
    }
    let wire = match args.wire {
        Some(w) if !(w.is_finite() && w > 0.0) => {
            return Err(Failure::Usage(format!(
                "--wire {w}: a measuring wire's diameter is a positive length"
            )))
        }
        Some(w) => Some(thread.as_ref().map_or(units, |t| t.units).to_mm(w)),
        None => None,
    };
    Ok(Some(passes::Measuring { tip, thread, wire }))
}

/// An empty program (nothing but blanks) is an error: the run stops before its output is kept.
fn not_empty(file: &Path, content: &input::Content) -> Result<(), Failure> {
    if content.empty() {
        return Err(input::Content::failure(file));
    }
    Ok(())
}

/// A library error of a run on `file`.
fn lib(file: &Path) -> impl Fn(Error) -> Failure + '_ {
    move |e| failure(file, e)
}

fn io_failure(e: io::Error) -> Failure {
    if e.kind() == io::ErrorKind::BrokenPipe {
        Failure::Quiet
    } else {
        Failure::Other(format!("cannot write the output: {}", reason(&e)))
    }
}

/// `threadcut controllers`: the library's list ([`threadcut::commands::controllers`]).
fn controllers(format: TextJson, out: Option<&Path>) -> Result<(), Failure> {
    use threadcut::commands::{self, Kind};
    let list = commands::controllers();
    output::write(Path::new("-"), out, |w| {
        match format {
            TextJson::Text => {
                for c in &list {
                    let kind = if c.kind == Kind::Mill { "(mill) " } else { "" };
                    writeln!(w, "{:<14} {kind}{}", c.name, c.description)?;
                }
            }
            TextJson::Json => {
                serde_json::to_writer_pretty(&mut *w, &list).map_err(io::Error::from)?;
                writeln!(w)?;
            }
        }
        Ok(())
    })
}

/// The codes a machine's controller threads with, as `G32, G76, G92`.
fn thread_codes(machine: &Machine) -> String {
    threadcut::commands::thread_codes(threadcut::check::Source::Gcode(machine))
}

/// A program with no thread: said on standard error, naming what the controller threads with.
/// Not an error (exit status 0): the program was read, and there is nothing in it to show.
fn no_thread(file: &Path, codes: &str) {
    eprint!(
        "{}",
        render::warning(&format!(
            "no thread found in {}: no threading cycle and no synchronised move\n  = help: this controller threads with {codes}; is it the right --controller?",
            input::display(file)
        ))
    );
}

fn warn(file: &Path, summary: &Summary) {
    for w in &summary.warnings {
        eprint!("{}", render::diagnostic(file, w));
    }
}

/// The lathe machine a command is given: a profile file, or a built-in profile by name.
fn load_machine(args: &MachineArgs) -> Result<Machine, Failure> {
    if let Some(path) = &args.machine {
        let text = std::fs::read_to_string(path).map_err(|e| {
            Failure::Usage(format!("cannot read {}: {}", path.display(), reason(&e)))
        })?;
        return Machine::from_toml(&text).map_err(|e| {
            // The place in the profile, as a diagnostic's ` --> file:line:column`.
            let place = e.span().map_or(String::new(), |span| {
                let before = &text[..span.start.min(text.len())];
                let line = before.matches('\n').count() + 1;
                let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                format!("\n --> {}:{line}:{column}", path.display())
            });
            Failure::Usage(format!(
                "{} is not a machine profile: {}{place}",
                path.display(),
                e.message().trim_end()
            ))
        });
    }
    match &args.controller {
        Some(name) => built_in_name(name, ProfileKind::Lathe)
            .map(|n| Machine::built_in(n).expect("built-in profiles parse"))
            .map_err(|e| Failure::Usage(name_error(name, e, ProfileKind::Lathe))),
        None => Err(Failure::Usage(format!(
            "name the controller with --controller (built in: {}) or a profile with --machine",
            ProfileKind::Lathe.names().join(", ")
        ))),
    }
}

/// What a name that is no built-in profile of the kind wanted means, for this command.
fn name_error(name: &str, e: NameError, wanted: ProfileKind) -> String {
    let command = command_name();
    match e {
        NameError::OtherKind {
            name: other,
            kind: ProfileKind::Mill,
        } => format!(
            "`{name}` is a milling profile, and `threadcut {command}` reads lathe programs\n  = help: read a milling program's moves with `threadcut expand --controller {other} --format jsonl`; write a thread-milling program with `threadcut mill --controller {other} …`; lathe controllers: {}",
            ProfileKind::Lathe.names().join(", ")
        ),
        NameError::OtherKind {
            name: other,
            kind: ProfileKind::Lathe,
        } => format!(
            "`{name}` is a lathe controller, and `threadcut mill` writes thread-milling programs\n  = help: for a lathe use `threadcut expand`, `passes`, `check` or `plot` with --controller {other}; milling profiles: {}",
            ProfileKind::Mill.names().join(", ")
        ),
        NameError::Unknown { suggestion } => {
            let known = wanted.names().join(", ");
            match suggestion {
                Some(s) => format!(
                    "unknown controller `{name}`\n  = help: did you mean `{s}`? (built in: {known})"
                ),
                None => format!("unknown controller `{name}`\n  = help: built in: {known}"),
            }
        }
    }
}

/// `threadcut passes` on G-code.
fn passes(
    input: Box<dyn BufRead>,
    out: &mut dyn Write,
    mut writer: passes::PassesWriter,
    machine: &Machine,
    options: &program::Options,
    blanks: &mut threadcut::commands::Blanks,
) -> Result<(Summary, u32), Error> {
    let mut count = 0;
    let summary = threadcut::threads::each_gcode_with(input, machine, None, options, |t| {
        count += 1;
        let decimals = machine.decimals(t.job.units) as usize + 1;
        let blank = blanks.take(t.job.line);
        writer.thread_with(out, &t, decimals, "", blank)
    })?;
    writer.end(out)?;
    Ok((summary, count))
}
