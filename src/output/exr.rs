//! Linear radiance as OpenEXR: 32-bit float RGB, scanlines top row first,
//! written atomically like every output (encoded by the `image` crate).

use std::path::Path;

use crate::error::{Error, Result};

/// Whether `path` names an OpenEXR file (by its extension, any case).
pub fn is_exr_path(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
}

/// Writes `width` x `height` pixels of linear RGB (`rgb`: three f32 a pixel,
/// row-major, top row first) as a 32-bit float OpenEXR file at `path`.
pub fn write_exr_atomic(path: &Path, width: u32, height: u32, rgb: &[f32]) -> Result<()> {
    debug_assert_eq!(rgb.len(), width as usize * height as usize * 3);
    let mut bytes = std::io::Cursor::new(Vec::new());
    image::ImageEncoder::write_image(
        image::codecs::openexr::OpenExrEncoder::new(&mut bytes),
        bytemuck::cast_slice(rgb),
        width,
        height,
        image::ExtendedColorType::Rgb32F,
    )
    .map_err(|source| Error::Image {
        path: path.to_path_buf(),
        source,
    })?;
    super::write_file_atomic(path, bytes.get_ref())
}

/// Reads an OpenEXR file's RGB as f32 (for tests and comparisons).
pub fn read_exr_rgb(path: &Path) -> Result<(u32, u32, Vec<f32>)> {
    let img = image::open(path)
        .map_err(|source| Error::Image {
            path: path.to_path_buf(),
            source,
        })?
        .to_rgb32f();
    Ok((img.width(), img.height(), img.into_raw()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values far outside [0, 1], and tiny ones, come back bit for bit.
    #[test]
    fn radiance_round_trips_through_exr_exactly() {
        let dir = std::env::temp_dir().join(format!("kdray-exr-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("round.exr");
        let rgb: Vec<f32> = (0..4 * 3 * 3)
            .map(|i| (i as f32 - 5.0) * 37.25 + 1e-6 * i as f32)
            .collect();
        write_exr_atomic(&path, 4, 3, &rgb).unwrap();
        let (w, h, back) = read_exr_rgb(&path).unwrap();
        assert_eq!((w, h), (4, 3));
        assert_eq!(back, rgb);
        assert!(is_exr_path(Path::new("a/b.EXR")) && !is_exr_path(Path::new("a.png")));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
