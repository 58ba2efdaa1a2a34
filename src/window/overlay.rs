//! The window's line overlay on the GPU: a LineList render pipeline
//! (shaders/overlay.wgsl) that draws world-space segments
//! ([`LineVertex`], from `inspect_lines`) with the camera's projection
//! (`projection`) over the present pass, in the same render pass, without
//! a depth test (the lines lie on top of the image).

use bytemuck::{Pod, Zeroable};

use super::draw_pipeline::{uniform_buffer, DrawPipeline, DrawPipelineDesc};
use super::inspect_lines::LineVertex;
use crate::error::Result;
use crate::gpu::{bindings, shaders, GpuContext};

/// The overlay's uniform (shaders/overlay.wgsl's `OverlayParams`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct OverlayParams {
    /// World to clip space, column-major.
    pub view_projection: [[f32; 4]; 4],
}

/// The overlay's pipeline, uniform and lines.
pub struct Overlay {
    lines: DrawPipeline,
    /// For the format the present pass draws to.
    pipeline: wgpu::RenderPipeline,
    params: wgpu::Buffer,
    group: wgpu::BindGroup,
    /// The lines' vertices (two per line) and their number; None: nothing
    /// to draw.
    vertices: Option<(wgpu::Buffer, u32)>,
}

const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 2] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3];

impl Overlay {
    /// The overlay for a target of `format`, with no lines.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat) -> Self {
        let lines = DrawPipeline::new(
            device,
            DrawPipelineDesc {
                label: "overlay",
                table: &bindings::OVERLAY_BINDINGS,
                stages: wgpu::ShaderStages::VERTEX,
                entry_points: (
                    bindings::OVERLAY_VERTEX_ENTRY_POINT,
                    bindings::OVERLAY_FRAGMENT_ENTRY_POINT,
                ),
                topology: wgpu::PrimitiveTopology::LineList,
                vertices: Some(wgpu::VertexBufferLayout {
                    array_stride: std::mem::size_of::<LineVertex>() as u64,
                    step_mode: wgpu::VertexStepMode::Vertex,
                    attributes: &VERTEX_ATTRIBUTES,
                }),
            },
            shaders::overlay_module(device),
        );
        let params = uniform_buffer(
            device,
            "overlay params",
            std::mem::size_of::<OverlayParams>(),
        );
        let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("overlay"),
            layout: lines.bind_layout(),
            entries: &[wgpu::BindGroupEntry {
                binding: bindings::OVERLAY_PARAMS.index,
                resource: params.as_entire_binding(),
            }],
        });
        let pipeline = lines.for_format(device, format);
        Overlay {
            lines,
            pipeline,
            params,
            group,
            vertices: None,
        }
    }

    /// The pipeline for another target format (screenshots).
    pub fn pipeline_for(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> wgpu::RenderPipeline {
        self.lines.for_format(device, format)
    }

    pub fn pipeline(&self) -> &wgpu::RenderPipeline {
        &self.pipeline
    }

    /// Draws `vertices` (a LineList: two per line) from now on; none:
    /// nothing.
    pub fn set_lines(&mut self, ctx: &GpuContext, vertices: &[LineVertex]) -> Result<()> {
        if vertices.is_empty() {
            self.vertices = None;
            return Ok(());
        }
        let bytes: &[u8] = bytemuck::cast_slice(vertices);
        let buffer = ctx.checked("uploading the overlay's lines", |device| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("overlay lines"),
                size: bytes.len() as u64,
                usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            })
        })?;
        ctx.queue.write_buffer(&buffer, 0, bytes);
        self.vertices = Some((buffer, vertices.len() as u32));
        Ok(())
    }

    /// Draws nothing from now on.
    pub fn clear(&mut self) {
        self.vertices = None;
    }

    pub fn has_lines(&self) -> bool {
        self.vertices.is_some()
    }

    /// The projection the next draws use (world to clip space).
    pub fn set_view(&self, queue: &wgpu::Queue, view_projection: glam::Mat4) {
        let params = OverlayParams {
            view_projection: view_projection.to_cols_array_2d(),
        };
        queue.write_buffer(&self.params, 0, bytemuck::bytes_of(&params));
    }

    /// Draws the lines with `pipeline` (this overlay's, for the pass's
    /// format) into `pass`, after what it drew before.
    pub fn draw(&self, pass: &mut wgpu::RenderPass, pipeline: &wgpu::RenderPipeline) {
        let Some((buffer, count)) = &self.vertices else {
            return;
        };
        pass.set_pipeline(pipeline);
        pass.set_bind_group(0, &self.group, &[]);
        pass.set_vertex_buffer(0, buffer.slice(..));
        pass.draw(0..*count, 0..1);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shader's uniform and vertex input have the host's layout: naga's
    /// size of `OverlayParams` is the struct's, and `VertexIn` reads two
    /// vec3<f32> at the offsets [`VERTEX_ATTRIBUTES`] give, which tile
    /// [`LineVertex`].
    #[test]
    fn the_overlay_shader_reads_the_hosts_layout() {
        let (module, _) = shaders::parse_and_validate(&shaders::overlay_source());
        let size_of = |name: &str| {
            let (_, ty) = module
                .types
                .iter()
                .find(|(_, t)| t.name.as_deref() == Some(name))
                .unwrap_or_else(|| panic!("no struct {name}"));
            ty.inner.size(module.to_ctx())
        };
        assert_eq!(
            size_of("OverlayParams") as usize,
            std::mem::size_of::<OverlayParams>()
        );
        assert_eq!(std::mem::size_of::<LineVertex>(), 24);
        let offsets: Vec<u64> = VERTEX_ATTRIBUTES.iter().map(|a| a.offset).collect();
        assert_eq!(offsets, [0, 12]);
        assert_eq!(
            std::mem::offset_of!(LineVertex, colour),
            VERTEX_ATTRIBUTES[1].offset as usize
        );
    }
}
