//! Level 1 of `validate`: rule conformance (MODEL.md A2-A7). For every state of a
//! site alone in an otherwise empty pipe, the reference engine's exact
//! one-step outcome distribution (enumerated over every branch of every
//! draw, [`crate::pipe::draws::Enumerator`]), at the interior, both walls,
//! W = 1 and W = 2, and both ends of the open pipe; and a probe that
//! measures a candidate's outcome frequencies on the same isolated sites and
//! compares them with the table by exact binomial tests.
//!
//! An outcome is the set of particles after the step, each as (x, y - y0,
//! channel) relative to the probe site (x0, y0), and the change of the flux
//! counters. In the periodic probes many probe sites, 9 rows apart, share
//! one pipe. In one step a particle moves at most 1 row, plus 1 row per hop
//! of a relocation walk when collisions come before gravity (the relocated
//! rest particle then falls); a probe site 4 rows from either block edge is
//! thus isolated unless a walk takes 4 hops or more (in an empty pipe the
//! first hop lands on an empty site, so longer walks need several extra
//! particles to meet on one site). Blocks 5 rows apart were too close: with
//! collision before gravity a two-hop walk and a fall reach the next block,
//! and the reference itself failed level 1 for every reading without
//! `gravity-first` (found while writing the fast engine).

use super::candidate::{Candidate, RunPlan};
use crate::error::{Error, Result};
use crate::pipe::draws::Enumerator;
use crate::pipe::engine::PipeEngine;
use crate::pipe::{Boundary, Params, Pipe, Rules};
use crate::run::derive_seed;
use serde::Serialize;
use std::collections::BTreeMap;

/// Rows per probe block in the periodic probes (the probe site is row 4).
pub const BLOCK: usize = 9;
/// Row of the probe site inside its block.
const Y0: usize = 4;

/// Where a probe site sits.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Probe {
    /// Name, e.g. `interior-even`.
    pub name: &'static str,
    /// Pipe width W.
    pub width: usize,
    /// Column of the probe site.
    pub x: usize,
    /// Open pipe of [`BLOCK`] rows without injection (else periodic).
    pub open: bool,
    /// In the open pipe: the probe site is the top row (else the bottom).
    pub top: bool,
}

/// The probes: interior (even and odd column), both walls (even and odd
/// right-wall column), W = 1, W = 2, and the two ends of the open pipe (W =
/// 3, middle column, no injection: the exits; the injection is compared at
/// level 2).
pub fn probes() -> Vec<Probe> {
    let per = |name, width, x| Probe {
        name,
        width,
        x,
        open: false,
        top: false,
    };
    let open = |name, top| Probe {
        name,
        width: OPEN_WIDTH + 1,
        x: OPEN_WIDTH / 2,
        open: true,
        top,
    };
    vec![
        per("interior-even", 5, 2),
        per("interior-odd", 5, 1),
        per("left-wall", 5, 0),
        per("right-wall-even", 5, 4),
        per("right-wall-odd", 6, 5),
        per("w1", 1, 0),
        per("w2-left", 2, 0),
        per("w2-right", 2, 1),
        open("open-bottom", false),
        open("open-top", true),
    ]
}

/// Whether the reading `rules` runs on `probe`'s pipe and its probe site
/// can hold `state`: with `wall-sites` (READINGS.md P12) the probes of W <
/// 3 have no column between the walls, and a wall site holds only its two
/// inward diagonals; the other (probe, state) pairs are left out of level 1.
pub fn holds(probe: &Probe, rules: Rules, state: u8) -> bool {
    let width = if probe.open {
        OPEN_WIDTH + 1
    } else {
        probe.width
    };
    if rules.wall_sites && width < 3 {
        return false;
    }
    state & !rules.channels_of_column(probe.x, width) == 0
}

/// The (probe index, state) pairs of level 1 under `rules` ([`holds`]).
pub fn cases(rules: Rules) -> Vec<(usize, u8)> {
    let probes = probes();
    (0..probes.len())
        .flat_map(|p| (0..128u8).map(move |s| (p, s)))
        .filter(|&(p, s)| holds(&probes[p], rules, s))
        .collect()
}

/// Columns per probe block of the open probes, the probe in the middle. Even,
/// so that every probe column has the same parity (the odd columns are
/// offset by half a row, MODEL.md A1); 6, so that the walls (column 0 and
/// the extra last column) are 3 columns from every probe and no particle
/// reaches them in one step unless a relocation walk takes 3 hops.
const OPEN_WIDTH: usize = 6;

impl Probe {
    /// The pipe of `blocks` probe sites: stacked along the pipe (periodic,
    /// [`BLOCK`] rows each) or across it (open, [`OPEN_WIDTH`] columns each plus a
    /// last wall column, the probe in the middle; a particle moves at most
    /// one column in a step, a relocated one two).
    fn params(&self, base: &Params, blocks: usize) -> Params {
        let (width, length, boundary) = if self.open {
            (
                OPEN_WIDTH * blocks + 1,
                BLOCK,
                Boundary::Open { inject: 0.0 },
            )
        } else {
            (self.width, BLOCK * blocks, Boundary::Periodic)
        };
        Params {
            width,
            length,
            bin: BLOCK,
            boundary,
            ..*base
        }
    }

    /// The probe site of block `k`.
    fn site(&self, k: usize) -> (usize, usize) {
        match (self.open, self.top) {
            (false, _) => (self.x, BLOCK * k + Y0),
            (true, false) => (OPEN_WIDTH * k + self.x, 0),
            (true, true) => (OPEN_WIDTH * k + self.x, BLOCK - 1),
        }
    }

    /// The block of an occupied site (x, y).
    fn block(&self, x: usize, y: usize) -> usize {
        if self.open {
            x / OPEN_WIDTH
        } else {
            y / BLOCK
        }
    }

    /// Shift a site of block `k` to block 0.
    fn to_block0(self, k: usize, (x, y, s): (usize, usize, u8)) -> (usize, usize, u8) {
        if self.open {
            (x - OPEN_WIDTH * k, y, s)
        } else {
            (x, y - BLOCK * k, s)
        }
    }
}

/// One outcome: particles (x, y - y0, channel), sorted, and the change of
/// (injected, out at the bottom, out at the top).
pub type Outcome = (Vec<(usize, i64, u8)>, [u64; 3]);

fn key((parts, flux): &Outcome) -> String {
    let p: Vec<String> = parts
        .iter()
        .map(|(x, dy, c)| format!("{x}:{dy}:{c}"))
        .collect();
    format!("{}|{}:{}:{}", p.join(","), flux[0], flux[1], flux[2])
}

/// The particles of `sites` as (x, y - y0, channel), sorted.
fn particles(sites: &[(usize, usize, u8)], y0: usize) -> Vec<(usize, i64, u8)> {
    let mut v = Vec::new();
    for &(x, y, s) in sites {
        for c in 0..7u8 {
            if s & (1 << c) != 0 {
                v.push((x, y as i64 - y0 as i64, c));
            }
        }
    }
    v.sort();
    v
}

/// The exact distribution of one (probe, state): outcome key -> probability,
/// and the probability mass of the paths cut at [`crate::pipe::draws::CUTOFF`]
/// (relocation walks of several extras; an upper bound on the error).
pub fn exact(
    probe: &Probe,
    base: &Params,
    rules: Rules,
    state: u8,
) -> Result<(BTreeMap<String, f64>, f64)> {
    let params = probe.params(base, 1);
    let (x0, y0) = probe.site(0);
    let mut pipe = Pipe::new(params, rules, 1)?;
    pipe.clear();
    let mut e = Some(Enumerator::new());
    let mut dist = BTreeMap::new();
    loop {
        let mut p = pipe.clone().with_draws(e.take().expect("enumerator"));
        p.set_site(x0, y0, state);
        p.step()?;
        let sites = PipeEngine::occupied_sites(&p);
        let f = p.flux();
        let o: Outcome = (particles(&sites, y0), [f.injected, f.out_bottom, f.out_top]);
        let mut en = p.into_draws();
        let prob = en.probability();
        if prob > 0.0 {
            *dist.entry(key(&o)).or_insert(0.0) += prob;
        }
        let cut = en.truncated_mass();
        if !en.advance() {
            return Ok((dist, cut));
        }
        e = Some(en);
    }
}

/// The exported table (`validate --export-table`): every probe and state.
#[derive(Debug, Clone, Serialize)]
pub struct Table {
    /// What the table is.
    pub about: &'static str,
    /// Parameters (W, L and the boundary are the probe's).
    pub params: Params,
    /// The rule reading.
    pub rules: String,
    /// Per probe: its geometry and, per state 0..128, the outcome keys and
    /// their probabilities.
    pub probes: Vec<TableProbe>,
    /// Largest probability mass, over all probes and states, of the
    /// enumeration paths cut at `CUTOFF` (a bound on each entry's error).
    pub max_truncated_mass: f64,
    /// The memory probes ([`super::memory`]): per probe, its start and the
    /// exact distribution of its trajectory.
    pub memory: Vec<super::memory::TableMemory>,
}

/// One probe of the [`Table`].
#[derive(Debug, Clone, Serialize)]
pub struct TableProbe {
    /// The probe.
    pub probe: Probe,
    /// Per state 0..128: outcome key -> probability.
    pub states: Vec<BTreeMap<String, f64>>,
}

/// Whether `--export-table` can serve `model`: the table is the pipe's
/// level 1 (the hopper's level 1 has no table of outcome probabilities).
///
/// Errors: `model` is the hopper alone ([`crate::ErrorKind::InvalidParameter`]).
pub fn exportable(model: super::Model) -> crate::Result<()> {
    if model == super::Model::Hopper {
        return Err(crate::Error::new(
            crate::ErrorKind::InvalidParameter,
            "--export-table writes the pipe's level-1 table; the hopper has none: drop --model hopper",
        ));
    }
    Ok(())
}

/// `validate --export-table`: the exact table of `rules` at the default
/// parameters, as JSON, to `path` (for an external candidate's own tests).
pub fn export_table(path: &std::path::Path, rules: Rules) -> Result<()> {
    let t = table(&Params::default(), rules)?;
    let text = serde_json::to_string(&t).map_err(|e| {
        crate::error::Error::new(
            crate::error::ErrorKind::Io,
            format!("{}: {e}", path.display()),
        )
    })?;
    crate::run::write_atomic(path, text.as_bytes())
}

/// The whole exact table for `base` (p, g, b) and `rules`.
pub fn table(base: &Params, rules: Rules) -> Result<Table> {
    let mut max_truncated_mass: f64 = 0.0;
    let mut out = Vec::new();
    for probe in probes() {
        if rules.wall_sites && !holds(&probe, rules, 0) {
            continue; // no pipe of this width under `wall-sites`
        }
        let mut states = Vec::new();
        for s in 0..128u8 {
            if !holds(&probe, rules, s) {
                states.push(BTreeMap::new()); // a state its site cannot hold
                continue;
            }
            let (d, cut) = exact(&probe, base, rules, s)?;
            max_truncated_mass = max_truncated_mass.max(cut);
            states.push(d);
        }
        out.push(TableProbe { probe, states });
    }
    Ok(Table {
        about: "exact one-step outcome distribution of a lone site (granular-automata validate, level 1); outcome key: particles x:dy:channel relative to the probe row, then |injected:out_bottom:out_top",
        params: *base,
        rules: rules.to_string(),
        probes: out,
        max_truncated_mass,
        memory: super::memory::table(base, rules)?,
    })
}

/// The measured outcome counts of a candidate: per probe, per state.
pub fn measure(
    cand: &dyn Candidate,
    probe: &Probe,
    base: &Params,
    rules: &str,
    state: u8,
    trials: usize,
    seed: u64,
) -> Result<BTreeMap<String, u64>> {
    let params = probe.params(base, trials);
    let init: Vec<_> = (0..trials)
        .map(|k| {
            let (x, y) = probe.site(k);
            (x, y, state)
        })
        .collect();
    let plan = RunPlan {
        params,
        rules: rules.to_string(),
        seed,
        steps: 1,
        every: 1,
        init: Some(init),
        sites: true,
    };
    let s = cand.run(&plan)?;
    let mut per_block: Vec<Vec<(usize, usize, u8)>> = vec![Vec::new(); trials];
    for &site in s[0].sites.as_deref().unwrap_or(&[]) {
        // (the open pipe's last wall column belongs to the last block)
        let k = probe.block(site.0, site.1).min(trials - 1);
        per_block[k].push(probe.to_block0(k, site));
    }
    // the flux of the open probes: per block, from the particles missing at
    // the ends (no injection; a probe's particles leave only through its end)
    let y0 = probe.site(0).1;
    let mut counts = BTreeMap::new();
    for b in &per_block {
        let parts = particles(b, y0);
        let flux = if probe.open {
            let before = state.count_ones() as u64;
            let lost = before.saturating_sub(parts.len() as u64);
            if probe.top {
                [0, 0, lost]
            } else {
                [0, lost, 0]
            }
        } else {
            [0, 0, 0]
        };
        *counts.entry(key(&(parts, flux))).or_insert(0u64) += 1;
    }
    Ok(counts)
}

/// ln(n!) (Stirling series beyond a table of exact values).
fn ln_factorial(n: u64) -> f64 {
    if n < 32 {
        return (1..=n).map(|k| (k as f64).ln()).sum();
    }
    let x = n as f64 + 1.0;
    (x - 0.5) * x.ln() - x + 0.5 * (2.0 * std::f64::consts::PI).ln() + 1.0 / (12.0 * x)
        - 1.0 / (360.0 * x.powi(3))
        + 1.0 / (1260.0 * x.powi(5))
}

/// The exact two-sided binomial p-value of `k` successes in `n` trials of
/// probability `q`: 2 min(P(X <= k), P(X >= k)), at most 1.
pub fn binomial_two_sided(k: u64, n: u64, q: f64) -> f64 {
    if q <= 0.0 {
        return if k == 0 { 1.0 } else { 0.0 };
    }
    if q >= 1.0 {
        return if k == n { 1.0 } else { 0.0 };
    }
    let (lq, lr) = (q.ln(), (1.0 - q).ln());
    let lnf = ln_factorial(n);
    let pmf = |x: u64| {
        (lnf - ln_factorial(x) - ln_factorial(n - x) + x as f64 * lq + (n - x) as f64 * lr).exp()
    };
    let lower: f64 = (0..=k).map(pmf).sum();
    let upper: f64 = (k..=n).map(pmf).sum();
    (2.0 * lower.min(upper)).min(1.0)
}

/// One (probe, state, outcome) whose frequency differs from the table.
#[derive(Debug, Clone, Serialize)]
pub struct Difference {
    /// Probe name.
    pub probe: String,
    /// The incoming state byte.
    pub state: u8,
    /// The outcome key.
    pub outcome: String,
    /// Its probability in the reference (0: impossible there).
    pub expected: f64,
    /// Its measured frequency.
    pub observed: f64,
    /// Trials.
    pub trials: usize,
    /// Exact two-sided binomial p-value.
    pub p_value: f64,
}

/// The result of level 1.
#[derive(Debug, Clone, Serialize)]
pub struct Level1 {
    /// Trials per (probe, state).
    pub trials: usize,
    /// Number of binomial tests (outcomes with 0 < q < 1).
    pub tests: usize,
    /// Family-wise false-alarm rate (Bonferroni over the tests; an outcome
    /// the reference cannot produce fails without a test).
    pub alpha: f64,
    /// Every (probe, state, outcome) that differs.
    pub differences: Vec<Difference>,
    /// Whether the candidate conforms (no difference).
    pub pass: bool,
}

/// Fewest level-1 trials per (probe, state) (`--trials`). The exact test
/// rejects at the Bonferroni threshold 0.01 / 3602 (the default table's
/// family): at 100 trials an outcome of probability 1/2 seen 26 times or
/// fewer (or 74 times or more) is rejected; at 20 trials only one never or
/// always seen, and at fewer not even that: the test cannot decide, and
/// every candidate with the right outcomes would pass.
pub const MIN_TRIALS: usize = 100;

/// Most level-1 trials per (probe, state) (`--trials`).
pub const MAX_TRIALS: usize = 1_000_000;

/// Level 1: measure `cand` on every probe and state with `trials` trials and
/// test every outcome's frequency against the exact table of the reference,
/// at family-wise false-alarm rate `alpha`.
pub fn level1(
    cand: &dyn Candidate,
    base: &Params,
    rules: &str,
    trials: usize,
    seed: u64,
    alpha: f64,
    tick: &(dyn Fn() + Sync),
) -> Result<Level1> {
    if !(MIN_TRIALS..=MAX_TRIALS).contains(&trials) {
        return Err(Error::out_of_range(
            "--trials",
            trials,
            &format!("{MIN_TRIALS}..={MAX_TRIALS}"),
        ));
    }
    let r: Rules = rules.parse()?;
    let probes = probes();
    let jobs = cases(r);
    let results = crate::run::ensemble(jobs.len(), |j| {
        let (pi, s) = jobs[j];
        let probe = &probes[pi];
        let (ex, _) = exact(probe, base, r, s)?;
        let seed = derive_seed(seed, j as u64);
        let obs = measure(cand, probe, base, rules, s, trials, seed)?;
        tick();
        Ok((pi, s, ex, obs))
    });
    let mut results: Vec<_> = results.into_iter().collect::<Result<_>>()?;
    // the memory probes (two sites over several steps), as two more jobs
    let mut names: Vec<&str> = probes.iter().map(|p| p.name).collect();
    for pair in super::memory::Pair::ALL {
        let memory_seed = derive_seed(seed, (jobs.len() + names.len()) as u64);
        let ex = super::memory::exact(pair, base, r)?;
        let n = trials / super::memory::TRIALS_DIVISOR;
        let obs = super::memory::measure(pair, cand, base, rules, n, memory_seed)?;
        tick();
        results.push((names.len(), crate::pipe::collision::REST_BIT, ex, obs));
        names.push(pair.name());
    }
    let tests: usize = results
        .iter()
        .map(|(_, _, ex, _)| ex.values().filter(|&&q| q < 1.0).count())
        .sum();
    let threshold = alpha / tests.max(1) as f64;
    let mut differences = Vec::new();
    for (pi, s, ex, obs) in &results {
        // trials of this probe: `trials`, or fewer for a memory probe
        let n: u64 = obs.values().sum();
        let mut diff = |outcome: &str, q: f64, k: u64, pv: f64| {
            differences.push(Difference {
                probe: names[*pi].to_string(),
                state: *s,
                outcome: outcome.to_string(),
                expected: q,
                observed: k as f64 / n as f64,
                trials: n as usize,
                p_value: pv,
            })
        };
        for (o, &k) in obs {
            if !ex.contains_key(o) {
                diff(o, 0.0, k, 0.0);
            }
        }
        for (o, &q) in ex {
            let k = obs.get(o).copied().unwrap_or(0);
            let pv = binomial_two_sided(k, n, q);
            if pv < threshold {
                diff(o, q, k, pv);
            }
        }
    }
    Ok(Level1 {
        trials,
        tests,
        alpha,
        pass: differences.is_empty(),
        differences,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binomial_p_values() {
        assert!((binomial_two_sided(5, 10, 0.5) - 1.0).abs() < 1e-12);
        // P(X <= 1) for n = 10, q = 0.5 is 11/1024
        assert!((binomial_two_sided(1, 10, 0.5) - 22.0 / 1024.0).abs() < 1e-12);
        assert_eq!(binomial_two_sided(3, 10, 0.0), 0.0);
        let big = binomial_two_sided(5000, 10000, 0.5);
        assert!(big > 0.99, "{big}");
        assert!(binomial_two_sided(4700, 10000, 0.5) < 1e-8);
    }

    #[test]
    fn the_fewest_trials_can_decide() {
        let threshold = 0.01 / 3602.0;
        let n = MIN_TRIALS as u64;
        assert!(binomial_two_sided(26, n, 0.5) < threshold);
        assert!(binomial_two_sided(27, n, 0.5) > threshold);
        assert!(binomial_two_sided(0, 20, 0.5) < threshold);
        assert!(binomial_two_sided(0, 19, 0.5) > threshold);
    }

    #[test]
    fn every_exact_distribution_sums_to_one_and_conserves_mass_inside() {
        let base = Params::default();
        for probe in probes() {
            for s in [0u8, 0b0000_0011, 0b0100_1001, 0b0111_1111, 0b0001_0101] {
                let (d, cut) = exact(&probe, &base, Rules::default(), s).unwrap();
                assert!(cut < 1e-6, "{} {s}: cut {cut}", probe.name);
                let total: f64 = d.values().sum();
                assert!((total - 1.0).abs() < 1e-9, "{} {s}: {total}", probe.name);
            }
        }
    }
}
