//! The `threadcut` commands as library functions, one per command, shared by the command line, the
//! Python package and any other binding: each takes the program and the options as values and
//! writes or returns the command's data, so that every surface gives the same JSON and text for
//! the same program. A surface only reads its files, parses its own arguments and prints.
//!
//! | command | function |
//! | --- | --- |
//! | `controllers` | [`controllers`] |
//! | `passes --json` | [`passes_json`], [`passes_json_with`] (each thread's blank; text: [`each_thread`], [`Thread::simulated`], [`Blanks`]) |
//! | `expand` (`--format gcode`/`jsonl`) | [`expand`] |
//! | `plot` | [`plot_program`] (the part the program makes, from `check`, and [`plot`]) |
//! | `convert` | [`crate::convert::convert_text`] |
//! | `check` | [`crate::check::check`] |
//! | `post` | [`crate::apt::post::write`] |
//! | `thread --json` | [`StandardThread::to_json`](crate::thread::standard::StandardThread::to_json) |
//! | `mill` | [`crate::mill::Request::prepare`] |
//!
//! The stock the options give over a machine profile's `[stock]`: [`with_stock`].
//!
//! A program is G-code for a controller or APT/CL ([`Source`], as `check` takes it; [`source`]
//! tells which from the text).

pub mod milled;

use std::io::{BufRead, Write};

use crate::check::{self, ThreadBlank};
use crate::machine::{Machine, BUILT_IN};
use crate::program::{self, Error, Summary};
pub use crate::render::{PartPicture, Plot, Selection};
use crate::sim::Tip;
pub use crate::source::{source, thread_codes, Source};
use crate::threads::{self, Thread};
use crate::units::Units;

/// What a run over a program found besides its output: the reader's summary (lines, the
/// dialect's warnings) and the number of threads.
#[derive(Debug, Default)]
pub struct Run {
    pub summary: Summary,
    pub threads: u32,
}

/// What a controller profile is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// A lathe: `expand`, `passes`, `check`, `plot`, `convert`, `post`.
    Lathe,
    /// A milling machine: `mill`.
    Mill,
}

/// One built-in controller profile.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Controller {
    pub name: &'static str,
    pub kind: Kind,
    pub description: String,
}

/// `threadcut controllers`: every built-in profile, the lathe controllers first, then the milling
/// ones, each in the order of its table.
pub fn controllers() -> Vec<Controller> {
    let lathes = BUILT_IN.iter().map(|(name, _)| Controller {
        name,
        kind: Kind::Lathe,
        description: Machine::built_in(name)
            .map(|m| m.description)
            .unwrap_or_default(),
    });
    let mills = crate::mill::profile::BUILT_IN
        .iter()
        .map(|(name, _)| Controller {
            name,
            kind: Kind::Mill,
            description: crate::mill::profile::MillProfile::built_in(name)
                .map(|m| m.description)
                .unwrap_or_default(),
        });
    lathes.chain(mills).collect()
}

/// What to say of a program in which no thread was found, `codes` what its controller threads
/// with ([`thread_codes`]).
pub fn no_thread(codes: &str) -> String {
    format!(
        "no thread found: no threading cycle and no synchronised move (this controller threads with {codes}; is it the right --controller?)"
    )
}

/// The statements an APT/CL program threads with.
pub use crate::apt::THREAD_STATEMENTS as APT_THREAD_STATEMENTS;

/// Every thread of a program, in order, to `each`: [`threads::each_gcode`] or
/// [`threads::each_apt`]; depths from the crest where the program gives it, else from the first
/// pass.
pub fn each_thread<R: BufRead>(
    input: R,
    source: Source,
    options: &program::Options,
    mut each: impl FnMut(Thread) -> Result<(), Error>,
) -> Result<Run, Error> {
    let mut count = 0;
    let mut counted = |t: Thread| {
        count += 1;
        each(t)
    };
    let summary = match source {
        Source::Gcode(machine) => {
            threads::each_gcode_with(input, machine, None, options, &mut counted)?
        }
        Source::Apt(_) => threads::each_apt(input, &mut counted)?,
    };
    Ok(Run {
        summary,
        threads: count,
    })
}

/// `threadcut passes --json`: `{"cycles":[…]}` and a newline, one object per thread
/// ([`threads::passes_json`], the simulated columns cut with `tip`, in program units), written as
/// each thread is found. `options`: the run's limits and what a program with control flow does
/// ([`program::Options`]).
pub fn passes_json<R: BufRead>(
    input: R,
    source: Source,
    tip: Tip,
    options: &program::Options,
    out: &mut dyn Write,
) -> Result<Run, Error> {
    out.write_all(br#"{"cycles":["#)?;
    let mut first = true;
    let run = each_thread(input, source, options, |t| {
        if !first {
            out.write_all(b",")?;
        }
        first = false;
        let section = t.simulated(tip);
        let cycle = threads::passes_json(&t, section.as_ref());
        serde_json::to_writer(&mut *out, &cycle).map_err(std::io::Error::other)?;
        Ok(())
    })?;
    out.write_all(b"]}\n")?;
    Ok(run)
}

/// What `expand` writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ExpandFormat {
    /// The program with each cycle replaced by plain moves in the controller's format; an APT/CL
    /// program posted for the machine ([`crate::apt::post::write`]).
    Gcode,
    /// One JSON object per motion, program units, X as a radius
    /// ([`crate::post::motion_json`]).
    Jsonl,
}

/// `threadcut expand`: [`program::expand_gcode`] or [`program::expand_jsonl`] for G-code; for
/// APT/CL, the post ([`crate::apt::post::write`], which needs the machine) or
/// [`crate::apt::expand_jsonl`].
pub fn expand<R: BufRead>(
    input: R,
    source: Source,
    format: ExpandFormat,
    options: &program::Options,
    out: &mut dyn Write,
) -> Result<Summary, Error> {
    match (source, format) {
        (Source::Gcode(machine), ExpandFormat::Gcode) => {
            program::expand_gcode_with(input, out, machine, options)
        }
        (Source::Gcode(machine), ExpandFormat::Jsonl) => {
            program::expand_jsonl_with(input, out, machine, options)
        }
        (Source::Apt(Some(machine)), ExpandFormat::Gcode) => {
            crate::apt::post::write(input, out, machine)
        }
        (Source::Apt(None), ExpandFormat::Gcode) => Err(Error::Setup(
            "an APT/CL program is posted for a controller: name one".to_string(),
        )),
        (Source::Apt(_), ExpandFormat::Jsonl) => crate::apt::expand_jsonl(input, out),
    }
}

/// `threadcut plot`: the SVG of the threads' pass diagrams and XZ toolpaths
/// ([`crate::render::program_plot_with`], [`crate::render::apt_plot`]), the tool's tip in program
/// units: at most [`crate::render::MAX_PLOTTED`] threads, or the one `selection` names, the picture
/// saying what it left out ([`Plot::drawn`]).
pub fn plot<R: BufRead>(
    input: R,
    source: Source,
    tip: Tip,
    selection: Selection,
    options: &program::Options,
) -> Result<Plot, Error> {
    match source {
        Source::Gcode(machine) => {
            crate::render::program_plot_with(input, machine, tip, selection, options)
        }
        Source::Apt(_) => crate::render::apt_plot(input, tip, selection),
    }
}

/// `check`'s options with the stock: each value the caller gives (`--stock-diameter`,
/// `--stock-start`, `--stock-length`, `--stock-bore`), else the machine profile's `[stock]`.
pub fn with_stock(
    opts: check::Options,
    given: crate::machine::Stock,
    machine: Option<&Machine>,
) -> check::Options {
    let stock = given.over(machine.and_then(|m| m.stock).unwrap_or_default());
    check::Options {
        stock_diameter: stock.diameter,
        stock_start: stock.face,
        stock_length: stock.length,
        stock_bore: stock.bore,
        ..opts
    }
}

/// The picture of the part `check` found ([`check::Report::part`]), labelled in `units`.
pub fn part_picture(view: &check::whole::View, units: Units) -> PartPicture {
    use crate::render::part::{Hit, TeethBand};
    PartPicture {
        stock: view.stock,
        outline: view.outline.clone(),
        teeth: view
            .teeth
            .iter()
            .map(|t| TeethBand {
                line: t.line,
                crest: t.crest,
                root: t.root,
            })
            .collect(),
        hits: view
            .hits
            .iter()
            .map(|h| Hit {
                line: h.line,
                from: h.from,
                to: h.to,
                at: h.at,
                error: h.error,
            })
            .collect(),
        hits_complete: view.hits.len() < check::whole::VIEW_HITS_MAX,
        units,
    }
}

/// What `plot` draws of the part the program makes.
#[derive(Clone, Debug, Default)]
pub struct PartPlot {
    /// The check the part comes from: its stock and tool ([`with_stock`]).
    pub check: check::Options,
    /// The part alone, without the threads' panels (`plot --part`).
    pub alone: bool,
}

/// `threadcut plot` with the part: the picture of [`plot`], with the part the program makes
/// drawn above the threads where the program cut anything, a stock is given or a rapid runs into
/// material ([`crate::render::part`]); or the part alone. The program is read twice (`open` gives
/// it each time): once by `check`, once for the threads. APT/CL programs cut no part: their
/// picture is [`plot`]'s, and the part alone is refused.
pub fn plot_program<R: BufRead>(
    mut open: impl FnMut() -> std::io::Result<R>,
    source: Source,
    tip: Tip,
    selection: Selection,
    options: &program::Options,
    part: &PartPlot,
) -> Result<Plot, Error> {
    let Source::Gcode(machine) = source else {
        if part.alone {
            return Err(Error::Setup(
                "the part is drawn for G-code programs: an APT/CL file's moves are not cut into a part".into(),
            ));
        }
        return plot(open()?, source, tip, selection, options);
    };
    let opts = check::Options {
        max_blocks: options.max_blocks,
        library: options.library.clone(),
        call: options.call.clone(),
        start: options.start,
        ..part.check.clone()
    };
    let report = check::check(open()?, source, &opts)?;
    let picture = part_picture(&report.part, machine.units);
    if report.stopped {
        // The controller's alarm: the threads' run stops at it with the same error.
        return crate::render::program_plot_with(open()?, machine, tip, selection, options);
    }
    if part.alone {
        return Ok(Plot {
            svg: crate::render::part::svg(&picture),
            summary: Summary {
                lines: report.lines,
                ..Summary::default()
            },
            threads: report.threads as usize,
            drawn: Vec::new(),
        });
    }
    let shown = picture.worth_drawing().then_some(&picture);
    crate::render::program_plot_part(open()?, machine, tip, selection, options, shown)
}

/// Each thread's blank as `check` took it ([`check::Report::blanks`]), handed out in program
/// order to the threads `passes` lists.
#[derive(Debug, Default)]
pub struct Blanks {
    blanks: Vec<ThreadBlank>,
    next: usize,
}

impl Blanks {
    /// The blanks of `check` run over the program with `opts` (its stock and tool). A program
    /// `check` cannot read has none.
    pub fn of<R: BufRead>(input: R, source: Source, opts: &check::Options) -> Blanks {
        Blanks {
            blanks: check::check(input, source, opts)
                .map(|r| r.blanks)
                .unwrap_or_default(),
            next: 0,
        }
    }

    /// The blank of the next thread, which starts at `line`: the first blank from where the last
    /// was taken that was checked at that line.
    pub fn take(&mut self, line: u32) -> Option<&ThreadBlank> {
        let i = self.blanks[self.next..]
            .iter()
            .position(|b| b.line == line)?
            + self.next;
        self.next = i + 1;
        self.blanks.get(i)
    }
}

/// A number of a blank: program units, to 6 decimals (finer than any control's resolution).
fn blank_number(v: f64) -> f64 {
    (v * 1e6).round() / 1e6
}

/// A thread's blank as `passes --format json` writes it: `{crest, crest_from, face, face_from}`,
/// the crest a diameter, program units.
pub fn blank_json(b: &ThreadBlank) -> serde_json::Value {
    serde_json::json!({
        "crest": blank_number(b.crest),
        "crest_from": b.crest_from,
        "face": blank_number(b.face),
        "face_from": b.face_from,
    })
}

/// A thread's blank as `passes` writes it in text: `blank: crest Ø19.8 (measured), face Z0
/// (assumed)`.
pub fn blank_text(b: &ThreadBlank) -> String {
    let word = |k: check::Basis| match k {
        check::Basis::Measured => "measured on the part the program turned",
        check::Basis::Given => "given",
        check::Basis::Assumed => "assumed",
        check::Basis::Unknown => "not known",
    };
    format!(
        "blank: crest Ø{} ({}), face Z{} ({})",
        check::number(blank_number(b.crest)),
        word(b.crest_from),
        check::number(blank_number(b.face)),
        word(b.face_from)
    )
}

/// [`passes_json`] with each thread's `blank` ([`blank_json`]) from `check` run over the same
/// program with `check` (its stock and tool): a G-code program is read twice (`open` gives it
/// each time).
pub fn passes_json_with<R: BufRead>(
    mut open: impl FnMut() -> std::io::Result<R>,
    source: Source,
    tip: Tip,
    options: &program::Options,
    check: &check::Options,
    out: &mut dyn Write,
) -> Result<Run, Error> {
    let opts = check::Options {
        max_blocks: options.max_blocks,
        library: options.library.clone(),
        call: options.call.clone(),
        start: options.start,
        ..check.clone()
    };
    // APT/CL: `passes` of a CL file states no blank (the command line's, which reads it without
    // a controller).
    let mut blanks = match source {
        Source::Gcode(_) => Blanks::of(open()?, source, &opts),
        Source::Apt(_) => Blanks::default(),
    };
    out.write_all(br#"{"cycles":["#)?;
    let mut first = true;
    let run = each_thread(open()?, source, options, |t| {
        if !first {
            out.write_all(b",")?;
        }
        first = false;
        let section = t.simulated(tip);
        let mut cycle = threads::passes_json(&t, section.as_ref());
        if let (Some(o), Some(b)) = (cycle.as_object_mut(), blanks.take(t.job.line)) {
            o.insert("blank".into(), blank_json(b));
        }
        if let (Some(o), Some(r)) = (cycle.as_object_mut(), reading_of(&t, check)) {
            o.insert("measure".into(), reading_json(&r, t.job.units));
        }
        serde_json::to_writer(&mut *out, &cycle).map_err(std::io::Error::other)?;
        Ok(())
    })?;
    out.write_all(b"]}\n")?;
    Ok(run)
}

/// What `passes` says a thread will measure ([`check::reading`]), as text after the table's
/// title: `measure: …`, or why it cannot be said.
pub fn reading_text(r: &Result<check::Reading, String>, units: Units) -> String {
    let r = match r {
        Ok(r) => r,
        Err(why) => return format!("measure: not stated: {why}"),
    };
    let u = units.name();
    let len = |mm: f64| check::length(units, mm);
    let mut parts = vec![format!(
        "pitch diameter {} {u} as cut",
        len(r.pitch_diameter)
    )];
    if let Some(o) = &r.over_wires {
        parts.push(format!(
            "over {} {u} wires{} M = {} {u} (with the lead angle, NBS H28; {} by the simple formula)",
            len(o.wire),
            if o.best { " (the best wire)" } else { "" },
            len(o.m.corrected),
            len(o.m.simple),
        ));
    }
    if let Some(w) = &r.window {
        let (lo, hi) = w.pitch_diameter;
        let mut s = format!(
            "{} allows a pitch diameter of {}–{} {u}",
            w.class,
            len(lo),
            len(hi)
        );
        if let Some((mlo, mhi)) = w.over_wires {
            s += &format!(" (M {}–{} {u})", len(mlo), len(mhi));
        }
        s += &if w.deeper.abs() < 5e-7 {
            ": it is at the window's middle".to_string()
        } else {
            format!(
                ": {} {} {u} {} (on the radius) brings it to the window's middle",
                if w.deeper > 0.0 {
                    "cutting"
                } else {
                    "stopping"
                },
                len(w.deeper.abs()),
                if w.deeper > 0.0 {
                    "deeper"
                } else {
                    "shallower"
                },
            )
        };
        parts.push(s);
    }
    let mut text = format!("measure: {}", parts.join("; "));
    if !r.assumed.is_empty() {
        text += &format!(" (assumed: {})", r.assumed.join("; "));
    }
    text
}

/// [`reading_text`] as the `measure` object of `passes --format json` (program units):
/// `{pitch_diameter, wire, best_wire, m, m_simple, class, pitch_diameter_min, pitch_diameter_max,
/// m_min, m_max, deeper, assumed}`, the keys that do not apply null; or `{not_stated: why}`.
pub fn reading_json(r: &Result<check::Reading, String>, units: Units) -> serde_json::Value {
    let r = match r {
        Ok(r) => r,
        Err(why) => return serde_json::json!({ "not_stated": why }),
    };
    let v = |mm: f64| units.from_mm(mm);
    let o = r.over_wires.as_ref();
    let w = r.window.as_ref();
    serde_json::json!({
        "pitch_diameter": v(r.pitch_diameter),
        "wire": o.map(|o| v(o.wire)),
        "best_wire": o.map(|o| o.best),
        "m": o.map(|o| v(o.m.corrected)),
        "m_simple": o.map(|o| v(o.m.simple)),
        "class": w.map(|w| w.class.clone()),
        "pitch_diameter_min": w.map(|w| v(w.pitch_diameter.0)),
        "pitch_diameter_max": w.map(|w| v(w.pitch_diameter.1)),
        "m_min": w.and_then(|w| w.over_wires).map(|m| v(m.0)),
        "m_max": w.and_then(|w| w.over_wires).map(|m| v(m.1)),
        "deeper": w.map(|w| v(w.deeper)),
        "assumed": r.assumed,
    })
}

/// What `t` will measure under `check`'s options, when they make the tool's form known (a tip
/// given, or a standard thread named); `None` otherwise.
pub fn reading_of(t: &Thread, check: &check::Options) -> Option<Result<check::Reading, String>> {
    if check.thread.is_none() && check.tip.is_none() {
        return None;
    }
    let units = t.job.units;
    let tip = check.tip.map(|tip| crate::sim::tip_in_mm(tip, units));
    let wire = check
        .wire
        .map(|w| check.thread.as_ref().map_or(units, |s| s.units).to_mm(w));
    Some(check::reading(t, tip, check.thread.as_ref(), wire))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    const G76: &str = "G0 X22 Z3\nG76 P010060 Q50 R0.02\nG76 X17.546 Z-20 P1227 Q400 F2\nG0 X40\n";

    fn fanuc() -> Machine {
        Machine::built_in("fanuc").unwrap()
    }

    #[test]
    fn controllers_lists_lathes_then_mills() {
        let all = controllers();
        assert_eq!(
            all.len(),
            BUILT_IN.len() + crate::mill::profile::BUILT_IN.len()
        );
        assert_eq!(all[0].name, BUILT_IN[0].0);
        assert_eq!(all[0].kind, Kind::Lathe);
        let centroid = all.iter().find(|c| c.name == "centroid").unwrap();
        assert_eq!(centroid.kind, Kind::Mill);
        assert!(all.iter().all(|c| !c.description.is_empty()));
    }

    #[test]
    fn source_is_apt_by_extension_or_first_statement() {
        let m = fanuc();
        let apt = source(Path::new(""), b"$$ cl\nPARTNO TEST\n", Some(&m));
        assert!(matches!(apt, Some(Source::Apt(Some(_)))));
        let by_name = source(Path::new("x.cl"), G76.as_bytes(), None);
        assert!(matches!(by_name, Some(Source::Apt(None))));
        assert!(matches!(
            source(Path::new(""), G76.as_bytes(), Some(&m)),
            Some(Source::Gcode(_))
        ));
        assert!(source(Path::new("x.nc"), G76.as_bytes(), None).is_none());
    }

    #[test]
    fn passes_json_is_one_object_per_thread() {
        let m = fanuc();
        let mut out = Vec::new();
        let run = passes_json(
            G76.as_bytes(),
            Source::Gcode(&m),
            Tip::Sharp,
            &Default::default(),
            &mut out,
        )
        .unwrap();
        assert_eq!(run.threads, 1);
        let v: serde_json::Value = serde_json::from_slice(&out).unwrap();
        let cycles = v["cycles"].as_array().unwrap();
        assert_eq!(cycles.len(), 1);
        let passes = cycles[0]["passes"].as_array().unwrap();
        // P1227 (1.227 mm) at the last pass; Q400 (0.4 mm) the first depth.
        let last = passes.last().unwrap();
        assert!((last["depth"].as_f64().unwrap() - 1.227).abs() < 5e-4);
        assert!((passes[0]["depth"].as_f64().unwrap() - 0.4).abs() < 5e-4);
        assert!(out.ends_with(b"]}\n"));
    }

    #[test]
    fn no_thread_gives_an_empty_list_and_the_codes_to_name() {
        let m = fanuc();
        let mut out = Vec::new();
        let run = passes_json(
            &b"G0 X10\n"[..],
            Source::Gcode(&m),
            Tip::Sharp,
            &Default::default(),
            &mut out,
        )
        .unwrap();
        assert_eq!(run.threads, 0);
        assert_eq!(out, b"{\"cycles\":[]}\n");
        assert_eq!(thread_codes(Source::Gcode(&m)), "G32, G76, G92");
        assert_eq!(thread_codes(Source::Apt(None)), APT_THREAD_STATEMENTS);
    }

    #[test]
    fn expand_of_apt_to_gcode_needs_a_machine() {
        let apt = "PARTNO X\nFROM/0,0,50\n";
        let e = expand(
            apt.as_bytes(),
            Source::Apt(None),
            ExpandFormat::Gcode,
            &Default::default(),
            &mut Vec::new(),
        );
        assert!(matches!(e, Err(Error::Setup(_))));
    }

    #[test]
    fn expand_jsonl_is_one_object_per_motion() {
        let m = fanuc();
        let mut out = Vec::new();
        expand(
            G76.as_bytes(),
            Source::Gcode(&m),
            ExpandFormat::Jsonl,
            &Default::default(),
            &mut out,
        )
        .unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<serde_json::Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert!(lines.iter().any(|v| v["kind"] == "thread"));
        assert!(lines.iter().all(|v| v["line"].as_u64().is_some()));
    }

    #[test]
    fn plot_draws_every_thread() {
        let m = fanuc();
        let two = format!("{G76}{G76}");
        let all = plot(
            two.as_bytes(),
            Source::Gcode(&m),
            Tip::Sharp,
            Selection::default(),
            &Default::default(),
        )
        .unwrap();
        assert_eq!((all.threads, all.drawn.len()), (2, 2));
        assert!(all.svg.starts_with("<svg") || all.svg.starts_with("<?xml"));
        let second = Selection {
            only: Some(2),
            ..Selection::default()
        };
        let one = plot(
            two.as_bytes(),
            Source::Gcode(&m),
            Tip::Sharp,
            second,
            &Default::default(),
        )
        .unwrap();
        assert_eq!((one.threads, one.drawn.len()), (2, 1));
        assert_eq!(one.drawn[0].0, 2);
    }
}
