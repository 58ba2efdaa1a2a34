//! Each ray as a source records it (the reference tracer's `TracedRay`, the
//! inspect kernel's `RecordedRay`) turned into the document's
//! [`InspectedRay`]: its walk's events as steps named by the tree's nodes,
//! its hit, its counts and its light.

use glam::Vec3;

use super::document::{
    Counts, InspectedHit, InspectedLight, InspectedRay, Restart, Resume, Rope, Step, Tested,
};
use crate::geometry::{Ray, T_INFINITY};
use crate::gpu::bindings::walk_codes::LIGHT_SKY;
use crate::gpu::walk_log::RecordedLight;
use crate::gpu::RecordedRay;
use crate::kdtree::traverse::WalkCost;
use crate::kdtree::{KdTree, WalkEvent};
use crate::layout::KdNode;
use crate::layout::{LIGHT_DIRECTIONAL, LIGHT_EMITTER, LIGHT_SPOT};
use crate::scene::{LightKind, Scene};
use kdray_core::reference::{LightId, RayKind, ReferenceTracer, TracedRay};

/// One ray as either source gives it.
pub(super) struct RayRecord<'a> {
    kind: RayKind,
    any: bool,
    ray: Ray,
    t_limit: f32,
    walk: &'a [WalkEvent],
    hit: Option<HitRecord>,
    cost: WalkCost,
    light: Option<InspectedLight>,
}

/// A hit: the object, t, the point and the unit geometric normal facing
/// the ray.
struct HitRecord {
    object: u32,
    t: f32,
    point: Vec3,
    normal: Vec3,
}

pub(super) fn cpu_record<'a>(
    scene: &Scene,
    tracer: &ReferenceTracer,
    traced: &'a TracedRay,
) -> RayRecord<'a> {
    let ray = traced.ray;
    let spheres = tracer.primitives().spheres.len() as u32;
    RayRecord {
        kind: traced.kind,
        any: traced.any,
        ray,
        t_limit: traced.t_limit,
        walk: &traced.walk,
        hit: traced.hit.map(|h| {
            let point = ray.origin + h.t * ray.dir;
            HitRecord {
                object: h.object,
                t: h.t,
                point,
                normal: tracer.surface(h.object, point, ray.dir).geometric,
            }
        }),
        cost: traced.cost,
        light: traced.light.map(|aim| {
            let kind = match aim.light {
                LightId::Scene(i) => scene.lights.get(i as usize).map(|l| match l.kind {
                    LightKind::Point => "point",
                    LightKind::Spot { .. } => "spot",
                    LightKind::Directional { .. } => "directional",
                }),
                _ => None,
            };
            light_named(aim.light, kind, spheres, aim.pick, 0.0)
        }),
    }
}

/// The name of a scene light's kind (`GpuLight::kind`).
fn light_kind_name(kind: u32) -> &'static str {
    match kind {
        LIGHT_SPOT => "spot",
        LIGHT_DIRECTIONAL => "directional",
        _ => "point",
    }
}

/// A shadow ray's light in the document's terms; `scene_kind` a scene
/// light's kind, `spheres` the scene's sphere count, `density` 0 for none.
fn light_named(
    light: LightId,
    scene_kind: Option<&'static str>,
    spheres: u32,
    pick: f32,
    density: f32,
) -> InspectedLight {
    let mut named = InspectedLight {
        source: "light",
        index: None,
        kind: None,
        object: None,
        triangle: None,
        pick,
        pdf: (density > 0.0).then_some(density),
    };
    match light {
        LightId::Scene(i) => {
            named.index = Some(i);
            named.kind = scene_kind;
        }
        LightId::Emitter(object) => {
            named.source = "emitter";
            named.object = Some(object);
            named.kind = Some(if object < spheres {
                "sphere"
            } else {
                "triangle"
            });
            named.triangle = object.checked_sub(spheres);
        }
        LightId::Sky => named.source = "sky",
    }
    named
}

/// The light the kernel logged for a shadow ray, in the document's terms.
fn kernel_light(light: &RecordedLight, spheres: u32) -> InspectedLight {
    let id = match light.kind {
        LIGHT_SKY => LightId::Sky,
        LIGHT_EMITTER => LightId::Emitter(light.object),
        _ => LightId::Scene(light.entry),
    };
    let kind = light_kind_name(light.kind);
    light_named(id, Some(kind), spheres, light.pick, light.density)
}

pub(super) fn kernel_record(recorded: &RecordedRay, spheres: u32) -> RayRecord<'_> {
    RayRecord {
        kind: recorded.kind,
        any: recorded.any,
        ray: recorded.ray,
        t_limit: recorded.t_limit,
        walk: &recorded.walk,
        hit: recorded.hit.map(|h| HitRecord {
            object: h.object,
            t: h.t,
            point: h.point,
            normal: h.normal,
        }),
        cost: recorded.cost,
        light: recorded.light.map(|l| kernel_light(&l, spheres)),
    }
}

/// What a step needs to know of the tree.
pub(super) struct TreeView<'a> {
    nodes: &'a [KdNode],
    leaf_objects: &'a [u32],
    depths: Vec<u32>,
    /// Objects below this id are spheres.
    spheres: u32,
}

impl<'a> TreeView<'a> {
    /// `tree`'s nodes (none for brute force) in a scene of `spheres` spheres.
    pub(super) fn of(tree: Option<&'a KdTree>, spheres: u32) -> TreeView<'a> {
        TreeView {
            nodes: tree.map_or(&[][..], |t| &t.nodes),
            leaf_objects: tree.map_or(&[][..], |t| &t.leaf_objects),
            depths: tree.map(node_depths).unwrap_or_default(),
            spheres,
        }
    }
}

/// Each node's depth (the root's 0): children follow their parent in the
/// flat layout, the lower at i + 1, the upper at `index`.
fn node_depths(tree: &KdTree) -> Vec<u32> {
    let mut depths = vec![0u32; tree.nodes.len()];
    for (i, n) in tree.nodes.iter().enumerate() {
        if !n.is_leaf() {
            let child_depth = depths[i] + 1;
            for child in [i + 1, n.index as usize] {
                if let Some(d) = depths.get_mut(child) {
                    *d = child_depth;
                }
            }
        }
    }
    depths
}

const AXES: [&str; 3] = ["x", "y", "z"];
const FACES: [&str; 6] = ["x-", "x+", "y-", "y+", "z-", "z+"];

pub(super) fn inspected_ray(view: &TreeView, traced: &RayRecord) -> InspectedRay {
    let ray = traced.ray;
    let mut walk: Vec<Step> = Vec::new();
    let mut t_interval = None;
    let mut restarts = 0;
    for event in traced.walk {
        let depth = |node: usize| view.depths.get(node).copied().unwrap_or(0);
        match *event {
            WalkEvent::Segment { t_min, t_far } => t_interval = Some([t_min, t_far]),
            WalkEvent::Node {
                node,
                t_min,
                t_max,
                near,
                far,
                t_split,
                crosses,
            } => {
                let n = view.nodes[node];
                walk.push(Step::Node {
                    node,
                    depth: depth(node),
                    axis: AXES[(n.kind as usize).min(2)],
                    split: n.split,
                    t: [t_min, t_max],
                    near,
                    t_split: crosses.then_some(t_split),
                    far: crosses.then_some(far),
                });
            }
            WalkEvent::Leaf { node, t_min, t_max } => {
                let n = view.nodes[node];
                let objects = &view.leaf_objects[n.index as usize..(n.index + n.count) as usize];
                walk.push(Step::Leaf {
                    leaf: node,
                    depth: depth(node),
                    objects: objects.to_vec(),
                    t: [t_min, t_max],
                    tested: Vec::new(),
                    skipped: false,
                });
            }
            WalkEvent::SkippedLeaf { .. } => {
                if let Some(Step::Leaf { skipped, .. }) = walk.last_mut() {
                    *skipped = true;
                }
            }
            WalkEvent::Tested { object, t } => {
                if let Some(Step::Leaf { tested, .. }) = walk.last_mut() {
                    tested.push(Tested {
                        object,
                        hit: t.is_some(),
                        t,
                    });
                }
            }
            WalkEvent::Push { node, t_max } => walk.push(Step::Push {
                push: Resume { node, t_max },
            }),
            WalkEvent::Pop { node, t_max } => walk.push(Step::Pop {
                pop: Resume { node, t_max },
            }),
            WalkEvent::Restart { node, t_min } => {
                restarts += 1;
                walk.push(Step::Restart {
                    restart: Restart { node, t_min },
                });
            }
            WalkEvent::Rope { face, node, t_min } => walk.push(Step::Rope {
                rope: Rope {
                    face: FACES[face.min(5)],
                    node,
                    t_min,
                },
            }),
        }
    }
    InspectedRay {
        kind: match traced.kind {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Reflected => "reflected",
            RayKind::Refracted => "refracted",
            RayKind::Bounce => "bounce",
        },
        query: if traced.any { "any" } else { "nearest" },
        origin: ray.origin.to_array(),
        direction: ray.dir.to_array(),
        t_limit: (traced.t_limit < T_INFINITY).then_some(traced.t_limit),
        t_interval,
        walk,
        hit: traced.hit.as_ref().map(|h| inspected_hit(view, h)),
        counts: Counts {
            nodes: traced.cost.nodes_visited,
            leaves: traced.cost.leaves_visited,
            tests: traced.cost.objects_tested,
            restarts,
        },
        light: traced.light.clone(),
    }
}

fn inspected_hit(view: &TreeView, hit: &HitRecord) -> InspectedHit {
    InspectedHit {
        object: hit.object,
        kind: if hit.object < view.spheres {
            "sphere"
        } else {
            "triangle"
        },
        t: hit.t,
        point: hit.point.to_array(),
        normal: hit.normal.to_array(),
    }
}
