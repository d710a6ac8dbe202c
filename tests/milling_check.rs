//! `check` of machining-centre programs (issue 24): milled threads and taps, each fault written
//! after the ways thread milling and tapping go wrong — a wrong Z on one turn, the wrong hand,
//! compensation on the wrong side, the wrong cutter, a straight entry onto the finished thread,
//! the spindle stopped, a tapping feed that is not pitch × rpm, a tap turned the wrong way —
//! found at its line, and the correct twin of each without an error.

use threadcut::check::milling::{check, Options, ToolSize};
use threadcut::check::Report;
use threadcut::diag::Code;
use threadcut::mill::profile::MillProfile;
use threadcut::mill::{Hand, Side};
use threadcut::thread::standard::lookup;

const NUT: &str = include_str!("data/mill/fanuc-m20-internal-g41.nc");
const TAP: &str = include_str!("data/mill/fanuc-m10-rigid-tap.nc");
const BOLT: &str = include_str!("data/mill/linuxcnc-m12-helix.ngc");

fn run(text: &str, profile: &str, o: &Options) -> Report {
    check(text.as_bytes(), &MillProfile::built_in(profile).unwrap(), o)
}

fn named(thread: &str) -> Options {
    let hand = if threadcut::thread::standard::split_hand(thread).1 {
        Hand::Left
    } else {
        Hand::Right
    };
    Options {
        thread: Some((lookup(thread).unwrap(), hand)),
        ..Options::default()
    }
}

/// The findings as (code, line).
fn found(r: &Report) -> Vec<(Code, u32)> {
    r.diagnostics
        .iter()
        .map(|d| (d.code, d.span.line))
        .collect()
}

fn notes(r: &Report) -> String {
    r.notes
        .iter()
        .map(|n| n.message.as_str())
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn a_nut_milled_under_g41_is_right() {
    let r = run(NUT, "fanuc-mill", &named("M20x2.5-6H"));
    assert_eq!(found(&r), [], "{:?}", r.diagnostics);
    assert_eq!(r.threads, 1);
    let n = notes(&r);
    // 8 turns of 2.5 from Z-20 to Z0, the contour Ø20 (6H's minimum major diameter); with the
    // root flat P/8 the pitch diameter is 20 − 2·(1.25 − 0.3125)/(2·tan 30°) = 18.3762.
    assert!(
        n.contains("lead 2.5, 1 start, right-hand, bottom-up, 1 radial pass from Z0 to Z-20; internal (from where the tool came in); major diameter cut 20; climb milling"),
        "{n}"
    );
    assert!(
        n.contains("6H allows a pitch diameter of 18.376–18.6 mm"),
        "{n}"
    );
}

#[test]
fn a_turn_written_with_the_wrong_z() {
    // Line 13 ends at Z-9.9: that turn rises 2.6, the next 2.4.
    let text = NUT.replacen("Z-10. I-10.", "Z-9.9 I-10.", 1);
    let r = run(&text, "fanuc-mill", &Options::default());
    assert_eq!(found(&r), [(Code::Helix, 13)], "{:?}", r.diagnostics);
    assert!(r.diagnostics[0]
        .message
        .contains("advances 2.6 over 1 turn"));
}

#[test]
fn the_wrong_hand_for_the_thread_named() {
    // G2 rising is a left-hand helix.
    let text = NUT
        .replace("G3 X10. Y0. Z", "G2 X10. Y0. Z")
        .replace("G41 D4", "G42 D4");
    let r = run(&text, "fanuc-mill", &named("M20x2.5-6H"));
    assert!(
        found(&r).contains(&(Code::OutOfClass, 10)),
        "{:?}",
        r.diagnostics
    );
    let msg = &r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::OutOfClass)
        .unwrap()
        .message;
    assert!(
        msg.contains("the helix is left-hand (G2 rising), and M20x2.5-6H is right-hand"),
        "{msg}"
    );
    // Named left-hand, the same program is right.
    let r = run(&text, "fanuc-mill", &named("M20x2.5-6H-LH"));
    assert!(
        !found(&r).iter().any(|f| f.0 == Code::OutOfClass),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn compensation_on_the_wrong_side_of_a_bore() {
    // G42 with G3 puts the cutter outside the circle; the tool came in from the axis.
    let text = NUT.replace("G41 D4", "G42 D4");
    let r = run(&text, "fanuc-mill", &Options::default());
    assert!(
        found(&r).contains(&(Code::Helix, 10)),
        "{:?}",
        r.diagnostics
    );
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::Helix)
        .unwrap();
    assert!(
        d.message
            .contains("G42 with G3 keeps the cutter outside the programmed circle"),
        "{}",
        d.message
    );
}

#[test]
fn the_wrong_cutter_for_a_tool_centre_path() {
    // The bolt's path is the centre of a 10 mm cutter at R9.9: minor Ø9.8. Loaded with an 8 mm
    // cutter it cuts Ø11.8, far above d3 max of M12x1.75-6g.
    let mut o = named("M12x1.75-6g");
    o.tool_diameter = Some(10.0);
    let r = run(BOLT, "linuxcnc-mill", &o);
    assert_eq!(
        found(&r),
        [(Code::HelixAssumed, 7)],
        "only the straight entry: {:?}",
        r.diagnostics
    );
    o.tool_diameter = None;
    o.tools = vec![ToolSize::Tool(2, 8.0)];
    let r = run(BOLT, "linuxcnc-mill", &o);
    assert!(
        found(&r).contains(&(Code::OutOfClass, 8)),
        "{:?}",
        r.diagnostics
    );
    let d = r
        .diagnostics
        .iter()
        .find(|d| d.code == Code::OutOfClass)
        .unwrap();
    assert!(
        d.message
            .contains("the minor diameter the cutter reaches is 11.8"),
        "{}",
        d.message
    );
    // Without the cutter's size nothing is claimed of the diameters.
    let r = run(BOLT, "linuxcnc-mill", &named("M12x1.75-6g"));
    assert!(notes(&r).contains("the cutter's diameter is not known (--tool-diameter)"));
}

#[test]
fn a_straight_entry_onto_the_finished_thread_and_its_arc_twin() {
    let o = Options {
        tool_diameter: Some(10.0),
        ..Options::default()
    };
    let r = run(BOLT, "linuxcnc-mill", &o);
    assert_eq!(found(&r), [(Code::HelixAssumed, 7)]);
    // Entered on a quarter arc tangent to the helix (about X9.9 Y5, radius 5, from X14.9 Y5): no
    // mark, and the arc stays outside the thread's radius (an external thread).
    let text = BOLT.replace(
        "G0 Z0\nG1 X9.9 Y0 F300",
        "G0 Z0\nG1 X14.9 Y5 F300\nG2 X9.9 Y0 I-5 J0",
    );
    let r = run(&text, "linuxcnc-mill", &o);
    assert_eq!(found(&r), [], "{:?}", r.diagnostics);
}

#[test]
fn a_helix_with_the_spindle_stopped() {
    let text = NUT.replace("G43 H4 Z5.", "G43 H4 Z5.\nM5");
    let r = run(&text, "fanuc-mill", &Options::default());
    assert_eq!(found(&r)[0], (Code::MachineState, 8), "{:?}", r.diagnostics);
}

#[test]
fn a_rigid_tap_fed_at_pitch_times_speed_and_its_faults() {
    let r = run(TAP, "fanuc-mill", &named("M10x1.5-6H"));
    assert_eq!(found(&r), [], "{:?}", r.diagnostics);
    assert_eq!(r.threads, 2, "two holes");
    // Both holes rigid: M29 lasts while the tapping cycle is modal.
    assert!(notes(&r).matches("rigid").count() == 2, "{}", notes(&r));
    // F1190 at S800: 1.4875 per turn, behind the tap by 18 + 2 = 20 / 1.4875 × 0.0125 = 0.168.
    let text = TAP.replace("F1200.", "F1190.");
    let r = run(&text, "fanuc-mill", &named("M10x1.5-6H"));
    assert_eq!(found(&r)[0], (Code::Tapping, 8), "{:?}", r.diagnostics);
    // Without the tap named, a lead 0.8 % off 1.5 is a warning.
    let r = run(&text, "fanuc-mill", &Options::default());
    assert_eq!(
        found(&r)[0],
        (Code::TappingAssumed, 8),
        "{:?}",
        r.diagnostics
    );
    // M4 before a G84: the tap screws in backwards.
    let text = TAP.replace("S800 M3", "S800 M4");
    let r = run(&text, "fanuc-mill", &named("M10x1.5-6H"));
    assert_eq!(found(&r)[0], (Code::Tapping, 8), "{:?}", r.diagnostics);
    assert!(r.diagnostics[0].message.contains(
        "G84 is a right-hand tapping cycle and the spindle turns counter-clockwise (M4)"
    ));
    // A left-hand tap named for a G84.
    let r = run(TAP, "fanuc-mill", &named("M10x1.5-6H-LH"));
    assert!(
        found(&r).contains(&(Code::Tapping, 8)),
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn the_side_given_overrides_nothing_it_contradicts() {
    // Told external, the nut's G41 with G3 (a bore's compensation) is named as on the wrong side.
    let o = Options {
        side: Some(Side::External),
        ..Options::default()
    };
    let r = run(NUT, "fanuc-mill", &o);
    assert!(
        found(&r).contains(&(Code::Helix, 10)),
        "{:?}",
        r.diagnostics
    );
}
