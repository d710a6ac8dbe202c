//! `threadcut post FILE.apt --controller C`, and the APT side of `passes` and `expand`.

use std::io::{self, BufRead, Write};
use std::path::Path;

use threadcut::apt;
use threadcut::machine::Machine;
use threadcut::program::{self, Error, Summary};
use threadcut::thread::PassKind;

use super::{output, warn, Failure};

/// Whether `input` (not yet consumed) holds APT/CL source.
pub fn is_apt(file: &Path, input: &mut dyn BufRead) -> bool {
    let head = input.fill_buf().map(|b| b.to_vec()).unwrap_or_default();
    apt::looks_like_apt(file, &head)
}

/// `threadcut post`.
pub fn post(
    file: &Path,
    input: Box<dyn BufRead>,
    machine: &Machine,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let summary = output::write(file, out, |w| apt::post::write(input, w, machine))?;
    warn(file, &summary);
    Ok(())
}

/// `threadcut expand FILE.apt --format jsonl`.
pub fn expand_jsonl(
    file: &Path,
    input: Box<dyn BufRead>,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let summary = output::write(file, out, |w| apt::expand_jsonl(input, w))?;
    warn(file, &summary);
    Ok(())
}

/// `threadcut passes FILE.apt`: the same table and JSON schema as for G-code; X is the CL radius.
pub fn passes(
    file: &Path,
    input: Box<dyn BufRead>,
    json: bool,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let summary = output::write(file, out, |w| passes_to(input, w, json))?;
    warn(file, &summary);
    Ok(())
}

fn passes_to(input: Box<dyn BufRead>, out: &mut dyn Write, json: bool) -> Result<Summary, Error> {
    if json {
        out.write_all(br#"{"cycles":["#)?;
    }
    let mut first = true;
    let summary = apt::run(input, |_, ev| {
        let apt::Event::Cycle(job) = ev else {
            return Ok(());
        };
        let passes = job.passes()?;
        let rows = program::pass_rows(&job, &passes, false);
        if json {
            if !first {
                out.write_all(b",")?;
            }
            let cycle = serde_json::json!({
                "line": job.line,
                "controller": job.controller,
                "units": job.units,
                "passes": rows,
            });
            serde_json::to_writer(&mut *out, &cycle).map_err(io::Error::other)?;
        } else {
            let d = if job.units == threadcut::units::Units::Inch {
                5
            } else {
                4
            };
            let rough = passes.iter().filter(|p| p.kind == PassKind::Rough).count();
            writeln!(
                out,
                "line {}: APT THREAD/ON cycle, {} rough + {} finishing passes ({}; depth along the in-feed axis, X a radius)",
                job.line,
                rough,
                passes.len() - rough,
                job.units.name()
            )?;
            writeln!(
                out,
                "{:>4}  {:<6} {:>10} {:>10} {:>11} {:>11} {:>10} {:>6}",
                "pass", "kind", "depth", "increment", "x", "z", "area", "share"
            )?;
            for r in &rows {
                let kind = match r.kind {
                    PassKind::Rough => "rough",
                    PassKind::Finish => "finish",
                };
                writeln!(
                    out,
                    "{:>4}  {:<6} {:>10.d$} {:>10.d$} {:>11.d$} {:>11.d$} {:>10.5} {:>5.1}%",
                    r.n,
                    kind,
                    r.depth,
                    r.increment,
                    r.x,
                    r.z,
                    r.area,
                    r.share * 100.0
                )?;
            }
            writeln!(out)?;
        }
        first = false;
        Ok(())
    })?;
    if json {
        out.write_all(b"]}\n")?;
    }
    Ok(summary)
}
