//! `map-memory N`: prepares a random N x N map (20 % of its cells occupied, seeded; default
//! N = 4096) once, as `homospline plan MAP` does (`PreparedMap::new`: grid, brushfire,
//! complete Voronoi graph and its index, clearance model, rays), and prints the time, the
//! peak resident memory of the process (`VmHWM` of `/proc/self/status`, Linux) and both per
//! cell. `--stages` first times the stages one by one. `--plan` then plans corner to corner
//! on the prepared map (2 classes, the map defaults; as the `map_size` bench) and prints the
//! plan's stage times and the peak memory after it, then a short plan in the middle of the
//! map (64 cells along the diagonal: a local re-plan). Run by `cargo xtask map-memory`.

use std::time::Instant;

use homospline_maps::PreparedMap;

/// Peak and current resident memory of this process, bytes (`None` off Linux).
fn memory() -> Option<(u64, u64)> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| -> Option<u64> {
        let line = status.lines().find(|l| l.starts_with(name))?;
        let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
        Some(kb * 1024)
    };
    Some((field("VmHWM:")?, field("VmRSS:")?))
}

fn mb(b: u64) -> f64 {
    b as f64 / 1e6
}

fn main() -> std::process::ExitCode {
    let mut n = 4096usize;
    let mut stages = false;
    let mut plan = false;
    for a in std::env::args().skip(1) {
        match a.as_str() {
            "--stages" => stages = true,
            "--plan" => plan = true,
            s => match s.parse() {
                Ok(v) if v >= 2 => n = v,
                _ => {
                    eprintln!("usage: map-memory [N] [--stages] [--plan]");
                    return std::process::ExitCode::from(2);
                }
            },
        }
    }
    let map = homospline_testkit::random_map(n);
    let cells = (n * n) as f64;
    let before = memory().map_or(0, |m| m.1);
    if stages {
        let t = Instant::now();
        let grid = map.to_grid().expect("a grid");
        let field = homospline_voronoi::DistanceField::build(&grid);
        let t_field = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let keep = homospline_voronoi::skeleton::skeleton_cells(&grid, &field);
        let t_skel = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let traced = homospline_voronoi::skeleton::trace(&grid, &field, &keep);
        let t_trace = t.elapsed().as_secs_f64();
        drop((keep, traced));
        let t = Instant::now();
        let g = homospline_voronoi::complete_graph(&grid, &field);
        let t_graph = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let mg = homospline_voronoi::MapGraph::from_graph(&grid, g);
        let t_index = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let model = homospline_maps::GridModel::new(&grid, &field);
        let t_model = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let rays = homospline_maps::rays_of(&mg);
        let t_rays = t.elapsed().as_secs_f64();
        drop((model, rays, mg));
        println!(
            "stages: grid+field {t_field:.2} s, skeleton {t_skel:.2} s, trace {t_trace:.2} s, \
             complete graph (skeleton+trace+prune) {t_graph:.2} s, index {t_index:.2} s, \
             model {t_model:.2} s, rays {t_rays:.2} s"
        );
    }
    let t = Instant::now();
    let prepared = match PreparedMap::new(&map) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("{}: {e}", map.name);
            return std::process::ExitCode::FAILURE;
        }
    };
    let secs = t.elapsed().as_secs_f64();
    let g = &prepared.graph.graph;
    println!(
        "{}: {} x {} cells, graph {} nodes {} edges; prepared in {:.2} s ({:.0} ns per cell)",
        map.name,
        n,
        n,
        g.nodes.len(),
        g.edges.len(),
        secs,
        secs * 1e9 / cells
    );
    match memory() {
        Some((peak, now)) => println!(
            "peak RSS {:.0} MB ({:.1} bytes per cell; the map itself {:.0} MB of it); \
             resident after {:.0} MB ({:.1} bytes per cell held by the prepared map){}",
            mb(peak),
            peak as f64 / cells,
            mb(before),
            mb(now),
            now.saturating_sub(before) as f64 / cells,
            if stages {
                " [--stages: the peak may be the stages']"
            } else {
                ""
            }
        ),
        None => println!("peak RSS: not available (no /proc/self/status)"),
    }
    if plan {
        let (s, t) = (
            homospline_testkit::free_diagonal_centre(&map, 10, 1),
            homospline_testkit::free_diagonal_centre(&map, n - 96, -1),
        );
        let mut cfg = homospline_optim::PlanConfig::maps();
        cfg.classes = 2;
        let clock = Instant::now();
        let result = prepared.plan(s, t, &cfg);
        let wall = clock.elapsed().as_secs_f64() * 1e3;
        match result {
            Ok(p) => println!(
                "plan ({:.1}, {:.1}) -> ({:.1}, {:.1}), 2 classes: {wall:.0} ms (per-query graph \
                 {:.0}, class search {:.0}, optimisation {:.0}); {} classes, lengths {:?}, \
                 collision-free {:?}; peak RSS {}",
                s.x,
                s.y,
                t.x,
                t.y,
                p.timing.voronoi,
                p.timing.classes,
                p.timing.optimize,
                p.classes.len(),
                p.classes
                    .iter()
                    .map(|c| (c.length * 10.0).round() / 10.0)
                    .collect::<Vec<_>>(),
                p.classes
                    .iter()
                    .map(|c| c.collision_free)
                    .collect::<Vec<_>>(),
                memory().map_or("n/a".to_string(), |m| format!("{:.0} MB", mb(m.0))),
            ),
            Err(e) => {
                eprintln!("{}: plan: {e}", map.name);
                return std::process::ExitCode::FAILURE;
            }
        }
        // A short query in the middle of the map (a local re-plan): its work should follow
        // the route, not the map.
        let (s, t) = (
            homospline_testkit::free_diagonal_centre(&map, n / 2, 1),
            homospline_testkit::free_diagonal_centre(&map, n / 2 + 64, 1),
        );
        let clock = Instant::now();
        match prepared.plan(s, t, &cfg) {
            Ok(p) => println!(
                "short plan ({:.1}, {:.1}) -> ({:.1}, {:.1}): {:.1} ms (class search {:.1}, \
                 optimisation {:.1}); lengths {:?}",
                s.x,
                s.y,
                t.x,
                t.y,
                clock.elapsed().as_secs_f64() * 1e3,
                p.timing.classes,
                p.timing.optimize,
                p.classes
                    .iter()
                    .map(|c| (c.length * 10.0).round() / 10.0)
                    .collect::<Vec<_>>(),
            ),
            Err(e) => {
                eprintln!("{}: short plan: {e}", map.name);
                return std::process::ExitCode::FAILURE;
            }
        }
    }
    std::process::ExitCode::SUCCESS
}
