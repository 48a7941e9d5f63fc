//! The hopper automaton (MODEL.md B3, B5): interaction, propagation with the
//! conflict rule, the dilation spacing, rain-filling and emptying.

use super::energy::{
    motion, orientation, state, DilationParams, DilationReading, EnergyParams, EnergyTable,
};
use super::geometry::{Geometry, GeometryParams, SiteKind, OFF};
use crate::error::{check_range, check_unit, Error, Result};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::{Deserialize, Serialize};

/// Site value of a hole.
pub const HOLE: u8 = 0;
/// Site value of a wall (and of the closed plug).
pub const WALL: u8 = 255;

/// Site value of a grain in state `s` (0..21).
pub fn grain(s: usize) -> u8 {
    s as u8 + 1
}

/// Whether a site value holds a grain.
pub fn is_grain(site: u8) -> bool {
    site != HOLE && site != WALL
}

/// The state (0..21) of a grain site value.
pub fn grain_state(site: u8) -> usize {
    site as usize - 1
}

/// Gaussian rain of MODEL.md B5: each iteration each empty site of the top
/// row receives a rest grain of random orientation with probability
/// `peak * exp(-(x - centre)^2 / (2 sigma^2))` (x in columns).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RainParams {
    /// Centre column; `None` is the outlet's column.
    pub centre: Option<f64>,
    /// Width sigma, in columns.
    pub sigma: f64,
    /// Peak probability per site and iteration.
    pub peak: f64,
}

impl Default for RainParams {
    /// Peak 0.5, sigma = 12 columns, centred on the outlet (MODEL.md B2).
    fn default() -> Self {
        RainParams {
            centre: None,
            sigma: 12.0,
            peak: 0.5,
        }
    }
}

/// The order of the interaction step (HOPPER_READINGS.md R5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum UpdateOrder {
    /// All grains choose at once from the previous iteration, then move
    /// (BB90: "simultaneously"; default).
    #[default]
    Synchronous,
    /// Wrong reading kept as a diagnostic (it contradicts "simultaneously"):
    /// grains choose and move one at a time in a random order, each seeing
    /// the moves already made (no conflicts can arise).
    Sequential,
}

/// What the losers of a conflict for one hole do (HOPPER_READINGS.md R4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum ConflictRule {
    /// The losers come to rest keeping the orientation they chose (default).
    #[default]
    KeepOrientation,
    /// The losers come to rest in the orientation they had before
    /// (`conflict-revert`).
    Revert,
}

/// The update rules of one iteration that the text leaves open (MODEL.md B3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub struct Dynamics {
    /// Order of the interaction step.
    pub order: UpdateOrder,
    /// The losers of a conflict.
    pub conflict: ConflictRule,
}

/// All parameters of a hopper run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
pub struct HopperParams {
    /// Container sizes (MODEL.md B2).
    pub geometry: GeometryParams,
    /// Energy (MODEL.md B4).
    pub energy: EnergyParams,
    /// Dilation spacing (MODEL.md B4).
    pub dilation: DilationParams,
    /// Filling (MODEL.md B5).
    pub rain: RainParams,
    /// Update order and conflict rule (MODEL.md B3).
    pub dynamics: Dynamics,
}

impl HopperParams {
    /// The quick-tier hopper: the small container, rain sigma 6 columns.
    pub fn quick() -> Self {
        HopperParams {
            geometry: GeometryParams::quick(),
            rain: RainParams {
                sigma: 6.0,
                ..Default::default()
            },
            ..Default::default()
        }
    }

    /// One line naming the rule variants.
    pub fn rules(&self) -> String {
        format!(
            "BB90 hopper (MODEL.md B): aligned = {}, rest pairs = {:?}, dilation = {:?} (K = {}, tau = {}), walls not in the energy sum, {:?} interaction, conflicts to the lowest E (losers: {:?}), rain sigma {}",
            self.energy.aligned.name(),
            self.energy.rest_pairs,
            self.dilation.reading,
            self.dilation.k,
            self.dilation.tau,
            self.dynamics.order,
            self.dynamics.conflict,
            self.rain.sigma
        )
    }
}

/// What one iteration did.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct StepReport {
    /// Grains that left through the outlet.
    pub outflow: u32,
    /// Grains that moved.
    pub moved: u32,
    /// Grains evaluated in the interaction step (the rest cost nothing).
    pub evaluated: u32,
    /// Grains added by rain.
    pub added: u32,
}

/// A running hopper: a pure function of (parameters, seed).
#[derive(Debug, Clone)]
pub struct Hopper {
    params: HopperParams,
    geom: Geometry,
    table: EnergyTable,
    rng: Xoshiro256PlusPlus,
    site: Vec<u8>,
    dil: Vec<f64>,
    // scratch
    next: Vec<u8>,
    next_dil: Vec<f64>,
    energy: Vec<f64>,
    claim: Vec<u32>,
    ties: Vec<u32>,
    movers: Vec<u32>,
    top_row: Vec<usize>,
    open: bool,
    added: u64,
    removed: u64,
    iteration: u64,
    site_updates: f64,
}

/// No claim on a target site.
const NONE: u32 = u32::MAX;

impl Hopper {
    /// An empty hopper with the plug closed.
    pub fn new(params: HopperParams, seed: u64) -> Result<Self> {
        let geom = Geometry::new(params.geometry)?;
        let table = EnergyTable::new(params.energy)?;
        params.dilation.validate()?;
        check_unit("rain peak", params.rain.peak)?;
        check_range("rain sigma", params.rain.sigma, 1e-3, 1e6)?;
        if let Some(c) = params.rain.centre {
            check_range("rain centre", c, 0.0, (params.geometry.width - 1) as f64)?;
        }
        let n = geom.kind.len();
        let site: Vec<u8> = geom
            .kind
            .iter()
            .map(|k| if *k == SiteKind::Inside { HOLE } else { WALL })
            .collect();
        let h = geom.height();
        let top_row: Vec<usize> = (0..geom.width())
            .map(|x| geom.index(x, h - 1))
            .filter(|&i| geom.kind[i] == SiteKind::Inside)
            .collect();
        if top_row.is_empty() {
            return Err(Error::out_of_range(
                "width",
                params.geometry.width,
                "a width that leaves inside sites on the top row",
            ));
        }
        Ok(Hopper {
            params,
            geom,
            table,
            rng: Xoshiro256PlusPlus::seed_from_u64(seed),
            next: site.clone(),
            site,
            dil: vec![1.0; n],
            next_dil: vec![1.0; n],
            energy: vec![0.0; n],
            claim: vec![NONE; n],
            ties: vec![0; n],
            movers: Vec::new(),
            top_row,
            open: false,
            added: 0,
            removed: 0,
            iteration: 0,
            site_updates: 0.0,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &HopperParams {
        &self.params
    }

    /// The container.
    pub fn geometry(&self) -> &Geometry {
        &self.geom
    }

    /// The energy tables.
    pub fn table(&self) -> &EnergyTable {
        &self.table
    }

    /// Site values (`HOLE`, `WALL` or `grain(s)`), index `y * width + x`.
    pub fn sites(&self) -> &[u8] {
        &self.site
    }

    /// Running averages D_i of the spacing (meaningful on grain sites).
    pub fn spacing(&self) -> &[f64] {
        &self.dil
    }

    /// Grains inside the hopper.
    pub fn grains(&self) -> u64 {
        self.added - self.removed
    }

    /// Grains added so far.
    pub fn added(&self) -> u64 {
        self.added
    }

    /// Grains removed through the outlet so far.
    pub fn removed(&self) -> u64 {
        self.removed
    }

    /// Iterations done.
    pub fn iteration(&self) -> u64 {
        self.iteration
    }

    /// Whether the plug is open.
    pub fn is_open(&self) -> bool {
        self.open
    }

    /// Grain evaluations plus site scans done so far (for summary.json).
    pub fn site_updates(&self) -> f64 {
        self.site_updates
    }

    /// Count the grains on the lattice (for the conservation test).
    pub fn count_grains(&self) -> u64 {
        self.site.iter().filter(|&&s| is_grain(s)).count() as u64
    }

    /// Open the plug: its wall sites become holes (MODEL.md B5).
    pub fn open(&mut self) {
        self.open = true;
        for (i, k) in self.geom.kind.iter().enumerate() {
            if *k == SiteKind::Plug {
                self.site[i] = HOLE;
            }
        }
    }

    fn hole(&self, j: u32) -> bool {
        j != OFF && self.site[j as usize] == HOLE
    }

    /// Energy of grain `i` in state `s` given its neighbourhood (MODEL.md B4).
    fn energy_of(&self, i: usize, s: usize, hole_below: bool) -> f64 {
        let mut e = self.table.gravity(hole_below, motion(s));
        for (k, &j) in self.geom.nbr[i].iter().enumerate() {
            if j == OFF {
                continue;
            }
            let sj = self.site[j as usize];
            if is_grain(sj) {
                let w = self.pair_weight(i, j as usize);
                // the neighbour lies in direction k + 1 (the bond's axis
                // matters under the along-bond reading of "aligned")
                e += self.table.pair_factor(s, grain_state(sj), k + 1) * w;
            }
        }
        e
    }

    fn pair_weight(&self, i: usize, j: usize) -> f64 {
        match self.params.dilation.reading {
            DilationReading::Unit => self.table.dilation_weight(1.0),
            _ => self
                .table
                .dilation_weight(0.5 * (self.dil[i] + self.dil[j])),
        }
    }

    /// The state grain `i` takes in the interaction step, from the current
    /// `site` array, and whether it was evaluated (MODEL.md B3); sets
    /// `energy[i]` for a moving choice.
    fn choose(&mut self, i: usize) -> (usize, bool) {
        let s = grain_state(self.site[i]);
        let nb = self.geom.nbr[i];
        let hole_below = self.hole(nb[2]) || self.hole(nb[3]) || self.hole(nb[4]);
        let moving_nbr = nb.iter().any(|&j| {
            j != OFF
                && is_grain(self.site[j as usize])
                && motion(grain_state(self.site[j as usize])) != 0
        });
        if hole_below || moving_nbr {
            // candidate motions: rest and the directions towards holes
            let mut cand = [0usize; 7];
            let mut nc = 1;
            for c in 1..=6 {
                if self.hole(nb[c - 1]) {
                    cand[nc] = c;
                    nc += 1;
                }
            }
            let mut best = f64::INFINITY;
            let mut best_s = s;
            let mut nties = 0u32;
            for o in 0..3 {
                for &v in &cand[..nc] {
                    let t = state(o, v);
                    let e = self.energy_of(i, t, hole_below);
                    let tol = 1e-9 * e.abs().max(1.0);
                    if nties == 0 || e < best - tol {
                        best = e;
                        best_s = t;
                        nties = 1;
                    } else if e <= best + tol {
                        nties += 1;
                        if self.rng.random_range(0..nties) == 0 {
                            best_s = t;
                        }
                    }
                }
            }
            self.energy[i] = best;
            (best_s, true)
        } else {
            let v = motion(s);
            if v != 0 && !self.hole(nb[v - 1]) {
                (state(orientation(s), 0), false)
            } else {
                if v != 0 {
                    self.energy[i] = self.energy_of(i, s, hole_below);
                }
                (s, false)
            }
        }
    }

    /// One iteration (MODEL.md B3), then rain if `rain` (MODEL.md B5), then
    /// the spacing update (MODEL.md B4).
    pub fn step(&mut self, rain: bool) -> StepReport {
        let mut report = StepReport::default();
        match self.params.dynamics.order {
            UpdateOrder::Synchronous => self.step_synchronous(&mut report),
            UpdateOrder::Sequential => self.step_sequential(&mut report),
        }
        self.finish_step(rain, report)
    }

    /// Interaction and propagation one grain at a time in a random order
    /// ([`UpdateOrder::Sequential`]).
    fn step_sequential(&mut self, report: &mut StepReport) {
        let n = self.site.len();
        self.movers.clear();
        for i in 0..n {
            if is_grain(self.site[i]) {
                self.movers.push(i as u32);
            }
        }
        for k in (1..self.movers.len()).rev() {
            let j = self.rng.random_range(0..=k);
            self.movers.swap(k, j);
        }
        // `ties` marks the sites that received a grain in this iteration
        let order = std::mem::take(&mut self.movers);
        for &i in &order {
            let i = i as usize;
            if !is_grain(self.site[i]) || self.ties[i] == 1 {
                continue;
            }
            let (new_s, evaluated) = self.choose(i);
            report.evaluated += evaluated as u32;
            let v = motion(new_s);
            if v == 0 {
                self.site[i] = grain(new_s);
                continue;
            }
            let t = self.geom.nbr[i][v - 1] as usize;
            report.moved += 1;
            if self.geom.kind[t] == SiteKind::Plug {
                report.outflow += 1;
            } else {
                self.site[t] = grain(new_s);
                self.dil[t] = self.dil[i];
                self.ties[t] = 1;
            }
            self.site[i] = HOLE;
        }
        for &i in &order {
            for j in self.geom.nbr[i as usize] {
                if j != OFF {
                    self.ties[j as usize] = 0;
                }
            }
        }
        self.movers = order;
        self.site_updates += n as f64 + 21.0 * report.evaluated as f64;
    }

    /// The synchronous interaction step and the propagation with the
    /// conflict rule (MODEL.md B3).
    fn step_synchronous(&mut self, report: &mut StepReport) {
        let n = self.site.len();
        self.movers.clear();
        // 1. interaction, synchronous on the previous states
        for i in 0..n {
            let si = self.site[i];
            if !is_grain(si) {
                self.next[i] = si;
                continue;
            }
            let (new_s, evaluated) = self.choose(i);
            report.evaluated += evaluated as u32;
            self.next[i] = grain(new_s);
            if motion(new_s) != 0 {
                self.movers.push(i as u32);
            }
        }
        self.site_updates += n as f64 + 21.0 * report.evaluated as f64;
        // 2. propagation with the conflict rule: the lowest E wins a hole
        for k in 0..self.movers.len() {
            let i = self.movers[k] as usize;
            let v = motion(grain_state(self.next[i]));
            let t = self.geom.nbr[i][v - 1] as usize;
            let c = self.claim[t];
            if c == NONE {
                self.claim[t] = i as u32;
                self.ties[t] = 1;
            } else {
                let (e, ec) = (self.energy[i], self.energy[c as usize]);
                let tol = 1e-9 * ec.abs().max(1.0);
                if e < ec - tol {
                    self.claim[t] = i as u32;
                    self.ties[t] = 1;
                } else if e <= ec + tol {
                    self.ties[t] += 1;
                    if self.rng.random_range(0..self.ties[t]) == 0 {
                        self.claim[t] = i as u32;
                    }
                }
            }
        }
        self.next_dil.copy_from_slice(&self.dil);
        for k in 0..self.movers.len() {
            let i = self.movers[k] as usize;
            let s = grain_state(self.next[i]);
            let t = self.geom.nbr[i][motion(s) - 1] as usize;
            if self.claim[t] == i as u32 {
                report.moved += 1;
                if self.geom.kind[t] == SiteKind::Plug {
                    report.outflow += 1;
                    self.next[t] = HOLE;
                } else {
                    self.next[t] = grain(s);
                    self.next_dil[t] = self.dil[i];
                }
                self.next[i] = HOLE;
            } else {
                let o = match self.params.dynamics.conflict {
                    ConflictRule::KeepOrientation => orientation(s),
                    ConflictRule::Revert => orientation(grain_state(self.site[i])),
                };
                self.next[i] = grain(state(o, 0));
            }
        }
        for k in 0..self.movers.len() {
            let i = self.movers[k] as usize;
            for j in self.geom.nbr[i] {
                if j != OFF {
                    self.claim[j as usize] = NONE;
                }
            }
        }
        std::mem::swap(&mut self.site, &mut self.next);
        std::mem::swap(&mut self.dil, &mut self.next_dil);
    }

    /// Outflow bookkeeping, rain (MODEL.md B5) and the spacing (MODEL.md B4).
    fn finish_step(&mut self, rain: bool, mut report: StepReport) -> StepReport {
        self.removed += report.outflow as u64;
        // 3. rain on the empty sites of the top row
        let mut fresh: Vec<usize> = Vec::new();
        if rain {
            let centre = self
                .params
                .rain
                .centre
                .unwrap_or(self.geom.centre_column as f64);
            let two_s2 = 2.0 * self.params.rain.sigma * self.params.rain.sigma;
            let w = self.geom.width();
            for k in 0..self.top_row.len() {
                let i = self.top_row[k];
                if self.site[i] != HOLE {
                    continue;
                }
                let x = (i % w) as f64;
                let p = self.params.rain.peak * (-(x - centre) * (x - centre) / two_s2).exp();
                if self.rng.random::<f64>() < p {
                    let o = self.rng.random_range(0..3usize);
                    self.site[i] = grain(state(o, 0));
                    fresh.push(i);
                    report.added += 1;
                }
            }
        }
        self.added += report.added as u64;
        // 4. spacing: rays of up to K steps, running average over tau
        self.update_spacing(&fresh);
        self.iteration += 1;
        report
    }

    /// r_i of MODEL.md B4 for every grain, then D_i += (r_i - D_i)/tau
    /// (D_i = r_i for the grains in `fresh`).
    fn update_spacing(&mut self, fresh: &[usize]) {
        let reading = self.params.dilation.reading;
        if reading == DilationReading::Unit {
            return;
        }
        let k = self.params.dilation.k;
        let tau = self.params.dilation.tau;
        let through = reading == DilationReading::RaysThroughWalls;
        for i in 0..self.site.len() {
            if !is_grain(self.site[i]) {
                continue;
            }
            let r = self.ray_mean(i, k, through);
            self.dil[i] += (r - self.dil[i]) / tau;
        }
        for &i in fresh {
            self.dil[i] = self.ray_mean(i, k, through);
        }
    }

    fn ray_mean(&self, i: usize, k: usize, through: bool) -> f64 {
        let mut sum = 0usize;
        for c in 0..6 {
            let mut j = i as u32;
            let mut s_c = k;
            for s in 1..=k {
                j = self.geom.nbr[j as usize][c];
                if j == OFF {
                    if !through {
                        s_c = s;
                    }
                    break;
                }
                let v = self.site[j as usize];
                if is_grain(v) || (v == WALL && !through) {
                    s_c = s;
                    break;
                }
            }
            sum += s_c;
        }
        sum as f64 / 6.0
    }

    /// Rain until `target` grains have been added or `max_iterations` passed,
    /// then step without rain until nothing moves (at most `max_settle`
    /// iterations). Returns the iterations done.
    pub fn fill(&mut self, target: u64, max_iterations: u64, max_settle: u64) -> u64 {
        let start = self.iteration;
        while self.added < target && self.iteration - start < max_iterations {
            self.step(true);
        }
        for _ in 0..max_settle {
            if self.step(false).moved == 0 {
                break;
            }
        }
        self.iteration - start
    }

    /// Energies E_i of every candidate state of grain `i` in the current
    /// configuration, as `(state, E)` (for inspection and tests).
    pub fn debug_energies(&self, i: usize) -> Vec<(usize, f64)> {
        let nb = self.geom.nbr[i];
        let hole_below = self.hole(nb[2]) || self.hole(nb[3]) || self.hole(nb[4]);
        let mut out = vec![];
        for o in 0..3 {
            for v in 0..7 {
                if v == 0 || self.hole(nb[v - 1]) {
                    out.push((state(o, v), self.energy_of(i, state(o, v), hole_below)));
                }
            }
        }
        out
    }

    /// Set site `i` to `value` (`HOLE` or a grain), keeping the grain count
    /// (prepared states of the engine contract, [`super::engine`]); a fresh
    /// grain starts at D_i = 1.
    pub fn set_site(&mut self, i: usize, value: u8) {
        if is_grain(self.site[i]) {
            self.added = self.added.saturating_sub(1);
        }
        if is_grain(value) {
            self.added += 1;
            self.dil[i] = 1.0;
        }
        self.site[i] = value;
    }

    /// Set the running mean spacing D_i of site `i` (prepared states).
    pub fn set_spacing(&mut self, i: usize, d: f64) {
        self.dil[i] = d;
    }

    /// This hopper with another energy table (the mutants of `validate`,
    /// `crate::validate::mutants`).
    pub fn with_table(mut self, table: EnergyTable) -> Self {
        self.table = table;
        self
    }

    /// Whether the grain at site `i` moved in the last iteration.
    pub fn moving(&self, i: usize) -> bool {
        is_grain(self.site[i]) && motion(grain_state(self.site[i])) != 0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lone_grain_falls_and_leaves() {
        let mut h = Hopper::new(HopperParams::quick(), 1).unwrap();
        h.open();
        let g = h.geometry().clone();
        let i = g.index(g.centre_column, 20);
        h.site[i] = grain(0);
        h.added = 1;
        let mut out = 0;
        for _ in 0..100 {
            out += h.step(false).outflow;
        }
        assert_eq!(out, 1);
        assert_eq!(h.count_grains(), 0);
    }
}
