//! `check` takes the blank at a thread from the part the program turned (issue 23): with the
//! bar's diameter given, a program that turns the bar down (G71/G70, plain G1 moves) and then
//! threads is judged on the turned diameter, not on the bar's — and the same program without the
//! turning, threading the bar as it is, still gets the rapids through the blank it makes.

use threadcut::check::{check, Options, Report, Source};
use threadcut::diag::Code;
use threadcut::machine::Machine;

fn run(src: &str, controller: &str, stock: f64) -> Report {
    let m = Machine::built_in(controller).unwrap();
    let opts = Options {
        stock_diameter: Some(stock),
        stock_start: Some(0.0),
        ..Options::default()
    };
    check(src.as_bytes(), Source::Gcode(&m), &opts).unwrap()
}

fn errors(r: &Report) -> Vec<(Code, u32)> {
    r.diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| (d.code, d.span.line))
        .collect()
}

/// An M20x2.5 thread on a Ø25 bar: the G76's retract rapids at X24 run above the Ø19.8 the program
/// turned (radius 12 > 9.9), and through the bar it would cut if it had not been turned.
const THREAD: &str = "\
T0303
G97 S800 M03
G00 X24. Z5.
G76 P020060 Q100 R0.05
G76 X16.85 Z-27. P1575 Q400 F2.5
G00 X100. Z100.
M30
";

const G71_G70: &str = "\
G21 G99
T0101
G96 S180 M03
G00 X27. Z2.
G71 U1.5 R0.5
G71 P10 Q20 U0.4 W0.1 F0.25
N10 G00 X16.
G01 Z0. F0.12
X19.8 Z-1.9
Z-30.
X22.
X24. Z-31.
Z-45.
N20 X27.
G70 P10 Q20
G00 X100. Z100.
";

#[test]
fn a_bar_turned_down_by_g71_and_g70_is_the_blank_at_the_thread() {
    let r = run(&format!("{G71_G70}{THREAD}"), "fanuc", 25.0);
    assert_eq!(errors(&r), vec![], "{:?}", r.diagnostics);
    assert_eq!(r.threads, 1);
    // The note says which surface the blank is, and that the program made it.
    assert!(
        r.notes.iter().any(|n| n.message.contains(
            "the surface along the thread is Ø19.8 as the program turned it at line 15 (the bar Ø25 given)"
        )),
        "{:?}",
        r.notes
    );
}

#[test]
fn the_same_thread_on_the_bar_as_it_is_runs_its_rapids_through_the_blank() {
    // No turning: the retract rapids at X24 run through the Ø25 bar the thread is cut in.
    let r = run(&format!("G21 G99\n{THREAD}"), "fanuc", 25.0);
    let e = errors(&r);
    assert!(e.contains(&(Code::Collision, 6)), "{:?}", r.diagnostics);
}

#[test]
fn a_bar_turned_with_plain_moves_is_the_blank_too() {
    // G1 moves turn Ø25 to Ø19.8 over Z2..-30 (the face at Z0): the thread's blank is Ø19.8.
    let turned =
        "G21 G99\nT0101\nG97 S1000 M03\nG00 X26. Z2.\nG01 X19.8 F0.2\nZ-30.\nX26.\nG00 Z5.\n";
    let r = run(&format!("{turned}{THREAD}"), "fanuc", 25.0);
    assert_eq!(errors(&r), vec![], "{:?}", r.diagnostics);
    // Turned only to Ø23.9 (radius 11.95 < 12): the retract at X24 is above it — no error; to
    // Ø24.2 (radius 12.1 > 12) the retract rapids run through what is left: E011.
    let to = |d: f64| {
        format!("G21 G99\nT0101\nG97 S1000 M03\nG00 X26. Z2.\nG01 X{d} F0.2\nZ-30.\nX26.\nG00 Z5.\n{THREAD}")
    };
    assert_eq!(errors(&run(&to(23.9), "fanuc", 25.0)), vec![]);
    let e = errors(&run(&to(24.2), "fanuc", 25.0));
    assert!(e.contains(&(Code::Collision, 13)), "{e:?}");
}

#[test]
fn gsk_g71_then_g92_passes_on_the_turned_diameter() {
    let src = "\
G0 X100 Z100
T0101
M3 S900
G0 X22 Z2
G71 U1 R0.5 F0.2
G71 P10 Q20 U0.3 W0.05
N10 G0 X12.8
G1 Z0 F0.1
X15.8 Z-1.5
Z-25
X18
N20 Z-35
G70 P10 Q20
G0 X100 Z100
T0202
M3 S600
G0 X18 Z4
G92 X15.2 Z-22 F1.5
X14.8
X14.5
X14.3
X14.15
X14.1
X14.1
G0 X100 Z100
M30
";
    let r = run(src, "gsk980", 20.0);
    assert_eq!(errors(&r), vec![], "{:?}", r.diagnostics);
    assert!(
        r.notes
            .iter()
            .any(|n| n.message.contains("Ø15.8 as the program turned it")),
        "{:?}",
        r.notes
    );
}
