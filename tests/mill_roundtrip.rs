//! Issue 24, item 5: every program `threadcut mill` writes reads back through the milling reader
//! (`millprog`) and thread recognition as the thread that was asked for — over thread names,
//! sides, hands, passes, starts, teeth, compensation, lead-ins, directions and controllers.

use proptest::prelude::*;
use proptest::strategy::ValueTree;

use threadcut::check::milling::{read, Options};
use threadcut::mill::profile::MillProfile;
use threadcut::mill::request::Request;
use threadcut::mill::{Comp, Direction, Hand, LeadIn, Side};
use threadcut::units::Units;

const THREADS: [(&str, f64, f64); 6] = [
    // (name, length, a cutter that fits both sides), in the thread's units.
    ("M20x2.5", 16.0, 12.0),
    ("M12x1.75", 12.0, 7.0),
    ("M8x1.25", 10.0, 5.0),
    ("M30x2", 20.0, 16.0),
    ("1/2-13 UNC", 0.6, 0.3),
    ("3/4-16 UNF", 0.75, 0.45),
];

const CONTROLLERS: [&str; 4] = ["fanuc-mill", "haas-mill", "linuxcnc-mill", "centroid"];

fn request() -> impl Strategy<Value = Request> {
    (
        0..THREADS.len(),
        any::<bool>(),
        any::<bool>(),
        1u32..4,
        1u32..4,
        1u32..3,
        any::<bool>(),
        any::<bool>(),
        prop_oneof![
            Just(None),
            Just(Some(Direction::TopDown)),
            Just(Some(Direction::BottomUp))
        ],
        0..CONTROLLERS.len(),
    )
        .prop_map(
            |(k, internal, left, passes, starts, teeth, comp_off, radial, direction, c)| {
                let (name, length, tool) = THREADS[k];
                let side = if internal {
                    Side::Internal
                } else {
                    Side::External
                };
                let mut r = Request::new(
                    name,
                    side,
                    length,
                    tool,
                    if name.starts_with('M') { 300.0 } else { 12.0 },
                    MillProfile::built_in(CONTROLLERS[c]).unwrap(),
                );
                r.hand = if left { Hand::Left } else { Hand::Right };
                r.passes = passes;
                r.starts = starts;
                r.teeth = teeth;
                r.comp = if comp_off {
                    Comp::Off
                } else {
                    Comp::Controller
                };
                r.lead_in = if radial { LeadIn::Radial } else { LeadIn::Arc };
                r.direction = direction;
                r.d_register = Some(7);
                r
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn threadcut_mill_programs_read_back_as_asked(r in request()) {
        let Ok(m) = r.prepare() else { return Ok(()) };
        let mut text = Vec::new();
        m.write_gcode(&mut text).unwrap();
        let units = m.options.units;
        let o = Options {
            tool_diameter: Some(r.tool_diameter),
            teeth: Some(r.teeth),
            ..Options::default()
        };
        let milled = read(&text[..], &m.profile, &o)
            .map_err(|d| TestCaseError::fail(format!("{}: {}", d.span.line, d.message)))?;
        let what = String::from_utf8_lossy(&text).into_owned();
        prop_assert_eq!(milled.threads.len(), 1, "{}", what);
        let t = &milled.threads[0];
        let p = &m.plan;
        // Positions are written to the program's resolution: 0.001 mm or 0.0001 inch.
        let eps = units.to_mm(if units == Units::Mm { 0.001 } else { 0.0001 }) * 4.0;
        prop_assert!((t.lead - p.lead).abs() < eps, "lead {} vs {}", t.lead, p.lead);
        prop_assert_eq!(t.starts, p.starts);
        prop_assert!((t.pitch - p.pitch).abs() < eps);
        prop_assert_eq!(t.hand, p.hand);
        prop_assert_eq!(t.direction, p.direction);
        prop_assert_eq!(t.side.map(|s| s.0), Some(p.side));
        prop_assert_eq!(t.pass_radii(eps).len(), p.pass_radii.len());
        prop_assert_eq!(t.helices.len() as u32, p.pass_radii.len() as u32 * p.starts);
        let root = t.root_diameter.expect("the cutter is given");
        prop_assert!((root - 2.0 * p.final_radius).abs() < 2.0 * eps, "root {} vs {}", root, 2.0 * p.final_radius);
        // Every start's helix is found, each at its own phase.
        let mut seen: Vec<u32> = t.helices.iter().map(|h| h.start_index).collect();
        seen.sort_unstable();
        seen.dedup();
        prop_assert_eq!(seen.len() as u32, p.starts);
    }
}

/// Most combinations are millable: the property is not vacuous.
#[test]
fn most_requests_prepare() {
    let mut runner = proptest::test_runner::TestRunner::deterministic();
    let mut ok = 0;
    for _ in 0..200 {
        let r = request().new_tree(&mut runner).unwrap().current();
        ok += usize::from(r.prepare().is_ok());
    }
    assert!(ok > 150, "only {ok} of 200 requests prepare");
}
