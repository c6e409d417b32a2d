//! The memory a plan on a grid may need, checked against the process's address-space limit
//! before anything grid-sized is allocated: a map or scene too large for `ulimit -v` is
//! refused with what it needs, instead of the allocator aborting the process half way.

use homospline_maps::OccupancyMap;
use homospline_maps::footprint::Lattice;
use thiserror::Error;

/// Address space a process planning on a grid of `cells` cells may need, at most, beyond
/// [`BASE_BYTES`]: bytes per cell. The slope of the address space a corner-to-corner plan
/// needs against the cells, on the hardest random maps, rounded up (measured:
/// docs/performance.md, "Measurements behind the defaults").
pub const BYTES_PER_CELL: u64 = 130;

/// Address space of the process before its grid: the program, its threads' stacks and
/// their allocator arenas: the intercept of the same measurement, rounded up (measured:
/// docs/performance.md, "Measurements behind the defaults").
pub const BASE_BYTES: u64 = 160 << 20;

/// The grid is larger than the process may hold.
#[derive(Debug, Error, PartialEq)]
#[error(
    "{what} needs up to about {needed_mb} MB of memory ({cells} grid cells at {BYTES_PER_CELL} \
     bytes each, plus {base_mb} MB for the program), and this process may use {limit_mb} MB \
     (its address-space limit, `ulimit -v`): raise the limit, or use a coarser grid (crop or \
     downsample the map, or lower --resolution)",
    needed_mb = needed / 1_000_000,
    base_mb = BASE_BYTES / 1_000_000,
    limit_mb = limit / 1_000_000
)]
pub struct OutOfMemory {
    /// What was to be built, for the message ("map X (2048 x 2048 cells)").
    pub what: String,
    /// Grid cells.
    pub cells: u64,
    /// Bytes it may need ([`needed`]).
    pub needed: u64,
    /// The soft address-space limit, bytes.
    pub limit: u64,
}

/// The address space a plan on `cells` grid cells may need, bytes.
///
/// # Examples
///
/// ```
/// use homospline_front::memory::{BASE_BYTES, OutOfMemory, needed};
///
/// assert_eq!(needed(0), BASE_BYTES);
/// assert_eq!(needed(1 << 20), BASE_BYTES + 130 * (1 << 20));
/// assert_eq!(needed(u64::MAX), u64::MAX);
/// // The message names what needs the memory, how much, and the limit.
/// let e = OutOfMemory {
///     what: "map m (2048 x 2048 cells)".into(),
///     cells: 2048 * 2048,
///     needed: needed(2048 * 2048),
///     limit: 409_600_000,
/// };
/// let text = e.to_string();
/// assert!(text.starts_with("map m (2048 x 2048 cells) needs up to about 713 MB"), "{text}");
/// assert!(text.contains("may use 409 MB"), "{text}");
/// ```
pub fn needed(cells: u64) -> u64 {
    BASE_BYTES.saturating_add(cells.saturating_mul(BYTES_PER_CELL))
}

/// The most grid cells whose [`needed`] memory the process's address-space limit allows;
/// `None` without a limit.
pub fn cells_within_limit() -> Option<u64> {
    address_space_limit().map(|l| l.saturating_sub(BASE_BYTES) / BYTES_PER_CELL)
}

/// The grid cells `map` is prepared on for a robot of `radius`: the lattice of
/// [`Lattice::of`] for a disc (half-cell, or the cell centres on maps too large for it),
/// the map's own cells for a point.
///
/// # Examples
///
/// ```
/// use homospline_front::memory::map_cells;
/// use homospline_geom::Point;
/// use homospline_maps::OccupancyMap;
///
/// let map = |width: usize, height: usize| OccupancyMap {
///     name: "m".into(),
///     width,
///     height,
///     cell: 1.0,
///     origin: Point::origin(),
///     occupied: vec![false; width * height],
///     y_down: false,
/// };
/// assert_eq!(map_cells(&map(10, 20), 0.0), 200);
/// // A disc: the half-cell lattice.
/// assert_eq!(map_cells(&map(10, 20), 0.5), 21 * 41);
/// // Too large for it: the cell centres.
/// assert_eq!(map_cells(&map(4096, 4096), 0.5), 4096 * 4096);
/// ```
pub fn map_cells(map: &OccupancyMap, radius: f64) -> u64 {
    if radius > 0.0 {
        let l = Lattice::of(map);
        (l.cols as u64).saturating_mul(l.rows as u64)
    } else {
        (map.width as u64).saturating_mul(map.height as u64)
    }
}

/// [`check`] for preparing `map` (named `name` in the message) for a robot of `radius`.
pub fn check_map(name: &str, map: &OccupancyMap, radius: f64) -> Result<(), OutOfMemory> {
    check(
        || format!("map {name} ({} x {} cells)", map.width, map.height),
        map_cells(map, radius),
    )
}

/// The grid cells of a scene's graph at `resolution` cells per unit: its bounds' extent and
/// a wall ring (as `homospline_voronoi::Grid::from_scene`), saturating.
pub fn scene_cells(scene: &homospline_geom::Scene, resolution: f64) -> u64 {
    let ext = homospline_voronoi::grid::scene_area(scene, resolution).extent();
    let across = |e: f64| ((e * resolution).ceil() + 2.0).clamp(0.0, u32::MAX as f64) as u64;
    across(ext.x).saturating_mul(across(ext.y))
}

/// Refuses a grid of `cells` cells whose [`needed`] memory exceeds the process's soft
/// address-space limit (`RLIMIT_AS`). No limit, or a platform without one, passes.
pub fn check(what: impl FnOnce() -> String, cells: u64) -> Result<(), OutOfMemory> {
    let need = needed(cells);
    match address_space_limit() {
        Some(limit) if need > limit => Err(OutOfMemory {
            what: what(),
            cells,
            needed: need,
            limit,
        }),
        _ => Ok(()),
    }
}

/// The soft limit on the process's address space, bytes; `None` when unlimited.
pub fn address_space_limit() -> Option<u64> {
    #[cfg(unix)]
    {
        match rlimit::getrlimit(rlimit::Resource::AS) {
            Ok((soft, _)) if soft != rlimit::INFINITY => Some(soft),
            _ => None,
        }
    }
    #[cfg(not(unix))]
    {
        None
    }
}
