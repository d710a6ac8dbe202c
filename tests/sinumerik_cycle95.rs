//! Sinumerik's CYCLE95 (stock removal), issue 23: read with its contour (a section `START:END`
//! of the program, or the subprogram NPP in its own file), expanded into plain moves with
//! hand-computed numbers, refused where threadcut does not model it, and cut by `check`.
//! docs/dialects/sinumerik.md, "CYCLE95".

use threadcut::check::{self, Report, Source};
use threadcut::diag::{Code, Diagnostic};
use threadcut::interp::library::{Library, Provided};
use threadcut::machine::Machine;
use threadcut::program::{self, Options};

/// The moves `expand` writes for the cycle: (G, X as written, Z), from the comment that names
/// the cycle to the next numbered block.
fn cycle_moves(src: &str, files: &[(&str, &str)]) -> Vec<(u8, f64, f64)> {
    let out = expand(src, files).unwrap();
    let mut lines = out
        .lines()
        .skip_while(|l| !l.contains("turning cycle of line"));
    lines.next().expect("the cycle's comment");
    lines
        .take_while(|l| l.starts_with('G'))
        .map(|l| {
            let mut w = l.split_whitespace();
            let g = w.next().unwrap()[1..].parse().unwrap();
            let mut num = |c: char| {
                let v = w.next().unwrap();
                assert!(v.starts_with(c), "{l}");
                v[1..].parse::<f64>().unwrap()
            };
            (g, num('X'), num('Z'))
        })
        .collect()
}

fn expand(src: &str, files: &[(&str, &str)]) -> Result<String, Diagnostic> {
    let m = Machine::built_in("sinumerik").unwrap();
    let opts = Options {
        library: Some(Library::new(Provided::new(
            files
                .iter()
                .map(|(n, t)| (n.to_string(), t.as_bytes().to_vec())),
        ))),
        ..Options::default()
    };
    let mut out = Vec::new();
    match program::expand_gcode_with(src.as_bytes(), &mut out, &m, &opts) {
        Ok(_) => Ok(String::from_utf8(out).unwrap()),
        Err(program::Error::Input(d)) => Err(d),
        Err(e) => panic!("{e}"),
    }
}

fn error(src: &str) -> Diagnostic {
    expand(src, &[]).unwrap_err()
}

fn assert_moves(got: &[(u8, f64, f64)], want: &[(u8, f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            g.0 == w.0 && (g.1 - w.1).abs() <= tol && (g.2 - w.2).abs() <= tol,
            "move {i}: {g:?}, expected {w:?}\n{got:?}"
        );
    }
}

/// The stepped shaft Ø20 × 20, Ø30 to Z−40, up to Ø40, as a section after M30.
const SHAFT: &str = "ANF: G1 X20 Z0\nZ-20\nX30\nZ-40\nENDE: X40\n";

fn program(cycle: &str, contour: &str) -> String {
    format!("N10 G18 G90 G95 DIAMON\nN20 T1 D1\nN30 G0 X60 Z5\n{cycle}\nN50 G0 X100 Z100\nN60 M30\n{contour}")
}

#[test]
fn vari_1_longitudinal_roughing_metric_in_equal_layers() {
    // FALZ 0.2, FALX 0.5 (radius): the contour moves to Ø21, Ø31, Ø41 and its shoulders to
    // Z−19.8, Z−39.8, its face to Z0.2. Start point: X (41 + 2·1) = 43, Z 0.2 + 1 = 1.2. Depth
    // (radius) 20.5 − 10.5 = 10, MID 2: 5 layers of 2 (Ø37, 33, 29, 25, 21). Each: G0 down at
    // Z1.2, G1 to where the contour rises, G1 up the contour to the layer before, lift 1 in both
    // axes (Ø+2, Z+1), G0 back to Z1.2.
    let got = cycle_moves(
        &program(
            "N40 CYCLE95(\"ANF:ENDE\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , , 1)",
            SHAFT,
        ),
        &[],
    );
    assert_moves(
        &got,
        &[
            (0, 43.0, 1.2),
            (0, 37.0, 1.2),
            (1, 37.0, -39.8),
            (1, 41.0, -39.8),
            (0, 43.0, -38.8),
            (0, 43.0, 1.2),
            (0, 33.0, 1.2),
            (1, 33.0, -39.8),
            (1, 37.0, -39.8),
            (0, 39.0, -38.8),
            (0, 39.0, 1.2),
            (0, 29.0, 1.2),
            (1, 29.0, -19.8),
            (1, 31.0, -19.8),
            (1, 31.0, -39.8),
            (1, 33.0, -39.8),
            (0, 35.0, -38.8),
            (0, 35.0, 1.2),
            (0, 25.0, 1.2),
            (1, 25.0, -19.8),
            (1, 29.0, -19.8),
            (0, 31.0, -18.8),
            (0, 31.0, 1.2),
            (0, 21.0, 1.2),
            (1, 21.0, -19.8),
            (1, 25.0, -19.8),
            (0, 27.0, -18.8),
            (0, 27.0, 1.2),
            (0, 43.0, 1.2),
        ],
        0.0005,
    );
}

#[test]
fn vari_5_finishing_follows_the_subprogram_contour() {
    // The contour in KONT1.SPF. Finishing alone: G0 to the start point (X43 Z1.2, the same
    // allowances and lift as above), G0 to Ø20 at Z1.2, G1 to the contour's first point and
    // along it, G0 back to the start point.
    let spf = "G1 X20 Z0\nZ-20\nX30\nZ-40\nX40\nM17\n";
    let got = cycle_moves(
        &program(
            "N40 CYCLE95(\"KONT1\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 5, , , 1)",
            "",
        ),
        &[("KONT1.SPF", spf)],
    );
    assert_moves(
        &got,
        &[
            (0, 43.0, 1.2),
            (0, 20.0, 1.2),
            (1, 20.0, 0.0),
            (1, 20.0, -20.0),
            (1, 30.0, -20.0),
            (1, 30.0, -40.0),
            (1, 40.0, -40.0),
            (0, 43.0, 1.2),
        ],
        0.0005,
    );
}

#[test]
fn vari_9_complete_machining_in_inch_g70() {
    // The shaft in inch: Ø0.8 to Z−0.8, Ø1.2 to Z−1.6, up to Ø1.6; MID 0.08 (radius), no
    // allowance, _VRT 0.04. Start point X1.6 + 0.08 = 1.68, Z0.04. Depth 0.4, 5 layers of 0.08
    // (Ø1.44, 1.28, 1.12, 0.96, 0.8); then the finishing pass from Ø0.8 at Z0.04.
    let src = "N10 G18 G90 G70 DIAMON\nN20 T1 D1\nN30 G0 X2.4 Z0.2\nN40 CYCLE95(\"A1:E1\", 0.08, 0, 0, 0, 0.012, 0.006, 0.004, 9, 0, 0, 0.04)\nN50 G0 X4 Z4\nN60 M30\nA1: G1 X0.8 Z0\nZ-0.8\nX1.2\nZ-1.6\nE1: X1.6\n";
    let got = cycle_moves(src, &[]);
    assert_moves(
        &got,
        &[
            (0, 1.68, 0.04),
            (0, 1.44, 0.04),
            (1, 1.44, -1.6),
            (1, 1.6, -1.6),
            (0, 1.68, -1.56),
            (0, 1.68, 0.04),
            (0, 1.28, 0.04),
            (1, 1.28, -1.6),
            (1, 1.44, -1.6),
            (0, 1.52, -1.56),
            (0, 1.52, 0.04),
            (0, 1.12, 0.04),
            (1, 1.12, -0.8),
            (1, 1.2, -0.8),
            (1, 1.2, -1.6),
            (1, 1.28, -1.6),
            (0, 1.36, -1.56),
            (0, 1.36, 0.04),
            (0, 0.96, 0.04),
            (1, 0.96, -0.8),
            (1, 1.12, -0.8),
            (0, 1.2, -0.76),
            (0, 1.2, 0.04),
            (0, 0.8, 0.04),
            (1, 0.8, -0.8),
            (1, 0.96, -0.8),
            (0, 1.04, -0.76),
            (0, 1.04, 0.04),
            (0, 1.68, 0.04),
            // finishing
            (0, 0.8, 0.04),
            (1, 0.8, 0.0),
            (1, 0.8, -0.8),
            (1, 1.2, -0.8),
            (1, 1.2, -1.6),
            (1, 1.6, -1.6),
            (0, 1.68, 0.04),
        ],
        0.00005,
    );
}

#[test]
fn vari_3_internal_roughing_steps_away_from_the_axis() {
    // A bore Ø30 to Z−10, Ø20 to Z−30, down to the drilled Ø14; FALX 0.5 toward the axis: Ø29,
    // Ø19, Ø13. Start point Ø13 − 2 = Ø11, Z1. Depth (radius) 14.5 − 6.5 = 8, MID 3: 3 layers of
    // 8/3 at radius 9.1667, 11.8333, 14.5 (Ø18.3333, Ø23.6667, Ø29); lift toward the axis.
    let contour = "B1: G1 X30 Z0\nZ-10\nX20\nZ-30\nB2: X14\n";
    let src = format!("N10 G18 G90 G95 DIAMON\nN20 T2 D1\nN30 G0 X10 Z5\nN40 CYCLE95(\"B1:B2\", 3, 0, 0.5, , 0.2, 0.1, 0.1, 3, , , 1)\nN50 G0 X10 Z100\nN60 M30\n{contour}");
    let (a, b) = (2.0 * (6.5 + 8.0 / 3.0), 2.0 * (6.5 + 16.0 / 3.0));
    assert_moves(
        &cycle_moves(&src, &[]),
        &[
            (0, 11.0, 1.0),
            (0, a, 1.0),
            (1, a, -30.0),
            (1, 13.0, -30.0),
            (0, 11.0, -29.0),
            (0, 11.0, 1.0),
            (0, b, 1.0),
            (1, b, -10.0),
            (1, 19.0, -10.0),
            (1, 19.0, -30.0),
            (1, a, -30.0),
            (0, a - 2.0, -29.0),
            (0, a - 2.0, 1.0),
            (0, 29.0, 1.0),
            (1, 29.0, -10.0),
            (1, b, -10.0),
            (0, b - 2.0, -9.0),
            (0, b - 2.0, 1.0),
            (0, 11.0, 1.0),
        ],
        0.0005,
    );
}

#[test]
fn vari_2_face_roughing_in_layers_along_z() {
    // A face: rim at Z−6 from Ø60 to Ø40, shoulder up to Z0, face to the axis. FALZ 0.2: Z−5.8,
    // Z0.2. Start point Ø62 (Ø60 + 2·1), Z1.2. Depth 6, MID 2: layers at Z−1.8, −3.8, −5.8,
    // each fed from Ø62 toward the axis to the shoulder at Ø40.
    let contour = "F1: G1 X60 Z-6\nX40\nZ0\nF2: X0\n";
    let src = format!("N10 G18 G90 G95 DIAMON\nN20 T1 D1\nN30 G0 X70 Z5\nN40 CYCLE95(\"F1:F2\", 2, 0.2, 0, , 0.2, 0.1, 0.1, 2, , , 1)\nN50 G0 X100 Z100\nN60 M30\n{contour}");
    assert_moves(
        &cycle_moves(&src, &[]),
        &[
            (0, 62.0, 1.2),
            (0, 62.0, -1.8),
            (1, 40.0, -1.8),
            (1, 40.0, 0.2),
            (0, 42.0, 1.2),
            (0, 62.0, 1.2),
            (0, 62.0, -3.8),
            (1, 40.0, -3.8),
            (1, 40.0, -1.8),
            (0, 42.0, -0.8),
            (0, 62.0, -0.8),
            (0, 62.0, -5.8),
            (1, 40.0, -5.8),
            (1, 40.0, -3.8),
            (0, 42.0, -2.8),
            (0, 62.0, -2.8),
            (0, 62.0, 1.2),
        ],
        0.0005,
    );
}

#[test]
fn what_threadcut_does_not_model_is_refused_at_its_line_and_column() {
    let at = |d: &Diagnostic| (d.code, d.span.line, d.span.column);
    let cycle = |args: &str| program(&format!("N40 CYCLE95({args})"), SHAFT);
    // VARI outside 1–12: alarm 61002 at VARI.
    let d = error(&cycle(
        "\"ANF:ENDE\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 13, , , 1",
    ));
    assert_eq!(at(&d), (Code::OutOfRange, 4, 55), "{d:?}");
    assert!(d.message.contains("61002"), "{}", d.message);
    // DAM (chip breaking) is not simulated: at DAM.
    let d = error(&cycle(
        "\"ANF:ENDE\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , 5, 1",
    ));
    assert_eq!(at(&d), (Code::Unsupported, 4, 60), "{d:?}");
    // Roughing without MID.
    let d = error(&cycle(
        "\"ANF:ENDE\", , 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , , 1",
    ));
    assert_eq!((d.code, d.span.line), (Code::MissingWord, 4), "{d:?}");
    // A signed allowance: at FALX.
    let d = error(&cycle(
        "\"ANF:ENDE\", 2, 0.2, -0.5, , 0.3, 0.1, 0.1, 1, , , 1",
    ));
    assert_eq!(at(&d), (Code::OutOfRange, 4, 33), "{d:?}");
    // NPP must be text.
    let d = error(&cycle("12, 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , , 1"));
    assert_eq!(at(&d), (Code::MissingWord, 4, 13), "{d:?}");
    // A label the program does not have.
    let d = error(&cycle(
        "\"ANF:ENDX\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , , 1",
    ));
    assert_eq!((d.code, d.span.line), (Code::MissingWord, 4), "{d:?}");
    assert!(d.message.contains("ENDX"), "{}", d.message);
    // A relief cut (the contour goes back into the part): at the block that does.
    let relief = "ANF: G1 X30 Z0\nZ-10\nX20 Z-12\nZ-20\nENDE: X40\n";
    let d = error(&program(
        "N40 CYCLE95(\"ANF:ENDE\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , , 1)",
        relief,
    ));
    assert_eq!(
        (d.code, d.span.line, d.span.column),
        (Code::Unsupported, 9, 1),
        "{d:?}"
    );
    // A subprogram that is not there.
    let d = error(&cycle("\"NOPE\", 2, 0.2, 0.5, , 0.3, 0.1, 0.1, 1, , , 1"));
    assert_eq!((d.code, d.span.line), (Code::MissingWord, 4), "{d:?}");
}

fn check(src: &str, stock: f64) -> Report {
    let m = Machine::built_in("sinumerik").unwrap();
    let opts = check::Options {
        stock_diameter: Some(stock),
        stock_start: Some(0.0),
        ..check::Options::default()
    };
    check::check(src.as_bytes(), Source::Gcode(&m), &opts).unwrap()
}

#[test]
fn a_bar_turned_by_cycle95_then_threaded_by_cycle97_checks_on_the_turned_diameter() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/real/sinumerik-cycle95-cycle97-m20.mpf"
    );
    let src = std::fs::read_to_string(path).unwrap();
    let r = check(&src, 25.0);
    let errors: Vec<_> = r.diagnostics.iter().filter(|d| d.is_error()).collect();
    assert!(errors.is_empty(), "{:?}", r.diagnostics);
    assert_eq!(r.threads, 1);
    assert!(
        r.notes.iter().any(|n| n.message.contains(
            "the surface along the thread is Ø19.8 as the program turned it at line 7 (the bar Ø25 given)"
        )),
        "{:?}",
        r.notes
    );
    // Without the stock removal the thread is cut in the bar as it is: the cycle's rapids at
    // Ø24 (N90) and its retracts run through the Ø25 bar.
    let bare = src.replace(
        "N50 CYCLE95(\"CONT_A:CONT_E\", 1.5, 0.1, 0.2, , 0.25, 0.15, 0.1, 9, , , 0.5)",
        "",
    );
    let r = check(&bare, 25.0);
    assert!(
        r.diagnostics
            .iter()
            .any(|d| d.is_error() && d.code == Code::Collision),
        "{:?}",
        r.diagnostics
    );
}
