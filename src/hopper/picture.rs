//! Snapshots of the hopper shaded by orientation, as in BB90 Fig. 2: three
//! distinguishable shades for the three orientations, holes white, walls
//! dark, with a legend.

use super::energy::{orientation, ORIENTATION_NAMES};
use super::geometry::Geometry;
use super::model::{grain_state, is_grain, WALL};
use crate::error::Result;
use crate::lattice::position;
use crate::plot::{plot_err, register_fonts, FONT};
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
    register_fonts();
    let (w, h) = (geom.width(), geom.height());
    let phys_w = (w as f64 - 1.0) * 3f64.sqrt() / 2.0 + 1.0;
    let phys_h = h as f64 + 0.5;
    let pw = (phys_w * scale).ceil() as u32 + 10;
    let ph = (phys_h * scale).ceil() as u32 + 30;
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let (top, legend) = (50u32, 50u32);
    let size = (pw * cols as u32, top + ph * rows as u32 + legend);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(plot_err)?;
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
    root.present().map_err(plot_err)?;
    Ok(())
}
