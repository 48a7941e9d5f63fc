//! The BB90 claims of issue 15 (HOPPER_READINGS.md Part 1) at the quick tier,
//! graded by the one rule of `granular_automata::analysis::grading` with the
//! thresholds `hopper-fig2`/`hopper-fig3` use: each claim the chosen
//! reading reproduces passes for it and is contradicted ("not reproduced",
//! not merely undecided) for a named wrong model; the claims it does not
//! reproduce are pinned to the quick-tier measurement so a change is noticed.
//!
//! Seeds: derive_seed(1, r), r = 0..3, the seeds of `hopper-fig2 --tier
//! quick` (base seed 1), so the numbers here are the binary's.

use granular_automata::analysis::grading::{grade, Claim, Estimate, Verdict};
use granular_automata::hopper::experiment::{
    core_rows, lag_correlation, run, Case, Plan, Record, FIG2_MEASURES, WINDOW_FULL, WINDOW_SKIP,
};
use granular_automata::hopper::{Geometry, Hopper, HopperParams};
use granular_automata::run::{derive_seed, ensemble};

/// Base seed, as `hopper-fig2 --tier quick`.
const SEED: u64 = 1;
/// Runs per ensemble (the quick tier's 3).
const RUNS: usize = 3;

/// The reading chosen in issue 15 (HOPPER_READINGS.md Part 3), the library
/// default since notes/hopper-default-switch.md.
const CHOSEN: Case = Case::BETA1_SAME;

fn records(case: Case, tweak: impl Fn(&mut HopperParams)) -> (HopperParams, Vec<Record>) {
    let mut p = case.params(HopperParams::quick());
    tweak(&mut p);
    ensemble_records(p)
}

/// The library default, untouched (`HopperParams::quick()`): the claims of
/// the chosen reading are asserted of the default itself.
fn default_records() -> (HopperParams, Vec<Record>) {
    let p = HopperParams::quick();
    assert_eq!(
        p,
        CHOSEN.params(HopperParams::quick()),
        "the default is the chosen reading"
    );
    ensemble_records(p)
}

fn ensemble_records(p: HopperParams) -> (HopperParams, Vec<Record>) {
    let mut plan = Plan::new(5_000, vec![]);
    plan.fill_fraction = 0.7;
    let recs = ensemble(RUNS, |r| {
        run(p, derive_seed(SEED, r as u64), &plan).expect("valid parameters")
    });
    (p, recs)
}

/// The per-run values of the `hopper-fig2` measure `name`.
fn measure(p: HopperParams, recs: &[Record], name: &str) -> Estimate {
    let g = Geometry::new(p.geometry).unwrap();
    let rows = core_rows(&Hopper::new(p, 0).unwrap());
    let f = FIG2_MEASURES
        .iter()
        .find(|(m, _)| *m == name)
        .expect("a hopper-fig2 measure")
        .1;
    Estimate::of(&recs.iter().map(|r| f(r, &g, &rows)).collect::<Vec<_>>())
}

/// The central-core statistic of `hopper-fig2` (>= 4 reproduces).
fn core_ratio(p: HopperParams, recs: &[Record]) -> f64 {
    let c = measure(p, recs, "activity_centre").mean;
    let w = measure(p, recs, "activity_wall").mean;
    (c + 1e-3) / (w + 1e-3)
}

fn lag1(recs: &[Record]) -> Estimate {
    Estimate::of(
        &recs
            .iter()
            .map(|r| lag_correlation(r.window(WINDOW_SKIP, WINDOW_FULL), 1))
            .collect::<Vec<_>>(),
    )
}

/// Thresholds of `reproduce/hopper_fig2.rs` (fixed before measuring).
const ORDER: Claim = Claim::Above { threshold: 0.45 };
const SURFACE: Claim = Claim::Above { threshold: 0.2 };
const LOWERED: Claim = Claim::Below { threshold: 0.0 };

#[test]
fn chosen_reading_reproduces_its_claims_and_wrong_models_do_not() {
    let (p, recs) = default_records();
    assert!(recs.iter().all(|r| r.emptied), "the chosen reading empties");
    // claim 5: a central core with stagnant sides; the literal reading
    // empties by sliding blocks (quick: 1.5-2.0)
    let ratio = core_ratio(p, &recs);
    assert!(ratio >= 4.0, "chosen: centre/wall activity {ratio}");
    let (pl, literal) = records(Case::BETA1_ALONG, |_| {});
    let r = core_ratio(pl, &literal);
    assert!(r < 4.0, "literal reading: centre/wall activity {r}");
    // claim 10: a V-shaped free surface; the literal reading with rest
    // pairs aligned stays flat or tilted
    let s = measure(p, &recs, "surface_slope_half_empty");
    assert_eq!(
        grade(s, SURFACE),
        Verdict::Reproduced,
        "chosen: surface {s:?}"
    );
    let (pr, rest) = records(Case::BETA1_REST, |_| {});
    let s = measure(pr, &rest, "surface_slope_half_empty");
    assert_eq!(
        grade(s, SURFACE),
        Verdict::NotReproduced,
        "rest-same: surface {s:?}"
    );
    // claim 7: density lowered in the core
    let d = measure(p, &recs, "occupancy_core").minus(measure(p, &recs, "occupancy_sides"));
    assert_eq!(
        grade(d, LOWERED),
        Verdict::Reproduced,
        "chosen: occupancy {d:?}"
    );
    // claim 2: orientational order; the structureless grain (S = 1) has none
    let o = measure(p, &recs, "order_half_empty");
    assert_eq!(grade(o, ORDER), Verdict::Reproduced, "chosen: order {o:?}");
    let (ps, spherical) = records(CHOSEN, |p| p.energy.s = 1.0);
    let o = measure(ps, &spherical, "order_half_empty");
    assert_eq!(
        grade(o, ORDER),
        Verdict::NotReproduced,
        "S = 1: order {o:?}"
    );
    // S = 1 also contradicts the vertical core and container-scale order
    let v = measure(ps, &spherical, "vertical_fraction_moving");
    let vertical = Claim::Above { threshold: 0.45 };
    assert_eq!(
        grade(v, vertical),
        Verdict::NotReproduced,
        "S = 1: vertical {v:?}"
    );
    let l = measure(ps, &spherical, "corr_length_half_empty");
    let container = Claim::Above { threshold: 8.0 };
    assert_eq!(
        grade(l, container),
        Verdict::NotReproduced,
        "S = 1: length {l:?}"
    );
}

/// Known discrepancies of the chosen reading at the quick tier, pinned to
/// the measurement of `hopper-fig2`/`hopper-fig3 --tier quick` (issue 15):
/// the container-scale order and the vertical core are undecided there, and
/// the outflow alternates with period 2 (lag-1 correlation -0.29 at the quick tier).
#[test]
fn chosen_reading_known_discrepancies_are_pinned() {
    let (p, recs) = default_records();
    // quick, seeds derive_seed(1, 0..3): 6.1 +- 0.5 (hopper-fig2)
    let l = measure(p, &recs, "corr_length_half_empty");
    assert!((4.0..=9.0).contains(&l.mean), "correlation length {l:?}");
    // quick: 0.48 +- 0.10
    let v = measure(p, &recs, "vertical_fraction_moving");
    assert!((0.3..=0.65).contains(&v.mean), "vertical fraction {v:?}");
    // the period-2 alternation: white noise would give 0
    let q = lag1(&recs);
    assert!((-0.45..=-0.15).contains(&q.mean), "lag-1 correlation {q:?}");
}
