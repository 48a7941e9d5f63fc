//! PH95 Fig. 9: alpha and the wave speed v against the mean density rho
//! (L = 220 unless `--length`, W = 11, p = b = g = 0.5). Above some rho the model's own
//! validity ends (rest particles outnumber sites, MODEL.md A4): such runs are
//! counted per point and the limit is reported, not a crash. PH95 III G's
//! claims: `drivers::dependence::fig9_claims`, as in `pipe-matrix`.
//!
//! `cargo run --release --bin waves-fig9 -- --tier quick`

use clap::Parser;
use granular_automata::cli::SequentialArgs;
use granular_automata::drivers::dependence::{checks as claim_checks, fig9_claims, fig9_validity};
use granular_automata::drivers::sweep::{plot_alpha_v, points_1d, Curve, PointResult, SweepFigure};
use granular_automata::pipe::Params;
use granular_automata::plot::{errorbar_chart_at, ErrSeries, PALETTE};
use plotters::chart::SeriesLabelPosition;
use serde_json::json;

#[derive(Parser)]
#[command(
    about = "PH95 Fig. 9: alpha and wave speed against the density rho, with the model's validity limit"
)]
struct Args {
    #[command(flatten)]
    seq: SequentialArgs,
    /// The densities, separated by commas, e.g. `--rho 1.8,1.9,2.0,2.1` to
    /// locate the validity limit (default by tier; quick:
    /// 0.2,0.6,1,1.4,2,3). Sorted; the largest is the one that must reach
    /// the limit.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    rho: Vec<f64>,
    /// The pipe length L, a multiple of the bin (10). PH95 gives none for
    /// Figs. 8-10; the default 220 is that of Figs. 6-7 (MODEL.md). The
    /// peak is searched in PH94's fit range j <= 1000 (m = 16384), i.e. for
    /// v <= L / 328 rows per step: below L = 220 a wave of v = 0.4 lies
    /// outside it and v reads a noise bin.
    #[arg(long, default_value_t = 220, allow_negative_numbers = true, value_parser = |s: &str| granular_automata::cli::parse_count("--length", s, 0, usize::MAX))]
    length: usize,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let mut rhos: Vec<f64> = if args.rho.is_empty() {
        args.seq
            .pipe
            .common
            .tier
            .pick(
                &[0.2, 0.6, 1.0, 1.4, 2.0, 3.0][..],
                &[0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.5, 3.0][..],
                &[
                    0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0, 2.2, 2.5, 3.0,
                ][..],
            )
            .to_vec()
    } else {
        args.rho.clone()
    };
    granular_automata::cli::reject_duplicates("--rho", &rhos)?;
    rhos.sort_by(f64::total_cmp);
    // p = b = g = 0.5
    let base = Params {
        length: args.length,
        ..Params::default()
    };
    let points = points_1d("rho", &rhos, |rho| Params { rho, ..base });
    // a bad --length or --rho fails before any run, naming the option
    let named = |option: &str, p: &Params| {
        p.validate()
            .and_then(|()| granular_automata::cli::check_populated(p))
            .map_err(|e| granular_automata::Error::new(e.kind, format!("{option}: {}", e.message)))
    };
    named("--length", &base)?;
    for p in &points {
        named("--rho", &p.params)?;
    }
    let graded = |rs: &[PointResult]| {
        let all: Vec<&PointResult> = rs.iter().collect();
        let mut checks = fig9_validity(rs, &mut Default::default());
        checks.extend(claim_checks(fig9_claims(&all)));
        checks
    };
    let fig = SweepFigure::run_graded("waves-fig9", "PH95 Fig. 9", &args.seq, points, graded)?;
    let Some((fig, checks)) = fig else {
        return Ok(());
    };
    let res = &fig.results;

    let all = fig.all();
    fig.write_csv("waves-fig9.csv", &["rho"], &all)?;
    let title = format!(
        "PH95 Fig. 9: L = {}, p = b = g = 0.5, {}, rules {}",
        base.length,
        fig.runs_per_point(),
        fig.rules
    );
    let xlabel = "mean density rho (particles per site)";
    let mut metrics = fig.metrics();
    fig9_validity(res, &mut metrics);
    plot_alpha_v(
        &fig.out,
        "waves-fig9",
        &title,
        xlabel,
        &[Curve {
            label: "valid runs only",
            points: &all,
            xi: 0,
        }],
        &checks,
    )?;
    let frac: Vec<(f64, f64, f64)> = res
        .iter()
        .map(|r| {
            (
                r.point.x[0],
                r.invalid as f64 / (r.valid + r.invalid) as f64,
                0.0,
            )
        })
        .collect();
    errorbar_chart_at(
        &fig.out.path("waves-fig9_validity.png"),
        &format!("{title}: model validity (MODEL.md A4)"),
        xlabel,
        "fraction of runs stopped: rest particles exceed sites",
        &[ErrSeries::new("invalid runs / runs", frac, PALETTE[1])],
        SeriesLabelPosition::UpperLeft,
    )?;

    fig.finish(
        json!({"base": base, "rho": rhos, "setup": fig.setup_of(base)}),
        metrics,
        checks,
    )?;
    Ok(())
}
