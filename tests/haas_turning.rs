//! Haas's one-block turning cycles: G71/G72 `P Q U W D F [I K] [R1]` and G73 `P Q U W I K D F`
//! read onto the machine-neutral model (the same moves as Fanuc's two-block cycles with the same
//! values), their words' errors at line:column, and the retract of Setting 73 from the profile
//! (docs/dialects/haas.md, "Turning cycles").

use threadcut::diag::Severity;
use threadcut::machine::Machine;
use threadcut::program;

/// The program's moves as `expand --format jsonl` lists them: (kind, x radius, z) in program
/// units, the moves before the cycle left out (`skip`).
fn jsonl(src: &str, machine: &Machine, skip: usize) -> Vec<(String, f64, f64)> {
    let mut out = Vec::new();
    program::expand_jsonl(src.as_bytes(), &mut out, machine).unwrap_or_else(|e| panic!("{e}"));
    String::from_utf8(out)
        .unwrap()
        .lines()
        .skip(skip)
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            (
                v["kind"].as_str().unwrap().to_string(),
                v["x"].as_f64().unwrap(),
                v["z"].as_f64().unwrap(),
            )
        })
        .collect()
}

/// The same value at the output's resolution (0.001 mm; 0.0001 inch).
fn same(a: f64, b: f64) -> bool {
    (a - b).abs() < 5e-5
}

fn assert_moves(got: &[(String, f64, f64)], want: &[(&str, f64, f64)]) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(want) {
        let kind = match w.0 {
            "R" => "rapid",
            "F" => "feed",
            k => k,
        };
        assert!(
            g.0 == kind && same(g.1, w.1) && same(g.2, w.2),
            "{g:?} ≠ {w:?} in {got:?}"
        );
    }
}

fn haas() -> Machine {
    Machine::built_in("haas").unwrap()
}

/// The built-in Haas profile with Setting 73 stated (`retract` inch) or left out (`None`).
fn haas_with(retract: Option<f64>) -> Machine {
    let mut m = haas();
    let s = m.haas.as_mut().unwrap();
    s.roughing_retract_in = retract;
    s.roughing_retract_assumed = false;
    m
}

/// The error of a program: "line:column message".
fn error(src: &str, machine: &Machine) -> String {
    match program::run(src.as_bytes(), machine, |_, _| Ok(())) {
        Err(program::Error::Input(d)) => format!("{}:{} {}", d.span.line, d.span.column, d.message),
        other => panic!("no error: {other:?}"),
    }
}

/// The error `expand` meets making a cycle's moves: "line message".
fn expand_error(src: &str, machine: &Machine) -> String {
    let mut out = Vec::new();
    match program::expand_jsonl(src.as_bytes(), &mut out, machine) {
        Err(program::Error::Input(d)) => format!("{} {}", d.span.line, d.message),
        other => panic!("no error: {other:?}"),
    }
}

/// The warnings of a program: (line, message).
fn warnings(src: &str, machine: &Machine) -> Vec<(u32, String)> {
    let summary = program::run(src.as_bytes(), machine, |_, _| Ok(())).unwrap();
    summary
        .warnings
        .iter()
        .map(|d| {
            assert_eq!(d.severity, Severity::Warning);
            (d.span.line, d.message.clone())
        })
        .collect()
}

/// A shaft: start X50 Z2 (radius 25); N10 G0 X30 (radius 15); G1 Z−20; N20 X50 (radius 25).
const SHAFT: &str = "N10 G0 X30.\nG1 Z-20.\nN20 X50.\n";

/// G71 type I outside, in mm: D2 (radius), U1 (diameter: 0.5 radius) W0.1, Setting 73 =
/// 0.05 in = 1.27 mm. The shape shifted by (0.5, 0.1): (15.5, 2.1) → (15.5, −19.9) → (25.5,
/// −19.9). Layers every 2 from radius 25, strictly above the lowest radius 15.5: 23, 21, 19, 17
/// (⌈9.5/2⌉ − 1 = 4); each cut from Z2 to the wall at Z−19.9, a 45° retract of 1.27 (to
/// radius h + 1.27, Z−18.63), back to Z2 at that height; then the shape shifted, back to the start.
#[test]
fn g71_type_i_outside_in_mm_as_the_hand_computes_it() {
    let src = format!("G21\nG0 X50. Z2.\nG71 P10 Q20 U1. W0.1 D2. F0.2\n{SHAFT}");
    let want: &[(&str, f64, f64)] = &[
        ("R", 23.0, 2.0),
        ("F", 23.0, -19.9),
        ("R", 24.27, -18.63),
        ("R", 24.27, 2.0),
        ("R", 21.0, 2.0),
        ("F", 21.0, -19.9),
        ("R", 22.27, -18.63),
        ("R", 22.27, 2.0),
        ("R", 19.0, 2.0),
        ("F", 19.0, -19.9),
        ("R", 20.27, -18.63),
        ("R", 20.27, 2.0),
        ("R", 17.0, 2.0),
        ("F", 17.0, -19.9),
        ("R", 18.27, -18.63),
        ("R", 18.27, 2.1),
        ("R", 15.5, 2.1),
        ("F", 15.5, -19.9),
        ("F", 25.5, -19.9),
        ("R", 25.0, 2.0),
    ];
    let got = jsonl(&src, &haas(), 1);
    assert_moves(&got, want);
    // Fanuc's two blocks with the same values (R(e) = 1.27) make the same moves.
    let fanuc = format!("G0 X50. Z2.\nG71 U2. R1.27\nG71 P10 Q20 U1. W0.1 F0.2\n{SHAFT}");
    assert_eq!(jsonl(&fanuc, &Machine::built_in("fanuc").unwrap(), 1), got);
}

/// The same shaft in inch (every length ÷ 25.4; Setting 73 is 0.05 in): the same moves, scaled.
#[test]
fn g71_in_inch_is_the_mm_cycle_scaled() {
    let mm = jsonl(
        &format!("G21\nG0 X50. Z2.\nG71 P10 Q20 U1. W0.1 D2. F0.2\n{SHAFT}"),
        &haas(),
        1,
    );
    let inch = |v: f64| format!("{:.6}", v / 25.4);
    let src = format!(
        "G20\nG0 X{} Z{}\nG71 P10 Q20 U{} W{} D{} F0.008\nN10 G0 X{}\nG1 Z{}\nN20 X{}\n",
        inch(50.0),
        inch(2.0),
        inch(1.0),
        inch(0.1),
        inch(2.0),
        inch(30.0),
        inch(-20.0),
        inch(50.0)
    );
    let got = jsonl(&src, &haas(), 1);
    assert_eq!(got.len(), mm.len(), "{got:?}");
    for (g, m) in got.iter().zip(&mm) {
        assert_eq!(g.0, m.0);
        assert!(
            (g.1 * 25.4 - m.1).abs() < 2e-4 && (g.2 * 25.4 - m.2).abs() < 2e-4,
            "{g:?} ≠ {m:?}"
        );
    }
    // The first cut at radius 23 mm = 0.905512 in, to Z−19.9 mm = −0.783465 in.
    assert!(
        same(got[1].1, 0.905512) && same(got[1].2, -0.783465),
        "{got:?}"
    );
}

/// I, K: the rough pass allowance (I a radius) beyond U, W. The layers and a first pass along the
/// shape stop at (0.5 + 0.3, 0.1 + 0.2) = (0.8, 0.3): the wall at Z−19.7, the floor at radius
/// 15.8 (still 4 layers: ⌈9.2/2⌉ − 1); then a second pass along the shape at (0.5, 0.1).
#[test]
fn g71_rough_pass_allowance_then_a_pass_at_the_finishing_allowance() {
    let src = format!("G21\nG0 X50. Z2.\nG71 P10 Q20 U1. W0.1 I0.3 K0.2 D2. F0.2\n{SHAFT}");
    let want: &[(&str, f64, f64)] = &[
        ("R", 23.0, 2.0),
        ("F", 23.0, -19.7),
        ("R", 24.27, -18.43),
        ("R", 24.27, 2.0),
        ("R", 21.0, 2.0),
        ("F", 21.0, -19.7),
        ("R", 22.27, -18.43),
        ("R", 22.27, 2.0),
        ("R", 19.0, 2.0),
        ("F", 19.0, -19.7),
        ("R", 20.27, -18.43),
        ("R", 20.27, 2.0),
        ("R", 17.0, 2.0),
        ("F", 17.0, -19.7),
        ("R", 18.27, -18.43),
        ("R", 18.27, 2.3),
        ("R", 15.8, 2.3),
        ("F", 15.8, -19.7),
        ("F", 25.8, -19.7),
        ("R", 25.0, 2.0),
        // The second pass: from the start over the cut material to the shape at (0.5, 0.1).
        ("R", 25.0, 2.1),
        ("R", 15.5, 2.1),
        ("F", 15.5, -19.9),
        ("F", 25.5, -19.9),
        ("R", 25.0, 2.0),
    ];
    assert_moves(&jsonl(&src, &haas(), 1), want);
}

/// Inside a bore: start X20 Z2 (radius 10), N10 G0 X40 (radius 20), G1 Z−15, N20 X20; U−1
/// (radius −0.5) W0.1: the shape shifted to (19.5, 2.1) → (19.5, −14.9) → (9.5, −14.9). Layers
/// every 2 upward from radius 10, below 19.5: 12, 14, 16, 18; the retract goes down, toward the
/// axis: radius h − 1.27 at Z−13.63.
#[test]
fn g71_inside_a_bore_retracts_toward_the_axis() {
    let src = "G21\nG0 X20. Z2.\nG71 P10 Q20 U-1. W0.1 D2. F0.2\nN10 G0 X40.\nG1 Z-15.\nN20 X20.\n";
    let want: &[(&str, f64, f64)] = &[
        ("R", 12.0, 2.0),
        ("F", 12.0, -14.9),
        ("R", 10.73, -13.63),
        ("R", 10.73, 2.0),
        ("R", 14.0, 2.0),
        ("F", 14.0, -14.9),
        ("R", 12.73, -13.63),
        ("R", 12.73, 2.0),
        ("R", 16.0, 2.0),
        ("F", 16.0, -14.9),
        ("R", 14.73, -13.63),
        ("R", 14.73, 2.0),
        ("R", 18.0, 2.0),
        ("F", 18.0, -14.9),
        ("R", 16.73, -13.63),
        ("R", 16.73, 2.1),
        ("R", 19.5, 2.1),
        ("F", 19.5, -14.9),
        ("F", 9.5, -14.9),
        ("R", 10.0, 2.0),
    ];
    assert_moves(&jsonl(src, &haas(), 1), want);
}

/// G72 facing: start X52 Z1 (radius 26); N10 G0 Z−4; G1 X20 (radius 10); N20 Z1; U0.4 (radius
/// 0.2) W0.2, D1.5 in Z. The shape shifted: (26.2, −3.8) → (10.2, −3.8) → (10.2, 1.2). Layers
/// every 1.5 down from Z1, above −3.8: −0.5, −2, −3.5 (⌈4.8/1.5⌉ − 1 = 3); each cut along X to
/// the wall at radius 10.2, a retract of 1.27 in Z and back in X (to radius 11.47).
#[test]
fn g72_facing_as_the_hand_computes_it() {
    let src = "G21\nG0 X52. Z1.\nG72 P10 Q20 U0.4 W0.2 D1.5 F0.2\nN10 G0 Z-4.\nG1 X20.\nN20 Z1.\n";
    let want: &[(&str, f64, f64)] = &[
        ("R", 26.0, -0.5),
        ("F", 10.2, -0.5),
        ("R", 11.47, 0.77),
        ("R", 26.0, 0.77),
        ("R", 26.0, -2.0),
        ("F", 10.2, -2.0),
        ("R", 11.47, -0.73),
        ("R", 26.0, -0.73),
        ("R", 26.0, -3.5),
        ("F", 10.2, -3.5),
        ("R", 11.47, -2.23),
        ("R", 26.2, -2.23),
        ("R", 26.2, -3.8),
        ("F", 10.2, -3.8),
        ("F", 10.2, 1.2),
        ("R", 26.0, 1.0),
    ];
    let got = jsonl(src, &haas(), 1);
    assert_moves(&got, want);
    let fanuc =
        "G0 X52. Z1.\nG72 W1.5 R1.27\nG72 P10 Q20 U0.4 W0.2 F0.2\nN10 G0 Z-4.\nG1 X20.\nN20 Z1.\n";
    assert_eq!(jsonl(fanuc, &Machine::built_in("fanuc").unwrap(), 1), got);
}

/// G73: I3 (radius) K0.5 the relief from the first cut to the last, D3 passes, U1 W0.1. Pass k
/// is shifted by the allowance plus (3 − k)/2 of the relief: (3.5, 0.6), (2.0, 0.35), (0.5,
/// 0.1); each from its shifted start, the first block at rapid.
#[test]
fn g73_in_d_passes_from_the_relief_to_the_allowance() {
    let src = format!("G21\nG0 X50. Z2.\nG73 P10 Q20 U1. W0.1 I3. K0.5 D3 F0.2\n{SHAFT}");
    let want: &[(&str, f64, f64)] = &[
        ("R", 28.5, 2.6),
        ("R", 18.5, 2.6),
        ("F", 18.5, -19.4),
        ("F", 28.5, -19.4),
        ("R", 27.0, 2.35),
        ("R", 17.0, 2.35),
        ("F", 17.0, -19.65),
        ("F", 27.0, -19.65),
        ("R", 25.5, 2.1),
        ("R", 15.5, 2.1),
        ("F", 15.5, -19.9),
        ("F", 25.5, -19.9),
        ("R", 25.0, 2.0),
    ];
    let got = jsonl(&src, &haas(), 1);
    assert_moves(&got, want);
    let fanuc = format!("G0 X50. Z2.\nG73 U3. W0.5 R3\nG73 P10 Q20 U1. W0.1 F0.2\n{SHAFT}");
    assert_eq!(jsonl(&fanuc, &Machine::built_in("fanuc").unwrap(), 1), got);
}

/// R1 selects type 2 (YASNAC): the same moves as Fanuc's type II, chosen there by a first block
/// that names both axes. The shape has a pocket: radius 15 to Z−10, down to 12 (R2 arc-free
/// V: a line to radius 12 at Z−14, back to 15 at Z−18), to Z−25, out to 25.
#[test]
fn r1_selects_type_ii_as_a_first_block_with_both_axes_does() {
    let shape = "G1 Z-10.\nX24. Z-14.\nX30. Z-18.\nZ-25.\nN20 X50.\n";
    let haas_src =
        format!("G21\nG0 X50. Z2.\nG71 P10 Q20 U0.4 W0.1 D2. R1 F0.2\nN10 G0 X30.\n{shape}");
    let fanuc_src =
        format!("G0 X50. Z2.\nG71 U2. R1.27\nG71 P10 Q20 U0.4 W0.1 F0.2\nN10 G0 X30. Z2.\n{shape}");
    let got = jsonl(&haas_src, &haas(), 1);
    assert_eq!(
        jsonl(&fanuc_src, &Machine::built_in("fanuc").unwrap(), 1),
        got
    );
    // Type II cuts into the V: some feed reaches below radius 15.2 (the shifted floor) at the
    // V's bottom, radius 12.2.
    assert!(
        got.iter().any(|m| m.0 == "feed" && same(m.1, 12.2)),
        "{got:?}"
    );
    // Without R1 the same shape is type I, which refuses the V (PS0064's twin on X).
    let e = expand_error(&haas_src.replace(" R1", ""), &haas());
    assert!(
        e.starts_with("6 ") && e.contains("monotonically in X"),
        "{e}"
    );
}

/// Setting 73 comes from the profile: a retract of 0.1 in (2.54 mm) moves the first retract to
/// radius 23 + 2.54 at Z−19.9 + 2.54; no warning when the profile does not call it assumed.
#[test]
fn the_retract_is_the_profile_s_setting_73() {
    let src = format!("G21\nG0 X50. Z2.\nG71 P10 Q20 U1. W0.1 D2. F0.2\n{SHAFT}");
    let m = haas_with(Some(0.1));
    let got = jsonl(&src, &m, 1);
    assert!(same(got[2].1, 25.54) && same(got[2].2, -17.36), "{got:?}");
    assert!(warnings(&src, &m).is_empty());
    // The built-in profile's value is assumed: a warning at the cycle says so.
    let w = warnings(&src, &haas());
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].0 == 3 && w[0].1.contains("Setting 73, assumed 1.27 mm"),
        "{w:?}"
    );
    // A profile without Setting 73: refused at D, saying which setting is missing.
    let e = error(&src, &haas_with(None));
    assert!(e.starts_with("3:22 ") && e.contains("not read"), "{e}");
}

/// Each word's error, at its line and column.
#[test]
fn word_errors_at_line_and_column() {
    let m = haas();
    let run = |cycle: &str| error(&format!("G21\nG0 X50. Z2.\n{cycle}\n{SHAFT}"), &m);
    // No D: the depth of cut (Setting 72 otherwise, which no profile states).
    let e = run("G71 P10 Q20 U1. W0.1 F0.2");
    assert!(e.starts_with("3:1 ") && e.contains("no D"), "{e}");
    // D not positive.
    let e = run("G71 P10 Q20 U1. W0.1 D0 F0.2");
    assert!(
        e.starts_with("3:22 ") && e.contains("positive radius"),
        "{e}"
    );
    let e = run("G72 P10 Q20 U1. W0.1 D-1. F0.2");
    assert!(
        e.starts_with("3:22 ") && e.contains("positive radius"),
        "{e}"
    );
    // R other than 1.
    let e = run("G71 P10 Q20 U1. W0.1 D2. R2 F0.2");
    assert!(
        e.starts_with("3:26 ") && e.contains("only the value 1"),
        "{e}"
    );
    // G73's D: a whole number of passes.
    let e = run("G73 P10 Q20 U1. W0.1 I3. K0.5 D2.5 F0.2");
    assert!(
        e.starts_with("3:31 ") && e.contains("number of cutting passes"),
        "{e}"
    );
    let e = run("G73 P10 Q20 U1. W0.1 I3. K0.5 F0.2");
    assert!(e.starts_with("3:1 ") && e.contains("needs D"), "{e}");
    // Fanuc's first block is not Haas's form.
    let e = run("G71 U2. R1.");
    assert!(e.starts_with("3:1 ") && e.contains("is one block"), "{e}");
    // A word the cycle does not take.
    let e = run("G71 P10 Q20 U1. W0.1 D2. A30. F0.2");
    assert!(e.starts_with("3:26 "), "{e}");
    // The contour's own alarms stay the model's: type I turning back in Z.
    let e = expand_error(
        "G21\nG0 X50. Z2.\nG71 P10 Q20 U1. W0.1 D2. F0.2\nN10 G0 X30.\nG1 Z-20.\nZ-10.\nN20 X50.\n",
        &m,
    );
    assert!(e.starts_with("6 ") && e.contains("PS0064"), "{e}");
}

/// FS15's one-block G71 stays refused (its retract is a parameter no profile states).
#[test]
fn fs15_one_block_stock_removal_is_still_refused() {
    let src = "G0 X2. Z0.1\nG71 P1 Q2 U0.02 W0.005 D0.05 F0.01\nN1 G0 X1.\nN2 G1 Z-1.\n";
    let e = error(src, &Machine::built_in("fanuc15").unwrap());
    assert!(e.starts_with("2:24 ") && e.contains("one-block G71"), "{e}");
}

/// Every reader of the Fanuc family (Fanuc, GSK, Haas) raises PS0064 at the block where a type I
/// contour turns back in Z (N… `X36. Z-5.` after Z−10), through the one model.
#[test]
fn a_type_i_contour_turning_back_in_z_is_ps0064_at_that_block_on_every_reader() {
    let shape = "N10 G0 X30.\nG1 Z-10.\nX36. Z-5.\nG1 Z-20.\nN20 X50.\n";
    let two_block = format!("G0 X50. Z2.\nG71 U2. R1.\nG71 P10 Q20 U1. W0.1 F0.2\n{shape}");
    for m in ["fanuc", "gsk980"] {
        let e = expand_error(&two_block, &Machine::built_in(m).unwrap());
        assert!(
            e.starts_with("6 PS0064") && e.contains("turns back"),
            "{m}: {e}"
        );
    }
    let one_block = format!("G21\nG0 X50. Z2.\nG71 P10 Q20 U1. W0.1 D2. F0.2\n{shape}");
    let e = expand_error(&one_block, &haas());
    assert!(
        e.starts_with("6 PS0064") && e.contains("turns back"),
        "haas: {e}"
    );
}

/// A G0 inside a G71 contour is a line of the contour: the pass along the outline follows it
/// (as a feed, like every line of the shape), shifted by the allowance. Start X50 Z2, U1 W0.1 (0.5,
/// 0.1), Δd 2, e 1: the last outline is (15.5, 2.1) → (15.5, −9.9) → G0 X36: (18.5, −9.9) →
/// (18.5, −19.9) → (25.5, −19.9), then back to the start.
#[test]
fn a_g0_inside_a_contour_is_a_line_of_it() {
    let src = "G0 X50. Z2.\nG71 U2. R1.\nG71 P10 Q20 U1. W0.1 F0.2\nN10 G0 X30.\nG1 Z-10.\nG0 X36.\nG1 Z-20.\nN20 X50.\n";
    let got = jsonl(src, &Machine::built_in("fanuc").unwrap(), 1);
    let tail = &got[got.len() - 6..];
    assert_moves(
        tail,
        &[
            ("R", 15.5, 2.1),
            ("F", 15.5, -9.9),
            ("F", 18.5, -9.9),
            ("F", 18.5, -19.9),
            ("F", 25.5, -19.9),
            ("R", 25.0, 2.0),
        ],
    );
    // The layers stop at the step too: the layer at radius 17 ends at Z−9.9 (the shape at radius
    // 15.5 is below it only to Z−9.9), then retracts by 1 to (18, −8.9).
    let at17: Vec<_> = got.iter().filter(|m| same(m.1, 17.0)).collect();
    assert!(
        at17.iter().any(|m| m.0 == "feed" && same(m.2, -9.9)),
        "{got:?}"
    );
}
