//! The part cut by hand-made moves; every expected number is worked in a comment (X a radius, mm).

use super::*;

const TOL: f64 = 0.001;

fn feed(x: f64, z: f64, line: u32) -> Motion {
    Motion {
        kind: MotionKind::Feed,
        to: Pos::new(x, z),
        pass: 0,
        line,
    }
}

fn thread(x: f64, z: f64, line: u32, pass: u32) -> Motion {
    Motion {
        kind: MotionKind::Thread {
            lead: 2.5,
            dlead: 0.0,
            phase_deg: 0.0,
        },
        to: Pos::new(x, z),
        pass,
        line,
    }
}

fn rapid(x: f64, z: f64, line: u32) -> Motion {
    Motion {
        kind: MotionKind::Rapid,
        to: Pos::new(x, z),
        pass: 0,
        line,
    }
}

/// Runs `moves` from `start` through the part: feeds cut, rapids only move.
fn run(part: &mut Part, start: Pos, moves: &[Motion], tool: &Tool) -> Pos {
    let mut at = start;
    for m in moves {
        part.cut(at, m, tool).unwrap();
        at = m.to;
    }
    at
}

fn bar(diameter: f64, face: f64, length: f64) -> Stock {
    Stock {
        diameter: Dim::given(diameter),
        face: Dim::given(face),
        length: Dim::given(length),
        bore: Dim::assumed(0.0),
    }
}

fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOL
}

fn cut_by(hit: &Hit) -> Option<u32> {
    match hit.origin {
        Origin::Cut(c) => Some(c.line),
        _ => None,
    }
}

/// A Ø40 bar with its face at Z1, faced at Z0 (line 2) and turned to Ø30 over Z0..-20 (line 4)
/// with a point turning tool.
fn faced_and_turned() -> Part {
    let mut part = Part::new(&bar(40.0, 1.0, 60.0), TOL).unwrap();
    let tool = Tool::point(Body::Turning);
    let moves = [
        rapid(21.0, 0.0, 1),
        // Facing to X-1 (radius −0.5): the end edge takes Z0..1 over the whole face.
        feed(-0.5, 0.0, 2),
        rapid(15.0, 2.0, 3),
        // Turning: the body above the tip takes everything outside R15 over Z2..-20.
        feed(15.0, -20.0, 4),
        feed(21.0, -20.0, 5),
        rapid(21.0, 2.0, 6),
    ];
    run(&mut part, Pos::new(30.0, 10.0), &moves, &tool);
    part
}

#[test]
fn a_faced_and_turned_bar_has_the_turned_diameter_and_face() {
    let part = faced_and_turned();
    // Z-10: from the axis to R15; Z-30: the bar's R20; the face at Z0 now.
    let r = part.radius_at(-10.0).unwrap();
    assert!(near(r.outer, 15.0) && r.bore.is_none(), "{r:?}");
    assert!(near(part.radius_at(-30.0).unwrap().outer, 20.0));
    assert!(near(part.face_z().unwrap(), 0.0));
    assert!(near(part.face_at(10.0).unwrap(), 0.0));
    // The shoulder's face at Z-20 between R15 and R20.
    assert!(near(part.face_at(17.0).unwrap(), -20.0));
    assert!(part.radius_at(0.5).is_none());
    // Four corners of the stock and the two of the step: no more vertices than that.
    assert_eq!(part.vertex_count(), 6, "{:?}", part.outline());
}

#[test]
fn a_rapid_into_the_turned_diameter_names_its_line() {
    let part = faced_and_turned();
    // G0 X28 Z-10 from X32 Z2, i.e. (16, 2) → (14, −10): x = 16 − 2t, z = 2 − 12t reaches R15 at
    // t = 0.5, Z = 2 − 6 = −4. It crosses the diameter Ø30 turned at line 4.
    let hit = part
        .rapid_hits(Pos::new(16.0, 2.0), Pos::new(14.0, -10.0))
        .expect("a hit");
    assert!(near(hit.at.x, 15.0) && near(hit.at.z, -4.0), "{hit:?}");
    assert_eq!(cut_by(&hit), Some(4));
    assert!(
        matches!(hit.surface, Surface::Diameter { diameter, bore: false } if near(diameter, 30.0))
    );
    assert_eq!(hit.stock_only(), None);
    assert_eq!(
        hit.describe(Units::Mm),
        "the turned diameter Ø30 at Z-4 (cut at line 4)"
    );
    // G0 X32 Z-10 from the same point stays above Ø30, in the air the turning made: no hit.
    assert_eq!(
        part.rapid_hits(Pos::new(16.0, 2.0), Pos::new(16.0, -10.0)),
        None
    );
    // A rapid along the turned diameter at R15 only touches it: no hit; 0.0004 below it (less
    // than half the resolution) neither; 0.002 below it, a hit.
    assert_eq!(
        part.rapid_hits(Pos::new(15.0, 2.0), Pos::new(15.0, -15.0)),
        None
    );
    assert_eq!(
        part.rapid_hits(Pos::new(14.9996, 2.0), Pos::new(14.9996, -15.0)),
        None
    );
    let hit = part
        .rapid_hits(Pos::new(14.998, 2.0), Pos::new(14.998, -15.0))
        .expect("a hit");
    // It enters through the face cut at line 2, at Z0.
    assert_eq!(cut_by(&hit), Some(2));
    assert!(matches!(hit.surface, Surface::Face { z } if near(z, 0.0)));
}

#[test]
fn rapids_into_stock_given_and_assumed() {
    // Ø40 given, face at Z0 assumed.
    let stock = Stock {
        diameter: Dim::given(40.0),
        face: Dim::given_or(None, 0.0),
        length: Dim::given(50.0),
        bore: Dim::given_or(None, 0.0),
    };
    let part = Part::new(&stock, TOL).unwrap();
    // Into the face at (10, 0): the face is only assumed.
    let hit = part
        .rapid_hits(Pos::new(10.0, 5.0), Pos::new(10.0, -5.0))
        .unwrap();
    assert!(near(hit.at.z, 0.0) && near(hit.at.x, 10.0));
    assert_eq!(hit.stock_only(), Some(Known::Assumed));
    assert_eq!(
        hit.describe(Units::Mm),
        "the stock's face at Z0 (stock as assumed)"
    );
    // Into the outside diameter at (20, −10): given.
    let hit = part
        .rapid_hits(Pos::new(25.0, -10.0), Pos::new(15.0, -10.0))
        .unwrap();
    assert!(near(hit.at.x, 20.0));
    assert_eq!(hit.stock_only(), Some(Known::Given));
    // In inches: Ø40 mm is 1.5748 in, Z-10 mm is -0.3937 in.
    assert_eq!(
        hit.describe(Units::Inch),
        "the stock's outside Ø1.5748 at Z-0.3937 (stock as given)"
    );
    // Outside the stock: nothing.
    assert_eq!(
        part.rapid_hits(Pos::new(25.0, 5.0), Pos::new(21.0, -60.0)),
        None
    );
}

#[test]
fn a_bore_enlarged_by_a_boring_move() {
    // A tube Ø40 × Ø10 bore, face Z0; a point boring tool from X12 Z2 to Z-15 (line 2) enlarges
    // the bore to Ø12 over Z0..-15, then retracts along its cut.
    let stock = Stock {
        bore: Dim::given(10.0),
        ..bar(40.0, 0.0, 30.0)
    };
    let mut part = Part::new(&stock, TOL).unwrap();
    let tool = Tool::point(Body::Turning);
    let moves = [feed(6.0, -15.0, 2), rapid(6.0, 2.0, 3)];
    run(&mut part, Pos::new(6.0, 2.0), &moves, &tool);
    let r = part.radius_at(-10.0).unwrap();
    assert!(near(r.outer, 20.0) && near(r.bore.unwrap(), 6.0), "{r:?}");
    assert!(near(part.radius_at(-20.0).unwrap().bore.unwrap(), 5.0));
    // G0 X16 at Z-10 from X12: into the bore wall Ø12 made by line 2.
    let hit = part
        .rapid_hits(Pos::new(6.0, -10.0), Pos::new(8.0, -10.0))
        .unwrap();
    assert_eq!(cut_by(&hit), Some(2));
    assert_eq!(
        hit.describe(Units::Mm),
        "the bore wall Ø12 at Z-10 (cut at line 2)"
    );
    // Down the bore at R5.5 past Z-15: into the step the boring left at Z-15 (line 2). The
    // nose ran down the wall, not across the step: the step is cleared, its material the
    // stock's as given.
    let hit = part
        .rapid_hits(Pos::new(5.5, -5.0), Pos::new(5.5, -25.0))
        .unwrap();
    assert!(near(hit.at.z, -15.0));
    assert!(
        matches!(hit.origin, Origin::Cleared(c) if c.line == 2),
        "{hit:?}"
    );
    assert_eq!(hit.stock_only(), Some(Known::Given));
    assert!(matches!(hit.surface, Surface::Face { z } if near(z, -15.0)));
}

/// An M20x2.5 external thread on a Ø20 bar (face Z0): three passes at R9.5, R9.0 and the root
/// R8.4665 (Ø16.933) from Z5 to Z-20 (line 10), each back out at R11.
fn threaded() -> Part {
    let mut part = Part::new(&bar(20.0, 0.0, 50.0), TOL).unwrap();
    let tool = Tool::point(Body::Radial);
    let mut moves = Vec::new();
    for (n, x) in [(1, 9.5), (2, 9.0), (3, 8.4665)] {
        moves.extend([
            rapid(x, 5.0, 10),
            thread(x, -20.0, 10, n),
            rapid(11.0, -20.0, 10),
            rapid(11.0, 5.0, 10),
        ]);
    }
    run(&mut part, Pos::new(11.0, 5.0), &moves, &tool);
    part
}

#[test]
fn a_rapid_through_the_thread_hits_its_root() {
    let part = threaded();
    assert!(near(part.radius_at(-10.0).unwrap().outer, 8.4665));
    // G0 X15 Z-10 from the cycle's start X22 Z5: (11, 5) → (7.5, −10) reaches R8.4665 at
    // t = (11 − 8.4665)/3.5 = 0.723857, Z = 5 − 15·0.723857 = −5.857857.
    let hit = part
        .rapid_hits(Pos::new(11.0, 5.0), Pos::new(7.5, -10.0))
        .unwrap();
    assert!(near(hit.at.z, -5.857857), "{hit:?}");
    assert!(matches!(
        hit.origin,
        Origin::Cut(Cut {
            line: 10,
            pass: 3,
            kind: CutKind::Thread
        })
    ));
    assert_eq!(
        hit.describe(Units::Mm),
        "the thread's root Ø16.933 at Z-5.858 (cut at line 10)"
    );
}

#[test]
fn an_arc_turned_radius() {
    // A Ø40 bar, face Z0: from the axis along the face to X20 Z0 (radius 10), a convex R5
    // corner G3 to X30 Z-5 about (10, −5), then Ø30 to Z-30 (lines 2–5).
    let mut part = Part::new(&bar(40.0, 0.0, 60.0), TOL).unwrap();
    let tool = Tool::point(Body::Turning);
    let arc = Motion {
        kind: MotionKind::Arc {
            centre: Pos::new(10.0, -5.0),
            clockwise: false,
        },
        to: Pos::new(15.0, -5.0),
        pass: 0,
        line: 4,
    };
    let moves = [
        feed(0.0, 0.0, 2),
        feed(10.0, 0.0, 3),
        arc,
        feed(15.0, -30.0, 5),
        feed(21.0, -30.0, 6),
    ];
    run(&mut part, Pos::new(0.0, 2.0), &moves, &tool);
    // On the arc, x = 10 + √(25 − (z + 5)²): at Z-1, 10 + √9 = 13; at Z-2.5, 10 + √18.75 =
    // 14.330127. The chords lie inside the circle by at most half the tolerance.
    for (z, x) in [(-1.0, 13.0), (-2.5, 14.330127), (-4.0, 10.0 + 24f64.sqrt())] {
        let got = part.radius_at(z).unwrap().outer;
        assert!(
            got <= x + 1e-4 && x - got <= TOL / 2.0 + 1e-4,
            "Z{z}: {got} vs {x}"
        );
    }
    assert!(near(part.radius_at(-10.0).unwrap().outer, 15.0));
    assert!(near(part.radius_at(-40.0).unwrap().outer, 20.0));
    // A rapid into the round at 45°: from (20, 5) toward the centre (10, −5) meets the circle at
    // (10 + 5/√2, −5 + 5/√2) = (13.535534, −1.464466): the profile cut at line 4.
    let hit = part
        .rapid_hits(Pos::new(20.0, 5.0), Pos::new(10.0, -5.0))
        .unwrap();
    assert!((hit.at.x - 13.535534).abs() < 2.0 * TOL, "{hit:?}");
    assert_eq!(cut_by(&hit), Some(4));
    assert!(matches!(hit.surface, Surface::Slope { .. }));
}

#[test]
fn a_nose_radius_leaves_the_programmed_diameter() {
    // A turning tool with a 0.8 nose programmed at X30 (R15) along Z, without compensation: the
    // nose's centre runs at R15.8, its lowest point at R15: the diameter is Ø30.
    let mut part = Part::new(&bar(40.0, 0.0, 60.0), TOL).unwrap();
    let tool = Tool {
        nose_radius: 0.8,
        body: Body::Turning,
    };
    run(
        &mut part,
        Pos::new(15.0, 2.0),
        &[feed(15.0, -20.0, 7)],
        &tool,
    );
    assert!(near(part.radius_at(-10.0).unwrap().outer, 15.0));
    // At the end the nose leaves its round: its centre stops at (15.8, −19.2), so at Z-19.6
    // the material reaches the circle, 15.8 − √(0.8² − 0.4²) = 15.8 − 0.692820 = 15.107180.
    let r = part.radius_at(-19.6).unwrap().outer;
    assert!((r - 15.107180).abs() <= TOL, "{r}");
}

#[test]
fn a_thread_running_into_a_shoulder() {
    // A Ø30 bar (face Z0) turned to Ø20 over Z0..-18 (line 2), the shoulder face at Z-18
    // (line 3). A thread whose first pass (0.4 deep, at R9.6) runs to Z-20 meets the shoulder:
    // beyond R9.6 + 0.4 = R10 it would take R10..R15 over Z-20..-18: 5 × 2 = 10 mm², first met
    // at Z-18.
    let mut part = Part::new(&bar(30.0, 0.0, 50.0), TOL).unwrap();
    let turning = Tool::point(Body::Turning);
    run(
        &mut part,
        Pos::new(10.0, 2.0),
        &[feed(10.0, -18.0, 2), feed(16.0, -18.0, 3)],
        &turning,
    );
    let threading = Tool::point(Body::Radial);
    let passes = |end: f64| {
        vec![
            rapid(9.6, 5.0, 20),
            thread(9.6, end, 20, 1),
            rapid(11.0, end, 20),
            rapid(11.0, 5.0, 20),
            rapid(9.2, 5.0, 20),
            thread(9.2, end, 20, 2),
        ]
    };
    let s = part
        .shoulder(Pos::new(11.0, 5.0), &passes(-20.0), &threading, 0.4)
        .unwrap()
        .expect("a shoulder");
    assert!(near(s.z, -18.0) && (s.area - 10.0).abs() < 1e-6, "{s:?}");
    assert_eq!((s.line, s.pass), (20, 1));
    // The same thread ending at Z-17 meets nothing deeper than its passes.
    assert_eq!(
        part.shoulder(Pos::new(11.0, 5.0), &passes(-17.0), &threading, 0.4)
            .unwrap(),
        None
    );
    // The part itself is not cut by the question.
    assert!(near(part.radius_at(-10.0).unwrap().outer, 10.0));
}

#[test]
fn an_arc_without_a_centre_is_cut_as_its_chord() {
    let mut part = Part::new(&bar(40.0, 0.0, 60.0), TOL).unwrap();
    let tool = Tool::point(Body::Turning);
    // The chord from (10, 2) to (15, −3) (a 45° line), then along Ø30.
    part.cut_chord(Pos::new(10.0, 2.0), &feed(15.0, -3.0, 8), &tool)
        .unwrap();
    // At Z-1 the chord is at R10 + 3 = 13; a rapid down R14 enters it at Z2 − 4 = −2.
    assert!(near(part.radius_at(-1.0).unwrap().outer, 13.0), "{part:?}");
    let hit = part
        .rapid_hits(Pos::new(14.0, 2.0), Pos::new(14.0, -4.0))
        .unwrap();
    assert!(matches!(
        hit.origin,
        Origin::Cut(Cut {
            kind: CutKind::Chord,
            line: 8,
            ..
        })
    ));
}

#[test]
fn bad_stock_and_moves_are_refused() {
    let s = Stock {
        bore: Dim::given(50.0),
        ..bar(40.0, 0.0, 30.0)
    };
    assert!(Part::new(&s, TOL).is_err());
    assert!(Part::new(&bar(f64::NAN, 0.0, 30.0), TOL).is_err());
    assert!(Part::new(&bar(40.0, 0.0, 0.0), TOL).is_err());
    let mut part = Part::new(&bar(40.0, 0.0, 30.0), TOL).unwrap();
    let tool = Tool::point(Body::Turning);
    assert!(part
        .cut(Pos::new(0.0, 0.0), &feed(1e9, 0.0, 3), &tool)
        .is_err());
}

/// `moves` feed moves of a roughing pattern over and over: passes at 50 depths cycling, each
/// turning to one of seven lengths and facing out.
pub fn roughing(moves: usize) -> Vec<Motion> {
    let mut out = Vec::with_capacity(moves * 2);
    let mut i = 0;
    while out.len() < moves * 2 {
        let x = 19.0 - (i % 50) as f64 * 0.1;
        let z = -20.0 - (i % 7) as f64;
        out.extend([
            rapid(x, 2.0, 1),
            feed(x, z, 2),
            feed(x + 1.0, z, 3),
            rapid(x + 1.0, 2.0, 4),
        ]);
        i += 1;
    }
    out
}

#[test]
fn the_outline_stays_small_on_a_long_program() {
    // 100,000 feed moves. After the first cycle of 350 passes the profile is set (R14.1 to
    // Z-26, with the steps of the seven lengths at the 50 depths in between): later passes cut
    // air, and the outline never grows past the bound.
    // (A point tool keeps the test quick in a debug build; benches/part.rs times the same
    // program with a 0.4 nose, and the next test bounds a nose's outline.)
    let moves = roughing(100_000);
    let mut part = Part::new(&bar(40.0, 0.0, 60.0), TOL).unwrap();
    let tool = Tool::point(Body::Turning);
    let (mut at, mut most) = (Pos::new(21.0, 2.0), 0);
    let mut feeds = 0;
    for m in &moves {
        part.cut(at, m, &tool).unwrap();
        feeds += usize::from(m.kind != MotionKind::Rapid);
        most = most.max(part.vertex_count());
        at = m.to;
    }
    assert!(feeds >= 100_000);
    assert!(most <= BOUND_ROUGHING, "{most} vertices");
    eprintln!("most vertices, point tool: {most}");
}

#[test]
fn a_nose_keeps_the_outline_small_too() {
    // 2,000 feed moves of the same program with a 0.4 nose: the profile is set after the first
    // 350 passes (700 feed moves); the nose's rounds add vertices, within the bound.
    let moves = roughing(2_000);
    let mut part = Part::new(&bar(40.0, 0.0, 60.0), TOL).unwrap();
    let tool = Tool {
        nose_radius: 0.4,
        body: Body::Turning,
    };
    let (mut at, mut most, mut at_700) = (Pos::new(21.0, 2.0), 0, 0);
    for (i, m) in moves.iter().enumerate() {
        part.cut(at, m, &tool).unwrap();
        most = most.max(part.vertex_count());
        if i == 1400 {
            at_700 = part.vertex_count();
        }
        at = m.to;
    }
    eprintln!(
        "most vertices, nose r0.4: {most}, after the first cycle {at_700}, at the end {}",
        part.vertex_count()
    );
    assert!(most <= BOUND_NOSE, "{most} vertices");
    // After the first cycle the outline does not grow.
    assert!(part.vertex_count() <= at_700);
}

/// The most vertices [`a_nose_keeps_the_outline_small_too`] may reach.
const BOUND_NOSE: usize = 2_000;

/// The most vertices [`the_outline_stays_small_on_a_long_program`] may reach.
const BOUND_ROUGHING: usize = 200;

#[test]
fn an_internal_thread_and_a_retract_through_it() {
    // An M20x2.5 internal thread in a tube Ø40 × Ø17.294 bore (face Z0): passes at R9.0, R9.6
    // and the major R10 from Z5 (in front of the face) to Z-20 (line 30). The tool works in the
    // bore, so its body reaches toward the axis: the tube's outside stays Ø40.
    let stock = Stock {
        bore: Dim::given(17.294),
        ..bar(40.0, 0.0, 40.0)
    };
    let mut part = Part::new(&stock, TOL).unwrap();
    let tool = Tool::point(Body::Radial);
    let mut moves = Vec::new();
    for (n, x) in [(1, 9.0), (2, 9.6), (3, 10.0)] {
        moves.extend([
            rapid(x, 5.0, 30),
            thread(x, -20.0, 30, n),
            rapid(8.0, -20.0, 30),
            rapid(8.0, 5.0, 30),
        ]);
    }
    run(&mut part, Pos::new(8.0, 5.0), &moves, &tool);
    let r = part.radius_at(-10.0).unwrap();
    assert!(near(r.outer, 20.0) && near(r.bore.unwrap(), 10.0), "{r:?}");
    // Beyond the thread the bore is the stock's R8.647.
    assert!(near(part.radius_at(-25.0).unwrap().bore.unwrap(), 8.647));
    // G0 Z-10 then G0 X40 inside the bore: from (8, −10) out to (20, −10), into the thread's
    // root (its major diameter Ø20) at R10.
    let hit = part
        .rapid_hits(Pos::new(8.0, -10.0), Pos::new(20.0, -10.0))
        .unwrap();
    assert!(near(hit.at.x, 10.0));
    assert_eq!(
        hit.describe(Units::Mm),
        "the thread's root Ø20 at Z-10 (cut at line 30)"
    );
    // A pass that runs on into a step of the bore (Z-20 to Z-25 at R9.6 where the bore stays
    // R8.647) meets material more than its 0.4 depth toward the axis: 9.6 − 0.4 = 9.2 down to
    // 8.647 over Z-20..-25, 0.553 × 5 = 2.765 mm², first met at Z-20.
    let deeper = [rapid(9.6, 5.0, 31), thread(9.6, -25.0, 31, 1)];
    let s = part
        .shoulder(Pos::new(8.0, 5.0), &deeper, &tool, 0.4)
        .unwrap()
        .expect("a shoulder");
    assert!(near(s.z, -20.0) && (s.area - 2.765).abs() < 1e-6, "{s:?}");
}

/// `outline::surface_beyond` (one look at the edges) against the sorted crossings searched from
/// the start radius, as `Part::surface_beyond` did before: the same crossing and origin, ties
/// included. Rings on a coarse grid (many equal radii and vertices on the line), every edge
/// with its own origin so that a tie broken the other way would show.
mod surface_beyond_as_sorted {
    use super::outline::{self, Point, Ring};
    use super::*;
    use proptest::prelude::*;

    fn rings(raw: &[Vec<(i32, i32)>]) -> Vec<Ring> {
        let mut line = 0;
        raw.iter()
            .map(|pts| Ring {
                pts: pts.iter().map(|&(x, z)| Point::new(x, z)).collect(),
                origins: pts
                    .iter()
                    .map(|_| {
                        line += 1;
                        Origin::Cut(Cut {
                            line,
                            pass: 0,
                            kind: CutKind::Feed,
                        })
                    })
                    .collect(),
            })
            .collect()
    }

    fn sorted(rings: &[Ring], z: f64, from: f64, inward: bool) -> Option<(f64, Origin)> {
        let xs = outline::surfaces_at_z(rings, z);
        if inward {
            xs.into_iter().rev().find(|s| s.0 < from)
        } else {
            xs.into_iter().find(|s| s.0 > from)
        }
    }

    proptest! {
        #[test]
        fn the_same_crossing(
            raw in prop::collection::vec(
                prop::collection::vec((-4i32..=4, -4i32..=4).prop_map(|(x, z)| (x * 1000, z * 1000)), 3..9),
                1..4,
            ),
            zk in -5i32..=5,
            zfrac in prop::sample::select(vec![0.0, 0.5, 0.25]),
            fk in -5i32..=5,
            inward in any::<bool>(),
        ) {
            let rings = rings(&raw);
            let z = (f64::from(zk * 1000) + zfrac * 1000.0) * GRID;
            let from = f64::from(fk * 1000) * GRID;
            let two = sorted(&rings, z, from, inward).map(|s| (s.0.to_bits(), s.1));
            // Edge by edge, and through the bands (which must pick the same edges).
            let one = outline::surface_beyond(&rings, None, z, from, inward);
            prop_assert_eq!(one.map(|s| (s.0.to_bits(), s.1)), two);
            let slabs = outline::Slabs::new(&rings).expect("a small outline");
            let banded = outline::surface_beyond(&rings, Some(&slabs), z, from, inward);
            prop_assert_eq!(banded.map(|s| (s.0.to_bits(), s.1)), two);
        }
    }

    /// Two edges crossing at the same radius: outward the first edge's origin, inward the last's
    /// (the sorted order is stable). Two squares side by side sharing the edge x = 1000 (grid
    /// steps): at z = 500 the crossings are x = 0, 1000 (first square), 1000, 2000 (second).
    #[test]
    fn ties_go_as_the_sorted_search_went() {
        let rings = rings(&[
            vec![(0, 0), (1000, 0), (1000, 1000), (0, 1000)],
            vec![(1000, 0), (2000, 0), (2000, 1000), (1000, 1000)],
        ]);
        let z = 500.0 * GRID;
        for (from, inward) in [(500.0, false), (1500.0, true)] {
            let from = from * GRID;
            let one = outline::surface_beyond(&rings, None, z, from, inward);
            assert_eq!(one, sorted(&rings, z, from, inward));
            assert!((one.unwrap().0 - 1000.0 * GRID).abs() < 1e-12);
        }
        // Outward from x = 500 the first square's right edge (its 2nd edge, line 2); inward
        // from x = 1500 the second square's left edge (its 4th edge, line 8).
        let line = |s: Option<(f64, Origin)>| match s.unwrap().1 {
            Origin::Cut(c) => c.line,
            _ => 0,
        };
        assert_eq!(
            line(outline::surface_beyond(
                &rings,
                None,
                z,
                500.0 * GRID,
                false
            )),
            2
        );
        assert_eq!(
            line(outline::surface_beyond(
                &rings,
                None,
                z,
                1500.0 * GRID,
                true
            )),
            8
        );
    }
}

/// The greatest of a linear function over the outline in a band of Z: on the faced and turned
/// bar, the radius alone is R15 over Z-5..-15 (the turned diameter), R20 once the band takes in
/// the shoulder at Z-20; measured from a taper rising 0.1 per mm toward -Z (R = 14 + 0.1·(−z)),
/// the turned diameter stands highest at the band's +Z end: 15 − (14 + 0.5) = 0.5 at Z-5.
#[test]
fn the_greatest_in_a_band_is_at_an_edges_end() {
    let part = faced_and_turned();
    let radius = |p: Pos, _: Origin| p.x;
    assert!(near(
        part.greatest_in_band(-15.0, -5.0, radius).unwrap(),
        15.0
    ));
    assert!(near(
        part.greatest_in_band(-25.0, -5.0, radius).unwrap(),
        20.0
    ));
    let over_taper = |p: Pos, _: Origin| p.x - (14.0 - 0.1 * p.z);
    assert!(near(
        part.greatest_in_band(-15.0, -5.0, over_taper).unwrap(),
        0.5
    ));
    // Only the edges the function takes: the turned surface's (line 4) — the same 0.5.
    let turned = |p: Pos, o: Origin| match o {
        Origin::Cut(c) if c.line == 4 => p.x - (14.0 - 0.1 * p.z),
        _ => f64::NEG_INFINITY,
    };
    assert!(near(
        part.greatest_in_band(-15.0, -5.0, turned).unwrap(),
        0.5
    ));
    // Beyond the bar's end (Z-59): no material.
    assert!(part.greatest_in_band(-80.0, -70.0, radius).is_none());
}
