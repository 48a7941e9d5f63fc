//! Recording a run: bin densities every `every` steps (the space-time data of
//! PH94 Fig. 1), with the contrast and kinetic energy at each sample, and the
//! band statistics of MODEL.md A11 over the late part of the record.

use super::observables::{contrast, random_start_bin_variance, LowK};
use super::{Params, Pipe, Rules};
use crate::error::Result;
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

    /// Density contrast C at each sample [PH95 eq. 1].
    pub fn contrast(&self) -> Vec<f64> {
        self.n.iter().map(|v| contrast(v)).collect()
    }

    /// Join another record that continues this one (same sampling).
    pub fn extend(&mut self, other: Record) {
        self.n.extend(other.n);
        self.energy.extend(other.energy);
    }
}

/// Run `steps` steps, sampling the bins at the current time and then after
/// every `every` steps (so `steps / every + 1` samples). `tick(done)` is called
/// after each sample for progress bars.
pub fn record(
    pipe: &mut Pipe,
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
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
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
    let mut low = LowK::new(3, k, var0);
    let mut c = 0.0;
    let mut var = 0.0;
    for v in samples {
        low.add(v);
        c += contrast(v);
        let mean = v.iter().sum::<f64>() / k.max(1) as f64;
        var += v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / k.max(1) as f64;
    }
    let n = samples.len().max(1) as f64;
    Bands {
        contrast: c / n,
        s_low: low.mean(),
        var_ratio: var / n / var0,
    }
}

/// The four runs of PH94 Fig. 1 for one seed, each with its band statistics
/// over the second half: (a) p = 0.1; (b) p = 0; (c) (b) continued with
/// p = 0.1; (d) p = 0.1, b = 0; everything else from `base`.
pub fn fig1_panels(
    base: Params,
    rules: Rules,
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
    let mut a = Pipe::new(pa, rules, seed)?;
    let ra = record(&mut a, steps, every, |_| tick(every))?;
    let mut b = Pipe::new(pb, rules, seed)?;
    let rb = record(&mut b, steps, every, |_| tick(every))?;
    b.set_p(0.1)?;
    let mut rc = record(&mut b, steps, every, |_| tick(every))?;
    rc.n.remove(0); // the first sample of (c) is the last of (b)
    rc.energy.remove(0);
    rc.t0 += every;
    let mut d = Pipe::new(pd, rules, seed)?;
    let rd = record(&mut d, steps, every, |_| tick(every))?;
    Ok(vec![
        stats(ra, &pa),
        stats(rb, &pb),
        stats(rc, &pa),
        stats(rd, &pd),
    ])
}

/// Band statistics of one run of `steps` steps sampled every `every`, over
/// the second half (MODEL.md A11).
pub fn run_bands(params: Params, rules: Rules, seed: u64, steps: u64, every: u64) -> Result<Bands> {
    let mut pipe = Pipe::new(params, rules, seed)?;
    let rec = record(&mut pipe, steps, every, |_| {})?;
    Ok(bands(
        &rec,
        rec.n.len() / 2,
        params.rho,
        params.bin,
        params.width,
    ))
}
