//! `threadcut mill`: TB029's numbers and direction table, exact absolute Z, and reading the written
//! program back to check that it reproduces the helix.

use std::process::Command;

use threadcut::mill::readback::{self, SegKind, Segment};
use threadcut::mill::Side;
use threadcut::mill::{self, profile::FeedReference, Comp, Direction, Hand, LeadIn, MillSpec};
use threadcut::thread::standard;

fn run(args: &[&str]) -> (String, String, i32) {
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .arg("mill")
        .args(args)
        .output()
        .expect("the binary runs");
    (
        String::from_utf8(out.stdout).unwrap(),
        String::from_utf8(out.stderr).unwrap(),
        out.status.code().unwrap_or(-1),
    )
}

fn ok(args: &[&str]) -> String {
    let (out, err, code) = run(args);
    assert_eq!(code, 0, "threadcut mill {args:?} failed: {err}");
    out
}

fn arcs(segs: &[Segment]) -> Vec<Segment> {
    segs.iter()
        .copied()
        .filter(|s| matches!(s.kind, SegKind::Arc { .. }))
        .collect()
}

/// The full 360° arcs (helix turns) of a program.
fn turns(segs: &[Segment]) -> Vec<Segment> {
    arcs(segs)
        .into_iter()
        .filter(|s| s.from[0] == s.to[0] && s.from[1] == s.to[1])
        .collect()
}

/// TB029 internal example: "an internal thread with a one-inch diameter has a major diameter of
/// 1.0000". Any move to a point 0.5000" from the center point is acceptable." With compensation on,
/// the program is the thread contour: every turn runs at radius 0.5000 about the centre.
#[test]
fn seed_internal_one_inch_major() {
    let out = ok(&[
        "--thread",
        "1-8 UNC",
        "--internal",
        "--length",
        "0.5",
        "--tool-diameter",
        "0.5",
        "--feed",
        "10",
        "-c",
        "centroid",
        "--d-register",
        "1",
        "--center",
        "2,3",
    ]);
    let p = readback::read(&out).unwrap();
    assert_eq!(p.units, Some(threadcut::units::Units::Inch));
    let t = turns(&p.segments);
    assert_eq!(
        t.len(),
        4,
        "0.5 in × 8 threads per inch = 4 turns (TB029 step 6)"
    );
    for s in &t {
        let (r0, r1) = s.radii().unwrap();
        assert!((r0 - 0.5).abs() < 1e-9 && (r1 - 0.5).abs() < 1e-9, "{s:?}");
        assert_eq!(
            s.kind,
            SegKind::Arc {
                center: [2.0, 3.0],
                cw: false
            }
        );
    }
    assert!(out.contains("G3 X2.5 Y3. Z-0.375 I-0.5 J0."), "{out}");
}

/// TB029 external example: 1"-8 has a minor diameter of 0.8492"; the start point is 0.4246" from
/// the centre.
#[test]
fn seed_external_minor_radius() {
    let out = ok(&[
        "--thread",
        "1-8 UNC",
        "--external",
        "--length",
        "0.75",
        "--tool-diameter",
        "0.75",
        "--feed",
        "12",
        "-c",
        "centroid",
        "--d-register",
        "3",
        "--lead",
        "radial",
    ]);
    let p = readback::read(&out).unwrap();
    let t = turns(&p.segments);
    assert_eq!(t.len(), 6);
    for s in &t {
        let (r, _) = s.radii().unwrap();
        assert!((r - 0.4246).abs() < 1e-9, "radius {r}");
    }
    // TB029 step 4: a straight one-axis move (not an arc) to the start point, compensation on.
    let entry = p
        .segments
        .iter()
        .find(|s| s.comp.is_some())
        .expect("a compensated move");
    assert_eq!(entry.kind, SegKind::Feed);
    assert_eq!(entry.from[1], entry.to[1], "one axis: Y unchanged");
    assert_eq!(entry.from[2], entry.to[2], "one axis: Z unchanged");
    assert_eq!(entry.to[0], 0.4246);
    // TB029 external step 1: the approach point is at least half a tool diameter clear of the
    // 0.9980" cylinder.
    let approach = p.segments[0].to;
    assert!(approach[0] - 0.998 / 2.0 >= 0.75 / 2.0, "{approach:?}");
}

/// TB029's table for right-hand threads and tip 4 for left-hand ones.
#[test]
fn direction_and_compensation_table() {
    // (side, left-hand, direction, expected arc, expected compensation)
    let table = [
        ("--internal", false, "--bottom-up", "G3", "G41"),
        ("--internal", false, "--top-down", "G2", "G42"),
        ("--external", false, "--bottom-up", "G3", "G42"),
        ("--external", false, "--top-down", "G2", "G41"),
        ("--internal", true, "--bottom-up", "G2", "G42"),
        ("--internal", true, "--top-down", "G3", "G41"),
        ("--external", true, "--bottom-up", "G2", "G41"),
        ("--external", true, "--top-down", "G3", "G42"),
    ];
    for (side, left, dir, arc, comp) in table {
        let mut args = vec![
            "--thread",
            "M12",
            side,
            dir,
            "--length",
            "10",
            "--tool-diameter",
            "8",
            "--feed",
            "200",
            "-c",
            "fanuc-mill",
            "--d-register",
            "7",
        ];
        if left {
            args.push("--left");
        }
        let out = ok(&args);
        let p = readback::read(&out).unwrap();
        let t = turns(&p.segments);
        assert!(!t.is_empty());
        let want_cw = arc == "G2";
        for s in &t {
            let SegKind::Arc { cw, .. } = s.kind else {
                unreachable!()
            };
            assert_eq!(cw, want_cw, "{side} left={left} {dir}: helix arc");
            let want = if comp == "G41" {
                mill::CompSide::Left
            } else {
                mill::CompSide::Right
            };
            assert_eq!(s.comp, Some(want), "{side} left={left} {dir}: compensation");
            // Each turn rises (bottom-up) or falls (top-down) one pitch.
            let dz = s.to[2] - s.from[2];
            let want_dz = if dir == "--bottom-up" { 1.75 } else { -1.75 };
            assert!((dz - want_dz).abs() < 1e-9, "{side} {dir}: dz {dz}");
            // The helix's hand: counter-clockwise while rising is right-handed.
            let right_handed = cw != (dz > 0.0);
            assert_eq!(right_handed, !left, "{side} left={left} {dir}: hand");
        }
        assert!(out.contains(&format!("{comp} D7 G1")), "{out}");
    }
}

/// TB029 tip 1: with a pitch of more than four decimals, every turn's Z is computed from the exact
/// pitch and rounded once. 1/4-28 UNF: P = 0.0357142857… in; 200 turns.
#[test]
fn absolute_z_does_not_drift_over_200_turns() {
    let p_in = 1.0 / 28.0;
    let length = format!("{}", 200.0 * p_in);
    let out = ok(&[
        "--thread",
        "1/4-28 UNF",
        "--internal",
        "--bottom-up",
        "--length",
        &length,
        "--tool-diameter",
        "0.15",
        "--feed",
        "8",
        "-c",
        "centroid",
        "--d-register",
        "1",
        "--start-z",
        "0",
    ]);
    let p = readback::read(&out).unwrap();
    let t = turns(&p.segments);
    assert_eq!(t.len(), 200);
    let bottom = -200.0 * p_in;
    for (k, s) in t.iter().enumerate() {
        let exact = bottom + (k + 1) as f64 * p_in;
        let written = s.to[2];
        assert!(
            (written - exact).abs() <= 0.00005 + 1e-12,
            "turn {}: Z {written} vs exact {exact}",
            k + 1
        );
        assert_eq!(written, (exact * 1e4).round() / 1e4, "turn {}", k + 1);
    }
    // Accumulating the pitch rounded to four digits (0.0357) would end 0.0029" low: the test can
    // tell the two apart.
    let accumulated = (bottom * 1e4).round() / 1e4 + 200.0 * 0.0357;
    assert!((t[199].to[2] - accumulated).abs() > 0.002);
    assert_eq!(t[199].to[2], 0.0);
}

/// Reading the program back reproduces the helix: centre, radius, one pitch per 360°, the lead arcs
/// tangent to it and in phase with it, and the compensated contour equal to the tool-centre path
/// offset by the tool radius.
#[test]
fn read_back_reproduces_the_helix() {
    let common = [
        "--thread",
        "M16",
        "--internal",
        "--length",
        "20",
        "--tool-diameter",
        "10",
        "--feed",
        "250",
        "-c",
        "linuxcnc-mill",
        "--center",
        "40,-25",
        "--start-z",
        "-3",
    ];
    let mut a = common.to_vec();
    a.extend(["--comp", "none"]);
    let centre_path = readback::read(&ok(&a)).unwrap();
    let contour = readback::read(&ok(&common)).unwrap();
    let tool_r = 5.0;
    let tc = turns(&centre_path.segments);
    let ct = turns(&contour.segments);
    assert_eq!(tc.len(), 10, "20 mm / 2 mm pitch");
    assert_eq!(tc.len(), ct.len());
    let major = standard::lookup("M16-6H")
        .unwrap()
        .internal
        .unwrap()
        .major
        .min
        .unwrap();
    for (c, k) in tc.iter().zip(&ct) {
        let SegKind::Arc { center, .. } = c.kind else {
            unreachable!()
        };
        assert_eq!(center, [40.0, -25.0]);
        let (rc, _) = c.radii().unwrap();
        let (rk, _) = k.radii().unwrap();
        assert!((rk - major / 2.0).abs() < 5e-5, "contour radius {rk}");
        assert!(
            (rc - (rk - tool_r)).abs() < 5e-5,
            "centre {rc} = contour {rk} − tool radius"
        );
        assert!((c.sweep().unwrap() - std::f64::consts::TAU).abs() < 1e-12);
        assert!((c.to[2] - c.from[2] - 2.0).abs() < 1e-9);
        assert_eq!(c.to[2], k.to[2]);
        assert_eq!(c.comp, None);
    }
    // The helix starts at the thread bottom (bottom-up, climb) and ends at the top.
    assert_eq!(tc[0].from[2], -23.0);
    assert_eq!(tc[9].to[2], -3.0);
    // Lead-in: an arc ending where the helix starts, tangent to it, climbing 1/8 pitch over the
    // 45° it covers about the thread axis (its start is at −45°).
    let all = arcs(&centre_path.segments);
    let lead_in = all[0];
    assert_eq!(lead_in.to, tc[0].from);
    let SegKind::Arc { center: m, cw } = lead_in.kind else {
        unreachable!()
    };
    assert!(!cw);
    // Tangent at the joint: the lead arc's radius vector at its end is parallel to the helix's.
    let v1 = [lead_in.to[0] - m[0], lead_in.to[1] - m[1]];
    let v2 = [lead_in.to[0] - 40.0, lead_in.to[1] + 25.0];
    assert!((v1[0] * v2[1] - v1[1] * v2[0]).abs() < 1e-3, "tangent");
    let angle = (lead_in.from[1] + 25.0).atan2(lead_in.from[0] - 40.0);
    assert!(
        (angle + std::f64::consts::FRAC_PI_4).abs() < 1e-3,
        "start at −45°: {angle}"
    );
    assert!(
        (lead_in.to[2] - lead_in.from[2] - 0.25).abs() < 1e-3,
        "rises P/8"
    );
    // The entry to the lead arc is a straight radial move from the centre (in phase at every
    // point), the exit a straight move back to it.
    let entry = centre_path
        .segments
        .iter()
        .find(|s| s.to == lead_in.from && s.kind == SegKind::Feed)
        .unwrap();
    assert_eq!([entry.from[0], entry.from[1]], [40.0, -25.0]);
}

/// Arc-feed compensation: the edge feed F becomes F·(D − d)/D on an internal helix and F·(D + d)/D
/// on an external one (D: the diameter the edge cuts, d: the tool).
#[test]
fn arc_feed_compensation() {
    let out = ok(&[
        "--thread",
        "M10",
        "--internal",
        "--length",
        "6",
        "--tool-diameter",
        "7",
        "--feed",
        "300",
        "-c",
        "fanuc-mill",
        "--d-register",
        "1",
    ]);
    // 300 · (10 − 7)/10 = 90.
    let p = readback::read(&out).unwrap();
    assert!(
        turns(&p.segments).iter().all(|s| s.feed == Some(90.0)),
        "{out}"
    );
    let out = ok(&[
        "--thread",
        "M10",
        "--external",
        "--length",
        "6",
        "--tool-diameter",
        "7",
        "--feed",
        "300",
        "-c",
        "fanuc-mill",
        "--comp",
        "none",
    ]);
    // Minor diameter (d3 max) 8.128: 300 · (8.128 + 7)/8.128 = 558.37.
    let p = readback::read(&out).unwrap();
    for s in turns(&p.segments) {
        assert!(
            (s.feed.unwrap() - 300.0 * 15.128 / 8.128).abs() < 0.06,
            "{:?}",
            s.feed
        );
    }
    // Straight moves keep the requested feed.
    assert!(p
        .segments
        .iter()
        .filter(|s| s.kind == SegKind::Feed)
        .all(|s| s.feed == Some(300.0)));
}

fn spec(side: Side, teeth: u32, passes: u32) -> MillSpec {
    MillSpec {
        thread: standard::lookup("M20").unwrap(),
        side,
        hand: Hand::Right,
        length: 15.0,
        tool_diameter: 12.0,
        teeth,
        direction: None,
        passes,
        starts: 1,
        comp: Comp::Off,
        center: (0.0, 0.0),
        start_z: 0.0,
        clearance: 5.0,
        feed: 400.0,
        lead_in: LeadIn::Arc,
        comp_feed: FeedReference::Centre,
    }
}

/// Constant-area passes: (R_k − R_crest)² grows by the same amount each pass and the last pass
/// reaches the finished diameter.
#[test]
fn passes_remove_equal_areas() {
    for side in [Side::Internal, Side::External] {
        let plan = mill::plan(&spec(side, 1, 5)).unwrap();
        let h: Vec<f64> = plan
            .pass_radii
            .iter()
            .map(|r| (r - plan.crest_radius).abs())
            .collect();
        let total = (plan.final_radius - plan.crest_radius).abs();
        for (k, d) in h.iter().enumerate() {
            let want = total * ((k + 1) as f64 / 5.0).sqrt();
            assert!((d - want).abs() < 1e-12, "{side:?} pass {}", k + 1);
        }
        assert_eq!(*plan.pass_radii.last().unwrap(), plan.final_radius);
        // Every pass makes the same number of turns about the same axis.
        let per_pass = plan
            .moves
            .iter()
            .filter(|m| {
                matches!(
                    m.kind,
                    mill::MoveKind::Arc {
                        center: (0.0, 0.0),
                        ..
                    }
                )
            })
            .count();
        assert_eq!(per_pass, 5 * plan.turns as usize);
    }
}

/// A tool with N teeth one pitch apart cuts N pitches per turn: ⌈(L − (N − 1)·P)/P⌉ turns.
#[test]
fn multi_tooth_tools_need_fewer_turns() {
    let p = 2.5; // M20
    for (teeth, want) in [(1, 6), (3, 4), (4, 3), (6, 1), (9, 1)] {
        let plan = mill::plan(&spec(Side::Internal, teeth, 1)).unwrap();
        assert_eq!(plan.turns, want, "{teeth} teeth");
        let covered = f64::from(teeth - 1) * p + f64::from(plan.turns) * p;
        assert!(covered >= 15.0 - 1e-9);
    }
    let plan = mill::plan(&spec(Side::Internal, 9, 1)).unwrap();
    let w = plan.warnings(threadcut::units::Units::Mm);
    assert!(w.iter().any(|w| w.contains("--teeth")), "{w:?}");
}

#[test]
fn bad_input_names_the_flag() {
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "--thread",
                "M10",
                "--internal",
                "--length",
                "10",
                "--tool-diameter",
                "9",
                "--feed",
                "100",
                "-c",
                "centroid",
                "--d-register",
                "1",
            ],
            "--tool-diameter",
        ),
        (
            &[
                "--thread",
                "M10",
                "--internal",
                "--length",
                "0",
                "--tool-diameter",
                "6",
                "--feed",
                "100",
                "-c",
                "centroid",
                "--d-register",
                "1",
            ],
            "--length",
        ),
        (
            &[
                "--thread",
                "M10x1.4",
                "--internal",
                "--length",
                "10",
                "--tool-diameter",
                "6",
                "--feed",
                "100",
                "-c",
                "centroid",
                "--d-register",
                "1",
            ],
            "M10x1.5",
        ),
        (
            &[
                "--thread",
                "M10",
                "--length",
                "10",
                "--tool-diameter",
                "6",
                "--feed",
                "100",
                "-c",
                "centroid",
                "--d-register",
                "1",
            ],
            "--internal",
        ),
        (
            &[
                "--thread",
                "M10",
                "--internal",
                "--length",
                "10",
                "--tool-diameter",
                "6",
                "--feed",
                "100",
                "-c",
                "haas",
            ],
            "linuxcnc-mill",
        ),
        (
            &[
                "--thread",
                "M10",
                "--internal",
                "--length",
                "10",
                "--tool-diameter",
                "6",
                "--feed",
                "-5",
                "-c",
                "linuxcnc-mill",
            ],
            "--feed",
        ),
        (
            &[
                "--thread",
                "M10-6g",
                "--internal",
                "--length",
                "10",
                "--tool-diameter",
                "6",
                "--feed",
                "100",
                "-c",
                "linuxcnc-mill",
            ],
            "class 6g",
        ),
    ];
    for (args, want) in cases {
        let (out, err, code) = run(args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(out.is_empty(), "nothing is written on error");
        assert!(
            err.contains(want),
            "{args:?}: `{err}` should mention {want}"
        );
    }
}

/// `--format jsonl`: arcs as {"kind":"arc","x","y","z","i","j","cw"…}, the same moves as the
/// G-code, unrounded.
#[test]
fn jsonl_arcs_match_the_gcode() {
    let args = [
        "--thread",
        "3/8-16 UNC",
        "--internal",
        "--length",
        "0.5",
        "--tool-diameter",
        "0.22",
        "--feed",
        "15",
        "-c",
        "linuxcnc-mill",
        "--passes",
        "2",
    ];
    let g = readback::read(&ok(&args)).unwrap();
    let mut j = args.to_vec();
    j.extend(["--format", "jsonl"]);
    let text = ok(&j);
    let mut lines = text.lines();
    let plan: serde_json::Value = serde_json::from_str(lines.next().unwrap()).unwrap();
    assert_eq!(plan["kind"], "plan");
    let arcs_json: Vec<serde_json::Value> = lines
        .map(|l| serde_json::from_str::<serde_json::Value>(l).unwrap())
        .filter(|v| v["kind"] == "arc")
        .collect();
    let arcs_g = arcs(&g.segments);
    assert_eq!(arcs_json.len(), arcs_g.len());
    for (a, s) in arcs_json.iter().zip(&arcs_g) {
        let keys: Vec<&str> = a.as_object().unwrap().keys().map(|k| k.as_str()).collect();
        for k in ["kind", "x", "y", "z", "i", "j", "cw"] {
            assert!(keys.contains(&k), "{a}");
        }
        let SegKind::Arc { center, cw } = s.kind else {
            unreachable!()
        };
        assert_eq!(a["cw"].as_bool(), Some(cw));
        for (key, v) in [("x", s.to[0]), ("y", s.to[1]), ("z", s.to[2])] {
            assert!(
                (a[key].as_f64().unwrap() - v).abs() <= 0.000_005 + 1e-12,
                "{key}"
            );
        }
        let ci = s.from[0] + a["i"].as_f64().unwrap();
        assert!((ci - center[0]).abs() < 1e-5);
    }
    assert!(text
        .lines()
        .nth(2)
        .unwrap()
        .starts_with(r#"{"kind":"feed","x":"#));
}

/// LinuxCNC refuses a compensation entry move no longer than the tool radius; the check sees it.
#[test]
fn linuxcnc_entry_move_rule_is_checked() {
    let profile = mill::profile::MillProfile::built_in("linuxcnc-mill").unwrap();
    let mut s = spec(Side::Internal, 1, 1);
    s.comp = Comp::Controller;
    let mut plan = mill::plan(&s).unwrap();
    assert!(mill::profile_checks(&plan, &profile).is_ok());
    // Shorten the entry move to less than the tool radius.
    let i = plan.moves.iter().position(|m| m.comp.is_some()).unwrap();
    let from = plan.moves[i - 1].to;
    plan.moves[i].to.x = from.x + 1.0;
    plan.moves[i].to.y = from.y;
    let e = mill::profile_checks(&plan, &profile).unwrap_err();
    assert!(e.message.contains("entry"), "{}", e.message);
    let fanuc = mill::profile::MillProfile::built_in("fanuc-mill").unwrap();
    assert!(mill::profile_checks(&plan, &fanuc).is_ok());
}

#[test]
fn directions_helper_and_climb() {
    assert_eq!(
        mill::climb(Side::Internal, Hand::Right),
        Direction::BottomUp
    );
    assert_eq!(mill::climb(Side::External, Hand::Right), Direction::TopDown);
    assert_eq!(mill::climb(Side::Internal, Hand::Left), Direction::TopDown);
    assert_eq!(mill::climb(Side::External, Hand::Left), Direction::BottomUp);
}

/// The lead arcs meet the thread in phase: wherever the tool reaches into the material, the arc's
/// Z equals the Z the helix groove has at that angle about the axis. Internal lead arcs pass through
/// the axis (radius A/2), so they are exact; external ones are split into arcs that end in phase,
/// leaving a small error between the joints.
#[test]
fn lead_arcs_are_in_phase_with_the_helix() {
    for (side, crest, tol_of_pitch) in [
        ("--internal", 17.294 / 2.0, 1e-6),
        ("--external", 19.958 / 2.0, 0.003),
    ] {
        for dir in ["--bottom-up", "--top-down"] {
            let out = ok(&[
                "--thread",
                "M20",
                side,
                dir,
                "--length",
                "10",
                "--tool-diameter",
                "12",
                "--feed",
                "300",
                "-c",
                "linuxcnc-mill",
                "--comp",
                "none",
            ]);
            let p = readback::read(&out).unwrap();
            let all = arcs(&p.segments);
            let t = turns(&p.segments);
            let first = all.iter().position(|s| *s == t[0]).unwrap();
            let last = all.iter().position(|s| *s == t[t.len() - 1]).unwrap();
            let dz_dphi = (t[0].to[2] - t[0].from[2]) / t[0].sweep().unwrap();
            let mut worst: f64 = 0.0;
            let mut samples = 0;
            for (k, s) in all.iter().enumerate() {
                let z_ref = if k < first {
                    t[0].from[2]
                } else if k > last {
                    t[t.len() - 1].to[2]
                } else {
                    continue;
                };
                // Z never reverses: every lead arc moves along Z the way the helix does (or not
                // at all).
                let dz = s.to[2] - s.from[2];
                assert!(
                    dz * (t[0].to[2] - t[0].from[2]) >= 0.0,
                    "{side} {dir}: Z reverses: {s:?}"
                );
                let SegKind::Arc { center: m, .. } = s.kind else {
                    unreachable!()
                };
                let r = (s.from[0] - m[0]).hypot(s.from[1] - m[1]);
                let a0 = (s.from[1] - m[1]).atan2(s.from[0] - m[0]);
                let sweep = s.sweep().unwrap();
                for i in 0..=200 {
                    let f = f64::from(i) / 200.0;
                    let th = a0 + f * sweep;
                    let (x, y) = (m[0] + r * th.cos(), m[1] + r * th.sin());
                    let z = s.from[2] + f * (s.to[2] - s.from[2]);
                    let dist = x.hypot(y);
                    let reach = if side == "--internal" {
                        dist + 6.0
                    } else {
                        dist - 6.0
                    };
                    let in_material = if side == "--internal" {
                        reach > crest
                    } else {
                        reach < crest
                    };
                    if in_material {
                        let z_helix = z_ref + dz_dphi * y.atan2(x);
                        worst = worst.max((z - z_helix).abs());
                        samples += 1;
                    }
                }
            }
            assert!(
                samples > 50,
                "{side} {dir}: the lead arcs reach into the material"
            );
            assert!(
                worst <= tol_of_pitch * 2.5 + 1e-4,
                "{side} {dir}: phase error {worst} mm"
            );
        }
    }
}

/// Multi-start: each turn advances one lead (starts × pitch); start j is start 0 turned by
/// 360°·j/starts about the axis, so its groove lies j pitches along, with the same absolute Z.
#[test]
fn multi_start_threads_advance_one_lead() {
    let out = ok(&[
        "--thread",
        "M16",
        "--internal",
        "--starts",
        "2",
        "--length",
        "16",
        "--tool-diameter",
        "10",
        "--feed",
        "250",
        "-c",
        "linuxcnc-mill",
        "--comp",
        "none",
    ]);
    let p = readback::read(&out).unwrap();
    let t = turns(&p.segments);
    assert_eq!(
        t.len(),
        8,
        "16 mm / 4 mm lead = 4 turns per start, 2 starts"
    );
    for s in &t {
        assert!(
            (s.to[2] - s.from[2] - 4.0).abs() < 1e-9,
            "one lead per turn"
        );
    }
    let (a, b) = (t[0], t[4]);
    assert_eq!(
        a.from[2], b.from[2],
        "both starts begin at the thread bottom"
    );
    // Start 1 begins half a turn round: where start 0's groove is one pitch higher.
    let ang = |s: &Segment| s.from[1].atan2(s.from[0]);
    let d = (ang(&b) - ang(&a)).rem_euclid(std::f64::consts::TAU);
    assert!((d - std::f64::consts::PI).abs() < 1e-4, "{d}");
    // The groove of start 0 at start 1's starting angle is at its start Z + lead/2 = + one pitch;
    // start 1 there is at its start Z: the two grooves are one pitch apart (mod the lead).
    let z0_at = a.from[2] + 4.0 * d / std::f64::consts::TAU;
    assert!(((z0_at - b.from[2]) - 2.0).abs() < 1e-9);
}

#[test]
fn the_issues_flags_alone_make_a_program_on_every_controller() {
    // The issue's command line, no --d-register: G41/G42 keep the offset register in force, which
    // the program and stderr both say. (--feed is required: the arc-feed compensation the issue
    // asks for compensates a requested feed.)
    for controller in ["centroid", "fanuc-mill", "haas-mill", "linuxcnc-mill"] {
        let (stdout, stderr, code) = run(&[
            "--thread",
            "M10x1.5",
            "--internal",
            "--length",
            "12",
            "--tool-diameter",
            "6",
            "--feed",
            "300",
            "--controller",
            controller,
        ]);
        assert_eq!(code, 0, "{controller}: {stderr}");
        assert!(
            stdout.contains("G41") || stdout.contains("G42"),
            "{controller}: {stdout}"
        );
        let comp = stdout
            .lines()
            .find(|l| l.starts_with("G41") || l.starts_with("G42"))
            .unwrap();
        assert!(!comp.contains('D'), "{controller}: {comp}");
        if controller != "linuxcnc-mill" {
            assert!(
                stdout.contains("no D word: the tool-radius offset in force is used"),
                "{stdout}"
            );
            assert!(stderr.contains("no --d-register"), "{stderr}");
        }
    }
}
