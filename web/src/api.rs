//! The page's API: JSON in, JSON out, over the `threadcut` library. Plain Rust (tested natively);
//! `lib.rs` only wraps these functions for wasm-bindgen.

use serde::Deserialize;
use serde_json::{json, Map, Value};

use threadcut::check::{self, Source};
use threadcut::commands;
use threadcut::diag::{Code, Diagnostic, Severity};
use threadcut::machine::{Machine, Stock, BUILT_IN};
use threadcut::post;
use threadcut::program::{self, Error};
use threadcut::render;
use threadcut::sim::{self, Tip, Tool};
use threadcut::thread::standard::{self, Surface};
use threadcut::threads;

use crate::forms::{self, Placed};

/// More motions than this are not sent to the page (the plots and the G-code still cover them all).
pub const MAX_MOTIONS: usize = 20_000;

fn error(message: impl Into<String>) -> Value {
    json!({"ok": false, "error": message.into()})
}

/// Every built-in lathe controller, the cycle form of those that have one, and the names of the
/// standard threads threadcut knows.
pub fn controllers() -> Value {
    let list: Vec<Value> = BUILT_IN
        .iter()
        .filter_map(|(name, _)| Machine::built_in(name))
        .map(|m| {
            let form = forms::form(&m.name);
            json!({
                "name": m.name,
                "description": m.description,
                "units": m.units,
                "diameter_x": m.diameter_x,
                "form": form,
            })
        })
        .collect();
    json!({"ok": true, "controllers": list, "threads": standard::known_names()})
}

/// A standard thread's data (mm) with the limits of both sides, its three-wire measurement over
/// the best wire (`wires`: [`standard::wires::Wires`], mm) and, for a metric or Unified thread, the
/// GO / NOT GO gauges of both sides' classes (`gauges`: `{external, internal}`, each a list of
/// [`standard::gauges::GaugePair`], mm; `null` for the other forms), as `threadcut thread` prints them.
pub fn thread(name: &str) -> Value {
    match standard::lookup(name) {
        Ok(t) => {
            let ext = t.limits(Surface::External);
            let int = t.limits(Surface::Internal);
            let gauges = matches!(
                t.family,
                standard::Family::Metric | standard::Family::Unified
            )
            .then(|| {
                json!({
                    "external": standard::gauges::gauges(&ext),
                    "internal": standard::gauges::gauges(&int),
                })
            });
            json!({
                "ok": true,
                "thread": t,
                "external": ext,
                "internal": int,
                "wires": t.wires(None),
                "gauges": gauges,
            })
        }
        Err(d) => json!({"ok": false, "error": d.message, "hint": d.hint}),
    }
}

#[derive(Deserialize)]
struct FormRequest {
    controller: String,
    thread: String,
    #[serde(default)]
    internal: bool,
}

/// The values of a controller's form filled in from a standard thread.
pub fn fill(request: &str) -> Value {
    let r: FormRequest = match serde_json::from_str(request) {
        Ok(r) => r,
        Err(e) => return error(format!("bad request: {e}")),
    };
    if forms::form(&r.controller).is_none() {
        return error(format!("no cycle form for controller `{}`", r.controller));
    }
    let t = match standard::lookup(&r.thread) {
        Ok(t) => t,
        Err(d) => return json!({"ok": false, "error": d.message, "hint": d.hint}),
    };
    let side = if r.internal {
        Surface::Internal
    } else {
        Surface::External
    };
    let values: Map<String, Value> = forms::fill(&r.controller, &t, side)
        .into_iter()
        .map(|(k, v)| (k.to_string(), Value::String(v)))
        .collect();
    json!({"ok": true, "thread": t.name, "values": values})
}

#[derive(Deserialize)]
struct PlanRequest {
    controller: String,
    values: Map<String, Value>,
}

/// The program a form's values make, analysed; each diagnostic names the field it points into.
pub fn plan(request: &str) -> Value {
    let r: PlanRequest = match serde_json::from_str(request) {
        Ok(r) => r,
        Err(e) => return error(format!("bad request: {e}")),
    };
    let Some(form) = forms::form(&r.controller) else {
        return error(format!("no cycle form for controller `{}`", r.controller));
    };
    let (text, placed) = form.program(|id| match r.values.get(id) {
        Some(Value::String(s)) => Some(s.clone()),
        Some(Value::Number(n)) => Some(n.to_string()),
        _ => None,
    });
    let mut out = analyse_text(&r.controller, &text, Some(&placed));
    if let Some(o) = out.as_object_mut() {
        o.insert("fields".into(), json!(placed));
    }
    out
}

#[derive(Deserialize)]
struct AnalyseRequest {
    controller: String,
    program: String,
    /// Whether to list the motions (`expand --format jsonl`); the page does not show them, and a
    /// long program's list costs as much as the rest of the analysis. Default: yes.
    #[serde(default = "yes")]
    motions: bool,
    /// Whether to list each thread's blank (`blanks`, as `check` gives them): one entry a
    /// thread, which the page does not show. Default: yes.
    #[serde(default = "yes")]
    blanks: bool,
    /// At most this many threads get their pass table (`cycles`); `cycles_total` counts them all.
    /// Default: every thread.
    #[serde(default)]
    max_cycles: Option<usize>,
    /// The stock (`check --stock-diameter`, `--stock-start`, `--stock-length`, `--stock-bore`),
    /// program units; each absent: not known.
    #[serde(default)]
    stock_diameter: Option<f64>,
    #[serde(default)]
    stock_start: Option<f64>,
    #[serde(default)]
    stock_length: Option<f64>,
    #[serde(default)]
    stock_bore: Option<f64>,
    /// Where the tool is before the program's first line, `[x, z]` as the program writes them at
    /// power-on (`--start X,Z`); absent: not known.
    #[serde(default)]
    start: Option<[f64; 2]>,
    /// At most this many lines of the expanded program (`gcode`); `gcode_total` counts them all,
    /// and [`expand`] gives the whole program. Default: the whole program.
    #[serde(default)]
    gcode_lines: Option<usize>,
    /// At most this many rows in each pass table (`passes`), the table's `passes_total` counting
    /// them all when there are more. Default: every pass.
    #[serde(default)]
    max_passes: Option<usize>,
}

/// What an analysis lists besides its findings, and the stock it checks with.
#[derive(Clone, Copy)]
struct Listing {
    motions: bool,
    blanks: bool,
    max_cycles: usize,
    /// The lines of the expanded program given (the rest counted).
    gcode_lines: usize,
    /// The rows of each pass table given (the rest counted).
    max_passes: usize,
    stock: Stock,
    /// `--start X,Z`, or not known.
    start: program::Start,
}

fn yes() -> bool {
    true
}

/// A pasted program, analysed as the CLI would.
pub fn analyse(request: &str) -> Value {
    match serde_json::from_str::<AnalyseRequest>(request) {
        Ok(r) => analyse_with(
            &r.controller,
            &r.program,
            None,
            Listing {
                motions: r.motions,
                blanks: r.blanks,
                max_cycles: r.max_cycles.unwrap_or(usize::MAX),
                gcode_lines: r.gcode_lines.unwrap_or(usize::MAX),
                max_passes: r.max_passes.unwrap_or(usize::MAX),
                stock: Stock {
                    diameter: r.stock_diameter,
                    face: r.stock_start,
                    length: r.stock_length,
                    bore: r.stock_bore,
                },
                start: start_of(r.start),
            },
        ),
        Err(e) => error(format!("bad request: {e}")),
    }
}

fn diagnostic(d: &Diagnostic, placed: Option<&[Placed]>) -> Value {
    let s = d.span;
    let field = placed.and_then(|p| forms::field_at(p, s.line, s.column, s.len));
    json!({
        "severity": d.severity,
        "code": d.code.as_str(),
        "message": d.message,
        "hint": d.hint,
        "line": s.line,
        "column": s.column,
        "len": s.len,
        "start": s.start,
        "field": field,
    })
}

/// A library error as a diagnostic: the program's, with its place (and `placed`'s field), or a
/// message with no place.
fn error_diagnostic(e: Error, placed: Option<&[Placed]>) -> Value {
    match e {
        Error::Input(d) => diagnostic(&d, placed),
        other => json!({
            "severity": "error", "code": null, "message": other.to_string(),
            "hint": null, "line": 0, "column": 0, "len": 0, "start": 0, "field": null,
        }),
    }
}

/// `--start X,Z` from a request, or not known.
fn start_of(start: Option<[f64; 2]>) -> program::Start {
    match start {
        Some([x, z]) if x.is_finite() && z.is_finite() => program::Start::At { x, z },
        _ => program::Start::Unknown,
    }
}

/// Everything the page shows for one program: the findings of `threadcut check` (the same library
/// function, the same options: none), the pass table of each thread (the rows of `threadcut passes
/// --json`), the expanded G-code (`threadcut expand`), the motions (`threadcut expand --format
/// jsonl`), the plots and the diagnostics with their spans.
pub fn analyse_text(controller: &str, text: &str, placed: Option<&[Placed]>) -> Value {
    analyse_with(
        controller,
        text,
        placed,
        Listing {
            motions: true,
            blanks: true,
            max_cycles: usize::MAX,
            gcode_lines: usize::MAX,
            max_passes: usize::MAX,
            stock: Stock::default(),
            start: program::Start::Unknown,
        },
    )
}

/// [`analyse_text`], listing the motions or not (`motions`: `[]` and `motions_total` 0 when
/// not), and the pass tables of the first `max_cycles` threads.
fn analyse_with(
    controller: &str,
    text: &str,
    placed: Option<&[Placed]>,
    listing: Listing,
) -> Value {
    let Some(machine) = Machine::built_in(controller) else {
        let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
        return error(format!(
            "unknown controller `{controller}` (built in: {})",
            names.join(", ")
        ));
    };
    let mut diagnostics = Vec::new();
    let mut failed = false;
    let fail = |e: Error, diagnostics: &mut Vec<Value>, failed: &mut bool| {
        *failed = true;
        diagnostics.push(error_diagnostic(e, placed));
    };

    // The check: every finding of `threadcut check` (with the stock given), the controller's
    // alarm among them.
    let mut notes = Vec::new();
    let mut lines = 0;
    let mut blanks = Vec::new();
    let mut part = None;
    let opts = check::Options {
        start: listing.start,
        ..commands::with_stock(check::Options::default(), listing.stock, Some(&machine))
    };
    // A cycle on its own (the check stopped where a cycle's start is not known): its pass table
    // is still shown where it does not depend on the start, as `passes` gives it.
    let mut start_unknown = false;
    // The number of threads, when the check read the whole program without an error: the pass
    // tables then stop at the last one shown (the threads after it read as the check read them).
    let mut threads_read = None;
    match check::check(text.as_bytes(), Source::Gcode(&machine), &opts) {
        Ok(report) => {
            lines = report.lines;
            failed = report.stopped;
            threads_read = (!report.stopped
                && !report
                    .diagnostics
                    .iter()
                    .any(|d| d.severity == Severity::Error))
            .then_some(report.threads as usize);
            start_unknown = report.stopped
                && report
                    .diagnostics
                    .iter()
                    .any(|d| d.code == Code::UnknownPosition && d.severity == Severity::Error);
            // The part picture from this check, as `plot` composes it (`commands::plot_program`).
            part = Some(commands::part_picture(&report.part, machine.units))
                .filter(|p| p.worth_drawing());
            blanks = report
                .blanks
                .iter()
                .filter(|_| listing.blanks)
                .map(|b| {
                    let mut v = commands::blank_json(b);
                    v["line"] = b.line.into();
                    v
                })
                .collect();
            diagnostics.extend(report.diagnostics.iter().map(|d| diagnostic(d, placed)));
            notes = report
                .notes
                .iter()
                .map(|n| json!({"line": n.span.line, "message": n.message}))
                .collect();
        }
        Err(e) => fail(e, &mut diagnostics, &mut failed),
    }

    // The pass tables, thread by thread, and the threads the plot draws: read once when the
    // plot reads the program as the tables do (no start given).
    let mut cycles = Vec::new();
    let mut cycles_total = 0usize;
    let options = program::Options {
        start: listing.start,
        ..program::Options::default()
    };
    let mut drawn = Vec::new();
    let mut shared = false;
    if !failed || start_unknown {
        let tables = program::Options {
            start: if start_unknown {
                program::Start::Unstated
            } else {
                listing.start
            },
            ..options.clone()
        };
        shared = tables == program::Options::default();
        let mut enough = false;
        let run = threads::each_gcode_with(text.as_bytes(), &machine, None, &tables, |t| {
            cycles_total += 1;
            if cycles.len() < listing.max_cycles {
                // As `threadcut passes --json` with its default (sharp) tool: the simulated
                // columns null where the section cannot be simulated.
                let tool = Tool {
                    angle_deg: t.job.tool_angle_deg,
                    tip: Tip::Sharp,
                };
                let section = sim::section(&t.job, &t.passes, &tool, 0.0).ok();
                cycles.push(threads::passes_json_first(
                    &t,
                    section.as_ref(),
                    listing.max_passes,
                ));
            }
            if shared && drawn.len() < render::MAX_PLOTTED {
                drawn.push(t);
            }
            let done = cycles.len() >= listing.max_cycles
                && (!shared || drawn.len() >= render::MAX_PLOTTED);
            if done && threads_read.is_some() {
                // Not an error: what is shown is all there, and the check counted the rest.
                enough = true;
                return Err(Error::Setup(String::new()));
            }
            Ok(())
        });
        match run {
            Err(_) if enough => cycles_total = threads_read.unwrap_or(cycles_total),
            // The check said it already (a LinuxCNC G76, whose passes depend on its start).
            Err(_) if start_unknown => {}
            Err(e) => fail(e, &mut diagnostics, &mut failed),
            Ok(_) => {}
        }
    }

    // The expanded program and the motions, exactly as `threadcut expand` writes them.
    let mut gcode = None;
    let mut gcode_total = 0usize;
    let mut motions = Vec::new();
    let mut motions_total = 0usize;
    if !failed {
        let mut head = Head::new(listing.gcode_lines);
        match program::expand_gcode_to(text.as_bytes(), &mut head, &machine, &options) {
            Ok(_) => {
                gcode_total = head.total();
                gcode = Some(utf8(head.text));
            }
            Err(e) => fail(e, &mut diagnostics, &mut failed),
        }
    }
    if !failed && listing.motions {
        let mut buf = Vec::new();
        match program::expand_jsonl_with(text.as_bytes(), &mut buf, &machine, &options) {
            Ok(_) => {
                for l in String::from_utf8_lossy(&buf).lines() {
                    motions_total += 1;
                    if motions.len() < MAX_MOTIONS {
                        if let Ok(v) = serde_json::from_str::<Value>(l) {
                            motions.push(v);
                        }
                    }
                }
            }
            Err(e) => fail(e, &mut diagnostics, &mut failed),
        }
    }
    // The plots, as `threadcut plot` draws them: the part the program makes, then the threads.
    let mut plot_error = None;
    let mut svg = None;
    if !failed && shared {
        match render::first_threads_svg(&drawn, cycles_total, Tip::Sharp, part.as_ref()) {
            Ok(p) => svg = Some(p),
            Err(e) => plot_error = Some(e.to_string()),
        }
    } else if !failed {
        match render::program_plot_part(
            text.as_bytes(),
            &machine,
            Tip::Sharp,
            commands::Selection::default(),
            &program::Options::default(),
            part.as_ref(),
        ) {
            Ok(p) => svg = Some(p.svg),
            Err(e) => plot_error = Some(e.to_string()),
        }
    }

    json!({
        "ok": !failed,
        "controller": controller,
        "program": text,
        "lines": lines,
        "cycles": cycles,
        "cycles_total": cycles_total,
        "gcode": gcode,
        "gcode_total": gcode_total,
        "motions": motions,
        "motions_total": motions_total,
        "svg": svg,
        "plot_error": plot_error,
        "diagnostics": diagnostics,
        "notes": notes,
        "blanks": blanks,
    })
}

/// Text the library wrote: valid UTF-8 (the program's own text and the moves), kept without a
/// copy.
fn utf8(bytes: Vec<u8>) -> String {
    String::from_utf8(bytes).unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned())
}

/// The first lines of an expanded program, and the number of all its lines. A cycle's moves past
/// those lines are counted ([`post::Moves::lines`]), not formatted, so that a long paste's
/// analysis does not write megabytes the page does not show.
struct Head {
    text: Vec<u8>,
    /// Lines kept at most.
    max: usize,
    /// Line ends seen, and whether text follows the last.
    ends: usize,
    open: bool,
}

impl Head {
    fn new(max: usize) -> Head {
        Head {
            text: Vec::new(),
            max,
            ends: 0,
            open: false,
        }
    }

    fn total(&self) -> usize {
        self.ends + usize::from(self.open)
    }
}

impl std::io::Write for Head {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if buf.is_empty() {
            return Ok(0);
        }
        if self.ends < self.max {
            // Up to the end of the last line kept.
            let wanted = self.max - self.ends;
            let cut = buf
                .iter()
                .enumerate()
                .filter(|(_, &b)| b == b'\n')
                .nth(wanted - 1)
                .map_or(buf.len(), |(i, _)| i + 1);
            self.text.extend_from_slice(&buf[..cut]);
        }
        self.ends += buf.iter().filter(|&&b| b == b'\n').count();
        self.open = buf.last() != Some(&b'\n');
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

impl post::MovesOut for Head {
    fn keeps_text(&self) -> bool {
        self.ends < self.max
    }

    fn moves(&mut self, moves: post::Moves) -> std::io::Result<()> {
        if self.ends < self.max {
            let mut text = Vec::new();
            moves.write(&mut text)?;
            return std::io::Write::write_all(self, &text);
        }
        let n = moves.lines();
        self.ends += n;
        self.open &= n == 0;
        Ok(())
    }
}

#[derive(Deserialize)]
struct ExpandRequest {
    controller: String,
    program: String,
    /// As [`AnalyseRequest`]'s.
    #[serde(default)]
    start: Option<[f64; 2]>,
}

/// The whole expanded program, as `threadcut expand` writes it: `{ok, gcode}`, or `{ok: false,
/// error, diagnostics}`. The page asks for it when Copy or Download needs more than the lines its
/// analysis showed.
pub fn expand(request: &str) -> Value {
    let r: ExpandRequest = match serde_json::from_str(request) {
        Ok(r) => r,
        Err(e) => return error(format!("bad request: {e}")),
    };
    let Some(machine) = Machine::built_in(&r.controller) else {
        return error(format!("unknown controller `{}`", r.controller));
    };
    let options = program::Options {
        start: start_of(r.start),
        ..program::Options::default()
    };
    let mut out = Vec::new();
    match program::expand_gcode_with(r.program.as_bytes(), &mut out, &machine, &options) {
        Ok(_) => json!({"ok": true, "gcode": utf8(out)}),
        Err(e) => {
            let d = error_diagnostic(e, None);
            json!({"ok": false, "error": d["message"], "diagnostics": [d]})
        }
    }
}

#[derive(Deserialize)]
struct ConvertRequest {
    /// The controller the program is written for.
    from: String,
    /// The controller to write it for.
    to: String,
    program: String,
    /// A program with control flow: convert the executed program (`threadcut convert --flatten`).
    #[serde(default)]
    flatten: bool,
    /// The largest drift of a lead over its thread, in the converted program's units
    /// (`threadcut convert --max-lead-drift`); absent: a quarter of the class tolerance.
    #[serde(default)]
    max_lead_drift: Option<f64>,
    /// Named tools and the numbers that call them (`{"THREAD_EXT_60": "T0101"}`,
    /// `threadcut convert --tool THREAD_EXT_60=T0101`).
    #[serde(default)]
    tools: std::collections::BTreeMap<String, String>,
}

/// A program converted for another controller, as `threadcut convert` writes it
/// ([`threadcut::convert::convert`]): `{ok, from, to, program, native, plain: [{line, reason}],
/// warnings}`, or `{ok: false, error, diagnostics}` with the block that cannot be converted.
pub fn convert(request: &str) -> Value {
    let r: ConvertRequest = match serde_json::from_str(request) {
        Ok(r) => r,
        Err(e) => return error(format!("bad request: {e}")),
    };
    let machine = |name: &str| {
        Machine::built_in(name).ok_or_else(|| {
            let names: Vec<&str> = BUILT_IN.iter().map(|(n, _)| *n).collect();
            error(format!(
                "unknown controller `{name}` (built in: {})",
                names.join(", ")
            ))
        })
    };
    let (from, to) = match (machine(&r.from), machine(&r.to)) {
        (Ok(f), Ok(t)) => (f, t),
        (Err(e), _) | (_, Err(e)) => return e,
    };
    let mut out = Vec::new();
    let options = threadcut::convert::Options {
        run: threadcut::program::Options {
            flatten: r.flatten,
            ..Default::default()
        },
        max_lead_drift: r.max_lead_drift,
        tools: r.tools.into_iter().collect(),
    };
    match threadcut::convert::convert(r.program.as_bytes(), &mut out, &from, &to, &options) {
        Ok(report) => json!({
            "ok": true,
            "from": r.from,
            "to": r.to,
            "program": String::from_utf8_lossy(&out),
            "native": report.native,
            "plain": report
                .plain
                .iter()
                .map(|(line, reason)| json!({"line": line, "reason": reason}))
                .collect::<Vec<_>>(),
            "warnings": report
                .summary
                .warnings
                .iter()
                .map(|d| diagnostic(d, None))
                .collect::<Vec<_>>(),
        }),
        Err(e) => {
            let d = error_diagnostic(e, None);
            json!({
                "ok": false,
                "from": r.from,
                "to": r.to,
                "error": d["message"],
                "diagnostics": [d],
            })
        }
    }
}
