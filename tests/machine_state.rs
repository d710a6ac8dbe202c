//! The machine's state at each thread (`check::state`): faults written after how real programs go
//! wrong — an `M5` left before the threading tool, an `M1`/`M0` before it with no restart (posts
//! restate `G97 S… M3` after every optional stop for this reason), an `M19` orientation left from
//! cross drilling, the end of the program, the spindle reversed between hand-written passes, the
//! turret indexed between passes — each found at its line with its severity, and each fault's
//! twin (the restart added, the one tool kept) with no finding.

use threadcut::check::{check, Options, Source};
use threadcut::diag::Severity;
use threadcut::machine::Machine;

/// The machine-state findings of `program` on `controller`: (code, line, message), and the
/// number of errors of any kind.
fn state(controller: &str, program: &str) -> (Vec<(&'static str, u32, String)>, usize) {
    let m = Machine::built_in(controller).unwrap();
    let r = check(program.as_bytes(), Source::Gcode(&m), &Options::default()).unwrap();
    let found = r
        .diagnostics
        .iter()
        .filter(|d| matches!(d.code.as_str(), "E017" | "W010"))
        .map(|d| {
            assert_eq!(
                d.severity == Severity::Error,
                d.code.as_str() == "E017",
                "{d:?}"
            );
            (d.code.as_str(), d.span.line, d.message.clone())
        })
        .collect();
    (found, r.errors())
}

/// Asserts one machine-state finding, `code` at `line`, whose message contains `words`.
fn one(controller: &str, program: &str, code: &str, line: u32, words: &str) {
    let (found, _) = state(controller, program);
    assert_eq!(found.len(), 1, "{controller}: {found:?}");
    let (c, l, message) = &found[0];
    assert_eq!((*c, *l), (code, line), "{controller}: {message}");
    assert!(message.contains(words), "{controller}: {message}");
}

/// Asserts no finding at all about the machine's state, and no error.
fn clean(controller: &str, program: &str) {
    let (found, errors) = state(controller, program);
    assert!(found.is_empty(), "{controller}: {found:?}");
    assert_eq!(errors, 0, "{controller}");
}

const FANUC_G76: &str = "%
O0001
G21 G99
T0101
G97 S600 M3
G0 X32. Z5.
{}
G76 P020060 Q100 R0.05
G76 X27.546 Z-30. P1227 Q400 F2.
G0 X100. Z100.
M30
%
";

fn fanuc_g76(between: &str) -> String {
    FANUC_G76.replace("{}", between)
}

#[test]
fn fanuc_m5_before_the_cycle_is_an_error_at_the_cycle() {
    // Line 7 stops the spindle; the cycle's second block (line 9) is the thread's block.
    one(
        "fanuc",
        &fanuc_g76("M5"),
        "E017",
        9,
        "M5 at line 7 stops it, and no M3 or M4 restarts it",
    );
    clean("fanuc", &fanuc_g76("M5\nM3"));
    clean("fanuc", &fanuc_g76("M5\nS600 M4"));
}

#[test]
fn fanuc_program_stops_are_warnings_naming_the_assumption() {
    one(
        "fanuc",
        &fanuc_g76("M0"),
        "W010",
        9,
        "assuming it stops the spindle too, as most machine builders' ladders do",
    );
    one(
        "fanuc",
        &fanuc_g76("M1"),
        "W010",
        9,
        "optional stop switch is on",
    );
    clean("fanuc", &fanuc_g76("M1\nG97 S600 M3"));
}

#[test]
fn fanuc_orientation_and_the_end_of_the_program_stop_the_spindle() {
    one(
        "fanuc",
        &fanuc_g76("M19"),
        "E017",
        9,
        "M19 at line 7 orients it",
    );
    one(
        "fanuc",
        &fanuc_g76("M19\nG0 X32. Z5."),
        "E017",
        10,
        "M19 at line 7",
    );
    clean("fanuc", &fanuc_g76("M19\nM3"));
    // A stop after the thread is no fault.
    clean(
        "fanuc",
        &fanuc_g76("").replace("G0 X100. Z100.", "G0 X100. Z100. M5"),
    );
}

#[test]
fn a_stop_on_the_threads_own_block_acts_after_its_motion() {
    // ISO 6983-1: M05 acts at the end of the block, after the move; the next pass is cut stopped.
    let p = "G21 G99\nT0101\nG97 S600 M3\nG0 X22. Z5.\nX19.4\nG32 Z-20. F2.5 M5\n\
             G0 X22.\nZ5.\nX19.0\nG32 Z-20. F2.5\nG0 X22.\nZ5.\nM30\n";
    one(
        "fanuc",
        p,
        "E017",
        10,
        "the passes from line 10 on are cut with the spindle stopped: M5 at line 6",
    );
}

/// Hand-written G32 passes of M20x2.5; `second` goes before the second pass (line 11).
fn g32_passes(second: &str) -> String {
    format!(
        "%\nO0002\nG21 G99\nT0303\nG97 S600 M3\nG0 X22. Z5.\nX19.4\nG32 Z-20. F2.5\nG0 X22.\nZ5.\n\
         {second}\nX19.0\nG32 Z-20. F2.5\nG0 X22.\nZ5.\nX18.7\nG32 Z-20. F2.5\nG0 X22.\nZ5.\nM30\n%\n"
    )
}

#[test]
fn the_spindle_reversed_between_passes_is_an_error_naming_both_codes() {
    // The second pass is line 13 (its G32).
    one(
        "fanuc",
        &g32_passes("M4"),
        "E017",
        13,
        "M4 at line 11 reverses M3 at line 5",
    );
    // Restated the same way: no fault.
    clean("fanuc", &g32_passes("M3"));
    // Stopped and restarted the same way between passes: the thread's start is synchronised
    // again, no fault.
    clean("fanuc", &g32_passes("M5\nM3"));
    // Stopped, restarted the other way: reversed.
    let (found, _) = state("fanuc", &g32_passes("M5\nM4"));
    assert_eq!(found.len(), 1, "{found:?}");
    assert_eq!((found[0].0, found[0].1), ("E017", 14));
    assert!(found[0].2.contains("M4 at line 12 reverses M3 at line 5"));
}

#[test]
fn a_tool_change_between_passes_is_an_error_the_same_tool_a_warning() {
    one(
        "fanuc",
        &g32_passes("T0505"),
        "E017",
        13,
        "T0505 at line 11 replaces T0303 at line 4",
    );
    one(
        "fanuc",
        &g32_passes("T0303"),
        "W010",
        13,
        "T0303 at line 11 after T0303 at line 4",
    );
    // Another offset of the same tool (a wear offset for the last passes): a warning.
    one(
        "fanuc",
        &g32_passes("T0313"),
        "W010",
        13,
        "T0313 at line 11",
    );
}

#[test]
fn a_new_work_offset_between_two_threads_makes_them_two_grooves() {
    // The same coordinates in another work system are another part's groove (a sub-spindle, a
    // second fixture): no tool-change finding.
    let p = g32_passes("G55\nT0505");
    let (found, _) = state("fanuc", &p);
    assert!(found.is_empty(), "{found:?}");
}

#[test]
fn two_cycles_over_one_groove_with_another_tool_between_them() {
    // Rough with T0303, finish with T0505 over the same groove: the second tool's offset does not
    // put it in the first's groove.
    let p = "G21 G99\nT0303\nG97 S600 M3\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\n\
             G76 X27.546 Z-30. P1227 Q400 F2.\nG0 X100. Z100.\nT0505\nG97 S600 M3\nG0 X32. Z5.\n\
             G76 P010060 Q50 R0.02\nG76 X27.546 Z-30. P1227 Q400 F2.\nG0 X100. Z100.\nM30\n";
    one(
        "fanuc",
        p,
        "E017",
        12,
        "between this thread and the one just before it over the same groove: T0505 at line 8",
    );
    // Two different threads with two tools (the shop program of tests/data/real) stay clean.
    clean(
        "fanuc",
        &std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("tests/data/real/fanuc-two-threads-chamfer.nc"),
        )
        .unwrap(),
    );
}

#[test]
fn haas_m00_stops_the_spindle_as_its_manual_says() {
    let p = |between: &str| {
        format!(
            "%\nO02001\nG20 G40 G99\nT505\nG50 S2500\nG97 S950 M03\nG00 X0.9 Z0.3 M08\n{between}\n\
             G76 X0.6273 Z-1.125 K0.0613 D0.015 F0.1 A60 P2\nG00 X2. Z1. M09\nM30\n%\n"
        )
    };
    one(
        "haas",
        &p("M00"),
        "E017",
        9,
        "which on this control stops the spindle",
    );
    one("haas", &p("M01"), "W010", 9, "optional stop switch is on");
    one("haas", &p("M19"), "E017", 9, "M19 at line 8 orients it");
    clean("haas", &p("M00\nG97 S950 M03"));
}

#[test]
fn gsk_modal_g92_after_m5() {
    let p = |between: &str| {
        format!(
            "O0001;\nG0 X100 Z100;\nT0202;\nM3 S600;\n{between}\nG0 X32 Z3;\nG92 X29.2 Z-25 F2;\n\
             X28.6;\nX28.1;\nX27.7;\nG0 X100 Z100;\nM30;\n"
        )
    };
    one("gsk980", &p("M5;"), "E017", 7, "M5 at line 5 stops it");
    one(
        "gsk980",
        &p("M0;"),
        "W010",
        7,
        "assuming it stops the spindle",
    );
    clean("gsk980", &p("M5;\nM3;"));
    // Reversed between two of the modal G92's passes.
    let reversed = p("").replace("X28.1;", "M4;\nX28.1;");
    one(
        "gsk980",
        &reversed,
        "E017",
        10,
        "M4 at line 9 reverses M3 at line 4",
    );
}

#[test]
fn linuxcnc_keeps_its_interpreters_rule_and_its_pauses() {
    let g33 = |between: &str| {
        format!(
            "G7 G21 G18 G90 G40\nM3 S400\n{between}\nG0 X20 Z4\nG0 X15.4\nG33 Z-20 K2\nG0 X20\n\
             G0 Z4\nG0 X14.9\nG33 Z-20 K2\nG0 X20\nG0 Z4\nM5\nM2\n"
        )
    };
    one("linuxcnc", &g33("M5"), "E017", 6, "M5 at line 3 stops it");
    one(
        "linuxcnc",
        &g33("M19"),
        "E017",
        6,
        "M19 at line 3 orients it",
    );
    // LinuxCNC's M0/M1 pause the program; its interpreter stops the spindle only at the end.
    clean("linuxcnc", &g33("M0"));
    clean("linuxcnc", &g33("M1"));
    clean("linuxcnc", &g33("M5\nM3"));
    // G76 with the spindle stopped stays LinuxCNC's own alarm, at the G76.
    let m = Machine::built_in("linuxcnc").unwrap();
    let p = "G7 G21 G18\nS500 M3\nM5\nG0 X22 Z5\nG76 P2.5 Z-30 I-2.0 J0.6 R1.5 K3.067 Q29.5 H2 E2 L2\nM2\n";
    let r = check(p.as_bytes(), Source::Gcode(&m), &Options::default()).unwrap();
    assert_eq!(r.errors(), 1, "{:?}", r.diagnostics);
    assert_eq!(r.diagnostics[0].span.line, 5);
    assert!(r.diagnostics[0]
        .message
        .contains("Chosen spindle (0) not turning in G76"));
    // Reversed between G33 passes.
    one(
        "linuxcnc",
        &g33("").replace("G0 X14.9", "M4\nG0 X14.9"),
        "E017",
        11,
        "M4 at line 9 reverses M3 at line 2",
    );
}

#[test]
fn linuxcnc_changes_tools_at_m6() {
    // `T5` only prepares the tool; the change is at M6.
    let p = |between: &str| {
        format!(
            "G7 G21 G18 G90 G40\nT3 M6\nM3 S400\nG0 X20 Z4\nG0 X15.4\nG33 Z-20 K2\nG0 X20\nG0 Z4\n\
             {between}\nG0 X14.9\nG33 Z-20 K2\nG0 X20\nG0 Z4\nM5\nM2\n"
        )
    };
    one(
        "linuxcnc",
        &p("M6 T5"),
        "E017",
        11,
        "T5 at line 9 replaces T3 at line 2",
    );
    clean("linuxcnc", &p("T5"));
}

#[test]
fn sinumerik_m5_before_cycle97() {
    let p = |between: &str| {
        format!(
            "N10 G18 G90 G95 G71 DIAMON\nN20 T1 D1\nN30 G97 S900 M3 M8\n{between}\nN60 G0 X30 Z6\n\
             N70 CYCLE97(1.5,,0,-32,24,24,4,2,0.92,0.05,-29,0,7,2,3,1)\nN80 G0 X60 Z80 M9\nN90 M30\n"
        )
    };
    one(
        "sinumerik",
        &p("N40 M5"),
        "E017",
        6,
        "M5 at line 4 stops it",
    );
    one(
        "sinumerik",
        &p("N40 M0"),
        "W010",
        6,
        "assuming it stops the spindle",
    );
    clean("sinumerik", &p("N40 M5\nN50 M3"));
}

#[test]
fn omniturn_and_fanuc_b_and_ab9() {
    // OmniTurn: T4 F200 selects the tool; M5 before its G33.
    let omni =
        |between: &str| format!("T4F200\nM3\n{between}\nX0Z.2\nX.237\nG33X.212Z-.5I.012K.05PC\n");
    one("omniturn", &omni("M5"), "E017", 6, "M5 at line 3 stops it");
    clean("omniturn", &omni("M5\nM3"));
    // Fanuc system B: G33 passes reversed.
    let b = "G21 G99\nT0101\nG97 S600 M3\nG0 X22. Z5.\nX19.4\nG33 Z-20. F2.5\nG0 X22.\nZ5.\nM4\n\
             X19.0\nG33 Z-20. F2.5\nG0 X22.\nZ5.\nM30\n";
    one(
        "fanuc-b",
        b,
        "E017",
        11,
        "M4 at line 9 reverses M3 at line 3",
    );
    // Allen-Bradley: M5 before its G78.
    let ab = |between: &str| {
        format!("G21\nM3 S600\n{between}\nG90 G00 X12. Z5.\nG78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1\nG00 X50. Z50.\n")
    };
    one("ab9", &ab("M5"), "E017", 5, "M5 at line 3 stops it");
    clean("ab9", &ab("M5\nM3"));
}

#[test]
fn apt_spindl_off_before_the_thread() {
    let p = |off: &str| {
        format!(
            "UNITS/MM\nSPINDL/600,RPM,CLW\n{off}\nPITCH/2.5,MMPR\nFEDRAT/0.2,MMPR\nRAPID\nGOTO/12,0,5\n\
             THREAD/ON,DEPTH,1.534,CUTS,6,OPTION,1,FINCUT,1,0.05,RETURN\nGOTO/10,0,5\nGOTO/10,0,-30\n\
             THREAD/OFF\nGOTO/15,0,5\nSPINDL/OFF\nFINI\n"
        )
    };
    let run = |text: String| {
        check(text.as_bytes(), Source::Apt(None), &Options::default())
            .unwrap()
            .diagnostics
            .into_iter()
            .filter(|d| d.code.as_str() == "E017")
            .map(|d| d.message)
            .collect::<Vec<_>>()
    };
    let found = run(p("SPINDL/OFF"));
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(found[0].contains("SPINDL/OFF stops it"), "{found:?}");
    assert!(run(p("SPINDL/OFF\nSPINDL/600,RPM,CLW")).is_empty());
}

#[test]
fn a_program_that_never_starts_the_spindle_is_not_judged() {
    // A fragment (no M3/M4, no M5): its spindle is not known, as today.
    let (found, _) = state(
        "fanuc",
        "G0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n",
    );
    assert!(found.is_empty(), "{found:?}");
}
