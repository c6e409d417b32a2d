//! SVG pictures the way the paper's figures show a plan: the potential field as a heat map,
//! obstacles, the Voronoi graph, the class seeds, the optimised paths (the chosen one bold),
//! start and goal, a legend and a scale bar. Each layer is a `<g>` with its own `id`.
//!
//! A map's occupancy is one raster, a PNG of one pixel per cell (1-bit indexed colour,
//! encoded by the `png` crate) embedded as a base64 data URI and drawn pixelated,
//! so that no seams show between cells; its Voronoi graph is drawn thin and light, under the
//! paths.

use base64::Engine as _;
use base64::engine::general_purpose::STANDARD;
use homospline_front::report::{ClassNames, fault};
use homospline_geom::{Bounds, Point, Real, Scene};
use homospline_maps::OccupancyMap;
use homospline_optim::Plan;
use homospline_voronoi::VoronoiGraph;
use svg::Document;
use svg::node::element::path::Data;
use svg::node::element::{Circle, Group, Image, Line, Path, Rectangle, Text};

/// Picture width in pixels.
const WIDTH: Real = 900.0;
/// Heat-map cells along the longer side.
const HEAT_CELLS: usize = 90;
/// Colour of occupied map cells (`#555`, as scene obstacles).
const OCCUPIED: [u8; 3] = [0x55, 0x55, 0x55];
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

    /// How the Voronoi graph is drawn over this background: on a map, thin and light (at
    /// most 0.6 of a cell wide) so the paths stand out.
    fn graph_style(&self, v: &View) -> GraphStyle {
        match self {
            Background::Scene(..) => GraphStyle {
                colour: "#999",
                width: 1.2,
                node_colour: "#777",
                node_radius: 2.2,
                opacity: None,
            },
            Background::Map(map) => {
                let width = (0.6 * map.cell * v.scale).min(1.0);
                GraphStyle {
                    colour: "#bbb",
                    width,
                    node_colour: "#bbb",
                    node_radius: width,
                    opacity: Some(0.5),
                }
            }
        }
    }
}

/// Stroke and node dots of the Voronoi graph.
struct GraphStyle {
    colour: &'static str,
    width: Real,
    node_colour: &'static str,
    node_radius: Real,
    /// Opacity of the whole layer.
    opacity: Option<Real>,
}

/// Where map coordinates land on the page: `bounds` scaled to a width, y up (ROS, scenes) or
/// down (images, MovingAI).
pub struct View {
    min: Point,
    max: Point,
    /// Pixels per map unit.
    pub scale: Real,
    y_down: bool,
}

impl View {
    fn new(bg: &Background<'_>) -> Self {
        Self::fit(&bg.bounds(), bg.y_down(), WIDTH)
    }
    /// `b` with its longer side `width` pixels.
    pub fn fit(b: &Bounds, y_down: bool, width: Real) -> Self {
        let e = b.extent();
        Self {
            min: b.min,
            max: b.max,
            scale: width / e.x.max(e.y),
            y_down,
        }
    }
    /// The page x of map x.
    pub fn x(&self, x: Real) -> Real {
        (x - self.min.x) * self.scale
    }
    /// The page y of map y.
    pub fn y(&self, y: Real) -> Real {
        if self.y_down {
            (y - self.min.y) * self.scale
        } else {
            (self.max.y - y) * self.scale
        }
    }
    /// The drawing's width, pixels.
    pub fn w(&self) -> Real {
        (self.max.x - self.min.x) * self.scale
    }
    /// The drawing's height, pixels.
    pub fn h(&self) -> Real {
        (self.max.y - self.min.y) * self.scale
    }
    /// Points as a polyline's `points` text.
    pub fn points(&self, pts: &mut dyn Iterator<Item = Point>) -> String {
        pts.map(|p| format!("{:.2},{:.2}", self.x(p.x), self.y(p.y)))
            .collect::<Vec<_>>()
            .join(" ")
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

fn voronoi(graph: &VoronoiGraph, v: &View, style: &GraphStyle) -> Group {
    let mut g = Group::new().set("id", "voronoi");
    if let Some(o) = style.opacity {
        g = g.set("opacity", o);
    }
    for e in &graph.edges {
        let pts: Vec<Point> = e.polyline.iter().map(|p| Point::new(p[0], p[1])).collect();
        g = g.add(
            Path::new()
                .set("d", v.poly(&pts))
                .set("fill", "none")
                .set("stroke", style.colour)
                .set("stroke-width", style.width),
        );
    }
    for n in &graph.nodes {
        g = g.add(
            Circle::new()
                .set("cx", v.x(n.at[0]))
                .set("cy", v.y(n.at[1]))
                .set("r", style.node_radius)
                .set("fill", style.node_colour),
        );
    }
    g
}

/// Occupied cells: one `<image>`, a PNG of one pixel per cell (occupied grey, free
/// transparent), placed over the map's bounds and drawn pixelated. PNG rows run down the
/// screen: cell row `j` is picture row `j` when the map's y runs down (MovingAI), row
/// `height - 1 - j` when it runs up (ROS).
fn cells(map: &OccupancyMap, v: &View) -> Group {
    let b = map.bounds();
    let (y_a, y_b) = (v.y(b.min.y), v.y(b.max.y));
    // Whether cell row 0 is at the top of the picture (the map's y runs down the screen).
    let row0_on_top = y_a <= y_b;
    let group = Group::new().set("id", "obstacles");
    match occupancy_href(map, row0_on_top) {
        Ok(href) => group.add(
            Image::new()
                .set("x", v.x(b.min.x))
                .set("y", y_a.min(y_b))
                .set("width", (b.max.x - b.min.x) * v.scale)
                .set("height", (y_a - y_b).abs())
                .set("preserveAspectRatio", "none")
                .set("image-rendering", "optimizeSpeed")
                .set("style", "image-rendering: pixelated")
                .set("href", href),
        ),
        // Said in the picture rather than left out unseen.
        Err(e) => group.add(
            Text::new(format!("the map's cells could not be drawn: {e}"))
                .set("x", v.x(b.min.x))
                .set("y", y_a.min(y_b) + 13.0)
                .set("font-size", 13),
        ),
    }
}

/// The occupancy of `map` as a `data:` URI of a 1-bit PNG, one pixel per cell (occupied grey,
/// free transparent), cell row 0 at the top when `row0_on_top`; the encoder's error in words
/// when the map has no cells to draw.
pub(crate) fn occupancy_href(map: &OccupancyMap, row0_on_top: bool) -> Result<String, String> {
    let (w, h) = (map.width, map.height);
    let png = indexed_1bit(w, h, [[0xff; 3], OCCUPIED], [0, 0xff], |i, r| {
        let j = if row0_on_top { r } else { h - 1 - r };
        map.occupied[j * w + i]
    })?;
    Ok(format!("data:image/png;base64,{}", STANDARD.encode(png)))
}

/// The PNG of a `width x height` image whose pixel `(column, row)` (row 0 at the top) is
/// palette entry 1 where `pixel` says so and entry 0 elsewhere; `palette` gives the two RGB
/// colours and `alpha` their opacities: 1-bit indexed colour, encoded by the `png` crate.
fn indexed_1bit(
    width: usize,
    height: usize,
    palette: [[u8; 3]; 2],
    alpha: [u8; 2],
    pixel: impl Fn(usize, usize) -> bool,
) -> Result<Vec<u8>, String> {
    let stride = width.div_ceil(8);
    let mut packed = vec![0u8; stride * height];
    for (r, row) in packed.chunks_mut(stride.max(1)).enumerate() {
        for i in 0..width {
            if pixel(i, r) {
                row[i / 8] |= 0x80 >> (i % 8);
            }
        }
    }
    let size = |n: usize| u32::try_from(n).map_err(|_| format!("{n} pixels do not fit a PNG"));
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, size(width)?, size(height)?);
    encoder.set_color(png::ColorType::Indexed);
    encoder.set_depth(png::BitDepth::One);
    encoder.set_palette(palette.as_flattened().to_vec());
    encoder.set_trns(alpha.to_vec());
    let mut writer = encoder.write_header().map_err(|e| e.to_string())?;
    writer
        .write_image_data(&packed)
        .and_then(|()| writer.finish())
        .map_err(|e| e.to_string())?;
    Ok(out)
}

/// Width of a line of `text` in pixels at `font_size`, an upper estimate for sans-serif
/// (0.6 em a character; most glyphs are narrower).
pub fn text_width(text: &str, font_size: Real) -> Real {
    0.6 * font_size * text.chars().count() as Real
}

/// A label's anchor near a marker at `(x, y)`: up and to the right, or to the other side
/// where that would leave the picture `w x h` (a label is `width` wide and `size` high).
pub fn label_at(
    (x, y): (Real, Real),
    width: Real,
    size: Real,
    (w, h): (Real, Real),
) -> (Real, Real) {
    let lx = if x + 8.0 + width <= w {
        x + 8.0
    } else {
        (x - 8.0 - width).max(0.0)
    };
    let ly = if y - 8.0 - size >= 0.0 {
        y - 8.0
    } else {
        (y + 8.0 + size).min(h)
    };
    (lx, ly)
}

fn endpoints(start: Point, goal: Point, v: &View) -> Group {
    let mut g = Group::new().set("id", "endpoints");
    for (p, label, colour) in [(start, "S", "#2ca02c"), (goal, "T", "#d62728")] {
        let (x, y) = (v.x(p.x), v.y(p.y));
        let (lx, ly) = label_at((x, y), text_width(label, 16.0), 16.0, (v.w(), v.h()));
        g = g
            .add(
                Circle::new()
                    .set("cx", x)
                    .set("cy", y)
                    .set("r", 6)
                    .set("fill", colour)
                    .set("stroke", "black"),
            )
            .add(
                Text::new(label)
                    .set("x", lx)
                    .set("y", ly)
                    .set("font-size", 16)
                    .set("font-family", "sans-serif"),
            );
    }
    g
}

/// Padding of the legend's box.
const STRIP_PAD: Real = 12.0;
/// Height of the scale bar's row, at the top of the strip under the drawing.
const SCALE_ROW: Real = 40.0;
/// A legend row's height.
const ROW: Real = 20.0;
/// The legend's font size.
const LEGEND_FONT: Real = 13.0;

/// The strip under the drawing: the scale bar's row, then the legend in columns of rows,
/// each column as wide as the longest label, as many columns as the page's width holds.
/// The page is widened when one column is wider than the drawing (a tall, narrow map).
struct LegendLayout {
    rows: usize,
    columns: usize,
    column_width: Real,
    /// The page's width.
    width: Real,
}

impl LegendLayout {
    fn new(items: &[(&str, String, bool)], v: &View) -> Self {
        let widest = items
            .iter()
            .map(|(_, l, _)| text_width(l, LEGEND_FONT))
            .fold(0.0, Real::max);
        let column_width = 36.0 + widest + 16.0;
        let width = v.w().max(column_width).ceil();
        let columns = ((width / column_width).floor() as usize).clamp(1, items.len().max(1));
        Self {
            rows: items.len().div_ceil(columns).max(1),
            columns,
            column_width,
            width,
        }
    }

    /// The legend box's height.
    fn box_height(&self) -> Real {
        ROW * self.rows as Real + STRIP_PAD
    }

    /// The strip's height.
    fn height(&self) -> Real {
        SCALE_ROW + self.box_height() + STRIP_PAD
    }
}

/// A scale bar at the left of the strip's first row, a round length of at most a fifth of
/// the map's width that fits the page.
fn scale_bar(v: &View, page_width: Real) -> Group {
    let target = ((v.max.x - v.min.x) / 5.0).min((page_width - 60.0).max(40.0) / v.scale);
    let mag = 10f64.powf(target.log10().floor());
    let len = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .rfind(|l| *l <= target)
        .unwrap_or(mag);
    // Under the drawing, in the strip: never over a path or an endpoint.
    let (x0, y0) = (20.0, v.h() + 30.0);
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

/// The legend, in the strip under the drawing and the scale bar (off the start, the goal
/// and every curve), sized to its labels.
fn legend(items: &[(&str, String, bool)], layout: &LegendLayout, v: &View) -> Group {
    let mut g = Group::new().set("id", "legend");
    let top = v.h() + SCALE_ROW;
    g = g.add(
        Rectangle::new()
            .set("x", 0)
            .set("y", top)
            .set("width", layout.column_width * layout.columns as Real)
            .set("height", layout.box_height())
            .set("fill", "white")
            .set("stroke", "#333"),
    );
    for (k, (colour, label, dashed)) in items.iter().enumerate() {
        let (col, row) = (k / layout.rows, k % layout.rows);
        let x0 = 8.0 + layout.column_width * col as Real;
        let y = top + STRIP_PAD + 4.0 + ROW * row as Real;
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
                .set("font-size", LEGEND_FONT)
                .set("font-family", "sans-serif"),
        );
    }
    g
}

/// The document: the drawing `v.w() x v.h()` and the strip under it, `layout.width` wide.
fn document(v: &View, layout: &LegendLayout) -> Document {
    let (w, h) = (layout.width, (v.h() + layout.height()).ceil());
    Document::new()
        .set("viewBox", (0, 0, w, h))
        .set("width", w)
        .set("height", h)
        .add(
            Rectangle::new()
                .set("width", "100%")
                .set("height", "100%")
                .set("fill", "white"),
        )
}

/// Where world coordinates land on `bg`'s pictures: `[ox, sx, oy, sy]`, the page's x being
/// `ox + sx * x` and its y `oy + sy * y` (for `homospline serve`'s clicks).
pub fn transform(bg: &Background<'_>) -> [Real; 4] {
    let v = View::new(bg);
    let (x0, y0) = (v.x(0.0), v.y(0.0));
    [x0, v.x(1.0) - x0, y0, v.y(1.0) - y0]
}

/// The background alone (a scene's heat map and obstacles, or a map's cells), with its
/// scale bar and the start and goal when known: what `homospline serve` shows before a plan.
pub fn background_svg(bg: &Background<'_>, ends: Option<(Point, Point)>) -> String {
    let v = View::new(bg);
    let layout = LegendLayout::new(&[], &v);
    let mut doc = bg.layers(&v, document(&v, &layout));
    if let Some((s, t)) = ends {
        doc = doc.add(endpoints(s, t, &v));
    }
    doc.add(scale_bar(&v, layout.width)).to_string()
}

/// A plan: background (heat map and circles, or map cells), Voronoi graph, seeds, paths
/// (chosen bold), start and goal, legend, scale bar.
pub fn plan_svg(bg: &Background<'_>, plan: &Plan, names: ClassNames) -> String {
    let v = View::new(bg);
    let style = bg.graph_style(&v);
    let items = plan_legend(plan, &style, names);
    let layout = LegendLayout::new(&items, &v);
    let mut doc = bg.layers(&v, document(&v, &layout));
    if let Some(g) = &plan.graph {
        doc = doc.add(voronoi(g, &v, &style));
    }
    let mut seeds = Group::new().set("id", "seeds");
    let mut paths = Group::new().set("id", "paths");
    let mut best = Group::new().set("id", "best");
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
    }
    let (start, goal) = (plan.start, plan.goal);
    doc.add(seeds)
        .add(paths)
        .add(best)
        .add(endpoints(start, goal, &v))
        .add(legend(&items, &layout, &v))
        .add(scale_bar(&v, layout.width))
        .to_string()
}

/// A plan's legend: the graph, each class by its name (`names`), the seeds.
fn plan_legend(
    plan: &Plan,
    style: &GraphStyle,
    names: ClassNames,
) -> Vec<(&'static str, String, bool)> {
    let mut items = vec![(style.colour, "Voronoi graph".to_owned(), false)];
    for c in &plan.classes {
        let chosen = plan.best == Some(c.rank);
        items.push((
            PALETTE[(c.rank - 1) % PALETTE.len()],
            format!(
                "{}{}{}",
                names.ranked(c.rank, &c.signature),
                if chosen { " (chosen)" } else { "" },
                fault(c).map_or(String::new(), |f| format!(" {}", f.shout()))
            ),
            false,
        ));
    }
    items.push(("#555", "class seeds: dashed".to_owned(), true));
    items
}

/// A Voronoi graph: background, graph, start and goal, legend, scale bar.
pub fn graph_svg(bg: &Background<'_>, graph: &VoronoiGraph) -> String {
    let v = View::new(bg);
    let style = bg.graph_style(&v);
    let items = vec![(
        style.colour,
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
    let layout = LegendLayout::new(&items, &v);
    let mut doc = bg
        .layers(&v, document(&v, &layout))
        .add(voronoi(graph, &v, &style));
    if let (Some(s), Some(t)) = (at(graph.start), at(graph.goal)) {
        doc = doc.add(endpoints(s, t, &v));
    }
    doc.add(legend(&items, &layout, &v))
        .add(scale_bar(&v, layout.width))
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use homospline_voronoi::{Edge, Node, NodeKind};

    fn map(w: usize, h: usize, y_down: bool) -> OccupancyMap {
        let occupied = (0..w * h)
            .map(|k| {
                let (i, j) = (k % w, k / w);
                i == 0 || j == 0 || (i * 7 + j * j * 3) % 11 == 0 || (i < 3 && j + 2 == h)
            })
            .collect();
        OccupancyMap {
            name: "m".to_owned(),
            width: w,
            height: h,
            cell: 0.5,
            origin: Point::new(-2.0, 3.0),
            occupied,
            y_down,
        }
    }

    /// The `<image>` elements of an SVG: each one's attributes.
    fn images(svg: &str) -> Vec<Vec<(String, String)>> {
        let mut reader = quick_xml::Reader::from_str(svg);
        let mut out = Vec::new();
        loop {
            match reader.read_event().expect("well-formed SVG") {
                quick_xml::events::Event::Empty(e) | quick_xml::events::Event::Start(e)
                    if e.name().as_ref() == b"image" =>
                {
                    out.push(
                        e.attributes()
                            .map(|a| {
                                let a = a.unwrap();
                                (
                                    String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                                    String::from_utf8(a.value.to_vec()).unwrap(),
                                )
                            })
                            .collect(),
                    );
                }
                quick_xml::events::Event::Eof => break,
                _ => {}
            }
        }
        out
    }

    /// The occupancy a PNG holds: its opaque dark pixels (occupied cells are opaque grey,
    /// free ones transparent), decoded by the `image` crate, laid out as the map readers lay
    /// rows out (image row 0 at the top, y up: row `r` at y index `h - 1 - r`).
    fn decode(png: &[u8], w: usize, h: usize) -> Vec<bool> {
        let img = image::load_from_memory(png).unwrap().to_rgba8();
        assert_eq!((img.width() as usize, img.height() as usize), (w, h));
        let mut occ = vec![false; w * h];
        for (i, r, px) in img.enumerate_pixels() {
            occ[(h - 1 - r as usize) * w + i as usize] = px.0[3] == 255 && px.0[0] < 128;
        }
        occ
    }

    #[test]
    fn the_png_decodes_back_to_the_pixels() {
        // Wider than 8 and not a multiple of it; a tall one besides.
        for (w, h) in [(1, 1), (13, 5), (300, 1800)] {
            let on = |i: usize, r: usize| (i * 5 + r * 3) % 7 < 2;
            let png = indexed_1bit(w, h, [[0xff; 3], [0x55; 3]], [0, 0xff], on).unwrap();
            assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
            let occ = decode(&png, w, h);
            for r in 0..h {
                for i in 0..w {
                    // The reader puts image row r at y index h - 1 - r.
                    assert_eq!(
                        occ[(h - 1 - r) * w + i],
                        on(i, r),
                        "({i}, {r}) of {w} x {h}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_map_is_one_raster_over_its_cells_the_right_way_up() {
        let (w, h) = (21, 9);
        for y_down in [true, false] {
            let m = map(w, h, y_down);
            let g = VoronoiGraph {
                resolution: 2.0,
                nodes: vec![
                    Node {
                        id: 0,
                        at: [1.0, 5.0],
                        clearance: 1.0,
                        kind: NodeKind::Junction,
                    },
                    Node {
                        id: 1,
                        at: [6.0, 5.0],
                        clearance: 1.0,
                        kind: NodeKind::DeadEnd,
                    },
                ],
                edges: vec![Edge {
                    from: 0,
                    to: 1,
                    length: 5.0,
                    min_clearance: 1.0,
                    mean_clearance: 1.0,
                    polyline: vec![[1.0, 5.0], [6.0, 5.0]].into(),
                }],
                start: None,
                goal: None,
                obstacles: vec![],
                built_for: None,
            };
            let svg = graph_svg(&Background::Map(&m), &g);
            assert!(!svg.contains("fill=\"#555\""), "no cell rectangles");
            let imgs = images(&svg);
            assert_eq!(imgs.len(), 1);
            let attr = |k: &str| {
                imgs[0]
                    .iter()
                    .find(|(a, _)| a == k)
                    .map(|(_, v)| v.clone())
                    .unwrap()
            };
            let num = |k: &str| attr(k).parse::<f64>().unwrap();
            // The map is 10.5 x 4.5 units: 900 px across.
            let scale = 900.0 / 10.5;
            assert_eq!((num("x"), num("y")), (0.0, 0.0));
            assert!((num("width") - 900.0).abs() < 1e-9);
            assert!((num("height") - 4.5 * scale).abs() < 1e-9);
            assert!(attr("style").contains("image-rendering: pixelated"));
            let png = STANDARD
                .decode(attr("href").strip_prefix("data:image/png;base64,").unwrap())
                .unwrap();
            let occ = decode(&png, w, h);
            for j in 0..h {
                // Picture row of cell row j: from the top, j when y runs down.
                let r = if y_down { j } else { h - 1 - j };
                for i in 0..w {
                    assert_eq!(occ[(h - 1 - r) * w + i], m.occupied[j * w + i]);
                }
            }
            // The graph is thin (0.6 of a cell at most), light and half transparent.
            assert!(svg.contains("<g id=\"voronoi\" opacity=\"0.5\">"), "{svg}");
            assert!(svg.contains("stroke=\"#bbb\" stroke-width=\"1\""));
        }
    }

    /// The scale bar's drawn length is its label's length at the picture's scale, on wide
    /// and tall maps and on narrow pages (it once was cut to 150 px and kept its label).
    #[test]
    fn the_scale_bar_is_as_long_as_it_says() {
        for (w, h) in [(21, 9), (200, 9), (9, 200), (3, 300)] {
            let m = map(w, h, true);
            let v = View::new(&Background::Map(&m));
            // A page is at least a legend column wide (about 150 px).
            for page in [v.w().max(150.0), v.w().max(400.0)] {
                let text = scale_bar(&v, page).to_string();
                let num = |key: &str| -> f64 {
                    let at = text.find(&format!("{key}=\"")).unwrap() + key.len() + 2;
                    text[at..].split('"').next().unwrap().parse().unwrap()
                };
                let label: f64 = text
                    .split("map units")
                    .next()
                    .and_then(|t| t.rsplit('>').next())
                    .unwrap()
                    .trim()
                    .parse()
                    .unwrap();
                let drawn = num("x2") - num("x1");
                assert!((drawn - label * v.scale).abs() < 1e-6, "{w} x {h}: {text}");
                assert!(num("x2") <= page, "{w} x {h}: the bar leaves the page");
            }
        }
    }

    #[test]
    fn the_raster_sits_where_the_cells_do() {
        // A cell's centre in map coordinates lands on its pixel of the image.
        for y_down in [true, false] {
            let m = map(21, 9, y_down);
            let v = View::new(&Background::Map(&m));
            let b = m.bounds();
            let (top, bottom) = (
                v.y(b.min.y).min(v.y(b.max.y)),
                v.y(b.min.y).max(v.y(b.max.y)),
            );
            let px = (bottom - top) / m.height as Real;
            for j in 0..m.height {
                let y = m.origin.y + (j as Real + 0.5) * m.cell;
                let r = ((v.y(y) - top) / px).floor() as usize;
                assert_eq!(r, if y_down { j } else { m.height - 1 - j });
            }
        }
    }
}
