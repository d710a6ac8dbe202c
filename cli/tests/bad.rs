//! The bad-input corpus (tests/bad/): every malformed program stops with its expected first
//! diagnostic, exit status 2, and no output file.

use std::path::Path;
use std::process::Command;

#[derive(serde::Deserialize)]
struct Corpus {
    case: Vec<Case>,
}

#[derive(serde::Deserialize)]
struct Case {
    file: String,
    /// `expand` (the default) or `post` (APT input).
    #[serde(default = "expand")]
    command: String,
    controller: String,
    code: String,
    at: String,
    says: String,
}

fn expand() -> String {
    "expand".to_string()
}

#[test]
fn every_bad_program_gets_its_diagnostic_and_leaves_no_file() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/bad");
    let corpus: Corpus =
        toml::from_str(&std::fs::read_to_string(root.join("cases.toml")).unwrap()).unwrap();
    assert!(
        corpus.case.len() >= 80,
        "the corpus shrank to {}",
        corpus.case.len()
    );
    let out_dir = std::env::temp_dir().join(format!("threadcut-bad-{}", std::process::id()));
    std::fs::create_dir_all(&out_dir).unwrap();
    let mut failures = Vec::new();
    for case in &corpus.case {
        let input = root.join(&case.file);
        let output = out_dir.join("out.nc");
        let run = Command::new(env!("CARGO_BIN_EXE_threadcut"))
            .args([
                case.command.as_str(),
                input.to_str().unwrap(),
                "--controller",
                &case.controller,
                "-o",
            ])
            .arg(&output)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&run.stderr);
        let first = stderr.lines().next().unwrap_or("");
        let place = format!("{}:{}", input.display(), case.at);
        let problems = [
            (
                run.status.code() != Some(2),
                format!("exit status {:?}", run.status.code()),
            ),
            (
                !first.contains(&format!("[{}]", case.code)),
                format!("first line {first:?}"),
            ),
            (
                !first.contains(&case.says),
                format!("message lacks {:?}", case.says),
            ),
            (
                !stderr.contains(&place),
                format!("no {place} in {stderr:?}"),
            ),
            (output.exists(), "an output file was written".to_string()),
            (
                std::fs::read_dir(&out_dir).unwrap().count() != 0,
                "a temporary file was left".to_string(),
            ),
            (stderr.contains("panicked"), "panic".to_string()),
        ];
        for (bad, what) in problems {
            if bad {
                failures.push(format!("{}: {what}", case.file));
            }
        }
        let _ = std::fs::remove_file(&output);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
