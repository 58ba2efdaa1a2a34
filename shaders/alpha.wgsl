// The walks' alpha test (glTF alphaMode MASK and BLEND): a triangle whose
// material has an alpha mode is not there where its alpha fails, so
// test_object (intersect.wgsl) finds no hit at such a point, in every walk
// and the brute-force loop, for nearest and any hits: primary, reflected,
// shadow and path rays all pass through. Mirrors
// crates/kdray-core/src/geometry/alpha_test.rs; compiled out without ALPHA_TEST.
//
// Alpha at a hit: the material's factor times, on a textured triangle,
// its base-colour texture's alpha at the hit's texture coordinates (the
// first channel, which the base colour always reads; on the base level by
// the magnification filter: a walk has no ray cone), times its vertex
// colours' alpha there. MASK,
// and BLEND outside the path tracer, compare it with `alpha_cutoff`; BLEND
// in the path tracer with a number in (0, 1] hashed from the ray and the
// object, so a ray passes with probability 1 - alpha and every walk of
// that ray decides alike.

// The alpha of texture `t` at uv, on its base level by its magnification
// filter, texel centres at (i + 0.5) / size: sample_level's rule.
fn sample_alpha(t: u32, uv: vec2<f32>) -> f32 {
    let header = TEXTURE_PREFIX_WORDS + TEXTURE_HEADER_WORDS * t;
    let level = texture_level(header, 0u);
    let size = vec2<f32>(f32(level.width), f32(level.height));
    let limit = vec2<f32>(TEXEL_COORDINATE_LIMIT);
    if (textures[header + 2u] == TEXTURE_NEAREST) {
        let p = clamp(floor(uv * size), -limit, limit);
        return texel_alpha(level, i32(p.x), i32(p.y));
    }
    let p = clamp(uv * size - 0.5, -limit, limit);
    let p0 = floor(p);
    let f = p - p0;
    let x = i32(p0.x);
    let y = i32(p0.y);
    let top = texel_alpha(level, x, y) * (1.0 - f.x) + texel_alpha(level, x + 1, y) * f.x;
    let bottom = texel_alpha(level, x, y + 1) * (1.0 - f.x) + texel_alpha(level, x + 1, y + 1) * f.x;
    return top * (1.0 - f.y) + bottom * f.y;
}

// Texel (x, y)'s alpha, wrapped into `level`: byte / 255.
fn texel_alpha(level: TextureLevel, x: i32, y: i32) -> f32 {
    let xi = wrap_texel(x, i32(level.width), level.wrap.x);
    let yi = wrap_texel(y, i32(level.height), level.wrap.y);
    return unpack4x8unorm(textures[level.first + u32(yi) * level.width + u32(xi)]).w;
}

// A number in (0, 1], 24 bits, from the ray's origin and direction (their
// f32 bits) and the object's id in the scene's order.
fn coverage_hash(ray: Ray, scene_id: u32) -> f32 {
    var h = pcg_hash(scene_id);
    h = pcg_hash(h ^ bitcast<u32>(ray.origin.x));
    h = pcg_hash(h ^ bitcast<u32>(ray.origin.y));
    h = pcg_hash(h ^ bitcast<u32>(ray.origin.z));
    h = pcg_hash(h ^ bitcast<u32>(ray.dir.x));
    h = pcg_hash(h ^ bitcast<u32>(ray.dir.y));
    h = pcg_hash(h ^ bitcast<u32>(ray.dir.z));
    return f32((h >> 8u) + 1u) * (1.0 / 16777216.0);
}

// Whether triangle object `id` (`tri`), hit at t > 0 along `ray`, has a
// hole there.
fn alpha_hole(id: u32, tri: Triangle, ray: Ray, t: f32) -> bool {
    let m = materials[objects[id].x];
    if (m.alpha_mode == ALPHA_OPAQUE) {
        return false;
    }
    var alpha = m.alpha_factor;
    if (TEXTURES) {
        let h = texture_hit(id - params.sphere_count, ray.origin + t * ray.dir);
        if (h.found) {
            if (m.texture != NO_TEXTURE) {
                alpha *= sample_alpha(m.texture, h.uv);
            }
            alpha *= vertex_colour(h).w;
        }
    }
    var cutoff = m.alpha_cutoff;
    if (m.alpha_mode == ALPHA_BLEND && is_path()) {
        cutoff = coverage_hash(ray, tri.scene_id);
    }
    return alpha < cutoff;
}
