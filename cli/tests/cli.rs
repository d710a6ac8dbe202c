//! The `threadcut` command as a user runs it: exit status, diagnostics, output files.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

fn threadcut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .expect("run threadcut")
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("threadcut-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const GOOD: &str =
    "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\nG0 X80 Z10\n";

#[test]
fn bundled_example_expands() {
    let example = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples/gsk-g78.nc");
    let out = threadcut(&["expand", example, "--controller", "gsk980"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains("G32 X"), "{text}");
    assert!(!text.lines().any(|l| l.starts_with("G78")), "{text}");
}

#[test]
fn expand_to_a_file_and_passes_json() {
    let dir = temp_dir("ok");
    let input = write(&dir, "in.nc", GOOD);
    let output = dir.join("out.nc");
    let out = threadcut(&[
        "expand",
        input.to_str().unwrap(),
        "-c",
        "gsk980",
        "-o",
        output.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(out.stdout.is_empty());
    let text = std::fs::read_to_string(&output).unwrap();
    assert!(text.starts_with("G0 X80 Z10\n(threadcut"), "{text}");
    // An ordinary new file's mode (0666 less the umask: the same as `File::create` gives), not a
    // temporary file's 0600.
    use std::os::unix::fs::PermissionsExt;
    let reference = std::env::temp_dir().join(format!("threadcut-mode-{}", std::process::id()));
    std::fs::File::create(&reference).unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&output), mode(&reference));
    std::fs::remove_file(&reference).unwrap();
    // No temporary file is left beside it.
    let names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");

    let out = threadcut(&[
        "passes",
        input.to_str().unwrap(),
        "--controller",
        "gsk980",
        "--json",
    ]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let cycle = &v["cycles"][0];
    assert_eq!(cycle["line"], 3);
    assert_eq!(cycle["controller"], "gsk980");
    let pass = &cycle["passes"][1];
    for key in ["n", "kind", "depth", "increment", "x", "z", "area"] {
        assert!(pass.get(key).is_some(), "missing {key} in {pass}");
    }
    assert_eq!(pass["kind"], "rough");
    assert_eq!(pass["x"], 61.0);
    assert_eq!(cycle["passes"][3]["kind"], "finish");
}

#[test]
fn bad_input_exits_2_with_a_caret_and_writes_nothing() {
    let dir = temp_dir("bad");
    let input = write(
        &dir,
        "bad.nc",
        "G0 X80 Z10\nG78 P020545 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3\n",
    );
    let output = dir.join("out.nc");
    let out = threadcut(&[
        "expand",
        input.to_str().unwrap(),
        "--controller",
        "gsk980",
        "-o",
        output.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("error[E004]: P(r)=05"), "{err}");
    assert!(err.contains("bad.nc:2:8"), "{err}");
    assert!(
        err.contains("2 | G78 P020545 Q0.15 R0.5\n  |        ^^"),
        "{err}"
    );
    assert!(err.contains("help:"), "{err}");
    assert!(!output.exists());
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        1,
        "a temporary file was left behind"
    );
}

#[test]
fn missing_word_alarm_points_at_g78() {
    let dir = temp_dir("alarm");
    let input = write(&dir, "a.nc", "G0 X80 Z10\n  G78 X60 Z-60 Q1.8 F3\n");
    let out = threadcut(&["passes", input.to_str().unwrap(), "-c", "gsk980"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("a.nc:2:3") && err.contains("P(k) is missing"),
        "{err}"
    );
}

#[test]
fn usage_errors() {
    let dir = temp_dir("same");
    let input = write(&dir, "in.nc", GOOD);
    let out = threadcut(&["expand", input.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--controller"));
    let out = threadcut(&["expand", input.to_str().unwrap(), "-c", "nosuch"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown controller `nosuch`"));
    let out = threadcut(&["expand", "no-such-file.nc", "-c", "gsk980"]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(
        String::from_utf8_lossy(&out.stderr),
        "error: cannot read no-such-file.nc: No such file or directory\n"
    );
    let out = threadcut(&[
        "expand",
        input.to_str().unwrap(),
        "-c",
        "gsk980",
        "-o",
        input.to_str().unwrap(),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert_eq!(std::fs::read_to_string(&input).unwrap(), GOOD);
}

#[test]
fn controllers_lists_built_ins() {
    let out = threadcut(&["controllers"]);
    assert!(out.status.success());
    assert!(String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .any(|l| l.starts_with("gsk980 ")));
}

#[test]
fn machine_profile_from_a_file() {
    let dir = temp_dir("machine");
    let profile = include_str!("../../profiles/gsk980.toml").replace("p5142 = 1 ", "p5142 = 3 ");
    let m = write(&dir, "m.toml", &profile);
    let input = write(&dir, "in.nc", "G0 X80 Z10\nG78 X60 Z-60 P3 Q1.8 F3\n");
    let out = threadcut(&[
        "passes",
        input.to_str().unwrap(),
        "--machine",
        m.to_str().unwrap(),
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let passes = v["cycles"][0]["passes"].as_array().unwrap();
    assert_eq!(passes.iter().filter(|p| p["kind"] == "finish").count(), 3);
}

#[test]
fn a_closed_stdout_ends_quietly() {
    let mut big = String::new();
    for i in 0..20_000 {
        big.push_str(&format!("G0 X{} Z10\n", 80 + i % 7));
        big.push_str("G78 X60 Z-60 P3 Q0.3 F3\n");
    }
    let mut child = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["expand", "-", "-c", "gsk980"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let feeder = std::thread::spawn(move || {
        let _ = stdin.write_all(big.as_bytes());
    });
    let mut first = [0u8; 16];
    child
        .stdout
        .as_mut()
        .unwrap()
        .read_exact(&mut first)
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    feeder.join().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn special_files_are_written_in_place_never_replaced() {
    // `-o /dev/null` once renamed a temporary file over the device. A FIFO stands in for it here.
    use std::os::unix::fs::FileTypeExt;
    let dir = temp_dir("fifo");
    let input = write(&dir, "in.nc", GOOD);
    let fifo = dir.join("pipe");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
    };
    let out = threadcut(&[
        "expand",
        input.to_str().unwrap(),
        "-c",
        "gsk980",
        "-o",
        fifo.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = reader.join().unwrap();
    assert!(text.contains("G32 X62.4 Z-58. F3."), "{text}");
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // And a symbolic link keeps pointing at its file, which receives the output.
    let real = dir.join("real.nc");
    std::fs::write(&real, "old").unwrap();
    let link = dir.join("link.nc");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    let out = threadcut(&[
        "expand",
        input.to_str().unwrap(),
        "-c",
        "gsk980",
        "-o",
        link.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read_to_string(&real).unwrap().contains("G32"));
}

/// Each finding shows its own line, read where its span says the line begins: after CRLF line
/// ends and a comment in UTF-8 (bytes, not characters, count), and for a repeated cycle with a
/// warning on each of its lines.
#[test]
fn each_finding_shows_its_own_line() {
    let dir = temp_dir("own-line");
    let mut text = String::from("(GEWINDE ÜBER M20 – PRÜFEN)\r\nG21\r\nG97 S500 M3\r\n");
    for i in 0..3 {
        // A one-pass G76 (D above K) run again, a different X each time to tell the lines apart.
        text += &format!("G0 X22. Z5.\r\nG76 X16.9{i}3 Z-30. K1.534 D2. F2.5 A60\r\n");
    }
    let file = write(&dir, "again.nc", &text);
    let out = threadcut(&["passes", file.to_str().unwrap(), "-c", "haas"]);
    let err = String::from_utf8_lossy(&out.stderr);
    for (i, line) in [5, 7, 9].iter().enumerate() {
        let shown = format!("{line} | G76 X16.9{i}3 Z-30. K1.534 D2. F2.5 A60\n");
        assert!(err.contains(&shown), "{shown:?} not in\n{err}");
    }
}

#[test]
fn a_long_file_read_on_two_threads_is_copied_exactly_and_an_alarm_late_in_it_is_told_at_its_line() {
    // A file of 4 MiB or more is read ahead, and every other part of it is lexed on a second
    // thread (cli/src/cli/lookahead.rs, in parts of 1 MiB): the output and the errors must be
    // those of reading it on one.
    let dir = temp_dir("long");
    let mut text = String::from("G21 G99\nG0 X100 Z5\n");
    let mut lines = 2;
    while text.len() < 6 << 20 {
        let (x, z) = (20 + lines % 7, lines % 400);
        text.push_str(&format!("G1 X{x}.250 Z-{z}.05 F0.15\nG0 X30. W1.\n"));
        lines += 2;
    }
    let input = write(&dir, "long.nc", &text);
    let output = dir.join("out.nc");
    let run = |input: &Path| {
        threadcut(&[
            "expand",
            input.to_str().unwrap(),
            "-c",
            "gsk980",
            "-o",
            output.to_str().unwrap(),
        ])
    };
    let out = run(&input);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(std::fs::read(&output).unwrap() == text.as_bytes());
    std::fs::remove_file(&output).unwrap();
    // An alarm in the run's own part (the fifth MiB) and in one the second thread reads (the
    // sixth): the line and column of the one-thread run, and no output file.
    for mib in [4, 5] {
        let at = (mib << 20) + 100;
        let at = at + text[at..].find('\n').unwrap() + 1;
        let line = text[..at].matches('\n').count() + 1;
        let bad = format!("{}G1 X20 Z-1 G345\n{}", &text[..at], &text[at..]);
        let input = write(&dir, "bad.nc", &bad);
        let out = run(&input);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains("G345 is not a G code of gsk980"), "{err}");
        assert!(err.contains(&format!("bad.nc:{line}:12")), "{line}: {err}");
        assert!(!output.exists(), "a half-written output");
    }
}
