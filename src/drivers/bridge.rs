//! The calibrated bridge between the lane and the gas (READINGS.md P23,
//! `lane-collide:q`): the plan of
//! docs/notebook/2026-12-07-calibrated-bridge-plan.md as code. The 39
//! claims of the reproduction matrix ([`crate::drivers::claims::CLAIMS`]) are sorted
//! into three kinds by what they assert, split into a calibration half and a
//! test half by a fixed rule, q is picked from a grid on the calibration half
//! alone, and the decision rule compares the picked reading with the
//! default on the test half.

use super::claims::{Graded, Verdict};
use crate::error::{Error, ErrorKind, Result};
use crate::pipe::Rules;
use crate::plot::{line_chart, Line};
use plotters::chart::SeriesLabelPosition;
use plotters::style::RGBColor;
use serde::Serialize;
use std::path::Path;

/// What a claim asserts, fixed before any run of the plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// It needs density waves where it is measured: waves present, a
    /// 1/f^alpha background with alpha near 1 or above, alpha rising with
    /// rho, contrast rising, or a property of a wave (speed, front, width).
    Waves,
    /// It needs a gas without waves: no waves, white noise, or alpha the
    /// same whatever p, b or g.
    Gas,
    /// Neither: relaxation, the open pipe's flow and I_c, claims that ask
    /// for waves at some densities and none at others, and how v depends on
    /// the parameters.
    Other,
}

/// The kind of every claim of [`CLAIMS`](crate::drivers::claims::CLAIMS), by the words of [`Kind`].
pub const KINDS: [(&str, Kind); 39] = [
    ("waves_1a", Kind::Waves),
    ("none_p0", Kind::Gas),
    ("return_1c", Kind::Waves),
    ("none_b0", Kind::Gas),
    ("rho_window", Kind::Other),
    ("alpha_fig2", Kind::Waves),
    ("v_fig2", Kind::Waves),
    ("alpha_p08", Kind::Waves),
    ("white_p0", Kind::Gas),
    ("white_b0", Kind::Gas),
    ("peak_b0", Kind::Other),
    ("alpha_const_p", Kind::Gas),
    ("v_const_p", Kind::Other),
    ("contrast_rises", Kind::Waves),
    ("contrast_saturates", Kind::Other),
    ("energy_rises", Kind::Other),
    ("energy_saturates", Kind::Other),
    ("steep_front", Kind::Waves),
    ("width_grows", Kind::Waves),
    ("v_fig5", Kind::Waves),
    ("flows_fig11", Kind::Other),
    ("v_fig11", Kind::Waves),
    ("i_c", Kind::Other),
    ("i_c_size", Kind::Other),
    ("i_c_params", Kind::Other),
    ("one_over_f_ic", Kind::Waves),
    ("white_half_ic", Kind::Gas),
    ("clogs_054", Kind::Other),
    ("alpha_zero_low_rho", Kind::Gas),
    ("alpha_rises_rho", Kind::Waves),
    ("alpha_rho2", Kind::Waves),
    ("v_const_rho", Kind::Other),
    ("alpha_const_b", Kind::Gas),
    ("alpha_indep_g", Kind::Gas),
    ("v_falls_with_b", Kind::Other),
    ("v_falls_more_small_g", Kind::Other),
    ("v_changes_with_g", Kind::Other),
    ("alpha_indep_pbg", Kind::Gas),
    ("alpha_fig2_published", Kind::Waves),
];

/// The headline claims: a calibrated reading that loses one of them (its
/// verdict not reproduced where the default's is reproduced or undecided)
/// does not become the default (the rule of the extensions' screen,
/// docs/notebook/2026-12-04-extensions-beyond-the-text.md).
pub const HEADLINE: [&str; 8] = [
    "alpha_fig2_published",
    "alpha_fig2",
    "v_fig2",
    "alpha_p08",
    "white_p0",
    "white_b0",
    "peak_b0",
    "v_fig5",
];

/// The grid of q, fixed in the plan; q = 0 is the default itself
/// (`lane-collide:0` is the default step for step).
pub const GRID: [f64; 7] = [0.0, 0.0003, 0.001, 0.003, 0.01, 0.03, 0.1];

/// The kind of claim `id`.
pub fn kind(id: &str) -> Option<Kind> {
    KINDS.iter().find(|k| k.0 == id).map(|k| k.1)
}

/// The two halves (calibration, test): within each kind the claims are
/// sorted by id and dealt alternately, the first to calibration.
pub fn split() -> (Vec<&'static str>, Vec<&'static str>) {
    let (mut cal, mut test) = (Vec::new(), Vec::new());
    for k in [Kind::Waves, Kind::Gas, Kind::Other] {
        let mut ids: Vec<&str> = KINDS.iter().filter(|c| c.1 == k).map(|c| c.0).collect();
        ids.sort_unstable();
        for (i, id) in ids.into_iter().enumerate() {
            if i % 2 == 0 {
                cal.push(id)
            } else {
                test.push(id)
            }
        }
    }
    (cal, test)
}

/// Verdict counts over a set of claims.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Score {
    /// Claims reproduced.
    pub reproduced: usize,
    /// Claims not reproduced.
    pub not_reproduced: usize,
    /// Claims undecided, or not graded.
    pub undecided: usize,
}

/// The score of `graded` over the claims `ids` (a claim not graded counts
/// as undecided).
pub fn score(graded: &[Graded], ids: &[&str]) -> Score {
    let mut s = Score::default();
    for id in ids {
        match graded.iter().find(|g| g.claim == *id).map(|g| g.verdict) {
            Some(Verdict::Reproduced) => s.reproduced += 1,
            Some(Verdict::NotReproduced) => s.not_reproduced += 1,
            _ => s.undecided += 1,
        }
    }
    s
}

/// The plan's rule: the q whose reading reproduces the most claims of
/// `calibration`; ties go to fewer not reproduced, then to the smaller q.
/// `grid` pairs each q with its grades; only the calibration claims are
/// read.
pub fn choose(grid: &[(f64, Vec<Graded>)], calibration: &[&str]) -> Result<f64> {
    let best = grid
        .iter()
        .map(|(q, g)| (*q, score(g, calibration)))
        .min_by(|a, b| {
            (b.1.reproduced, a.1.not_reproduced)
                .cmp(&(a.1.reproduced, b.1.not_reproduced))
                .then(a.0.total_cmp(&b.0))
        });
    best.map(|b| b.0).ok_or_else(|| {
        Error::new(
            ErrorKind::InvalidParameter,
            "bridge: the grid of q is empty",
        )
    })
}

/// The plan's decision on the test half.
#[derive(Debug, Clone, Serialize)]
pub struct Decision {
    /// The q picked on the calibration half.
    pub q: f64,
    /// The default's score on the test half.
    pub default_test: Score,
    /// The picked reading's score on the test half.
    pub picked_test: Score,
    /// Headline claims the picked reading loses against the default.
    pub headline_lost: Vec<String>,
    /// Test claims it turns to reproduced, and those it loses (reproduced
    /// by the default, not by it).
    pub turned: Vec<String>,
    /// See `turned`.
    pub lost: Vec<String>,
    /// Whether the picked reading becomes the default: strictly more test
    /// claims reproduced and no headline claim lost.
    pub adopt: bool,
}

/// Apply the decision rule to the default's and the picked reading's grades.
pub fn decide(q: f64, default: &[Graded], picked: &[Graded], test: &[&str]) -> Decision {
    let verdict = |g: &[Graded], id: &str| {
        g.iter()
            .find(|x| x.claim == id)
            .map_or(Verdict::Undecided, |x| x.verdict)
    };
    let headline_lost: Vec<String> = HEADLINE
        .iter()
        .filter(|id| {
            verdict(default, id) != Verdict::NotReproduced
                && verdict(picked, id) == Verdict::NotReproduced
        })
        .map(|s| s.to_string())
        .collect();
    let moved = |from: &[Graded], to: &[Graded]| -> Vec<String> {
        test.iter()
            .filter(|id| {
                verdict(to, id) == Verdict::Reproduced && verdict(from, id) != Verdict::Reproduced
            })
            .map(|s| s.to_string())
            .collect()
    };
    let (default_test, picked_test) = (score(default, test), score(picked, test));
    Decision {
        q,
        default_test,
        picked_test,
        adopt: q > 0.0
            && picked_test.reproduced > default_test.reproduced
            && headline_lost.is_empty(),
        headline_lost,
        turned: moved(default, picked),
        lost: moved(picked, default),
    }
}

/// The reading of grid point q: the default, with `lane-collide:q` when
/// q > 0.
pub fn reading(q: f64) -> Result<Rules> {
    if q == 0.0 {
        Ok(Rules::default())
    } else {
        format!("default+lane-collide:{q}").parse()
    }
}

/// One row of the score table: q, half, kind and the score there.
#[derive(Debug, Clone, Serialize)]
pub struct ScoreRow {
    /// The grid point.
    pub q: f64,
    /// `calibration` or `test`.
    pub half: &'static str,
    /// The kind of claims counted.
    pub kind: Kind,
    /// Their verdicts.
    pub score: Score,
}

/// The score of every grid point, in each half and of each kind.
pub fn score_rows(grid: &[(f64, Vec<Graded>)]) -> Vec<ScoreRow> {
    let (cal, test) = split();
    let mut rows = Vec::new();
    for (q, graded) in grid {
        for (half, ids) in [("calibration", &cal), ("test", &test)] {
            for k in [Kind::Waves, Kind::Gas, Kind::Other] {
                let of_kind: Vec<&str> = ids
                    .iter()
                    .copied()
                    .filter(|id| kind(id) == Some(k))
                    .collect();
                rows.push(ScoreRow {
                    q: *q,
                    half,
                    kind: k,
                    score: score(graded, &of_kind),
                });
            }
        }
    }
    rows
}

/// Where q = 0 (the default) is drawn on the log10 q axis: one decade left
/// of the smallest q of the grid.
pub const Q0_AT: f64 = -4.5;

/// The trade-off figure: claims reproduced against log10 q for each half,
/// its waves claims, its gas claims and all its claims, with q = 0 (the
/// default) drawn at `Q0_AT`. Lines that would coincide are drawn up to
/// 0.1 apart, so none hides another (the axis label says so).
pub fn chart(path: &Path, rows: &[ScoreRow], picked: f64) -> Result<()> {
    let series = [
        (
            "calibration",
            Some(Kind::Waves),
            RGBColor(31, 119, 180),
            -0.1,
        ),
        (
            "calibration",
            Some(Kind::Gas),
            RGBColor(255, 127, 14),
            -0.06,
        ),
        ("calibration", None, RGBColor(0, 0, 0), -0.02),
        ("test", Some(Kind::Waves), RGBColor(44, 160, 44), 0.02),
        ("test", Some(Kind::Gas), RGBColor(214, 39, 40), 0.06),
        ("test", None, RGBColor(148, 103, 189), 0.1),
    ];
    let x = |q: f64| if q > 0.0 { q.log10() } else { Q0_AT };
    let mut qs: Vec<f64> = rows.iter().map(|r| r.q).collect();
    qs.sort_by(f64::total_cmp);
    qs.dedup();
    let mut lines = Vec::new();
    for (half, k, color, dy) in series {
        let pts: Vec<(f64, f64)> = qs
            .iter()
            .map(|&q| {
                let n: usize = rows
                    .iter()
                    .filter(|r| r.q == q && r.half == half && k.is_none_or(|k| r.kind == k))
                    .map(|r| r.score.reproduced)
                    .sum();
                (x(q), n as f64 + dy)
            })
            .collect();
        let what = k.map_or("all".to_string(), |k| format!("{k:?}").to_lowercase());
        lines.push(Line::new(&format!("{half}, {what} claims"), pts, color));
    }
    line_chart(
        path,
        &format!(
            "lane-collide:q: claims reproduced against q (q = 0 at {Q0_AT}); picked on the calibration half: q = {picked}"
        ),
        "log10 q (the default, q = 0, drawn at the left edge)",
        "claims reproduced (lines up to 0.1 apart)",
        &lines,
        false,
        SeriesLabelPosition::UpperRight,
    )
}

#[cfg(test)]
mod tests {
    use super::super::claims::CLAIMS;
    use super::*;

    fn graded(pairs: &[(&str, Verdict)]) -> Vec<Graded> {
        pairs
            .iter()
            .map(|(id, v)| Graded {
                claim: id.to_string(),
                measured: 0.0,
                error: 0.0,
                verdict: *v,
                detail: String::new(),
                runs: 3,
            })
            .collect()
    }

    #[test]
    fn every_claim_has_one_kind_and_each_half_holds_both_kinds() {
        let ids: Vec<&str> = CLAIMS.iter().map(|c| c.0).collect();
        let kinds: Vec<&str> = KINDS.iter().map(|c| c.0).collect();
        assert_eq!(ids, kinds);
        let (cal, test) = split();
        assert_eq!(cal.len() + test.len(), 39);
        for half in [&cal, &test] {
            for k in [Kind::Waves, Kind::Gas] {
                assert!(half.iter().filter(|id| kind(id) == Some(k)).count() >= 4);
            }
        }
        assert!(cal.iter().all(|id| !test.contains(id)));
        assert!(HEADLINE.iter().all(|id| kind(id).is_some()));
    }

    #[test]
    fn the_rule_reads_only_the_calibration_half_and_breaks_ties_to_the_smaller_q() {
        use Verdict::*;
        let (cal, test) = split();
        let (c, t) = (cal[0], test[0]);
        let grid = vec![
            (0.0, graded(&[(c, NotReproduced), (t, Reproduced)])),
            (0.01, graded(&[(c, Reproduced), (t, NotReproduced)])),
            (0.1, graded(&[(c, Reproduced), (t, Reproduced)])),
        ];
        assert_eq!(choose(&grid, &cal).unwrap(), 0.01);
        let tie = vec![
            (0.03, graded(&[(c, Undecided)])),
            (0.001, graded(&[(c, Undecided)])),
            (0.1, graded(&[(c, NotReproduced)])),
        ];
        assert_eq!(choose(&tie, &cal).unwrap(), 0.001);
        assert!(choose(&[], &cal).is_err());
    }

    #[test]
    fn a_reading_that_loses_a_headline_claim_is_not_adopted() {
        use Verdict::*;
        let (_, test) = split();
        let default = graded(&[("alpha_fig2", Reproduced)]);
        let mut better: Vec<(&str, Verdict)> = test.iter().map(|id| (*id, Reproduced)).collect();
        better.retain(|p| p.0 != "alpha_fig2");
        better.push(("alpha_fig2", NotReproduced));
        let d = decide(0.01, &default, &graded(&better), &test);
        assert_eq!(d.headline_lost, ["alpha_fig2"]);
        assert!(!d.adopt);
        better.retain(|p| p.0 != "alpha_fig2");
        let d = decide(0.01, &default, &graded(&better), &test);
        assert!(d.adopt, "{d:?}");
        assert!(!decide(0.0, &default, &graded(&better), &test).adopt);
    }
}
