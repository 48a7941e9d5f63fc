//! The hopper drawn on the triangular lattice (MODEL.md B2): a 60° wedge
//! (each wall 30° from vertical) ending in an outlet channel, closed at the
//! bottom by a plug of wall sites until emptying starts.
//!
//! Row 0 is the plug row: under the outlet it is wall while closed and hole
//! once opened; a grain that moves into it leaves the hopper (MODEL.md B5).

use crate::error::{check_min, Error, Result};
use crate::lattice::{neighbour, position};
use serde::{Deserialize, Serialize};

/// Sizes of the hopper (MODEL.md B2; the paper gives only the wedge angle).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GeometryParams {
    /// Lattice columns W (horizontal).
    pub width: usize,
    /// Lattice rows H (vertical, gravity towards row 0).
    pub height: usize,
    /// Columns of the outlet channel.
    pub outlet_width: usize,
    /// Rows of the outlet channel above the plug row.
    pub channel_height: usize,
}

impl Default for GeometryParams {
    /// The prototype set-up of MODEL.md B2: 174 x 129 sites, outlet 7 columns,
    /// channel 4 rows (11229 inside sites).
    fn default() -> Self {
        GeometryParams {
            width: 174,
            height: 129,
            outlet_width: 7,
            channel_height: 4,
        }
    }
}

impl GeometryParams {
    /// A small hopper for the quick tier and the tests (100 x 75 sites, outlet 7, channel 4: 3782 inside sites).
    pub fn quick() -> Self {
        GeometryParams {
            width: 100,
            height: 75,
            outlet_width: 7,
            channel_height: 4,
        }
    }

    /// Check the sizes; the error names the value and the allowed range.
    pub fn validate(&self) -> Result<()> {
        check_min("outlet_width", self.outlet_width, 1)?;
        check_min("channel_height", self.channel_height, 1)?;
        check_min("width", self.width, 3)?;
        let most = max_outlet_width(self.width);
        if self.outlet_width > most {
            return Err(Error::out_of_range(
                "outlet_width",
                self.outlet_width,
                &format!(
                    "[1, {most}] for width = {} (the outlet is centred on column {} between the wall columns 0 and {})",
                    self.width,
                    self.width / 2,
                    self.width - 1
                ),
            ));
        }
        check_min("height", self.height, self.channel_height + 4)?;
        if self.width > 4096 || self.height > 4096 {
            return Err(Error::out_of_range(
                "width x height",
                format!("{} x {}", self.width, self.height),
                "[.., 4096] each",
            ));
        }
        Ok(())
    }
}

/// Whether an outlet of `outlet` columns, centred on column `width / 2`
/// (columns `width/2 - (outlet-1)/2 ..`, see [`Geometry::new`]), lies
/// between the wall columns 0 and `width - 1`.
fn outlet_fits(outlet: usize, width: usize) -> bool {
    let c0 = width / 2;
    let left = (outlet.max(1) - 1) / 2;
    let right = outlet.max(1) - 1 - left;
    outlet >= 1 && c0 > left && c0 + right + 2 <= width
}

/// The widest outlet a hopper of `width` columns holds (its whole base:
/// `width - 2` columns when the centring allows, else `width - 3`); 0 when
/// `width < 3`.
pub fn max_outlet_width(width: usize) -> usize {
    (1..width.saturating_sub(1))
        .rev()
        .find(|&o| outlet_fits(o, width))
        .unwrap_or(0)
}

/// Kind of a site of the hopper container (never changes except the plug).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SiteKind {
    /// Wall: never holds a grain.
    Wall,
    /// Inside the hopper: holds a grain or a hole.
    Inside,
    /// Plug row under the outlet: wall until opened, then the exit.
    Plug,
}

/// Marker for "no neighbour" (off the lattice, which counts as wall).
pub const OFF: u32 = u32::MAX;

/// The drawn hopper: site kinds and the neighbour table.
#[derive(Debug, Clone)]
pub struct Geometry {
    /// The sizes it was drawn from.
    pub params: GeometryParams,
    /// Site kind of site `y * width + x`.
    pub kind: Vec<SiteKind>,
    /// Neighbour index in direction `c` at `nbr[i][c - 1]`, or [`OFF`].
    pub nbr: Vec<[u32; 6]>,
    /// Column of the outlet's centre.
    pub centre_column: usize,
    /// Horizontal position of the outlet's centre (lattice units).
    pub centre_x: f64,
    /// Number of inside sites.
    pub inside: usize,
}

impl Geometry {
    /// Draw the hopper: a site `(x, y)` with `y >= 1` is inside when
    /// `|X - X_c| <= half-width + max(Y - Y_channel_top, 0) * tan 30°`
    /// (positions `X, Y` from [`position`]), the outermost columns and the
    /// row 0 outside the outlet are walls.
    pub fn new(params: GeometryParams) -> Result<Self> {
        params.validate()?;
        let (w, h) = (params.width, params.height);
        let c0 = w / 2;
        let first = c0 - (params.outlet_width - 1) / 2;
        let last = first + params.outlet_width - 1;
        if first < 1 || last > w - 2 {
            return Err(Error::out_of_range(
                "outlet_width",
                params.outlet_width,
                &format!("[1, {}] for width = {w}", w - 2),
            ));
        }
        let xc = 0.5 * (position(first, 0).0 + position(last, 0).0);
        let half = 0.5 * (position(last, 0).0 - position(first, 0).0);
        let top = params.channel_height as f64;
        let tan30 = 1.0 / 3f64.sqrt();
        let mut kind = vec![SiteKind::Wall; w * h];
        let mut inside = 0;
        for y in 0..h {
            for x in 0..w {
                let k = if y == 0 {
                    if (first..=last).contains(&x) {
                        SiteKind::Plug
                    } else {
                        SiteKind::Wall
                    }
                } else if x == 0 || x == w - 1 {
                    SiteKind::Wall
                } else {
                    let (px, py) = position(x, y);
                    let py = py - (x % 2) as f64 * 0.5; // row height, not the staggered one
                    let allowed = half + (py - top).max(0.0) * tan30 + 1e-9;
                    if (px - xc).abs() <= allowed {
                        SiteKind::Inside
                    } else {
                        SiteKind::Wall
                    }
                };
                if k == SiteKind::Inside {
                    inside += 1;
                }
                kind[y * w + x] = k;
            }
        }
        let mut nbr = vec![[OFF; 6]; w * h];
        for y in 0..h {
            for x in 0..w {
                for c in 1..=6 {
                    let (nx, ny) = neighbour(x, y, c);
                    if nx >= 0 && ny >= 0 && (nx as usize) < w && (ny as usize) < h {
                        nbr[y * w + x][c - 1] = (ny as usize * w + nx as usize) as u32;
                    }
                }
            }
        }
        Ok(Geometry {
            params,
            kind,
            nbr,
            centre_column: c0,
            centre_x: xc,
            inside,
        })
    }

    /// Lattice columns.
    pub fn width(&self) -> usize {
        self.params.width
    }

    /// Lattice rows.
    pub fn height(&self) -> usize {
        self.params.height
    }

    /// Index of site `(x, y)`.
    pub fn index(&self, x: usize, y: usize) -> usize {
        y * self.params.width + x
    }

    /// Columns `(first, last)` of the inside sites of row `y` (None if none).
    pub fn row_span(&self, y: usize) -> Option<(usize, usize)> {
        let w = self.params.width;
        let xs: Vec<usize> = (0..w)
            .filter(|&x| self.kind[y * w + x] == SiteKind::Inside)
            .collect();
        Some((*xs.first()?, *xs.last()?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_matches_the_prototype_size() {
        let g = Geometry::new(GeometryParams::default()).unwrap();
        // MODEL.md B2 reports 11229 inside sites for this set-up; the exact
        // count depends on how the staircase is rounded, so allow 2%.
        assert!(
            (g.inside as f64 - 11229.0).abs() < 0.02 * 11229.0,
            "inside = {}",
            g.inside
        );
        // the outlet channel is outlet_width wide
        let (a, b) = g.row_span(1).unwrap();
        assert_eq!(b - a + 1, 7);
        // symmetric within one column
        let (a, b) = g.row_span(100).unwrap();
        assert!((a as i64 + b as i64 - 2 * g.centre_column as i64).abs() <= 1);
    }

    #[test]
    fn the_widest_outlet_fits_and_one_more_is_an_error() {
        for width in 3..40 {
            let most = max_outlet_width(width);
            assert!(
                most + 3 >= width && most + 2 <= width,
                "width {width}: {most}"
            );
            let p = |outlet_width| GeometryParams {
                width,
                height: 20,
                outlet_width,
                channel_height: 4,
            };
            let g = Geometry::new(p(most)).unwrap();
            assert_eq!(g.row_span(1).map(|(a, b)| b - a + 1), Some(most));
            let e = Geometry::new(p(most + 1)).unwrap_err();
            assert!(e.message.contains(&format!("[1, {most}]")), "{}", e.message);
        }
    }

    #[test]
    fn bad_sizes_are_errors() {
        let mut p = GeometryParams::quick();
        p.outlet_width = 0;
        assert!(Geometry::new(p).is_err());
        let mut p = GeometryParams::quick();
        p.height = 3;
        let e = Geometry::new(p).unwrap_err();
        assert!(e.message.contains("height"), "{}", e.message);
    }
}
