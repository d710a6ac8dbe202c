//! `threadcut check` on whole programs: every bundled example and every real-style program in
//! `tests/data/real/` checks without an error; the expansion of a cycle into plain moves (what
//! `threadcut expand` writes) checks exactly like the cycle; threads written as plain moves get
//! their pass table.

use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// The controller a file is written for: the built-in profile whose name is the longest prefix of
/// the file's name (`fanuc15-…` is fanuc15's, `fanuc-b-…` fanuc-b's, `fanuc-…` fanuc's; `gsk-…`
/// is gsk980's); APT needs none.
fn controller(path: &Path) -> Option<&'static str> {
    let name = path.file_name().unwrap().to_str().unwrap();
    if name.ends_with(".apt") {
        return None;
    }
    Some(
        [
            ("ab9", "ab9"),
            ("fanuc", "fanuc"),
            ("fanuc15", "fanuc15"),
            ("fanuc-b", "fanuc-b"),
            ("gsk", "gsk980"),
            ("gsk980", "gsk980"),
            ("haas", "haas"),
            ("linuxcnc", "linuxcnc"),
            ("omniturn", "omniturn"),
            ("sinumerik", "sinumerik"),
        ]
        .iter()
        .filter(|(prefix, _)| {
            name.strip_prefix(prefix)
                .is_some_and(|rest| rest.starts_with('-'))
        })
        .max_by_key(|(prefix, _)| prefix.len())
        .unwrap_or_else(|| panic!("no controller for {name}"))
        .1,
    )
}

fn run(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

fn check(path: &Path, extra: &[&str]) -> (i32, String) {
    let mut args = vec!["check", path.to_str().unwrap()];
    if let Some(c) = controller(path) {
        args.extend(["-c", c]);
    }
    args.extend_from_slice(extra);
    let (code, out, _) = run(&args);
    (code, out)
}

/// The programs of a directory that `check` reads.
fn programs(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            matches!(
                p.extension().and_then(|e| e.to_str()),
                Some("nc" | "ngc" | "mpf" | "apt")
            )
        })
        .collect();
    files.sort();
    files
}

#[test]
fn every_bundled_example_checks_without_an_error() {
    let files = programs(&root().join("examples"));
    assert!(files.len() >= 25, "{files:?}");
    // Every lathe controller has an example, checked as its own.
    let controllers: std::collections::BTreeSet<&str> =
        files.iter().filter_map(|f| controller(f)).collect();
    for c in [
        "ab9",
        "fanuc",
        "fanuc15",
        "fanuc-b",
        "gsk980",
        "haas",
        "linuxcnc",
        "omniturn",
        "sinumerik",
    ] {
        assert!(
            controllers.contains(c),
            "no example for {c}: {controllers:?}"
        );
    }
    for f in files {
        let (code, out) = check(&f, &[]);
        assert_eq!(code, 0, "{}: {out}", f.display());
        assert!(!out.contains("error["), "{}: {out}", f.display());
        assert!(out.contains(" 0 errors,"), "{}: {out}", f.display());
    }
}

/// Real-style programs, written for these tests after how shops write them: hand-written G32
/// passes (radial, and flank infeed with backed-off starts), a modal G92 after G71/G70 roughing,
/// internal and inch G76 cycles, two threads with a tool change, a tapered pipe thread in G32,
/// GSK's G92 with threads per inch and its G76, LinuxCNC's G33 passes and an internal G76, APT
/// COUPLE passes, Haas's one-block G76 among its own codes (G154, G187, M23), FS15's G92 with an I
/// taper, G-code system B's G33 passes under G90/G91, a Sinumerik 840D internal CYCLE97 among
/// G54/G500/G641 ADIS=/G710/LIMS=; a Fanuc program between two `G28 U0. W0.`, Haas's `G28` and `G54` before
/// its G76, LinuxCNC named parameters in the G76 words, GSK blocks ended by `;`, Sinumerik's
/// `G96 S… LIMS=… M3` on one block; Fanuc G71/G70 then G76, GSK G71 (F on its first block)/G70 then
/// G92 passes. None may give an error; each is read as the threads it cuts.
#[test]
fn real_style_programs_have_no_false_error() {
    let files = programs(&root().join("tests/data/real"));
    assert!(files.len() >= 21, "{files:?}");
    for f in &files {
        let (code, out) = check(f, &[]);
        assert_eq!(code, 0, "{}: {out}", f.display());
        assert!(!out.contains("error["), "{}: {out}", f.display());
        let threads = if f.ends_with("fanuc-two-threads-chamfer.nc") {
            "in 2 threads"
        } else {
            "in 1 thread"
        };
        assert!(out.contains(threads), "{}: {out}", f.display());
    }
}

/// The findings (errors and warnings: level, code, message, hint) of `check --format json`.
fn findings(path: &Path, extra: &[&str]) -> Vec<(String, String, String, String)> {
    let mut args = vec!["--format", "json"];
    args.extend_from_slice(extra);
    let (_, out) = check(path, &args);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("{e}: {out}"));
    v.as_array()
        .unwrap()
        .iter()
        .filter(|f| f["level"] != "note")
        .map(|f| {
            let s = |k: &str| f[k].as_str().unwrap_or("").to_string();
            (s("level"), s("code"), s("message"), s("hint"))
        })
        .collect()
}

/// The findings in an order that does not depend on the lines they are at (a cycle's are all at
/// its block, its expansion's at the pass each concerns).
fn sorted(mut f: Vec<(String, String, String, String)>) -> Vec<(String, String, String, String)> {
    f.sort();
    f
}

/// `threadcut expand` of `path` (a cycle as plain G32/G33 moves, or as the controller's own
/// single passes) into a file beside the test's output.
fn expanded(path: &Path, name: &str) -> PathBuf {
    let out = tmp(name);
    let (code, _, err) = run(&[
        "expand",
        path.to_str().unwrap(),
        "-c",
        controller(path).unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    out
}

/// The G32 version of a G76 example (what `threadcut expand` writes) gives the same findings as
/// the G76, with the same options: here a run-up too short for 2000 rpm (W003) and a one-lead
/// chamfer shorter than δ2 (W007); with a blank given, the same collisions; with `--thread`, the
/// same judgement of the thread.
#[test]
fn the_g32_version_of_a_g76_checks_like_the_g76() {
    let g76 = tmp("fanuc-twin-g76.nc");
    let src = std::fs::read_to_string(root().join("examples/fanuc-m30x2-g76.nc"))
        .unwrap()
        .replace("S600", "S2000")
        .replace("P020060", "P021060")
        .replace("G0 X32. Z5.", "G0 X32. Z3.");
    std::fs::write(&g76, src).unwrap();
    let g32 = expanded(&g76, "fanuc-twin-g32.nc");
    let text = std::fs::read_to_string(&g32).unwrap();
    assert_eq!(text.matches("G32").count(), 20, "{text}");
    assert!(!text.contains("G76 X"), "{text}");
    for extra in [
        &[][..],
        &["--stock-start", "0", "--stock-diameter", "30"][..],
        &["--stock-start", "3"][..],
        &["--thread", "M30x2-6g"][..],
        &["--thread", "M30x2-6g", "--nose-radius", "0.25"][..],
    ] {
        let (a, b) = (sorted(findings(&g76, extra)), sorted(findings(&g32, extra)));
        assert_eq!(a, b, "{extra:?}");
        assert!(!a.is_empty(), "{extra:?}: a case with findings");
    }
    let codes: Vec<String> = findings(&g76, &[]).into_iter().map(|f| f.1).collect();
    assert_eq!(codes, ["W003", "W007"]);
    let codes: Vec<String> = findings(&g76, &["--thread", "M30x2-6g"])
        .into_iter()
        .map(|f| f.1)
        .collect();
    assert!(codes.contains(&"E016".to_string()), "{codes:?}");
}

/// The same for every bundled cycle that `expand` writes as plain moves or single passes: GSK's
/// G78, Fanuc's G92, LinuxCNC's G76 (external with an exit taper, internal with entry and exit
/// ramps), Allen-Bradley's G78, OmniTurn's G33 (written back as single `O` passes), FS15's and
/// Haas's one-block G76 (two starts by Q), system B's G78, Sinumerik's CYCLE97 (two starts by SF=).
#[test]
fn every_expanded_example_checks_like_its_cycles() {
    for name in [
        "gsk-g78.nc",
        "fanuc-g92-passes.nc",
        "linuxcnc-m20-exit-taper.ngc",
        "linuxcnc-internal-entry-taper.ngc",
        "ab9-metric-p1.nc",
        "ab9-inch-p3-e.nc",
        "omniturn-external.nc",
        "omniturn-internal.nc",
        "omniturn-taper.nc",
        "fanuc15-m30x2-g76.nc",
        "fanuc-b-m20x1.5-g78.nc",
        "haas-3-4-10-p2.nc",
        "haas-m24x3-two-start.nc",
        "sinumerik-m24x1.5-cycle97.mpf",
        "sinumerik-internal-two-start.mpf",
    ] {
        let path = root().join("examples").join(name);
        let ext = path.extension().unwrap().to_str().unwrap();
        let twin = expanded(&path, &format!("{name}.twin.{ext}"));
        for extra in [&[][..], &["--stock-start", "0"][..]] {
            assert_eq!(
                sorted(findings(&path, extra)),
                sorted(findings(&twin, extra)),
                "{name} {extra:?}"
            );
        }
        let (_, a) = check(&path, &[]);
        let (_, b) = check(&twin, &[]);
        let count = |s: &str| {
            s.lines()
                .last()
                .unwrap()
                .split(" in ")
                .nth(1)
                .unwrap()
                .to_string()
        };
        // A cycle that cuts its starts one after another by the spindle angle (CYCLE97 NUMT=2) is
        // one thread; its expansion writes each start's passes at their own SF=, one thread per
        // start, as two G76 cycles with Q0 and Q180000 are two threads.
        let threads = if name == "sinumerik-internal-two-start.mpf" {
            "2 threads".to_string()
        } else {
            count(&a)
        };
        assert_eq!(threads, count(&b), "{name}");
    }
}

/// Hand-written G32 passes are one thread: `passes` prints its table with depths measured from
/// the first pass (the crest is not known), the Z of each backed-off start, and which passes
/// finish it.
#[test]
fn hand_written_passes_get_a_pass_table() {
    let f = root().join("tests/data/real/fanuc-g32-flank-m24x3.nc");
    let (code, out, _) = run(&["passes", f.to_str().unwrap(), "-c", "fanuc"]);
    assert_eq!(code, 0, "{out}");
    assert!(
        out.starts_with("line 9: 10 synchronised passes as one thread (lines 9–47), 9 rough passes and 1 finishing pass (mm); depths from the first pass: the crest is not known"),
        "{out}"
    );
    // Pass 2 at X22.7: (23.3 − 22.7)/2 = 0.3 below pass 1, its start 0.169 further back.
    assert!(
        out.contains("   2  rough      0.3000     0.3000     22.7000      6.3670"),
        "{out}"
    );
    // Pass 10 is the deepest, (23.3 − 20.32)/2 = 1.49 below pass 1: it finishes the thread.
    assert!(
        out.contains("  10  finish     1.4900     0.0900     20.3200      6.9330"),
        "{out}"
    );
    // JSON says where the depths are measured from.
    let (_, out, _) = run(&["passes", f.to_str().unwrap(), "-c", "fanuc", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["cycles"][0]["source"], "moves");
    assert_eq!(v["cycles"][0]["depth_from"], "first_pass");
    assert_eq!(v["cycles"][0]["passes"].as_array().unwrap().len(), 10);
    // A cycle's table says it is measured from the crest.
    let f = root().join("examples/fanuc-m30x2-g76.nc");
    let (_, out, _) = run(&["passes", f.to_str().unwrap(), "-c", "fanuc", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["cycles"][0]["source"], "cycle");
    assert_eq!(v["cycles"][0]["depth_from"], "crest");
}

/// `plot` draws threads written as plain moves.
#[test]
fn hand_written_passes_are_plotted() {
    let f = root().join("tests/data/real/fanuc-g32-radial-m20.nc");
    let svg = tmp("real-g32.svg");
    let (code, _, err) = run(&[
        "plot",
        f.to_str().unwrap(),
        "-c",
        "fanuc",
        "-o",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(
        text.contains("line 9: 11 synchronised passes as one thread (lines 9–"),
        "{}",
        &text[..600]
    );
}

/// A spring pass written as a G32 after a G76 continues the G76's thread.
#[test]
fn a_spring_pass_after_a_cycle_joins_its_thread() {
    let src = "G21 G99\nG97 S500 M3\nG0 X32. Z5.\nG76 P010060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\nG0 X27.546 Z5.\nG32 Z-30. F2.\nG0 X32.\nZ5.\nM30\n";
    let f = tmp("fanuc-spring.nc");
    std::fs::write(&f, src).unwrap();
    let (_, out, _) = run(&["passes", f.to_str().unwrap(), "-c", "fanuc"]);
    assert!(
        out.starts_with(
            "line 5: fanuc cycle and 1 more pass after it, 8 rough passes and 2 finishing passes (mm)"
        ),
        "{out}"
    );
    assert!(
        out.contains("  10  finish     1.2270     0.0000     27.5460      5.0000"),
        "{out}"
    );
    let (code, out) = check(&f, &[]);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("in 1 thread"), "{out}");
}
