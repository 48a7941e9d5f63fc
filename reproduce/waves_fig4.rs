//! PH95 Fig. 4: the profile of the strongest wave. For each run, 2048
//! density fields in the steady state are shifted along the pipe to overlap
//! maximally, hierarchically (pairs, then pairs of pairs, ...; [PH95 B],
//! `pipe::overlap::align_hierarchical`) and averaged; the run profiles are
//! aligned the same way and averaged over runs. Several lengths L, W = 11,
//! rho = 1, p = 0.1, g = b = 0.5.
//!
//! Choices (not in the paper): bins of 4 rows (the lengths are powers of two;
//! finer bins resolve the front); a warm-up before the first field (by
//! tier); fields every T0 = 40 steps. Metrics per run, on the run's profile
//! centred on its maximum: the amplitude (max - mean) / mean; the half-widths
//! at half the excess maximum on the front side (downstream, towards lower y:
//! the waves travel down, waves-fig2/fig5) and on the back side; the width
//! (their sum, rows); the asymmetry (back - front) / (back + front), > 0 for
//! a steep front. Alignment makes even pure noise look like a bump, so each
//! run also aligns as many white-noise fields with the run's own per-bin
//! variance (over its fields; generator seeded from the run's seed with a
//! fixed offset): the excess amplitude over that null is the wave's
//! (`pipe::overlap::profile_run`).
//!
//! `cargo run --release --bin waves-fig4 -- --tier quick`

use clap::Parser;
use granular_automata::analysis::grading::{Claim, Estimate};
use granular_automata::cli::WaveOptions;
use granular_automata::pipe::observables::random_start_bin_variance;
use granular_automata::pipe::overlap::{
    ensemble_profile, profile_run, steep_front_check, width_grows_check, ProfileRun, FIELDS_EVERY,
    FIG4_BIN, PROFILE_MEASURES,
};
use granular_automata::pipe::record::Steady;
use granular_automata::pipe::Params;
use granular_automata::plot::{line_chart, Line, PALETTE};
use granular_automata::run::{stat_metrics, stats_by, Check};
use serde_json::json;

#[derive(Parser)]
#[command(about = "PH95 Fig. 4: profile of the strongest wave (maximal-overlap average)")]
struct Args {
    #[command(flatten)]
    wave: WaveOptions,
    /// Pipe lengths (multiples of 4), comma separated.
    #[arg(long, value_delimiter = ',', default_values_t = vec![128usize, 256, 512, 1024], allow_hyphen_values = true)]
    lengths: Vec<usize>,
}

const T0: u64 = FIELDS_EVERY;
/// A wave's amplitude must exceed NULL_FACTOR times the white-noise
/// alignment bias (excess over the bias > the bias itself).
const NULL_FACTOR: f64 = 2.0;
const BIN: usize = FIG4_BIN;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let (fig, rules, c) = args.wave.start("waves-fig4", "PH95 Fig. 4")?;
    let engine = args.wave.rules.engine(args.wave.common.tier)?;
    let runs = c.runs_or(4, 16, 64);
    granular_automata::cli::reject_duplicates("--lengths", &args.lengths)?;
    for &length in &args.lengths {
        args.wave.pipe(length, BIN)?; // a bad length fails before any run
    }
    let steady = Steady::ph95(c.tier, c.tier.pick(512, 2048, 2048), T0);
    let (fields, warmup) = (steady.fields, steady.warmup);
    let mut per_l: Vec<(Params, Option<Vec<ProfileRun>>)> = Vec::new();
    let mut seeds = Vec::new();
    for &length in &args.lengths {
        let params = args.wave.pipe(length, BIN)?;
        // "analysis": bump when the per-run computation changes, so stale run
        // files are not reused (ensemble resume)
        let key = json!({"analysis": 2, "params": params, "rules": rules.to_string(), "engine": engine, "fields": fields, "warmup": warmup, "T0": T0});
        let ens = c.ensemble(fig.binary, &key, runs)?;
        let mean = (BIN * params.width) as f64 * params.rho;
        let outcome = ens.run(steady.steps(), |_, seed, tick| {
            let f = steady.record(params, rules, engine, seed, tick)?;
            Ok(profile_run(&f, mean, BIN, seed))
        })?;
        seeds = ens.seeds();
        per_l.push((params, outcome.complete(&format!("L = {length}: "))));
    }
    let Some(per_l) = per_l
        .into_iter()
        .map(|(p, res)| res.map(|r| (p, r)))
        .collect::<Option<Vec<_>>>()
    else {
        return Ok(());
    };
    let out = fig.output(&c.out)?;

    let mut metrics = std::collections::BTreeMap::new();
    let (mut lines, mut rows, mut shape_pts) = (vec![], vec![], [vec![], vec![], vec![]]);
    let (mut checks, mut steep) = (vec![], vec![]);
    for (k, (params, res)) in per_l.iter().enumerate() {
        let l = params.length;
        let st = stats_by(res, &PROFILE_MEASURES);
        let ((m, e), null, asy) = (
            st["excess_amplitude"],
            st["null_amplitude"].0,
            st["asymmetry"],
        );
        let random_var = random_start_bin_variance(params.rho, BIN, params.width);
        metrics.insert(format!("random_start_bin_variance_L{l}"), random_var);
        metrics.extend(stat_metrics(
            st.iter().map(|(n, &v)| (format!("{n}_L{l}"), v)),
        ));
        for (pts, y) in shape_pts
            .iter_mut()
            .zip([st["amplitude"].0, st["width"].0, asy.0])
        {
            pts.push((l as f64, y));
        }
        let pts = ensemble_profile(res, BIN);
        rows.extend(pts.iter().map(|&(x, y)| vec![l as f64, x, y]));
        lines.push(Line::new(
            &format!("L = {l}"),
            pts,
            PALETTE[k % PALETTE.len()],
        ));
        let excess = Estimate::new(m, e, res.len());
        let threshold = (NULL_FACTOR - 1.0) * null;
        checks.push(Check::published(
            &format!("wave_profile_L{l}"),
            "PH95 Fig. 4 (a wave profile)",
            excess,
            Claim::Above { threshold },
            &format!("a wave: the excess amplitude over the alignment bias of white noise (same alignment, the run's per-bin variance) exceeds that bias itself, null = {null:.4} (amplitude above twice the noise level; factor {NULL_FACTOR} as fig1's s_low threshold, fixed after a wave-free reading with correlated noise, any-mover, showed excesses of 0.3-0.8 of the null)"),
        ));
        checks.push(Check::pinned(
            &format!("flat_profile_L{l}"),
            "the wave-free control (p = 0)",
            excess,
            Claim::Below { threshold },
            &format!("flat within noise: excess below null = {null:.4} (expected for a wave-free reading such as p = 0)"),
        ));
        steep.push(steep_front_check(l, res));
    }
    checks.extend(steep);
    if per_l.len() > 1 {
        let by_l = |(p, _): &&(Params, Vec<ProfileRun>)| p.length;
        let first = per_l.iter().min_by_key(by_l).expect("lengths");
        let last = per_l.iter().max_by_key(by_l).expect("lengths");
        checks.push(width_grows_check(
            (first.0.length, &first.1),
            (last.0.length, &last.1),
        ));
    }
    out.write_csv(
        "fig4_profiles.csv",
        &["L", "y_minus_peak_rows", "density_over_mean"],
        &rows,
    )?;
    let runs_rows: Vec<Vec<f64>> = per_l
        .iter()
        .flat_map(|(p, res)| {
            let l = p.length as f64;
            res.iter()
                .enumerate()
                .map(move |(i, r)| [l, i as f64].into_iter().chain(r.row()).collect())
        })
        .collect();
    let header: Vec<&str> = ["L", "run"]
        .into_iter()
        .chain(ProfileRun::COLUMNS)
        .collect();
    out.write_csv("runs.csv", &header, &runs_rows)?;
    let p = args.wave.p;
    line_chart(
        &out.path("fig4.png"),
        &format!(
            "PH95 Fig. 4: aligned wave profile, p = {p}, {runs} runs x {fields} fields, {rules}"
        ),
        "y - y_peak (rows); gravity towards negative values",
        "density / mean density",
        &lines,
        false,
    )?;
    let [amp, width, asym] = shape_pts;
    let x100 = |v: Vec<(f64, f64)>| v.into_iter().map(|(x, y)| (x, 100.0 * y)).collect();
    line_chart(
        &out.path("fig4_shape.png"),
        &format!("PH95 Fig. 4: wave shape against L, p = {p}, {runs} runs"),
        "pipe length L (rows)",
        "amplitude (x100), width (rows), asymmetry (x100)",
        &[
            Line::new("amplitude (max - mean) / mean x 100", x100(amp), PALETTE[0]).markers(),
            Line::new("width at half excess (rows)", width, PALETTE[1]).markers(),
            Line::new("asymmetry x 100 (> 0: steep front)", x100(asym), PALETTE[2]).markers(),
        ],
        false,
    )?;
    let summary_params = json!({"L": args.lengths, "W": 11, "rho": 1.0, "p": p, "g": 0.5, "b": 0.5, "bin": BIN, "fields": fields, "T0": T0, "warmup": warmup, "runs": runs});
    let site_updates = per_l
        .iter()
        .map(|(p, _)| (runs as u64 * steady.steps() * p.sites() as u64) as f64)
        .sum();
    fig.finish(&out, seeds, summary_params, site_updates, metrics, checks)?;
    Ok(())
}
