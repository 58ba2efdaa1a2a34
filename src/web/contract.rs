//! The host-shader contract as JSON (`contract.json` in the site), made
//! from `gpu::bindings` and `layout`: what the page's script binds, its
//! entry points and workgroup sizes, the shared constants, the overrides,
//! the byte layout of the uniforms it writes, the optional bindings with the
//! text that swaps each for its placeholder, and the bundle's format. The
//! script reads every layout and number from here; none is kept in it.

use serde_json::{json, Value};

use crate::choice::Choice;
use crate::gpu::bindings::{
    self, Access, Binding, SharedValue, ACCUMULATE_TILE, OPTIONAL_BINDINGS, PRESENT_BINDINGS,
    PRESENT_CONSTANTS, SHARED_CONSTANTS, UNSPLIT,
};
use crate::gpu::kernel_variant::{Walk, OVERRIDES};
use crate::gpu::{Accel, FrameParams, KernelVariant, PresentParams};
use crate::kdtree::Traversal;
use crate::layout::{INTEGRATOR_PATH, INTEGRATOR_WHITTED};
use crate::scene::Integrator;

use super::bundle;

/// File names of the site that the contract names.
pub const KERNEL_FILE: &str = "kernel.wgsl";
pub const PRESENT_FILE: &str = "present.wgsl";
/// The inspect kernel (`gpu::shaders::inspect_source_without`).
pub const INSPECT_FILE: &str = "inspect.wgsl";
pub const BUNDLE_FILE: &str = "scene.kdray";

fn binding_json(b: &Binding) -> Value {
    json!({
        "name": b.name,
        "index": b.index,
        "type": b.wgsl_type,
        "access": match b.access {
            Access::Uniform => "uniform",
            Access::StorageRead => "read-only-storage",
            Access::StorageReadWrite => "storage",
        },
    })
}

/// One field of a uniform: its name, byte offset, scalar type and count.
type Field = (&'static str, usize, &'static str, usize);

/// One field of a uniform struct, by name: (name, byte offset, scalar type, count).
macro_rules! field {
    ($struct:ty, $name:ident, $ty:literal, $n:literal) => {
        (
            stringify!($name),
            std::mem::offset_of!($struct, $name),
            $ty,
            $n,
        )
    };
}

/// `FrameParams`'s fields, by offset (the tests check they tile it).
fn frame_params_fields() -> Vec<Field> {
    vec![
        field!(FrameParams, camera_position, "f32", 3),
        field!(FrameParams, tan_half_vfov, "f32", 1),
        field!(FrameParams, camera_forward, "f32", 3),
        field!(FrameParams, aspect, "f32", 1),
        field!(FrameParams, camera_right, "f32", 3),
        field!(FrameParams, min_intensity, "f32", 1),
        field!(FrameParams, camera_up, "f32", 3),
        field!(FrameParams, max_depth, "u32", 1),
        field!(FrameParams, background, "f32", 3),
        field!(FrameParams, shadow_mode, "u32", 1),
        field!(FrameParams, scene_min, "f32", 3),
        field!(FrameParams, sphere_count, "u32", 1),
        field!(FrameParams, scene_max, "f32", 3),
        field!(FrameParams, object_count, "u32", 1),
        field!(FrameParams, width, "u32", 1),
        field!(FrameParams, height, "u32", 1),
        field!(FrameParams, samples_per_axis, "u32", 1),
        field!(FrameParams, light_count, "u32", 1),
        field!(FrameParams, tile_origin, "u32", 2),
        field!(FrameParams, tile_size, "u32", 2),
        field!(FrameParams, accel, "u32", 1),
        field!(FrameParams, node_count, "u32", 1),
        field!(FrameParams, sample_index, "u32", 1),
        field!(FrameParams, traversal, "u32", 1),
        field!(FrameParams, integrator, "u32", 1),
        field!(FrameParams, seed, "u32", 1),
        field!(FrameParams, emitter_count, "u32", 1),
        field!(FrameParams, sample_count, "u32", 1),
        field!(FrameParams, samples, "u32", 1),
        field!(FrameParams, env_offset, "u32", 1),
        field!(FrameParams, env_width, "u32", 1),
        field!(FrameParams, env_height, "u32", 1),
        field!(FrameParams, env_intensity, "f32", 1),
        field!(FrameParams, env_rotation_cos, "f32", 1),
        field!(FrameParams, env_rotation_sin, "f32", 1),
        field!(FrameParams, _pad0, "u32", 1),
    ]
}

/// `PresentParams`'s fields, by offset.
fn present_params_fields() -> Vec<Field> {
    vec![
        field!(PresentParams, image_size, "u32", 2),
        field!(PresentParams, target_size, "u32", 2),
        field!(PresentParams, preview_size, "u32", 2),
        field!(PresentParams, show_image, "u32", 1),
        field!(PresentParams, tone_map, "u32", 1),
        field!(PresentParams, exposure_scale, "f32", 1),
    ]
}

/// Words per pixel of render_tile's output with FEATURE_OUTPUT, and where
/// the albedo and normal sums start (shaders/trace.wgsl, add_radiance).
const FEATURE_WORDS: usize = 12;
const ALBEDO_WORD: usize = 4;
const NORMAL_WORD: usize = 8;

/// The denoise kernels' uniforms (shaders/denoise/), by name: their
/// layouts as `struct_json` gives them.
pub(super) fn denoise_params_json() -> Value {
    use crate::denoise::{ConvParams, PackParams, ResampleParams};
    let pack = vec![
        field!(PackParams, tile_width, "u32", 1),
        field!(PackParams, tile_height, "u32", 1),
        field!(PackParams, src_width, "u32", 1),
        field!(PackParams, src_height, "u32", 1),
        field!(PackParams, offset_x, "u32", 1),
        field!(PackParams, offset_y, "u32", 1),
        field!(PackParams, channels, "u32", 1),
        field!(PackParams, out_x, "u32", 1),
        field!(PackParams, out_y, "u32", 1),
        field!(PackParams, out_width, "u32", 1),
        field!(PackParams, out_height, "u32", 1),
        field!(PackParams, input_scale, "f32", 1),
        field!(PackParams, output_scale, "f32", 1),
        field!(PackParams, pu_norm, "f32", 1),
        field!(PackParams, pu_max, "f32", 1),
        field!(PackParams, pad, "u32", 1),
    ];
    let conv = vec![
        field!(ConvParams, width, "u32", 1),
        field!(ConvParams, height, "u32", 1),
        field!(ConvParams, src_channels, "u32", 1),
        field!(ConvParams, skip_channels, "u32", 1),
        field!(ConvParams, out_channels, "u32", 1),
        field!(ConvParams, first_output, "u32", 1),
        field!(ConvParams, relu, "u32", 1),
        field!(ConvParams, first_row, "u32", 1),
    ];
    let resample = vec![
        field!(ResampleParams, width, "u32", 1),
        field!(ResampleParams, height, "u32", 1),
        field!(ResampleParams, channels, "u32", 1),
        field!(ResampleParams, pad, "u32", 1),
    ];
    json!({
        "pack": struct_json(std::mem::size_of::<PackParams>(), &pack),
        "conv": struct_json(std::mem::size_of::<ConvParams>(), &conv),
        "resample": struct_json(std::mem::size_of::<ResampleParams>(), &resample),
    })
}

fn struct_json(size: usize, fields: &[Field]) -> Value {
    let fields: serde_json::Map<String, Value> = fields
        .iter()
        .map(|&(name, offset, ty, count)| {
            (
                name.to_string(),
                json!({"offset": offset, "type": ty, "count": count}),
            )
        })
        .collect();
    json!({"size": size, "fields": fields})
}

/// The window's line colours by the page's names of what they show.
fn inspect_colours() -> Value {
    use crate::window::inspect_lines::LineKind;
    let kinds = [
        ("leaf", LineKind::Leaf),
        ("hit_leaf", LineKind::HitLeaf),
        ("split_plane", LineKind::SplitPlane),
        ("primary", LineKind::Primary),
        ("shadow", LineKind::Shadow),
        ("reflected", LineKind::Reflected),
        ("refracted", LineKind::Refracted),
        ("bounce", LineKind::Bounce),
    ];
    Value::Object(
        kinds
            .iter()
            .map(|(name, kind)| (name.to_string(), json!(kind.colour())))
            .collect(),
    )
}

/// The overrides each of the page's pipeline choices sets; the bundle's
/// `overrides` set the rest (`kernel_variant::SCENE_OVERRIDES`).
pub const CHOICE_OVERRIDES: [(&str, &[&str]); 4] = [
    ("walk", &["ACCEL", "TRAVERSAL"]),
    ("costs", &["COUNT_COSTS"]),
    ("integrator", &["INTEGRATOR"]),
    ("entry", &["RADIANCE_OUTPUT", "FEATURE_OUTPUT"]),
];

/// A variant that reads no optional binding: the choices are made on it.
const LEAST: KernelVariant = KernelVariant {
    split_scene: false,
    walk: Walk::Brute,
    spheres: false,
    triangles: false,
    smooth_triangles: false,
    glass: false,
    textures: false,
    alpha_test: false,
    spot_or_directional_lights: false,
    count_costs: false,
    integrator: INTEGRATOR_WHITTED,
    radiance_output: false,
    feature_output: false,
};

/// The page's pipeline choices, each value by the page's name for it, as
/// `KernelVariant` makes it: the overrides the choice sets (`constants`)
/// and the needs of the optional bindings it reads (`reads`).
fn pipeline_choices() -> Value {
    let [walk_names, costs_names, integrator_names, entry_names] =
        CHOICE_OVERRIDES.map(|(_, names)| names);
    let made = |names: &[&str], v: KernelVariant| {
        let overrides: serde_json::Map<String, Value> = v
            .constants()
            .into_iter()
            .filter(|(name, _)| names.contains(name))
            .map(|(name, value)| (name.to_string(), json!(value)))
            .collect();
        let mut needs: Vec<&str> = Vec::new();
        for (_, need) in OPTIONAL_BINDINGS {
            if v.reads(need) && !needs.contains(&need.name()) {
                needs.push(need.name());
            }
        }
        json!({"overrides": overrides, "needs": needs})
    };
    let walk = |walk| KernelVariant { walk, ..LEAST };
    let mut walks = serde_json::Map::new();
    walks.insert(
        Accel::Brute.name().into(),
        made(walk_names, walk(Walk::Brute)),
    );
    for t in Traversal::ALL {
        walks.insert(t.name().into(), made(walk_names, walk(Walk::Kdtree(t))));
    }
    let costs = |count_costs| {
        made(
            costs_names,
            KernelVariant {
                count_costs,
                ..LEAST
            },
        )
    };
    let integrators: serde_json::Map<String, Value> = Integrator::ALL
        .iter()
        .map(|&i| {
            let integrator = match i {
                Integrator::Whitted => INTEGRATOR_WHITTED,
                Integrator::Path => INTEGRATOR_PATH,
            };
            let v = KernelVariant {
                integrator,
                ..LEAST
            };
            (i.name().to_string(), made(integrator_names, v))
        })
        .collect();
    // RADIANCE_OUTPUT and FEATURE_OUTPUT are render_tile's: off, as the
    // window's and the inspector's pipelines have them.
    let entry = made(entry_names, LEAST);
    // The denoiser's input: render_tile's radiance and feature sums, as
    // `render --denoise` traces them.
    let features = made(
        entry_names,
        KernelVariant {
            radiance_output: true,
            feature_output: true,
            ..LEAST
        },
    );
    json!({
        "walk": walks,
        "costs": {"off": costs(false), "on": costs(true)},
        "integrator": integrators,
        "entry": {"accumulate": entry, "inspect": entry, "features": features},
    })
}

/// The contract as the page reads it.
pub fn contract_json() -> Value {
    let constants: serde_json::Map<String, Value> = SHARED_CONSTANTS
        .iter()
        .chain(&PRESENT_CONSTANTS)
        .map(|&(name, value)| {
            let v = match value {
                SharedValue::U32(v) => json!(v),
                SharedValue::F32(v) => json!(v),
            };
            (name.to_string(), v)
        })
        .collect();
    let accumulate = bindings::entry_point_bindings(UNSPLIT, ACCUMULATE_TILE.outputs);
    let inspect = bindings::entry_point_bindings(UNSPLIT, bindings::INSPECT_PIXEL.outputs);
    let features = bindings::entry_point_bindings(UNSPLIT, bindings::RENDER_TILE.outputs);
    json!({
        "generator": format!("kdray {}", env!("CARGO_PKG_VERSION")),
        "files": {"kernel": KERNEL_FILE, "present": PRESENT_FILE, "inspect": INSPECT_FILE, "bundle": BUNDLE_FILE},
        "bundle": {
            "magic": std::str::from_utf8(bundle::MAGIC).expect("ASCII"),
            "version": bundle::FORMAT_VERSION,
            "header_bytes": bundle::HEADER_BYTES,
            "section_entry_bytes": bundle::SECTION_ENTRY_BYTES,
            // An empty array is bound as one zeroed element of this size.
            "empty_array_bytes": crate::gpu::scene_buffers::EMPTY_ARRAY_BYTES,
            "section_name_bytes": bundle::SECTION_NAME_BYTES,
            "scene_arrays": bindings::scene(UNSPLIT).iter().map(|b| b.name).collect::<Vec<_>>(),
            "cameras": {
                "section": "cameras",
                "header_bytes": bundle::CAMERAS_HEADER_BYTES,
                "values_per_frame": bundle::CAMERA_VALUES,
            },
            "frame_lights": {
                "section": bundle::FRAME_LIGHTS_SECTION,
                "binding": bindings::LIGHTS.name,
                "bytes_per_light": std::mem::size_of::<crate::layout::GpuLight>(),
            },
        },
        "accumulate": {
            "entry_point": ACCUMULATE_TILE.name,
            "workgroup": ACCUMULATE_TILE.workgroup,
            "bindings": accumulate.iter().map(binding_json).collect::<Vec<_>>(),
            "params": bindings::PARAMS.name,
            "outputs": ACCUMULATE_TILE.outputs.iter().map(|b| b.name).collect::<Vec<_>>(),
            "texel_bytes": crate::gpu::accumulate::ACCUMULATION_TEXEL,
            "cost_words": bindings::COST_WORDS,
        },
        // window.kdray.inspect(x, y): the inspect kernel's entry point, its
        // log (gpu::walk_log; the INSPECT_* and RAY_* constants) and the
        // document it becomes (src/inspect/document.rs, docs/inspect.md).
        "inspect": {
            "entry_point": bindings::INSPECT_PIXEL.name,
            "workgroup": bindings::INSPECT_PIXEL.workgroup,
            "bindings": inspect.iter().map(binding_json).collect::<Vec<_>>(),
            "log": bindings::INSPECT_LOG.name,
            "first_log_words": crate::gpu::walk_log::FIRST_LOG_WORDS,
            "version": crate::inspect::INSPECT_VERSION,
            // Inspection mode's line colours (linear RGB, as the window's).
            "colours": inspect_colours(),
        },
        // The denoiser's input on the page (denoise=1, N): render_tile with
        // RADIANCE_OUTPUT and FEATURE_OUTPUT adds each pass's sample to
        // per-pixel sums of radiance, albedo and normal (shaders/trace.wgsl,
        // add_radiance), after the ray counters.
        "features": {
            "entry_point": bindings::RENDER_TILE.name,
            "workgroup": bindings::RENDER_TILE.workgroup,
            "bindings": features.iter().map(binding_json).collect::<Vec<_>>(),
            "params": bindings::PARAMS.name,
            "output": bindings::TILE_OUTPUT.name,
            "header_bytes": std::mem::size_of::<crate::gpu::RayCounters>(),
            "words_per_pixel": FEATURE_WORDS,
            "albedo_word": ALBEDO_WORD,
            "normal_word": NORMAL_WORD,
        },
        "optional_bindings": OPTIONAL_BINDINGS.iter().map(|(b, need)| json!({
            "name": b.name,
            "need": need.name(),
            "declaration": bindings::declaration(b, true),
            "placeholder": bindings::declaration(b, false),
        })).collect::<Vec<_>>(),
        "overrides": OVERRIDES,
        // What each pipeline choice (walk, costs, integrator, entry point)
        // sets of them; the bundle's scene sets the others.
        "pipeline_choices": pipeline_choices(),
        // The cost heatmap's colour map: [at, [r, g, b]] control points.
        "heatmap_stops": crate::output::heatmap::STOPS,
        "constants": constants,
        "frame_params": struct_json(std::mem::size_of::<FrameParams>(), &frame_params_fields()),
        "present": {
            "vertex": bindings::PRESENT_VERTEX_ENTRY_POINT,
            "fragment": bindings::PRESENT_FRAGMENT_ENTRY_POINT,
            "bindings": PRESENT_BINDINGS.iter().map(binding_json).collect::<Vec<_>>(),
            "params": struct_json(std::mem::size_of::<PresentParams>(), &present_params_fields()),
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The fields listed for each uniform tile it: in order, no gap, no
    /// overlap, up to its size (the last padding word of PresentParams
    /// aside), so the page writes every field where the kernel reads it.
    #[test]
    fn uniform_fields_tile_their_structs() {
        for (fields, size) in [
            (frame_params_fields(), std::mem::size_of::<FrameParams>()),
            (
                present_params_fields(),
                std::mem::size_of::<PresentParams>() - 4,
            ),
        ] {
            let mut at = 0;
            for (name, offset, _, count) in fields {
                assert_eq!(offset, at, "{name}");
                at += 4 * count;
            }
            assert_eq!(at, size);
        }
        let denoise = denoise_params_json();
        for name in ["pack", "conv", "resample"] {
            let s = &denoise[name];
            let mut offsets: Vec<u64> = s["fields"]
                .as_object()
                .unwrap()
                .values()
                .map(|f| f["offset"].as_u64().unwrap())
                .collect();
            offsets.sort();
            let expected: Vec<u64> = (0..offsets.len() as u64).map(|i| 4 * i).collect();
            assert_eq!(offsets, expected, "{name}");
            assert_eq!(
                s["size"].as_u64().unwrap(),
                4 * offsets.len() as u64,
                "{name}"
            );
        }
    }

    /// The bundle's scene overrides and the choices' overrides are the
    /// kernel's, each once; a change of a scene fact of the variant changes
    /// only scene overrides, and a change of one choice only that choice's.
    #[test]
    fn scene_and_choices_split_the_overrides() {
        use crate::gpu::kernel_variant::SCENE_OVERRIDES;
        let mut names: Vec<&str> = SCENE_OVERRIDES
            .iter()
            .chain(CHOICE_OVERRIDES.iter().flat_map(|(_, n)| n.iter()))
            .copied()
            .collect();
        names.sort();
        let mut all = OVERRIDES.to_vec();
        all.sort();
        assert_eq!(names, all);
        let choice = |c: &str| CHOICE_OVERRIDES.iter().find(|(n, _)| *n == c).unwrap().1;
        for base in [LEAST, KernelVariant::GENERAL] {
            let flip = |f: fn(&mut KernelVariant)| {
                let mut v = base;
                f(&mut v);
                v
            };
            let changes: Vec<(KernelVariant, &[&str])> = vec![
                (flip(|v| v.split_scene ^= true), &SCENE_OVERRIDES),
                (flip(|v| v.spheres ^= true), &SCENE_OVERRIDES),
                (flip(|v| v.triangles ^= true), &SCENE_OVERRIDES),
                (flip(|v| v.smooth_triangles ^= true), &SCENE_OVERRIDES),
                (flip(|v| v.glass ^= true), &SCENE_OVERRIDES),
                (flip(|v| v.textures ^= true), &SCENE_OVERRIDES),
                (flip(|v| v.alpha_test ^= true), &SCENE_OVERRIDES),
                (
                    flip(|v| v.spot_or_directional_lights ^= true),
                    &SCENE_OVERRIDES,
                ),
                (
                    flip(|v| v.walk = Walk::Kdtree(Traversal::Ropes)),
                    choice("walk"),
                ),
                (flip(|v| v.walk = Walk::FromParams), choice("walk")),
                (flip(|v| v.count_costs ^= true), choice("costs")),
                (
                    flip(|v| v.integrator = INTEGRATOR_PATH),
                    choice("integrator"),
                ),
                (flip(|v| v.radiance_output ^= true), choice("entry")),
                (flip(|v| v.feature_output ^= true), choice("entry")),
            ];
            for (i, (changed, allowed)) in changes.into_iter().enumerate() {
                for ((name, a), (_, b)) in base.constants().iter().zip(changed.constants()) {
                    assert!(a == &b || allowed.contains(name), "change {i} sets {name}");
                }
            }
        }
    }

    /// Every optional binding is one of accumulate_tile's.
    #[test]
    fn optional_bindings_are_accumulate_bindings() {
        let all = bindings::entry_point_bindings(UNSPLIT, ACCUMULATE_TILE.outputs);
        for (b, _) in OPTIONAL_BINDINGS {
            assert!(all.contains(&b), "{}", b.name);
        }
    }
}
