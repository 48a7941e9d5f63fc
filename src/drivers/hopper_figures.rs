//! The hopper figures of BB90 from their runs: Fig. 2 (filling and
//! emptying; [`Fig2Runs`](crate::drivers::hopper_figures::Fig2Runs)) and Fig. 3 (the outflow and its spectrum;
//! [`fig3_readings`](crate::drivers::hopper_figures::fig3_readings), [`draw_fig3`](crate::drivers::hopper_figures::draw_fig3)). Per figure its metrics, the checks of
//! its claims with their thresholds and margins (fixed before
//! measuring; HOPPER_READINGS.md lists the claims) and its charts, for every
//! case (reading of "aligned", MODEL.md B4, B6). The runs themselves are
//! [`crate::hopper::experiment`]'s; used by `hopper-fig2` and `hopper-fig3`.

use super::margins::ALPHA_MARGIN;
use crate::analysis::fit::LinearFit;
use crate::analysis::grading::{Claim, Estimate, Kind};
use crate::analysis::spectrum::frequency;
use crate::error::Result;
use crate::hopper::experiment::{
    analyse_outflow, core_rows, lag_correlation, open_window_rates, run_cases, Case, Measure, Plan,
    Record, FIG2_MEASURES, WINDOW_FULL, WINDOW_SKIP,
};
use crate::hopper::picture::{draw_snapshots, outflow_charts, spectrum_chart, Panel};
use crate::hopper::{Geometry, Hopper, HopperParams};
use crate::plot::{line_chart, points, Line, PALETTE};
use crate::run::{mean_sem_at, mean_sem_by, metrics_of, stat_metrics, Check, Output, Tier};
use plotters::chart::SeriesLabelPosition;
use std::collections::BTreeMap;

/// BB90 Fig. 2a, central core: (activity at centre + 1e-3)/(next to walls
/// + 1e-3) >= this.
pub const CORE_RATIO: f64 = 4.0;
/// BB90 Fig. 2a, core of constant width: FWHM at 40% minus at 20% of the
/// wedge height within this many lattice spacings of 0 (the wedge itself
/// widens by ~29 spacings between those rows at 174 x 129, ~16 at the quick
/// tier).
pub const CORE_WIDTH_MARGIN: f64 = 3.0;
/// BB90 Fig. 2a, the upper free surface takes a V shape: slope (tan of the
/// surface angle about the outlet column) above this, half emptied.
pub const SURFACE_SLOPE: f64 = 0.2;
/// BB90 Figs. 2b-f, orientational order: fraction of equal neighbour
/// orientations above this (1/3 random).
pub const ORDER: f64 = 0.45;
/// BB90 Figs. 2c-f, order on the container scale: correlation length above
/// this many steps.
pub const CONTAINER_SCALE: f64 = 8.0;
/// BB90 Figs. 2c-f, flowing grains orient vertically: vertical fraction of
/// moving grains above this (1/3 random).
pub const VERTICAL: f64 = 0.45;
/// BB90 Fig. 2c, stagnant sides dense ("0% holes"): occupancy above this.
pub const DENSE_SIDES: f64 = 0.9;
/// BB90 abstract, defects in the body: enclosed vacancies per 1000 grains
/// above this.
pub const DEFECTS: f64 = 1.0;
/// BB90 Fig. 2a, beta = 0 structureless: order within this of 1/3.
pub const STRUCTURELESS_MARGIN: f64 = 0.03;

/// The Fig. 2 measure `name` of [`FIG2_MEASURES`] (a name of that list).
fn fig2_measure(name: &str) -> Measure {
    FIG2_MEASURES
        .iter()
        .find(|(m, _)| *m == name)
        .expect("a measure of FIG2_MEASURES")
        .1
}

/// The runs of BB90 Fig. 2: per case its records in seed order, with the
/// hopper's geometry and its two core rows ([`core_rows`]).
pub struct Fig2Runs {
    /// The cases (readings), a beta = 0 case first.
    pub cases: Vec<Case>,
    /// The records of each case, in seed order.
    pub recs: Vec<Vec<Record>>,
    /// The geometry of the hopper.
    pub geom: Geometry,
    /// The rows of the core widths (20% and 40% of the wedge).
    pub rows: [usize; 2],
}

impl Fig2Runs {
    /// Run every case of `base` once per seed following `plan` on `threads`
    /// threads ([`run_cases`]).
    pub fn run(
        base: HopperParams,
        cases: Vec<Case>,
        seeds: &[u64],
        plan: &Plan,
        threads: usize,
    ) -> Result<Self> {
        let recs = run_cases(base, &cases, seeds, plan, threads)?;
        let probe = Hopper::new(base, 0)?;
        Ok(Fig2Runs {
            cases,
            recs,
            geom: probe.geometry().clone(),
            rows: core_rows(&probe),
        })
    }

    /// The per-run values of the measure `name` over `runs`.
    fn per_run(&self, runs: &[Record], name: &str) -> Vec<f64> {
        let f = fig2_measure(name);
        runs.iter().map(|r| f(r, &self.geom, &self.rows)).collect()
    }

    /// Mean over `runs` of the measure `name`.
    fn mean(&self, runs: &[Record], name: &str) -> f64 {
        let f = fig2_measure(name);
        mean_sem_by(runs, |r| f(r, &self.geom, &self.rows)).0
    }

    /// Every measure of [`FIG2_MEASURES`] per case, mean and standard error
    /// over runs, named `<case>_<measure>` (and `_err`).
    pub fn metrics(&self) -> BTreeMap<String, f64> {
        let mut m = BTreeMap::new();
        for (case, rs) in self.cases.iter().zip(&self.recs) {
            for (name, f) in FIG2_MEASURES {
                let stat = mean_sem_by(rs, |r| f(r, &self.geom, &self.rows));
                m.insert(format!("{}_{name}", case.key), stat);
            }
        }
        stat_metrics(m.iter().map(|(k, v)| (k, *v)))
    }

    /// Site updates computed over every run.
    pub fn site_updates(&self) -> f64 {
        self.recs
            .iter()
            .map(|rs| rs.iter().map(|r| r.site_updates).sum::<f64>())
            .sum()
    }

    /// The snapshots of BB90 Fig. 2 (panels a-f, [`Panel::fig2`]) of run 0,
    /// one picture `hopper-fig2-<reading>.png` per beta = 1 case, at
    /// `snaps` iterations after opening, `scale` pixels per site.
    pub fn draw_snapshots(
        &self,
        out: &Output,
        snaps: &[u64],
        scale: f64,
        tier: Tier,
    ) -> Result<()> {
        // panel (a) is the first beta = 0 case; the pictures show each other
        // case beside it (a case list without one draws none, and says so)
        let Some(zero) = self.cases.iter().position(|c| c.beta == 0.0) else {
            println!(
                "no beta = 0 case among --cases: the snapshot pictures, whose panel (a) is beta = 0, are not drawn"
            );
            return Ok(());
        };
        let others = self.cases.iter().zip(&self.recs).enumerate();
        for (_, (case, rs)) in others.filter(|(i, _)| *i != zero) {
            // the three readings of "aligned" are named by the reading
            let name = match case.key {
                "beta1_along" | "beta1_same" | "beta1_bond" => case.aligned.name(),
                key => key,
            };
            let panels = Panel::fig2(&self.recs[zero][0], &rs[0], case.beta, snaps);
            draw_snapshots(
                &out.path(&format!("hopper-fig2-{name}.png")),
                &format!(
                    "BB90 Fig. 2: hopper, aligned = {name} (iterations after opening; tier {})",
                    tier.name()
                ),
                &self.geom,
                &panels,
                3,
                scale,
            )?;
        }
        Ok(())
    }

    /// The time-averaged activity across the hopper at the core rows (run
    /// 0) and the orientational correlation g(r), r = 1..=`rmax`, half
    /// emptied (mean over runs): `activity_profiles.csv`, `g_of_r.csv` and
    /// their charts.
    pub fn draw_profiles(&self, out: &Output, rmax: usize) -> Result<()> {
        let geom = &self.geom;
        let (mut lines, mut rows_csv, mut glines, mut g_csv) = (vec![], vec![], vec![], vec![]);
        for (c, (case, rs)) in self.cases.iter().zip(&self.recs).enumerate() {
            let cap = case.caption;
            for (k, &y) in self.rows.iter().enumerate() {
                let p = rs[0].activity.profile(geom, y);
                let centre = geom.centre_column as f64;
                let pts = p.iter().map(|&(x, a)| (x as f64 - centre, a)).collect();
                lines.push(Line::new(
                    &format!("{cap}, row {y}"),
                    pts,
                    PALETTE[(2 * c + k) % PALETTE.len()],
                ));
                for &(x, a) in &p {
                    let occupancy = rs[0].activity.occupancy(x, y);
                    rows_csv.push(vec![c as f64, y as f64, x as f64, a, occupancy]);
                }
            }
            let gh: Vec<&[f64]> = rs.iter().map(|r| &r.g_half[..]).collect();
            let r: Vec<f64> = (1..=rmax).map(|d| d as f64).collect();
            let mean = mean_sem_at(&gh, rmax).0;
            glines.push(Line::new(cap, points(&r, &mean), PALETTE[c % PALETTE.len()]).markers());
            g_csv.extend(r.iter().zip(&mean).map(|(&d, &v)| vec![c as f64, d, v]));
        }
        let header = ["case", "row", "column", "activity", "occupancy"];
        out.write_csv("activity_profiles.csv", &header, &rows_csv)?;
        line_chart(
            &out.path("hopper-fig2-activity.png"),
            "BB90 Fig. 2: time-averaged activity across the hopper (run 0)",
            "column - outlet column",
            "fraction of iterations with a moving grain",
            &lines,
            false,
            SeriesLabelPosition::UpperRight,
        )?;
        glines.push(Line::new(
            "random: 1/3",
            vec![(1.0, 1.0 / 3.0), (rmax as f64, 1.0 / 3.0)],
            PALETTE[5],
        ));
        out.write_csv("g_of_r.csv", &["case", "r", "g_half_empty"], &g_csv)?;
        line_chart(
            &out.path("hopper-fig2-gr.png"),
            "BB90 Fig. 2: orientational correlation g(r), half emptied",
            "distance r (lattice steps along an axis)",
            "fraction of pairs with equal orientation",
            &glines,
            false,
            SeriesLabelPosition::UpperRight,
        )
    }

    /// The qualitative claims of BB90 Fig. 2 (no published numbers), every
    /// claim for every case it applies to, in case order.
    pub fn checks(&self) -> Vec<Check> {
        let mut checks = Vec::new();
        for (case, rs) in self.cases.iter().zip(&self.recs) {
            checks.extend(self.case_checks(case, rs));
        }
        checks
    }

    /// The checks of BB90 Fig. 2 for one case with records `rs`.
    fn case_checks(&self, case: &Case, rs: &[Record]) -> Vec<Check> {
        let (k, cap, n) = (case.key, case.caption, rs.len());
        let e = |name: &str| Estimate::of(&self.per_run(rs, name));
        let mut checks = Vec::new();
        checks.push(Check::test(
            &format!("{k}_empties"),
            Kind::Published,
            "BB90 Figs. 2-3 (the hopper flows until empty)",
            self.mean(rs, "remaining_grains"),
            n,
            rs.iter().all(|r| r.emptied),
            &format!("{cap}: every run empties (statistic: grains left, mean over runs)"),
        ));
        let ratio =
            (self.mean(rs, "activity_centre") + 1e-3) / (self.mean(rs, "activity_wall") + 1e-3);
        checks.push(Check::test(&format!("{k}_central_core"), Kind::Published,
            "BB90 Fig. 2a, Fig. 1 feature (3) (flow in a central region, stagnant sides)",
            ratio, n, ratio >= CORE_RATIO,
            &format!("{cap}: (activity at centre + 1e-3)/(activity next to the walls + 1e-3) >= {CORE_RATIO} at the lower core row, of the means over runs")));
        // the published claims: (name, source, statistic, claim, what is measured)
        let above = |threshold| Claim::Above { threshold };
        let published = |rows: Vec<(&'static str, &'static str, Estimate, Claim, String)>| {
            rows.into_iter()
                .map(|(name, source, stat, claim, what)| {
                    let (name, what) = (format!("{k}_{name}"), format!("{cap}: {what}"));
                    Check::published(&name, source, stat, claim, &what)
                })
                .collect::<Vec<_>>()
        };
        #[rustfmt::skip]
        checks.extend(published(vec![
            ("core_constant_width", "BB90 Fig. 2a (a core that approaches a constant width)",
                e("core_width_change"), Claim::Within { target: 0.0, margin: CORE_WIDTH_MARGIN },
                format!("core FWHM at 40% minus at 20% of the wedge height, within {CORE_WIDTH_MARGIN} lattice spacings of 0")),
            ("core_lowered_density", "BB90 Fig. 2a (density uniformly lowered inside the core)",
                e("occupancy_core").minus(e("occupancy_sides")), Claim::Below { threshold: 0.0 },
                "occupancy core - sides < 0".into()),
            ("surface_v_shape", "BB90 Fig. 2a and abstract (the upper surface takes the shape of physical flows)",
                e("surface_slope_half_empty"), above(SURFACE_SLOPE),
                format!("surface slope about the outlet column, half emptied, > {SURFACE_SLOPE}")),
        ]));
        if case.beta == 0.0 {
            #[rustfmt::skip]
            checks.extend(published(vec![
                ("structureless", "BB90 Fig. 2a (structureless flow)",
                    e("order_half_empty"), Claim::Within { target: 1.0 / 3.0, margin: STRUCTURELESS_MARGIN },
                    format!("order parameter within {STRUCTURELESS_MARGIN} of 1/3 (random)")),
            ]));
            return checks;
        }
        #[rustfmt::skip]
        checks.extend(published(vec![
            ("order_forms_while_filling", "BB90 Fig. 2b (the fill has orientational order)",
                e("order_filled"), above(ORDER), format!("order parameter after filling > {ORDER} (1/3 random)")),
            ("order", "BB90 abstract, Figs. 2c-f (alignment of the particles)",
                e("order_half_empty"), above(ORDER), format!("order parameter half emptied > {ORDER} (1/3 random)")),
            ("container_scale_order", "BB90 Figs. 2c-f (orientations correlated over the container's dimensions)",
                e("corr_length_half_empty"), above(CONTAINER_SCALE),
                format!("correlation length half emptied > {CONTAINER_SCALE} steps (capped at 16)")),
            ("vertical_core", "BB90 Figs. 2c-f with Fig. 1 feature (3) (grains in the flowing region orient vertically)",
                e("vertical_fraction_moving"), above(VERTICAL),
                format!("fraction of moving grains with vertical orientation > {VERTICAL} (1/3 random)")),
            ("dense_sides", "BB90 Fig. 2c (the shaded region has 0% holes)",
                e("occupancy_sides"), above(DENSE_SIDES), format!("occupancy outside the core > {DENSE_SIDES}")),
            ("defects", "BB90 abstract (defects form in the body of the material)",
                e("vacancies_per_1000_half_empty"), above(DEFECTS),
                format!("enclosed vacancies per 1000 grains half emptied > {DEFECTS}")),
        ]));
        checks
    }
}

/// Iterations recorded after opening (BB90 Fig. 3).
pub const FIG3_RECORD: u64 = 6144;

/// Margin Delta of "no monotonic variation" (BB90 Fig. 3): the mean outflow
/// rate of the second half within 10% of the first half's (relative to the
/// mean rate), fixed 2026-12-01.
pub const TREND_MARGIN: f64 = 0.1;

/// Margin Delta of "white" over the whole band (BB90 Fig. 3; fixed
/// before measuring): the lag-1 autocorrelation of the outflow within
/// 0.1 of 0.
pub const LAG1_MARGIN: f64 = 0.1;

/// Margin Delta of "qualitatively similar results with orientation off"
/// (BB90 Fig. 3 caption; fixed before measuring): the stationary
/// rate with orientation on over the rate with it off, within 0.2 of 1.
pub const RATE_RATIO_MARGIN: f64 = 0.2;

/// The mean outflow rate of one run in the stationary window of BB90 Fig. 3
/// ([`Record::window`] with [`WINDOW_SKIP`] and [`WINDOW_FULL`]).
pub fn stationary_rate(r: &Record) -> f64 {
    let w = r.window(WINDOW_SKIP, WINDOW_FULL);
    w.iter().sum::<f64>() / w.len().max(1) as f64
}

/// What BB90 Fig. 3 reads from the runs of every case.
pub struct Fig3Readings {
    /// The metrics, named `<case>_<name>`.
    pub metrics: BTreeMap<String, f64>,
    /// The checks of every case, in case order.
    pub checks: Vec<Check>,
    /// Per case the mean power spectrum P(j), j = 0..m, and its log-log fit
    /// for f <= 1/8.
    pub spectra: Vec<(Vec<f64>, LinearFit)>,
    /// Site updates computed over every run.
    pub site_updates: f64,
}

/// The delete-one jackknife SE over runs of the slope of the averaged
/// outflow spectrum ([`analyse_outflow`] with `m` frequencies): the
/// acceptance estimator of BB90 Fig. 3's flat spectrum, the rule of the
/// pipe's spectra (an averaged spectrum, resampled over runs).
pub fn slope_jackknife_se(records: &[Record], m: usize) -> Result<f64> {
    crate::analysis::resample::jackknife_se(records.len(), |i| {
        let rest: Vec<Record> = records
            .iter()
            .enumerate()
            .filter(|&(j, _)| j != i)
            .map(|(_, r)| r.clone())
            .collect();
        Ok(analyse_outflow(&rest, m)?.fit.slope)
    })
}

/// The cases of hopper figure `binary`'s `--cases` (`cases`, keys of
/// [`Case::ALL`]); a `--shard` in `c` is refused, as the figure keeps all its
/// runs in one process.
pub fn cases_of(c: &crate::cli::Common, cases: &str, binary: &str) -> Result<Vec<Case>> {
    let cases = Case::parse_list(cases)?;
    c.reject_shard(binary)?;
    Ok(cases)
}

/// BB90 Fig. 3's set-up at `tier`: the hopper (quick: small; standard:
/// 174 x 129; paper and acceptance: 270 x 200, whose stationary window
/// covers the 6144 recorded iterations), the plan and the spectrum's m.
pub fn fig3_setup(tier: Tier) -> (HopperParams, Plan, usize) {
    use crate::hopper::{GeometryParams, RainParams};
    let tall = HopperParams {
        geometry: GeometryParams {
            width: 270,
            height: 200,
            outlet_width: 7,
            channel_height: 4,
        },
        rain: RainParams {
            sigma: 18.0,
            ..Default::default()
        },
        ..Default::default()
    };
    let base = tier.pick(HopperParams::quick(), HopperParams::default(), tall);
    let mut plan = Plan::new(tier.pick(6_000, 12_000, 20_000), vec![]);
    plan.fill_fraction = tier.pick(0.7, 0.85, 0.85);
    plan.min_record = FIG3_RECORD;
    (base, plan, tier.pick(64, 128, 256))
}

/// The readings of BB90 Fig. 3 from the records `recs` of each of `cases`
/// ([`analyse_outflow`] with `m` frequencies): per case its outflow
/// metrics and the checks of no trend, a white spectrum (slope and lag-1
/// correlation), emptying and, for beta = 1, a rate like that of the first
/// beta = 0 case. At the acceptance tier the slope's SE is the jackknife
/// over runs ([`slope_jackknife_se`]) and its margin that of
/// [`crate::drivers::acceptance::MARGINS`]; at the other tiers the fit's
/// own error and [`ALPHA_MARGIN`].
pub fn fig3_readings(
    cases: &[Case],
    recs: &[Vec<Record>],
    m: usize,
    tier: Tier,
) -> Result<Fig3Readings> {
    let beta0_rate = cases
        .iter()
        .position(|c| c.beta == 0.0)
        .map(|i| Estimate::of(&recs[i].iter().map(stationary_rate).collect::<Vec<_>>()));
    let mut metrics = BTreeMap::new();
    let mut checks = Vec::new();
    let mut spectra = Vec::new();
    let mut site_updates = 0.0;
    for (case, rs) in cases.iter().zip(recs) {
        let (key, cap) = (case.key, case.caption);
        site_updates += rs.iter().map(|r| r.site_updates).sum::<f64>();
        let a = analyse_outflow(rs, m)?;
        let open30 = open_window_rates(rs, WINDOW_FULL);
        let acceptance = crate::drivers::acceptance::margin("hopper-fig3", "white_spectrum")
            .filter(|_| tier.is_acceptance());
        // The slope's SE as graded (and as the chart's legend shows it).
        let fit = match acceptance {
            Some(_) => LinearFit {
                slope_err: slope_jackknife_se(rs, m)?,
                ..a.fit
            },
            None => a.fit,
        };
        let n = rs.len() as f64;
        let (emptied, _) = mean_sem_by(rs, |r| r.empty_iterations as f64);
        let initial = rs.iter().map(|r| r.initial as f64).sum::<f64>() / n;
        let more = [
            ("empty_iterations", emptied),
            ("mean_rate_open_to_30", open30.0),
            ("sd_rate_open_to_30", open30.1),
            ("initial_grains", initial),
        ];
        let named = a.named().into_iter().chain(more);
        metrics.extend(metrics_of(
            named.map(|(name, v)| (format!("{key}_{name}"), v)),
        ));
        let runs = rs.len();
        let r = &a.rates;
        checks.push(Check::published(
            &format!("{key}_no_trend"),
            "BB90 Fig. 3 (no monotonic variation of the flow rate)",
            Estimate::new(
                (r.second - r.first) / r.mean,
                r.first_se.hypot(r.second_se) / r.mean,
                runs,
            ),
            Claim::Within {
                target: 0.0,
                margin: TREND_MARGIN,
            },
            &format!(
                "(second - first half mean rate) / mean rate within Delta = {TREND_MARGIN}; {cap}"
            ),
        ));
        checks.push(match acceptance {
            Some(mg) => Check::published(
                &format!("{key}_white_spectrum"),
                mg.source,
                Estimate::new(fit.slope, fit.slope_err, runs),
                mg.claim(),
                &format!("log-log slope of the averaged spectrum for f <= 1/8, jackknife SE over runs; {}; {cap}", mg.note()),
            ),
            None => Check::published(
                &format!("{key}_white_spectrum"),
                "BB90 Fig. 3 (a flat power spectrum of the outflow)",
                Estimate::new(fit.slope, fit.slope_err, runs),
                Claim::Within {
                    target: 0.0,
                    margin: ALPHA_MARGIN,
                },
                &format!("log-log slope of the mean spectrum for f <= 1/8 within Delta = {ALPHA_MARGIN} of 0 (the pipe's white-noise margin); {cap}"),
            ),
        });
        checks.push(Check::test(
            &format!("{key}_empties"),
            Kind::Published,
            "BB90 Fig. 3 (the hopper empties)",
            rs.iter().map(|r| r.remaining as f64).sum::<f64>(),
            runs,
            rs.iter().all(|r| r.emptied),
            &format!("the hopper empties without jamming in every run (statistic: grains left, all runs); {cap}"),
        ));
        let lag1: Vec<f64> = rs
            .iter()
            .map(|r| lag_correlation(r.window(WINDOW_SKIP, WINDOW_FULL), 1))
            .collect();
        checks.push(Check::published(
            &format!("{key}_white_lag1"),
            "BB90 Fig. 3 (a flat power spectrum: white noise over the whole band)",
            Estimate::of(&lag1),
            Claim::Within {
                target: 0.0,
                margin: LAG1_MARGIN,
            },
            &format!("lag-1 autocorrelation of the outflow in the stationary window (per run) within Delta = {LAG1_MARGIN} of 0 (white noise: 0; a period-2 alternation: negative); {cap}"),
        ));
        if let (Some(b0), true) = (beta0_rate, case.beta != 0.0) {
            let on = Estimate::of(&rs.iter().map(stationary_rate).collect::<Vec<_>>());
            let ratio = on.mean / b0.mean;
            let se = ratio * ((on.se / on.mean).powi(2) + (b0.se / b0.mean).powi(2)).sqrt();
            checks.push(Check::published(
                &format!("{key}_rate_like_orientation_off"),
                "BB90 Fig. 3 caption (qualitatively similar results with orientation off)",
                Estimate::new(ratio, se, on.n.min(b0.n)),
                Claim::Within {
                    target: 1.0,
                    margin: RATE_RATIO_MARGIN,
                },
                &format!("stationary outflow rate over that of beta = 0 within Delta = {RATE_RATIO_MARGIN} of 1; {cap}"),
            ));
        }
        spectra.push((a.spectrum, fit));
    }
    Ok(Fig3Readings {
        metrics,
        checks,
        spectra,
        site_updates,
    })
}

/// The charts of BB90 Fig. 3: (a) and (b), the outflow of run 0 of each
/// case over the first [`FIG3_RECORD`] iterations (`outflow_run0.csv`,
/// `hopper-fig3a-<case>.png`, `hopper-fig3b-<case>.png`), and the mean power
/// spectra of `readings` (`spectra.csv`, `hopper-fig3-spectrum.png`).
pub fn draw_fig3(
    out: &Output,
    cases: &[Case],
    recs: &[Vec<Record>],
    readings: &Fig3Readings,
) -> Result<()> {
    let record = FIG3_RECORD as usize;
    let t: Vec<f64> = (0..record).map(|t| t as f64).collect();
    let q0: Vec<&[f64]> = recs.iter().map(|rs| &rs[0].outflow[..record]).collect();
    let mut header = vec!["iteration"];
    header.extend(cases.iter().map(|c| c.key));
    let mut columns: Vec<&[f64]> = vec![&t[..]];
    columns.extend(q0.iter().copied());
    out.write_columns("outflow_run0.csv", &header, &columns)?;
    let spec_csv: Vec<Vec<f64>> = (readings.spectra.iter().enumerate())
        .flat_map(|(c, (p, _))| {
            let m = p.len();
            (0..m).map(move |j| vec![c as f64, frequency(j, m), p[j]])
        })
        .collect();
    out.write_csv("spectra.csv", &["case", "frequency", "power"], &spec_csv)?;
    for (case, q) in cases.iter().zip(&q0) {
        let path = |fig: &str| out.path(&format!("hopper-fig3{fig}-{}.png", case.key));
        outflow_charts(&path("a"), &path("b"), case.caption, q)?;
    }
    let spectra: Vec<_> = (cases.iter().zip(&readings.spectra))
        .map(|(c, (p, f))| (c.caption, &p[..], *f))
        .collect();
    spectrum_chart(&out.path("hopper-fig3-spectrum.png"), &spectra)
}
