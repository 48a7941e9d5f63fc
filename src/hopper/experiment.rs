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

    /// The outflow while more than `fraction` of the initial grains remained
    /// inside (the stationary window of BB90 Fig. 3).
    pub fn window(&self, fraction: f64) -> &[f64] {
        let limit = fraction * self.initial as f64;
        let n = self
            .inside
            .iter()
            .position(|&g| (g as f64) <= limit)
            .unwrap_or(self.inside.len());
        &self.outflow[..n]
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
