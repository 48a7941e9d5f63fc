//! What is read off a spectrum P(j) (MODEL.md A9): the exponent alpha of
//! P(j) ~ j^-alpha ("Exponent alpha"), the sharp peak and the wave velocity
//! from it ("Wave velocity from the peak").
//!
//! # Choices (documented as MODEL.md A9 asks)
//!
//! - **Fit**: ordinary least squares of log10 P(j) against log10 j over
//!   j_lo <= j <= j_hi, all points by default ([`Binning::AllPoints`]), or
//!   the means of log10 j and log10 P in bins equally spaced in log10 j
//!   ([`Binning::LogBins`]). alpha = -slope, alpha_err = the standard error
//!   of the slope from the residuals. Averaging log P instead of P biases
//!   the intercept (E log chi^2 < log E chi^2) but not the slope.
//! - **Caveat on alpha_err**: neighbouring bins of a triangle-windowed
//!   estimate are correlated (correlation of the powers about 0.37 for
//!   adjacent bins, 0.02 for next-nearest), which the residual standard
//!   error ignores: with all points it underestimates the true scatter of
//!   alpha by a factor of about sqrt(1 + 2*0.37 + 2*0.02) ~ 1.3 (measured in
//!   the tests' calibration: 1.2-1.4).
//! - **Fit range**: 40 <= j <= 1000 at m = 16384 ([PH94]); for other m both
//!   ends scale with m / 16384 ([`default_fit_range`]).
//! - **Peak**: the j in the fit range maximising P(j) / B(j), B(j) the
//!   running median of P over the symmetric window j-h..=j+h, h =
//!   [`PEAK_BACKGROUND_HALF_WINDOW`] = 16 bins, shrunk symmetrically near
//!   j = 1 and j = m-1 ([`local_background`]). For a monotone spectrum the
//!   median of a symmetric window is the centre value, so the steep
//!   low-frequency end of a 1/f spectrum has contrast ~1 and is not taken for
//!   a peak, while a line (a few bins wide) does not move the median of 33
//!   bins.
//! - **Peak exclusion**: j_peak - h ..= j_peak + h with the default
//!   h = max(4, m / 1024) ([`default_peak_half_width`]): 16 bins at
//!   m = 16384. Four bins cover the main lobe (+-2 bins) of the triangle
//!   window's response to a pure line and its first side lobe; m / 1024 bins
//!   is a fixed band of 1/2048 cycles per sample, so that a peak of given
//!   physical width is excluded alike for every m (at [PH94]'s j = 596 it
//!   is +-2.7 per cent of the peak frequency). [`alpha_sensitivity`] reports
//!   alpha for other widths.

use crate::error::{Error, ErrorKind, Result};
use std::ops::RangeInclusive;

/// The result of [`linear_fit`]: y = intercept + slope * x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearFit {
    /// The least-squares slope.
    pub slope: f64,
    /// The least-squares intercept.
    pub intercept: f64,
    /// Standard error of the slope, from the residuals (n - 2 degrees of
    /// freedom).
    pub slope_err: f64,
    /// Standard error of the intercept, from the residuals.
    pub intercept_err: f64,
    /// Number of points fitted.
    pub n: usize,
}

/// Ordinary least squares of `y` against `x`, with standard errors from the
/// residuals: s^2 = sum r^2 / (n - 2), slope_err = s / sqrt(Sxx),
/// intercept_err = s * sqrt(1/n + mean(x)^2 / Sxx).
///
/// Errors: [`ErrorKind::InvalidParameter`] for slices of different lengths,
/// fewer than 3 points or all x equal; [`ErrorKind::BadSeries`] for
/// non-finite values.
pub fn linear_fit(x: &[f64], y: &[f64]) -> Result<LinearFit> {
    if x.len() != y.len() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "linear_fit got {} x values and {} y values; pass equally many",
                x.len(),
                y.len()
            ),
        ));
    }
    let n = x.len();
    if n < 3 {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "linear_fit got n = {n} points, allowed range [3, inf) (standard errors need \
                 n - 2 >= 1); widen the fit range"
            ),
        ));
    }
    if let Some(i) = (0..n).find(|&i| !x[i].is_finite() || !y[i].is_finite()) {
        return Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "linear_fit point {i} is (x, y) = ({}, {}); all values must be finite",
                x[i], y[i]
            ),
        ));
    }
    let nf = n as f64;
    let mx = x.iter().sum::<f64>() / nf;
    let my = y.iter().sum::<f64>() / nf;
    let mut sxx = 0.0;
    let mut sxy = 0.0;
    for (xi, yi) in x.iter().zip(y) {
        sxx += (xi - mx) * (xi - mx);
        sxy += (xi - mx) * (yi - my);
    }
    if sxx <= 0.0 {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "linear_fit: all {n} x values equal {mx}; the slope is undefined; use distinct x"
            ),
        ));
    }
    let slope = sxy / sxx;
    let intercept = my - slope * mx;
    let ssr: f64 = x
        .iter()
        .zip(y)
        .map(|(xi, yi)| {
            let r = yi - intercept - slope * xi;
            r * r
        })
        .sum();
    let s2 = ssr / (nf - 2.0);
    Ok(LinearFit {
        slope,
        intercept,
        slope_err: (s2 / sxx).sqrt(),
        intercept_err: (s2 * (1.0 / nf + mx * mx / sxx)).sqrt(),
        n,
    })
}

/// Which points enter the power-law fit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Binning {
    /// Every bin j of the range (minus the excluded ones) is one point: the
    /// plain least-squares slope of MODEL.md A9. The default.
    #[default]
    AllPoints,
    /// The means of log10 j and log10 P(j) over bins equally spaced in
    /// log10 j, `per_decade` of them per decade starting at log10 j_lo; each
    /// non-empty bin is one point, so every decade weighs the same.
    LogBins {
        /// Bins per decade of j, at least 1 (e.g. 20).
        per_decade: usize,
    },
}

/// What [`fit_power_law`] fits: the range j_lo..=j_hi minus the `exclude`
/// ranges, with the given binning.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PowerLawParams {
    /// First bin of the fit range, at least 1.
    pub j_lo: usize,
    /// Last bin of the fit range (inclusive), below the spectrum's length.
    pub j_hi: usize,
    /// Bins left out (e.g. the peak, see [`exclude_peak`]).
    pub exclude: Vec<RangeInclusive<usize>>,
    /// All points or log-binned.
    pub binning: Binning,
}

impl PowerLawParams {
    /// The [`default_fit_range`] for `m`, nothing excluded, all points.
    pub fn default_for(m: usize) -> Self {
        let (j_lo, j_hi) = default_fit_range(m);
        PowerLawParams {
            j_lo,
            j_hi,
            exclude: Vec::new(),
            binning: Binning::AllPoints,
        }
    }

    fn is_excluded(&self, j: usize) -> bool {
        self.exclude.iter().any(|r| r.contains(&j))
    }
}

/// The result of [`fit_power_law`]: P(j) ~ 10^log10_amplitude * j^-alpha.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PowerLawFit {
    /// The exponent, minus the slope of log10 P against log10 j.
    pub alpha: f64,
    /// The standard error of the slope (see the module docs for its caveat).
    pub alpha_err: f64,
    /// The intercept, log10 P at j = 1 (biased low when log-binned).
    pub log10_amplitude: f64,
    /// Points in the regression (bins j, or log bins with [`Binning::LogBins`]).
    pub n_points: usize,
    /// Spectral bins j used (after exclusion), whatever the binning.
    pub n_bins: usize,
}

/// Fit P(j) ~ j^-alpha by least squares in log-log over the range of
/// `params` (MODEL.md A9 "Exponent alpha"; see the module docs).
///
/// Errors: [`ErrorKind::InvalidParameter`] for j_lo = 0, j_lo >= j_hi,
/// j_hi >= p.len(), per_decade = 0 or fewer than 3 points left;
/// [`ErrorKind::BadSeries`] for a P(j) in the range that is not finite and
/// positive.
pub fn fit_power_law(p: &[f64], params: &PowerLawParams) -> Result<PowerLawFit> {
    check_range_in(p, params.j_lo, params.j_hi)?;
    let mut lx = Vec::new();
    let mut ly = Vec::new();
    for j in params.j_lo..=params.j_hi {
        if params.is_excluded(j) {
            continue;
        }
        let v = p[j];
        if !(v.is_finite() && v > 0.0) {
            return Err(Error::new(
                ErrorKind::BadSeries,
                format!(
                    "P({j}) = {v}; a power-law fit needs finite P > 0 in the fit range \
                     {}..={}; exclude j = {j} or check the spectrum",
                    params.j_lo, params.j_hi
                ),
            ));
        }
        lx.push((j as f64).log10());
        ly.push(v.log10());
    }
    let n_bins = lx.len();
    let (x, y) = match params.binning {
        Binning::AllPoints => (lx, ly),
        Binning::LogBins { per_decade } => {
            if per_decade == 0 {
                return Err(Error::out_of_range("per_decade", 0, "[1, inf)"));
            }
            log_bin(&lx, &ly, (params.j_lo as f64).log10(), per_decade)
        }
    };
    if x.len() < 3 {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "power-law fit over {}..={} has n = {} points after exclusion and binning, \
                 allowed range [3, inf); widen the range, exclude less or use more bins \
                 per decade",
                params.j_lo,
                params.j_hi,
                x.len()
            ),
        ));
    }
    let f = linear_fit(&x, &y)?;
    Ok(PowerLawFit {
        alpha: -f.slope,
        alpha_err: f.slope_err,
        log10_amplitude: f.intercept,
        n_points: f.n,
        n_bins,
    })
}

/// Means of x and y in bins of x of width 1/per_decade starting at `x0`
/// (x = log10 j >= x0); empty bins are skipped.
fn log_bin(x: &[f64], y: &[f64], x0: f64, per_decade: usize) -> (Vec<f64>, Vec<f64>) {
    let mut bx: Vec<f64> = Vec::new();
    let mut by: Vec<f64> = Vec::new();
    let mut count: Vec<usize> = Vec::new();
    for (&xi, &yi) in x.iter().zip(y) {
        // The tiny offset keeps a j that sits exactly on an edge (e.g. a
        // power of ten) in the bin it starts, despite rounding.
        let b = ((xi - x0) * per_decade as f64 + 1e-9).floor().max(0.0) as usize;
        if b >= count.len() {
            bx.resize(b + 1, 0.0);
            by.resize(b + 1, 0.0);
            count.resize(b + 1, 0);
        }
        bx[b] += xi;
        by[b] += yi;
        count[b] += 1;
    }
    let mut ox = Vec::new();
    let mut oy = Vec::new();
    for b in 0..count.len() {
        if count[b] > 0 {
            ox.push(bx[b] / count[b] as f64);
            oy.push(by[b] / count[b] as f64);
        }
    }
    (ox, oy)
}

/// Check 1 <= j_lo <= j_hi < p.len().
fn check_range_in(p: &[f64], j_lo: usize, j_hi: usize) -> Result<()> {
    if j_lo == 0 || j_lo > j_hi || j_hi >= p.len() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "range j_lo..=j_hi = {j_lo}..={j_hi} is not allowed for a spectrum of {} \
                 values: need 1 <= j_lo <= j_hi <= {}; see default_fit_range",
                p.len(),
                p.len().saturating_sub(1)
            ),
        ));
    }
    Ok(())
}

/// The default fit range for `m` output frequencies: [PH94]'s 40..=1000 at
/// m = 16384, both ends scaled by m / 16384 and rounded to the nearest
/// integer (halves up), with j_lo >= 2 and j_hi <= m - 1 (and j_hi >= j_lo).
///
/// ```
/// use granular_automata::analysis::fit::default_fit_range;
/// assert_eq!(default_fit_range(16384), (40, 1000));
/// assert_eq!(default_fit_range(4096), (10, 250));
/// assert_eq!(default_fit_range(1024), (3, 63));
/// ```
pub fn default_fit_range(m: usize) -> (usize, usize) {
    let scale = |j: usize| (j * m + 8192) / 16384;
    let j_lo = scale(40).max(2);
    let j_hi = scale(1000).min(m.saturating_sub(1)).max(j_lo);
    (j_lo, j_hi)
}

/// Half-width h of the running-median window of [`local_background`] used
/// by [`find_peak`]: 2h + 1 = 33 bins.
pub const PEAK_BACKGROUND_HALF_WINDOW: usize = 16;

/// The smooth background B(j) under bin `j`: the median of
/// P(j-h..=j+h) with h = [`PEAK_BACKGROUND_HALF_WINDOW`], shrunk to
/// min(h, j-1, len-1-j) so that the window stays symmetric and never
/// contains the DC bin j = 0. For a monotone spectrum this is P(j) itself.
pub fn local_background(p: &[f64], j: usize) -> f64 {
    let h = PEAK_BACKGROUND_HALF_WINDOW
        .min(j.saturating_sub(1))
        .min(p.len().saturating_sub(j + 1));
    let mut w: Vec<f64> = p[j - h..=j + h].to_vec();
    w.sort_by(f64::total_cmp);
    w[h]
}

/// The sharp peak of the spectrum inside j_lo..=j_hi (only there): the j
/// maximising P(j) / [`local_background`](j) (ties: the lowest j). See the
/// module docs for why this does not pick the low-frequency end of a 1/f
/// spectrum.
///
/// Errors: [`ErrorKind::InvalidParameter`] unless 1 <= j_lo <= j_hi <
/// p.len(); [`ErrorKind::BadSeries`] for a non-finite or non-positive
/// background.
pub fn find_peak(p: &[f64], j_lo: usize, j_hi: usize) -> Result<usize> {
    Ok(find_peak_contrast(p, j_lo, j_hi)?.0)
}

/// [`find_peak`] and the peak's contrast P(j_peak) / B(j_peak) (about 1-4
/// for a spectrum without a line; a sharp line gives much more).
pub fn find_peak_contrast(p: &[f64], j_lo: usize, j_hi: usize) -> Result<(usize, f64)> {
    check_range_in(p, j_lo, j_hi)?;
    let mut best = (j_lo, f64::NEG_INFINITY);
    for j in j_lo..=j_hi {
        let b = local_background(p, j);
        if !(b.is_finite() && b > 0.0 && p[j].is_finite()) {
            return Err(Error::new(
                ErrorKind::BadSeries,
                format!(
                    "P({j}) = {} over background {b}: peak finding needs finite P and a \
                     positive background; check the spectrum",
                    p[j]
                ),
            ));
        }
        let c = p[j] / b;
        if c > best.1 {
            best = (j, c);
        }
    }
    Ok(best)
}

/// The default half-width of the peak exclusion for `m` output
/// frequencies: max(4, m / 1024) bins, 16 at m = 16384 (see the module docs).
pub fn default_peak_half_width(m: usize) -> usize {
    (m / 1024).max(4)
}

/// The bins removed around a peak: j_peak - half_width ..= j_peak +
/// half_width (saturating at 0).
pub fn exclude_peak(j_peak: usize, half_width: usize) -> RangeInclusive<usize> {
    j_peak.saturating_sub(half_width)..=j_peak.saturating_add(half_width)
}

/// Half-widths for [`alpha_sensitivity`]: 0 (no exclusion), d/2, d, 2d and
/// 4d with d = [`default_peak_half_width`]`(m)`.
pub fn default_sensitivity_widths(m: usize) -> Vec<usize> {
    let d = default_peak_half_width(m);
    vec![0, d / 2, d, 2 * d, 4 * d]
}

/// alpha for several peak-exclusion half-widths (MODEL.md A9 asks for the
/// sensitivity of alpha to the peak removal): for each width, the fit of
/// `params` with [`exclude_peak`]`(j_peak, width)` added to its exclusions.
/// Width 0 means no peak exclusion at all (not even the peak bin).
pub fn alpha_sensitivity(
    p: &[f64],
    params: &PowerLawParams,
    j_peak: usize,
    half_widths: &[usize],
) -> Result<Vec<(usize, PowerLawFit)>> {
    half_widths
        .iter()
        .map(|&w| {
            let mut q = params.clone();
            if w > 0 {
                q.exclude.push(exclude_peak(j_peak, w));
            }
            fit_power_law(p, &q).map(|f| (w, f))
        })
        .collect()
}

/// The default analysis of MODEL.md A9: [`default_fit_range`], the peak
/// found there, removed with [`default_peak_half_width`], all points.
#[derive(Debug, Clone, PartialEq)]
pub struct AlphaEstimate {
    /// The power-law fit with the peak removed.
    pub fit: PowerLawFit,
    /// The peak ([`find_peak`]).
    pub j_peak: usize,
    /// Its contrast P / background ([`find_peak_contrast`]).
    pub contrast: f64,
    /// The bins removed around it.
    pub excluded: RangeInclusive<usize>,
}

/// alpha of a spectrum of m = p.len() frequencies the default way: see
/// [`AlphaEstimate`]. The peak bins are removed even when the contrast shows
/// no real line (that costs 2h + 1 bins of noise, nothing else).
pub fn estimate_alpha(p: &[f64]) -> Result<AlphaEstimate> {
    let m = p.len();
    let mut params = PowerLawParams::default_for(m);
    let (j_peak, contrast) = find_peak_contrast(p, params.j_lo, params.j_hi)?;
    let excluded = exclude_peak(j_peak, default_peak_half_width(m));
    params.exclude.push(excluded.clone());
    Ok(AlphaEstimate {
        fit: fit_power_law(p, &params)?,
        j_peak,
        contrast,
        excluded,
    })
}

/// The wave velocity from the spectral peak (MODEL.md A9):
/// v = L * j_peak / (T0 * 2m) rows per step, for a pipe of `l_rows` rows
/// sampled every `t0_steps` steps, with `m` output frequencies.
///
/// The check of MODEL.md A9 ([PH94]): L = 220, j = 596, T0 = 10,
/// m = 16384 gives v = 0.40.
///
/// ```
/// use granular_automata::analysis::fit::wave_velocity;
/// let v = wave_velocity(220, 596, 10, 16384);
/// assert_eq!(format!("{v:.2}"), "0.40");
/// ```
pub fn wave_velocity(l_rows: usize, j_peak: usize, t0_steps: usize, m: usize) -> f64 {
    l_rows as f64 * j_peak as f64 / (t0_steps as f64 * 2.0 * m as f64)
}

/// The period of bin `j` in steps: T0 * 2m / j (infinite for j = 0).
///
/// The check of MODEL.md A9 ([PH94]): "f = 1000 corresponds to T = 328".
///
/// ```
/// use granular_automata::analysis::fit::period_steps;
/// assert!((period_steps(1000, 10, 16384) - 327.68).abs() < 1e-12);
/// ```
pub fn period_steps(j: usize, t0_steps: usize, m: usize) -> f64 {
    t0_steps as f64 * 2.0 * m as f64 / j as f64
}
