//! The BB90 claims (MODEL.md B6, HOPPER_READINGS.md Part 1) at the quick tier,
//! graded by the one rule of `granular_automata::analysis::grading` with the
//! thresholds `hopper-fig2`/`hopper-fig3` use: each claim the chosen
//! reading reproduces passes for it and is contradicted ("not reproduced",
//! not merely undecided) for a named wrong model; the claims it does not
//! reproduce are pinned to the quick-tier measurement so a change is noticed.
//!
//! Seeds: derive_seed(1, r), r = 0..3, the seeds of `hopper-fig2 --tier
//! quick` and `hopper-fig3 --tier quick` (base seed 1), so the numbers here
//! are the binaries'. Each ensemble (a model, 3 runs) is run once and shared
//! by the tests ([`records`]).
//!
//! Checks the default (along-bond, `beta1_bond`) reproduces at the quick
//! tier, and the wrong model that contradicts each (values: quick, seed 1;
//! EXPERIMENTS.md "A named wrong model for each reproduced check", EXPERIMENTS.md "The along-bond reading"):
//!
//! | check | default | wrong model |
//! |---|---|---|
//! | `beta1_bond_empties`, `beta0_empties` | all runs empty | Delta = 0 (beta 1), d = 1 (beta 0): jam |
//! | `*_central_core` | 16.4, 5.4 | literal reading 2.0; through-wall rays (beta 0) 0.52 |
//! | `*_core_lowered_density` | -0.25, -0.21 | none (see the test) |
//! | `beta1_bond_core_constant_width` | 0.29 +- 0.29 | none (see the test) |
//! | `beta1_bond_order`, `_order_forms_while_filling` | 0.71, 0.70 | S = 1: 1/3 |
//! | `beta1_bond_dense_sides` | 0.960 | alpha = 20: 0.751 |
//! | `beta1_bond_defects` | 13.3 | none (see the test) |
//! | `beta0_structureless` | 0.337 | beta = 1: 0.71 |
//! | `beta1_bond_rate_like_orientation_off` | 0.95 | tau = 200: 2.38 |
//!
//! Not reproduced by the default at the quick tier (so pinned, not tested
//! against a wrong model): the V surface, container-scale order, vertical
//! core (all undecided), white lag-1 (contradicted); the trend and the
//! spectral slope are undecided, and beta = 0's V surface is undecided
//! (HOPPER_READINGS.md, EXPERIMENTS.md). The V surface keeps its wrong
//! model (rest-same, contradicted) so the check is shown able to fail.

use granular_automata::analysis::grading::{grade, Claim, Estimate, Verdict};
use granular_automata::hopper::experiment::{
    core_rows, lag_correlation, run, Case, Plan, Record, FIG2_MEASURES, WINDOW_FULL, WINDOW_SKIP,
};
use granular_automata::hopper::{DilationReading, Geometry, Hopper, HopperParams};
use granular_automata::run::{derive_seed, ensemble};
use std::sync::{Arc, Mutex, OnceLock};

/// Base seed, as `hopper-fig2 --tier quick`.
const SEED: u64 = 1;
/// Runs per ensemble (the quick tier's 3).
const RUNS: usize = 3;

/// The reading chosen in HOPPER_READINGS.md Part 3, the library
/// default since EXPERIMENTS.md "The along-bond reading" (same-orientation before,
/// EXPERIMENTS.md "The hopper's default reading switches to same-orientation").
const CHOSEN: Case = Case::BETA1_BOND;

/// Thresholds and margins of `hopper-fig2` and `hopper-fig3`
/// (`src/drivers/hopper_figures.rs`; fixed before measuring).
const CORE_RATIO: f64 = 4.0;
const CORE_WIDTH: Claim = Claim::Within {
    target: 0.0,
    margin: 3.0,
};
const ORDER: Claim = Claim::Above { threshold: 0.45 };
const SURFACE: Claim = Claim::Above { threshold: 0.2 };
const LOWERED: Claim = Claim::Below { threshold: 0.0 };
const DENSE_SIDES: Claim = Claim::Above { threshold: 0.9 };
const VERTICAL: Claim = Claim::Above { threshold: 0.45 };
const CONTAINER: Claim = Claim::Above { threshold: 8.0 };
const DEFECTS: Claim = Claim::Above { threshold: 1.0 };
const STRUCTURELESS: Claim = Claim::Within {
    target: 1.0 / 3.0,
    margin: 0.03,
};
const RATE_RATIO: Claim = Claim::Within {
    target: 1.0,
    margin: 0.2,
};

/// One model's ensemble: its parameters and the records of the 3 runs.
type Ensemble = (HopperParams, Arc<Vec<Record>>);

/// The ensemble of `case` (with `tweak` applied to the quick parameters),
/// run once per test binary and shared by every test that asks for it.
fn records(case: Case, tweak: impl Fn(&mut HopperParams)) -> Ensemble {
    let mut p = case.params(HopperParams::quick());
    tweak(&mut p);
    ensemble_records(p)
}

/// The library default, untouched (`HopperParams::quick()`): the claims of
/// the chosen reading are asserted of the default itself.
fn default_records() -> Ensemble {
    let p = HopperParams::quick();
    assert_eq!(
        p,
        CHOSEN.params(HopperParams::quick()),
        "the default is the chosen reading"
    );
    ensemble_records(p)
}

type Cell = Arc<OnceLock<Arc<Vec<Record>>>>;

fn ensemble_records(p: HopperParams) -> Ensemble {
    static CACHE: Mutex<Vec<(HopperParams, Cell)>> = Mutex::new(Vec::new());
    let cell = {
        let mut cache = CACHE.lock().unwrap_or_else(|e| e.into_inner());
        match cache.iter().find(|(q, _)| *q == p) {
            Some((_, c)) => c.clone(),
            None => {
                let c = Cell::default();
                cache.push((p, c.clone()));
                c
            }
        }
    };
    let recs = cell.get_or_init(|| {
        // the plan of `hopper-fig2 --tier quick`; `hopper-fig3 --tier quick`
        // differs only in how long it keeps recording after the hopper is
        // empty, so its checks see the same runs
        let mut plan = Plan::new(5_000, vec![]);
        plan.fill_fraction = 0.7;
        Arc::new(ensemble(RUNS, |r| {
            run(p, derive_seed(SEED, r as u64), &plan).expect("valid parameters")
        }))
    });
    (p, recs.clone())
}

/// The per-run values of the `hopper-fig2` measure `name`.
fn measure((p, recs): &Ensemble, name: &str) -> Estimate {
    let g = Geometry::new(p.geometry).unwrap();
    let rows = core_rows(&Hopper::new(*p, 0).unwrap());
    let f = FIG2_MEASURES
        .iter()
        .find(|(m, _)| *m == name)
        .expect("a hopper-fig2 measure")
        .1;
    Estimate::of(&recs.iter().map(|r| f(r, &g, &rows)).collect::<Vec<_>>())
}

/// `<case>_empties`: every run empties (both binaries).
fn empties((_, recs): &Ensemble) -> Verdict {
    Verdict::of(recs.iter().all(|r| r.emptied))
}

/// The central-core statistic of `hopper-fig2` (>= 4 reproduces).
fn core_ratio(e: &Ensemble) -> f64 {
    let c = measure(e, "activity_centre").mean;
    let w = measure(e, "activity_wall").mean;
    (c + 1e-3) / (w + 1e-3)
}

/// `<case>_core_lowered_density`: occupancy core - sides.
fn lowered(e: &Ensemble) -> Estimate {
    measure(e, "occupancy_core").minus(measure(e, "occupancy_sides"))
}

/// The stationary outflow rate per run (`hopper-fig3`).
fn rate((_, recs): &Ensemble) -> Estimate {
    Estimate::of(
        &recs
            .iter()
            .map(|r| {
                let w = r.window(WINDOW_SKIP, WINDOW_FULL);
                w.iter().sum::<f64>() / w.len().max(1) as f64
            })
            .collect::<Vec<_>>(),
    )
}

/// `<case>_rate_like_orientation_off` of `hopper-fig3`: the rate of `on`
/// over that of `off`, the standard error propagated as the binary does.
fn rate_ratio(on: &Ensemble, off: &Ensemble) -> Estimate {
    let (on, off) = (rate(on), rate(off));
    let ratio = on.mean / off.mean;
    let se = ratio * ((on.se / on.mean).powi(2) + (off.se / off.mean).powi(2)).sqrt();
    Estimate::new(ratio, se, on.n.min(off.n))
}

fn lag1((_, recs): &Ensemble) -> Estimate {
    Estimate::of(
        &recs
            .iter()
            .map(|r| lag_correlation(r.window(WINDOW_SKIP, WINDOW_FULL), 1))
            .collect::<Vec<_>>(),
    )
}

#[test]
fn empties_and_jams_without_gravity_or_dilation() {
    let chosen = default_records();
    let beta0 = records(Case::BETA0, |_| {});
    assert_eq!(empties(&chosen), Verdict::Reproduced, "chosen empties");
    assert_eq!(empties(&beta0), Verdict::Reproduced, "beta = 0 empties");
    // Delta = 0 (BB90: 3): no gravity penalty, nothing drives the grains
    // down: the rain stalls in the top rows (quick: 61-75 grains after
    // 20 000 iterations of rain) and almost none leave (0 of 3 runs empty)
    let flat = records(CHOSEN, |p| p.energy.delta = 0.0);
    assert_eq!(empties(&flat), Verdict::NotReproduced, "Delta = 0 empties");
    // d = 1 (MODEL.md B4): 5 * 1.1^3 > Delta, so a grain with a hole below
    // stays; at beta = 0 the hopper jams (quick: 2646-2647 of ~2647 left)
    let unit = records(Case::BETA0, |p| p.dilation.reading = DilationReading::Unit);
    assert_eq!(empties(&unit), Verdict::NotReproduced, "d = 1 empties");
}

#[test]
fn central_core_and_its_wrong_models() {
    // claim 5: a central core with stagnant sides
    let r = core_ratio(&default_records());
    assert!(r >= CORE_RATIO, "chosen: centre/wall activity {r}");
    let r = core_ratio(&records(Case::BETA0, |_| {}));
    assert!(r >= CORE_RATIO, "beta = 0: centre/wall activity {r}");
    // the literal reading empties by sliding blocks (quick: 1.97)
    let r = core_ratio(&records(Case::BETA1_ALONG, |_| {}));
    assert!(r < CORE_RATIO, "literal reading: centre/wall activity {r}");
    // rays through the walls read the walls as open: the material slips
    // along them (MODEL.md B4; quick: 0.52)
    let through = records(Case::BETA0, |p| {
        p.dilation.reading = DilationReading::RaysThroughWalls
    });
    let r = core_ratio(&through);
    assert!(
        r < CORE_RATIO,
        "through-wall rays: centre/wall activity {r}"
    );
}

#[test]
fn v_surface_and_lowered_core_density() {
    let chosen = default_records();
    // claim 10: a V-shaped free surface. The chosen reading leaves it
    // undecided at the quick tier (0.54 +- 0.08, k = 4.30; reproduced at
    // the paper tier, 0.48 +- 0.04, and on one of the two standard seed
    // sets): pinned. The literal reading with rest pairs aligned stays
    // flat or tilted: the check can fail.
    let s = measure(&chosen, "surface_slope_half_empty");
    assert_ne!(
        grade(s, SURFACE),
        Verdict::NotReproduced,
        "chosen: surface {s:?}"
    );
    assert!((0.3..=0.8).contains(&s.mean), "chosen: surface {s:?}");
    let s = measure(
        &records(Case::BETA1_REST, |_| {}),
        "surface_slope_half_empty",
    );
    assert_eq!(
        grade(s, SURFACE),
        Verdict::NotReproduced,
        "rest-same: surface {s:?}"
    );
    // claim 7: density lowered in the core, for the default and beta = 0.
    // No named model contradicts it at the quick tier: every model that
    // flows lowers the core's density (quick, core - sides: literal -0.07,
    // rest-same -0.08, S = 1 -0.21, through-wall rays -0.30, alpha = 20
    // -0.20, gamma = 20 -0.29, tau = 200 -0.06, sequential -0.07; literal
    // and its narrow rain undecided); the models that jam (Delta = 0) have
    // no core, and their 0 - 0 is no measurement of the claim.
    let d = lowered(&chosen);
    assert_eq!(
        grade(d, LOWERED),
        Verdict::Reproduced,
        "chosen: occupancy {d:?}"
    );
    // claim 6: the core approaches a constant width (quick: 0.29 +- 0.29
    // lattice spacings between 20% and 40% of the wedge height). No named
    // model contradicts it at the quick tier (EXPERIMENTS.md "The along-bond reading"): the literal
    // reading 5.2 +- 4.8, rest-same -3.2 +- 4.6, same-orientation 1.2 +-
    // 2.0, alpha = 20 5.2 +- 1.8, gamma = 0 8.4 +- 5.3, S = 1 2.0 +- 0.3
    // are undecided; through-wall rays, tau = 200, beta = 20 reproduce it;
    // Delta = 0 has no core (0 - 0).
    let w = measure(&chosen, "core_width_change");
    assert_eq!(
        grade(w, CORE_WIDTH),
        Verdict::Reproduced,
        "chosen: width change {w:?}"
    );
    let d = lowered(&records(Case::BETA0, |_| {}));
    assert_eq!(
        grade(d, LOWERED),
        Verdict::Reproduced,
        "beta = 0: occupancy {d:?}"
    );
}

#[test]
fn dense_sides_and_alpha_at_its_extreme() {
    // claim 11: no holes in the stagnant sides (quick: 0.960 +- 0.003)
    let s = measure(&default_records(), "occupancy_sides");
    assert_eq!(
        grade(s, DENSE_SIDES),
        Verdict::Reproduced,
        "chosen: sides {s:?}"
    );
    // alpha = 20 (BB90: 3, the top of the allowed range): the shear term
    // swamps gravity and dilation, grains that differ in velocity from a
    // neighbour stay put, and the sides keep holes (quick: 0.751 +- 0.012)
    let stiff = records(CHOSEN, |p| p.energy.alpha = 20.0);
    let s = measure(&stiff, "occupancy_sides");
    assert_eq!(
        grade(s, DENSE_SIDES),
        Verdict::NotReproduced,
        "alpha = 20: sides {s:?}"
    );
}

#[test]
fn order_and_structureless_grains() {
    let chosen = default_records();
    // claims 2-3: orientational order half emptied and after filling; the
    // structureless grain (S = 1: aligned pairs cost the same as any
    // other) has none
    let spherical = records(CHOSEN, |p| p.energy.s = 1.0);
    for name in ["order_half_empty", "order_filled"] {
        let o = measure(&chosen, name);
        assert_eq!(grade(o, ORDER), Verdict::Reproduced, "chosen: {name} {o:?}");
        let o = measure(&spherical, name);
        assert_eq!(
            grade(o, ORDER),
            Verdict::NotReproduced,
            "S = 1: {name} {o:?}"
        );
    }
    // S = 1 also contradicts the vertical core and container-scale order
    // (which the chosen reading leaves undecided; pinned below)
    let v = measure(&spherical, "vertical_fraction_moving");
    assert_eq!(
        grade(v, VERTICAL),
        Verdict::NotReproduced,
        "S = 1: vertical {v:?}"
    );
    let l = measure(&spherical, "corr_length_half_empty");
    assert_eq!(
        grade(l, CONTAINER),
        Verdict::NotReproduced,
        "S = 1: length {l:?}"
    );
    // claim 8: beta = 0 is structureless; with the orientation energy left
    // on (beta = 1, the chosen reading) it is not (quick: 0.71)
    let o = measure(&records(Case::BETA0, |_| {}), "order_half_empty");
    assert_eq!(
        grade(o, STRUCTURELESS),
        Verdict::Reproduced,
        "beta = 0: order {o:?}"
    );
    let o = measure(&chosen, "order_half_empty");
    assert_eq!(
        grade(o, STRUCTURELESS),
        Verdict::NotReproduced,
        "beta = 1 as beta = 0: order {o:?}"
    );
}

#[test]
fn rate_like_orientation_off_and_slow_dilation_memory() {
    // claim 16: the stationary rate with beta = 1 over that with beta = 0
    // within 0.2 of 1 (quick: 0.952 +- 0.020)
    let q = rate_ratio(&default_records(), &records(Case::BETA0, |_| {}));
    assert_eq!(
        grade(q, RATE_RATIO),
        Verdict::Reproduced,
        "chosen: rate ratio {q:?}"
    );
    // tau = 200 (MODEL.md B4: 8), the wrong model of hopper_acceptance.rs:
    // the dilation memory outlasts the flow's changes; beta = 0 then
    // creeps through a dense packing (rate 0.80) while beta = 1 flows
    // faster (quick: ratio 2.38 +- 0.04). The literal reading (0.73 +- 0.02)
    // is contradicted only at the standard tier (0.716 +- 0.008; quick,
    // 3 runs: undecided).
    let slow = |case: Case| records(case, |p| p.dilation.tau = 200.0);
    let q = rate_ratio(&slow(CHOSEN), &slow(Case::BETA0));
    assert_eq!(
        grade(q, RATE_RATIO),
        Verdict::NotReproduced,
        "tau = 200: rate ratio {q:?}"
    );
}

/// Known discrepancies of the chosen reading at the quick tier, pinned to
/// the measurement of `hopper-fig2`/`hopper-fig3 --tier quick`:
/// the container-scale order and the vertical core are undecided there
/// (the vertical core is contradicted at the standard and paper tiers,
/// 0.39-0.40), and the outflow alternates with period 2 (lag-1
/// correlation -0.25 at the quick tier). The defects claim is reproduced;
/// no named model contradicts it.
#[test]
fn chosen_reading_known_discrepancies_are_pinned() {
    let chosen = default_records();
    // quick, seeds derive_seed(1, 0..3): 10.0 +- 2.6 (hopper-fig2);
    // reproduced at the standard and paper tiers (15.1-16)
    let l = measure(&chosen, "corr_length_half_empty");
    assert!((6.0..=14.0).contains(&l.mean), "correlation length {l:?}");
    // quick: 0.462 +- 0.012, undecided against 0.45
    let v = measure(&chosen, "vertical_fraction_moving");
    assert_eq!(grade(v, VERTICAL), Verdict::Undecided, "vertical {v:?}");
    assert!((0.4..=0.55).contains(&v.mean), "vertical fraction {v:?}");
    // claim 12, reproduced: 13.3 +- 0.7 enclosed vacancies per 1000 grains
    // (k = 4.30 at 3 runs). No named model contradicts it: every model
    // tried that flows has more than 1 (quick: literal 6.8, rest-same 4.8,
    // S = 1 9.1, alpha = 20 3.8, gamma = 0 5.5, beta = 20 8.6, through-wall
    // rays 36); Delta = 0 gives 0 only because it never flows.
    let d = measure(&chosen, "vacancies_per_1000_half_empty");
    assert_eq!(grade(d, DEFECTS), Verdict::Reproduced, "defects {d:?}");
    // the period-2 alternation: white noise would give 0
    let q = lag1(&chosen);
    assert!((-0.45..=-0.15).contains(&q.mean), "lag-1 correlation {q:?}");
}
