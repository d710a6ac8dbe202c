//! Writing behind: the output's system calls (the kernel's copy into the page cache, the disk's
//! write-back) on a second thread, while the first goes on producing. The library stays
//! single-threaded (it builds for wasm32); the command's two cores are used here. The bytes and
//! their order are exactly what the producer wrote: the writer thread takes whole buffers in the
//! order they were filled and writes each with `write_all`.
//!
//! Memory is flat: [`BUFFERS`] buffers of [`CAPACITY`] bytes go round between the two threads
//! (docs/performance.md, "Issue 28").

use std::io::{self, Write};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

/// Bytes a buffer holds before it is handed to the writer thread.
const CAPACITY: usize = 1 << 20;
/// Buffers in circulation: one being filled, the others being written or waiting.
const BUFFERS: usize = 3;
/// A file being written is asked to reach the disk every this many bytes (see [`Sink`]).
const SYNC_EVERY: u64 = 8 << 20;

/// Where the writer thread writes, and whether it starts the disk's write-back early.
pub trait Sink: Write + Send + 'static {
    /// Starts writing what was written so far to the disk (a file that will be synced at its end
    /// anyway: syncing along the way overlaps the disk's work with the producer's), or nothing.
    fn sync_along(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// A temporary file that is synced before it replaces the target.
pub struct Synced(pub tempfile::NamedTempFile);

impl Write for Synced {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.write(buf)
    }
    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

impl Sink for Synced {
    fn sync_along(&mut self) -> io::Result<()> {
        self.0.as_file().sync_data()
    }
}

impl Sink for std::fs::File {}

/// Standard output, locked for each buffer (so that nothing else waits on the lock for long)
/// and flushed after it (its own line buffer keeps nothing back).
pub struct Stdout(pub io::Stdout);

impl Write for Stdout {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.0.lock().write(buf)
    }
    fn write_all(&mut self, buf: &[u8]) -> io::Result<()> {
        let mut lock = self.0.lock();
        lock.write_all(buf)?;
        lock.flush()
    }
    fn flush(&mut self) -> io::Result<()> {
        self.0.flush()
    }
}

impl Sink for Stdout {}

/// A writer whose buffers are written by another thread. Dropped without [`WriteBehind::finish`],
/// it still writes everything written to it (as `BufWriter` does), ignoring errors.
pub struct WriteBehind<W: Sink> {
    buf: Vec<u8>,
    /// Filled buffers to the writer thread (`None` once finished).
    full: Option<SyncSender<Vec<u8>>>,
    /// Written buffers back, or the writer's first error.
    empty: Receiver<io::Result<Vec<u8>>>,
    /// Buffers handed out and not yet back.
    out: usize,
    thread: Option<JoinHandle<W>>,
}

impl<W: Sink> WriteBehind<W> {
    pub fn new(mut sink: W) -> WriteBehind<W> {
        let (full, to_write) = sync_channel::<Vec<u8>>(BUFFERS);
        let (written, empty) = sync_channel::<io::Result<Vec<u8>>>(BUFFERS);
        let thread = std::thread::spawn(move || {
            let mut failed = false;
            let mut since_sync = 0u64;
            // Ends when the producer's side is dropped; bounded by the buffers it sends.
            for mut buf in to_write {
                let result = if failed {
                    Err(io::Error::other("an earlier write failed"))
                } else {
                    since_sync += buf.len() as u64;
                    let mut r = sink.write_all(&buf);
                    if r.is_ok() && since_sync >= SYNC_EVERY {
                        since_sync = 0;
                        r = sink.sync_along();
                    }
                    r
                };
                failed |= result.is_err();
                buf.clear();
                // The producer may be gone (dropped after an error): nothing to tell then.
                let _ = written.send(result.map(|()| buf));
            }
            sink
        });
        WriteBehind {
            buf: Vec::with_capacity(CAPACITY),
            full: Some(full),
            empty,
            out: 0,
            thread: Some(thread),
        }
    }

    /// Hands the current buffer to the writer thread and takes an empty one (a new one while
    /// fewer than [`BUFFERS`] exist, else the next written one back, waiting for it).
    fn ship(&mut self) -> io::Result<()> {
        if self.buf.is_empty() {
            return Ok(());
        }
        let next = if self.out + 1 < BUFFERS {
            Vec::with_capacity(CAPACITY)
        } else {
            self.take_back()?
        };
        let filled = std::mem::replace(&mut self.buf, next);
        let Some(full) = &self.full else {
            return Err(io::Error::other("written after the end"));
        };
        full.send(filled).map_err(|_| gone())?;
        self.out += 1;
        Ok(())
    }

    /// The next written buffer back (or the writer's error).
    fn take_back(&mut self) -> io::Result<Vec<u8>> {
        let buf = self.empty.recv().map_err(|_| gone())??;
        self.out -= 1;
        Ok(buf)
    }

    /// Writes what is left, waits for the writer thread and returns the sink, or the first error.
    pub fn finish(mut self) -> io::Result<W> {
        self.ship()?;
        while self.out > 0 {
            self.take_back()?;
        }
        self.full = None;
        let thread = self.thread.take().expect("finished once");
        let mut sink = thread.join().map_err(|_| gone())?;
        sink.flush()?;
        Ok(sink)
    }
}

/// The writer thread ended before its work (it panicked).
fn gone() -> io::Error {
    io::Error::other("the output's writer thread stopped")
}

impl<W: Sink> Write for WriteBehind<W> {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        self.write_all(data)?;
        Ok(data.len())
    }

    fn write_all(&mut self, mut data: &[u8]) -> io::Result<()> {
        // Bounded by the data: each round takes at least one byte or ships a full buffer.
        while !data.is_empty() {
            let room = CAPACITY - self.buf.len();
            if room == 0 {
                self.ship()?;
                continue;
            }
            let n = room.min(data.len());
            self.buf.extend_from_slice(&data[..n]);
            data = &data[n..];
        }
        Ok(())
    }

    /// Everything written so far has been written by the sink when this returns.
    fn flush(&mut self) -> io::Result<()> {
        self.ship()?;
        while self.out > 0 {
            let buf = self.take_back()?;
            // Kept for the next buffer: the count of buffers stays within BUFFERS.
            if self.buf.capacity() < buf.capacity() && self.buf.is_empty() {
                self.buf = buf;
            }
        }
        Ok(())
    }
}

impl<W: Sink> Drop for WriteBehind<W> {
    fn drop(&mut self) {
        if self.thread.is_some() {
            // As a `BufWriter` dropped on an error path: what was written still reaches the
            // output, and errors are ignored.
            let _ = self.ship();
            self.full = None;
            if let Some(t) = self.thread.take() {
                let _ = t.join();
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    /// A sink that keeps what it is given, in pieces of at most 7 bytes (short writes).
    #[derive(Clone, Default)]
    struct Kept(Arc<Mutex<Vec<u8>>>);

    impl Write for Kept {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            let n = buf.len().min(7);
            self.0.lock().unwrap().extend_from_slice(&buf[..n]);
            Ok(n)
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }
    impl Sink for Kept {}

    fn pattern(len: usize) -> Vec<u8> {
        (0..len).map(|i| (i * 31 % 251) as u8).collect()
    }

    #[test]
    fn the_bytes_arrive_in_order_across_many_buffers() {
        let kept = Kept::default();
        let mut w = WriteBehind::new(kept.clone());
        // 5.5 buffers' worth, in pieces of varied sizes (one longer than a buffer).
        let data = pattern(CAPACITY * 11 / 2);
        let mut at = 0;
        for size in [1, 10, 1000, CAPACITY + 3, 65_536].iter().cycle() {
            if at == data.len() {
                break;
            }
            let end = (at + size).min(data.len());
            w.write_all(&data[at..end]).unwrap();
            at = end;
        }
        w.finish().unwrap();
        assert!(*kept.0.lock().unwrap() == data);
    }

    #[test]
    fn flush_means_written() {
        let kept = Kept::default();
        let mut w = WriteBehind::new(kept.clone());
        w.write_all(b"G0 X1\n").unwrap();
        w.flush().unwrap();
        assert_eq!(kept.0.lock().unwrap().as_slice(), b"G0 X1\n");
        w.write_all(b"M30\n").unwrap();
        drop(w);
        assert_eq!(kept.0.lock().unwrap().as_slice(), b"G0 X1\nM30\n");
    }

    /// A sink that refuses every write.
    struct Full;
    impl Write for Full {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::new(io::ErrorKind::StorageFull, "no space"))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }
    impl Sink for Full {}

    #[test]
    fn the_writers_error_comes_back_to_the_producer() {
        let mut w = WriteBehind::new(Full);
        let data = pattern(CAPACITY);
        // Bounded: the error must come back within BUFFERS + 1 buffers.
        let mut failed = None;
        for _ in 0..BUFFERS + 2 {
            if let Err(e) = w.write_all(&data) {
                failed = Some(e);
                break;
            }
        }
        let e = failed.or_else(|| w.finish().err()).expect("an error");
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
    }
}
