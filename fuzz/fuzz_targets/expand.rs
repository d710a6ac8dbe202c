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
            let text = String::from_utf8_lossy(&out);
            assert!(!text.contains("NaN") && !text.contains("inf"), "{name}: {text}");
        }
        out.clear();
        if program::expand_jsonl(data, &mut out, &machine).is_ok() {
            let text = String::from_utf8_lossy(&out);
            assert!(!text.contains("null") && !text.contains("NaN"), "{name}: {text}");
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
