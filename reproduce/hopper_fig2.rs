//! BB90 Fig. 2: the hopper filling (b) and emptying with beta = 0 (a) and
//! beta = 1 (c-f), for both readings of "aligned" (MODEL.md B4, B6).
//!
//! `cargo run --release --bin hopper-fig2 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::grading::{Claim, Estimate, Kind};
use granular_automata::cli::Common;
use granular_automata::hopper::experiment::{core_rows, run_cases, Case, Plan, FIG2_MEASURES};
use granular_automata::hopper::picture::{draw_snapshots, Panel};
use granular_automata::hopper::{Hopper, HopperParams};
use granular_automata::plot::{line_chart, points, Line, PALETTE};
use granular_automata::run::{derive_seed, mean_sem_at, mean_sem_by, stat_metrics, Check, Figure};
use std::collections::BTreeMap;

#[derive(Parser, Debug)]
#[command(about = "BB90 Fig. 2: hopper filling and emptying, beta = 0 vs beta = 1")]
struct Args {
    /// quick: a small hopper; standard and paper: 174 x 129. `--runs`: runs
    /// per case averaged in the metrics (snapshots show run 0).
    #[command(flatten)]
    common: Common,
}

/// The three cases.
const CASES: [Case; 3] = [Case::BETA0, Case::BETA1_ALONG, Case::BETA1_SAME];

fn main() -> granular_automata::Result<()> {
    let args = Args::parse();
    let c = &args.common;
    c.reject_shard("hopper-fig2")?;
    let tier = c.tier;
    let runs = c.runs_or(3, 4, 8);
    let base = tier.pick(
        HopperParams::quick(),
        HopperParams::default(),
        HopperParams::default(),
    );
    let fig = Figure::start("hopper-fig2", "BB90 Fig. 2", tier, base.rules());
    let snaps: Vec<u64> = tier.pick(
        vec![100, 300, 600, 900],
        vec![250, 1000, 2000, 3000],
        vec![250, 1000, 2000, 3000],
    );
    let mut plan = Plan::new(tier.pick(5_000, 20_000, 20_000), snaps.clone());
    // the quick hopper is short: at 85% the rain heap touches the lid of the
    // lattice, whose rays read as dense and hold an arch; fill to 70% instead
    plan.fill_fraction = tier.pick(0.7, 0.85, 0.85);
    let out = fig.output(&c.out)?;
    let seeds: Vec<u64> = (0..runs as u64).map(|r| derive_seed(c.seed, r)).collect();
    let recs = run_cases(base, &CASES, &seeds, &plan, c.thread_count())?;
    let probe = Hopper::new(base, 0)?;
    let geom = probe.geometry().clone();
    let rows = core_rows(&probe);

    // metrics: per case, mean and standard error over runs
    let mut m = BTreeMap::new();
    for (case, rs) in CASES.iter().zip(&recs) {
        for (name, f) in FIG2_MEASURES {
            let stat = mean_sem_by(rs, |r| f(r, &geom, &rows));
            m.insert(format!("{}_{name}", case.key), stat);
        }
    }
    let g = |k: &str| m[k];
    let metrics = stat_metrics(m.iter().map(|(k, v)| (k, *v)));
    let site_updates = recs
        .iter()
        .map(|rs| rs.iter().map(|r| r.site_updates).sum::<f64>())
        .sum();

    // pictures: one per reading of "aligned", run 0
    let scale = tier.pick(5.0, 2.6, 2.6);
    for (case, rs) in CASES.iter().zip(&recs).skip(1) {
        let name = case.aligned.name();
        let panels = Panel::fig2(&recs[0][0], &rs[0], &snaps);
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
    let (mut lines, mut rows_csv, mut glines, mut g_csv) = (vec![], vec![], vec![], vec![]);
    for (c, (case, rs)) in CASES.iter().zip(&recs).enumerate() {
        let cap = case.caption;
        for (k, &y) in rows.iter().enumerate() {
            let p = rs[0].activity.profile(&geom, y);
            let centre = geom.centre_column as f64;
            let pts = p.iter().map(|&(x, a)| (x as f64 - centre, a)).collect();
            lines.push(Line::new(
                &format!("{cap}, row {y}"),
                pts,
                PALETTE[2 * c + k],
            ));
            for &(x, a) in &p {
                let occupancy = rs[0].activity.occupancy(x, y);
                rows_csv.push(vec![c as f64, y as f64, x as f64, a, occupancy]);
            }
        }
        let gh: Vec<&[f64]> = rs.iter().map(|r| &r.g_half[..]).collect();
        let r: Vec<f64> = (1..=plan.rmax).map(|d| d as f64).collect();
        let mean = mean_sem_at(&gh, plan.rmax).0;
        glines.push(Line::new(cap, points(&r, &mean), PALETTE[c]).markers());
        g_csv.extend(r.iter().zip(&mean).map(|(&d, &v)| vec![c as f64, d, v]));
    }
    let header = ["case", "row", "column", "activity", "occupancy"];
    out.write_csv("activity_profiles.csv", &header, &rows_csv)?;
    line_chart(
        &out.path("hopper-fig2-activity.png"),
        "BB90 Fig. 2: time-averaged activity across the hopper (run 0)",
        "column - outlet column",
        "fraction of iterations with a moving grain",
        &lines,
        false,
    )?;
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
    let n = recs[0].len();
    let e = |k: &str| Estimate::from(g(k), n);
    let src = "BB90 Fig. 2 (qualitative)";
    let above = |threshold| Claim::Above { threshold };
    let empties = |c: usize, name: &str, what: &str| {
        Check::test(
            name,
            Kind::Published,
            "BB90 Fig. 2 (the hopper flows until empty)",
            g(&format!("{}_remaining_grains", CASES[c].key)).0,
            n,
            emptied[c],
            &format!("{what}: every run empties (statistic: grains left, mean over runs)"),
        )
    };
    let checks = vec![
        empties(0, "beta0_empties", "beta = 0"),
        empties(1, "beta1_along_empties", "beta = 1, literal reading"),
        empties(2, "beta1_same_empties", "beta = 1, same-orientation reading"),
        Check::test("beta0_central_core", Kind::Published, "BB90 Fig. 2a (a central flowing core)", ratio, n, ratio >= 4.0,
            "(activity at centre + 1e-3)/(activity next to the walls + 1e-3) >= 4 at the lower core row, of the means over runs (as tests/hopper_acceptance.rs)"),
        Check::published("beta0_core_lowered_density", "BB90 Fig. 2a (density lowered inside the core)",
            e("beta0_occupancy_core").minus(e("beta0_occupancy_sides")), Claim::Below { threshold: 0.0 },
            "occupancy core - sides < 0"),
        Check::published("beta0_structureless", src, e("beta0_order_half_empty"),
            Claim::Within { target: 1.0 / 3.0, margin: 0.03 },
            "beta = 0: order parameter within 0.03 of 1/3 (random)"),
        Check::published("beta1_order_forms_while_filling", "BB90 Fig. 2b", e("beta1_along_order_filled"), above(0.45),
            "order parameter > 0.45 after filling (literal reading)"),
        Check::published("beta1_same_order", "BB90 Fig. 2c-f", e("beta1_same_order_half_empty"), above(0.45),
            "order parameter > 0.45 (same-orientation reading)"),
        Check::published("beta1_along_vertical_core", "BB90 Fig. 2c-f", e("beta1_along_vertical_fraction_moving"), above(0.45),
            "moving grains mostly vertical (> 0.45; 1/3 random), literal reading"),
        Check::published("beta1_same_vertical_core", "BB90 Fig. 2c-f", e("beta1_same_vertical_fraction_moving"), above(0.45),
            "moving grains mostly vertical (> 0.45; 1/3 random), same-orientation reading"),
        Check::published("beta1_along_container_scale_order", "BB90 Fig. 2c-f", e("beta1_along_corr_length_half_empty"), above(8.0),
            "correlation length > 8 steps (container scale), literal reading"),
        Check::published("beta1_same_container_scale_order", "BB90 Fig. 2c-f", e("beta1_same_corr_length_half_empty"), above(8.0),
            "correlation length > 8 steps (container scale), same-orientation reading"),
    ];
    let params = serde_json::json!({
        "hopper": base,
        "cases": CASES.iter().map(Case::json).collect::<Vec<_>>(),
        "runs": runs,
        "fill_fraction": plan.fill_fraction,
        "snapshot_iterations": snaps,
        "activity_window": "while more than 50% of the grains remain",
        "core_rows": rows,
        "inside_sites": geom.inside,
    });
    fig.finish(&out, seeds, params, site_updates, metrics, checks)
}
