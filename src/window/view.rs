//! The window's GPU side, around the progressive accumulation
//! ([`crate::gpu::Accumulation`]): the present pass (shaders/present.wgsl)
//! that shows the image (or its denoised version) or the preview, the cost
//! heatmap shown instead of them, the line overlay drawn over them
//! (`overlay.rs`), and screenshots of what the two show.

use super::draw_pipeline::{uniform_buffer, DrawPipeline, DrawPipelineDesc};
use super::overlay::Overlay;
use crate::error::{Error, Result};
use crate::gpu::accumulate::ACCUMULATION_TEXEL;
use crate::gpu::FrameParams;
use crate::gpu::{bindings, shaders, Accumulation, GpuContext, SceneBuffers};

pub use crate::gpu::PresentParams;
pub use crate::gpu::Target;

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

/// What the present pass reads, for accumulation buffers of one size.
struct PresentGroups {
    /// The heatmap's texels (`heatmap_view`), shown instead of the image
    /// and the preview while the heatmap is on.
    heat_image: wgpu::Buffer,
    heat_preview: wgpu::Buffer,
    /// The image and the preview.
    colours: wgpu::BindGroup,
    heatmap: wgpu::BindGroup,
}

pub struct Viewer {
    accumulation: Accumulation,
    /// The present pass's layouts, for the surface's format and others.
    present_parts: DrawPipeline,
    present: wgpu::RenderPipeline,
    present_params: wgpu::Buffer,
    /// The format `present` draws to (the surface's view format).
    target_format: wgpu::TextureFormat,
    groups: PresentGroups,
    /// While the cost heatmap is shown: its scale's top (work per sample).
    heatmap: Option<u32>,
    /// Lines drawn over the image (an inspected pixel's rays and cells).
    overlay: Overlay,
    /// The denoised image, made at the first denoise, and whether it is
    /// shown instead of the image.
    denoised: Option<DenoisedImage>,
    show_denoised: bool,
}

/// A denoised image as the present pass reads an image: each pixel's
/// radiance with a sample count of 1, beside the preview.
struct DenoisedImage {
    colours: wgpu::Buffer,
    group: wgpu::BindGroup,
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
        let accumulation = Accumulation::new(ctx, scene, pixels)?;
        ctx.checked("creating the window's present pass", |device| {
            let present_parts = DrawPipeline::new(
                device,
                DrawPipelineDesc {
                    label: "present",
                    table: &bindings::PRESENT_BINDINGS,
                    stages: wgpu::ShaderStages::FRAGMENT,
                    entry_points: (
                        bindings::PRESENT_VERTEX_ENTRY_POINT,
                        bindings::PRESENT_FRAGMENT_ENTRY_POINT,
                    ),
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    vertices: None,
                },
                shaders::present_module(device),
            );
            let present_params = uniform_buffer(
                device,
                "present params",
                std::mem::size_of::<PresentParams>(),
            );
            let groups = present_groups(
                device,
                present_parts.bind_layout(),
                &present_params,
                &accumulation,
            );
            Viewer {
                present: present_parts.for_format(device, target_format),
                accumulation,
                present_parts,
                present_params,
                target_format,
                groups,
                heatmap: None,
                overlay: Overlay::new(device, target_format),
                denoised: None,
                show_denoised: false,
            }
        })
    }

    /// Traces `scene` from now on.
    pub fn set_scene(&mut self, ctx: &GpuContext, scene: &SceneBuffers) -> Result<()> {
        self.accumulation.set_scene(ctx, scene)
    }

    /// Makes room for images of `pixels` pixels (the contents are lost if
    /// the buffers grow).
    pub fn reserve(&mut self, ctx: &GpuContext, scene: &SceneBuffers, pixels: u64) -> Result<()> {
        if self.accumulation.reserve(ctx, scene, pixels)? {
            (self.denoised, self.show_denoised) = (None, false);
            self.groups = ctx.checked("allocating the heatmap buffers", |device| {
                present_groups(
                    device,
                    self.present_parts.bind_layout(),
                    &self.present_params,
                    &self.accumulation,
                )
            })?;
        }
        Ok(())
    }

    /// Largest image an accumulation buffer may hold on this device.
    pub fn max_pixels(ctx: &GpuContext) -> u64 {
        Accumulation::max_pixels(ctx)
    }

    /// Shows `rgb` (linear radiance, three floats a pixel, the image's
    /// pixels) instead of the image from the next present on, tone-mapped
    /// as the image is.
    pub fn show_denoised(&mut self, ctx: &GpuContext, rgb: &[f32]) -> Result<()> {
        let pixels = (rgb.len() / 3) as u64;
        if pixels > self.accumulation.capacity() {
            return Err(Error::Gpu(format!(
                "a denoised image of {pixels} pixels is bigger than the window's image"
            )));
        }
        if self.denoised.is_none() {
            let made = ctx.checked("allocating the denoised image", |device| {
                let colours = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some("denoised"),
                    size: self.accumulation.capacity() * ACCUMULATION_TEXEL,
                    usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
                    mapped_at_creation: false,
                });
                let group = present_group(
                    device,
                    self.present_parts.bind_layout(),
                    "present denoised",
                    [
                        &self.present_params,
                        &colours,
                        self.accumulation.colours(Target::Preview),
                    ],
                );
                DenoisedImage { colours, group }
            })?;
            self.denoised = Some(made);
        }
        let texels: Vec<[f32; 4]> = rgb
            .chunks_exact(3)
            .map(|c| [c[0], c[1], c[2], 1.0])
            .collect();
        if let Some(d) = &self.denoised {
            ctx.queue
                .write_buffer(&d.colours, 0, bytemuck::cast_slice(&texels));
        }
        self.show_denoised = true;
        Ok(())
    }

    /// Shows the image again, not the denoised one.
    pub fn hide_denoised(&mut self) {
        self.show_denoised = false;
    }

    /// Whether the denoised image is shown instead of the image.
    pub fn shows_denoised(&self) -> bool {
        self.show_denoised && self.denoised.is_some()
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
        self.accumulation.encode(
            ctx,
            &mut encoder,
            work.target,
            work.clear_pixels,
            work.pass.as_ref(),
        )?;
        if heatmap {
            ctx.queue.submit([encoder.finish()]);
            self.heatmap = Some(self.update_heatmap(ctx, &work.present)?);
            encoder = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                    label: Some("present heatmap"),
                });
        } else {
            self.heatmap = None;
        }
        // The heatmap's texels are levels already: quantised, not tone mapped.
        let present = match self.heatmap {
            Some(_) => PresentParams {
                tone_map: crate::gpu::PRESENT_QUANTISE,
                ..work.present
            },
            None => work.present,
        };
        ctx.queue
            .write_buffer(&self.present_params, 0, bytemuck::bytes_of(&present));
        self.draw(
            &mut encoder,
            (&self.present, self.overlay.pipeline()),
            target,
        );
        ctx.queue.submit([encoder.finish()]);
        Ok(())
    }

    /// The lines drawn over the image.
    pub fn overlay_mut(&mut self) -> &mut Overlay {
        &mut self.overlay
    }

    /// The heatmap's scale while it is shown.
    pub fn heatmap_scale(&self) -> Option<u32> {
        self.heatmap
    }

    /// Reads back the colours and costs of the image and the preview that
    /// `present` shows, and writes their heatmap texels; returns the
    /// scale's top (the image's, or the preview's when only it is shown).
    fn update_heatmap(&self, ctx: &GpuContext, present: &PresentParams) -> Result<u32> {
        let capacity = self.accumulation.capacity();
        let pixels = |size: [u32; 2]| (size[0] as u64 * size[1] as u64).min(capacity);
        let sources = [
            (
                Target::Image,
                &self.groups.heat_image,
                pixels(present.image_size) * present.show_image.min(1) as u64,
            ),
            (
                Target::Preview,
                &self.groups.heat_preview,
                pixels(present.preview_size),
            ),
        ];
        let mut scale = None;
        for (target, heat, n) in sources {
            if n == 0 {
                continue;
            }
            let (colours, costs) = self.accumulation.read_back(ctx, target, n)?;
            let (texels, max) = super::heatmap_view::heatmap_texels(&costs, &colours);
            ctx.queue
                .write_buffer(heat, 0, bytemuck::cast_slice(&texels));
            scale.get_or_insert(max);
        }
        Ok(scale.unwrap_or(1))
    }

    /// The present pass with `pipelines` (the present pass's and the
    /// overlay's, for `target`'s format): the image, then the lines.
    fn draw(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        (pipeline, lines): (&wgpu::RenderPipeline, &wgpu::RenderPipeline),
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
        let group = match (self.heatmap, &self.denoised) {
            (Some(_), _) => &self.groups.heatmap,
            (None, Some(d)) if self.show_denoised => &d.group,
            (None, _) => &self.groups.colours,
        };
        pass.set_bind_group(0, group, &[]);
        pass.draw(0..3, 0..1);
        self.overlay.draw(&mut pass, lines);
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
            let pipelines = (format != self.target_format).then(|| {
                (
                    self.present_parts.for_format(device, format),
                    self.overlay.pipeline_for(device, format),
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
            let pipelines = match &pipelines {
                Some((present, lines)) => (present, lines),
                None => (&self.present, self.overlay.pipeline()),
            };
            self.draw(&mut encoder, pipelines, &view);
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

/// The present pass's bind groups over `accumulation`'s buffers, and the
/// heatmap's texel buffers of the same size with theirs.
fn present_groups(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    params: &wgpu::Buffer,
    accumulation: &Accumulation,
) -> PresentGroups {
    let heat = |label| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: accumulation.capacity() * ACCUMULATION_TEXEL,
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        })
    };
    let group = |label: &str, image: &wgpu::Buffer, preview: &wgpu::Buffer| {
        present_group(device, layout, label, [params, image, preview])
    };
    let (heat_image, heat_preview) = (heat("heatmap"), heat("preview heatmap"));
    PresentGroups {
        colours: group(
            "present",
            accumulation.colours(Target::Image),
            accumulation.colours(Target::Preview),
        ),
        heatmap: group("present heatmap", &heat_image, &heat_preview),
        heat_image,
        heat_preview,
    }
}

/// A bind group of the present pass over `buffers`: PRESENT_BINDINGS'
/// parameters, image and preview.
fn present_group(
    device: &wgpu::Device,
    layout: &wgpu::BindGroupLayout,
    label: &str,
    buffers: [&wgpu::Buffer; 3],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry> = bindings::PRESENT_BINDINGS
        .iter()
        .zip(buffers)
        .map(|(b, buffer)| wgpu::BindGroupEntry {
            binding: b.index,
            resource: buffer.as_entire_binding(),
        })
        .collect();
    device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
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
        let mut params = FrameParams::for_prepared(prepared, scene);
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
                tone_map: crate::gpu::PRESENT_QUANTISE,
                exposure_scale: 1.0,
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
        assert!(!viewer.accumulation.scene_variant().split_scene);
        let expected = picture(&ctx, &mut viewer, &prepared, &whole);
        assert!(
            expected.chunks(3).any(|p| p != &expected[..3]),
            "the picture is blank"
        );
        viewer.set_scene(&ctx, &split).unwrap();
        assert!(viewer.accumulation.scene_variant().split_scene);
        assert!(picture(&ctx, &mut viewer, &prepared, &split) == expected);
        let made = viewer.accumulation.variants();
        assert!(made.iter().any(|v| v.split_scene) && made.iter().any(|v| !v.split_scene));
        viewer.set_scene(&ctx, &whole).unwrap();
        assert!(!viewer.accumulation.scene_variant().split_scene);
        assert!(picture(&ctx, &mut viewer, &prepared, &whole) == expected);

        // A viewer that starts with the split scene traces it with the split
        // pipeline (the context's pipelines hold the first viewer's too).
        let mut viewer = Viewer::new(&ctx, &split, format, pixels).unwrap();
        assert!(viewer.accumulation.scene_variant().split_scene);
        assert!(picture(&ctx, &mut viewer, &prepared, &split) == expected);
        assert!(viewer.accumulation.variants().iter().any(|v| v.split_scene));
    }
}
