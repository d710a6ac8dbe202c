//! `threadcut post FILE.apt --controller C`, and the APT side of `passes` and `expand`.

use std::io::{BufRead, Write};
use std::path::Path;

use threadcut::apt;
use threadcut::machine::Machine;
use threadcut::program::{Error, Summary};

use super::input::Content;
use super::passes::PassesWriter;
use super::{lib, not_empty, output, warn, Failure, ReportFormat};

/// Whether `input` (not yet consumed) holds APT/CL source.
pub fn is_apt(file: &Path, input: &mut dyn BufRead) -> bool {
    let head = input.fill_buf().map(|b| b.to_vec()).unwrap_or_default();
    apt::looks_like_apt(file, &head)
}

/// `threadcut post`.
pub fn post(
    file: &Path,
    input: Box<dyn BufRead>,
    content: &Content,
    machine: &Machine,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let summary = output::write(file, out, |w| {
        let summary = apt::post::write(input, w, machine).map_err(lib(file))?;
        not_empty(file, content)?;
        Ok(summary)
    })?;
    warn(file, &summary);
    Ok(())
}

/// `threadcut expand FILE.apt --format jsonl`.
pub fn expand_jsonl(
    file: &Path,
    input: Box<dyn BufRead>,
    content: &Content,
    out: Option<&Path>,
) -> Result<(), Failure> {
    let summary = output::write(file, out, |w| {
        let summary = apt::expand_jsonl(input, w).map_err(lib(file))?;
        not_empty(file, content)?;
        Ok(summary)
    })?;
    warn(file, &summary);
    Ok(())
}

/// `threadcut passes FILE.apt`: the same table and JSON schema as for G-code; X is the CL radius.
pub fn passes(
    file: &Path,
    input: Box<dyn BufRead>,
    content: &Content,
    format: ReportFormat,
    out: Option<&Path>,
    tip: threadcut::sim::Tip,
) -> Result<(), Failure> {
    let (summary, count) = output::write(file, out, |w| {
        let done = passes_to(input, w, format, tip).map_err(lib(file))?;
        not_empty(file, content)?;
        Ok(done)
    })?;
    warn(file, &summary);
    if count == 0 {
        super::no_thread(file, threadcut::commands::APT_THREAD_STATEMENTS);
    }
    Ok(())
}

fn passes_to(
    input: Box<dyn BufRead>,
    out: &mut dyn Write,
    format: ReportFormat,
    tip: threadcut::sim::Tip,
) -> Result<(Summary, u32), Error> {
    let mut writer = PassesWriter::begin(out, format, tip)?;
    let mut count = 0;
    let summary = threadcut::threads::each_apt(input, |t| {
        count += 1;
        let decimals = if t.job.units == threadcut::units::Units::Inch {
            5
        } else {
            4
        };
        writer.thread(
            out,
            &t,
            decimals,
            " (APT; depth along the in-feed axis, X a radius)",
        )
    })?;
    writer.end(out)?;
    Ok((summary, count))
}
