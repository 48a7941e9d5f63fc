//! What the figures measure on the hopper (MODEL.md B6): the time-averaged
//! activity and occupancy (core width, stagnant sides), the orientational
//! order and its decay with distance, and the outflow statistics.

use super::energy::orientation;
use super::geometry::{Geometry, SiteKind, OFF};
use super::model::{grain_state, is_grain, Hopper};
use crate::error::{Error, ErrorKind, Result};

/// Time averages of activity (a grain that moved) and occupancy per site.
#[derive(Debug, Clone)]
pub struct Activity {
    width: usize,
    moving: Vec<u32>,
    occupied: Vec<u32>,
    frames: u32,
}

impl Activity {
    /// An empty accumulator for `geom`.
    pub fn new(geom: &Geometry) -> Self {
        let n = geom.kind.len();
        Activity {
            width: geom.width(),
            moving: vec![0; n],
            occupied: vec![0; n],
            frames: 0,
        }
    }

    /// Add the current state of `h` (after an iteration).
    pub fn record(&mut self, h: &Hopper) {
        for (i, &s) in h.sites().iter().enumerate() {
            if is_grain(s) {
                self.occupied[i] += 1;
                if h.moving(i) {
                    self.moving[i] += 1;
                }
            }
        }
        self.frames += 1;
    }

    /// Frames recorded.
    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Time-averaged activity of site `(x, y)`: the fraction of frames in which
    /// a grain there had just moved.
    pub fn activity(&self, x: usize, y: usize) -> f64 {
        self.moving[y * self.width + x] as f64 / self.frames.max(1) as f64
    }

    /// Time-averaged occupancy of site `(x, y)`.
    pub fn occupancy(&self, x: usize, y: usize) -> f64 {
        self.occupied[y * self.width + x] as f64 / self.frames.max(1) as f64
    }

    /// The activity profile across row `y`: `(x, activity)` for inside sites.
    pub fn profile(&self, geom: &Geometry, y: usize) -> Vec<(usize, f64)> {
        (0..geom.width())
            .filter(|&x| geom.kind[geom.index(x, y)] == SiteKind::Inside)
            .map(|x| (x, self.activity(x, y)))
            .collect()
    }

    /// The core at row `y`: columns `(left, right)` around the maximum of the
    /// activity profile where it stays at or above half its maximum.
    pub fn core(&self, geom: &Geometry, y: usize) -> Option<(usize, usize)> {
        let p = self.profile(geom, y);
        let (imax, &(_, amax)) = p
            .iter()
            .enumerate()
            .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))?;
        if amax <= 0.0 {
            return None;
        }
        let (mut l, mut r) = (imax, imax);
        while l > 0 && p[l - 1].1 >= 0.5 * amax {
            l -= 1;
        }
        while r + 1 < p.len() && p[r + 1].1 >= 0.5 * amax {
            r += 1;
        }
        Some((p[l].0, p[r].0))
    }

    /// Core width at row `y`: the full width at half maximum of the activity
    /// profile, in lattice spacings (columns x sqrt(3)/2); 0 if no activity.
    pub fn core_width(&self, geom: &Geometry, y: usize) -> f64 {
        match self.core(geom, y) {
            Some((l, r)) => (r - l + 1) as f64 * 3f64.sqrt() / 2.0,
            None => 0.0,
        }
    }

    /// Mean occupancy inside the core and at the sides (inside sites outside
    /// the core) over rows `ys`, the core taken row by row.
    pub fn core_and_side_occupancy(&self, geom: &Geometry, ys: &[usize]) -> (f64, f64) {
        let (mut c, mut nc, mut s, mut ns) = (0.0, 0usize, 0.0, 0usize);
        for &y in ys {
            let Some((l, r)) = self.core(geom, y) else {
                continue;
            };
            for (x, _) in self.profile(geom, y) {
                if (l..=r).contains(&x) {
                    c += self.occupancy(x, y);
                    nc += 1;
                } else {
                    s += self.occupancy(x, y);
                    ns += 1;
                }
            }
        }
        (c / nc.max(1) as f64, s / ns.max(1) as f64)
    }

    /// Activity at the centre (mean over the 3 central columns) and near the
    /// walls (mean over the `band` inside sites next to each wall) of row `y`.
    pub fn centre_and_wall_activity(&self, geom: &Geometry, y: usize, band: usize) -> (f64, f64) {
        let p = self.profile(geom, y);
        if p.is_empty() {
            return (0.0, 0.0);
        }
        let c0 = geom.centre_column;
        let centre: Vec<f64> = p
            .iter()
            .filter(|(x, _)| x.abs_diff(c0) <= 1)
            .map(|&(_, a)| a)
            .collect();
        let band = band.min(p.len() / 2).max(1);
        let wall: Vec<f64> = p[..band]
            .iter()
            .chain(p[p.len() - band..].iter())
            .map(|&(_, a)| a)
            .collect();
        let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
        (mean(&centre), mean(&wall))
    }
}

/// The orientational order parameter: the fraction of neighbouring grain
/// pairs with equal orientation (1/3 for random orientations).
pub fn order_parameter(h: &Hopper) -> f64 {
    orientation_correlation(h, 1)[0]
}

/// g(r) for r = 1..=rmax: the fraction of grain pairs r steps apart along a
/// lattice axis (up, up-left, up-right) with equal orientation; NaN when no
/// pair exists at that distance.
pub fn orientation_correlation(h: &Hopper, rmax: usize) -> Vec<f64> {
    orientation_correlation_of(h.geometry(), h.sites(), rmax)
}

/// [`orientation_correlation`] of the site values `sites` of any engine
/// on the container `g` (the engine contract, [`super::engine`]).
pub fn orientation_correlation_of(g: &Geometry, sites: &[u8], rmax: usize) -> Vec<f64> {
    let mut equal = vec![0u64; rmax];
    let mut pairs = vec![0u64; rmax];
    for (i, &si) in sites.iter().enumerate() {
        if !is_grain(si) {
            continue;
        }
        let oi = orientation(grain_state(si));
        for c in [0usize, 1, 5] {
            let mut j = i as u32;
            for r in 0..rmax {
                j = g.nbr[j as usize][c];
                if j == OFF {
                    break;
                }
                let sj = sites[j as usize];
                if is_grain(sj) {
                    pairs[r] += 1;
                    if orientation(grain_state(sj)) == oi {
                        equal[r] += 1;
                    }
                }
            }
        }
    }
    equal
        .iter()
        .zip(&pairs)
        .map(|(&e, &p)| {
            if p == 0 {
                f64::NAN
            } else {
                e as f64 / p as f64
            }
        })
        .collect()
}

/// The V shape of the upper free surface (BB90 Fig. 2a, Figs. 2c-f): with
/// top(x) the highest grain of column x (drawn coordinates, mean over
/// columns x-1..=x+1) and q = width/6 columns, the slope
/// [(top(c - q) + top(c + q))/2 - top(c)] / (q sqrt(3)/2) about the outlet
/// column c: 0 for a flat surface, tan of the surface angle for a V; NaN
/// when one of those columns holds no grain.
pub fn surface_slope(g: &Geometry, sites: &[u8]) -> f64 {
    let w = g.width();
    let q = w / 6;
    let c = g.centre_column;
    if q == 0 || c < q + 1 || c + q + 1 >= w || sites.len() != g.kind.len() {
        return f64::NAN;
    }
    let top_column = |x: usize| -> Option<f64> {
        (0..g.height())
            .rev()
            .find(|&y| is_grain(sites[g.index(x, y)]))
            .map(|y| y as f64 + 0.5 * (x % 2) as f64)
    };
    let top = |x: usize| -> Option<f64> {
        let t: Option<Vec<f64>> = (x - 1..=x + 1).map(top_column).collect();
        t.map(|t| t.iter().sum::<f64>() / 3.0)
    };
    match (top(c - q), top(c), top(c + q)) {
        (Some(l), Some(m), Some(r)) => (0.5 * (l + r) - m) / (q as f64 * 3f64.sqrt() / 2.0),
        _ => f64::NAN,
    }
}

/// Defects in the body of the material (BB90 abstract): holes inside the
/// container whose six neighbours are all grains or walls, per 1000 grains;
/// NaN when there are no grains.
pub fn enclosed_vacancies(g: &Geometry, sites: &[u8]) -> f64 {
    if sites.len() != g.kind.len() {
        return f64::NAN;
    }
    let grains = sites.iter().filter(|&&s| is_grain(s)).count();
    if grains == 0 {
        return f64::NAN;
    }
    let enclosed = (0..sites.len())
        .filter(|&i| {
            g.kind[i] == SiteKind::Inside
                && sites[i] == super::model::HOLE
                && g.nbr[i]
                    .iter()
                    .all(|&j| j == OFF || sites[j as usize] != super::model::HOLE)
        })
        .count();
    1000.0 * enclosed as f64 / grains as f64
}

/// Correlation length of the orientation: the distance at which the excess
/// g(r) - 1/3 first falls below 1/e of its value at r = 1 (linear
/// interpolation; `rmax` when it never does; 0 when g(1) <= 1/3).
pub fn correlation_length(g: &[f64]) -> f64 {
    let third = 1.0 / 3.0;
    if g.is_empty() || g[0].is_nan() || g[0] <= third {
        return 0.0;
    }
    let level = (g[0] - third) / std::f64::consts::E;
    for r in 1..g.len() {
        let (a, b) = (g[r - 1] - third, g[r] - third);
        if !b.is_finite() {
            return r as f64;
        }
        if b < level {
            return r as f64 + (a - level) / (a - b);
        }
    }
    g.len() as f64
}

/// Mean rates of the outflow per iteration over a window, with standard
/// errors from block means (blocks of `block` iterations), so short-range
/// correlations do not shrink the error.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutflowStats {
    /// Mean grains per iteration over the window.
    pub mean: f64,
    /// Standard deviation of the per-iteration outflow.
    pub sd: f64,
    /// Mean of the first half of the window.
    pub first: f64,
    /// Standard error of `first`.
    pub first_se: f64,
    /// Mean of the second half of the window.
    pub second: f64,
    /// Standard error of `second`.
    pub second_se: f64,
    /// Iterations in the window.
    pub len: usize,
}

impl OutflowStats {
    /// Statistics of `series`, blocks of `block` iterations (at least two
    /// blocks per half are required).
    pub fn new(series: &[f64], block: usize) -> Result<Self> {
        let block = block.max(1);
        if series.len() < 4 * block {
            return Err(Error::new(
                ErrorKind::BadSeries,
                format!(
                    "outflow window of {} iterations is shorter than 4 blocks of {block}; run a larger hopper or a smaller block",
                    series.len()
                ),
            ));
        }
        let n = series.len();
        let mean = series.iter().sum::<f64>() / n as f64;
        let sd = (series.iter().map(|q| (q - mean).powi(2)).sum::<f64>() / (n as f64 - 1.0)).sqrt();
        let half = |xs: &[f64]| {
            let means: Vec<f64> = xs
                .chunks_exact(block)
                .map(|b| b.iter().sum::<f64>() / block as f64)
                .collect();
            crate::run::mean_sem(&means)
        };
        let (first, first_se) = half(&series[..n / 2]);
        let (second, second_se) = half(&series[n / 2..]);
        Ok(OutflowStats {
            mean,
            sd,
            first,
            first_se,
            second,
            second_se,
            len: n,
        })
    }

    /// The statistics of an ensemble of windows (at least one): each mean
    /// the mean over the windows, each standard error the root of the sum
    /// of their squares over the number of windows, `len` the shortest.
    pub fn combine(stats: &[OutflowStats]) -> OutflowStats {
        let n = stats.len() as f64;
        let avg = |f: &dyn Fn(&OutflowStats) -> f64| stats.iter().map(f).sum::<f64>() / n;
        let comb = |f: &dyn Fn(&OutflowStats) -> f64| {
            stats.iter().map(|s| f(s).powi(2)).sum::<f64>().sqrt() / n
        };
        OutflowStats {
            mean: avg(&|s| s.mean),
            sd: avg(&|s| s.sd),
            first: avg(&|s| s.first),
            first_se: comb(&|s| s.first_se),
            second: avg(&|s| s.second),
            second_se: comb(&|s| s.second_se),
            len: stats.iter().map(|s| s.len).min().unwrap_or(0),
        }
    }

    /// (second - first) in units of their combined standard error.
    pub fn trend_z(&self) -> f64 {
        (self.second - self.first) / (self.first_se.powi(2) + self.second_se.powi(2)).sqrt()
    }
}

/// Centred running mean over `w` iterations (shorter at the ends).
pub fn running_mean(series: &[f64], w: usize) -> Vec<f64> {
    let h = w / 2;
    (0..series.len())
        .map(|t| {
            let a = t.saturating_sub(h);
            let b = (t + h + 1).min(series.len());
            series[a..b].iter().sum::<f64>() / (b - a) as f64
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn correlation_length_of_an_exponential() {
        let g: Vec<f64> = (1..=20)
            .map(|r| 1.0 / 3.0 + 0.5 * (-(r as f64 - 1.0) / 4.0).exp())
            .collect();
        let xi = correlation_length(&g);
        assert!((xi - 5.0).abs() < 0.2, "{xi}");
    }
}
