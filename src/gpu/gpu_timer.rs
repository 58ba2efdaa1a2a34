//! A tile's GPU time from two timestamp queries around its compute pass,
//! and the context's waits and readbacks that the renderer's dispatches
//! use.

use super::context::GpuContext;
use crate::error::{Error, Result};

/// Two timestamps around each tile's compute pass.
pub(super) struct GpuTimer {
    queries: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    readback: wgpu::Buffer,
}

impl GpuTimer {
    pub(super) fn new(device: &wgpu::Device) -> Self {
        GpuTimer {
            queries: device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("tile time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            }),
            resolved: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            }),
            readback: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("timestamps readback"),
                size: 16,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
        }
    }

    pub(super) fn writes(&self) -> wgpu::ComputePassTimestampWrites<'_> {
        wgpu::ComputePassTimestampWrites {
            query_set: &self.queries,
            beginning_of_pass_write_index: Some(0),
            end_of_pass_write_index: Some(1),
        }
    }

    pub(super) fn resolve(&self, encoder: &mut wgpu::CommandEncoder) {
        encoder.resolve_query_set(&self.queries, 0..2, &self.resolved, 0);
        encoder.copy_buffer_to_buffer(&self.resolved, 0, &self.readback, 0, 16);
    }

    pub(super) fn read_ms(&self, ctx: &GpuContext) -> Result<f64> {
        let bytes = ctx.read_buffer(&self.readback, 16)?;
        let ticks: &[u64] = bytemuck::cast_slice(&bytes);
        let ns = ticks[1].saturating_sub(ticks[0]) as f64 * ctx.queue.get_timestamp_period() as f64;
        Ok(ns * 1e-6)
    }
}

impl GpuContext {
    /// Waits until the GPU has run every submission (a dispatch's wall time
    /// where there are no timestamps; a check for device loss).
    pub(crate) fn wait_idle(&self) -> Result<()> {
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu(format!("waiting for the GPU failed: {e}")))?;
        self.check_health()
    }

    /// Maps `buffer` (after the last submission), copies out `size` bytes, unmaps.
    pub(crate) fn read_buffer(&self, buffer: &wgpu::Buffer, size: u64) -> Result<Vec<u8>> {
        let slice = buffer.slice(..size);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |r| {
            let _ = sender.send(r);
        });
        self.device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| Error::Gpu(format!("waiting for the GPU failed: {e}")))?;
        self.check_health()?;
        match receiver.recv() {
            Ok(Ok(())) => {}
            Ok(Err(e)) => return Err(Error::Gpu(format!("reading back from the GPU failed: {e}"))),
            Err(_) => return Err(Error::Gpu("the GPU never finished the readback".into())),
        }
        let bytes = slice
            .get_mapped_range()
            .map_err(|e| Error::Gpu(format!("reading back from the GPU failed: {e}")))?
            .to_vec();
        buffer.unmap();
        Ok(bytes)
    }
}
