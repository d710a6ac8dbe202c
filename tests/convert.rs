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
                // An axis whose start is not known: the move is measured from its end there.
                from: Pos::new(mv.from.x.unwrap_or(mv.to.x), mv.from.z.unwrap_or(mv.to.z)),
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
    let lex = d.meanings();
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

/// One pair's outcome, as the table in docs/translation.md writes it. A program with control flow
/// is converted as `--flatten` converts it (the executed program; without it the conversion stops
/// at its first line of control flow on a target without macros, or keeps its structure on one
/// with them, `programs_with_control_flow_need_flatten_where_the_target_has_no_macros`), and its row says
/// so.
fn outcome(name: &str, from: &Machine, to: &Machine, text: &str) -> String {
    outcome_with(name, from, to, text, &[], &|_| false)
}

/// [`outcome`] with named tools (`--tool`), the moves `ignored` left out of both motions.
fn outcome_with(
    name: &str,
    from: &Machine,
    to: &Machine,
    text: &str,
    tools: &[(String, String)],
    ignored: &dyn Fn(&Move) -> bool,
) -> String {
    let mut out = Vec::new();
    let flatten = convert::Options {
        run: program::Options {
            flatten: true,
            ..Default::default()
        },
        tools: tools.to_vec(),
        ..Default::default()
    };
    match convert::convert(text.as_bytes(), &mut out, from, to, &flatten) {
        Ok(Report {
            native,
            plain,
            summary,
            ..
        }) => {
            let flattened = if summary.interpreted_from.is_some() {
                "flattened: "
            } else {
                ""
            };
            let converted = String::from_utf8(out).unwrap();
            let mut want = motion(text, from).unwrap();
            let mut got = motion(&converted, to).unwrap_or_else(|e| {
                panic!(
                    "{name} → {}: the converted program does not read back: {e}\n{converted}",
                    to.name
                )
            });
            want.retain(|m| !ignored(m));
            got.retain(|m| !ignored(m));
            let (pos, lead) = tolerances(to);
            if let Some(why) = differs(&want, &got, pos, lead) {
                panic!("{name} → {}: {why}\n{converted}", to.name);
            }
            let cycles = native as usize + plain.len();
            let what = if cycles == 0 {
                "converted (no cycle)".to_string()
            } else if plain.is_empty() {
                format!("native {native}")
            } else {
                let mut why: Vec<&str> = plain.iter().map(|(_, w)| w.as_str()).collect();
                why.dedup();
                format!("native {native}, plain {}: {}", plain.len(), why.join("; "))
            };
            format!("{flattened}{what}")
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
            if let Some(n) = o.trim_start_matches("flattened: ").strip_prefix("native ") {
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

/// The matrix again as a shop states its machines (issue 26): the named tool given its number
/// (`--tool THREAD_EXT_60=T0101`) and the reference point placed in the Allen-Bradley and
/// OmniTurn profiles (`[reference] g28`, X10" on diameter and X5" on radius, Z6"; the source's
/// profile places the same point). Every pair
/// converted reads back with the source's motion ([`outcome`]); the 36 refusals of the built-in
/// profiles become 26, none of them a named tool or a reference return: what remains is the
/// OmniTurn's G33 (no plain synchronised move: 20) and start angles the target's plain thread
/// moves cannot state (6).
#[test]
fn with_the_shops_statements_named_tools_and_reference_returns_convert() {
    let tools = [("THREAD_EXT_60".to_string(), "T0101".to_string())];
    // The reference point at radius 5" (127 mm), Z 6" (152.4 mm), in a profile's units and X
    // mode; the source is given the same point, so that both programs end their return there.
    let placed = |mut m: Machine| {
        let inch = m.units == Units::Inch;
        let unit = if inch { 1.0 } else { 25.4 };
        let x = if m.diameter_x { 10.0 } else { 5.0 } * unit;
        m.reference = Some(threadcut::machine::ReferencePoints {
            g28: threadcut::machine::AxisPoint {
                x: Some(x),
                z: Some(6.0 * unit),
            },
            ..Default::default()
        });
        m
    };
    let (mut pairs, mut refused, mut omniturn, mut angle) = (0, 0, 0, 0);
    for (name, controller, text) in examples() {
        for (target, _) in BUILT_IN {
            if *target == controller {
                continue;
            }
            pairs += 1;
            let (mut from, mut to) = (
                Machine::built_in(controller).unwrap(),
                Machine::built_in(target).unwrap(),
            );
            if matches!(*target, "ab9" | "omniturn") {
                (from, to) = (placed(from), placed(to));
            }
            // The source's return is no move in threadcut's reading (the position jumps there);
            // the target's rapid to the point is: left out of both.
            let at_reference = |m: &Move| {
                m.rapid && ((m.to.x - 127.0).abs() < 1e-6 || (m.to.z - 152.4).abs() < 1e-6)
            };
            let o = outcome_with(&name, &from, &to, &text, &tools, &at_reference);
            if !o.starts_with("refused") {
                continue;
            }
            refused += 1;
            assert!(
                !o.contains("by its name") && !o.contains("reference return"),
                "{name} → {target}: {o}"
            );
            if o.contains("omniturn has no plain") {
                omniturn += 1;
            } else if o.contains("start angle") {
                angle += 1;
            } else {
                panic!("{name} → {target}: {o}");
            }
        }
    }
    assert_eq!((pairs, refused, omniturn, angle), (208, 26, 20, 6));
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
    let out = convert::convert_text(src, &metric, &inch, &Default::default()).unwrap();
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
    let out = convert::convert_text(src, &fanuc, &inch, &Default::default()).unwrap();
    assert!(
        out.ends_with("G95\nG0 X0.3937 Z0.19685\nG1 Z-0.3937 F0.01\nM30\n"),
        "{out}"
    );
    // Issue 26's 2 mm lead on the inch OmniTurn: 2 mm = .0787402", written K.07875 on the
    // .00005" grid, .0000098" a turn; over the thread's 27.08 mm = 1.0661" (13.54 turns) it drifts
    // .0001333", × cot 30° = .0002308" on the pitch diameter. The limit: Ø 2 × 6.0198 = 12.04 mm,
    // M12.04x2-6g: Td2 = 90·2^0.4·√(11.2·22.4)^0.1 = 156.6 → R40 160 µm, a quarter 40 µm =
    // .0015748". Converted, the drift stated.
    let src = "G0 X0 Z5.08\nX6.0198\nG33X5.3848Z-22.I0.3048K2.PC\n";
    let mut out = Vec::new();
    let report = convert::convert(
        src.as_bytes(),
        &mut out,
        &metric,
        &inch,
        &Default::default(),
    )
    .unwrap();
    let out = String::from_utf8(out).unwrap();
    let stated = "(threadcut: lead 2. mm written as 0.07875 inch drifts 0.0001333 inch over the thread's 1.0661 inch, 0.0002308 inch on the pitch diameter at cot 30°; limit 0.0015748 inch, a quarter of 6g's pitch-diameter tolerance for M12.04x2, ISO metric assumed from the 60° tool)\nG33 X0.212 Z-0.86615 I0.012 K0.07875 C29. P\n";
    assert!(out.ends_with(stated), "{out}");
    let w = &report.summary.warnings;
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].message.contains("drifts 0.0001333 inch"),
        "{}",
        w[0].message
    );
    assert_eq!(w[0].span.line, 3);
}

fn drift_options(max: Option<f64>) -> convert::Options {
    convert::Options {
        max_lead_drift: max,
        ..Default::default()
    }
}

fn fanuc_to_haas(src: &str, max: Option<f64>) -> Result<String, threadcut::diag::Diagnostic> {
    convert::convert_text(
        src,
        &Machine::built_in("fanuc").unwrap(),
        &Machine::built_in("haas").unwrap(),
        &drift_options(max),
    )
}

/// A lead the target writes to fewer decimals drifts over the thread; judged at the limit, a
/// quarter of the medium class's pitch-diameter tolerance, on the drift × cot 30°.
///
/// mm: F1.50004 on Haas (4 decimals) is F1.5, 0.00004 mm a turn. M20x1.5-6g: Td2 =
/// 90·1.5^0.4·√(11.2·22.4)^0.1 = 90·1.17608·1.3182 = 139.5 → R40 140 µm, the limit 0.035 mm.
/// From Z5 to Z-750 (755 mm): 0.00004·755/1.50004 = 0.0201328 mm, × 1.7320508 = 0.034871: under;
/// to Z-760 (765 mm): 0.0203995, 0.0353329: over.
///
/// inch: F.0769231 (13 tpi, Unified) is F.07692 (5 decimals), 0.0000031" a turn. 1/2-13 2A: Td2
/// 0.0050" (d2 0.4485/0.4435), the limit 0.00125". From Z.2 to Z-17.6 (17.8"): 0.0000031·17.8/
/// 0.0769231 = 0.0007173", × 1.7320508 = 0.0012425: under; to Z-17.8 (18"): 0.0007254,
/// 0.0012564: over.
#[test]
fn the_lead_drift_is_judged_at_a_quarter_of_the_class_tolerance_in_both_unit_systems() {
    let mm = |z: &str| format!("G21 G99\nG0 X22. Z5.\nG92 X20. Z{z} F1.50004\nM30\n");
    let out = fanuc_to_haas(&mm("-750."), None).unwrap();
    assert!(out.contains("(threadcut: lead 1.50004 mm written as 1.5 mm drifts 0.0201328 mm over the thread's 755. mm, 0.034871 mm on the pitch diameter at cot 30°; limit 0.035 mm, a quarter of 6g's pitch-diameter tolerance for M20x1.5, ISO metric assumed from the 60° tool)\nG92 X20. Z-750. F1.5\n"), "{out}");
    let e = fanuc_to_haas(&mm("-760."), None).unwrap_err();
    assert_eq!(e.span.line, 3);
    assert!(e.message.contains("0.0353329 mm on the pitch diameter at cot 30°, beyond the limit 0.035 mm, a quarter of 6g's pitch-diameter tolerance for M20x1.5"), "{}", e.message);
    // --max-lead-drift moves the limit (the drift along the thread, the program's units).
    assert!(fanuc_to_haas(&mm("-760."), Some(0.0204)).is_ok());
    let e = fanuc_to_haas(&mm("-750."), Some(0.02)).unwrap_err();
    assert!(
        e.message
            .contains("beyond the limit 0.02 mm along the thread, the limit given"),
        "{}",
        e.message
    );

    let inch = |z: &str| format!("G20 G99\nG0 X.6 Z.2\nG92 X.5 Z{z} F.0769231\nM30\n");
    let out = fanuc_to_haas(&inch("-17.6"), None).unwrap();
    assert!(out.contains("0.0012425 inch on the pitch diameter at cot 30°; limit 0.00125 inch, a quarter of 2A's pitch-diameter tolerance for 0.5-13 UN, Unified inch assumed from the 60° tool and its lead, a whole number of threads per inch)\nG92 X0.5 Z-17.6 F0.07692\n"), "{out}");
    let e = fanuc_to_haas(&inch("-17.8"), None).unwrap_err();
    assert!(e.message.contains("drifts 0.0007254 inch over the thread's 18. inch, 0.0012564 inch on the pitch diameter at cot 30°, beyond the limit 0.00125 inch, a quarter of 2A's"), "{}", e.message);
    assert!(fanuc_to_haas(&inch("-17.8"), Some(0.00073)).is_ok());
    assert!(fanuc_to_haas(&inch("-17.6"), Some(0.0007)).is_err());
    // A negative limit is no length.
    let e = fanuc_to_haas(&inch("-1."), Some(-1.0)).unwrap_err();
    assert!(
        e.message.contains("expected a length of 0 or more"),
        "{}",
        e.message
    );
}

/// Issue 26's 1/2-13 UNC program: E13 (1/13") on Fanuc is F.07692, .0000031" short a turn; over
/// the thread's .95" (12.35 turns) .000038", .0000658" on the pitch diameter, a nineteenth of
/// the limit .00125": converted, the drift stated in a comment and a warning.
#[test]
fn the_half_inch_unc_example_converts_with_its_drift_stated() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/ab9-inch-p3-e.nc"),
    )
    .unwrap();
    let mut out = Vec::new();
    let report = convert::convert(
        text.as_bytes(),
        &mut out,
        &Machine::built_in("ab9").unwrap(),
        &Machine::built_in("fanuc").unwrap(),
        &Default::default(),
    )
    .unwrap();
    let out = String::from_utf8(out).unwrap();
    assert!(out.contains("(threadcut: lead 0.076923 inch written as 0.07692 inch drifts 0.000038 inch over the thread's 0.95 inch, 0.0000658 inch on the pitch diameter at cot 30°; limit 0.00125 inch"), "{out}");
    assert!(report
        .summary
        .warnings
        .iter()
        .any(|w| w.message.contains("0.0000658 inch on the pitch diameter")));
}

/// `post` states what its program relies on, for every lathe controller: the units (the code, or
/// for a control with one unit system its name), feed per revolution at the start and each
/// FEDRAT's mode before its F, X on diameter or radius where the control has a code for it —
/// never the control's power-on state. Every posted program reads back on its controller.
#[test]
fn posted_programs_state_units_and_feed_mode_for_every_controller() {
    use threadcut::dialect::lexicon::{Function, Plane};
    let cl = "UNITS/MM\nSPINDL/500,RPM,CLW\nRAPID\nGOTO/20,0,5\nFEDRAT/100,MMPM\nGOTO/18,0,5\nFEDRAT/0.2,MMPR\nGOTO/18,0,-20\nFINI\n";
    for (name, _) in BUILT_IN {
        let m = Machine::built_in(name).unwrap();
        let d = dialect::open(&m).unwrap();
        let lex = d.meanings();
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
fn lexicon_cell(lex: &threadcut::dialect::lexicon::Meanings, row: &str) -> String {
    use threadcut::dialect::lexicon::{
        DwellForm, Function as F, LimitForm, Plane, ReturnForm, ToolForm,
    };
    let codes = |fs: &[F]| -> String {
        let all: Vec<String> = fs
            .iter()
            .map(|f| {
                lex.entries()
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
            Some(DwellForm::XSecondsOrPMilliseconds) => {
                format!("{} X(s) P(ms)", codes(&[F::Dwell]))
            }
            Some(DwellForm::PSeconds) => format!("{} P(s)", codes(&[F::Dwell])),
            Some(DwellForm::PSecondsOrMilliseconds) => {
                format!("{} P(s.)/P(ms)", codes(&[F::Dwell]))
            }
            Some(DwellForm::FSeconds) => format!("{} F(s)", codes(&[F::Dwell])),
            None => "—".into(),
        },
        "set position" => codes(&[F::SetPosition, F::RestatePosition]),
        "spindle limit" => match lex.spindle_limit {
            Some(LimitForm::Code) => format!("{} S", codes(&[F::SpindleLimit])),
            Some(LimitForm::Setting(s)) => format!("{s}="),
            Some(LimitForm::OnSurfaceSpeed(l)) => {
                format!("{} … {}", codes(&[F::SurfaceSpeed]), l as char)
            }
            None => "—".into(),
        },
        "reference return" => match lex.reference {
            Some(ReturnForm::IncrementalWords { x, z }) => format!(
                "{} {}0 {}0{}",
                codes(&[F::ReferenceReturn]),
                x as char,
                z as char,
                if lex.return_all_without_axes {
                    " (bare: all)"
                } else {
                    ""
                }
            ),
            Some(ReturnForm::IncrementalMode) => format!(
                "{} {} X0 Z0, {}{}",
                codes(&[F::Incremental]),
                codes(&[F::ReferenceReturn]),
                codes(&[F::Absolute]),
                if lex.return_all_without_axes {
                    " (bare: all)"
                } else {
                    ""
                }
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
            .map(|d| lexicon_cell(&d.meanings(), row))
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

fn conv(src: &str, from: &str, to: &str) -> Result<String, threadcut::diag::Diagnostic> {
    convert::convert_text(
        src,
        &Machine::built_in(from).unwrap(),
        &Machine::built_in(to).unwrap(),
        &Default::default(),
    )
}

/// The converted program without its header (its comments and the block of modes).
fn body(text: &str) -> String {
    text.lines()
        .skip_while(|l| l.starts_with('%'))
        .skip_while(|l| l.starts_with("(threadcut") || l.starts_with("; threadcut"))
        .skip(1)
        .collect::<Vec<_>>()
        .join("\n")
}

/// Tools in each controller's form: (tool, offset) read from the source's, written in the target's.
#[test]
fn tools_are_rewritten_in_the_targets_form() {
    let src = "G0 X40. Z5.\nT0303\nT0102\nT0100\n";
    assert_eq!(
        body(&conv(src, "fanuc", "linuxcnc").unwrap()),
        "G0 X20. Z5.\nT3 M6 G43\nT1 M6 G43 H2\nT1 M6 G49"
    );
    // Sinumerik: the tool's first cutting edge is its own offset; D0 cancels it.
    assert_eq!(
        body(&conv("G0 X40. Z5.\nT0303\nT0300\n", "fanuc", "sinumerik").unwrap()),
        "G0 X40.000 Z5.000\nT3 D1\nT3 D0"
    );
    let e = conv(src, "fanuc", "sinumerik").unwrap_err();
    assert_eq!((e.span.line, e.span.column), (3, 1), "{}", e.message);
    assert!(e.message.contains("tool 1 with offset 2"), "{}", e.message);
    // LinuxCNC's T prepares, M6 changes, G43 applies: one Fanuc call.
    assert_eq!(
        body(&conv("G8\nG0 X20 Z5\nT3\nM6\nG43\nG49\n", "linuxcnc", "fanuc").unwrap()),
        "G0 X40. Z5.\nT0300\nT0303\nT0300"
    );
    // Sinumerik T7 D1 and Haas T505 are Fanuc's T0707 and T0505; OmniTurn's T4 is T0404.
    assert!(conv("N20 T7 D1\n", "sinumerik", "fanuc")
        .unwrap()
        .contains("\nN20 T0707\n"));
    assert!(conv("T505\n", "haas", "fanuc")
        .unwrap()
        .contains("\nT0505\n"));
    assert!(conv("T4\n", "omniturn", "fanuc")
        .unwrap()
        .contains("\nT0404\n"));
}

/// Dwells, spindle limits, surface speeds and units: each in the target's words.
#[test]
fn dwell_spindle_and_units_in_the_targets_words() {
    // Fanuc's G4 X (seconds) or P (milliseconds) is LinuxCNC's G4 P (seconds), Sinumerik's G4 F.
    let src = "G4 X1.5\nG4 P2500\n";
    assert_eq!(
        body(&conv(src, "fanuc", "linuxcnc").unwrap()),
        "G4 P1.5\nG4 P2.5"
    );
    assert_eq!(
        body(&conv(src, "fanuc", "sinumerik").unwrap()),
        "G4 F1.5\nG4 F2.5"
    );
    // The spindle limit: a code with S, a setting, or D on LinuxCNC's next G96.
    let src = "G50 S2000\nG96 S180 M3\n";
    assert_eq!(
        body(&conv(src, "fanuc", "fanuc-b").unwrap()),
        "G92 S2000\nG96 S180 M3"
    );
    assert_eq!(
        body(&conv(src, "fanuc", "sinumerik").unwrap()),
        "LIMS=2000\nG96 S180 M3"
    );
    assert_eq!(
        body(&conv(src, "fanuc", "linuxcnc").unwrap()),
        "(spindle limit 2000 rpm: written on the next constant-surface-speed block, if any)\nG96 D2000 S180 M3"
    );
    // Allen-Bradley has no spindle-limit word in threadcut's lexicon: a comment, and a faster
    // speed (or constant surface speed) after it is refused.
    let ab = conv("G50 S2000\nG97 S1500 M3\n", "fanuc", "ab9").unwrap();
    assert!(ab.contains("(spindle limit 2000 rpm not written"), "{ab}");
    let e = conv("G50 S2000\nG97 S2500 M3\n", "fanuc", "ab9").unwrap_err();
    assert_eq!((e.span.line, e.span.column), (2, 5), "{}", e.message);
    let e = conv("G50 S2000\nG96 S200 M3\n", "fanuc", "ab9").unwrap_err();
    assert_eq!(e.span.line, 2, "{}", e.message);
    // A surface speed stays in the program's units where the target has them.
    let css = conv("G21\nG96 S200\n", "fanuc", "linuxcnc").unwrap();
    assert!(css.ends_with("G21\nG96 S200\n"), "{css}");
    // Units switch where the target has them.
    let out = conv("G20\nG0 X1. Z0.5\nG21\nG0 X20. Z5.\n", "fanuc", "linuxcnc").unwrap();
    assert!(
        out.ends_with("G20\nG0 X0.5 Z0.5\nG21\nG0 X10. Z5.\n"),
        "{out}"
    );
}

/// Reference returns straight from the tool, set positions that change something, arcs by their
/// radius; comments and data lines in the target's style.
#[test]
fn positions_returns_arcs_and_comments() {
    // Haas's bare G28 returns every axis (its lexicon says so): Fanuc names both.
    assert_eq!(
        body(&conv("G28\n", "haas", "fanuc").unwrap()),
        "G28 U0. W0."
    );
    assert_eq!(
        body(&conv("G28 U0. W0.\n", "fanuc", "sinumerik").unwrap()),
        "G74 X1=0 Z1=0"
    );
    // A Fanuc G28 with no axis returns none: nothing to write.
    assert_eq!(body(&conv("G28\n", "fanuc", "haas").unwrap()), "");
    // An absolute intermediate point where the tool is counts as straight from it.
    assert_eq!(
        body(&conv("G0 X40. Z5.\nG28 X40.\n", "fanuc", "gsk980").unwrap()),
        "G0 X40. Z5.\nG28 U0."
    );
    // Setting the coordinates the tool already has is no change; others are written.
    assert_eq!(
        body(
            &conv(
                "G0 X40. Z5.\nG50 X40. Z5.\nG50 X50. Z5.\n",
                "fanuc",
                "linuxcnc"
            )
            .unwrap()
        ),
        "G0 X20. Z5.\nG92 X25. Z5."
    );
    // Arcs by radius; centre words are refused at the word.
    assert_eq!(
        body(&conv("G0 X20. Z0.\nG2 X24. Z-2. R2. F0.1\n", "fanuc", "linuxcnc").unwrap()),
        "G0 X10. Z0.\nG2 X12. Z-2. R2. F0.1"
    );
    let e = conv("G0 X20. Z0.\nG2 X24. Z-2. I2. K0\n", "fanuc", "linuxcnc").unwrap_err();
    assert_eq!((e.span.line, e.span.column), (2, 14));
    // Sinumerik's parameters become comments; their values are in the converted cycle.
    let out = conv(
        "R1=2 ; lead\nDEF REAL D=1.2\nT1 D1\nG0 X40 Z5\nCYCLE97(R1,,0,-20,30,30,2,2,D,0,0,0,4,0,1,1)\n",
        "sinumerik",
        "fanuc",
    )
    .unwrap();
    assert!(
        out.contains("\n(R1=2 ; lead)\n(DEF REAL D=1.2)\nT0101\n"),
        "{out}"
    );
    // A canned cycle other than threading is not converted.
    let e = conv("G0 X40. Z5.\nG90 X38. Z-20. F0.2\n", "fanuc", "linuxcnc").unwrap_err();
    assert!(
        e.message.contains("canned cycle other than threading"),
        "{}",
        e.message
    );
}

/// A program with control flow (subroutines, loops, parameters): the same profile keeps its text
/// as it is; a controller with a macro language (Custom Macro B, LinuxCNC's o-words) gets it with
/// its structure (tests/convert_macros.rs); another controller needs `--flatten`
/// (`program::Options::flatten`), which converts the executed program (the matrix reads each
/// such conversion back); without it the conversion stops at the program's first line of
/// control flow and says why (docs/translation.md, "Programs with control flow").
#[test]
fn programs_with_control_flow_need_flatten_where_the_target_has_no_macros() {
    const MACROS: [&str; 6] = ["fanuc", "fanuc15", "fanuc-b", "gsk980", "haas", "linuxcnc"];
    let mut seen = 0;
    for (name, controller, text) in examples() {
        let from = Machine::built_in(controller).unwrap();
        let run = program::run(text.as_bytes(), &from, |_, _| Ok(())).unwrap();
        let Some(line) = run.interpreted_from else {
            continue;
        };
        seen += 1;
        let header = format!("(threadcut convert: {controller} to {controller})\n");
        let same = convert::convert_text(&text, &from, &from, &Default::default()).unwrap();
        assert_eq!(same.replacen(&header, "", 1), text, "{name}");
        for (target, _) in BUILT_IN.iter().filter(|(t, _)| {
            *t != controller && !(MACROS.contains(t) && MACROS.contains(&controller))
        }) {
            let to = Machine::built_in(target).unwrap();
            let e = convert::convert_text(&text, &from, &to, &Default::default()).unwrap_err();
            assert_eq!(e.span.line, line, "{name} → {target}: {}", e.message);
            assert!(
                e.message
                    .contains(&format!("control flow from line {line} on"))
                    && e.message
                        .ends_with(&format!("does not rewrite for {target}")),
                "{name} → {target}: {}",
                e.message
            );
            assert!(e.hint.as_deref().unwrap_or("").contains("--flatten"));
        }
    }
    assert!(seen >= 5, "the bundled macro examples: {seen}");
    // Control flow from the first line on: the header still comes first (after a `%`).
    for src in ["#1=20\nG0 X#1 Z1.\nM30\n", "%\n#1=20\nG0 X#1 Z1.\nM30\n%\n"] {
        let same = conv(src, "fanuc", "fanuc").unwrap();
        let header = "(threadcut convert: fanuc to fanuc)\n";
        assert_eq!(
            same,
            match src.strip_prefix("%\n") {
                Some(rest) => format!("%\n{header}{rest}"),
                None => format!("{header}{src}"),
            }
        );
    }
    // The same macro language: Fanuc's loop for Haas keeps its loop, and with `--flatten` is
    // converted as executed.
    let loop_ = "G21 G99\nG0 X26. Z5.\n#5=1\nWHILE[#5LE3]DO1\nG92 X[24.-#5*0.3] Z-20. F1.5\n#5=#5+1\nEND1\nM30\n";
    assert_eq!(
        body(&conv(loop_, "fanuc", "haas").unwrap()),
        "G21 G99\nG0 X26. Z5.\n#5=1\nWHILE [#5 LE 3] DO1\nG92 X[24-#5*0.3] Z-20. F1.5\n#5=#5+1\nEND1\nM30"
    );
    let flat = convert::convert_text(
        loop_,
        &Machine::built_in("fanuc").unwrap(),
        &Machine::built_in("haas").unwrap(),
        &convert::Options {
            run: program::Options {
                flatten: true,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(
        body(&flat),
        "G21 G99\nG0 X26. Z5.\nG92 X23.7 Z-20. F1.5\nG92 X23.4 Z-20. F1.5\nG92 X23.1 Z-20. F1.5\nM30",
        "{flat}"
    );
}

/// The lines after the program's end are not run: for another controller its blank lines,
/// comments (in the target's form) and delimiters are kept, a line with words is an error
/// (nothing says what it means), and `--flatten`, which writes only what runs, leaves it out.
#[test]
fn lines_after_the_end_keep_their_comments_only() {
    let src = "G0 X20. Z5.\nM30\n\n(SPARE)\n%\n";
    assert_eq!(
        body(&conv(src, "fanuc", "sinumerik").unwrap()),
        "G0 X20.000 Z5.000\nM30\n\n; SPARE"
    );
    assert!(conv(src, "fanuc", "linuxcnc")
        .unwrap()
        .ends_with("M30\n\n(SPARE)\n%\n"));
    let after = "G0 X20. Z5.\nM30\nG0 X30.\n";
    let e = conv(after, "fanuc", "linuxcnc").unwrap_err();
    assert!(
        e.message.contains("`G0 X30.` follows the program's end"),
        "{}",
        e.message
    );
    let flat = convert::convert_text(
        after,
        &Machine::built_in("fanuc").unwrap(),
        &Machine::built_in("linuxcnc").unwrap(),
        &convert::Options {
            run: program::Options {
                flatten: true,
                ..Default::default()
            },
            ..Default::default()
        },
    )
    .unwrap();
    assert!(flat.ends_with("M30\n"), "{flat}");
}

fn first_lines(text: &str, n: usize) -> Vec<&str> {
    text.lines().take(n).collect()
}

/// A converted program is laid out as its target expects (issue 26): the delimiter `%` where the
/// target uses one, the program's number or name (Fanuc's O number is the first block after `%`:
/// "% / O0001(MEMORY CARD SAMPLE FILE) / G17 G49 G97 … / M30 / %", FANUC Series 16i/18i-TB
/// operator's manual B-63524EN/01, memory card file format), then the comment naming the
/// conversion and the block of stated modes; the end code as the source wrote it.
#[test]
fn programs_begin_with_their_number_then_the_stated_modes() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/fanuc-m30x2-g76.nc"),
    )
    .unwrap();
    let haas = conv(&text, "fanuc", "haas").unwrap();
    assert_eq!(
        first_lines(&haas, 4),
        [
            "%",
            "O0001 (M30x2 external thread, G76)",
            "(threadcut convert: fanuc to haas, mm, feed per revolution)",
            "G21 G18 G99 G97"
        ]
    );
    assert!(haas.ends_with("M30\n%\n"), "{haas}");
    // LinuxCNC numbers no programs (its o-words label subroutines): the number is a comment,
    // first after its `%`.
    let linuxcnc = conv(&text, "fanuc", "linuxcnc").unwrap();
    assert_eq!(
        first_lines(&linuxcnc, 4),
        [
            "%",
            "(program O0001; M30x2 external thread, G76)",
            "(threadcut convert: fanuc to linuxcnc, mm, feed per revolution)",
            "G21 G90 G8 G18 G95 G97"
        ]
    );
    assert!(linuxcnc.ends_with("M30\n%\n"), "{linuxcnc}");
    // Sinumerik names a program by its file: the number a comment, first; no `%`.
    let sinumerik = conv(&text, "fanuc", "sinumerik").unwrap();
    assert_eq!(
        first_lines(&sinumerik, 3),
        [
            "; program O0001; M30x2 external thread, G76",
            "; threadcut convert: fanuc to sinumerik, mm, feed per revolution",
            "G71 G90 DIAMON G18 G95 G97"
        ]
    );
    assert!(sinumerik.ends_with("M30\n"), "{sinumerik}");
    // The same profile: the program as it is, the comment after its number.
    let same = conv(&text, "fanuc", "fanuc").unwrap();
    assert_eq!(
        first_lines(&same, 3),
        [
            "%",
            "O0001 (M30x2 external thread, G76)",
            "(threadcut convert: fanuc to fanuc)"
        ]
    );
    // Sinumerik's name header first (a comment for Fanuc), then what the program states.
    let src = "%_N_TEST_MPF\n;$PATH=/_N_MPF_DIR\nG71\nG0 X20 Z5\nM2\n";
    let fanuc = conv(src, "sinumerik", "fanuc").unwrap();
    assert_eq!(
        first_lines(&fanuc, 4),
        [
            "(%_N_TEST_MPF)",
            "(threadcut convert: sinumerik to fanuc, mm, feed per minute)",
            "G21 G18 G98 G97",
            "($PATH=/_N_MPF_DIR)"
        ]
    );
    assert!(fanuc.ends_with("G0 X20. Z5.\nM2\n"), "{fanuc}");
    // A number on a block with words is that block: the modes come before it.
    let with_words = conv("O0005 G0 X20. Z5.\nM30\n", "fanuc", "haas").unwrap();
    assert_eq!(first_lines(&with_words, 3)[2], "O0005 G0 X20. Z5.");
}
