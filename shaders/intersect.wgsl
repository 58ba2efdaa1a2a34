// Rays, boxes, spheres and triangles. Mirrors crates/kdray-core/src/geometry/
// (ray.rs, aabb.rs, sphere.rs, triangle.rs, primitives.rs) line by line.

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

// The watertight test's per-ray constants (RayShear in
// crates/kdray-core/src/geometry/triangle.rs): kz the axis the ray runs most along, kx,
// ky the others; (sx, sy, sz) map the direction onto (0, 0, 1).
struct RayShear {
    kx: u32,
    ky: u32,
    kz: u32,
    sx: f32,
    sy: f32,
    sz: f32,
}

fn ray_shear(dir: vec3<f32>) -> RayShear {
    let m = abs(dir);
    var kz = 2u;
    if (m.x >= m.y && m.x >= m.z) {
        kz = 0u;
    } else if (m.y >= m.z) {
        kz = 1u;
    }
    let kx = (kz + 1u) % 3u;
    let ky = (kz + 2u) % 3u;
    let sz = 1.0 / dir[kz];
    return RayShear(kx, ky, kz, dir[kx] * sz, dir[ky] * sz, sz);
}

// Whether dir lies in the triangle's plane as far as its own arithmetic can
// tell: the normal's component along it, from the edges alone, within
// IN_PLANE_MARGIN of the normal's size. See TriangleF32::runs_in_plane.
fn runs_in_plane(tri: Triangle, dir: vec3<f32>) -> bool {
    let n = cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
    let m = abs(n);
    return abs(dot(n, dir)) <= (m.x + m.y + m.z) * IN_PLANE_MARGIN;
}

// Watertight, two-sided (Woop, Benthin and Wald, JCGT 2013); t > 0 or
// NO_HIT. Edge-function signs come from comparing two rounded products, the
// same two in both triangles of a shared edge; equal products (an edge
// function of 0) count as inside. See TriangleF32::intersect.
fn intersect_triangle(tri: Triangle, ray: Ray) -> f32 {
    let sh = ray_shear(ray.dir);
    let a = tri.v0 - ray.origin;
    let b = tri.v1 - ray.origin;
    let c = tri.v2 - ray.origin;
    let ax = a[sh.kx] - sh.sx * a[sh.kz];
    let ay = a[sh.ky] - sh.sy * a[sh.kz];
    let bx = b[sh.kx] - sh.sx * b[sh.kz];
    let by = b[sh.ky] - sh.sy * b[sh.kz];
    let cx = c[sh.kx] - sh.sx * c[sh.kz];
    let cy = c[sh.ky] - sh.sy * c[sh.kz];
    let u0 = cx * by;
    let u1 = cy * bx;
    let v0 = ax * cy;
    let v1 = ay * cx;
    let w0 = bx * ay;
    let w1 = by * ax;
    let any_negative = u0 < u1 || v0 < v1 || w0 < w1;
    let any_positive = u0 > u1 || v0 > v1 || w0 > w1;
    if (any_negative && any_positive) {
        return NO_HIT;
    }
    let det = (u0 - u1) + (v0 - v1) + (w0 - w1);
    if (abs(det) < 1e-30 || runs_in_plane(tri, ray.dir)) {
        return NO_HIT;
    }
    let az = sh.sz * a[sh.kz];
    let bz = sh.sz * b[sh.kz];
    let cz = sh.sz * c[sh.kz];
    let t_scaled = (u0 - u1) * az + (v0 - v1) * bz + (w0 - w1) * cz;
    let t = t_scaled * (1.0 / det);
    return select(NO_HIT, t, t > 0.0 && holds_hit_at(tri, ray, t));
}

// Whether the point at t lies within HIT_BOX_MARGIN of the largest
// coordinate the test works with of the triangle's box; farther, the hit is
// the rounding's. See TriangleF32::holds_hit_at.
fn holds_hit_at(tri: Triangle, ray: Ray, t: f32) -> bool {
    let lo = min(tri.v0, min(tri.v1, tri.v2));
    let hi = max(tri.v0, max(tri.v1, tri.v2));
    let p = ray.origin + ray.dir * t;
    let m = max(abs(lo), abs(hi));
    let o = abs(ray.origin);
    let scale = max(max(m.x, max(m.y, m.z)), max(o.x, max(o.y, o.z)));
    let margin = vec3<f32>(scale * HIT_BOX_MARGIN);
    return all(lo - margin <= p) && all(p <= hi + margin);
}

// Sphere `id`, stored as one vec4 (center, radius): one load on llvmpipe.
fn sphere(id: u32) -> Sphere {
    let v = spheres[id];
    return Sphere(v.xyz, v.w);
}

// An object test: the hit's t (NO_HIT: none) and the object's id in the
// scene's order, which breaks the walks' ties between equal t. A triangle
// carries its id beside its vertices; a sphere's 16 bytes have no room, so
// its id is read from `objects` (a load the compiler leaves out where the id
// is not used: any-hit walks and brute force, which break no ties by it).
struct ObjectTest {
    t: f32,
    scene_id: u32,
}

fn test_object(id: u32, ray: Ray) -> ObjectTest {
    if (is_sphere(id)) {
        return ObjectTest(intersect_sphere(sphere(id), ray), objects[id].y);
    }
    let tri = triangle(id - params.sphere_count);
    var t = intersect_triangle(tri, ray);
    if (ALPHA_TEST && t > 0.0 && alpha_hole(id, tri, ray, t)) {
        t = NO_HIT;   // a hole in an alpha-tested surface: rays pass
    }
    return ObjectTest(t, tri.scene_id);
}

// Largest coordinate magnitude the object's intersection works with.
fn object_magnitude(id: u32) -> f32 {
    if (is_sphere(id)) {
        let s = sphere(id);
        let c = abs(s.center);
        return max(c.x, max(c.y, c.z)) + s.radius;
    }
    let tri = triangle(id - params.sphere_count);
    let m = max(abs(tri.v0), max(abs(tri.v1), abs(tri.v2)));
    return max(m.x, max(m.y, m.z));
}

// Unit geometric normal at p (not yet turned to face the ray).
fn object_normal(id: u32, p: vec3<f32>) -> vec3<f32> {
    if (is_sphere(id)) {
        return normalize(p - sphere(id).center);
    }
    let tri = triangle(id - params.sphere_count);
    return normalize(cross(tri.v1 - tri.v0, tri.v2 - tri.v0));
}

fn max_component(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

// Offset of secondary ray origins along N: see spawn_offset in
// crates/kdray-core/src/geometry/ray.rs.
fn spawn_offset(p: vec3<f32>, magnitude: f32) -> f32 {
    return max(1e-4 * max(max_component(abs(p)), 1.0), magnitude * (1.0 / 4194304.0));
}
