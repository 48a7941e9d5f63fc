//! The published claims of PH95 Fig. 3 as checks: the driver above
//! `analysis::relaxation` (which measures the approach to saturation) that
//! `waves-fig3` and the reproduction matrix share.

use crate::analysis::grading::{Claim, Estimate};
use crate::analysis::relaxation::{Saturation, SATURATION_MARGIN};
use crate::run::Check;

/// The published claims of PH95 Fig. 3, graded by the one rule from the
/// contrast `c` and the energy loss `e` of `runs` runs (used by
/// `waves-fig3` and by the reproduction matrix):
/// - `contrast_rises` (Fig. 3a): C_sat - C(0) per run above 0;
/// - `contrast_saturates` (Fig. 3a): the late drift of C over |C_sat - C(0)|
///   within [`SATURATION_MARGIN`] of 0;
/// - `energy_loss_rises` (Fig. 3b): the saturation value of E(0) - E(t)
///   above 0;
/// - `energy_loss_saturates` (Fig. 3b): its late drift over its saturation
///   value within [`SATURATION_MARGIN`] of 0.
///
/// A ratio over a change of 0 is NaN: undecided.
pub fn fig3_checks(c: &Saturation, e: &Saturation, runs: usize) -> Vec<Check> {
    let ((c_rise, c_rise_err), (c_drift, c_drift_err)) = (c.change, c.late_drift);
    let ((e_drift, e_drift_err), (e_sat, e_sat_err)) = (e.late_drift, e.saturation);
    let est = |m: f64, e: f64| Estimate::new(m, e, runs);
    let ratio = |(d, de): (f64, f64), total: f64| est(d / total.abs(), de / total.abs());
    let saturated = Claim::Within {
        target: 0.0,
        margin: SATURATION_MARGIN,
    };
    let above_zero = Claim::Above { threshold: 0.0 };
    // (name, source, statistic, claim, how it is measured)
    #[rustfmt::skip]
    let rows = [
        ("contrast_rises", "PH95 Fig. 3a (C rises from its start)", est(c_rise, c_rise_err), above_zero, "C_sat - C(0) per run > 0"),
        ("contrast_saturates", "PH95 Fig. 3a (C saturates)", ratio((c_drift, c_drift_err), c_rise), saturated,
            "(mean over the last quarter - mean over the third quarter) / |C_sat - C(0)| within 0.1 of 0"),
        ("energy_loss_rises", "PH95 Fig. 3b (E(0) - E(t) rises)", est(e_sat, e_sat_err), above_zero, "saturation value of E(0) - E(t) > 0"),
        ("energy_loss_saturates", "PH95 Fig. 3b (E(0) - E(t) saturates)", ratio((e_drift, e_drift_err), e_sat), saturated,
            "(last quarter - third quarter) / saturation value of E(0) - E(t) within 0.1 of 0"),
    ];
    rows.into_iter()
        .map(|(name, source, stat, claim, how)| Check::published(name, source, stat, claim, how))
        .collect()
}
