//! PNG pictures (`--png`): the command's SVG rendered by resvg at twice its size, text in
//! the system's fonts.

use anyhow::Context;
use resvg::{tiny_skia, usvg};

/// Pixels per SVG unit in a PNG: 2 (an 800-unit figure is 1,600 pixels wide).
pub const PNG_SCALE: f32 = 2.0;

/// Families tried for `sans-serif`, in order.
const SANS_SERIF: [&str; 6] = [
    "DejaVu Sans",
    "Liberation Sans",
    "Noto Sans",
    "FreeSans",
    "Arial",
    "Helvetica",
];

/// A rendered picture: the PNG's bytes and its size in pixels.
pub struct Png {
    /// The encoded PNG.
    pub bytes: Vec<u8>,
    /// Width and height, pixels.
    pub size: (u32, u32),
    /// Whether a system font was found for the text (else the PNG has none).
    pub has_fonts: bool,
}

/// `svg` rendered at [`PNG_SCALE`] on a white page. Errors only if the SVG cannot be read
/// (ours always can) or its size is not a picture's.
pub fn render(svg: &str) -> anyhow::Result<Png> {
    let mut options = usvg::Options::default();
    let fonts = options.fontdb_mut();
    fonts.load_system_fonts();
    // Our pictures ask for `sans-serif`, which fontdb maps to Arial: take the first of the
    // common free families the system has, else any family it has.
    let families: Vec<String> = fonts
        .faces()
        .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
        .collect();
    let sans = SANS_SERIF
        .iter()
        .find(|want| families.iter().any(|f| f == *want))
        .map(|f| (*f).to_owned())
        .or_else(|| families.first().cloned());
    let has_fonts = sans.is_some();
    if let Some(family) = sans {
        fonts.set_sans_serif_family(family);
    }
    let tree = usvg::Tree::from_str(svg, &options).context("reading the picture to render it")?;
    let size = tree
        .size()
        .to_int_size()
        .scale_by(PNG_SCALE)
        .context("picture size")?;
    let mut pixmap = tiny_skia::Pixmap::new(size.width(), size.height())
        .with_context(|| format!("a picture of {} x {} pixels", size.width(), size.height()))?;
    pixmap.fill(tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        tiny_skia::Transform::from_scale(PNG_SCALE, PNG_SCALE),
        &mut pixmap.as_mut(),
    );
    let bytes = pixmap.encode_png().context("encoding the PNG")?;
    Ok(Png {
        bytes,
        size: (size.width(), size.height()),
        has_fonts,
    })
}

/// Renders `svg` and writes it to `path` as the `what` (a PNG), saying so on stderr, with a
/// note when no font was found.
pub fn write_png(path: &std::path::Path, what: &str, svg: &str) -> anyhow::Result<()> {
    let png = render(svg)?;
    crate::out::write(path, what, &png.bytes)?;
    say!(
        "{what}: {} ({} x {} pixels)",
        path.display(),
        png.size.0,
        png.size.1
    );
    if !png.has_fonts {
        say!(
            "note: no system font was found, so the PNG has no text; install one (Debian: fonts-dejavu-core)"
        );
    }
    Ok(())
}
