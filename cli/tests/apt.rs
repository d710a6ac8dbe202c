//! APT/CL THREAD (seed 000): every parameter, every row of the DEPTH/CUTS/STEP table, every
//! conflict with its place, face, multi-start and variable-lead threads, and the posted output.

use threadcut::apt;
use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::Machine;
use threadcut::program::{self, Error};
use threadcut::thread::{Exit, Flank, Infeed, Job, PassKind, Side};
use threadcut::toolpath::{self, MotionKind};
use threadcut::translate;
use threadcut::units::Pos;

const EPS: f64 = 1e-9;

/// A CL program around one THREAD/ON: initial point (12, 5), contour X10 Z5 → X10 Z-30, pitch 2 mm.
fn wrap(params: &str) -> String {
    format!(
        "UNITS/MM\nPITCH/2,MMPR\nRAPID\nGOTO/12,0,5\nTHREAD/ON{params}\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\nFINI\n"
    )
}

fn job(src: &str) -> Job {
    let mut jobs = apt::jobs(src.as_bytes()).unwrap_or_else(|e| panic!("{e}\n{src}"));
    assert_eq!(jobs.len(), 1);
    jobs.remove(0)
}

fn err(src: &str) -> Diagnostic {
    match apt::jobs(src.as_bytes()) {
        Err(Error::Input(d)) => d,
        Err(e) => panic!("not an input error: {e}"),
        Ok(_) => panic!("accepted:\n{src}"),
    }
}

/// Rough and finish depths (mm along the in-feed axis).
fn depths(j: &Job) -> (Vec<f64>, Vec<f64>) {
    let p = j.passes().unwrap();
    (
        p.iter()
            .filter(|p| p.kind == PassKind::Rough)
            .map(|p| p.depth)
            .collect(),
        p.iter()
            .filter(|p| p.kind == PassKind::Finish)
            .map(|p| p.depth)
            .collect(),
    )
}

fn close(a: &[f64], b: &[f64]) {
    assert_eq!(a.len(), b.len(), "{a:?} vs {b:?}");
    for (x, y) in a.iter().zip(b) {
        assert!((x - y).abs() < 1e-9, "{a:?} vs {b:?}");
    }
}

/// The place of a diagnostic in the source: line and column of the word it names.
fn at(d: &Diagnostic) -> (u32, u32) {
    (d.span.line, d.span.column)
}

// ---- the table of permitted combinations ------------------------------------------------------

#[test]
fn row1_depth_cuts_step_constant_steps_verified() {
    let j = job(&wrap(",DEPTH,1.25,CUTS,4,STEP,0.3,FINCUT,1,0.05"));
    let (r, f) = depths(&j);
    close(&r, &[0.3, 0.6, 0.9, 1.2]);
    close(&f, &[1.25]);
    // The same without DEPTH, and with the bare-step form CUTS,c,s.
    for p in [
        ",CUTS,4,STEP,0.3,FINCUT,1,0.05",
        ",CUTS,4,0.3,FINCUT,1,0.05",
        ",DEPTH,1.25,CUTS,4,0.3,FINCUT,1,0.05",
    ] {
        let (r2, f2) = depths(&job(&wrap(p)));
        close(&r2, &r);
        close(&f2, &f);
    }
}

#[test]
fn row1_depth_that_does_not_match_is_a_conflict_at_depth() {
    let d = err(&wrap(",DEPTH,1.3,CUTS,4,STEP,0.3,FINCUT,1,0.05"));
    assert_eq!(d.code, Code::Conflict);
    assert_eq!(at(&d), (5, 11));
    assert!(d.message.contains("1.25"), "{d}");
    // Within half a unit of the fourth decimal it verifies.
    depths(&job(&wrap(",DEPTH,1.25004,CUTS,4,STEP,0.3,FINCUT,1,0.05")));
}

#[test]
fn couplets_give_the_exact_sequence() {
    let j = job(&wrap(",DEPTH,0.95,CUTS,2,0.3,3,0.1,FINCUT,1,0.05"));
    let (r, f) = depths(&j);
    close(&r, &[0.3, 0.6, 0.7, 0.8, 0.9]);
    close(&f, &[0.95]);
    let d = err(&wrap(",CUTS,2,0.3,3"));
    assert_eq!((d.code, at(&d)), (Code::Syntax, (5, 22)));
}

#[test]
fn row2_depth_cuts_follow_the_option_law() {
    // OPTION 0: steps decrease by a constant amount: 4,3,2,1 × 2·1.2/20.
    let (r, _) = depths(&job(&wrap(",DEPTH,1.2,CUTS,4")));
    close(&r, &[0.48, 0.84, 1.08, 1.2]);
    // OPTION 1/2: constant cross-section, d_n = D·√(n/c).
    for o in [1, 2] {
        let (r, _) = depths(&job(&wrap(&format!(",DEPTH,1.2,CUTS,4,OPTION,{o}"))));
        close(&r, &[0.6, 1.2 * 0.5f64.sqrt(), 1.2 * 0.75f64.sqrt(), 1.2]);
    }
    // OPTION 3/4: constant depth.
    for o in [3, 4] {
        let (r, _) = depths(&job(&wrap(&format!(",DEPTH,1.2,CUTS,4,OPTION,{o}"))));
        close(&r, &[0.3, 0.6, 0.9, 1.2]);
    }
    // c cuts over the depth less the finish allowance.
    let (r, f) = depths(&job(&wrap(",DEPTH,1.25,CUTS,4,OPTION,3,FINCUT,2,0.05")));
    close(&r, &[0.3, 0.6, 0.9, 1.2]);
    close(&f, &[1.25, 1.25]);
}

#[test]
fn row3_depth_step_first_step_then_the_option_law() {
    // OPTION 0: N = ⌈2·1.2/0.5 − 1⌉ = 4, decrement 0.5/4: 0.5, 0.375, 0.25, then clipped.
    let (r, _) = depths(&job(&wrap(",DEPTH,1.2,STEP,0.5")));
    close(&r, &[0.5, 0.875, 1.125, 1.2]);
    let (r, _) = depths(&job(&wrap(",DEPTH,1.2,STEP,0.5,OPTION,1")));
    close(
        &r,
        &[
            0.5,
            0.5 * 2f64.sqrt(),
            0.5 * 3f64.sqrt(),
            1.0,
            0.5 * 5f64.sqrt(),
            1.2,
        ],
    );
    let (r, _) = depths(&job(&wrap(",DEPTH,1.2,STEP,0.5,OPTION,3")));
    close(&r, &[0.5, 1.0, 1.2]);
}

#[test]
fn row4_depth_alone_is_one_pass_at_full_depth() {
    let (r, f) = depths(&job(&wrap(",DEPTH,1.2")));
    close(&r, &[1.2]);
    assert!(f.is_empty());
}

#[test]
fn row5_cuts_1_is_one_pass_on_the_contour() {
    let j = job(&wrap(",CUTS,1"));
    let (r, _) = depths(&j);
    close(&r, &[0.0]);
    let path = toolpath::build(&j).unwrap();
    let thread: Vec<_> = path
        .motions
        .iter()
        .filter(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .collect();
    assert_eq!(thread.len(), 1);
    assert_eq!(thread[0].to, Pos::new(10.0, -30.0));
    assert_eq!(path.motions[0].to, Pos::new(10.0, 5.0));
}

#[test]
fn combinations_outside_the_table_are_errors_with_places() {
    let cases: &[(&str, Code, (u32, u32))] = &[
        (",STEP,0.2", Code::MissingWord, (5, 11)),
        (",CUTS,3", Code::MissingWord, (5, 11)),
        ("", Code::MissingWord, (5, 1)),
        (",CUTS,2,0.3,STEP,0.2", Code::Conflict, (5, 22)),
        (",DEPTH,1,DEPTH,2", Code::Conflict, (5, 19)),
        (",DEPTH,-1", Code::OutOfRange, (5, 11)),
        (",DEPTH,1,FINCUT,1,1", Code::OutOfRange, (5, 19)),
        (",CUTS,1,FINCUT,1,0.1", Code::Conflict, (5, 18)),
        (",DEPTH,1,SPEED,3", Code::Unsupported, (5, 19)),
        (",DEPTH,1,3", Code::Syntax, (5, 19)),
    ];
    for (p, code, place) in cases {
        let d = err(&wrap(p));
        assert_eq!((d.code, at(&d)), (*code, *place), "{p}: {d}");
    }
}

#[test]
fn fincut_with_zero_cuts_cuts_to_depth_less_dist() {
    let (r, f) = depths(&job(&wrap(",DEPTH,1.2,CUTS,3,OPTION,3,FINCUT,0,0.3")));
    close(&r, &[0.3, 0.6, 0.9]);
    assert!(f.is_empty());
    let j = job(&wrap(",DEPTH,1.2,FINCUT,2"));
    let (r, f) = depths(&j);
    close(&r, &[1.2]);
    close(&f, &[1.2, 1.2]); // spring passes
}

#[test]
fn two_hundred_cuts_per_cycle() {
    let (r, _) = depths(&job(&wrap(",DEPTH,2,CUTS,200,OPTION,3")));
    assert_eq!(r.len(), 200);
    for p in [
        ",DEPTH,2,CUTS,201",
        ",CUTS,100,0.01,101,0.01",
        ",DEPTH,2,CUTS,200,FINCUT,1",
    ] {
        let d = err(&wrap(p));
        assert_eq!(d.code, Code::TooManyPasses, "{p}");
        assert_eq!(d.span.line, 5);
    }
    let d = err(&wrap(",DEPTH,2,STEP,0.001,OPTION,3"));
    assert_eq!((d.code, at(&d)), (Code::TooManyPasses, (5, 19)));
}

// ---- in-feed: CUTANG, TLANGL, OPTION ---------------------------------------------------------

#[test]
fn default_cutang_follows_the_initial_point() {
    let j = job(&wrap(",DEPTH,1"));
    assert_eq!(
        (j.geometry.side, j.infeed),
        (Side::External, Infeed::Radial)
    );
    // From below the contour: an internal thread, in-feed toward +X.
    let src = "UNITS/MM\nPITCH/2,MMPR\nGOTO/8,0,5\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\n";
    let j = job(src);
    assert_eq!(j.geometry.side, Side::Internal);
    assert_eq!(j.passes().unwrap()[0].start, Pos::new(11.0, 5.0));
}

#[test]
fn cutang_gives_an_oblique_plunge_line() {
    // 150°: 30° off −X toward +Z. Depth is the perpendicular distance from the thread line.
    let j = job(&wrap(",CUTS,3,0.4,CUTANG,150"));
    assert!(matches!(
        j.infeed,
        Infeed::Flank {
            flank: Flank::Left,
            ..
        }
    ));
    assert!((j_angle(&j) - 30.0).abs() < 1e-12);
    for p in j.passes().unwrap() {
        let t = 30f64.to_radians().tan();
        assert!((p.start.x - (10.0 - p.depth)).abs() < EPS);
        assert!((p.start.z - (5.0 + p.depth * t)).abs() < EPS, "{p:?}");
    }
}

fn j_angle(j: &Job) -> f64 {
    match j.infeed {
        Infeed::Flank { angle_deg, .. } => angle_deg,
        _ => f64::NAN,
    }
}

#[test]
fn cutang_range_and_the_ten_degree_rule() {
    for (p, code, col) in [
        (",DEPTH,1,CUTANG,400", Code::OutOfRange, 19),
        (",DEPTH,1,CUTANG,95", Code::OutOfRange, 19),
        (",DEPTH,1,CUTANG,-100", Code::OutOfRange, 19),
        (",DEPTH,1,CUTANG,135,OPTION,1", Code::Conflict, 30),
    ] {
        let d = err(&wrap(p));
        assert_eq!((d.code, at(&d)), (code, (5, col)), "{p}: {d}");
    }
    // 100° is exactly 10° from the Z axis: refused; 101° is accepted.
    assert_eq!(err(&wrap(",DEPTH,1,CUTANG,100")).code, Code::OutOfRange);
    job(&wrap(",DEPTH,1,CUTANG,101"));
}

#[test]
fn taper_depth_is_perpendicular_to_the_thread_line() {
    let src = "UNITS/MM\nPITCH/2,MMPR\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/9,0,-5\nTHREAD/OFF\n";
    let j = job(src);
    let p = j.passes().unwrap()[0];
    // Distance of the pass point from the line through (10,5)-(9,-5).
    let (dx, dz) = (-1.0f64, -10.0f64);
    let len = dx.hypot(dz);
    let dist = ((p.start.x - 10.0) * dz - (p.start.z - 5.0) * dx).abs() / len;
    assert!((dist - 1.0).abs() < 1e-12, "{dist}");
    assert_eq!(p.start.z, 5.0);
}

#[test]
fn options_single_and_alternating_edges_with_tlangl() {
    let t = 27.5f64.to_radians().tan();
    let j = job(&wrap(",DEPTH,1.2,CUTS,4,OPTION,3,TLANGL,55"));
    assert_eq!(j.tool_angle_deg, 55.0);
    // Single edge: every pass offset by tan(angle/2)·depth, back toward the start (+Z here).
    for p in j.passes().unwrap() {
        assert!((p.offset - p.depth * t).abs() < EPS);
    }
    // Alternating: only the even-numbered cuts are offset.
    let j = job(&wrap(",DEPTH,1.2,CUTS,4,OPTION,4,TLANGL,55"));
    for p in j.passes().unwrap() {
        let want = if p.n % 2 == 0 { p.depth * t } else { 0.0 };
        assert!((p.offset - want).abs() < EPS, "{p:?}");
    }
    assert_eq!(err(&wrap(",DEPTH,1,OPTION,5")).code, Code::OutOfRange);
    assert_eq!(err(&wrap(",DEPTH,1,TLANGL,0")).code, Code::OutOfRange);
}

// ---- chamfer, pull-out, return ---------------------------------------------------------------

#[test]
fn atangl_with_its_default_height() {
    let h = 2.0 / (2.0 * 30f64.to_radians().tan());
    let j = job(&wrap(",DEPTH,1,ATANGL,45"));
    match j.exit {
        Exit::PullOut {
            start_before,
            length,
            outward,
        } => {
            assert_eq!(start_before, 0.0);
            assert!((outward - h).abs() < EPS && (length - h).abs() < EPS);
        }
        e => panic!("{e:?}"),
    }
    // 20° off X is 70° from the thread axis: linear.
    assert!(
        matches!(job(&wrap(",DEPTH,1,ATANGL,20,1")).exit, Exit::FeedOut { outward, .. } if outward == 1.0)
    );
    for p in [",DEPTH,1,ATANGL,0", ",DEPTH,1,ATANGL,0,0"] {
        assert_eq!(job(&wrap(p)).exit, Exit::Straight, "{p}");
    }
    assert_eq!(err(&wrap(",DEPTH,1,ATANGL,85")).code, Code::OutOfRange);
}

#[test]
fn chamfr_length_angle_and_off() {
    let j = job(&wrap(",DEPTH,1,CHAMFR,2"));
    assert_eq!(
        j.exit,
        Exit::PullOut {
            start_before: 0.0,
            length: 2.0,
            outward: 2.0 * 45f64.to_radians().tan()
        }
    );
    let j = job(&wrap(",DEPTH,1,CHAMFR,-2,60"));
    match j.exit {
        Exit::PullOut {
            start_before,
            length,
            outward,
        } => {
            assert_eq!((start_before, length), (2.0, 2.0));
            assert!((outward - 2.0 * 3f64.sqrt()).abs() < EPS);
        }
        e => panic!("{e:?}"),
    }
    assert!(matches!(
        job(&wrap(",DEPTH,1,CHAMFR,2,20")).exit,
        Exit::FeedOut { .. }
    ));
    for p in [",DEPTH,1,CHAMFR,0", ",DEPTH,1,CHAMFR,0,0"] {
        assert_eq!(job(&wrap(p)).exit, Exit::Straight);
    }
    let d = err(&wrap(",DEPTH,1,CHAMFR,2,5"));
    assert_eq!((d.code, at(&d)), (Code::OutOfRange, (5, 19)));
}

#[test]
fn third_goto_is_the_chamfer_and_only_one_method_is_allowed() {
    let src = "UNITS/MM\nPITCH/2,MMPR\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/10,0,-30\nGOTO/11.5,0,-31.5\nTHREAD/OFF\n";
    let j = job(src);
    assert_eq!(
        j.exit,
        Exit::PullOut {
            start_before: 0.0,
            length: 1.5,
            outward: 1.5
        }
    );
    // The delta is applied at the end of every cut.
    let path = toolpath::build(&j).unwrap();
    let ends: Vec<Pos> = path
        .segments()
        .filter(|(from, m)| matches!(m.kind, MotionKind::Thread { .. }) && from.z == -30.0)
        .map(|(from, m)| Pos::new(m.to.x - from.x, m.to.z - from.z))
        .collect();
    assert!(!ends.is_empty());
    for d in ends {
        assert!((d.x - 1.5).abs() < EPS && (d.z + 1.5).abs() < EPS);
    }
    let twice = src.replace("DEPTH,1", "DEPTH,1,CHAMFR,1");
    let d = err(&twice);
    assert_eq!((d.code, at(&d)), (Code::Conflict, (4, 19)));
    let d = err(&wrap(",DEPTH,1,ATANGL,45,CHAMFR,1"));
    assert_eq!((d.code, at(&d)), (Code::Conflict, (5, 29)));
    // A steep third GOTO (more than 60° from the axis) is cut with a linear move.
    let steep = src.replace("GOTO/11.5,0,-31.5", "GOTO/12,0,-30.5");
    assert!(matches!(job(&steep).exit, Exit::FeedOut { .. }));
}

#[test]
fn return_heights() {
    let h = 2.0 / (2.0 * 30f64.to_radians().tan());
    assert!((job(&wrap(",DEPTH,1")).retract.x - (10.0 + h)).abs() < EPS);
    assert_eq!(job(&wrap(",DEPTH,1,RETURN,0.5")).retract.x, 10.5);
    let j = job(&wrap(",DEPTH,1,RETURN"));
    assert_eq!((j.retract.x, j.retract.z), (12.0, 5.0));
    // A pull-out that ends above the return height raises it: the retract never moves inward.
    // Single pass at depth 1, 45° chamfer rising 2: it ends at X 10 − 1 + 2 = 11.
    assert_eq!(job(&wrap(",DEPTH,1,CHAMFR,2,RETURN,0.5")).retract.x, 11.0);
    // After each pass: straight out to the return height, back above the start point.
    let path = toolpath::build(&job(&wrap(",DEPTH,1,RETURN,0.5"))).unwrap();
    let m = &path.motions;
    assert_eq!(
        (m[2].kind, m[2].to),
        (MotionKind::Rapid, Pos::new(10.5, -30.0))
    );
    assert_eq!(
        (m[3].kind, m[3].to),
        (MotionKind::Rapid, Pos::new(10.5, 5.0))
    );
}

// ---- pitch, starts, variable lead -------------------------------------------------------------

#[test]
fn pitch_units_and_modal_scope() {
    let inch = |p: &str| {
        job(&format!(
            "UNITS/INCHES\n{p}\nGOTO/0.5,0,0.2\nTHREAD/ON,DEPTH,0.04\nGOTO/0.4,0,0.2\nGOTO/0.4,0,-1\nTHREAD/OFF\n"
        ))
        .lead
        .lead
    };
    for p in [
        "PITCH/8,TPI",
        "PITCH/TPI,8",
        "PITCH/0.125,IPR",
        "PITCH/3.175,MMPR",
        "PITCH/0.125,PERREV",
        "PITCH/8",
    ] {
        assert!((inch(p) - 3.175).abs() < 1e-12, "{p}: {}", inch(p));
    }
    // THREAD/ON's pitch overrides PITCH for that thread only.
    let src = "UNITS/MM\nPITCH/2,MMPR\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1,MMPR,1.5\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\n";
    let jobs = apt::jobs(src.as_bytes()).unwrap();
    assert_eq!((jobs[0].lead.lead, jobs[1].lead.lead), (1.5, 2.0));
    let d =
        err("UNITS/MM\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\n");
    assert_eq!((d.code, at(&d)), (Code::MissingWord, (3, 1)));
}

#[test]
fn multi_start_cuts_each_pass_for_every_start() {
    let j = job(&wrap(",CUTS,2,0.5,MULTRD,2"));
    assert_eq!(j.lead.starts, 2);
    let path = toolpath::build(&j).unwrap();
    let starts: Vec<(u32, Pos)> = path
        .segments()
        .filter(|(_, m)| matches!(m.kind, MotionKind::Thread { .. }))
        .map(|(from, m)| (m.pass, from))
        .collect();
    // Pass 1 for start 1 then start 2 (one pitch = lead/2 further back), then pass 2.
    assert_eq!(
        starts,
        vec![
            (1, Pos::new(9.5, 5.0)),
            (1, Pos::new(9.5, 6.0)),
            (2, Pos::new(9.0, 5.0)),
            (2, Pos::new(9.0, 6.0)),
        ]
    );
    assert_eq!(err(&wrap(",DEPTH,1,MULTRD,0")).code, Code::OutOfRange);
    let d = err(&wrap(",DEPTH,1,MULTRD,2,INCR,0.1"));
    assert_eq!(d.code, Code::Conflict);
}

/// Walks the synchronised moves of one pass and returns the long-axis distance travelled after
/// `k` revolutions, using each move's own starting lead and the lead change per revolution.
fn distance_after(moves: &[(f64, f64, f64)], k: f64) -> f64 {
    // (length along Z, lead at start, dlead)
    let mut revs = k;
    let mut done = 0.0;
    for &(len, l, dl) in moves {
        // Revolutions to run `len`: l·r + dl·r²/2 = len.
        let r = if dl == 0.0 {
            len / l
        } else {
            (-l + (l * l + 2.0 * dl * len).sqrt()) / dl
        };
        if revs <= r {
            return done + l * revs + dl * revs * revs / 2.0;
        }
        revs -= r;
        done += len;
    }
    done
}

#[test]
fn variable_lead_axial_position_after_k_revolutions() {
    // Lead 2 mm growing 0.1 mm per revolution, a 45° chamfer after the thread.
    let j = job(&wrap(",DEPTH,1,INCR,0.1,CHAMFR,2"));
    assert_eq!((j.lead.lead, j.lead.dlead), (2.0, 0.1));
    let path = toolpath::build(&j).unwrap();
    let moves: Vec<(f64, f64, f64)> = path
        .segments()
        .filter_map(|(from, m)| match m.kind {
            MotionKind::Thread { lead, dlead, .. } if m.pass == 1 => {
                let d = m.to.minus(from);
                // The lead along Z: the chamfer is 45°, so its long axis is Z as well.
                assert!(d.z.abs() >= d.x.abs());
                Some((d.z.abs(), lead, dlead))
            }
            _ => None,
        })
        .collect();
    assert_eq!(moves.len(), 2);
    // The chamfer starts 35 mm on: the lead there is √(2² + 2·0.1·35) = √11.
    assert!((moves[1].1 - 11f64.sqrt()).abs() < 1e-12);
    for k in [1.0, 5.0, 12.0, 13.5] {
        let want = 2.0 * k + 0.1 * k * k / 2.0;
        let got = distance_after(&moves, k);
        assert!((got - want).abs() < 1e-9, "k={k}: {got} vs {want}");
    }
    // DECR that would bring the lead to zero inside the thread is refused.
    let d = err(&wrap(",DEPTH,1,DECR,0.1"));
    assert_eq!((d.code, at(&d)), (Code::Geometry, (5, 19)));
}

// ---- face threads ----------------------------------------------------------------------------

#[test]
fn face_thread_feeds_along_z_and_threads_along_x() {
    let src = "UNITS/MM\nPITCH/1.5,MMPR\nGOTO/22,0,3\nTHREAD/ON,CUTS,3,0.3,RETURN,1\nGOTO/20,0,0\nGOTO/5,0,0\nTHREAD/OFF\n";
    let j = job(src);
    assert_eq!(j.geometry.side, Side::FaceFront);
    let path = toolpath::build(&j).unwrap();
    let t: Vec<(Pos, Pos, f64)> = path
        .segments()
        .filter_map(|(from, m)| match m.kind {
            MotionKind::Thread { lead, .. } => Some((from, m.to, lead)),
            _ => None,
        })
        .collect();
    assert_eq!(t.len(), 3);
    for (i, (from, to, lead)) in t.iter().enumerate() {
        let d = 0.3 * (i + 1) as f64;
        assert!((from.z + d).abs() < EPS && (to.z + d).abs() < EPS);
        assert_eq!((from.x, to.x, *lead), (20.0, 5.0, 1.5));
    }
    // Retract along +Z to the return height, then back along X above the start point.
    let after = path
        .motions
        .iter()
        .position(|m| matches!(m.kind, MotionKind::Thread { .. }))
        .unwrap();
    assert_eq!(path.motions[after + 1].to, Pos::new(5.0, 1.0));
    assert_eq!(path.motions[after + 2].to, Pos::new(20.0, 1.0));
    // A face taper (X travel larger than Z travel) is a face thread too.
    let taper = src.replace("GOTO/5,0,0", "GOTO/5,0,-2");
    assert_eq!(job(&taper).geometry.side, Side::FaceFront);
}

// ---- statements ------------------------------------------------------------------------------

#[test]
fn single_pass_thread_is_couple() {
    let a = "UNITS/MM\nPITCH/2,MMPR\nGOTO/10,0,5\nTHREAD/TURN\nGOTO/10,0,-30\nFINI\n";
    let b = "UNITS/MM\nPITCH/2,MMPR\nGOTO/10,0,5\nCOUPLE/ON\nGOTO/10,0,-30\nCOUPLE/OFF\nFINI\n";
    let run = |src: &str| {
        let mut out = Vec::new();
        apt::expand_jsonl(src.as_bytes(), &mut out).unwrap();
        String::from_utf8(out)
            .unwrap()
            .replace("\"line\":6", "\"line\":5")
    };
    let (x, y) = (run(a), run(b));
    assert_eq!(x, y);
    assert!(
        x.contains(r#"{"kind":"thread","x":10.0,"z":-30.0,"lead":2.0,"pass":0,"line":5}"#),
        "{x}"
    );
}

#[test]
fn unsupported_statements_are_named_with_their_line() {
    let d = err("UNITS/MM\nGOTO/12,0,5\nCUTTER/0.8\n");
    assert_eq!((d.code, at(&d)), (Code::Unsupported, (3, 1)));
    assert!(d.message.contains("CUTTER"));
    let d = err(&wrap(",DEPTH,1").replace("GOTO/10,0,5\n", "GOTO/10,0,5\nFEDRAT/1\n"));
    assert_eq!((d.code, at(&d)), (Code::Unsupported, (7, 1)));
    let d = err("UNITS/MM\nPITCH/2,MMPR\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\n");
    assert_eq!((d.code, at(&d)), (Code::Syntax, (4, 1)));
    let d = err("UNITS/MM\nFINI\nGOTO/1,0,1\n");
    assert_eq!(at(&d), (3, 1));
    let d =
        err("UNITS/MM\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\n");
    assert_eq!(d.code, Code::MissingWord);
}

// ---- posting ----------------------------------------------------------------------------------

fn post(src: &str, target: &str) -> String {
    let m = Machine::built_in(target).unwrap();
    let mut out = Vec::new();
    apt::post::write(src.as_bytes(), &mut out, &m).unwrap_or_else(|e| panic!("{e}"));
    String::from_utf8(out).unwrap()
}

/// Every built-in controller: a thread it can express natively comes out as its native cycle, and
/// reading that text back reproduces the APT job's toolpath.
#[test]
fn native_output_reads_back_to_the_same_toolpath() {
    let src = "UNITS/MM\nPITCH/2.5,MMPR,MULTRD,2\nRAPID\nGOTO/12,0,5\nTHREAD/ON,DEPTH,1.534,CUTS,6,OPTION,1,FINCUT,1,0.05,RETURN\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\nFINI\n";
    let apt_job = job(src);
    for (name, _) in threadcut::machine::BUILT_IN {
        let m = Machine::built_in(name).unwrap();
        let mut out = Vec::new();
        if let Err(e) = apt::post::write(src.as_bytes(), &mut out, &m) {
            // The inch-only OmniTurn writes a 2.5 mm lead as K0.09845", within the thread's
            // class (a quarter of 6g's Td2 on the pitch diameter), but its G33 cuts one start
            // from the spindle's index: this two-start thread is refused for that.
            assert_eq!(*name, "omniturn", "{e}");
            assert!(e.to_string().contains("G33 cuts one start"), "{e}");
            continue;
        }
        let text = String::from_utf8(out).unwrap();
        let d = threadcut::dialect::open(&m).unwrap();
        let mut in_units = apt_job.clone();
        in_units.units = m.units;
        let path = toolpath::build(&in_units).unwrap();
        let Ok(native) = translate::native(&m, d.as_ref(), &in_units, &path) else {
            continue;
        };
        for l in &native {
            assert!(text.contains(l.as_str()), "{name}: {text}");
        }
        let mut job = apt_job.clone();
        job.units = m.units;
        let back = program::jobs(text.as_bytes(), &m).unwrap();
        assert_eq!(back.len(), 1, "{text}");
        let want = toolpath::build(&job).unwrap();
        let got = toolpath::build(&back[0]).unwrap();
        translate::same_motion(&want, &got, (0.0005 + 1e-9, 0.00005 + 1e-9))
            .unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
    }
    // gsk980 writes G78 for it.
    assert!(post(src, "gsk980").contains("G78 P010160"));
}

#[test]
fn jobs_the_target_cannot_express_are_plain_moves_with_the_reason() {
    // OPTION 0's decrementing steps are not a G78 depth law.
    let text = post(&wrap(",DEPTH,1.2,CUTS,4"), "gsk980");
    assert!(
        text.contains("(threadcut: plain moves, not the native cycle: "),
        "{text}"
    );
    assert!(text.contains("G32 X19.04 Z-30. F2."), "{text}");
    // A steep chamfer is cut with G1, a 45° one with G32.
    let text = post(&wrap(",DEPTH,1,CHAMFR,1,70"), "gsk980");
    assert!(text.contains("G1 X"), "{text}");
    let text = post(&wrap(",DEPTH,1,CHAMFR,1"), "gsk980");
    assert!(
        !text.contains("G1 X") && text.contains("G32 X20. Z-31."),
        "{text}"
    );
    // Face threads: plain moves, G32 along X.
    let face = "UNITS/MM\nPITCH/1.5,MMPR\nRAPID\nGOTO/22,0,3\nTHREAD/ON,DEPTH,0.9,CUTS,3,OPTION,3,FINCUT,1\nGOTO/20,0,0\nGOTO/5,0,0\nTHREAD/OFF\n";
    let text = post(face, "gsk980");
    assert!(text.contains("cannot cut a face thread"), "{text}");
    // OPTION 3 shifts each pass back toward the start along X: tan 30° · depth.
    assert!(text.contains("G32 X10.346 Z-0.3 F1.5"), "{text}");
}

#[test]
fn variable_lead_is_refused_by_a_target_without_a_variable_lead_move() {
    let m = Machine::built_in("gsk980").unwrap();
    let mut out = Vec::new();
    let e = apt::post::write(wrap(",DEPTH,1,INCR,0.01").as_bytes(), &mut out, &m).unwrap_err();
    match e {
        Error::Input(d) => assert_eq!((d.code, d.span.line), (Code::Unsupported, 5)),
        e => panic!("{e}"),
    }
}

#[test]
fn plain_motion_feeds_spindle_and_inch_cl_on_a_mm_machine() {
    let src = "PARTNO SHAFT 12\nUNITS/INCHES\nSPINDL/800,RPM,CCLW\nFEDRAT/0.004,IPR\nRAPID\nGOTO/1,0,0.1\nGOTO/0.5,0,0.1\nGOTO/0.5,0,-1\nSPINDL/OFF\nFINI\n";
    let text = post(src, "gsk980");
    assert_eq!(
        text,
        "(threadcut post for gsk980, mm, feed per revolution)\nG21 G18 G99 G97\n(SHAFT 12)\nS800 M4\n(FEDRAT: F0.1016 mm per revolution)\nG0 X50.8 Z2.54\nG1 X25.4 Z2.54 F0.1016\nG1 X25.4 Z-25.4\nM5\nM30\n"
    );
    let m = Machine::built_in("gsk980").unwrap();
    let e = apt::post::write("UNITS/MM\nGOTO/1,0,1\n".as_bytes(), &mut Vec::new(), &m).unwrap_err();
    assert!(matches!(e, Error::Input(d) if d.code == Code::MissingWord && d.span.line == 2));
}

// ---- the command line --------------------------------------------------------------------------

fn threadcut(args: &[&str]) -> std::process::Output {
    std::process::Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn cli_post_passes_and_expand() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("m20.apt");
    std::fs::write(&file, wrap(",DEPTH,1.2,CUTS,4,OPTION,3,FINCUT,1,RETURN")).unwrap();
    let f = file.to_str().unwrap();
    let out = threadcut(&["post", f, "--controller", "gsk980"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(String::from_utf8_lossy(&out.stdout).contains("G78 P010160 Q0. R0. D0"));
    let out = threadcut(&["passes", f, "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let passes = v["cycles"][0]["passes"].as_array().unwrap();
    assert_eq!(passes.len(), 5);
    assert_eq!(passes[0]["depth"], 0.3);
    assert_eq!(passes[0]["x"], 9.7);
    let out = threadcut(&["expand", f, "--format", "jsonl"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.lines()
            .any(|l| l.starts_with(r#"{"kind":"thread","x":9.7,"#)
                && l.ends_with(r#""lead":2.0,"pass":1,"line":8}"#)),
        "{text}"
    );
    // Content detection when the name says nothing.
    let other = dir.path().join("thread.txt");
    std::fs::copy(&file, &other).unwrap();
    assert!(threadcut(&["passes", other.to_str().unwrap()])
        .status
        .success());
    // Bad input: exit 2 and file:line:column.
    std::fs::write(&file, wrap(",DEPTH,1,CUTANG,95")).unwrap();
    let out = threadcut(&["post", f, "-c", "gsk980"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("m20.apt:5:19"), "{err}");
}

#[test]
fn rapid_before_thread_on_belongs_to_the_cycle() {
    let src = "UNITS/MM\nPITCH/2,MMPR\nFEDRAT/100\nGOTO/12,0,5\nRAPID\nTHREAD/ON,DEPTH,1\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\nGOTO/14,0,5\n";
    let mut out = Vec::new();
    apt::expand_jsonl(src.as_bytes(), &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let last = text.lines().last().unwrap();
    assert!(last.starts_with(r#"{"kind":"feed","x":14.0"#), "{text}");
}

#[test]
fn y_and_missing_units_are_warned_about() {
    let src = "GOTO/12,3,5\n";
    let s = apt::run(src.as_bytes(), |_, _| Ok(())).unwrap();
    let places: Vec<(Code, u32, u32)> = s
        .warnings
        .iter()
        .map(|w| (w.code, w.span.line, w.span.column))
        .collect();
    assert_eq!(
        places,
        vec![(Code::Suspicious, 1, 1), (Code::Suspicious, 1, 9)]
    );
}

#[test]
fn the_examples_read() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples");
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "apt") {
            let text = std::fs::read_to_string(&path).unwrap();
            let jobs =
                apt::jobs(text.as_bytes()).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            for j in &jobs {
                toolpath::build(j).unwrap();
            }
            n += jobs.len();
        }
    }
    assert!(n >= 4);
}

#[test]
fn expand_jsonl_carries_the_lead_change() {
    let mut out = Vec::new();
    apt::expand_jsonl(wrap(",DEPTH,1,INCR,0.1").as_bytes(), &mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(
        text.contains(
            r#"{"kind":"thread","x":9.0,"z":-30.0,"lead":2.0,"dlead":0.1,"pass":1,"line":8}"#
        ),
        "{text}"
    );
}

mod never_panics {
    use proptest::prelude::*;

    fn token() -> impl Strategy<Value = String> {
        prop_oneof![
            Just("GOTO/".to_string()),
            Just("THREAD/ON".to_string()),
            Just("THREAD/OFF".to_string()),
            Just("THREAD/TURN".to_string()),
            Just("PITCH/".to_string()),
            Just("UNITS/INCHES".to_string()),
            Just("COUPLE/ON".to_string()),
            Just("RAPID".to_string()),
            Just(",".to_string()),
            Just("\n".to_string()),
            Just(" $\n".to_string()),
            Just("$$ c\n".to_string()),
            prop_oneof![
                Just("DEPTH"),
                Just("CUTS"),
                Just("STEP"),
                Just("FINCUT"),
                Just("CUTANG"),
                Just("TLANGL"),
                Just("OPTION"),
                Just("ATANGL"),
                Just("CHAMFR"),
                Just("RETURN"),
                Just("TPI"),
                Just("MMPR"),
                Just("MULTRD"),
                Just("INCR"),
                Just("DECR")
            ]
            .prop_map(str::to_string),
            (-50.0f64..50.0).prop_map(|v| format!("{v:.3}")),
            (0u32..300).prop_map(|v| v.to_string()),
        ]
    }

    proptest! {
        #[test]
        fn apt_input_never_panics(tokens in proptest::collection::vec(token(), 0..60)) {
            let src = tokens.concat();
            if let Ok(jobs) = threadcut::apt::jobs(src.as_bytes()) {
                for j in &jobs {
                    let _ = threadcut::toolpath::build(j);
                }
            }
            let m = threadcut::machine::Machine::built_in("gsk980").unwrap();
            let _ = threadcut::apt::post::write(src.as_bytes(), &mut Vec::new(), &m);
        }
    }
}

mod properties {
    use proptest::prelude::*;
    use threadcut::thread::PassKind;

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]
        #[test]
        fn passes_deepen_and_end_at_the_depth(
            option in 0u8..5,
            depth in 0.2f64..3.0,
            cuts in 1u32..40,
            by_step in any::<bool>(),
            fin in 0u32..3,
            dist in 0.0f64..0.1,
            oblique in -25.0f64..25.0,
            chamfer in prop_oneof![Just(String::new()), Just(",CHAMFR,1.5".to_string()), Just(",ATANGL,40".to_string()), Just(",CHAMFR,-1,70".to_string())],
        ) {
            let cutang = if option == 0 { 180.0 + oblique } else { 180.0 };
            let spec = if by_step {
                format!("DEPTH,{depth:.4},STEP,{:.4}", depth / f64::from(cuts) * 1.5)
            } else {
                format!("DEPTH,{depth:.4},CUTS,{cuts}")
            };
            let src = format!(
                "UNITS/MM\nPITCH/2,MMPR\nRAPID\nGOTO/14,0,5\nTHREAD/ON,{spec},OPTION,{option},FINCUT,{fin},{dist:.4},CUTANG,{cutang:.3}{chamfer}\nGOTO/10,0,5\nGOTO/10,0,-30\nTHREAD/OFF\n"
            );
            let jobs = threadcut::apt::jobs(src.as_bytes());
            let jobs = match jobs {
                Ok(jobs) => jobs,
                // A first step small enough to need more than 200 cuts.
                Err(threadcut::program::Error::Input(d)) if d.code == threadcut::diag::Code::TooManyPasses => return Ok(()),
                Err(e) => panic!("{e}\n{src}"),
            };
            let j = &jobs[0];
            let p = j.passes().unwrap();
            let mut last = -1.0;
            for pass in &p {
                prop_assert!(pass.depth >= last - 1e-12, "{src}");
                last = pass.depth;
            }
            prop_assert!((last - j.geometry.depth).abs() < 1e-9, "{src}");
            let rough = p.iter().filter(|q| q.kind == PassKind::Rough).count();
            prop_assert!(rough as u32 + fin <= 200);
            let path = threadcut::toolpath::build(j).unwrap();
            prop_assert!(path.motions.iter().all(|m| m.to.is_finite()));
            let m = threadcut::machine::Machine::built_in("gsk980").unwrap();
            threadcut::apt::post::write(src.as_bytes(), &mut Vec::new(), &m).unwrap();
        }
    }
}

#[test]
fn decr_shrinks_the_lead_along_the_pass() {
    let j = job(&wrap(",DEPTH,1,DECR,0.02,CHAMFR,2"));
    assert_eq!(j.lead.dlead, -0.02);
    let path = toolpath::build(&j).unwrap();
    let leads: Vec<f64> = path
        .motions
        .iter()
        .filter_map(|m| match m.kind {
            MotionKind::Thread { lead, .. } if m.pass == 1 => Some(lead),
            _ => None,
        })
        .collect();
    // √(2² − 2·0.02·35) = √2.6 where the chamfer begins.
    assert_eq!(leads.len(), 2);
    assert_eq!(leads[0], 2.0);
    assert!((leads[1] - 2.6f64.sqrt()).abs() < 1e-12);
}

#[test]
fn internal_thread_retracts_toward_the_axis() {
    let src = "UNITS/MM\nPITCH/1.5,MMPR\nGOTO/8,0,3\nTHREAD/ON,DEPTH,0.8,CUTS,4,OPTION,1,RETURN,0.5\nGOTO/9,0,3\nGOTO/9,0,-20\nTHREAD/OFF\n";
    let j = job(src);
    assert_eq!(j.geometry.side, Side::Internal);
    assert_eq!(j.retract.x, 8.5);
    let p = j.passes().unwrap();
    assert!((p[3].start.x - 9.8).abs() < EPS);
    // Single edge: shifted back toward the start (+Z) by tan 30° · depth.
    assert!((p[3].offset - 0.8 * 30f64.to_radians().tan()).abs() < EPS);
}
