//! Native cycles are written only when reading them back reproduces the motion.

use threadcut::machine::Machine;
use threadcut::program;
use threadcut::translate::{job_to_string, Written};

#[test]
fn gsk_g78_round_trips_as_a_native_cycle() {
    let gsk = Machine::built_in("gsk980").unwrap();
    for src in [
        "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n",
        "G0 X20 Z5\nG78 P010460 Q0.05 R0.02 E0.5\nG78 X24 Z-20 P0.8 Q0.2 I20\n",
        "G0 X50 Z2\nG78 P030360 Q0.1 R0.05 D0 L2\nG78 U-12 W-32 R-1 P1.2 Q0.3 F2.5\n",
    ] {
        let jobs = program::jobs(src.as_bytes(), &gsk).unwrap();
        let (text, written) = job_to_string(&gsk, &jobs[0]).unwrap();
        assert_eq!(written, Written::Native, "{src}\n{text}");
        assert!(text.starts_with("G78 P"), "{text}");
    }
}

#[test]
fn a_job_g78_cannot_express_falls_back_to_plain_moves_and_says_why() {
    let gsk = Machine::built_in("gsk980").unwrap();
    let src = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3\n";
    let mut job = program::jobs(src.as_bytes(), &gsk).unwrap().remove(0);
    job.lead.starts = 100;
    let (text, written) = job_to_string(&gsk, &job).unwrap();
    assert!(
        matches!(written, Written::Plain(ref why) if why.contains("1 to 99 starts")),
        "{written:?}"
    );
    assert!(text.starts_with("(threadcut: plain moves, not the native cycle: G78 allows 1 to 99 starts and 1 to 99 finishing passes)\nG0 X"), "{text}");
}

#[test]
fn a_variable_lead_is_never_written_as_a_constant_one() {
    // Neither G78 nor GSK's G32 can cut a lead that changes every revolution: an error, not G32 moves.
    let gsk = Machine::built_in("gsk980").unwrap();
    let src = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3\n";
    let mut job = program::jobs(src.as_bytes(), &gsk).unwrap().remove(0);
    job.lead.dlead = 0.01;
    match job_to_string(&gsk, &job) {
        Err(program::Error::Input(d)) => {
            assert_eq!(d.code, threadcut::diag::Code::Unsupported);
            assert_eq!(d.span.line, 3);
            assert!(d.message.contains("no variable-lead move"), "{}", d.message);
        }
        other => panic!("{other:?}"),
    }
}
