//! The wave speed from the power spectrum of the bin densities (MODEL.md A9,
//! "Wave velocity from the peak"), for a stack of density fields: the NR
//! `spctrm` of each bin's time series averaged over the bins, its
//! fundamental peak, refined to a fraction of a frequency bin, converted to
//! rows per step. Used by PH95 Fig. 5 to compare with the real-space speed.

use crate::analysis::spectrum::{average_spectra, spctrm, SpectrumParams};
use crate::error::{Error, Result};

/// Systematic error allowed for [`spectral_peak`] when the line falls
/// between frequency bins, in bins: 0.05. The unit test
/// `peak_interpolation_bias_is_small` measures at most 0.018 bins for a
/// steep-fronted pulse travelling at speeds between output bins (L = 512,
/// bins of 8 rows, T0 = 40, m = 256); 0.05 leaves a margin of about 3.
pub const PEAK_BIAS_BINS: f64 = 0.05;

/// The spectral peak: the j of largest power P(j) in 2..=m/4 (the
/// fundamental of a travelling wave; a contrast against a local background
/// would pick a harmonic of a sharp wave in about one run in five), refined
/// by a parabola through ln P at the peak and its two neighbours; in
/// fractional bins. Errors for spectra shorter than 12 bins.
pub fn spectral_peak(p: &[f64]) -> Result<f64> {
    let m = p.len();
    if m < 12 {
        return Err(Error::out_of_range("spectrum length m", m, "[12, inf)"));
    }
    let hi = (m / 4).min(m - 2);
    let j = (2..=hi)
        .max_by(|&a, &b| p[a].total_cmp(&p[b]).then(b.cmp(&a)))
        .expect("a non-empty range");
    let (l, c, r) = (p[j - 1].ln(), p[j].ln(), p[j + 1].ln());
    let den = l - 2.0 * c + r;
    let d = if den < 0.0 && den.is_finite() {
        (0.5 * (l - r) / den).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    Ok(j as f64 + d)
}

/// The bin-averaged spectrum of `fields[t][i]` (sampled every `t0` steps)
/// and the speed (rows per step, >= 0) of its [`spectral_peak`]:
/// v = L j / (t0 2m) for a periodic pipe of `length` rows.
pub fn spectral_speed(
    fields: &[Vec<f64>],
    length: usize,
    t0: u64,
    spec: &SpectrumParams,
) -> Result<(Vec<f64>, f64)> {
    let k = fields.first().map(|f| f.len()).unwrap_or(0);
    let per_bin = (0..k)
        .map(|i| spctrm(&fields.iter().map(|n| n[i]).collect::<Vec<_>>(), spec))
        .collect::<Result<Vec<_>>>()?;
    let spectrum = average_spectra(&per_bin)?;
    let j = spectral_peak(&spectrum)?;
    Ok((spectrum, peak_speed(length, j, t0, spec.m)))
}

/// The speed (rows per step) of a wave at (fractional) frequency bin `j` of
/// an m-frequency spectrum sampled every `t0` steps in a periodic pipe of
/// `length` rows: v = L j / (t0 2m).
pub fn peak_speed(length: usize, j: f64, t0: u64, m: usize) -> f64 {
    length as f64 * j / (t0 as f64 * 2.0 * m as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::spectrum::Window;

    /// A pulse with a steep front and a long tail travelling down at `v`
    /// rows per step through L = 512 rows in bins of 8, sampled every 40
    /// steps, 1024 fields: the estimated speed is within [`PEAK_BIAS_BINS`].
    #[test]
    fn peak_interpolation_bias_is_small() {
        let (l, bin, t0, n) = (512usize, 8usize, 40u64, 1024usize);
        let spec = SpectrumParams {
            m: n / 4,
            k: 1,
            window: Window::Parzen1988,
        };
        let res = l as f64 / (t0 as f64 * 2.0 * spec.m as f64);
        let mut worst: f64 = 0.0;
        for v in [0.2, 0.2137, 0.23, 0.2456, 0.25, 0.2631, 0.29] {
            let fields: Vec<Vec<f64>> = (0..n)
                .map(|t| {
                    let c = (400.0 - v * (t as f64) * t0 as f64).rem_euclid(l as f64);
                    (0..l / bin)
                        .map(|i| {
                            let y = (i * bin) as f64 + 0.5 * bin as f64;
                            let d = (y - c).rem_euclid(l as f64); // distance above the front
                            88.0 + 30.0 * (-d / 60.0).exp()
                        })
                        .collect()
                })
                .collect();
            let (_, est) = spectral_speed(&fields, l, t0, &spec).unwrap();
            worst = worst.max(((est - v) / res).abs());
        }
        eprintln!("worst bias {worst:.3} bins");
        assert!(worst < PEAK_BIAS_BINS, "bias {worst} bins");
    }
}
