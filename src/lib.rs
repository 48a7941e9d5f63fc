//! # granular-automata
//!
//! A validated reference implementation of two classic cellular-automaton
//! models of granular flow, with one binary per published figure and tests
//! that grade the results against the published values.
//!
//! ## Guide
//!
//! Add the crate (`cargo add granular-automata`); the examples below run as
//! doctests in a second or two, on small lattices.
//!
//! **Run a pipe.** [`pipe::Pipe`] is the reference engine of the pipe
//! lattice gas; [`pipe::Params`] defaults to PH94 Fig. 2's set-up (p = g =
//! b = 0.5, rho = 1), here on a pipe of 5 columns and 60 rows. A run is a
//! pure function of (parameters, rules, seed).
//!
//! ```
//! use granular_automata::pipe::{Params, Pipe, Rules};
//! let params = Params { width: 5, length: 60, ..Params::default() };
//! let mut pipe = Pipe::new(params, Rules::default(), 1)?;
//! pipe.run(1_000)?;
//! println!("{:?}", pipe.bin_counts()); // particles in each bin of 10 rows
//! # Ok::<(), granular_automata::Error>(())
//! ```
//!
//! **Take its spectrum.** The figures record a bin's particle count every
//! T0 = 10 steps, estimate its power spectrum with Numerical Recipes'
//! `spctrm` ([`analysis::spectrum`]) and fit P ~ f^-alpha with the wave
//! peak left out ([`analysis::fit::estimate_alpha`]); MODEL.md A9. The
//! papers use m = 16384 frequencies; m = 256 keeps this short.
//!
//! ```
//! use granular_automata::analysis::fit::estimate_alpha;
//! use granular_automata::analysis::spectrum::{spctrm, SpectrumParams};
//! use granular_automata::pipe::{Params, Pipe, Rules};
//! let params = Params { width: 5, length: 60, ..Params::default() };
//! let mut pipe = Pipe::new(params, Rules::default(), 1)?;
//! let spectrum = SpectrumParams { m: 256, k: 2, ..SpectrumParams::default() };
//! let mut series = Vec::new();
//! for _ in 0..spectrum.samples_used() {
//!     pipe.run(10)?;
//!     series.push(pipe.bin_counts()[0]);
//! }
//! let p = spctrm(&series, &spectrum)?;
//! let fit = estimate_alpha(&p)?.fit;
//! println!("alpha = {:.2} +- {:.2}", fit.alpha, fit.alpha_err);
//! # Ok::<(), granular_automata::Error>(())
//! ```
//!
//! **Grade a value.** Every check grades the mean of n independent runs
//! and its standard error against a claim fixed before measuring, by one
//! rule ([`analysis::grading`]): here PH94's alpha = 1.33 with the
//! acceptance margin 0.059 ([`drivers::acceptance`]). Fewer than 3 runs
//! decide nothing.
//!
//! ```
//! use granular_automata::analysis::grading::{grade, Claim, Estimate, Verdict};
//! let claim = Claim::Within { target: 1.33, margin: 0.059 };
//! assert_eq!(grade(Estimate::new(1.32, 0.005, 8), claim), Verdict::Reproduced);
//! assert_eq!(grade(Estimate::new(1.10, 0.005, 8), claim), Verdict::NotReproduced);
//! assert_eq!(grade(Estimate::new(1.32, 0.005, 2), claim), Verdict::Undecided);
//! ```
//!
//! **Validate an engine.** [`validate::validate`] checks a candidate
//! engine against the reference (VALIDATION.md): level 1 the rules step by
//! step, level 2 the statistics of whole runs. A candidate is the fast
//! engine, a deliberate mutant, an external program (`cmd:...`) or any
//! type implementing [`validate::candidate::Candidate`]. The sizes here are
//! far below the quick tier's.
//!
//! ```
//! use granular_automata::run::Tier;
//! use granular_automata::validate::{candidate_from, validate, Level, Model, Plan, Size};
//! let fast = candidate_from("fast", None)?;
//! let size = Size { trials: 500, runs: 2, hopper_runs: 2 };
//! let plan = Plan::new("default", Level::One, Model::Pipe, Tier::Quick, size, 1);
//! let report = validate(fast.as_ref(), &plan, &|| {})?;
//! assert!(report.pass);
//! # Ok::<(), granular_automata::Error>(())
//! ```
//!
//! ## Map
//!
//! **The two automata.**
//!
//! - The **pipe lattice gas** of Peng & Herrmann (PH94, PH95): particles on a
//!   triangular lattice in a vertical pipe, dissipative collisions (p),
//!   gravity (g), rough walls (b). Engine and rule readings in [`pipe`]
//!   ([`pipe::Pipe`], [`pipe::Rules`], default `ph94+gravity-first+wall-move+inject-late`);
//!   the open pipe in [`pipe::open`]; observables in [`pipe::observables`],
//!   [`pipe::overlap`] and [`drivers::spectra`]; the graded claims in
//!   [`drivers::claims`].
//! - The **hopper automaton** of Baxter & Behringer (BB90): oriented grains
//!   choosing the state of least energy in a 60° wedge, filled by rain and
//!   emptied through an outlet. In [`hopper`] ([`hopper::Hopper`]).
//!
//! Both use the lattice of [`lattice`]; spectra, fits and the one grading
//! rule are in [`analysis`].
//!
//! **The figure binaries** (`reproduce/`, one per published figure:
//! `fig1`, `fig2` for PH94; `waves-fig2` ... `waves-fig12` for PH95;
//! `hopper-fig2`, `hopper-fig3` for BB90; plus `pipe-matrix`, the grading of
//! every rule reading against every claim). Each takes `--tier quick`
//! (seconds, what the tests run), `standard` (minutes) or `paper` (the
//! published sizes), see [`run::Tier`], and the shared options of [`cli`];
//! each writes PNGs, CSVs and a `summary.json` with its checks
//! ([`run::Summary`]) under `--out DIR/<binary>/`. Runs are pure functions of
//! (parameters, rules, seed); the ensemble runner is [`ensemble`].
//!
//! **The engine contract** ([`validate`], `VALIDATION.md`): a `validate`
//! command that checks another implementation against this reference
//! engine; the bytes of a run and the golden snapshots in `golden/` are the
//! baseline of the reference engine itself.
//!
//! **The documents** (in the repository root):
//!
//! - `MODEL.md`: the specification: every rule with the papers' item and
//!   section, every choice the papers leave open and the default taken, the
//!   observables, the published targets. The code cites its sections as
//!   "MODEL.md A5".
//! - `READINGS.md`: every place where the papers' text allows more than one
//!   implementation, with the named variant of each option.
//! - `EXPERIMENTS.md`: every measured number with its command, tier, seeds,
//!   ensemble size and wall time.
//!
//! Errors are values of [`Error`]: every failure names the offending value
//! and the allowed range.
#![deny(missing_docs)]

pub mod analysis;
pub mod cli;
pub mod drivers;
pub mod ensemble;
pub mod error;
pub mod experiments;
pub mod fuzz;
pub mod hopper;
pub mod lattice;
pub mod pipe;
pub mod plot;
pub mod readings_map;
pub mod report;
pub mod run;
pub mod speed;
pub mod validate;

pub use error::{Error, ErrorKind, Result};
