// Data shared with the host. Every struct here mirrors a #[repr(C)] type in
// crates/kdray-core/src/layout/; a unit test checks sizes, offsets and field
// types against naga's layout.

struct KdNode {
    kind: u32,       // 0, 1, 2: inner node splitting x, y, z; 3: leaf
    split: f32,      // inner: the plane's coordinate on axis `kind`
    index: u32,      // inner: right child; leaf: first entry in leaf_objects
    count: u32,      // leaf: number of object ids
}

// A k-d node as stored (crates/kdray-core/src/layout/ GpuKdNode), 8 bytes;
// kd_node() unpacks it into a KdNode.
struct PackedKdNode {
    tag_and_index: u32,   // kind in bits 0-1; inner: above child, leaf: count
    split_or_first: u32,  // inner: the plane (f32 bits); leaf: first entry
}

// A leaf's box and the node beyond each face (crates/kdray-core/src/layout/
// LeafRopes). Face 2 * axis is the low side, 2 * axis + 1 the high side.
struct LeafRopes {
    faces: array<f32, 6>,   // plane coordinate of each face; -inf / +inf on the scene's boundary
    ropes: array<u32, 6>,   // node beyond each face; NO_ROPE on the scene's boundary
}

struct Sphere {
    center: vec3<f32>,
    radius: f32,
}

struct Triangle {
    v0: vec3<f32>,
    normals: u32,    // index into triangle_normals, or FLAT_TRIANGLE
    v1: vec3<f32>,
    scene_id: u32,   // its id in the scene's order (objects[i].y), for ties
    v2: vec3<f32>,
}

// A smooth triangle's unit vertex normals, octahedral-encoded: two 16-bit snorm
// coordinates each, x in the low half (crates/kdray-core/src/layout/
// GpuTriangleNormals).
struct TriangleNormals {
    n0: u32,
    n1: u32,
    n2: u32,
}

struct Material {
    ambient: vec3<f32>,
    shininess: f32,
    diffuse: vec3<f32>,
    reflection: f32,
    specular: vec3<f32>,
    transmission: f32,   // 0 opaque .. 1 clear (glass.wgsl)
    ior: f32,            // index of refraction inside; outside is 1
    texture: u32,        // its base-colour texture (texture.wgsl), or NO_TEXTURE
    metallic: f32,       // path tracer, MODEL_METAL_ROUGH: glTF's metallic
    roughness: f32,      // and perceptual roughness (GGX alpha = roughness^2)
    emission: vec3<f32>, // emitted radiance (path tracer)
    model: u32,          // MODEL_LAMBERTIAN or MODEL_METAL_ROUGH (bsdf.wgsl)
    // The path tracer's maps (texture.wgsl), each or NO_TEXTURE.
    metal_rough_texture: u32,
    emissive_texture: u32,
    normal_texture: u32,
    normal_scale: f32,
    // The walks' alpha test (alpha.wgsl): ALPHA_OPAQUE, _MASK or _BLEND;
    // alpha below the cutoff is a hole; the constant alpha.
    alpha_mode: u32,
    alpha_cutoff: f32,
    alpha_factor: f32,
    // The Whitted integrator's occlusion map (texture.wgsl), or NO_TEXTURE,
    // and its strength in [0, 1].
    occlusion_texture: u32,
    occlusion_strength: f32,
    // The texture slots (UV_SLOT_*) that read the second channel of
    // texture coordinates (texture.wgsl).
    uv_channels: u32,
    two_sided: u32,       // 1: an emitting triangle emits on both sides (emitters.wgsl)
    // Path tracer: the dielectric's perceptual roughness (0: smooth glass,
    // bsdf_dielectric.wgsl; else bsdf_rough_dielectric.wgsl).
    transmission_roughness: f32,
    absorption: vec3<f32>, // path tracer: per scene unit, of the medium inside (0: clear)
    thin_walled: u32,     // path tracer: 1: the dielectric has air on both sides
}

// The lights buffer: `light_count` scene lights (kind LIGHT_POINT,
// LIGHT_SPOT or LIGHT_DIRECTIONAL), then `emitter_count` emissive objects
// (kind LIGHT_EMITTER, `object` their GPU id, in increasing order,
// `diffuse` their radiance), then the light tree's nodes, each in a Light
// record (emitters.wgsl, `light_node`). `pick`, `cdf`, `beyond` and
// `leaf`: the path tracer's choice of a light (emitters.wgsl,
// `sample_light`).
struct Light {
    position: vec3<f32>,  // point and spot lights
    kind: u32,
    ambient: vec3<f32>,
    object: u32,
    diffuse: vec3<f32>,
    cos_outer: f32,       // spot: cosine of the outer cone's half-angle
    specular: vec3<f32>,
    spot_scale: f32,      // spot: 1 / max(cos inner - cos outer, 0.001)
    direction: vec3<f32>, // spot: its axis; directional: where the light travels (unit)
    path_scale: f32,      // point and spot: the path tracer's intensity is diffuse * path_scale
    pick: f32,            // a scene light's probability; an emitter's: its block's, past the scene lights
    cdf: f32,             // a scene light: the sum of the picks before it
    beyond: f32,          // the probability of passing its block
    leaf: u32,            // an emitter: its leaf in the light tree
}

// A node of the emitters' light tree (layout::light_tree::GpuLightNode),
// stored in a Light record after the emitters (emitters.wgsl, `light_node`).
struct LightNode {
    lo: vec3<f32>,        // the box around its emitters
    child: u32,           // inner: its first child (the second follows); leaf: LIGHT_TREE_LEAF | emitter
    hi: vec3<f32>,
    parent: u32,          // LIGHT_TREE_ROOT for the root
    axis: vec3<f32>,      // the cone around its emitters' normals
    cos_theta_o: f32,
    phi: f32,             // its power
    cos_theta_e: f32,     // how far past a normal it emits
    two_sided: u32,
    _pad: u32,
}

struct FrameParams {
    camera_position: vec3<f32>,
    tan_half_vfov: f32,
    camera_forward: vec3<f32>,
    aspect: f32,
    camera_right: vec3<f32>,
    min_intensity: f32,
    camera_up: vec3<f32>,
    max_depth: u32,
    background: vec3<f32>,
    shadow_mode: u32,
    scene_min: vec3<f32>,
    sphere_count: u32,
    scene_max: vec3<f32>,
    object_count: u32,
    width: u32,
    height: u32,
    samples_per_axis: u32,
    light_count: u32,
    tile_origin: vec2<u32>,
    tile_size: vec2<u32>,
    accel: u32,
    node_count: u32,
    // accumulate_tile: which cell of the k x k sample grid this pass traces.
    sample_index: u32,
    traversal: u32,   // TRAVERSAL_RESTART, TRAVERSAL_ROPES or TRAVERSAL_SHORT_STACK
    integrator: u32,  // INTEGRATOR_WHITTED or INTEGRATOR_PATH
    seed: u32,        // the path tracer's random seed
    emitter_count: u32,
    // render_tile with RADIANCE_OUTPUT: samples sample_index ..
    // sample_index + sample_count, added to the pixel's sums.
    sample_count: u32,
    samples: u32,     // of the whole frame (the host's count)
    // [environment] image in `textures` (environment.wgsl); env_width 0: none.
    env_offset: u32,
    env_width: u32,
    env_height: u32,
    env_intensity: f32,
    env_rotation_cos: f32,
    env_rotation_sin: f32,
    _pad0: u32,
}

// Rays traced by one dispatch, by kind; each invocation adds its own counts.
struct RayCounters {
    primary: atomic<u32>,
    shadow: atomic<u32>,
    reflection: atomic<u32>,
    // Invocations whose loops ran LOOP_LIMIT_WARNING iterations or more.
    loop_limited: atomic<u32>,
    // Path samples whose radiance was NaN or infinite (dropped).
    nonfinite: atomic<u32>,
}

// render_tile's output: ray counts, then per pixel of the tile, row-major,
// tile_size.x wide, one packed RGBA8 or, with RADIANCE_OUTPUT, four words:
// the sums of its samples' red, green and blue radiance (f32 bits), unused;
// with FEATURE_OUTPUT too, eight more: the albedo sums, unused, the normal
// sums, unused (trace.wgsl, add_radiance).
struct TileOutput {
    rays: RayCounters,
    pixels: array<u32>,
}

// A ray for `trace_rays` (the debug entry point), and its answer.
struct QueryRay {
    origin: vec3<f32>,
    t_limit: f32,      // nearest hit: t <= t_limit; any hit: t < t_limit
    dir: vec3<f32>,    // unit length
    any_hit: u32,      // 1: shadow-ray query (first hit before t_limit)
}

struct QueryHit {
    t: f32,
    object: u32,       // GPU object id, or NO_OBJECT
}

// Bindings and the constants shared with the host are generated from
// src/gpu/bindings/ and prepended to the kernel.
