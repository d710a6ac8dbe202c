//! Sinumerik (`--controller sinumerik`): CYCLE97's pass tables computed by hand for every VARI mode,
//! both systems of units (G70/G71/G700/G710), internal and external, taper and multi-start; each
//! alarm at its line and column; G33 with SF; programs written the way Sinumerik shops write them;
//! and `expand` reading back to the same motion, start angles included.
//! Decisions: docs/dialects/sinumerik.md.

use threadcut::diag::{Code, Diagnostic, Severity};
use threadcut::machine::Machine;
use threadcut::program::{self, Event};
use threadcut::thread::{Infeed, Job, PassKind, Side, StartIndexing};
use threadcut::toolpath::{self, MotionKind};
use threadcut::units::{Pos, Units};

fn sinumerik() -> Machine {
    Machine::built_in("sinumerik").unwrap()
}

fn jobs(src: &str) -> Vec<Job> {
    program::jobs(src.as_bytes(), &sinumerik()).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

fn job(src: &str) -> Job {
    let mut all = jobs(src);
    assert_eq!(all.len(), 1, "{src}");
    all.remove(0)
}

fn error(src: &str) -> Diagnostic {
    match program::jobs(src.as_bytes(), &sinumerik()) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an input error, got {other:?}\n{src}"),
    }
}

fn warnings(src: &str) -> Vec<Diagnostic> {
    program::run(src.as_bytes(), &sinumerik(), |_, _| Ok(()))
        .unwrap()
        .warnings
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

/// Depths (program units, radial) and X infeed points (diameter, program units) of every pass.
fn table(job: &Job) -> Vec<(PassKind, f64, f64, f64)> {
    let u = job.units;
    job.passes()
        .unwrap()
        .iter()
        .map(|p| {
            (
                p.kind,
                u.from_mm(p.depth),
                u.from_mm(p.start.x) * 2.0,
                u.from_mm(p.start.z),
            )
        })
        .collect()
}

fn assert_table(job: &Job, want: &[(PassKind, f64, f64, f64)], tol: f64) {
    let got = table(job);
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert_eq!(g.0, w.0, "pass {}", i + 1);
        assert!(
            close(g.1, w.1, tol) && close(g.2, w.2, tol) && close(g.3, w.3, tol),
            "pass {}: got {g:?}, want {w:?}",
            i + 1
        );
    }
}

use PassKind::{Finish as F, Rough as R};

#[test]
fn vari_1_external_constant_infeed_metric_g71() {
    // M30x2 on a 30 mm blank: TDEP 1.2, FAL 0.1, NRC 4, NID 1. Roughing 1.1 in four equal steps
    // of 0.275; the allowance in one cut to 1.2, then one idle pass. X = 30 − 2·depth.
    let job =
        job("G71 DIAMON\nT1 D1\nG0 X40 Z10\nCYCLE97(2,,0,-30,30,30,3,2,1.2,0.1,0,0,4,1,1,1)\n");
    assert_eq!(job.units, Units::Mm);
    assert_eq!(job.geometry.side, Side::External);
    assert_eq!(job.infeed, Infeed::Radial);
    assert_table(
        &job,
        &[
            (R, 0.275, 29.45, 3.0),
            (R, 0.55, 28.9, 3.0),
            (R, 0.825, 28.35, 3.0),
            (R, 1.1, 27.8, 3.0),
            (F, 1.2, 27.6, 3.0),
            (F, 1.2, 27.6, 3.0),
        ],
        1e-9,
    );
    // The whole path: G0 to the start point (1 mm above the diameter, at the run-in path APP 3
    // before SPL), then each pass in, G33 to the run-out path ROP 2 past FPL, out, back.
    let path = toolpath::build(&job).unwrap();
    assert_eq!(path.start, Pos::new(20.0, 10.0));
    assert_eq!(path.motions.len(), 1 + 6 * 4);
    let m = &path.motions;
    assert_eq!(
        (m[0].kind, m[0].to),
        (MotionKind::Rapid, Pos::new(16.0, 3.0))
    );
    assert_eq!(m[1].to, Pos::new(14.725, 3.0));
    assert_eq!(
        m[2].kind,
        MotionKind::Thread {
            lead: 2.0,
            dlead: 0.0,
            phase_deg: 0.0
        }
    );
    assert_eq!(m[2].to, Pos::new(14.725, -32.0));
    assert_eq!(m[3].to, Pos::new(16.0, -32.0));
    assert_eq!(m[4].to, Pos::new(16.0, 3.0));
    // The cycle leaves the tool at its start point.
    assert_eq!(path.end(), Pos::new(16.0, 3.0));
    assert_eq!(job.end_point(), Pos::new(16.0, 3.0));
}

#[test]
fn vari_3_external_constant_cross_section_metric_g710() {
    // M24x1.5: TDEP 0.92, FAL 0.05, NRC 6, NID 2. Constant cross-section: d_n = 0.87·√(n/6),
    // worked out by hand: 0.87/√6 = 0.355176, 0.87/√3 = 0.502295, 0.87/√2 = 0.615183,
    // 0.87·√(2/3) = 0.710352, 0.87·√(5/6) = 0.794198, 0.87.
    let job = job("G710\nG0 X30 Z5\nCYCLE97(1.5,,0,-30,24,24,4,2,0.92,0.05,0,0,6,2,3,1)\n");
    let d = [0.355176, 0.502295, 0.615183, 0.710352, 0.794198, 0.87];
    let mut want: Vec<_> = d.iter().map(|&d| (R, d, 24.0 - 2.0 * d, 4.0)).collect();
    want.extend([(F, 0.92, 22.16, 4.0); 3]);
    assert_table(&job, &want, 1e-6);
    // Equal chip areas over the roughing cuts (a sharp 60° V: area ∝ d²).
    let passes = job.passes().unwrap();
    for p in &passes[1..6] {
        assert!(close(p.area, passes[0].area, 1e-12), "{passes:?}");
    }
}

#[test]
fn vari_2_internal_constant_infeed_inch_g70() {
    // 1"-8 internal on a 0.8647" tap hole: TDEP 0.0677", FAL 0.003", NRC 5, NID 1. Roughing
    // 0.0647" in steps of 0.01294"; X grows from the tap-hole diameter. The start point lies
    // 1 mm (0.03937") below the tap hole whatever the units: radius 0.43235 − 0.03937.
    let job = job(
        "G70\nG0 X0.5 Z1\nCYCLE97(0.125,,0,-1,0.8647,0.8647,0.2,0.1,0.0677,0.003,0,0,5,1,2,1)\n",
    );
    assert_eq!(job.units, Units::Inch);
    assert_eq!(job.geometry.side, Side::Internal);
    assert!(close(job.lead.lead, 3.175, 1e-12));
    assert_table(
        &job,
        &[
            (R, 0.01294, 0.89058, 0.2),
            (R, 0.02588, 0.91646, 0.2),
            (R, 0.03882, 0.94234, 0.2),
            (R, 0.05176, 0.96822, 0.2),
            (R, 0.0647, 0.9941, 0.2),
            (F, 0.0677, 1.0001, 0.2),
            (F, 0.0677, 1.0001, 0.2),
        ],
        1e-9,
    );
    let retract = job.end_point();
    assert!(close(retract.x, 0.43235 * 25.4 - 1.0, 1e-9), "{retract:?}");
    assert!(close(retract.z, 0.2 * 25.4, 1e-9));
    // The thread move runs to the run-out path: FPL −1" − ROP 0.1".
    let path = toolpath::build(&job).unwrap();
    assert!(close(path.motions[2].to.z, -1.1 * 25.4, 1e-9));
}

#[test]
fn vari_4_internal_constant_cross_section_inch_g700_and_back_to_mm() {
    // G700 inch: TDEP 0.04", FAL 0, NRC 4 → d_n = 0.04·√(n/4) = 0.02, 0.028284, 0.034641, 0.04
    // (by hand: 0.04·0.707107, 0.04·0.866025), then the finishing cut at 0.04 (no allowance to
    // remove) and no idle pass. A later G710 cycle is in mm again.
    let src = "G700\nG0 X0.3 Z0.5\nCYCLE97(0.05,,0,-0.5,0.4,0.4,0.1,0.05,0.04,0,0,0,4,0,4,1)\nG710\nG0 X20 Z5\nCYCLE97(1,,0,-10,10,10,2,1,0.6,0,0,0,2,0,4,1)\n";
    let all = jobs(src);
    assert_eq!((all[0].units, all[1].units), (Units::Inch, Units::Mm));
    assert_table(
        &all[0],
        &[
            (R, 0.02, 0.44, 0.1),
            (R, 0.028284, 0.456569, 0.1),
            (R, 0.034641, 0.469282, 0.1),
            (R, 0.04, 0.48, 0.1),
            (F, 0.04, 0.48, 0.1),
        ],
        5e-7,
    );
    // 0.6·√(1/2) = 0.424264, 0.6.
    assert_table(
        &all[1],
        &[
            (R, 0.424264, 10.848528, 2.0),
            (R, 0.6, 11.2, 2.0),
            (F, 0.6, 11.2, 2.0),
        ],
        5e-7,
    );
}

#[test]
fn mpit_gives_the_iso_coarse_pitch_and_may_repeat_pit() {
    // MPIT 16: M16, pitch 2 mm; PIT 2 with it agrees.
    for args in ["0,16", "2,16", ",16"] {
        let job = job(&format!(
            "G0 X20 Z5\nCYCLE97({args},0,-20,16,16,2,1,1.227,0.05,0,0,5,1,3,1)\n"
        ));
        assert_eq!(job.lead.lead, 2.0, "{args}");
    }
    // In an inch program MPIT is still a metric size.
    let job =
        job("G70\nG0 X1 Z0.2\nCYCLE97(,12,0,-0.8,0.4724,0.4724,0.1,0.05,0.0425,0,0,0,5,0,3,1)\n");
    assert_eq!(job.lead.lead, 1.75);
}

#[test]
fn taper_thread_follows_the_line_through_dm1_and_dm2() {
    // DM1 20 at Z0, DM2 22 at Z−20: the radius grows 0.05 per mm toward −Z. With the run-in 2
    // and run-out 2 the crest runs from radius 9.9 at Z2 to 11.1 at Z−22. VARI 1, TDEP 0.92,
    // FAL 0, NRC 4: steps 0.23. The start point is 1 mm above the larger end: X = 2·12.1.
    let job = job("G0 X30 Z5\nCYCLE97(1.5,,0,-20,20,22,2,2,0.92,0,0,0,4,0,1,1)\n");
    assert!(close(job.geometry.taper(), 9.9 - 11.1, 1e-12));
    assert_table(
        &job,
        &[
            (R, 0.23, 19.34, 2.0),
            (R, 0.46, 18.88, 2.0),
            (R, 0.69, 18.42, 2.0),
            (R, 0.92, 17.96, 2.0),
            (F, 0.92, 17.96, 2.0),
        ],
        1e-9,
    );
    let path = toolpath::build(&job).unwrap();
    assert!(close(path.motions[0].to.x, 12.1, 1e-12));
    // Pass 1's G33 ends at the larger diameter, 2·(11.1 − 0.23).
    assert!(close(path.motions[2].to.x * 2.0, 21.74, 1e-9));
    assert!(close(path.motions[2].to.z, -22.0, 1e-12));
    // A negative IANG on a taper infeeds along one flank (alternating is for cylinders only).
    let job = self::job("G0 X30 Z5\nCYCLE97(1.5,,0,-20,20,22,2,2,0.92,0,-29,0,4,0,1,1)\n");
    assert!(matches!(job.infeed, Infeed::Flank { angle_deg, .. } if angle_deg == 29.0));
}

#[test]
fn iang_positive_infeeds_along_one_flank_negative_alternates() {
    // TDEP 1, FAL 0, NRC 4, VARI 1: depths 0.25, 0.5, 0.75, 1. Cut toward −Z from Z0 (APP 0).
    // Positive IANG 30: shallower passes start behind (toward +Z) by (1 − d)·tan 30°, the
    // full-depth passes at Z0.
    let t = 30f64.to_radians().tan();
    let z = |src: &str| -> Vec<f64> { table(&job(src)).iter().map(|r| r.3).collect() };
    let single = z("G0 X30 Z5\nCYCLE97(2,,0,-20,24,24,0,0,1,0,30,0,4,0,1,1)\n");
    let want = [0.75 * t, 0.5 * t, 0.25 * t, 0.0, 0.0];
    for (g, w) in single.iter().zip(want) {
        assert!(close(*g, w, 1e-12), "{single:?}");
    }
    // Negative: odd passes on the rear flank, even passes on the front flank, (1 − d)·tan 30°
    // ahead of the groove's axis; the finishing cut on the axis.
    let alternating = z("G0 X30 Z5\nCYCLE97(2,,0,-20,24,24,0,0,1,0,-30,0,4,0,1,1)\n");
    let want = [0.75 * t, -0.5 * t, 0.25 * t, 0.0, 0.0];
    for (g, w) in alternating.iter().zip(want) {
        assert!(close(*g, w, 1e-12), "{alternating:?}");
    }
    // Cutting toward +Z mirrors it: shallower passes start at lower Z.
    let up = z("G0 X30 Z-25\nCYCLE97(2,,-20,0,24,24,0,0,1,0,30,0,4,0,1,1)\n");
    assert!(close(up[0], -20.0 - 0.75 * t, 1e-12), "{up:?}");
}

#[test]
fn multi_start_by_numt_turns_the_spindle_and_cuts_each_start_whole() {
    // Three starts, lead 6 (pitch 2), first start at NSP 30°: starts at 30°, 150°, 270°, each
    // cut completely (all passes) before the next, all from the same Z.
    let job = job("G0 X40 Z10\nCYCLE97(6,,0,-20,30,30,2,2,1.2,0,0,30,4,0,1,3)\n");
    assert_eq!(job.lead.starts, 3);
    assert_eq!(job.lead.indexing, StartIndexing::Angle);
    let path = toolpath::build(&job).unwrap();
    let threads: Vec<(u32, f64, Pos)> = path
        .segments()
        .filter_map(|(from, m)| match m.kind {
            MotionKind::Thread { phase_deg, .. } => Some((m.pass, phase_deg, from)),
            _ => None,
        })
        .collect();
    assert_eq!(threads.len(), 3 * 5);
    for (i, &(pass, phase, from)) in threads.iter().enumerate() {
        assert_eq!(pass, (i % 5) as u32 + 1);
        assert_eq!(phase, [30.0, 150.0, 270.0][i / 5]);
        assert_eq!(from.z, 2.0);
    }
    // Single start: NUMT 0 and 1 are the same.
    let one = self::job("G0 X40 Z10\nCYCLE97(2,,0,-20,30,30,2,2,1.2,0,0,90,4,0,1,0)\n");
    assert_eq!((one.lead.starts, one.lead.phase_deg), (1, 90.0));
}

#[test]
fn parameters_set_earlier_are_cycle_arguments() {
    // R parameters and DEF variables, with signs, as shops write their thread tables.
    let src = "DEF REAL PITCH=1.5, DEPTH\nDEPTH=0.92\nR10=30 R11=-30 R12=24\nG0 X30 Z5\nCYCLE97(PITCH,,0,R11,R12,R12,4,2,DEPTH,0.05,30,0,6,2,3,1)\n";
    let a = job(src);
    let b = job("G0 X30 Z5\nCYCLE97(1.5,,0,-30,24,24,4,2,0.92,0.05,30,0,6,2,3,1)\n");
    assert_eq!(a.geometry, b.geometry);
    assert_eq!(a.lead, b.lead);
    assert_eq!(a.passes().unwrap(), b.passes().unwrap());
    // A parameter the program never set lives on the control: refused where it is used.
    let e = error("G0 X30 Z5\nCYCLE97(R7,,0,-30,24,24,4,2,0.92,0.05,30,0,6,2,3,1)\n");
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::Unsupported, 2, 9)
    );
    assert!(e.message.contains("R7 is not set"), "{}", e.message);
    // An expression in a setting is computed (tests/sinumerik_flow.rs); in a cycle's argument
    // it is refused at its operator.
    let e = error("G0 X30 Z5\nCYCLE97(R1+0.5,,0,-30,24,24,4,2,0.92,0.05,30,0,6,2,3,1)\n");
    assert_eq!((e.span.line, e.span.column), (2, 11));
}

/// The alarms of the cycle and threadcut's own errors, each at its line and column.
#[test]
fn alarms_at_their_line_and_column() {
    let head = "N10 G0 X30 Z5\n";
    let at = |call: &str| -> (Code, u32, u32, String) {
        let e = error(&format!("{head}{call}\n"));
        (e.code, e.span.line, e.span.column, e.message)
    };
    // 61001: PIT and MPIT contradict (at MPIT), neither is given (at PIT, or the name when
    // empty), MPIT is no thread size, PIT is negative.
    let (code, line, col, msg) = at("N20 CYCLE97(1.5,16,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)");
    assert_eq!((code, line, col), (Code::OutOfRange, 2, 17));
    assert!(msg.contains("61001") && msg.contains("contradict"), "{msg}");
    let (_, _, col, msg) = at("N20 CYCLE97(0,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)");
    assert_eq!(col, 13);
    assert!(
        msg.starts_with("CYCLE97 alarm 61001 \"Thread pitch incorrectly defined\""),
        "{msg}"
    );
    let (_, _, col, _) = at("N20 CYCLE97(,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)");
    assert_eq!(col, 5);
    let (_, _, col, msg) = at("N20 CYCLE97(,13,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)");
    assert_eq!(col, 14);
    assert!(msg.contains("MPIT 13"), "{msg}");
    let (_, _, col, _) = at("N20 CYCLE97(-1.5,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)");
    assert_eq!(col, 13);
    // 61002: VARI outside 1–4, at VARI; left out, at the cycle's name.
    let (code, _, col, msg) = at("N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,5,1)");
    assert_eq!((code, col), (Code::OutOfRange, 46));
    assert!(
        msg.contains("61002 \"Machining type incorrectly defined\""),
        "{msg}"
    );
    let (_, _, col, _) = at("N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1)");
    assert_eq!(col, 5);
    // 61000: the tool offset deselected with D0.
    let e = error("T1 D0\nG0 X30 Z5\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\n");
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Conflict, 3, 1));
    assert!(
        e.message.contains("61000 \"No tool offset active\""),
        "{}",
        e.message
    );
    // … and active again with D1 or a tool change.
    assert_eq!(
        jobs("D0\nT2\nG0 X30 Z5\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\n").len(),
        1
    );
    // threadcut's own: no depth, allowance not below the depth, no roughing cut, a fractional
    // count, no length, a face thread, a start angle out of range, a negative run-in.
    for (call, col, code) in [
        (
            "N20 CYCLE97(2,,0,-20,16,16,2,1,0,0,0,0,5,1,3,1)",
            32,
            Code::MissingWord,
        ),
        (
            "N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,1.2,0,0,5,1,3,1)",
            36,
            Code::Geometry,
        ),
        (
            "N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,0,1,3,1)",
            42,
            Code::OutOfRange,
        ),
        (
            "N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5.5,1,3,1)",
            42,
            Code::OutOfRange,
        ),
        (
            "N20 CYCLE97(2,,0,0,16,16,2,1,1.2,0,0,0,5,1,3,1)",
            18,
            Code::Geometry,
        ),
        (
            "N20 CYCLE97(2,,0,-2,16,30,2,1,1.2,0,0,0,5,1,3,1)",
            24,
            Code::Unsupported,
        ),
        (
            "N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,360,5,1,3,1)",
            40,
            Code::OutOfRange,
        ),
        (
            "N20 CYCLE97(2,,0,-20,16,16,-2,1,1.2,0,0,0,5,1,3,1)",
            28,
            Code::OutOfRange,
        ),
        (
            "N20 CYCLE97(2,,0,-20,0,0,2,1,1.2,0,0,0,5,1,3,1)",
            22,
            Code::OutOfRange,
        ),
    ] {
        let (c, line, column, msg) = at(call);
        assert_eq!((c, line, column), (code, 2, col), "{call}: {msg}");
    }
    // Too many parameters: at the eighteenth.
    let (_, _, col, _) = at("N20 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1,0,7)");
    assert_eq!(col, 52);
    // The cycle stands in a block of its own.
    let (code, _, col, _) = at("N20 G0 CYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)");
    assert_eq!((code, col), (Code::Conflict, 5));
}

#[test]
fn moves_threadcut_does_not_follow_are_refused_not_guessed() {
    for (src, col) in [
        ("G0 X20 Z5\nG34 Z-20 K1.5 F0.01\n", 1),
        ("G0 X20 Z5\nN5 G331 Z-20 K1.5\n", 4),
        ("G0 X20 Z5\nG91 G63 Z-20 F300\n", 5),
        ("G0 X20 Z5\nROT RPL=10\n", 1),
    ] {
        let e = error(src);
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (Code::Unsupported, 2, col),
            "{src}"
        );
    }
    // A name alone in its block is a call of the subprogram of that name: not in the file and
    // no include directory given, the control's alarm 14011.
    for (src, file) in [
        ("G0 X20 Z5\nMYSUB\n", "MYSUB.SPF"),
        ("G0 X20 Z5\nL100\n", "L100.SPF"),
    ] {
        let e = error(src);
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (Code::MissingWord, 2, 1),
            "{src}"
        );
        assert!(e.message.contains("alarm 14011"), "{}", e.message);
        assert!(
            e.hint.as_deref().is_some_and(|h| h.contains(file)),
            "{:?}",
            e.hint
        );
    }
}

#[test]
fn settings_that_move_nothing_pass_through() {
    // A machine start-up block, the spindle, the fixed point for a tool change, a message.
    let src = "TRAFOOF\nG18 G90 G95 G54 G64 SOFT\nSETMS(1)\nG96 S180 LIMS=2800 M3\nS1=500 M1=4\nMSG(\"THREAD M24 (EXTERNAL)\")\nG75 FP=2 X1=0 Z1=0\nG0 X30 Z5\nCYCLE97(1.5,,0,-20,24,24,2,1,0.92,0,0,0,4,0,3,1)\nMSG()\n";
    let job = job(src);
    assert_eq!(job.start, Pos::new(15.0, 5.0));
    let mut out = Vec::new();
    program::expand_gcode(src.as_bytes(), &mut out, &sinumerik()).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.starts_with("TRAFOOF\nG18 G90 G95 G54 G64 SOFT\nSETMS(1)\n"),
        "{text}"
    );
    assert!(text.ends_with("MSG()\n"), "{text}");
}

#[test]
fn cycle99_is_refused_with_the_reason() {
    let e = error("G0 X30 Z5\nCYCLE99(0,24,-30,24,2,1,0.92,0.05,30,0,6,2,1.5,1300101,1)\n");
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::Unsupported, 2, 1)
    );
    assert!(e.hint.unwrap().contains("CYCLE97"));
}

#[test]
fn warnings_for_a_steep_infeed_and_an_unknown_start() {
    let w = warnings("G0 X30 Z5\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,35,0,5,1,3,1)\n");
    assert_eq!(w.len(), 1);
    assert_eq!((w[0].code, w[0].span.column), (Code::Suspicious, 34));
    // After a reference point approach the position is unknown: the cycle starts at its own
    // start point, with a warning.
    let src = "G74 X1=0 Z1=0\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\n";
    let w = warnings(src);
    assert!(w
        .iter()
        .any(|w| w.code == Code::UnknownPosition && w.severity == Severity::Warning));
    assert_eq!(job(src).start, Pos::new(9.0, 2.0));
}

#[test]
fn g33_with_sf_and_the_modal_start_angle() {
    // SF= sets the start angle (setting data 42000) for this and later G33 blocks; K is the pitch
    // along Z, I along X for a move steeper than 45°.
    let src = "G0 X20 Z5\nG33 Z-20 K1.5 SF=90\nG0 X22\nZ5\nX19.8\nG33 Z-20 K1.5\nG0 X30 Z5\nG33 X40 Z4 I2\n";
    let mut moves = vec![];
    program::run(src.as_bytes(), &sinumerik(), |_, ev| {
        if let Event::Plain { mv: Some(mv), .. } = ev {
            if let Some(lead) = mv.lead {
                moves.push((mv.to, lead, mv.phase_deg));
            }
        }
        Ok(())
    })
    .unwrap();
    assert_eq!(
        moves,
        [
            (Pos::new(10.0, -20.0), 1.5, 90.0),
            (Pos::new(9.9, -20.0), 1.5, 90.0),
            (Pos::new(20.0, 4.0), 2.0, 90.0),
        ]
    );
    let e = error("G0 X20 Z5\nG33 Z-20 K1.5 SF=360\n");
    assert_eq!((e.code, e.span.column), (Code::OutOfRange, 18));
    let e = error("G0 X20 Z5\nG33 X40 Z4 I2 K1\n");
    assert_eq!((e.code, e.span.column), (Code::Conflict, 12));
}

#[test]
fn diamof_and_diam90_read_x_on_radius() {
    let at = |src: &str| {
        let mut last = None;
        program::run(src.as_bytes(), &sinumerik(), |m, _| {
            last = m.position.known();
            Ok(())
        })
        .unwrap();
        last.unwrap()
    };
    assert_eq!(at("DIAMOF\nG0 X20 Z5\n"), Pos::new(20.0, 5.0));
    assert_eq!(at("DIAMON\nG0 X20 Z5\n"), Pos::new(10.0, 5.0));
    // DIAM90: absolute X on diameter, incremental X on radius.
    assert_eq!(at("DIAM90\nG0 X20 Z5\nG91 G1 X-2\n"), Pos::new(8.0, 5.0));
    assert_eq!(
        at("DIAM90\nG0 X20 Z5\nG91 G1 X-2\nG90 X30\n"),
        Pos::new(15.0, 5.0)
    );
    // DM1/DM2 are diameters whatever the mode.
    let a = job("DIAMOF\nG0 X20 Z5\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\n");
    let b = job("G0 X40 Z5\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\n");
    assert_eq!(a.geometry, b.geometry);
}

/// A program written as a Sinumerik shop writes one: the control's file header, a blank for the
/// simulation, tools by name, constant cutting speed with a speed limit, comments, a grooving
/// cycle passed through, R parameters for the thread, and the thread cycle.
const SHOP: &str = "%_N_SHAFT_M24_MPF
;$PATH=/_N_WKS_DIR/_N_SHAFT_WPD
; SHAFT 24 -- THREAD M24x1.5 -- 6g
N10 G18 G90 G95 G71 DIAMON
N20 WORKPIECE(,\"\",,\"CYLINDER\",0,0,-80,-80,30)
N30 T=\"ROUGHING_80\" D1
N40 G96 S220 LIMS=3000 M4
N50 G0 X32 Z2 M8
N60 CYCLE93(24,-30,3,1.5,0,0,0,0,0,0,0,0.2,0.2,1,0,5,1)
N70 G0 X100 Z100
N80 T=\"THREAD_EXT_1.5\" D1 ; 60 deg insert
N90 G97 S1000 M3
N100 R1=1.5 ; pitch
N110 R2=0.92 ; thread depth
N120 G0 X30 Z8
N130 CYCLE97(R1,,0,-35,24,24,4,2,R2,0.05,29,0,8,2,3,1)
N140 G0 X100 Z100 M9
N150 M30
";

#[test]
fn a_shop_program_expands_and_passes_everything_else_through() {
    let job = job(SHOP);
    assert_eq!(job.line, 16);
    assert_eq!(job.start, Pos::new(15.0, 8.0));
    let mut out = Vec::new();
    program::expand_gcode(SHOP.as_bytes(), &mut out, &sinumerik()).unwrap();
    let text = String::from_utf8(out).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Every line but the cycle's is copied byte for byte, in order.
    let kept: Vec<&str> = SHOP.lines().filter(|l| !l.contains("CYCLE97")).collect();
    let mut at = 0;
    for l in &lines {
        if at < kept.len() && *l == kept[at] {
            at += 1;
        }
    }
    assert_eq!(at, kept.len(), "{text}");
    assert!(text.contains(
        "; threadcut: sinumerik cycle of line 16 as 8 rough passes and 3 finishing passes"
    ));
    assert!(text.contains("G33 X"), "{text}");
    assert!(text.contains(" K1.5000 SF=0.0000\n"), "{text}");
    assert!(!text.contains("CYCLE97"));
}

/// Every synchronised move of a program (from, to, lead, start angle), from plain blocks and
/// cycles alike: the start angle of a move that begins a chain of thread moves.
fn thread_moves(src: &str) -> Vec<(Pos, Pos, f64, f64)> {
    let mut moves = Vec::new();
    program::run(src.as_bytes(), &sinumerik(), |_, ev| {
        match ev {
            Event::Plain { mv: Some(mv), .. } if mv.lead.is_some() => {
                let from = mv.from.known().expect("a thread move from a known start");
                moves.push((from, mv.to, mv.lead.unwrap(), mv.phase_deg))
            }
            Event::Cycle { job, .. } => {
                for (from, m) in toolpath::build(&job)?.segments() {
                    if let MotionKind::Thread {
                        lead, phase_deg, ..
                    } = m.kind
                    {
                        moves.push((from, m.to, lead, phase_deg));
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

/// The bundled Sinumerik examples.
fn examples() -> Vec<String> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/examples");
    let mut found: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_str()
                .unwrap()
                .starts_with("sinumerik-")
        })
        .map(|p| std::fs::read_to_string(p).unwrap())
        .collect();
    found.sort();
    assert!(found.len() >= 2);
    found
}

#[test]
fn expansions_read_back_to_the_same_motion_with_their_start_angles() {
    let examples = examples();
    for src in [
        SHOP,
        examples[0].as_str(),
        examples[1].as_str(),
        // Multi-start, alternating infeed, inch, internal, taper, DIAMOF, DIAM90 under G91.
        "G0 X40 Z10\nCYCLE97(6,,0,-20,30,30,2,2,1.2,0.05,-29,30,4,1,3,3)\n",
        "G70\nG0 X0.5 Z1\nCYCLE97(0.125,,0,-1,0.8647,0.8647,0.2,0.1,0.0677,0.003,29.5,45,5,1,2,2)\n",
        "G0 X30 Z5\nCYCLE97(1.5,,0,-20,20,22,2,2,0.92,0,0,0,4,0,1,1)\n",
        "DIAMOF\nG0 X20 Z5\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\nG1 X15\n",
        "DIAM90\nG0 X40 Z5\nG91\nCYCLE97(2,,0,-20,16,16,2,1,1.2,0,0,0,5,1,3,1)\nG1 X-2\n",
    ] {
        let mut out = Vec::new();
        program::expand_gcode(src.as_bytes(), &mut out, &sinumerik()).unwrap();
        let expanded = String::from_utf8(out).unwrap();
        let (a, b) = (thread_moves(src), thread_moves(&expanded));
        assert_eq!(a.len(), b.len(), "{src}\n---\n{expanded}");
        // X on diameter to 0.001 mm (0.0001 inch): within half a step on the radius.
        let tol = if src.contains("G70") { 0.0001 * 25.4 / 2.0 } else { 0.0005 } + 1e-9;
        for (x, y) in a.iter().zip(&b) {
            let same = |p: Pos, q: Pos| close(p.x, q.x, tol) && close(p.z, q.z, tol);
            assert!(same(x.0, y.0) && same(x.1, y.1), "{x:?} vs {y:?}\n{expanded}");
            assert!(close(x.2, y.2, 1e-6), "lead {x:?} vs {y:?}");
            assert!(close(x.3, y.3, 5e-5), "start angle {x:?} vs {y:?}");
        }
        // The positions after the program agree too (the cycle leaves the tool at its start).
        let end = |s: &str| {
            let mut last = None;
            program::run(s.as_bytes(), &sinumerik(), |m, _| {
                last = m.position.known();
                Ok(())
            })
            .unwrap();
            last
        };
        let (p, q) = (end(src).unwrap(), end(&expanded).unwrap());
        assert!(close(p.x, q.x, tol) && close(p.z, q.z, tol), "{p:?} vs {q:?}\n{expanded}");
    }
}

#[test]
fn a_start_angle_is_never_dropped_by_a_controller_that_cannot_write_it() {
    // LinuxCNC's G33 has no start angle in threadcut: a multi-start thread indexed by the
    // spindle is refused rather than written as one start cut three times.
    let job = job("G0 X40 Z10\nCYCLE97(6,,0,-20,30,30,2,2,1.2,0,0,0,4,0,1,3)\n");
    let linuxcnc = Machine::built_in("linuxcnc").unwrap();
    let e = threadcut::translate::job_to_string(&linuxcnc, &job).unwrap_err();
    assert!(e.to_string().contains("turning the spindle"), "{e}");
    // Fanuc's G32 takes Q: each start's passes begin with its angle (Q not modal: none at 0°).
    let fanuc = Machine::built_in("fanuc").unwrap();
    let (text, _) = threadcut::translate::job_to_string(&fanuc, &job).unwrap();
    let runs = text.lines().filter(|l| l.starts_with("G32")).count();
    let q = |count: &str| text.lines().filter(|l| l.ends_with(count)).count();
    assert!(runs > 0 && q(" Q120000") > 0, "{text}");
    assert_eq!(q(" Q120000"), q(" Q240000"), "{text}");
    let qs = text
        .lines()
        .filter(|l| !l.starts_with('('))
        .map(|l| l.matches(" Q").count());
    assert_eq!(qs.sum::<usize>(), 2 * q(" Q120000"), "{text}");
    // A single start at angle 0 translates.
    let job = self::job("G0 X40 Z10\nCYCLE97(2,,0,-20,30,30,2,2,1.2,0,0,0,4,0,1,1)\n");
    let (text, _) = threadcut::translate::job_to_string(&fanuc, &job).unwrap();
    assert!(text.contains("G32") && !text.contains(" Q"), "{text}");
}
