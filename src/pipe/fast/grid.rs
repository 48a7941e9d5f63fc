//! The bit planes of the fast engine: for every column x and channel c
//! (MODEL.md A1) one bit per row, bit `y % 64` of word `y / 64`. The seven
//! channel words of 64 sites of a column are stored together as one
//! [`Word`], so that a rule (MODEL.md A3-A6) reads and writes one array.
//! Bits of rows `>= L` in the last word of a column are always zero.

/// Channel words of 64 sites of one column: `w[c]` bit j = channel c of row
/// `64 k + j`.
pub type Word = [u64; 7];

/// Mask of the bits `a..b` of a word (`0 <= a < b <= 64`).
pub fn bit_range(a: usize, b: usize) -> u64 {
    debug_assert!(a < b && b <= 64);
    let ones = if b - a == 64 {
        u64::MAX
    } else {
        (1u64 << (b - a)) - 1
    };
    ones << a
}

/// The state of a W x L pipe as bit planes.
#[derive(Debug, Clone)]
pub struct Grid {
    width: usize,
    length: usize,
    /// Words per column, ceil(L / 64).
    words: usize,
    /// Valid rows of the last word of a column.
    last_mask: u64,
    /// Bit of row L-1 within the last word.
    top_bit: u32,
    /// Column x, word k at index `x * words + k`.
    cells: Vec<Word>,
}

impl Grid {
    /// An empty pipe of `width` columns and `length` rows (both >= 1).
    pub fn new(width: usize, length: usize) -> Self {
        let words = length.div_ceil(64);
        let used = length - 64 * (words - 1);
        Grid {
            width,
            length,
            words,
            last_mask: bit_range(0, used),
            top_bit: ((length - 1) % 64) as u32,
            cells: vec![[0; 7]; width * words],
        }
    }

    /// Words per column.
    pub fn words(&self) -> usize {
        self.words
    }

    /// The lanes of word `k` that are rows of the pipe.
    pub fn lanes(&self, k: usize) -> u64 {
        if k + 1 == self.words {
            self.last_mask
        } else {
            u64::MAX
        }
    }

    /// Every word, column by column.
    pub fn cells(&self) -> &[Word] {
        &self.cells
    }

    /// Every word, column by column, mutable.
    pub fn cells_mut(&mut self) -> &mut [Word] {
        &mut self.cells
    }

    /// The words of column `x`, bottom to top.
    pub fn column(&self, x: usize) -> &[Word] {
        &self.cells[x * self.words..(x + 1) * self.words]
    }

    /// The words of column `x`, mutable.
    pub fn column_mut(&mut self, x: usize) -> &mut [Word] {
        &mut self.cells[x * self.words..(x + 1) * self.words]
    }

    /// Empty every site.
    pub fn clear(&mut self) {
        self.cells.iter_mut().for_each(|w| *w = [0; 7]);
    }

    fn at(&self, x: usize, y: usize) -> (usize, u32) {
        debug_assert!(x < self.width && y < self.length);
        (x * self.words + y / 64, (y % 64) as u32)
    }

    /// Whether channel `c` of site (x, y) is occupied.
    pub fn get(&self, x: usize, y: usize, c: usize) -> bool {
        let (i, j) = self.at(x, y);
        self.cells[i][c] >> j & 1 == 1
    }

    /// Occupy channel `c` of site (x, y).
    pub fn set(&mut self, x: usize, y: usize, c: usize) {
        let (i, j) = self.at(x, y);
        self.cells[i][c] |= 1 << j;
    }

    /// The state byte of site (x, y) (bit c = channel c).
    pub fn site(&self, x: usize, y: usize) -> u8 {
        let (i, j) = self.at(x, y);
        let w = &self.cells[i];
        (0..7).fold(0u8, |s, c| s | (((w[c] >> j) & 1) as u8) << c)
    }

    /// Set the state byte of site (x, y) (bits 0..=6).
    pub fn set_site(&mut self, x: usize, y: usize, state: u8) {
        let (i, j) = self.at(x, y);
        for (c, plane) in self.cells[i].iter_mut().enumerate() {
            *plane = (*plane & !(1 << j)) | (((state >> c) & 1) as u64) << j;
        }
    }

    /// Particles in each channel.
    pub fn channel_counts(&self) -> [u64; 7] {
        let mut n = [0u64; 7];
        for w in &self.cells {
            for (v, plane) in n.iter_mut().zip(w) {
                *v += plane.count_ones() as u64;
            }
        }
        n
    }

    /// Channel `c` of column `col` moved one row up, word `k`: new[y] =
    /// old[y - 1], row 0 filled from row L-1 (periodic) or empty (open).
    #[inline]
    fn up(&self, col: &[Word], c: usize, k: usize, periodic: bool) -> u64 {
        let carry = if k > 0 {
            col[k - 1][c] >> 63
        } else if periodic {
            (col[self.words - 1][c] >> self.top_bit) & 1
        } else {
            0
        };
        (col[k][c] << 1 | carry) & self.lanes(k)
    }

    /// Channel `c` of column `col` moved one row down, word `k`: new[y] =
    /// old[y + 1], row L-1 filled from row 0 (periodic) or empty (open).
    #[inline]
    fn down(&self, col: &[Word], c: usize, k: usize, periodic: bool) -> u64 {
        if k + 1 < self.words {
            col[k][c] >> 1 | col[k + 1][c] << 63
        } else if periodic {
            col[k][c] >> 1 | (col[0][c] & 1) << self.top_bit
        } else {
            col[k][c] >> 1
        }
    }

    /// The lanes of word `k` of column `x` whose neighbour below (row y - 1,
    /// along channel 4, MODEL.md A1) holds channel `c`; below row 0 the
    /// periodic pipe wraps to row L-1 and the open pipe has no site
    /// (`lane-collide`, READINGS.md P23).
    pub fn from_below(&self, x: usize, c: usize, k: usize, periodic: bool) -> u64 {
        self.up(self.column(x), c, k, periodic)
    }

    /// `rest-ahead` (READINGS.md P7): the lanes of word `k` of column `x`
    /// whose neighbour along channel 2 (up-left), and along channel 6
    /// (up-right), holds a rest particle (MODEL.md A1: column x -+ 1, row
    /// y + x % 2). Beyond a wall or the open top there is none; the periodic
    /// pipe wraps row L to row 0.
    pub fn rest_ahead(&self, x: usize, k: usize, periodic: bool) -> (u64, u64) {
        let odd = x % 2 == 1;
        let rest = |col: &[Word]| {
            if odd {
                self.down(col, 0, k, periodic)
            } else {
                col[k][0]
            }
        };
        let left = if x > 0 { rest(self.column(x - 1)) } else { 0 };
        let right = if x + 1 < self.width {
            rest(self.column(x + 1))
        } else {
            0
        };
        (left, right)
    }

    /// Free streaming (MODEL.md A2 step 4, A1 neighbours) into `next`: every
    /// mover goes to its neighbour; movers whose neighbour is a wall or a row
    /// beyond the open ends are dropped here (the walls put theirs back,
    /// MODEL.md A6). Destination column x of parity o = x % 2 receives
    /// channel 2 from (x+1, y-1+o), 3 from (x+1, y+o), 5 from (x-1, y+o),
    /// 6 from (x-1, y-1+o), 1 from (x, y-1), 4 from (x, y+1).
    pub fn stream_into(&self, next: &mut Grid, periodic: bool) {
        let (w, nw) = (self.width, self.words);
        for x in 0..w {
            let here = self.column(x);
            let right = (x + 1 < w).then(|| self.column(x + 1));
            let left = (x > 0).then(|| self.column(x - 1));
            let odd = x % 2 == 1;
            let out = &mut next.cells[x * nw..(x + 1) * nw];
            for (k, o) in out.iter_mut().enumerate() {
                let mut s = [0u64; 7];
                s[0] = here[k][0];
                s[1] = self.up(here, 1, k, periodic);
                s[4] = self.down(here, 4, k, periodic);
                if let Some(r) = right {
                    (s[2], s[3]) = if odd {
                        (r[k][2], self.down(r, 3, k, periodic))
                    } else {
                        (self.up(r, 2, k, periodic), r[k][3])
                    };
                }
                if let Some(l) = left {
                    (s[5], s[6]) = if odd {
                        (self.down(l, 5, k, periodic), l[k][6])
                    } else {
                        (l[k][5], self.up(l, 6, k, periodic))
                    };
                }
                *o = s;
            }
        }
    }
}

/// The three bit planes of the number of particles (0..=7) of 64 sites: a
/// bit-sliced adder of the seven channels.
pub fn site_totals(w: &Word) -> [u64; 3] {
    let full_add = |a: u64, b: u64, c: u64| (a ^ b ^ c, (a & b) | (c & (a ^ b)));
    let (s1, c1) = full_add(w[0], w[1], w[2]);
    let (s2, c2) = full_add(w[3], w[4], w[5]);
    let (ones, c3) = full_add(s1, s2, w[6]);
    let (twos, fours) = full_add(c1, c2, c3);
    [ones, twos, fours]
}

impl crate::pipe::relocation::RestChannels for Grid {
    fn has_rest(&self, x: usize, y: usize) -> bool {
        self.get(x, y, 0)
    }
    fn put_rest(&mut self, x: usize, y: usize) {
        self.set(x, y, 0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sites_round_trip_and_high_bits_stay_clear() {
        for l in [1usize, 10, 63, 64, 65, 128, 220] {
            let mut g = Grid::new(3, l);
            for y in 0..l {
                g.set_site(1, y, (y % 128) as u8);
            }
            for y in 0..l {
                assert_eq!(g.site(1, y), (y % 128) as u8, "L {l} y {y}");
            }
            let last = g.column(1)[g.words() - 1];
            assert!(last.iter().all(|&p| p & !g.lanes(g.words() - 1) == 0));
        }
    }

    #[test]
    fn the_adder_counts_the_channels() {
        let mut w = [0u64; 7];
        for s in 0..64u64 {
            // lane s holds the state s | (s & 1) << 6: 0..=7 particles
            let state = s | (s & 1) << 6;
            for (c, p) in w.iter_mut().enumerate() {
                *p |= ((state >> c) & 1) << s;
            }
        }
        let [a, b, c] = site_totals(&w);
        for s in 0..64u64 {
            let state = s | (s & 1) << 6;
            let n = (a >> s & 1) + 2 * (b >> s & 1) + 4 * (c >> s & 1);
            assert_eq!(n, state.count_ones() as u64);
        }
    }
}
