//! `threadcut passes`: each cycle's pass table with the simulated columns, as text or as
//! `{"cycles":[…]}` streamed one cycle at a time. G-code and APT input share it.

use std::io::{self, Write};

use threadcut::check::ThreadBlank;
use threadcut::commands;
use threadcut::program::{self, Error};
use threadcut::sim::{self, tip_in_mm, Tip, Tool};
use threadcut::thread::standard::StandardThread;
use threadcut::thread::PassKind;
use threadcut::threads::{self, Thread};

use super::ReportFormat;

pub struct PassesWriter {
    format: ReportFormat,
    tip: Tip,
    cycles: usize,
    measuring: Option<Measuring>,
}

/// What a thread will measure is stated when the tool's form is known: its tip given, or the
/// standard thread named (`--thread`, its root form then assumed at the tip).
pub struct Measuring {
    /// The tip as given (program units).
    pub tip: Option<Tip>,
    pub thread: Option<StandardThread>,
    /// The wire one owns (mm).
    pub wire: Option<f64>,
}

impl PassesWriter {
    pub fn begin(out: &mut dyn Write, format: ReportFormat, tip: Tip) -> io::Result<PassesWriter> {
        if format == ReportFormat::Json {
            out.write_all(br#"{"cycles":["#)?;
        }
        Ok(PassesWriter {
            format,
            tip,
            cycles: 0,
            measuring: None,
        })
    }

    /// States, for each thread, what it will measure (`measure: …`; `measure` in JSON).
    pub fn measuring(mut self, m: Measuring) -> PassesWriter {
        self.measuring = Some(m);
        self
    }

    fn reading(&self, t: &Thread) -> Option<Result<threadcut::check::Reading, String>> {
        let m = self.measuring.as_ref()?;
        let tip = m.tip.map(|tip| tip_in_mm(tip, t.job.units));
        Some(threadcut::check::reading(t, tip, m.thread.as_ref(), m.wire))
    }

    /// One thread. `decimals`: of depths and positions in the table; `columns`: what the title says
    /// of the columns (X a radius, for APT), if anything.
    pub fn thread(
        &mut self,
        out: &mut dyn Write,
        t: &Thread,
        decimals: usize,
        columns: &str,
    ) -> Result<(), Error> {
        self.thread_with(out, t, decimals, columns, None)
    }

    /// [`PassesWriter::thread`] with the thread's blank as `check` took it: a `blank` object in
    /// JSON, a line after the title in text.
    pub fn thread_with(
        &mut self,
        out: &mut dyn Write,
        t: &Thread,
        decimals: usize,
        columns: &str,
        blank: Option<&ThreadBlank>,
    ) -> Result<(), Error> {
        let job = &t.job;
        let passes = &t.passes;
        let rows = program::pass_rows(job, passes, t.diameter_x);
        // The simulated columns: chip area with the tool's real tip, share, cutting flank. A tool
        // the section cannot draw (a 0° angle, an absurd size) leaves them empty rather than
        // failing the table the controller accepted.
        let tool = Tool {
            angle_deg: job.tool_angle_deg,
            tip: tip_in_mm(self.tip, job.units),
        };
        let section = sim::section(job, passes, &tool, 0.0).ok();
        let sim = |i: usize| section.as_ref().and_then(|s| s.passes.get(i));
        let area_scale = job.units.scale() * job.units.scale();
        if self.format != ReportFormat::Text {
            if self.cycles > 0 && self.format == ReportFormat::Json {
                out.write_all(b",")?;
            }
            let mut cycle = threads::passes_json(t, section.as_ref());
            if let (Some(o), Some(b)) = (cycle.as_object_mut(), blank) {
                o.insert("blank".into(), commands::blank_json(b));
            }
            if let (Some(o), Some(f)) = (cycle.as_object_mut(), called_file(t)) {
                o.insert("file".into(), f.into());
            }
            if let (Some(o), Some(r)) = (cycle.as_object_mut(), self.reading(t)) {
                o.insert("measure".into(), commands::reading_json(&r, job.units));
            }
            serde_json::to_writer(&mut *out, &cycle).map_err(io::Error::other)?;
            if self.format == ReportFormat::Jsonl {
                out.write_all(b"\n")?;
            }
        } else {
            let d = decimals;
            let rough = passes.iter().filter(|p| p.kind == PassKind::Rough).count();
            writeln!(
                out,
                "line {}{}: {}{columns}, {} ({}){}",
                job.line,
                called_file(t).map_or(String::new(), |f| format!(" of {f}")),
                t.describe(),
                threadcut::text::rough_and_finishing(rough, passes.len() - rough),
                job.units.name(),
                if t.crest_known() {
                    ""
                } else {
                    "; depths from the first pass: the crest is not known"
                }
            )?;
            if let Some(b) = blank {
                writeln!(out, "{}", commands::blank_text(b))?;
            }
            if let Some(r) = self.reading(t) {
                writeln!(out, "{}", commands::reading_text(&r, job.units))?;
            }
            if let Some(note) = t.start_note() {
                writeln!(out, "note: {note}")?;
            }
            let z_known = !t.unknown_start[1];
            writeln!(
                out,
                "{:>4}  {:<6} {:>10} {:>10} {:>11} {:>11} {:>10} {:>6} {:>10} {:>6}  {:<5}",
                "pass",
                "kind",
                "depth",
                "increment",
                "x",
                "z",
                "area",
                "share",
                "sim area",
                "share",
                "flank"
            )?;
            for (i, r) in rows.iter().enumerate() {
                let kind = match r.kind {
                    PassKind::Rough => "rough",
                    PassKind::Finish => "finish",
                };
                writeln!(
                    out,
                    "{:>4}  {:<6} {:>10.d$} {:>10.d$} {:>11.d$} {:>11} {:>10.5} {:>5.1}% {:>10} {:>6}  {:<5}",
                    r.n,
                    kind,
                    r.depth,
                    r.increment,
                    r.x,
                    if z_known {
                        format!("{:.d$}", r.z)
                    } else {
                        "?".into()
                    },
                    r.area,
                    r.share * 100.0,
                    sim(i).map_or("-".into(), |s| format!("{:.5}", s.area / area_scale)),
                    sim(i).map_or("-".into(), |s| format!("{:.1}%", s.share * 100.0)),
                    sim(i).map_or("-", |s| s.flank.name())
                )?;
            }
            writeln!(out)?;
        }
        self.cycles += 1;
        Ok(())
    }

    pub fn end(self, out: &mut dyn Write) -> io::Result<()> {
        if self.format == ReportFormat::Json {
            out.write_all(b"]}\n")?;
        }
        Ok(())
    }
}

/// The name of the called file a thread lies in (`--include`), if it is not in the program's own
/// file: the table's title and its JSON (`file`) name it.
fn called_file(t: &Thread) -> Option<String> {
    (t.job.span.file() != 0).then(|| super::render::file_of(std::path::Path::new(""), &t.job.span))
}
