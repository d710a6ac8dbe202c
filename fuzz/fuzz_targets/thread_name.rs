//! The standard-thread name parser (`M10x1.25-6g`, `1/2-13 UNC-2A`, …) on arbitrary text: a thread or
//! an error with suggestions, never a panic; every thread it accepts has ordered, finite limits.
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::thread::standard::{self, Surface};

fuzz_target!(|data: &[u8]| {
    let Ok(name) = std::str::from_utf8(data) else {
        return;
    };
    match standard::lookup(name) {
        Ok(t) => {
            for side in [Surface::External, Surface::Internal] {
                let l = t.limits(side);
                for (lo, hi) in [(l.major.min, l.major.max), (l.pitch.min, l.pitch.max), (l.minor.min, l.minor.max)] {
                    if let (Some(lo), Some(hi)) = (lo, hi) {
                        assert!(lo.is_finite() && hi.is_finite() && lo <= hi, "{name}: {lo} > {hi}");
                    }
                }
            }
        }
        Err(_) => {
            let _ = standard::nearest(name, None);
        }
    }
});
