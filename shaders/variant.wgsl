// What this pipeline is specialised for: pipeline-overridable constants the
// host sets per scene and frame and folds away before the driver sees the
// kernel (src/gpu/specialise.rs; src/gpu/kernel_variant.rs says why:
// llvmpipe runs a branch by masking lanes, not by jumping, so code a frame
// cannot reach still costs it unless the compiler removes it). The defaults
// are the general variant, which reads every choice from `params`.

// Whether the scene's arrays may be split over several bindings
// (chunks.wgsl). Measured on lavapipe (torus scene, release build),
// selecting the chunk at run time cost 25-45% of the frame even when the
// branch was uniform.
override SPLIT_SCENE: bool = true;
// ACCEL_KDTREE or ACCEL_BRUTE; FROM_PARAMS: `params.accel`.
override ACCEL: u32 = FROM_PARAMS;
// TRAVERSAL_RESTART, _ROPES or _SHORT_STACK; FROM_PARAMS: `params.traversal`.
override TRAVERSAL: u32 = FROM_PARAMS;
// Whether the scene may hold spheres, and triangles.
override SPHERES: bool = true;
override TRIANGLES: bool = true;
// Whether a triangle may have vertex normals.
override SMOOTH_TRIANGLES: bool = true;
// Whether a material may transmit (glass.wgsl): without it the path is the
// opaque one, so scenes without glass pay nothing for it.
override GLASS: bool = true;
// Whether a triangle may be textured (texture.wgsl): without it the
// material is read as it was before textures.
override TEXTURES: bool = true;
// Whether a material may have an alpha mode (alpha.wgsl): without it the
// walks' object test is the geometric one, so opaque scenes pay nothing.
override ALPHA_TEST: bool = true;
// Whether a scene light may be a spot or directional light (shade.wgsl,
// emitters.wgsl): without, every one is a point light. Measured on lavapipe (release build,
// 640 x 360), the kinds' branches cost the seed's and the mirrors' scenes,
// which have point lights only, 4 - 7% of their frame.
override SPOT_OR_DIRECTIONAL_LIGHTS: bool = true;
// Whether the walks count their work (walk_cost in traverse.wgsl): frames
// that report it (--stats, the heatmap, bench's counted frame, the window)
// and the ray-query kernel. Counting is private register adds, yet without
// it llvmpipe runs 4.7% fewer instructions for the bunny and its frame is
// 1 - 3% shorter (docs/design.md, "Counting only when asked").
override COUNT_COSTS: bool = true;
// INTEGRATOR_WHITTED (trace.wgsl, glass.wgsl) or INTEGRATOR_PATH
// (path.wgsl); FROM_PARAMS: `params.integrator`.
override INTEGRATOR: u32 = FROM_PARAMS;
// Whether render_tile writes each pixel's radiance sums as floats (the path
// tracer, and EXR output) instead of 8-bit colour.
override RADIANCE_OUTPUT: bool = false;
// Whether render_tile with RADIANCE_OUTPUT also writes each pixel's feature
// sums for the denoiser (path.wgsl, "Features"): the albedo and shading
// normal of its samples' first hits that are not a perfect mirror or
// smooth glass. Without it the path tracer is the plain one.
override FEATURE_OUTPUT: bool = false;

// The kind of a scene light (LIGHT_POINT, _SPOT or _DIRECTIONAL) as the
// pipeline sees it: a point light where the scene has no other kind.
fn scene_light_kind(kind: u32) -> u32 {
    if (!SPOT_OR_DIRECTIONAL_LIGHTS) {
        return LIGHT_POINT;
    }
    return kind;
}

// Whether the frame is path traced.
fn is_path() -> bool {
    if (INTEGRATOR != FROM_PARAMS) {
        return INTEGRATOR == INTEGRATOR_PATH;
    }
    return params.integrator == INTEGRATOR_PATH;
}

fn frame_accel() -> u32 {
    if (ACCEL != FROM_PARAMS) {
        return ACCEL;
    }
    return params.accel;
}

fn frame_traversal() -> u32 {
    if (TRAVERSAL != FROM_PARAMS) {
        return TRAVERSAL;
    }
    return params.traversal;
}

// Whether object `id` is a sphere (spheres come first, then triangles).
fn is_sphere(id: u32) -> bool {
    if (!TRIANGLES) {
        return true;
    }
    if (!SPHERES) {
        return false;
    }
    return id < params.sphere_count;
}
