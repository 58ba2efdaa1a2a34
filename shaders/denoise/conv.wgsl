// The denoiser's 3x3 convolution (src/denoise/): one invocation computes
// sixteen output channels of eight pixels side by side in a row; one
// dispatch computes those sixteen channels of a band of rows (from
// `first_row`: the whole image when it is 0 and the dispatch covers every
// row). The input is `src`'s channels, then `skip`'s (the U-Net's
// concatenation, never stored); zero padding of one pixel; bias; ReLU
// unless it is the last layer. Tensors are planar CHW f32.
//
// Why so much per invocation: llvmpipe runs invocations side by side in
// SIMD lanes, and a load at a per-lane index costs it one load per lane,
// so the tensor reads, not the multiplies, set the time. Eight pixels
// share the ten columns of each of the three rows they read, and sixteen
// outputs share each value read: on a 64-channel layer this ran 4.3 times
// faster than one pixel's eight outputs an invocation (more pixels or
// outputs spilled registers and ran slower).
//
// The weights are two uniform blocks of at most 64 KiB each, bound at their
// offsets in the network's weights buffer: `weights` holds outputs
// first_output .. + 7, `weights_hi` the next eight (for a layer whose last
// outputs fit one block, the same block again: those outputs are padding
// and never stored). A block holds its eight biases in its first two
// vec4s, then for input channel i and tap t (ky * 3 + kx) the eight
// weights in the two vec4s at 2 + (i * 9 + t) * 2. Every index into them
// is the same for all invocations, so a weight is read once for all of
// them (from a storage buffer llvmpipe read it per invocation). Loops run
// over input channels only (at most 160 for the U-Net: far under
// llvmpipe's 65,535 iterations); the rest is written out, as llvmpipe
// keeps named values in registers where it would index private arrays in
// memory (a version with loops over pixels and taps ran 5 times slower).

struct ConvParams {
    width: u32,
    height: u32,
    src_channels: u32,
    skip_channels: u32,
    // Output channels stored (the last dispatch's may be partly padding).
    out_channels: u32,
    // This dispatch's outputs: first_output .. first_output + 15.
    first_output: u32,
    relu: u32,
    // The band's first row: invocation row 0 computes this row.
    first_row: u32,
}

@group(0) @binding(0) var<uniform> p: ConvParams;
@group(0) @binding(1) var<uniform> weights: array<vec4<f32>, 4096>;
@group(0) @binding(2) var<uniform> weights_hi: array<vec4<f32>, 4096>;
@group(0) @binding(3) var<storage, read> src: array<f32>;
@group(0) @binding(4) var<storage, read> skip: array<f32>;
@group(0) @binding(5) var<storage, read_write> dst: array<f32>;

// The ten columns x0 - 1 .. x0 + 8 an invocation reads, clamped into the
// row, and their masks (0 outside the image: zero padding).
struct Columns {
    c0: u32, c1: u32, c2: u32, c3: u32, c4: u32, c5: u32, c6: u32, c7: u32, c8: u32, c9: u32,
    m0: f32, m1: f32, m2: f32, m3: f32, m4: f32, m5: f32, m6: f32, m7: f32, m8: f32, m9: f32,
}

// 1 where column x is in the image, else 0.
fn inside(x: u32) -> f32 {
    return select(1.0, 0.0, x >= p.width);
}

// One row's ten values, masked.
struct Row {
    v0: f32, v1: f32, v2: f32, v3: f32, v4: f32, v5: f32, v6: f32, v7: f32, v8: f32, v9: f32,
}

// Sixteen output channels.
struct Out16 { a: vec4<f32>, b: vec4<f32>, c: vec4<f32>, d: vec4<f32> }

// The eight pixels' outputs.
struct Acc {
    p0: Out16, p1: Out16, p2: Out16, p3: Out16, p4: Out16, p5: Out16, p6: Out16, p7: Out16,
}

fn fma16(o: Out16, x: f32, w: Out16) -> Out16 {
    return Out16(o.a + x * w.a, o.b + x * w.b, o.c + x * w.c, o.d + x * w.d);
}

// The sixteen weights of tap entry k (input channel and tap).
fn tap_weights(k: u32) -> Out16 {
    return Out16(weights[k], weights[k + 1u], weights_hi[k], weights_hi[k + 1u]);
}

// One kernel row's three taps over the eight pixels; `k` is the first
// tap's vec4 in the blocks.
fn add_row(acc: Acc, r: Row, k: u32) -> Acc {
    let w0 = tap_weights(k);
    let w1 = tap_weights(k + 2u);
    let w2 = tap_weights(k + 4u);
    var a = acc;
    a.p0 = fma16(fma16(fma16(a.p0, r.v0, w0), r.v1, w1), r.v2, w2);
    a.p1 = fma16(fma16(fma16(a.p1, r.v1, w0), r.v2, w1), r.v3, w2);
    a.p2 = fma16(fma16(fma16(a.p2, r.v2, w0), r.v3, w1), r.v4, w2);
    a.p3 = fma16(fma16(fma16(a.p3, r.v3, w0), r.v4, w1), r.v5, w2);
    a.p4 = fma16(fma16(fma16(a.p4, r.v4, w0), r.v5, w1), r.v6, w2);
    a.p5 = fma16(fma16(fma16(a.p5, r.v5, w0), r.v6, w1), r.v7, w2);
    a.p6 = fma16(fma16(fma16(a.p6, r.v6, w0), r.v7, w1), r.v8, w2);
    a.p7 = fma16(fma16(fma16(a.p7, r.v7, w0), r.v8, w1), r.v9, w2);
    return a;
}

fn src_row(k: u32, c: Columns, m: f32) -> Row {
    return Row(src[k + c.c0] * m * c.m0, src[k + c.c1] * m * c.m1, src[k + c.c2] * m * c.m2,
        src[k + c.c3] * m * c.m3, src[k + c.c4] * m * c.m4, src[k + c.c5] * m * c.m5,
        src[k + c.c6] * m * c.m6, src[k + c.c7] * m * c.m7, src[k + c.c8] * m * c.m8,
        src[k + c.c9] * m * c.m9);
}

fn skip_row(k: u32, c: Columns, m: f32) -> Row {
    return Row(skip[k + c.c0] * m * c.m0, skip[k + c.c1] * m * c.m1, skip[k + c.c2] * m * c.m2,
        skip[k + c.c3] * m * c.m3, skip[k + c.c4] * m * c.m4, skip[k + c.c5] * m * c.m5,
        skip[k + c.c6] * m * c.m6, skip[k + c.c7] * m * c.m7, skip[k + c.c8] * m * c.m8,
        skip[k + c.c9] * m * c.m9);
}

// Output channel `o` of `pixel`, unless `o` is padding.
fn store(o: u32, pixel: u32, v: f32) {
    if (o < p.out_channels) {
        dst[o * p.width * p.height + pixel] = v;
    }
}

// The sixteen outputs of pixel (x, y), unless x is past the row.
fn store16(x: u32, y: u32, o: Out16) {
    if (x >= p.width) { return; }
    let px = y * p.width + x;
    let g = p.first_output;
    var a = o;
    if (p.relu != 0u) {
        let z = vec4<f32>(0.0);
        a = Out16(max(a.a, z), max(a.b, z), max(a.c, z), max(a.d, z));
    }
    store(g, px, a.a.x); store(g + 1u, px, a.a.y); store(g + 2u, px, a.a.z); store(g + 3u, px, a.a.w);
    store(g + 4u, px, a.b.x); store(g + 5u, px, a.b.y); store(g + 6u, px, a.b.z); store(g + 7u, px, a.b.w);
    store(g + 8u, px, a.c.x); store(g + 9u, px, a.c.y); store(g + 10u, px, a.c.z); store(g + 11u, px, a.c.w);
    store(g + 12u, px, a.d.x); store(g + 13u, px, a.d.y); store(g + 14u, px, a.d.z); store(g + 15u, px, a.d.w);
}

// Invocations past the image compute clamped pixels and store nothing: no
// early return, so every invocation runs the same loop in step.
@compute @workgroup_size(8, 8, 1)
fn conv3x3(@builtin(global_invocation_id) id: vec3<u32>) {
    let w = p.width;
    let x0 = id.x * 8u;
    let row = id.y + p.first_row;
    let y = min(row, p.height - 1u);
    let last = w - 1u;
    var c: Columns;
    c.c0 = select(min(x0, last) - 1u, 0u, x0 == 0u);
    c.c1 = min(x0, last); c.c2 = min(x0 + 1u, last); c.c3 = min(x0 + 2u, last); c.c4 = min(x0 + 3u, last);
    c.c5 = min(x0 + 4u, last); c.c6 = min(x0 + 5u, last); c.c7 = min(x0 + 6u, last); c.c8 = min(x0 + 7u, last);
    c.c9 = min(x0 + 8u, last);
    c.m0 = select(1.0, 0.0, x0 == 0u);
    c.m1 = inside(x0); c.m2 = inside(x0 + 1u); c.m3 = inside(x0 + 2u); c.m4 = inside(x0 + 3u);
    c.m5 = inside(x0 + 4u); c.m6 = inside(x0 + 5u); c.m7 = inside(x0 + 6u); c.m8 = inside(x0 + 7u);
    c.m9 = inside(x0 + 8u);
    let r0 = select(y - 1u, 0u, y == 0u) * w;
    let r1 = y * w;
    let r2 = min(y + 1u, p.height - 1u) * w;
    let m0 = select(1.0, 0.0, y == 0u);
    let m2 = select(1.0, 0.0, y + 1u >= p.height);
    let plane = w * p.height;
    let bias = Out16(weights[0], weights[1], weights_hi[0], weights_hi[1]);
    var acc = Acc(bias, bias, bias, bias, bias, bias, bias, bias);
    for (var i = 0u; i < p.src_channels; i++) {
        let k = i * plane;
        let b = 2u + i * 18u;
        acc = add_row(acc, src_row(k + r0, c, m0), b);
        acc = add_row(acc, src_row(k + r1, c, 1.0), b + 6u);
        acc = add_row(acc, src_row(k + r2, c, m2), b + 12u);
    }
    for (var i = 0u; i < p.skip_channels; i++) {
        let k = i * plane;
        let b = 2u + (p.src_channels + i) * 18u;
        acc = add_row(acc, skip_row(k + r0, c, m0), b);
        acc = add_row(acc, skip_row(k + r1, c, 1.0), b + 6u);
        acc = add_row(acc, skip_row(k + r2, c, m2), b + 12u);
    }
    if (row >= p.height) { return; }
    store16(x0, y, acc.p0); store16(x0 + 1u, y, acc.p1); store16(x0 + 2u, y, acc.p2); store16(x0 + 3u, y, acc.p3);
    store16(x0 + 4u, y, acc.p4); store16(x0 + 5u, y, acc.p5); store16(x0 + 6u, y, acc.p6); store16(x0 + 7u, y, acc.p7);
}
