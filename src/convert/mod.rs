//! A program for one controller rewritten for another: dialect → model → dialect.
//!
//! * Every threading cycle is read into the model ([`crate::thread::Job`]) by the source's dialect
//!   and written by [`crate::translate::write_job`]: the target's native cycle when some choice of
//!   its words reads back as the same motion, plain moves with the reason otherwise, or a refusal
//!   naming the target's limit.
//! * Every other block is read through the source's [`lexicon::Lexicon`] into machine-neutral
//!   meanings ([`block::Block`]: units, feed mode, spindle, tools, positions, …) and written
//!   through the target's ([`write`]). Positions become absolute, in the target profile's X
//!   convention; numbers always carry a decimal point; units the target does not have are
//!   converted (a metric program for the inch-only OmniTurn is written in inches, the lead's
//!   rounding over each thread stated).
//! * The converted program states at its start what the source program relied on: its units,
//!   absolute distances, X on diameter or radius, the ZX plane, its feed mode and rpm, in the
//!   target's words where the target has them.
//!
//! Nothing here names a controller: each dialect states its own lexicon. Decisions and the
//! results over every bundled example: `docs/translation.md`.

pub mod block;
pub mod lexicon;
mod write;

use std::io::{BufRead, Write};

use crate::diag::{Code, Diagnostic, Span};
use crate::dialect;
use crate::machine::Machine;
use crate::program::{self, Error, Event, Summary};

use block::Source;

/// What a conversion did besides writing the program.
#[derive(Debug, Default)]
pub struct Report {
    pub summary: Summary,
    /// Cycles written as the target's native cycle.
    pub native: u32,
    /// Cycles written as plain moves: the line of the cycle and why its native cycle was not used.
    pub plain: Vec<(u32, String)>,
}

/// Converts the program `input`, written for `from`, into a program for `to`, written to `out`.
/// Lines end as the input's first line does. With the same profile on both sides the program is
/// copied as it is. An error is the first block that cannot be converted, at its word, naming the
/// target's limit (the output up to it has been written).
pub fn convert<R: BufRead>(
    mut input: R,
    out: &mut dyn Write,
    from: &Machine,
    to: &Machine,
) -> Result<Report, Error> {
    let ending = crate::eol::LineEnding::peek(&mut input)?;
    let out = &mut crate::eol::Writer::new(out, ending);
    let source_dialect = dialect::open(from).map_err(Error::Setup)?;
    let target = dialect::open(to).map_err(Error::Setup)?;
    let conv = source_dialect.conventions().clone();
    let mut src = Source {
        name: &from.name,
        lexicon: source_dialect.lexicon(),
        dialect: source_dialect.as_ref(),
        uw_incremental: conv.uw_incremental,
        canned_cycles: conv.canned_cycles,
        paren_comments: !source_dialect.syntax().parens_not_comments,
        declared: Default::default(),
    };
    if from == to {
        // The program as it is, after a comment naming the conversion (after a leading `%`).
        let mut header = target
            .format()
            .comment(&format!("threadcut convert: {} to {}", from.name, to.name));
        let summary = program::run(input, from, |_, ev| {
            let line = match ev {
                Event::Plain { line, .. }
                | Event::Settings { line }
                | Event::Cycle { line, .. } => line,
            };
            if !line.shape.percent {
                if let Some(h) = header.take() {
                    writeln!(out, "{h}")?;
                }
            }
            out.write_all(line.raw)?;
            Ok(())
        })?;
        return Ok(Report {
            summary,
            ..Report::default()
        });
    }
    let mut w = write::Writer::new(out, from, to, target.as_ref(), src.lexicon)?;
    let summary = program::run(input, from, |modal, ev| match ev {
        Event::Plain { line, mv } => {
            w.header_before(line)?;
            if line.shape.percent {
                return w.delimiter();
            }
            let b = block::decode(line, &mut src, modal)?;
            w.plain(line, &b, mv, modal)
        }
        Event::Settings { line } => {
            w.header_before(line)?;
            w.comment_only(&block::comments(line.text, src.paren_comments))
        }
        Event::Cycle { line, job, .. } => {
            w.header_before(line)?;
            w.cycle(line, *job, &block::comments(line.text, src.paren_comments))
        }
    })?;
    let mut report = w.finish();
    report.summary = summary;
    Ok(report)
}

/// [`convert`] on a program held in memory: the converted text, or the first block that cannot be
/// converted (a profile that cannot be used is an error without a place).
pub fn convert_text(program: &str, from: &Machine, to: &Machine) -> Result<String, Diagnostic> {
    let mut out = Vec::new();
    match convert(program.as_bytes(), &mut out, from, to) {
        Ok(_) => Ok(String::from_utf8_lossy(&out).into_owned()),
        Err(Error::Input(d)) => Err(d),
        Err(e) => Err(Diagnostic::error(
            Code::Unsupported,
            Span::default(),
            e.to_string(),
        )),
    }
}
