//! The nearest-obstacle regions cleaned up for the crack graph: stray cells of a region, cut
//! off from the rest of it (the discrete regions can touch their obstacle only diagonally),
//! join a neighbouring region, so that every region is 4-connected and holds its obstacle and
//! the cracks have one independent cycle per obstacle. Two ways: bounded fills from the cracks
//! for small strays ([`local_strays`]), and a full labelling as the fallback ([`regions`]).

use crate::crack_bits::Cracks;
use crate::field::DistanceField;
use crate::grid::Grid;
use crate::union_find::find_root;

/// Largest stray component [`local_strays`] looks for.
const STRAY_LIMIT: usize = 16;

/// The small stray components (at most [`STRAY_LIMIT`] cells, holding no obstacle cell) of
/// the nearest-obstacle regions, each with the label of the neighbouring region it joins,
/// as `(cell, label)` pairs. Fills start from the cells on each side of every crack and stop
/// at a cell already known to belong to a large component.
pub(crate) fn local_strays(
    grid: &Grid,
    field: &DistanceField,
    cracks: &Cracks,
) -> Vec<(usize, u32)> {
    let (w, h) = (field.width(), field.height());
    let lab = |c: usize| field.nearest_at(c);
    let occ = grid.occupancy();
    // 0 unknown, 1 in a large or obstacle-holding component, 2 stray.
    let mut state = vec![0u8; w * h];
    let mut strays: Vec<Vec<usize>> = Vec::new();
    let mut fill = Vec::with_capacity(STRAY_LIMIT + 1);
    let mut stack = Vec::new();
    let cw = cracks.cw;
    // Every component's first cell in raster order has cracks on its left and lower sides
    // (its neighbours there are outside it, hence of another label): only such cells start
    // fills, which finds every component at a tenth of the work of starting from every crack.
    for (cc, ci, cj) in (0..h).flat_map(|cj| (0..w).map(move |ci| (cj * cw + ci, ci, cj))) {
        if cracks.deg[cc] < 2 || !(cracks.v[cc] && cracks.h[cc]) {
            continue;
        }
        {
            let start = cj * w + ci;
            if state[start] != 0 {
                continue;
            }
            let l = lab(start);
            fill.clear();
            stack.clear();
            stack.push((start, ci, cj));
            state[start] = 3; // in the current fill
            let mut large = false;
            while let Some((c, i, j)) = stack.pop() {
                fill.push(c);
                if occ[c] || fill.len() > STRAY_LIMIT {
                    large = true;
                    break;
                }
                for (n, ni, nj) in [
                    (i + 1 < w).then(|| (c + 1, i + 1, j)),
                    (j + 1 < h).then(|| (c + w, i, j + 1)),
                    (i > 0).then(|| (c - 1, i - 1, j)),
                    (j > 0).then(|| (c - w, i, j - 1)),
                ]
                .into_iter()
                .flatten()
                {
                    if lab(n) != l {
                        continue;
                    }
                    match state[n] {
                        0 => {
                            state[n] = 3;
                            stack.push((n, ni, nj));
                        }
                        1 => large = true,
                        _ => {}
                    }
                }
                if large {
                    break;
                }
            }
            let mark = if large { 1 } else { 2 };
            for &c in fill.iter().chain(stack.iter().map(|(c, _, _)| c)) {
                state[c] = mark;
            }
            if !large {
                let mut comp = fill.clone();
                comp.sort_unstable();
                strays.push(comp);
            }
        }
    }
    let mut out = Vec::new();
    for comp in &strays {
        // The first neighbour, in raster order of the component's cells, outside it.
        let l = lab(comp[0]);
        let new = comp.iter().find_map(|&c| {
            let (i, j) = (c % w, c / w);
            [
                (i + 1 < w).then(|| c + 1),
                (j + 1 < h).then(|| c + w),
                (i > 0).then(|| c - 1),
                (j > 0).then(|| c - w),
            ]
            .into_iter()
            .flatten()
            .map(|n| {
                out.iter()
                    .find(|&&(x, _)| x == n)
                    .map_or_else(|| lab(n), |&(_, m)| m)
            })
            .find(|&m| m != l)
        });
        if let Some(m) = new {
            out.extend(comp.iter().map(|&c| (c, m)));
        }
    }
    out
}

/// The region of every cell: its nearest obstacle, except that cells cut off from the rest
/// of their obstacle's region (the discrete regions can have stray cells that touch it only
/// diagonally) join the region of a 4-neighbour, so that every region is 4-connected and
/// holds its obstacle.
///
/// Two-pass connected-component labelling of equal-label cells (4-connected) with
/// union-find; a component is kept when it holds an occupied cell. Stray cells then take
/// the label of a kept neighbour, breadth-first from the kept cells that border them, in
/// raster order: deterministic.
pub(crate) fn regions(grid: &Grid, field: &DistanceField) -> Vec<u32> {
    let (w, h) = (field.width(), field.height());
    let mut label: Vec<u32> = (0..w * h).map(|c| field.nearest_at(c)).collect();
    let occ = grid.occupancy();
    let mut comp = vec![0u32; w * h];
    let mut parent: Vec<usize> = Vec::new();
    let mut keep: Vec<bool> = Vec::new();
    let root = |p: &mut [usize], i: u32| find_root(p, i as usize);
    for j in 0..h {
        for i in 0..w {
            let c = j * w + i;
            let l = label[c];
            let left = (i > 0 && label[c - 1] == l).then(|| comp[c - 1]);
            let up = (j > 0 && label[c - w] == l).then(|| comp[c - w]);
            let id = match (left, up) {
                (Some(a), Some(b)) => {
                    let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                    if ra != rb {
                        let (lo, hi) = (ra.min(rb), ra.max(rb));
                        parent[hi] = lo;
                        keep[lo] |= keep[hi];
                    }
                    ra.min(rb) as u32
                }
                (Some(a), None) => a,
                (None, Some(b)) => b,
                (None, None) => {
                    parent.push(parent.len());
                    keep.push(false);
                    (parent.len() - 1) as u32
                }
            };
            comp[c] = id;
            if occ[c] {
                let r = root(&mut parent, id);
                keep[r] = true;
            }
        }
    }
    let mut kept = vec![true; w * h];
    let mut any_stray = false;
    for c in 0..w * h {
        let r = root(&mut parent, comp[c]);
        if !keep[r] {
            kept[c] = false;
            any_stray = true;
        }
    }
    if !any_stray {
        return label;
    }
    let neighbours = |c: usize| {
        let (i, j) = (c % w, c / w);
        [
            (i + 1 < w).then(|| c + 1),
            (j + 1 < h).then(|| c + w),
            (i > 0).then(|| c - 1),
            (j > 0).then(|| c - w),
        ]
    };
    let mut queue: std::collections::VecDeque<usize> = (0..w * h)
        .filter(|&c| kept[c] && neighbours(c).into_iter().flatten().any(|n| !kept[n]))
        .collect();
    while let Some(c) = queue.pop_front() {
        for n in neighbours(c).into_iter().flatten() {
            if !kept[n] {
                kept[n] = true;
                label[n] = label[c];
                queue.push_back(n);
            }
        }
    }
    label
}
