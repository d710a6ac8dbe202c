//! Fanuc's FS15 program format (`--controller fanuc15`): the one-block G76 X Z I K D F A P Q with
//! parameters 5130–5143 behind it, G92 with an I taper and a Q start angle (`docs/dialects/fanuc.md`,
//! "FS15 program format"). Tables are computed by hand and compared at the program's resolution.

use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::thread::{Job, PassKind, Side};
use threadcut::toolpath;
use threadcut::translate;

fn machine(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

fn jobs_on(src: &str, m: &Machine) -> Vec<Job> {
    program::jobs(src.as_bytes(), m).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

fn jobs(src: &str) -> Vec<Job> {
    jobs_on(src, &machine("fanuc15"))
}

fn error(src: &str) -> Diagnostic {
    match program::jobs(src.as_bytes(), &machine("fanuc15")) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an error, got {other:?}"),
    }
}

fn assert_table(job: &Job, decimals: i32, want: &[(PassKind, f64, f64)]) {
    let got = program::pass_rows(job, &job.passes().unwrap(), true);
    let at = |v: f64| (v * 10f64.powi(decimals)).round() as i64;
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

fn same_motion(a: &Job, b: &Job) {
    let (pa, pb) = (toolpath::build(a).unwrap(), toolpath::build(b).unwrap());
    translate::same_motion(&pa, &pb, (1e-9, 1e-12)).unwrap_or_else(|e| panic!("{e}"));
}

use PassKind::{Finish, Rough};

/// M30×2 external in an FS15 shop's style. Parameters (profile): 5140 Δdmin .1, 5141 d .05, 5142 m
/// 1, 5130 one-lead chamfer. dₙ = .4·√n, increments at least .1: .4, .565685, .69282, .8, then .9,
/// 1.0, 1.1 (√n·.4 falls behind), 1.177 = K − d; one finishing pass at 1.227. X = 30 − 2dₙ, Z = 5 +
/// (K − dₙ)·tan 30°, the finish on the groove's axis at Z5.
const M30_FS15: &str = "%
O1530 (M30X2 OD THREAD - FS15 FORMAT)
G21 G99
G28 U0. W0.
T0707
G97 S600 M03
G00 X32. Z5. M08
G76 X27.546 Z-30. K1.227 D0.4 F2. A60 P1
G00 X100. Z100. M09
M30
%
";

#[test]
fn p1_metric_external_table() {
    let job = &jobs(M30_FS15)[0];
    assert_eq!(job.controller, "fanuc15");
    assert_table(
        job,
        3,
        &[
            (Rough, 29.200, 5.477),
            (Rough, 28.869, 5.382),
            (Rough, 28.614, 5.308),
            (Rough, 28.400, 5.247),
            (Rough, 28.200, 5.189),
            (Rough, 28.000, 5.131),
            (Rough, 27.800, 5.073),
            (Rough, 27.646, 5.029),
            (Finish, 27.546, 5.000),
        ],
    );
}

/// The one-block form and the standard format's two blocks are one cycle: with the same
/// parameters (m 1, r 10, a 60, Δdmin .1, d .05) they move the tool identically.
#[test]
fn one_block_is_the_two_block_cycle() {
    let two = "G21\nG00 X32. Z5.\nG76 P011060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";
    let a = &jobs_on(two, &machine("fanuc"))[0];
    let b = &jobs(M30_FS15)[0];
    same_motion(a, b);
}

/// A absent is parameter 5143 (60°); P3 constant depth, inch, internal, tapered (I +.01: the root
/// at the start is .01 larger in radius): 1-8 internal, K .0677, D .02, d = .05 mm = .0019685":
/// dₙ = .02, .04, .06, then .08 → K − d = .0657315; finish at K. The crest (minor) at the start is
/// 2·(.51 − .0677) = .8846; X = .8846 + 2dₙ; Z = .2 + (K − dₙ)·tan 30°.
#[test]
fn p3_inch_internal_taper_with_the_parameter_angle() {
    let src = "G20\nG00 X0.8 Z0.2\nG76 X1. Z-1.2 I0.01 K0.0677 D0.02 F0.125 P3\n";
    let job = &jobs(src)[0];
    assert_eq!(job.geometry.side, Side::Internal);
    assert_eq!(job.tool_angle_deg, 60.0);
    assert_table(
        job,
        4,
        &[
            (Rough, 0.9246, 0.2275),
            (Rough, 0.9646, 0.2160),
            (Rough, 1.0046, 0.2044),
            (Rough, 1.0161, 0.2011),
            (Finish, 1.0200, 0.2000),
        ],
    );
}

/// P2 and P4 alternate; A0 is a plunge whatever P says (P1 ≡ P2 there).
#[test]
fn p2_p4_alternate_and_a0_plunges() {
    let pre = "G21\nG00 X32. Z5.\n";
    let job = |p: &str| jobs(&format!("{pre}G76 X27.546 Z-30. K1.227 D0.4 F2. {p}\n"))[0].clone();
    let p2 = job("A60 P2");
    let rows = program::pass_rows(&p2, &p2.passes().unwrap(), true);
    // Pass 1 on the single edge (Z5.477, as P1), pass 2 mirrored: 5 − (K − .565685)·tan 30°.
    assert!((rows[0].z - 5.477).abs() < 5e-4 && (rows[1].z - 4.618).abs() < 5e-4);
    // P4: dₙ = .4n: .4, .8, then 1.2 → 1.177; finish 1.227.
    let p4 = job("A60 P4");
    let d: Vec<f64> = p4.passes().unwrap().iter().map(|p| p.depth).collect();
    assert_eq!(d.len(), 4);
    for (got, want) in d.iter().zip([0.4, 0.8, 1.177, 1.227]) {
        assert!((got - want).abs() < 1e-12, "{d:?}");
    }
    same_motion(&job("A0 P1"), &job("A0 P2"));
}

/// A two-start thread as two cycles, Q0 and Q180000 (lead 4): the same passes, the second half a
/// turn later; P absent is P1.
#[test]
fn two_starts_by_q() {
    let src = "G21\nG00 X32. Z5.\nG76 X27.546 Z-30. K1.227 D0.4 F4. A60 Q0\nG76 X27.546 Z-30. K1.227 D0.4 F4. A60 Q180000\n";
    let js = jobs(src);
    assert_eq!((js[0].lead.phase_deg, js[1].lead.phase_deg), (0.0, 180.0));
    let (a, b) = (
        toolpath::build(&js[0]).unwrap(),
        toolpath::build(&js[1]).unwrap(),
    );
    assert_eq!(a.motions.len(), b.motions.len());
    for (m, n) in a.motions.iter().zip(&b.motions) {
        assert_eq!(m.to, n.to);
    }
    // The one-block G76 writes the start angle back: the native cycle reads back with it.
    let (text, how) = translate::job_to_string(&machine("fanuc15"), &js[1]).unwrap();
    assert_eq!(how, translate::Written::Native, "{text}");
    assert!(
        text.starts_with("G76 X27.546 Z-30. K1.227 D0.4 F4. A60 P1 Q180000"),
        "{text}"
    );
    // The standard format's two-block G76 cannot: plain moves with Q on each pass, and the reason.
    let (text, how) = translate::job_to_string(&machine("fanuc"), &js[1]).unwrap();
    assert!(
        matches!(how, translate::Written::Plain(ref why) if why.contains("start angle")),
        "{text}"
    );
    assert!(text.contains("G32 X29.2 Z-25.523 F4. Q180000\n"), "{text}");
}

/// G92's taper is I in the FS15 format (R is refused), and it takes Q.
#[test]
fn g92_with_i_and_q() {
    let js = jobs("G21\nG00 X40. Z5.\nG92 X29.2 Z-30. I-0.5 F2. Q90000\nX28.6 Q90000\n");
    assert_eq!(js[0].geometry.crest_start.x, 14.1);
    assert_eq!(js[1].geometry.crest_start.x, 13.8, "the repeat keeps I");
    assert_eq!((js[0].lead.phase_deg, js[1].lead.phase_deg), (90.0, 90.0));
    let e = error("G21\nG00 X40. Z5.\nG92 X29.2 Z-30. R-0.5 F2.\n");
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::Unsupported, 3, 17)
    );
    // Read back as G92 with I and Q.
    let (text, how) = translate::job_to_string(&machine("fanuc15"), &js[0]).unwrap();
    assert_eq!(how, translate::Written::Native);
    assert_eq!(text, "G92 X29.2 Z-30. I-0.5 F2. Q90000\n");
}

#[test]
fn fs15_alarms_at_line_and_column() {
    let pre = "G21\nG00 X32. Z5.\n";
    for (block, code, column, text) in [
        (
            "G76 X27.546 Z-30. K0 D0.4 F2.",
            Code::OutOfRange,
            19,
            "PS0062",
        ),
        (
            "G76 X27.546 Z-30. K1.227 D0 F2.",
            Code::OutOfRange,
            26,
            "PS0062",
        ),
        (
            "G76 X27.546 Z-30. K1.227 D0.4 E2.",
            Code::Unsupported,
            31,
            "E on G76",
        ),
        (
            "G76 X27.546 Z-30. K1.227 D0.4 F2. A130",
            Code::OutOfRange,
            35,
            "0 to 120",
        ),
        (
            "G76 X27.546 Z-30. K1.227 D0.4 F2. P0",
            Code::OutOfRange,
            35,
            "1 to 4",
        ),
        (
            "G76 X27.546 Z-30. K1.227 D0.4 F2. Q-1",
            Code::OutOfRange,
            35,
            "0 to 360000",
        ),
        (
            "G76 X27.546 Z-30. K1.227 D0.4",
            Code::MissingWord,
            1,
            "no lead",
        ),
    ] {
        let e = error(&format!("{pre}{block}\n"));
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (code, 3, column),
            "{block}: {e}"
        );
        assert!(e.message.contains(text), "{block}: {}", e.message);
    }
    // The standard format's first block on an FS15 control.
    let e = error(&format!("{pre}G76 P011060 Q100 R0.05\n"));
    assert_eq!(e.code, Code::MissingWord);
    assert!(e.hint.unwrap().contains("two-block"));
}

/// Allen-Bradley's G78 is FS15's G76 (the inference `docs/dialects/allen-bradley-g78.md` records),
/// and threadcut reads both with one cycle: with the same machine values they move alike.
#[test]
fn ab9_g78_and_fs15_g76_are_one_cycle() {
    // ab9's AMP: no allowance, one spring pass, minimum cut .001", no pull-out.
    let mut fs15 = machine("fanuc15");
    let p = fs15.fanuc.as_mut().unwrap();
    p.p5130 = 0;
    p.p5140 = 0.0254;
    p.p5141 = 0.0;
    p.p5142 = 1;
    for (p, a) in [("P1", "A60"), ("P2", "A60"), ("P3", "A29"), ("P4", "A0")] {
        let cycle = format!("X0.6272 Z-1. K0.0614 D0.02 F0.1 {a} {p}");
        let ab = &jobs_on(
            &format!("G20\nG0 X0.85 Z0.25\nG78 {cycle}\n"),
            &machine("ab9"),
        )[0];
        let f = &jobs_on(&format!("G20\nG0 X0.85 Z0.25\nG76 {cycle}\n"), &fs15)[0];
        same_motion(ab, f);
    }
}
