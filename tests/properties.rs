//! Properties of the engines over generated cases (proptest): random sizes
//! down to W = 1 and L = 1, random rho, p, g, b (0 and 1 included), every
//! rule reading, random initial states, both pipe engines.
//!
//! - the periodic pipe conserves particles at every step (MODEL.md A7);
//! - the open pipe's books balance at every step: injected - out = N(t) - N(0);
//! - exclusion: a site is a set of at most seven channels (bit 7 clear), and
//!   the engine's channel counts, bin counts and the occupied bits of its
//!   sites agree;
//! - a run is the same for every thread count of the ensemble runner;
//! - the fast engine equals the reference bit for bit at every step that
//!   has no random choice (p, g, b and I each 0 or 1);
//! - the hopper conserves grains (inside + removed = added) and every
//!   evaluated grain that moves takes a state of least energy (MODEL.md B3-B4).
//!
//! A failing case is shrunk to a smallest one and kept in
//! `proptest-regressions/properties.txt`, which is committed: every later run
//! tries it first.
//!
//! Budgets: `cargo test --release --test properties` runs [`CI_CASES`] cases
//! per property (a few seconds in all). The long run sets the count:
//! `PROPTEST_CASES=20000 cargo test --release --test properties`
//! (docs/reference/generated-input.md has the measured counts and times).

mod common;

use common::certain::Certain;
use granular_automata::hopper::{
    Aligned, ConflictRule, DilationReading, Dynamics, Hopper, HopperParams, RestPairs, UpdateOrder,
};
use granular_automata::pipe::engine::PipeEngine;
use granular_automata::pipe::fast::FastPipe;
use granular_automata::pipe::open::books_balance;
use granular_automata::pipe::{
    is_validity_limit, Boundary, Engine, GravityWording, LaneCollide, Params, Pipe, Probability,
    RestPlacement, Rules,
};
use granular_automata::run::{derive_seed, ensemble_with_threads};
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::cell::Cell;

/// Cases per property in CI (`PROPTEST_CASES` overrides it).
const CI_CASES: u32 = 2000;

/// The proptest configuration: [`CI_CASES`] cases, or `PROPTEST_CASES`.
fn config() -> Config {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(CI_CASES);
    Config {
        cases,
        ..Config::default()
    }
}

/// A probability: 0, 1 or any value between.
fn unit() -> BoxedStrategy<f64> {
    prop_oneof![Just(0.0), Just(1.0), 0.0..=1.0f64].boxed()
}

/// A probability with a certain outcome: 0 or 1.
fn certain() -> BoxedStrategy<f64> {
    prop_oneof![Just(0.0), Just(1.0)].boxed()
}

/// Every rule reading: a gravity wording, any set of the ten switches
/// (`gravity-first` wins over `gravity-last`, which it excludes), and
/// `lane-collide` at p or at a probability q of its own.
fn rules() -> impl Strategy<Value = Rules> {
    (0..4usize, any::<[bool; 10]>(), unit()).prop_map(|(g, s, q)| {
        let gravity = [
            GravityWording::Ph94,
            GravityWording::AnyMover,
            GravityWording::UpToRest,
            GravityWording::RestAhead,
        ][g];
        Rules {
            gravity,
            wall_drag: s[0],
            gravity_first: s[1],
            gravity_last: s[2] && !s[1],
            rest: if s[3] {
                RestPlacement::RestUp
            } else {
                RestPlacement::RandomWalk
            },
            wall_move: s[4],
            rest_slide: s[5],
            fhp_rest: s[6],
            inject_down: s[7],
            inject_late: s[8],
            lane_collide: match (s[9], g % 2 == 0) {
                (false, _) => LaneCollide::Off,
                (true, true) => LaneCollide::AtP,
                (true, false) => LaneCollide::At(Probability::new(q).unwrap()),
            },
            ..Rules::MODEL_MD
        }
    })
}

/// A pipe case: its parameters (W in 1..=12, L = bin * bins up to 120),
/// rules, seed, steps and an initial state (`None`: the random start of
/// MODEL.md A8; else one byte per site, column by column).
#[derive(Debug, Clone)]
struct PipeCase {
    params: Params,
    rules: Rules,
    seed: u64,
    steps: u64,
    state: Option<Vec<u8>>,
}

/// A pipe case with p, g, b from `prob` and I from `inject` (`None`: periodic).
fn pipe_case(
    prob: BoxedStrategy<f64>,
    inject: Option<BoxedStrategy<f64>>,
) -> impl Strategy<Value = PipeCase> {
    let boundary = match inject {
        None => Just(Boundary::Periodic).boxed(),
        Some(i) => i.prop_map(|inject| Boundary::Open { inject }).boxed(),
    };
    let rho = prop_oneof![Just(1e-3), Just(1.0), Just(5.999), 0.01..5.99f64];
    (
        (1..=12usize, 1..=3usize, 1..=40usize),
        rho,
        (prob.clone(), prob.clone(), prob),
        boundary,
        rules(),
        any::<u64>(),
        1..=80u64,
        any::<bool>(),
    )
        .prop_flat_map(
            |((width, bin, bins), rho, (p, g, b), boundary, rules, seed, steps, prepared)| {
                let params = Params {
                    width,
                    length: bin * bins,
                    rho,
                    p,
                    g,
                    b,
                    bin,
                    boundary,
                };
                let n = if prepared { width * bin * bins } else { 0 };
                proptest::collection::vec(0u8..128, n).prop_map(move |v| PipeCase {
                    params,
                    rules,
                    seed,
                    steps,
                    state: prepared.then_some(v),
                })
            },
        )
}

/// Write `state` into `e` site by site (column by column).
fn prepare(e: &mut dyn PipeEngine, state: &[u8]) {
    let p = *e.params();
    for x in 0..p.width {
        for y in 0..p.length {
            e.set_site(x, y, state[x * p.length + y]);
        }
    }
}

/// Exclusion and the consistency of the counts: every site byte is a set of
/// the seven channels, and the occupied bits, the channel counts and the
/// bin counts give the same N.
fn counts_agree(e: &dyn PipeEngine) -> std::result::Result<u64, TestCaseError> {
    let p = *e.params();
    let mut bits = [0u64; 7];
    for x in 0..p.width {
        for y in 0..p.length {
            let s = e.site(x, y);
            prop_assert!(s < 128, "site ({x}, {y}) = {s:#x}: more than 7 channels");
            for (c, n) in bits.iter_mut().enumerate() {
                *n += (s >> c & 1) as u64;
            }
        }
    }
    prop_assert_eq!(
        e.channel_counts(),
        bits,
        "channel counts vs the sites' bits"
    );
    let n = e.particle_count();
    let binned: f64 = e.bin_counts().iter().sum();
    prop_assert_eq!(binned, n as f64, "bin counts vs N");
    Ok(n)
}

/// Run `case` on `engine`, checking [`counts_agree`] and `books(e, n0)` at
/// every step; a validity limit (MODEL.md A4) ends the run, any other error
/// fails it. The steps checked.
fn run_checked(
    case: &PipeCase,
    engine: Engine,
    books: impl Fn(&dyn PipeEngine, u64) -> bool,
) -> std::result::Result<u64, TestCaseError> {
    let mut e = engine
        .build(case.params, case.rules, case.seed)
        .map_err(|err| TestCaseError::fail(format!("build: {err}")))?;
    if let Some(s) = &case.state {
        prepare(e.as_mut(), s);
    }
    let n0 = counts_agree(e.as_ref())?;
    for t in 0..case.steps {
        match e.step() {
            Ok(()) => {}
            Err(err) if is_validity_limit(err.kind) => return Ok(t),
            Err(err) => return Err(TestCaseError::fail(format!("step {t}: {err:?}"))),
        }
        counts_agree(e.as_ref())?;
        prop_assert!(
            books(e.as_ref(), n0),
            "{engine}: after step {}: N = {}, N(0) = {n0}, flux {:?}",
            t + 1,
            e.particle_count(),
            e.flux()
        );
    }
    Ok(case.steps)
}

/// The periodic pipe's books: N(t) = N(0).
fn conserved(e: &dyn PipeEngine, n0: u64) -> bool {
    e.particle_count() == n0
}

/// The engine of a case: reference or fast.
fn engine() -> impl Strategy<Value = Engine> {
    prop_oneof![Just(Engine::Reference), Just(Engine::Fast)]
}

proptest! {
    #![proptest_config(config())]

    /// The periodic pipe keeps every particle, and its sites are sets of channels.
    #[test]
    fn the_periodic_pipe_conserves_particles(case in pipe_case(unit(), None), engine in engine()) {
        run_checked(&case, engine, conserved)?;
    }

    /// The open pipe's books balance at every step (MODEL.md A7).
    #[test]
    fn the_open_pipe_books_balance(case in pipe_case(unit(), Some(unit())), engine in engine()) {
        run_checked(&case, engine, books_balance)?;
    }

    /// A run's result does not depend on the thread count of the ensemble.
    #[test]
    fn runs_do_not_depend_on_the_thread_count(
        case in pipe_case(unit(), Some(unit())),
        periodic in any::<bool>(),
        engine in engine(),
        threads in 2..=4usize,
    ) {
        let mut params = case.params;
        if periodic {
            params.boundary = Boundary::Periodic;
        }
        let run = |i: usize| -> Vec<u8> {
            let Ok(mut e) = engine.build(params, case.rules, derive_seed(case.seed, i as u64)) else {
                return vec![];
            };
            let stopped = e.run(case.steps).err().map(|err| err.kind);
            let mut v: Vec<u8> = format!("{stopped:?} {:?} {}", e.flux(), e.time()).into_bytes();
            for x in 0..params.width {
                v.extend((0..params.length).map(|y| e.site(x, y)));
            }
            v
        };
        let one = ensemble_with_threads(5, 1, run);
        prop_assert_eq!(ensemble_with_threads(5, threads, run), one);
    }

    /// The fast engine equals the reference site by site and in its flux at
    /// every step without a random choice (p, g, b, I in {0, 1}).
    #[test]
    fn the_fast_engine_equals_the_reference_where_the_step_is_certain(
        case in pipe_case(certain(), Some(certain())),
        periodic in any::<bool>(),
    ) {
        let mut params = case.params;
        if periodic {
            params.boundary = Boundary::Periodic;
        }
        lockstep(params, case.rules, case.seed, case.state.as_deref(), case.steps)?;
    }

    /// Grains are conserved (inside + removed = added) and a grain that was
    /// evaluated and moves takes a state of least energy (MODEL.md B3-B4).
    #[test]
    fn the_hopper_conserves_grains_and_moves_to_least_energy(case in hopper_case()) {
        hopper_checked(&case)?;
    }
}

// ---------------------------------------------------------------- lockstep

/// Step the two engines side by side from the same state; compare every
/// certain step (sites, N and the flux of the step); after a step with a
/// random choice the fast engine takes the reference's state. The steps
/// compared.
fn lockstep(
    params: Params,
    rules: Rules,
    seed: u64,
    state: Option<&[u8]>,
    steps: u64,
) -> std::result::Result<u64, TestCaseError> {
    let certain = Certain::default();
    let choices = certain.choices.clone();
    let mut r = Pipe::new(params, rules, seed).unwrap().with_draws(certain);
    let mut f = FastPipe::new(params, rules, seed).unwrap();
    let (w, l) = (params.width, params.length);
    for x in 0..w {
        for y in 0..l {
            let s = state.map_or(r.site(x, y), |s| s[x * l + y]);
            r.set_site(x, y, s);
            f.set_site(x, y, s);
        }
    }
    let mut compared = 0;
    for t in 1..=steps {
        let (rf, ff) = (r.flux(), f.flux());
        choices.set(0);
        let (a, b) = (r.step(), f.step());
        if choices.get() > 0 {
            if a.is_err() || b.is_err() {
                return Ok(compared);
            }
            for x in 0..w {
                for y in 0..l {
                    f.set_site(x, y, r.site(x, y));
                }
            }
            continue;
        }
        prop_assert_eq!(&a, &b, "step {}: the same result", t);
        if a.is_err() {
            return Ok(compared);
        }
        compared += 1;
        for x in 0..w {
            for y in 0..l {
                prop_assert_eq!(
                    f.site(x, y),
                    r.site(x, y),
                    "site ({}, {}) after step {}",
                    x,
                    y,
                    t
                );
            }
        }
        let d = |now: granular_automata::pipe::Flux, then: granular_automata::pipe::Flux| {
            [
                now.injected - then.injected,
                now.out_bottom - then.out_bottom,
                now.out_top - then.out_top,
            ]
        };
        prop_assert_eq!(d(f.flux(), ff), d(r.flux(), rf), "flux of step {}", t);
        prop_assert_eq!(f.time(), r.time());
    }
    Ok(compared)
}

// ------------------------------------------------------------------ hopper

/// A hopper case: small random geometry, every reading, random energy
/// parameters, rain, the iteration the plug opens and the iterations run.
#[derive(Debug, Clone)]
struct HopperCase {
    params: HopperParams,
    seed: u64,
    open_at: u64,
    rain_until: u64,
    iterations: u64,
}

fn hopper_case() -> impl Strategy<Value = HopperCase> {
    let geometry = (3..=24usize, 1..=4usize, 0..=16usize, any::<u16>()).prop_map(
        |(width, channel, extra, o)| {
            let most = granular_automata::hopper::geometry::max_outlet_width(width).max(1);
            granular_automata::hopper::GeometryParams {
                width,
                height: channel + 4 + extra,
                outlet_width: 1 + o as usize % most,
                channel_height: channel,
            }
        },
    );
    let energy = (
        prop_oneof![Just(0.0), 0.0..10.0f64],
        0.0..0.99f64,
        prop_oneof![Just(1.0), 0.001..=1.0f64],
        (
            0.0..6.0f64,
            prop_oneof![Just(0.0), Just(1.0), 0.0..4.0f64],
            0.0..4.0f64,
        ),
        (0..3usize, any::<bool>()),
    );
    let dynamics = (
        0..3usize,
        1..=4usize,
        1.0..12.0f64,
        any::<bool>(),
        any::<bool>(),
    );
    (
        geometry,
        energy,
        dynamics,
        unit(),
        any::<u64>(),
        (0..40u64, 0..40u64, 1..=60u64),
    )
        .prop_map(
            |(
                geometry,
                (delta, c, s, (alpha, beta, gamma), (a, same)),
                (d, k, tau, seq, revert),
                peak,
                seed,
                (open_at, rain_until, iterations),
            )| {
                let mut params = HopperParams::quick();
                params.geometry = geometry;
                params.energy.delta = delta;
                params.energy.c = c;
                params.energy.s = s;
                params.energy.alpha = alpha;
                params.energy.beta = beta;
                params.energy.gamma = gamma;
                params.energy.aligned = Aligned::ALL[a];
                params.energy.rest_pairs = if same {
                    RestPairs::SameOrientation
                } else {
                    RestPairs::NotAligned
                };
                params.dilation.reading = [
                    DilationReading::Rays,
                    DilationReading::RaysThroughWalls,
                    DilationReading::Unit,
                ][d];
                params.dilation.k = k;
                params.dilation.tau = tau;
                params.rain.peak = peak;
                params.rain.sigma = 1.0 + (seed % 8) as f64;
                params.dynamics = Dynamics {
                    order: if seq {
                        UpdateOrder::Sequential
                    } else {
                        UpdateOrder::Synchronous
                    },
                    conflict: if revert {
                        ConflictRule::Revert
                    } else {
                        ConflictRule::KeepOrientation
                    },
                };
                HopperCase {
                    params,
                    seed,
                    open_at,
                    rain_until,
                    iterations,
                }
            },
        )
}

/// No neighbour in that direction.
const OFF: u32 = u32::MAX;

/// Run `case`, checking the grains at every iteration and the least
/// energy at every synchronous one; the moves checked against the energy.
fn hopper_checked(case: &HopperCase) -> std::result::Result<u64, TestCaseError> {
    let mut h = Hopper::new(case.params, case.seed)
        .map_err(|e| TestCaseError::fail(format!("new: {e}")))?;
    let synchronous = case.params.dynamics.order == UpdateOrder::Synchronous;
    let mut checked = 0;
    for it in 0..case.iterations {
        if it == case.open_at {
            h.open();
        }
        let before = synchronous.then(|| h.clone());
        h.step(it < case.rain_until);
        prop_assert_eq!(
            h.count_grains() + h.removed(),
            h.added(),
            "iteration {}",
            it
        );
        if let Some(h0) = before {
            checked += least_energy(&h0, &h)?;
        }
    }
    Ok(checked)
}

/// Every grain of `h1` that moved in the iteration from `h0` (its motion is
/// not rest) came from the neighbour opposite its motion; when that grain
/// was evaluated in `h0` (a hole below or a moving neighbour, MODEL.md B3)
/// its state has the least energy of its candidates there. The moves checked.
fn least_energy(h0: &Hopper, h1: &Hopper) -> std::result::Result<u64, TestCaseError> {
    use granular_automata::hopper::energy::motion;
    use granular_automata::hopper::model::{grain_state, is_grain};
    let g = h0.geometry();
    let (s0, s1) = (h0.sites(), h1.sites());
    let hole = |j: u32| j != OFF && s0[j as usize] == 0;
    let mut checked = 0;
    for (t, &site) in s1.iter().enumerate() {
        if !is_grain(site) {
            continue;
        }
        let s = grain_state(site);
        let v = motion(s);
        if v == 0 {
            continue;
        }
        let from = g.nbr[t]
            .iter()
            .copied()
            .find(|&j| j != OFF && g.nbr[j as usize][v - 1] == t as u32);
        let Some(i) = from.map(|j| j as usize) else {
            return Err(TestCaseError::fail(format!(
                "site {t}: a mover with no site behind it"
            )));
        };
        prop_assert!(
            is_grain(s0[i]),
            "site {}: its grain came from {}, empty before",
            t,
            i
        );
        let nb = g.nbr[i];
        let below = hole(nb[2]) || hole(nb[3]) || hole(nb[4]);
        let moving = nb.iter().any(|&j| {
            j != OFF && is_grain(s0[j as usize]) && motion(grain_state(s0[j as usize])) != 0
        });
        if !(below || moving) {
            continue;
        }
        let e = h0.debug_energies(i);
        let least = e.iter().map(|x| x.1).fold(f64::INFINITY, f64::min);
        let Some(&(_, chosen)) = e.iter().find(|x| x.0 == s) else {
            return Err(TestCaseError::fail(format!(
                "site {i}: state {s} is no candidate"
            )));
        };
        prop_assert!(
            chosen <= least + 1e-6 * least.abs().max(1.0),
            "grain at {} moved in state {} with E = {}, least E = {}",
            i,
            s,
            chosen,
            least
        );
        checked += 1;
    }
    Ok(checked)
}

/// The generated cases reach the checks: over 200 cases each, most pipe
/// steps run (rather than ending at a validity limit), many steps are
/// compared between the engines, and many hopper moves against the energy.
#[test]
fn the_generated_cases_reach_the_checks() {
    use proptest::test_runner::TestRunner;
    let count = |strategy: BoxedStrategy<PipeCase>, f: &dyn Fn(&PipeCase) -> u64| {
        let total = Cell::new(0u64);
        TestRunner::new(Config::with_cases(200))
            .run(&strategy, |case| {
                total.set(total.get() + f(&case));
                Ok(())
            })
            .unwrap();
        total.get()
    };
    let periodic = count(pipe_case(unit(), None).boxed(), &|c| {
        run_checked(c, Engine::Fast, conserved).unwrap()
    });
    let compared = count(pipe_case(certain(), Some(certain())).boxed(), &|c| {
        lockstep(c.params, c.rules, c.seed, c.state.as_deref(), c.steps).unwrap()
    });
    let moves = Cell::new(0u64);
    TestRunner::new(Config::with_cases(200))
        .run(&hopper_case(), |case| {
            moves.set(moves.get() + hopper_checked(&case).unwrap());
            Ok(())
        })
        .unwrap();
    eprintln!(
        "periodic steps {periodic}, compared {compared}, hopper moves {}",
        moves.get()
    );
    assert!(periodic > 4000, "periodic steps checked: {periodic}");
    assert!(compared > 2000, "certain steps compared: {compared}");
    assert!(moves.get() > 1000, "hopper moves checked: {}", moves.get());
}
