//! Haas lathes: the one-block G76 (P1–P4, A, I, Q), Settings 86/95/96/99 and M23/M24, G92 with I and
//! Q, G32 with Q, and the errors at their place (`docs/dialects/haas.md`). Every table below is
//! computed by hand from the laws in that page and compared at the program's resolution (0.0001 inch,
//! 0.001 mm), as the program would write the numbers.

use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::Machine;
use threadcut::program::{self, PassRow};
use threadcut::thread::{Exit, Job, PassKind};
use threadcut::toolpath::{self, MotionKind};

fn haas() -> Machine {
    Machine::built_in("haas").unwrap()
}

fn jobs_on(src: &str, m: &Machine) -> Vec<Job> {
    program::jobs(src.as_bytes(), m).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

fn jobs(src: &str) -> Vec<Job> {
    jobs_on(src, &haas())
}

fn error_on(src: &str, m: &Machine) -> Diagnostic {
    match program::jobs(src.as_bytes(), m) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an error, got {other:?}\n{src}"),
    }
}

fn rows(job: &Job) -> Vec<PassRow> {
    program::pass_rows(job, &job.passes().unwrap(), true)
}

/// The pass table (kind, X as written, Z) against a hand table, at `decimals` places.
fn assert_table(job: &Job, decimals: i32, want: &[(PassKind, f64, f64)]) {
    let got = rows(job);
    let scale = 10f64.powi(decimals);
    let at = |v: f64| (v * scale).round() as i64;
    assert_eq!(got.len(), want.len(), "pass count");
    for (r, &(kind, x, z)) in got.iter().zip(want) {
        assert_eq!(
            (r.kind, at(r.x), at(r.z)),
            (kind, at(x), at(z)),
            "pass {}: X{} Z{} (want X{x} Z{z})",
            r.n,
            r.x,
            r.z
        );
    }
}

fn expand(src: &str, m: &Machine) -> String {
    let mut out = Vec::new();
    program::expand_gcode(src.as_bytes(), &mut out, m).unwrap_or_else(|e| panic!("{e}"));
    String::from_utf8(out).unwrap()
}

use PassKind::{Finish, Rough};

/// 3/4-10 UNC external, as a Haas shop writes it (inch, diameter, A60, P1).
const THREE_QUARTER_TEN: &str = "%
O01010 (3/4-10 UNC OD THREAD)
G20 G99
T505 (OD THREAD 60 DEG)
G97 S900 M03
G00 X0.85 Z0.25 M08
G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60 P1
G00 X3. Z3. M09
M30
%
";

/// P1, inch, external: K .0614, D .02, Setting 99 .001, Setting 86 0. dₙ = .02·√n (no increment
/// falls below .001): .02, .028284, .034641, .04, .044721, .04899, .052915, .056569, .06, then
/// .063246 ≥ K, clipped to .0614. X = .75 − 2dₙ; single edge toward −Z: Z = .25 + (K − dₙ)·tan 30°.
#[test]
fn p1_inch_external_three_quarter_ten() {
    let job = &jobs(THREE_QUARTER_TEN)[0];
    assert_eq!(job.controller, "haas");
    assert_table(
        job,
        4,
        &[
            (Rough, 0.7100, 0.2739),
            (Rough, 0.6934, 0.2691),
            (Rough, 0.6807, 0.2654),
            (Rough, 0.6700, 0.2624),
            (Rough, 0.6606, 0.2596),
            (Rough, 0.6520, 0.2572),
            (Rough, 0.6442, 0.2549),
            (Rough, 0.6369, 0.2528),
            (Rough, 0.6300, 0.2508),
            (Rough, 0.6272, 0.2500),
        ],
    );
    // Setting 95 = 1 lead at Setting 96 = 45°: pass 1 ends at Z −1 + (K − .02)·tan 30° = −.9761,
    // its pull-out starts .1 before that and rises .1 (radius).
    let out = expand(THREE_QUARTER_TEN, &haas());
    assert!(
        out.contains("G0 X0.71 Z0.2739\nG32 X0.71 Z-0.8761 F0.1\nG32 X0.91 Z-0.9761 F0.1\nG0 X0.85 Z-0.9761\nG0 X0.85 Z0.25\n"),
        "{out}"
    );
    // The full-depth pass ends on the programmed point, its pull-out at Z−1.
    assert!(
        out.contains("G32 X0.6272 Z-0.9 F0.1\nG32 X0.8272 Z-1. F0.1\n"),
        "{out}"
    );
    // Every other line is copied.
    assert!(out.starts_with("%\nO01010 (3/4-10 UNC OD THREAD)\nG20 G99\nT505"));
    assert!(out.ends_with("G00 X3. Z3. M09\nM30\n%\n"));
}

/// P2, metric, internal M30×2 nut: start inside the bore at X27, root at the major diameter X30.
/// K 1.083, D .35, Setting 99 = .001" = .0254 mm (never reached). dₙ = .35·√n: .35, .494975,
/// .606218, .7, .782624, .857321, .926013, .989949, 1.05, then 1.106797 → 1.083. The crest (minor)
/// is X30 − 2K = 27.834; X = 27.834 + 2dₙ. Odd passes on the single edge, Z = 5 + (K − dₙ)·tan 30°;
/// even passes mirrored about the full-depth position, Z = 5 − (K − dₙ)·tan 30°.
#[test]
fn p2_metric_internal_alternates() {
    let src = "G21\nG00 X27. Z5.\nG76 X30. Z-25. K1.083 D0.35 F2. A60 P2\nG00 X27. Z50.\n";
    let job = &jobs(src)[0];
    assert_eq!(job.geometry.side, threadcut::thread::Side::Internal);
    assert_table(
        job,
        3,
        &[
            (Rough, 28.534, 5.423),
            (Rough, 28.824, 4.661),
            (Rough, 29.046, 5.275),
            (Rough, 29.234, 4.779),
            (Rough, 29.399, 5.173),
            (Rough, 29.549, 4.870),
            (Rough, 29.686, 5.091),
            (Rough, 29.814, 4.946),
            (Rough, 29.934, 5.019),
            (Rough, 30.000, 5.000),
        ],
    );
    // An internal pull-out leaves the part toward −X: pass 10 ends at X30 − 2·2 = 26 (radius 13).
    let path = toolpath::build(job).unwrap();
    let pull = path
        .motions
        .iter()
        .rfind(|m| m.pass == 10 && matches!(m.kind, MotionKind::Thread { .. }))
        .unwrap();
    assert!((pull.to.x - 13.0).abs() < 1e-9 && (pull.to.z + 25.0).abs() < 1e-9);
}

/// P3, inch, external taper (I −.025 over the 1" from Z.2 to Z−.8): constant depth dₙ = n·.012 =
/// .012, .024, .036, .048, then .06 → .05. The crest at the start is X.7 + 2·(−.025) + 2·.05 = .75.
#[test]
fn p3_inch_taper_constant_depth() {
    let src = "G20\nG00 X0.9 Z0.2\nG76 X0.7 Z-0.8 I-0.025 K0.05 D0.012 F0.0714 A60 P3\n";
    let job = &jobs(src)[0];
    assert_table(
        job,
        4,
        &[
            (Rough, 0.7260, 0.2219),
            (Rough, 0.7020, 0.2150),
            (Rough, 0.6780, 0.2081),
            (Rough, 0.6540, 0.2012),
            (Rough, 0.6500, 0.2000),
        ],
    );
    // The passes run parallel to the root: the last one from X.65 at Z.2 to X.7 at Z−.8 (radius
    // .35), its pull-out from one lead (.0714) before the end.
    let path = toolpath::build(job).unwrap();
    let last: Vec<_> = path
        .motions
        .iter()
        .filter(|m| m.pass == 5 && matches!(m.kind, MotionKind::Thread { .. }))
        .collect();
    let inch = |mm: f64| mm / 25.4;
    let z_break = -0.8 + 0.0714;
    assert!((inch(last[0].to.z) - z_break).abs() < 5e-5);
    assert!((inch(last[0].to.x) - (0.325 + 0.025 * (0.2 - z_break))).abs() < 5e-5);
    assert!((inch(last[1].to.z) + 0.8).abs() < 5e-5);
}

/// P4, metric, a two-start thread cut as two cycles (Q0, Q180000) with the chamfer off (M24):
/// lead 4, K 1.25, D .4, A30: dₙ = .4n = .4, .8, 1.2, 1.25; X = 19 − 2dₙ; Z = 3 ± (K − dₙ)·tan 15°.
#[test]
fn p4_metric_two_starts_by_q() {
    let src = "G21\nG00 X22. Z3.\nM24\nG76 X16.5 Z-20. K1.25 D0.4 F4. A30 P4 Q0\nG76 X16.5 Z-20. K1.25 D0.4 F4. A30 P4 Q180000\nM23\n";
    let js = jobs(src);
    assert_eq!(js.len(), 2);
    let table = [
        (Rough, 18.2, 3.228),
        (Rough, 17.4, 2.879),
        (Rough, 16.6, 3.013),
        (Rough, 16.5, 3.0),
    ];
    for job in &js {
        assert_table(job, 3, &table);
        assert_eq!(job.exit, Exit::Straight, "M24: no chamfer");
        assert_eq!(job.lead.starts, 1);
    }
    assert_eq!(js[0].lead.phase_deg, 0.0);
    assert_eq!(js[1].lead.phase_deg, 180.0);
    // The second start's synchronised moves carry the phase; expand writes Q on each pass's G32.
    let path = toolpath::build(&js[1]).unwrap();
    assert!(path.motions.iter().all(|m| match m.kind {
        MotionKind::Thread { phase_deg, .. } => phase_deg == 180.0,
        _ => true,
    }));
    let out = expand(src, &haas());
    assert!(
        out.contains("G0 X18.2 Z3.228\nG32 X18.2 Z-19.772 F4. Q180000\n"),
        "{out}"
    );
    assert_eq!(out.matches("Q180000\n").count(), 4, "one Q per pass: {out}");
    assert!(out.contains("G0 X18.2 Z3.228\nG32 X18.2 Z-19.772 F4.\n"));
}

#[test]
fn a_absent_is_a_plunge() {
    let src = "G20\nG00 X0.85 Z0.25\nG76 X0.6272 Z-1. K0.0614 D0.02 F0.1\n";
    let job = &jobs(src)[0];
    assert_eq!(job.infeed, threadcut::thread::Infeed::Radial);
    // Every pass starts at the start point's Z; the chip areas assume a 60° tool.
    assert!(rows(job).iter().all(|r| (r.z - 0.25).abs() < 1e-12));
    assert_eq!(job.tool_angle_deg, 60.0);
}

/// Setting 86 = .005 (one finishing pass at K), Setting 99 = .004: on the 3/4-10 cycle the √n
/// increments fall below .004 after pass 6: .04899 + .004 = .05299 (√7·.02 = .052915 is less), then
/// √8·.02 = .056569 < .05699 → .05699 ≥ K − .005 = .0564, clipped; then the finish at .0614.
#[test]
fn settings_86_and_99_from_the_profile() {
    let text = Machine::built_in("haas").unwrap();
    let mut m = text.clone();
    let mut s = m.haas.clone().unwrap();
    s.finish_allowance_in = 0.005;
    s.min_cut_in = 0.004;
    m.haas = Some(s);
    let job = &jobs_on(THREE_QUARTER_TEN, &m)[0];
    assert_table(
        job,
        4,
        &[
            (Rough, 0.7100, 0.2739),
            (Rough, 0.6934, 0.2691),
            (Rough, 0.6807, 0.2654),
            (Rough, 0.6700, 0.2624),
            (Rough, 0.6606, 0.2596),
            (Rough, 0.6520, 0.2572),
            (Rough, 0.6440, 0.2549),
            (Rough, 0.6372, 0.2529),
            (Finish, 0.6272, 0.2500),
        ],
    );
    // Setting 86 at or above K is refused at the cycle.
    let mut s = m.haas.clone().unwrap();
    s.finish_allowance_in = 0.07;
    m.haas = Some(s);
    let e = error_on(THREE_QUARTER_TEN, &m);
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Geometry, 7, 1));
    assert!(e.message.contains("Setting 86"), "{}", e.message);
}

#[test]
fn m24_turns_the_chamfer_off_m23_on() {
    let cycle = "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60\n";
    let src = format!(
        "G20\nG00 X0.85 Z0.25\n{cycle}M24\n{cycle}G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60 M23\n"
    );
    let js = jobs(&src);
    let one_lead = Exit::PullOut {
        start_before: 2.54,
        length: 2.54,
        outward: 2.54 * 45f64.to_radians().tan(),
    };
    assert_eq!(js[0].exit, one_lead);
    assert_eq!(js[1].exit, Exit::Straight);
    assert_eq!(js[2].exit, one_lead, "M23 on the cycle's own block");
    // Setting 95 = 0 is no chamfer either.
    let mut m = haas();
    let mut s = m.haas.clone().unwrap();
    s.chamfer_leads = 0.0;
    m.haas = Some(s);
    assert_eq!(jobs_on(&src, &m)[0].exit, Exit::Straight);
}

#[test]
fn g92_repeats_with_i_taper_and_q() {
    // A Haas G92 pass list, the second start by Q180000 on each of its passes.
    let src = "G20\nG00 X1.1 Z0.2\nG92 X0.98 Z-1. I-0.02 F0.125\nX0.96\nX0.95\nG92 X0.98 Z-1. I-0.02 F0.125 Q180000\nX0.96 Q180000\nX0.95\nG00 X2.\n";
    let mut warnings = Vec::new();
    let m = haas();
    let mut js = Vec::new();
    let summary = program::run(src.as_bytes(), &m, |_, ev| {
        if let program::Event::Cycle { job, .. } = ev {
            js.push(*job);
        }
        Ok(())
    })
    .unwrap();
    warnings.extend(summary.warnings);
    assert_eq!(js.len(), 6);
    // I is the radius at the start minus at the end: the cut starts at X.98 + 2·(−.02) = .94.
    let start_x: Vec<f64> = js
        .iter()
        .map(|j| j.geometry.crest_start.x * 2.0 / 25.4)
        .collect();
    for (got, want) in start_x.iter().zip([0.94, 0.92, 0.91, 0.94, 0.92, 0.91]) {
        assert!((got - want).abs() < 5e-5, "{start_x:?}");
    }
    let phases: Vec<f64> = js.iter().map(|j| j.lead.phase_deg).collect();
    assert_eq!(phases, [0.0, 0.0, 0.0, 180.0, 180.0, 0.0]);
    // Q is not modal: the last repeat starts at 0°, and the reader says so at its line.
    let w: Vec<_> = warnings
        .iter()
        .filter(|w| w.message.contains("not modal"))
        .collect();
    assert_eq!(w.len(), 1);
    assert_eq!(w[0].span.line, 8);
    // The chamfer is Settings 95/96: one lead (.125) at 45°.
    assert!(matches!(js[0].exit, Exit::PullOut { length, .. } if (length - 3.175).abs() < 1e-12));
}

#[test]
fn q_is_a_start_angle_in_thousandths() {
    let pre = "G20\nG00 X0.85 Z0.25\n";
    let one = |q: &str| {
        let src = format!("{pre}G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60 {q}\n");
        jobs(&src)[0].lead.phase_deg
    };
    assert_eq!(one("Q120000"), 120.0);
    assert_eq!(one("Q1"), 0.001);
    assert_eq!(
        one("Q360000"),
        0.0,
        "360° is the one-revolution signal again"
    );
}

#[test]
fn g32_q_and_e() {
    let pre = "G20\nG00 X0.95 Z0.2\n";
    // G32 and its Q pass through: the block is the modal reader's.
    let src = format!("{pre}G32 Z-1. F0.125 Q90000\nG00 X1.2\n");
    assert_eq!(expand(&src, &haas()), src);
    assert!(jobs(&src).is_empty());
    for (block, code, column, text) in [
        (
            "G32 Z-1. F0.125 Q90.",
            Code::Syntax,
            17,
            "without a decimal point",
        ),
        (
            "G32 Z-1. F0.125 Q361000",
            Code::OutOfRange,
            17,
            "0 to 360000",
        ),
        ("G32 Z-1. E0.125", Code::Unsupported, 10, "E is not a word"),
    ] {
        let e = error_on(&format!("{pre}{block}\n"), &haas());
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (code, 3, column),
            "{block}"
        );
        assert!(e.message.contains(text), "{block}: {}", e.message);
    }
    // While G32 is modal, a block of axis words with a Q is a thread move too.
    let e = error_on(&format!("{pre}G32 Z-0.5 F0.125\nX1. Z-1. Q-5\n"), &haas());
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::OutOfRange, 4, 10)
    );
    // Elsewhere Q is another word's (a G71 P..Q.. block): not checked as a start angle. (Haas's
    // one-block G71 reads Q20 as its contour's last block, which this program lacks.)
    let src = format!("{pre}G71 P10 Q20 U0.02 W0.005 D0.05 F0.01\nG00 X1.2\n");
    let e = error_on(&src, &haas());
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::MissingWord, 3, 1),
        "{}",
        e.message
    );
    assert!(e.message.contains("N10 is not found"), "{}", e.message);
}

#[test]
fn haas_alarms_at_line_and_column() {
    let pre = "G20\nG00 X0.85 Z0.25\n";
    let cases: &[(&str, Code, u32, &str)] = &[
        (
            "G76 X0.6272 Z-1. D0.02 F0.1 A60",
            Code::MissingWord,
            1,
            "needs K",
        ),
        (
            "G76 X0.6272 Z-1. K0 D0.02 F0.1 A60",
            Code::OutOfRange,
            18,
            "above zero",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 F0.1 A60",
            Code::MissingWord,
            1,
            "needs D",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D-0.02 F0.1",
            Code::OutOfRange,
            26,
            "unsigned",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A121",
            Code::OutOfRange,
            37,
            "0 to 120",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60.",
            Code::Syntax,
            37,
            "without a decimal point",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60 P5",
            Code::OutOfRange,
            41,
            "1 to 4",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60 Q180.",
            Code::Syntax,
            41,
            "without a decimal point",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60 Q400000",
            Code::OutOfRange,
            41,
            "0 to 360000",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 E0.1",
            Code::Conflict,
            37,
            "either F or E",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 A60",
            Code::MissingWord,
            1,
            "no lead",
        ),
        (
            "G76 Z-1. K0.0614 D0.02 F0.1 A60",
            Code::MissingWord,
            1,
            "X (or U)",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 R0.01",
            Code::Unsupported,
            37,
            "not a word",
        ),
        (
            "G00 G76 X0.6272 Z-1. K0.0614 D0.02 F0.1",
            Code::Conflict,
            1,
            "shares a block",
        ),
        (
            "G76 X0.6272 Z0.25 K0.0614 D0.02 F0.1",
            Code::Geometry,
            1,
            "no length",
        ),
        (
            "G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 I-1.3",
            Code::Geometry,
            1,
            "taper",
        ),
        (
            "G76 X0.8 Z-1. K0.0614 D0.02 F0.1",
            Code::Geometry,
            1,
            "inside the thread",
        ),
        (
            "G76 X0.85 Z-1. K0.0614 D0.02 F0.1",
            Code::Geometry,
            1,
            "external from an internal",
        ),
        (
            "G76 X0.6272 Z-0.2 K0.0614 D0.02 F0.5",
            Code::Geometry,
            1,
            "not shorter than the thread",
        ),
    ];
    for &(cycle, code, column, text) in cases {
        let e = error_on(&format!("{pre}{cycle}\n"), &haas());
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (code, 3, column),
            "{cycle}: {e}"
        );
        assert!(e.message.contains(text), "{cycle}: {}", e.message);
    }
}

#[test]
fn haas_two_block_g76_unknown_start_and_one_pass_depth() {
    let pre = "G20\nG00 X0.85 Z0.25\n";
    // The first block of the two-block G76: the hint names the form and the controller that reads it.
    let e = error_on(&format!("{pre}G76 P010060 Q0015 R0.001\n"), &haas());
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::MissingWord, 3, 1)
    );
    let hint = e.hint.unwrap();
    assert!(
        hint.contains("two-block") && hint.contains("--controller fanuc"),
        "{hint}"
    );
    // Before any position is known.
    let e = error_on("G20\nG76 X0.6272 Z-1. K0.0614 D0.02 F0.1\n", &haas());
    assert_eq!((e.code, e.span.line), (Code::UnknownPosition, 2));
    // D ≥ K cuts the thread in one pass: a warning, not an error.
    let summary = program::run(
        format!("{pre}G76 X0.6272 Z-1. K0.0614 D0.07 F0.1\n").as_bytes(),
        &haas(),
        |_, _| Ok(()),
    )
    .unwrap();
    assert!(summary
        .warnings
        .iter()
        .any(|w| w.code == Code::Suspicious && w.message.contains("one pass")));
}

/// `post` and `convert` write Haas's own cycles where they reproduce the motion: the one-block G76
/// (A, P, Q included) and G92 with I and Q; a job whose finishing allowance is not Setting 86's is
/// plain moves with the reason.
#[test]
fn native_cycles_read_back() {
    use threadcut::translate::{job_to_string, Written};
    let src = "G20\nG00 X0.9 Z0.3\nG76 X0.6273 Z-1.125 K0.0613 D0.015 F0.1 A60 P2 Q90000\nG92 X0.7 Z-1. I-0.02 F0.1 Q270000\n";
    let js = jobs(src);
    let (text, how) = job_to_string(&haas(), &js[0]).unwrap();
    assert_eq!(how, Written::Native, "{text}");
    assert_eq!(
        text,
        "G76 X0.6273 Z-1.125 K0.0613 D0.015 F0.1 A60 P2 Q90000\n"
    );
    let (text, how) = job_to_string(&haas(), &js[1]).unwrap();
    assert_eq!(how, Written::Native, "{text}");
    assert_eq!(text, "G92 X0.7 Z-1. I-0.02 F0.1 Q270000\n");
    // Fanuc's two-block G76 leaves 0.05 mm for its finishing passes; Haas's Setting 86 is 0.
    let fanuc = Machine::built_in("fanuc").unwrap();
    let job = &jobs_on(
        "G0 X32. Z5.\nG76 P011060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n",
        &fanuc,
    )[0];
    let (text, how) = job_to_string(&haas(), job).unwrap();
    assert!(
        matches!(how, Written::Plain(ref why) if why.contains("Setting 86")),
        "{text}"
    );
}

/// U/W are incremental X/Z from the start point (system A); E is the lead as F is, on G76 and G92.
#[test]
fn u_w_and_e_are_haas_words() {
    let pre = "G20\nG00 X0.85 Z0.25\n";
    let abs = &jobs(&format!("{pre}G76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60\n"))[0];
    let inc = &jobs(&format!(
        "{pre}G76 U-0.2228 W-1.25 K0.0614 D0.02 E0.1 A60\n"
    ))[0];
    threadcut::translate::same_motion(
        &toolpath::build(abs).unwrap(),
        &toolpath::build(inc).unwrap(),
        (1e-9, 1e-12),
    )
    .unwrap();
    let f = &jobs(&format!("{pre}G92 X0.7 Z-1. F0.1\n"))[0];
    let e = &jobs(&format!("{pre}G92 X0.7 Z-1. E0.1\n"))[0];
    assert_eq!(f.lead, e.lead);
    let err = error_on(&format!("{pre}G92 X0.7 Z-1. E0.1 F0.1\n"), &haas());
    assert_eq!(
        (err.code, err.span.line, err.span.column),
        (Code::Conflict, 3, 20)
    );
}

/// Every synchronised move of a program (from, to, lead, start angle), from plain blocks and
/// cycles alike.
fn thread_moves(src: &str) -> Vec<(threadcut::units::Pos, threadcut::units::Pos, f64, f64)> {
    let mut moves = Vec::new();
    program::run(src.as_bytes(), &haas(), |_, ev| {
        match ev {
            program::Event::Plain { mv: Some(mv), .. } if mv.lead.is_some() => {
                let from = mv.from.known().expect("a thread move from a known start");
                moves.push((from, mv.to, mv.lead.unwrap(), mv.phase_deg))
            }
            program::Event::Cycle { job, .. } => {
                for (from, m) in toolpath::build(&job)?.segments() {
                    if let MotionKind::Thread {
                        lead, phase_deg, ..
                    } = m.kind
                    {
                        moves.push((from, m.to, lead, phase_deg));
                    }
                }
            }
            _ => {}
        }
        Ok(())
    })
    .unwrap_or_else(|e| panic!("{e}\n{src}"));
    moves
}

#[test]
fn plain_g32_q_starts_a_run_at_its_angle() {
    // Q90000 begins a run at 90°; the pull-out that continues it (G32 modal, no Q) is part of the
    // same run; after a rapid a G32 without Q starts at 0°.
    let src = "G20\nG00 X0.95 Z0.2\nG32 Z-1. F0.125 Q90000\nX1.05 Z-1.1\nM08\nG32 X1.1 Z-1.2\nG00 X1.2\nZ0.2\nG32 X0.95 Z-1. F0.125\n";
    let phases: Vec<f64> = thread_moves(src).iter().map(|m| m.3).collect();
    assert_eq!(phases, [90.0, 90.0, 90.0, 0.0]);
    // The block still passes through as written.
    assert_eq!(expand(src, &haas()), src);
}

#[test]
fn expansions_read_back_with_their_start_angles() {
    let src = include_str!("../examples/haas-m24x3-two-start.nc");
    let mut out = Vec::new();
    program::expand_gcode(src.as_bytes(), &mut out, &haas()).unwrap();
    let expanded = String::from_utf8(out).unwrap();
    assert!(expanded.contains(" Q180000\n"), "{expanded}");
    let (a, b) = (thread_moves(src), thread_moves(&expanded));
    assert_eq!(a.len(), b.len(), "{expanded}");
    assert!(a.iter().any(|m| m.3 == 180.0) && a.iter().any(|m| m.3 == 0.0));
    // X on diameter to 0.001 mm: within half a step on the radius.
    let tol = 0.0005 + 1e-9;
    for (x, y) in a.iter().zip(&b) {
        let near = |p: f64, q: f64| (p - q).abs() <= tol;
        assert!(
            near(x.0.x, y.0.x) && near(x.0.z, y.0.z) && near(x.1.x, y.1.x) && near(x.1.z, y.1.z),
            "{x:?} vs {y:?}"
        );
        assert!((x.2 - y.2).abs() <= 1e-6, "lead {x:?} vs {y:?}");
        assert!(
            threadcut::translate::same_angle(x.3, y.3),
            "start angle {x:?} vs {y:?}"
        );
    }
}
