//! The centre of every plain G2/G3 move (`PlainMove::centre`), from I/K and from R, on Fanuc (X a
//! diameter, I/K incremental) and LinuxCNC (X a radius here, G90.1 absolute I/K), in millimetres
//! and in inches. Expected centres are worked by hand in the comments (X a radius, mm).

use threadcut::gcode::MotionMode;
use threadcut::machine::Machine;
use threadcut::program::{self, Event};
use threadcut::units::Pos;

/// The centres of the program's arcs, in order.
fn centres(machine: &str, src: &str) -> Vec<Option<Pos>> {
    let machine = Machine::built_in(machine).unwrap();
    let mut out = Vec::new();
    program::run(src.as_bytes(), &machine, |_, e| {
        if let Event::Plain { mv: Some(mv), .. } = e {
            if matches!(mv.mode, MotionMode::ArcCw | MotionMode::ArcCcw) {
                out.push(mv.centre);
            } else {
                assert_eq!(mv.centre, None, "a straight move has no centre");
            }
        }
        Ok(())
    })
    .unwrap();
    out
}

fn near(got: Option<Pos>, x: f64, z: f64) {
    let got = got.expect("a centre");
    assert!(
        (got.x - x).abs() < 1e-9 && (got.z - z).abs() < 1e-9,
        "centre {got:?}, expected X{x} Z{z}"
    );
}

#[test]
fn fanuc_radius_and_ik_in_mm() {
    // From X20 Z0 (radius 10, Z0) to X30 Z-5 (radius 15, Z-5), a quarter circle of radius 5:
    // the two centres on the chord's bisector are (X15, Z0) and (X10, Z-5). Seen with Z right and
    // X up, G2 from (Z0, X10) about (Z0, X15) starts at −90° and ends at 180°, turning clockwise
    // through 90°: the shorter clockwise arc is about (X15, Z0); G3's about (X10, Z-5); R-5 takes
    // the other side (the 270° arc).
    // (Fanuc reads a number without a decimal point in least increments: every word has one.)
    let src = "G0 X20. Z0.\nG2 X30. Z-5. R5.\nG0 X20. Z0.\nG3 X30. Z-5. R5.\n\
               G0 X20. Z0.\nG2 X30. Z-5. R-5.\nG0 X20. Z0.\nG2 X30. Z-5. I5. K0.\n\
               G0 X20. Z0.\nG3 X30. Z-5. I0. K-5.\n";
    let c = centres("fanuc", src);
    assert_eq!(c.len(), 5);
    near(c[0], 15.0, 0.0);
    near(c[1], 10.0, -5.0);
    near(c[2], 10.0, -5.0);
    // I5 is a radius (not halved like X): 10 + 5 = 15; K0: Z0.
    near(c[3], 15.0, 0.0);
    // I0 K-5: (10, 0 − 5).
    near(c[4], 10.0, -5.0);
}

#[test]
fn fanuc_radius_and_ik_in_inches() {
    // G20: X1. is a diameter of 1 in, radius 12.7 mm; X1.5 radius 19.05; Z-.25 is -6.35 mm. R.25
    // = 6.35 mm: the same quarter circle, centre (19.05, 0) for G2; I.25 is 6.35 mm from 12.7.
    let src = "G20\nG0 X1. Z0.\nG2 X1.5 Z-.25 R.25\nG0 X1. Z0.\nG2 X1.5 Z-.25 I.25 K0.\n";
    let c = centres("fanuc", src);
    near(c[0], 19.05, 0.0);
    near(c[1], 19.05, 0.0);
}

#[test]
fn fanuc_r_takes_precedence_and_a_half_circle_centres_on_the_chord() {
    // From X20 Z0 to X20 Z-10 with R5: the chord (10 mm) is a diameter, the centre its midpoint
    // (10, -5), whatever I says.
    let c = centres("fanuc", "G0 X20. Z0.\nG2 X20. Z-10. R5. I7.\n");
    near(c[0], 10.0, -5.0);
    // R4 cannot reach: half the chord is 5 > 4: no centre (the move keeps its end point).
    let c = centres("fanuc", "G0 X20. Z0.\nG2 X20. Z-10. R4.\n");
    assert_eq!(c, vec![None]);
}

#[test]
fn linuxcnc_incremental_and_absolute_ik() {
    // The profile writes X as a radius. From X10 Z0 to X15 Z-5: G2 I5 K0 → (15, 0); under G90.1
    // I15 K0 is the centre itself; G91.1 returns to incremental: I0 K-5 → (10, -5) for G3.
    let src = "G18 G21\nG0 X10 Z0\nG2 X15 Z-5 I5 K0\nG0 X10 Z0\nG90.1\nG2 X15 Z-5 I15 K0\n\
               G91.1\nG0 X10 Z0\nG3 X15 Z-5 I0 K-5\nG0 X10 Z0\nG3 X15 Z-5 R5\n";
    let c = centres("linuxcnc", src);
    assert_eq!(c.len(), 4);
    near(c[0], 15.0, 0.0);
    near(c[1], 15.0, 0.0);
    near(c[2], 10.0, -5.0);
    near(c[3], 10.0, -5.0);
}

#[test]
fn linuxcnc_in_inches() {
    // G20: X.5 is 12.7 mm, X.75 19.05 mm, Z-.25 -6.35 mm; I.25 is 6.35 mm: centre (19.05, 0);
    // R-.25 the longer arc, on the other side: (12.7, -6.35).
    let src = "G20 G18\nG0 X.5 Z0\nG2 X.75 Z-.25 I.25 K0\nG0 X.5 Z0\nG2 X.75 Z-.25 R-.25\n";
    let c = centres("linuxcnc", src);
    near(c[0], 19.05, 0.0);
    near(c[1], 12.7, -6.35);
}
