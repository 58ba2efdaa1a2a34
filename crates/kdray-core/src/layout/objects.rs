//! The scene's objects as the kernel reads them: [`GpuSphere`],
//! [`GpuTriangle`], and a smooth triangle's packed vertex normals
//! ([`GpuTriangleNormals`], decoded by `decode_normal` in shaders/shade.wgsl).

use bytemuck::{Pod, Zeroable};

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuSphere {
    pub center: [f32; 3],
    pub radius: f32,
}

/// A triangle, 48 bytes: three vertices, and in the first vertex's padding
/// the index of its vertex normals in `triangle_normals` (smooth shading),
/// or [`GpuTriangle::FLAT`]; in the second's, its id in the scene's object
/// order (as `objects[i][1]`), which the walk's tie-break reads with the
/// vertices rather than with a load of its own; in the third's, its record
/// of texture coordinates in the `textures` buffer
/// ([`TextureWords`](crate::layout::TextureWords)), or
/// [`GpuTriangle::UNTEXTURED`] (read only by the TEXTURES kernel).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuTriangle {
    pub v0: [f32; 3],
    pub normals: u32,
    pub v1: [f32; 3],
    pub scene_id: u32,
    pub v2: [f32; 3],
    pub uvs: u32,
}

impl GpuTriangle {
    /// `normals` of a flat-shaded triangle: it has no vertex normals.
    pub const FLAT: u32 = u32::MAX;
    /// `uvs` of a triangle without texture coordinates.
    pub const UNTEXTURED: u32 = u32::MAX;
}

/// The unit vertex normals of a smooth-shaded triangle, 12 bytes: each
/// octahedral-encoded (Cigolle et al. 2014, "A Survey of Efficient
/// Representations for Independent Unit Vectors") in two 16-bit signed
/// normalised coordinates, x in the low half. The decoded normal is within
/// about 1e-4 rad of the original: far below what 8-bit shading can show.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Eq, Pod, Zeroable)]
pub struct GpuTriangleNormals {
    pub n0: u32,
    pub n1: u32,
    pub n2: u32,
}

/// The quantisation step of an octahedral coordinate: 1 / 32767.
const OCT_SCALE: f32 = 1.0 / 32767.0;

impl GpuTriangleNormals {
    /// Encodes three unit vectors (the host's f64 normals).
    pub fn pack(normals: [glam::DVec3; 3]) -> Self {
        let [n0, n1, n2] = normals.map(encode_octahedral);
        GpuTriangleNormals { n0, n1, n2 }
    }

    /// The three unit normals exactly as the kernel decodes them
    /// (`decode_normal` in shaders/shade.wgsl).
    pub fn unpack(&self) -> [glam::Vec3; 3] {
        [self.n0, self.n1, self.n2].map(decode_octahedral)
    }
}

/// A unit vector folded onto the octahedron |x| + |y| + |z| = 1 and its
/// lower half unfolded onto the square's corners, each coordinate rounded
/// to a 16-bit snorm (WGSL's pack2x16snorm layout).
fn encode_octahedral(n: glam::DVec3) -> u32 {
    let sign = |x: f64| if x >= 0.0 { 1.0 } else { -1.0 };
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    let (mut x, mut y) = if l1 > 0.0 {
        (n.x / l1, n.y / l1)
    } else {
        (0.0, 0.0)
    };
    if n.z < 0.0 {
        (x, y) = ((1.0 - y.abs()) * sign(x), (1.0 - x.abs()) * sign(y));
    }
    let snorm = |c: f64| ((c.clamp(-1.0, 1.0) * 32767.0).round() as i16) as u16 as u32;
    snorm(x) | (snorm(y) << 16)
}

/// Mirror of `decode_normal` in shaders/shade.wgsl, operation for operation.
fn decode_octahedral(w: u32) -> glam::Vec3 {
    let x = ((((w << 16) as i32) >> 16) as f32 * OCT_SCALE).max(-1.0);
    let y = (((w as i32) >> 16) as f32 * OCT_SCALE).max(-1.0);
    let mut n = glam::Vec3::new(x, y, 1.0 - x.abs() - y.abs());
    let fold = (-n.z).max(0.0);
    n.x += if n.x >= 0.0 { -fold } else { fold };
    n.y += if n.y >= 0.0 { -fold } else { fold };
    n.normalize()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Octahedral normals come back within 1e-4 rad of what went in, on
    /// every octant, the poles, the equator and the octahedron's edges.
    #[test]
    fn packed_normals_decode_within_1e_4_rad() {
        use glam::DVec3;
        // The six axis directions, and two on or just off the octahedron's edges.
        let mut normals: Vec<DVec3> = DVec3::AXES.iter().flat_map(|&a| [a, -a]).collect();
        normals.push(DVec3::new(1.0, 1.0, 0.0).normalize());
        normals.push(DVec3::new(-1.0, 1.0, -1e-9).normalize());
        // A spiral over the sphere (Fibonacci points).
        let n = 2000;
        for i in 0..n {
            let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
            let r = (1.0 - z * z).sqrt();
            let phi = i as f64 * 2.399_963_229_728_653;
            normals.push(DVec3::new(r * phi.cos(), r * phi.sin(), z));
        }
        let mut worst = 0.0f64;
        for pair in normals.chunks(3).filter(|c| c.len() == 3) {
            let packed = GpuTriangleNormals::pack([pair[0], pair[1], pair[2]]);
            for (original, decoded) in pair.iter().zip(packed.unpack()) {
                let angle = original.angle_between(decoded.as_dvec3());
                worst = worst.max(angle);
                assert!(
                    angle < 1e-4,
                    "{original} came back as {decoded} ({angle} rad)"
                );
                assert!((decoded.length() - 1.0).abs() < 1e-6);
            }
        }
        // Not trivially exact: the encoding does quantise.
        assert!(worst > 1e-6, "worst error {worst}");
    }
}
