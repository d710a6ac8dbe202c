//! Conversion between controllers over the whole matrix of bundled examples × lathe controllers:
//! every converted program reads back on the target with the source's motion, or the conversion
//! is refused with a reason that names the target's limit. The outcome of every pair — native
//! cycles, plain cycles and each refusal's reason — is the table in `docs/translation.md`, which
//! this test keeps current.

use std::path::Path;

use threadcut::convert::{self, Report};
use threadcut::dialect;
use threadcut::machine::{Machine, BUILT_IN};
use threadcut::program::{self, Event};
use threadcut::toolpath::{self, MotionKind};
use threadcut::translate::same_angle;
use threadcut::units::{Pos, Units};

/// Each bundled G-code example and the controller it is written for (its name's prefix).
fn examples() -> Vec<(String, &'static str, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut out = Vec::new();
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .filter(|n| n.ends_with(".nc") || n.ends_with(".ngc") || n.ends_with(".mpf"))
        .collect();
    names.sort();
    for name in names {
        // The longest profile name that prefixes the file's name.
        let controller = BUILT_IN
            .iter()
            .map(|(n, _)| *n)
            .filter(|n| name.starts_with(n) || (*n == "gsk980" && name.starts_with("gsk")))
            .max_by_key(|n| n.len())
            .unwrap_or_else(|| panic!("{name}: no controller"));
        let text = std::fs::read_to_string(dir.join(&name)).unwrap();
        out.push((name, controller, text));
    }
    out
}

/// A move: kind, start, end, lead (mm along the longer axis) and start angle.
#[derive(Clone, Copy, Debug)]
struct Move {
    rapid: bool,
    thread: Option<(f64, f64)>,
    /// A cutting move's feed (the F register, mm per minute or per revolution).
    feed: Option<f64>,
    from: Pos,
    to: Pos,
}

/// Every move `text` makes on `m`: plain moves and each cycle's toolpath, moves of no length left
/// out (a cycle's rapid to where the tool already is).
fn motion(text: &str, m: &Machine) -> Result<Vec<Move>, program::Error> {
    let mut moves = Vec::new();
    program::run(text.as_bytes(), m, |modal, ev| {
        match ev {
            Event::Plain { mv: Some(mv), .. } => moves.push(Move {
                rapid: mv.mode == threadcut::gcode::MotionMode::Rapid,
                thread: mv.lead.map(|l| (l, mv.phase_deg)),
                feed: (mv.mode != threadcut::gcode::MotionMode::Rapid && mv.lead.is_none())
                    .then(|| modal.f_word.map(|f| modal.units.to_mm(f)))
                    .flatten(),
                from: mv.from,
                to: mv.to,
            }),
            Event::Cycle { job, .. } => {
                let path = toolpath::build(&job)?;
                for (from, mo) in path.segments() {
                    moves.push(Move {
                        rapid: mo.kind == MotionKind::Rapid,
                        thread: match mo.kind {
                            MotionKind::Thread {
                                lead, phase_deg, ..
                            } => Some((lead, phase_deg)),
                            _ => None,
                        },
                        feed: None,
                        from,
                        to: mo.to,
                    });
                }
            }
            _ => {}
        }
        Ok(())
    })?;
    moves.retain(|m| m.from.distance(m.to) > 1e-12);
    Ok(moves)
}

/// The first difference between two motions, within `pos` (mm) and `lead` (mm per revolution).
fn differs(a: &[Move], b: &[Move], pos: f64, lead: f64) -> Option<String> {
    if a.len() != b.len() {
        return Some(format!("{} moves instead of {}", b.len(), a.len()));
    }
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        let same_kind = x.rapid == y.rapid
            && match (x.thread, y.thread) {
                (None, None) => true,
                (Some((la, pa)), Some((lb, pb))) => (la - lb).abs() <= lead && same_angle(pa, pb),
                _ => false,
            };
        let d = x.to.minus(y.to);
        let same_feed = match (x.feed, y.feed) {
            (Some(a), Some(b)) => (a - b).abs() <= 1e-6 * a.abs().max(1.0),
            (a, b) => a.is_none() == b.is_none(),
        };
        if !same_kind || !same_feed || d.x.abs() > pos || d.z.abs() > pos {
            return Some(format!("move {}: {x:?} became {y:?}", i + 1));
        }
    }
    None
}

/// Half the coarsest output resolution of `to` (mm, a program may switch units), and half its
/// coarsest lead step.
fn tolerances(to: &Machine) -> (f64, f64) {
    let d = dialect::open(to).unwrap();
    let lex = d.lexicon();
    let units = [Units::Mm, Units::Inch]
        .into_iter()
        .filter(|u| lex.has_units(*u));
    let res = units
        .clone()
        .map(|u| u.to_mm(d.output_step(1.0, u).unwrap_or(to.resolution(u))))
        .fold(0.0, f64::max);
    let digits = d.format().lead_decimals;
    let lead = units
        .map(|u| {
            u.to_mm(
                d.output_step(1.0, u)
                    .unwrap_or(10f64.powi(-(digits[(u == Units::Inch) as usize] as i32))),
            )
        })
        .fold(0.0, f64::max);
    (res * 0.5 + 1e-9, lead * 0.5 + 1e-9)
}

/// One pair's outcome, as the table in docs/translation.md writes it.
fn outcome(name: &str, from: &Machine, to: &Machine, text: &str) -> String {
    let mut out = Vec::new();
    match convert::convert(text.as_bytes(), &mut out, from, to) {
        Ok(Report { native, plain, .. }) => {
            let converted = String::from_utf8(out).unwrap();
            let want = motion(text, from).unwrap();
            let got = motion(&converted, to).unwrap_or_else(|e| {
                panic!(
                    "{name} → {}: the converted program does not read back: {e}\n{converted}",
                    to.name
                )
            });
            let (pos, lead) = tolerances(to);
            if let Some(why) = differs(&want, &got, pos, lead) {
                panic!("{name} → {}: {why}\n{converted}", to.name);
            }
            let cycles = native as usize + plain.len();
            if cycles == 0 {
                "converted (no cycle)".to_string()
            } else if plain.is_empty() {
                format!("native {native}")
            } else {
                let mut why: Vec<&str> = plain.iter().map(|(_, w)| w.as_str()).collect();
                why.dedup();
                format!("native {native}, plain {}: {}", plain.len(), why.join("; "))
            }
        }
        Err(program::Error::Input(d)) => {
            format!("refused at line {}: {}", d.span.line, d.message)
        }
        Err(e) => panic!("{name} → {}: {e}", to.name),
    }
}

const BEGIN: &str = "<!-- matrix:begin (tests/convert.rs writes this table) -->";
const END: &str = "<!-- matrix:end -->";

#[test]
fn every_example_converts_to_every_lathe_controller_or_is_refused_for_a_reason() {
    let mut rows = vec![
        "| example | to | outcome |".to_string(),
        "|---|---|---|".to_string(),
    ];
    let (mut pairs, mut refused, mut native, mut plain) = (0, 0, 0, 0);
    for (name, controller, text) in examples() {
        let from = Machine::built_in(controller).unwrap();
        for (target, _) in BUILT_IN {
            if *target == controller {
                continue;
            }
            pairs += 1;
            let to = Machine::built_in(target).unwrap();
            let o = outcome(&name, &from, &to, &text);
            if o.starts_with("refused") {
                refused += 1;
            }
            if let Some(n) = o.strip_prefix("native ") {
                let mut parts = n.split(", plain ");
                native += parts.next().unwrap().parse::<u32>().unwrap();
                plain += parts
                    .next()
                    .map_or(0, |p| p.split(':').next().unwrap().parse::<u32>().unwrap());
            }
            rows.push(format!("| {name} | {target} | {} |", o.replace('|', "\\|")));
        }
    }
    rows.push(String::new());
    rows.push(format!(
        "{pairs} pairs: {} converted ({native} cycles native, {plain} as plain moves), {refused} refused.",
        pairs - refused
    ));
    let table = rows.join("\n");
    let doc_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/translation.md");
    let doc = std::fs::read_to_string(&doc_path).unwrap();
    let (Some(b), Some(e)) = (doc.find(BEGIN), doc.find(END)) else {
        panic!("docs/translation.md has no matrix block; it should be:\n{BEGIN}\n{table}\n{END}");
    };
    let current = doc[b + BEGIN.len()..e].trim();
    if current != table.trim() {
        if std::env::var_os("THREADCUT_BLESS").is_some() {
            let new = format!("{}{BEGIN}\n{table}\n{}", &doc[..b], &doc[e..]);
            std::fs::write(&doc_path, new).unwrap();
        } else {
            panic!("docs/translation.md's matrix is out of date (THREADCUT_BLESS=1 rewrites it):\n{table}");
        }
    }
}

/// A metric program for the inch-only OmniTurn is written in inches: positions, feeds and the
/// cycle's words converted, the lead's rounding over the thread stated. (An OmniTurn profile in
/// mm reads the same cycle in mm: its K1.27 mm is .05" exactly.)
#[test]
fn metric_programs_are_converted_to_inch_for_the_omniturn() {
    let mut metric = Machine::built_in("omniturn").unwrap();
    metric.units = Units::Mm;
    let inch = Machine::built_in("omniturn").unwrap();
    let src = "T4F200\nX0Z5.08\nX6.0198\nG33X5.3848Z-12.7I0.3048K1.27PC\n";
    let out = convert::convert_text(src, &metric, &inch).unwrap();
    assert_eq!(
        out,
        "(threadcut convert: omniturn to omniturn, inch, feed per minute)\n\
         G90 G73 G94\n\
         F7.87402 T4\n\
         G0 X0. Z0.2\n\
         G0 X0.237\n\
         (threadcut: in inch: lead 1.27 mm written as 0.05 inch: 0. inch per turn, 0. inch over the thread's 0.7 inch)\n\
         G33 X0.212 Z-0.5 I0.012 K0.05 C29. P\n"
    );
    // Plain moves from a metric Fanuc program: radius, inches, F in inches per revolution.
    let fanuc = Machine::built_in("fanuc").unwrap();
    let src = "G21 G99\nG0 X20. Z5.\nG1 Z-10. F0.254\nM30\n";
    let out = convert::convert_text(src, &fanuc, &inch).unwrap();
    assert!(
        out.ends_with("G95\nG0 X0.3937 Z0.19685\nG1 Z-0.3937 F0.01\nM30\n"),
        "{out}"
    );
    // A metric lead the grid cannot hold is refused with the drift (the matrix lists the
    // bundled examples refused so).
    let src = "G0 X0 Z5.08\nX6.0198\nG33X5.3848Z-12.7I0.3048K1.5PC\n";
    let e = convert::convert_text(src, &metric, &inch).unwrap_err();
    assert!(e.message.contains("drifts"), "{}", e.message);
    assert_eq!(e.span.line, 3);
}

/// `post` states what its program relies on, for every lathe controller: the units (the code, or
/// for a control with one unit system its name), feed per revolution at the start and each
/// FEDRAT's mode before its F, X on diameter or radius where the control has a code for it —
/// never the control's power-on state. Every posted program reads back on its controller.
#[test]
fn posted_programs_state_units_and_feed_mode_for_every_controller() {
    use threadcut::convert::lexicon::{Function, Plane};
    let cl = "UNITS/MM\nSPINDL/500,RPM,CLW\nRAPID\nGOTO/20,0,5\nFEDRAT/100,MMPM\nGOTO/18,0,5\nFEDRAT/0.2,MMPR\nGOTO/18,0,-20\nFINI\n";
    for (name, _) in BUILT_IN {
        let m = Machine::built_in(name).unwrap();
        let d = dialect::open(&m).unwrap();
        let lex = d.lexicon();
        let mut out = Vec::new();
        threadcut::apt::post::write(cl.as_bytes(), &mut out, &m).unwrap();
        let text = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        let code = |f: Function| lex.code(f).map(|c| c.text());
        // The first block that is not a comment states the modes.
        let header = lines
            .iter()
            .find(|l| !l.starts_with('(') && !l.starts_with(';'))
            .unwrap();
        let words: Vec<&str> = header.split_whitespace().collect();
        match code(Function::Units(m.units)) {
            Some(c) => assert!(words.contains(&c.as_str()), "{name}: {header}"),
            None => {
                assert_eq!(lex.only_units, Some(m.units), "{name}");
                assert!(lines[0].contains(m.units.name()), "{name}: {}", lines[0]);
            }
        }
        let per_rev = code(Function::FeedPerRevolution).unwrap();
        let per_min = code(Function::FeedPerMinute).unwrap();
        assert!(words.contains(&per_rev.as_str()), "{name}: {header}");
        for f in [Function::Diameter, Function::Radius] {
            if let (Some(c), true) = (code(f), (f == Function::Diameter) == m.diameter_x) {
                assert!(words.contains(&c.as_str()), "{name}: {header}");
            }
        }
        if let Some(c) = code(Function::Plane(Plane::Zx)) {
            assert!(words.contains(&c.as_str()), "{name}: {header}");
        }
        // Each FEDRAT that changes the mode states it before the F it gives.
        let at = |needle: &str| {
            lines
                .iter()
                .position(|l| l.split_whitespace().any(|w| w == needle))
        };
        let first_f = lines.iter().position(|l| l.contains(" F")).unwrap();
        let min_at = at(&per_min).unwrap_or_else(|| panic!("{name}: {text}"));
        assert!(min_at < first_f, "{name}: {text}");
        let rev_again = lines[min_at..]
            .iter()
            .position(|l| l.split_whitespace().any(|w| w == per_rev))
            .unwrap();
        assert!(
            lines[min_at + rev_again..].iter().any(|l| l.contains(" F")),
            "{name}: {text}"
        );
        threadcut::program::run(text.as_bytes(), &m, |_, _| Ok(()))
            .unwrap_or_else(|e| panic!("{name}: {e}\n{text}"));
    }
}

/// One controller's words for a row of the lexicon table.
fn lexicon_cell(lex: &threadcut::convert::lexicon::Lexicon, row: &str) -> String {
    use threadcut::convert::lexicon::{
        DwellForm, Function as F, LimitForm, Plane, ReturnForm, ToolForm,
    };
    let codes = |fs: &[F]| -> String {
        let all: Vec<String> = fs
            .iter()
            .map(|f| {
                lex.codes
                    .iter()
                    .flat_map(|g| g.iter())
                    .filter(|(_, g)| g == f)
                    .map(|(c, _)| c.text())
                    .collect::<Vec<_>>()
                    .join("/")
            })
            .collect();
        if all.iter().all(|c| c.is_empty()) {
            "—".into()
        } else {
            all.iter()
                .map(|c| if c.is_empty() { "—" } else { c.as_str() })
                .collect::<Vec<_>>()
                .join(" ")
        }
    };
    match row {
        "inch / mm" => match lex.only_units {
            Some(u) => format!("{} only", u.name()),
            None => codes(&[F::Units(Units::Inch), F::Units(Units::Mm)]),
        },
        "absolute / incremental" => codes(&[F::Absolute, F::Incremental]),
        "X diameter / radius" => codes(&[F::Diameter, F::Radius]),
        "planes XY / ZX / YZ" => codes(&[
            F::Plane(Plane::Xy),
            F::Plane(Plane::Zx),
            F::Plane(Plane::Yz),
        ]),
        "feed per minute / revolution" => codes(&[F::FeedPerMinute, F::FeedPerRevolution]),
        "feed mode at power-on" => match lex.power_on_feed {
            F::FeedPerMinute => "per minute".into(),
            _ => "per revolution".into(),
        },
        "surface speed / rpm" => codes(&[F::SurfaceSpeed, F::Rpm]),
        "compensation off / left / right" => codes(&[
            F::CompensationOff,
            F::CompensationLeft,
            F::CompensationRight,
        ]),
        "work offsets" => codes(&[
            F::WorkOffset(1),
            F::WorkOffset(2),
            F::WorkOffset(3),
            F::WorkOffset(4),
            F::WorkOffset(5),
            F::WorkOffset(6),
        ]),
        "thread move" => codes(&[F::Thread]),
        "dwell" => match lex.dwell {
            Some(DwellForm::XSecondsOrPMilliseconds) => format!("{} X(s) P(ms)", codes(&[F::Dwell])),
            Some(DwellForm::PSeconds) => format!("{} P(s)", codes(&[F::Dwell])),
            Some(DwellForm::PSecondsOrMilliseconds) => format!("{} P(s.)/P(ms)", codes(&[F::Dwell])),
            Some(DwellForm::FSeconds) => format!("{} F(s)", codes(&[F::Dwell])),
            None => "—".into(),
        },
        "set position" => codes(&[F::SetPosition, F::RestatePosition]),
        "spindle limit" => match lex.spindle_limit {
            Some(LimitForm::Code) => format!("{} S", codes(&[F::SpindleLimit])),
            Some(LimitForm::Setting(s)) => format!("{s}="),
            Some(LimitForm::OnSurfaceSpeed(l)) => format!("{} … {}", codes(&[F::SurfaceSpeed]), l as char),
            None => "—".into(),
        },
        "reference return" => match lex.reference {
            Some(ReturnForm::IncrementalWords { x, z }) => format!(
                "{} {}0 {}0{}",
                codes(&[F::ReferenceReturn]),
                x as char,
                z as char,
                if lex.return_all_without_axes { " (bare: all)" } else { "" }
            ),
            Some(ReturnForm::IncrementalMode) => format!(
                "{} {} X0 Z0, {}{}",
                codes(&[F::Incremental]),
                codes(&[F::ReferenceReturn]),
                codes(&[F::Absolute]),
                if lex.return_all_without_axes { " (bare: all)" } else { "" }
            ),
            Some(ReturnForm::MachineAxes { x, z }) => {
                format!("{} {x}=0 {z}=0", codes(&[F::ReferenceReturn]))
            }
            None => "—".into(),
        },
        "tool" => match lex.tool {
            ToolForm::Combined { .. } => "T0101 (tool, offset)".into(),
            ToolForm::Single => "T4 (its own offset)".into(),
            ToolForm::ToolAndEdge => "T7 D1 (edge 1: its offset)".into(),
            ToolForm::ChangeAndOffset => format!(
                "T1 {} {} [H] / {}",
                codes(&[F::ToolChange]),
                codes(&[F::ToolOffset]),
                codes(&[F::ToolOffsetOff])
            ),
        },
        "spindle cw / ccw / stop" => codes(&[F::SpindleCw, F::SpindleCcw, F::SpindleStop]),
        "coolant on / mist / off" => codes(&[F::CoolantOn, F::MistOn, F::CoolantOff]),
        "end / end and rewind" => codes(&[F::End, F::EndRewind]),
        "stop / optional stop" => codes(&[F::Stop, F::OptionalStop]),
        "cycle settings (carried by the jobs)" => codes(&[F::CycleSetting]),
        "thread move's lead words" => {
            let w = String::from_utf8_lossy(lex.thread_words).to_string();
            let mut all: Vec<String> = w.chars().map(|c| c.to_string()).collect();
            all.extend(lex.thread_settings.iter().map(|s| format!("{s}=")));
            if all.is_empty() {
                "—".into()
            } else {
                all.join(" ")
            }
        }
        "O program numbers / N / %" => format!(
            "{} / {} / {}",
            if lex.program_number { "yes" } else { "no" },
            if lex.sequence_numbers { "yes" } else { "no" },
            if lex.delimiters { "yes" } else { "no" }
        ),
        _ => unreachable!(),
    }
}

const LEXICON_BEGIN: &str = "<!-- lexicon:begin (tests/convert.rs writes this table) -->";
const LEXICON_END: &str = "<!-- lexicon:end -->";

/// The table of every controller's lexicon in docs/translation.md is the lexicons themselves.
#[test]
fn the_lexicon_table_is_the_dialects_lexicons() {
    let rows = [
        "inch / mm",
        "absolute / incremental",
        "X diameter / radius",
        "planes XY / ZX / YZ",
        "feed per minute / revolution",
        "feed mode at power-on",
        "surface speed / rpm",
        "spindle limit",
        "compensation off / left / right",
        "work offsets",
        "thread move",
        "thread move's lead words",
        "dwell",
        "set position",
        "reference return",
        "tool",
        "spindle cw / ccw / stop",
        "coolant on / mist / off",
        "end / end and rewind",
        "stop / optional stop",
        "cycle settings (carried by the jobs)",
        "O program numbers / N / %",
    ];
    let machines: Vec<Machine> = BUILT_IN
        .iter()
        .map(|(n, _)| Machine::built_in(n).unwrap())
        .collect();
    let dialects: Vec<_> = machines.iter().map(|m| dialect::open(m).unwrap()).collect();
    let mut table = format!(
        "| | {} |\n|---|{}\n",
        machines
            .iter()
            .map(|m| m.name.as_str())
            .collect::<Vec<_>>()
            .join(" | "),
        "---|".repeat(machines.len())
    );
    for row in rows {
        let cells: Vec<String> = dialects
            .iter()
            .map(|d| lexicon_cell(d.lexicon(), row))
            .collect();
        table.push_str(&format!("| {row} | {} |\n", cells.join(" | ")));
    }
    let doc_path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/translation.md");
    let doc = std::fs::read_to_string(&doc_path).unwrap();
    let (Some(b), Some(e)) = (doc.find(LEXICON_BEGIN), doc.find(LEXICON_END)) else {
        panic!("docs/translation.md has no lexicon block:\n{LEXICON_BEGIN}\n{table}{LEXICON_END}");
    };
    if doc[b + LEXICON_BEGIN.len()..e].trim() != table.trim() {
        if std::env::var_os("THREADCUT_BLESS").is_some() {
            let new = format!("{}{LEXICON_BEGIN}\n{table}{}", &doc[..b], &doc[e..]);
            std::fs::write(&doc_path, new).unwrap();
        } else {
            panic!("docs/translation.md's lexicon table is out of date (THREADCUT_BLESS=1 rewrites it):\n{table}");
        }
    }
}
