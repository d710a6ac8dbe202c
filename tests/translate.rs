//! Native cycles are written only when reading them back reproduces the motion.

use threadcut::machine::Machine;
use threadcut::program;
use threadcut::translate::{job_to_string, Written};

#[test]
fn gsk_g78_round_trips_as_a_native_cycle() {
    let gsk = Machine::built_in("gsk980").unwrap();
    for src in [
        "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n",
        "G0 X20 Z5\nG78 P010460 Q0.05 R0.02 E0.5\nG78 X24 Z-20 P0.8 Q0.2 I20\n",
        "G0 X50 Z2\nG78 P030360 Q0.1 R0.05 D0 L2\nG78 U-12 W-32 R-1 P1.2 Q0.3 F2.5\n",
    ] {
        let jobs = program::jobs(src.as_bytes(), &gsk).unwrap();
        let (text, written) = job_to_string(&gsk, &jobs[0]).unwrap();
        assert_eq!(written, Written::Native, "{src}\n{text}");
        assert!(text.starts_with("G78 P"), "{text}");
    }
}

#[test]
fn a_job_g78_cannot_express_falls_back_to_plain_moves_and_says_why() {
    let gsk = Machine::built_in("gsk980").unwrap();
    let src = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3\n";
    let mut job = program::jobs(src.as_bytes(), &gsk).unwrap().remove(0);
    job.lead.starts = 100;
    let (text, written) = job_to_string(&gsk, &job).unwrap();
    assert!(
        matches!(written, Written::Plain(ref why) if why.contains("1 to 99 starts")),
        "{written:?}"
    );
    assert!(text.starts_with("(threadcut: plain moves, not the native cycle: G78 allows 1 to 99 starts and 1 to 99 finishing passes)\nG0 X"), "{text}");
}

#[test]
fn a_variable_lead_is_never_written_as_a_constant_one() {
    // Neither G78 nor GSK's G32 can cut a lead that changes every revolution: an error, not G32 moves.
    let gsk = Machine::built_in("gsk980").unwrap();
    let src = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3\n";
    let mut job = program::jobs(src.as_bytes(), &gsk).unwrap().remove(0);
    job.lead.dlead = 0.01;
    match job_to_string(&gsk, &job) {
        Err(program::Error::Input(d)) => {
            assert_eq!(d.code, threadcut::diag::Code::Unsupported);
            assert_eq!(d.span.line, 3);
            assert!(d.message.contains("no variable-lead move"), "{}", d.message);
        }
        other => panic!("{other:?}"),
    }
}

fn machine(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

/// The native text for the first cycle of `src` (read on `from`), written for `to`: it must be
/// native.
fn native(src: &str, from: &str, to: &str) -> Vec<String> {
    let job = program::jobs(src.as_bytes(), &machine(from))
        .unwrap()
        .remove(0);
    let (text, written) = job_to_string(&machine(to), &job).unwrap();
    assert_eq!(written, Written::Native, "{src} on {to}:\n{text}");
    text.lines().map(str::to_string).collect()
}

/// Allen-Bradley's G78 writes each bundled example back word for word (hand-checked: X on
/// diameter, K and D radii, the lead in the active units — E13 as F0.07692, 1/13" to 0.00001" —,
/// the tool angle A and the infeed P), and chooses A by the motion: a plunge (A0) whatever P said.
#[test]
fn allen_bradley_g78_writes_its_examples_back_and_chooses_a_by_the_infeed() {
    for (file, want) in [
        (
            "ab9-metric-p1.nc",
            "G78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1",
        ),
        (
            "ab9-inch-p3-e.nc",
            "G78 X0.4056 Z-0.75 K0.0472 D0.01 F0.07692 A60 P3",
        ),
        (
            "ab9-taper-p4.nc",
            "G78 X0.9 Z-1. I-0.03 K0.05 D0.015 F0.0833 A60 P4",
        ),
    ] {
        let src = std::fs::read_to_string(format!("examples/{file}")).unwrap();
        let mut lines = native(&src, "ab9", "ab9");
        // F0.07692 is not 1/13": the drift over the thread stated before the cycle (.0000031" a
        // turn over .95", 12.35 turns: .000038").
        if file == "ab9-inch-p3-e.nc" {
            let c = lines.remove(0);
            assert!(c.starts_with("(threadcut: lead 0.076923 inch written as 0.07692 inch drifts 0.000038 inch over the thread's 0.95 inch"), "{c}");
        }
        assert_eq!(lines, [want], "{file}");
    }
    // A0 is a plunge: P2 (alternating) moves as P1, and the search writes the first that reads
    // back, though the job's chip areas assume a 60° tool.
    let src = "G21\nG0 X12. Z5.\nG78 X8.16 Z-20. K0.92 D0.35 F1.5 A0 P2\n";
    let job = program::jobs(src.as_bytes(), &machine("ab9"))
        .unwrap()
        .remove(0);
    assert_eq!(job.tool_angle_deg, 60.0);
    assert_eq!(
        native(src, "ab9", "ab9"),
        ["G78 X8.16 Z-20. K0.92 D0.35 F1.5 A0 P1"]
    );
    // A job with a start angle is not a G78 (it has no Q), nor plain G33 moves (nor do they).
    let src = "G21\nG0 X12. Z5.\nG76 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1 Q90000\n";
    let mut job = program::jobs(src.as_bytes(), &machine("fanuc15"))
        .unwrap()
        .remove(0);
    job.plan.finish_allowance = 0.0;
    let d = threadcut::dialect::open(&machine("ab9")).unwrap();
    assert_eq!(d.emit_native(&job).unwrap_err(), "G78 has no start angle");
    let e = job_to_string(&machine("ab9"), &job).unwrap_err();
    assert!(e.to_string().contains("cannot state a start angle"), "{e}");
}

/// OmniTurn's G33 writes each seed example back (hand-checked against the seed's own blocks: X,
/// I and A in the profile's radius mode — the taper example was written in G72, diameters —, K in
/// inches, C alone as 29°, P and O as flags), the four-start coarse thread inside G35 … G36 with
/// the G92 that restates the start point.
#[test]
fn omniturn_g33_writes_every_seed_example_back() {
    for (file, want) in [
        (
            "omniturn-external.nc",
            &["G33 X0.212 Z-0.5 I0.012 K0.05 C29. P"][..],
        ),
        (
            "omniturn-cleanup.nc",
            &["G33 X0.212 Z-0.5 I0.008 K0.05 C29. P O"][..],
        ),
        (
            "omniturn-internal.nc",
            &["G33 X0.46875 Z-0.75 I0.01 K0.05 C29."][..],
        ),
        (
            "omniturn-taper.nc",
            &["G33 X0.1825 Z-0.5 I0.0025 K0.0769 A0.0175"][..],
        ),
        (
            "omniturn-three-start.nc",
            &["G33 X0.212 Z-0.5 I0.01 K0.15 P"][..],
        ),
        (
            "omniturn-four-start-g35.nc",
            &[
                "G35",
                "G92 X0.5 Z0.2",
                "G33 X0.45 Z-0.75 I0.01 K0.4 C29.",
                "G36",
                "G92 X0.5 Z0.2",
            ][..],
        ),
    ] {
        let src = std::fs::read_to_string(format!("examples/{file}")).unwrap();
        assert_eq!(native(&src, "omniturn", "omniturn"), want, "{file}");
    }
    // What G33 cannot express is said, property by property.
    let fanuc = "G21 G99\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";
    let mut job = program::jobs(fanuc.as_bytes(), &machine("fanuc"))
        .unwrap()
        .remove(0);
    let d = threadcut::dialect::open(&machine("omniturn")).unwrap();
    assert_eq!(
        d.emit_native(&job).unwrap_err(),
        "OmniTurn programs are written in inches"
    );
    job.units = threadcut::units::Units::Inch;
    assert!(
        d.emit_native(&job)
            .unwrap_err()
            .contains("first pass from the tool's position"),
        "{:?}",
        d.emit_native(&job)
    );
}

/// Sinumerik's CYCLE97 writes each bundled example back (hand-checked: the run-in and run-out
/// become part of the thread, SPL − APP and FPL + ROP with APP = ROP = 0; DM1/DM2 the crest
/// diameters; NID the finishing passes after the first; `_VRT` the 1 mm lift written out), and
/// finds NRC for another controller's cycle: Fanuc's G76 with k = 1, Δd = 0.5 and no binding
/// minimum cut cuts 0.5·√n, which is CYCLE97's (TDEP − FAL)·√(n/NRC) with NRC = (1/0.5)² = 4.
#[test]
fn cycle97_writes_its_examples_back_and_finds_nrc_for_a_g76() {
    for (file, want) in [
        (
            "sinumerik-m24x1.5-cycle97.mpf",
            "CYCLE97(1.5000,,4.000,-34.000,24.000,24.000,0,0,0.920,0.050,-29.0000,0.0000,7,2,3,1,1.000)",
        ),
        (
            "sinumerik-internal-two-start.mpf",
            "CYCLE97(3.0000,,6.000,-27.000,38.376,38.376,0,0,0.812,0.040,0.0000,0.0000,8,1,4,2,1.000)",
        ),
    ] {
        let src = std::fs::read_to_string(format!("examples/{file}")).unwrap();
        assert_eq!(native(&src, "sinumerik", "sinumerik"), [want], "{file}");
    }
    let g76 = "G21\nG0 X32. Z5.\nG76 P010060 Q10 R0\nG76 X28. Z-30. P1000 Q500 F2.\n";
    assert_eq!(
        native(g76, "fanuc", "sinumerik"),
        ["CYCLE97(2.0000,,5.000,-30.000,30.000,30.000,0,0,1.000,0.000,30.0000,0.0000,4,0,3,1,1.000)"]
    );
    // Δd 0.4 on k 1: (1/0.4)² = 6.25 cuts — no NRC gives these depths.
    let g76 = "G21\nG0 X32. Z5.\nG76 P010060 Q10 R0\nG76 X28. Z-30. P1000 Q400 F2.\n";
    let job = program::jobs(g76.as_bytes(), &machine("fanuc"))
        .unwrap()
        .remove(0);
    let (_, written) = job_to_string(&machine("sinumerik"), &job).unwrap();
    assert!(
        matches!(written, Written::Plain(ref why) if why.contains("NRC")),
        "{written:?}"
    );
}

/// The example: a radial-infeed GSK G78 (r = 0 with a 60° tool) is a Fanuc G76 with a 0°
/// tool angle. The search writes a = 00 — not the job's 60°, whose flank infeed would cut other
/// passes — and the read-back accepts it; G78 finishes at the last rough pass's Z and G76 on the
/// groove's axis, which for a radial infeed is the same place.
#[test]
fn a_radial_gsk_g78_is_a_fanuc_g76_with_a_zero_tool_angle() {
    let gsk = "G0 X80 Z10\nG78 P010060 Q0.15 R0.1\nG78 X60 Z-60 P3 Q1.2 F3\n";
    let job = program::jobs(gsk.as_bytes(), &machine("gsk980"))
        .unwrap()
        .remove(0);
    assert_eq!(job.tool_angle_deg, 60.0);
    assert_eq!(
        native(gsk, "gsk980", "fanuc"),
        ["G76 P010000 Q150 R0.1", "G76 X60. Z-60. P3000 Q1200 F3."]
    );
    // The same on the FS15 format's one-block G76 needs its machine's allowance and passes
    // (parameters 5141/5142: 0.05 mm, 1 pass): R(d) 0.1 is not expressible there.
    let job = program::jobs(gsk.as_bytes(), &machine("gsk980"))
        .unwrap()
        .remove(0);
    let (_, written) = job_to_string(&machine("fanuc15"), &job).unwrap();
    assert!(
        matches!(written, Written::Plain(ref why) if why.contains("finishing allowance")),
        "{written:?}"
    );
}

/// A lead written in other units drifts over the thread: M10×1.5 over 20 mm on the OmniTurn's
/// .00005" grid is K.05905 (1.5/25.4 = .0590551), .0000051" short a turn, .0000680" over 13⅓
/// turns. 2.54 mm is .1" exactly: no drift.
#[test]
fn the_lead_rounding_over_the_thread_is_hand_computed() {
    let omniturn = machine("omniturn");
    let d = threadcut::dialect::open(&omniturn).unwrap();
    let src = "G21\nG0 X12. Z5.\nG78 X8.16 Z-15. K0.92 D0.35 F1.5 A60 P1\n";
    let mut job = program::jobs(src.as_bytes(), &machine("ab9"))
        .unwrap()
        .remove(0);
    job.units = threadcut::units::Units::Inch;
    let r = threadcut::translate::lead_rounding(&omniturn, d.as_ref(), &job);
    assert!((r.written - 0.05905).abs() < 1e-12, "{r:?}");
    assert!((r.length - 20.0 / 25.4).abs() < 1e-12);
    let drift = (1.5 / 25.4 - 0.05905) * (20.0 / 1.5);
    assert!(
        (r.over_length - drift).abs() < 1e-12 && drift > 0.00005,
        "{r:?}"
    );
    assert!((r.resolution - 0.00005).abs() < 1e-15);
    assert_eq!(
        r.describe(threadcut::units::Units::Mm),
        "lead 1.5 mm written as 0.05905 inch: 0.0000051 inch per turn, 0.0000682 inch over the thread's 0.7874 inch"
    );
    // Judged: × cot 30° = .0001181" on the pitch diameter; M10x1.5-6g Td2 = 90·1.5^0.4·
    // √(5.6·11.2)^0.1 = 130.2 → R40 132 µm (d2 9.026/8.894), a quarter 33 µm = .0012992": within.
    use threadcut::translate::{DriftRule, LeadDrift};
    let judged = LeadDrift::judge(r, &job, &DriftRule::new(threadcut::units::Units::Mm));
    assert!((judged.pitch_diameter - drift * 3f64.sqrt()).abs() < 1e-12);
    assert!(
        (judged.limit_value() - 0.033 / 25.4).abs() < 1e-12,
        "{judged:?}"
    );
    assert!(judged.drifts() && !judged.over());
    // A limit given below the drift (along the thread, inch) refuses it.
    let rule = DriftRule {
        max: Some(0.00006),
        source_units: threadcut::units::Units::Mm,
    };
    assert!(LeadDrift::judge(r, &job, &rule).over());
    job.lead.lead = 2.54;
    let r = threadcut::translate::lead_rounding(&omniturn, d.as_ref(), &job);
    assert!(
        (r.written - 0.1).abs() < 1e-12 && r.over_length < 1e-12,
        "{r:?}"
    );
}
