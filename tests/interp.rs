//! The macro interpreter (`threadcut::interp`), through the whole run: every construct of
//! LinuxCNC's o-words and parameters and of Fanuc/GSK Custom Macro B, checked against the motion
//! it makes (hand-computed from the controls' documentation), the errors the controls raise (at
//! their line and column), the limits that keep a run bounded, and properties: an interpreted
//! straight-line program moves as the streamed one, `--flatten` read back moves as the original,
//! and a Fanuc macro program moves as its LinuxCNC twin.

use proptest::prelude::*;

use threadcut::diag::Diagnostic;
use threadcut::machine::Machine;
use threadcut::program::{self, Error, Options};

/// One motion of `expand --format jsonl`: kind, x (radius), z, lead, source line.
#[derive(Clone, Debug, PartialEq)]
struct Move {
    kind: String,
    x: f64,
    z: f64,
    lead: Option<f64>,
    line: u32,
}

fn run_jsonl(src: &str, controller: &str, options: &Options) -> Result<Vec<Move>, Error> {
    let machine = Machine::built_in(controller).unwrap();
    let mut out = Vec::new();
    program::expand_jsonl_with(src.as_bytes(), &mut out, &machine, options)?;
    Ok(String::from_utf8(out)
        .unwrap()
        .lines()
        .map(|l| {
            let v: serde_json::Value = serde_json::from_str(l).unwrap();
            Move {
                kind: v["kind"].as_str().unwrap().to_string(),
                x: v["x"].as_f64().unwrap(),
                z: v["z"].as_f64().unwrap(),
                lead: v.get("lead").and_then(|l| l.as_f64()),
                line: v["line"].as_u64().unwrap() as u32,
            }
        })
        .collect())
}

fn moves(src: &str, controller: &str) -> Vec<Move> {
    run_jsonl(src, controller, &Options::default()).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

/// The moves made by the blocks of `lines`, as (kind, x, z).
fn moves_of(src: &str, controller: &str, lines: &[u32]) -> Vec<(String, f64, f64)> {
    moves(src, controller)
        .into_iter()
        .filter(|m| lines.contains(&m.line))
        .map(|m| (m.kind, m.x, m.z))
        .collect()
}

fn error(src: &str, controller: &str) -> Diagnostic {
    error_with(src, controller, &Options::default())
}

fn error_with(src: &str, controller: &str, options: &Options) -> Diagnostic {
    match run_jsonl(src, controller, options) {
        Err(Error::Input(d)) => d,
        other => panic!("expected an input error, got {other:?}\n{src}"),
    }
}

fn mv(kind: &str, x: f64, z: f64) -> (String, f64, f64) {
    (kind.to_string(), x, z)
}

fn close(a: &[(String, f64, f64)], b: &[(String, f64, f64)]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(p, q)| p.0 == q.0 && (p.1 - q.1).abs() < 1e-9 && (p.2 - q.2).abs() < 1e-9)
}

macro_rules! assert_moves {
    ($got:expr, $want:expr) => {{
        let (got, want) = ($got, $want);
        assert!(close(&got, &want), "got  {got:?}\nwant {want:?}");
    }};
}

// ---------------------------------------------------------------------------------------------
// LinuxCNC
// ---------------------------------------------------------------------------------------------

/// o-code.adoc's while example (a sawtooth), in the lathe's XZ plane, radius mode.
#[test]
fn linuxcnc_while_loop_repeats_its_body() {
    let src = "G8 G21 G18\nG0 X1 Z0\n#1 = 0\nF25\no101 while [#1 LT 3]\n  G1 X0\n  G1 Z[-#1] X1\n  #1 = [#1+1]\no101 endwhile\nM2\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[6, 7]),
        vec![
            mv("feed", 0.0, 0.0),
            mv("feed", 1.0, 0.0),
            mv("feed", 0.0, 0.0),
            mv("feed", 1.0, -1.0),
            mv("feed", 0.0, -1.0),
            mv("feed", 1.0, -2.0),
        ]
    );
}

#[test]
fn linuxcnc_sub_arguments_are_local_and_restored() {
    // #1..#30 are the call's arguments (unpassed ones 0, as LinuxCNC's interpreter sets them)
    // and get their values back on return; #31 and up are global.
    let src = "G8 G21\n\
        o<pos> sub\n\
          G0 X[#1] Z[#2 + #3]\n\
          #3 = [#1 * 2]\n\
          #40 = [#1 * 3]\n\
        o<pos> endsub\n\
        G0 X0 Z0\n\
        #3 = 7\n\
        o<pos> call [5] [1]\n\
        G1 X#3 Z#40 F1\n\
        M2\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[3, 10]),
        vec![mv("rapid", 5.0, 1.0), mv("feed", 7.0, 15.0)]
    );
}

#[test]
fn linuxcnc_named_parameters_local_and_global() {
    let src = "G8 G21\n\
        G0 X0 Z0\n\
        #<_g> = 2\n\
        o<s> sub\n\
          #<here> = [#<_g> + 1]\n\
          #<_g> = [#<here> * 10]\n\
          G0 X#<here> Z0\n\
        o<s> endsub\n\
        o<s> call\n\
        G0 X#<_g> Z0\n\
        M2\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[7, 10]),
        vec![mv("rapid", 3.0, 0.0), mv("rapid", 30.0, 0.0)]
    );
    // A local parameter vanishes when its subroutine returns.
    let src = "G8\nG0 X0 Z0\no<s> sub\n#<here> = 1\no<s> endsub\no<s> call\nG0 X#<here>\nM2\n";
    let e = error(src, "linuxcnc");
    assert_eq!(e.message, "Named parameter #<here> not defined");
    assert_eq!((e.span.line, e.span.column), (7, 5));
    // Names ignore case and blanks.
    let src = "G8\nG0 X0 Z0\n#<P a R am> = 4\nG0 X#<param>\nM2\n";
    assert_moves!(moves_of(src, "linuxcnc", &[4]), vec![mv("rapid", 4.0, 0.0)]);
}

#[test]
fn linuxcnc_if_elseif_else() {
    let prog = |v: f64| {
        format!(
            "G8 G21\nG0 X0 Z0\n#2 = {v}\no102 if [#2 GT 5]\n  G0 X1\no102 elseif [#2 LT 2]\n  G0 X2\no102 else\n  G0 X3\no102 endif\nG0 Z1\nM2\n"
        )
    };
    let xs = |v: f64| -> Vec<f64> {
        moves(&prog(v), "linuxcnc")
            .iter()
            .filter(|m| m.z == 0.0)
            .map(|m| m.x)
            .collect()
    };
    // (The first positioning, from a start not known, is listed too.)
    assert_eq!(xs(7.0), [0.0, 1.0]);
    assert_eq!(xs(1.0), [0.0, 2.0]);
    assert_eq!(xs(3.0), [0.0, 3.0]);
}

#[test]
fn linuxcnc_do_while_break_continue_and_repeat() {
    // o-code.adoc's do-while example: #1 goes 0, 1, 2 → 3 (the continue), and the loop ends.
    let src = "G8\nG0 X0 Z0\n#1 = 0\n\
        o100 do\n\
          G0 Z#1\n\
          o110 if [#1 EQ 2]\n\
            #1 = 3\n\
            o100 continue\n\
          o110 endif\n\
          G0 X[#1 + 10]\n\
          #1 = [#1 + 1]\n\
        o100 while [#1 LT 3]\n\
        M2\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[5, 10]),
        vec![
            mv("rapid", 0.0, 0.0),
            mv("rapid", 10.0, 0.0),
            mv("rapid", 10.0, 1.0),
            mv("rapid", 11.0, 1.0),
            mv("rapid", 11.0, 2.0),
        ]
    );
    // break leaves the innermost while named.
    let src = "G8\nG0 X0 Z0\n#1 = 0\no1 while [1]\n  #1 = [#1 + 1]\n  o2 if [#1 GE 4]\n    o1 break\n  o2 endif\n  G0 Z#1\no1 endwhile\nG0 X5\nM2\n";
    let got: Vec<f64> = moves(src, "linuxcnc").iter().map(|m| m.z).collect();
    assert_eq!(got, [0.0, 1.0, 2.0, 3.0, 3.0]);
    // repeat, and a repeat of zero.
    let src = "G8\nG0 X0 Z0\nG91\no103 repeat [5]\n  G0 Z-1\no103 endrepeat\no104 repeat [0]\n  G0 X9\no104 endrepeat\nM2\n";
    let got: Vec<f64> = moves(src, "linuxcnc").iter().map(|m| m.z).collect();
    assert_eq!(got, [0.0, -1.0, -2.0, -3.0, -4.0, -5.0]);
}

#[test]
fn linuxcnc_return_values_and_indirection() {
    let src = "G8\nG0 X0 Z0\n\
        o<sq> sub\n\
          o1 if [#1 LT 0]\n\
            o<sq> return [0]\n\
          o1 endif\n\
        o<sq> endsub [#1 * #1]\n\
        o<sq> call [3]\n\
        G0 X#<_value> Z#<_value_returned>\n\
        #101 = 98\n\
        o100 sub\n\
          G0 X1 Z1\n\
        o100 endsub\n\
        o[#101 + 2] call\n\
        M2\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[9, 12]),
        vec![mv("rapid", 9.0, 1.0), mv("rapid", 1.0, 1.0)]
    );
}

#[test]
fn linuxcnc_parameters_take_effect_after_the_line() {
    // overview.adoc: with #3 at 15, `#3=6 G1 X#3` moves to X15 and leaves #3 at 6.
    let src = "G8 G21\nG0 X0 Z0\n#3 = 15\n#3=6 G1 X#3 F1\nG1 X#3\nM2\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[4, 5]),
        vec![mv("feed", 15.0, 0.0), mv("feed", 6.0, 0.0)]
    );
    // Settings on one line are parallel; the last of one parameter wins.
    let src = "G8\nG0 X0 Z0\n#1 = 5\n#1=10 #2=#1\n#3=15 #3=6\nG0 X#2 Z#3\nM2\n";
    assert_moves!(moves_of(src, "linuxcnc", &[6]), vec![mv("rapid", 5.0, 6.0)]);
}

#[test]
fn linuxcnc_expressions_in_every_word() {
    // overview.adoc's precedence example, and functions in degrees.
    let src = "G8 G21\nG0 X0 Z0\nG0 X[2.0 / 3 * 1.5 - 5.5 / 11.0] Z[1 + acos[0] - [2 ** [4.0/2]]]\nG0 X[atan[1]/[1]] Z[fix[-2.8] + fup[2.2] + round[2.5] + [7 mod 3] + abs[-1] + sqrt[4]]\nG0 X[2 EQ 2.0000001] Z[1 GT 2 OR 3 LT 4]\nG0 X-#<_x> Z[exp[0] + ln[1]]\nM2\n";
    let got = moves_of(src, "linuxcnc", &[3, 4, 5, 6]);
    assert_moves!(
        got,
        vec![
            mv("rapid", 0.5, 87.0),
            mv("rapid", 45.0, 7.0),
            mv("rapid", 1.0, 1.0),
            mv("rapid", -1.0, 1.0),
        ]
    );
}

#[test]
fn linuxcnc_active_comments_are_comments() {
    let src = "G8\nG0 X0 Z0\n#1 = 2\n(DEBUG, parameter 1 is [#1])\n(PRINT, #1)\n(MSG, done)\nG0 X#1\nM2\n";
    assert_moves!(moves_of(src, "linuxcnc", &[7]), vec![mv("rapid", 2.0, 0.0)]);
}

#[test]
fn linuxcnc_g76_in_a_loop_is_listed_once_per_run() {
    let src = "G7 G21 G18\nS500 M3\n\
        o100 sub\n\
          G0 X[#1] Z5\n\
          G76 P2.5 Z-30 I-1.0 J0.3 R1.5 K1.5335 Q29.5 H2 E2 L2\n\
        o100 endsub\n\
        #1 = 0\n\
        o101 while [#1 LT 3]\n\
          o100 call [22 + #1]\n\
          #1 = [#1 + 1]\n\
        o101 endwhile\n\
        M2\n";
    let all = moves(src, "linuxcnc");
    let cycle = all.iter().filter(|m| m.line == 5).count();
    // linuxcnc-g76.md §3: 71 moves a cycle.
    assert_eq!(cycle, 3 * 71);
    let machine = Machine::built_in("linuxcnc").unwrap();
    let jobs = program::jobs(src.as_bytes(), &machine).unwrap();
    assert_eq!(jobs.len(), 3);
    let starts: Vec<f64> = jobs.iter().map(|j| j.start.x).collect();
    assert_eq!(starts, [11.0, 11.5, 12.0]);
    assert!(jobs.iter().all(|j| j.line == 5));
}

#[test]
fn linuxcnc_subs_may_follow_their_call_and_calls_nest_ten_levels() {
    let src = "G8\nG0 X0 Z0\no200 call [4]\nM2\no200 sub\nG0 X#1\no200 endsub\n";
    assert_moves!(moves_of(src, "linuxcnc", &[6]), vec![mv("rapid", 4.0, 0.0)]);
    // Recursion: the main program and nine levels of calls run; the tenth level is refused.
    let deep = |n: u32| {
        format!(
            "G8\nG0 X0 Z0\no<r> sub\no1 if [#1 GT 0]\nG0 X#1\no<r> call [#1 - 1]\no1 endif\no<r> endsub\no<r> call [{n}]\nM2\n"
        )
    };
    // Eight moves and the first positioning.
    assert_eq!(moves(&deep(8), "linuxcnc").len(), 9);
    let e = error(&deep(9), "linuxcnc");
    assert_eq!(e.message, "Too many subroutine levels");
    assert_eq!(e.span.line, 6);
}

#[test]
fn linuxcnc_numbered_programs() {
    // o-code.adoc's numbered-program example: #1 is global in M98 subprograms, L repeats.
    let src = "o1\nG8\nG0 X0 Z0\n#1 = 0\nM98 P100 L5\nG0 X#1\nM30\no100\n#1 = [#1 + 1]\nM98 P200 L5\nM99\no200\n#1 = [#1 + 0.01]\nM99\n";
    let got = moves_of(src, "linuxcnc", &[6]);
    assert_eq!(got.len(), 1);
    assert!((got[0].1 - 5.25).abs() < 1e-9, "{got:?}");
}

#[test]
fn linuxcnc_errors_at_their_place() {
    let e = error("G8\nG0 X0 Z0\n#1 = 0\nG0 X[10 / #1]\nM2\n", "linuxcnc");
    assert_eq!(e.message, "Attempt to divide by zero");
    assert_eq!((e.span.line, e.span.column), (4, 9));
    let e = error("G8\nG0 X0 Z0\no1 while [1]\nG0 X1\nM2\n", "linuxcnc");
    assert_eq!(e.message, "o1 while has no o1 endwhile");
    assert_eq!(e.span.line, 3);
    let e = error("G8\nG0 X0 Z0\no300 call\nM2\n", "linuxcnc");
    assert_eq!(e.message, "EOF seeking o-word: o<300> from line: 3");
    assert_eq!((e.span.line, e.span.column), (3, 1));
    let e = error("G8\nG0 X0 Z0\no5 endsub\nM2\n", "linuxcnc");
    assert!(
        e.message.starts_with("not in a subroutine definition"),
        "{}",
        e.message
    );
    // rs274 (LinuxCNC 2.9): "4: no matching while/do label: '  o1 break' (found 'if' in line 3)".
    let e = error(
        "G8\nG0 X0 Z0\no1 if [1]\n  o1 break\no1 endif\nM2\n",
        "linuxcnc",
    );
    assert_eq!(
        e.message,
        "no matching while/do label: 'o1 break' (found 'if' in line 3)"
    );
    assert_eq!((e.span.line, e.span.column), (4, 3));
    let e = error(
        "G8\nG0 X0 Z0\no4 repeat [2]\no4 continue\no4 endrepeat\nM2\n",
        "linuxcnc",
    );
    assert_eq!(
        e.message,
        "no matching while/do label: 'o4 continue' (found 'repeat' in line 3)"
    );
    let e = error("G8\nG0 X0 Z0\no7 else\nM2\n", "linuxcnc");
    // rs274: "3: undefined O-word label: 'o7 else'" (the line quoted).
    assert_eq!(e.message, "undefined O-word label: 'o7 else'");
    let e = error("G8\nG0 X0 Z0\nG0 X[sqrt[-4]]\nM2\n", "linuxcnc");
    assert_eq!(e.message, "Negative argument to sqrt");
    let e = error(
        "G8\nG0 X0 Z0\no1 if [1]\no2 while [1]\no1 endif\nM2\n",
        "linuxcnc",
    );
    assert_eq!(
        e.message,
        "o2 while has no o2 endwhile before o1 endif (line 5)"
    );
    assert_eq!(e.span.line, 4);
    let e = error(
        "G8\nG0 X0 Z0\no<a> sub\no<b> sub\no<b> endsub\no<a> endsub\nM2\n",
        "linuxcnc",
    );
    assert_eq!(e.message, "Nested subroutine definition");
    assert_eq!(e.span.line, 4);
    // Lines before the error ran.
    let got = run_jsonl(
        "G8\nG0 X0 Z0\nG0 X1\n#1 = [1/0]\nM2\n",
        "linuxcnc",
        &Options::default(),
    );
    assert!(got.is_err());
}

#[test]
fn linuxcnc_program_end_ends_the_run() {
    // M2 ends the program; a subroutine after it is only a definition.
    let src = "G8\nG0 X0 Z0\no9 call\nM2\no9 sub\nG0 X3\no9 endsub\nG0 X99\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[6, 8]),
        vec![mv("rapid", 3.0, 0.0)]
    );
    // M2 in a subroutine ends the whole run.
    let src = "G8\nG0 X0 Z0\no9 sub\nG0 X3\nM2\no9 endsub\no9 call\nG0 X99\n";
    assert_moves!(
        moves_of(src, "linuxcnc", &[4, 8]),
        vec![mv("rapid", 3.0, 0.0)]
    );
    // A straight-line program stops at M2 too.
    let src = "G8\nG0 X0 Z0\nG0 X1\nM2\nG0 X2\n";
    assert_eq!(moves(src, "linuxcnc").len(), 2);
}

// ---------------------------------------------------------------------------------------------
// Fanuc Custom Macro B
// ---------------------------------------------------------------------------------------------

/// A classic macro threading program: single G32 passes, the depth computed per pass.
const FANUC_G32_PASSES: &str = "%\nO0001\nG21 G99\nG97 S500 M3\nG0 X24. Z5.\n#1=1\nWHILE[#1LE3]DO1\n#2=20.-#1*0.2\nG0 X#2\nG32 Z-20. F2.\nG0 X24.\nZ5.\n#1=#1+1\nEND1\nM30\n%\n";

#[test]
fn fanuc_while_do_end() {
    let got: Vec<(String, f64, f64)> = moves(FANUC_G32_PASSES, "fanuc")
        .into_iter()
        .filter(|m| m.line == 10)
        .map(|m| (m.kind, m.x, m.z))
        .collect();
    assert_moves!(
        got,
        vec![
            mv("thread", 9.9, -20.0),
            mv("thread", 9.8, -20.0),
            mv("thread", 9.7, -20.0),
        ]
    );
}

#[test]
fn fanuc_if_goto_and_if_then() {
    // A counted loop with IF … GOTO back to a block that came before the first macro statement.
    let src = "G21\nG0 X10. Z0\nN10 G0 U2.\n#100=#100+1\nIF[#100LT3]GOTO10\nIF[#100EQ3]THEN#101=7.\nG0 X#101\nGOTO20\nG0 X99.\nN20 M30\n";
    let xs: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.x).collect();
    assert_eq!(xs, [5.0, 6.0, 7.0, 8.0, 3.5]);
    // GOTO with a computed sequence number, forward.
    let src = "G21\nG0 X10. Z0\n#1=30\nGOTO#1\nN20 G0 X1.\nN30 G0 X2.\nM30\n";
    let xs: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.x).collect();
    assert_eq!(xs, [5.0, 1.0]);
}

#[test]
fn fanuc_variables_read_as_values() {
    // Fanuc's standard input reads X10 as 10 µm; a variable's 10 is 10 mm ("counts as written
    // with a decimal point"), rounded to the least input increment.
    let src = "G21\nG0 X10. Z0\n#1=10\nG0 X#1 Z10\n#2=12.3456\nG0 X#2\nG0 X[#1*2] Z-#1\nM30\n";
    assert_moves!(
        moves_of(src, "fanuc", &[4, 6, 7]),
        vec![
            mv("rapid", 5.0, 0.01),
            mv("rapid", 6.173, 0.01),
            mv("rapid", 10.0, -10.0),
        ]
    );
    // A vacant variable leaves its address out.
    let src = "G21\nG0 X10. Z0\nG0 X#10 Z5.\n#10=#0\nG0 X#10 Z6.\nM30\n";
    assert_moves!(
        moves_of(src, "fanuc", &[3, 5]),
        vec![mv("rapid", 5.0, 5.0), mv("rapid", 5.0, 6.0)]
    );
}

#[test]
fn fanuc_m98_m99_subprograms_after_m30() {
    let src = "%\nO0001\nG21\nG0 X40. Z10.\nM98 P1000 L2\nM98 P31001\nG0 X50.\nM30\n%\nO1000\nG0 W-1.\nM99\n%\nO1001\nG0 U-2.\nM99\n%\n";
    let zs: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.z).collect();
    assert_eq!(zs, [10.0, 9.0, 8.0, 8.0, 8.0, 8.0, 8.0]);
    let xs: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.x).collect();
    assert_eq!(xs, [20.0, 20.0, 20.0, 19.0, 18.0, 17.0, 25.0]);
    // M99 P returns to a sequence number of the caller.
    let src = "G21\nG0 X40. Z10.\nM98 P1000\nG0 X1.\nN50 G0 X2.\nM30\nO1000\nG0 Z9.\nM99 P50\n";
    let xs: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.x).collect();
    assert_eq!(xs, [20.0, 20.0, 1.0]);
    // A call to a program the file does not hold names its number.
    let e = error("G21\nG0 X40. Z10.\nM98 P1234\nM30\n", "fanuc");
    assert!(
        e.message.contains("O1234 is not in the file"),
        "{}",
        e.message
    );
    assert_eq!((e.span.line, e.span.column), (3, 5));
    // M99 in the main program: run once, with a warning.
    let machine = Machine::built_in("fanuc").unwrap();
    let summary =
        program::run("G21\nG0 X1. Z1.\nM99\n".as_bytes(), &machine, |_, _| Ok(())).unwrap();
    assert!(summary.warnings[0]
        .message
        .contains("M99 in the main program"));
}

#[test]
fn fanuc_g65_arguments_and_local_levels() {
    // G65 P9010 A… B… I… : A→#1, B→#2, I→#4; the macro's locals are its own.
    let src = "G21\nG0 X40. Z10.\n#1=99.\nG65 P9010 A2. B3. I4.\nG0 X#1\nM30\nO9010\nG0 X[#1+#2+#4] Z#2\n#1=50.\nM99\n";
    assert_moves!(
        moves_of(src, "fanuc", &[5, 8]),
        vec![mv("rapid", 4.5, 3.0), mv("rapid", 49.5, 3.0)]
    );
    // Arguments written without a decimal point read as the machine reads such numbers (least
    // increments on Fanuc's standard input); L repeats the call.
    let src = "G21\nG0 X40. Z10.\nG65 P9011 Z1000 L3\nM30\nO9011\nG0 W-#26\nM99\n";
    let zs: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.z).collect();
    assert_eq!(zs, [10.0, 9.0, 8.0, 7.0]);
    // Macro calls nest four levels (the main program is level 0).
    let nest = |n: u32| {
        format!("G21\nG0 X40. Z10.\nG65 P1 A{n}.\nM30\nO0001\nIF[#1EQ1]GOTO9\nG65 P1 A[#1-1]\nN9 G0 W-1.\nM99\n")
    };
    // Four moves and the first positioning.
    assert_eq!(moves(&nest(4), "fanuc").len(), 5);
    let e = error(&nest(5), "fanuc");
    assert!(e.message.contains("at most 4 levels"), "{}", e.message);
    assert_eq!(e.span.line, 7);
}

#[test]
fn fanuc_g76_with_computed_words() {
    // The two-block G76 written with variables: P(m)(r)(a) from a value, P(k) and Q(Δd) as
    // counts of increments, the rest as lengths.
    let plain = "G21\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\nM30\n";
    let macro_ = "G21\nG0 X32. Z5.\n#1=20060\n#2=1227\n#3=27.546\nG76 P#1 Q100 R0.05\nG76 X#3 Z-30. P#2 Q[#2/3.0675] F2.\nM30\n";
    let a: Vec<(f64, f64)> = moves(plain, "fanuc").iter().map(|m| (m.x, m.z)).collect();
    let b: Vec<(f64, f64)> = moves(macro_, "fanuc").iter().map(|m| (m.x, m.z)).collect();
    assert!(!a.is_empty());
    assert_eq!(a, b);
}

#[test]
fn fanuc_errors_at_their_place() {
    let e = error("G21\nG0 X1. Z1.\n#1=0\n#2=5/#1\nM30\n", "fanuc");
    assert!(e.message.contains("PS0112"), "{}", e.message);
    assert_eq!((e.span.line, e.span.column), (4, 5));
    let e = error("G21\nG0 X1. Z1.\nWHILE[1EQ1]DO4\nEND4\nM30\n", "fanuc");
    assert!(e.message.contains("PS0126"), "{}", e.message);
    assert_eq!(e.span.line, 3);
    let e = error("G21\nG0 X1. Z1.\n#1=1\nEND1\nM30\n", "fanuc");
    assert!(e.message.contains("END1 without WHILE"), "{}", e.message);
    let e = error(
        "G21\nG0 X1. Z1.\n#1=1\nWHILE[#1LT3]DO1\n#1=#1+1\nM30\n",
        "fanuc",
    );
    assert!(e.message.contains("DO1 has no END1"), "{}", e.message);
    assert_eq!(e.span.line, 4);
    let e = error("G21\nG0 X1. Z1.\n#1=1 G0 X2.\nM30\n", "fanuc");
    assert!(e.message.contains("PS0127"), "{}", e.message);
    let e = error("G21\nG0 X1. Z1.\nGOTO77\nM30\n", "fanuc");
    assert!(e.message.contains("no block N77"), "{}", e.message);
    assert_eq!(e.span.line, 3);
    let e = error("G21\nG0 X1. Z1.\n#3000=12 (TOO DEEP)\nM30\n", "fanuc");
    assert!(e.message.contains("macro alarm 3012"), "{}", e.message);
    let e = error("G21\nG0 X1. Z1.\n#1=SQRT[-1]\nM30\n", "fanuc");
    assert!(e.message.contains("PS0119"), "{}", e.message);
    // Subprograms nest four levels.
    let e = error(
        "G21\nG0 X1. Z1.\nM98 P1\nM30\nO0001\nM98 P1\nM99\n",
        "fanuc",
    );
    assert!(e.message.contains("at most 4 levels"), "{}", e.message);
}

#[test]
fn dialect_alarms_on_computed_words_point_at_the_written_word() {
    // The dialect checks the evaluated block; its error lands on the word as written.
    let e = error(
        "G7 G21 G18\nS500 M3\nG0 X24 Z5\n#<j> = 0\nG76 P1.5 Z-20 I-1 J#<j> K0.92\nM2\n",
        "linuxcnc",
    );
    assert_eq!(e.message, "In G76, J must be greater than 0");
    assert_eq!((e.span.line, e.span.column, e.span.len), (5, 19, 5));
    let e = error(
        "G21\nG0 X32. Z5.\n#1=0\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q#1 F2.\nM30\n",
        "fanuc",
    );
    assert!(e.message.contains("PS0062"), "{}", e.message);
    assert_eq!((e.span.line, e.span.column), (5, 25));
}

// ---------------------------------------------------------------------------------------------
// Haas (its macros: Fanuc's Macro B with M97, M99 P jumps and #10000–#10999)
// ---------------------------------------------------------------------------------------------

/// Haas's M97 P n L k calls the block N n of the same program k times and returns at M99 (the
/// Haas DIY "M97 Local Sub-Program Call" page's form): three passes, 0.2 mm deeper each, after
/// the first positioning.
#[test]
fn haas_m97_local_subprogram_repeats() {
    let src = "G21 G99\nG0 X30. Z5.\n#10000=0\nM97 P1000 L3\nG0 X50. Z50.\nM30\nN1000 (ONE PASS)\n#10000=#10000+0.2\nG0 X[29.-#10000] Z5.\nG32 Z-20. F1.5\nG0 X30.\nZ5.\nM99\n";
    let xs: Vec<f64> = moves(src, "haas")
        .iter()
        .filter(|m| m.kind == "thread")
        .map(|m| m.x)
        .collect();
    assert_eq!(xs, [14.4, 14.3, 14.2]);
    let last = moves(src, "haas").last().cloned().unwrap();
    assert_eq!((last.x, last.z, last.line), (25.0, 50.0, 5));
    // A missing block names its number; L0 calls nothing.
    let e = error("G21\nG0 X30. Z5.\nM97 P2000\nM30\nN1000 M99\n", "haas");
    assert!(e.message.contains("no block N2000"), "{}", e.message);
    assert_eq!((e.span.line, e.span.column), (3, 5));
    let src = "G21\nG0 X30. Z5.\nM97 P1000 L0\nG0 X31.\nM30\nN1000 G0 X1.\nM99\n";
    let xs: Vec<f64> = moves(src, "haas").iter().map(|m| m.x).collect();
    assert_eq!(xs, [15.0, 15.5]);
    // Fanuc has no M97: it is a plain M code there, and N1000 after M30 never runs.
    let xs: Vec<f64> = moves(src.replace("L0", "").as_str(), "fanuc")
        .iter()
        .map(|m| m.x)
        .collect();
    assert_eq!(xs, [15.0, 15.5]);
}

/// Haas's M99 P n jumps to N n of the program it is in and does not return ("It does not return
/// control to the calling subprogram"); `[condition] M99 P n` jumps when the condition holds.
/// On Fanuc, M99 P n in a subprogram returns to the caller's N n.
#[test]
fn haas_m99_p_jumps_where_fanuc_returns() {
    let src = "G21\nG0 X40. Z10.\nM98 P1000\nG0 X1.\nN50 G0 X2.\nM30\nO1000\nG0 Z9.\nM99 P50\nN50 G0 X3.\nM99\n";
    let fanuc: Vec<f64> = moves(src, "fanuc").iter().map(|m| m.x).collect();
    assert_eq!(fanuc, [20.0, 20.0, 1.0]);
    // Haas: N50 of O1000 (X3.), then its M99 returns after the call (X1., X2.).
    let haas: Vec<f64> = moves(src, "haas").iter().map(|m| m.x).collect();
    assert_eq!(haas, [20.0, 20.0, 1.5, 0.5, 1.0]);
    // A counted loop in the main program with the conditional M99.
    let src = "G21\nG0 X40. Z10.\n#10001=0\nN10 #10001=#10001+1\nG0 W-1.\n[#10001 LT 3] M99 P10\nG0 X50.\nM30\n";
    let zs: Vec<f64> = moves(src, "haas").iter().map(|m| m.z).collect();
    assert_eq!(zs, [10.0, 9.0, 8.0, 7.0, 7.0]);
    // The same block is refused on Fanuc, which has no conditional M99.
    assert!(matches!(
        run_jsonl(src, "fanuc", &Options::default()),
        Err(Error::Input(_))
    ));
}

/// #10000–#10999 are Haas's general-purpose variables, kept apart from #100–#999; on Fanuc they
/// are not variables threadcut keeps (alarm PS0115).
#[test]
fn haas_wide_common_variables() {
    let src = "G21\nG0 X40. Z10.\n#10500=12.\n#500=3.\nG0 X#10500 Z#500\nM30\n";
    let got: Vec<(f64, f64)> = moves(src, "haas").iter().map(|m| (m.x, m.z)).collect();
    assert_eq!(got, [(20.0, 10.0), (6.0, 3.0)]);
    let e = error(src, "fanuc");
    assert!(
        e.message.contains("#10500 is not a variable"),
        "{}",
        e.message
    );
}

/// A Haas macro program (M97 local subprogram, #10000 variables) moves as its Fanuc twin (M98 to
/// a program after M30, #100 variables).
#[test]
fn haas_programs_move_as_their_fanuc_twins() {
    let haas = "G21 G99\nG97 S500 M03\nG0 X32. Z5.\n#10000=0\nM97 P100 L4\nG0 X60. Z60.\nM30\nN100\n#10000=#10000+0.25\nG0 X[30.-#10000]\nG32 Z-25. F2.\nG0 X32.\nZ5.\nM99\n";
    let fanuc = "G21 G99\nG97 S500 M03\nG0 X32. Z5.\n#100=0\nM98 P100 L4\nG0 X60. Z60.\nM30\nO0100\n#100=#100+0.25\nG0 X[30.-#100]\nG32 Z-25. F2.\nG0 X32.\nZ5.\nM99\n";
    let a = shape(&moves(haas, "haas"));
    let b = shape(&moves(fanuc, "fanuc"));
    assert_eq!(a.len(), 1 + 4 * 4 + 1);
    assert_eq!(a, b);
}

// ---------------------------------------------------------------------------------------------
// GSK 980TDi
// ---------------------------------------------------------------------------------------------

#[test]
fn gsk_g65_operations() {
    // G65 H01 (=), H02 (+), H84 (jump when less): a counted loop of rapid moves.
    let src = "G0 X40 Z10\nG65 H01 P#100 Q0\nN10 G65 H02 P#100 Q#100 R1\nG0 X[40-#100*2] Z10\nG65 H84 P10 Q#100 R3\nM30\n";
    let xs: Vec<f64> = moves(src, "gsk980").iter().map(|m| m.x).collect();
    assert_eq!(xs, [20.0, 19.0, 18.0, 17.0]);
    // H26, H27, H24/H25, H31, H34.
    let src = "G0 X40 Z10\nG65 H01 P#1 Q6\nG65 H26 P#1 Q4 R3\nG65 H27 P#2 Q3 R4\nG65 H25 P#3 Q12\nG65 H24 P#4 Q#3\nG65 H31 P#5 Q2 R30\nG65 H34 P#6 Q-1 R-1\nG0 X#1 Z#2\nG0 X#3 Z#4\nG0 X#5 Z#6\nM30\n";
    let got: Vec<(f64, f64)> = moves(src, "gsk980").iter().map(|m| (m.x, m.z)).collect();
    assert_eq!(got.len(), 4);
    assert_eq!(got[1], (4.0, 5.0));
    assert_eq!(got[2], (9.0, 12.0));
    assert!(
        (got[3].0 - 0.5).abs() < 1e-9 && (got[3].1 - 225.0).abs() < 1e-9,
        "{got:?}"
    );
    let e = error("G0 X40 Z10\nG65 H99 P7\nM30\n", "gsk980");
    assert!(e.message.contains("P/S alarm 507"), "{}", e.message);
    // G65 without H is not a call on this control.
    let e = error("G0 X40 Z10\nG65 P1000 A1\nM30\n", "gsk980");
    assert!(e.message.contains("G65 needs H"), "{}", e.message);
}

#[test]
fn gsk_m98_packs_its_count_and_nests_four_levels() {
    let src = "G0 X40 Z10\nM98 P00021000\nM30\nO1000\nG0 W-1\nM99\n";
    let zs: Vec<f64> = moves(src, "gsk980").iter().map(|m| m.z).collect();
    assert_eq!(zs, [10.0, 9.0, 8.0]);
    let e = error("G0 X40 Z10\nM98 P1000 L2\nM30\nO1000\nM99\n", "gsk980");
    assert!(e.message.contains("count is packed in P"), "{}", e.message);
    let e = error("G0 X40 Z10\nM98 P1\nM30\nO0001\nM98 P1\nM99\n", "gsk980");
    assert!(e.message.contains("at most 4 levels"), "{}", e.message);
    // Macro B statements run on GSK too.
    let src = "G0 X40 Z10\n#1=0\nWHILE[#1LT2]DO1\nG0 W-1\n#1=#1+1\nEND1\nM30\n";
    assert_eq!(moves(src, "gsk980").len(), 3);
}

// ---------------------------------------------------------------------------------------------
// Bounds
// ---------------------------------------------------------------------------------------------

#[test]
fn endless_loops_end_with_an_error_naming_the_loop() {
    for (controller, src, line) in [
        (
            "linuxcnc",
            "G8\nG0 X0 Z0\n#1 = 0\no1 while [1]\n  #1 = [#1 + 1]\no1 endwhile\nM2\n",
            4,
        ),
        (
            "linuxcnc",
            "G8\nG0 X0 Z0\no2 do\no2 while [1 GT 0]\nM2\n",
            3,
        ),
        (
            "fanuc",
            "G21\nG0 X1. Z1.\n#1=0\nWHILE[1EQ1]DO1\n#1=#1+1\nEND1\nM30\n",
            4,
        ),
        ("fanuc", "G21\nG0 X1. Z1.\nN10 #1=#1+1\nGOTO10\nM30\n", 3),
        (
            "gsk980",
            "G0 X1 Z1\nN10 G65 H02 P#100 Q#100 R1\nG65 H80 P10\nM30\n",
            2,
        ),
    ] {
        let t = std::time::Instant::now();
        let e = error_with(
            src,
            controller,
            &Options {
                max_blocks: 200_000,
                ..Options::default()
            },
        );
        assert!(t.elapsed().as_secs() < 5, "{controller}: {:?}", t.elapsed());
        assert!(
            e.message.contains("ran past 200000 executed blocks"),
            "{}",
            e.message
        );
        assert!(
            e.message.contains(&format!(
                "loop of line{}",
                if e.message.contains("lines") { "s" } else { "" }
            )),
            "{}",
            e.message
        );
        assert_eq!(e.span.line, line, "{controller}: {}", e.message);
    }
    // The default limit, a million blocks, within seconds too (in a debug build).
    let t = std::time::Instant::now();
    let e = error("G8\nG0 X0 Z0\no1 while [1]\no1 endwhile\nM2\n", "linuxcnc");
    assert!(
        e.message.contains("1000000 executed blocks"),
        "{}",
        e.message
    );
    assert!(t.elapsed().as_secs() < 30, "{:?}", t.elapsed());
}

#[test]
fn long_lines_in_loops_exhaust_the_evaluation_budget() {
    let expr = format!("[1{}]", "+1".repeat(50_000));
    let src = format!("G8\nG0 X0 Z0\no1 while [1]\n#1 = {expr}\no1 endwhile\nM2\n");
    let t = std::time::Instant::now();
    let e = error(&src, "linuxcnc");
    assert!(e.message.contains("evaluation budget"), "{}", e.message);
    assert!(t.elapsed().as_secs() < 20, "{:?}", t.elapsed());
}

// ---------------------------------------------------------------------------------------------
// expand: the program's text, or the executed program
// ---------------------------------------------------------------------------------------------

fn expand(src: &str, controller: &str, flatten: bool) -> Result<String, Error> {
    let machine = Machine::built_in(controller).unwrap();
    let mut out = Vec::new();
    program::expand_gcode_with(
        src.as_bytes(),
        &mut out,
        &machine,
        &Options {
            flatten,
            ..Options::default()
        },
    )?;
    Ok(String::from_utf8(out).unwrap())
}

#[test]
fn expand_keeps_the_text_and_replaces_a_cycle_that_always_expands_the_same() {
    // The same cycle from the same start, three times: replaced in place once.
    let src = "G7 G21 G18\nS500 M3\n#1 = 0\no1 while [#1 LT 3]\n  G0 X22 Z5\n  G76 P2.5 Z-30 I-1.0 J0.3 K1.5335\n  #1 = [#1 + 1]\no1 endwhile\nM2\n";
    let out = expand(src, "linuxcnc", false).unwrap();
    assert!(out.starts_with("G7 G21 G18\nS500 M3\n#1 = 0\no1 while [#1 LT 3]\n  G0 X22 Z5\n(threadcut: linuxcnc cycle of line 6"), "{out}");
    assert!(out.ends_with("  #1 = [#1 + 1]\no1 endwhile\nM2\n"), "{out}");
    assert_eq!(out.matches("threadcut: linuxcnc cycle").count(), 1);
    // From different start points: exit 2 naming the block and its two runs.
    let src = src.replace("G0 X22 Z5", "G0 X[22 + #1] Z5");
    match expand(&src, "linuxcnc", false) {
        Err(Error::Input(d)) => {
            assert_eq!(d.span.line, 6);
            assert!(d.message.contains("starting at X22"), "{}", d.message);
            assert!(d.message.contains("starting at X23"), "{}", d.message);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn expand_compares_a_cycle_before_the_first_macro_statement_that_a_jump_runs_again() {
    // The G92 of line 3 streams (expanded as always), then the GOTO runs it again from the same
    // start: the expansion already written stands for both runs.
    let src = "G21\nG0 X32. Z5.\nN10 G92 X29.2 Z-30. F2.\n#100=#100+1\nIF[#100LT2]GOTO10\nM30\n";
    let out = expand(src, "fanuc", false).unwrap();
    assert!(
        out.starts_with("G21\nG0 X32. Z5.\n(threadcut: fanuc cycle of line 3"),
        "{out}"
    );
    assert!(
        out.ends_with("#100=#100+1\nIF[#100LT2]GOTO10\nM30\n"),
        "{out}"
    );
    assert_eq!(
        moves(src, "fanuc").iter().filter(|m| m.line == 3).count(),
        2 * 5
    );
    // From another start the second time: exit 2, naming the line and both runs.
    let src =
        "G21\nG0 X32. Z5.\nN10 G0 U2.\nG92 X29.2 Z-30. F2.\n#100=#100+1\nIF[#100LT2]GOTO10\nM30\n";
    match expand(src, "fanuc", false) {
        Err(Error::Input(d)) => {
            assert_eq!(d.span.line, 4);
            assert!(
                d.message
                    .contains("before the program's first macro statement"),
                "{}",
                d.message
            );
            assert!(d.message.contains("starting at X36"), "{}", d.message);
        }
        other => panic!("{other:?}"),
    }
    // The second run's modal state differs in what its expansion does not write (G55 and a feed
    // of the plain moves): the same moves from the same start, so the expansion stands for both.
    // (What a streamed cycle is compared by is its expansion, made again from the state it ran
    // in, not that state.)
    let src = "G21\nG54\nN10 G0 X32. Z5.\nG92 X29.2 Z-30. F2.\nG55 G1 Z6. F0.3\n#100=#100+1\nIF[#100LT2]GOTO10\nM30\n";
    let out = expand(src, "fanuc", false).unwrap();
    assert!(out.contains("(threadcut: fanuc cycle of line 4"), "{out}");
    assert_eq!(
        moves(src, "fanuc").iter().filter(|m| m.line == 4).count(),
        2 * 5
    );
    // From the same start, but reached in G1 the second time (N10 has no motion word): the
    // expansion restores G1 after the moves the second time only. Refused.
    let src = "G21 G99\nG0\nN10 X32. Z5.\nG76 P010060 Q100 R0.05\nG76 X29.2 Z-30. P1000 Q400 F2.\nG1 Z6. F0.3\n#100=#100+1\nIF[#100LT2]GOTO10\nM30\n";
    let e = expand(src, "fanuc", false);
    assert!(
        matches!(&e, Err(Error::Input(d)) if d.span.line == 5 && d.message.contains("starting at X32 Z5")),
        "{e:?}"
    );
}

#[test]
fn flatten_writes_the_executed_program() {
    let out = expand(FANUC_G32_PASSES, "fanuc", true).unwrap();
    assert_eq!(
        out,
        "%\nO0001\nG21 G99\nG97 S500 M3\nG0 X24. Z5.\nG0 X19.8\nG32 Z-20. F2.\nG0 X24.\nZ5.\nG0 X19.6\nG32 Z-20. F2.\nG0 X24.\nZ5.\nG0 X19.4\nG32 Z-20. F2.\nG0 X24.\nZ5.\nM30\n%\n"
    );
    // Read back (no macros left), it moves as the original.
    assert_eq!(moves(&out, "fanuc"), {
        let mut m = moves(FANUC_G32_PASSES, "fanuc");
        // The flattened text has other line numbers.
        for (a, b) in m.iter_mut().zip(moves(&out, "fanuc")) {
            a.line = b.line;
        }
        m
    });
}

// ---------------------------------------------------------------------------------------------
// Properties
// ---------------------------------------------------------------------------------------------

/// A number as a Fanuc length: always with a decimal point.
fn dot(v: f64) -> String {
    let s = format!("{v}");
    if s.contains('.') {
        s
    } else {
        s + "."
    }
}

/// Motions without their lines (for programs whose lines differ).
fn shape(ms: &[Move]) -> Vec<(String, i64, i64, Option<i64>)> {
    // Compared at 1e-9 mm: both runs compute the same doubles, or read the same text.
    let q = |v: f64| (v * 1e9).round() as i64;
    ms.iter()
        .map(|m| (m.kind.clone(), q(m.x), q(m.z), m.lead.map(q)))
        .collect()
}

fn linuxcnc_straight_line() -> impl Strategy<Value = Vec<String>> {
    let line = prop_oneof![
        (0.0f64..40.0, -40.0f64..5.0).prop_map(|(x, z)| format!("G0 X{x:.3} Z{z:.3}")),
        (0.0f64..40.0, -40.0f64..5.0).prop_map(|(x, z)| format!("G1 X{x:.3} Z{z:.3} F0.2")),
        (5.0f64..40.0, -40.0f64..-1.0, 0.5f64..3.0)
            .prop_map(|(x, z, k)| format!("G33 X{x:.3} Z{z:.3} K{k:.3}")),
        Just("G91".to_string()),
        Just("G90".to_string()),
        Just("G7".to_string()),
        Just("G8".to_string()),
        Just("(a comment)".to_string()),
        (0.5f64..4.0).prop_map(|z| format!("G0 Z{z:.2}\nG76 P1.5 Z-20 I-0.8 J0.2 K0.92")),
    ];
    proptest::collection::vec(line, 1..14)
}

fn fanuc_straight_line() -> impl Strategy<Value = Vec<String>> {
    let line = prop_oneof![
        (0.0f64..40.0, -40.0f64..5.0).prop_map(|(x, z)| format!("G0 X{x:.3} Z{z:.3}")),
        (0.0f64..40.0, -40.0f64..5.0).prop_map(|(x, z)| format!("G1 X{x:.3} Z{z:.3} F0.2")),
        (-2.0f64..2.0, -2.0f64..2.0).prop_map(|(u, w)| format!("G1 U{u:.3} W{w:.3}")),
        (5.0f64..40.0, -40.0f64..-1.0, 0.5f64..3.0)
            .prop_map(|(x, z, f)| format!("G32 X{x:.3} Z{z:.3} F{f:.3}")),
        Just("(a comment)".to_string()),
        (1.0f64..4.0).prop_map(|z| format!(
            "G0 X32. Z{z:.2}\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2."
        )),
        (1.0f64..4.0).prop_map(|z| format!("G0 X32. Z{z:.2}\nG92 X29.2 Z-30. F2.")),
    ];
    proptest::collection::vec(line, 1..14)
}

/// The Fanuc lines as another member of the family writes them: its own thread move, single-pass
/// cycle and multiple threading cycle (`fanuc15` and `haas`: the one-block G76; `fanuc-b`: G33,
/// G78 and the two-block G76).
fn family_lines(lines: &[String], controller: &str) -> Vec<String> {
    let one_block = "G0 X32. Z5.\nG76 X27.546 Z-30. K1.227 D0.4 F2. A60 P1";
    lines
        .iter()
        .map(|l| {
            let mut l = l.clone();
            if l.contains("G76 P020060") {
                let z = l
                    .split_once('\n')
                    .map_or("G0 X32. Z5.", |(a, _)| a)
                    .to_string();
                l = match controller {
                    "fanuc15" | "haas" => one_block.replacen("G0 X32. Z5.", &z, 1),
                    _ => l,
                };
            }
            if controller == "fanuc-b" {
                l = l.replace("G32 ", "G33 ").replace("G92 ", "G78 ");
            }
            l
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// A straight-line program the interpreter runs (a macro statement that changes nothing put
    /// in at any line) moves exactly as the streamed program, on every control with macros.
    #[test]
    fn interpreted_straight_line_moves_as_streamed(
        lines in linuxcnc_straight_line(),
        at in 0usize..14,
        fanuc_lines in fanuc_straight_line(),
        fanuc_at in 0usize..14,
    ) {
        let fanuc15_lines = family_lines(&fanuc_lines, "fanuc15");
        let fanuc_b_lines = family_lines(&fanuc_lines, "fanuc-b");
        let haas_lines = family_lines(&fanuc_lines, "haas");
        for (controller, head, lines, at, noop) in [
            ("linuxcnc", "G18 G21 S500 M3\nG0 X30 Z5\n", &lines, at, "#<_unused> = [1 + 1]"),
            ("fanuc", "G21 G99\nG0 X30. Z5.\n", &fanuc_lines, fanuc_at, "#100=1"),
            ("gsk980", "G0 X30 Z5\n", &fanuc_lines, fanuc_at, "#100=1"),
            ("fanuc15", "G21 G99\nG0 X30. Z5.\n", &fanuc15_lines, fanuc_at, "#100=1"),
            ("fanuc-b", "G21 G95\nG0 X30. Z5.\n", &fanuc_b_lines, fanuc_at, "#100=1"),
            ("haas", "G21 G99\nG0 X30. Z5.\n", &haas_lines, fanuc_at, "#10000=1"),
        ] {
            let body = lines.join("\n");
            let plain = format!("{head}{body}\n");
            let mut with = lines.clone();
            with.insert(at.min(with.len()), noop.to_string());
            let interpreted = format!("{head}{}\n", with.join("\n"));
            let a = run_jsonl(&plain, controller, &Options::default());
            let b = run_jsonl(&interpreted, controller, &Options::default());
            match (a, b) {
                (Ok(a), Ok(b)) => prop_assert_eq!(shape(&a), shape(&b), "{}\n{}", controller, interpreted),
                (Err(_), Err(_)) => {}
                (a, b) => prop_assert!(false, "{}: {:?} vs {:?}\n{}", controller, a.err(), b.err(), interpreted),
            }
        }
    }

    /// `expand --flatten` read back moves as the original program with control flow.
    #[test]
    fn flattened_programs_read_back_the_same(
        passes in 1usize..5,
        x0 in 20.0f64..30.0,
        step in 0.05f64..0.5,
        length in 5.0f64..30.0,
        lead in 0.5f64..3.0,
        reps in 1u32..4,
    ) {
        let linuxcnc = format!(
            "G7 G21 G18\nS500 M3\nG0 X{x0} Z5\n\
             o<pass> sub\n  G0 X[#1]\n  G33 Z-{length} K{lead}\n  G0 X{x1}\n  G0 Z5\no<pass> endsub\n\
             o2 repeat [{reps}]\n#<n> = 1\no1 while [#<n> LE {passes}]\n  o<pass> call [{x0} - #<n> * {step}]\n  #<n> = [#<n> + 1]\no1 endwhile\no2 endrepeat\nM2\n",
            x1 = x0 + 4.0,
        );
        let fanuc = format!(
            "%\nO0001\nG21 G99\nG0 X{x0:.3} Z5.\n#5=0\nWHILE[#5LT{reps}]DO1\n#1=1\nWHILE[#1LE{passes}]DO2\nG65 P100 A[{x0:.3}-#1*{step:.4}]\n#1=#1+1\nEND2\n#5=#5+1\nEND1\nM30\n%\nO100\nG0 X#1\nG32 Z-{length:.3} F{lead:.4}\nG0 X{x1:.3}\nZ5.\nM99\n%\n",
            x1 = x0 + 4.0,
        );
        for (controller, src) in [("linuxcnc", &linuxcnc), ("fanuc", &fanuc), ("haas", &fanuc), ("fanuc15", &fanuc)] {
            let original = moves(src, controller);
            prop_assert_eq!(original.iter().filter(|m| m.kind == "thread").count(), passes * reps as usize);
            let flat = expand(src, controller, true).unwrap();
            prop_assert!(!flat.contains('#') && !flat.contains('['), "{}", flat);
            let back = moves(&flat, controller);
            prop_assert_eq!(shape(&original), shape(&back), "{}", flat);
        }
    }

    /// A Fanuc macro program moves as its LinuxCNC twin.
    #[test]
    fn fanuc_macro_programs_move_as_their_linuxcnc_twins(
        passes in 1usize..6,
        x0 in 20.0f64..30.0,
        step in 0.05f64..0.4,
        length in 5.0f64..30.0,
        lead in 0.5f64..3.0,
    ) {
        let x0 = (x0 * 1000.0).round() / 1000.0;
        let step = (step * 1000.0).round() / 1000.0;
        let length = (length * 1000.0).round() / 1000.0;
        let lead = (lead * 1000.0).round() / 1000.0;
        let linuxcnc = format!(
            "G7 G21 G18\nS500 M3\nG0 X{x0} Z5\n#<p> = 1\no10 while [#<p> LE {passes}]\n  #<x> = [{x0} - #<p> * {step}]\n  G0 X#<x>\n  G33 Z-{length} K{lead}\n  G0 X[{x0} + 2]\n  G0 Z5\n  #<p> = [#<p> + 1]\no10 endwhile\nM2\n"
        );
        let fanuc = format!(
            "G21 G99\nS500 M3\nG0 X{} Z5.\n#1=1\nWHILE[#1LE{passes}]DO1\n#2={x0}-#1*{step}\nG0 X#2\nG32 Z-{} F{}\nG0 X[{x0}+2.]\nZ5.\n#1=#1+1\nEND1\nM30\n",
            dot(x0), dot(length), dot(lead)
        );
        let a = shape(&moves(&linuxcnc, "linuxcnc"));
        let b = shape(&moves(&fanuc, "fanuc"));
        // Fanuc rounds X#2 to the least increment (0.001 mm, on the diameter): compare at that.
        prop_assert_eq!(a.len(), b.len());
        for (p, q) in a.iter().zip(&b) {
            prop_assert_eq!(&p.0, &q.0);
            prop_assert!((p.1 - q.1).abs() <= 500_000, "{:?} {:?}", p, q);
            prop_assert_eq!(p.2, q.2);
            prop_assert_eq!(p.3, q.3);
        }
    }
}

/// Pieces of macro programs, glued at random into lines: whatever they make, the run ends with an
/// output or an error (never a panic, never a hang).
const FRAGMENTS: &[&str] = &[
    "o1 while [#1 LT 3]",
    "o1 endwhile",
    "o2 if [#2 GT 1]",
    "o2 elseif [#2 EQ 0]",
    "o2 else",
    "o2 endif",
    "o3 do",
    "o3 while [#3 LT 2]",
    "o4 repeat [2]",
    "o4 endrepeat",
    "o1 break",
    "o1 continue",
    "o<s> sub",
    "o<s> endsub [#1]",
    "o<s> return",
    "o<s> call [1] [2]",
    "o[#9] call",
    "#1 = [#1 + 1]",
    "#2 = [#2 - 1]",
    "#<_g> = 5",
    "#<l> = #<_g>",
    "G0 X[#1 * 2] Z#2",
    "G1 X#<l> Z[-#1] F0.2",
    "G33 Z-10 K1.5",
    "G76 P1.5 Z-20 I-0.8 J0.2 K0.92",
    "G7",
    "S500 M3",
    "M2",
    "M98 P100",
    "M99",
    "o100",
    "#100=#100+1",
    "WHILE[#100LT3]DO1",
    "END1",
    "IF[#100GT2]GOTO20",
    "IF[#1EQ#0]THEN#1=1",
    "N20 G0 X30. Z5.",
    "GOTO20",
    "G65 P100 A1. I2.",
    "G65 H02 P#100 Q#100 R1",
    "G65 H84 P20 Q#100 R3",
    "M98 P21000",
    "M30",
    "O1000",
    "O100",
    "G92 X29.2 Z-30. F2.",
    "G0 X[1/#0]",
    "M97 P20 L2",
    "[#100 LT 3] M99 P20",
    "M99 P20",
    "#10000=#10000+1",
    "[",
    "#",
    "(comment)",
    "%",
];

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_macro_programs_end(
        lines in proptest::collection::vec(proptest::collection::vec(proptest::sample::select(FRAGMENTS), 1..3), 0..25),
    ) {
        let mut src = String::from("G0 X30 Z5\n");
        for l in &lines {
            src.push_str(&l.join(" "));
            src.push('\n');
        }
        let options = Options {
            max_blocks: 5_000,
            ..Options::default()
        };
        for controller in ["linuxcnc", "fanuc", "gsk980", "haas"] {
            let t = std::time::Instant::now();
            let _ = run_jsonl(&src, controller, &options);
            let _ = expand(&src, controller, true);
            prop_assert!(t.elapsed().as_secs() < 10, "{}: {:?}\n{}", controller, t.elapsed(), src);
        }
    }
}

/// A Fanuc `GOTO` may jump back into the plain lines before the first macro statement while that
/// beginning is at most `interp::PREFIX_KEPT` bytes (the reader keeps it in place); past it the
/// jump is the control's "sequence number not found" with a hint saying why.
#[test]
fn a_jump_back_reaches_the_kept_beginning_only() {
    let program = |filler: usize| {
        let mut s = String::from("G21\nN10 G0 X30. Z5.\n");
        for _ in 0..filler {
            s.push_str("G1 X30.000 Z5.000 F0.2\n");
        }
        s.push_str("#100=#100+1\nIF[#100LT2]GOTO10\nM30\n");
        s
    };
    // 1,000 lines (about 23 KB): N10 runs twice.
    let ms = moves(&program(1_000), "fanuc");
    assert_eq!(ms.iter().filter(|m| m.line == 2).count(), 2);
    // 50,000 lines (1.15 MB, more than 1 MiB): the beginning is no longer held.
    let e = error(&program(50_000), "fanuc");
    assert!(e.message.contains("there is no block N10"), "{}", e.message);
    let hint = e.hint.unwrap_or_default();
    assert!(hint.contains("no longer held"), "{hint}");
    assert_eq!(threadcut::interp::PREFIX_KEPT, 1 << 20);
}
