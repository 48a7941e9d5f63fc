//! Level 1's memory probe: what the lone-site probes of
//! [`super::conformance`] cannot see. Those see one step of many isolated
//! sites, so a candidate whose every one-site distribution is exact passes
//! them even when its draws are correlated between neighbouring sites or
//! between steps (the bugs a counter-based generator keyed by site but not
//! by time, or one random word shared by two lanes, would make).
//!
//! The probes: two rest particles alone in a periodic pipe W = 4, L =
//! 9, for [`STEPS`] steps, one pipe per trial;
//! [`Pair::Across`] side by side (columns 1 and 2, row 4), [`Pair::Along`]
//! one above the other (column 1, rows 4 and 5), since an engine may lay
//! its lanes across the pipe or along it. A rest particle falls with
//! probability g per step (MODEL.md A5), independently of the other and of
//! its own past. The outcome is the whole trajectory (the occupied sites
//! after every step); its exact distribution comes from the reference by
//! enumerating every draw of the [`STEPS`] steps
//! ([`crate::pipe::draws::Enumerator`]), interactions included. Draws shared
//! by the two sites make them fall together; draws repeated from step to
//! step make a particle that stays at rest stay for ever.

use super::candidate::{Candidate, RunPlan, Sample};
use crate::error::{Error, ErrorKind, Result};
use crate::pipe::collision::REST_BIT;
use crate::pipe::draws::Enumerator;
use crate::pipe::engine::PipeEngine;
use crate::pipe::{Boundary, Params, Pipe, Rules};
use crate::run::derive_seed;
use std::collections::BTreeMap;

/// Where the two rest particles sit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pair {
    /// Side by side: (1, 4) and (2, 4).
    Across,
    /// One above the other: (1, 4) and (1, 5).
    Along,
}

impl Pair {
    /// Both probes.
    pub const ALL: [Pair; 2] = [Pair::Across, Pair::Along];

    /// The probe's name in level 1's differences.
    pub fn name(self) -> &'static str {
        match self {
            Pair::Across => "memory-across",
            Pair::Along => "memory-along",
        }
    }

    /// The prepared start.
    fn init(self) -> Vec<(usize, usize, u8)> {
        match self {
            Pair::Across => vec![(1, Y0, REST_BIT), (2, Y0, REST_BIT)],
            Pair::Along => vec![(1, Y0, REST_BIT), (1, Y0 + 1, REST_BIT)],
        }
    }
}
/// Steps of each trial.
pub const STEPS: u64 = 4;
/// Level-1 trials per lone-site state over trials of each memory probe: a
/// trial is a run of its own (a process for an external candidate), and
/// the correlations it looks for are gross (a pair that always falls
/// together, a particle that never falls).
pub const TRIALS_DIVISOR: usize = 4;
/// Rows of the probe's pipe (as a block of the lone-site probes).
const LENGTH: usize = 9;
/// Row of the lower rest particle (a falling particle reaches row 0 after
/// [`STEPS`] steps, without wrapping).
const Y0: usize = 4;

/// The probe's pipe: W = 4, L = 9, periodic, with p, g, b of `base`.
fn params(base: &Params) -> Params {
    Params {
        width: 4,
        length: LENGTH,
        bin: LENGTH,
        boundary: Boundary::Periodic,
        ..*base
    }
}

/// One trajectory: per step, the occupied sites "x:y:state" joined by ','.
fn key(per_step: &[Vec<(usize, usize, u8)>]) -> String {
    per_step
        .iter()
        .map(|sites| {
            let mut s: Vec<String> = sites
                .iter()
                .map(|(x, y, b)| format!("{x}:{y}:{b}"))
                .collect();
            s.sort();
            s.join(",")
        })
        .collect::<Vec<_>>()
        .join(" / ")
}

/// The exact distribution of the trajectory under the reference: key ->
/// probability.
pub fn exact(pair: Pair, base: &Params, rules: Rules) -> Result<BTreeMap<String, f64>> {
    let mut pipe = Pipe::new(params(base), rules, 1)?;
    pipe.clear();
    for (x, y, s) in pair.init() {
        pipe.set_site(x, y, s);
    }
    let mut e = Some(Enumerator::new());
    let mut dist = BTreeMap::new();
    loop {
        let mut p = pipe.clone().with_draws(e.take().expect("enumerator"));
        let mut path = Vec::new();
        for _ in 0..STEPS {
            p.step()?;
            path.push(PipeEngine::occupied_sites(&p));
        }
        let mut en = p.into_draws();
        let prob = en.probability();
        if prob > 0.0 {
            *dist.entry(key(&path)).or_insert(0.0) += prob;
        }
        if !en.advance() {
            return Ok(dist);
        }
        e = Some(en);
    }
}

/// One memory probe in the exported table (`validate --export-table`).
#[derive(Debug, Clone, serde::Serialize)]
pub struct TableMemory {
    /// The probe's name.
    pub name: &'static str,
    /// Its pipe (W, L, periodic; p, g, b of the table).
    pub params: Params,
    /// The prepared sites (x, y, state byte).
    pub init: Vec<(usize, usize, u8)>,
    /// Steps, a sample after each.
    pub steps: u64,
    /// Trajectory key (per step the sites "x:y:state" joined by ',', steps
    /// joined by " / ") -> probability.
    pub trajectories: BTreeMap<String, f64>,
}

/// Both memory probes for the exported table.
pub fn table(base: &Params, rules: Rules) -> Result<Vec<TableMemory>> {
    Pair::ALL
        .iter()
        .map(|&pair| {
            Ok(TableMemory {
                name: pair.name(),
                params: params(base),
                init: pair.init(),
                steps: STEPS,
                trajectories: exact(pair, base, rules)?,
            })
        })
        .collect()
}

/// The trajectory of one trial's samples.
fn trajectory(pair: Pair, samples: &[Sample]) -> Result<String> {
    if samples.len() != STEPS as usize {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "the candidate returned {} samples for the {} probe, not {STEPS}",
                samples.len(),
                pair.name()
            ),
        ));
    }
    let path: Vec<_> = samples
        .iter()
        .map(|s| s.sites.clone().unwrap_or_default())
        .collect();
    Ok(key(&path))
}

/// The candidate's trajectory counts over `trials` pipes, seeds derived
/// from `seed`.
pub fn measure(
    pair: Pair,
    cand: &dyn Candidate,
    base: &Params,
    rules: &str,
    trials: usize,
    seed: u64,
) -> Result<BTreeMap<String, u64>> {
    let runs = crate::run::ensemble(trials, |k| {
        let plan = RunPlan {
            params: params(base),
            rules: rules.to_string(),
            seed: derive_seed(seed, k as u64),
            steps: STEPS,
            every: 1,
            init: Some(pair.init()),
            sites: true,
        };
        trajectory(pair, &cand.run(&plan)?)
    });
    let mut counts = BTreeMap::new();
    for r in runs {
        *counts.entry(r?).or_insert(0u64) += 1;
    }
    Ok(counts)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Side by side: two independent geometric fall times, 5 x 5
    /// trajectories, and the one where both stay at rest has probability
    /// (1 - g)^(2 STEPS). One above the other, the same stay.
    #[test]
    fn the_exact_trajectories_are_two_independent_geometric_falls() {
        let base = Params::default();
        let along = exact(Pair::Along, &base, Rules::default()).unwrap();
        let still = (1.0 - base.g).powi(2 * STEPS as i32);
        assert!(along.values().any(|&q| (q - still).abs() < 1e-12));
        assert!((along.values().sum::<f64>() - 1.0).abs() < 1e-12);
        let d = exact(Pair::Across, &base, Rules::default()).unwrap();
        assert_eq!(d.len(), 25);
        let total: f64 = d.values().sum();
        assert!((total - 1.0).abs() < 1e-12);
        let stay = d.values().cloned().fold(0.0, f64::max);
        assert!((stay - 0.25).abs() < 1e-9, "{stay}"); // both fall at step 1
        assert!(d.values().any(|&q| (q - still).abs() < 1e-12));
    }
}
