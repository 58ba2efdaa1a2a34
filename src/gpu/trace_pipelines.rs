//! The trace kernel's pipelines for one entry point and bind group layout,
//! one per [`KernelVariant`], each made the first time a frame needs it.
//! llvmpipe compiles a variant at its first dispatch, in about 0.35 s (one
//! measurement, under load: the 1,000-sphere frame took 475 ms with an empty
//! shader cache, 126 ms with it filled); Mesa's shader cache keeps it.

use std::collections::HashMap;
use std::sync::Mutex;

use super::{GpuContext, KernelVariant};
use crate::error::{Error, Result};

pub struct TracePipelines {
    module: wgpu::ShaderModule,
    layout: wgpu::BindGroupLayout,
    entry_point: &'static str,
    made: Mutex<HashMap<KernelVariant, wgpu::ComputePipeline>>,
}

impl TracePipelines {
    /// No pipeline is made yet.
    pub fn new(
        module: wgpu::ShaderModule,
        layout: wgpu::BindGroupLayout,
        entry_point: &'static str,
    ) -> Self {
        TracePipelines {
            module,
            layout,
            entry_point,
            made: Mutex::new(HashMap::new()),
        }
    }

    /// The bind group layout every pipeline of the set uses.
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
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
            super::bindings::trace_pipeline_on(
                device,
                &self.module,
                self.entry_point,
                &self.layout,
                variant,
            )
        })?;
        made.insert(variant, p.clone());
        Ok(p)
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
