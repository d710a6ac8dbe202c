//! The APT/CL reader, THREAD lowering and `post` to every lathe controller on arbitrary bytes:
//! an error or a program, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::apt;
use threadcut::machine::{Machine, BUILT_IN};

fuzz_target!(|data: &[u8]| {
    if let Ok(jobs) = apt::jobs(data) {
        for job in jobs.iter().take(4) {
            let _ = job.passes();
        }
    }
    for (name, _) in BUILT_IN {
        let machine = Machine::built_in(name).unwrap();
        let _ = apt::post::write(data, &mut Vec::new(), &machine);
    }
});
