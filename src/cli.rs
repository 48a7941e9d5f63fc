//! Command-line options shared by every figure binary (the output contract
//! of the README, "Figure binaries"): `--tier`, `--seed`, `--runs`, `--rules`, `--out`; and
//! those of the PH95 wave figures (Figs. 2-5), with `--p`.
//!
//! A pipe figure whose options are just these parses them with
//! [`PipeArgs::parse_about`]; one with options of its own flattens
//! [`PipeArgs`] into its `clap::Parser`.

use crate::ensemble::{Ensemble, Shard};
use crate::pipe::record::fig1_pipe;
use crate::pipe::rules::RULE_NAMES;
use crate::pipe::{Params, Rules};
use crate::run::{Figure, Tier};
use std::path::PathBuf;

/// Options every figure binary takes (flatten into its own `clap::Parser`).
#[derive(Debug, Clone, clap::Args)]
pub struct Common {
    /// How much to compute: quick (seconds), standard (minutes), paper (published sizes).
    #[arg(long, value_enum, default_value_t = Tier::Quick)]
    pub tier: Tier,
    /// Base seed; run i of an ensemble uses derive_seed(seed, i).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Number of independent runs to average (default: set by the tier).
    #[arg(long)]
    pub runs: Option<usize>,
    /// Output folder; the figure writes into `OUT/<binary>/`.
    #[arg(long, default_value = "results")]
    pub out: PathBuf,
    /// Run only shard i of n (runs r with r mod n = i, 0 <= i < n), e.g.
    /// `--shard $SLURM_ARRAY_TASK_ID/8`; combine the shards' --out folders
    /// with the `merge` binary, then rerun without --shard to analyse.
    #[arg(long)]
    pub shard: Option<Shard>,
    /// Worker threads (default: all cores); results do not depend on it.
    #[arg(long)]
    pub threads: Option<usize>,
}

/// The `--rules` option of the pipe figures.
#[derive(Debug, Clone, clap::Args)]
pub struct PipeRules {
    /// Rule reading: names joined by '+', e.g. ph94, any-mover, ph94+wall-drag,
    /// any-mover+gravity-first+rest-up ('--rules help' lists them).
    #[arg(long, default_value = "default")]
    pub rules: String,
}

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

    /// Start figure `binary` reproducing `paper` with these rules and the
    /// options `common`: the figure (its clock running), the parsed rules,
    /// and `common`.
    pub fn start<'c>(
        &self,
        common: &'c Common,
        binary: &'static str,
        paper: &'static str,
    ) -> crate::Result<(Figure, Rules, &'c Common)> {
        let rules = self.parse()?;
        let fig = Figure::start(binary, paper, common.tier, rules.to_string());
        Ok((fig, rules, common))
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
    #[arg(long, default_value_t = 0.1)]
    pub p: f64,
}

impl WaveOptions {
    /// Start figure `binary` reproducing `paper`: the figure (its clock
    /// running), the parsed `--rules`, and the common options.
    pub fn start(
        &self,
        binary: &'static str,
        paper: &'static str,
    ) -> crate::Result<(Figure, Rules, &Common)> {
        self.rules.start(&self.common, binary, paper)
    }

    /// The pipe of the PH95 wave figures, `length` rows in bins of `bin`
    /// rows, with `--p`: otherwise that of PH94 Fig. 1 (W = 11, rho = 1,
    /// g = b = 0.5, periodic; [`fig1_pipe`]); validated.
    pub fn pipe(&self, length: usize, bin: usize) -> crate::Result<Params> {
        let params = Params {
            length,
            bin,
            p: self.p,
            ..fig1_pipe()
        };
        params.validate()?;
        Ok(params)
    }
}

impl Common {
    /// `--threads` if given, else all cores.
    pub fn thread_count(&self) -> usize {
        self.threads.unwrap_or_else(crate::run::threads).max(1)
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

    /// `--runs` if given, else the tier's default; at least 1.
    pub fn runs_or(&self, quick: usize, standard: usize, paper: usize) -> usize {
        self.runs
            .unwrap_or(self.tier.pick(quick, standard, paper))
            .max(1)
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
