//! `check` on whole programs (issues 23 and 28): the page's 30,000-line paste (turning moves and a
//! GSK G78: every move cuts the part `check` follows), the heavier paste of 10,000 GSK G78 cycles
//! (30,000 lines), one thread of 8,000 and of 32,000 hand-written G33 passes, and one Haas G76
//! run 4,000 and 16,000 times (spring passes appended to its thread); in each pair the time should
//! grow in proportion: ratio near 4. In-process through
//! the library, and as the command (`target/release/threadcut`) paired with another revision's
//! (`THREADCUT_BASE_BIN`). Figures and the commands: docs/performance.md.

mod support;

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, Criterion};
use threadcut::check::{check, Options, Source};
use threadcut::machine::Machine;

use support::{base_binary, find_binary, run_any};

/// The page's browser test's paste: 30,000 feed moves, then a G78 (web/e2e/test.mjs, step 8).
fn paste() -> String {
    let mut big = String::from("G0 X80 Z10\n");
    for i in 0..30_000 {
        big += &format!("G1 X{}.5 Z-{}.25 F0.2\n", 20 + (i % 50), i % 40);
    }
    big += "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n";
    big
}

/// The page's heavier paste (issue 28, item 4): 30,000 lines that are all cycles, 10,000 GSK
/// G78 threads of the paste's own cycle, each from its start point.
fn gsk_cycles(n: usize) -> String {
    "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n".repeat(n)
}

/// One thread of `n` G33 passes on LinuxCNC (radius mode), each back out and to the start.
fn g33_passes(n: usize) -> String {
    let mut out = String::from("G18 G21 G8\nS300 M3\nG0 X12 Z5\n");
    for i in 0..n {
        let x = 10.0 - 0.001 * (i % 1000) as f64;
        out += &format!("G0 X{x:.4} Z5\nG33 Z-20 K1.5\nG0 X12\nG0 Z5\n");
    }
    out + "M2\n"
}

/// One Haas G76 that cuts the whole depth in one pass (D above K), run `n` times from its start:
/// one thread, each run after the first a spring pass appended to it.
fn haas_spring_passes(n: usize) -> String {
    String::from("G21\nG97 S500 M3\n")
        + &"G0 X22. Z5.\nG76 X16.933 Z-30. K1.534 D2. F2.5 A60\n".repeat(n)
}

fn bench(c: &mut Criterion) {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let mut g = c.benchmark_group("check");
    g.sample_size(10);
    let cases = [
        (
            "gsk980",
            "paste 30000 lines",
            paste(),
            "bench-check-paste.nc",
        ),
        (
            "gsk980",
            "10000 G78 cycles",
            gsk_cycles(10_000),
            "bench-check-gsk10000.nc",
        ),
        (
            "linuxcnc",
            "8000 G33 passes",
            g33_passes(8_000),
            "bench-check-8000.ngc",
        ),
        (
            "linuxcnc",
            "32000 G33 passes",
            g33_passes(32_000),
            "bench-check-32000.ngc",
        ),
        (
            "haas",
            "G76 run 4000 times",
            haas_spring_passes(4_000),
            "bench-check-haas4000.nc",
        ),
        (
            "haas",
            "G76 run 16000 times",
            haas_spring_passes(16_000),
            "bench-check-haas16000.nc",
        ),
    ];
    let release = root.join("target").join("release").join("threadcut");
    let bin = find_binary("THREADCUT_BIN", &[release], None);
    let base = base_binary();
    for (controller, name, text, file) in &cases {
        let machine = Machine::built_in(controller).unwrap();
        g.bench_function(format!("check {name}"), |b| {
            b.iter(|| {
                check(
                    text.as_bytes(),
                    Source::Gcode(&machine),
                    &Options::default(),
                )
                .unwrap()
            })
        });
        let path = root.join("target").join(file);
        std::fs::write(&path, text).unwrap();
        let path = path.to_string_lossy().into_owned();
        let args = ["check", path.as_str(), "-c", controller, "--format", "json"];
        if let Some(bin) = &bin {
            g.bench_function(format!("threadcut check {name} (process)"), |b| {
                b.iter(|| run_any(bin, &args))
            });
        }
        if let Some(base) = &base {
            g.bench_function(
                format!("base revision: threadcut check {name} (process)"),
                |b| b.iter(|| run_any(base, &args)),
            );
        }
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
