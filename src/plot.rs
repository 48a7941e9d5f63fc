//! Plotting: PNG charts with an embedded font (DejaVu Sans, registered once),
//! so nothing depends on system fonts.
//!
//! Generic helpers only: line charts (linear or log-log) and gray-scale
//! space-time images. Model-specific pictures live beside their model.

use crate::error::{Error, ErrorKind, Result};
use plotters::coord::ranged1d::ValueFormatter;
use plotters::coord::{CoordTranslate, Shift};
use plotters::prelude::*;
use plotters::style::FontStyle;
use std::path::Path;
use std::sync::{Once, RwLock};

/// Font family name under which the embedded font is registered.
pub const FONT: &str = "sans-serif";

static REGISTER: Once = Once::new();

/// Text appended in brackets to every chart title this process draws (e.g.
/// `fast engine`), so that a PNG names what made it; empty: nothing.
static CAPTION_NOTE: RwLock<String> = RwLock::new(String::new());

/// Append `[note]` to every chart title drawn from now on (empty: none). The
/// figure plumbing sets the pipe engine here (`cli::PipeRules::engine`).
pub fn set_caption_note(note: &str) {
    if let Ok(mut n) = CAPTION_NOTE.write() {
        *n = note.to_string();
    }
}

/// `title` with the caption note of [`set_caption_note`], if any.
pub fn captioned(title: &str) -> String {
    match CAPTION_NOTE.read() {
        Ok(n) if !n.is_empty() => format!("{title} [{n}]"),
        _ => title.to_string(),
    }
}

/// The paper's claims about the figure a process draws, written under every
/// PNG it draws ([`set_published_note`]); empty: nothing.
static PUBLISHED_NOTE: RwLock<String> = RwLock::new(String::new());

/// Write `note` (what the paper publishes about the figure) in a strip under
/// every PNG drawn from now on (empty: none). Set by `run::Figure::start`.
pub fn set_published_note(note: &str) {
    if let Ok(mut n) = PUBLISHED_NOTE.write() {
        *n = note.to_string();
    }
}

/// `text` broken at spaces into lines of at most `width` characters.
pub fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(l) if l.chars().count() + 1 + word.chars().count() <= width => {
                l.push(' ');
                l.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

/// Register the embedded DejaVu Sans font with plotters (idempotent).
pub fn register_fonts() {
    REGISTER.call_once(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular())
            .map_err(|_| ())
            .expect("embedded DejaVu Sans is a valid font");
        plotters::style::register_font(FONT, FontStyle::Bold, dejavu::sans::bold())
            .map_err(|_| ())
            .expect("embedded DejaVu Sans Bold is a valid font");
    });
}

/// Turn any plotting error into the library's error type.
pub fn plot_err<E: std::fmt::Display>(e: E) -> Error {
    Error::new(ErrorKind::Io, format!("plotting failed: {e}"))
}

/// Draw a PNG of `size` pixels to `path`: a white background, then `draw`;
/// with a published note ([`set_published_note`]), a strip that states it is
/// added under the `size` pixels that `draw` gets.
pub fn png(
    path: &Path,
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<BitMapBackend, Shift>) -> Result<()>,
) -> Result<()> {
    register_fonts();
    let note = PUBLISHED_NOTE.read().map(|n| n.clone()).unwrap_or_default();
    // DejaVu Sans at 14 px averages about 7.7 px per character
    let lines = if note.is_empty() {
        Vec::new()
    } else {
        wrap(
            &format!("Published in {note}"),
            ((size.0 as f64 - 20.0) / 7.7) as usize,
        )
    };
    let strip = if lines.is_empty() {
        0
    } else {
        8 + 18 * lines.len() as u32
    };
    let root = BitMapBackend::new(path, (size.0, size.1 + strip)).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
    let (top, foot) = root.split_vertically(size.1);
    draw(&top)?;
    if strip > 0 {
        foot.fill(&RGBColor(244, 244, 244)).map_err(plot_err)?;
        for (i, line) in lines.iter().enumerate() {
            foot.draw(&Text::new(
                line.clone(),
                (10, 4 + 18 * i as i32),
                (FONT, 14).into_font().color(&BLACK),
            ))
            .map_err(plot_err)?;
        }
    }
    root.present().map_err(plot_err)?;
    Ok(())
}

/// The font size, at most `max`, at which `title` fits into `width` pixels
/// (DejaVu Sans averages about 0.55 em per character), at least 11.
pub fn caption_size(title: &str, width: u32, max: f64) -> f64 {
    let chars = title.chars().count().max(1) as f64;
    ((width as f64 - 30.0) / (0.55 * chars)).clamp(11.0, max)
}

/// A chart builder in the house style: `title` in 20 pt (smaller if it
/// would not fit), a margin of 15 pixels (35 on the right, where the last
/// x tick label is centred on the edge), 50 pixels for the x labels and
/// `y_labels` for the y labels.
pub fn chart_builder<'a, 'b, DB: DrawingBackend>(
    root: &'a DrawingArea<DB, Shift>,
    title: &str,
    y_labels: u32,
) -> ChartBuilder<'a, 'b, DB> {
    let mut builder = ChartBuilder::on(root);
    let title = captioned(title);
    let size = caption_size(&title, root.dim_in_pixel().0, 20.0);
    builder
        .caption(title, (FONT, size))
        .margin(15)
        // room for the last x tick label, centred on the right edge
        .margin_right(35)
        .x_label_area_size(50)
        .y_label_area_size(y_labels);
    builder
}

/// The legend of a chart's labelled series, in the house style, at `position`.
pub fn draw_legend<'a, DB: DrawingBackend + 'a, CT: CoordTranslate>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<()> {
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((FONT, 16))
        .position(position)
        .draw()
        .map_err(plot_err)
}

/// Axes with tick labels ([`tick`]) and descriptions, in the house style.
fn draw_axes<DB: DrawingBackend, X, Y>(
    chart: &mut ChartContext<DB, Cartesian2d<X, Y>>,
    xlabel: &str,
    ylabel: &str,
    log: bool,
) -> Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_label_formatter(&|v: &f64| tick(*v, log))
        .y_label_formatter(&|v: &f64| tick(*v, log))
        .x_desc(xlabel)
        .y_desc(ylabel)
        .label_style((FONT, 16))
        .draw()
        .map_err(plot_err)
}

/// The smallest and the largest of all `values` (infinities when empty).
pub fn value_range(values: &[Vec<f64>]) -> (f64, f64) {
    let all = || values.iter().flatten().copied();
    (
        all().fold(f64::INFINITY, f64::min),
        all().fold(f64::NEG_INFINITY, f64::max),
    )
}

/// A named line of a chart.
#[derive(Debug, Clone)]
pub struct Line {
    /// Legend label.
    pub label: String,
    /// Points (x, y).
    pub points: Vec<(f64, f64)>,
    /// Colour.
    pub color: RGBColor,
    /// Draw as points (circles) instead of a connected line.
    pub markers: bool,
}

impl Line {
    /// A connected line.
    pub fn new(label: &str, points: Vec<(f64, f64)>, color: RGBColor) -> Self {
        Line {
            label: label.to_string(),
            points,
            color,
            markers: false,
        }
    }

    /// Drawn as markers.
    pub fn markers(mut self) -> Self {
        self.markers = true;
        self
    }
}

/// Points `(x[i], y[i])`.
pub fn points(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    x.iter().copied().zip(y.iter().copied()).collect()
}

/// A mean curve `mean` with standard errors `sem` at `x`: the line
/// `label` in `color`, then the lines "mean + 1 SE" (orange) and
/// "mean - 1 SE" (green).
pub fn mean_se_lines(
    label: &str,
    x: &[f64],
    mean: &[f64],
    sem: &[f64],
    color: RGBColor,
) -> Vec<Line> {
    let pts = |s: f64| {
        x.iter()
            .zip(mean.iter().zip(sem))
            .map(|(&x, (&m, &e))| (x, m + s * e))
            .collect()
    };
    vec![
        Line::new(label, pts(0.0), color),
        Line::new("mean + 1 SE", pts(1.0), PALETTE[4]),
        Line::new("mean - 1 SE", pts(-1.0), PALETTE[2]),
    ]
}

/// A palette of distinguishable colours.
pub const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 90, 181),
    RGBColor(220, 50, 32),
    RGBColor(0, 150, 60),
    RGBColor(150, 60, 170),
    RGBColor(230, 140, 0),
    RGBColor(60, 60, 60),
];

fn bounds(lines: &[Line], log: bool) -> ((f64, f64), (f64, f64)) {
    let mut xs = (f64::INFINITY, f64::NEG_INFINITY);
    let mut ys = (f64::INFINITY, f64::NEG_INFINITY);
    for l in lines {
        for &(x, y) in &l.points {
            if !x.is_finite() || !y.is_finite() || (log && (x <= 0.0 || y <= 0.0)) {
                continue;
            }
            xs = (xs.0.min(x), xs.1.max(x));
            ys = (ys.0.min(y), ys.1.max(y));
        }
    }
    if !xs.0.is_finite() {
        xs = (1.0, 10.0);
        ys = (1.0, 10.0);
    }
    if xs.0 == xs.1 {
        xs = (xs.0 - 1.0, xs.1 + 1.0);
    }
    if ys.0 == ys.1 {
        ys = (ys.0 - 1.0, ys.1 + 1.0);
    }
    if log {
        ((xs.0, xs.1 * 1.05), (ys.0 / 1.5, ys.1 * 1.5))
    } else {
        let pad = 0.05 * (ys.1 - ys.0);
        ((xs.0, xs.1), (ys.0 - pad, ys.1 + pad))
    }
}

/// Tick label: plain numbers on linear axes, `1e-3` style on log axes
/// outside [0.01, 10^5].
fn tick(v: f64, log: bool) -> String {
    let a = v.abs();
    if !log && a < 1e-9 {
        "0".to_string()
    } else if log && !(0.01..1e5).contains(&a) {
        format!("{v:.0e}")
    } else if a >= 100.0 || (log && a >= 1.0) {
        format!("{v:.0}")
    } else {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    }
}

/// Draw a line chart to `path` (PNG) with the legend at `legend`. `log`
/// makes both axes logarithmic.
pub fn line_chart(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    lines: &[Line],
    log: bool,
    legend: SeriesLabelPosition,
) -> Result<()> {
    let ((x0, x1), (y0, y1)) = bounds(lines, log);
    png(path, (900, 650), |root| {
        let mut builder = chart_builder(root, title, 80);
        if log {
            let chart = builder
                .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
                .map_err(plot_err)?;
            draw_lines(chart, xlabel, ylabel, lines, log, legend)
        } else {
            let chart = builder
                .build_cartesian_2d(x0..x1, y0..y1)
                .map_err(plot_err)?;
            draw_lines(chart, xlabel, ylabel, lines, log, legend)
        }
    })
}

/// The axes, `lines` and legend of [`line_chart`] (linear or log-log).
fn draw_lines<'a, DB: DrawingBackend + 'a, X, Y>(
    mut chart: ChartContext<'a, DB, Cartesian2d<X, Y>>,
    xlabel: &str,
    ylabel: &str,
    lines: &[Line],
    log: bool,
    legend: SeriesLabelPosition,
) -> Result<()>
where
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    draw_axes(&mut chart, xlabel, ylabel, log)?;
    for l in lines {
        let pts: Vec<(f64, f64)> = l
            .points
            .iter()
            .copied()
            .filter(|&(x, y)| x.is_finite() && y.is_finite() && (!log || (x > 0.0 && y > 0.0)))
            .collect();
        let color = l.color;
        // a line without a label stays out of the legend
        if l.markers {
            let drawn = chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, color.filled())))
                .map_err(plot_err)?;
            if !l.label.is_empty() {
                drawn
                    .label(l.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
            }
        } else {
            let drawn = chart
                .draw_series(LineSeries::new(pts, color.stroke_width(2)))
                .map_err(plot_err)?;
            if !l.label.is_empty() {
                drawn.label(l.label.clone()).legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            }
        }
    }
    draw_legend(&mut chart, legend)
}

/// A gray-scale image of a field `values[t][i]` (time samples x bins),
/// drawn with time along the horizontal axis and bins along the vertical.
#[derive(Debug, Clone)]
pub struct SpaceTime<'a> {
    /// Samples: `values[t][i]`, bin `i` at time sample `t`.
    pub values: &'a [Vec<f64>],
    /// Value drawn white.
    pub white: f64,
    /// Value drawn black.
    pub black: f64,
    /// Time of sample `t` is `t0 + t * dt`.
    pub t0: f64,
    /// Time between samples.
    pub dt: f64,
    /// Rows per bin (for the vertical axis in rows).
    pub rows_per_bin: f64,
    /// Draw time running right to left (as in PH94 Fig. 1).
    pub time_right_to_left: bool,
    /// Draw bin 0 (the bottom of the pipe) at the bottom of the image, so
    /// gravity points from the top of the image to its bottom.
    pub bottom_at_bottom: bool,
}

impl SpaceTime<'_> {
    /// Draw onto a drawing area with axes, title and labels.
    pub fn draw<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, plotters::coord::Shift>,
        title: &str,
    ) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        register_fonts();
        let nt = self.values.len().max(1);
        let nb = self.values.first().map(|v| v.len()).unwrap_or(1).max(1);
        let t_first = self.t0;
        let t_last = self.t0 + (nt as f64) * self.dt;
        let (xa, xb) = if self.time_right_to_left {
            (t_last, t_first)
        } else {
            (t_first, t_last)
        };
        let height = nb as f64 * self.rows_per_bin;
        let title = captioned(title);
        let mut chart = ChartBuilder::on(area)
            .caption(
                &title,
                (FONT, caption_size(&title, area.dim_in_pixel().0, 17.0)),
            )
            .margin(8)
            .x_label_area_size(40)
            .y_label_area_size(65)
            .build_cartesian_2d(xa..xb, 0.0..height)
            .map_err(plot_err)?;
        let time_label = if self.time_right_to_left {
            "time (steps), runs right to left"
        } else {
            "time (steps), runs left to right"
        };
        chart
            .configure_mesh()
            .disable_mesh()
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .x_desc(time_label)
            .y_desc("height y (rows), gravity downwards")
            .label_style((FONT, 13))
            .draw()
            .map_err(plot_err)?;
        // pixel-exact fill: map each pixel of the plotting area to a cell
        let plot = chart.plotting_area();
        let (px, py) = plot.dim_in_pixel();
        let span = (self.black - self.white).abs().max(1e-12);
        for ix in 0..px {
            let fx = (ix as f64 + 0.5) / px as f64;
            let ft = if self.time_right_to_left {
                1.0 - fx
            } else {
                fx
            };
            let t = ((ft * nt as f64) as usize).min(nt - 1);
            for iy in 0..py {
                let fy = (iy as f64 + 0.5) / py as f64; // 0 at top
                let fb = if self.bottom_at_bottom { 1.0 - fy } else { fy };
                let b = ((fb * nb as f64) as usize).min(nb - 1);
                let v = self.values[t][b];
                let level = ((v - self.white) / span).clamp(0.0, 1.0);
                let g = (255.0 * (1.0 - level)).round() as u8;
                let (x, y) = plot.get_base_pixel();
                area.draw_pixel(
                    (
                        x + ix as i32 - area.get_base_pixel().0,
                        y + iy as i32 - area.get_base_pixel().1,
                    ),
                    &RGBColor(g, g, g),
                )
                .map_err(plot_err)?;
            }
        }
        Ok(())
    }
}

/// Horizontal axis of the pipe pictures with gravity from left to right.
const PIPE_ACROSS: &str =
    "distance from the top of the pipe, L - y (rows); gravity points left to right";

/// Density profiles of a pipe stacked upward, one per time (PH95 Fig. 2a):
/// profile j is drawn as `profiles[j].1 - centre` raised by `j * offset`
/// against the distance from the top of the pipe `x` (gravity from left to
/// right, x from 0 to `length`), in the colours of the palette, labelled
/// `profiles[j].0` at its left end.
pub fn stacked_profiles(
    path: &Path,
    title: &str,
    ylabel: &str,
    length: f64,
    x: &[f64],
    profiles: &[(String, &[f64])],
    (centre, offset): (f64, f64),
) -> Result<()> {
    png(path, (1100, 900), |root| {
        let top = profiles.len() as f64 * offset;
        let mut chart = chart_builder(root, title, 80)
            .build_cartesian_2d(0.0..length, -offset..top)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(PIPE_ACROSS)
            .y_desc(ylabel)
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style((FONT, 15))
            .draw()
            .map_err(plot_err)?;
        for (j, (label, n)) in profiles.iter().enumerate() {
            let base = j as f64 * offset;
            let pts: Vec<(f64, f64)> = x
                .iter()
                .zip(*n)
                .map(|(&x, &v)| (x, base + v - centre))
                .collect();
            chart
                .draw_series(LineSeries::new(
                    pts,
                    PALETTE[j % PALETTE.len()].stroke_width(2),
                ))
                .map_err(plot_err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    label.clone(),
                    (0.01 * length, base + 0.35 * offset),
                    (FONT, 14),
                )))
                .map_err(plot_err)?;
        }
        Ok(())
    })
}

/// The space-time plot of a pipe's bin densities `values[t][i]` (sample t
/// at time t * `dt`, bin i of `rows_per_bin` rows from the bottom) with
/// time upward and gravity from left to right (PH95 Fig. 2b): gray level
/// linear from white at `white` to black at `black`.
pub fn space_time_upward(
    path: &Path,
    title: &str,
    values: &[Vec<f64>],
    dt: u64,
    rows_per_bin: usize,
    (white, black): (f64, f64),
) -> Result<()> {
    let bins = values.first().map_or(0, |v| v.len());
    let (l, bin) = ((bins * rows_per_bin) as f64, rows_per_bin as f64);
    png(path, (1100, 900), |root| {
        let tmax = (values.len() as u64 * dt) as f64;
        let mut chart = chart_builder(root, title, 80)
            .build_cartesian_2d(0.0..l, 0.0..tmax)
            .map_err(plot_err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc(PIPE_ACROSS)
            .y_desc("time t (steps), upward")
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| format!("{v:.0}"))
            .label_style((FONT, 15))
            .draw()
            .map_err(plot_err)?;
        let span = (black - white).max(1e-9);
        chart
            .draw_series(values.iter().enumerate().flat_map(|(t, v)| {
                v.iter().enumerate().map(move |(i, &x)| {
                    let g = (255.0 * (1.0 - (x - white) / span)).round() as u8;
                    let x0 = l - (i as f64 + 1.0) * bin;
                    let t0 = (t as u64 * dt) as f64;
                    Rectangle::new(
                        [(x0, t0), (x0 + bin, t0 + dt as f64)],
                        RGBColor(g, g, g).filled(),
                    )
                })
            }))
            .map_err(plot_err)?;
        Ok(())
    })
}

/// A series of points with symmetric vertical error bars: `(x, y, err)`.
#[derive(Debug, Clone)]
pub struct ErrSeries {
    /// Legend label.
    pub label: String,
    /// Points (x, y, one standard error of y); non-finite points are skipped.
    pub points: Vec<(f64, f64, f64)>,
    /// Colour.
    pub color: RGBColor,
}

impl ErrSeries {
    /// A series of points with error bars, joined by a thin line.
    pub fn new(label: &str, points: Vec<(f64, f64, f64)>, color: RGBColor) -> Self {
        ErrSeries {
            label: label.to_string(),
            points,
            color,
        }
    }
}

/// Draw points with vertical error bars (y +- err), joined by thin lines,
/// on linear axes to `path` (PNG), legend in the corner that covers the
/// fewest points ([`free_corner`]).
pub fn errorbar_chart(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[ErrSeries],
) -> Result<()> {
    errorbar_chart_at(path, title, xlabel, ylabel, series, free_corner(series))
}

/// The legend corner of an error-bar chart that hides the fewest points and
/// error-bar ends: the legend box is taken as 45% of the width and 8% of the
/// height per series (plus 6%), the data scaled to the chart's bounds. Ties
/// go to upper right, upper left, lower right, lower left, in that order.
pub fn free_corner(series: &[ErrSeries]) -> SeriesLabelPosition {
    free_corner_rows(series, series.len())
}

/// [`free_corner`] for a legend of `rows` lines.
pub fn free_corner_rows(series: &[ErrSeries], rows: usize) -> SeriesLabelPosition {
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|&&(x, y, _)| x.is_finite() && y.is_finite())
        .flat_map(|&(x, y, e)| {
            let e = if e.is_finite() { e } else { 0.0 };
            [(x, y), (x, y - e), (x, y + e)]
        })
        .collect();
    let envelope = [Line::new("", pts.clone(), PALETTE[0])];
    let ((x0, x1), (y0, y1)) = bounds(&envelope, false);
    let xpad = 0.04 * (x1 - x0);
    let (x0, x1) = (x0 - xpad, x1 + xpad);
    let (w, h) = (0.45, 0.06 + 0.08 * rows as f64);
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let hidden = |right: bool, upper: bool| {
        pts.iter()
            .filter(|&&(x, y)| {
                let (u, v) = ((x - x0) / (x1 - x0), (y - y0) / (y1 - y0));
                (if right { u >= 1.0 - w } else { u <= w })
                    && (if upper { v >= 1.0 - h } else { v <= h })
            })
            .count()
    };
    corners
        .into_iter()
        .min_by_key(|&(_, right, upper)| hidden(right, upper))
        .map(|c| c.0)
        .expect("four corners")
}

/// [`errorbar_chart`] with the legend at `legend`.
pub fn errorbar_chart_at(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[ErrSeries],
    legend: SeriesLabelPosition,
) -> Result<()> {
    let none = Marks::default();
    errorbar_chart_marked(path, title, xlabel, ylabel, series, &none, legend)
}

/// Boxes of the values a claim allows: (x, lowest, highest).
pub type Boxes = Vec<(f64, f64, f64)>;

/// What a paper publishes about an error-bar chart's points: boxes of the
/// values a claim allows, and claims without a number as legend lines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Marks {
    /// One entry per claim wording: its legend label and its boxes
    /// (x, lowest, highest allowed value).
    pub bands: Vec<(String, Boxes)>,
    /// Claims without a number, one legend line each.
    pub notes: Vec<String>,
}

impl Marks {
    /// The legend lines the marks add.
    pub fn rows(&self) -> usize {
        self.bands.len() + self.notes.len()
    }
}

/// Fill colours of the published boxes, one per claim wording.
const BAND_COLORS: [RGBColor; 3] = [
    RGBColor(150, 150, 150),
    RGBColor(230, 170, 60),
    RGBColor(120, 190, 120),
];

/// [`errorbar_chart_at`] with the published `marks` drawn under the points.
pub fn errorbar_chart_marked(
    path: &Path,
    title: &str,
    xlabel: &str,
    ylabel: &str,
    series: &[ErrSeries],
    marks: &Marks,
    legend: SeriesLabelPosition,
) -> Result<()> {
    let finite = |s: &ErrSeries| -> Vec<(f64, f64, f64)> {
        s.points
            .iter()
            .copied()
            .filter(|&(x, y, _)| x.is_finite() && y.is_finite())
            .map(|(x, y, e)| (x, y, if e.is_finite() { e } else { 0.0 }))
            .collect()
    };
    // bounds include the ends of the error bars
    let envelope: Vec<Line> = series
        .iter()
        .map(|s| {
            let pts = finite(s)
                .iter()
                .flat_map(|&(x, y, e)| [(x, y - e), (x, y + e)])
                .collect();
            Line::new("", pts, s.color)
        })
        .chain(marks.bands.iter().map(|(_, boxes)| {
            let pts = boxes
                .iter()
                .flat_map(|&(x, lo, hi)| [(x, lo), (x, hi)])
                .collect();
            Line::new("", pts, BLACK)
        }))
        .collect();
    let ((x0, x1), (y0, y1)) = bounds(&envelope, false);
    let xpad = 0.04 * (x1 - x0);
    png(path, (900, 650), |root| {
        let mut chart = chart_builder(root, title, 80)
            .build_cartesian_2d((x0 - xpad)..(x1 + xpad), y0..y1)
            .map_err(plot_err)?;
        draw_axes(&mut chart, xlabel, ylabel, false)?;
        let half = 0.02 * (x1 - x0 + 2.0 * xpad);
        for (i, (label, boxes)) in marks.bands.iter().enumerate() {
            let fill = BAND_COLORS[i % BAND_COLORS.len()].mix(0.45);
            chart
                .draw_series(
                    boxes
                        .iter()
                        .filter(|b| b.0.is_finite())
                        .map(|&(x, lo, hi)| {
                            Rectangle::new([(x - half, lo), (x + half, hi)], fill.filled())
                        }),
                )
                .map_err(plot_err)?
                .label(label.clone())
                .legend(move |(x, y)| {
                    Rectangle::new([(x + 4, y - 6), (x + 16, y + 6)], fill.filled())
                });
        }
        for note in &marks.notes {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(plot_err)?
                .label(note.clone())
                .legend(|(x, y)| Text::new("*", (x + 6, y - 8), (FONT, 16).into_font()));
        }
        for s in series {
            let pts = finite(s);
            let color = s.color;
            chart
                .draw_series(LineSeries::new(
                    pts.iter().map(|&(x, y, _)| (x, y)),
                    color.stroke_width(1),
                ))
                .map_err(plot_err)?;
            chart
                .draw_series(pts.iter().map(|&(x, y, e)| {
                    PathElement::new(vec![(x, y - e), (x, y + e)], color.stroke_width(2))
                }))
                .map_err(plot_err)?;
            // caps: short horizontal strokes at both ends, 1.5% of the x range
            let cap = 0.015 * (x1 - x0 + 2.0 * xpad);
            chart
                .draw_series(pts.iter().flat_map(|&(x, y, e)| {
                    [y - e, y + e].map(|yy| {
                        PathElement::new(vec![(x - cap, yy), (x + cap, yy)], color.stroke_width(2))
                    })
                }))
                .map_err(plot_err)?;
            chart
                .draw_series(
                    pts.iter()
                        .map(|&(x, y, _)| Circle::new((x, y), 4, color.filled())),
                )
                .map_err(plot_err)?
                .label(s.label.clone())
                .legend(move |(x, y)| Circle::new((x + 10, y), 4, color.filled()));
        }
        draw_legend(&mut chart, legend)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_legend_goes_to_a_corner_without_points() {
        let line = |pts: Vec<(f64, f64, f64)>| [ErrSeries::new("s", pts, PALETTE[0])];
        let rising: Vec<_> = (0..8).map(|i| (i as f64, i as f64, 0.1)).collect();
        let falling: Vec<_> = (0..8).map(|i| (i as f64, -(i as f64), 0.1)).collect();
        assert_eq!(free_corner(&line(rising)), SeriesLabelPosition::UpperLeft);
        assert_eq!(free_corner(&line(falling)), SeriesLabelPosition::UpperRight);
        // a peak in the upper middle-right with low ends: upper left
        let pts = vec![
            (0.0, 0.0, 0.0),
            (5.0, 0.5, 0.0),
            (8.0, 1.0, 0.0),
            (10.0, 0.0, 0.0),
        ];
        assert_eq!(free_corner(&line(pts)), SeriesLabelPosition::UpperLeft);
    }
}
