//! Programs in several files (issue 25, items 2 and 5): a call to a program the file does not
//! hold finds it in the include directories (`tests/data/multifile/`), in the dialect's file
//! names; findings inside a called file name that file and line and the call; a file not found
//! names every path tried. The LinuxCNC program is compared move for move with LinuxCNC's own
//! interpreter `rs274`, which finds the subroutine file through an INI's
//! `[RS274NGC]SUBROUTINE_PATH` (skipped, saying so, where rs274 is not installed).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use threadcut::diag::{Code, Diagnostic, FILE_SPACING};
use threadcut::interp::library::{Dirs, Library, Provided};
use threadcut::machine::Machine;
use threadcut::program::{self, Options};

fn data(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/multifile")
        .join(path)
}

fn options(dirs: &[&str]) -> Options {
    Options {
        library: Some(Library::new(Dirs::new(
            dirs.iter().map(|d| data(d)).collect(),
        ))),
        ..Options::default()
    }
}

/// A motion of `expand --format jsonl`: kind, x (radius), z, lead, source line.
#[derive(Debug, PartialEq)]
struct Move {
    kind: String,
    x: f64,
    z: f64,
    lead: Option<f64>,
    line: u64,
}

fn run(controller: &str, main: &str, options: &Options) -> Result<Vec<Move>, Diagnostic> {
    let text = std::fs::read(data(main)).unwrap();
    let machine = Machine::built_in(controller).unwrap();
    let mut out = Vec::new();
    match program::expand_jsonl_with(text.as_slice(), &mut out, &machine, options) {
        Ok(_) => {}
        Err(program::Error::Input(d)) => return Err(d),
        Err(e) => panic!("{main}: {e}"),
    }
    Ok(String::from_utf8(out)
        .unwrap()
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            Move {
                kind: v["kind"].as_str().unwrap().to_string(),
                x: v["x"].as_f64().unwrap(),
                z: v["z"].as_f64().unwrap(),
                lead: v["lead"].as_f64(),
                line: v["line"].as_u64().unwrap(),
            }
        })
        .collect())
}

/// The thread moves: (x radius, z end, lead), compared at the program's resolution (0.001 mm,
/// 0.0001 in).
fn threads(moves: &[Move]) -> Vec<(f64, f64, f64)> {
    moves
        .iter()
        .filter(|m| m.kind == "thread")
        .map(|m| (m.x, m.z, m.lead.unwrap()))
        .collect()
}

fn assert_near(got: &[(f64, f64, f64)], want: &[(f64, f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len(), "{got:?} against {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g.0 - w.0).abs() < tol && (g.1 - w.1).abs() < tol && (g.2 - w.2).abs() < tol,
            "{got:?} against {want:?}"
        );
    }
}

/// The three passes of the M20x2 programs: diameters 19.4, 19.0, 18.7 are radii 9.7, 9.5, 9.35,
/// each to Z-20 at lead 2.
const M20_PASSES: [(f64, f64, f64); 3] = [(9.7, -20.0, 2.0), (9.5, -20.0, 2.0), (9.35, -20.0, 2.0)];

#[test]
fn fanuc_m98_runs_o9010_from_its_own_file() {
    let moves = run("fanuc", "fanuc/main-m98.nc", &options(&["fanuc/lib"])).unwrap();
    assert_near(&threads(&moves), &M20_PASSES, 1e-3);
    // Each pass: rapid to the diameter, the thread, out to X22 (radius 11), back to Z5 — lines
    // 3 to 6 of O9010.nc; the main program's last move is its line 13.
    let lines: Vec<u64> = moves.iter().map(|m| m.line).collect();
    assert_eq!(lines, [6, 3, 4, 5, 6, 3, 4, 5, 6, 3, 4, 5, 6, 13]);
    assert_eq!((moves[4].x, moves[4].z), (11.0, 5.0));
}

#[test]
fn without_an_include_directory_the_call_is_not_found() {
    let d = run("fanuc", "fanuc/main-m98.nc", &Options::default()).unwrap_err();
    assert_eq!(
        (d.code, d.span.line, d.span.file()),
        (Code::MissingWord, 8, 0)
    );
    assert!(
        d.message.contains("O9010 is not in the file"),
        "{}",
        d.message
    );
}

#[test]
fn fanuc_g65_passes_its_arguments_to_a_file_named_by_digits() {
    // G65 P9011 A19.4 B-20. F2.: #1 = 19.4, #2 = -20, #9 = 2 in O9011 (9011.nc).
    let moves = run("fanuc", "fanuc/main-g65.nc", &options(&["fanuc/lib"])).unwrap();
    assert_near(&threads(&moves), &M20_PASSES, 1e-3);
}

#[test]
fn haas_m98_finds_its_five_digit_program_in_any_case() {
    // O01234 is stored as `o01234.NC`; #100 = 0.96 and 0.94 in are radii 0.48 and 0.47, to
    // Z-0.75 at lead 0.0769 in.
    let moves = run("haas", "haas/main.nc", &options(&["haas/lib"])).unwrap();
    assert_near(
        &threads(&moves),
        &[(0.48, -0.75, 0.0769), (0.47, -0.75, 0.0769)],
        1e-4,
    );
}

#[test]
fn linuxcnc_call_reads_name_ngc() {
    let moves = run("linuxcnc", "linuxcnc/main.ngc", &options(&["linuxcnc/lib"])).unwrap();
    assert_near(&threads(&moves), &M20_PASSES, 1e-3);
}

#[test]
fn include_directories_are_searched_in_order() {
    // errors/lib has no O9010; fanuc/lib, searched next, has it.
    let moves = run(
        "fanuc",
        "fanuc/main-m98.nc",
        &options(&["errors/lib", "fanuc/lib"]),
    )
    .unwrap();
    assert_eq!(threads(&moves).len(), 3);
}

#[test]
fn a_missing_file_names_every_path_tried() {
    let d = run(
        "fanuc",
        "errors/missing.nc",
        &options(&["errors/lib", "fanuc/lib"]),
    )
    .unwrap_err();
    assert_eq!(
        (d.code, d.span.line, d.span.column),
        (Code::MissingWord, 4, 5)
    );
    assert!(
        d.message
            .contains("program O9020 is not in the file nor in the include directories"),
        "{}",
        d.message
    );
    let hint = d.hint.unwrap();
    for dir in ["errors/lib", "fanuc/lib"] {
        for name in ["O9020", "O9020.nc", "O09020.nc", "9020.nc", "9020.tap"] {
            let path = data(dir).join(name).display().to_string();
            assert!(hint.contains(&path), "{path} not in {hint}");
        }
    }
}

#[test]
fn an_error_inside_a_called_file_names_it_and_the_call() {
    let lib = Library::new(Dirs::new(vec![data("errors/lib")]));
    let opts = Options {
        library: Some(lib.clone()),
        ..Options::default()
    };
    let d = run("fanuc", "errors/bad-inside.nc", &opts).unwrap_err();
    // `G32 Z[-20.*] F2.`: the `]` at column 12 of line 3 of O9030.nc, the first file read.
    assert_eq!((d.code, d.span.line, d.span.column), (Code::Syntax, 3, 12));
    assert_eq!(d.span.file(), 1);
    let (name, text) = lib.0.source(1).unwrap();
    assert!(name.ends_with("O9030.nc"), "{name}");
    let at = (d.span.start - FILE_SPACING) as usize;
    assert_eq!(text[at], b']');
    // Called from line 5 of the main program (file 0).
    assert_eq!(d.calls.len(), 1);
    assert_eq!((d.calls[0].line, d.calls[0].file()), (5, 0));
}

#[test]
fn a_provided_map_serves_without_a_file_system() {
    let text = std::fs::read(data("linuxcnc/lib/thread_pass.ngc")).unwrap();
    let opts = Options {
        library: Some(Library::new(Provided::new([(
            "thread_pass.ngc".to_string(),
            text,
        )]))),
        ..Options::default()
    };
    let moves = run("linuxcnc", "linuxcnc/main.ngc", &opts).unwrap();
    assert_near(&threads(&moves), &M20_PASSES, 1e-3);
    // LinuxCNC's file name is `name.ngc` exactly: another case is not it.
    let opts = Options {
        library: Some(Library::new(Provided::new([(
            "THREAD_PASS.ngc".to_string(),
            b"o<thread_pass> sub\no<thread_pass> endsub\n".to_vec(),
        )]))),
        ..Options::default()
    };
    let d = run("linuxcnc", "linuxcnc/main.ngc", &opts).unwrap_err();
    assert_eq!(d.hint.as_deref(), Some("looked for thread_pass.ngc"));
}

fn rs274() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("THREADCUT_RS274") {
        return Some(PathBuf::from(p));
    }
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|dir| dir.join("rs274"))
        .find(|p| p.is_file())
}

static RS274: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// rs274's moves: (kind, x, z, lead when synchronised).
fn canon(rs274: &Path, main: &Path, subroutines: &Path) -> Vec<(String, f64, f64, Option<f64>)> {
    // One rs274 at a time: the runs share the INI and the output file.
    let _one_at_a_time = RS274.lock().unwrap_or_else(|e| e.into_inner());
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("multifile");
    std::fs::create_dir_all(&dir).unwrap();
    let ini = dir.join("subroutines.ini");
    std::fs::write(
        &ini,
        format!("[RS274NGC]\nSUBROUTINE_PATH = {}\n", subroutines.display()),
    )
    .unwrap();
    let out = dir.join("main.canon");
    let run = Command::new(rs274)
        .current_dir(&dir)
        .arg("-i")
        .arg(&ini)
        .arg("-g")
        .arg(main)
        .arg(&out)
        .stdin(Stdio::null())
        .output()
        .unwrap();
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let mut sync = None;
    let mut moves = Vec::new();
    for line in std::fs::read_to_string(&out).unwrap().lines() {
        // `   13 N..... STRAIGHT_TRAVERSE(11.0000, 0.0000, 5.0000, …)`
        let Some((_, call)) = line.split_once("N..... ") else {
            continue;
        };
        let Some((name, rest)) = call.split_once('(') else {
            continue;
        };
        let args: Vec<f64> = rest
            .trim_end_matches(')')
            .split(',')
            .filter_map(|a| a.trim().parse().ok())
            .collect();
        match name {
            "START_SPEED_FEED_SYNC" => sync = Some(args[0]),
            "STOP_SPEED_FEED_SYNCH" => sync = None,
            "STRAIGHT_TRAVERSE" => moves.push(("rapid".into(), args[0], args[2], None)),
            "STRAIGHT_FEED" => moves.push((
                if sync.is_some() { "thread" } else { "feed" }.into(),
                args[0],
                args[2],
                sync,
            )),
            _ => {}
        }
    }
    moves
}

#[test]
fn linuxcnc_subroutine_file_move_for_move_against_rs274() {
    let Some(rs274) = rs274() else {
        eprintln!("rs274 not found: the comparison with LinuxCNC is skipped");
        return;
    };
    let reference = canon(&rs274, &data("linuxcnc/main.ngc"), &data("linuxcnc/lib"));
    let ours = run("linuxcnc", "linuxcnc/main.ngc", &options(&["linuxcnc/lib"])).unwrap();
    same_as_rs274(&reference, &ours);
    assert_eq!(ours.len(), 14);
}

/// `--call`: the LatheMacro-style file `call/threading.ngc` run as its GUI calls it.
fn call(text: &str) -> Options {
    Options {
        call: Some(text.to_string()),
        ..Options::default()
    }
}

const THREADING_CALL: &str = "o<threading> call [20] [2.5] [-25] [1.5] [3]";

#[test]
fn call_runs_a_subroutine_file_with_the_values_given() {
    let moves = run("linuxcnc", "call/threading.ngc", &call(THREADING_CALL)).unwrap();
    // #1 = 20 (major diameter), #2 = 2.5 (pitch), #3 = -25 (end Z), #4 = 1.5 (depth), #5 = 3
    // passes, in G8 (X a radius): pass k at X = 20/2 − 1.5·k/3 = 9.5, 9.0, 8.5, to Z-25 at
    // lead 2.5, each from and back to X = 20/2 + 1 = 11 at Z2.
    assert_near(
        &threads(&moves),
        &[(9.5, -25.0, 2.5), (9.0, -25.0, 2.5), (8.5, -25.0, 2.5)],
        1e-3,
    );
    assert_eq!((moves[0].x, moves[0].z, moves[0].line), (11.0, 2.0, 7));
}

#[test]
fn a_file_that_only_defines_subroutines_says_so() {
    let text = std::fs::read(data("call/threading.ngc")).unwrap();
    let machine = Machine::built_in("linuxcnc").unwrap();
    let summary = program::run(text.as_slice(), &machine, |_, _| Ok(())).unwrap();
    assert_eq!(summary.uncalled, ["threading"]);
    let w = &summary.warnings[0];
    assert_eq!((w.code, w.span.line), (Code::Suspicious, 3));
    assert!(w
        .message
        .contains("defines subroutines (o<threading>) and calls none"));
    assert!(w
        .hint
        .as_deref()
        .unwrap()
        .contains("--call 'o<threading> call"));
}

#[test]
fn call_runs_a_fanuc_macro_file_with_g65_arguments() {
    // O9011 (9011.nc) called as `G65 P9011 A19.4 B-20. F2.`: #1 = 19.4 (radius 9.7), #2 = -20,
    // #9 = 2. Its first block `G0 X#1` leaves Z unknown (nothing placed the tool before the
    // call), so the first move listed is the thread.
    let moves = run(
        "fanuc",
        "fanuc/lib/9011.nc",
        &call("G65 P9011 A19.4 B-20. F2."),
    )
    .unwrap();
    assert_near(&threads(&moves), &[(9.7, -20.0, 2.0)], 1e-3);
}

#[test]
fn a_call_that_does_not_parse_is_refused_on_its_line() {
    // The call is read as the line after the file's 18: line 19.
    let d = run(
        "linuxcnc",
        "call/threading.ngc",
        &call("o<threading> call [20] [2.5"),
    )
    .unwrap_err();
    assert_eq!((d.code, d.span.line), (Code::Syntax, 19));
}

#[test]
fn call_move_for_move_against_rs274() {
    let Some(rs274) = rs274() else {
        eprintln!("rs274 not found: the comparison with LinuxCNC is skipped");
        return;
    };
    // rs274 runs a one-line main program with the call, finding threading.ngc on its path.
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("multifile-call");
    std::fs::create_dir_all(&dir).unwrap();
    let main = dir.join("main.ngc");
    std::fs::write(&main, format!("{THREADING_CALL}\nM2\n")).unwrap();
    let reference = canon(&rs274, &main, &data("call"));
    let ours = run("linuxcnc", "call/threading.ngc", &call(THREADING_CALL)).unwrap();
    // rs274 starts at the origin and lists the first rapid; threadcut's first move has an
    // unknown start: both list it.
    same_as_rs274(&reference, &ours);
    assert_eq!(ours.len(), 13);
}

/// Sinumerik: a main program calls `BAR_GROOVE(depth)`, a PROC in `bar_groove.spf` (found as
/// `BAR_GROOVE.SPF` in any case). Per call, pass X = 64 − depth (radius 32 − depth/2); start 0
/// from Z10 to Z−60, start 1 shifted by 1·8/2 = 4 (Z14 to Z−56); lead 8; out to X70 (radius 35)
/// and back to Z10. The R parameters set in the main program are the subprogram's too (they
/// are the channel's); DEPTH is the PROC's own.
#[test]
fn sinumerik_calls_a_proc_in_its_spf_file() {
    let got = run("sinumerik", "sinumerik/DRUM.MPF", &options(&["sinumerik"])).unwrap();
    let mut want = vec![("rapid", 35.0, 10.0)];
    for d in [0.0, 0.6, 1.0] {
        let r = (64.0 - d) / 2.0;
        for (zs, ze) in [(10.0, -60.0), (14.0, -56.0)] {
            want.push(("rapid", r, zs));
            want.push(("thread", r, ze));
            want.push(("rapid", 35.0, ze));
            want.push(("rapid", 35.0, 10.0));
        }
    }
    want.push(("rapid", 50.0, 50.0));
    assert_eq!(got.len(), want.len(), "{got:?}");
    for (g, w) in got.iter().zip(&want) {
        assert_eq!(g.kind, w.0, "{g:?} {w:?}");
        assert!(
            (g.x - w.1).abs() < 5e-4 && (g.z - w.2).abs() < 5e-4,
            "{g:?} {w:?}"
        );
        if g.kind == "thread" {
            assert_eq!(g.lead, Some(8.0));
        }
    }
    // Without the directory the call names what it looked for.
    let e = run("sinumerik", "sinumerik/DRUM.MPF", &options(&["fanuc"])).unwrap_err();
    assert_eq!(e.span.line, 5, "{}", e.message);
    assert!(e.message.contains("BAR_GROOVE"), "{}", e.message);
    assert!(
        e.hint
            .as_deref()
            .is_some_and(|h| h.contains("BAR_GROOVE.SPF")),
        "{:?}",
        e.hint
    );
}

/// A subprogram file without a PROC line (`BAR_CENTR.SPF`: its blocks, then M17), called by
/// its bare name twice: passes at X64 and X63.5 (radius 32, 31.75) from Z10 to Z−60, lead 8.
#[test]
fn sinumerik_calls_a_subprogram_file_by_its_bare_name() {
    let got = run("sinumerik", "sinumerik/ROPE.MPF", &options(&["sinumerik"])).unwrap();
    let threads: Vec<(f64, f64)> = got
        .iter()
        .filter(|m| m.kind == "thread")
        .map(|m| (m.x, m.z))
        .collect();
    assert_eq!(threads.len(), 2, "{got:?}");
    for (t, r) in threads.iter().zip([32.0, 31.75]) {
        assert!((t.0 - r).abs() < 5e-4 && (t.1 + 60.0).abs() < 5e-4, "{t:?}");
    }
    // The motion after the calls goes on in the main program.
    let last = got.last().unwrap();
    assert!(
        (last.x - 50.0).abs() < 5e-4 && (last.z - 50.0).abs() < 5e-4,
        "{last:?}"
    );
}

/// A numbered subprogram: `L10` (and `L10 P2`, run twice) calls `L10.SPF`: passes at X64, then
/// twice at X63.5 (radius 32, 31.75, 31.75), Z10 to Z−40, lead 2.
#[test]
fn sinumerik_calls_a_numbered_subprogram() {
    let got = run(
        "sinumerik",
        "sinumerik/NUMBERED.MPF",
        &options(&["sinumerik"]),
    )
    .unwrap();
    let threads: Vec<f64> = got
        .iter()
        .filter(|m| m.kind == "thread")
        .map(|m| m.x)
        .collect();
    assert_eq!(threads.len(), 3, "{got:?}");
    for (x, r) in threads.iter().zip([32.0, 31.75, 31.75]) {
        assert!((x - r).abs() < 5e-4, "{x} {r}");
    }
}

/// Sinumerik's `--call`: `PASSES(20, -25, 2.5)` runs the PROC of `PASSES.SPF` with DIA = 20,
/// ZEND = −25, LEAD = 2.5 (DIAMON: X a diameter, the stream a radius): one pass at X20 (radius
/// 10) from Z5 to Z−25, lead 2.5. Without the call the file says what it defines, in its own
/// words.
#[test]
fn call_runs_a_sinumerik_proc_file() {
    let moves = run(
        "sinumerik",
        "call/PASSES.SPF",
        &call("PASSES(20, -25, 2.5)"),
    )
    .unwrap();
    assert_near(&threads(&moves), &[(10.0, -25.0, 2.5)], 1e-3);
    let text = std::fs::read(data("call/PASSES.SPF")).unwrap();
    let machine = Machine::built_in("sinumerik").unwrap();
    let summary = program::run(text.as_slice(), &machine, |_, _| Ok(())).unwrap();
    assert_eq!(summary.uncalled, ["PASSES"]);
    let w = &summary.warnings[0];
    assert!(
        w.message
            .contains("defines subroutines (PROC PASSES) and calls none"),
        "{}",
        w.message
    );
    assert!(
        w.hint
            .as_deref()
            .unwrap()
            .contains("--call 'PASSES(arg1, arg2, …)'"),
        "{:?}",
        w.hint
    );
}

/// rs274's moves and threadcut's, the same: kind, end (rs274 prints four decimals of a position)
/// and lead (six decimals).
#[track_caller]
fn same_as_rs274(reference: &[(String, f64, f64, Option<f64>)], ours: &[Move]) {
    assert_eq!(reference.len(), ours.len(), "{reference:?}\n{ours:?}");
    for (r, o) in reference.iter().zip(ours) {
        assert_eq!(r.0, o.kind, "{r:?} {o:?}");
        assert!(
            (r.1 - o.x).abs() < 0.6e-4 && (r.2 - o.z).abs() < 0.6e-4,
            "{r:?} {o:?}"
        );
        if let (Some(a), Some(b)) = (r.3, o.lead) {
            assert!((a - b).abs() < 1e-6, "{r:?} {o:?}");
        }
    }
}
