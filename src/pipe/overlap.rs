//! Maximal overlap of density fields (MODEL.md A9; \[PH95\] sections B and C,
//! Figs. 4 and 5): the shift along the periodic pipe that makes two bin
//! profiles overlap most, the hierarchical alignment and averaging of many
//! fields into one wave profile, and the real-space wave speed from the
//! shift of maximal overlap against the time interval.
//!
//! Conventions: a profile `a` has K bins, bin 0 at the bottom of the pipe.
//! [`shifted`]`(a, s)[i] = a[(i + s) mod K]`, so a pattern that has moved up
//! by `s` bins between `a` and `b` gives `best_shift(a, b) = +s` (up =
//! against gravity). The overlap is the periodic cross-correlation of the
//! mean-subtracted profiles, O(s) = sum_i (a_i - abar) (b_{i+s} - bbar),
//! which has the same maximiser as sum_i a_i b_{i+s} \[PH95 eq. 2\].
//!
//! ```
//! use granular_automata::pipe::overlap::{best_shift, shifted};
//! let a = vec![0.0, 1.0, 5.0, 1.0, 0.0, 0.0, 0.0, 0.0];
//! let b = shifted(&a, -3); // the bump moved up by 3 bins
//! assert_eq!(best_shift(&a, &b), 3);
//! ```

use super::observables::s_low;
use super::Params;
use crate::analysis::fit::linear_fit;
use crate::analysis::grading::{Claim, Estimate};
use crate::analysis::spectrum::SpectrumParams;
use crate::analysis::waves::spectral_speed;
use crate::error::Result;
use crate::run::{Check, NamedMeasure};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

/// The profile rotated by `s` bins: `out[i] = a[(i + s) mod K]`.
pub fn shifted(a: &[f64], s: i64) -> Vec<f64> {
    let k = a.len() as i64;
    if k == 0 {
        return Vec::new();
    }
    (0..k).map(|i| a[(i + s).rem_euclid(k) as usize]).collect()
}

fn centred(a: &[f64]) -> Vec<f64> {
    let m = a.iter().sum::<f64>() / a.len().max(1) as f64;
    a.iter().map(|v| v - m).collect()
}

/// O(s) for s = 0..K: sum_i (a_i - abar)(b_{(i+s) mod K} - bbar).
pub fn overlaps(a: &[f64], b: &[f64]) -> Vec<f64> {
    assert_eq!(a.len(), b.len(), "profiles of equal length");
    let (a, b) = (centred(a), centred(b));
    let k = a.len();
    (0..k)
        .map(|s| (0..k).map(|i| a[i] * b[(i + s) % k]).sum())
        .collect()
}

/// Add O(s) of (a, b) to `acc` (length K), without allocating centred copies
/// when the caller passes already centred profiles.
pub fn add_overlaps_centred(a: &[f64], b: &[f64], acc: &mut [f64]) {
    let k = a.len();
    for (s, o) in acc.iter_mut().enumerate() {
        let mut sum = 0.0;
        for i in 0..k - s {
            sum += a[i] * b[i + s];
        }
        for i in k - s..k {
            sum += a[i] * b[i + s - k];
        }
        *o += sum;
    }
}

/// Map a shift in 0..K to the signed range (-K/2, K/2].
pub fn signed(s: usize, k: usize) -> i64 {
    let (s, k) = (s as i64, k as i64);
    if s > k / 2 {
        s - k
    } else {
        s
    }
}

/// The argmax of `o` (ties: the lowest index).
pub fn argmax(o: &[f64]) -> usize {
    let mut best = 0;
    for (i, &v) in o.iter().enumerate() {
        if v > o[best] {
            best = i;
        }
    }
    best
}

/// The maximiser of a periodic overlap curve, refined to a fraction of a bin
/// by a parabola through the maximum and its two neighbours; in [0, K).
pub fn refined_argmax(o: &[f64]) -> f64 {
    let k = o.len();
    let j = argmax(o);
    if k < 3 {
        return j as f64;
    }
    let (l, c, r) = (o[(j + k - 1) % k], o[j], o[(j + 1) % k]);
    let den = l - 2.0 * c + r;
    let d = if den < 0.0 {
        (0.5 * (l - r) / den).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    (j as f64 + d).rem_euclid(k as f64)
}

/// The shift of maximal overlap of `b` relative to `a`, signed in
/// (-K/2, K/2]: the number of bins the pattern moved up from `a` to `b`.
pub fn best_shift(a: &[f64], b: &[f64]) -> i64 {
    signed(argmax(&overlaps(a, b)), a.len())
}

/// Hierarchical alignment \[PH95 B\]: fields are paired (0, 1), (2, 3), ...;
/// the second of each pair is shifted to overlap the first maximally and
/// the two are averaged; the averages are paired again, until one profile
/// remains (an odd one out is carried to the next level unchanged, with its
/// weight). Returns the weighted average profile, in the frame of field 0.
pub fn align_hierarchical(fields: &[Vec<f64>]) -> Vec<f64> {
    assert!(!fields.is_empty(), "at least one field");
    let mut level: Vec<(Vec<f64>, f64)> = fields.iter().map(|f| (f.clone(), 1.0)).collect();
    while level.len() > 1 {
        let mut next = Vec::with_capacity(level.len().div_ceil(2));
        let mut it = level.into_iter();
        while let Some((a, wa)) = it.next() {
            match it.next() {
                Some((b, wb)) => {
                    let s = best_shift(&a, &b);
                    let b = shifted(&b, s);
                    let w = wa + wb;
                    let avg = a
                        .iter()
                        .zip(&b)
                        .map(|(x, y)| (wa * x + wb * y) / w)
                        .collect();
                    next.push((avg, w));
                }
                None => next.push((a, wa)),
            }
        }
        level = next;
    }
    level.pop().expect("one profile").0
}

/// The profile rotated so that its maximum sits at bin K/2.
pub fn centre_on_max(a: &[f64]) -> Vec<f64> {
    let k = a.len();
    let j = argmax(a) as i64;
    shifted(a, j - (k / 2) as i64)
}

/// The shift of maximal overlap s(tau) of a run's fields against the time
/// interval tau = m * (sample spacing), m = 1..=max_lag \[PH95 C, Fig. 5\]:
/// for each m the overlaps of all pairs (t, t + m) are summed (the
/// two-point correlation of \[PH95 eq. 2\]), the maximiser is refined to a
/// fraction of a bin ([`refined_argmax`]) and unwrapped so that it changes
/// by less than K/2 from one lag to the next (starting from 0 at m = 0).
/// Returns s(m) in bins for m = 1..=max_lag.
pub fn shift_against_lag(fields: &[Vec<f64>], max_lag: usize) -> Vec<f64> {
    let k = fields[0].len();
    let c: Vec<Vec<f64>> = fields.iter().map(|f| centred(f)).collect();
    let mut out = Vec::with_capacity(max_lag);
    let mut prev = 0.0;
    for m in 1..=max_lag.min(fields.len() - 1) {
        let mut acc = vec![0.0; k];
        for t in 0..fields.len() - m {
            add_overlaps_centred(&c[t], &c[t + m], &mut acc);
        }
        let s = refined_argmax(&acc);
        // unwrap: the representative of s mod K nearest to prev
        let kf = k as f64;
        let s = s + kf * ((prev - s) / kf).round();
        out.push(s);
        prev = s;
    }
    out
}

/// The real-space wave speed \[PH95 C, Fig. 5\] of fields sampled every `dt`
/// steps in bins of `rows_per_bin` rows: the shift of maximal overlap
/// s(tau) in rows for tau = dt, 2 dt, ..., max_lag dt
/// ([`shift_against_lag`]) and the least-squares slope of s against tau
/// (rows per step, + = up, against gravity).
pub fn real_space_speed(
    fields: &[Vec<f64>],
    max_lag: usize,
    dt: u64,
    rows_per_bin: usize,
) -> Result<(Vec<f64>, f64)> {
    let s = shift_against_lag(fields, max_lag);
    let tau: Vec<f64> = (1..=s.len()).map(|m| (m as u64 * dt) as f64).collect();
    let rows: Vec<f64> = s.iter().map(|v| v * rows_per_bin as f64).collect();
    let speed = linear_fit(&tau, &rows)?.slope;
    Ok((rows, speed))
}

/// The slope of s(tau) (rows at tau = dt, 2 dt, ..., as returned by
/// [`real_space_speed`]) over the late half of the lags only; NaN if it
/// cannot be fitted.
pub fn late_lag_speed(shift_rows: &[f64], dt: u64) -> f64 {
    let from = shift_rows.len() / 2;
    let x: Vec<f64> = (from..shift_rows.len())
        .map(|m| ((m as u64 + 1) * dt) as f64)
        .collect();
    linear_fit(&x, &shift_rows[from..])
        .map(|f| f.slope)
        .unwrap_or(f64::NAN)
}

/// The run's time-mean profile: the mean of each bin over all `fields`
/// (the standing part of the density; reading (b) of the real-space speed,
/// docs/decisions/real-space-speed-three-ways.md).
pub fn time_mean_profile(fields: &[Vec<f64>]) -> Vec<f64> {
    let k = fields.first().map_or(0, Vec::len);
    let n = fields.len().max(1) as f64;
    (0..k)
        .map(|i| fields.iter().map(|f| f[i]).sum::<f64>() / n)
        .collect()
}

/// The fluctuations dn_i(t) = n_i(t) - (time mean of n_i over the run):
/// only what changes in time is left.
pub fn fluctuations(fields: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let mean = time_mean_profile(fields);
    fields
        .iter()
        .map(|f| f.iter().zip(&mean).map(|(v, m)| v - m).collect())
        .collect()
}

/// Reading (b) of the real-space speed \[PH95 C, Fig. 5\]: the shift of
/// maximal overlap of the [`fluctuations`] (the run's time-mean profile
/// removed, so a standing pattern cannot overlap), fitted as
/// [`real_space_speed`]. Returns s(tau) in rows and the slope (rows per
/// step, + = up).
pub fn real_space_speed_fluctuations(
    fields: &[Vec<f64>],
    max_lag: usize,
    dt: u64,
    rows_per_bin: usize,
) -> Result<(Vec<f64>, f64)> {
    real_space_speed(&fluctuations(fields), max_lag, dt, rows_per_bin)
}

/// The space-time cross-correlation C(s, tau) = < dn_i(t) dn_{i+s}(t + tau) >
/// of the fluctuations `dn` (bins periodic, the mean over every bin i and
/// every t with both samples in the record), for tau = -max_lag..=max_lag
/// samples: element `tau + max_lag`.
pub fn cross_correlation(dn: &[Vec<f64>], s: i64, max_lag: usize) -> Vec<f64> {
    let (n, k) = (dn.len(), dn.first().map_or(0, Vec::len));
    let lag = max_lag as i64;
    (-lag..=lag)
        .map(|tau| {
            let (from, to) = (tau.min(0).unsigned_abs() as usize, n as i64 - tau.max(0));
            let mut sum = 0.0;
            let mut count = 0usize;
            for t in from..to.max(from as i64) as usize {
                let (a, b) = (&dn[t], &dn[(t as i64 + tau) as usize]);
                for i in 0..k {
                    sum += a[i] * b[(i as i64 + s).rem_euclid(k as i64) as usize];
                }
                count += k;
            }
            if count == 0 {
                f64::NAN
            } else {
                sum / count as f64
            }
        })
        .collect()
}

/// The maximiser of a non-periodic curve, refined by a parabola through the
/// maximum and its two neighbours (no refinement at either end).
fn refined_argmax_open(c: &[f64]) -> f64 {
    let j = argmax(c);
    if j == 0 || j + 1 >= c.len() {
        return j as f64;
    }
    let (l, m, r) = (c[j - 1], c[j], c[j + 1]);
    let den = l - 2.0 * m + r;
    let d = if den < 0.0 {
        (0.5 * (l - r) / den).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    j as f64 + d
}

/// Reading (c) of the real-space speed \[PH95 C, Fig. 5; III I, Fig. 11\]:
/// the ridge of the space-time cross-correlation of the [`fluctuations`].
/// For each separation s = 1..=`separations` bins the lag tau*(s) of the
/// maximum of C(s, tau) over tau = -max_lag..=max_lag samples (refined by a
/// parabola; negative for a ridge moving down), and the least-squares slope
/// of s against tau*(s) through the origin: PH95 Fig. 11's R / T_c read at
/// many R. Rows per step, + = up; NaN when every tau* is 0.
pub fn ridge_speed(
    fields: &[Vec<f64>],
    separations: usize,
    max_lag: usize,
    dt: u64,
    rows_per_bin: usize,
) -> f64 {
    let dn = fluctuations(fields);
    let lag = max_lag.min(fields.len().saturating_sub(1));
    let (mut st, mut tt) = (0.0, 0.0);
    for s in 1..=separations {
        let c = cross_correlation(&dn, s as i64, lag);
        let tau = (refined_argmax_open(&c) - lag as f64) * dt as f64;
        let rows = (s * rows_per_bin) as f64;
        st += rows * tau;
        tt += tau * tau;
    }
    if tt > 0.0 {
        st / tt
    } else {
        f64::NAN
    }
}

/// Separations 1..=FIG5_RIDGE_SEPARATIONS bins of reading (c) at PH95
/// Fig. 5's set-up (64 rows in bins of 8: at v = 0.36 the furthest is
/// crossed in under 5 of the 20 lags).
pub const FIG5_RIDGE_SEPARATIONS: usize = 8;

/// One run's wave speed measured both ways \[PH95 Fig. 5\]: in real space
/// ([`real_space_speed`], and read (b) and (c) as well) and from the
/// spectral peak ([`spectral_speed`]).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SpeedRun {
    /// s(tau) in rows for tau = dt, 2 dt, ..., max_lag dt.
    pub shift_rows: Vec<f64>,
    /// Slope of s against tau (rows per step, + = up, against gravity):
    /// reading (a), the raw fields.
    pub speed: f64,
    /// Reading (b): the same slope with the run's time-mean profile removed
    /// ([`real_space_speed_fluctuations`]).
    pub speed_fluctuations: f64,
    /// Reading (c): the ridge of the space-time cross-correlation
    /// ([`ridge_speed`], separations 1..=[`FIG5_RIDGE_SEPARATIONS`] bins).
    pub speed_ridge: f64,
    /// Bin-averaged spectrum of this run.
    pub spectrum: Vec<f64>,
    /// Spectral speed of this run (rows per step, always >= 0).
    pub speed_spectral: f64,
    /// s_low of the fields (MODEL.md A11).
    pub s_low: f64,
}

impl SpeedRun {
    /// Measure the steady-state `fields` of a pipe with `params`, sampled
    /// every `dt` steps: lags up to `max_lag`, the spectrum with `spec`.
    pub fn measure(
        fields: &[Vec<f64>],
        params: &Params,
        dt: u64,
        max_lag: usize,
        spec: &SpectrumParams,
    ) -> Result<Self> {
        let (shift_rows, speed) = real_space_speed(fields, max_lag, dt, params.bin)?;
        let (spectrum, speed_spectral) = spectral_speed(fields, params.length, dt, spec)?;
        let speed_fluctuations = real_space_speed_fluctuations(fields, max_lag, dt, params.bin)?.1;
        let speed_ridge = ridge_speed(fields, FIG5_RIDGE_SEPARATIONS, max_lag, dt, params.bin);
        Ok(SpeedRun {
            shift_rows,
            speed,
            speed_fluctuations,
            speed_ridge,
            spectrum,
            speed_spectral,
            s_low: s_low(fields, params.rho, params.bin, params.width),
        })
    }
}

/// Shape statistics of a wave profile centred on its maximum \[PH95 Fig. 4\].
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
pub struct WaveShape {
    /// (max - mean) / mean.
    pub amplitude: f64,
    /// Half-width (rows) at half the excess maximum on the front side
    /// (downstream, towards lower y).
    pub front: f64,
    /// Half-width (rows) on the back side (upstream).
    pub back: f64,
    /// front + back (rows).
    pub width: f64,
    /// (back - front) / (back + front): > 0 for a steep front.
    pub asymmetry: f64,
}

/// Distance (in bins, interpolated) from the maximum at `c` to where the
/// excess first falls to half, walking by `dir` (+1 up, -1 down); at most K/2.
fn half_distance(p: &[f64], c: usize, mean: f64, dir: i64) -> f64 {
    let k = p.len() as i64;
    let half = 0.5 * (p[c] - mean);
    let mut prev = p[c] - mean;
    for d in 1..=k / 2 {
        let v = p[(c as i64 + dir * d).rem_euclid(k) as usize] - mean;
        if v <= half {
            let f = if prev != v {
                (prev - half) / (prev - v)
            } else {
                1.0
            };
            return (d - 1) as f64 + f;
        }
        prev = v;
    }
    (k / 2) as f64
}

/// The shape of `profile` (bins of `rows_per_bin` rows), centred on its
/// maximum.
pub fn wave_shape(profile: &[f64], rows_per_bin: usize) -> WaveShape {
    let p = centre_on_max(profile);
    let c = argmax(&p);
    let mean = p.iter().sum::<f64>() / p.len() as f64;
    let front = half_distance(&p, c, mean, -1) * rows_per_bin as f64;
    let back = half_distance(&p, c, mean, 1) * rows_per_bin as f64;
    WaveShape {
        amplitude: (p[c] - mean) / mean,
        front,
        back,
        width: front + back,
        asymmetry: (back - front) / (back + front),
    }
}

/// One run's wave profile \[PH95 Fig. 4\] and its alignment-bias null.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ProfileRun {
    /// The run's aligned profile, centred on its maximum (particles per bin).
    pub profile: Vec<f64>,
    /// Its shape.
    pub shape: WaveShape,
    /// The same alignment of white-noise fields (the alignment-bias null).
    pub null: WaveShape,
    /// Per-bin variance over the fields (mean over bins), the null's variance.
    pub bin_variance: f64,
}

impl ProfileRun {
    /// Names of the columns of [`ProfileRun::row`].
    pub const COLUMNS: [&'static str; 6] = [
        "amplitude",
        "width",
        "front",
        "back",
        "asymmetry",
        "null_amplitude",
    ];

    /// The run's shape and null amplitude, for a table of runs.
    pub fn row(&self) -> [f64; 6] {
        let s = &self.shape;
        [
            s.amplitude,
            s.width,
            s.front,
            s.back,
            s.asymmetry,
            self.null.amplitude,
        ]
    }
}

/// Align the `fields` of one run hierarchically into its wave profile.
/// Alignment makes even pure noise look like a bump, so as many white-noise
/// fields of mean `mean` and the run's own per-bin variance (over its
/// fields, mean over bins; Box-Muller, generator seeded from `seed` with a
/// fixed offset) are aligned the same way: the null.
pub fn profile_run(fields: &[Vec<f64>], mean: f64, rows_per_bin: usize, seed: u64) -> ProfileRun {
    let profile = centre_on_max(&align_hierarchical(fields));
    let (n, kb) = (fields.len(), fields[0].len());
    let var = (0..kb)
        .map(|i| {
            let m = fields.iter().map(|f| f[i]).sum::<f64>() / n as f64;
            fields.iter().map(|f| (f[i] - m).powi(2)).sum::<f64>() / (n as f64 - 1.0)
        })
        .sum::<f64>()
        / kb as f64;
    let sd = var.sqrt();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x5EED_0FA1_1000);
    let noise: Vec<Vec<f64>> = (0..n)
        .map(|_| {
            (0..kb)
                .map(|_| {
                    let (u, v): (f64, f64) = (rng.random(), rng.random());
                    mean + sd * (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
                })
                .collect()
        })
        .collect();
    ProfileRun {
        shape: wave_shape(&profile, rows_per_bin),
        null: wave_shape(&align_hierarchical(&noise), rows_per_bin),
        profile,
        bin_variance: var,
    }
}

/// What PH95 Fig. 4 reports of each [`ProfileRun`], with its name: its
/// shape, its null amplitude (the alignment bias), the excess of the
/// amplitude over the null, the per-bin variance.
pub const PROFILE_MEASURES: [NamedMeasure<ProfileRun>; 8] = [
    ("amplitude", |r| r.shape.amplitude),
    ("null_amplitude", |r| r.null.amplitude),
    ("excess_amplitude", |r| r.shape.amplitude - r.null.amplitude),
    ("width", |r| r.shape.width),
    ("front_half_width", |r| r.shape.front),
    ("back_half_width", |r| r.shape.back),
    ("asymmetry", |r| r.shape.asymmetry),
    ("bin_variance", |r| r.bin_variance),
];

/// The ensemble profile of the runs' profiles (bins of `rows_per_bin`
/// rows), aligned hierarchically and centred on its maximum: points
/// (y - y_peak in rows, density / mean density).
pub fn ensemble_profile(runs: &[ProfileRun], rows_per_bin: usize) -> Vec<(f64, f64)> {
    let profiles: Vec<Vec<f64>> = runs.iter().map(|r| r.profile.clone()).collect();
    let prof = centre_on_max(&align_hierarchical(&profiles));
    let kb = prof.len();
    let mean = prof.iter().sum::<f64>() / kb as f64;
    (0..kb)
        .map(|i| {
            let y = (i as i64 - (kb / 2) as i64) * rows_per_bin as i64;
            (y as f64, prof[i] / mean)
        })
        .collect()
}

/// Steps between the fields of PH95 Figs. 4 and 5 (T0, a choice: the
/// paper records every step).
pub const FIELDS_EVERY: u64 = 40;
/// Rows per bin of PH95 Fig. 4 (the lengths are powers of two; finer bins
/// resolve the front).
pub const FIG4_BIN: usize = 4;
/// Rows per bin of PH95 Fig. 5 (512 is not a multiple of 10).
pub const FIG5_BIN: usize = 8;
/// Lags 1..=FIG5_MAX_LAG of the real-space speed of PH95 Fig. 5.
pub const FIG5_MAX_LAG: usize = 20;

/// Margin Delta of the wave-speed claims: the published error bar of the
/// wave speed (PH95 Fig. 5: 0.36 +- 0.05), fixed 2026-12-01.
pub const SPEED_MARGIN: f64 = 0.05;

/// PH95 Fig. 4, "the wave front is steeper than the back side" at pipe
/// length `l`: the per-run asymmetry (back - front) / (back + front) of the
/// half-widths above 0 (used by `waves-fig4` and the reproduction matrix).
pub fn steep_front_check(l: usize, runs: &[ProfileRun]) -> Check {
    let a: Vec<f64> = runs.iter().map(|r| r.shape.asymmetry).collect();
    Check::published(
        &format!("steep_front_L{l}"),
        "PH95 Fig. 4 (the downstream front is steeper than the back)",
        Estimate::of(&a),
        Claim::Above { threshold: 0.0 },
        "asymmetry (back - front) / (back + front) of the half-widths > 0",
    )
}

/// PH95 Fig. 4, "the width of the wave grows with the pipe length (almost
/// linearly)": the mean width at half the excess maximum at the longest
/// pipe minus that at the shortest, each over its runs (SEs in
/// quadrature), above 0. `short` and `long` are (L, runs).
pub fn width_grows_check(short: (usize, &[ProfileRun]), long: (usize, &[ProfileRun])) -> Check {
    let w = |r: &[ProfileRun]| Estimate::of(&r.iter().map(|r| r.shape.width).collect::<Vec<_>>());
    Check::published(
        "width_grows_with_l",
        "PH95 Fig. 4 (the width of the wave grows with L, almost linearly)",
        w(long.1).minus(w(short.1)),
        Claim::Above { threshold: 0.0 },
        &format!(
            "width (rows, at half the excess maximum) at L = {} minus that at L = {} > 0",
            long.0, short.0
        ),
    )
}

/// PH95 Fig. 5, v = 0.36 +- 0.05 at L = 512: the mean over runs of the
/// |real-space speed| (slope of the shift of maximal overlap against the
/// interval) within [`SPEED_MARGIN`] of 0.36 (used by `waves-fig5` and the
/// reproduction matrix).
pub fn wave_speed_check(runs: &[SpeedRun]) -> Check {
    let v: Vec<f64> = runs.iter().map(|r| r.speed.abs()).collect();
    Check::published(
        "wave_speed",
        "PH95 Fig. 5 (v = 0.36 +- 0.05 at L = 512)",
        Estimate::of(&v),
        Claim::Within {
            target: 0.36,
            margin: SPEED_MARGIN,
        },
        &format!("|real-space speed| (slope of the shift of maximal overlap) over all runs; margin Delta = {SPEED_MARGIN}, the published error bar"),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bump(k: usize, at: f64, width: f64) -> Vec<f64> {
        (0..k)
            .map(|i| {
                let mut d = (i as f64 - at).abs();
                d = d.min(k as f64 - d);
                10.0 + 5.0 * (-(d * d) / (2.0 * width * width)).exp()
            })
            .collect()
    }

    #[test]
    fn best_shift_finds_a_moved_bump_both_ways() {
        let a = bump(40, 10.0, 2.0);
        assert_eq!(best_shift(&a, &bump(40, 17.0, 2.0)), 7);
        assert_eq!(best_shift(&a, &bump(40, 3.0, 2.0)), -7);
        assert_eq!(best_shift(&a, &bump(40, 38.0, 2.0)), -12, "wraps");
        assert_eq!(shifted(&shifted(&a, 5), -5), a);
    }

    #[test]
    fn refined_shift_is_sub_bin() {
        let a = bump(64, 20.0, 3.0);
        let b = bump(64, 22.4, 3.0);
        let s = refined_argmax(&overlaps(&a, &b));
        assert!((s - 2.4).abs() < 0.15, "{s}");
    }

    #[test]
    fn hierarchical_alignment_recovers_the_bump() {
        // the same bump at 8 positions averages into the unshifted bump
        let fields: Vec<Vec<f64>> = (0..8)
            .map(|j| bump(50, 5.0 + 4.0 * j as f64, 2.0))
            .collect();
        let avg = align_hierarchical(&fields);
        let want = bump(50, 5.0, 2.0);
        for (x, y) in avg.iter().zip(&want) {
            assert!((x - y).abs() < 1e-12);
        }
        let c = centre_on_max(&avg);
        assert_eq!(argmax(&c), 25);
    }

    /// A ridge moving at `v` bins per sample (amplitude 2) over a standing
    /// bump at bin 40 (amplitude 8), K = 64, 400 samples.
    fn ridge_over_standing(v: f64) -> Vec<Vec<f64>> {
        (0..400)
            .map(|t| {
                let moving = bump(64, (10.0 + v * t as f64).rem_euclid(64.0), 2.0);
                let standing = bump(64, 40.0, 3.0);
                moving
                    .iter()
                    .zip(&standing)
                    .map(|(m, s)| 0.4 * (m - 10.0) + 1.6 * (s - 10.0) + 20.0)
                    .collect()
            })
            .collect()
    }

    #[test]
    fn raw_overlap_locks_on_a_standing_pattern_the_other_readings_find_the_ridge() {
        // 0.8 bins per sample up = 0.8 * 8 rows / 40 steps = 0.16 rows per step
        let (v, dt, bin) = (0.8, 40, 8);
        let want = v * bin as f64 / dt as f64;
        let fields = ridge_over_standing(v);
        let (_, a) = real_space_speed(&fields, 20, dt, bin).unwrap();
        assert!(a.abs() < 0.2 * want, "(a) {a} should lock near 0");
        let (_, b) = real_space_speed_fluctuations(&fields, 20, dt, bin).unwrap();
        assert!((b - want).abs() < 0.02 * want, "(b) {b} vs {want}");
        let c = ridge_speed(&fields, 8, 20, dt, bin);
        assert!((c - want).abs() < 0.05 * want, "(c) {c} vs {want}");
        // and downwards
        let fields = ridge_over_standing(-v);
        let b = real_space_speed_fluctuations(&fields, 20, dt, bin)
            .unwrap()
            .1;
        let c = ridge_speed(&fields, 8, 20, dt, bin);
        assert!((b + want).abs() < 0.02 * want, "(b) {b} vs {}", -want);
        assert!((c + want).abs() < 0.05 * want, "(c) {c} vs {}", -want);
    }

    #[test]
    fn the_time_mean_profile_is_removed_exactly() {
        let fields = vec![vec![1.0, 2.0, 3.0], vec![3.0, 2.0, 1.0]];
        assert_eq!(time_mean_profile(&fields), vec![2.0, 2.0, 2.0]);
        assert_eq!(fluctuations(&fields)[0], vec![-1.0, 0.0, 1.0]);
        // C(s, tau) of a pattern that does not change is NaN-free and
        // symmetric in tau
        let dn = fluctuations(&ridge_over_standing(0.5));
        let c = cross_correlation(&dn, 0, 3);
        assert_eq!(c.len(), 7);
        assert!(c.iter().all(|v| v.is_finite()));
        assert!(argmax(&c) == 3, "{c:?}");
    }

    #[test]
    fn shift_against_lag_is_linear_for_a_travelling_bump() {
        // 0.7 bins per sample, down (negative), wrapping several times
        let fields: Vec<Vec<f64>> = (0..200)
            .map(|t| bump(32, (100.0 - 0.7 * t as f64).rem_euclid(32.0), 2.5))
            .collect();
        let s = shift_against_lag(&fields, 120);
        for (m, v) in s.iter().enumerate() {
            let want = -0.7 * (m + 1) as f64;
            assert!((v - want).abs() < 0.2, "lag {}: {v} vs {want}", m + 1);
        }
    }
}
