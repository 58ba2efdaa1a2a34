// The interactive window's present pass: a fullscreen triangle whose
// fragments show the accumulation buffer that trace.wgsl's accumulate_tile
// fills. Compiled on its own, after the bindings gpu/bindings/ generates
// (PRESENT_BINDINGS: `present`, `accumulation`, `preview`).
//
// Each pixel's mean (sum / count) becomes the level the headless PNG would
// hold, written as that level / 255 to a non-sRGB (Unorm) target, so the
// window shows the PNG's pixel values: Whitted colours (and the heatmap)
// quantised as render_tile does, floor(255 * clamp(mean, 0, 1) + 0.5); path
// radiance scaled by 2^exposure, through ToneMap::to_srgb8's curve (ACES or
// a clamp) and the sRGB transfer function, then quantised alike. The preview, a smaller image traced while the camera moves,
// shows where the image has no sample yet; each window pixel shows the pixel
// of the image (or preview) it falls in.

struct PresentParams {
    // Size of the image in the accumulation buffer (row-major, this wide).
    image_size: vec2<u32>,
    // Size of the target in pixels.
    target_size: vec2<u32>,
    // Size of the preview (0 x 0: none).
    preview_size: vec2<u32>,
    // 0: show the preview only (the image is out of date).
    show_image: u32,
    // PRESENT_QUANTISE, PRESENT_ACES or PRESENT_CLAMP_SRGB.
    tone_map: u32,
    // 2^exposure (path radiance only).
    exposure_scale: f32,
    _pad: u32,
}

// The shown value of a pixel's mean, as ToneMap::to_srgb8 (before its
// quantisation) for path radiance.
fn tone_mapped(mean: vec3<f32>) -> vec3<f32> {
    if (present.tone_map == PRESENT_QUANTISE) {
        return clamp(mean, vec3<f32>(0.0), vec3<f32>(1.0));
    }
    var v = mean * present.exposure_scale;
    if (present.tone_map == PRESENT_ACES) {
        v = max(v, vec3<f32>(0.0));
        v = (v * (2.51 * v + 0.03)) / (v * (2.43 * v + 0.59) + 0.14);
    }
    let c = clamp(v, vec3<f32>(0.0), vec3<f32>(1.0));
    let curve = 1.055 * pow(c, vec3<f32>(1.0 / 2.4)) - 0.055;
    return select(curve, 12.92 * c, c <= vec3<f32>(0.0031308));
}

// One triangle covering the target: (-1, -1), (3, -1), (-1, 3).
@vertex
fn vs_main(@builtin(vertex_index) index: u32) -> @builtin(position) vec4<f32> {
    let x = f32((index & 1u) * 4u) - 1.0;
    let y = f32((index >> 1u) * 4u) - 1.0;
    return vec4<f32>(x, y, 0.0, 1.0);
}

// The pixel of a `size` image that target pixel `p` falls in.
fn image_index(p: vec2<u32>, size: vec2<u32>) -> u32 {
    let target_size = max(present.target_size, vec2<u32>(1u));
    let q = min(p * size / target_size, size - vec2<u32>(1u));
    return q.y * size.x + q.x;
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    // Framebuffer coordinates: origin at the top left, pixel centres at .5.
    let p = vec2<u32>(frag.xy);
    var a = vec4<f32>(0.0);
    if (present.show_image != 0u && all(present.image_size > vec2<u32>(0u))) {
        a = accumulation[image_index(p, present.image_size)];
    }
    if (a.w <= 0.0 && all(present.preview_size > vec2<u32>(0u))) {
        a = preview[image_index(p, present.preview_size)];
    }
    if (a.w <= 0.0) {
        return vec4<f32>(0.0, 0.0, 0.0, 1.0);
    }
    let c = tone_mapped(a.xyz / a.w);
    return vec4<f32>(floor(255.0 * c + 0.5) / 255.0, 1.0);
}
