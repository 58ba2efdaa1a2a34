//! `[environment] image`: the sky as an equirectangular image of linear
//! radiance (Radiance HDR or OpenEXR), what rays that escape the scene see.
//!
//! Convention (as Mitsuba, Blender and three.js lay such images out): the
//! top row looks straight up (+y), the bottom row straight down; the
//! image's centre column looks along -z (where a camera at +z looking at
//! the origin looks), and u grows toward +x: a direction d is read at
//! u = 1/2 + atan2(d.x, -d.z) / 2 pi, v = acos(d.y) / pi, nearest texel.
//! `rotation` (degrees) turns the sky about +y, counter-clockwise seen from
//! above; `intensity` scales it.
//!
//! The path tracer samples the sky by its texels' luminance times sin(v pi)
//! (their solid angle): [`EnvironmentMap::sampling_tables`].

use glam::DVec3;

/// A decoded sky image and how it is placed.
#[derive(Debug, Clone, PartialEq)]
pub struct EnvironmentMap {
    /// The file name as the scene wrote it (relative to the scene's folder).
    pub path: String,
    pub width: u32,
    pub height: u32,
    /// Linear RGB radiance, row-major, top row first; finite, >= 0.
    pub texels: Vec<[f32; 3]>,
    /// >= 0, finite.
    pub intensity: f64,
    /// Degrees about +y, finite.
    pub rotation_degrees: f64,
}

/// Rec. 709 luminance of linear RGB.
pub fn luminance(c: [f32; 3]) -> f32 {
    0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]
}

impl EnvironmentMap {
    /// Decodes an HDR or EXR image (or any image the texture reader takes)
    /// into linear RGB: its width, height and texels. Refuses an image
    /// without pixels, and radiance that is negative or not finite, naming
    /// the first such texel.
    pub fn decode(bytes: &[u8]) -> Result<(u32, u32, Vec<[f32; 3]>), String> {
        let image = if is_other_radiance_header(bytes) {
            decode_radiance_leniently(bytes)
        } else {
            image::load_from_memory(bytes)
        }
        .map_err(|e| e.to_string())?;
        let rgb = image.into_rgb32f();
        let (width, height) = rgb.dimensions();
        if width == 0 || height == 0 {
            return Err("the image has no pixels".to_string());
        }
        let texels: Vec<[f32; 3]> = rgb.pixels().map(|p| p.0).collect();
        if let Some(i) = texels
            .iter()
            .position(|t| t.iter().any(|c| !c.is_finite() || *c < 0.0))
        {
            let (x, y) = (i as u32 % width, i as u32 / width);
            return Err(format!(
                "texel ({x}, {y}) is {:?}: radiance must be finite and >= 0",
                texels[i]
            ));
        }
        Ok((width, height, texels))
    }

    /// The texel (column, row) that direction `d` (unit) reads, rotation
    /// applied: the kernel's `environment_texel`, in f64.
    pub fn texel_of(&self, d: DVec3) -> (u32, u32) {
        let (s, c) = self.rotation_degrees.to_radians().sin_cos();
        // The sky turned by +rotation: look the direction up turned back.
        let x = c * d.x - s * d.z;
        let z = s * d.x + c * d.z;
        let u = 0.5 + x.atan2(-z) / std::f64::consts::TAU;
        let v = d.y.clamp(-1.0, 1.0).acos() / std::f64::consts::PI;
        let col = ((u * self.width as f64) as u32).min(self.width - 1);
        let row = ((v * self.height as f64) as u32).min(self.height - 1);
        (col, row)
    }

    /// The sky's radiance along `d` (unit), intensity applied.
    pub fn radiance(&self, d: DVec3) -> DVec3 {
        let (col, row) = self.texel_of(d);
        let t = self.texels[(row * self.width + col) as usize];
        DVec3::new(t[0] as f64, t[1] as f64, t[2] as f64) * self.intensity
    }

    /// Importance sampling's tables, each a cumulative distribution from 0
    /// to 1: the rows' (`height + 1` values; a row's weight is its texels'
    /// luminance sum times sin of its polar angle at the row's centre) and,
    /// row after row, each row's texels (`width + 1` values a row; a row of
    /// zero weight is uniform). A sky of zero luminance everywhere has a
    /// uniform table.
    pub fn sampling_tables(&self) -> (Vec<f32>, Vec<f32>) {
        let (w, h) = (self.width as usize, self.height as usize);
        let mut rows = Vec::with_capacity(h + 1);
        let mut columns = Vec::with_capacity(h * (w + 1));
        let mut row_weights = Vec::with_capacity(h);
        for r in 0..h {
            let sin = ((r as f64 + 0.5) / h as f64 * std::f64::consts::PI).sin();
            let texels = &self.texels[r * w..(r + 1) * w];
            let weights: Vec<f64> = texels.iter().map(|&t| luminance(t) as f64).collect();
            row_weights.push(weights.iter().sum::<f64>() * sin);
            push_cdf(&mut columns, &weights);
        }
        push_cdf(&mut rows, &row_weights);
        (rows, columns)
    }
}

/// A Radiance HDR whose first line names another program than RADIANCE:
/// `#?RGBE`, as Greg Ward's and Bruce Walter's RGBE writers (and stb's,
/// OpenCV's and Mitsuba's after them) write it. Radiance's own readers take
/// any `#?` line; the image crate's strict reader takes only `#?RADIANCE`.
fn is_other_radiance_header(bytes: &[u8]) -> bool {
    bytes.starts_with(b"#?") && !bytes.starts_with(image::codecs::hdr::SIGNATURE)
}

/// The lenient reader skips the `#?` line as a comment and reads the rest
/// as the strict one does.
fn decode_radiance_leniently(bytes: &[u8]) -> image::ImageResult<image::DynamicImage> {
    let decoder =
        image::codecs::hdr::HdrDecoder::with_strictness(std::io::Cursor::new(bytes), false)?;
    image::DynamicImage::from_decoder(decoder)
}

/// Appends the cumulative distribution of `weights` (len + 1 values from 0
/// to exactly 1; uniform where they sum to 0).
fn push_cdf(out: &mut Vec<f32>, weights: &[f64]) {
    let total: f64 = weights.iter().sum();
    out.push(0.0);
    let mut running = 0.0;
    for (i, &w) in weights.iter().enumerate() {
        running += if total > 0.0 {
            w / total
        } else {
            1.0 / weights.len() as f64
        };
        out.push(if i + 1 == weights.len() {
            1.0
        } else {
            running as f32
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sky(width: u32, height: u32, texels: Vec<[f32; 3]>, rotation: f64) -> EnvironmentMap {
        EnvironmentMap {
            path: "sky.hdr".into(),
            width,
            height,
            texels,
            intensity: 1.0,
            rotation_degrees: rotation,
        }
    }

    /// Up reads the top row, down the bottom; -z the centre column, +x the
    /// column three quarters across, +z the edge; turned by 90 degrees
    /// (counter-clockwise seen from above), the sky shows toward -x what it
    /// showed toward -z.
    #[test]
    fn directions_read_the_documented_texels() {
        let map = sky(8, 4, vec![[0.0; 3]; 32], 0.0);
        assert_eq!(map.texel_of(DVec3::Y).1, 0);
        assert_eq!(map.texel_of(-DVec3::Y).1, 3);
        assert_eq!(map.texel_of(-DVec3::Z), (4, 2));
        assert_eq!(map.texel_of(DVec3::X), (6, 2));
        assert_eq!(map.texel_of(-DVec3::X), (2, 2));
        // +z lies on the seam: the last column (u = 1) or the first.
        assert!(matches!(map.texel_of(DVec3::Z).0, 0 | 7));
        let turned = sky(8, 4, vec![[0.0; 3]; 32], 90.0);
        assert_eq!(turned.texel_of(-DVec3::X), map.texel_of(-DVec3::Z));
    }

    #[test]
    fn sampling_tables_follow_luminance_times_solid_angle() {
        // 4 x 2: one bright texel in the top row.
        let mut texels = vec![[0.0; 3]; 8];
        texels[1] = [1.0, 1.0, 1.0];
        let (rows, columns) = sky(4, 2, texels, 0.0).sampling_tables();
        assert_eq!(rows, vec![0.0, 1.0, 1.0]);
        assert_eq!(&columns[..5], &[0.0, 0.0, 1.0, 1.0, 1.0]);
        // The dark row is uniform.
        assert_eq!(&columns[5..], &[0.0, 0.25, 0.5, 0.75, 1.0]);
    }

    #[test]
    fn negative_or_non_finite_radiance_is_refused() {
        let mut bytes = std::io::Cursor::new(Vec::new());
        let img = image::Rgb32FImage::from_raw(2, 1, vec![1.0, 1.0, 1.0, -1.0, 0.0, 0.0]).unwrap();
        image::DynamicImage::ImageRgb32F(img)
            .write_to(&mut bytes, image::ImageFormat::OpenExr)
            .unwrap();
        let e = EnvironmentMap::decode(bytes.get_ref()).unwrap_err();
        assert!(e.contains("texel (1, 0)"), "{e}");
        assert!(EnvironmentMap::decode(b"#?RADIANCE\nnot really").is_err());
    }

    /// A 3 x 2 Radiance file with `program` on its first line, as RGBE
    /// writers lay it out: header, blank line, resolution, flat RGBE texels.
    fn radiance_file(program: &str) -> Vec<u8> {
        let mut bytes = format!(
            "#?{program}\n# written by hand\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n-Y 2 +X 3\n"
        )
        .into_bytes();
        for texel in [
            [128u8, 64, 32, 129],
            [0, 0, 0, 0],
            [200, 100, 50, 140],
            [255, 255, 255, 120],
            [10, 20, 30, 128],
            [128, 128, 128, 130],
        ] {
            bytes.extend_from_slice(&texel);
        }
        bytes
    }

    #[test]
    fn radiance_files_headed_rgbe_read_as_radiance_ones() {
        let (w, h, rgbe) = EnvironmentMap::decode(&radiance_file("RGBE")).unwrap();
        assert_eq!((w, h), (3, 2));
        let radiance = EnvironmentMap::decode(&radiance_file("RADIANCE")).unwrap();
        assert_eq!((w, h, rgbe.clone()), radiance);
        // A mantissa m with exponent e is m 2^(e - 136), within half a step
        // of m (readers differ on adding one half); black stays black.
        let near = |got: [f32; 3], want: [f32; 3]| {
            (0..3).all(|c| (got[c] - want[c]).abs() <= 0.01 * want[c].max(0.01))
        };
        assert!(near(rgbe[0], [1.0, 0.5, 0.25]), "{rgbe:?}");
        assert_eq!(rgbe[1], [0.0; 3]);
        assert!(near(rgbe[2], [3200.0, 1600.0, 800.0]), "{rgbe:?}");
        assert!(near(rgbe[5], [2.0, 2.0, 2.0]), "{rgbe:?}");
        // Another program's name is no excuse for a truncated file.
        let file = radiance_file("RGBE");
        assert!(EnvironmentMap::decode(&file[..file.len() - 5]).is_err());
    }
}
