//! Programs with control flow through the `threadcut` command: what each command does with them,
//! `--flatten`, `--max-blocks`, standard input, and the errors (exit status 2, file:line:column).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn threadcut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .expect("run threadcut")
}

fn example(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("threadcut-interp-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn stdout(out: &Output) -> String {
    assert!(
        out.status.success(),
        "exit {:?}: {}",
        out.status.code(),
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone()).unwrap()
}

/// The motions of `expand --format jsonl`, without their source lines.
fn motions(jsonl: &str) -> Vec<String> {
    jsonl
        .lines()
        .map(|l| {
            let mut v: serde_json::Value = serde_json::from_str(l).unwrap();
            // Source lines differ, and an expanded cycle's moves are plain moves (pass 0).
            v.as_object_mut().unwrap().remove("line");
            v.as_object_mut().unwrap().remove("pass");
            v.to_string()
        })
        .collect()
}

#[test]
fn flatten_writes_straight_line_code_that_moves_the_same() {
    let file = example("fanuc-macro-g92-passes.nc");
    let flat = stdout(&threadcut(&["expand", &file, "-c", "fanuc", "--flatten"]));
    assert!(!flat.contains('#') && !flat.contains("WHILE"), "{flat}");
    // Six G92 passes, each expanded where the loop ran it.
    assert_eq!(flat.matches("threadcut: fanuc cycle of line 15").count(), 6);
    let dir = temp_dir("flatten");
    let written = write(&dir, "flat.nc", &flat);
    let original = stdout(&threadcut(&[
        "expand", &file, "-c", "fanuc", "--format", "jsonl",
    ]));
    let back = stdout(&threadcut(&[
        "expand",
        written.to_str().unwrap(),
        "-c",
        "fanuc",
        "--format",
        "jsonl",
    ]));
    assert_eq!(motions(&original), motions(&back));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn expand_names_a_cycle_whose_runs_differ() {
    let file = example("linuxcnc-sub-two-threads.ngc");
    let out = threadcut(&["expand", &file, "-c", "linuxcnc"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("linuxcnc-sub-two-threads.ngc:7:1"), "{err}");
    assert!(err.contains("called at line 9"), "{err}");
    assert!(err.contains("called at line 10"), "{err}");
    assert!(err.contains("--flatten"), "{err}");
    // The Fanuc subprogram runs twice from the same start: replaced in place, the text kept.
    let text = stdout(&threadcut(&[
        "expand",
        &example("fanuc-m98-subprogram.nc"),
        "-c",
        "fanuc",
    ]));
    assert!(
        text.contains("M98 P1000\nG0 X100. Z100.\nM00 (NEXT PART)\nM98 P1000\n"),
        "{text}"
    );
    assert!(text.contains("O1000 (M30X2 EXTERNAL, G76)\nG0 X32. Z5.\n(threadcut: line 15 sets the cycle that follows)\n(threadcut: fanuc cycle of line 16"), "{text}");
    assert!(text.ends_with("M99\n%\n"), "{text}");
}

#[test]
fn passes_check_and_plot_report_the_execution() {
    let file = example("linuxcnc-sub-two-threads.ngc");
    let table = stdout(&threadcut(&["passes", &file, "-c", "linuxcnc"]));
    assert_eq!(
        table.matches("line 7: linuxcnc cycle").count(),
        2,
        "{table}"
    );
    let check = stdout(&threadcut(&["check", &file, "-c", "linuxcnc"]));
    assert!(check.contains("in 2 threads"), "{check}");
    let dir = temp_dir("plot");
    let svg = dir.join("out.svg");
    stdout(&threadcut(&[
        "plot",
        &file,
        "-c",
        "linuxcnc",
        "-o",
        svg.to_str().unwrap(),
    ]));
    assert!(std::fs::read_to_string(&svg).unwrap().starts_with("<svg"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn max_blocks_stops_an_endless_loop() {
    let dir = temp_dir("endless");
    let file = write(
        &dir,
        "loop.nc",
        "G21\nG0 X10. Z2.\n#1=0\nWHILE[#1GE0]DO1\n#1=#1+1\nEND1\nM30\n",
    );
    let t = std::time::Instant::now();
    for command in ["expand", "passes", "check"] {
        let out = threadcut(&[
            command,
            file.to_str().unwrap(),
            "-c",
            "fanuc",
            "--max-blocks",
            "5000",
        ]);
        assert_eq!(out.status.code(), Some(2), "{command}");
        let text = String::from_utf8_lossy(&out.stderr).to_string()
            + &String::from_utf8_lossy(&out.stdout);
        assert!(text.contains("loop.nc:4:1"), "{command}: {text}");
        assert!(
            text.contains("ran past 5000 executed blocks"),
            "{command}: {text}"
        );
    }
    // With the default limit too, within seconds.
    let out = threadcut(&[
        "expand",
        file.to_str().unwrap(),
        "-c",
        "fanuc",
        "--format",
        "jsonl",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("1000000 executed blocks"));
    assert!(t.elapsed().as_secs() < 20, "{:?}", t.elapsed());
    let out = threadcut(&[
        "expand",
        file.to_str().unwrap(),
        "-c",
        "fanuc",
        "--max-blocks",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn standard_input_is_interpreted_too() {
    let program = std::fs::read(example("fanuc-macro-g92-passes.nc")).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["expand", "-", "-c", "fanuc", "--format", "jsonl"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(&program).unwrap();
    let out = child.wait_with_output().unwrap();
    let from_stdin = stdout(&out);
    let from_file = stdout(&threadcut(&[
        "expand",
        &example("fanuc-macro-g92-passes.nc"),
        "-c",
        "fanuc",
        "--format",
        "jsonl",
    ]));
    assert_eq!(from_stdin, from_file);
    assert!(from_file.lines().count() > 6);
}

#[test]
fn convert_keeps_or_flattens() {
    let dir = temp_dir("convert");
    let program = write(
        &dir,
        "p.nc",
        "G21 G99\nG0 X26. Z5.\n#5=1\nWHILE[#5LE3]DO1\nG92 X[24.-#5*0.3] Z-20. F1.5\n#5=#5+1\nEND1\nM30\n",
    );
    let program = program.to_str().unwrap();
    // LinuxCNC's o-words: the loop is kept, its G92 passes as LinuxCNC's moves with the
    // diameter's expression halved (LinuxCNC's X is the radius).
    let kept = stdout(&threadcut(&[
        "convert", program, "--from", "fanuc", "--to", "linuxcnc",
    ]));
    assert!(kept.contains("o101 while [#5 LE 3]"), "{kept}");
    assert!(kept.contains("G0 X[[24-#5*0.3]/2] Z5."), "{kept}");
    // A controller without macros: the control flow cannot be kept.
    let out = threadcut(&["convert", program, "--from", "fanuc", "--to", "ab9"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("control flow from line 3"), "{err}");
    assert!(err.contains("--flatten"), "{err}");
    let text = stdout(&threadcut(&[
        "convert",
        program,
        "--from",
        "fanuc",
        "--to",
        "linuxcnc",
        "--flatten",
    ]));
    assert!(!text.contains('#') && !text.contains("WHILE"), "{text}");
    assert!(text.matches("G33 ").count() >= 3, "{text}");
    std::fs::remove_dir_all(&dir).ok();
    let file = example("fanuc-macro-g92-passes.nc");
    // Flattened, it converts: six G92 passes for GSK, no macro left.
    let text = stdout(&threadcut(&[
        "convert",
        &file,
        "--from",
        "fanuc",
        "--to",
        "gsk980",
        "--flatten",
    ]));
    assert!(!text.contains('#') && !text.contains("WHILE"), "{text}");
    assert_eq!(text.matches("G92 X").count(), 6, "{text}");
    // The same controller: the text as it is.
    let same = stdout(&threadcut(&[
        "convert", &file, "--from", "fanuc", "--to", "fanuc",
    ]));
    assert_eq!(
        same.replace("(threadcut convert: fanuc to fanuc)\n", ""),
        std::fs::read_to_string(&file).unwrap()
    );
}

#[test]
fn lines_after_the_program_end_are_copied_not_run() {
    let dir = temp_dir("after-end");
    let src = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\nM30\n%\nG78 X1 (never run, even though it is no valid block)\n";
    let file = write(&dir, "p.nc", src);
    let text = stdout(&threadcut(&[
        "expand",
        file.to_str().unwrap(),
        "-c",
        "gsk980",
    ]));
    assert!(
        text.ends_with("M30\n%\nG78 X1 (never run, even though it is no valid block)\n"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn macro_errors_point_at_the_source() {
    let dir = temp_dir("errors");
    for (controller, src, at, says) in [
        (
            "linuxcnc",
            "G8\nG0 X0 Z0\n#1 = 0\nG0 X[5 / #1]\nM2\n",
            "4:8",
            "Attempt to divide by zero",
        ),
        (
            "linuxcnc",
            "G8\nG0 X0 Z0\no200 call\nM2\n",
            "3:1",
            "EOF seeking o-word: o<200>",
        ),
        (
            "fanuc",
            "G21\nG0 X1. Z1.\nM98 P4321\nM30\n",
            "3:5",
            "O4321 is not in the file",
        ),
        (
            "fanuc",
            "G21\nG0 X1. Z1.\nWHILE[#1LT2]DO1\nM30\n",
            "3:1",
            "DO1 has no END1",
        ),
        (
            "gsk980",
            "G0 X1 Z1\nG65 H02 P#1 Q[1/0] R2\nM30\n",
            "2:",
            "division by zero",
        ),
    ] {
        let file = write(&dir, "bad.nc", src);
        let out = threadcut(&["expand", file.to_str().unwrap(), "-c", controller]);
        assert_eq!(out.status.code(), Some(2), "{src}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("bad.nc:{at}")), "{err}");
        assert!(err.contains(says), "{err}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

fn multifile(path: &str) -> String {
    format!(
        "{}/../tests/data/multifile/{path}",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn include_finds_a_called_program_and_an_error_in_it_shows_its_file() {
    // O9010 from the include directory: three thread passes (docs/cli.md, `--include`).
    let out = threadcut(&[
        "expand",
        "-c",
        "fanuc",
        "--format",
        "jsonl",
        "--include",
        &multifile("fanuc/lib"),
        &multifile("fanuc/main-m98.nc"),
    ]);
    assert_eq!(stdout(&out).matches("\"thread\"").count(), 3);
    // An error on line 3 of O9030.nc: its text under its name, then the call.
    let out = threadcut(&[
        "expand",
        "-c",
        "fanuc",
        "--include",
        &multifile("errors/lib"),
        &multifile("errors/bad-inside.nc"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("errors/lib/O9030.nc:3:12"), "{err}");
    assert!(err.contains("3 | G32 Z[-20.*] F2."), "{err}");
    assert!(
        err.contains("note: called from line 5 of ") && err.contains("errors/bad-inside.nc"),
        "{err}"
    );
    // Not found: every path tried.
    let out = threadcut(&[
        "expand",
        "-c",
        "fanuc",
        "--include",
        &multifile("errors/lib"),
        &multifile("errors/missing.nc"),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("missing.nc:4:5"), "{err}");
    assert!(err.contains("errors/lib/O9020.nc"), "{err}");
}

#[test]
fn a_profile_names_include_directories_relative_to_itself() {
    // `include = ["lib"]` in a profile beside a copy of O9010.nc's directory.
    let dir = temp_dir("profile-include");
    std::fs::create_dir_all(dir.join("lib")).unwrap();
    std::fs::copy(multifile("fanuc/lib/O9010.nc"), dir.join("lib/O9010.nc")).unwrap();
    let fanuc = std::fs::read_to_string(format!(
        "{}/../profiles/fanuc.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap();
    let profile = write(&dir, "shop.toml", &format!("include = [\"lib\"]\n{fanuc}"));
    let out = threadcut(&[
        "expand",
        "--machine",
        profile.to_str().unwrap(),
        "--format",
        "jsonl",
        &multifile("fanuc/main-m98.nc"),
    ]);
    assert_eq!(stdout(&out).matches("\"thread\"").count(), 3);
    // Without it, the call is not found.
    let plain = write(&dir, "plain.toml", &fanuc);
    let out = threadcut(&[
        "expand",
        "--machine",
        plain.to_str().unwrap(),
        &multifile("fanuc/main-m98.nc"),
    ]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn call_runs_a_subroutine_file_and_without_it_the_file_says_so() {
    let file = multifile("call/threading.ngc");
    let out = threadcut(&[
        "passes",
        "-c",
        "linuxcnc",
        "--call",
        "o<threading> call [20] [2.5] [-25] [1.5] [3]",
        &file,
    ]);
    // Three passes of lead 2.5 to depth 1.5 (docs/cli.md, `--call`).
    assert!(stdout(&out).contains("3 synchronised passes"));
    let out = threadcut(&["passes", "-c", "linuxcnc", &file]);
    assert_eq!(out.status.code(), Some(0));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("defines subroutines (o<threading>) and calls none of them"),
        "{err}"
    );
    assert!(err.contains("--call 'o<threading> call"), "{err}");
    assert!(!err.contains("no thread found"), "{err}");
}

/// `check`'s own findings about a thread in a called file (issue 25, item 5): the thread O9010
/// cuts (three G32 passes to X18.7 from the crest Ø20: 0.65 deep) is judged against M20x2-6g,
/// whose minor diameter is at most 17.508; the error is at line 4 of O9010.nc, called from line 8
/// of main-m98.nc, in the text, and in JSON with `called_from`. The notes name the called file.
#[test]
fn checks_findings_in_a_called_file_name_the_call() {
    let args = |format: &str| {
        threadcut(&[
            "check",
            "-c",
            "fanuc",
            "--thread",
            "M20x2-6g",
            "--format",
            format,
            "--include",
            &multifile("fanuc/lib"),
            &multifile("fanuc/main-m98.nc"),
        ])
    };
    // Exit status 2: the check found an error.
    let out = args("text");
    assert_eq!(out.status.code(), Some(2));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("fanuc/lib/O9010.nc:4:1"), "{text}");
    assert!(text.contains("minor diameter 18.7 > 17.508 max"), "{text}");
    assert!(
        text.contains("note: called from line 8 of ") && text.contains("main-m98.nc"),
        "{text}"
    );
    assert!(
        text.contains("note: ") && text.contains("O9010.nc:4: judged against M20x2-6g"),
        "{text}"
    );
    let json: serde_json::Value = serde_json::from_slice(&args("json").stdout).unwrap();
    let e016 = json
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["code"] == "E016")
        .unwrap();
    assert!(
        e016["file"]
            .as_str()
            .unwrap()
            .ends_with("fanuc/lib/O9010.nc"),
        "{e016}"
    );
    assert_eq!(e016["line"], 4);
    let from = &e016["called_from"][0];
    assert!(
        from["file"]
            .as_str()
            .unwrap()
            .ends_with("fanuc/main-m98.nc"),
        "{e016}"
    );
    assert_eq!(from["line"], 8);
    // `passes` names the file its thread lies in.
    let out = threadcut(&[
        "passes",
        "-c",
        "fanuc",
        "--include",
        &multifile("fanuc/lib"),
        &multifile("fanuc/main-m98.nc"),
    ]);
    let text = stdout(&out);
    assert!(
        text.starts_with("line 4 of ") && text.contains("fanuc/lib/O9010.nc: "),
        "{text}"
    );
}
