//! The cracks of a labelling of the grid's cells: the cell sides between cells of different
//! labels, as bitsets on the lattice of cell corners, with the number of cracks at each
//! corner; patched in place where a few cells change label. The crack graph
//! ([`crate::crack`]) traces them ([`crate::trace`]).

use crate::trace::Lattice;

/// Crack bitsets: `v[j * (w + 1) + i]` is the side between cells `(i - 1, j)` and `(i, j)`
/// (corner `(i, j)` to `(i, j + 1)`); `h[j * (w + 1) + i]` the side between `(i, j - 1)` and
/// `(i, j)` (corner `(i, j)` to `(i + 1, j)`).
pub(crate) struct Cracks {
    /// Corners across (`w + 1`).
    pub(crate) cw: usize,
    /// Corners up (`h + 1`).
    pub(crate) ch: usize,
    /// Vertical cracks, by their lower corner.
    pub(crate) v: Vec<bool>,
    /// Horizontal cracks, by their left corner.
    pub(crate) h: Vec<bool>,
    /// Cracks meeting at each corner.
    pub(crate) deg: Vec<u8>,
}

impl Cracks {
    /// The cracks of a labelling given row by row: `row(j, out)` writes the labels of row
    /// `j` to `out`.
    pub(crate) fn new(w: usize, h: usize, row: impl Fn(usize, &mut [u32])) -> Self {
        let (cw, ch) = (w + 1, h + 1);
        let mut v = vec![false; cw * ch];
        let mut hz = vec![false; cw * ch];
        // Cracks first, comparing whole rows (the loops vectorise), then the degrees.
        let (mut below, mut cur) = (vec![0u32; w], vec![0u32; w]);
        for j in 0..h {
            row(j, &mut cur);
            let c = j * cw;
            for (x, pair) in v[c + 1..c + w].iter_mut().zip(cur.windows(2)) {
                *x = pair[0] != pair[1];
            }
            if j > 0 {
                for ((x, a), b) in hz[c..c + w].iter_mut().zip(&cur).zip(&below) {
                    *x = a != b;
                }
            }
            std::mem::swap(&mut below, &mut cur);
        }
        // A corner meets the vertical cracks above and below it and the horizontal ones to
        // its right and left.
        let mut deg = vec![0u8; cw * ch];
        for cj in 0..ch {
            let c = cj * cw;
            for ci in 0..cw {
                let up = u8::from(v[c + ci]);
                let down = if cj > 0 { u8::from(v[c + ci - cw]) } else { 0 };
                let right = u8::from(hz[c + ci]);
                let left = if ci > 0 { u8::from(hz[c + ci - 1]) } else { 0 };
                deg[c + ci] = up + down + right + left;
            }
        }
        Self {
            cw,
            ch,
            v,
            h: hz,
            deg,
        }
    }

    /// Recomputes the cracks on the four sides of each of `cells` under `label`.
    pub(crate) fn patch(
        &mut self,
        w: usize,
        h: usize,
        cells: &[usize],
        label: impl Fn(usize) -> u32,
    ) {
        let cw = self.cw;
        let set_v = |this: &mut Self, i: usize, j: usize| {
            // Side between (i - 1, j) and (i, j), corner (i, j) to (i, j + 1).
            if i == 0 || i >= w {
                return;
            }
            let c = j * cw + i;
            let now = label(j * w + i - 1) != label(j * w + i);
            if now != this.v[c] {
                this.v[c] = now;
                let d = if now { 1 } else { u8::MAX };
                this.deg[c] = this.deg[c].wrapping_add(d);
                this.deg[c + cw] = this.deg[c + cw].wrapping_add(d);
            }
        };
        let set_h = |this: &mut Self, i: usize, j: usize, label: &dyn Fn(usize) -> u32| {
            if j == 0 || j >= h {
                return;
            }
            let c = j * cw + i;
            let now = label((j - 1) * w + i) != label(j * w + i);
            if now != this.h[c] {
                this.h[c] = now;
                let d = if now { 1 } else { u8::MAX };
                this.deg[c] = this.deg[c].wrapping_add(d);
                this.deg[c + 1] = this.deg[c + 1].wrapping_add(d);
            }
        };
        for &cell in cells {
            let (i, j) = (cell % w, cell / w);
            set_v(self, i, j);
            set_v(self, i + 1, j);
            set_h(self, i, j, &label);
            set_h(self, i, j + 1, &label);
        }
    }

    /// Column and row of corner `c`, by 32-bit division (corner indices fit: keys are below
    /// 2^25 cells).
    #[inline]
    pub(crate) fn split(&self, c: usize) -> (usize, usize) {
        let (c32, cw32) = (c as u32, self.cw as u32);
        ((c32 % cw32) as usize, (c32 / cw32) as usize)
    }

    /// The first corner (in the order left, right, lower, upper side) of a crack on a side of
    /// cell `(ci, cj)`.
    pub(crate) fn corner_of_cell(&self, ci: usize, cj: usize) -> Option<usize> {
        let cw = self.cw;
        [
            (self.v[cj * cw + ci], cj * cw + ci),
            (ci + 1 < cw && self.v[cj * cw + ci + 1], cj * cw + ci + 1),
            (self.h[cj * cw + ci], cj * cw + ci),
            (
                cj + 1 < self.ch && self.h[(cj + 1) * cw + ci],
                (cj + 1) * cw + ci,
            ),
        ]
        .into_iter()
        .find_map(|(crack, corner)| crack.then_some(corner))
    }
}

/// Corners are the sites, cracks the steps (crack id `2 * corner + 0` vertical, `+ 1`
/// horizontal, by the crack's lower or left corner).
impl Lattice for Cracks {
    fn sites(&self) -> usize {
        self.deg.len()
    }

    fn member(&self, c: usize) -> bool {
        self.deg[c] > 0
    }

    fn degree(&self, c: usize) -> u8 {
        self.deg[c]
    }

    /// In the order up, right, down, left.
    fn neighbours(&self, c: usize, out: &mut Vec<(usize, usize)>) {
        out.clear();
        // No bounds arithmetic: a vertical crack starts only below the top corner row and a
        // horizontal one only left of the last corner column, so `v[c]` and `h[c]` imply that
        // the corner above or to the right exists, and `h` of the last corner of a row
        // (reached by `c - 1` from a row's first corner) is always false.
        if self.v[c] {
            out.push((c + self.cw, 2 * c));
        }
        if self.h[c] {
            out.push((c + 1, 2 * c + 1));
        }
        if c >= self.cw && self.v[c - self.cw] {
            out.push((c - self.cw, 2 * (c - self.cw)));
        }
        if c >= 1 && self.h[c - 1] {
            out.push((c - 1, 2 * (c - 1) + 1));
        }
    }
}
