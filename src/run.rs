//! Run plumbing shared by every figure binary: tiers, seeds, ensembles of
//! independent runs over all cores, progress bars, and the output contract
//! (`DIR/<binary>/` with PNGs, CSVs and `summary.json`).

use crate::analysis::grading::{grade, Claim, Estimate, Kind, Verdict, MIN_RUNS};
use crate::error::{Error, ErrorKind, Result};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// How much a figure computes: `quick` (seconds, for tests), `standard`
/// (minutes), `paper` (the published sizes) or `acceptance` (the published
/// sizes on the validated fast engine, with the acceptance estimators and
/// run counts of [`crate::drivers::acceptance`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Tier {
    /// Seconds: small lattices, short runs; what the tests use.
    Quick,
    /// Minutes: between quick and paper.
    Standard,
    /// The sizes and lengths of the published figure.
    Paper,
    /// The published sizes and lengths, as `paper`, graded for acceptance:
    /// the pipe on the fast engine unless `--engine` says otherwise, the
    /// estimators and margins fixed in `drivers::acceptance` before
    /// measuring, and run counts chosen from a pilot's power analysis.
    Acceptance,
}

impl Tier {
    /// Lower-case name as used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Tier::Quick => "quick",
            Tier::Standard => "standard",
            Tier::Paper => "paper",
            Tier::Acceptance => "acceptance",
        }
    }

    /// Pick one of three values by tier; `acceptance` takes the paper's
    /// value (it runs the published set-ups).
    pub fn pick<T>(self, quick: T, standard: T, paper: T) -> T {
        match self {
            Tier::Quick => quick,
            Tier::Standard => standard,
            Tier::Paper | Tier::Acceptance => paper,
        }
    }

    /// Whether this is the acceptance tier.
    pub fn is_acceptance(self) -> bool {
        self == Tier::Acceptance
    }
}

/// The seed of run `index` of an ensemble with base seed `base`
/// (SplitMix64 of the pair), so runs are independent and reproducible.
pub fn derive_seed(base: u64, index: u64) -> u64 {
    let mut z = base
        .wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(index.wrapping_add(1).wrapping_mul(0xD1B5_4A32_D192_ED03));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seeds of runs 0..`runs` of an ensemble with base seed `base`
/// ([`derive_seed`] of each index).
pub fn run_seeds(base: u64, runs: usize) -> Vec<u64> {
    (0..runs as u64).map(|i| derive_seed(base, i)).collect()
}

/// Number of worker threads: all available cores.
pub fn threads() -> usize {
    std::thread::available_parallelism()
        .map(|n| n.get())
        .unwrap_or(1)
}

/// Run `f(index)` for `index in 0..n` on all cores and return the results in
/// index order. Each run must be a pure function of its index (derive its seed
/// with [`derive_seed`]); the result is then independent of the thread count.
pub fn ensemble<T, F>(n: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync,
{
    ensemble_with_threads(n, threads(), f)
}

/// [`ensemble`] with an explicit thread count (for tests of determinism).
pub fn ensemble_with_threads<T, F>(n: usize, threads: usize, f: F) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync,
{
    ensemble_until(n, threads, f, |_| false)
}

/// [`ensemble_with_threads`] for a sequential decision: the results in
/// index order up to and including the first for which `decides` holds
/// (all `n` when none does). Runs after that index are not started; every
/// run before it is computed, so the result does not depend on `threads`.
pub fn ensemble_until<T, F, D>(n: usize, threads: usize, f: F, decides: D) -> Vec<T>
where
    T: Send,
    F: Fn(usize) -> T + Sync,
    D: Fn(&T) -> bool + Sync,
{
    let next = AtomicUsize::new(0);
    let decided_at = AtomicUsize::new(usize::MAX);
    let slots: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1).min(n.max(1)) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= n || i > decided_at.load(Ordering::SeqCst) {
                    break;
                }
                let r = f(i);
                if decides(&r) {
                    decided_at.fetch_min(i, Ordering::SeqCst);
                }
                slots.lock().expect("a worker panicked")[i] = Some(r);
            });
        }
    });
    let last = decided_at.into_inner().min(n.saturating_sub(1));
    slots
        .into_inner()
        .expect("a worker panicked")
        .into_iter()
        .take(if n == 0 { 0 } else { last + 1 })
        .map(|r| r.expect("every run up to the decision finished"))
        .collect()
}

/// A progress bar on stderr with the house style (hidden when `len == 0`).
pub fn progress(len: u64, what: &str) -> ProgressBar {
    let pb = ProgressBar::new(len);
    pb.set_style(
        ProgressStyle::with_template(
            "{msg:>14} [{elapsed_precise}] {wide_bar} {pos}/{len} (eta {eta})",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    pb.set_message(what.to_string());
    pb
}

/// One graded check of a figure (docs/reference/outputs.md, summary.json): a
/// statistic measured over `runs` independent runs, the claim it is graded
/// against by the one rule of [`crate::analysis::grading`], and the verdict.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    /// Name of the check (e.g. `alpha`).
    pub name: String,
    /// What the check compares against: `published`, `pinned` or `identity`.
    pub kind: Kind,
    /// The measured value (mean over runs).
    pub measured: f64,
    /// One standard error of the measured value (spread over runs; NaN when
    /// there are fewer than two runs).
    pub error: f64,
    /// Number of independent runs behind `measured` (0 for exact identities).
    pub runs: usize,
    /// The target value: the paper's (kind `published`) or this code's
    /// earlier measurement (kind `pinned`); `None` for threshold claims and
    /// blind figures.
    pub published: Option<f64>,
    /// Where the target comes from (paper, figure, section), or what the
    /// pinned value is (command, tier, seed).
    pub source: String,
    /// The test: `within` (equivalence with a margin), `above` or `below` a
    /// threshold; `None` for identities and blind checks.
    pub claim: Option<Claim>,
    /// The margin Delta of a `within` claim or the threshold of an
    /// `above`/`below` claim, fixed before measuring.
    pub tolerance: Option<f64>,
    /// The grade: reproduced, not-reproduced or undecided.
    pub verdict: Verdict,
    /// `verdict == reproduced`.
    pub pass: bool,
    /// What is measured and why the margin; for a failing published check,
    /// the known discrepancy.
    pub note: String,
    /// Where the claim goes on the figure's chart ([`Drawn`]); not written
    /// to summary.json.
    #[serde(skip)]
    pub drawn: Option<Drawn>,
    /// Where a sequentially graded check stopped (the acceptance tier's default design); absent
    /// for a fixed count.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sequential: Option<Sequential>,
    /// The labels of the sweep points the check is computed from (empty:
    /// not known, so a sequential sweep keeps every point running while the
    /// check is open); not written to summary.json.
    #[serde(skip)]
    pub points: Vec<String>,
}

/// Where a sequentially graded check stopped
/// ([`crate::analysis::sequential`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sequential {
    /// The error-spending rule.
    pub spending: &'static str,
    /// The runs at each look of the design.
    pub looks: Vec<usize>,
    /// The chance of each kind of wrong verdict over all looks, at most.
    pub alpha: f64,
    /// The look it stopped at, counted from 1.
    pub look: usize,
    /// The runs at that look.
    pub runs: usize,
    /// The boundary k at that look.
    pub boundary: f64,
}

/// What a published claim about plotted points looks like on a chart: a band
/// of the values it allows at one point, or a statement in the legend.
#[derive(Debug, Clone, PartialEq)]
pub enum Drawn {
    /// The claim allows `quantity` (`alpha` or `v`) in `lo..=hi` at the
    /// point labelled `point`; `label` names the claim in the legend.
    Band {
        /// The plotted quantity's name.
        quantity: &'static str,
        /// The point's label (e.g. `p0.05`).
        point: String,
        /// The lowest value the claim allows.
        lo: f64,
        /// The highest value the claim allows.
        hi: f64,
        /// The legend's words for the claim.
        label: String,
    },
    /// A claim without a number about `quantity` at `points` (all of them
    /// must be on the chart), stated in the legend as `label`.
    Note {
        /// The plotted quantity's name.
        quantity: &'static str,
        /// The labels of the points the claim compares.
        points: Vec<String>,
        /// The legend's words for the claim.
        label: String,
    },
}

impl Drawn {
    /// The quantity the claim is about.
    pub fn quantity(&self) -> &'static str {
        match self {
            Drawn::Band { quantity, .. } | Drawn::Note { quantity, .. } => quantity,
        }
    }

    /// The legend's words.
    pub fn label(&self) -> &str {
        match self {
            Drawn::Band { label, .. } | Drawn::Note { label, .. } => label,
        }
    }
}

impl Check {
    /// A check of `est` against `claim` by the one grading rule.
    pub fn graded(
        name: &str,
        kind: Kind,
        source: &str,
        est: Estimate,
        claim: Claim,
        note: &str,
    ) -> Self {
        let verdict = grade(est, claim);
        let (published, tolerance) = match claim {
            Claim::Within { target, margin } => (Some(target), margin),
            Claim::Above { threshold } | Claim::Below { threshold } => (None, threshold),
        };
        let mut note = note.to_string();
        if est.n < MIN_RUNS {
            note.push_str(&format!(
                "; UNDECIDED: {} run(s), at least {MIN_RUNS} are needed to grade",
                est.n
            ));
        }
        Check {
            name: name.to_string(),
            kind,
            measured: est.mean,
            error: est.se,
            runs: est.n,
            published,
            source: source.to_string(),
            claim: Some(claim),
            tolerance: Some(tolerance),
            verdict,
            pass: verdict == Verdict::Reproduced,
            note,
            drawn: None,
            sequential: None,
            points: Vec::new(),
        }
    }

    /// This check, graded by `design` and stopped at `stop`.
    pub fn stopped(
        mut self,
        design: &crate::analysis::sequential::Design,
        stop: &crate::analysis::sequential::Stop,
    ) -> Self {
        self.sequential = Some(Sequential {
            spending: design.spending.name(),
            looks: design.looks.clone(),
            alpha: design.alpha,
            look: stop.look + 1,
            runs: stop.runs,
            boundary: stop.boundary,
        });
        self
    }

    /// This check, computed from the sweep points labelled `points`.
    pub fn on_points(mut self, points: Vec<String>) -> Self {
        self.points = points;
        self
    }

    /// This check graded again by the one rule with coverage factor `k` (a
    /// look of a sequential design); a check without a claim is unchanged.
    pub fn regraded(mut self, k: f64) -> Self {
        if let Some(claim) = self.claim {
            let est = Estimate::new(self.measured, self.error, self.runs);
            self.verdict = crate::analysis::grading::grade_with(est, claim, k);
            self.pass = self.verdict == Verdict::Reproduced;
        }
        self
    }

    /// This check, drawn on its figure's chart as `drawn`.
    pub fn drawn(mut self, drawn: Drawn) -> Self {
        self.drawn = Some(drawn);
        self
    }

    /// A check against the paper (`source` names paper and figure).
    pub fn published(name: &str, source: &str, est: Estimate, claim: Claim, note: &str) -> Self {
        Check::graded(name, Kind::Published, source, est, claim, note)
    }

    /// A regression guard against this code's own earlier measurement
    /// (`source` says which), never a validation.
    pub fn pinned(name: &str, source: &str, est: Estimate, claim: Claim, note: &str) -> Self {
        Check::graded(name, Kind::Pinned, source, est, claim, note)
    }

    /// An exact identity of the model (e.g. conservation): `measured` is the
    /// violation or the quantity, `holds` whether the identity holds.
    pub fn identity(name: &str, measured: f64, holds: bool, note: &str) -> Self {
        Check::exact(name, Kind::Identity, "", measured, holds, note)
    }

    /// A claim about every one of the runs made (a count, not an estimate:
    /// e.g. "no run at rho <= 1 leaves the model's validity"), which holds or
    /// not without statistical error.
    pub fn exact(
        name: &str,
        kind: Kind,
        source: &str,
        measured: f64,
        holds: bool,
        note: &str,
    ) -> Self {
        let verdict = Verdict::of(holds);
        Check {
            name: name.to_string(),
            kind,
            measured,
            error: 0.0,
            runs: 0,
            published: None,
            source: source.to_string(),
            claim: None,
            tolerance: None,
            verdict,
            pass: holds,
            note: note.to_string(),
            drawn: None,
            sequential: None,
            points: Vec::new(),
        }
    }

    /// A check whose verdict was reached by the grading rule elsewhere (e.g.
    /// a claim of the reproduction matrix, `crate::drivers::claims`).
    #[allow(clippy::too_many_arguments)]
    pub fn with_verdict(
        name: &str,
        kind: Kind,
        source: &str,
        measured: f64,
        error: f64,
        runs: usize,
        verdict: Verdict,
        note: &str,
    ) -> Self {
        let mut c = Check::exact(
            name,
            kind,
            source,
            measured,
            verdict == Verdict::Reproduced,
            note,
        );
        c.error = error;
        c.runs = runs;
        c.verdict = verdict;
        c
    }

    /// A significance test whose `statistic` already carries the noise of
    /// the `runs` runs (e.g. a Student t of a trend against its critical
    /// value, stated in `note` with its false-alarm rate): `holds` is the
    /// test's outcome, graded undecided with fewer than [`MIN_RUNS`] runs.
    pub fn test(
        name: &str,
        kind: Kind,
        source: &str,
        statistic: f64,
        runs: usize,
        holds: bool,
        note: &str,
    ) -> Self {
        let mut c = Check::exact(name, kind, source, statistic, holds, note);
        c.runs = runs;
        if runs < MIN_RUNS {
            c.verdict = Verdict::Undecided;
            c.pass = false;
            c.note.push_str(&format!(
                "; UNDECIDED: {runs} run(s), at least {MIN_RUNS} are needed to grade"
            ));
        }
        c
    }

    /// A published claim whose value is withheld (a blind figure): measured
    /// and reported, graded `undecided` until the comparison is made.
    pub fn blind(name: &str, source: &str, est: Estimate, note: &str) -> Self {
        Check {
            name: name.to_string(),
            kind: Kind::Published,
            measured: est.mean,
            error: est.se,
            runs: est.n,
            published: None,
            source: source.to_string(),
            claim: None,
            tolerance: None,
            verdict: Verdict::Undecided,
            pass: false,
            note: format!("BLIND (published value withheld): {note}"),
            drawn: None,
            sequential: None,
            points: Vec::new(),
        }
    }

    /// The same check with the paper's value of the quantity in
    /// `published` (for a threshold or test claim whose published value is
    /// a number, e.g. T_c = 880 of PH95 Fig. 11).
    pub fn with_published(mut self, value: f64) -> Self {
        self.published = Some(value);
        self
    }

    /// The measured value and its standard error as text: `m +- e`, or
    /// `no value` when there is none (e.g. no valid run), never `NaN`.
    pub fn value_text(&self) -> String {
        if self.measured.is_finite() && self.runs == 1 {
            // one run has no spread: its error bar is not 0, it is unknown
            format!("{:.4} (no standard error: one run)", self.measured)
        } else if self.measured.is_finite() && self.error.is_finite() {
            format!("{:.4} +- {:.4}", self.measured, self.error)
        } else if self.measured.is_finite() {
            format!("{:.4} (no standard error)", self.measured)
        } else {
            "no value".to_string()
        }
    }

    /// One line for the terminal.
    pub fn line(&self) -> String {
        let target = match (self.claim, self.published) {
            (Some(Claim::Within { target, margin }), _) => format!("{target:.4} +- {margin:.4}"),
            (Some(Claim::Above { threshold }), _) => format!("> {threshold:.4}"),
            (Some(Claim::Below { threshold }), _) => format!("< {threshold:.4}"),
            (None, Some(p)) => format!("{p:.4}"),
            // no number to compare: the claim is the one its source states
            (None, None) => format!("as stated in \"{}\":", self.source),
        };
        format!(
            "[{}] {} ({}): measured {} ({} runs), claim {} {}",
            match self.verdict {
                Verdict::Reproduced => "PASS",
                Verdict::NotReproduced => "FAIL",
                Verdict::Undecided => "UNDECIDED",
            },
            self.name,
            self.kind.name(),
            self.value_text(),
            self.runs,
            target,
            self.note
        )
    }
}

/// Append `reason` to the note of every failing check: a published value the
/// reading does not reproduce is a known discrepancy, reported, never hidden.
pub fn mark_discrepancies(checks: &mut [Check], reason: &str) {
    for c in checks
        .iter_mut()
        .filter(|c| c.kind == Kind::Published && c.verdict == Verdict::NotReproduced)
    {
        c.note.push_str("; NOT REPRODUCED: ");
        c.note.push_str(reason);
    }
}

/// The `summary.json` of a figure binary (README, "Figure binaries": the output contract).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// Binary name, e.g. `fig1`.
    pub figure: String,
    /// Paper and figure, e.g. `PH94 Fig. 1`.
    pub paper: String,
    /// Tier the figure ran at.
    pub tier: Tier,
    /// Seeds of the runs.
    pub seeds: Vec<u64>,
    /// Parameters as given to the model(s).
    pub params: serde_json::Value,
    /// Rule variant(s) used, as printed by the model.
    pub rules: String,
    /// The engine that ran the model (`reference` or, for the pipe, `fast`),
    /// with its revision from revision 2 on (`Engine::label`).
    pub engine: String,
    /// Wall-clock time of this invocation of the figure (runs resumed from
    /// saved files cost nothing here; `site_updates` counts them).
    pub wall_seconds: f64,
    /// Total number of site updates (sites x steps) computed.
    pub site_updates: f64,
    /// Named numbers (metric names fixed per figure); finite only: a
    /// metric without a value is moved to `missing_metrics` when written.
    pub metrics: BTreeMap<String, f64>,
    /// Metrics that have no value (NaN or infinite, e.g. a mean over no
    /// qualifying run), each with the reason; never written as NaN/null.
    pub missing_metrics: BTreeMap<String, String>,
    /// Comparisons with published values.
    pub checks: Vec<Check>,
}

/// A figure binary from start to summary: created first thing in `main`,
/// it names the output folder and fills in the fixed fields of the
/// [`Summary`] (figure, paper, tier, rules, and the wall-clock time since
/// its creation).
#[derive(Debug, Clone)]
pub struct Figure {
    /// Binary name, e.g. `waves-fig2`; also its output folder.
    pub binary: &'static str,
    /// Paper and figure, e.g. `PH95 Fig. 2`.
    pub paper: &'static str,
    /// Tier the figure runs at.
    pub tier: Tier,
    /// Rule variant(s), as printed by the model.
    pub rules: String,
    /// The engine that runs the model (`reference` unless `--engine` says
    /// otherwise).
    pub engine: String,
    /// Why a metric may have no value ([`Figure::explain_missing`]).
    missing: BTreeMap<String, String>,
    start: Instant,
}

impl Figure {
    /// Start the clock of figure `binary` reproducing `paper`.
    pub fn start(binary: &'static str, paper: &'static str, tier: Tier, rules: String) -> Self {
        Figure {
            binary,
            paper,
            tier,
            rules,
            engine: "reference".into(),
            missing: BTreeMap::new(),
            start: Instant::now(),
        }
    }

    /// State why metric `name` (and `name_err`) may have no value, e.g. "no
    /// run forms bands": if it is not finite when the summary is written, it
    /// is left out of `metrics` and listed in `missing_metrics` with this
    /// reason (otherwise with a generic one).
    pub fn explain_missing(mut self, name: &str, reason: &str) -> Self {
        self.missing.insert(name.to_string(), reason.to_string());
        self
    }

    /// Create (if needed) the output folder `out/<binary>/`.
    pub fn output(&self, out: &Path) -> Result<Output> {
        Output::new(out, self.binary)
    }

    /// Write `summary.json` into `out` with the results of the runs with
    /// `seeds` (see [`Output::finish`]).
    pub fn finish(
        &self,
        out: &Output,
        seeds: Vec<u64>,
        params: serde_json::Value,
        site_updates: f64,
        metrics: BTreeMap<String, f64>,
        checks: Vec<Check>,
    ) -> Result<()> {
        out.finish(&Summary {
            figure: self.binary.into(),
            paper: self.paper.into(),
            tier: self.tier,
            seeds,
            params,
            rules: self.rules.clone(),
            engine: self.engine.clone(),
            wall_seconds: self.start.elapsed().as_secs_f64(),
            site_updates,
            metrics,
            missing_metrics: self.missing.clone(),
            checks,
        })?;
        Ok(())
    }
}

/// Check one check of a written summary.json (`c`, as [`Check`] writes it)
/// the way the report reads it: every field of its type and range, its
/// claim consistent with `published` and `tolerance`, `pass` with
/// `verdict`, and the verdict the one rule's
/// ([`crate::analysis::grading`]) for its value, SE and runs, with the
/// boundary k of its `sequential` block where it has one. A check without
/// a claim (an identity, a composite) is checked for its fields and `pass`.
/// Fields of the older format (no `kind`, no `verdict`) may be missing.
/// Returns what is wrong, naming the field.
pub fn verify_check(c: &serde_json::Value) -> std::result::Result<(), String> {
    use serde_json::Value;
    let number = |field: &str| -> std::result::Result<f64, String> {
        match &c[field] {
            Value::Null => Ok(f64::NAN),
            Value::Number(x) => Ok(x.as_f64().unwrap_or(f64::NAN)),
            v => Err(format!("`{field}` is {v}, not a number or null")),
        }
    };
    let (measured, error) = (number("measured")?, number("error")?);
    let (published, tolerance) = (number("published")?, number("tolerance")?);
    if error < 0.0 {
        return Err(format!("`error` is {error}, not a standard error >= 0"));
    }
    let runs = match &c["runs"] {
        Value::Null => None,
        v => Some(
            v.as_u64()
                .ok_or_else(|| format!("`runs` is {v}, not a run count (a whole number >= 0)"))?,
        ),
    };
    let pass = match &c["pass"] {
        Value::Null => None,
        Value::Bool(b) => Some(*b),
        v => return Err(format!("`pass` is {v}, not true or false")),
    };
    let verdict = match &c["verdict"] {
        Value::Null => None,
        v => Some(serde_json::from_value::<Verdict>(v.clone()).map_err(|_| {
            format!("`verdict` is {v}, not one of reproduced, not-reproduced, undecided")
        })?),
    };
    if let (Some(p), Some(v)) = (pass, verdict) {
        if p != (v == Verdict::Reproduced) {
            return Err(format!(
                "`pass` is {p} but `verdict` is {}: pass is verdict == reproduced",
                v.status()
            ));
        }
    }
    let claim = match &c["claim"] {
        Value::Null => None,
        v => Some(
            serde_json::from_value::<Claim>(v.clone())
                .map_err(|e| format!("`claim` is {v}, not a claim ({e})"))?,
        ),
    };
    let same = |a: f64, b: f64| a == b || (a.is_nan() && b.is_nan());
    match claim {
        None => {}
        Some(Claim::Within { target, margin }) => {
            if !(target.is_finite() && margin.is_finite() && margin >= 0.0) {
                return Err(format!(
                    "`claim` has target {target} and margin {margin}: both finite, the margin >= 0"
                ));
            }
            // absent (null) in the older format; stated, they must agree
            let agrees = |stated: f64, x: f64| stated.is_nan() || same(stated, x);
            if !agrees(published, target) || !agrees(tolerance, margin) {
                return Err(format!(
                    "`published` {published} and `tolerance` {tolerance} are not the claim's target {target} and margin {margin}"
                ));
            }
        }
        Some(Claim::Above { threshold }) | Some(Claim::Below { threshold })
            if !threshold.is_finite() || !(tolerance.is_nan() || same(tolerance, threshold)) =>
        {
            return Err(format!(
                "`claim` has threshold {threshold} and `tolerance` {tolerance}: a finite threshold, the same in both"
            ));
        }
        Some(_) => {}
    }
    let k = match &c["sequential"] {
        Value::Null => None,
        Value::Object(q) => {
            let boundary = q.get("boundary").and_then(Value::as_f64);
            let look = q.get("look").and_then(Value::as_u64);
            let looks: Option<Vec<u64>> = q
                .get("looks")
                .and_then(Value::as_array)
                .and_then(|a| a.iter().map(Value::as_u64).collect());
            let at = q.get("runs").and_then(Value::as_u64);
            match (boundary, look, looks, at) {
                (Some(b), Some(j), Some(ls), Some(n))
                    if b.is_finite()
                        && b > 0.0
                        && j >= 1
                        && ls.get(j as usize - 1).is_some_and(|&at| n <= at)
                        && runs == Some(n) =>
                {
                    Some(b)
                }
                _ => {
                    return Err(format!(
                        "`sequential` is {}, not a design's stop: a boundary k > 0, a look j >= 1 of `looks`, and `runs` (at most the look's, fewer where runs were invalid) the check's runs",
                        Value::Object(q.clone())
                    ))
                }
            }
        }
        v => return Err(format!("`sequential` is {v}, not a design's stop")),
    };
    if let (Some(claim), Some(stated)) = (claim, verdict) {
        let est = Estimate::new(measured, error, runs.unwrap_or(0) as usize);
        let rule = match k {
            Some(k) => crate::analysis::grading::grade_with(est, claim, k),
            None => grade(est, claim),
        };
        if rule != stated {
            return Err(format!(
                "`verdict` is {} but the one rule gives {} for {measured} +- {error} over {} runs ({})",
                stated.status(),
                rule.status(),
                runs.unwrap_or(0),
                claim.describe()
            ));
        }
    }
    Ok(())
}

/// The reason given for a metric without a value when the figure states none.
pub const NO_VALUE: &str =
    "no value: the measurement is not finite (NaN or infinite), e.g. a mean over no qualifying run";

/// The reason given for the standard error `name_err` of a metric `name`
/// that has a value: one value has no spread ([`mean_sem`]).
pub const NO_ERROR: &str =
    "no value: a standard error needs at least two values (e.g. --runs 1 gives one run)";

impl Summary {
    /// This summary with every non-finite metric moved to `missing_metrics`,
    /// with the reason stated for it in `missing_metrics`; for `name_err`
    /// otherwise [`NO_ERROR`] when `name` has a value, else the reason of
    /// `name`; else [`NO_VALUE`]. Reasons of metrics that do have a value
    /// are dropped.
    pub fn without_missing_metrics(&self) -> Summary {
        let mut s = self.clone();
        let reasons = std::mem::take(&mut s.missing_metrics);
        let metrics = s.metrics.clone();
        let reason = |k: &str| {
            let base = k.strip_suffix("_err");
            if let Some(r) = reasons.get(k) {
                format!("no value: {r}")
            } else if base.is_some_and(|b| metrics.get(b).is_some_and(|v| v.is_finite())) {
                NO_ERROR.to_string()
            } else {
                base.and_then(|b| reasons.get(b))
                    .map_or(NO_VALUE.to_string(), |r| format!("no value: {r}"))
            }
        };
        s.metrics.retain(|k, v| {
            if !v.is_finite() {
                s.missing_metrics.insert(k.clone(), reason(k));
            }
            v.is_finite()
        });
        s
    }
}

/// Metrics from `(name, value)` pairs.
pub fn metrics_of<S: Into<String>>(
    values: impl IntoIterator<Item = (S, f64)>,
) -> BTreeMap<String, f64> {
    values.into_iter().map(|(k, v)| (k.into(), v)).collect()
}

/// Metrics from `(name, (mean, standard error))` pairs: `name` holds the
/// mean and `name_err` the standard error.
pub fn stat_metrics<S: AsRef<str>>(
    stats: impl IntoIterator<Item = (S, (f64, f64))>,
) -> BTreeMap<String, f64> {
    stats
        .into_iter()
        .flat_map(|(k, (m, e))| {
            [
                (k.as_ref().to_string(), m),
                (format!("{}_err", k.as_ref()), e),
            ]
        })
        .collect()
}

/// The output folder of one figure binary: `DIR/<binary>/`. It remembers
/// the files it was asked for ([`Output::path`]), so that PNGs and CSVs
/// left by an earlier run of other options are named as stale.
#[derive(Debug, Clone)]
pub struct Output {
    dir: PathBuf,
    named: std::sync::Arc<std::sync::Mutex<std::collections::BTreeSet<String>>>,
}

/// What the papers publish about each figure, in a line: written under every
/// PNG the figure draws ([`Output::new`], [`crate::plot::set_published_note`]),
/// so that a picture is seen against the claims it is graded by.
pub const PUBLISHED: [(&str, &str); 15] = [
    ("fig1", "PH94 Fig. 1: density waves at p = 0.1 (a) and again once dissipation is back on (c); none at p = 0 (b) or with smooth walls, b = 0 (d)."),
    ("fig2", "PH94 Fig. 2: 1/f^alpha density noise with alpha = 1.33 +- 0.02 (fit 40 <= f <= 1000); spectral peak near f = 596, v = 0.40."),
    ("waves-fig2", "PH95 Fig. 2: density waves form from the random start."),
    ("waves-fig3", "PH95 Fig. 3: the contrast C (a) and the energy lost, E(0) - E(t) (b), rise from the start and then saturate."),
    ("waves-fig4", "PH95 Fig. 4, III B: a wave profile whose front is sharper than its back; its width grows about linearly with L."),
    ("waves-fig5", "PH95 Fig. 5, III C: bands travel at L = 512 with v = 0.36 +- 0.05 from the shift of maximal overlap, the same as from the spectral peak."),
    ("waves-fig6", "PH95 Fig. 6, III D: alpha about 1.33 at p = 0.8."),
    ("waves-fig7", "PH95 Fig. 7, III E: white noise (alpha = 0) at p = 0 and at b = 0; at b = 0 a large peak at v = 1/2 exactly."),
    ("waves-fig8", "PH95 Fig. 8: alpha about constant for every p > 0 and above its value at p = 0; v does not change with p."),
    ("waves-fig9", "PH95 Fig. 9, III G: white noise (alpha = 0) for rho <= 0.8; alpha rises with rho above 1, to about 1.86 at rho = 2; v constant in rho."),
    ("waves-fig10", "PH95 Fig. 10, III H: alpha constant for any b > 0 and in g; v falls as b grows from 0.25 to 1, more at the smaller g, and the larger g is faster."),
    ("waves-fig11", "PH95 Fig. 11: the pipe at I = 0.5, g = 0.2 flows; C(R, T) peaks at T_c = 880 (v = 0.34)."),
    ("waves-fig12", "PH95 Fig. 12, III I: I_c = 0.52 for every pipe size; N(t) stationary below I_c and growing above it (clogs at I = 0.54); 1/f noise (alpha = 1) at I_c, white noise (alpha = 0) away from it."),
    ("hopper-fig2", "BB90 Figs. 1-2: the hopper empties through a central core of about constant width and lowered density between dense stagnant sides, under a V-shaped surface; beta = 0 is structureless (order 1/3); beta = 1 orders the fill over the container, vertically in the core, with defects."),
    ("hopper-fig3", "BB90 Fig. 3: the outflow has no trend and a flat power spectrum (white noise); similar with orientation off; the hopper empties."),
];

impl Output {
    /// Create (if needed) `out/<binary>/`, and write what the papers publish
    /// about figure `binary` ([`PUBLISHED`]) under every PNG drawn from now on.
    pub fn new(out: &Path, binary: &str) -> Result<Self> {
        let note = PUBLISHED.iter().find(|(b, _)| *b == binary);
        crate::plot::set_published_note(note.map_or("", |(_, n)| n));
        let dir = out.join(binary);
        fs::create_dir_all(&dir).map_err(|e| {
            Error::new(
                ErrorKind::Io,
                format!(
                    "cannot create output folder {}: {e}; choose another --out",
                    dir.display()
                ),
            )
        })?;
        Ok(Output {
            dir,
            named: Default::default(),
        })
    }

    /// Path of a file inside the output folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.named
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .insert(name.to_string());
        self.dir.join(name)
    }

    /// The PNG and CSV files in the folder that this run did not write:
    /// left by an earlier run (e.g. one without `--correlation-only`).
    pub fn stale_files(&self) -> Vec<String> {
        let named = self.named.lock().unwrap_or_else(|e| e.into_inner()).clone();
        let mut stale: Vec<String> = fs::read_dir(&self.dir)
            .into_iter()
            .flatten()
            .flatten()
            .filter(|e| e.path().is_file())
            .filter_map(|e| e.file_name().into_string().ok())
            .filter(|n| (n.ends_with(".png") || n.ends_with(".csv")) && !named.contains(n))
            .collect();
        stale.sort();
        stale
    }

    /// The output folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// Write a CSV file with a header line and rows of numbers; a value that
    /// is not finite (NaN: nothing to measure) is written as an empty cell.
    pub fn write_csv<S: AsRef<str>>(
        &self,
        name: &str,
        header: &[S],
        rows: &[Vec<f64>],
    ) -> Result<PathBuf> {
        let path = self.path(name);
        let mut s = String::new();
        let header: Vec<&str> = header.iter().map(AsRef::as_ref).collect();
        s.push_str(&header.join(","));
        s.push('\n');
        for r in rows {
            let line: Vec<String> = r
                .iter()
                .map(|v| {
                    if v.is_finite() {
                        format!("{v}")
                    } else {
                        String::new()
                    }
                })
                .collect();
            s.push_str(&line.join(","));
            s.push('\n');
        }
        write_atomic(&path, s.as_bytes())?;
        Ok(path)
    }

    /// Write a CSV file of one row per run: its seed, then `row(result)`,
    /// under `header` (which names the seed column too).
    pub fn write_runs<T>(
        &self,
        name: &str,
        header: &[&str],
        seeds: &[u64],
        results: &[T],
        row: impl Fn(&T) -> Vec<f64>,
    ) -> Result<PathBuf> {
        let rows: Vec<Vec<f64>> = results
            .iter()
            .zip(seeds)
            .map(|(r, &s)| std::iter::once(s as f64).chain(row(r)).collect())
            .collect();
        self.write_csv(name, header, &rows)
    }

    /// Write a CSV file of equally long `columns` under `header`.
    pub fn write_columns<S: AsRef<str>>(
        &self,
        name: &str,
        header: &[S],
        columns: &[&[f64]],
    ) -> Result<PathBuf> {
        let n = columns.first().map_or(0, |c| c.len());
        let rows: Vec<Vec<f64>> = (0..n)
            .map(|i| columns.iter().map(|c| c[i]).collect())
            .collect();
        self.write_csv(name, header, &rows)
    }

    /// Write `summary.json` and print one line per metric and per check on
    /// stdout; metrics without a value go to `missing_metrics`, never NaN
    /// or null ([`Summary::without_missing_metrics`]).
    pub fn finish(&self, summary: &Summary) -> Result<PathBuf> {
        let path = self.path("summary.json");
        let summary = &summary.without_missing_metrics();
        let serialise = |e: serde_json::Error| {
            Error::new(ErrorKind::Io, format!("cannot serialise summary: {e}"))
        };
        let mut value = serde_json::to_value(summary).map_err(serialise)?;
        let stale = self.stale_files();
        if let serde_json::Value::Object(fields) = &mut value {
            // files of an earlier run with other options: named, kept, and
            // left out of the report
            if !stale.is_empty() {
                fields.insert("stale_files".into(), stale.clone().into());
            }
            // CPU time of this invocation, all threads (like wall_seconds,
            // runs resumed from saved files cost nothing here); left out
            // when the system cannot tell it
            if let Some(cpu) = cpu_seconds() {
                fields.insert("cpu_seconds".into(), cpu.into());
            }
        }
        let text = serde_json::to_string_pretty(&value).map_err(serialise)?;
        write_atomic(&path, text.as_bytes())?;
        println!("wrote {}", self.dir.display());
        for (k, v) in &summary.metrics {
            println!("  {k} = {v:.6}");
        }
        for (k, why) in &summary.missing_metrics {
            println!("  {k}: {why}");
        }
        for c in &summary.checks {
            println!("{}", c.line());
        }
        if !stale.is_empty() {
            println!(
                "not written by this run, left from an earlier one (summary.json stale_files; the report leaves them out): {}",
                stale.join(", ")
            );
        }
        if !summary.tier.is_acceptance() {
            if let Some(line) = at_published_set_up(&summary.figure) {
                println!("{line}");
            }
        }
        Ok(path)
    }
}

/// Most steps any binary or plan accepts (a billion: hours per run at the
/// papers' sizes); the same cap everywhere (`cli::check_steps`, the
/// plans of the external contract).
pub const MAX_STEPS: u64 = 1_000_000_000;

/// Where the committed report lies (its report.json holds the verdicts at
/// the published set-ups).
const COMMITTED_REPORT: &str = "docs/report";

/// The line a run below the published set-up ends with: the committed
/// verdicts of figure `binary`'s published claims at the published set-up
/// (default reading; over the committed seed sets where it has them), where
/// they are recorded, and the command that recomputes them. `None` when the
/// committed report is not at hand (an installed binary) or has no claim
/// of the figure.
pub fn at_published_set_up(binary: &str) -> Option<String> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(COMMITTED_REPORT)
        .join("report.json");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).ok()?).ok()?;
    let rows: Vec<&serde_json::Value> = report["rows"]
        .as_array()?
        .iter()
        .filter(|r| r["binary"] == binary && r["kind"] == "published" && r["reading"].is_null())
        .collect();
    let verdict_of = |r: &serde_json::Value| {
        let at = if r["seed_sets"].is_object() {
            &r["seed_sets"]
        } else {
            r
        };
        at["verdict"]
            .as_str()
            .unwrap_or("undecided")
            .replace('-', " ")
    };
    let claims: Vec<String> = rows
        .iter()
        .map(|r| {
            let (at, n) = match r["seed_sets"].is_object() {
                true => (
                    &r["seed_sets"],
                    format!("{} seed sets", r["seed_sets"]["seeds"]),
                ),
                false => (*r, format!("{} runs", r["runs"])),
            };
            let value = match (at["measured"].as_f64(), at["error"].as_f64()) {
                (Some(m), Some(e)) => format!("{m:.4} +- {e:.4}"),
                (Some(m), None) => format!("{m:.4}"),
                _ => "no value".into(),
            };
            let verdict = verdict_of(r);
            format!(
                "{} {value} ({n}), {verdict}",
                r["name"].as_str().unwrap_or("?")
            )
        })
        .collect();
    if claims.is_empty() {
        return None;
    }
    let shown = if claims.len() <= 3 {
        claims.join("; ")
    } else {
        let count = |v: &str| rows.iter().filter(|r| verdict_of(r) == v).count();
        format!(
            "{} published claims, {} reproduced, {} not reproduced, {} undecided",
            claims.len(),
            count("reproduced"),
            count("not reproduced"),
            count("undecided")
        )
    };
    Some(format!(
        "at the published set-up (default reading): {shown} ({COMMITTED_REPORT}/REPORT.md); this tier is a smoke test, \
         `report --tier acceptance --only {binary} --seed-sets docs/acceptance` recomputes it"
    ))
}

/// CPU seconds this process has used so far, all threads together (the
/// `cpu_seconds` of summary.json; read by the `speed-accuracy` binary);
/// `None` where the system does not report it.
pub fn cpu_seconds() -> Option<f64> {
    cpu_time::ProcessTime::try_now()
        .ok()
        .map(|t| t.as_duration().as_secs_f64())
}

/// Write a file via a temporary name and a rename, so a crash never leaves a
/// half-written file behind.
/// Errors name `path` (e.g. a folder where the file should be), and leave
/// no temporary file behind.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = path.with_extension("tmp~");
    let cannot = |e: std::io::Error| {
        let _ = fs::remove_file(&tmp);
        let what = if path.is_dir() {
            format!("{e}: a folder is in the way; remove or rename it")
        } else {
            e.to_string()
        };
        Error::new(
            ErrorKind::Io,
            format!("cannot write {}: {what}", path.display()),
        )
    };
    let mut f = fs::File::create(&tmp).map_err(cannot)?;
    f.write_all(bytes).map_err(cannot)?;
    f.sync_all().ok();
    drop(f);
    fs::rename(&tmp, path).map_err(cannot)?;
    Ok(())
}

/// Characters Windows refuses in a file name, and that `cargo package`
/// refuses in a packaged path.
const NOT_PORTABLE: [char; 9] = ['<', '>', ':', '"', '/', '\\', '|', '?', '*'];

/// Names Windows reserves for devices, whatever the extension (`NUL.json`).
const RESERVED: [&str; 22] = [
    "CON", "PRN", "AUX", "NUL", "COM1", "COM2", "COM3", "COM4", "COM5", "COM6", "COM7", "COM8",
    "COM9", "LPT1", "LPT2", "LPT3", "LPT4", "LPT5", "LPT6", "LPT7", "LPT8", "LPT9",
];

/// `name` as a file name every system and `cargo package` accept: each
/// character Windows refuses (`< > : " / \ | ? *` and control characters)
/// becomes `_`, as do trailing dots and spaces; a reserved device name
/// (`CON`, `NUL`, `COM1`, ... with or without an extension) gets a leading
/// `_`; an empty name becomes `_`. A portable name is returned unchanged,
/// so rule readings (`default+lane-collide:0.1` ->
/// `default+lane-collide_0.1`) name their saved files the same way on
/// every system.
pub fn portable_file_name(name: &str) -> String {
    let mut out: String = name
        .chars()
        .map(|c| match NOT_PORTABLE.contains(&c) || c.is_control() {
            true => '_',
            false => c,
        })
        .collect();
    let kept = out.trim_end_matches(['.', ' ']).len();
    let trailing = out.len() - kept;
    out.truncate(kept);
    out.extend(std::iter::repeat_n('_', trailing));
    let stem = out.split('.').next().unwrap_or_default();
    if out.is_empty() || RESERVED.iter().any(|r| r.eq_ignore_ascii_case(stem)) {
        out.insert(0, '_');
    }
    out
}

/// Whether `name` is a file name every system accepts: it is its own
/// [`portable_file_name`].
pub fn is_portable_file_name(name: &str) -> bool {
    portable_file_name(name) == name
}

pub use crate::analysis::stats::mean_sem;

/// The difference a - b of two (value, standard error) pairs, with the
/// errors combined in quadrature.
pub fn difference((a, ea): (f64, f64), (b, eb): (f64, f64)) -> (f64, f64) {
    (a - b, (ea * ea + eb * eb).sqrt())
}

/// The median of `xs` (the mean of the middle two for an even count; NaN
/// when empty).
pub fn median(xs: &[f64]) -> f64 {
    let mut v = xs.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => v[n / 2],
        _ => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

/// [`mean_sem`] of `f` over `items` (e.g. one field of every run's result).
pub fn mean_sem_by<T>(items: &[T], f: impl Fn(&T) -> f64) -> (f64, f64) {
    mean_sem(&items.iter().map(f).collect::<Vec<_>>())
}

/// A per-run number with its name, e.g. `("amplitude", |r| r.shape.amplitude)`.
pub type NamedMeasure<T> = (&'static str, fn(&T) -> f64);

/// [`mean_sem`] of each named measure over `items`, with its name.
pub fn stats_by<T>(
    items: &[T],
    measures: &[NamedMeasure<T>],
) -> BTreeMap<&'static str, (f64, f64)> {
    measures
        .iter()
        .map(|&(name, f)| (name, mean_sem_by(items, f)))
        .collect()
}

/// [`mean_sem`] over the `series` at each index 0..len (e.g. each sample
/// time of every run): the mean curve and its standard errors (NaN where
/// there are no series).
pub fn mean_sem_at<V: AsRef<[f64]>>(series: &[V], len: usize) -> (Vec<f64>, Vec<f64>) {
    (0..len)
        .map(|t| mean_sem(&series.iter().map(|s| s.as_ref()[t]).collect::<Vec<_>>()))
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A written check is verified by the one rule: the check as written
    /// passes, each hand edit that breaks a type, a range or the verdict
    /// is named.
    #[test]
    fn written_checks_are_verified_by_the_one_rule() {
        let c = Check::published(
            "alpha",
            "PH94 Fig. 2",
            Estimate::new(1.30, 0.01, 128),
            Claim::Within {
                target: 1.33,
                margin: 0.059,
            },
            "",
        );
        let good = serde_json::to_value(&c).unwrap();
        assert_eq!(verify_check(&good), Ok(()));
        let edited = |f: &dyn Fn(&mut serde_json::Value)| {
            let mut v = good.clone();
            f(&mut v);
            verify_check(&v).unwrap_err()
        };
        let e = edited(&|v| {
            v["verdict"] = "not-reproduced".into();
            v["pass"] = false.into();
        });
        assert!(e.contains("the one rule gives reproduced"), "{e}");
        let e = edited(&|v| v["measured"] = 1.20.into());
        assert!(e.contains("gives not-reproduced"), "{e}");
        assert!(edited(&|v| v["pass"] = false.into()).contains("`pass`"));
        assert!(edited(&|v| v["runs"] = (-3).into()).contains("`runs`"));
        assert!(edited(&|v| v["error"] = (-0.1).into()).contains("`error`"));
        assert!(edited(&|v| v["tolerance"] = 0.5.into()).contains("`tolerance`"));
        assert!(edited(&|v| v["claim"]["margin"] = (-1.0).into()).contains("margin"));
        assert!(edited(&|v| v["sequential"] = 3.into()).contains("`sequential`"));
        // a sequential stop grades with its own boundary: k = 4 leaves
        // 1.30 +- 0.01 undecided (0.03 + 0.04 > 0.059)
        let mut seq = good.clone();
        seq["sequential"] = serde_json::json!({"spending": "obrien-fleming", "looks": [16, 128],
            "alpha": 0.025, "look": 2, "runs": 128, "boundary": 4.0});
        assert!(verify_check(&seq).unwrap_err().contains("gives undecided"));
        seq["verdict"] = "undecided".into();
        seq["pass"] = false.into();
        assert_eq!(verify_check(&seq), Ok(()));
    }

    #[test]
    fn a_portable_file_name_replaces_what_windows_refuses() {
        let p = portable_file_name;
        assert_eq!(
            p("ph94+inject-late+lane-collide:0.001.standard-seed1.json"),
            "ph94+inject-late+lane-collide_0.001.standard-seed1.json"
        );
        assert_eq!(p(r#"a<b>c:d"e/f\g|h?i*j"#), "a_b_c_d_e_f_g_h_i_j");
        assert_eq!(p("tab\there\n"), "tab_here_");
        assert_eq!(p("ends with dots.."), "ends with dots__");
        assert_eq!(p("ends with a space "), "ends with a space_");
        assert_eq!(p("."), "_");
        assert_eq!(p(""), "_");
        for reserved in ["CON", "nul", "Aux.json", "com1.tar.gz", "LPT9"] {
            assert_eq!(p(reserved), format!("_{reserved}"), "{reserved}");
        }
        // names that only look reserved are kept
        for kept in [
            "CONSOLE",
            "null.json",
            "com10",
            "my-nul",
            "a.con",
            "fig2.png",
        ] {
            assert_eq!(p(kept), kept);
            assert!(is_portable_file_name(kept));
        }
        assert!(!is_portable_file_name("lane-collide:0.1"));
        // the portable name is portable, and kept as it is
        for name in ["a:b.", "NUL", "x?*", " . "] {
            let once = p(name);
            assert!(is_portable_file_name(&once), "{name} -> {once}");
        }
    }

    /// The prefix up to the first deciding run, at every thread count.
    #[test]
    fn ensemble_until_is_the_prefix_to_the_first_decision() {
        for threads in [1, 2, 5] {
            let v = ensemble_until(20, threads, |i| i * 10, |&x| x == 70 || x == 120);
            assert_eq!(v, (0..=7).map(|i| i * 10).collect::<Vec<_>>(), "{threads}");
            assert_eq!(
                ensemble_until(4, threads, |i| i, |_| false),
                vec![0, 1, 2, 3]
            );
            assert!(ensemble_until(0, threads, |i| i, |_| true).is_empty());
        }
    }

    #[test]
    fn ensemble_is_independent_of_thread_count() {
        let f = |i: usize| derive_seed(42, i as u64);
        let a = ensemble_with_threads(17, 1, f);
        let b = ensemble_with_threads(17, 3, f);
        assert_eq!(a, b);
        // seeds differ between runs
        let mut s = a.clone();
        s.sort();
        s.dedup();
        assert_eq!(s.len(), 17);
    }

    #[test]
    fn a_check_without_a_value_prints_no_nan() {
        let none = Check::published(
            "x",
            "test",
            Estimate::of(&[]),
            Claim::Within {
                target: 1.0,
                margin: 0.1,
            },
            "no valid run",
        );
        assert_eq!(none.verdict, Verdict::Undecided);
        assert!(!none.line().contains("NaN"), "{}", none.line());
        assert!(none.line().contains("no value (0 runs)"), "{}", none.line());
        let some = Check::published(
            "x",
            "test",
            Estimate::new(1.0, 0.01, 4),
            Claim::Within {
                target: 1.0,
                margin: 0.1,
            },
            "",
        );
        assert!(some.line().contains("1.0000 +- 0.0100 (4 runs)"));
        // a check graded elsewhere (pipe-matrix) has no number to print:
        // its line names the claim as its source states it
        let graded = Check::with_verdict(
            "default.x",
            Kind::Published,
            "PH94 Fig. 1b: no waves at p = 0",
            0.9,
            0.07,
            3,
            Verdict::Reproduced,
            "s_low = 0.9",
        );
        assert!(
            graded
                .line()
                .contains("claim as stated in \"PH94 Fig. 1b: no waves at p = 0\": s_low"),
            "{}",
            graded.line()
        );
    }

    #[test]
    fn metrics_and_summaries_of_runs() {
        let m = stat_metrics([("a", (1.0, 0.5))]);
        assert_eq!(m["a"], 1.0);
        assert_eq!(m["a_err"], 0.5);
        assert_eq!(metrics_of([("b", 2.0)])["b"], 2.0);
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 2.0, 3.0]), 2.5);
        assert!(median(&[]).is_nan());
        assert_eq!(difference((3.0, 3.0), (1.0, 4.0)), (2.0, 5.0));
        let (m, e) = mean_sem_at(&[vec![1.0, 2.0], vec![3.0, 2.0]], 2);
        assert_eq!(m, vec![2.0, 2.0]);
        assert_eq!(e, vec![1.0, 0.0]);
        let s = stats_by(&[1.0, 3.0], &[("x", |v: &f64| *v)]);
        assert_eq!(s["x"], (2.0, 1.0));
    }

    #[test]
    fn metrics_without_value_are_listed_with_a_reason_never_written_as_nan() {
        let dir = std::env::temp_dir().join(format!("ga-missing-{}", std::process::id()));
        let fig = Figure::start("t", "test", Tier::Quick, "r".into())
            .explain_missing("v_waves", "no run forms bands");
        let out = fig.output(&dir).unwrap();
        let (c, c_err) = mean_sem(&[2.0]);
        let metrics = metrics_of([
            ("a", 1.0),
            ("v_waves", f64::NAN),
            ("v_waves_err", f64::NAN),
            ("b", f64::INFINITY),
            ("c", c),
            ("c_err", c_err),
        ]);
        fig.finish(&out, vec![1], serde_json::json!({}), 0.0, metrics, vec![])
            .unwrap();
        let text = std::fs::read_to_string(out.path("summary.json")).unwrap();
        assert!(!text.contains("null"), "{text}");
        let s: serde_json::Value = serde_json::from_str(&text).unwrap();
        assert_eq!(s["metrics"], serde_json::json!({"a": 1.0, "c": 2.0}));
        let missing = &s["missing_metrics"];
        assert_eq!(missing["v_waves"], "no value: no run forms bands");
        assert_eq!(missing["v_waves_err"], "no value: no run forms bands");
        assert_eq!(missing["b"], NO_VALUE);
        // one value has a mean but no standard error (not 0)
        assert_eq!(missing["c_err"], NO_ERROR);
        out.write_csv("x.csv", &["a", "b"], &[vec![1.5, f64::NAN]])
            .unwrap();
        let csv = std::fs::read_to_string(out.path("x.csv")).unwrap();
        assert_eq!(csv, "a,b\n1.5,\n");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn mean_and_error() {
        let (m, e) = mean_sem(&[1.0, 2.0, 3.0]);
        assert!((m - 2.0).abs() < 1e-12);
        assert!((e - (1.0f64 / 3.0).sqrt()).abs() < 1e-12);
    }
}
