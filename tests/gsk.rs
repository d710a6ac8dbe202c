//! GSK G78 (seed 001) pinned with exact numbers: the seed's example, hand-computed cases, every alarm,
//! and properties over random cycles. Section numbers (§) refer to shared/reference/gsk-g78-english.md.
//! Expected values are computed by hand from the seed's formulas and written out as literals.

use proptest::prelude::*;

use threadcut::diag::{Code, Diagnostic};
use threadcut::gcode::MotionMode;
use threadcut::machine::Machine;
use threadcut::program::{self, Event};
use threadcut::thread::{Pass, PassKind};
use threadcut::toolpath::{self, MotionKind, Toolpath};
use threadcut::units::Pos;

const TAN30: f64 = 0.577_350_269_189_625_8;
const TAN22_5: f64 = 0.414_213_562_373_095_03;

fn gsk() -> Machine {
    Machine::built_in("gsk980").unwrap()
}

fn passes(src: &str) -> Vec<Pass> {
    let jobs = program::jobs(src.as_bytes(), &gsk()).unwrap_or_else(|e| panic!("{e}"));
    jobs[0].passes().unwrap()
}

fn path(src: &str) -> Toolpath {
    let jobs = program::jobs(src.as_bytes(), &gsk()).unwrap_or_else(|e| panic!("{e}"));
    toolpath::build(&jobs[0]).unwrap()
}

fn error(src: &str) -> Diagnostic {
    match program::jobs(src.as_bytes(), &gsk()) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an input error, got {other:?}"),
    }
}

fn expand(src: &str) -> String {
    let mut out = Vec::new();
    program::expand_gcode(src.as_bytes(), &mut out, &gsk()).unwrap();
    String::from_utf8(out).unwrap()
}

#[track_caller]
fn close(a: f64, b: f64) {
    assert!((a - b).abs() < 1e-6, "{a} != {b}");
}

/// Depths (radius), diameter X and Z of each pass's infeed point.
#[track_caller]
fn assert_passes(got: &[Pass], expect: &[(PassKind, f64, f64, f64)]) {
    assert_eq!(got.len(), expect.len(), "{got:#?}");
    for (p, &(kind, depth, x_dia, z)) in got.iter().zip(expect) {
        assert_eq!(p.kind, kind, "pass {}", p.n);
        close(p.depth, depth);
        close(p.start.x * 2.0, x_dia);
        close(p.start.z, z);
    }
}

use PassKind::{Finish as F, Rough as R};

// ---------------------------------------------------------------------------------------------
// The seed's example (§13)

const SEED_EXAMPLE: &str =
    "G00 X80 Z10\nG78 P020545 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F300 J1.5 K2\nG00 X80 Z10\n";

#[test]
fn seed_example_as_printed_is_refused_at_its_infeed_mode() {
    // P020545 packs r = 05, outside the 0–4 range of §3 and parameter 5144 (docs/dialects/gsk-g78.md).
    let e = error(SEED_EXAMPLE);
    assert_eq!(e.code, Code::OutOfRange);
    assert_eq!((e.span.line, e.span.column, e.span.len), (2, 8, 2));
    assert!(e.message.contains("P(r)=05"), "{}", e.message);
}

#[test]
fn seed_example_with_centre_line_infeed_and_its_300mm_lead() {
    // r taken as 0; F300 kept as printed: it is inside the F range (§4), so it runs, with a warning.
    let src = SEED_EXAMPLE.replace("P020545", "P020045");
    let mut warnings = Vec::new();
    let jobs = {
        let mut jobs = Vec::new();
        let summary = program::run(src.as_bytes(), &gsk(), |_, ev| {
            if let Event::Cycle { job, .. } = ev {
                jobs.push(*job);
            }
            Ok(())
        })
        .unwrap();
        warnings.extend(summary.warnings);
        jobs
    };
    assert_eq!(warnings.len(), 1);
    assert_eq!(warnings[0].code, Code::Suspicious);
    assert_eq!(warnings[0].span.line, 3);
    assert_eq!(jobs[0].lead.lead, 300.0);
    // k 3, d 0.5 → rough limit 2.5; Δd 1.8 → 1.8, then √2·1.8 = 2.546 ≥ 2.5 → 2.5; m = 2 finishing at 3.
    let p = jobs[0].passes().unwrap();
    assert_passes(
        &p,
        &[
            (R, 1.8, 62.4, 10.0),
            (R, 2.5, 61.0, 10.0),
            (F, 3.0, 60.0, 10.0),
            (F, 3.0, 60.0, 10.0),
        ],
    );
    // Sharp 45° V: area d²·tan 22.5°.
    close(p[0].area, 1.8 * 1.8 * TAN22_5);
    close(p[1].area, (2.5 * 2.5 - 1.8 * 1.8) * TAN22_5);
    close(p[2].area, (9.0 - 6.25) * TAN22_5);
    close(p[3].area, 0.0);
}

#[test]
fn seed_example_motion_follows_the_execution_sequence() {
    // §11: rapid A → infeed point; thread to K before the end; tail-out J (radius) over K; rapid X
    // then Z back to A. With F3 the motion is the same shape as with F300, only the lead differs.
    let src = SEED_EXAMPLE
        .replace("P020545", "P020045")
        .replace("F300", "F3");
    let out = expand(&src);
    let expected = "\
G00 X80 Z10
(threadcut: line 2 sets the cycle that follows)
(threadcut: gsk980 cycle of line 3 as 2 rough passes and 2 finishing passes)
G0 X62.4 Z10.
G32 X62.4 Z-58. F3.
G32 X65.4 Z-60. F3.
G0 X80. Z-60.
G0 X80. Z10.
G0 X61. Z10.
G32 X61. Z-58. F3.
G32 X64. Z-60. F3.
G0 X80. Z-60.
G0 X80. Z10.
G0 X60. Z10.
G32 X60. Z-58. F3.
G32 X63. Z-60. F3.
G0 X80. Z-60.
G0 X80. Z10.
G0 X60. Z10.
G32 X60. Z-58. F3.
G32 X63. Z-60. F3.
G0 X80. Z-60.
G0 X80. Z10.
G00 X80 Z10
";
    assert_eq!(out, expected);
}

// ---------------------------------------------------------------------------------------------
// Hand-computed cases

#[test]
fn min_cut_takes_over_left_flank_infeed() {
    // M30×2 external, k = 0.6134·2 = 1.227 → root Ø27.546; Δd 0.4, Δdmin 0.1, d 0.05, m 2, a 60°.
    // √n·0.4: 0.4, 0.565685, 0.692820, 0.8; then √5·0.4 = 0.894 < 0.8 + 0.1 → Δdmin rules: 0.9, 1.0,
    // 1.1; 1.2 ≥ k − d = 1.177 → 1.177. Mode 1: Z = 5 + depth·tan 30°; finishing at the last rough Z.
    let p = passes("G0 X32 Z5\nG78 P020160 Q0.1 R0.05\nG78 X27.546 Z-30 P1.227 Q0.4 F2\n");
    let z = |d: f64| 5.0 + d * TAN30;
    let rough = [
        0.4,
        0.565_685_424_949_238,
        0.692_820_323_027_551,
        0.8,
        0.9,
        1.0,
        1.1,
        1.177,
    ];
    let mut expect: Vec<_> = rough
        .iter()
        .map(|&d| (R, d, 30.0 - 2.0 * d, z(d)))
        .collect();
    expect.push((F, 1.227, 27.546, z(1.177)));
    expect.push((F, 1.227, 27.546, z(1.177)));
    assert_passes(&p, &expect);
    // Single-flank passes share one flank: the groove is one V; the first finishing pass cuts the rest.
    close(p[0].area, 0.16 * TAN30);
    close(p[4].area, (0.81 - 0.64) * TAN30);
    close(p[8].area, (1.227f64.powi(2) - 1.177f64.powi(2)) * TAN30);
    close(p.iter().map(|p| p.area).sum(), 1.227f64.powi(2) * TAN30);
}

#[test]
fn internal_equal_distance_right_flank_with_lead_in() {
    // Internal: A (Ø20) is below C (Ø24) → positive-direction infeed (§8). D0: every pass Δd = 0.3
    // up to k − d = 0.9. Mode 2: Z = 5 − depth·tan 30°. Crest Ø22 = root Ø24 − 2k.
    let src = "G0 X20 Z5\nG78 P010260 Q0 R0.1 D0 E0.5\nG78 X24 Z-20 P1.0 Q0.3 F1.5\n";
    let z = |d: f64| 5.0 - d * TAN30;
    assert_passes(
        &passes(src),
        &[
            (R, 0.3, 22.6, z(0.3)),
            (R, 0.6, 23.2, z(0.6)),
            (R, 0.9, 23.8, z(0.9)),
            (F, 1.0, 24.0, z(0.9)),
        ],
    );
    // §10: rapid to E (radius) short of the infeed point, screw in synchronised, then thread W = −25.
    let path = path(src);
    let m = &path.motions;
    assert_eq!(m[0].kind, MotionKind::Rapid);
    close(m[0].to.x, 11.3 - 0.5);
    assert!(matches!(m[1].kind, MotionKind::Thread { lead, .. } if lead == 1.5));
    assert_eq!(m[1].to, Pos::new(11.3, z(0.3)));
    close(m[2].to.z, z(0.3) - 25.0);
    // No J/K and parameter 5130 = 0: no tail-out; rapid X to A, then Z to A.
    assert_eq!(m[3].to, Pos::new(10.0, m[2].to.z));
    assert_eq!(m[4].to, Pos::new(10.0, 5.0));
}

#[test]
fn external_taper_alternating_left_right_inch_lead_via_i() {
    // I14 → lead 25.4/14 mm. R(i) = −1.5: C at radius 20 − 1.5 = 18.5, crest 19.6 → 21.1 at the end.
    // √n law, Δdmin 0.05, limit 1.08. Mode 4: odd passes Z = 3 + d·t; even passes mirror them about
    // the groove's axis 3 + k·t, i.e. Z = 3 + (2k − d)·t (docs/dialects/gsk-g78.md).
    let src = "G0 X50 Z3\nG78 P010460 Q0.05 R0.02\nG78 X40 Z-30 R-1.5 P1.1 Q0.45 I14\n";
    let jobs = program::jobs(src.as_bytes(), &gsk()).unwrap();
    close(jobs[0].lead.lead, 25.4 / 14.0);
    let d = [
        0.45,
        0.636_396_103_067_893,
        0.779_422_863_405_995,
        0.9,
        1.006_230_589_874_906,
        1.08,
    ];
    let z = |n: usize, d: f64| {
        if n % 2 == 1 {
            3.0 + d * TAN30
        } else {
            3.0 + (2.2 - d) * TAN30
        }
    };
    let mut expect: Vec<_> = d
        .iter()
        .enumerate()
        .map(|(i, &d)| (R, d, 39.2 - 2.0 * d, z(i + 1, d)))
        .collect();
    expect.push((F, 1.1, 37.0, z(6, 1.08)));
    assert_passes(&jobs[0].passes().unwrap(), &expect);
    // The thread move runs along the taper: X grows by 1.5 (radius) over W = −33.
    let path = toolpath::build(&jobs[0]).unwrap();
    close(path.motions[1].to.x - path.motions[0].to.x, 1.5);
    close(path.motions[1].to.z - path.motions[0].to.z, -33.0);
}

#[test]
fn right_centre_alternating_single_rough_pass_and_modal_tail_out() {
    // Δd 0.8 ≥ k − d = 0.5: one rough pass at 0.5. m = 3. Mode 3 starts on the right: Z = 2 − d·t.
    // J0.5 without K: K = J (980TDi rule). Tail-out starts K before the pass end, rises J (radius).
    let src = "G0 X30 Z2\nG78 P030360 Q0.1 R0.1\nG78 X25 Z-15 P0.6 Q0.8 F1 J0.5\n";
    let z = 2.0 - 0.5 * TAN30;
    assert_passes(
        &passes(src),
        &[
            (R, 0.5, 25.2, z),
            (F, 0.6, 25.0, z),
            (F, 0.6, 25.0, z),
            (F, 0.6, 25.0, z),
        ],
    );
    let m = path(src).motions;
    assert_eq!(m[1].to, Pos::new(12.6, z - 17.0 + 0.5));
    assert_eq!(m[2].to, Pos::new(12.6 + 0.5, z - 17.0));
    // J and K are modal: a second cycle without them keeps the same tail-out.
    let two = format!("{src}G78 X25 Z-15 P0.6 Q0.8 F1\n");
    let jobs = program::jobs(two.as_bytes(), &gsk()).unwrap();
    assert_eq!(jobs[0].exit, jobs[1].exit);
}

#[test]
fn inch_program_in_g20() {
    // G20: every length in inches. k 0.06, Δd 0.02, Δdmin 0.002, d 0.001 → limit 0.059.
    let src = "G20 G0 X1.2 Z0.2\nG78 P010060 Q0.002 R0.001\nG78 X0.9 Z-1 P0.06 Q0.02 F0.1\n";
    let jobs = program::jobs(src.as_bytes(), &gsk()).unwrap();
    let p = jobs[0].passes().unwrap();
    let inch = [
        0.02,
        0.028_284_271_247_461_9,
        0.034_641_016_151_377_55,
        0.04,
        0.044_721_359_549_995_8,
        0.048_989_794_855_663_56,
        0.052_915_026_221_291_81,
        0.056_568_542_494_923_8,
        0.059,
        0.06,
    ];
    assert_eq!(p.len(), inch.len());
    for (p, d) in p.iter().zip(inch) {
        close(p.depth, d * 25.4);
        close(p.start.x, (0.51 - d) * 25.4);
    }
    close(jobs[0].lead.lead, 2.54);
    let jsonl = {
        let mut out = Vec::new();
        program::expand_jsonl(src.as_bytes(), &mut out, &gsk()).unwrap();
        String::from_utf8(out).unwrap()
    };
    // JSON lines are in program units with X as a radius: the first thread move ends at Z0.2 − 1.2.
    // The G20 G0 block comes from an unknown position to a known one: it is reported, marked as
    // such; the cycle's rapid follows.
    let first: serde_json::Value = serde_json::from_str(jsonl.lines().next().unwrap()).unwrap();
    assert_eq!(first["start_unknown"], serde_json::json!(["x", "z"]));
    let thread: serde_json::Value = serde_json::from_str(jsonl.lines().nth(2).unwrap()).unwrap();
    assert_eq!(thread["kind"], "thread");
    close(thread["x"].as_f64().unwrap(), 0.49);
    close(thread["z"].as_f64().unwrap(), -1.0);
    close(thread["lead"].as_f64().unwrap(), 0.1);
    assert_eq!(thread["pass"], 1);
    assert_eq!(thread["line"], 3);
}

#[test]
fn parameters_fill_the_missing_first_block() {
    // No first block: 5140–5145 of the profile (Δdmin 0.1, d 0.05, m 1, a 60, r 0, D 1).
    let p = passes("G0 X32 Z5\nG78 X27.546 Z-30 P1.227 Q0.4 F2\n");
    assert_eq!(p.iter().filter(|p| p.kind == F).count(), 1);
    close(p[p.len() - 2].depth, 1.177);
    assert!(p.iter().all(|p| p.start.z == 5.0));
    // Parameter 5130 (0.1 lead units) and 5131 give the tail-out when J and K were never written.
    let mut m = gsk();
    m.gsk.as_mut().unwrap().p5130 = 10;
    m.gsk.as_mut().unwrap().p5131 = 30;
    let jobs = program::jobs(&b"G0 X32 Z5\nG78 X27.546 Z-30 P1.227 Q0.4 F2\n"[..], &m).unwrap();
    match jobs[0].exit {
        threadcut::thread::Exit::PullOut {
            start_before,
            length,
            outward,
        } => {
            close(start_before, 2.0);
            close(length, 2.0);
            close(outward, 2.0 * TAN30);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn multi_start_cuts_every_start_at_each_depth() {
    let src = "G0 X32 Z5\nG78 P010060 Q0.1 R0.05 L2\nG78 X27.546 Z-30 P1.227 Q0.6 F4\n";
    let path = path(src);
    let starts: Vec<f64> = path
        .segments()
        .filter(|(from, m)| {
            matches!(m.kind, MotionKind::Thread { .. }) && from.x < 15.0 && m.pass == 1
        })
        .map(|(from, _)| from.z)
        .collect();
    // Second start 4/2 = 2 mm further from the part.
    assert_eq!(starts, vec![5.0, 7.0]);
}

// ---------------------------------------------------------------------------------------------
// Alarms and ranges: message, line and column

#[track_caller]
fn assert_error(src: &str, code: Code, line: u32, column: u32, text: &str) {
    let e = error(src);
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (code, line, column),
        "{e}"
    );
    assert!(e.message.contains(text), "{:?} lacks {text:?}", e.message);
}

#[test]
fn alarms_for_missing_height_and_first_depth() {
    assert_error(
        "G0 X32 Z5\nG78 X27 Z-30 Q0.4 F2\n",
        Code::MissingWord,
        2,
        1,
        "P(k) is missing",
    );
    assert_error(
        "G0 X32 Z5\n  G78 X27 Z-30 P1 F2\n",
        Code::MissingWord,
        2,
        3,
        "Q(Δd) is missing",
    );
}

#[test]
fn words_out_of_range_name_word_value_and_range() {
    let c = "G0 X32 Z5\n";
    assert_error(
        &format!("{c}G78 X27 Z-30 P0 Q0.4 F2\n"),
        Code::OutOfRange,
        2,
        14,
        "P(k)=0 is out of range: G78 allows 0.001 to 999999.999",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 F10000\n"),
        Code::OutOfRange,
        2,
        22,
        "F (lead)=10000",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 I300\n"),
        Code::OutOfRange,
        2,
        22,
        "0.0001 to 254",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 F2 J-1\n"),
        Code::OutOfRange,
        2,
        25,
        "J (tail-out, short axis)=-1",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 R-1000000 P1 Q0.4 F2\n"),
        Code::OutOfRange,
        2,
        14,
        "R(i)=-1000000",
    );
    assert_error(
        &format!("{c}G78 P000060\n"),
        Code::OutOfRange,
        2,
        6,
        "P(m)=00",
    );
    assert_error(
        &format!("{c}G78 P010160 D2\n"),
        Code::OutOfRange,
        2,
        13,
        "D (depth mode)=2",
    );
    assert_error(
        &format!("{c}G78 P010160 L0\n"),
        Code::OutOfRange,
        2,
        13,
        "L (number of starts)=0",
    );
    assert_error(
        &format!("{c}G78 P010160 Q-0.1\n"),
        Code::OutOfRange,
        2,
        13,
        "Q(Δdmin)=-0.1",
    );
    assert_error(
        &format!("{c}G78 P1.5\n"),
        Code::Syntax,
        2,
        5,
        "is not P(m)(r)(a)",
    );
    assert_error(
        &format!("{c}G78 P0101601\n"),
        Code::Syntax,
        2,
        5,
        "is not P(m)(r)(a)",
    );
    // ISC inch: the table's tighter range applies.
    let mut m = gsk();
    m.increment_system = threadcut::machine::IncrementSystem::Isc;
    let e = match program::jobs(&b"G20 G0 X2 Z1\nG78 X1.5 Z-1 P10000 Q0.1 F0.1\n"[..], &m) {
        Err(program::Error::Input(d)) => d,
        other => panic!("{other:?}"),
    };
    assert!(
        e.message.contains("0.00001 to 9999.99999 (ISC, inch)"),
        "{}",
        e.message
    );
}

#[test]
fn cycle_errors_that_a_careful_control_refuses() {
    let c = "G0 X32 Z5\n";
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4\n"),
        Code::MissingWord,
        2,
        1,
        "no lead",
    );
    assert_error(
        "G78 X27 Z-30 P1 Q0.4 F2\n",
        Code::UnknownPosition,
        1,
        1,
        "the tool's X and Z are not known here",
    );
    assert_error(
        &format!("{c}G78 X27 P1 Q0.4 F2\n"),
        Code::MissingWord,
        2,
        1,
        "X (or U) and Z (or W)",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 F2 R0.2\nG78 P010060 R1\nG78 X27 Z-30 P1 Q0.4 F2\n"),
        Code::Geometry,
        4,
        1,
        "finishing allowance R(d) 1 is not smaller",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 R-40 P1 Q0.4 F2\n"),
        Code::Geometry,
        2,
        1,
        "face-like",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 F2 K40\n"),
        Code::Geometry,
        2,
        1,
        "tail-out K 40",
    );
    assert_error(
        "G0 X28 Z5\nG78 X27 Z-30 P1 Q0.4 F2\n",
        Code::Geometry,
        2,
        1,
        "inside the thread",
    );
    assert_error(
        "G0 X27 Z5\nG78 X27 Z-30 P1 Q0.4 F2\n",
        Code::Geometry,
        2,
        1,
        "cannot tell an external",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 F2 H3\n"),
        Code::Unsupported,
        2,
        25,
        "H is not a word",
    );
    assert_error(
        &format!("{c}G01 G78 X27 Z-30 P1 Q0.4 F2\n"),
        Code::Conflict,
        2,
        1,
        "shares a block",
    );
    assert_error(
        &format!("{c}G78 X27 U1 Z-30 P1 Q0.4 F2\n"),
        Code::Conflict,
        2,
        9,
        "X and U",
    );
    assert_error(
        &format!("{c}G78 X27 Z-30 P1 Q0.4 F2 I8\n"),
        Code::Conflict,
        2,
        25,
        "F (lead) and I",
    );
    assert_error(
        &format!("{c}G78 P010060 Q0 R0\nG78 X27 Z-30 P100 Q0.000001 F2\n"),
        Code::OutOfRange,
        3,
        19,
        "Q(Δd)=0.000001",
    );
    // The plan is computed when the cycle is expanded: the error points at the cycle's G78.
    let src = format!("{c}G78 P010060 Q0 R0\nG78 X27 Z-30 P2 Q0.001 F2\n");
    let e = match program::expand_gcode(src.as_bytes(), &mut Vec::new(), &gsk()) {
        Err(program::Error::Input(d)) => d,
        other => panic!("{other:?}"),
    };
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::TooManyPasses, 3, 1)
    );
    assert!(
        e.message.contains("more than 10000 rough passes"),
        "{}",
        e.message
    );
}

// ---------------------------------------------------------------------------------------------
// Properties over random valid cycles

#[derive(Debug, Clone)]
struct Cycle {
    external: bool,
    root: f64,
    taper: f64,
    length: f64,
    height: f64,
    first: f64,
    min_cut: f64,
    allowance: f64,
    finish: u32,
    mode: u32,
    angle: u32,
    depth_mode: u32,
    tail: Option<(f64, f64)>,
    lead: f64,
    lead_in: f64,
}

impl Cycle {
    fn program(&self) -> String {
        let clear = self.height + self.taper.abs() + 2.0;
        let a_x = if self.external {
            self.root + clear
        } else {
            (self.root - clear).max(0.5)
        };
        let mut first = format!(
            "G78 P{:02}{:02}{:02} Q{:.3} R{:.3} D{}",
            self.finish, self.mode, self.angle, self.min_cut, self.allowance, self.depth_mode
        );
        if self.lead_in > 0.0 {
            first.push_str(&format!(" E{:.3}", self.lead_in));
        }
        let mut second = format!(
            "G78 X{:.3} Z{:.3} R{:.3} P{:.3} Q{:.3} F{:.3}",
            self.root * 2.0,
            -self.length,
            self.taper,
            self.height,
            self.first,
            self.lead
        );
        if let Some((j, k)) = self.tail {
            second.push_str(&format!(" J{j:.3} K{k:.3}"));
        }
        format!(
            "G0 X{:.3} Z2\n{first}\n{second}\nG0 X{:.3} Z2\n",
            a_x * 2.0,
            a_x * 2.0
        )
    }
}

fn cycles() -> impl Strategy<Value = Cycle> {
    (
        (
            any::<bool>(),
            8.0..40.0f64,
            -0.8..0.8f64,
            8.0..60.0f64,
            0.3..3.0f64,
        ),
        (
            0.05..1.0f64,
            0.0..0.2f64,
            0.0..0.2f64,
            1u32..4,
            0u32..5,
            0u32..100,
            0u32..2,
        ),
        (
            proptest::option::of((0.1..1.5f64, 0.1..2.0f64)),
            0.5..6.0f64,
            prop_oneof![Just(0.0), 0.1..1.0f64],
        ),
    )
        .prop_map(
            |(
                (external, root, taper, length, height),
                (first, min_cut, allowance_frac, finish, mode, angle, depth_mode),
                (tail, lead, lead_in),
            )| Cycle {
                external,
                root: if external { root } else { root + height + 3.0 },
                taper,
                length,
                height,
                first: (first * height).max(0.02),
                min_cut: if depth_mode == 1 {
                    min_cut.max(0.01)
                } else {
                    min_cut
                },
                allowance: allowance_frac * height,
                finish,
                mode,
                angle,
                depth_mode,
                tail,
                lead,
                lead_in,
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn depths_increase_and_finish_at_full_depth(c in cycles()) {
        let src = c.program();
        let jobs = program::jobs(src.as_bytes(), &gsk()).map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
        let job = &jobs[0];
        let p = job.passes().unwrap();
        let k = job.geometry.depth;
        let limit = k - job.plan.finish_allowance;
        let rough: Vec<_> = p.iter().filter(|p| p.kind == PassKind::Rough).collect();
        for w in rough.windows(2) {
            prop_assert!(w[1].depth > w[0].depth, "{src}");
        }
        prop_assert!(rough.iter().all(|p| p.depth <= limit + 1e-12), "{src}");
        prop_assert_eq!(rough.last().unwrap().depth, limit);
        prop_assert_eq!(p.last().unwrap().kind, PassKind::Finish);
        prop_assert_eq!(p.last().unwrap().depth, k);
        prop_assert_eq!(p.len() - rough.len(), c.finish as usize);
        // Chip areas add up to the whole groove and none is negative.
        prop_assert!(p.iter().all(|p| p.area >= 0.0));
    }

    #[test]
    fn toolpath_starts_and_ends_at_a_and_cuts_the_programmed_length(c in cycles()) {
        let src = c.program();
        let job = program::jobs(src.as_bytes(), &gsk()).unwrap().remove(0);
        let path = toolpath::build(&job).unwrap();
        prop_assert_eq!(path.start, job.start);
        prop_assert_eq!(path.end(), job.start);
        let mut thread_z = 0.0;
        for (from, m) in path.segments() {
            prop_assert!(m.to.is_finite());
            if let MotionKind::Thread { lead, .. } = m.kind {
                prop_assert!(lead > 0.0);
                thread_z += (m.to.z - from.z).abs();
            }
        }
        // Every pass travels W = Z end − Z of A = −length − 2 along Z, tail-out included.
        let passes = job.passes().unwrap().len() as f64;
        let w = (job.geometry.crest_end.z - 2.0).abs();
        prop_assert!((w - c.length - 2.0).abs() < 0.001);
        prop_assert!((thread_z - passes * w).abs() < 1e-6 * passes * w, "{thread_z} {src}");
    }

    #[test]
    fn expanded_gcode_reads_back_as_the_same_motion(c in cycles()) {
        let src = c.program();
        let job = program::jobs(src.as_bytes(), &gsk()).unwrap().remove(0);
        let path = toolpath::build(&job).unwrap();
        let out = expand(&src);
        // Read the expansion back as plain G0/G32 and collect the moves after the positioning block.
        let mut moves = Vec::new();
        program::run(out.as_bytes(), &gsk(), |_, ev| {
            if let Event::Plain { mv: Some(mv), .. } = ev {
                moves.push(mv);
            }
            Ok(())
        }).unwrap();
        // The first is the positioning block itself (from an unknown start), the last the block
        // after the cycle.
        prop_assert_eq!(moves[0].from, threadcut::gcode::Position::UNKNOWN);
        let cycle_moves = &moves[1..moves.len() - 1];
        prop_assert_eq!(cycle_moves.len(), path.motions.len());
        for (mv, m) in cycle_moves.iter().zip(&path.motions) {
            // X is written on diameter to 0.001: a radius within 0.0005; Z within 0.0005.
            prop_assert!((mv.to.x - m.to.x).abs() <= 0.000_500_1 && (mv.to.z - m.to.z).abs() <= 0.000_500_1, "{mv:?} vs {m:?}");
            match m.kind {
                MotionKind::Rapid => prop_assert_eq!(mv.mode, MotionMode::Rapid),
                MotionKind::Thread { lead, .. } => {
                    prop_assert_eq!(mv.mode, MotionMode::Thread);
                    prop_assert!((mv.lead.unwrap() - lead).abs() <= 0.000_050_1);
                }
                MotionKind::Feed => prop_assert_eq!(mv.mode, MotionMode::Feed),
                MotionKind::Arc { clockwise, .. } => prop_assert_eq!(
                    mv.mode,
                    if clockwise { MotionMode::ArcCw } else { MotionMode::ArcCcw }
                ),
            }
        }
    }
}

#[test]
fn other_blocks_pass_through_byte_for_byte() {
    let src = "%\r\nO1234 (THREAD)\r\n/N10 G0 X80 Z10 ; block delete\r\nT0101 M3 S300\r\nG78 P010060 Q0.1 R0.05\r\nG78 X60 Z-30 P3 Q1.2 F3\r\nG01 X90 F0.2\r\nM30\r\n%";
    let out = expand(src);
    assert!(
        out.starts_with(
            "%\r\nO1234 (THREAD)\r\n/N10 G0 X80 Z10 ; block delete\r\nT0101 M3 S300\r\n"
        ),
        "{out}"
    );
    // The expansion's own lines end as the program's do (CRLF in, CRLF out).
    assert!(
        out.ends_with("G0 X80. Z10.\r\nG01 X90 F0.2\r\nM30\r\n%"),
        "{out}"
    );
    assert_eq!(out.matches('\n').count(), out.matches("\r\n").count());
}

#[test]
fn modal_state_after_an_expanded_cycle_is_the_original_programs() {
    // Before the cycle G01 was modal with F0.2; G78 is one-shot and its F3 lands in the F register,
    // so the original's next bare `X90` is a G01 at F3. The expansion must leave the same state.
    let src = "G0 X80 Z10\nG01 Z10 F0.2\nG78 X60 Z-30 P3 Q1.2 F3 J1 K5\nX90\n";
    let out = expand(src);
    assert!(out.ends_with("G0 X80. Z10.\nG1\nX90\n"), "{out}");
    // A tail-out steeper than 45° writes a different F on its last block: restore F3.
    let src = "G0 X80 Z10\nG01 Z10 F0.2\nG78 X60 Z-30 P3 Q1.2 F3 J2 K1\nX90\n";
    assert!(expand(src).ends_with("G0 X80. Z10.\nG1 F3.\nX90\n"));
}

#[test]
fn incremental_end_point_with_u_and_w() {
    // U/W are measured from A (X80 Z10): U-20 W-70 is the same end point as X60 Z-60 (§3).
    let absolute = passes("G0 X80 Z10\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-60 P1.5 Q0.5 F2\n");
    let incremental = passes("G0 X80 Z10\nG78 P010060 Q0.1 R0.05\nG78 U-20 W-70 P1.5 Q0.5 F2\n");
    assert_eq!(absolute, incremental);
    // Crest Ø63 = root Ø60 + 2·1.5. √n·0.5 up to n = 6 (increments ≥ 0.1); at n = 7 √7·0.5 − √6·0.5 =
    // 0.098 < Δdmin, so 1.224745 + 0.1, then + 0.1 again; 1.524745 ≥ k − d = 1.45 → 1.45.
    let rough = [
        0.5,
        0.707_106_781_186_547_5,
        0.866_025_403_784_438_6,
        1.0,
        1.118_033_988_749_895,
        1.224_744_871_391_589,
        1.324_744_871_391_589,
        1.424_744_871_391_589,
        1.45,
    ];
    let mut expect: Vec<_> = rough
        .iter()
        .map(|&d| (R, d, 63.0 - 2.0 * d, 10.0))
        .collect();
    expect.push((F, 1.5, 60.0, 10.0));
    assert_passes(&incremental, &expect);
}
