// The sky: `params.background` (a uniform radiance), or `[environment] image`,
// an equirectangular image of linear radiance in the `textures` buffer from
// `params.env_offset` (crates/kdray-core/src/layout/scene_arrays.rs,
// EnvironmentWords: the texels, three f32 each, then the rows' and each row's
// cumulative distributions for importance sampling). The layout and the direction -> texel rule mirror
// crates/kdray-core/src/scene/environment.rs: the top row looks up (+y), the
// centre column along -z, u grows toward +x; the image is turned by `rotation`
// about +y; nearest texel.

fn has_environment_image() -> bool {
    return TEXTURES && params.env_width > 0u;
}

fn env_word(i: u32) -> f32 {
    return bitcast<f32>(textures[params.env_offset + i]);
}

// The direction d (unit) turned back by the sky's rotation.
fn environment_local(d: vec3<f32>) -> vec3<f32> {
    let c = params.env_rotation_cos;
    let s = params.env_rotation_sin;
    return vec3<f32>(c * d.x - s * d.z, d.y, s * d.x + c * d.z);
}

// The texel (column, row) direction d reads.
fn environment_texel(d: vec3<f32>) -> vec2<u32> {
    let l = environment_local(d);
    let u = 0.5 + atan2(l.x, -l.z) * (1.0 / (2.0 * PI));
    let v = acos(clamp(l.y, -1.0, 1.0)) * (1.0 / PI);
    let w = params.env_width;
    let h = params.env_height;
    return vec2<u32>(min(u32(max(u * f32(w), 0.0)), w - 1u), min(u32(max(v * f32(h), 0.0)), h - 1u));
}

fn environment_texel_radiance(t: vec2<u32>) -> vec3<f32> {
    let i = 3u * (t.y * params.env_width + t.x);
    return vec3<f32>(env_word(i), env_word(i + 1u), env_word(i + 2u)) * params.env_intensity;
}

// What a ray that escapes along d sees.
fn sky(d: vec3<f32>) -> vec3<f32> {
    if (!has_environment_image()) {
        return params.background;
    }
    return environment_texel_radiance(environment_texel(d));
}

fn env_rows_cdf(i: u32) -> f32 {
    return env_word(3u * params.env_width * params.env_height + i);
}

fn env_row_cdf(row: u32, i: u32) -> f32 {
    let w = params.env_width;
    return env_word(3u * w * params.env_height + params.env_height + 1u + row * (w + 1u) + i);
}

// The solid-angle density with which sample_environment picks d: a
// texel's probability spread over its solid angle.
fn environment_pdf(d: vec3<f32>) -> f32 {
    let t = environment_texel(d);
    let p_row = env_rows_cdf(t.y + 1u) - env_rows_cdf(t.y);
    let p_col = env_row_cdf(t.y, t.x + 1u) - env_row_cdf(t.y, t.x);
    let sin_theta = sqrt(max(1.0 - d.y * d.y, 0.0));
    if (sin_theta <= 0.0) {
        return 0.0;
    }
    let w = f32(params.env_width);
    let h = f32(params.env_height);
    return p_row * p_col * w * h / (2.0 * PI * PI * sin_theta);
}

// The last i in [0, n) with cdf(i) <= u: a binary search of a cumulative
// distribution of n + 1 values (entries of `row`'s, or the rows' where row
// is NO_OBJECT).
fn environment_search(row: u32, n: u32, u: f32) -> u32 {
    var lo = 0u;
    var hi = n;
    while (hi - lo > 1u) {
        loop_iterations += 1u;
        let mid = (lo + hi) / 2u;
        var c: f32;
        if (row == NO_OBJECT) {
            c = env_rows_cdf(mid);
        } else {
            c = env_row_cdf(row, mid);
        }
        if (c <= u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// A direction drawn from the sky's texels by luminance times solid angle,
// uniformly within its texel.
fn sample_environment() -> vec3<f32> {
    let row = environment_search(NO_OBJECT, params.env_height, random());
    let col = environment_search(row, params.env_width, random());
    let u = (f32(col) + random()) / f32(params.env_width);
    let v = (f32(row) + random()) / f32(params.env_height);
    let phi = (u - 0.5) * 2.0 * PI;
    let theta = v * PI;
    let l = vec3<f32>(sin(theta) * sin(phi), cos(theta), -sin(theta) * cos(phi));
    let c = params.env_rotation_cos;
    let s = params.env_rotation_sin;
    return normalize(vec3<f32>(c * l.x + s * l.z, l.y, -s * l.x + c * l.z));
}
