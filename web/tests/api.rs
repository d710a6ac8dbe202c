//! The page's API, natively: the same functions the wasm module exports.

use serde_json::{json, Value};
use threadcut_web::api;

fn values(controller: &str, thread: &str) -> Value {
    let v = api::fill(&json!({"controller": controller, "thread": thread}).to_string());
    assert_eq!(v["ok"], true, "{v}");
    v["values"].clone()
}

fn plan(controller: &str, values: &Value) -> Value {
    api::plan(&json!({"controller": controller, "values": values}).to_string())
}

#[test]
fn every_form_has_unique_field_ids_and_belongs_to_a_built_in_controller() {
    let c = api::controllers();
    let list = c["controllers"].as_array().unwrap();
    assert_eq!(list.len(), threadcut::machine::BUILT_IN.len());
    for name in threadcut_web::forms::CONTROLLERS {
        let form = threadcut_web::forms::form(name).unwrap();
        let mut ids: Vec<&str> = form.fields().map(|f| f.id).collect();
        let n = ids.len();
        ids.sort();
        ids.dedup();
        assert_eq!(ids.len(), n, "{name}: duplicate field ids");
        assert!(list
            .iter()
            .any(|m| m["name"] == *name && m["form"].is_object()));
    }
}

/// M20x2.5 external on GSK G78: k = 17/24·H = 0.613435·2.5 = 1.534 (to 0.001), root diameter
/// 20 − 2·1.534 = 16.932, R 0.05, Δd = (1.534 − 0.05)/√10 = 0.47 (to 0.01), Δdmin 0.1, left-flank
/// infeed at 60°. Depths d_n = max(0.47·√n, d_{n−1} + 0.1), clipped at k − d = 1.484:
/// 0.47, 0.66468, 0.81406, 0.94, 1.05095, 1.15126, 1.25126 (√7·0.47 = 1.24350 < 1.15126 + 0.1),
/// 1.35126, 1.45126, 1.484; then two finishing passes at 1.534.
#[test]
fn m20x2_5_on_gsk_g78_plans_the_hand_computed_passes() {
    let v = values("gsk980", "M20x2.5");
    assert_eq!(v["x"], "16.932");
    assert_eq!(v["k"], "1.534");
    assert_eq!(v["dd"], "0.47");
    assert_eq!(v["lead"], "2.5");
    let out = plan("gsk980", &v);
    assert_eq!(out["ok"], true, "{out}");
    assert!(out["program"]
        .as_str()
        .unwrap()
        .contains("G78 X16.932 Z-30. P1.534 Q0.47 F2.5\n"));
    let rows = out["cycles"][0]["passes"].as_array().unwrap();
    let depths: Vec<f64> = rows.iter().map(|r| r["depth"].as_f64().unwrap()).collect();
    let want = [
        0.47,
        0.47 * 2f64.sqrt(),
        0.47 * 3f64.sqrt(),
        0.94,
        0.47 * 5f64.sqrt(),
        0.47 * 6f64.sqrt(),
        0.47 * 6f64.sqrt() + 0.1,
        0.47 * 6f64.sqrt() + 0.2,
        0.47 * 6f64.sqrt() + 0.3,
        1.484,
        1.534,
        1.534,
    ];
    assert_eq!(depths.len(), want.len(), "{depths:?}");
    for (d, w) in depths.iter().zip(want) {
        assert!((d - w).abs() < 1e-9, "{depths:?}");
    }
    // X on diameter from the 20 mm crest; Z shifted along the left flank by d·tan 30°.
    assert!((rows[0]["x"].as_f64().unwrap() - 19.06).abs() < 1e-9);
    // Start Z: three leads of run-up, 7.5.
    assert_eq!(v["sz"], "7.5");
    let z0 = 7.5 + 0.47 * 30f64.to_radians().tan();
    assert!(
        (rows[0]["z"].as_f64().unwrap() - z0).abs() < 1e-9,
        "{} {z0}",
        rows[0]
    );
    assert_eq!(rows[10]["kind"], "finish");
    // The expanded program is `threadcut expand`'s: the G78 blocks become G0/G32 moves.
    let gcode = out["gcode"].as_str().unwrap();
    assert!(!gcode.contains("G78"));
    assert_eq!(gcode.matches("G32").count(), 12, "{gcode}");
    // One thread motion per pass.
    let threads = out["motions"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["kind"] == "thread")
        .count();
    assert_eq!(threads, 12);
    assert!(out["diagnostics"].as_array().unwrap().is_empty());
}

#[test]
fn a_bad_packed_digit_points_at_its_own_field() {
    let mut v = values("gsk980", "M20x2.5");
    v["r"] = json!("5");
    let out = plan("gsk980", &v);
    assert_eq!(out["ok"], false);
    let d = &out["diagnostics"][0];
    assert_eq!(d["code"], "E004", "{d}");
    assert_eq!(d["field"], "r", "{d}");
    assert_eq!(d["line"], 4);
    // `G78 P02` then the r digits at column 8.
    assert_eq!(d["column"], 8);
    assert!(out["cycles"].as_array().unwrap().is_empty());
    assert!(out["gcode"].is_null());
}

#[test]
fn a_malformed_number_points_at_its_field() {
    let mut v = values("fanuc", "M20x2.5");
    v["x"] = json!("16.9.3");
    let out = plan("fanuc", &v);
    assert_eq!(out["ok"], false);
    assert_eq!(out["diagnostics"][0]["field"], "x", "{out}");
}

#[test]
fn every_form_plans_a_standard_thread_without_diagnostics() {
    for c in threadcut_web::forms::CONTROLLERS {
        for thread in ["M20x2.5", "M6", "1/2-13 UNC"] {
            let out = plan(c, &values(c, thread));
            assert_eq!(out["ok"], true, "{c} {thread}: {}", out["diagnostics"]);
            let errors: Vec<&Value> = out["diagnostics"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["severity"] == "error")
                .collect();
            assert!(errors.is_empty(), "{c} {thread}: {errors:?}");
            // The page's end-to-end test reads "No errors or warnings" for M20x2.5.
            if thread == "M20x2.5" {
                assert_eq!(out["diagnostics"], json!([]), "{c} {thread}");
            }
            let rows = out["cycles"][0]["passes"].as_array().unwrap();
            assert!(rows.len() >= 3, "{c} {thread}");
        }
    }
}

#[test]
fn internal_threads_cut_outward() {
    for c in threadcut_web::forms::CONTROLLERS {
        let v =
            api::fill(&json!({"controller": c, "thread": "M20x2.5", "internal": true}).to_string());
        let out = plan(c, &v["values"]);
        assert_eq!(out["ok"], true, "{c}: {}", out["diagnostics"]);
        let rows = out["cycles"][0]["passes"].as_array().unwrap();
        let x: Vec<f64> = rows.iter().map(|r| r["x"].as_f64().unwrap()).collect();
        assert!(x.windows(2).all(|w| w[1] >= w[0]), "{c}: {x:?}");
    }
}

#[test]
fn a_pasted_program_is_analysed_with_the_error_place() {
    let program = "G00 X32 Z5\nG78 P020545 Q0.15 R0.5\nG78 X27.546 Z-30 P1.227 Q0.4 F2\n";
    let out = api::analyse(&json!({"controller": "gsk980", "program": program}).to_string());
    assert_eq!(out["ok"], false);
    let d = &out["diagnostics"][0];
    assert_eq!(
        (d["line"].clone(), d["column"].clone()),
        (json!(2), json!(8))
    );
    assert_eq!(d["len"], 2);
    assert!(d["field"].is_null());

    let good = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../examples/gsk-g78.nc"
    ))
    .unwrap();
    let out = api::analyse(&json!({"controller": "gsk980", "program": good}).to_string());
    assert_eq!(out["ok"], true, "{out}");
    assert_eq!(out["cycles"].as_array().unwrap().len(), 2);
}

#[test]
fn unknown_names_are_errors_not_panics() {
    assert_eq!(api::thread("M7x9")["ok"], false);
    assert_eq!(
        api::fill(r#"{"controller":"nope","thread":"M6"}"#)["ok"],
        false
    );
    assert_eq!(api::plan("not json")["ok"], false);
    let out = api::analyse(r#"{"controller":"nope","program":"G0 X1"}"#);
    assert_eq!(out["ok"], false);
    assert!(out["error"].as_str().unwrap().contains("gsk980"));
}

#[test]
fn the_plan_carries_the_librarys_plot_and_simulated_columns() {
    let out = plan("gsk980", &values("gsk980", "M20x2.5"));
    let svg = out["svg"].as_str().unwrap();
    assert!(
        svg.starts_with("<svg") || svg.starts_with("<?xml"),
        "{}",
        &svg[..80]
    );
    assert!(svg.contains("</svg>"));
    // Same SVG as the library's `threadcut plot` path for the generated program.
    let machine = threadcut::machine::Machine::built_in("gsk980").unwrap();
    let (want, _, _) = threadcut::render::program_svg(
        out["program"].as_str().unwrap().as_bytes(),
        &machine,
        threadcut::sim::Tip::Sharp,
    )
    .unwrap();
    assert_eq!(svg, want);
    // A sharp tool's simulated chip areas equal the sharp-V areas of the table.
    for r in out["cycles"][0]["passes"].as_array().unwrap() {
        let (a, s) = (r["area"].as_f64().unwrap(), r["sim_area"].as_f64().unwrap());
        assert!((a - s).abs() < 1e-6 * a.max(1.0), "{r}");
    }
}

/// Every form cuts the standard's thread height: 17/24·H = 0.613435·P to the program's resolution
/// (M20x2.5: 1.534 mm; 1/2-13 UNC: 0.613435 · 0.076923 in = 0.0472 in), external and internal
/// (5/8·H = 0.541266·P: 1.353 mm; 0.0416 in), whatever units each controller writes it in.
#[test]
fn every_form_reaches_the_standard_thread_height() {
    for c in threadcut_web::forms::CONTROLLERS {
        for (thread, internal, depth) in [
            ("M20x2.5", false, 1.534),
            ("M20x2.5", true, 1.353),
            ("1/2-13 UNC", false, 0.0472),
            ("1/2-13 UNC", true, 0.0416),
        ] {
            let v = api::fill(
                &json!({"controller": c, "thread": thread, "internal": internal}).to_string(),
            );
            let out = plan(c, &v["values"]);
            assert_eq!(out["ok"], true, "{c} {thread}: {}", out["diagnostics"]);
            let rows = out["cycles"][0]["passes"].as_array().unwrap();
            let last = rows.last().unwrap()["depth"].as_f64().unwrap();
            assert!(
                (last - depth).abs() < 1e-9,
                "{c} {thread} {internal}: {last}"
            );
        }
    }
}

/// The new forms in the picker: Tr20x4 on GSK G78 takes the 30° tool and h3 = 2.25 mm (root
/// 20 − 4.5 = 15.5); 1/2-10 ACME on Fanuc the 29° tool; a 1/2 NPT on Allen-Bradley's G78 gets its
/// taper word I = −(Z travel)/32 in inch (Z0.2143 → Z−0.53, the effective thread L2 0.5337 to
/// 0.01: 0.7443/32 = 0.0233); every plan reads without an error.
#[test]
fn standard_forms_fill_the_forms() {
    let names = api::controllers()["threads"].clone();
    for n in [
        "Tr20x4",
        "1/2-10 ACME",
        "1/2-14 NPT",
        "R1/2",
        "G1/2",
        "1/2-12 BSW",
    ] {
        assert!(names.as_array().unwrap().iter().any(|v| v == n), "{n}");
    }
    let v = values("gsk980", "Tr20x4");
    assert_eq!(v["a"], "30");
    assert_eq!(v["k"], "2.25");
    assert_eq!(v["x"], "15.5");
    let p = plan("gsk980", &v);
    assert_eq!(p["ok"], true, "{p}");
    let v = values("fanuc", "1/2-10 ACME");
    assert_eq!(v["a"], "29");
    assert_eq!(plan("fanuc", &v)["ok"], true);
    let v = values("ab9", "1/2 NPT");
    assert_eq!(v["a"], "60");
    assert_eq!(v["z"], "-0.53", "{v}");
    assert_eq!(v["taper"], "-0.0233", "{v}");
    let p = plan("ab9", &v);
    assert_eq!(p["ok"], true, "{p}");
    let t = api::thread("1/2-14 NPT");
    assert_eq!(t["thread"]["profile"]["angle_deg"], 60.0);
    assert!(t["thread"]["taper"]["gauge_length"].as_f64().unwrap() > 8.0);
}

/// The page runs the library's one check: the same findings, in the same order, as `threadcut
/// check` (which calls the same function with the same, default, options).
#[test]
fn the_page_shows_the_checks_findings() {
    let program =
        "G21 G99\nG97 S2000 M3\nG0 X40. Z2.\nG92 X29.2 Z-30. F2.\nX28.7\nX28.3\nG0 X100. Z100.\n";
    let out = api::analyse(&json!({"controller": "fanuc", "program": program}).to_string());
    let machine = threadcut::machine::Machine::built_in("fanuc").unwrap();
    let report = threadcut::check::check(
        program.as_bytes(),
        threadcut::check::Source::Gcode(&machine),
        &threadcut::check::Options::default(),
    )
    .unwrap();
    let page: Vec<(String, String)> = out["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .map(|d| {
            (
                d["code"].as_str().unwrap().to_string(),
                d["message"].as_str().unwrap().to_string(),
            )
        })
        .collect();
    let cli: Vec<(String, String)> = report
        .diagnostics
        .iter()
        .map(|d| (d.code.as_str().to_string(), d.message.clone()))
        .collect();
    assert_eq!(page, cli);
    assert!(page.iter().any(|(c, _)| c == "W003"), "{page:?}");
    assert_eq!(out["notes"].as_array().unwrap().len(), report.notes.len());
    // The three G92 blocks are one thread of three passes.
    assert_eq!(out["cycles"].as_array().unwrap().len(), 1);
    assert_eq!(out["cycles"][0]["source"], "moves");
    assert_eq!(out["cycles"][0]["passes"].as_array().unwrap().len(), 3);
}

/// A lead typed without a decimal point on a Fanuc form (`F25`: 0.025 mm) is flagged on its
/// field.
#[test]
fn a_lead_without_a_decimal_point_is_flagged_on_its_field() {
    let mut v = values("fanuc", "M20x2.5");
    v["lead"] = json!("25");
    let out = plan("fanuc", &v);
    let d = out["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .find(|d| d["code"] == "W006")
        .unwrap_or_else(|| panic!("{}", out["diagnostics"]))
        .clone();
    assert_eq!(d["field"], "lead", "{d}");
    assert!(
        d["message"]
            .as_str()
            .unwrap()
            .starts_with("F25 has no decimal point: this control reads it as a lead of 0.025 mm"),
        "{d}"
    );
}

/// 1/2-13 UNC: the lead 1/13" = 0.0769230769… in is written to each controller's lead resolution
/// (the decimals its writer gives the lead word: 5 in inch on GSK, Fanuc and Allen-Bradley, 7 on
/// LinuxCNC), never cut to the 4 decimals of a position (P0.0769 would cut 0.0769 in per turn,
/// 0.03 mm off after 13 turns).
#[test]
fn inch_leads_are_written_to_the_controllers_resolution() {
    for (c, want) in [
        ("gsk980", "0.07692"),
        ("fanuc", "0.07692"),
        ("ab9", "0.07692"),
        ("linuxcnc", "0.0769231"),
    ] {
        let v = values(c, "1/2-13 UNC");
        assert_eq!(v["lead"], want, "{c}");
        let out = plan(c, &v);
        assert_eq!(out["ok"], true, "{c}: {}", out["diagnostics"]);
        let lead = out["cycles"][0]["passes"].as_array().map(|p| p.len());
        assert!(lead.is_some_and(|n| n >= 3), "{c}");
    }
    // Metric leads are unchanged: 2.5 is 2.5.
    assert_eq!(values("linuxcnc", "M20x2.5")["lead"], "2.5");
}

/// The motions are listed unless the request says not to (the page does not show them).
#[test]
fn analysis_lists_motions_unless_asked_not_to() {
    let program = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n";
    let with = api::analyse(&json!({"controller": "gsk980", "program": program}).to_string());
    let without = api::analyse(
        &json!({"controller": "gsk980", "program": program, "motions": false}).to_string(),
    );
    assert!(with["motions_total"].as_u64().unwrap() > 10, "{with}");
    assert_eq!(without["motions_total"], 0);
    assert_eq!(without["motions"], json!([]));
    assert_eq!(with["cycles"], without["cycles"]);
    assert_eq!(with["gcode"], without["gcode"]);
}

/// An unknown thread name: the error and the nearest names, in words the page can show (no
/// command-line command in them).
#[test]
fn unknown_threads_say_so_without_command_lines() {
    for r in [
        api::thread("M99"),
        api::fill(&json!({"controller": "gsk980", "thread": "M99"}).to_string()),
    ] {
        assert_eq!(r["ok"], false, "{r}");
        assert_eq!(
            r["hint"], "nearest known threads: M68x6, M64x2, M64x3",
            "{r}"
        );
        assert!(!r.to_string().contains("threadcut"), "{r}");
    }
}

/// The Convert tab's call: the library's conversion, its native and plain cycles, and the block
/// that cannot be converted with its place.
#[test]
fn convert_gives_the_program_its_cycles_and_the_refusal_with_its_place() {
    let fanuc =
        "G21 G99\nG0 X32. Z5.\nG76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\nM30\n";
    let r = api::convert(&json!({"from": "fanuc", "to": "gsk980", "program": fanuc}).to_string());
    assert_eq!(r["ok"], true, "{r}");
    assert_eq!(r["native"], 1);
    assert!(r["program"]
        .as_str()
        .unwrap()
        .contains("G76 P020060 Q100 R0.05\nG76 X27.546 Z-30. P1227 Q400 F2.\n"));
    let r = api::convert(&json!({"from": "fanuc", "to": "linuxcnc", "program": fanuc}).to_string());
    assert_eq!(
        (r["ok"].clone(), r["native"].clone()),
        (json!(true), json!(0)),
        "{r}"
    );
    assert_eq!(r["plain"][0]["line"], 4);
    assert!(r["plain"][0]["reason"]
        .as_str()
        .unwrap()
        .contains("LinuxCNC's G76"));
    let r = api::convert(&json!({"from": "fanuc", "to": "omniturn", "program": fanuc}).to_string());
    assert_eq!(r["ok"], false, "{r}");
    assert_eq!(r["diagnostics"][0]["line"], 4);
    assert!(r["error"].as_str().unwrap().contains("G33"), "{r}");
    // A lead Haas writes to 4 decimals drifts: stated, within the class's limit; refused beyond
    // the request's own limit (the converted program's units, along the thread).
    let lead = "G21 G99\nG0 X22. Z5.\nG92 X20. Z-30. F1.50004\nM30\n";
    let r = api::convert(&json!({"from": "fanuc", "to": "haas", "program": lead}).to_string());
    assert_eq!(r["ok"], true, "{r}");
    assert!(
        r["program"]
            .as_str()
            .unwrap()
            .contains("drifts 0.0009333 mm"),
        "{r}"
    );
    assert!(
        r["warnings"].to_string().contains("drifts 0.0009333 mm"),
        "{r}"
    );
    let r = api::convert(
        &json!({"from": "fanuc", "to": "haas", "program": lead, "max_lead_drift": 0.0005})
            .to_string(),
    );
    assert_eq!(r["ok"], false, "{r}");
    assert!(
        r["error"].as_str().unwrap().contains("the limit given"),
        "{r}"
    );
    // A named tool by the number the request gives (`--tool THREAD_EXT_60=T0101`); without it,
    // refused with the flag in the hint.
    let named = "G0 X40 Z5\nT=\"THREAD_EXT_60\" D1\n";
    let r = api::convert(
        &json!({"from": "sinumerik", "to": "fanuc", "program": named, "tools": {"THREAD_EXT_60": "T0101"}})
            .to_string(),
    );
    assert_eq!(r["ok"], true, "{r}");
    assert!(r["program"].as_str().unwrap().contains("\nT0101\n"), "{r}");
    let r =
        api::convert(&json!({"from": "sinumerik", "to": "fanuc", "program": named}).to_string());
    assert_eq!(r["ok"], false, "{r}");
    assert!(r.to_string().contains("--tool THREAD_EXT_60=T0101"), "{r}");
    let r = api::convert(&json!({"from": "fanuc", "to": "nope", "program": ""}).to_string());
    assert!(r["error"]
        .as_str()
        .unwrap()
        .contains("unknown controller `nope`"));
}

/// The page's analysis draws the part as `plot` does (the same library composition), with the
/// stock the form gives: a rapid through the thread just cut is red at its line, and each
/// thread's blank is listed.
#[test]
fn a_pasted_program_shows_its_part_and_the_rapid_into_it() {
    // Turns Ø19.8 (G71/G70), G76 M20x2.5 at line 18, a rapid through the thread at line 19.
    let program = "G21 G99\nT0101\nG97 S800 M03\nG00 X27. Z2.\nG71 U1.5 R0.5\nG71 P10 Q20 U0.4 W0.1 F0.25\nN10 G00 X16.\nG01 Z0. F0.12\nX19.8 Z-1.9\nZ-30.\nX24.\nN20 X27.\nG70 P10 Q20\nG00 X100. Z100.\nT0303\nG00 X24. Z5.\nG76 P020060 Q100 R0.05\nG76 X16.85 Z-27. P1575 Q400 F2.5\nG00 X15. Z-10.\nG00 X100. Z100.\nM30\n";
    let out = api::analyse(
        &json!({"controller": "fanuc", "program": program, "stock_diameter": 25.0, "stock_start": 0.0})
            .to_string(),
    );
    let svg = out["svg"].as_str().unwrap();
    assert!(svg.contains("The part as the program makes it"));
    assert!(svg.contains("dashed: the stock Ø25 as given"));
    assert_eq!(svg.matches("class=\"rapid-hit\"").count(), 1);
    assert!(svg.contains(">line 19</text>"));
    let e011: Vec<_> = out["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["code"] == "E011")
        .map(|d| d["line"].as_u64().unwrap())
        .collect();
    assert_eq!(e011, [19]);
    assert_eq!(
        out["blanks"],
        json!([{"line": 18, "crest": 19.8, "crest_from": "measured", "face": 0.0, "face_from": "given"}])
    );
    // The page asks for no blanks (it shows none): the rest of the analysis is the same.
    let without = api::analyse(
        &json!({"controller": "fanuc", "program": program, "stock_diameter": 25.0, "stock_start": 0.0, "blanks": false})
            .to_string(),
    );
    assert_eq!(without["blanks"], json!([]));
    assert_eq!(without["diagnostics"], out["diagnostics"]);
    assert_eq!(without["svg"], out["svg"]);
    // Without a stock the part is still drawn (the program cut it), the bar's size not known.
    let out = api::analyse(&json!({"controller": "fanuc", "program": program}).to_string());
    assert!(out["svg"]
        .as_str()
        .unwrap()
        .contains("the stock's size is not given"));
}

/// The page's thread shows the three wires and the gauges (issue 27), as `threadcut thread` gives
/// them: M10x1.5 best wire P/(2·cos 30°) = 0.866025 mm, M over it at d2 9.025721: 10.324760
/// (simple formula; codingace.net's table); 6g's GO ring at 8.994, NOT GO at 8.862; 6H's GO plug
/// at 9.026 (Westport's metric gauge chart). A trapezoidal thread has wires but no gauges.
#[test]
fn thread_gives_wires_and_gauges() {
    let t = api::thread("M10x1.5");
    assert_eq!(t["ok"], true);
    let close = |v: &serde_json::Value, want: f64| (v.as_f64().unwrap() - want).abs() < 5e-4;
    assert!(close(&t["wires"]["best"], 0.866025), "{}", t["wires"]);
    assert!(
        close(&t["wires"]["basic"]["simple"], 10.324760),
        "{}",
        t["wires"]
    );
    let ring = &t["gauges"]["external"][0];
    assert_eq!(ring["gauge"], "thread ring");
    assert!(
        close(&ring["go"], 8.994) && close(&ring["not_go"], 8.862),
        "{ring}"
    );
    assert!(
        close(&t["gauges"]["internal"][0]["go"], 9.026),
        "{}",
        t["gauges"]
    );
    let tr = api::thread("Tr40x7");
    assert!(
        tr["gauges"].is_null() && tr["wires"]["best"].is_number(),
        "{tr}"
    );
}

/// A cycle pasted on its own: the check says it cannot start without the tool's position, and
/// the pass table is shown all the same (the Z column null, the note saying what is not known);
/// with `start` the program is expanded. FS15's one-block G76: pass 1 at D = 0.485 below the
/// crest, X = 16.93 + 2·(1.534 − 0.485) = 19.028.
#[test]
fn a_cycle_on_its_own_shows_its_pass_table() {
    let program = "M3 S500\nG76 X16.93 Z-25. K1.534 D.485 F2.5\nM30\n";
    let out = api::analyse(&json!({"controller": "fanuc15", "program": program}).to_string());
    assert_eq!(out["ok"], false, "{out}");
    let errors: Vec<&Value> = out["diagnostics"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|d| d["severity"] == "error")
        .collect();
    assert_eq!(errors.len(), 1, "{out}");
    assert_eq!(errors[0]["code"], "E006");
    let cycle = &out["cycles"][0];
    assert!(
        (cycle["passes"][0]["x"].as_f64().unwrap() - 19.028).abs() < 1e-6,
        "{cycle}"
    );
    assert!(cycle["passes"][0]["z"].is_null());
    assert!(cycle["start_unknown"]["note"]
        .as_str()
        .unwrap()
        .contains("the start point is not known"));
    assert!(out["gcode"].is_null(), "{out}");

    let out = api::analyse(
        &json!({"controller": "fanuc15", "program": program, "start": [22.0, 5.0]}).to_string(),
    );
    assert_eq!(out["ok"], true, "{out}");
    assert!(out["cycles"][0].get("start_unknown").is_none());
    assert!(out["gcode"].as_str().unwrap().contains("X19.028"));
}

/// The pass tables stop at the last one shown when the check read the whole program without an
/// error, and take the number of threads from it: every example, real program and bad program
/// analysed with one table, and with every table, says the same of the program.
#[test]
fn the_tables_shown_early_say_what_every_table_says() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/..");
    let lathe = [
        "gsk980",
        "omniturn",
        "ab9",
        "fanuc",
        "fanuc15",
        "fanuc-b",
        "haas",
        "linuxcnc",
        "sinumerik",
    ];
    let mut files = Vec::new();
    for dir in ["examples", "tests/data/real", "tests/bad"] {
        let mut stack = vec![std::path::PathBuf::from(root).join(dir)];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap() {
                let p = e.unwrap().path();
                if p.is_dir() {
                    stack.push(p);
                } else if matches!(
                    p.extension().and_then(|e| e.to_str()),
                    Some("nc" | "ngc" | "mpf" | "MPF")
                ) {
                    files.push(p);
                }
            }
        }
    }
    files.sort();
    let mut early = 0;
    for file in &files {
        let path = file.to_string_lossy();
        // The controller the file is written for, by its directory or its name's first word.
        let named: Vec<&str> = lathe
            .iter()
            .copied()
            .filter(|c| {
                let name = file.file_name().unwrap().to_string_lossy();
                path.contains(&format!("/{c}/")) || name.starts_with(&format!("{c}-"))
            })
            .collect();
        let controller = match named.as_slice() {
            [] if path.ends_with(".mpf") || path.ends_with(".MPF") => "sinumerik",
            [] if path.ends_with(".ngc") => "linuxcnc",
            [] => continue,
            // `fanuc15-…` names fanuc too: the longest name is meant.
            names => names.iter().max_by_key(|n| n.len()).unwrap(),
        };
        let program = String::from_utf8_lossy(&std::fs::read(file).unwrap()).into_owned();
        let analyse = |max: Option<usize>| {
            let mut request =
                json!({"controller": controller, "program": program, "motions": false});
            if let Some(m) = max {
                request["max_cycles"] = m.into();
            }
            api::analyse(&request.to_string())
        };
        let all = analyse(None);
        let total = all["cycles_total"].as_u64().unwrap() as usize;
        for max in [0, 1] {
            let mut some = analyse(Some(max));
            let shown = some["cycles"].as_array().unwrap().clone();
            assert_eq!(
                shown[..],
                all["cycles"].as_array().unwrap()[..shown.len()],
                "{path}"
            );
            assert_eq!(shown.len(), total.min(max), "{path}");
            early += usize::from(total > max);
            some["cycles"] = all["cycles"].clone();
            assert_eq!(some, all, "{path} ({controller}), {max} table(s)");
        }
    }
    assert!(
        files.len() > 200 && early > 40,
        "{} files, {early} stopped early",
        files.len()
    );
}

/// The page draws a long program's plot from the threads its tables read, stopping there: the
/// same picture as `threadcut plot` draws reading the whole program (here 60 threads, of which
/// the first 50 are drawn and the picture says so), with the part from the same check.
#[test]
fn the_page_draws_what_plot_draws_from_one_reading() {
    use threadcut::check::{self, Source};
    use threadcut::{commands, machine::Machine, program, render, sim::Tip};
    let program: String = (0..60)
        .map(|i| {
            format!(
                "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-{} P3 Q1.8 F3 J1.5 K2\n",
                40 + i % 7
            )
        })
        .collect();
    let page = api::analyse(
        &json!({"controller": "gsk980", "program": program, "motions": false, "max_cycles": 20})
            .to_string(),
    );
    assert_eq!(page["cycles_total"], 60);
    assert_eq!(page["cycles"].as_array().unwrap().len(), 20);
    let machine = Machine::built_in("gsk980").unwrap();
    let report = check::check(
        program.as_bytes(),
        Source::Gcode(&machine),
        &commands::with_stock(
            check::Options::default(),
            Default::default(),
            Some(&machine),
        ),
    )
    .unwrap();
    let part =
        Some(commands::part_picture(&report.part, machine.units)).filter(|p| p.worth_drawing());
    let plot = render::program_plot_part(
        program.as_bytes(),
        &machine,
        Tip::Sharp,
        render::Selection::default(),
        &program::Options::default(),
        part.as_ref(),
    )
    .unwrap();
    assert_eq!((plot.threads, plot.drawn.len()), (60, 50));
    assert_eq!(page["svg"].as_str().unwrap(), plot.svg);
}

/// The lines of the expanded program an analysis gives (`gcode_lines`) are the first lines of the
/// whole program, `gcode_total` counts its lines, and `expand` gives it whole: for every example
/// (each with its controller), for a CRLF program, and for cycles whose moves lie past the lines
/// given (counted, not written).
#[test]
fn the_expanded_programs_head_and_count_are_the_whole_programs() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../examples");
    let mut cases: Vec<(String, String)> = Vec::new();
    for e in std::fs::read_dir(root).unwrap() {
        let p = e.unwrap().path();
        let name = p.file_name().unwrap().to_string_lossy().into_owned();
        let controller = [
            "fanuc15",
            "fanuc-b",
            "fanuc",
            "gsk",
            "haas",
            "linuxcnc",
            "omniturn",
            "ab9",
            "sinumerik",
        ]
        .into_iter()
        .find(|c| name.starts_with(c));
        if let (Some(c), false) = (controller, name.ends_with(".apt") || name.ends_with(".sh")) {
            let c = if c == "gsk" { "gsk980" } else { c };
            cases.push((c.into(), std::fs::read_to_string(&p).unwrap()));
        }
    }
    let cycle = "G0 X80 Z10\nG78 P020045 Q0.15 R0.5\nG78 X60 Z-60 P3 Q1.8 F3 J1.5 K2\n";
    cases.push(("gsk980".into(), cycle.repeat(40)));
    cases.push((
        "gsk980".into(),
        cycle.repeat(3).replace('\n', "\r\n") + "M30",
    ));
    assert!(cases.len() > 20);
    for (controller, program) in &cases {
        let whole = api::expand(&json!({"controller": controller, "program": program}).to_string());
        if whole["ok"] != true {
            // A program `expand` refuses (a cycle that runs differently each time round a loop):
            // the analysis says the same.
            let a =
                api::analyse(&json!({"controller": controller, "program": program}).to_string());
            assert_eq!(a["ok"], false);
            let found = a["diagnostics"].as_array().unwrap();
            assert!(found.contains(&whole["diagnostics"][0]), "{a}");
            continue;
        }
        let whole = whole["gcode"].as_str().unwrap();
        let lines: Vec<&str> = whole.split_inclusive('\n').collect();
        for n in [0, 1, 7, 100, 100_000] {
            let a = api::analyse(
                &json!({"controller": controller, "program": program, "motions": false,
                        "gcode_lines": n})
                .to_string(),
            );
            assert_eq!(a["gcode_total"], lines.len(), "{controller} {n}\n{program}");
            assert_eq!(
                a["gcode"].as_str().unwrap(),
                lines[..n.min(lines.len())].concat(),
                "{controller} {n}"
            );
        }
        let all = api::analyse(
            &json!({"controller": controller, "program": program, "motions": false}).to_string(),
        );
        assert_eq!(all["gcode"].as_str().unwrap(), whole);
    }
}

/// A thread of many passes written as moves: its table lists the first `max_passes` rows, each
/// as the whole table has it (the simulated shares from the section of every pass), and
/// `passes_total` counts them all; without the limit there is no `passes_total`.
#[test]
fn a_long_pass_table_lists_its_first_rows() {
    let mut program = String::from("G21 G99\nG97 S500 M3\nG0 X22. Z5.\nG92 X19.9 Z-30. F2.5\n");
    for i in 1..40 {
        program += &format!("X{:.3}\n", 19.9 - 0.05 * f64::from(i));
    }
    let analyse = |max: Option<usize>| {
        let mut request = json!({"controller": "fanuc", "program": program, "motions": false});
        if let Some(m) = max {
            request["max_passes"] = m.into();
        }
        api::analyse(&request.to_string())
    };
    let all = analyse(None);
    let some = analyse(Some(10));
    let (all, some) = (&all["cycles"][0], &some["cycles"][0]);
    assert_eq!(all["passes"].as_array().unwrap().len(), 40, "{all}");
    assert!(all.get("passes_total").is_none());
    assert_eq!(some["passes_total"], 40);
    assert_eq!(
        some["passes"].as_array().unwrap()[..],
        all["passes"].as_array().unwrap()[..10]
    );
    // The shares are of the whole thread: the ten listed do not add up to one.
    let shares: f64 = some["passes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["sim_share"].as_f64().unwrap())
        .sum();
    assert!(shares < 0.9, "{shares}");
}

/// The page's expansion keeps its first lines only: a cycle of a macro program's streamed
/// beginning past them is recorded by its job and state, not formatted, and a jump that runs it
/// again is still held to the same expansion (`program::interpreted`). Past the first line here.
#[test]
fn a_jump_back_past_the_shown_lines_is_compared_as_always() {
    let analyse = |program: &str, lines: usize| {
        api::analyse(
            &json!({"controller": "fanuc", "program": program, "motions": false, "gcode_lines": lines})
                .to_string(),
        )
    };
    // The second run of the G76 is reached in G1 (N10 has no motion word): its expansion
    // restores G1 after the moves, the first run's does not. Refused, at the cycle's line.
    let differs = "G21 G99\nG97 S500 M3\nG0\nN10 X32. Z5.\nG76 P010060 Q100 R0.05\nG76 X29.2 Z-30. P1000 Q400 F2.\nG1 Z6. F0.3\n#100=#100+1\nIF[#100LT2]GOTO10\nM30\n";
    for lines in [1, 1000] {
        let out = analyse(differs, lines);
        assert_eq!(out["ok"], false, "{lines}: {out}");
        let d = &out["diagnostics"][0];
        assert_eq!(
            (d["code"].as_str(), d["line"].as_u64()),
            (Some("E005"), Some(6)),
            "{d}"
        );
        assert!(
            d["message"]
                .as_str()
                .unwrap()
                .contains("starting at X32 Z5"),
            "{d}"
        );
    }
    // The same from the same state each time (G0 in N10): accepted, and the count of the
    // expanded program's lines is the one the whole expansion has.
    let same = differs.replace("N10 X32.", "N10 G0 X32.");
    let (head, whole) = (analyse(&same, 1), analyse(&same, 1000));
    assert_eq!(head["ok"], true, "{head}");
    assert_eq!(head["gcode"].as_str().unwrap(), "G21 G99\n");
    assert_eq!(head["diagnostics"], json!([]));
    assert_eq!(head["gcode_total"], whole["gcode_total"]);
    assert_eq!(
        whole["gcode"].as_str().unwrap().lines().count() as u64,
        whole["gcode_total"].as_u64().unwrap()
    );
}
