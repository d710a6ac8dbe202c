//! `threadcut post FILE.apt --controller C`, and telling APT/CL input from G-code.

use std::io::BufRead;
use std::path::Path;

use threadcut::apt;
use threadcut::machine::Machine;

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
