//! The random walk of relocation (MODEL.md A4) on a table of neighbours: the
//! walk of [`relocation::random_walk`], hop for hop and draw for draw, in
//! fewer instructions per hop.
//!
//! A site is named by its bit in the grid's rest plane, `x * stride + y`
//! with `stride` = 64 rows per word ([`Grid`]). For every site the table
//! lists its valid neighbours in direction order 1..=6 (walls, and rows
//! beyond the open ends, left out) and their number `n`; a hop takes the
//! `below(n)`-th of them, as [`relocation::random_walk`] does. Entries are
//! 16-bit where the pipe has at most 2^16 such bits, so that the table of
//! the PH95 pipes stays in the first-level cache.
//!
//! Near a clogged pipe most of a run's time is in these walks: a lower-end
//! run of waves-fig12 (220x11, I = 0.5078) makes about 700 hops per extra
//! rest particle and 16 extra particles per step. EXPERIMENTS.md ("The walk
//! of relocation on a neighbour table") has the timings.

use super::grid::{Grid, Word};
use super::lanes;
use crate::error::Result;
use crate::lattice::neighbour;
use crate::pipe::relocation;
use crate::pipe::{Boundary, Params, Rules};
use rand::Rng;

/// A site's name in the table: an index into the rest plane.
trait Site: Copy + Default {
    fn new(s: usize) -> Self;
    fn get(self) -> usize;
}

impl Site for u16 {
    fn new(s: usize) -> Self {
        s as u16
    }
    fn get(self) -> usize {
        self as usize
    }
}

impl Site for u32 {
    fn new(s: usize) -> Self {
        s as u32
    }
    fn get(self) -> usize {
        self as usize
    }
}

/// The neighbour table of one pipe's sites, in 16-bit entries if they fit.
#[derive(Debug, Clone)]
enum Table {
    Small(Vec<[u16; 6]>),
    Large(Vec<[u32; 6]>),
}

/// The neighbour table of relocation's walk for one pipe.
#[derive(Debug, Clone)]
pub struct Walker {
    /// Bits per column in the rest plane (64 per word).
    stride: usize,
    /// Per site: its valid neighbours in direction order (the first `n`).
    next: Table,
    /// Per site: the number `n` of valid neighbours.
    count: Vec<u8>,
    /// The longest walk ([`relocation::walk_bound`]).
    bound: u64,
}

impl Walker {
    /// The table of the pipe `params` under `rules` (its walls: the wall
    /// sites of `wall-sites` are left out as the walls are), stored with
    /// `words` words per column.
    pub fn new(params: &Params, rules: Rules, words: usize) -> Self {
        let stride = 64 * words;
        let mut count = vec![0u8; params.width * stride];
        let next = if params.width * stride <= 1 << 16 {
            Table::Small(table(params, rules, stride, &mut count))
        } else {
            Table::Large(table(params, rules, stride, &mut count))
        };
        Walker {
            stride,
            next,
            count,
            bound: relocation::walk_bound(params),
        }
    }

    /// The walk from (x, y) until a site with an empty rest channel, which
    /// it fills: the hops and draws of [`relocation::random_walk`], and its
    /// error ([`relocation::stuck`]) when no such site is found.
    pub fn walk(
        &self,
        grid: &mut Grid,
        rng: &mut impl Rng,
        params: &Params,
        (x, y): (usize, usize),
        time: u64,
    ) -> Result<()> {
        let s = x * self.stride + y;
        let cells = grid.cells_mut();
        let placed = match &self.next {
            Table::Small(next) => self.hops(next, cells, rng, s),
            Table::Large(next) => self.hops(next, cells, rng, s),
        };
        if placed {
            Ok(())
        } else {
            Err(relocation::stuck(params, time))
        }
    }

    /// The hops from site `s`: true once a free rest channel is filled,
    /// false at a dead end or after the bound.
    fn hops<S: Site>(
        &self,
        next: &[[S; 6]],
        cells: &mut [Word],
        rng: &mut impl Rng,
        mut s: usize,
    ) -> bool {
        if self.count[s] == 0 {
            return false; // a site without neighbours: W = 1 and L = 1
        }
        // every other site has a neighbour; an interior one has six, and its
        // hop is read off the first draw unless that draw is one of the few
        // that `below` rejects, so that the next site need not wait for `n`
        for _ in 0..self.bound {
            let n = self.count[s] as u32;
            let first = rng.next_u32();
            let m = first as u64 * 6;
            let k = if n == 6 && m as u32 >= 6 {
                (m >> 32) as u32
            } else {
                lanes::below_from(rng, first, n)
            };
            s = next[s][k as usize].get();
            let (word, bit) = (s / 64, s % 64);
            if cells[word][0] >> bit & 1 == 0 {
                cells[word][0] |= 1 << bit;
                return true;
            }
        }
        false
    }
}

/// The valid neighbours of every site of `params` (rest-plane bits with
/// `stride` per column), and their number into `count`.
fn table<S: Site>(params: &Params, rules: Rules, stride: usize, count: &mut [u8]) -> Vec<[S; 6]> {
    let (w, l) = (params.width, params.length);
    let periodic = params.boundary == Boundary::Periodic;
    let inner = rules.inner_columns(w);
    let mut next = vec![[S::default(); 6]; w * stride];
    for x in inner.clone() {
        for y in 0..l {
            let s = x * stride + y;
            let mut n = 0;
            for c in 1..=6 {
                let (nx, ny) = neighbour(x, y, c);
                if nx < inner.start as i64 || nx >= inner.end as i64 {
                    continue;
                }
                let ny = if periodic {
                    ny.rem_euclid(l as i64)
                } else if ny < 0 || ny >= l as i64 {
                    continue;
                } else {
                    ny
                };
                next[s][n] = S::new(nx as usize * stride + ny as usize);
                n += 1;
            }
            count[s] = n as u8;
        }
    }
    next
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pipe::relocation::{random_walk, RestChannels};
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// A lattice filled with rest particles but for `holes` random sites.
    fn nearly_full(params: &Params, holes: usize, seed: u64) -> Grid {
        let (w, l) = (params.width, params.length);
        let mut g = Grid::new(w, l);
        for x in 0..w {
            for y in 0..l {
                g.put_rest(x, y);
            }
        }
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        for _ in 0..holes {
            let (x, y) = (
                lanes::below(&mut rng, w as u32),
                lanes::below(&mut rng, l as u32),
            );
            g.set_site(x as usize, y as usize, 0);
        }
        g
    }

    /// The table walk fills the site the reference's walk fills and leaves
    /// the generator where it does, in every pipe shape (walls, open ends,
    /// periodic wrap, one column, one row, both table widths).
    #[test]
    fn the_table_walk_is_the_reference_walk() {
        let shapes = [
            (1, 7, false, false),
            (2, 1, false, false),
            (1, 3, true, false),
            (5, 60, false, false),
            (5, 60, true, false),
            (11, 220, false, false),
            (4, 130, true, false),
            (3, 22000, false, false),
            (3, 7, true, true),
            (5, 60, false, true),
            (11, 220, true, true),
            (4, 130, false, true),
        ];
        for (w, l, periodic, wall_sites) in shapes {
            let rules = Rules {
                wall_sites,
                ..Rules::default()
            };
            let params = Params {
                width: w,
                length: l,
                boundary: if periodic {
                    Boundary::Periodic
                } else {
                    Boundary::Open { inject: 0.5 }
                },
                ..Params::default()
            };
            let holes = 1 + w * l / 20;
            let mut a = nearly_full(&params, holes, 7);
            let mut b = a.clone();
            let walker = Walker::new(&params, rules, a.words());
            assert_eq!(
                matches!(walker.next, Table::Large(_)),
                w * a.words() * 64 > 1 << 16
            );
            let mut ra = Xoshiro256PlusPlus::seed_from_u64(w as u64 * 1000 + l as u64);
            let mut rb = ra.clone();
            // at most half the holes: the last walks to the last holes are long
            // (with wall-sites about (W - 2)/W of the holes can be reached)
            let inner = rules.inner_columns(w);
            for i in 0..(holes / 2 * inner.len() / w).clamp(1, 300) {
                let (x, y) = (inner.start + i * 7 % inner.len(), i * 13 % l);
                let fast = walker.walk(&mut a, &mut ra, &params, (x, y), 0);
                let below = &mut |n| lanes::below(&mut rb, n);
                let slow = random_walk(&mut b, below, &params, rules, x, y, 0);
                assert_eq!(fast.is_ok(), slow.is_ok(), "{w}x{l} walk {i}");
                assert_eq!(ra, rb, "{w}x{l} walk {i}: the draws differ");
                assert!(
                    a.cells() == b.cells(),
                    "{w}x{l} walk {i}: the lattices differ"
                );
            }
        }
    }

    /// A full one-site pipe is a dead end: the walk reports it, as the
    /// reference's does.
    #[test]
    fn a_site_without_neighbours_is_stuck() {
        let params = Params {
            width: 1,
            length: 1,
            boundary: Boundary::Open { inject: 0.5 },
            ..Params::default()
        };
        let mut g = nearly_full(&params, 0, 1);
        let walker = Walker::new(&params, Rules::default(), g.words());
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
        let e = walker
            .walk(&mut g, &mut rng, &params, (0, 0), 3)
            .unwrap_err();
        assert_eq!(e.kind, crate::error::ErrorKind::RelocationStuck);
    }
}
