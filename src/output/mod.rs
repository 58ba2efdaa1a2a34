//! Writing images: PNG, atomically (a temporary file in the same folder,
//! then a rename), so a failed run never leaves a half-written output.
//! Renders stream their rows into the `png` crate's encoder as they come
//! off the GPU ([`PngStream`]: memory holds one band, never the whole
//! image); images held in memory (screenshots, plots, heatmaps) are
//! encoded and read by the `image` crate. [`denoised`]: a path-traced
//! image's denoiser inputs, denoised and written with them.

pub mod denoised;
pub mod exr;
pub mod font;
pub mod heatmap;

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::error::{Error, Result};

/// An 8-bit RGB PNG being written row by row to a temporary file next to its
/// destination; `finish` renames it into place. Dropped unfinished, it
/// removes the temporary file and leaves the destination untouched.
pub struct PngStream {
    path: PathBuf,
    tmp: PathBuf,
    writer: Option<png::StreamWriter<'static, BufWriter<File>>>,
}

impl PngStream {
    pub fn create(path: &Path, width: u32, height: u32) -> Result<Self> {
        let tmp = temp_path_for(path)?;
        let file = File::create(&tmp)
            .map_err(|e| file_error(path, "cannot create a temporary file", e))?;
        let mut stream = PngStream {
            path: path.to_path_buf(),
            tmp,
            writer: None,
        };
        let mut encoder = png::Encoder::new(BufWriter::new(file), width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let writer = encoder
            .write_header()
            .and_then(|w| w.into_stream_writer())
            .map_err(|e| png_error(path, e))?;
        stream.writer = Some(writer);
        Ok(stream)
    }

    /// Appends whole rows (3 bytes per pixel), top to bottom.
    pub fn write_rows(&mut self, rgb: &[u8]) -> Result<()> {
        let writer = self
            .writer
            .as_mut()
            .ok_or_else(|| Error::Output("PNG stream already finished".into()))?;
        writer
            .write_all(rgb)
            .map_err(|e| file_error(&self.path, "cannot write", e))
    }

    /// Completes the file, flushes it to disk and renames it into place.
    pub fn finish(mut self) -> Result<()> {
        let writer = self
            .writer
            .take()
            .ok_or_else(|| Error::Output("PNG stream already finished".into()))?;
        writer.finish().map_err(|e| png_error(&self.path, e))?;
        File::open(&self.tmp)
            .and_then(|f| f.sync_all())
            .map_err(|e| file_error(&self.path, "cannot write", e))?;
        std::fs::rename(&self.tmp, &self.path)
            .map_err(|e| file_error(&self.path, "cannot rename the temporary file into place", e))
    }
}

impl Drop for PngStream {
    fn drop(&mut self) {
        if self.writer.is_some() || self.tmp.exists() {
            self.writer = None;
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// `.NAME.tmp-PID` in the folder of `path`: written first, then renamed over
/// `path`, so readers see the old file or the whole new one.
fn temp_path_for(path: &Path) -> Result<PathBuf> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let name = path
        .file_name()
        .ok_or_else(|| Error::Output(format!("{}: not a file name", path.display())))?;
    Ok(dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    )))
}

/// Writes `bytes` to `path` atomically (temporary file, flush to disk, rename).
pub fn write_file_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let tmp = temp_path_for(path)?;
    let result = (|| {
        let mut file = File::create(&tmp)
            .map_err(|e| file_error(path, "cannot create a temporary file", e))?;
        file.write_all(bytes)
            .map_err(|e| file_error(path, "cannot write", e))?;
        file.sync_all()
            .map_err(|e| file_error(path, "cannot write", e))?;
        std::fs::rename(&tmp, path)
            .map_err(|e| file_error(path, "cannot rename the temporary file into place", e))
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

fn file_error(path: &Path, what: &'static str, source: std::io::Error) -> Error {
    Error::File {
        path: path.to_path_buf(),
        what,
        source,
    }
}

fn png_error(path: &Path, source: png::EncodingError) -> Error {
    Error::Png {
        path: path.to_path_buf(),
        what: "cannot write",
        source,
    }
}

/// Writes an 8-bit RGB image held in memory (row-major, top row first) as a
/// PNG at `path`, atomically: screenshots, plots and heatmaps, encoded by
/// the `image` crate (big renders stream through [`PngStream`] instead).
pub fn write_png_atomic(path: &Path, width: u32, height: u32, rgb: &[u8]) -> Result<()> {
    let mut bytes = Vec::new();
    image::ImageEncoder::write_image(
        image::codecs::png::PngEncoder::new(&mut bytes),
        rgb,
        width,
        height,
        image::ExtendedColorType::Rgb8,
    )
    .map_err(|source| Error::Image {
        path: path.to_path_buf(),
        source,
    })?;
    write_file_atomic(path, &bytes)
}

/// Reads a PNG as 8-bit RGB (for tests and comparisons).
pub fn read_png_rgb(path: &Path) -> Result<(u32, u32, Vec<u8>)> {
    let img = image::open(path)
        .map_err(|source| Error::Image {
            path: path.to_path_buf(),
            source,
        })?
        .to_rgb8();
    Ok((img.width(), img.height(), img.into_raw()))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("kdray-output-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn streamed_rows_make_the_same_png_as_one_write() {
        let dir = temp_dir("stream");
        let (w, h) = (7u32, 5u32);
        let rgb: Vec<u8> = (0..w * h * 3).map(|i| (i * 37 % 251) as u8).collect();
        let mut stream = PngStream::create(&dir.join("a.png"), w, h).unwrap();
        for band in rgb.chunks(w as usize * 3 * 2) {
            stream.write_rows(band).unwrap();
        }
        stream.finish().unwrap();
        assert_eq!(read_png_rgb(&dir.join("a.png")).unwrap(), (w, h, rgb));
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary file left"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// A render that fails half-way leaves the previous output untouched.
    #[test]
    fn an_unfinished_stream_leaves_the_destination_untouched() {
        let dir = temp_dir("unfinished");
        let path = dir.join("out.png");
        std::fs::write(&path, b"previous").unwrap();
        let mut stream = PngStream::create(&path, 4, 4).unwrap();
        stream.write_rows(&[0; 4 * 3 * 2]).unwrap();
        drop(stream);
        assert_eq!(std::fs::read(&path).unwrap(), b"previous");
        assert_eq!(
            std::fs::read_dir(&dir).unwrap().count(),
            1,
            "no temporary file left"
        );
        std::fs::remove_dir_all(dir).unwrap();
    }
}
