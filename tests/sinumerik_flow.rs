//! Sinumerik's program flow (`--controller sinumerik`): R parameters and DEF variables in
//! expressions on every address, the functions in degrees and Sinumerik's precedence, labels and
//! GOTOF/GOTOB/GOTO/GOTOC, IF/ELSE/ENDIF, WHILE, FOR, LOOP, REPEAT/UNTIL, PROC subprograms of the
//! same file called by name with parameters and P, RET/M17 — each against the motion computed by
//! hand; a rope-drum style program whose G33 passes a subprogram cuts; a program equal in motion to
//! its Fanuc Macro B twin; and the errors at their line and column.
//! Decisions: docs/dialects/sinumerik.md, "Program flow".

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

fn run(src: &str, controller: &str, options: &Options) -> Result<Vec<Move>, Error> {
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

fn moves(src: &str) -> Vec<Move> {
    run(src, "sinumerik", &Options::default()).unwrap_or_else(|e| panic!("{e}\n{src}"))
}

/// The end points (radius X, Z) of the moves, in order.
fn points(src: &str) -> Vec<(f64, f64)> {
    moves(src).iter().map(|m| (m.x, m.z)).collect()
}

fn error(src: &str) -> Diagnostic {
    error_with(src, &Options::default())
}

fn error_with(src: &str, options: &Options) -> Diagnostic {
    match run(src, "sinumerik", options) {
        Err(Error::Input(d)) => d,
        other => panic!("expected an input error, got {other:?}\n{src}"),
    }
}

/// Points equal at the program's resolution (0.001 mm).
fn assert_points(got: &[(f64, f64)], want: &[(f64, f64)]) {
    assert_eq!(got.len(), want.len(), "got {got:?}\nwant {want:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g.0 - w.0).abs() < 5e-4 && (g.1 - w.1).abs() < 5e-4,
            "move {}: got {g:?}, want {w:?}",
            i + 1
        );
    }
}

const HEAD: &str = "G18 G90 G71 DIAMON\n";

#[test]
fn r_parameters_and_def_variables_in_expressions_on_every_address() {
    let src = format!(
        "{HEAD}R4=60 R21=1.5 R6=-30 R3=2\n\
         DEF REAL STEP=0.25, HALF\n\
         HALF=STEP/2\n\
         G0 X=R4-R21 Z=R6+R3\n\
         G1 X=R4-2*(R21+STEP) Z=-HALF F0.2\n\
         G0 X=R4 Z=R3*R3\n\
         M30\n"
    );
    // X is a diameter (DIAMON); the moves give radii.
    // 60 − 1.5 = 58.5 → 29.25, Z −30 + 2 = −28;
    // 60 − 2·(1.5 + 0.25) = 56.5 → 28.25, Z −0.25/2 = −0.125; 60 → 30, Z 2·2 = 4.
    assert_points(
        &points(&src),
        &[(29.25, -28.0), (28.25, -0.125), (30.0, 4.0)],
    );
}

#[test]
fn functions_in_degrees_and_sinumerik_precedence() {
    let cases: &[(&str, f64)] = &[
        // sqrt(3² + 4²) = 5
        ("SQRT(POT(3)+POT(4))", 5.0),
        ("2*SIN(30)+COS(60)", 1.5),
        ("TAN(45)+ASIN(0.5)/30+ACOS(0.5)/60", 3.0),
        ("ATAN2(1,-1)", 135.0),
        ("ATAN2(-1,-1)", -135.0),
        ("TRUNC(-2.7)+ROUND(2.5)", 1.0),
        ("7 MOD 3 + 7 DIV 2", 4.0),
        ("LN(EXP(2))+ABS(-3)", 5.0),
        ("2+3*4-10/5", 12.0),
        ("-(2-5)*2", 6.0),
        ("1.5EX2/100", 1.5),
        // The comparisons come last, AND before them: R1==1 AND R2==2 is R1==(1 AND R2)==2, which
        // with R1 = 1, R2 = 2 is (1 == 1) == 2, false; parenthesised, true.
        ("R1==1 AND R2==2", 0.0),
        ("(R1==1) AND (R2==2)", 1.0),
        ("NOT R1==0", 1.0),
        ("(R1<>R2) OR (R1>=5)", 1.0),
        ("R1==1 XOR R2==2", 0.0),
    ];
    for (expr, want) in cases {
        let src = format!("{HEAD}R1=1 R2=2\nR9={expr}\nG0 X=2*R9 Z0\nM30\n");
        let got = points(&src);
        assert!(
            (got[0].0 - want).abs() < 5e-4,
            "{expr}: got {}, want {want}",
            got[0].0
        );
    }
}

#[test]
fn labels_and_the_four_jumps() {
    let src = format!(
        "{HEAD}R1=0\n\
         G0 X10 Z0\n\
         GOTOF SKIP\n\
         G0 X99 Z99\n\
         SKIP: G0 X20\n\
         BACK: R1=R1+1\n\
         G0 Z=-R1\n\
         IF R1<3 GOTOB BACK\n\
         GOTO AHEAD\n\
         G0 X98\n\
         AHEAD: GOTOC NOWHERE\n\
         N100 G0 X30\n\
         IF R1==3 GOTOF N200\n\
         G0 X97\n\
         N200 G0 X40 GOTOF DONE\n\
         G0 X96\n\
         DONE: M30\n"
    );
    // X10 Z0; the X99 block skipped; X20; Z −1, −2, −3 (BACK three times); X98 skipped; GOTOC to
    // a label that is nowhere goes on; X30; X97 skipped; X40 and its jump past X96.
    assert_points(
        &points(&src),
        &[
            (5.0, 0.0),
            (10.0, 0.0),
            (10.0, -1.0),
            (10.0, -2.0),
            (10.0, -3.0),
            (15.0, -3.0),
            (20.0, -3.0),
        ],
    );
}

#[test]
fn if_else_endif_while_for_loop_and_repeat() {
    let src = format!(
        "{HEAD}G0 X0 Z0\n\
         R1=2\n\
         IF R1>1\n\
           G0 X10\n\
         ELSE\n\
           G0 X90\n\
         ENDIF\n\
         IF R1>5\n\
           G0 X91\n\
         ENDIF\n\
         WHILE R1<4\n\
           R1=R1+1\n\
           G0 Z=-R1\n\
         ENDWHILE\n\
         DEF INT I\n\
         FOR I=1 TO 3\n\
           G0 X=20+I\n\
         ENDFOR\n\
         R2=0\n\
         LOOP\n\
           R2=R2+1\n\
           IF R2>2 GOTOF OUT\n\
           G0 Z=R2\n\
         ENDLOOP\n\
         OUT: REPEAT\n\
           R2=R2-1\n\
           G0 X=R2*10\n\
         UNTIL R2<=1\n\
         M30\n"
    );
    // IF takes X10 (not X90, not X91); WHILE: Z −3, −4; FOR: X 21, 22, 23; LOOP: Z 1, 2 then
    // out at R2 = 3; REPEAT: R2 2 → X20, 1 → X10, until R2 <= 1.
    assert_points(
        &points(&src),
        &[
            (0.0, 0.0),
            (5.0, 0.0),
            (5.0, -3.0),
            (5.0, -4.0),
            (10.5, -4.0),
            (11.0, -4.0),
            (11.5, -4.0),
            (11.5, 1.0),
            (11.5, 2.0),
            (10.0, 2.0),
            (5.0, 2.0),
        ],
    );
}

#[test]
fn repeat_with_labels_runs_a_section_again() {
    let src = format!(
        "{HEAD}R1=0\n\
         G0 X0 Z0\n\
         START: R1=R1+1\n\
         G0 Z=-R1\n\
         REPEAT START P=2\n\
         ONE: R1=R1+1 G0 X=R1*2\n\
         REPEATB ONE P=2\n\
         REPEAT START ONE\n\
         M30\n"
    );
    // START..(the block before REPEAT) has run once; P=2 runs it twice more: Z −1, −2, −3.
    // ONE: R1 4, X8 (radius 4); REPEATB runs that block twice more: radius 5, 6.
    // REPEAT START ONE runs START to ONE once more, the inner REPEAT with it: Z −7, then −8 and
    // −9, then ONE: R1 10, radius 10.
    assert_points(
        &points(&src),
        &[
            (0.0, 0.0),
            (0.0, -1.0),
            (0.0, -2.0),
            (0.0, -3.0),
            (4.0, -3.0),
            (5.0, -3.0),
            (6.0, -3.0),
            (6.0, -7.0),
            (6.0, -8.0),
            (6.0, -9.0),
            (10.0, -9.0),
        ],
    );
    let e = error(&format!("{HEAD}R1=0\nREPEAT NOWHERE P=2\nM30\n"));
    assert!(e.message.contains("NOWHERE") && e.span.line == 3, "{e}");
}

#[test]
fn procs_called_by_name_with_parameters_and_a_repeat_count() {
    let src = format!(
        "{HEAD}G0 X50 Z5\n\
         R10=0\n\
         STEP_IN(40, -10)\n\
         CALL \"COUNT\"\n\
         COUNT P3\n\
         STEP_IN(30)\n\
         M30\n\
         PROC STEP_IN(REAL DIA, REAL ZEND)\n\
         DEF REAL HALF=DIA/2\n\
         G1 X=DIA Z=ZEND F0.1\n\
         G0 X=DIA+HALF\n\
         RET\n\
         PROC COUNT\n\
         R10=R10+1\n\
         G0 Z=R10\n\
         M17\n"
    );
    // STEP_IN(40, −10): X40 Z−10, then X60; COUNT once (Z1), three times (Z2, Z3, Z4);
    // STEP_IN(30): ZEND not given is 0: X30 Z0, X45.
    assert_points(
        &points(&src),
        &[
            (25.0, 5.0),
            (20.0, -10.0),
            (30.0, -10.0),
            (30.0, 1.0),
            (30.0, 2.0),
            (30.0, 3.0),
            (30.0, 4.0),
            (15.0, 0.0),
            (22.5, 0.0),
        ],
    );
}

/// A rope-drum style program: the main program sets R parameters and calls its subprogram once
/// per infeed; the subprogram cuts one G33 pass per start of a two-start groove, counting the
/// starts with a label, `IF … GOTOF` and `GOTOB`.
const DRUM: &str = "; two-start groove, three infeeds\n\
G18 G90 G71 DIAMON\n\
G0 X70 Z10\n\
R5=8 R6=-60 R4=64 R2=2 ; lead, end of thread, diameter, starts\n\
R21=0\n\
GROOVE\n\
R21=0.6\n\
GROOVE\n\
R21=1.0\n\
GROOVE\n\
G0 X100 Z50\n\
M30\n\
\n\
PROC GROOVE\n\
R1=0\n\
NEXT: R3=R1*R5/R2 ; the start's shift along Z\n\
G0 X=R4-R21 Z=10+R3\n\
G33 Z=R6+R3 K=R5\n\
G0 X70\n\
Z=10\n\
R1=R1+1\n\
IF R1==R2 GOTOF LAST\n\
GOTOB NEXT\n\
LAST: M17\n";

#[test]
fn a_rope_drum_program_cuts_its_passes_in_a_subprogram() {
    let got = moves(DRUM);
    // Per call, R21 = d: pass X = 64 − d (radius 32 − d/2); start 0 from Z10 to Z−60, start 1
    // shifted by 1·8/2 = 4: from Z14 to Z−56; each thread move with lead 8; out to X70 (radius 35)
    // and back to Z10.
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
            assert_eq!(g.line, 18, "the G33 block of the subprogram");
        }
    }
}

#[test]
fn a_sinumerik_program_moves_as_its_fanuc_macro_twin() {
    let sinumerik = "G18 G90 G71 DIAMON\n\
        G0 X60 Z5\n\
        DEF REAL DEPTH=0.4\n\
        R1=0\n\
        WHILE R1<4\n\
        R1=R1+1\n\
        G0 X=58-R1*DEPTH Z5\n\
        G33 Z-30 K2\n\
        G0 X62\n\
        IF R1==2\n\
        G0 Z=5+SQRT(4)\n\
        ENDIF\n\
        ENDWHILE\n\
        M30\n";
    let fanuc = "G21 G18 G99\n\
        G0 X60. Z5.\n\
        #2=0.4\n\
        #1=0\n\
        WHILE [#1 LT 4] DO1\n\
        #1=#1+1\n\
        G0 X[58-#1*#2] Z5.\n\
        G32 Z-30. F2.\n\
        G0 X62.\n\
        IF [#1 NE 2] GOTO 10\n\
        G0 Z[5+SQRT[4]]\n\
        N10 END1\n\
        M30\n";
    let a = moves(sinumerik);
    let b = run(fanuc, "fanuc", &Options::default()).unwrap_or_else(|e| panic!("{e}"));
    // Four passes: X 58 − 0.4·n, Z5 → Z−30 with lead 2, out to X62; after the second, Z7.
    assert_eq!(a.len(), 1 + 4 * 3 + 1, "{a:?}");
    assert_eq!(a.len(), b.len());
    for (m, n) in a.iter().zip(&b) {
        assert_eq!(m.kind, n.kind);
        assert_eq!(m.lead, n.lead);
        assert!(
            (m.x - n.x).abs() < 5e-4 && (m.z - n.z).abs() < 5e-4,
            "{m:?} {n:?}"
        );
    }
    assert!(
        (a[4].x - 28.6).abs() < 5e-4,
        "second pass: X57.2 is radius 28.6"
    );
}

#[test]
fn errors_at_their_line_and_column_naming_the_word() {
    // A label that is nowhere.
    let e = error(&format!("{HEAD}G0 X10 Z0\nIF 1==1 GOTOF FINISH\nM30\n"));
    assert_eq!((e.span.line, e.span.column), (3, 9), "{e}");
    assert!(
        e.message.contains("GOTOF FINISH") && e.message.contains("14080"),
        "{e}"
    );
    // GOTOB looks only backward: its label after it is not found.
    let e = error(&format!("{HEAD}G0 X10 Z0\nGOTOB AHEAD\nAHEAD: M30\n"));
    assert_eq!((e.span.line, e.span.column), (3, 1), "{e}");
    assert!(e.message.contains("GOTOB AHEAD") && e.message.contains("before this block"));
    // A loop that never ends stops at the bound, naming its lines.
    let options = Options {
        max_blocks: 500,
        ..Options::default()
    };
    let e = error_with(
        &format!("{HEAD}G0 X0 Z0\nTOP: G0 X1\nGOTOB TOP\nM30\n"),
        &options,
    );
    assert!(
        e.message.contains("lines 3 to 4") && e.message.contains("500"),
        "{e}"
    );
    // An R parameter never set, a variable never declared, a structure never closed.
    let e = error(&format!("{HEAD}G0 X=R7+1 Z0\nM30\n"));
    assert_eq!((e.span.line, e.span.column), (2, 6), "{e}");
    assert!(e.message.contains("R7"), "{e}");
    let e = error(&format!(
        "{HEAD}R1=0\nIF R1==0 GOTOF L1\nL1: G0 X=DEPTH Z0\nM30\n"
    ));
    assert!(e.message.contains("DEPTH") && e.span.line == 4, "{e}");
    let e = error(&format!("{HEAD}R1=1\nWHILE R1<3\nR1=R1+1\nM30\n"));
    assert!(e.message.contains("WHILE without ENDWHILE"), "{e}");
    assert_eq!((e.span.line, e.span.column), (3, 1), "{e}");
    let e = error(&format!("{HEAD}R1=0\nENDIF\nM30\n"));
    assert!(
        e.message.contains("ENDIF without") && e.span.line == 3,
        "{e}"
    );
    // A call of a subprogram with more arguments than its parameters; one never returning.
    let e = error(&format!(
        "{HEAD}R1=0\nSUB(1,2)\nM30\nPROC SUB(REAL A)\nRET\n"
    ));
    assert!(e.message.contains("12340") && e.span.line == 3, "{e}");
    let e = error(&format!("{HEAD}R1=0\nSUB\nM30\nPROC SUB\nG0 X1 Z1\n"));
    assert!(e.message.contains("without RET or M17"), "{e}");
    // Division by zero.
    let e = error(&format!("{HEAD}R1=0\nR2=5/R1\nM30\n"));
    assert!(
        e.message.contains("division by zero") && e.span.line == 3,
        "{e}"
    );
}

#[test]
fn programs_without_flow_still_stream_and_mixed_blocks_go_to_the_dialect() {
    // A program whose parameters are plain values is read as before; SF= and CYCLE97 with R
    // parameters set by the interpreter are read by the dialect with their values.
    let src = format!(
        "{HEAD}G0 X40 Z5\n\
         R1=0\n\
         WHILE R1<1\n\
         R1=R1+1\n\
         R7=90\n\
         ENDWHILE\n\
         SF=R7\n\
         G33 Z-20 K2\n\
         M30\n"
    );
    let m = moves(&src);
    assert_eq!(m.len(), 2, "{m:?}");
    assert_eq!(m[1].lead, Some(2.0));
}

#[test]
fn flatten_writes_straight_line_code_that_moves_the_same() {
    // The rope-drum program, and a program whose SF= and CYCLE97 (read by the dialect as written)
    // take R parameters set inside a loop: flattened, the values come before the lines that read
    // them, and the straight-line program moves as the original.
    let mixed = format!(
        "{HEAD}G0 X40 Z5\n\
         R1=0\n\
         WHILE R1<1\n\
         R1=R1+1\n\
         R7=90 R8=1.5\n\
         ENDWHILE\n\
         SF=R7\n\
         G33 Z-20 K2\n\
         G0 X40\n\
         CYCLE97(R8,,0,-30,24,24,4,2,0.92,0.05,30,0,6,2,3,1)\n\
         M30\n"
    );
    for src in [DRUM.to_string(), mixed] {
        let machine = Machine::built_in("sinumerik").unwrap();
        let mut out = Vec::new();
        let options = Options {
            flatten: true,
            ..Options::default()
        };
        program::expand_gcode_with(src.as_bytes(), &mut out, &machine, &options)
            .unwrap_or_else(|e| panic!("{e}\n{src}"));
        let flat = String::from_utf8(out).unwrap();
        assert!(!flat.contains("GOTO") && !flat.contains("WHILE"), "{flat}");
        let (a, b) = (moves(&src), moves(&flat));
        assert_eq!(a.len(), b.len(), "{flat}");
        for (m, n) in a.iter().zip(&b) {
            assert_eq!((&m.kind, m.lead), (&n.kind, n.lead), "{flat}");
            assert!(
                (m.x - n.x).abs() < 5e-4 && (m.z - n.z).abs() < 5e-4,
                "{m:?} {n:?}\n{flat}"
            );
        }
    }
}
