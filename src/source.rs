//! What a program is written in: G-code for a controller, or APT/CL ([`Source`]); which of the two
//! a text is ([`source`]); and what its control threads with ([`thread_codes`]), for saying that a
//! program has no thread. `check` and the commands both take a [`Source`].

use std::path::Path;

use crate::machine::Machine;

/// What the program is written in.
#[derive(Clone, Copy, Debug)]
pub enum Source<'m> {
    /// G-code for this machine's controller.
    Gcode(&'m Machine),
    /// APT/CL; a machine's limits apply when one is named.
    Apt(Option<&'m Machine>),
}

/// What `head` (the program's first bytes) is written in: APT/CL by the file's extension or its
/// first statement ([`crate::apt::looks_like_apt`]), otherwise G-code for `machine`. `name` is the
/// file's name, or an empty path for a program given as text. APT takes `machine` for the
/// commands that need one (`expand` to G-code, `check`'s limits); G-code without one is
/// [`crate::program::Error::Setup`] where it is read.
pub fn source<'m>(name: &Path, head: &[u8], machine: Option<&'m Machine>) -> Option<Source<'m>> {
    if crate::apt::looks_like_apt(name, head) {
        Some(Source::Apt(machine))
    } else {
        machine.map(Source::Gcode)
    }
}

/// What the program's controller threads with (`G32, G76, G92`; the APT statements for APT/CL),
/// for saying that a program has no thread.
pub fn thread_codes(source: Source) -> String {
    match source {
        Source::Apt(_) => crate::apt::THREAD_STATEMENTS.to_string(),
        Source::Gcode(machine) => crate::dialect::open(machine)
            .map(|d| d.vocabulary().thread_codes())
            .unwrap_or_default(),
    }
}
