//! Acceptance test of PH95 Fig. 2 (MODEL.md A10): the `waves-fig2` binary at the
//! quick tier (the paper's L = 2200 and 40000 steps, 2 runs, seed 1).
//!
//! Waves: s_low - 2 SE > 2 over the late half (the fig1 statistic, an
//! uncorrelated gas gives 1). It must fail for a wave-free model (p = 0,
//! PH94 Fig. 1b). The pattern's real-space speed is a smoke check: downward
//! between 0.15 and 0.35 rows per step (the independent prototype of
//! MODEL.md A11 measured ~0.25 for this reading; the band is a loose smoke
//! tolerance, the precise value is waves-fig5's job).

mod common;
use common::pass;

fn run(tag: &str, extra: &[&str]) -> serde_json::Value {
    let files = [
        "fig2a.png",
        "fig2b.png",
        "fig2b_spacetime_run0.csv",
        "fig2a_snapshots_run0.csv",
    ];
    let args = [&["--tier", "quick", "--seed", "1"], extra].concat();
    run_figure!("waves-fig2", &args, tag, &files)
}

#[test]
fn fig2_quick_waves_form_and_p0_has_none() {
    let s = run("default", &[]);
    assert!(pass(&s, "waves_form"), "{}", s["metrics"]);
    let v = s["metrics"]["speed_real_space"].as_f64().unwrap();
    assert!((-0.35..-0.15).contains(&v), "speed {v}");
    let w = run("p0", &["--p", "0"]);
    assert!(
        common::contradicted(&w, "waves_form"),
        "p = 0: {}",
        w["metrics"]
    );
}
