//! Pass plans: the depth law (how deep each pass goes) and the finishing passes.

use serde::Serialize;

use super::{area, FinishPosition, Job};
use crate::diag::{Code, Diagnostic, Result};
use crate::units::Pos;

/// Depths closer than this are the same depth (mm). Far below any controller's resolution, far
/// above f64 noise on lengths of a few metres.
pub const DEPTH_TOLERANCE: f64 = 1e-9;

/// More rough passes than this is a programming error (a first depth of a few microns on a deep
/// thread), not a plan. Controllers stop at a few hundred; APT allows 200 cuts.
pub const MAX_ROUGH_PASSES: u32 = 10_000;

/// How deep each rough pass goes.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "law", rename_all = "snake_case")]
pub enum DepthLaw {
    /// `d_n = first · n^(1/degression)`, each increment at least `min_step`.
    ///
    /// degression 1 is a constant step (GSK G78 D0: "every pass cuts Δd"); degression 2 is the
    /// constant-area law `d_n = Δd·√n` (GSK G78 D1 and G76, Fanuc G76). Once √n·Δd − √(n−1)·Δd falls
    /// below Δdmin every later pass cuts Δdmin (GSK G78 §7 note 1: "next depth = Δdmin + previous").
    Power {
        first: f64,
        degression: f64,
        min_step: f64,
    },
    /// Cumulative depths, given outright.
    Explicit { depths: Vec<f64> },
    /// The first pass is cut at the reference itself (depth 0: the controller only knows where the
    /// tool stands, not the crest), then `d_n = step · (n−1)^(1/degression)`.
    ///
    /// OmniTurn G33 (seed 002): "the starting location in X is the major diameter, less the amount
    /// of the first pass"; I is "the starting incremental amount of material to be removed after
    /// the first pass", then the cut shrinks so the material removed stays constant — degression
    /// 2 measured from the start position: `d_n = I·√(n−1)`.
    FromStart { step: f64, degression: f64 },
}

/// The depth law plus what it is applied to.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassPlan {
    pub law: DepthLaw,
    /// Radial stock left for the finishing passes: rough passes stop at `depth − finish_allowance`.
    pub finish_allowance: f64,
    /// Passes at full depth: the first removes the allowance, the rest are spring passes.
    pub finish_passes: u32,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum PassKind {
    Rough,
    Finish,
}

/// One pass of the plan.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Pass {
    /// 1-based pass number.
    pub n: u32,
    pub kind: PassKind,
    /// Depth below the crest (radial).
    pub depth: f64,
    /// Depth added by this pass.
    pub increment: f64,
    /// Lateral (+Z) shift of the infeed point from the reference point.
    pub offset: f64,
    /// Where the pass's thread move begins (radius, mm), before any multi-start shift.
    pub start: Pos,
    /// Chip cross-section of the pass for a sharp V of the tool angle (mm²).
    pub area: f64,
    /// The pass's share of the total area (0..1).
    pub share: f64,
}

/// Cumulative rough depths for `law`, stopping at `limit` (the last one is clipped to it).
pub fn rough_depths(law: &DepthLaw, limit: f64) -> Result<Vec<f64>> {
    let mut depths = Vec::new();
    match law {
        DepthLaw::Power {
            first,
            degression,
            min_step,
        } => {
            let mut previous = 0.0_f64;
            for n in 1..=MAX_ROUGH_PASSES + 1 {
                if n > MAX_ROUGH_PASSES {
                    return Err(too_many(limit, *first));
                }
                let law_depth = first * f64::from(n).powf(1.0 / degression);
                let depth = if n == 1 {
                    law_depth
                } else {
                    law_depth.max(previous + min_step)
                };
                if depth >= limit - DEPTH_TOLERANCE {
                    depths.push(limit);
                    break;
                }
                depths.push(depth);
                previous = depth;
            }
        }
        DepthLaw::FromStart { step, degression } => {
            depths.push(0.0);
            if limit <= DEPTH_TOLERANCE {
                return Ok(depths);
            }
            for k in 1..=MAX_ROUGH_PASSES {
                if k == MAX_ROUGH_PASSES {
                    return Err(too_many(limit, *step));
                }
                let depth = step * f64::from(k).powf(1.0 / degression);
                if depth >= limit - DEPTH_TOLERANCE {
                    depths.push(limit);
                    break;
                }
                depths.push(depth);
            }
        }
        DepthLaw::Explicit { depths: given } => {
            for &d in given {
                if d >= limit - DEPTH_TOLERANCE {
                    depths.push(limit);
                    break;
                }
                depths.push(d);
            }
        }
    }
    Ok(depths)
}

fn too_many(limit: f64, first: f64) -> Diagnostic {
    Diagnostic::error(
        Code::TooManyPasses,
        Default::default(),
        format!(
            "the plan needs more than {MAX_ROUGH_PASSES} rough passes (first depth {first}, rough depth {limit})"
        ),
    )
    .with_hint("raise the first depth of cut or the minimum cut")
}

/// The full pass table of a job: rough passes, then finishing passes at full depth.
pub fn plan_passes(job: &Job) -> Result<Vec<Pass>> {
    let mut passes = plan_geometry(job)?;
    let t = super::tan_deg(job.tool_angle_deg / 2.0);
    let cuts: Vec<(f64, f64)> = passes.iter().map(|p| (p.offset, p.depth)).collect();
    let areas = area::chip_areas(&cuts, t);
    let sum: f64 = areas.iter().sum();
    for (p, a) in passes.iter_mut().zip(areas) {
        p.area = a;
        p.share = if sum > 0.0 { a / sum } else { 0.0 };
    }
    Ok(passes)
}

/// The pass table without chip areas (`area` and `share` are 0): all that motion needs.
pub fn plan_geometry(job: &Job) -> Result<Vec<Pass>> {
    let total = job.geometry.depth;
    let limit = total - job.plan.finish_allowance;
    let rough = rough_depths(&job.plan.law, limit).map_err(|mut e| {
        e.span = job.span;
        e
    })?;
    let mut passes: Vec<Pass> = Vec::with_capacity(rough.len() + job.plan.finish_passes as usize);
    let place = |depth: f64, offset: f64| {
        job.geometry
            .crest_start
            .plus(job.geometry.side.infeed().scale(depth))
            .plus(job.geometry.side.lateral().scale(offset))
    };
    let mut previous = 0.0;
    for (i, &depth) in rough.iter().enumerate() {
        let n = i as u32 + 1;
        let offset = job.infeed.offset(n, depth, total);
        passes.push(Pass {
            n,
            kind: PassKind::Rough,
            depth,
            increment: depth - previous,
            offset,
            start: place(depth, offset),
            area: 0.0,
            share: 0.0,
        });
        previous = depth;
    }
    let finish_offset = match (job.finish_at, passes.last()) {
        (FinishPosition::LastRough, Some(last)) => last.offset,
        _ => job.infeed.axis(total),
    };
    for i in 0..job.plan.finish_passes {
        let n = passes.len() as u32 + 1;
        passes.push(Pass {
            n,
            kind: PassKind::Finish,
            depth: total,
            increment: if i == 0 { total - previous } else { 0.0 },
            offset: finish_offset,
            start: place(total, finish_offset),
            area: 0.0,
            share: 0.0,
        });
    }
    Ok(passes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn degressive(first: f64, min_step: f64) -> DepthLaw {
        DepthLaw::Power {
            first,
            degression: 2.0,
            min_step,
        }
    }

    #[test]
    fn sqrt_law_with_minimum_cut_hand_computed() {
        // threading-notes §c.3: k 1.227, Δd 0.4, Δdmin 0.1, d 0.05 → limit 1.177.
        let d = rough_depths(&degressive(0.4, 0.1), 1.177).unwrap();
        let expect = [
            0.4,
            0.4 * 2f64.sqrt(),
            0.4 * 3f64.sqrt(),
            0.8,
            0.9,
            1.0,
            1.1,
            1.177,
        ];
        assert_eq!(d.len(), expect.len());
        for (a, b) in d.iter().zip(expect) {
            assert!((a - b).abs() < 1e-12, "{d:?}");
        }
    }

    #[test]
    fn constant_step_is_clipped_to_the_limit() {
        let law = DepthLaw::Power {
            first: 0.3,
            degression: 1.0,
            min_step: 0.0,
        };
        let d = rough_depths(&law, 1.0).unwrap();
        assert_eq!(d.len(), 4);
        assert!((d[2] - 0.9).abs() < 1e-12 && d[3] == 1.0);
    }

    #[test]
    fn exact_landing_is_not_doubled() {
        // 0.25·√16 = 1.0 exactly: the 16th pass lands on the limit, no 17th sliver pass.
        let d = rough_depths(&degressive(0.25, 0.0), 1.0).unwrap();
        assert_eq!(d.len(), 16);
    }

    #[test]
    fn from_start_law_cuts_the_first_pass_at_the_reference() {
        // OmniTurn seed, first external example: I .012 over .025 (inch, radius).
        let law = DepthLaw::FromStart {
            step: 0.012,
            degression: 2.0,
        };
        let d = rough_depths(&law, 0.025).unwrap();
        let expect = [
            0.0,
            0.012,
            0.012 * 2f64.sqrt(),
            0.012 * 3f64.sqrt(),
            0.024,
            0.025,
        ];
        assert_eq!(d.len(), expect.len(), "{d:?}");
        for (a, b) in d.iter().zip(expect) {
            assert!((a - b).abs() < 1e-15, "{d:?}");
        }
        // 0.01·√25 lands exactly on 0.05: no sliver pass.
        let law = DepthLaw::FromStart {
            step: 0.01,
            degression: 2.0,
        };
        assert_eq!(rough_depths(&law, 0.05).unwrap().len(), 26);
    }

    #[test]
    fn runaway_plans_are_refused() {
        let e = rough_depths(&degressive(1e-6, 0.0), 100.0).unwrap_err();
        assert_eq!(e.code, Code::TooManyPasses);
    }
}
