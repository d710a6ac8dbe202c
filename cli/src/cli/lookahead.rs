//! Reading ahead on the second core: while the run reads one part of a long program, a second
//! thread reads the part after it (`threadcut::program::ahead`), and the run takes those lines
//! without reading them again when its state at the seam is the one the thread assumed. The
//! library checks that, so the output and the errors are the one-thread run's exactly
//! (docs/architecture.md, "Reading ahead").
//!
//! The input is cut into parts at nominal offsets ([`SIZES`]: the run's and the thread's parts in
//! turn, 1 MiB each); a part starts at the first line start at or after its nominal offset. The
//! thread reads its parts in order, at most [`DEPTH`] answers ahead of the run; the run reads its
//! own and, at the seam of each of the thread's, takes the thread's answer. Each part is read from a state known before it: the run's at
//! the seam where it last read a part itself, or the state after the lines the thread took from
//! its part before (the run's own there, when the run took them). From that state the thread
//! first reads the last lines before the part's seam (`Sizes::warm` bytes at most), which set the
//! position, feed and modes a plain program keeps writing again, and then the part. Memory is
//! flat: one part's bytes and a few states. The thread stops after [`GIVE_UP`] answers in a row
//! the run could not take.

use std::collections::VecDeque;
use std::io;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use std::thread::JoinHandle;

use threadcut::gcode::Modal;
use threadcut::machine::Machine;
use threadcut::program::ahead::{self, Ahead, Taken};

/// The parts' sizes (up to their last line's end): the run reads a part of `run` bytes, then
/// takes the thread's part of `ahead` bytes, and so on.
#[derive(Clone, Copy, Debug)]
pub struct Sizes {
    pub run: u64,
    pub ahead: u64,
    /// Bytes before a part read to guess the state at its seam.
    pub warm: u64,
}

const SIZES: Sizes = Sizes {
    run: 1 << 20,
    ahead: 1 << 20,
    warm: 4 << 10,
};
/// How far past a nominal offset a line end is looked for: a line longer than this ends the
/// look ahead for that part (the run reads it itself).
const SLACK: u64 = 64 << 10;

/// Input that can be read at any offset (a file; bytes in memory for tests).
pub trait Source: Send + 'static {
    fn len(&self) -> io::Result<u64>;
    fn read_at(&self, buf: &mut [u8], offset: u64) -> io::Result<usize>;
}

impl Source for std::fs::File {
    fn len(&self) -> io::Result<u64> {
        Ok(self.metadata()?.len())
    }
    #[cfg(unix)]
    fn read_at(&self, buf: &mut [u8], offset: u64) -> io::Result<usize> {
        std::os::unix::fs::FileExt::read_at(self, buf, offset)
    }
    #[cfg(windows)]
    fn read_at(&self, buf: &mut [u8], offset: u64) -> io::Result<usize> {
        std::os::windows::fs::FileExt::seek_read(self, buf, offset)
    }
}

/// The file's length and time of its last change when the run began: the look ahead reads the
/// file a second time, at offsets, so a file written while it is read could give the two readings
/// different bytes. The run ends in an error then (as it would have to anyway: the program read
/// is neither the old file nor the new one).
pub struct Stamp {
    file: std::fs::File,
    first: (u64, std::time::SystemTime),
}

impl Stamp {
    /// `None` where the system gives no time of change (the check is then not made).
    pub fn of(file: &std::fs::File) -> Option<Stamp> {
        let file = file.try_clone().ok()?;
        let first = stamp(&file)?;
        Some(Stamp { file, first })
    }

    /// Whether the file is as it was.
    pub fn unchanged(&self) -> bool {
        stamp(&self.file) == Some(self.first)
    }
}

fn stamp(file: &std::fs::File) -> Option<(u64, std::time::SystemTime)> {
    let m = file.metadata().ok()?;
    Some((m.len(), m.modified().ok()?))
}

/// The state the run had at a line start: the thread's first guess, and a better one later
/// where the run read a part itself.
struct Known {
    at: u64,
    modal: Modal,
}

/// What the thread found for the part at `nominal`: its seam and the lines taken.
struct Answer {
    nominal: u64,
    found: Option<(u64, Taken)>,
}

/// Answers the thread keeps ready at most (memory flat).
const DEPTH: usize = 2;

/// Answers in a row the run could not take, after which the thread stops: it would only take a
/// core from the run (a program in incremental coordinates, whose position no part's last lines
/// tell; a program of cycles, which the thread does not read).
const GIVE_UP: u32 = 3;

#[derive(Default)]
struct State {
    /// The run's latest state at a seam where it read the part itself.
    known: Option<Known>,
    answers: VecDeque<Answer>,
    /// The run is over: the thread ends.
    stop: bool,
    /// The thread has ended (it could not open the dialect, or failed): no answer comes.
    gone: bool,
}

type Shared = Arc<(Mutex<State>, Condvar)>;

fn lock(shared: &Shared) -> MutexGuard<'_, State> {
    // A thread that panicked holding the lock left nothing half-done that matters here.
    shared.0.lock().unwrap_or_else(|e| e.into_inner())
}

fn wait<'a>(shared: &'a Shared, state: MutexGuard<'a, State>) -> MutexGuard<'a, State> {
    shared.1.wait(state).unwrap_or_else(|e| e.into_inner())
}

/// The run's side: an [`Ahead`] whose thread reads every other part of the input: the
/// thread the odd ones, the run the even ones.
pub struct LookAhead {
    shared: Shared,
    thread: Option<JoinHandle<()>>,
    sizes: Sizes,
    len: u64,
    /// The seam the run was last given.
    seam: u64,
    /// The bytes of the lines handed to the run (which takes them where its state agrees).
    handed: u64,
    /// Answers in a row the run could not take.
    misses: u32,
}

impl LookAhead {
    /// A look ahead over `source` (the program's file) for `machine`.
    pub fn new<S: Source>(source: S, machine: Machine) -> LookAhead {
        LookAhead::with_sizes(source, machine, SIZES)
    }

    fn with_sizes<S: Source>(source: S, machine: Machine, sizes: Sizes) -> LookAhead {
        let shared: Shared = Arc::default();
        let len = source.len().unwrap_or(0);
        let theirs = shared.clone();
        let thread = std::thread::spawn(move || {
            let work = AssertUnwindSafe(|| look(&theirs, &source, &machine, sizes, len));
            let _ = catch_unwind(work);
            lock(&theirs).gone = true;
            theirs.1.notify_all();
        });
        LookAhead {
            shared,
            thread: Some(thread),
            sizes,
            len,
            seam: 0,
            handed: 0,
            misses: 0,
        }
    }

    /// The thread's answer for the part at `nominal`, once it has one.
    fn answer(&mut self, nominal: u64) -> Option<(u64, Taken)> {
        let mut state = lock(&self.shared);
        loop {
            while let Some(a) = state.answers.pop_front() {
                if a.nominal == nominal {
                    drop(state);
                    self.shared.1.notify_all();
                    return a.found;
                }
            }
            if state.gone {
                return None;
            }
            state = wait(&self.shared, state);
        }
    }
}

impl Ahead for LookAhead {
    fn first_seam(&mut self) -> u64 {
        0
    }

    fn at(&mut self, offset: u64, modal: &Modal, at_rest: bool) -> (Option<Taken>, u64) {
        let nominal = self.seam;
        let Sizes { run, ahead, .. } = self.sizes;
        if nominal >= self.len {
            self.seam = u64::MAX;
            return (None, u64::MAX);
        }
        if nominal % (run + ahead) == run {
            self.seam = nominal + ahead;
            let found = self.answer(nominal);
            // (The run checks the same again: the thread's answer is never trusted.)
            return match found {
                Some((seam, taken)) if seam == offset && at_rest && taken.entry.same(modal) => {
                    self.misses = 0;
                    self.handed += taken.bytes;
                    (Some(taken), self.seam)
                }
                _ => {
                    self.misses += 1;
                    if self.misses < GIVE_UP {
                        return (None, self.seam);
                    }
                    self.seam = u64::MAX;
                    lock(&self.shared).stop = true;
                    self.shared.1.notify_all();
                    (None, u64::MAX)
                }
            };
        }
        self.seam = nominal + run;
        let mut state = lock(&self.shared);
        state.known = Some(Known {
            at: offset,
            modal: modal.clone(),
        });
        drop(state);
        self.shared.1.notify_all();
        (None, self.seam)
    }
}

impl Drop for LookAhead {
    fn drop(&mut self) {
        lock(&self.shared).stop = true;
        self.shared.1.notify_all();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// The thread: reads the odd parts, in order, until the input or the run is over. Each part is
/// read from the latest state known before it: the run's, or the state after the lines the
/// thread took from the part before (exactly the run's there when the run takes them).
fn look<S: Source>(shared: &Shared, source: &S, machine: &Machine, sizes: Sizes, len: u64) {
    let Ok(mut looker) = ahead::looker(machine) else {
        return;
    };
    let mut buf = Vec::new();
    let mut guess: Option<Known> = None;
    let mut nominal = sizes.run;
    while nominal < len {
        {
            let mut state = lock(shared);
            loop {
                if state.stop {
                    return;
                }
                if let Some(k) = state.known.take_if(|k| k.at < nominal) {
                    if guess.as_ref().is_none_or(|g| g.at <= k.at) {
                        guess = Some(k);
                    }
                }
                if guess.is_some() && state.answers.len() < DEPTH {
                    break;
                }
                state = wait(shared, state);
            }
        }
        let Some(g) = &guess else { return };
        let found = part(source, g.at, nominal, sizes, &mut buf)
            .and_then(|(seam, warm, text)| Some((seam, looker(&g.modal, warm, text)?)));
        if let Some((seam, taken)) = &found {
            guess = Some(Known {
                at: seam + taken.bytes,
                modal: taken.exit.clone(),
            });
        }
        lock(shared).answers.push_back(Answer { nominal, found });
        shared.1.notify_all();
        nominal += sizes.run + sizes.ahead;
    }
}

/// The part at `nominal`, read into `buf`, for a state known at the line start `known`: its
/// seam, the lines before it that guess the state there (from `known` on), and its own lines.
/// `None` where the input ends before it, a line is longer than [`SLACK`], or the input cannot be
/// read (the run reads it itself and reports that).
fn part<'b, S: Source>(
    source: &S,
    known: u64,
    nominal: u64,
    sizes: Sizes,
    buf: &'b mut Vec<u8>,
) -> Option<(u64, &'b [u8], &'b [u8])> {
    let len = source.len().ok()?;
    if nominal >= len || known >= nominal {
        return None;
    }
    let Sizes { ahead, warm, .. } = sizes;
    let from = known.max(nominal.saturating_sub(warm + 1));
    let to = len.min(nominal + ahead + SLACK);
    buf.resize((to - from) as usize, 0);
    read_exact_at(source, buf, from).ok()?;
    let bytes = &buf[..];
    // The first line start at or after `at` (a line start itself, or `from`'s line's end).
    let line_start = |at: u64| -> Option<u64> {
        if at <= known {
            return Some(known);
        }
        if at >= len {
            return Some(len);
        }
        let i = usize::try_from((at - 1).checked_sub(from)?).ok()?;
        match memchr::memchr(b'\n', bytes.get(i..)?) {
            Some(k) => Some(from + (i + k) as u64 + 1),
            None if to == len => Some(len),
            None => None,
        }
    };
    let seam = line_start(nominal)?;
    let end = line_start(nominal + ahead)?.max(seam);
    let first = line_start(seam.saturating_sub(warm).max(from))?.min(seam);
    let at = |o: u64| (o - from) as usize;
    Some((seam, &bytes[at(first)..at(seam)], &bytes[at(seam)..at(end)]))
}

fn read_exact_at<S: Source>(source: &S, mut buf: &mut [u8], mut offset: u64) -> io::Result<()> {
    // Each round reads at least a byte or ends.
    while !buf.is_empty() {
        match source.read_at(buf, offset) {
            Ok(0) => return Err(io::ErrorKind::UnexpectedEof.into()),
            Ok(n) => {
                buf = &mut buf[n..];
                offset += n as u64;
            }
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use threadcut::program::{self, Options};

    impl Source for Vec<u8> {
        fn len(&self) -> io::Result<u64> {
            Ok(self.len() as u64)
        }
        fn read_at(&self, buf: &mut [u8], offset: u64) -> io::Result<usize> {
            let from = (offset as usize).min(self.len());
            let n = buf.len().min(self.len() - from);
            buf[..n].copy_from_slice(&self[from..from + n]);
            Ok(n)
        }
    }

    /// `expand` of `src` and how it ended, with the look ahead's thread at these sizes (and the
    /// bytes it handed the run) or without it.
    fn expand(src: &[u8], machine: &Machine, sizes: Option<Sizes>) -> (Vec<u8>, String, u64) {
        let mut out = Vec::new();
        let mut now = threadcut::post::Now(&mut out);
        let options = Options::default();
        let (end, handed) = match sizes {
            None => (
                program::expand_gcode_to(src, &mut now, machine, &options),
                0,
            ),
            Some(sizes) => {
                let mut look = LookAhead::with_sizes(src.to_vec(), machine.clone(), sizes);
                let end =
                    program::expand_gcode_ahead(src, &mut now, machine, &options, Some(&mut look));
                (end, look.handed)
            }
        };
        (out, format!("{end:?}"), handed)
    }

    fn programs() -> Vec<(std::path::PathBuf, Vec<u8>)> {
        let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
        let mut files = vec![];
        for dir in ["examples", "tests/data/real"] {
            for entry in std::fs::read_dir(format!("{root}/{dir}")).unwrap() {
                let path = entry.unwrap().path();
                if path.is_file() {
                    let text = std::fs::read(&path).unwrap();
                    files.push((path, text));
                }
            }
        }
        files
    }

    #[test]
    fn the_bundled_and_real_programs_expand_the_same_read_ahead() {
        let mut handed = 0;
        for (path, src) in programs() {
            for (name, _) in threadcut::machine::BUILT_IN {
                let m = Machine::built_in(name).unwrap();
                let (out, end, _) = expand(&src, &m, None);
                for (run, ahead, warm) in [(1, 1, 0), (5, 3, 64), (61, 97, 4096)] {
                    let sizes = Sizes { run, ahead, warm };
                    let got = expand(&src, &m, Some(sizes));
                    assert!(
                        (&got.0, &got.1) == (&out, &end),
                        "{} on {name}, sizes {sizes:?}: {} / {end}",
                        path.display(),
                        got.1
                    );
                    handed += got.2;
                }
            }
        }
        assert!(handed > 1_000, "the thread handed the run {handed} bytes");
    }

    #[test]
    fn a_program_in_incremental_coordinates_is_read_on_one_thread() {
        // Its position after a part's last lines depends on every line before: no guess is the
        // run's state, nothing is taken, and the thread stops after GIVE_UP answers.
        let mut src = b"G21 G99\nG0 X100 Z5\n".to_vec();
        for i in 0..20_000 {
            let (x, z) = (i % 7, i % 5);
            src.extend_from_slice(format!("G1 U-0.{x}1 W0.{z}3 F0.15\n").as_bytes());
        }
        let m = Machine::built_in("gsk980").unwrap();
        let sizes = Sizes {
            run: 8 << 10,
            ahead: 8 << 10,
            warm: 1 << 10,
        };
        let (out, end, _) = expand(&src, &m, None);
        assert!(out == src && end.starts_with("Ok"), "{end}");
        let (got, got_end, handed) = expand(&src, &m, Some(sizes));
        assert!(got == src && got_end == end);
        assert_eq!(handed, 0);
    }

    #[test]
    fn a_long_plain_program_is_read_half_ahead_and_an_error_late_in_it_is_the_same() {
        let mut src = b"G21 G99\nG0 X100 Z5\n".to_vec();
        for i in 0..20_000 {
            let z = -f64::from(i % 400) * 0.05;
            src.extend_from_slice(
                format!(
                    "G1 X{:.3} Z{z:.3} F0.15\nG0 X30. W1.\n",
                    20.0 + f64::from(i % 7)
                )
                .as_bytes(),
            );
        }
        let m = Machine::built_in("gsk980").unwrap();
        let (out, end, _) = expand(&src, &m, None);
        assert!(out == src && end.starts_with("Ok"), "{end}");
        let sizes = Sizes {
            run: 6 << 10,
            ahead: 10 << 10,
            warm: 1 << 10,
        };
        let (got, got_end, handed) = expand(&src, &m, Some(sizes));
        assert!(got == src && got_end == end);
        // The thread reads every other part: 10/16 of the input.
        assert!(handed > src.len() as u64 / 2, "{handed} of {}", src.len());
        // An alarm in a part the thread reads: the output stops before its line, and the error
        // is the one-thread run's, at its line and column.
        let at = src.len() * 3 / 4;
        let at = at + src[at..].iter().position(|&b| b == b'\n').unwrap() + 1;
        let mut bad = src[..at].to_vec();
        bad.extend_from_slice(b"G1 X20 Z-1 G345\n");
        bad.extend_from_slice(&src[at..]);
        let want = expand(&bad, &m, None);
        assert!(want.1.contains("Err"), "{}", want.1);
        let got = expand(&bad, &m, Some(sizes));
        assert!(got.0 == want.0 && got.1 == want.1, "{}", got.1);
    }
}
