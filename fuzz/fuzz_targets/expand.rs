//! Every controller's cycle reader, `expand` (G-code and JSON lines) and the pass tables on arbitrary
//! bytes: an error or an output, never a panic, and never a non-finite number in the output.
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::machine::{Machine, BUILT_IN};
use threadcut::program;

fuzz_target!(|data: &[u8]| {
    for (name, _) in BUILT_IN {
        let machine = Machine::built_in(name).unwrap();
        let mut out = Vec::new();
        if program::expand_gcode(data, &mut out, &machine).is_ok() {
            // Move lines (no comment) never carry a non-finite number; comments and copied lines may
            // say anything ("infeed").
            for line in String::from_utf8_lossy(&out).lines() {
                if line.starts_with('G') && !line.contains('(') && !line.contains(';') {
                    assert!(!line.contains("NaN") && !line.contains("inf"), "{name}: {line}");
                }
            }
        }
        out.clear();
        if program::expand_jsonl(data, &mut out, &machine).is_ok() {
            for line in String::from_utf8_lossy(&out).lines() {
                let v: serde_json::Value = serde_json::from_str(line).expect("valid JSON");
                for key in ["x", "z", "lead"] {
                    if let Some(n) = v.get(key) {
                        assert!(n.as_f64().is_some_and(f64::is_finite), "{name}: {line}");
                    }
                }
            }
        }
        if let Ok(jobs) = program::jobs(data, &machine) {
            for job in jobs.iter().take(4) {
                if let Ok(passes) = job.passes() {
                    assert!(passes.iter().all(|p| p.depth.is_finite() && p.area.is_finite()));
                }
            }
        }
    }
});
