//! What the process benchmarks share: finding a binary, running it, and the binary of another
//! revision to pair with (`THREADCUT_BASE_BIN`). Each bench uses a part of it.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// The first of `candidates` that exists as a file, or the program found on the `PATH`.
pub fn find_binary(env: &str, candidates: &[PathBuf], on_path: Option<&str>) -> Option<PathBuf> {
    if let Some(p) = std::env::var_os(env) {
        let p = PathBuf::from(p);
        return p.is_file().then_some(p);
    }
    if let Some(p) = candidates.iter().find(|p| p.is_file()) {
        return Some(p.clone());
    }
    let name = on_path?;
    std::env::split_paths(&std::env::var_os("PATH")?)
        .map(|dir| dir.join(name))
        .find(|p| p.is_file())
}

/// Runs `bin args…` to completion, its output to the null device (standard error kept for the
/// message); panics if it fails.
pub fn run(bin: &Path, args: &[&str]) {
    let out = Command::new(bin)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{} {args:?}: {}: {}",
        bin.display(),
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The `threadcut` command built from another revision (`THREADCUT_BASE_BIN`), to run in the same
/// benchmark run as this one: before and after a change, paired.
pub fn base_binary() -> Option<PathBuf> {
    find_binary("THREADCUT_BASE_BIN", &[], None)
}

/// Runs `bin args…` to completion, its output to the null device, whatever its exit status (a
/// `check` that finds errors exits 2); panics only if it cannot run or is killed.
pub fn run_any(bin: &Path, args: &[&str]) {
    let status = Command::new(bin)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .unwrap();
    assert!(
        status.code().is_some(),
        "{} {args:?}: {status}",
        bin.display()
    );
}
