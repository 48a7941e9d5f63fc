//! The power-spectrum estimator of MODEL.md A9 "Power spectrum": Numerical
//! Recipes in C (1988, 1st edition) `spctrm`, without overlap.
//!
//! # The estimator
//!
//! With `m` output frequencies and `k` as in NR, a segment has `N = 2m`
//! samples and `2k` consecutive segments are used, i.e. `4km` samples
//! (extra samples at the end of the series are ignored; fewer is an error).
//! The mean of the whole used series is subtracted (MODEL.md A9), every
//! segment is multiplied by the window `w_i` (i = 0..N-1) and transformed,
//! X_s(j) = sum_i w_i x_{s,i} exp(-2 pi i i j / N). NR reads two segments into
//! the real and imaginary parts of one complex FFT; here each segment gets its
//! own FFT, which gives the same periodograms (checked against a
//! transliteration of NR's code in the tests). The output is, for
//! j = 0..m-1 at [`frequency`] j/(2m) cycles per sample,
//!
//! ```text
//! P(0) = 1/(2k) sum_s |X_s(0)|^2                  / (N sum_i w_i^2)
//! P(j) = 1/(2k) sum_s (|X_s(j)|^2 + |X_s(N-j)|^2) / (N sum_i w_i^2)
//! ```
//!
//! The Nyquist value j = m is dropped, as NR does.
//!
//! # Normalisation
//!
//! NR accumulates, per complex FFT Z = X + iY holding two segments,
//! `p[1] += |Z_0|^2` and `p[j] += |Z_j|^2 + |Z_{N-j}|^2` (j >= 1 in 0-based
//! terms), which equals |X_0|^2 + |Y_0|^2 and |X_j|^2 + |X_{N-j}|^2 + |Y_j|^2 +
//! |Y_{N-j}|^2 because X and Y are transforms of real data. It then divides by
//! `den = k * sumw * 4m` with `sumw = sum_i w_i^2` over one segment; since
//! 4m = 2N and there are 2k segments, that is `2k * N * sumw` = (number of
//! segments) * N * sum w^2, the formula above. By Parseval,
//! sum_{j=0}^{N-1} |X_s(j)|^2 = N sum_i w_i^2 x_{s,i}^2, so
//!
//! ```text
//! sum_{j=0}^{m-1} P(j) + P_Nyquist = 1/(2k) sum_s sum_i w_i^2 x_{s,i}^2 / sum_i w_i^2,
//! ```
//!
//! the window-weighted mean square of the (mean-subtracted) series: "the sum
//! of P over the one-sided frequencies is the mean square of the signal". A
//! sine of amplitude A at a bin frequency j0 has sum_j P(j) = A^2/2 up to
//! the window-weighting of sin^2, a relative error of about 0.15/j0^2 for
//! the triangles (tested to 1e-3 for j0 >= 20; 15 per cent at j0 = 1).

use crate::error::{Error, ErrorKind, Result};
use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

/// The data window applied to each segment of N = 2m samples.
///
/// The default is [`Window::Parzen1988`], the window of MODEL.md A9.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Window {
    /// The triangle that NR (1988, 1st edition) calls "Parzen":
    /// w_i = 1 - |(i - (N-1)/2) / ((N+1)/2)| for i = 0..N-1 (NR's
    /// `facm = m - 0.5`, `facp = 1/(m + 0.5)`); it never reaches 0. The
    /// default (MODEL.md A9).
    #[default]
    Parzen1988,
    /// The same triangle as NR's 2nd edition (1992) names it, "Bartlett",
    /// shifted by half a sample: w_i = 1 - |(i - N/2) / (N/2)| (`facm = m`,
    /// `facp = 1/m`), so w_0 = 0.
    Bartlett1992,
    /// No window, w_i = 1 (NR's "square" window).
    Square,
}

impl Window {
    /// The weight w_i of sample `i` (0-based) of a segment of `n` samples.
    pub fn weight(self, i: usize, n: usize) -> f64 {
        let i = i as f64;
        let n = n as f64;
        match self {
            Window::Parzen1988 => 1.0 - ((i - (n - 1.0) / 2.0) / ((n + 1.0) / 2.0)).abs(),
            Window::Bartlett1992 => 1.0 - ((i - n / 2.0) / (n / 2.0)).abs(),
            Window::Square => 1.0,
        }
    }

    /// All `n` weights of a segment of `n` samples.
    pub fn weights(self, n: usize) -> Vec<f64> {
        (0..n).map(|i| self.weight(i, n)).collect()
    }

    /// A short name for file names and plot legends.
    pub fn name(self) -> &'static str {
        match self {
            Window::Parzen1988 => "parzen1988",
            Window::Bartlett1992 => "bartlett1992",
            Window::Square => "square",
        }
    }
}

/// The parameters of [`spctrm`] (MODEL.md A9): `m` output frequencies,
/// `2k` segments of `2m` samples, and the window.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SpectrumParams {
    /// Number of output frequencies; a segment has 2m samples. A power of
    /// two, at least 2. The paper uses 16384.
    pub m: usize,
    /// Half the number of segments (NR's `k`); at least 1. The paper uses 4.
    pub k: usize,
    /// The data window; MODEL.md A9 uses [`Window::Parzen1988`].
    pub window: Window,
}

impl Default for SpectrumParams {
    /// The set-up of \[PH94\] Fig. 2 (MODEL.md A9): m = 16384, k = 4, the 1988
    /// "Parzen" window.
    fn default() -> Self {
        SpectrumParams {
            m: 16384,
            k: 4,
            window: Window::Parzen1988,
        }
    }
}

impl SpectrumParams {
    /// Check `m` (a power of two, >= 2) and `k` (>= 1), and that 4km
    /// samples can be counted.
    pub fn validate(&self) -> Result<()> {
        if self.m < 2 || !self.m.is_power_of_two() {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "spectrum m = {} is not allowed: m must be a power of two >= 2 \
                     (NR spctrm); use e.g. m = {}",
                    self.m,
                    self.m.max(2).next_power_of_two()
                ),
            ));
        }
        if self.k == 0 {
            return Err(Error::out_of_range("spectrum k", self.k, "[1, inf)"));
        }
        if self
            .m
            .checked_mul(self.k)
            .and_then(|x| x.checked_mul(4))
            .is_none()
        {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "spectrum 4*k*m overflows for m = {}, k = {}; choose smaller m or k",
                    self.m, self.k
                ),
            ));
        }
        Ok(())
    }

    /// The number of samples the estimator uses, 4km (2k segments of 2m).
    pub fn samples_used(&self) -> usize {
        4 * self.k * self.m
    }
}

/// The frequency of output bin `j` in cycles per sample: j / (2m).
///
/// ```
/// use granular_automata::analysis::spectrum::frequency;
/// assert_eq!(frequency(1000, 16384), 1000.0 / 32768.0);
/// ```
pub fn frequency(j: usize, m: usize) -> f64 {
    j as f64 / (2.0 * m as f64)
}

/// The NR (1988) `spctrm` power spectrum of `series` without overlap
/// (MODEL.md A9; see the module docs for the formula and normalisation).
///
/// Returns P(j) for j = 0..m-1. Uses the first 4km samples and ignores the
/// rest. Errors ([`ErrorKind::InvalidParameter`]) for m not a power of two
/// or < 2 and k = 0; ([`ErrorKind::BadSeries`]) for fewer than 4km samples,
/// a non-finite value among the used samples, or used samples that are all
/// equal (the spectrum would be identically zero).
pub fn spctrm(series: &[f64], params: &SpectrumParams) -> Result<Vec<f64>> {
    params.validate()?;
    let m = params.m;
    let k = params.k;
    let n_seg = 2 * m;
    let n_used = params.samples_used();
    if series.len() < n_used {
        return Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "time series has {} samples but the spectrum with m = {m}, k = {k} needs \
                 4*k*m = {n_used}; record a longer series or lower m or k",
                series.len()
            ),
        ));
    }
    let used = &series[..n_used];
    if let Some((i, v)) = used.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "time series sample {i} is {v}; all {n_used} used samples must be finite; \
                 check the recording"
            ),
        ));
    }
    if used.iter().all(|&v| v == used[0]) {
        return Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "all {n_used} used samples of the time series equal {}; the spectrum of a \
                 constant series is zero and log P is undefined; record a fluctuating \
                 observable (e.g. another bin or a longer run)",
                used[0]
            ),
        ));
    }
    let mean = used.iter().sum::<f64>() / n_used as f64;
    let w = params.window.weights(n_seg);
    let sumw: f64 = w.iter().map(|x| x * x).sum();

    let fft = FftPlanner::<f64>::new().plan_fft_forward(n_seg);
    let mut buf = vec![Complex::new(0.0, 0.0); n_seg];
    let mut p = vec![0.0; m];
    for seg in used.chunks_exact(n_seg) {
        for ((b, &x), &wi) in buf.iter_mut().zip(seg).zip(&w) {
            *b = Complex::new((x - mean) * wi, 0.0);
        }
        fft.process(&mut buf);
        p[0] += buf[0].norm_sqr();
        for (j, pj) in p.iter_mut().enumerate().skip(1) {
            *pj += buf[j].norm_sqr() + buf[n_seg - j].norm_sqr();
        }
    }
    let den = (2 * k) as f64 * n_seg as f64 * sumw;
    for pj in &mut p {
        *pj /= den;
    }
    Ok(p)
}

/// The element-wise mean of several spectra of equal length (e.g. of
/// independent runs or of several bins).
///
/// Errors ([`ErrorKind::InvalidParameter`]) for no spectra or spectra of
/// different lengths.
pub fn average_spectra(spectra: &[Vec<f64>]) -> Result<Vec<f64>> {
    let Some(first) = spectra.first() else {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            "average_spectra got 0 spectra; pass at least 1",
        ));
    };
    let len = first.len();
    if let Some((i, s)) = spectra.iter().enumerate().find(|(_, s)| s.len() != len) {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "spectrum {i} has {} values but spectrum 0 has {len}; average only spectra \
                 computed with the same m",
                s.len()
            ),
        ));
    }
    let mut mean = vec![0.0; len];
    for s in spectra {
        for (a, &v) in mean.iter_mut().zip(s) {
            *a += v;
        }
    }
    let n = spectra.len() as f64;
    for a in &mut mean {
        *a /= n;
    }
    Ok(mean)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;
    use std::f64::consts::PI;

    /// The one seed of every randomised test in this module.
    const SEED: u64 = 0x5eed_5bec_7a11;

    fn white(n: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
        (0..n).map(|_| rng.random::<f64>() - 0.5).collect()
    }

    /// A line-by-line transliteration of NR (1988) `spctrm` with
    /// `ovrlap = 0` (1-based arrays, two segments per complex FFT, `four1`
    /// with isign = +1, i.e. exp(+2 pi i jk/N), unnormalised), reading from
    /// an already mean-subtracted series. The reference for [`spctrm`].
    // Keeps NR's 1-based index arithmetic on purpose.
    #[allow(clippy::needless_range_loop)]
    fn nr_spctrm(x: &[f64], m: usize, k: usize, facm: f64, facp: f64) -> Vec<f64> {
        let window = |j: usize| 1.0 - (((j as f64 - 1.0) - facm) * facp).abs();
        let mm = m + m;
        let m4 = mm + mm;
        let m43 = m4 + 3;
        let m44 = m43 + 1;
        let mut w1 = vec![0.0; m4 + 1];
        let mut p = vec![0.0; m + 1];
        let mut sumw = 0.0;
        let mut den = 0.0;
        for j in 1..=mm {
            sumw += window(j) * window(j);
        }
        let four1 = FftPlanner::<f64>::new().plan_fft_inverse(mm);
        let mut input = x.iter();
        for _kk in 1..=k {
            for joff in [-1i64, 0] {
                let mut j = (joff + 2) as usize;
                while j <= m4 {
                    w1[j] = *input.next().unwrap();
                    j += 2;
                }
            }
            for j in 1..=mm {
                let j2 = j + j;
                let w = window(j);
                w1[j2] *= w;
                w1[j2 - 1] *= w;
            }
            let mut c: Vec<Complex<f64>> = (0..mm)
                .map(|i| Complex::new(w1[2 * i + 1], w1[2 * i + 2]))
                .collect();
            four1.process(&mut c);
            for (i, z) in c.iter().enumerate() {
                w1[2 * i + 1] = z.re;
                w1[2 * i + 2] = z.im;
            }
            p[1] += w1[1] * w1[1] + w1[2] * w1[2];
            for j in 2..=m {
                let j2 = j + j;
                p[j] += w1[j2] * w1[j2]
                    + w1[j2 - 1] * w1[j2 - 1]
                    + w1[m44 - j2] * w1[m44 - j2]
                    + w1[m43 - j2] * w1[m43 - j2];
            }
            den += sumw;
        }
        den *= m4 as f64;
        p[1..].iter().map(|v| v / den).collect()
    }

    #[test]
    fn windows_match_nr_macros() {
        // NR: WINDOW(j,a,b) = 1 - |((j-1) - a) * b|, 1-based j.
        let m = 8;
        let n = 2 * m;
        for i in 0..n {
            let j = (i + 1) as f64;
            let parzen = 1.0 - (((j - 1.0) - (m as f64 - 0.5)) / (m as f64 + 0.5)).abs();
            let bartlett = 1.0 - (((j - 1.0) - m as f64) / m as f64).abs();
            assert!((Window::Parzen1988.weight(i, n) - parzen).abs() < 1e-15);
            assert!((Window::Bartlett1992.weight(i, n) - bartlett).abs() < 1e-15);
            assert_eq!(Window::Square.weight(i, n), 1.0);
        }
        // Parzen1988 is symmetric and never 0; Bartlett1992 starts at 0.
        let w = Window::Parzen1988.weights(n);
        assert!((w[0] - w[n - 1]).abs() < 1e-15 && w[0] > 0.0);
        assert_eq!(Window::Bartlett1992.weight(0, n), 0.0);
        assert_eq!(Window::default(), Window::Parzen1988);
    }

    #[test]
    fn matches_transliterated_nr_code() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(SEED);
        let (m, k) = (64, 3);
        let mut x = white(4 * k * m + 17, &mut rng);
        // A trend and a line make the comparison non-trivial.
        for (i, v) in x.iter_mut().enumerate() {
            *v += 1e-3 * i as f64 + (2.0 * PI * 0.1 * i as f64).sin();
        }
        let n_used = 4 * k * m;
        let mean = x[..n_used].iter().sum::<f64>() / n_used as f64;
        let centred: Vec<f64> = x[..n_used].iter().map(|v| v - mean).collect();
        for (window, facm, facp) in [
            (Window::Parzen1988, m as f64 - 0.5, 1.0 / (m as f64 + 0.5)),
            (Window::Bartlett1992, m as f64, 1.0 / m as f64),
            (Window::Square, 0.0, 0.0),
        ] {
            let ours = spctrm(&x, &SpectrumParams { m, k, window }).unwrap();
            let nr = nr_spctrm(&centred, m, k, facm, facp);
            assert_eq!(ours.len(), m);
            for (j, (a, b)) in ours.iter().zip(&nr).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-10 * b.abs().max(1e-12),
                    "{window:?} j = {j}: ours {a}, NR {b}"
                );
            }
        }
    }

    #[test]
    fn sine_total_power_is_half_amplitude_squared() {
        let (m, k) = (1024, 4);
        let amp = 3.0;
        for window in [Window::Parzen1988, Window::Bartlett1992, Window::Square] {
            // j0 >= 20: for a triangle window, sum_i w_i^2 cos(4 pi j0 i / N)
            // / sum_i w_i^2 ~ 0.15 / j0^2 (the phase of the sine against the
            // window), below 4e-4 here; at j0 = 1 it is 15 per cent.
            for j0 in [20, 37, 500] {
                let x: Vec<f64> = (0..4 * k * m)
                    .map(|i| amp * (2.0 * PI * j0 as f64 * i as f64 / (2 * m) as f64).sin())
                    .collect();
                let p = spctrm(&x, &SpectrumParams { m, k, window }).unwrap();
                let total: f64 = p.iter().sum();
                let want = amp * amp / 2.0;
                assert!(
                    (total / want - 1.0).abs() < 1e-3,
                    "{window:?} j0 = {j0}: sum P = {total}, A^2/2 = {want}"
                );
            }
        }
    }

    #[test]
    fn low_frequency_sine_power_follows_the_window_weighting() {
        // sum P = A^2/2 * (1 -+ c/j0^2) for sin / cos, c = 0.1518 for the
        // Parzen1988 triangle at m = 1024 (sum_i w_i^2 cos(4 pi j0 i/N) /
        // sum_i w_i^2, computed independently).
        let (m, k) = (1024, 4);
        let params = SpectrumParams {
            m,
            k,
            window: Window::Parzen1988,
        };
        for j0 in [1usize, 2, 5] {
            for (sign, phase) in [(-1.0, 0.0), (1.0, PI / 2.0)] {
                let x: Vec<f64> = (0..4 * k * m)
                    .map(|i| (2.0 * PI * j0 as f64 * i as f64 / (2 * m) as f64 + phase).sin())
                    .collect();
                let total: f64 = spctrm(&x, &params).unwrap().iter().sum();
                let want = 0.5 * (1.0 + sign * 0.1518 / (j0 * j0) as f64);
                assert!(
                    (total / want - 1.0).abs() < 2e-4,
                    "j0 = {j0}: {total} vs {want}"
                );
            }
        }
    }

    #[test]
    fn white_noise_total_power_is_variance() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(SEED);
        let (m, k) = (1024, 4);
        let x = white(4 * k * m, &mut rng);
        let p = spctrm(
            &x,
            &SpectrumParams {
                m,
                k,
                window: Window::default(),
            },
        )
        .unwrap();
        let total: f64 = p.iter().sum();
        // Uniform on [-1/2, 1/2): variance 1/12; sum P = weighted mean square
        // minus the dropped Nyquist bin (1/m of it), to a few per cent.
        assert!((total * 12.0 - 1.0).abs() < 0.03, "sum P = {total}");
    }

    #[test]
    fn sine_peaks_at_its_bin() {
        let (m, k) = (1024, 4);
        for j0 in [5, 64, 333, 1000] {
            let x: Vec<f64> = (0..4 * k * m)
                .map(|i| (2.0 * PI * j0 as f64 * i as f64 / (2 * m) as f64).cos())
                .collect();
            let p = spctrm(
                &x,
                &SpectrumParams {
                    m,
                    k,
                    window: Window::default(),
                },
            )
            .unwrap();
            let argmax = (0..m).max_by(|&a, &b| p[a].total_cmp(&p[b])).unwrap();
            assert_eq!(argmax, j0);
            assert!((frequency(j0, m) - j0 as f64 / 2048.0).abs() < 1e-15);
        }
    }

    #[test]
    fn extra_samples_are_ignored() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(SEED);
        let (m, k) = (64, 2);
        let x = white(4 * k * m + 100, &mut rng);
        let params = SpectrumParams {
            m,
            k,
            window: Window::default(),
        };
        assert_eq!(
            spctrm(&x, &params).unwrap(),
            spctrm(&x[..4 * k * m], &params).unwrap()
        );
    }

    #[test]
    fn bad_input_is_an_error() {
        let params = SpectrumParams {
            m: 64,
            k: 2,
            window: Window::default(),
        };
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(SEED);
        let x = white(512, &mut rng);

        let e = spctrm(&x[..511], &params).unwrap_err();
        assert_eq!(e.kind, ErrorKind::BadSeries);
        assert!(
            e.message.contains("511") && e.message.contains("512"),
            "{}",
            e.message
        );

        let e = spctrm(&[2.5; 512], &params).unwrap_err();
        assert_eq!(e.kind, ErrorKind::BadSeries);
        assert!(e.message.contains("2.5"), "{}", e.message);

        let mut y = x.clone();
        y[7] = f64::NAN;
        let e = spctrm(&y, &params).unwrap_err();
        assert_eq!(e.kind, ErrorKind::BadSeries);
        assert!(e.message.contains("sample 7"), "{}", e.message);

        for m in [0, 1, 3, 100] {
            let e = spctrm(&x, &SpectrumParams { m, ..params }).unwrap_err();
            assert_eq!(e.kind, ErrorKind::InvalidParameter);
            assert!(e.message.contains(&format!("m = {m}")), "{}", e.message);
        }
        let e = spctrm(&x, &SpectrumParams { k: 0, ..params }).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidParameter);
        assert!(e.message.contains("k = 0"), "{}", e.message);
    }

    #[test]
    fn averaging_spectra() {
        let a = vec![1.0, 2.0, 3.0];
        let b = vec![3.0, 4.0, 5.0];
        assert_eq!(
            average_spectra(&[a.clone(), b]).unwrap(),
            vec![2.0, 3.0, 4.0]
        );
        assert!(average_spectra(&[]).is_err());
        let e = average_spectra(&[a, vec![1.0]]).unwrap_err();
        assert_eq!(e.kind, ErrorKind::InvalidParameter);
    }
}
