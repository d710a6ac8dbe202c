//! `threadcut passes` as a table: each thread's passes with the simulated columns. The JSON form
//! is the library's (`commands::passes_json`); G-code and APT input share both.

use std::io::{BufRead, Write};

use threadcut::commands::{self, Run, Source};
use threadcut::program::Error;
use threadcut::sim::Tip;
use threadcut::thread::PassKind;
use threadcut::threads::Thread;

/// Every thread's table, one after the other.
pub fn text<R: BufRead>(
    input: R,
    source: Source,
    tip: Tip,
    out: &mut dyn Write,
) -> Result<Run, Error> {
    commands::each_thread(input, source, |t| {
        // Depths and positions to one decimal beyond the control's resolution; APT's X is the CL
        // radius, said in the title.
        let (decimals, columns) = match source {
            Source::Gcode(machine) => (machine.decimals(t.job.units) as usize + 1, ""),
            Source::Apt(_) => (
                if t.job.units == threadcut::units::Units::Inch {
                    5
                } else {
                    4
                },
                " (APT; depth along the in-feed axis, X a radius)",
            ),
        };
        thread(out, &t, tip, decimals, columns)
    })
}

/// One thread. `decimals`: of depths and positions in the table; `columns`: what the title says
/// of the columns (X a radius, for APT), if anything.
fn thread(
    out: &mut dyn Write,
    t: &Thread,
    tip: Tip,
    decimals: usize,
    columns: &str,
) -> Result<(), Error> {
    let job = &t.job;
    let passes = &t.passes;
    let rows = threadcut::program::pass_rows(job, passes, t.diameter_x);
    let section = t.simulated(tip);
    let sim = |i: usize| section.as_ref().and_then(|s| s.passes.get(i));
    let area_scale = job.units.scale() * job.units.scale();
    let d = decimals;
    let rough = passes.iter().filter(|p| p.kind == PassKind::Rough).count();
    writeln!(
        out,
        "line {}: {}{columns}, {} rough + {} finishing passes ({}){}",
        job.line,
        t.describe(),
        rough,
        passes.len() - rough,
        job.units.name(),
        if t.crest_known() {
            ""
        } else {
            "; depths from the first pass: the crest is not known"
        }
    )?;
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
            "{:>4}  {:<6} {:>10.d$} {:>10.d$} {:>11.d$} {:>11.d$} {:>10.5} {:>5.1}% {:>10} {:>6}  {:<5}",
            r.n,
            kind,
            r.depth,
            r.increment,
            r.x,
            r.z,
            r.area,
            r.share * 100.0,
            sim(i).map_or("-".into(), |s| format!("{:.5}", s.area / area_scale)),
            sim(i).map_or("-".into(), |s| format!("{:.1}%", s.share * 100.0)),
            sim(i).map_or("-", |s| s.flank.name())
        )?;
    }
    writeln!(out)?;
    Ok(())
}
