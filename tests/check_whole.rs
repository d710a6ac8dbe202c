//! `check` sees the whole program (issue 23): the part the program turns, the threads it cuts in
//! it, and every rapid move judged against both. Each fault program is written after the way real
//! programs go wrong (a rapid straight to the next tool's start through the thread just cut; a
//! boring bar retracted in X inside the bore; a thread run past its relief into the shoulder; the
//! crest turned oversize), each with its correct twin, which must find nothing.

use threadcut::check::{check, Basis, Options, Report, Source};
use threadcut::diag::Code;
use threadcut::machine::Machine;
use threadcut::thread::standard;

fn run_with(src: &str, controller: &str, opts: &Options) -> Report {
    let m = Machine::built_in(controller).unwrap();
    check(src.as_bytes(), Source::Gcode(&m), opts).unwrap()
}

fn run(src: &str, controller: &str) -> Report {
    run_with(src, controller, &Options::default())
}

fn bar(d: f64) -> Options {
    Options {
        stock_diameter: Some(d),
        stock_start: Some(0.0),
        ..Options::default()
    }
}

/// (code, line, message) of every error.
fn errors(r: &Report) -> Vec<(Code, u32, String)> {
    r.diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| (d.code, d.span.line, d.message.clone()))
        .collect()
}

fn has(r: &Report, code: Code, line: u32, text: &str) -> bool {
    r.diagnostics
        .iter()
        .any(|d| d.code == code && d.span.line == line && d.message.contains(text))
}

/// An M20x2.5 thread by a Fanuc two-block G76 from X22 Z5 to Z-30, root Ø16.933 (the crest
/// X16.933 + 2 × 1.534 = Ø20.001), then `after` and the return.
fn m20(after: &str) -> String {
    format!(
        "O0001\nG21 G18 G99\nT0303\nG97 S800 M3\nG0 X22. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.933 Z-30. P1534 Q400 F2.5\n{after}G0 X100. Z100.\nM30\n"
    )
}

#[test]
fn a_rapid_through_the_thread_just_cut_is_an_error_at_its_line() {
    // From the cycle's start (X22 Z5) straight to X15 Z-10: across the face into the teeth (the
    // crest Ø20 over Z0..-30) and below the root Ø16.933.
    let r = run(&m20("G0 X15. Z-10.\n"), "fanuc");
    assert!(
        has(
            &r,
            Code::Collision,
            8,
            "runs through the thread cut at line 7"
        ),
        "{:?}",
        r.diagnostics
    );
    assert!(has(&r, Code::Collision, 8, "root Ø16.933, Z0 to Z-30"));
    // The move after it starts inside the thread: not reported again.
    assert_eq!(errors(&r).len(), 1, "{:?}", errors(&r));
    // The twin: back to the start first, then away.
    assert_eq!(errors(&run(&m20("G0 X22. Z5.\n"), "fanuc")), vec![]);
    // Along the crest at X22, clear of the teeth (radius 11 > 10.0005): nothing.
    assert_eq!(errors(&run(&m20("G0 X22. Z-10.\n"), "fanuc")), vec![]);
}

#[test]
fn a_retract_in_x_inside_the_bore_runs_through_an_internal_thread() {
    // M20x2 internal (minor Ø17.294, major Ø20) from X16 Z5 to Z-25; then the bar's tool goes
    // to Z-10 inside the bore (legal: X16 lies in the Ø17.294 hole) and out in X through the
    // thread: the error is on that line, not on the one inside the bore.
    let prog = |after: &str| {
        format!(
            "O0002\nG21 G18 G99\nT0505\nG97 S600 M3\nG0 X16. Z5.\nG76 P020060 Q100 R0.05\nG76 X20. Z-25. P1353 Q300 F2.\n{after}G0 Z100.\nM30\n"
        )
    };
    let r = run(&prog("G0 Z-10.\nG0 X40.\n"), "fanuc");
    assert_eq!(
        errors(&r).iter().map(|e| (e.0, e.1)).collect::<Vec<_>>(),
        vec![(Code::Collision, 9)],
        "{:?}",
        r.diagnostics
    );
    assert!(has(&r, Code::Collision, 9, "root Ø20"));
    // With the bar given (Ø40) the same: the bore the thread needs is open, whatever the
    // program drilled.
    let r = run_with(&prog("G0 Z-10.\nG0 X40.\n"), "fanuc", &bar(40.0));
    assert_eq!(
        errors(&r).iter().map(|e| (e.0, e.1)).collect::<Vec<_>>(),
        vec![(Code::Collision, 9)],
        "{:?}",
        r.diagnostics
    );
    // The twin: out of the bore along Z first.
    let twin = prog("G0 Z-10.\nG0 Z5.\nG0 X40.\n");
    assert_eq!(errors(&run(&twin, "fanuc")), vec![]);
    assert_eq!(errors(&run_with(&twin, "fanuc", &bar(40.0))), vec![]);
}

/// G71/G70 turn Ø19.8 over Z0..-32 with a 1 mm chamfer and a shoulder Ø24 from Z-32 (a Ø25
/// bar, the cycle from X26 Z2); then `thread`.
fn turned(thread: &str) -> String {
    format!(
        "O0003\nG21 G18 G99\nT0101\nG97 S1000 M3\nG0 X26. Z2.\nG71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X16.\nG1 X19.8 Z-1.\nZ-32.\nX24.\nN20 X26. Z-33.\nG70 P10 Q20\nG0 X100. Z100.\nT0303\nG97 S800 M3\nG0 X22. Z5.\n{thread}G0 X100. Z100.\nM30\n"
    )
}

#[test]
fn the_blank_is_the_diameter_the_program_turned() {
    let r = run_with(
        &turned("G76 P020060 Q100 R0.05\nG76 X16.933 Z-28. P1534 Q400 F2.5\n"),
        "fanuc",
        &bar(25.0),
    );
    assert_eq!(errors(&r), vec![]);
    assert!(r.notes.iter().any(|n| n
        .message
        .contains("the surface along the thread is Ø19.8 as the program turned it at line 13 (the bar Ø25 given)")));
    assert_eq!(r.blanks.len(), 1);
    assert!((r.blanks[0].crest - 19.8).abs() < 1e-9, "{:?}", r.blanks);
    assert_eq!(r.blanks[0].crest_from, Basis::Measured);
    assert_eq!(r.blanks[0].face_from, Basis::Given);
    // Without the bar: the turned surface is a fact all the same.
    let r = run(
        &turned("G76 P020060 Q100 R0.05\nG76 X16.933 Z-28. P1534 Q400 F2.5\n"),
        "fanuc",
    );
    assert_eq!(errors(&r), vec![]);
    assert_eq!(r.blanks[0].crest_from, Basis::Measured);
}

#[test]
fn a_thread_run_into_the_shoulder_is_an_error_naming_it() {
    // The thread runs to Z-34, past the shoulder at Z-32 (Ø24 > the Ø19.8 blank).
    let r = run_with(
        &turned("G76 P020060 Q100 R0.05\nG76 X16.933 Z-34. P1534 Q400 F2.5\n"),
        "fanuc",
        &bar(25.0),
    );
    assert!(
        has(&r, Code::Shoulder, 19, "a shoulder at Z-32"),
        "{:?}",
        r.diagnostics
    );
    // Beyond the shoulder's chamfer (Ø24 to Ø26 over Z-32..-33) the Ø25 bar stands: the last
    // pass would take Ø25 down to the root Ø16.933, a chip (25 − 16.933) / 2 = 4.0335 deep.
    assert!(has(
        &r,
        Code::Shoulder,
        19,
        "up to Ø25 beyond it (the stock as given)"
    ));
    assert!(has(&r, Code::Shoulder, 19, "a chip 4.03"));
    // Without the bar the shoulder's chamfer, cut at line 13, is the fact: up to Ø26.
    let r = run(
        &turned("G76 P020060 Q100 R0.05\nG76 X16.933 Z-34. P1534 Q400 F2.5\n"),
        "fanuc",
    );
    assert!(
        has(&r, Code::Shoulder, 19, "a shoulder at Z-32: the part stands up to Ø26 beyond it (as the program cut it at line 13)"),
        "{:?}",
        r.diagnostics
    );
    // Its twin ends 4 mm before the shoulder.
    let r = run_with(
        &turned("G76 P020060 Q100 R0.05\nG76 X16.933 Z-28. P1534 Q400 F2.5\n"),
        "fanuc",
        &bar(25.0),
    );
    assert!(!r.diagnostics.iter().any(|d| d.code == Code::Shoulder));
}

#[test]
fn a_rapid_into_the_turned_shoulder_is_an_error() {
    // After G70, from X100 Z100 straight to X22 Z-40: through the shoulder's chamfer (cut by
    // the G70 at line 13) — behind a surface the program cut, whatever the bar.
    let r = run(&turned("G0 X22. Z-40.\n"), "fanuc");
    assert!(
        r.diagnostics.iter().any(|d| d.code == Code::Collision
            && d.span.line == 18
            && d.message.contains("(cut at line 13)")),
        "{:?}",
        r.diagnostics
    );
    // The twin goes out in X first, then along Z above the shoulder, then in.
    let r = run(&turned("G0 X30. Z5.\nG0 Z-40.\nG0 X26.\n"), "fanuc");
    assert_eq!(errors(&r), vec![]);
}

#[test]
fn a_crest_turned_oversize_is_judged_against_the_class() {
    // G1 X20.3 turns the crest to Ø20.3; M20x2.5-6g's major diameter is 19.623–19.958.
    let prog = |d: &str| {
        format!(
            "O0004\nG21 G18 G99\nT0101\nG97 S1000 M3\nG0 X21. Z2.\nG1 X{d} F0.2\nZ-32.\nX26.\nG0 X100. Z100.\nT0303\nG97 S800 M3\nG0 X22. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.933 Z-28. P1534 Q400 F2.5\nG0 X100. Z100.\nM30\n"
        )
    };
    let opts = Options {
        thread: Some(standard::lookup("M20x2.5-6g").unwrap()),
        ..Options::default()
    };
    let r = run_with(&prog("20.3"), "fanuc", &opts);
    assert!(
        has(
            &r,
            Code::OutOfClass,
            14,
            "the crest turned at line 7 is Ø20.3"
        ),
        "{:?}",
        r.diagnostics
    );
    assert!(has(&r, Code::OutOfClass, 14, "19.623–19.958"));
    let r = run_with(&prog("19.85"), "fanuc", &opts);
    assert!(
        !r.diagnostics
            .iter()
            .any(|d| d.message.contains("the crest turned")),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn a_rapid_into_the_part_after_a_gsk_g78_is_found() {
    // GSK 980TDi G78 M16x1.5 from X18 Z3 to Z-20 (the part's face at Z0; P(r)=1: left flank,
    // k = 0.975 radius), then straight to the parting tool's start at X18 Z-25 — diagonally
    // through the thread.
    let prog = |after: &str| {
        format!(
            "G0 X100 Z100\nT0303\nM3 S600\nG0 X18 Z3\nG78 P020160 Q0.05 R0.05\nG78 X14.05 Z-20 P0.975 Q0.3 F1.5\n{after}G0 X100 Z100\nM30\n"
        )
    };
    let r = run(&prog("G0 X15 Z-25\n"), "gsk980");
    assert!(
        has(
            &r,
            Code::Collision,
            7,
            "runs through the thread cut at line 6"
        ),
        "{:?}",
        r.diagnostics
    );
    let r = run(&prog("G0 X30\nZ-25\n"), "gsk980");
    assert_eq!(errors(&r), vec![]);
}

#[test]
fn a_rapid_into_the_bar_given_is_an_error_into_its_assumed_face_a_warning() {
    // A Ø40 bar; the tool comes to X30 Z5 and on to Z-5: into the bar through its face.
    let prog = "G21 G18 G99\nT0101\nG97 S800 M3\nG0 X30. Z5.\nG0 Z-5.\nG0 X100. Z100.\nT0303\nG0 X42. Z5.\nG32 Z-20. F2.\nG0 X45.\nZ5.\nM30\n";
    let r = run_with(prog, "fanuc", &bar(40.0));
    assert!(
        has(
            &r,
            Code::Collision,
            5,
            "the stock's face at Z0 (stock as given)"
        ),
        "{:?}",
        r.diagnostics
    );
    // The face only assumed (no --stock-start): a warning that says so.
    let opts = Options {
        stock_diameter: Some(40.0),
        ..Options::default()
    };
    let r = run_with(prog, "fanuc", &opts);
    assert!(
        r.diagnostics
            .iter()
            .any(|d| d.code == Code::CollisionAssumed
                && d.span.line == 5
                && d.message.contains("face at Z0 assumed")),
        "{:?}",
        r.diagnostics
    );
    // Nothing given: the bar is not known, and nothing is claimed about it.
    let r = run(prog, "fanuc");
    assert!(
        !r.diagnostics.iter().any(|d| d.span.line == 5),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn a_relief_groove_and_a_drilled_and_bored_part_raise_nothing() {
    // Turn Ø19.8, groove Ø16.5 at Z-30 with a grooving tool (plunge in X, rapid out), thread
    // into the groove; drill on the axis, bore Ø18 with plain moves (retract toward the axis),
    // rapid out of the bore.
    let prog = "\
G21 G18 G99
T0101
G97 S1000 M3
G0 X26. Z2.
G1 X19.8 F0.2
Z-33.
X26.
G0 Z2.
T0202
G0 X22. Z-30.
G1 X16.5 F0.05
G0 X22.
G0 X100. Z100.
T0303
G97 S800 M3
G0 X22. Z5.
G76 P020060 Q100 R0.05
G76 X16.933 Z-29. P1534 Q400 F2.5
G0 X100. Z100.
T0404
G0 X0. Z2.
G1 Z-20. F0.1
G0 Z2.
T0505
G0 X12. Z2.
G1 Z-15. F0.15
G1 X11.
G0 Z2.
G0 X100. Z100.
M30
";
    let r = run_with(prog, "fanuc", &bar(25.0));
    assert_eq!(errors(&r), vec![], "{:?}", r.diagnostics);
    assert!(
        !r.diagnostics
            .iter()
            .any(|d| d.code == Code::CollisionAssumed),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn a_rapid_through_a_linuxcnc_g76_thread_is_found() {
    let prog = |after: &str| {
        format!(
            "G18 G21 G90 G7\nT1 M6\nS500 M3\nG0 X22 Z5\nG76 P2.5 Z-30 I-1 J0.4 K1.534 Q29.5 L0 E0 H0 R1.5\n{after}G0 X40 Z40\nM2\n"
        )
    };
    let r = run(&prog("G0 X15 Z-12\n"), "linuxcnc");
    assert!(
        has(
            &r,
            Code::Collision,
            6,
            "runs through the thread cut at line 5"
        ),
        "{:?}",
        r.diagnostics
    );
    assert_eq!(errors(&run(&prog("G0 X22 Z5\n"), "linuxcnc")), vec![]);
}

#[test]
fn a_turning_cycle_threadcut_does_not_simulate_is_said() {
    // Sinumerik CYCLE93 (grooving) passes through unsimulated: check says so at its call, so
    // that a finding about the blank after it is read knowing the part lacks what it cut.
    let prog = "G18 G90 G95 DIAMON\nT1 D1\nG97 S800 M3\nG0 X32 Z2\nCYCLE93(24,-30,3,1.5,0,0,0,0,0,0,0,0.2,0.2,1,0,5,1)\nG0 X30 Z8\nCYCLE97(1.5,,0,-35,24,24,4,2,0.92,0.05,29,0,8,2,3,1)\nG0 X100 Z100\nM30\n";
    let r = run(prog, "sinumerik");
    assert!(
        r.diagnostics.iter().any(|d| d.code == Code::Suspicious
            && d.span.line == 5
            && d.message.starts_with("CYCLE93 is not simulated")),
        "{:?}",
        r.diagnostics
    );
    assert_eq!(errors(&r), vec![]);
}

#[test]
fn a_rapid_inside_the_turned_part_is_an_error_even_through_an_unknown_face() {
    // G71/G70 turn Ø30 over Z0..-40 (no bar given, the face never cut); the next tool comes
    // straight from X100 Z100 to X20 Z-10: in through the bar's face (not known) and then inside
    // the Ø30 the program turned, 5 below it at Z-10 — material behind a surface it cut.
    let prog = |after: &str| {
        format!(
            "G21 G18 G99\nT0101\nG97 S1000 M3\nG0 X32. Z2.\nG71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G0 X26.\nG1 X30. Z-2.\nZ-40.\nN20 X32.\nG70 P10 Q20\nG0 X100. Z100.\nT0202\n{after}G0 X100. Z100.\nM30\n"
        )
    };
    let r = run(&prog("G0 X20. Z-10.\n"), "fanuc");
    assert!(
        has(&r, Code::Collision, 14, "runs inside the part")
            && has(&r, Code::Collision, 14, "behind the surface cut at line 11"),
        "{:?}",
        r.diagnostics
    );
    // Only that move: the one after it starts inside and is not reported again.
    assert_eq!(errors(&r).len(), 1, "{:?}", errors(&r));
    // The twin goes round: out to X34, along Z above the Ø30, then in to X31.
    assert_eq!(
        errors(&run(&prog("G0 X34. Z2.\nG0 Z-10.\nG0 X31.\n"), "fanuc")),
        vec![]
    );
    // The note says what the judgement rests on.
    assert!(r
        .notes
        .iter()
        .any(|n| n.message.starts_with("part: the bar's size is not given")));
}

#[test]
fn another_work_coordinate_system_starts_another_part() {
    // Op 1 (G54) turns Ø30 over Z0..-40; the part is turned round and op 2 (G55) faces and
    // turns the other end in its own coordinates: its rapid to X20 Z-10 is inside op 1's part,
    // not op 2's — no error. The same rapid in G54 is one.
    let prog = |ws: &str| {
        format!(
            "G21 G18 G99\nG54\nT0101\nG97 S1000 M3\nG0 X32. Z2.\nG1 X30. F0.2\nZ-40.\nX32.\nG0 X100. Z100.\nM0\n{ws}\nT0101\nG0 X100. Z100.\nG0 X20. Z-10.\nG0 X100. Z100.\nM30\n"
        )
    };
    assert_eq!(errors(&run(&prog("G55"), "fanuc")), vec![]);
    assert!(
        has(
            &run(&prog("G54"), "fanuc"),
            Code::Collision,
            14,
            "behind the surface cut at line 7"
        ),
        "{:?}",
        run(&prog("G54"), "fanuc").diagnostics
    );
}

/// A shop-style shaft (after the way shops write them): face with G94, rough G71, finish G70,
/// groove with G75, thread with G76, part off with G1 — no error, the blank measured on the
/// turned Ø24 and the faced Z0; its twin with a rapid straight from the thread to the groove.
#[test]
fn a_shaft_program_faced_turned_grooved_threaded_and_parted_off_is_clean() {
    let prog = |after_thread: &str| {
        format!(
            "O1001\nG21 G40 G99\nG28 U0.\nT0101\nG50 S2500\nG96 S180 M03\nG00 X52. Z2. M08\nG94 X-1.6 Z0.5 F0.15\nZ0.\nG71 U2. R0.5\nG71 P100 Q200 U0.4 W0.1 F0.25\nN100 G00 X18.\nG01 X24. Z-1. F0.12\nZ-38.\nX30.\nX34. Z-40.\nZ-60.\nX48.\nN200 X52. Z-62.\nG70 P100 Q200\nG00 X100. Z100.\nT0202\nG97 S800 M03\nG00 X32. Z-38.\nG75 R0.5\nG75 X19.5 P1500 F0.05\nG00 X100. Z100.\nT0303\nG97 S700 M03\nG00 X27. Z5.\nG76 P020060 Q100 R0.05\nG76 X21.546 Z-36. P1227 Q350 F2.\n{after_thread}G00 X100. Z100.\nT0404\nG97 S600 M03\nG00 X54. Z-65.\nG01 X-1. F0.05\nG00 X54.\nG00 X100. Z100. M09\nM30\n"
        )
    };
    for opts in [Options::default(), bar(50.0)] {
        let r = run_with(&prog(""), "fanuc", &opts);
        assert_eq!(errors(&r), vec![]);
        assert_eq!(r.blanks[0].crest_from, Basis::Measured);
        assert_eq!(r.blanks[0].face_from, Basis::Measured, "{:?}", r.blanks);
        assert!(r
            .notes
            .iter()
            .any(|n| n.message
                == "blank: the part's face is at Z0 as the program faced it at line 9"));
    }
    let r = run(&prog("G00 X20. Z-20.\n"), "fanuc");
    assert!(
        has(
            &r,
            Code::Collision,
            33,
            "runs through the thread cut at line 32"
        ),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn a_thread_whose_root_lies_outside_the_turned_part_cuts_nothing() {
    // LinuxCNC in diameter mode: the part turned to Ø16 over Z2..-25, then a G76 from the drive
    // line X18 with I-0.5 (the crest Ø17.5) and K0.92 (a depth of 0.46 on the radius): its root
    // Ø17.5 − 0.92 = Ø16.58 lies above the Ø16 turned — the thread cuts nothing.
    let prog = |k: &str| {
        format!(
            "G7 G18 G21 G90 G95\nT1 M6\nS1200 M3\nG0 X22 Z2\nG1 X16 F0.1\nZ-25\nX22\nG0 X30 Z30\nT2 M6\nS600 M3\nG0 X18 Z3\nG76 P1.5 Z-20 I-0.5 J0.2 K{k} Q29.5 L0 E0 H1 R1.5\nG0 X30 Z30\nM2\n"
        )
    };
    let r = run(&prog("0.92"), "linuxcnc");
    assert!(
        has(&r, Code::DepthNotReached, 12, "the thread cuts nothing: its deepest pass (Ø16.58) does not reach the part, which the program turned to Ø16 at line 6"),
        "{:?}",
        r.diagnostics
    );
    // K3 (Ø17.5 − 3 = Ø14.5 at the root) cuts the thread into the Ø16.
    let r = run(&prog("3"), "linuxcnc");
    assert!(
        !r.diagnostics
            .iter()
            .any(|d| d.message.contains("cuts nothing")),
        "{:?}",
        r.diagnostics
    );
    // The same K0.92 thread run on to Z-40: beyond the Z-25 turned lies the bar of unknown
    // size (no stock given), which its deepest pass may well cut, so nothing is said.
    let r = run(
        &prog("0.92").replace("G76 P1.5 Z-20", "G76 P1.5 Z-40"),
        "linuxcnc",
    );
    assert!(
        !r.diagnostics
            .iter()
            .any(|d| d.message.contains("cuts nothing")),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn a_rapid_through_a_modal_g92_thread_is_found_once() {
    // GSK G92 M20x1.5 in six passes (a thread written as single-pass cycles, read whole when the
    // next block ends it), then straight to X15 Z-10 through it, then away from there: one error,
    // at the move into the thread; the move out of it is the tool getting out.
    let prog = "G0 X100 Z100\nT0303\nM3 S600\nG0 X22 Z4\nG92 X19.2 Z-22 F1.5\nX18.7\nX18.3\nX18.1\nX18.05\nG0 X15 Z-10\nG0 X100 Z100\nM30\n";
    let r = run(prog, "gsk980");
    assert_eq!(
        errors(&r).iter().map(|e| (e.0, e.1)).collect::<Vec<_>>(),
        vec![(Code::Collision, 10)],
        "{:?}",
        r.diagnostics
    );
    assert!(has(
        &r,
        Code::Collision,
        10,
        "runs through the thread cut at line 5"
    ));
}

#[test]
fn a_face_cycle_whose_first_layer_rapids_under_the_groove_is_told() {
    // tests/data/linuxcnc-ref/g72-1-g72-2-face-groove-g7.ngc (moves equal to rs274's): G72's
    // first layer rapids from X0 to X40 at Z-6.2, then retracts to Z-6.5. The tool starts at
    // X44 Z2 and G72.1 leaves its allowance on the +Z side, so the face's material lies on -Z of
    // the profile; no move before reached Z-6.2 between Ø4.36 and Ø40 (G72.1 stays above Z-5.6
    // there, G72.2's outline runs down the groove's flank to Ø4, Z-6.2). Both rapids run through
    // material the program left: a true finding, not a false one (docs/dialects/
    // linuxcnc-turning.md, "A face profile's side").
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/linuxcnc-ref/g72-1-g72-2-face-groove-g7.ngc"
    );
    let r = run(&std::fs::read_to_string(path).unwrap(), "linuxcnc");
    assert!(
        has(
            &r,
            Code::Collision,
            17,
            "rapid move to X40 Z-6.2 runs into the profile at Ø4, Z-6.2 (cut at line 16)"
        ),
        "{:?}",
        r.diagnostics
    );
    assert!(has(
        &r,
        Code::Collision,
        17,
        "rapid move to X0.6 Z-6.5 runs inside the part"
    ));
    assert_eq!(errors(&r).len(), 2, "{:?}", errors(&r));
}

/// The same thread cut again (a spring pass run as a second cycle, or a program repeated): a
/// rapid through its teeth names the latest cut, and a different thread cut between two of them
/// is still looked at — the repeats are looked at once, not the threads between.
#[test]
fn a_thread_cut_again_is_named_by_its_latest_cut() {
    let again = "G0 X22. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.933 Z-30. P1534 Q400 F2.5\n";
    // Lines 8–10 the same cycle again; the rapid at line 11.
    let r = run(&m20(&format!("{again}G0 X15. Z-10.\n")), "fanuc");
    assert!(
        has(
            &r,
            Code::Collision,
            11,
            "runs through the thread cut at line 10"
        ),
        "{:?}",
        r.diagnostics
    );
    // Between them an M16x2 to Z-60 (root Ø13.546), approached and left clear of the M20's
    // teeth, then the M20 again, then a rapid into the M16's teeth alone (from radius 11 at Z-40
    // to radius 6, below its root 6.773): it is found behind the repeated M20.
    let m16 = "G0 X22. Z-35.\nG0 X18.\nG76 P020060 Q100 R0.05\nG76 X13.546 Z-60. P1227 Q400 F2.\n";
    let r = run_with(
        &m20(&format!(
            "{m16}G0 X22.\nG0 Z5.\n{again}G0 X22. Z-40.\nG0 X12. Z-50.\n"
        )),
        "fanuc",
        // The face at Z0 given: the M16's teeth are known from the face to its end.
        &Options {
            stock_start: Some(0.0),
            ..Options::default()
        },
    );
    assert_eq!(
        errors(&r).iter().map(|e| e.1).collect::<Vec<_>>(),
        vec![18],
        "{:?}",
        r.diagnostics
    );
    assert!(
        has(
            &r,
            Code::Collision,
            18,
            "runs through the thread cut at line 11"
        ),
        "{:?}",
        r.diagnostics
    );
}

/// A finding on a line a loop runs again is one finding on that line: the merged message lists
/// the other lines it was found on, never its own line again (GSK's G65 loop runs the G78 at
/// line 5 three times, each without a spindle speed).
#[test]
fn a_line_a_loop_runs_again_is_not_listed_again() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/gsk-g65-loop.nc"
    ))
    .unwrap();
    let r = run(&src, "gsk980");
    let w005: Vec<_> = r
        .diagnostics
        .iter()
        .filter(|d| d.code == Code::Spindle)
        .collect();
    assert_eq!(w005.len(), 1, "{:?}", r.diagnostics);
    assert_eq!(w005[0].span.line, 5);
    assert!(!w005[0].message.contains("also on"), "{}", w005[0].message);
}
