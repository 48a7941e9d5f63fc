//! PH95 Fig. 6: the density spectrum at strong dissipation p = 0.8 (L = 220,
//! W = 11, rho = 1, g = b = 0.5). Published: alpha about 1.33.
//!
//! `cargo run --release --bin waves-fig6 -- --tier quick`

use granular_automata::cli::SequentialArgs;
use granular_automata::drivers::margins::ALPHA_MARGIN;
use granular_automata::drivers::spectra::SpectrumFigure;
use granular_automata::pipe::Params;

granular_automata::main_of!(body);

fn body() -> Result<(), Box<dyn std::error::Error>> {
    let args =
        SequentialArgs::parse_about("PH95 Fig. 6: density spectrum at p = 0.8 (alpha about 1.33)");
    let fig = SpectrumFigure {
        binary: "waves-fig6",
        paper: "PH95 Fig. 6",
        params: Params {
            p: 0.8,
            ..Params::default()
        },
        // "about 1.33", graded with the matrix's margin (drivers::claims)
        alpha: (1.33, ALPHA_MARGIN),
        v_peak: None,
        note: "; published 'about 1.33'",
    };
    fig.run(&args)?;
    Ok(())
}
