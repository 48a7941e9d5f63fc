//! The hopper half of `validate` (MODEL.md B3-B4, VALIDATION.md "Hopper"): a
//! candidate's hopper engine, behind the contract of
//! [`crate::hopper::engine`], against the reference [`Hopper`].
//!
//! - Level 1 (deterministic, no statistics): the energies E_i the candidate
//!   reports for prepared neighbourhoods against the formula of MODEL.md B4
//!   (BB90 eqs. 1-6) written out here independently of
//!   `crate::hopper::energy`; the conflict rule of MODEL.md B3 on two grains
//!   aiming at one hole with known energies; the spacing update of MODEL.md
//!   B4 (rays of K steps, running mean over tau, carried along by a moving
//!   grain) on every grain of those set-ups.
//! - Level 2: short fill-and-empty runs (MODEL.md B5) at beta = 0 and beta =
//!   1, observables of BB90 Figs. 2-3, Welch tests with one Holm family over
//!   all hopper observables (separate from the pipe family), reference and
//!   candidate on disjoint seeds.
//!
//! [`Hopper`]: crate::hopper::Hopper

use super::scenes::{compare, mean_se, Level2, Sampling, CANDIDATE_SALT};
use crate::error::{Error, ErrorKind, Result};
use crate::hopper::energy::{motion, orientation, state, STATES};
use crate::hopper::engine::{HopperBuilder, HopperEngine};
use crate::hopper::geometry::{SiteKind, OFF};
use crate::hopper::model::{grain, grain_state, is_grain, HOLE, WALL};
use crate::hopper::observables::orientation_correlation_of;
use crate::hopper::{Aligned, EnergyParams, HopperParams, RestPairs};
use crate::lattice::{velocity, DOWN_LEFT, DOWN_RIGHT, UP, UP_LEFT, UP_RIGHT};
use crate::run::{derive_seed, Tier};
use serde::Serialize;
use std::collections::BTreeMap;

/// Relative tolerance of the exact checks of level 1.
pub const TOLERANCE: f64 = 1e-12;

/// Differences kept in a report (all are counted).
const KEEP: usize = 200;

/// One check of level 1 the candidate failed.
#[derive(Debug, Clone, Serialize)]
pub struct HopperDifference {
    /// `energy`, `conflict` or `spacing`.
    pub check: &'static str,
    /// The set-up and the quantity.
    pub case: String,
    /// The rule's value (NaN when the difference is not a number).
    pub expected: f64,
    /// The candidate's value.
    pub observed: f64,
}

/// Result of level 1 for the hopper.
#[derive(Debug, Clone, Serialize)]
pub struct HopperLevel1 {
    /// Energies E_i compared with the formula.
    pub energies: usize,
    /// Conflict set-ups run.
    pub conflicts: usize,
    /// Spacings D_i compared.
    pub spacings: usize,
    /// Relative tolerance of every comparison.
    pub tolerance: f64,
    /// Number of differences.
    pub failed: usize,
    /// The first differences.
    pub differences: Vec<HopperDifference>,
    /// No difference.
    pub pass: bool,
}

/// A neighbour in a prepared neighbourhood.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Nb {
    Hole,
    Grain(usize),
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE * b.abs().max(1.0)
}

/// The orientation axis parallel to direction `c` (1..=6): direction c
/// points at 90° + 60° (c - 1); O = 0, 1, 2 are the axes at 90°, 150°, 30°
/// (vertical, +60°, -60°; MODEL.md B1), so the axis is (c - 1) mod 3.
fn axis(c: usize) -> usize {
    (c - 1) % 3
}

/// E_inter's F_shear^alpha F_orient^beta F_dilation^gamma for grain state
/// `si` and neighbour state `sn` in direction `c` (1..=6) from the grain, at
/// pair spacing `d` (MODEL.md B4).
fn pair_energy(p: &EnergyParams, si: usize, sn: usize, c: usize, d: f64) -> f64 {
    let ((ax, ay), (bx, by)) = (velocity(motion(si)), velocity(motion(sn)));
    let shear = ((ax - bx).powi(2) + (ay - by).powi(2)).sqrt() + 0.1;
    let (oi, on, vi, vn) = (orientation(si), orientation(sn), motion(si), motion(sn));
    let aligned = oi == on
        && match p.aligned {
            Aligned::SameOrientation => true,
            // the common axis lies along the bond to the neighbour
            Aligned::AlongBond => axis(c) == oi,
            Aligned::AlongVelocity => {
                (vi != 0 && axis(vi) == oi)
                    || (vn != 0 && axis(vn) == oi)
                    || (vi == 0 && vn == 0 && p.rest_pairs == RestPairs::SameOrientation)
            }
        };
    let orient = if aligned { p.s } else { 1.0 };
    let dil = if d <= 1.0 / (1.0 - p.c) { 1.0 / d } else { 0.2 };
    shear.powf(p.alpha) * orient.powf(p.beta) * dil.powf(p.gamma)
}

/// E_i of a grain in state `s` with neighbours `nb` (directions 1..=6) at
/// pair spacing `d`: E_gravity + sum of E_inter over the grains (MODEL.md B4).
fn energy(p: &EnergyParams, s: usize, nb: &[Nb; 6], d: f64) -> f64 {
    let hole_below = nb[2..5].contains(&Nb::Hole);
    let mut e = if hole_below && !(3..=5).contains(&motion(s)) {
        p.delta
    } else {
        0.0
    };
    for (k, n) in nb.iter().enumerate() {
        if let Nb::Grain(sn) = n {
            e += pair_energy(p, s, *sn, k + 1, d);
        }
    }
    e
}

/// r_i of MODEL.md B4 at site `i`: the mean over the six directions of the
/// steps (1..=K) to the first grain or wall (off the lattice counts as a
/// wall), K when there is none.
fn ray_mean(e: &dyn HopperEngine, i: usize, k: usize) -> f64 {
    let (nbr, sites) = (&e.geometry().nbr, e.sites());
    let steps = |c: usize| {
        let mut j = i;
        for s in 1..=k {
            let n = nbr[j][c];
            if n == OFF {
                return s;
            }
            j = n as usize;
            if is_grain(sites[j]) || sites[j] == WALL {
                return s;
            }
        }
        k
    };
    (0..6).map(steps).sum::<usize>() as f64 / 6.0
}

struct Checker {
    energies: usize,
    conflicts: usize,
    spacings: usize,
    failed: usize,
    differences: Vec<HopperDifference>,
}

impl Checker {
    fn differ(&mut self, check: &'static str, case: String, expected: f64, observed: f64) {
        self.failed += 1;
        if self.differences.len() < KEEP {
            self.differences.push(HopperDifference {
                check,
                case,
                expected,
                observed,
            });
        }
    }

    /// Grain `s0` at `i` with neighbours `nb`, every spacing `d`: the
    /// candidate's E of each state it may take against [`energy`].
    fn energy_case(
        &mut self,
        e: &mut dyn HopperEngine,
        p: &EnergyParams,
        i: usize,
        nb: &[Nb; 6],
        d: f64,
        label: &str,
    ) -> Result<()> {
        let ns = e.geometry().nbr[i];
        e.set_site(i, grain(0))?;
        e.set_spacing(i, d)?;
        for c in 0..6 {
            let j = ns[c] as usize;
            match nb[c] {
                Nb::Hole => e.set_site(j, HOLE)?,
                Nb::Grain(s) => {
                    e.set_site(j, grain(s))?;
                    e.set_spacing(j, d)?;
                }
            }
        }
        let got = e.energies(i)?;
        let mut want: Vec<usize> = (0..3)
            .flat_map(|o| (0..7).map(move |v| (o, v)))
            .filter(|&(_, v)| v == 0 || nb[v - 1] == Nb::Hole)
            .map(|(o, v)| state(o, v))
            .collect();
        want.sort_unstable();
        let mut states: Vec<usize> = got.iter().map(|g| g.0).collect();
        states.sort_unstable();
        if states != want {
            self.differ(
                "energy",
                format!("{label}: states offered {states:?}, the rule allows {want:?}"),
                want.len() as f64,
                states.len() as f64,
            );
        }
        for (s, val) in got {
            if s >= STATES {
                continue;
            }
            self.energies += 1;
            let x = energy(p, s, nb, d);
            if !close(val, x) {
                self.differ(
                    "energy",
                    format!(
                        "{label}: E of state (O {}, v {})",
                        orientation(s),
                        motion(s)
                    ),
                    x,
                    val,
                );
            }
        }
        Ok(())
    }
}

/// A hopper for the prepared set-ups: the quick container, closed, no rain.
fn probe_params(energy: EnergyParams) -> HopperParams {
    HopperParams {
        energy,
        ..HopperParams::quick()
    }
}

fn energy_checks(b: &dyn HopperBuilder, ck: &mut Checker, seed: u64) -> Result<()> {
    // the default reading (whatever `EnergyParams::default` holds), every
    // other reading of "aligned" (`Aligned::ALL`), and other parameters
    let default = EnergyParams::default();
    let mut variants = vec![default];
    variants.extend(
        Aligned::ALL
            .iter()
            .filter(|&&a| a != default.aligned)
            .map(|&aligned| EnergyParams { aligned, ..default }),
    );
    variants.extend([EnergyParams {
        delta: 2.0,
        c: 0.3,
        s: 0.1,
        alpha: 2.0,
        beta: 0.5,
        gamma: 1.5,
        aligned: Aligned::AlongVelocity,
        ..EnergyParams::default()
    }]);
    for (vi, p) in variants.iter().enumerate() {
        let mut e = b.build(probe_params(*p), derive_seed(seed, vi as u64))?;
        let g = e.geometry().clone();
        let i = g.index(g.centre_column, g.height() / 2);
        if g.nbr[i]
            .iter()
            .any(|&j| j == OFF || g.kind[j as usize] != SiteKind::Inside)
        {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                "the energy probe site needs six inside neighbours",
            ));
        }
        let mut cases: Vec<([Nb; 6], String)> = Vec::new();
        for c in 0..6 {
            for sn in 0..STATES {
                let mut nb = [Nb::Hole; 6];
                nb[c] = Nb::Grain(sn);
                cases.push((
                    nb,
                    format!("one neighbour in direction {} state {sn}", c + 1),
                ));
            }
        }
        for c in [UP, UP_LEFT, UP_RIGHT] {
            for sn in 0..STATES {
                let mut nb = [Nb::Grain(0); 6];
                for (k, n) in nb.iter_mut().enumerate() {
                    if k < 2 || k == 5 {
                        *n = Nb::Hole;
                    }
                }
                nb[c - 1] = Nb::Grain(sn);
                cases.push((nb, format!("resting below, direction {c} state {sn}")));
            }
        }
        let mut x = 0x9E37_79B9_7F4A_7C15u64 ^ seed;
        for k in 0..24 {
            let mut nb = [Nb::Hole; 6];
            for n in nb.iter_mut() {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let r = (x >> 33) as usize % (STATES + 2);
                if r < STATES {
                    *n = Nb::Grain(r);
                }
            }
            cases.push((nb, format!("mixed neighbourhood {k}")));
        }
        for d in [1.0, 1.1, 1.6] {
            for (nb, label) in &cases {
                let label = format!("params {vi}, d = {d}, {label}");
                ck.energy_case(e.as_mut(), p, i, nb, d, &label)?;
            }
        }
    }
    Ok(())
}

/// Fill every inside site at rows `1..=top` with resting grains (orientation
/// by site), spacing `d(i)`.
fn packed(e: &mut dyn HopperEngine, top: usize, d: &dyn Fn(usize) -> f64) -> Result<()> {
    let g = e.geometry().clone();
    for y in 1..=top {
        for x in 0..g.width() {
            let i = g.index(x, y);
            if g.kind[i] == SiteKind::Inside {
                e.set_site(i, grain(state(i % 3, 0)))?;
                e.set_spacing(i, d(i))?;
            }
        }
    }
    Ok(())
}

/// Compare every grain's D_i after one step with D + (r - D)/tau, D the
/// spacing before the step at the grain's origin (`origin` maps a site after
/// the step to its site before).
fn spacing_check(
    ck: &mut Checker,
    e: &dyn HopperEngine,
    rule: &HopperParams,
    before: &[f64],
    origin: &dyn Fn(usize) -> usize,
    label: &str,
) {
    let (k, tau) = (rule.dilation.k, rule.dilation.tau);
    for (i, &s) in e.sites().iter().enumerate() {
        if !is_grain(s) {
            continue;
        }
        ck.spacings += 1;
        let d0 = before[origin(i)];
        let want = d0 + (ray_mean(e, i, k) - d0) / tau;
        let got = e.spacing()[i];
        if !close(got, want) {
            ck.differ(
                "spacing",
                format!("{label}: D of the grain at site {i}"),
                want,
                got,
            );
        }
    }
}

fn spacing_checks(b: &dyn HopperBuilder, ck: &mut Checker, seed: u64) -> Result<()> {
    // a lone grain in the air: all six rays are K long, wherever it falls
    let rule = probe_params(EnergyParams::default());
    let mut e = b.build(rule, derive_seed(seed, 10))?;
    let g = e.geometry().clone();
    let i0 = g.index(g.centre_column, g.height() / 2);
    e.set_site(i0, grain(0))?;
    e.set_spacing(i0, 1.0)?;
    let before = e.spacing().to_vec();
    e.step(false);
    e.error()?; // a contract fault of an external candidate, not a difference
    let grains: Vec<usize> = (0..g.kind.len())
        .filter(|&i| is_grain(e.sites()[i]))
        .collect();
    if grains.len() != 1 {
        ck.differ(
            "spacing",
            "lone grain: grains after one step".into(),
            1.0,
            grains.len() as f64,
        );
    } else {
        spacing_check(ck, e.as_ref(), &rule, &before, &|_| i0, "lone grain");
    }
    // a packed bottom at rest: nothing moves, every D relaxes towards r
    let mut e = b.build(rule, derive_seed(seed, 11))?;
    let top = g.params.channel_height + 6;
    packed(e.as_mut(), top, &|i| 1.0 + 0.05 * (i % 5) as f64)?;
    let (before, sites) = (e.spacing().to_vec(), e.sites().to_vec());
    e.step(false);
    e.error()?; // a contract fault of an external candidate, not a difference
    if e.sites() != sites.as_slice() {
        ck.differ("spacing", "packed bottom: a grain moved".into(), 0.0, 1.0);
    } else {
        spacing_check(ck, e.as_ref(), &rule, &before, &|i| i, "packed bottom");
    }
    Ok(())
}

/// Two grains A (up-left of a hole h) and B (up-right of h) on the top of a
/// packed bottom, both pulled into h; the one with the larger D has the
/// smaller E and must win h (MODEL.md B3 step 2); the loser comes to rest.
fn conflict_checks(b: &dyn HopperBuilder, ck: &mut Checker, seed: u64) -> Result<()> {
    let p = EnergyParams {
        beta: 0.0,
        ..EnergyParams::default()
    };
    for (case, a_loose) in [("B looser", false), ("A looser", true)] {
        let rule = probe_params(p);
        let mut e = b.build(rule, derive_seed(seed, 20 + a_loose as u64))?;
        let g = e.geometry().clone();
        let top = g.params.channel_height + 6;
        packed(e.as_mut(), top, &|_| 1.0)?;
        let c0 = g.centre_column;
        let h = [c0, c0 + 1, c0 - 1]
            .into_iter()
            .map(|x| g.index(x, top))
            .find(|&h| {
                let n = g.nbr[h];
                n[UP - 1] != OFF
                    && g.kind[n[UP - 1] as usize] == SiteKind::Inside
                    && !is_grain(e.sites()[n[UP - 1] as usize])
                    && [UP_LEFT, UP_RIGHT]
                        .iter()
                        .all(|&c| n[c - 1] != OFF && is_grain(e.sites()[n[c - 1] as usize]))
            })
            .ok_or_else(|| {
                Error::new(
                    ErrorKind::InvalidParameter,
                    "no conflict site on the packed top row",
                )
            })?;
        let (a, bb) = (
            g.nbr[h][UP_LEFT - 1] as usize,
            g.nbr[h][UP_RIGHT - 1] as usize,
        );
        e.set_site(h, HOLE)?;
        let loose = if a_loose { a } else { bb };
        e.set_spacing(loose, 1.2)?;
        // the rule's energies of A and B for every state (beta = 0: the
        // orientation does not matter, use O = 0)
        let nb_of = |e: &dyn HopperEngine, i: usize| -> [Nb; 6] {
            let mut nb = [Nb::Hole; 6];
            for (c, n) in nb.iter_mut().enumerate() {
                let j = g.nbr[i][c];
                if j != OFF && is_grain(e.sites()[j as usize]) {
                    *n = Nb::Grain(grain_state(e.sites()[j as usize]));
                }
            }
            nb
        };
        let best = |e: &dyn HopperEngine, i: usize| -> (usize, f64) {
            let nb = nb_of(e, i);
            let mut out = (0, f64::INFINITY);
            for v in 0..7 {
                let free = v == 0 || {
                    let j = g.nbr[i][v - 1];
                    j != OFF && e.sites()[j as usize] == HOLE
                };
                if !free {
                    continue;
                }
                // pair spacing: (D_i + D_N)/2 per pair
                let s = state(0, v);
                let hole_below = nb[2..5].contains(&Nb::Hole);
                let mut en = if hole_below && !(3..=5).contains(&v) {
                    p.delta
                } else {
                    0.0
                };
                for (c, n) in nb.iter().enumerate() {
                    if let Nb::Grain(sn) = n {
                        let d = 0.5 * (e.spacing()[i] + e.spacing()[g.nbr[i][c] as usize]);
                        en += pair_energy(&p, s, *sn, c + 1, d);
                    }
                }
                if en < out.1 {
                    out = (v, en);
                }
            }
            out
        };
        let (ba, bb_) = (best(e.as_ref(), a), best(e.as_ref(), bb));
        if ba.0 != DOWN_RIGHT || bb_.0 != DOWN_LEFT || close(ba.1, bb_.1) {
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!("the conflict set-up is not one: A {ba:?}, B {bb_:?}"),
            ));
        }
        let (winner, loser, dir) = if ba.1 < bb_.1 {
            (a, bb, DOWN_RIGHT)
        } else {
            (bb, a, DOWN_LEFT)
        };
        let before_sites = e.sites().to_vec();
        let before = e.spacing().to_vec();
        e.step(false);
        e.error()?; // a contract fault of an external candidate, not a difference
        ck.conflicts += 1;
        let s = e.sites();
        let label = format!("conflict ({case})");
        let ok = is_grain(s[h])
            && motion(grain_state(s[h])) == dir
            && s[winner] == HOLE
            && is_grain(s[loser])
            && motion(grain_state(s[loser])) == 0;
        if !ok {
            ck.differ(
                "conflict",
                format!(
                    "{label}: the grain with the lower E (site {winner}, E = {:.4} against {:.4}) must move into the hole {h} and the other come to rest",
                    ba.1.min(bb_.1),
                    ba.1.max(bb_.1)
                ),
                winner as f64,
                if is_grain(s[winner]) { loser as f64 } else { f64::NAN },
            );
            continue;
        }
        let others_still = (0..s.len())
            .filter(|&i| i != h && i != winner && i != loser)
            .all(|i| s[i] == before_sites[i]);
        if !others_still {
            ck.differ(
                "conflict",
                format!("{label}: another grain moved"),
                0.0,
                1.0,
            );
            continue;
        }
        spacing_check(
            ck,
            e.as_ref(),
            &rule,
            &before,
            &|i| if i == h { winner } else { i },
            &label,
        );
    }
    Ok(())
}

/// Level 1 for the hopper: energies, conflicts and spacings of `cand`
/// against the rules (deterministic; any difference fails).
pub fn level1(cand: &dyn HopperBuilder, seed: u64) -> Result<HopperLevel1> {
    let mut ck = Checker {
        energies: 0,
        conflicts: 0,
        spacings: 0,
        failed: 0,
        differences: Vec::new(),
    };
    energy_checks(cand, &mut ck, seed)?;
    conflict_checks(cand, &mut ck, seed)?;
    spacing_checks(cand, &mut ck, seed)?;
    Ok(HopperLevel1 {
        energies: ck.energies,
        conflicts: ck.conflicts,
        spacings: ck.spacings,
        tolerance: TOLERANCE,
        pass: ck.failed == 0,
        failed: ck.failed,
        differences: ck.differences,
    })
}

/// One hopper scene: fill, settle, open, and record a window of outflow.
#[derive(Debug, Clone, Serialize)]
pub struct HopperScene {
    /// Name, e.g. `beta0`.
    pub name: &'static str,
    /// The hopper.
    pub params: HopperParams,
    /// Rain until this fraction of the inside sites holds grains.
    pub fill_fraction: f64,
    /// Most iterations of rain.
    pub max_fill: u64,
    /// Most iterations of settling.
    pub max_settle: u64,
    /// Iterations after opening before the outflow counts (start-up).
    pub skip: u64,
    /// Iterations of outflow recorded after the start-up.
    pub window: u64,
}

/// The hopper scenes at `tier`: BB90 Fig. 2 at beta = 0 and beta = 1
/// (the default reading of "aligned", `EnergyParams::default`: along the
/// bond) in the quick-tier container of MODEL.md B2 (100 x 75
/// sites), filled to 70%; 300 iterations of outflow recorded (standard and
/// paper: 600).
pub fn hopper_scenes(tier: Tier) -> Vec<HopperScene> {
    let params = HopperParams::quick();
    let sc = |name, beta| HopperScene {
        name,
        params: HopperParams {
            energy: EnergyParams {
                beta,
                ..params.energy
            },
            ..params
        },
        fill_fraction: 0.7,
        max_fill: 5000,
        max_settle: 1000,
        skip: 20,
        window: tier.pick(300, 600, 600),
    };
    vec![sc("beta0", 0.0), sc("beta1", 1.0)]
}

/// The observables of one run of `scene` by `b` with `seed`.
pub fn run_scene(
    b: &dyn HopperBuilder,
    scene: &HopperScene,
    seed: u64,
) -> Result<(BTreeMap<String, f64>, f64)> {
    let mut e = b.build(scene.params, seed)?;
    let inside = e.geometry().inside;
    let target = (scene.fill_fraction * inside as f64) as u64;
    let fill_iterations = e.fill(target, scene.max_fill, scene.max_settle);
    let g_filled = orientation_correlation_of(e.geometry(), e.sites(), 4);
    let initial = e.grains();
    e.open();
    let mut outflow = Vec::with_capacity(scene.window as usize);
    let mut moving = [0u64; 3];
    let steps = e.empty_steps(scene.skip + scene.window);
    e.error()?;
    for (r, m) in steps.into_iter().skip(scene.skip as usize) {
        outflow.push(r.outflow as f64);
        for (total, k) in moving.iter_mut().zip(m) {
            *total += k;
        }
    }
    let g_end = orientation_correlation_of(e.geometry(), e.sites(), 4);
    let (m, _) = mean_se(&outflow);
    let sd = (outflow.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (outflow.len() as f64 - 1.0))
        .sqrt();
    let moving_total: u64 = moving.iter().sum();
    let mut o = BTreeMap::new();
    o.insert("outflow_rate".to_string(), m);
    o.insert("outflow_sd".to_string(), sd);
    o.insert("order_filled".to_string(), g_filled[0]);
    o.insert("order_flowing".to_string(), g_end[0]);
    o.insert("g4_flowing".to_string(), g_end[3]);
    o.insert(
        "vertical_fraction_moving".to_string(),
        moving[0] as f64 / moving_total.max(1) as f64,
    );
    o.insert("fill_iterations".to_string(), fill_iterations as f64);
    o.insert("initial_grains".to_string(), initial as f64);
    o.insert("remaining_grains".to_string(), e.grains() as f64);
    Ok((o, e.site_updates()))
}

/// Per observable: the values of every run of one scene.
type Columns = BTreeMap<String, Vec<f64>>;

fn run_all(
    b: &dyn HopperBuilder,
    scenes: &[HopperScene],
    runs: usize,
    seed: u64,
    tick: &(dyn Fn() + Sync),
) -> Result<(Vec<Columns>, f64)> {
    let mut work = 0.0;
    let mut out = Vec::new();
    for (si, sc) in scenes.iter().enumerate() {
        let per = crate::run::ensemble(runs, |r| {
            let o = run_scene(b, sc, derive_seed(seed, (si * 1_000_003 + r) as u64));
            tick();
            o
        });
        let mut cols: BTreeMap<String, Vec<f64>> = BTreeMap::new();
        for o in per {
            let (o, w) = o?;
            work += w;
            for (k, v) in o {
                cols.entry(k).or_default().push(v);
            }
        }
        out.push(cols);
    }
    Ok((out, work))
}

/// Level 2 for the hopper: every observable of every scene, Welch tests,
/// one Holm family at `alpha` over the hopper comparisons.
pub fn level2(
    (reference, cand): (&dyn HopperBuilder, &dyn HopperBuilder),
    scenes: &[HopperScene],
    sampling: Sampling,
    tick: &(dyn Fn() + Sync),
) -> Result<Level2> {
    let Sampling { runs, seed, alpha } = sampling;
    let (r, wr) = run_all(reference, scenes, runs, seed, tick)?;
    let (c, wc) = run_all(cand, scenes, runs, seed ^ CANDIDATE_SALT, tick)?;
    let names: Vec<&str> = scenes.iter().map(|sc| sc.name).collect();
    let comparisons = compare(&names, &r, &c, alpha);
    Ok(Level2 {
        runs,
        alpha,
        pass: !comparisons.iter().any(|c| c.differs),
        comparisons,
        site_updates: wr + wc,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::hopper::engine::Reference;

    #[test]
    fn the_reference_passes_level_1() {
        let l = level1(&Reference, 1).unwrap();
        assert!(l.pass, "{:?}", &l.differences[..l.differences.len().min(5)]);
        assert!(
            l.energies > 10_000 && l.conflicts == 2 && l.spacings > 100,
            "{l:?}"
        );
    }

    #[test]
    fn pair_energy_is_the_formula_of_b4() {
        let literal = EnergyParams {
            aligned: Aligned::AlongVelocity,
            ..EnergyParams::default()
        };
        // a vertical grain falling next to a resting vertical grain at its
        // side (direction 2), d = 1: aligned along its velocity, 1.1^3 * 0.01
        let e = pair_energy(&literal, state(0, 4), state(0, 0), 2, 1.0);
        assert!(close(e, 1.1f64.powi(3) * 0.01));
        // dilated pair: F_dilation = 0.2
        let e = pair_energy(&literal, state(1, 0), state(2, 0), 2, 1.3);
        assert!(close(e, 0.1f64.powi(3) * 0.04));
        // two resting vertical grains, d = 1: not aligned in the literal
        // reading (no velocity), aligned in the same-orientation reading
        let e = pair_energy(&literal, state(0, 0), state(0, 0), 2, 1.0);
        assert!(close(e, 0.1f64.powi(3)));
        let p = EnergyParams {
            aligned: Aligned::SameOrientation,
            ..EnergyParams::default()
        };
        let e = pair_energy(&p, state(0, 0), state(0, 0), 2, 1.0);
        assert!(close(e, 0.1f64.powi(3) * 0.01));
        // along-bond (the default): the resting vertical pair is aligned
        // one above the other (direction 1 or 4), not side by side
        let bond = EnergyParams::default();
        assert_eq!(bond.aligned, Aligned::AlongBond);
        let e = pair_energy(&bond, state(0, 0), state(0, 0), 4, 1.0);
        assert!(close(e, 0.1f64.powi(3) * 0.01));
        let e = pair_energy(&bond, state(0, 0), state(0, 0), 2, 1.0);
        assert!(close(e, 0.1f64.powi(3)));
        // -60° grains along direction 3 (down-left), d = 1.1: 1e-5 / 1.21
        let e = pair_energy(&bond, state(2, 0), state(2, 0), 3, 1.1);
        assert!(close(e, 1e-5 / 1.21));
        // the falling grain of the first case: aligned in the literal and
        // same-orientation readings, not along the bond (its neighbour is
        // beside it)
        let e = pair_energy(&bond, state(0, 4), state(0, 0), 2, 1.0);
        assert!(close(e, 1.1f64.powi(3)));
        let e = pair_energy(&p, state(0, 4), state(0, 0), 2, 1.0);
        assert!(close(e, 1.1f64.powi(3) * 0.01));
    }
}
