//! LinuxCNC G76: motion compared with LinuxCNC's own canonical calls (the worked output of
//! `shared/reference/linuxcnc-g76.md` §3) and with an oracle that follows the notes' §1.2–1.4
//! pseudo-code literally, to 1e-9 mm.

use std::process::Command;

use threadcut::machine::Machine;
use threadcut::post::path_lead;
use threadcut::program;
use threadcut::toolpath::{self, MotionKind};

/// One canonical move: rapid or synchronised feed, radius X, Z, and the sync pitch.
#[derive(Debug, Clone, Copy)]
struct Canon {
    rapid: bool,
    x: f64,
    z: f64,
    pitch: f64,
}

fn linuxcnc() -> Machine {
    Machine::built_in("linuxcnc").unwrap()
}

/// threadcut's motion of the program's only G76, as canonical moves (the G76 part only).
fn ours(src: &str) -> Vec<Canon> {
    let jobs = program::jobs(src.as_bytes(), &linuxcnc()).unwrap_or_else(|e| panic!("{e}\n{src}"));
    assert_eq!(jobs.len(), 1);
    let path = toolpath::build(&jobs[0]).unwrap();
    path.segments()
        .map(|(from, m)| match m.kind {
            MotionKind::Rapid => Canon {
                rapid: true,
                x: m.to.x,
                z: m.to.z,
                pitch: 0.0,
            },
            MotionKind::Thread { lead, .. } => Canon {
                rapid: false,
                x: m.to.x,
                z: m.to.z,
                pitch: path_lead(lead, m.to.minus(from)),
            },
            MotionKind::Feed | MotionKind::Arc { .. } => panic!("G76 makes no plain feed"),
        })
        .collect()
}

/// Parameters of the oracle, radius values after any G7 halving.
#[derive(Clone, Copy, Debug)]
struct G76 {
    x0: f64,
    z0: f64,
    p: f64,
    z: f64,
    i: f64,
    j: f64,
    k: f64,
    r: f64,
    q: f64,
    h: i32,
    e: f64,
    l: u32,
}

/// `linuxcnc-g76.md` §1.2–1.4, transcribed line by line.
fn oracle(c: G76) -> Vec<Canon> {
    let boring = c.i > 0.0;
    let sgn = |d: f64| if boring { c.x0 + d } else { c.x0 - d };
    let start_depth = c.i.abs() + c.j.abs();
    let end_depth = c.i.abs() + c.k.abs();
    let h = c.k.abs();
    let mut q = c.q.to_radians();
    if c.z > c.z0 {
        q = -q;
    }
    let r = c.r.max(1.0);
    let mut taper = c.e.max(0.0);
    let taper_pitch = if taper > 0.0 {
        c.p * taper.hypot(h) / taper
    } else {
        c.p
    };
    if c.z > c.z0 {
        taper = -taper;
    }
    let target_z = c.z + h * q.tan();
    let mut out = Vec::new();
    let rapid = |out: &mut Vec<Canon>, x: f64, z: f64| {
        out.push(Canon {
            rapid: true,
            x,
            z,
            pitch: 0.0,
        })
    };
    let feed = |out: &mut Vec<Canon>, x: f64, z: f64, pitch: f64| {
        out.push(Canon {
            rapid: false,
            x,
            z,
            pitch,
        })
    };
    let pass = |out: &mut Vec<Canon>, d: f64| {
        let zoff = (d - c.i.abs()) * q.tan();
        let xcut = sgn(d);
        let xback = sgn(d - end_depth);
        let xtap = sgn(d - h);
        rapid(out, xback, c.z0 - zoff);
        if taper != 0.0 && c.l & 1 != 0 {
            feed(out, xtap, c.z0 - zoff, taper_pitch);
            feed(out, xcut, c.z0 - zoff - taper, taper_pitch);
        } else {
            rapid(out, xcut, c.z0 - zoff);
        }
        if taper != 0.0 && c.l & 2 != 0 {
            feed(out, xcut, target_z - zoff + taper, c.p);
            feed(out, xtap, target_z - zoff, taper_pitch);
        } else {
            feed(out, xcut, target_z - zoff, c.p);
        }
        rapid(out, xback, target_z - zoff);
    };
    let mut n = 1;
    let mut depth = start_depth;
    while depth < end_depth {
        pass(&mut out, depth);
        n += 1;
        depth = c.i.abs() + c.j.abs() * f64::from(n).powf(1.0 / r);
    }
    for _ in 0..=c.h {
        pass(&mut out, end_depth);
    }
    rapid(&mut out, c.x0, c.z);
    out
}

fn assert_same(a: &[Canon], b: &[Canon], tol: f64, what: &str) {
    assert_eq!(
        a.len(),
        b.len(),
        "{what}: move count\nours {a:?}\noracle {b:?}"
    );
    for (n, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(x.rapid, y.rapid, "{what}: move {} kind", n + 1);
        let bad =
            (x.x - y.x).abs() > tol || (x.z - y.z).abs() > tol || (x.pitch - y.pitch).abs() > tol;
        assert!(!bad, "{what}: move {}: ours {x:?} LinuxCNC {y:?}", n + 1);
    }
}

fn program(c: &G76, diameter: bool) -> String {
    let s = if diameter { 2.0 } else { 1.0 };
    let mut t = format!(
        "{}\nG21 G18\nS500 M3\nG0 X{} Z{}\nG76 P{} Z{} I{} J{} K{}",
        if diameter { "G7" } else { "G8" },
        c.x0 * s,
        c.z0,
        c.p,
        c.z,
        c.i * s,
        c.j * s,
        c.k * s
    );
    if c.r != 1.0 {
        t.push_str(&format!(" R{}", c.r));
    }
    if c.q != 0.0 {
        t.push_str(&format!(" Q{}", c.q));
    }
    t.push_str(&format!(" H{}", c.h));
    if c.e != 0.0 {
        t.push_str(&format!(" E{} L{}", c.e, c.l));
    }
    t + "\nM2\n"
}

const M20: G76 = G76 {
    x0: 11.0,
    z0: 5.0,
    p: 2.5,
    z: -30.0,
    i: -0.5,
    j: 0.15,
    k: 0.76675,
    r: 1.5,
    q: 29.5,
    h: 2,
    e: 2.0,
    l: 2,
};

#[test]
fn worked_output_of_the_notes_matches_to_its_printed_digits() {
    // linuxcnc-g76.md §3, printed by LinuxCNC's rs274 with 4 decimals (pitches with 6).
    let src = "G7 G21 G18\nS500 M3\nG0 X22 Z5\nG76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\nM2\n";
    let got = ours(src);
    assert_eq!(
        got.len(),
        14 * 5 + 1,
        "14 passes of 5 moves and the final rapid"
    );
    let first = [
        (true, 11.6167, 4.9151, 0.0),
        (true, 10.3500, 4.9151, 0.0),
        (false, 10.3500, -27.6511, 2.5),
        (false, 11.1167, -29.6511, 2.677425),
        (true, 11.6167, -29.6511, 0.0),
    ];
    for (m, (rapid, x, z, p)) in got.iter().zip(first) {
        assert_eq!(m.rapid, rapid);
        assert!(
            (m.x - x).abs() < 0.5e-4 && (m.z - z).abs() < 0.5e-4,
            "{m:?}"
        );
        assert!((m.pitch - p).abs() < 0.5e-6, "{m:?}");
    }
    let last = &got[got.len() - 6..];
    let expect = [
        (true, 11.0, 4.5662),
        (true, 9.7332, 4.5662),
        (false, 9.7332, -28.0),
        (false, 10.5, -30.0),
        (true, 11.0, -30.0),
        (true, 11.0, -30.0),
    ];
    for (m, (rapid, x, z)) in last.iter().zip(expect) {
        assert_eq!(m.rapid, rapid);
        assert!(
            (m.x - x).abs() < 0.5e-4 && (m.z - z).abs() < 0.5e-4,
            "{m:?}"
        );
    }
    assert_same(&got, &oracle(M20), 1e-9, "worked example");
}

#[test]
fn m20_in_diameter_and_radius_mode_give_identical_motion() {
    // §3: m20_dia (G7, I-2.0 J0.6 K3.067) and m20_rad (G8, I-1.0 J0.3 K1.5335) are identical:
    // 14 passes, first cut X 9.7000 at Z 4.8303, final cut X 8.4665 from Z 4.1324 to -28.0000,
    // then a ramp to (10.0000, -30.0000), taper pitch 3.150303.
    let m20 = G76 {
        x0: 11.0,
        i: -1.0,
        j: 0.3,
        k: 1.5335,
        ..M20
    };
    let dia = ours(&program(&m20, true));
    let rad = ours(&program(&m20, false));
    assert_same(&dia, &rad, 1e-12, "G7 vs G8");
    assert_same(&rad, &oracle(m20), 1e-9, "m20");
    assert_eq!(rad.len(), 14 * 5 + 1);
    assert!((rad[1].x - 9.7).abs() < 0.5e-4 && (rad[1].z - 4.8303).abs() < 0.5e-4);
    let fin = &rad[rad.len() - 5..];
    assert!((fin[0].x - 8.4665).abs() < 0.5e-4 && (fin[0].z - 4.1324).abs() < 0.5e-4);
    assert!((fin[1].z + 28.0).abs() < 1e-9 && (fin[2].x - 10.0).abs() < 1e-9);
    assert!((fin[2].pitch - 3.150303).abs() < 0.5e-6);
}

#[test]
fn entry_taper_first_pass_matches_linuxcnc() {
    // §3: the M20 thread with L1: TRAVERSE(12.2335,4.8303), SYNC(3.150303) FEED(11.2335,4.8303),
    // FEED(9.7000,2.8303), SYNC(2.5) FEED(9.7000,-29.3021), TRAVERSE(12.2335,-29.3021).
    let c = G76 {
        i: -1.0,
        j: 0.3,
        k: 1.5335,
        l: 1,
        ..M20
    };
    let got = ours(&program(&c, false));
    let expect = [
        (true, 12.2335, 4.8303, 0.0),
        (false, 11.2335, 4.8303, 3.150303),
        (false, 9.7, 2.8303, 3.150303),
        (false, 9.7, -29.3021, 2.5),
        (true, 12.2335, -29.3021, 0.0),
    ];
    for (m, (rapid, x, z, p)) in got.iter().zip(expect) {
        assert_eq!(m.rapid, rapid, "{m:?}");
        assert!(
            (m.x - x).abs() < 0.5e-4 && (m.z - z).abs() < 0.5e-4,
            "{m:?}"
        );
        assert!((m.pitch - p).abs() < 0.5e-6, "{m:?}");
    }
    assert_same(&got, &oracle(c), 1e-9, "entry taper");
}

#[test]
fn a_grid_of_well_formed_programs_matches_the_oracle_to_1e_9() {
    let mut count = 0;
    for (x0, i) in [(11.0, -0.5), (6.0, 1.2), (20.0, -2.0)] {
        for (z0, z) in [(5.0, -30.0), (-40.0, 2.0), (0.0, -12.5)] {
            for (j, k) in [(0.15, 0.76675), (0.1, 0.95), (0.4, 1.3)] {
                for r in [1.0, 1.5, 2.0, 2.6] {
                    for q in [0.0, 29.5, 30.0, -10.0] {
                        for (e, l) in [(0.0, 0), (1.5, 1), (2.0, 2), (1.0, 3), (2.0, 4)] {
                            for h in [0, 3] {
                                let c = G76 {
                                    x0,
                                    z0,
                                    p: 1.75,
                                    z,
                                    i,
                                    j,
                                    k,
                                    r,
                                    q,
                                    h,
                                    e,
                                    l,
                                };
                                let src = program(&c, false);
                                assert_same(&ours(&src), &oracle(c), 1e-9, &src);
                                count += 1;
                            }
                        }
                    }
                }
            }
        }
    }
    assert_eq!(count, 3 * 3 * 3 * 4 * 4 * 5 * 2);
}

#[test]
fn incremental_z_and_inch_units() {
    // G91: Z-35 from Z5 ends at -30 (§1.1). G20: every length in inches.
    let a = ours("G8 G21\nM3 S300\nG0 X11 Z5\nG91\nG76 P2.5 Z-35 I-0.5 J0.15 K0.76675 H1\n");
    let b = ours("G8 G21\nM3 S300\nG0 X11 Z5\nG76 P2.5 Z-30 I-0.5 J0.15 K0.76675 H1\n");
    assert_same(&a, &b, 1e-12, "G91");
    let inch = ours("G20 G8\nM3\nG0 X0.5 Z0.2\nG76 P0.0625 Z-1 I-0.02 J0.005 K0.0383 R2 Q29 H1\n");
    let c = G76 {
        x0: 0.5 * 25.4,
        z0: 0.2 * 25.4,
        p: 0.0625 * 25.4,
        z: -25.4,
        i: -0.02 * 25.4,
        j: 0.005 * 25.4,
        k: 0.0383 * 25.4,
        r: 2.0,
        q: 29.0,
        h: 1,
        e: 0.0,
        l: 0,
    };
    assert_same(&inch, &oracle(c), 1e-9, "inch");
}

fn error_of(src: &str) -> threadcut::diag::Diagnostic {
    match program::jobs(src.as_bytes(), &linuxcnc()) {
        Err(program::Error::Input(d)) => d,
        other => panic!("expected an error for {src:?}, got {other:?}"),
    }
}

#[test]
fn linuxcnc_error_texts_in_their_order() {
    let pre = "G8 G18\nM3 S100\nG0 X11 Z5\n";
    for (block, text) in [
        ("G76 P2 Z-20 I-1 J0.1 K0.5 H-2", "Negative h word used"),
        ("G76 P2 Z-20 I-1 J0.1 K0.5 L-1", "Negative l word used"),
        (
            "G76 P2 Z-20 I-1 J0.1 K0.5 H1.5",
            "Non integer value for integer",
        ),
        ("G76 P2 I-1 J0.1 K0.5", "All axes missing with motion code"),
        ("G76 Z-20 I-1 J0.1 K0.5", "P word missing with G76"),
        ("G76 P-1 Z-20 I-1 J0.1 K0.5", "P word missing with G76"),
        ("G76 P2 Z-20 I-1 K0.5", "I J or K words missing with G76"),
        (
            "G76 P2 Z-20 I-1 J0.1 K0.5 $1",
            "Invalid D-number in G76 cycle",
        ),
        (
            "G76 P2 Z-20 I-1 J0.1 K0.5 A3",
            "Cannot move rotary axes with G76",
        ),
        ("G76 P2 Z-20 I0 J0.1 K0.5", "In G76, I must not be 0"),
        (
            "G76 P2 Z-20 I-1 J0 K0.5",
            "In G76, J must be greater than 0",
        ),
        (
            "G76 P2 Z-20 I-1 J0.1 K0.1",
            "In G76, K must be greater than J",
        ),
        (
            "G76 P2 Z-20 I-1 J0.1 K-0.5",
            "In G76, K must be greater than J",
        ),
        (
            "G41.1 D1\nG76 P2 Z-20 I-1 J0.1 K0.5",
            "Cannot use G76 threading cycle with cutter radius compensation on",
        ),
    ] {
        let e = error_of(&format!("{pre}{block}\n"));
        assert_eq!(e.message, text, "{block}");
        assert!(e.span.line >= 4, "{block}: {:?}", e.span);
    }
    let e = error_of("G8\nG0 X11 Z5\nG76 P2 Z-20 I-1 J0.1 K0.5\n");
    assert_eq!(e.message, "Chosen spindle (0) not turning in G76");
    // G76 is modal, P/I/J/K are not: a bare Z line after it is another G76 without P.
    let e = error_of(&format!("{pre}G76 P2 Z-20 I-1 J0.1 K0.5\nZ-25\n"));
    assert_eq!(
        (e.message.as_str(), e.span.line),
        ("P word missing with G76", 5)
    );
}

#[test]
fn documented_errors_linuxcnc_does_not_raise_are_refused() {
    let pre = "G8 G18\nM3 S100\nG0 X11 Z5\n";
    for (block, needle) in [
        ("G76 P2 Z-20 I-1 J0.1 K0.5 H-1", "Negative h word used"),
        ("G76 P2 Z-20 I-1 J0.1 K0.5 R0.5", "at least 1.0"),
        ("G76 P2 Z-20 X10 I-1 J0.1 K0.5", "not a word of G76"),
        ("G76 P0 Z-20 I-1 J0.1 K0.5", "must be positive"),
        (
            "G76 P2 Z-20 I-1 J0.1 K0.5 E13 L3",
            "longer than half the drive line",
        ),
        ("G17\nG76 P2 Z-20 I-1 J0.1 K0.5", "ZX plane"),
    ] {
        let e = error_of(&format!("{pre}{block}\n"));
        assert!(e.message.contains(needle), "{block}: {}", e.message);
    }
}

#[test]
fn floating_point_sliver_pass_is_not_cut() {
    // §1.6 quirk 2: I-0.1 J0.3 K0.9 R1 H0 gives LinuxCNC a fourth pass at 0.9−1e-16; threadcut
    // treats depths within 1e-9 mm of K as K (docs/dialects/linuxcnc-g76.md).
    let src = "G8\nM3\nG0 X5 Z1\nG76 P1 Z-10 I-0.1 J0.3 K0.9 H0\n";
    let job = &program::jobs(src.as_bytes(), &linuxcnc()).unwrap()[0];
    let depths: Vec<f64> = job.passes().unwrap().iter().map(|p| p.depth).collect();
    assert_eq!(depths.len(), 3, "{depths:?}");
    assert!((depths[1] - 0.6).abs() < 1e-12 && depths[2] == 0.9);
}

#[test]
fn g7_on_the_g76_line_halves_once() {
    // §1.6 quirk 1 (LinuxCNC halves twice): threadcut follows the documentation.
    let same_line = ours("G8\nM3\nG0 X11 Z5\nG7 G76 P2.5 Z-30 I-2.0 J0.6 K3.067 H1\n");
    let earlier = ours("G7\nM3\nG0 X22 Z5\nG76 P2.5 Z-30 I-2.0 J0.6 K3.067 H1\n");
    assert_same(&same_line, &earlier, 1e-12, "G7 on the G76 line");
}

#[test]
fn expand_writes_g33_k_in_the_programs_x_mode_and_ends_at_z_end() {
    let dir = std::env::temp_dir().join(format!("threadcut-lcnc-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("m20.ngc");
    std::fs::write(
        &file,
        "G7 G21 G18\nS500 M3\nG0 X22 Z5\nG76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\nG0 X30\nM2\n",
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(["expand", file.to_str().unwrap(), "--controller", "linuxcnc"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[4], "G0 X23.2335 Z4.9151");
    assert_eq!(lines[6], "G33 X20.7 Z-27.6511 K2.5");
    assert_eq!(lines[7], "G33 X22.2335 Z-29.6511 K2.677425");
    assert!(text.contains("G0 X22. Z-30.\nG0 X30\n"), "{text}");
    // Read back by threadcut's LinuxCNC reader, the expansion is plain G0/G33: no cycle left.
    let back = program::jobs(text.as_bytes(), &linuxcnc()).unwrap();
    assert!(back.is_empty());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn every_example_expands() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples");
    let mut n = 0;
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_str().unwrap().to_string();
        // The profile a file's name begins with (the longest: `fanuc-b-…` is system B's).
        let Some(controller) = ["linuxcnc", "fanuc-b", "fanuc15", "fanuc", "haas"]
            .into_iter()
            .find(|c| name.starts_with(&format!("{c}-")))
        else {
            continue;
        };
        let text = std::fs::read(&path).unwrap();
        let m = Machine::built_in(controller).unwrap();
        let jobs = program::jobs(&text[..], &m).unwrap_or_else(|e| panic!("{name}: {e}"));
        for j in &jobs {
            toolpath::build(j).unwrap();
        }
        // Every example cuts a thread: a cycle, or passes written as plain moves.
        let mut threads = 0;
        threadcut::threads::each_gcode(&text[..], &m, None, |_| {
            threads += 1;
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(threads > 0, "{name}");
        n += 1;
    }
    assert!(n >= 8);
}
