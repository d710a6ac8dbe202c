//! OmniTurn G33 (seed 002): every worked example of the seed with its exact passes, the machine
//! limits, the controller's bad inputs, and the CLI.

use std::process::Command;

use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::Machine;
use threadcut::program::{self, Error};
use threadcut::thread::{tan_deg, Job, PassKind, Side};
use threadcut::toolpath::{self, MotionKind};

const IN: f64 = 25.4;
/// Comparisons in inches: far below the controller's .00005" resolution.
const EPS: f64 = 1e-9;

fn machine() -> Machine {
    Machine::built_in("omniturn").unwrap()
}

fn jobs(src: &str) -> Vec<Job> {
    program::jobs(src.as_bytes(), &machine()).unwrap_or_else(|e| panic!("{e}"))
}

fn job(src: &str) -> Job {
    let mut all = jobs(src);
    assert_eq!(all.len(), 1);
    all.remove(0)
}

fn example(name: &str) -> String {
    std::fs::read_to_string(format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn error(src: &str) -> Diagnostic {
    match program::jobs(src.as_bytes(), &machine()) {
        Err(Error::Input(d)) => d,
        Err(e) => panic!("not an input error: {e}"),
        Ok(_) => panic!("accepted: {src}"),
    }
}

fn warnings(src: &str) -> Vec<Diagnostic> {
    program::run(src.as_bytes(), &machine(), |_, _| Ok(()))
        .unwrap()
        .warnings
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < EPS
}

/// (depth, x radius, z) of each pass in inches.
fn table(job: &Job) -> Vec<(f64, f64, f64)> {
    job.passes()
        .unwrap()
        .iter()
        .map(|p| (p.depth / IN, p.start.x / IN, p.start.z / IN))
        .collect()
}

/// The seed's law: the first pass at the start, then depth I·√(n−1), clipped to the final X.
fn expected_depths(i: f64, total: f64) -> Vec<f64> {
    let mut d = vec![0.0];
    for k in 1.. {
        let next = i * f64::from(k).sqrt();
        if next >= total - 1e-12 {
            d.push(total);
            break;
        }
        d.push(next);
    }
    d
}

#[test]
fn external_example_passes_retract_and_pull_out() {
    // T4F200 / X0Z.2 / X.237 / G33X.212Z-.5I.012K.05PC (radius mode, G73).
    let job = job(&example("omniturn-external.nc"));
    assert_eq!(job.geometry.side, Side::External);
    assert!(close(job.lead.lead / IN, 0.05));
    let t = tan_deg(29.0);
    let got = table(&job);
    let depths = [
        0.0,
        0.012,
        0.012 * 2f64.sqrt(),
        0.012 * 3f64.sqrt(),
        0.024,
        0.025,
    ];
    assert_eq!(got.len(), 6, "{got:?}");
    for (&(d, x, z), want) in got.iter().zip(depths) {
        assert!(close(d, want), "{got:?}");
        assert!(close(x, 0.237 - want), "{got:?}");
        // C: deeper passes start further along the cut (toward −Z), by depth·tan 29°.
        assert!(close(z, 0.2 - want * t), "{got:?}");
    }
    // Hand values: pass 3 at X.220029 Z.190593, the last at X.212 Z.186142.
    assert!((got[2].1 - 0.220_029).abs() < 5e-7 && (got[2].2 - 0.190_593).abs() < 5e-7);
    assert!((got[5].2 - 0.186_142).abs() < 5e-7);
    // Retract to start X + 3·I = .273; P pulls out from Z-.5 as far beyond Z as X travels.
    assert!(close(job.retract.x / IN, 0.273));
    let path = toolpath::build(&job).unwrap();
    let threads: Vec<_> = path
        .motions
        .iter()
        .filter(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .collect();
    assert_eq!(threads.len(), 12);
    for (pass, pair) in threads.chunks(2).enumerate() {
        let (cut, pull) = (pair[0].to, pair[1].to);
        assert!(close(cut.z / IN, -0.5), "pass {} ends at Z-.5", pass + 1);
        let x_travel = 0.273 - cut.x / IN;
        assert!(close(pull.x / IN, 0.273));
        assert!(close(pull.z / IN, -0.5 - x_travel), "pass {}", pass + 1);
    }
    // Every pass goes back to the same retract point; the cycle ends at the start point.
    let back: Vec<_> = path
        .motions
        .iter()
        .filter(|m| m.kind == MotionKind::Rapid && close(m.to.z / IN, 0.2) && m.to.x > 0.25 * IN)
        .collect();
    assert_eq!(back.len(), 6);
    assert_eq!(path.end(), job.start);
    // No pass goes past the final X.
    assert!(path.motions.iter().all(|m| m.to.x / IN >= 0.212 - EPS));
}

#[test]
fn internal_example_cuts_outward() {
    // T8 / X.4375Z.2 / X.4425 / G33X.46875Z-.75I.01K.05C: 15/16-20 internal, .005" first cut.
    let job = job(&example("omniturn-internal.nc"));
    assert_eq!(job.geometry.side, Side::Internal);
    let got = table(&job);
    let want = expected_depths(0.01, 0.02625);
    assert_eq!(got.len(), 8);
    assert_eq!(want.len(), 8);
    let t = tan_deg(29.0);
    for (&(d, x, z), w) in got.iter().zip(&want) {
        assert!(
            close(d, *w) && close(x, 0.4425 + w) && close(z, 0.2 - w * t),
            "{got:?}"
        );
    }
    assert!(close(got[7].1, 0.46875));
    // Retract inward (away from the bore wall): .4425 − 3·.01.
    assert!(close(job.retract.x / IN, 0.4125));
    // No P: each pass ends at Z-.75 and leaves straight (rapid) to the retract X.
    let path = toolpath::build(&job).unwrap();
    let mut last_thread = None;
    for m in &path.motions {
        match m.kind {
            MotionKind::Thread { .. } => {
                assert!(close(m.to.z / IN, -0.75));
                last_thread = Some(m.to);
            }
            MotionKind::Rapid => {
                if let Some(end) = last_thread.take() {
                    assert!(close(m.to.z, end.z) && close(m.to.x / IN, 0.4125));
                }
            }
            MotionKind::Feed | MotionKind::Arc { .. } => panic!("no feed moves in G33"),
        }
    }
    assert!(path.motions.iter().all(|m| m.to.x / IN <= 0.46875 + EPS));
}

#[test]
fn clean_up_pass_with_o_retraces_the_last_pass() {
    // G33X.212Z-.5I.008K.05PCO from the same start: one pass at the finished depth.
    let single = job(&example("omniturn-cleanup.nc"));
    let passes = single.passes().unwrap();
    assert_eq!(passes.len(), 1);
    assert_eq!(passes[0].kind, PassKind::Finish);
    let full = job(&example("omniturn-external.nc"));
    let last = *full.passes().unwrap().last().unwrap();
    // Same start point, same C and P: the same helix, at the same place.
    assert!(close(passes[0].start.x, last.start.x) && close(passes[0].start.z, last.start.z));
    assert!(close(passes[0].start.z / IN, 0.2 - 0.025 * tan_deg(29.0)));
    // It pulls out to 3 × its own I: .237 + .024 = .261, running .049 beyond Z.
    let path = toolpath::build(&single).unwrap();
    let kinds: Vec<_> = path.motions.iter().map(|m| m.kind).collect();
    assert_eq!(kinds.len(), 5, "{:?}", path.motions);
    let pull = path.motions[2].to;
    assert!(close(pull.x / IN, 0.261) && close(pull.z / IN, -0.549));
    assert_eq!(path.end(), single.start);
}

#[test]
fn three_start_example_shifts_each_start_by_lead_over_three() {
    let all = jobs(&example("omniturn-three-start.nc"));
    assert_eq!(all.len(), 3);
    let want = expected_depths(0.01, 0.035);
    assert_eq!(want.len(), 14);
    for (s, job) in all.iter().enumerate() {
        assert!(close(job.lead.lead / IN, 0.15));
        assert_eq!(job.lead.starts, 1, "each start is its own G33");
        let z0 = 0.2 + 0.05 * s as f64;
        assert!(close(job.start.z / IN, z0));
        let got = table(job);
        assert_eq!(got.len(), 14);
        for (&(d, x, z), w) in got.iter().zip(&want) {
            assert!(
                close(d, *w) && close(x, 0.247 - w) && close(z, z0),
                "{got:?}"
            );
        }
        // P: the last pass pulls out from X.212 to .247 + .03 = .277, .065 beyond Z-.5.
        let path = toolpath::build(job).unwrap();
        let pull = path
            .motions
            .iter()
            .rev()
            .find(|m| matches!(m.kind, MotionKind::Thread { .. }))
            .unwrap();
        assert!(close(pull.to.x / IN, 0.277) && close(pull.to.z / IN, -0.565));
    }
    // The spacing is lead / starts.
    let spacing = (all[1].start.z - all[0].start.z) / IN;
    assert!(close(spacing, 0.15 / 3.0));
}

#[test]
fn taper_example_in_diameter_mode() {
    // G72: X, I and A are diameters. X.415 → X.365, I.005 (.0025 radius), A.035 over Z.2 → Z-.5.
    let job = job(&example("omniturn-taper.nc"));
    let got = table(&job);
    let want = expected_depths(0.0025, 0.025);
    assert_eq!(want.len(), 101);
    assert_eq!(got.len(), 101);
    for (&(d, x, z), w) in got.iter().zip(&want) {
        assert!(
            close(d, *w) && close(x, 0.2075 - w) && close(z, 0.2),
            "{got:?}"
        );
    }
    // A is the X travel over the whole Z travel, approach included: +.0175 radius.
    assert!(close(
        job.geometry.crest_end.x / IN - job.geometry.crest_start.x / IN,
        0.0175
    ));
    let path = toolpath::build(&job).unwrap();
    let first_cut = path
        .motions
        .iter()
        .find(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .unwrap();
    assert!(close(first_cut.to.x / IN, 0.225) && close(first_cut.to.z / IN, -0.5));
    // The taper climbs toward the end: the retract there keeps its 3·I clearance (.2325), then
    // the tool returns along Z and steps in to the retract point .215 at the start.
    let after: Vec<_> = path.motions[2..5]
        .iter()
        .map(|m| (m.to.x / IN, m.to.z / IN))
        .collect();
    let want = [(0.2325, -0.5), (0.2325, 0.2), (0.215, 0.2)];
    for (g, w) in after.iter().zip(want) {
        assert!(close(g.0, w.0) && close(g.1, w.1), "{after:?}");
    }
    // The pass table writes X as the program does: diameters in G72.
    let out = run_cli(&[
        "passes",
        "--json",
        "-c",
        "omniturn",
        &path_of("omniturn-taper.nc"),
    ]);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let x0 = v["cycles"][0]["passes"][0]["x"].as_f64().unwrap();
    assert!(close(x0, 0.415));
}

#[test]
fn four_start_example_in_g35() {
    let all = jobs(&example("omniturn-four-start-g35.nc"));
    assert_eq!(all.len(), 4);
    let want = expected_depths(0.01, 0.05);
    assert_eq!(want.len(), 26, "0.01·√25 lands exactly on .05");
    let t = tan_deg(29.0);
    for (s, job) in all.iter().enumerate() {
        assert!(close(job.lead.lead / IN, 0.4));
        let z0 = 0.2 + 0.1 * s as f64;
        assert!(close(job.start.z / IN, z0) && close(job.start.x / IN, 0.5));
        let got = table(job);
        assert_eq!(got.len(), 26);
        for (&(d, x, z), w) in got.iter().zip(&want) {
            assert!(
                close(d, *w) && close(x, 0.5 - w) && close(z, z0 - w * t),
                "{got:?}"
            );
        }
    }
    // The same cycle without G35 is refused, naming the mode to use.
    let e = error("X.5Z.2\nG33X.45Z-.75I.01K.4C\n");
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::OutOfRange, 2, 17)
    );
    assert!(e.message.contains("normal feed mode"), "{}", e.message);
    assert!(e
        .hint
        .as_deref()
        .unwrap()
        .contains("G35 on a line by itself"));
}

#[test]
fn lead_limits_name_the_mode_to_use() {
    let e = error("X.5Z.2\nG35\nG92X.5Z.2\nG33X.45Z-.75I.01K1.5\n");
    assert_eq!((e.code, e.span.line), (Code::OutOfRange, 4));
    assert!(e.message.contains("of G35"), "{}", e.message);
    assert!(e.hint.unwrap().contains("G35F2"));
    // G35F2 accepts it; its resolution is .0005".
    let ok = jobs("X.5Z.2\nG35F2\nG92X.5Z.2\nG33X.45Z-.75I.01K1.5\n");
    assert!(close(ok[0].lead.lead / IN, 1.5));
    let e = error("X.5Z.2\nG35F2\nG92X.5Z.2\nG33X.45Z-.75I.01K2.5\n");
    assert!(e.hint.unwrap().contains("no OmniTurn feed mode"));
    // Back in the normal mode after G36, .2" is the limit again.
    let e = error("X.5Z.2\nG35\nG92X.5Z.2\nG36\nG92X.5Z.2\nG33X.45Z-.75I.01K.25\n");
    assert_eq!(e.span.line, 6);
}

#[test]
fn coarse_mode_lines_follow_the_seed_format() {
    // G35 must be alone on its line.
    let e = error("X.5Z.2\nG35 X1\n");
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Conflict, 2, 5));
    // The following line must be G92 X Z …
    let e = error("X.5Z.2\nG35\nG33X.45Z-.75I.01K.4\n");
    assert_eq!((e.code, e.span.line), (Code::MissingWord, 3));
    // … with the current coordinates.
    let e = error("X.5Z.2\nG35\nG92X.5Z.25\n");
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Conflict, 3, 7));
    // G36 only where G35 was used.
    let e = error("X.5Z.2\nG35\nG92X.5Z.2\nX.5Z.3\nG36\n");
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Geometry, 5, 1));
    // Only G35 and G35F2 exist.
    let e = error("X.5Z.2\nG35F3\n");
    assert_eq!((e.code, e.span.column), (Code::OutOfRange, 4));
}

#[test]
fn bad_cycle_words_are_errors_with_their_place() {
    let cases: &[(&str, Code, u32, &str)] = &[
        (
            "X.237Z.2\nG33X.212Z-.5K.05\n",
            Code::MissingWord,
            1,
            "needs I",
        ),
        (
            "X.237Z.2\nG33X.212Z-.5I.01\n",
            Code::MissingWord,
            1,
            "needs K",
        ),
        (
            "X.237Z.2\nG33Z-.5I.01K.05\n",
            Code::MissingWord,
            1,
            "needs X",
        ),
        (
            "X.237Z.2\nG33X.212I.01K.05\n",
            Code::MissingWord,
            1,
            "needs Z",
        ),
        (
            "X.237Z.2\nG33X.212Z-.5I0K.05\n",
            Code::OutOfRange,
            13,
            "positive",
        ),
        (
            "X.237Z.2\nG33X.212Z-.5I.01K.05C31\n",
            Code::OutOfRange,
            21,
            "0 to 30",
        ),
        (
            "X.237Z.2\nG33X.212Z-.5I.01K.05P1\n",
            Code::Syntax,
            21,
            "flag",
        ),
        (
            "X.237Z.2\nG33X.212Z-.5I.01K.05 Q2\n",
            Code::Unsupported,
            22,
            "not a word",
        ),
        (
            "X.237Z.2\nG33X.237Z-.5I.01K.05\n",
            Code::Geometry,
            4,
            "equals the start X",
        ),
        (
            "G33X.212Z-.5I.01K.05\n",
            Code::UnknownPosition,
            1,
            "not known",
        ),
        ("G21\n", Code::Unsupported, 1, "inch"),
        (
            "X.237Z.2\nG33X.212Z-.5I.01K.05A.8\n",
            Code::Geometry,
            1,
            "taper",
        ),
    ];
    for &(src, code, column, text) in cases {
        let e = error(src);
        assert_eq!((e.code, e.span.column), (code, column), "{src}: {e}");
        assert!(e.message.contains(text), "{src}: {}", e.message);
    }
}

#[test]
fn machine_limits_are_warnings() {
    // S × K above the slide's 300 ipm.
    let w = warnings("S2000\nX.237Z.2\nG33X.212Z-.5I.012K.2\n");
    assert_eq!(w.len(), 1, "{w:?}");
    assert_eq!(
        (w[0].code, w[0].span.line, w[0].span.column),
        (Code::MachineLimit, 3, 18)
    );
    assert!(w[0].message.contains("= 400.0 ipm"), "{}", w[0].message);
    assert!(w[0].hint.as_deref().unwrap().contains("S1500"));
    assert!(warnings("S1500\nX.237Z.2\nG33X.212Z-.5I.012K.2\n").is_empty());
    // Too little run-up in front of the face (Z0).
    let w = warnings("X.237Z.05\nG33X.212Z-.5I.012K.05\n");
    assert_eq!((w.len(), w[0].code), (1, Code::MachineLimit));
    assert!(w[0].message.contains("0.05\""), "{}", w[0].message);
    // Every seed example is inside both limits.
    for f in [
        "external",
        "internal",
        "cleanup",
        "three-start",
        "taper",
        "four-start-g35",
    ] {
        assert!(
            warnings(&example(&format!("omniturn-{f}.nc"))).is_empty(),
            "{f}"
        );
    }
}

#[test]
fn expansion_as_single_passes_reproduces_every_thread_move() {
    let m = machine();
    for f in [
        "external",
        "internal",
        "cleanup",
        "three-start",
        "taper",
        "four-start-g35",
    ] {
        let src = example(&format!("omniturn-{f}.nc"));
        let mut out = Vec::new();
        program::expand_gcode(src.as_bytes(), &mut out, &m).unwrap();
        let text = String::from_utf8(out).unwrap();
        // Read the expansion back: its thread moves are the original's, to the output resolution.
        let threads = |jobs: &[Job]| -> Vec<(f64, f64)> {
            jobs.iter()
                .flat_map(|j| toolpath::build(j).unwrap().motions)
                .filter(|m| matches!(m.kind, MotionKind::Thread { .. }))
                .map(|m| (m.to.x / IN, m.to.z / IN))
                .collect()
        };
        let before = threads(&jobs(&src));
        let after = threads(&jobs(&text));
        assert_eq!(before.len(), after.len(), "{f}:\n{text}");
        let resolution = if f.contains("g35") { 0.00025 } else { 0.00005 };
        for (a, b) in before.iter().zip(&after) {
            // X is rounded once to the resolution; C and P carry that rounding into Z.
            assert!(
                (a.0 - b.0).abs() <= resolution && (a.1 - b.1).abs() <= resolution,
                "{f}: {a:?} vs {b:?}\n{text}"
            );
        }
        // Non-cycle lines pass through unchanged.
        for line in src.lines().filter(|l| !l.contains("G33")) {
            assert!(text.lines().any(|o| o == line), "{f}: {line}");
        }
    }
}

fn path_of(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn run_cli(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_expand_passes_and_jsonl() {
    let file = path_of("omniturn-external.nc");
    let out = run_cli(&["expand", "-c", "omniturn", &file]);
    assert!(out.status.success());
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(
        text.contains("G33 X0.225 Z-0.5 I0.012 K0.05 C29. P\n"),
        "{text}"
    );
    assert!(
        text.contains("G33 X0.22005 Z-0.5 I0.012 K0.05 C29. P O\n"),
        "{text}"
    );
    let out = run_cli(&["expand", "-c", "omniturn", "--format", "jsonl", &file]);
    assert!(out.status.success());
    let lines: Vec<serde_json::Value> = out
        .stdout
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect();
    assert_eq!(lines.iter().filter(|v| v["kind"] == "thread").count(), 12);
    let out = run_cli(&["passes", "--json", "-c", "omniturn", &file]);
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let cycle = &v["cycles"][0];
    assert_eq!(cycle["controller"], "omniturn");
    assert_eq!(cycle["units"], "inch");
    let passes = cycle["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 6);
    for key in ["n", "kind", "depth", "increment", "x", "z", "area", "share"] {
        assert!(passes[0].get(key).is_some(), "{key}");
    }
}

#[test]
fn cli_bad_input_exits_2_with_line_and_column() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("bad.nc");
    std::fs::write(&file, "X.5Z.2\nG33X.45Z-.75I.01K.4C\n").unwrap();
    for cmd in ["expand", "passes"] {
        let out = run_cli(&[cmd, "-c", "omniturn", file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{cmd}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains("2:17"), "{cmd}: {err}");
        assert!(err.contains("G35"), "{cmd}: {err}");
    }
}

#[test]
fn g73_radius_mode_at_power_on_and_g72_switches_x_i_and_a() {
    // No G72/G73 written: X.237 is a radius (the seed's multi-start program relies on it).
    let radius = job("X0Z.2\nX.237\nG33X.212Z-.5I.012K.05A.01\n");
    assert!(close(radius.start.x / IN, 0.237));
    // The same cycle in G72: every X amount doubles, the job is the same.
    let diameter = job("G72\nX0Z.2\nX.474\nG33X.424Z-.5I.024K.05A.02\n");
    assert_eq!(table(&radius), table(&diameter));
    assert!(close(diameter.retract.x / IN, 0.273));
    let taper = |j: &Job| (j.geometry.crest_end.x - j.geometry.crest_start.x) / IN;
    assert!(close(taper(&radius), 0.01) && close(taper(&diameter), 0.01));
    // G73 switches back, modally.
    let back = jobs("G72\nX0Z.2\nX.474\nG73\nX.237\nG33X.212Z-.5I.012K.05A.01\n");
    assert_eq!(table(&back[0]), table(&radius));
    // The expansion writes X and I in the mode of the cycle.
    let mut out = Vec::new();
    program::expand_gcode(
        "G72\nX0Z.2\nX.474\nG33X.424Z-.5I.024K.05\n".as_bytes(),
        &mut out,
        &machine(),
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("G33 X0.45 Z-0.5 I0.024 K0.05\n"), "{text}");
}
