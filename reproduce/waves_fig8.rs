//! PH95 Fig. 8: alpha and the wave speed v against the dissipation p
//! (L = 220, W = 11, rho = 1, b = g = 0.5; spectrum of bin 0 sampled every
//! 10 steps). Checks: the published claims of Fig. 8 (alpha about
//! constant for every p > 0, v independent of p: each point p > 0 against
//! p = 0.5, shared with the reproduction matrix, `sweep::same_as_check`),
//! the p = 0 point against waves-fig7, alpha rising from p = 0 to 0.5
//! (`dependence::fig8_checks`).
//!
//! `cargo run --release --bin waves-fig8 -- --tier quick`

use clap::Parser;
use granular_automata::cli::SequentialArgs;
use granular_automata::drivers::dependence::fig8_checks;
use granular_automata::drivers::sweep::{
    plot_alpha_v, points_1d, Curve, PointResult, SweepFigure, FIG8_P,
};
use granular_automata::pipe::Params;
use serde_json::json;

#[derive(Parser)]
#[command(about = "PH95 Fig. 8: alpha and wave speed against the dissipation p")]
struct Args {
    #[command(flatten)]
    pipe: SequentialArgs,
    /// The dissipation values, separated by commas (default by tier; quick:
    /// 0,0.05,0.2,0.5,1). Must include 0 and 0.5, the points the checks
    /// compare; e.g. `--p 0,0.5` for the checks alone.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    p: Vec<f64>,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let Args {
        pipe: args,
        p: chosen,
    } = Args::parse();
    let by_tier: &[f64] = args.pipe.common.tier.pick(
        &[0.0, 0.05, 0.2, 0.5, 1.0][..],
        &[0.0, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0][..],
        &FIG8_P[..],
    );
    let mut ps = if chosen.is_empty() {
        by_tier.to_vec()
    } else {
        chosen
    };
    granular_automata::cli::reject_duplicates("--p", &ps)?;
    ps.sort_by(f64::total_cmp);
    if !ps.contains(&0.0) || !ps.contains(&0.5) {
        return Err(granular_automata::Error::new(
            granular_automata::ErrorKind::InvalidParameter,
            format!("--p {ps:?}: must include 0 and 0.5 (the points the checks compare)"),
        )
        .into());
    }
    // rho = 1, b = g = 0.5
    let base = Params::default();
    let points = points_1d("p", &ps, |p| Params { p, ..base });
    for pt in &points {
        // a bad --p fails before any run, naming the option
        pt.params
            .validate()
            .map_err(|e| granular_automata::Error::new(e.kind, format!("--p: {}", e.message)))?;
    }
    let tier = args.pipe.common.tier;
    let graded = |rs: &[PointResult]| fig8_checks(tier, &rs.iter().collect::<Vec<_>>());
    let fig = SweepFigure::run_graded("waves-fig8", "PH95 Fig. 8", &args, points, graded)?;
    let Some((fig, checks)) = fig else {
        return Ok(());
    };

    let all = fig.all();
    fig.write_csv("waves-fig8.csv", &["p"], &all)?;
    plot_alpha_v(
        &fig.out,
        "waves-fig8",
        &format!(
            "PH95 Fig. 8: L = 220, rho = 1, b = g = 0.5, {}, rules {}",
            fig.runs_per_point(),
            fig.rules
        ),
        "dissipation p",
        &[Curve {
            label: "b = g = 0.5, rho = 1",
            points: &all,
            xi: 0,
        }],
        &checks,
    )?;
    fig.finish(
        json!({"base": base, "p": ps, "setup": fig.setup_of(base)}),
        fig.metrics(),
        checks,
    )?;
    Ok(())
}
