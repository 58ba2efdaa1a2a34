// The surface at a hit: its normals and where rays leave it (`Surface`,
// `surface_at`; `mapped_surface_at` with the normal map), the mirror
// direction about it, and its material there
// (`material_at`, reading the textures of texture.wgsl). Beside its texture
// coordinates a triangle's record holds
// (crates/kdray-core/src/layout/texture_words.rs, TextureWords) vertex
// colours, which multiply the base colour, and the tangent frame in which
// its normal map bends the shading normal. docs/scene-format.md, "glTF
// materials", states both rules.

// Where a path meets a surface, seen from the incoming ray (mirrored by
// `Surface` in crates/kdray-core/src/reference/surface.rs).
struct Surface {
    // Unit geometric normal, facing the incoming ray: the side rays leave
    // from, and the direction of the spawn offset.
    geometric: vec3<f32>,
    // Unit shading normal, on the geometric normal's side: the vertex
    // normals interpolated at the hit for a smooth triangle, else `geometric`.
    shading: vec3<f32>,
    // Where secondary rays start before the offset along `geometric`: the
    // hit moved out to the smooth surface the vertex normals describe
    // (Hanika 2021), so that shadow rays clear the neighbouring facets.
    spawn_point: vec3<f32>,
}

// The surface at hit point p of object `id`, hit by a ray along `ray_dir`.
fn surface_at(id: u32, p: vec3<f32>, ray_dir: vec3<f32>) -> Surface {
    var g = object_normal(id, p);
    if (dot(g, ray_dir) > 0.0) {
        g = -g;
    }
    if (is_sphere(id)) {
        return Surface(g, g, p);
    }
    let tri = triangle(id - params.sphere_count);
    if (!SMOOTH_TRIANGLES || tri.normals == FLAT_TRIANGLE) {
        return Surface(g, g, p);
    }
    let record = triangle_normals_record(tri.normals);
    let b = barycentrics(tri, p);
    var n0 = decode_normal(record.n0);
    var n1 = decode_normal(record.n1);
    var n2 = decode_normal(record.n2);
    var n = b.x * n0 + b.y * n1 + b.z * n2;
    // Triangles are two-sided: the vertex normals turn with the face.
    if (dot(n, g) < 0.0) {
        n = -n;
        n0 = -n0;
        n1 = -n1;
        n2 = -n2;
    }
    if (dot(n, n) < 1e-12) {
        return Surface(g, g, p); // the vertex normals cancel out here
    }
    // Hanika 2021: p projected onto each vertex's tangent plane where it lies
    // below it, the projections weighted like the normals.
    let d0 = min(dot(p - tri.v0, n0), 0.0);
    let d1 = min(dot(p - tri.v1, n1), 0.0);
    let d2 = min(dot(p - tri.v2, n2), 0.0);
    let lifted = p - (b.x * d0 * n0 + b.y * d1 * n1 + b.z * d2 * n2);
    return Surface(g, normalize(n), lifted);
}

// The mirror direction about the shading normal, or about the geometric
// normal where that one would send the ray into the surface (grazing rays
// on a coarse smooth mesh).
fn reflection_dir(dir: vec3<f32>, s: Surface) -> vec3<f32> {
    let r = normalize(reflect(dir, s.shading));
    if (dot(r, s.geometric) > 0.0) {
        return r;
    }
    return normalize(reflect(dir, s.geometric));
}

// The material of object `id` at hit point p, reached along unit `dir` by
// a path `path_length` long from the eye: on a triangle with a record, its
// diffuse and ambient colours multiplied by its base-colour texture (as
// stored for the Whitted integrator, decoded from sRGB for the path
// tracer) and by its vertex colours; for the Whitted integrator its
// ambient colour darkened by the occlusion map (red, by the map's
// strength); for the path tracer its metallic and roughnesses (the
// model's and the dielectric's) scaled by the metallic-roughness map's
// blue and green, its emission by the emissive
// map (sRGB).
fn material_at(id: u32, p: vec3<f32>, dir: vec3<f32>, path_length: f32) -> Material {
    var m = materials[objects[id].x];
    if (!TEXTURES || is_sphere(id)) {
        return m;
    }
    let h = texture_hit(id - params.sphere_count, p);
    if (!h.found) {
        return m;
    }
    let path = is_path();
    let cone_width = pixel_spread_angle() * path_length;
    if (m.texture != NO_TEXTURE) {
        let c = sample_at_hit(m.texture, slot_hit(h, m, UV_SLOT_BASE), dir, cone_width, path);
        m.diffuse *= c;
        m.ambient *= c;
    }
    let colour = vertex_colour(h).xyz;
    m.diffuse *= colour;
    m.ambient *= colour;
    if (!path && m.occlusion_texture != NO_TEXTURE) {
        let at = slot_hit(h, m, UV_SLOT_OCCLUSION);
        let ao = sample_at_hit(m.occlusion_texture, at, dir, cone_width, false).x;
        m.ambient *= 1.0 + m.occlusion_strength * (ao - 1.0);
    }
    if (path && m.metal_rough_texture != NO_TEXTURE) {
        let at = slot_hit(h, m, UV_SLOT_METAL_ROUGH);
        let mr = sample_at_hit(m.metal_rough_texture, at, dir, cone_width, false);
        m.roughness *= mr.y;
        m.transmission_roughness *= mr.y;
        m.metallic *= mr.z;
    }
    if (path && m.emissive_texture != NO_TEXTURE) {
        let at = slot_hit(h, m, UV_SLOT_EMISSIVE);
        m.emission *= sample_at_hit(m.emissive_texture, at, dir, cone_width, true);
    }
    return m;
}

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

// The surface at a hit as both integrators shade it: `surface_at` with its
// shading normal bent by the material's normal map, unless the bent normal
// would face away from the geometric side (then it keeps its own).
fn mapped_surface_at(id: u32, p: vec3<f32>, ray_dir: vec3<f32>) -> Surface {
    var s = surface_at(id, p, ray_dir);
    let bent = mapped_normal(id, p, s.shading);
    if (dot(bent, s.geometric) > 0.0) {
        s.shading = bent;
    }
    return s;
}
