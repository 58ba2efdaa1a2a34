// Base-colour textures (src/scene/texture.rs states the rule; its `sample`
// is the CPU mirror): at a textured triangle's hit the texture coordinates
// are interpolated with the hit's barycentrics, the texture is sampled
// there (point or bilinear at its one level, texel centres at
// (i + 0.5) / size, each axis wrapped by its mode) and the texel multiplies
// the material's diffuse and ambient colours. The `textures` buffer's
// layout: src/layout/texture_words.rs, TextureWords. Without TEXTURES the material is
// read as before.

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

// Texel (x, y) of the texture whose header starts at word `header`.
fn texel(header: u32, x: i32, y: i32) -> vec3<f32> {
    let width = textures[header + 1u];
    let xi = wrap_texel(x, i32(width), textures[header + 4u]);
    let yi = wrap_texel(y, i32(textures[header + 2u]), textures[header + 5u]);
    return unpack4x8unorm(textures[textures[header] + u32(yi) * width + u32(xi)]).xyz;
}

// a * (1 - t) + b * t, spelled out as the CPU mirror computes it.
fn lerp3(a: vec3<f32>, b: vec3<f32>, t: f32) -> vec3<f32> {
    return a * (1.0 - t) + b * t;
}

// Texture `t` at texture coordinates uv (v down from the image's top row).
fn sample_texture(t: u32, uv: vec2<f32>) -> vec3<f32> {
    let header = 1u + TEXTURE_HEADER_WORDS * t;
    let size = vec2<f32>(f32(textures[header + 1u]), f32(textures[header + 2u]));
    let limit = vec2<f32>(TEXEL_COORDINATE_LIMIT);
    if (textures[header + 3u] == TEXTURE_NEAREST) {
        let p = clamp(floor(uv * size), -limit, limit);
        return texel(header, i32(p.x), i32(p.y));
    }
    let p = clamp(uv * size - 0.5, -limit, limit);
    let p0 = floor(p);
    let f = p - p0;
    let x = i32(p0.x);
    let y = i32(p0.y);
    let top = lerp3(texel(header, x, y), texel(header, x + 1, y), f.x);
    let bottom = lerp3(texel(header, x, y + 1), texel(header, x + 1, y + 1), f.x);
    return lerp3(top, bottom, f.y);
}

fn record_uv(word: u32) -> vec2<f32> {
    return vec2<f32>(bitcast<f32>(textures[word]), bitcast<f32>(textures[word + 1u]));
}

// The material of object `id` at hit point p: its diffuse and ambient
// colours multiplied by its texture where the object is a textured triangle.
fn material_at(id: u32, p: vec3<f32>) -> Material {
    var m = materials[objects[id].x];
    if (!TEXTURES || m.texture == NO_TEXTURE || is_sphere(id)) {
        return m;
    }
    let i = id - params.sphere_count;
    let record = triangle_uv_record(i);
    if (record == UNTEXTURED) {
        return m;
    }
    let b = barycentrics(triangle(i), p);
    let r = textures[0] + TEXTURE_RECORD_WORDS * record;
    let uv = b.x * record_uv(r) + b.y * record_uv(r + 2u) + b.z * record_uv(r + 4u);
    let c = sample_texture(m.texture, uv);
    m.diffuse *= c;
    m.ambient *= c;
    return m;
}
