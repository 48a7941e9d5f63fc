//! The `--engine` option of the pipe figures (issue 13): every pipe figure
//! runs with the fast engine and records it in summary.json, an unknown
//! engine is a typed error naming the known ones, and PH94 Fig. 2 run by the
//! fast engine decides its claims as the reference does (the fast engine is
//! validated by `validate`, tests/fast_engine.rs; this is the figure-level
//! check that the plumbing hands it the figure's runs).

mod common;
use common::{contradicted, metric, pass, run_figure};
use std::process::Command;

/// (binary, executable, the cheapest arguments that exercise it, a file it
/// must write)
fn figures() -> Vec<(&'static str, &'static str, Vec<&'static str>, &'static str)> {
    vec![
        (
            "fig1",
            env!("CARGO_BIN_EXE_fig1"),
            vec!["--runs", "1"],
            "fig1.png",
        ),
        (
            "waves-fig2",
            env!("CARGO_BIN_EXE_waves-fig2"),
            vec!["--runs", "1"],
            "summary.json",
        ),
        (
            "waves-fig3",
            env!("CARGO_BIN_EXE_waves-fig3"),
            vec!["--runs", "1", "--steps", "2000"],
            "summary.json",
        ),
        (
            "waves-fig4",
            env!("CARGO_BIN_EXE_waves-fig4"),
            vec!["--runs", "1", "--lengths", "128"],
            "summary.json",
        ),
        (
            "waves-fig5",
            env!("CARGO_BIN_EXE_waves-fig5"),
            vec!["--runs", "1", "--length", "128"],
            "summary.json",
        ),
        (
            "waves-fig6",
            env!("CARGO_BIN_EXE_waves-fig6"),
            vec!["--runs", "1"],
            "summary.json",
        ),
        (
            "waves-fig7",
            env!("CARGO_BIN_EXE_waves-fig7"),
            vec!["--runs", "1"],
            "summary.json",
        ),
        (
            "waves-fig8",
            env!("CARGO_BIN_EXE_waves-fig8"),
            vec!["--runs", "1", "--p", "0,0.5"],
            "summary.json",
        ),
        (
            "waves-fig9",
            env!("CARGO_BIN_EXE_waves-fig9"),
            vec!["--runs", "1", "--rho", "1.4"],
            "summary.json",
        ),
        (
            "waves-fig10",
            env!("CARGO_BIN_EXE_waves-fig10"),
            vec!["--runs", "1"],
            "summary.json",
        ),
        (
            "waves-fig11",
            env!("CARGO_BIN_EXE_waves-fig11"),
            vec!["--runs", "1", "--correlation-only"],
            "summary.json",
        ),
        (
            "waves-fig12",
            env!("CARGO_BIN_EXE_waves-fig12"),
            vec![
                "--runs",
                "1",
                "--sizes",
                "220x11",
                "--no-spectra",
                "--bisections",
                "3",
            ],
            "summary.json",
        ),
    ]
}

#[test]
fn every_pipe_figure_runs_with_the_fast_engine_and_records_it() {
    for (bin, exe, extra, file) in figures() {
        let mut args = vec!["--tier", "quick", "--seed", "1", "--engine", "fast"];
        args.extend(extra);
        let s = run_figure(bin, exe, &args, "fast", &[file]);
        assert_eq!(s["engine"], "fast", "{bin}: summary.json names the engine");
    }
}

#[test]
fn an_unknown_engine_is_an_error_naming_the_known_ones() {
    let out = Command::new(env!("CARGO_BIN_EXE_fig2"))
        .args(["--engine", "gpu", "--out"])
        .arg(std::env::temp_dir().join("engines-unknown"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("gpu") && err.contains("reference, fast"),
        "{err}"
    );
}

/// PH94 Fig. 2 at the quick tier (4 runs, seed 1) with the fast engine: the
/// same decisions as the reference's in tests/spectra.rs (alpha not
/// contradicted and within the margin 0.1 of 4/3; v_peak reproduced within
/// 0.01 of 0.40), and the reference's default summary names its engine.
#[test]
fn fig2_with_the_fast_engine_decides_as_the_reference() {
    let fig2 = env!("CARGO_BIN_EXE_fig2");
    let args = ["--tier", "quick", "--seed", "1", "--engine", "fast"];
    let s = run_figure("fig2", fig2, &args, "fast-decides", &["fig2.png"]);
    assert_eq!(s["engine"], "fast");
    let (a, ae) = (metric(&s, "alpha"), metric(&s, "alpha_err"));
    assert!(!contradicted(&s, "alpha"), "alpha = {a} +- {ae}");
    assert!((a - 4.0 / 3.0).abs() <= 0.1, "alpha = {a} +- {ae}");
    assert!(pass(&s, "v_peak"), "v_peak = {}", metric(&s, "v_peak"));
}
