//! `kdray inspect`: every ray one pixel's first sample traces, with the k-d
//! walk that searched it, step by step, as one JSON document
//! (docs/inspect.md describes the format, [`INSPECT_VERSION`]).
//!
//! Two sources give the same document ([`WalkSource`]):
//! - the kernel: the inspect kernel ([`crate::gpu::WalkRecorder`]) traces
//!   the pixel's sample on the GPU as the renderer does, with either
//!   integrator, and logs every ray and walk step as it runs;
//! - the CPU mirror: the reference tracer
//!   ([`kdray_core::reference::ReferenceTracer::trace_recorded`]) follows
//!   the Whitted kernel's path in f32, and the CPU mirrors of the walks
//!   report their steps to an observer ([`crate::kdtree::WalkObserver`]).
//!
//! The GPU tests hold the two to each other, and each inspected ray's hit
//! and counted work to the kernel's ray queries.

use std::path::Path;

use serde::Serialize;

use crate::choice::Choice;
use crate::error::{Error, Result};
use crate::geometry::{Primitives, Ray, T_INFINITY};
use crate::gpu::bindings::walk_codes::LIGHT_SKY;
use crate::gpu::{Accel, GpuContext, GpuScene, PreparedScene, RecordedRay, WalkRecorder};
use crate::kdtree::traverse::WalkCost;
use crate::kdtree::{BuildParams, BuildStrategy, KdTree, Traversal, WalkEvent};
use crate::layout::KdNode;
use crate::layout::{LIGHT_DIRECTIONAL, LIGHT_EMITTER, LIGHT_SPOT};
use crate::render::RenderFlags;
use crate::scene::{Integrator, LightKind, Scene};
use glam::Vec3;
use kdray_core::reference::{LightId, RayKind, ReferenceTracer, TracedRay};

/// The format's version: raised when a key changes meaning or goes.
pub const INSPECT_VERSION: u32 = 1;

/// What to inspect: a pixel (column, row from the top-left) of a frame,
/// rendered with `flags` (size, samples, walk, build), and where the walk
/// comes from.
#[derive(Debug, Clone)]
pub struct InspectRequest {
    pub pixel: (u32, u32),
    pub frame: u32,
    pub flags: RenderFlags,
    pub source: WalkSource,
}

/// Where the rays and their walks come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum WalkSource {
    /// Logged by the kernel on the GPU as it traces the pixel (either
    /// integrator).
    #[default]
    Kernel,
    /// Traced on the CPU by the reference tracer and the walks' mirrors
    /// (the Whitted integrator; needs no GPU).
    CpuMirror,
}

impl WalkSource {
    /// The name `--walk-source` takes and the document's `walk_source`.
    pub fn name(self) -> &'static str {
        match self {
            WalkSource::Kernel => "kernel",
            WalkSource::CpuMirror => "cpu",
        }
    }

    /// From `--walk-source`'s value.
    pub fn parse(text: &str) -> Result<WalkSource> {
        match text {
            "kernel" => Ok(WalkSource::Kernel),
            "cpu" => Ok(WalkSource::CpuMirror),
            _ => Err(Error::Usage(format!(
                "--walk-source: expected kernel or cpu, got {text:?}"
            ))),
        }
    }
}

/// The document `kdray inspect` prints.
#[derive(Debug, Clone, Serialize)]
pub struct Inspection {
    pub version: u32,
    pub scene: String,
    /// Column, row; (0, 0) is the top-left pixel.
    pub pixel: [u32; 2],
    pub frame: u32,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel; the rays are those of sample 0 (the top-left
    /// cell of the k x k grid).
    pub samples: u32,
    /// `whitted` or `path`.
    pub integrator: &'static str,
    /// `kdtree` or `brute` (no walk: every object tested).
    pub accel: &'static str,
    pub traversal: &'static str,
    pub build: &'static str,
    /// `kernel` or `cpu`.
    pub walk_source: &'static str,
    pub rays: Vec<InspectedRay>,
    /// The sample's colour (Whitted, before clamping) or radiance (path)
    /// as the kernel computed it; the kernel source only.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sample: Option<[f32; 3]>,
}

/// One traced ray.
#[derive(Debug, Clone, Serialize)]
pub struct InspectedRay {
    /// `primary`, `shadow`, `reflected`, `refracted` or (path) `bounce`.
    pub kind: &'static str,
    /// `nearest` (the closest hit) or `any` (a shadow ray's: any hit before
    /// the light ends the search).
    pub query: &'static str,
    pub origin: [f32; 3],
    /// Unit.
    pub direction: [f32; 3],
    /// How far the query looks (`null`: unbounded).
    pub t_limit: Option<f32>,
    /// The part of the ray the walk searches: inside the scene's box, past
    /// the origin, up to `t_limit` (`null`: none, the walk never starts;
    /// always with brute force, which clips nothing).
    pub t_interval: Option<[f32; 2]>,
    pub walk: Vec<Step>,
    pub hit: Option<InspectedHit>,
    pub counts: Counts,
    /// A shadow ray's light: what it aims at, and with what probability.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub light: Option<InspectedLight>,
}

/// The light a shadow ray aims at, in the scene's terms, and the chance
/// the integrator gave it: in the path tracer's next-event estimation the
/// probability of picking it from the hit (by power; an emitter through the
/// light tree) and the density of the ray's
/// direction; in the Whitted integrator every light gets its shadow ray
/// (probability 1).
#[derive(Debug, Clone, Serialize, PartialEq)]
pub struct InspectedLight {
    /// `light` (an entry of the scene's `[[lights]]`), `emitter` (an object
    /// whose material emits) or `sky` (the sky image).
    pub source: &'static str,
    /// A scene light: its index in `[[lights]]`, in file order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub index: Option<u32>,
    /// A scene light: `point`, `spot` or `directional`; an emitter:
    /// `sphere` or `triangle`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<&'static str>,
    /// An emitter: its object id, numbered as hits are.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub object: Option<u32>,
    /// An emissive triangle: its index among the scene's triangles.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub triangle: Option<u32>,
    /// The probability the light was picked with (Whitted: 1).
    pub pick: f32,
    /// The solid-angle density of the ray's direction, the pick included
    /// (the path tracer, for an emitter or the sky); `null` for a point,
    /// spot or directional light (a delta) and in the Whitted integrator.
    pub pdf: Option<f32>,
}

impl InspectedLight {
    /// The light, as the CPU reference names it.
    pub fn id(&self) -> LightId {
        match (self.source, self.index, self.object) {
            ("light", Some(i), _) => LightId::Scene(i),
            ("emitter", _, Some(o)) => LightId::Emitter(o),
            _ => LightId::Sky,
        }
    }
}

/// One step of a walk: an inner node, a leaf, or how the walk moved on.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Step {
    Node {
        node: usize,
        depth: u32,
        axis: &'static str,
        split: f32,
        /// The segment still to search in this node.
        t: [f32; 2],
        /// The child the walk goes on in.
        near: usize,
        /// Where the segment crosses the plane into the other child, when
        /// it does (`far`).
        #[serde(skip_serializing_if = "Option::is_none")]
        t_split: Option<f32>,
        #[serde(skip_serializing_if = "Option::is_none")]
        far: Option<usize>,
    },
    Leaf {
        leaf: usize,
        depth: u32,
        objects: Vec<u32>,
        /// Where the ray is inside the leaf.
        t: [f32; 2],
        tested: Vec<Tested>,
        /// The rope walk's leaf the ray spends no time in: not tested.
        #[serde(skip_serializing_if = "std::ops::Not::not")]
        skipped: bool,
    },
    Push {
        push: Resume,
    },
    Pop {
        pop: Resume,
    },
    Restart {
        restart: Restart,
    },
    Rope {
        rope: Rope,
    },
}

/// A short-stack entry: the far child and the segment's end there.
#[derive(Debug, Clone, Serialize)]
pub struct Resume {
    pub node: usize,
    pub t_max: f32,
}

/// A descent starting over from `node` at `t_min`.
#[derive(Debug, Clone, Serialize)]
pub struct Restart {
    pub node: usize,
    pub t_min: f32,
}

/// The rope walk leaving a leaf through `face` at `t_min` for `node`.
#[derive(Debug, Clone, Serialize)]
pub struct Rope {
    /// `x-`, `x+`, `y-`, `y+`, `z-` or `z+`.
    pub face: &'static str,
    pub node: usize,
    pub t_min: f32,
}

/// One object test in a leaf.
#[derive(Debug, Clone, Serialize)]
pub struct Tested {
    pub object: u32,
    pub hit: bool,
    /// Where the ray meets the object (any t > 0, within the query's limit
    /// or not).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<f32>,
}

/// What the query returned.
#[derive(Debug, Clone, Serialize)]
pub struct InspectedHit {
    pub object: u32,
    /// `sphere` or `triangle`.
    pub kind: &'static str,
    pub t: f32,
    pub point: [f32; 3],
    /// Unit geometric normal, facing the ray.
    pub normal: [f32; 3],
}

/// The walk's work, counted as the kernel counts it (`WalkCost`), and its
/// restarts.
#[derive(Debug, Clone, Copy, Serialize, PartialEq, Eq)]
pub struct Counts {
    pub nodes: u32,
    pub leaves: u32,
    pub tests: u32,
    pub restarts: u32,
}

/// Loads `path` and inspects `request`'s pixel. Bad input (the scene, a
/// flag, the pixel, the frame, the CPU mirror with the path integrator) is
/// a usage or scene error (exit 2).
pub fn inspect_file(path: &Path, request: &InspectRequest) -> Result<Inspection> {
    // The CPU mirror walks the world-space triangles, instances flattened.
    let mut scene = crate::scene::load_scene(path)?.flattened();
    let flags = &request.flags;
    flags.check()?;
    flags.apply(&mut scene)?;
    if request.source == WalkSource::CpuMirror && scene.render.integrator != Integrator::Whitted {
        return Err(Error::Usage(
            "--walk-source cpu follows the Whitted integrator's rays only; the kernel's (--walk-source kernel) follows the path tracer's too".into(),
        ));
    }
    let frames = scene.frame_count();
    if request.frame >= frames {
        return Err(Error::Usage(format!(
            "--frame: the scene has frames 0..{frames}, got {}",
            request.frame
        )));
    }
    let shown = scene.frame(request.frame);
    (scene.camera, scene.lights) = (shown.camera, shown.lights);
    check_pixel(&scene, request.pixel)?;
    let mut inspection = match request.source {
        WalkSource::CpuMirror => {
            let tree = match flags.accel {
                Accel::Kdtree => Some(build_tree(&scene, flags.build)),
                Accel::Brute => None,
            };
            inspect_scene(&scene, tree, flags.traversal, request.pixel)?
        }
        WalkSource::Kernel => {
            let ctx = GpuContext::new()?;
            let prepared = PreparedScene::built_by(scene, flags.accel, flags.build);
            let gpu = GpuScene::upload(&ctx, prepared)?;
            let recorder = WalkRecorder::new(&ctx)?;
            inspect_on_gpu(&ctx, &recorder, &gpu, flags.traversal, request.pixel)?
        }
    };
    inspection.scene = path.display().to_string();
    inspection.frame = request.frame;
    inspection.build = flags.build.name();
    Ok(inspection)
}

/// The tree `kdray render` builds for `scene` with `strategy`
/// (`PreparedScene::built_by`), over `Primitives::from_scene`'s numbering.
pub fn build_tree(scene: &Scene, strategy: BuildStrategy) -> KdTree {
    let prims = Primitives::from_scene(scene);
    let params = BuildParams {
        strategy,
        ..BuildParams::for_primitives(&prims)
    };
    KdTree::build_for(&prims, params)
}

/// Parses `--pixel`'s `X,Y` (two whole numbers).
pub fn parse_pixel(text: &str) -> Result<(u32, u32)> {
    let bad = || {
        Error::Usage(format!(
            "--pixel: expected X,Y (two whole numbers), got {text:?}"
        ))
    };
    let (x, y) = text.split_once(',').ok_or_else(bad)?;
    let number = |s: &str| s.trim().parse::<u32>().map_err(|_| bad());
    Ok((number(x)?, number(y)?))
}

/// A pixel outside `scene`'s image is a usage error.
fn check_pixel(scene: &Scene, (x, y): (u32, u32)) -> Result<()> {
    let r = &scene.render;
    if x >= r.width || y >= r.height {
        return Err(Error::Usage(format!(
            "--pixel: {x},{y} is outside the {} x {} image (columns 0..{}, rows 0..{})",
            r.width, r.height, r.width, r.height
        )));
    }
    Ok(())
}

/// The document's fields that do not depend on the source; `scene`,
/// `frame` and `build` are left for the caller (empty, 0 and the default
/// build).
fn document(scene: &Scene, (x, y): (u32, u32), accel: Accel, traversal: Traversal) -> Inspection {
    let r = &scene.render;
    Inspection {
        version: INSPECT_VERSION,
        scene: String::new(),
        pixel: [x, y],
        frame: 0,
        width: r.width,
        height: r.height,
        samples: r.samples,
        integrator: r.integrator.name(),
        accel: match accel {
            Accel::Kdtree => "kdtree",
            Accel::Brute => "brute",
        },
        traversal: traversal.name(),
        build: BuildStrategy::default().name(),
        walk_source: WalkSource::CpuMirror.name(),
        rays: Vec::new(),
        sample: None,
    }
}

/// Inspects pixel (column, row) of `scene` as it stands (size, samples,
/// camera and lights of the frame wanted) with the CPU mirror, walking
/// `tree` (built over `Primitives::from_scene(scene)`) with `traversal`, or
/// brute force (`None`). The document's `scene`, `frame` and `build` are
/// left for the caller (empty, 0 and the default build).
pub fn inspect_scene(
    scene: &Scene,
    tree: Option<KdTree>,
    traversal: Traversal,
    (x, y): (u32, u32),
) -> Result<Inspection> {
    check_pixel(scene, (x, y))?;
    let accel = if tree.is_some() {
        Accel::Kdtree
    } else {
        Accel::Brute
    };
    let mut inspection = document(scene, (x, y), accel, traversal);
    let kept = tree.clone();
    let view = TreeView::of(kept.as_ref(), scene.spheres.len() as u32);
    let tracer = match tree {
        Some(tree) => ReferenceTracer::with_tree(scene, tree, traversal),
        None => ReferenceTracer::new(scene, false),
    };
    let primary = tracer.sample_ray(y, x, 0, 0);
    inspection.rays = tracer
        .trace_recorded(primary)
        .iter()
        .map(|t| inspected_ray(&view, &cpu_record(scene, &tracer, t)))
        .collect();
    Ok(inspection)
}

/// Inspects pixel (column, row) of `scene`'s own frame (its camera, lights
/// and `[render]`) with the kernel: `recorder` traces the pixel's first
/// sample on the GPU with the integrator the scene asks for and the walk
/// `traversal`, logging its rays and walks. The document's `scene`, `frame`
/// and `build` are left for the caller (empty, 0 and the default build).
pub fn inspect_on_gpu(
    ctx: &GpuContext,
    recorder: &WalkRecorder,
    scene: &GpuScene,
    traversal: Traversal,
    pixel: (u32, u32),
) -> Result<Inspection> {
    let params = scene.frame_params();
    inspect_frame_on_gpu(
        ctx,
        recorder,
        scene,
        scene.scene(),
        params,
        traversal,
        pixel,
    )
}

/// [`inspect_on_gpu`] for the frame `params` describe (its camera, size
/// and settings: the window's view) walked with `traversal`, with `shown`
/// the scene as that frame sees it (its `[render]` names the document's
/// size, samples and integrator).
pub fn inspect_frame_on_gpu(
    ctx: &GpuContext,
    recorder: &WalkRecorder,
    scene: &GpuScene,
    shown: &Scene,
    params: crate::gpu::FrameParams,
    traversal: Traversal,
    pixel: (u32, u32),
) -> Result<Inspection> {
    check_pixel(shown, pixel)?;
    let params = params.with_traversal(traversal);
    let log = recorder.record(ctx, scene.buffers(), &params, pixel)?;
    let mut inspection = document(shown, pixel, scene.accel(), traversal);
    let tree = match scene.accel() {
        Accel::Kdtree => Some(&scene.prepared().tree),
        Accel::Brute => None,
    };
    let view = TreeView::of(tree, shown.spheres.len() as u32);
    inspection.rays = log
        .rays
        .iter()
        .map(|r| inspected_ray(&view, &kernel_record(r, shown.spheres.len() as u32)))
        .collect();
    inspection.walk_source = WalkSource::Kernel.name();
    inspection.sample = Some(log.sample);
    Ok(inspection)
}

/// One ray as either source gives it.
struct RayRecord<'a> {
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

fn cpu_record<'a>(scene: &Scene, tracer: &ReferenceTracer, traced: &'a TracedRay) -> RayRecord<'a> {
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
fn kernel_light(light: &crate::gpu::walk_log::RecordedLight, spheres: u32) -> InspectedLight {
    let id = match light.kind {
        LIGHT_SKY => LightId::Sky,
        LIGHT_EMITTER => LightId::Emitter(light.object),
        _ => LightId::Scene(light.entry),
    };
    let kind = light_kind_name(light.kind);
    light_named(id, Some(kind), spheres, light.pick, light.density)
}

fn kernel_record(recorded: &RecordedRay, spheres: u32) -> RayRecord<'_> {
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
struct TreeView<'a> {
    nodes: &'a [KdNode],
    leaf_objects: &'a [u32],
    depths: Vec<u32>,
    /// Objects below this id are spheres.
    spheres: u32,
}

impl<'a> TreeView<'a> {
    /// `tree`'s nodes (none for brute force) in a scene of `spheres` spheres.
    fn of(tree: Option<&'a KdTree>, spheres: u32) -> TreeView<'a> {
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

fn inspected_ray(view: &TreeView, traced: &RayRecord) -> InspectedRay {
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
