//! PH95 Fig. 11, the open pipe (MODEL.md A7) of `waves-fig11`: the
//! ensembles of correlation runs at each injection rate, (a) the space-time
//! plot of run 0, (b) the two-point correlation C(R, T) (MODEL.md A9) with
//! its peak T_c and speed v = R bin / T_c, and the metrics and checks of the
//! published rate I = 0.5 (clogging, the speed, the onset of the rise) and
//! of the stationary rate [`I_CORR`](crate::drivers::fig11::I_CORR). The set-ups, the per-run record and
//! the graded claims shared with the reproduction matrix are
//! [`crate::drivers::open_pipe`]'s.

use super::open_pipe::{
    corr_onset, corr_run, corr_speed, fig11_pipe, fig11_speed_check, flows_check, CorrRun,
    CorrSpeed, FIG11_CORR, FIG11_INJECT,
};
use crate::analysis::grading::Kind;
use crate::cli::Common;
use crate::ensemble::Outcome;
use crate::error::Result;
use crate::pipe::open::{open_run, peak_index};
use crate::pipe::{Engine, Rules};
use crate::plot::{line_chart, png, Line, SpaceTime, PALETTE};
use crate::run::{mean_sem, Check, Output};
use plotters::chart::SeriesLabelPosition;
use serde_json::json;
use std::collections::BTreeMap;

/// The injection rate at which PH95 Fig. 11b's correlation is measured
/// (stationary at this set-up, below I_c; the published I = 0.5 clogs with
/// the default reading, MODEL.md A4).
pub const I_CORR: f64 = 0.3;

/// Steps over which the rise of C(-R, T) is taken for its onset
/// (exploratory metric).
pub const ONSET_WINDOW: u64 = 50;

/// The correlation runs of PH95 Fig. 11 ([`corr_run`], sampled by
/// [`FIG11_CORR`]) at each injection rate of `rates`, `runs` runs of `steps`
/// steps per rate on the ensemble runner of `common` (figure
/// `waves-fig11`); `None` when this process ran one shard only (a line per
/// rate says so).
pub fn corr_ensembles(
    common: &Common,
    rates: &[f64],
    rules: Rules,
    engine: Engine,
    steps: u64,
    runs: usize,
) -> Result<Option<Vec<Vec<CorrRun>>>> {
    let s = FIG11_CORR;
    let mut results = Vec::new();
    for &inject in rates {
        let key = json!({"open-correlation": fig11_pipe(inject), "steps": steps, "every": s.every, "skip": s.skip, "t_max": s.t_max, "r": s.r, "rules": rules.to_string(), "engine": engine});
        let ens = common.ensemble("waves-fig11", &key, runs)?;
        let out = ens.run(steps, |_, seed, tick| {
            corr_run(fig11_pipe(inject), rules, engine, seed, steps, &s, tick)
        })?;
        match out {
            Outcome::Complete(v) => results.push(v),
            Outcome::ShardDone { shard, dir, .. } => {
                println!("waves-fig11 I = {inject}: shard {shard} done in {}; merge, then rerun without --shard", dir.display());
            }
        }
    }
    Ok((results.len() == rates.len()).then_some(results))
}

/// PH95 Fig. 11a at injection rate `inject`: the space-time plot of n_i
/// every 80 steps of one open run with `seed` (`waves-fig11a_I<inject>.png`),
/// with the step at which it clogged, if it did.
pub fn draw_space_time(
    out: &Output,
    inject: f64,
    rules: Rules,
    engine: Engine,
    seed: u64,
    steps: u64,
) -> Result<()> {
    let rec = open_run(
        fig11_pipe(inject),
        rules,
        engine,
        seed,
        steps,
        80,
        true,
        &|_| {},
    )?;
    let hi = rec.n.iter().flatten().cloned().fold(1.0, f64::max);
    let st = SpaceTime {
        values: &rec.n,
        white: 0.0,
        black: hi,
        t0: 80.0,
        dt: 80.0,
        rows_per_bin: 10.0,
        time_right_to_left: false,
        bottom_at_bottom: true,
    };
    let stop = match &rec.stopped {
        Some((s, _)) => format!(", clogged at step {s}"),
        None => String::new(),
    };
    let path = out.path(&format!("waves-fig11a_I{inject}.png"));
    png(&path, (1100, 650), |root| {
        st.draw(
            root,
            &format!("PH95 Fig. 11a: open pipe L = 1000, W = 5, I = {inject}, g = 0.2, time left to right, n_i white 0 black {hi:.0}{stop}"),
        )
    })
}

/// PH95 Fig. 11b: C(+R, T) and C(-R, T) of `cs` (the open pipe at injection
/// rate `inject`) as `<stem>.csv` and `<stem>.png`, with the peak and its
/// speed.
pub fn draw_correlation(out: &Output, stem: &str, inject: f64, cs: &CorrSpeed) -> Result<()> {
    let (r, every, t_max) = (FIG11_CORR.r, FIG11_CORR.every, FIG11_CORR.t_max);
    let (up, down, t_c_samples, t_c) = (&cs.up, &cs.down, cs.t_c_samples, cs.t_c);
    let (main, dir) = if cs.upward {
        (up, "up")
    } else {
        (down, "down")
    };
    let (v_corr, v_corr_err) = mean_sem(&cs.speeds);
    let rows: Vec<Vec<f64>> = (0..=t_max)
        .map(|t| vec![(t as u64 * every) as f64, up[t], down[t]])
        .collect();
    out.write_csv(&format!("{stem}.csv"), &["T", "C_up", "C_down"], &rows)?;
    let pts = |c: &[f64]| -> Vec<(f64, f64)> {
        c.iter()
            .enumerate()
            .map(|(t, &y)| ((t as u64 * every) as f64, y))
            .collect()
    };
    // the published peak T_c = 880 (v = 0.34), measured at I = 0.5
    let published: Vec<Line> = (inject == 0.5)
        .then(|| {
            let ys = up
                .iter()
                .chain(down.iter())
                .copied()
                .filter(|y| y.is_finite());
            let (lo, hi) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            });
            Line::new(
                "published T_c = 880 (v = 0.34)",
                vec![(880.0, lo), (880.0, hi)],
                plotters::style::RGBColor(0, 0, 0),
            )
        })
        .into_iter()
        .collect();
    line_chart(
        &out.path(&format!("{stem}.png")),
        &format!(
            "PH95 Fig. 11b: C(R = {r} bins, T), open pipe I = {inject}, g = 0.2, mean of {} runs",
            cs.valid
        ),
        "T (steps)",
        "C(R, T) (fluctuations, per bin pair and sample)",
        &[
            published,
            vec![
                Line::new(
                    &format!("R = +{r}: bin i+R above i (moving up)"),
                    pts(up),
                    PALETTE[0],
                ),
                Line::new(
                    &format!("R = -{r}: bin i+R below i (moving down)"),
                    pts(down),
                    PALETTE[1],
                ),
                Line::new(
                    &format!("peak T_c = {t_c} ({dir}), v = {v_corr:.3} +- {v_corr_err:.3}"),
                    vec![(t_c, main[t_c_samples])],
                    PALETTE[2],
                )
                .markers(),
            ],
        ]
        .concat(),
        false,
        SeriesLabelPosition::UpperRight,
    )
}

/// What PH95 Fig. 11 reads from its runs.
pub struct Fig11Readings {
    /// The metrics of `summary.json`.
    pub metrics: BTreeMap<String, f64>,
    /// The checks: the mass bookkeeping, the published rate's (when run)
    /// and the correlation peak at [`I_CORR`].
    pub checks: Vec<Check>,
    /// The correlation and its speed at [`I_CORR`].
    pub corr: CorrSpeed,
    /// The same at the published rate, when it ran.
    pub paper: Option<CorrSpeed>,
}

/// The readings of PH95 Fig. 11 from the runs `paper` at the published rate
/// I = 0.5 (`None`: not run) and `corr` at [`I_CORR`], each of `steps`
/// steps: the speed from C(R, T) at both rates, the clogging and the
/// exploratory onset of C(-R, T) at I = 0.5, and the checks.
pub fn fig11_readings(paper: Option<&[CorrRun]>, corr: &[CorrRun], steps: u64) -> Fig11Readings {
    let (every, t_max) = (FIG11_CORR.every, FIG11_CORR.t_max);
    let bin = fig11_pipe(FIG11_INJECT).bin;
    let cs = corr_speed(corr, &FIG11_CORR, bin);
    let (v_corr, v_corr_err) = mean_sem(&cs.speeds);
    let book: u64 = (paper.unwrap_or_default().iter())
        .chain(corr.iter())
        .map(|r| r.bookkeeping_errors)
        .sum();
    let mut metrics = BTreeMap::new();
    metrics.insert("t_c".into(), cs.t_c);
    metrics.insert("v_corr".into(), v_corr);
    metrics.insert("v_corr_err".into(), v_corr_err);
    metrics.insert("direction_up".into(), if cs.upward { 1.0 } else { 0.0 });
    let t_c_of = |c: &[f64]| (peak_index(c, 1).unwrap_or(0) as u64 * every) as f64;
    metrics.insert("t_c_up".into(), t_c_of(&cs.up));
    metrics.insert("t_c_down".into(), t_c_of(&cs.down));
    metrics.insert("inject_correlation".into(), I_CORR);
    metrics.insert("valid_runs_correlation".into(), cs.valid as f64);
    let mut checks = vec![Check::identity(
        "bookkeeping_exact",
        book as f64,
        book == 0,
        "MODEL.md A7: injected - out_bottom - out_top = N(t) - N(0) at every sample of every run",
    )];
    let paper_speed = paper.map(|paper| {
        // clogging at the published rate
        let clogged: Vec<f64> = paper
            .iter()
            .filter_map(|r| r.stopped_at.map(|s| s as f64))
            .collect();
        let (clog_step, clog_step_err) = mean_sem(&clogged);
        metrics.insert(
            "clogged_fraction_I0.5".into(),
            clogged.len() as f64 / paper.len() as f64,
        );
        metrics.insert("clog_step_I0.5".into(), clog_step);
        metrics.insert("clog_step_I0.5_err".into(), clog_step_err);
        checks.push(flows_check(paper, steps));
        let ps = corr_speed(paper, &FIG11_CORR, bin);
        metrics.insert("valid_runs_I0.5".into(), ps.valid as f64);
        checks.push(fig11_speed_check(&ps, paper.len()));
        // exploratory, not a check: the onset of C(-R, T)'s steepest rise
        // (pre-registered, EXPERIMENTS.md "Fig. 11: an onset
        // statistic")
        let on = corr_onset(paper, &ps, &FIG11_CORR, bin, ONSET_WINDOW);
        let (t_on, t_on_err) = mean_sem(&on.t_on);
        let (v_on, v_on_err) = mean_sem(&on.v_on);
        metrics.insert("t_onset_down_I0.5".into(), t_on);
        metrics.insert("t_onset_down_I0.5_err".into(), t_on_err);
        metrics.insert("v_onset_down_I0.5".into(), v_on);
        metrics.insert("v_onset_down_I0.5_err".into(), v_on_err);
        metrics.insert("onset_runs_I0.5".into(), on.v_on.len() as f64);
        metrics.insert(
            "no_onset_runs_I0.5".into(),
            (ps.valid - on.v_on.len()) as f64,
        );
        if let Some(t) = on.t_on_mean_curve {
            metrics.insert("t_onset_down_mean_curve_I0.5".into(), t);
        }
        ps
    });
    // a qualitative claim of the mean curve over the valid runs: undecided
    // with fewer than 3 of them (the one grading rule)
    let inside = cs.t_c_samples > 1 && cs.t_c_samples < t_max && cs.valid == corr.len();
    checks.push(Check::test("correlation_peak_inside", Kind::Published, "PH95 Fig. 11 (C(R, T) peaks at T_c = 880)", cs.t_c, cs.valid, inside,
            &format!("C(R, T) at I = {I_CORR} has its peak strictly inside 0 < T < {} steps, all runs stationary (the published T_c = 880 is at I = 0.5: paper_setup_speed)", t_max as u64 * every)).with_published(880.0));
    Fig11Readings {
        metrics,
        checks,
        corr: cs,
        paper: paper_speed,
    }
}
