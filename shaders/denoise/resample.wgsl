// The denoiser's 2x2 max pooling (stride 2) and 2x nearest-neighbour
// upsampling (src/denoise/): one invocation per output value, the z of the
// dispatch the channel. Tensors are planar CHW f32; `width` and `height`
// are the output's (the input's are twice or half as large).

struct ResampleParams {
    width: u32,
    height: u32,
    channels: u32,
    pad: u32,
}

@group(0) @binding(0) var<uniform> p: ResampleParams;
@group(0) @binding(1) var<storage, read> src: array<f32>;
@group(0) @binding(2) var<storage, read_write> dst: array<f32>;

@compute @workgroup_size(8, 8, 1)
fn max_pool2(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= p.width || id.y >= p.height || id.z >= p.channels) {
        return;
    }
    let src_width = p.width * 2u;
    let base = (id.z * p.height * 2u + id.y * 2u) * src_width + id.x * 2u;
    let m = max(max(src[base], src[base + 1u]), max(src[base + src_width], src[base + src_width + 1u]));
    dst[(id.z * p.height + id.y) * p.width + id.x] = m;
}

@compute @workgroup_size(8, 8, 1)
fn upsample2(@builtin(global_invocation_id) id: vec3<u32>) {
    if (id.x >= p.width || id.y >= p.height || id.z >= p.channels) {
        return;
    }
    let src_width = p.width / 2u;
    let src_height = p.height / 2u;
    let v = src[(id.z * src_height + id.y / 2u) * src_width + id.x / 2u];
    dst[(id.z * p.height + id.y) * p.width + id.x] = v;
}
