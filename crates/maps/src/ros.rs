//! ROS map_server maps: the YAML (`image`, `resolution`, `origin`, `negate`,
//! `occupied_thresh`, `free_thresh`, `mode`) and its PGM or PNG image.
//!
//! Conversion as nav2's map_io: `p = value / 255`, `p = 1 - p` unless `negate`;
//! `p >= occupied_thresh` is occupied, `p <= free_thresh` free, anything between unknown.
//! Unknown cells are treated as occupied: a robot plans only through space known to be free.
//! Image row 0 is the top of the map; the world's y axis points up from `origin`. A rotated
//! origin (yaw != 0) is refused rather than silently ignored.

use homospline_geom::Point;
use homospline_geom::math::Num;
use serde::Deserialize;

use crate::{MapError, OccupancyMap, stem};

/// The map YAML.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RosMapYaml {
    /// Image file, relative to the YAML.
    pub image: String,
    /// Metres per cell.
    pub resolution: f64,
    /// Pose of the lower-left pixel: x, y, yaw.
    pub origin: [f64; 3],
    /// Whether white means occupied.
    #[serde(default)]
    pub negate: i32,
    /// Threshold for occupied.
    pub occupied_thresh: f64,
    /// Threshold for free.
    pub free_thresh: f64,
    /// `trinary` (default), `scale` or `raw`.
    #[serde(default)]
    pub mode: Option<String>,
}

fn err(source: &str, line: Option<usize>, problem: impl Into<String>) -> MapError {
    MapError::Format {
        source_name: source.to_owned(),
        line,
        problem: problem.into(),
    }
}

/// Reads and checks the YAML.
pub fn read_yaml(text: &str, source: &str) -> Result<RosMapYaml, MapError> {
    let y: RosMapYaml = homospline_geom::scene::from_yaml(text).map_err(|e| {
        // The key it sits under and the problem in words ("negate: expected a whole
        // number, got 'true'"), at its line.
        let e = homospline_geom::scene::yaml_error(text, &e, source, "malformed map YAML");
        let problem = match e.field {
            Some(k) => format!("{k}: {}", e.problem),
            None => e.problem,
        };
        err(source, e.line.map(|l| l as usize), problem)
    })?;
    // A cell below a nanometre is no map (1e-200 was read and planned into an empty path:
    // lengths underflowed). Large cells are refused by the map's extent (`read_map`).
    if !(y.resolution.is_finite() && y.resolution >= MIN_RESOLUTION) {
        return Err(err(
            source,
            None,
            format!(
                "resolution: must be a cell size of at least {MIN_RESOLUTION:e} metres, got {}",
                Num(y.resolution)
            ),
        ));
    }
    if !y.origin.iter().all(|v| v.is_finite()) {
        return Err(err(source, None, "origin: must be finite"));
    }
    if y.origin[2] != 0.0 {
        return Err(err(
            source,
            None,
            format!(
                "origin: yaw {} is not supported (rotate the map image instead)",
                y.origin[2]
            ),
        ));
    }
    if !(0.0..=1.0).contains(&y.free_thresh)
        || !(0.0..=1.0).contains(&y.occupied_thresh)
        || y.free_thresh >= y.occupied_thresh
    {
        return Err(err(
            source,
            None,
            format!(
                "free_thresh {} and occupied_thresh {} must satisfy 0 <= free < occupied <= 1",
                y.free_thresh, y.occupied_thresh
            ),
        ));
    }
    if !(y.negate == 0 || y.negate == 1) {
        return Err(err(
            source,
            None,
            format!("negate: must be 0 or 1, got {}", y.negate),
        ));
    }
    match y.mode.as_deref() {
        None | Some("trinary") | Some("scale") => {}
        Some(m) => {
            return Err(err(
                source,
                None,
                format!("mode: '{m}' is not supported (trinary or scale)"),
            ));
        }
    }
    Ok(y)
}

/// The least cell size accepted, metres.
pub const MIN_RESOLUTION: f64 = 1e-9;

/// The map from its YAML and the image's bytes (`image_source` names it in errors).
pub fn read_map(
    yaml: &RosMapYaml,
    yaml_source: &str,
    image: &[u8],
    image_source: &str,
) -> Result<OccupancyMap, MapError> {
    let cannot =
        |e: image::ImageError| err(image_source, None, format!("cannot decode the image: {e}"));
    // The size from the image's header, refused before its pixels are decoded (a 20000^2
    // image took a gigabyte before it was refused).
    let decoder = image::ImageReader::new(std::io::Cursor::new(image))
        .with_guessed_format()
        .map_err(|e| cannot(e.into()))?
        .into_decoder()
        .map_err(cannot)?;
    let (w, h) = image::ImageDecoder::dimensions(&decoder);
    crate::check_map_size(&stem(yaml_source), w as usize, h as usize)?;
    let gray = image::DynamicImage::from_decoder(decoder)
        .map_err(cannot)?
        .to_luma8();
    let (w, h) = (gray.width() as usize, gray.height() as usize);
    if w == 0 || h == 0 {
        return Err(err(
            image_source,
            None,
            format!("image size {w} x {h} is not supported"),
        ));
    }
    // As for a scene's coordinates: far beyond any map, and small enough for the planner's
    // arithmetic (a resolution of 1e300 hung it, 1e9 asked for 104 GB of path samples).
    let extent = yaml.resolution * w.max(h) as f64;
    let far = yaml.origin[0].abs().max(yaml.origin[1].abs()) + extent;
    if far.is_nan() || far > homospline_geom::scene::MAX_MAGNITUDE {
        return Err(err(
            yaml_source,
            None,
            format!(
                "{}: {} m per cell over {} x {} cells from origin [{}, {}] reaches {far:e}; coordinates must stay within {:e}",
                // The field at fault: the origin when it alone is too far, else the resolution.
                if far - extent > homospline_geom::scene::MAX_MAGNITUDE {
                    "origin"
                } else {
                    "resolution"
                },
                Num(yaml.resolution),
                w,
                h,
                Num(yaml.origin[0]),
                Num(yaml.origin[1]),
                homospline_geom::scene::MAX_MAGNITUDE
            ),
        ));
    }
    let mut occupied = vec![true; w * h];
    for (col, row, px) in gray.enumerate_pixels() {
        let mut p = px.0[0] as f64 / 255.0;
        if yaml.negate == 0 {
            p = 1.0 - p;
        }
        let free = p <= yaml.free_thresh;
        let j = h - 1 - row as usize;
        occupied[j * w + col as usize] = !free;
    }
    Ok(OccupancyMap {
        name: stem(yaml_source),
        width: w,
        height: h,
        cell: yaml.resolution,
        origin: Point::new(yaml.origin[0], yaml.origin[1]),
        occupied,
        y_down: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_resolution_below_a_nanometre_is_refused() {
        for r in ["1e-200", "0", "-0.05", ".nan", ".inf"] {
            let text = format!(
                "image: m.pgm\nresolution: {r}\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
            );
            let e = read_yaml(&text, "m.yaml").unwrap_err().to_string();
            assert!(e.contains("resolution: must be a cell size"), "{r}: {e}");
        }
        let ok = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
        assert!(read_yaml(ok, "m.yaml").is_ok());
    }
}
