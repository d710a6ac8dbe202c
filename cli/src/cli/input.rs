//! The program a command reads: a file or standard input, watched on its way through the library
//! for two things only the command line cares about: whether it holds anything but blanks (an
//! empty program is an error, not an empty result) and how far the reading has come (a progress
//! bar on standard error, on a terminal, for a run that lasts).
//!
//! The watch costs nothing per line: it sees the input in the reader's chunks (64 KiB), and it
//! stops looking at the bytes once the first one that is not a blank has passed.

use std::cell::Cell;
use std::fs::File;
use std::io::{self, BufRead, BufReader, IsTerminal, Read};
use std::path::Path;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::{reason, Failure};

/// A run shorter than this shows no progress bar (it would only flicker).
const QUIET_FOR: Duration = Duration::from_millis(400);

/// A file at least this long is read ahead by a second thread; a shorter one is read before a
/// thread would have started.
const READ_AHEAD_FROM: u64 = 4 << 20;

/// The command runs as a LinuxCNC program filter (`convert --filter`): progress is reported as
/// the `FILTER_PROGRESS=N` lines LinuxCNC's screens read from standard error, not as a bar.
static FILTER: AtomicBool = AtomicBool::new(false);

/// Reports the reading's progress as a LinuxCNC program filter does from now on.
pub fn report_as_filter() {
    FILTER.store(true, Ordering::Relaxed);
}

/// Whether the program held anything but blanks, known once it has been read.
#[derive(Clone)]
pub struct Content(Rc<Cell<bool>>);

impl Content {
    /// Nothing but blanks (spaces, tabs, line ends) has been read.
    pub fn empty(&self) -> bool {
        !self.0.get()
    }

    /// The error an empty program is: exit status 2, nothing written.
    pub fn failure(file: &Path) -> Failure {
        Failure::Usage(format!(
            "{} is empty: there is no program to read\n  = help: give the program's file, or `-` and the program on standard input",
            display(file)
        ))
    }
}

/// How a file is named in messages: `-` is standard input.
pub fn display(file: &Path) -> String {
    if file.as_os_str() == "-" {
        "standard input".into()
    } else {
        file.display().to_string()
    }
}

/// Opens the program: `-` is standard input. A directory or a file that cannot be opened is an
/// error naming the file and the system's reason.
pub fn open(file: &Path) -> Result<(Box<dyn BufRead>, Content), Failure> {
    open_long(file).map(|(reader, content, _)| (reader, content))
}

/// A program opened by [`open_long`]: the reader, the watch on its content, and a second
/// handle on a long file.
pub type Long = (Box<dyn BufRead>, Content, Option<File>);

/// [`open`], with a second handle on the file when it is long enough to be read ahead (a
/// regular file of [`READ_AHEAD_FROM`] bytes or more): the same file, for reading at offsets
/// (`lookahead`).
pub fn open_long(file: &Path) -> Result<Long, Failure> {
    let seen = Rc::new(Cell::new(false));
    let content = Content(seen.clone());
    let cannot =
        |e: &io::Error| Failure::Usage(format!("cannot read {}: {}", file.display(), reason(e)));
    if file.as_os_str() == "-" {
        let stdin = io::stdin();
        let bar = Bar::new(None, stdin.is_terminal());
        let reader = BufReader::with_capacity(1 << 16, stdin);
        return Ok((Box::new(Watch::new(reader, seen, None, bar)), content, None));
    }
    let f = File::open(file).map_err(|e| cannot(&e))?;
    let meta = f.metadata().map_err(|e| cannot(&e))?;
    if meta.is_dir() {
        return Err(cannot(&io::Error::from(io::ErrorKind::IsADirectory)));
    }
    let len = meta.is_file().then_some(meta.len());
    let bar = Bar::new(len, false);
    if len.is_some_and(|n| n >= READ_AHEAD_FROM) {
        // A long file is read by a second thread while this one works (`ahead`).
        // A second handle that reads at offsets without moving the first one's position: on
        // Unix (`pread`); elsewhere a duplicated handle shares the position, so none is made.
        let handle = if cfg!(unix) { f.try_clone().ok() } else { None };
        let reader = BufReader::with_capacity(1 << 16, super::ahead::ReadAhead::new(f));
        return Ok((
            Box::new(Watch::new(reader, seen, len, bar)),
            content,
            handle,
        ));
    }
    let reader = BufReader::with_capacity(1 << 16, f);
    Ok((Box::new(Watch::new(reader, seen, len, bar)), content, None))
}

/// A program read more than once (`plot` and `passes` read it for `check` and then for the
/// threads): the file again, or standard input, kept in a temporary file as it is first read so
/// that memory stays bounded whatever its size.
pub struct Replay {
    path: std::path::PathBuf,
    _kept: Option<tempfile::NamedTempFile>,
}

impl Replay {
    /// The program `file` names (`-`: standard input, copied to a temporary file now).
    pub fn new(file: &Path) -> Result<Replay, Failure> {
        if file.as_os_str() != "-" {
            return Ok(Replay {
                path: file.to_path_buf(),
                _kept: None,
            });
        }
        let cannot = |e: io::Error| {
            Failure::Other(format!(
                "cannot keep standard input for a second reading: {}",
                reason(&e)
            ))
        };
        let mut kept = tempfile::NamedTempFile::new().map_err(cannot)?;
        io::copy(&mut io::stdin().lock(), kept.as_file_mut()).map_err(cannot)?;
        Ok(Replay {
            path: kept.path().to_path_buf(),
            _kept: Some(kept),
        })
    }

    /// The first reading, watched as [`open`] watches it (`file`: the name in messages).
    pub fn first(&self, file: &Path) -> Result<(Box<dyn BufRead>, Content), Failure> {
        open(&self.path).map_err(|e| match e {
            Failure::Usage(_) if file.as_os_str() == "-" => {
                Failure::Other("cannot read standard input again".into())
            }
            other => other,
        })
    }

    /// Another reading, from the start.
    pub fn again(&self) -> io::Result<Box<dyn BufRead>> {
        Ok(Box::new(BufReader::with_capacity(
            1 << 16,
            File::open(&self.path)?,
        )))
    }
}

/// The readings of a [`Replay`] as one opener: the watched first one, then fresh ones.
pub fn readings<'a>(
    replay: &'a Replay,
    first: Box<dyn BufRead>,
) -> impl FnMut() -> io::Result<Box<dyn BufRead>> + 'a {
    let mut first = Some(first);
    move || match first.take() {
        Some(r) => Ok(r),
        None => replay.again(),
    }
}

/// The input on its way through: what it holds and how far it has been read.
struct Watch<R> {
    inner: R,
    seen: Rc<Cell<bool>>,
    bar: Option<Bar>,
    filter: Option<FilterProgress>,
}

impl<R> Watch<R> {
    /// `len`: the file's size, where known.
    fn new(inner: R, seen: Rc<Cell<bool>>, len: Option<u64>, bar: Option<Bar>) -> Watch<R> {
        let filter = FILTER.load(Ordering::Relaxed).then_some(FilterProgress {
            total: len,
            done: 0,
            percent: 0,
        });
        Watch {
            inner,
            seen,
            bar: if filter.is_some() { None } else { bar },
            filter,
        }
    }

    fn look(&self, bytes: &[u8]) {
        if !self.seen.get() && bytes.iter().any(|b| !b.is_ascii_whitespace()) {
            self.seen.set(true);
        }
    }

    fn advance(&mut self, n: usize) {
        if let Some(bar) = &mut self.bar {
            bar.advance(n);
        }
        if let Some(f) = &mut self.filter {
            f.advance(n);
        }
    }
}

/// LinuxCNC's progress protocol for program filters: a line `FILTER_PROGRESS=N` on standard
/// error sets the screen's progress bar to N % (LinuxCNC's "Filter Programs" documentation).
/// One line per whole percent of the file read; none for standard input, whose size is unknown.
struct FilterProgress {
    total: Option<u64>,
    done: u64,
    percent: u64,
}

impl FilterProgress {
    fn advance(&mut self, n: usize) {
        let Some(total) = self.total.filter(|&t| t > 0) else {
            return;
        };
        self.done += n as u64;
        let percent = (self.done.min(total) * 100) / total;
        if percent > self.percent {
            self.percent = percent;
            eprintln!("FILTER_PROGRESS={percent}");
        }
    }
}

impl<R: Read> Read for Watch<R> {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.look(&buf[..n]);
        self.advance(n);
        Ok(n)
    }
}

impl<R: BufRead> BufRead for Watch<R> {
    fn fill_buf(&mut self) -> io::Result<&[u8]> {
        let buf = self.inner.fill_buf()?;
        if !self.seen.get() && buf.iter().any(|b| !b.is_ascii_whitespace()) {
            self.seen.set(true);
        }
        Ok(buf)
    }

    fn consume(&mut self, n: usize) {
        self.inner.consume(n);
        self.advance(n);
    }
}

/// A progress bar on standard error, drawn only on a terminal and only once the run has lasted
/// [`QUIET_FOR`]; cleared when the input is dropped (the library has read it all, or stopped at an
/// error, before anything else is printed).
struct Bar {
    bar: ProgressBar,
    started: Instant,
    shown: bool,
}

impl Bar {
    /// `len`: the file's size (a bar), or `None` (a spinner counting bytes). No bar when standard
    /// error is not a terminal, or when standard input is the terminal itself (`typing`).
    fn new(len: Option<u64>, typing: bool) -> Option<Bar> {
        if !io::stderr().is_terminal() || typing {
            return None;
        }
        let bar = match len {
            Some(len) => ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::hidden())
                .with_style(
                ProgressStyle::with_template(
                    "{spinner} reading {bytes}/{total_bytes} [{wide_bar}] {percent}% {eta} left",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            ),
            None => ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden()).with_style(
                ProgressStyle::with_template("{spinner} reading {bytes} ({bytes_per_sec})")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            ),
        };
        Some(Bar {
            bar,
            started: Instant::now(),
            shown: false,
        })
    }

    fn advance(&mut self, n: usize) {
        self.bar.inc(n as u64);
        if !self.shown && self.started.elapsed() >= QUIET_FOR {
            self.shown = true;
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}
