// Next-event estimation for the path tracer: one light chosen (the
// `light_count` scene lights, the `emitter_count` emissive objects, the sky
// image), a direction toward it, its radiance and the solid-angle density
// of choosing that direction; and the same density for a direction that
// BSDF sampling found, for multiple importance sampling. The scene lights,
// the emitters together and the sky are chosen by power through a
// distribution in the lights buffer's entries (each scene light's `pick`
// and `cdf`, each block's chance of being passed, `beyond`); among the
// emitters, the light tree chooses from the shading point: at each inner
// node one child, in proportion to its importance there, down to one
// emitter's leaf; both built on the host
// (crates/kdray-core/src/layout/light_picks.rs and light_tree.rs). The
// tree's nodes follow the emitters' entries in the lights buffer, one Light
// record each (no buffer more to bind). An emitter's probability, for the
// weights of multiple importance sampling, is the product of the same
// shares, recomputed up the parent links from its leaf. A sphere is
// sampled uniformly in the cone it subtends (it emits outward), a triangle
// uniformly by area (it emits on its front side, the side
// (v1 - v0) x (v2 - v0) points to, or on both where its material is
// two-sided).

struct LightSample {
    dir: vec3<f32>,
    distance: f32,       // to the point sampled
    radiance: vec3<f32>, // arriving along dir if unblocked (a point light: intensity / d^2; directional: irradiance)
    pdf: f32,            // solid angle density, the choice included; 0: nothing to add
    delta: bool,         // a point, spot or directional light: no BSDF sample can find it
    object: u32,         // the emitter's GPU id (NO_OBJECT: a scene light)
}

// Point lights, emitters and, with an image, the sky.
fn lights_total() -> u32 {
    return params.light_count + params.emitter_count + select(0u, 1u, has_environment_image());
}

// The probability that the choice passes the scene lights (falls on an
// emitter or the sky).
fn past_scene_lights() -> f32 {
    if (params.light_count == 0u) {
        return 1.0;
    }
    return lights[0].beyond;
}

// The probability that the choice falls on the sky, given that it passed
// the scene lights.
fn past_emitters() -> f32 {
    if (params.emitter_count == 0u) {
        return 1.0;
    }
    return lights[params.light_count].beyond;
}

// The probability that sample_light picks the sky image.
fn sky_pick() -> f32 {
    if (!has_environment_image()) {
        return 0.0;
    }
    return past_scene_lights() * past_emitters();
}

// The last entry k in [first, end) with lights[k].cdf <= u (the block's
// first entry's cdf is 0): a binary search of the block's distribution. An
// entry of pick 0 shares its cdf with the next, so it is never found.
fn search_lights(first: u32, end: u32, u: f32) -> u32 {
    var lo = first;
    var hi = end;
    while (hi - lo > 1u) {
        loop_iterations += 1u;
        let mid = (lo + hi) / 2u;
        if (lights[mid].cdf <= u) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return lo;
}

// The entry of emitter `id` (a GPU object id), or NO_OBJECT: a binary
// search of the emitters' entries, which the host sorts by object id.
fn emitter_entry(id: u32) -> u32 {
    var lo = params.light_count;
    var hi = params.light_count + params.emitter_count;
    while (lo < hi) {
        loop_iterations += 1u;
        let mid = (lo + hi) / 2u;
        let o = lights[mid].object;
        if (o == id) {
            return mid;
        }
        if (o < id) {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return NO_OBJECT;
}

// The probability that sample_light picks the emitters' block (some
// emitter).
fn emitters_pick() -> f32 {
    return past_scene_lights() * lights[params.light_count].pick;
}

// Node i of the light tree (counted from its root, which follows the
// emitters' entries), unpacked from its Light record
// (layout::light_tree::GpuLightNode::to_light).
fn light_node(i: u32) -> LightNode {
    let l = lights[params.light_count + params.emitter_count + i];
    return LightNode(
        l.position, l.kind, l.ambient, l.object, l.diffuse, l.cos_outer,
        l.specular.x, l.specular.y, bitcast<u32>(l.specular.z), 0u
    );
}

// The importance of node n at p, on a surface of unit geometric normal
// `normal` (facing the ray: the side next_event lights): phi cos theta' /
// d^2 cos theta_i', d the distance from p to its box's centre (at least
// the radius of the sphere around the box), theta' the smallest angle
// between a direction it may emit in and the direction to p that its box
// and cone allow, theta_i' the smallest angle between `normal` and a
// direction from p into the sphere around the box; 0 where it sends
// nothing toward p or lies wholly behind the surface. The host's
// light_tree::importance computes the same in f64.
fn light_importance(n: LightNode, p: vec3<f32>, normal: vec3<f32>) -> f32 {
    if (n.phi <= 0.0) {
        return 0.0;
    }
    let centre = 0.5 * (n.lo + n.hi);
    let radius2 = 0.25 * dot(n.hi - n.lo, n.hi - n.lo);
    let to_p = p - centre;
    let dist2 = dot(to_p, to_p);
    let d2 = max(dist2, radius2);
    var cos_w = 1.0;
    if (dist2 > 0.0) {
        cos_w = dot(n.axis, to_p) / sqrt(dist2);
    }
    if (n.two_sided != 0u) {
        cos_w = abs(cos_w);
    }
    let sin_w = sqrt(max(1.0 - cos_w * cos_w, 0.0));
    // The half-angle of the sphere around the box, seen from p (all
    // directions from inside it).
    var cos_b = -1.0;
    if (dist2 > radius2) {
        cos_b = sqrt(max(1.0 - radius2 / dist2, 0.0));
    }
    let sin_b = sqrt(max(1.0 - cos_b * cos_b, 0.0));
    let cos_o = n.cos_theta_o;
    let sin_o = sqrt(max(1.0 - cos_o * cos_o, 0.0));
    // theta_x = max(theta_w - theta_o, 0), theta' = max(theta_x - theta_b, 0).
    var cos_x = 1.0;
    var sin_x = 0.0;
    if (cos_w < cos_o) {
        cos_x = cos_w * cos_o + sin_w * sin_o;
        sin_x = sin_w * cos_o - cos_w * sin_o;
    }
    var cos_p = 1.0;
    if (cos_x < cos_b) {
        cos_p = cos_x * cos_b + sin_x * sin_b;
    }
    if (cos_p <= n.cos_theta_e) {
        return 0.0;
    }
    // theta_i' = max(theta_i - theta_b, 0), theta_i the angle between the
    // normal and the direction from p to the box's centre.
    var cos_i = 1.0;
    if (dist2 > 0.0) {
        cos_i = -dot(normal, to_p) / sqrt(dist2);
    }
    let sin_i = sqrt(max(1.0 - cos_i * cos_i, 0.0));
    var cos_pi = 1.0;
    if (cos_i < cos_b) {
        cos_pi = cos_i * cos_b + sin_i * sin_b;
    }
    if (cos_pi <= 0.0) {
        return 0.0;
    }
    return n.phi * cos_p * cos_pi / d2;
}

struct TreePick {
    entry: u32, // the emitter's entry in the lights buffer; NO_OBJECT: none
    pick: f32,  // the probability of the walk ending there
}

// The light tree's walk from the root at p (on a surface of geometric
// normal `normal`) with u in [0, 1): at each inner node, the first child
// where u falls below its share of the two importances (u then stretched
// over that share), else the second.
fn tree_pick(p: vec3<f32>, normal: vec3<f32>, u_in: f32) -> TreePick {
    var u = u_in;
    var node = light_node(0u);
    var pick = 1.0;
    while ((node.child & LIGHT_TREE_LEAF) == 0u) {
        loop_iterations += 1u;
        let first = light_node(node.child);
        let second = light_node(node.child + 1u);
        let a = light_importance(first, p, normal);
        let b = light_importance(second, p, normal);
        if (a + b <= 0.0) {
            return TreePick(NO_OBJECT, 0.0);
        }
        let share = a / (a + b);
        if (u < share) {
            u = min(u / share, 0.99999994);
            pick *= share;
            node = first;
        } else {
            u = min((u - share) / (1.0 - share), 0.99999994);
            pick *= b / (a + b);
            node = second;
        }
    }
    return TreePick(params.light_count + (node.child & ~LIGHT_TREE_LEAF), pick);
}

// The probability that the light tree's walk at p (normal `normal`) ends
// at `leaf`: the product of the shares tree_pick takes, from the leaf up to
// the root.
fn tree_leaf_pick(leaf: u32, p: vec3<f32>, normal: vec3<f32>) -> f32 {
    if (leaf == NO_LEAF) {
        return 0.0;
    }
    var i = leaf;
    var node = light_node(i);
    var pick = 1.0;
    while (node.parent != LIGHT_TREE_ROOT) {
        loop_iterations += 1u;
        let parent = light_node(node.parent);
        let a = light_importance(light_node(parent.child), p, normal);
        let b = light_importance(light_node(parent.child + 1u), p, normal);
        if (a + b <= 0.0) {
            return 0.0;
        }
        pick *= select(b, a, i == parent.child) / (a + b);
        i = node.parent;
        node = parent;
    }
    return pick;
}

fn emitter_radiance(id: u32) -> vec3<f32> {
    return materials[objects[id].x].emission;
}

// 1 - cos of the half-angle of the cone sphere `s` subtends from p (0 when p
// is inside), written so that small far spheres keep their precision.
fn sphere_cone_width(s: Sphere, p: vec3<f32>) -> f32 {
    let d2 = dot(s.center - p, s.center - p);
    let r2 = s.radius * s.radius;
    if (d2 <= r2) {
        return 0.0;
    }
    let sin2 = r2 / d2;
    return sin2 / (1.0 + sqrt(1.0 - sin2));
}

fn triangle_front(tri: Triangle) -> vec3<f32> {
    return cross(tri.v1 - tri.v0, tri.v2 - tri.v0);
}

// The cosine at emitter triangle `id` (front `front`, |front| = twice its
// area) of the direction `dir` toward it: positive where it emits that way,
// from its front side, or either side where its material is two-sided.
fn emitting_cosine(id: u32, front: vec3<f32>, dir: vec3<f32>, twice_area: f32) -> f32 {
    let c = -dot(front, dir) / twice_area;
    if (materials[objects[id].x].two_sided != 0u) {
        return abs(c);
    }
    return c;
}

fn no_light() -> LightSample {
    return LightSample(vec3<f32>(0.0, 0.0, 1.0), 0.0, vec3<f32>(0.0), 0.0, false, NO_OBJECT);
}

// A sample toward one light, seen from p (the shading point, on a surface
// of unit geometric normal `normal` facing the ray; shadow rays start at
// `origin`, p moved off the surface). One random number picks the
// light: below 1 - past_scene_lights() it searches the scene lights'
// distribution, above it is stretched over the emitters' block and the
// sky's, and within the emitters' over the light tree's walk.
fn sample_light(p: vec3<f32>, normal: vec3<f32>) -> LightSample {
    let total = lights_total();
    if (total == 0u) {
        return no_light();
    }
    let u = random();
    let u1 = random();
    let u2 = random();
    let past = past_scene_lights();
    var k: u32;
    var choice: f32;
    if (u < 1.0 - past) {
        k = search_lights(0u, params.light_count, u);
        choice = lights[k].pick;
    } else {
        // Below 1, past f32 rounding: u < 1 and past > 0 here.
        let v = min((u - (1.0 - past)) / past, 0.99999994);
        let emitters_end = 1.0 - past_emitters();
        if (v < emitters_end) {
            let t = tree_pick(p, normal, min(v / emitters_end, 0.99999994));
            if (t.entry == NO_OBJECT) {
                return no_light(); // no emitter sends light toward p
            }
            k = t.entry;
            choice = emitters_pick() * t.pick;
        } else {
            k = params.light_count + params.emitter_count; // the sky
            choice = sky_pick();
        }
    }
    mark_light(k, choice);
    if (choice <= 0.0) {
        return no_light();
    }
    if (k == params.light_count + params.emitter_count) {
        let dir = sample_environment();
        let pdf = choice * environment_pdf(dir);
        if (pdf <= 0.0) {
            return no_light();
        }
        return LightSample(dir, T_INFINITY, sky(dir), pdf, false, NO_OBJECT);
    }
    let light = lights[k];
    if (k < params.light_count) {
        // Delta lights: a directional light's `diffuse` is the irradiance it
        // gives a surface facing it; a point or spot light's radiant
        // intensity is `diffuse * path_scale`, a spot's times its falloff.
        let kind = scene_light_kind(light.kind);
        if (kind == LIGHT_DIRECTIONAL) {
            return LightSample(-light.direction, T_INFINITY, light.diffuse, choice, true, NO_OBJECT);
        }
        let to = light.position - p;
        let d2 = dot(to, to);
        if (d2 <= 0.0) {
            return no_light();
        }
        let d = sqrt(d2);
        var intensity = light.diffuse * light.path_scale;
        if (kind == LIGHT_SPOT) {
            intensity *= spot_factor(light, dot(-to / d, light.direction));
        }
        return LightSample(to / d, d, intensity / d2, choice, true, NO_OBJECT);
    }
    let id = light.object;
    if (is_sphere(id)) {
        let s = sphere(id);
        let width = sphere_cone_width(s, p);
        if (width <= 0.0) {
            return no_light();
        }
        let axis = normalize(s.center - p);
        let cos_t = 1.0 - u1 * width;
        let sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
        let phi = 2.0 * PI * u2;
        let dir = normalize(tangent_frame(axis) * vec3<f32>(sin_t * cos(phi), sin_t * sin(phi), cos_t));
        let t = intersect_sphere(s, Ray(p, dir));
        if (t == NO_HIT) {
            return no_light(); // grazing the rim in f32
        }
        return LightSample(dir, t, light.diffuse, choice / (2.0 * PI * width), false, id);
    }
    let tri = triangle(id - params.sphere_count);
    let su = sqrt(u1);
    let q = (1.0 - su) * tri.v0 + su * (1.0 - u2) * tri.v1 + su * u2 * tri.v2;
    let front = triangle_front(tri);
    let twice_area = length(front);
    let to = q - p;
    let d2 = dot(to, to);
    if (twice_area <= 0.0 || d2 <= 0.0) {
        return no_light();
    }
    let d = sqrt(d2);
    let dir = to / d;
    let cos_l = emitting_cosine(id, front, dir, twice_area);
    if (cos_l <= 0.0) {
        return no_light(); // its back faces p
    }
    let radiance = light.diffuse * emissive_scale(id, q);
    return LightSample(dir, d, radiance, choice * d2 / (0.5 * twice_area * cos_l), false, id);
}

// The density with which sample_light, from the shading point `at` (its
// normal `at_normal`), picks the direction `dir` that meets emitter `id`
// at distance t from p (the ray's origin, `at` moved off the surface; 0
// where it could not): the emitter's pick as the sampler has it at `at`,
// times the density within it.
fn light_pdf(id: u32, at: vec3<f32>, at_normal: vec3<f32>, p: vec3<f32>, dir: vec3<f32>, t: f32) -> f32 {
    let k = emitter_entry(id);
    if (k == NO_OBJECT) {
        return 0.0;
    }
    let choice = emitters_pick() * tree_leaf_pick(lights[k].leaf, at, at_normal);
    if (choice <= 0.0) {
        return 0.0;
    }
    if (is_sphere(id)) {
        let width = sphere_cone_width(sphere(id), p);
        if (width <= 0.0) {
            return 0.0;
        }
        return choice / (2.0 * PI * width);
    }
    let tri = triangle(id - params.sphere_count);
    let front = triangle_front(tri);
    let twice_area = length(front);
    let cos_l = emitting_cosine(id, front, dir, twice_area);
    if (cos_l <= 0.0) {
        return 0.0;
    }
    return choice * t * t / (0.5 * twice_area * cos_l);
}

// The radiance emitter `id` sends back along -dir from its hit at p (0 from
// a sphere's inside or a one-sided triangle's back).
fn emitted(id: u32, p: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    let e = emitter_radiance(id);
    if (is_sphere(id)) {
        if (dot(p - sphere(id).center, dir) >= 0.0) {
            return vec3<f32>(0.0);
        }
        return e;
    }
    let tri = triangle(id - params.sphere_count);
    let two_sided = materials[objects[id].x].two_sided != 0u;
    if (!two_sided && dot(triangle_front(tri), dir) >= 0.0) {
        return vec3<f32>(0.0);
    }
    return e * emissive_scale(id, p);
}

// Where the shadow ray toward `light`, leaving from `origin`, must find
// nothing before it (an any-hit ray counts hits at t < limit); 0: the light
// cannot be reached. An emitter's own hit is computed from the shadow ray's
// origin with the walk's own test, so that the light never shadows itself
// (from p, a ray grazing a sphere's rim meets it sooner when moved off the
// surface).
fn shadow_limit(light: LightSample, origin: vec3<f32>) -> f32 {
    if (light.object == NO_OBJECT) {
        return light.distance;
    }
    let t = test_object(light.object, Ray(origin, light.dir)).t;
    if (t == NO_HIT) {
        return 0.0;
    }
    return t;
}

// The power heuristic (Veach 1997, beta = 2) for the strategy with density a.
fn mis_weight(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    if (a2 + b2 <= 0.0) {
        return 0.0;
    }
    return a2 / (a2 + b2);
}
