//! Hand-computed moves for each construct, and each alarm at its line and column.

use super::*;
use crate::mill::motion::{Comp, Feed, MillKind, Plane, Rotation};

#[derive(Default)]
struct Collect {
    moves: Vec<MillMotion>,
    taps: Vec<TapCycle>,
}

impl Sink for Collect {
    fn motion(&mut self, m: &MillMotion, _work: u16) -> Result<(), Diagnostic> {
        self.moves.push(*m);
        Ok(())
    }
    fn tap(&mut self, t: &TapCycle) -> Result<(), Diagnostic> {
        self.taps.push(*t);
        Ok(())
    }
}

fn read(profile: &str, src: &str) -> Result<Collect, Diagnostic> {
    let p = MillProfile::built_in(profile).unwrap();
    let mut c = Collect::default();
    run(src.as_bytes(), &p, &Options::default(), &mut c)?;
    Ok(c)
}

fn ok(profile: &str, src: &str) -> Collect {
    read(profile, src).unwrap_or_else(|e| panic!("{e:?}"))
}

/// Within the output resolution (a micrometre).
fn near(a: [f64; 3], b: [f64; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-6)
}

fn assert_at(m: &MillMotion, to: [f64; 3]) {
    assert!(
        near(m.to, to),
        "line {}: {:?} is not {:?}",
        m.line,
        m.to,
        to
    );
}

fn centre(m: &MillMotion) -> [f64; 3] {
    match m.kind {
        MillKind::Arc { centre, .. } => centre,
        k => panic!("not an arc: {k:?}"),
    }
}

fn err(profile: &str, src: &str) -> Diagnostic {
    match read(profile, src) {
        Ok(_) => panic!("no error"),
        Err(e) => e,
    }
}

#[test]
fn incremental_centres_and_r_arcs_of_both_signs() {
    let c = ok(
        "fanuc-mill",
        "G21 G90 G17\nG0 X10. Y0. Z1.\nG1 Z-1. F100.\n\
         G3 X0. Y10. I-10. J0.\n\
         G2 X10. Y0. R10.\n\
         G2 X0. Y10. R-10.\n",
    );
    let m = &c.moves;
    // Line 4: from (10, 0) with I-10 J0 the centre is (10 − 10, 0) = the origin.
    assert!(near(centre(&m[2]), [0.0, 0.0, -1.0]));
    assert_at(&m[2], [0.0, 10.0, -1.0]);
    // Line 5: from (0, 10) to (10, 0), R10, clockwise, shorter arc: chord (10, −10), half
    // 7.0711, h = √(100 − 50) = 7.0711; the right of the chord from the midpoint (5, 5) is
    // (−10, −10)/14.142·7.0711 = (−5, −5): the centre is the origin.
    assert!(near(centre(&m[3]), [0.0, 0.0, -1.0]));
    // Line 6: from (10, 0) to (0, 10) clockwise the shorter arc's centre is right of the chord,
    // (5, 5) + (5, 5) = (10, 10); R−10 takes the longer arc about the left one, (5, 5) − (5, 5)
    // = the origin, and sweeps 270° clockwise.
    assert!(near(centre(&m[4]), [0.0, 0.0, -1.0]));
    let (r, s) = m[4].sweep(1e-9).unwrap();
    assert!((r - 10.0).abs() < 1e-9 && (s + 1.5 * std::f64::consts::PI).abs() < 1e-9);
}

#[test]
fn a_helix_in_g91_and_the_g18_g19_planes() {
    let c = ok(
        "fanuc-mill",
        "G21 G90 G0 X5. Y0. Z0.\nG1 F300.\n\
         G91 G3 X0. Y0. Z-2.5 I-5. J0.\n\
         G90 G18 G2 X-5. Z-2.5 I-5. K0.\n\
         G19 G3 Y5. Z2.5 J0. K5.\n",
    );
    let m = &c.moves;
    // A full turn about (0, 0) dropping 2.5 (the pitch of M20x2.5).
    assert!(near(centre(&m[1]), [0.0, 0.0, 0.0]));
    assert_at(&m[1], [5.0, 0.0, -2.5]);
    let (_, s) = m[1].sweep(1e-9).unwrap();
    assert!((s - std::f64::consts::TAU).abs() < 1e-9);
    // G18: I is X's, K is Z's; from (5, 0, −2.5) the centre is (0, 0, −2.5).
    match m[2].kind {
        MillKind::Arc { plane, centre, .. } => {
            assert_eq!(plane, Plane::Zx);
            assert!(near(centre, [0.0, 0.0, -2.5]));
        }
        _ => panic!(),
    }
    // G19: J is Y's, K is Z's; from (−5, 0, −2.5): centre (−5, 0, 2.5).
    assert!(near(centre(&m[3]), [-5.0, 0.0, 2.5]));
    assert_at(&m[3], [-5.0, 5.0, 2.5]);
}

#[test]
fn g52_shift_g92_and_inch_to_mm() {
    let c = ok(
        "fanuc-mill",
        "G20 G90 G0 X1. Y2. Z0.1\nG52 X1.\nG0 X0. Y0.\nG52 X0.\nG92 X0. Y0.\nG0 X1. Y1.\n",
    );
    let m = &c.moves;
    // Inch: (1, 2, 0.1) in = (25.4, 50.8, 2.54) mm.
    assert_at(&m[0], [25.4, 50.8, 2.54]);
    // G52 X1.: program X0 is work X 1 in = 25.4 mm; Y0 is 0.
    assert_at(&m[1], [25.4, 0.0, 2.54]);
    // G92 X0 Y0 at (25.4, 0) after G52 X0: X1 Y1 is (25.4 + 25.4, 0 + 25.4).
    assert_at(&m[2], [50.8, 25.4, 2.54]);
}

#[test]
fn numbers_without_a_decimal_point() {
    // Fanuc: a least increment (X10 = 0.010 mm); LinuxCNC and Haas: whole units.
    let f = ok("fanuc-mill", "G21 G0 X10 Y0 Z0\n");
    assert_at(&f.moves[0], [0.010, 0.0, 0.0]);
    let l = ok("linuxcnc-mill", "G21 G0 X10 Y0 Z0\n");
    assert_at(&l.moves[0], [10.0, 0.0, 0.0]);
    let h = ok("haas-mill", "G21 G0 X10 Y0 Z0\n");
    assert_at(&h.moves[0], [10.0, 0.0, 0.0]);
}

#[test]
fn compensation_length_offset_tool_and_spindle_are_the_state() {
    let c = ok(
        "haas-mill",
        "G21 G90 T4 M6\nS800 M3\nG0 G43 H4 X0 Y0 Z5.\nG1 G41 D14 X10. F250.\nG40 X0\n",
    );
    let s = c.moves[1].state;
    assert_eq!(s.comp, Comp::Left { d: Some(14) });
    assert_eq!(s.tool, Some(4));
    assert_eq!(s.length_offset, Some(4));
    assert_eq!(s.rotation, Rotation::Cw);
    assert_eq!(s.rpm, Some(800.0));
    assert_eq!(s.feed, Feed::PerMinute(250.0));
    assert_eq!(c.moves[2].state.comp, Comp::Off);
}

#[test]
fn drilling_with_g98_and_g99_returns() {
    let c = ok(
        "fanuc-mill",
        "G21 G90 G0 X0 Y0 Z50.\nG98 G81 X10. Y0 Z-5. R2. F100.\nG99 X20.\nG80\n",
    );
    let ends: Vec<[f64; 3]> = c.moves.iter().map(|m| m.to).collect();
    // Hole 1 (G98): XY at the initial level 50, rapid to R 2, feed to −5, rapid to 50.
    // Hole 2 (G99): XY at 50, R 2, −5, back to R 2.
    let expected = [
        [0.0, 0.0, 50.0],
        [10.0, 0.0, 50.0],
        [10.0, 0.0, 2.0],
        [10.0, 0.0, -5.0],
        [10.0, 0.0, 50.0],
        [20.0, 0.0, 50.0],
        [20.0, 0.0, 2.0],
        [20.0, 0.0, -5.0],
        [20.0, 0.0, 2.0],
    ];
    assert_eq!(ends.len(), expected.len());
    for (a, b) in ends.iter().zip(expected) {
        assert!(near(*a, b), "{a:?} {b:?}");
    }
    assert!(matches!(c.moves[3].kind, MillKind::Feed));
    assert!(matches!(c.moves[4].kind, MillKind::Rapid));
}

#[test]
fn peck_drilling_g83_goes_back_to_r_each_peck() {
    // Haas: Setting 22 is 0.05 in = 1.27 mm above the last depth.
    let c = ok(
        "haas-mill",
        "G21 G90 G0 X0 Y0 Z10.\nG99 G83 Z-6. R1. Q3. F80.\n",
    );
    let z: Vec<f64> = c.moves.iter().skip(1).map(|m| m.to[2]).collect();
    // R 1; feed to −2; rapid to R 1; rapid to −2 + 1.27 = −0.73; feed to −5; R; −3.73; feed
    // to −6 (the last peck short); back to R.
    let expected = [1.0, -2.0, 1.0, -0.73, -5.0, 1.0, -3.73, -6.0, 1.0];
    assert_eq!(z.len(), expected.len(), "{z:?}");
    for (a, b) in z.iter().zip(expected) {
        assert!((a - b).abs() < 1e-9, "{z:?}");
    }
}

#[test]
fn tapping_cycles_are_events_and_rigid_moves_are_synchronised() {
    // Fanuc M29 S500: rigid; G95 F1.5 is the lead 1.5 mm. Under G94 F750 S500 the lead is
    // 750/500 = 1.5 too.
    let c = ok(
        "fanuc-mill",
        "G21 G90 G0 X0 Y0 Z20.\nS500 M3\nG95 M29 S500\nG98 G84 X5. Y5. Z-12. R3. F1.5\nG80\nG94\nG99 G84 X15. Y5. Z-12. R3. F750. P200\nG80\n",
    );
    assert_eq!(c.taps.len(), 2);
    let t = c.taps[0];
    assert!(t.rigid && t.code == 840 && t.line == 4);
    assert_eq!(t.feed, Feed::PerRev(1.5));
    assert!((t.r - 3.0).abs() < 1e-9 && (t.bottom + 12.0).abs() < 1e-9);
    let sync: Vec<&MillMotion> = c
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MillKind::Sync { .. }))
        .collect();
    assert_eq!(sync.len(), 2);
    assert!(matches!(sync[0].kind, MillKind::Sync { lead } if (lead - 1.5).abs() < 1e-12));
    // In under M3, out under M4 (the spindle reversed at the bottom).
    assert_eq!(sync[0].state.rotation, Rotation::Cw);
    assert_eq!(sync[1].state.rotation, Rotation::Ccw);
    // The second cycle without M29: floating, fed in and out; P200 is 0.2 s.
    let t = c.taps[1];
    assert!(!t.rigid && t.dwell == Some(0.2));
    assert_eq!(t.feed, Feed::PerMinute(750.0));
    let last = c.moves.last().unwrap();
    assert!(matches!(last.kind, MillKind::Feed) && near(last.to, [15.0, 5.0, 3.0]));
}

#[test]
fn a_macro_b_program_mills_a_helix_in_nested_loops_under_g52() {
    // Two radial passes (#2 = 9.4, 9.6 ... radius from 0), each three turns of pitch 2.5 from
    // Z0 down, about the local origin X50 Y20.
    let src = "G21 G90 G17\nG52 X50. Y20.\nG0 X0 Y0 Z5.\nG1 Z0 F300.\n#1 = 1\nWHILE [#1 LE 2] DO1\n\
        #2 = 9.2 + 0.2 * #1\nG1 X#2 Y0 Z0\n#3 = 1\nWHILE [#3 LE 3] DO2\n\
        G2 X#2 Y0 Z-[2.5 * #3] I-#2 J0\n#3 = #3 + 1\nEND2\n#1 = #1 + 1\nEND1\nG0 Z[#5003 + 10.]\nM30\n";
    let c = ok("fanuc-mill", src);
    let arcs: Vec<&MillMotion> = c
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MillKind::Arc { .. }))
        .collect();
    assert_eq!(arcs.len(), 6);
    // Pass 2, turn 3: radius 9.6, centre (50, 20), end (59.6, 20, −7.5).
    assert!(near(centre(arcs[5]), [50.0, 20.0, -5.0]));
    assert_at(arcs[5], [59.6, 20.0, -7.5]);
    assert_eq!(arcs[5].line, 11);
    // #5003 is Z in the program's coordinates: −7.5 + 10.
    assert_at(c.moves.last().unwrap(), [59.6, 20.0, 2.5]);
}

#[test]
fn an_o_word_program_repeats_its_helix() {
    let src = "G21 G90 G17 G0 X5 Y0 Z0\nF200\n#1 = 0\no100 while [#1 LT 4]\n\
        G3 X5 Y0 Z[-1.5 * [#1 + 1]] I-5 J0\n#1 = [#1 + 1]\no100 endwhile\nG0 Z[#<_z> + 20]\nM2\n";
    let c = ok("linuxcnc-mill", src);
    assert_eq!(c.moves.len(), 6);
    assert_at(&c.moves[4], [5.0, 0.0, -6.0]);
    assert_at(&c.moves[5], [5.0, 0.0, 14.0]);
}

#[test]
fn linuxcnc_p_turns_and_g33_1() {
    let c = ok(
        "linuxcnc-mill",
        "G21 G90 G0 X5 Y0 Z0\nS300 M3\nG2 X5 Y0 Z-7.5 I-5 J0 P3 F100\nG0 X20 Y20 Z2\nG33.1 Z-10 K1.25\n",
    );
    // P3: two full turns and the last (here also full) one.
    assert!(matches!(c.moves[1].kind, MillKind::Arc { turns: 2, .. }));
    let (_, s) = c.moves[1].sweep(1e-9).unwrap();
    assert!((s + 3.0 * std::f64::consts::TAU).abs() < 1e-9);
    assert_eq!(c.taps.len(), 1);
    assert_eq!(c.taps[0].feed, Feed::PerRev(1.25));
    let n = c.moves.len();
    assert_at(&c.moves[n - 2], [20.0, 20.0, -10.0]);
    assert_at(&c.moves[n - 1], [20.0, 20.0, 2.0]);
}

#[test]
fn alarms_at_their_line_and_column() {
    // An arc whose end is off its circle: 10 from the centre at the start, 10.5 at the end.
    let e = err(
        "fanuc-mill",
        "G21 G0 X10. Y0 Z0\nG2 X0 Y-10.5 I-10. J0 F100.\n",
    );
    assert_eq!((e.span.line, e.span.column), (2, 14));
    assert!(e.message.contains("PS0020"), "{}", e.message);
    // R too small: half the chord is 10, R 5.
    let e = err(
        "fanuc-mill",
        "G21 G0 X10. Y0 Z0\nG1 F100.\nG2 X-10. Y0 R5.\n",
    );
    assert_eq!((e.span.line, e.span.column), (3, 13));
    // G41 on an arc.
    let e = err(
        "haas-mill",
        "G21 G0 X10. Y0 Z0\nG41 D1 G2 X0 Y10. R10. F100.\n",
    );
    assert_eq!((e.span.line, e.span.column), (2, 8));
    // A canned cycle without R.
    let e = err("fanuc-mill", "G21 G0 X0 Y0 Z10.\nG81 X5. Z-3. F100.\n");
    assert_eq!((e.span.line, e.span.column), (2, 1));
    assert!(e.message.contains("without R"));
    // An incremental move on an axis not known.
    let e = err("fanuc-mill", "G21 G91 G0 X5.\n");
    assert_eq!((e.span.line, e.span.column), (1, 12));
    // A LinuxCNC arc off its circle, by LinuxCNC's rule and message.
    let e = err(
        "linuxcnc-mill",
        "G21 G0 X10 Y0 Z0\nG2 X0 Y-10.5 I-10 J0 F100\n",
    );
    assert!(e.message.starts_with("Radius to end of arc differs"));
    // A rotary axis is not read.
    let e = err("haas-mill", "G21 G0 X0 Y0 Z0\nG0 A90.\n");
    assert_eq!((e.span.line, e.span.column), (2, 4));
    // G28 without a reference leaves the position unknown: an arc then has no start.
    let e = err("haas-mill", "G21 G0 X0 Y0 Z0\nG28\nG2 X1. Y1. R1. F10.\n");
    assert_eq!(e.span.line, 3);
}

#[test]
fn a_shop_header_g91_g28_and_k_repeats() {
    // A CAM post's safety line, the Z home, a work system, a tool and three holes 10 apart by K
    // in G91: X 10, 20, 30 from X0, each R 2 below the initial level 30 (G91 R−28: 30 − 28),
    // Z 5 below R (Z−5: −3).
    let src = "%\nO1000 (PART)\nG00 G17 G40 G49 G80 G90 G15 G69 G05.1 Q1\nG91 G28 Z0.\n\
        G90 G54 X0 Y0\nT1 M06\nS2000 M03\nG43 H01 Z30.\nG91 G99 G81 X10. R-28. Z-5. K3 F200.\nG80 G90\nM30\n%\n";
    let c = ok("fanuc-mill", src);
    let holes: Vec<f64> = c
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MillKind::Feed))
        .map(|m| {
            assert!((m.to[2] + 3.0).abs() < 1e-9, "{m:?}");
            m.to[0]
        })
        .collect();
    assert_eq!(holes, [10.0, 20.0, 30.0]);
    // The first move known on every axis: G43 H01 Z30. (Z came home unknown).
    assert_eq!(c.moves[0].line, 8);
    assert!(c.moves[0].from[2].is_nan());
    assert_eq!(c.moves[0].state.length_offset, Some(1));
}

#[test]
fn haas_work_offsets_smoothing_and_local_subprograms() {
    // G154 P1 and G187 read; M97 P100 runs N100 as a subprogram: a helix of one turn about
    // (0, 0) from (8, 0, 0) to (8, 0, −1.25).
    let src = "G20 G187 P1\nG21 G90 G154 P1 G0 X8. Y0 Z0\nF300.\nM97 P100\nM30\nN100 G3 X8. Y0 Z-1.25 I-8. J0\nM99\n";
    let c = ok("haas-mill", src);
    assert_eq!(c.moves.len(), 2);
    assert!(near(centre(&c.moves[1]), [0.0, 0.0, 0.0]));
    assert_at(&c.moves[1], [8.0, 0.0, -1.25]);
    assert_eq!(c.moves[1].line, 6);
}

#[test]
fn a_g65_macro_call_mills_its_arguments() {
    // G65 P9010 A8. B2.: #1 = 8 (radius), #2 = 2 (pitch): one turn down one pitch.
    let src = "G21 G90 G0 X0 Y0 Z0\nF200.\nG65 P9010 A8. B2.\nM30\nO9010\nG1 X#1\nG2 X#1 Y0 Z-#2 I-#1 J0\nM99\n";
    let c = ok("fanuc-mill", src);
    let arc = c.moves.last().unwrap();
    assert!(near(centre(arc), [0.0, 0.0, 0.0]));
    assert_at(arc, [8.0, 0.0, -2.0]);
}

#[test]
fn the_profile_reference_places_g28_and_centroid_has_no_macros() {
    let text = format!(
        "{}\n[reference]\ng28 = {{ x = 0.0, y = 0.0, z = 100.0 }}\n",
        crate::machine::MILL_BUILT_IN
            .iter()
            .find(|(n, _)| *n == "fanuc-mill")
            .unwrap()
            .1
    );
    let p = MillProfile::from_toml(&text).unwrap();
    let mut c = Collect::default();
    let src = "G21 G90 G0 X10. Y10. Z5.\nG28 Z10.\nG1 X20. F100.\n";
    run(src.as_bytes(), &p, &Options::default(), &mut c).unwrap();
    // Through Z10 (the intermediate point) to the reference Z100; X and Y stay.
    assert_at(&c.moves[1], [10.0, 10.0, 10.0]);
    assert_at(&c.moves[2], [10.0, 10.0, 100.0]);
    assert_at(&c.moves[3], [20.0, 10.0, 100.0]);
    // Centroid: `#` is not read, nor a subprogram call passed over.
    let e = err("centroid", "G21 G0 X0 Y0 Z0\n#100 = 1\n");
    assert_eq!(e.span.line, 2);
    let e = err("centroid", "G21 G0 X0 Y0 Z0\nM98 P100\n");
    assert_eq!((e.span.line, e.span.column), (2, 1));
}

#[test]
fn a_change_of_work_system_and_g53_leave_the_position_unknown() {
    let e = err(
        "fanuc-mill",
        "G21 G90 G54 G0 X0 Y0 Z0\nG55\nG91 G1 X1. F100.\n",
    );
    assert_eq!((e.span.line, e.span.column), (3, 8));
    let e = err("fanuc-mill", "G21 G90 G0 X0 Y0 Z0\nG53 Z0\nG91 G0 Z1.\n");
    assert_eq!(e.span.line, 3);
    // The same system again keeps it.
    ok(
        "fanuc-mill",
        "G21 G90 G54 G0 X0 Y0 Z0\nG54\nG91 G1 X1. F100.\n",
    );
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(300))]
    /// Random blocks of the words a milling program holds never panic nor hang: each program is
    /// read or refused with a diagnostic, on every milling profile.
    #[test]
    fn random_milling_blocks_are_read_or_refused(
        blocks in proptest::collection::vec(
            proptest::collection::vec(
                (
                    proptest::sample::select(vec![
                        "G0", "G1", "G2", "G3", "G17", "G18", "G19", "G20", "G21", "G28", "G41",
                        "G40", "G43", "G52", "G53", "G55", "G73", "G80", "G81", "G83", "G84",
                        "G90", "G91", "G92", "G95", "G98", "G99", "G33.1", "M3", "M29", "M6",
                        "X", "Y", "Z", "I", "J", "K", "R", "Q", "P", "F", "S", "H", "D", "L", "T",
                    ]),
                    -30i32..30,
                ),
                0..6,
            ),
            0..12,
        ),
        profile in proptest::sample::select(vec!["fanuc-mill", "haas-mill", "centroid", "linuxcnc-mill"]),
    ) {
        let mut src = String::from("G21 G90 G0 X0 Y0 Z10.\n");
        for b in &blocks {
            for (word, v) in b {
                if word.starts_with(['G', 'M']) {
                    src.push_str(word);
                } else {
                    src.push_str(&format!("{word}{}.", v));
                }
                src.push(' ');
            }
            src.push('\n');
        }
        let _ = read(profile, &src);
    }
}
