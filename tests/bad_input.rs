//! Bad input on the command line of every kind found in issue 16: each is
//! refused before any run, with a non-zero exit and a message naming the
//! option (or value) and its allowed range; never a panic, an abort, a
//! silent coercion or a NaN result. Each call returns in well under a
//! second (nothing is computed).

use std::path::PathBuf;
use std::process::Command;

/// Run `exe` with `args` (figure binaries: output into a scratch folder,
/// `bench` and `explore` write nothing); assert it fails
/// cleanly (exit code 1 or clap's 2, no panic or abort) and that stderr
/// contains every one of `want`.
fn refused(exe: &str, args: &[&str], want: &[&str]) {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("bad-input");
    let mut cmd = Command::new(exe);
    cmd.args(args);
    if !(exe.ends_with("bench") || exe.ends_with("explore")) {
        cmd.arg("--out").arg(&out);
    }
    let o = cmd.output().expect("the binary runs");
    let err = String::from_utf8_lossy(&o.stderr);
    let code = o.status.code();
    assert!(
        matches!(code, Some(1) | Some(2)),
        "{exe} {args:?}: exit {code:?} (a panic is 101, an abort a signal): {err}"
    );
    assert!(!err.contains("panicked"), "{exe} {args:?} panicked: {err}");
    for w in want {
        assert!(err.contains(w), "{exe} {args:?}: '{w}' not in: {err}");
    }
}

#[test]
fn runs_and_threads_out_of_range_are_refused() {
    let huge = "18446744073709551615";
    for exe in [
        env!("CARGO_BIN_EXE_fig2"),
        env!("CARGO_BIN_EXE_fig1"),
        env!("CARGO_BIN_EXE_hopper-fig2"),
        env!("CARGO_BIN_EXE_hopper-fig3"),
        env!("CARGO_BIN_EXE_waves-fig3"),
        env!("CARGO_BIN_EXE_waves-fig5"),
        env!("CARGO_BIN_EXE_waves-fig8"),
    ] {
        refused(exe, &["--runs", huge], &["--runs", "1..=100000"]);
        refused(exe, &["--runs", "0"], &["--runs", "1..=100000"]);
        refused(exe, &["--threads", "0"], &["--threads", "1..=1024"]);
    }
}

#[test]
fn explore_refuses_bad_runs_and_densities_and_reads_negative_numbers() {
    let exe = env!("CARGO_BIN_EXE_explore");
    refused(exe, &["--runs", "0"], &["--runs", "1..=100000"]);
    refused(exe, &["--runs", "100000000000"], &["--runs", "1..=100000"]);
    refused(exe, &["--p", "-0.1"], &["p = -0.1", "[0, 1]"]);
    refused(exe, &["--rho", "0"], &["rho = 0", "(0, 6)"]);
    refused(exe, &["--rho", "6"], &["rho = 6", "(0, 6)"]);
    refused(exe, &["--steps", "0"], &["--steps = 0", "[160, inf)"]);
    refused(
        exe,
        &["--stops", "--steps", "1"],
        &["--steps = 1", "[2, inf)"],
    );
    refused(
        exe,
        &["--stops", "--engine", "fast", "--length", "220"],
        &["--engine = fast", "reference"],
    );
}

#[test]
fn figure_options_name_themselves_and_their_range() {
    refused(
        env!("CARGO_BIN_EXE_waves-fig12"),
        &["--steps", "0"],
        &["--steps", "1000..="],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig12"),
        &["--sizes", "220x11,220x11"],
        &["--sizes", "220x11", "more than once"],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig12"),
        &["--sizes", "220x1"],
        &["W", "220x1", "[2, inf)"],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig4"),
        &["--lengths", "128,128"],
        &["--lengths", "128", "more than once"],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig4"),
        &["--lengths", "4"],
        &["L = 4", "[8, inf)"],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig5"),
        &["--p", "-0.1"],
        &["p = -0.1", "[0, 1]"],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig9"),
        &["--rho", "0"],
        &["--rho", "rho = 0", "(0, 6)"],
    );
    refused(
        env!("CARGO_BIN_EXE_waves-fig9"),
        &["--rho", "-1,2"],
        &["--rho", "rho = -1"],
    );
    refused(
        env!("CARGO_BIN_EXE_bench"),
        &["--steps", "0"],
        &["--steps", "10..="],
    );
}

#[test]
fn merge_errors_name_the_path() {
    let missing = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("no-such-shard");
    refused(
        env!("CARGO_BIN_EXE_merge"),
        &[missing.to_str().unwrap()],
        &[missing.to_str().unwrap()],
    );
}
