//! One filling-and-emptying experiment (MODEL.md B5), recording what the
//! figures and the acceptance tests measure. Shared by `hopper-fig2`,
//! `hopper-fig3` and `tests/hopper_*.rs`, so the tests assert the very
//! numbers the figures report.

use super::energy::{motion, orientation};
use super::model::{grain_state, is_grain, Hopper, HopperParams};
use super::observables::{orientation_correlation, Activity};
use crate::error::{check_range, Result};

/// What to do and record in a run.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Rain until this fraction of the inside sites holds grains.
    pub fill_fraction: f64,
    /// Most iterations of rain.
    pub max_fill: u64,
    /// Most iterations of settling after the rain (stops when nothing moves).
    pub max_settle: u64,
    /// Most iterations after opening.
    pub max_empty: u64,
    /// Record the outflow for at least this many iterations after opening
    /// (zeros once empty), e.g. 6144 for BB90 Fig. 3.
    pub min_record: u64,
    /// Iterations after opening at which to keep a snapshot.
    pub snapshots: Vec<u64>,
    /// Accumulate activity while more than this fraction of the grains remain.
    pub activity_above: f64,
    /// Largest distance of g(r).
    pub rmax: usize,
    /// A run has jammed when nothing moved for this many iterations.
    pub jam_after: u64,
}

impl Plan {
    /// Defaults: fill to 85%, activity while more than 50% remain, g(r) to 16.
    pub fn new(max_empty: u64, snapshots: Vec<u64>) -> Self {
        Plan {
            fill_fraction: 0.85,
            max_fill: 20_000,
            max_settle: 2_000,
            max_empty,
            min_record: 0,
            snapshots,
            activity_above: 0.5,
            rmax: 16,
            jam_after: 100,
        }
    }
}

/// What a run recorded.
#[derive(Debug, Clone)]
pub struct Record {
    /// Grains when the plug opened.
    pub initial: u64,
    /// Iterations of rain and settling.
    pub fill_iterations: u64,
    /// Snapshot half-way through the rain (sites).
    pub mid_fill: Vec<u8>,
    /// Snapshot when the plug opened.
    pub filled: Vec<u8>,
    /// Snapshots `(iteration after opening, sites)`.
    pub snapshots: Vec<(u64, Vec<u8>)>,
    /// Activity and occupancy while more than `activity_above` remained.
    pub activity: Activity,
    /// g(r) when the plug opened.
    pub g_filled: Vec<f64>,
    /// g(r) when half the grains had left.
    pub g_half: Vec<f64>,
    /// Grains leaving per iteration after opening.
    pub outflow: Vec<f64>,
    /// Grains inside after each iteration after opening.
    pub inside: Vec<u64>,
    /// Whether the hopper emptied completely.
    pub emptied: bool,
    /// Whether it stopped because nothing moved for `jam_after` iterations.
    pub jammed: bool,
    /// Grains left inside at the end.
    pub remaining: u64,
    /// Iterations after opening until empty (or the end of the run).
    pub empty_iterations: u64,
    /// Moving grains of each orientation, summed over the activity window.
    pub moving_by_orientation: [u64; 3],
    /// Grains added, removed, and on the lattice at the end (conservation).
    pub added: u64,
    /// Grains removed through the outlet.
    pub removed: u64,
    /// Grains counted on the lattice at the end.
    pub counted: u64,
    /// Site updates computed.
    pub site_updates: f64,
}

impl Record {
    /// Fraction of moving grains with vertical orientation (1/3 if random).
    pub fn vertical_fraction_of_moving(&self) -> f64 {
        let n: u64 = self.moving_by_orientation.iter().sum();
        self.moving_by_orientation[0] as f64 / n.max(1) as f64
    }

    /// The stationary outflow of BB90 Fig. 3: the iterations after the
    /// start-up (once `skip` of the initial grains have left) while more than
    /// `full` of the initial grains remain inside.
    pub fn window(&self, skip: f64, full: f64) -> &[f64] {
        let n0 = self.initial as f64;
        let first = |limit: f64| {
            self.inside
                .iter()
                .position(|&g| (g as f64) <= limit)
                .unwrap_or(self.inside.len())
        };
        let a = if skip > 0.0 {
            (first((1.0 - skip) * n0) + 1).min(self.inside.len())
        } else {
            0
        };
        let b = first(full * n0).max(a);
        &self.outflow[a..b]
    }
}

/// Two heights for the core width: 20% and 40% of the wedge above the
/// outlet channel.
pub fn core_rows(h: &Hopper) -> [usize; 2] {
    let g = h.geometry();
    let ch = g.params.channel_height;
    let span = (g.height() - ch) as f64;
    [ch + (0.2 * span) as usize, ch + (0.4 * span) as usize]
}

/// Fill, open and empty one hopper with `params` and `seed` following `plan`.
pub fn run(params: HopperParams, seed: u64, plan: &Plan) -> Result<Record> {
    check_range("fill_fraction", plan.fill_fraction, 0.0, 1.0)?;
    check_range("activity_above", plan.activity_above, 0.0, 1.0)?;
    let mut h = Hopper::new(params, seed)?;
    let target = (plan.fill_fraction * h.geometry().inside as f64) as u64;
    let mut mid_fill = h.sites().to_vec();
    let mut it = 0;
    while h.added() < target && it < plan.max_fill {
        h.step(true);
        it += 1;
        if h.added() <= target / 2 {
            mid_fill = h.sites().to_vec();
        }
    }
    for _ in 0..plan.max_settle {
        it += 1;
        if h.step(false).moved == 0 {
            break;
        }
    }
    let filled = h.sites().to_vec();
    let g_filled = orientation_correlation(&h, plan.rmax);
    let initial = h.grains();
    h.open();
    let mut activity = Activity::new(h.geometry());
    let mut snapshots = Vec::new();
    let mut g_half = Vec::new();
    let mut outflow = Vec::new();
    let mut inside = Vec::new();
    let mut moving_by_orientation = [0u64; 3];
    let mut still = 0;
    let mut jammed = false;
    let mut empty_iterations = 0;
    let mut t = 0u64;
    while t < plan.max_empty.max(plan.min_record) {
        if h.grains() == 0 || jammed {
            if t >= plan.min_record {
                break;
            }
            outflow.push(0.0);
            inside.push(h.grains());
            t += 1;
            continue;
        }
        if t >= plan.max_empty {
            break;
        }
        let r = h.step(false);
        t += 1;
        outflow.push(r.outflow as f64);
        inside.push(h.grains());
        empty_iterations = t;
        still = if r.moved == 0 { still + 1 } else { 0 };
        if still >= plan.jam_after {
            jammed = true;
        }
        if h.grains() as f64 > plan.activity_above * initial as f64 {
            activity.record(&h);
            for &s in h.sites() {
                if is_grain(s) && motion(grain_state(s)) != 0 {
                    moving_by_orientation[orientation(grain_state(s))] += 1;
                }
            }
        }
        if g_half.is_empty() && 2 * h.grains() <= initial {
            g_half = orientation_correlation(&h, plan.rmax);
        }
        if plan.snapshots.contains(&t) {
            snapshots.push((t, h.sites().to_vec()));
        }
    }
    if g_half.is_empty() {
        g_half = orientation_correlation(&h, plan.rmax);
    }
    Ok(Record {
        initial,
        fill_iterations: it,
        mid_fill,
        filled,
        snapshots,
        activity,
        g_filled,
        g_half,
        outflow,
        inside,
        emptied: h.grains() == 0,
        jammed,
        remaining: h.grains(),
        empty_iterations,
        moving_by_orientation,
        added: h.added(),
        removed: h.removed(),
        counted: h.count_grains(),
        site_updates: h.site_updates(),
    })
}

/// Outflow analysis of BB90 Fig. 3 over an ensemble of runs.
#[derive(Debug, Clone)]
pub struct OutflowAnalysis {
    /// Mean grains per iteration in the stationary window (mean over runs).
    pub mean: f64,
    /// Standard deviation of the per-iteration outflow (mean over runs).
    pub sd: f64,
    /// Rate in the first half of the window (mean over runs).
    pub first: f64,
    /// Standard error of `first` (block means, combined over runs).
    pub first_se: f64,
    /// Rate in the second half of the window.
    pub second: f64,
    /// Standard error of `second`.
    pub second_se: f64,
    /// (second - first) / combined standard error.
    pub trend_z: f64,
    /// Mean length of the stationary window.
    pub window: f64,
    /// NR `spctrm` power P(j), j = 0..m-1, averaged over runs.
    pub spectrum: Vec<f64>,
    /// Frequency of P(j): j / (2m) cycles per iteration.
    pub frequencies: Vec<f64>,
    /// Segments pairs k used by `spctrm` (4km samples per run).
    pub k: usize,
    /// Log-log fit of P(f) for f <= 1/8.
    pub fit: crate::analysis::fit::LinearFit,
    /// Mean power in the top quarter of the band over that in the lowest
    /// quarter (excluding f = 0): above 1 for the period-2 alternation.
    pub high_to_low: f64,
    /// Lag-1 autocorrelation of the outflow (mean over runs).
    pub lag1: f64,
}

/// Where the stationary window starts: once this fraction of the grains left.
pub const WINDOW_SKIP: f64 = 0.15;
/// Where it ends: when only this fraction of the grains remains (BB90 Fig. 3:
/// "more than 30% full").
pub const WINDOW_FULL: f64 = 0.3;
/// Block length for the standard errors of the half-window rates.
pub const WINDOW_BLOCK: usize = 16;

/// Analyse the outflow of `records` (same parameters, different seeds):
/// half-window rates with block standard errors, and the NR `spctrm` power
/// spectrum with `m` frequencies on the stationary window, its log-log slope
/// fitted for f <= 1/8 (periods of 8 iterations or more, which the paper's
/// 11-iteration average keeps; above it the outlet's period-2 alternation
/// shapes the band).
pub fn analyse_outflow(records: &[Record], m: usize) -> Result<OutflowAnalysis> {
    use super::observables::OutflowStats;
    use crate::analysis::fit::linear_fit;
    use crate::analysis::spectrum::{frequency, spctrm, SpectrumParams, Window};
    use crate::error::{Error, ErrorKind};
    if records.is_empty() {
        return Err(Error::new(
            ErrorKind::BadSeries,
            "no runs to analyse; use runs >= 1",
        ));
    }
    let windows: Vec<&[f64]> = records
        .iter()
        .map(|r| r.window(WINDOW_SKIP, WINDOW_FULL))
        .collect();
    let stats: Vec<OutflowStats> = windows
        .iter()
        .map(|w| OutflowStats::new(w, WINDOW_BLOCK))
        .collect::<Result<_>>()?;
    let n = stats.len() as f64;
    let avg = |f: &dyn Fn(&OutflowStats) -> f64| stats.iter().map(f).sum::<f64>() / n;
    let comb = |f: &dyn Fn(&OutflowStats) -> f64| {
        stats.iter().map(|s| f(s).powi(2)).sum::<f64>().sqrt() / n
    };
    let (first, first_se) = (avg(&|s| s.first), comb(&|s| s.first_se));
    let (second, second_se) = (avg(&|s| s.second), comb(&|s| s.second_se));
    let shortest = stats.iter().map(|s| s.len).min().unwrap_or(0);
    let k = shortest / (4 * m.max(1));
    if k == 0 {
        return Err(Error::new(
            ErrorKind::BadSeries,
            format!(
                "stationary window of {shortest} iterations is shorter than 4m = {}; lower m or use a larger hopper",
                4 * m
            ),
        ));
    }
    let sp = SpectrumParams {
        m,
        k,
        window: Window::Parzen1988,
    };
    let mut p = vec![0.0; m];
    for w in &windows {
        for (a, b) in p.iter_mut().zip(spctrm(w, &sp)?) {
            *a += b / n;
        }
    }
    let (lx, ly): (Vec<f64>, Vec<f64>) = (1..=m / 4)
        .map(|j| (frequency(j, m).log10(), p[j].log10()))
        .unzip();
    let fit = linear_fit(&lx, &ly)?;
    let quarter = (m / 4).max(1);
    let high_to_low = p[m - quarter..].iter().sum::<f64>() / p[1..=quarter].iter().sum::<f64>();
    let lag1 = windows.iter().map(|w| lag_correlation(w, 1)).sum::<f64>() / n;
    Ok(OutflowAnalysis {
        mean: avg(&|s| s.mean),
        sd: avg(&|s| s.sd),
        first,
        first_se,
        second,
        second_se,
        trend_z: (second - first) / (first_se.powi(2) + second_se.powi(2)).sqrt(),
        window: avg(&|s| s.len as f64),
        frequencies: (0..m).map(|j| frequency(j, m)).collect(),
        spectrum: p,
        k,
        fit,
        high_to_low,
        lag1,
    })
}

/// Correlation coefficient of `q` with itself `lag` iterations later.
pub fn lag_correlation(q: &[f64], lag: usize) -> f64 {
    let n = q.len();
    if n <= lag + 1 {
        return f64::NAN;
    }
    let m = q.iter().sum::<f64>() / n as f64;
    let v = q.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n as f64;
    let c = (0..n - lag)
        .map(|i| (q[i] - m) * (q[i + lag] - m))
        .sum::<f64>()
        / (n - lag) as f64;
    c / v
}
