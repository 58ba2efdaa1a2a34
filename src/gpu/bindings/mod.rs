//! The host-shader contract in one place: every binding of the trace kernel
//! and of the window's present pass (number, WGSL name, type, access), each
//! entry point's name, outputs and workgroup size, and every constant both
//! sides use.
//!
//! The WGSL side is generated from here ([`wgsl_contract`],
//! [`wgsl_present_contract`]) and prepended to the shaders by
//! `gpu::shaders`, so a binding number, a size or a constant is written
//! once. Every bind group layout is built from the same table
//! ([`layout_entries`]). This module depends on no other part of `gpu`; the
//! tests in gpu/shaders.rs hold the assembled shaders to it through naga:
//! binding numbers and access by name, constants by value, workgroup sizes.
//!
//! The arrays that may lie in several bindings (their chunk bindings,
//! readers and share of the adapter's storage buffers) are in
//! bindings/split_arrays.rs, re-exported here; the inspect kernel's log
//! layout is in bindings/walk_codes.rs.

use crate::geometry::{HIT_BOX_MARGIN, IN_PLANE_MARGIN, PARALLEL_EPSILON, T_INFINITY};
use crate::layout::light_tree;
use crate::layout::{
    GpuMaterial, GpuTriangle, KdNode, LeafRopes, TextureWords, ACCEL_BRUTE, ACCEL_KDTREE,
    ALPHA_BLEND, ALPHA_MASK, ALPHA_OPAQUE, GLASS_STACK_DEPTH, INTEGRATOR_PATH, INTEGRATOR_WHITTED,
    LIGHT_DIRECTIONAL, LIGHT_EMITTER, LIGHT_POINT, LIGHT_SPOT, MODEL_LAMBERTIAN, MODEL_METAL_ROUGH,
    SHADOW_AMBIENT, SHADOW_CROSSINGS, SHADOW_SEED, TRAVERSAL_RESTART, TRAVERSAL_ROPES,
    TRAVERSAL_SHORT_STACK,
};

/// How a kernel reads or writes a binding.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Access {
    Uniform,
    StorageRead,
    StorageReadWrite,
}

/// One `@group(0) @binding(index) var<...> name: wgsl_type;` of the kernel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Binding {
    pub index: u32,
    pub name: &'static str,
    pub wgsl_type: &'static str,
    pub access: Access,
}

const fn binding(
    index: u32,
    name: &'static str,
    wgsl_type: &'static str,
    access: Access,
) -> Binding {
    Binding {
        index,
        name,
        wgsl_type,
        access,
    }
}

impl Binding {
    /// `T` of a runtime-sized `array<T>` binding.
    pub fn element_type(&self) -> &'static str {
        self.wgsl_type
            .strip_prefix("array<")
            .and_then(|t| t.strip_suffix('>'))
            .unwrap_or_else(|| panic!("{} is not a runtime-sized array", self.name))
    }
}

use walk_codes as log;
use Access::{StorageRead, StorageReadWrite, Uniform};

mod split_arrays;
pub mod walk_codes;
pub use split_arrays::{
    scene_chunks, ElementPart, SceneChunks, SplitArray, MAX_CHUNKS, SPLIT_ARRAYS,
    SPLIT_ARRAY_COUNT, UNSPLIT,
};

/// Camera, render settings, counts and the tile ([`crate::gpu::FrameParams`]).
/// Each entry point copies it into the private `params` before anything
/// else (shaders/frame_params.wgsl, `read_params`), and the kernel reads the copy.
pub const PARAMS: Binding = binding(0, "frame_params", "FrameParams", Uniform);
// Spheres, triangles and k-d nodes are declared as vectors, not as their
// structs (shaders/types.wgsl): llvmpipe loads each member of a struct with a
// loop over the 8 lanes of its own, so one vector load per 16 bytes is fewer
// loops (design.md, "Vector loads"). The shader unpacks them into the structs.
pub const SPHERES: Binding = binding(1, "spheres", "array<vec4<f32>>", StorageRead);
pub const TRIANGLES: Binding = binding(2, "triangles", "array<array<vec4<f32>, 3>>", StorageRead);
/// Per GPU object id (spheres first, then triangles, in the tree's leaf
/// order): x its material index, y its scene id, which breaks ties between
/// hits at an equal t as brute force's loop over the scene does.
pub const OBJECTS: Binding = binding(3, "objects", "array<vec2<u32>>", StorageRead);
pub const MATERIALS: Binding = binding(4, "materials", "array<Material>", StorageRead);
pub const LIGHTS: Binding = binding(5, "lights", "array<Light>", StorageRead);
pub const KD_NODES: Binding = binding(6, "kd_nodes", "array<vec2<u32>>", StorageRead);
pub const LEAF_OBJECTS: Binding = binding(7, "leaf_objects", "array<u32>", StorageRead);
/// `render_tile`'s output: ray counters, then one packed RGBA8 per pixel.
pub const TILE_OUTPUT: Binding = binding(8, "tile_output", "TileOutput", StorageReadWrite);
/// `accumulate_tile`'s output: per pixel, the sum of clamped samples and their count.
pub const ACCUMULATION: Binding = binding(9, "accumulation", "array<vec4<f32>>", StorageReadWrite);
/// The rope walk's per-leaf boxes and ropes ([`crate::layout::LeafRopes`]).
pub const LEAF_ROPES: Binding = binding(12, "leaf_ropes", "array<LeafRopes>", StorageRead);
/// For each k-d node, its record in `leaf_ropes` (leaves only).
pub const LEAF_ROPE_INDEX: Binding = binding(13, "leaf_rope_index", "array<u32>", StorageRead);
/// Vertex normals of the smooth-shaded triangles, indexed by
/// `Triangle::normals` ([`crate::layout::GpuTriangleNormals`]).
pub const TRIANGLE_NORMALS: Binding = binding(
    15,
    "triangle_normals",
    "array<TriangleNormals>",
    StorageRead,
);
/// The base-colour textures, their headers and the textured triangles'
/// texture coordinates, in one array of words
/// ([`crate::layout::TextureWords`]; shaders/texture.wgsl).
pub const TEXTURES: Binding = binding(16, "textures", "array<u32>", StorageRead);
/// `trace_rays` (the debug entry point): the rays to trace.
pub const QUERY_RAYS: Binding = binding(10, "query_rays", "array<QueryRay>", StorageRead);
/// `trace_rays`: one hit per ray.
pub const QUERY_HITS: Binding = binding(11, "query_hits", "array<QueryHit>", StorageReadWrite);

/// Per pixel, the walk cost of all its rays: three words (nodes visited,
/// leaves visited, objects tested; `kdtree::traverse::WalkCost`).
/// `render_tile`: per pixel of the tile, written; `accumulate_tile`: per
/// pixel of the image, added to. A one-word buffer turns it off (the
/// kernel writes only where three words per pixel fit).
pub const PIXEL_COSTS: Binding = binding(20, "pixel_costs", "array<u32>", StorageReadWrite);
/// `trace_rays`: the walk cost of each ray, three words as [`PIXEL_COSTS`].
pub const QUERY_COSTS: Binding = binding(21, "query_costs", "array<u32>", StorageReadWrite);

/// Words per pixel (or per query) in [`PIXEL_COSTS`] and [`QUERY_COSTS`].
pub const COST_WORDS: usize = 3;

/// `inspect_pixel` (the inspect kernel's entry point): the log of one
/// pixel's rays and walks (shaders/walk_record.wgsl, [`crate::gpu::walk_log`]).
pub const INSPECT_LOG: Binding = binding(22, "inspect_log", "array<u32>", StorageReadWrite);

/// The scene's storage buffers, in the order [`crate::gpu::SceneArrays`]
/// lists them, each split array with its first `chunks` bindings.
pub fn scene(chunks: SceneChunks) -> Vec<Binding> {
    let split = |i: usize| SPLIT_ARRAYS[i].chunks[..chunks[i]].to_vec();
    let mut scene = vec![SPHERES];
    scene.extend(split(0));
    scene.extend([OBJECTS, MATERIALS, LIGHTS]);
    scene.extend(split(1));
    scene.extend(split(2));
    scene.extend(split(3));
    scene.extend(split(4));
    scene.extend(split(5));
    scene.push(TEXTURES);
    scene
}

/// `render_tile`'s own buffers.
pub const RENDER_OUTPUTS: [Binding; 2] = [TILE_OUTPUT, PIXEL_COSTS];
/// `accumulate_tile`'s own buffers.
pub const ACCUMULATE_OUTPUTS: [Binding; 2] = [ACCUMULATION, PIXEL_COSTS];
/// `trace_rays`'s own buffers.
pub const QUERY_OUTPUTS: [Binding; 3] = [QUERY_RAYS, QUERY_HITS, QUERY_COSTS];
/// `inspect_pixel`'s own buffer.
pub const INSPECT_OUTPUTS: [Binding; 1] = [INSPECT_LOG];

/// Workgroup size of `render_tile` and `accumulate_tile` (pixels in x, y).
pub const TRACE_WORKGROUP: (u32, u32) = (8, 8);
/// Workgroup size of `trace_rays` (rays per workgroup).
pub const QUERY_WORKGROUP: u32 = 64;

/// One compute entry point of the trace kernel: its bindings are the frame
/// parameters, the scene, then `outputs`, in one bind group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EntryPoint {
    pub name: &'static str,
    /// Its own buffers (outputs, and for queries the rays), in the order
    /// `gpu::TracePipelines::bind_group` takes them.
    pub outputs: &'static [Binding],
    /// `@workgroup_size` (x, y, z), generated into the kernel.
    pub workgroup: [u32; 3],
}

/// Renders a tile to 8-bit colour (all samples of each pixel).
pub const RENDER_TILE: EntryPoint = EntryPoint {
    name: "render_tile",
    outputs: &RENDER_OUTPUTS,
    workgroup: [TRACE_WORKGROUP.0, TRACE_WORKGROUP.1, 1],
};
/// Adds one stratified sample per pixel to the accumulation buffer, for the
/// window's progressive refinement.
pub const ACCUMULATE_TILE: EntryPoint = EntryPoint {
    name: "accumulate_tile",
    outputs: &ACCUMULATE_OUTPUTS,
    workgroup: [TRACE_WORKGROUP.0, TRACE_WORKGROUP.1, 1],
};
/// Traces given rays and writes their hits (tests, debugging).
pub const TRACE_RAYS: EntryPoint = EntryPoint {
    name: "trace_rays",
    outputs: &QUERY_OUTPUTS,
    workgroup: [QUERY_WORKGROUP, 1, 1],
};
/// Every entry point of the trace kernel.
pub const ENTRY_POINTS: [EntryPoint; 3] = [RENDER_TILE, ACCUMULATE_TILE, TRACE_RAYS];
/// Traces one pixel's first sample and logs its rays and walks: the entry
/// point of the inspect kernel, which is the trace kernel with
/// shaders/walk_record.wgsl in place of walk_record_off.wgsl.
pub const INSPECT_PIXEL: EntryPoint = EntryPoint {
    name: "inspect_pixel",
    outputs: &INSPECT_OUTPUTS,
    workgroup: [INSPECT_LANES, 1, 1],
};
/// Invocations of `inspect_pixel`'s one workgroup, which all trace the
/// inspected sample (shaders/walk_record.wgsl says why).
pub const INSPECT_LANES: u32 = 8;
/// Every entry point of the inspect kernel.
pub const INSPECT_ENTRY_POINTS: [EntryPoint; 4] =
    [RENDER_TILE, ACCUMULATE_TILE, TRACE_RAYS, INSPECT_PIXEL];

/// The window's present pass (shaders/present.wgsl, a module of its own):
/// what it shows ([`crate::gpu::PresentParams`]), and the two
/// accumulation buffers `accumulate_tile` fills, read by its fragment stage.
pub const PRESENT_PARAMS: Binding = binding(0, "present", "PresentParams", Uniform);
/// Per pixel: the sum of its clamped samples (rgb) and their number (w).
pub const PRESENT_IMAGE: Binding = binding(1, "accumulation", "array<vec4<f32>>", StorageRead);
/// The preview, traced at a reduced resolution while the camera moves.
pub const PRESENT_PREVIEW: Binding = binding(2, "preview", "array<vec4<f32>>", StorageRead);
/// The present pass's bindings.
pub const PRESENT_BINDINGS: [Binding; 3] = [PRESENT_PARAMS, PRESENT_IMAGE, PRESENT_PREVIEW];
/// Its entry points.
pub const PRESENT_VERTEX_ENTRY_POINT: &str = "vs_main";
pub const PRESENT_FRAGMENT_ENTRY_POINT: &str = "fs_main";

/// The window's line overlay (shaders/overlay.wgsl, a module of its own):
/// the camera's world-to-clip matrix (`window::overlay::OverlayParams`),
/// read by its vertex stage.
pub const OVERLAY_PARAMS: Binding = binding(0, "overlay", "OverlayParams", Uniform);
/// The line overlay's bindings.
pub const OVERLAY_BINDINGS: [Binding; 1] = [OVERLAY_PARAMS];
/// Its entry points.
pub const OVERLAY_VERTEX_ENTRY_POINT: &str = "vs_line";
pub const OVERLAY_FRAGMENT_ENTRY_POINT: &str = "fs_line";

/// Every binding the kernel declares with `chunks` bindings per split
/// array: the parameters, the scene, and each entry point's own buffers.
pub fn all(chunks: SceneChunks) -> Vec<Binding> {
    declared(chunks, &ENTRY_POINTS)
}

/// The bindings a kernel of `entry_points` declares.
fn declared(chunks: SceneChunks, entry_points: &[EntryPoint]) -> Vec<Binding> {
    let mut all = entry_point_bindings(chunks, &[]);
    for b in entry_points.iter().flat_map(|e| e.outputs) {
        if !all.contains(b) {
            all.push(*b);
        }
    }
    all
}

/// The bindings an entry point uses: the frame parameters, the scene (with
/// `chunks` bindings per split array), and its own outputs (and inputs).
pub fn entry_point_bindings(chunks: SceneChunks, outputs: &[Binding]) -> Vec<Binding> {
    let mut all = vec![PARAMS];
    all.extend(scene(chunks));
    all.extend_from_slice(outputs);
    all
}

/// A constant shared by the host and the kernel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SharedValue {
    U32(u32),
    F32(f32),
}

/// Every constant the kernel and the host must agree on, by WGSL name.
pub const SHARED_CONSTANTS: [(&str, SharedValue); 77] = [
    ("KD_LEAF", SharedValue::U32(KdNode::LEAF)),
    ("ACCEL_KDTREE", SharedValue::U32(ACCEL_KDTREE)),
    ("ACCEL_BRUTE", SharedValue::U32(ACCEL_BRUTE)),
    ("SHADOW_AMBIENT", SharedValue::U32(SHADOW_AMBIENT)),
    ("SHADOW_SEED", SharedValue::U32(SHADOW_SEED)),
    // The integrator (`FrameParams::integrator`), the kinds of entry in the
    // lights buffer, and the path tracer's material models.
    ("INTEGRATOR_WHITTED", SharedValue::U32(INTEGRATOR_WHITTED)),
    ("INTEGRATOR_PATH", SharedValue::U32(INTEGRATOR_PATH)),
    ("LIGHT_POINT", SharedValue::U32(LIGHT_POINT)),
    ("LIGHT_EMITTER", SharedValue::U32(LIGHT_EMITTER)),
    ("LIGHT_SPOT", SharedValue::U32(LIGHT_SPOT)),
    ("LIGHT_DIRECTIONAL", SharedValue::U32(LIGHT_DIRECTIONAL)),
    // The light tree's nodes: a leaf's `child` bit, the root's `parent`,
    // an emitter's `leaf` outside the tree (layout::light_tree).
    (
        "LIGHT_TREE_LEAF",
        SharedValue::U32(light_tree::LIGHT_TREE_LEAF),
    ),
    (
        "LIGHT_TREE_ROOT",
        SharedValue::U32(light_tree::LIGHT_TREE_ROOT),
    ),
    ("NO_LEAF", SharedValue::U32(light_tree::NO_LEAF)),
    ("MODEL_LAMBERTIAN", SharedValue::U32(MODEL_LAMBERTIAN)),
    ("MODEL_METAL_ROUGH", SharedValue::U32(MODEL_METAL_ROUGH)),
    // The glass path's stack of pending rays (glass.wgsl).
    ("GLASS_STACK_DEPTH", SharedValue::U32(GLASS_STACK_DEPTH)),
    // Most transmissive surfaces a shadow ray passes before it is blocked.
    ("SHADOW_CROSSINGS", SharedValue::U32(SHADOW_CROSSINGS)),
    // Stand-in for infinity: implementations may assume there is no inf or NaN.
    ("T_INFINITY", SharedValue::F32(T_INFINITY)),
    // Direction components below this count as parallel to an axis plane.
    ("PARALLEL_EPSILON", SharedValue::F32(PARALLEL_EPSILON)),
    // A ray lies in a triangle's plane when the normal's component along it
    // is at most this share of the normal's size (TriangleF32::runs_in_plane).
    ("IN_PLANE_MARGIN", SharedValue::F32(IN_PLANE_MARGIN)),
    // A triangle's hit point may lie this share of the test's largest
    // coordinate outside its box (TriangleF32::holds_hit_at).
    ("HIT_BOX_MARGIN", SharedValue::F32(HIT_BOX_MARGIN)),
    // `QueryHit::object` and the kernel's `Hit::object` when nothing was hit.
    ("NO_OBJECT", SharedValue::U32(NO_OBJECT)),
    // Invocations whose loops ran this many iterations are counted as
    // loop-limited (half llvmpipe's 65,535; see RayCounters::loop_limited).
    ("LOOP_LIMIT_WARNING", SharedValue::U32(LOOP_LIMIT_WARNING)),
    // Rays per workgroup of `trace_rays`.
    ("QUERY_WORKGROUP", SharedValue::U32(QUERY_WORKGROUP)),
    // `FrameParams::traversal`: which k-d walk the kernel runs.
    ("TRAVERSAL_RESTART", SharedValue::U32(TRAVERSAL_RESTART)),
    ("TRAVERSAL_ROPES", SharedValue::U32(TRAVERSAL_ROPES)),
    (
        "TRAVERSAL_SHORT_STACK",
        SharedValue::U32(TRAVERSAL_SHORT_STACK),
    ),
    // Entries of the short-stack walk's stack (three named variables in
    // traverse_short_stack.wgsl).
    (
        "SHORT_STACK_DEPTH",
        SharedValue::U32(crate::kdtree::traverse::SHORT_STACK_DEPTH as u32),
    ),
    // A face on the scene's boundary has no rope.
    ("NO_ROPE", SharedValue::U32(LeafRopes::NONE)),
    // `Triangle::normals` of a flat-shaded triangle.
    ("FLAT_TRIANGLE", SharedValue::U32(GpuTriangle::FLAT)),
    // `textures` (texture.wgsl): a triangle without texture coordinates, a
    // material without a texture, and the words of the buffer's records.
    ("UNTEXTURED", SharedValue::U32(GpuTriangle::UNTEXTURED)),
    ("NO_TEXTURE", SharedValue::U32(GpuMaterial::NO_TEXTURE)),
    // `Material::alpha_mode` (alpha.wgsl): none, MASK, BLEND.
    ("ALPHA_OPAQUE", SharedValue::U32(ALPHA_OPAQUE)),
    ("ALPHA_MASK", SharedValue::U32(ALPHA_MASK)),
    ("ALPHA_BLEND", SharedValue::U32(ALPHA_BLEND)),
    (
        "TEXTURE_HEADER_WORDS",
        SharedValue::U32(TextureWords::HEADER_WORDS),
    ),
    (
        "TEXTURE_PREFIX_WORDS",
        SharedValue::U32(TextureWords::PREFIX_WORDS),
    ),
    (
        "TEXTURE_TANGENT_PRESENT",
        SharedValue::U32(TextureWords::TANGENT_PRESENT),
    ),
    // `Material::uv_channels`: the texture slots that read the second
    // channel of texture coordinates.
    (
        "UV_SLOT_BASE",
        SharedValue::U32(crate::layout::UV_SLOT_BASE),
    ),
    (
        "UV_SLOT_METAL_ROUGH",
        SharedValue::U32(crate::layout::UV_SLOT_METAL_ROUGH),
    ),
    (
        "UV_SLOT_NORMAL",
        SharedValue::U32(crate::layout::UV_SLOT_NORMAL),
    ),
    (
        "UV_SLOT_EMISSIVE",
        SharedValue::U32(crate::layout::UV_SLOT_EMISSIVE),
    ),
    (
        "UV_SLOT_OCCLUSION",
        SharedValue::U32(crate::layout::UV_SLOT_OCCLUSION),
    ),
    // Words per mip level in a texture's level table, and the mip modes.
    (
        "TEXTURE_LEVEL_WORDS",
        SharedValue::U32(TextureWords::LEVEL_WORDS),
    ),
    ("TEXTURE_MIP_NONE", SharedValue::U32(TextureWords::MIP_NONE)),
    (
        "TEXTURE_MIP_NEAREST",
        SharedValue::U32(TextureWords::MIP_NEAREST),
    ),
    (
        "TEXTURE_NEAREST",
        SharedValue::U32(TextureWords::FILTER_NEAREST),
    ),
    ("TEXTURE_CLAMP", SharedValue::U32(TextureWords::WRAP_CLAMP)),
    (
        "TEXTURE_MIRROR",
        SharedValue::U32(TextureWords::WRAP_MIRROR),
    ),
    // Texel coordinates are clamped into ±this before they become integers.
    (
        "TEXEL_COORDINATE_LIMIT",
        SharedValue::F32(crate::scene::texture::TEXEL_COORDINATE_LIMIT),
    ),
    // An override (variant.wgsl) that leaves its choice to `params`.
    ("FROM_PARAMS", SharedValue::U32(FROM_PARAMS)),
    // Words per pixel (or per query) in `pixel_costs` and `query_costs`.
    ("COST_WORDS", SharedValue::U32(COST_WORDS as u32)),
    // `@workgroup_size` of `render_tile` and `accumulate_tile`.
    ("TRACE_WORKGROUP_X", SharedValue::U32(TRACE_WORKGROUP.0)),
    ("TRACE_WORKGROUP_Y", SharedValue::U32(TRACE_WORKGROUP.1)),
    // The inspect kernel's log (walk_record.wgsl, bindings/walk_codes.rs): the
    // header, the records' tags, the kinds of ray and the sky's light kind.
    ("INSPECT_LANES", SharedValue::U32(INSPECT_LANES)),
    ("INSPECT_WORDS_USED", SharedValue::U32(log::WORDS_USED)),
    ("INSPECT_SINK", SharedValue::U32(log::SINK)),
    ("INSPECT_HEADER_WORDS", SharedValue::U32(log::HEADER_WORDS)),
    ("INSPECT_RAY", SharedValue::U32(log::RAY)),
    ("INSPECT_SEGMENT", SharedValue::U32(log::SEGMENT)),
    ("INSPECT_NODE", SharedValue::U32(log::NODE)),
    ("INSPECT_LEAF", SharedValue::U32(log::LEAF)),
    ("INSPECT_SKIPPED", SharedValue::U32(log::SKIPPED)),
    ("INSPECT_TESTED", SharedValue::U32(log::TESTED)),
    ("INSPECT_PUSH", SharedValue::U32(log::PUSH)),
    ("INSPECT_POP", SharedValue::U32(log::POP)),
    ("INSPECT_RESTART", SharedValue::U32(log::RESTART)),
    ("INSPECT_ROPE", SharedValue::U32(log::ROPE)),
    ("INSPECT_HIT", SharedValue::U32(log::HIT)),
    ("INSPECT_SAMPLE", SharedValue::U32(log::SAMPLE)),
    ("RAY_PRIMARY", SharedValue::U32(log::RAY_PRIMARY)),
    ("RAY_SHADOW", SharedValue::U32(log::RAY_SHADOW)),
    ("RAY_REFLECTED", SharedValue::U32(log::RAY_REFLECTED)),
    ("RAY_REFRACTED", SharedValue::U32(log::RAY_REFRACTED)),
    ("RAY_BOUNCE", SharedValue::U32(log::RAY_BOUNCE)),
    ("LIGHT_SKY", SharedValue::U32(log::LIGHT_SKY)),
];

/// An override's value (`gpu::kernel_variant`) meaning "read it from
/// `FrameParams` at run time".
pub const FROM_PARAMS: u32 = u32::MAX;

/// The object id of a miss.
pub const NO_OBJECT: u32 = u32::MAX;
/// See `RayCounters::loop_limited`.
pub const LOOP_LIMIT_WARNING: u32 = 32_768;

impl SharedValue {
    /// The value as a WGSL literal that reads back as exactly this value
    /// (Rust prints the shortest decimal that round-trips through f32).
    fn wgsl_literal(self) -> String {
        match self {
            SharedValue::U32(v) => format!("{v}u"),
            SharedValue::F32(v) => format!("{v:e}f"),
        }
    }

    fn wgsl_type(self) -> &'static str {
        match self {
            SharedValue::U32(_) => "u32",
            SharedValue::F32(_) => "f32",
        }
    }
}

fn address_space(access: Access) -> &'static str {
    match access {
        Access::Uniform => "uniform",
        Access::StorageRead => "storage, read",
        Access::StorageReadWrite => "storage, read_write",
    }
}

/// What makes a binding of the kernel needed: a kernel whose frames never
/// read it may declare it as a private one-element placeholder instead
/// ([`wgsl_contract_without`]), which binds nothing. WebGPU grants 8 storage
/// buffers per stage by default and SwiftShader 10, and `accumulate_tile`
/// with every binding has 12.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Need {
    /// The scene has spheres (`SPHERES`).
    Spheres,
    /// The scene has triangles (`TRIANGLES`).
    Triangles,
    /// Some triangle has vertex normals (`SMOOTH_TRIANGLES`).
    SmoothTriangles,
    /// The walk is a k-d walk, not brute force.
    KdWalk,
    /// The walk is the rope walk.
    RopeWalk,
    /// The pass counts the walks' work (`COUNT_COSTS`).
    Costs,
    /// Some material has a texture and some triangle texture coordinates
    /// (`TEXTURES`).
    Textures,
}

impl Need {
    /// Its name in the exported contract.
    pub fn name(self) -> &'static str {
        match self {
            Need::Spheres => "spheres",
            Need::Triangles => "triangles",
            Need::SmoothTriangles => "smooth_triangles",
            Need::KdWalk => "kd_walk",
            Need::RopeWalk => "rope_walk",
            Need::Costs => "costs",
            Need::Textures => "textures",
        }
    }
}

/// The bindings a kernel may leave out, each with what needs it (with one
/// binding per split array; every other binding of `accumulate_tile` is
/// always read).
pub const OPTIONAL_BINDINGS: [(Binding, Need); 9] = [
    (SPHERES, Need::Spheres),
    (TRIANGLES, Need::Triangles),
    (TRIANGLE_NORMALS, Need::SmoothTriangles),
    (KD_NODES, Need::KdWalk),
    (LEAF_OBJECTS, Need::KdWalk),
    (LEAF_ROPES, Need::RopeWalk),
    (LEAF_ROPE_INDEX, Need::RopeWalk),
    (PIXEL_COSTS, Need::Costs),
    (TEXTURES, Need::Textures),
];

/// Bindings whose length the kernel asks (`fn <name>_length() -> u32`,
/// generated beside the declaration; a placeholder's is 1).
const MEASURED: [Binding; 7] = [
    TRIANGLES,
    KD_NODES,
    LEAF_OBJECTS,
    LEAF_ROPES,
    LEAF_ROPE_INDEX,
    TRIANGLE_NORMALS,
    PIXEL_COSTS,
];

/// The WGSL text generated from this module for `chunks` bindings per split
/// array: the shared constants, the binding declarations (the struct types
/// they name are in shaders/types.wgsl) and each split array's chunk reader.
pub fn wgsl_contract(chunks: SceneChunks) -> String {
    wgsl_contract_without(chunks, &[])
}

/// [`wgsl_contract`] with each of `omitted` (of [`OPTIONAL_BINDINGS`])
/// declared as a private one-element array, not a binding: for a kernel
/// whose frames never read them.
pub fn wgsl_contract_without(chunks: SceneChunks, omitted: &[Binding]) -> String {
    wgsl_contract_of(&ENTRY_POINTS, chunks, omitted)
}

/// [`wgsl_contract_without`] for a kernel of `entry_points` (the trace
/// kernel's [`ENTRY_POINTS`], or the inspect kernel's
/// [`INSPECT_ENTRY_POINTS`]).
pub fn wgsl_contract_of(
    entry_points: &[EntryPoint],
    chunks: SceneChunks,
    omitted: &[Binding],
) -> String {
    let mut text = String::from("// Generated from src/gpu/bindings/mod.rs: edit it there.\n");
    for (name, value) in SHARED_CONSTANTS {
        text += &format!(
            "const {name}: {} = {};\n",
            value.wgsl_type(),
            value.wgsl_literal()
        );
    }
    for b in declared(chunks, entry_points) {
        text += &declaration(&b, !omitted.contains(&b));
    }
    for (array, chunks) in SPLIT_ARRAYS.iter().zip(chunks) {
        text += &array.wgsl_reader(chunks);
    }
    text
}

/// [`crate::gpu::PresentParams::tone_map`]: the mean clamped to [0, 1] and quantised.
pub const PRESENT_QUANTISE: u32 = 0;
/// [`crate::gpu::PresentParams::tone_map`]: ACES, then sRGB (`ToneMap::Aces`).
pub const PRESENT_ACES: u32 = 1;
/// [`crate::gpu::PresentParams::tone_map`]: clamped, then sRGB (`ToneMap::Clamp`).
pub const PRESENT_CLAMP_SRGB: u32 = 2;

/// The constants the present pass and the host agree on: how a pixel's
/// mean becomes its shown level (`PresentParams::tone_map`).
pub const PRESENT_CONSTANTS: [(&str, SharedValue); 3] = [
    ("PRESENT_QUANTISE", SharedValue::U32(PRESENT_QUANTISE)),
    ("PRESENT_ACES", SharedValue::U32(PRESENT_ACES)),
    ("PRESENT_CLAMP_SRGB", SharedValue::U32(PRESENT_CLAMP_SRGB)),
];

/// The present pass's generated constants and declarations (the struct
/// they name is in shaders/present.wgsl).
pub fn wgsl_present_contract() -> String {
    let mut text = String::from("// Generated from src/gpu/bindings/mod.rs: edit it there.\n");
    for (name, value) in PRESENT_CONSTANTS {
        text += &format!(
            "const {name}: {} = {};\n",
            value.wgsl_type(),
            value.wgsl_literal()
        );
    }
    text + &declarations(&PRESENT_BINDINGS)
}

/// The line overlay's generated declarations: its binding.
pub fn wgsl_overlay_contract() -> String {
    String::from("// Generated from src/gpu/bindings/mod.rs: edit it there.\n")
        + &declarations(&OVERLAY_BINDINGS)
}

/// `@group(0) @binding(index) var<...> name: type;` for each of `bindings`.
fn declarations(bindings: &[Binding]) -> String {
    bindings.iter().map(|b| declaration(b, true)).collect()
}

/// `b`'s declaration: bound, `@group(0) @binding(index) var<...> name:
/// type;`, else a private `array<element, 1>` of the same name; then, for a
/// binding the kernel measures, `fn <name>_length() -> u32` (its
/// `arrayLength`, or 1 for the placeholder). The export hands both forms to
/// the page, which swaps one for the other (src/web).
pub fn declaration(b: &Binding, bound: bool) -> String {
    let mut text = if bound {
        format!(
            "@group(0) @binding({}) var<{}> {}: {};\n",
            b.index,
            address_space(b.access),
            b.name,
            b.wgsl_type
        )
    } else {
        format!("var<private> {}: array<{}, 1>;\n", b.name, b.element_type())
    };
    if MEASURED.contains(b) {
        let length = if bound {
            format!("arrayLength(&{})", b.name)
        } else {
            "1u".to_string()
        };
        text += &format!("fn {}_length() -> u32 {{ return {length}; }}\n", b.name);
    }
    text
}

/// Layout entries for `bindings`, all visible to `stages`.
pub fn layout_entries(
    bindings: &[Binding],
    stages: wgpu::ShaderStages,
) -> Vec<wgpu::BindGroupLayoutEntry> {
    bindings
        .iter()
        .map(|b| wgpu::BindGroupLayoutEntry {
            binding: b.index,
            visibility: stages,
            ty: wgpu::BindingType::Buffer {
                ty: match b.access {
                    Access::Uniform => wgpu::BufferBindingType::Uniform,
                    Access::StorageRead => wgpu::BufferBindingType::Storage { read_only: true },
                    Access::StorageReadWrite => {
                        wgpu::BufferBindingType::Storage { read_only: false }
                    }
                },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect()
}
