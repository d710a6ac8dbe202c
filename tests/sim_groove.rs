//! `sim::groove` (what `check` judges of a groove, without simulating the material) gives exactly
//! the values `sim::section` reports for the same passes and tool, and refuses what it refuses.

use proptest::prelude::*;
use threadcut::machine::Machine;
use threadcut::sim::{self, Tip, Tool};

fn job(src: &str) -> Option<threadcut::thread::Job> {
    let machine = Machine::built_in("fanuc").unwrap();
    threadcut::program::jobs(src.as_bytes(), &machine)
        .ok()?
        .into_iter()
        .next()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]
    #[test]
    fn the_groove_is_the_sections(
        pitch in prop::sample::select(vec![0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0]),
        depth_um in 300u32..2_500,
        first_um in 50u32..600,
        finishes in 1u32..4,
        angle in prop::sample::select(vec![0u32, 29, 30, 55, 60]),
        chamfer in 0u32..20,
        tip in 0usize..3,
        tip_size in 0.01f64..0.3,
        stock in -0.3f64..0.5,
    ) {
        let x = 20.0 - 2.0 * f64::from(depth_um) / 1000.0;
        let src = format!(
            "G0 X24. Z5.\nG76 P{finishes:02}{chamfer:02}{angle:02} Q50 R0.02\nG76 X{x:.3} Z-30. P{depth_um} Q{first_um} F{pitch:.1}\n"
        );
        let job = job(&src).expect("a G76 job");
        let passes = job.passes().expect("its passes");
        let tip = match tip {
            0 => Tip::Sharp,
            1 => Tip::Radius { radius: tip_size },
            _ => Tip::Flat { width: tip_size },
        };
        let tool = Tool { angle_deg: if angle == 0 { 60.0 } else { f64::from(angle) }, tip };
        let section = sim::section(&job, &passes, &tool, stock);
        let groove = sim::groove(&job, &passes, &tool, stock);
        match (section, groove) {
            // Debug prints each number's shortest exact text: equal texts, equal bits.
            (Ok(s), Ok(g)) => prop_assert_eq!(format!("{:?}", s.groove.form), format!("{g:?}")),
            (Err(a), Err(b)) => prop_assert_eq!(a.message, b.message),
            (a, b) => prop_assert!(false, "section {:?}, groove {:?}", a.is_ok(), b.is_ok()),
        }
    }
}
