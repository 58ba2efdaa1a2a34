//! The host-shader layout checked from the WGSL side: every `#[repr(C)]`
//! type of `kdray_core::layout` has the size, member offsets and member types
//! of the WGSL struct of the same name, as naga reads the kernel.

use super::kernel_io::*;
use kdray_core::layout::light_tree::GpuLightNode;
use kdray_core::layout::*;

/// The WGSL type a Rust field stands for.
trait WgslField {
    fn matches(inner: &naga::TypeInner) -> bool;
}

fn is_scalar(inner: &naga::TypeInner, scalar: naga::Scalar) -> bool {
    *inner == naga::TypeInner::Scalar(scalar)
}

fn is_vector(inner: &naga::TypeInner, size: naga::VectorSize, scalar: naga::Scalar) -> bool {
    *inner == naga::TypeInner::Vector { size, scalar }
}

impl WgslField for f32 {
    fn matches(inner: &naga::TypeInner) -> bool {
        is_scalar(inner, naga::Scalar::F32)
    }
}
impl WgslField for u32 {
    fn matches(inner: &naga::TypeInner) -> bool {
        is_scalar(inner, naga::Scalar::U32)
    }
}
impl WgslField for [f32; 3] {
    fn matches(inner: &naga::TypeInner) -> bool {
        is_vector(inner, naga::VectorSize::Tri, naga::Scalar::F32)
    }
}
impl WgslField for [u32; 2] {
    fn matches(inner: &naga::TypeInner) -> bool {
        is_vector(inner, naga::VectorSize::Bi, naga::Scalar::U32)
    }
}
/// `array<f32 or u32, 6>`: six 4-byte elements (the element's scalar
/// type is behind a handle this check cannot follow; both are 4 bytes).
fn is_array_of_six_words(inner: &naga::TypeInner) -> bool {
    matches!(
        inner,
        naga::TypeInner::Array { size: naga::ArraySize::Constant(n), stride: 4, .. } if n.get() == 6
    )
}
impl WgslField for [f32; 6] {
    fn matches(inner: &naga::TypeInner) -> bool {
        is_array_of_six_words(inner)
    }
}
impl WgslField for [u32; 6] {
    fn matches(inner: &naga::TypeInner) -> bool {
        is_array_of_six_words(inner)
    }
}
/// The ray counters: u32 on the host, `atomic<u32>` in WGSL.
fn atomic_u32(inner: &naga::TypeInner) -> bool {
    *inner == naga::TypeInner::Atomic(naga::Scalar::U32)
}

/// A member check: name, offset, and whether a naga type is the field's.
type FieldCheck = (&'static str, usize, fn(&naga::TypeInner) -> bool);

/// `T::matches` for the type of `field`, inferred from an accessor.
fn matcher_of<S, T: WgslField>(_: fn(&S) -> &T) -> fn(&naga::TypeInner) -> bool {
    T::matches
}

/// Checks that a WGSL struct has the Rust type's size and that each of
/// its members sits at the offset of the Rust field of the same name,
/// with the WGSL type that field stands for.
fn check_layout(
    module: &naga::Module,
    wgsl_name: &str,
    rust_size: usize,
    rust_fields: &[FieldCheck],
) {
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(wgsl_name))
        .unwrap_or_else(|| panic!("no struct {wgsl_name} in types.wgsl"))
        .1;
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{wgsl_name} is not a struct")
    };
    assert_eq!(*span as usize, rust_size, "size of {wgsl_name}");
    for m in members {
        let name = m.name.as_deref().unwrap();
        let rust = rust_fields
            .iter()
            .find(|(n, _, _)| *n == name)
            .unwrap_or_else(|| panic!("{wgsl_name}.{name} has no Rust field"));
        assert_eq!(m.offset as usize, rust.1, "offset of {wgsl_name}.{name}");
        let inner = &module.types[m.ty].inner;
        assert!(
            (rust.2)(inner),
            "type of {wgsl_name}.{name}: WGSL has {inner:?}, which the Rust field is not"
        );
    }
}

macro_rules! layout_of {
    ($module:expr, $wgsl:literal, $rust:ty, [$($field:ident),* $(,)?]) => {
        check_layout(
            $module,
            $wgsl,
            std::mem::size_of::<$rust>(),
            &[$((
                stringify!($field),
                std::mem::offset_of!($rust, $field),
                matcher_of(|s: &$rust| &s.$field),
            )),*],
        )
    };
}

/// The kernel's shared types (shaders/types.wgsl), parsed and validated.
fn types_module() -> naga::Module {
    let source = include_str!("../../shaders/types.wgsl");
    super::shaders::parse_and_validate(source).0
}

#[test]
fn scene_records_match_their_wgsl_structs() {
    let module = types_module();
    layout_of!(&module, "KdNode", KdNode, [kind, split, index, count]);
    layout_of!(
        &module,
        "PackedKdNode",
        GpuKdNode,
        [tag_and_index, split_or_first]
    );
    layout_of!(&module, "LeafRopes", LeafRopes, [faces, ropes]);
    layout_of!(&module, "Sphere", GpuSphere, [center, radius]);
    layout_of!(
        &module,
        "Triangle",
        GpuTriangle,
        [v0, normals, v1, scene_id, v2]
    );
    layout_of!(&module, "TriangleNormals", GpuTriangleNormals, [n0, n1, n2]);
    layout_of!(
        &module,
        "Material",
        GpuMaterial,
        [
            ambient,
            shininess,
            diffuse,
            reflection,
            specular,
            transmission,
            ior,
            texture,
            metallic,
            roughness,
            emission,
            model,
            metal_rough_texture,
            emissive_texture,
            normal_texture,
            normal_scale,
            alpha_mode,
            alpha_cutoff,
            alpha_factor,
            occlusion_texture,
            occlusion_strength,
            uv_channels,
            two_sided,
            transmission_roughness,
            absorption,
            thin_walled
        ]
    );
    layout_of!(
        &module,
        "Light",
        GpuLight,
        [
            position, kind, ambient, object, diffuse, cos_outer, specular, spot_scale, direction,
            path_scale, pick, cdf, beyond, leaf
        ]
    );
    layout_of!(
        &module,
        "LightNode",
        GpuLightNode,
        [
            lo,
            child,
            hi,
            parent,
            axis,
            cos_theta_o,
            phi,
            cos_theta_e,
            two_sided,
            _pad
        ]
    );
}

#[test]
fn frame_params_match_their_wgsl_struct() {
    let module = types_module();
    layout_of!(
        &module,
        "FrameParams",
        FrameParams,
        [
            camera_position,
            tan_half_vfov,
            camera_forward,
            aspect,
            camera_right,
            min_intensity,
            camera_up,
            max_depth,
            background,
            shadow_mode,
            scene_min,
            sphere_count,
            scene_max,
            object_count,
            width,
            height,
            samples_per_axis,
            light_count,
            tile_origin,
            tile_size,
            accel,
            node_count,
            sample_index,
            traversal,
            integrator,
            seed,
            emitter_count,
            sample_count,
            samples,
            env_offset,
            env_width,
            env_height,
            env_intensity,
            env_rotation_cos,
            env_rotation_sin,
            _pad0,
        ]
    );
}

#[test]
fn ray_counters_and_queries_match_their_wgsl_structs() {
    let module = types_module();
    // The host reads the counters as u32s; WGSL adds to them atomically.
    let atomic: fn(&naga::TypeInner) -> bool = atomic_u32;
    check_layout(
        &module,
        "RayCounters",
        std::mem::size_of::<RayCounters>(),
        &[
            (
                "primary",
                std::mem::offset_of!(RayCounters, primary),
                atomic,
            ),
            ("shadow", std::mem::offset_of!(RayCounters, shadow), atomic),
            (
                "reflection",
                std::mem::offset_of!(RayCounters, reflection),
                atomic,
            ),
            (
                "loop_limited",
                std::mem::offset_of!(RayCounters, loop_limited),
                atomic,
            ),
            (
                "nonfinite",
                std::mem::offset_of!(RayCounters, nonfinite),
                atomic,
            ),
        ],
    );
    layout_of!(
        &module,
        "QueryRay",
        GpuQueryRay,
        [origin, t_limit, dir, any_hit]
    );
    layout_of!(&module, "QueryHit", GpuQueryHit, [t, object]);
}

#[test]
fn present_params_match_their_wgsl_struct() {
    let (present, _) = super::shaders::parse_and_validate(&super::shaders::present_source());
    layout_of!(
        &present,
        "PresentParams",
        PresentParams,
        [
            image_size,
            target_size,
            preview_size,
            show_image,
            tone_map,
            exposure_scale,
            _pad
        ]
    );
}
