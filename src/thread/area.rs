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
/// Incremental: each tent is inserted into the envelope of those before it (amortised O(log n)
/// a pass), so a thread of n passes costs O(n log n), not the O(n² log n) of taking the union
/// of every prefix ([`union_area`] stays the reference the tests compare with).
pub fn chip_areas(tents: &[(f64, f64)], t: f64) -> Vec<f64> {
    let mut envelope = Envelope::new(t);
    tents.iter().map(|&tent| envelope.insert(tent)).collect()
}

/// The tents no other covers, by apex position, and the area of their union.
///
/// A sorted vector rather than a tree: a thread's tents cover one another as the passes go
/// deeper (each radial or flank pass covers the one before it, a spring pass is covered by the
/// pass it repeats), so the envelope holds a handful of tents, and a look-up is a binary search
/// with no allocation (a `BTreeMap` here cost 2.8 times the instructions; docs/performance.md).
/// The price is a worst case no thread has: tents that never cover one another (one depth, every
/// pass at another offset, in no order) cost a shift of the vector each, 82 ms for 32,000
/// against the tree's 15 ms.
struct Envelope {
    t: f64,
    /// By [`Key`], each key once.
    kept: Vec<(Key, f64)>,
    area: f64,
}

/// A position along Z as a sort key: f64's total order.
#[derive(Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
struct Key(i64);

impl Key {
    fn of(z: f64) -> Key {
        let bits = z.to_bits() as i64;
        Key(bits ^ (((bits >> 63) as u64) >> 1) as i64)
    }

    fn z(self) -> f64 {
        let bits = self.0 ^ ((((self.0 >> 63) as u64) >> 1) as i64);
        f64::from_bits(bits as u64)
    }
}

impl Envelope {
    fn new(t: f64) -> Envelope {
        Envelope {
            t,
            kept: Vec::new(),
            area: 0.0,
        }
    }

    /// The small V two neighbouring tents share (its area).
    fn valley(&self, a: (f64, f64), b: (f64, f64)) -> f64 {
        let v = (a.1 + b.1 - (b.0 - a.0) / self.t) / 2.0;
        if v > 0.0 {
            v * v * self.t
        } else {
            0.0
        }
    }

    /// The kept tent at `i`, as `(z, depth)`.
    fn tent(&self, i: usize) -> (f64, f64) {
        let (k, d) = self.kept[i];
        (k.z(), d)
    }

    /// The area a run of neighbouring tents adds between two others: their own areas less the
    /// valleys along the chain `left, middle…, right`.
    fn chain(
        &self,
        left: Option<(f64, f64)>,
        middle: impl Iterator<Item = (f64, f64)> + Clone,
        right: Option<(f64, f64)>,
    ) -> f64 {
        let own: f64 = middle.clone().map(|(_, d)| d * d * self.t).sum();
        let seq = left.into_iter().chain(middle).chain(right);
        let shared: f64 = seq
            .clone()
            .zip(seq.skip(1))
            .map(|(a, b)| self.valley(a, b))
            .sum();
        own - shared
    }

    /// Adds a tent; the area it adds to the union.
    fn insert(&mut self, tent: (f64, f64)) -> f64 {
        let (z, d) = tent;
        if self.t <= 0.0 || d <= 0.0 {
            return 0.0;
        }
        let t = self.t;
        let key = Key::of(z);
        // The tents at or before the new apex are `kept[..at]`, the ones after it `kept[at..]`.
        let at = self.kept.partition_point(|&(k, _)| k <= key);
        let n = self.kept.len();
        if (at > 0 && covers(self.tent(at - 1), tent, t))
            || (at < n && covers(self.tent(at), tent, t))
        {
            return 0.0;
        }
        // The run of tents the new one covers, `kept[lo..hi]` around `at`, and the first it does
        // not cover on each side.
        let mut lo = at;
        while lo > 0 && covers(tent, self.tent(lo - 1), t) {
            lo -= 1;
        }
        let mut hi = at;
        while hi < n && covers(tent, self.tent(hi), t) {
            hi += 1;
        }
        let outer_left = lo.checked_sub(1).map(|i| self.tent(i));
        let outer_right = (hi < n).then(|| self.tent(hi));
        // The chain before: outer_left, removed…, outer_right; after: outer_left, tent, outer_right.
        let before = self.chain(outer_left, (lo..hi).map(|i| self.tent(i)), outer_right);
        let after = self.chain(outer_left, std::iter::once(tent), outer_right);
        if lo < hi {
            self.kept[lo] = (key, d);
            self.kept.drain(lo + 1..hi);
        } else {
            self.kept.insert(lo, (key, d));
        }
        let old = self.area;
        self.area += after - before;
        // Never negative, and never −0.
        if self.area > old {
            self.area - old
        } else {
            0.0
        }
    }
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

    proptest! {
        /// The incremental chip areas are the differences of the prefixes' unions.
        #[test]
        fn chip_areas_are_the_prefix_unions_differences(
            tents in proptest::collection::vec((-5.0f64..5.0, 0.0f64..2.0), 1..40),
            t in 0.1f64..2.0,
        ) {
            let fast = chip_areas(&tents, t);
            let mut before = 0.0;
            for (n, chip) in fast.iter().enumerate() {
                let after = union_area(&tents[..=n], t);
                let slow = if after > before { after - before } else { 0.0 };
                before = after;
                prop_assert!((chip - slow).abs() < 1e-9 * after.max(1.0), "{chip} vs {slow} at {n}");
            }
        }
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
