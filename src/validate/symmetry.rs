//! Level 2 of `validate`, the symmetry probes (VALIDATION.md "Pipe level 2:
//! symmetry probes"): what the exact process guarantees about where and when,
//! tested on the candidate's own runs.
//!
//! - *Translation along the periodic pipe* (MODEL.md A7-A8): every row is
//!   equivalent to every other, so the time-averaged occupation of a row,
//!   channel by channel, has the pooled mean of its run. A defect at a fixed
//!   set of rows (a tile seam, a word boundary of bit-sliced lanes, the wrap
//!   of the periodic pipe) shows as rows off that mean.
//! - *Mirror across the pipe* (MODEL.md A1, A6): column x and column W-1-x
//!   are equivalent with the channels mirrored (left and right swapped), in
//!   a pipe of odd width (so that the mirror keeps the column parity of the
//!   hexagonal lattice). A defect at a fixed set of columns (a word boundary
//!   at x = 64) shows as an asymmetry.
//! - *Stationarity*: the fraction of the particles in each channel in an
//!   early and a late window of the same runs, reference against candidate
//!   in each window and in the change from early to late; a defect that
//!   starts late (a counter that wraps, a stream reused or reseeded) shows in
//!   the late window.
//!
//! Every test gives one p-value; they join the Holm family of level 2
//! ([`super::scenes::level2`]), so the family-wise false-alarm rate of the
//! level stays [`super::ALPHA`].

use super::candidate::{check_identity, Candidate, RunPlan, Sample};
use super::scenes::{mean_se, welch, Comparison, Sampling, CANDIDATE_SALT};
use crate::analysis::sequential::normal_sf;
use crate::analysis::stats::student_t_sf;
use crate::error::{Error, ErrorKind, Result};
use crate::pipe::observables::contrast;
use crate::pipe::{Boundary, Params};
use crate::run::{derive_seed, Tier};
use serde::Serialize;

/// One probe scene: a pipe run long, sampled with its sites (for the row and
/// column profiles) or with its channel counts only (for the windows).
#[derive(Debug, Clone, Serialize)]
pub struct Probe {
    /// Name, e.g. `rows`.
    pub name: &'static str,
    /// The pipe.
    pub params: Params,
    /// Steps before the first sample counts.
    pub warmup: u64,
    /// Steps sampled after the warm-up (two windows of half each).
    pub steps: u64,
    /// Sampling interval.
    pub every: u64,
    /// Row and column profiles (the samples list the sites).
    pub profiles: bool,
    /// Early and late windows.
    pub windows: bool,
}

/// The probe scenes at `tier`: `rows` (W = 11, L = 200: L above 64 and not
/// a multiple of it, so three word boundaries of 64-row lanes and the wrap
/// lie inside), `wide` (W = 71: columns across x = 64) and `long` (two
/// windows of 4000 steps at quick; at standard 70000 steps in all, past
/// 2^16, where a 16-bit counter wraps). PH94 Fig. 2 parameters otherwise.
pub fn probes(tier: Tier) -> Vec<Probe> {
    let f = tier.pick(1, 4, 4);
    let fig2 = Params::default();
    vec![
        Probe {
            name: "rows",
            params: Params {
                length: 200,
                ..fig2
            },
            warmup: 500,
            steps: 3000 * f,
            every: 10 * f.min(2),
            profiles: true,
            windows: false,
        },
        Probe {
            name: "wide",
            params: Params {
                width: 71,
                length: 20,
                ..fig2
            },
            warmup: 500,
            steps: 2000 * f,
            every: 10 * f.min(2),
            profiles: true,
            windows: false,
        },
        Probe {
            name: "long",
            params: Params {
                length: 100,
                boundary: Boundary::Open { inject: 0.3 },
                ..fig2
            },
            warmup: 1000,
            steps: tier.pick(16000, 69000, 69000),
            every: 10,
            profiles: false,
            windows: true,
        },
    ]
}

/// Jobs of [`compare`] (one per run), for the progress bar.
pub fn jobs(tier: Tier, runs: usize) -> u64 {
    2 * runs as u64 * probes(tier).len() as u64
}

/// Site updates of both engines in [`compare`].
pub fn site_updates(tier: Tier, runs: usize) -> f64 {
    let per: f64 = probes(tier)
        .iter()
        .map(|p| ((p.warmup + p.steps) as usize * p.params.sites()) as f64)
        .sum();
    2.0 * runs as f64 * per
}

/// What one run gives: per row and per column, the mean number of particles
/// per site in each channel (index 7: all channels); per window, the
/// fraction of the particles in each channel.
#[derive(Debug, Clone, Default)]
pub struct RunProfile {
    /// `rows[y][c]`.
    pub rows: Vec<[f64; 8]>,
    /// `columns[x][c]`.
    pub columns: Vec<[f64; 8]>,
    /// `windows[w][o]`, w = 0 early, 1 late, o one of [`WINDOW_OBSERVABLES`].
    pub windows: Vec<[f64; 8]>,
}

/// The profile of a run of `probe` from its samples after the warm-up.
pub fn profile(probe: &Probe, samples: &[Sample]) -> Result<RunProfile> {
    let p = &probe.params;
    let s: Vec<&Sample> = samples.iter().filter(|s| s.t > probe.warmup).collect();
    let mut out = RunProfile::default();
    if probe.profiles {
        let (mut rows, mut columns) = (vec![[0.0; 8]; p.length], vec![[0.0; 8]; p.width]);
        for x in &s {
            let sites = x.sites.as_ref().ok_or_else(|| {
                Error::new(
                    ErrorKind::Io,
                    format!("the sample at t = {} lists no sites", x.t),
                )
            })?;
            for &(cx, cy, state) in sites {
                for c in (0..7).filter(|c| state >> c & 1 == 1) {
                    rows[cy][c] += 1.0;
                    columns[cx][c] += 1.0;
                }
            }
        }
        let n = s.len() as f64;
        for (v, per) in [(&mut rows, p.width), (&mut columns, p.length)] {
            for r in v.iter_mut() {
                r[7] = r[..7].iter().sum();
                r.iter_mut().for_each(|a| *a /= n * per as f64);
            }
        }
        (out.rows, out.columns) = (rows, columns);
    }
    if probe.windows {
        let half = probe.warmup + probe.steps / 2;
        for (lo, hi) in [(probe.warmup, half), (half, probe.warmup + probe.steps)] {
            let w: Vec<&&Sample> = s.iter().filter(|x| x.t > lo && x.t <= hi).collect();
            let mut f = [0.0; 8];
            for x in &w {
                let total = x.channels.iter().sum::<u64>().max(1) as f64;
                for (fc, &n) in f.iter_mut().zip(&x.channels) {
                    *fc += n as f64 / total / w.len() as f64;
                }
                f[7] += contrast(&x.bins) / w.len() as f64;
            }
            out.windows.push(f);
        }
    }
    Ok(out)
}

/// The profiles of `runs` runs of every probe by `cand` from base seed
/// `seed` (seeds apart from those of the scenes).
pub fn run_probes(
    cand: &dyn Candidate,
    probes: &[Probe],
    rules: &str,
    runs: usize,
    seed: u64,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Vec<RunProfile>>> {
    probes
        .iter()
        .enumerate()
        .map(|(pi, pr)| {
            crate::run::ensemble(runs, |r| {
                let plan = RunPlan {
                    params: pr.params,
                    rules: rules.to_string(),
                    seed: derive_seed(seed, ((100 + pi) * 1_000_003 + r) as u64),
                    steps: pr.warmup + pr.steps,
                    every: pr.every,
                    init: None,
                    sites: pr.profiles,
                };
                let samples = cand.run(&plan)?;
                for s in &samples {
                    check_identity(&s.bins, &s.channels).map_err(|why| {
                        Error::new(
                            ErrorKind::Io,
                            format!(
                                "candidate `{}`: its sample at t = {} {why}",
                                cand.name(),
                                s.t
                            ),
                        )
                    })?;
                }
                let o = profile(pr, &samples);
                tick();
                o
            })
            .into_iter()
            .collect()
        })
        .collect()
}

/// The observables of a window: the fraction of the particles in each
/// channel, and the contrast C of the bins (MODEL.md A9).
pub const WINDOW_OBSERVABLES: [&str; 8] = [
    "fraction rest",
    "fraction up",
    "fraction up-left",
    "fraction down-left",
    "fraction down",
    "fraction down-right",
    "fraction up-right",
    "contrast",
];

/// The mirror image of channel `c` (left and right swapped).
pub fn mirror(c: usize) -> usize {
    [0, 1, 6, 5, 4, 3, 2, 7][c]
}

/// The channel groups of the profile tests, each well populated in the
/// probe scenes (a channel that is almost never occupied, such as `up`
/// under gravity, gives counts too small for the normal tail of the
/// rows test): the rest particles, the falling ones, the diagonal movers
/// and all particles (a group's mirror image is the group).
pub const GROUPS: [(&str, &[usize]); 4] = [
    ("rest", &[0]),
    ("down", &[4]),
    ("diagonal", &[2, 3, 5, 6]),
    ("all", &[7]),
];

/// The profile of a group: `v` summed over its channels.
fn group(v: &[f64; 8], g: &[usize]) -> f64 {
    g.iter().map(|&c| v[c]).sum()
}

/// Translation test of one channel `c` over the rows: `r` and `k` the
/// reference's and the candidate's runs. Each run's row profile minus its
/// own mean over the rows is d(y), of mean 0 at every row. The noise of
/// d(y), the same at every row, is pooled over the rows and the runs of both
/// engines (the candidate's about its row means); the candidate's mean d(y)
/// over its runs is z(y) standard errors from 0. Statistic: max |z(y)|;
/// p-value: Bonferroni over the rows, L P(|Z| > max |z|). Returns the
/// reference's and the candidate's max |z|, the candidate's row of it, and
/// the p-value.
pub fn rows_test(r: &[RunProfile], k: &[RunProfile], g: &[usize]) -> (f64, f64, usize, f64) {
    let dev = |runs: &[RunProfile]| -> Vec<Vec<f64>> {
        runs.iter()
            .map(|p| {
                let m = p.rows.iter().map(|v| group(v, g)).sum::<f64>() / p.rows.len() as f64;
                p.rows.iter().map(|v| group(v, g) - m).collect()
            })
            .collect()
    };
    let (dr, dk) = (dev(r), dev(k));
    let l = dr[0].len();
    let means = |d: &[Vec<f64>]| -> Vec<f64> {
        (0..l)
            .map(|y| d.iter().map(|v| v[y]).sum::<f64>() / d.len() as f64)
            .collect()
    };
    let (mr, mk) = (means(&dr), means(&dk));
    let ss_r: f64 = dr.iter().flatten().map(|x| x * x).sum();
    let ss_k: f64 = dk
        .iter()
        .map(|v| v.iter().zip(&mk).map(|(x, m)| (x - m).powi(2)).sum::<f64>())
        .sum();
    let sigma = ((ss_r + ss_k) / (l as f64 * (dr.len() + dk.len() - 1) as f64)).sqrt();
    let max_z = |m: &[f64], n: usize| -> (f64, usize) {
        m.iter()
            .map(|x| zscore(*x, sigma / (n as f64).sqrt()))
            .enumerate()
            .fold((0.0, 0), |a, (y, z)| if z > a.0 { (z, y) } else { a })
    };
    let (zr, _) = max_z(&mr, dr.len());
    let (zk, row) = max_z(&mk, dk.len());
    let p = (l as f64 * 2.0 * normal_sf(zk)).min(1.0);
    (zr, zk, row, p)
}

/// |x| / se, with 0 / 0 = 0 and x / 0 = infinity.
fn zscore(x: f64, se: f64) -> f64 {
    if se > 0.0 {
        (x / se).abs()
    } else if x == 0.0 {
        0.0
    } else {
        f64::INFINITY
    }
}

/// Mirror test of one channel `c` over the columns of a pipe of odd width:
/// per run, a(x) = occupation of c in column x minus that of its mirror
/// channel in column W-1-x, for x < (W-1)/2, of mean 0. For each x the
/// candidate's mean a(x) against 0 by Student's t with the variance pooled
/// over both engines' runs (each about its own mean; n_r + n_k - 2 degrees
/// of freedom); p-value: Bonferroni over the columns. Returns the
/// reference's and the candidate's largest |t|, the candidate's column of
/// it, and the p-value.
pub fn columns_test(r: &[RunProfile], k: &[RunProfile], g: &[usize]) -> (f64, f64, usize, f64) {
    let w = r[0].columns.len();
    let pairs = (w - 1) / 2;
    let a = |p: &RunProfile, x: usize| group(&p.columns[x], g) - group(&p.columns[w - 1 - x], g);
    let df = r.len() + k.len() - 2;
    let (mut best, mut best_ref, mut col) = (0.0f64, 0.0f64, 0);
    for x in 0..pairs {
        let ar: Vec<f64> = r.iter().map(|p| a(p, x)).collect();
        let ak: Vec<f64> = k.iter().map(|p| a(p, x)).collect();
        let ss = |v: &[f64]| {
            let m = mean_se(v).0;
            v.iter().map(|y| (y - m).powi(2)).sum::<f64>()
        };
        let s = ((ss(&ar) + ss(&ak)) / df as f64).sqrt();
        let tk = zscore(mean_se(&ak).0, s / (ak.len() as f64).sqrt());
        let tr = zscore(mean_se(&ar).0, s / (ar.len() as f64).sqrt());
        best_ref = best_ref.max(tr);
        if tk > best {
            (best, col) = (tk, x);
        }
    }
    let p = if best.is_infinite() {
        0.0
    } else {
        let one = 2.0 * student_t_sf(best, df.max(1)).expect("df >= 1");
        (pairs as f64 * one).min(1.0)
    };
    (best_ref, best, col, p)
}

/// A comparison row of a max-type test (the p-value's Holm decision comes
/// later, over the whole level).
fn max_row(scene: &str, observable: String, (zr, zk, p): (f64, f64, f64)) -> Comparison {
    Comparison {
        scene: scene.to_string(),
        observable,
        reference: (zr, 0.0),
        candidate: (zk, 0.0),
        difference: zk - zr,
        p_value: p,
        holm_threshold: 0.0,
        differs: false,
    }
}

/// One value of a run's profile.
type Pick<'a> = &'a dyn Fn(&RunProfile) -> f64;

/// Every test of every probe: reference profiles `r`, candidate profiles
/// `k` (one list per probe), without the Holm decisions.
pub fn tests(probes: &[Probe], r: &[Vec<RunProfile>], k: &[Vec<RunProfile>]) -> Vec<Comparison> {
    let mut out = Vec::new();
    for (pi, pr) in probes.iter().enumerate() {
        let (r, k) = (&r[pi], &k[pi]);
        if pr.profiles && pr.params.boundary == Boundary::Periodic {
            for (name, g) in GROUPS {
                let (zr, zk, y, p) = rows_test(r, k, g);
                let what = format!("rows {name}: max |z| (row {y})");
                out.push(max_row(pr.name, what, (zr, zk, p)));
            }
        }
        if pr.profiles && pr.params.width % 2 == 1 && pr.params.width >= 3 {
            for (name, g) in GROUPS {
                let (tr, tk, x, p) = columns_test(r, k, g);
                let what = format!("mirror {name}: max |t| (column {x})");
                out.push(max_row(pr.name, what, (tr, tk, p)));
            }
        }
        if pr.windows {
            for (c, obs) in WINDOW_OBSERVABLES.iter().enumerate() {
                let f = |runs: &[RunProfile], g: Pick| -> Vec<f64> { runs.iter().map(g).collect() };
                let cases: [(&str, Pick); 3] = [
                    ("early", &|p| p.windows[0][c]),
                    ("late", &|p| p.windows[1][c]),
                    ("late - early", &|p| p.windows[1][c] - p.windows[0][c]),
                ];
                for (name, g) in cases {
                    let (rv, kv) = (f(r, g), f(k, g));
                    let (rm, km) = (mean_se(&rv), mean_se(&kv));
                    out.push(Comparison {
                        scene: pr.name.to_string(),
                        observable: format!("{obs} ({name})"),
                        reference: rm,
                        candidate: km,
                        difference: km.0 - rm.0,
                        p_value: welch(&rv, &kv),
                        holm_threshold: 0.0,
                        differs: false,
                    });
                }
            }
        }
    }
    out
}

/// The symmetry probes of `cand` against `reference` at `tier`: every test,
/// without the Holm decisions (level 2 makes them over all its tests).
pub fn compare(
    (reference, cand): (&dyn Candidate, &dyn Candidate),
    tier: Tier,
    rules: &str,
    sampling: Sampling,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<Comparison>> {
    let probes = probes(tier);
    let (runs, seed) = (sampling.runs, sampling.seed);
    let r = run_probes(reference, &probes, rules, runs, seed, tick)?;
    let k = run_probes(cand, &probes, rules, runs, seed ^ CANDIDATE_SALT, tick)?;
    Ok(tests(&probes, &r, &k))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn flat(rows: usize, bump: f64, seed: u64) -> RunProfile {
        // a flat profile with small deterministic noise and a bump at row 3
        let mut p = RunProfile::default();
        for y in 0..rows {
            let noise = (((y as u64 * 2654435761 + seed * 40503) % 1000) as f64 - 500.0) * 1e-5;
            let v = 1.0 + noise + if y == 3 { bump } else { 0.0 };
            p.rows.push([v; 8]);
        }
        p.columns = p.rows.clone();
        p
    }

    #[test]
    fn a_bump_at_one_row_is_found_there() {
        let r: Vec<RunProfile> = (0..8).map(|s| flat(50, 0.0, s)).collect();
        let k: Vec<RunProfile> = (8..16).map(|s| flat(50, 0.05, s)).collect();
        let (_, z, row, p) = rows_test(&r, &k, &[0]);
        assert_eq!(row, 3);
        assert!(z > 10.0 && p < 1e-10, "z {z} p {p}");
        let k0: Vec<RunProfile> = (8..16).map(|s| flat(50, 0.0, s)).collect();
        assert!(rows_test(&r, &k0, &[0]).3 > 1e-3);
    }

    #[test]
    fn the_mirror_swaps_left_and_right() {
        for c in 0..8 {
            assert_eq!(mirror(mirror(c)), c);
        }
        let (l, r) = (
            crate::lattice::velocity(2),
            crate::lattice::velocity(mirror(2)),
        );
        assert_eq!((l.0, l.1), (-r.0, r.1));
    }
}
