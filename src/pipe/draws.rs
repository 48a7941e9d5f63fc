//! The random choices of one pipe step, as a trait (MODEL.md A3-A6): every
//! random decision of the reference engine is one of four kinds of draw.
//!
//! - [`Xoshiro256PlusPlus`] makes the draws of a run (the same calls, in the
//!   same order, as before the trait existed: runs are unchanged).
//! - [`Enumerator`] walks every branch of every draw instead, with its exact
//!   probability: the reference engine then yields the exact one-step outcome
//!   distribution of a state (`crate::validate::conformance`, level 1 of
//!   `validate`).
//!
//! Probabilities are those the engine really uses: a probability q becomes
//! the 32-bit threshold `t = round(q 2^32)` of [`super::collision::threshold`],
//! so a draw is true with probability t / 2^32 exactly.

use rand::{Rng, RngExt};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Path probability below which [`Enumerator`] stops branching.
pub const CUTOFF: f64 = 1e-10;

/// 2^32, the scale of the 32-bit thresholds.
const SCALE: f64 = 4_294_967_296.0;

/// The four kinds of random choice of the reference engine.
pub trait Draws {
    /// True with probability `t / 2^32`; no draw is made when the outcome is
    /// certain (t = 0 or t >= 2^32).
    #[inline]
    fn chance(&mut self, t: u64) -> bool {
        if t == 0 {
            false
        } else if t >= 1 << 32 {
            true
        } else {
            self.uncertain(t)
        }
    }
    /// [`Draws::chance`] for an uncertain outcome, 0 < t < 2^32.
    fn uncertain(&mut self, t: u64) -> bool;
    /// An index k with probability (c\[k\] - c\[k-1\]) / 2^32 for the increasing
    /// cumulative thresholds `c` (the last index takes what is left).
    fn pick(&mut self, cumulative: &[u64]) -> usize;
    /// A fair coin.
    fn coin(&mut self) -> bool;
    /// A uniform integer in 0..n (n >= 1).
    fn below(&mut self, n: u32) -> u32;
}

impl Draws for Xoshiro256PlusPlus {
    #[inline]
    fn uncertain(&mut self, t: u64) -> bool {
        (self.next_u32() as u64) < t
    }

    #[inline]
    fn pick(&mut self, cumulative: &[u64]) -> usize {
        let u = self.next_u32() as u64;
        cumulative
            .iter()
            .position(|&c| u < c)
            .unwrap_or(cumulative.len() - 1)
    }

    #[inline]
    fn coin(&mut self) -> bool {
        self.next_u32() >> 31 == 1
    }

    #[inline]
    fn below(&mut self, n: u32) -> u32 {
        self.random_range(0..n)
    }
}

/// Enumerates every sequence of draw outcomes of a computation, depth first:
/// run the computation, read [`Enumerator::probability`], then call
/// [`Enumerator::advance`] until it returns false.
///
/// Paths whose probability falls below [`CUTOFF`] are not split further:
/// from there on the path follows one branch per draw (chosen by a fixed
/// hash of the draw's position, so that a walk does not go back and forth
/// between two full sites) and keeps its whole mass. The mass so assigned
/// is summed in [`Enumerator::truncated_mass`]: an upper bound on the total
/// variation distance between the computed and the exact distribution.
#[derive(Debug, Clone, Default)]
pub struct Enumerator {
    /// The branch taken at each draw of the current path, and the number of
    /// branches of that draw (1 for a draw past the cutoff).
    path: Vec<(usize, usize)>,
    /// `prefix[i]`: probability of the current path up to draw i
    /// (`prefix[0] = 1`).
    prefix: Vec<f64>,
    /// Position of the next draw on the current path.
    pos: usize,
    /// Probability of the current path where it passed the cutoff.
    cut_at: Option<f64>,
    /// Sum of the probabilities of the truncated paths run so far.
    truncated: f64,
}

impl Enumerator {
    /// A new enumeration (the first path takes branch 0 of every draw).
    pub fn new() -> Self {
        Self {
            prefix: vec![1.0],
            ..Self::default()
        }
    }

    /// Probability of the path just run.
    pub fn probability(&self) -> f64 {
        self.prefix[self.pos]
    }

    /// Total probability of the paths (run so far) that were truncated at
    /// [`CUTOFF`]; bounds the error of the enumerated distribution.
    pub fn truncated_mass(&self) -> f64 {
        self.truncated + self.cut_at.unwrap_or(0.0)
    }

    /// Move to the next path; false when every path has been run.
    pub fn advance(&mut self) -> bool {
        if let Some(m) = self.cut_at.take() {
            self.truncated += m;
        }
        self.path.truncate(self.pos);
        while let Some((k, n)) = self.path.pop() {
            if k + 1 < n {
                self.path.push((k + 1, n));
                self.pos = 0;
                self.prefix.truncate(1);
                return true;
            }
        }
        false
    }

    /// Take the next branch among `probs` (the probability of each branch).
    fn branch(&mut self, probs: &[f64]) -> usize {
        let here = self.prefix[self.pos];
        let truncated = here < CUTOFF;
        let k = if self.pos < self.path.len() {
            self.path[self.pos].0
        } else if truncated {
            if self.cut_at.is_none() {
                self.cut_at = Some(here);
            }
            // splitmix64 of the position: a fixed, well-mixed choice
            let mut z = (self.pos as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            let k = ((z ^ (z >> 31)) % probs.len() as u64) as usize;
            self.path.push((k, 1));
            k
        } else {
            self.path.push((0, probs.len()));
            0
        };
        // past the cutoff the path keeps its whole mass
        let w = if truncated { 1.0 } else { probs[k] };
        self.prefix.truncate(self.pos + 1);
        self.prefix.push(here * w);
        self.pos += 1;
        k
    }
}

impl Draws for Enumerator {
    fn uncertain(&mut self, t: u64) -> bool {
        let q = t as f64 / SCALE;
        self.branch(&[q, 1.0 - q]) == 0
    }

    fn pick(&mut self, cumulative: &[u64]) -> usize {
        let mut probs = Vec::with_capacity(cumulative.len());
        let mut prev = 0u64;
        for (k, &c) in cumulative.iter().enumerate() {
            let c = if k + 1 == cumulative.len() {
                1 << 32
            } else {
                c
            };
            probs.push(c.saturating_sub(prev) as f64 / SCALE);
            prev = c.max(prev);
        }
        self.branch(&probs)
    }

    fn coin(&mut self) -> bool {
        self.branch(&[0.5, 0.5]) == 0
    }

    fn below(&mut self, n: u32) -> u32 {
        let probs = vec![1.0 / n as f64; n as usize];
        self.branch(&probs) as u32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn enumeration_visits_every_path_with_its_probability() {
        // two chances and a three-way uniform draw: 12 paths summing to 1
        let mut e = Enumerator::new();
        let t = (0.25 * SCALE) as u64;
        let (mut paths, mut total) = (0, 0.0);
        loop {
            let a = e.chance(t);
            let n = if a { e.below(3) } else { 0 };
            let _ = e.chance(1 << 31);
            let _ = n;
            total += e.probability();
            paths += 1;
            if !e.advance() {
                break;
            }
        }
        assert_eq!(paths, 3 * 2 + 2);
        assert!((total - 1.0).abs() < 1e-12);
        assert_eq!(e.truncated_mass(), 0.0);
    }

    #[test]
    fn an_endless_walk_is_cut_and_its_mass_reported() {
        // a walk that goes on with probability 1/3 at each hop: without the
        // cutoff the enumeration would never end
        let mut e = Enumerator::new();
        let (mut paths, mut total) = (0u64, 0.0);
        loop {
            while e.below(3) == 0 {}
            total += e.probability();
            paths += 1;
            if !e.advance() {
                break;
            }
        }
        assert!((total - 1.0).abs() < 1e-12, "{total}");
        let m = e.truncated_mass();
        assert!(m > 0.0 && m < 10.0 * CUTOFF, "{m}");
        assert!(paths < 1 << 20, "{paths}");
    }
}
