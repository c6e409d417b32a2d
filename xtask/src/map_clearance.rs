//! `cargo xtask map-clearance`: how far the chosen map paths keep from walls, and how often a
//! robot of a given radius gets a plan, per MovingAI scenario file, sampled over every bucket.
//!
//! For each `.scen` file (its map beside it), or ROS map YAML (`--sample` seeded pairs of
//! free cell centres that keep the radius, the straight line as the optimum): `--sample N` scenarios spread evenly over the
//! file (default 40), planned at the map defaults ([`homospline_optim::PlanConfig::maps`]) on the map
//! prepared for `--robot-radius R` (default 0). Printed per file:
//! - `keep`: scenarios whose start and goal keep `R` from every occupied cell (the others are
//!   refused, as the planner refuses them); `apart`: of those, how many have no free route at
//!   that radius (start and goal in different free components of the inflated map);
//! - `planned`: collision-free plans among the scenarios that keep `R` and have a route, and
//!   the least such share over the tenths of the file (sorted by length: the worst bucket
//!   range);
//! - the medians over planned scenarios of length / octile optimum, of the certified
//!   clearance of the whole path, and of the certified clearance away from the first and
//!   last `dm` of the path (segment by segment, the model's rigorous bound on pieces of at
//!   most a twentieth of a cell, so within a fortieth of a cell of the least; with `R > 0`
//!   clearances are the robot body's, so a point's distance to the nearest occupied cell is
//!   at least `R` more).
//!
//! - `detour`: the worst, over planned scenarios, of the chosen class's length over the
//!   shortest collision-free class of the same plan keeping 0.9 of its least clearance
//!   (`--no-detour` plans without `PlanConfig::detour`, for the before and after);
//!   `joined`: scenarios whose start and goal an independent witness joins for the disc
//!   ([`witness_components`]); a joined scenario answered 'no route' fails the command.
//!
//! `--least-only` plans with the safety term of the least clearance only (`homospline_spline::CostConfig`'s
//! `safety_along`), the map defaults before it: the before-and-after of docs/method.md.

use anyhow::{Context, Result, bail};
use homospline_geom::{Point, Real};
use homospline_maps::{MapError, PreparedMap, movingai, sweep::sample_indices};
use homospline_spline::ClearanceModel;

/// Options of the command.
pub struct Options {
    pub files: Vec<std::path::PathBuf>,
    pub sample: usize,
    pub radius: Real,
    pub along: bool,
    pub weights: Vec<(String, Real)>,
    pub min_units: Option<usize>,
    pub detour: bool,
}

/// Parses `[--sample N] [--robot-radius R] [--least-only] [--weight NAME=VALUE] SCEN...`.
pub fn parse(args: &[String]) -> Result<Options> {
    let mut o = Options {
        files: Vec::new(),
        sample: 40,
        radius: 0.0,
        along: true,
        weights: Vec::new(),
        min_units: None,
        detour: true,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--sample" => {
                o.sample = it
                    .next()
                    .and_then(|n| n.parse().ok())
                    .filter(|&n: &usize| n > 0)
                    .context("--sample needs a positive number")?
            }
            "--robot-radius" => {
                o.radius = it
                    .next()
                    .and_then(|n| n.parse().ok())
                    .filter(|r: &Real| r.is_finite() && *r >= 0.0)
                    .context("--robot-radius needs a finite number >= 0")?
            }
            "--least-only" => o.along = false,
            "--no-detour" => o.detour = false,
            "--min-units" => {
                o.min_units = it.next().and_then(|n| n.parse().ok());
            }
            "--weight" => {
                let w = it.next().context("--weight needs NAME=VALUE")?;
                let (n, v) = w.split_once('=').context("--weight needs NAME=VALUE")?;
                o.weights
                    .push((n.to_owned(), v.parse().context("--weight: not a number")?));
            }
            flag if flag.starts_with('-') => bail!("unknown option {flag}"),
            f => o.files.push(f.into()),
        }
    }
    if o.files.is_empty() {
        bail!("no .scen file given");
    }
    Ok(o)
}

/// The certified clearance of the polyline `path` away from its first and last `skip` of
/// arc length, within `piece / 2` of the exact least (`None` when nothing is left).
pub fn inner_clearance(
    path: &[Point],
    model: &dyn ClearanceModel,
    skip: Real,
    piece: Real,
) -> Option<Real> {
    let total: Real = path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let (lo, hi) = (skip, total - skip);
    if hi <= lo {
        return None;
    }
    let mut s = 0.0;
    let mut best = Real::INFINITY;
    for w in path.windows(2) {
        let len = (w[1] - w[0]).norm();
        let (sa, sb) = (s, s + len);
        s = sb;
        if sb <= lo || sa >= hi || len == 0.0 {
            continue;
        }
        let at = |x: Real| w[0] + (w[1] - w[0]) * ((x - sa) / len);
        let (a, b) = (at(sa.max(lo)), at(sb.min(hi)));
        // The segment bound `(d(a) + d(b) - |ab|) / 2` on pieces of at most `piece`: within
        // `piece / 2` of the true least clearance of the segment.
        let n = (((b - a).norm() / piece).ceil() as usize).max(1);
        let mut da = model.exact_clearance(&a);
        for k in 1..=n {
            let q = a + (b - a) * (k as Real / n as Real);
            let dq = model.exact_clearance(&q);
            best = best.min(0.5 * (da + dq - (b - a).norm() / n as Real));
            da = dq;
        }
    }
    best.is_finite().then_some(best)
}

fn median(mut v: Vec<Real>) -> Real {
    if v.is_empty() {
        return Real::NAN;
    }
    v.sort_by(Real::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// A start, a goal and the optimum length between them.
type Case = (Point, Point, Real);

/// The map of `f` and its cases `(start, goal, optimum)` in order of length: a `.scen`
/// file's scenarios sampled over every bucket (the octile optimum), or for a ROS map YAML,
/// `sample` seeded pairs of free cell centres that keep the radius (the straight-line
/// distance as the optimum).
fn cases_of(
    f: &std::path::Path,
    o: &Options,
) -> Result<(homospline_maps::OccupancyMap, Vec<Case>)> {
    let name = f.display().to_string();
    if f.extension().is_some_and(|e| e == "yaml" || e == "yml") {
        let homospline_maps::input::Input::Map(map) =
            homospline_maps::input::load(f, |p| std::fs::read(p)).map_err(anyhow::Error::msg)?
        else {
            bail!("{name}: not a map");
        };
        let mut rng = homospline_testkit::SplitMix(7);
        let mut free_point = |map: &homospline_maps::OccupancyMap| {
            for _ in 0..100_000 {
                let i = (rng.next_unit() * map.width as f64) as usize;
                let j = (rng.next_unit() * map.height as f64) as usize;
                let p = Point::new(
                    map.origin.x + (i as Real + 0.5) * map.cell,
                    map.origin.y + (j as Real + 0.5) * map.cell,
                );
                if map.clearance_within(&p, o.radius + map.cell) >= o.radius.max(1e-9) {
                    return Some(p);
                }
            }
            None
        };
        let mut cases = Vec::new();
        for _ in 0..o.sample {
            let (Some(s), Some(g)) = (free_point(&map), free_point(&map)) else {
                bail!("{name}: no free cell keeps the radius");
            };
            cases.push((s, g, (g - s).norm()));
        }
        cases.sort_by(|a, b| a.2.total_cmp(&b.2));
        return Ok((map, cases));
    }
    let text = std::fs::read_to_string(f).with_context(|| format!("{name}: cannot read"))?;
    let scen = movingai::read_scen(&text, &name)?;
    let first = scen.first().context("no scenario")?;
    let map_path = f.with_file_name(
        std::path::Path::new(&first.map)
            .file_name()
            .context("no map name")?,
    );
    let map_text = std::fs::read_to_string(&map_path)
        .with_context(|| format!("{}: cannot read", map_path.display()))?;
    let map = movingai::read_map(&map_text, &map_path.display().to_string())?;
    let cases = sample_indices(scen.len(), o.sample)
        .into_iter()
        .map(|i| (scen[i].start, scen[i].goal, scen[i].optimal_length))
        .collect();
    Ok((map, cases))
}

/// A witness of the disc's free space independent of the planner's lattice: per cell
/// centre, its component among the centres that keep more than `radius` (exact clearance), 8-neighbours
/// joined where their segment keeps it (sampled every 1/64 cell, each sample asked for
/// `radius` plus the most the clearance can dip between two samples). Conservative: centres
/// it joins are joined for the disc. `None` for a centre that does not keep the radius.
pub fn witness_components(map: &homospline_maps::OccupancyMap, radius: Real) -> Vec<Option<usize>> {
    let (w, h) = (map.width, map.height);
    let centre = |i: usize, j: usize| {
        Point::new(
            map.origin.x + (i as Real + 0.5) * map.cell,
            map.origin.y + (j as Real + 0.5) * map.cell,
        )
    };
    let reach = radius + 2.0 * map.cell;
    let clear: Vec<Real> = (0..w * h)
        .map(|k| {
            if map.occupied[k] {
                0.0
            } else {
                map.clearance_within(&centre(k % w, k / w), reach)
            }
        })
        .collect();
    let keeps: Vec<bool> = clear.iter().map(|&c| c > radius).collect();
    let segment_keeps = |ka: usize, kb: usize| {
        let (a, b) = (centre(ka % w, ka / w), centre(kb % w, kb / w));
        // A point of the segment is within half its length of an end: it keeps at least
        // (d(a) + d(b) - |ab|) / 2 (the clearance is 1-Lipschitz).
        if 0.5 * (clear[ka] + clear[kb] - (b - a).norm()) > radius {
            return true;
        }
        let n = 64 * ((b - a).norm() / map.cell).ceil().max(1.0) as usize;
        let slack = 0.5 * (b - a).norm() / n as Real;
        (0..=n).all(|k| {
            map.clearance_within(&(a + (b - a) * (k as Real / n as Real)), reach) > radius + slack
        })
    };
    let mut parent: Vec<usize> = (0..w * h).collect();
    fn root(p: &mut [usize], mut k: usize) -> usize {
        while p[k] != k {
            p[k] = p[p[k]];
            k = p[k];
        }
        k
    }
    for j in 0..h {
        for i in 0..w {
            let k = j * w + i;
            if !keeps[k] {
                continue;
            }
            for (di, dj) in [(1i64, 0i64), (0, 1), (1, 1), (-1, 1)] {
                let (ni, nj) = (i as i64 + di, j as i64 + dj);
                if ni < 0 || ni >= w as i64 || nj >= h as i64 {
                    continue;
                }
                let m = nj as usize * w + ni as usize;
                if keeps[m] && segment_keeps(k, m) {
                    let (a, b) = (root(&mut parent, k), root(&mut parent, m));
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
    }
    (0..w * h)
        .map(|k| keeps[k].then(|| root(&mut parent, k)))
        .collect()
}

/// How much longer the chosen class is than the shortest other collision-free class of the
/// plan that keeps at least 0.9 of its least clearance (1 when none is shorter).
pub fn detour_ratio(plan: &homospline_optim::Plan) -> Real {
    let Some(c) = plan.chosen() else { return 1.0 };
    plan.classes
        .iter()
        .filter(|o| o.collision_free && o.min_clearance >= 0.9 * c.min_clearance)
        .map(|o| c.length / o.length)
        .fold(1.0, Real::max)
}

/// Runs the command.
pub fn run(o: &Options) -> Result<()> {
    println!(
        "robot radius {}, {} scenarios per file over every bucket, safety along the path {}",
        o.radius,
        o.sample,
        if o.along { "on" } else { "off" }
    );
    println!(
        "{:<28} {:>6} {:>6} {:>5} {:>7} {:>9} {:>10} {:>9} {:>9} {:>9} {:>7}",
        "file",
        "picked",
        "keep",
        "apart",
        "joined",
        "planned",
        "worst 10th",
        "len/oct",
        "clear",
        "inner",
        "detour"
    );
    let mut refused_joined = 0;
    let mut cfg = homospline_optim::PlanConfig::maps();
    cfg.growth.cost.safety_along = o.along;
    if !o.detour {
        cfg.detour = None;
    }
    if let Some(u) = o.min_units {
        cfg.growth.min_evaluations_per_round = u;
    }
    for (n, v) in &o.weights {
        cfg.growth.cost.set(n, *v)?;
    }
    let skip = cfg.growth.cost.dm;
    for f in &o.files {
        let (map, cases) = cases_of(f, o)?;
        let prepared = PreparedMap::for_robot(&map, o.radius)?;
        let witness = witness_components(&map, o.radius);
        let component = |p: &Point| {
            let i = ((p.x - map.origin.x) / map.cell).floor();
            let j = ((p.y - map.origin.y) / map.cell).floor();
            (i >= 0.0 && j >= 0.0 && (i as usize) < map.width && (j as usize) < map.height)
                .then(|| witness[j as usize * map.width + i as usize])
                .flatten()
        };
        let picked = cases.len();
        let (mut keep, mut apart, mut joined) = (0, 0, 0);
        // Per tenth of the cases (sorted by length): (planned, attempted).
        let mut tenths = [(0usize, 0usize); 10];
        let (mut ratios, mut clears, mut inners) = (Vec::new(), Vec::new(), Vec::new());
        let mut detour: Real = 1.0;
        for (i, &(start, goal, optimal)) in cases.iter().enumerate() {
            let tenth = (10 * i / cases.len()).min(9);
            let witnessed =
                matches!((component(&start), component(&goal)), (Some(a), Some(b)) if a == b);
            joined += usize::from(witnessed);
            match prepared.plan(start, goal, &cfg) {
                Err(MapError::Endpoint { problem, .. }) if problem.contains("robot radius") => {}
                Err(e) if e.is_no_route() => {
                    keep += 1;
                    apart += 1;
                    if witnessed {
                        refused_joined += 1;
                        eprintln!("{} case {i}: joined for the disc, yet: {e}", f.display());
                    }
                }
                Err(e) => {
                    keep += 1;
                    tenths[tenth].1 += 1;
                    eprintln!("{} case {i}: {e}", f.display());
                }
                Ok(plan) => {
                    keep += 1;
                    tenths[tenth].1 += 1;
                    let Some(b) = plan.best else {
                        if witnessed {
                            eprintln!("{} case {i}: joined for the disc, no plan", f.display());
                        }
                        continue;
                    };
                    let c = &plan.classes[b - 1];
                    tenths[tenth].0 += 1;
                    detour = detour.max(detour_ratio(&plan));
                    ratios.push(c.length / optimal);
                    clears.push(c.min_clearance);
                    if let Some(m) =
                        inner_clearance(&c.path, &prepared.model, skip, 0.05 * map.cell)
                    {
                        inners.push(m);
                    }
                }
            }
        }
        let planned: usize = tenths.iter().map(|t| t.0).sum();
        let tried: usize = tenths.iter().map(|t| t.1).sum();
        let worst = tenths
            .iter()
            .filter(|t| t.1 > 0)
            .map(|t| t.0 as Real / t.1 as Real)
            .fold(Real::INFINITY, Real::min);
        println!(
            "{:<28} {:>6} {:>6} {:>5} {:>7} {:>9} {:>9.0}% {:>9.4} {:>9.4} {:>9.4} {:>7.3}",
            map.name,
            picked,
            keep,
            apart,
            joined,
            format!("{planned}/{tried}"),
            100.0 * worst,
            median(ratios),
            median(clears),
            median(inners),
            detour
        );
    }
    if refused_joined > 0 {
        bail!("{refused_joined} scenarios joined for the disc were answered 'no route'");
    }
    Ok(())
}
