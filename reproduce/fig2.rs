//! PH94 Fig. 2: power spectrum of the particle count in one bin of 10 rows,
//! L = 220, W = 11, rho = 1, p = g = b = 0.5, sampled every 10 steps.
//! Published: alpha = 1.33 +- 0.02 over 40 <= j <= 1000, a sharp peak at
//! j = 596, i.e. v = 0.40.
//!
//! `cargo run --release --bin fig2 -- --tier quick`

use clap::Parser;
use granular_automata::cli::{Common, PipeRules};
use granular_automata::pipe::spectra::{run_figure, SpectrumFigure};
use granular_automata::pipe::Params;

#[derive(Parser)]
#[command(
    about = "PH94 Fig. 2: 1/f^alpha density spectrum with a wave peak (L = 220, p = g = b = 0.5)"
)]
struct Args {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    rules: PipeRules,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = Args::parse();
    let fig = SpectrumFigure {
        binary: "fig2",
        paper: "PH94 Fig. 2",
        params: Params {
            length: 220,
            width: 11,
            rho: 1.0,
            p: 0.5,
            g: 0.5,
            b: 0.5,
            ..Params::default()
        },
        alpha: (1.33, 0.02),         // PH94: 1.33 +- 0.02
        v_peak: Some((0.40, 0.005)), // PH94: 0.40, two decimals
        note: "",
    };
    run_figure(&fig, &args.common, args.rules.parse()?)?;
    Ok(())
}
