//! What a pipe run measures rather than evolves (MODEL.md A7, A9, A11):
//! the particle counts and bin densities n_i of the reference engine
//! [`Pipe`], the open pipe's flux counters [`Flux`], and the observables of
//! the bin densities: the density contrast, the low-k structure factor that
//! detects travelling bands.

use super::collision::{MOVERS, REST_BIT};
use super::draws::Draws;
use super::Pipe;
use serde::Serialize;

/// Density contrast C = (1/n_mean) sum_i |n_i - n_{i+1}|, periodic in i
/// \[PH95 eq. 1\]. Returns 0 for an empty pipe.
pub fn contrast(n: &[f64]) -> f64 {
    let k = n.len();
    if k == 0 {
        return 0.0;
    }
    let mean = n.iter().sum::<f64>() / k as f64;
    if mean <= 0.0 {
        return 0.0;
    }
    let s: f64 = (0..k).map(|i| (n[i] - n[(i + 1) % k]).abs()).sum();
    s / mean
}

/// |sum_i (n_i - nbar) exp(2 pi i k i / K)|^2 of one density profile.
pub fn structure_factor(n: &[f64], k: usize) -> f64 {
    let len = n.len();
    if len == 0 {
        return 0.0;
    }
    let mean = n.iter().sum::<f64>() / len as f64;
    let (mut re, mut im) = (0.0, 0.0);
    for (i, &v) in n.iter().enumerate() {
        let phase = 2.0 * std::f64::consts::PI * (k * i % len) as f64 / len as f64;
        re += (v - mean) * phase.cos();
        im += (v - mean) * phase.sin();
    }
    re * re + im * im
}

/// Variance of one bin's particle count in the random start (A8): 6 * bin * W
/// independent channels occupied with probability rho/6.
pub fn random_start_bin_variance(rho: f64, bin: usize, width: usize) -> f64 {
    (bin * width) as f64 * rho * (1.0 - rho / 6.0)
}

/// Expected density contrast C of the random start, K bins of `bin` rows:
/// independent bins of mean mu = bin W rho and variance s2
/// ([`random_start_bin_variance`]), so E|n_i - n_{i+1}| = 2 sqrt(s2 / pi)
/// (normal approximation) and C(0) = K 2 sqrt(s2 / pi) / mu.
pub fn random_start_contrast(rho: f64, bin: usize, width: usize, bins: usize) -> f64 {
    let mu = (bin * width) as f64 * rho;
    let s2 = random_start_bin_variance(rho, bin, width);
    bins as f64 * 2.0 * (s2 / std::f64::consts::PI).sqrt() / mu
}

/// The band statistic s_low (MODEL.md A11) of density fields `fields[t][i]`
/// of a pipe of initial density `rho`, bins of `bin` rows and `width`
/// columns: the mean of S(1..3) over the fields divided by its random-start
/// value ([`LowK::mean`]).
pub fn s_low(fields: &[Vec<f64>], rho: f64, bin: usize, width: usize) -> f64 {
    let k = fields.first().map_or(0, |v| v.len());
    let mut low = LowK::new(3, k, random_start_bin_variance(rho, bin, width));
    for v in fields {
        low.add(v);
    }
    low.mean()
}

/// Accumulates S(k) for k = 1..=kmax over samples, normalised by its value
/// for the random start, K * (per-bin variance): waves give S(1..3) >> 1,
/// a structureless gas about 1 (MODEL.md A11).
#[derive(Debug, Clone)]
pub struct LowK {
    sums: Vec<f64>,
    samples: usize,
    norm: f64,
}

impl LowK {
    /// An accumulator for modes 1..=kmax with the random-start normalisation
    /// for K bins of per-bin variance `bin_variance`.
    pub fn new(kmax: usize, bins: usize, bin_variance: f64) -> Self {
        LowK {
            sums: vec![0.0; kmax],
            samples: 0,
            norm: bins as f64 * bin_variance,
        }
    }

    /// Add one density profile.
    pub fn add(&mut self, n: &[f64]) {
        for (k, s) in self.sums.iter_mut().enumerate() {
            *s += structure_factor(n, k + 1);
        }
        self.samples += 1;
    }

    /// Normalised S(k) for k = 1..=kmax (NaN without samples or normalisation).
    pub fn normalised(&self) -> Vec<f64> {
        self.sums
            .iter()
            .map(|s| {
                if self.samples == 0 || self.norm <= 0.0 {
                    f64::NAN
                } else {
                    s / self.samples as f64 / self.norm
                }
            })
            .collect()
    }

    /// Mean of the normalised S(1..=kmax): the `s_low` statistic.
    pub fn mean(&self) -> f64 {
        let v = self.normalised();
        v.iter().sum::<f64>() / v.len() as f64
    }
}

/// Counters of the open pipe (MODEL.md A7): injected - out_bottom - out_top
/// equals the change of the particle number, exactly.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Flux {
    /// Particles injected at the top so far.
    pub injected: u64,
    /// Particles that left below row 0 (the outflow).
    pub out_bottom: u64,
    /// Particles that left above row L-1.
    pub out_top: u64,
}

/// What the reference engine measures (MODEL.md A9, \[PH95 Fig. 3\]); the
/// fast engine counts the same quantities word by word.
impl<D: Draws> Pipe<D> {
    /// The sum of `f(state)` over every site.
    fn sum_sites(&self, f: impl Fn(u8) -> u64) -> u64 {
        (0..self.params().width)
            .map(|x| self.column(x).iter().map(|&s| f(s)).sum::<u64>())
            .sum()
    }

    /// Total number of particles N (all channels).
    pub fn particle_count(&self) -> u64 {
        self.sum_sites(|s| s.count_ones() as u64)
    }

    /// Kinetic energy E = number of moving particles \[PH95 Fig. 3b\].
    pub fn moving_count(&self) -> u64 {
        self.sum_sites(|s| (s & MOVERS).count_ones() as u64)
    }

    /// Number of rest particles on the lattice (not counting extras).
    pub fn rest_count(&self) -> u64 {
        self.sum_sites(|s| (s & REST_BIT) as u64)
    }

    /// Number of particles in each channel 0..=6 (for diagnostics).
    pub fn channel_counts(&self) -> [u64; 7] {
        let mut n = [0u64; 7];
        for x in 0..self.params().width {
            for &s in self.column(x) {
                for (c, v) in n.iter_mut().enumerate() {
                    *v += ((s >> c) & 1) as u64;
                }
            }
        }
        n
    }

    /// Bin densities n_i (A9): particles in rows `i*bin .. (i+1)*bin`, all columns.
    pub fn bin_counts(&self) -> Vec<f64> {
        let mut out = vec![0.0; self.params().bins()];
        self.fill_bin_counts(&mut out);
        out
    }

    /// [`Pipe::bin_counts`] into a buffer of length K (no allocation).
    pub fn fill_bin_counts(&self, out: &mut [f64]) {
        let bin = self.params().bin;
        out.iter_mut().for_each(|v| *v = 0.0);
        for x in 0..self.params().width {
            for (k, chunk) in self.column(x).chunks(bin).enumerate() {
                out[k] += chunk.iter().map(|&s| s.count_ones()).sum::<u32>() as f64;
            }
        }
    }

    /// Particle count of bin `i` alone (cheap, for spectra of one bin).
    pub fn bin_count(&self, i: usize) -> u32 {
        let bin = self.params().bin;
        (0..self.params().width)
            .map(|x| {
                self.column(x)[i * bin..(i + 1) * bin]
                    .iter()
                    .map(|&s| s.count_ones())
                    .sum::<u32>()
            })
            .sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contrast_of_a_uniform_profile_is_zero_and_of_a_step_is_known() {
        assert_eq!(contrast(&[3.0; 8]), 0.0);
        // 0,2,0,2: mean 1, four jumps of 2
        assert!((contrast(&[0.0, 2.0, 0.0, 2.0]) - 8.0).abs() < 1e-12);
        assert_eq!(contrast(&[]), 0.0);
    }

    #[test]
    fn structure_factor_of_a_cosine_peaks_at_its_mode() {
        let k0 = 2;
        let n: Vec<f64> = (0..40)
            .map(|i| 10.0 + (2.0 * std::f64::consts::PI * (k0 * i) as f64 / 40.0).cos())
            .collect();
        // amplitude 1 cosine: |sum|^2 = (K/2)^2
        assert!((structure_factor(&n, k0) - 400.0).abs() < 1e-9);
        assert!(structure_factor(&n, 1) < 1e-9);
        let mut acc = LowK::new(3, 40, 1.0);
        acc.add(&n);
        assert!((acc.normalised()[1] - 10.0).abs() < 1e-9);
    }
}
