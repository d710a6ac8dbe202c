//! `check --thread` says what the machinist will measure (issue 27): the measurement over wires of
//! the thread a program cuts, next to the class's window, and the depth change that brings the
//! pitch diameter to the window's middle — one program per form, its M computed by hand.
//!
//! With no tool tip given, check assumes the standard's root form: the tool then leaves the pitch
//! line the basic profile's distance above the root it reaches (60° and 55°: 2H/3 on the diameter
//! above the root; trapezoidal and Acme: 2·h3 − (d − d2)), so the cut pitch diameter E follows
//! from the program's root X. M (best wire, NBS H28 with the lead angle) =
//! E − P·cot α/2 + w·(1 + cosec α) + w·½·tan²λ·cos α·cot α, tan λ = P/(π·E).

use threadcut::check::{check, Options, Source};
use threadcut::machine::Machine;
use threadcut::thread::standard::lookup;

/// The check's notes for `src` judged against `thread`.
fn notes(src: &str, controller: &str, thread: &str) -> String {
    let m = Machine::built_in(controller).unwrap();
    let opts = Options {
        thread: Some(lookup(thread).unwrap()),
        ..Options::default()
    };
    let r = check(src.as_bytes(), Source::Gcode(&m), &opts).unwrap();
    r.notes
        .iter()
        .map(|n| n.message.clone())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The number after `key` in `text`.
fn number_after(text: &str, key: &str) -> f64 {
    let at = text
        .find(key)
        .unwrap_or_else(|| panic!("no `{key}` in {text}"));
    let rest = &text[at + key.len()..];
    let n: String = rest
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    n.parse()
        .unwrap_or_else(|_| panic!("no number after `{key}` in {text}"))
}

fn close(got: f64, want: f64, tol: f64, what: &str) {
    assert!((got - want).abs() <= tol, "{what}: {got} vs {want}");
}

/// M12x1.75-6g cut to X9.853 from the crest Ø12.001 (G76 P1074): E = 9.853 + 2·1.515544/3 =
/// 10.863363; w = 1.75·0.577350 = 1.010363; simple M = E + 0.866025·1.75 = 12.378907; tan λ =
/// 1.75/(π·10.863363) = 0.051277, + 1.010363·0.75·0.0026293 = 0.001992: M = 12.380900 mm. The
/// window: 10.679 + 1.515544 + 0.002 … = 12.1966–12.3465. Middle of d2 10.679–10.829 is 10.754:
/// (10.863363 − 10.754)/2 = 0.0547 deeper.
#[test]
fn metric_60() {
    let src = "G97 S800 M03\nG00 X14. Z5.\nG76 P010060 Q50 R0.02\nG76 X9.853 Z-20. P1074 Q300 F1.75\nM30\n";
    let n = notes(src, "fanuc", "M12x1.75-6g");
    close(number_after(&n, "over "), 1.0104, 5e-5, "wire");
    close(number_after(&n, "M = "), 12.3809, 6e-5, "M");
    close(number_after(&n, "6g allows "), 12.1966, 6e-5, "M min");
    close(number_after(&n, "cutting "), 0.0547, 6e-5, "deeper");
    assert!(n.contains("deeper"), "{n}");
}

/// 1/2-13 UNC-2A (inch) to X0.4056 from the crest 0.5000 (P472): E = 0.4056 + 2·0.0666173/3 =
/// 0.4500116; w = 0.577350/13 = 0.0444115; simple M = E + 0.866025/13 = 0.5166289; tan λ =
/// (1/13)/(π·0.4500116) = 0.054411, + 0.0444115·0.75·0.0029606 = 0.0000986: M = 0.5167275 in.
/// The 2A window's middle 0.4460: (0.4500116 − 0.4460)/2 = 0.0020 deeper.
#[test]
fn unified_60_inch() {
    let src = "G20\nG97 S800 M03\nG00 X0.6 Z0.2\nG76 P010060 Q20 R0.001\nG76 X0.4056 Z-1. P472 Q100 F0.076923\nM30\n";
    let n = notes(src, "fanuc", "1/2-13 UNC-2A");
    close(number_after(&n, "M = "), 0.5167, 6e-5, "M");
    close(number_after(&n, "cutting "), 0.0020, 6e-5, "deeper");
}

/// Tr40x7-7e to X32 (h3 4, crest 40): E = 32 + 8 − 3.5 = 36.5; w = 7/(2·cos 15°) = 3.623467;
/// simple M = 36.5 − 7·3.732051/2 + 3.623467·4.863703 = 41.061289; tan λ = 7/(π·36.5) =
/// 0.061046, + 3.623467·½·0.0037266·0.965926·3.732051 = 0.024339: M = 41.085627 mm. The 7e window
/// d2 36.020–36.375 (ISO 2904): middle 36.1975, (36.5 − 36.1975)/2 = 0.15125 deeper.
#[test]
fn trapezoidal_30() {
    let src =
        "G97 S200 M03\nG00 X44. Z10.\nG76 P010030 Q50 R0.02\nG76 X32. Z-40. P4000 Q500 F7.\nM30\n";
    let n = notes(src, "fanuc", "Tr40x7-7e");
    close(number_after(&n, "M = "), 41.0856, 6e-5, "M");
    close(number_after(&n, "cutting "), 0.15125, 6e-5, "deeper");
}

/// 1-5 ACME-2G to X0.78 (h 0.5·0.2 + 0.010 = 0.110, crest 1.0): E = 0.78 + 0.22 − 0.1 = 0.9;
/// w = 0.2/(2·cos 14.5°) = 0.1032900; simple M = 0.9 − 0.2·3.866713/2 + 0.10329·4.993929 =
/// 1.0291518; + 0.0009674 (the lead-angle term, tan λ = 0.2/(π·0.9)): M = 1.0301191 in.
#[test]
fn acme_29_inch() {
    let src = "G20\nG97 S300 M03\nG00 X1.1 Z0.5\nG76 P010029 Q20 R0.001\nG76 X0.78 Z-2. P1100 Q150 F0.2\nM30\n";
    let n = notes(src, "fanuc", "1-5 ACME-2G");
    close(number_after(&n, "M = "), 1.0301, 6e-5, "M");
}

/// 1/2-12 BSW medium to X0.3933 (0.640327·P = 0.0533606 deep, crest 0.5): E = 0.3933 + 0.0533606
/// = 0.4466606; w = (1/12)/(2·cos 27.5°) = 0.0469742; simple M = E − 0.960491/12 +
/// 3.165681·0.0469742 = 0.5153251; tan λ = (1/12)/(π·0.4466606) = 0.059388, +
/// 0.0469742·½·0.0035270·0.887011·1.920982 = 0.0001411: M = 0.5154663 in.
#[test]
fn whitworth_55_inch() {
    let src = "G20\nG97 S600 M03\nG00 X0.6 Z0.2\nG76 P010055 Q20 R0.001\nG76 X0.3933 Z-1. P534 Q100 F0.083333\nM30\n";
    let n = notes(src, "fanuc", "1/2-12 BSW");
    close(number_after(&n, "M = "), 0.5155, 6e-5, "M");
}

/// An internal thread is gauged, not measured over wires: the note gives the pitch-diameter window
/// and the depth change. M12x1.75-6H bored from Ø10.106 to X12 (0.947 deep): with the standard's
/// flat-P/8 root the pitch line is 3/8·H·2 = 1.136658 below the major: E = 12 − 1.136658 =
/// 10.863342; 6H d2 10.863–11.063, middle 10.963: (10.963 − 10.863342)/2 = 0.0498 deeper.
#[test]
fn internal_gets_the_depth_to_the_middle() {
    let src =
        "G97 S800 M03\nG00 X9. Z5.\nG76 P010060 Q50 R0.02\nG76 X12. Z-20. P947 Q300 F1.75\nM30\n";
    let n = notes(src, "fanuc", "M12x1.75-6H");
    assert!(!n.contains("M = "), "{n}");
    close(number_after(&n, "cutting "), 0.0498, 1.5e-4, "deeper");
}

/// A taper thread says where the gauge stands: its stand-off in turns and in length.
#[test]
fn npt_states_the_gauge_standoff() {
    let src = "G20\nG97 S600 M03\nG00 X1. Z0.2\nG76 P010060 Q20 R0.001\nG76 X0.7211 Z-0.8 R0.025 P569 Q100 F0.071429\nM30\n";
    let n = notes(src, "fanuc", "1/2-14 NPT");
    assert!(n.contains("turns ("), "{n}");
}

/// `--wire`: the wire one owns. The M12x1.75-6g program of `metric_60` (E = 10.863363) over
/// 1.000 mm wires: simple M = E − 0.866025·1.75 + 3·1.000 = 10.863363 − 1.515544 + 3 = 12.347819;
/// tan λ = 0.051277, + 1.000·½·0.0026293·0.866025·1.732051 = 0.001972: M = 12.349791 mm. The
/// window over the same wires: 10.679 − 1.515544 + 3 + ½·(1.75/(π·10.679))²·1.5 = 12.163456 +
/// 0.002041 = 12.165497.
#[test]
fn a_wire_of_ones_own() {
    let m = Machine::built_in("fanuc").unwrap();
    let src = "G97 S800 M03\nG00 X14. Z5.\nG76 P010060 Q50 R0.02\nG76 X9.853 Z-20. P1074 Q300 F1.75\nM30\n";
    let opts = Options {
        thread: Some(lookup("M12x1.75-6g").unwrap()),
        wire: Some(1.0),
        ..Options::default()
    };
    let r = check(src.as_bytes(), Source::Gcode(&m), &opts).unwrap();
    let n: Vec<_> = r.notes.iter().map(|n| n.message.clone()).collect();
    let n = n.join("\n");
    close(number_after(&n, "over "), 1.0, 5e-5, "wire");
    close(number_after(&n, "M = "), 12.3498, 6e-5, "M");
    close(number_after(&n, "6g allows "), 12.1655, 6e-5, "M min");
    // An inch thread takes its wire in inches: 1/2-13 UNC-2A of `unified_60_inch` over 0.045 in:
    // M = 0.4500116 − 0.0666173 + 3·0.045 = 0.5183943 (+ 0.045·0.75·0.0029606 = 0.0000999).
    let src = "G20\nG97 S800 M03\nG00 X0.6 Z0.2\nG76 P010060 Q20 R0.001\nG76 X0.4056 Z-1. P472 Q100 F0.076923\nM30\n";
    let opts = Options {
        thread: Some(lookup("1/2-13 UNC-2A").unwrap()),
        wire: Some(0.045),
        ..Options::default()
    };
    let r = check(src.as_bytes(), Source::Gcode(&m), &opts).unwrap();
    let n: Vec<_> = r.notes.iter().map(|n| n.message.clone()).collect();
    let n = n.join("\n");
    close(number_after(&n, "M = "), 0.5185, 6e-5, "inch M");
}
