//! Test support shared by the crates' tests, the benches and `xtask`: the fixture scenes, the
//! seeded generator of random scenes and the generator of mission worlds.
//!
//! Tests, benches and tooling only (it reads files and panics on a broken fixture); no
//! library crate depends on it.

use std::path::PathBuf;

use homospline_geom::{Bounds, Circle, Obstacle, Point, Real, Scene};
use homospline_maps::OccupancyMap;
use homospline_mission::{MissionConfig, MissionWorld, Team, Uav, Ugv, WorldFile};
use homospline_optim::{Plan, plan};
use homospline_spline::{CircleModel, ClearanceModel};

/// `fixtures/scenes` of the workspace.
pub fn scenes_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/scenes")
}

/// The paper-like fixture scenes, in file-name order.
pub fn fixture_scenes() -> Vec<Scene> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(scenes_dir())
        .expect("fixtures/scenes is readable")
        .map(|e| e.expect("a directory entry").path())
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let bytes = std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            Scene::from_bytes(&bytes, &p.display().to_string()).unwrap_or_else(|e| panic!("{e}"))
        })
        .collect()
}

/// SplitMix64, a small seeded generator: the seeded scenes of the benches and of
/// `cargo xtask gen-scenes` are the same on every run and machine.
pub struct SplitMix(pub u64);

impl SplitMix {
    /// Uniform in `[0, 1)`.
    pub fn next_unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random `n x n` occupancy grid, row-major (`true` = occupied): every cell occupied with
/// probability `density`, seeded (like MovingAI's random512-20-0 at `density = 0.2`: the
/// map with the most cycles of its size). The maps of the preparation bench and of
/// `cargo xtask map-memory`.
pub fn random_occupancy(n: usize, density: f64, seed: u64) -> Vec<bool> {
    let mut rng = SplitMix(seed);
    (0..n * n).map(|_| rng.next_unit() < density).collect()
}

/// The `n x n` map of [`random_occupancy`] at 20 % (seed 43), unit cells, y down.
pub fn random_map(n: usize) -> OccupancyMap {
    OccupancyMap {
        name: format!("random{n}-20"),
        width: n,
        height: n,
        cell: 1.0,
        origin: Point::origin(),
        occupied: random_occupancy(n, 0.2, 43),
        y_down: true,
    }
}

/// The centre of the first cell on `map`'s diagonal from `(at, at)` (stepping by `step`)
/// whose 3 x 3 block is free: the corner-to-corner query of the large-map benches.
///
/// # Panics
/// When the walk leaves the map before finding one (a test helper).
pub fn free_diagonal_centre(map: &OccupancyMap, at: usize, step: isize) -> Point {
    let n = map.width;
    let free = |x: usize, y: usize| {
        (y - 1..=y + 1).all(|yy| (x - 1..=x + 1).all(|xx| !map.occupied[yy * n + xx]))
    };
    let mut k = at;
    while !free(k, k) {
        k = k
            .checked_add_signed(step)
            .filter(|&k| k >= 1 && k + 1 < n)
            .expect("a free block on the diagonal");
    }
    Point::new(k as f64 + 0.5, k as f64 + 0.5)
}

/// A scene in the square `[0, size]^2` with these obstacles, no robot radius and no danger
/// points, critical points or hazards.
pub fn square_scene(
    name: String,
    size: f64,
    start: Point,
    goal: Point,
    obstacles: Vec<Obstacle>,
) -> Scene {
    Scene {
        name,
        bounds: Bounds {
            min: Point::new(0.0, 0.0),
            max: Point::new(size, size),
        },
        start,
        goal,
        robot_radius: 0.0,
        obstacles,
        danger_points: vec![],
        critical_points: vec![],
        hazards: vec![],
    }
}

/// A seeded random scene in `[0, size]^2`: `n` circles in clusters of up to `group`, start
/// and goal at mid-height near the left and right sides and kept clear (`cargo xtask
/// gen-scenes` and the mission worlds).
pub fn random_scene(name: &str, seed: u64, size: f64, n: usize, group: usize) -> Scene {
    let mut rng = SplitMix(seed);
    let start = Point::new((size * 0.04 * 1000.0).round() / 1000.0, size * 0.5);
    let goal = Point::new((size * 0.96 * 1000.0).round() / 1000.0, size * 0.5);
    let keep = size * 0.03;
    let mut obstacles = Vec::new();
    let mut placed = 0;
    while placed < n {
        let k = (1 + (rng.next_unit() * group as f64) as usize).min(n - placed);
        let c = Point::new(
            size * (0.1 + 0.8 * rng.next_unit()),
            size * (0.05 + 0.9 * rng.next_unit()),
        );
        let r = size * (0.01 + 0.03 * rng.next_unit());
        let circles: Vec<Circle> = (0..k)
            .map(|_| {
                let a = rng.next_unit() * std::f64::consts::TAU;
                let d = r * 1.2 * rng.next_unit();
                let rr = (r * (0.5 + 0.5 * rng.next_unit()) * 1000.0).round() / 1000.0;
                Circle::new(
                    ((c.x + a.cos() * d) * 1000.0).round() / 1000.0,
                    ((c.y + a.sin() * d) * 1000.0).round() / 1000.0,
                    rr,
                )
            })
            .collect();
        if circles
            .iter()
            .any(|ci| ci.signed_distance(&start) < keep || ci.signed_distance(&goal) < keep)
        {
            continue;
        }
        placed += k;
        obstacles.push(Obstacle {
            name: format!("o{}", obstacles.len()),
            circles,
        });
    }
    square_scene(name.to_owned(), size, start, goal, obstacles)
}

/// The seeded random scenes of `fixtures/random`, as `cargo xtask gen-scenes` writes them:
/// 10 small scenes (60 x 60, 4 to 12 circles) and 5 with hundreds of circles (240 x 240).
pub fn random_fixture_scenes() -> Vec<Scene> {
    let small = (0..10u64).map(|i| {
        let n = 4 + (i as usize * 3) % 9;
        random_scene(&format!("random-small-{i:02}"), 1000 + i, 60.0, n, 3)
    });
    let large = (0..5u64).map(|i| {
        let n = 200 + 50 * i as usize;
        random_scene(&format!("random-large-{i:02}"), 2000 + i, 240.0, n, 6)
    });
    small.chain(large).collect()
}

/// The scenes of the ignored scan tests: the fixture scenes, the seeded random fixtures and
/// `SCAN_SCENES` generated worlds ([`world_scene`] 0, 1, ...; `default` when unset).
pub fn scan_scenes(default: u64) -> Vec<Scene> {
    let n: u64 = std::env::var("SCAN_SCENES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default);
    let mut all = fixture_scenes();
    all.extend(random_fixture_scenes());
    all.extend((0..n).map(world_scene));
    all
}

/// The default team of the generated worlds: a UGV at 1 unit/s seeing 6 units, and `uavs`
/// scouts taking off at the start, 3 units/s, seeing 8 units.
pub fn team(scene: &Scene, uavs: usize) -> Team {
    Team {
        ugv: Ugv {
            speed: 1.0,
            sensor_range: 6.0,
            radius: 0.0,
        },
        uavs: (0..uavs)
            .map(|_| Uav {
                start: scene.start,
                speed: 3.0,
                sensor_range: 8.0,
            })
            .collect(),
    }
}

/// A hidden obstacle that blocks the narrowest passage of class `rank` (1 = best) of `plan`:
/// a disc on its class path (the Voronoi ridge) where the ridge is least clear, filling the
/// passage, away from the start and the goal. `None` if the class has no such point.
pub fn blockage(scene: &Scene, plan: &Plan, rank: usize, name: &str) -> Option<Obstacle> {
    let class = plan.classes.get(rank - 1)?;
    let model = CircleModel::new(scene.circles());
    let away = 10.0;
    let (at, clear) = class
        .seed_path
        .windows(2)
        .flat_map(|w| (0..8).map(move |k| w[0] + (w[1] - w[0]) * (k as f64 / 8.0)))
        .filter(|p| (p - scene.start).norm() > away && (p - scene.goal).norm() > away)
        .map(|p| (p, model.clearance(&p).0))
        .filter(|(_, d)| *d > 0.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let r = ((clear + 0.5) * 1000.0).round() / 1000.0;
    let round = |v: f64| (v * 1000.0).round() / 1000.0;
    Some(Obstacle {
        name: name.to_owned(),
        circles: vec![Circle::new(round(at.x), round(at.y), r)],
    })
}

/// A world on `scene` with a hidden obstacle in the best class's narrowest passage (and, with
/// `second`, one in the second class's too), `uavs` scouts; `None` when the classes or a
/// valid blockage are missing.
pub fn blocked_world(scene: &Scene, uavs: usize, second: bool) -> Option<MissionWorld> {
    let cfg = MissionConfig::default();
    let p = plan(scene, &cfg.plan).ok()?;
    let mut hidden = vec![blockage(scene, &p, p.best?, "blockage")?];
    if second && p.classes.len() > 1 {
        hidden.extend(blockage(scene, &p, p.best? + 1, "blockage-2"));
    }
    MissionWorld::new(
        &format!("{}-blocked", scene.name),
        scene.clone(),
        hidden,
        Vec::new(),
        team(scene, uavs),
    )
    .ok()
}

/// The seeded generator of mission worlds for benchmarks: a random 60 x 60 scene of 5 to 12
/// circles with its best class blocked, and in every other world the second best too;
/// `None` for a seed whose scene does not give such a world (too few classes).
pub fn random_world(seed: u64, uavs: usize) -> Option<MissionWorld> {
    blocked_world(&world_scene(seed), uavs, seed % 2 == 1)
}

/// The prior scene of [`random_world`] `seed`: a random 60 x 60 scene of 5 to 12 circles.
pub fn world_scene(seed: u64) -> Scene {
    let mut rng = SplitMix(seed ^ 0x5EED);
    let n = 5 + (rng.next_unit() * 8.0) as usize;
    random_scene(&format!("world-{seed:03}"), 7000 + seed, 60.0, n, 3)
}

/// The mission worlds of `fixtures/worlds`, in file-name order, each joined with its scene.
pub fn fixture_worlds() -> Vec<MissionWorld> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/worlds");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("fixtures/worlds is readable")
        .map(|e| e.expect("a directory entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|p| {
            let text =
                std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            let file = WorldFile::from_str(&text, &p.display().to_string())
                .unwrap_or_else(|e| panic!("{e}"));
            let scene_path = p.parent().expect("a directory").join(&file.scene);
            let bytes = std::fs::read(&scene_path)
                .unwrap_or_else(|e| panic!("{}: {e}", scene_path.display()));
            let scene = Scene::from_bytes(&bytes, &scene_path.display().to_string())
                .unwrap_or_else(|e| panic!("{e}"));
            MissionWorld::from_file(file, scene).unwrap_or_else(|e| panic!("{e}"))
        })
        .collect()
}

/// Distance from segment `ab` to the closed square `[x0, x0 + s] x [y0, y0 + s]` (0 when
/// they meet).
pub fn segment_square(a: Point, b: Point, x0: Real, y0: Real, s: Real) -> Real {
    let inside = |p: Point| p.x >= x0 && p.x <= x0 + s && p.y >= y0 && p.y <= y0 + s;
    let corners = [
        Point::new(x0, y0),
        Point::new(x0 + s, y0),
        Point::new(x0 + s, y0 + s),
        Point::new(x0, y0 + s),
    ];
    if inside(a) || inside(b) {
        return 0.0;
    }
    // The segment crosses a side: parameters of the crossings with each side's line.
    let cross = |p: Point, q: Point, c: Point, d: Point| {
        let r = q - p;
        let e = d - c;
        let den = r.x * e.y - r.y * e.x;
        if den == 0.0 {
            return false;
        }
        let t = ((c - p).x * e.y - (c - p).y * e.x) / den;
        let u = ((c - p).x * r.y - (c - p).y * r.x) / den;
        (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u)
    };
    for k in 0..4 {
        if cross(a, b, corners[k], corners[(k + 1) % 4]) {
            return 0.0;
        }
    }
    let point_square = |p: Point| {
        let dx = (x0 - p.x).max(p.x - x0 - s).max(0.0);
        let dy = (y0 - p.y).max(p.y - y0 - s).max(0.0);
        dx.hypot(dy)
    };
    let point_segment = |c: Point| {
        let d = b - a;
        let t = if d.norm_squared() > 0.0 {
            ((c - a).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (a + d * t - c).norm()
    };
    corners
        .iter()
        .map(|&c| point_segment(c))
        .chain([point_square(a), point_square(b)])
        .fold(Real::INFINITY, Real::min)
}

/// The least distance from the polyline `track` to an occupied cell of `map` or to its
/// edge, exact (every cell within `reach` of each segment's box measured).
pub fn track_clearance(map: &OccupancyMap, track: &[Point], reach: Real) -> Real {
    let b = map.bounds();
    let mut best = Real::INFINITY;
    for p in track {
        best = best.min(
            (p.x - b.min.x)
                .min(b.max.x - p.x)
                .min(p.y - b.min.y)
                .min(b.max.y - p.y),
        );
    }
    for w in track.windows(2) {
        let cell = |v: Real, o: Real, n: usize| {
            (((v - o) / map.cell).floor().max(0.0) as usize).min(n - 1)
        };
        let r = reach + map.cell;
        let (i0, i1) = (
            cell(w[0].x.min(w[1].x) - r, map.origin.x, map.width),
            cell(w[0].x.max(w[1].x) + r, map.origin.x, map.width),
        );
        let (j0, j1) = (
            cell(w[0].y.min(w[1].y) - r, map.origin.y, map.height),
            cell(w[0].y.max(w[1].y) + r, map.origin.y, map.height),
        );
        for j in j0..=j1 {
            for i in i0..=i1 {
                if map.occupied[j * map.width + i] {
                    best = best.min(segment_square(
                        w[0],
                        w[1],
                        map.origin.x + i as Real * map.cell,
                        map.origin.y + j as Real * map.cell,
                        map.cell,
                    ));
                }
            }
        }
    }
    best
}

/// The seeded scene worlds of `cargo xtask missions`, four kinds in turn (`seed % 4`): the
/// best class's narrowest passage blocked; the two best classes' blocked; the best class
/// blocked late, at its narrowest point past half way (a dead end found late); and pebbles,
/// small hidden discs beside the three best classes' paths and their narrowest passages that
/// block none of them (a trap for a policy that switches on first sight). `None` for a seed
/// whose scene does not give such a world.
pub fn suite_world(seed: u64, uavs: usize) -> Option<MissionWorld> {
    let scene = world_scene(seed);
    match seed % 4 {
        0 | 1 => blocked_world(&scene, uavs, seed % 4 == 1),
        2 => late_world(&scene, uavs),
        _ => pebble_world(&scene, uavs, seed),
    }
}

/// A world on `scene` whose best class is blocked at its least clear point past half way.
fn late_world(scene: &Scene, uavs: usize) -> Option<MissionWorld> {
    let p = plan(scene, &MissionConfig::default().plan).ok()?;
    let class = p.classes.get(p.best? - 1)?;
    let model = CircleModel::new(scene.circles());
    let path = &class.seed_path;
    let half = path.len() / 2;
    let (at, clear) = path[half..]
        .iter()
        .filter(|q| (*q - scene.goal).norm() > 10.0)
        .map(|q| (*q, model.clearance(q).0))
        .filter(|(_, d)| *d > 0.0)
        .min_by(|a, b| a.1.total_cmp(&b.1))?;
    let round = |v: f64| (v * 1000.0).round() / 1000.0;
    MissionWorld::new(
        &format!("{}-late", scene.name),
        scene.clone(),
        vec![Obstacle {
            name: "dead-end".into(),
            circles: vec![Circle::new(round(at.x), round(at.y), round(clear + 0.5))],
        }],
        Vec::new(),
        team(scene, uavs),
    )
    .ok()
}

/// A world on `scene` with hidden pebbles that block nothing: beside the three best
/// classes' paths, toward the nearer obstacle, leaving most of the gap open.
fn pebble_world(scene: &Scene, uavs: usize, seed: u64) -> Option<MissionWorld> {
    let p = plan(scene, &MissionConfig::default().plan).ok()?;
    let model = CircleModel::new(scene.circles());
    let mut rng = SplitMix(seed ^ 0x9EBB1E);
    let round = |v: f64| (v * 1000.0).round() / 1000.0;
    let mut hidden = Vec::new();
    for class in p.classes.iter().filter(|c| c.collision_free).take(3) {
        let path = &class.path;
        if path.len() < 8 {
            continue;
        }
        for _ in 0..2 {
            let k = 2 + (rng.next_unit() * (path.len() - 4) as f64) as usize;
            let q = path[k];
            if (q - scene.start).norm() < 8.0 || (q - scene.goal).norm() < 8.0 {
                continue;
            }
            let (d, _) = model.clearance(&q);
            if d < 2.0 {
                continue;
            }
            // Toward the nearer side: the normal whose step loses clearance.
            let t = path[k + 1] - path[k - 1];
            let n = homospline_geom::Vector::new(-t.y, t.x) / t.norm().max(1e-12);
            let side = if model.clearance(&(q + n * 0.5)).0 < model.clearance(&(q - n * 0.5)).0 {
                n
            } else {
                -n
            };
            let r = (0.15 * d).min(0.8);
            let c = q + side * (0.65 * d);
            hidden.push(Obstacle {
                name: format!("pebble-{}", hidden.len() + 1),
                circles: vec![Circle::new(round(c.x), round(c.y), round(r))],
            });
        }
    }
    if hidden.is_empty() {
        return None;
    }
    MissionWorld::new(
        &format!("{}-pebbles", scene.name),
        scene.clone(),
        hidden,
        Vec::new(),
        team(scene, uavs),
    )
    .ok()
}

/// The fixture maps map worlds are made from: rooms with one-cell doors, a maze of dead
/// ends, a random field.
const WORLD_MAPS: [&str; 4] = [
    "room-32-32-4.map",
    "16room_000.map",
    "maze-32-32-2.map",
    "random-32-32-10.map",
];

/// The first `count` seeded map worlds of `cargo xtask missions`: on the fixture maps in
/// turn, a start and a goal far apart, and in the truth map one of three kinds in turn: the
/// chosen path's narrowest point (a door) blocked; its narrowest point past half way blocked
/// (a dead end found late); or single-cell pebbles beside the path in open space that block
/// nothing. The UGV is a point, and in every other world a disc of radius 0.3 (planned in
/// its exact free space). Only worlds whose truth map still joins start and goal are kept.
pub fn map_worlds(count: usize) -> Vec<homospline_mission::MapWorld> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/maps/movingai");
    let maps: Vec<OccupancyMap> = WORLD_MAPS
        .iter()
        .map(|f| {
            let p = dir.join(f);
            let text =
                std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            homospline_maps::movingai::read_map(&text, f).unwrap_or_else(|e| panic!("{e}"))
        })
        .collect();
    let mut out = Vec::new();
    let mut seed = 0u64;
    while out.len() < count && seed < 20 * count as u64 + 20 {
        if let Some(w) = map_world(&maps[seed as usize % maps.len()], seed) {
            out.push(w);
        }
        seed += 1;
    }
    out
}

/// Map world `seed` on `prior` (see [`map_worlds`]).
fn map_world(prior: &OccupancyMap, seed: u64) -> Option<homospline_mission::MapWorld> {
    let mut rng = SplitMix(seed ^ 0xA11CE);
    let free: Vec<(usize, usize)> = (0..prior.height)
        .flat_map(|j| (0..prior.width).map(move |i| (i, j)))
        .filter(|&(i, j)| !prior.occupied[j * prior.width + i])
        .collect();
    let centre = |(i, j): (usize, usize)| {
        Point::new(
            prior.origin.x + (i as Real + 0.5) * prior.cell,
            prior.origin.y + (j as Real + 0.5) * prior.cell,
        )
    };
    let diag = (prior.width as Real).hypot(prior.height as Real) * prior.cell;
    let pick = |rng: &mut SplitMix| centre(free[(rng.next_unit() * free.len() as f64) as usize]);
    let (start, goal) = (0..50)
        .map(|_| (pick(&mut rng), pick(&mut rng)))
        .find(|(s, g)| (s - g).norm() > 0.6 * diag)?;
    let cfg = homospline_optim::PlanConfig::maps();
    let radius = if seed % 2 == 1 { 0.3 } else { 0.0 };
    let prepared = homospline_maps::PreparedMap::for_robot(prior, radius).ok()?;
    let plan = prepared.plan(start, goal, &cfg).ok()?;
    let path = &plan.chosen()?.path;
    let clear = |q: &Point| prior.clearance_within(q, 8.0 * prior.cell);
    let away =
        |q: &Point| (q - start).norm() > 3.0 * prior.cell && (q - goal).norm() > 3.0 * prior.cell;
    let mut truth = prior.clone();
    let kind = (seed / WORLD_MAPS.len() as u64) % 3;
    let block = |truth: &mut OccupancyMap, at: Point, r: Real| {
        for j in 0..truth.height {
            for i in 0..truth.width {
                if truth.distance_to_cell(&at, (i, j)) < r {
                    truth.occupied[j * truth.width + i] = true;
                }
            }
        }
    };
    let name = match kind {
        0 | 1 => {
            let from = if kind == 0 { 0 } else { path.len() / 2 };
            let (at, c) = path[from..]
                .iter()
                .filter(|q| away(q))
                .map(|q| (*q, clear(q)))
                .min_by(|a, b| a.1.total_cmp(&b.1))?;
            block(&mut truth, at, c + 0.75 * prior.cell);
            if kind == 0 { "door" } else { "late" }
        }
        _ => {
            let mut placed = 0;
            for _ in 0..12 {
                let k = 1 + (rng.next_unit() * (path.len() - 2) as f64) as usize;
                let q = path[k];
                if !away(&q) || clear(&q) < 2.5 * prior.cell {
                    continue;
                }
                let t = path[(k + 1).min(path.len() - 1)] - path[k - 1];
                let n = homospline_geom::Vector::new(-t.y, t.x) / t.norm().max(1e-12);
                let side = if rng.next_unit() < 0.5 { n } else { -n };
                let c = q + side * (1.5 * prior.cell);
                let (fx, fy) = (
                    (c.x - prior.origin.x) / prior.cell,
                    (c.y - prior.origin.y) / prior.cell,
                );
                if fx < 0.0 || fy < 0.0 || fx as usize >= prior.width || fy as usize >= prior.height
                {
                    continue;
                }
                truth.occupied[fy as usize * prior.width + fx as usize] = true;
                placed += 1;
                if placed == 3 {
                    break;
                }
            }
            if placed == 0 {
                return None;
            }
            "pebbles"
        }
    };
    if truth.occupied == prior.occupied {
        return None;
    }
    // Keep worlds whose truth still has a route.
    homospline_maps::PreparedMap::for_robot(&truth, radius)
        .ok()?
        .plan(start, goal, &cfg)
        .ok()?
        .chosen()?;
    let uav = Uav {
        start,
        speed: 3.0,
        sensor_range: 5.0,
    };
    homospline_mission::MapWorld::new(
        &format!("{}-{seed}-{name}", prior.name),
        prior.clone(),
        truth,
        start,
        goal,
        Team {
            ugv: Ugv {
                speed: 1.0,
                sensor_range: 4.0,
                // Every other world a disc that one-cell doors still let through.
                radius,
            },
            uavs: vec![uav.clone(), uav],
        },
    )
    .ok()
}

/// A 16 x 10 map split by a wall with a diagonal door: column 7 from row 0 to row 3, column
/// 9 from row 5 to row 9 (cell `(i, j)` is the square `[i, i + 1] x [j, j + 1]`), so the only
/// way across is the gap between the corners (8, 4) and (9, 5), `sqrt 2` wide: a disc of
/// radius up to 0.7071 passes, turning in it. `extra`: one more occupied cell.
pub fn diagonal_door_map(extra: Option<(usize, usize)>) -> OccupancyMap {
    grid_map("diagonal-door", (16, 10), true, |i, j| {
        (i == 7 && j <= 3) || (i == 9 && j >= 5) || Some((i, j)) == extra
    })
}

/// A map of `w x h` cells of side 1 from the origin, cell `(i, j)` occupied where
/// `occupied(i, j)`; `y_down` as MovingAI (rows down) or ROS (rows up).
pub fn grid_map(
    name: &str,
    (w, h): (usize, usize),
    y_down: bool,
    occupied: impl Fn(usize, usize) -> bool,
) -> OccupancyMap {
    OccupancyMap {
        name: name.into(),
        width: w,
        height: h,
        cell: 1.0,
        origin: Point::origin(),
        occupied: (0..w * h).map(|k| occupied(k % w, k / w)).collect(),
        y_down,
    }
}
