//! Level 2 of `validate`: statistical equivalence on scenes (MODEL.md A9).
//! Reference and candidate each run the same fixed list of short scenes on
//! disjoint seeds; every observable of every scene is compared by Welch's
//! two-sample t test, and the family of all tests of the report is
//! controlled by Holm's step-down procedure at a stated family-wise
//! false-alarm rate.

use super::candidate::{Candidate, RunPlan, Sample};
use crate::analysis::fit::{estimate_alpha, wave_velocity};
use crate::analysis::spectrum::{spctrm, SpectrumParams};
use crate::analysis::stats::student_t_sf;
use crate::error::Result;
use crate::lattice::velocity;
use crate::pipe::observables::{contrast, structure_factor};
use crate::pipe::{Boundary, Params};
use crate::run::{derive_seed, Tier};
use serde::Serialize;
use std::collections::BTreeMap;

/// Seeds of the candidate's runs are derived from the base seed xor this,
/// so reference and candidate never share a seed.
pub const CANDIDATE_SALT: u64 = 0xCA0D_1DA7_E000_0001;

/// One scene: a short version of a figure's set-up.
#[derive(Debug, Clone, Serialize)]
pub struct Scene {
    /// Name, e.g. `fig2`.
    pub name: &'static str,
    /// The pipe.
    pub params: Params,
    /// Steps before the first sample counts.
    pub warmup: u64,
    /// Steps sampled.
    pub steps: u64,
    /// Sampling interval.
    pub every: u64,
    /// Spectrum of bin 0 (m output frequencies, k = 1), if any.
    pub spectrum_m: Option<usize>,
}

/// The fixed list of scenes at `tier` (quick: seconds; standard: minutes):
/// PH94 Fig. 1a, the Fig. 2 set-up (with its spectrum), p = 0, b = 0 and the
/// open pipe at I = 0.3.
pub fn scenes(tier: Tier) -> Vec<Scene> {
    let f = tier.pick(1, 4, 4);
    let fig2 = Params::default();
    let sc = |name, params, warmup: u64, steps: u64, every, spectrum_m| Scene {
        name,
        params,
        warmup,
        steps: steps * f,
        every,
        spectrum_m,
    };
    vec![
        sc(
            "fig1a",
            Params {
                length: 440,
                p: 0.1,
                ..fig2
            },
            1000,
            2000,
            10,
            None,
        ),
        sc("fig2", fig2, 1000, 8192, 2, Some(1024 * f as usize)),
        sc("p0", Params { p: 0.0, ..fig2 }, 1000, 4000, 10, None),
        sc("b0", Params { b: 0.0, ..fig2 }, 1000, 4000, 10, None),
        sc(
            "open",
            Params {
                boundary: Boundary::Open { inject: 0.3 },
                ..fig2
            },
            2000,
            4000,
            10,
            None,
        ),
    ]
}

/// The observables of one run of `scene` from its samples after the warm-up.
pub fn observables(scene: &Scene, samples: &[Sample]) -> Result<BTreeMap<String, f64>> {
    let p = &scene.params;
    let s: Vec<&Sample> = samples.iter().filter(|s| s.t > scene.warmup).collect();
    let n = s.len() as f64;
    let sites = p.sites() as f64;
    let mean = |f: &dyn Fn(&Sample) -> f64| s.iter().map(|x| f(x)).sum::<f64>() / n;
    let mut o = BTreeMap::new();
    for c in 0..7 {
        o.insert(
            format!("occupation_{c}"),
            mean(&|x| x.channels[c] as f64 / sites),
        );
    }
    o.insert(
        "vertical_velocity".into(),
        mean(&|x| {
            let total: u64 = x.channels.iter().sum();
            let vy: f64 = (0..7).map(|c| x.channels[c] as f64 * velocity(c).1).sum();
            if total == 0 {
                0.0
            } else {
                vy / total as f64
            }
        }),
    );
    let k = p.bins() as f64;
    for q in 1..=3 {
        o.insert(format!("S{q}"), mean(&|x| structure_factor(&x.bins, q) / k));
    }
    o.insert("contrast".into(), mean(&|x| contrast(&x.bins)));
    let bin_var = (0..p.bins())
        .map(|i| {
            let m = s.iter().map(|x| x.bins[i]).sum::<f64>() / n;
            s.iter().map(|x| (x.bins[i] - m).powi(2)).sum::<f64>() / (n - 1.0)
        })
        .sum::<f64>()
        / k;
    o.insert("bin_variance".into(), bin_var);
    if let Some(m) = scene.spectrum_m {
        let series: Vec<f64> = s.iter().map(|x| x.bins[0]).collect();
        let sp = SpectrumParams {
            m,
            k: 1,
            ..SpectrumParams::default()
        };
        let spec = spctrm(&series, &sp)?;
        let est = estimate_alpha(&spec)?;
        o.insert("alpha".into(), est.fit.alpha);
        o.insert(
            "v_peak".into(),
            wave_velocity(p.length, est.j_peak, scene.every as usize, m),
        );
    }
    if let Boundary::Open { .. } = p.boundary {
        let outs: Vec<f64> = s
            .windows(2)
            .map(|w| (w[1].flux[1] - w[0].flux[1]) as f64 / scene.every as f64)
            .collect();
        let m = outs.iter().sum::<f64>() / outs.len() as f64;
        let sd =
            (outs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (outs.len() as f64 - 1.0)).sqrt();
        o.insert("outflow_rate".into(), m);
        o.insert("outflow_sd".into(), sd);
    }
    Ok(o)
}

/// Mean and standard error of `xs`.
pub fn mean_se(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / n;
    let v = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (v / n).sqrt())
}

/// Two-sided p-value of Welch's t test of equal means (degrees of freedom
/// by Welch-Satterthwaite, rounded down).
pub fn welch(a: &[f64], b: &[f64]) -> f64 {
    let ((ma, sa), (mb, sb)) = (mean_se(a), mean_se(b));
    if !(ma.is_finite() && mb.is_finite()) {
        return if ma.is_nan() && mb.is_nan() { 1.0 } else { 0.0 };
    }
    let se2 = sa * sa + sb * sb;
    if se2 == 0.0 {
        return if ma == mb { 1.0 } else { 0.0 };
    }
    let t = (ma - mb) / se2.sqrt();
    let (na, nb) = (a.len() as f64, b.len() as f64);
    let df = se2 * se2 / (sa.powi(4) / (na - 1.0) + sb.powi(4) / (nb - 1.0));
    let df = (df.floor() as usize).max(1);
    (2.0 * student_t_sf(t.abs(), df).expect("df >= 1")).min(1.0)
}

/// One compared observable.
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// Scene name.
    pub scene: String,
    /// Observable name.
    pub observable: String,
    /// Reference mean and standard error over its runs.
    pub reference: (f64, f64),
    /// Candidate mean and standard error over its runs.
    pub candidate: (f64, f64),
    /// Candidate - reference.
    pub difference: f64,
    /// Welch's two-sided p-value.
    pub p_value: f64,
    /// Holm's threshold for this test's rank.
    pub holm_threshold: f64,
    /// Rejected by Holm (the candidate differs here).
    pub differs: bool,
}

/// The result of level 2.
#[derive(Debug, Clone, Serialize)]
pub struct Level2 {
    /// Runs per engine per scene.
    pub runs: usize,
    /// Family-wise false-alarm rate (Holm over all comparisons).
    pub alpha: f64,
    /// Every comparison.
    pub comparisons: Vec<Comparison>,
    /// Site updates of both engines.
    pub site_updates: f64,
    /// Whether no comparison differs.
    pub pass: bool,
}

/// Per scene, per observable: the values of every run of `cand`.
pub fn run_scenes(
    cand: &dyn Candidate,
    scenes: &[Scene],
    rules: &str,
    runs: usize,
    seed: u64,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<BTreeMap<String, Vec<f64>>>> {
    scenes
        .iter()
        .enumerate()
        .map(|(si, sc)| {
            let per = crate::run::ensemble(runs, |r| {
                let plan = RunPlan {
                    params: sc.params,
                    rules: rules.to_string(),
                    seed: derive_seed(seed, (si * 1_000_003 + r) as u64),
                    steps: sc.warmup + sc.steps,
                    every: sc.every,
                    init: None,
                    sites: false,
                };
                let samples = cand.run(&plan)?;
                for s in &samples {
                    super::candidate::check_identity(&s.bins, &s.channels).map_err(|why| {
                        crate::Error::new(
                            crate::ErrorKind::Io,
                            format!(
                                "candidate `{}`: its sample at t = {} {why}",
                                cand.name(),
                                s.t
                            ),
                        )
                    })?;
                }
                let o = observables(sc, &samples);
                tick();
                o
            });
            let mut cols: BTreeMap<String, Vec<f64>> = BTreeMap::new();
            for o in per {
                for (k, v) in o? {
                    cols.entry(k).or_default().push(v);
                }
            }
            Ok(cols)
        })
        .collect()
}

/// Holm's step-down procedure: for p-values `ps`, the threshold alpha /
/// (m - rank) of each and whether it is rejected.
pub fn holm(ps: &[f64], alpha: f64) -> Vec<(f64, bool)> {
    let m = ps.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| ps[a].total_cmp(&ps[b]));
    let mut out = vec![(0.0, false); m];
    let mut still = true;
    for (rank, &i) in order.iter().enumerate() {
        let thr = alpha / (m - rank) as f64;
        still = still && ps[i] <= thr;
        out[i] = (thr, still);
    }
    out
}

/// Compare every observable of every scene (`names[i]` is scene i):
/// reference columns `r`, candidate columns `c` (observable -> one value per
/// run), Welch tests with Holm's correction at family-wise rate `alpha`.
pub fn compare(
    names: &[&str],
    r: &[BTreeMap<String, Vec<f64>>],
    c: &[BTreeMap<String, Vec<f64>>],
    alpha: f64,
) -> Vec<Comparison> {
    let mut comparisons = Vec::new();
    for (si, scene) in names.iter().enumerate() {
        for (name, rv) in &r[si] {
            let cv = &c[si][name];
            let (rm, cm) = (mean_se(rv), mean_se(cv));
            comparisons.push(Comparison {
                scene: scene.to_string(),
                observable: name.clone(),
                reference: rm,
                candidate: cm,
                difference: cm.0 - rm.0,
                p_value: welch(rv, cv),
                holm_threshold: 0.0,
                differs: false,
            });
        }
    }
    decide(&mut comparisons, alpha);
    comparisons
}

/// How level 2 samples (pipe and hopper): runs per engine per scene, the
/// reference's base seed (the candidate's seeds are disjoint from it), and
/// the family-wise false-alarm rate of the Holm family.
#[derive(Debug, Clone, Copy)]
pub struct Sampling {
    /// Runs per engine per scene, at least 3.
    pub runs: usize,
    /// Base seed of the reference's runs.
    pub seed: u64,
    /// Family-wise false-alarm rate.
    pub alpha: f64,
}

impl Sampling {
    /// A sampling of `runs` runs (an error below 3: Welch's test needs them).
    pub fn new(runs: usize, seed: u64, alpha: f64) -> Result<Self> {
        if runs < 3 {
            return Err(crate::Error::out_of_range(
                "level 2 runs per engine",
                runs,
                "[3, 10000]",
            ));
        }
        Ok(Sampling { runs, seed, alpha })
    }
}

/// Holm's decisions over every comparison of `cs` at family-wise rate
/// `alpha` (thresholds and rejections set in place).
pub fn decide(cs: &mut [Comparison], alpha: f64) {
    let ps: Vec<f64> = cs.iter().map(|c| c.p_value).collect();
    for (c, (thr, rej)) in cs.iter_mut().zip(holm(&ps, alpha)) {
        c.holm_threshold = thr;
        c.differs = rej;
    }
}

/// Level 2: compare `cand` with `reference` on every scene of the pipe
/// reading `rules`; the tests of `extra` (the symmetry probes, with their
/// site updates) join the same Holm family.
pub fn level2(
    (reference, cand): (&dyn Candidate, &dyn Candidate),
    scenes: &[Scene],
    rules: &str,
    sampling: Sampling,
    extra: (Vec<Comparison>, f64),
    tick: &(dyn Fn() + Sync),
) -> Result<Level2> {
    let Sampling { runs, seed, alpha } = sampling;
    let r = run_scenes(reference, scenes, rules, runs, seed, tick)?;
    let c = run_scenes(cand, scenes, rules, runs, seed ^ CANDIDATE_SALT, tick)?;
    let names: Vec<&str> = scenes.iter().map(|sc| sc.name).collect();
    let mut comparisons = compare(&names, &r, &c, alpha);
    comparisons.extend(extra.0);
    decide(&mut comparisons, alpha);
    let site_updates = extra.1
        + 2.0
            * runs as f64
            * scenes
                .iter()
                .map(|s| ((s.warmup + s.steps) as usize * s.params.sites()) as f64)
                .sum::<f64>();
    Ok(Level2 {
        runs,
        alpha,
        pass: !comparisons.iter().any(|c| c.differs),
        comparisons,
        site_updates,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holm_rejects_in_order_and_stops() {
        let r = holm(&[0.001, 0.04, 0.02, 0.5], 0.05);
        assert_eq!(r[0], (0.0125, true));
        assert_eq!(r[2], (0.05 / 3.0, false));
        assert!(!r[1].1 && !r[3].1);
    }

    #[test]
    fn welch_p_values() {
        let a = [1.0, 2.0, 3.0, 4.0];
        assert!((welch(&a, &a) - 1.0).abs() < 1e-12);
        let b = [11.0, 12.0, 13.0, 14.0];
        assert!(welch(&a, &b) < 1e-4);
        assert_eq!(welch(&[1.0, 1.0, 1.0], &[1.0, 1.0, 1.0]), 1.0);
        assert_eq!(welch(&[1.0, 1.0, 1.0], &[2.0, 2.0, 2.0]), 0.0);
    }
}
