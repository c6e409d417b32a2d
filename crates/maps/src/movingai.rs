//! MovingAI benchmark maps (`.map`) and scenarios (`.scen`), read line by line so that every
//! malformed file gets an error naming the line (`file:line: problem`); a scenario line's
//! fields are parsed by the `movingai` crate.
//!
//! Coordinates: one map unit per cell, x to the right, y down the file's rows; cell `(i, j)`
//! covers `[i, i + 1] x [j, j + 1]`; a scenario's cell `(sx, sy)` is the point
//! `(sx + 0.5, sy + 0.5)`. `.` `G` `S` are free; `@` `O` `T` `W` are blocked.

use homospline_geom::Point;
use homospline_geom::math::Num;

use crate::{MapError, OccupancyMap, stem};

/// One scenario of a `.scen` file.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Bucket.
    pub bucket: u32,
    /// The map file it names.
    pub map: String,
    /// The map's width the line declares, cells.
    pub map_width: usize,
    /// The map's height the line declares, cells.
    pub map_height: usize,
    /// Start, map coordinates (cell centre).
    pub start: Point,
    /// Goal, map coordinates (cell centre).
    pub goal: Point,
    /// The 8-connected (octile) optimal length given by the file.
    pub optimal_length: f64,
    /// Line of the file it was read from (1-based).
    pub line: usize,
}

impl Scenario {
    /// Checks that a map of `size` (width, height, cells; read from `map_source`) has the
    /// size this scenario's line of `source` declares. MovingAI would scale the map to the
    /// declared size; scaled maps are not supported, so the line is refused, `source:line`.
    pub fn check_map_size(
        &self,
        source: &str,
        size: (usize, usize),
        map_source: &str,
    ) -> Result<(), MapError> {
        if (self.map_width, self.map_height) == size {
            return Ok(());
        }
        Err(format_err(
            source,
            Some(self.line),
            format!(
                "map size: the line declares a {w} x {h} map (width x height), but its map {map_source} is {} x {}: scaled maps are not supported (MovingAI would scale the map to {w} x {h})",
                size.0,
                size.1,
                w = self.map_width,
                h = self.map_height,
            ),
        ))
    }
}

fn format_err(source: &str, line: Option<usize>, problem: impl Into<String>) -> MapError {
    MapError::Format {
        source_name: source.to_owned(),
        line,
        problem: problem.into(),
    }
}

/// The header keys of a `.map`, in the order MovingAI writes them.
const HEADER_KEYS: [&str; 3] = ["type", "height", "width"];

/// Reads a `.map` file's text. The header holds `type` (`octile`, or `4-connected`, which
/// reads the same here: the planner does not walk cells), `height` and `width`, each once
/// and in any order, then the line `map` and `height` rows of `width` cells. Every error
/// names its line; a field missing from the header is reported at the `map` line.
pub fn read_map(text: &str, source: &str) -> Result<OccupancyMap, MapError> {
    let err = |line: usize, p: String| format_err(source, Some(line), p);
    let lines: Vec<&str> = text.trim_start_matches('\u{feff}').lines().collect();
    // Each key's value and 1-based line.
    let mut header: [Option<(&str, usize)>; 3] = [None; 3];
    let mut body_at = None;
    for (n, l) in lines.iter().enumerate() {
        let l = l.trim();
        if l == "map" {
            body_at = Some(n + 1);
            break;
        }
        let mut parts = l.split_whitespace();
        let (key, value, rest) = (parts.next(), parts.next(), parts.next());
        let Some(key) = key else { continue };
        let slot = HEADER_KEYS.iter().position(|k| *k == key);
        match (slot, value, rest) {
            (Some(i), Some(v), None) => {
                if let Some((_, first)) = header[i] {
                    return Err(err(
                        n + 1,
                        format!("a second `{key}` line (the first is line {first})"),
                    ));
                }
                header[i] = Some((v, n + 1));
            }
            _ => {
                return Err(err(
                    n + 1,
                    format!("expected `type`, `height`, `width` or `map`, got '{l}'"),
                ));
            }
        }
    }
    let Some(body_at) = body_at else {
        return Err(if lines.iter().all(|l| l.trim().is_empty()) {
            err(1, "empty file: not a MovingAI map".into())
        } else {
            err(
                lines.len(),
                "no `map` line: the file ends in its header (not a MovingAI map?)".into(),
            )
        });
    };
    // Present, else missing from the header: reported at the `map` line.
    let field = |i: usize| -> Result<(&str, usize), MapError> {
        header[i].ok_or_else(|| {
            err(
                body_at,
                format!(
                    "missing `{}` line in the header (it must come before `map`)",
                    HEADER_KEYS[i]
                ),
            )
        })
    };
    let (kind, n) = field(0)?;
    if !(kind.eq_ignore_ascii_case("octile") || kind.eq_ignore_ascii_case("4-connected")) {
        return Err(err(
            n,
            format!("type '{kind}' is not a MovingAI map type (octile, or 4-connected)"),
        ));
    }
    let dim = |i: usize| -> Result<usize, MapError> {
        let (v, n) = field(i)?;
        v.parse::<usize>()
            .ok()
            .filter(|&d| d > 0 && d <= 16_384)
            .ok_or_else(|| {
                err(
                    n,
                    format!("{} '{v}' is not a size in 1..=16384", HEADER_KEYS[i]),
                )
            })
    };
    let (h, w) = (dim(1)?, dim(2)?);
    crate::check_map_size(&stem(source), w, h)?;
    // The rows with their 1-based lines (blank lines are skipped).
    let rows: Vec<(usize, &str)> = lines
        .iter()
        .enumerate()
        .skip(body_at)
        .filter(|(_, r)| !r.trim().is_empty())
        .map(|(i, r)| (i + 1, r.trim_end()))
        .collect();
    if rows.len() != h {
        // At the first row too many, or after the last row there is.
        let at = match rows.get(h) {
            Some(&(n, _)) => n,
            None => rows.last().map_or(body_at, |&(n, _)| n),
        };
        return Err(err(
            at,
            format!("expected {h} rows after `map`, found {}", rows.len()),
        ));
    }
    let mut occupied = Vec::with_capacity(w * h);
    for (r, &(n, row)) in rows.iter().enumerate() {
        let cells = row.chars().count();
        if cells != w {
            return Err(err(n, format!("row {r} has {cells} cells, expected {w}")));
        }
        for (c, ch) in row.chars().enumerate() {
            match ch {
                '.' | 'G' | 'S' => occupied.push(false),
                '@' | 'O' | 'T' | 'W' => occupied.push(true),
                _ => return Err(err(n, format!("unknown cell '{ch}' at column {c}"))),
            }
        }
    }
    Ok(OccupancyMap {
        name: stem(source),
        width: w,
        height: h,
        cell: 1.0,
        origin: Point::origin(),
        occupied,
        y_down: true,
    })
}

/// Reads a `.scen` file's text: one scenario a line, its fields tab-separated (bucket, map,
/// map width, map height, start x, start y, goal x, goal y, optimal length), after an
/// optional line `version 1` (or `version 1.0`; any other version is refused). Blank lines
/// are skipped, and so is a byte-order mark starting the file or a line. Files joined with
/// `cat` read as one: a `version` line may stand on any line, and `version 1` and
/// `version 1.0` are the same version. The declared map size is
/// checked against the map by [`Scenario::check_map_size`].
pub fn read_scen(text: &str, source: &str) -> Result<Vec<Scenario>, MapError> {
    let err = |n: usize, p: String| format_err(source, Some(n), p);
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        // A byte-order mark: at the start of the file, or of a file joined after another.
        let line = line.strip_prefix('\u{feff}').unwrap_or(line);
        if line.trim().is_empty() {
            continue;
        }
        // The `movingai` crate skips every line that starts with `version`: read them here.
        if line.trim_start().starts_with("version") {
            let words: Vec<&str> = line.split_whitespace().collect();
            if !matches!(words.as_slice(), ["version", "1" | "1.0"]) {
                return Err(err(
                    n + 1,
                    format!(
                        "'{}': unknown version (MovingAI scenario files begin with `version 1` or `version 1.0`)",
                        line.trim()
                    ),
                ));
            }
            // `version 1` and `version 1.0` are the one version: files that say either may be
            // joined.
            continue;
        }
        let rec = ::movingai::parser::parse_scen(line).map_err(|e| err(n + 1, e.to_string()))?;
        for r in rec {
            if !(r.optimal_length.is_finite() && r.optimal_length >= 0.0) {
                return Err(err(
                    n + 1,
                    format!("optimal length {} is not a length", Num(r.optimal_length)),
                ));
            }
            // The map is read beside the file, by its file name: `.` or nothing names none.
            if std::path::Path::new(&r.map_file).file_name().is_none() {
                return Err(err(
                    n + 1,
                    format!("map '{}' names no map file", r.map_file.escape_debug()),
                ));
            }
            // A cell off the map the line declares is no scenario (it had been planned and
            // reported as a failed one).
            for (what, (x, y)) in [("start", r.start_pos), ("goal", r.goal_pos)] {
                if x >= r.map_width || y >= r.map_height {
                    return Err(err(
                        n + 1,
                        format!(
                            "{what} cell ({x}, {y}) is outside the {} x {} map the line declares",
                            r.map_width, r.map_height
                        ),
                    ));
                }
            }
            let c = |(x, y): (usize, usize)| Point::new(x as f64 + 0.5, y as f64 + 0.5);
            check_optimum(
                r.optimal_length,
                c(r.start_pos),
                c(r.goal_pos),
                r.map_width,
                r.map_height,
            )
            .map_err(|e| err(n + 1, e))?;
            out.push(Scenario {
                bucket: r.bucket,
                map: r.map_file,
                map_width: r.map_width,
                map_height: r.map_height,
                start: c(r.start_pos),
                goal: c(r.goal_pos),
                optimal_length: r.optimal_length,
                line: n + 1,
            });
        }
    }
    if out.is_empty() {
        return Err(format_err(source, None, "no scenarios"));
    }
    Ok(out)
}

/// An optimal length no 8-connected path between `start` and `goal` on a `w` x `h` map
/// can have is refused: one shorter than the straight line (less 1e-5 of it: files print
/// six digits, `1.41421`) or longer than a step of `sqrt 2` through every cell. Its ratio
/// was reported as 0 or as a number of 300 digits.
fn check_optimum(opt: f64, start: Point, goal: Point, w: usize, h: usize) -> Result<(), String> {
    let line = (goal - start).norm();
    let most = (w as f64) * (h as f64) * std::f64::consts::SQRT_2;
    if opt < line * (1.0 - 1e-5) {
        return Err(format!(
            "optimal length {} is shorter than the straight line {line:.4} from start to goal",
            Num(opt)
        ));
    }
    if opt > most {
        return Err(format!(
            "optimal length {} is longer than any path on the {w} x {h} map it declares (at most {most:.0})",
            Num(opt)
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map_err(text: &str) -> String {
        read_map(text, "m.map").unwrap_err().to_string()
    }

    #[test]
    fn map_header_errors_name_their_line() {
        let e = map_err("type hex\nheight 1\nwidth 2\nmap\n..\n");
        assert_eq!(
            e,
            "m.map:1: type 'hex' is not a MovingAI map type (octile, or 4-connected)"
        );
        // A field missing from the header is reported at the `map` line, by name.
        let e = map_err("height 1\nwidth 2\nmap\n..\n");
        assert_eq!(
            e,
            "m.map:3: missing `type` line in the header (it must come before `map`)"
        );
        let e = map_err("type octile\nheight 1\nwidth two\nmap\n..\n");
        assert_eq!(e, "m.map:3: width 'two' is not a size in 1..=16384");
        let e = map_err("type octile\nwidth 2\nheight 1\nwidth 3\nmap\n..\n");
        assert_eq!(e, "m.map:4: a second `width` line (the first is line 2)");
        let e = map_err("type octile\nheight 1\nwidth 2\n");
        assert_eq!(
            e,
            "m.map:3: no `map` line: the file ends in its header (not a MovingAI map?)"
        );
        assert_eq!(map_err("\n \n"), "m.map:1: empty file: not a MovingAI map");
        // Rows are counted by their own lines, blank lines between them included.
        let e = map_err("type octile\nheight 2\nwidth 2\nmap\n..\n\n.\n");
        assert_eq!(e, "m.map:7: row 1 has 1 cells, expected 2");
        let e = map_err("type octile\nheight 1\nwidth 2\nmap\n..\n..\n");
        assert_eq!(e, "m.map:6: expected 1 rows after `map`, found 2");
    }

    /// Our cells against the `movingai` crate's own notion of passable, not a list of
    /// characters: on the fixture maps a cell is blocked here exactly where the crate's
    /// `is_traversable` says no; and each cell character MovingAI defines is blocked here
    /// exactly where the crate's `is_traversable_from` says it cannot be entered from
    /// ground (`.`). The two differ on water (`W`), which `is_traversable` counts as
    /// traversable "in some situation" (from water) and which is never entered from ground:
    /// blocked here.
    #[test]
    fn maps_read_as_the_movingai_crate_reads_them() {
        use ::movingai::Map2D;
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures/maps/movingai/");
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .filter(|n| n.ends_with(".map"))
            .collect();
        names.sort();
        assert!(names.len() >= 8, "{names:?}");
        for name in &names {
            let text = std::fs::read_to_string(format!("{dir}{name}")).unwrap();
            let map = read_map(&text, name).unwrap();
            let theirs = ::movingai::parser::parse_map(&text).unwrap();
            assert_eq!((map.width, map.height), (theirs.width(), theirs.height()));
            assert_eq!(map.occupied.len(), theirs.coords().count());
            // Row-major, as `occupied`.
            for (k, c) in theirs.coords().enumerate() {
                assert_eq!(
                    map.occupied[k],
                    !theirs.is_traversable(c),
                    "{name}: cell {c:?} '{}'",
                    theirs.get(c)
                );
            }
            assert!(map.occupied.iter().any(|&o| o) && map.occupied.iter().any(|&o| !o));
        }
        // Every character MovingAI defines, each beside ground: blocked here exactly where
        // the crate says it cannot be entered from the ground beside it.
        let kinds = ".G@OTSW";
        let rows: String = kinds.chars().map(|ch| format!(".{ch}\n")).collect();
        let text = format!("type octile\nheight {}\nwidth 2\nmap\n{rows}", kinds.len());
        let map = read_map(&text, "kinds.map").unwrap();
        let theirs = ::movingai::parser::parse_map(&text).unwrap();
        for (j, ch) in kinds.chars().enumerate() {
            assert_eq!(*theirs.get((1, j)), ch);
            assert_eq!(
                map.occupied[2 * j + 1],
                !theirs.is_traversable_from((0, j), (1, j)),
                "'{ch}'"
            );
        }
        // `4-connected` and any case of `octile` read, as the crate reads them.
        for kind in ["4-connected", "Octile"] {
            let text = format!("type {kind}\nheight 1\nwidth 2\nmap\n.@\n");
            assert_eq!(read_map(&text, "m.map").unwrap().occupied, [false, true]);
        }
    }

    const LINE: &str = "0\troom.map\t32\t32\t1\t2\t3\t4\t5.0";

    fn scen_err(text: &str) -> String {
        read_scen(text, "s.scen").unwrap_err().to_string()
    }

    #[test]
    fn scenario_versions_other_than_1_are_refused_at_their_line() {
        for v in ["version 1", "version 1.0"] {
            let s = read_scen(&format!("{v}\n{LINE}\n"), "s.scen").unwrap();
            assert_eq!((s[0].map_width, s[0].map_height, s[0].line), (32, 32, 2));
        }
        // No version line: read as version 1.
        assert_eq!(read_scen(LINE, "s.scen").unwrap().len(), 1);
        for (text, at) in [
            (
                format!("version 2\n{LINE}\n"),
                "s.scen:1: 'version 2': unknown version",
            ),
            (
                format!("version\n{LINE}\n"),
                "s.scen:1: 'version': unknown version",
            ),
            (
                format!("version1\n{LINE}\n"),
                "s.scen:1: 'version1': unknown version",
            ),
            (
                format!("\nversion 1.1\n{LINE}\n"),
                "s.scen:2: 'version 1.1': unknown version",
            ),
            // Joined files: an unknown version is refused at its own line.
            (
                format!("version 1\n{LINE}\nversion 2\n{LINE}\n"),
                "s.scen:3: 'version 2': unknown version",
            ),
        ] {
            let e = scen_err(&text);
            assert!(e.starts_with(at), "{e}");
        }
    }

    #[test]
    fn an_optimum_no_path_can_have_is_refused() {
        // Start (11, 6), goal (7, 18): the straight line is 12.6491.
        for (opt, what) in [
            (
                "1e308",
                "optimal length 1e308 is longer than any path on the 32 x 32 map it declares (at most 1448)",
            ),
            (
                "1e-320",
                "optimal length 1e-320 is shorter than the straight line 12.6491 from start to goal",
            ),
            (
                "12.6",
                "optimal length 12.6 is shorter than the straight line",
            ),
        ] {
            let line = format!("3\tm.map\t32\t32\t11\t6\t7\t18\t{opt}");
            let e = read_scen(&format!("version 1\n{line}\n"), "s.scen")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("s.scen:2: ") && e.contains(what), "{e}");
        }
        // The straight line to six digits, the octile length and the longest path are lengths.
        for opt in ["12.6491", "12.649111", "14.0", "1448"] {
            let line = format!("3\tm.map\t32\t32\t11\t6\t7\t18\t{opt}");
            read_scen(&format!("{line}\n"), "s.scen").unwrap_or_else(|e| panic!("{opt}: {e}"));
        }
    }

    #[test]
    fn a_map_field_that_names_no_file_is_refused() {
        for map in [".", "..", "maps/.."] {
            let line = format!("0\t{map}\t32\t32\t1\t1\t3\t1\t2");
            let e = read_scen(&format!("version 1\n{line}\n"), "s.scen")
                .unwrap_err()
                .to_string();
            assert_eq!(e, format!("s.scen:2: map '{map}' names no map file"));
        }
    }

    #[test]
    fn a_start_or_goal_off_the_declared_map_is_refused() {
        for (line, what) in [
            (
                "0\tm.map\t32\t32\t32\t1\t3\t1\t2",
                "start cell (32, 1) is outside the 32 x 32 map",
            ),
            (
                "0\tm.map\t32\t32\t1\t1\t3\t40\t2",
                "goal cell (3, 40) is outside the 32 x 32 map",
            ),
        ] {
            let e = read_scen(&format!("version 1\n{line}\n"), "s.scen")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("s.scen:2: ") && e.contains(what), "{e}");
        }
    }

    #[test]
    fn the_version_may_follow_blank_lines_or_a_byte_order_mark() {
        for text in [
            format!("\n  \nversion 1\n{LINE}\n"),
            format!("\u{feff}version 1\n{LINE}\n"),
            format!("\u{feff}\nversion 1\n{LINE}\n"),
            format!("\u{feff}{LINE}\n"),
        ] {
            let s = read_scen(&text, "s.scen").unwrap_or_else(|e| panic!("{text:?}: {e}"));
            assert_eq!(s.len(), 1, "{text:?}");
            assert_eq!(s[0].map_width, 32);
        }
        assert_eq!(
            read_scen(&format!("\n\nversion 1\n{LINE}\n"), "s.scen").unwrap()[0].line,
            4
        );
    }

    #[test]
    fn files_joined_with_cat_read_when_their_versions_agree() {
        let one = format!("version 1\n{LINE}\n{LINE}\n");
        let two = format!("version 1\n{}\n", LINE.replace("5.0", "7.5"));
        // Joined as `cat` joins them, with a byte-order mark on the second, and with
        // the first missing its version line.
        for text in [
            format!("{one}{two}"),
            format!("{one}\u{feff}{two}"),
            format!("{LINE}\n{LINE}\n{two}"),
        ] {
            let s = read_scen(&text, "s.scen").unwrap_or_else(|e| panic!("{text:?}: {e}"));
            assert_eq!(s.len(), 3, "{text:?}");
            assert_eq!(s[2].optimal_length, 7.5);
        }
        assert_eq!(
            read_scen(&format!("{one}{two}"), "s.scen")
                .unwrap()
                .iter()
                .map(|s| s.line)
                .collect::<Vec<_>>(),
            [2, 3, 5]
        );
        // `version 1` joined with `version 1.0`: the one version, read.
        let s = read_scen(&format!("{one}version 1.0\n{LINE}\n"), "s.scen").unwrap();
        assert_eq!(s.len(), 3);
    }

    #[test]
    fn a_scenario_for_a_map_of_another_size_is_refused_at_its_line() {
        let text = format!(
            "version 1\n{LINE}\n\n{}\n",
            LINE.replace("32\t32", "64\t32")
        );
        let s = read_scen(&text, "s.scen").unwrap();
        assert!(s[0].check_map_size("s.scen", (32, 32), "room.map").is_ok());
        assert_eq!(
            s[1].check_map_size("s.scen", (32, 32), "room.map")
                .unwrap_err()
                .to_string(),
            "s.scen:4: map size: the line declares a 64 x 32 map (width x height), but its map room.map is 32 x 32: scaled maps are not supported (MovingAI would scale the map to 64 x 32)"
        );
    }
}
