//! Output that is written whole or not at all: a temporary file beside the target, flushed, synced
//! and renamed over it only when everything succeeded.

use std::io::{self, BufWriter, Write};
use std::path::Path;

use threadcut::program::Error;

use super::{failure, Failure};

pub fn write<T>(
    input: &Path,
    output: Option<&Path>,
    produce: impl FnOnce(&mut dyn Write) -> Result<T, Error>,
) -> Result<T, Failure> {
    let target = output.filter(|p| p.as_os_str() != "-");
    let Some(target) = target else {
        let stdout = io::stdout();
        let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
        let summary = produce(&mut out).map_err(|e| failure(input, e))?;
        out.flush().map_err(|e| failure(input, Error::Io(e)))?;
        return Ok(summary);
    };
    if same_file(input, target) {
        return Err(Failure::Usage(format!(
            "-o {} names the input file; write the output elsewhere",
            target.display()
        )));
    }
    // A device, a FIFO or a socket (`-o /dev/null`, a pipe) is written in place: renaming a file
    // over it would replace the device itself.
    if let Ok(meta) = std::fs::metadata(target) {
        if !meta.is_file() {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(target)
                .map_err(|e| Failure::Other(format!("cannot write {}: {e}", target.display())))?;
            let mut out = BufWriter::with_capacity(1 << 16, file);
            let summary = produce(&mut out).map_err(|e| failure(input, e))?;
            out.flush().map_err(|e| failure(input, Error::Io(e)))?;
            return Ok(summary);
        }
    }
    // A symbolic link keeps pointing where it did: the file it names is replaced, not the link.
    let resolved = target.canonicalize().ok();
    let target = resolved.as_deref().unwrap_or(target);
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // The output gets the mode an ordinary new file would (0666 less the umask, applied by the
    // kernel at creation), or keeps the mode of the file it replaces; not tempfile's private 0600.
    let mode = std::fs::metadata(target).map_or_else(
        |_| std::os::unix::fs::PermissionsExt::from_mode(0o666),
        |m| m.permissions(),
    );
    let temp = tempfile::Builder::new()
        .prefix(".threadcut-")
        .suffix(".tmp")
        .permissions(mode)
        .tempfile_in(dir)
        .map_err(|e| Failure::Other(format!("cannot create a file in {}: {e}", dir.display())))?;
    let mut out = BufWriter::with_capacity(1 << 16, temp);
    // On any error the temporary file is dropped, which deletes it: nothing is left behind.
    let summary = produce(&mut out).map_err(|e| failure(input, e))?;
    let temp = out
        .into_inner()
        .map_err(|e| Failure::Other(format!("cannot write {}: {}", target.display(), e.error())))?;
    temp.as_file()
        .sync_all()
        .map_err(|e| Failure::Other(format!("cannot write {}: {e}", target.display())))?;
    temp.persist(target)
        .map_err(|e| Failure::Other(format!("cannot write {}: {}", target.display(), e.error)))?;
    Ok(summary)
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
