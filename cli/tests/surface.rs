//! One command-line surface (issue 17): formats, outputs, profiles, messages, line endings, big
//! inputs. Every test runs the real binary, as a user would.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn threadcut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .expect("run threadcut")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("threadcut-surface-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p.to_str().unwrap().to_string()
}

fn stdout(o: &Output) -> String {
    String::from_utf8(o.stdout.clone()).unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8(o.stderr.clone()).unwrap()
}

const GSK: &str =
    "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\nG0 X80 Z10\n";

/// A GSK program of `n` cycles.
fn cycles(n: usize) -> String {
    let mut s = String::from("G0 X80 Z10\n");
    for _ in 0..n {
        s.push_str("G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n");
    }
    s
}

// ---- formats ---------------------------------------------------------------------------------

#[test]
fn every_data_command_takes_format_and_the_json_flags_stay() {
    let dir = temp_dir("formats");
    let file = write(&dir, "p.nc", &cycles(2));
    // passes: --json is --format json; jsonl is one cycle object per line.
    let json = threadcut(&["passes", &file, "-c", "gsk980", "--json"]);
    let format_json = threadcut(&["passes", &file, "-c", "gsk980", "--format", "json"]);
    assert!(json.status.success(), "{}", stderr(&json));
    assert_eq!(json.stdout, format_json.stdout);
    let all: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let jsonl = threadcut(&["passes", &file, "-c", "gsk980", "--format", "jsonl"]);
    assert!(jsonl.status.success(), "{}", stderr(&jsonl));
    let lines: Vec<serde_json::Value> = stdout(&jsonl)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 2);
    assert_eq!(&lines[..], all["cycles"].as_array().unwrap().as_slice());
    assert_eq!(lines[0]["line"], 4);
    // expand keeps --format jsonl; post takes it too (APT).
    let out = threadcut(&["expand", &file, "-c", "gsk980", "--format", "jsonl"]);
    assert!(out.status.success());
    let first: serde_json::Value =
        serde_json::from_str(stdout(&out).lines().next().unwrap()).unwrap();
    assert_eq!(first["kind"], "rapid");
    let apt = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/m20-external.apt");
    let post = threadcut(&["post", apt, "--format", "jsonl"]);
    let expand = threadcut(&["expand", apt, "--format", "jsonl"]);
    assert!(post.status.success(), "{}", stderr(&post));
    assert_eq!(post.stdout, expand.stdout);
    // check: text, json, jsonl (one finding per line).
    let check = threadcut(&["check", &file, "-c", "gsk980", "--format", "jsonl"]);
    let findings: Vec<serde_json::Value> = stdout(&check)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let whole = threadcut(&["check", &file, "-c", "gsk980", "--format", "json"]);
    let whole: serde_json::Value = serde_json::from_slice(&whole.stdout).unwrap();
    assert!(!findings.is_empty());
    assert_eq!(&findings[..], whole.as_array().unwrap().as_slice());
    // thread: --json is --format json.
    let a = threadcut(&["thread", "M10", "--json"]);
    let b = threadcut(&["thread", "M10", "--format", "json"]);
    assert!(a.status.success());
    assert_eq!(a.stdout, b.stdout);
    // controllers: text and json, lathe and milling profiles apart.
    let c = threadcut(&["controllers", "--format", "json"]);
    let list: serde_json::Value = serde_json::from_slice(&c.stdout).unwrap();
    let kind = |name: &str| {
        list.as_array()
            .unwrap()
            .iter()
            .find(|v| v["name"] == name)
            .map(|v| v["kind"].as_str().unwrap().to_string())
    };
    assert_eq!(kind("gsk980").as_deref(), Some("lathe"));
    assert_eq!(kind("centroid").as_deref(), Some("mill"));
    // plot: svg; convert: gcode.
    assert!(
        threadcut(&["plot", &file, "-c", "gsk980", "--format", "svg"])
            .status
            .success()
    );
    assert!(threadcut(&[
        "convert", &file, "--from", "gsk980", "--to", "fanuc", "--format", "gcode"
    ])
    .status
    .success());
}

#[test]
fn plot_writes_to_standard_output_and_every_command_takes_o() {
    let dir = temp_dir("stdout");
    let file = write(&dir, "p.nc", GSK);
    let out = threadcut(&["plot", &file, "-c", "gsk980"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stdout(&out).starts_with("<svg "), "{}", stdout(&out));
    // -o on the commands that used to print only to standard output: the same bytes in a file.
    for args in [
        vec!["check", &file, "-c", "gsk980"],
        vec!["thread", "M10"],
        vec!["controllers"],
        vec!["plot", &file, "-c", "gsk980"],
    ] {
        let to_stdout = threadcut(&args);
        let target = dir.join(format!("{}.out", args[0]));
        let mut with_o = args.clone();
        with_o.extend(["-o", target.to_str().unwrap()]);
        let o = threadcut(&with_o);
        assert_eq!(o.status.code(), to_stdout.status.code(), "{args:?}");
        assert!(o.stdout.is_empty(), "{args:?}");
        assert_eq!(
            std::fs::read(&target).unwrap(),
            to_stdout.stdout,
            "{args:?}"
        );
    }
}

#[test]
fn machine_profiles_wherever_a_controller_is_named() {
    let dir = temp_dir("machine");
    let file = write(&dir, "p.nc", GSK);
    let gsk = write(&dir, "gsk.toml", include_str!("../../profiles/gsk980.toml"));
    let fanuc = write(
        &dir,
        "fanuc.toml",
        include_str!("../../profiles/fanuc.toml"),
    );
    let by_name = threadcut(&["convert", &file, "--from", "gsk980", "--to", "fanuc"]);
    let by_file = threadcut(&[
        "convert",
        &file,
        "--from-machine",
        &gsk,
        "--to-machine",
        &fanuc,
    ]);
    assert!(by_file.status.success(), "{}", stderr(&by_file));
    assert_eq!(by_name.stdout, by_file.stdout);
    // A taper thread's cycle word, from a profile file.
    let ab = write(&dir, "ab9.toml", include_str!("../../profiles/ab9.toml"));
    let a = threadcut(&["thread", "1/2-14 NPT", "-c", "ab9"]);
    let b = threadcut(&["thread", "1/2-14 NPT", "--machine", &ab]);
    assert!(b.status.success(), "{}", stderr(&b));
    assert_eq!(a.stdout, b.stdout);
    // A milling profile file for mill.
    let centroid = write(&dir, "c.toml", include_str!("../../profiles/centroid.toml"));
    let mill = |how: &[&str]| {
        let mut args = vec![
            "mill",
            "--thread",
            "M10x1.5",
            "--internal",
            "--length",
            "10",
            "--tool-diameter",
            "6",
            "--feed",
            "300",
            "--comp",
            "none",
        ];
        args.extend(how);
        threadcut(&args)
    };
    let a = mill(&["-c", "centroid"]);
    let b = mill(&["--machine", &centroid]);
    assert!(b.status.success(), "{}", stderr(&b));
    assert_eq!(a.stdout, b.stdout);
}

#[test]
fn help_describes_file_and_output_everywhere() {
    for cmd in ["expand", "passes", "check", "plot", "post", "convert"] {
        let help = stdout(&threadcut(&[cmd, "--help"]));
        assert!(help.contains("<FILE>"), "{cmd}: {help}");
        assert!(help.contains("standard input"), "{cmd}: {help}");
        assert!(help.contains("-o, --output <OUT>"), "{cmd}: {help}");
        assert!(help.contains("standard output"), "{cmd}: {help}");
        assert!(help.contains("--format <FORMAT>"), "{cmd}: {help}");
    }
    for cmd in ["thread", "controllers", "mill"] {
        let help = stdout(&threadcut(&[cmd, "--help"]));
        assert!(help.contains("-o, --output <OUT>"), "{cmd}: {help}");
        assert!(help.contains("--format <FORMAT>"), "{cmd}: {help}");
    }
    for cmd in [
        "expand", "passes", "check", "plot", "post", "thread", "mill",
    ] {
        let help = stdout(&threadcut(&[cmd, "--help"]));
        assert!(help.contains("--machine <FILE.toml>"), "{cmd}: {help}");
    }
}

// ---- controllers -----------------------------------------------------------------------------

#[test]
fn expand_reads_a_milling_program_on_a_milling_profile() {
    let dir = temp_dir("mill-expand");
    // A quarter circle G3 from (10, 0) about the origin (I-10) dropping 0.5, inch: 25.4 mm.
    let file = write(
        &dir,
        "m.nc",
        "G20 G90 G0 X1. Y0 Z0.1\nG1 Z0 F10.\nG3 X0 Y1. Z-0.02 I-1. J0\nM30\n",
    );
    let out = threadcut(&["expand", &file, "-c", "haas-mill", "--format", "jsonl"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    let arc = text.lines().nth(2).unwrap();
    let v: serde_json::Value = serde_json::from_str(arc).unwrap();
    assert_eq!(v["kind"], "arc");
    assert_eq!(v["line"], 3);
    assert!((v["y"].as_f64().unwrap() - 25.4).abs() < 1e-9);
    assert!((v["z"].as_f64().unwrap() + 0.508).abs() < 1e-9);
    assert_eq!(v["clockwise"], false);
    assert_eq!(v["state"]["feed"]["value"].as_f64().unwrap(), 254.0);
    // As G-code: the moves in mm, in the profile's format, ended by M30.
    let out = threadcut(&["expand", &file, "-c", "haas-mill"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = stdout(&out);
    assert!(text.contains("G3 X0. Y25.4 Z-0.508 I-25.4 J0."), "{text}");
    assert!(text.trim_end().ends_with("M30"), "{text}");
}

#[test]
fn controller_names_ignore_case_and_suggest() {
    let dir = temp_dir("names");
    let file = write(&dir, "p.nc", GSK);
    let upper = threadcut(&["passes", &file, "--controller", "GSK980"]);
    let lower = threadcut(&["passes", &file, "--controller", "gsk980"]);
    assert!(upper.status.success(), "{}", stderr(&upper));
    assert_eq!(upper.stdout, lower.stdout);
    let out = threadcut(&["passes", &file, "--controller", "GSK"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out)
            .starts_with("error: unknown controller `GSK`\n  = help: did you mean `gsk980`?"),
        "{}",
        stderr(&out)
    );
    // A lathe program on a milling profile (which reads a machining centre's program: issue 24),
    // and a lathe controller for mill: said, with the right command.
    let out = threadcut(&["passes", &file, "-c", "centroid"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.starts_with(
            "error[E015]: G78 is not a code threadcut reads in a Centroid milling program"
        ),
        "{err}"
    );
    assert!(
        err.contains("a lathe program is read with a lathe controller (gsk980, "),
        "{err}"
    );
    let out = threadcut(&[
        "mill",
        "--thread",
        "M10",
        "--internal",
        "--length",
        "10",
        "--tool-diameter",
        "6",
        "--feed",
        "300",
        "-c",
        "Fanuc",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.starts_with("error: `Fanuc` is a lathe controller, and `threadcut mill` writes thread-milling programs"),
        "{err}"
    );
    assert!(
        err.contains("milling profiles: centroid, fanuc-mill, haas-mill, linuxcnc-mill"),
        "{err}"
    );
}

// ---- messages --------------------------------------------------------------------------------

/// Every message is `error: …`, `error[E…]: …` or `warning…: …`, with `  = help:`/`  = note:` or a
/// snippet after it: never `threadcut: …`.
fn one_form(err: &str) {
    let first = err.lines().next().unwrap_or("");
    assert!(
        first.starts_with("error: ")
            || first.starts_with("error[E")
            || first.starts_with("warning"),
        "{err}"
    );
    assert!(!err.contains("threadcut: "), "{err}");
}

#[test]
fn an_empty_program_is_an_error_for_every_command() {
    let dir = temp_dir("empty");
    let empty = write(&dir, "empty.nc", "");
    let blank = write(&dir, "blank.nc", "\n  \r\n\t\n");
    for file in [&empty, &blank] {
        for args in [
            vec!["expand", file, "-c", "gsk980"],
            vec!["expand", file, "-c", "gsk980", "--format", "jsonl"],
            vec!["passes", file, "-c", "gsk980"],
            vec!["check", file, "-c", "gsk980"],
            vec!["plot", file, "-c", "gsk980"],
            vec!["convert", file, "--from", "gsk980", "--to", "fanuc"],
            vec!["post", file, "-c", "fanuc"],
        ] {
            let out_file = dir.join("out");
            let mut with_o = args.clone();
            with_o.extend(["-o", out_file.to_str().unwrap()]);
            let out = threadcut(&with_o);
            assert_eq!(out.status.code(), Some(2), "{args:?}");
            let err = stderr(&out);
            one_form(&err);
            assert!(
                err.starts_with(&format!(
                    "error: {file} is empty: there is no program to read\n"
                )),
                "{args:?}: {err}"
            );
            assert!(!out_file.exists(), "{args:?}: an output was written");
        }
    }
    // Standard input too.
    let mut child = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["passes", "-", "-c", "fanuc"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdin.take());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).starts_with("error: standard input is empty"));
}

#[test]
fn files_that_cannot_be_read_or_written_name_the_file_and_the_reason() {
    let dir = temp_dir("io");
    let file = write(&dir, "p.nc", GSK);
    let d = dir.to_str().unwrap();
    // A directory as the program: no invented line and column.
    let out = threadcut(&["passes", d, "-c", "gsk980"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        format!("error: cannot read {d}: is a directory\n")
    );
    // -o into a folder that does not exist: the folder and the reason, no temporary file.
    let missing = dir.join("no-such-dir").join("out.nc");
    let out = threadcut(&[
        "expand",
        &file,
        "-c",
        "gsk980",
        "-o",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = stderr(&out);
    assert_eq!(
        err,
        format!(
            "error: cannot write {}: {}: No such file or directory\n",
            missing.display(),
            dir.join("no-such-dir").display()
        )
    );
    assert!(
        !err.contains(".threadcut-") && !err.contains("os error"),
        "{err}"
    );
    // -o onto a directory.
    let out = threadcut(&["expand", &file, "-c", "gsk980", "-o", d]);
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        stderr(&out),
        format!("error: cannot write {d}: is a directory\n")
    );
    // A profile that is not TOML: the file, the reason, the place.
    let bad = write(&dir, "bad.toml", "name = \"x\"\nunits = [\n");
    let out = threadcut(&["passes", &file, "--machine", &bad]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    one_form(&err);
    assert!(
        err.starts_with(&format!("error: {bad} is not a machine profile: ")),
        "{err}"
    );
    assert!(err.contains(&format!(" --> {bad}:")), "{err}");
}

#[test]
fn usage_errors_take_the_one_form() {
    let dir = temp_dir("usage");
    let file = write(&dir, "p.nc", GSK);
    // clap's own errors, rewritten.
    let out = threadcut(&["passes", &file, "-c", "gsk980", "--frmat", "json"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    one_form(&err);
    assert!(
        err.starts_with("error: unexpected argument '--frmat' found\n"),
        "{err}"
    );
    assert!(
        err.contains("\n  = help: a similar argument exists: '--format'"),
        "{err}"
    );
    assert!(err.contains("\n  = note: usage: threadcut passes"), "{err}");
    assert!(!err.contains("\n\n"), "{err}");
    let out = threadcut(&["passes", &file, "-c", "gsk980", "--format", "xml"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.starts_with("error: invalid value 'xml' for '--format <FORMAT>'\n  = help: possible values: text, json, jsonl\n"), "{err}");
    let out = threadcut(&["mill", "--thread", "M10"]);
    let err = stderr(&out);
    one_form(&err);
    assert!(
        err.starts_with(
            "error: the following required arguments were not provided: --length <LENGTH>, "
        ),
        "{err}"
    );
    // The library's diagnostics: compiler style, standard input named.
    let mut child = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["expand", "-", "-c", "fanuc"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(b"G0 X1.2.3\n")
        .unwrap();
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.starts_with("error[E001]: "), "{err}");
    assert!(err.contains("\n --> <stdin>:1:8\n"), "{err}");
    // A program without a thread: a warning, exit status 0.
    let plain = write(&dir, "plain.nc", "G0 X10 Z5\nG1 Z-10 F0.2\n");
    let out = threadcut(&["passes", &plain, "-c", "fanuc"]);
    assert_eq!(out.status.code(), Some(0));
    let err = stderr(&out);
    one_form(&err);
    assert!(
        err.starts_with(&format!("warning: no thread found in {plain}: ")),
        "{err}"
    );
    // Help and version are not errors.
    assert!(threadcut(&["--version"]).status.success());
    assert!(threadcut(&["expand", "--help"]).status.success());
}

// ---- words -----------------------------------------------------------------------------------

#[test]
fn mill_counts_and_units_read_right() {
    let mill = |thread: &str, extra: &[&str]| {
        let mut args = vec![
            "mill",
            "--thread",
            thread,
            "--internal",
            "-c",
            "centroid",
            "--comp",
            "none",
        ];
        if !extra.contains(&"--length") {
            args.extend(["--length", "10", "--tool-diameter", "6", "--feed", "300"]);
        }
        args.extend(extra);
        let out = threadcut(&args);
        assert!(out.status.success(), "{}", stderr(&out));
        stdout(&out)
    };
    let metric = mill("M10x1.5", &[]);
    assert!(metric.contains(", 1 radial pass, "), "{metric}");
    assert!(metric.contains(", 1 tooth)"), "{metric}");
    assert!(metric.contains(" 1 start, "), "{metric}");
    // 10 mm / 1.5 mm = 6.6667 turns: a metric thread has a pitch, not threads per inch.
    assert!(metric.contains("; length / pitch = 6.6667)"), "{metric}");
    assert!(!metric.contains("threads per inch"), "{metric}");
    let more = mill(
        "M10x1.5",
        &["--passes", "2", "--teeth", "2", "--starts", "2"],
    );
    assert!(more.contains(", 2 radial passes, "), "{more}");
    assert!(more.contains(", 2 teeth)"), "{more}");
    assert!(more.contains(" 2 starts, "), "{more}");
    // 1/2-13: 0.5 in × 13 = 6.5 turns, as TB029 counts them.
    let inch = mill(
        "1/2-13 UNC",
        &["--length", "0.5", "--tool-diameter", "0.25", "--feed", "12"],
    );
    assert!(
        inch.contains("; length × threads per inch = 6.5000)"),
        "{inch}"
    );
}

#[test]
fn thread_suggestions_are_threads_like_the_name() {
    let out = threadcut(&["thread", "M99"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    one_form(&err);
    assert!(
        err.contains("= help: nearest known threads: M68x6, M64x2, M64x3 (`threadcut thread --list` lists them all)"),
        "{err}"
    );
    assert!(!err.contains("UNC") && !err.contains("Tr"), "{err}");
}

// ---- line endings ----------------------------------------------------------------------------

/// Every line of `bytes` ends in CRLF.
fn all_crlf(bytes: &[u8]) -> bool {
    let text = String::from_utf8_lossy(bytes);
    text.matches('\n').count() == text.matches("\r\n").count() && !text.contains("\r\r")
}

#[test]
fn crlf_in_crlf_out() {
    let dir = temp_dir("crlf");
    let crlf = GSK.replace('\n', "\r\n");
    let file = write(&dir, "p.nc", &crlf);
    let expand = threadcut(&["expand", &file, "-c", "gsk980"]);
    assert!(expand.status.success());
    assert!(stdout(&expand).contains("G32"));
    assert!(all_crlf(&expand.stdout), "{:?}", stdout(&expand));
    let convert = threadcut(&["convert", &file, "--from", "gsk980", "--to", "linuxcnc"]);
    assert!(convert.status.success(), "{}", stderr(&convert));
    assert!(all_crlf(&convert.stdout), "{:?}", stdout(&convert));
    let apt = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/m20-external.apt"
    ))
    .unwrap();
    let apt_crlf = write(&dir, "p.apt", &apt.replace('\n', "\r\n"));
    let post = threadcut(&["post", &apt_crlf, "-c", "fanuc"]);
    assert!(post.status.success(), "{}", stderr(&post));
    assert!(all_crlf(&post.stdout), "{:?}", stdout(&post));
    // LF stays LF.
    let lf = write(&dir, "lf.nc", GSK);
    let expand = threadcut(&["expand", &lf, "-c", "gsk980"]);
    assert!(!expand.stdout.contains(&b'\r'));
}

// ---- big inputs ------------------------------------------------------------------------------

#[test]
fn plot_of_many_cycles_is_bounded_and_says_what_it_left_out() {
    let dir = temp_dir("plot");
    let file = write(&dir, "many.nc", &cycles(2000));
    let out = threadcut(&["plot", &file, "-c", "gsk980"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = stdout(&out);
    assert!(svg.len() < 1_000_000, "{} bytes", svg.len());
    assert_eq!(svg.matches("gsk980 cycle, ").count(), 50);
    assert!(svg.contains("threads 1–50 of 2000 drawn, 1950 left out"));
    let err = stderr(&out);
    one_form(&err);
    assert!(
        err.starts_with(&format!("warning: {file}: threads 1–50 of 2000 drawn, 1950 left out (lines 4–151)\n  = help: `--cycle N` draws")),
        "{err}"
    );
    // --cycle N: that thread alone.
    let out = threadcut(&["plot", &file, "-c", "gsk980", "--cycle", "1234"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = stdout(&out);
    assert_eq!(svg.matches("gsk980 cycle, ").count(), 1);
    assert!(svg.contains("line 3703: gsk980 cycle"), "{}", &svg[..600]);
    assert!(svg.contains("thread 1234 of 2000 drawn, 1999 left out"));
    // Asked for: the picture says what it left out, standard error needs not.
    assert_eq!(stderr(&out), "");
    let out = threadcut(&["plot", &file, "-c", "gsk980", "--cycle", "2001"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        stderr(&out),
        format!("error: --cycle 2001: {file} has 2000 threads\n")
    );
    // A thread of thousands of passes stays small too.
    let deep = write(
        &dir,
        "deep.nc",
        "G0 X80 Z10\nG78 P020060 Q0.001 R0.01\nG78 X40 Z-60 P10 Q0.11 F3\n",
    );
    let out = threadcut(&["plot", &deep, "-c", "gsk980"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = stdout(&out);
    assert!(svg.len() < 2_500_000, "{} bytes", svg.len());
    assert!(svg.contains("6965 rough passes"), "{}", &svg[..600]);
    assert!(
        svg.contains("toolpath and tool of 1 pass in 18 drawn"),
        "{}",
        &svg[..600]
    );
    // A cycle that cuts in one pass, run again 3,000 times from the same start: one thread of
    // 3,000 passes, every one after the first a spring pass at full depth in the same place.
    // Each is drawn once, not 3,000 times over.
    let once = "G0 X22. Z5.\nG76 X16.933 Z-30. K1.534 D2. F2.5 A60\n";
    let again = write(
        &dir,
        "again.nc",
        &format!("G21\nG97 S500 M3\n{}", once.repeat(3000)),
    );
    let out = threadcut(&["plot", &again, "-c", "haas"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let svg = stdout(&out);
    assert!(
        svg.contains("0 rough passes and 3000 finishing passes"),
        "{}",
        &svg[..600]
    );
    // The tool outlines of one pass in eight (a spring pass is not drawn again over the pass
    // before it), and the target form.
    let outlines = svg.matches("<polyline").count();
    assert!((375..=380).contains(&outlines), "{outlines} outlines");
    assert!(svg.len() < 400_000, "{} bytes", svg.len()); // 2.2 MB when each was drawn
}

#[test]
fn progress_shows_on_a_terminal_only() {
    let dir = temp_dir("progress");
    // Long enough to outlast the bar's quiet time in a debug build on a fast machine (6,000
    // cycles took 0.47 s once `check` got faster: too close).
    let file = write(&dir, "big.nc", &cycles(24_000));
    // Standard error a pipe: not a byte of progress.
    let out = threadcut(&["check", &file, "-c", "gsk980", "-o", "/dev/null"]);
    assert!(out.status.success());
    assert!(out.stderr.is_empty(), "{}", stderr(&out));
    // On a terminal (script(1) gives the command one), a run of more than a moment shows the bar
    // on standard error, and clears it.
    let Ok(script) = which("script") else {
        eprintln!("no script(1): the terminal half is not run");
        return;
    };
    let cmd = format!(
        "{} check {file} -c gsk980 -o /dev/null",
        env!("CARGO_BIN_EXE_threadcut")
    );
    let out = Command::new(script)
        .args(["-qec", &cmd, "/dev/null"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
    let seen = String::from_utf8_lossy(&out.stdout);
    assert!(seen.contains("reading "), "{seen:?}");
    assert!(seen.contains("KiB/"), "{seen:?}");
}

fn which(name: &str) -> Result<PathBuf, ()> {
    std::env::var_os("PATH")
        .and_then(|p| {
            std::env::split_paths(&p)
                .map(|d| d.join(name))
                .find(|p| p.is_file())
        })
        .ok_or(())
}
