//! Every picture the command line writes, on the fixture scenes, maps and worlds: its text
//! stays inside its canvas with no two texts overlapping, its legend stays off the start,
//! the goal and every curve, and every marker is at least 4 pixels across. Stills of
//! missions (`--svg-at`) and PNGs (`--png`) too.

use crate::common::{assert_ok, homospline, root, tmp};
use quick_xml::events::{BytesStart, Event};

/// A box on the page: `[x0, x1] x [y0, y1]`, pixels, y down.
#[derive(Clone, Copy, Debug)]
struct Bbox {
    x0: f64,
    y0: f64,
    x1: f64,
    y1: f64,
}

impl Bbox {
    fn meets(&self, o: &Bbox) -> bool {
        self.x0 < o.x1 && o.x0 < self.x1 && self.y0 < o.y1 && o.y0 < self.y1
    }
    fn holds(&self, (x, y): (f64, f64)) -> bool {
        self.x0 < x && x < self.x1 && self.y0 < y && y < self.y1
    }
    fn join(self, o: Bbox) -> Bbox {
        Bbox {
            x0: self.x0.min(o.x0),
            y0: self.y0.min(o.y0),
            x1: self.x1.max(o.x1),
            y1: self.y1.max(o.y1),
        }
    }
}

/// What the checks need of an SVG.
#[derive(Default, Debug)]
struct Page {
    width: f64,
    height: f64,
    /// Each text's content and its box, with 0.6 em a character (an upper estimate for
    /// sans-serif; the picture code sizes its labels with the same rule).
    texts: Vec<(String, Bbox)>,
    /// The legend's box: its rectangle, or its texts'.
    legend: Option<Bbox>,
    /// The start's and the goal's markers.
    ends: Vec<Bbox>,
    /// Every vertex of every path and polyline outside the legend.
    vertices: Vec<(f64, f64)>,
    /// Markers other than the ends: where a map changed (`rect.change-box`), the robots.
    markers: Vec<(&'static str, Bbox)>,
    /// Animation elements.
    animations: usize,
}

fn attr(e: &BytesStart<'_>, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.as_ref() == key.as_bytes())
        .map(|a| String::from_utf8(a.value.to_vec()).unwrap())
}

fn num(e: &BytesStart<'_>, key: &str) -> Option<f64> {
    attr(e, key).and_then(|v| v.trim_end_matches("px").parse().ok())
}

/// The numbers of a path's `d` or a polyline's `points`, in pairs.
fn pairs(text: &str) -> Vec<(f64, f64)> {
    let v: Vec<f64> = text
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter_map(|t| t.parse().ok())
        .collect();
    v.chunks_exact(2).map(|p| (p[0], p[1])).collect()
}

/// The box of a `<circle>`.
fn disc_box(e: &BytesStart<'_>) -> Bbox {
    let (x, y, r) = (
        num(e, "cx").unwrap(),
        num(e, "cy").unwrap(),
        num(e, "r").unwrap(),
    );
    Bbox {
        x0: x - r,
        y0: y - r,
        x1: x + r,
        y1: y + r,
    }
}

fn read_page(svg: &str) -> Page {
    let mut reader = quick_xml::Reader::from_str(svg);
    let mut page = Page::default();
    let mut groups: Vec<Option<String>> = Vec::new();
    let mut text: Option<(f64, f64, f64)> = None;
    loop {
        let (e, empty) = match reader.read_event().expect("well-formed SVG") {
            Event::Start(e) => (e, false),
            Event::Empty(e) => (e, true),
            Event::Text(t) => {
                if let Some((x, y, size)) = text.take() {
                    let content = t.xml_content().unwrap().trim().to_owned();
                    let w = 0.6 * size * content.chars().count() as f64;
                    let b = Bbox {
                        x0: x,
                        y0: y - size,
                        x1: x + w,
                        y1: y + 0.3 * size,
                    };
                    if groups.iter().flatten().any(|g| g == "legend") {
                        page.legend = Some(page.legend.map_or(b, |l| l.join(b)));
                    }
                    page.texts.push((content, b));
                }
                continue;
            }
            Event::End(e) => {
                if e.name().as_ref() == b"g" {
                    groups.pop();
                }
                continue;
            }
            Event::Eof => break,
            _ => continue,
        };
        let in_group = |id: &str| groups.iter().flatten().any(|g| g == id);
        match e.name().as_ref() {
            b"svg" => {
                page.width = num(&e, "width").unwrap();
                page.height = num(&e, "height").unwrap();
            }
            b"g" if !empty => groups.push(attr(&e, "id")),
            b"text" => {
                let size = num(&e, "font-size").unwrap();
                text = Some((num(&e, "x").unwrap(), num(&e, "y").unwrap(), size));
            }
            b"rect" if in_group("legend") => {
                let (x, y) = (num(&e, "x").unwrap(), num(&e, "y").unwrap());
                let b = Bbox {
                    x0: x,
                    y0: y,
                    x1: x + num(&e, "width").unwrap(),
                    y1: y + num(&e, "height").unwrap(),
                };
                page.legend = Some(page.legend.map_or(b, |l| l.join(b)));
            }
            b"circle" if in_group("endpoints") => page.ends.push(disc_box(&e)),
            b"rect" if attr(&e, "class").as_deref() == Some("change-box") => {
                let (x, y) = (num(&e, "x").unwrap(), num(&e, "y").unwrap());
                page.markers.push((
                    "map change",
                    Bbox {
                        x0: x,
                        y0: y,
                        x1: x + num(&e, "width").unwrap(),
                        y1: y + num(&e, "height").unwrap(),
                    },
                ));
            }
            b"circle" if in_group("robots") => page.markers.push(("robot", disc_box(&e))),
            b"animate" | b"animateMotion" => page.animations += 1,
            b"path" if !in_group("legend") => page.vertices.extend(pairs(&attr(&e, "d").unwrap())),
            b"polyline" => page.vertices.extend(pairs(&attr(&e, "points").unwrap())),
            _ => {}
        }
    }
    page
}

/// Asserts the page's rules on the SVG at `path`.
fn check(path: &std::path::Path, what: &str) {
    let svg = std::fs::read_to_string(path).unwrap();
    let page = read_page(&svg);
    assert!(page.width > 0.0 && page.height > 0.0, "{what}: no size");
    let canvas = Bbox {
        x0: -0.5,
        y0: -0.5,
        x1: page.width + 0.5,
        y1: page.height + 0.5,
    };
    for (t, b) in &page.texts {
        let inside =
            canvas.x0 <= b.x0 && b.x1 <= canvas.x1 && canvas.y0 <= b.y0 && b.y1 <= canvas.y1;
        assert!(
            inside,
            "{what}: text '{t}' at {b:?} leaves the {} x {} canvas",
            page.width, page.height
        );
    }
    for (i, (t, b)) in page.texts.iter().enumerate() {
        if let Some((u, c)) = page.texts[i + 1..].iter().find(|(_, c)| b.meets(c)) {
            panic!("{what}: text '{t}' at {b:?} overlaps '{u}' at {c:?}");
        }
    }
    for (kind, b) in page
        .ends
        .iter()
        .map(|b| ("endpoint", b))
        .chain(page.markers.iter().map(|(k, b)| (*k, b)))
    {
        assert!(
            b.x1 - b.x0 >= 4.0 && b.y1 - b.y0 >= 4.0,
            "{what}: a {kind} marker {b:?} is under 4 pixels"
        );
    }
    let legend = page.legend.unwrap_or_else(|| panic!("{what}: no legend"));
    assert!(
        page.ends.len() == 2,
        "{what}: {} endpoint markers",
        page.ends.len()
    );
    for e in &page.ends {
        assert!(
            !legend.meets(e),
            "{what}: the legend {legend:?} covers an endpoint {e:?}"
        );
    }
    if let Some(v) = page.vertices.iter().find(|v| legend.holds(**v)) {
        panic!("{what}: the legend {legend:?} covers a curve's vertex {v:?}");
    }
}

/// The boxes drawn round map changes and small blockages.
fn change_boxes(page: &Page) -> Vec<&Bbox> {
    page.markers
        .iter()
        .filter(|(k, _)| *k == "map change")
        .map(|(_, b)| b)
        .collect()
}

/// The PNG at `path`, asserted to be twice the size of the SVG `page`.
fn png_of(path: &std::path::Path, page: &Page) -> image::RgbImage {
    let image = image::open(path).unwrap().to_rgb8();
    assert_eq!(
        (image.width() as f64, image.height() as f64),
        (2.0 * page.width, 2.0 * page.height),
        "twice the SVG's size"
    );
    image
}

/// The last (longest) scenario of a `.scen` file as `--start`/`--goal` cell centres.
fn longest(scen: &str) -> (String, String, String) {
    let text = std::fs::read_to_string(root().join(scen)).unwrap();
    let last = text.lines().last().unwrap();
    let f: Vec<&str> = last.split('\t').collect();
    let c = |k: usize| f[k].parse::<f64>().unwrap() + 0.5;
    let map = std::path::Path::new(scen).with_file_name(f[1]);
    (
        map.display().to_string(),
        format!("{},{}", c(4), c(5)),
        format!("{},{}", c(6), c(7)),
    )
}

#[test]
fn plans_and_graphs_of_scenes_keep_their_text_inside_and_legend_off_the_ends() {
    for scene in [
        "concave-cup",
        "convex",
        "field",
        "narrow-pass",
        "two-homotopies",
    ] {
        let file = format!("fixtures/scenes/{scene}.yaml");
        for (cmd, name) in [("plan", "plan"), ("graph", "graph")] {
            let svg = tmp(&format!("{scene}.{name}.svg"));
            let out = homospline()
                .args([cmd, &file, "--svg", svg.to_str().unwrap()])
                .output()
                .unwrap();
            assert!(out.status.code().is_some_and(|c| c <= 1), "{scene} {cmd}");
            check(&svg, &format!("{cmd} {scene}"));
        }
    }
}

/// A tall, narrow scene: the legend's column is wider than the drawing, and the page is
/// widened to hold it.
#[test]
fn a_tall_narrow_scene_keeps_its_legend_on_the_page() {
    let scene = tmp("tall.yaml");
    std::fs::write(
        &scene,
        "name: tall\nbounds: {min: [0, 0], max: [8, 120]}\nstart: [4, 2]\ngoal: [4, 118]\n\
         obstacles:\n  - name: a\n    circles: [[2, 40, 1.2], [6, 80, 1.2]]\n",
    )
    .unwrap();
    for cmd in ["plan", "graph"] {
        let svg = tmp(&format!("tall.{cmd}.svg"));
        let out = homospline()
            .args([cmd, scene.to_str().unwrap(), "--svg", svg.to_str().unwrap()])
            .output()
            .unwrap();
        assert_ok(&out);
        check(&svg, &format!("{cmd} tall"));
    }
}

#[test]
fn plans_on_maps_keep_their_text_inside_and_legend_off_the_ends() {
    for scen in [
        "fixtures/maps/movingai/maze-32-32-2-random-1.scen",
        "fixtures/maps/movingai/random-32-32-10-random-1.scen",
        "fixtures/maps/movingai/room-32-32-4-random-1.scen",
        "fixtures/maps/movingai/warehouse-10-20-10-2-1-random-1.scen",
    ] {
        let (map, start, goal) = longest(scen);
        let svg = tmp("map-plan.svg");
        let out = homospline()
            .args(["plan", &map, "--start", &start, "--goal", &goal])
            .args(["--svg", svg.to_str().unwrap()])
            .output()
            .unwrap();
        assert_ok(&out);
        check(&svg, &format!("plan {map} {start} {goal}"));
    }
}

#[test]
fn missions_keep_their_caption_inside_and_draw_robots_at_their_start() {
    let dir = root().join("fixtures/worlds");
    let mut worlds: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .chain(std::fs::read_dir(dir.join("maps")).unwrap())
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    worlds.sort();
    assert!(worlds.len() >= 7);
    for w in &worlds {
        let svg = tmp("mission.svg");
        let out = homospline()
            .args([
                "simulate",
                w.to_str().unwrap(),
                "--svg",
                svg.to_str().unwrap(),
            ])
            .output()
            .unwrap();
        assert!(out.status.code().is_some_and(|c| c <= 1), "{}", w.display());
        check(&svg, &format!("simulate {}", w.display()));
        // A static view shows each robot where it starts, not at the page's corner.
        let text = std::fs::read_to_string(&svg).unwrap();
        let robots = &text[text.find("<g id=\"robots\">").unwrap()..];
        for circle in robots.split("<circle").skip(1) {
            assert!(
                circle.contains(" cx=\""),
                "{}: a robot without a position",
                w.display()
            );
            assert!(!circle.starts_with(" r="), "{}", w.display());
        }
        assert!(!text.contains(" 1 scouts "), "{}: one scout", w.display());
    }
}

/// A still of a map mission (`--svg-at`): no animation, the blocked door's box at least 8
/// pixels on a 512 x 512 map, the UGV away from its start, the caption's time; and its
/// PNG (`--png`), twice the SVG's size, with the map's cells in their exact grey.
#[test]
fn mission_stills_and_pngs_show_the_moment_with_every_marker_visible() {
    let world = "fixtures/worlds/maps/16room-blocked.yaml";
    let (svg, png) = (tmp("still.svg"), tmp("still.png"));
    let out = homospline()
        .args(["simulate", world, "--svg-at", "150"])
        .args([
            "--svg",
            svg.to_str().unwrap(),
            "--png",
            png.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(out.status.code().is_some_and(|c| c <= 1));
    check(&svg, "simulate --svg-at 150");
    let text = std::fs::read_to_string(&svg).unwrap();
    let page = read_page(&text);
    assert_eq!(page.animations, 0, "a still has no animation");
    assert!(
        text.contains("at: 150.0 s of "),
        "the caption gives the time"
    );
    let boxes = change_boxes(&page);
    assert!(!boxes.is_empty(), "the blocked door has its box");
    for b in boxes {
        assert!(b.x1 - b.x0 >= 8.0 && b.y1 - b.y0 >= 8.0, "{b:?}");
    }
    let animated = tmp("animated.svg");
    let out = homospline()
        .args(["simulate", world, "--svg", animated.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(out.status.code().is_some_and(|c| c <= 1));
    let start = |t: &str| {
        let robots = &t[t.find("<g id=\"robots\">").unwrap()..];
        let last = robots.rfind("<circle").unwrap();
        pairs(&robots[last..robots[last..].find("fill").unwrap() + last])
    };
    let still_ugv = start(&text);
    let animated_ugv = start(&std::fs::read_to_string(&animated).unwrap());
    assert_ne!(
        still_ugv, animated_ugv,
        "at 150 s the UGV has left its start"
    );
    let image = png_of(&png, &page);
    let grey = image.pixels().filter(|p| p.0 == [0x55, 0x55, 0x55]).count();
    assert!(
        grey > 10_000,
        "the map's walls in their exact grey: {grey} pixels"
    );
}

/// `plan --png` on a map: the PNG decodes at twice the SVG's size, its cells drawn
/// pixelated (in their exact grey, most of their area), and the legend lettered.
#[test]
fn map_plan_pngs_are_twice_the_svg_with_sharp_cells() {
    let (svg, png) = (tmp("plan-png.svg"), tmp("plan.png"));
    let map = "fixtures/maps/movingai/random-32-32-10.map";
    let out = homospline()
        .args(["plan", map, "--start", "1.5,27.5", "--goal", "30.5,2.5"])
        .args([
            "--svg",
            svg.to_str().unwrap(),
            "--png",
            png.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = std::fs::read_to_string(&svg).unwrap();
    let page = read_page(&text);
    let legend: Vec<&str> = page.texts.iter().map(|(t, _)| t.as_str()).collect();
    assert!(
        legend.contains(&"A (chosen)") && legend.contains(&"B"),
        "{legend:?}"
    );
    let image = png_of(&png, &page);
    // The map's occupied cells, and the pixels of a cell at twice the picture's scale.
    let cells = std::fs::read_to_string(root().join(map))
        .unwrap()
        .lines()
        .skip(4)
        .flat_map(|l| l.chars())
        .filter(|c| matches!(c, '@' | 'O' | 'T' | 'W'))
        .count();
    let image_el = &text[text.find("<image").unwrap()..];
    let width: f64 = image_el[image_el.find(" width=\"").unwrap() + 8..]
        .split('"')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    let cell_px = 2.0 * width / 32.0;
    let expected = cells as f64 * cell_px * cell_px;
    let grey = image.pixels().filter(|p| p.0 == [0x55, 0x55, 0x55]).count() as f64;
    assert!(
        grey > 0.8 * expected && grey < 1.01 * expected,
        "{grey} grey pixels against {expected} for {cells} cells"
    );
}

/// A hidden obstacle far smaller than a marker (a pebble of radius 0.05 on a 60-unit scene,
/// under a pixel) gets a box of at least 8 pixels that shows where it is; `graph --png`
/// writes its picture too; a map's raster is drawn pixelated, sharp at any zoom.
#[test]
fn small_blockages_are_boxed_and_graphs_render_to_png() {
    let dir = tmp("pebble-world");
    std::fs::create_dir_all(&dir).unwrap();
    let world = dir.join("pebble.yaml");
    std::fs::write(
        &world,
        format!(
            "version: 1\nname: pebble\nscene: {}\nhidden_obstacles:\n- name: pebble\n  circles: [[30.0, 45.0, 0.05]]\nteam:\n  ugv: {{speed: 1.0, sensor_range: 6.0}}\n  uavs: []\n",
            root().join("fixtures/scenes/convex.yaml").display()
        ),
    )
    .unwrap();
    let svg = dir.join("pebble.svg");
    let out = homospline()
        .args([
            "simulate",
            world.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.code().is_some_and(|c| c <= 1),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    check(&svg, "simulate pebble");
    let page = read_page(&std::fs::read_to_string(&svg).unwrap());
    let boxes = change_boxes(&page);
    assert_eq!(boxes.len(), 1, "{:?}", page.markers);
    assert!(boxes[0].x1 - boxes[0].x0 >= 8.0);

    let (gsvg, gpng) = (dir.join("graph.svg"), dir.join("graph.png"));
    let map = "fixtures/maps/movingai/random-32-32-10.map";
    let out = homospline()
        .args([
            "graph",
            map,
            "--svg",
            gsvg.to_str().unwrap(),
            "--png",
            gpng.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_ok(&out);
    let text = std::fs::read_to_string(&gsvg).unwrap();
    let image = &text[text.find("<image").unwrap()..];
    let image = &image[..image.find('>').unwrap()];
    assert!(
        image.contains("image-rendering: pixelated") && image.contains("optimizeSpeed"),
        "{image}"
    );
    png_of(&gpng, &read_page(&text));
}
