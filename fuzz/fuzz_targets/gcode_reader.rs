//! The G-code reader on arbitrary bytes: every line lexes or gives a diagnostic; never a panic, and
//! every span points inside the input.
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::gcode::Reader;

fuzz_target!(|data: &[u8]| {
    let mut reader = Reader::new(data);
    while let Some(line) = reader.next_line() {
        match line {
            Ok(line) => {
                for w in line.words {
                    assert!(w.value.is_finite());
                    assert!(w.span.start + u64::from(w.span.len) <= data.len() as u64);
                }
            }
            Err(d) => {
                assert!(d.span.start <= data.len() as u64);
                assert!(d.span.line >= 1);
                break;
            }
        }
    }
});
