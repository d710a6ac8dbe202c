//! Fanuc G76/G92/G32 (threading-notes §c.3, §e) and GSK's G76/G92, which share the same code.

use threadcut::diag::Code;
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::thread::{Exit, Job, PassKind};
use threadcut::toolpath::{self, MotionKind};
use threadcut::units::Pos;

fn fanuc() -> Machine {
    Machine::built_in("fanuc").unwrap()
}

fn jobs(src: &str, m: &Machine) -> Vec<Job> {
    program::jobs(src.as_bytes(), m).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

fn error(src: &str, m: &Machine) -> threadcut::diag::Diagnostic {
    match program::jobs(src.as_bytes(), m) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an error, got {other:?}"),
    }
}

const TAN30: f64 = 0.577_350_269_189_625_8;

/// M30×2 external: k = 1.227, Δd = 0.4, Δdmin = 0.1, d = 0.05, m = 2 (threading-notes §c.3).
const M30: &str = "G0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";

#[test]
fn g76_depths_follow_sqrt_n_with_the_minimum_cut_and_allowance() {
    let job = &jobs(M30, &fanuc())[0];
    let passes = job.passes().unwrap();
    let expect = [
        0.4,
        0.4 * 2f64.sqrt(),
        0.4 * 3f64.sqrt(),
        0.8,
        0.9,
        1.0,
        1.1,
        1.177,
        1.227,
        1.227,
    ];
    assert_eq!(passes.len(), expect.len());
    for (p, d) in passes.iter().zip(expect) {
        assert!(
            (p.depth - d).abs() < 1e-12,
            "pass {}: {} vs {d}",
            p.n,
            p.depth
        );
    }
    assert_eq!(
        passes.iter().filter(|p| p.kind == PassKind::Finish).count(),
        2
    );
}

#[test]
fn g76_single_edge_infeed_along_the_flank_ends_at_the_programmed_point() {
    let job = &jobs(M30, &fanuc())[0];
    let path = toolpath::build(job).unwrap();
    // Pass 1: the crest is at radius 15 (root 13.773 + k), first depth 0.4; the pass sits
    // (k − d₁)·tan 30° behind the full-depth pass, which starts at the start point's Z.
    let m = &path.motions;
    assert_eq!(m[0].kind, MotionKind::Rapid);
    assert!((m[0].to.x - 14.6).abs() < 1e-12);
    assert!((m[0].to.z - (5.0 + 0.827 * TAN30)).abs() < 1e-12);
    assert!((m[1].to.z - (-30.0 + 0.827 * TAN30)).abs() < 1e-12);
    // Out to the start X, back to the start Z after each pass.
    assert_eq!(m[2].to, Pos::new(16.0, m[1].to.z));
    assert_eq!(m[3].to, Pos::new(16.0, 5.0));
    // The finishing passes: from (13.773, 5) to (13.773, −30), the programmed end point.
    let last = &m[m.len() - 4..];
    assert!((last[0].to.x - 13.773).abs() < 1e-12 && (last[0].to.z - 5.0).abs() < 1e-12);
    assert!((last[1].to.x - 13.773).abs() < 1e-12 && (last[1].to.z + 30.0).abs() < 1e-12);
    assert_eq!(
        m.len(),
        10 * 4,
        "no extra return: the cycle ends at its start point"
    );
    // The leading edge cuts: every deeper pass starts further toward −Z.
    let starts: Vec<f64> = job.passes().unwrap().iter().map(|p| p.start.z).collect();
    assert!(starts.windows(2).all(|w| w[1] <= w[0]), "{starts:?}");
}

#[test]
fn g76_chamfer_r_is_in_tenths_of_a_lead_at_parameter_5131s_angle() {
    let src = "G0 X32. Z5.\nG76 P011560 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";
    let job = &jobs(src, &fanuc())[0];
    // r = 15: 1.5 leads = 3 mm along Z, 45° (parameter 5131 = 0).
    assert_eq!(
        job.exit,
        Exit::PullOut {
            start_before: 3.0,
            length: 3.0,
            outward: 3.0 * (45f64).to_radians().tan()
        }
    );
    let path = toolpath::build(job).unwrap();
    let m = &path.motions;
    let n = m.len();
    assert!((m[n - 4].to.z + 27.0).abs() < 1e-12);
    assert!((m[n - 3].to.z + 30.0).abs() < 1e-12 && (m[n - 3].to.x - 16.773).abs() < 1e-9);
    // The first block rewrites parameter 5130: a later G92 cuts the same chamfer.
    let src = format!("{src}G92 X29. Z-30.\n");
    let g92 = &jobs(&src, &fanuc())[1];
    assert_eq!(g92.exit, job.exit);
}

#[test]
fn p_and_q_are_least_increments_without_a_decimal_point() {
    // ISB: P1227 is 1.227 mm; inch: P483 is 0.0483 inch.
    let job = &jobs(M30, &fanuc())[0];
    assert_eq!(job.geometry.depth, 1.227);
    let inch = "G20\nG0 X1.3 Z0.2\nG76 P010060 Q40 R0.002\nG76 X1.1034 Z-1. P483 Q150 F0.0625\n";
    let job = &jobs(inch, &fanuc())[0];
    assert!((job.geometry.depth - 0.0483 * 25.4).abs() < 1e-12);
    let e = error(
        "G0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q0.4 F2.\n",
        &fanuc(),
    );
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Syntax, 3, 25));
    assert!(
        e.message.contains("without a decimal point"),
        "{}",
        e.message
    );
    let e = error(
        "G0 X32. Z5.\nG76 P020060 Q0.1 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n",
        &fanuc(),
    );
    assert_eq!((e.span.line, e.span.column), (2, 13));
}

#[test]
fn g76_alarms() {
    let pre = "G0 X32. Z5.\n";
    for (block, code, needle) in [
        (
            "G76 X27.546 Z-30. Q400 F2.",
            Code::MissingWord,
            "P(k) is missing",
        ),
        (
            "G76 X27.546 Z-30. P1227 F2.",
            Code::MissingWord,
            "Q(Δd) is missing",
        ),
        (
            "G76 X27.546 Z-30. P0 Q400 F2.",
            Code::OutOfRange,
            "greater than 0",
        ),
        ("G76 X27.546 Z-30. P1227 Q400", Code::MissingWord, "no lead"),
        ("G76 P020061 Q100", Code::OutOfRange, "tool-tip angle"),
        ("G76 P000060 Q100", Code::OutOfRange, "finishing passes"),
        (
            "G76 X27.546 Z-30. P1227 Q400 E12.",
            Code::Unsupported,
            "E on G76",
        ),
        (
            "G76 X27.546 Z-30. P40 Q400 F2.",
            Code::Geometry,
            "finishing allowance",
        ),
    ] {
        let e = error(&format!("{pre}{block}\n"), &fanuc());
        assert_eq!(e.code, code, "{block}: {}", e.message);
        assert!(e.message.contains(needle), "{block}: {}", e.message);
        assert_eq!(e.span.line, 2);
    }
}

#[test]
fn g92_is_one_box_pass_with_the_parameter_chamfer_and_is_modal() {
    let src = "G0 X40. Z5.\nG92 X29.2 Z-30. F2.\nX28.6\nG4 X1.\nX28.2 R-0.5\nG0 X50.\nX40.\n";
    let js = jobs(src, &fanuc());
    assert_eq!(
        js.len(),
        3,
        "a dwell is not a repeat; the G0 ends the modal G92"
    );
    let path = toolpath::build(&js[0]).unwrap();
    // 5130 = 10: a chamfer of one lead (2 mm) at 45°, then out to X40 and back to Z5.
    let expect = [
        (14.6, 5.0),
        (14.6, -28.0),
        (16.6, -30.0),
        (20.0, -30.0),
        (20.0, 5.0),
    ];
    assert_eq!(path.motions.len(), expect.len());
    for (m, (x, z)) in path.motions.iter().zip(expect) {
        assert!(
            (m.to.x - x).abs() < 1e-12 && (m.to.z - z).abs() < 1e-12,
            "{m:?}"
        );
    }
    assert!(matches!(path.motions[1].kind, MotionKind::Thread { lead, .. } if lead == 2.0));
    // The repeat keeps Z and F; R(i) moves the start: 14.1 + (−0.5) at the start.
    assert_eq!(js[1].geometry.crest_start, Pos::new(14.3, 5.0));
    assert_eq!(js[2].geometry.crest_start, Pos::new(13.6, 5.0));
    assert_eq!(js[2].geometry.crest_end, Pos::new(14.1, -30.0));
}

#[test]
fn g92_taper_r_beyond_half_u_is_refused() {
    let e = error("G0 X40. Z5.\nG92 X29.2 Z-30. R6. F2.\n", &fanuc());
    assert_eq!((e.code, e.span.line), (Code::Geometry, 2));
    assert!(e.message.contains("|U/2|"), "{}", e.message);
}

#[test]
fn g32_is_a_plain_thread_move() {
    let src = "G0 X29.2 Z5.\nG32 Z-30. F2.\nG0 X40.\n";
    assert!(jobs(src, &fanuc()).is_empty());
    let out = expand(src, "fanuc");
    assert_eq!(out, src);
}

fn expand(src: &str, controller: &str) -> String {
    let mut out = Vec::new();
    program::expand_gcode(
        src.as_bytes(),
        &mut out,
        &Machine::built_in(controller).unwrap(),
    )
    .unwrap();
    String::from_utf8(out).unwrap()
}

#[test]
fn gsk_g76_and_g92_are_the_same_code_as_fanuc() {
    // The same text on both controllers (every number has a decimal point except the P/Q
    // increments, which both read as µm) gives the same motion; only the parameters differ, so
    // the chamfer is written on the block for G76 and as J/K for GSK's G92.
    let gsk = Machine::built_in("gsk980").unwrap();
    let a = &jobs(M30, &fanuc())[0];
    let b = &jobs(M30, &gsk)[0];
    assert_eq!(
        toolpath::build(a).unwrap().motions,
        toolpath::build(b).unwrap().motions
    );
    assert_eq!(b.controller, "gsk980");
    let g = &jobs("G0 X40. Z5.\nG92 X29.2 Z-30. F2. J2. K2.\n", &gsk)[0];
    let f = &jobs("G0 X40. Z5.\nG92 X29.2 Z-30. F2.\n", &fanuc())[0];
    // Fanuc's 45° chamfer rises 2·tan 45° = 2 − 2e-16: the same motion within 1e-12.
    let (pg, pf) = (toolpath::build(g).unwrap(), toolpath::build(f).unwrap());
    assert_eq!(pg.motions.len(), pf.motions.len());
    for (a, b) in pg.motions.iter().zip(&pf.motions) {
        assert!(a.to.distance(b.to) < 1e-12, "{a:?} {b:?}");
    }
    // GSK's J alone means K = J; L is the number of starts.
    let g = &jobs("G0 X40. Z5.\nG92 X29.2 Z-30. F4. J1. L2\n", &gsk)[0];
    assert_eq!(g.lead.starts, 2);
    assert_eq!(
        g.exit,
        Exit::PullOut {
            start_before: 1.0,
            length: 1.0,
            outward: 1.0
        }
    );
    // GSK's G78 is untouched by the G76/G92 reader, and a G78 ends a modal G92.
    let src = "G0 X80 Z10\nG92 X60 Z-30 F2\nG78 P010060 Q0.1 R0.05\nG78 X60 Z-30 P1.2 Q0.4 F2\n";
    let js = jobs(src, &gsk);
    assert_eq!(js.len(), 2);
    assert_eq!(
        js[1].finish_at,
        threadcut::thread::FinishPosition::LastRough
    );
}

#[test]
fn fanuc_reads_numbers_without_a_point_as_least_increments() {
    // X32000 is 32 mm on an ISB Fanuc; the G76 that follows starts there.
    let a = &jobs(M30, &fanuc())[0];
    let b = &jobs(
        "G0 X32000 Z5000\nG76 P020060 Q100 R50\nG76 X27546 Z-30000 P1227 Q400 F2.\n",
        &fanuc(),
    )[0];
    assert_eq!(
        toolpath::build(a).unwrap().motions,
        toolpath::build(b).unwrap().motions
    );
}

/// Real Haas and FS15 programs were refused with "K is not a word of the second G76 block": a
/// one-block G76 on a two-block control now says what it is and which controllers read it.
#[test]
fn a_one_block_g76_on_a_two_block_control_says_so() {
    let src = "G20\nG00 X0.85 Z0.25\nG76 X0.6272 Z-1. K0.0614 D0.02 F0.1 A60\n";
    for controller in ["fanuc", "gsk980", "fanuc-b"] {
        let e = error(src, &Machine::built_in(controller).unwrap());
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (Code::UnknownCode, 3, 18),
            "{controller}: {e}"
        );
        assert!(e.message.contains("one-block G76"), "{}", e.message);
        assert!(!e.message.contains("second G76 block"), "{}", e.message);
        let hint = e.hint.unwrap();
        assert!(
            hint.contains("--controller haas") && hint.contains("--controller fanuc15"),
            "{hint}"
        );
    }
}

/// Q on G32 and G92: the start angle in 0.001° (Fanuc 30i manual §4.1.2: "Increment: 0.001
/// degrees, Valid setting range: 0 to 360 degrees"), written without a decimal point.
#[test]
fn q_is_the_start_angle_of_g32_and_g92() {
    let pre = "G0 X40. Z5.\n";
    let js = jobs(&format!("{pre}G92 X29.2 Z-30. F4. Q180000\n"), &fanuc());
    assert_eq!(js[0].lead.phase_deg, 180.0);
    for (block, code, column) in [
        ("G32 Z-30. F2. Q180.", Code::Syntax, 15),
        ("G32 Z-30. F2. Q360001", Code::OutOfRange, 15),
        ("G92 X29.2 Z-30. F2. Q-90000", Code::OutOfRange, 21),
        ("G92 X29.2 Z-30. F2. Q1.5", Code::Syntax, 21),
    ] {
        let e = error(&format!("{pre}{block}\n"), &fanuc());
        assert_eq!(
            (e.code, e.span.line, e.span.column),
            (code, 2, column),
            "{block}"
        );
    }
    // The two-block G76 has no start angle: its Q is Δd.
    assert_eq!(jobs(M30, &fanuc())[0].lead.phase_deg, 0.0);
    // GSK reads none (G92 L cuts further starts): Q there is not a G92 word.
    let gsk = Machine::built_in("gsk980").unwrap();
    let e = error(&format!("{pre}G92 X29.2 Z-30. F2. Q90000\n"), &gsk);
    assert_eq!((e.code, e.span.column), (Code::Unsupported, 21));
    // A G92 with a start angle is written back natively, Q included.
    let (text, how) = threadcut::translate::job_to_string(&fanuc(), &js[0]).unwrap();
    assert_eq!(how, threadcut::translate::Written::Native);
    assert_eq!(text, "G92 X29.2 Z-30. F4. Q180000\n");
    // A plain G32's Q reaches its move, and the run's pull-out; a G32 after a rapid starts at 0°.
    let mut phases = Vec::new();
    let src = format!("{pre}G32 Z-30. F2. Q180000\nX42. Z-32.\nG0 X44.\nZ5.\nG32 X40. Z-30.\n");
    program::run(src.as_bytes(), &fanuc(), |_, ev| {
        if let program::Event::Plain { mv: Some(mv), .. } = ev {
            if mv.lead.is_some() {
                phases.push(mv.phase_deg);
            }
        }
        Ok(())
    })
    .unwrap();
    assert_eq!(phases, [180.0, 180.0, 0.0]);
}

/// The same M30×2 job in G-code systems A, B and C: the cycles' G numbers change, the motion does
/// not. B: G33, G78 (single pass), G76, G92 sets coordinates, G90/G91. C: G21 (single pass), G78
/// (multiple, two blocks), G70/G71 inch/mm, G20 a turning cycle.
#[test]
fn g_code_systems_a_b_and_c() {
    let a = "G21\nG0 X32. Z5.\nG92 X29.2 Z-30. F2.\nX28.6\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";
    let b = "G21 G95\nG92 X100. Z50.\nG0 X32. Z5.\nG78 X29.2 Z-30. F2.\nX28.6\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n";
    let c = "G71 G95\nG92 X100. Z50.\nG20 X30. Z-10. F0.2\nG0 X32. Z5.\nG21 X29.2 Z-30. F2.\nX28.6\nG78 P020060 Q100 R0.05\nG78 X27.546 Z-30. P1227 Q400 F2.\n";
    let system_b = Machine::built_in("fanuc-b").unwrap();
    let mut system_c = system_b.clone();
    system_c.fanuc.as_mut().unwrap().gcode_system = threadcut::machine::GCodeSystem::C;
    let ja = jobs(a, &fanuc());
    for (src, m) in [(b, &system_b), (c, &system_c)] {
        let js = jobs(src, m);
        assert_eq!(js.len(), 3, "{src}");
        for (x, y) in ja.iter().zip(&js) {
            threadcut::translate::same_motion(
                &toolpath::build(x).unwrap(),
                &toolpath::build(y).unwrap(),
                (1e-12, 1e-12),
            )
            .unwrap_or_else(|e| panic!("{e}: {src}"));
            assert_eq!(
                y.units,
                threadcut::units::Units::Mm,
                "G20 is no unit code in C"
            );
        }
    }
    // In B, G91 makes X/Z incremental (U/W stay incremental words too), and G33 is the thread move.
    let js = jobs(
        "G21\nG0 X40. Z10.\nG91 G0 X-8. Z-5.\nG90 G78 X29.2 Z-30. F2.\nG0 U8. W5.\nG78 X29.2 Z-30. F2.\n",
        &system_b,
    );
    assert_eq!(js[0].start, threadcut::units::Pos::new(16.0, 5.0));
    assert_eq!(js[1].start, threadcut::units::Pos::new(20.0, 10.0));
    let out = {
        let mut out = Vec::new();
        program::expand_gcode(
            "G21\nG0 X40. Z5.\nG78 X29.2 Z-30. F2. Q90000\n".as_bytes(),
            &mut out,
            &system_b,
        )
        .unwrap();
        String::from_utf8(out).unwrap()
    };
    assert!(
        out.contains("G0 X29.2 Z5.\nG33 X29.2 Z-28. F2. Q90000\nG33 X33.2 Z-30. F2.\n"),
        "{out}"
    );
    // A G91 on the cycle's own block applies to its words and stays: expand writes the moves
    // absolute between G90 and G91.
    let mut out = Vec::new();
    program::expand_gcode(
        "G21\nG0 X40. Z5.\nG91 G78 X-10.8 Z-35. F2.\nG0 X5.\n".as_bytes(),
        &mut out,
        &system_b,
    )
    .unwrap();
    let out = String::from_utf8(out).unwrap();
    assert!(
        out.contains("G90\nG0 X29.2 Z5.\nG33 X29.2 Z-28. F2.\nG33 X33.2 Z-30. F2.\nG0 X40. Z-30.\nG0 X40. Z5.\nG91\nG0 X5.\n"),
        "{out}"
    );
    // In B, G92 is not a thread cycle: with X/Z it sets the position, never cuts.
    assert!(jobs("G21\nG92 X29.2 Z-30.\n", &system_b).is_empty());
    // In A, G78 is no code of Fanuc's: the control's alarm, naming system B among those that have
    // it; in B, G32 (system A's thread move) is the alarm.
    let e = error("G21\nG0 X40. Z5.\nG78 X29.2 Z-30. F2.\n", &fanuc());
    assert_eq!(
        (e.code, e.span.line, e.span.column),
        (Code::UnknownCode, 3, 1)
    );
    assert!(e.message.ends_with("G78 is not a G code of fanuc"), "{e}");
    assert!(e.hint.unwrap().contains("--controller fanuc-b"));
    let e = error("G21\nG0 X40. Z5.\nG32 Z-30. F2.\n", &system_b);
    assert!(
        e.message
            .ends_with("G32 is not a G code of fanuc (G-code system B)"),
        "{e}"
    );
    let e = error("G71\nG0 X40. Z5.\nG32 Z-30. F2.\n", &system_c);
    assert_eq!((e.code, e.span.line), (Code::UnknownCode, 3), "{e}");
    assert!(e.message.ends_with("fanuc (G-code system C)"), "{e}");
    // Native writing uses the system's numbers, and reads back.
    let (text, how) = threadcut::translate::job_to_string(&system_c, &ja[2]).unwrap();
    assert_eq!(how, threadcut::translate::Written::Native, "{text}");
    assert!(
        text.starts_with("G78 P020060 Q100 R0.05\nG78 X27.546 Z-30. P1227 Q400 F2."),
        "{text}"
    );
    let (text, _) = threadcut::translate::job_to_string(&system_c, &ja[0]).unwrap();
    assert_eq!(text, "G21 X29.2 Z-30. F2.\n");
}

/// A thread shorter than its chamfer: the error gives the thread's length as the program's
/// coordinates make it (Z0.005 to Z-0.03: 0.035, not the difference's binary 0.034999999999999996).
#[test]
fn a_thread_shorter_than_its_chamfer_says_its_length_as_written() {
    let d = error("G0 X22. Z0.005\nG92 X19.5 Z-0.03 F2.5\n", &fanuc());
    assert_eq!(
        d.message,
        "the chamfer (parameter 5130) 2.5 is not shorter than the thread (0.035 along Z)"
    );
}
