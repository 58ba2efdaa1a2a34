//! The interactive window, `kdray render SCENE --window`: the scene traced by
//! the same compute shader as the headless path, refined progressively while
//! the camera is still, with mouse and keyboard controls and hot reload.
//!
//! - [`camera_controller`]: input events in, camera out (pure, unit-tested).
//! - `input`: winit events -> the controller's inputs and the window's
//!   own key actions.
//! - `refinement`: which image each frame traces: preview scale, bands,
//!   passes (pure, unit-tested).
//! - `click`: left clicks (not drags) and the image pixel under the cursor
//!   (pure, unit-tested).
//! - `frame_stats`: frame figures and the exit report (pure, unit-tested).
//! - `heatmap_view`: the cost heatmap's texels (pure, unit-tested).
//! - [`inspect_lines`]: an inspected pixel's rays, cells and split planes as
//!   world-space lines, and its counts (pure, unit-tested).
//! - [`projection`]: the camera's projection that draws them, the inverse of
//!   the kernel's camera rays (pure, unit-tested).
//! - `inspection`: inspection mode (X): a click inspects a pixel.
//! - `overlay`: the line pipeline that draws them over the image.
//! - `draw_pipeline`: what the present and overlay pipelines share: layouts
//!   from a binding table, and a pipeline for any target format.
//! - `denoise_schedule`: when the still image is denoised (pure,
//!   unit-tested).
//! - `denoise_budget`: how much of a denoise in progress a frame runs
//!   (pure, unit-tested).
//! - `denoising`: denoising (N): the feature pass beside the
//!   accumulation's, and the denoiser run on its sums a few units a frame.
//! - `title`: what the title bar says, and how often (pure, unit-tested).
//! - `playback`: which frame of the scene's animation is shown (pure,
//!   unit-tested).
//! - [`reload`]: loading the scene, and polling its file and the files it
//!   reads.
//! - `surface`: the window's surface: device, format, resizing, present.
//! - [`view`]: the present pass over the accumulation
//!   ([`crate::gpu::Accumulation`]), the heatmap and screenshots.
//! - `session`: the open window's state and what a frame does with it.
//! - `session_denoising`: the session's denoising (N): toggling it, its
//!   title, and each frame's share of it.
//! - `session_inspection`: the session's inspection mode (X): clicks,
//!   inspecting again, the overlay's projection.
//! - `app`: the winit event handler that ties them together.
//! - `test_scenes` (tests only): the unit tests' scenes, loaded at a size.

mod app;
pub mod camera_controller;
mod click;
mod denoise_budget;
mod denoise_schedule;
mod denoising;
mod draw_pipeline;
mod frame_stats;
mod heatmap_view;
mod input;
pub mod inspect_lines;
mod inspection;
mod overlay;
mod playback;
pub mod projection;
mod refinement;
pub mod reload;
mod session;
mod session_denoising;
mod session_inspection;
mod surface;
#[cfg(test)]
mod test_scenes;
mod title;
pub mod view;

use std::path::PathBuf;

use crate::error::{Error, Result};
use crate::render::RenderFlags;

/// Samples per pixel the window refines to when neither the scene nor
/// `--samples` asks for more.
pub const DEFAULT_WINDOW_SAMPLES: u32 = 16;
/// Path samples per pixel the window refines to when neither the scene nor
/// `--samples` asks for more.
pub const DEFAULT_WINDOW_PATH_SAMPLES: u32 = 256;

/// What `kdray render SCENE --window ...` asked for.
#[derive(Debug, Clone)]
pub struct WindowOptions {
    pub scene: PathBuf,
    /// As for a render, but: `width` and `height` are the window's size in
    /// physical pixels (default: the scene's aspect ratio, fitted into 960 x
    /// 720 logical pixels); `samples` the samples per pixel to refine to
    /// (default: the scene's, at least [`DEFAULT_WINDOW_SAMPLES`], or
    /// [`DEFAULT_WINDOW_PATH_SAMPLES`] path traced); the
    /// walk and build are those to start with (T and K cycle them).
    pub flags: RenderFlags,
    /// Present this many frames, then exit.
    pub frames: Option<u32>,
    /// On exit, save the last presented frame here.
    pub screenshot: Option<PathBuf>,
    /// On exit, print the frame figures as one JSON object on stdout.
    pub stats: bool,
    /// Start playing the scene's animation.
    pub play: bool,
    /// `--denoise[=BOOL]`: start with denoising on (or off) whatever the
    /// scene's `[render] denoise` says (N toggles it).
    pub denoise: Option<bool>,
}

impl WindowOptions {
    fn validate(&self) -> Result<()> {
        self.flags.check()?;
        if self.frames == Some(0) {
            return Err(Error::Usage("--frames: must be at least 1, got 0".into()));
        }
        Ok(())
    }
}

/// Opens the window and runs until it is closed (Esc, the close button,
/// Ctrl-C / SIGTERM, or `--frames`). A scene that does not load at start is
/// an error (exit code 2); later reload errors are only reported.
pub fn run(options: WindowOptions) -> Result<()> {
    options.validate()?;
    // Before the event loop and any other thread: Mesa's Vulkan layers read
    // it when the window's instance lists devices (gpu/context.rs).
    crate::gpu::context::give_mesa_a_runtime_dir();
    app::run(options)
}

/// Ctrl-C and SIGTERM ask the window to close (saving `--screenshot`)
/// instead of killing the process.
mod signals {
    use std::sync::atomic::{AtomicBool, Ordering};

    static QUIT: AtomicBool = AtomicBool::new(false);

    #[cfg(unix)]
    extern "C" fn on_signal(_: libc::c_int) {
        QUIT.store(true, Ordering::SeqCst);
    }

    pub fn install() {
        #[cfg(unix)]
        {
            let handler = on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t;
            // SAFETY: the handler only stores to an atomic, which is
            // async-signal-safe.
            unsafe {
                libc::signal(libc::SIGINT, handler);
                libc::signal(libc::SIGTERM, handler);
            }
        }
    }

    pub fn quit_requested() -> bool {
        QUIT.load(Ordering::SeqCst)
    }
}
