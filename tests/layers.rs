//! The layering rule of docs/architecture.md ("Layers"), checked on the source: every module of the
//! library uses only modules on lower floors. A `crate::name` path or a `use crate::{…}` list in a
//! module's files (outside its `#[cfg(test)]` part and comments) is a use of `name`.

use std::collections::BTreeMap;
use std::fs;
use std::path::Path;

/// The floors, from the ground up; the same table as docs/architecture.md.
const FLOORS: &[&[&str]] = &[
    &["units", "diag", "eol", "text"],
    &["thread", "machine"],
    &["toolpath", "sim"],
    &["post", "turning", "part"],
    &["gcode", "mill"],
    &["interp"],
    &["dialect"],
    &["program", "millprog"],
    &["translate"],
    &["convert", "apt"],
    &["threads", "source"],
    &["check", "render"],
    &["commands"],
];

fn floor_of(module: &str) -> Option<usize> {
    FLOORS.iter().position(|f| f.contains(&module))
}

/// The code of a file without its test module and its comments.
fn code(text: &str) -> String {
    let text = text.split("#[cfg(test)]").next().unwrap_or_default();
    text.lines()
        .map(|l| l.split("//").next().unwrap_or_default())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The library modules that `text` uses by path.
fn uses(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut rest = text;
    while let Some(i) = rest.find("crate::") {
        rest = &rest[i + "crate::".len()..];
        if let Some(list) = rest.strip_prefix('{') {
            let end = list.find('}').unwrap_or(list.len());
            for item in list[..end].split(',') {
                let name: String = item
                    .trim()
                    .chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect();
                out.push(name);
            }
        } else {
            out.push(
                rest.chars()
                    .take_while(|c| c.is_alphanumeric() || *c == '_')
                    .collect(),
            );
        }
    }
    out
}

fn files(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

#[test]
fn every_module_uses_only_lower_floors() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut all = Vec::new();
    files(&src, &mut all);
    let mut wrong: BTreeMap<String, Vec<String>> = BTreeMap::new();
    let mut seen = 0;
    for path in all {
        let rel = path.strip_prefix(&src).unwrap();
        let first = rel
            .components()
            .next()
            .unwrap()
            .as_os_str()
            .to_string_lossy();
        let module = first.trim_end_matches(".rs").to_string();
        if module == "lib" {
            continue;
        }
        let Some(mine) = floor_of(&module) else {
            panic!(
                "module `{module}` is on no floor of tests/layers.rs (and docs/architecture.md)"
            );
        };
        seen += 1;
        for used in uses(&code(&fs::read_to_string(&path).unwrap())) {
            if used == module || used.is_empty() {
                continue;
            }
            let Some(theirs) = floor_of(&used) else {
                panic!(
                    "{} uses `crate::{used}`, which is on no floor",
                    rel.display()
                );
            };
            if theirs >= mine {
                wrong
                    .entry(format!("{} (floor {})", rel.display(), mine + 1))
                    .or_default()
                    .push(format!("{used} (floor {})", theirs + 1));
            }
        }
    }
    assert!(seen > 50, "only {seen} files read");
    assert!(
        wrong.is_empty(),
        "modules that use a module on their own or a higher floor: {wrong:#?}"
    );
}

#[test]
fn the_reader_of_uses_sees_paths_and_lists() {
    assert_eq!(
        uses(
            "use crate::diag::{Code};\nuse crate::{gcode::Line, units};\nlet x = crate::post::f();"
        ),
        ["diag", "gcode", "units", "post"]
    );
    assert_eq!(
        code("a // crate::x\n#[cfg(test)]\nmod tests { crate::y }"),
        "a "
    );
}
