//! `threadcut convert FILE --from C1 --to C2`: the library's conversion
//! ([`threadcut::convert::convert`]), its output written as the command writes every output.
//! Decisions: `docs/translation.md`.

use std::io::{BufRead, Write};

use threadcut::convert::Report;
use threadcut::machine::Machine;
use threadcut::program::{Error, Options};

/// Converts `input` (for `from`) into a program for `to`.
pub fn convert(
    input: Box<dyn BufRead>,
    out: &mut dyn Write,
    from: &Machine,
    to: &Machine,
    options: &Options,
) -> Result<Report, Error> {
    threadcut::convert::convert(input, out, from, to, options)
}
