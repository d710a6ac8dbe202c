//! Programs written the way shops write them, on every lathe dialect: positioning split over two
//! lines, reference returns with and without a profile position, start points at the crest within
//! the program's resolution, and LinuxCNC's own reading rules (blanks, one word per letter, words no
//! G code of the line uses). The programs are written for these tests after studying published
//! shop programs, student lathe programs and LinuxCNC's `nc_files`; none is copied.
//! `docs/dialects/README.md` states each rule and its source.

use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::Machine;
use threadcut::program;
use threadcut::thread::Job;
use threadcut::units::Pos;

fn machine(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

/// A built-in profile with a `[reference]` table added.
fn with_reference(name: &str, table: &str) -> Machine {
    let text = threadcut::machine::BUILT_IN
        .iter()
        .find(|(n, _)| *n == name)
        .unwrap()
        .1;
    Machine::from_toml(&format!("{text}\n[reference]\n{table}\n")).unwrap()
}

#[track_caller]
fn jobs(m: &Machine, src: &str) -> Vec<Job> {
    program::jobs(src.as_bytes(), m).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

#[track_caller]
fn error(m: &Machine, src: &str) -> Diagnostic {
    match program::jobs(src.as_bytes(), m) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an input error, got {other:?}\n{src}"),
    }
}

/// The error's code, line, column and a piece of its message.
#[track_caller]
fn assert_error(d: &Diagnostic, code: Code, line: u32, column: u32, text: &str) {
    assert_eq!(
        (d.code, d.span.line, d.span.column),
        (code, line, column),
        "{}",
        d.message
    );
    assert!(
        d.message.contains(text),
        "{:?} does not contain {text:?}",
        d.message
    );
}

#[track_caller]
fn close(got: Pos, want: Pos) {
    assert!(
        (got.x - want.x).abs() < 1e-9 && (got.z - want.z).abs() < 1e-9,
        "{got:?} != {want:?}"
    );
}

// ---------------------------------------------------------------------------------------------
// Positioning on separate lines

/// One program per dialect: the tool comes to the start point X first, then Z, each on its own
/// line, after a tool change and a reference return; the cycle starts there. `(machine, program,
/// start point in mm radius, the cycle's line and column)`.
const SPLIT: &[(&str, &str, Pos, u32, u32)] = &[
    (
        "fanuc",
        "%\nO2001 (M16X1.5 EXT)\nN10 G21 G40 G99\nN20 G28 U0. W0.\nN30 T0505\nN40 G97 S800 M03\n\
         N50 G00 X18.\nN60 Z4.\nN70 G76 P010060 Q50 R0.02\nN80 G76 X14.16 Z-22. P920 Q250 F1.5\n\
         N90 G00 X50.\nN100 G28 U0. W0.\nN110 M30\n%\n",
        Pos::new(9.0, 4.0),
        10,
        5,
    ),
    (
        "fanuc",
        "O2002\nG28 U0 W0\nT0303\nG97 S700 M3\nG0 X26.\nZ3.\nG92 X23.2 Z-18. F1.5\nX22.8\nX22.38\n\
         G0 X60.\nM30\n",
        Pos::new(13.0, 3.0),
        7,
        1,
    ),
    (
        "gsk980",
        "O0012\nG28 U0 W0\nT0202\nM03 S500\nG00 X13.\nZ1.\nG78 P010060 Q0.08 R0.05\n\
         G78 X10.376 Z-12 P0.812 Q0.25 F1.25\nG00 X30\nM30\n",
        Pos::new(6.5, 1.0),
        8,
        1,
    ),
    (
        "linuxcnc",
        "(M12x1.75 external)\nG7 G18 G21 G90\nT2 M6\nS400 M3\nG0 X13.\nZ1.\n\
         G76 P1.75 Z-15 I-0.5 J0.2 K2.147 Q29.5 H1 R2\nM5\nM2\n",
        Pos::new(6.5, 1.0),
        7,
        1,
    ),
    (
        "omniturn",
        "(1/2-20 EXT, RADIUS MODE)\nT4F200\nX.3\nZ.2\nG33X.212Z-.5I.012K.05PC\n",
        Pos::new(0.3 * 25.4, 0.2 * 25.4),
        5,
        1,
    ),
    (
        "ab9",
        "(1/2-13 UNC)\nG20\nG90 G00 X.6\nZ.2\nG78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3\n",
        Pos::new(0.3 * 25.4, 0.2 * 25.4),
        5,
        1,
    ),
    (
        // Haas: inch, X on diameter, numbers as a calculator reads them; each axis homed on its
        // own line, as Haas's own examples write it.
        "haas",
        "%\nO03001 (1/2-13 UNC-2A OD)\nG20 G99\nG28 U0.\nG28 W0.\nT404\nG97 S900 M03\n\
         G00 X.6\nZ.25\nG76 X.4056 Z-.75 K.0472 D.012 F.0769 A60 P2\nG00 X2.\nG28 U0.\nM30\n%\n",
        Pos::new(0.3 * 25.4, 0.25 * 25.4),
        10,
        1,
    ),
    (
        "fanuc15",
        "%\nO1531 (M20X1.5 OD, FS15 FORMAT)\nG21 G99\nG28 U0. W0.\nT0303\nG97 S700 M03\n\
         G00 X23.\nZ3.\nG76 X18.16 Z-20. K0.92 D0.3 F1.5 A60 P1\nG00 X100.\nM30\n%\n",
        Pos::new(11.5, 3.0),
        9,
        1,
    ),
    (
        // Fanuc's G-code system B: the two-block G76, G90 as the distance code.
        "fanuc-b",
        "O2002 (M16X1.5 OD, SYSTEM B)\nG21 G90 G95\nG28 U0. W0.\nT0505\nG97 S800 M03\n\
         G00 X18.\nZ4.\nG76 P010060 Q50 R0.02\nG76 X14.16 Z-22. P920 Q250 F1.5\nG00 X50.\nM30\n",
        Pos::new(9.0, 4.0),
        9,
        1,
    ),
    (
        // System B's single-pass cycle G78, modal.
        "fanuc-b",
        "O2003\nG28 U0. W0.\nT0505\nG90 G00 X22.\nZ4.\nG78 X19.4 Z-25. F1.5\nX19.\nX18.7\n\
         G00 X100.\nM30\n",
        Pos::new(11.0, 4.0),
        6,
        1,
    ),
];

#[test]
fn split_positioning_gives_the_start_point_on_every_dialect() {
    for &(name, src, start, line, _) in SPLIT {
        let jobs = jobs(&machine(name), src);
        close(jobs[0].start, start);
        assert_eq!(jobs[0].line, line, "{name}");
    }
}

#[test]
fn an_inch_program_that_returns_each_axis_on_its_own_line() {
    // The way lathe classes write Fanuc programs: `G28 G0 U0 W0` before each tool, `G28 U0` and
    // `G28 W0` after it, the work system and Z on one line, X on the next, inch in G20.
    let src = "%\nO0003 (1-16 UN EXT THREAD)\nG20 G99\nG28 G0 U0 W0\nT0303 (60 DEG THREAD)\n\
               G97 S800 M03\nG00 G54 Z.2\nG00 X1.1 M08\nG76 P010060 Q100 R.001\n\
               G76 X.9233 Z-1. P383 Q100 F.0625\nM09\nG28 U0\nG28 W0\nM30\n%\n";
    let jobs = jobs(&machine("fanuc"), src);
    close(jobs[0].start, Pos::new(0.55 * 25.4, 0.2 * 25.4));
    assert!((jobs[0].lead.lead - 0.0625 * 25.4).abs() < 1e-12);
    // P383 and Q100 are counts of 0.0001 inch.
    assert!((jobs[0].geometry.depth - 0.0383 * 25.4).abs() < 1e-12);
}

#[test]
fn a_start_point_with_one_axis_never_positioned_is_refused_naming_it() {
    for &(name, src, _, line, column) in SPLIT {
        let m = machine(name);
        // Without the Z line (and without the cycle's own earlier Z): Z was never given.
        let without_z: String = src
            .lines()
            .filter(|l| {
                !matches!(
                    l.trim_start_matches(|c: char| c == 'N' || c.is_ascii_digit())
                        .trim(),
                    "Z4." | "Z3." | "Z1." | "Z.2" | "Z.25"
                )
            })
            .map(|l| format!("{l}\n"))
            .collect();
        let e = error(&m, &without_z);
        assert_error(
            &e,
            Code::UnknownPosition,
            line - 1,
            column,
            "the tool's Z is not known here",
        );
        // Without the X word (its motion code stays): X was never given.
        let without_x: String = src
            .lines()
            .map(|l| match l {
                "N50 G00 X18." => "N50 G00",
                "G0 X26." | "G0 X13." => "G0",
                "G00 X13." => "G00",
                "X.3" => "",
                "G90 G00 X.6" => "G90 G00",
                "G00 X.6" | "G00 X23." | "G00 X18." => "G00",
                "G90 G00 X22." => "G90 G00",
                l => l,
            })
            .map(|l| format!("{l}\n"))
            .collect();
        let e = error(&m, &without_x);
        assert_error(
            &e,
            Code::UnknownPosition,
            line,
            column,
            "the tool's X is not known here",
        );
    }
}

#[test]
fn moves_from_an_unknown_start_are_reported_with_their_unknown_axes() {
    let src = "G7 G21\nG0 X13.\nZ1.\nG1 Z-5. F0.1\n";
    let mut out = Vec::new();
    program::expand_jsonl(src.as_bytes(), &mut out, &machine("linuxcnc")).unwrap();
    let lines: Vec<serde_json::Value> = String::from_utf8(out)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // `G0 X13.` ends where Z is still unknown: no known end point, not reported. `Z1.` ends at a
    // known point from a start whose Z is unknown; `G1 Z-5.` starts where `Z1.` ended.
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert_eq!(
        lines[0],
        serde_json::json!({"kind":"rapid","x":6.5,"z":1.0,"pass":0,"line":3,"start_unknown":["z"]})
    );
    assert_eq!(
        lines[1],
        serde_json::json!({"kind":"feed","x":6.5,"z":-5.0,"pass":0,"line":4})
    );
}

// ---------------------------------------------------------------------------------------------
// Reference returns

const FANUC_AFTER_G28: &str =
    "G0 X18. Z4.\n{RETURN}\nG76 P010060 Q50 R0.02\nG76 X14.16 Z-22. P920 Q250 F1.5\n";

fn fanuc_with(ret: &str) -> String {
    FANUC_AFTER_G28.replace("{RETURN}", ret)
}

#[test]
fn a_reference_return_leaves_the_axes_it_names_unknown() {
    let m = machine("fanuc");
    let e = error(&m, &fanuc_with("G28 U0. W0."));
    assert_error(
        &e,
        Code::UnknownPosition,
        4,
        1,
        "the tool's X and Z are not known",
    );
    // Fanuc: only the axes commanded return.
    let e = error(&m, &fanuc_with("G28 U0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's X is not known");
    let e = error(&m, &fanuc_with("G28 W0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's Z is not known");
    // A return without axis words moves no axis on Fanuc: the start point stays.
    close(jobs(&m, &fanuc_with("G28"))[0].start, Pos::new(9.0, 4.0));
    // G30 (second reference point) and G53 (machine coordinates) likewise.
    let e = error(&m, &fanuc_with("G30 U0. W0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "X and Z");
    let e = error(&m, &fanuc_with("G53 G0 X0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's X is not known");
    // G29 returns to its absolute words; incremental ones count from an intermediate point.
    let ret = "G28 U0. W0.\nG29 X18. Z4.";
    close(jobs(&m, &fanuc_with(ret))[0].start, Pos::new(9.0, 4.0));
    let e = error(&m, &fanuc_with("G28 U0. W0.\nG29 X18. W0."));
    assert_error(&e, Code::UnknownPosition, 5, 1, "the tool's Z is not known");
    // Another work coordinate system moves the program's coordinates; the one in force does not.
    close(jobs(&m, &fanuc_with("G54"))[0].start, Pos::new(9.0, 4.0));
    let e = error(&m, &fanuc_with("G55"));
    assert_error(&e, Code::UnknownPosition, 4, 1, "X and Z");
    // A move on the block that selects the system is in the new system's coordinates.
    close(
        jobs(&m, &fanuc_with("G55 G0 X18. Z4."))[0].start,
        Pos::new(9.0, 4.0),
    );
    let e = error(&m, &fanuc_with("G55 G0 X18."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's Z is not known");
}

#[test]
fn a_reference_return_ends_where_the_profile_says() {
    // X as the program writes it (a diameter on this profile), in the profile's units.
    let m = with_reference("fanuc", "g28 = { x = 200.0, z = 150.0 }");
    let jobs_after = |ret: &str| jobs(&m, &fanuc_with(ret));
    close(jobs_after("G28 U0. W0.")[0].start, Pos::new(100.0, 150.0));
    close(jobs_after("G28 U0.")[0].start, Pos::new(100.0, 4.0));
    // The profile states no second reference point.
    let e = error(&m, &fanuc_with("G30 U0. W0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "X and Z");
    // One axis stated, one not.
    let m = with_reference(
        "fanuc",
        "g28 = { z = 150.0 }\ng30 = { x = 120.0, z = 90.0 }",
    );
    let e = error(&m, &fanuc_with("G28 U0. W0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's X is not known");
    close(
        jobs(&m, &fanuc_with("G30 U0. W0."))[0].start,
        Pos::new(60.0, 90.0),
    );
}

const LINUXCNC_AFTER_RETURN: &str =
    "G7 G21 G18\nS400 M3\nG0 X13. Z1.\n{RETURN}\nG76 P1.75 Z-15 I-0.5 J0.2 K2.147\n";

#[test]
fn linuxcnc_returns_every_axis_without_axis_words() {
    let m = machine("linuxcnc");
    let src = |ret: &str| LINUXCNC_AFTER_RETURN.replace("{RETURN}", ret);
    let e = error(&m, &src("G28"));
    assert_error(
        &e,
        Code::UnknownPosition,
        5,
        1,
        "the tool's X and Z are not known",
    );
    // With an axis word, only that axis returns (after the intermediate point).
    let e = error(&m, &src("G28 X20."));
    assert_error(&e, Code::UnknownPosition, 5, 1, "the tool's X is not known");
    // G28.1 stores where the tool is; G28 goes back there.
    let stored = "G28.1\nG0 X40. Z40.\nG28";
    close(jobs(&m, &src(stored))[0].start, Pos::new(6.5, 1.0));
    // The profile's position, in the profile's X convention (radius: LinuxCNC starts in G8).
    let m = with_reference("linuxcnc", "g28 = { x = 7.0, z = 2.0 }");
    close(jobs(&m, &src("G28"))[0].start, Pos::new(7.0, 2.0));
    // G92.1 drops the G92 offsets, whose size this reader does not keep.
    let e = error(&machine("linuxcnc"), &src("G92.1"));
    assert_error(&e, Code::UnknownPosition, 5, 1, "X and Z");
}

#[test]
fn offsets_set_by_g10_and_g52_are_no_move() {
    // `G10 L2 P1 X.. Z..` sets a work offset: its axis words are no move, and the program's
    // coordinates may have moved.
    let m = machine("linuxcnc");
    let src =
        "G8 G21 G18\nM3 S400\nG0 X6.5 Z1\nG10 L2 P1 X0 Z-100\nG76 P1.75 Z-15 I-0.5 J0.2 K1.0735\n";
    let e = error(&m, src);
    assert_error(&e, Code::UnknownPosition, 5, 1, "X and Z");
    let mut out = Vec::new();
    program::expand_jsonl(&src.as_bytes()[..src.find("G76").unwrap()], &mut out, &m).unwrap();
    assert_eq!(
        String::from_utf8(out).unwrap().lines().count(),
        1,
        "the G0 only"
    );
    let e = error(&machine("fanuc"), &fanuc_with("G52 X0. Z-50."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "X and Z");
}

#[test]
fn set_position_keeps_the_axis_it_does_not_name() {
    // LinuxCNC's G92 Z0 sets Z only; X stays known.
    let m = machine("linuxcnc");
    let src = "G8 G21\nS400 M3\nG0 X6.5 Z0.9\nG92 Z0\nG76 P1.75 Z-15 I-0.5 J0.2 K1.0735\n";
    close(jobs(&m, src)[0].start, Pos::new(6.5, 0.0));
    // Fanuc's G50 from an unknown position: the named axes become known.
    let m = machine("fanuc");
    let src = "G50 X18. Z4.\nG76 P010060 Q50 R0.02\nG76 X14.16 Z-22. P920 Q250 F1.5\n";
    close(jobs(&m, src)[0].start, Pos::new(9.0, 4.0));
}

const HAAS_AFTER_RETURN: &str =
    "G20\nG00 X.6 Z.25\n{RETURN}\nG76 X.4056 Z-.75 K.0472 D.012 F.0769 A60 P2\n";

#[test]
fn haas_returns_every_axis_without_axis_words() {
    // Haas's G28: "returns all axes … simultaneously to the machine zero position when no axis
    // is specified"; with axis words only those axes return.
    let m = machine("haas");
    let src = |ret: &str| HAAS_AFTER_RETURN.replace("{RETURN}", ret);
    let start = Pos::new(0.3 * 25.4, 0.25 * 25.4);
    let e = error(&m, &src("G28"));
    assert_error(
        &e,
        Code::UnknownPosition,
        4,
        1,
        "the tool's X and Z are not known",
    );
    let e = error(&m, &src("G28 U0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's X is not known");
    let e = error(&m, &src("G28 W0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's Z is not known");
    // Work offsets: G54 is in force at power-on; G55 and G110–G129 are others; every G154 P..
    // may be another of its 99.
    close(jobs(&m, &src("G54"))[0].start, start);
    for other in ["G55", "G110", "G129", "G154 P1"] {
        let e = error(&m, &src(other));
        assert_error(&e, Code::UnknownPosition, 4, 1, "X and Z");
    }
    let e = error(&m, &src("G53 G00 X0."));
    assert_error(&e, Code::UnknownPosition, 4, 1, "the tool's X is not known");
    // The profile's machine zero, in inch and on diameter as Haas programs write X.
    let m = with_reference("haas", "g28 = { x = 10.0, z = 8.0 }");
    close(
        jobs(&m, &src("G28"))[0].start,
        Pos::new(5.0 * 25.4, 8.0 * 25.4),
    );
    close(
        jobs(&m, &src("G28 W0."))[0].start,
        Pos::new(0.3 * 25.4, 8.0 * 25.4),
    );
}

#[test]
fn fanuc_g_code_systems_take_their_own_position_codes() {
    // The reference returns, G53 and G54–G59 are the same in A, B and C; the coordinate setting
    // (G50 in A, G92 in B and C) and the workpiece coordinate preset (G50.3 in A, G92.1 in B and C)
    // are renumbered (`fanuc_family::GCodes`).
    let a = machine("fanuc");
    let b = machine("fanuc-b");
    let mut c = b.clone();
    c.fanuc.as_mut().unwrap().gcode_system = threadcut::machine::GCodeSystem::C;
    let cycle_a = "G76 P010060 Q50 R0.02\nG76 X14.16 Z-22. P920 Q250 F1.5\n";
    let cycle_c = "G78 P010060 Q50 R0.02\nG78 X14.16 Z-22. P920 Q250 F1.5\n";
    for (m, set, preset, cycle) in [
        (&a, "G50", "G50.3", cycle_a),
        (&b, "G92", "G92.1", cycle_a),
        (&c, "G92", "G92.1", cycle_c),
    ] {
        let name = format!("system {:?}", m.fanuc.as_ref().unwrap().gcode_system);
        // Set position, from nowhere known: the named axes.
        let src = format!("{set} X18. Z4.\n{cycle}");
        close(jobs(m, &src)[0].start, Pos::new(9.0, 4.0));
        // The preset moves the coordinates by an amount the program does not state.
        let src = format!("G0 X18. Z4.\n{preset} X0. Z0.\n{cycle}");
        let e = error(m, &src);
        assert_error(&e, Code::UnknownPosition, 4, 1, "X and Z");
        // The same reference returns and work offsets in every system.
        for (ret, text) in [
            ("G28 U0.", "the tool's X is not known"),
            ("G30 W0.", "the tool's Z is not known"),
            ("G53 G0 X0.", "the tool's X is not known"),
            ("G30.1 U0.", "the tool's X is not known"),
            ("G56", "X and Z"),
            ("G10 P0 X0. Z0.", "X and Z"),
            ("G52 X0. Z-10.", "X and Z"),
        ] {
            let src = format!("G0 X18. Z4.\n{ret}\n{cycle}");
            let e = error(m, &src);
            assert_error(&e, Code::UnknownPosition, 4, 1, text);
            assert!(e.message.contains(text), "{name}: {ret}");
        }
    }
}

/// The CYCLE97 of `src` on `m`: its job and the warnings of the run.
fn cycle97(m: &Machine, src: &str) -> (Job, Vec<Diagnostic>) {
    let mut job = None;
    let summary = program::run(src.as_bytes(), m, |_, ev| {
        if let program::Event::Cycle { job: j, .. } = ev {
            job = Some(*j);
        }
        Ok(())
    })
    .unwrap_or_else(|e| panic!("{e}\n{src}"));
    (job.expect("a cycle"), summary.warnings)
}

const SINUMERIK_SHOP: &str = "N10 G18 G90 G95 G71 DIAMON\nN20 G74 X1=0 Z1=0\n\
    N30 T=\"THREAD_EXT_60\" D1\nN40 G97 S900 M3\nN50 G0 X30\nN60 Z6\n\
    N70 CYCLE97(1.5,,0,-32,24,24,4,2,0.92,0.05,-29,0,7,2,3,1)\nN80 G0 X60 Z80\nN90 M30\n";

#[test]
fn sinumerik_split_positioning_and_its_position_codes() {
    let m = machine("sinumerik");
    // CYCLE97 starts from its own start point; where the tool was is the start of its G0 there,
    // which it shows from its start point, with a warning, when an axis is not known.
    let (job, warnings) = cycle97(&m, SINUMERIK_SHOP);
    close(job.start, Pos::new(15.0, 6.0));
    assert!(warnings.is_empty(), "{warnings:?}");
    let unknown = |src: &str, axes: &str| {
        let (job, warnings) = cycle97(&m, src);
        assert_eq!(warnings.len(), 1, "{src}: {warnings:?}");
        assert_eq!(warnings[0].code, Code::UnknownPosition);
        assert!(
            warnings[0]
                .message
                .contains(&format!("the tool's {axes} before CYCLE97")),
            "{src}: {}",
            warnings[0].message
        );
        close(job.start, Pos::new(job.retract.x, job.retract.z));
    };
    unknown(&SINUMERIK_SHOP.replace("N60 Z6\n", ""), "Z");
    unknown(&SINUMERIK_SHOP.replace("N50 G0 X30\n", "N50 G0\n"), "X");
    // G74 approaches the reference point with the machine axes it names (X1=, Z1=, or the
    // axis's own name with `=`); the other axis stays where it was.
    let after =
        |codes: &str| SINUMERIK_SHOP.replace("N70 CYCLE97", &format!("{codes}\nN70 CYCLE97"));
    unknown(&after("G74 X1=0"), "X");
    unknown(&after("G74 Z1=0"), "Z");
    unknown(&after("G74 X1=0 Z1=0"), "X and Z");
    // G75 (a fixed point from the machine data), G53/G153 and SUPA (machine coordinates): the
    // named axes become unknown, and the block is no move in the program's coordinates.
    unknown(&after("G75 FP=2 Z1=0"), "Z");
    unknown(&after("G75 FP=1 X=0"), "X");
    unknown(&after("G53 G0 X100"), "X");
    unknown(&after("G153 G0 Z100"), "Z");
    unknown(&after("SUPA G0 Z100"), "Z");
    // The settable work offsets: G500 is in force at power-on; G54–G57 and G505–G599 are others.
    let (_, warnings) = cycle97(&m, &after("G500"));
    assert!(warnings.is_empty(), "{warnings:?}");
    for other in ["G54", "G57", "G505", "G599"] {
        unknown(&after(other), "X and Z");
    }
    let (_, warnings) = cycle97(&m, &after("G54 G0 X30 Z6\nG54"));
    assert!(warnings.is_empty(), "{warnings:?}");
    // The programmable zero offsets are frames, refused as TRANS is; the working-area limits
    // G25/G26 move nothing.
    let e = error(&m, &after("G58 Z-10"));
    assert_error(
        &e,
        Code::Unsupported,
        7,
        1,
        "G58: threadcut does not follow frames",
    );
    let (job, warnings) = cycle97(&m, &after("G25 X0 Z-200\nG26 X400 Z300"));
    assert!(warnings.is_empty(), "{warnings:?}");
    close(job.start, Pos::new(15.0, 6.0));
    // The profile's reference point (its `g28`: Sinumerik's G74), on diameter as X is written.
    let m = with_reference("sinumerik", "g28 = { x = 300.0, z = 200.0 }");
    let (job, warnings) = cycle97(&m, &after("G74 X1=0 Z1=0"));
    assert!(warnings.is_empty(), "{warnings:?}");
    close(job.start, Pos::new(150.0, 200.0));
    // A thread move after positioning on two lines starts at the known point.
    let mut moves = vec![];
    program::run(
        "G18 G90 G95 DIAMON\nG74 X1=0 Z1=0\nG0 X23\nZ5\nG33 Z-20 K1.5 SF=90\n".as_bytes(),
        &machine("sinumerik"),
        |_, ev| {
            if let program::Event::Plain { mv: Some(mv), .. } = ev {
                moves.push(mv);
            }
            Ok(())
        },
    )
    .unwrap();
    // `G0 X23` ends where Z is not known: no move; `Z5` ends at a known point; the thread runs
    // from there.
    assert_eq!(moves.len(), 2, "{moves:?}");
    assert_eq!(moves[0].from.unknown_axes(), ["Z"]);
    assert_eq!(moves[1].from.known(), Some(Pos::new(11.5, 5.0)));
    assert_eq!((moves[1].lead, moves[1].phase_deg), (Some(1.5), 90.0));
}

// ---------------------------------------------------------------------------------------------
// Comparisons at the program's resolution

const GSK_AT_THE_CREST: &str =
    "G00 X{X} Z5\nG78 P010060 Q0.1 R0.05\nG78 X36.933 Z-30 P1.534 Q0.3 F2.5{TAIL}\n";

fn gsk_crest(x: &str, tail: &str) -> String {
    GSK_AT_THE_CREST.replace("{X}", x).replace("{TAIL}", tail)
}

#[test]
fn a_start_point_within_the_resolution_of_the_crest_is_on_the_crest() {
    let m = machine("gsk980");
    // The crest is at X36.933 + 2 × 1.534 = X40.001 (diameter, IS-B mm: one increment 0.001).
    for x in ["40", "40.0005", "40.001", "40.5"] {
        let jobs = jobs(&m, &gsk_crest(x, ""));
        assert_eq!(jobs[0].start.x * 2.0, x.parse::<f64>().unwrap(), "X{x}");
        assert!((jobs[0].geometry.crest_start.x * 2.0 - 40.001).abs() < 1e-9);
    }
    // Inside by more than one increment: the return along Z would cut the thread.
    for x in ["39.999", "39.998", "39"] {
        let e = error(&m, &gsk_crest(x, ""));
        assert_error(
            &e,
            Code::Geometry,
            3,
            1,
            "lies inside the thread (the crest is at X40.001)",
        );
    }
    // An internal thread: the crest is below the start, at X42 − 2 × 1.534 = X38.932.
    let internal = |x: &str| format!("G00 X{x} Z5\nG78 X42 Z-30 P1.534 Q0.3 F2.5\n");
    jobs(&m, &internal("38.933"));
    jobs(&m, &internal("38.9325"));
    let e = error(&m, &internal("38.934"));
    assert_error(&e, Code::Geometry, 2, 1, "inside the thread");
    // Fanuc's G76: the crest at X14.16 + 2 × 0.92 = X16. (P920 in least increments).
    let m = machine("fanuc");
    let fanuc =
        |x: &str| format!("G0 X{x} Z4.\nG76 P010060 Q50 R0.02\nG76 X14.16 Z-22. P920 Q250 F1.5\n");
    jobs(&m, &fanuc("15.999"));
    let e = error(&m, &fanuc("15.998"));
    assert_error(&e, Code::Geometry, 3, 1, "inside the thread");
    // Allen-Bradley, inch (one increment 0.0001 in): the top of the thread at X.4056 + 2 × .0472.
    let m = machine("ab9");
    let ab = |x: &str| format!("G20\nG0 X{x} Z.2\nG78 X.4056 Z-.75 K.0472 D.01 E13 A60 P3\n");
    jobs(&m, &ab(".4999"));
    let e = error(&m, &ab(".4998"));
    assert_error(&e, Code::Geometry, 3, 1, "lies inside the thread");
    // The one-block G76 of the FS15 format: the top of the thread at X27.546 + 2 × 1.227 = X30.
    let m = machine("fanuc15");
    let fs15 = |x: &str| format!("G0 X{x} Z5.\nG76 X27.546 Z-30. K1.227 D0.4 F2. A60 P1\n");
    jobs(&m, &fs15("29.999"));
    let e = error(&m, &fs15("29.998"));
    assert_error(
        &e,
        Code::Geometry,
        2,
        1,
        "lies inside the thread (its top is at X30.)",
    );
    // Haas's, in inch: X.4056 + 2 × .0472 = X.5.
    let m = machine("haas");
    let haas =
        |x: &str| format!("G20\nG00 X{x} Z.25\nG76 X.4056 Z-.75 K.0472 D.012 F.0769 A60 P2\n");
    jobs(&m, &haas(".4999"));
    let e = error(&m, &haas(".4998"));
    assert_error(&e, Code::Geometry, 3, 1, "lies inside the thread");
    // Fanuc system B's single-pass G78: a start X within one increment of the cut's X cannot tell
    // an external from an internal thread.
    let m = machine("fanuc-b");
    let b = |x: &str| format!("G0 X{x} Z4.\nG78 X19.4 Z-25. F1.5\n");
    let e = error(&m, &b("19.4005"));
    assert_error(
        &e,
        Code::Geometry,
        2,
        1,
        "cannot tell an external from an internal",
    );
    jobs(&m, &b("19.402"));
}

#[test]
fn lengths_and_equalities_at_the_resolution() {
    let m = machine("gsk980");
    // The tail-out K against the thread's 35 mm: as long, or within one increment of it, is not
    // shorter; two increments shorter is.
    for k in ["35", "34.999"] {
        let e = error(&m, &gsk_crest("40", &format!(" J1 K{k}")));
        assert_error(&e, Code::Geometry, 3, 1, "is not shorter than the thread");
    }
    jobs(&m, &gsk_crest("40", " J1 K34.998"));
    // A thread end Z within one increment of the start's Z has no length.
    let e = error(&m, "G00 X40 Z5\nG78 X36.933 Z4.999 P1.534 Q0.3 F2.5\n");
    assert_error(&e, Code::Geometry, 2, 1, "no length");
    // A start X within one increment of the root cannot tell external from internal.
    let e = error(&m, "G00 X36.9335 Z5\nG78 X36.933 Z-30 P1.534 Q0.3 F2.5\n");
    assert_error(
        &e,
        Code::Geometry,
        2,
        1,
        "cannot tell an external from an internal",
    );
    // OmniTurn (IS-C inch, radius mode: one increment .00001 in): the final X within it of the
    // start X cuts nothing.
    let m = machine("omniturn");
    let e = error(&m, "X.21201Z.2\nG33X.212Z-.5I.012K.05\n");
    assert_error(&e, Code::Geometry, 2, 4, "equals the start X");
    jobs(&m, "X.21202Z.2\nG33X.212Z-.5I.012K.05\n");
    // LinuxCNC (IS-C mm, G8: one increment 0.0001 mm): K within it of J is not greater.
    let m = machine("linuxcnc");
    let lcnc = |k: &str| format!("M3 S300\nG0 X7 Z2\nG76 P1.5 Z-20 I-0.5 J0.2 K{k}\n");
    let e = error(&m, &lcnc("0.20005"));
    assert_error(
        &e,
        Code::OutOfRange,
        3,
        26,
        "In G76, K must be greater than J",
    );
    jobs(&m, &lcnc("0.2002"));
    // CYCLE97 (IS-B mm, its lengths as written): FPL within one increment of SPL has no length;
    // FAL within one increment of TDEP is not smaller than it.
    let m = machine("sinumerik");
    let c97 = |spl_fpl: &str, tdep_fal: &str| {
        format!("G0 X30 Z6\nCYCLE97(1.5,,{spl_fpl},24,24,4,2,{tdep_fal},-29,0,7,2,3,1)\n")
    };
    let e = error(&m, &c97("0,0.0009", "0.92,0.05"));
    assert_error(&e, Code::Geometry, 2, 16, "FPL 0.0009 equals SPL");
    cycle97(&m, &c97("0,-0.002", "0.92,0.05"));
    let e = error(&m, &c97("0,-32", "0.92,0.9195"));
    assert_error(
        &e,
        Code::Geometry,
        2,
        35,
        "is not smaller than the thread depth",
    );
    cycle97(&m, &c97("0,-32", "0.92,0.918"));
}

// ---------------------------------------------------------------------------------------------
// LinuxCNC's reading rules

const LCNC_PRE: &str = "G8 G18 G21\nM3 S400\nG0 X11 Z5\n";

/// The 1-based column of the last `needle` in `line`.
fn column(line: &str, needle: &str) -> u32 {
    line.rfind(needle).unwrap() as u32 + 1
}

#[test]
fn linuxcnc_ignores_blanks_everywhere_outside_comments() {
    let m = machine("linuxcnc");
    let compact = jobs(
        &m,
        &format!("{LCNC_PRE}G76 P2.5 Z-30 I-1 J0.1 K0.5 R1.5 Q29.5\n"),
    );
    for spaced in [
        "G 7 6 P2 . 5 Z - 3 0 I - 1 J 0 . 1 K 0 . 5 R 1 . 5 Q 2 9 . 5",
        "G76P2.5Z-30I-1J0.1K0.5R1.5Q29.5",
        "g76\tp2.\t5 z-30 i-1 j0.1 k0.5 r1.5 q29.5",
        "G76 P2.5 (pitch 2 . 5) Z-30 I-1 J0.1 K0.5 R1.5 Q29.5 ; drive line",
    ] {
        let got = jobs(&m, &format!("{LCNC_PRE}{spaced}\n"));
        assert_eq!(
            format!("{:?}", got[0].geometry),
            format!("{:?}", compact[0].geometry),
            "{spaced}"
        );
        assert_eq!(got[0].lead, compact[0].lead, "{spaced}");
        assert_eq!(
            format!("{:?}", got[0].plan),
            format!("{:?}", compact[0].plan),
            "{spaced}"
        );
    }
    // Positioning written with blanks inside its numbers.
    let got = jobs(
        &m,
        "G8 G18\nM3 S400\nG0 X 1 1 . 0 Z 5\nG76 P2.5 Z-30 I-1 J0.1 K0.5\n",
    );
    close(got[0].start, Pos::new(11.0, 5.0));
    // A comment inside a comment is LinuxCNC's error; elsewhere the first `)` closes it.
    let line = "G0 X11 (tool (T4) back) Z5";
    let e = error(&m, &format!("{line}\n"));
    assert_error(
        &e,
        Code::Syntax,
        1,
        column(line, "(T4"),
        "Nested comment found",
    );
    // Other controllers end a number at a blank: `G 7 6` is no G76 there.
    let e = error(&machine("fanuc"), "G0 X2 0. Z5.\n");
    assert_eq!((e.code, e.span.line, e.span.column), (Code::Syntax, 1, 7));
}

#[test]
fn linuxcnc_refuses_a_letter_twice_on_one_line() {
    let m = machine("linuxcnc");
    for (line, second, message) in [
        (
            "G76 P2.5 Z-30 I-1 J0.1 K0.5 P3",
            "P3",
            "Multiple p words on one line",
        ),
        (
            "G76 P2.5 Z-30 I-1 J0.1 K0.5 Q29.5 Q30",
            "Q30",
            "Multiple q words on one line",
        ),
        (
            "G76 P2.5 Z-30 Z-25 I-1 J0.1 K0.5",
            "Z-25",
            "Multiple z words on one line",
        ),
        (
            "G76 P2.5 Z-30 I-1 I-2 J0.1 K0.5",
            "I-2",
            "Multiple i words on one line",
        ),
        (
            "G76 P2.5 Z-30 I-1 J0.1 K0.5 H1 H2",
            "H2",
            "Multiple h words on one line",
        ),
        (
            "G76 P2.5 Z-30 I-1 J0.1 K0.5 E1 L1 E2",
            "E2",
            "Multiple e words on one line",
        ),
        (
            "G76 P2.5 Z-30 I-1 J0.1 K0.5 $0 $0",
            "$0",
            "Multiple spindle choice ($) words on one line",
        ),
        (
            "G1 X10 Z-5 F0.1 F0.2",
            "F0.2",
            "Multiple f words on one line",
        ),
        ("G0 X10 X12", "X12", "Multiple x words on one line"),
        ("G0 X10 W1 W2", "W2", "Multiple W words on one line"),
        ("S400 M3 S500", "S500", "Multiple s words on one line"),
        ("T1 M6 T2", "T2", "Multiple t words on one line"),
        ("G0 G1 X10", "G1", "Two g codes used from same modal group"),
        ("M3 M4 S400", "M4", "Two m codes used from same modal group"),
        ("N10 G0 X10 N20", "N20", "Bad character 'n' used"),
    ] {
        let e = error(&m, &format!("{LCNC_PRE}{line}\n"));
        assert_error(&e, e.code, 4, column(line, second), message);
        assert_eq!(e.message, message);
    }
    // G and M codes of different modal groups share a line; other controllers read a repeated
    // letter as before (Fanuc: the last one counts).
    jobs(&m, &format!("{LCNC_PRE}G7 G90 G0 X22 Z5 M8 M3\n"));
    jobs(&machine("fanuc"), "G0 X20. Z5. F0.1 F0.2\n");
}

/// LinuxCNC's `arc_data_r` (found comparing with rs274, tests/linuxcnc_reference.rs): an R arc
/// whose radius cannot reach the end point, or that ends where it starts, is refused; half the
/// chord equal to R (a half circle) is an arc.
#[test]
fn linuxcnc_r_arc_must_reach_its_end_point() {
    let m = machine("linuxcnc");
    // From (7, -1) to (8, -1.5), radius mode: half the chord is √1.25 / 2 = 0.559 > 0.5.
    let d = error(&m, "G8 G21 G18\nF100\nG0 X7 Z-1\nG2 X8 Z-1.5 R0.5\nM2\n");
    assert_error(
        &d,
        Code::Geometry,
        4,
        13,
        "Arc radius too small to reach end point",
    );
    assert!(
        d.hint.as_deref().unwrap().contains("0.559 mm"),
        "{:?}",
        d.hint
    );
    program::jobs(
        "G8 G21 G18\nF100\nG0 X7 Z-1\nG2 X8 Z-1.5 R0.56\nM2\n".as_bytes(),
        &m,
    )
    .unwrap();
    // A half circle: half the chord is R exactly.
    program::jobs(
        "G8 G21 G18\nF100\nG0 X7 Z-1\nG3 X7 Z-2 R0.5\nM2\n".as_bytes(),
        &m,
    )
    .unwrap();
    // G7: X is a diameter, so X14 → X16 is 1 mm of radius; the same arc.
    let d = error(&m, "G7 G21 G18\nF100\nG0 X14 Z-1\nG2 X16 Z-1.5 R0.5\nM2\n");
    assert_error(&d, Code::Geometry, 4, 14, "Arc radius too small");
    // The line's own G91 counts: X1 Z-0.5 from (7, -1) is the same end point.
    let d = error(
        &m,
        "G8 G21 G18\nF100\nG0 X7 Z-1\nG91 G2 X1 Z-0.5 R0.5\nM2\n",
    );
    assert_error(&d, Code::Geometry, 4, 17, "Arc radius too small");
    // Inch: the chord and R in the same units.
    let d = error(
        &m,
        "G8 G20 G18\nF10\nG0 X0.7 Z-0.1\nG2 X0.8 Z-0.15 R0.05\nM2\n",
    );
    assert_error(&d, Code::Geometry, 4, 16, "Arc radius too small");
    assert!(
        d.hint.as_deref().unwrap().contains("0.0559 inch"),
        "{:?}",
        d.hint
    );
    let d = error(&m, "G8 G21 G18\nF100\nG0 X7 Z-1\nG2 X7 Z-1 R0.5\nM2\n");
    assert_error(
        &d,
        Code::Geometry,
        4,
        11,
        "Current point same as end point of arc",
    );
}

/// LinuxCNC's `arc_data_ijk` with its default tolerances (2·√2·0.01 mm or 0.001 inch, or 0.1 % of
/// the radius; never 100 tolerances), found comparing with rs274 and pinned at rs274's own
/// boundaries (tests/data/linuxcnc-ref/bad/arc-centre-off.ngc).
#[test]
fn linuxcnc_ik_arc_ends_on_its_circle() {
    let m = machine("linuxcnc");
    let arc = |head: &str, k: &str| format!("{head}\nF100\nG0 X4 Z1\nG1 Z0\nG3 X6 Z-2 {k}\nM2\n");
    // From (4, 0) to (6, -2) about (4, -2.03): r1 = 2.03, r2 = 2.000225 (rs274 refuses it).
    let d = error(&m, &arc("G8 G21 G18", "K-2.03"));
    assert_error(
        &d,
        Code::Geometry,
        5,
        11,
        "Radius to end of arc differs from radius to start",
    );
    assert_eq!(
        d.message,
        "Radius to end of arc differs from radius to start: start=(Z0.0000,X4.0000) \
         center=(Z-2.0300,X4.0000) end=(Z-2.0000,X6.0000) r1=2.0300 r2=2.0002 abs_err=0.02978 \
         rel_err=1.4667%"
    );
    // 0.0248 mm apart: within 2·√2·0.01 mm (rs274 runs it).
    program::jobs(arc("G8 G21 G18", "K-2.025").as_bytes(), &m).unwrap();
    // I is a radius also in G7: X8 → X12 is 2 mm of radius, the same arcs.
    let g7 = |k: &str| format!("G7 G21 G18\nF100\nG0 X8 Z1\nG1 Z0\nG3 X12 Z-2 {k}\nM2\n");
    program::jobs(g7("I0 K-2").as_bytes(), &m).unwrap();
    assert_error(
        &error(&m, &g7("K-2.03")),
        Code::Geometry,
        5,
        12,
        "Radius to end",
    );
    // 0.1 % of a 100 mm radius is 0.1 mm: 0.09 passes, 0.11 does not (as rs274).
    let big = |k: &str| format!("G8 G21 G18\nF100\nG0 X4 Z1\nG1 Z0\nG3 X104 Z-100 {k}\nM2\n");
    program::jobs(big("K-100.09").as_bytes(), &m).unwrap();
    assert_error(
        &error(&m, &big("K-100.11")),
        Code::Geometry,
        5,
        15,
        "Radius to end",
    );
    // Inch: 2·√2·0.001 inch = 0.00283.
    let inch = |k: &str| format!("G8 G20 G18\nF10\nG0 X0.4 Z0.1\nG1 Z0\nG3 X0.6 Z-0.2 {k}\nM2\n");
    program::jobs(inch("K-0.2025").as_bytes(), &m).unwrap();
    let d = error(&m, &inch("K-0.2029"));
    assert!(
        d.message.ends_with("abs_err=0.002879 rel_err=1.4189%"),
        "{}",
        d.message
    );
    // G90.1: I and K are the centre itself.
    program::jobs(
        "G8 G21 G18 G90.1\nF100\nG0 X4 Z1\nG1 Z0\nG3 X6 Z-2 I4 K-2\nM2\n".as_bytes(),
        &m,
    )
    .unwrap();
}

#[test]
fn linuxcnc_refuses_a_word_no_code_of_its_line_uses() {
    let m = machine("linuxcnc");
    for (line, word, message) in [
        ("G76 P2.5 Z-30 I-1 J0.1 K0.5 D1", "D1", "D word with no G41, G41.1, G42, G42.1, G71, G71.1, G71.2 G73, G83 or G96 to use it"),
        ("G0 X10 I1", "I1", "I word with no G2, G3, G5, G5.1, G6, G6.1, G10, G33.1, G76, or G87 to use it"),
        ("G1 X10 Z-5 J1 F0.1", "J1", "J word with no G2, G3, G5, G5.1, G6, G6.1, G10, G76 or G87 to use it"),
        ("G1 Z-5 K1 F0.1", "K1", "K word with no G2, G3, G6.2, G33, G33.1, G76, or G87 to use it"),
        ("G0 X10 E5", "E5", "E word with no G70, G76, M66, M67 or M68 to use it"),
        ("G0 X10 H1", "H1", "H word with no G43 or G76 to use it"),
        ("G0 X10 L2", "L2", "L word with no G10, cutter compensation, canned cycle, digital/analog input, M98 or NURBS code"),
        ("G1 X10 P2 F0.1", "P2", "P word with no G2 G3 G4 G10 G64 G5 G5.2 G6, G6.2, G76 G82 G86 G88 G89 or M50 M51 M52 M53 M62 M63 M64 M65 M66 M98 or user M code to use it"),
        ("G0 X10 Q29.5", "Q29.5", "Q word with no G5, G6, G10, G64, G73, G76, G83, M19, M66, M67, M68 or user M code that uses it"),
        ("G1 X10 R2 F0.1", "R2", "R word with no g code that uses it"),
        ("G0 X10 $0", "$0", "$ (spindle selection) word with no M3, M4, M5, M19, M51, G33, G33.1, G76, G95, G96 or G97 to use it"),
        // The modal G76 ends at G0: a later I has no G76 to go with.
        ("G0 X12\nZ5 I-1", "I-1", "I word with no"),
        // A line of I and K alone goes with an arc only.
        ("I1 K1", "I1", "I word with no"),
    ] {
        let e = error(&m, &format!("{LCNC_PRE}{line}\n"));
        let last = line.lines().last().unwrap();
        let at = 3 + line.lines().count() as u32;
        assert_error(&e, Code::Unsupported, at, column(last, word), message);
    }
    // The same words where a code of the line (or the modal motion) uses them (arcs whose end
    // points lie on their circles: rs274 checks that, and so does threadcut).
    for line in [
        "G76 P2.5 Z-30 I-1 J0.1 K0.5 R1.5 Q29.5 H1 E1 L1 $0",
        "G2 X13 Z3 I1 K-1 F0.1",
        "G2 X12 Z3 R1.2 F0.1\nX14 Z1 R1.5",
        "G3 X13 Z7 I1 K1 F0.1\nI1 K1",
        "G4 P0.5",
        "G96 D2500 S180",
        "G95 $0",
        "M3 $0 S300",
        "G43 H1",
        "G64 P0.01 Q0.005",
        "G41 D1",
        "G33 Z-10 K1.5",
        "G76 P2.5 Z-30 I-1 J0.1 K0.5\nZ-20 P2.5 I-1 J0.1 K0.5",
    ] {
        jobs(&m, &format!("{LCNC_PRE}{line}\n"));
    }
    // Axis words need a motion: none is in force at the start of a program or after G80.
    let e = error(&m, "G18\nX10 Z5\n");
    assert_error(
        &e,
        Code::Conflict,
        2,
        1,
        "Cannot use axis values without a g code that uses them",
    );
    let e = error(&m, &format!("{LCNC_PRE}G80\nX10\n"));
    assert_error(
        &e,
        Code::Conflict,
        5,
        1,
        "Cannot use axis values without a g code that uses them",
    );
    let e = error(&m, &format!("{LCNC_PRE}G80 X10\n"));
    assert_error(&e, Code::Conflict, 4, 5, "Cannot use axis values with g80");
    let e = error(&m, &format!("{LCNC_PRE}G28 G0 X10\n"));
    assert_error(
        &e,
        Code::Conflict,
        4,
        5,
        "Cannot use two g codes that both use axis values",
    );
    // What G33 and G96 need.
    let e = error(&m, &format!("{LCNC_PRE}G33 Z-10\n"));
    assert_error(&e, Code::MissingWord, 4, 1, "K word missing with g33/g33.1");
    let e = error(&m, &format!("{LCNC_PRE}G33 Z-10 K1.5 F200\n"));
    assert_error(&e, Code::Conflict, 4, 15, "F word used with a g33/g33.1");
    let e = error(&m, &format!("{LCNC_PRE}G96 D2500\n"));
    assert_error(&e, Code::MissingWord, 4, 1, "S word missing with G96");
    // Other controllers do not check unused words.
    jobs(&machine("fanuc"), "G0 X20. Z5. I1 Q2\n");
}

#[test]
fn numbers_have_no_exponent() {
    // LinuxCNC reads `X1e3` as X1 and E3, as it reads every E: an E no code uses is its error.
    let m = machine("linuxcnc");
    let line = "G0 X1e3 Z5";
    let e = error(&m, &format!("{LCNC_PRE}{line}\n"));
    assert_error(
        &e,
        Code::Unsupported,
        4,
        column(line, "e3"),
        "E word with no G70, G76, M66, M67 or M68 to use it",
    );
    // Elsewhere an E glued to a number, on a block where E means nothing, is refused as the
    // exponent it is: read as X1 it would move the tool somewhere else.
    for (name, src, at, text) in [
        (
            "fanuc",
            "G0 X20. Z5.\nG1 Z-1.5e2 F0.2\n",
            (2, 4),
            "`Z-1.5e2`",
        ),
        ("gsk980", "G00 X1E3 Z5\n", (1, 5), "`X1E3`"),
        ("ab9", "G20\nG0 X.5E1 Z.1\n", (2, 4), "`X.5E1`"),
        ("omniturn", "X.3Z.2\nX.25e-1\n", (2, 1), "`X.25e-1`"),
        ("haas", "G20\nG00 X.9E1 Z.3\n", (2, 5), "`X.9E1`"),
        (
            "fanuc15",
            "G0 X20. Z5.\nG1 Z-1.5e2 F0.2\n",
            (2, 4),
            "`Z-1.5e2`",
        ),
        (
            "fanuc-b",
            "G0 X20. Z5.\nG01 Z-1.5E2 F0.2\n",
            (2, 5),
            "`Z-1.5E2`",
        ),
        // Sinumerik writes an exponent as `EX` (`1.5EX2`); `1.5E2` is no number there either.
        (
            "sinumerik",
            "G0 X20 Z5\nG1 Z-1.5e2 F0.2\n",
            (2, 4),
            "`Z-1.5e2`",
        ),
    ] {
        let e = error(&machine(name), src);
        assert_error(&e, Code::Syntax, at.0, at.1, text);
        assert!(
            e.message.contains("G-code numbers have no exponent"),
            "{}",
            e.message
        );
    }
    // Where E is a word of the block, it is that word, glued or not: Allen-Bradley's threads per
    // inch on G33 and G78, GSK's lead-in on the first G78 block.
    let ab = jobs(
        &machine("ab9"),
        "G20\nG0 X.6 Z.2\nG78X.4056Z-.75K.0472D.01E13A60P3\n",
    );
    assert!((ab[0].lead.lead - 25.4 / 13.0).abs() < 1e-12);
    let mut out = Vec::new();
    program::expand_gcode(
        &b"G20\nG0 X.6 Z.2\nG33 X.6 Z-.75E13\n"[..],
        &mut out,
        &machine("ab9"),
    )
    .unwrap();
    jobs(
        &machine("gsk980"),
        "G00 X40 Z5\nG78 P010060 Q0.1 R0.05 E0.5\nG78 X36.933 Z-30 P1.534 Q0.3 F2.5\n",
    );
    // Haas's E is G76's and G92's lead (F(E)), glued to the word before it or not.
    let haas = jobs(
        &machine("haas"),
        "G20\nG00 X.6 Z.25\nG76 X.4056 Z-.75 K.0472 D.012E.0769 A60 P2\n",
    );
    assert!((haas[0].lead.lead - 0.0769 * 25.4).abs() < 1e-12);
    // An E with a blank before it is an E word as before (Fanuc's plain blocks ignore it).
    jobs(&machine("fanuc"), "G0 X20. E5\n");
}
