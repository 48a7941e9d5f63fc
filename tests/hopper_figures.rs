//! Smoke tests of the two hopper figure binaries at the quick tier: the
//! output contract (PNGs, CSVs, summary.json with every field) and the
//! metrics that end up on the plots. The binaries are deterministic (base
//! seed 1), so the asserted ranges are wide margins around one known run,
//! not statistical tolerances; the statistical checks are in
//! `hopper_acceptance.rs`.

use std::path::PathBuf;
use std::process::{Command, Stdio};

/// Base seed passed to the binaries.
const SEED: &str = "1";

fn run(bin: &str, exe: &str) -> serde_json::Value {
    let out: PathBuf =
        std::env::temp_dir().join(format!("hopper-figures-{}-{bin}", std::process::id()));
    let status = Command::new(exe)
        .args(["--tier", "quick", "--seed", SEED, "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .expect("binary runs");
    assert!(status.success(), "{bin} failed");
    let dir = out.join(bin);
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json written");
    let v: serde_json::Value = serde_json::from_str(&text).expect("valid json");
    for key in [
        "figure",
        "paper",
        "tier",
        "seeds",
        "params",
        "rules",
        "wall_seconds",
        "site_updates",
        "metrics",
        "checks",
    ] {
        assert!(v.get(key).is_some(), "{bin}: summary.json lacks {key}");
    }
    let pngs = std::fs::read_dir(&dir)
        .unwrap()
        .filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "png")
        })
        .count();
    assert!(pngs >= 3, "{bin}: {pngs} PNGs");
    std::fs::remove_dir_all(&out).ok();
    v
}

fn metric(v: &serde_json::Value, name: &str) -> f64 {
    v["metrics"][name]
        .as_f64()
        .unwrap_or_else(|| panic!("metric {name} missing"))
}

/// The cases of both hopper figures' default `--cases`.
const CASES: [&str; 4] = ["beta0", "beta1_bond", "beta1_along", "beta1_same"];

/// Every case of [`CASES`] has each metric of `names` (`<case>_<name>`).
fn has_metrics(v: &serde_json::Value, names: &[&str]) {
    for case in CASES {
        for m in names {
            metric(v, &format!("{case}_{m}"));
        }
    }
}

#[test]
fn hopper_fig2_writes_its_figure_and_metrics() {
    let v = run("hopper-fig2", env!("CARGO_BIN_EXE_hopper-fig2"));
    assert_eq!(v["paper"], "BB90 Fig. 2");
    has_metrics(
        &v,
        &[
            "core_width_low",
            "core_width_high",
            "occupancy_core",
            "occupancy_sides",
            "order_half_empty",
            "g8_half_empty",
        ],
    );
    for case in CASES {
        assert_eq!(
            metric(&v, &format!("{case}_remaining_grains")),
            0.0,
            "{case} empties"
        );
    }
    assert!((metric(&v, "beta0_order_half_empty") - 1.0 / 3.0).abs() < 0.03);
    assert_eq!(
        first_beta1_case(&v),
        "beta1_bond",
        "the default reading first"
    );
    assert!(metric(&v, "beta1_bond_order_half_empty") > 0.5);
    assert!(metric(&v, "beta1_same_order_half_empty") > 0.5);
    assert!(metric(&v, "beta1_along_order_half_empty") > 0.5);
    assert!(metric(&v, "beta0_occupancy_core") < metric(&v, "beta0_occupancy_sides"));
}

/// Key of the first beta = 1 case of the default `--cases`, and check that
/// it is the library default reading of "aligned" (along the bond).
fn first_beta1_case(v: &serde_json::Value) -> String {
    let cases = v["params"]["cases"].as_array().expect("params.cases");
    let c = cases
        .iter()
        .find(|c| c["beta"].as_f64() == Some(1.0))
        .expect("a beta = 1 case");
    assert_eq!(c["aligned"], "along-bond");
    assert_eq!(v["params"]["hopper"]["energy"]["aligned"], "along-bond");
    c["key"].as_str().unwrap().to_string()
}

#[test]
fn hopper_fig3_writes_its_figure_and_metrics() {
    let v = run("hopper-fig3", env!("CARGO_BIN_EXE_hopper-fig3"));
    assert_eq!(v["paper"], "BB90 Fig. 3");
    assert_eq!(
        first_beta1_case(&v),
        "beta1_bond",
        "the default reading first"
    );
    has_metrics(
        &v,
        &[
            "mean_rate",
            "sd_rate",
            "rate_first_half",
            "rate_second_half",
            "spectral_slope",
            "spectral_slope_err",
        ],
    );
    for case in CASES {
        let rate = metric(&v, &format!("{case}_mean_rate"));
        assert!(rate > 1.0 && rate < 3.0, "{case}: rate {rate}");
    }
}
