//! Acceptance tests of `waves-fig6` (PH95 Fig. 6, p = 0.8) and `waves-fig10`
//! (PH95 Fig. 10, alpha against b and g, v against b) at the quick tier,
//! seed 1, read from summary.json.
//! Cost: about 20 s and 55 s of two cores. What is asserted: the output
//! contract (files, fields, every metric finite or listed as missing with a
//! reason), alpha of Fig. 6 pinned at its quick-tier value (1.357 +- 0.033
//! over 4 runs, measured 2026-12-01; EXPERIMENTS.md's older row of 1.145 is
//! from an earlier reading) and the physics of Fig. 10 that the rules
//! imply: rough walls slow the waves (v falls from b = 0.25 to b = 1 at both
//! gravities).

mod common;
use common::metric;

const QUICK: [&str; 4] = ["--tier", "quick", "--seed", "1"];

/// Every metric is a finite number (a metric without a value is listed in
/// missing_metrics with its reason instead).
fn metrics_are_finite(s: &serde_json::Value) {
    for (k, v) in s["metrics"].as_object().expect("metrics") {
        assert!(v.as_f64().is_some_and(f64::is_finite), "metric {k} = {v}");
    }
    for (k, why) in s["missing_metrics"].as_object().expect("missing_metrics") {
        assert!(
            why.as_str().is_some_and(|w| !w.is_empty()),
            "{k} without a reason"
        );
    }
}

fn check<'a>(s: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    s["checks"]
        .as_array()
        .expect("checks")
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("check {name} present"))
}

#[test]
fn fig6_quick_reports_alpha_and_its_check() {
    let s = run_figure!("waves-fig6", &QUICK, "quick", &["waves-fig6.png"],);
    assert_eq!(s["figure"], "waves-fig6");
    assert_eq!(s["paper"], "PH95 Fig. 6");
    assert_eq!(s["tier"], "quick");
    metrics_are_finite(&s);
    // pinned: 1.357 +- 0.033 (4 runs, seed 1); the window is 4 of
    // those standard errors either side (the seeds are fixed, so a change
    // means the model or the estimator changed)
    let a = metric(&s, "alpha");
    assert!((1.225..=1.489).contains(&a), "alpha = {a}");
    let c = check(&s, "alpha");
    assert_eq!(c["published"], 1.33);
    assert_eq!(c["measured"].as_f64(), Some(a), "{c}");
}

#[test]
fn fig10_quick_reports_every_point_and_rough_walls_slow_the_waves() {
    let s = run_figure!(
        "waves-fig10",
        &QUICK,
        "quick",
        &[
            "waves-fig10.csv",
            "waves-fig10a_b.png",
            "waves-fig10a_g.png",
            "waves-fig10b.png",
        ],
    );
    assert_eq!(s["figure"], "waves-fig10");
    assert_eq!(s["paper"], "PH95 Fig. 10");
    metrics_are_finite(&s);
    // the 9 distinct points of the quick tier, each with alpha and v
    // (or listed as missing)
    let points = [
        "b0_g0.5",
        "b0.05_g0.5",
        "b0.25_g0.5",
        "b0.5_g0.5",
        "b1_g0.5",
        "b0.5_g0.2",
        "b0.5_g1",
        "b0.25_g0.2",
        "b1_g0.2",
    ];
    for p in points {
        for q in ["alpha", "v"] {
            let k = format!("{q}_{p}");
            assert!(
                s["metrics"].get(&k).is_some() || s["missing_metrics"].get(&k).is_some(),
                "{k} reported"
            );
        }
    }
    for name in ["b0_matches_waves_fig7", "alpha_rises_with_b"] {
        check(&s, name);
    }
    // rough walls slow the waves: v(b = 1) below v(b = 0.25) by more than
    // 3 combined SE, at g = 0.5 and at g = 0.2 (measured 0.43 and 0.34)
    for g in ["0.5", "0.2"] {
        let (lo, hi) = (format!("v_b0.25_g{g}"), format!("v_b1_g{g}"));
        let e = (metric(&s, &format!("{lo}_err")).powi(2)
            + metric(&s, &format!("{hi}_err")).powi(2))
        .sqrt();
        assert!(
            metric(&s, &lo) - metric(&s, &hi) > 3.0 * e,
            "g = {g}: v(b = 0.25) = {}, v(b = 1) = {} +- {e}",
            metric(&s, &lo),
            metric(&s, &hi)
        );
    }
}
