//! The kernel's debug entry point, `trace_rays` (shaders/query.wgsl): rays in,
//! the kernel's own hits out, with no camera and no shading. Tests hold the
//! GPU walks against the CPU mirror and brute force ray by ray with it, on
//! the same random scenes and rays as the CPU property tests.

use super::bindings;
use super::context::buffer_holding;
use super::trace_pipelines::TracePipeline;
use super::{Accel, GpuContext, KernelVariant, SceneBuffers, TracePipelines};
use crate::error::Result;
use crate::geometry::Ray;
use crate::gpu::{FrameParams, GpuQueryHit, GpuQueryRay};
use crate::kdtree::traverse::{Hit, WalkCost};
use crate::kdtree::Traversal;

/// One query: a ray, how far to look, and which question.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayQuery {
    pub ray: Ray,
    /// Nearest hit: `t <= t_limit`; any hit: `t < t_limit`.
    pub t_limit: f32,
    /// Any-hit (shadow-ray) query rather than nearest hit.
    pub any_hit: bool,
}

/// The `trace_rays` pipeline: the general variant, which reads every choice
/// from the frame's uniforms, so the tests hold that form of the kernel to
/// the CPU (the renderer's tests hold the specialised ones to it).
pub struct RayQueries {
    pipelines: std::sync::Arc<TracePipelines>,
    pipeline: TracePipeline,
}

/// Most workgroups in one dimension of a dispatch (WebGPU's default limit).
const MAX_GROUPS_PER_DIMENSION: u32 = 65_535;

impl RayQueries {
    pub fn new(ctx: &GpuContext) -> Result<Self> {
        let pipelines = ctx.trace_pipelines(bindings::TRACE_RAYS)?;
        let pipeline = pipelines.get(ctx, KernelVariant::GENERAL)?;
        Ok(RayQueries {
            pipelines,
            pipeline,
        })
    }

    /// Traces `queries` through `scene` with `accel` (the k-d tree with the
    /// restart walk). Hits name objects by the scene's ids (`scene_ids` maps
    /// GPU ids back: `SceneArrays::scene_ids`).
    pub fn trace(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        scene_ids: &[u32],
        accel: Accel,
        queries: &[RayQuery],
    ) -> Result<Vec<Option<Hit>>> {
        let counted =
            self.trace_counted(ctx, scene, scene_ids, accel, Traversal::default(), queries)?;
        Ok(counted.into_iter().map(|(hit, _)| hit).collect())
    }

    /// [`RayQueries::trace`] with the k-d walk `traversal`, and with the
    /// work the kernel's walk did for each ray (counted as the CPU mirror
    /// counts it: `WalkCost`).
    pub fn trace_counted(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        scene_ids: &[u32],
        accel: Accel,
        traversal: Traversal,
        queries: &[RayQuery],
    ) -> Result<Vec<(Option<Hit>, WalkCost)>> {
        if queries.is_empty() {
            return Ok(Vec::new());
        }
        let params = FrameParams::for_queries(scene, accel).with_traversal(traversal);
        let (bind_group, hits, costs, readback, hits_bytes, costs_bytes) =
            self.query_buffers(ctx, scene, &params, queries)?;
        let bind_group = bind_group.for_pipeline(ctx, &self.pipeline)?;
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("trace_rays"),
            });
        self.encode_dispatch(&mut encoder, &self.pipeline, &bind_group, queries.len());
        encoder.copy_buffer_to_buffer(&hits, 0, &readback, 0, hits_bytes);
        encoder.copy_buffer_to_buffer(&costs, 0, &readback, hits_bytes, costs_bytes);
        ctx.queue.submit([encoder.finish()]);
        let bytes = ctx.read_buffer(&readback, hits_bytes + costs_bytes)?;
        let (hit_bytes, cost_bytes) = bytes.split_at(hits_bytes as usize);
        let hits: &[GpuQueryHit] = bytemuck::cast_slice(hit_bytes);
        let costs: &[u32] = bytemuck::cast_slice(cost_bytes);
        Ok(hits
            .iter()
            .zip(costs.chunks_exact(bindings::COST_WORDS))
            .map(|(h, c)| {
                let hit = (h.object != bindings::NO_OBJECT).then(|| Hit {
                    object: scene_ids
                        .get(h.object as usize)
                        .copied()
                        .unwrap_or(u32::MAX),
                    t: h.t,
                });
                (hit, WalkCost::from_words(c))
            })
            .collect())
    }

    /// Submit-to-done wall time (ms) of each of `repeats` dispatches of
    /// `queries` through `scene` with the k-d walk `traversal`, by the
    /// kernel specialised for the scene and walk with no cost counting: the
    /// cost of tracing a queue of rays alone, as a wavefront's extension
    /// and shadow stages would (the bench's `--wavefront-bound`). The
    /// buffers are made once, before the first.
    pub fn time_queries(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        traversal: Traversal,
        queries: &[RayQuery],
        repeats: u32,
    ) -> Result<Vec<f64>> {
        let params = FrameParams::for_queries(scene, Accel::Kdtree).with_traversal(traversal);
        let variant = KernelVariant {
            count_costs: false,
            ..KernelVariant::for_scene(scene).with_walk_of(&params)
        };
        let pipeline = self.pipelines.get(ctx, variant)?;
        let (bind_group, ..) = self.query_buffers(ctx, scene, &params, queries)?;
        let bind_group = bind_group.for_pipeline(ctx, &pipeline)?;
        let mut times = Vec::new();
        for _ in 0..repeats {
            let mut encoder = ctx.device.create_command_encoder(&Default::default());
            self.encode_dispatch(&mut encoder, &pipeline, &bind_group, queries.len());
            let started = std::time::Instant::now();
            ctx.queue.submit([encoder.finish()]);
            ctx.wait_idle()?;
            times.push(started.elapsed().as_secs_f64() * 1e3);
        }
        Ok(times)
    }

    /// The query's uniform, rays, hits, costs and readback buffers, bound.
    #[allow(clippy::type_complexity)]
    fn query_buffers(
        &self,
        ctx: &GpuContext,
        scene: &SceneBuffers,
        params: &FrameParams,
        queries: &[RayQuery],
    ) -> Result<(
        super::trace_pipelines::TraceBindGroup,
        wgpu::Buffer,
        wgpu::Buffer,
        wgpu::Buffer,
        u64,
        u64,
    )> {
        let rays: Vec<GpuQueryRay> = queries
            .iter()
            .map(|q| GpuQueryRay {
                origin: q.ray.origin.to_array(),
                t_limit: q.t_limit,
                dir: q.ray.dir.to_array(),
                any_hit: q.any_hit as u32,
            })
            .collect();
        let hits_bytes = (queries.len() * std::mem::size_of::<GpuQueryHit>()) as u64;
        let costs_bytes = (queries.len() * bindings::COST_WORDS * 4) as u64;
        let (bind_group, hits, costs, readback) =
            ctx.checked("allocating the ray query buffers", |device| {
                let storage =
                    |label, contents: &[u8], usage| buffer_holding(device, label, contents, usage);
                let params = storage(
                    "query params",
                    bytemuck::bytes_of(params),
                    wgpu::BufferUsages::UNIFORM,
                );
                let rays = storage(
                    "query rays",
                    bytemuck::cast_slice(&rays),
                    wgpu::BufferUsages::STORAGE,
                );
                let hits = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("query hits"),
                    size: hits_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let costs = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("query costs"),
                    size: costs_bytes,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
                    mapped_at_creation: false,
                });
                let readback = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("query hits and costs readback"),
                    size: hits_bytes + costs_bytes,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                // QUERY_OUTPUTS: the rays, their hits, their costs.
                let bind_group =
                    self.pipelines
                        .bind_group(device, &params, scene, &[&rays, &hits, &costs]);
                (bind_group, hits, costs, readback)
            })?;
        Ok((bind_group, hits, costs, readback, hits_bytes, costs_bytes))
    }

    /// Records the dispatch of one invocation per query.
    fn encode_dispatch(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &TracePipeline,
        bind_group: &wgpu::BindGroup,
        queries: usize,
    ) {
        let (groups, _) = self.pipelines.workgroups(queries as u32, 1);
        let (gx, gy) = if groups <= MAX_GROUPS_PER_DIMENSION {
            (groups, 1)
        } else {
            (
                MAX_GROUPS_PER_DIMENSION,
                groups.div_ceil(MAX_GROUPS_PER_DIMENSION),
            )
        };
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("trace_rays"),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline.pipeline);
        pass.set_bind_group(0, bind_group, &[]);
        pass.dispatch_workgroups(gx, gy, 1);
    }
}
