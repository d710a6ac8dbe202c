//! A cycle on its own through the command: `passes` gives the pass table with a note of what is
//! not known, `expand` and `check` say they need the start point, and `--start X,Z` gives it
//! (docs/cli.md, "A cycle on its own").

use std::process::Command;

/// Runs `threadcut ARGS -` with `src` on standard input: (exit status, stdout, stderr).
fn run(args: &[&str], src: &str) -> (i32, String, String) {
    use std::io::Write;
    let mut child = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .arg("-")
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // A usage error exits before reading: the program's bytes then meet a closed pipe.
    if let Err(e) = child.stdin.take().unwrap().write_all(src.as_bytes()) {
        assert_eq!(e.kind(), std::io::ErrorKind::BrokenPipe, "{e}");
    }
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// FS15's one-block G76 (mm): K1.534, D0.485, P1 by default (one flank, constant amount).
const G76: &str = "M3 S500\nG76 X16.93 Z-25. K1.534 D.485 F2.5\nM30\n";

/// `passes` of the cycle alone. FS15's profile: the least cut 0.1 (parameter 5140), the finishing
/// allowance 0.05 (5141). Rough passes at 0.485·√n: 0.485, 0.68589, 0.84004, 0.97, 1.08449,
/// 1.188; then 0.485·√7 = 1.28319 < 1.188 + 0.1 → 1.288, 1.388; 1.488 passes K − 0.05 = 1.484 →
/// 1.484; the finishing pass at K = 1.534 (increment 0.05). Pass 1 at X 16.93 + 2·(1.534 − 0.485)
/// = 19.028, the finishing pass at 16.93; the Z column not known.
#[test]
fn passes_of_a_cycle_alone() {
    let (code, out, err) = run(&["passes", "-c", "fanuc15"], G76);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("note: the start point is not known (the tool's X and Z before the cycle)"),
        "{out}"
    );
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.trim_start().starts_with(|c: char| c.is_ascii_digit()))
        .collect();
    assert_eq!(rows.len(), 10, "{out}");
    let cols: Vec<&str> = rows[0].split_whitespace().collect();
    assert_eq!(
        &cols[..6],
        ["1", "rough", "0.4850", "0.4850", "19.0280", "?"],
        "{out}"
    );
    let cols: Vec<&str> = rows[7].split_whitespace().collect();
    assert_eq!(
        &cols[..6],
        ["8", "rough", "1.3880", "0.1000", "17.2220", "?"],
        "{out}"
    );
    let cols: Vec<&str> = rows[9].split_whitespace().collect();
    assert_eq!(
        &cols[..6],
        ["10", "finish", "1.5340", "0.0500", "16.9300", "?"],
        "{out}"
    );

    let (code, out, _) = run(&["passes", "-c", "fanuc15", "--json"], G76);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let cycle = &v["cycles"][0];
    assert!(cycle["passes"][0]["z"].is_null(), "{cycle}");
    assert!((cycle["passes"][0]["x"].as_f64().unwrap() - 19.028).abs() < 1e-6);
    assert_eq!(
        cycle["start_unknown"]["axes"],
        serde_json::json!(["X", "Z"])
    );

    // With the start given, the table is the same and the note gone; Z known (Z5 plus pass 1's
    // flank shift (1.534 − 0.485)·tan 30° = 0.60564 → 5.6056).
    let (code, out, _) = run(&["passes", "-c", "fanuc15", "--start", "22,5"], G76);
    assert_eq!(code, 0);
    assert!(!out.contains("not known"), "{out}");
    let first = out
        .lines()
        .find(|l| l.trim_start().starts_with("1 "))
        .unwrap();
    let cols: Vec<&str> = first.split_whitespace().collect();
    assert_eq!(
        &cols[..6],
        ["1", "rough", "0.4850", "0.4850", "19.0280", "5.6056"],
        "{out}"
    );
}

/// `expand` and `plot` need the start: refused, saying how to give it; given, they run.
#[test]
fn expand_and_plot_need_the_start() {
    for cmd in ["expand", "plot"] {
        let (code, _, err) = run(&[cmd, "-c", "fanuc15"], G76);
        assert_ne!(code, 0, "{cmd}");
        assert!(
            err.contains("G76 starts where the tool is, and the tool's X and Z are not known here"),
            "{err}"
        );
        assert!(err.contains("--start X,Z"), "{err}");
        let (code, out, err) = run(&[cmd, "-c", "fanuc15", "--start", "22,5"], G76);
        assert_eq!(code, 0, "{cmd}: {err}");
        assert!(!out.is_empty());
    }
    let (_, out, _) = run(&["expand", "-c", "fanuc15", "--start", "22,5"], G76);
    // Pass 1: rapid to X19.028 at Z5.606 (Z5 + 0.60564, at the output's 0.001).
    assert!(out.contains("X19.028 Z5.606"), "{out}");
}

/// `check` cannot judge the motion without the start; with `--start` it finds what depends on
/// it: a start below the crest (X18 diameter, the thread's top at 16.93 + 2·1.534 = 19.998)
/// would cut through the thread on the way back between passes.
#[test]
fn check_takes_the_start() {
    let (code, out, _) = run(&["check", "-c", "fanuc15"], G76);
    assert_eq!(code, 2);
    assert!(out.contains("error[E006]"), "{out}");
    assert!(out.contains("--start X,Z"), "{out}");
    let (code, out, _) = run(&["check", "-c", "fanuc15", "--start", "18,5"], G76);
    assert_eq!(code, 2, "{out}");
    assert!(
        out.contains(
            "error[E007]: the start point X18. lies inside the thread (its top is at X19.998)"
        ),
        "{out}"
    );
    let (code, out, _) = run(&["check", "-c", "fanuc15", "--start", "22,5"], G76);
    assert_eq!(code, 0, "{out}");
    assert!(out.contains("0 errors"), "{out}");
}

/// `--start` takes two numbers.
#[test]
fn a_bad_start_is_a_usage_error() {
    for bad in ["22", "22,", "a,5", "22;5", "inf,5"] {
        let (code, _, err) = run(&["passes", "-c", "fanuc15", "--start", bad], G76);
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(err.contains("expected X,Z"), "{bad}: {err}");
    }
}
