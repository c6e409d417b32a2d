//! SVG pictures the way the paper's figures show a plan: the potential field as a heat map,
//! obstacles, the Voronoi graph, the class seeds, the optimised paths (the chosen one bold),
//! start and goal, a legend and a scale bar. Each layer is a `<g>` with its own `id`.

use homospline_geom::{Bounds, Point, Real, Scene};
use homospline_maps::OccupancyMap;
use homospline_optim::Plan;
use homospline_voronoi::VoronoiGraph;
use svg::Document;
use svg::node::element::path::Data;
use svg::node::element::{Circle, Group, Line, Path, Rectangle, Text};

/// Picture width in pixels.
const WIDTH: Real = 900.0;
/// Heat-map cells along the longer side.
const HEAT_CELLS: usize = 90;
/// Colours of the class paths, by rank.
const PALETTE: [&str; 8] = [
    "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf", "#7f7f7f",
];

/// What is drawn under the graph and the paths.
pub enum Background<'a> {
    /// A scene of circles, with the potential of `alpha` as a heat map.
    Scene(&'a Scene, Real),
    /// An occupancy map: its occupied cells.
    Map(&'a OccupancyMap),
}

impl Background<'_> {
    fn bounds(&self) -> Bounds {
        match self {
            Background::Scene(s, _) => s.bounds,
            Background::Map(m) => m.bounds(),
        }
    }

    fn y_down(&self) -> bool {
        matches!(self, Background::Map(m) if m.y_down)
    }

    fn layers(&self, v: &View, doc: Document) -> Document {
        match self {
            Background::Scene(scene, alpha) => {
                doc.add(heat_map(scene, v, *alpha)).add(obstacles(scene, v))
            }
            Background::Map(map) => doc.add(cells(map, v)),
        }
    }
}

struct View {
    min: Point,
    max: Point,
    scale: Real,
    y_down: bool,
}

impl View {
    fn new(bg: &Background<'_>) -> Self {
        let b = bg.bounds();
        let e = b.extent();
        Self {
            min: b.min,
            max: b.max,
            scale: WIDTH / e.x.max(e.y),
            y_down: bg.y_down(),
        }
    }
    fn x(&self, x: Real) -> Real {
        (x - self.min.x) * self.scale
    }
    fn y(&self, y: Real) -> Real {
        if self.y_down {
            (y - self.min.y) * self.scale
        } else {
            (self.max.y - y) * self.scale
        }
    }
    fn w(&self) -> Real {
        (self.max.x - self.min.x) * self.scale
    }
    fn h(&self) -> Real {
        (self.max.y - self.min.y) * self.scale
    }
    fn poly(&self, pts: &[Point]) -> Data {
        let mut d = Data::new();
        for (i, p) in pts.iter().enumerate() {
            let xy = (self.x(p.x), self.y(p.y));
            d = if i == 0 { d.move_to(xy) } else { d.line_to(xy) };
        }
        d
    }
}

fn heat_map(scene: &Scene, v: &View, alpha: Real) -> Group {
    let circles = scene.circles();
    let e = scene.bounds.extent();
    let cell = e.x.max(e.y) / HEAT_CELLS as Real;
    let (nx, ny) = ((e.x / cell).ceil() as usize, (e.y / cell).ceil() as usize);
    let mut g = Group::new().set("id", "heatmap");
    for j in 0..ny {
        for i in 0..nx {
            let p = Point::new(
                scene.bounds.min.x + (i as Real + 0.5) * cell,
                scene.bounds.min.y + (j as Real + 0.5) * cell,
            );
            let u: Real = circles
                .iter()
                .map(|c| 1.0 + (alpha * (c.radius - (p - c.center).norm())).tanh())
                .sum();
            let t = (u / 2.0).clamp(0.0, 1.0);
            if t < 0.01 {
                continue;
            }
            let (r, gg, b) = (255.0, 255.0 * (1.0 - 0.75 * t), 255.0 * (1.0 - t));
            g = g.add(
                Rectangle::new()
                    .set("x", v.x(p.x - cell / 2.0))
                    .set("y", v.y(p.y + cell / 2.0).min(v.y(p.y - cell / 2.0)))
                    .set("width", cell * v.scale + 0.5)
                    .set("height", cell * v.scale + 0.5)
                    .set("fill", format!("rgb({:.0},{:.0},{:.0})", r, gg, b)),
            );
        }
    }
    g
}

fn obstacles(scene: &Scene, v: &View) -> Group {
    let mut g = Group::new().set("id", "obstacles");
    for o in &scene.obstacles {
        for c in &o.circles {
            g = g.add(
                Circle::new()
                    .set("cx", v.x(c.center.x))
                    .set("cy", v.y(c.center.y))
                    .set("r", (c.radius + scene.robot_radius) * v.scale)
                    .set("fill", "#555")
                    .set("fill-opacity", 0.85),
            );
        }
    }
    g
}

fn voronoi(graph: &VoronoiGraph, v: &View) -> Group {
    let mut g = Group::new().set("id", "voronoi");
    for e in &graph.edges {
        let pts: Vec<Point> = e.polyline.iter().map(|p| Point::new(p[0], p[1])).collect();
        g = g.add(
            Path::new()
                .set("d", v.poly(&pts))
                .set("fill", "none")
                .set("stroke", "#999")
                .set("stroke-width", 1.2),
        );
    }
    for n in &graph.nodes {
        g = g.add(
            Circle::new()
                .set("cx", v.x(n.at[0]))
                .set("cy", v.y(n.at[1]))
                .set("r", 2.2)
                .set("fill", "#777"),
        );
    }
    g
}

/// Occupied cells, one rectangle per run along a row.
fn cells(map: &OccupancyMap, v: &View) -> Group {
    let mut g = Group::new().set("id", "obstacles");
    for j in 0..map.height {
        let mut i = 0;
        while i < map.width {
            if !map.occupied[j * map.width + i] {
                i += 1;
                continue;
            }
            let start = i;
            while i < map.width && map.occupied[j * map.width + i] {
                i += 1;
            }
            let (x0, y0) = (
                map.origin.x + start as Real * map.cell,
                map.origin.y + j as Real * map.cell,
            );
            let (y_a, y_b) = (v.y(y0), v.y(y0 + map.cell));
            g = g.add(
                Rectangle::new()
                    .set("x", v.x(x0))
                    .set("y", y_a.min(y_b))
                    .set("width", (i - start) as Real * map.cell * v.scale)
                    .set("height", (y_a - y_b).abs())
                    .set("fill", "#555"),
            );
        }
    }
    g
}

fn endpoints(start: Point, goal: Point, v: &View) -> Group {
    let mut g = Group::new().set("id", "endpoints");
    for (p, label, colour) in [(start, "S", "#2ca02c"), (goal, "T", "#d62728")] {
        g = g
            .add(
                Circle::new()
                    .set("cx", v.x(p.x))
                    .set("cy", v.y(p.y))
                    .set("r", 6)
                    .set("fill", colour)
                    .set("stroke", "black"),
            )
            .add(
                Text::new(label)
                    .set("x", v.x(p.x) + 8.0)
                    .set("y", v.y(p.y) - 8.0)
                    .set("font-size", 16)
                    .set("font-family", "sans-serif"),
            );
    }
    g
}

fn scale_bar(v: &View) -> Group {
    let target = (v.max.x - v.min.x) / 5.0;
    let mag = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .rfind(|l| *l <= target)
        .unwrap_or(mag);
    let (x0, y0) = (20.0, v.h() - 20.0);
    Group::new()
        .set("id", "scale-bar")
        .add(
            Line::new()
                .set("x1", x0)
                .set("y1", y0)
                .set("x2", x0 + len * v.scale)
                .set("y2", y0)
                .set("stroke", "black")
                .set("stroke-width", 3),
        )
        .add(
            Text::new(format!("{len} map units"))
                .set("x", x0)
                .set("y", y0 - 6.0)
                .set("font-size", 13)
                .set("font-family", "sans-serif"),
        )
}

fn legend(items: &[(&str, String, bool)], v: &View) -> Group {
    let mut g = Group::new().set("id", "legend");
    let (x0, y0) = (v.w() - 250.0, 16.0);
    g = g.add(
        Rectangle::new()
            .set("x", x0 - 8.0)
            .set("y", y0 - 12.0)
            .set("width", 250)
            .set("height", 20.0 * items.len() as Real + 10.0)
            .set("fill", "white")
            .set("fill-opacity", 0.85)
            .set("stroke", "#333"),
    );
    for (k, (colour, label, dashed)) in items.iter().enumerate() {
        let y = y0 + 20.0 * k as Real;
        let mut line = Line::new()
            .set("x1", x0)
            .set("y1", y)
            .set("x2", x0 + 28.0)
            .set("y2", y)
            .set("stroke", *colour)
            .set("stroke-width", 3);
        if *dashed {
            line = line.set("stroke-dasharray", "5,4");
        }
        g = g.add(line).add(
            Text::new(label.clone())
                .set("x", x0 + 36.0)
                .set("y", y + 4.0)
                .set("font-size", 13)
                .set("font-family", "sans-serif"),
        );
    }
    g
}

fn document(v: &View) -> Document {
    Document::new()
        .set("viewBox", (0, 0, v.w().ceil(), v.h().ceil()))
        .set("width", v.w().ceil())
        .set("height", v.h().ceil())
        .add(
            Rectangle::new()
                .set("width", "100%")
                .set("height", "100%")
                .set("fill", "white"),
        )
}

/// A plan: background (heat map and circles, or map cells), Voronoi graph, seeds, paths
/// (chosen bold), start and goal, legend, scale bar.
pub fn plan_svg(bg: &Background<'_>, plan: &Plan) -> String {
    let v = View::new(bg);
    let mut doc = bg.layers(&v, document(&v));
    if let Some(g) = &plan.graph {
        doc = doc.add(voronoi(g, &v));
    }
    let mut seeds = Group::new().set("id", "seeds");
    let mut paths = Group::new().set("id", "paths");
    let mut best = Group::new().set("id", "best");
    let mut items = vec![("#999", "Voronoi graph".to_owned(), false)];
    for c in &plan.classes {
        let colour = PALETTE[(c.rank - 1) % PALETTE.len()];
        seeds = seeds.add(
            Path::new()
                .set("d", v.poly(&c.seed_path))
                .set("fill", "none")
                .set("stroke", colour)
                .set("stroke-width", 1.5)
                .set("stroke-dasharray", "5,4"),
        );
        let chosen = plan.best == Some(c.rank);
        let p = Path::new()
            .set("d", v.poly(&c.path))
            .set("fill", "none")
            .set("stroke", colour)
            .set("stroke-width", if chosen { 5.0 } else { 2.0 });
        if chosen {
            best = best.add(p);
        } else {
            paths = paths.add(p);
        }
        items.push((
            colour,
            format!(
                "#{} {}{}{}",
                c.rank,
                c.signature,
                if chosen { " (chosen)" } else { "" },
                if c.collision_free { "" } else { " COLLIDES" }
            ),
            false,
        ));
    }
    items.push(("#555", "class seeds: dashed".to_owned(), true));
    let (start, goal) = (plan.start, plan.goal);
    doc.add(seeds)
        .add(paths)
        .add(best)
        .add(endpoints(start, goal, &v))
        .add(legend(&items, &v))
        .add(scale_bar(&v))
        .to_string()
}

/// A Voronoi graph: background, graph, start and goal, legend, scale bar.
pub fn graph_svg(bg: &Background<'_>, graph: &VoronoiGraph) -> String {
    let v = View::new(bg);
    let items = vec![(
        "#999",
        format!(
            "Voronoi graph: {} nodes, {} edges",
            graph.nodes.len(),
            graph.edges.len()
        ),
        false,
    )];
    let at = |n: Option<usize>| {
        n.and_then(|i| graph.nodes.get(i))
            .map(|n| Point::new(n.at[0], n.at[1]))
    };
    let mut doc = bg.layers(&v, document(&v)).add(voronoi(graph, &v));
    if let (Some(s), Some(t)) = (at(graph.start), at(graph.goal)) {
        doc = doc.add(endpoints(s, t, &v));
    }
    doc.add(legend(&items, &v)).add(scale_bar(&v)).to_string()
}
