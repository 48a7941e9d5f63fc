//! Acceptance at the published set-ups (`--tier acceptance`, MODEL.md A10): the
//! headline claims of PH94 Fig. 2, PH95 Figs. 5-7 and BB90 Figs. 2-3 run as a
//! user runs them, the pipe on the fast engine and the hopper on its
//! reference engine, with the estimators and margins of
//! `drivers::acceptance`, and each verdict is asserted as recorded for base
//! seed 1 in EXPERIMENTS.md "Acceptance at the published set-ups" (with the
//! stability of each verdict over 20 base seeds). A change to the model, an
//! engine or the analysis that flips a verdict, or moves a value, fails here.
//! The pipe figures run the tier's default sequential design
//! (`drivers::acceptance::design`). Each test also checks that its run is,
//! result for result (a sequential run: on the checks that ran as many
//! runs), the committed seed set 1 of docs/acceptance, and asserts the
//! verdicts over all 20
//! committed seed sets (what `report --seed-sets docs/acceptance` prints):
//! a change that alters a result also shows that the committed seed sets
//! need refiling.
//!
//! Cost on two cores: fig2 about 290 CPU-s (128 runs of 2.6 million steps),
//! waves-fig6 about 260 CPU-s (128 runs), waves-fig7 about 60 CPU-s (8 runs
//! per case), waves-fig5 about 47 CPU-s (128 runs), hopper-fig3 (the default
//! reading and beta = 0, 16 runs each) about 300 CPU-s, hopper-fig2 (the
//! same two cases, 8 runs each) about 30 CPU-s.
//!
//! The three costliest (fig2, waves-fig6, hopper-fig3: about 850 CPU-s of
//! the 1000) are `#[ignore]`d: `cargo test --release --test acceptance --
//! --include-ignored` runs them all. In their place the default `cargo
//! test` runs each at its published set-up with the first few runs of base
//! seed 1 (`..._first_runs_are_pinned`, about 160 CPU-s together): their
//! values are pinned to the last bit, so any change to the model, an engine
//! or the analysis at those set-ups fails there too, and the verdicts of
//! the 20 committed seed sets are asserted from the files. A pinned value
//! that moves means: run the ignored tests, and refile the seed sets
//! (docs/acceptance/run-seeds.sh --refile) if a result moved.

mod common;

use common::verdict;
use granular_automata::drivers::acceptance_study::{all_seeds, committed_twin, Twin};
use std::collections::BTreeMap;

/// The published checks of summary `s` graded over every committed seed set
/// of its figure in docs/acceptance (check -> verdict), once `s` is shown to
/// be its committed twin: the same seeds and the same results. `None`
/// outside a checkout of the repository (the seed sets are not published
/// with the crate).
fn over_seed_sets(s: &serde_json::Value) -> Option<BTreeMap<String, String>> {
    let fig = s["figure"].as_str().expect("figure");
    let from = common::in_repository(&format!("docs/acceptance/{fig}"))?;
    match committed_twin(&from, fig, s).unwrap() {
        Twin::Identical { .. } => {}
        other => panic!(
            "{fig}: this run is not its committed seed set ({other:?}): refile {} (docs/acceptance/run-seeds.sh --refile)",
            from.display()
        ),
    }
    let (n, all) = all_seeds(&from, fig).unwrap();
    assert!(n >= 20, "{fig}: {n} committed seed sets");
    let over = all
        .into_iter()
        .map(|a| (a.check, a.verdict.status().to_string()))
        .collect();
    Some(over)
}

/// Figure `$bin` at its published set-up (`--tier acceptance` and the
/// options `$extra`), writing `$files`: its summary, once it is shown to have
/// run at that tier on `$engine` with `$runs` seeds.
macro_rules! at_published_set_up {
    ($bin:literal, $extra:expr, $files:expr, $engine:literal, $runs:literal) => {{
        let mut args = vec!["--tier", "acceptance"];
        args.extend_from_slice($extra);
        let s = run_figure!($bin, &args, "acceptance", $files);
        let seeds = s["seeds"].as_array().expect("seeds").len();
        assert_eq!(
            (s["tier"].as_str(), s["engine"].as_str(), seeds),
            (Some("acceptance"), Some($engine), $runs)
        );
        s
    }};
}

/// A recorded value: `measured` of check `name` equals `value` to 1e-9
/// (runs are pure functions of seed, rules and engine: the same bytes).
fn assert_value(s: &serde_json::Value, name: &str, value: f64, error: f64) {
    let c = s["checks"]
        .as_array()
        .expect("checks")
        .iter()
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("check {name} present"));
    let (m, e) = (
        c["measured"].as_f64().unwrap(),
        c["error"].as_f64().unwrap(),
    );
    assert!(
        (m - value).abs() < 1e-9 && (e - error).abs() < 1e-9,
        "{name}: measured {m} +- {e}, recorded {value} +- {error}"
    );
}

/// Figure `$bin` again with the fixed design (`--fixed-runs $runs`) into
/// the folder of its acceptance run above, whose saved runs it resumes: its
/// summary.
macro_rules! fixed_rerun {
    ($bin:literal, $runs:literal) => {{
        let out = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join(concat!($bin, "-acceptance"));
        let status = std::process::Command::new(env!(concat!("CARGO_BIN_EXE_", $bin)))
            .args(["--tier", "acceptance", "--fixed-runs", $runs, "--out"])
            .arg(&out)
            .status()
            .expect("the binary runs");
        assert!(status.success(), "{} --fixed-runs failed", $bin);
        let text = std::fs::read_to_string(out.join($bin).join("summary.json")).unwrap();
        let s: serde_json::Value = serde_json::from_str(&text).unwrap();
        s
    }};
}

/// Where check `name` stopped under the sequential design: (look, runs).
fn stopped(s: &serde_json::Value, name: &str) -> (u64, u64) {
    let q = &common::check(s, name)["sequential"];
    (q["look"].as_u64().unwrap(), q["runs"].as_u64().unwrap())
}

#[test]
#[ignore = "the whole published set-up, beyond CI's budget: its first runs are pinned below; run with --include-ignored"]
fn ph94_fig2_at_the_published_set_up_alpha_undecided_v_reproduced() {
    let s = at_published_set_up!(
        "fig2",
        &[],
        &["fig2.png", "spectrum.csv", "runs.csv"],
        "fast",
        128
    );
    // the default sequential design (looks 16, 32, 64, 128, O'Brien-Fleming):
    // alpha = 1.33 +- 0.059 runs to the last look, undecided at 19 of 20
    // base seeds with the fixed count (seed 19: not reproduced by 0.001);
    // all 2560 runs decide it not reproduced, and ~3400 runs per seed set
    // would give a stable verdict
    assert_eq!(verdict(&s, "alpha"), "undecided");
    assert_eq!(stopped(&s, "alpha"), (4, 128));
    assert_value(&s, "alpha", ALPHA_SEED1.0, ALPHA_SEED1.1);
    // v = 0.40 +- 0.007 is decided at the third look, 64 runs (k = 3.08)
    assert_eq!(verdict(&s, "v_peak"), "reproduced");
    assert_eq!(stopped(&s, "v_peak"), (3, 64));
    assert_value(&s, "v_peak", V_SEED1_64.0, V_SEED1_64.1);
    // over the 20 committed seed sets (2560 runs, the fixed design): alpha
    // 1.2634 +- 0.0026 not reproduced, v 0.3949 +- 0.0001 reproduced; the
    // twin is compared by runs (alpha's 128)
    if let Some(over) = over_seed_sets(&s) {
        assert_eq!(over["alpha"], "not-reproduced");
        assert_eq!(over["v_peak"], "reproduced");
    }
    // the fixed design resumes the same 128 runs and grades v over all
    let f = fixed_rerun!("fig2", "128");
    assert!(common::check(&f, "v_peak")["sequential"].is_null());
    assert_eq!(verdict(&f, "v_peak"), "reproduced");
    assert_value(&f, "v_peak", V_SEED1.0, V_SEED1.1);
    assert_value(&f, "alpha", ALPHA_SEED1.0, ALPHA_SEED1.1);
    if let Some(from) = common::in_repository("docs/acceptance/fig2") {
        assert!(matches!(
            committed_twin(&from, "fig2", &f).unwrap(),
            Twin::Identical { .. }
        ));
    }
}

#[test]
#[ignore = "the whole published set-up, beyond CI's budget: its first runs are pinned below; run with --include-ignored"]
fn ph95_fig6_at_the_published_set_up_alpha_undecided() {
    let s = at_published_set_up!(
        "waves-fig6",
        &[],
        &["waves-fig6.png", "spectrum.csv", "runs.csv"],
        "fast",
        128
    );
    // alpha = 1.33 +- 0.026: runs to the design's last look; undecided at 14
    // of 20 base seeds (6 not reproduced); all 2560 runs decide it not
    // reproduced (1.2945 +- 0.0014)
    assert_eq!(verdict(&s, "alpha"), "undecided");
    assert_eq!(stopped(&s, "alpha"), (4, 128));
    assert_value(&s, "alpha", FIG6_ALPHA_SEED1.0, FIG6_ALPHA_SEED1.1);
    if let Some(over) = over_seed_sets(&s) {
        assert_eq!(over["alpha"], "not-reproduced");
    }
}

/// alpha and its bootstrap SE of `waves-fig6 --tier acceptance --seed 1`
/// (docs/acceptance/waves-fig6/seed-1; the SE was the jackknife's 0.00689
/// until 2026-12-05).
const FIG6_ALPHA_SEED1: (f64, f64) = (1.2991502192576334, 0.007068415082855593);

/// alpha and its bootstrap SE of `fig2 --tier acceptance --seed 1` (the
/// SE was the jackknife's 0.01078 until 2026-12-05).
const ALPHA_SEED1: (f64, f64) = (1.2562365452968807, 0.010848018237458627);
/// v and its bootstrap SE of `fig2 --tier acceptance --seed 1 --fixed-runs 128`.
const V_SEED1: (f64, f64) = (0.39544677734375, 0.0006265051476578973);
/// v and its bootstrap SE over the first 64 runs, where the sequential
/// design stops it.
const V_SEED1_64: (f64, f64) = (0.394775390625, 0.0005742309637889227);

#[test]
fn ph95_fig7_at_the_published_set_up_not_white_with_the_line_at_one_half() {
    let s = at_published_set_up!("waves-fig7", &[], &["waves-fig7.png"], "fast", 8);
    // known discrepancies of the default reading: the spectra rise with
    // frequency (alpha < 0) instead of being white
    assert_eq!(verdict(&s, "alpha_p0"), "not-reproduced");
    assert_eq!(verdict(&s, "alpha_b0"), "not-reproduced");
    assert_eq!(verdict(&s, "v_peak_b0"), "reproduced");
    let Some(over) = over_seed_sets(&s) else {
        return;
    };
    let names = ["alpha_p0", "alpha_b0", "v_peak_b0"];
    let verdicts: Vec<&str> = names.iter().map(|n| over[*n].as_str()).collect();
    assert_eq!(verdicts, ["not-reproduced", "not-reproduced", "reproduced"]);
}

/// |v| and its SE, and the speed difference and its SE, of `waves-fig5
/// --tier acceptance --seed 1` (128 runs, fast engine).
const FIG5_SEED1: [(f64, f64); 2] = [
    (0.1237244593824342, 0.019357313113881364),
    (0.0658999479343195, 0.020668995437570687),
];

#[test]
fn ph95_fig5_at_the_published_set_up_speed_not_reproduced_speeds_coincide() {
    let s = at_published_set_up!("waves-fig5", &[], &["fig5.png", "runs.csv"], "fast", 128);
    // v = 0.36 +- 0.151 (2 x 0.05 + s_open 0.051): the default reading's
    // overlap speed is about 0.12, a known discrepancy (no bands at L = 512)
    assert_eq!(verdict(&s, "wave_speed"), "not-reproduced");
    assert_value(&s, "wave_speed", FIG5_SEED1[0].0, FIG5_SEED1[0].1);
    // the two speeds coincide within the same margin (both near 0.1)
    assert_eq!(verdict(&s, "speeds_agree"), "reproduced");
    assert_value(&s, "speeds_agree", FIG5_SEED1[1].0, FIG5_SEED1[1].1);
    // without runs that form bands the conditional variants cannot be graded
    assert_eq!(verdict(&s, "speeds_agree_wave_runs"), "undecided");
    let Some(over) = over_seed_sets(&s) else {
        return;
    };
    assert_eq!(over["wave_speed"], "not-reproduced");
    assert_eq!(over["speeds_agree"], "reproduced");
    assert_eq!(over["speeds_agree_wave_runs"], "undecided");
}

/// The flat-spectrum slope and its jackknife SE, and the rate ratio
/// (orientation on over off) and its SE, of `hopper-fig3 --tier acceptance
/// --cases beta1_bond,beta0 --seed 1` (16 runs per case, reference engine;
/// the same values as the four-case run of the committed report, since every
/// case sees the same seeds).
const BB90_FIG3_SEED1: [(f64, f64); 2] = [
    (-0.010397654710842653, 0.012133283802772806),
    (0.9419639539452221, 0.0034985868121581673),
];

#[test]
#[ignore = "the whole published set-up, beyond CI's budget: its first runs are pinned below; run with --include-ignored"]
fn bb90_fig3_at_the_published_set_up_rate_steady_spectrum_flat_not_white_at_lag_one() {
    let s = at_published_set_up!(
        "hopper-fig3",
        &["--cases", "beta1_bond,beta0"],
        &[
            "hopper-fig3-spectrum.png",
            "spectra.csv",
            "outflow_run0.csv"
        ],
        "reference",
        16
    );
    // the outflow rate: no trend, and the same with orientation on as off
    // (within 0.1 and 0.2)
    for name in ["beta1_bond_no_trend", "beta0_no_trend"] {
        assert_eq!(verdict(&s, name), "reproduced", "{name}");
    }
    assert_eq!(
        verdict(&s, "beta1_bond_rate_like_orientation_off"),
        "reproduced"
    );
    assert_value(
        &s,
        "beta1_bond_rate_like_orientation_off",
        BB90_FIG3_SEED1[1].0,
        BB90_FIG3_SEED1[1].1,
    );
    // the spectrum: flat below f = 1/8 with orientation on (slope 0 +- 0.111)
    assert_eq!(verdict(&s, "beta1_bond_white_spectrum"), "reproduced");
    assert_value(
        &s,
        "beta1_bond_white_spectrum",
        BB90_FIG3_SEED1[0].0,
        BB90_FIG3_SEED1[0].1,
    );
    // at beta = 0: flat in 19 of 20 seed sets; seed 1 is the one undecided
    // (-0.068 +- 0.021 against 0 +- 0.111)
    assert_eq!(verdict(&s, "beta0_white_spectrum"), "undecided");
    // known discrepancy: a period-2 alternation makes the lag-1
    // autocorrelation about -0.17, so the noise is not white over the whole
    // band (the spectrum rises above f = 1/4)
    for name in ["beta1_bond_white_lag1", "beta0_white_lag1"] {
        assert_eq!(verdict(&s, name), "not-reproduced", "{name}");
    }
    // over the 20 committed seed sets: the same verdicts, but for the flat
    // spectrum at beta = 0, which they decide reproduced
    let Some(over) = over_seed_sets(&s) else {
        return;
    };
    assert_eq!(over["beta0_white_spectrum"], "reproduced");
    assert_same_over_seed_sets(&s, &over, &["beta0_white_spectrum"]);
}

/// Every published check of `s` with a claim to grade (a number, not only
/// the words of the paper) has the same verdict over the committed seed
/// sets (`over`) as in `s`, except those named in `but`.
fn assert_same_over_seed_sets(
    s: &serde_json::Value,
    over: &BTreeMap<String, String>,
    but: &[&str],
) {
    let published = s["checks"].as_array().expect("checks").iter();
    let published = published.filter(|c| c["kind"] == "published" && c["claim"].is_object());
    let mut seen = 0;
    for c in published.filter(|c| !but.contains(&c["name"].as_str().unwrap())) {
        let name = c["name"].as_str().unwrap();
        assert_eq!(Some(&verdict(s, name)), over.get(name), "{name}");
        seen += 1;
    }
    assert!(seen > 0);
}

/// Seed 1 of BB90 Fig. 2's one claim the default reading does not reproduce:
/// the vertical fraction of moving grains in the core (> 0.45).
const BB90_FIG2_VERTICAL_SEED1: (f64, f64) = (0.3992569127293831, 0.0028609930071602464);

#[test]
fn bb90_fig2_at_the_published_set_up_every_claim_but_the_vertical_core() {
    let s = at_published_set_up!(
        "hopper-fig2",
        &["--cases", "beta0,beta1_bond"],
        &[
            "hopper-fig2-activity.png",
            "g_of_r.csv",
            "activity_profiles.csv"
        ],
        "reference",
        8
    );
    // each verdict repeats in all 20 base seeds (EXPERIMENTS.md "10. BB90
    // Fig. 2 and four cheap pipe figures over 20 seeds"); the values equal
    // those of the four-case default `--cases`, which sees the same seeds
    let beta0 = [
        "empties",
        "central_core",
        "core_constant_width",
        "core_lowered_density",
        "surface_v_shape",
        "structureless",
    ];
    let beta1 = [
        "empties",
        "central_core",
        "core_constant_width",
        "core_lowered_density",
        "surface_v_shape",
        "order_forms_while_filling",
        "order",
        "container_scale_order",
        "dense_sides",
        "defects",
    ];
    let names = beta0.iter().map(|n| format!("beta0_{n}"));
    for name in names.chain(beta1.iter().map(|n| format!("beta1_bond_{n}"))) {
        assert_eq!(verdict(&s, &name), "reproduced", "{name}");
    }
    // known discrepancy: the vertical fraction of the core's moving grains
    // is about 0.40 (1/3 at random), not above the threshold 0.45
    let name = "beta1_bond_vertical_core";
    assert_eq!(verdict(&s, name), "not-reproduced");
    let (value, error) = BB90_FIG2_VERTICAL_SEED1;
    assert_value(&s, name, value, error);
    // the same 17 verdicts over the 20 committed seed sets
    if let Some(over) = over_seed_sets(&s) {
        assert_same_over_seed_sets(&s, &over, &[]);
    }
}

/// The acceptance-tier reference of the sweeps' pinned checks
/// (`b0_matches_waves_fig7`, `p0_matches_waves_fig7`) is what the committed
/// PH95 Fig. 7 seed sets hold: their mean and the SE of their spread, to the
/// four digits the reference keeps. A refiled Fig. 7 that moves alpha fails
/// here until the reference follows.
#[test]
fn the_sweeps_fig7_reference_is_the_committed_fig7_seed_sets() {
    use granular_automata::drivers::sweep::{fig7_reference, Fig7Case};
    use granular_automata::run::Tier;
    let Some(from) = common::in_repository("docs/acceptance/waves-fig7") else {
        return;
    };
    let (seeds, all) = all_seeds(&from, "waves-fig7").unwrap();
    assert_eq!(seeds, 20);
    for (check, case) in [("alpha_p0", Fig7Case::P0), ("alpha_b0", Fig7Case::B0)] {
        let e = all.iter().find(|a| a.check == check).unwrap();
        let e = e.estimate.unwrap();
        let r = fig7_reference(Tier::Acceptance, case);
        let four = |x: f64| (x * 1e4).round() / 1e4;
        assert_eq!((four(e.mean), four(e.se)), (r.alpha, r.se), "{check}");
    }
}

/// PH95 Fig. 12's one published number, I_c = 0.52 (III I), over the 20
/// committed seed sets of its cut (`docs/acceptance/waves-fig12-ic`: the
/// main pipe without spectra; EXPERIMENTS.md section 13): the committed
/// report's whole Fig. 12 run is the cut's seed set 1 in every result they
/// share, and I_c is reproduced over the 20, at 0.51171875 in each. A whole
/// seed costs about 80 min and a seed of the cut 90 s, both beyond CI: this
/// test reads the committed files, so a refiled cut or report that moves
/// I_c fails here.
#[test]
fn ph95_fig12_i_c_over_the_seed_sets_of_its_cut() {
    let (Some(from), Some(report)) = (
        common::in_repository("docs/acceptance/waves-fig12-ic"),
        common::in_repository("docs/report/waves-fig12"),
    ) else {
        return;
    };
    let cut = std::fs::read_to_string(from.join("cut.txt")).unwrap();
    assert_eq!(cut.trim(), "waves-fig12 --sizes 220x11 --no-spectra");
    let whole = std::fs::read_to_string(report.join("summary.json"));
    let whole: serde_json::Value = serde_json::from_str(&whole.unwrap()).unwrap();
    match committed_twin(&from, "waves-fig12", &whole).unwrap() {
        Twin::Identical { committed } => assert!(committed.starts_with(from.join("seed-1"))),
        other => panic!("the report's Fig. 12 is not the cut's seed set 1: {other:?}"),
    }
    let (seeds, all) = all_seeds(&from, "waves-fig12").unwrap();
    assert_eq!(seeds, 20);
    let i_c = all.iter().find(|a| a.check == "i_c").expect("i_c graded");
    assert_eq!(i_c.verdict.status(), "reproduced");
    let e = i_c.estimate.unwrap();
    assert_eq!(
        (e.mean, e.se),
        (0.51171875, 0.0),
        "the same rate at every seed"
    );
}

/// The verdicts of figure `fig`'s published checks over its 20 committed
/// seed sets (check -> verdict), read from docs/acceptance; `None` outside
/// a checkout of the repository.
fn committed_verdicts(fig: &str) -> Option<BTreeMap<String, String>> {
    let from = common::in_repository(&format!("docs/acceptance/{fig}"))?;
    let (n, all) = all_seeds(&from, fig).unwrap();
    assert!(n >= 20, "{fig}: {n} committed seed sets");
    let over = all.into_iter();
    Some(
        over.map(|a| (a.check, a.verdict.status().to_string()))
            .collect(),
    )
}

/// Figure `$bin` at its published set-up with only the first `$runs` runs
/// of base seed 1 (`--fixed-runs $runs` and the options `$extra`): its
/// summary, once it is shown to have run that many on `$engine`.
macro_rules! first_runs {
    ($bin:literal, $extra:expr, $engine:literal, $runs:literal) => {{
        let mut args = vec!["--tier", "acceptance", "--fixed-runs", stringify!($runs)];
        args.extend_from_slice($extra);
        let s = run_figure!($bin, &args, "first-runs", &["summary.json"]);
        let seeds = s["seeds"].as_array().expect("seeds").len();
        assert_eq!((s["engine"].as_str(), seeds), (Some($engine), $runs));
        s
    }};
}

#[test]
fn ph94_fig2_first_runs_are_pinned() {
    // `fig2 --tier acceptance --fixed-runs 8`: the first 8 of the 128 runs
    // of seed set 1 (about 18 CPU-s)
    let s = first_runs!("fig2", &[], "fast", 8);
    assert_value(&s, "alpha", 1.3003720036938649, 0.04767478367976209);
    assert_value(&s, "v_peak", 0.3934326171875, 0.00885426484067535);
    if let Some(over) = committed_verdicts("fig2") {
        assert_eq!(over["alpha"], "not-reproduced");
        assert_eq!(over["v_peak"], "reproduced");
    }
}

#[test]
fn ph95_fig6_first_runs_are_pinned() {
    // `waves-fig6 --tier acceptance --fixed-runs 8` (about 16 CPU-s)
    let s = first_runs!("waves-fig6", &[], "fast", 8);
    assert_value(&s, "alpha", 1.3109107904569017, 0.014386300351212942);
    if let Some(over) = committed_verdicts("waves-fig6") {
        assert_eq!(over["alpha"], "not-reproduced");
    }
}

#[test]
fn bb90_fig3_first_runs_are_pinned() {
    // `hopper-fig3 --tier acceptance --cases beta1_bond,beta0 --fixed-runs 3`
    // (about 60 CPU-s): the rate ratio, the flat spectrum and the lag-1
    // autocorrelation, the three estimators of its claims
    let s = first_runs!(
        "hopper-fig3",
        &["--cases", "beta1_bond,beta0"],
        "reference",
        3
    );
    let pinned = [
        (
            "beta1_bond_white_spectrum",
            -0.02014911711291312,
            0.03615370474173753,
        ),
        (
            "beta1_bond_rate_like_orientation_off",
            0.9497557823948374,
            0.0056416362553666595,
        ),
        (
            "beta0_white_lag1",
            -0.18759344202114633,
            0.010547071989277214,
        ),
    ];
    for (name, value, error) in pinned {
        assert_value(&s, name, value, error);
    }
    // the whole run's verdicts over the 20 committed seed sets: all as seed
    // 1 gives them, the flat spectrum at beta = 0 reproduced
    if let Some(over) = committed_verdicts("hopper-fig3") {
        for name in ["beta1_bond_no_trend", "beta0_no_trend"] {
            assert_eq!(over[name], "reproduced", "{name}");
        }
        assert_eq!(over["beta1_bond_rate_like_orientation_off"], "reproduced");
        assert_eq!(over["beta1_bond_white_spectrum"], "reproduced");
        assert_eq!(over["beta0_white_spectrum"], "reproduced");
        for name in ["beta1_bond_white_lag1", "beta0_white_lag1"] {
            assert_eq!(over[name], "not-reproduced", "{name}");
        }
    }
}
