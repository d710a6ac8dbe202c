//! The cross-section simulation against exact results: the sharp-V areas of `thread::area`, closed
//! forms for nose-radius and flat tools, hand-computed chip thicknesses, and clipper2 as an
//! independent boolean engine.

use clipper2_rust as clipper;
use proptest::prelude::*;
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::sim::{self, CuttingFlank, Tip, Tool};
use threadcut::thread::{
    DepthLaw, Entry, Exit, FinishPosition, Flank, Geometry, Infeed, Job, Lead, PassKind, PassPlan,
    Retract, Side,
};
use threadcut::units::{Pos, Units};

const T30: f64 = 0.577_350_269_189_625_8; // tan 30°

fn job(law: DepthLaw, depth: f64, infeed: Infeed, finish_passes: u32, allowance: f64) -> Job {
    Job {
        line: 1,
        span: Default::default(),
        controller: "test",
        units: Units::Mm,
        start: Pos::new(25.0, 5.0),
        geometry: Geometry {
            crest_start: Pos::new(20.0, 5.0),
            crest_end: Pos::new(20.0, -30.0),
            depth,
            side: Side::External,
        },
        lead: Lead::constant(2.0),
        plan: PassPlan {
            law,
            finish_allowance: allowance,
            finish_passes,
        },
        infeed,
        finish_at: FinishPosition::LastRough,
        tool_angle_deg: 60.0,
        entry: Entry::Direct,
        exit: Exit::Straight,
        retract: Retract { x: 25.0, z: 5.0 },
        return_path: threadcut::thread::ReturnPath::Box,
    }
}

fn sqrt_law(first: f64) -> DepthLaw {
    DepthLaw::Power {
        first,
        degression: 2.0,
        min_step: 0.0,
    }
}

fn flank(f: Flank) -> Infeed {
    Infeed::Flank {
        flank: f,
        angle_deg: 30.0,
    }
}

fn close(a: f64, b: f64, abs: f64) -> bool {
    (a - b).abs() <= abs
}

#[test]
fn constant_area_law_gives_equal_chips() {
    // d_n = 0.25·√n reaches 1.0 at n = 16 exactly: sixteen equal chips of 0.25²·tan 30°.
    for infeed in [Infeed::Radial, flank(Flank::Left), flank(Flank::Right)] {
        let j = job(sqrt_law(0.25), 1.0, infeed, 1, 0.0);
        let passes = j.passes().unwrap();
        let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
        let rough: Vec<_> = s
            .passes
            .iter()
            .zip(&passes)
            .filter(|(_, p)| p.kind == PassKind::Rough)
            .map(|(s, _)| s.area)
            .collect();
        assert_eq!(rough.len(), 16);
        let mean = rough.iter().sum::<f64>() / rough.len() as f64;
        assert!(close(mean, 0.0625 * T30, 1e-6), "{infeed:?}: {mean}");
        for a in &rough {
            assert!((a / mean - 1.0).abs() < 0.01, "{infeed:?}: {rough:?}");
        }
        // The spring pass at full depth cuts nothing.
        assert_eq!(s.passes.last().unwrap().flank, CuttingFlank::None);
        assert!(s.passes.last().unwrap().area < sim::AREA_EPSILON);
    }
}

#[test]
fn sharp_tool_agrees_with_the_exact_tent_areas() {
    let infeeds = [
        Infeed::Radial,
        flank(Flank::Left),
        flank(Flank::Right),
        Infeed::Alternating {
            first: Flank::Right,
            second: Flank::Centre,
            angle_deg: 30.0,
        },
        Infeed::Alternating {
            first: Flank::Left,
            second: Flank::Right,
            angle_deg: 30.0,
        },
        Infeed::Flank {
            flank: Flank::Left,
            angle_deg: 29.0,
        },
    ];
    for infeed in infeeds {
        let law = DepthLaw::Power {
            first: 0.35,
            degression: 2.0,
            min_step: 0.08,
        };
        let j = job(law, 1.227, infeed, 2, 0.05);
        let passes = j.passes().unwrap();
        let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
        for (sp, p) in s.passes.iter().zip(&passes) {
            assert!(
                close(sp.area, p.area, 1e-5 + 1e-4 * p.area),
                "{infeed:?} pass {}: sim {} exact {}",
                p.n,
                sp.area,
                p.area
            );
        }
    }
}

#[test]
fn the_gsk_example_program_simulates_like_the_pass_table() {
    let src = "G00 X80 Z10\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let machine = Machine::built_in("gsk980").unwrap();
    let jobs = program::jobs(src.as_bytes(), &machine).unwrap();
    let passes = jobs[0].passes().unwrap();
    let s = sim::section(&jobs[0], &passes, &Tool::sharp(60.0), 0.0).unwrap();
    assert_eq!(s.passes.len(), passes.len());
    for (sp, p) in s.passes.iter().zip(&passes) {
        assert!(close(sp.area, p.area, 1e-5), "pass {}", p.n);
        assert!(close(sp.share, p.share, 1e-5), "pass {}", p.n);
    }
    // Radial infeed: every chip is cut by both edges; the groove is the target exactly.
    assert!(s.passes[..passes.len() - 1]
        .iter()
        .all(|p| p.flank == CuttingFlank::Both));
    let g = s.groove;
    assert!(close(g.form.depth_reached, 1.2, 1e-12));
    assert!(close(g.form.depth_at_axis, 1.2, 1e-12));
    assert!(close(g.form.flank_angle_left_deg, 30.0, 1e-9));
    assert!(close(g.form.flank_angle_right_deg, 30.0, 1e-9));
    assert!(g.overcut_area < 1e-5 && g.left_in_form < 1e-5, "{g:?}");
    assert!(g.form.ridge.abs() < 1e-12);
    // Pitch line: the 60° target groove 1.2 deep is 1.0 wide (half the 2 mm pitch) at
    // 1.2 − 0.5/tan 30° = 0.33397 deep.
    assert!(close(
        g.form.pitch_line_depth.unwrap(),
        1.2 - 0.5 / T30,
        1e-9
    ));
    assert!(close(g.form.pitch_diameter_error.unwrap(), 0.0, 1e-9));
}

#[test]
fn radial_passes_with_a_nose_cut_exactly_the_target_form() {
    // Radial passes end in a plunge of the same tool to full depth on the axis, so the groove is
    // the target form: nothing cut outside it, nothing left in it, whether the blank is the crest
    // line or stands 0.3 above it (the target clipped to the blank's top).
    let src = "G00 X80 Z10\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let machine = Machine::built_in("gsk980").unwrap();
    let jobs = program::jobs(src.as_bytes(), &machine).unwrap();
    let passes = jobs[0].passes().unwrap();
    let tool = Tool {
        angle_deg: 60.0,
        tip: Tip::Radius { radius: 0.15 },
    };
    for stock in [0.0, 0.3] {
        let s = sim::section(&jobs[0], &passes, &tool, stock).unwrap();
        let g = s.groove;
        // Within the 1 nm grid's rounding of where the flanks cross the blank's top (≈ 1e-7).
        assert!(
            g.overcut_area < 1e-6 && g.left_in_form < 1e-6,
            "{stock}: {g:?}"
        );
        // The whole form: the rounded V from the blank's top to the full depth, less nothing.
        let (r, a) = (0.15, 30f64.to_radians());
        let c = r / a.sin() - r;
        let exact = (1.2 + stock + c).powi(2) * T30
            - (r * r / T30 - r * r * (std::f64::consts::FRAC_PI_2 - a));
        assert!(
            close(s.total_area, exact, 1e-6),
            "{stock}: {} vs {exact}",
            s.total_area
        );
    }
}

#[test]
fn radial_chip_thickness_is_the_increment_times_sin_half_angle() {
    // Depths 0.5, 0.8, 1.0 radial: the flanks move Δd·sin 30° normal to themselves.
    let law = DepthLaw::Explicit {
        depths: vec![0.5, 0.8],
    };
    let j = job(law, 1.0, Infeed::Radial, 1, 0.0);
    let passes = j.passes().unwrap();
    let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
    assert!(
        close(s.passes[1].max_thickness, 0.3 * 0.5, 1e-5),
        "{:?}",
        s.passes[1]
    );
    assert!(
        close(s.passes[2].max_thickness, 0.2 * 0.5, 1e-5),
        "{:?}",
        s.passes[2]
    );
    // First pass: the chip is the whole V under the crest line; the crest point above the tip is
    // the farthest from the edges, d·sin 30°.
    assert!(
        close(s.passes[0].max_thickness, 0.5 * 0.5, 1e-5),
        "{:?}",
        s.passes[0]
    );
}

#[test]
fn flank_infeed_cuts_with_one_edge_twice_as_thick() {
    // Flank::Left (the tip rides down the groove's −Z flank): the tool's +Z edge cuts, and the
    // chip on it is 2·Δd·sin 30° = Δd thick.
    let law = DepthLaw::Explicit {
        depths: vec![0.5, 0.8],
    };
    let j = job(law, 1.0, flank(Flank::Left), 1, 0.0);
    let passes = j.passes().unwrap();
    let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
    assert_eq!(s.passes[0].flank, CuttingFlank::Both);
    assert_eq!(s.passes[1].flank, CuttingFlank::Right);
    // The finishing pass plunges straight in at the last rough pass's offset (LastRough): both.
    assert_eq!(s.passes[2].flank, CuttingFlank::Both);
    assert!(
        close(s.passes[1].max_thickness, 0.3, 1e-5),
        "{:?}",
        s.passes[1]
    );
    // The −Z share of pass 2: the triangle between the tool's axis u = 0.8t, the old groove's
    // +Z flank and the shared −Z flank, 0.3t wide and 0.6 tall: 0.09t of (0.8² − 0.5²)·t.
    assert!(close(s.passes[1].left_share, 0.09 / 0.39, 1e-6));
    let j = job(
        DepthLaw::Explicit {
            depths: vec![0.5, 0.8],
        },
        1.0,
        flank(Flank::Right),
        1,
        0.0,
    );
    let passes = j.passes().unwrap();
    let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
    assert_eq!(s.passes[1].flank, CuttingFlank::Left);
    assert!(close(s.groove.form.flank_angle_left_deg, 30.0, 1e-9));
}

#[test]
fn nose_radius_first_chip_matches_the_closed_form() {
    // One pass 0.6 deep with r = 0.1: the V to the extended apex, (d + c)²·t with
    // c = r/sin 30° − r = 0.1, minus the corner between apex and arc, r²/t − r²(π/2 − 30°).
    let r = 0.1;
    let j = job(
        DepthLaw::Explicit { depths: vec![] },
        0.6,
        Infeed::Radial,
        1,
        0.6 - 1e-12,
    );
    let passes = j.passes().unwrap();
    let tool = Tool {
        angle_deg: 60.0,
        tip: Tip::Radius { radius: r },
    };
    let s = sim::section(&j, &passes, &tool, 0.0).unwrap();
    let a = 30f64.to_radians();
    let exact =
        (0.6 + r) * (0.6 + r) * T30 - (r * r / T30 - r * r * (std::f64::consts::FRAC_PI_2 - a));
    // The arc is flattened into chords within sim::tool::NOSE_TOLERANCE (0.5 µm) of it, on a
    // polygon that keeps the arc's area (10 chords for this 0.1 mm nose), so a chip that takes
    // the whole nose has the exact area. What is left is the 1 nm grid: the outline's vertices and
    // the flanks' crossings with the crest line are rounded to it, which moves each flank by up to
    // about 0.5 nm over the 0.7 mm it cuts, < 1e-6 mm² in all (4e-7 here). With the fixed 24
    // plain chords used before, the chip lacked the chords' segments, 1.3e-5 mm², which the test
    // subtracted and then allowed 2e-6.
    assert_eq!(tool.nose_polygon().unwrap().segments, 10);
    assert!(
        close(s.passes[0].area, exact, 1e-6),
        "{} vs {}",
        s.passes[0].area,
        exact
    );
}

#[test]
fn flat_tip_and_stock_above_the_crest() {
    // A 0.2 flat, one pass 0.5 deep into a blank 0.1 above the crest: a trapezoid 0.6 tall,
    // 0.2 wide at the bottom, 0.2 + 2·0.6·t at the top.
    let j = job(
        DepthLaw::Explicit { depths: vec![] },
        0.5,
        Infeed::Radial,
        1,
        0.5 - 1e-12,
    );
    let passes = j.passes().unwrap();
    let tool = Tool {
        angle_deg: 60.0,
        tip: Tip::Flat { width: 0.2 },
    };
    let s = sim::section(&j, &passes, &tool, 0.1).unwrap();
    let exact = 0.6 * (0.2 + 0.2 + 1.2 * T30) / 2.0;
    assert!(close(s.passes[0].area, exact, 1e-6), "{}", s.passes[0].area);
    // A blank below the crest by more than the depth: nothing to cut.
    let s = sim::section(&j, &passes, &tool, -0.6).unwrap();
    assert!(s.total_area < sim::AREA_EPSILON);
}

#[test]
fn alternating_infeed_leaves_ridges_and_overcut_when_it_finishes_off_axis() {
    // GSK mode 4 style left/right alternation finishing at the last rough position: the last
    // rough pass (n = 2, a mirrored one) is off the axis, so the flank it rides is cut beyond the
    // target and the other one is left short.
    let law = DepthLaw::Explicit {
        depths: vec![0.6, 0.9],
    };
    let infeed = Infeed::Alternating {
        first: Flank::Left,
        second: Flank::Right,
        angle_deg: 25.0,
    };
    let j = job(law, 1.0, infeed, 1, 0.0);
    let passes = j.passes().unwrap();
    let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
    let g = s.groove;
    // The finish pass sits at pass 2's offset, not on the axis.
    assert_eq!(passes[2].offset, passes[1].offset);
    let tan25 = 25f64.to_radians().tan();
    let (u1, u2) = (0.6 * tan25, 2.0 * tan25 - 0.9 * tan25);
    assert!(close(g.form.axis, tan25, 1e-12));
    // Pass 1's tent (u1, 0.6) pokes out of the finish tent (u2, 1.0): they meet at
    // (0.6 + 1.0 − (u2 − u1)/t)/2, which leaves a ridge below pass 1's tip.
    let valley = (1.6 - (u2 - u1) / T30) / 2.0;
    assert!(close(g.form.ridge, 0.6 - valley, 1e-9), "{g:?}");
    // Pitch line: the 1.0-deep target is 1.0 wide (half the 2 mm pitch) at 1 − 0.5/t. There the
    // groove runs from pass 1's left flank to the finish pass's right flank.
    let v = 1.0 - 0.5 / T30;
    assert!(close(g.form.pitch_line_depth.unwrap(), v, 1e-9));
    let (left, right) = (u1 - (0.6 - v) * T30, u2 + (1.0 - v) * T30);
    assert!(close(g.form.centre, (left + right) / 2.0, 1e-9));
    // 2.2 µm too wide: an external pitch diameter 2.2/tan 30° = 3.8 µm undersize.
    let excess = (right - left) - 1.0;
    assert!(
        close(g.form.pitch_diameter_error.unwrap(), -excess / T30, 1e-9),
        "{g:?}"
    );
    assert!(g.overcut_area > 1e-4 && g.left_in_form > 1e-4, "{g:?}");
}

#[test]
fn ridge_between_left_and_right_passes_hand_computed() {
    // Two 1.0-deep passes 0.4 apart with a 60° tool: the V's meet 0.2/tan 30° above the tips,
    // so a ridge 1.0 − (1.0 − 0.2/tan 30°) = 0.34641 stands between them.
    let law = DepthLaw::Explicit { depths: vec![] };
    let j = job(law, 1.0, Infeed::Radial, 1, 0.0);
    let mut passes = j.passes().unwrap();
    assert_eq!(passes.len(), 1);
    let mut second = passes[0];
    passes[0].offset = -0.2;
    second.offset = 0.2;
    second.n = 2;
    passes.push(second);
    let s = sim::section(&j, &passes, &Tool::sharp(60.0), 0.0).unwrap();
    assert!(
        close(s.groove.form.ridge, 0.2 / T30, 1e-9),
        "{}",
        s.groove.form.ridge
    );
    assert!(close(s.groove.form.depth_at_axis, 1.0 - 0.2 / T30, 1e-9));
}

#[test]
fn bad_tools_and_huge_sections_are_diagnostics_not_panics() {
    let j = job(sqrt_law(0.25), 1.0, Infeed::Radial, 1, 0.0);
    let passes = j.passes().unwrap();
    assert!(sim::section(&j, &passes, &Tool::sharp(200.0), 0.0).is_err());
    assert!(sim::section(&j, &passes, &Tool::sharp(60.0), f64::NAN).is_err());
    assert!(sim::section(&j, &passes, &Tool::sharp(60.0), 1e6).is_err());
}

/// Chip areas by clipper2, as an independent engine: material ∩ tool, then material − tool.
fn clipper_chips(cuts: &[(f64, f64)], tool: &Tool) -> Vec<f64> {
    let path = |pts: &[(f64, f64)]| -> clipper::PathD {
        pts.iter()
            .map(|&(u, v)| clipper::Point::new(u, v))
            .collect()
    };
    let mut material: clipper::PathsD = vec![path(&[
        (-50.0, 0.0),
        (50.0, 0.0),
        (50.0, 10.0),
        (-50.0, 10.0),
    ])];
    cuts.iter()
        .map(|&(u0, d)| {
            let t: clipper::PathsD = vec![path(&tool.outline(u0, d, -1.0))];
            let chip = clipper::intersect_d(&material, &t, clipper::FillRule::NonZero, 8);
            material = clipper::difference_d(&material, &t, clipper::FillRule::NonZero, 8);
            clipper::area_paths(&chip).abs()
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn i_overlay_agrees_with_clipper2(
        steps in proptest::collection::vec((0.02..0.4f64, -0.3..0.3f64), 1..10),
        radius in 0.0..0.2f64,
        flat in proptest::prop_oneof![Just(false), Just(true)],
    ) {
        let mut depth = 0.0;
        let cuts: Vec<(f64, f64)> = steps.iter().map(|&(dd, u)| { depth += dd; (u, depth) }).collect();
        let mut j = job(DepthLaw::Explicit { depths: cuts.iter().map(|c| c.1).collect() }, depth + 0.1, Infeed::Radial, 0, 0.0);
        j.plan.finish_allowance = 0.1;
        let mut passes = j.passes().unwrap();
        for (p, c) in passes.iter_mut().zip(&cuts) {
            p.offset = c.0;
        }
        let tool = Tool { angle_deg: 60.0, tip: if flat { Tip::Flat { width: radius } } else { Tip::Radius { radius } } };
        let s = sim::section(&j, &passes, &tool, 0.0).unwrap();
        let oracle = clipper_chips(&cuts, &tool);
        for (a, b) in s.passes.iter().zip(&oracle) {
            prop_assert!((a.area - b).abs() < 1e-5 + 1e-5 * b, "{} vs {}", a.area, b);
        }
    }
}

#[test]
fn flank_infeed_with_a_nose_agrees_with_clipper2() {
    // The benchmark's thread (benches/sim.rs): the tool slides its flank along the one the last
    // pass cut, where the material is straightened after each pass (nanometre slivers dropped).
    // Every chip still agrees with clipper2, which sees neither the grid nor the straightening.
    let src = "G00 X50 Z10\nG78 P010160 Q0.05 R0.02\nG78 X36.96 Z-40 P2.76 Q0.64 F4.5\n";
    let machine = Machine::built_in("gsk980").unwrap();
    let job = program::jobs(src.as_bytes(), &machine).unwrap().remove(0);
    let passes = job.passes().unwrap();
    assert_eq!(passes.len(), 20);
    for radius in [0.1, 0.2, 0.4] {
        let tool = Tool {
            angle_deg: 60.0,
            tip: Tip::Radius { radius },
        };
        let s = sim::section(&job, &passes, &tool, 0.0).unwrap();
        let cuts: Vec<(f64, f64)> = passes.iter().map(|p| (p.offset, p.depth)).collect();
        let oracle = clipper_chips(&cuts, &tool);
        for (a, b) in s.passes.iter().zip(&oracle) {
            assert!(
                (a.area - b).abs() < 1e-5 + 1e-5 * b,
                "r {radius} pass {}: {} vs {b}",
                a.n,
                a.area
            );
        }
    }
}

#[test]
fn passes_json_gains_the_simulated_columns() {
    let input = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("sim-passes.nc");
    std::fs::write(
        &input,
        "G00 X80 Z10\nG78 P010160 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n",
    )
    .unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["passes", input.to_str().unwrap(), "-c", "gsk980", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let rows = v["cycles"][0]["passes"].as_array().unwrap();
    for r in rows {
        // The existing keys stay; the sharp-tool simulation agrees with the exact area.
        for key in ["n", "kind", "depth", "increment", "x", "z", "area", "share"] {
            assert!(r.get(key).is_some(), "{key}");
        }
        let (exact, sim) = (r["area"].as_f64().unwrap(), r["sim_area"].as_f64().unwrap());
        assert!(close(exact, sim, 1e-5), "{r}");
        assert!(r["sim_share"].is_f64() && r["chip_thickness"].is_f64());
    }
    // Left-flank infeed (r = 01): after the first pass the tool's +Z edge does the cutting.
    assert_eq!(rows[0]["cutting_flank"], "both");
    assert_eq!(rows[2]["cutting_flank"], "right");
}
