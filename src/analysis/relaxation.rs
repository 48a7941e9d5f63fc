//! The approach of an ensemble of time series to saturation \[PH95 Fig. 3\]:
//! window means, the time to cover a fraction of the way from the start to
//! the saturation value, and that half-time of the ensemble mean with a
//! jackknife standard error over the runs.

use super::stats::mean_sem;

/// How an ensemble of runs' series approaches saturation: each statistic
/// as (mean, standard error) over the runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Saturation {
    /// The value at the first sample.
    pub start: (f64, f64),
    /// The saturation value: the mean over the last quarter of the time span.
    pub saturation: (f64, f64),
    /// Saturation minus start.
    pub change: (f64, f64),
    /// Mean over the last quarter minus the mean over the third quarter
    /// (about 0 once saturated).
    pub late_drift: (f64, f64),
    /// [`half_time`] of the ensemble mean (jackknife error).
    pub half_time: (f64, f64),
}

impl Saturation {
    /// The statistics of `runs` (each sampled at `times`).
    pub fn of(runs: &[Vec<f64>], times: &[f64]) -> Self {
        let late = |v: &[f64]| window(v, times, 0.75, 1.0);
        let per_run =
            |f: &dyn Fn(&[f64]) -> f64| mean_sem(&runs.iter().map(|r| f(r)).collect::<Vec<_>>());
        Saturation {
            start: per_run(&|r| r[0]),
            saturation: per_run(&late),
            change: per_run(&|r| late(r) - r[0]),
            late_drift: per_run(&|r| late(r) - window(r, times, 0.5, 0.75)),
            half_time: half_time(runs, times),
        }
    }

    /// Every statistic with its field name.
    pub fn named(&self) -> [(&'static str, (f64, f64)); 5] {
        [
            ("start", self.start),
            ("saturation", self.saturation),
            ("change", self.change),
            ("half_time", self.half_time),
            ("late_drift", self.late_drift),
        ]
    }
}

/// Mean of `v` over the samples with fa <= t / t_end < fb (fb = 1
/// includes the end), `times` the sample times of `v`.
pub fn window(v: &[f64], times: &[f64], fa: f64, fb: f64) -> f64 {
    let end = *times.last().expect("samples");
    let sel: Vec<f64> = v
        .iter()
        .zip(times)
        .filter(|(_, &t)| t >= fa * end && (t < fb * end || fb >= 1.0))
        .map(|(&x, _)| x)
        .collect();
    sel.iter().sum::<f64>() / sel.len().max(1) as f64
}

/// First time (linear interpolation between samples) at which `v` reaches
/// `v[0] + frac * (target - v[0])`, approaching from `v[0]`; NaN if never.
pub fn time_to(v: &[f64], times: &[f64], target: f64, frac: f64) -> f64 {
    let level = v[0] + frac * (target - v[0]);
    let up = target >= v[0];
    for t in 1..v.len() {
        let reached = if up { v[t] >= level } else { v[t] <= level };
        if reached {
            let (a, b) = (v[t - 1], v[t]);
            let f = if b != a { (level - a) / (b - a) } else { 1.0 };
            return times[t - 1] + f.clamp(0.0, 1.0) * (times[t] - times[t - 1]);
        }
    }
    f64::NAN
}

/// Half-time of the ensemble mean of `runs` (half-way from its value at
/// the first sample to its mean over the last quarter of the time span)
/// with a jackknife standard error over runs (0 for one run).
pub fn half_time(runs: &[Vec<f64>], times: &[f64]) -> (f64, f64) {
    let stat = |sel: &[&Vec<f64>]| {
        let n = sel[0].len();
        let m: Vec<f64> = (0..n)
            .map(|t| sel.iter().map(|r| r[t]).sum::<f64>() / sel.len() as f64)
            .collect();
        time_to(&m, times, window(&m, times, 0.75, 1.0), 0.5)
    };
    let all: Vec<&Vec<f64>> = runs.iter().collect();
    let full = stat(&all);
    let n = runs.len();
    if n < 2 {
        // one run: no spread (listed as missing, not 0)
        return (full, f64::NAN);
    }
    let loo: Vec<f64> = (0..n)
        .map(|k| {
            let sel: Vec<&Vec<f64>> = runs
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != k)
                .map(|(_, r)| r)
                .collect();
            stat(&sel)
        })
        .collect();
    let m = loo.iter().sum::<f64>() / n as f64;
    let var = loo.iter().map(|x| (x - m) * (x - m)).sum::<f64>() * (n as f64 - 1.0) / n as f64;
    (full, var.sqrt())
}

/// Largest late drift of a saturated series, as a fraction of its total
/// change: (mean over the last quarter - mean over the third quarter) /
/// |change| within this of 0 (fixed 2026-11-25).
pub const SATURATION_MARGIN: f64 = 0.1;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn half_time_of_an_exponential_approach() {
        // 1 - exp(-t / 10): half-way at 10 ln 2
        let times: Vec<f64> = (0..=400).map(|t| t as f64).collect();
        let v: Vec<f64> = times.iter().map(|t| 1.0 - (-t / 10.0).exp()).collect();
        let (h, e) = half_time(&[v.clone(), v], &times);
        assert!((h - 10.0 * 2f64.ln()).abs() < 0.01, "{h}");
        assert_eq!(e, 0.0);
        assert!(time_to(&[0.0, 1.0], &[0.0, 1.0], -1.0, 0.5).is_nan());
    }
}
