//! Bad input on the command line of every kind tried: each is
//! refused before any run, with a non-zero exit and a message naming the
//! option (or value) and its allowed range; never a panic, an abort, a
//! silent coercion or a NaN result. Each call returns in well under a
//! second (nothing is computed).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// u64::MAX, the largest number a count option can be given.
const HUGE: &str = "18446744073709551615";

/// waves-fig9 over one point (rho = 5.99) with one run: a quick sweep.
const SWEEP_ONE_RUN: [&str; 4] = ["--rho", "5.99", "--runs", "1"];

/// Run `exe` with `args` (figure binaries: output into a scratch folder,
/// `bench` and `explore` write nothing); assert it fails
/// cleanly (exit code 1 or clap's 2, no panic or abort) and that stderr
/// contains every one of `want`. Returns the exit code.
fn refused(exe: &str, args: &[&str], want: &[&str]) -> i32 {
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
    assert_has(&err, want);
    code.expect("an exit code")
}

/// Run `exe` with `args` and `--out out`, to its end.
fn run_out(exe: &str, args: &[&str], out: &Path) -> Output {
    Command::new(exe)
        .args(args)
        .arg("--out")
        .arg(out)
        .output()
        .expect("the binary runs")
}

/// [`run_out`], asserting that the run succeeded; its standard output.
fn ran(exe: &str, args: &[&str], out: &Path) -> String {
    let o = run_out(exe, args, out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8_lossy(&o.stdout).into_owned()
}

/// `report --no-run` of the hopper-fig3 folder of `r` at the acceptance
/// tier, with `extra` arguments.
fn report_hopper_fig3(r: &Path, extra: &[&str]) -> Output {
    let args = ["--no-run", "--only", "hopper-fig3", "--tier", "acceptance"];
    run_out(
        env!("CARGO_BIN_EXE_report"),
        &[&args[..], extra].concat(),
        r,
    )
}

/// Assert that `text` contains every one of `want`.
fn assert_has(text: &str, want: &[&str]) {
    for w in want {
        assert!(text.contains(w), "'{w}' not in: {text}");
    }
}

#[test]
fn runs_and_threads_out_of_range_are_refused() {
    for exe in [
        env!("CARGO_BIN_EXE_fig2"),
        env!("CARGO_BIN_EXE_fig1"),
        env!("CARGO_BIN_EXE_hopper-fig2"),
        env!("CARGO_BIN_EXE_hopper-fig3"),
        env!("CARGO_BIN_EXE_waves-fig3"),
        env!("CARGO_BIN_EXE_waves-fig5"),
        env!("CARGO_BIN_EXE_waves-fig8"),
    ] {
        refused(exe, &["--runs", HUGE], &["--runs", "1..=100000"]);
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
    refused(exe, &["--steps", "0"], &["--steps = 0", "160..=1000000000"]);
    refused(
        exe,
        &["--stops", "--steps", "1"],
        &["--steps = 1", "2..=1000000000"],
    );
    refused(
        exe,
        &["--stops", "--engine", "fast", "--length", "220"],
        &["--engine = fast", "reference"],
    );
}

/// A figure option out of its range: (binary, its arguments separated by
/// spaces, what stderr must name).
const FIGURE_OPTION_CASES: &[(&str, &str, &[&str])] = &[
    ("waves-fig12", "--steps 0", &["--steps", "1000..="]),
    (
        "waves-fig12",
        "--sizes 220x11,220x11",
        &["--sizes", "220x11", "more than once"],
    ),
    ("waves-fig12", "--sizes 220x1", &["W", "220x1", "[2, inf)"]),
    (
        "waves-fig4",
        "--lengths 128,128",
        &["--lengths", "128", "more than once"],
    ),
    ("waves-fig4", "--lengths 4", &["L = 4", "[8, inf)"]),
    ("waves-fig5", "--p -0.1", &["p = -0.1", "[0, 1]"]),
    ("waves-fig9", "--rho 0", &["--rho", "rho = 0", "(0, 6)"]),
    ("waves-fig9", "--rho -1,2", &["--rho", "rho = -1"]),
    (
        "waves-fig9",
        "--length 225",
        &["--length", "L = 225", "multiple of bin = 10"],
    ),
    (
        "waves-fig9",
        "--length 0",
        &["--length", "L (length) = 0", "[1, inf)"],
    ),
    ("bench", "--steps 0", &["--steps", "10..="]),
];

#[test]
fn figure_options_name_themselves_and_their_range() {
    // every binary lies in the folder of `bench`
    let dir = std::path::Path::new(env!("CARGO_BIN_EXE_bench"))
        .parent()
        .expect("a folder");
    for &(name, args, want) in FIGURE_OPTION_CASES {
        let exe = dir.join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
        let args: Vec<&str> = args.split(' ').collect();
        refused(exe.to_str().expect("a UTF-8 path"), &args, want);
    }
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

/// A scratch folder of this test file, emptied.
/// The JSON file at `path` (a summary, a run file).
fn json_at(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every usage error of `validate` exits 2 (VALIDATION.md), a
/// failing candidate 1; `--trials` has the lower bound at which the level-1
/// test can decide (`conformance::MIN_TRIALS`), negative numbers name
/// their option.
#[test]
fn validate_usage_errors_exit_2_and_name_the_option() {
    let exe = env!("CARGO_BIN_EXE_validate");
    for (args, want) in [
        (&["--trials", "1"][..], &["--trials", "100..=1000000"][..]),
        (&["--trials", "-1"], &["--trials = -1", "100..=1000000"]),
        (&["--runs", "-1"], &["--runs = -1", "3..=10000"]),
        (&["--runs", "2"], &["--runs = 2", "3..=10000"]),
        (&["--hopper-runs", "-3"], &["--hopper-runs = -3"]),
        (&["--repeat", "0"], &["--repeat = 0", "1..=10000"]),
        (&["--seed", "-1"], &["--seed"]),
        (&["--candidate", "mutant:nope"], &["biased-stream"]),
        (&["--rules", "nope"], &["nope"]),
        (&["--detect", "0"], &["--detect", "(0, 1]"]),
        (&["--detect", "150%"], &["--detect", "(0, 1]"]),
        (&["--detect", "1%", "--trials", "500"], &["--trials"]),
        (&["--detect", "0.01%"], &["smallest error"]),
    ] {
        let code = refused(exe, args, want);
        assert_eq!(code, 2, "validate {args:?}: a usage error exits 2");
    }
}

/// An external candidate whose samples have the wrong shape is
/// named a contract error with its first bad line (never an index panic, nor
/// graded as differing observables); a program that prints garbage is
/// quoted.
#[test]
fn validate_names_the_first_sample_of_the_wrong_shape() {
    let exe = env!("CARGO_BIN_EXE_validate");
    let example = env!("CARGO_BIN_EXE_validate-example");
    let out = scratch("bad-sample");
    let edited = |sed: &str| format!("cmd:f() {{ {example} \"$@\" | sed '{sed}'; }}; f");
    for (cand, want) in [
        (
            edited(r#"s/"bins":\[[^,]*,/"bins":[/"#),
            // the first run of level 2 is the rows probe's pipe, L = 200
            &["line 1 has 19 bins", "L / bin = 200 / 10 = 20"][..],
        ),
        (
            edited(r#"s/"bins":\[/"bins":[1.0,1.0,1.0,1.0,1.0,/"#),
            &["line 1 has 25 bins"],
        ),
        (
            edited(r#"s/"bins":\[[^]]*\]/"bins":[]/"#),
            &["line 1 has 0 bins"],
        ),
        (
            edited(r#"s/"channels":\[[0-9]*,/"channels":[/"#),
            &["line 1 has 6 channel counts", "asks for 7"],
        ),
        (
            edited(r#"s/"flux":\[/"flux":[0,/"#),
            &["line 1 has 4 flux counts", "asks for 3"],
        ),
        (
            edited(r#"2s/"t":[0-9]*/"t":7/"#),
            &["line 2 has t = 7", "t = 20"],
        ),
        (
            "cmd:echo garbage".to_string(),
            &["garbage run --plan -"][..],
        ),
    ] {
        let args = ["--candidate", &cand, "--level", "2", "--runs", "3"];
        let mut cmd = Command::new(exe);
        let o = cmd.args(args).arg("--out").arg(&out).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{cand}: {err}");
        assert!(!err.contains("panicked"), "{cand}: {err}");
        assert!(err.contains("see VALIDATION.md for the contract"), "{err}");
        for w in want {
            assert!(err.contains(w), "{cand}: '{w}' not in: {err}");
        }
    }
}

/// `--cases` of the hopper figures rejects a case given twice.
#[test]
fn hopper_cases_are_given_once() {
    for exe in [
        env!("CARGO_BIN_EXE_hopper-fig2"),
        env!("CARGO_BIN_EXE_hopper-fig3"),
    ] {
        refused(
            exe,
            &["--cases", "beta0,beta0"],
            &["--cases", "beta0", "more than once"],
        );
    }
}

/// An effectively empty pipe (fewer than one particle per bin on
/// average) or a pipe of one bin is refused, not measured as C = 0.
#[test]
fn effectively_empty_pipes_are_refused() {
    refused(
        env!("CARGO_BIN_EXE_waves-fig9"),
        &["--rho", "1e-300"],
        &["--rho", "rho = 1e-300", "[1/110, 6)"],
    );
    let explore = env!("CARGO_BIN_EXE_explore");
    refused(
        explore,
        &["--rho", "1e-300"],
        &["rho = 1e-300", "[1/110, 6)"],
    );
    refused(
        explore,
        &["--rho", "0.05", "--width", "1"],
        &["rho = 0.05", "[1/10, 6)"],
    );
    refused(explore, &["--length", "10"], &["L = 10", "[20, inf)"]);
}

/// `--steps` has the same cap in every binary, and sizes are
/// multiplied without wrapping around.
#[test]
fn steps_share_one_cap_and_sizes_do_not_wrap() {
    for exe in [
        env!("CARGO_BIN_EXE_waves-fig3"),
        env!("CARGO_BIN_EXE_waves-fig11"),
        env!("CARGO_BIN_EXE_waves-fig12"),
        env!("CARGO_BIN_EXE_explore"),
        env!("CARGO_BIN_EXE_bench"),
    ] {
        for steps in [HUGE, "1000000001"] {
            refused(exe, &["--steps", steps], &["--steps", "..=1000000000"]);
        }
    }
    let e = refused(
        env!("CARGO_BIN_EXE_waves-fig12"),
        &["--sizes", &format!("220x{HUGE}")],
        &[
            "(W + 2) * (L + 2)",
            "18446744073709551617 * 222 = 4095177184363520458974",
            "[9, 4294967295]",
        ],
    );
    assert_eq!(e, 2, "a size out of range is a usage error");
}

/// `report` and `speed-accuracy` range-check their numbers and
/// name the option of a negative one; `report --only` offers figures only.
#[test]
fn report_and_speed_accuracy_check_their_numbers() {
    let report = env!("CARGO_BIN_EXE_report");
    for t in ["0", "-1", "1025"] {
        refused(report, &["--threads", t], &["--threads", "1..=1024"]);
    }
    refused(report, &["--seed", "-1"], &["--seed"]);
    for tool in ["validate", "validate-example"] {
        refused(report, &["--only", tool], &["unknown figure", tool]);
    }
    let speed = env!("CARGO_BIN_EXE_speed-accuracy");
    refused(speed, &["--seed", "-1"], &["--seed"]);
    refused(speed, &["--threads", "-1"], &["--threads", "1..=1024"]);
}

/// `speed-accuracy --from` names a missing folder and a damaged
/// summary.json before it runs anything.
#[test]
fn speed_accuracy_from_names_missing_and_damaged_summaries() {
    let speed = env!("CARGO_BIN_EXE_speed-accuracy");
    let dir = scratch("speed-from");
    let missing = dir.join("no-such-folder");
    let quick = [
        "--figures",
        "fig1",
        "--tiers",
        "quick",
        "--engines",
        "reference",
    ];
    let args = |from: &PathBuf| {
        let mut a: Vec<String> = quick.iter().map(|s| s.to_string()).collect();
        a.extend(["--from".to_string(), from.display().to_string()]);
        a
    };
    let a = args(&missing);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    refused(
        speed,
        &a,
        &["--from", missing.to_str().unwrap(), "no such folder"],
    );
    let earlier = dir.join("earlier");
    std::fs::create_dir_all(earlier.join("fig1")).unwrap();
    let summary = earlier.join("fig1").join("summary.json");
    std::fs::write(&summary, "{\"tier\": ").unwrap();
    let a = args(&earlier);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    refused(speed, &a, &[summary.to_str().unwrap(), "is not JSON"]);
}

/// An --out whose summary.json is a folder is named, and no
/// temporary file is left behind.
#[test]
fn a_folder_in_the_way_of_summary_json_is_named() {
    let out = scratch("summary-folder");
    let fig = out.join("waves-fig3");
    std::fs::create_dir_all(fig.join("summary.json")).unwrap();
    let args = ["--runs", "1", "--steps", "480"];
    let o = run_out(env!("CARGO_BIN_EXE_waves-fig3"), &args, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let path = fig.join("summary.json");
    assert!(err.contains(path.to_str().unwrap()), "{err}");
    let left: Vec<_> = std::fs::read_dir(&fig)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with("tmp~"))
        .collect();
    assert!(left.is_empty(), "temporary files left: {left:?}");
}

/// `merge` checks every run file's key (seed, tier, parameters),
/// index and seed against the folder it goes into, names what differs and
/// copies nothing; an empty shard folder and a shard that is a file are
/// named as such.
#[test]
fn merge_rejects_foreign_runs_and_empty_or_file_shards() {
    let dir = scratch("merge-foreign");
    let fig3 = env!("CARGO_BIN_EXE_waves-fig3");
    let shard = |name: &str, shard: &str, extra: &[&str]| {
        let out = dir.join(name);
        let args = [&["--runs", "2", "--shard", shard][..], extra].concat();
        assert!(run_out(fig3, &args, &out).status.success(), "{name}");
        let runs = out.join("waves-fig3").join("runs");
        let hash = std::fs::read_dir(&runs).unwrap().next().unwrap().unwrap();
        hash.path()
    };
    // shard 0 holds run 0; the others' run 1 would complete it
    let good = shard("good", "0/2", &["--steps", "480"]);
    let other_seed = shard("seed2", "1/2", &["--steps", "480", "--seed", "2"]);
    let other_tier = shard("standard", "1/2", &["--steps", "600", "--tier", "standard"]);
    // run file `file` of `from` copied as `as_file` into the good run folder
    // of another shard
    let hash = good.file_name().unwrap();
    let smuggle = |name: &str, from: &PathBuf, file: &str, as_file: &str| {
        let folder = dir.join(name).join("waves-fig3").join("runs").join(hash);
        std::fs::create_dir_all(&folder).unwrap();
        std::fs::copy(from.join(file), folder.join(as_file)).unwrap();
        dir.join(name)
    };
    // merge into `target`: exit 1 with every one of `want` in the message
    let target = dir.join("merged");
    let refused_merge = |shards: &[&PathBuf], want: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_merge"))
            .arg("--out")
            .arg(&target)
            .args(shards)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert_has(&err, want);
        assert!(!target.exists(), "nothing is copied: {err}");
    };
    let good_out = dir.join("good");
    for (bad, want) in [
        (
            smuggle("x-seed", &other_seed, "run-00001.json", "run-00001.json"),
            "base_seed: 2 vs 1",
        ),
        (
            smuggle("x-tier", &other_tier, "run-00001.json", "run-00001.json"),
            "config.tier: \"standard\" vs \"quick\"",
        ),
        (
            smuggle("x-index", &good, "run-00000.json", "run-00001.json"),
            "its index is 0, its file name says 1",
        ),
    ] {
        refused_merge(&[&good_out, &bad], &["does not belong in", want]);
    }
    let empty = scratch("merge-foreign-empty");
    refused_merge(
        &[&good_out, &empty],
        &[empty.to_str().unwrap(), "holds no run folder"],
    );
    let file = dir.join("a-file");
    std::fs::write(&file, "").unwrap();
    refused_merge(
        &[&file],
        &[file.to_str().unwrap(), "is a file, not a folder"],
    );
}

/// A copy of the committed report's `hopper-fig3` folder in a fresh `R/`;
/// `None` outside a checkout of the repository (the report is not
/// published with the crate).
fn report_folder_with_hopper_fig3(name: &str) -> Option<PathBuf> {
    let from = common::in_repository("docs/report/hopper-fig3")?;
    let r = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&r);
    let to = r.join("hopper-fig3");
    std::fs::create_dir_all(&to).unwrap();
    for e in std::fs::read_dir(&from).unwrap() {
        let e = e.unwrap();
        std::fs::copy(e.path(), to.join(e.file_name())).unwrap();
    }
    Some(r)
}

/// `report --publish` into its own `--out` (or inside it) is refused before
/// anything is written: it used to delete the figure's folder, summary.json
/// included, and then fail to copy it.
#[test]
fn report_refuses_to_publish_into_its_own_out_and_deletes_nothing() {
    let Some(r) = report_folder_with_hopper_fig3("publish-into-out") else {
        return;
    };
    let files = |d: &PathBuf| std::fs::read_dir(d).unwrap().count();
    let before = files(&r.join("hopper-fig3"));
    for publish in [r.clone(), r.join("copy"), r.join("hopper-fig3")] {
        let o = report_hopper_fig3(&r, &["--publish", publish.to_str().unwrap()]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{publish:?}: {err}");
        assert_has(&err, &["--publish", "apart from --out"]);
        assert_eq!(
            files(&r.join("hopper-fig3")),
            before,
            "{publish:?} deleted files"
        );
        assert!(r.join("hopper-fig3/summary.json").is_file());
        assert!(!r.join("copy").exists());
    }
}

/// A publish folder whose figure folder holds a file a published copy does
/// not write is refused, and the file is kept; a clean one is published.
#[test]
fn report_publish_keeps_what_it_did_not_write() {
    let Some(r) = report_folder_with_hopper_fig3("publish-foreign-file") else {
        return;
    };
    let dest = r.with_file_name("publish-foreign-file-dest");
    let _ = std::fs::remove_dir_all(&dest);
    std::fs::create_dir_all(dest.join("hopper-fig3")).unwrap();
    std::fs::write(dest.join("hopper-fig3/notes.txt"), "mine").unwrap();
    let publish = |d: &PathBuf| report_hopper_fig3(&r, &["--publish", d.to_str().unwrap()]);
    let o = publish(&dest);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("notes.txt"), "{err}");
    assert_eq!(
        std::fs::read_to_string(dest.join("hopper-fig3/notes.txt")).unwrap(),
        "mine"
    );
    std::fs::remove_file(dest.join("hopper-fig3/notes.txt")).unwrap();
    let o = publish(&dest);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(dest.join("hopper-fig3/summary.json").is_file());
    assert!(dest.join("index.html").is_file());
    assert!(!dest.join(".publish-staging").exists());
}

/// Exit statuses follow the kind of error, not where it is caught: a value
/// out of range or an unknown name exits 2 like clap's own usage errors,
/// and `--help` exits 0, in every binary.
#[test]
fn usage_errors_exit_2_and_help_exits_0_everywhere() {
    let fig2 = env!("CARGO_BIN_EXE_fig2");
    let fig3 = env!("CARGO_BIN_EXE_waves-fig3");
    for (exe, args, want) in [
        (fig3, &["--p", "2"][..], "p = 2"),
        (fig3, &["--p", "NaN"][..], "p = NaN"),
        (fig2, &["--rules", "x"][..], "x"),
        (fig2, &["--engine", "gpu"][..], "gpu"),
        (
            env!("CARGO_BIN_EXE_report"),
            &["--only", "x"][..],
            "unknown figure",
        ),
        (
            env!("CARGO_BIN_EXE_hopper-fig2"),
            &["--cases", "nope"][..],
            "nope",
        ),
        (
            env!("CARGO_BIN_EXE_validate-example"),
            &["walk"][..],
            "usage",
        ),
        // the sequential design (the acceptance tier's default) cannot
        // shard; its options need it, and a count is fixed one way only
        (
            env!("CARGO_BIN_EXE_waves-fig6"),
            &["--tier", "acceptance", "--shard", "0/2"][..],
            "give --fixed-runs N",
        ),
        (
            fig2,
            &["--sequential-max", "4"][..],
            "only for the sequential design",
        ),
        (
            fig2,
            &[
                "--tier",
                "acceptance",
                "--fixed-runs",
                "64",
                "--sequential-max",
                "4",
            ][..],
            "only for the sequential design",
        ),
        (fig2, &["--sequential-max", "0"][..], "1..=64"),
        // PH95 Fig. 12 grades its spectrum points sequentially too
        (
            env!("CARGO_BIN_EXE_waves-fig12"),
            &["--sequential-max", "2"][..],
            "only for the sequential design",
        ),
        (
            env!("CARGO_BIN_EXE_waves-fig12"),
            &["--tier", "acceptance", "--sequential-max", "65"][..],
            "1..=64",
        ),
        (fig2, &["--fixed-runs", "0"][..], "1..=100000"),
        (
            fig2,
            &["--fixed-runs", "64", "--runs", "64"][..],
            "cannot be used multiple times",
        ),
    ] {
        assert_eq!(refused(exe, args, &[want]), 2, "{exe} {args:?}");
    }
    for exe in [
        env!("CARGO_BIN_EXE_validate-example"),
        env!("CARGO_BIN_EXE_validate-detection"),
        fig2,
        env!("CARGO_BIN_EXE_validate"),
        env!("CARGO_BIN_EXE_report"),
    ] {
        let o = Command::new(exe).arg("--help").output().unwrap();
        assert_eq!(o.status.code(), Some(0), "{exe} --help");
        assert!(String::from_utf8_lossy(&o.stdout).contains("usage") || !o.stdout.is_empty());
    }
}

/// A candidate whose bins break the contract's identity (whole particles,
/// summing to the channel counts) fails, whatever its series look like:
/// every bin + 1 or + 0.5 used to pass level 2, and constant bins aborted
/// with an error that did not name the candidate. Each is now a FAIL with
/// a report naming what was wrong; the first bad run stops the level.
#[test]
fn validate_fails_a_candidate_that_breaks_the_bin_identity() {
    let exe = env!("CARGO_BIN_EXE_validate");
    let example = env!("CARGO_BIN_EXE_validate-example");
    let edited = |perl: &str| format!("cmd:f() {{ {example} \"$@\" | perl -pe '{perl}'; }}; f");
    let bins = |expr: &str| {
        edited(&format!(
            r#"s/"bins":\[([^\]]*)\]/"\"bins\":[".join(",", map {{ {expr} }} split(",", $1))."]"/e"#
        ))
    };
    for (tag, cand, want) in [
        ("plus-one", bins("$_ + 1"), "bins summing to"),
        ("plus-half", bins("$_ + 0.5"), "not a whole number"),
        ("zero", bins("0"), "bins summing to"),
        ("huge", bins("1e308"), "bins summing to"),
    ] {
        let out = scratch(&format!("identity-{tag}"));
        let args = [
            "--candidate",
            &cand,
            "--level",
            "2",
            "--runs",
            "3",
            "--model",
            "pipe",
        ];
        let start = std::time::Instant::now();
        let o = run_out(exe, &args, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{tag}: {err}");
        assert!(err.contains("FAILS") && err.contains(want), "{tag}: {err}");
        let report = std::fs::read_to_string(out.join("validate/report.md")).unwrap();
        assert!(
            report.contains("FAIL") && report.contains(want),
            "{tag}: {report}"
        );
        assert!(
            report.contains("perl"),
            "the report names the candidate: {report}"
        );
        assert!(
            start.elapsed().as_secs() < 60,
            "{tag}: the first bad run stops it"
        );
    }
}

/// A candidate that prints a line far longer than its plan allows is
/// stopped with a typed error instead of being read into memory.
#[test]
fn validate_caps_the_length_of_a_candidate_line() {
    let exe = env!("CARGO_BIN_EXE_validate");
    let out = scratch("long-line");
    let cand = "cmd:f() { head -c 50000000 /dev/zero | tr '\\0' x; }; f";
    let args = ["--candidate", cand, "--level", "1", "--model", "pipe"];
    let o = run_out(exe, &args, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_has(&err, &["bytes", "its plan"]);
}

/// SIGINT to `validate` stops the external candidate it is running (its
/// own process group) before exiting: it used to be left running.
#[test]
fn an_interrupted_validate_stops_its_candidate() {
    let exe = env!("CARGO_BIN_EXE_validate");
    let out = scratch("interrupted");
    let mut child = Command::new(exe)
        .args(["--candidate", "cmd:f() { sleep 37.25; }; f", "--level", "1"])
        .args(["--model", "pipe", "--out"])
        .arg(&out)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while common::sleeps_with("37.25").is_empty() && start.elapsed().as_secs() < 20 {
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    assert!(
        !common::sleeps_with("37.25").is_empty(),
        "the candidate started"
    );
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    assert!(kill.unwrap().success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130));
    std::thread::sleep(std::time::Duration::from_millis(200));
    assert_eq!(common::sleeps_with("37.25"), Vec::<String>::new());
}

/// `report --no-run` over the committed hopper-fig3 summary after `edit`:
/// its exit code and its standard output and error together.
fn report_over_edited_summary(
    tag: &str,
    edit: &dyn Fn(&str) -> String,
    extra: &[&str],
) -> Option<(i32, String)> {
    let r = report_folder_with_hopper_fig3(&format!("malformed-{tag}"))?;
    let path = r.join("hopper-fig3/summary.json");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, edit(&text)).unwrap();
    let o = report_hopper_fig3(&r, extra);
    let all = format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
    Some((o.status.code().unwrap_or(-1), all))
}

/// A summary.json that is truncated, empty, not JSON (NaN, 1e999), has no
/// checks, a decided verdict without a value, an unknown verdict or kind,
/// or is of another tier fails the figure (exit 1), naming what is wrong;
/// it used to count as run, or as reproduced.
#[test]
fn report_refuses_malformed_summaries() {
    // a summary edited as JSON: parse, apply `f`, write back
    type Edit = Box<dyn Fn(&str) -> String>;
    let json = |f: fn(&mut serde_json::Value)| -> Edit {
        Box::new(move |t| {
            let mut v: serde_json::Value = serde_json::from_str(t).unwrap();
            f(&mut v);
            v.to_string()
        })
    };
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "truncated",
            Box::new(|t| t[..t.len() / 2].to_string()),
            "cannot read",
        ),
        ("empty", Box::new(|_| String::new()), "cannot read"),
        (
            "nan",
            Box::new(|t| t.replacen("\"measured\": ", "\"measured\": NaN, \"x\": ", 1)),
            "cannot read",
        ),
        (
            "huge",
            Box::new(|t| t.replacen("\"measured\": ", "\"measured\": 1e999, \"x\": ", 1)),
            "cannot read",
        ),
        (
            "no-checks",
            Box::new(|t| t.replacen("\"checks\"", "\"chex\"", 1)),
            "no `checks` field",
        ),
        (
            "null-measured",
            json(|v| {
                v["checks"][0]["verdict"] = "reproduced".into();
                v["checks"][0]["measured"] = serde_json::Value::Null;
            }),
            "`measured` is null",
        ),
        (
            "bogus-verdict",
            json(|v| v["checks"][0]["verdict"] = "bogus".into()),
            "`verdict` is \"bogus\"",
        ),
        (
            "bogus-kind",
            json(|v| v["checks"][0]["kind"] = "folklore".into()),
            "`kind` is \"folklore\"",
        ),
        (
            "other-tier",
            json(|v| v["tier"] = "paper".into()),
            "of the paper tier, this report's is acceptance",
        ),
    ];
    for (tag, edit, want) in cases {
        let Some((code, all)) = report_over_edited_summary(tag, &*edit, &[]) else {
            return;
        };
        assert_eq!(code, 1, "{tag}: {all}");
        assert!(
            all.contains(want) && all.contains("hopper-fig3"),
            "{tag}: {want:?} not in {all}"
        );
    }
    let (code, all) = report_over_edited_summary("unedited", &|t| t.to_string(), &[]).unwrap();
    assert_eq!(code, 0, "{all}");
}

/// `report --seed-sets` refuses a copied seed set (it counted twice) and a
/// seed set of another set-up, naming both folders.
#[test]
fn report_seed_sets_refuse_copies_and_mismatches() {
    let sets = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("seed-set-copies");
    let _ = std::fs::remove_dir_all(&sets);
    let Some(from) = common::in_repository("docs/acceptance/hopper-fig3") else {
        return;
    };
    for e in std::fs::read_dir(&from).unwrap().flatten() {
        if !e.path().join("summary.json").is_file() {
            continue;
        }
        let to = sets.join("hopper-fig3").join(e.file_name());
        std::fs::create_dir_all(&to).unwrap();
        std::fs::copy(e.path().join("summary.json"), to.join("summary.json")).unwrap();
    }
    let extra = sets.join("hopper-fig3/seed-99");
    std::fs::create_dir_all(&extra).unwrap();
    let five = std::fs::read_to_string(from.join("seed-5/summary.json")).unwrap();
    let seed_sets = ["--seed-sets", sets.to_str().unwrap()];
    std::fs::write(extra.join("summary.json"), &five).unwrap();
    // sealed as filed: the copy is refused for being a copy
    let seal = |only: &[String]| {
        granular_automata::drivers::acceptance_study::seal(
            &sets.join("hopper-fig3"),
            "hopper-fig3",
            only,
        )
        .unwrap()
    };
    seal(&[]);
    let (_, all) =
        report_over_edited_summary("copied-set", &|t| t.to_string(), &seed_sets).unwrap();
    assert_has(&all, &["counts once", "seed-99"]);
    let mut other: serde_json::Value = serde_json::from_str(&five).unwrap();
    other["seeds"][0] = 7.into();
    other["tier"] = "paper".into();
    std::fs::write(extra.join("summary.json"), other.to_string()).unwrap();
    seal(&["seed-99".into()]);
    let (_, all) =
        report_over_edited_summary("other-set-up", &|t| t.to_string(), &seed_sets).unwrap();
    assert_has(&all, &["share one set-up", "tier paper"]);
}

/// PNGs and CSVs an earlier run left in a figure's folder (e.g. before
/// `--correlation-only`) are named in summary.json as `stale_files`, kept,
/// and left out of the report, which linked them as this run's.
#[test]
fn stale_outputs_of_an_earlier_run_are_named_and_not_reported() {
    let out = scratch("stale-outputs");
    let fig = out.join("waves-fig3");
    std::fs::create_dir_all(&fig).unwrap();
    std::fs::write(fig.join("old-plot.png"), b"not a picture of this run").unwrap();
    std::fs::write(fig.join("old.csv"), b"a,b\n").unwrap();
    let args = ["--runs", "1", "--steps", "480"];
    let text = ran(env!("CARGO_BIN_EXE_waves-fig3"), &args, &out);
    assert_has(&text, &["old-plot.png", "stale_files"]);
    let s = json_at(&fig.join("summary.json"));
    assert_eq!(
        s["stale_files"],
        serde_json::json!(["old-plot.png", "old.csv"])
    );
    assert!(fig.join("old-plot.png").is_file(), "kept");
    let args = ["--no-run", "--only", "waves-fig3", "--tier", "quick"];
    ran(env!("CARGO_BIN_EXE_report"), &args, &out);
    let page = std::fs::read_to_string(out.join("report/REPORT.md")).unwrap();
    assert!(
        !page.contains("old-plot.png") && !page.contains("old.csv"),
        "{page}"
    );
    assert!(page.contains("waves-fig3"));
}

/// hopper-fig2 draws its snapshot pictures beside the first beta = 0 case
/// whatever the order of `--cases`, and says so when there is none (it
/// labelled a beta = 1 run "beta = 0" and skipped silently).
#[test]
fn hopper_fig2_panels_follow_the_cases_not_their_order() {
    let exe = env!("CARGO_BIN_EXE_hopper-fig2");
    let out = scratch("hopper-fig2-cases");
    let text = ran(exe, &["--cases", "beta1_bond", "--runs", "1"], &out);
    assert!(text.contains("no beta = 0 case among --cases"), "{text}");
    // one run has no error bar, not one of 0
    let zero = |l: &&str| l.contains("(1 runs)") && l.contains("+- 0.0000");
    assert_eq!(text.lines().find(zero), None);
    let text = ran(exe, &["--cases", "beta1_bond,beta0", "--runs", "1"], &out);
    assert!(!text.contains("no beta = 0 case"), "{text}");
    let pictures: Vec<String> = std::fs::read_dir(out.join("hopper-fig2"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("hopper-fig2-") && n.ends_with(".png"))
        .filter(|n| !n.contains("activity") && !n.ends_with("-gr.png"))
        .collect();
    assert_eq!(
        pictures,
        ["hopper-fig2-along-bond.png"],
        "the beta = 1 case's picture"
    );
    assert_eq!(
        pictures.len(),
        1,
        "one picture, of the beta = 1 case: {pictures:?}"
    );
}

/// FNV-1a, 64 bits: the run files' checksum (src/ensemble.rs).
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A saved run whose `contrast` series was shortened and its file re-sealed
/// with a valid checksum is refused, naming the file, instead of panicking
/// in the analysis.
#[test]
fn a_resealed_run_with_a_short_series_is_refused() {
    let exe = env!("CARGO_BIN_EXE_waves-fig3");
    let out = scratch("resealed-run");
    let args = ["--runs", "1", "--steps", "480"];
    ran(exe, &args, &out);
    let mut files = vec![];
    let mut stack = vec![out.clone()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.file_name().unwrap().to_string_lossy().starts_with("run-") {
                files.push(p);
            }
        }
    }
    assert_eq!(files.len(), 1, "{files:?}");
    let mut v = json_at(&files[0]);
    let body = v.as_object_mut().unwrap();
    body.remove("checksum");
    let series = body["result"]["contrast"]
        .as_array_mut()
        .expect("a contrast series");
    series.truncate(series.len() / 2);
    let sum = format!(
        "{:016x}",
        fnv1a64(
            serde_json::Value::Object(body.clone())
                .to_string()
                .as_bytes()
        )
    );
    body.insert("checksum".into(), sum.into());
    std::fs::write(&files[0], v.to_string()).unwrap();
    let o = run_out(exe, &args, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_has(&err, &["`contrast` series has", "run-00000.json"]);
}

/// Zero or one run is undecided and has no error bar: a sweep with no run
/// at rho <= 1 does not pass the claim about those runs, and fig2's alpha
/// over one run has no `alpha_err` (it used to be the fit's own error).
#[test]
fn zero_or_one_run_decides_nothing_and_has_no_error_bar() {
    let out = scratch("vacuous");
    let o = run_out(env!("CARGO_BIN_EXE_waves-fig9"), &SWEEP_ONE_RUN, &out);
    let text = String::from_utf8_lossy(&o.stdout);
    let line = text.lines().find(|l| l.contains("valid_up_to_rho_1"));
    assert!(
        line.is_some_and(|l| l.starts_with("[UNDECIDED]")),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = ran(env!("CARGO_BIN_EXE_fig2"), &["--runs", "1"], &out);
    let s = json_at(&out.join("fig2/summary.json"));
    assert!(s["metrics"]["alpha_err"].is_null(), "{}", s["metrics"]);
    assert!(
        s["missing_metrics"]["alpha_err"].is_string(),
        "{}",
        s["missing_metrics"]
    );
    assert!(text.contains("(no standard error: one run)"), "{text}");
}

/// `validate-example` plans: steps and iteration counts are capped, a plan
/// that asks for no sample is an error (it exited 0 with no output), and a
/// long plan is streamed (it held every sample in memory first).
#[test]
fn validate_example_caps_its_plans_and_streams() {
    let exe = env!("CARGO_BIN_EXE_validate-example");
    let pipe = r#"{"params":{"length":64,"width":4,"rho":1.0,"p":0.5,"g":0.5,"b":0.5,"bin":8,"boundary":"Periodic"},"rules":"default","seed":1,"init":null,"sites":false,"#;
    let run = |mode: &str, plan: String| {
        let mut c = Command::new(exe)
            .args([mode, "--plan", "-"])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        use std::io::Write;
        c.stdin.take().unwrap().write_all(plan.as_bytes()).unwrap();
        c.wait_with_output().unwrap()
    };
    for (steps, every, want) in [
        ("0", "1", "steps = 0"),
        ("2", "5", "every = 5"),
        (HUGE, HUGE, "steps = 18446744073709551615"),
    ] {
        let o = run(
            "run",
            format!("{pipe}\"steps\":{steps},\"every\":{every}}}"),
        );
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{steps} {every}: {err}");
        assert!(err.contains(want), "{err}");
        assert!(o.stdout.is_empty());
    }
    let o = run("run", format!("{pipe}\"steps\":3,\"every\":1}}"));
    assert_eq!(String::from_utf8_lossy(&o.stdout).lines().count(), 3);
    let params = serde_json::to_string(&granular_automata::hopper::HopperParams::quick()).unwrap();
    let hopper =
        |action: &str| format!(r#"{{"params":{params},"seed":1,"state":null,"action":{action}}}"#);
    for (action, want) in [
        (
            format!(r#"{{"steps":{{"n":{HUGE},"rain":false}}}}"#),
            "n = 18446744073709551615",
        ),
        (
            format!(r#"{{"fill":{{"target":10,"max_iterations":{HUGE},"max_settle":1}}}}"#),
            "max_iterations = 18446744073709551615",
        ),
    ] {
        let o = run("hopper", hopper(&action));
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{action}: {err}");
        assert!(err.contains(want), "{err}");
    }
}

/// `validate-detection` refuses a CSV it cannot count (a duplicated seed,
/// a NaN factor, no rows) naming it, instead of counting it; and
/// `validate --export-table --model hopper` is refused (it wrote the
/// pipe's table).
#[test]
fn validate_detection_refuses_what_it_cannot_count() {
    let exe = env!("CARGO_BIN_EXE_validate-detection");
    let head = "# candidate=mutant:p-r3*F level=One model=Pipe tier=Quick rules=default trials=4000 runs=8 hopper_runs=8\nseed,pass\n";
    for (tag, factor, rows, want) in [
        ("dup", "1.05", "1,true\n1,true\n", "counted twice"),
        ("nan", "NaN", "1,true\n", "not a finite positive number"),
        ("empty", "1.05", "", "no validation rows"),
    ] {
        let dir = scratch(&format!("detection-{tag}"));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("repeat-x.csv"), head.replace('F', factor) + rows).unwrap();
        let o = Command::new(exe).arg(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{tag}: {err}");
        assert!(
            err.contains(want) && err.contains("repeat-x.csv"),
            "{tag}: {err}"
        );
        assert!(!dir.join("detection.csv").exists());
    }
    let table = scratch("export-hopper").join("table.json");
    let o = Command::new(env!("CARGO_BIN_EXE_validate"))
        .args(["--model", "hopper", "--export-table"])
        .arg(&table)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(!table.exists());
}

/// Messages say what is allowed: the real size limit, `all` only alone,
/// an empty case name, a short time limit to the digit, and a length
/// suggestion that is itself accepted.
#[test]
fn messages_name_what_is_allowed() {
    refused(
        env!("CARGO_BIN_EXE_explore"),
        &["--length", "2000000000", "--width", "1"],
        &["(W + 2) * (L + 2)", "3 * 2000000002", "[9, 4294967295]"],
    );
    refused(
        env!("CARGO_BIN_EXE_hopper-fig2"),
        &["--cases", ","],
        &["empty case name"],
    );
    let e = refused(
        env!("CARGO_BIN_EXE_waves-fig4"),
        &["--lengths", "130"],
        &["L = 128 or 132"],
    );
    assert_eq!(e, 2);
    let e = refused(
        env!("CARGO_BIN_EXE_waves-fig4"),
        &["--lengths", "6"],
        &["choose L = 8 ("],
    );
    assert_eq!(e, 2);
    // the `#` hides the arguments validate appends ("$@"), which would make
    // sleep fail at once and race the time limit
    let out = scratch("timeout-message");
    let args = [
        "--candidate",
        "cmd:sleep 5 #",
        "--level",
        "1",
        "--model",
        "pipe",
        "--run-timeout",
        "0.001",
    ];
    let o = run_out(env!("CARGO_BIN_EXE_validate"), &args, &out);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("time limit of 0.001 s"), "{err}");
}

/// `pipe-matrix --help` (and the other figures that keep their runs in one
/// process) does not offer `--shard`, which it refuses.
#[test]
fn help_offers_no_shard_where_it_is_refused() {
    for exe in [
        env!("CARGO_BIN_EXE_pipe-matrix"),
        env!("CARGO_BIN_EXE_hopper-fig2"),
        env!("CARGO_BIN_EXE_hopper-fig3"),
        env!("CARGO_BIN_EXE_waves-fig12"),
    ] {
        let o = Command::new(exe).arg("--help").output().unwrap();
        assert!(
            !String::from_utf8_lossy(&o.stdout).contains("--shard"),
            "{exe}"
        );
        refused(exe, &["--shard", "0/2"], &["does not support --shard"]);
    }
    let o = Command::new(env!("CARGO_BIN_EXE_fig2"))
        .arg("--help")
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&o.stdout).contains("--shard"));
}

/// `report --args-for` reads its arguments as a shell does (quotes kept
/// together), and REPORT.md's Regenerate line is shell-quoted, so pasting
/// it runs the same command.
#[test]
fn report_quotes_its_regenerate_line_and_reads_quoted_args() {
    let Some(r) = report_folder_with_hopper_fig3("quoted-args") else {
        return;
    };
    let o = report_hopper_fig3(&r, &["--args-for", "hopper-fig3=--cases 'beta0'"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let page = std::fs::read_to_string(r.join("report/REPORT.md")).unwrap();
    let quoted = r#"'hopper-fig3=--cases '\''beta0'\'''"#;
    assert!(page.contains(quoted), "{quoted} not in {page}");
    let o = Command::new(env!("CARGO_BIN_EXE_report"))
        .args([
            "--no-run",
            "--only",
            "hopper-fig3",
            "--args-for",
            "hopper-fig3='--cases",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("unterminated"));
}

/// A sweep's pictures are written through its output folder, so a fresh
/// run names none of its own files as stale (they would leave the report).
#[test]
fn a_fresh_sweep_has_no_stale_files() {
    let out = scratch("fresh-sweep");
    let o = run_out(env!("CARGO_BIN_EXE_waves-fig9"), &SWEEP_ONE_RUN, &out);
    assert!(
        out.join("waves-fig9/waves-fig9_alpha.png").is_file(),
        "{o:?}"
    );
    let s = json_at(&out.join("waves-fig9/summary.json"));
    assert!(s["stale_files"].is_null(), "{}", s["stale_files"]);
}

#[test]
fn sequential_design_names_a_folder_without_saved_spectra() {
    let exe = env!("CARGO_BIN_EXE_sequential-design");
    refused(
        exe,
        &["--spectra", "no-such-suite", "--trials", "100"],
        &["no-such-suite", "cannot list"],
    );
    refused(exe, &["--trials", "99"], &["--trials", "100..=10000000"]);
}
