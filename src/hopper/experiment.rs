//! One filling-and-emptying experiment (MODEL.md B5), recording what the
//! figures and the acceptance tests measure. Shared by `hopper-fig2`,
//! `hopper-fig3` and `tests/hopper_*.rs`, so the tests assert the very
//! numbers the figures report.

use super::energy::{motion, orientation, Aligned, RestPairs};
use super::geometry::Geometry;
use super::model::{
    grain_state, is_grain, ConflictRule, Dynamics, Hopper, HopperParams, UpdateOrder,
};
use super::observables::{
    correlation_length, enclosed_vacancies, orientation_correlation, surface_slope, Activity,
    OutflowStats,
};
use crate::error::{check_range, Result};
use crate::run::{ensemble_with_threads, progress};

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
    /// Snapshot when half the grains had left (sites).
    pub half: Vec<u8>,
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

    /// The snapshot kept `t` iterations after opening, if any.
    pub fn snapshot(&self, t: u64) -> Option<&[u8]> {
        self.snapshots
            .iter()
            .find(|(s, _)| *s == t)
            .map(|(_, v)| v.as_slice())
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

/// One per-run number of BB90 Fig. 2, from the record, the geometry and the
/// two core rows ([`core_rows`]).
pub type Measure = fn(&Record, &Geometry, &[usize; 2]) -> f64;

/// The per-run numbers of BB90 Fig. 2 with their names (the metric names
/// of `hopper-fig2`, after the case): core widths and occupancies at the
/// core rows, activity at the centre and next to the walls, order and
/// correlation length of the orientations, emptying.
pub const FIG2_MEASURES: [(&str, Measure); 23] = [
    ("core_width_low", |r, g, y| r.activity.core_width(g, y[0])),
    ("core_width_high", |r, g, y| r.activity.core_width(g, y[1])),
    ("occupancy_core", |r, g, y| {
        r.activity.core_and_side_occupancy(g, y).0
    }),
    ("occupancy_sides", |r, g, y| {
        r.activity.core_and_side_occupancy(g, y).1
    }),
    ("activity_centre", |r, g, y| {
        r.activity.centre_and_wall_activity(g, y[0], 2).0
    }),
    ("activity_wall", |r, g, y| {
        r.activity.centre_and_wall_activity(g, y[0], 2).1
    }),
    ("order_filled", |r, _, _| r.g_filled[0]),
    ("order_half_empty", |r, _, _| r.g_half[0]),
    ("g2_half_empty", |r, _, _| r.g_half[1]),
    ("g4_half_empty", |r, _, _| r.g_half[3]),
    ("g8_half_empty", |r, _, _| r.g_half[7]),
    ("g16_half_empty", |r, _, _| r.g_half[15]),
    ("corr_length_filled", |r, _, _| {
        correlation_length(&r.g_filled)
    }),
    ("corr_length_half_empty", |r, _, _| {
        correlation_length(&r.g_half)
    }),
    ("vertical_fraction_moving", |r, _, _| {
        r.vertical_fraction_of_moving()
    }),
    ("empty_iterations", |r, _, _| r.empty_iterations as f64),
    ("remaining_grains", |r, _, _| r.remaining as f64),
    ("initial_grains", |r, _, _| r.initial as f64),
    ("fill_iterations", |r, _, _| r.fill_iterations as f64),
    ("mean_rate", |r, _, _| {
        r.removed as f64 / r.empty_iterations.max(1) as f64
    }),
    ("core_width_change", |r, g, y| {
        r.activity.core_width(g, y[1]) - r.activity.core_width(g, y[0])
    }),
    ("surface_slope_half_empty", |r, g, _| {
        surface_slope(g, &r.half)
    }),
    ("vacancies_per_1000_half_empty", |r, g, _| {
        enclosed_vacancies(g, &r.half)
    }),
];

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
    let mut half = Vec::new();
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
            half = h.sites().to_vec();
        }
        if plan.snapshots.contains(&t) {
            snapshots.push((t, h.sites().to_vec()));
        }
    }
    if g_half.is_empty() {
        g_half = orientation_correlation(&h, plan.rmax);
        half = h.sites().to_vec();
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
        half,
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

/// One case of a hopper figure: the energy's beta and reading of "aligned".
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// Prefix of the case's metric names, e.g. `beta1_along`.
    pub key: &'static str,
    /// Legend and title text, e.g. `beta = 1, aligned = along-velocity`.
    pub caption: &'static str,
    /// Weight of the orientation energy.
    pub beta: f64,
    /// Reading of "aligned" (MODEL.md B4).
    pub aligned: Aligned,
    /// Reading of "aligned" for two grains at rest (HOPPER_READINGS.md R1b).
    pub rest_pairs: RestPairs,
    /// Rain width as a multiple of the tier's sigma (HOPPER_READINGS.md R7).
    pub rain_scale: f64,
    /// Update order and conflict rule (HOPPER_READINGS.md R4-R5).
    pub dynamics: Dynamics,
}

impl Case {
    /// Orientation off (beta = 0); the reading of "aligned" is the default
    /// one, though at beta = 0 no reading enters the energy.
    pub const BETA0: Case = Case {
        key: "beta0",
        caption: "beta = 0",
        beta: 0.0,
        aligned: Aligned::DEFAULT,
        rest_pairs: RestPairs::NotAligned,
        rain_scale: 1.0,
        dynamics: Dynamics {
            order: UpdateOrder::Synchronous,
            conflict: ConflictRule::KeepOrientation,
        },
    };
    /// Orientation on (beta = 1), "aligned" read literally: along the velocity
    /// (a named variant; the default reading is [`Case::BETA1_BOND`]).
    pub const BETA1_ALONG: Case = Case {
        key: "beta1_along",
        caption: "beta = 1, aligned = along-velocity",
        beta: 1.0,
        aligned: Aligned::AlongVelocity,
        ..Case::BETA0
    };
    /// Orientation on (beta = 1), "aligned" read as the same orientation (a
    /// named variant; the library default before along-bond).
    pub const BETA1_SAME: Case = Case {
        key: "beta1_same",
        caption: "beta = 1, aligned = same-orientation",
        beta: 1.0,
        aligned: Aligned::SameOrientation,
        ..Case::BETA0
    };
    /// Orientation on (beta = 1), "aligned" read as the same orientation
    /// lying along the bond between the two grains: the library default
    /// (`HopperParams::default()`, HOPPER_READINGS.md R1 and Part 3).
    pub const BETA1_BOND: Case = Case {
        key: "beta1_bond",
        caption: "beta = 1, aligned = along-bond",
        beta: 1.0,
        aligned: Aligned::AlongBond,
        ..Case::BETA0
    };
    /// beta = 1, literal reading, and two grains at rest count as aligned
    /// when their orientations agree (HOPPER_READINGS.md R1b).
    pub const BETA1_REST: Case = Case {
        key: "beta1_rest",
        caption: "beta = 1, aligned = along-velocity, rest pairs = same",
        rest_pairs: RestPairs::SameOrientation,
        ..Case::BETA1_ALONG
    };
    /// The literal reading filled by a narrow rain, sigma a quarter of the
    /// tier's (HOPPER_READINGS.md R7).
    pub const BETA1_ALONG_NARROW: Case = Case::BETA1_ALONG.narrow(
        "beta1_along_narrow",
        "beta = 1, along-velocity, narrow rain",
    );
    /// The same-orientation reading filled by a narrow rain.
    pub const BETA1_SAME_NARROW: Case = Case::BETA1_SAME.narrow(
        "beta1_same_narrow",
        "beta = 1, same-orientation, narrow rain",
    );
    /// The rest-pairs reading filled by a narrow rain.
    pub const BETA1_REST_NARROW: Case = Case::BETA1_REST.narrow(
        "beta1_rest_narrow",
        "beta = 1, along-velocity, rest pairs = same, narrow rain",
    );
    /// beta = 0 with grains updated one at a time in a random order (a
    /// diagnostic that contradicts BB90's "simultaneously").
    pub const BETA0_SEQUENTIAL: Case = Case {
        key: "beta0_sequential",
        caption: "beta = 0, sequential update",
        dynamics: Dynamics {
            order: UpdateOrder::Sequential,
            conflict: ConflictRule::KeepOrientation,
        },
        ..Case::BETA0
    };
    /// beta = 0 with the losers of a conflict reverting their orientation.
    pub const BETA0_REVERT: Case = Case {
        key: "beta0_revert",
        caption: "beta = 0, conflict losers revert",
        dynamics: Dynamics {
            order: UpdateOrder::Synchronous,
            conflict: ConflictRule::Revert,
        },
        ..Case::BETA0
    };
    /// The literal reading with the sequential update (diagnostic).
    pub const BETA1_ALONG_SEQUENTIAL: Case = Case {
        key: "beta1_along_sequential",
        caption: "beta = 1, along-velocity, sequential update",
        dynamics: Case::BETA0_SEQUENTIAL.dynamics,
        ..Case::BETA1_ALONG
    };
    /// The literal reading with conflict losers reverting.
    pub const BETA1_ALONG_REVERT: Case = Case {
        key: "beta1_along_revert",
        caption: "beta = 1, along-velocity, conflict losers revert",
        dynamics: Case::BETA0_REVERT.dynamics,
        ..Case::BETA1_ALONG
    };
    /// The same-orientation reading with the sequential update (diagnostic).
    pub const BETA1_SAME_SEQUENTIAL: Case = Case {
        key: "beta1_same_sequential",
        caption: "beta = 1, same-orientation, sequential update",
        dynamics: Case::BETA0_SEQUENTIAL.dynamics,
        ..Case::BETA1_SAME
    };

    /// Every named case, for `--cases`.
    pub const ALL: [Case; 13] = [
        Case::BETA0,
        Case::BETA1_ALONG,
        Case::BETA1_SAME,
        Case::BETA1_BOND,
        Case::BETA1_REST,
        Case::BETA1_ALONG_NARROW,
        Case::BETA1_SAME_NARROW,
        Case::BETA1_REST_NARROW,
        Case::BETA0_SEQUENTIAL,
        Case::BETA0_REVERT,
        Case::BETA1_ALONG_SEQUENTIAL,
        Case::BETA1_ALONG_REVERT,
        Case::BETA1_SAME_SEQUENTIAL,
    ];

    /// This case filled by a narrow rain, sigma a quarter of the tier's
    /// (HOPPER_READINGS.md R7), as the case `key` with legend `caption`.
    pub const fn narrow(self, key: &'static str, caption: &'static str) -> Case {
        Case {
            key,
            caption,
            rain_scale: 0.25,
            ..self
        }
    }

    /// The cases named in the comma-separated list `keys` (`--cases`); a
    /// typed error names an unknown key and the known ones, or a key given
    /// twice.
    pub fn parse_list(keys: &str) -> Result<Vec<Case>> {
        let list = keys;
        let keys: Vec<&str> = keys.split(',').map(str::trim).collect();
        if keys.contains(&"") {
            return Err(crate::error::Error::new(
                crate::error::ErrorKind::InvalidParameter,
                format!(
                    "--cases '{list}': an empty case name; give case names separated by commas"
                ),
            ));
        }
        crate::error::reject_duplicates("--cases", &keys)?;
        keys.into_iter()
            .map(|k| {
                Case::ALL
                    .iter()
                    .find(|c| c.key == k)
                    .copied()
                    .ok_or_else(|| {
                        let known: Vec<&str> = Case::ALL.iter().map(|c| c.key).collect();
                        crate::error::Error::out_of_range("case", k, &known.join(", "))
                    })
            })
            .collect()
    }

    /// `base` with this case's beta and reading.
    pub fn params(&self, base: HopperParams) -> HopperParams {
        let mut p = base;
        p.energy.beta = self.beta;
        p.energy.aligned = self.aligned;
        p.energy.rest_pairs = self.rest_pairs;
        p.rain.sigma *= self.rain_scale;
        p.dynamics = self.dynamics;
        p
    }

    /// Whether this case is the default model at its beta: the default
    /// reading of "aligned" and of rest pairs, the tier's rain and the
    /// default dynamics ([`HopperParams::default`]). Its checks are the
    /// project's claims; the other cases' are comparisons of readings.
    pub fn is_default_reading(&self) -> bool {
        let d = HopperParams::default();
        self.aligned == d.energy.aligned
            && self.rest_pairs == d.energy.rest_pairs
            && self.rain_scale == 1.0
            && self.dynamics == d.dynamics
    }

    /// The case as recorded in `summary.json`: key, beta, reading and
    /// whether it is the default reading (`report` counts only those
    /// cases' checks as the project's claims).
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({"key": self.key, "beta": self.beta, "aligned": self.aligned.name(),
            "rest_pairs": self.rest_pairs, "rain_scale": self.rain_scale, "dynamics": self.dynamics,
            "default_reading": self.is_default_reading()})
    }
}

/// Run every case once per seed following `plan` on `threads` threads, with
/// a progress bar; the records per case, in seed order (the first error in
/// that order stops the figure).
pub fn run_cases(
    base: HopperParams,
    cases: &[Case],
    seeds: &[u64],
    plan: &Plan,
    threads: usize,
) -> Result<Vec<Vec<Record>>> {
    let pb = progress((cases.len() * seeds.len()) as u64, "hopper runs");
    let jobs: Vec<(usize, usize)> = (0..cases.len())
        .flat_map(|c| (0..seeds.len()).map(move |r| (c, r)))
        .collect();
    let results = ensemble_with_threads(jobs.len(), threads, |j| {
        let (c, r) = jobs[j];
        let rec = run(cases[c].params(base), seeds[r], plan);
        pb.inc(1);
        rec
    });
    pb.finish();
    let mut recs: Vec<Vec<Record>> = (0..cases.len()).map(|_| Vec::new()).collect();
    for (j, rec) in results.into_iter().enumerate() {
        recs[jobs[j].0].push(rec?);
    }
    Ok(recs)
}

/// Outflow analysis of BB90 Fig. 3 over an ensemble of runs.
#[derive(Debug, Clone)]
pub struct OutflowAnalysis {
    /// Rates in the stationary window ([`OutflowStats::combine`] of the
    /// runs: means over runs, standard errors combined, `len` the shortest
    /// window).
    pub rates: OutflowStats,
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

impl OutflowAnalysis {
    /// The numbers of the analysis under the names `hopper-fig3` reports
    /// (after the case's key).
    pub fn named(&self) -> [(&'static str, f64); 13] {
        [
            ("mean_rate", self.rates.mean),
            ("sd_rate", self.rates.sd),
            ("rate_first_half", self.rates.first),
            ("rate_first_half_err", self.rates.first_se),
            ("rate_second_half", self.rates.second),
            ("rate_second_half_err", self.rates.second_se),
            ("trend_z", self.rates.trend_z()),
            ("window_iterations", self.window),
            ("spectral_slope", self.fit.slope),
            ("spectral_slope_err", self.fit.slope_err),
            ("spectrum_k", self.k as f64),
            ("spectrum_high_to_low", self.high_to_low),
            ("lag1_correlation", self.lag1),
        ]
    }
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
    let rates = OutflowStats::combine(&stats);
    let shortest = rates.len;
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
        rates,
        window: stats.iter().map(|s| s.len as f64).sum::<f64>() / n,
        frequencies: (0..m).map(|j| frequency(j, m)).collect(),
        spectrum: p,
        k,
        fit,
        high_to_low,
        lag1,
    })
}

/// The outflow rate from opening while more than `full` of the grains
/// remain, the window taken literally (no start-up skipped): the
/// mean rate and the standard deviation of the per-iteration outflow, each
/// averaged over `records`.
pub fn open_window_rates(records: &[Record], full: f64) -> (f64, f64) {
    let n = records.len() as f64;
    let mut rates = (0.0, 0.0);
    for r in records {
        let w = r.window(0.0, full);
        let mu = w.iter().sum::<f64>() / w.len().max(1) as f64;
        let var = w.iter().map(|q| (q - mu).powi(2)).sum::<f64>() / (w.len().max(2) - 1) as f64;
        rates.0 += mu / n;
        rates.1 += var.sqrt() / n;
    }
    rates
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

#[cfg(test)]
mod reading_tests {
    use super::Case;

    /// beta = 0 and the along-bond beta = 1 case are the default model; the
    /// other readings and the diagnostic dynamics are comparisons.
    #[test]
    fn default_reading_cases() {
        let default: Vec<&str> = Case::ALL
            .iter()
            .filter(|c| c.is_default_reading())
            .map(|c| c.key)
            .collect();
        assert_eq!(default, ["beta0", "beta1_bond"]);
        assert_eq!(Case::BETA1_SAME.json()["default_reading"], false);
    }
}
