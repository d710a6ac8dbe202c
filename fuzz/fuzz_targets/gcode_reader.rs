//! The G-code reader on arbitrary bytes: every line lexes or gives a diagnostic; never a panic, and
//! every span points inside the input. The first byte picks the syntax: the shared one, OmniTurn's
//! bare flags, LinuxCNC's blanks anywhere and nested comments refused, or Sinumerik's parentheses
//! that are no comments and lines handed over unread.
#![no_main]

use libfuzzer_sys::fuzz_target;
use threadcut::gcode::{Reader, Syntax};

fuzz_target!(|data: &[u8]| {
    let syntax = match data.first().map(|b| b % 4) {
        Some(1) => Syntax {
            bare: b"PCO",
            ..Syntax::default()
        },
        Some(2) => Syntax {
            blanks_anywhere: true,
            nested_comment_error: true,
            ..Syntax::default()
        },
        Some(3) => threadcut::dialect::sinumerik::SYNTAX,
        _ => Syntax::default(),
    };
    let mut reader = Reader::new(data).with_syntax(syntax);
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
