//! Writing behind: the output's system calls (the kernel's copy into the page cache, the disk's
//! write-back) on a second thread, while the first goes on producing; and the formatting of
//! `expand`'s cycles (`post::Moves`, the larger part of an expansion's work) there too. The library
//! stays single-threaded (it builds for wasm32); the command's two cores are used here. The bytes and
//! their order are exactly what the producer wrote: the writer thread takes whole buffers in the
//! order they were filled, and writes each cycle's moves in the place the library gave them.
//!
//! Memory is flat: [`BUFFERS`] buffers of at most [`CAPACITY`] bytes and [`MOVES`] cycles go round
//! between the two threads (docs/performance.md, "Issue 28").

use std::io::{self, BufWriter, Write};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::thread::JoinHandle;

use threadcut::post::{Moves, MovesOut};

/// Bytes a buffer holds before it is handed to the writer thread.
const CAPACITY: usize = 1 << 20;
/// Cycles a buffer holds before it is handed to the writer thread: enough that the threads meet
/// rarely, few enough that the second starts early.
const MOVES: usize = 64;
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

/// What goes to the writer thread: bytes, and cycles' moves to be written at byte offsets in them
/// (in order; each before the byte at its offset).
#[derive(Default)]
struct Chunk {
    bytes: Vec<u8>,
    moves: Vec<(usize, Moves)>,
}

impl Chunk {
    fn new() -> Chunk {
        Chunk {
            bytes: Vec::with_capacity(CAPACITY),
            moves: Vec::new(),
        }
    }

    fn is_empty(&self) -> bool {
        self.bytes.is_empty() && self.moves.is_empty()
    }
}

/// The writer thread's side: writes each chunk whole, formatting its moves into `text` (written
/// together with the bytes around them, a buffer at a time).
struct Writer<W: Sink> {
    sink: W,
    text: Vec<u8>,
    since_sync: u64,
}

impl<W: Sink> Writer<W> {
    fn chunk(&mut self, chunk: &mut Chunk) -> io::Result<()> {
        if chunk.moves.is_empty() {
            self.out(&chunk.bytes)?;
        } else {
            let mut at = 0;
            // The moves go back with the buffer and are dropped by the thread that made them:
            // memory freed by another thread costs the allocator far more.
            for (offset, moves) in &chunk.moves {
                let offset = *offset;
                self.text.extend_from_slice(&chunk.bytes[at..offset]);
                at = offset;
                if let Err(e) = moves.write(&mut self.text) {
                    // What came before the cycle is written, as one thread writes it.
                    self.flush_text()?;
                    return Err(e);
                }
                if self.text.len() >= CAPACITY {
                    self.flush_text()?;
                }
            }
            self.text.extend_from_slice(&chunk.bytes[at..]);
            self.flush_text()?;
        }
        chunk.bytes.clear();
        Ok(())
    }

    fn flush_text(&mut self) -> io::Result<()> {
        let text = std::mem::take(&mut self.text);
        let r = self.out(&text);
        self.text = text;
        self.text.clear();
        r
    }

    fn out(&mut self, bytes: &[u8]) -> io::Result<()> {
        self.since_sync += bytes.len() as u64;
        self.sink.write_all(bytes)?;
        if self.since_sync >= SYNC_EVERY {
            self.since_sync = 0;
            self.sink.sync_along()?;
        }
        Ok(())
    }
}

/// A writer whose buffers are written by another thread. Dropped without [`WriteBehind::finish`],
/// it still writes everything written to it (as `BufWriter` does), ignoring errors.
pub struct WriteBehind<W: Sink> {
    buf: Chunk,
    /// Filled buffers to the writer thread (`None` once finished).
    full: Option<SyncSender<Chunk>>,
    /// Written buffers back, or the writer's first error.
    empty: Receiver<io::Result<Chunk>>,
    /// Buffers handed out and not yet back.
    out: usize,
    /// A buffer back early ([`back_early`](Self::back_early)), not yet used.
    spare: Option<Chunk>,
    /// Cycles formatted on this thread and handed to the writer thread (for the tests).
    cycles: [usize; 2],
    thread: Option<JoinHandle<W>>,
}

impl<W: Sink> WriteBehind<W> {
    pub fn new(sink: W) -> WriteBehind<W> {
        let (full, to_write) = sync_channel::<Chunk>(BUFFERS);
        let (written, empty) = sync_channel::<io::Result<Chunk>>(BUFFERS);
        let thread = std::thread::spawn(move || {
            let mut writer = Writer {
                sink,
                text: Vec::new(),
                since_sync: 0,
            };
            let mut failed = false;
            // Ends when the producer's side is dropped; bounded by the buffers it sends.
            for mut chunk in to_write {
                let result = if failed {
                    Err(io::Error::other("an earlier write failed"))
                } else {
                    writer.chunk(&mut chunk)
                };
                failed |= result.is_err();
                chunk.bytes.clear();
                // The producer may be gone (dropped after an error): nothing to tell then.
                let _ = written.send(result.map(|()| chunk));
            }
            writer.sink
        });
        WriteBehind {
            buf: Chunk::new(),
            full: Some(full),
            empty,
            out: 0,
            spare: None,
            cycles: [0; 2],
            thread: Some(thread),
        }
    }

    /// Hands the current buffer to the writer thread and takes an empty one (a new one while
    /// fewer than [`BUFFERS`] exist, else the next written one back, waiting for it).
    fn ship(&mut self) -> io::Result<()> {
        if self.buf.is_empty() {
            return Ok(());
        }
        let next = if let Some(spare) = self.spare.take() {
            spare
        } else if self.out + 1 < BUFFERS {
            Chunk::new()
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
    fn take_back(&mut self) -> io::Result<Chunk> {
        let mut buf = self.empty.recv().map_err(|_| gone())??;
        self.out -= 1;
        buf.moves.clear();
        Ok(buf)
    }

    /// Whether a written buffer has come back (kept for the next [`ship`](Self::ship)), without
    /// waiting for one.
    fn back_early(&mut self) -> io::Result<bool> {
        if self.spare.is_some() {
            return Ok(true);
        }
        match self.empty.try_recv() {
            Ok(buf) => {
                let mut buf = buf?;
                buf.moves.clear();
                self.out -= 1;
                self.spare = Some(buf);
                Ok(true)
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => Ok(false),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => Err(gone()),
        }
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
            let room = CAPACITY.saturating_sub(self.buf.bytes.len());
            if room == 0 {
                self.ship()?;
                continue;
            }
            let n = room.min(data.len());
            self.buf.bytes.extend_from_slice(&data[..n]);
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
            if self.buf.bytes.capacity() < buf.bytes.capacity() && self.buf.is_empty() {
                self.buf = buf;
            }
        }
        Ok(())
    }
}

impl<W: Sink> MovesOut for WriteBehind<W> {
    /// The moves go in their place among the bytes, and the writer thread formats them; while
    /// every other buffer is still with it, this thread formats them itself, so that neither waits
    /// for the other (which of the two formats a cycle changes no byte).
    fn moves(&mut self, moves: Moves) -> io::Result<()> {
        if self.out + 1 >= BUFFERS && !self.back_early()? {
            self.cycles[0] += 1;
            moves.write(&mut self.buf.bytes)?;
            if self.buf.bytes.len() >= CAPACITY {
                self.ship()?;
            }
            return Ok(());
        }
        self.cycles[1] += 1;
        let at = self.buf.bytes.len();
        self.buf.moves.push((at, moves));
        if self.buf.moves.len() >= MOVES {
            self.ship()?;
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

/// A buffered writer on this thread until the first cycle's moves come: from there on, written
/// behind ([`WriteBehind`]). For a device (the null device, a terminal): copying a program's
/// plain lines into the writer thread's buffers costs more than the device's write, but a cycle's
/// formatting is worth a second core.
pub enum Lazy<W: Sink> {
    Here(BufWriter<W>),
    Behind(WriteBehind<W>),
    /// Only while switching (or after a failed switch).
    Gone,
}

impl<W: Sink> Lazy<W> {
    pub fn new(sink: W) -> Lazy<W> {
        Lazy::Here(BufWriter::with_capacity(1 << 16, sink))
    }

    /// Writes what is left and waits for it.
    pub fn finish(self) -> io::Result<()> {
        match self {
            Lazy::Here(mut w) => w.flush(),
            Lazy::Behind(w) => w.finish().map(drop),
            Lazy::Gone => Err(gone()),
        }
    }

    fn behind(&mut self) -> io::Result<&mut WriteBehind<W>> {
        if let Lazy::Here(_) = self {
            if let Lazy::Here(here) = std::mem::replace(self, Lazy::Gone) {
                let sink = here.into_inner().map_err(|e| e.into_error())?;
                *self = Lazy::Behind(WriteBehind::new(sink));
            }
        }
        match self {
            Lazy::Behind(w) => Ok(w),
            _ => Err(gone()),
        }
    }
}

impl<W: Sink> Write for Lazy<W> {
    fn write(&mut self, data: &[u8]) -> io::Result<usize> {
        match self {
            Lazy::Here(w) => w.write(data),
            Lazy::Behind(w) => w.write(data),
            Lazy::Gone => Err(gone()),
        }
    }
    fn write_all(&mut self, data: &[u8]) -> io::Result<()> {
        match self {
            Lazy::Here(w) => w.write_all(data),
            Lazy::Behind(w) => w.write_all(data),
            Lazy::Gone => Err(gone()),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self {
            Lazy::Here(w) => w.flush(),
            Lazy::Behind(w) => w.flush(),
            Lazy::Gone => Err(gone()),
        }
    }
}

impl<W: Sink> MovesOut for Lazy<W> {
    fn moves(&mut self, moves: Moves) -> io::Result<()> {
        self.behind()?.moves(moves)
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

    /// `expand` through the writer thread writes what the library writes at once, byte for byte:
    /// the cycles it formats there, and those this thread formats while the writer is behind (a
    /// sink slowed down on purpose makes both happen).
    #[test]
    fn cycles_formatted_behind_come_out_in_their_place() {
        let mut text = String::from("G7 G21 G18\nS500 M3\n");
        for n in 0..400 {
            text.push_str(&format!(
                "G0 X{} Z5\n(cycle {n})\n",
                22.0 + (n % 7) as f64 * 0.5
            ));
            text.push_str("G76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\n");
        }
        text.push_str("M2\n");
        let machine = threadcut::machine::Machine::built_in("linuxcnc").unwrap();
        let mut want = Vec::new();
        threadcut::program::expand_gcode(text.as_bytes(), &mut want, &machine).unwrap();
        for slow in [false, true] {
            let kept = Slow(Kept::default(), slow);
            let mut w = WriteBehind::new(kept.clone());
            let options = threadcut::program::Options::default();
            threadcut::program::expand_gcode_to(text.as_bytes(), &mut w, &machine, &options)
                .unwrap();
            let [here, behind] = w.cycles;
            assert_eq!(here + behind, 400);
            // (Without the sleep either may happen: the threads race.)
            assert!(
                behind > 0 && (here > 0 || !slow),
                "{here} here, {behind} behind"
            );
            w.finish().unwrap();
            assert!(*kept.0 .0.lock().unwrap() == want, "slow writer: {slow}");
            let kept = Kept::default();
            let mut lazy = Lazy::new(kept.clone());
            threadcut::program::expand_gcode_to(text.as_bytes(), &mut lazy, &machine, &options)
                .unwrap();
            lazy.finish().unwrap();
            assert!(*kept.0.lock().unwrap() == want);
        }
    }

    /// [`Kept`], optionally sleeping a little at each write of a buffer.
    #[derive(Clone)]
    struct Slow(Kept, bool);
    impl Write for Slow {
        fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
            self.0.write(buf)
        }
        fn write_all(&mut self, mut buf: &[u8]) -> io::Result<()> {
            if self.1 {
                std::thread::sleep(std::time::Duration::from_millis(2));
            }
            while !buf.is_empty() {
                let n = self.0.write(buf)?;
                buf = &buf[n..];
            }
            Ok(())
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }
    impl Sink for Slow {}

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
