//! PH94 Fig. 2: power spectrum of the particle count in one bin of 10 rows,
//! L = 220, W = 11, rho = 1, p = g = b = 0.5, sampled every 10 steps.
//! Published: alpha = 1.33 +- 0.02 over 40 <= j <= 1000, a sharp peak at
//! j = 596, i.e. v = 0.40.
//!
//! `cargo run --release --bin fig2 -- --tier quick`

use granular_automata::cli::SequentialArgs;
use granular_automata::drivers::margins::{ALPHA_MARGIN, V_MARGIN};
use granular_automata::drivers::spectra::SpectrumFigure;
use granular_automata::pipe::Params;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args = SequentialArgs::parse_about(
        "PH94 Fig. 2: 1/f^alpha density spectrum with a wave peak (L = 220, p = g = b = 0.5)",
    );
    let fig = SpectrumFigure {
        binary: "fig2",
        paper: "PH94 Fig. 2",
        // the default pipe is this figure's: L = 220, W = 11, rho = 1, p = g = b = 0.5
        params: Params::default(),
        // PH94: alpha = 1.33 +- 0.02 and a peak at v = 0.40; margins Delta
        // fixed before measuring, as in the matrix (drivers::claims)
        alpha: (1.33, ALPHA_MARGIN),
        v_peak: Some((0.40, V_MARGIN)),
        note: "",
    };
    fig.run(&args)?;
    Ok(())
}
