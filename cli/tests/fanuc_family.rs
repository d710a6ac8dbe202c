//! The Fanuc family on the command line: Haas, the FS15 program format and G-code system B run on
//! their bundled examples, and a one-block G76 given to a two-block control fails with its place.

use std::process::{Command, Output};

fn threadcut(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_threadcut"))
        .args(args)
        .output()
        .expect("run threadcut")
}

fn example(name: &str) -> String {
    format!("{}/../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn ok(out: Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn bundled_examples_expand_plan_and_check_clean() {
    for (file, controller, cycles) in [
        ("haas-3-4-10-p2.nc", "haas", 1),
        ("haas-m24x3-two-start.nc", "haas", 2),
        ("fanuc15-m30x2-g76.nc", "fanuc15", 1),
        ("fanuc-b-m20x1.5-g78.nc", "fanuc-b", 7),
    ] {
        let path = example(file);
        let text = ok(threadcut(&["expand", &path, "-c", controller]));
        assert_eq!(
            text.matches("(threadcut: ").count(),
            cycles,
            "{file}: {text}"
        );
        // No cycle is left in the expansion.
        assert!(
            !text
                .lines()
                .any(|l| l.starts_with("G76 X") || l.starts_with("G78 X")),
            "{file}: {text}"
        );
        let json = ok(threadcut(&["passes", "--json", &path, "-c", controller]));
        assert!(json.contains("\"passes\""), "{file}: {json}");
        // Measured from the part's face at Z0, every cycle reaches its depth with room to run up.
        let check = threadcut(&["check", &path, "-c", controller, "--stock-start", "0"]);
        assert!(
            check.status.success(),
            "{file}: {}",
            String::from_utf8_lossy(&check.stderr)
        );
    }
    // The second start of the Haas example: the start angle on each pass's first G32.
    let text = ok(threadcut(&[
        "expand",
        &example("haas-m24x3-two-start.nc"),
        "-c",
        "haas",
    ]));
    assert_eq!(text.matches(" Q180000\n").count(), 10, "{text}");
    // In G-code system B the thread move is G33.
    let text = ok(threadcut(&[
        "expand",
        &example("fanuc-b-m20x1.5-g78.nc"),
        "-c",
        "fanuc-b",
    ]));
    assert!(text.contains("G33 X18.16 Z-23.5 F1.5\n"), "{text}");
}

#[test]
fn jsonl_carries_the_start_angle() {
    let text = ok(threadcut(&[
        "expand",
        &example("haas-m24x3-two-start.nc"),
        "-c",
        "haas",
        "--format",
        "jsonl",
    ]));
    let with_phase = text.lines().filter(|l| l.contains("\"phase\":180")).count();
    let threads_of_line_10 = text
        .lines()
        .filter(|l| l.contains("\"kind\":\"thread\"") && l.contains("\"line\":10"))
        .count();
    assert!(with_phase > 0);
    assert_eq!(with_phase, threads_of_line_10, "{text}");
    assert!(!text
        .lines()
        .any(|l| l.contains("\"line\":9") && l.contains("phase")));
}

#[test]
fn a_haas_program_on_fanuc_names_the_right_controllers() {
    let out = threadcut(&["expand", &example("haas-3-4-10-p2.nc"), "-c", "fanuc"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("haas-3-4-10-p2.nc:11:21"), "{err}");
    assert!(
        err.contains("one-block G76") && err.contains("--controller haas"),
        "{err}"
    );
}

#[test]
fn convert_rewrites_between_g_code_systems() {
    // System A to B: G99 is G95, the two-block G76 the same, the header in B's words (G90 for
    // absolute distances, which system A has no code for).
    let text = ok(threadcut(&[
        "convert",
        &example("fanuc-m30x2-g76.nc"),
        "--from",
        "fanuc",
        "--to",
        "fanuc-b",
    ]));
    assert!(
        text.starts_with("%\nO0001 (M30x2 external thread, G76)\n(threadcut convert: fanuc to fanuc-b, mm, feed per revolution)\nG21 G90 G18 G95 G97\nG21 G95"),
        "{text}"
    );
    assert!(
        text.contains("G21 G95\nT0101\nG97 S600 M3\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n"),
        "{text}"
    );
    // B to A: the single-pass G78 is G92, G92 S (the spindle limit) is G50 S.
    let text = ok(threadcut(&[
        "convert",
        &example("fanuc-b-m20x1.5-g78.nc"),
        "--from",
        "fanuc-b",
        "--to",
        "fanuc",
    ]));
    assert!(
        text.contains("\nG50 S2500\n") && text.contains("\nG92 X19.4 Z-25. F1.5\n"),
        "{text}"
    );
    // Haas and the FS15 format are system A: their cycles convert through the model.
    let dir = std::env::temp_dir().join(format!("threadcut-ff-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("fs15.nc");
    std::fs::write(
        &file,
        "G21 G99\nG00 X32. Z5.\nG76 X27.546 Z-30. K1.227 D0.4 F2. A60 P1\nG00 X100.\n",
    )
    .unwrap();
    let text = ok(threadcut(&[
        "convert",
        file.to_str().unwrap(),
        "--from",
        "fanuc15",
        "--to",
        "fanuc",
    ]));
    assert!(
        text.contains("G76 P011060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n"),
        "{text}"
    );
}
