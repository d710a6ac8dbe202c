//! Output that is written whole or not at all: a temporary file beside the target, flushed, synced
//! and renamed over it only when everything succeeded. Errors name the file asked for and the
//! system's reason, never the temporary file.

use std::io::{self, Write};
use std::os::unix::fs::FileTypeExt;
use std::path::Path;

use threadcut::post::MovesOut;

use super::behind::{self, Lazy, WriteBehind};
use super::{reason, Failure};

/// Runs `produce` into standard output (`output` absent or `-`) or into the file `output`.
/// `input` is the program read (to refuse writing over it).
pub fn write<T>(
    input: &Path,
    output: Option<&Path>,
    produce: impl FnOnce(&mut dyn Write) -> Result<T, Failure>,
) -> Result<T, Failure> {
    write_moves(input, output, |out| produce(out))
}

/// [`write`] for `expand`, whose cycles' moves may be formatted on the writer thread
/// ([`MovesOut`]): a device, which [`write`] writes on this thread, is written behind from the
/// first cycle on (`behind::Lazy`).
pub fn write_moves<T>(
    input: &Path,
    output: Option<&Path>,
    produce: impl FnOnce(&mut dyn MovesOut) -> Result<T, Failure>,
) -> Result<T, Failure> {
    let target = output.filter(|p| p.as_os_str() != "-");
    let Some(target) = target else {
        let stdout = io::stdout();
        if stdout_is_device() {
            let mut out = Lazy::new(behind::Stdout(stdout));
            let summary = produce(&mut out).map_err(|f| named(f, None))?;
            out.finish().map_err(|e| cannot_write(None, &e))?;
            return Ok(summary);
        }
        // The output is written by a second thread (`behind`); an error return drops it, which
        // still writes what was produced, as the buffered writer did.
        let mut out = WriteBehind::new(behind::Stdout(stdout));
        let summary = produce(&mut out).map_err(|f| named(f, None))?;
        out.finish().map_err(|e| cannot_write(None, &e))?;
        return Ok(summary);
    };
    if same_file(input, target) {
        return Err(Failure::Usage(format!(
            "-o {} names the input file; write the output elsewhere",
            target.display()
        )));
    }
    let cannot = |e: &io::Error| cannot_write(Some(target), e);
    // A device, a FIFO or a socket (`-o /dev/null`, a pipe) is written in place: renaming a file
    // over it would replace the device itself.
    if let Ok(meta) = std::fs::metadata(target) {
        if meta.is_dir() {
            return Err(cannot(&io::Error::from(io::ErrorKind::IsADirectory)));
        }
        if !meta.is_file() {
            let file = std::fs::OpenOptions::new()
                .write(true)
                .open(target)
                .map_err(|e| cannot(&e))?;
            if meta.file_type().is_char_device() {
                // A device written in place costs nothing worth a second thread (the null
                // device; a terminal is paced by the reader).
                let mut out = Lazy::new(file);
                let summary = produce(&mut out).map_err(|f| named(f, Some(target)))?;
                out.finish().map_err(|e| cannot(&e))?;
                return Ok(summary);
            }
            // A FIFO or a socket: written behind, as a file is.
            let mut out = WriteBehind::new(file);
            let summary = produce(&mut out).map_err(|f| named(f, Some(target)))?;
            out.finish().map_err(|e| cannot(&e))?;
            return Ok(summary);
        }
    }
    // A symbolic link keeps pointing where it did: the file it names is replaced, not the link.
    let resolved = target.canonicalize().ok();
    let file = resolved.as_deref().unwrap_or(target);
    let dir = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    // The folder must exist: said with its own reason (no such file or directory, not a
    // directory), before any temporary file is tried.
    let folder = |e: &io::Error| {
        Failure::Other(format!(
            "cannot write {}: {}: {}",
            target.display(),
            dir.display(),
            reason(e)
        ))
    };
    match std::fs::metadata(dir) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => return Err(folder(&io::Error::from(io::ErrorKind::NotADirectory))),
        Err(e) => return Err(folder(&e)),
    }
    // The output gets the mode an ordinary new file would (0666 less the umask, applied by the
    // kernel at creation), or keeps the mode of the file it replaces; not tempfile's private 0600.
    let mode = std::fs::metadata(file).map_or_else(
        |_| std::os::unix::fs::PermissionsExt::from_mode(0o666),
        |m| m.permissions(),
    );
    let temp = tempfile::Builder::new()
        .prefix(".threadcut-")
        .suffix(".tmp")
        .permissions(mode)
        .tempfile_in(dir)
        .map_err(|e| cannot(&e))?;
    // Written by a second thread, which also starts the disk's write-back along the way
    // (`behind::Synced`), so that the sync at the end has little left to wait for.
    let mut out = WriteBehind::new(behind::Synced(temp));
    // On any error the temporary file is dropped, which deletes it: nothing is left behind.
    let summary = produce(&mut out).map_err(|f| named(f, Some(target)))?;
    let behind::Synced(temp) = out.finish().map_err(|e| cannot(&e))?;
    temp.as_file().sync_all().map_err(|e| cannot(&e))?;
    temp.persist(file).map_err(|e| cannot(&e.error))?;
    Ok(summary)
}

/// Whether standard output is a character device (a terminal, the null device), which
/// [`write`] writes through a buffer on this thread; a file or a pipe is written behind.
fn stdout_is_device() -> bool {
    use std::os::fd::AsFd;
    let fd = io::stdout().as_fd().try_clone_to_owned();
    fd.and_then(|fd| std::fs::File::from(fd).metadata())
        .is_ok_and(|m| m.file_type().is_char_device())
}

/// `cannot write OUT: reason` (exit status 1); a reader that went away ends quietly.
fn cannot_write(target: Option<&Path>, e: &io::Error) -> Failure {
    if e.kind() == io::ErrorKind::BrokenPipe {
        return Failure::Quiet;
    }
    let what = target.map_or("to standard output".to_string(), |t| {
        t.display().to_string()
    });
    Failure::Other(format!("cannot write {what}: {}", reason(e)))
}

/// A failure to write while producing names the output.
fn named(f: Failure, target: Option<&Path>) -> Failure {
    match f {
        Failure::Other(msg) if msg.starts_with("cannot write the output: ") => {
            let what = target.map_or("to standard output".to_string(), |t| {
                t.display().to_string()
            });
            Failure::Other(msg.replacen("the output", &what, 1))
        }
        f => f,
    }
}

fn same_file(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}
