//! The published claims of PH95 Fig. 3 as checks: the driver above
//! `analysis::relaxation` (which measures the approach to saturation) that
//! `waves-fig3` and the reproduction matrix share; and the figure's panels.

use crate::analysis::grading::{Claim, Estimate};
use crate::analysis::relaxation::{Saturation, SATURATION_MARGIN};
use crate::error::Result;
use crate::plot::{line_chart, mean_se_lines, Line, PALETTE};
use crate::run::{Check, Output};
use plotters::chart::SeriesLabelPosition;

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

/// `fig3.csv` and the panels of PH95 Fig. 3 at the sample times `t`: (a) the
/// contrast's mean and standard error over runs with its random-start value
/// `c0_theory`, (b) the energy loss's; `title_tail` ends both titles.
pub fn draw_fig3(
    out: &Output,
    t: &[f64],
    (cm, ce): (&[f64], &[f64]),
    (em, ee): (&[f64], &[f64]),
    c0_theory: f64,
    title_tail: &str,
) -> Result<()> {
    let header = [
        "t",
        "contrast_mean",
        "contrast_sem",
        "energy_loss_mean",
        "energy_loss_sem",
    ];
    out.write_columns("fig3.csv", &header, &[t, cm, ce, em, ee])?;
    let mut a = mean_se_lines("mean over runs", t, cm, ce, PALETTE[0]);
    let last = *t.last().expect("samples");
    let flat = vec![(0.0, c0_theory), (last, c0_theory)];
    a.push(Line::new("random-start value", flat, PALETTE[5]));
    line_chart(
        &out.path("fig3a.png"),
        &format!("PH95 Fig. 3a: contrast C(t), {title_tail}"),
        "time t (steps)",
        "density contrast C (PH95 eq. 1)",
        &a,
        false,
        SeriesLabelPosition::UpperRight,
    )?;
    line_chart(
        &out.path("fig3b.png"),
        &format!("PH95 Fig. 3b: energy loss E(0)-E(t), {title_tail}"),
        "time t (steps)",
        "E(0) - E(t) (moving particles lost)",
        &mean_se_lines("mean over runs", t, em, ee, PALETTE[1]),
        false,
        SeriesLabelPosition::UpperRight,
    )
}
