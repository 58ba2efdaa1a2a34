// Base-colour textures (crates/kdray-core/src/scene/texture/ states the
// rule; its `sample_lod` is the CPU mirror, and its ray_cone.rs mirrors the
// level of detail): at a textured triangle's hit the texture coordinates
// are interpolated with the hit's barycentrics; the level of detail lambda
// comes from the ray cone's width there (the pixel's spread angle times the
// path's length from the eye); lambda <= 0 reads the base level with the
// magnification filter, above 0 the minification filter reads the base
// level, the nearest mip level or the two nearest blended (point or
// bilinear within a level, texel centres at (i + 0.5) / the level's size,
// each axis wrapped by its mode); the texel multiplies the material's
// diffuse and ambient colours (`material_at`, surface.wgsl). The `textures`
// buffer's layout: crates/kdray-core/src/layout/texture_words.rs,
// TextureWords. Without TEXTURES the material is read as before.

// The record of texture coordinates of triangle i (the third vertex's
// padding), or UNTEXTURED.
fn triangle_uv_record(i: u32) -> u32 {
    if (!SPLIT_SCENE) {
        return bitcast<u32>(triangles[i][2].w);
    }
    let at = chunk_index(i, triangles_length(), TRIANGLES_CHUNKS);
    return bitcast<u32>(triangles_chunk(at.chunk, at.index)[2].w);
}

// Texel index i of an axis of n texels, wrapped into 0..n-1 (|i| <= 2^24).
fn wrap_texel(i: i32, n: i32, mode: u32) -> i32 {
    if (mode == TEXTURE_CLAMP) {
        return clamp(i, 0, n - 1);
    }
    if (mode == TEXTURE_MIRROR) {
        let period = 2 * n;
        let m = ((i % period) + period) % period;
        return select(m, period - 1 - m, m >= n);
    }
    return ((i % n) + n) % n;
}

// One mip level of a texture: where its texels start, its size, and the
// texture's wrap modes along u and v.
struct TextureLevel {
    first: u32,
    width: u32,
    height: u32,
    wrap: vec2<u32>,
}

// Level k of the texture whose header starts at word `header`.
fn texture_level(header: u32, k: u32) -> TextureLevel {
    let entry = textures[header] + TEXTURE_LEVEL_WORDS * k;
    return TextureLevel(
        textures[entry],
        textures[entry + 1u],
        textures[entry + 2u],
        vec2<u32>(textures[header + 5u], textures[header + 6u])
    );
}

// Texel (x, y) of `level`, wrapped into it: byte / 255, or with `srgb`
// decoded from the sRGB transfer function to linear (the path tracer's
// colour textures).
fn texel(level: TextureLevel, x: i32, y: i32, srgb: bool) -> vec3<f32> {
    let xi = wrap_texel(x, i32(level.width), level.wrap.x);
    let yi = wrap_texel(y, i32(level.height), level.wrap.y);
    let c = unpack4x8unorm(textures[level.first + u32(yi) * level.width + u32(xi)]).xyz;
    if (srgb) {
        return srgb_to_linear(c);
    }
    return c;
}

// The sRGB transfer function's inverse (IEC 61966-2-1), per channel.
fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let curve = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(curve, c / 12.92, c <= vec3<f32>(0.04045));
}

// a * (1 - t) + b * t, spelled out as the CPU mirror computes it.
fn lerp3(a: vec3<f32>, b: vec3<f32>, t: f32) -> vec3<f32> {
    return a * (1.0 - t) + b * t;
}

// Level k of the texture at `header`, at uv, point (TEXTURE_NEAREST) or
// bilinear.
fn sample_level(header: u32, k: u32, filter_mode: u32, uv: vec2<f32>, srgb: bool) -> vec3<f32> {
    let level = texture_level(header, k);
    let size = vec2<f32>(f32(level.width), f32(level.height));
    let limit = vec2<f32>(TEXEL_COORDINATE_LIMIT);
    if (filter_mode == TEXTURE_NEAREST) {
        let p = clamp(floor(uv * size), -limit, limit);
        return texel(level, i32(p.x), i32(p.y), srgb);
    }
    let p = clamp(uv * size - 0.5, -limit, limit);
    let p0 = floor(p);
    let f = p - p0;
    let x = i32(p0.x);
    let y = i32(p0.y);
    let top = lerp3(texel(level, x, y, srgb), texel(level, x + 1, y, srgb), f.x);
    let bottom = lerp3(texel(level, x, y + 1, srgb), texel(level, x + 1, y + 1, srgb), f.x);
    return lerp3(top, bottom, f.y);
}

// Texture `t` at texture coordinates uv (v down from the image's top row)
// and level of detail lambda, its texels decoded from sRGB if `srgb`.
fn sample_texture(t: u32, uv: vec2<f32>, lambda: f32, srgb: bool) -> vec3<f32> {
    let header = TEXTURE_PREFIX_WORDS + TEXTURE_HEADER_WORDS * t;
    if (lambda <= 0.0) {
        return sample_level(header, 0u, textures[header + 2u], uv, srgb);
    }
    let min_filter = textures[header + 3u];
    let mip = textures[header + 4u];
    if (mip == TEXTURE_MIP_NONE) {
        return sample_level(header, 0u, min_filter, uv, srgb);
    }
    let lod = min(lambda, f32(textures[header + 1u] - 1u));
    if (mip == TEXTURE_MIP_NEAREST) {
        return sample_level(header, u32(ceil(lod - 0.5)), min_filter, uv, srgb);
    }
    let l0 = floor(lod);
    let f = lod - l0;
    let a = sample_level(header, u32(l0), min_filter, uv, srgb);
    if (f == 0.0) {
        return a;
    }
    return lerp3(a, sample_level(header, u32(l0) + 1u, min_filter, uv, srgb), f);
}

// The spread angle of one pixel's ray cone, in radians.
fn pixel_spread_angle() -> f32 {
    return atan(2.0 * params.tan_half_vfov / f32(params.height));
}

// lambda = Delta + log2(cone_width) - log2(|n . d|), Delta = 0.5 log2(texel
// area / world area) of triangle `tri` with texture coordinates uv0..uv2 on
// a texture of `size` texels; 0 where a factor is not positive.
fn texture_lod(
    tri: Triangle,
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    uv2: vec2<f32>,
    size: vec2<f32>,
    dir: vec3<f32>,
    cone_width: f32
) -> f32 {
    let n = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    let world_area = length(n);
    let t1 = uv1 - uv0;
    let t2 = uv2 - uv0;
    let texel_area = abs(t1.x * t2.y - t2.x * t1.y) * size.x * size.y;
    let cosine = abs(dot(n, dir)) / world_area;
    if (!(world_area > 0.0 && texel_area > 0.0 && cosine > 0.0 && cone_width > 0.0)) {
        return 0.0;
    }
    return 0.5 * log2(texel_area / world_area) + log2(cone_width) - log2(cosine);
}

// Word k of the buffer's prefix (TextureWords): the records' first word,
// a record's length, where its colours, tangents and second coordinates
// begin. Read through a parameter: where `textures` is a one-word
// placeholder (an adapter short of storage buffers, a frame that reads no
// texture), a constant index past 0 would not validate.
fn texture_prefix(k: u32) -> u32 {
    return textures[k];
}

fn record_uv(word: u32) -> vec2<f32> {
    return vec2<f32>(bitcast<f32>(textures[word]), bitcast<f32>(textures[word + 1u]));
}

// Where a triangle's hit reads its record: the coordinates interpolated
// at the hit, the corners' coordinates, the hit's barycentrics and the
// record's first word; `found` false for a triangle without a record.
struct TextureHit {
    found: bool,
    tri: Triangle,
    uv0: vec2<f32>,
    uv1: vec2<f32>,
    uv2: vec2<f32>,
    uv: vec2<f32>,
    b: vec3<f32>,
    record: u32,
}

fn texture_hit(i: u32, p: vec3<f32>) -> TextureHit {
    let record = triangle_uv_record(i);
    let tri = triangle(i);
    if (record == UNTEXTURED) {
        let zero = vec2<f32>(0.0);
        return TextureHit(false, tri, zero, zero, zero, zero, vec3<f32>(0.0), 0u);
    }
    let b = barycentrics(tri, p);
    let r = texture_prefix(0u) + texture_prefix(1u) * record;
    let uv0 = record_uv(r);
    let uv1 = record_uv(r + 2u);
    let uv2 = record_uv(r + 4u);
    return TextureHit(true, tri, uv0, uv1, uv2, b.x * uv0 + b.y * uv1 + b.z * uv2, b, r);
}

// The hit `h` as material `m`'s texture slot `slot` (UV_SLOT_*) reads it:
// on the second channel of texture coordinates where the material says so.
fn slot_hit(h: TextureHit, m: Material, slot: u32) -> TextureHit {
    let at = texture_prefix(4u);
    if ((m.uv_channels & slot) == 0u || at == 0u || !h.found) {
        return h;
    }
    var s = h;
    s.uv0 = record_uv(h.record + at);
    s.uv1 = record_uv(h.record + at + 2u);
    s.uv2 = record_uv(h.record + at + 4u);
    s.uv = h.b.x * s.uv0 + h.b.y * s.uv1 + h.b.z * s.uv2;
    return s;
}

// Texture `t` at the hit `h`, seen along `dir` with a cone `cone_width` wide.
fn sample_at_hit(t: u32, h: TextureHit, dir: vec3<f32>, cone_width: f32, srgb: bool) -> vec3<f32> {
    let base = texture_level(TEXTURE_PREFIX_WORDS + TEXTURE_HEADER_WORDS * t, 0u);
    let size = vec2<f32>(f32(base.width), f32(base.height));
    let lambda = texture_lod(h.tri, h.uv0, h.uv1, h.uv2, size, dir, cone_width);
    return sample_texture(t, h.uv, lambda, srgb);
}

// What the emissive map makes of emitter `id`'s emission at p, on the
// base level (a light sample has no ray cone): 1 without one.
fn emissive_scale(id: u32, p: vec3<f32>) -> vec3<f32> {
    if (!TEXTURES || is_sphere(id)) {
        return vec3<f32>(1.0);
    }
    let m = materials[objects[id].x];
    if (m.emissive_texture == NO_TEXTURE) {
        return vec3<f32>(1.0);
    }
    let h = slot_hit(texture_hit(id - params.sphere_count, p), m, UV_SLOT_EMISSIVE);
    if (!h.found) {
        return vec3<f32>(1.0);
    }
    return sample_texture(m.emissive_texture, h.uv, 0.0, true);
}
