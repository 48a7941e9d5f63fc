//! Snapshots of the hopper shaded by orientation, as in BB90 Fig. 2: three
//! distinguishable shades for the three orientations, holes white, walls
//! dark, with a legend.

use super::energy::{orientation, ORIENTATION_NAMES};
use super::experiment::Record;
use super::geometry::Geometry;
use super::model::{grain_state, is_grain, WALL};
use super::observables::running_mean;
use crate::analysis::fit::LinearFit;
use crate::analysis::spectrum::frequency;
use crate::error::Result;
use crate::lattice::position;
use crate::plot::{chart_builder, draw_legend, line_chart, plot_err, png, Line, FONT, PALETTE};
use plotters::prelude::*;
use std::path::Path;

/// Shades of the orientations vertical, +60°, -60° (light, medium, dark;
/// also distinct in hue).
pub const ORIENTATION_SHADES: [RGBColor; 3] = [
    RGBColor(240, 200, 40),
    RGBColor(213, 94, 0),
    RGBColor(0, 90, 160),
];
/// Shade of the walls.
pub const WALL_SHADE: RGBColor = RGBColor(35, 35, 35);
/// Shade of the holes.
pub const HOLE_SHADE: RGBColor = RGBColor(255, 255, 255);

/// One panel: a caption and the site values of a snapshot.
#[derive(Debug, Clone)]
pub struct Panel {
    /// Caption above the panel, e.g. "(c) beta = 1, iteration 500".
    pub caption: String,
    /// Site values (`Hopper::sites`).
    pub sites: Vec<u8>,
}

impl Panel {
    /// The BB90 Fig. 2 panels: (a) the `beta0` run `snaps[1]` iterations
    /// after opening; (b) the `beta1` run half-way through the rain; (c-f)
    /// the `beta1` run at `snaps` (at most four), whose panels are captioned
    /// with its own `beta` (1 in the paper). A missing snapshot is drawn
    /// empty.
    pub fn fig2(beta0: &Record, beta1: &Record, beta: f64, snaps: &[u64]) -> Vec<Panel> {
        let blank = vec![0; beta1.mid_fill.len()];
        let snap = |rec: &Record, t| rec.snapshot(t).map_or(blank.clone(), <[u8]>::to_vec);
        let mut panels = vec![
            Panel {
                caption: format!("(a) beta = 0, iteration {}", snaps[1]),
                sites: snap(beta0, snaps[1]),
            },
            Panel {
                caption: format!("(b) filling, beta = {beta}"),
                sites: beta1.mid_fill.clone(),
            },
        ];
        for (k, &t) in snaps.iter().enumerate() {
            panels.push(Panel {
                caption: format!("({}) beta = {beta}, iteration {t}", ["c", "d", "e", "f"][k]),
                sites: snap(beta1, t),
            });
        }
        panels
    }
}

fn shade(site: u8) -> RGBColor {
    if site == WALL {
        WALL_SHADE
    } else if is_grain(site) {
        ORIENTATION_SHADES[orientation(grain_state(site))]
    } else {
        HOLE_SHADE
    }
}

/// Draw `panels` in a grid of `cols` columns with a title and a legend.
pub fn draw_snapshots(
    path: &Path,
    title: &str,
    geom: &Geometry,
    panels: &[Panel],
    cols: usize,
    scale: f64,
) -> Result<()> {
    let (w, h) = (geom.width(), geom.height());
    let phys_w = (w as f64 - 1.0) * 3f64.sqrt() / 2.0 + 1.0;
    let phys_h = h as f64 + 0.5;
    let pw = (phys_w * scale).ceil() as u32 + 10;
    let ph = (phys_h * scale).ceil() as u32 + 30;
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let (top, legend) = (50u32, 50u32);
    let size = (pw * cols as u32, top + ph * rows as u32 + legend);
    png(path, size, |root| {
        root.draw(&Text::new(
            title.to_string(),
            (10, 12),
            (FONT, 22).into_font().color(&BLACK),
        ))
        .map_err(plot_err)?;
        let (cw, chh) = (3f64.sqrt() / 2.0 * scale, scale);
        for (k, p) in panels.iter().enumerate() {
            let ox = (k % cols) as u32 * pw + 5;
            let oy = top + (k / cols) as u32 * ph;
            root.draw(&Text::new(
                p.caption.clone(),
                (ox as i32, oy as i32 + 2),
                (FONT, 16).into_font().color(&BLACK),
            ))
            .map_err(plot_err)?;
            let base_y = oy as f64 + 25.0 + phys_h * scale;
            for y in 0..h {
                for x in 0..w {
                    let (px, py) = position(x, y);
                    let x0 = ox as f64 + px * scale;
                    let y1 = base_y - py * scale;
                    let c = shade(p.sites[y * w + x]);
                    root.draw(&Rectangle::new(
                        [
                            (x0 as i32, (y1 - chh) as i32),
                            ((x0 + cw).ceil() as i32, y1.ceil() as i32),
                        ],
                        c.filled(),
                    ))
                    .map_err(plot_err)?;
                }
            }
        }
        // legend
        let ly = (top + ph * rows as u32 + 15) as i32;
        let mut lx = 10i32;
        let items: Vec<(String, RGBColor)> = ORIENTATION_NAMES
            .iter()
            .zip(ORIENTATION_SHADES)
            .map(|(n, c)| (format!("grain, orientation {n}"), c))
            .chain([
                ("hole".to_string(), HOLE_SHADE),
                ("wall".to_string(), WALL_SHADE),
            ])
            .collect();
        for (name, c) in items {
            root.draw(&Rectangle::new([(lx, ly), (lx + 20, ly + 20)], c.filled()))
                .map_err(plot_err)?;
            root.draw(&Rectangle::new([(lx, ly), (lx + 20, ly + 20)], BLACK))
                .map_err(plot_err)?;
            root.draw(&Text::new(
                name.clone(),
                (lx + 26, ly + 2),
                (FONT, 16).into_font().color(&BLACK),
            ))
            .map_err(plot_err)?;
            lx += 40 + 9 * name.chars().count() as i32;
        }
        Ok(())
    })
}

/// One series of a time chart: label, values per iteration, colour, width.
#[derive(Debug, Clone)]
pub struct TimeSeries {
    /// Legend label.
    pub label: String,
    /// Value at iteration t = index.
    pub values: Vec<f64>,
    /// Colour.
    pub color: RGBColor,
    /// Stroke width in pixels (1 for dense raw series: wider strokes of
    /// near-vertical segments draw miter spikes).
    pub width: u32,
}

/// A line chart of series against iteration (BB90 Fig. 3a/b).
pub fn time_chart(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[TimeSeries],
) -> Result<()> {
    let n = series
        .iter()
        .map(|s| s.values.len())
        .max()
        .unwrap_or(1)
        .max(2);
    let ymax = series
        .iter()
        .flat_map(|s| s.values.iter().copied())
        .fold(1.0f64, f64::max)
        * 1.08;
    png(path, (1100, 600), |root| {
        let mut chart = chart_builder(root, title, 70)
            .build_cartesian_2d(0.0..n as f64, 0.0..ymax)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .x_desc(xlabel)
            .y_desc(ylabel)
            .label_style((FONT, 16))
            .draw()
            .map_err(plot_err)?;
        for s in series {
            let color = s.color;
            let width = s.width;
            chart
                .draw_series(LineSeries::new(
                    s.values.iter().enumerate().map(|(t, &v)| (t as f64, v)),
                    color.stroke_width(width),
                ))
                .map_err(plot_err)?
                .label(s.label.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(3))
                });
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    })
}

/// Light grey for the raw series under its average.
const RAW_SHADE: RGBColor = RGBColor(170, 170, 170);

/// The outflow charts of BB90 Fig. 3 for the per-iteration outflow `q` of
/// one run of case `caption`: (a) to `path_a`, raw and averaged over 5
/// iterations; (b) to `path_b`, averaged over 11 iterations.
pub fn outflow_charts(path_a: &Path, path_b: &Path, caption: &str, q: &[f64]) -> Result<()> {
    let ts = |label: &str, values: Vec<f64>, color| TimeSeries {
        label: label.to_string(),
        values,
        color,
        width: 1,
    };
    let (x, y) = ("iterations after opening", "grains leaving per iteration");
    time_chart(
        path_a,
        &format!("BB90 Fig. 3a: grains leaving per iteration, {caption} (run 0)"),
        x,
        y,
        &[
            ts("raw", q.to_vec(), RAW_SHADE),
            ts("averaged over 5 iterations", running_mean(q, 5), PALETTE[0]),
        ],
    )?;
    time_chart(
        path_b,
        &format!("BB90 Fig. 3b: grains leaving per iteration averaged over 11 iterations, {caption} (run 0)"),
        x,
        y,
        &[ts("averaged over 11 iterations", running_mean(q, 11), PALETTE[1])],
    )
}

/// The power spectrum chart of BB90 Fig. 3: per case its caption, the
/// spectrum P(j), j = 0..m-1 (drawn from j = 1, log-log as log10 values)
/// and the fit over f <= 1/8 (j <= m/4).
pub fn spectrum_chart(path: &Path, spectra: &[(&str, &[f64], LinearFit)]) -> Result<()> {
    let mut lines = Vec::new();
    for (c, (cap, p, fit)) in spectra.iter().enumerate() {
        let m = p.len();
        let pts: Vec<(f64, f64)> = (1..m)
            .map(|j| (frequency(j, m).log10(), p[j].log10()))
            .collect();
        let fitted: Vec<(f64, f64)> = pts[..m / 4]
            .iter()
            .map(|&(lf, _)| (lf, fit.intercept + fit.slope * lf))
            .collect();
        lines.push(Line::new(cap, pts, PALETTE[c % PALETTE.len()]).markers());
        let label = format!(
            "fit f <= 1/8: slope {:.3} +- {:.3}",
            fit.slope, fit.slope_err
        );
        lines.push(Line::new(&label, fitted, PALETTE[c % PALETTE.len()]));
    }
    line_chart(
        path,
        "BB90 Fig. 3: power spectrum of the outflow (from 15% out until 30% remain)",
        "log10 frequency (cycles per iteration)",
        "log10 power (NR spctrm, averaged over runs)",
        &lines,
        false,
        SeriesLabelPosition::UpperRight,
    )
}
