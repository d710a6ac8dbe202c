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
