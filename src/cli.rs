//! Command-line options shared by every figure binary (the output contract
//! of the README, "Figure binaries"): `--tier`, `--seed`, `--runs`, `--rules`, `--out`; and
//! those of the PH95 wave figures (Figs. 2-5), with `--p`.
//!
//! A pipe figure whose options are just these parses them with
//! [`PipeArgs::parse_about`]; one with options of its own flattens
//! [`PipeArgs`] into its `clap::Parser`.

use crate::analysis::grading::MIN_RUNS;
use crate::ensemble::{Ensemble, Shard};
use crate::pipe::record::fig1_pipe;
use crate::pipe::rules::RULE_NAMES;
use crate::pipe::{Params, Rules};
use crate::run::{Figure, Tier};
use std::path::PathBuf;

pub use crate::ensemble::MAX_RUNS;

/// Largest `--threads` accepted (far above any machine this runs on).
pub const MAX_THREADS: usize = 1024;

/// Parse a whole number `s` of option `name` in `lo..=hi`; otherwise an
/// [`crate::ErrorKind::InvalidParameter`] error naming the option, the value
/// and the range (never a silent coercion: `--runs 0` is an error).
pub fn parse_count(name: &str, s: &str, lo: usize, hi: usize) -> crate::Result<usize> {
    match s.trim().parse::<usize>() {
        Ok(n) if (lo..=hi).contains(&n) => Ok(n),
        _ => Err(crate::Error::out_of_range(name, s, &format!("{lo}..={hi}"))),
    }
}

/// Parse `s` as the value of option `name`: a finite number in
/// `lo..=hi`, or an error naming the value and the range.
pub fn parse_real(name: &str, s: &str, lo: f64, hi: f64) -> crate::Result<f64> {
    let range = format!("{lo}..={hi}");
    let v: f64 = s
        .trim()
        .parse()
        .map_err(|_| crate::Error::out_of_range(name, s, &range))?;
    if v.is_finite() && (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(crate::Error::out_of_range(name, v, &range))
    }
}

/// Parse a seed option `name`: a whole number in 0..=2^64 - 1.
pub fn parse_seed(name: &str, s: &str) -> crate::Result<u64> {
    s.trim()
        .parse::<u64>()
        .map_err(|_| crate::Error::out_of_range(name, s, &format!("0..={}", u64::MAX)))
}

/// Parse `--runs`: a whole number in 1..=[`MAX_RUNS`].
pub fn parse_runs(s: &str) -> crate::Result<usize> {
    parse_count("--runs", s, 1, MAX_RUNS)
}

/// Parse `--threads`: a whole number in 1..=[`MAX_THREADS`].
pub fn parse_threads(s: &str) -> crate::Result<usize> {
    parse_count("--threads", s, 1, MAX_THREADS)
}

pub use crate::error::reject_duplicates;

/// Reject a pipe of fewer than two bins: its one bin count is the
/// conserved particle number (periodic pipe) or the whole pipe, so no wave,
/// profile or bin spectrum can be measured. An
/// [`crate::ErrorKind::InvalidParameter`] error naming L and the allowed range.
pub fn check_two_bins(length: usize, bin: usize) -> crate::Result<()> {
    if length < 2 * bin {
        return Err(crate::Error::new(
            crate::ErrorKind::InvalidParameter,
            format!(
                "L = {length} with bins of {bin} rows is a pipe of {} bin(s): nothing to measure between bins; \
                 choose L in [{}, inf), a multiple of {bin}",
                length / bin,
                2 * bin
            ),
        ));
    }
    Ok(())
}

pub use crate::run::MAX_STEPS;

/// Check `--steps` against `min..=`[`MAX_STEPS`]: `steps`, or an
/// [`crate::ErrorKind::InvalidParameter`] error naming the value and the
/// range; `why` says what the lower bound is for.
pub fn check_steps(steps: u64, min: u64, why: &str) -> crate::Result<u64> {
    if (min..=MAX_STEPS).contains(&steps) {
        Ok(steps)
    } else {
        Err(crate::Error::out_of_range(
            "--steps",
            steps,
            &format!("{min}..={MAX_STEPS} ({why})"),
        ))
    }
}

/// Reject an effectively empty periodic pipe: fewer than one particle per
/// bin on average (rho W bin < 1, MODEL.md A8), where the bins hold mostly
/// nothing and a contrast, structure factor or spectrum measures the
/// emptiness, not the waves; also fewer than two bins ([`check_two_bins`]).
/// An [`crate::ErrorKind::InvalidParameter`] error naming rho and the
/// allowed range at this W and bin.
pub fn check_populated(params: &Params) -> crate::Result<()> {
    check_two_bins(params.length, params.bin)?;
    let sites = params.width * params.bin;
    if params.rho * (sites as f64) < 1.0 {
        // (Debug: 1e-300, not three hundred digits)
        return Err(crate::Error::out_of_range(
            "rho",
            format!("{:?}", params.rho),
            &format!(
                "[1/{sites}, {}) (at least one particle per bin of {sites} sites on average)",
                crate::pipe::RHO_RANGE.1
            ),
        ));
    }
    Ok(())
}

/// Options every figure binary takes (flatten into its own `clap::Parser`).
#[derive(Debug, Clone, clap::Args)]
pub struct Common {
    /// How much to compute: quick (seconds), standard (minutes), paper
    /// (published sizes), acceptance (published sizes, fast engine for the
    /// pipe, the acceptance estimators and run counts).
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    pub tier: Tier,
    /// Base seed; run i of an ensemble uses derive_seed(seed, i).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Number of independent runs to average, 1..=100000 (default: set by the
    /// tier). `--fixed-runs` is the same option: at --tier acceptance it
    /// replaces the sequential design of PH94 Fig. 2 and PH95 Figs. 6 and
    /// 8-10 by this fixed count (per sweep point), which sharding needs.
    #[arg(long, visible_alias = "fixed-runs", value_parser = parse_runs, allow_negative_numbers = true)]
    pub runs: Option<usize>,
    /// Output folder; the figure writes into `OUT/<binary>/`.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Run only shard i of n (runs r with r mod n = i, 0 <= i < n), e.g.
    /// `--shard $SLURM_ARRAY_TASK_ID/8`; combine the shards' --out folders
    /// with the `merge` binary, then rerun without --shard to analyse.
    #[arg(long, allow_hyphen_values = true)]
    pub shard: Option<Shard>,
    /// Worker threads, 1..=1024 (default: all cores); results do not depend on it.
    #[arg(long, value_parser = parse_threads, allow_negative_numbers = true)]
    pub threads: Option<usize>,
}

/// The `--rules` option of the pipe figures.
#[derive(Debug, Clone, clap::Args)]
pub struct PipeRules {
    /// Rule reading: names joined by '+', e.g. ph94, any-mover, ph94+wall-drag,
    /// any-mover+gravity-first+rest-up ('--rules help' lists them).
    #[arg(long, default_value = "default")]
    pub rules: String,
    /// Engine: reference (plain, one byte per site) or fast (bit-sliced,
    /// validated against the reference by `validate`). Default: reference,
    /// but fast at --tier acceptance.
    #[arg(long)]
    pub engine: Option<String>,
}

/// `--runs` (`--fixed-runs`) of the matrix and the bridge: the figures'
/// help speaks of a sequential design these do not have.
pub const MATRIX_RUNS_HELP: &str = "Runs for every set-up of the matrix (spectra, waves, open pipe), 1..=100000 (default: set by the tier); --fixed-runs is the same option, as in every figure (the matrix has no sequential design)";

/// The options of a pipe figure: [`Common`] and `--rules`.
#[derive(Debug, Clone, clap::Parser)]
pub struct PipeArgs {
    /// `--tier`, `--seed`, `--runs`, `--out`, `--shard`, `--threads`.
    #[command(flatten)]
    pub common: Common,
    /// `--rules`.
    #[command(flatten)]
    pub rules: PipeRules,
}

impl PipeArgs {
    /// Parse the command line of a figure binary whose `--help` starts with
    /// `about` (exits with clap's message on bad input or `--help`).
    pub fn parse_about(about: &'static str) -> Self {
        use clap::{CommandFactory, FromArgMatches};
        let matches = Self::command().about(about).get_matches();
        Self::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
    }
}

/// The options of a pipe figure that grades sequentially at the acceptance
/// tier (PH94 Fig. 2, PH95 Figs. 6, 8-10 and 12's spectra): [`PipeArgs`] and
/// `--sequential-max` (`--fixed-runs`, an alias of `--runs`, keeps the
/// fixed design).
#[derive(Debug, Clone, clap::Parser)]
pub struct SequentialArgs {
    /// `--tier`, `--seed`, `--runs`, `--out`, `--shard`, `--threads`, `--rules`, `--engine`.
    #[command(flatten)]
    pub pipe: PipeArgs,
    /// At --tier acceptance, sequential design only: its largest look as F
    /// times the figure's fixed count, 1..=64 (default 1; 4 decides more
    /// claims at about 1.5 times the fixed design's runs,
    /// docs/sequential-design).
    #[arg(long, value_parser = parse_factor, default_value_t = 1, allow_negative_numbers = true)]
    pub sequential_max: usize,
}

/// Parse `--sequential-max`: a whole number in 1..=64.
pub fn parse_factor(s: &str) -> crate::Result<usize> {
    parse_count("--sequential-max", s, 1, 64)
}

impl SequentialArgs {
    /// Parse the command line of a figure whose `--help` starts with
    /// `about` (exits with clap's message on bad input).
    pub fn parse_about(about: &'static str) -> Self {
        use clap::{CommandFactory, FromArgMatches};
        let matches = Self::command().about(about).get_matches();
        Self::from_arg_matches(&matches).unwrap_or_else(|e| e.exit())
    }

    /// Whether the figure grades sequentially: at the acceptance tier,
    /// unless a run count is fixed (`--fixed-runs`, or `--runs`). Refuses
    /// `--shard` with the sequential design (a look needs every run of the
    /// one before it) and `--sequential-max` without it.
    pub fn sequential(&self) -> crate::Result<bool> {
        let c = &self.pipe.common;
        let sequential = c.tier.is_acceptance() && c.runs.is_none();
        let bad = |why: String| Err(crate::Error::new(crate::ErrorKind::InvalidParameter, why));
        if sequential && c.shard.is_some() {
            return bad("--shard at --tier acceptance: the default sequential design needs every run of one look before the next, in one process; give --fixed-runs N (the fixed count, 128 for most figures) to shard".into());
        }
        // the acceptance estimators (a bootstrap over runs) need at least
        // MIN_RUNS runs: refused here, before any run is made or written
        if let Some(n) = c.runs.filter(|&n| c.tier.is_acceptance() && n < MIN_RUNS) {
            return bad(format!(
                "--fixed-runs {n} (--runs) at --tier acceptance: its estimators need at least {MIN_RUNS} runs; choose --fixed-runs in [{MIN_RUNS}, 100000]"
            ));
        }
        if !sequential && self.sequential_max != 1 {
            return bad(format!(
                "--sequential-max {}: only for the sequential design, at --tier acceptance without --runs or --fixed-runs",
                self.sequential_max
            ));
        }
        Ok(sequential)
    }
}

/// Exit status of a failed command, by the kind of its error: 2 for a
/// usage error (a value out of its range, an unknown name, options that do
/// not fit together: [`crate::ErrorKind::InvalidParameter`], as clap's own
/// usage errors), 1 for a failure while running (input or output, a series
/// that cannot be analysed).
pub fn exit_status(e: &(dyn std::error::Error + 'static)) -> i32 {
    match e.downcast_ref::<crate::Error>() {
        Some(e)
            if matches!(
                e.kind,
                crate::ErrorKind::InvalidParameter | crate::ErrorKind::RestExceedsSites
            ) =>
        {
            2
        }
        _ => 1,
    }
}

/// Run a command's `body`; on an error print `binary: error` to stderr and
/// exit with [`exit_status`] (2 for a usage error, 1 otherwise). Every
/// binary's `main` is this call.
pub fn exit_on_error<E>(binary: &str, body: impl FnOnce() -> Result<(), E>)
where
    E: Into<Box<dyn std::error::Error>>,
{
    if let Err(e) = body() {
        let e: Box<dyn std::error::Error> = e.into();
        eprintln!("{binary}: {e}");
        std::process::exit(exit_status(e.as_ref()));
    }
}

/// The `main` of a binary whose work is the function `$body`: it runs it
/// through [`exit_on_error`] under the binary's name.
#[macro_export]
macro_rules! main_of {
    ($body:ident) => {
        fn main() {
            $crate::cli::exit_on_error(env!("CARGO_BIN_NAME"), $body);
        }
    };
}

impl PipeRules {
    /// Parse the rules; `help` prints the known names and exits.
    pub fn parse(&self) -> crate::Result<Rules> {
        if self.rules == "help" {
            for (name, what) in RULE_NAMES {
                println!("{name:14} {what}");
            }
            std::process::exit(0);
        }
        self.rules.parse()
    }

    /// Parse `--engine` (when absent: `fast` at the acceptance tier,
    /// `reference` at the others); the chart titles drawn from then on name
    /// it (`[reference engine]`, `[fast engine]`).
    pub fn engine(&self, tier: Tier) -> crate::Result<crate::pipe::Engine> {
        let default = if tier.is_acceptance() {
            "fast"
        } else {
            "reference"
        };
        let e: crate::pipe::Engine = self.engine.as_deref().unwrap_or(default).parse()?;
        crate::plot::set_caption_note(&format!("{e} engine"));
        Ok(e)
    }

    /// Start figure `binary` reproducing `paper` with these rules and the
    /// options `common`: the figure (its clock running), the parsed rules,
    /// the engine ([`PipeRules::engine`]) and `common`.
    pub fn start<'c>(
        &self,
        common: &'c Common,
        binary: &'static str,
        paper: &'static str,
    ) -> crate::Result<(Figure, Rules, crate::pipe::Engine, &'c Common)> {
        let rules = self.parse()?;
        let engine = self.engine(common.tier)?;
        let mut fig = Figure::start(binary, paper, common.tier, rules.to_string());
        fig.engine = engine.label();
        Ok((fig, rules, engine, common))
    }
}

/// The options of the PH95 wave figures (Figs. 2-5): the common ones,
/// `--rules` and `--p` (flatten into the figure's own `clap::Parser`).
#[derive(Debug, Clone, clap::Args)]
pub struct WaveOptions {
    /// `--tier`, `--seed`, `--runs`, `--out`, `--shard`, `--threads`.
    #[command(flatten)]
    pub common: Common,
    /// `--rules`.
    #[command(flatten)]
    pub rules: PipeRules,
    /// Dissipation p (the figure: 0.1); p = 0 is the wave-free control.
    #[arg(long, default_value_t = 0.1, allow_negative_numbers = true)]
    pub p: f64,
}

impl WaveOptions {
    /// Start figure `binary` reproducing `paper`: the figure (its clock
    /// running), the parsed `--rules`, the engine and the common options.
    pub fn start(
        &self,
        binary: &'static str,
        paper: &'static str,
    ) -> crate::Result<(Figure, Rules, crate::pipe::Engine, &Common)> {
        self.rules.start(&self.common, binary, paper)
    }

    /// The pipe of the PH95 wave figures, `length` rows in bins of `bin`
    /// rows, with `--p`: otherwise that of PH94 Fig. 1 (W = 11, rho = 1,
    /// g = b = 0.5, periodic; [`fig1_pipe`]); validated, with at least two
    /// bins ([`check_two_bins`]).
    pub fn pipe(&self, length: usize, bin: usize) -> crate::Result<Params> {
        let params = Params {
            length,
            bin,
            p: self.p,
            ..fig1_pipe()
        };
        params.validate()?;
        check_two_bins(length, bin)?;
        Ok(params)
    }
}

impl Common {
    /// `--threads` if given (1..=[`MAX_THREADS`], checked when parsed), else all cores.
    pub fn thread_count(&self) -> usize {
        self.threads.unwrap_or_else(crate::run::threads)
    }

    /// For figures that keep all their runs in one process: a `--shard` is
    /// an error (never silently ignored).
    pub fn reject_shard(&self, binary: &str) -> crate::Result<()> {
        match self.shard {
            Some(s) => Err(crate::Error::new(
                crate::ErrorKind::InvalidParameter,
                format!("{binary} does not support --shard (got {s}); run it without --shard"),
            )),
            None => Ok(()),
        }
    }

    /// `--runs` if given (1..=[`MAX_RUNS`], checked when parsed), else the
    /// tier's default.
    pub fn runs_or(&self, quick: usize, standard: usize, paper: usize) -> usize {
        self.runs.unwrap_or(self.tier.pick(quick, standard, paper))
    }

    /// [`Common::runs_or`] for a figure with an acceptance design: at the
    /// acceptance tier the run count of its power analysis
    /// ([`crate::drivers::acceptance`]), otherwise the tier's default.
    pub fn runs_for(
        &self,
        quick: usize,
        standard: usize,
        paper: usize,
        acceptance: usize,
    ) -> usize {
        match (self.runs, self.tier) {
            (Some(n), _) => n,
            (None, Tier::Acceptance) => acceptance,
            (None, t) => t.pick(quick, standard, paper),
        }
    }

    /// The ensemble runner of a figure (`crate::ensemble`): `runs` runs of the
    /// configuration `key` (tier, parameters, rules: everything that changes a
    /// run's result) with `--seed`, `--shard` and `--threads` applied, saving
    /// each run under `OUT/<binary>/runs/`.
    pub fn ensemble(
        &self,
        binary: &str,
        key: &serde_json::Value,
        runs: usize,
    ) -> crate::Result<Ensemble> {
        let key = serde_json::json!({"tier": self.tier, "config": key});
        let e = Ensemble::new(&self.out, binary, &key, self.seed, runs, self.shard)?;
        Ok(match self.threads {
            Some(n) => e.threads(n),
            None => e,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    /// The engine named by `--engine` reaches every chart title (a PNG from
    /// the fast engine must not look like one from the reference).
    #[test]
    fn the_caption_note_names_the_engine() {
        let args = PipeRules {
            rules: "default".to_string(),
            engine: Some("fast".to_string()),
        };
        args.engine(crate::run::Tier::Quick).unwrap();
        assert_eq!(
            crate::plot::captioned("PH95 Fig. 12"),
            "PH95 Fig. 12 [fast engine]"
        );
        crate::plot::set_caption_note("");
        assert_eq!(crate::plot::captioned("PH95 Fig. 12"), "PH95 Fig. 12");
    }

    fn parse(args: &[&str]) -> std::result::Result<PipeArgs, String> {
        PipeArgs::try_parse_from(std::iter::once("fig").chain(args.iter().copied()))
            .map_err(|e| e.to_string())
    }

    #[test]
    fn runs_and_threads_out_of_range_are_errors_naming_the_option() {
        for bad in [
            "0",
            "100001",
            "18446744073709551615",
            "99999999999999999999",
            "-1",
        ] {
            let e = parse(&["--runs", bad]).unwrap_err();
            assert!(e.contains("--runs") && e.contains("1..=100000"), "{e}");
        }
        for bad in ["0", "1025", "-2"] {
            let e = parse(&["--threads", bad]).unwrap_err();
            assert!(e.contains("--threads") && e.contains("1..=1024"), "{e}");
        }
        let a = parse(&["--runs", "100000", "--threads", "1"]).unwrap();
        assert_eq!(a.common.runs_or(1, 1, 1), 100000);
        assert_eq!(a.common.thread_count(), 1);
        assert_eq!(parse(&[]).unwrap().common.runs_or(3, 4, 5), 3);
    }

    #[test]
    fn duplicates_and_one_bin_pipes_are_errors_naming_the_value() {
        let e = reject_duplicates("--lengths", &[128, 256, 128]).unwrap_err();
        assert!(e.message.contains("--lengths: 128"), "{}", e.message);
        assert!(reject_duplicates("--lengths", &[128, 256]).is_ok());
        let e = check_two_bins(8, 8).unwrap_err();
        assert!(e.message.contains("L = 8") && e.message.contains("[16, inf)"));
        assert!(check_two_bins(16, 8).is_ok());
        let opts = WaveOptions {
            common: parse(&[]).unwrap().common,
            rules: PipeRules {
                rules: "default".into(),
                engine: None,
            },
            p: 0.1,
        };
        assert!(opts.pipe(8, 8).is_err() && opts.pipe(16, 8).is_ok());
    }

    #[test]
    fn negative_numbers_reach_the_range_check() {
        #[derive(clap::Parser)]
        struct Fig {
            #[command(flatten)]
            wave: WaveOptions,
        }
        let f = Fig::try_parse_from(["fig", "--p", "-0.1"]).unwrap();
        let e = f.wave.pipe(16, 8).unwrap_err();
        assert!(e.message.contains("p = -0.1"), "{}", e.message);
    }
}
