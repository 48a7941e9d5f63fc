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
pub const CUTOFF: f64 = 1e-14;

/// 2^32, the scale of the 32-bit thresholds.
const SCALE: f64 = 4_294_967_296.0;

/// The four kinds of random choice of the reference engine.
pub trait Draws {
    /// True with probability `t / 2^32`; no draw is made when the outcome is
    /// certain (t = 0 or t >= 2^32).
    fn chance(&mut self, t: u64) -> bool;
    /// An index k with probability (c[k] - c[k-1]) / 2^32 for the increasing
    /// cumulative thresholds `c` (the last index takes what is left).
    fn pick(&mut self, cumulative: &[u64]) -> usize;
    /// A fair coin.
    fn coin(&mut self) -> bool;
    /// A uniform integer in 0..n (n >= 1).
    fn below(&mut self, n: u32) -> u32;
}

impl Draws for Xoshiro256PlusPlus {
    #[inline]
    fn chance(&mut self, t: u64) -> bool {
        if t == 0 {
            false
        } else if t >= 1 << 32 {
            true
        } else {
            (self.next_u32() as u64) < t
        }
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
#[derive(Debug, Clone, Default)]
pub struct Enumerator {
    /// The branch taken at each draw of the current path, and the number of
    /// branches of that draw.
    path: Vec<(usize, usize)>,
    /// Probability of each branch taken so far on the current path.
    weights: Vec<f64>,
    /// Position of the next draw on the current path.
    pos: usize,
}

impl Enumerator {
    /// A new enumeration (the first path takes branch 0 of every draw).
    pub fn new() -> Self {
        Self::default()
    }

    /// Probability of the path just run.
    pub fn probability(&self) -> f64 {
        self.weights[..self.pos].iter().product()
    }

    /// Move to the next path; false when every path has been run.
    pub fn advance(&mut self) -> bool {
        self.path.truncate(self.pos);
        while let Some((k, n)) = self.path.pop() {
            if k + 1 < n {
                self.path.push((k + 1, n));
                self.pos = 0;
                self.weights.clear();
                return true;
            }
        }
        false
    }

    /// Take the next branch among `probs` (the probability of each branch).
    /// Below a path probability of [`CUTOFF`] the siblings are no longer
    /// explored: the path takes branch `pos mod n` with weight 1 (it carries
    /// its whole remaining mass), so that unbounded computations (a
    /// relocation walk that keeps hitting full sites) end; the mass moved is
    /// below CUTOFF per truncated path.
    fn branch(&mut self, probs: &[f64]) -> usize {
        let here: f64 = self.weights[..self.pos.min(self.weights.len())].iter().product();
        let truncated = here < CUTOFF;
        let k = if self.pos < self.path.len() {
            self.path[self.pos].0
        } else if truncated {
            let k = self.pos % probs.len();
            self.path.push((k, 1));
            k
        } else {
            self.path.push((0, probs.len()));
            0
        };
        self.weights.truncate(self.pos);
        self.weights.push(if truncated { 1.0 } else { probs[k] });
        self.pos += 1;
        k
    }
}

impl Draws for Enumerator {
    fn chance(&mut self, t: u64) -> bool {
        if t == 0 {
            false
        } else if t >= 1 << 32 {
            true
        } else {
            let q = t as f64 / SCALE;
            self.branch(&[q, 1.0 - q]) == 0
        }
    }

    fn pick(&mut self, cumulative: &[u64]) -> usize {
        let mut probs = Vec::with_capacity(cumulative.len());
        let mut prev = 0u64;
        for (k, &c) in cumulative.iter().enumerate() {
            let c = if k + 1 == cumulative.len() { 1 << 32 } else { c };
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
    }
}
