//! Exact chip areas for a sharp V tool.
//!
//! Each pass leaves a V-shaped "tent" below the crest line: apex at lateral position `z`, depth `d`,
//! flanks at the tool's half angle (slope `t = tan(half angle)` laterally per unit of depth), so its
//! area is `d²·t`. The groove after n passes is the union of n tents; a pass's chip is what its tent
//! adds to the union. Tents of equal slope have a simple union: drop the tents whose apex lies inside
//! another, sort the rest by apex, and subtract the small V below each valley between neighbours
//! (the intersection of two non-neighbours lies inside the tent between them, so inclusion–exclusion
//! stops at neighbours). The result is exact, with no polygon clipping.

/// The union area of tents `(z, depth)` with flank slope `t`.
pub fn union_area(tents: &[(f64, f64)], t: f64) -> f64 {
    if t <= 0.0 {
        return 0.0;
    }
    let mut sorted: Vec<(f64, f64)> = tents.iter().copied().filter(|&(_, d)| d > 0.0).collect();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
    // Keep the tents no other tent covers: a tent at (z, d) covers (z', d') when d − |z − z'|/t ≥ d'.
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(sorted.len());
    for tent in sorted {
        if let Some(&last) = kept.last() {
            if covers(last, tent, t) {
                continue;
            }
        }
        while let Some(&last) = kept.last() {
            if covers(tent, last, t) {
                kept.pop();
            } else {
                break;
            }
        }
        kept.push(tent);
    }
    let mut area: f64 = kept.iter().map(|&(_, d)| d * d * t).sum();
    for pair in kept.windows(2) {
        let ((za, da), (zb, db)) = (pair[0], pair[1]);
        let valley = (da + db - (zb - za) / t) / 2.0;
        if valley > 0.0 {
            area -= valley * valley * t;
        }
    }
    area
}

fn covers(a: (f64, f64), b: (f64, f64), t: f64) -> bool {
    a.1 - (a.0 - b.0).abs() / t >= b.1
}

/// The chip area of each pass in order: how much its tent adds to the groove cut before it.
pub fn chip_areas(tents: &[(f64, f64)], t: f64) -> Vec<f64> {
    let mut before = 0.0;
    (1..=tents.len())
        .map(|n| {
            let after = union_area(&tents[..n], t);
            // Never negative, and never −0 (an empty f64 sum is −0.0).
            let chip = if after > before { after - before } else { 0.0 };
            before = after;
            chip
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const T60: f64 = 0.577_350_269_189_625_8; // tan 30°

    #[test]
    fn one_tent_is_d_squared_t() {
        assert!((union_area(&[(0.0, 2.0)], T60) - 4.0 * T60).abs() < 1e-12);
    }

    #[test]
    fn radial_passes_telescope() {
        let areas = chip_areas(&[(0.0, 1.0), (0.0, 2.0)], 1.0);
        assert_eq!(areas, vec![1.0, 3.0]);
    }

    #[test]
    fn flank_passes_share_one_flank() {
        // Tip riding the left flank: offset = d·t; the union is the deepest tent alone.
        let tents: Vec<_> = [0.5, 1.0, 1.5].iter().map(|&d| (d * T60, d)).collect();
        assert!((union_area(&tents, T60) - 1.5 * 1.5 * T60).abs() < 1e-12);
    }

    #[test]
    fn two_apart_tents_overlap_by_a_small_v() {
        // t = 1: tents of depth 1 at z = 0 and z = 1 meet at depth 0.5 → overlap 0.25.
        assert!((union_area(&[(0.0, 1.0), (1.0, 1.0)], 1.0) - 1.75).abs() < 1e-12);
        // Apart by more than their width: no overlap.
        assert!((union_area(&[(0.0, 1.0), (3.0, 1.0)], 1.0) - 2.0).abs() < 1e-12);
    }

    /// Numerical integral of the upper envelope, as an independent oracle.
    fn brute(tents: &[(f64, f64)], t: f64) -> f64 {
        let lo = tents
            .iter()
            .map(|&(z, d)| z - d * t)
            .fold(f64::INFINITY, f64::min);
        let hi = tents
            .iter()
            .map(|&(z, d)| z + d * t)
            .fold(f64::NEG_INFINITY, f64::max);
        let steps = 20_000;
        let h = (hi - lo) / steps as f64;
        (0..steps)
            .map(|i| {
                let z = lo + (i as f64 + 0.5) * h;
                tents
                    .iter()
                    .map(|&(zc, d)| (d - (z - zc).abs() / t).max(0.0))
                    .fold(0.0, f64::max)
                    * h
            })
            .sum()
    }

    proptest! {
        #[test]
        fn union_matches_numerical_integral(
            tents in proptest::collection::vec((-2.0..2.0f64, 0.01..2.0f64), 1..8),
            t in 0.2..1.5f64,
        ) {
            let exact = union_area(&tents, t);
            let approx = brute(&tents, t);
            prop_assert!((exact - approx).abs() < 1e-3 * approx.max(1.0), "{exact} vs {approx}");
        }
    }
}
