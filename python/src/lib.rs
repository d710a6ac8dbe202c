//! threadcut for Python: the `threadcut` commands as functions over the library's
//! `threadcut::commands` (and `check`, `apt::post`, `mill::Request`, `StandardThread::to_json`), the
//! same functions the command line calls, so that a function's data is the command's JSON, parsed
//! by Python's own `json` module.
//!
//! This crate only converts: Python values in, the library's results out, the library's errors as
//! `InputError` and its warnings as `InputWarning`. The signatures and their documentation are in
//! `threadcut.pyi`.

use std::path::Path;

mod milling;

use pyo3::create_exception;
use pyo3::exceptions::{PyUserWarning, PyValueError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyList};

use threadcut::check::{self, Report};
use threadcut::commands::{self, ExpandFormat, Source};
use threadcut::diag::Diagnostic;
use threadcut::interp::library::{Dirs, Library};
use threadcut::machine::{built_in_name, Machine, NameError, ProfileKind, Stock};
use threadcut::mill::profile::MillProfile;
use threadcut::mill::{Comp, Direction, Hand, LeadIn, Request, Side};
use threadcut::program::{Error, Options, Start, Summary};
use threadcut::sim::Tip;
use threadcut::thread::standard;
use threadcut::units::Units;

create_exception!(
    threadcut,
    InputError,
    PyValueError,
    "Bad input: a program the controller refuses, an unknown controller or thread, a bad option.\n\n`str(error)` is the command line's one-line form: `<string>:2:8: error[E004]: message` for a\nplace in the program (the program is named `<string>`), `error[E004]: message` for a thread\nname or a milling option, `profile.toml:3:1: error: message` for a machine profile, and\n`error: message` for an error with no code (an unknown controller, a bad keyword value)."
);
create_exception!(
    threadcut,
    InputWarning,
    PyUserWarning,
    "A finding worth a word that does not stop the function (the command line's warnings).\n\nIt has the attributes of `InputError` (`file`, `line`, `column`, `code`, `message`, `hint`),\nand `str(warning)` is the same one-line form with `warning` for `error`."
);

/// The file name of a program given as text, in messages.
const PROGRAM: &str = "<string>";

/// What an `InputError` or `InputWarning` carries.
struct Problem {
    file: Option<String>,
    line: Option<u32>,
    column: Option<u32>,
    code: Option<&'static str>,
    message: String,
    hint: Option<String>,
    /// `str()`: the command line's one-line form.
    text: String,
}

impl Problem {
    /// A diagnostic of the library; `file` is where its line and column are.
    fn diagnostic(d: &Diagnostic, file: Option<&str>) -> Problem {
        let placed = d.span.line > 0;
        Problem {
            file: file.map(str::to_string),
            line: placed.then_some(d.span.line),
            column: placed.then_some(d.span.column),
            code: Some(d.code.as_str()),
            message: d.message.clone(),
            hint: d.hint.clone(),
            text: d.headline(file),
        }
    }

    /// An error with no code and no place: an unknown controller, a bad option.
    fn usage(message: impl Into<String>) -> Problem {
        let message = message.into();
        Problem {
            file: None,
            line: None,
            column: None,
            code: None,
            text: format!("error: {message}"),
            message,
            hint: None,
        }
    }

    /// A warning with no code and no place (the milling plan's).
    fn plain_warning(message: &str) -> Problem {
        Problem {
            text: format!("warning: {message}"),
            ..Problem::usage(message)
        }
    }

    fn fill(&self, obj: &Bound<'_, PyAny>) -> PyResult<()> {
        obj.setattr("file", self.file.as_deref())?;
        obj.setattr("line", self.line)?;
        obj.setattr("column", self.column)?;
        obj.setattr("code", self.code)?;
        obj.setattr("message", self.message.as_str())?;
        obj.setattr("hint", self.hint.as_deref())?;
        Ok(())
    }

    fn error(self, py: Python<'_>) -> PyErr {
        let err = InputError::new_err(self.text.clone());
        if let Err(e) = self.fill(err.value(py).as_any()) {
            return e;
        }
        err
    }

    /// Issues the problem as an `InputWarning` (an error if the warnings filter says so).
    fn warn(self, py: Python<'_>) -> PyResult<()> {
        let w = py.get_type::<InputWarning>().call1((self.text.clone(),))?;
        self.fill(&w)?;
        py.import("warnings")?
            .call_method1("warn", (w, py.None(), 1))?;
        Ok(())
    }
}

/// A run's error as a Python exception: the program's diagnostics at their place in it.
fn run_error(py: Python<'_>, e: Error) -> PyErr {
    match e {
        Error::Input(d) => Problem::diagnostic(&d, Some(PROGRAM)).error(py),
        Error::Setup(msg) => Problem::usage(msg).error(py),
        Error::Io(e) => e.into(),
    }
}

/// The run's warnings (the dialect's, at their place in the program) as `InputWarning`s.
fn warn_all(py: Python<'_>, summary: &Summary) -> PyResult<()> {
    for w in &summary.warnings {
        Problem::diagnostic(w, Some(PROGRAM)).warn(py)?;
    }
    Ok(())
}

fn warn_no_thread(py: Python<'_>, threads: u32, source: Source) -> PyResult<()> {
    if threads == 0 {
        Problem::plain_warning(&commands::no_thread(&commands::thread_codes(source))).warn(py)?;
    }
    Ok(())
}

/// `machine=`: a path (`str`, `os.PathLike`) or an object with `read()` (an open file,
/// `io.StringIO(toml_text)`): its TOML text and the name to give in messages.
fn profile_text(py: Python<'_>, machine: &Bound<'_, PyAny>) -> PyResult<(String, String)> {
    if machine.hasattr("read")? {
        let text: String = machine.call_method0("read")?.extract()?;
        let name = machine
            .getattr("name")
            .ok()
            .and_then(|n| n.extract::<String>().ok())
            .unwrap_or_else(|| "<machine>".to_string());
        return Ok((text, name));
    }
    // Python reads the file, so that a missing one is Python's own FileNotFoundError with its name.
    let path: String = py
        .import("os")?
        .call_method1("fspath", (machine,))?
        .extract()?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("encoding", "utf-8")?;
    let text: String = py
        .import("pathlib")?
        .call_method1("Path", (&path,))?
        .call_method("read_text", (), Some(&kwargs))?
        .extract()?;
    Ok((text, path))
}

/// The machine to read the program with: the built-in profile `controller`, or the profile
/// `machine` names, which must be that controller's (its name or its dialect).
fn resolve(
    py: Python<'_>,
    controller: &str,
    machine: Option<&Bound<'_, PyAny>>,
) -> PyResult<Machine> {
    let Some(machine) = machine.filter(|m| !m.is_none()) else {
        let name = built_in_name(controller, ProfileKind::Lathe)
            .map_err(|e| name_problem(controller, e, ProfileKind::Lathe).error(py))?;
        return Ok(Machine::built_in(name).expect("built-in profiles parse"));
    };
    let (text, name) = profile_text(py, machine)?;
    let m = Machine::from_toml(&text).map_err(|e| {
        let (line, column) = e.span().map_or((None, None), |s| {
            let (l, c) = line_column(&text, s.start);
            (Some(l), Some(c))
        });
        let message = e.message().trim().to_string();
        let text = match (line, column) {
            (Some(l), Some(c)) => format!("{name}:{l}:{c}: error: {message}"),
            _ => format!("{name}: error: {message}"),
        };
        Problem {
            file: Some(name.clone()),
            line,
            column,
            code: None,
            message,
            hint: None,
            text,
        }
        .error(py)
    })?;
    if m.name != controller && m.dialect != controller {
        return Err(Problem::usage(format!(
            "the machine profile {name} is `{}`, for the {} dialect, not the controller `{controller}`: name the profile's controller (`{}`), or leave machine out to use the built-in `{controller}`",
            m.name, m.dialect, m.dialect
        ))
        .error(py));
    }
    Ok(m)
}

/// A controller name that is no built-in profile of the kind a function wants: the command line's
/// message, with the function to call instead where the name is of the other kind.
fn name_problem(given: &str, e: NameError, wanted: ProfileKind) -> Problem {
    let (message, hint) = match e {
        NameError::OtherKind {
            name,
            kind: ProfileKind::Mill,
        } => (
            format!("`{given}` is a milling profile, and this function reads lathe programs"),
            format!(
                "write a thread-milling program for it with `threadcut.mill(..., controller=\"{name}\")`; lathe controllers: {}",
                ProfileKind::Lathe.names().join(", ")
            ),
        ),
        NameError::OtherKind {
            name,
            kind: ProfileKind::Lathe,
        } => (
            format!("`{given}` is a lathe controller, and `threadcut.mill` writes thread-milling programs"),
            format!(
                "for a lathe use `threadcut.expand`, `passes`, `check` or `plot_svg` with controller \"{name}\"; milling profiles: {}",
                ProfileKind::Mill.names().join(", ")
            ),
        ),
        NameError::Unknown { suggestion } => {
            let known = wanted.names().join(", ");
            (
                format!("unknown controller `{given}`"),
                match suggestion {
                    Some(s) => format!("did you mean `{s}`? (built in: {known})"),
                    None => format!("built in: {known}"),
                },
            )
        }
    };
    Problem {
        text: format!("error: {message}"),
        hint: Some(hint),
        ..Problem::usage(message)
    }
}

/// The 1-based line and column (bytes) of byte `at` of `text`.
fn line_column(text: &str, at: usize) -> (u32, u32) {
    let before = &text.as_bytes()[..at.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let start = before
        .iter()
        .rposition(|&b| b == b'\n')
        .map_or(0, |i| i + 1);
    (line as u32, (before.len() - start + 1) as u32)
}

/// APT/CL or G-code for `machine`, from the program's text.
fn source<'m>(program: &str, machine: &'m Machine) -> Source<'m> {
    commands::source(Path::new(""), program.as_bytes(), Some(machine))
        .unwrap_or(Source::Gcode(machine))
}

fn json_loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

/// The run's options with `start=(x, z)` (`--start X,Z`: the tool before the first line), else
/// `otherwise` (`Start::Unstated` for `passes`: a cycle on its own gives its table), and the
/// directories calls search (`include=`, `--include`).
fn run_options(
    py: Python<'_>,
    start: Option<(f64, f64)>,
    otherwise: Start,
    include: Option<Vec<std::path::PathBuf>>,
) -> PyResult<Options> {
    let start = match start {
        Some((x, z)) if x.is_finite() && z.is_finite() => Start::At { x, z },
        Some((x, z)) => {
            return Err(Problem::usage(format!(
                "start=({x}, {z}): expected two finite numbers, X and Z"
            ))
            .error(py))
        }
        None => otherwise,
    };
    Ok(Options {
        start,
        library: library(include),
        ..Options::default()
    })
}

/// Text the library wrote (UTF-8: the program came in as `str`).
fn text(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// The library of the `include` keyword's directories (issue 25: `--include DIR`): none without.
fn library(include: Option<Vec<std::path::PathBuf>>) -> Option<Library> {
    include
        .filter(|dirs| !dirs.is_empty())
        .map(|dirs| Library::new(Dirs::new(dirs)))
}

/// The built-in controller profiles, as `threadcut controllers` lists them: the lathe
/// controllers, then the milling ones (`centroid`, `fanuc-mill`, `linuxcnc-mill`, for `mill`).
#[pyfunction(name = "controllers")]
fn controllers_py() -> Vec<&'static str> {
    commands::controllers()
        .into_iter()
        .map(|c| c.name)
        .collect()
}

/// Each thread's pass table: the `cycles` of `threadcut passes --json`.
///
/// One dict per thread (a cycle, or passes written as plain synchronised moves): `line`,
/// `controller`, `units` (`"mm"` or `"inch"`), `source` (`"cycle"` or `"moves"`), `depth_from`
/// (`"crest"` or `"first_pass"`) and `passes`, one dict per pass: `n`, `kind` (`"rough"` or
/// `"finish"`), `depth` (radius, from the crest), `increment`, `x` (as the program writes it)
/// and `z` of the infeed point, `area` and `share` of a sharp V of the tool angle, and the
/// simulated `sim_area`, `sim_share`, `cutting_flank` and `chip_thickness` (None where the section
/// cannot be simulated), and for G-code `blank`: the thread's blank as `check` takes it, `{crest, crest_from,
/// face, face_from}` (the crest a diameter; `*_from` `"measured"` on the part the program turned,
/// `"given"`, `"assumed"` or `"unknown"`). Program units. The stock keywords are `check`'s; each
/// not given is the machine profile's `[stock]` value, if any. With `thread` (a standard thread's
/// name, as `check` takes it) each dict has `measure`: what the thread will measure (`pitch_diameter`
/// as cut, `wire`, `m` over it, the class's `pitch_diameter_min`/`_max`, `m_min`/`m_max`, the
/// `deeper` change of the final depth to the window's middle, and `assumed`), or `{not_stated}`
/// with the reason; `wire` the measuring wire one owns (the thread's units).
///
/// `start=(x, z)` places the tool before the program's first line, as the program writes it at
/// power-on (the profile's units, X on diameter where the control's X is; `--start X,Z`).
/// Without it, a cycle whose start point is not known (a cycle shown on its own) still gives its
/// pass table where the table does not depend on the start (Fanuc-family G76 and G92, the
/// one-block G76, GSK's G78): its `z` is None and `start_unknown` (`{axes, note}`) says what is
/// not known; LinuxCNC's G76, whose passes are placed from the drive line, raises `InputError`.
///
/// A milling controller (`fanuc-mill`, `haas-mill`, `linuxcnc-mill`, `centroid`) gives a dict
/// instead, `threadcut passes --format json`'s: `milled`, one dict per milled thread (its axis,
/// `lead`, `starts`, `pitch`, `hand`, `direction`, `side` and `side_from`, `climb`,
/// `root_diameter`, and `passes`, one dict per helix), and `taps`, one per tapping cycle; with
/// `check`'s milling keywords.
///
/// A program with no thread gives `[]` and an `InputWarning`. Raises `InputError` for a program
/// the controller refuses (at its line and column) or an unknown controller.
#[pyfunction(name = "passes")]
#[pyo3(signature = (program, controller, *, machine=None, thread=None, wire=None, stock_diameter=None, stock_start=None, stock_length=None, stock_bore=None, include=None, start=None, internal=None, tool_diameter=None, teeth=None, tools=None))]
#[allow(clippy::too_many_arguments)]
fn passes_py<'py>(
    py: Python<'py>,
    program: String,
    controller: &str,
    machine: Option<&Bound<'py, PyAny>>,
    thread: Option<&str>,
    wire: Option<f64>,
    stock_diameter: Option<f64>,
    stock_start: Option<f64>,
    stock_length: Option<f64>,
    stock_bore: Option<f64>,
    include: Option<Vec<std::path::PathBuf>>,
    start: Option<(f64, f64)>,
    internal: Option<bool>,
    tool_diameter: Option<f64>,
    teeth: Option<u32>,
    tools: Option<std::collections::HashMap<String, f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let kw = milling::Keywords {
        internal,
        tool_diameter,
        teeth,
        tools,
    };
    if let Some((profile, o)) = milling::call(py, controller, machine, (thread, wire), &kw)? {
        return json_loads(py, &milling::passes_json(py, &program, &profile, &o)?);
    }
    milling::refuse_on_a_lathe(py, &kw)?;
    let m = resolve(py, controller, machine)?;
    let src = source(&program, &m);
    let options = run_options(py, start, Start::Unstated, include)?;
    let stock = Stock {
        diameter: stock_diameter,
        face: stock_start,
        length: stock_length,
        bore: stock_bore,
    };
    let (thread, wire) = thread_keywords(py, thread, wire)?;
    let opts = commands::with_stock(
        check::Options {
            thread,
            wire,
            library: options.library.clone(),
            ..check::Options::default()
        },
        stock,
        Some(&m),
    );
    let mut out = Vec::new();
    let run = py
        .detach(|| {
            commands::passes_json_with(
                || Ok(program.as_bytes()),
                src,
                Tip::Sharp,
                &options,
                &opts,
                &mut out,
            )
        })
        .map_err(|e| run_error(py, e))?;
    warn_all(py, &run.summary)?;
    warn_no_thread(py, run.threads, src)?;
    json_loads(py, &text(out))?.get_item("cycles")
}

/// Every motion of the program: the objects of `threadcut expand --format jsonl`.
///
/// One dict per motion: `kind` (`"rapid"`, `"feed"` or `"thread"`), `x` (a radius) and `z` of
/// its end, program units, `pass` and `line`; a thread move adds `lead`, `dlead` where the lead
/// varies, and `phase`, the spindle start angle in degrees, where it is not 0.
///
/// Raises `InputError` for a program the controller refuses or an unknown controller.
#[pyfunction(name = "motions")]
#[pyo3(signature = (program, controller, *, machine=None, include=None, start=None))]
fn motions_py<'py>(
    py: Python<'py>,
    program: String,
    controller: &str,
    machine: Option<&Bound<'py, PyAny>>,
    include: Option<Vec<std::path::PathBuf>>,
    start: Option<(f64, f64)>,
) -> PyResult<Bound<'py, PyAny>> {
    let m = resolve(py, controller, machine)?;
    let src = source(&program, &m);
    let options = run_options(py, start, Start::Unknown, include)?;
    let mut out = Vec::new();
    let summary = py
        .detach(|| {
            commands::expand(
                program.as_bytes(),
                src,
                ExpandFormat::Jsonl,
                &options,
                &mut out,
            )
        })
        .map_err(|e| run_error(py, e))?;
    warn_all(py, &summary)?;
    // One JSON object per line: parsed as one array.
    let lines = text(out);
    let mut array = String::with_capacity(lines.len() + 2);
    array.push('[');
    for (i, line) in lines.lines().enumerate() {
        if i > 0 {
            array.push(',');
        }
        array.push_str(line);
    }
    array.push(']');
    json_loads(py, &array)
}

/// The program with each threading cycle replaced by plain moves in the controller's own
/// format (`threadcut expand`); every other line is kept as written. An APT/CL program is posted
/// for the controller, as `post` does.
///
/// A program with control flow (subroutines, loops, parameters) keeps its own text where every
/// run of a cycle in it makes the same moves; `flatten=True` writes the executed program as
/// straight-line code instead (`--flatten`).
///
/// Raises `InputError` for a program the controller refuses or an unknown controller.
#[pyfunction(name = "expand")]
#[pyo3(signature = (program, controller, *, machine=None, flatten=false, include=None, start=None))]
fn expand_py(
    py: Python<'_>,
    program: String,
    controller: &str,
    machine: Option<&Bound<'_, PyAny>>,
    flatten: bool,
    include: Option<Vec<std::path::PathBuf>>,
    start: Option<(f64, f64)>,
) -> PyResult<String> {
    let m = resolve(py, controller, machine)?;
    let src = source(&program, &m);
    let options = Options {
        flatten,
        ..run_options(py, start, Start::Unknown, include)?
    };
    let mut out = Vec::new();
    let summary = py
        .detach(|| {
            commands::expand(
                program.as_bytes(),
                src,
                ExpandFormat::Gcode,
                &options,
                &mut out,
            )
        })
        .map_err(|e| run_error(py, e))?;
    warn_all(py, &summary)?;
    Ok(text(out))
}

/// What the program will do wrong before the spindle turns: `threadcut check --format json`.
///
/// One dict per finding: `line`, `column`, `level` (`"error"`, `"warning"` or `"note"`, an
/// assumption), `code` (`"E013"`, None for a note), `message` and `hint` (or None); errors and
/// warnings first, then the notes. A controller alarm is an error finding, not an exception.
/// `thread` judges the thread cut against a standard thread's class (`"M30x2-6g"`), and its note
/// states the measurement over `wire` (the thread's units, `--wire`; default the best wire);
/// `stock_diameter` is the bar's diameter, `stock_start` the Z of its face, `stock_length` its
/// length toward the chuck and `stock_bore` a bore through it, in program units (`--stock-*`;
/// each not given is the machine profile's `[stock]` value, else not known: the crest and Z0
/// are assumed, and said in a note).
///
/// The list is a `CheckResult` with two more attributes: `blanks`, each thread's blank (`line`,
/// `crest`, `crest_from`, `face`, `face_from`, as `passes` gives it) and `hits`, the rapid moves
/// that run into material (`line`, `level` `"error"` or `"warning"`, and `from`, `to`, `at` —
/// where it enters the material — each `(x, z)` in mm, X a radius).
///
/// A milling controller (`fanuc-mill`, `haas-mill`, `linuxcnc-mill`, `centroid`) reads a
/// machining centre's program: its milled threads (helices about one axis) and its tapping cycles
/// are judged (docs/milling-check.md); `internal` (True, False: external), `tool_diameter`,
/// `teeth` and `tools` (`{"D16": 17.0, "T5": 12}`: a cutter's diameter by its offset register or
/// tool number), in program units, tell what the program does not show.
///
/// A program with no thread gives `[]` and an `InputWarning`. Raises `InputError` for an unknown
/// controller or thread.
#[pyfunction(name = "check")]
#[pyo3(signature = (program, controller, *, machine=None, thread=None, wire=None, stock_diameter=None, stock_start=None, stock_length=None, stock_bore=None, include=None, start=None, internal=None, tool_diameter=None, teeth=None, tools=None))]
#[allow(clippy::too_many_arguments)]
fn check_py<'py>(
    py: Python<'py>,
    program: String,
    controller: &str,
    machine: Option<&Bound<'py, PyAny>>,
    thread: Option<&str>,
    wire: Option<f64>,
    stock_diameter: Option<f64>,
    stock_start: Option<f64>,
    stock_length: Option<f64>,
    stock_bore: Option<f64>,
    include: Option<Vec<std::path::PathBuf>>,
    start: Option<(f64, f64)>,
    internal: Option<bool>,
    tool_diameter: Option<f64>,
    teeth: Option<u32>,
    tools: Option<std::collections::HashMap<String, f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let kw = milling::Keywords {
        internal,
        tool_diameter,
        teeth,
        tools,
    };
    if let Some((profile, o)) = milling::call(py, controller, machine, (thread, wire), &kw)? {
        let report = py.detach(|| check::milling::check(program.as_bytes(), &profile, &o));
        return check_result_class(py)?.call1((findings(py, &report)?,));
    }
    milling::refuse_on_a_lathe(py, &kw)?;
    let m = resolve(py, controller, machine)?;
    let run = run_options(py, start, Start::Unknown, include)?;
    let (thread, wire) = thread_keywords(py, thread, wire)?;
    let stock = Stock {
        diameter: stock_diameter,
        face: stock_start,
        length: stock_length,
        bore: stock_bore,
    };
    let opts = commands::with_stock(
        check::Options {
            thread,
            wire,
            library: run.library.clone(),
            start: run.start,
            ..check::Options::default()
        },
        stock,
        Some(&m),
    );
    let src = source(&program, &m);
    let report = py
        .detach(|| check::check(program.as_bytes(), src, &opts))
        .map_err(|e| run_error(py, e))?;
    if !report.stopped {
        warn_no_thread(py, report.threads, src)?;
    }
    let result = check_result_class(py)?.call1((findings(py, &report)?,))?;
    result.setattr("blanks", blanks(py, &report)?)?;
    result.setattr("hits", hits(py, &report)?)?;
    Ok(result)
}

/// The class of `check`'s result: a list of findings (as it always was) with `blanks` and `hits`.
static CHECK_RESULT: PyOnceLock<Py<PyAny>> = PyOnceLock::new();

fn check_result_class(py: Python<'_>) -> PyResult<&Bound<'_, PyAny>> {
    CHECK_RESULT
        .get_or_try_init(py, || {
            let m = PyModule::from_code(
                py,
                c"class CheckResult(list):\n    \"\"\"`check`'s findings, a list, with each thread's blank and the rapids into material.\"\"\"\n    __module__ = 'threadcut'\n    blanks = ()\n    hits = ()\n",
                c"threadcut_check_result.py",
                c"threadcut_check_result",
            )?;
            Ok(m.getattr("CheckResult")?.unbind())
        })
        .map(|c| c.bind(py))
}

/// Each thread's blank: `{line, crest, crest_from, face, face_from}` (`passes`' `blank` with the
/// thread's line).
fn blanks<'py>(py: Python<'py>, report: &Report) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for b in &report.blanks {
        let d = json_loads(py, &commands::blank_json(b).to_string())?;
        d.set_item("line", b.line)?;
        list.append(d)?;
    }
    Ok(list)
}

/// The rapids into material, in program order (at most the check's first 1000): `{line, level,
/// from, to, at}`, each point `(x, z)` in mm with X a radius, `at` where it enters the material,
/// `level` `"error"` (a surface the program cut, a thread, a stock given) or `"warning"` (a stock
/// assumed).
fn hits<'py>(py: Python<'py>, report: &Report) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for h in &report.part.hits {
        let d = PyDict::new(py);
        d.set_item("line", h.line)?;
        d.set_item("level", if h.error { "error" } else { "warning" })?;
        d.set_item("from", (h.from.x, h.from.z))?;
        d.set_item("to", (h.to.x, h.to.z))?;
        d.set_item("at", (h.at.x, h.at.z))?;
        list.append(d)?;
    }
    Ok(list)
}

/// `check --format json`'s objects without `file`: `{line, column, level, code, message, hint}`.
fn findings<'py>(py: Python<'py>, report: &Report) -> PyResult<Bound<'py, PyList>> {
    let list = PyList::empty(py);
    for f in report.findings(PROGRAM) {
        let d = PyDict::new(py);
        d.set_item("line", f.line)?;
        d.set_item("column", f.column)?;
        d.set_item("level", f.level)?;
        d.set_item("code", f.code)?;
        d.set_item("message", f.message)?;
        d.set_item("hint", f.hint)?;
        list.append(d)?;
    }
    Ok(list)
}

/// One SVG of the threads' pass diagrams and XZ toolpaths (`threadcut plot`): at most the first
/// 50 threads, the picture saying what it left out, or only the `cycle`th thread (1-based).
///
/// Above them, the part the program makes (where it cuts anything, a stock is given or a rapid
/// runs into material): the stock, the part, each thread's teeth, the rapids into material in red
/// at their line; `part=True` draws it alone (`--part`). The stock keywords are `check`'s.
///
/// A milling controller draws each milled thread along its axis and from the side, with `check`'s
/// milling keywords.
///
/// A program with no thread gives an empty drawing and an `InputWarning`; threads left out without
/// `cycle` are an `InputWarning` too. Raises `InputError` for a program the controller refuses, an
/// unknown controller, or a `cycle` the program does not have.
#[pyfunction(name = "plot_svg")]
#[pyo3(signature = (program, controller, *, machine=None, cycle=None, part=false, stock_diameter=None, stock_start=None, stock_length=None, stock_bore=None, include=None, start=None, internal=None, tool_diameter=None, teeth=None, tools=None))]
#[allow(clippy::too_many_arguments)]
fn plot_svg_py(
    py: Python<'_>,
    program: String,
    controller: &str,
    machine: Option<&Bound<'_, PyAny>>,
    cycle: Option<usize>,
    part: bool,
    stock_diameter: Option<f64>,
    stock_start: Option<f64>,
    stock_length: Option<f64>,
    stock_bore: Option<f64>,
    include: Option<Vec<std::path::PathBuf>>,
    start: Option<(f64, f64)>,
    internal: Option<bool>,
    tool_diameter: Option<f64>,
    teeth: Option<u32>,
    tools: Option<std::collections::HashMap<String, f64>>,
) -> PyResult<String> {
    let kw = milling::Keywords {
        internal,
        tool_diameter,
        teeth,
        tools,
    };
    if let Some((profile, o)) = milling::call(py, controller, machine, (None, None), &kw)? {
        return milling::svg(py, &program, &profile, &o);
    }
    milling::refuse_on_a_lathe(py, &kw)?;
    let m = resolve(py, controller, machine)?;

    let src = source(&program, &m);
    let options = run_options(py, start, Start::Unknown, include)?;
    if cycle == Some(0) {
        return Err(Problem::usage("cycle=0: threads are counted from 1").error(py));
    }
    let selection = commands::Selection {
        only: cycle,
        ..commands::Selection::default()
    };
    if part && cycle.is_some() {
        return Err(Problem::usage("part=True draws the part alone: no cycle with it").error(py));
    }
    let stock = Stock {
        diameter: stock_diameter,
        face: stock_start,
        length: stock_length,
        bore: stock_bore,
    };
    let part_plot = commands::PartPlot {
        check: commands::with_stock(
            check::Options {
                library: options.library.clone(),
                start: options.start,
                ..check::Options::default()
            },
            stock,
            Some(&m),
        ),
        alone: part,
    };
    let plot = py
        .detach(|| {
            commands::plot_program(
                || Ok(program.as_bytes()),
                src,
                Tip::Sharp,
                selection,
                &options,
                &part_plot,
            )
        })
        .map_err(|e| run_error(py, e))?;
    warn_all(py, &plot.summary)?;
    if part {
        return Ok(plot.svg);
    }
    if let Some(n) = cycle.filter(|n| *n > plot.threads) {
        return Err(Problem::usage(format!(
            "cycle={n}: the program has {}",
            threadcut::text::count(plot.threads, "thread", "threads")
        ))
        .error(py));
    }
    warn_no_thread(py, plot.threads as u32, src)?;
    // Threads left out unasked (`cycle` names the one wanted: the picture says the rest).
    if cycle.is_none() && plot.threads > 0 && plot.drawn.len() < plot.threads {
        let numbers: Vec<usize> = plot.drawn.iter().map(|(n, _)| *n).collect();
        Problem::plain_warning(&threadcut::render::svg::left_out(&numbers, plot.threads))
            .warn(py)?;
    }
    Ok(plot.svg)
}

/// A standard thread: the object of `threadcut thread NAME --json`.
///
/// `name` is `M10`, `M10x1.25-6g`, `1/2-13 UNC-2A`, `#10-32 UNF`, `1/2-14 NPT`, `Tr20x4`, ... .
/// Keys: `name`, `family`, `series`, `units` (the standard's own), `pitch`, `pitch_mm`, `tpi`,
/// `basic` (`major`, `pitch_diameter`, `minor`, `fundamental_height`), `thread_height` and
/// `turning_infeed` (`external`, `internal`), and `external` / `internal`: the class limits
/// (`class`, `deviation`, `major`, `pitch`, `minor`, each `{min, max}`) of the side the name asks
/// for, both without a class; other forms than ISO metric and Unified add `profile` and `taper`.
/// `wires`: the three-wire measurement (`wire`, `best`, `min`, `max`, `fits`, `formula`, `basic`,
/// `class`, `limits`: M over the wire at the basic and the external class's pitch diameters, by the
/// simple formula and with the lead angle), over `wire` (the thread's units, as `--wire`) when
/// given, else over the best wire; `gauges` (metric and Unified): the GO / NOT GO gauge sizes of
/// each side's class, as `threadcut thread NAME --wire D --json` prints them.
///
/// Raises `InputError` for a name threadcut does not know (its hint names the nearest ones) or a
/// wire that is not a positive length.
#[pyfunction(name = "thread")]
#[pyo3(signature = (name, *, wire=None))]
fn thread_py<'py>(py: Python<'py>, name: &str, wire: Option<f64>) -> PyResult<Bound<'py, PyAny>> {
    let t = standard::lookup(name).map_err(|d| Problem::diagnostic(&d, None).error(py))?;
    let mut v = t.to_json();
    if let Some(w) = wire_keyword(py, wire, true)? {
        v["wires"] = t.wires(Some(t.units.to_mm(w))).to_json(t.units);
    }
    json_loads(py, &v.to_string())
}

/// The `wire` keyword (`--wire`): a positive diameter in the thread's units, and only with a
/// thread to measure.
/// `thread=` (a standard thread's name, as `--thread`) and `wire=` (with it, as `--wire`).
fn thread_keywords(
    py: Python<'_>,
    thread: Option<&str>,
    wire: Option<f64>,
) -> PyResult<(Option<standard::StandardThread>, Option<f64>)> {
    let thread = match thread {
        Some(name) => {
            Some(standard::lookup(name).map_err(|d| Problem::diagnostic(&d, None).error(py))?)
        }
        None => None,
    };
    let wire = wire_keyword(py, wire, thread.is_some())?;
    Ok((thread, wire))
}

fn wire_keyword(py: Python<'_>, wire: Option<f64>, thread: bool) -> PyResult<Option<f64>> {
    match wire {
        Some(w) if !thread => Err(Problem::usage(format!(
            "wire={w}: the wire measures a standard thread: give thread= too (--wire needs --thread)"
        ))
        .error(py)),
        Some(w) if !(w.is_finite() && w > 0.0) => Err(Problem::usage(format!(
            "wire={w}: a measuring wire's diameter is a positive length (the thread's units)"
        ))
        .error(py)),
        w => Ok(w),
    }
}

/// A keyword that takes one of a few words.
fn choice<T: Copy>(py: Python<'_>, keyword: &str, given: &str, words: &[(&str, T)]) -> PyResult<T> {
    words
        .iter()
        .find(|(w, _)| w.eq_ignore_ascii_case(given))
        .map(|&(_, v)| v)
        .ok_or_else(|| {
            let names: Vec<String> = words.iter().map(|(w, _)| format!("\"{w}\"")).collect();
            Problem::usage(format!(
                "{keyword}={given:?}: expected {}",
                names.join(" or ")
            ))
            .error(py)
        })
}

/// A thread-milling program (`threadcut mill`): helical G2/G3 full circles, cutter
/// compensation, lead-in and lead-out, for a milling controller (`centroid`, `fanuc-mill`,
/// `linuxcnc-mill`).
///
/// The options are the command's flags as keywords: `left` (a left-hand thread), `teeth` (on
/// the tool, one pitch apart), `top_down` or `bottom_up` (default: climb milling), `passes`
/// (radial, of equal chip area), `starts`, `comp` (`"g41"`: the controller's compensation, or
/// `"none"`: the tool-centre path), `center` (the thread's axis, X and Y), `start_z` (the top of
/// the thread), `lead` (`"arc"` or `"radial"`), `clearance` (above `start_z` for rapid moves,
/// default 5 mm), `units` (`"mm"` or `"inch"`, default the thread's own) and `d_register` (the
/// D word of G41/G42). Lengths and the feed are in program units.
///
/// Warnings about the plan are `InputWarning`s. Raises `InputError` for an unknown thread or
/// milling controller, a class for the other side, or a plan that cannot be milled; its message
/// names the command line's flag (`--length`).
#[pyfunction(name = "mill")]
#[pyo3(signature = (
    thread, *, internal, length, tool_diameter, feed, controller,
    left=false, teeth=1, top_down=false, bottom_up=false, passes=1, starts=1, comp="g41",
    center=(0.0, 0.0), start_z=0.0, lead="arc", clearance=None, units=None, d_register=None
), text_signature = "(thread, *, internal, length, tool_diameter, feed, controller, left=False, teeth=1, top_down=False, bottom_up=False, passes=1, starts=1, comp='g41', center=(0.0, 0.0), start_z=0.0, lead='arc', clearance=None, units=None, d_register=None)")]
#[allow(clippy::too_many_arguments)]
fn mill_py(
    py: Python<'_>,
    thread: &str,
    internal: bool,
    length: f64,
    tool_diameter: f64,
    feed: f64,
    controller: &str,
    left: bool,
    teeth: u32,
    top_down: bool,
    bottom_up: bool,
    passes: u32,
    starts: u32,
    comp: &str,
    center: (f64, f64),
    start_z: f64,
    lead: &str,
    clearance: Option<f64>,
    units: Option<&str>,
    d_register: Option<u32>,
) -> PyResult<String> {
    let name = built_in_name(controller, ProfileKind::Mill)
        .map_err(|e| name_problem(controller, e, ProfileKind::Mill).error(py))?;
    let profile = MillProfile::built_in(name).expect("built-in profiles parse");
    let side = if internal {
        Side::Internal
    } else {
        Side::External
    };
    let direction = match (top_down, bottom_up) {
        (true, true) => {
            return Err(Problem::usage(
                "top_down and bottom_up: give one direction, or neither for climb milling",
            )
            .error(py))
        }
        (true, false) => Some(Direction::TopDown),
        (false, true) => Some(Direction::BottomUp),
        (false, false) => None,
    };
    let units = match units {
        Some(u) => Some(choice(
            py,
            "units",
            u,
            &[("mm", Units::Mm), ("inch", Units::Inch)],
        )?),
        None => None,
    };
    let request = Request {
        hand: if left { Hand::Left } else { Hand::Right },
        teeth,
        direction,
        passes,
        starts,
        comp: choice(
            py,
            "comp",
            comp,
            &[("g41", Comp::Controller), ("none", Comp::Off)],
        )?,
        center,
        start_z,
        lead_in: choice(
            py,
            "lead",
            lead,
            &[("arc", LeadIn::Arc), ("radial", LeadIn::Radial)],
        )?,
        clearance,
        units,
        d_register,
        ..Request::new(thread, side, length, tool_diameter, feed, profile)
    };
    let milling = request
        .prepare()
        .map_err(|d| Problem::diagnostic(&d, None).error(py))?;
    for w in &milling.warnings {
        Problem {
            hint: w.hint.clone(),
            ..Problem::plain_warning(&w.message)
        }
        .warn(py)?;
    }
    let mut out = Vec::new();
    milling.write_gcode(&mut out)?;
    Ok(text(out))
}

/// The program, written for controller `source`, as a program for controller `target`
/// (`threadcut convert`): each cycle as the target's native cycle where reading it back gives the
/// same toolpath, else as plain moves with a comment saying why; every other block through the
/// two controllers' codes. A program with control flow is copied as it is for the same
/// controller; for another one it is converted as executed only with `flatten=True`.
/// `max_lead_drift`: the largest drift of a lead the target cannot write exactly, over its thread,
/// in the converted program's units (default: a quarter of the thread's medium-class
/// pitch-diameter tolerance; the drift is always stated in a comment and an `InputWarning`).
/// `tools`: named tools and the numbers that call them (`{"THREAD_EXT_60": "T0101"}`: tool 1,
/// offset 1; `"T4"`: tool 4 with its own offset), as `--tool NAME=T0101`: a Sinumerik
/// `T="THREAD_EXT_60" D1` written `T0101`, and `T0101` written `T="THREAD_EXT_60" D1` for
/// Sinumerik; each replaces the target profile's `[tools]` entry of the same name.
/// `source_machine` and `target_machine` are machine profiles, as `machine` elsewhere.
///
/// Raises `InputError` at the first block the target cannot express (its line, column and word),
/// for an unknown controller, or for a program the source controller refuses.
#[pyfunction(name = "convert")]
#[pyo3(signature = (program, source, target, *, source_machine=None, target_machine=None, flatten=false, max_lead_drift=None, tools=None))]
#[allow(clippy::too_many_arguments)]
fn convert_py(
    py: Python<'_>,
    program: String,
    source: &str,
    target: &str,
    source_machine: Option<&Bound<'_, PyAny>>,
    target_machine: Option<&Bound<'_, PyAny>>,
    flatten: bool,
    max_lead_drift: Option<f64>,
    tools: Option<std::collections::BTreeMap<String, String>>,
) -> PyResult<String> {
    let from = resolve(py, source, source_machine)?;
    let to = resolve(py, target, target_machine)?;
    let options = threadcut::convert::Options {
        run: Options {
            flatten,
            ..Options::default()
        },
        max_lead_drift,
        tools: tools.unwrap_or_default().into_iter().collect(),
    };
    let mut out = Vec::new();
    let report = py
        .detach(|| threadcut::convert::convert(program.as_bytes(), &mut out, &from, &to, &options))
        .map_err(|e| run_error(py, e))?;
    warn_all(py, &report.summary)?;
    Ok(text(out))
}

/// An APT/CL program posted for a controller (`threadcut post`): each THREAD as the
/// controller's native cycle where reading it back gives the same toolpath, else as plain moves
/// with a comment saying why.
///
/// Raises `InputError` for a statement the post cannot read or an unknown controller.
#[pyfunction(name = "post")]
#[pyo3(signature = (apt, controller, *, machine=None))]
fn post_py(
    py: Python<'_>,
    apt: String,
    controller: &str,
    machine: Option<&Bound<'_, PyAny>>,
) -> PyResult<String> {
    let m = resolve(py, controller, machine)?;
    let mut out = Vec::new();
    let summary = py
        .detach(|| threadcut::apt::post::write(apt.as_bytes(), &mut out, &m))
        .map_err(|e| run_error(py, e))?;
    warn_all(py, &summary)?;
    Ok(text(out))
}

/// threadcut: exact pass-by-pass motion for CNC thread-cutting cycles.
///
/// Each function is one `threadcut` command, computed by the same library function the command line
/// calls, so that its data is the command's JSON. A program is G-code for `controller` or APT/CL
/// (recognised by its first statement: PARTNO, UNITS/, MACHIN/, FROM/, GOTO/, PITCH/, CLPRNT).
///
/// `machine`, where a function takes it, is a machine profile in TOML (see the repository's
/// `profiles/`): a path (`str` or `os.PathLike`), or an object with `read()` that gives its text, such
/// as an open file or `io.StringIO(toml_text)`. A `str` is always a path, never TOML text. The profile
/// must be the controller's: its `name` or its `dialect` is `controller`.
///
/// `include`, where a function takes it, is a list of directories where calls find the programs the
/// program does not hold (`--include DIR`, in order): Fanuc/Haas/GSK `O9010`, `O9010.nc`, `9010.nc`
/// (any case), LinuxCNC `name.ngc` for `o<name> call`, Sinumerik `NAME.SPF` (any case).
///
/// Bad input raises `InputError`; findings that do not stop a function are issued as `InputWarning`
/// through Python's `warnings` module.
#[pymodule(name = "threadcut")]
fn threadcut_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    for (name, class) in [
        ("InputError", py.get_type::<InputError>()),
        ("InputWarning", py.get_type::<InputWarning>()),
    ] {
        // Every instance has the attributes, None where they do not apply.
        for attr in ["file", "line", "column", "code", "message", "hint"] {
            class.setattr(attr, py.None())?;
        }
        m.add(name, class)?;
    }
    m.add_function(wrap_pyfunction!(controllers_py, m)?)?;
    m.add_function(wrap_pyfunction!(passes_py, m)?)?;
    m.add_function(wrap_pyfunction!(motions_py, m)?)?;
    m.add_function(wrap_pyfunction!(expand_py, m)?)?;
    m.add_function(wrap_pyfunction!(check_py, m)?)?;
    m.add_function(wrap_pyfunction!(plot_svg_py, m)?)?;
    m.add_function(wrap_pyfunction!(thread_py, m)?)?;
    m.add_function(wrap_pyfunction!(mill_py, m)?)?;
    m.add_function(wrap_pyfunction!(convert_py, m)?)?;
    m.add_function(wrap_pyfunction!(post_py, m)?)?;
    // `from .threadcut import *` (the package's `__init__.py`) takes these, `__version__` too.
    m.add(
        "__all__",
        [
            "__version__",
            "InputError",
            "InputWarning",
            "controllers",
            "passes",
            "motions",
            "expand",
            "check",
            "plot_svg",
            "thread",
            "mill",
            "convert",
            "post",
            "CheckResult",
        ],
    )?;
    m.add("CheckResult", check_result_class(py)?)?;
    Ok(())
}
