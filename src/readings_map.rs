//! The map of claims by readings (MODEL.md A11; the plan and its decision
//! rule: docs/decisions/claims-by-readings-map.md): every published check
//! of the pipe's figure binaries, graded under each named reading of the
//! rule text, with the figures' own statistics, estimators and margins.
//!
//! Each reading runs every pipe figure (`fig1`, `fig2`, `waves-fig2` to
//! `waves-fig12`) as `report` runs them, with `--rules <reading>` added, into
//! a folder of its own; a figure whose summary is already there with the
//! same rules, tier and engine is read instead of rerun, so an interrupted
//! map resumes. The claims are the checks of kind `published` (identities
//! and pinned values are left out: they hold under every reading by
//! construction or test the estimators, not the model), each tagged with a
//! [`Kind`] by [`kind_of`], a rule fixed before any reading was graded.

use crate::error::{Error, ErrorKind, Result};
use crate::pipe::Rules;
use crate::plot::{plot_err, register_fonts, FONT};
use crate::report::{self, Options, Row};
use crate::run::Tier;
use plotters::prelude::*;
use serde::Serialize;
use serde_json::Value;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The readings of the plan, in its column order: a short label (the
/// reading's folder) and its `--rules` value.
pub const READINGS: [(&str, &str); 11] = [
    ("default", "default"),
    ("literal-labels", "default+literal-labels"),
    ("wall-sites", "default+wall-sites"),
    ("literal+wall-sites", "default+literal-labels+wall-sites"),
    (
        "any-mover+literal",
        "any-mover+gravity-first+wall-move+inject-late+literal-labels",
    ),
    (
        "any-mover+wall-sites",
        "any-mover+gravity-first+wall-move+inject-late+wall-sites",
    ),
    (
        "any-mover+literal+wall-sites",
        "any-mover+gravity-first+wall-move+inject-late+literal-labels+wall-sites",
    ),
    ("fhp-rest", "default+fhp-rest"),
    (
        "any-mover+lane-collide",
        "any-mover+gravity-first+wall-move+lane-collide",
    ),
    ("wall-drag", "ph94+wall-drag+wall-move"),
    ("rest-ahead", "rest-ahead+gravity-first+wall-move"),
];

/// The pipe's figure binaries whose published checks the map grades, in
/// the papers' order: every figure but the hopper's.
pub fn figures() -> Vec<&'static str> {
    let order = crate::experiments::ORDER.into_iter();
    order.filter(|b| report::is_pipe_figure(b)).collect()
}

/// The headline claims the decision rule protects: PH94 Fig. 2's v and
/// PH95 Fig. 12's I_c (binary, check).
pub const HEADLINE: [(&str, &str); 2] = [("fig2", "v_peak"), ("waves-fig12", "i_c")];

/// The kind of a claim, the map's row groups.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub enum Kind {
    /// Density waves: PH94 Fig. 1, PH95 Figs. 2, 4, 5 and the dense regions
    /// of Fig. 11.
    Waves,
    /// 1/f spectra: PH94 Fig. 2, PH95 Figs. 6 and 8-10.
    Spectra,
    /// The gas: PH95 Fig. 3's relaxation, white noise at p = 0 or b = 0
    /// (Fig. 7) and at low rho (Fig. 9).
    Gas,
    /// The open pipe: PH95 Fig. 11's flow and Fig. 12.
    OpenPipe,
}

impl Kind {
    /// The kinds in row order.
    pub const ALL: [Kind; 4] = [Kind::Waves, Kind::Spectra, Kind::Gas, Kind::OpenPipe];

    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Waves => "waves",
            Kind::Spectra => "spectra",
            Kind::Gas => "gas",
            Kind::OpenPipe => "open pipe",
        }
    }
}

/// The kind of check `check` of figure `binary` (the plan's grouping:
/// Fig. 3 is the gas's relaxation, Fig. 9's white noise at low rho is the
/// gas's, Fig. 11's speed and correlation are its dense regions').
pub fn kind_of(binary: &str, check: &str) -> Kind {
    match binary {
        "fig1" | "waves-fig2" | "waves-fig4" | "waves-fig5" => Kind::Waves,
        "waves-fig3" | "waves-fig7" => Kind::Gas,
        "waves-fig9" if check.starts_with("alpha_zero") => Kind::Gas,
        "fig2" | "waves-fig6" | "waves-fig8" | "waves-fig9" | "waves-fig10" => Kind::Spectra,
        "waves-fig11" if check != "paper_setup_flows" => Kind::Waves,
        _ => Kind::OpenPipe,
    }
}

/// One claim's grade under one reading.
#[derive(Debug, Clone, Serialize)]
pub struct Cell {
    /// reproduced | not-reproduced | undecided.
    pub verdict: String,
    /// The measured value.
    pub measured: Option<f64>,
    /// Its standard error.
    pub error: Option<f64>,
    /// Runs behind it.
    pub runs: Option<u64>,
}

/// One claim: a published check of a pipe figure, graded per reading.
#[derive(Debug, Clone, Serialize)]
pub struct Claim {
    /// Figure binary.
    pub binary: String,
    /// Check name.
    pub check: String,
    /// Its kind ([`kind_of`]).
    pub kind: Kind,
    /// Where the paper states it.
    pub source: String,
    /// Its grade per reading, in [`Map::readings`] order (`None`: the
    /// figure did not run or has no such check under that reading).
    pub cells: Vec<Option<Cell>>,
}

impl Claim {
    /// `binary.check`.
    pub fn id(&self) -> String {
        format!("{}.{}", self.binary, self.check)
    }

    /// Whether reading `r` reproduces it.
    pub fn reproduced_by(&self, r: usize) -> bool {
        matches!(&self.cells[r], Some(c) if c.verdict == "reproduced")
    }
}

/// The map: claims x readings.
#[derive(Debug, Clone, Serialize)]
pub struct Map {
    /// Tier of every run.
    pub tier: String,
    /// Engine of every run.
    pub engine: String,
    /// The readings (label, rules), the columns.
    pub readings: Vec<(String, String)>,
    /// The claims, the rows, grouped by kind.
    pub claims: Vec<Claim>,
    /// Figures that did not run under a reading: (reading, binary, why).
    pub failures: Vec<(String, String, String)>,
}

/// Readings named by label (`all`: every one of [`READINGS`]), in the
/// plan's order. An unknown label is an error naming the allowed ones.
pub fn select(labels: &str) -> Result<Vec<(String, String)>> {
    if labels.trim() == "all" {
        return Ok(READINGS
            .map(|(l, r)| (l.to_string(), r.to_string()))
            .to_vec());
    }
    let names: Vec<&str> = labels.split(',').map(str::trim).collect();
    crate::error::reject_duplicates("--readings", &names)?;
    let mut chosen = vec![];
    for label in names {
        let Some((l, r)) = READINGS.iter().find(|(l, _)| *l == label) else {
            let known: Vec<&str> = READINGS.iter().map(|r| r.0).collect();
            return Err(Error::new(
                ErrorKind::InvalidParameter,
                format!(
                    "--readings: unknown reading '{label}'; use 'all' or labels from {{{}}}",
                    known.join(", ")
                ),
            ));
        };
        chosen.push((l.to_string(), r.to_string()));
    }
    chosen.sort_by_key(|(l, _)| READINGS.iter().position(|r| r.0 == l));
    Ok(chosen)
}

/// Whether `out/<binary>/summary.json` holds a finished run of `rules` at
/// `tier` on `engine`.
fn finished(out: &Path, binary: &str, rules: &Rules, tier: Tier, engine: &str) -> bool {
    let path = out.join(binary).join("summary.json");
    let Some(s) = std::fs::read_to_string(path)
        .ok()
        .and_then(|t| serde_json::from_str::<Value>(&t).ok())
    else {
        return false;
    };
    s["rules"].as_str() == Some(&rules.to_string())
        && s["tier"].as_str() == Some(tier.name())
        && s["engine"].as_str() == Some(engine)
}

/// Run (or read, where finished) every pipe figure under each reading into
/// `base.out/<label>/` and collect the map. `base` gives the tier, seed,
/// threads, engine and the binaries' folder (with `no_run`, nothing runs:
/// the summaries already there are read); its figures and extra arguments
/// are replaced.
pub fn run(base: &Options, readings: &[(String, String)]) -> Result<Map> {
    let engine = base.engine.clone().unwrap_or_else(|| "reference".into());
    let mut per_reading = vec![];
    let mut failures = vec![];
    for (label, rules) in readings {
        let parsed: Rules = rules.parse()?;
        let mut opts = base.clone();
        opts.out = base.out.join(label);
        opts.figures = figures().into_iter().map(String::from).collect();
        opts.extra = figures()
            .into_iter()
            .map(|f| (f.to_string(), vec!["--rules".to_string(), rules.clone()]))
            .collect();
        let mut runs = vec![];
        for binary in figures() {
            let done = base.no_run || finished(&opts.out, binary, &parsed, opts.tier, &engine);
            let run = if done {
                report::summary_only(&opts.out, binary)
            } else {
                eprintln!("readings-map: {label}: {binary} ({rules})");
                report::run_figure(&opts, binary)
            };
            if let Some(why) = &run.failure {
                failures.push((label.clone(), binary.to_string(), why.clone()));
            }
            runs.push(run);
        }
        per_reading.push(report::collect(&opts, runs).rows);
    }
    let map = assemble(base.tier, &engine, readings, &per_reading, failures);
    if map.claims.is_empty() {
        return Err(Error::new(
            ErrorKind::InvalidParameter,
            format!(
                "no published check of any pipe figure in {} ({} tier): run without --no-run, or name the folder holding <reading>/<figure>/summary.json",
                base.out.display(),
                base.tier.name()
            ),
        ));
    }
    Ok(map)
}

/// The map from each reading's report rows (its published checks of the
/// default case), claims in the order first seen, grouped by kind.
pub fn assemble(
    tier: Tier,
    engine: &str,
    readings: &[(String, String)],
    rows: &[Vec<Row>],
    failures: Vec<(String, String, String)>,
) -> Map {
    let mut claims: Vec<Claim> = vec![];
    let mut index: BTreeMap<(String, String), usize> = BTreeMap::new();
    for (r, rows) in rows.iter().enumerate() {
        let published = rows
            .iter()
            .filter(|w| w.kind == "published" && w.reading.is_none());
        for w in published {
            let key = (w.binary.clone(), w.name.clone());
            let i = *index.entry(key).or_insert_with(|| {
                claims.push(Claim {
                    binary: w.binary.clone(),
                    check: w.name.clone(),
                    kind: kind_of(&w.binary, &w.name),
                    source: w.source.clone(),
                    cells: vec![None; readings.len()],
                });
                claims.len() - 1
            });
            claims[i].cells[r] = Some(Cell {
                verdict: w.verdict.clone(),
                measured: w.measured,
                error: w.error,
                runs: w.runs,
            });
        }
    }
    claims.sort_by_key(|c| c.kind); // stable: figure order within a kind
    Map {
        tier: tier.name().to_string(),
        engine: engine.to_string(),
        readings: readings.to_vec(),
        claims,
        failures,
    }
}

/// Claims reproduced by reading `r`, in all and per kind.
pub fn reproduced(map: &Map, r: usize) -> (usize, BTreeMap<Kind, usize>) {
    let mut per = BTreeMap::new();
    let mut all = 0;
    for c in map.claims.iter().filter(|c| c.reproduced_by(r)) {
        *per.entry(c.kind).or_insert(0) += 1;
        all += 1;
    }
    (all, per)
}

/// A pair of claims no graded reading reproduces together, though each is
/// reproduced by some reading: the claims (indices into [`Map::claims`])
/// and the readings that reproduce each.
#[derive(Debug, Clone, Serialize)]
pub struct Conflict {
    /// The two claims.
    pub claims: (usize, usize),
    /// Readings (labels) reproducing the first.
    pub first_by: Vec<String>,
    /// Readings reproducing the second.
    pub second_by: Vec<String>,
}

/// Every conflict of the map, in claim order.
pub fn conflicts(map: &Map) -> Vec<Conflict> {
    let n = map.readings.len();
    let by = |c: &Claim| -> Vec<usize> { (0..n).filter(|&r| c.reproduced_by(r)).collect() };
    let labels = |rs: &[usize]| rs.iter().map(|&r| map.readings[r].0.clone()).collect();
    let mut out = vec![];
    for (i, a) in map.claims.iter().enumerate() {
        let ra = by(a);
        if ra.is_empty() {
            continue;
        }
        for (j, b) in map.claims.iter().enumerate().skip(i + 1) {
            let rb = by(b);
            if !rb.is_empty() && !ra.iter().any(|r| rb.contains(r)) {
                out.push(Conflict {
                    claims: (i, j),
                    first_by: labels(&ra),
                    second_by: labels(&rb),
                });
            }
        }
    }
    out
}

/// The decision rule of the plan applied: the reading (index) that
/// reproduces strictly more claims than the default (column 0) and loses
/// no headline claim the default reproduces; the most claims wins, and a
/// tie between such readings keeps the default. `None`: the default stays.
pub fn decision(map: &Map) -> Option<usize> {
    if map.readings.first().map(|r| r.0.as_str()) != Some("default") {
        return None;
    }
    let headline: Vec<&Claim> = map
        .claims
        .iter()
        .filter(|c| HEADLINE.contains(&(c.binary.as_str(), c.check.as_str())))
        .collect();
    let count = |r| reproduced(map, r).0;
    let keeps = |r| {
        headline
            .iter()
            .all(|c| !c.reproduced_by(0) || c.reproduced_by(r))
    };
    let better: Vec<usize> = (1..map.readings.len())
        .filter(|&r| count(r) > count(0) && keeps(r))
        .collect();
    let best = better.iter().map(|&r| count(r)).max()?;
    let top: Vec<usize> = better.into_iter().filter(|&r| count(r) == best).collect();
    (top.len() == 1).then(|| top[0])
}

fn short(v: &str) -> &'static str {
    match v {
        "reproduced" => "yes",
        "not-reproduced" => "no",
        _ => "?",
    }
}

fn value(c: &Cell) -> String {
    match (c.measured, c.error) {
        (Some(m), Some(e)) => format!("{} +- {}", report::num(Some(m)), report::num(Some(e))),
        (Some(m), None) => report::num(Some(m)),
        _ => "-".into(),
    }
}

/// The map as CSV: one line per claim, per reading its verdict, value and
/// error.
pub fn csv(map: &Map) -> String {
    let mut s = String::from("kind,binary,check");
    for (l, _) in &map.readings {
        let _ = write!(s, ",{l}.verdict,{l}.measured,{l}.error");
    }
    s.push('\n');
    let num = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x}"));
    for c in &map.claims {
        let _ = write!(s, "{},{},{}", c.kind.name(), c.binary, c.check);
        for cell in &c.cells {
            match cell {
                Some(x) => {
                    let _ = write!(s, ",{},{},{}", x.verdict, num(x.measured), num(x.error));
                }
                None => s.push_str(",not run,,"),
            }
        }
        s.push('\n');
    }
    s
}

/// The map as Markdown: totals per reading and kind, the decision rule's
/// outcome, then every claim's verdicts.
pub fn markdown(map: &Map, command: &str) -> String {
    let mut s = format!(
        "# Claims by readings ({} tier, {} engine)\n\n`{command}`\n\n",
        map.tier, map.engine
    );
    s.push_str("| reading | rules | reproduced |");
    for k in Kind::ALL {
        let _ = write!(s, " {} |", k.name());
    }
    s.push_str("\n|---|---|---|---|---|---|---|\n");
    for (r, (l, rules)) in map.readings.iter().enumerate() {
        let (all, per) = reproduced(map, r);
        let _ = write!(s, "| {l} | `{rules}` | {all} of {} |", map.claims.len());
        for k in Kind::ALL {
            let of = map.claims.iter().filter(|c| c.kind == k).count();
            let _ = write!(s, " {} of {of} |", per.get(&k).copied().unwrap_or(0));
        }
        s.push('\n');
    }
    let outcome = match decision(map) {
        Some(r) => format!(
            "reading `{}` reproduces strictly more claims and keeps the headline claims: by the rule it becomes the default (its own decision record and commit)",
            map.readings[r].0
        ),
        None => "the default stays: no reading reproduces strictly more claims while keeping the headline claims (or a tie between such readings)".into(),
    };
    let _ = writeln!(s, "\nDecision rule (fixed before grading): {outcome}.\n");
    for (l, b, why) in &map.failures {
        let _ = writeln!(s, "- not run: {b} under {l}: {why}");
    }
    s.push_str("\n| kind | claim |");
    for (l, _) in &map.readings {
        let _ = write!(s, " {l} |");
    }
    s.push_str("\n|---|---|");
    s.push_str(&"---|".repeat(map.readings.len()));
    s.push('\n');
    for c in &map.claims {
        let _ = write!(s, "| {} | {} |", c.kind.name(), c.id());
        for cell in &c.cells {
            match cell {
                Some(x) => {
                    let _ = write!(s, " {} {} |", short(&x.verdict), value(x));
                }
                None => s.push_str(" not run |"),
            }
        }
        s.push('\n');
    }
    s
}

/// The conflict list as Markdown, grouped by the kinds of the two claims.
pub fn conflicts_markdown(map: &Map, list: &[Conflict]) -> String {
    let mut s = format!(
        "# Conflicts: pairs of claims no graded reading reproduces together ({} tier)\n\n{} pairs. Each line: the two claims, then the readings that reproduce each.\n",
        map.tier,
        list.len()
    );
    let mut groups: BTreeMap<(Kind, Kind), Vec<&Conflict>> = BTreeMap::new();
    for c in list {
        let (a, b) = (map.claims[c.claims.0].kind, map.claims[c.claims.1].kind);
        groups.entry((a.min(b), a.max(b))).or_default().push(c);
    }
    for ((a, b), cs) in groups {
        let _ = writeln!(s, "\n## {} x {} ({} pairs)\n", a.name(), b.name(), cs.len());
        for c in cs {
            let (x, y) = (&map.claims[c.claims.0], &map.claims[c.claims.1]);
            let _ = writeln!(
                s,
                "- {} ({}) x {} ({})",
                x.id(),
                c.first_by.join(", "),
                y.id(),
                c.second_by.join(", ")
            );
        }
    }
    s
}

/// Draw the map: claims as rows grouped by kind, readings as columns, each
/// cell coloured by its verdict, the totals under the columns.
pub fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    map: &Map,
) -> Result<()> {
    register_fonts();
    root.fill(&WHITE).map_err(plot_err)?;
    let (left, top, cw, rh) = (330, 150, 96, 16);
    let text = |s: &str, at: (i32, i32), size: u32| {
        root.draw(&Text::new(s.to_string(), at, (FONT, size)))
            .map_err(plot_err)
    };
    let title = format!(
        "PH94/PH95 published claims x readings of the rule text ({} tier, {} engine)",
        map.tier, map.engine
    );
    let fit = crate::plot::caption_size(&title, root.dim_in_pixel().0, 20.0);
    text(&title, (10, 10), fit as u32)?;
    text(
        "green: reproduced, red: not reproduced, grey: undecided, white: not run",
        (10, 36),
        14,
    )?;
    for (r, (l, _)) in map.readings.iter().enumerate() {
        let x = left + cw * r as i32;
        let parts: Vec<&str> = l.split('+').collect();
        for (k, p) in parts.iter().enumerate() {
            let p = if k > 0 {
                format!("+{p}")
            } else {
                p.to_string()
            };
            text(&p, (x + 4, top - 70 + 16 * k as i32), 13)?;
        }
    }
    let mut y = top;
    for kind in Kind::ALL {
        let rows: Vec<&Claim> = map.claims.iter().filter(|c| c.kind == kind).collect();
        if rows.is_empty() {
            continue;
        }
        text(kind.name(), (10, y), 15)?;
        y += rh + 2;
        for c in rows {
            text(&c.id(), (20, y + 1), 12)?;
            for (r, cell) in c.cells.iter().enumerate() {
                let x = left + cw * r as i32;
                let color = match cell.as_ref().map(|c| c.verdict.as_str()) {
                    Some("reproduced") => RGBColor(120, 200, 120),
                    Some("not-reproduced") => RGBColor(230, 120, 110),
                    Some(_) => RGBColor(200, 200, 200),
                    None => WHITE,
                };
                root.draw(&Rectangle::new(
                    [(x, y), (x + cw - 3, y + rh - 2)],
                    color.filled(),
                ))
                .map_err(plot_err)?;
            }
            y += rh;
        }
        y += 6;
    }
    text("reproduced", (10, y + 6), 14)?;
    for r in 0..map.readings.len() {
        let (all, _) = reproduced(map, r);
        let x = left + cw * r as i32;
        text(
            &format!("{all} of {}", map.claims.len()),
            (x + 4, y + 6),
            14,
        )?;
    }
    root.present().map_err(plot_err)
}

/// The map's picture size in pixels.
pub fn size(map: &Map) -> (u32, u32) {
    let w = 330 + 96 * map.readings.len() as u32 + 20;
    let h = 150 + 16 * map.claims.len() as u32 + 24 * Kind::ALL.len() as u32 + 50;
    (w, h)
}

/// Write `map.png`, `matrix.csv`, `matrix.md`, `conflicts.md`
/// and `map.json` into `dir`.
pub fn write(dir: &Path, map: &Map, command: &str) -> Result<PathBuf> {
    std::fs::create_dir_all(dir)?;
    let (w, h) = size(map);
    draw(
        &BitMapBackend::new(&dir.join("map.png"), (w, h)).into_drawing_area(),
        map,
    )?;
    crate::run::write_atomic(&dir.join("matrix.csv"), csv(map).as_bytes())?;
    crate::run::write_atomic(&dir.join("matrix.md"), markdown(map, command).as_bytes())?;
    let list = conflicts(map);
    let md = conflicts_markdown(map, &list);
    crate::run::write_atomic(&dir.join("conflicts.md"), md.as_bytes())?;
    let json = serde_json::json!({"map": map, "conflicts": list, "decision": decision(map)});
    let text = serde_json::to_string_pretty(&json)
        .map_err(|e| Error::new(ErrorKind::Io, e.to_string()))?;
    crate::run::write_atomic(&dir.join("map.json"), text.as_bytes())?;
    Ok(dir.join("matrix.md"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(binary: &str, name: &str, verdict: &str) -> Row {
        let s = serde_json::json!({"paper": "PH95 Fig. 5", "rules": "x"});
        let c = serde_json::json!({"name": name, "kind": "published", "verdict": verdict, "measured": 1.0, "error": 0.1});
        Row::from_json(binary, &s, &c)
    }

    fn map_of(grades: &[[&str; 3]]) -> Map {
        let readings: Vec<(String, String)> = ["default", "literal-labels", "wall-sites"]
            .iter()
            .map(|l| (l.to_string(), l.to_string()))
            .collect();
        let claims = [
            ("fig2", "v_peak"),
            ("waves-fig5", "wave_speed"),
            ("fig2", "alpha"),
        ];
        let rows: Vec<Vec<Row>> = (0..3)
            .map(|r| {
                claims
                    .iter()
                    .zip(grades)
                    .map(|((b, n), g)| row(b, n, g[r]))
                    .collect()
            })
            .collect();
        assemble(Tier::Quick, "fast", &readings, &rows, vec![])
    }

    #[test]
    fn kinds_follow_the_plan() {
        assert_eq!(kind_of("waves-fig3", "contrast_rises"), Kind::Gas);
        assert_eq!(kind_of("waves-fig9", "alpha_zero_rho0.2"), Kind::Gas);
        assert_eq!(kind_of("waves-fig9", "alpha_at_rho2"), Kind::Spectra);
        assert_eq!(kind_of("waves-fig11", "paper_setup_speed"), Kind::Waves);
        assert_eq!(kind_of("waves-fig11", "paper_setup_flows"), Kind::OpenPipe);
        assert_eq!(kind_of("fig1", "waves_a"), Kind::Waves);
    }

    #[test]
    fn conflicts_are_pairs_no_reading_reproduces_together() {
        // v: default only; speed: literal only; alpha: nobody
        let m = map_of(&[
            ["reproduced", "not-reproduced", "undecided"],
            ["not-reproduced", "reproduced", "not-reproduced"],
            ["not-reproduced", "not-reproduced", "undecided"],
        ]);
        let c = conflicts(&m);
        assert_eq!(c.len(), 1);
        let (a, b) = (&m.claims[c[0].claims.0], &m.claims[c[0].claims.1]);
        let mut ids = [a.id(), b.id()];
        ids.sort();
        assert_eq!(ids, ["fig2.v_peak", "waves-fig5.wave_speed"]);
    }

    #[test]
    fn the_decision_rule_needs_more_claims_and_the_headline() {
        // literal-labels reproduces 2 to the default's 1 but loses v: no change
        let m = map_of(&[
            ["reproduced", "not-reproduced", "reproduced"],
            ["not-reproduced", "reproduced", "not-reproduced"],
            ["not-reproduced", "reproduced", "not-reproduced"],
        ]);
        assert_eq!(decision(&m), None);
        // wall-sites keeps v and adds alpha: it wins
        let m = map_of(&[
            ["reproduced", "not-reproduced", "reproduced"],
            ["not-reproduced", "reproduced", "not-reproduced"],
            ["not-reproduced", "not-reproduced", "reproduced"],
        ]);
        assert_eq!(decision(&m), Some(2));
    }

    #[test]
    fn unknown_readings_are_named() {
        let e = select("default,nonsense").unwrap_err().to_string();
        assert!(
            e.contains("nonsense") && e.contains("literal-labels"),
            "{e}"
        );
        assert_eq!(select("wall-sites,default").unwrap()[0].0, "default");
        for (_, rules) in READINGS {
            rules.parse::<Rules>().unwrap();
        }
    }
}
