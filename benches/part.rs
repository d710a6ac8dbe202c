//! The part model cut by a long roughing program: 10,000 and 100,000 feed moves (the time should
//! grow in proportion: the outline stays bounded, docs/simulation.md "The part"), and the rapid
//! check against the part they leave.

use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;
use threadcut::part::{Body, Dim, Part, Stock, Tool};
use threadcut::toolpath::{Motion, MotionKind};
use threadcut::units::Pos;

fn mv(kind: MotionKind, x: f64, z: f64, line: u32) -> Motion {
    Motion {
        kind,
        to: Pos::new(x, z),
        pass: 0,
        line,
    }
}

/// `feeds` feed moves of roughing passes over and over: 50 depths cycling, each pass turning to
/// one of seven lengths and facing out, with rapids between (as the part's own test).
fn roughing(feeds: usize) -> Vec<Motion> {
    let mut out = Vec::with_capacity(feeds * 2);
    let mut i = 0;
    while out.len() < feeds * 2 {
        let x = 19.0 - (i % 50) as f64 * 0.1;
        let z = -20.0 - (i % 7) as f64;
        out.extend([
            mv(MotionKind::Rapid, x, 2.0, 1),
            mv(MotionKind::Feed, x, z, 2),
            mv(MotionKind::Feed, x + 1.0, z, 3),
            mv(MotionKind::Rapid, x + 1.0, 2.0, 4),
        ]);
        i += 1;
    }
    out
}

fn stock() -> Stock {
    Stock {
        diameter: Dim::given(40.0),
        face: Dim::given(0.0),
        length: Dim::given(60.0),
        bore: Dim::assumed(0.0),
    }
}

fn cut_all(moves: &[Motion], tool: &Tool) -> Part {
    let mut part = Part::new(&stock(), 0.001).unwrap();
    let mut at = Pos::new(21.0, 2.0);
    for m in moves {
        part.cut(at, m, tool).unwrap();
        at = m.to;
    }
    part
}

fn bench(c: &mut Criterion) {
    let tool = Tool {
        nose_radius: 0.4,
        body: Body::Turning,
    };
    let mut g = c.benchmark_group("part");
    g.sample_size(10);
    for feeds in [10_000, 100_000] {
        let moves = roughing(feeds);
        g.bench_function(format!("cut {feeds} feed moves, nose r0.4"), |b| {
            b.iter(|| cut_all(black_box(&moves), &tool))
        });
    }
    let part = cut_all(&roughing(10_000), &tool);
    g.bench_function("rapid check on the roughed part", |b| {
        b.iter(|| part.rapid_hits(black_box(Pos::new(16.0, 2.0)), Pos::new(14.0, -10.0)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
