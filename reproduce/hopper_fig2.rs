//! BB90 Fig. 2: the hopper filling (b) and emptying with beta = 0 (a) and
//! beta = 1 (c-f), for both readings of "aligned" (MODEL.md B4, B6).
//!
//! `cargo run --release --bin hopper-fig2 -- --tier quick`

use clap::Parser;
use granular_automata::hopper::experiment::{core_rows, run, Plan, Record};
use granular_automata::hopper::observables::correlation_length;
use granular_automata::hopper::picture::{draw_snapshots, Panel};
use granular_automata::hopper::{Aligned, Hopper, HopperParams};
use granular_automata::plot::{line_chart, Line, PALETTE};
use granular_automata::run::{
    derive_seed, ensemble, mean_sem, progress, Check, Output, Summary, Tier,
};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Parser, Debug)]
#[command(about = "BB90 Fig. 2: hopper filling and emptying, beta = 0 vs beta = 1")]
struct Args {
    /// quick (seconds, small hopper), standard or paper (174 x 129 hopper).
    #[arg(long, value_enum, default_value = "quick")]
    tier: Tier,
    /// Base seed; run r uses derive_seed(seed, r).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Runs per case averaged in the metrics (snapshots show run 0).
    #[arg(long)]
    runs: Option<usize>,
    /// Output folder.
    #[arg(long, default_value = "results")]
    out: PathBuf,
}

/// The three cases: (key, caption, beta, aligned).
const CASES: [(&str, &str, f64, Aligned); 3] = [
    ("beta0", "beta = 0", 0.0, Aligned::AlongVelocity),
    (
        "beta1_along",
        "beta = 1, aligned = along-velocity",
        1.0,
        Aligned::AlongVelocity,
    ),
    (
        "beta1_same",
        "beta = 1, aligned = same-orientation",
        1.0,
        Aligned::SameOrientation,
    ),
];

fn main() -> granular_automata::Result<()> {
    let args = Args::parse();
    let start = Instant::now();
    let tier = args.tier;
    let runs = args.runs.unwrap_or(tier.pick(2, 4, 8)).max(1);
    let base = tier.pick(
        HopperParams::quick(),
        HopperParams::default(),
        HopperParams::default(),
    );
    let snaps: Vec<u64> = tier.pick(
        vec![100, 300, 600, 900],
        vec![250, 1000, 2000, 3000],
        vec![250, 1000, 2000, 3000],
    );
    let mut plan = Plan::new(tier.pick(5_000, 20_000, 20_000), snaps.clone());
    // the quick hopper is short: at 85% the rain heap touches the lid of the
    // lattice, whose rays read as dense and hold an arch; fill to 70% instead
    plan.fill_fraction = tier.pick(0.7, 0.85, 0.85);
    let out = Output::new(&args.out, "hopper-fig2")?;
    let seeds: Vec<u64> = (0..runs as u64)
        .map(|r| derive_seed(args.seed, r))
        .collect();

    let pb = progress((CASES.len() * runs) as u64, "hopper runs");
    let jobs: Vec<(usize, usize)> = (0..CASES.len())
        .flat_map(|c| (0..runs).map(move |r| (c, r)))
        .collect();
    let results = ensemble(jobs.len(), |j| {
        let (c, r) = jobs[j];
        let mut p = base;
        p.energy.beta = CASES[c].2;
        p.energy.aligned = CASES[c].3;
        let rec = run(p, seeds[r], &plan);
        pb.inc(1);
        rec
    });
    pb.finish();
    let mut recs: Vec<Vec<Record>> = (0..CASES.len()).map(|_| Vec::new()).collect();
    for (j, rec) in results.into_iter().enumerate() {
        recs[jobs[j].0].push(rec?);
    }
    let probe = Hopper::new(base, 0)?;
    let geom = probe.geometry().clone();
    let rows = core_rows(&probe);

    // metrics
    let mut metrics = BTreeMap::new();
    let mut stat = |name: String, xs: Vec<f64>| {
        let (m, e) = mean_sem(&xs);
        metrics.insert(name.clone(), m);
        metrics.insert(format!("{name}_err"), e);
        (m, e)
    };
    let mut m = BTreeMap::new();
    let mut site_updates = 0.0;
    for (c, (key, ..)) in CASES.iter().enumerate() {
        let rs = &recs[c];
        site_updates += rs.iter().map(|r| r.site_updates).sum::<f64>();
        let per = |f: &dyn Fn(&Record) -> f64| rs.iter().map(f).collect::<Vec<f64>>();
        let mut put =
            |n: &str, v: Vec<f64>| m.insert(format!("{key}_{n}"), stat(format!("{key}_{n}"), v));
        put(
            "core_width_low",
            per(&|r| r.activity.core_width(&geom, rows[0])),
        );
        put(
            "core_width_high",
            per(&|r| r.activity.core_width(&geom, rows[1])),
        );
        put(
            "occupancy_core",
            per(&|r| r.activity.core_and_side_occupancy(&geom, &rows).0),
        );
        put(
            "occupancy_sides",
            per(&|r| r.activity.core_and_side_occupancy(&geom, &rows).1),
        );
        put(
            "activity_centre",
            per(&|r| r.activity.centre_and_wall_activity(&geom, rows[0], 2).0),
        );
        put(
            "activity_wall",
            per(&|r| r.activity.centre_and_wall_activity(&geom, rows[0], 2).1),
        );
        put("order_filled", per(&|r| r.g_filled[0]));
        put("order_half_empty", per(&|r| r.g_half[0]));
        for d in [2usize, 4, 8, 16] {
            put(&format!("g{d}_half_empty"), per(&|r| r.g_half[d - 1]));
        }
        put(
            "corr_length_filled",
            per(&|r| correlation_length(&r.g_filled)),
        );
        put(
            "corr_length_half_empty",
            per(&|r| correlation_length(&r.g_half)),
        );
        put(
            "vertical_fraction_moving",
            per(&|r| r.vertical_fraction_of_moving()),
        );
        put("empty_iterations", per(&|r| r.empty_iterations as f64));
        put("remaining_grains", per(&|r| r.remaining as f64));
        put("initial_grains", per(&|r| r.initial as f64));
        put("fill_iterations", per(&|r| r.fill_iterations as f64));
        put(
            "mean_rate",
            per(&|r| r.removed as f64 / r.empty_iterations.max(1) as f64),
        );
    }
    let g = |k: &str| m[k];

    // pictures: one per reading of "aligned", run 0
    let snap_of = |rec: &Record, t: u64| {
        rec.snapshots
            .iter()
            .find(|(s, _)| *s == t)
            .map(|(_, v)| v.clone())
            .unwrap_or_else(|| vec![0; geom.kind.len()])
    };
    let scale = tier.pick(5.0, 2.6, 2.6);
    for c in [1usize, 2] {
        let name = CASES[c].3.name();
        let r0 = &recs[c][0];
        let mut panels = vec![
            Panel {
                caption: format!("(a) beta = 0, iteration {}", snaps[1]),
                sites: snap_of(&recs[0][0], snaps[1]),
            },
            Panel {
                caption: "(b) filling, beta = 1".to_string(),
                sites: r0.mid_fill.clone(),
            },
        ];
        for (k, &t) in snaps.iter().enumerate() {
            panels.push(Panel {
                caption: format!("({}) beta = 1, iteration {t}", ["c", "d", "e", "f"][k]),
                sites: snap_of(r0, t),
            });
        }
        draw_snapshots(
            &out.path(&format!("hopper-fig2-{name}.png")),
            &format!(
                "BB90 Fig. 2: hopper, aligned = {name} (iterations after opening; tier {})",
                tier.name()
            ),
            &geom,
            &panels,
            3,
            scale,
        )?;
    }
    // activity profiles and g(r)
    let mut lines = Vec::new();
    let mut rows_csv = Vec::new();
    for (c, (_, cap, ..)) in CASES.iter().enumerate() {
        for (k, &y) in rows.iter().enumerate() {
            let p = recs[c][0].activity.profile(&geom, y);
            lines.push(Line::new(
                &format!("{cap}, row {y}"),
                p.iter()
                    .map(|&(x, a)| (x as f64 - geom.centre_column as f64, a))
                    .collect(),
                PALETTE[2 * c + k],
            ));
            for &(x, a) in &p {
                rows_csv.push(vec![
                    c as f64,
                    y as f64,
                    x as f64,
                    a,
                    recs[c][0].activity.occupancy(x, y),
                ]);
            }
        }
    }
    out.write_csv(
        "activity_profiles.csv",
        &["case", "row", "column", "activity", "occupancy"],
        &rows_csv,
    )?;
    line_chart(
        &out.path("hopper-fig2-activity.png"),
        "BB90 Fig. 2: time-averaged activity across the hopper (run 0)",
        "column - outlet column",
        "fraction of iterations with a moving grain",
        &lines,
        false,
    )?;
    let mut glines = Vec::new();
    let mut g_csv = Vec::new();
    for (c, (_, cap, ..)) in CASES.iter().enumerate() {
        let gh: Vec<Vec<f64>> = recs[c].iter().map(|r| r.g_half.clone()).collect();
        let mean: Vec<f64> = (0..plan.rmax)
            .map(|d| mean_sem(&gh.iter().map(|v| v[d]).collect::<Vec<_>>()).0)
            .collect();
        glines.push(
            Line::new(
                cap,
                mean.iter()
                    .enumerate()
                    .map(|(d, &v)| ((d + 1) as f64, v))
                    .collect(),
                PALETTE[c],
            )
            .markers(),
        );
        for (d, &v) in mean.iter().enumerate() {
            g_csv.push(vec![c as f64, (d + 1) as f64, v]);
        }
    }
    glines.push(Line::new(
        "random: 1/3",
        vec![(1.0, 1.0 / 3.0), (plan.rmax as f64, 1.0 / 3.0)],
        PALETTE[5],
    ));
    out.write_csv("g_of_r.csv", &["case", "r", "g_half_empty"], &g_csv)?;
    line_chart(
        &out.path("hopper-fig2-gr.png"),
        "BB90 Fig. 2: orientational correlation g(r), half emptied",
        "distance r (lattice steps along an axis)",
        "fraction of pairs with equal orientation",
        &glines,
        false,
    )?;

    // checks (no published numbers: qualitative claims of BB90 Fig. 2)
    let emptied: Vec<bool> = recs.iter().map(|rs| rs.iter().all(|r| r.emptied)).collect();
    let ratio = (g("beta0_activity_centre").0 + 1e-3) / (g("beta0_activity_wall").0 + 1e-3);
    let checks = vec![
        Check::claim("beta0_empties", g("beta0_remaining_grains").0, 0.0, emptied[0], "BB90 Fig. 2a: beta = 0 flows until empty, no jam"),
        Check::claim("beta1_along_empties", g("beta1_along_remaining_grains").0, 0.0, emptied[1], "beta = 1, literal reading: empties"),
        Check::claim("beta1_same_empties", g("beta1_same_remaining_grains").0, 0.0, emptied[2], "beta = 1, same-orientation reading: empties"),
        Check::claim("beta0_central_core", ratio, 0.0, ratio >= 4.0, "BB90 Fig. 2a: (activity at centre + 1e-3)/(activity next to the walls + 1e-3) >= 4 at the lower core row (as tests/hopper_acceptance.rs)"),
        Check::claim("beta0_core_lowered_density", g("beta0_occupancy_core").0 - g("beta0_occupancy_sides").0, g("beta0_occupancy_core").1, g("beta0_occupancy_core").0 < g("beta0_occupancy_sides").0, "BB90 Fig. 2a: density lowered inside the core (occupancy core - sides < 0)"),
        Check::claim("beta0_structureless", g("beta0_order_half_empty").0, g("beta0_order_half_empty").1, (g("beta0_order_half_empty").0 - 1.0 / 3.0).abs() < 0.03, "BB90 Fig. 2a: order parameter within 0.03 of 1/3 (random)"),
        Check::claim("beta1_order_forms_while_filling", g("beta1_along_order_filled").0, g("beta1_along_order_filled").1, g("beta1_along_order_filled").0 > 0.45, "BB90 Fig. 2b: order parameter > 0.45 after filling (literal reading)"),
        Check::claim("beta1_same_order", g("beta1_same_order_half_empty").0, g("beta1_same_order_half_empty").1, g("beta1_same_order_half_empty").0 > 0.45, "BB90 Fig. 2c-f: order parameter > 0.45 (same-orientation reading)"),
        Check::claim("beta1_along_vertical_core", g("beta1_along_vertical_fraction_moving").0, g("beta1_along_vertical_fraction_moving").1, g("beta1_along_vertical_fraction_moving").0 > 0.45, "BB90 Fig. 2c-f: moving grains mostly vertical (> 0.45; 1/3 random), literal reading"),
        Check::claim("beta1_same_vertical_core", g("beta1_same_vertical_fraction_moving").0, g("beta1_same_vertical_fraction_moving").1, g("beta1_same_vertical_fraction_moving").0 > 0.45, "BB90 Fig. 2c-f: moving grains mostly vertical (> 0.45; 1/3 random), same-orientation reading"),
        Check::claim("beta1_along_container_scale_order", g("beta1_along_corr_length_half_empty").0, g("beta1_along_corr_length_half_empty").1, g("beta1_along_corr_length_half_empty").0 >= 8.0, "BB90 Fig. 2c-f: correlation length >= 8 steps (container scale), literal reading"),
        Check::claim("beta1_same_container_scale_order", g("beta1_same_corr_length_half_empty").0, g("beta1_same_corr_length_half_empty").1, g("beta1_same_corr_length_half_empty").0 >= 8.0, "BB90 Fig. 2c-f: correlation length >= 8 steps (container scale), same-orientation reading"),
    ];
    let params = serde_json::json!({
        "hopper": base,
        "cases": CASES.iter().map(|(k, _, b, a)| serde_json::json!({"key": k, "beta": b, "aligned": a.name()})).collect::<Vec<_>>(),
        "runs": runs,
        "fill_fraction": plan.fill_fraction,
        "snapshot_iterations": snaps,
        "activity_window": "while more than 50% of the grains remain",
        "core_rows": rows,
        "inside_sites": geom.inside,
    });
    let summary = Summary {
        figure: "hopper-fig2".into(),
        paper: "BB90 Fig. 2".into(),
        tier,
        seeds,
        params,
        rules: base.rules(),
        wall_seconds: start.elapsed().as_secs_f64(),
        site_updates,
        metrics,
        checks,
    };
    out.finish(&summary)?;
    Ok(())
}
