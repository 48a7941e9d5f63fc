//! Recording a run: bin densities every `every` steps (the space-time data of
//! PH94 Fig. 1), with the contrast and kinetic energy at each sample, and the
//! band statistics of MODEL.md A11 over the late part of the record; the
//! steady-state fields of PH95 Figs. 4 and 5 ([`Steady`]) and the approach
//! to the steady state of PH95 Fig. 3 ([`relaxation`]).

use super::engine::PipeEngine;
use super::observables::{contrast, random_start_bin_variance, s_low};
use super::Engine;
use super::{Params, Rules};
use crate::error::Result;
use crate::run::Tier;
use serde::{Deserialize, Serialize};

/// Bin densities sampled during a run.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Record {
    /// Time (steps) of the first sample.
    pub t0: u64,
    /// Steps between samples.
    pub every: u64,
    /// `n[t][i]`: particles in bin i at sample t.
    pub n: Vec<Vec<f64>>,
    /// Kinetic energy E (moving particles) at each sample.
    pub energy: Vec<f64>,
}

impl Record {
    /// Time of sample `t`.
    pub fn time(&self, t: usize) -> u64 {
        self.t0 + t as u64 * self.every
    }

    /// Density contrast C at each sample \[PH95 eq. 1\].
    pub fn contrast(&self) -> Vec<f64> {
        self.n.iter().map(|v| contrast(v)).collect()
    }

    /// Join another record that continues this one (same sampling).
    pub fn extend(&mut self, other: Record) {
        self.n.extend(other.n);
        self.energy.extend(other.energy);
    }

    /// The CSV header of [`Record::csv_rows`]: `t, n0, n1, ...`.
    pub fn csv_header(&self) -> Vec<String> {
        let k = self.n.first().map_or(0, |v| v.len());
        std::iter::once("t".to_string())
            .chain((0..k).map(|i| format!("n{i}")))
            .collect()
    }

    /// One row per sample: its time, then the bin counts.
    pub fn csv_rows(&self) -> Vec<Vec<f64>> {
        self.n
            .iter()
            .enumerate()
            .map(|(t, v)| {
                std::iter::once(self.time(t) as f64)
                    .chain(v.iter().copied())
                    .collect()
            })
            .collect()
    }
}

/// Run `steps` steps, sampling the bins at the current time and then after
/// every `every` steps (so `steps / every + 1` samples). `tick(done)` is called
/// after each sample for progress bars.
pub fn record(
    pipe: &mut dyn PipeEngine,
    steps: u64,
    every: u64,
    mut tick: impl FnMut(u64),
) -> Result<Record> {
    let every = every.max(1);
    let mut rec = Record {
        t0: pipe.time(),
        every,
        n: vec![pipe.bin_counts()],
        energy: vec![pipe.moving_count() as f64],
    };
    let mut done = 0;
    while done + every <= steps {
        pipe.run(every)?;
        done += every;
        rec.n.push(pipe.bin_counts());
        rec.energy.push(pipe.moving_count() as f64);
        tick(done);
    }
    Ok(rec)
}

/// Band statistics of the samples from `from` on (MODEL.md A11).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
pub struct Bands {
    /// Mean density contrast C over the samples.
    pub contrast: f64,
    /// Mean of S(1..3) divided by its random-start value K * var.
    pub s_low: f64,
    /// Mean per-bin variance of n_i (over bins, per sample) divided by its
    /// random-start value: well below 1 when the gas has collapsed into a
    /// uniform free-falling plug (MODEL.md A11), about 1 for a random gas.
    pub var_ratio: f64,
}

/// Band statistics over the samples `from..` of `rec` for a pipe of initial
/// density `rho`, `bin` rows per bin and `width` columns.
pub fn bands(rec: &Record, from: usize, rho: f64, bin: usize, width: usize) -> Bands {
    let samples = &rec.n[from.min(rec.n.len())..];
    let k = samples.first().map(|v| v.len()).unwrap_or(0);
    let var0 = random_start_bin_variance(rho, bin, width);
    let mut c = 0.0;
    let mut var = 0.0;
    for v in samples {
        c += contrast(v);
        let mean = v.iter().sum::<f64>() / k.max(1) as f64;
        var += v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / k.max(1) as f64;
    }
    let n = samples.len().max(1) as f64;
    Bands {
        contrast: c / n,
        s_low: s_low(samples, rho, bin, width),
        var_ratio: var / n / var0,
    }
}

/// The pipe of PH94 Fig. 1a: that of PH94 Fig. 2 ([`Params::default`]:
/// W = 11, rho = 1, g = b = 0.5, bins of 10 rows, periodic) at L = 2200 and
/// p = 0.1. PH95 Figs. 2-5 vary its length, p and bins.
pub fn fig1_pipe() -> Params {
    Params {
        length: 2200,
        p: 0.1,
        ..Params::default()
    }
}

/// The four runs of PH94 Fig. 1 for one seed, each with its band statistics
/// over the second half: (a) p = 0.1; (b) p = 0; (c) (b) continued with
/// p = 0.1; (d) p = 0.1, b = 0; everything else from `base`.
pub fn fig1_panels(
    base: Params,
    rules: Rules,
    engine: Engine,
    seed: u64,
    steps: u64,
    every: u64,
    tick: &(dyn Fn(u64) + Sync),
) -> Result<Vec<(Record, Bands)>> {
    let stats = |rec: Record, params: &Params| {
        let b = bands(&rec, rec.n.len() / 2, params.rho, params.bin, params.width);
        (rec, b)
    };
    let pa = Params { p: 0.1, ..base };
    let pb = Params { p: 0.0, ..base };
    let pd = Params {
        p: 0.1,
        b: 0.0,
        ..base
    };
    let mut a = engine.build(pa, rules, seed)?;
    let ra = record(a.as_mut(), steps, every, |_| tick(every))?;
    let mut b = engine.build(pb, rules, seed)?;
    let rb = record(b.as_mut(), steps, every, |_| tick(every))?;
    b.set_p(0.1)?;
    let mut rc = record(b.as_mut(), steps, every, |_| tick(every))?;
    rc.n.remove(0); // the first sample of (c) is the last of (b)
    rc.energy.remove(0);
    rc.t0 += every;
    let mut d = engine.build(pd, rules, seed)?;
    let rd = record(d.as_mut(), steps, every, |_| tick(every))?;
    Ok(vec![
        stats(ra, &pa),
        stats(rb, &pb),
        stats(rc, &pa),
        stats(rd, &pd),
    ])
}

/// Band statistics of `steps` steps of `pipe` sampled every `every`, over
/// the second half (MODEL.md A11).
pub fn run_bands(pipe: &mut dyn PipeEngine, steps: u64, every: u64) -> Result<Bands> {
    let rec = record(pipe, steps, every, |_| {})?;
    let params = pipe.params();
    Ok(bands(
        &rec,
        rec.n.len() / 2,
        params.rho,
        params.bin,
        params.width,
    ))
}

/// When the density fields of the steady state are taken [PH95 Figs. 4,
/// 5]: after `warmup` steps from the random start, then every `every` steps,
/// `fields` in all.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Steady {
    /// Steps before the first field.
    pub warmup: u64,
    /// Number of fields.
    pub fields: usize,
    /// Steps between fields (T0).
    pub every: u64,
}

impl Steady {
    /// `fields` fields every `every` steps after the warm-up of PH95 Figs.
    /// 4 and 5 at `tier`: 10000, 20000 or 40000 steps.
    pub fn ph95(tier: Tier, fields: usize, every: u64) -> Self {
        Steady {
            warmup: tier.pick(10_000, 20_000, 40_000),
            fields,
            every,
        }
    }

    /// Steps of a run: the warm-up and the fields.
    pub fn steps(&self) -> u64 {
        self.warmup + self.fields.saturating_sub(1) as u64 * self.every
    }

    /// The fields (bin counts) of one run. `tick(steps)` reports progress.
    pub fn record(
        &self,
        params: Params,
        rules: Rules,
        engine: Engine,
        seed: u64,
        tick: &(dyn Fn(u64) + Sync),
    ) -> Result<Vec<Vec<f64>>> {
        let mut pipe = engine.build(params, rules, seed)?;
        pipe.run(self.warmup)?;
        tick(self.warmup);
        let steps = self.fields.saturating_sub(1) as u64 * self.every;
        Ok(record(pipe.as_mut(), steps, self.every, |_| tick(self.every))?.n)
    }
}

/// Steps sampled one by one at the start of a PH95 Fig. 3 run, so the fast
/// energy loss (half-time of tens of steps) is resolved at every tier.
pub const RELAXATION_EARLY: u64 = 400;

/// Steps per run and sampling interval of PH95 Fig. 3 at `tier` (20000,
/// 50000, 100000 steps; every 20, 50, 100 steps after the first
/// [`RELAXATION_EARLY`]).
pub fn relaxation_schedule(tier: Tier) -> (u64, u64) {
    (tier.pick(20_000, 50_000, 100_000), tier.pick(20, 50, 100))
}

/// Sample times of [`relaxation`]: every step up to `early` (the fast
/// energy loss, with a half-time of tens of steps), then every `every`
/// steps up to `steps`.
pub fn sample_times(steps: u64, every: u64, early: u64) -> Vec<u64> {
    let mut t: Vec<u64> = (0..=early.min(steps)).collect();
    let mut x = early + every;
    while x <= steps {
        t.push(x);
        x += every;
    }
    t
}

/// One run's approach to the steady state \[PH95 Fig. 3\], at its sample times.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Relaxation {
    /// Density contrast C(t).
    pub contrast: Vec<f64>,
    /// Kinetic energy loss E(0) - E(t).
    pub energy_loss: Vec<f64>,
    /// Largest |E(0) - E(t) - rest(t)| over the samples (0 in the periodic pipe).
    pub identity_error: f64,
}

/// Run the pipe from the random start to the last of `times` (increasing,
/// from 0), recording C(t) and E(0) - E(t) at each. `tick(steps)` reports
/// progress.
pub fn relaxation(
    params: Params,
    rules: Rules,
    engine: Engine,
    seed: u64,
    times: &[u64],
    tick: &(dyn Fn(u64) + Sync),
) -> Result<Relaxation> {
    let mut pipe = engine.build(params, rules, seed)?;
    let mut bins = vec![0.0; params.bins()];
    let e0 = pipe.moving_count() as f64;
    let mut s = Relaxation {
        contrast: Vec::new(),
        energy_loss: Vec::new(),
        identity_error: 0.0,
    };
    let mut now = 0;
    for &t in times {
        pipe.run(t - now)?;
        tick(t - now);
        now = t;
        pipe.fill_bin_counts(&mut bins);
        s.contrast.push(contrast(&bins));
        let loss = e0 - pipe.moving_count() as f64;
        s.energy_loss.push(loss);
        s.identity_error = s
            .identity_error
            .max((loss - pipe.rest_count() as f64).abs());
    }
    Ok(s)
}
