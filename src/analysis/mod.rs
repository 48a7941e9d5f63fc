//! Analysis of recorded time series (MODEL.md A9): power spectra of bin
//! densities and what is read off them.
//!
//! - [`spectrum`]: the Numerical Recipes (1988) `spctrm` estimator without
//!   overlap (MODEL.md A9 "Power spectrum"), with the 1988 "Parzen" triangle
//!   as the default window.
//! - [`fit`]: least squares, the exponent alpha of P(j) ~ j^-alpha with the
//!   sharp peak removed (A9 "Exponent alpha"), peak finding and the wave
//!   velocity from the peak (A9 "Wave velocity from the peak").
//! - [`waves`]: the wave speed from the spectra of a stack of density fields.
//! - [`relaxation`]: the approach of an ensemble of series to saturation
//!   (half-times, window means; PH95 Fig. 3).
//! - [`grading`]: the one grading rule of every check (reproduced / not
//!   reproduced / undecided).
//! - [`sequential`]: the one rule at looks fixed in advance, with boundaries
//!   from an error-spending rule (group-sequential grading).
//! - [`representative`]: whether a published single-run fit is a typical
//!   run of the model (the central 95 % of the per-run fits).
//! - [`stats`]: Student's t tail and critical values for one-sided tests.

pub mod fit;
pub mod grading;
pub mod mean_spectrum;
pub mod relaxation;
pub mod representative;
pub mod resample;
pub mod sequential;
pub mod spectrum;
pub mod stats;
pub mod waves;
