//! Reading ahead: the input's system calls (the kernel's copy out of the page cache, a disk's
//! reads) on a second thread, while the first lexes what came before. The library stays
//! single-threaded (it builds for wasm32); the command's two cores are used here. The bytes, and
//! where a read error falls among them, are exactly what the file gives: the reading thread hands
//! over its buffers in order, and an error after everything read before it.
//!
//! Memory is flat: [`BUFFERS`] buffers of [`CAPACITY`] bytes go round between the two threads
//! (docs/performance.md, "Issue 28").

use std::io::{self, Read};
use std::sync::mpsc::{sync_channel, Receiver, SyncSender};

/// Bytes the reading thread reads into a buffer before handing it over.
const CAPACITY: usize = 256 << 10;
/// Buffers in circulation: one being read from, the others being filled or waiting.
const BUFFERS: usize = 4;

/// A reader whose input is read by another thread. The thread ends at the input's end, at its
/// first error, or when this is dropped.
pub struct ReadAhead {
    /// The buffer being read from, and how far.
    current: Vec<u8>,
    at: usize,
    /// Filled buffers (empty: the end of the input), or the input's error.
    filled: Receiver<io::Result<Vec<u8>>>,
    /// Read buffers back to the reading thread.
    empty: SyncSender<Vec<u8>>,
    /// The end or an error has been handed out: nothing more comes.
    done: bool,
}

impl ReadAhead {
    pub fn new<R: Read + Send + 'static>(mut input: R) -> ReadAhead {
        let (to_read, filled) = sync_channel::<io::Result<Vec<u8>>>(BUFFERS);
        let (empty, back) = sync_channel::<Vec<u8>>(BUFFERS);
        std::thread::spawn(move || {
            let mut spare = (1..BUFFERS).map(|_| Vec::new()).collect::<Vec<_>>();
            // Each round reads at least one byte or ends: bounded by the input.
            loop {
                let mut buf = match spare.pop() {
                    Some(b) => b,
                    None => match back.recv() {
                        Ok(b) => b,
                        Err(_) => return, // the consumer is gone
                    },
                };
                buf.resize(CAPACITY, 0);
                let (n, error) = fill(&mut input, &mut buf);
                buf.truncate(n);
                let end = n == 0;
                if n > 0 && to_read.send(Ok(buf)).is_err() {
                    return;
                }
                if let Some(e) = error {
                    let _ = to_read.send(Err(e));
                    return;
                }
                if end {
                    let _ = to_read.send(Ok(Vec::new()));
                    return;
                }
            }
        });
        ReadAhead {
            current: Vec::new(),
            at: 0,
            filled,
            empty,
            done: false,
        }
    }
}

/// Reads into `buf` until it is full, the input ends or fails: the count read, and the error.
fn fill<R: Read>(input: &mut R, buf: &mut [u8]) -> (usize, Option<io::Error>) {
    let mut n = 0;
    while n < buf.len() {
        match input.read(&mut buf[n..]) {
            Ok(0) => break,
            Ok(k) => n += k,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return (n, Some(e)),
        }
    }
    (n, None)
}

impl Read for ReadAhead {
    fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
        if self.at == self.current.len() {
            if self.done || out.is_empty() {
                return Ok(0);
            }
            let next = match self.filled.recv() {
                Ok(Ok(b)) => b,
                Ok(Err(e)) => {
                    self.done = true;
                    return Err(e);
                }
                Err(_) => return Err(io::Error::other("the input's reading thread stopped")),
            };
            self.done = next.is_empty();
            let used = std::mem::replace(&mut self.current, next);
            self.at = 0;
            // The reading thread may have ended (the end is near): then the buffer is dropped.
            let _ = self.empty.try_send(used);
        }
        let n = out.len().min(self.current.len() - self.at);
        out[..n].copy_from_slice(&self.current[self.at..self.at + n]);
        self.at += n;
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An input that gives `data` in reads of at most 4093 bytes, then fails or ends.
    struct Source {
        data: Vec<u8>,
        at: usize,
        fail: bool,
    }

    impl Read for Source {
        fn read(&mut self, out: &mut [u8]) -> io::Result<usize> {
            if self.at == self.data.len() {
                return if self.fail {
                    Err(io::Error::new(io::ErrorKind::InvalidData, "bad sector"))
                } else {
                    Ok(0)
                };
            }
            let n = out.len().min(4093).min(self.data.len() - self.at);
            out[..n].copy_from_slice(&self.data[self.at..self.at + n]);
            self.at += n;
            Ok(n)
        }
    }

    fn pattern(len: usize) -> Vec<u8> {
        (0..len).map(|i| (i * 31 % 251) as u8).collect()
    }

    /// Everything `r` gives in reads of 128 KiB (the library's), and its error.
    fn drain(mut r: ReadAhead) -> (Vec<u8>, Option<io::Error>) {
        let mut got = Vec::new();
        let mut chunk = vec![0u8; 128 << 10];
        // Bounded: the source is finite and each read takes at least one byte or ends.
        loop {
            match r.read(&mut chunk) {
                Ok(0) => return (got, None),
                Ok(n) => got.extend_from_slice(&chunk[..n]),
                Err(e) => return (got, Some(e)),
            }
        }
    }

    #[test]
    fn the_bytes_arrive_in_order_and_end() {
        let data = pattern(CAPACITY * 7 / 2 + 5);
        let (got, error) = drain(ReadAhead::new(Source {
            data: data.clone(),
            at: 0,
            fail: false,
        }));
        assert!(error.is_none());
        assert!(got == data);
    }

    #[test]
    fn an_error_comes_after_the_bytes_before_it() {
        let data = pattern(CAPACITY + 12_345);
        let (got, error) = drain(ReadAhead::new(Source {
            data: data.clone(),
            at: 0,
            fail: true,
        }));
        assert_eq!(error.map(|e| e.kind()), Some(io::ErrorKind::InvalidData));
        assert!(got == data);
    }

    #[test]
    fn an_empty_input_ends_at_once() {
        let (got, error) = drain(ReadAhead::new(Source {
            data: Vec::new(),
            at: 0,
            fail: false,
        }));
        assert!(got.is_empty() && error.is_none());
    }
}
