//! Estimators on an ensemble of spectra, one row per run: the exponent and
//! the peak of the *averaged* spectrum, with standard errors by resampling
//! the runs ([`super::resample`]). The acceptance tier grades with these
//! (`drivers::acceptance`; chosen on pilot seeds, EXPERIMENTS.md
//! "Acceptance at the published set-ups"):
//!
//! - [`alpha_of_mean`]: the default fit of MODEL.md A9 on the averaged
//!   spectrum, bootstrap SE. A run whose own fit is an outlier (one in 16
//!   had alpha 0.78) adds only 1/n of its power to the average.
//! - [`v_of_mean`]: the peak of the averaged spectrum, bootstrap SE.
//!
//! Both statistics contain the position of a maximum (alpha through the
//! bins it removes around the peak), which is not smooth in the data: a
//! delete-one jackknife multiplies every jump of that position by about
//! sqrt(n - 1), so neither uses it (EXPERIMENTS.md "The SE of alpha when
//! the removed peak moves").
//! - [`v_of_mean_refined`]: the peak refined below one bin; a pilot
//!   candidate, not used for grading.

use super::fit::{estimate_alpha_of, find_peak_contrast, wave_velocity, PowerLawParams};
use super::grading::Estimate;
use super::resample::{bootstrap_se, jackknife_se, mean_of_rows, mean_without};
use crate::error::Result;

/// Bootstrap resamples of the acceptance estimators.
pub const BOOTSTRAP_RESAMPLES: usize = 400;

/// Seed of the bootstrap's generator (a constant: the estimate is a pure
/// function of the runs).
pub const BOOTSTRAP_SEED: u64 = 0x5EED_0029;

/// alpha of the averaged spectrum (the default fit of MODEL.md A9) with the
/// bootstrap standard error over runs: each resample's averaged spectrum
/// finds its own peak and removes its own bins, so where the peak is a
/// noise maximum the spread of where it falls is part of the SE.
pub fn alpha_of_mean(rows: &[Vec<f64>]) -> Result<Estimate> {
    let m = rows.first().map_or(0, Vec::len);
    alpha_of_mean_of(rows, m)
}

/// [`alpha_of_mean`] of spectra of `m` frequencies given by their first
/// bins (at least [`super::fit::alpha_prefix`]`(m)`, all rows alike): the same
/// estimate and SE, bit for bit, for a sixteenth of the work at m = 16384
/// (the sequential designs' simulations resample them many times).
pub fn alpha_of_mean_of(rows: &[Vec<f64>], m: usize) -> Result<Estimate> {
    if rows.len() < 3 {
        return Err(crate::error::Error::out_of_range(
            "alpha of the averaged spectrum: number of runs",
            rows.len(),
            "[3, inf)",
        ));
    }
    let alpha_of = |idx: &[usize]| -> Result<f64> {
        Ok(estimate_alpha_of(&mean_of_rows(rows, idx), m)?.fit.alpha)
    };
    let all: Vec<usize> = (0..rows.len()).collect();
    let alpha = alpha_of(&all)?;
    let se = bootstrap_se(rows.len(), BOOTSTRAP_RESAMPLES, BOOTSTRAP_SEED, alpha_of)?;
    Ok(Estimate::new(alpha, se, rows.len()))
}

/// The peak velocity of the averaged spectrum of a pipe of `length` rows
/// sampled every `t0` steps (peak found as in MODEL.md A9 inside the fit
/// range) with the bootstrap standard error over runs.
pub fn v_of_mean(rows: &[Vec<f64>], length: usize, t0: u64) -> Result<Estimate> {
    let v_of = |idx: &[usize]| -> Result<f64> {
        let p = mean_of_rows(rows, idx);
        let params = PowerLawParams::default_for(p.len());
        let (j, _) = find_peak_contrast(&p, params.j_lo, params.j_hi)?;
        Ok(wave_velocity(length, j, t0 as usize, p.len()))
    };
    let all: Vec<usize> = (0..rows.len()).collect();
    let v = v_of(&all)?;
    let se = bootstrap_se(rows.len(), BOOTSTRAP_RESAMPLES, BOOTSTRAP_SEED, v_of)?;
    Ok(Estimate::new(v, se, rows.len()))
}

/// Half-width, in bins of m = 16384, of the parabola fitted around the
/// maximum of the averaged spectrum by [`refined_peak`].
pub const PEAK_FIT_HALF_WIDTH: usize = 4;

/// The peak of `p` inside the fit range, refined below one bin: the bin j0
/// that [`find_peak_contrast`] picks, then the vertex of the least-squares
/// parabola through ln P(j) for |j - j0| <= h (h =
/// [`PEAK_FIT_HALF_WIDTH`] scaled to m, at least 1), kept within h of j0.
/// Smooth in the data, unlike the bin alone, so its standard error falls
/// as 1/sqrt(runs).
pub fn refined_peak(p: &[f64]) -> Result<f64> {
    let m = p.len();
    let params = PowerLawParams::default_for(m);
    let (j0, _) = find_peak_contrast(p, params.j_lo, params.j_hi)?;
    let h = (PEAK_FIT_HALF_WIDTH * m / 16384).max(1);
    let (lo, hi) = (j0.saturating_sub(h).max(1), (j0 + h).min(m - 1));
    let (mut s, mut sx, mut sx2, mut sx3, mut sx4, mut sy, mut sxy, mut sx2y) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for (j, &v) in p.iter().enumerate().take(hi + 1).skip(lo) {
        let x = j as f64 - j0 as f64;
        let y = v.max(f64::MIN_POSITIVE).ln();
        s += 1.0;
        sx += x;
        sx2 += x * x;
        sx3 += x * x * x;
        sx4 += x * x * x * x;
        sy += y;
        sxy += x * y;
        sx2y += x * x * y;
    }
    // normal equations of y = a + b x + c x^2 (Cramer's rule)
    let det3 = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let a = [[s, sx, sx2], [sx, sx2, sx3], [sx2, sx3, sx4]];
    let d = det3(a);
    let b = det3([[s, sy, sx2], [sx, sxy, sx3], [sx2, sx2y, sx4]]) / d;
    let c = det3([[s, sx, sy], [sx, sx2, sxy], [sx2, sx3, sx2y]]) / d;
    let shift = if c < 0.0 && d.abs() > 0.0 {
        (-b / (2.0 * c)).clamp(-(h as f64), h as f64)
    } else {
        0.0
    };
    Ok(j0 as f64 + shift)
}

/// The velocity of the [`refined_peak`] of the averaged spectrum (pipe of
/// `length` rows sampled every `t0` steps) with the jackknife standard
/// error over runs.
pub fn v_of_mean_refined(rows: &[Vec<f64>], length: usize, t0: u64) -> Result<Estimate> {
    let v_of = |p: &[f64]| -> Result<f64> {
        Ok(length as f64 * refined_peak(p)? / (t0 as f64 * 2.0 * p.len() as f64))
    };
    let all: Vec<usize> = (0..rows.len()).collect();
    let mean = mean_of_rows(rows, &all);
    let v = v_of(&mean)?;
    let sum: Vec<f64> = mean.iter().map(|x| x * rows.len() as f64).collect();
    let se = jackknife_se(rows.len(), |i| v_of(&mean_without(rows, &sum, i)))?;
    Ok(Estimate::new(v, se, rows.len()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::fit::alpha_prefix;
    use rand::{RngExt, SeedableRng};

    /// `n` noisy spectra of 16384 frequencies: j^-1.3 with a line at 600.
    fn spectra(n: usize) -> Vec<Vec<f64>> {
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(7);
        (0..n)
            .map(|_| {
                (0..16384)
                    .map(|j| {
                        let line = if (598..=602).contains(&j) { 5.0 } else { 1.0 };
                        let e: f64 = -(1.0 - rng.random::<f64>()).ln();
                        line * (j.max(1) as f64).powf(-1.3) * e
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn a_prefix_gives_the_same_alpha_and_se_bit_for_bit() {
        let rows = spectra(8);
        let m = 16384;
        let prefix: Vec<Vec<f64>> = rows.iter().map(|r| r[..alpha_prefix(m)].to_vec()).collect();
        let full = alpha_of_mean(&rows).unwrap();
        let cut = alpha_of_mean_of(&prefix, m).unwrap();
        assert_eq!(full.mean.to_bits(), cut.mean.to_bits());
        assert_eq!(full.se.to_bits(), cut.se.to_bits());
        assert!((full.mean - 1.3).abs() < 0.1, "{}", full.mean);
        // one bin short, or fewer than three runs: refused, not a panic
        let short: Vec<Vec<f64>> = prefix.iter().map(|r| r[..r.len() - 1].to_vec()).collect();
        assert!(alpha_of_mean_of(&short, m).is_err());
        assert!(alpha_of_mean(&rows[..2]).is_err());
        assert!(alpha_of_mean(&[]).is_err());
    }
}
