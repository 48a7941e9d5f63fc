//! Hostile and extreme input at the newest surfaces, as an outside tester
//! tries it: a summary on its margin's edge or with an SE of 1e308, hand
//! edits of a summary or of a committed seed set, a candidate that forks or
//! daemonizes, counts that overflow, and options given negative or extreme
//! values. Each is refused (naming the file, the field or the value and its
//! range) or handled, within a bound on its time; never a hang, a panic or
//! a silent acceptance.

mod common;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// Run `cmd` for at most `limit`; its output and the time it took, or
/// `None` (the process killed) when it did not end in time.
fn within(cmd: &mut Command, limit: Duration) -> (Option<Output>, Duration) {
    let start = Instant::now();
    let child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the binary starts");
    let id = child.id();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || tx.send(child.wait_with_output()));
    match rx.recv_timeout(limit) {
        Ok(o) => (Some(o.expect("the output is read")), start.elapsed()),
        Err(_) => {
            let _ = Command::new("kill")
                .args(["-KILL", &id.to_string()])
                .status();
            (None, start.elapsed())
        }
    }
}

/// Its stdout and stderr, one text.
fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// A fresh report folder holding the committed report's fig2 summary after
/// `edit`; `None` outside a checkout (the published crate has no docs/).
fn fig2_report(tag: &str, edit: impl Fn(&mut Value)) -> Option<PathBuf> {
    let committed = common::in_repository("docs/report/fig2/summary.json")?;
    let out = common::fresh_dir(&format!("hardening-{tag}"));
    std::fs::create_dir_all(out.join("fig2")).unwrap();
    let text = std::fs::read_to_string(committed).unwrap();
    let mut s: Value = serde_json::from_str(&text).unwrap();
    edit(&mut s);
    std::fs::write(out.join("fig2/summary.json"), s.to_string()).unwrap();
    Some(out)
}

/// The check `name` of summary `s`, to edit.
fn check<'a>(s: &'a mut Value, name: &str) -> &'a mut Value {
    s["checks"]
        .as_array_mut()
        .unwrap()
        .iter_mut()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("no check {name}"))
}

/// `report --no-run --tier acceptance --only fig2 --out OUT`.
fn report_cmd(out: &Path) -> Command {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_report"));
    let args = ["--no-run", "--tier", "acceptance", "--only", "fig2"];
    cmd.args(args).arg("--out").arg(out);
    cmd
}

/// [`report_cmd`] with `extra`, stopped after 30 s.
fn report_no_run(out: &Path, extra: &[&str]) -> (Option<Output>, Duration) {
    within(report_cmd(out).args(extra), Duration::from_secs(30))
}

/// A summary on its margin's edge, or with an SE up to 1e308, renders at
/// once: the runs that would decide it are found in O(log) evaluations of
/// the coverage factor, each O(1) past 62 runs (it hung: the factor cost
/// grew with the run count, and the search doubled it up to 10^9).
#[test]
fn a_check_on_its_margins_edge_or_with_a_huge_se_renders_within_a_second() {
    let cases: [(&str, f64, f64); 4] = [
        ("edge", 1.33 - 0.059 - 1e-6, 0.010848018237458627),
        ("se-1e3", 1.2562365452968807, 1e3),
        ("se-1e100", 1.2562365452968807, 1e100),
        ("se-1e308", 1.2562365452968807, 1e308),
    ];
    for (tag, alpha, se) in cases {
        let Some(out) = fig2_report(tag, |s| {
            let c = check(s, "alpha");
            c["measured"] = alpha.into();
            c["error"] = se.into();
            c["verdict"] = "undecided".into();
            c["pass"] = false.into();
        }) else {
            return;
        };
        let (o, took) = report_no_run(&out, &[]);
        let o = o.unwrap_or_else(|| panic!("{tag}: report did not end in 30 s"));
        assert!(o.status.success(), "{tag}: {}", text(&o));
        assert!(took < Duration::from_secs(1), "{tag}: took {took:?}");
        let md = std::fs::read_to_string(out.join("report/REPORT.md")).unwrap();
        let want = if tag == "edge" {
            "more than 1000000000 runs"
        } else {
            "no run count decides it"
        };
        assert!(
            md.contains(want) || md.contains("more than 1000000000 runs"),
            "{tag}: {md}"
        );
    }
}

/// `report --no-run` recomputes every verdict from the value, SE, runs and
/// margin by the one rule, and checks each field's type: a hand-edited
/// summary that disagrees is refused, naming the file and the field (it
/// was taken at its word: a forged "reproduced" raised the headline).
#[test]
fn hand_edited_summaries_are_refused_naming_the_file_and_field() {
    type Edit = Box<dyn Fn(&mut Value)>;
    let edits: Vec<(&str, Edit, &str)> = vec![
        (
            "forged-verdict",
            Box::new(|s| {
                let c = check(s, "alpha");
                c["verdict"] = "reproduced".into();
                c["pass"] = true.into();
            }),
            "the one rule gives undecided",
        ),
        (
            "string-value",
            Box::new(|s| check(s, "alpha")["measured"] = "abc".into()),
            "`measured` is \"abc\"",
        ),
        (
            "string-pass",
            Box::new(|s| check(s, "alpha")["pass"] = "yes".into()),
            "`pass` is \"yes\"",
        ),
        (
            "negative-margin",
            Box::new(|s| {
                let c = check(s, "alpha");
                c["claim"]["margin"] = (-0.059).into();
                c["tolerance"] = (-0.059).into();
            }),
            "the margin >= 0",
        ),
        (
            "negative-runs",
            Box::new(|s| check(s, "alpha")["runs"] = (-1).into()),
            "`runs` is -1",
        ),
        (
            "bad-sequential",
            Box::new(|s| check(s, "v_peak")["sequential"] = serde_json::json!({"look": "x"})),
            "`sequential`",
        ),
        (
            "metrics-array",
            Box::new(|s| s["metrics"] = serde_json::json!([1, 2])),
            "`metrics`",
        ),
    ];
    for (tag, edit, want) in edits {
        let Some(out) = fig2_report(tag, edit) else {
            return;
        };
        let (o, took) = report_no_run(&out, &[]);
        let o = o.unwrap_or_else(|| panic!("{tag}: report did not end in 30 s"));
        let all = text(&o);
        assert_eq!(o.status.code(), Some(1), "{tag}: {all}");
        assert!(
            all.contains("fig2/summary.json") && all.contains(want),
            "{tag}: {want:?} not in {all}"
        );
        assert!(took < Duration::from_secs(1), "{tag}: took {took:?}");
    }
}

/// A committed seed set edited by hand is refused by `report --seed-sets`,
/// naming the file: by the one rule where its verdict no longer fits its
/// value, by its seal where the edit kept them consistent (one number
/// changed in a copy turned "alpha over 20 seed sets" from not reproduced
/// to undecided, exit 0, no warning).
#[test]
fn a_tampered_seed_set_is_refused_naming_the_file() {
    let Some(from) = common::in_repository("docs/acceptance/fig2") else {
        return;
    };
    for (tag, forge) in [("value", false), ("value-and-verdict", true)] {
        let sets = common::fresh_dir(&format!("hardening-sets-{tag}"));
        let dir = sets.join("fig2");
        for e in std::fs::read_dir(&from).unwrap().flatten() {
            let s = e.path().join("fig2/summary.json");
            if s.is_file() {
                let to = dir.join(e.file_name()).join("fig2");
                std::fs::create_dir_all(&to).unwrap();
                std::fs::copy(&s, to.join("summary.json")).unwrap();
            }
        }
        if from.join("seals.tsv").is_file() {
            std::fs::copy(from.join("seals.tsv"), dir.join("seals.tsv")).unwrap();
        }
        let five = dir.join("seed-5/fig2/summary.json");
        let mut s: Value = serde_json::from_str(&std::fs::read_to_string(&five).unwrap()).unwrap();
        let c = check(&mut s, "alpha");
        c["measured"] = 1.33.into();
        if forge {
            // a verdict that fits the forged value: only the seal shows it
            let (se, runs) = (c["error"].as_f64().unwrap(), c["runs"].as_u64().unwrap());
            let est = granular_automata::analysis::grading::Estimate::new(1.33, se, runs as usize);
            let claim = granular_automata::analysis::grading::Claim::Within {
                target: 1.33,
                margin: c["claim"]["margin"].as_f64().unwrap(),
            };
            let v = granular_automata::analysis::grading::grade(est, claim);
            c["verdict"] = v.status().into();
            c["pass"] = (v == granular_automata::analysis::grading::Verdict::Reproduced).into();
        }
        std::fs::write(&five, s.to_string()).unwrap();
        // this run is seed set 1, as in the committed report
        let out = fig2_report(&format!("twin-{tag}"), |_| {}).expect("in a checkout");
        let (o, took) = report_no_run(&out, &["--seed-sets", sets.to_str().unwrap()]);
        let o = o.unwrap_or_else(|| panic!("{tag}: report did not end in 30 s"));
        let all = text(&o);
        assert!(
            all.contains("seed-5/fig2/summary.json")
                && all.contains(if forge { "seal" } else { "one rule" }),
            "{tag}: {all}"
        );
        assert!(
            !all.contains("fig2 alpha over 20 seed sets"),
            "{tag}: graded over the tampered sets: {all}"
        );
        assert!(took < Duration::from_secs(1), "{tag}: took {took:?}");
    }
}

/// A candidate that forks a child keeping its output open, or a daemon in
/// a session of its own, is stopped at its run's end or time limit with
/// everything it started: `validate` ends at once and no process is left
/// (it waited for the child's end, ignoring --run-timeout, and left it
/// running).
#[test]
fn a_forking_or_daemonizing_candidate_is_stopped_with_everything_it_started() {
    for (tag, cmd, needle) in [
        ("fork", "cmd:sleep 43.25 & echo not-a-sample #", "43.25"),
        (
            "daemon",
            "cmd:setsid sleep 47.25 & echo not-a-sample #",
            "47.25",
        ),
        ("stall", "cmd:sleep 41.25 & sleep 39.25 #", "1.25"),
    ] {
        let out = common::fresh_dir(&format!("hardening-{tag}"));
        let mut v = Command::new(env!("CARGO_BIN_EXE_validate"));
        v.args(["--candidate", cmd, "--level", "1", "--model", "pipe"])
            .args(["--run-timeout", "2", "--out"])
            .arg(&out);
        let (o, took) = within(&mut v, Duration::from_secs(60));
        let o = o.unwrap_or_else(|| panic!("{tag}: validate did not end in 60 s"));
        assert_eq!(o.status.code(), Some(1), "{tag}: {}", text(&o));
        assert!(took < Duration::from_secs(10), "{tag}: took {took:?}");
        std::thread::sleep(Duration::from_millis(200));
        assert_eq!(common::sleeps_with(needle), Vec::<String>::new(), "{tag}");
    }
}

/// The contract's identity sums the channel counts without wrap-around: a
/// sample whose counts overflow 64 bits is refused (they summed to 0 and
/// passed against empty bins).
#[test]
fn channel_counts_that_overflow_are_refused() {
    use granular_automata::validate::candidate::check_identity;
    let e = check_identity(&[0.0], &[u64::MAX, 1, 0, 0, 0, 0, 0]).unwrap_err();
    assert!(e.contains("overflows"), "{e}");
    assert!(check_identity(&[3.0], &[1, 2, 0, 0, 0, 0, 0]).is_ok());
}

/// A hopper candidate's end line is held to its plan: iterations beyond
/// what the plan asked for, or counters no run of it could reach, are
/// refused (an end line with iterations 2^64 - 1 was accepted and the
/// report showed 1.8e19 iterations).
#[test]
fn a_hopper_end_line_beyond_its_plan_is_refused() {
    let dir = common::fresh_dir("hardening-hopper-end");
    std::fs::create_dir_all(&dir).unwrap();
    // the real engine, its end line's iterations replaced
    let script = dir.join("liar.sh");
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\n\"{}\" \"$@\" | sed 's/\"iterations\":[0-9]*/\"iterations\":18446744073709551615/'\n",
            env!("CARGO_BIN_EXE_validate-example")
        ),
    )
    .unwrap();
    let mut v = Command::new(env!("CARGO_BIN_EXE_validate"));
    v.arg("--candidate")
        .arg(format!("cmd:sh {}", script.display()))
        .args(["--level", "2", "--model", "hopper", "--out"])
        .arg(dir.join("out"));
    let (o, took) = within(&mut v, Duration::from_secs(300));
    let o = o.expect("validate ends");
    assert!(took < Duration::from_secs(30), "took {took:?}");
    let all = text(&o);
    assert_eq!(o.status.code(), Some(1), "{all}");
    assert!(
        all.contains("iterations = 18446744073709551615, where its plan asks for"),
        "{all}"
    );
}

/// Too few runs for the acceptance estimators are refused before any run,
/// and nothing is written (2 runs were computed, their PNG and CSVs
/// written beside an older summary, and only then refused).
#[test]
fn too_few_acceptance_runs_are_refused_before_running() {
    for runs in ["1", "2"] {
        let out = common::fresh_dir(&format!("hardening-few-runs-{runs}"));
        let mut f = Command::new(env!("CARGO_BIN_EXE_fig2"));
        f.args(["--tier", "acceptance", "--fixed-runs", runs, "--out"])
            .arg(&out);
        let (o, took) = within(&mut f, Duration::from_secs(60));
        let o = o.expect("fig2 ends");
        assert_eq!(o.status.code(), Some(2), "{}", text(&o));
        assert!(text(&o).contains("at least 3 runs"), "{}", text(&o));
        assert!(took < Duration::from_secs(1), "took {took:?}");
        assert!(!out.join("fig2").exists(), "fig2 wrote into {out:?}");
    }
}

/// `sequential-design --spectra`: a run file whose spectrum is no power
/// spectrum, too few runs, or a margin that cannot be one are refused at
/// once, naming the file and the value (exit 1, not the usage code 2);
/// the binary takes --threads.
#[test]
fn sequential_design_refuses_bad_spectra_naming_the_file() {
    let suite = common::fresh_dir("hardening-spectra");
    let write = |fig: &str, runs: usize, bad_bin: Option<f64>, margin: f64| {
        let folder = suite.join(fig).join("runs/k");
        let _ = std::fs::remove_dir_all(&folder);
        std::fs::create_dir_all(&folder).unwrap();
        for i in 0..runs {
            let mut spectrum: Vec<f64> = (1..=4096).map(|j| (j as f64).powf(-1.3)).collect();
            if let (0, Some(x)) = (i, bad_bin) {
                spectrum[7] = x;
            }
            let mut body = serde_json::json!({"index": i, "key": {}, "seed": i,
                "result": {"spectrum": spectrum}});
            let sum = fnv1a64(body.to_string().as_bytes());
            body["checksum"] = format!("{sum:016x}").into();
            std::fs::write(folder.join(format!("run-{i:05}.json")), body.to_string()).unwrap();
        }
        let summary = serde_json::json!({"checks": [{"name": "alpha", "tolerance": margin}]});
        std::fs::write(suite.join(fig).join("summary.json"), summary.to_string()).unwrap();
    };
    let run = |extra: &[&str]| {
        let mut c = Command::new(env!("CARGO_BIN_EXE_sequential-design"));
        c.args(["--trials", "100", "--spectra"])
            .arg(&suite)
            .args(extra)
            .arg("--out")
            .arg(suite.join("out"));
        let (o, took) = within(&mut c, Duration::from_secs(60));
        (o.expect("sequential-design ends"), took)
    };
    write("waves-fig6", 4, None, 0.06);
    for (bad, margin, runs, want) in [
        (Some(-1.0), 0.06, 4, "spectrum bin 7 is -1"),
        (Some(0.0), 0.06, 4, "spectrum bin 7 is 0"),
        (None, 1e308, 4, "outside the allowed range (0, 1]"),
        (None, 0.06, 2, "at least 3"),
    ] {
        write("fig2", runs, bad, margin);
        let (o, took) = run(&["--threads", "1"]);
        let all = text(&o);
        assert_eq!(o.status.code(), Some(1), "{want}: {all}");
        assert!(all.contains(want) && all.contains("fig2"), "{want}: {all}");
        assert!(took < Duration::from_secs(2), "{want}: took {took:?}");
    }
}

/// FNV-1a, as the run files' checksum (`ensemble::fnv1a64`).
fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Negative values reach the option's own parser, which names the value
/// and its range (clap said "unexpected argument '-1'").
#[test]
fn negative_values_name_the_option_and_its_range() {
    let (fuzz, design) = (
        env!("CARGO_BIN_EXE_fuzz"),
        env!("CARGO_BIN_EXE_sequential-design"),
    );
    let (fig2, fig9) = (env!("CARGO_BIN_EXE_fig2"), env!("CARGO_BIN_EXE_waves-fig9"));
    let range = "is outside the allowed range";
    for (exe, args, want) in [
        (fig2, &["--sequential-max", "-1"][..], "1..=64"),
        (fuzz, &["--inputs", "-1"][..], "1..=100000000"),
        (fuzz, &["--seed", "-1"][..], "0..=18446744073709551615"),
        (design, &["--trials", "-5"][..], "100..=10000000"),
        (fig9, &["--length", "-220"][..], "0..="),
    ] {
        let o = Command::new(exe).args(args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{exe} {args:?}");
        let want = format!("{} = {} {range} {want}", args[0], args[1]);
        assert!(text(&o).contains(&want), "{exe} {args:?}: {}", text(&o));
    }
}

/// Extreme floats are written as 1e300 and 1e-320, not with hundreds of
/// digits, in messages and in a reading's name.
#[test]
fn extreme_floats_are_written_short() {
    for args in [
        &["--p", "1e300"][..],
        &["--p", "-1e300"][..],
        &["--rho", "1e-320"][..],
        &["--g", "1e-320", "--p", "2"][..],
    ] {
        let o = Command::new(env!("CARGO_BIN_EXE_explore"))
            .args(args)
            .output()
            .unwrap();
        let err = text(&o);
        assert!(!o.status.success(), "{args:?}");
        let longest = err
            .split(|c: char| !c.is_ascii_digit())
            .map(str::len)
            .max()
            .unwrap_or(0);
        assert!(longest < 30, "{args:?}: {err}");
    }
    let r: granular_automata::pipe::Rules = "default+lane-collide:1e-320".parse().unwrap();
    assert!(r.to_string().ends_with("+lane-collide:1e-320"), "{r}");
    let r: granular_automata::pipe::Rules = "default+lane-collide:0.001".parse().unwrap();
    assert!(r.to_string().ends_with("+lane-collide:0.001"), "{r}");
    let e = "default+lane-collide:1e300"
        .parse::<granular_automata::pipe::Rules>()
        .unwrap_err();
    assert!(e.to_string().contains("q = 1e300 is outside"), "{e}");
}

/// An impossible length suggests only lengths the pipe can have (it
/// offered L = 18446744073709551610 for L = 2^64 - 1).
#[test]
fn an_impossible_length_suggests_a_possible_one() {
    let o = Command::new(env!("CARGO_BIN_EXE_explore"))
        .args(["--length", "18446744073709551615"])
        .output()
        .unwrap();
    let err = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("choose L = 18446744073709551610"), "{err}");
    assert!(err.contains("[9, 4294967295]"), "{err}");
}

/// A file where an output folder should go is refused before the work,
/// within a second (fuzz and report checked the path only after it).
#[test]
fn a_file_given_as_output_folder_is_refused_before_the_work() {
    let dir = common::fresh_dir("hardening-out-file");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let mut fuzz = Command::new(env!("CARGO_BIN_EXE_fuzz"));
    fuzz.args(["--readers", "summary", "--inputs", "100000", "--out"])
        .arg(&file);
    let Some(out) = fig2_report("publish-file", |_| {}) else {
        return;
    };
    let mut report = report_cmd(&out);
    report.arg("--publish").arg(&file);
    for (name, cmd) in [("fuzz", &mut fuzz), ("report", &mut report)] {
        let (o, took) = within(cmd, Duration::from_secs(60));
        let o = o.expect("ends");
        assert!(!o.status.success(), "{name}");
        assert!(text(&o).contains("a-file"), "{name}: {}", text(&o));
        assert!(took < Duration::from_secs(1), "{name}: took {took:?}");
    }
}

/// An unreadable --claim-notes file is a failure while running, exit 1 as
/// docs/reference/cli.md says (it exited 2, the usage code).
#[test]
fn a_missing_claim_notes_file_exits_one() {
    let Some(out) = fig2_report("claim-notes", |_| {}) else {
        return;
    };
    let o = report_cmd(&out)
        .args(["--experiments"])
        .arg(out.join("EXPERIMENTS.md"))
        .args(["--claim-notes", "/no/such/notes.tsv"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("/no/such/notes.tsv"), "{}", text(&o));
}

/// The matrix and the bridge describe their own --runs, not the
/// sequential design of the figures, which they do not have.
#[test]
fn the_matrix_help_describes_its_own_runs() {
    for exe in [
        env!("CARGO_BIN_EXE_bridge"),
        env!("CARGO_BIN_EXE_pipe-matrix"),
    ] {
        let o = Command::new(exe).arg("--help").output().unwrap();
        let help = text(&o);
        assert!(
            !help.contains("replaces the sequential design"),
            "{exe}: {help}"
        );
        assert!(
            help.contains("the matrix has no sequential design"),
            "{exe}: {help}"
        );
    }
}
