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

use crate::choice::Choice;
use crate::error::{Error, Result};
use crate::geometry::Primitives;
use crate::gpu::{Accel, GpuContext, GpuScene, PreparedScene, WalkRecorder};
use crate::kdtree::{BuildParams, BuildStrategy, KdTree, Traversal};
use crate::render::RenderFlags;
use crate::scene::{Integrator, Scene};
use kdray_core::reference::ReferenceTracer;

mod document;
mod inspected_rays;

pub use document::{
    Counts, InspectedHit, InspectedLight, InspectedRay, Inspection, Restart, Resume, Rope, Step,
    Tested, INSPECT_VERSION,
};
use inspected_rays::{cpu_record, inspected_ray, kernel_record, TreeView};

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
