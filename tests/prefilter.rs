//! `Dialect::prefilter` lets `program::run` skip `Dialect::read` for lines that are none of the
//! dialect's business. Skipping must change nothing: the events, the modal state after every line,
//! the warnings and the first error are the same as when every line is offered to `read`.
//! (The prefilters look at the lexer's word summary, `Line::summary`, before the words: the words
//! below include G codes written in ways it treats differently.)

use proptest::prelude::*;
use threadcut::dialect::{self, Read};
use threadcut::gcode::{Modal, Reader};
use threadcut::interp::Control;
use threadcut::machine::Machine;
use threadcut::program::{self, Event};

/// What happened, line by line, and how it ended.
type Trace = (Vec<String>, String);

fn with_prefilter(src: &str, machine: &Machine) -> Trace {
    let mut seen = vec![];
    let end = program::run(src.as_bytes(), machine, |modal, ev| {
        seen.push(match ev {
            Event::Plain { line, mv } => format!("{} plain {mv:?} {modal:?}", line.number),
            Event::Settings { line } => format!("{} settings {modal:?}", line.number),
            Event::Cycle { line, job, .. } => format!("{} cycle {job:?} {modal:?}", line.number),
            Event::Turning { line, job, .. } => {
                format!("{} turning {job:?} {modal:?}", line.number)
            }
        });
        Ok(())
    });
    let end = match end {
        Ok(summary) => format!("ok {} {:?}", summary.cycles, summary.warnings),
        Err(e) => format!("error {e:?}"),
    };
    (seen, end)
}

/// Whether the program has control flow for this machine: the interpreter runs it from its first
/// line of control flow, which the line-by-line model below does not describe.
fn interpreted(src: &str, machine: &Machine) -> bool {
    let d = dialect::open(machine).unwrap();
    let Some(syntax) = d.macros() else {
        return false;
    };
    let mut reader = Reader::new(src.as_bytes()).with_syntax(d.conventions().syntax);
    while let Some(line) = reader.next_line() {
        match line {
            Ok(l) => match syntax.control(&l) {
                Control::Interpret => return true,
                Control::End => return false,
                Control::No => {}
            },
            Err(e) => {
                let text = src.lines().nth(e.span.line as usize - 1).unwrap_or("");
                return syntax.looks_like_macro(text.as_bytes());
            }
        }
    }
    false
}

/// `program::run` as it was before the prefilter: every line goes to `read`.
fn without_prefilter(src: &str, machine: &Machine) -> Trace {
    let mut d = dialect::open(machine).unwrap();
    let conv = d.conventions().clone();
    let mut modal = Modal::for_machine(&conv, machine);
    modal.vocabulary = Some(d.vocabulary());
    let mut reader = Reader::new(src.as_bytes()).with_syntax(conv.syntax);
    let mut seen = vec![];
    let mut warnings = vec![];
    let mut cycles = 0;
    let macros = d.macros().is_some();
    while let Some(line) = reader.next_line() {
        let line = match line {
            Ok(l) => l,
            Err(e) => return (seen, format!("error {:?}", program::Error::Input(e))),
        };
        // A dialect with macros ends the run at the program's end (M2, M30).
        let end = macros
            && line
                .words
                .iter()
                .any(|w| w.letter == b'M' && (w.value == 2.0 || w.value == 30.0));
        let before = warnings.len();
        match d.read(&line, &mut modal, &mut warnings) {
            Err(e) => return (seen, format!("error {:?}", program::Error::Input(e))),
            Ok(Read::Plain) => match modal.apply(&conv, &line) {
                Ok(mv) => seen.push(format!("{} plain {mv:?} {modal:?}", line.number)),
                Err(e) => return (seen, format!("error {:?}", program::Error::Input(e))),
            },
            Ok(Read::Applied(mv) | Read::Own { mv, .. }) => {
                seen.push(format!("{} plain {mv:?} {modal:?}", line.number))
            }
            Ok(Read::Settings) => seen.push(format!("{} settings {modal:?}", line.number)),
            Ok(Read::Cycle(job)) => {
                cycles += 1;
                modal.position = threadcut::gcode::Position::at(job.end_point());
                seen.push(format!("{} cycle {job:?} {modal:?}", line.number));
            }
            Ok(Read::Turning(job)) => {
                if let Some(job) = &job {
                    cycles += 1;
                    modal.position = threadcut::gcode::Position::at(job.end_point());
                }
                seen.push(format!("{} turning {job:?} {modal:?}", line.number));
            }
        }
        for w in &mut warnings[before..] {
            if w.span.line == 0 {
                w.span = line.span();
            }
        }
        if end {
            break;
        }
    }
    if let Err(e) = d.end_of_input() {
        return (seen, format!("error {:?}", program::Error::Input(e)));
    }
    (seen, format!("ok {cycles} {warnings:?}"))
}

const WORDS: &[&str] = &[
    "G0",
    "G1",
    "G01",
    "G2",
    "G3",
    // Written in ways the lexer's word summary (`Line::summary`) counts as other than G0–G3.
    "G1.0",
    "G-0",
    "G04",
    "g78",
    "G78.0",
    "G4",
    "G20",
    "G21",
    "G32",
    "G33",
    "G35",
    "G36",
    "G50",
    "G72",
    "G73",
    "G78",
    "G90",
    "G91",
    "G92",
    "G28",
    "X1.5",
    "X20",
    "X.5",
    "Z-3",
    "Z0.5",
    "Z-.75",
    "U-0.2",
    "W-1",
    "F0.1",
    "F2",
    "F.05",
    "E0.05",
    "E8",
    "I8",
    "K0.05",
    "J1.5",
    "P020545",
    "P3",
    "P",
    "Q0.15",
    "Q1.8",
    "R0.5",
    "D1",
    "L2",
    "S500",
    "S9000",
    "C",
    "C29",
    "O",
    "M3",
    "T0101",
    "(c)",
    "N10",
    // Whole cycles of each dialect, so that cycles (and their checks of earlier state) happen.
    "G33X.212Z-.5I.012K.05PC",
    "G78 P020045 Q0.15 R0.5",
    "G78 X60 Z-60 P3 Q1.8 F3 J1.5 K2",
    "G78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1",
    // Fanuc-family G76/G92 (fanuc, and gsk980 through the shared reader), LinuxCNC's G76.
    "G76 P020060 Q100 R0.05",
    "G76 X27.546 Z-30. P1227 Q400 F2.",
    "G92 X29.2 Z-30. F2.",
    "G76 P2.5 Z-30 I-1.0 J0.3 K1.5335",
    "G7",
    "G8",
    // Fanuc-family turning cycles: a contour read after its cycle, a modal box cycle.
    "G71 U1.5 R0.5",
    "G71 P10 Q20 U0.4 W0.1 F0.2",
    "N10 G0 X20",
    "N20 G1 Z-10",
    "G70 P10 Q20",
    "G90 X30 Z-10 F0.2",
    "G74 R0.5",
    "G74 Z-10 Q3000 F0.1",
    // Sinumerik: its cycle, its start angle, parameters, diameter and unit codes, tool offsets.
    "CYCLE97(1.5,,0,-20,24,24,2,1,0.92,0.05,30,0,5,1,3,1)",
    "CYCLE97(R1,,0,-20,24,24,2,1,0.92,0.05,-29,0,5,1,3,2)",
    "G33 Z-20 K1.5 SF=90",
    "R1=2",
    "DIAMOF",
    "DIAM90",
    "D0",
    "T2",
    "G70",
    "G71",
    "G710",
    "G74 X1=0 Z1=0",
    "; c",
    // Where the tool is: reference returns, machine coordinates, work offsets, offset changes
    // (each dialect's own list), and exponents (E glued to a number).
    "G28",
    "G28.1",
    "G29",
    "G30",
    "G53",
    "G55",
    "G10",
    "G154",
    "G500",
    "G153",
    "SUPA",
    "G75 FP=2 Z1=0",
    "X1e3",
    // Haas and the FS15 format: the start angle Q, the chamfer switches.
    "Q90000",
    "M23",
    "M24",
];

fn program() -> impl Strategy<Value = String> {
    let line = proptest::collection::vec(proptest::sample::select(WORDS), 0..5)
        .prop_map(|words| words.join(" "));
    proptest::collection::vec(line, 0..12).prop_map(|lines| {
        let mut text = String::from("G0 X2 Z0.5\n");
        for l in lines {
            text.push_str(&l);
            text.push('\n');
        }
        text
    })
}

#[test]
fn bundled_examples_trace_the_same() {
    for entry in std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/examples")).unwrap() {
        let path = entry.unwrap().path();
        // examples/python/ holds the Python package's examples.
        if path.is_dir() {
            continue;
        }
        let src = std::fs::read_to_string(&path).unwrap();
        for (name, _) in threadcut::machine::BUILT_IN {
            let m = Machine::built_in(name).unwrap();
            // (A shell script's `#!` is a macro line to a dialect with macros.)
            if interpreted(&src, &m) {
                continue;
            }
            let got = with_prefilter(&src, &m);
            let want = without_prefilter(&src, &m);
            assert_eq!(got, want, "{} on {name}", path.display());
        }
    }
}

#[test]
fn state_read_from_plain_lines_is_kept() {
    // OmniTurn keeps the last S for its slide-speed check of a later G33: the S line has no cycle
    // code but must still reach `read`.
    let src = "G0 X2 Z0.5\nS9000\nX.237\nG33X.212Z-.5I.012K.05PC\n";
    let m = Machine::built_in("omniturn").unwrap();
    let want = without_prefilter(src, &m);
    assert!(want.1.contains("MachineLimit"), "{want:?}");
    assert_eq!(with_prefilter(src, &m), want);
}

proptest! {
    #[test]
    fn skipping_read_changes_nothing(
        src in program(),
        which in 0usize..threadcut::machine::BUILT_IN.len(),
    ) {
        let m = Machine::built_in(threadcut::machine::BUILT_IN[which].0).unwrap();
        prop_assume!(!interpreted(&src, &m));
        prop_assert_eq!(with_prefilter(&src, &m), without_prefilter(&src, &m));
    }
}
