//! ROS map_server maps: the YAML (`image`, `resolution`, `origin`, `negate`,
//! `occupied_thresh`, `free_thresh`, `mode`) and its PGM or PNG image.
//!
//! Conversion as nav2's map_io (`loadMapFromFile`): a pixel's shade is the plain mean of its
//! red, green and blue (a grey pixel's value), and, in `trinary` mode of an image with an
//! alpha channel, its alpha too (255 opaque); `p = 1 - shade / 255` unless `negate`
//! (`p = shade / 255`). `p > occupied_thresh` is occupied, `p < free_thresh` free, anything
//! between unknown; in `scale` mode a pixel that is not opaque is unknown. Unknown cells are
//! treated as occupied: a robot plans only through space known to be free. 16-bit images
//! are read at 8 bits.
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

/// The 1-based line of top-level `key` in a map YAML (`key:` at the start of a line), for
/// the checks made after reading.
fn line_of(text: &str, key: &str) -> Option<usize> {
    text.lines()
        .position(|l| {
            l.strip_prefix(key)
                .is_some_and(|r| r.trim_start().starts_with(':'))
        })
        .map(|i| i + 1)
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
            line_of(text, "resolution"),
            format!(
                "resolution: must be a cell size of at least {MIN_RESOLUTION:e} metres, got {}",
                Num(y.resolution)
            ),
        ));
    }
    if !y.origin.iter().all(|v| v.is_finite()) {
        return Err(err(
            source,
            line_of(text, "origin"),
            "origin: must be finite",
        ));
    }
    if y.origin[2] != 0.0 {
        return Err(err(
            source,
            line_of(text, "origin"),
            format!(
                "origin: yaw {} is not supported (rotate the map image instead)",
                Num(y.origin[2])
            ),
        ));
    }
    if !(0.0..=1.0).contains(&y.free_thresh)
        || !(0.0..=1.0).contains(&y.occupied_thresh)
        || y.free_thresh >= y.occupied_thresh
    {
        return Err(err(
            source,
            line_of(text, "free_thresh"),
            format!(
                "free_thresh {} and occupied_thresh {} must satisfy 0 <= free < occupied <= 1",
                y.free_thresh, y.occupied_thresh
            ),
        ));
    }
    if !(y.negate == 0 || y.negate == 1) {
        return Err(err(
            source,
            line_of(text, "negate"),
            format!("negate: must be 0 or 1, got {}", y.negate),
        ));
    }
    match y.mode.as_deref() {
        None | Some("trinary") | Some("scale") => {}
        Some(m) => {
            return Err(err(
                source,
                line_of(text, "mode"),
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
    let img = image::DynamicImage::from_decoder(decoder).map_err(cannot)?;
    let has_alpha = img.color().has_alpha();
    let (w, h) = (img.width() as usize, img.height() as usize);
    if w == 0 || h == 0 {
        return Err(err(
            image_source,
            None,
            format!("image size {w} x {h} is not supported"),
        ));
    }
    crate::check_geometry(yaml.resolution, [yaml.origin[0], yaml.origin[1]], w, h)
        .map_err(|(field, problem)| err(yaml_source, None, format!("{field}: {problem}")))?;
    let scale = yaml.mode.as_deref() == Some("scale");
    let mut occupied = vec![true; w * h];
    for (col, row, px) in image::GenericImageView::pixels(&img) {
        let [r, g, b, a] = px.0;
        let free = if scale && a != 255 {
            false
        } else {
            pixel_is_free(
                [r, g, b],
                (has_alpha && !scale).then_some(a),
                yaml.negate != 0,
                yaml.free_thresh,
            )
        };
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

/// Whether nav2 reads a pixel free: the mean of its colour channels (and its alpha, when
/// given: trinary mode of an image with an alpha channel) as the shade, `p = 1 - shade`
/// (`shade` with `negate`), free when `p < free_thresh`.
fn pixel_is_free(rgb: [u8; 3], alpha: Option<u8>, negate: bool, free_thresh: f64) -> bool {
    let (sum, n) = rgb
        .iter()
        .chain(alpha.iter())
        .fold((0u32, 0u32), |(s, n), &c| (s + c as u32, n + 1));
    let shade = sum as f64 / n as f64 / 255.0;
    let p = if negate { shade } else { 1.0 - shade };
    p < free_thresh
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 3 x 1 map YAML and PNG bytes of `pixels` (RGBA, or RGB when `alpha` is false).
    fn png_map(pixels: &[[u8; 4]], alpha: bool, mode: &str) -> OccupancyMap {
        let (w, h) = (pixels.len() as u32, 1);
        let mut bytes = Vec::new();
        let enc = image::codecs::png::PngEncoder::new(&mut bytes);
        let (raw, ty): (Vec<u8>, _) = if alpha {
            (
                pixels.iter().flatten().copied().collect(),
                image::ExtendedColorType::Rgba8,
            )
        } else {
            (
                pixels.iter().flat_map(|p| [p[0], p[1], p[2]]).collect(),
                image::ExtendedColorType::Rgb8,
            )
        };
        image::ImageEncoder::write_image(enc, &raw, w, h, ty).unwrap();
        let yaml = read_yaml(
            &format!(
                "image: m.png\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: {mode}\n"
            ),
            "m.yaml",
        )
        .unwrap();
        read_map(&yaml, "m.yaml", &bytes, "m.png").unwrap()
    }

    #[test]
    fn colour_pixels_are_the_mean_of_their_channels_as_nav2_reads_them() {
        // (255, 255, 100): mean 203.3, p = 0.203 >= 0.196: unknown (a luminance weighting
        // read 237 and freed it). (255, 180, 255): mean 230, p = 0.098: free. White: free.
        let m = png_map(
            &[
                [255, 255, 100, 255],
                [255, 180, 255, 255],
                [255, 255, 255, 255],
            ],
            false,
            "trinary",
        );
        assert_eq!(m.occupied, vec![true, false, false]);
    }

    #[test]
    fn alpha_counts_in_trinary_mode_and_is_unknown_in_scale_mode() {
        // Transparent light grey: trinary mean (250 * 3 + 0) / 4 = 187.5, p = 0.26: unknown
        // (dropping alpha freed it). Opaque white: free. Half-transparent white in scale
        // mode: not opaque, unknown; opaque white in scale mode: free.
        let m = png_map(&[[250, 250, 250, 0], [255, 255, 255, 255]], true, "trinary");
        assert_eq!(m.occupied, vec![true, false]);
        let m = png_map(&[[255, 255, 255, 128], [255, 255, 255, 255]], true, "scale");
        assert_eq!(m.occupied, vec![true, false]);
    }

    #[test]
    fn free_is_strictly_below_the_threshold() {
        // 255 * (1 - 0.196) = 205.02: 205 reads p = 0.196078..., not below 0.196.
        assert!(!pixel_is_free([205, 205, 205], None, false, 0.196));
        assert!(pixel_is_free([206, 206, 206], None, false, 0.196));
        assert!(pixel_is_free([10, 10, 10], None, true, 0.196));
    }

    #[test]
    fn a_resolution_below_a_nanometre_is_refused() {
        for r in ["1e-200", "0", "-0.05", ".nan", ".inf"] {
            let text = format!(
                "image: m.pgm\nresolution: {r}\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n"
            );
            let e = read_yaml(&text, "m.yaml").unwrap_err().to_string();
            assert!(
                e.starts_with("m.yaml:2: resolution: must be a cell size"),
                "{r}: {e}"
            );
        }
        let ok = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
        assert!(read_yaml(ok, "m.yaml").is_ok());
    }

    #[test]
    fn a_yaw_is_refused_with_its_value_written_short() {
        // 1e-300 was written out with 300 digits.
        let text = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 1e-300]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
        let e = read_yaml(text, "m.yaml").unwrap_err().to_string();
        assert!(
            e.contains(
                "m.yaml:3: origin: yaw 1e-300 is not supported (rotate the map image instead)"
            ),
            "{e}"
        );
    }

    #[test]
    fn a_value_refused_after_reading_is_blamed_at_its_line() {
        let base = "image: m.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
        for (from, to, want) in [
            (
                "free_thresh: 0.196",
                "free_thresh: 0.9",
                "m.yaml:6: free_thresh 0.9",
            ),
            ("negate: 0", "negate: 2", "m.yaml:4: negate: must be 0 or 1"),
            (
                "origin: [0, 0, 0]",
                "origin: [.nan, 0, 0]",
                "m.yaml:3: origin: must be finite",
            ),
        ] {
            let e = read_yaml(&base.replace(from, to), "m.yaml")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with(want), "{to}: {e}");
        }
        let moded = format!("{base}mode: raw\n");
        let e = read_yaml(&moded, "m.yaml").unwrap_err().to_string();
        assert!(
            e.starts_with("m.yaml:7: mode: 'raw' is not supported"),
            "{e}"
        );
    }
}
