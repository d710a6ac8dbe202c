//! Motions a control has and threadcut does not follow — hole-machining canned cycles, rigid
//! tapping, probing, splines — are refused at their word (E009), never read as something else.
//! Before, a Fanuc G83 or a LinuxCNC G33.1 block took the modal G0 and was streamed as a rapid
//! to its Z: into the part, and the tool left there for the moves after it.

use threadcut::diag::Code;
use threadcut::machine::Machine;
use threadcut::program;

/// The refusal of `src` on `controller`: (line, column, message).
fn refusal(controller: &str, src: &str) -> (u32, u32, String) {
    let machine = Machine::built_in(controller).unwrap();
    let mut out = Vec::new();
    match program::expand_jsonl(src.as_bytes(), &mut out, &machine) {
        Err(program::Error::Input(d)) => {
            assert_eq!(d.code, Code::Unsupported, "{controller}: {}", d.message);
            (d.span.line, d.span.column, d.message)
        }
        other => panic!(
            "{controller}: {src:?} was read ({:?}): {}",
            other.map(|_| ()),
            String::from_utf8_lossy(&out)
        ),
    }
}

#[test]
fn fanuc_family_hole_cycles_are_refused_at_their_word() {
    let src = "G21 G99\nG0 X0 Z5.\nS300 M3\nG83 Z-10. Q2000 F0.1\nG0 X50. Z50.\nM30\n";
    for c in ["fanuc", "fanuc-b", "fanuc15", "haas"] {
        let (line, column, message) = refusal(c, src);
        assert_eq!((line, column), (4, 1), "{c}");
        assert!(
            message
                .starts_with("G83 (peck drilling cycle) is a motion threadcut does not follow yet"),
            "{c}: {message}"
        );
    }
    let (line, _, message) = refusal("haas", &src.replace("G83 Z-10. Q2000", "G84 Z-10."));
    assert_eq!(line, 4);
    assert!(message.starts_with("G84 (tapping cycle)"), "{message}");
    let (line, _, message) = refusal("gsk980", &src.replace("G83 Z-10. Q2000", "G84 Z-10."));
    assert_eq!(line, 4);
    assert!(
        message.starts_with("G84 (end-face rigid tapping cycle)"),
        "{message}"
    );
}

#[test]
fn linuxcnc_rigid_tapping_probing_splines_and_canned_cycles_are_refused() {
    // rs274 runs G33.1 as RIGID_TAP (in, the spindle reversed, back to the start) and G38.2 as
    // STRAIGHT_PROBE: neither is a rapid, which is what the block read as before.
    let head = "G18 G21 G90 G95\nT1 M6\nS300 M3\nG0 X0 Z5\n";
    for (block, starts) in [
        ("G33.1 Z-20 K1.5", "G33.1 (rigid tapping move"),
        ("G38.2 Z-10 F100", "G38.2 (probing move"),
        ("G5.2 X1 Z1 P1", "G5.2 (NURBS block"),
        ("G17 G81 Z-10 R1 F100", "G81 (drilling cycle)"),
        (
            "G73 Z-10 R1 Q1 F100",
            "G73 (drilling cycle with chip breaking)",
        ),
    ] {
        let (line, _, message) = refusal("linuxcnc", &format!("{head}{block}\nG0 X50 Z50\nM2\n"));
        assert_eq!(line, 5, "{block}");
        assert!(message.starts_with(starts), "{block}: {message}");
    }
    // G33 itself, and G80 (no motion), still read.
    let machine = Machine::built_in("linuxcnc").unwrap();
    let mut out = Vec::new();
    program::expand_jsonl(
        format!("{head}G33 Z-20 K1.5\nG80\nG0 X50 Z50\nM2\n").as_bytes(),
        &mut out,
        &machine,
    )
    .unwrap();
    assert!(String::from_utf8(out)
        .unwrap()
        .contains("\"kind\":\"thread\""));
}
