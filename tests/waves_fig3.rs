//! PH95 Fig. 3 (MODEL.md A10): the energy identity E(0) - E(t) = rest particles
//! (exact, every step), and an acceptance test of the `waves-fig3` binary at
//! the quick tier shortened to 4000 steps and 16 runs (about a second).

use granular_automata::pipe::{Params, Pipe, Rules};

mod common;
use common::metric;
use common::pass;

fn run(tag: &str, extra: &[&str]) -> serde_json::Value {
    let files = ["fig3a.png", "fig3b.png", "fig3.csv"];
    let quick = [
        "--tier", "quick", "--seed", "1", "--runs", "16", "--steps", "4000",
    ];
    run_figure!("waves-fig3", &[&quick, extra].concat(), tag, &files)
}

/// Base seed of every run in this file.
const SEED: u64 = 3;

fn fig3_params(p: f64) -> Params {
    Params {
        length: 256,
        width: 11,
        rho: 1.0,
        p,
        g: 0.5,
        b: 0.5,
        bin: 8,
        ..Params::default()
    }
}

/// Largest |E(0) - E(t) - rest(t)| over `steps` steps.
fn identity_error(pipe: &mut Pipe, steps: u64) -> u64 {
    let e0 = pipe.moving_count() as i64;
    let mut worst = 0;
    for _ in 0..steps {
        pipe.step().unwrap();
        let d = e0 - pipe.moving_count() as i64 - pipe.rest_count() as i64;
        worst = worst.max(d.unsigned_abs());
    }
    worst
}

#[test]
fn energy_loss_equals_rest_particles_at_every_step() {
    for rules in [
        "default",
        "any-mover",
        "ph94+rest-up",
        "ph94+wall-drag+gravity-first",
    ] {
        for p in [0.1, 0.5] {
            let r: Rules = rules.parse().unwrap();
            let mut pipe = Pipe::new(fig3_params(p), r, SEED).unwrap();
            assert_eq!(identity_error(&mut pipe, 2000), 0, "{rules}, p = {p}");
            assert!(pipe.rest_count() > 0, "{rules}: rest particles were made");
        }
    }
}

#[test]
fn energy_identity_fails_for_a_start_with_rest_particles() {
    // the identity needs a start without rest particles: put some in and it
    // must fail (so the check can detect a wrong initial state)
    let mut pipe = Pipe::new(fig3_params(0.1), Rules::default(), SEED).unwrap();
    for y in (0..256).step_by(4) {
        let s = pipe.site(5, y);
        pipe.set_site(5, y, s | 1);
    }
    assert!(identity_error(&mut pipe, 200) > 0);
}

/// Default reading: the energy identity holds, the energy loss rises and
/// saturates, C(0) is not contradicted as the random-start value (margin
/// 2%, normal approximation; undecided at this tier), and C falls below it (the measured behaviour of this
/// reading, EXPERIMENTS.md; PH95 says C rises). Wrong model p = 0
/// (no dissipation): no rest particles, so the energy loss is exactly 0 and
/// `energy_loss_rises` fails.
#[test]
fn fig3_quick_default_and_p0() {
    let s = run("default", &[]);
    for c in ["energy_identity", "energy_loss_rises"] {
        assert!(pass(&s, c), "{c}: {}", s["metrics"]);
    }
    // C(0) = 3.462 +- 0.087 against 3.514 with a margin of 2%: k SE alone
    // (0.17) exceeds the margin, so the one grading rule leaves it undecided
    // at the quick tier (the old rule's "3 SE + 2%" widened with the spread);
    // asserted not contradicted (it would be for a start off by 0.25)
    assert!(
        !common::contradicted(&s, "contrast_start_is_random"),
        "{}",
        s["metrics"]
    );
    assert!(metric(&s, "energy_loss_saturation") > 20.0);
    assert!(metric(&s, "contrast_change") + 2.0 * metric(&s, "contrast_change_err") < 0.0);
    assert!(
        common::contradicted(&s, "contrast_rises"),
        "{}",
        s["metrics"]
    );
    let w = run("p0", &["--p", "0"]);
    assert!(pass(&w, "energy_identity"));
    assert!(
        common::contradicted(&w, "energy_loss_rises"),
        "{}",
        w["metrics"]
    );
    assert_eq!(metric(&w, "energy_loss_saturation"), 0.0);
}
