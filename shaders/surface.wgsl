// What a triangle's record holds beside its texture coordinates
// (src/layout/texture_words.rs, TextureWords): vertex colours, which
// multiply the base colour, and the tangent frame in which its normal map
// bends the shading normal. docs/scene-format.md, "glTF materials", states
// both rules.

// The vertex colour at the hit `h` (linear RGBA, the corners' interpolated
// by the hit's barycentrics): white where the scene has none.
fn vertex_colour(h: TextureHit) -> vec4<f32> {
    let at = texture_prefix(2u);
    if (at == 0u) {
        return vec4<f32>(1.0);
    }
    let r = h.record + at;
    let c0 = vec4<f32>(unpack2x16unorm(textures[r]), unpack2x16unorm(textures[r + 1u]));
    let c1 = vec4<f32>(unpack2x16unorm(textures[r + 2u]), unpack2x16unorm(textures[r + 3u]));
    let c2 = vec4<f32>(unpack2x16unorm(textures[r + 4u]), unpack2x16unorm(textures[r + 5u]));
    return h.b.x * c0 + h.b.y * c1 + h.b.z * c2;
}

// The tangent frame at the hit `h` for the shading normal n: the corners'
// tangents interpolated and made orthogonal to n, and the bitangent's
// sign (that of the interpolated w); w = 0 where the triangle has none.
fn record_tangent(h: TextureHit, n: vec3<f32>) -> vec4<f32> {
    let at = texture_prefix(3u);
    if (at == 0u) {
        return vec4<f32>(0.0);
    }
    let r = h.record + at;
    let flags = textures[r + 3u];
    if ((flags & TEXTURE_TANGENT_PRESENT) == 0u) {
        return vec4<f32>(0.0);
    }
    let t = h.b.x * decode_normal(textures[r]) + h.b.y * decode_normal(textures[r + 1u])
        + h.b.z * decode_normal(textures[r + 2u]);
    let sign = vec3<f32>(
        select(1.0, -1.0, (flags & 1u) != 0u),
        select(1.0, -1.0, (flags & 2u) != 0u),
        select(1.0, -1.0, (flags & 4u) != 0u)
    );
    let w = dot(h.b, sign);
    let ortho = t - n * dot(n, t);
    if (dot(ortho, ortho) <= 0.0 || w == 0.0) {
        return vec4<f32>(0.0);
    }
    return vec4<f32>(normalize(ortho), select(1.0, -1.0, w < 0.0));
}

// The shading normal n (unit, facing the ray) bent by the normal map of
// object `id`'s material at p: the texel's 2c - 1 with x and y scaled by
// the map's scale, in the frame T (the record's tangent made orthogonal to
// n), B = w (n x T), n. n itself where there is no map or no tangent.
fn mapped_normal(id: u32, p: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    if (!TEXTURES || is_sphere(id)) {
        return n;
    }
    let m = materials[objects[id].x];
    if (m.normal_texture == NO_TEXTURE) {
        return n;
    }
    let h = slot_hit(texture_hit(id - params.sphere_count, p), m, UV_SLOT_NORMAL);
    if (!h.found) {
        return n;
    }
    let frame = record_tangent(h, n);
    if (frame.w == 0.0) {
        return n;
    }
    let tangent = frame.xyz;
    let bitangent = frame.w * cross(n, tangent);
    let c = sample_texture(m.normal_texture, h.uv, 0.0, false) * 2.0 - 1.0;
    let bent = tangent * (c.x * m.normal_scale) + bitangent * (c.y * m.normal_scale) + n * c.z;
    if (dot(bent, bent) <= 0.0) {
        return n;
    }
    return normalize(bent);
}
