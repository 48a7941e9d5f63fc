//! What moves and what stands in the steady state of the periodic pipe
//! (docs/decisions/real-space-speed-three-ways.md, "What is measured"): the
//! mean particle speed, the shares at rest and in the lane of channel 4
//! (MODEL.md A11), the wave speed read three ways and from the spectrum
//! (\[PH95 C, Fig. 5\]; [`super::overlap::SpeedRun`]), whether a standing
//! pattern exists and what holds it. One run is a pure function of
//! (parameters, rules, seed, engine); `explore --mechanism` prints a table
//! of runs.

use super::overlap::{time_mean_profile, SpeedRun};
use super::record::Steady;
use super::{Engine, Params, Rules};
use crate::analysis::spectrum::{SpectrumParams, Window};
use crate::error::Result;
use crate::lattice::velocity;
use crate::run::{derive_seed, ensemble, mean_sem_by};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;

/// One run's mechanism measurements, each a mean over the run's fields
/// unless stated.
#[derive(Debug, Clone)]
pub struct Mechanism {
    /// Mean vertical velocity of all particles (rows per step, + = up).
    pub v_all: f64,
    /// Mean vertical velocity of the moving particles alone.
    pub v_movers: f64,
    /// Share of the particles at rest (channel 0).
    pub rest_share: f64,
    /// Share of the movers in channel 4 (straight down, the lane of A11).
    pub lane_share: f64,
    /// The wave speed read three ways and from the spectrum.
    pub speeds: SpeedRun,
    /// Variance over bins of the run's time-mean profile over that of the
    /// same record with each field rotated by its own random shift (a
    /// standing pattern gives >> 1, none about 1).
    pub standing_ratio: f64,
    /// Share at rest of the particles in the bins above the median of the
    /// time-mean profile.
    pub rest_share_high: f64,
    /// The same in the bins below the median.
    pub rest_share_low: f64,
    /// Share of the movers in channel 4, bins above the median.
    pub lane_share_high: f64,
    /// The same, bins below the median.
    pub lane_share_low: f64,
    /// Mean number of consecutive steps a site holds a rest particle
    /// (stretches that begin and end inside the record; the site, not the
    /// particle, is followed).
    pub rest_dwell_mean: f64,
    /// The 90th percentile of those stretches.
    pub rest_dwell_p90: f64,
}

impl Mechanism {
    /// Names of the columns of [`Mechanism::row`].
    pub const COLUMNS: [&'static str; 16] = [
        "v_all",
        "v_movers",
        "rest_share",
        "lane_share",
        "speed_raw_overlap",
        "speed_fluctuations",
        "speed_ridge",
        "speed_spectral",
        "s_low",
        "standing_ratio",
        "rest_share_high",
        "rest_share_low",
        "lane_share_high",
        "lane_share_low",
        "rest_dwell_mean",
        "rest_dwell_p90",
    ];

    /// The run's values in the order of [`Mechanism::COLUMNS`].
    pub fn row(&self) -> [f64; 16] {
        let s = &self.speeds;
        [
            self.v_all,
            self.v_movers,
            self.rest_share,
            self.lane_share,
            s.speed,
            s.speed_fluctuations,
            s.speed_ridge,
            s.speed_spectral,
            s.s_low,
            self.standing_ratio,
            self.rest_share_high,
            self.rest_share_low,
            self.lane_share_high,
            self.lane_share_low,
            self.rest_dwell_mean,
            self.rest_dwell_p90,
        ]
    }
}

/// Per field and bin: particles, rest particles, movers and channel-4
/// movers (indices [`ALL`], [`REST`], [`MOVERS`], [`LANE`]).
type BinCounts = [Vec<f64>; 4];
const ALL: usize = 0;
const REST: usize = 1;
const MOVERS: usize = 2;
const LANE: usize = 3;

/// The variance over bins of `a`.
fn variance(a: &[f64]) -> f64 {
    let m = a.iter().sum::<f64>() / a.len() as f64;
    a.iter().map(|v| (v - m).powi(2)).sum::<f64>() / a.len() as f64
}

/// [`Mechanism::standing_ratio`] of `fields`, the null's shifts drawn from
/// `seed`.
pub fn standing_ratio(fields: &[Vec<f64>], seed: u64) -> f64 {
    let k = fields[0].len();
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ 0x57A_4D11);
    let rotated: Vec<Vec<f64>> = fields
        .iter()
        .map(|f| super::overlap::shifted(f, rng.random_range(0..k) as i64))
        .collect();
    variance(&time_mean_profile(fields)) / variance(&time_mean_profile(&rotated))
}

/// The `q` quantile (0..=1, nearest rank) of `v`; NaN when empty.
fn quantile(v: &mut [u32], q: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_unstable();
    let i = ((q * v.len() as f64).ceil() as usize).clamp(1, v.len()) - 1;
    v[i] as f64
}

/// Measure one run of `params` with `rules` on `engine` from `seed`: the
/// fields of `steady` (bins of `params.bin` rows), the speeds with lags up
/// to `max_lag` and the spectrum with `spec`, the rest stretches at every
/// step of the record.
pub fn measure(
    params: Params,
    rules: Rules,
    engine: Engine,
    seed: u64,
    steady: &Steady,
    max_lag: usize,
    spec: &SpectrumParams,
) -> Result<Mechanism> {
    let mut pipe = engine.build(params, rules, seed)?;
    pipe.run(steady.warmup)?;
    let (w, l, bin, k) = (params.width, params.length, params.bin, params.bins());
    let mut per_field: Vec<BinCounts> = Vec::with_capacity(steady.fields);
    let (mut vy, mut n_all, mut n_movers) = (0.0, 0.0, 0.0);
    // the rest stretch of each site: steps so far; u32::MAX = began before
    // the record (left out)
    let mut stretch = vec![u32::MAX; w * l];
    for x in 0..w {
        for y in 0..l {
            if pipe.site(x, y) & 1 == 0 {
                stretch[x * l + y] = 0;
            }
        }
    }
    let mut stretches: Vec<u32> = Vec::new();
    let steps = steady.steps() - steady.warmup;
    for t in 0..=steps {
        if t % steady.every == 0 {
            let mut c: BinCounts = std::array::from_fn(|_| vec![0.0; k]);
            for x in 0..w {
                for y in 0..l {
                    let s = pipe.site(x, y);
                    let i = y / bin;
                    c[ALL][i] += s.count_ones() as f64;
                    c[REST][i] += (s & 1) as f64;
                    c[MOVERS][i] += (s >> 1).count_ones() as f64;
                    c[LANE][i] += ((s >> 4) & 1) as f64;
                    for ch in 1..7 {
                        if s >> ch & 1 == 1 {
                            vy += velocity(ch).1;
                        }
                    }
                }
            }
            n_all += c[ALL].iter().sum::<f64>();
            n_movers += c[MOVERS].iter().sum::<f64>();
            per_field.push(c);
        }
        if t == steps {
            break;
        }
        pipe.step()?;
        for x in 0..w {
            for y in 0..l {
                let st = &mut stretch[x * l + y];
                if pipe.site(x, y) & 1 == 1 {
                    // u32::MAX (began before the record) stays
                    *st = st.saturating_add(1);
                } else {
                    if *st != u32::MAX && *st > 0 {
                        stretches.push(*st);
                    }
                    *st = 0;
                }
            }
        }
    }
    let fields: Vec<Vec<f64>> = per_field.iter().map(|c| c[ALL].clone()).collect();
    let speeds = SpeedRun::measure(&fields, &params, steady.every, max_lag, spec)?;
    let mean = time_mean_profile(&fields);
    let mut sorted = mean.clone();
    sorted.sort_by(f64::total_cmp);
    let median = 0.5 * (sorted[(k - 1) / 2] + sorted[k / 2]);
    let share = |num: usize, den: usize, high: bool| {
        let (mut a, mut b) = (0.0, 0.0);
        for c in &per_field {
            for i in (0..k).filter(|&i| (mean[i] > median) == high) {
                a += c[num][i];
                b += c[den][i];
            }
        }
        a / b
    };
    let total = |j: usize| {
        per_field
            .iter()
            .map(|c| c[j].iter().sum::<f64>())
            .sum::<f64>()
    };
    let dwell_mean = stretches.iter().map(|&v| v as f64).sum::<f64>() / stretches.len() as f64;
    Ok(Mechanism {
        v_all: vy / n_all,
        v_movers: vy / n_movers,
        rest_share: total(REST) / total(ALL),
        lane_share: total(LANE) / total(MOVERS),
        standing_ratio: standing_ratio(&fields, seed),
        rest_share_high: share(REST, ALL, true),
        rest_share_low: share(REST, ALL, false),
        lane_share_high: share(LANE, MOVERS, true),
        lane_share_low: share(LANE, MOVERS, false),
        rest_dwell_mean: dwell_mean,
        rest_dwell_p90: quantile(&mut stretches, 0.9),
        speeds,
    })
}

/// `runs` runs of PH95 Fig. 5's record at `tier` (as `waves-fig5`: fields
/// every 40 steps, lags up to 20, spectrum of m = fields / 4 frequencies
/// with the 1988 Parzen window) from base seed `seed`: a CSV table, one
/// row per run (seed first), then the mean and the standard error over
/// runs of every column.
pub fn table(
    params: Params,
    rules: Rules,
    engine: Engine,
    tier: crate::run::Tier,
    runs: usize,
    seed: u64,
) -> Result<String> {
    use super::overlap::{FIELDS_EVERY, FIG5_MAX_LAG};
    let steady = Steady::ph95(tier, tier.pick(1024, 2048, 2048), FIELDS_EVERY);
    let spec = SpectrumParams {
        m: steady.fields / 4,
        k: 1,
        window: Window::Parzen1988,
    };
    spec.validate()?;
    let res: Vec<(u64, Mechanism)> = ensemble(runs, |i| {
        let s = derive_seed(seed, i as u64);
        measure(params, rules, engine, s, &steady, FIG5_MAX_LAG, &spec).map(|m| (s, m))
    })
    .into_iter()
    .collect::<Result<_>>()?;
    let mut out = format!("seed,{}\n", Mechanism::COLUMNS.join(","));
    for (s, m) in &res {
        let row: Vec<String> = m.row().iter().map(|v| format!("{v:.5}")).collect();
        out.push_str(&format!("{s},{}\n", row.join(",")));
    }
    for (name, which) in [("mean", 0), ("se", 1)] {
        let row: Vec<String> = (0..Mechanism::COLUMNS.len())
            .map(|j| {
                let (m, e) = mean_sem_by(&res, |(_, r)| r.row()[j]);
                format!("{:.5}", if which == 0 { m } else { e })
            })
            .collect();
        out.push_str(&format!("{name},{}\n", row.join(",")));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_standing_pattern_has_a_large_ratio_and_a_uniformly_moving_one_none() {
        let k = 32;
        let bump = |at: usize| -> Vec<f64> {
            (0..k)
                .map(|i| if (i + k - at) % k < 4 { 5.0 } else { 1.0 })
                .collect()
        };
        let standing: Vec<Vec<f64>> = (0..256).map(|_| bump(7)).collect();
        assert!(standing_ratio(&standing, 1) > 10.0);
        let moving: Vec<Vec<f64>> = (0..256).map(|t| bump(t % k)).collect();
        let r = standing_ratio(&moving, 1);
        assert!(
            r < 1e-9,
            "a uniformly moving bump has a flat time mean: {r}"
        );
    }

    #[test]
    fn quantiles_by_nearest_rank() {
        let mut v: Vec<u32> = (1..=10).collect();
        assert_eq!(quantile(&mut v, 0.9), 9.0);
        assert_eq!(quantile(&mut v, 0.5), 5.0);
        assert!(quantile(&mut [], 0.5).is_nan());
    }

    #[test]
    fn a_run_is_a_pure_function_of_its_seed_and_its_shares_are_shares() {
        let params = Params {
            length: 64,
            bin: 8,
            p: 0.1,
            ..Params::default()
        };
        let steady = Steady {
            warmup: 200,
            fields: 64,
            every: 10,
        };
        let spec = SpectrumParams {
            m: 16,
            k: 1,
            window: Window::Parzen1988,
        };
        let run = |s| measure(params, Rules::default(), Engine::Fast, s, &steady, 5, &spec);
        let (a, b) = (run(3).unwrap(), run(3).unwrap());
        assert_eq!(a.row().map(f64::to_bits), b.row().map(f64::to_bits));
        for v in [
            a.rest_share,
            a.lane_share,
            a.rest_share_high,
            a.lane_share_low,
        ] {
            assert!((0.0..=1.0).contains(&v), "{v}");
        }
        assert!(a.v_all.abs() <= 1.0 && a.v_movers.abs() <= 1.0);
        assert!(a.rest_dwell_mean >= 1.0 && a.rest_dwell_p90 >= 1.0);
    }
}
