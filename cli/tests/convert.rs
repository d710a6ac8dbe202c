//! `threadcut convert`: native cycles where reading them back reproduces the motion, plain moves
//! with a reason otherwise, other blocks rewritten where they mean the same thing.

use std::path::PathBuf;
use std::process::{Command, Output};

use threadcut::gcode::MotionMode;
use threadcut::machine::Machine;
use threadcut::program::{self, Event};
use threadcut::toolpath::{self, MotionKind};
use threadcut::translate::{job_to_string, Written};
use threadcut::units::Pos;

/// `text` written to a file of that name, in a directory of its own: tests run in parallel and
/// several write a `t.nc` of their own.
fn file(name: &str, text: &str) -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("threadcut-convert-{}-{n}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn convert(name: &str, text: &str, from: &str, to: &str) -> Output {
    let p = file(name, text);
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["convert", p.to_str().unwrap(), "--from", from, "--to", to])
        .output()
        .unwrap()
}

fn ok(o: Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout).unwrap()
}

/// Every move the program makes on `controller`: plain moves and expanded cycles, as
/// (rapid?, end point, lead along the longer axis).
fn motion(text: &str, controller: &str) -> Vec<(bool, Pos, f64)> {
    let m = Machine::built_in(controller).unwrap();
    let mut moves = Vec::new();
    program::run(text.as_bytes(), &m, |_, ev| {
        match ev {
            Event::Plain { mv: Some(mv), .. } => {
                // Along the longer axis whatever the lead word means (LinuxCNC's K is along the
                // path): the reader converts it.
                let lead = mv.lead.unwrap_or(0.0);
                moves.push((mv.mode == MotionMode::Rapid, mv.to, lead));
            }
            Event::Cycle { job, .. } => {
                for mo in toolpath::build(&job)?.motions {
                    let lead = match mo.kind {
                        MotionKind::Thread { lead, .. } => lead,
                        _ => 0.0,
                    };
                    moves.push((mo.kind == MotionKind::Rapid, mo.to, lead));
                }
            }
            _ => {}
        }
        Ok(())
    })
    .unwrap_or_else(|e| panic!("{e}\n{text}"));
    moves
}

fn same_motion(a: &[(bool, Pos, f64)], b: &[(bool, Pos, f64)], tol: f64) {
    // Zero-length moves (LinuxCNC's final rapid) carry no motion.
    let strip = |v: &[(bool, Pos, f64)]| {
        let mut out: Vec<(bool, Pos, f64)> = Vec::new();
        for &m in v {
            if out.last().is_some_and(|l| l.1.distance(m.1) < 1e-12) {
                continue;
            }
            out.push(m);
        }
        out
    };
    let (a, b) = (strip(a), strip(b));
    assert_eq!(a.len(), b.len(), "\n{a:?}\n{b:?}");
    for (i, (x, y)) in a.iter().zip(&b).enumerate() {
        assert_eq!(x.0, y.0, "move {i}: {x:?} {y:?}");
        let d = x.1.minus(y.1);
        assert!(
            d.x.abs() <= tol && d.z.abs() <= tol,
            "move {i}: {x:?} {y:?}"
        );
        assert!((x.2 - y.2).abs() <= 1e-4, "move {i}: lead {x:?} {y:?}");
    }
}

const FANUC_M30: &str = "G21 G99\nG97 S600 M3\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\nG0 X100. Z100.\nM30\n";

#[test]
fn fanuc_g76_becomes_gsk_g76_natively_and_back() {
    let gsk = ok(convert("f.nc", FANUC_M30, "fanuc", "gsk980"));
    assert!(
        gsk.contains("G76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n"),
        "{gsk}"
    );
    same_motion(&motion(FANUC_M30, "fanuc"), &motion(&gsk, "gsk980"), 1e-9);
    let back = ok(convert("g.nc", &gsk, "gsk980", "fanuc"));
    assert!(
        back.contains("G76 X27.546 Z-30. P1227 Q400 F2.\n"),
        "{back}"
    );
    same_motion(&motion(&back, "fanuc"), &motion(FANUC_M30, "fanuc"), 1e-9);
}

#[test]
fn fanuc_g92_becomes_gsk_g92_with_its_chamfer_as_j_k() {
    let src = "G0 X40. Z5.\nG92 X29.2 Z-30. F2.\nX28.6\nG0 X100.\n";
    let gsk = ok(convert("g92.nc", src, "fanuc", "gsk980"));
    assert!(
        gsk.contains("G92 X29.2 Z-30. J2. K2. F2.\nG92 X28.6 Z-30. J2. K2. F2.\n"),
        "{gsk}"
    );
    same_motion(&motion(src, "fanuc"), &motion(&gsk, "gsk980"), 1e-9);
}

#[test]
fn linuxcnc_to_fanuc_is_plain_g32_moves_with_the_reason() {
    let src = "G7 G21 G18\nS500 M3\nG0 X22 Z5\nG76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\nG0 X40\nM2\n";
    let out = ok(convert("l.ngc", src, "linuxcnc", "fanuc"));
    assert!(
        out.contains(
            "(threadcut: plain moves, not the native cycle: G76 retracts to the start point's X"
        ),
        "{out}"
    );
    assert!(out.contains("\nG21 G18\n") && !out.contains("G7 "), "{out}");
    assert!(out.contains("G32 X20.7 Z-27.651 F2.5\n"), "{out}");
    // The converted program moves as LinuxCNC does, to the target's 0.001 mm (diameter) output.
    same_motion(
        &motion(src, "linuxcnc"),
        &motion(&out, "fanuc"),
        0.5e-3 + 1e-9,
    );
}

#[test]
fn fanuc_to_linuxcnc_writes_g33_k_along_the_path() {
    // A taper G32: F is the lead along Z (the longer axis); LinuxCNC's K is along the path.
    let src = "G0 X20. Z5.\nG32 X24. Z-15. F2.\nG0 X40.\n";
    let out = ok(convert("t.nc", src, "fanuc", "linuxcnc"));
    let k = 2.0 * (2.0f64).hypot(20.0) / 20.0;
    assert!(
        out.contains(&format!(
            "G33 X12. Z-15. K{}\n",
            threadcut::post::number(k, 6, false)
        )),
        "{out}"
    );
    assert!(
        out.starts_with(
            "(threadcut convert: fanuc to linuxcnc, mm, feed per revolution)\nG21 G90 G8 G18 G95 G97\n"
        ),
        "{out}"
    );
    same_motion(&motion(src, "fanuc"), &motion(&out, "linuxcnc"), 1e-4);
    // A G76 becomes plain G33 moves: LinuxCNC's G76 cannot return to the start point.
    let g76 = ok(convert("g76.nc", FANUC_M30, "fanuc", "linuxcnc"));
    assert!(
        g76.contains("LinuxCNC's G76 retracts each pass to its own X"),
        "{g76}"
    );
    assert!(
        g76.contains("G95"),
        "G99 (feed per revolution) is G95: {g76}"
    );
    same_motion(
        &motion(FANUC_M30, "fanuc"),
        &motion(&g76, "linuxcnc"),
        0.5e-4 + 1e-9,
    );
}

#[test]
fn linuxcnc_g76_round_trips_natively() {
    let m = Machine::built_in("linuxcnc").unwrap();
    for src in [
        "G8\nM3\nG0 X11 Z5\nG76 P2.5 Z-30 I-0.5 J0.15 K0.76675 R1.5 Q29.5 H2 E2 L2\n",
        "G8\nM3\nG0 X6 Z-40\nG76 P1.75 Z2 I1.2 J0.1 K0.95 Q30 H1 E1.5 L3\n",
        "G7\nM3\nG0 X22 Z5\nG76 P2 Z-20 I-1 J0.2 K2.4 R2\n",
    ] {
        let job = &program::jobs(src.as_bytes(), &m).unwrap()[0];
        let (text, written) = job_to_string(&m, job).unwrap();
        assert_eq!(written, Written::Native, "{src}\n{text}");
        assert!(text.starts_with("G76 P"), "{text}");
    }
}

#[test]
fn same_controller_is_a_copy() {
    let src = "G7 G21 G18\nS500 M3\nG0 X22 Z5\nG76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\nM2\n";
    let out = ok(convert("same.ngc", src, "linuxcnc", "linuxcnc"));
    assert_eq!(
        out,
        format!("(threadcut convert: linuxcnc to linuxcnc)\n{src}")
    );
}

#[test]
fn blocks_without_a_counterpart_are_errors_at_their_word() {
    // Tools, set positions and reference returns are converted where the target has them …
    let src = "G21\nG0 X32. Z5.\nT0102\nG50 X100. Z100.\nG28 U0.\n";
    let out = ok(convert("t.nc", src, "fanuc", "linuxcnc"));
    assert!(
        out.contains("\nT1 M6 G43 H2\nG92 X50. Z100.\nG91 G28 X0.\nG90\n"),
        "{out}"
    );
    // … and refused at their word where it does not: OmniTurn's T is the tool with its own offset.
    let o = convert("t.nc", src, "fanuc", "omniturn");
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("t.nc:3:1") && err.contains("offset 2"),
        "{err}"
    );
    // A reference return through an intermediate point away from the tool is not converted.
    let o = convert("g28.nc", "G0 X40. Z5.\nG28 U10.\n", "fanuc", "linuxcnc");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("g28.nc:2:5"));
    // G2 with centre words: not rewritten rather than guessed.
    let o = convert(
        "arc.ngc",
        "G8\nG0 X10 Z0\nG2 X12 Z-2 I2 K0\n",
        "linuxcnc",
        "fanuc",
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&o.stderr).contains(":3:"),
        "{:?}",
        o
    );
}

#[test]
fn the_feed_rate_comes_back_after_thread_moves_on_an_f_lead_target() {
    // On Fanuc, G32's F is also the feed register: after the threads, a G1 that relied on the
    // source's modal F0.2 would feed at the lead. The converter restores it before the next block.
    let src = "G8 G21 G95\nS500 M3\nG1 X11 Z5 F0.2\nG76 P2.5 Z-30 I-0.5 J0.15 K0.76675 H1\nG1 X12 Z-31\nG33 X11 Z-40 K2\nG33 X11 Z-45 K2\nG1 X13\n";
    let out = ok(convert("feed.ngc", src, "linuxcnc", "fanuc"));
    assert!(out.contains("G0 X22. Z-30.\nG1 X24. Z-31. F0.2\n"), "{out}");
    assert!(
        // The first G33 is a taper from X12 Z-31: F is its lead along Z, 2·9/√82.
        out.contains("G32 X22. Z-40. F1.9878\nG32 X22. Z-45. F2.\nG1 X26. F0.2\n"),
        "{out}"
    );
}

#[test]
fn linuxcnc_blanks_inside_words_are_written_without_them() {
    // LinuxCNC reads `S 1 2 0 0` as S1200; the target gets S1200, which it can read.
    let src = "G 8 G 2 1 G 1 8\nS 1 2 0 0 M 3\nG0 X 1 6 Z 5\nG 7 6 P2 . 5 Z - 3 0 I - 1 J 0 . 3 K 1 . 5\nM2\n";
    let out = ok(convert("blanks.ngc", src, "linuxcnc", "fanuc"));
    assert!(out.contains("S1200") && out.contains("M3"), "{out}");
    same_motion(&motion(src, "linuxcnc"), &motion(&out, "fanuc"), 0.0006);
}

#[test]
fn reference_returns_keep_their_intermediate_point() {
    // `G28 U0 W0` between two cycles: its words are the intermediate point, not a move to be
    // rewritten as absolute coordinates; the program positions again after it.
    let src = "G21 G99\nG97 S600 M3\nG0 X32. Z5.\nG92 X29.2 Z-30. F2.\nG28 U0 W0\nG0 X32.\nZ5.\nG92 X28.8 Z-30. F2.\nM30\n";
    let out = ok(convert("g28.nc", src, "fanuc", "gsk980"));
    assert!(out.contains("G28 U0. W0."), "{out}");
    same_motion(&motion(src, "fanuc"), &motion(&out, "gsk980"), 0.0006);
}

/// `convert --filter` as LinuxCNC's AXIS runs a program filter (`/usr/bin/axis`,
/// `filter_program`): `sh -c "<the INI's command> '<file>'"`, standard output the program,
/// `FILTER_PROGRESS=N` lines on standard error (its pattern `^FILTER_PROGRESS=(\d*)$`), any other
/// standard-error line shown in the "Filter failed" dialog when the exit status is not 0.
#[test]
fn convert_runs_as_a_linuxcnc_program_filter() {
    let bin = env!("CARGO_BIN_EXE_threadcut");
    // A program longer than one read (64 KiB), so that the progress climbs in steps.
    let mut src = String::from("G21 G99\nT0101\nG97 S800 M03\nG00 X22. Z3.\n");
    for _ in 0..16000 {
        src.push_str("G00 X22. Z3.\n");
    }
    src.push_str("G76 P010060 Q50 R0.02\nG76 X17.546 Z-20. P1227 Q400 F2.\nG00 X40. Z50.\nM30\n");
    let path = file("filter.nc", &src);
    let filter = format!("{bin} convert --filter --from fanuc --to linuxcnc");
    let run = Command::new("sh")
        .arg("-c")
        .arg(format!("{filter} '{}'", path.display()))
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let out = String::from_utf8(run.stdout).unwrap();
    assert!(out.contains("G33") || out.contains("G76"), "{out}");
    let stderr = String::from_utf8(run.stderr).unwrap();
    let progress: Vec<u32> = stderr
        .lines()
        .filter_map(|l| l.strip_prefix("FILTER_PROGRESS="))
        .map(|n| n.parse().unwrap())
        .collect();
    assert!(progress.len() >= 2, "{stderr}");
    assert!(progress.windows(2).all(|w| w[0] < w[1]), "{progress:?}");
    assert_eq!(progress.last(), Some(&100));
    // A block LinuxCNC cannot be given: status not 0, the reason on standard error, for the dialog.
    let bad = file(
        "filter-bad.nc",
        "G21 G99\nG0 X0 Z5.\nS300 M3\nG83 Z-10. Q2000 F0.1\nM30\n",
    );
    let run = Command::new("sh")
        .arg("-c")
        .arg(format!("{filter} '{}'", bad.display()))
        .output()
        .unwrap();
    assert_ne!(run.status.code(), Some(0));
    let stderr = String::from_utf8(run.stderr).unwrap();
    assert!(stderr.contains("G83 (peck drilling cycle)"), "{stderr}");
    assert!(
        !stderr.contains('\x1b'),
        "no colour for the dialog: {stderr:?}"
    );
    // The program goes to standard output: --filter with -o is a usage error.
    let o = Command::new(bin)
        .args([
            "convert", "--filter", "--from", "fanuc", "--to", "linuxcnc", "-o", "x.ngc",
        ])
        .arg(&path)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
}
