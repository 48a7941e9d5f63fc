//! PH95 Fig. 12: the open pipe at p = b = g = 0.5 (MODEL.md A7). The critical
//! injection rate I_c (the largest I at which N(t) becomes stationary: no
//! clogging) by bisection with a trend test, and its dependence on W and L;
//! (a) spectra of the bottom bin below, near and above I_c; (b) alpha against
//! I; (c) N(t) for several I averaged over runs. Choice: the main pipe is
//! L = 220, W = 11 (as Figs. 2-10); I_c is also measured for other W and L.
//! Each bisection rate stops at its first clogging run (in run order), which
//! decides its verdict: `waves-fig12_bisection.csv` gives the runs made
//! (`runs`) and what they showed; I_c is the same as with every run. At
//! `--tier acceptance` the spectrum points stop look by look (the
//! sequential design, `drivers::critical::run_spectra`) unless
//! `--fixed-runs` fixes their count.
//! Published checks (shared with the reproduction matrix,
//! `drivers::open_pipe`): I_c = 0.52, I_c independent of W and L, 1/f at
//! I_c (at the largest rate the bisection found stationary), white noise at
//! 0.5 I_c, clogging at I = 0.54.
//!
//! `cargo run --release --bin waves-fig12 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{reject_duplicates, SequentialArgs};
use granular_automata::drivers::critical::{
    self, check_options, check_sizes, default_sizes, plot_nt, plot_spectra, round_rate,
    run_spectra, spectrum_points, verdict, Measured, Trends, EVERY, NT_FRACTIONS,
    SPECTRUM_FRACTIONS,
};
use granular_automata::drivers::open_pipe::{fig12_pipe, CLOG_INJECT};
use granular_automata::drivers::spectra::tier_setup;
use granular_automata::drivers::sweep::results_site_updates;
use granular_automata::pipe::open::{trend_threshold, PipeSize, TREND_FALSE_ALARM};
use granular_automata::pipe::Params;
use granular_automata::run::{run_seeds, Output, Summary};
use serde_json::json;
use std::time::Instant;

#[derive(Parser)]
#[command(about = "PH95 Fig. 12: open pipe, critical injection rate, spectra and alpha against I", mut_arg("shard", |a| a.hide(true)))]
struct Args {
    #[command(flatten)]
    seq: SequentialArgs,
    /// Steps of each trend run of N(t) from an empty pipe (default by tier:
    /// 20000, 50000, 100000). Shorter runs see fewer clogs: I_c is biased up.
    #[arg(long, allow_negative_numbers = true)]
    steps: Option<u64>,
    /// Pipes whose I_c is measured, as LxW separated by commas; the first is
    /// the main pipe of panels (a)-(c) (default by tier; quick:
    /// 220x11,220x5,440x11).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    sizes: Vec<PipeSize>,
    /// Bisection steps for I_c on [0, 1] (default by tier: 5, 6, 7); the
    /// error of I_c is the final half-width 2^-(n+1).
    #[arg(long, allow_negative_numbers = true)]
    bisections: Option<usize>,
    /// Skip the spectra (panels a and b: waves-fig12a.png, waves-fig12b.png,
    /// waves-fig12b.csv), about three quarters of the cost: only I_c and N(t).
    #[arg(long)]
    no_spectra: bool,
}

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let rules = args.seq.pipe.rules.parse()?;
    let engine = args.seq.pipe.rules.engine(args.seq.pipe.common.tier)?;
    let c = &args.seq.pipe.common;
    c.reject_shard("waves-fig12")?; // the bisection is sequential
    args.seq.sequential()?; // the design's options are checked before any run
    let steps: u64 = args.steps.unwrap_or(c.tier.pick(20_000, 50_000, 100_000));
    let runs = c.runs_or(4, 8, 32);
    let bisect_steps = args.bisections.unwrap_or(c.tier.pick(5, 6, 7));
    check_options(steps, bisect_steps)?;
    let geoms: Vec<(usize, usize)> = match args.sizes.is_empty() {
        true => default_sizes(c.tier),
        false => args.sizes.iter().map(|s| (s.length, s.width)).collect(),
    };
    reject_duplicates("--sizes", &args.sizes)?;
    check_sizes(&geoms)?; // bad sizes fail before any run
    let (l0, w0) = geoms[0];
    let main_pipe = format!("L = {l0}, W = {w0}");
    let start = Instant::now();
    let (common, [f0, f1, f2]) = (c, SPECTRUM_FRACTIONS);
    let trends = Trends {
        common,
        rules,
        engine,
        steps,
        runs,
    };
    let bisections = trends.bisect_sizes(&geoms, bisect_steps)?;
    let (_, _, i_c, i_c_err) = bisections.ic[0];
    // (c) N(t) below, near and above I_c at the main pipe
    let mut nt = Vec::new();
    for f in NT_FRACTIONS {
        let i = round_rate((f * i_c).min(1.0));
        let v = trends.run(fig12_pipe(l0, w0, i), false)?;
        nt.push((i, verdict(&v), v));
    }
    // PH95 Fig. 12c: N(t) at the published I = 0.54
    let clog = trends.run(fig12_pipe(l0, w0, CLOG_INJECT), false)?;
    // (a), (b) spectra of the bottom bin against I
    let ifr: &[f64] = if args.no_spectra {
        &[]
    } else {
        c.tier.pick(f0, f1, f2)
    };
    let points = spectrum_points(ifr, (l0, w0), (i_c, i_c_err));
    let sruns = c.runs_or(2, 8, 32);
    let setup_of = |p| tier_setup(c.tier, p, rules, engine);
    let (res, stopped) = run_spectra(&args.seq, &points, sruns, setup_of, (!args.no_spectra, i_c))?;
    let wall = start.elapsed().as_secs_f64();

    let out = Output::new(&c.out, "waves-fig12")?;
    bisections.write_csv(&out)?;
    plot_nt(&out, &nt, &main_pipe, runs)?;
    let measured = Measured {
        bisections: &bisections,
        nt: &nt,
        clog: &clog,
        spectra: &res,
        with_spectra: !args.no_spectra,
        stopped: stopped.as_deref(),
        runs,
    };
    let (checks, metrics) = (critical::checks(&measured), measured.metrics());
    if !res.is_empty() {
        plot_spectra(&out, &res, &main_pipe, i_c, rules, &checks)?;
    }
    let thr = trend_threshold(runs);
    let base = Params::default(); // p = b = g = 0.5
    out.finish(&Summary {
        figure: "waves-fig12".into(),
        paper: "PH95 Fig. 12".into(),
        tier: c.tier,
        seeds: run_seeds(c.seed, res.iter().map(|r| r.valid + r.invalid).fold(runs, usize::max)),
        params: json!({"base": base, "geometries": geoms, "trend_steps": steps, "trend_every": EVERY, "trend_runs": runs,
            "trend_false_alarm": TREND_FALSE_ALARM, "trend_threshold": thr,
            "bisection_steps": bisect_steps, "spectrum_runs": sruns, "I_over_I_c": ifr, "setup": setup_of(fig12_pipe(l0, w0, i_c))}),
        rules: rules.to_string(),
        engine: engine.label(),
        wall_seconds: wall,
        site_updates: bisections.rows.iter().map(|r| r[0] * r[1] * r[3]).sum::<f64>() * steps as f64
            + results_site_updates(&res, setup_of),
        metrics,
        missing_metrics: Default::default(),
        checks,
    })?;
    Ok(())
}
