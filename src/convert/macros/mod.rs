//! Macro programs translated with their structure: Fanuc/GSK/Haas Custom Macro B ⇄ LinuxCNC
//! o-words (docs/translation.md, "Macro programs").
//!
//! The source program is read into statements with the interpreter's own scanner and expression
//! parser ([`read`]), arranged as its structure ([`shape`]: loops, conditions, subprograms,
//! calls; Fanuc's GOTOs as the skips and loops they are), and written in the target's macro
//! language ([`emit`]). The blocks between the statements are converted as any block is, from the
//! program's run: each block's text is what the conversion of its runs wrote, expression words
//! written as expressions where the runs' numbers follow them ([`fit`]). The result is run
//! through the target's interpreter and its motion compared with the source's ([`verify`]):
//! a translation that does not move the same is refused.

mod emit;
mod fit;
mod read;
mod shape;
mod verify;

use std::collections::HashMap;

use crate::diag::{Code, Diagnostic, Span};
use crate::interp::{Lang, Syntax};
use crate::machine::Machine;
use crate::program;

pub use fit::Run;

/// What the structural translation needs.
pub struct Request<'a> {
    pub text: &'a [u8],
    pub from: &'a Machine,
    pub to: &'a Machine,
    pub syntax: Syntax,
    pub to_syntax: Syntax,
    /// Each line's runs (by line number), from the conversion of the executed program.
    pub runs: &'a HashMap<u32, Vec<Run>>,
    /// A comment in the target's style.
    pub comment: &'a dyn Fn(&str) -> String,
    pub run: &'a program::Options,
}

/// The program in the target's macro language, verified by its motion.
pub fn translate(r: &Request) -> Result<String, program::Error> {
    let stmts = read::program(r.text, &r.syntax)?;
    let shape = match r.syntax.lang {
        Lang::Ngc => shape::ngc(&stmts)?,
        _ => shape::macro_b(&stmts, &r.syntax)?,
    };
    let tol = verify::tolerance(r.from, r.to);
    // In the output's units: the coarser of the two controls' increments.
    let units_tol = [crate::units::Units::Mm, crate::units::Units::Inch]
        .into_iter()
        .flat_map(|u| [r.from.resolution(u), r.to.resolution(u)])
        .fold(0.0, f64::max)
        * 0.5
        + 1e-9;
    let mut main = Vec::new();
    shape::walk(&shape.main, &mut main);
    let mut blocks = Blocks::new();
    templates(&stmts, &main, r.runs, None, units_tol, &mut blocks)?;
    let mut copies = HashMap::new();
    for sub in &shape.subs {
        let mut lines = Vec::new();
        shape::walk(&sub.body, &mut lines);
        if let Some(callers) = sub_templates(&stmts, &lines, r.runs, units_tol, &mut blocks)? {
            copies.insert(sub.name.clone(), callers);
        }
    }
    let text = emit::Emit::new(
        &stmts,
        r.syntax,
        r.to_syntax,
        &blocks,
        r.comment,
        (r.from.diameter_x, r.to.diameter_x),
    )
    .program(&shape, &copies)?;
    check(r, &text, tol)?;
    Ok(text)
}

/// Each line's text, by its index and, in a subprogram written once for each call, the line of the
/// call.
pub type Blocks = HashMap<(usize, Option<u32>), Vec<fit::Piece>>;

/// The texts of `lines` from their runs (those of `caller`'s call only, when given).
fn templates(
    stmts: &[read::Stmt],
    lines: &[usize],
    runs: &HashMap<u32, Vec<Run>>,
    caller: Option<u32>,
    tol: f64,
    blocks: &mut Blocks,
) -> Result<(), Diagnostic> {
    for &i in lines {
        let s = &stmts[i];
        let Some(runs) = runs.get(&s.number) else {
            continue;
        };
        let runs: Vec<Run> = runs
            .iter()
            .filter(|r| caller.is_none() || r.caller == caller)
            .cloned()
            .collect();
        if runs.is_empty() {
            continue;
        }
        let words = match &s.st {
            read::St::Block(w) => w.as_slice(),
            _ => &[],
        };
        blocks.insert(
            (i, caller),
            fit::template(&runs, words, s.span, s.number, tol)?,
        );
    }
    Ok(())
}

/// A subprogram's texts: one for all its calls, or, where a block has no one text (a cycle whose
/// passes are computed from the call's arguments), one copy of the subprogram for each line that
/// calls it, the calls' lines returned.
fn sub_templates(
    stmts: &[read::Stmt],
    lines: &[usize],
    runs: &HashMap<u32, Vec<Run>>,
    tol: f64,
    blocks: &mut Blocks,
) -> Result<Option<Vec<u32>>, Diagnostic> {
    let Err(one) = templates(stmts, lines, runs, None, tol, blocks) else {
        return Ok(None);
    };
    let mut callers: Vec<u32> = lines
        .iter()
        .flat_map(|i| runs.get(&stmts[*i].number).into_iter().flatten())
        .filter_map(|r| r.caller)
        .collect();
    callers.sort_unstable();
    callers.dedup();
    if callers.len() < 2 {
        return Err(one);
    }
    for c in &callers {
        if templates(stmts, lines, runs, Some(*c), tol, blocks).is_err() {
            return Err(one);
        }
    }
    Ok(Some(callers))
}

/// The converted program moves as the source does.
fn check(r: &Request, text: &str, tol: f64) -> Result<(), program::Error> {
    let options = program::Options {
        flatten: false,
        ..r.run.clone()
    };
    let source = verify::motion(r.text, r.from, &options)?;
    let converted = verify::motion(text.as_bytes(), r.to, &options).map_err(|e| {
        let why = match e {
            program::Error::Input(d) => format!("line {}: {}", d.span.line, d.message),
            e => e.to_string(),
        };
        refused(format!(
            "the program translated for {} does not run there ({why}); threadcut does not write a program it cannot verify",
            r.to.name
        ))
    })?;
    match verify::differs(&source, &converted, tol) {
        None => Ok(()),
        Some(d) => Err(refused(format!(
            "the program translated for {} does not move as the source does ({d}); threadcut does not write it",
            r.to.name
        ))),
    }
}

fn refused(msg: String) -> program::Error {
    program::Error::Input(
        Diagnostic::error(Code::Unsupported, Span::default(), msg)
            .with_hint("--flatten writes the executed program instead"),
    )
}
