//! The macro interpreter of every dialect that has one (LinuxCNC o-words and parameters, Fanuc and
//! GSK Macro B, Haas and the Fanuc G-code systems and FS15 format), through `expand` (the program's text and `--flatten`) and the motion stream, on
//! arbitrary bytes: an error or an output, never a panic, a hang or a stack overflow (a small
//! block limit keeps each run short). A flattened program is read back: it must run too.
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::machine::Machine;
use threadcut::program::{self, Options};

fuzz_target!(|data: &[u8]| {
    for name in ["linuxcnc", "fanuc", "gsk980", "haas", "fanuc15", "fanuc-b", "sinumerik"] {
        let machine = Machine::built_in(name).unwrap();
        for flatten in [false, true] {
            let options = Options {
                max_blocks: 20_000,
                flatten,
                ..Options::default()
            };
            let mut out = Vec::new();
            let expanded = program::expand_gcode_with(data, &mut out, &machine, &options);
            if flatten && expanded.is_ok() {
                // The executed program, read back: no control flow is left to run (an error is
                // possible, as for any text; a panic is not).
                let mut again = Vec::new();
                let _ = program::expand_jsonl_with(&out[..], &mut again, &machine, &options);
            }
        }
        let mut out = Vec::new();
        // Also as `passes` reads a cycle shown on its own (its start not stated).
        let options = Options {
            max_blocks: 20_000,
            start: program::Start::Unstated,
            ..Options::default()
        };
        if program::expand_jsonl_with(data, &mut out, &machine, &options).is_ok() {
            for line in String::from_utf8_lossy(&out).lines() {
                assert!(
                    !line.contains("NaN") && !line.contains("inf"),
                    "{name}: {line}"
                );
            }
        }
    }
});
