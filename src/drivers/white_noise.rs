//! PH95 Fig. 7's checks (`waves-fig7`): white noise (alpha about 0) at
//! p = 0 and at b = 0, and at b = 0 a spectral line at v = 1/2 exactly; at
//! the acceptance tier with the estimators and margins of
//! [`crate::drivers::acceptance`].

use super::acceptance::margin;
use super::margins::ALPHA_MARGIN;
use super::spectra::{SpectrumEnsemble, SpectrumSetup};
use crate::analysis::grading::Claim;
use crate::analysis::mean_spectrum::{alpha_of_mean, v_of_mean};
use crate::run::Check;
use std::collections::BTreeMap;

/// The cases of PH95 Fig. 7, in the order of the ensembles: p = 0 and b = 0.
pub const CASES: [&str; 2] = ["p0", "b0"];

/// Each case's alpha, peak velocity and peak contrast with their errors.
pub fn metrics(ens: &[SpectrumEnsemble]) -> BTreeMap<String, f64> {
    let mut metrics = BTreeMap::new();
    for (e, name) in ens.iter().zip(CASES) {
        metrics.insert(format!("alpha_{name}"), e.alpha);
        metrics.insert(format!("alpha_{name}_err"), e.alpha_err);
        metrics.insert(format!("v_peak_{name}"), e.v_peak);
        metrics.insert(format!("v_peak_{name}_err"), e.v_err);
        metrics.insert(format!("peak_contrast_{name}"), e.fit_of_mean.contrast);
    }
    metrics
}

/// The checks below the acceptance tier: the mean of the per-run fitted
/// alpha within [`ALPHA_MARGIN`] of 0 for both cases, and the peak of the
/// averaged spectrum at b = 0 within two frequency bins of v = 1/2 (`setup`:
/// the set-up of the spectra, for the width of a bin).
pub fn checks(setup: &SpectrumSetup, ens: &[SpectrumEnsemble]) -> Vec<Check> {
    let bin_width_v = setup.params.length as f64 / (10.0 * 2.0 * setup.m as f64);
    let white = |name: &str, e: &SpectrumEnsemble, what: &str| {
        Check::published(
            name,
            "PH95 Fig. 7 (alpha about 0)",
            e.alpha_estimate(),
            Claim::Within {
                target: 0.0,
                margin: ALPHA_MARGIN,
            },
            &format!("white noise at {what}; mean of the per-run fitted alpha, margin Delta = {ALPHA_MARGIN} as in pipe-matrix"),
        )
    };
    vec![
        white("alpha_p0", &ens[0], "p = 0"),
        white("alpha_b0", &ens[1], "b = 0"),
        // "exactly 1/2" is a spectral line: its position in the averaged
        // spectrum is fixed to a frequency bin, so the margin is two bins
        Check::published(
            "v_peak_b0",
            "PH95 Fig. 7 (peak at v = 1/2 exactly)",
            ens[1].v_estimate(),
            Claim::Within {
                target: 0.5,
                margin: 2.0 * bin_width_v,
            },
            "peak of the averaged spectrum at b = 0, SE of the per-run peaks; margin Delta = two frequency bins",
        ),
    ]
}

/// The checks at the acceptance tier: the estimators and margins of
/// `drivers::acceptance` (fit of the averaged spectrum, bootstrap SE; peak
/// of the averaged spectrum, bootstrap SE).
pub fn acceptance_checks(
    setup: &SpectrumSetup,
    ens: &[SpectrumEnsemble],
) -> crate::Result<Vec<Check>> {
    let mut checks = Vec::new();
    for (check, e) in [("alpha_p0", &ens[0]), ("alpha_b0", &ens[1])] {
        if let Some(m) = margin("waves-fig7", check) {
            checks.push(Check::published(
                check,
                m.source,
                alpha_of_mean(&e.spectra())?,
                m.claim(),
                &format!(
                    "fit of the averaged spectrum, bootstrap SE over runs; {}",
                    m.note()
                ),
            ));
        }
    }
    if let Some(m) = margin("waves-fig7", "v_peak_b0") {
        checks.push(Check::published(
            "v_peak_b0",
            m.source,
            v_of_mean(&ens[1].spectra(), setup.params.length, setup.t0)?,
            m.claim(),
            &format!(
                "peak of the averaged spectrum at b = 0, bootstrap SE over runs; {}",
                m.note()
            ),
        ));
    }
    Ok(checks)
}

/// The published alpha of check `name` among `checks` (a claim within a
/// margin) drawn over the spectrum of `ens` ([`super::spectra::published_alpha_lines`]);
/// none when the check states no such claim.
pub fn published_lines(
    checks: &[crate::run::Check],
    name: &str,
    ens: &super::spectra::SpectrumEnsemble,
) -> Vec<crate::plot::Line> {
    match checks.iter().find(|c| c.name == name).and_then(|c| c.claim) {
        Some(crate::analysis::grading::Claim::Within { target, margin }) => {
            super::spectra::published_alpha_lines(ens, (target, margin))
        }
        _ => vec![],
    }
}
