//! G71/G72 moves computed by hand, their alarms, and properties over random shapes.

use proptest::prelude::*;

use super::*;
use crate::turning::{Contour, Segment, Shape, Strategy};
use crate::units::Pos;

/// A straight block of the shape.
fn line(x: f64, z: f64, n: u32) -> Segment {
    Segment {
        to: Pos::new(x, z),
        shape: Shape::Line,
        line: n,
    }
}

fn arc(x: f64, z: f64, cx: f64, cz: f64, clockwise: bool, n: u32) -> Segment {
    Segment {
        to: Pos::new(x, z),
        shape: Shape::Arc {
            centre: Pos::new(cx, cz),
            clockwise,
        },
        line: n,
    }
}

struct Words {
    along: Along,
    depth: f64,
    retract: f64,
    allowance: (f64, f64),
    pockets: bool,
}

fn rough(start: Pos, segments: Vec<Segment>, w: Words) -> Rough {
    Rough {
        along: w.along,
        start,
        depth: w.depth,
        retract: w.retract,
        allowance_x: w.allowance.0,
        allowance_z: w.allowance.1,
        pockets: w.pockets,
        contour: Contour { start, segments },
        strategy: Strategy::Layers,
        then_outline: None,
    }
}

/// 'R' rapid, 'F' feed, 'A' arc (its centre checked apart).
type Want = (u32, char, f64, f64);

/// The moves against the expected ones, at 0.0001 mm (a tenth of IS-B's increment).
fn assert_moves(got: &[Motion], want: &[Want], scale: f64) {
    let brief: Vec<_> = got
        .iter()
        .map(|m| {
            let k = match m.kind {
                MotionKind::Rapid => 'R',
                MotionKind::Feed => 'F',
                MotionKind::Arc { .. } => 'A',
                MotionKind::Thread { .. } => 'T',
            };
            (m.pass, k, m.to.x / scale, m.to.z / scale)
        })
        .collect();
    assert_eq!(got.len(), want.len(), "{brief:#?}");
    for (i, (g, w)) in brief.iter().zip(want).enumerate() {
        let close = (g.2 - w.2).abs() < 1e-4 / scale && (g.3 - w.3).abs() < 1e-4 / scale;
        assert!(
            g.0 == w.0 && g.1 == w.1 && close,
            "move {i}: {g:?}, want {w:?}\n{brief:#?}"
        );
    }
}

/// Start X50 Z2 (radius 25). N10 G0 X16 (radius 8); N20 G1 X20 Z0 (45° chamfer); N30 Z−15;
/// N40 X28; N50 G3 X36 Z−19 R4 (centre radius 14, Z−19); N60 G1 Z−30; N70 X50.4 (radius 25.2).
fn shaft(scale: f64) -> (Pos, Vec<Segment>) {
    let p = |x: f64, z: f64| (x * scale, z * scale);
    let l = |(x, z): (f64, f64), n| line(x, z, n);
    let (ax, az) = p(25.0, 2.0);
    let (cx, cz) = p(14.0, -19.0);
    let (ex, ez) = p(18.0, -19.0);
    let segs = vec![
        l(p(8.0, 2.0), 10),
        l(p(10.0, 0.0), 20),
        l(p(10.0, -15.0), 30),
        l(p(14.0, -15.0), 40),
        arc(ex, ez, cx, cz, false, 50),
        l(p(18.0, -30.0), 60),
        l(p(25.2, -30.0), 70),
    ];
    (Pos::new(ax, az), segs)
}

/// The stepped shaft's moves, in the shaft's units (hand-computed in the comments of
/// `external_type_i_on_a_stepped_shaft`).
const SHAFT: [Want; 28] = [
    (1, 'R', 22.0, 2.0),
    (1, 'F', 22.0, -29.9),
    (1, 'R', 22.5, -29.4),
    (2, 'R', 22.5, 2.0),
    (2, 'R', 19.0, 2.0),
    (2, 'F', 19.0, -29.9),
    (2, 'R', 19.5, -29.4),
    (3, 'R', 19.5, 2.0),
    (3, 'R', 16.0, 2.0),
    (3, 'F', 16.0, -15.327_886),
    (3, 'R', 16.5, -14.827_886),
    (4, 'R', 16.5, 2.0),
    (4, 'R', 13.0, 2.0),
    (4, 'F', 13.0, -14.9),
    (4, 'R', 13.5, -14.4),
    (5, 'R', 13.5, 2.0),
    (5, 'R', 10.0, 2.0),
    (5, 'F', 10.0, 0.3),
    (5, 'R', 10.5, 0.8),
    (6, 'R', 10.5, 2.1),
    (6, 'R', 8.2, 2.1),
    (6, 'F', 10.2, 0.1),
    (6, 'F', 10.2, -14.9),
    (6, 'F', 14.2, -14.9),
    (6, 'A', 18.2, -18.9),
    (6, 'F', 18.2, -29.9),
    (6, 'F', 25.4, -29.9),
    (6, 'R', 25.0, 2.0),
];

#[test]
fn external_type_i_on_a_stepped_shaft() {
    // Δd 3 (radius), e 0.5, U0.4 W0.1: the shape shifts by X+0.2 (radius) Z+0.1.
    // Shifted: A′ (8.2, 2.1), chamfer to (10.2, 0.1), Z−14.9, X14.2, arc to (18.2, −18.9) about
    // (14.2, −18.9), Z−29.9, X25.4.
    // Layers from X25 down by 3 while above the lowest point 8.2: 25 − 8.2 = 16.8 → 5 layers,
    // X22, 19, 16, 13, 10.
    // X22 and X19 run to the last wall (the shape first reaches X25 there): Z−29.9.
    // X16 meets the arc: 14.2 + √(16 − (z + 18.9)²) = 16 → (z + 18.9)² = 16 − 1.8² = 12.76,
    //   √12.76 = 3.572114 → Z = −18.9 + 3.572114 = −15.327886.
    // X13 meets the shoulder X10.2→14.2 at Z−14.9.
    // X10 meets the chamfer (slope 1 from (8.2, 2.1)): Z = 2.1 − (10 − 8.2) = 0.3.
    // Each cut ends with a 45° rapid of 0.5 up and back (Z + 0.5), then a rapid back to Z2 and
    // the next infeed at rapid (the shape's first block is G00).
    // Last: rapid to A′ (8.2, 2.1) and the shifted shape, then a rapid back to X25 Z2.
    let (start, segs) = shaft(1.0);
    let w = Words {
        along: Along::Z,
        depth: 3.0,
        retract: 0.5,
        allowance: (0.2, 0.1),
        pockets: false,
    };
    let m = moves(&rough(start, segs, w), 5).unwrap();
    assert_moves(&m, &SHAFT, 1.0);
    assert!(m.iter().all(|m| m.line == 5));
    // The arc keeps its direction and its centre moves with the allowance.
    assert_eq!(
        m[24].kind,
        MotionKind::Arc {
            centre: Pos::new(14.2, -18.9),
            clockwise: false
        }
    );
}

#[test]
fn the_same_shaft_in_inch() {
    // The shaft drawn in inches (X1.0 is radius 1 inch), Δd 0.12", e 0.02", U0.008" W0.004":
    // the model holds millimetres, so every value is ×25.4, and the moves are the mm moves'
    // shape scaled: layers 25 − 3k (in the shaft's units) become 1.0·25.4 … — the same table
    // divided by the scale. Scale the mm words with it: 3 → 0.12", 0.5 → 0.02", (0.2, 0.1) →
    // (0.008", 0.004").
    let scale = 0.04 * 25.4; // the shaft in units of 0.04" (25 units = 1.0"), in mm
    let (start, segs) = shaft(scale);
    let w = Words {
        along: Along::Z,
        depth: 3.0 * scale,
        retract: 0.5 * scale,
        allowance: (0.2 * scale, 0.1 * scale),
        pockets: false,
    };
    let m = moves(&rough(start, segs, w), 5).unwrap();
    assert_moves(&m, &SHAFT, scale);
    // The first cut's height in inches: 22 units × 0.04" = 0.88" radius (Ø1.76").
    assert!((m[0].to.x / 25.4 - 0.88).abs() < 1e-9);
}

#[test]
fn internal_type_i_a_bore_with_a_counterbore() {
    // Boring from X16 Z2 (radius 8): N10 G0 X30 (radius 15); N20 G1 Z−10; N30 X20 (radius 10);
    // N40 Z−25; N50 X14 (radius 7). Δd 2, e 0.5, U−0.4 (radius −0.2: inside) W0.1.
    // Shifted: (14.8, 2.1), Z−9.9, X9.8, Z−24.9, X6.8. The infeed is +X.
    // Layers from radius 8 outward by 2 while below the deepest 14.8: 14.8 − 8 = 6.8 → 3 layers,
    // X10, 12, 14, each meeting the counterbore's shoulder at Z−9.9 (the Ø19.6 bore lies at
    // 9.8, short of the first layer: its 1.8 mm are the last pass's).
    // Retracts 0.5 toward the axis: X9.5, 11.5, 13.5 at Z−9.4.
    let start = Pos::new(8.0, 2.0);
    let segs = vec![
        line(15.0, 2.0, 10),
        line(15.0, -10.0, 20),
        line(10.0, -10.0, 30),
        line(10.0, -25.0, 40),
        line(7.0, -25.0, 50),
    ];
    let w = Words {
        along: Along::Z,
        depth: 2.0,
        retract: 0.5,
        allowance: (-0.2, 0.1),
        pockets: false,
    };
    let m = moves(&rough(start, segs, w), 8).unwrap();
    let want: [Want; 18] = [
        (1, 'R', 10.0, 2.0),
        (1, 'F', 10.0, -9.9),
        (1, 'R', 9.5, -9.4),
        (2, 'R', 9.5, 2.0),
        (2, 'R', 12.0, 2.0),
        (2, 'F', 12.0, -9.9),
        (2, 'R', 11.5, -9.4),
        (3, 'R', 11.5, 2.0),
        (3, 'R', 14.0, 2.0),
        (3, 'F', 14.0, -9.9),
        (3, 'R', 13.5, -9.4),
        (4, 'R', 13.5, 2.1),
        (4, 'R', 14.8, 2.1),
        (4, 'F', 14.8, -9.9),
        (4, 'F', 9.8, -9.9),
        (4, 'F', 9.8, -24.9),
        (4, 'F', 6.8, -24.9),
        (4, 'R', 8.0, 2.0),
    ];
    assert_moves(&m, &want, 1.0);
}

#[test]
fn g72_facing_a_stepped_face() {
    // G72 from X52 Z2 (radius 26): N10 G0 Z−6; N20 G1 X40 (radius 20); N30 Z−3; N40 X24
    // (radius 12); N50 G3 X20 Z−1 R2 (centre radius 12, Z−1); N60 G1 Z2. Δd 2 (in Z), e 0.5,
    // U0.2 (radius 0.1) W0.2.
    // Working frame: the infeed is −Z, the cut −X. Shifted: (26.1, −5.8), X20.1, Z−2.8, X12.1,
    // arc to (10.1, −0.8) about (12.1, −0.8), Z2.2.
    // Layers from Z2 down by 2 while above −5.8: 7.8 → 3 layers, Z0, −2, −4.
    // Z0 runs to the last wall X10.1 (the shape first reaches Z2 there).
    // Z−2 meets the arc: −0.8 − √(4 − (x − 12.1)²) = −2 → (x − 12.1)² = 4 − 1.44 = 2.56 →
    //   x = 12.1 − 1.6 = 10.5.
    // Z−4 meets the step at X20.1.
    // Retracts: Z + 0.5 and X + 0.5 (back toward the start).
    let start = Pos::new(26.0, 2.0);
    let segs = vec![
        line(26.0, -6.0, 10),
        line(20.0, -6.0, 20),
        line(20.0, -3.0, 30),
        line(12.0, -3.0, 40),
        arc(10.0, -1.0, 12.0, -1.0, false, 50),
        line(10.0, 2.0, 60),
    ];
    let w = Words {
        along: Along::X,
        depth: 2.0,
        retract: 0.5,
        allowance: (0.1, 0.2),
        pockets: false,
    };
    let m = moves(&rough(start, segs, w), 3).unwrap();
    let want: [Want; 19] = [
        (1, 'R', 26.0, 0.0),
        (1, 'F', 10.1, 0.0),
        (1, 'R', 10.6, 0.5),
        (2, 'R', 26.0, 0.5),
        (2, 'R', 26.0, -2.0),
        (2, 'F', 10.5, -2.0),
        (2, 'R', 11.0, -1.5),
        (3, 'R', 26.0, -1.5),
        (3, 'R', 26.0, -4.0),
        (3, 'F', 20.1, -4.0),
        (3, 'R', 20.6, -3.5),
        (4, 'R', 26.1, -3.5),
        (4, 'R', 26.1, -5.8),
        (4, 'F', 20.1, -5.8),
        (4, 'F', 20.1, -2.8),
        (4, 'F', 12.1, -2.8),
        (4, 'A', 10.1, -0.8),
        (4, 'F', 10.1, 2.2),
        (4, 'R', 26.0, 2.0),
    ];
    assert_moves(&m, &want, 1.0);
}

/// Start X50 Z2 (radius 25); N10 G0 X20 W0 (radius 10); N20 G1 Z−10; N30 X12 Z−14 (radius 6);
/// N40 Z−20; N50 X28 Z−24 (radius 14); N60 Z−30; N70 X50 (radius 25).
fn pocket() -> (Pos, Vec<Segment>) {
    let segs = vec![
        line(10.0, 2.0, 10),
        line(10.0, -10.0, 20),
        line(6.0, -14.0, 30),
        line(6.0, -20.0, 40),
        line(14.0, -24.0, 50),
        line(14.0, -30.0, 60),
        line(25.0, -30.0, 70),
    ];
    (Pos::new(25.0, 2.0), segs)
}

#[test]
fn type_ii_roughs_a_pocket_and_type_i_refuses_it() {
    // Δd 3, e 0.5, no allowance. Layers from 25 while above the pocket's floor 6: 19 → 6
    // layers, 22, 19, 16, 13, 10, 7.
    // 22, 19, 16: to the last wall, Z−30. 13: the rising flank (6 → 14 over Z−20 → −24) meets
    // 13 at Z = −20 − (13 − 6)/2 = −23.5. 10: only the pocket (the Ø20 land lies at 10 itself):
    // from the falling flank's top Z−10 to the rising flank at −20 − 4/2 = −22; the tool
    // travels at 13.5 to Z−10 and feeds down the flank's start. 7: falling flank at
    // Z = −10 − 3 = −13, rising at −20 − 1/2 = −20.5.
    // Last: back up to the deepest layer that spans the way back (13, at 13.5), to Z2, then the
    // shape.
    let (start, segs) = pocket();
    let w = Words {
        along: Along::Z,
        depth: 3.0,
        retract: 0.5,
        allowance: (0.0, 0.0),
        pockets: true,
    };
    let m = moves(&rough(start, segs.clone(), w), 4).unwrap();
    let want: [Want; 33] = [
        (1, 'R', 22.0, 2.0),
        (1, 'F', 22.0, -30.0),
        (1, 'R', 22.5, -29.5),
        (2, 'R', 22.5, 2.0),
        (2, 'R', 19.0, 2.0),
        (2, 'F', 19.0, -30.0),
        (2, 'R', 19.5, -29.5),
        (3, 'R', 19.5, 2.0),
        (3, 'R', 16.0, 2.0),
        (3, 'F', 16.0, -30.0),
        (3, 'R', 16.5, -29.5),
        (4, 'R', 16.5, 2.0),
        (4, 'R', 13.0, 2.0),
        (4, 'F', 13.0, -23.5),
        (4, 'R', 13.5, -23.0),
        (5, 'R', 13.5, -10.0),
        (5, 'F', 10.0, -10.0),
        (5, 'F', 10.0, -22.0),
        (5, 'R', 10.5, -21.5),
        (6, 'R', 10.5, -13.0),
        (6, 'F', 7.0, -13.0),
        (6, 'F', 7.0, -20.5),
        (6, 'R', 7.5, -20.0),
        (7, 'R', 13.5, -20.0),
        (7, 'R', 13.5, 2.0),
        (7, 'R', 10.0, 2.0),
        (7, 'F', 10.0, -10.0),
        (7, 'F', 6.0, -14.0),
        (7, 'F', 6.0, -20.0),
        (7, 'F', 14.0, -24.0),
        (7, 'F', 14.0, -30.0),
        (7, 'F', 25.0, -30.0),
        (7, 'R', 25.0, 2.0),
    ];
    assert_moves(&m, &want, 1.0);

    let w = Words {
        along: Along::Z,
        depth: 3.0,
        retract: 0.5,
        allowance: (0.0, 0.0),
        pockets: false,
    };
    let e = moves(&rough(start, segs, w), 4).unwrap_err();
    // N30 goes back into the part in X: the second axis of the ZX plane.
    assert_eq!((e.code, e.span.line), (Code::Geometry, 30));
    assert!(e.message.starts_with("PS0329"), "{}", e.message);
}

#[test]
fn two_pockets_are_roughed_one_after_the_other() {
    // Start radius 20 Z2: N10 G0 X… (radius 10) W0; Z−5; pocket 1 down to 4 (Z−7 … −11) and up;
    // land at 10 to Z−16; pocket 2 down to 4 (Z−18 … −22) and up to 10 at Z−24; Z−30; X40.
    let start = Pos::new(20.0, 2.0);
    let segs = vec![
        line(10.0, 2.0, 10),
        line(10.0, -5.0, 20),
        line(4.0, -7.0, 30),
        line(4.0, -11.0, 40),
        line(10.0, -13.0, 50),
        line(10.0, -16.0, 60),
        line(4.0, -18.0, 70),
        line(4.0, -22.0, 80),
        line(10.0, -24.0, 90),
        line(10.0, -30.0, 100),
        line(20.0, -30.0, 110),
    ];
    let w = Words {
        along: Along::Z,
        depth: 2.5,
        retract: 0.5,
        allowance: (0.0, 0.0),
        pockets: true,
    };
    let m = moves(&rough(start, segs, w), 4).unwrap();
    // Cuts (feed moves along Z): layers 17.5, 15, 12.5 whole; from 10 (the land's own height)
    // the pockets alone, 10, 7.5 and 5 in each (5 > 4, the floors; 2.5 would be below).
    // Pocket 1 first, to its floor, then pocket 2.
    let cuts: Vec<(f64, f64)> = m
        .iter()
        .zip(m.iter().skip(1))
        .filter(|(a, b)| b.kind == MotionKind::Feed && (a.to.x - b.to.x).abs() < 1e-9)
        .filter(|(_, b)| b.pass <= 9)
        .map(|(_, b)| (b.to.x, b.pass as f64))
        .collect();
    let levels: Vec<f64> = cuts.iter().map(|c| c.0).collect();
    assert_eq!(levels, [17.5, 15.0, 12.5, 10.0, 7.5, 5.0, 10.0, 7.5, 5.0]);
    // Pocket 1's cuts end at Z−13 at the latest (its rising flank reaches the land there),
    // pocket 2's after Z−16.
    let ends: Vec<f64> = m
        .iter()
        .zip(m.iter().skip(1))
        .filter(|(a, b)| b.kind == MotionKind::Feed && (a.to.x - b.to.x).abs() < 1e-9)
        .filter(|(_, b)| b.pass <= 9)
        .map(|(_, b)| b.to.z)
        .collect();
    assert!(ends[3..6].iter().all(|&z| z >= -13.0 - 1e-9) && ends[6..].iter().all(|&z| z < -16.0));
    assert_eq!(m.last().unwrap().pass, 10);
}

#[test]
fn alarms() {
    let (start, segs) = shaft(1.0);
    let words = |depth, retract| Words {
        along: Along::Z,
        depth,
        retract,
        allowance: (0.2, 0.1),
        pockets: false,
    };
    for depth in [0.0, -1.0, f64::NAN] {
        let e = moves(&rough(start, segs.clone(), words(depth, 0.5)), 5).unwrap_err();
        assert!(e.message.starts_with("PS0062"), "{}", e.message);
        assert_eq!((e.code, e.span.line), (Code::OutOfRange, 5));
    }
    let e = moves(&rough(start, segs.clone(), words(3.0, -0.1)), 5).unwrap_err();
    assert!(e.message.starts_with("PS0062"), "{}", e.message);

    // Type I: the first block moves in Z.
    let mut s = segs.clone();
    s[0] = line(8.0, 1.0, 10);
    let e = moves(&rough(start, s, words(3.0, 0.5)), 5).unwrap_err();
    assert!(e.message.starts_with("PS0065"), "{}", e.message);
    assert_eq!(e.span.line, 10);

    // The first block is an arc.
    let mut s = segs.clone();
    s[0] = arc(8.0, 2.0, 16.5, 2.0, true, 10);
    let e = moves(&rough(start, s, words(3.0, 0.5)), 5).unwrap_err();
    assert!(e.message.starts_with("PS0065"), "{}", e.message);

    // A block turning back along Z (N60 to Z−10 after Z−19): PS0064 at its line.
    let mut s = segs.clone();
    s[5] = line(18.0, -10.0, 60);
    let e = moves(&rough(start, s, words(3.0, 0.5)), 5).unwrap_err();
    assert!(e.message.starts_with("PS0064"), "{}", e.message);
    assert_eq!(e.span.line, 60);

    // An arc that bulges back along Z (a G2 the other way round the corner): PS0064.
    let mut s = segs.clone();
    s[4] = arc(18.0, -19.0, 18.0, -15.0, false, 50);
    let e = moves(&rough(start, s, words(3.0, 0.5)), 5).unwrap_err();
    assert_eq!(e.span.line, 50, "{}", e.message);

    // The shape does not start at the start point.
    let mut r = rough(start, segs.clone(), words(3.0, 0.5));
    r.contour.start = Pos::new(25.0, 5.0);
    assert_eq!(moves(&r, 5).unwrap_err().code, Code::Geometry);

    // A depth of cut far too small for the shape.
    let e = moves(&rough(start, segs.clone(), words(1e-6, 0.0)), 5).unwrap_err();
    assert_eq!(e.code, Code::TooManyPasses);

    // Only the first block.
    let e = moves(&rough(start, segs[..1].to_vec(), words(3.0, 0.5)), 5).unwrap_err();
    assert_eq!((e.code, e.span.line), (Code::Geometry, 10));
}

// ---- properties ----

/// The shifted shape's floor at `t` in the working frame, found apart from the code under test:
/// the lowest point any segment has at that t (lines only).
fn floor(frame: Frame, pts: &[Pos], t: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    for w in pts.windows(2) {
        let (a, b) = (frame.to(w[0]), frame.to(w[1]));
        let (lo, hi) = (a.t.min(b.t), a.t.max(b.t));
        if t < lo - 1e-9 || t > hi + 1e-9 {
            continue;
        }
        let h = if hi - lo < 1e-12 {
            a.h.min(b.h)
        } else {
            a.h + (b.h - a.h) * (t - a.t) / (b.t - a.t)
        };
        best = Some(best.map_or(h, |x: f64| x.min(h)));
    }
    best
}

/// An external G71 shape toward −Z from X`x0` Z2: each step (dz ≥ 0.5, dx) from the previous
/// point; type I keeps dx ≥ 0.
fn shape(first: f64, steps: &[(f64, f64)], monotone: bool) -> Vec<Segment> {
    let mut x = first;
    let mut z = 0.0;
    let mut out = vec![line(first, 2.0, 10), line(first, 0.0, 11)];
    for (i, &(dz, dx)) in steps.iter().enumerate() {
        z -= dz;
        x = if monotone {
            x + dx.abs()
        } else {
            (x + dx).max(1.0)
        };
        out.push(line(x, z, 12 + i as u32));
    }
    out
}

fn check_properties(r: &Rough, m: &[Motion]) -> std::result::Result<(), TestCaseError> {
    let frame = Frame {
        along: Along::Z,
        infeed: -1.0,
        cut: -1.0,
    };
    let shift = Vec2::new(r.allowance_x, r.allowance_z);
    let pts: Vec<Pos> = r
        .contour
        .segments
        .iter()
        .map(|s| s.to.plus(shift))
        .collect();
    let start = frame.to(r.start);
    let lowest = pts.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let mut at = r.start;
    for mv in m {
        prop_assert!(mv.to.is_finite());
        if mv.kind == MotionKind::Feed {
            // Never below the shape plus its allowance, at the ends and at points along.
            for i in 0..=16 {
                let f = i as f64 / 16.0;
                let p = frame.to(Pos::new(
                    at.x + (mv.to.x - at.x) * f,
                    at.z + (mv.to.z - at.z) * f,
                ));
                if let Some(fl) = floor(frame, &pts, p.t) {
                    prop_assert!(p.h >= fl - 1e-6, "{mv:?} from {at:?} cuts below {fl}");
                }
            }
        }
        at = mv.to;
    }
    // Back at the start.
    prop_assert!(at.distance(r.start) < 1e-9);
    // The roughing layers lie Δd apart from the start down, none skipped, the last within Δd of
    // the lowest point, and the final pass along the shape reaches the allowance.
    let last_pass = m.last().unwrap().pass;
    let mut rough_levels: Vec<f64> = m
        .iter()
        .zip(std::iter::once(&r.start).chain(m.iter().map(|m| &m.to)))
        .filter(|(mv, from)| {
            mv.kind == MotionKind::Feed && mv.pass < last_pass && (mv.to.x - from.x).abs() < 1e-12
        })
        .map(|(mv, _)| mv.to.x)
        .collect();
    rough_levels.sort_by(|a, b| b.partial_cmp(a).unwrap());
    rough_levels.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    let mut expect = start.h;
    for l in &rough_levels {
        expect -= r.depth;
        prop_assert!((l - expect).abs() < 1e-6, "levels {rough_levels:?}");
    }
    prop_assert!(
        expect - lowest <= r.depth + 1e-6,
        "last layer {expect}, lowest {lowest}"
    );
    let along: Vec<_> = m
        .iter()
        .filter(|mv| mv.pass == last_pass && mv.kind == MotionKind::Feed)
        .collect();
    prop_assert_eq!(along.len(), pts.len() - 1);
    for (mv, p) in along.iter().zip(&pts[1..]) {
        prop_assert!(mv.to.distance(*p) < 1e-9);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn type_i_passes_stay_above_the_shape(
        first in 2.0f64..10.0,
        steps in prop::collection::vec((0.5f64..6.0, 0.0f64..4.0), 1..8),
        depth in 0.3f64..4.0,
        retract in 0.0f64..1.0,
        ax in 0.0f64..0.5,
        az in 0.0f64..0.3,
    ) {
        let segs = shape(first, &steps, true);
        let top = segs.iter().map(|s| s.to.x).fold(0.0, f64::max);
        let r = rough(Pos::new(top + 3.0, 2.0), segs, Words {
            along: Along::Z, depth, retract, allowance: (ax, az), pockets: false,
        });
        let m = moves(&r, 1).unwrap();
        check_properties(&r, &m)?;
    }

    #[test]
    fn type_ii_passes_stay_above_the_shape(
        first in 2.0f64..10.0,
        steps in prop::collection::vec((0.5f64..6.0, -5.0f64..5.0), 1..10),
        depth in 0.3f64..4.0,
        retract in 0.0f64..1.0,
        ax in 0.0f64..0.5,
    ) {
        let segs = shape(first, &steps, false);
        let top = segs.iter().map(|s| s.to.x).fold(0.0, f64::max);
        let r = rough(Pos::new(top + 3.0, 2.0), segs, Words {
            along: Along::Z, depth, retract, allowance: (ax, 0.0), pockets: true,
        });
        let m = moves(&r, 1).unwrap();
        check_properties(&r, &m)?;
        // Travel at rapid never runs through the region below the shape either.
        let frame = Frame { along: Along::Z, infeed: -1.0, cut: -1.0 };
        let pts: Vec<Pos> = r.contour.segments.iter().map(|s| s.to.plus(Vec2::new(ax, 0.0))).collect();
        let mut at = r.start;
        for mv in &m[..m.len() - 1] {
            for i in 0..=16 {
                let f = i as f64 / 16.0;
                let p = frame.to(Pos::new(at.x + (mv.to.x - at.x) * f, at.z + (mv.to.z - at.z) * f));
                if let Some(fl) = floor(frame, &pts, p.t) {
                    prop_assert!(p.h >= fl - 1e-6, "{mv:?} from {at:?} runs below {fl}");
                }
            }
            at = mv.to;
        }
    }
}
