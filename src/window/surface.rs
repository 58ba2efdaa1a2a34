//! The window's surface: the device that can draw to it, its format and
//! configuration, resizing, whether it can be drawn to now, and taking and
//! presenting its images.

use std::sync::Arc;
use std::time::{Duration, Instant};

use winit::dpi::PhysicalSize;
use winit::event_loop::OwnedDisplayHandle;
use winit::window::Window;

use crate::error::{Error, Result};
use crate::gpu::GpuContext;

/// How often the window manager is asked whether the window is minimised.
const STATE_CHECK_INTERVAL: Duration = Duration::from_millis(100);
/// How long to wait after the surface said the window cannot be seen.
const OCCLUDED_RETRY: Duration = Duration::from_millis(250);

/// The surface, configured to the window's size.
pub struct WindowSurface {
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The format the present pass writes (never sRGB).
    view_format: wgpu::TextureFormat,
    /// A zero-size window.
    minimized: bool,
    /// The window system says the window cannot be seen.
    occluded: bool,
    /// The surface said so: no frames before this.
    retry_at: Option<Instant>,
    /// The window manager says the window is minimised (checked every
    /// [`STATE_CHECK_INTERVAL`]).
    wm_minimized: bool,
    next_state_check: Instant,
}

/// The surface's image for one frame.
pub struct SurfaceFrame {
    texture: wgpu::SurfaceTexture,
    /// The view the present pass draws to.
    pub view: wgpu::TextureView,
    /// Presentable, but the surface should be configured again after.
    suboptimal: bool,
}

/// What asking the surface for an image gave.
pub enum Acquired {
    Frame(SurfaceFrame),
    /// No image this time (a timeout, or the window cannot be seen).
    Skipped,
    /// The surface no longer fits the window: resize to the window's size,
    /// then [`WindowSurface::reconfigure`].
    Outdated,
}

/// A device for the window: native APIs first, GL (with the window's
/// display, which EGL needs to present) only if none of them can.
fn open_gpu(
    display: &OwnedDisplayHandle,
    window: &Arc<Window>,
) -> Result<(wgpu::Surface<'static>, GpuContext)> {
    let env = wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(display.clone()));
    let native = wgpu::Backends::VULKAN | wgpu::Backends::METAL | wgpu::Backends::DX12;
    let mut last = None;
    for backends in [env.backends & native, env.backends & wgpu::Backends::GL] {
        if backends.is_empty() {
            continue;
        }
        let instance = wgpu::Instance::new(wgpu::InstanceDescriptor {
            backends,
            ..wgpu::InstanceDescriptor::new_with_display_handle_from_env(Box::new(display.clone()))
        });
        let surface = match instance.create_surface(window.clone()) {
            Ok(s) => s,
            Err(e) => {
                last = Some(Error::Gpu(format!("cannot draw to the window: {e}")));
                continue;
            }
        };
        match GpuContext::for_surface(&instance, &surface) {
            Ok(ctx) => return Ok((surface, ctx)),
            Err(e) => last = Some(e),
        }
    }
    Err(last.unwrap_or_else(|| Error::Gpu(crate::gpu::context::NO_ADAPTER_HELP.to_string())))
}

impl WindowSurface {
    /// Opens a device for `window` and configures its surface to the
    /// window's size.
    pub fn open(display: &OwnedDisplayHandle, window: &Arc<Window>) -> Result<(Self, GpuContext)> {
        let (surface, ctx) = open_gpu(display, window)?;
        let caps = surface.get_capabilities(&ctx.adapter);
        // A non-sRGB format, so the present pass's values reach the screen
        // as the PNG's bytes; failing that an sRGB one viewed as Unorm.
        let format = caps
            .formats
            .iter()
            .copied()
            .find(|f| {
                matches!(
                    f,
                    wgpu::TextureFormat::Bgra8Unorm | wgpu::TextureFormat::Rgba8Unorm
                )
            })
            .or_else(|| caps.formats.iter().copied().find(|f| !f.is_srgb()))
            .or_else(|| caps.formats.first().copied())
            .ok_or_else(|| {
                Error::Gpu(format!("{} cannot draw to this window", ctx.adapter_line()))
            })?;
        let view_format = format.remove_srgb_suffix();
        let size = window.inner_size();
        let config = wgpu::SurfaceConfiguration {
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
            format,
            color_space: Default::default(),
            width: size.width.max(1),
            height: size.height.max(1),
            present_mode: wgpu::PresentMode::AutoVsync,
            desired_maximum_frame_latency: 2,
            alpha_mode: wgpu::CompositeAlphaMode::Auto,
            view_formats: if view_format == format {
                vec![]
            } else {
                vec![view_format]
            },
        };
        ctx.checked("configuring the window's surface", |device| {
            surface.configure(device, &config)
        })?;
        let surface = WindowSurface {
            surface,
            config,
            view_format,
            minimized: size.width == 0 || size.height == 0,
            occluded: false,
            retry_at: None,
            wm_minimized: false,
            next_state_check: Instant::now(),
        };
        Ok((surface, ctx))
    }

    /// The surface's size in physical pixels (the window's, unless it is
    /// minimised).
    pub fn size(&self) -> (u32, u32) {
        (self.config.width, self.config.height)
    }

    /// The format the present pass writes.
    pub fn view_format(&self) -> wgpu::TextureFormat {
        self.view_format
    }

    pub fn is_minimized(&self) -> bool {
        self.minimized
    }

    /// The window is now `size`; true if the surface changed size (a
    /// minimised, zero-size window keeps the last size).
    pub fn resize(&mut self, ctx: &GpuContext, size: PhysicalSize<u32>) -> bool {
        self.minimized = size.width == 0 || size.height == 0;
        if self.minimized || (size.width, size.height) == self.size() {
            return false;
        }
        self.config.width = size.width;
        self.config.height = size.height;
        self.surface.configure(&ctx.device, &self.config);
        true
    }

    /// Configures the surface again at its size, unless minimised.
    pub fn reconfigure(&self, ctx: &GpuContext) {
        if !self.minimized {
            self.surface.configure(&ctx.device, &self.config);
        }
    }

    pub fn set_occluded(&mut self, occluded: bool) {
        self.occluded = occluded;
    }

    /// Whether a frame could be shown at `now`: not minimised, not hidden,
    /// not waiting after the surface said it cannot be seen.
    pub fn can_draw(&mut self, now: Instant, window: &Window) -> bool {
        if now >= self.next_state_check {
            // A round trip to the window system: not every frame.
            self.next_state_check = now + STATE_CHECK_INTERVAL;
            self.wm_minimized = window.is_minimized() == Some(true);
        }
        !(self.minimized
            || self.wm_minimized
            || self.occluded
            || self.retry_at.is_some_and(|t| now < t))
    }

    /// The surface's next image, at `now`.
    pub fn acquire(&mut self, ctx: &GpuContext, now: Instant) -> Result<Acquired> {
        let (texture, suboptimal) = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => (t, false),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => (t, true),
            wgpu::CurrentSurfaceTexture::Timeout => return Ok(Acquired::Skipped),
            wgpu::CurrentSurfaceTexture::Occluded => {
                self.retry_at = Some(now + OCCLUDED_RETRY);
                return Ok(Acquired::Skipped);
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                return Ok(Acquired::Outdated)
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                ctx.check_health()?;
                return Err(Error::Gpu("the window's surface failed validation".into()));
            }
        };
        let view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        Ok(Acquired::Frame(SurfaceFrame {
            texture,
            view,
            suboptimal,
        }))
    }

    /// Shows `frame` (its work submitted) in `window`.
    pub fn present(&self, ctx: &GpuContext, window: &Window, frame: SurfaceFrame) {
        window.pre_present_notify();
        ctx.queue.present(frame.texture);
        if frame.suboptimal {
            self.surface.configure(&ctx.device, &self.config);
        }
    }
}
