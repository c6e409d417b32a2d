//! Homotopy signatures of paths with fixed ends in the plane minus obstacle points.
//!
//! [`Rays`]: from each obstacle's representative point a ray goes to infinity in one fixed
//! direction, so no two rays cross. A path's [`Signature`] is the sequence of signed ray
//! crossings (`+i`: ray `i` crossed from its right to its left), freely reduced (`+i -i`
//! cancels). The plane minus `n` points has the free group on `n` letters as fundamental
//! group, and that word is the path's element of it, so two paths with the same ends are
//! homotopic exactly when their reduced words are equal: an exact integer invariant
//! (homotopy, not only homology) that does not merge classes however many obstacles there
//! are.
//!
//! [`h_signature`]: the H-signature of Bhattacharya, Likhachev and Kumar, per obstacle the
//! complex integral of `dz / (z - z_i)` along the path; equal for homologous paths, and its
//! imaginary parts over `2 pi` give a distance between classes.

use homospline_geom::{Point, Real, Scene, Vector};
use multiversion::multiversion;

/// The ray system: one ray per representative point, all in one direction.
#[derive(Clone, Debug, PartialEq)]
pub struct Rays {
    origins: Vec<Point>,
    dir: Vector,
    /// `(q, i, origin_i)` sorted, `q = dir x origin_i`: a segment can only cross the rays
    /// whose `q` lies between its ends' (see [`Rays::cross_segment`]). The origin is copied
    /// in, so that a segment's candidates are read in one sweep of memory (on a map of
    /// hundreds of thousands of obstacles, reading each from `origins` missed the cache).
    by_q: Vec<(Real, usize, Point)>,
    /// Largest coordinate magnitude of the origins, for the candidate margin.
    scale: Real,
    /// The origins bucketed on a uniform grid, for box queries ([`Rays::sweep_is_clear`]).
    buckets: Buckets,
}

/// Origins bucketed on a uniform grid of about one origin per bucket.
#[derive(Clone, Debug, PartialEq)]
struct Buckets {
    lo: Point,
    /// Buckets per unit length.
    inv: Real,
    nx: usize,
    ny: usize,
    /// Bucket `b` holds `items[start[b]..start[b + 1]]`.
    start: Vec<u32>,
    items: Vec<u32>,
}

impl Buckets {
    fn new(origins: &[Point]) -> Self {
        let n = origins.len();
        let (mut lo, mut hi) = (Point::new(0.0, 0.0), Point::new(0.0, 0.0));
        if let Some(first) = origins.first() {
            (lo, hi) = (*first, *first);
            for o in origins {
                lo = lo.inf(o);
                hi = hi.sup(o);
            }
        }
        let (wx, wy) = ((hi.x - lo.x).max(1e-9), (hi.y - lo.y).max(1e-9));
        // About one origin per bucket; on origins (nearly) on a line the area is ~0 and the
        // side is set by the line's length instead, else a query would walk thousands of
        // empty rows.
        let side = (wx * wy / n.max(1) as Real)
            .sqrt()
            .max(wx.max(wy) / n.clamp(1, 4096) as Real);
        let inv = 1.0 / side;
        let nx = ((wx * inv) as usize + 1).min(4096);
        let ny = ((wy * inv) as usize + 1).min(4096);
        let bucket = |o: &Point| {
            let i = (((o.x - lo.x) * inv) as usize).min(nx - 1);
            let j = (((o.y - lo.y) * inv) as usize).min(ny - 1);
            j * nx + i
        };
        let mut count = vec![0u32; nx * ny + 1];
        for o in origins {
            count[bucket(o) + 1] += 1;
        }
        for b in 0..nx * ny {
            count[b + 1] += count[b];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; n];
        for (k, o) in origins.iter().enumerate() {
            let b = bucket(o);
            items[fill[b] as usize] = k as u32;
            fill[b] += 1;
        }
        Self {
            lo,
            inv,
            nx,
            ny,
            start: count,
            items,
        }
    }

    /// Whether some origin in the closed box `[lo, hi]` satisfies `hit` (given its index
    /// and itself); the origins are tested each once, in a fixed order.
    fn any_in_box(
        &self,
        origins: &[Point],
        lo: &Point,
        hi: &Point,
        mut hit: impl FnMut(usize, &Point) -> bool,
    ) -> bool {
        if origins.is_empty() {
            return false;
        }
        let clamp =
            |v: Real, n: usize| -> usize { if v <= 0.0 { 0 } else { (v as usize).min(n - 1) } };
        let (i0, i1) = (
            clamp((lo.x - self.lo.x) * self.inv, self.nx),
            clamp((hi.x - self.lo.x) * self.inv, self.nx),
        );
        let (j0, j1) = (
            clamp((lo.y - self.lo.y) * self.inv, self.ny),
            clamp((hi.y - self.lo.y) * self.inv, self.ny),
        );
        (j0..=j1).any(|j| {
            let row = j * self.nx;
            let (a, b) = (
                self.start[row + i0] as usize,
                self.start[row + i1 + 1] as usize,
            );
            self.items[a..b].iter().any(|&k| {
                let o = &origins[k as usize];
                o.x >= lo.x && o.x <= hi.x && o.y >= lo.y && o.y <= hi.y && hit(k as usize, o)
            })
        })
    }
}

/// A reduced word of signed ray crossings: letter `+(i + 1)` or `-(i + 1)` for ray `i`.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct Signature(pub Vec<i32>);

impl Signature {
    /// The empty word: the class of paths that cross no ray on balance.
    pub fn identity() -> Self {
        Self(Vec::new())
    }

    /// Appends one letter, reducing.
    pub fn push(&mut self, letter: i32) {
        if self.0.last() == Some(&-letter) {
            self.0.pop();
        } else {
            self.0.push(letter);
        }
    }

    /// `self` followed by `other`, reduced.
    pub fn concat(&self, other: &Signature) -> Signature {
        let mut s = self.clone();
        for &l in &other.0 {
            s.push(l);
        }
        s
    }

    /// The word of the reversed path.
    pub fn inverse(&self) -> Signature {
        Signature(self.0.iter().rev().map(|l| -l).collect())
    }

    /// Whether it is the empty word.
    pub fn is_identity(&self) -> bool {
        self.0.is_empty()
    }
}

impl std::fmt::Display for Signature {
    /// A stable text form: `e` for the empty word, else letters such as `+3-1+12`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.is_empty() {
            return f.write_str("e");
        }
        for l in &self.0 {
            write!(f, "{}{}", if *l > 0 { '+' } else { '-' }, l.abs())?;
        }
        Ok(())
    }
}

impl Rays {
    /// Rays from `origins` in a fixed direction. The direction is tilted off the axes, and
    /// turned further if two origins would lie on one ray.
    pub fn new(origins: Vec<Point>) -> Self {
        let mut angle: Real = 1.4137;
        let scale = scale_of(&origins);
        loop {
            let dir = Vector::new(angle.cos(), angle.sin());
            // Two origins on one line along `dir`: |q(b) - q(a)| <= 1e-9 (1 + |b - a|), with
            // q(p) = dir x p. Such pairs are within 1e-9 (1 + diameter) of each other in q
            // (widened past rounding), so only neighbours in q order are tested: O(n log n)
            // rather than all pairs, with the same answer.
            let mut qs: Vec<(Real, usize)> = origins
                .iter()
                .enumerate()
                .map(|(i, o)| (dir.x * o.y - dir.y * o.x, i))
                .collect();
            qs.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let window = 2e-9 * (1.0 + 2.0 * scale) + 1e-12 * scale;
            let collinear = (0..qs.len()).any(|x| {
                qs[x + 1..]
                    .iter()
                    .take_while(|(q, _)| q - qs[x].0 <= window)
                    .any(|&(_, j)| {
                        let v = origins[j] - origins[qs[x].1];
                        (dir.x * v.y - dir.y * v.x).abs() <= 1e-9 * (1.0 + v.norm())
                    })
            });
            if !collinear || angle > 1.7 {
                let buckets = Buckets::new(&origins);
                let by_q = qs.iter().map(|&(q, i)| (q, i, origins[i])).collect();
                return Self {
                    origins,
                    dir,
                    by_q,
                    scale,
                    buckets,
                };
            }
            angle += 0.0123;
        }
    }

    /// Rays from the representatives of `scene`'s topological obstacles, in their order
    /// (ray `i` is obstacle `i`).
    pub fn for_scene(scene: &Scene) -> Self {
        Self::new(
            scene
                .topological_obstacles()
                .iter()
                .map(|t| t.representative)
                .collect(),
        )
    }

    /// The rays' common direction: the first of the angles `1.4137 + 0.0123 k` (radians, up
    /// to 1.7) along which no two origins lie on one line.
    pub fn direction(&self) -> Vector {
        self.dir
    }

    /// Number of rays.
    pub fn len(&self) -> usize {
        self.origins.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.origins.is_empty()
    }

    /// The representative points.
    pub fn origins(&self) -> &[Point] {
        &self.origins
    }

    /// Side of `p` with respect to the line along the rays' direction through `o` (ray `i`'s
    /// line when `o` is its origin): `true` on the left (or on the line).
    #[inline]
    fn left_of(&self, o: &Point, p: &Point) -> bool {
        let v = p - o;
        self.dir.x * v.y - self.dir.y * v.x >= 0.0
    }

    /// The crossing of segment `a -> b`, whose ends lie on different sides of ray `i`'s line
    /// (`b` on the left when `lb`), with that ray: where the segment meets the line (its
    /// parameter along the segment) and the signed letter, or `None` when the meeting point
    /// is not on the ray.
    #[inline]
    fn crossing(&self, i: usize, a: &Point, b: &Point, lb: bool) -> Option<(Real, i32)> {
        self.crossing_of(i, self.origins[i], a, b, lb)
    }

    /// [`Rays::crossing`] with ray `i`'s origin `o` given.
    #[inline]
    fn crossing_of(
        &self,
        i: usize,
        o: Point,
        a: &Point,
        b: &Point,
        lb: bool,
    ) -> Option<(Real, i32)> {
        let (da, db) = (self.dir.perp(&(a - o)), self.dir.perp(&(b - o)));
        let t = da / (da - db);
        let x = a + (b - a) * t;
        let letter = i as i32 + 1;
        ((x - o).dot(&self.dir) >= 0.0).then_some((t, if lb { letter } else { -letter }))
    }

    /// Whether the straight segment between the ends of `stretch` can replace it in any path
    /// without changing the path's class: the loop along `stretch` and back along the
    /// segment has the empty word. The rest of the path crosses the same rays either way, so
    /// this is the whole path's signature compared, for the cost of the stretch's.
    pub fn chord_keeps_class(&self, stretch: &[Point]) -> bool {
        let (Some(first), Some(last)) = (stretch.first(), stretch.last()) else {
            return true;
        };
        let mut word = self.signature(stretch);
        self.cross_segment(last, first, &mut word);
        word.is_identity()
    }

    /// Appends the crossings of segment `a -> b` to `word`, in the order along the segment.
    pub fn cross_segment(&self, a: &Point, b: &Point, word: &mut Signature) {
        let mut cursor = None;
        let ends = [self.key(a), self.key(b)];
        self.cross_segment_at(a, b, ends, word, &mut cursor);
    }

    /// A point's `q = dir x p` and largest coordinate magnitude, which the crossing test of
    /// either segment it ends reads.
    fn key(&self, p: &Point) -> (Real, Real) {
        (self.dir.x * p.y - self.dir.y * p.x, p.coords.amax())
    }

    /// [`Rays::cross_segment`] with a cursor into the rays sorted by `q`: consecutive
    /// segments of a polyline have nearby `q` ranges, so the first ray in range is found by
    /// walking from the previous segment's (a binary search when it is far or unknown).
    /// The result does not depend on the cursor.
    fn cross_segment_at(
        &self,
        a: &Point,
        b: &Point,
        [(qa, ma), (qb, mb)]: [(Real, Real); 2],
        word: &mut Signature,
        cursor: &mut Option<usize>,
    ) {
        // Ray i's side test is `q(p) - q(o_i) >= 0` up to rounding, `q(p) = dir x p` (`qa`,
        // `qb`: [`Rays::key`]): only rays with `q(o_i)` between `q(a)` and `q(b)` (widened far
        // beyond the rounding) can change sides; the exact test below decides, so the result
        // is the same as testing all.
        let margin = 1e-9 * (1.0 + self.scale + ma + mb);
        let (lo, hi) = (qa.min(qb) - margin, qa.max(qb) + margin);
        let first = match *cursor {
            Some(mut c) => {
                // partition_point by a short walk: by_q[..first] < lo <= by_q[first..].
                let mut steps = 0;
                while c > 0 && self.by_q[c - 1].0 >= lo && steps < 16 {
                    c -= 1;
                    steps += 1;
                }
                while c < self.by_q.len() && self.by_q[c].0 < lo && steps < 16 {
                    c += 1;
                    steps += 1;
                }
                let settled = (c == 0 || self.by_q[c - 1].0 < lo)
                    && (c == self.by_q.len() || self.by_q[c].0 >= lo);
                if settled {
                    c
                } else {
                    self.by_q.partition_point(|&(q, ..)| q < lo)
                }
            }
            None => self.by_q.partition_point(|&(q, ..)| q < lo),
        };
        *cursor = Some(first);
        let candidates = self.by_q[first..]
            .iter()
            .take_while(|&&(q, ..)| q <= hi)
            .map(|&(_, i, o)| (i, o));
        self.push_crossings(a, b, candidates, &mut Vec::new(), word);
    }

    /// Appends to `word` the letters of segment `a -> b` against the rays of `candidates`
    /// (index and origin; any order, each once), in the order the segment crosses them:
    /// by parameter along it, then by letter. `hits` is scratch space.
    #[inline]
    fn push_crossings(
        &self,
        a: &Point,
        b: &Point,
        candidates: impl IntoIterator<Item = (usize, Point)>,
        hits: &mut Vec<(Real, i32)>,
        word: &mut Signature,
    ) {
        hits.clear();
        for (i, o) in candidates {
            let (la, lb) = (self.left_of(&o, a), self.left_of(&o, b));
            if la != lb {
                hits.extend(self.crossing_of(i, o, a, b, lb));
            }
        }
        hits.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)));
        for &(_, l) in hits.iter() {
            word.push(l);
        }
    }

    /// Whether `to` is proven to have the signature of `from` without computing it: the two
    /// polylines have as many points and the same ends, and the straight-line homotopy
    /// between them (point `k` of one moving to point `k` of the other) meets no origin. The
    /// homotopy's quadrilateral between segment `k` of either lies in the convex hull of its
    /// four corners (the union of the four triangles on three of them); when no origin is in
    /// any hull or within a margin of it (far beyond rounding, so the crossing tests of both
    /// polylines are exact), the paths are homotopic in the plane minus the origins and their
    /// words are equal. `false` proves nothing: compute the signature. Cost: the hulls' boxes'
    /// buckets, about one origin per bucket; an optimiser's step moves a curve little, so this
    /// is far cheaper than the signature among thousands of origins.
    pub fn sweep_is_clear(&self, from: &[Point], to: &[Point]) -> bool {
        if from.len() != to.len() || from.len() < 2 || !same_ends(from, to) {
            return false;
        }
        (0..from.len() - 1).all(|k| self.quad_is_clear([from[k], from[k + 1], to[k + 1], to[k]]))
    }

    /// How far each point of `polyline` may move, its ends fixed, with its signature
    /// unchanged: the least distance from an origin to the polyline, less a margin far
    /// beyond rounding (that of [`Rays::sweep_is_clear`], for the polyline's own box), and 0
    /// when nothing is left or there is no polyline. Another polyline of as many points and
    /// the same ends, whose point `k` lies less than this from point `k` of `polyline`, has
    /// the same signature: the straight-line homotopy between them stays within that
    /// distance of `polyline` (a point of a segment between two moved points moves by at
    /// most the larger move), so it meets no origin. For a caller that checks many small
    /// moves of one polyline known to be in a class: one pass over the origins here, then
    /// a distance per move instead of a signature. `+inf` with no origins.
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_geom::Point;
    /// use homospline_homotopy::Rays;
    ///
    /// let rays = Rays::new(vec![Point::new(0.0, 0.0)]);
    /// let above = [Point::new(-5.0, 2.0), Point::new(0.0, 2.0), Point::new(5.0, 2.0)];
    /// let margin = rays.word_margin(&above);
    /// assert!(margin > 1.99 && margin < 2.0);
    /// let lower = [above[0], Point::new(0.0, 0.5), above[2]];
    /// assert!((lower[1] - above[1]).norm() < margin);
    /// assert_eq!(rays.signature(&lower), rays.signature(&above));
    /// ```
    ///
    /// # See also
    /// [`Rays::sweep_is_clear`], which proves a move of any size clear of the origins.
    pub fn word_margin(&self, polyline: &[Point]) -> Real {
        if polyline.len() < 2 {
            return 0.0;
        }
        let (_, _, rounding) = self.margin_box(polyline);
        let least = self
            .origins
            .iter()
            .map(|o| {
                polyline
                    .windows(2)
                    .map(|w| homospline_geom::math::distance_point_segment(o, &w[0], &w[1]))
                    .fold(Real::INFINITY, Real::min)
            })
            .fold(Real::INFINITY, Real::min);
        (least - 2.0 * rounding).max(0.0)
    }

    /// How far `p` may move without crossing the line of any ray, less the same rounding
    /// margin as [`Rays::word_margin`]'s: the least distance from `p` to a ray's whole line
    /// (0 when nothing is left, `+inf` without rays). A polyline's end that moves by less
    /// than this crosses no ray on the way, so the end of a polyline moved within its
    /// [`Rays::word_margin`] may also move by that much (the computed last point of a curve
    /// differs from its goal by rounding) and keep the word.
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_geom::Point;
    /// use homospline_homotopy::Rays;
    ///
    /// let rays = Rays::new(vec![Point::new(0.0, 0.0)]);
    /// let on_the_line = Point::new(0.0, 0.0) + rays.direction() * 5.0;
    /// assert_eq!(rays.line_gap(&on_the_line), 0.0);
    /// assert!(rays.line_gap(&Point::new(0.0, 0.0)) == 0.0);
    /// ```
    pub fn line_gap(&self, p: &Point) -> Real {
        let dir = self.direction();
        let len = dir.norm();
        let (_, _, rounding) = self.margin_box(std::slice::from_ref(p));
        let least = self
            .origins
            .iter()
            .map(|o| dir.perp(&(p - o)).abs() / len)
            .fold(Real::INFINITY, Real::min);
        (least - 2.0 * rounding).max(0.0)
    }

    /// Whether no origin lies in or near the convex hull of the quadrilateral `[a, b, c, d]`
    /// ([`Rays::sweep_is_clear`]): the loop round it is then contractible.
    fn quad_is_clear(&self, [a, b, c, d]: [Point; 4]) -> bool {
        let (lo, hi, box_margin) = self.margin_box(&[a, b, c, d]);
        !self.buckets.any_in_box(&self.origins, &lo, &hi, |_, o| {
            [(a, b, c), (a, c, d), (a, b, d), (b, c, d)]
                .iter()
                .any(|(p, q, r)| near_triangle(o, p, q, r, box_margin))
        })
    }

    /// The bounding box of `pts`, widened far beyond rounding, and the width added.
    fn margin_box(&self, pts: &[Point]) -> (Point, Point, Real) {
        let (mut lo, mut hi) = (pts[0], pts[0]);
        for p in &pts[1..] {
            lo = lo.inf(p);
            hi = hi.sup(p);
        }
        let box_margin = 1e-9 * (1.0 + self.scale) + 1e-12 * (lo.coords.amax() + hi.coords.amax());
        lo -= Vector::repeat(box_margin);
        hi += Vector::repeat(box_margin);
        (lo, hi, box_margin)
    }

    /// Whether `to` has the class of `from` (two polylines with the same ends), decided from
    /// the obstacles near where they differ: `Some(true)` proven the same, `Some(false)`
    /// proven different, `None` when that would read more than [`LOCAL_ORIGINS`] origins
    /// (or make more than [`LOCAL_TESTS`] side tests for one loop) or the ends differ
    /// (compute the signatures).
    ///
    /// The two are cut into cells at matching points (point `k` of each when they have as
    /// many; else every point of the one with fewer and the point of the other at about the
    /// same share of its length): a cell is the loop along `from`'s stretch, across, back
    /// along `to`'s and across again. The loop
    /// along `from` and back along `to` is the product of the cells' loops, each conjugated.
    /// A cell of one segment each with no origin in or near its convex hull (the test of
    /// [`Rays::sweep_is_clear`]), or of more with none in or near its bounding box, is
    /// contractible. A run of the others, consecutive, makes one closed loop, whose class in
    /// the plane minus every origin is trivial exactly when it is in its bounding box minus
    /// the origins inside (the box's group is a free factor of the plane's): its word is
    /// read against the rays of those origins alone. Every run's word empty proves the same
    /// class; a single run whose word is not empty proves another (the loop is then a
    /// conjugate of it); several runs, some not empty, decide nothing.
    ///
    /// # Examples
    ///
    /// ```
    /// use homospline_geom::Point;
    /// use homospline_homotopy::Rays;
    ///
    /// let rays = Rays::new(vec![Point::new(0.0, 0.0), Point::new(10.0, 0.0)]);
    /// let s = Point::new(-5.0, 1.0);
    /// let t = Point::new(15.0, 1.0);
    /// let above = [s, Point::new(0.0, 1.0), Point::new(10.0, 1.0), t];
    /// let higher = [s, Point::new(0.0, 2.0), Point::new(5.0, 4.0), Point::new(10.0, 3.0), t];
    /// let dips = [s, Point::new(0.0, -1.0), Point::new(10.0, 1.0), t];
    /// assert_eq!(rays.same_class(&above, &higher), Some(true));
    /// assert_eq!(rays.same_class(&above, &dips), Some(false));
    /// assert_ne!(rays.signature(&above), rays.signature(&dips));
    /// ```
    ///
    /// # See also
    /// [`Rays::sweep_is_clear`], the proof without reading any word; [`Rays::signature`].
    pub fn same_class(&self, from: &[Point], to: &[Point]) -> Option<bool> {
        if from.len() < 2 || to.len() < 2 || !same_ends(from, to) {
            return None;
        }
        let pairs = matching_points(from, to);
        let cells = pairs.len() - 1;
        let ends = |c: usize| pairs[c];
        let mut runs: Vec<(usize, usize)> = Vec::new();
        for c in 0..cells {
            let ((i0, j0), (i1, j1)) = (ends(c), ends(c + 1));
            let clear = if i1 == i0 + 1 && j1 == j0 + 1 {
                self.quad_is_clear([from[i0], from[i1], to[j1], to[j0]])
            } else {
                let mut pts = from[i0..=i1].to_vec();
                pts.extend_from_slice(&to[j0..=j1]);
                let (lo, hi, _) = self.margin_box(&pts);
                !self
                    .buckets
                    .any_in_box(&self.origins, &lo, &hi, |_, _| true)
            };
            if clear {
                continue;
            }
            match runs.last_mut() {
                Some((_, end)) if *end == c => *end = c + 1,
                _ => runs.push((c, c + 1)),
            }
        }
        let mut budget = LOCAL_ORIGINS;
        let mut all_empty = true;
        for &(c0, c1) in &runs {
            let ((i0, j0), (i1, j1)) = (ends(c0), ends(c1));
            let mut lp: Vec<Point> = from[i0..=i1].to_vec();
            lp.extend(to[j0..=j1].iter().rev());
            lp.push(from[i0]);
            all_empty &= self.local_word_is_empty(&lp, &mut budget)?;
            if !all_empty && runs.len() > 1 {
                return None;
            }
        }
        Some(all_empty)
    }

    /// Whether the closed polyline `lp` has the empty word against the rays of the origins
    /// in its bounding box (widened as [`Rays::margin_box`]); `None` when they are more
    /// than `budget` (which they are taken from).
    fn local_word_is_empty(&self, lp: &[Point], budget: &mut usize) -> Option<bool> {
        let (lo, hi, _) = self.margin_box(lp);
        let mut near: Vec<usize> = Vec::new();
        let over = self.buckets.any_in_box(&self.origins, &lo, &hi, |i, _| {
            near.push(i);
            near.len() > *budget
        });
        if over || lp.len().saturating_mul(near.len()) > LOCAL_TESTS {
            return None;
        }
        *budget -= near.len();
        let mut word = Signature::identity();
        let mut hits = Vec::new();
        for s in lp.windows(2) {
            let candidates = near.iter().map(|&i| (i, self.origins[i]));
            self.push_crossings(&s[0], &s[1], candidates, &mut hits, &mut word);
        }
        Some(word.is_identity())
    }

    /// The signature of a polyline.
    pub fn signature(&self, path: &[Point]) -> Signature {
        if self.origins.len() <= FEW_RAYS {
            return self.signature_by_sides(path);
        }
        self.signature_by_q(path)
    }

    /// [`Rays::signature`] by the rays' `q` order ([`Rays::cross_segment_at`]): each segment
    /// tests only the rays whose `q` lies between its ends'. For many rays.
    fn signature_by_q(&self, path: &[Point]) -> Signature {
        let mut w = Signature::identity();
        let mut cursor = None;
        let Some(first) = path.first() else {
            return w;
        };
        let mut key_a = self.key(first);
        for s in path.windows(2) {
            let key_b = self.key(&s[1]);
            self.cross_segment_at(&s[0], &s[1], [key_a, key_b], &mut w, &mut cursor);
            key_a = key_b;
        }
        w
    }
}

/// The points at which [`Rays::same_class`] cuts `a` and `b` into cells, as pairs of
/// indices, both increasing, from `(0, 0)` to the last of each: point `k` of each when they
/// have as many points; else every point of the one with fewer, each with the first point
/// of the other at or past the same share of its length (at least one point on, leaving one
/// for each pair still to come).
fn matching_points(a: &[Point], b: &[Point]) -> Vec<(usize, usize)> {
    if a.len() == b.len() {
        return (0..a.len()).map(|k| (k, k)).collect();
    }
    let (short, long, swap) = if a.len() < b.len() {
        (a, b, false)
    } else {
        (b, a, true)
    };
    let shares = |p: &[Point]| -> Vec<Real> {
        let mut acc = vec![0.0; p.len()];
        for k in 1..p.len() {
            acc[k] = acc[k - 1] + (p[k] - p[k - 1]).norm();
        }
        let total = acc[p.len() - 1].max(Real::MIN_POSITIVE);
        acc.iter_mut().for_each(|v| *v /= total);
        acc
    };
    let (sa, sb) = (shares(short), shares(long));
    let (n, m) = (short.len(), long.len());
    let mut out = Vec::with_capacity(n);
    let mut j = 0;
    for (k, &share) in sa.iter().enumerate() {
        j = if k == 0 {
            0
        } else if k == n - 1 {
            m - 1
        } else {
            let mut at = j + 1;
            while at < m - 1 && sb[at] < share {
                at += 1;
            }
            at.min(m - n + k)
        };
        out.push(if swap { (j, k) } else { (k, j) });
    }
    out
}

/// Whether two polylines start at one point and end at one point.
fn same_ends(a: &[Point], b: &[Point]) -> bool {
    a.first() == b.first() && a.last() == b.last()
}

/// Most origins [`Rays::same_class`] reads near where two polylines differ before it leaves
/// the answer to their signatures.
pub const LOCAL_ORIGINS: usize = 4096;

/// Most side tests (a loop's points times the origins in its box) [`Rays::same_class`]
/// makes for one loop: a long loop among thousands of origins would cost more than the
/// signature of a whole map path (about 18 ms on a random 4096^2 map).
pub const LOCAL_TESTS: usize = 1 << 21;

/// With at most this many rays, [`Rays::signature`] tests every point against every ray's
/// line (`Rays::signature_by_sides`): a few vectorised operations per ray and point,
/// against `Rays::cross_segment_at`'s search and bookkeeping per segment (the class check
/// of an optimiser's candidate, 50 or so points among a scene's few obstacles, was a seventh
/// of a plan's instructions that way).
pub const FEW_RAYS: usize = 16;

impl Rays {
    /// [`Rays::signature`] for at most [`FEW_RAYS`] rays: a segment can cross ray `i` only
    /// where its ends lie on different sides of the ray's line ([`Rays::left`]'s exact test,
    /// the same expression as [`Rays::cross_segment_at`]'s), found ray by ray over every
    /// point at once (a loop the compiler vectorises), each crossing by [`Rays::crossing`] as
    /// there; the crossings are pushed in the same order (by segment, then by their parameter
    /// along it, then by letter), so the word is the same as [`Rays::signature_by_q`]'s.
    fn signature_by_sides(&self, path: &[Point]) -> Signature {
        let n = path.len();
        if n < 2 {
            return Signature::identity();
        }
        // `try_with`: a thread tearing down its locals gets fresh buffers instead of a panic.
        let mut scratch = SIDES_SCRATCH.try_with(|s| s.take()).unwrap_or_default();
        let w = self.signature_by_sides_in(path, &mut scratch);
        let _ = SIDES_SCRATCH.try_with(|s| s.set(scratch));
        w
    }

    /// [`Rays::signature_by_sides`] on the buffers of `scratch`.
    fn signature_by_sides_in(&self, path: &[Point], scratch: &mut SidesScratch) -> Signature {
        let n = path.len();
        let SidesScratch {
            xs,
            ys,
            left,
            flips,
            hits,
        } = scratch;
        xs.clear();
        xs.extend(path.iter().map(|p| p.x));
        ys.clear();
        ys.extend(path.iter().map(|p| p.y));
        left.clear();
        left.resize(n, 0);
        flips.clear();
        flips.resize(n - 1, 0);
        hits.clear();
        for (i, o) in self.origins.iter().enumerate() {
            sides_and_flips(xs, ys, o, &self.dir, left, flips);
            // Segments whose ends are on different sides, found 8 at a time (most words
            // of 8 segments have none, so this is cheaper than a byte scan; measured:
            // docs/performance.md, "Measurements behind the defaults").
            for (c, chunk) in flips.chunks(8).enumerate() {
                let mut word = [0u8; 8];
                word[..chunk.len()].copy_from_slice(chunk);
                if u64::from_ne_bytes(word) == 0 {
                    continue;
                }
                for (j, _) in chunk.iter().enumerate().filter(|(_, f)| **f != 0) {
                    let k = 8 * c + j;
                    let lb = left[k + 1] == 1;
                    if let Some((t, l)) = self.crossing(i, &path[k], &path[k + 1], lb) {
                        hits.push((k, t, l));
                    }
                }
            }
        }
        hits.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)).then(x.2.cmp(&y.2)));
        let mut w = Signature::identity();
        for &(_, _, l) in hits.iter() {
            w.push(l);
        }
        w
    }
}

/// The buffers of [`Rays::signature_by_sides`], kept per thread between calls: an
/// optimiser's guard checks the class of every candidate curve, and these five allocations
/// were most of a scene plan's allocation (1.8 % of its samples).
#[derive(Default)]
struct SidesScratch {
    xs: Vec<Real>,
    ys: Vec<Real>,
    left: Vec<u8>,
    flips: Vec<u8>,
    /// (segment, parameter along it, letter) of every crossing.
    hits: Vec<(usize, Real, i32)>,
}

thread_local! {
    /// Taken out for a signature and put back after it (a `Cell`: a nested call, which
    /// does not happen, would only allocate its own).
    static SIDES_SCRATCH: std::cell::Cell<SidesScratch> =
        std::cell::Cell::new(SidesScratch::default());
}

/// [`Rays::left`] of every point `(xs[k], ys[k])` for the ray from `o` along `dir` (1 on the
/// left or on the line; the same expression, `v = p - o`, `dir x v >= 0`), and whether each
/// segment's ends are on different sides.
#[multiversion(targets("x86_64+avx512f+avx512vl+avx512bw+avx2", "x86_64+avx2"))]
fn sides_and_flips(
    xs: &[Real],
    ys: &[Real],
    o: &Point,
    dir: &Vector,
    left: &mut [u8],
    flips: &mut [u8],
) {
    let (ox, oy, dx, dy) = (o.x, o.y, dir.x, dir.y);
    for ((l, &x), &y) in left.iter_mut().zip(xs).zip(ys) {
        *l = u8::from(dx * (y - oy) - dy * (x - ox) >= 0.0);
    }
    for (f, pair) in flips.iter_mut().zip(left.windows(2)) {
        *f = pair[0] ^ pair[1];
    }
}

/// Whether `o` is in the closed triangle `p q r` (any orientation, degenerate included) or
/// within `margin` of its edges.
fn near_triangle(o: &Point, p: &Point, q: &Point, r: &Point, margin: Real) -> bool {
    let cross = |a: &Point, b: &Point| (b - a).perp(&(o - a));
    let (u, v, w) = (cross(p, q), cross(q, r), cross(r, p));
    let inside = (u >= 0.0 && v >= 0.0 && w >= 0.0) || (u <= 0.0 && v <= 0.0 && w <= 0.0);
    inside
        || [(p, q), (q, r), (r, p)]
            .iter()
            .any(|(a, b)| homospline_geom::math::distance_point_segment(o, a, b) <= margin)
}

/// The largest coordinate magnitude of `points` (0 for none).
fn scale_of(points: &[Point]) -> Real {
    points.iter().map(|o| o.coords.amax()).fold(0.0, Real::max)
}

/// The H-signature of a polyline: per representative point `z_i`, the complex integral of
/// `dz / (z - z_i)`, as `(real, imaginary)`. Each segment contributes `log((b - z_i) /
/// (a - z_i))` on the principal branch (a segment turns by less than pi around a point off
/// it). The real parts depend only on the ends; the imaginary parts are the winding angles.
pub fn h_signature(path: &[Point], origins: &[Point]) -> Vec<(Real, Real)> {
    origins
        .iter()
        .map(|z| {
            let mut acc = (0.0, 0.0);
            for s in path.windows(2) {
                let (a, b) = (s[0] - z, s[1] - z);
                // (b / a) as a complex number.
                let den = a.norm_squared();
                let re = (b.x * a.x + b.y * a.y) / den;
                let im = (b.y * a.x - b.x * a.y) / den;
                acc.0 += 0.5 * (re * re + im * im).ln();
                acc.1 += im.atan2(re);
            }
            acc
        })
        .collect()
}

/// Distance between two H-signatures: the largest difference of winding numbers
/// (imaginary parts over `2 pi`); 0 for homologous paths, at least 1 otherwise.
pub fn h_distance(a: &[(Real, Real)], b: &[(Real, Real)]) -> Real {
    a.iter()
        .zip(b)
        .map(|(x, y)| ((x.1 - y.1) / std::f64::consts::TAU).abs())
        .fold(0.0, Real::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn point() -> impl Strategy<Value = Point> {
        // Half-unit coordinates: many points fall exactly on a ray's line or on an origin's
        // level, where the side test's ties decide.
        (-40i32..40, -40i32..40).prop_map(|(x, y)| Point::new(x as Real / 2.0, y as Real / 2.0))
    }

    proptest! {
        /// The side-mask word is the `q`-order word, letter for letter, for any polyline
        /// among up to [`FEW_RAYS`] origins (and, with more origins, still when asked).
        #[test]
        fn words_by_sides_equal_words_by_q(
            origins in proptest::collection::vec(point(), 1..=24),
            path in proptest::collection::vec(
                prop_oneof![point(), (-20.0..20.0f64, -20.0..20.0f64).prop_map(|(x, y)| Point::new(x, y))],
                0..60,
            ),
        ) {
            let mut origins = origins;
            origins.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
            origins.dedup();
            let rays = Rays::new(origins);
            prop_assert_eq!(rays.signature_by_sides(&path), rays.signature_by_q(&path));
        }
    }

    #[test]
    fn a_loop_round_one_origin_reads_its_letter_by_either_way() {
        let rays = Rays::new(vec![Point::new(0.0, 0.0), Point::new(5.0, 0.0)]);
        let square = [
            Point::new(-1.0, -1.0),
            Point::new(1.0, -1.0),
            Point::new(1.0, 1.0),
            Point::new(-1.0, 1.0),
            Point::new(-1.0, -1.0),
        ];
        let w = rays.signature_by_sides(&square);
        assert_eq!(w, rays.signature_by_q(&square));
        assert_eq!(w.to_string().len(), 2, "{w}");
    }
}
