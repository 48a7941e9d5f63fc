//! The drivers the figure binaries share, one layer above the models. They
//! run the models, grade the claims and may read the command-line options
//! ([`crate::cli`]); the models ([`crate::pipe`], [`crate::hopper`]) and the
//! analysis ([`crate::analysis`]) never import this layer or the CLI.
//!
//! - Shared by many figures: an ensemble of density spectra ([`spectra`]),
//!   a sweep of spectra over a parameter ([`sweep`]), the open pipe's claims
//!   ([`open_pipe`]), the margins of the published claims ([`margins`]).
//! - One figure's procedure, so that its binary stays a short script:
//!   PH94 Fig. 1 ([`bands`]), PH95 Fig. 3 ([`relaxation`]),
//!   Figs. 4-5 ([`profiles`]), Fig. 7 ([`white_noise`]), Fig. 11
//!   ([`fig11`]), Fig. 12 ([`critical`]), BB90 Figs. 2-3
//!   ([`hopper_figures`]).
//! - The reproduction matrix of the pipe readings ([`claims`], run by
//!   [`matrix`]) and the acceptance tier ([`acceptance`],
//!   [`acceptance_study`]).

pub mod acceptance;
pub mod acceptance_study;
/// PH94 Fig. 1: the density bands of its four panels over an ensemble, their checks and plots.
pub mod bands;
/// The calibrated bridge `lane-collide:q`: kinds of claims, the split, the rule that picks q.
pub mod bridge;
pub mod claims;
/// PH95 Fig. 12: I_c by bisection at every pipe size, N(t), the spectra's rates, checks and panels.
pub mod critical;
/// PH95 III F-H (Figs. 9-10): the claims on how alpha and v depend on rho, b and g.
pub mod dependence;
/// PH95 Fig. 11, the open pipe's correlation runs, panels and readings.
pub mod fig11;
/// The hopper figures of BB90 Figs. 2 and 3: metrics, checks and charts from their runs.
pub mod hopper_figures;
pub mod margins;
/// `pipe-matrix`: every reading graded against every claim, saved, tabulated and drawn.
pub mod matrix;
pub mod open_pipe;
/// PH95 Figs. 4 and 5: the wave profile and the wave speeds read over an ensemble.
pub mod profiles;
pub mod relaxation;
/// The group-sequential designs measured: wrong-verdict rates and runs against the truth.
pub mod sequential;
pub mod spectra;
pub mod sweep;
/// PH95 Fig. 7: white noise at p = 0 and b = 0, the peak at v = 1/2.
pub mod white_noise;
