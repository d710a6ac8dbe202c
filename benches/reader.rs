//! Pass-through throughput of `threadcut expand` on a large program without threading cycles:
//! every line is lexed and its modal state tracked, then copied byte for byte.
//!
//! `cargo bench --bench reader` (the input, about 50 MB, is generated under target/ once). Besides
//! the whole pass-through, three stages (lex; + modal state; + prefilter and run loop) show where
//! the time goes.
//! The peak resident memory after the runs from the file is printed so that it can be compared
//! across input sizes (docs/performance.md). A last run takes the input from memory: the reader's
//! own speed, without the kernel's copy of the file. The `threadcut` command runs the file as a
//! process too (`target/release/threadcut` or `THREADCUT_BIN`), and beside it, with
//! `THREADCUT_BASE_BIN`, the command built from another revision.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::PathBuf;

mod support;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use threadcut::dialect;
use threadcut::gcode::{Modal, Reader};
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::units::Units;

use support::{base_binary, find_binary, run};

/// Writes a lathe program of about `bytes` bytes: positioning, turning, arcs, comments, dwell, tool
/// changes — everything but threading cycles.
pub fn generate(path: &PathBuf, bytes: u64) {
    if path.metadata().map(|m| m.len() >= bytes).unwrap_or(false) {
        return;
    }
    let mut out = BufWriter::new(File::create(path).unwrap());
    let mut written = 0u64;
    let mut n = 0u64;
    writeln!(out, "%\nO1000 (GENERATED)\nG21 G99\nG0 X100 Z5").unwrap();
    while written < bytes {
        let x = 20.0 + (n % 400) as f64 * 0.125;
        let z = -((n % 900) as f64) * 0.05;
        let line = match n % 8 {
            0 => format!("N{} G0 X{x:.3} Z2.\n", n % 10000),
            1 => format!("G1 Z{z:.3} F0.15\n"),
            2 => format!("G1 X{:.3} W-0.5 (FACE)\n", x + 1.0),
            3 => format!("G2 X{:.3} Z{z:.3} R2.5\n", x + 2.0),
            4 => "U-0.4 W-1.25 ; chamfer\n".to_string(),
            5 => "G04 X0.5\n".to_string(),
            6 => format!("T0{}0{} M08\n", n % 8 + 1, n % 8 + 1),
            _ => format!("G0 X{:.3} Z{:.3}\n", x + 5.0, z + 3.0),
        };
        written += line.len() as u64;
        out.write_all(line.as_bytes()).unwrap();
        n += 1;
    }
    writeln!(out, "M30\n%").unwrap();
}

fn peak_rss_kib() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

fn pass_through(c: &mut Criterion) {
    let size: u64 = std::env::var("THREADCUT_BENCH_MB")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(50)
        << 20;
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("target")
        .join(format!("bench-reader-{}mb.nc", size >> 20));
    generate(&path, size);
    let len = path.metadata().unwrap().len();
    let machine = Machine::built_in("gsk980").unwrap();
    let open = || BufReader::with_capacity(1 << 16, File::open(&path).unwrap());
    let mut group = c.benchmark_group("reader");
    group.throughput(Throughput::Bytes(len));
    group.sample_size(10);
    group.bench_function(format!("expand pass-through {} MB", len >> 20), |b| {
        b.iter(|| {
            let mut sink = BufWriter::with_capacity(1 << 16, std::io::sink());
            program::expand_gcode(open(), &mut sink, &machine).unwrap()
        })
    });
    // The reference, in the same run: the same bytes copied out of the page cache and dropped,
    // 128 KiB a read as the reader reads (what `dd if=FILE of=/dev/null bs=128k` does). The
    // pass-through's target is measured against this (issue 18: 1 GB/s; docs/performance.md).
    group.bench_function(format!("reference: copy {} MB (dd)", len >> 20), |b| {
        b.iter(|| {
            let mut file = File::open(&path).unwrap();
            let mut buf = vec![0u8; 128 << 10];
            let mut total = 0usize;
            loop {
                match file.read(&mut buf).unwrap() {
                    0 => break total,
                    n => total += n,
                }
            }
        })
    });
    // The same work in stages, each adding one step, to show where the time goes
    // (docs/performance.md): lexing only; plus the modal state; plus the dialect's prefilter and
    // the run loop (everything but the output).
    group.bench_function("stage 1: read and lex", |b| {
        b.iter(|| {
            let mut reader = Reader::new(open());
            let mut words = 0;
            // As `program::run` reads: the fast path's lines first.
            loop {
                let line = match reader.next_plain_line() {
                    Some(line) => line,
                    None => match reader.next_line() {
                        Some(line) => line.unwrap(),
                        None => break,
                    },
                };
                words += line.words.len();
            }
            words
        })
    });
    group.bench_function("stage 2: + modal state", |b| {
        b.iter(|| {
            let dialect = dialect::open(&machine).unwrap();
            let conv = dialect.conventions().clone();
            let no_point = [
                machine.no_point_scale(Units::Mm),
                machine.no_point_scale(Units::Inch),
            ];
            let mut modal = Modal::new(&conv, machine.units, no_point);
            let mut reader = Reader::new(open());
            let mut moves = 0;
            loop {
                let line = match reader.next_plain_line() {
                    Some(line) => line,
                    None => match reader.next_line() {
                        Some(line) => line.unwrap(),
                        None => break,
                    },
                };
                moves += usize::from(modal.apply(&conv, &line).unwrap().is_some());
            }
            moves
        })
    });
    group.bench_function("stage 3: + prefilter and run loop", |b| {
        b.iter(|| {
            let mut plain = 0;
            program::run(open(), &machine, |_, ev| {
                plain += usize::from(matches!(ev, program::Event::Plain { .. }));
                Ok(())
            })
            .unwrap();
            plain
        })
    });
    if let Some(kib) = peak_rss_kib() {
        println!(
            "peak resident memory of the bench process: {kib} KiB (input {} MB)",
            len >> 20
        );
    }
    // The same pass-through from a copy of the file in memory (read once, before the runs): the
    // reader's own speed on one core, without the kernel's copy from the page cache that every
    // run above includes (≈ 10 % of it on this machine kind, docs/performance.md). Last, because
    // the copy makes the process's peak memory the file's size.
    let data = std::fs::read(&path).unwrap();
    group.bench_function(
        format!("expand pass-through {} MB from memory", len >> 20),
        |b| {
            b.iter(|| {
                let mut sink = BufWriter::with_capacity(1 << 16, std::io::sink());
                program::expand_gcode(&data[..], &mut sink, &machine).unwrap()
            })
        },
    );
    // The command as a process on the same file (start-up, file output included), and, with
    // THREADCUT_BASE_BIN, the command of another revision beside it: before and after, paired.
    let file = path.to_str().unwrap();
    let args = ["expand", file, "-c", "gsk980", "-o", "/dev/null"];
    let release = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/release/threadcut");
    if let Some(bin) = find_binary("THREADCUT_BIN", &[release], None) {
        group.bench_function("threadcut expand pass-through (process)", |b| {
            b.iter(|| run(&bin, &args))
        });
    }
    if let Some(base) = base_binary() {
        group.bench_function(
            "base revision: threadcut expand pass-through (process)",
            |b| b.iter(|| run(&base, &args)),
        );
    }
    // Issue 28's goal: the command writing the pass-through to a file within twice the time of a
    // plain copy of the same bytes to a file. The copy reads 128 KiB at a time and writes each
    // read (`dd bs=128k of=FILE`); the second reference also syncs the file at its end, as the
    // command does before it renames its output over the target (a file that is written whole or
    // not at all). Both write under target/.
    let target = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target");
    let copy_to = target.join("bench-reader-copy.nc");
    for sync in [false, true] {
        let name = if sync {
            format!("reference: copy {} MB to a file, synced", len >> 20)
        } else {
            format!("reference: copy {} MB to a file", len >> 20)
        };
        group.bench_function(name, |b| b.iter(|| copy_file(&path, &copy_to, sync)));
    }
    let out = target.join("bench-reader-out.nc");
    let to_file = ["expand", file, "-c", "gsk980", "-o", out.to_str().unwrap()];
    if let Some(bin) = find_binary("THREADCUT_BIN", &[release_bin()], None) {
        group.bench_function("threadcut expand pass-through to a file (process)", |b| {
            b.iter(|| run(&bin, &to_file))
        });
    }
    if let Some(base) = base_binary() {
        group.bench_function(
            "base revision: threadcut expand pass-through to a file (process)",
            |b| b.iter(|| run(&base, &to_file)),
        );
    }
    group.finish();
    let _ = std::fs::remove_file(&copy_to);
    let _ = std::fs::remove_file(&out);
}

/// The command built by `cargo build --release -p threadcut-cli`.
fn release_bin() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("target/release/threadcut")
}

/// `from` copied to `to` 128 KiB at a time, and synced at the end when `sync`.
fn copy_file(from: &PathBuf, to: &PathBuf, sync: bool) -> usize {
    let mut input = File::open(from).unwrap();
    let mut output = File::create(to).unwrap();
    let mut buf = vec![0u8; 128 << 10];
    let mut total = 0usize;
    loop {
        match input.read(&mut buf).unwrap() {
            0 => break,
            n => {
                output.write_all(&buf[..n]).unwrap();
                total += n;
            }
        }
    }
    if sync {
        output.sync_all().unwrap();
    }
    total
}

criterion_group!(benches, pass_through);
criterion_main!(benches);
