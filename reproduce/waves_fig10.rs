//! PH95 Fig. 10: (a) alpha against the wall roughness b (p = g = 0.5,
//! rho = 1) and against gravity g (p = b = 0.5); (b) the wave speed v against
//! b from 0.25 to 1 for g = 0.5 and the smaller g = 0.2. L = 220, W = 11.
//! The published claims of PH95 III H (alpha constant for b > 0 and in g;
//! v falling with b, more at the smaller g; v changing with g) are graded
//! by `drivers::dependence::fig10_checks`, as in `pipe-matrix`.
//!
//! `cargo run --release --bin waves-fig10 -- --tier quick`

use granular_automata::cli::SequentialArgs;
use granular_automata::drivers::dependence::{fig10_checks, G_LOW};
use granular_automata::drivers::sweep::{
    sweep_chart, Curve, PointResult, Quantity, SweepFigure, SweepPoint,
};
use granular_automata::pipe::Params;
use serde_json::json;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = SequentialArgs::parse_about(
        "PH95 Fig. 10: alpha against b and g, wave speed against b for two gravities",
    );
    let tier = args.pipe.common.tier;
    let bs: &[f64] = tier.pick(
        &[0.0, 0.05, 0.25, 0.5, 1.0][..],
        &[0.0, 0.02, 0.05, 0.1, 0.25, 0.5, 0.75, 1.0][..],
        &[0.0, 0.02, 0.05, 0.1, 0.25, 0.4, 0.5, 0.6, 0.75, 0.9, 1.0][..],
    );
    let gs: &[f64] = tier.pick(
        &[0.2, 0.5, 1.0][..],
        &[0.1, 0.2, 0.3, 0.5, 0.7, 1.0][..],
        &[0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0][..],
    );
    let bv: Vec<f64> = bs.iter().copied().filter(|&b| b >= 0.25).collect();
    let base = Params::default(); // rho = 1, p = g = b = 0.5
    let point = |b: f64, g: f64| SweepPoint {
        label: format!("b{b}_g{g}"),
        x: vec![b, g],
        params: Params { b, g, ..base },
    };
    // panel (a) over b, panel (a) over g, panel (b) at G_LOW (g = 0.5 is the first)
    let panel_b: Vec<SweepPoint> = bs.iter().map(|&b| point(b, 0.5)).collect();
    let panel_g: Vec<SweepPoint> = gs.iter().map(|&g| point(0.5, g)).collect();
    let panel_low: Vec<SweepPoint> = bv.iter().map(|&b| point(b, G_LOW)).collect();
    let mut points: Vec<SweepPoint> = Vec::new();
    for p in panel_b.iter().chain(&panel_g).chain(&panel_low) {
        if !points.iter().any(|q| q.label == p.label) {
            points.push(p.clone());
        }
    }
    let graded = |rs: &[PointResult]| fig10_checks(tier, &rs.iter().collect::<Vec<_>>());
    let fig = SweepFigure::run_graded("waves-fig10", "PH95 Fig. 10", &args, points, graded)?;
    let Some((fig, checks)) = fig else {
        return Ok(());
    };
    let find = |p: &SweepPoint| fig.find(&p.label);
    let rb: Vec<&PointResult> = panel_b.iter().map(find).collect();
    let rg: Vec<&PointResult> = panel_g.iter().map(find).collect();
    let rv_hi: Vec<&PointResult> = rb
        .iter()
        .copied()
        .filter(|r| r.point.x[0] >= 0.25)
        .collect();
    let rv_lo: Vec<&PointResult> = panel_low.iter().map(find).collect();

    let xb = ["b", "g"];
    fig.write_csv("waves-fig10.csv", &xb, &fig.all())?;
    fig.write_csv("waves-fig10a_b.csv", &xb, &rb)?;
    fig.write_csv("waves-fig10a_g.csv", &xb, &rg)?;
    let mut vb = rv_hi.clone();
    vb.extend(rv_lo.iter().copied());
    fig.write_csv("waves-fig10b.csv", &xb, &vb)?;

    let title = format!(
        "PH95 Fig. 10: L = 220, rho = 1, p = 0.5, {}, rules {}",
        fig.runs_per_point(),
        fig.rules
    );
    let b_label = "wall roughness b (bounce-back probability)";
    let g_low = format!("g = {G_LOW}");
    for (png, what, xlabel, q, curves) in [
        (
            "waves-fig10a_b.png",
            "(a) alpha against b",
            b_label,
            Quantity::Alpha,
            vec![Curve {
                label: "g = 0.5",
                points: &rb,
                xi: 0,
            }],
        ),
        (
            "waves-fig10a_g.png",
            "(a) alpha against g",
            "gravity g (probability of a gravity move)",
            Quantity::Alpha,
            vec![Curve {
                label: "b = 0.5",
                points: &rg,
                xi: 1,
            }],
        ),
        (
            "waves-fig10b.png",
            "(b) v against b",
            b_label,
            Quantity::V,
            vec![
                Curve {
                    label: "g = 0.5",
                    points: &rv_hi,
                    xi: 0,
                },
                Curve {
                    label: &g_low,
                    points: &rv_lo,
                    xi: 0,
                },
            ],
        ),
    ] {
        sweep_chart(
            &fig.out.path(png),
            &format!("{title}: {what}"),
            xlabel,
            q,
            &curves,
            &checks,
            None,
        )?;
    }

    fig.finish(
        json!({"base": base, "b": bs, "g": gs, "b_for_v": bv, "g_low": G_LOW, "setup": fig.setup_of(base)}),
        fig.metrics(),
        checks,
    )?;
    Ok(())
}
