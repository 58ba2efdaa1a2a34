// Rays, boxes, spheres and triangles. Mirrors src/geometry.rs line by line.

const NO_HIT: f32 = -1.0;

struct Ray {
    origin: vec3<f32>,
    dir: vec3<f32>,   // unit length
}

// The ray's [t0, t1] inside the box; t0 > t1 when it misses.
fn box_interval(box_min: vec3<f32>, box_max: vec3<f32>, ray: Ray) -> vec2<f32> {
    var t0 = -T_INFINITY;
    var t1 = T_INFINITY;
    for (var a = 0u; a < 3u; a++) {
        let o = ray.origin[a];
        let d = ray.dir[a];
        if (abs(d) < PARALLEL_EPSILON) {
            if (o < box_min[a] || o > box_max[a]) {
                return vec2<f32>(1.0, 0.0);
            }
        } else {
            let inv = 1.0 / d;
            let ta = (box_min[a] - o) * inv;
            let tb = (box_max[a] - o) * inv;
            t0 = max(t0, min(ta, tb));
            t1 = min(t1, max(ta, tb));
        }
    }
    return vec2<f32>(t0, t1);
}

// Smallest root t > 0, or NO_HIT. Haines et al., Ray Tracing Gems ch. 7.
fn intersect_sphere(s: Sphere, ray: Ray) -> f32 {
    let f = ray.origin - s.center;
    let b = dot(f, ray.dir);
    let l = f - b * ray.dir;
    let r2 = s.radius * s.radius;
    let disc = r2 - dot(l, l);
    if (disc < 0.0) {
        return NO_HIT;
    }
    let sign_b = select(-1.0, 1.0, b >= 0.0);
    let q = -b - sign_b * sqrt(disc);
    if (q == 0.0) {
        return NO_HIT;
    }
    let c = dot(f, f) - r2;
    let ta = c / q;
    let near = min(ta, q);
    let far = max(ta, q);
    if (near > 0.0) {
        return near;
    }
    if (far > 0.0) {
        return far;
    }
    return NO_HIT;
}

// Möller–Trumbore, two-sided; t > 0 or NO_HIT.
fn intersect_triangle(tri: Triangle, ray: Ray) -> f32 {
    let e1 = tri.v1 - tri.v0;
    let e2 = tri.v2 - tri.v0;
    let p = cross(ray.dir, e2);
    let det = dot(e1, p);
    if (abs(det) < 1e-30) {
        return NO_HIT;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - tri.v0;
    let u = dot(s, p) * inv_det;
    if (u < 0.0 || u > 1.0) {
        return NO_HIT;
    }
    let q = cross(s, e1);
    let v = dot(ray.dir, q) * inv_det;
    if (v < 0.0 || u + v > 1.0) {
        return NO_HIT;
    }
    let t = dot(e2, q) * inv_det;
    return select(NO_HIT, t, t > 0.0);
}

fn intersect_object(id: u32, ray: Ray) -> f32 {
    if (id < params.sphere_count) {
        return intersect_sphere(spheres[id], ray);
    }
    return intersect_triangle(triangle(id - params.sphere_count), ray);
}

// Largest coordinate magnitude the object's intersection works with.
fn object_magnitude(id: u32) -> f32 {
    if (id < params.sphere_count) {
        let s = spheres[id];
        let c = abs(s.center);
        return max(c.x, max(c.y, c.z)) + s.radius;
    }
    let tri = triangle(id - params.sphere_count);
    let m = max(abs(tri.v0), max(abs(tri.v1), abs(tri.v2)));
    return max(m.x, max(m.y, m.z));
}

// Unit geometric normal at p (not yet turned to face the ray).
fn object_normal(id: u32, p: vec3<f32>) -> vec3<f32> {
    if (id < params.sphere_count) {
        return normalize(p - spheres[id].center);
    }
    let tri = triangle(id - params.sphere_count);
    return normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

fn max_component(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// Offset of secondary ray origins along N: see spawn_offset in src/geometry.rs.
fn spawn_offset(p: vec3<f32>, magnitude: f32) -> f32 {
    return max(1e-4 * max(max_component(abs(p)), 1.0), magnitude * (1.0 / 4194304.0));
}
