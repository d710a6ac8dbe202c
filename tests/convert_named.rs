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

/// The built-in Haas profile with the shop's Settings: 86 = 0.002 in, 95 = 1 lead, 96 = 45°,
/// 99 = 0.001 in, stated (not threadcut's assumed values).
fn haas_stated() -> Machine {
    let mut m = built_in("haas");
    let s = m.haas.as_mut().unwrap();
    s.finish_allowance_in = 0.002;
    s.chamfer_leads = 1.0;
    s.chamfer_angle_deg = 45.0;
    s.min_cut_in = 0.001;
    s.thread_settings_assumed = false;
    m
}

/// Fanuc's two-block G76 in inches: one finishing pass (P01…), a one-lead chamfer (…10…) at 60°
/// (…60), Δdmin Q10 = 0.0010", R0.002 finishing allowance; K = 0.0613", Δd = 0.0150", lead 0.1".
const FANUC_G76: &str = "G20 G99\nG0 X0.9 Z0.3\nG76 P011060 Q10 R0.002\nG76 X0.6273 Z-1.125 P613 Q150 F0.1\nG0 X4. Z4.\nM30\n";

/// Every threading move of a program's cycles, read on `m`: (start, end) in mm, X radius.
fn thread_moves(text: &str, m: &Machine) -> Vec<(f64, f64, f64, f64)> {
    let mut out = Vec::new();
    for job in
        threadcut::program::jobs(text.as_bytes(), m).unwrap_or_else(|e| panic!("{e}\n{text}"))
    {
        let path = threadcut::toolpath::build(&job).unwrap();
        for (from, mo) in path.segments() {
            if matches!(mo.kind, threadcut::toolpath::MotionKind::Thread { .. }) {
                out.push((from.x, from.z, mo.to.x, mo.to.z));
            }
        }
    }
    out
}

/// With the machine's Settings 86, 95, 96 and 99 stated, Fanuc's two-block G76 becomes Haas's
/// one-block G76 (A60: the 60° infeed; P1: one edge, constant area), which read back on that
/// profile cuts the same passes; the header lists the four settings it relies on.
#[test]
fn fanucs_two_block_g76_is_haass_g76_with_the_settings_stated() {
    let fanuc = built_in("fanuc");
    let haas = haas_stated();
    let out = conv(FANUC_G76, &fanuc, &haas).unwrap();
    assert!(
        out.lines()
            .any(|l| l == "G76 X0.6273 Z-1.125 K0.0613 D0.015 F0.1 A60 P1"),
        "{out}"
    );
    assert!(!out.contains("G32"), "{out}");
    let header = out.lines().nth(1).unwrap();
    assert_eq!(
        header,
        "(threadcut: this program relies on the machine's settings: Setting 86, thread finish allowance: 0.002 in; Setting 95, thread chamfer size: 1 lead; Setting 96, thread chamfer angle: 45 deg; Setting 99, thread minimum cut: 0.001 in)"
    );
    // The same passes, at the output resolution (0.0001 in = 0.00254 mm).
    let want = thread_moves(FANUC_G76, &fanuc);
    let got = thread_moves(&out, &haas);
    assert_eq!(want.len(), got.len(), "{out}");
    // Passes: rough to K − R = 0.0593" by d√n from Δd 0.015" (n = 1 … 16: 0.015·√16 = 0.06 ≥
    // 0.0593, so 16 rough passes), then one finishing pass at K: 17 passes, each a thread move
    // and its synchronised 45° pull-out over one lead: 34.
    assert_eq!(want.len(), 34);
    for (a, b) in want.iter().zip(&got) {
        for (p, q) in [(a.0, b.0), (a.1, b.1), (a.2, b.2), (a.3, b.3)] {
            assert!((p - q).abs() <= 0.00254, "{a:?} vs {b:?}\n{out}");
        }
    }
}

/// Without the settings stated (the built-in profile's are threadcut's), the same program is plain
/// moves as before, and a G76 that would match threadcut's values is not written either: its
/// passes would depend on Settings 86 and 99 nobody stated.
#[test]
fn without_the_settings_stated_the_g76_is_plain_moves() {
    let fanuc = built_in("fanuc");
    let out = conv(FANUC_G76, &fanuc, &built_in("haas")).unwrap();
    assert!(!out.lines().any(|l| l.starts_with("G76")), "{out}");
    assert!(out.contains("G32 X"), "{out}");
    assert!(!out.contains("relies on the machine's settings"), "{out}");
    // A job that threadcut's own values would cut is refused its G76 for the settings, and said
    // why: a Haas G76 read with those values, converted for another Haas profile that states
    // nothing either (Fanuc's G76 always has a finishing pass; threadcut's Setting 86 is 0, none).
    let plain = "G20 G99\nG0 X0.9 Z0.3\nG76 X0.6273 Z-1.125 K0.0613 D0.015 F0.1 A60\nM30\n";
    let mut other = built_in("haas");
    other.name = "haas-other".into();
    let out = conv(plain, &built_in("haas"), &other).unwrap();
    assert!(!out.lines().any(|l| l.starts_with("G76")), "{out}");
    assert!(
        out.contains("G76 reads Setting 86 and Setting 99 from the machine, and the target profile does not state them"),
        "{out}"
    );
    // Stated with those values, it is written.
    let mut stated = haas_stated();
    stated.haas.as_mut().unwrap().finish_allowance_in = 0.0;
    let out = conv(plain, &built_in("haas"), &stated).unwrap();
    assert!(
        out.lines()
            .any(|l| l == "G76 X0.6273 Z-1.125 K0.0613 D0.015 F0.1 A60 P1"),
        "{out}"
    );
}

/// G92 reads only the chamfer (Settings 95 and 96): written as before, the header saying the
/// factory defaults are assumed where the profile does not state them, or the stated values.
#[test]
fn a_g92_lists_the_chamfer_settings_it_relies_on() {
    let fanuc = built_in("fanuc");
    let src = "G21 G99\nG0 X40. Z5.\nG92 X29.2 Z-30. F2.\nM30\n";
    let out = conv(src, &fanuc, &built_in("haas")).unwrap();
    assert!(out.lines().any(|l| l == "G92 X29.2 Z-30. F2."), "{out}");
    assert_eq!(
        out.lines().nth(1).unwrap(),
        "(threadcut: this program relies on the machine's settings: Setting 95, thread chamfer size: 1 lead, the factory default, not stated in the target profile; Setting 96, thread chamfer angle: 45 deg, the factory default, not stated in the target profile)"
    );
    let out = conv(src, &fanuc, &haas_stated()).unwrap();
    assert_eq!(
        out.lines().nth(1).unwrap(),
        "(threadcut: this program relies on the machine's settings: Setting 95, thread chamfer size: 1 lead; Setting 96, thread chamfer angle: 45 deg)"
    );
    // Plain moves only: no setting relied on, no line.
    let out = conv(
        "G21 G99\nG0 X40. Z5.\nG32 Z-30. F2.\nM30\n",
        &fanuc,
        &built_in("haas"),
    )
    .unwrap();
    assert!(!out.contains("relies on"), "{out}");
}
