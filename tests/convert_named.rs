//! Conversion with what the target machine states beyond its controller's words (issue 26): tools
//! by the shop's names (`--tool`, the profile's `[tools]`), reference returns where the target
//! has no code for them (the profile's `[reference]`), and the settings a one-block cycle reads
//! (Haas Settings 86, 95, 96, 99). docs/translation.md says each decision.

use threadcut::convert::{self, Options};
use threadcut::diag::Diagnostic;
use threadcut::machine::Machine;

fn built_in(name: &str) -> Machine {
    Machine::built_in(name).unwrap()
}

fn with_tools(
    src: &str,
    from: &Machine,
    to: &Machine,
    tools: &[(&str, &str)],
) -> Result<String, Diagnostic> {
    let options = Options {
        tools: tools
            .iter()
            .map(|(n, t)| (n.to_string(), t.to_string()))
            .collect(),
        ..Default::default()
    };
    convert::convert_text(src, from, to, &options)
}

/// The converted program's lines that are neither comments nor the header's block of modes,
/// without their trailing comments.
fn blocks(text: &str) -> Vec<String> {
    text.lines()
        .skip_while(|l| l.starts_with('%'))
        .skip(2)
        .filter(|l| !l.starts_with('(') && !l.starts_with(';'))
        .map(|l| l.split(" (").next().unwrap_or(l).to_string())
        .collect()
}

const NAMED: &str = "G0 X40 Z5\nT=\"THREAD_EXT_60\" D1\nT=\"THREAD_EXT_60\" D0\n";

/// A Sinumerik tool called by name is written by the number the command gives, in each numbering
/// controller's form: the Fanuc family and Allen-Bradley T + tool + two-digit offset, the OmniTurn
/// the tool alone (its own offset), LinuxCNC T, M6, G43; D0 is the tool without its offset.
#[test]
fn a_named_tool_is_written_by_its_number_on_every_numbering_controller() {
    let from = built_in("sinumerik");
    let cases: &[(&str, &str, &[&str])] = &[
        ("fanuc", "T0101", &["T0101", "T0100"]),
        ("fanuc15", "T0101", &["T0101", "T0100"]),
        ("fanuc-b", "T0101", &["T0101", "T0100"]),
        ("gsk980", "T0101", &["T0101", "T0100"]),
        ("haas", "T0101", &["T0101", "T0100"]),
        ("ab9", "T0101", &["T0101", "T0100"]),
        ("linuxcnc", "T0101", &["T1 M6 G43", "T1 M6 G49"]),
    ];
    for (to, number, want) in cases {
        let out = with_tools(NAMED, &from, &built_in(to), &[("THREAD_EXT_60", number)])
            .unwrap_or_else(|e| panic!("{to}: {}", e.message));
        let b = blocks(&out);
        assert_eq!(&b[1..], *want, "{to}:\n{out}");
    }
    // The OmniTurn applies a tool's own offset and no other: T4 (tool 4, offset 4), and D0 has no
    // counterpart there.
    let out = with_tools(
        "G0 X40 Z5\nT=\"THREAD_EXT_60\" D1\n",
        &from,
        &built_in("omniturn"),
        &[("THREAD_EXT_60", "T4")],
    )
    .unwrap();
    assert_eq!(blocks(&out).last().map(String::as_str), Some("T4"), "{out}");
}

/// Without a number for the name, the refusal of before, at the name, its hint naming the flag.
#[test]
fn an_unnamed_tool_is_refused_with_the_flag_in_its_hint() {
    let from = built_in("sinumerik");
    for to in [
        "fanuc", "fanuc15", "fanuc-b", "gsk980", "haas", "ab9", "omniturn", "linuxcnc",
    ] {
        let e = with_tools(NAMED, &from, &built_in(to), &[("OTHER", "T0202")]).unwrap_err();
        assert_eq!((e.span.line, e.span.column), (2, 1), "{to}: {}", e.message);
        assert!(
            e.message.contains("called by its name THREAD_EXT_60"),
            "{to}: {}",
            e.message
        );
        let hint = e.hint.unwrap_or_default();
        assert!(hint.contains("--tool THREAD_EXT_60=T0101"), "{to}: {hint}");
        assert!(hint.contains("[tools]"), "{to}: {hint}");
    }
}

/// A number whose offset is not the tool's: D1 applies that offset (T0103: tool 1, offset 3).
#[test]
fn the_first_cutting_edge_applies_the_offset_the_number_gives() {
    let from = built_in("sinumerik");
    let map = [("THREAD_EXT_60", "T0103")];
    let out = with_tools(NAMED, &from, &built_in("fanuc"), &map).unwrap();
    assert_eq!(blocks(&out)[1..], ["T0103", "T0100"], "{out}");
    let out = with_tools(NAMED, &from, &built_in("linuxcnc"), &map).unwrap();
    assert_eq!(blocks(&out)[1..], ["T1 M6 G43 H3", "T1 M6 G49"], "{out}");
    // A second cutting edge has no number in the mapping: refused at D2.
    let e = with_tools("T=\"THREAD_EXT_60\" D2\n", &from, &built_in("fanuc"), &map).unwrap_err();
    assert!(e.message.contains("D2"), "{}", e.message);
    // The OmniTurn cannot apply offset 3 to tool 1.
    let e = with_tools(NAMED, &from, &built_in("omniturn"), &map).unwrap_err();
    assert!(e.message.contains("tool 1 with offset 3"), "{}", e.message);
}

/// Back to Sinumerik: a numbered tool the mapping names is called by its name, D1 where the
/// offset is the named one, D0 without offset; a tool the mapping does not name stays numbered.
#[test]
fn a_numbered_tool_is_written_by_its_name_for_sinumerik_when_named() {
    let from = built_in("fanuc");
    let to = built_in("sinumerik");
    let src = "G0 X40. Z5.\nT0303\nT0300\nT0202\n";
    let out = with_tools(src, &from, &to, &[("THREAD_EXT_60", "T0303")]).unwrap();
    assert_eq!(
        blocks(&out)[1..],
        ["T=\"THREAD_EXT_60\" D1", "T=\"THREAD_EXT_60\" D0", "T2 D1"],
        "{out}"
    );
    // Unmapped: as before, by number.
    let out = with_tools(src, &from, &to, &[]).unwrap();
    assert_eq!(blocks(&out)[1..], ["T3 D1", "T3 D0", "T2 D1"], "{out}");
    // The named tool with another offset than its own has no edge to write: refused at the word.
    let e = with_tools("T0305\n", &from, &to, &[("THREAD_EXT_60", "T0303")]).unwrap_err();
    assert_eq!(e.span.line, 1);
    assert!(
        e.message
            .contains("tool 3 is named THREAD_EXT_60 with offset 3"),
        "{}",
        e.message
    );
    // Read back on Sinumerik and converted again for Fanuc: the same calls.
    let out = with_tools(src, &from, &to, &[("THREAD_EXT_60", "T0303")]).unwrap();
    let back = with_tools(&out, &to, &from, &[("THREAD_EXT_60", "T0303")]).unwrap();
    let calls: Vec<String> = blocks(&back)
        .into_iter()
        .filter(|l| l.starts_with('T'))
        .collect();
    assert_eq!(calls, ["T0303", "T0300", "T0202"], "{back}");
}

/// The target profile's `[tools]` table names tools as `--tool` does; the command's entry of the
/// same name wins.
#[test]
fn the_target_profiles_tools_table_names_tools() {
    let mut fanuc: Machine = Machine::from_toml(&format!(
        "{}\n[tools]\nTHREAD_EXT_60 = \"T0505\"\n",
        threadcut::machine::BUILT_IN
            .iter()
            .find(|(n, _)| *n == "fanuc")
            .unwrap()
            .1
    ))
    .unwrap();
    let from = built_in("sinumerik");
    let out = with_tools(NAMED, &from, &fanuc, &[]).unwrap();
    assert_eq!(blocks(&out)[1..], ["T0505", "T0500"], "{out}");
    let out = with_tools(NAMED, &from, &fanuc, &[("THREAD_EXT_60", "T0707")]).unwrap();
    assert_eq!(blocks(&out)[1..], ["T0707", "T0700"], "{out}");
    // A value that is no tool call is an error naming the table's entry.
    fanuc
        .tools
        .insert("THREAD_EXT_60".into(), "tool five".into());
    let e = with_tools(NAMED, &from, &fanuc, &[]).unwrap_err();
    assert!(e.message.contains("[tools] THREAD_EXT_60"), "{}", e.message);
}

fn with_reference(name: &str, x: Option<f64>, z: Option<f64>) -> Machine {
    let mut m = built_in(name);
    m.reference = Some(threadcut::machine::ReferencePoints {
        g28: threadcut::machine::AxisPoint { x, z },
        ..Default::default()
    });
    m
}

fn conv(src: &str, from: &Machine, to: &Machine) -> Result<String, Diagnostic> {
    convert::convert_text(src, from, to, &Options::default())
}

/// Allen-Bradley (its G28 is the 7300-compatible thread cycle) and the OmniTurn (no reference
/// return documented): a return is a rapid to where the target profile's `[reference] g28`
/// places the returning axes, in the profile's units and X mode.
#[test]
fn a_reference_return_goes_to_the_profiles_reference_point_where_the_target_has_none() {
    let fanuc = built_in("fanuc");
    // ab9 profile: inch, X on diameter; g28 at X10" (Ø) Z6". The metric program stays metric
    // (the 9/Series has G21): X 10 × 25.4 = 254 mm on diameter, Z 6 × 25.4 = 152.4 mm.
    let ab = with_reference("ab9", Some(10.0), Some(6.0));
    let out = conv("G21 G99\nG0 X40. Z5.\nG28 U0. W0.\nG28 U0.\n", &fanuc, &ab).unwrap();
    let b = blocks(&out);
    assert_eq!(b[2..], ["G0 X254. Z152.4", "G0 X254."], "{out}");
    // OmniTurn profile: inch only, X on radius (G73): g28 at X5" (radius) Z6"; a Haas bare G28
    // returns both axes.
    let omni = with_reference("omniturn", Some(5.0), Some(6.0));
    let out = conv("G20\nG28\n", &built_in("haas"), &omni).unwrap();
    assert_eq!(blocks(&out).last().unwrap(), "G0 X5. Z6.", "{out}");
    // The block says what it stands for.
    assert!(
        out.contains(
            "G0 X5. Z6. (G28: the reference point, where the profile's [reference] g28 places it)"
        ),
        "{out}"
    );
}

/// Without the position (no `[reference]`, or not the axis that returns): refused as before, at
/// the code, with the table in the hint; targets with a return code keep writing it.
#[test]
fn a_reference_return_without_the_position_is_refused_for_allen_bradley_and_the_omniturn() {
    let fanuc = built_in("fanuc");
    for to in [
        built_in("ab9"),
        built_in("omniturn"),
        with_reference("ab9", None, Some(6.0)),
        with_reference("omniturn", None, Some(6.0)),
    ] {
        let e = conv("G20\nG0 X1. Z.2\nG28 U0.\n", &fanuc, &to).unwrap_err();
        assert_eq!((e.span.line, e.span.column), (3, 1), "{}", e.message);
        assert!(
            e.message.contains("no reference return") && e.message.contains("reference point's X"),
            "{}",
            e.message
        );
        assert!(e.hint.unwrap_or_default().contains("[reference]"));
    }
    // Z alone is placed: a return of Z is written.
    let out = conv(
        "G20\nG28 W0.\n",
        &fanuc,
        &with_reference("ab9", None, Some(6.0)),
    )
    .unwrap();
    assert_eq!(blocks(&out).last().unwrap(), "G0 Z6.", "{out}");
    // Fanuc and LinuxCNC have a return code: written as before, whatever the profile places.
    let out = conv(
        "G20\nG28 U0.\n",
        &built_in("haas"),
        &with_reference("fanuc", Some(10.0), None),
    )
    .unwrap();
    assert_eq!(blocks(&out).last().unwrap(), "G28 U0.", "{out}");
}
