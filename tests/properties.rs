//! Properties every controller's cycles must have, over random valid cycles: the toolpath starts
//! at the cycle's start point and ends at its end point, thread moves carry the cycle's lead, the last pass reaches
//! full depth, and reading the expanded program back reproduces every synchronised move within the
//! output resolution. One harness, one generator per controller.

use proptest::prelude::*;

use threadcut::machine::Machine;
use threadcut::program::{self, Event};
use threadcut::toolpath::{self, MotionKind};
use threadcut::units::Pos;

/// A synchronised move: from, to, lead (mm, along its longer axis).
type ThreadMove = (Pos, Pos, f64);

/// Every synchronised move a program makes, from plain blocks and cycles alike.
fn thread_moves(src: &str, machine: &Machine) -> Vec<ThreadMove> {
    let mut moves = Vec::new();
    program::run(src.as_bytes(), machine, |_, ev| {
        match ev {
            Event::Plain { mv: Some(mv), .. } if mv.lead.is_some() => {
                // Thread moves in these programs start from a known point.
                moves.push((mv.from.known().unwrap(), mv.to, mv.lead.unwrap()))
            }
            Event::Cycle { job, .. } => {
                let path = toolpath::build(&job)?;
                for (from, m) in path.segments() {
                    if let MotionKind::Thread { lead, .. } = m.kind {
                        moves.push((from, m.to, lead));
                    }
                }
            }
            _ => {}
        }
        Ok(())
    })
    .unwrap_or_else(|e| panic!("{e}\n{src}"));
    moves
}

/// The checks, for one controller and one program with one cycle.
fn check(controller: &str, src: &str, tolerance_mm: f64) -> Result<(), TestCaseError> {
    let machine = Machine::built_in(controller).unwrap();
    let jobs = program::jobs(src.as_bytes(), &machine)
        .map_err(|e| TestCaseError::fail(format!("{e}\n{src}")))?;
    prop_assert_eq!(jobs.len(), 1);
    let job = &jobs[0];
    let passes = job.passes().unwrap();
    let path = toolpath::build(job).unwrap();
    prop_assert_eq!(path.start, job.start);
    // Fanuc-style cycles end where they started; LinuxCNC's G76 at the end of its drive line.
    prop_assert_eq!(
        path.end(),
        job.end_point(),
        "the cycle must end at its end point\n{}",
        src
    );
    prop_assert_eq!(passes.last().unwrap().depth, job.geometry.depth);
    for (from, m) in path.segments() {
        prop_assert!(m.to.is_finite());
        if let MotionKind::Thread { lead, .. } = m.kind {
            let d = m.to.minus(from);
            if d.z == 0.0 {
                // A radial synchronised move (a screw-in) has no Z rate to compare.
                continue;
            }
            // Along Z the lead is the cycle's; a steeper move keeps Z's rate per revolution.
            let expect = if d.x.abs() <= d.z.abs() {
                job.lead.lead
            } else {
                job.lead.lead * d.x.abs() / d.z.abs()
            };
            prop_assert!(
                (lead - expect).abs() < 1e-9,
                "lead {} vs {}\n{}",
                lead,
                expect,
                src
            );
        }
    }
    // Expand, read the expansion back, compare every synchronised move.
    let mut out = Vec::new();
    program::expand_gcode(src.as_bytes(), &mut out, &machine).unwrap();
    let expanded = String::from_utf8(out).unwrap();
    let original = thread_moves(src, &machine);
    let again = thread_moves(&expanded, &machine);
    prop_assert_eq!(original.len(), again.len(), "{}\n---\n{}", src, expanded);
    for (a, b) in original.iter().zip(&again) {
        let close =
            |p: Pos, q: Pos| (p.x - q.x).abs() <= tolerance_mm && (p.z - q.z).abs() <= tolerance_mm;
        prop_assert!(
            close(a.0, b.0) && close(a.1, b.1),
            "{:?} vs {:?}\n{}\n---\n{}",
            a,
            b,
            src,
            expanded
        );
        prop_assert!((a.2 - b.2).abs() <= tolerance_mm, "lead {} vs {}", a.2, b.2);
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn gsk980_g78(
        external in any::<bool>(),
        root in 10.0..40.0f64,
        height in 0.4..2.5f64,
        first_frac in 0.15..0.9f64,
        length in 10.0..60.0f64,
        mode in 0u32..5,
        angle in prop_oneof![Just(60u32), Just(55), Just(30), Just(0)],
        depth_mode in 0u32..2,
        lead in 0.5..4.0f64,
    ) {
        let a = if external { root + 2.0 * height + 4.0 } else { root - 2.0 * height - 4.0 };
        let src = format!(
            "G0 X{a:.3} Z3\nG78 P01{mode:02}{angle:02} Q0.05 R0.02 D{depth_mode}\nG78 X{root:.3} Z{:.3} P{height:.3} Q{:.3} F{lead:.3} J0.5 K1\n",
            -length,
            height * first_frac
        );
        // X on diameter to 0.001: radius within 0.0005; Z within 0.0005; F to 0.0001.
        check("gsk980", &src, 0.0005 + 1e-9)?;
    }

    #[test]
    fn ab9_g78(
        root in 0.3..1.5f64,
        height in 0.02..0.08f64,
        first_frac in 0.2..0.9f64,
        length in 0.4..2.0f64,
        p in 1u32..5,
        angle in prop_oneof![Just(60u32), Just(29), Just(0)],
        tpi in prop_oneof![Just(8.0f64), Just(13.0), Just(20.0), Just(32.0)],
    ) {
        let start = root + 2.0 * height + 0.1;
        let src = format!(
            "G20\nG90 G00 X{start:.4} Z.2\nG78 X{root:.4} Z{:.4} K{height:.4} D{:.4} E{tpi} A{angle} P{p}\n",
            -length,
            height * first_frac
        );
        // Inch, 4 decimals on diameter: radius within 0.00005" = 0.00127 mm.
        check("ab9", &src, 0.000_05 * 25.4 + 1e-9)?;
    }

    #[test]
    fn fanuc_g76(
        root in 10.0..40.0f64,
        height_um in 400u32..2500,
        first_frac in 0.15..0.9f64,
        length in 10.0..60.0f64,
        chamfer in 0u32..20,
        angle in prop_oneof![Just(60u32), Just(55), Just(29), Just(0)],
        lead in 0.5..4.0f64,
    ) {
        let start = root + 2.0 * f64::from(height_um) / 1000.0 + 4.0;
        let first_um = (f64::from(height_um) * first_frac) as u32 + 1;
        let src = format!(
            "G21 G99\nG97 S600 M3\nG0 X{start:.3} Z5.\nG76 P01{chamfer:02}{angle:02} Q50 R0.02\nG76 X{root:.3} Z{:.3} P{height_um} Q{first_um} F{lead:.3}\n",
            -length
        );
        check("fanuc", &src, 0.0005 + 1e-9)?;
    }

    #[test]
    fn linuxcnc_g76(
        external in any::<bool>(),
        pitch in 0.5..3.0f64,
        start_gap in 0.3..1.5f64,
        first in 0.05..0.4f64,
        full_frac in 0.4..1.0f64,
        r in prop_oneof![Just(1.0f64), Just(1.5), Just(2.0), Just(2.5)],
        q in prop_oneof![Just(0.0f64), Just(29.5)],
        h in 0u32..3,
        taper in prop_oneof![Just(None), (1u32..4, 0.5..3.0f64).prop_map(Some)],
        length in 15.0..60.0f64,
    ) {
        // Radius mode (G8): the drive line is where the tool stands, I is the offset to the crest.
        let x = if external { 12.0 } else { 8.0 };
        let i = if external { -start_gap } else { start_gap };
        let k = pitch * 0.6134 * full_frac + first;
        let mut src = format!(
            "G8 G21 G18\nS500 M3\nG0 X{x} Z5\nG76 P{pitch:.4} Z{:.4} I{i:.4} J{first:.4} K{k:.4} R{r} Q{q} H{h}",
            5.0 - length
        );
        if let Some((l, e)) = taper {
            src.push_str(&format!(" E{e:.4} L{l}"));
        }
        src.push('\n');
        // LinuxCNC writes 4 decimals in mm (profile); radius mode: half a step.
        check("linuxcnc", &src, 0.000_05 + 1e-9)?;
    }

    #[test]
    fn omniturn_g33(
        external in any::<bool>(),
        root in 0.2..0.8f64,
        height in 0.02..0.06f64,
        i in 0.004..0.015f64,
        length in 0.3..1.5f64,
        k in prop_oneof![Just(0.05f64), Just(0.0625), Just(0.1)],
        flags in prop_oneof![Just(""), Just("P"), Just("C"), Just("PC")],
    ) {
        // Values on the control's .00005" grid, as an OmniTurn program is written (an off-grid I moves
        // the retract point 3·I by three times its rounding: a known gap, docs/reliability.md).
        let on_grid = |v: f64| (v / 0.000_05).round() * 0.000_05;
        let (root, height, i, length) = (on_grid(root), on_grid(height), on_grid(i), on_grid(length));
        // Radius mode (G73, the power-on default): the tool starts at the first pass's X.
        let (start, final_x) = if external {
            (root + height - i, root)
        } else {
            (root - height + i, root)
        };
        let src = format!(
            "X0Z.2\nX{start:.5}\nG33X{final_x:.5}Z{:.5}I{i:.5}K{k}{flags}\n",
            -length
        );
        // G36 resolution .00005". OmniTurn has no plain synchronised move, so the expansion restates
        // each pass as a single-pass G33 (docs/dialects/omniturn-g33.md): the pull-out's end is
        // derived from two rounded words, so it may be off by up to one resolution step, not half.
        check("omniturn", &src, 0.000_05 * 25.4 + 1e-6)?;
    }

    #[test]
    fn sinumerik_cycle97(
        vari in 1u32..5,
        inch in any::<bool>(),
        diameter in 10.0..60.0f64,
        taper in prop_oneof![Just(0.0f64), -3.0..3.0f64],
        length in 10.0..60.0f64,
        toward_chuck in any::<bool>(),
        pitch in 0.5..4.0f64,
        fal_frac in 0.0..0.2f64,
        iang in prop_oneof![Just(0.0f64), Just(29.0), Just(-29.0), Just(30.0)],
        nrc in 1u32..12,
        nid in 0u32..3,
        numt in 0u32..4,
        nsp in 0.0..359.0f64,
        app in 0.0..5.0f64,
        rop in 0.0..5.0f64,
    ) {
        // Values in program units: mm under G71, inch under G70 (4 decimals, as written).
        let (code, scale, digits) = if inch { ("G70", 1.0 / 25.4, 4) } else { ("G71", 1.0, 3) };
        let v = |mm: f64| format!("{:.*}", digits, mm * scale);
        let tdep = pitch * 0.6134;
        let (spl, fpl) = if toward_chuck { (0.0, -length) } else { (-length, 0.0) };
        let start_z = if toward_chuck { 10.0 } else { -length - 10.0 };
        let internal = vari % 2 == 0;
        let start_x = if internal { diameter / 3.0 } else { diameter + 10.0 };
        let src = format!(
            "{code} DIAMON\nT1 D1\nG0 X{} Z{}\nCYCLE97({},,{},{},{},{},{},{},{},{},{iang},{nsp:.4},{nrc},{nid},{vari},{numt})\n",
            v(start_x), v(start_z), v(pitch), v(spl), v(fpl), v(diameter), v(diameter + taper),
            v(app), v(rop), v(tdep), v(tdep * fal_frac),
        );
        // X on diameter to 0.001 mm / 0.0001 inch: the radius within half a step.
        let tolerance = if inch { 0.000_05 * 25.4 } else { 0.0005 };
        check("sinumerik", &src, tolerance + 1e-9)?;
    }
}

/// Found by `omniturn_g33`: with I off the .00005" grid, "passes 1 and 2 as one G33" was written with
/// X and I rounded apart, and reading it back added a third, 0.00003" sliver pass.
#[test]
fn omniturn_expansion_never_adds_a_sliver_pass() {
    for src in [
        "X0Z.2\nX0.18952\nG33X0.20000Z-0.30000I0.00952K0.05\n",
        "X0Z.2\nX0.19300\nG33X0.20000Z-0.30000I0.01300K0.05\n",
    ] {
        let machine = Machine::built_in("omniturn").unwrap();
        let mut out = Vec::new();
        program::expand_gcode(src.as_bytes(), &mut out, &machine).unwrap();
        let expanded = String::from_utf8(out).unwrap();
        assert_eq!(
            thread_moves(src, &machine).len(),
            thread_moves(&expanded, &machine).len(),
            "{expanded}"
        );
    }
}
