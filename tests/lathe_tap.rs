//! A tap on a lathe's centre line (issue 24, item 3): synchronised moves (G32, G33) on X0 are a
//! tap held in the turret, judged as a tap — its lead against the named tap's pitch — and not as
//! an external thread of diameter 0.

use threadcut::check::{check, Options, Report, Source};
use threadcut::diag::Code;
use threadcut::machine::Machine;
use threadcut::thread::standard;

const FANUC: &str = "O0010 (M10X1.5 TAP ON THE CENTRE LINE)
G21 G18 G99 G97
T0505
S300 M3
G0 X0. Z5.
G32 Z-20. F1.5
M4
G32 Z5. F1.5
M5
G0 X50. Z50.
M30
";

fn run(src: &str, controller: &str, thread: Option<&str>) -> Report {
    let m = Machine::built_in(controller).unwrap();
    let opts = Options {
        thread: thread.map(|t| standard::lookup(t).unwrap()),
        ..Options::default()
    };
    check(src.as_bytes(), Source::Gcode(&m), &opts).unwrap()
}

fn codes(r: &Report) -> Vec<(Code, u32)> {
    r.diagnostics
        .iter()
        .map(|d| (d.code, d.span.line))
        .collect()
}

#[test]
fn a_tap_fed_at_its_pitch_is_right() {
    let r = run(FANUC, "fanuc", Some("M10x1.5-6H"));
    assert_eq!(codes(&r), [], "{:?}", r.diagnostics);
    let notes: Vec<&str> = r.notes.iter().map(|n| n.message.as_str()).collect();
    assert!(
        notes.iter().any(|n| n.starts_with("the tap on the centre line: right-hand tap, lead 1.5 per turn")),
        "{notes:?}"
    );
}

#[test]
fn a_tap_fed_off_its_pitch_is_an_error_at_its_line() {
    // F1.45: over Z5 to Z-20 the feed falls 25 / 1.45 × 0.05 = 0.8621 behind the tap.
    let r = run(&FANUC.replace("F1.5", "F1.45"), "fanuc", Some("M10x1.5-6H"));
    assert_eq!(codes(&r), [(Code::Tapping, 6)], "{:?}", r.diagnostics);
    assert!(r.diagnostics[0]
        .message
        .contains("the feed falls 0.8621 behind the tap"));
    // Without the tap named, F1.48 is 1.3 % off 1.5: most likely a wrong F, a warning.
    let r = run(&FANUC.replace("F1.5", "F1.48"), "fanuc", None);
    assert_eq!(
        codes(&r),
        [(Code::TappingAssumed, 6)],
        "{:?}",
        r.diagnostics
    );
}

#[test]
fn linuxcncs_g33_on_the_centre_line_is_a_tap_too() {
    let ngc = "G21 G18 G7 G90\nS300 M3\nG0 X0 Z5\nG33 Z-20 K1.5\nM4\nG33 Z5 K1.5\nM5\nM2\n";
    let r = run(ngc, "linuxcnc", Some("M10x1.5-6H"));
    assert_eq!(codes(&r), [], "{:?}", r.diagnostics);
    assert!(r
        .notes
        .iter()
        .any(|n| n.message.contains("the tap on the centre line")));
}
