//! The part the program makes, seen (issue 23, "See it"): `plot` draws it, `plot --part` alone,
//! `passes` states each thread's blank, and a machine profile's `[stock]` stands in for the
//! stock options the command line does not give.

use std::io::Write;
use std::path::PathBuf;
use std::process::{Command, Stdio};

/// Turns Ø19.8 from a Ø25 bar (G71/G70, contour N10–N20), then cuts M20x2.5 with G76 (root
/// Ø16.85 from X16.85), then a rapid at line 19 runs from X24 Z5 to X15 Z-10: through the
/// thread's teeth (the crest Ø19.8 is crossed near Z-2, as `check` finds: E011).
const HIT: &str = "G21 G99\nT0101\nG97 S800 M03\nG00 X27. Z2.\nG71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G00 X16.\nG01 Z0. F0.12\nX19.8 Z-1.9\nZ-30.\nX24.\nN20 X27.\nG70 P10 Q20\nG00 X100. Z100.\nT0303\nG00 X24. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.85 Z-27. P1575 Q400 F2.5\nG00 X15. Z-10.\nG00 X100. Z100.\nM30\n";
/// The line of HIT's rapid through the thread.
const HIT_LINE: u32 = 19;

/// A plain G76 M20x2.5 with nothing turned: its blank is the stock, or the crest assumed.
const G76: &str = "G97 S800 M03\nG00 X24. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.85 Z-27. P1575 Q400 F2.5\nG00 X100. Z100.\nM30\n";

fn tmp(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name)
}

/// Runs `threadcut ARGS… FILE` on `src` (a file named after `name`); (status, stdout, stderr).
fn run(name: &str, src: &str, args: &[&str]) -> (i32, String, String) {
    let input = tmp(&format!("part-{name}.nc"));
    std::fs::write(&input, src).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .arg(&input)
        .output()
        .unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
    )
}

/// The same through standard input.
fn run_stdin(src: &str, args: &[&str]) -> (i32, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .arg("-")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    child
        .stdin
        .take()
        .unwrap()
        .write_all(src.as_bytes())
        .unwrap();
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap(),
        String::from_utf8(out.stdout).unwrap(),
    )
}

/// A profile: the built-in fanuc's with `extra` appended.
fn profile(name: &str, extra: &str) -> PathBuf {
    let text = threadcut::machine::BUILT_IN
        .iter()
        .find(|(n, _)| *n == "fanuc")
        .unwrap()
        .1;
    let path = tmp(&format!("part-{name}.toml"));
    std::fs::write(&path, format!("{text}\n{extra}")).unwrap();
    path
}

#[test]
fn plot_draws_the_part_and_the_rapid_into_it_in_red_at_its_line() {
    let (code, svg, err) = run(
        "hit",
        HIT,
        &[
            "plot",
            "-c",
            "fanuc",
            "--stock-diameter",
            "25",
            "--stock-start",
            "0",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(svg.contains("The part as the program makes it"), "{svg}");
    assert!(svg.contains("1 rapid move runs into material"));
    // One red line and its label at its line; the thread's teeth labelled at the G76's line.
    assert_eq!(svg.matches("class=\"rapid-hit\"").count(), 1);
    assert!(svg.contains(r##"stroke="#d00""##));
    assert!(svg.contains(&format!(">line {HIT_LINE}</text>")));
    assert!(svg.contains("thread, line 18"));
    assert!(svg.contains("dashed: the stock Ø25 as given"));
    // The thread's own panels are still there, below the part.
    assert!(svg.contains("Pass diagram"));
    let part_at = svg.find("The part as").unwrap();
    assert!(part_at < svg.find("Pass diagram").unwrap());
}

/// The rapid's red line, drawn on the page where the model puts it: from X24 Z5 (radius 12) to
/// X15 Z-10 (radius 7.5); the page maps Z to the right and X up, so the line runs down to the
/// left, and its marker sits where it enters the crest (radius 9.9, the turned Ø19.8).
#[test]
fn the_red_line_runs_where_the_rapid_runs() {
    let (_, svg, _) = run("hit-geometry", HIT, &["plot", "-c", "fanuc", "--part"]);
    let line = svg
        .lines()
        .find(|l| l.contains("rapid-hit"))
        .expect("a red line");
    let num = |key: &str| -> f64 {
        let at = line.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        line[at..].split('"').next().unwrap().parse().unwrap()
    };
    let (x1, y1, x2, y2) = (num("x1"), num("y1"), num("x2"), num("y2"));
    // From Z5 to Z-10: to the left; from radius 12 to 7.5: down the page (y grows).
    assert!(x2 < x1 && y2 > y1, "{line}");
    // The page's scale along Z and X from the line itself: 15 mm of Z, 4.5 mm of radius.
    let (sz, sx) = ((x1 - x2) / 15.0, (y2 - y1) / 4.5);
    assert!(sz > 0.0 && sx > 0.0);
    // The marker: the circle after the line, at the entry point.
    let circle = svg.lines().find(|l| l.starts_with("<circle")).unwrap();
    let c = |key: &str| -> f64 {
        let at = circle.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
        circle[at..].split('"').next().unwrap().parse().unwrap()
    };
    // Its radius on the page from the start: (12 − r)·sx down; r is the crest's 9.9 within the
    // resolution (check says X19.798).
    let r = 12.0 - (c("cy") - y1) / sx;
    assert!((r - 9.9).abs() < 0.01, "entry at radius {r}");
}

#[test]
fn plot_part_alone_draws_no_thread_panel() {
    let (code, svg, err) = run("alone", HIT, &["plot", "-c", "fanuc", "--part"]);
    assert_eq!(code, 0, "{err}");
    assert!(svg.contains("The part as the program makes it"));
    assert!(!svg.contains("Pass diagram"));
    assert!(svg.contains("the stock's size is not given"));
    // Without a stock the rapid still runs through the thread the program cut: a fact.
    assert!(svg.contains(r##"stroke="#d00""##));
    // --part and --cycle do not go together.
    let (code, _, err) = run(
        "alone-cycle",
        HIT,
        &["plot", "-c", "fanuc", "--part", "--cycle", "1"],
    );
    assert_eq!(code, 2, "{err}");
    // Standard input works too: it is read twice.
    let (code, from_stdin) = run_stdin(HIT, &["plot", "-c", "fanuc", "--part"]);
    assert_eq!(code, 0);
    assert_eq!(from_stdin, svg);
}

/// A program that cuts nothing, with no stock given and no rapid into material: the picture is
/// the threads' alone, as before the part was drawn.
#[test]
fn a_thread_alone_keeps_its_picture() {
    let (code, svg, _) = run("g76", G76, &["plot", "-c", "fanuc"]);
    assert_eq!(code, 0);
    assert!(!svg.contains("The part as"));
    let (_, with_stock, _) = run(
        "g76-stock",
        G76,
        &["plot", "-c", "fanuc", "--stock-diameter", "20"],
    );
    assert!(with_stock.contains("The part as"));
    assert!(with_stock.contains("dashed: the stock Ø20 as given"));
}

/// Rapids into a given stock, 150 of them: the picture draws the first 100 and says so.
#[test]
fn rapids_drawn_are_capped_and_the_picture_says_so() {
    let mut src = String::from("G97 S800 M03\n");
    for i in 0..150 {
        // Each from outside the Ø40 bar at Z5 to X30 Z-(i+1) inside it, and back out.
        src.push_str(&format!("G00 X50. Z5.\nG00 X30. Z-{}.\n", i + 1));
    }
    src.push_str("G00 X50. Z5.\nM30\n");
    let (code, svg, err) = run(
        "many",
        &src,
        &[
            "plot",
            "-c",
            "fanuc",
            "--part",
            "--stock-diameter",
            "40",
            "--stock-start",
            "0",
        ],
    );
    assert_eq!(code, 0, "{err}");
    assert!(svg.contains("150 rapid moves run into material"), "{svg}");
    assert!(svg.contains("the first 100 of 150 rapids into material drawn"));
    assert_eq!(svg.matches("class=\"rapid-hit\"").count(), 100);
}

/// `plot --part`'s SVG is deterministic: snapshotted.
#[test]
fn part_plot_snapshot() {
    let (_, svg, _) = run(
        "snapshot",
        HIT,
        &[
            "plot",
            "-c",
            "fanuc",
            "--part",
            "--stock-diameter",
            "25",
            "--stock-start",
            "0",
            "--stock-length",
            "40",
        ],
    );
    insta::assert_snapshot!("part_svg", svg);
}

fn blanks(json: &str) -> Vec<serde_json::Value> {
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["blank"].clone())
        .collect()
}

#[test]
fn passes_states_each_threads_blank() {
    // Turned Ø19.8 at line 10: measured on the part. The face: Z0 assumed (check's rule).
    let (code, json, _) = run("blank", HIT, &["passes", "-c", "fanuc", "--format", "json"]);
    assert_eq!(code, 0);
    assert_eq!(
        blanks(&json),
        vec![
            serde_json::json!({"crest": 19.8, "crest_from": "measured", "face": 0.0, "face_from": "assumed"})
        ]
    );
    // The keys that were there stay.
    let v: serde_json::Value = serde_json::from_str(&json).unwrap();
    for key in [
        "line",
        "controller",
        "units",
        "source",
        "depth_from",
        "passes",
    ] {
        assert!(v["cycles"][0].get(key).is_some(), "{key}");
    }
    // Nothing turned: the stock given is the blank, the face given.
    let (_, json, _) = run(
        "blank-given",
        G76,
        &[
            "passes",
            "-c",
            "fanuc",
            "--json",
            "--stock-diameter",
            "20",
            "--stock-start",
            "1",
        ],
    );
    assert_eq!(
        blanks(&json),
        vec![
            serde_json::json!({"crest": 20.0, "crest_from": "given", "face": 1.0, "face_from": "given"})
        ]
    );
    // Nothing given: the cycle's crest Ø20 (X24 start, G76 X16.85 + 2·1.575 = 20.0) assumed.
    let (_, json, _) = run("blank-assumed", G76, &["passes", "-c", "fanuc", "--json"]);
    assert_eq!(blanks(&json)[0]["crest_from"], "assumed");
    assert!((blanks(&json)[0]["crest"].as_f64().unwrap() - 20.0).abs() < 5e-4);
    // Text: one line per thread after its title.
    let (_, text, _) = run("blank-text", HIT, &["passes", "-c", "fanuc"]);
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("line 18: "), "{text}");
    assert_eq!(
        lines[1],
        "blank: crest Ø19.8 (measured on the part the program turned), face Z0 (assumed)"
    );
    // JSON lines carry it too; standard input gives the same.
    let (_, jsonl, _) = run(
        "blank-jsonl",
        HIT,
        &["passes", "-c", "fanuc", "--format", "jsonl"],
    );
    let one: serde_json::Value = serde_json::from_str(jsonl.lines().next().unwrap()).unwrap();
    assert_eq!(one["blank"]["crest_from"], "measured");
    let (_, from_stdin) = run_stdin(HIT, &["passes", "-c", "fanuc", "--format", "json"]);
    assert_eq!(from_stdin, json_of(HIT));
}

fn json_of(src: &str) -> String {
    run(
        "blank-again",
        src,
        &["passes", "-c", "fanuc", "--format", "json"],
    )
    .1
}

#[test]
fn a_profile_stock_stands_in_where_the_command_line_gives_none() {
    let m = profile("stock", "[stock]\ndiameter = 20.5\nface = 2.0\n");
    let m = m.to_str().unwrap();
    let (_, json, err) = run("profile", G76, &["passes", "--machine", m, "--json"]);
    assert_eq!(
        blanks(&json),
        vec![
            serde_json::json!({"crest": 20.5, "crest_from": "given", "face": 2.0, "face_from": "given"})
        ],
        "{err}"
    );
    // The command line wins, value by value.
    let (_, json, _) = run(
        "profile-over",
        G76,
        &[
            "passes",
            "--machine",
            m,
            "--json",
            "--stock-diameter",
            "20.2",
        ],
    );
    assert_eq!(
        blanks(&json),
        vec![
            serde_json::json!({"crest": 20.2, "crest_from": "given", "face": 2.0, "face_from": "given"})
        ]
    );
    // check and plot take it the same way: the profile's stock is the command line's.
    let (c1, by_profile, _) = run(
        "profile-check",
        HIT,
        &["check", "--machine", m, "--format", "json"],
    );
    let (c2, by_flags, _) = run(
        "profile-check",
        HIT,
        &[
            "check",
            "--machine",
            m,
            "--format",
            "json",
            "--stock-diameter",
            "20.5",
            "--stock-start",
            "2",
        ],
    );
    assert_eq!((c1, &by_profile), (c2, &by_flags));
    let (_, svg, _) = run("profile-plot", G76, &["plot", "--machine", m, "--part"]);
    assert!(svg.contains("dashed: the stock Ø20.5 as given"), "{svg}");
    // A key [stock] does not know is refused, naming the place.
    let bad = profile("stock-bad", "[stock]\ndiametre = 20.5\n");
    let (code, _, err) = run(
        "profile-bad",
        G76,
        &["passes", "--machine", bad.to_str().unwrap()],
    );
    assert_eq!(code, 2);
    assert!(err.contains("diametre"), "{err}");
}

#[test]
fn stock_values_that_are_no_length_are_usage_errors() {
    for (flag, v) in [
        ("--stock-diameter", "0"),
        ("--stock-length", "0"),
        ("--stock-bore", "nan"),
    ] {
        let (code, _, err) = run("bad-stock", G76, &["plot", "-c", "fanuc", flag, v]);
        assert_eq!(code, 2, "{flag} {v}: {err}");
        assert!(err.contains(flag), "{err}");
    }
}
