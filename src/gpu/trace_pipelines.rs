//! The one place a compute pipeline of the trace kernel is assembled: the
//! kernel's module, an explicit bind group layout of one entry point's
//! bindings from the contract (gpu/bindings/), its bind groups, and one
//! pipeline per [`KernelVariant`], each made the first time a frame needs
//! it. The headless renderer (`render_tile`), the window's accumulation
//! (`accumulate_tile`) and the ray queries (`trace_rays`) all use it.
//!
//! Fitting the adapter: an entry point with every binding has up to 13
//! storage buffers (`trace_rays`; `render_tile` and `accumulate_tile` 12).
//! Where the device allows that many per shader stage (lavapipe 32), every
//! variant shares one layout and one parsed kernel, whose module each
//! variant specialises for itself (gpu/specialise.rs). Where it does not
//! (SwiftShader's Vulkan allows 10, as a browser's WebGPU may), each
//! variant binds only what its frames read: the bindings it never reads
//! ([`KernelVariant::unread_bindings`]) become private placeholders in its
//! module ([`super::shaders::trace_source_without`], the kernel the page
//! builds) and are left out of its layout and bind groups. A variant that
//! still needs more is refused in one line naming the limit.
//!
//! llvmpipe compiles a variant at its first dispatch (from hundredths of a
//! second for the seed's to about a tenth for the Cornell box's path
//! tracer, release build: benchmarks.md, "Start-up"; the general variants,
//! not folded, take seconds), so each entry point's pipelines are made
//! once per context and shared ([`GpuContext::trace_pipelines`]).

use std::any::Any;
use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex};

use super::bindings::{self, Access, Binding, EntryPoint, SceneChunks};
use super::kernel_io::FrameParams;
use super::{GpuContext, KernelVariant, SceneBuffers};
use crate::error::{Error, Result};

/// One entry point of the trace kernel, ready to bind and dispatch.
pub struct TracePipelines {
    entry: EntryPoint,
    chunks: SceneChunks,
    /// The device's storage buffers per shader stage.
    storage_limit: usize,
    /// Whether the entry point with every binding passes `storage_limit`,
    /// so that each variant binds only what it reads.
    slim: bool,
    /// The module and layout for each set of bindings left out (only the
    /// empty set unless `slim`), by the left-out binding numbers.
    kernels: Mutex<HashMap<Vec<u32>, Arc<Kernel>>>,
    made: Mutex<HashMap<KernelVariant, TracePipeline>>,
}

/// The kernel's module with some optional bindings left out, and the bind
/// group layout of the entry point's other bindings.
struct Kernel {
    /// The kernel as naga reads it, each variant's module specialised from
    /// it (gpu/specialise.rs).
    ir: (naga::Module, naga::valid::ModuleInfo),
    layout: wgpu::BindGroupLayout,
    /// The binding numbers left out (sorted): the key of its bind groups.
    omitted: Vec<u32>,
}

/// One variant's compute pipeline, and the kernel (layout) it was made with.
#[derive(Clone)]
pub struct TracePipeline {
    pub pipeline: wgpu::ComputePipeline,
    kernel: Arc<Kernel>,
}

/// The buffers of one dispatch (frame parameters, scene, the entry point's
/// own), bound as each pipeline's layout wants: one bind group per set of
/// left-out bindings, made the first time a pipeline asks for it (with
/// every binding: at once, when the buffers are named).
pub struct TraceBindGroup {
    label: &'static str,
    /// Every binding of the entry point and its buffer.
    buffers: Vec<(u32, wgpu::Buffer)>,
    /// The groups made so far, by the binding numbers they leave out.
    groups: Mutex<HashMap<Vec<u32>, wgpu::BindGroup>>,
}

/// How many of `bindings` are storage buffers.
fn storage_buffers(bindings: &[Binding]) -> usize {
    bindings
        .iter()
        .filter(|b| b.access != Access::Uniform)
        .count()
}

/// `map[key]`, made by `make` (under the map's lock) the first time it
/// is asked for; the kernels, pipelines and bind groups are each made once.
fn cached<K: Eq + Hash, V: Clone>(
    map: &Mutex<HashMap<K, V>>,
    what: &str,
    key: K,
    make: impl FnOnce() -> Result<V>,
) -> Result<V> {
    let mut map = map
        .lock()
        .map_err(|_| Error::Gpu(format!("the {what}' lock was poisoned")))?;
    if let Some(made) = map.get(&key) {
        return Ok(made.clone());
    }
    let made = make()?;
    map.insert(key, made.clone());
    Ok(made)
}

impl GpuContext {
    /// The pipelines of the trace kernel's entry point `entry` on this
    /// context, made the first time they are asked for.
    pub fn trace_pipelines(&self, entry: EntryPoint) -> Result<Arc<TracePipelines>> {
        let made = cached(&self.trace_pipelines, "trace pipelines", entry.name, || {
            Ok(Arc::new(TracePipelines::new(self, entry)?) as Arc<dyn Any + Send + Sync>)
        })?;
        made.downcast()
            .map_err(|_| Error::Gpu(format!("{} has pipelines of another type", entry.name)))
    }
}

impl TracePipelines {
    /// The kernel's module on `ctx`'s device and the layout of `entry`'s
    /// bindings there (the scene split as the device's limits allow:
    /// `bindings::scene_chunks`); on a device with too few storage buffers
    /// per stage for every binding, nothing until a variant is asked for.
    /// No pipeline is made yet.
    pub fn new(ctx: &GpuContext, entry: EntryPoint) -> Result<Self> {
        let limits = ctx.device.limits();
        let chunks = bindings::scene_chunks(&limits);
        let storage_limit = limits.max_storage_buffers_per_shader_stage as usize;
        let every = bindings::entry_point_bindings(chunks, entry.outputs);
        // The optional bindings are those of an unsplit scene
        // (`bindings::OPTIONAL_BINDINGS`); a device that splits it has room
        // for every binding anyway (`scene_chunks`).
        let slim = storage_buffers(&every) > storage_limit && chunks == bindings::UNSPLIT;
        let pipelines = TracePipelines {
            entry,
            chunks,
            storage_limit,
            slim,
            kernels: Mutex::new(HashMap::new()),
            made: Mutex::new(HashMap::new()),
        };
        if !slim {
            pipelines.kernel(ctx, &[])?;
        }
        Ok(pipelines)
    }

    /// The bindings `variant`'s pipeline leaves out: those it never reads
    /// where the device is short of storage buffers, else none.
    fn omitted(&self, variant: KernelVariant) -> Vec<Binding> {
        match self.slim {
            true => variant.unread_bindings(),
            false => Vec::new(),
        }
    }

    /// The module and layout with `omitted` left out, made now if it is the
    /// first call for them; refused in one line if the rest still has more
    /// storage buffers than the device allows per stage.
    fn kernel(&self, ctx: &GpuContext, omitted: &[Binding]) -> Result<Arc<Kernel>> {
        let mut key: Vec<u32> = omitted.iter().map(|b| b.index).collect();
        key.sort_unstable();
        cached(&self.kernels, "trace kernels", key.clone(), || {
            let bound: Vec<Binding> =
                bindings::entry_point_bindings(self.chunks, self.entry.outputs)
                    .into_iter()
                    .filter(|b| !omitted.contains(b))
                    .collect();
            let needed = storage_buffers(&bound);
            if needed > self.storage_limit {
                return Err(Error::Gpu(format!(
                    "{} needs {needed} storage buffers for this scene and walk, but {} allows {} per shader stage (max_storage_buffers_per_shader_stage)",
                    self.entry.name, ctx.info.name, self.storage_limit
                )));
            }
            let what = format!("creating the {} pipeline", self.entry.name);
            let ir =
                super::shaders::kernel_ir(self.entry, self.chunks, omitted).map_err(Error::Gpu)?;
            let kernel = ctx.checked(&what, |device| {
                let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some(self.entry.name),
                    entries: &bindings::layout_entries(&bound, wgpu::ShaderStages::COMPUTE),
                });
                Kernel {
                    ir,
                    layout,
                    omitted: key,
                }
            })?;
            Ok(Arc::new(kernel))
        })
    }

    /// The buffers of one dispatch: the frame's parameters, the scene's
    /// buffers, then the entry point's own buffers in the order of
    /// [`EntryPoint::outputs`]. With every binding in one layout, its bind
    /// group is made now (in the caller's error scope).
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        scene: &SceneBuffers,
        outputs: &[&wgpu::Buffer],
    ) -> TraceBindGroup {
        assert_eq!(
            outputs.len(),
            self.entry.outputs.len(),
            "{}",
            self.entry.name
        );
        let mut buffers = vec![(bindings::PARAMS.index, params.clone())];
        buffers.extend(scene.bound_buffers());
        buffers.extend(
            self.entry
                .outputs
                .iter()
                .zip(outputs)
                .map(|(b, buffer)| (b.index, (*buffer).clone())),
        );
        let group = TraceBindGroup {
            label: self.entry.name,
            buffers,
            groups: Mutex::new(HashMap::new()),
        };
        if !self.slim {
            let full = self
                .kernels
                .lock()
                .ok()
                .and_then(|k| k.get(&Vec::new()).cloned());
            if let Some(kernel) = full {
                let made = group.create(device, &kernel);
                if let Ok(mut groups) = group.groups.lock() {
                    groups.insert(Vec::new(), made);
                }
            }
        }
        group
    }

    /// Workgroups that cover `width` x `height` invocations.
    pub fn workgroups(&self, width: u32, height: u32) -> (u32, u32) {
        let [x, y, _] = self.entry.workgroup;
        (width.div_ceil(x), height.div_ceil(y))
    }

    /// Records into `encoder` one pass of `variant` over the tile `params`
    /// names (`tile_size`), with `group`'s buffers: the pipeline and its
    /// bind group made the first time they are asked for, `params` written
    /// to `params_buffer` now (submit before the next write).
    pub fn encode_tile(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        variant: KernelVariant,
        group: &TraceBindGroup,
        (params_buffer, params): (&wgpu::Buffer, &FrameParams),
    ) -> Result<()> {
        let pipeline = self.get(ctx, variant)?;
        let group = group.for_pipeline(ctx, &pipeline)?;
        ctx.queue
            .write_buffer(params_buffer, 0, bytemuck::bytes_of(params));
        self.record_pass(encoder, label, &pipeline, &group, params.tile_size, None);
        Ok(())
    }

    /// Records into `encoder` one pass of `pipeline` over `tile_size`
    /// invocations (whole workgroups) with `group`, timed by
    /// `timestamp_writes` if given.
    pub fn record_pass(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        label: &str,
        pipeline: &TracePipeline,
        group: &wgpu::BindGroup,
        [width, height]: [u32; 2],
        timestamp_writes: Option<wgpu::ComputePassTimestampWrites<'_>>,
    ) {
        let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes,
        });
        pass.set_pipeline(&pipeline.pipeline);
        pass.set_bind_group(0, group, &[]);
        let (gx, gy) = self.workgroups(width, height);
        pass.dispatch_workgroups(gx, gy, 1);
    }

    /// The pipeline for `variant`, made now if it is the first call for it.
    pub fn get(&self, ctx: &GpuContext, variant: KernelVariant) -> Result<TracePipeline> {
        cached(&self.made, "trace pipelines", variant, || {
            let kernel = self.kernel(ctx, &self.omitted(variant))?;
            let cache = ctx.pipeline_cache.as_ref();
            let pipeline = ctx.checked("creating a trace pipeline", |device| {
                self.pipeline(device, &kernel, variant, cache.map(|c| c.cache()))
            })??;
            if let Some(cache) = cache {
                cache.save();
            }
            Ok(TracePipeline { pipeline, kernel })
        })
    }

    /// A compute pipeline for the entry point with `kernel`'s explicit
    /// layout (so bind groups built from the same table fit it, whatever
    /// the entry point happens to use), specialised as `variant` says.
    fn pipeline(
        &self,
        device: &wgpu::Device,
        kernel: &Kernel,
        variant: KernelVariant,
        cache: Option<&wgpu::PipelineCache>,
    ) -> Result<wgpu::ComputePipeline> {
        let name = self.entry.name;
        // The general variants decide the walk and the rest from the
        // frame's uniforms, so folding would remove little from them; and
        // folded, the general path-tracing variant kept LLVM busy for
        // minutes where unfolded it compiles in seconds (lavapipe, Mesa 22.3).
        let fold = variant.walk != super::kernel_variant::Walk::FromParams;
        let module = super::shaders::specialised_module(
            device,
            &kernel.ir,
            name,
            &variant.constants(),
            fold,
        )
        .map_err(Error::Gpu)?;
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(name),
            bind_group_layouts: &[Some(&kernel.layout)],
            immediate_size: 0,
        });
        Ok(
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(name),
                // The overrides are applied on the host (gpu/specialise.rs).
                compilation_options: Default::default(),
                cache,
            }),
        )
    }

    /// Whether each variant binds only what it reads (the device has too
    /// few storage buffers per stage for every binding).
    pub fn binds_only_what_is_read(&self) -> bool {
        self.slim
    }

    /// The variants made so far.
    #[cfg(test)]
    pub fn variants(&self) -> Vec<KernelVariant> {
        self.made
            .lock()
            .map(|m| m.keys().copied().collect())
            .unwrap_or_default()
    }
}

impl TraceBindGroup {
    /// The bind group that fits `pipeline`'s layout, made now (in an error
    /// scope of its own) if it is the first call for that layout.
    pub fn for_pipeline(
        &self,
        ctx: &GpuContext,
        pipeline: &TracePipeline,
    ) -> Result<wgpu::BindGroup> {
        let kernel = &pipeline.kernel;
        cached(&self.groups, "bind groups", kernel.omitted.clone(), || {
            ctx.checked("binding the scene", |device| self.create(device, kernel))
        })
    }

    /// A bind group of every buffer but those `kernel` leaves out.
    fn create(&self, device: &wgpu::Device, kernel: &Kernel) -> wgpu::BindGroup {
        let entries: Vec<wgpu::BindGroupEntry<'_>> = self
            .buffers
            .iter()
            .filter(|(index, _)| !kernel.omitted.contains(index))
            .map(|(index, buffer)| wgpu::BindGroupEntry {
                binding: *index,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.label),
            layout: &kernel.layout,
            entries: &entries,
        })
    }
}
