//! Writing images: PNG, atomically (a temporary file in the same folder,
//! then a rename), so a failed run never leaves a half-written output.

use std::path::Path;

use crate::error::{Error, Result};

/// Writes 8-bit RGB pixels (row-major, top row first) as a PNG at `path`.
pub fn write_png_atomic(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    let fail = |what: &str, e: &dyn std::fmt::Display| {
        Error::Output(format!("{}: {what}: {e}", path.display()))
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| Error::Output(format!("{}: not a file name", path.display())))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| {
        let file =
            std::fs::File::create(&tmp).map_err(|e| fail("cannot create a temporary file", &e))?;
        let mut writer = std::io::BufWriter::new(file);
        let encoder = image::codecs::png::PngEncoder::new(&mut writer);
        image::ImageEncoder::write_image(
            encoder,
            rgb,
            width,
            height,
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| fail("cannot encode PNG", &e))?;
        let file = writer
            .into_inner()
            .map_err(|e| fail("cannot write", &e.error().to_string()))?;
        file.sync_all().map_err(|e| fail("cannot write", &e))?;
        std::fs::rename(&tmp, path)
            .map_err(|e| fail("cannot rename the temporary file into place", &e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// Reads a PNG as 8-bit RGB (for tests and comparisons).
pub fn read_png_rgb(path: &Path) -> Result<(u32, u32, Vec<u8>)> {
    let img = image::open(path)
        .map_err(|e| Error::Output(format!("{}: {e}", path.display())))?
        .to_rgb8();
    Ok((img.width(), img.height(), img.into_raw()))
}
