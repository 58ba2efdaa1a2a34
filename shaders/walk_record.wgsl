// The walk recorder of the inspect kernel (`inspect_pixel`, the entry point
// below): every ray one pixel's first sample traces, and every step of the
// walk that searches it, written to `inspect_log` as the k-d walks and the
// integrators make them. The render kernel holds walk_record_off.wgsl in
// this file's place, whose functions do nothing, so its walks are the same
// code without the calls. src/gpu/walk_log.rs reads the log.
//
// The log: word INSPECT_WORDS_USED holds how many words the invocation
// meant to write (past the buffer's end: the log is cut short), word
// INSPECT_SINK takes the writes that are not the log's, then records from
// word INSPECT_HEADER_WORDS: a tag (INSPECT_RAY, ...), then
// its fields, floats as their bits. One invocation writes it.

// Whether this invocation writes the log (the first of the workgroup).
var<private> inspect_writes: bool;
// The log's length, in words.
var<private> inspect_length: u32;
// The next word to write.
var<private> inspect_at: u32 = INSPECT_HEADER_WORDS;
// The kind of the next ray traced (RAY_PRIMARY, ...), set where the
// integrators make the ray.
var<private> inspect_kind: u32 = RAY_PRIMARY;
// The walk's work counted before the ray's walk began.
var<private> inspect_cost: vec3<u32>;
// The light the next shadow rays aim at (mark_light): its entry in
// `lights` (the sky: light_count + emitter_count), its kind (LIGHT_*, the
// sky LIGHT_SKY), its object's scene id (an emitter; else NO_OBJECT), the
// probability it was picked with, and the solid-angle density of the
// shadow ray's direction (mark_light_density; 0: a delta light).
var<private> inspect_light: u32 = NO_OBJECT;
var<private> inspect_light_kind: u32;
var<private> inspect_light_object: u32 = NO_OBJECT;
var<private> inspect_pick: f32;
var<private> inspect_density: f32;

// Writes word `w` at the next place, or, for the other lanes and past the
// log's end, into the sink word (INSPECT_SINK), which nothing reads:
// branch-free (`&`, not `&&`, which becomes a branch), since SwiftShader
// took minutes to compile the kernel with a branch around each store.
fn log_word(w: u32) {
    let room = inspect_writes & (inspect_at < inspect_length);
    inspect_log[select(INSPECT_SINK, inspect_at, room)] = w;
    inspect_at += 1u;
}

fn log_float(f: f32) {
    log_word(bitcast<u32>(f));
}

fn log_vec3(v: vec3<f32>) {
    log_float(v.x);
    log_float(v.y);
    log_float(v.z);
}

fn mark_ray(kind: u32) {
    inspect_kind = kind;
}

// The light the shadow rays from here on aim at: entry `entry` of `lights`
// (light_count + emitter_count: the sky image), picked with probability
// `pick` (the path tracer's sample_light; Whitted's shade: 1, every light).
fn mark_light(entry: u32, pick: f32) {
    let count = params.light_count + params.emitter_count;
    inspect_light = entry;
    inspect_pick = pick;
    inspect_density = 0.0;
    inspect_light_kind = LIGHT_SKY;
    inspect_light_object = NO_OBJECT;
    if (entry < count) {
        let light = lights[entry];
        inspect_light_kind = light.kind;
        if (light.kind == LIGHT_EMITTER) {
            inspect_light_object = objects[light.object].y;
        }
    }
}

// The solid-angle density of the next shadow ray's direction, the pick
// included (0: a delta light).
fn mark_light_density(density: f32) {
    inspect_density = density;
}

// A ray about to be walked: its kind, query, origin, direction and limit,
// and for a shadow ray its light (none for the others), without a branch.
fn record_ray(ray: Ray, t_limit: f32, any_hit: bool) {
    let shadow = inspect_kind == RAY_SHADOW;
    log_word(INSPECT_RAY);
    log_word(inspect_kind);
    log_word(select(0u, 1u, any_hit));
    log_vec3(ray.origin);
    log_vec3(ray.dir);
    log_float(t_limit);
    log_word(select(NO_OBJECT, inspect_light, shadow));
    log_word(select(0u, inspect_light_kind, shadow));
    log_word(select(NO_OBJECT, inspect_light_object, shadow));
    log_float(select(0.0, inspect_pick, shadow));
    log_float(select(0.0, inspect_density, shadow));
    inspect_cost = walk_cost;
}

// What the ray's query returned: the hit's scene id (NO_OBJECT: none), t,
// the point and the unit geometric normal facing the ray (as the shading
// sees them), and the walk's counted work for this ray.
fn record_hit(ray: Ray, hit: Hit) {
    log_word(INSPECT_HIT);
    log_word(hit.scene_id);
    log_float(hit.t);
    var point = vec3<f32>(0.0);
    var normal = vec3<f32>(0.0);
    if (hit.object != NO_OBJECT) {
        // surface_at's geometric normal, without the shading normal.
        point = ray.origin + hit.t * ray.dir;
        normal = object_normal(hit.object, point);
        if (dot(normal, ray.dir) > 0.0) {
            normal = -normal;
        }
    }
    log_vec3(point);
    log_vec3(normal);
    let cost = walk_cost - inspect_cost;
    log_word(cost.x);
    log_word(cost.y);
    log_word(cost.z);
}

fn record_segment(segment: vec2<f32>) {
    log_word(INSPECT_SEGMENT);
    log_float(segment.x);
    log_float(segment.y);
}

fn record_node(node: u32, t_min: f32, t_max: f32, step: DescentStep) {
    log_word(INSPECT_NODE);
    log_word(node);
    log_float(t_min);
    log_float(t_max);
    log_word(step.near);
    log_word(step.far);
    log_float(step.t_split);
    log_word(select(0u, 1u, step.crosses));
}

fn record_leaf(node: u32, t_min: f32, t_max: f32) {
    log_word(INSPECT_LEAF);
    log_word(node);
    log_float(t_min);
    log_float(t_max);
}

fn record_skipped_leaf(node: u32) {
    log_word(INSPECT_SKIPPED);
    log_word(node);
}

// One object test: its scene id and where the ray meets it (t > 0), if it does.
fn record_test(scene_id: u32, t: f32) {
    log_word(INSPECT_TESTED);
    log_word(scene_id);
    log_word(select(0u, 1u, t > 0.0));
    log_float(t);
}

fn record_push(node: u32, t_max: f32) {
    log_word(INSPECT_PUSH);
    log_word(node);
    log_float(t_max);
}

fn record_pop(node: u32, t_max: f32) {
    log_word(INSPECT_POP);
    log_word(node);
    log_float(t_max);
}

fn record_restart(node: u32, t_min: f32) {
    log_word(INSPECT_RESTART);
    log_word(node);
    log_float(t_min);
}

fn record_rope(face: u32, node: u32, t_min: f32) {
    log_word(INSPECT_ROPE);
    log_word(face);
    log_word(node);
    log_float(t_min);
}

// Traces sample 0 of pixel `params.tile_origin` as render_tile and
// accumulate_tile do (Whitted: the top-left cell of the k x k grid; path:
// the first random sample), recording its rays and walks; the sample's
// unclamped colour closes the log. Every invocation of the workgroup traces
// the same sample and the first one writes the log: with one invocation per
// workgroup, llvmpipe (Mesa 22.3) ran a leaf's test loop once and ended the
// sample early; with INSPECT_LANES alike, the lanes run as render_tile's do.
@compute @workgroup_size(INSPECT_LANES, 1, 1)
fn inspect_pixel(@builtin(local_invocation_index) lane: u32) {
    read_params();
    inspect_writes = lane == 0u;
    inspect_length = arrayLength(&inspect_log);
    let c = radiance_sample(params.tile_origin, 0u);
    log_word(INSPECT_SAMPLE);
    log_vec3(c);
    inspect_log[select(INSPECT_SINK, INSPECT_WORDS_USED, inspect_writes)] = inspect_at;
}
