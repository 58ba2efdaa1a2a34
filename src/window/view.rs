//! The window's GPU side: the progressive accumulation pass (the trace
//! kernel's `accumulate_tile` entry point), the present pass
//! (shaders/present.wgsl) and screenshots of what the present pass shows.

use crate::error::{Error, Result};
use crate::gpu::{bindings, shaders, GpuContext, KernelVariant, SceneBuffers, TracePipelines};
use crate::layout::FrameParams;

pub use crate::layout::PresentParams;

/// Bytes per pixel of the accumulation buffers (a vec4<f32>).
const ACCUMULATION_TEXEL: u64 = 16;

/// The two accumulation buffers: the image refined while the camera is
/// still, and the reduced-resolution preview traced while it moves (which
/// the present pass shows where the image has no sample yet).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Target {
    Image,
    Preview,
}

/// What one frame does on the GPU, in order.
#[derive(Debug, Clone, Copy)]
pub struct FrameWork {
    /// The buffer that the clear and the pass write.
    pub target: Target,
    /// Zero its first `n` pixels first.
    pub clear_pixels: Option<u64>,
    /// One accumulation pass over (a band of) the image these parameters
    /// describe.
    pub pass: Option<FrameParams>,
    pub present: PresentParams,
}

/// The layouts and uniforms that bind groups are made from.
struct Layouts {
    trace: wgpu::BindGroupLayout,
    present: wgpu::BindGroupLayout,
    params: wgpu::Buffer,
    present_params: wgpu::Buffer,
}

/// Bytes per pixel of the cost buffers (`bindings::PIXEL_COSTS`).
const COST_TEXEL: u64 = bindings::COST_WORDS as u64 * 4;

/// Buffers and bind groups that depend on the image size and the scene.
struct Bindings {
    image: wgpu::Buffer,
    preview: wgpu::Buffer,
    /// Each pixel's walk cost, summed over passes like the colour.
    image_costs: wgpu::Buffer,
    preview_costs: wgpu::Buffer,
    /// The heatmap's texels (`heatmap_view`), shown instead of the image
    /// and the preview while the heatmap is on.
    heat_image: wgpu::Buffer,
    heat_preview: wgpu::Buffer,
    heat_present_group: wgpu::BindGroup,
    /// Pixels each buffer holds.
    capacity: u64,
    image_group: wgpu::BindGroup,
    preview_group: wgpu::BindGroup,
    present_group: wgpu::BindGroup,
}

impl Layouts {
    fn trace_group(
        &self,
        device: &wgpu::Device,
        scene: &SceneBuffers,
        target: &wgpu::Buffer,
        costs: &wgpu::Buffer,
    ) -> wgpu::BindGroup {
        let mut entries = vec![wgpu::BindGroupEntry {
            binding: bindings::PARAMS.index,
            resource: self.params.as_entire_binding(),
        }];
        entries.extend(scene.bind_entries());
        entries.push(wgpu::BindGroupEntry {
            binding: bindings::ACCUMULATION.index,
            resource: target.as_entire_binding(),
        });
        entries.push(wgpu::BindGroupEntry {
            binding: bindings::PIXEL_COSTS.index,
            resource: costs.as_entire_binding(),
        });
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("accumulate"),
            layout: &self.trace,
            entries: &entries,
        })
    }

    fn bindings(&self, device: &wgpu::Device, scene: &SceneBuffers, pixels: u64) -> Bindings {
        let pixels = pixels.max(1);
        let buffer = |label, texel| {
            device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: pixels * texel,
                usage: wgpu::BufferUsages::STORAGE
                    | wgpu::BufferUsages::COPY_DST
                    | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            })
        };
        let image = buffer("accumulation", ACCUMULATION_TEXEL);
        let preview = buffer("preview", ACCUMULATION_TEXEL);
        let image_costs = buffer("accumulation costs", COST_TEXEL);
        let preview_costs = buffer("preview costs", COST_TEXEL);
        let heat_image = buffer("heatmap", ACCUMULATION_TEXEL);
        let heat_preview = buffer("preview heatmap", ACCUMULATION_TEXEL);
        let present_group = |label, image: &wgpu::Buffer, preview: &wgpu::Buffer| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &self.present,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: self.present_params.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: image.as_entire_binding(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: preview.as_entire_binding(),
                    },
                ],
            })
        };
        Bindings {
            image_group: self.trace_group(device, scene, &image, &image_costs),
            preview_group: self.trace_group(device, scene, &preview, &preview_costs),
            present_group: present_group("present", &image, &preview),
            heat_present_group: present_group("present heatmap", &heat_image, &heat_preview),
            image,
            preview,
            image_costs,
            preview_costs,
            heat_image,
            heat_preview,
            capacity: pixels,
        }
    }
}

pub struct Viewer {
    /// `accumulate_tile`, one pipeline per kernel variant.
    accumulate: TracePipelines,
    /// The kernel variant of the scene shown, its walk left to each frame.
    scene_variant: KernelVariant,
    present_pipeline_layout: wgpu::PipelineLayout,
    present_module: wgpu::ShaderModule,
    present: wgpu::RenderPipeline,
    /// The format `present` draws to (the surface's view format).
    target_format: wgpu::TextureFormat,
    layouts: Layouts,
    bindings: Bindings,
    /// While the cost heatmap is shown: its scale's top (work per sample).
    heatmap: Option<u32>,
}

fn storage(
    binding: u32,
    read_only: bool,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn uniform(binding: u32, visibility: wgpu::ShaderStages) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Uniform,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

fn present_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    module: &wgpu::ShaderModule,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("present"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some(shaders::PRESENT_VERTEX_ENTRY_POINT),
            compilation_options: Default::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(shaders::PRESENT_FRAGMENT_ENTRY_POINT),
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

impl Viewer {
    /// Pipelines and buffers for a target of `target_format` and images of
    /// up to `pixels` pixels, showing `scene`.
    pub fn new(
        ctx: &GpuContext,
        scene: &SceneBuffers,
        target_format: wgpu::TextureFormat,
        pixels: u64,
    ) -> Result<Self> {
        ctx.checked("creating the window's pipelines", |device| {
            let module = shaders::trace_module(device);
            let trace = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(shaders::ACCUMULATE_ENTRY_POINT),
                entries: &bindings::layout_entries(&bindings::entry_point_bindings(
                    bindings::scene_chunks(&device.limits()),
                    &bindings::ACCUMULATE_OUTPUTS,
                )),
            });
            let fragment = wgpu::ShaderStages::FRAGMENT;
            let present = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("present"),
                entries: &[
                    uniform(0, fragment),
                    storage(1, true, fragment),
                    storage(2, true, fragment),
                ],
            });
            let present_pipeline_layout =
                device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                    label: Some("present"),
                    bind_group_layouts: &[Some(&present)],
                    immediate_size: 0,
                });
            let present_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some("present"),
                source: wgpu::ShaderSource::Wgsl(shaders::PRESENT_SOURCE.into()),
            });
            let uniform_buffer = |label, size| {
                device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(label),
                    size,
                    usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                })
            };
            let layouts = Layouts {
                trace,
                present,
                params: uniform_buffer(
                    "window frame params",
                    std::mem::size_of::<FrameParams>() as u64,
                ),
                present_params: uniform_buffer(
                    "present params",
                    std::mem::size_of::<PresentParams>() as u64,
                ),
            };
            Viewer {
                accumulate: TracePipelines::new(
                    module,
                    layouts.trace.clone(),
                    shaders::ACCUMULATE_ENTRY_POINT,
                ),
                scene_variant: KernelVariant::for_scene(scene),
                present: present_pipeline(
                    device,
                    &present_pipeline_layout,
                    &present_module,
                    target_format,
                ),
                present_pipeline_layout,
                present_module,
                target_format,
                bindings: layouts.bindings(device, scene, pixels),
                layouts,
                heatmap: None,
            }
        })
    }

    /// Traces `scene` from now on.
    pub fn set_scene(&mut self, ctx: &GpuContext, scene: &SceneBuffers) -> Result<()> {
        self.scene_variant = KernelVariant::for_scene(scene);
        let b = &self.bindings;
        let (image_group, preview_group) = ctx.checked("binding the scene", |device| {
            (
                self.layouts
                    .trace_group(device, scene, &b.image, &b.image_costs),
                self.layouts
                    .trace_group(device, scene, &b.preview, &b.preview_costs),
            )
        })?;
        self.bindings.image_group = image_group;
        self.bindings.preview_group = preview_group;
        Ok(())
    }

    /// Makes room for images of `pixels` pixels (the contents are lost if
    /// the buffers grow).
    pub fn reserve(&mut self, ctx: &GpuContext, scene: &SceneBuffers, pixels: u64) -> Result<()> {
        if pixels <= self.bindings.capacity {
            return Ok(());
        }
        self.bindings = ctx.checked("allocating the accumulation buffers", |device| {
            self.layouts.bindings(device, scene, pixels)
        })?;
        Ok(())
    }

    /// Largest image an accumulation buffer may hold on this device.
    pub fn max_pixels(ctx: &GpuContext) -> u64 {
        // The accumulation texel is the largest of the buffers' texels.
        crate::gpu::max_binding_bytes(&ctx.device.limits()) / ACCUMULATION_TEXEL
    }

    /// Runs `work` and draws to `target`: with `heatmap`, the cost heatmap
    /// (the pass's costs read back and turned into texels before the
    /// present pass), else the image.
    pub fn frame(
        &mut self,
        ctx: &GpuContext,
        target: &wgpu::TextureView,
        work: &FrameWork,
        heatmap: bool,
    ) -> Result<()> {
        let mut encoder = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        if heatmap {
            self.encode_trace(ctx, &mut encoder, work)?;
            ctx.queue.submit([encoder.finish()]);
            self.heatmap = Some(self.update_heatmap(ctx, &work.present)?);
            encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("present heatmap"),
                });
        } else {
            self.heatmap = None;
            self.encode_trace(ctx, &mut encoder, work)?;
        }
        ctx.queue.write_buffer(
            &self.layouts.present_params,
            0,
            bytemuck::bytes_of(&work.present),
        );
        self.draw(&mut encoder, &self.present, target);
        ctx.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// The heatmap's scale while it is shown.
    pub fn heatmap_scale(&self) -> Option<u32> {
        self.heatmap
    }

    /// Reads back the colours and costs of the image and the preview that
    /// `present` shows, and writes their heatmap texels; returns the
    /// scale's top (the image's, or the preview's when only it is shown).
    fn update_heatmap(&self, ctx: &GpuContext, present: &PresentParams) -> Result<u32> {
        let b = &self.bindings;
        let pixels = |size: [u32; 2]| (size[0] as u64 * size[1] as u64).min(b.capacity);
        let sources = [
            (
                &b.image,
                &b.image_costs,
                &b.heat_image,
                pixels(present.image_size) * present.show_image.min(1) as u64,
            ),
            (
                &b.preview,
                &b.preview_costs,
                &b.heat_preview,
                pixels(present.preview_size),
            ),
        ];
        let mut scale = None;
        for (colours, costs, heat, n) in sources {
            if n == 0 {
                continue;
            }
            let (colour_bytes, cost_bytes) = (n * ACCUMULATION_TEXEL, n * COST_TEXEL);
            let readback = ctx.checked("reading back the heatmap's costs", |device| {
                let readback = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("heatmap readback"),
                    size: colour_bytes + cost_bytes,
                    usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let mut encoder = device.create_command_encoder(&Default::default());
                encoder.copy_buffer_to_buffer(colours, 0, &readback, 0, colour_bytes);
                encoder.copy_buffer_to_buffer(costs, 0, &readback, colour_bytes, cost_bytes);
                ctx.queue.submit([encoder.finish()]);
                readback
            })?;
            let bytes = ctx.read_buffer(&readback, colour_bytes + cost_bytes)?;
            let (colour_bytes, cost_bytes) = bytes.split_at(colour_bytes as usize);
            let (texels, max) = super::heatmap_view::heatmap_texels(
                bytemuck::cast_slice(cost_bytes),
                bytemuck::cast_slice(colour_bytes),
            );
            ctx.queue
                .write_buffer(heat, 0, bytemuck::cast_slice(&texels));
            scale.get_or_insert(max);
        }
        Ok(scale.unwrap_or(1))
    }

    /// Records `work`'s clear and pass into `encoder`. The uniforms are
    /// written now; submit before the next call. The pass's pipeline is the
    /// scene's variant with the pass's walk, made the first time it is
    /// needed (a new scene, or a walk chosen by key).
    fn encode_trace(
        &self,
        ctx: &GpuContext,
        encoder: &mut wgpu::CommandEncoder,
        work: &FrameWork,
    ) -> Result<()> {
        let b = &self.bindings;
        let (buffer, costs, group) = match work.target {
            Target::Image => (&b.image, &b.image_costs, &b.image_group),
            Target::Preview => (&b.preview, &b.preview_costs, &b.preview_group),
        };
        if let Some(pixels) = work.clear_pixels {
            let pixels = pixels.clamp(1, b.capacity);
            encoder.clear_buffer(buffer, 0, Some(pixels * ACCUMULATION_TEXEL));
            encoder.clear_buffer(costs, 0, Some(pixels * COST_TEXEL));
        }
        if let Some(params) = &work.pass {
            let pipeline = self
                .accumulate
                .get(ctx, self.scene_variant.with_walk_of(params))?;
            ctx.queue
                .write_buffer(&self.layouts.params, 0, bytemuck::bytes_of(params));
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("accumulate"),
                timestamp_writes: None,
            });
            pass.set_pipeline(&pipeline);
            pass.set_bind_group(0, group, &[]);
            let (gx, gy) = shaders::TRACE_WORKGROUP;
            pass.dispatch_workgroups(
                params.tile_size[0].div_ceil(gx),
                params.tile_size[1].div_ceil(gy),
                1,
            );
        }
        Ok(())
    }

    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        pipeline: &wgpu::RenderPipeline,
        target: &wgpu::TextureView,
    ) {
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("present"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: target,
                depth_slice: None,
                resolve_target: None,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: None,
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_pipeline(pipeline);
        let group = match self.heatmap {
            Some(_) => &self.bindings.heat_present_group,
            None => &self.bindings.present_group,
        };
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
    }

    /// Draws the present pass again, as the last frame showed it, into an
    /// offscreen texture of the target's size and reads it back as 8-bit
    /// RGB. The texture has the target's format when that is an 8-bit one
    /// (so the pixels are the window's), else Rgba8Unorm.
    pub fn capture(&self, ctx: &GpuContext, width: u32, height: u32) -> Result<Vec<u8>> {
        use wgpu::TextureFormat as F;
        let format = match self.target_format {
            f @ (F::Rgba8Unorm | F::Bgra8Unorm) => f,
            _ => F::Rgba8Unorm,
        };
        let row_bytes = width * 4;
        let padded_row = row_bytes.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let size = padded_row as u64 * height as u64;
        let readback = ctx.checked("capturing the window", |device| {
            let pipeline = (format != self.target_format).then(|| {
                present_pipeline(
                    device,
                    &self.present_pipeline_layout,
                    &self.present_module,
                    format,
                )
            });
            let texture = device.create_texture(&wgpu::TextureDescriptor {
                label: Some("screenshot"),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
                view_formats: &[],
            });
            let readback = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("screenshot readback"),
                size,
                usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let view = texture.create_view(&Default::default());
            let mut encoder = device.create_command_encoder(&Default::default());
            self.draw(
                &mut encoder,
                pipeline.as_ref().unwrap_or(&self.present),
                &view,
            );
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: &texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &readback,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(padded_row),
                        rows_per_image: Some(height),
                    },
                },
                wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
            );
            ctx.queue.submit([encoder.finish()]);
            readback
        })?;
        let bytes = ctx.read_buffer(&readback, size)?;
        let bgra = format == F::Bgra8Unorm;
        let mut rgb = Vec::with_capacity(width as usize * height as usize * 3);
        for row in bytes.chunks_exact(padded_row as usize) {
            for p in row[..row_bytes as usize].chunks_exact(4) {
                if bgra {
                    rgb.extend_from_slice(&[p[2], p[1], p[0]]);
                } else {
                    rgb.extend_from_slice(&p[..3]);
                }
            }
        }
        if rgb.len() != width as usize * height as usize * 3 {
            return Err(Error::Gpu("the screenshot readback came back short".into()));
        }
        Ok(rgb)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::{Accel, PreparedScene};

    /// The window's picture of `scene` after one pass (one sample a pixel).
    fn picture(
        ctx: &GpuContext,
        viewer: &mut Viewer,
        prepared: &PreparedScene,
        scene: &SceneBuffers,
    ) -> Vec<u8> {
        let (w, h) = (prepared.scene.render.width, prepared.scene.render.height);
        let mut params = prepared.frame_params(scene, Accel::Kdtree);
        params.samples_per_axis = 1;
        params.sample_index = 0;
        params.tile_origin = [0, 0];
        params.tile_size = [w, h];
        let work = FrameWork {
            target: Target::Image,
            clear_pixels: Some(w as u64 * h as u64),
            pass: Some(params),
            present: PresentParams {
                image_size: [w, h],
                target_size: [w, h],
                preview_size: [0, 0],
                show_image: 1,
                _pad: 0,
            },
        };
        let target = ctx.device.create_texture(&wgpu::TextureDescriptor {
            label: Some("test target"),
            size: wgpu::Extent3d {
                width: w,
                height: h,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Rgba8Unorm,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            view_formats: &[],
        });
        let view = target.create_view(&Default::default());
        viewer.frame(ctx, &view, &work, false).unwrap();
        viewer.capture(ctx, w, h).unwrap()
    }

    /// The window picks its trace pipeline by the scene's split, as the
    /// headless renderer does: a scene whose arrays lie in several bindings
    /// (forced by small chunks) shows the same picture as the same scene
    /// unsplit, whether the viewer starts with it or switches to it (a hot
    /// reload), and switching back restores the unsplit pipeline. Without
    /// the chunk selection the split scene's indices past the first chunk
    /// would read the wrong (bounds-checked) elements.
    #[test]
    fn the_window_traces_split_scenes_with_the_split_pipeline() {
        let ctx = GpuContext::new().unwrap();
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/torus.toml");
        let mut scene = crate::scene::load_scene(&path).unwrap();
        (scene.render.width, scene.render.height) = (96, 54);
        let prepared = PreparedScene::new(scene, Accel::Kdtree);
        let a = &prepared.arrays;
        // Two chunks of each split array (bindings::SPLIT_ARRAYS order).
        let half = |n: usize, size: u64| (n as u64 / 2 + 1) * size;
        let chunks = [
            half(a.triangles.len(), 48),
            half(a.nodes.len(), 8),
            half(a.leaf_objects.len(), 4),
            half(a.leaf_ropes.len(), 48),
            half(a.leaf_rope_index.len(), 4),
            half(a.triangle_normals.len(), 12),
        ];
        let whole = SceneBuffers::upload(&ctx, a).unwrap();
        let split = SceneBuffers::upload_split(&ctx, a, chunks).unwrap();
        assert!(split.split && !whole.split);
        let pixels = 96 * 54;
        let format = wgpu::TextureFormat::Rgba8Unorm;

        let mut viewer = Viewer::new(&ctx, &whole, format, pixels).unwrap();
        assert!(!viewer.scene_variant.split_scene);
        let expected = picture(&ctx, &mut viewer, &prepared, &whole);
        assert!(
            expected.chunks(3).any(|p| p != &expected[..3]),
            "the picture is blank"
        );
        viewer.set_scene(&ctx, &split).unwrap();
        assert!(viewer.scene_variant.split_scene);
        assert!(picture(&ctx, &mut viewer, &prepared, &split) == expected);
        let made = viewer.accumulate.variants();
        assert!(made.iter().any(|v| v.split_scene) && made.iter().any(|v| !v.split_scene));
        viewer.set_scene(&ctx, &whole).unwrap();
        assert!(!viewer.scene_variant.split_scene);
        assert!(picture(&ctx, &mut viewer, &prepared, &whole) == expected);

        let mut viewer = Viewer::new(&ctx, &split, format, pixels).unwrap();
        assert!(viewer.scene_variant.split_scene);
        assert!(picture(&ctx, &mut viewer, &prepared, &split) == expected);
        assert!(viewer.accumulate.variants().iter().all(|v| v.split_scene));
    }
}
