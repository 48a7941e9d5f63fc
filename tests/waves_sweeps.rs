//! Acceptance tests of the PH95 Figs. 8-11 binaries at the quick tier (seed 1),
//! read from summary.json. The published values are withheld (blind
//! reproduction), so what is asserted is internal consistency, each shown to
//! fail for a wrong reading (`any-mover`, the literal [PH95] gravity wording).
//! Seeds are fixed, so the tests are deterministic; the false-alarm rates
//! stated are those of the statistic for a fresh seed.

mod common;
use common::{metric, pass};

const QUICK: [&str; 4] = ["--tier", "quick", "--seed", "1"];

fn args<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut v = QUICK.to_vec();
    v.extend(extra);
    v
}

#[test]
fn fig8_p0_point_agrees_with_fig7_and_a_wrong_reading_fails() {
    let exe = env!("CARGO_BIN_EXE_waves-fig8");
    let files = ["waves-fig8.csv", "waves-fig8_alpha.png", "waves-fig8_v.png"];
    // 2 runs per point (about 40 s): the p = 0 point must agree with
    // waves-fig7 within 3 combined SE (false-alarm rate ~0.3%), and alpha must
    // rise from p = 0 to p = 0.5 by more than 3 combined SE.
    let s = common::run_figure(
        "waves-fig8",
        exe,
        &args(&["--runs", "2"]),
        "default",
        &files,
    );
    assert!(
        pass(&s, "p0_matches_waves_fig7"),
        "alpha_p0 = {}",
        metric(&s, "alpha_p0")
    );
    assert!(pass(&s, "alpha_rises_with_p"));
    // the literal PH95 gravity wording gives alpha(p = 0) ~ -0.28, not -0.56
    let w = common::run_figure(
        "waves-fig8",
        exe,
        &args(&["--runs", "1", "--rules", "any-mover"]),
        "any-mover",
        &files,
    );
    assert!(
        !pass(&w, "p0_matches_waves_fig7"),
        "any-mover alpha_p0 = {} must fail",
        metric(&w, "alpha_p0")
    );
}

#[test]
fn fig9_counts_invalid_runs_and_reports_the_validity_limit() {
    // one run per point (about 20 s): no run at rho <= 1 is invalid, the
    // largest rho (3) is invalid, reported in the metrics, no crash. The
    // check fails if the limit is not reached (a wrong model that never
    // fills with rest particles) or a low-density run stops.
    let s = common::run_figure(
        "waves-fig9",
        env!("CARGO_BIN_EXE_waves-fig9"),
        &args(&["--runs", "1"]),
        "default",
        &[
            "waves-fig9.csv",
            "waves-fig9_alpha.png",
            "waves-fig9_validity.png",
        ],
    );
    assert!(pass(&s, "valid_up_to_rho_1"));
    assert!(pass(&s, "validity_limit_detected"));
    let lim = metric(&s, "rho_limit_any_invalid");
    assert!(lim > 1.0 && lim <= 3.0, "rho limit {lim}");
}

#[test]
fn fig11_bookkeeping_and_correlation_speed() {
    let s = common::run_figure(
        "waves-fig11",
        env!("CARGO_BIN_EXE_waves-fig11"),
        &args(&["--runs", "2"]),
        "default",
        &FIG11_FILES,
    );
    assert!(pass(&s, "bookkeeping_exact"));
    assert!(pass(&s, "correlation_peak_inside"));
    assert!(within_pinned(&s), "v_corr = {}", metric(&s, "v_corr"));
}

const FIG11_FILES: [&str; 4] = [
    "waves-fig11b.csv",
    "waves-fig11b.png",
    "waves-fig11a_I0.5.png",
    "waves-fig11a_I0.3.png",
];

/// v_corr pinned at 1.0 +- 0 (quick, seed 1, 2 runs, default reading
/// `ph94+gravity-first+wall-move`: C(R, T) peaks at T = R, the free-falling
/// streams; `ph94` gave 0.2765 +- 0.0013, EXPERIMENTS.md); tolerance 3
/// combined SE.
fn within_pinned(s: &serde_json::Value) -> bool {
    let pinned = (1.0, 0.0);
    let (v, e) = (metric(s, "v_corr"), metric(s, "v_corr_err"));
    (v - pinned.0).abs() <= 3.0 * (e * e + pinned.1 * pinned.1).sqrt()
}

/// The pinned correlation speed fails for the `ph94` reading (v_corr =
/// 0.2765). Ignored by default to keep the suite short (about 40 s
/// on two shared cores; the clogging I = 0.5 runs dominate): run with
/// `cargo test --release --test waves_sweeps -- --ignored`.
#[test]
#[ignore]
fn fig11_a_wrong_reading_fails_the_pinned_speed() {
    let w = common::run_figure(
        "waves-fig11",
        env!("CARGO_BIN_EXE_waves-fig11"),
        &args(&["--runs", "2", "--rules", "ph94"]),
        "ph94",
        &FIG11_FILES,
    );
    assert!(
        !within_pinned(&w),
        "ph94 v_corr = {} must fail",
        metric(&w, "v_corr")
    );
}
