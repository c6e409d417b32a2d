//! Mission worlds (feature `mission`): the fixture worlds, the seeded scene worlds of
//! `cargo xtask missions` and its map worlds.

use std::path::PathBuf;

use homospline_geom::{Circle, Obstacle, Point, Real, Scene};
use homospline_maps::OccupancyMap;
use homospline_mission::{MissionConfig, MissionWorld, Team, Uav, Ugv, WorldFile};
use homospline_optim::{Plan, plan};
use homospline_spline::{CircleModel, ClearanceModel};

use crate::{SplitMix, world_scene};

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
