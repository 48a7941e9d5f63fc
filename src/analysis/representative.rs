//! "The published fit is a typical single run of the model": the claim of a
//! representative spectrum (PH94 Fig. 2, PH95 Fig. 6; the decision record
//! docs/decisions/representative-spectrum.md). Each of PH94's and PH95's
//! spectra is one run, averaged over S = 4 segments (PH94 text under Fig. 2,
//! PH95 III D), and the published alpha is that run's fit. A model reproduces
//! it when the published alpha lies inside the central 95 % of the per-run
//! fitted alpha, each run's fit error included.
//!
//! The per-run distribution is the mixture of one normal N(alpha_i,
//! err_i^2) per run, so a run's own fit error widens its share. Its 2.5 %
//! and 97.5 % quantiles carry bootstrap SEs over runs. The claim is the two
//! one-sided claims "lower quantile below the published value" and "upper
//! quantile above it", each graded by the one rule ([`super::grading`]) and
//! joined by [`super::grading::all_of`].

use super::grading::{all_of, grade, Claim, Estimate, Verdict};
use super::resample::bootstrap_se;
use super::sequential::normal_sf;
use crate::error::{Error, ErrorKind, Result};

/// The central share of the per-run distribution the published value must
/// lie in (fixed in the decision record).
pub const CENTRAL: f64 = 0.95;

/// Bootstrap resamples for the SEs of the quantiles.
pub const RESAMPLES: usize = 400;

/// The `prob` quantile of the mixture of N(mean_i, sd_i^2), by bisection of
/// its distribution function. Runs are `(mean, sd)`; sd = 0 is a point.
pub fn mixture_quantile(runs: &[(f64, f64)], idx: &[usize], prob: f64) -> Result<f64> {
    if idx.is_empty() || !(0.0..=1.0).contains(&prob) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "mixture quantile: {} runs, prob {prob}; needs runs and prob in [0, 1]",
                idx.len()
            ),
        ));
    }
    if idx
        .iter()
        .any(|&i| !runs[i].0.is_finite() || !runs[i].1.is_finite() || runs[i].1 < 0.0)
    {
        return Err(Error::new(
            ErrorKind::BadSeries,
            "mixture quantile: a run's alpha or fit error is not finite, or the error is negative",
        ));
    }
    let cdf = |x: f64| {
        idx.iter()
            .map(|&i| {
                let (m, s) = runs[i];
                if s == 0.0 {
                    f64::from(u8::from(x >= m))
                } else {
                    1.0 - normal_sf((x - m) / s)
                }
            })
            .sum::<f64>()
            / idx.len() as f64
    };
    let span = idx.iter().map(|&i| runs[i].1).fold(0.0, f64::max) * 10.0 + 1.0;
    let lo0 = idx.iter().map(|&i| runs[i].0).fold(f64::INFINITY, f64::min) - span;
    let hi0 = idx
        .iter()
        .map(|&i| runs[i].0)
        .fold(f64::NEG_INFINITY, f64::max)
        + span;
    let (mut lo, mut hi) = (lo0, hi0);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if cdf(mid) < prob {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// The graded claim: the central interval's ends with their SEs, and the
/// verdict.
#[derive(Debug, Clone, Copy)]
pub struct Representative {
    /// The lower end (2.5 % quantile) and its bootstrap SE over runs.
    pub low: Estimate,
    /// The upper end (97.5 % quantile) and its bootstrap SE.
    pub high: Estimate,
    /// Reproduced when both ends are beyond the published value by k SE,
    /// not reproduced when either is short of it by k SE.
    pub verdict: Verdict,
}

/// Grade "`published` is a typical single run" over `runs` (alpha, fit
/// error) with bootstrap generator `seed`.
pub fn representative(runs: &[(f64, f64)], published: f64, seed: u64) -> Result<Representative> {
    let all: Vec<usize> = (0..runs.len()).collect();
    let tail = (1.0 - CENTRAL) / 2.0;
    let end = |prob: f64, salt: u64| -> Result<Estimate> {
        let mean = mixture_quantile(runs, &all, prob)?;
        let se = bootstrap_se(runs.len(), RESAMPLES, seed ^ salt, |idx| {
            mixture_quantile(runs, idx, prob)
        })?;
        Ok(Estimate {
            mean,
            se,
            n: runs.len(),
        })
    };
    let (low, high) = (end(tail, 0x10)?, end(1.0 - tail, 0x20)?);
    let verdict = all_of([
        grade(
            low,
            Claim::Below {
                threshold: published,
            },
        ),
        grade(
            high,
            Claim::Above {
                threshold: published,
            },
        ),
    ]);
    Ok(Representative { low, high, verdict })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs spread as N(1.25, 0.1^2) with a fit error of 0.02 each.
    fn runs(n: usize, centre: f64) -> Vec<(f64, f64)> {
        (0..n)
            .map(|i| {
                let z = super::super::sequential::normal_isf((i as f64 + 0.5) / n as f64);
                (centre + 0.1 * z, 0.02)
            })
            .collect()
    }

    #[test]
    fn the_quantiles_of_one_normal_are_its_own() {
        let one = [(1.0, 0.5)];
        let q = mixture_quantile(&one, &[0], 0.975).unwrap();
        assert!((q - (1.0 + 0.5 * 1.959964)).abs() < 1e-4, "{q}");
        assert!(mixture_quantile(&one, &[], 0.5).is_err());
        assert!(mixture_quantile(&[(f64::NAN, 0.1)], &[0], 0.5).is_err());
    }

    #[test]
    fn a_value_inside_is_typical_and_one_far_outside_is_not() {
        let r = runs(400, 1.25);
        let inside = representative(&r, 1.33, 1).unwrap();
        assert_eq!(inside.verdict, Verdict::Reproduced, "{inside:?}");
        assert!(inside.low.mean < 1.1 && inside.high.mean > 1.4);
        let outside = representative(&r, 1.8, 1).unwrap();
        assert_eq!(outside.verdict, Verdict::NotReproduced);
        // a wrong model whose runs sit far below the published value fails
        let wrong = representative(&runs(400, 0.9), 1.33, 1).unwrap();
        assert_eq!(wrong.verdict, Verdict::NotReproduced);
        // near an end the bootstrap leaves it open
        let edge = representative(&runs(30, 1.25), inside.high.mean, 1).unwrap();
        assert_eq!(edge.verdict, Verdict::Undecided);
    }
}
