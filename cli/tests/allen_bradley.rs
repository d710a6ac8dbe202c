//! Allen-Bradley 9/Series G78 (seed 003): the word table, the P1–P4 infeeds, the AMP values in the
//! profile, the controller's bad inputs, and the CLI.

use std::process::Command;

use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::{EWord, Machine};
use threadcut::program::{self, Error};
use threadcut::thread::{tan_deg, Job, PassKind, Side};
use threadcut::toolpath::{self, MotionKind};

const IN: f64 = 25.4;
const EPS: f64 = 1e-9;

fn machine() -> Machine {
    Machine::built_in("ab9").unwrap()
}

fn jobs_on(src: &str, m: &Machine) -> Vec<Job> {
    program::jobs(src.as_bytes(), m).unwrap_or_else(|e| panic!("{e}"))
}

fn job_on(src: &str, m: &Machine) -> Job {
    let mut all = jobs_on(src, m);
    assert_eq!(all.len(), 1);
    all.remove(0)
}

fn read(src: &str) -> Job {
    job_on(src, &machine())
}

fn example(name: &str) -> String {
    std::fs::read_to_string(path_of(name)).unwrap()
}

fn path_of(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn error(src: &str) -> Diagnostic {
    match program::jobs(src.as_bytes(), &machine()) {
        Err(Error::Input(d)) => d,
        Err(e) => panic!("not an input error: {e}"),
        Ok(_) => panic!("accepted: {src}"),
    }
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < EPS
}

/// (kind, depth, z) of each pass, in the program's units (`scale` mm per unit).
fn table(job: &Job, scale: f64) -> Vec<(PassKind, f64, f64)> {
    job.passes()
        .unwrap()
        .iter()
        .map(|p| (p.kind, p.depth / scale, p.start.z / scale))
        .collect()
}

#[test]
fn p1_constant_amount_single_edge_metric() {
    // G78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1 from X12 Z5 (G21, X on diameter).
    let job = read(&example("ab9-metric-p1.nc"));
    assert_eq!(job.geometry.side, Side::External);
    assert!(close(job.lead.lead, 1.5));
    let got = table(&job, 1.0);
    // d_n = D·√n until K (threading-notes §a.4: 0.350 0.495 0.606 0.700 0.783 0.857 0.920), then
    // the profile's one finishing pass at K.
    let mut want: Vec<f64> = (1..=6).map(|n| 0.35 * f64::from(n).sqrt()).collect();
    want.push(0.92);
    want.push(0.92);
    assert_eq!(got.len(), 8, "{got:?}");
    let t = tan_deg(30.0);
    for (i, (&(kind, d, z), w)) in got.iter().zip(&want).enumerate() {
        assert_eq!(
            kind,
            if i < 7 {
                PassKind::Rough
            } else {
                PassKind::Finish
            }
        );
        assert!(close(d, *w), "{got:?}");
        // One edge, A/2 = 30°: deeper passes move toward −Z; the full depth lands on Z5.
        assert!(close(z, 5.0 + (0.92 - w) * t), "{got:?}");
    }
    assert!((got[0].2 - 5.329_090).abs() < 1e-6);
    // The last pass reaches the programmed X and Z exactly; every pass returns to the start point.
    let path = toolpath::build(&job).unwrap();
    let last_cut = path
        .motions
        .iter()
        .rev()
        .find(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .unwrap();
    assert!(close(last_cut.to.x, 4.08) && close(last_cut.to.z, -20.0));
    for pair in path.motions.windows(2) {
        if matches!(pair[0].kind, MotionKind::Thread { .. }) {
            assert!(close(pair[1].to.x, 6.0), "straight out to the start X");
        }
    }
    assert_eq!(path.end(), job.start);
    assert!(path.motions.iter().all(|m| m.to.z >= -20.0 - EPS));
}

#[test]
fn p3_constant_depth_with_e_threads_per_inch() {
    // G78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3: E is threads per inch (AMP), always inch.
    let job = read(&example("ab9-inch-p3-e.nc"));
    assert!(close(job.lead.lead, IN / 13.0));
    let got = table(&job, IN);
    let want = [0.01, 0.02, 0.03, 0.04, 0.0472, 0.0472];
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (&(_, d, _), w) in got.iter().zip(want) {
        assert!(close(d, w), "{got:?}");
    }
    // E stays inch in a metric program: 13 TPI is 1.953846 mm.
    let metric = read("G21\nG90 G0 X15. Z5.\nG78 X10. Z-20. K1. D.3 E13 A60 P3\n");
    assert!(close(metric.lead.lead, IN / 13.0));
    // With the AMP set to inches per thread, E.0769 is a .0769" lead.
    let mut m = machine();
    m.ab9.as_mut().unwrap().e_word = EWord::InchesPerThread;
    let ipt = job_on(
        "G20\nG90 G0 X.6 Z.2\nG78 X.4056 Z-.75 K.0472 D.01 E.0769 A60 P3\n",
        &m,
    );
    assert!(close(ipt.lead.lead / IN, 0.0769));
}

#[test]
fn p2_and_p4_alternate_edges_about_the_final_pass() {
    // P4 (constant depth, alternating), taper I-.03: tests/../examples/ab9-taper-p4.nc.
    let job = read(&example("ab9-taper-p4.nc"));
    let got = table(&job, IN);
    let t = tan_deg(30.0);
    let depths = [0.015, 0.03, 0.045, 0.05, 0.05];
    assert_eq!(got.len(), 5);
    for (i, (&(_, d, z), w)) in got.iter().zip(depths).enumerate() {
        assert!(close(d, w));
        // Odd passes on the leading edge (behind the final pass), even ones mirrored ahead of it.
        let side = if i % 2 == 0 { 1.0 } else { -1.0 };
        let want = if i == 4 {
            0.25
        } else {
            0.25 + side * (0.05 - w) * t
        };
        assert!(close(z, want), "pass {}: {got:?}", i + 1);
    }
    // P2 is the same alternation on the constant-amount law.
    let p2 = read("G20\nG90 G0 X1.2 Z.25\nG78 X.9 Z-1. K.05 D.015 F.0833 A60 P2\n");
    let d: Vec<f64> = table(&p2, IN).iter().map(|r| r.1).collect();
    assert!(close(d[1], 0.015 * 2f64.sqrt()) && close(d[2], 0.015 * 3f64.sqrt()));
    assert!(table(&p2, IN)[1].2 < 0.25 && table(&p2, IN)[2].2 > 0.25);
}

#[test]
fn taper_i_is_the_radius_change_to_the_end_point() {
    // X.9 (diameter) is the root at the end; I-.03 (radius, always) puts the root at the start
    // at radius .42; the last pass runs from (.42, Z.25) to (.45, Z-1).
    let job = read(&example("ab9-taper-p4.nc"));
    let path = toolpath::build(&job).unwrap();
    let cuts: Vec<_> = path
        .motions
        .iter()
        .filter(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .collect();
    let last = cuts.last().unwrap();
    assert!(close(last.to.x / IN, 0.45) && close(last.to.z / IN, -1.0));
    let before_last = path
        .motions
        .iter()
        .rev()
        .skip_while(|m| !matches!(m.kind, MotionKind::Thread { .. }))
        .nth(1)
        .unwrap();
    assert!(close(before_last.to.x / IN, 0.42) && close(before_last.to.z / IN, 0.25));
    // Every pass is parallel to the root line: +.03 radius over 1.25 of Z.
    let mut from = path.start;
    for m in &path.motions {
        if matches!(m.kind, MotionKind::Thread { .. }) {
            let (dx, dz) = (m.to.x - from.x, m.to.z - from.z);
            assert!(close(dx / dz, 0.03 / -1.25));
        }
        from = m.to;
    }
}

#[test]
fn a0_is_a_plunge_infeed() {
    let job = read("G20\nG90 G0 X.6 Z.2\nG78 X.4056 Z-.75 K.0472 D.01 E13 P1\n");
    assert!(job
        .passes()
        .unwrap()
        .iter()
        .all(|p| close(p.start.z / IN, 0.2)));
    let p2 = read("G20\nG90 G0 X.6 Z.2\nG78 X.4056 Z-.75 K.0472 D.01 E13 A0 P2\n");
    assert_eq!(
        job.passes().unwrap(),
        p2.passes().unwrap(),
        "with A0, P1 ≡ P2"
    );
}

#[test]
fn minimum_cut_from_the_profile() {
    // K.1 D.005 P1: √n increments fall below the AMP minimum cut .001" after pass 6.
    let job = read("G20\nG90 G0 X1.2 Z.2\nG78 X.8 Z-1. K.1 D.005 F.05 A60 P1\n");
    let got: Vec<f64> = table(&job, IN).iter().map(|r| r.1).collect();
    let mut want = vec![];
    let mut prev: f64 = 0.0;
    for n in 1.. {
        let law = 0.005 * f64::from(n).sqrt();
        let d = if n == 1 { law } else { law.max(prev + 0.001) };
        if d >= 0.1 - 1e-12 {
            want.push(0.1);
            break;
        }
        want.push(d);
        prev = d;
    }
    want.push(0.1); // the finishing pass
    assert_eq!(got.len(), want.len());
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() < 1e-9, "{got:?}");
    }
    assert!(close(got[6] - got[5], 0.001), "pass 7 is the minimum cut");
}

#[test]
fn chamfer_pull_out_from_the_profile() {
    let mut m = machine();
    let p = m.ab9.as_mut().unwrap();
    p.chamfer_leads = 1.0;
    p.chamfer_angle_deg = 45.0;
    let job = job_on(&example("ab9-metric-p1.nc"), &m);
    let path = toolpath::build(&job).unwrap();
    let cuts: Vec<_> = path
        .motions
        .iter()
        .filter(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .collect();
    // Last pass: the pull-out starts one lead (1.5) before Z-20 and rises 1.5 at 45°.
    let n = cuts.len();
    assert!(close(cuts[n - 2].to.z, -18.5) && close(cuts[n - 2].to.x, 4.08));
    assert!(close(cuts[n - 1].to.z, -20.0) && close(cuts[n - 1].to.x, 5.58));
}

#[test]
fn incremental_words_and_radius_mode() {
    // G91: X and Z from the start point; a radius-mode profile reads X as a radius.
    let inc = read("G20\nG90 G0 X.6 Z.2\nG91\nG78 X-.1944 Z-.95 K.0472 D.01 E13 A60 P3\n");
    let abs = read(&example("ab9-inch-p3-e.nc"));
    assert!((inc.geometry.crest_end.x - abs.geometry.crest_end.x).abs() < 1e-9);
    assert!((inc.geometry.crest_end.z - abs.geometry.crest_end.z).abs() < 1e-9);
    let mut m = machine();
    m.diameter_x = false;
    let radius = job_on(
        "G20\nG90 G0 X.3 Z.2\nG78 X.2028 Z-.75 K.0472 D.01 E13 A60 P3\n",
        &m,
    );
    assert!((radius.geometry.crest_end.x - abs.geometry.crest_end.x).abs() < 1e-9);
}

#[test]
fn bad_inputs_are_errors_with_their_place() {
    let start = "G20\nG90 G0 X.6 Z.2\n";
    let cases: &[(&str, Code, u32, &str)] = &[
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E13 F.0769 A60 P3",
            Code::Conflict,
            34,
            "E and F",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 A60 P3",
            Code::MissingWord,
            1,
            "lead",
        ),
        (
            "G78 X.4056 Z-.75 D.01 E13 A60 P3",
            Code::MissingWord,
            1,
            "needs K",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 E13 A60 P3",
            Code::MissingWord,
            1,
            "needs D",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E13 A60",
            Code::MissingWord,
            1,
            "needs P",
        ),
        (
            "G78 Z-.75 K.0472 D.01 E13 A60 P3",
            Code::MissingWord,
            1,
            "needs X",
        ),
        (
            "G78 X.4056 K.0472 D.01 E13 A60 P3",
            Code::MissingWord,
            1,
            "needs Z",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E13 A121 P3",
            Code::OutOfRange,
            34,
            "0 to 120",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E13 A29.5 P3",
            Code::OutOfRange,
            34,
            "whole number",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E13 A60 P5",
            Code::OutOfRange,
            38,
            "1 to 4",
        ),
        (
            "G78 X.4056 Z-.75 K-.0472 D.01 E13 A60 P3",
            Code::OutOfRange,
            18,
            "unsigned",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D0 E13 A60 P3",
            Code::OutOfRange,
            25,
            "unsigned",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E0 A60 P3",
            Code::OutOfRange,
            30,
            "unsigned",
        ),
        (
            "G78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3 Q2",
            Code::Unsupported,
            41,
            "not a word",
        ),
        (
            "G0 G78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3",
            Code::Conflict,
            1,
            "shares",
        ),
        (
            "G78 X.4056 Z.2 K.0472 D.01 E13 A60 P3",
            Code::Geometry,
            1,
            "no length",
        ),
        (
            "G78 X.55 Z-.75 K.0472 D.01 E13 A60 P3",
            Code::Geometry,
            1,
            "inside the thread",
        ),
        ("G33 Z-.5 E13 F.1", Code::Conflict, 14, "E and F"),
    ];
    for &(cycle, code, column, text) in cases {
        let src = format!("{start}{cycle}\n");
        let e = error(&src);
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (code, 3, column),
            "{cycle}: {e}"
        );
        assert!(e.message.contains(text), "{cycle}: {}", e.message);
    }
    let e = error("G78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3\n");
    assert_eq!(e.code, Code::UnknownPosition);
}

fn run_cli(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_expand_passes_and_jsonl() {
    let file = path_of("ab9-metric-p1.nc");
    let out = run_cli(&["expand", "-c", "ab9", &file]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    // Allen-Bradley's own words: G0 and the single-pass G33 with F, X on diameter.
    assert!(
        text.contains("G0 X9.3 Z5.329\nG33 X9.3 Z-19.671 F1.5\nG0 X12. Z-19.671\n"),
        "{text}"
    );
    assert!(text.contains("G33 X8.16 Z-20. F1.5\n"), "{text}");
    assert!(text.ends_with("G00 X50. Z50.\n"), "{text}");
    assert_eq!(text.matches("G33 ").count(), 8);
    let out = run_cli(&["expand", "-c", "ab9", "--format", "jsonl", &file]);
    assert!(out.status.success());
    let threads = out
        .stdout
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice::<serde_json::Value>(l).unwrap())
        .filter(|v| v["kind"] == "thread")
        .count();
    assert_eq!(threads, 8);
    let out = run_cli(&["passes", "--json", "-c", "ab9", &file]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let cycle = &v["cycles"][0];
    assert_eq!(
        (cycle["controller"].as_str(), cycle["units"].as_str()),
        (Some("ab9"), Some("mm"))
    );
    let passes = cycle["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 8);
    assert!(
        close(passes[6]["x"].as_f64().unwrap(), 8.16),
        "X as programmed: diameter"
    );
    // An E-word program expands to F in the active units (inch here).
    let out = run_cli(&["expand", "-c", "ab9", &path_of("ab9-inch-p3-e.nc")]);
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("F0.07692\n") || text.contains("F.07692\n"),
        "{text}"
    );
}

#[test]
fn cli_bad_input_exits_2_with_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.nc");
    std::fs::write(
        &file,
        "G20\nG90 G0 X.6 Z.2\nG78 X.4056 Z-.75 K.0472 D.01 E13 F.0769 A60 P3\n",
    )
    .unwrap();
    for cmd in ["expand", "passes"] {
        let out = run_cli(&[cmd, "-c", "ab9", file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{cmd}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("3:34") && err.contains("E and F"),
            "{cmd}: {err}"
        );
    }
}
