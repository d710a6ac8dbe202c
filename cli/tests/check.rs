//! `threadcut check`: each check with a hand-computed case, through the binary (exit status,
//! line:column) and through the library.

use std::path::PathBuf;
use std::process::Command;

use threadcut::diag::Code;
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::sim::check::{self, CheckOptions, Rpm};
use threadcut::thread::DepthLaw;

fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Runs `threadcut check` on `src`; returns (exit status, stdout).
fn check_cli(name: &str, src: &str, extra: &[&str]) -> (i32, String) {
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
    )
}

fn gsk<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = vec!["-c", "gsk980"];
    v.extend_from_slice(extra);
    v
}

/// A radial 2 mm thread from Z10 to Z-30, spindle at 600 rpm.
const CLEAN: &str =
    "G00 X80 Z10\nG97 S600 M03\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";

#[test]
fn a_clean_program_passes() {
    // The part's face at Z5 leaves 5 mm of run-up; 2.379 mm are needed (see below).
    let (code, out) = check_cli("clean", CLEAN, &gsk(&["--stock-start", "5"]));
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings in 1 cycle"), "{out}");
}

#[test]
fn run_up_shorter_than_the_servo_lag() {
    // δ1 = T1·V·(−1 − ln a) = 0.033 s · (2 mm · 600 rpm / 60) · (−1 − ln 0.01) = 2.3794 mm, and
    // the blank starts where the thread does.
    let (code, out) = check_cli("runup", CLEAN, &gsk(&[]));
    assert_eq!(code, 0, "a warning only: {out}");
    assert!(out.contains("warning[W003]"), "{out}");
    assert!(out.contains("needs 2.3794 mm of run-up"), "{out}");
    assert!(out.contains("check-runup.nc:4:1"), "{out}");
    // With the face 2 mm away, 0.3794 mm are missing.
    let (_, out) = check_cli("runup2", CLEAN, &gsk(&["--stock-start", "8"]));
    assert!(out.contains("starts 2 mm before the blank"), "{out}");
    assert!(out.contains("start the cycle 0.3794 mm further"), "{out}");
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
    // 2666 rpm is fine.
    let ok = src.replace("S3000", "S2666");
    let (code, out) = check_cli("feed-ok", &ok, &gsk(&["--stock-start", "100"]));
    assert!(!out.contains("E012"), "{out}");
    assert_eq!(
        code, 2,
        "the face at Z100 puts the start point inside the blank: {out}"
    );
}

#[test]
fn rapid_moves_into_the_blank() {
    // Right-flank infeed (r = 02): each pass starts d·tan 30° toward −Z, inside the blank that
    // begins at the thread's start Z10.
    let src = "G00 X80 Z10\nG97 S300\nG78 P010260 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let (code, out) = check_cli("rapid", src, &gsk(&[]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains(
            "error[E011]: pass 1: a rapid move from (radius 40, Z10) to (radius 30.8, Z9.7691)"
        ),
        "{out}"
    );
    // With the part's face at Z5 every pass starts in the air.
    let (_, out) = check_cli("rapid-face", src, &gsk(&["--stock-start", "5"]));
    assert!(!out.contains("E011"), "{out}");
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
    let opts = CheckOptions {
        stock_start: Some(5.0),
        ..CheckOptions::default()
    };
    let mut out = Vec::new();
    check::check_cycle(&job, &machine, &opts, &Rpm(300.0), &mut out);
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
fn a_tool_the_section_cannot_draw_is_a_warning() {
    // P(a) = 00: a 0° tool. The controller runs the cycle; the section cannot be drawn.
    let src = "G00 X80 Z10\nG97 S300\nG78 P010000\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let (code, out) = check_cli("angle0", src, &gsk(&["--stock-start", "5"]));
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("warning[W004]: the groove cannot be simulated"),
        "{out}"
    );
}
