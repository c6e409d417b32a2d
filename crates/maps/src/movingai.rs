//! MovingAI benchmark maps (`.map`) and scenarios (`.scen`), read with the `movingai` crate
//! after a line-by-line check that gives malformed files an error naming the line.
//!
//! Coordinates: one map unit per cell, x to the right, y down the file's rows; cell `(i, j)`
//! covers `[i, i + 1] x [j, j + 1]`; a scenario's cell `(sx, sy)` is the point
//! `(sx + 0.5, sy + 0.5)`. `.` `G` `S` are free; `@` `O` `T` `W` are blocked.

use homospline_geom::Point;

use crate::{MapError, OccupancyMap, stem};

/// One scenario of a `.scen` file.
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// Bucket.
    pub bucket: u32,
    /// The map file it names.
    pub map: String,
    /// Start, map coordinates (cell centre).
    pub start: Point,
    /// Goal, map coordinates (cell centre).
    pub goal: Point,
    /// The 8-connected (octile) optimal length given by the file.
    pub optimal_length: f64,
    /// Line of the file it was read from (1-based).
    pub line: usize,
}

fn format_err(source: &str, line: Option<usize>, problem: impl Into<String>) -> MapError {
    MapError::Format {
        source_name: source.to_owned(),
        line,
        problem: problem.into(),
    }
}

/// Reads a `.map` file's text.
pub fn read_map(text: &str, source: &str) -> Result<OccupancyMap, MapError> {
    let err = |line: Option<usize>, p: String| format_err(source, line, p);
    let lines: Vec<&str> = text.lines().collect();
    let mut header = std::collections::HashMap::new();
    let mut body_at = None;
    for (n, l) in lines.iter().enumerate() {
        let l = l.trim();
        if l == "map" {
            body_at = Some(n + 1);
            break;
        }
        let mut parts = l.split_whitespace();
        match (parts.next(), parts.next(), parts.next()) {
            (Some(k @ ("type" | "height" | "width")), Some(v), None) => {
                header.insert(k, (v, n + 1));
            }
            (None, _, _) => {}
            _ => {
                return Err(err(
                    Some(n + 1),
                    format!("expected `type`, `height`, `width` or `map`, got '{l}'"),
                ));
            }
        }
    }
    let body_at = body_at.ok_or_else(|| err(None, "no `map` line: not a MovingAI map".into()))?;
    let dim = |k: &str| -> Result<usize, MapError> {
        let (v, n) = header
            .get(k)
            .ok_or_else(|| err(None, format!("missing `{k}` line")))?;
        v.parse::<usize>()
            .ok()
            .filter(|&d| d > 0 && d <= 16_384)
            .ok_or_else(|| err(Some(*n), format!("{k} '{v}' is not a size in 1..=16384")))
    };
    let (w, h) = (dim("width")?, dim("height")?);
    let rows: Vec<&str> = lines[body_at..]
        .iter()
        .copied()
        .filter(|r| !r.trim().is_empty())
        .collect();
    if rows.len() != h {
        return Err(err(
            Some(body_at + rows.len().min(h)),
            format!("expected {h} rows after `map`, found {}", rows.len()),
        ));
    }
    for (r, row) in rows.iter().enumerate() {
        let n = body_at + r + 1;
        let row = row.trim_end();
        if row.chars().count() != w {
            return Err(err(
                Some(n),
                format!("row {r} has {} cells, expected {w}", row.chars().count()),
            ));
        }
        if let Some((c, ch)) = row
            .chars()
            .enumerate()
            .find(|(_, ch)| !matches!(ch, '.' | 'G' | 'S' | '@' | 'O' | 'T' | 'W'))
        {
            return Err(err(Some(n), format!("unknown cell '{ch}' at column {c}")));
        }
    }
    let parsed = ::movingai::parser::parse_map(text).map_err(|e| err(None, e.to_string()))?;
    use ::movingai::Map2D;
    let occupied = (0..h)
        .flat_map(|j| (0..w).map(move |i| (i, j)))
        .map(|(i, j)| matches!(parsed.get((i, j)), '@' | 'O' | 'T' | 'W'))
        .collect();
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

/// Reads a `.scen` file's text.
pub fn read_scen(text: &str, source: &str) -> Result<Vec<Scenario>, MapError> {
    let mut out = Vec::new();
    for (n, line) in text.lines().enumerate() {
        if n == 0 && line.starts_with("version") || line.trim().is_empty() {
            continue;
        }
        let rec = ::movingai::parser::parse_scen(line)
            .map_err(|e| format_err(source, Some(n + 1), e.to_string()))?;
        for r in rec {
            if !(r.optimal_length.is_finite() && r.optimal_length >= 0.0) {
                return Err(format_err(
                    source,
                    Some(n + 1),
                    format!("optimal length {} is not a length", r.optimal_length),
                ));
            }
            let c = |(x, y): (usize, usize)| Point::new(x as f64 + 0.5, y as f64 + 0.5);
            out.push(Scenario {
                bucket: r.bucket,
                map: r.map_file,
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
