//! LinuxCNC programs run through LinuxCNC's own interpreter and through threadcut, compared move
//! for move (issue 13: "move-for-move identical to LinuxCNC's interpreter").
//!
//! The reference is LinuxCNC's standalone interpreter `rs274` (`rs274 -g in.ngc out.txt`, which
//! writes the canonical machining commands the interpreter issues). The test uses the program
//! named by the environment variable `THREADCUT_RS274` (a path that is not a file fails the test),
//! else `rs274` on the `PATH`; when neither is given it prints that it is skipped and passes
//! (machines without LinuxCNC). Checked with LinuxCNC 2.9.0~pre1 (Debian `linuxcnc-uspace`).
//! Reproduce:
//! `THREADCUT_RS274=/usr/bin/rs274 cargo test --test linuxcnc_reference -- --nocapture`.
//!
//! The corpus: `tests/data/linuxcnc-ref/*.ngc` (written for this test), every LinuxCNC example
//! `examples/linuxcnc-*.ngc` and the shop-style `tests/data/real/linuxcnc-*.ngc`. Programs that
//! LinuxCNC refuses are in `tests/data/linuxcnc-ref/bad/`: threadcut must refuse them too, with
//! LinuxCNC's message, on the line rs274 prints.
//!
//! How the canonical commands map onto threadcut's motion stream (`threadcut expand -c linuxcnc
//! --format jsonl`, [`program::expand_jsonl`]); every other canonical command is ignored:
//!
//! | rs274 canon | threadcut motion |
//! |---|---|
//! | `STRAIGHT_TRAVERSE(x, y, z, …)` | `rapid` to (x, z) |
//! | `STRAIGHT_FEED(x, y, z, …)` outside synchronisation | `feed` to (x, z) |
//! | `STRAIGHT_FEED` after `START_SPEED_FEED_SYNC(k, 0)`, before `STOP_SPEED_FEED_SYNCH()` | `thread` to (x, z) with lead k |
//! | `ARC_FEED(z, x, cz, cx, rotation, …)` (plane XZ: first axis Z, second X) | `arc` to (x, z) about (cx, cz), `cw` when rotation < 0 (the centre compared where threadcut's stream gives it: a turning cycle's arcs) |
//!
//! * Positions: canon X is the radius (also under G7, checked), in the program's units (after
//!   `USE_LENGTH_UNITS(CANON_UNITS_INCHES)` inches, checked with G20 programs), as is threadcut's
//!   stream. rs274 prints four decimals, so positions agree when they differ by less than
//!   0.6·10⁻⁴ program units (the fourth decimal, rounded).
//! * Leads: LinuxCNC's `k` is the travel per revolution along the move's path (G76's ramps run at
//!   `P·hypot(E,K)/E`); threadcut's stream gives the lead along the move's longer axis. The test
//!   converts threadcut's lead to the path (`lead · length / longer axis`, the start being the
//!   previous motion's end) and compares with rs274's six decimals (within 10⁻⁶).
//! * rs274 starts at the origin; threadcut's first move has an unknown start and a known end: only
//!   end points are compared, so that is the same.
//!
//! Known differences are listed in [`KNOWN`] with their reason; each is asserted to still differ,
//! so that a fix (or a LinuxCNC change) is noticed. docs/dialects/linuxcnc-macros.md, "Checked
//! against rs274", records the results.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use threadcut::machine::Machine;
use threadcut::program;

/// Programs where threadcut deliberately or knowingly differs from rs274, and why.
const KNOWN: &[(&str, &str)] = &[
    (
        "g7-on-the-g76-line.ngc",
        "deliberate (docs/dialects/linuxcnc-g76.md, Deviations): G7 on the G76 line makes LinuxCNC \
         halve I, J and K twice; threadcut halves them once, as the documentation says",
    ),
    (
        "g76-exact-landing.ngc",
        "deliberate (docs/dialects/linuxcnc-g76.md, Deviations): J·n^(1/R) lands on K but LinuxCNC's \
         strict `depth < K` in doubles cuts one pass 1e-16 short of K and then K; threadcut takes a \
         depth within 1e-9 mm of K as K and cuts one pass fewer",
    ),
    (
        "g28-reference.ngc",
        "threadcut's motion stream does not list G28's two rapids (to the intermediate point, then \
         to the reference point); without a [reference] table in the profile the position after \
         G28 is unknown, and the moves after it are the same",
    ),
    (
        "g71-fillet-chamfer.ngc",
        "threadcut does not read a G7x profile's corner fillets (A) and chamfers (C) yet and refuses \
         the block (docs/dialects/linuxcnc-turning.md, Differences)",
    ),
    (
        "quirk-break-then-do.ngc",
        "LinuxCNC interpreter quirk: a `break` of a while loop (executed, or only passed over when \
         the loop ends) leaves `doing_break` set, and the next do-while loop ends after one run; \
         threadcut follows the documentation (the do loop runs while its condition holds)",
    ),
    (
        "quirk-continue-then-repeat.ngc",
        "LinuxCNC interpreter quirk: `continue` in a do loop leaves `doing_continue` set, and the next \
         loop end reached while skipping (here the end of a repeat) loops back once more, so the \
         repeat body runs twice as often; threadcut follows the documentation",
    ),
    (
        "unclosed-while-ended-by-m2.ngc",
        "LinuxCNC never notices a while without endwhile when M2 inside its body ends the program; \
         threadcut refuses the unclosed loop when the run reaches it (docs/dialects/linuxcnc-macros.md)",
    ),
];

#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    Rapid,
    Feed,
    /// Synchronised, with the travel per revolution along the move's path.
    Thread(f64),
    /// A circular move, clockwise or not, about (cx radius, cz).
    Arc {
        cw: bool,
        cx: f64,
        cz: f64,
    },
}

#[derive(Clone, Copy, Debug)]
struct Motion {
    kind: Kind,
    x: f64,
    z: f64,
}

/// Positions: rs274 prints four decimals.
const POSITION_TOLERANCE: f64 = 0.6e-4;
/// Leads: rs274 prints six decimals.
const LEAD_TOLERANCE: f64 = 1e-6;

/// An error as rs274 reports it: the message and the block's text.
#[derive(Debug)]
struct Refusal {
    message: String,
    block: String,
}

fn rs274() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("THREADCUT_RS274") {
        // Asked for by name: a wrong path is a failure, not a skip.
        let p = PathBuf::from(p);
        assert!(p.is_file(), "THREADCUT_RS274={} is not a file", p.display());
        return Some(p);
    }
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|dir| dir.join("rs274"))
        .find(|p| p.is_file())
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn ngc_files(dir: &Path, prefix: &str) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "ngc")
                && p.file_name().unwrap().to_string_lossy().starts_with(prefix)
        })
        .collect();
    files.sort();
    files
}

fn number(s: &str) -> f64 {
    s.trim()
        .parse()
        .unwrap_or_else(|_| panic!("canon number {s:?}"))
}

static RS274: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Runs rs274 on `file`: its motions, or its error.
fn canon(rs274: &Path, file: &Path) -> Result<Vec<Motion>, Refusal> {
    canon_with(rs274, file, None)
}

/// [`canon`] with a tool table (`rs274 -t`): a converted program calls the source's tools by
/// number, which rs274's own small table does not hold; a machine's table would.
fn canon_with(rs274: &Path, file: &Path, tools: Option<&Path>) -> Result<Vec<Motion>, Refusal> {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("linuxcnc-ref");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join(format!(
        "{}.canon",
        file.file_stem().unwrap().to_string_lossy()
    ));
    // Two rs274 processes at once disturb each other (seen as empty refusals): one at a time.
    let _one_at_a_time = RS274.lock().unwrap_or_else(|e| e.into_inner());
    let mut command = Command::new(rs274);
    if let Some(t) = tools {
        command.arg("-t").arg(t);
    }
    let run = command
        .current_dir(&dir)
        .arg("-g")
        .arg(file)
        .arg(&out)
        .stdin(Stdio::null())
        .output()
        .unwrap_or_else(|e| panic!("cannot run {}: {e}", rs274.display()));
    if !run.status.success() {
        // stderr: "executing", the message, the block's text.
        let text = String::from_utf8_lossy(&run.stderr);
        let mut lines = text.lines().filter(|l| l.trim() != "executing");
        return Err(Refusal {
            message: lines.next().unwrap_or("").trim().to_string(),
            block: lines.next().unwrap_or("").trim().to_string(),
        });
    }
    let text = std::fs::read_to_string(&out).unwrap();
    Ok(parse_canon(&text))
}

/// The motions of rs274's canonical commands (the table in the header).
fn parse_canon(text: &str) -> Vec<Motion> {
    let mut motions = Vec::new();
    let mut sync: Option<f64> = None;
    for line in text.lines() {
        // "   14 N..... STRAIGHT_TRAVERSE(12.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)", the
        // second field the block's N number when it has one ("N30   ").
        let mut call = line.trim_start();
        for _ in 0..2 {
            call = call
                .split_once(char::is_whitespace)
                .map_or("", |(_, rest)| rest.trim_start());
        }
        let Some((name, rest)) = call.split_once('(') else {
            continue;
        };
        let args: Vec<&str> = rest.trim_end_matches(')').split(',').collect();
        match name {
            "START_SPEED_FEED_SYNC" => sync = Some(number(args[0])),
            "STOP_SPEED_FEED_SYNCH" => sync = None,
            "STRAIGHT_TRAVERSE" | "STRAIGHT_FEED" => motions.push(Motion {
                kind: match (name, sync) {
                    ("STRAIGHT_TRAVERSE", _) => Kind::Rapid,
                    (_, Some(lead)) => Kind::Thread(lead),
                    (_, None) => Kind::Feed,
                },
                x: number(args[0]),
                z: number(args[2]),
            }),
            "ARC_FEED" => motions.push(Motion {
                kind: Kind::Arc {
                    cw: number(args[4]) < 0.0,
                    cx: number(args[3]),
                    cz: number(args[2]),
                },
                x: number(args[1]),
                z: number(args[0]),
            }),
            // A motion this mapping does not know would go unnoticed: refuse it.
            other if is_unmapped_motion(other) => {
                panic!("canon motion {other} has no mapping in tests/linuxcnc_reference.rs")
            }
            _ => {}
        }
    }
    motions
}

/// Canonical commands that move the tool and are not in the mapping (rigid tapping, probing,
/// splines, NURBS): none of the corpus may use them.
fn is_unmapped_motion(name: &str) -> bool {
    ["FEED", "TRAVERSE", "PROBE", "TAP", "NURBS", "SPLINE"]
        .iter()
        .any(|m| name.contains(m))
        && !matches!(
            name,
            "SET_FEED_RATE"
                | "SET_FEED_MODE"
                | "SET_FEED_REFERENCE"
                | "ENABLE_FEED_OVERRIDE"
                | "DISABLE_FEED_OVERRIDE"
                | "START_SPEED_FEED_SYNC"
                | "STOP_SPEED_FEED_SYNCH"
                | "SET_TRAVERSE_RATE"
        )
}

/// threadcut's motion stream for `file`, leads converted to the path; or its error (message and
/// line).
fn threadcut(file: &Path) -> Result<Vec<Motion>, (String, u32)> {
    let text = std::fs::read(file).unwrap();
    motions_on(file, &text, "linuxcnc")
}

/// threadcut's motion stream of `text` read as `controller` reads it.
fn motions_on(file: &Path, text: &[u8], controller: &str) -> Result<Vec<Motion>, (String, u32)> {
    let machine = Machine::built_in(controller).unwrap();
    let mut out = Vec::new();
    match program::expand_jsonl(text, &mut out, &machine) {
        Ok(_) => {}
        Err(program::Error::Input(d)) => return Err((d.message, d.span.line)),
        Err(e) => panic!("{}: {e}", file.display()),
    }
    let mut motions: Vec<Motion> = Vec::new();
    for line in String::from_utf8(out).unwrap().lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        let (x, z) = (v["x"].as_f64().unwrap(), v["z"].as_f64().unwrap());
        let kind = match v["kind"].as_str().unwrap() {
            "rapid" => Kind::Rapid,
            "feed" => Kind::Feed,
            "arc" => Kind::Arc {
                cw: v["cw"].as_bool().unwrap(),
                // A plain G2/G3 block's arc is streamed without its centre (NaN: not compared).
                cx: v["cx"].as_f64().unwrap_or(f64::NAN),
                cz: v["cz"].as_f64().unwrap_or(f64::NAN),
            },
            "thread" => {
                let lead = v["lead"].as_f64().unwrap();
                Kind::Thread(match motions.last() {
                    Some(from) => path_lead(lead, x - from.x, z - from.z),
                    None => lead,
                })
            }
            other => panic!("{}: motion kind {other}", file.display()),
        };
        motions.push(Motion { kind, x, z });
    }
    Ok(motions)
}

/// A lead along the longer axis, as the travel per revolution along the move's path.
fn path_lead(lead: f64, dx: f64, dz: f64) -> f64 {
    let longer = dx.abs().max(dz.abs());
    if longer == 0.0 {
        lead
    } else {
        lead * dx.hypot(dz) / longer
    }
}

/// The first difference between the two motion lists, if any.
fn difference(reference: &[Motion], ours: &[Motion]) -> Option<String> {
    for (i, (r, o)) in reference.iter().zip(ours).enumerate() {
        let same_kind = match (r.kind, o.kind) {
            (Kind::Thread(a), Kind::Thread(b)) => (a - b).abs() <= LEAD_TOLERANCE,
            // Centres as positions are compared: at rs274's four decimals.
            (
                Kind::Arc { cw, cx, cz },
                Kind::Arc {
                    cw: cw2,
                    cx: cx2,
                    cz: cz2,
                },
            ) => {
                cw == cw2
                    && (cx2.is_nan() || (cx - cx2).abs() <= POSITION_TOLERANCE)
                    && (cz2.is_nan() || (cz - cz2).abs() <= POSITION_TOLERANCE)
            }
            (a, b) => a == b,
        };
        if !same_kind
            || (r.x - o.x).abs() > POSITION_TOLERANCE
            || (r.z - o.z).abs() > POSITION_TOLERANCE
        {
            return Some(format!("move {}: rs274 {r:?}, threadcut {o:?}", i + 1));
        }
    }
    (reference.len() != ours.len()).then(|| {
        format!(
            "rs274 has {} moves, threadcut {}",
            reference.len(),
            ours.len()
        )
    })
}

/// The outcome of one program.
enum Outcome {
    Same { moves: usize },
    Differs(String),
}

fn compare(rs274: &Path, file: &Path) -> Outcome {
    match (canon(rs274, file), threadcut(file)) {
        (Ok(reference), Ok(ours)) => match difference(&reference, &ours) {
            None => Outcome::Same {
                moves: reference.len(),
            },
            Some(d) => Outcome::Differs(d),
        },
        (Err(r), Ok(_)) => Outcome::Differs(format!(
            "rs274 refuses it ({} at {:?}), threadcut runs it",
            r.message, r.block
        )),
        (Ok(_), Err((message, line))) => Outcome::Differs(format!(
            "threadcut refuses it ({message} at line {line}), rs274 runs it"
        )),
        (Err(r), Err((message, line))) => Outcome::Differs(format!(
            "both refuse it: rs274 {:?} at {:?}, threadcut {message:?} at line {line}",
            r.message, r.block
        )),
    }
}

#[test]
fn linuxcnc_programs_move_for_move_as_rs274_runs_them() {
    let Some(rs274) = rs274() else {
        println!(
            "linuxcnc_reference: skipped (no rs274: set THREADCUT_RS274 or put rs274 on PATH)"
        );
        return;
    };
    let mut files = ngc_files(&root().join("tests/data/linuxcnc-ref"), "");
    files.extend(ngc_files(&root().join("examples"), "linuxcnc-"));
    files.extend(ngc_files(&root().join("tests/data/real"), "linuxcnc-"));
    assert!(files.len() >= 20, "the corpus has {} programs", files.len());
    let (mut programs, mut moves) = (0, 0);
    let mut failures = Vec::new();
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let known = KNOWN.iter().find(|(n, _)| *n == name);
        match (compare(&rs274, file), known) {
            (Outcome::Same { moves: n }, None) => {
                programs += 1;
                moves += n;
                println!("{name}: {n} moves identical");
            }
            (Outcome::Differs(d), Some((_, why))) => {
                println!("{name}: known difference ({why}): {d}");
            }
            (Outcome::Differs(d), None) => failures.push(format!("{name}: {d}")),
            (Outcome::Same { .. }, Some(_)) => failures.push(format!(
                "{name}: listed as a known difference but now identical: take it off KNOWN"
            )),
        }
    }
    println!(
        "linuxcnc_reference: {programs} programs, {moves} moves identical to {}; {} known differences",
        rs274.display(),
        KNOWN.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// rs274's moves without those of a reference return (`G28`) in the source: threadcut's stream
/// leaves a reference return out (where it ends is the machine's, known only from a profile's
/// `[reference]`), while rs274 runs it to its home, the origin (its default parameters
/// #5161–#5166 are 0), through the intermediate point. Left out: each rapid that ends at the
/// origin on the axes it moves (`G28 X0.` sends X alone), and the rapid before it when that one stayed where the tool was (`G91 G28 X0 Z0`'s
/// intermediate point).
fn without_reference_returns(source: &[u8], moves: Vec<Motion>) -> Vec<Motion> {
    if !String::from_utf8_lossy(source)
        .to_ascii_uppercase()
        .contains("G28")
    {
        return moves;
    }
    let near = |a: (f64, f64), b: (f64, f64)| {
        (a.0 - b.0).abs() <= POSITION_TOLERANCE && (a.1 - b.1).abs() <= POSITION_TOLERANCE
    };
    let mut kept: Vec<Motion> = Vec::new();
    // Where the tool is before each kept move, and whether the last kept move stayed there.
    let mut at = (0.0, 0.0);
    let mut stayed = false;
    for m in moves {
        let here = (m.x, m.z);
        // Home on the axes the return names (`G28 X0.` sends X alone).
        let home = near(here, (0.0, 0.0))
            || (near((here.0, 0.0), (0.0, 0.0)) && near((0.0, here.1), (0.0, at.1)))
            || (near((0.0, here.1), (0.0, 0.0)) && near((here.0, 0.0), (at.0, 0.0)));
        if m.kind == Kind::Rapid && home {
            // The return home; the intermediate point before it, where the tool already was.
            if stayed {
                kept.pop();
            }
            at = here;
            stayed = false;
            continue;
        }
        stayed = m.kind == Kind::Rapid && near(here, at);
        at = here;
        kept.push(m);
    }
    kept
}

/// Bundled programs whose filtered output LinuxCNC refuses, with its message and why.
const KNOWN_FILTER: &[(&str, &str, &str)] = &[(
    "gsk-g65-loop.nc",
    "Spindle not turning in G33",
    "the source never starts the spindle (started by hand on the GSK); LinuxCNC's interpreter \
     refuses a synchronised move with the spindle stopped: docs/linuxcnc-filter.md",
)];

/// The LinuxCNC program filter (`threadcut convert --filter --from C --to linuxcnc`, issue 26
/// item 7; docs/linuxcnc-filter.md): every bundled Fanuc-family, Haas, GSK and Sinumerik example
/// converted as the filter converts it (the library's `convert`; with `--flatten`, as the INI line
/// for macro programs reads), the result run through rs274, and its moves compared with
/// threadcut's reading of the source on its own controller. A program the conversion refuses
/// must be refused as something LinuxCNC's words cannot say (E009), never as an error.
#[test]
fn the_filters_output_runs_in_linuxcnc_as_its_source_reads() {
    let Some(rs274) = rs274() else {
        println!("linuxcnc filter: skipped (no rs274)");
        return;
    };
    let controller = |name: &str| -> Option<&'static str> {
        [
            ("fanuc15-", "fanuc15"),
            ("fanuc-b-", "fanuc-b"),
            ("fanuc-", "fanuc"),
            ("haas-", "haas"),
            ("gsk-", "gsk980"),
            ("sinumerik-", "sinumerik"),
        ]
        .iter()
        .find(|(p, _)| name.starts_with(p))
        .map(|(_, c)| *c)
    };
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("linuxcnc-filter");
    std::fs::create_dir_all(&dir).unwrap();
    // Tools 1 to 99 at zero offsets: the source programs' turret stations.
    let tools = dir.join("tools.tbl");
    let table: String = (1..100).map(|t| format!("T{t} P{t} X0 Z0 ;\n")).collect();
    std::fs::write(&tools, table).unwrap();
    let linuxcnc = Machine::built_in("linuxcnc").unwrap();
    let options = threadcut::convert::Options {
        run: program::Options {
            flatten: true,
            ..program::Options::default()
        },
        ..Default::default()
    };
    let (mut same, mut refused, mut failures) = (0, Vec::new(), Vec::new());
    let mut files: Vec<PathBuf> = std::fs::read_dir(root().join("examples"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_file())
        .collect();
    files.sort();
    for file in files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let Some(from) = controller(&name) else {
            continue;
        };
        let text = std::fs::read(&file).unwrap();
        let source = Machine::built_in(from).unwrap();
        let mut out = Vec::new();
        match threadcut::convert::convert(text.as_slice(), &mut out, &source, &linuxcnc, &options) {
            Ok(_) => {}
            Err(program::Error::Input(d)) => {
                assert_eq!(
                    d.code,
                    threadcut::diag::Code::Unsupported,
                    "{name}: not a limit of the target's: {}",
                    d.message
                );
                refused.push(format!("{name}: {}", d.message));
                continue;
            }
            Err(e) => panic!("{name}: {e}"),
        }
        let converted = dir.join(format!(
            "{}.ngc",
            file.file_stem().unwrap().to_string_lossy()
        ));
        std::fs::write(&converted, &out).unwrap();
        let ours = motions_on(&file, &text, from);
        let known = KNOWN_FILTER.iter().find(|(n, _, _)| *n == name);
        match (canon_with(&rs274, &converted, Some(&tools)), ours) {
            (Err(r), _) if known.is_some_and(|k| r.message == k.1) => {
                println!("{name}: rs274 refuses it as known ({})", known.unwrap().2);
            }
            (Ok(reference), Ok(ours)) => {
                match difference(&without_reference_returns(&text, reference), &ours) {
                    None => {
                        same += 1;
                        println!("{name} ({from}): {} moves identical in rs274", ours.len());
                    }
                    Some(d) => failures.push(format!("{name}: {d}")),
                }
            }
            (Err(r), _) => failures.push(format!(
                "{name}: rs274 refuses the filter's output: {} at {:?}",
                r.message, r.block
            )),
            (_, Err((m, l))) => failures.push(format!(
                "{name}: threadcut refuses the source: {m} at line {l}"
            )),
        }
    }
    for r in &refused {
        println!("refused: {r}");
    }
    println!(
        "linuxcnc filter: {same} programs move for move, {} refused",
        refused.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(same >= 8, "only {same} programs compared");
}

/// Programs both refuse, where threadcut's message or line knowingly differs from rs274's.
const KNOWN_REFUSALS: &[(&str, &str)] = &[(
    "unclosed-while.ngc",
    "LinuxCNC reads on to the end of the file and says \"File ended with no percent sign or program \
     end\" at the last line; threadcut names the loop at its while line \
     (\"o10 while has no o10 endwhile\", docs/dialects/linuxcnc-macros.md)",
)];

/// rs274's message made comparable, and the line it names when the message names one.
///
/// * `N: text` (o-word errors carry the line's sequence number): the text, line N.
/// * `EOF in file:PATH seeking o-word: o<x> from line: N`: threadcut's library does not know the
///   file's name, so `in file:PATH ` is left out; the line is N (rs274 prints the last line read).
fn comparable(message: &str) -> (String, Option<u32>) {
    if let Some((n, rest)) = message.split_once(": ") {
        if let Ok(n) = n.parse::<u32>() {
            return (rest.to_string(), Some(n));
        }
    }
    if let (Some(start), Some(seek)) = (message.find("in file:"), message.find(" seeking o-word")) {
        let line = message
            .rsplit_once("from line: ")
            .and_then(|(_, n)| n.trim().parse().ok());
        return (
            format!("{}{}", &message[..start].trim_end(), &message[seek..]),
            line,
        );
    }
    (message.to_string(), None)
}

/// The line numbers of `file` whose text (blanks aside) is `block`.
fn lines_holding(file: &Path, block: &str) -> Vec<u32> {
    let squeeze = |s: &str| s.split_whitespace().collect::<String>();
    let block = squeeze(block);
    std::fs::read_to_string(file)
        .unwrap()
        .lines()
        .enumerate()
        .filter(|(_, l)| squeeze(l) == block)
        .map(|(i, _)| i as u32 + 1)
        .collect()
}

/// Whether threadcut's refusal is rs274's: the same message (blanks aside) on the same line.
fn same_refusal(file: &Path, refusal: &Refusal, message: &str, line: u32) -> bool {
    let squeeze = |s: &str| s.split_whitespace().collect::<String>();
    let (theirs, their_line) = comparable(&refusal.message);
    let lines = match their_line {
        Some(n) => vec![n],
        None => lines_holding(file, &refusal.block),
    };
    squeeze(message).contains(&squeeze(&theirs)) && lines.contains(&line)
}

#[test]
fn programs_linuxcnc_refuses_are_refused_with_its_message_on_its_line() {
    let Some(rs274) = rs274() else {
        println!(
            "linuxcnc_reference: skipped (no rs274: set THREADCUT_RS274 or put rs274 on PATH)"
        );
        return;
    };
    let files = ngc_files(&root().join("tests/data/linuxcnc-ref/bad"), "");
    assert!(files.len() >= 10, "{} bad programs", files.len());
    let mut failures = Vec::new();
    let mut same = 0;
    for file in &files {
        let name = file.file_name().unwrap().to_string_lossy().into_owned();
        let known = KNOWN_REFUSALS.iter().find(|(n, _)| *n == name);
        let refusal = match canon(&rs274, file) {
            Err(r) => r,
            Ok(_) => {
                failures.push(format!("{name}: rs274 runs it"));
                continue;
            }
        };
        let (message, line) = match threadcut(file) {
            Ok(_) => {
                failures.push(format!(
                    "{name}: threadcut runs it; rs274: {:?}",
                    refusal.message
                ));
                continue;
            }
            Err(e) => e,
        };
        let what = format!(
            "rs274 {:?} at {:?}, threadcut {message:?} at line {line}",
            refusal.message, refusal.block
        );
        match (same_refusal(file, &refusal, &message, line), known) {
            (true, None) => {
                same += 1;
                println!("{name}: both refuse it: {message:?} at line {line}");
            }
            (false, Some((_, why))) => println!("{name}: known difference ({why}): {what}"),
            (false, None) => failures.push(format!("{name}: {what}")),
            (true, Some(_)) => failures.push(format!(
                "{name}: listed in KNOWN_REFUSALS but now the same: take it off"
            )),
        }
    }
    println!(
        "linuxcnc_reference: {same} refused programs with rs274's message and line; {} known differences",
        KNOWN_REFUSALS.len()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn rs274_messages_are_made_comparable() {
    assert_eq!(
        comparable("4: no matching while/do label: '  o1 break' (found 'if' in line 3)"),
        (
            "no matching while/do label: '  o1 break' (found 'if' in line 3)".to_string(),
            Some(4)
        )
    );
    assert_eq!(
        comparable("EOF in file:/a/b.ngc seeking o-word: o<missing> from line: 4"),
        (
            "EOF seeking o-word: o<missing> from line: 4".to_string(),
            Some(4)
        )
    );
    assert_eq!(
        comparable("Attempt to divide by zero"),
        ("Attempt to divide by zero".to_string(), None)
    );
}

#[test]
fn canon_lines_map_onto_motions() {
    let text = "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_MM)\n\
   12 N..... STRAIGHT_TRAVERSE(12.0000, 0.0000, 5.0000, 0.0000, 0.0000, 0.0000)\n\
   13 N..... SET_FEED_RATE(100.0000)\n\
   14 N..... STRAIGHT_FEED(11.0000, 0.0000, 4.0000, 0.0000, 0.0000, 0.0000)\n\
   15 N..... START_SPEED_FEED_SYNC(1.705680,0)\n\
   16 N..... STRAIGHT_FEED(10.6380, 0.0000, -39.8586, 0.0000, 0.0000, 0.0000)\n\
   17 N..... STOP_SPEED_FEED_SYNCH()\n\
   18 N..... ARC_FEED(-2.0000, 7.0000, 0.0000, 7.0000, -1, 0.0000, 0.0000, 0.0000, 0.0000)\n\
   19 N..... ARC_FEED(-4.0000, 9.0000, -4.0000, 7.0000, 1, 0.0000, 0.0000, 0.0000, 0.0000)\n\
   20 N30    STRAIGHT_TRAVERSE(10.0000, 0.0000, 2.0000, 0.0000, 0.0000, 0.0000)\n";
    let m = parse_canon(text);
    let kinds: Vec<Kind> = m.iter().map(|m| m.kind).collect();
    assert_eq!(
        kinds,
        [
            Kind::Rapid,
            Kind::Feed,
            Kind::Thread(1.70568),
            Kind::Arc {
                cw: true,
                cx: 7.0,
                cz: 0.0
            },
            Kind::Arc {
                cw: false,
                cx: 7.0,
                cz: -4.0
            },
            Kind::Rapid
        ]
    );
    assert_eq!((m[5].x, m[5].z), (10.0, 2.0));
    assert!(is_unmapped_motion("RIGID_TAP"));
    assert!(is_unmapped_motion("STRAIGHT_PROBE"));
    assert!(!is_unmapped_motion("SET_FEED_RATE"));
    assert!(!is_unmapped_motion("START_SPEED_FEED_SYNC"));
    assert_eq!((m[2].x, m[2].z), (10.638, -39.8586));
    assert_eq!((m[3].x, m[3].z), (7.0, -2.0));
    // A 45° ramp with 1.5 along Z per revolution travels 1.5·√2 along its path.
    assert!((path_lead(1.5, 1.5, -1.5) - 1.5 * 2f64.sqrt()).abs() < 1e-12);
    assert_eq!(path_lead(1.5, 0.0, 0.0), 1.5);
}
