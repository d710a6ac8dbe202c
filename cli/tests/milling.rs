//! `passes`, `check` and `plot` on a milling profile (issue 24): the command line over the
//! milling reader and thread recognition, as a user runs it.

use std::process::{Command, Output};

fn threadcut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .expect("run threadcut")
}

fn data(name: &str) -> String {
    format!("{}/../tests/data/mill/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn text(b: &[u8]) -> String {
    String::from_utf8(b.to_vec()).unwrap()
}

#[test]
fn passes_lists_each_helix_and_each_tap() {
    let out = threadcut(&[
        "passes",
        &data("fanuc-m20-internal-g41.nc"),
        "-c",
        "fanuc-mill",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let s = text(&out.stdout);
    assert!(s.starts_with("line 10: milled thread about X0 Y0 (G17), internal (from the entry), right-hand, bottom-up, climb; lead 2.5, 1 start, pitch 2.5 (mm)\n"), "{s}");
    // One helix: R10 under G41 (the contour: Ø20), Z-20 to Z0 in 8 turns, lines 10–17.
    assert!(
        s.contains("   1      1          10          20         -20           0   8.000  10-17"),
        "{s}"
    );
    let out = threadcut(&[
        "passes",
        &data("fanuc-m10-rigid-tap.nc"),
        "-c",
        "fanuc-mill",
        "--format",
        "json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["milled"].as_array().unwrap().len(), 0);
    let taps = v["taps"].as_array().unwrap();
    assert_eq!(taps.len(), 2);
    assert_eq!(taps[1]["position"][0], 40.0);
    assert_eq!(taps[0]["code"], 840);
    let out = threadcut(&[
        "passes",
        &data("linuxcnc-m12-helix.ngc"),
        "-c",
        "linuxcnc-mill",
        "--format",
        "jsonl",
        "--tool-diameter",
        "10",
    ]);
    let line: serde_json::Value =
        serde_json::from_slice(text(&out.stdout).lines().next().unwrap().as_bytes()).unwrap();
    assert_eq!(line["side"], "external");
    assert_eq!(line["side_from"], "entry");
    // 2·9.9 − 10 = 9.8.
    assert!((line["root_diameter"].as_f64().unwrap() - 9.8).abs() < 1e-9);
    assert_eq!(line["passes"][0]["turns"], 6.0);
}

#[test]
fn check_reports_a_fault_at_its_line_and_exits_2() {
    let good = threadcut(&[
        "check",
        &data("fanuc-m20-internal-g41.nc"),
        "-c",
        "fanuc-mill",
        "--thread",
        "M20x2.5-6H",
    ]);
    assert!(good.status.success(), "{}", text(&good.stdout));
    assert!(text(&good.stdout).ends_with("0 errors, 0 warnings in 1 thread\n"));
    // The bolt's path with an 8 mm cutter in tool 2: the minor diameter 2·9.9 − 8 = 11.8.
    let out = threadcut(&[
        "check",
        &data("linuxcnc-m12-helix.ngc"),
        "-c",
        "linuxcnc-mill",
        "--thread",
        "M12x1.75-6g",
        "--tool",
        "T2=8",
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let e = v
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["code"] == "E016")
        .expect("E016");
    assert_eq!(e["line"], 8);
    assert!(e["message"]
        .as_str()
        .unwrap()
        .contains("the minor diameter the cutter reaches is 11.8"));
    // A --tool that is not Dn=D or Tn=D is a usage error.
    let out = threadcut(&[
        "check",
        &data("linuxcnc-m12-helix.ngc"),
        "-c",
        "linuxcnc-mill",
        "--tool",
        "X2=8",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        text(&out.stderr).contains("--tool X2=8: expected a register or tool number"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn plot_draws_the_helix() {
    let out = threadcut(&[
        "plot",
        &data("fanuc-m20-internal-g41.nc"),
        "-c",
        "fanuc-mill",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let svg = text(&out.stdout);
    assert!(
        svg.starts_with("<svg")
            && svg.contains("line 10: lead 2.5, 1 start(s), 1 passes about (0, 0)"),
        "{svg}"
    );
    // A program with no thread says so on standard error.
    let out = threadcut(&["plot", &data("fanuc-m10-rigid-tap.nc"), "-c", "fanuc-mill"]);
    assert!(text(&out.stdout).contains("no milled thread in this program"));
}
