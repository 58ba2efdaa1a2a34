// The interactive window's line overlay: world-space segments (an inspected
// pixel's rays, the k-d cells its walks visited and the split planes they
// crossed; src/window/inspect_lines.rs) drawn over the present pass with the
// window camera's projection (src/window/projection.rs), without a depth
// test. Compiled on its own, after the binding gpu/bindings/ generates
// (OVERLAY_BINDINGS: `overlay`).

struct OverlayParams {
    // World position (w = 1) to clip space, column-major.
    view_projection: mat4x4<f32>,
}

// window::inspect_lines::LineVertex: scene units, linear RGB in 0..1.
struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) colour: vec3<f32>,
}

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) colour: vec3<f32>,
}

@vertex
fn vs_line(v: VertexIn) -> VertexOut {
    var out: VertexOut;
    out.clip = overlay.view_projection * vec4<f32>(v.position, 1.0);
    out.colour = v.colour;
    return out;
}

// The colour as is: the target is the present pass's non-sRGB one.
@fragment
fn fs_line(v: VertexOut) -> @location(0) vec4<f32> {
    return vec4<f32>(v.colour, 1.0);
}
