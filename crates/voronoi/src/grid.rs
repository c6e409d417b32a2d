//! Occupancy grids: free or occupied cells over a rectangle, with the bounds as walls.

use homospline_geom::{Point, Real, Scene};
use thiserror::Error;

/// Largest grid, in cells, the field can label exactly (keys are raster indices below 2^25).
pub const MAX_CELLS: usize = 1 << 25;

/// The offsets `(di, dj)` of a cell's 8 neighbours in ring order: east first, then
/// counter-clockwise in (column, row); the even entries are the 4-neighbours.
pub const NEIGHBOURS_8: [(i64, i64); 8] = [
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
    (0, -1),
    (1, -1),
];

/// The neighbours of cell `(i, j)` that lie inside a `width x height` grid, in
/// [`NEIGHBOURS_8`] order: each one's cell and its offset `(di, dj)`.
///
/// # Examples
///
/// ```
/// use homospline_voronoi::grid::neighbours_8;
///
/// // A corner cell has three neighbours.
/// let around: Vec<_> = neighbours_8(0, 0, 4, 3).map(|(cell, _)| cell).collect();
/// assert_eq!(around, [(1, 0), (1, 1), (0, 1)]);
/// assert_eq!(neighbours_8(1, 1, 4, 3).count(), 8);
/// ```
pub fn neighbours_8(
    i: usize,
    j: usize,
    width: usize,
    height: usize,
) -> impl Iterator<Item = ((usize, usize), (i64, i64))> {
    NEIGHBOURS_8.into_iter().filter_map(move |(di, dj)| {
        let (ni, nj) = (i as i64 + di, j as i64 + dj);
        (ni >= 0 && nj >= 0 && ni < width as i64 && nj < height as i64)
            .then_some(((ni as usize, nj as usize), (di, dj)))
    })
}

/// The cell of a `width x height` grid of square cells of side `cell`, lower-left corner at
/// `origin`, that holds `p` (a point on a side goes to the cell above or right of it);
/// `None` outside the grid or for a point that is not a number.
pub fn cell_holding(
    origin: &Point,
    cell: Real,
    width: usize,
    height: usize,
    p: &Point,
) -> Option<(usize, usize)> {
    let fx = (p.x - origin.x) / cell;
    let fy = (p.y - origin.y) / cell;
    if !(fx >= 0.0 && fy >= 0.0) {
        return None;
    }
    let (i, j) = (fx as usize, fy as usize);
    (i < width && j < height).then_some((i, j))
}

/// How close to a cell side, in cells, a point counts as on it ([`cells_holding`]).
pub const ON_SIDE: Real = 1e-9;

/// Along one axis, at `f` cells from the origin in a row of `n` cells: the cell holding `f`,
/// and its neighbour whose closed interval holds it too where `f` is within [`ON_SIDE`] of a
/// side (decimal coordinates land a side at 201.99999999999997 cells).
pub fn cells_holding(f: Real, n: usize) -> [Option<usize>; 3] {
    let i = (f.max(0.0) as usize).min(n.saturating_sub(1));
    let d = f - i as Real;
    [
        Some(i),
        (d < ON_SIDE && i > 0).then(|| i - 1),
        (1.0 - d < ON_SIDE && i + 1 < n).then_some(i + 1),
    ]
}

/// Fewest cells a scene's grid may have along the longer side of its bounds: coarser, the
/// grid no longer sees the scene (at 3 x 3 cells the graph's nodes lay far outside the
/// bounds, and at 5 cells across a scene of a hundred units it had no path).
pub const MIN_CELLS_ACROSS: usize = 16;

/// Why a grid cannot be made.
#[derive(Debug, Error, PartialEq)]
pub enum GridError {
    /// Resolution not positive and finite.
    #[error("resolution must be positive and finite, got {0}")]
    Resolution(Real),
    /// Too few cells along the scene's longer side.
    #[error(
        "the grid would have {cells} cells along the scene's longer side (at least {min}): raise the resolution"
    )]
    TooCoarse {
        /// Cells along the longer side.
        cells: usize,
        /// The limit.
        min: usize,
    },
    /// Too many cells.
    #[error(
        "the grid would have {cells} cells (at most {max} are supported): lower the resolution"
    )]
    TooLarge {
        /// Cells asked for.
        cells: usize,
        /// The limit.
        max: usize,
    },
    /// A scene's resolution too fine for the cell limit, with the finest that fits.
    #[error(
        "the grid would have {cells} cells at this resolution (at most {max} are supported): \
         a resolution of at most {fits} cells per unit fits"
    )]
    TooFine {
        /// Cells asked for.
        cells: usize,
        /// The limit.
        max: usize,
        /// The finest resolution whose grid keeps to the limit, rounded down to 3 digits.
        fits: Real,
    },
    /// Occupancy data of the wrong size.
    #[error("occupancy has {got} cells, expected {width} x {height}")]
    Size {
        /// Cells given.
        got: usize,
        /// Width.
        width: usize,
        /// Height.
        height: usize,
    },
}

/// The finest resolution, to 3 significant digits and rounded down, at which a scene of
/// extent `ex x ey` keeps to [`MAX_CELLS`] (walls included).
fn finest_resolution(ex: Real, ey: Real) -> Real {
    let cells = |r: Real| ((ex * r).ceil() + 2.0) * ((ey * r).ceil() + 2.0);
    let r = (MAX_CELLS as Real / (ex * ey).max(Real::MIN_POSITIVE)).sqrt();
    // `k / per` with `k` whole: a quotient prints as short as it is (81, not the
    // 81.00000000000001 of `810 * 0.1`).
    let per = 10f64.powf(2.0 - r.log10().floor());
    let mut k = (r * per).floor();
    while k > 0.0 && cells(k / per) > MAX_CELLS as Real {
        k -= 1.0;
    }
    k / per
}

/// The area a scene's grid at `resolution` covers: its working area
/// ([`Scene::working_area`]), or its bounds when the area would be under
/// [`MIN_CELLS_ACROSS`] cells across and the bounds' grid is within [`MAX_CELLS`] (so that
/// a `--resolution` that suits the bounds is never refused for the area's sake).
pub fn scene_area(scene: &Scene, resolution: Real) -> homospline_geom::Bounds {
    let area = scene.working_area();
    let (e, b) = (area.extent(), scene.bounds.extent());
    // The bounds only where their grid is within the limit: else the area's refusal
    // (too coarse) names what it needs, where the bounds' (too fine) would suggest a grid
    // that cannot see the obstacles.
    let bounds_fit = (b.x * resolution).ceil() * (b.y * resolution).ceil() <= MAX_CELLS as Real;
    if e.x.max(e.y) * resolution < MIN_CELLS_ACROSS as Real && bounds_fit {
        scene.bounds
    } else {
        area
    }
}

/// The cells of a scene's grid at `resolution` ([`Grid::from_scene`]): its area
/// ([`scene_area`]) and the wall ring, as a real so that a grid past any limit still counts.
pub fn scene_cells(scene: &Scene, resolution: Real) -> Real {
    let e = scene_area(scene, resolution).extent();
    ((e.x * resolution).ceil() + 2.0) * ((e.y * resolution).ceil() + 2.0)
}

/// A grid of square cells. Cell `(i, j)` covers `[x0 + i h, x0 + (i + 1) h] x
/// [y0 + j h, y0 + (j + 1) h]` with `(x0, y0) = origin`, `h = cell`. The outermost ring of
/// cells is always occupied: it is the wall that bounds the free space.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    width: usize,
    height: usize,
    origin: Point,
    cell: Real,
    occ: Vec<bool>,
}

impl Grid {
    /// A grid of `width x height` cells (walls included), all free inside the wall ring.
    pub fn new(width: usize, height: usize, origin: Point, cell: Real) -> Result<Self, GridError> {
        if !(cell.is_finite() && cell > 0.0) {
            return Err(GridError::Resolution(1.0 / cell));
        }
        let cells = width.saturating_mul(height);
        if cells > MAX_CELLS || width < 3 || height < 3 {
            return Err(GridError::TooLarge {
                cells,
                max: MAX_CELLS,
            });
        }
        let mut g = Self {
            width,
            height,
            origin,
            cell,
            occ: vec![false; cells],
        };
        g.wall();
        Ok(g)
    }

    /// A grid from occupancy (`true` = occupied), row-major from `(0, 0)`; the outer ring is
    /// made a wall.
    pub fn from_occupancy(
        width: usize,
        height: usize,
        origin: Point,
        cell: Real,
        occ: Vec<bool>,
    ) -> Result<Self, GridError> {
        if occ.len() != width.saturating_mul(height) {
            return Err(GridError::Size {
                got: occ.len(),
                width,
                height,
            });
        }
        let mut g = Self::new(width, height, origin, cell)?;
        g.occ = occ;
        g.wall();
        Ok(g)
    }

    /// Rasterises a scene at `resolution` cells per map unit: its working area (the bounds
    /// where they are within three times the box of the obstacles and ends,
    /// [`Scene::working_area`]) plus a one-cell wall ring; a cell is occupied when its
    /// centre is inside or on an (inflated) circle. An area too small for the grid's least
    /// size at this resolution is the bounds.
    pub fn from_scene(scene: &Scene, resolution: Real) -> Result<Self, GridError> {
        if !(resolution.is_finite() && resolution > 0.0) {
            return Err(GridError::Resolution(resolution));
        }
        let h = 1.0 / resolution;
        let area = scene_area(scene, resolution);
        let ext = area.extent();
        let w = (ext.x / h).ceil();
        let hh = (ext.y / h).ceil();
        if w.max(hh) < MIN_CELLS_ACROSS as Real {
            return Err(GridError::TooCoarse {
                cells: w.max(hh) as usize,
                min: MIN_CELLS_ACROSS,
            });
        }
        if w * hh > MAX_CELLS as Real {
            return Err(GridError::TooFine {
                cells: (w * hh).min(usize::MAX as Real) as usize,
                max: MAX_CELLS,
                fits: finest_resolution(ext.x, ext.y),
            });
        }
        let (width, height) = (w as usize + 2, hh as usize + 2);
        let origin = Point::new(area.min.x - h, area.min.y - h);
        let mut g = Self::new(width, height, origin, h)?;
        for c in scene.circles() {
            g.fill_disc(&c.center, c.radius);
        }
        Ok(g)
    }

    /// Marks every cell whose centre lies in the closed disc.
    pub fn fill_disc(&mut self, center: &Point, radius: Real) {
        let h = self.cell;
        let to_i =
            |x: Real, o: Real, n: usize| (((x - o) / h - 0.5).clamp(0.0, n as Real - 1.0)) as usize;
        let i0 = to_i(center.x - radius, self.origin.x, self.width);
        let i1 = to_i(center.x + radius, self.origin.x, self.width) + 1;
        let j0 = to_i(center.y - radius, self.origin.y, self.height);
        let j1 = to_i(center.y + radius, self.origin.y, self.height) + 1;
        let r2 = radius * radius;
        for j in j0..=j1.min(self.height - 1) {
            for i in i0..=i1.min(self.width - 1) {
                let p = self.center(i, j);
                if (p - center).norm_squared() <= r2 {
                    self.occ[j * self.width + i] = true;
                }
            }
        }
    }

    fn wall(&mut self) {
        let (w, h) = (self.width, self.height);
        for i in 0..w {
            self.occ[i] = true;
            self.occ[(h - 1) * w + i] = true;
        }
        for j in 0..h {
            self.occ[j * w] = true;
            self.occ[j * w + w - 1] = true;
        }
    }

    /// Cells across.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Cells up.
    pub fn height(&self) -> usize {
        self.height
    }

    /// Lower-left corner of cell `(0, 0)`.
    pub fn origin(&self) -> Point {
        self.origin
    }

    /// Cell size in map units.
    pub fn cell(&self) -> Real {
        self.cell
    }

    /// Cells per map unit.
    pub fn resolution(&self) -> Real {
        1.0 / self.cell
    }

    /// Raster index of `(i, j)`.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.width + i
    }

    /// Whether `(i, j)` is occupied.
    #[inline]
    pub fn occupied(&self, i: usize, j: usize) -> bool {
        self.occ[j * self.width + i]
    }

    /// Occupancy, row-major.
    pub fn occupancy(&self) -> &[bool] {
        &self.occ
    }

    /// Sets a cell; the wall ring stays occupied.
    pub fn set(&mut self, i: usize, j: usize, occupied: bool) {
        if i == 0 || j == 0 || i + 1 >= self.width || j + 1 >= self.height {
            return;
        }
        self.occ[j * self.width + i] = occupied;
    }

    /// Centre of cell `(i, j)`.
    #[inline]
    pub fn center(&self, i: usize, j: usize) -> Point {
        Point::new(
            self.origin.x + (i as Real + 0.5) * self.cell,
            self.origin.y + (j as Real + 0.5) * self.cell,
        )
    }

    /// The corner point `(i, j)` (lower-left corner of cell `(i, j)`).
    #[inline]
    pub fn corner(&self, i: usize, j: usize) -> Point {
        Point::new(
            self.origin.x + i as Real * self.cell,
            self.origin.y + j as Real * self.cell,
        )
    }

    /// The cell holding `p`, if any.
    pub fn cell_of(&self, p: &Point) -> Option<(usize, usize)> {
        cell_holding(&self.origin, self.cell, self.width, self.height, p)
    }
}
