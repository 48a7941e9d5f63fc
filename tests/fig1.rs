//! Acceptance test of PH94 Fig. 1 (MODEL.md A10): runs the `fig1` binary at
//! the quick tier (the paper's L = 2200 and 40000 steps, 4 seeds) and reads its
//! summary.json.
//!
//! The statistic is s_low = S(1..3) over the late half divided by its
//! random-start value, graded by the one rule of `analysis::grading`: waves
//! when s_low - k SE > 2, no waves when s_low + k SE <= 2, with SE the
//! standard error over the 4 seeds and k = t(0.975, 3) = 3.18 (the seeds are
//! fixed, so the test is deterministic). The same statistic must fail
//! ("not reproduced", not merely undecided) for
//! a wrong model: the literal [PH95] gravity wording (`any-mover`), under which
//! the gas collapses into free fall and forms no bands (MODEL.md A11).

mod common;
use common::pass as check;

fn run_fig1(rules: &str, tag: &str) -> serde_json::Value {
    let files = [
        "fig1.png",
        "fig1_a.png",
        "fig1_b.png",
        "fig1_c.png",
        "fig1_d.png",
        "bins_a.csv",
    ];
    let args = ["--tier", "quick", "--seed", "1", "--rules", rules];
    run_figure!("fig1", &args, tag, &files)
}

#[test]
fn default_rules_form_waves_in_a_and_c_only_and_any_mover_fails() {
    let s = run_fig1("default", "default");
    for key in ["contrast_a", "contrast_d_err", "s_low_a", "s_low_d_err"] {
        assert!(s["metrics"][key].as_f64().unwrap().is_finite(), "{key}");
    }
    assert_eq!(s["rules"], "ph94+gravity-first+wall-move+inject-late");
    // waves_c (bands return when p is switched on) varies most from run to
    // run (s_low_c = 8.7 +- 2.4 over the 4 quick runs): with k = t(0.975, 3)
    // = 3.18 the one grading rule leaves it undecided at the quick tier, so
    // here it must not be contradicted; the other claims are decided
    let c = common::verdict(&s, "waves_c");
    assert!(c != "not-reproduced", "waves_c: {c}: {}", s["metrics"]);
    for name in [
        "waves_a",
        "waves_b",
        "waves_d",
        "s_low_a_gt_b",
        "s_low_a_gt_d",
        "s_low_c_gt_b",
        "s_low_c_gt_d",
    ] {
        assert!(
            check(&s, name),
            "default rules: {name} must pass: {}",
            s["metrics"]
        );
    }
    // the wrong model: no bands at p = 0.1, so the same checks fail
    let w = run_fig1("any-mover", "any-mover");
    // (s_low_c_gt_d is undecided for it at this tier, so not listed)
    for name in ["waves_a", "waves_c", "s_low_a_gt_b", "s_low_c_gt_b"] {
        assert!(
            common::contradicted(&w, name),
            "any-mover: {name} must fail: {}",
            w["metrics"]
        );
    }
}
