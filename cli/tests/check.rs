//! `threadcut check`: each check with a hand-computed case, through the binary (exit status,
//! line:column) and through the library.

use std::path::PathBuf;
use std::process::Command;

use threadcut::check::{self, Options, Rpm};
use threadcut::diag::Code;
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::thread::DepthLaw;
use threadcut::threads::Thread;

fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Runs `threadcut check` on `src`; returns (exit status, stdout).
fn check_cli(name: &str, src: &str, extra: &[&str]) -> (i32, String) {
    let (code, out, _) = check_cli_err(name, src, extra);
    (code, out)
}

/// Runs `threadcut check` on `src`; returns (exit status, stdout, stderr).
fn check_cli_err(name: &str, src: &str, extra: &[&str]) -> (i32, String, String) {
    let input = tmp(&format!("check-{name}.nc"));
    std::fs::write(&input, src).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .arg("check")
        .arg(&input)
        .args(extra)
        .output()
        .unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn gsk<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-c", "gsk980"];
    v.extend_from_slice(extra);
    v
}

/// A radial 2 mm thread from Z10 to Z-30, spindle at 600 rpm: 9 passes (0.4·√n with a 0.1 minimum
/// cut to 1.15, then the finishing pass at 1.2).
const CLEAN: &str =
    "G00 X80 Z10\nG97 S600 M03\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";

#[test]
fn a_clean_program_passes() {
    // The part's face at Z5 leaves 5 mm of run-up; 2.379 mm are needed (see below).
    let (code, out) = check_cli("clean", CLEAN, &gsk(&["--stock-start", "5"]));
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings in 1 thread"), "{out}");
    // Without --stock-start the face is assumed at Z0 (10 mm of run-up), and the note says so.
    let (code, out) = check_cli("clean0", CLEAN, &gsk(&[]));
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings in 1 thread"), "{out}");
    assert!(
        out.contains("note: ") && out.contains(":4: blank: the part's face assumed at Z0 and the blank assumed turned to the thread's crest (Ø62.4)"),
        "{out}"
    );
}

#[test]
fn run_up_shorter_than_the_servo_lag() {
    // δ1 = T1·V·(−1 − ln a) = 0.033 s · (2 mm · 600 rpm / 60) · (−1 − ln 0.01) = 2.3794 mm; with
    // the face where the thread starts every pass starts at it: one warning for passes 1–9.
    let (code, out) = check_cli("runup", CLEAN, &gsk(&["--stock-start", "10"]));
    assert_eq!(code, 0, "a warning only: {out}");
    assert!(out.contains("warning[W003]: passes 1–9"), "{out}");
    assert!(out.contains("starts at the blank's face"), "{out}");
    assert!(out.contains("needs 2.3794 mm of run-up"), "{out}");
    assert!(out.contains("check-runup.nc:4:1"), "{out}");
    assert_eq!(out.matches("W003").count(), 1, "{out}");
    // With the face 2 mm away, 0.3794 mm are missing.
    let (_, out) = check_cli("runup2", CLEAN, &gsk(&["--stock-start", "8"]));
    assert!(out.contains("starts 2 mm before the blank"), "{out}");
    assert!(out.contains("start the thread 0.3794 mm further"), "{out}");
    // With the face assumed at Z0, the warning says so: the start point at Z1 leaves 1 mm.
    let src = CLEAN.replace("Z10", "Z1");
    let (_, out) = check_cli("runup3", &src, &gsk(&[]));
    assert!(
        out.contains("starts 1 mm before the blank (the part's face assumed at Z0) but the synchronised feed needs 2.3794 mm"),
        "{out}"
    );
}

#[test]
fn synchronised_feed_above_the_axis_limit() {
    // 3 mm lead × 3000 rpm = 9000 mm/min > the gsk980 profile's 8000 mm/min.
    let src = "G00 X80 Z10\nG97 S3000 M03\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F3\n";
    let (code, out) = check_cli("feed", src, &gsk(&["--stock-start", "100"]));
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("error[E012]"), "{out}");
    assert!(out.contains("9000 mm/min (lead 3 × 3000 rpm)"), "{out}");
    assert!(out.contains("2666 rpm or less"), "{out}");
    // 2666 rpm is fine. The face at Z100 puts the start point inside the blank: with the blank's
    // diameter assumed (the crest) a warning, with both given an error.
    let ok = src.replace("S3000", "S2666");
    let (code, out) = check_cli("feed-ok", &ok, &gsk(&["--stock-start", "100"]));
    assert!(!out.contains("E012"), "{out}");
    assert!(out.contains("warning[W008]"), "{out}");
    assert_eq!(code, 0, "{out}");
    let (code, out) = check_cli(
        "feed-ok2",
        &ok,
        &gsk(&["--stock-start", "100", "--stock-diameter", "62.4"]),
    );
    assert!(out.contains("error[E011]"), "{out}");
    assert_eq!(code, 2, "{out}");
}

#[test]
fn rapid_moves_into_the_blank_are_errors_only_for_a_given_blank() {
    // Right-flank infeed (r = 02): each pass starts d·tan 30° toward −Z. With the face at Z0 (the
    // default assumption) every start at Z9.77 … lies in front of the part: nothing.
    let src = "G00 X80 Z10\nG97 S300\nG78 P010260 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let (code, out) = check_cli("rapid", src, &gsk(&[]));
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("E011") && !out.contains("W008"), "{out}");
    // The face where the thread starts (given), the diameter assumed: a warning naming it.
    let (code, out) = check_cli("rapid-face", src, &gsk(&["--stock-start", "10"]));
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains(
            "warning[W008]: passes 1–9: a rapid move from (radius 40, Z10) to (radius 30.8, Z9.7691) runs through the blank"
        ),
        "{out}"
    );
    assert!(
        out.contains("with the blank assumed turned to the thread's crest (Ø62.4)"),
        "{out}"
    );
    // Both given: a fact, an error.
    let (code, out) = check_cli(
        "rapid-given",
        src,
        &gsk(&["--stock-start", "10", "--stock-diameter", "62.4"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E011]: passes 1–9: a rapid move from (radius 40, Z10) to (radius 30.8, Z9.7691) runs through the blank (8 more rapid moves do too)"),
        "{out}"
    );
    // Radial infeed from a start point inside a Ø90 blank: the return along X80 cuts through it.
    let (code, out) = check_cli(
        "rapid-stock",
        CLEAN,
        &gsk(&["--stock-diameter", "90", "--stock-start", "5"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("error[E011]"), "{out}");
    assert!(out.contains("to (radius 40, Z10)"), "{out}");
}

#[test]
fn the_issue_programs_flank_infeed_start_is_not_an_error() {
    // The issue's report: `check examples/fanuc-m30x2-g76.nc -c fanuc` raised E011 for the first
    // pass's backed-off start (radius 14.6, Z5.4775). The face is assumed at Z0 now.
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/fanuc-m30x2-g76.nc"
    ))
    .unwrap();
    let (code, out) = check_cli("issue", &src, &["-c", "fanuc"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings in 1 thread"), "{out}");
}

#[test]
fn lead_beyond_the_controllers_maximum() {
    let profile = Machine::built_in("gsk980").unwrap();
    let mut text = toml::to_string(&profile).unwrap();
    text = text.replace("max_lead_mm = 500.0", "max_lead_mm = 1.5");
    let path = tmp("check-lead.toml");
    std::fs::write(&path, text).unwrap();
    let (code, out) = check_cli(
        "lead",
        CLEAN,
        &["--machine", path.to_str().unwrap(), "--stock-start", "5"],
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E014]: the lead 2 is beyond this controller's maximum 1.5 (mm)"),
        "{out}"
    );
}

#[test]
fn thread_shorter_than_one_lead() {
    let src = "G00 X80 Z10\nG97 S100\nG78 P010060 Q0.1 R0.05\nG78 X60 Z8.5 P1.2 Q0.4 F2\n";
    let (code, out) = check_cli("short", src, &gsk(&["--stock-start", "20"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E007]: the thread is 1.5 long, shorter than one lead (2)"),
        "{out}"
    );
    // The dialect's own warning stays.
    assert!(out.contains("warning[W001]"), "{out}");
}

#[test]
fn controller_alarms_are_check_errors() {
    // The tail-out K10 is not shorter than the 8 mm thread: the GSK dialect refuses it.
    let src = "G00 X80 Z10\nG97 S100\nG78 P010060 Q0.1 R0.05\nG78 X60 Z2 P1.2 Q0.4 F2 J1 K10\n";
    let (code, out) = check_cli("alarm", src, &gsk(&[]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E007]: the tail-out K 10 is not shorter than the thread"),
        "{out}"
    );
    assert!(
        out.contains("checking stopped at the controller's alarm"),
        "{out}"
    );
    // A missing P(k) is the controller's alarm, with its line and column.
    let src = "G00 X80 Z10\nG78 X60 Z-30 Q0.4 F2\n";
    let (code, out) = check_cli("alarm2", src, &gsk(&[]));
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("error[E003]"), "{out}");
    assert!(out.contains("check-alarm2.nc:2:1"), "{out}");
}

#[test]
fn spindle_unknown_or_constant_surface_speed() {
    let src = CLEAN.replace("G97 S600 M03\n", "");
    let (code, out) = check_cli("nos", &src, &gsk(&["--stock-start", "5"]));
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("warning[W005]: no spindle speed (S)"), "{out}");
    // G96 S150 (m/min) at the first thread move's radius 30.8 mm: 150000/(2π·30.8) = 775.1 rpm,
    // under the G50 clamp of 2000.
    let src = CLEAN.replace("G97 S600 M03", "G50 S2000\nG96 S150 M03");
    let (_, out) = check_cli("css", &src, &gsk(&["--stock-start", "5"]));
    assert!(out.contains("constant surface speed (G96)"), "{out}");
    // 2·775 = 1550 mm/min: no feed error; the run-up needs 0.033·(2·775.1/60)·3.605 = 3.07 mm.
    assert!(!out.contains("E012"), "{out}");
}

#[test]
fn depth_not_reached_and_ridges_through_the_library() {
    let src = CLEAN.as_bytes();
    let machine = Machine::built_in("gsk980").unwrap();
    let mut job = program::jobs(src, &machine).unwrap().remove(0);
    // Two explicit rough passes and no finishing pass: the groove stops at 0.6 of 1.2.
    job.plan.law = DepthLaw::Explicit {
        depths: vec![0.3, 0.6],
    };
    job.plan.finish_allowance = 0.0;
    job.plan.finish_passes = 0;
    let thread = Thread::from_cycle(job, true).unwrap();
    let opts = Options {
        stock_start: Some(5.0),
        ..Options::default()
    };
    let (mut out, mut notes) = (Vec::new(), Vec::new());
    check::check_thread(&thread, &machine, &opts, &Rpm(300.0), &mut out, &mut notes);
    let d = out
        .iter()
        .find(|d| d.code == Code::DepthNotReached)
        .expect("E013");
    assert!(d.is_error());
    assert_eq!(
        d.message,
        "the passes reach 0.6 deep, the thread needs 1.2 (radius)"
    );
    assert_eq!(d.span.line, 4);
}

#[test]
fn a_face_past_the_thread_is_refused() {
    let (code, out) = check_cli("face", CLEAN, &gsk(&["--stock-start", "-40"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("the blank's face (Z-40) lies at or past the thread's end (Z-30)"),
        "{out}"
    );
}

#[test]
fn retracts_out_of_the_groove_are_not_collisions_but_ridges_are_reported() {
    // Internal thread (start point below the root), left/right alternating infeed (r = 04), the
    // finishing passes at the last rough pass's offset. Pass 1 ends 0.1732 short of Z-20 (its
    // offset) and retracts straight out of its groove: allowed.
    let src = "G00 X20 Z5\nG97 S500\nG78 P020460 Q0.1 R0.05\nG78 X26 Z-20 P1.0 Q0.3 F1.5\n";
    let (code, out) = check_cli("internal", src, &gsk(&["--stock-start", "0"]));
    assert!(!out.contains("E011"), "{out}");
    assert_eq!(code, 0, "{out}");
    // Depths 0.3·√n with a 0.1 minimum cut: pass 7 at 0.9243 sits at 0.9243·tan 30° = 0.53365,
    // the finish at 1.0 at pass 8's mirror offset 2·tan 30° − 0.95·tan 30° = 0.60622. Their V's meet
    // at (0.9243 + 1.0 − 0.07257/tan 30°)/2 = 0.8993: a ridge 0.9243 − 0.8993 = 0.025 high.
    assert!(out.contains("warning[W004]: a ridge 0.025 high"), "{out}");
    assert!(out.contains("comes out 0.05 over size"), "{out}");
}

#[test]
fn a_zero_degree_cycle_is_cut_with_a_sixty_degree_tool() {
    // P(a) = 00: a radial infeed, which says nothing of the insert; the section is cut with a 60°
    // tool and a note says so (it could not be simulated before).
    let src = "G00 X80 Z10\nG97 S300\nG78 P010000\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let (code, out) = check_cli("angle0", src, &gsk(&["--stock-start", "5"]));
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("cannot be simulated"), "{out}");
    assert!(
        out.contains(
            "the cycle's tool angle is 0° (a radial infeed): the section is cut with a 60° tool"
        ),
        "{out}"
    );
}

#[test]
fn run_out_shorter_than_the_servo_lag_at_the_end() {
    // Fanuc G76 with a one-lead chamfer (P(r) = 10, 2 mm) at 2000 rpm: V = 2·2000/60 = 66.67
    // mm/s, δ2 = T1·V = 0.033·66.67 = 2.2 mm > 2 mm: the last 0.2 mm of full thread are cut with a
    // lead error, on every pass.
    let src = "G21 G99\nG97 S2000 M3\nG0 X32. Z10.\nG76 P021060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";
    let (code, out) = check_cli("runout", src, &["-c", "fanuc"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("warning[W007]: passes 1–10: the pull-out is 2 mm long but the synchronised feed needs δ2 = 2.2 mm to stop (servo time constant 0.033 s): the last 0.2 mm of full-depth thread before it are cut with a lead error"),
        "{out}"
    );
    // At 1800 rpm δ2 = 1.98 mm: inside the chamfer.
    let (_, out) = check_cli(
        "runout-ok",
        &src.replace("S2000", "S1800"),
        &["-c", "fanuc"],
    );
    assert!(!out.contains("W007"), "{out}");
    // A straight exit (P(r) = 00): nothing to judge it against.
    let (_, out) = check_cli(
        "runout-straight",
        &src.replace("P021060", "P020060"),
        &["-c", "fanuc"],
    );
    assert!(!out.contains("W007"), "{out}");
}

#[test]
fn a_modal_g92_is_one_thread_with_one_warning_per_finding() {
    // Five G92 passes at 2000 rpm from Z2: δ1 = 0.033·(2·2000/60)·3.605 = 7.93 mm > 2 mm. One
    // warning for the thread, naming its passes (it was five identical warnings).
    let src = "G21 G99\nG97 S2000 M3\nG0 X40. Z2.\nG92 X29.2 Z-30. F2.\nX28.7\nX28.3\nX27.9\nX27.546\nG0 X100. Z100.\n";
    let (code, out) = check_cli("g92", src, &["-c", "fanuc"]);
    assert_eq!(code, 0, "{out}");
    assert_eq!(out.matches("warning[W003]").count(), 1, "{out}");
    assert!(out.contains("warning[W003]: passes 1–5"), "{out}");
    assert!(out.contains("in 1 thread"), "{out}");
}

#[test]
fn json_findings_have_exactly_the_documented_keys() {
    let (code, out) = check_cli(
        "json",
        CLEAN,
        &gsk(&["--stock-start", "10", "--format", "json"]),
    );
    assert_eq!(code, 0, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let list = v.as_array().unwrap();
    assert!(!list.is_empty());
    let keys = ["code", "column", "file", "hint", "level", "line", "message"];
    for f in list {
        let mut got: Vec<&str> = f.as_object().unwrap().keys().map(String::as_str).collect();
        got.sort_unstable();
        assert_eq!(got, keys, "{f}");
    }
    let w = &list[0];
    assert_eq!(w["level"], "warning");
    assert_eq!(w["code"], "W003");
    assert_eq!(w["line"], 4);
    assert_eq!(w["column"], 1);
    assert!(w["file"].as_str().unwrap().ends_with("check-json.nc"));
    // The assumptions are notes: level "note", code null.
    assert!(list
        .iter()
        .any(|f| f["level"] == "note" && f["code"].is_null()));
}

#[test]
fn words_without_a_decimal_point_on_a_least_increment_control() {
    // Fanuc reads F2 on a thread block as 2 least increments: a lead of 0.002 mm. One warning, at
    // the first such word, with the value meant and a count of the others.
    let src = "G21 G99\nG97 S500 M3\nG0 X40. Z5.\nG92 X29.2 Z-30. F2\nX28.7\nX28\n";
    let (_, out) = check_cli("dot", src, &["-c", "fanuc"]);
    assert_eq!(out.matches("W006").count(), 1, "{out}");
    assert!(
        out.contains("warning[W006]: F2 has no decimal point: this control reads it as a lead of 0.002 mm (2 least increments of 0.001 mm); if 2 mm was meant, write F2. instead. 1 more axis or lead word is without a decimal point (line 6)"),
        "{out}"
    );
    assert!(out.contains("check-dot.nc:4:17"), "{out}");
    // `G0 X32 Z5` (the issue's program): X is read as 0.032 mm.
    let src = "G21 G99\nG0 X32 Z5\n";
    let (_, out) = check_cli("dot2", src, &["-c", "fanuc"]);
    assert!(
        out.contains("X32 has no decimal point: this control reads it as 0.032 mm (32 least increments of 0.001 mm); if 32 mm was meant, write X32. instead. 1 more axis or lead word is without a decimal point (line 2)"),
        "{out}"
    );
    // GSK reads X32 as 32 mm ("calculator" input): nothing to say.
    let (_, out) = check_cli("dot3", src, &gsk(&[]));
    assert!(!out.contains("W006"), "{out}");
    // A dwell's X is a time, and zero is zero either way.
    let (_, out) = check_cli("dot4", "G04 X1000\nG0 X0 Z0\n", &["-c", "fanuc"]);
    assert!(!out.contains("W006"), "{out}");
}

#[test]
fn a_g_code_the_controller_does_not_have_is_its_alarm() {
    // GSK's G78 checked as a Fanuc program: Fanuc's alarm at the word, the controllers that have it.
    let src = "G21\nG0 X40. Z5.\nG78 X29.2 Z-30. P1.2 Q0.3 F2.\n";
    let (code, out) = check_cli("g78", src, &["-c", "fanuc"]);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E015]: alarm PS0010 (improper G-code): G78 is not a G code of fanuc"),
        "{out}"
    );
    assert!(out.contains("check-g78.nc:3:1"), "{out}");
    assert!(
        out.contains(
            "help: gsk980 has G78 with these words: check the program with --controller gsk980"
        ),
        "{out}"
    );
    // G33 on Fanuc system A (which threads with G32): LinuxCNC and OmniTurn have a G33 with K.
    let src = "G21\nG0 X40. Z5.\nG33 Z-30. K2.\n";
    let (code, out) = check_cli("g33", src, &["-c", "fanuc"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("G33 is not a G code of fanuc"), "{out}");
    assert!(
        out.contains("omniturn, linuxcnc and sinumerik have G33 with these words"),
        "{out}"
    );
    // A one-block G76 (FS15 / Haas format) on a two-block control.
    let src = "G21\nG0 X32. Z5.\nG76 X27.546 Z-30. K1.227 D0.4 F2. A60\n";
    let (code, out) = check_cli("g76-one-block", src, &["-c", "fanuc"]);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E015]: K is a word of the one-block G76 (X Z I K D F A P Q: Fanuc's FS15 program format, Haas), and fanuc reads G76 in two blocks"),
        "{out}"
    );
    // At the word, and the controllers that read the one-block form come from their vocabularies.
    assert!(out.contains("check-g76-one-block.nc:3:19"), "{out}");
    assert!(
        out.contains("fanuc15 and haas have G76 with these words: check the program with --controller fanuc15 or --controller haas"),
        "{out}"
    );
    assert!(
        out.contains(
            "on fanuc: G76 P(m)(r)(a) Q(Δdmin) R(d), then G76 X(U) Z(W) R(i) P(k) Q(Δd) F(L)"
        ),
        "{out}"
    );
    // LinuxCNC's own words for a code it does not have; GSK's G32 is not LinuxCNC's.
    let (code, out) = check_cli("lc-g32", "G0 X20 Z5\nG32 Z-20 F1.5\n", &["-c", "linuxcnc"]);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("Unknown g code used: G32 is not a G code of linuxcnc"),
        "{out}"
    );
    assert!(
        out.contains("gsk980, fanuc, fanuc15 and haas have G32"),
        "{out}"
    );
}

#[test]
fn a_program_with_no_thread_says_so_on_standard_error() {
    let src = "G21\nG0 X40. Z5.\nG1 Z-30. F0.2\n";
    let (code, out, err) = check_cli_err("nothread", src, &["-c", "fanuc"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("in 0 threads"), "{out}");
    assert!(
        err.starts_with("warning: no thread found in ")
            && err.contains(": no threading cycle and no synchronised move\n  = help: this controller threads with G32, G76, G92; is it the right --controller?"),
        "{err}"
    );
    // A G92 threading program read on LinuxCNC, where G92 sets offsets: no thread.
    let src = "G0 X40 Z5\nG92 X29.2 Z-30\n";
    let (_, _, err) = check_cli_err("nothread-lc", src, &["-c", "linuxcnc"]);
    assert!(err.contains("threads with G33, G76"), "{err}");
    for cmd in ["passes", "plot"] {
        let input = tmp("check-nothread.nc");
        let mut c = Command::new(env!("CARGO_BIN_EXE_threadcut"));
        c.arg(cmd).arg(&input).args(["-c", "fanuc"]);
        if cmd == "plot" {
            c.arg("-o").arg(tmp("check-nothread.svg"));
        }
        let out = c.output().unwrap();
        assert!(out.status.success());
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains("no thread found"), "{cmd}: {err}");
    }
}

#[test]
fn apt_programs_are_checked_and_plotted() {
    let file = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/m20-external.apt");
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["check", file])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(out.status.success(), "{text}");
    assert!(text.contains("0 errors, 0 warnings in 1 thread"), "{text}");
    // With a controller's limits.
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["check", file, "-c", "gsk980", "--format", "json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let svg = tmp("check-apt.svg");
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["plot", file, "-o"])
        .arg(&svg)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("line 12: apt cycle"), "{}", &text[..400]);
}

/// A synchronised move whose start is not known (here after `G28 W0.`, which the fanuc profile
/// does not place) cuts from a point the program does not say: it is no pass (not a pass from Z0),
/// `check`, `passes` and `plot` warn at it, and the passes after it are one thread of their own.
#[test]
fn a_thread_move_from_an_unknown_start_is_no_pass_and_says_so() {
    let src = "G21 G99\nG97 S500 M3\nG0 X30. Z5.\nG28 W0.\nG32 Z-20. F1.5\nG0 X32.\nZ5.\nX29.2\nG32 Z-20. F1.5\nG0 X32.\nZ5.\nX28.8\nG32 Z-20. F1.5\nG0 X32.\nM30\n";
    let (code, out) = check_cli("unknown-start", src, &["-c", "fanuc"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains(
            "warning[W001]: this synchronised move starts where the tool's Z is not known"
        ),
        "{out}"
    );
    assert!(out.contains("check-unknown-start.nc:5:1"), "{out}");
    assert!(out.contains("0 errors, 1 warning in 1 thread"), "{out}");
    // Through the library: the thread is the two passes of lines 9 and 13, 0.2 mm apart.
    let m = Machine::built_in("fanuc").unwrap();
    let mut threads: Vec<Thread> = Vec::new();
    let summary = threadcut::threads::each_gcode(src.as_bytes(), &m, None, |t| {
        threads.push(t);
        Ok(())
    })
    .unwrap();
    assert_eq!(threads.len(), 1);
    assert_eq!(threads[0].passes.len(), 2);
    assert!((threads[0].passes[1].depth - 0.2).abs() < 1e-9);
    assert_eq!(summary.warnings.len(), 1);
    assert_eq!(summary.warnings[0].code, Code::Suspicious);
    assert_eq!(summary.warnings[0].span.line, 5);
    // `passes` says it on standard error.
    let input = tmp("passes-unknown-start.nc");
    std::fs::write(&input, src).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["passes", "-c", "fanuc"])
        .arg(&input)
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("warning[W001]") && err.contains(":5:1"),
        "{err}"
    );
}

/// The blank's surface is compared at the program's resolution: in inch, one increment of X
/// (.0001 on diameter) is 1.27 µm of radius, more than the fixed micrometre the check used. A
/// return along Z at X.4999 over stock of Ø.5 is on the stock, not through it; X.4998 is through.
#[test]
fn the_blank_is_compared_at_the_programs_resolution() {
    let src = "G20 G99\nG97 S500 M3\nG0 X.4999 Z.2\nX.49\nG32 Z-1. F.076923\nG0 X.4999\nZ.2\nX.48\nG32 Z-1. F.076923\nG0 X.4999\nZ.2\nM30\n";
    let blank = [
        "-c",
        "fanuc",
        "--stock-diameter",
        ".5",
        "--stock-start",
        "0",
    ];
    let (code, out) = check_cli("inch-on-stock", src, &blank);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings in 1 thread"), "{out}");
    let (code, out) = check_cli("inch-in-stock", &src.replace("X.4999", "X.4998"), &blank);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E011]: passes 1, 2: a rapid move"),
        "{out}"
    );
}

/// `check` runs a program with control flow as the control does: G32 passes written once in a
/// subprogram that a loop calls four times are one thread of four passes, judged at the G32's
/// line; `Options::max_blocks` bounds the run (an endless loop is the error, the run stopped).
#[test]
fn check_runs_programs_with_control_flow() {
    let src = "G21 G99\nG97 S500 M03\nG0 X32. Z5.\n#100=0\nM98 P100 L4\nG0 X60. Z60.\nM30\nO0100\n#100=#100+0.25\nG0 X[30.-#100]\nG32 Z-25. F2.\nG0 X32.\nZ5.\nM99\n";
    let args = ["-c", "fanuc", "--thread", "M30x2-6g", "--stock-start", "0"];
    let (code, out) = check_cli("macro-passes", src, &args);
    assert_eq!(code, 2, "{out}");
    // Four passes of 0.125 mm from Ø29.75 to Ø29: 0.5 deep from the crest Ø30.
    assert!(
        out.contains(
            "error[E016]: minor diameter 29 > 27.508 max for M30x2-6g: the passes reach 0.5 deep"
        ),
        "{out}"
    );
    assert!(out.contains("check-macro-passes.nc:11:1"), "{out}");
    assert!(out.contains("1 error, 1 warning in 1 thread"), "{out}");
    let m = Machine::built_in("fanuc").unwrap();
    let endless = "G21\nG0 X30. Z5.\n#1=0\nWHILE[#1GE0]DO1\n#1=#1+1\nEND1\nM30\n";
    let opts = Options {
        max_blocks: 1000,
        ..Options::default()
    };
    let r = check::check(endless.as_bytes(), check::Source::Gcode(&m), &opts).unwrap();
    assert!(r.stopped);
    let d = r.diagnostics.iter().find(|d| d.is_error()).unwrap();
    assert!(
        d.message
            .contains("the loop of lines 4 to 6 ran past 1000 executed blocks"),
        "{}",
        d.message
    );
    assert_eq!(d.span.line, 4);
}
