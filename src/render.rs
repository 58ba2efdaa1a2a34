//! One frame end to end: scene -> primitives and k-d tree
//! ([`PreparedScene`]) -> GPU buffers ([`GpuScene`]) -> tiled dispatch ->
//! 8-bit image, with the figures `--stats` reports; or one part of a
//! frame ([`FramePart`]: some of its rows, from another camera and lights),
//! as a farm task renders it. [`RenderFlags`] are the overrides and the
//! search a render is asked for.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::choice::Choice;
use crate::error::Result;
use crate::gpu::{
    Accel, CostTotals, GpuContext, GpuScene, GpuTimeSource, PreparedScene, RenderSummary,
    RenderedImage, Renderer, RowBand, TilePlan,
};
use crate::kdtree::{BuildStrategy, Traversal};
use crate::scene::{Frame, Integrator, Scene};

/// What `kdray render --stats` prints, as one JSON object.
#[derive(Debug, Clone, Serialize)]
pub struct RenderStats {
    pub adapter: String,
    pub backend: String,
    pub accel: Accel,
    /// The k-d walk (meaningful with `accel` kdtree).
    pub traversal: Traversal,
    pub width: u32,
    pub height: u32,
    pub samples: u32,
    #[serde(serialize_with = "by_name::serialize")]
    pub integrator: Integrator,
    pub spheres: usize,
    pub triangles: usize,
    pub kd_nodes: usize,
    pub kd_leaves: usize,
    pub kd_max_depth: u32,
    pub kd_refs_per_leaf: f64,
    /// Bytes of scene data in storage buffers.
    pub gpu_scene_bytes: u64,
    /// Of those, the textures' (headers, texture coordinates and texels).
    pub texture_bytes: u64,
    pub build_ms: f64,
    pub upload_ms: f64,
    pub gpu_ms: f64,
    pub gpu_time_source: GpuTimeSource,
    pub total_ms: f64,
    pub primary_rays: u64,
    /// Shadow and reflection rays, counted by the shader.
    pub shadow_rays: u64,
    pub reflection_rays: u64,
    /// Primary rays per second of GPU time, in millions.
    pub mrays_per_s: f64,
    /// All rays (primary + shadow + reflection) per second of GPU time, in millions.
    pub total_mrays_per_s: f64,
    /// Pixels (invocations) whose loops came near llvmpipe's limit of 65,535
    /// iterations (their own count reached half of it); only counted on
    /// llvmpipe, where such pixels may be wrong.
    pub loop_limited_pixels: u64,
    /// Path samples whose radiance was NaN or infinite, dropped (0 for the
    /// Whitted integrator): no such value reaches a pixel.
    pub nonfinite_samples: u64,
    /// Pixel samples per second of GPU time, in millions (the path tracer's
    /// speed: every sample is one path).
    pub msamples_per_s: f64,
    /// The walk's work (when counted: `--stats` and `--heatmap` count it).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub cost: Option<CostStats>,
}

/// The walk's work over the frame, every ray of every pixel (primary,
/// shadow, reflection), counted as `kdtree::traverse::WalkCost`: totals,
/// and per ray (over all three kinds).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CostStats {
    pub nodes_visited: u64,
    pub leaves_visited: u64,
    pub objects_tested: u64,
    pub nodes_visited_per_ray: f64,
    pub leaves_visited_per_ray: f64,
    pub objects_tested_per_ray: f64,
}

impl CostStats {
    pub fn new(totals: CostTotals, rays: u64) -> Self {
        let per_ray = |n: u64| n as f64 / rays.max(1) as f64;
        CostStats {
            nodes_visited: totals.nodes_visited,
            leaves_visited: totals.leaves_visited,
            objects_tested: totals.objects_tested,
            nodes_visited_per_ray: per_ray(totals.nodes_visited),
            leaves_visited_per_ray: per_ray(totals.leaves_visited),
            objects_tested_per_ray: per_ray(totals.objects_tested),
        }
    }
}

impl RenderStats {
    /// A one-line warning when llvmpipe's loop limit may have cut paths short.
    pub fn loop_limit_warning(&self) -> Option<String> {
        (self.loop_limited_pixels > 0).then(|| {
            format!(
                "warning: {} pixels needed more than llvmpipe's 65,535 loop iterations per pixel and may be wrong \
                 (fewer samples, a lower max_depth or --accel kdtree help; a real GPU has no such limit)",
                self.loop_limited_pixels
            )
        })
    }
}

/// The flags of a render: overrides of the scene's `[render]` size and
/// samples, and the search (accel, walk, build). `kdray render` and every
/// farm task take the same (a farm records them in its plan).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RenderFlags {
    pub width: Option<u32>,
    pub height: Option<u32>,
    pub samples: Option<u32>,
    #[serde(with = "by_name")]
    pub accel: Accel,
    #[serde(with = "by_name")]
    pub traversal: Traversal,
    #[serde(with = "by_name")]
    pub build: BuildStrategy,
    /// Overrides `[render] integrator`.
    #[serde(default, with = "option_by_name")]
    pub integrator: Option<Integrator>,
    /// Overrides `[render] seed`.
    #[serde(default)]
    pub seed: Option<u32>,
}

impl RenderFlags {
    /// Checks the overrides as `kdray render` does (errors name the flag).
    pub fn check(&self) -> Result<()> {
        check_render_flags(self.width, self.height, self.samples)
    }

    /// Applies the overrides to `scene`'s `[render]`, then checks what they
    /// make together: the samples for the integrator (a perfect square for
    /// Whitted's grid), and a light for the Whitted integrator.
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        let r = &mut scene.render;
        r.samples = self.samples.unwrap_or(r.samples);
        r.width = self.width.unwrap_or(r.width);
        r.height = self.height.unwrap_or(r.height);
        r.integrator = self.integrator.unwrap_or(r.integrator);
        r.seed = self.seed.unwrap_or(r.seed);
        crate::scene::check_samples(r.samples, r.integrator).map_err(|m| {
            let integrator = r.integrator.name();
            crate::Error::Usage(format!("--samples: {m} (with the {integrator} integrator)"))
        })?;
        if r.integrator == Integrator::Whitted && scene.lights.is_empty() {
            return Err(crate::Error::Usage(
                "--integrator whitted: the scene has no [[lights]]; the Whitted integrator needs one"
                    .into(),
            ));
        }
        Ok(())
    }
}
/// A farm plan's flags in tests: no overrides, the default search.
#[cfg(test)]
impl RenderFlags {
    pub(crate) fn no_overrides() -> Self {
        RenderFlags {
            width: None,
            height: None,
            samples: None,
            accel: Accel::Kdtree,
            traversal: Default::default(),
            build: Default::default(),
            integrator: None,
            seed: None,
        }
    }
}

/// An optional [`Choice`](crate::choice::Choice) written by its name.
mod option_by_name {
    use crate::choice::Choice;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<T: Choice, S: Serializer>(value: &Option<T>, s: S) -> Result<S::Ok, S::Error> {
        match value {
            Some(v) => s.serialize_some(v.name()),
            None => s.serialize_none(),
        }
    }

    pub fn deserialize<'de, T: Choice, D: Deserializer<'de>>(d: D) -> Result<Option<T>, D::Error> {
        match Option::<String>::deserialize(d)? {
            None => Ok(None),
            Some(name) => T::from_name(&name)
                .map(Some)
                .ok_or_else(|| serde::de::Error::custom(format!("unknown name {name}"))),
        }
    }
}

/// A [`Choice`](crate::choice::Choice) written by its name (farm.json).
mod by_name {
    use crate::choice::Choice;
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<T: Choice, S: Serializer>(value: &T, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(value.name())
    }

    pub fn deserialize<'de, T: Choice, D: Deserializer<'de>>(d: D) -> Result<T, D::Error> {
        let name = String::deserialize(d)?;
        T::from_name(&name).ok_or_else(|| serde::de::Error::custom(format!("unknown name {name}")))
    }
}

/// Checks command-line overrides of the image size and the samples against
/// the rules of the scene file's `[render]` keys; errors name the flag.
pub fn check_render_flags(
    width: Option<u32>,
    height: Option<u32>,
    samples: Option<u32>,
) -> Result<()> {
    let max = crate::scene::MAX_IMAGE_SIDE;
    for (flag, value) in [("--width", width), ("--height", height)] {
        if let Some(v) = value.filter(|v| !(1..=max).contains(v)) {
            return Err(crate::Error::Usage(format!(
                "{flag}: must be in 1..={max}, got {v}"
            )));
        }
    }
    if samples == Some(0) {
        return Err(crate::Error::Usage(
            "--samples: must be at least 1, got 0".into(),
        ));
    }
    Ok(())
}

fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Renders `scene` on `ctx` into memory (preparing a copy of it).
/// `max_tile_pixels` bounds one dispatch.
pub fn render_scene(
    ctx: &GpuContext,
    scene: &Scene,
    accel: Accel,
    max_tile_pixels: u64,
) -> Result<(RenderedImage, RenderStats)> {
    let r = &scene.render;
    let mut rgb = Vec::with_capacity(r.width as usize * r.height as usize * 3);
    let uploaded = GpuScene::upload(ctx, PreparedScene::new(scene.clone(), accel))?;
    let options = StreamOptions {
        max_tile_pixels,
        with_cost: true,
        ..StreamOptions::new(Traversal::default())
    };
    let (stats, summary) = render_streaming(ctx, &uploaded, None, options, &mut |band| {
        rgb.extend_from_slice(band.rgb);
        Ok(())
    })?;
    let image = RenderedImage {
        width: r.width,
        height: r.height,
        rgb,
        gpu_ms: summary.gpu_ms,
        gpu_time_source: summary.gpu_time_source,
        rays: summary.rays,
    };
    Ok((image, stats))
}

/// Which part of a frame a render covers: rows `rows.0..rows.1` of the
/// image (clamped to its height), seen from `frame`'s camera under its
/// lights, with the scene's `[render]` settings. Its pixels are those of
/// the whole frame's render: a pixel's colour depends on its place in the
/// image, never on the band or tile it was traced in.
#[derive(Debug, Clone, PartialEq)]
pub struct FramePart {
    pub frame: Frame,
    pub rows: (u32, u32),
    /// Path frames: only samples `first .. first + count` of each pixel
    /// (`None`: all `[render] samples`), their mean as the pixel
    /// ([`Renderer::with_sample_range`](crate::gpu::Renderer::with_sample_range)).
    pub samples: Option<(u32, u32)>,
}

impl FramePart {
    /// Every row of the scene's frame from its own camera and lights.
    pub fn whole(scene: &Scene) -> Self {
        FramePart {
            frame: Frame {
                camera: scene.camera,
                lights: scene.lights.clone(),
            },
            rows: (0, scene.render.height),
            samples: None,
        }
    }
}

/// The renderer `render_streaming` renders `scene` with (its radiance read
/// back if `radiance`, and a path frame's feature images if `features`).
fn renderer_for(
    ctx: &GpuContext,
    scene: &Scene,
    radiance: bool,
    features: bool,
) -> Result<Renderer> {
    let mut renderer = Renderer::new(ctx)?.with_settings(&scene.render);
    if radiance {
        renderer = renderer.with_radiance();
    }
    if features {
        renderer = renderer.with_features();
    }
    Ok(renderer)
}

/// Has the driver compile the pipeline that [`render_streaming`] runs for
/// frames of `uploaded` seen from `camera` with `traversal` (and
/// `radiance`), by tracing one workgroup's pixels: llvmpipe compiles a
/// pipeline at its first dispatch, in seconds, and every later render on
/// `ctx` shares it. A farm task does this while it prepares, so that its
/// fixed cost holds the compilation and its frames do not.
pub fn compile_for(
    ctx: &GpuContext,
    uploaded: &GpuScene,
    camera: &crate::scene::Camera,
    traversal: Traversal,
    radiance: bool,
) -> Result<()> {
    compile_for_output(ctx, uploaded, camera, traversal, radiance, false)
}

/// [`compile_for`] the pipeline whose bands also carry a path frame's
/// feature images when `features` (`StreamOptions::features`: a farm task
/// whose frames are denoised).
pub fn compile_for_output(
    ctx: &GpuContext,
    uploaded: &GpuScene,
    camera: &crate::scene::Camera,
    traversal: Traversal,
    radiance: bool,
    features: bool,
) -> Result<()> {
    let scene = &uploaded.prepared().scene;
    let params = uploaded
        .view_params(camera, &scene.render, uploaded.accel())
        .with_traversal(traversal);
    renderer_for(ctx, scene, radiance, features)?.compile(ctx, uploaded.buffers(), params, false)
}

/// How [`render_streaming`] traces and what its bands carry.
#[derive(Debug, Clone, Copy)]
pub struct StreamOptions {
    /// The k-d tree's walk.
    pub traversal: Traversal,
    /// The most pixels one dispatch traces.
    pub max_tile_pixels: u64,
    /// The bands carry each pixel's walk cost, and the stats their totals.
    pub with_cost: bool,
    /// The bands carry linear radiance beside the 8-bit colours.
    pub radiance: bool,
    /// Path frames' bands also carry the denoiser's feature images
    /// (`RowBand::features`: each pixel's mean albedo and normal).
    pub features: bool,
}

impl StreamOptions {
    /// `traversal`, in tiles of the default size, colours only.
    pub fn new(traversal: Traversal) -> Self {
        StreamOptions {
            traversal,
            max_tile_pixels: TilePlan::DEFAULT_MAX_TILE_PIXELS,
            with_cost: false,
            radiance: false,
            features: false,
        }
    }
}

/// Renders `part` of the frame of `uploaded` (the scene's own camera and
/// lights, every row, when `None`: a farm task's band of rows, or an
/// animation's frame without rebuilding the tree, name theirs; the part's
/// lights are written into the lights buffer first) with the search it was
/// prepared for and, for the k-d tree, the walk `options` names. Bands of
/// rows go to `sink` top to bottom as they are read back (for images too
/// big to hold, and progress bars), numbered in the whole image; the stats
/// count the rays of the rendered rows.
pub fn render_streaming(
    ctx: &GpuContext,
    uploaded: &GpuScene,
    part: Option<&FramePart>,
    options: StreamOptions,
    sink: &mut dyn FnMut(RowBand<'_>) -> Result<()>,
) -> Result<(RenderStats, RenderSummary)> {
    let StreamOptions {
        traversal,
        max_tile_pixels,
        with_cost,
        radiance,
        features,
    } = options;
    let total = Instant::now();
    let (prepared, buffers) = (uploaded.prepared(), uploaded.buffers());
    let (accel, upload_ms) = (uploaded.accel(), uploaded.upload_ms());
    let scene = &prepared.scene;

    let mut renderer = renderer_for(ctx, scene, radiance, features)?;
    // Flattening and the pipelines' creation count as upload.
    let transfer_ms = upload_ms;
    let upload_ms = prepared.flatten_ms + transfer_ms + ms_since(total);

    let whole;
    let part = match part {
        Some(part) => part,
        None => {
            whole = FramePart::whole(scene);
            &whole
        }
    };
    if let Some((first, count)) = part.samples {
        renderer = renderer.with_sample_range(first, count);
    }
    uploaded.write_lights(ctx, &part.frame.lights);
    let params = uploaded
        .view_params(&part.frame.camera, &scene.render, accel)
        .with_traversal(traversal);
    let (first_row, end_row) = (part.rows.0, part.rows.1.min(scene.render.height));
    let max_binding = crate::gpu::max_binding_bytes(&ctx.device.limits());
    let plan = TilePlan::new(
        scene.render.width,
        scene.render.height,
        max_tile_pixels,
        max_binding,
    )
    .with_rows(first_row, end_row);
    let summary = renderer.render_bands_with_cost(ctx, buffers, params, plan, with_cost, sink)?;
    let tree_stats = prepared.tree.stats();
    let rows = end_row.saturating_sub(first_row) as u64;
    let samples = part
        .samples
        .map_or(scene.render.samples, |(_, count)| count);
    let primary_rays = scene.render.width as u64 * rows * samples as u64;
    let stats = RenderStats {
        adapter: ctx.info.name.clone(),
        backend: format!("{:?}", ctx.info.backend),
        accel,
        traversal,
        width: scene.render.width,
        height: scene.render.height,
        samples: scene.render.samples,
        integrator: scene.render.integrator,
        spheres: scene.spheres.len(),
        triangles: scene.triangles.len(),
        kd_nodes: tree_stats.nodes,
        kd_leaves: tree_stats.leaves,
        kd_max_depth: tree_stats.max_depth,
        kd_refs_per_leaf: tree_stats.refs_per_leaf,
        gpu_scene_bytes: prepared.arrays.byte_size(),
        texture_bytes: std::mem::size_of_val(prepared.arrays.textures.as_slice()) as u64,
        build_ms: prepared.build_ms,
        upload_ms,
        gpu_ms: summary.gpu_ms,
        gpu_time_source: summary.gpu_time_source,
        // From the start of the build.
        total_ms: prepared.build_ms + prepared.flatten_ms + transfer_ms + ms_since(total),
        primary_rays,
        shadow_rays: summary.rays.shadow,
        reflection_rays: summary.rays.reflection,
        mrays_per_s: millions_per_second(primary_rays, summary.gpu_ms),
        total_mrays_per_s: millions_per_second(summary.rays.total(), summary.gpu_ms),
        loop_limited_pixels: if ctx.has_loop_limit() {
            summary.rays.loop_limited
        } else {
            0
        },
        nonfinite_samples: summary.rays.nonfinite,
        // One primary ray per sample.
        msamples_per_s: millions_per_second(primary_rays, summary.gpu_ms),
        cost: summary
            .cost
            .map(|totals| CostStats::new(totals, summary.rays.total())),
    };
    Ok((stats, summary))
}

/// `count` per second of `gpu_ms` milliseconds, in millions.
pub(crate) fn millions_per_second(count: u64, gpu_ms: f64) -> f64 {
    count as f64 / (gpu_ms * 1e3).max(1e-9)
}
