//! The GPU data layout: `#[repr(C)]` Pod types that mirror the structs of
//! shaders/types.wgsl byte for byte, and [`SceneArrays`], a scene and its
//! tree flattened into them. A unit test checks every size and field
//! offset against naga's layout of the WGSL declarations.
//!
//! WGSL's `vec3<f32>` is 16-byte aligned, so each `[f32; 3]` is followed by a
//! 4-byte field (a scalar that belongs with it, or explicit padding).

mod scene_arrays;
mod texture_words;
pub use scene_arrays::{EnvironmentWords, SceneArrays};
pub use texture_words::{Records, TextureWords};

use bytemuck::{Pod, Zeroable};

/// A k-d tree node, 16 bytes, as the build writes it and the CPU walks read
/// it (the kernel reads [`GpuKdNode`]). Nodes are stored depth first: an
/// inner node's left ("below the plane") child is the next node.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct KdNode {
    /// 0, 1, 2: inner node splitting on x, y, z; [`KdNode::LEAF`]: leaf.
    pub kind: u32,
    /// Inner: the plane's coordinate on axis `kind`. Leaf: unused (0).
    pub split: f32,
    /// Inner: index of the right ("above the plane") child.
    /// Leaf: index of its first object id in the leaf-object list.
    pub index: u32,
    /// Leaf: number of object ids. Inner: 0.
    pub count: u32,
}

impl KdNode {
    pub const LEAF: u32 = 3;

    pub fn is_leaf(&self) -> bool {
        self.kind == Self::LEAF
    }
}

/// A k-d tree node as the kernel reads it, 8 bytes: the same node as a
/// [`KdNode`] in half the space (the layout of Wald's thesis, 2004). The
/// kind sits in the low 2 bits of `tag_and_index`, and above it an inner
/// node's above-child index or a leaf's object count; `split_or_first` is
/// an inner node's plane (its f32 bits) or a leaf's first entry in the
/// leaf-object list. A descent step loads two words instead of four:
/// measured on lavapipe, 11% off the bunny's frame and 12% off the gears'
/// (docs/benchmarks.md). Unpacked by `unpack_kd_node` in
/// shaders/chunks.wgsl, which [`GpuKdNode::unpack`] mirrors.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuKdNode {
    pub tag_and_index: u32,
    pub split_or_first: u32,
}

impl GpuKdNode {
    /// The largest child index or leaf count the 30 bits above the kind
    /// hold: a tree of more nodes, or with more leaf references, cannot be
    /// packed (`SceneArrays::check_fits` refuses it).
    pub const MAX_INDEX: u32 = (1 << 30) - 1;

    /// `n` packed; its index (inner) or count (leaf) must be at most
    /// [`GpuKdNode::MAX_INDEX`], and a leaf's `split` and an inner node's
    /// `count` must be 0 (as the build writes them) for `unpack` to give
    /// `n` back.
    pub fn pack(n: &KdNode) -> Self {
        let (above, low) = if n.is_leaf() {
            (n.count, n.index)
        } else {
            (n.index, n.split.to_bits())
        };
        GpuKdNode {
            tag_and_index: n.kind | (above << 2),
            split_or_first: low,
        }
    }

    /// The node `pack` was given, as the kernel's `unpack_kd_node` reads it.
    pub fn unpack(&self) -> KdNode {
        let kind = self.tag_and_index & 3;
        let above = self.tag_and_index >> 2;
        if kind == KdNode::LEAF {
            KdNode {
                kind,
                split: 0.0,
                index: self.split_or_first,
                count: above,
            }
        } else {
            KdNode {
                kind,
                split: f32::from_bits(self.split_or_first),
                index: above,
                count: 0,
            }
        }
    }
}

/// A leaf's box and its six ropes (Popov et al. 2007), 48 bytes: the rope
/// walk's per-leaf data (`kdtree::ropes`). Face `2 * axis` is the box's
/// low side on that axis, `2 * axis + 1` its high side; a ray leaves through
/// face `2 * axis + (dir[axis] > 0)`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct LeafRopes {
    /// The plane coordinate of each face (min x, max x, min y, max y, min z,
    /// max z); on the scene's boundary -inf for a low face and +inf for a
    /// high one, so that a ray never meets it (the rope walk then needs no
    /// rope to see that it has none).
    pub faces: [f32; 6],
    /// The node beyond each face: the smallest one whose cell holds the
    /// whole face strictly inside its planes; [`LeafRopes::NONE`] on the
    /// scene's boundary.
    pub ropes: [u32; 6],
}

impl LeafRopes {
    pub const NONE: u32 = u32::MAX;
}

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
/// of texture coordinates in the `textures` buffer ([`TextureWords`]), or
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

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuMaterial {
    pub ambient: [f32; 3],
    pub shininess: f32,
    pub diffuse: [f32; 3],
    pub reflection: f32,
    pub specular: [f32; 3],
    /// 0 opaque .. 1 clear; read only by the glass variant of the kernel.
    pub transmission: f32,
    /// Index of refraction of the inside (the outside is 1).
    pub ior: f32,
    /// Its base-colour texture in the `textures` buffer, or
    /// [`GpuMaterial::NO_TEXTURE`].
    pub texture: u32,
    /// glTF's metallic and perceptual roughness, read by the path tracer
    /// where `model` is [`MODEL_METAL_ROUGH`].
    pub metallic: f32,
    pub roughness: f32,
    /// Emitted radiance (the path tracer's lights).
    pub emission: [f32; 3],
    /// [`MODEL_LAMBERTIAN`] or [`MODEL_METAL_ROUGH`]: how the path tracer
    /// reads `diffuse`.
    pub model: u32,
    /// The path tracer's maps in the `textures` buffer, each or
    /// [`GpuMaterial::NO_TEXTURE`]: metallic-roughness (blue, green),
    /// emissive, and the tangent-space normal map with its x-y scale.
    pub metal_rough_texture: u32,
    pub emissive_texture: u32,
    pub normal_texture: u32,
    pub normal_scale: f32,
    /// [`ALPHA_OPAQUE`], [`ALPHA_MASK`] or [`ALPHA_BLEND`]: whether the
    /// walks' alpha test (shaders/alpha.wgsl) reads this material.
    pub alpha_mode: u32,
    /// Alpha below this is a hole (MASK; BLEND outside the path tracer).
    pub alpha_cutoff: f32,
    /// The constant alpha, times the base-colour texture's where textured.
    pub alpha_factor: f32,
    /// The Whitted integrator's occlusion map (red darkens the ambient
    /// term), or [`GpuMaterial::NO_TEXTURE`], and its strength in [0, 1].
    pub occlusion_texture: u32,
    pub occlusion_strength: f32,
    /// The slots ([`UV_SLOT_BASE`] ...) that read the second channel of
    /// texture coordinates.
    pub uv_channels: u32,
    /// 1: an emitting triangle emits from both sides; 0: its front only.
    pub two_sided: u32,
    pub _pad2: u32,
}

impl GpuMaterial {
    /// `texture` of a material without one.
    pub const NO_TEXTURE: u32 = u32::MAX;
}

/// `GpuMaterial::alpha_mode`: alpha ignored, the surface everywhere.
pub const ALPHA_OPAQUE: u32 = 0;
/// `GpuMaterial::alpha_mode`: alpha below `alpha_cutoff` is a hole.
pub const ALPHA_MASK: u32 = 1;
/// `GpuMaterial::alpha_mode`: a ray passes with probability 1 - alpha in
/// the path tracer; elsewhere as [`ALPHA_MASK`].
pub const ALPHA_BLEND: u32 = 2;

/// `GpuMaterial::model`: `diffuse` is a Lambertian albedo.
pub const MODEL_LAMBERTIAN: u32 = 0;
/// `GpuMaterial::model`: glTF 2.0's metal/rough BRDF with base colour `diffuse`.
pub const MODEL_METAL_ROUGH: u32 = 1;

/// `GpuMaterial::uv_channels` (and [`crate::scene::MaterialMaps::second_uv`]):
/// the texture slots that read a triangle's second channel of texture
/// coordinates; the others read the first.
pub const UV_SLOT_BASE: u32 = 1;
pub const UV_SLOT_METAL_ROUGH: u32 = 2;
pub const UV_SLOT_NORMAL: u32 = 4;
pub const UV_SLOT_EMISSIVE: u32 = 8;
pub const UV_SLOT_OCCLUSION: u32 = 16;

#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct GpuLight {
    pub position: [f32; 3],
    /// [`LIGHT_POINT`], [`LIGHT_SPOT`], [`LIGHT_DIRECTIONAL`], or
    /// [`LIGHT_EMITTER`]: an emissive object, `object`, whose radiance is
    /// `diffuse` (the path tracer samples it).
    pub kind: u32,
    pub ambient: [f32; 3],
    /// An emitter's GPU object id.
    pub object: u32,
    pub diffuse: [f32; 3],
    /// A spot light: the cosine of its outer cone's half-angle.
    pub cos_outer: f32,
    pub specular: [f32; 3],
    /// A spot light: 1 / max(cos inner - cos outer, 0.001), the falloff's
    /// slope (`scene::spot_factor`).
    pub spot_scale: f32,
    /// A spot light's axis, a directional light's travel: unit.
    pub direction: [f32; 3],
    /// A point or spot light: the path tracer's radiant intensity is
    /// `diffuse * path_scale` (`scene::Light::path_intensity_scale`).
    pub path_scale: f32,
}

/// `GpuLight::kind`: a point light of the scene's `[[lights]]`.
pub const LIGHT_POINT: u32 = 0;
/// `GpuLight::kind`: an object whose material emits. The lights buffer
/// holds the scene's lights first, then the emitters.
pub const LIGHT_EMITTER: u32 = 1;
/// `GpuLight::kind`: a spot light of the scene's `[[lights]]`.
pub const LIGHT_SPOT: u32 = 2;
/// `GpuLight::kind`: a directional light of the scene's `[[lights]]`.
pub const LIGHT_DIRECTIONAL: u32 = 3;

/// `FrameParams::integrator` values.
pub const INTEGRATOR_WHITTED: u32 = 0;
pub const INTEGRATOR_PATH: u32 = 1;

/// `FrameParams::accel` values.
pub const ACCEL_KDTREE: u32 = 0;
pub const ACCEL_BRUTE: u32 = 1;
/// `FrameParams::traversal` values (`kdtree::Traversal`).
pub const TRAVERSAL_RESTART: u32 = 0;
pub const TRAVERSAL_ROPES: u32 = 1;
pub const TRAVERSAL_SHORT_STACK: u32 = 2;
/// The glass path's stack: at most this many rays wait while a sample
/// follows another (shaders/glass.wgsl; docs/scene-format.md says how).
pub const GLASS_STACK_DEPTH: u32 = 4;
/// A shadow ray through glass passes at most this many transmissive
/// surfaces; one that would pass more counts as blocked.
pub const SHADOW_CROSSINGS: u32 = 8;
/// `FrameParams::shadow_mode` values.
pub const SHADOW_AMBIENT: u32 = 0;
pub const SHADOW_SEED: u32 = 1;

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

    proptest::proptest! {
        /// Packing keeps every field the kernel reads: an inner node's
        /// axis, plane bits (negative zero, subnormals, infinities) and
        /// child index up to the 30-bit limit; a leaf's first entry (any
        /// u32) and count up to the limit.
        #[test]
        fn packed_nodes_unpack_to_the_same_node(
            axis in 0u32..3,
            split_bits in proptest::prelude::any::<u32>(),
            index in 0..=GpuKdNode::MAX_INDEX,
            first in proptest::prelude::any::<u32>(),
        ) {
            let split = f32::from_bits(split_bits);
            let inner = KdNode { kind: axis, split, index, count: 0 };
            let back = GpuKdNode::pack(&inner).unpack();
            proptest::prop_assert_eq!((back.kind, back.split.to_bits(), back.index, back.count),
                (axis, split_bits, index, 0));
            let leaf = KdNode { kind: KdNode::LEAF, split: 0.0, index: first, count: index };
            proptest::prop_assert_eq!(GpuKdNode::pack(&leaf).unpack(), leaf);
        }
    }

    #[test]
    fn the_packing_limits_are_30_bits() {
        let top = KdNode {
            kind: 2,
            split: -1.5,
            index: GpuKdNode::MAX_INDEX,
            count: 0,
        };
        assert_eq!(GpuKdNode::pack(&top).tag_and_index, u32::MAX - 1);
        let leaf = KdNode {
            kind: KdNode::LEAF,
            split: 0.0,
            index: u32::MAX,
            count: GpuKdNode::MAX_INDEX,
        };
        assert_eq!(GpuKdNode::pack(&leaf).tag_and_index, u32::MAX);
    }
}
