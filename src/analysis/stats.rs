//! Small statistics of the project: the mean with its standard error, and
//! Student's t distribution for the one-sided tests (the trend test of the open pipe, `crate::pipe::open::stationarity`): the
//! upper tail probability for an integer number of degrees of freedom, in
//! closed form (Abramowitz & Stegun 26.7.3-4), and its inverse.

use crate::error::{Error, Result};

/// P(T > t) for Student's t with `df` >= 1 degrees of freedom.
pub fn student_t_sf(t: f64, df: usize) -> Result<f64> {
    if df == 0 {
        return Err(Error::out_of_range("degrees of freedom", 0, "[1, inf)"));
    }
    if t.is_nan() {
        return Ok(f64::NAN);
    }
    let theta = (t.abs() / (df as f64).sqrt()).atan();
    let (s, c) = theta.sin_cos();
    // A = P(|T| < |t|): a finite series in cos(theta)
    let a = if df % 2 == 1 {
        let (mut sum, mut term) = (0.0, c);
        if df >= 3 {
            sum = c;
            for k in 1..(df - 1) / 2 {
                term *= c * c * (2 * k) as f64 / (2 * k + 1) as f64;
                sum += term;
            }
        }
        2.0 / std::f64::consts::PI * (theta + s * sum)
    } else {
        let (mut sum, mut term) = (1.0, 1.0);
        for k in 1..df / 2 {
            term *= c * c * (2 * k - 1) as f64 / (2 * k) as f64;
            sum += term;
        }
        s * sum
    };
    let upper = (0.5 * (1.0 - a)).max(0.0);
    Ok(if t >= 0.0 { upper } else { 1.0 - upper })
}

/// The t with P(T > t) = `p` for Student's t with `df` >= 1 degrees of
/// freedom (the one-sided critical value of a test at false-alarm rate p),
/// p in (0, 0.5], to a relative precision of about 1e-10.
pub fn student_t_isf(p: f64, df: usize) -> Result<f64> {
    if !(p > 0.0 && p <= 0.5) {
        return Err(Error::out_of_range("tail probability p", p, "(0, 0.5]"));
    }
    student_t_sf(0.0, df)?;
    let sf = |t: f64| student_t_sf(t, df).expect("df checked");
    let (mut lo, mut hi) = (0.0, 1.0);
    while sf(hi) > p {
        lo = hi;
        hi *= 2.0;
    }
    while hi - lo > 1e-10 * hi {
        let mid = 0.5 * (lo + hi);
        if sf(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// Mean and standard error of the mean; the error of a single value is
/// NaN (no spread measured, not 0: a summary lists it under
/// `missing_metrics`, `run::NO_ERROR`), both are NaN for no values.
pub fn mean_sem(xs: &[f64]) -> (f64, f64) {
    let n = xs.len();
    if n == 0 {
        return (f64::NAN, f64::NAN);
    }
    let m = xs.iter().sum::<f64>() / n as f64;
    if n < 2 {
        return (m, f64::NAN);
    }
    let var = xs.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n as f64 - 1.0);
    (m, (var / n as f64).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn critical_values_match_the_tables() {
        // one-sided critical values t(1 - p, df) from the standard tables
        for (p, df, t) in [
            (0.025, 1, 12.706),
            (0.025, 2, 4.303),
            (0.025, 3, 3.182),
            (0.05, 10, 1.812),
            (0.001, 3, 10.215),
            (0.001, 4, 7.173),
            (0.001, 7, 4.785),
            (0.001, 30, 3.385),
            (0.005, 31, 2.744),
        ] {
            let got = student_t_isf(p, df).unwrap();
            assert!((got - t).abs() < 1.5e-3, "df {df}, p {p}: {got} vs {t}");
        }
        // symmetry, the centre, and the normal limit
        assert!(
            (student_t_sf(-2.0, 5).unwrap() - (1.0 - student_t_sf(2.0, 5).unwrap())).abs() < 1e-14
        );
        assert!((student_t_sf(0.0, 4).unwrap() - 0.5).abs() < 1e-15);
        assert!((student_t_sf(3.0, 2000).unwrap() - 0.00135).abs() < 2e-5);
        assert!(student_t_sf(1.0, 0).is_err() && student_t_isf(0.7, 3).is_err());
    }
}
