// The render kernel's walk recorder: nothing. The inspect kernel holds
// walk_record.wgsl in this file's place, whose functions log each ray and
// walk step; here they are empty, so the compilers drop the calls and
// their arguments.

fn mark_ray(kind: u32) {}
fn mark_light(entry: u32, pick: f32) {}
fn mark_light_density(density: f32) {}
fn record_ray(ray: Ray, t_limit: f32, any_hit: bool) {}
fn record_hit(ray: Ray, hit: Hit) {}
fn record_segment(segment: vec2<f32>) {}
fn record_node(node: u32, t_min: f32, t_max: f32, step: DescentStep) {}
fn record_leaf(node: u32, t_min: f32, t_max: f32) {}
fn record_skipped_leaf(node: u32) {}
fn record_test(scene_id: u32, t: f32) {}
fn record_push(node: u32, t_max: f32) {}
fn record_pop(node: u32, t_max: f32) {}
fn record_restart(node: u32, t_min: f32) {}
fn record_rope(face: u32, node: u32, t_min: f32) {}
