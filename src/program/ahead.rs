//! Plain lines read ahead: a second core (the command's) reads a later part of a program while
//! the run reads the part before it, and the run takes the lines read ahead without reading them
//! again when the state it reached equals the one the look ahead assumed (docs/architecture.md,
//! "Reading ahead").
//!
//! The library stays single-threaded (it builds for wasm32): this module only has the two halves
//! of the work, each a plain function of its inputs. [`looker`] reads a part of the input from
//! an assumed state, as [`expand`](super::expand_gcode_to)'s run would: the lines its fast path
//! takes (no cycle, no line for the dialect, no control flow, no error), the state after them. The
//! run asks an [`Ahead`] at its seams and takes the lines only where
//! - its dialect is [at rest](crate::dialect::Dialect::at_rest) (its prefilter then answers as
//!   the fresh dialect the look ahead used), and
//! - its modal state is [the same](Modal::same), to the bit, as the one the look ahead started
//!   from.
//!
//! Reading a line depends on nothing before it but that state, so the lines taken, their errors
//! (none) and the state after them are exactly what the run would have found; their bytes are
//! copied unchanged as ever. Where the state differs the run reads the lines itself.

use super::{Control, Error};
use crate::dialect::{self, Dialect};
use crate::gcode::{Conventions, Modal, Reader};
use crate::machine::Machine;

/// Lines a look ahead read from a seam on, all of them plain.
#[derive(Clone, Debug)]
pub struct Taken {
    /// The state the look ahead assumed at the seam.
    pub entry: Modal,
    /// The state after the lines.
    pub exit: Modal,
    /// Their bytes and their number (whole lines, each with its line end but perhaps the input's
    /// last).
    pub bytes: u64,
    pub lines: u32,
}

/// What a run asks at its seams (the command's look ahead).
pub trait Ahead {
    /// The first seam: an offset in the input. The run stops at the first line that starts at or
    /// after a seam, and calls [`at`](Ahead::at) there.
    fn first_seam(&mut self) -> u64;
    /// The run is at `offset`, the first line start at or after the last seam given, with
    /// `modal`; `at_rest`: its dialect is at rest. The lines read ahead from `offset`, if any,
    /// and the next seam (`u64::MAX`: none). The run checks the lines' entry state itself.
    fn at(&mut self, offset: u64, modal: &Modal, at_rest: bool) -> (Option<Taken>, u64);
}

/// A look ahead for `machine`'s dialect, opened once: called with the state at some line start,
/// the lines from there to a seam (`warm`, read to guess the state at the seam) and the lines
/// after the seam (`text`, whole lines), it returns the plain lines at the front of `text` and
/// the state it assumed at the seam (`warm` read from `modal`). `None` when a line of `warm` is
/// not plain, or a line's modal state is an error (the run finds it itself).
pub type Looker = Box<dyn FnMut(&Modal, &[u8], &[u8]) -> Option<Taken>>;

/// [`Looker`] for `machine`'s dialect.
pub fn looker(machine: &Machine) -> Result<Looker, Error> {
    dialect::open_with(machine, Open).map_err(Error::Setup)
}

struct Open;

impl dialect::WithDialect for Open {
    type Output = Looker;
    fn run<D: Dialect + 'static>(self, dialect: D) -> Looker {
        let conv = dialect.conventions().clone();
        Box::new(move |modal, warm, text| {
            let mut modal = modal.clone();
            let (_, _, whole) = plain_lines(&dialect, &conv, &mut modal, warm)?;
            if !whole {
                return None;
            }
            let entry = modal.clone();
            let (bytes, lines, _) = plain_lines(&dialect, &conv, &mut modal, text)?;
            Some(Taken {
                entry,
                exit: modal,
                bytes,
                lines,
            })
        })
    }
}

/// The lines at the front of `text` that the run's fast path would take as plain with a dialect
/// at rest (`program::drive_with`: not the dialect's, no control flow, no error), `modal` after
/// them: their bytes, their number, and whether they are all of `text`. `None` when a line's
/// state is an error: `modal` is then spoilt.
fn plain_lines<D: Dialect>(
    dialect: &D,
    conv: &Conventions,
    modal: &mut Modal,
    text: &[u8],
) -> Option<(u64, u32, bool)> {
    let macros = dialect.macros();
    let mut reader = Reader::new(text).with_syntax(conv.syntax);
    let mut lines = 0;
    // One line a round: bounded by `text`.
    loop {
        let offset = reader.offset();
        let line = match reader.next_line() {
            None => return Some((offset, lines, true)),
            Some(Ok(line)) => line,
            // The run reports it (or its interpreter reads it).
            Some(Err(_)) => return Some((offset, lines, false)),
        };
        if dialect.prefilter(&line)
            || macros
                .as_ref()
                .is_some_and(|m| m.control(&line) != Control::No)
        {
            return Some((offset, lines, false));
        }
        modal.advance(conv, &line).ok()?;
        lines += 1;
    }
}
