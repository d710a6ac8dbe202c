//! A cycle on its own: a threading cycle shown without the lines that position the tool (training
//! pages, manuals, forum answers). Its pass table is read where it does not depend on the start
//! point (`program::Start::Unstated`, what `passes` runs with); what depends on it is stated not
//! known; a cycle whose passes depend on the start refuses with the reason; `Start::At` places
//! the tool before the first line. Decisions: docs/cli.md, "A cycle on its own".

use threadcut::check::Source;
use threadcut::commands;
use threadcut::diag::{Code, Diagnostic};
use threadcut::machine::Machine;
use threadcut::program::{self, Start};
use threadcut::thread::PassKind;
use threadcut::threads::{self, Thread};

fn machine(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

fn threads_with(name: &str, src: &str, start: Start) -> Result<Vec<Thread>, program::Error> {
    let m = machine(name);
    let options = program::Options {
        start,
        ..program::Options::default()
    };
    let mut found = Vec::new();
    commands::each_thread(src.as_bytes(), Source::Gcode(&m), &options, |t| {
        found.push(t);
        Ok(())
    })?;
    Ok(found)
}

#[track_caller]
fn alone(name: &str, src: &str) -> Vec<Thread> {
    threads_with(name, src, Start::Unstated).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

#[track_caller]
fn refused(name: &str, src: &str, start: Start) -> Diagnostic {
    match threads_with(name, src, start) {
        Err(program::Error::Input(d)) => d,
        Err(e) => panic!("expected an input error, got {e}"),
        Ok(t) => panic!("expected an input error, got {} threads", t.len()),
    }
}

#[track_caller]
fn close(got: f64, want: f64, what: &str) {
    // The program's resolution is 0.001 mm; the expected values are rounded to 0.00001.
    assert!((got - want).abs() < 1e-5, "{what}: {got} != {want}");
}

/// Haas's one-block G76 on its own, in mm. Haas P1 (the default: one edge, constant amount):
/// the depth of pass n from the crest is d_n = D·√n, D = 0.485, until the next would pass the
/// thread height K = 1.534, which the last pass cuts:
///   d1 = 0.485, d2 = 0.485·√2 = 0.68589, d3 = 0.84004, d4 = 0.97000, d5 = 1.08449,
///   d6 = 1.18800, d7 = 1.28319, d8 = 1.37179, d9 = 1.45500, d10 = 0.485·√10 = 1.53370,
///   (d11 = 0.485·√11 = 1.60857 > 1.534) → pass 11 at 1.534.
/// X of each pass (diameter) = X + 2·(K − d_n): pass 1 = 16.93 + 2·1.049 = 19.028, pass 4 =
/// 16.93 + 2·0.564 = 18.058, pass 11 = 16.93. The chip of a 60° sharp V between depths a < b is
/// tan 30°·(b² − a²): every pass but the last tan 30°·D² = 0.57735·0.235225 = 0.13581; the last
/// 0.57735·(1.534² − 10·0.235225) = 0.57735·(2.353156 − 2.35225) = 0.00052.
#[test]
fn haas_one_block_g76_on_its_own() {
    let t = alone("haas", "G21\nG76 X16.93 Z-25. K1.534 D.485 F2.5\n");
    assert_eq!(t.len(), 1);
    let t = &t[0];
    assert_eq!(t.unknown_start, [true, true]);
    let p = &t.passes;
    assert_eq!(p.len(), 11);
    assert!(p.iter().all(|p| p.kind == PassKind::Rough));
    let want = [
        0.485, 0.68589, 0.84004, 0.97, 1.08449, 1.188, 1.28319, 1.37179, 1.455, 1.5337, 1.534,
    ];
    for (pass, d) in p.iter().zip(want) {
        close(pass.depth, d, &format!("depth of pass {}", pass.n));
        // X as the program writes it (diameter): X + 2·(K − d).
        close(
            pass.start.x * 2.0,
            16.93 + 2.0 * (1.534 - d),
            "X of the pass",
        );
    }
    for pass in &p[..10] {
        close(pass.area, 0.13581, "a constant-amount pass's chip");
    }
    close(p[10].area, 0.00052, "the last pass's chip");
    // Monotonic depths, the last at the thread height.
    assert!(p.windows(2).all(|w| w[1].depth > w[0].depth));
    close(p[10].depth, t.job.geometry.depth, "last pass at K");
}

/// The table does not depend on the start: with the start given, every depth, X and chip is the
/// same; only the Z where each pass starts becomes known.
#[test]
fn the_table_is_the_one_a_given_start_gives() {
    let src = "G21\nG76 X16.93 Z-25. K1.534 D.485 F2.5\n";
    let given = threads_with("haas", src, Start::At { x: 22.0, z: 5.0 }).unwrap();
    let unstated = alone("haas", src);
    assert_eq!(given[0].unknown_start, [false, false]);
    assert!(given[0].start_note().is_none());
    assert_eq!(given[0].passes.len(), unstated[0].passes.len());
    for (g, u) in given[0].passes.iter().zip(&unstated[0].passes) {
        close(g.depth, u.depth, "depth");
        close(g.increment, u.increment, "increment");
        close(g.start.x, u.start.x, "X");
        close(g.area, u.area, "chip");
        close(g.offset, u.offset, "lateral offset");
        // Known now: the Z where the pass starts is the given start's and the pass's offset. The
        // start is in the units at power-on, before the program's G21: Haas's profile is inch,
        // so Z5 is 5·25.4 = 127 mm.
        close(g.start.z, 127.0 + g.offset, "Z where the pass starts");
    }
}

/// Fanuc's two-block G76 on its own. P020060: two finishing passes, 60°; Q100: the least cut
/// Δdmin = 0.1; R0.05: the finishing allowance; P1227: K = 1.227; Q400: Δd = 0.4. Rough passes
/// at Δd·√n down to K − R = 1.177, each at least Δdmin deeper than the last:
///   0.4, 0.4·√2 = 0.56569, 0.4·√3 = 0.69282, 0.4·√4 = 0.8; 0.4·√5 = 0.89443 is less than
///   0.8 + 0.1 → 0.9; 0.4·√6 = 0.97980 < 1.0 → 1.0; 0.4·√7 = 1.05830 < 1.1 → 1.1;
///   0.4·√8 = 1.13137 < 1.2 → 1.2, beyond 1.177 → 1.177; then two finishing passes at 1.227.
/// X of pass 1 (diameter) = 27.546 + 2·(1.227 − 0.4) = 29.2.
#[test]
fn fanuc_two_block_g76_on_its_own() {
    let t = alone(
        "fanuc",
        "G76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n",
    );
    let t = &t[0];
    assert_eq!(t.unknown_start, [true, true]);
    let want = [
        0.4, 0.56569, 0.69282, 0.8, 0.9, 1.0, 1.1, 1.177, 1.227, 1.227,
    ];
    assert_eq!(t.passes.len(), want.len());
    for (pass, d) in t.passes.iter().zip(want) {
        close(pass.depth, d, &format!("depth of pass {}", pass.n));
    }
    assert_eq!(t.passes[8].kind, PassKind::Finish);
    close(t.passes[0].start.x * 2.0, 29.2, "X of pass 1");
    let json = threads::passes_json(t, None);
    let rows = json["passes"].as_array().unwrap();
    assert!(rows.iter().all(|r| r["z"].is_null()), "{json}");
    close(rows[0]["x"].as_f64().unwrap(), 29.2, "x of the first row");
    assert_eq!(json["start_unknown"]["axes"], serde_json::json!(["X", "Z"]));
    let note = json["start_unknown"]["note"].as_str().unwrap();
    assert!(note.contains("the Z where each pass starts"), "{note}");
    assert!(note.contains("--start X,Z"), "{note}");
}

/// GSK's G92 series on its own: the X of each pass is programmed. Depths from the first pass
/// (radius): (19.2 − X)/2 = 0, 0.3, 0.5, 0.65, 0.75.
#[test]
fn gsk_g92_series_on_its_own() {
    let t = alone(
        "gsk980",
        "G92 X19.2 Z-25. F2.5\nX18.6\nX18.2\nX17.9\nX17.7\nM30\n",
    );
    assert_eq!(t.len(), 1, "one thread of five passes");
    let t = &t[0];
    assert_eq!(t.unknown_start, [true, true]);
    let xs = [19.2, 18.6, 18.2, 17.9, 17.7];
    assert_eq!(t.passes.len(), xs.len());
    for (pass, x) in t.passes.iter().zip(xs) {
        close(pass.start.x * 2.0, x, "X of the pass as programmed");
        close(pass.depth, (19.2 - x) / 2.0, "depth from the first pass");
    }
}

/// Only Z not known (the tool placed on X): the side is known, Z is not.
#[test]
fn only_the_unknown_axis_is_stated() {
    let t = alone("fanuc15", "G0 X22.\nG76 X16.93 Z-25. K1.534 D.485 F2.5\n");
    assert_eq!(t[0].unknown_start, [false, true]);
    let note = t[0].start_note().unwrap();
    assert!(note.contains("the tool's Z before the cycle"), "{note}");
    assert!(!note.contains("external"), "{note}");
}

/// Two cycles on their own: the first ends where it started, which is not known either.
#[test]
fn a_cycle_after_a_cycle_on_its_own() {
    let t = alone(
        "fanuc15",
        "G76 X16.93 Z-25. K1.534 D.485 F2.5\nG76 X16.93 Z-25. K1.534 D.3 F2.5\n",
    );
    assert_eq!(t.len(), 2);
    assert!(t.iter().all(|t| t.unknown_start == [true, true]));
    close(t[1].passes[0].depth, 0.3, "the second cycle's first depth");
}

/// An end point counted from the start (U, W) depends on it: refused, naming the word.
#[test]
fn an_incremental_end_needs_the_start() {
    let d = refused("gsk980", "G92 U-3. Z-25. F2.5\n", Start::Unstated);
    assert_eq!(d.code, Code::UnknownPosition);
    assert_eq!((d.span.line, d.span.column), (1, 5));
    assert!(
        d.message.contains("U counts from the cycle's start point"),
        "{}",
        d.message
    );
}

/// LinuxCNC's G76 places every pass from its drive line, which starts where the tool is: no table
/// without it, and the refusal says why.
#[test]
fn linuxcnc_g76_refuses_with_its_reason() {
    let d = refused(
        "linuxcnc",
        "G7 G21\nM3 S500\nG76 P2.5 Z-30 I-1.0 J0.3 K1.5335\n",
        Start::Unstated,
    );
    assert_eq!(d.code, Code::UnknownPosition);
    assert_eq!(d.span.line, 3);
    assert!(d.message.contains("drive line"), "{}", d.message);
    let hint = d.hint.unwrap_or_default();
    assert!(hint.contains("no pass table"), "{hint}");
    assert!(hint.contains("--start X,Z"), "{hint}");
}

/// Without `Unstated` (expand, plot, check) a cycle on its own is refused as before, and the
/// hint says how to give the start.
#[test]
fn expand_and_check_still_need_the_start() {
    let src = "G76 X16.93 Z-25. K1.534 D.485 F2.5\n";
    let d = refused("fanuc15", src, Start::Unknown);
    assert!(
        d.message.contains("the tool's X and Z are not known here"),
        "{}",
        d.message
    );
    assert!(d.hint.unwrap_or_default().contains("--start X,Z"));
    let m = machine("fanuc15");
    let mut out = Vec::new();
    let opts = program::Options {
        start: Start::At { x: 22.0, z: 5.0 },
        ..program::Options::default()
    };
    program::expand_jsonl_with(src.as_bytes(), &mut out, &m, &opts).unwrap();
    let text = String::from_utf8(out).unwrap();
    // The first move leaves the start for pass 1: X 19.028 diameter = 9.514 radius, at Z5 plus
    // the flank infeed's shift (P1, A60: the pass rides the flank, (K − d1)·tan 30° =
    // 1.049·0.57735 = 0.60564 toward the start side).
    let first: serde_json::Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    close(first["x"].as_f64().unwrap(), 9.514, "X of pass 1 (radius)");
    close(first["z"].as_f64().unwrap(), 5.60564, "Z of pass 1");
}

/// Allen-Bradley's G78 on its own (the shared one-block lowering, as FS15's and Haas's G76): the
/// bundled M10x1.5 (K0.92, D0.35, P1), whose depths are D·√n: 0.35, 0.35·√2 = 0.49497,
/// 0.35·√3 = 0.60622, 0.7; the X of pass 1 (diameter) = 8.16 + 2·(0.92 − 0.35) = 9.3. The table
/// is the one its start (X12 Z5, the example's) gives, but for the Z where each pass starts.
#[test]
fn allen_bradley_g78_on_its_own() {
    let src = "G21\nG78 X8.16 Z-20. K0.92 D0.35 F1.5 A60 P1\nM30\n";
    let t = &alone("ab9", src)[0];
    assert_eq!(t.unknown_start, [true, true]);
    for (p, d) in t.passes.iter().zip([0.35, 0.49497, 0.60622, 0.7]) {
        close(p.depth, d, "depth");
    }
    let rows = program::pass_rows(&t.job, &t.passes, t.diameter_x);
    close(rows[0].x, 9.3, "X of pass 1");
    // Inch at power-on (the profile's units): X12 Z5 in the example are mm after its G21, so the
    // start is given as 12/25.4, 5/25.4 in.
    let given = threads_with(
        "ab9",
        src,
        Start::At {
            x: 12.0 / 25.4,
            z: 5.0 / 25.4,
        },
    )
    .unwrap();
    assert_eq!(given[0].passes.len(), t.passes.len());
    for (g, u) in given[0].passes.iter().zip(&t.passes) {
        close(g.depth, u.depth, "depth");
        close(g.start.x, u.start.x, "X");
        close(g.area, u.area, "chip");
    }
}
