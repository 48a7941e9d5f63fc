//! Acceptance tests of the density spectra (MODEL.md A9-A10): PH94 Fig. 2 and PH95
//! Figs. 6-7, run through the figure binaries and read from summary.json.
//!
//! Tier: quick (m = 4096, 4 runs). Grading: the one rule of
//! `analysis::grading` (reproduced when |d| + k SE <= margin, k = max(2,
//! t(0.975, n - 1)); margin 0.1 for alpha, 0.01 for v). With 4 runs k =
//! 3.18, so k SE of alpha alone exceeds its margin at any tier CI can afford
//! (4 runs at the paper sizes gave 1.330 +- 0.066, still undecided): the test
//! asserts what 4 quick runs can decide. The default's alpha is not
//! contradicted and its estimate lies within the margin, its v_peak is
//! reproduced, and named wrong readings are contradicted ("not reproduced",
//! not merely undecided). Even 16 paper runs leave alpha undecided
//! (1.290 +- 0.045; the ignored test
//! `fig2_alpha_at_16_paper_runs_is_not_contradicted`, EXPERIMENTS.md). The
//! seeds are fixed, so the tests are deterministic.

mod common;
use common::{contradicted, metric, pass as check};

fn run(bin: &str, exe: &str, args: &[&str], tag: &str) -> serde_json::Value {
    common::run_figure(bin, exe, args, tag, &[&format!("{bin}.png")])
}

const QUICK: [&str; 4] = ["--tier", "quick", "--seed", "1"];

/// The default's fig2 at the quick tier, run once for both tests.
fn fig2_quick() -> &'static serde_json::Value {
    static S: std::sync::OnceLock<serde_json::Value> = std::sync::OnceLock::new();
    S.get_or_init(|| run("fig2", env!("CARGO_BIN_EXE_fig2"), &QUICK, "quick"))
}

#[test]
fn fig2_alpha_and_peak_velocity_agree_with_ph94_and_wrong_readings_fail() {
    let fig2 = env!("CARGO_BIN_EXE_fig2");
    let s = fig2_quick();
    let (a, ae) = (metric(s, "alpha"), metric(s, "alpha_err"));
    assert!(!contradicted(s, "alpha"), "alpha = {a} +- {ae}");
    assert!((a - 4.0 / 3.0).abs() <= 0.1, "alpha = {a} +- {ae}");
    assert!(check(s, "v_peak"), "v_peak = {}", metric(s, "v_peak"));
    // Known discrepancy, pinned: the peak of the mean spectrum sits at
    // j = 147 of m = 4096 here (v = 0.3948; at the paper sizes j = 587 of
    // 16384, v = 0.394), not at the paper's v = 0.40 (the `ph94` reading
    // gives 0.40). Pinned within 2 bins (v +- 0.0054), eight times the
    // standard error of v_peak over the 4 runs (measured by this test,
    // quick, seed 1).
    assert!(
        (metric(s, "j_peak") - 147.0).abs() <= 2.0,
        "j_peak = {}",
        metric(s, "j_peak")
    );

    // The wrong readings fail by a wide margin already at the quick tier:
    // the literal [PH95] gravity wording (its peak sits at v = 0.43), and
    // wall drag with gravity first (alpha about 0.9).
    for (rules, tag, fails) in [
        ("any-mover", "any-mover", "v_peak"),
        ("ph94+wall-drag+gravity-first", "wall-drag", "alpha"),
    ] {
        let mut args = QUICK.to_vec();
        args.extend(["--rules", rules]);
        let w = run("fig2", fig2, &args, tag);
        assert!(
            contradicted(&w, fails),
            "{rules} {fails} = {} must fail",
            metric(&w, fails)
        );
    }
}

/// PH94 Fig. 2's alpha at 16 paper runs (about 4 minutes on 2 cores; run
/// with `--ignored`). Measured 2026-12-01: 1.290 +- 0.045, k =
/// t(0.975, 15) = 2.13, still undecided (the per-run fits scatter with sd
/// 0.18, so more runs shrink SE slowly; EXPERIMENTS.md "The one grading
/// rule"). Asserted: not contradicted, estimate within the margin.
#[test]
#[ignore]
fn fig2_alpha_at_16_paper_runs_is_not_contradicted() {
    let args = ["--tier", "paper", "--runs", "16", "--seed", "1"];
    let s = run("fig2", env!("CARGO_BIN_EXE_fig2"), &args, "paper16");
    let (a, ae) = (metric(&s, "alpha"), metric(&s, "alpha_err"));
    assert!(!contradicted(&s, "alpha"), "alpha = {a} +- {ae}");
    assert!((a - 4.0 / 3.0).abs() <= 0.1, "alpha = {a} +- {ae}");
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
    let d = fig2_quick();
    let (a, ae) = (metric(d, "alpha"), metric(d, "alpha_err"));
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
            contradicted(&s, &format!("alpha_{case}")),
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
    // (not reproduced; at this tier undecided rather than contradicted: its
    // per-run peaks scatter, v_peak_b0 = 0.64 +- 0.14 over 4 runs)
    assert!(
        !check(&w, "v_peak_b0"),
        "ph94 v_peak_b0 = {} must fail",
        metric(&w, "v_peak_b0")
    );
}
