//! A deterministic Latin hypercube on the unit box: the space-filling sweep
//! of `--method surrogate`.
//!
//! Each of the `d` coordinates takes each of the `N` stratum centres
//! `(k + ½)/N` exactly once. Of [`CANDIDATES`] such designs, drawn from a
//! fixed seed, the one whose two closest points are farthest apart
//! (maximin) is kept. The same arguments always give the same points, to
//! the bit, so a second call finds them in the journal.

/// Random designs compared for the maximin choice.
pub const CANDIDATES: usize = 64;

/// The seed of the designs.
pub const SEED: u64 = 0x5eed_1a7e_5c0f_f1e5;

/// SplitMix64: a small generator with a fixed sequence for a seed.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n > 0`; the bias of the modulus is below
    /// `n / 2⁶⁴`, nothing for a design's size).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// The least squared distance between two points of a design.
fn least_distance(points: &[Vec<f64>]) -> f64 {
    let mut least = f64::INFINITY;
    for (i, a) in points.iter().enumerate() {
        for b in &points[i + 1..] {
            let d: f64 = a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum();
            least = least.min(d);
        }
    }
    least
}

/// `n` points of the `dims`-dimensional unit box, a maximin Latin
/// hypercube of stratum centres (empty when `n` or `dims` is zero).
pub fn latin_hypercube(n: usize, dims: usize) -> Vec<Vec<f64>> {
    if n == 0 || dims == 0 {
        return Vec::new();
    }
    let mut rng = SplitMix64(SEED ^ ((n as u64) << 32) ^ dims as u64);
    let mut best: Vec<Vec<f64>> = Vec::new();
    let mut best_distance = -1.0;
    let mut order: Vec<usize> = Vec::with_capacity(n);
    for _ in 0..CANDIDATES {
        let mut design = vec![vec![0.0; dims]; n];
        for j in 0..dims {
            order.clear();
            order.extend(0..n);
            // Fisher–Yates shuffle of the strata.
            for i in (1..n).rev() {
                order.swap(i, rng.below(i + 1));
            }
            for (point, &k) in design.iter_mut().zip(&order) {
                point[j] = (k as f64 + 0.5) / n as f64;
            }
        }
        let distance = least_distance(&design);
        if distance > best_distance {
            best_distance = distance;
            best = design;
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every coordinate holds every stratum centre once; the design is the
    /// same on a second call; a 1-D design is the grid of centres.
    #[test]
    fn latin_hypercube_fills_every_stratum_once_and_repeats() {
        for (n, dims) in [(11, 1), (21, 2), (31, 3)] {
            let design = latin_hypercube(n, dims);
            assert_eq!(design.len(), n);
            for j in 0..dims {
                let mut strata: Vec<usize> = design
                    .iter()
                    .map(|p| (p[j] * n as f64 - 0.5).round() as usize)
                    .collect();
                strata.sort_unstable();
                assert_eq!(strata, (0..n).collect::<Vec<_>>(), "n {n}, dims {dims}");
            }
            assert_eq!(design, latin_hypercube(n, dims));
        }
        let mut grid: Vec<f64> = latin_hypercube(4, 1).into_iter().map(|p| p[0]).collect();
        grid.sort_by(f64::total_cmp);
        assert_eq!(grid, vec![0.125, 0.375, 0.625, 0.875]);
        assert!(latin_hypercube(0, 2).is_empty());
    }

    /// The maximin choice spreads the points: in 2-D with 20 points, the
    /// closest pair of the chosen design is farther apart than that of the
    /// first candidate alone would typically be (at least one stratum
    /// width, 1/20, where a random design often has two points diagonal
    /// neighbours at √2/20).
    #[test]
    fn latin_hypercube_maximin_keeps_points_apart() {
        let design = latin_hypercube(20, 2);
        let least = least_distance(&design).sqrt();
        assert!(least >= 1.5 / 20.0, "closest pair {least}");
    }
}
