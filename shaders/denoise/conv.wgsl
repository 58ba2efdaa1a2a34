// The denoiser's 3x3 convolution (src/denoise/): one invocation computes
// eight output channels (one group) of one pixel; one dispatch computes
// one group of a band of rows (from `first_row`; the whole image when it
// is 0 and the dispatch covers every row). The input is `src`'s channels, then `skip`'s
// (the U-Net's concatenation, never stored); zero padding of one pixel;
// bias; ReLU unless it is the last layer. Tensors are planar CHW f32.
//
// The group's weights are a uniform block of at most 64 KiB (bound at the
// group's offset in the network's weights buffer): the eight biases in
// its first two vec4s, then for input channel i and tap t (ky * 3 + kx)
// the eight weights in the two vec4s at 2 + (i * 9 + t) * 2. Every index
// into it is the same for all invocations, so a weight is read once for
// all of them: from a storage buffer llvmpipe read each weight per
// invocation, and the whole denoise ran several times slower. Loops run
// over input channels only (at most 160 for the U-Net: far under
// llvmpipe's 65,535 iterations).

struct ConvParams {
    width: u32,
    height: u32,
    src_channels: u32,
    skip_channels: u32,
    // Output channels stored (the last group may be partly padding).
    out_channels: u32,
    // This dispatch's group: output channels 8 * group ..
    group: u32,
    relu: u32,
    // The band's first row: invocation row 0 computes this row.
    first_row: u32,
}

@group(0) @binding(0) var<uniform> p: ConvParams;
@group(0) @binding(1) var<uniform> weights: array<vec4<f32>, 4096>;
@group(0) @binding(2) var<storage, read> src: array<f32>;
@group(0) @binding(3) var<storage, read> skip: array<f32>;
@group(0) @binding(4) var<storage, read_write> dst: array<f32>;

// The 3x3 neighbourhood's flat indices in one plane (rows and columns
// clamped into the image) and the mask of each tap (0 outside: zero
// padding).
struct Taps {
    r0: u32,
    r1: u32,
    r2: u32,
    c0: u32,
    c1: u32,
    c2: u32,
    m00: f32,
    m01: f32,
    m02: f32,
    m10: f32,
    m12: f32,
    m20: f32,
    m21: f32,
    m22: f32,
}

fn taps(x: u32, y: u32) -> Taps {
    var t: Taps;
    let w = p.width;
    t.r0 = select(y - 1u, 0u, y == 0u) * w;
    t.r1 = y * w;
    t.r2 = min(y + 1u, p.height - 1u) * w;
    t.c0 = select(x - 1u, 0u, x == 0u);
    t.c1 = x;
    t.c2 = min(x + 1u, w - 1u);
    let top = select(1.0, 0.0, y == 0u);
    let bottom = select(1.0, 0.0, y + 1u >= p.height);
    let left = select(1.0, 0.0, x == 0u);
    let right = select(1.0, 0.0, x + 1u >= w);
    t.m00 = top * left;
    t.m01 = top;
    t.m02 = top * right;
    t.m10 = left;
    t.m12 = right;
    t.m20 = bottom * left;
    t.m21 = bottom;
    t.m22 = bottom * right;
    return t;
}

// The group's eight outputs.
struct Acc {
    lo: vec4<f32>,
    hi: vec4<f32>,
}

// Adds nine input values (taps in row-major order) times their weights,
// which start at `b` (two vec4s a tap). Written out: private arrays with
// a dynamic index and short loops cost llvmpipe several times more.
fn madd9(acc: Acc, b: u32, v0: f32, v1: f32, v2: f32, v3: f32, v4: f32, v5: f32, v6: f32, v7: f32, v8: f32) -> Acc {
    var a = acc;
    a.lo += v0 * weights[b] + v1 * weights[b + 2u] + v2 * weights[b + 4u];
    a.hi += v0 * weights[b + 1u] + v1 * weights[b + 3u] + v2 * weights[b + 5u];
    a.lo += v3 * weights[b + 6u] + v4 * weights[b + 8u] + v5 * weights[b + 10u];
    a.hi += v3 * weights[b + 7u] + v4 * weights[b + 9u] + v5 * weights[b + 11u];
    a.lo += v6 * weights[b + 12u] + v7 * weights[b + 14u] + v8 * weights[b + 16u];
    a.hi += v6 * weights[b + 13u] + v7 * weights[b + 15u] + v8 * weights[b + 17u];
    return a;
}

fn add_src(acc: Acc, plane: u32, t: Taps, b: u32) -> Acc {
    let a = plane + t.r0;
    let m = plane + t.r1;
    let z = plane + t.r2;
    return madd9(acc, b,
        src[a + t.c0] * t.m00, src[a + t.c1] * t.m01, src[a + t.c2] * t.m02,
        src[m + t.c0] * t.m10, src[m + t.c1], src[m + t.c2] * t.m12,
        src[z + t.c0] * t.m20, src[z + t.c1] * t.m21, src[z + t.c2] * t.m22);
}

fn add_skip(acc: Acc, plane: u32, t: Taps, b: u32) -> Acc {
    let a = plane + t.r0;
    let m = plane + t.r1;
    let z = plane + t.r2;
    return madd9(acc, b,
        skip[a + t.c0] * t.m00, skip[a + t.c1] * t.m01, skip[a + t.c2] * t.m02,
        skip[m + t.c0] * t.m10, skip[m + t.c1], skip[m + t.c2] * t.m12,
        skip[z + t.c0] * t.m20, skip[z + t.c1] * t.m21, skip[z + t.c2] * t.m22);
}

// Output channel `o` of `pixel`, unless `o` is padding of the last group.
fn store(o: u32, pixel: u32, v: f32) {
    if (o < p.out_channels) {
        dst[o * p.width * p.height + pixel] = v;
    }
}

@compute @workgroup_size(8, 8, 1)
fn conv3x3(@builtin(global_invocation_id) id: vec3<u32>) {
    // Invocations past the edge compute the edge pixel and store nothing:
    // no early return, so every invocation runs the same loop in step.
    let row = id.y + p.first_row;
    let inside = id.x < p.width && row < p.height;
    let x = min(id.x, p.width - 1u);
    let y = min(row, p.height - 1u);
    let g = p.group;
    let t = taps(x, y);
    let plane = p.width * p.height;
    var acc: Acc;
    acc.lo = weights[0];
    acc.hi = weights[1];
    let group_base = 2u;
    for (var i = 0u; i < p.src_channels; i++) {
        acc = add_src(acc, i * plane, t, group_base + i * 18u);
    }
    for (var i = 0u; i < p.skip_channels; i++) {
        acc = add_skip(acc, i * plane, t, group_base + (p.src_channels + i) * 18u);
    }
    if (p.relu != 0u) {
        acc.lo = max(acc.lo, vec4<f32>(0.0));
        acc.hi = max(acc.hi, vec4<f32>(0.0));
    }
    if (!inside) {
        return;
    }
    let pixel = y * p.width + x;
    let o = g * 8u;
    store(o, pixel, acc.lo.x);
    store(o + 1u, pixel, acc.lo.y);
    store(o + 2u, pixel, acc.lo.z);
    store(o + 3u, pixel, acc.lo.w);
    store(o + 4u, pixel, acc.hi.x);
    store(o + 5u, pixel, acc.hi.y);
    store(o + 6u, pixel, acc.hi.z);
    store(o + 7u, pixel, acc.hi.w);
}
