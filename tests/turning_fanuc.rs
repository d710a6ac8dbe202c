//! The Fanuc family's turning cycles (Fanuc systems A/B/C, FS15 format, GSK 980TDi, Haas): read
//! into the machine-neutral model, streamed through the program (a contour's blocks read once,
//! not run as plain moves), expanded into plain moves and read back.

use threadcut::machine::Machine;
use threadcut::program::{self, Event};
use threadcut::turning::{Along, Cycle, Segment, Shape, TurningJob};
use threadcut::units::Pos;

/// The program's moves as `expand --format jsonl` lists them: (kind, x, z) in program units, X a
/// radius.
fn jsonl(src: &str, machine: &Machine) -> Result<Vec<(String, f64, f64)>, String> {
    let mut out = Vec::new();
    program::expand_jsonl(src.as_bytes(), &mut out, machine).map_err(|e| e.to_string())?;
    Ok(String::from_utf8(out)
        .unwrap()
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            (
                v["kind"].as_str().unwrap().to_string(),
                v["x"].as_f64().unwrap(),
                v["z"].as_f64().unwrap(),
            )
        })
        .collect())
}

/// At the output's resolution (0.001 mm, 0.0001 inch and tighter): the same value.
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 5e-5
}

fn assert_moves(got: &[(String, f64, f64)], want: &[(&str, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            g.0 == w.0 && same(g.1, w.1) && same(g.2, w.2),
            "{g:?} ≠ {w:?} in {got:?}"
        );
    }
}

fn machine(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

/// Fanuc in G-code system C (system B's profile with its system changed).
fn fanuc_c() -> Machine {
    let text = threadcut::machine::BUILT_IN
        .iter()
        .find(|(n, _)| *n == "fanuc-b")
        .unwrap()
        .1;
    assert!(text.contains("gcode_system = \"b\""), "{text}");
    Machine::from_toml(&text.replace("gcode_system = \"b\"", "gcode_system = \"c\"")).unwrap()
}

/// Every turning job of a program, and the lines streamed as plain blocks.
fn turning(src: &str, machine: &Machine) -> Result<(Vec<TurningJob>, Vec<u32>), String> {
    let mut jobs = Vec::new();
    let mut plain = Vec::new();
    program::run(src.as_bytes(), machine, |_, ev| {
        match ev {
            Event::Turning { job: Some(job), .. } => jobs.push(*job),
            Event::Plain { line, .. } => plain.push(line.number),
            _ => {}
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?;
    Ok((jobs, plain))
}

fn error(src: &str, machine: &Machine) -> String {
    match program::run(src.as_bytes(), machine, |_, _| Ok(())) {
        Err(program::Error::Input(d)) => format!("{}:{} {}", d.span.line, d.span.column, d.message),
        other => panic!("no error: {other:?}"),
    }
}

// --- Box cycles ---------------------------------------------------------------------------------

#[test]
fn g90_with_a_taper_and_a_repeat_in_system_a() {
    // Start Ø50 Z2 (r25). G90 X40. Z-30. R-2.: the cut starts at r20 + (−2) = 18 at Z2, runs to
    // r20 Z-30, out to r25, back to Z2. `X36.` repeats it to r18 with the same Z and R: the cut
    // starts at r16.
    let src = "G21\nG0 X50. Z2.\nG90 X40. Z-30. R-2. F0.2\nX36.\nG0 X100. Z100.\nM30\n";
    let got = jsonl(src, &machine("fanuc")).unwrap();
    assert_moves(
        &got,
        &[
            ("rapid", 25.0, 2.0),
            ("rapid", 18.0, 2.0),
            ("feed", 20.0, -30.0),
            ("feed", 25.0, -30.0),
            ("rapid", 25.0, 2.0),
            ("rapid", 16.0, 2.0),
            ("feed", 18.0, -30.0),
            ("feed", 25.0, -30.0),
            ("rapid", 25.0, 2.0),
            ("rapid", 50.0, 100.0),
        ],
    );
}

#[test]
fn a_facing_box_cycle_in_inch_in_system_b() {
    // System B: G79 faces (G94 in A). Inch: start Ø2. Z0.1 (r1), end Ø0.5 (r0.25) Z-0.1: in Z to
    // -0.1, across to r0.25, out to Z0.1, back to r1. `Z-0.2` repeats at Z-0.2.
    let src = "G20\nG0 X2. Z0.1\nG79 X0.5 Z-0.1 F0.004\nZ-0.2\nG0 X3.\n";
    let got = jsonl(src, &machine("fanuc-b")).unwrap();
    assert_moves(
        &got,
        &[
            ("rapid", 1.0, 0.1),
            ("rapid", 1.0, -0.1),
            ("feed", 0.25, -0.1),
            ("feed", 0.25, 0.1),
            ("rapid", 1.0, 0.1),
            ("rapid", 1.0, -0.2),
            ("feed", 0.25, -0.2),
            ("feed", 0.25, 0.1),
            ("rapid", 1.0, 0.1),
            ("rapid", 1.5, 0.1),
        ],
    );
    // In system A, G79 is no code of the control.
    assert!(error(src, &machine("fanuc")).contains("G79"));
}

#[test]
fn an_internal_box_cycle_in_system_c() {
    // System C: G20 is the turning box cycle, G71 millimetre input. A bore: start Ø20 Z2 (r10),
    // end Ø30 (r15) Z-20 — the cut runs outward, the return inward.
    let src = "G71\nG0 X20. Z2.\nG20 U10. W-22. F0.15\n";
    let got = jsonl(src, &fanuc_c()).unwrap();
    assert_moves(
        &got,
        &[
            ("rapid", 10.0, 2.0),
            ("rapid", 15.0, 2.0),
            ("feed", 15.0, -20.0),
            ("feed", 10.0, -20.0),
            ("rapid", 10.0, 2.0),
        ],
    );
}

#[test]
fn a_taper_beyond_the_start_point_is_refused() {
    // Start r25, end r20: R+6 would start the cut at r26, outside the start point.
    let e = error("G0 X50. Z2.\nG90 X40. Z-30. R6. F0.2\n", &machine("fanuc"));
    assert!(e.starts_with("2:1 "), "{e}");
    assert!(e.contains("R6"), "{e}");
}

#[test]
fn haas_and_fs15_take_the_taper_in_i() {
    // Haas G90 … I: the same cut as Fanuc's R.
    let src = "G0 X50. Z2.\nG90 X40. Z-30. I-2. F0.2\n";
    for m in ["haas", "fanuc15"] {
        let got = jsonl(src, &machine(m)).unwrap();
        assert!(same(got[1].1, 18.0), "{m}: {got:?}");
    }
    // … and Fanuc's R is not a word of theirs.
    let e = error("G0 X50. Z2.\nG90 X40. Z-30. R-2. F0.2\n", &machine("haas"));
    assert!(e.contains("R is not a word"), "{e}");
}

#[test]
fn gsk_reads_the_box_cycles_as_fanuc_does() {
    let src = "G0 X60. Z2.\nG94 X20. Z-3. F0.2\n";
    let got = jsonl(src, &machine("gsk980")).unwrap();
    assert_moves(
        &got,
        &[
            ("rapid", 30.0, 2.0),
            ("rapid", 30.0, -3.0),
            ("feed", 10.0, -3.0),
            ("feed", 10.0, 2.0),
            ("rapid", 30.0, 2.0),
        ],
    );
}

// --- Peck cycles --------------------------------------------------------------------------------

#[test]
fn g74_drills_in_pecks() {
    // e = 0.5; Q4000: 4 mm (least input increments, 0.001 mm). From Z1 to Z-10: feeds to -3, -7,
    // then -10, a retract of 0.5 after each but the last; back to Z1.
    let src = "G0 X0. Z1.\nG74 R0.5\nG74 Z-10. Q4000 F0.1\n";
    let got = jsonl(src, &machine("fanuc")).unwrap();
    assert_moves(
        &got,
        &[
            ("rapid", 0.0, 1.0),
            ("feed", 0.0, -3.0),
            ("rapid", 0.0, -2.5),
            ("feed", 0.0, -7.0),
            ("rapid", 0.0, -6.5),
            ("feed", 0.0, -10.0),
            ("rapid", 0.0, 1.0),
        ],
    );
}

#[test]
fn g75_grooves_in_columns() {
    // e = 1; from Ø50 (r25) Z-10 to Ø30 (r15) Z-14; P4000: pecks of 4 mm in X (r21, r17, r15),
    // Q3000: shifts of 3 mm in Z (-13, then -14).
    let src = "G0 X50. Z-10.\nG75 R1.\nG75 X30. Z-14. P4000 Q3000 F0.05\n";
    let got = jsonl(src, &machine("fanuc")).unwrap();
    let mut want = vec![("rapid", 25.0, -10.0)];
    for (i, z) in [-10.0, -13.0, -14.0].into_iter().enumerate() {
        if i > 0 {
            want.push(("rapid", 25.0, z));
        }
        want.extend([
            ("feed", 21.0, z),
            ("rapid", 22.0, z),
            ("feed", 17.0, z),
            ("rapid", 18.0, z),
            ("feed", 15.0, z),
            ("rapid", 25.0, z),
        ]);
    }
    want.push(("rapid", 25.0, -10.0));
    assert_moves(&got, &want);
}

#[test]
fn g74_in_inch_with_a_relief_toward_the_start() {
    // Inch, IS-B: Q and P in 0.0001 inch. From Ø1. (r0.5) Z0.05 to Ø0.8 (r0.4) Z-0.1: P1000 shifts
    // 0.1 inch (one shift), Q1000 pecks 0.1 inch (to -0.05, then -0.1); R0.01 relief back toward
    // the start's X (+), e 0.02.
    let src = "G20\nG0 X1. Z0.05\nG74 R0.02\nG74 X0.8 Z-0.1 P1000 Q1000 R0.01 F0.002\n";
    let got = jsonl(src, &machine("fanuc")).unwrap();
    let mut want = vec![("rapid", 0.5, 0.05)];
    for (i, x) in [0.5, 0.4].into_iter().enumerate() {
        if i > 0 {
            want.push(("rapid", x, 0.05));
        }
        want.extend([
            ("feed", x, -0.05),
            ("rapid", x, -0.03),
            ("feed", x, -0.1),
            ("rapid", x + 0.01, -0.1),
            ("rapid", x + 0.01, 0.05),
        ]);
    }
    want.push(("rapid", 0.5, 0.05));
    assert_moves(&got, &want);
}

#[test]
fn peck_cycle_alarms() {
    let f = machine("fanuc");
    // X moves but P(Δi), the shift, is missing.
    let e = error("G0 X50. Z1.\nG74 R0.5\nG74 X40. Z-10. Q2000 F0.1\n", &f);
    assert!(
        e.starts_with("3:1 ") && e.contains("PS0062") && e.contains("P(Δi)"),
        "{e}"
    );
    // A negative relief where the shift gives its direction.
    let e = error(
        "G0 X50. Z1.\nG74 R0.5\nG74 X40. Z-10. P2000 Q2000 R-0.1 F0.1\n",
        &f,
    );
    assert!(e.contains("PS0062") && e.contains("R(Δd)"), "{e}");
    // Q with a decimal point.
    let e = error("G0 X0. Z1.\nG74 R0.5\nG74 Z-10. Q4. F0.1\n", &f);
    assert!(e.contains("without a decimal point"), "{e}");
    // No retract e at all: the first block is missing.
    let e = error("G0 X0. Z1.\nG74 Z-10. Q4000 F0.1\n", &f);
    assert!(e.starts_with("2:1 ") && e.contains("R(e)"), "{e}");
}

// --- Cycles with a contour ----------------------------------------------------------------------

const G71: &str = "\
G0 X50. Z2.
G71 U2. R0.5
G71 P10 Q20 U0.4 W0.1 F0.25
N10 G0 X20.
G1 Z-10. F0.1
X30. Z-20.
G2 X40. Z-25. R5.
N20 G1 X50.
G70 P10 Q20
G0 X100. Z100.
M30
";

/// G71's contour: from the start point r25 Z2, N10 to r10, along to Z-10, a cone to r15 Z-20,
/// an arc R5 to r20 Z-25 about (r20, Z-20) — the chord from (15,−20) to (20,−25) is 5√2, its
/// half 3.536, the centre 3.536 to the right of it (clockwise): (20, −20), 5 from both ends —,
/// out to r25.
fn g71_contour() -> Vec<Segment> {
    let line = |x, z, l| Segment {
        to: Pos::new(x, z),
        shape: Shape::Line,
        line: l,
    };
    vec![
        line(10.0, 2.0, 4),
        line(10.0, -10.0, 5),
        line(15.0, -20.0, 6),
        Segment {
            to: Pos::new(20.0, -25.0),
            shape: Shape::Arc {
                centre: Pos::new(20.0, -20.0),
                clockwise: true,
            },
            line: 7,
        },
        line(25.0, -25.0, 8),
    ]
}

fn assert_contour(got: &[Segment], want: &[Segment]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.line, w.line);
        assert!(
            same(g.to.x, w.to.x) && same(g.to.z, w.to.z),
            "{g:?} ≠ {w:?}"
        );
        match (g.shape, w.shape) {
            (Shape::Line, Shape::Line) => {}
            (
                Shape::Arc {
                    centre: a,
                    clockwise: ca,
                },
                Shape::Arc {
                    centre: b,
                    clockwise: cb,
                },
            ) => assert!(
                ca == cb && same(a.x, b.x) && same(a.z, b.z),
                "{g:?} ≠ {w:?}"
            ),
            _ => panic!("{g:?} ≠ {w:?}"),
        }
    }
}

#[test]
fn g71_reads_its_contour_once_and_the_program_goes_on_after_it() {
    let (jobs, plain) = turning(G71, &machine("fanuc")).unwrap();
    assert_eq!(jobs.len(), 2, "{jobs:?}");
    let Cycle::Rough(r) = &jobs[0].cycle else {
        panic!("{jobs:?}")
    };
    assert_eq!(jobs[0].line, 3);
    assert_eq!(r.along, Along::Z);
    assert_eq!(r.start, Pos::new(25.0, 2.0));
    assert!(same(r.depth, 2.0) && same(r.retract, 0.5));
    // U0.4 is a diameter: 0.2 of radius.
    assert!(same(r.allowance_x, 0.2) && same(r.allowance_z, 0.1));
    // N10 names X alone: type I.
    assert!(!r.pockets);
    assert_eq!(r.contour.start, Pos::new(25.0, 2.0));
    assert_contour(&r.contour.segments, &g71_contour());
    // G70 P10 Q20 finishes along the same blocks, from where G71 left the tool.
    let Cycle::Finish(f) = &jobs[1].cycle else {
        panic!("{jobs:?}")
    };
    assert_eq!(jobs[1].line, 9);
    assert_eq!(f.start, Pos::new(25.0, 2.0));
    assert_contour(&f.contour.segments, &g71_contour());
    // The contour's blocks (lines 4–8) are not run as plain moves; the program goes on at line 10.
    assert_eq!(plain, vec![1, 10, 11], "{plain:?}");
}

#[test]
fn type_ii_when_the_first_block_names_both_axes() {
    let src = G71.replace("N10 G0 X20.", "N10 G0 X20. W0");
    let (jobs, _) = turning(&src, &machine("fanuc")).unwrap();
    let Cycle::Rough(r) = &jobs[0].cycle else {
        panic!()
    };
    assert!(r.pockets);
}

#[test]
fn g72_g73_and_the_systems_numbers() {
    // G72 W(Δd) R(e): facing; its contour from the start point.
    let src = "G0 X52. Z2.\nG72 W1.5 R0.3\nG72 P1 Q2 U0.2 W0.05 F0.2\nN1 G0 Z-5.\nN2 G1 X10. Z0.\n";
    let (jobs, _) = turning(src, &machine("fanuc")).unwrap();
    let Cycle::Rough(r) = &jobs[0].cycle else {
        panic!()
    };
    assert_eq!(r.along, Along::X);
    assert!(same(r.depth, 1.5) && same(r.retract, 0.3) && same(r.allowance_x, 0.1));
    assert_eq!(r.contour.segments.len(), 2);
    assert!(same(r.contour.segments[1].to.x, 5.0));
    // G73 U(Δi) W(Δk) R(d): Δi is a radius (U3. is 3 mm, not 1.5).
    let src = "G0 X60. Z5.\nG73 U3. W1. R4\nG73 P5 Q6 U0.4 W0.1 F0.2\nN5 G1 X30. Z0.\nN6 Z-20.\n";
    let (jobs, _) = turning(src, &machine("fanuc")).unwrap();
    let Cycle::Pattern(p) = &jobs[0].cycle else {
        panic!()
    };
    assert!(same(p.relief_x, 3.0) && same(p.relief_z, 1.0) && p.passes == 4);
    assert!(same(p.allowance_x, 0.2) && same(p.allowance_z, 0.1));
    assert_eq!(p.contour.segments.len(), 2);
    // System C numbers them G73 (stock removal in turning) and G72 (finishing); G71 is metric.
    let src = "G71\n".to_string() + &G71.replace("G71", "G73").replace("G70 P10", "G72 P10");
    let (jobs, _) = turning(&src, &fanuc_c()).unwrap();
    assert!(matches!(jobs[0].cycle, Cycle::Rough(_)));
    assert!(matches!(jobs[1].cycle, Cycle::Finish(_)));
    // System B numbers them as A.
    let (jobs, _) = turning(G71, &machine("fanuc-b")).unwrap();
    assert_eq!(jobs.len(), 2);
    // GSK 980TDi writes them as Fanuc does.
    let (jobs, _) = turning(G71, &machine("gsk980")).unwrap();
    assert_eq!(jobs.len(), 2);
}

#[test]
fn a_contour_in_inch_with_incremental_words_and_an_i_k_arc() {
    // Inch, U/W incremental: from r1. Z0.1, N10 to Ø0.8 (r0.4), W-0.6 to Z-0.5, a G3 quarter arc
    // about (I0.2, K0 from its start) = (r0.6, Z-0.5) to r0.6 Z-0.7… no: U0.4 W-0.2 → r0.6 Z-0.7;
    // its ends are 0.2 from the centre (0.6, −0.5): (0.4,−0.5) and (0.6,−0.7). In mm: ×25.4.
    let src = "G20\nG0 X2. Z0.1\nG71 U0.05 R0.01\nG71 P10 Q20 U0.02 W0.005 F0.01\nN10 G0 X0.8\nG1 W-0.6\nG3 U0.4 W-0.2 I0.2 K0.\nN20 G1 X2.\n";
    let (jobs, _) = turning(src, &machine("fanuc")).unwrap();
    let Cycle::Rough(r) = &jobs[0].cycle else {
        panic!()
    };
    let mm = |v: f64| v * 25.4;
    assert!(same(r.depth, mm(0.05)) && same(r.allowance_x, mm(0.01)));
    let s = &r.contour.segments;
    assert_eq!(s.len(), 4);
    assert!(same(s[1].to.x, mm(0.4)) && same(s[1].to.z, mm(-0.5)));
    match s[2].shape {
        Shape::Arc { centre, clockwise } => {
            assert!(!clockwise);
            assert!(
                same(centre.x, mm(0.6)) && same(centre.z, mm(-0.5)),
                "{centre:?}"
            );
        }
        _ => panic!("{s:?}"),
    }
}

#[test]
fn contour_alarms_at_their_lines() {
    let f = machine("fanuc");
    // No block N20: PS0063 at the G71 block.
    let e = error(&G71.replace("N20 G1 X50.\nG70 P10 Q20\n", "G1 X50.\n"), &f);
    assert!(
        e.starts_with("3:1 ") && e.contains("PS0063") && e.contains("N20"),
        "{e}"
    );
    // … and where a cycle's block comes before it, that block is PS0066 (the control reads the
    // blocks after N10 as the contour's).
    let e = error(&G71.replace("N20 G1 X50.", "G1 X50."), &f);
    assert!(e.starts_with("9:1 ") && e.contains("PS0066"), "{e}");
    // No block N10 at all.
    let e = error(&G71.replace("N10 G0", "G0"), &f);
    assert!(
        e.starts_with("3:1 ") && e.contains("PS0063") && e.contains("N10"),
        "{e}"
    );
    // Q missing: PS0061.
    let e = error(&G71.replace("G71 P10 Q20", "G71 P10"), &f);
    assert!(e.starts_with("3:1 ") && e.contains("PS0061"), "{e}");
    // A depth of cut of 0: PS0062 at the word.
    let e = error(&G71.replace("U2. R0.5", "U0 R0.5"), &f);
    assert!(e.starts_with("2:5 ") && e.contains("PS0062"), "{e}");
    // The first block of the contour is an arc: PS0065.
    let e = error(&G71.replace("N10 G0 X20.", "N10 G2 X20. Z2. R20."), &f);
    assert!(e.starts_with("4:1 ") && e.contains("PS0065"), "{e}");
    // A thread move in the contour: PS0066 at the code.
    let e = error(&G71.replace("G1 Z-10. F0.1", "G32 Z-10. F1."), &f);
    assert!(e.starts_with("5:1 ") && e.contains("PS0066"), "{e}");
    // An arc whose radius cannot reach its end: PS0020.
    let e = error(&G71.replace("R5.", "R3."), &f);
    assert!(e.starts_with("7:1 ") && e.contains("PS0020"), "{e}");
    // G70 with a contour no cycle read: PS0063.
    let e = error("G0 X50. Z2.\nG70 P10 Q20\n", &f);
    assert!(e.starts_with("2:1 ") && e.contains("PS0063"), "{e}");
    // P with a decimal point is no sequence number.
    let e = error(&G71.replace("P10 Q20 U0.4", "P10. Q20 U0.4"), &f);
    assert!(
        e.starts_with("3:5 ") && e.contains("sequence number"),
        "{e}"
    );
    // The first block never written: the depth of cut is unknown.
    let e = error(&G71.replace("G71 U2. R0.5\n", ""), &f);
    assert!(
        e.starts_with("2:1 ") && e.contains("depth of cut Δd"),
        "{e}"
    );
}

#[test]
fn a_contour_without_its_end_stops_at_the_limit() {
    let mut src =
        String::from("G0 X50. Z2.\nG71 U2. R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X20.\n");
    for _ in 0..10_001 {
        src.push_str("G1 Z-1.\n");
    }
    src.push_str("N20 X50.\n");
    let e = error(&src, &machine("fanuc"));
    assert!(
        e.starts_with("3:1 ") && e.contains("N10") && e.contains("10000"),
        "{e}"
    );
}

#[test]
fn a_cycle_with_a_contour_is_no_thread() {
    // `passes` and `check` see threads only: the G71/G70 and a G90 are none.
    let src = "G0 X50. Z2.\nG90 X40. Z-30. F0.2\n".to_string() + G71;
    let mut threads = 0;
    threadcut::threads::each_gcode(src.as_bytes(), &machine("fanuc"), None, |_| {
        threads += 1;
        Ok(())
    })
    .unwrap();
    assert_eq!(threads, 0);
}

// --- Expand and read back -----------------------------------------------------------------------

#[test]
fn expanded_box_and_peck_cycles_read_back_to_the_same_moves() {
    let cases = [
        (
            "fanuc",
            "G21\nG0 X50. Z2.\nG90 X40. Z-30. R-2. F0.2\nX36.\nG0 X100. Z100.\nM30\n",
        ),
        (
            "fanuc",
            "G0 X50. Z-10.\nG75 R1.\nG75 X30. Z-14. P4000 Q3000 F0.05\nG1 X60.\n",
        ),
        (
            "fanuc-b",
            "G20\nG0 X2. Z0.1\nG79 X0.5 Z-0.1 F0.004\nZ-0.2\nG0 X3.\n",
        ),
        ("gsk980", "G0 X60. Z2.\nG94 X20. Z-3. R-1. F0.2\n"),
        ("haas", "G0 X50. Z2.\nG90 X40. Z-30. I-2. F0.2\n"),
    ];
    for (name, src) in cases {
        let m = machine(name);
        let mut out = Vec::new();
        program::expand_gcode(src.as_bytes(), &mut out, &m).unwrap();
        let text = String::from_utf8(out).unwrap();
        assert!(!text.contains("G90 X") && !text.contains("G75 X"), "{text}");
        assert_eq!(
            jsonl(&text, &m).unwrap(),
            jsonl(src, &m).unwrap(),
            "{name}:\n{text}"
        );
    }
}

#[test]
fn expand_writes_a_contour_s_blocks_as_comments() {
    // The control does not run the contour's blocks where they stand: expand writes them as
    // comments, then the cycles' moves; the expanded program moves as the original does.
    let m = machine("fanuc");
    let mut out = Vec::new();
    program::expand_gcode(G71.as_bytes(), &mut out, &m).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains("(threadcut: not run here: G71 P10 Q20"),
        "{text}"
    );
    for block in ["N10 G0 X20.", "X30. Z-20.", "N20 G1 X50."] {
        assert!(
            text.contains(&format!("(threadcut: not run here: {block})")),
            "{text}"
        );
        assert!(
            text.lines().all(|l| l.trim() != block),
            "{block} runs:\n{text}"
        );
    }
    // The same moves, at the program's resolution (X on diameter to 0.001: a radius within
    // 0.0005; Z within 0.0005).
    let (back, cycle) = (jsonl(&text, &m).unwrap(), jsonl(G71, &m).unwrap());
    assert_eq!(back.len(), cycle.len(), "{text}");
    for (b, c) in back.iter().zip(&cycle) {
        assert!(
            b.0 == c.0 && (b.1 - c.1).abs() <= 0.000_500_1 && (b.2 - c.2).abs() <= 0.000_500_1,
            "{b:?} vs {c:?}"
        );
    }
}

#[test]
fn arcs_written_as_plain_moves_read_back_as_the_same_contour() {
    use threadcut::toolpath::{Motion, MotionKind, Toolpath};
    let m = machine("fanuc");
    let mv = |kind, x, z| Motion {
        kind,
        to: Pos::new(x, z),
        pass: 1,
        line: 1,
    };
    let arc = |x, z, cx, cz, clockwise| {
        mv(
            MotionKind::Arc {
                centre: Pos::new(cx, cz),
                clockwise,
            },
            x,
            z,
        )
    };
    // A contour with a fillet, a convex and a concave arc, in mm and in inch.
    let motions = vec![
        mv(MotionKind::Feed, 10.0, 2.0),
        mv(MotionKind::Feed, 10.0, -10.0),
        arc(12.0, -12.0, 12.0, -10.0, false),
        arc(17.0, -17.0, 17.0, -12.0, true),
        mv(MotionKind::Feed, 25.0, -17.0),
    ];
    for units in [threadcut::units::Units::Mm, threadcut::units::Units::Inch] {
        let path = Toolpath {
            start: Pos::new(25.4, 2.54),
            motions: motions.clone(),
        };
        let format = threadcut::dialect::open(&m).unwrap().format();
        let mut out = Vec::new();
        threadcut::post::write_moves(&mut out, &format, units, &path).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let n = lines.len();
        let mut src = String::from(if units == threadcut::units::Units::Mm {
            "G21\nG0 X50.8 Z2.54\nG71 U1. R0.5\nG71 P10 Q20 U0. W0. F0.2\n"
        } else {
            "G20\nG0 X2. Z0.1\nG71 U0.04 R0.02\nG71 P10 Q20 U0. W0. F0.008\n"
        });
        for (i, l) in lines.iter().enumerate() {
            let n_word = if i == 0 {
                "N10 "
            } else if i == n - 1 {
                "N20 "
            } else {
                ""
            };
            src.push_str(&format!("{n_word}{l}\n"));
        }
        let (jobs, _) = turning(&src, &m).unwrap();
        let Cycle::Rough(r) = &jobs[0].cycle else {
            panic!()
        };
        // Written at 0.001 mm / 0.0001 inch: the same contour within one increment.
        let tol = if units == threadcut::units::Units::Mm {
            0.0011
        } else {
            0.0026
        };
        assert_eq!(r.contour.segments.len(), motions.len(), "{src}");
        for (s, m) in r.contour.segments.iter().zip(&motions) {
            assert!(s.to.distance(m.to) < tol, "{s:?} ≠ {m:?}\n{src}");
            match (s.shape, m.kind) {
                (Shape::Line, MotionKind::Feed) => {}
                (
                    Shape::Arc { centre, clockwise },
                    MotionKind::Arc {
                        centre: c,
                        clockwise: cw,
                    },
                ) => {
                    assert_eq!(clockwise, cw);
                    assert!(centre.distance(c) < tol, "{centre:?} ≠ {c:?}\n{src}");
                }
                _ => panic!("{s:?} ≠ {m:?}"),
            }
        }
    }
}

#[test]
fn the_one_block_stock_removal_of_fs15_is_refused_at_its_d_word() {
    // FS15's `G71 P Q U W D F`: its retract is a machine parameter no profile states. (Haas's,
    // with Setting 73 in its profile, is read: tests/haas_turning.rs.)
    let src = "G0 X2. Z0.1\nG71 P1 Q2 U0.02 W0.005 D0.05 F0.01\nN1 G0 X1.\nN2 G1 Z-1.\n";
    let e = error(src, &machine("fanuc15"));
    assert!(
        e.starts_with("2:24 ") && e.contains("one-block G71"),
        "fanuc15: {e}"
    );
    // Fanuc's standard format reads the two blocks; there D is no word of G71.
    let e = error(src, &machine("fanuc"));
    assert!(e.contains("D is not a word"), "{e}");
}

/// GSK's first G71/G72/G73 block takes F, S and T ("G71 U(Δd) R(e) F S T;" in the GSK 980TDi
/// and 988T manuals); Fanuc's first block does not (its F S T are on the second).
#[test]
fn gsk_takes_f_s_t_on_the_first_block_fanuc_does_not() {
    let gsk = "G0 X22. Z2.\nG71 U1. R0.5 F0.2 S900 T0101\nG71 P10 Q20 U0.3 W0.05\n\
               N10 G0 X12.8\nG1 Z0. F0.1\nX15.8 Z-1.5\nZ-25.\nN20 X22.\nG0 X100. Z100.\n";
    let (jobs, _) = turning(gsk, &machine("gsk980")).unwrap();
    assert_eq!(jobs.len(), 1);
    match &jobs[0].cycle {
        Cycle::Rough(r) => {
            // U1. is the depth of cut (radius), R0.5 the retract; U0.3 the allowance (diameter).
            assert!(same(r.depth, 1.0) && same(r.retract, 0.5));
            assert!(same(r.allowance_x, 0.15) && same(r.allowance_z, 0.05));
            assert_eq!(r.contour.segments.len(), 5);
        }
        other => panic!("{other:?}"),
    }
    let e = error(
        "G0 X22. Z2.\nG71 U1. R0.5 F0.2\nG71 P10 Q20 U0.3 W0.05\nN10 G0 X12.8\nN20 X22.\n",
        &machine("fanuc"),
    );
    assert!(e.contains("F is not a word of the first G71 block"), "{e}");
}
