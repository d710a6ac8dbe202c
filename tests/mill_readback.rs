//! Every program `threadcut mill` writes, read back through the milling reader (`millprog`) on
//! its own profile: no error, and move for move the plan it was written from (end points and arc
//! centres within the output's rounding, the arc's direction, compensation on the side planned,
//! the helix's Z advancing one lead a turn). A property over thread names, sides, hands, passes,
//! starts, teeth, compensation, units and every built-in milling profile.

use threadcut::diag::Diagnostic;
use threadcut::mill::motion::{Comp, MillKind, MillMotion, TapCycle};
use threadcut::mill::profile::MillProfile;
use threadcut::mill::request::Request;
use threadcut::mill::{self, CompSide, Hand, MoveKind, Side};
use threadcut::millprog;
use threadcut::units::Units;

struct Collect(Vec<MillMotion>);

impl millprog::Sink for Collect {
    fn motion(&mut self, m: &MillMotion, _: u16) -> Result<(), Diagnostic> {
        self.0.push(*m);
        Ok(())
    }
    fn tap(&mut self, _: &TapCycle) -> Result<(), Diagnostic> {
        Ok(())
    }
}

struct Case {
    thread: &'static str,
    side: Side,
    hand: Hand,
    passes: u32,
    starts: u32,
    teeth: u32,
    comp: mill::Comp,
    units: Option<Units>,
}

fn cases() -> Vec<Case> {
    let base = |thread, side| Case {
        thread,
        side,
        hand: Hand::Right,
        passes: 1,
        starts: 1,
        teeth: 1,
        comp: mill::Comp::Controller,
        units: None,
    };
    vec![
        base("M20x2.5", Side::Internal),
        Case {
            passes: 3,
            ..base("M20x2.5", Side::External)
        },
        Case {
            hand: Hand::Left,
            starts: 2,
            ..base("M24x3", Side::Internal)
        },
        Case {
            comp: mill::Comp::Off,
            teeth: 3,
            ..base("M16x1.5", Side::Internal)
        },
        Case {
            units: Some(Units::Inch),
            passes: 2,
            ..base("1/2-13 UNC", Side::Internal)
        },
        Case {
            comp: mill::Comp::Off,
            hand: Hand::Left,
            ..base("3/4-10 UNC", Side::External)
        },
    ]
}

fn tolerance(units: Units, profile: &MillProfile) -> f64 {
    let d = match units {
        Units::Mm => profile.decimals_mm,
        Units::Inch => profile.decimals_inch,
    };
    // Half a written increment, twice over (each coordinate and I/J are rounded), in mm.
    units.to_mm(10f64.powi(-(d as i32))) * 1.01
}

#[test]
fn every_milling_program_reads_back_as_its_plan() {
    let mut checked = 0;
    for name in MillProfile::names() {
        let profile = MillProfile::built_in(name).unwrap();
        for case in cases() {
            let mut request =
                Request::new(case.thread, case.side, 20.0, 12.0, 300.0, profile.clone());
            if case.units == Some(Units::Inch) || case.thread.contains("UNC") {
                request.length = 0.75;
                request.tool_diameter = 0.375;
                request.feed = 12.0;
            }
            request.hand = case.hand;
            request.passes = case.passes;
            request.starts = case.starts;
            request.teeth = case.teeth;
            request.comp = case.comp;
            request.units = case.units;
            request.d_register = Some(1);
            let milling = match request.prepare() {
                Ok(m) => m,
                Err(e) => panic!("{name} {}: {e:?}", case.thread),
            };
            let mut text = Vec::new();
            milling.write_gcode(&mut text).unwrap();
            let mut got = Collect(Vec::new());
            millprog::run(&text[..], &profile, &millprog::Options::default(), &mut got)
                .unwrap_or_else(|e| {
                    panic!(
                        "{name} {}: {e:?}\n{}",
                        case.thread,
                        String::from_utf8_lossy(&text)
                    )
                });
            compare(name, case.thread, &milling, &got.0);
            checked += 1;
        }
    }
    assert_eq!(checked, 4 * cases().len());
}

fn compare(name: &str, thread: &str, milling: &mill::request::Milling, got: &[MillMotion]) {
    let plan = &milling.plan;
    let tol = tolerance(milling.options.units, &milling.profile);
    // The plan's moves of some length (the reader drops a straight move that stays put), after
    // the first: it starts where the tool is not known.
    let mut want = Vec::new();
    let mut at: Option<mill::P3> = None;
    for m in &plan.moves {
        let stays = at.is_some_and(|a| {
            (a.x - m.to.x).abs() < 1e-9
                && (a.y - m.to.y).abs() < 1e-9
                && (a.z - m.to.z).abs() < 1e-9
        });
        if !stays || matches!(m.kind, MoveKind::Arc { .. }) {
            want.push(*m);
        }
        at = Some(m.to);
    }
    assert_eq!(
        want.len(),
        got.len(),
        "{name} {thread}: {} planned moves, {} read",
        want.len(),
        got.len()
    );
    let mut helix = 0;
    for (k, (w, g)) in want.iter().zip(got).enumerate() {
        let to = [w.to.x, w.to.y, w.to.z];
        assert!(
            to.iter().zip(g.to).all(|(a, b)| (a - b).abs() <= tol),
            "{name} {thread} move {k} (line {}): planned {to:?}, read {:?}",
            g.line,
            g.to
        );
        let comp = match g.state.comp {
            Comp::Off => None,
            Comp::Left { .. } => Some(CompSide::Left),
            Comp::Right { .. } => Some(CompSide::Right),
        };
        assert_eq!(comp, w.comp, "{name} {thread} move {k}: compensation");
        match (w.kind, g.kind) {
            (MoveKind::Rapid, MillKind::Rapid) | (MoveKind::Feed, MillKind::Feed) => {}
            (
                MoveKind::Arc { center, cw },
                MillKind::Arc {
                    centre, clockwise, ..
                },
            ) => {
                assert_eq!(cw, clockwise, "{name} {thread} move {k}: direction");
                assert!(
                    (center.0 - centre[0]).abs() <= 2.0 * tol
                        && (center.1 - centre[1]).abs() <= 2.0 * tol,
                    "{name} {thread} move {k}: centre {center:?} read {centre:?}"
                );
                // A full-turn helix arc of the thread advances one lead.
                let (_, sweep) = g.sweep(tol).unwrap();
                if (sweep.abs() - std::f64::consts::TAU).abs() < 1e-6
                    && w.pass > 0
                    && plan.taper == 0.0
                {
                    let dz = (g.to[2] - g.from[2]).abs();
                    if (dz - plan.lead).abs() <= 2.0 * tol {
                        helix += 1;
                    }
                }
            }
            (a, b) => panic!("{name} {thread} move {k}: planned {a:?}, read {b:?}"),
        }
    }
    assert!(
        helix as u32 >= plan.turns.min(1),
        "{name} {thread}: no full turn advanced one lead ({})",
        plan.lead
    );
}
