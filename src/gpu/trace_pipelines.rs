//! The one place a compute pipeline of the trace kernel is assembled: the
//! kernel's module, an explicit bind group layout of one entry point's
//! bindings from the contract (gpu/bindings.rs), its bind groups, and one
//! pipeline per [`KernelVariant`], each made the first time a frame needs
//! it. The headless renderer (`render_tile`), the window's accumulation
//! (`accumulate_tile`) and the ray queries (`trace_rays`) all use it.
//!
//! llvmpipe compiles a variant at its first dispatch, in about 0.35 s (one
//! measurement, under load: the 1,000-sphere frame took 475 ms with an empty
//! shader cache, 126 ms with it filled); Mesa's shader cache keeps it.

use std::collections::HashMap;
use std::sync::Mutex;

use super::bindings::{self, EntryPoint};
use super::{GpuContext, KernelVariant, SceneBuffers};
use crate::error::{Error, Result};

/// One entry point of the trace kernel, ready to bind and dispatch.
pub struct TracePipelines {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    entry: EntryPoint,
    made: Mutex<HashMap<KernelVariant, wgpu::ComputePipeline>>,
}

impl TracePipelines {
    /// The kernel's module on `ctx`'s device and the layout of `entry`'s
    /// bindings there (the scene split as the device's limits allow:
    /// `bindings::scene_chunks`). No pipeline is made yet.
    pub fn new(ctx: &GpuContext, entry: EntryPoint) -> Result<Self> {
        ctx.checked(&format!("creating the {} pipeline", entry.name), |device| {
            let chunks = bindings::scene_chunks(&device.limits());
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(entry.name),
                entries: &bindings::layout_entries(
                    &bindings::entry_point_bindings(chunks, entry.outputs),
                    wgpu::ShaderStages::COMPUTE,
                ),
            });
            TracePipelines {
                module: super::shaders::trace_module(device),
                layout,
                entry,
                made: Mutex::new(HashMap::new()),
            }
        })
    }

    /// The bind group of one dispatch: the frame's parameters, the scene's
    /// buffers, then the entry point's own buffers in the order of
    /// [`EntryPoint::outputs`].
    pub fn bind_group(
        &self,
        device: &wgpu::Device,
        params: &wgpu::Buffer,
        scene: &SceneBuffers,
        outputs: &[&wgpu::Buffer],
    ) -> wgpu::BindGroup {
        assert_eq!(
            outputs.len(),
            self.entry.outputs.len(),
            "{}",
            self.entry.name
        );
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: bindings::PARAMS.index,
            resource: params.as_entire_binding(),
        }];
        entries.extend(scene.bind_entries());
        entries.extend(self.entry.outputs.iter().zip(outputs).map(|(b, buffer)| {
            wgpu::BindGroupEntry {
                binding: b.index,
                resource: buffer.as_entire_binding(),
            }
        }));
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(self.entry.name),
            layout: &self.layout,
            entries: &entries,
        })
    }

    /// Workgroups that cover `width` x `height` invocations.
    pub fn workgroups(&self, width: u32, height: u32) -> (u32, u32) {
        let [x, y, _] = self.entry.workgroup;
        (width.div_ceil(x), height.div_ceil(y))
    }

    /// The pipeline for `variant`, made now if it is the first call for it.
    pub fn get(&self, ctx: &GpuContext, variant: KernelVariant) -> Result<wgpu::ComputePipeline> {
        let mut made = self
            .made
            .lock()
            .map_err(|_| Error::Gpu("the trace pipelines' lock was poisoned".to_string()))?;
        if let Some(p) = made.get(&variant) {
            return Ok(p.clone());
        }
        let p = ctx.checked("creating a trace pipeline", |device| {
            self.pipeline(device, variant)
        })?;
        made.insert(variant, p.clone());
        Ok(p)
    }

    /// A compute pipeline for the entry point with the explicit layout (so
    /// bind groups built from the same table fit it, whatever the entry
    /// point happens to use), specialised as `variant` says.
    fn pipeline(&self, device: &wgpu::Device, variant: KernelVariant) -> wgpu::ComputePipeline {
        let name = self.entry.name;
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(name),
            bind_group_layouts: &[Some(&self.layout)],
            immediate_size: 0,
        });
        device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
            label: Some(name),
            layout: Some(&pipeline_layout),
            module: &self.module,
            entry_point: Some(name),
            compilation_options: wgpu::PipelineCompilationOptions {
                constants: &variant.constants(),
                ..Default::default()
            },
            cache: None,
        })
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
