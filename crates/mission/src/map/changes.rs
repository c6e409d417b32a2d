//! The changes between a prior map and its truth map: 8-connected groups of cells whose
//! state differs, each all blocked or all freed.

use homospline_maps::OccupancyMap;
use homospline_voronoi::grid::neighbours_8;

use crate::world::types::Change;

/// The 8-connected groups of cells that differ between `prior` and `truth`, each all blocked
/// or all freed, in raster order of their first cells.
pub(super) fn changes(prior: &OccupancyMap, truth: &OccupancyMap) -> Vec<Change> {
    let (w, h) = (prior.width, prior.height);
    let differs = |k: usize| prior.occupied[k] != truth.occupied[k];
    let mut seen = vec![false; w * h];
    let mut out = Vec::new();
    let (mut nb, mut nf) = (0, 0);
    for k0 in 0..w * h {
        if seen[k0] || !differs(k0) {
            continue;
        }
        let blocked = truth.occupied[k0];
        seen[k0] = true;
        let mut cells = vec![k0];
        let mut n = 0;
        while n < cells.len() {
            let k = cells[n];
            n += 1;
            for ((x, y), _) in neighbours_8(k % w, k / w, w, h) {
                let q = y * w + x;
                if !seen[q] && differs(q) && truth.occupied[q] == blocked {
                    seen[q] = true;
                    cells.push(q);
                }
            }
        }
        cells.sort_unstable();
        let name = if blocked {
            nb += 1;
            format!("blocked-{}", nb - 1)
        } else {
            nf += 1;
            format!("freed-{}", nf - 1)
        };
        out.push(Change {
            name,
            blocked,
            cells: cells.into_iter().map(|k| (k % w, k / w)).collect(),
        });
    }
    out
}
