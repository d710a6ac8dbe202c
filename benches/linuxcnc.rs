//! `threadcut expand` on 5,000 LinuxCNC G76 cycles (10,000 lines, 360,000 motions): the issue's
//! target is a tenth of LinuxCNC's own interpreter on the same program (≈0.31 s), i.e. ≤ 0.031 s.
//! Figures and the command: docs/performance.md, "LinuxCNC G76 expansion".

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use threadcut::machine::Machine;
use threadcut::program;

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
    let mut g = c.benchmark_group("linuxcnc");
    g.throughput(Throughput::Elements(motions as u64));
    g.sample_size(20);
    g.bench_function("expand 5000 G76 (gcode)", |b| {
        b.iter(|| {
            let mut out = std::io::sink();
            program::expand_gcode(text.as_bytes(), &mut out, &machine).unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, expand);
criterion_main!(benches);
