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

/// A look ahead on the run's own thread (`program::ahead`; the command's runs on another): at
/// each seam it reads the lines from the first line start `chunk` bytes on, from the run's state
/// there or, every third time, from the state of the seam before (a wrong guess, which the run
/// must not take), warmed by up to `warm` bytes of the lines before.
struct Beside<'a> {
    text: &'a [u8],
    look: program::ahead::Looker,
    chunk: u64,
    warm: u64,
    ready: Option<(u64, program::ahead::Taken)>,
    stale: Option<Modal>,
    calls: u32,
}

impl program::ahead::Ahead for Beside<'_> {
    fn first_seam(&mut self) -> u64 {
        0
    }

    fn at(
        &mut self,
        offset: u64,
        modal: &Modal,
        _at_rest: bool,
    ) -> (Option<program::ahead::Taken>, u64) {
        if let Some((seam, taken)) = self.ready.take() {
            if seam == offset {
                let next = offset + taken.bytes;
                return (Some(taken), next);
            }
        }
        self.calls += 1;
        let guess = match &self.stale {
            Some(stale) if self.calls.is_multiple_of(3) => stale.clone(),
            _ => modal.clone(),
        };
        self.stale = Some(modal.clone());
        let text = self.text;
        // The first line start at or after `at`.
        let start = |at: u64| -> u64 {
            if at <= offset {
                return offset;
            }
            let from = (at - 1) as usize;
            match text
                .get(from..)
                .and_then(|t| t.iter().position(|&b| b == b'\n'))
            {
                Some(i) => (from + i + 1) as u64,
                None => text.len() as u64,
            }
        };
        let seam = start(offset + self.chunk);
        let end = start(seam + 2 * self.chunk);
        let first = start(seam.saturating_sub(self.warm)).min(seam);
        let (warm, part) = (
            &text[first as usize..seam as usize],
            &text[seam as usize..end as usize],
        );
        self.ready = (self.look)(&guess, warm, part).map(|taken| (seam, taken));
        (None, offset + self.chunk)
    }
}

/// `expand` of `src`, and how it ended, with a look ahead of these sizes or without one.
fn expand_reading_ahead(
    src: &[u8],
    machine: &Machine,
    sizes: Option<(u64, u64)>,
) -> (Vec<u8>, String) {
    let mut out = Vec::new();
    let options = program::Options::default();
    let end = match sizes {
        None => {
            program::expand_gcode_to(src, &mut threadcut::post::Now(&mut out), machine, &options)
        }
        Some((chunk, warm)) => {
            let mut beside = Beside {
                text: src,
                look: program::ahead::looker(machine).unwrap(),
                chunk,
                warm,
                ready: None,
                stale: None,
                calls: 0,
            };
            program::expand_gcode_ahead(
                src,
                &mut threadcut::post::Now(&mut out),
                machine,
                &options,
                Some(&mut beside),
            )
        }
    };
    (out, format!("{end:?}"))
}

#[test]
fn reading_ahead_changes_nothing_in_the_bundled_and_real_programs() {
    let root = env!("CARGO_MANIFEST_DIR");
    let mut files = vec![];
    for dir in ["examples", "tests/data/real"] {
        for entry in std::fs::read_dir(format!("{root}/{dir}")).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                files.push(path);
            }
        }
    }
    let mut taken_some = 0;
    for path in files {
        let src = std::fs::read(&path).unwrap();
        for (name, _) in threadcut::machine::BUILT_IN {
            let m = Machine::built_in(name).unwrap();
            let want = expand_reading_ahead(&src, &m, None);
            for sizes in [(1, 0), (1, 40), (7, 300), (64, 16), (500, 4096)] {
                let got = expand_reading_ahead(&src, &m, Some(sizes));
                assert!(
                    got == want,
                    "{} on {name}, sizes {sizes:?}:\n{}\n{}\nwant:\n{}\n{}",
                    path.display(),
                    String::from_utf8_lossy(&got.0),
                    got.1,
                    String::from_utf8_lossy(&want.0),
                    want.1
                );
            }
            taken_some += usize::from(want.1.starts_with("Ok"));
        }
    }
    assert!(taken_some > 100, "{taken_some} programs expanded");
}

proptest! {
    // Many cases: a seam must fall where a dialect is not at rest (between a G92 and the block
    // that repeats it) for a wrong `at_rest` to show.
    #![proptest_config(ProptestConfig::with_cases(3000))]
    #[test]
    fn reading_ahead_changes_nothing(
        src in program(),
        which in 0usize..threadcut::machine::BUILT_IN.len(),
        chunk in 1u64..40,
        warm in 0u64..60,
    ) {
        let m = Machine::built_in(threadcut::machine::BUILT_IN[which].0).unwrap();
        let want = expand_reading_ahead(src.as_bytes(), &m, None);
        prop_assert_eq!(expand_reading_ahead(src.as_bytes(), &m, Some((chunk, warm))), want);
    }
}

/// `Dialect::at_rest` promises that the prefilter answers every line as a freshly opened
/// dialect's does: checked after each line of `src` (each read as the run reads it), on every
/// line of the word list and of `src`. The first line where it does not hold.
fn at_rest_breaks(src: &str, machine: &Machine) -> Option<String> {
    let fresh = dialect::open(machine).unwrap();
    let mut d = dialect::open(machine).unwrap();
    let conv = d.conventions().clone();
    let mut modal = Modal::for_machine(&conv, machine);
    modal.vocabulary = Some(d.vocabulary());
    let probes = format!("{}\n{src}", WORDS.join("\n"));
    let mut reader = Reader::new(src.as_bytes()).with_syntax(conv.syntax);
    let mut warnings = vec![];
    while let Some(Ok(line)) = reader.next_line() {
        match d.read(&line, &mut modal, &mut warnings) {
            Ok(Read::Plain) if modal.apply(&conv, &line).is_ok() => {}
            Ok(Read::Plain) | Err(_) => return None,
            Ok(_) => {}
        }
        if !d.at_rest() {
            continue;
        }
        let mut probe = Reader::new(probes.as_bytes()).with_syntax(conv.syntax);
        while let Some(p) = probe.next_line() {
            let Ok(p) = p else { continue };
            if d.prefilter(&p) != fresh.prefilter(&p) {
                return Some(format!(
                    "after line {}: {:?}",
                    line.number,
                    String::from_utf8_lossy(p.text)
                ));
            }
        }
    }
    None
}

proptest! {
    #[test]
    fn a_dialect_at_rest_prefilters_as_a_fresh_one(
        src in program(),
        which in 0usize..threadcut::machine::BUILT_IN.len(),
    ) {
        let m = Machine::built_in(threadcut::machine::BUILT_IN[which].0).unwrap();
        prop_assert_eq!(at_rest_breaks(&src, &m), None);
    }
}

#[test]
fn at_rest_does_not_hide_a_modal_cycle_in_progress() {
    // OmniTurn checks the block after a G35 (its G92 check); Fanuc's G92 is repeated by a block
    // of axis words; Sinumerik restores the radius after a CYCLE97 expanded under DIAM90 and G91.
    for (name, src) in [
        ("omniturn", "G0 X2 Z0.5\nG35\nX1.5\n"),
        ("fanuc", "G0 X32 Z5\nG92 X29.2 Z-30. F2.\nX28.6\n"),
        (
            "sinumerik",
            "G0 X32 Z5\nDIAM90\nG91\nCYCLE97(1.5,,0,-20,24,24,2,1,0.92,0.05,30,0,5,1,3,1)\nX1\n",
        ),
    ] {
        let m = Machine::built_in(name).unwrap();
        assert_eq!(at_rest_breaks(src, &m), None, "{name}");
        let d = dialect::open(&m).unwrap();
        assert!(d.at_rest(), "{name}: a fresh dialect is at rest");
    }
}
