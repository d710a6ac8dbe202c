//! `threadcut expand` on 5,000 LinuxCNC G76 cycles (10,000 lines, 360,000 motions), paired in the
//! same run with LinuxCNC's own interpreter on the same program where it is installed: issue 18's
//! target is at most a twentieth of its time. Figures and the command: docs/performance.md,
//! "LinuxCNC G76 expansion".
//!
//! Three measurements: the library (`program::expand_gcode` into a sink, in process); the
//! `threadcut` command as a process (`target/release/threadcut`, when it has been built with
//! `cargo build --release -p threadcut-cli`; else `THREADCUT_BIN`); and LinuxCNC's standalone
//! interpreter `rs274` as a process (`THREADCUT_RS274=/path/to/rs274`, or `rs274` on the `PATH`,
//! which Debian's `linuxcnc-uspace` package installs), run as `rs274 -g PROGRAM /dev/null` (batch
//! mode, its canonical-motion calls written to the null device). Each process run includes its
//! start-up. Absent binaries are skipped with a note: the library's figure always runs. With
//! `THREADCUT_BASE_BIN` naming the command built from another revision, that binary runs the same
//! program in the same run (a refactor's before and after, paired).

mod support;

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use threadcut::machine::Machine;
use threadcut::program;

use support::{base_binary, find_binary, run};

/// The worked example of linuxcnc-g76.md §3 (14 passes, 71 moves each), 5,000 times with
/// varying drive lines: each cycle is a G0 to its start and a G76 line.
pub fn program_text(cycles: usize) -> String {
    let mut s = String::from("G7 G21 G18\nS500 M3\n");
    for n in 0..cycles {
        let x = 22.0 + (n % 7) as f64 * 0.5;
        s.push_str(&format!("G0 X{x} Z5\n"));
        s.push_str("G76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\n");
    }
    s.push_str("M2\n");
    s
}

fn expand(c: &mut Criterion) {
    let text = program_text(5_000);
    let machine = Machine::built_in("linuxcnc").unwrap();
    // Sanity: the input really makes 360,000 motions: 71 per G76 and one G0 per cycle (the very
    // first G0 starts nowhere known and is listed with `start_unknown`).
    let mut lines = Vec::new();
    program::expand_jsonl(text.as_bytes(), &mut lines, &machine).unwrap();
    let motions = lines.iter().filter(|&&b| b == b'\n').count();
    assert_eq!(motions, 5_000 * 72);
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let file = root.join("target").join("bench-lcnc5000.ngc");
    std::fs::write(&file, &text).unwrap();
    let file = file.to_str().unwrap();

    let mut g = c.benchmark_group("linuxcnc");
    g.throughput(Throughput::Elements(motions as u64));
    g.sample_size(20);
    g.bench_function("expand 5000 G76 (gcode)", |b| {
        b.iter(|| {
            let mut out = std::io::sink();
            program::expand_gcode(text.as_bytes(), &mut out, &machine).unwrap()
        })
    });
    let release = root.join("target").join("release").join("threadcut");
    let args = ["expand", file, "-c", "linuxcnc", "-o", "/dev/null"];
    match find_binary("THREADCUT_BIN", &[release], None) {
        Some(bin) => {
            g.bench_function("threadcut expand 5000 G76 (process)", |b| {
                b.iter(|| run(&bin, &args))
            });
        }
        None => eprintln!(
            "linuxcnc: no threadcut binary (cargo build --release -p threadcut-cli, or set \
             THREADCUT_BIN): the command's figure is skipped"
        ),
    }
    if let Some(base) = base_binary() {
        g.bench_function("base revision: threadcut expand 5000 G76 (process)", |b| {
            b.iter(|| run(&base, &args))
        });
    }
    match find_binary("THREADCUT_RS274", &[], Some("rs274")) {
        Some(rs274) => {
            g.bench_function("reference: LinuxCNC rs274 5000 G76 (process)", |b| {
                b.iter(|| run(&rs274, &["-g", file, "/dev/null"]))
            });
        }
        None => eprintln!(
            "linuxcnc: no rs274 (set THREADCUT_RS274 to LinuxCNC's standalone interpreter, or \
             install it): the reference is skipped"
        ),
    }
    g.finish();
}

criterion_group!(benches, expand);
criterion_main!(benches);
