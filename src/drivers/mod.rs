//! The drivers the figure binaries share, one layer above the models: an
//! ensemble of density spectra ([`spectra`]), a sweep of spectra over a
//! parameter ([`sweep`]), the open pipe's claims ([`open_pipe`]) and the reproduction matrix of the pipe readings
//! ([`claims`]), with the margins they share ([`margins`]). They run the models, grade the claims and may read the
//! command-line options ([`crate::cli`]); the models ([`crate::pipe`],
//! [`crate::hopper`]) and the analysis ([`crate::analysis`]) never import this
//! layer or the CLI.

pub mod acceptance;
pub mod acceptance_study;
/// PH94 Fig. 1: the density bands of its four panels over an ensemble, their checks and plots.
pub mod bands;
pub mod claims;
/// PH95 Fig. 11, the open pipe's correlation runs, panels and readings.
pub mod fig11;
/// The hopper figures of BB90 Figs. 2 and 3: metrics, checks and charts from their runs.
pub mod hopper_figures;
pub mod margins;
pub mod open_pipe;
/// PH95 Figs. 4 and 5: the wave profile and the wave speeds read over an ensemble.
pub mod profiles;
pub mod relaxation;
pub mod spectra;
pub mod sweep;
