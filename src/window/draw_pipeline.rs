//! What the window's two render pipelines (the present pass and the line
//! overlay) share: a bind group layout made from a binding table of
//! `gpu::bindings`, a shader module, and a pipeline made for any colour
//! format, that of the window's surface or of a screenshot's texture.

use crate::gpu::bindings::{self, Binding};

/// A render pipeline's fixed parts, from which [`DrawPipeline::for_format`]
/// makes the pipeline for a target of any format.
pub struct DrawPipeline {
    label: &'static str,
    bind_layout: wgpu::BindGroupLayout,
    layout: wgpu::PipelineLayout,
    module: wgpu::ShaderModule,
    entry_points: (&'static str, &'static str),
    topology: wgpu::PrimitiveTopology,
    /// The vertex buffer's layout; None: the vertex shader makes its
    /// vertices from their index.
    vertices: Option<wgpu::VertexBufferLayout<'static>>,
}

/// What a [`DrawPipeline`] is made of, besides its shader module.
pub struct DrawPipelineDesc {
    pub label: &'static str,
    /// The binding table of its one bind group, and the stages that see it.
    pub table: &'static [Binding],
    pub stages: wgpu::ShaderStages,
    /// The module's (vertex, fragment) entry points.
    pub entry_points: (&'static str, &'static str),
    pub topology: wgpu::PrimitiveTopology,
    /// The vertex buffer's layout; None: the vertex shader makes its
    /// vertices from their index.
    pub vertices: Option<wgpu::VertexBufferLayout<'static>>,
}

impl DrawPipeline {
    /// The layouts `desc` describes, over `module`.
    pub fn new(device: &wgpu::Device, desc: DrawPipelineDesc, module: wgpu::ShaderModule) -> Self {
        let DrawPipelineDesc {
            label,
            table,
            stages,
            entry_points,
            topology,
            vertices,
        } = desc;
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &bindings::layout_entries(table, stages),
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&bind_layout)],
            immediate_size: 0,
        });
        DrawPipeline {
            label,
            bind_layout,
            layout,
            module,
            entry_points,
            topology,
            vertices,
        }
    }

    /// The layout of the pipeline's one bind group.
    pub fn bind_layout(&self) -> &wgpu::BindGroupLayout {
        &self.bind_layout
    }

    /// The pipeline drawing into a target of `format`, without blending
    /// (it replaces what it covers).
    pub fn for_format(
        &self,
        device: &wgpu::Device,
        format: wgpu::TextureFormat,
    ) -> wgpu::RenderPipeline {
        let buffers: Vec<Option<wgpu::VertexBufferLayout>> =
            self.vertices.iter().cloned().map(Some).collect();
        device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some(self.label),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &self.module,
                entry_point: Some(self.entry_points.0),
                compilation_options: Default::default(),
                buffers: &buffers,
            },
            primitive: wgpu::PrimitiveState {
                topology: self.topology,
                ..Default::default()
            },
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &self.module,
                entry_point: Some(self.entry_points.1),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        })
    }
}

/// A uniform buffer of `size` bytes that the queue writes.
pub fn uniform_buffer(device: &wgpu::Device, label: &'static str, size: usize) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size as u64,
        usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}
