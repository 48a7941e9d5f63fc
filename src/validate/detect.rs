//! `validate --detect E`: the level-1 trials and level-2
//! runs that catch a rule probability off by the relative error E with
//! power 0.95, from the measured detection table (VALIDATION.md, "The
//! smallest detectable error"; EXPERIMENTS.md, "The smallest detectable
//! error of validate").
//!
//! The scaling: a probability q used as (1 + e) q shifts the frequency of
//! an outcome by about e q, and the statistics of both levels (binomial
//! counts at level 1, Welch's t of run means at level 2) grow as e sqrt(n)
//! for n trials or runs. So the power at (e, n) is the power at (e', n')
//! with e sqrt(n) = e' sqrt(n'). The table measured the power at two trial
//! counts (quick 4000, standard 20000) and several e; the constants below
//! are the smallest e sqrt(n) at which every knob was caught in at least
//! 19 of 20 validations.
//!
//! Level 1 sees p (R2, R3), R1's split, g and b; only level 2 sees the
//! injection rate I of the open pipe, so level 2's runs come from it.

use super::Level;
use crate::error::{Error, ErrorKind, Result};
use crate::run::Tier;

/// e sqrt(trials) of level 1 at power 0.95 for every knob of level 1: at
/// e sqrt(n) = 0.03 sqrt(20000) = 4.24 (standard tier, +3 %) p, p in R3
/// alone and R1's split were each caught 20 of 20 times, g and b already at
/// 2.83 (+2 %); below it, R3 alone at 3.16 (quick, +5 %) only 6 of 20, R1's
/// split 15 of 20. Measured 2026-12-04 to 2026-12-05 (EXPERIMENTS.md).
pub const LEVEL1_C: f64 = 4.25;

/// e sqrt(runs) of level 2 at power 0.95 for the injection rate, at the
/// scenes of the quick and of the standard tier: +3 % with 8 runs (quick)
/// caught 20 of 20 times, +1 % 8 of 20; +1 % with 16 runs (standard) 20 of
/// 20 (an upper bound). Measured 2026-12-05.
pub const LEVEL2_C: (f64, f64) = (0.085, 0.04);

/// Strength x sqrt(level-2 runs) of `mutant:seam*S` at power 0.95, quick
/// and standard scenes (VALIDATION.md, "Defects of decomposition and
/// time"): S = 0.001 with 8 runs caught 20 of 20 times at quick, 0.0003 10
/// of 20 (measured 2026-12-07). The standard tier uses the quick constant
/// (its probes run longer: an upper bound).
pub const SEAM_C: (f64, f64) = (0.0029, 0.0029);

/// Strength x sqrt(level-2 runs) of `mutant:lane-boundary*S` at power
/// 0.95: S = 0.0001 with 8 runs caught 20 of 20 times at quick, the
/// smallest strength measured (an upper bound).
pub const LANE_C: (f64, f64) = (0.00029, 0.00029);

/// Relative error x sqrt(level-2 runs) of `mutant:g*F@2000` at power 0.95:
/// F = 1.05 with 8 runs caught 20 of 20 times at quick, 1.03 9 of 20.
pub const DRIFT_C: (f64, f64) = (0.142, 0.142);

/// Level-1 CPU seconds per trial per state (reference and candidate both
/// the reference engine; `validate --level 1`, quick 4.1 s for 4000
/// trials, standard 20.3 s for 20000, measured 2026-12-05).
pub const LEVEL1_CPU_PER_TRIAL: f64 = 1.0e-3;

/// Level-2 CPU seconds per run per engine (all scenes, both engines): quick
/// 3.05 s for 8 runs, standard 19.95 s for 16 runs (measured 2026-12-05).
pub const LEVEL2_CPU_PER_RUN: (f64, f64) = (0.38, 1.25);

/// The class of defect `--detect` sizes a validation for (VALIDATION.md,
/// "What each level can see").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// A rule probability off by a relative error (levels 1 and 2).
    Rule,
    /// A seam of one row in alternate columns, reversal with probability S
    /// per step and site (`mutant:seam*S`; level 2, the rows probe).
    Seam,
    /// Reversals at the word boundaries of the fast engine with probability
    /// S (`mutant:lane-boundary*S`; level 2, the rows probe).
    LaneBoundary,
    /// g off by a relative error from step 2000 on (`mutant:g*F@2000`;
    /// level 2, the window probe).
    Drift,
}

impl Class {
    /// Its name, as `--detect CLASS:E` takes it.
    pub fn name(self) -> &'static str {
        match self {
            Class::Rule => "rule",
            Class::Seam => "seam",
            Class::LaneBoundary => "lane-boundary",
            Class::Drift => "drift",
        }
    }

    /// What its size means, for the line `--detect` prints.
    fn what(self) -> &'static str {
        match self {
            Class::Rule => "any rule probability off by that much",
            Class::Seam => {
                "a seam of one row in alternate columns reversing moving particles with that probability per step"
            }
            Class::LaneBoundary => {
                "reversals at 64-row word boundaries with that probability per step"
            }
            Class::Drift => "g off by that much from step 2000 on",
        }
    }

    /// Size x sqrt(level-2 runs) at power 0.95 at the quick and standard
    /// scenes ([`LEVEL2_C`] for a rule probability; the others measured
    /// with the defect mutants, VALIDATION.md).
    fn level2_c(self) -> (f64, f64) {
        match self {
            Class::Rule => LEVEL2_C,
            Class::Seam => SEAM_C,
            Class::LaneBoundary => LANE_C,
            Class::Drift => DRIFT_C,
        }
    }
}

/// The classes, as `--detect CLASS:E` names them.
pub const CLASSES: [Class; 4] = [Class::Rule, Class::Seam, Class::LaneBoundary, Class::Drift];

/// A target of `--detect`: a class and the size of its defect.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// The class.
    pub class: Class,
    /// The relative error (rule, drift) or the strength (seam, lane boundary).
    pub e: f64,
}

/// Parse the value of `--detect`: `E` (a rule probability off by E) or
/// `CLASS:E`, CLASS one of [`CLASSES`], E as [`parse_error`] takes it.
pub fn parse_target(s: &str) -> Result<Target> {
    let (class, e) = match s.split_once(':') {
        None => (Class::Rule, s),
        Some((c, e)) => {
            let class = CLASSES
                .iter()
                .find(|k| k.name() == c.trim())
                .copied()
                .ok_or_else(|| {
                    let names: Vec<&str> = CLASSES.iter().map(|k| k.name()).collect();
                    Error::out_of_range("--detect class", c, &names.join(", "))
                })?;
            (class, e)
        }
    };
    Ok(Target {
        class,
        e: parse_error(e)?,
    })
}

/// What `--detect` chose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Detect {
    /// The relative error to catch.
    pub e: f64,
    /// Level-1 trials per state.
    pub trials: usize,
    /// Level-2 runs per engine per scene.
    pub runs: usize,
    /// Estimated CPU seconds when the candidate is as fast as the reference.
    pub cpu_seconds: f64,
}

/// Parse the value of `--detect`: `3%` or `0.03`, a relative error in
/// (0, 1].
pub fn parse_error(s: &str) -> Result<f64> {
    let t = s.trim();
    let (num, scale) = match t.strip_suffix('%') {
        Some(n) => (n, 0.01),
        None => (t, 1.0),
    };
    match num.trim().parse::<f64>() {
        Ok(v) if v.is_finite() && v * scale > 0.0 && v * scale <= 1.0 => Ok(v * scale),
        _ => Err(Error::out_of_range(
            "--detect",
            s,
            "(0, 1] (a relative error, e.g. 3% or 0.03)",
        )),
    }
}

/// The smallest n with e sqrt(n) >= c.
fn needed(c: f64, e: f64) -> usize {
    ((c / e).powi(2)).ceil() as usize
}

/// Most level-2 runs per engine per scene (`validate --runs`).
pub const MAX_RUNS: usize = 10_000;

/// Trials and runs for a relative error `e` at the scenes of `tier`, for
/// the `levels` asked (the other's count stays as given), within
/// `max_trials` and [`MAX_RUNS`].
pub fn plan(
    target: Target,
    tier: Tier,
    levels: Level,
    (trials, runs): (usize, usize),
    max_trials: usize,
) -> Result<Detect> {
    let Target { class, e } = target;
    let max_runs = MAX_RUNS;
    let c2 = class.level2_c();
    let c2 = tier.pick(c2.0, c2.1, c2.1);
    let per_run = tier.pick(
        LEVEL2_CPU_PER_RUN.0,
        LEVEL2_CPU_PER_RUN.1,
        LEVEL2_CPU_PER_RUN.1,
    );
    let too_small = |what: &str, c: f64, max: usize| {
        Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--detect {:.3}%: {what} would need more than {max}; the smallest error it can target is {:.3}%",
                100.0 * e,
                100.0 * c / (max as f64).sqrt()
            ),
        )
    };
    let mut d = Detect {
        e,
        trials,
        runs,
        cpu_seconds: 0.0,
    };
    if levels != Level::Two && class == Class::Rule {
        d.trials = needed(LEVEL1_C, e).max(super::conformance::MIN_TRIALS);
        if d.trials > max_trials {
            return Err(too_small("level 1 trials per state", LEVEL1_C, max_trials));
        }
        d.cpu_seconds += LEVEL1_CPU_PER_TRIAL * d.trials as f64;
    }
    if levels != Level::One {
        d.runs = needed(c2, e).max(3);
        if d.runs > max_runs {
            return Err(too_small("level 2 runs per engine", c2, max_runs));
        }
        d.cpu_seconds += per_run * d.runs as f64;
    }
    Ok(d)
}

/// `validate --detect e`: set the trials and runs of `size` for `e` at
/// `tier` and `levels` ([`plan`]); the line to print before starting.
pub fn resize(size: &mut super::Size, t: Target, tier: Tier, levels: Level) -> Result<String> {
    let max_trials = super::conformance::MAX_TRIALS;
    if t.class != Class::Rule && levels == Level::One {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "--detect {}: level 1 cannot see this class; use --level 2 or all",
                t.class.name()
            ),
        ));
    }
    let d = plan(t, tier, levels, (size.trials, size.runs), max_trials)?;
    (size.trials, size.runs) = (d.trials, d.runs);
    Ok(describe(&d, t.class, levels))
}

/// The line `validate --detect` prints before it starts, naming the class
/// it sizes for.
pub fn describe(d: &Detect, class: Class, levels: Level) -> String {
    let mut parts = Vec::new();
    if levels != Level::Two && class == Class::Rule {
        parts.push(format!("level 1 with {} trials per state", d.trials));
    }
    if levels != Level::One {
        parts.push(format!("level 2 with {} runs per engine per scene", d.runs));
    }
    let blind = if class == Class::Rule || levels == Level::Two {
        ""
    } else {
        " (level 1 cannot see it: its trials stay as given)"
    };
    format!(
        "--detect {:.2}%: {}{blind} (power 0.95 against {}: class {}); about {:.0} CPU-s ({:.1} CPU-min) for a candidate as fast as the reference",
        100.0 * d.e,
        parts.join(" and "),
        class.what(),
        class.name(),
        d.cpu_seconds,
        d.cpu_seconds / 60.0
    )
}

/// One row of the detection table: `validate --repeat` of one parametric
/// mutant at one tier and level.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// `quick` or `standard`.
    pub tier: String,
    /// 1 or 2.
    pub level: u8,
    /// The knob (`p`, `r1-split`, ...).
    pub knob: String,
    /// The factor 1 + e.
    pub factor: f64,
    /// Validations that failed.
    pub failed: usize,
    /// Validations.
    pub total: usize,
    /// The step a drift starts at (`mutant:KNOB*F@T`), if it is one.
    pub start: Option<u64>,
}

impl Row {
    /// Its class: `seam` and `lane-boundary` (the factor is the
    /// strength S), `drift` (a start step), or `rule`.
    pub fn class(&self) -> &'static str {
        if self.knob.starts_with("seam") {
            "seam"
        } else if self.knob == "lane-boundary" {
            "lane-boundary"
        } else if self.start.is_some() {
            "drift"
        } else {
            "rule"
        }
    }
}

/// The defect rows of `rows` (every class but `rule`) as a Markdown table,
/// one line per (tier, level, mutant): the mutant as `--candidate` names
/// it and its failures.
pub fn defect_table(rows: &[Row]) -> String {
    let mut s =
        String::from("| class | tier | level | candidate | failed |\n|---|---|---|---|---|\n");
    let mut mine: Vec<&Row> = rows.iter().filter(|r| r.class() != "rule").collect();
    mine.sort_by(|a, b| {
        (
            a.class(),
            a.tier.as_str(),
            a.level,
            a.knob.as_str(),
            a.start,
        )
            .cmp(&(
                b.class(),
                b.tier.as_str(),
                b.level,
                b.knob.as_str(),
                b.start,
            ))
            .then(a.factor.total_cmp(&b.factor))
    });
    for r in mine {
        let at = r.start.map_or(String::new(), |t| format!("@{t}"));
        s.push_str(&format!(
            "| {} | {} | {} | `mutant:{}*{}{at}` | {} / {} |\n",
            r.class(),
            r.tier,
            r.level,
            r.knob,
            r.factor,
            r.failed,
            r.total
        ));
    }
    s
}

/// The row of one `--repeat` CSV (its header comment names the candidate
/// `mutant:KNOB*F`, the level and the tier); `None` for another candidate.
pub fn read_row(text: &str) -> Option<Row> {
    check_row(text).ok().flatten()
}

/// [`read_row`], checked: `Ok(None)` for a CSV that is not a mutant's
/// `--repeat` run (skipped), an error for one that is but cannot be counted:
/// a factor that is not a finite positive number, no validation rows, a row
/// without a seed and verdict, or a seed given twice.
pub fn check_row(text: &str) -> std::result::Result<Option<Row>, String> {
    let Some(head) = text.lines().next().and_then(|h| h.strip_prefix("# ")) else {
        return Ok(None);
    };
    let field = |k: &str| {
        head.split_whitespace()
            .find_map(|w| w.strip_prefix(k)?.strip_prefix('='))
    };
    let Some((knob, f)) = field("candidate")
        .and_then(|c| c.strip_prefix("mutant:"))
        .and_then(|c| c.split_once('*'))
    else {
        return Ok(None);
    };
    let level = match field("level") {
        Some("One") => 1,
        Some("Two") => 2,
        _ => return Ok(None),
    };
    let (f, start) = match f.split_once('@') {
        Some((f, t)) => (
            f,
            Some(
                t.parse::<u64>()
                    .map_err(|_| format!("start {t:?} is not a step"))?,
            ),
        ),
        None => (f, None),
    };
    let factor: f64 = f
        .parse()
        .map_err(|_| format!("factor {f:?} is not a number"))?;
    if !(factor.is_finite() && factor > 0.0) {
        return Err(format!("factor {f} is not a finite positive number"));
    }
    let tier = field("tier")
        .ok_or("no tier in the first line")?
        .to_lowercase();
    let rows: Vec<&str> = text.lines().skip(2).filter(|l| !l.is_empty()).collect();
    if rows.is_empty() {
        return Err("no validation rows".into());
    }
    let mut seeds = std::collections::BTreeSet::new();
    let mut failed = 0;
    for (i, l) in rows.iter().enumerate() {
        let mut cells = l.split(',');
        let (seed, pass) = (cells.next(), cells.next());
        let Some(seed) = seed.and_then(|s| s.parse::<u64>().ok()) else {
            return Err(format!("row {} has no seed: {l:?}", i + 1));
        };
        match pass {
            Some("true") => {}
            Some("false") => failed += 1,
            _ => return Err(format!("row {} has no verdict true/false: {l:?}", i + 1)),
        }
        if !seeds.insert(seed) {
            return Err(format!("seed {seed} is counted twice"));
        }
    }
    Ok(Some(Row {
        tier,
        level,
        knob: knob.to_string(),
        factor,
        failed,
        total: rows.len(),
        start,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_repeat_csv_is_one_row() {
        let text = "# candidate=mutant:p-r3*1.05 level=One model=Pipe tier=Quick rules=default trials=4000 runs=8 hopper_runs=8\nseed,pass\n1,true\n2,false\n3,false\n";
        let r = read_row(text).unwrap();
        assert_eq!(
            (r.knob.as_str(), r.level, r.tier.as_str()),
            ("p-r3", 1, "quick")
        );
        assert_eq!((r.factor, r.failed, r.total), (1.05, 2, 3));
        assert!(read_row("# candidate=reference level=One tier=Quick\n").is_none());
        let drift = text.replace("p-r3*1.05", "g*1.05@2000");
        let d = read_row(&drift).unwrap();
        assert_eq!((d.class(), d.start, d.factor), ("drift", Some(2000), 1.05));
        let seam = read_row(&text.replace("p-r3*1.05", "seam*0.001")).unwrap();
        assert_eq!((seam.class(), seam.factor), ("seam", 0.001));
        assert!(defect_table(&[r, d, seam]).contains("`mutant:g*1.05@2000` | 2 / 3"));
    }

    #[test]
    fn errors_parse_as_percent_or_fraction() {
        assert_eq!(parse_error("3%").unwrap(), 0.03);
        assert_eq!(parse_error("0.03").unwrap(), 0.03);
        for bad in ["0", "0%", "-1%", "150%", "x", "nan", "inf%"] {
            let e = parse_error(bad).unwrap_err();
            assert!(format!("{e}").contains("--detect"), "{bad}: {e}");
        }
    }

    #[test]
    fn counts_grow_as_one_over_e_squared() {
        let lim = 1_000_000;
        let rule = |e| Target {
            class: Class::Rule,
            e,
        };
        let a = plan(rule(0.10), Tier::Quick, Level::One, (4000, 8), lim).unwrap();
        let b = plan(rule(0.05), Tier::Quick, Level::One, (4000, 8), lim).unwrap();
        assert_eq!(a.trials, 1807); // (4.25 / 0.1)^2 = 1806.25
        assert!((b.trials as f64 / a.trials as f64 - 4.0).abs() < 0.01);
        assert_eq!(a.runs, 8); // level 2 not asked: the tier's
        let e = plan(rule(0.001), Tier::Quick, Level::One, (4000, 8), lim).unwrap_err();
        assert!(format!("{e}").contains("smallest error"), "{e}");
    }
}
