//! Standard errors by resampling the runs of an ensemble: the jackknife for
//! smooth statistics (the exponent of the averaged spectrum) and the
//! bootstrap for statistics that are not smooth in the data (the position of
//! the peak of the averaged spectrum, a median). Used by the acceptance
//! estimators (`drivers::acceptance`).
//!
//! Both are pure functions of their inputs: the bootstrap draws its
//! resamples from a generator seeded with a fixed `seed`, so an estimate is
//! the same bytes on any machine.

use crate::error::{Error, ErrorKind, Result};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// Delete-one jackknife standard error of a statistic of `n` runs:
/// `leave_out(i)` is the statistic without run i, and
/// SE^2 = (n - 1)/n sum_i (theta_(i) - mean theta_(.))^2.
///
/// Errors: fewer than 3 runs ([`ErrorKind::InvalidParameter`]); a
/// leave-one-out value that is not finite ([`ErrorKind::BadSeries`]); and
/// whatever `leave_out` returns.
pub fn jackknife_se(n: usize, leave_out: impl Fn(usize) -> Result<f64>) -> Result<f64> {
    check_runs("jackknife", n)?;
    let thetas = (0..n).map(&leave_out).collect::<Result<Vec<f64>>>()?;
    check_finite("jackknife", &thetas)?;
    let mean = thetas.iter().sum::<f64>() / n as f64;
    let ss = thetas.iter().map(|t| (t - mean) * (t - mean)).sum::<f64>();
    Ok((ss * (n as f64 - 1.0) / n as f64).sqrt())
}

/// Bootstrap standard error of a statistic of `n` runs: `b` resamples of n
/// run indices drawn with replacement (generator seeded with `seed`),
/// `of(indices)` the statistic of a resample, SE the standard deviation of
/// the `b` values (divisor b - 1).
///
/// Errors: fewer than 3 runs or fewer than 20 resamples
/// ([`ErrorKind::InvalidParameter`]); a resampled value that is not finite
/// ([`ErrorKind::BadSeries`]); and whatever `of` returns.
pub fn bootstrap_se(
    n: usize,
    b: usize,
    seed: u64,
    of: impl Fn(&[usize]) -> Result<f64>,
) -> Result<f64> {
    check_runs("bootstrap", n)?;
    if b < 20 {
        return Err(Error::out_of_range("bootstrap resamples", b, "[20, inf)"));
    }
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut values = Vec::with_capacity(b);
    let mut idx = vec![0usize; n];
    for _ in 0..b {
        for i in idx.iter_mut() {
            *i = rng.random_range(0..n);
        }
        values.push(of(&idx)?);
    }
    check_finite("bootstrap", &values)?;
    let mean = values.iter().sum::<f64>() / b as f64;
    let ss = values.iter().map(|t| (t - mean) * (t - mean)).sum::<f64>();
    Ok((ss / (b as f64 - 1.0)).sqrt())
}

/// The element-wise mean of the rows `idx` of `rows` (a resample's averaged
/// spectrum). `idx` must be non-empty and every row as long as the first.
pub fn mean_of_rows(rows: &[Vec<f64>], idx: &[usize]) -> Vec<f64> {
    let len = rows[idx[0]].len();
    let mut sum = vec![0.0; len];
    for &i in idx {
        for (s, v) in sum.iter_mut().zip(&rows[i]) {
            *s += v;
        }
    }
    let n = idx.len() as f64;
    sum.iter_mut().for_each(|s| *s /= n);
    sum
}

/// The mean of all rows but row `i`, from the sum of all rows.
pub fn mean_without(rows: &[Vec<f64>], sum: &[f64], i: usize) -> Vec<f64> {
    let n = (rows.len() - 1) as f64;
    sum.iter().zip(&rows[i]).map(|(s, v)| (s - v) / n).collect()
}

fn check_runs(what: &str, n: usize) -> Result<()> {
    if n < 3 {
        return Err(Error::out_of_range(
            &format!("{what}: number of runs"),
            n,
            "[3, inf)",
        ));
    }
    Ok(())
}

fn check_finite(what: &str, xs: &[f64]) -> Result<()> {
    match xs.iter().position(|x| !x.is_finite()) {
        Some(i) => Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "{what}: resample {i} gave {}; the statistic must be finite on every resample",
                xs[i]
            ),
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mean(xs: &[f64]) -> f64 {
        xs.iter().sum::<f64>() / xs.len() as f64
    }

    #[test]
    fn the_jackknife_of_a_mean_is_the_usual_standard_error() {
        let xs = [1.0, 4.0, 2.0, 8.0, 5.0, 7.0];
        let se = jackknife_se(xs.len(), |i| {
            let rest: Vec<f64> = xs
                .iter()
                .enumerate()
                .filter(|&(j, _)| j != i)
                .map(|(_, &x)| x)
                .collect();
            Ok(mean(&rest))
        })
        .unwrap();
        let sem = crate::analysis::grading::Estimate::of(&xs).se;
        assert!((se - sem).abs() < 1e-12, "{se} {sem}");
    }

    #[test]
    fn the_bootstrap_of_a_mean_is_close_to_the_standard_error_and_repeatable() {
        let xs: Vec<f64> = (0..50).map(|i| ((i * 37) % 50) as f64).collect();
        let of = |idx: &[usize]| Ok(idx.iter().map(|&i| xs[i]).sum::<f64>() / idx.len() as f64);
        let a = bootstrap_se(xs.len(), 2000, 7, of).unwrap();
        let b = bootstrap_se(xs.len(), 2000, 7, of).unwrap();
        assert_eq!(a, b);
        let sem = crate::analysis::grading::Estimate::of(&xs).se;
        // the bootstrap SE of a mean is sqrt((n-1)/n) SEM, up to 2000 draws
        assert!((a / sem - 1.0).abs() < 0.08, "{a} {sem}");
    }

    #[test]
    fn too_few_runs_or_resamples_and_non_finite_values_are_errors() {
        assert!(jackknife_se(2, |_| Ok(1.0)).is_err());
        assert!(bootstrap_se(2, 100, 1, |_| Ok(1.0)).is_err());
        assert!(bootstrap_se(10, 19, 1, |_| Ok(1.0)).is_err());
        let e = jackknife_se(5, |i| Ok(if i == 3 { f64::NAN } else { 1.0 })).unwrap_err();
        assert!(e.message.contains("resample 3"), "{}", e.message);
    }

    #[test]
    fn row_means_with_and_without_a_row() {
        let rows = vec![vec![1.0, 2.0], vec![3.0, 6.0], vec![5.0, 10.0]];
        assert_eq!(
            mean_of_rows(&rows, &[0, 2, 2]),
            vec![11.0 / 3.0, 22.0 / 3.0]
        );
        let sum = mean_of_rows(&rows, &[0, 1, 2])
            .iter()
            .map(|v| v * 3.0)
            .collect::<Vec<_>>();
        assert_eq!(mean_without(&rows, &sum, 1), vec![3.0, 6.0]);
    }
}
