//! Macro programs converted with their structure: Custom Macro B (Fanuc, Haas, GSK) ⇄ LinuxCNC
//! o-words. Each construct both ways with the text expected, the bundled macro examples on every
//! macro-language target (the table in docs/translation.md, "Macro programs"), generated
//! programs, and each refusal at its line and column. Every converted program is run here again
//! through the target's interpreter and its motion compared with the source's, independently of
//! the check the conversion makes itself.

use std::path::Path;

use proptest::prelude::*;
use threadcut::convert;
use threadcut::diag::Diagnostic;
use threadcut::machine::{Machine, BUILT_IN};
use threadcut::program::{self, Event};
use threadcut::toolpath::{self, MotionKind};
use threadcut::units::Pos;

/// (rapid, lead, end) of every move of length.
fn motion(text: &str, m: &Machine) -> Vec<(bool, Option<f64>, Pos)> {
    let mut moves = Vec::new();
    let mut at: Option<Pos> = None;
    program::run(text.as_bytes(), m, |_, ev| {
        match ev {
            Event::Plain { mv: Some(mv), .. } => moves.push((
                mv.mode == threadcut::gcode::MotionMode::Rapid,
                mv.lead,
                mv.to,
            )),
            Event::Cycle { job, .. } => {
                for (_, mo) in toolpath::build(&job)?.segments() {
                    let lead = match mo.kind {
                        MotionKind::Thread { lead, .. } => Some(lead),
                        _ => None,
                    };
                    moves.push((mo.kind == MotionKind::Rapid, lead, mo.to));
                }
            }
            _ => {}
        }
        Ok(())
    })
    .unwrap_or_else(|e| panic!("{e}\n{text}"));
    moves.retain(|(_, _, to)| {
        let moved = at.is_none_or(|a| a.distance(*to) > 1e-9);
        at = Some(*to);
        moved
    });
    moves
}

/// The two programs move alike, within `tol` mm.
fn same_motion(a: &str, from: &Machine, b: &str, to: &Machine, tol: f64) {
    let (x, y) = (motion(a, from), motion(b, to));
    assert_eq!(x.len(), y.len(), "move counts\n{b}");
    for (k, (p, q)) in x.iter().zip(&y).enumerate() {
        let d = p.2.minus(q.2);
        assert!(
            p.0 == q.0 && d.x.abs() <= tol && d.z.abs() <= tol,
            "move {}: {p:?} became {q:?}\n{b}",
            k + 1
        );
        match (p.1, q.1) {
            (None, None) => {}
            (Some(l), Some(m)) => assert!(
                (l - m).abs() <= tol,
                "move {}: lead {l} became {m}\n{b}",
                k + 1
            ),
            _ => panic!("move {}: {p:?} became {q:?}\n{b}", k + 1),
        }
    }
}

fn machine(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

fn conv(src: &str, from: &str, to: &str) -> Result<String, Diagnostic> {
    convert::convert_text(src, &machine(from), &machine(to), &Default::default())
}

/// The converted program without its header (the comment and the block of modes), checked to
/// move as the source does.
fn translated(src: &str, from: &str, to: &str) -> String {
    let out = conv(src, from, to).unwrap_or_else(|d| panic!("{from} → {to}: {d:?}\n{src}"));
    same_motion(src, &machine(from), &out, &machine(to), 0.0013);
    out.lines()
        .filter(|l| {
            !l.starts_with("(threadcut convert:")
                && !l.starts_with("G21 G90 G8")
                && !l.starts_with("G21 G18 G9")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn while_loops_both_ways() {
    // Fanuc's loop of G32 passes, the X of each computed: LinuxCNC's X is the radius (G8), so the
    // diameter #2 is written halved: #2 = 20 - 0.4·#1 → 19.6, 19.2 (diameter), 9.8, 9.6 (radius).
    let fanuc = "G21 G99\nG0 X24. Z5.\n#1=1\nWHILE[#1LE2]DO1\n#2=20.-0.4*#1\nG0 X#2\nG32 Z-20. F1.5\nG0 X24.\nZ5.\n#1=#1+1\nEND1\nM30\n";
    assert_eq!(
        translated(fanuc, "fanuc", "linuxcnc"),
        "G21 G95\nG0 X12. Z5.\n#1 = 1\no101 while [#1 LE 2]\n  #2 = [20-0.4*#1]\n  G0 X[#2/2]\n  G33 Z-20. K1.5\n  G0 X12.\n  G0 Z5.\n  #1 = [#1+1]\no101 endwhile\nM30"
    );
    let ngc = "G7 G21 G18\nG0 X24 Z5\n#1 = 1\no1 while [#1 LE 2]\n  #2 = [20 - 0.4 * #1]\n  G0 X#2\n  G33 Z-20 K1.5\n  G0 X24\n  G0 Z5\n  #1 = [#1 + 1]\no1 endwhile\nM2\n";
    assert_eq!(
        translated(ngc, "linuxcnc", "fanuc"),
        "G21 G18\nG0 X24. Z5.\n#1=1\nWHILE [#1 LE 2] DO1\n#2=20-0.4*#1\nG0 X#2\nG32 Z-20. F1.5\nG0 X24.\nG0 Z5.\n#1=#1+1\nEND1\nM2"
    );
}

#[test]
fn forward_gotos_are_conditions_and_backward_ones_loops() {
    // IF … GOTO forward: the blocks skipped run when the condition does not hold; a backward
    // IF … GOTO to an N before it: a loop tested at its end.
    let fanuc = "G21 G99\n#1=0\nN10\n#1=#1+1\nIF[#1GT1]GOTO20\nG0 X30. Z5.\nN20\nIF[#1LT3]GOTO10\nG0 X40. Z10.\nM30\n";
    assert_eq!(
        translated(fanuc, "fanuc", "linuxcnc"),
        "G21 G95\n#1 = 0\no101 do\n  #1 = [#1+1]\n  o102 if [#1 LE 1]\n    G0 X15. Z5.\n  o102 endif\no101 while [#1 LT 3]\nG0 X20. Z10.\nM30"
    );
    // And back: LinuxCNC's if/else and do/while in Custom Macro B's GOTOs.
    let ngc = "G7 G21 G18\n#1 = 0\no1 do\n  #1 = [#1 + 1]\n  o2 if [#1 GT 1]\n    G0 X30 Z5\n  o2 else\n    G0 X20 Z5\n  o2 endif\no1 while [#1 LT 3]\nM2\n";
    assert_eq!(
        translated(ngc, "linuxcnc", "fanuc"),
        "G21 G18\n#1=0\nN9001\n#1=#1+1\nIF [#1 LE 1] GOTO9002\nG0 X30. Z5.\nGOTO9003\nN9002\nG0 X20. Z5.\nN9003\nIF [#1 LT 3] GOTO9001\nM2"
    );
    // IF … THEN: one assignment under a condition, both ways.
    let then = "G21 G99\n#1=2\nIF[#1EQ2]THEN#2=30.\nG0 X#2 Z5.\nM30\n";
    let ngc = translated(then, "fanuc", "linuxcnc");
    assert!(
        ngc.contains("o101 if [#1 EQ 2]\n  #2 = 30\no101 endif"),
        "{ngc}"
    );
    let back = translated(&ngc, "linuxcnc", "fanuc");
    assert!(back.contains("IF [#1 EQ 2] THEN #2=30"), "{back}");
}

#[test]
fn subprograms_and_calls_both_ways() {
    // G65's letters to positional arguments: A → #1, B → #2, X → #24 (the gaps passed as 0).
    let fanuc = "%\nO0001\nG21 G99\nG65 P1000 A24. B1.5\nG65 P1000 A20. B1.\nM30\n%\nO1000 (ONE PASS)\nG0 X#1 Z5.\nG32 Z-20. F#2\nG0 X30.\nZ5.\nM99\n%\n";
    let ngc = translated(fanuc, "fanuc", "linuxcnc");
    assert!(
        ngc.contains("(ONE PASS)\no1000 sub\n  G0 X[#1/2] Z5.\n  G33 Z-20. K#2\n  G0 X15.\n  G0 Z5.\no1000 endsub"),
        "{ngc}"
    );
    assert!(
        ngc.contains("o1000 call [24] [1.5]\no1000 call [20] [1]\nM30"),
        "{ngc}"
    );
    // And back: positional arguments to G65's letters, with their decimal points.
    let back = translated(&ngc, "linuxcnc", "fanuc");
    assert!(
        back.contains(
            "G65 P1000 A24. B1.5\nG65 P1000 A20. B1.\nM30\nO1000\nG0 X#1 Z5.\nG32 Z-20. F#2"
        ),
        "{back}"
    );
    // M98 with a count: a repeat around the call; a named subroutine gets a program number.
    let m98 = "G21 G99\nG0 X30. Z5.\n#100=24.\nM98 P2000 L2\nM30\nO2000\nG0 X#100\nG32 Z-20. F1.5\nG0 X30.\nZ5.\n#100=#100-0.5\nM99\n";
    let ngc = translated(m98, "fanuc", "linuxcnc");
    assert!(
        ngc.contains("o101 repeat [2]\n  o2000 call\no101 endrepeat"),
        "{ngc}"
    );
    let named = "G7 G21 G18\no<pass> sub\n  G0 X#1 Z5\n  G33 Z-20 K1.5\n  G0 X30\n  G0 Z5\no<pass> endsub\no<pass> call [24]\nM2\n";
    let fanuc = translated(named, "linuxcnc", "fanuc");
    assert!(
        fanuc.contains("G65 P1000 A24.\nM2\nO1000 (o<pass>)\nG0 X#1 Z5."),
        "{fanuc}"
    );
    // Haas's M97 local subprogram; GSK has no G65 call: the arguments set, then M98.
    let haas = "G20 G99\nG0 X1. Z0.2\n#100=0.7\nM97 P100 L2\nM30\nN100\nG92 X#100 Z-1. F0.1\n#100=#100-0.02\nM99\n";
    let ngc = translated(haas, "haas", "linuxcnc");
    assert!(ngc.contains("o100 sub\n"), "{ngc}");
    let gsk = translated(named, "linuxcnc", "gsk980");
    assert!(gsk.contains("#1=24\nM98 P1000\nM2"), "{gsk}");
    // Haas: a local subprogram at its sequence number after M30, called by M97.
    let haas = translated(named, "linuxcnc", "haas");
    assert!(
        haas.contains("#1=24\nM97 P1000\nM2\nN1000 (o<pass>)\nG0 X#1 Z5."),
        "{haas}"
    );
}

/// A subroutine whose cycle has no one text for its two calls (LinuxCNC's G76 becomes Fanuc's
/// plain passes, computed from several arguments at once) is written once for each call.
#[test]
fn a_subroutine_whose_blocks_differ_by_call_is_written_for_each_call() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/linuxcnc-sub-two-threads.ngc"),
    )
    .unwrap();
    let fanuc = translated(&text, "linuxcnc", "fanuc");
    assert!(
        fanuc.contains(
            "G65 P1000 A24. B5. C-20. I1.5 J0.92\nG65 P1001 A20. B-25. C-40. I1. J0.61\n"
        ),
        "{fanuc}"
    );
    assert!(
        fanuc.contains("O1000 (o<thread> for the call on line 9)\n"),
        "{fanuc}"
    );
    assert!(
        fanuc.contains("O1001 (o<thread> for the call on line 10)\n"),
        "{fanuc}"
    );
    // The first call's passes: its first at X22.8 (24 − 2·(0.92 − …) as LinuxCNC's G76 cuts).
    assert!(
        fanuc.contains("G0 X22.8 Z5.\nG32 X22.8 Z#3 F1.5"),
        "{fanuc}"
    );
}

#[test]
fn named_parameters_take_free_common_variables() {
    let ngc = "G7 G21 G18\n#<major> = 24\n#<pitch> = 1.5\nG0 X[#<major> + 2] Z5\nG33 Z-20 K#<pitch>\nG0 X30\nM2\n";
    let fanuc = translated(ngc, "linuxcnc", "fanuc");
    assert!(
        fanuc.contains("(#<major> IS #500)\n(#<pitch> IS #501)\nG21 G18\n#500=24\n#501=1.5\nG0 X[#500+2] Z5.\nG32 Z-20. F#501\nG0 X30.\nM2"),
        "{fanuc}"
    );
}

/// The tool's position: Custom Macro B's #5001 (X as the program writes it, a diameter here) and
/// #5002, LinuxCNC's #5420 (the radius) and #5422.
#[test]
fn position_variables_are_each_others() {
    let fanuc = "G21 G99\nG0 X30. Z5.\n#1=#5001-4.\n#2=#5002\nG0 X#1 Z#2\nG32 Z-20. F1.5\nM30\n";
    let ngc = translated(fanuc, "fanuc", "linuxcnc");
    assert!(
        ngc.contains("#1 = [[#5420*2]-4]\n#2 = #5422\nG0 X[#1/2] Z#2"),
        "{ngc}"
    );
    let back = translated(&ngc, "linuxcnc", "fanuc");
    assert!(
        back.contains("#1=[#5001/2]*2-4\n#2=#5002\nG0 X#1 Z#2"),
        "{back}"
    );
}

#[test]
fn expressions_and_functions_in_each_syntax() {
    // Fanuc's one-argument ATAN is LinuxCNC's ATAN[x]/[1]; POW is **; the rest as written.
    let fanuc = "G21 G99\n#1=ATAN[1.]\n#2=POW[2.,3.]\n#3=SQRT[16.]+ABS[-2.]+ROUND[1.4]+FIX[2.7]+FUP[2.2]+[7.MOD3.]\n#4=SIN[30.]*COS[60.]*TAN[45.]\nG0 X[#1+#2+#3+#4] Z5.\nM30\n";
    let ngc = translated(fanuc, "fanuc", "linuxcnc");
    assert!(ngc.contains("#1 = ATAN[1]/[1]\n#2 = [2**3]\n"), "{ngc}");
    assert!(
        ngc.contains("#3 = [SQRT[16]+ABS[-2]+ROUND[1.4]+FIX[2.7]+FUP[2.2]+[7 MOD 3]]"),
        "{ngc}"
    );
    let back = translated(&ngc, "linuxcnc", "fanuc");
    assert!(back.contains("#1=ATAN[1]/[1]\n#2=POW[2,3]\n"), "{back}");
}

#[test]
fn gsk_operations_are_settings_and_jumps() {
    // G65 H01/H03 set #100, H85 jumps back to N10 while #100 ≥ 60: a loop tested at its end.
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/gsk-g65-loop.nc"),
    )
    .unwrap();
    let ngc = translated(&text, "gsk980", "linuxcnc");
    assert!(ngc.contains("#100 = 62\no101 do\n"), "{ngc}");
    assert!(
        ngc.contains("  #100 = [#100-1]\no101 while [#100 GE 60]"),
        "{ngc}"
    );
}

/// Each refusal at its line and column, naming what is missing.
#[test]
fn constructs_without_a_twin_are_refused_at_their_line() {
    let cases: [(&str, &str, &str, u32, u32, &str); 8] = [
        (
            "G21 G99\n#1=1\nGOTO10\nG0 X30. Z5.\nN10 G0 X20. Z5.\nM30\n",
            "fanuc",
            "linuxcnc",
            3,
            1,
            "GOTO 10 on line 3 is neither",
        ),
        (
            "G7 G21\n#<a> = 1\no1 if [EXISTS[#<a>]]\n  G0 X20 Z5\no1 endif\nM2\n",
            "linuxcnc",
            "fanuc",
            0,
            0,
            "EXISTS[#<a>]",
        ),
        (
            "G21 G99\n#1=1\nIF[#1EQ2]THEN#3000=1\nM30\n",
            "fanuc",
            "linuxcnc",
            3,
            14,
            "#3000, a system variable",
        ),
        (
            "G21 G99\n#1=1\nG65 P1000 A1\nM30\nO1000\nG0 X20. Z5.\nM99\n",
            "fanuc",
            "linuxcnc",
            3,
            11,
            "without a decimal point",
        ),
        (
            "G21 G99\n#1=20.\nM98 P1000\nG0 X#1 Z5.\nM30\nO1000\n#1=#1+2.\nM99\n",
            "fanuc",
            "linuxcnc",
            3,
            1,
            "the caller's local variables",
        ),
        (
            "G7 G21\n#1 = 0\no1 while [#1 LT 3]\n  #1 = [#1 + 1]\n  o1 break\no1 endwhile\nM2\n",
            "linuxcnc",
            "fanuc",
            5,
            3,
            "break and continue",
        ),
        (
            "G21 G99\nG0 X20. Z5.\nWHILE[#1LT2]DO1\nG0 U1. W0.\n#1=#1+1\nEND1\nM30\n",
            "fanuc",
            "linuxcnc",
            4,
            1,
            "converts to different blocks on different runs",
        ),
        (
            "G21 G99\n#1=0\nIF[#1EQ0]GOTO10\nG0 X20. Z5.\nN10 M30\n",
            "fanuc",
            "linuxcnc",
            4,
            1,
            "never runs",
        ),
    ];
    for (src, from, to, line, column, what) in cases {
        let d = conv(src, from, to).unwrap_err();
        assert!(d.message.contains(what), "{src}: {}", d.message);
        if line > 0 {
            assert_eq!(
                (d.span.line, d.span.column),
                (line, column),
                "{src}: {}",
                d.message
            );
        }
    }
}

/// The targets with a macro language; the others take a macro program only with `--flatten`.
const MACRO_TARGETS: [&str; 6] = ["fanuc", "fanuc15", "fanuc-b", "gsk980", "haas", "linuxcnc"];

const BEGIN: &str = "<!-- macros:begin (tests/convert_macros.rs writes this table) -->";
const END: &str = "<!-- macros:end -->";

/// Every bundled macro program on every other macro target, without `--flatten`: converted with
/// its structure (and moving as the source does), or refused at a line for a reason; the table is
/// docs/translation.md's (`THREADCUT_BLESS=1` rewrites it).
#[test]
fn macro_examples_keep_their_structure_on_every_macro_target() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let files = [
        ("examples/fanuc-macro-g92-passes.nc", "fanuc"),
        ("examples/fanuc-m98-subprogram.nc", "fanuc"),
        ("examples/gsk-g65-loop.nc", "gsk980"),
        ("examples/haas-m97-g92-passes.nc", "haas"),
        ("examples/linuxcnc-sub-two-threads.ngc", "linuxcnc"),
        (
            "tests/data/real/linuxcnc-named-parameters-g76.ngc",
            "linuxcnc",
        ),
    ];
    let mut rows = vec![
        "| program | to | outcome |".to_string(),
        "|---|---|---|".to_string(),
    ];
    let mut kept = 0;
    for (file, from) in files {
        let text = std::fs::read_to_string(root.join(file)).unwrap();
        for to in BUILT_IN.iter().map(|b| b.0).filter(|t| *t != from) {
            let outcome = match conv(&text, from, to) {
                Ok(out) => {
                    assert!(MACRO_TARGETS.contains(&to), "{file} → {to}");
                    same_motion(&text, &machine(from), &out, &machine(to), 0.0013);
                    let structure = [
                        "WHILE", " while ", " do", " sub", "G65", "M98", " call", "M97", "#",
                    ]
                    .iter()
                    .any(|k| out.contains(k));
                    assert!(structure, "{file} → {to}: no structure\n{out}");
                    kept += 1;
                    "structure kept".to_string()
                }
                Err(d) if MACRO_TARGETS.contains(&to) => {
                    // The message up to its explanation.
                    let what = d
                        .message
                        .split(", and no expression")
                        .next()
                        .unwrap_or_default();
                    format!("refused at line {}: {what}", d.span.line)
                }
                Err(d) => {
                    assert!(
                        d.message.contains("control flow from line"),
                        "{file} → {to}: {}",
                        d.message
                    );
                    continue;
                }
            };
            let name = file.rsplit('/').next().unwrap();
            rows.push(format!(
                "| {name} | {to} | {} |",
                outcome.replace('|', "\\|")
            ));
        }
    }
    assert!(kept >= 20, "{kept} programs kept their structure");
    let table = rows.join("\n");
    let doc_path = root.join("docs/translation.md");
    let doc = std::fs::read_to_string(&doc_path).unwrap();
    let (Some(b), Some(e)) = (doc.find(BEGIN), doc.find(END)) else {
        panic!("docs/translation.md has no macro table; it should be:\n{BEGIN}\n{table}\n{END}");
    };
    if doc[b + BEGIN.len()..e].trim() != table.trim() {
        if std::env::var_os("THREADCUT_BLESS").is_some() {
            std::fs::write(
                &doc_path,
                format!("{}{BEGIN}\n{table}\n{}", &doc[..b], &doc[e..]),
            )
            .unwrap();
        } else {
            panic!("docs/translation.md's macro table is out of date (THREADCUT_BLESS=1 rewrites it):\n{table}");
        }
    }
}

/// A small macro program: passes of a computed depth in a loop, a condition inside, a
/// subprogram with arguments; in Custom Macro B or as o-words.
fn program(passes: u32, depth: f64, pitch: f64, split: u32, ngc: bool) -> String {
    // Each pass's diameter 20 − 2·depth·√(n/passes); the passes after `split` a finer lead... no:
    // the same lead, a different return (the condition's two branches).
    if ngc {
        format!(
            "G7 G21 G18\no<pass> sub\n  G0 X#1 Z5\n  G33 Z-20 K#2\n  o9 if [#3 GT {split}]\n    G0 X24\n  o9 else\n    G0 X26\n  o9 endif\n  G0 Z5\no<pass> endsub\nG0 X26 Z5\n#1 = 1\no1 while [#1 LE {passes}]\n  #4 = [20 - 2 * {depth} * SQRT[#1 / {passes}]]\n  o<pass> call [#4] [{pitch}] [#1]\n  #1 = [#1 + 1]\no1 endwhile\nM2\n"
        )
    } else {
        format!(
            "G21 G99\nG0 X26. Z5.\n#10=1\nWHILE[#10LE{passes}]DO1\n#4=20.-2*{depth}*SQRT[#10/{passes}]\nG65 P1000 A#4 B{pitch:.2} C#10\n#10=#10+1\nEND1\nM30\nO1000\nG0 X#1 Z5.\nG32 Z-20. F#2\nIF[#3LE{split}]GOTO10\nG0 X24.\nGOTO20\nN10 G0 X26.\nN20 G0 Z5.\nM99\n"
        )
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 12, ..ProptestConfig::default() })]

    /// Generated macro programs convert both ways with their structure and move alike.
    #[test]
    fn generated_macro_programs_move_alike(
        passes in 2u32..6,
        depth in 0.5f64..1.2,
        pitch in prop::sample::select(vec![1.0, 1.25, 1.5, 2.0]),
        split in 1u32..5,
        ngc in any::<bool>(),
    ) {
        // Both branches of the condition run (a branch no run reaches is refused).
        let split = split.min(passes - 1);
        let depth = (depth * 1000.0).round() / 1000.0;
        let src = program(passes, depth, pitch, split, ngc);
        let (from, to) = if ngc { ("linuxcnc", "fanuc") } else { ("fanuc", "linuxcnc") };
        let out = conv(&src, from, to).unwrap_or_else(|d| panic!("{d:?}\n{src}"));
        same_motion(&src, &machine(from), &out, &machine(to), 0.0013);
        let back = conv(&out, to, from).unwrap_or_else(|d| panic!("{d:?}\n{out}"));
        same_motion(&src, &machine(from), &back, &machine(from), 0.0013);
    }
}
