// The denoiser's input packing and output unpacking (src/denoise/), as
// crates/kdray-core/src/denoise/pack.rs does on the CPU (OIDN 1.4.3's HDR
// conventions): colour scaled, sanitised and mapped by the normalised PU
// transfer function; albedo clamped to [0, 1]; normal clamped to [-1, 1]
// and mapped to [0, 1]; zero outside the image. The output goes back
// through the inverse PU and the inverse scale.
//
// `images` holds the tile's source rectangle of each image (colour, then
// albedo, then normal if present), three floats a pixel, row-major.

struct PackParams {
    // The tile's tensor size.
    tile_width: u32,
    tile_height: u32,
    // The source rectangle's size and where it starts in the tensor.
    src_width: u32,
    src_height: u32,
    offset_x: u32,
    offset_y: u32,
    // 3, 6 or 9.
    channels: u32,
    // The output rectangle, relative to the source rectangle (unpack).
    out_x: u32,
    out_y: u32,
    out_width: u32,
    out_height: u32,
    input_scale: f32,
    // 1 / input_scale, or 0 if the scale is 0.
    output_scale: f32,
    // 1 / PU(65504), and PU(65504).
    pu_norm: f32,
    pu_max: f32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> p: PackParams;
@group(0) @binding(1) var<storage, read> images: array<f32>;
@group(0) @binding(2) var<storage, read_write> tensor: array<f32>;

const PU_A: f32 = 1.41283765e+03;
const PU_B: f32 = 1.64593172e+00;
const PU_C: f32 = 4.31384981e-01;
const PU_D: f32 = -2.94139609e-03;
const PU_E: f32 = 1.92653254e-01;
const PU_F: f32 = 6.26026094e-03;
const PU_G: f32 = 9.98620152e-01;
const PU_Y0: f32 = 1.57945760e-06;
const PU_Y1: f32 = 3.22087631e-02;
const PU_X0: f32 = 2.23151711e-03;
const PU_X1: f32 = 3.70974749e-01;
// The largest f32, exactly: the decimal 3.40282347e+38 lies just above
// it, which Chromium's WGSL compiler refuses as out of range.
const F32_MAX: f32 = 0x1.fffffep+127f;

fn pu_forward(y: f32) -> f32 {
    if (y <= PU_Y0) {
        return PU_A * y;
    }
    if (y <= PU_Y1) {
        return PU_B * pow(y, PU_C) + PU_D;
    }
    return PU_E * log(y + PU_F) + PU_G;
}

fn pu_inverse(x: f32) -> f32 {
    if (x <= PU_X0) {
        return x / PU_A;
    }
    if (x <= PU_X1) {
        return pow((x - PU_D) / PU_B, 1.0 / PU_C);
    }
    return exp((x - PU_G) / PU_E) - PU_F;
}

// NaN to zero, then clamped to [lo, hi]. WGSL may assume no NaN in
// arithmetic, so NaN is found by its bits (exponent all ones, mantissa not 0).
fn sanitize(v: f32, lo: f32, hi: f32) -> f32 {
    let bits = bitcast<u32>(v);
    let is_nan = (bits & 0x7f800000u) == 0x7f800000u && (bits & 0x007fffffu) != 0u;
    return select(clamp(v, lo, hi), 0.0, is_nan);
}

@compute @workgroup_size(8, 8, 1)
fn pack_tile(@builtin(global_invocation_id) id: vec3<u32>) {
    let x = id.x;
    let y = id.y;
    if (x >= p.tile_width || y >= p.tile_height) {
        return;
    }
    let plane = p.tile_width * p.tile_height;
    let pixel = y * p.tile_width + x;
    let inside = x >= p.offset_x && y >= p.offset_y
        && x - p.offset_x < p.src_width && y - p.offset_y < p.src_height;
    if (!inside) {
        for (var c = 0u; c < p.channels; c++) {
            tensor[c * plane + pixel] = 0.0;
        }
        return;
    }
    let region = p.src_width * p.src_height * 3u;
    let at = ((y - p.offset_y) * p.src_width + (x - p.offset_x)) * 3u;
    for (var c = 0u; c < 3u; c++) {
        let v = sanitize(images[at + c] * p.input_scale, 0.0, F32_MAX);
        tensor[c * plane + pixel] = pu_forward(v) * p.pu_norm;
    }
    if (p.channels >= 6u) {
        for (var c = 0u; c < 3u; c++) {
            tensor[(3u + c) * plane + pixel] = sanitize(images[region + at + c], 0.0, 1.0);
        }
    }
    if (p.channels >= 9u) {
        for (var c = 0u; c < 3u; c++) {
            let n = sanitize(images[2u * region + at + c], -1.0, 1.0);
            tensor[(6u + c) * plane + pixel] = n * 0.5 + 0.5;
        }
    }
}

// Writes the output rectangle's pixels (three floats each, row-major) into
// `tensor`, which here is the output buffer; the network's output is
// bound as `images`.
@compute @workgroup_size(8, 8, 1)
fn unpack_tile(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= p.out_width || id.y >= p.out_height) {
        return;
    }
    let plane = p.tile_width * p.tile_height;
    let tx = p.offset_x + p.out_x + id.x;
    let ty = p.offset_y + p.out_y + id.y;
    let at = (id.y * p.out_width + id.x) * 3u;
    for (var c = 0u; c < 3u; c++) {
        let v = sanitize(images[c * plane + ty * p.tile_width + tx], 0.0, F32_MAX);
        tensor[at + c] = pu_inverse(v * p.pu_max) * p.output_scale;
    }
}
