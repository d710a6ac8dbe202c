//! The milling reader and `check` of a machining centre's program, on every built-in milling
//! controller, on arbitrary bytes: a report (its findings, the reader's error among them), never a
//! panic or a hang (the reader's block bound is kept small here).
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::check::milling::{check, Options};
use threadcut::machine::MILL_BUILT_IN;
use threadcut::mill::profile::MillProfile;
use threadcut::mill::Side;

fuzz_target!(|data: &[u8]| {
    for (i, (name, _)) in MILL_BUILT_IN.iter().enumerate() {
        let profile = MillProfile::built_in(name).unwrap();
        let mut o = Options {
            max_blocks: Some(20_000),
            ..Options::default()
        };
        // Every other controller reads with a thread named, a side and a cutter, which the
        // judging needs; the others as the plain command does.
        if i % 2 == 1 {
            o.thread = threadcut::check::milling::named_thread("M10x1.5").ok();
            o.side = Some(Side::Internal);
            o.tool_diameter = Some(6.0);
        }
        let _ = check(data, &profile, &o);
    }
});
