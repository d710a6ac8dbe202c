use super::*;
use crate::toolpath::MotionKind as K;

const R: K = K::Rapid;
const F: K = K::Feed;

fn line(x: f64, z: f64, n: u32) -> Segment {
    Segment {
        to: Pos::new(x, z),
        shape: Shape::Line,
        line: n,
    }
}

fn contour(points: &[(f64, f64)]) -> Contour {
    Contour {
        start: Pos::new(points[0].0, points[0].1),
        segments: points[1..]
            .iter()
            .enumerate()
            .map(|(i, &(x, z))| line(x, z, 101 + i as u32))
            .collect(),
    }
}

fn removal(along: Along, internal: bool, c: Contour) -> Removal {
    Removal {
        along,
        internal,
        from: Pos::new(30.0, 5.0),
        depth: 2.0,
        lift: 1.0,
        allowance_x: 0.0,
        allowance_z: 0.0,
        allowance: 0.0,
        rough: true,
        finish: false,
        contour: c,
    }
}

/// The moves as (kind, X radius, Z), compared at 0.0001 mm.
fn assert_moves(got: &[Motion], want: &[(K, f64, f64)]) {
    let got: Vec<_> = got.iter().map(|m| (m.kind, m.to.x, m.to.z)).collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.0, w.0, "move {i}: {got:?}");
        assert!(
            (g.1 - w.1).abs() < 1e-4 && (g.2 - w.2).abs() < 1e-4,
            "move {i}: {g:?} against {w:?}"
        );
    }
}

/// The stepped shaft Ø20 × 20, Ø30 × 20, to Ø40, written from the face (radius 10 at Z0).
fn shaft() -> Contour {
    contour(&[
        (10.0, 0.0),
        (10.0, -20.0),
        (15.0, -20.0),
        (15.0, -40.0),
        (20.0, -40.0),
    ])
}

#[test]
fn longitudinal_roughing_in_equal_layers_cleans_each_corner() {
    // Allowances FALX 0.5 (radius), FALZ 0.2: the contour moves by X+0.5 Z+0.2 to
    // (10.5, 0.2) (10.5, −19.8) (15.5, −19.8) (15.5, −39.8) (20.5, −39.8). Start point: before
    // the first point and above the highest by the lift 1: X 21.5, Z 1.2. Depth 20.5 − 10.5 =
    // 10, MID 2: 5 layers of 2 at X 18.5, 16.5, 14.5, 12.5, 10.5. Each: G0 down at Z1.2, G1 to
    // where the contour rises above the layer, G1 up the contour to the layer before, lift 1 in
    // X and Z, G0 back to Z1.2.
    let mut r = removal(Along::Z, false, shaft());
    r.allowance_x = 0.5;
    r.allowance_z = 0.2;
    let m = moves(&r, 7).unwrap();
    assert_moves(
        &m,
        &[
            (R, 21.5, 1.2),
            // layer 1: to the shoulder at Z−39.8, up it to 20.5 (the top)
            (R, 18.5, 1.2),
            (F, 18.5, -39.8),
            (F, 20.5, -39.8),
            (R, 21.5, -38.8),
            (R, 21.5, 1.2),
            // layer 2
            (R, 16.5, 1.2),
            (F, 16.5, -39.8),
            (F, 18.5, -39.8),
            (R, 19.5, -38.8),
            (R, 19.5, 1.2),
            // layer 3: ends at the shoulder Z−19.8, follows 15.5 to Z−39.8 and up to 16.5
            (R, 14.5, 1.2),
            (F, 14.5, -19.8),
            (F, 15.5, -19.8),
            (F, 15.5, -39.8),
            (F, 16.5, -39.8),
            (R, 17.5, -38.8),
            (R, 17.5, 1.2),
            // layer 4
            (R, 12.5, 1.2),
            (F, 12.5, -19.8),
            (F, 14.5, -19.8),
            (R, 15.5, -18.8),
            (R, 15.5, 1.2),
            // layer 5: on the allowance of Ø20 itself
            (R, 10.5, 1.2),
            (F, 10.5, -19.8),
            (F, 12.5, -19.8),
            (R, 13.5, -18.8),
            (R, 13.5, 1.2),
            (R, 21.5, 1.2),
        ],
    );
    assert_eq!(m.iter().map(|m| m.pass).max(), Some(5));
    assert!(m.iter().all(|m| m.line == 7));
    assert_eq!(start_point(&r).unwrap(), Pos::new(21.5, 1.2));
}

#[test]
fn a_depth_that_does_not_divide_evenly_is_split_into_equal_layers() {
    // Depth 10 (radius 20 down to 10, no allowance), MID 3: ⌈10/3⌉ = 4 layers of 2.5, at X
    // 17.5, 15, 12.5, 10.
    let mut r = removal(Along::Z, false, shaft());
    r.depth = 3.0;
    let m = moves(&r, 1).unwrap();
    let cuts: Vec<f64> = m
        .windows(2)
        .filter(|w| w[1].kind == F && w[0].kind == R)
        .map(|w| w[1].to.x)
        .collect();
    assert_eq!(cuts.len(), 4);
    for (got, want) in cuts.iter().zip([17.5, 15.0, 12.5, 10.0]) {
        assert!((got - want).abs() < 1e-9, "{cuts:?}");
    }
}

#[test]
fn finishing_follows_the_contour_as_written_from_the_start_point() {
    // Start point X21 Z1 (lift 1, no allowance). G0 to it, G0 down to X10 at Z1, G1 to the
    // contour's first point, along it, G0 back.
    let mut r = removal(Along::Z, false, shaft());
    r.rough = false;
    r.finish = true;
    let m = moves(&r, 1).unwrap();
    assert_moves(
        &m,
        &[
            (R, 21.0, 1.0),
            (R, 10.0, 1.0),
            (F, 10.0, 0.0),
            (F, 10.0, -20.0),
            (F, 15.0, -20.0),
            (F, 15.0, -40.0),
            (F, 20.0, -40.0),
            (R, 21.0, 1.0),
        ],
    );
    assert!(m.iter().all(|m| m.pass == 1));
}

#[test]
fn complete_machining_roughs_then_finishes_in_the_roughing_direction() {
    // The contour written from Ø40 back to the face: roughing orders it from the face; the
    // finishing pass after it runs from the face too. MID 5 on the depth 10: layers X15, X10.
    let mut c = shaft();
    let mut points = vec![c.start];
    points.extend(c.segments.iter().map(|s| s.to));
    points.reverse();
    c = contour(&points.iter().map(|p| (p.x, p.z)).collect::<Vec<_>>());
    let mut r = removal(Along::Z, false, c);
    r.depth = 5.0;
    r.finish = true;
    let m = moves(&r, 1).unwrap();
    assert_moves(
        &m,
        &[
            (R, 21.0, 1.0),
            (R, 15.0, 1.0),
            (F, 15.0, -40.0),
            (F, 20.0, -40.0),
            (R, 21.0, -39.0),
            (R, 21.0, 1.0),
            (R, 10.0, 1.0),
            (F, 10.0, -20.0),
            (F, 15.0, -20.0),
            (R, 16.0, -19.0),
            (R, 16.0, 1.0),
            (R, 21.0, 1.0),
            // finishing, pass 3
            (R, 10.0, 1.0),
            (F, 10.0, 0.0),
            (F, 10.0, -20.0),
            (F, 15.0, -20.0),
            (F, 15.0, -40.0),
            (F, 20.0, -40.0),
            (R, 21.0, 1.0),
        ],
    );
    assert_eq!(m.last().unwrap().pass, 3);
    // The roughing layers' lines name the blocks that were written last-first.
    assert_eq!(r.contour.segments[0].line, 101);
}

#[test]
fn internal_longitudinal_roughing_steps_away_from_the_axis() {
    // A bore: radius 15 to Z−10, 10 to Z−30, down to the drilled 7. FALX 0.5 moves it toward
    // the axis: 14.5, 9.5, 6.5. Frame h = −X: top −6.5, low −14.5, depth 8, MID 3: 3 layers of
    // 8/3 at X 9.16667, 11.83333, 14.5. Start X 5.5 (6.5 − 1), Z 1.
    let c = contour(&[
        (15.0, 0.0),
        (15.0, -10.0),
        (10.0, -10.0),
        (10.0, -30.0),
        (7.0, -30.0),
    ]);
    let mut r = removal(Along::Z, true, c);
    r.depth = 3.0;
    r.allowance_x = 0.5;
    let (h1, h2) = (6.5 + 8.0 / 3.0, 6.5 + 16.0 / 3.0);
    let m = moves(&r, 1).unwrap();
    assert_moves(
        &m,
        &[
            (R, 5.5, 1.0),
            (R, h1, 1.0),
            (F, h1, -30.0),
            (F, 6.5, -30.0),
            (R, 5.5, -29.0),
            (R, 5.5, 1.0),
            (R, h2, 1.0),
            (F, h2, -10.0),
            (F, 9.5, -10.0),
            (F, 9.5, -30.0),
            (F, h1, -30.0),
            (R, h1 - 1.0, -29.0),
            (R, h1 - 1.0, 1.0),
            (R, 14.5, 1.0),
            (F, 14.5, -10.0),
            (F, h2, -10.0),
            (R, h2 - 1.0, -9.0),
            (R, h2 - 1.0, 1.0),
            (R, 5.5, 1.0),
        ],
    );
}

#[test]
fn facing_roughing_layers_in_z_toward_the_chuck() {
    // A face: rim at Z−6 from radius 30 to 20, shoulder up to Z0, face to the axis. FALZ 0.2:
    // Z −5.8 and 0.2. Frame t = −X, h = Z: top 0.2, low −5.8, MID 2: layers Z −1.8, −3.8,
    // −5.8. Start X 31 (before radius 30 by the lift), Z 1.2.
    let c = contour(&[(30.0, -6.0), (20.0, -6.0), (20.0, 0.0), (0.0, 0.0)]);
    let mut r = removal(Along::X, false, c);
    r.allowance_z = 0.2;
    let m = moves(&r, 1).unwrap();
    assert_moves(
        &m,
        &[
            (R, 31.0, 1.2),
            (R, 31.0, -1.8),
            (F, 20.0, -1.8),
            (F, 20.0, 0.2),
            (R, 21.0, 1.2),
            (R, 31.0, 1.2),
            (R, 31.0, -3.8),
            (F, 20.0, -3.8),
            (F, 20.0, -1.8),
            (R, 21.0, -0.8),
            (R, 31.0, -0.8),
            (R, 31.0, -5.8),
            (F, 20.0, -5.8),
            (F, 20.0, -3.8),
            (R, 21.0, -2.8),
            (R, 31.0, -2.8),
            (R, 31.0, 1.2),
        ],
    );
}

#[test]
fn an_arc_is_followed_and_cut_where_the_layer_meets_it() {
    // Ø20 to Z−10, then a fillet of radius 10 about (X radius 20, Z−10) up to (20, −20): G2
    // (clockwise with Z to the right and X up). Depth 10, MID 5: layers X15 and X10.
    let c = Contour {
        start: Pos::new(10.0, 0.0),
        segments: vec![
            line(10.0, -10.0, 1),
            Segment {
                to: Pos::new(20.0, -20.0),
                shape: Shape::Arc {
                    centre: Pos::new(20.0, -10.0),
                    clockwise: true,
                },
                line: 2,
            },
        ],
    };
    let mut r = removal(Along::Z, false, c);
    r.depth = 5.0;
    let m = moves(&r, 1).unwrap();
    // Centre (20, −10), radius 10: at x = 15, z = −10 − √75 = −18.66025.
    let z = -10.0 - 75f64.sqrt();
    assert_eq!(m[2].kind, F);
    assert!(
        (m[2].to.x - 15.0).abs() < 1e-4 && (m[2].to.z - z).abs() < 1e-4,
        "{m:?}"
    );
    assert!(matches!(
        m[3].kind,
        K::Arc {
            clockwise: true,
            ..
        }
    ));
    assert!((m[3].to.x - 20.0).abs() < 1e-4 && (m[3].to.z + 20.0).abs() < 1e-4);
}

#[test]
fn a_relief_cut_is_refused_at_its_block() {
    // Ø30 to Z−10, down to Ø20 (into the part), out to Ø40.
    let c = contour(&[
        (15.0, 0.0),
        (15.0, -10.0),
        (10.0, -12.0),
        (10.0, -20.0),
        (20.0, -20.0),
    ]);
    let e = moves(&removal(Along::Z, false, c), 1).unwrap_err();
    assert_eq!((e.code, e.span.line), (Code::Unsupported, 102));
}

#[test]
fn a_contour_turning_back_along_the_cut_is_refused() {
    let c = contour(&[(10.0, 0.0), (10.0, -20.0), (15.0, -10.0), (20.0, -30.0)]);
    let e = moves(&removal(Along::Z, false, c), 1).unwrap_err();
    assert_eq!((e.code, e.span.line), (Code::Geometry, 102));
}

#[test]
fn values_no_cycle_runs_with_are_errors() {
    let mut r = removal(Along::Z, false, shaft());
    r.depth = 0.0;
    assert_eq!(moves(&r, 3).unwrap_err().code, Code::OutOfRange);
    let mut r = removal(Along::Z, false, shaft());
    r.depth = 1e-9;
    assert_eq!(moves(&r, 3).unwrap_err().code, Code::TooManyPasses);
}

#[test]
fn the_allowance_along_the_contour_is_a_shift_on_axis_lines_and_refused_on_a_taper() {
    // FAL 0.3 on the stepped shaft: the same moves as FALX 0.3 with FALZ 0.3.
    let mut a = removal(Along::Z, false, shaft());
    a.allowance = 0.3;
    let mut b = removal(Along::Z, false, shaft());
    b.allowance_x = 0.3;
    b.allowance_z = 0.3;
    assert_eq!(moves(&a, 1).unwrap(), moves(&b, 1).unwrap());
    // A chamfer (X and Z in one block): refused at its block.
    let c = contour(&[(8.0, 0.0), (10.0, -2.0), (10.0, -20.0), (20.0, -20.0)]);
    let mut r = removal(Along::Z, false, c);
    r.allowance = 0.3;
    let e = moves(&r, 1).unwrap_err();
    assert_eq!((e.code, e.span.line), (Code::Unsupported, 101));
}
