//! Milling a taper thread: the helix radius follows the standard's 1:16 taper on diameter.

use threadcut::mill::profile::{FeedReference, MillProfile};
use threadcut::mill::{self, Comp, Hand, LeadIn, MillSpec, MoveKind, Side};
use threadcut::thread::standard::lookup;

fn spec(name: &str, side: Side, length: f64, tool: f64) -> MillSpec {
    MillSpec {
        thread: lookup(name).unwrap(),
        side,
        hand: Hand::Right,
        length,
        tool_diameter: tool,
        teeth: 1,
        direction: None,
        passes: 2,
        starts: 1,
        comp: Comp::Off,
        center: (10.0, -5.0),
        start_z: 0.0,
        clearance: 5.0,
        feed: 300.0,
        lead_in: LeadIn::Arc,
        comp_feed: FeedReference::Centre,
    }
}

/// Every helix point of a 1/2-14 NPT external thread milled from its small end (Z0) down lies on
/// the cone: tool-centre radius − tool radius = the root at Z0 + |Z|/32 (1:16 on diameter); each
/// arc starts and ends on its own circle; the last pass's root at the gauge plane (L1 = 8.128 mm
/// down) is the standard's: E1 − 0.8·P.
#[test]
fn npt_helix_follows_one_in_sixteen() {
    let s = spec("1/2 NPT", Side::External, 13.556, 9.525);
    let plan = mill::plan(&s).unwrap();
    assert!((plan.taper - 1.0 / 32.0).abs() < 1e-15);
    assert!(plan.radial_for_taper);
    let (cx, cy) = s.center;
    let r_t = plan.tool_radius;
    let last = plan.pass_radii.len() as u32;
    let mut arcs = 0;
    let mut prev = None;
    for m in &plan.moves {
        if let (MoveKind::Arc { center, .. }, Some(p)) = (m.kind, prev) {
            let (p, _): ((f64, f64, f64), ()) = (p, ());
            // On its circle at both ends.
            let r0 = (p.0 - center.0).hypot(p.1 - center.1);
            let r1 = (m.to.x - center.0).hypot(m.to.y - center.1);
            assert!((r0 - r1).abs() < 1e-9, "{r0} {r1}");
            // On the cone.
            let contour = (m.to.x - cx).hypot(m.to.y - cy) - r_t;
            let want = plan.pass_radii[(m.pass - 1) as usize] + (plan.top_z - m.to.z) / 32.0;
            assert!(
                (contour - want).abs() < 1e-9,
                "pass {} Z{}: {contour} vs {want}",
                m.pass,
                m.to.z
            );
            if m.pass == last {
                arcs += 1;
            }
        }
        prev = Some((m.to.x, m.to.y, m.to.z));
    }
    assert!(arcs >= 4 * 7, "{arcs} arcs");
    // The final root at the gauge plane: E1 − 2·(0.8P/2) = 0.77843 − 0.05714 inch (basic,
    // truncation at its mean).
    let e1 = 0.77843 * 25.4;
    let h = 0.8 * 25.4 / 14.0;
    let truncation = (0.0024 + 0.0056) * 25.4; // min and max truncation (Table 1, 0.033·p → 0.0024)
    let major_at_gauge = e1 + 0.866025403784 * 25.4 / 14.0 - truncation;
    let root_at_gauge = major_at_gauge / 2.0 - h;
    let root_top = plan.final_radius;
    assert!(
        (root_top + 8.128 / 32.0 - root_at_gauge).abs() < 1e-4,
        "{} vs {root_at_gauge}",
        root_top + 8.128 / 32.0
    );
}

/// The written program: each G2/G3's I/J gives the same radius to its start and its end within
/// the output resolution, and the written end points lie on the cone within it.
#[test]
fn npt_program_arcs_close() {
    let s = spec("1/2 NPT", Side::External, 13.556, 9.525);
    let plan = mill::plan(&s).unwrap();
    let profile = MillProfile::built_in("fanuc-mill").unwrap();
    let mut out = Vec::new();
    mill::post::write_gcode(
        &mut out,
        &plan,
        &profile,
        mill::post::Options {
            units: threadcut::units::Units::Mm,
            d_register: None,
        },
    )
    .unwrap();
    let text = String::from_utf8(out).unwrap();
    assert!(text.contains("taper 1:16"), "{text}");
    let mut pos = [0.0f64; 3];
    let mut arcs = 0;
    for line in text.lines().filter(|l| !l.starts_with('(')) {
        let word = |c: char| {
            line.split_whitespace()
                .find(|w| w.starts_with(c))
                .and_then(|w| w[1..].parse::<f64>().ok())
        };
        let next = [
            word('X').unwrap_or(pos[0]),
            word('Y').unwrap_or(pos[1]),
            word('Z').unwrap_or(pos[2]),
        ];
        if line.starts_with("G2") || line.starts_with("G3") || line.contains(" G2 ") {
            let (i, j) = (word('I').unwrap_or(0.0), word('J').unwrap_or(0.0));
            let c = (pos[0] + i, pos[1] + j);
            let r0 = i.hypot(j);
            let r1 = (next[0] - c.0).hypot(next[1] - c.1);
            assert!((r0 - r1).abs() < 2e-3, "{line}: {r0} vs {r1}");
            arcs += 1;
        }
        pos = next;
    }
    assert!(arcs > 50);
}

/// Rc (internal, ISO 7-1) shrinks going down; G (parallel) keeps full circles.
#[test]
fn internal_taper_and_parallel() {
    let plan = mill::plan(&spec("Rc1/2", Side::Internal, 13.2, 12.0)).unwrap();
    assert!((plan.taper + 1.0 / 32.0).abs() < 1e-15);
    let g = mill::plan(&spec("G1/2", Side::Internal, 13.2, 12.0)).unwrap();
    assert_eq!(g.taper, 0.0);
    // Full circles about the axis, one a turn and pass.
    let about_axis = g
        .moves
        .iter()
        .filter(|m| matches!(m.kind, MoveKind::Arc { center, .. } if center == (10.0, -5.0)))
        .count();
    assert_eq!(about_axis as u32, g.turns * 2);
}
