//! Acceptance tests of the density spectra (issue 3): PH94 Fig. 2 and PH95
//! Figs. 6-7, run through the figure binaries and read from summary.json.
//!
//! Tier: `paper` sizes (m = 16384, 2^18 samples per run) with 4 runs instead
//! of 8: the quick tier (m = 4096) is too noisy to decide alpha against
//! 1.33 +- 0.02 (measured there 1.233 +- 0.032, EXPERIMENTS.md), while 4 paper
//! runs take about 30 s on two cores. (These tiers were fixed in session 1
//! for the `ph94` reading; the default changed to
//! `ph94+gravity-first+wall-move` in session 2, issue 4, and the tiers were
//! kept.) Tolerances are those of the binaries:
//! |measured - published| <= 2 sqrt(SE_runs^2 + published error^2), SE_runs the
//! standard error over the 4 runs (a false-alarm rate of about 5% for a
//! normally distributed mean; the seeds are fixed, so the test is
//! deterministic). Each claim is shown to fail for a reading that does not
//! reproduce it.

mod common;
use common::{metric, pass as check};

fn run(bin: &str, exe: &str, args: &[&str], tag: &str) -> serde_json::Value {
    common::run_figure(bin, exe, args, tag, &[&format!("{bin}.png")])
}

const PAPER4: [&str; 6] = ["--tier", "paper", "--runs", "4", "--seed", "1"];
const QUICK: [&str; 4] = ["--tier", "quick", "--seed", "1"];

#[test]
fn fig2_alpha_and_peak_velocity_agree_with_ph94_and_wrong_readings_fail() {
    let fig2 = env!("CARGO_BIN_EXE_fig2");
    let s = run("fig2", fig2, &PAPER4, "default");
    assert!(
        check(&s, "alpha"),
        "alpha = {} +- {}",
        metric(&s, "alpha"),
        metric(&s, "alpha_err")
    );
    assert!(check(&s, "v_peak"), "v_peak = {}", metric(&s, "v_peak"));
    // Known discrepancy, pinned: the peak of the mean spectrum sits at
    // j = 586 (v = 0.393; 8 runs: 587), not at the paper's 596 (v = 0.40; the
    // `ph94` reading gives 597). Pinned within 6 bins, three times the spread
    // of the single runs' peaks (583-590 in 7 of 8 runs at the paper tier,
    // EXPERIMENTS.md).
    assert!(
        (metric(&s, "j_peak") - 586.0).abs() <= 6.0,
        "j_peak = {}",
        metric(&s, "j_peak")
    );

    // The wrong readings fail by a wide margin already at the quick tier,
    // which is four times cheaper.
    // The literal [PH95] gravity wording: its peak sits at v = 0.43.
    let mut args = QUICK.to_vec();
    args.extend(["--rules", "any-mover"]);
    let w = run("fig2", fig2, &args, "any-mover");
    assert!(
        !check(&w, "v_peak"),
        "any-mover v_peak = {} must fail",
        metric(&w, "v_peak")
    );

    // Wall drag with gravity first: alpha about 0.9.
    let mut args = QUICK.to_vec();
    args.extend(["--rules", "ph94+wall-drag+gravity-first"]);
    let w = run("fig2", fig2, &args, "wall-drag");
    assert!(
        !check(&w, "alpha"),
        "wall-drag+gravity-first alpha = {} must fail",
        metric(&w, "alpha")
    );
}

#[test]
fn fig7_spectra_are_clearly_flatter_than_the_dissipative_one() {
    // PH95 Fig. 7 says white noise (alpha about 0) at p = 0 and at b = 0. The
    // default reading gives negative alpha instead (a known discrepancy, also
    // of every reading in MODEL.md A11), so what this test asserts is the part
    // it reproduces: both spectra are far flatter than the dissipative one
    // (alpha at least 1 lower, beyond 3 combined standard errors); and it
    // pins the discrepant values within 3 of their own standard errors, so a
    // change of the dynamics is noticed.
    let s = run(
        "waves-fig7",
        env!("CARGO_BIN_EXE_waves-fig7"),
        &["--tier", "quick", "--seed", "1"],
        "fig7",
    );
    let d = run(
        "fig2",
        env!("CARGO_BIN_EXE_fig2"),
        &["--tier", "quick", "--seed", "1"],
        "fig2-quick",
    );
    let (a, ae) = (metric(&d, "alpha"), metric(&d, "alpha_err"));
    for case in ["p0", "b0"] {
        let (x, xe) = (
            metric(&s, &format!("alpha_{case}")),
            metric(&s, &format!("alpha_{case}_err")),
        );
        let e = (ae * ae + xe * xe).sqrt();
        assert!(
            a - x > 1.0 && a - x > 3.0 * e,
            "alpha_{case} = {x} +- {xe} vs dissipative {a} +- {ae}"
        );
        assert!(
            !check(&s, &format!("alpha_{case}")),
            "alpha_{case}: the known discrepancy is reported"
        );
    }
    // measured at the quick tier, seed 1, default reading (EXPERIMENTS.md)
    let pinned = [("alpha_p0", -0.6019, 0.0217), ("alpha_b0", -3.0229, 0.0966)];
    for (name, value, err) in pinned {
        let x = metric(&s, name);
        assert!(
            (x - value).abs() <= 3.0 * err,
            "{name} = {x}, pinned {value} +- 3 x {err}"
        );
    }
    // b = 0: the peak at v = 1/2 exactly is reproduced by the default
    // reading (`wall-move`) ...
    assert!(
        check(&s, "v_peak_b0"),
        "v_peak_b0 = {}",
        metric(&s, "v_peak_b0")
    );
    // ... and not by the MODEL.md reading `ph94`, whose wall reflections
    // cost a step: its diagonal movers circle at v = 5/11 = 0.4545
    let w = run(
        "waves-fig7",
        env!("CARGO_BIN_EXE_waves-fig7"),
        &["--tier", "quick", "--seed", "1", "--rules", "ph94"],
        "fig7-ph94",
    );
    assert!(
        !check(&w, "v_peak_b0"),
        "ph94 v_peak_b0 = {} must fail",
        metric(&w, "v_peak_b0")
    );
}
