//! Simulating the section of a 20-pass thread (target: under 200 µs; docs/performance.md).

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use std::time::{Duration, Instant};
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::sim::{self, Tip, Tool};

/// M42×4.5-like: 2.76 deep, first cut 0.64 on the √n law with a 0.05 minimum cut, flank infeed;
/// 19 rough passes and one finishing pass.
const PROGRAM: &str = "G00 X50 Z10\nG78 P010160 Q0.05 R0.02\nG78 X36.96 Z-40 P2.76 Q0.64 F4.5\n";

fn bench(c: &mut Criterion) {
    let machine = Machine::built_in("gsk980").expect("built in");
    let job = program::jobs(PROGRAM.as_bytes(), &machine)
        .expect("valid program")
        .remove(0);
    let passes = job.passes().expect("plan");
    assert_eq!(passes.len(), 20, "the benchmark wants a 20-pass thread");
    let sharp = Tool::sharp(60.0);
    let nose = Tool {
        angle_deg: 60.0,
        tip: Tip::Radius { radius: 0.2 },
    };
    c.bench_function("section 20 passes sharp", |b| {
        b.iter(|| sim::section(black_box(&job), black_box(&passes), &sharp, 0.0).unwrap())
    });
    c.bench_function("section 20 passes nose r0.2", |b| {
        b.iter(|| sim::section(black_box(&job), black_box(&passes), &nose, 0.0).unwrap())
    });
    c.bench_function("section 20 passes sharp, thread CPU time", |b| {
        b.iter_custom(|iters| {
            cpu_timed(iters, || {
                black_box(sim::section(black_box(&job), black_box(&passes), &sharp, 0.0).unwrap());
            })
        })
    });
    c.bench_function("section 20 passes nose r0.2, thread CPU time", |b| {
        b.iter_custom(|iters| {
            cpu_timed(iters, || {
                black_box(sim::section(black_box(&job), black_box(&passes), &nose, 0.0).unwrap());
            })
        })
    });
    // Other nose radii: the number of chords follows the radius (sim::tool::NOSE_TOLERANCE).
    for radius in [0.1, 0.4] {
        let tool = Tool {
            angle_deg: 60.0,
            tip: Tip::Radius { radius },
        };
        c.bench_function(
            &format!("section 20 passes nose r{radius}, thread CPU time"),
            |b| {
                b.iter_custom(|iters| {
                    cpu_timed(iters, || {
                        black_box(
                            sim::section(black_box(&job), black_box(&passes), &tool, 0.0).unwrap(),
                        );
                    })
                })
            },
        );
    }
}

/// This thread's CPU time (ns): on a shared machine, wall-clock time also counts the time other
/// processes hold the core; this does not. `None` where the clock is missing.
fn thread_cpu_ns() -> Option<u64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec for the duration of the call.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then(|| ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64)
}

/// Runs `f` `iters` times, timed by CPU time where the system offers it.
fn cpu_timed(iters: u64, mut f: impl FnMut()) -> Duration {
    let (cpu, wall) = (thread_cpu_ns(), Instant::now());
    for _ in 0..iters {
        f();
    }
    match (cpu, thread_cpu_ns()) {
        (Some(a), Some(b)) => Duration::from_nanos(b - a),
        _ => wall.elapsed(),
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
