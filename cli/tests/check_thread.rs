//! `threadcut check --thread NAME`: the thread a program cuts, judged against the standard's class
//! limits, external and internal, in mm and in inch programs. Every expected number is worked out
//! below from the standard's basic profile (ISO 68-1, ASME B1.1): with 30° flanks, a tool whose
//! lowest point is at diameter T cuts a pitch diameter of
//!
//! * external, nose radius r: the flanks meet r below the tip (r/sin 30° − r), and the groove is half
//!   a pitch wide H/2 above that point, so PD = T + H − 2r;
//! * internal, flat w: the flanks meet (w/2)/tan 30° beyond the tip, so PD = T + w/tan 30° − H.

use std::path::PathBuf;
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

fn check(name: &str, src: &str, args: &[&str]) -> (i32, String) {
    threadcut("check", &format!("thread-{name}.nc"), src, args)
}

/// `threadcut COMMAND FILE ARGS` on `src` written to `file`: (exit status, stdout and stderr).
fn threadcut(command: &str, file: &str, src: &str, args: &[&str]) -> (i32, String) {
    let input = tmp(file);
    std::fs::write(&input, src).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .arg(command)
        .arg(&input)
        .args(args)
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap() + &String::from_utf8(out.stderr).unwrap();
    (out.status.code().unwrap(), text)
}

/// A Fanuc G76 from X`start` Z5 (mm) or Z.25 (inch) to root X`x`, thread height `k` in least
/// increments, lead `f`.
fn g76(inch: bool, start: &str, x: &str, z: &str, k: u32, f: &str) -> String {
    if inch {
        format!(
            "G20 G99\nG97 S600 M3\nG0 X{start} Z.25\nG76 P010060 Q0020 R.001\nG76 X{x} Z{z} P{k:04} Q0150 F{f}\nG0 X4. Z4.\nM30\n"
        )
    } else {
        format!(
            "G21 G99\nG97 S500 M3\nG0 X{start} Z5.\nG76 P010060 Q100 R0.05\nG76 X{x} Z{z} P{k} Q300 F{f}\nG0 X100. Z100.\nM30\n"
        )
    }
}

const FANUC: &[&str] = &["-c", "fanuc"];

fn args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = FANUC.to_vec();
    v.extend_from_slice(extra);
    v
}

/// External M30x2-6g (mm): pitch diameter 28.493–28.663, minor at most 27.508 (ISO 965-1).
/// H = 1.73205. A 0.25 mm nose at T = 27.4: PD = 27.4 + 1.73205 − 0.5 = 28.63205: inside.
#[test]
fn external_metric_inside_and_outside_the_class() {
    let ok = g76(false, "32.", "27.4", "-30.", 1300, "2.");
    let (code, out) = check(
        "ext-mm-ok",
        &ok,
        &args(&["--thread", "M30x2-6g", "--nose-radius", "0.25"]),
    );
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("E016") && !out.contains("W009"), "{out}");
    assert!(
        out.contains(
            "judged against M30x2-6g; cut: pitch diameter 28.6321, minor diameter 27.4 mm"
        ),
        "{out}"
    );
    // The textbook depth (17/24·H = 1.227 to d3 = 27.546) with the same tool: PD = 27.546 +
    // 1.73205 − 0.5 = 28.77805 > 28.663, and the root 27.546 > 27.508. Both are facts: errors.
    // Depth needed for the PD: 1.227 + (28.77805 − 28.663)/2 = 1.28453 to 1.227 + (28.77805 −
    // 28.493)/2 = 1.36953; for the minor: 1.227 + (27.546 − 27.508)/2 = 1.246.
    let book = g76(false, "32.", "27.546", "-30.", 1227, "2.");
    let (code, out) = check(
        "ext-mm-book",
        &book,
        &args(&["--thread", "M30x2-6g", "--nose-radius", "0.25"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: minor diameter 27.546 > 27.508 max for M30x2-6g: the passes reach 1.227 deep from the crest (Ø30), 6g needs at least 1.246"),
        "{out}"
    );
    assert!(
        out.contains("error[E016]: pitch diameter 28.7781 > 28.663 max for M30x2-6g: the passes reach 1.227 deep from the crest (Ø30), 6g needs 1.2845–"),
        "{out}"
    );
    assert!(out.contains("thread-ext-mm-book.nc:5:1"), "{out}");
    // Without the tool's tip the standard's root form is assumed (a nose radius of H/6 = 0.2887):
    // PD = 27.546 + 1.73205 − 0.57735 = 28.7007 = the basic pitch diameter, still > 28.663, but a
    // warning that names the assumption. The root stays an error.
    let (code, out) = check("ext-mm-assumed", &book, &args(&["--thread", "M30x2-6g"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("warning[W009]: pitch diameter 28.7007 > 28.663 max for M30x2-6g"),
        "{out}"
    );
    assert!(
        out.contains("(with a nose radius of 0.2887 mm: assumed, the standard's root form)"),
        "{out}"
    );
}

/// The issue's case: an M50x2 whose G76 P900 cuts far too shallow.
#[test]
fn the_issues_m50x2_that_cuts_too_shallow() {
    // Crest Ø50 (48.2 + 2·0.9), root 48.2 > 47.508 (6g's d3 max): 1.246 deep is needed.
    let src = g76(false, "52.", "48.2", "-40.", 900, "2.");
    let (code, out) = check("m50", &src, &args(&["--thread", "M50x2-6g"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: minor diameter 48.2 > 47.508 max for M50x2-6g: the passes reach 0.9 deep from the crest (Ø50), 6g needs at least 1.246"),
        "{out}"
    );
    // PD with the assumed H/6 nose: 48.2 + 1.73205 − 0.57735 = 49.3547.
    assert!(
        out.contains("pitch diameter 49.3547 > 48.663 max for M50x2-6g"),
        "{out}"
    );
}

/// Internal M30x2-6H (mm): pitch diameter 28.701–28.925, major at least 30. A 0.25 mm flat at
/// T = 30.1: PD = 30.1 + 0.25/tan 30° − 1.73205 = 30.1 + 0.43301 − 1.73205 = 28.80096: inside.
#[test]
fn internal_metric_inside_and_outside_the_class() {
    let ok = "G21 G99\nG97 S450 M3\nG0 X26. Z4.\nG76 P010060 Q50 R0.03\nG76 X30.1 Z-25. P1133 Q300 F2.\nG0 Z50.\nM30\n";
    let (code, out) = check(
        "int-mm-ok",
        ok,
        &args(&["--thread", "M30x2-6H", "--tip-flat", "0.25"]),
    );
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("E016") && !out.contains("W009"), "{out}");
    assert!(
        out.contains("cut: pitch diameter 28.801, major diameter 30.1 mm"),
        "{out}"
    );
    // Too shallow: T = 29.9 < 30 (1.033 + 0.05 = 1.083 deep needed), PD = 29.9 − 1.29904 =
    // 28.60096 < 28.701.
    let shallow = ok.replace("X30.1 Z-25. P1133", "X29.9 Z-25. P1033");
    let (code, out) = check(
        "int-mm-shallow",
        &shallow,
        &args(&["--thread", "M30x2-6H", "--tip-flat", "0.25"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: major diameter 29.9 < 30 min for M30x2-6H: the passes reach 1.033 deep from the crest (Ø27.834), 6H needs at least 1.083"),
        "{out}"
    );
    assert!(
        out.contains("error[E016]: pitch diameter 28.601 < 28.701 min for M30x2-6H"),
        "{out}"
    );
    // The class of the other side: the program cuts an internal thread.
    let (code, out) = check("int-mm-side", ok, &args(&["--thread", "M30x2-6g"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains(
            "M30x2-6g is a class of external threads, and the program cuts an internal thread"
        ),
        "{out}"
    );
}

/// External 3/4-10 UNC-2A (inch program): pitch diameter 0.6773–0.6832, minor at most 0.6291.
/// H = 0.0866025. A 0.012" nose at T = 0.618: PD = 0.618 + 0.0866025 − 0.024 = 0.6806: inside.
#[test]
fn external_inch_inside_and_outside_the_class() {
    let ok = g76(true, ".85", ".618", "-1.", 660, ".1");
    let (code, out) = check(
        "ext-in-ok",
        &ok,
        &args(&["--thread", "3/4-10 UNC-2A", "--nose-radius", ".012"]),
    );
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("E016") && !out.contains("W009"), "{out}");
    assert!(
        out.contains("cut: pitch diameter 0.6806, minor diameter 0.618 inch"),
        "{out}"
    );
    // The textbook depth (0.0613 to 0.6273): PD = 0.6273 + 0.0626025 = 0.6899 > 0.6832.
    let book = g76(true, ".85", ".6273", "-1.", 613, ".1");
    let (code, out) = check(
        "ext-in-book",
        &book,
        &args(&["--thread", "3/4-10 UNC-2A", "--nose-radius", ".012"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: pitch diameter 0.6899 > 0.6832 max for 3/4-10 UNC-2A"),
        "{out}"
    );
    assert!(!out.contains("minor diameter 0.6273 >"), "{out}");
    // The lead: F.1 is 10 threads per inch exactly; the same thread programmed in mm with F2.5
    // instead of 2.54: over the thread's 31.4 mm (from Z6 to Z-25.4: 12.56 turns of 2.5) the error
    // adds up to 12.56 · 0.04 = 0.5024 mm.
    let mm = "G21 G99\nG97 S600 M3\nG0 X21.6 Z6.\nG76 P010060 Q50 R0.03\nG76 X15.697 Z-25.4 P1558 Q380 F2.5\nG0 X100. Z100.\n";
    let (code, out) = check("ext-in-lead", mm, &args(&["--thread", "3/4-10 UNC-2A"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: lead 2.5 mm ≠ 2.54 mm for 3/4-10 UNC-2A: over the thread's 31.4 mm the error adds up to 0.5024"),
        "{out}"
    );
    assert!(
        out.contains("10 threads per inch is a lead of 2.54 mm"),
        "{out}"
    );
}

/// Internal 3/4-10 UNC-2B (inch program): pitch diameter 0.6850–0.6927, major at least 0.75. A
/// flat of P/8 = 0.0125" at T = 0.753: PD = 0.753 + 0.0125/tan 30° − 0.0866025 = 0.753 + 0.021651
/// − 0.0866025 = 0.68805 (0.688 to four decimals): inside.
#[test]
fn internal_inch_inside_and_outside_the_class() {
    let ok = "G20 G99\nG97 S500 M3\nG0 X.6 Z.2\nG76 P010060 Q0020 R.001\nG76 X.753 Z-.8 P0556 Q0120 F.1\nG0 Z2.\nM30\n";
    let (code, out) = check(
        "int-in-ok",
        ok,
        &args(&["--thread", "3/4-10 UNC-2B", "--tip-flat", ".0125"]),
    );
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("cut: pitch diameter 0.688, major diameter 0.753 inch"),
        "{out}"
    );
    // Too shallow by 0.004 on diameter: major 0.749 < 0.75, PD 0.68405 < 0.6850 (0.684 to four
    // decimals); 0.0536 + (0.75 − 0.749)/2 = 0.0541 deep is needed for the major, 0.0536 +
    // (0.685 − 0.68405)/2 = 0.0541 to 0.0536 + (0.6927 − 0.68405)/2 = 0.0579 for the PD.
    let shallow = ok.replace("X.753 Z-.8 P0556", "X.749 Z-.8 P0536");
    let (code, out) = check(
        "int-in-shallow",
        &shallow,
        &args(&["--thread", "3/4-10 UNC-2B", "--tip-flat", ".0125"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: major diameter 0.749 < 0.75 min for 3/4-10 UNC-2B"),
        "{out}"
    );
    assert!(
        out.contains("error[E016]: pitch diameter 0.684 < 0.685 min for 3/4-10 UNC-2B: the passes reach 0.0536 deep from the crest (Ø0.6418), 2B needs 0.0541–0.0579"),
        "{out}"
    );
}

/// A thread written as plain moves is judged like a cycle: its crest is the standard's (the
/// depths are measured from it), and its tool angle is the standard's.
#[test]
fn passes_written_as_moves_are_judged_too() {
    let f = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/real/fanuc-g32-radial-m20.nc"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["check", f, "-c", "fanuc", "--thread", "M20x2.5-6g"])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    // Root 16.933 > 16.891 (d3 = 16.933 − es 0.042): 1.5335 deep from Ø20, 1.5545 needed.
    assert!(
        text.contains("error[E016]: minor diameter 16.933 > 16.891 max for M20x2.5-6g: the passes reach 1.5335 deep from the crest (Ø20)"),
        "{text}"
    );
    assert!(
        text.contains("a 60° tool assumed (the program states none)"),
        "{text}"
    );
}

/// A cycle that states another tool angle than the thread's: the flanks are wrong.
#[test]
fn a_cycle_with_the_wrong_tool_angle() {
    let src = g76(false, "32.", "27.4", "-30.", 1300, "2.").replace("P010060", "P010055");
    let (code, out) = check(
        "angle",
        &src,
        &args(&["--thread", "M30x2-6g", "--nose-radius", "0.25"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: flank angles 27.5° and 27.5° (the cycle's 55° tool) for M30x2-6g, whose flanks are 30° ± 0.5° (60° thread)"),
        "{out}"
    );
}

/// The issue's LinuxCNC program whose I, J and K were written as radii in G7 (LinuxCNC reads them
/// as diameters and halves them): K0.92 cuts 0.46 deep, the root at Ø10 − 0.92 = 9.08 > 8.128
/// (M10x1.5-6g: d3 8.160 − 0.032). Without `--thread` nothing is assumed about the standard, so
/// nothing is said; with it, the root is an error.
#[test]
fn linuxcnc_depths_written_as_radii_in_g7() {
    let src = "G7 G21 G18\nS800 M3\nG0 X12 Z3\nG76 P1.5 Z-15 I-2.0 J0.2 K0.92 Q29.5 H1 R2\nM2\n";
    let (code, out) = check("lc-g7", src, &["-c", "linuxcnc"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors, 0 warnings"), "{out}");
    let (code, out) = check(
        "lc-g7-thread",
        src,
        &["-c", "linuxcnc", "--thread", "M10x1.5-6g"],
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: minor diameter 9.08 > 8.128 max for M10x1.5-6g: the passes reach 0.46 deep from the crest (Ø10), 6g needs at least 0.936"),
        "{out}"
    );
}

/// The issue's M20 program whose final X and thread height put the cycle's crest at Ø21.8: the
/// crest is no major diameter of M20x2.5 (and not its basic Ø20), and the root 17.8 is far above
/// d3 max 16.891.
#[test]
fn a_cycle_whose_crest_is_not_the_threads() {
    let src = g76(false, "24.", "17.8", "-25.", 2000, "2.5");
    let (code, out) = check("m20-crest", &src, &args(&["--thread", "M20x2.5-6g"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("warning[W009]: the cycle's crest Ø21.8 is not a major diameter of M20x2.5-6g (19.623–19.958 mm)"),
        "{out}"
    );
    assert!(out.contains("its first passes cut air"), "{out}");
    assert!(
        out.contains("error[E016]: minor diameter 17.8 > 16.891 max for M20x2.5-6g"),
        "{out}"
    );
    // A crest at the nominal Ø20 is not flagged (programs measure from it).
    let src = g76(false, "24.", "16.7", "-25.", 1650, "2.5");
    let (_, out) = check("m20-crest-ok", &src, &args(&["--thread", "M20x2.5-6g"]));
    assert!(!out.contains("the cycle's crest"), "{out}");
}

/// 1/2-14 NPT external (inch), judged at its gauge plane L1 = 0.320 from the pipe's end (Z0).
/// ASME B1.20.1: p = 1/14, E0 = 0.840 − (0.05·0.840 + 1.1)/14 = 0.75843, E1 = E0 + 0.320/16 =
/// 0.77843, ±1 turn = ±p/16 = ±0.0044643 on the pitch diameter (max 0.78289), H = 0.061859,
/// truncation 0.0024–0.0056 (mean 0.004). The G76 runs from Z0.2 to Z−0.6 with R−0.025 (1:16 on
/// diameter over 0.8), its root X0.7421 at Z−0.6, so at the gauge plane Z−0.32 the root is 0.7421 −
/// 0.28/16 = 0.7246. The flank infeed's last pass is at the programmed start, so the groove is one V:
/// * the standard's root form (a flat of 2·0.004·tan 30° = 0.0046188) cuts PD = root − 2·0.004 + H
///   = 0.7246 + 0.053859 = 0.778459: +0.0065 turns;
/// * a sharp tool cuts PD = root + H = 0.786459: (0.786459 − 0.77843)/0.0044643 = +1.80 turns;
/// * R−0.035 is a taper of 2·0.035/0.8 = 0.0875, outside 1/16 −1/192 … +1/96 (0.05729–0.07292).
#[test]
fn npt_external_judged_at_its_gauge_plane() {
    let npt = |r: &str| {
        format!("G20 G99\nG97 S600 M3\nG0 X1.0 Z0.2\nG76 P010060 Q20 R0.0005\nG76 X0.7421 Z-0.6 R{r} P539 Q150 F0.0714\nG0 X2. Z2.\nM30\n")
    };
    let good = npt("-0.025");
    let (code, out) = check("npt-ok", &good, &args(&["--thread", "1/2-14 NPT"]));
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("E016") && !out.contains("W009"), "{out}");
    assert!(
        out.contains("judged against 1/2-14 NPT at its gauge plane Z-0.32 (0.32 from the face at Z0, assumed): pitch diameter 0.7785 (basic 0.7784), the gauge +0.01 turns (+0.0005 inch) from its basic position (±1.00 allowed), taper 0.06250 on diameter"),
        "{out}"
    );
    // A sharp tool and the face given: where the ring gauge stands is a fact.
    let (code, out) = check(
        "npt-sharp",
        &good,
        &args(&[
            "--thread",
            "1/2-14 NPT",
            "--nose-radius",
            "0",
            "--stock-start",
            "0",
        ]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: pitch diameter 0.7865 inch at the gauge plane is above the maximum 0.7829 for 1/2-14 NPT: the gauge would stand +1.80 turns from its basic position (±1.00 allowed)"),
        "{out}"
    );
    // The face assumed: the same finding rests on it, a warning that says so.
    let (code, out) = check(
        "npt-sharp-face",
        &good,
        &args(&["--thread", "1/2-14 NPT", "--nose-radius", "0"]),
    );
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("warning[W009]: pitch diameter 0.7865 inch at the gauge plane")
            && out.contains("(assumed: the part's face at Z0 (--stock-start gives it))"),
        "{out}"
    );
    // The taper is the program's own: an error whatever was assumed.
    let (code, out) = check(
        "npt-taper",
        &npt("-0.035"),
        &args(&["--thread", "1/2-14 NPT"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: taper 0.08750 on diameter per unit length for 1/2-14 NPT, whose taper is 0.06250 (1:16), 0.05729 to 0.07292 allowed"),
        "{out}"
    );
    // A parallel thread named for a tapered one, and the other way round.
    let (code, out) = check("npt-as-unc", &good, &args(&["--thread", "1/2-13 UNC"]));
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("the thread is tapered (0.06250 on diameter per unit length), and 1/2-13 UNC-2A is a parallel thread"),
        "{out}"
    );
}

/// Rc1/2 internal (mm), judged half a pitch inside its opening (ISO 7-1:1994, 3.3 note 4, as quoted
/// in issue 27: the gauge plane P/2 = 0.907143 behind the face, where the pitch diameter of a 1:16
/// internal taper is P/2/16 = 0.056696 smaller than at the face; ±T2/2 =
/// ±2.3 mm, ±2.3/16 = ±0.14375 on the pitch diameter around d2 = 20.955 − 1.162 = 19.793; P =
/// 25.4/14 = 1.8142857, 55°). The G76 runs from Z3 to Z−20 with R0.719 (1:16 would be 0.71875:
/// the program's resolution, 2·0.001/23 on the taper, takes it as 1:16), its root X19.705 at Z−20,
/// so at Z0 the root is 19.705 + 20·(2·0.719/23) = 20.955435. The groove is half a pitch wide
/// P/(4·tan 27.5°) = 0.871305 above the flanks' meeting point, which a nose radius r puts
/// r/sin 27.5° − r beyond the tool's lowest point:
/// * the standard's root radius 0.137278·P = 0.249061 (0.290323 short of the point): PD =
///   20.955435 − 2·(0.871305 − 0.290323) = 19.793471 at the face, the basic size there, so
///   19.736775 at the gauge plane: (19.736775 − 19.793)/(P/16) = −0.50 turns;
/// * the root X20.005 (0.3 larger) and r = 0.249 (0.290254): PD = 21.255435 − 1.162102 = 20.093333,
///   at the face, 20.036637 at the gauge plane: above 19.93675 by (20.036637 − 19.793)/(P/16) =
///   +2.15 turns, ±2.3/P = ±1.27 allowed; with the standard's radius assumed instead,
///   21.255435 − 1.161964 = 20.093471 at the face, 20.036775 at the plane.
#[test]
fn rc_internal_judged_half_a_pitch_inside_its_opening() {
    let rc = |x: &str| {
        format!("G21 G99\nG97 S400 M3\nG0 X16. Z3.\nG76 P010055 Q50 R0.01\nG76 X{x} Z-20. R0.719 P1162 Q300 F1.814\nG0 X10. Z50.\nM30\n")
    };
    let (code, out) = check("rc-ok", &rc("19.705"), &args(&["--thread", "Rc1/2"]));
    assert_eq!(code, 0, "{out}");
    assert!(!out.contains("E016") && !out.contains("W00"), "{out}");
    assert!(
        out.contains("judged against Rc1/2 at its gauge plane Z-0.9071 (0.9071 from the face at Z0, assumed): pitch diameter 19.7368 (basic 19.793), the gauge -0.50 turns (-0.8994 mm) from its basic position (±1.27 allowed), taper 0.06250 on diameter"),
        "{out}"
    );
    let (code, out) = check(
        "rc-large",
        &rc("20.005"),
        &args(&[
            "--thread",
            "Rc1/2",
            "--nose-radius",
            "0.249",
            "--stock-start",
            "0",
        ]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("error[E016]: pitch diameter 20.0366 mm at the gauge plane is above the maximum 19.9367 for Rc1/2: the gauge would stand +2.15 turns from its basic position (±1.27 allowed)"),
        "{out}"
    );
    // Without the tool's tip, the same finding is a warning naming the tip assumed.
    let (code, out) = check(
        "rc-large-tip",
        &rc("20.005"),
        &args(&["--thread", "Rc1/2", "--stock-start", "0"]),
    );
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("warning[W009]: pitch diameter 20.0368 mm at the gauge plane")
            && out.contains("the tool's tip of the standard's root form"),
        "{out}"
    );
    // R names the external taper: the program cuts an internal one.
    let (code, out) = check("rc-as-r", &rc("19.705"), &args(&["--thread", "R1/2"]));
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("is a class of external threads"), "{out}");
}

/// `check --thread NAME --wire D`: the note's M is over the wire one owns (tests/wires.rs
/// `a_wire_of_ones_own`: M12x1.75-6g cut to X9.853, E = 10.863363, over 1.000 mm wires M =
/// 12.3498, the 6g window 12.1655–12.3154); `--wire` needs `--thread`, and a wire is positive.
#[test]
fn check_takes_the_wire_one_owns() {
    let src = "G97 S800 M03\nG00 X14. Z5.\nG76 P010060 Q50 R0.02\nG76 X9.853 Z-20. P1074 Q300 F1.75\nM30\n";
    let (code, out) = check(
        "wire-own",
        src,
        &args(&["--thread", "M12x1.75-6g", "--wire", "1"]),
    );
    // The program stops 0.017 short of 6g's largest minor diameter (E016): the note still says
    // what it measures.
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("over 1 wires this program gives M = 12.3498 mm, 6g allows 12.1655–12.3154"),
        "{out}"
    );
    let (code, out) = check("wire-alone", src, &args(&["--wire", "1"]));
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("--thread"), "{out}");
    let (code, out) = check(
        "wire-zero",
        src,
        &args(&["--thread", "M12x1.75-6g", "--wire", "0"]),
    );
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains("a measuring wire's diameter is a positive length"),
        "{out}"
    );
}

fn passes(name: &str, src: &str, args: &[&str]) -> (i32, String) {
    threadcut("passes", &format!("passes-{name}.nc"), src, args)
}

/// `passes` states what a thread will measure when the tool's form is known. The bundled Fanuc
/// G76 M30x2 (examples/fanuc-m30x2-g76.nc: crest Ø30, 60° tool, final depth 1.227, so the root is
/// at Ø27.546):
/// * with a 0.1 mm nose radius the flanks meet r below the tip, and the groove is a pitch
///   (1 mm) wide where it is 1/(2·tan 30°) = 0.866025 above that point: 0.766025 above the root,
///   PD = 27.546 + 2·0.766025 = 29.07805; over the best wire P/(2·cos 30°) = 1.1547, by the simple
///   formula M = E − P·cot 30°/2 + w·(1 + 1/sin 30°) = 29.07805 − 1.73205 + 3.46410 = 30.8101;
/// * with `--thread M30x2-6g` and no tip, the standard's root radius H/6 = 0.2887 is assumed:
///   0.866025 − 0.2887 above the root, PD = 27.546 + 2·0.57735 = 28.7007, M = 30.4332 (as `check
///   --thread` states it), and 6g's window 28.493–28.663 puts the middle 28.578 at
///   (28.7007 − 28.578)/2 = 0.0614 deeper.
#[test]
fn passes_states_what_the_thread_will_measure() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/fanuc-m30x2-g76.nc"
    ))
    .unwrap();
    let (code, out) = passes("nose", &src, &["-c", "fanuc", "--nose-radius", "0.1"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("measure: pitch diameter 29.0781 mm as cut; over 1.1547 mm wires (the best wire) M = 30.8105 mm (with the lead angle, NBS H28; 30.8101 by the simple formula)"), "{out}");
    let (code, out) = passes("class", &src, &["-c", "fanuc", "--thread", "M30x2-6g"]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("pitch diameter 28.7007 mm as cut"), "{out}");
    assert!(out.contains("M = 30.4332 mm"), "{out}");
    assert!(out.contains("6g allows a pitch diameter of 28.493–28.663 mm (M 30.2255–30.3955 mm): cutting 0.0614 mm deeper (on the radius) brings it to the window's middle"), "{out}");
    assert!(out.contains("assumed: the standard's root form"), "{out}");
    // The same as JSON, in the program's units.
    let (code, out) = passes(
        "json",
        &src,
        &[
            "-c", "fanuc", "--thread", "M30x2-6g", "--wire", "1.15", "--json",
        ],
    );
    assert_eq!(code, 0, "{out}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let m = &v["cycles"][0]["measure"];
    assert!(
        (m["pitch_diameter"].as_f64().unwrap() - 28.7007).abs() < 1e-4,
        "{m}"
    );
    assert!((m["wire"].as_f64().unwrap() - 1.15).abs() < 1e-12, "{m}");
    assert_eq!(m["best_wire"], false);
    assert_eq!(m["class"], "6g");
    assert!((m["deeper"].as_f64().unwrap() - 0.0614).abs() < 1e-4, "{m}");
    // Without the tool's form nothing is stated; a wire alone is refused.
    let (_, out) = passes("none", &src, &["-c", "fanuc"]);
    assert!(!out.contains("measure:"), "{out}");
    let (code, out) = passes("wire-alone", &src, &["-c", "fanuc", "--wire", "1"]);
    assert_eq!(code, 2, "{out}");
    assert!(out.contains("needs the tool's form"), "{out}");
}

/// A program of plain G32 passes does not say where its crest is (its depths run from the first
/// pass): `passes` says why it cannot state a measurement.
#[test]
fn passes_says_why_a_measurement_is_not_stated() {
    let src = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/fanuc-m20-g32-passes.nc"
    ))
    .unwrap();
    let (code, out) = passes("g32-tip", &src, &["-c", "fanuc", "--nose-radius", "0.1"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.contains("measure: not stated: the crest is not known, so neither is the depth the pitch diameter lies at"),
        "{out}"
    );
}
