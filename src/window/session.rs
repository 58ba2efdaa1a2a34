//! The open window's state: its surface and device, the uploaded scene, the
//! camera controls, refinement, playback, inspection mode, statistics and
//! title, and what a frame does with them. `app.rs` feeds it winit's events.
//! Each frame is one submission and one present: [`Refinement`] plans it,
//! `pass_params` turns its pass over the [`GpuScene`] into the shader's
//! parameters, [`Viewer`] records it, [`WindowSurface`] shows it and
//! [`FrameStats`] counts it. The session's denoising (N) is in
//! `session_denoising.rs`, its inspection mode (X) in
//! `session_inspection.rs`.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use winit::dpi::{LogicalSize, PhysicalSize, Size};
use winit::event_loop::{ActiveEventLoop, OwnedDisplayHandle};
use winit::window::Window;

use super::camera_controller::{Bounds, CameraController};
use super::click::ClickTracker;
use super::denoising::Denoising;
use super::frame_stats::{FrameStats, ReportContext};
use super::inspection::InspectMode;
use super::playback::Playback;
use super::refinement::{FrameKind, FramePlan, Pass, Refinement, Samples};
use super::surface::{Acquired, WindowSurface};
use super::title::{Progress, TitleBar, TitleFacts};
use super::view::{FrameWork, PresentParams, Target, Viewer};
use super::{WindowOptions, DEFAULT_WINDOW_PATH_SAMPLES, DEFAULT_WINDOW_SAMPLES};
use crate::error::{Error, Result};
use crate::gpu::FrameParams;
use crate::gpu::{Accel, GpuContext, GpuScene, PreparedScene};
use crate::kdtree::Traversal;
use crate::scene::{Camera, FramePath, Integrator, RenderSettings, Scene};

/// The largest window opened for a scene's own size, in logical pixels.
const DEFAULT_WINDOW: (f64, f64) = (960.0, 720.0);

/// Everything that exists once the window is open.
pub(super) struct Session {
    pub(super) window: Arc<Window>,
    pub(super) surface: WindowSurface,
    /// Leaked: the denoiser borrows it, and the window's one session
    /// holds it until the process exits.
    pub(super) ctx: &'static GpuContext,
    pub(super) viewer: Viewer,
    /// The last good scene.
    pub(super) scene: GpuScene,
    /// `render.max_depth` as the file said it (a reload that changes it wins
    /// over [ and ]).
    pub(super) file_max_depth: u32,
    pub(super) controller: CameraController,
    pub(super) accel: Accel,
    /// The k-d walk (T cycles them).
    pub(super) traversal: Traversal,
    /// Show the cost heatmap instead of the image (C toggles it).
    pub(super) heatmap: bool,
    /// The integrator traced: the scene's (after --integrator) until I
    /// toggles it.
    pub(super) integrator: Integrator,
    pub(super) max_depth: u32,
    pub(super) refinement: Refinement,
    /// The scene's animation: the frame shown, played by Space.
    pub(super) playback: Playback,
    /// The scene's camera and lights at every frame of its animation.
    pub(super) path: FramePath,
    /// When the camera's fly keys were last applied.
    pub(super) last_update: Instant,
    pub(super) stats: FrameStats,
    pub(super) title: TitleBar,
    /// Inspection mode (X) and the pixel it shows.
    pub(super) inspect: InspectMode,
    /// The inspect kernel, made at the first inspection.
    pub(super) recorder: Option<crate::gpu::WalkRecorder>,
    /// Left clicks (not drags), for inspection mode.
    pub(super) clicks: ClickTracker,
    /// Denoising (N): the feature pass, the denoiser and its schedule.
    pub(super) denoising: Denoising,
    /// The last frame ran units of a denoise.
    pub(super) denoised_last_frame: bool,
}

/// Window size: --width/--height in physical pixels; one of them alone keeps
/// the scene's aspect ratio; neither fits the scene into [`DEFAULT_WINDOW`].
fn window_size(options: &WindowOptions, scene: &Scene) -> Size {
    let (sw, sh) = (scene.render.width as f64, scene.render.height as f64);
    let side = |v: f64| (v.round() as u32).clamp(1, crate::scene::MAX_IMAGE_SIDE);
    match (options.flags.width, options.flags.height) {
        (Some(w), Some(h)) => PhysicalSize::new(w, h).into(),
        (Some(w), None) => PhysicalSize::new(w, side(w as f64 * sh / sw)).into(),
        (None, Some(h)) => PhysicalSize::new(side(h as f64 * sw / sh), h).into(),
        (None, None) => {
            let scale = (DEFAULT_WINDOW.0 / sw).min(DEFAULT_WINDOW.1 / sh).min(1.0);
            LogicalSize::new((sw * scale).round().max(1.0), (sh * scale).round().max(1.0)).into()
        }
    }
}

/// The samples per pixel the window refines to: --samples, else the
/// scene's, at least [`DEFAULT_WINDOW_SAMPLES`] (Whitted frames: the k x k
/// grid of that count) or [`DEFAULT_WINDOW_PATH_SAMPLES`] (path-traced
/// frames, sample n as `kdray render` traces it).
fn window_samples(options: &WindowOptions, scene: &Scene, integrator: Integrator) -> Samples {
    if integrator == Integrator::Path {
        return Samples::Random {
            count: options
                .flags
                .samples
                .unwrap_or_else(|| scene.render.samples.max(DEFAULT_WINDOW_PATH_SAMPLES)),
        };
    }
    let samples = options
        .flags
        .samples
        .unwrap_or_else(|| scene.render.samples.max(DEFAULT_WINDOW_SAMPLES));
    let per_axis = RenderSettings {
        samples,
        ..scene.render
    }
    .samples_per_axis();
    Samples::Grid { per_axis }
}

/// The frame rate the window plays `scene`'s animation at.
fn animation_fps(scene: &Scene) -> f64 {
    scene.animation.as_ref().map_or(24.0, |a| a.fps)
}

/// The scene's box, for the camera controls.
fn bounds(scene: &GpuScene) -> Bounds {
    let b = scene.bounds();
    Bounds {
        min: b.min.as_dvec3(),
        max: b.max.as_dvec3(),
    }
}

/// The kernel's parameters for `pass` of `scene` seen from `camera` in a
/// `w` x `h` window.
#[allow(clippy::too_many_arguments)]
fn pass_params(
    scene: &GpuScene,
    camera: &Camera,
    max_depth: u32,
    accel: Accel,
    integrator: Integrator,
    pass: &Pass,
    (w, h): (u32, u32),
) -> FrameParams {
    let (iw, ih) = pass.image;
    let render = RenderSettings {
        width: iw,
        height: ih,
        max_depth,
        integrator,
        ..scene.scene().render
    };
    let mut p = scene.view_params(camera, &render, accel);
    p.aspect = (w as f64 / h as f64) as f32;
    p.samples_per_axis = pass.samples_per_axis;
    p.sample_index = pass.sample_index;
    p.tile_origin = [0, pass.first_row];
    p.tile_size = [iw, pass.rows];
    p
}

/// `<scene stem>-NNN.png` in the current folder, the first that does not exist.
pub(super) fn next_screenshot_path(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "kdray".into(), |s| s.to_string_lossy().into_owned());
    (1..u32::MAX)
        .map(|n| PathBuf::from(format!("{stem}-{n:03}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| PathBuf::from(format!("{stem}-latest.png")))
}

impl Session {
    pub(super) fn open(
        event_loop: &ActiveEventLoop,
        display: &OwnedDisplayHandle,
        prepared: PreparedScene,
        options: &WindowOptions,
        name: &str,
    ) -> Result<Self> {
        let attributes = Window::default_attributes()
            .with_title(format!("{name} - kdray"))
            .with_inner_size(window_size(options, &prepared.scene));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Gpu(format!("cannot open a window: {e}")))?,
        );
        let (surface, ctx) = WindowSurface::open(display, &window)?;
        let ctx: &'static GpuContext = Box::leak(Box::new(ctx));
        let denoise = options.denoise.unwrap_or(prepared.scene.render.denoise);
        let scene = GpuScene::upload(ctx, prepared)?;
        let max_pixels = Viewer::max_pixels(ctx);
        let (width, height) = surface.size();
        let pixels = (width as u64 * height as u64).min(max_pixels);
        let viewer = Viewer::new(ctx, scene.buffers(), surface.view_format(), pixels)?;
        let mut playback = Playback::new(scene.scene().frame_count(), animation_fps(scene.scene()));
        if options.play {
            playback.toggle(Instant::now());
        }
        let path = scene.scene().frame_path();
        let home = path.camera_at(playback.frame());
        scene.write_lights(ctx, &path.lights_at(playback.frame()));
        let controller = CameraController::new(home, bounds(&scene), width, height);
        let file_max_depth = scene.scene().render.max_depth;
        let integrator = scene.scene().render.integrator;
        let samples = window_samples(options, scene.scene(), integrator);
        let now = Instant::now();
        Ok(Session {
            window,
            surface,
            ctx,
            viewer,
            scene,
            file_max_depth,
            controller,
            accel: options.flags.accel,
            traversal: options.flags.traversal,
            heatmap: false,
            integrator,
            max_depth: file_max_depth,
            refinement: Refinement::new(samples, max_pixels),
            playback,
            path,
            last_update: now,
            stats: FrameStats::new(now),
            title: TitleBar::new(now),
            inspect: InspectMode::default(),
            recorder: None,
            clicks: ClickTracker::default(),
            denoising: Denoising::new(denoise),
            denoised_last_frame: false,
        })
    }

    /// Shows `prepared` from now on (a reload).
    pub(super) fn set_scene(
        &mut self,
        prepared: PreparedScene,
        options: &WindowOptions,
    ) -> Result<()> {
        let scene = GpuScene::upload(self.ctx, prepared)?;
        self.viewer.set_scene(self.ctx, scene.buffers())?;
        self.playback.set_animation(
            scene.scene().frame_count(),
            animation_fps(scene.scene()),
            Instant::now(),
        );
        self.path = scene.scene().frame_path();
        self.controller
            .set_scene(self.path.camera_at(self.playback.frame()), bounds(&scene));
        scene.write_lights(self.ctx, &self.path.lights_at(self.playback.frame()));
        let max_depth = scene.scene().render.max_depth;
        if max_depth != self.file_max_depth {
            self.file_max_depth = max_depth;
            self.max_depth = max_depth;
        }
        self.integrator = scene.scene().render.integrator;
        self.refinement
            .set_samples(window_samples(options, scene.scene(), self.integrator));
        self.scene = scene;
        self.denoising.set_scene();
        self.refinement.invalidate();
        // The pixel's rays in the new scene (or tree).
        self.reinspect();
        Ok(())
    }

    /// Traces the other integrator from now on (I), refined to its samples.
    pub(super) fn toggle_integrator(&mut self, options: &WindowOptions) {
        self.integrator = match self.integrator {
            Integrator::Whitted => Integrator::Path,
            Integrator::Path => Integrator::Whitted,
        };
        self.refinement
            .set_samples(window_samples(options, self.scene.scene(), self.integrator));
        self.refinement.invalidate();
        self.denoising.refused = false;
    }

    /// Moves the camera to the animation's shown frame (the frame's camera
    /// becomes the home that R returns to) and puts its lights in place.
    pub(super) fn show_frame(&mut self, now: Instant) {
        let home = self.path.camera_at(self.playback.frame());
        if self.path.lights_move() {
            self.scene
                .write_lights(self.ctx, &self.path.lights_at(self.playback.frame()));
        }
        self.controller.set_scene(home, bounds(&self.scene));
        self.camera_moved(now);
        self.refinement.invalidate();
    }

    pub(super) fn camera_moved(&mut self, now: Instant) {
        self.refinement.camera_moved(now, self.surface.size());
    }

    pub(super) fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        if !self.surface.resize(self.ctx, size) {
            return Ok(());
        }
        let (iw, ih) = self.refinement.image_size(self.surface.size());
        self.viewer
            .reserve(self.ctx, self.scene.buffers(), iw as u64 * ih as u64)?;
        self.refinement.invalidate();
        Ok(())
    }

    /// Whether the event loop should ask for another frame now.
    pub(super) fn wants_frame(
        &mut self,
        now: Instant,
        auto_orbit: f64,
        frames: Option<u32>,
    ) -> bool {
        if !self.surface.can_draw(now, &self.window) {
            return false;
        }
        let camera = self.controller.is_flying() || auto_orbit != 0.0 || self.playback.is_playing();
        let counted = frames.is_some_and(|n| self.stats.presented() < n);
        let denoise = self.denoising.is_running() || self.denoise_pending(now);
        self.refinement.has_work(now) || camera || counted || denoise
    }

    /// Renders and presents one frame; None if the surface had no image.
    pub(super) fn frame(&mut self, now: Instant, auto_orbit: f64) -> Result<Option<FrameKind>> {
        if self.surface.is_minimized() {
            return Ok(None);
        }
        let dt = now.duration_since(self.last_update).as_secs_f64();
        self.last_update = now;
        if self.controller.update(dt) {
            self.camera_moved(now);
        }
        if auto_orbit != 0.0 && self.controller.orbit(auto_orbit, 0.0) {
            self.camera_moved(now);
        }
        if self.playback.advance(now) {
            self.show_frame(now);
        }
        let frame = match self.surface.acquire(self.ctx, now)? {
            Acquired::Frame(frame) => frame,
            Acquired::Skipped => return Ok(None),
            Acquired::Outdated => {
                let size = self.window.inner_size();
                self.resize(size)?;
                self.surface.reconfigure(self.ctx);
                return Ok(None);
            }
        };
        let window = self.surface.size();
        let plan = self.refinement.plan(now, window);
        let work = self.frame_work(&plan, window);
        let denoised = match self.denoise_frame(&plan, &work) {
            Ok(denoised) => denoised,
            Err(e) => {
                eprintln!("kdray: denoising failed, turned off: {e}");
                self.denoising.on = false;
                self.denoising.abandon();
                self.viewer.hide_denoised();
                false
            }
        };
        if self.viewer.overlay_mut().has_lines() {
            let view = self.overlay_view().gpu_matrix();
            self.viewer.overlay_mut().set_view(&self.ctx.queue, view);
        }
        self.viewer
            .frame(self.ctx, &frame.view, &work, self.heatmap)?;
        self.surface.present(self.ctx, &self.window, frame);
        self.ctx.check_health()?;
        let rays = plan.pass.map_or(0, |p| p.pixels());
        // This interval is the last frame's time: with denoise units in
        // it, not the time of its pass alone, so not one to learn from.
        let learn = !self.denoised_last_frame;
        self.denoised_last_frame = denoised;
        if let Some(ms) = self.stats.record(now, plan.kind, rays) {
            if learn {
                self.refinement.learn(plan.kind, ms, rays);
            }
        }
        Ok(Some(plan.kind))
    }

    /// The GPU work of `plan` in a `window`-sized window.
    pub(super) fn frame_work(&mut self, plan: &FramePlan, window: (u32, u32)) -> FrameWork {
        let camera = self.controller.camera();
        let pass = plan.pass.map(|p| {
            pass_params(
                &self.scene,
                &camera,
                self.max_depth,
                self.accel,
                self.integrator,
                &p,
                window,
            )
            .with_traversal(self.traversal)
        });
        let (target, show_image) = match plan.kind {
            FrameKind::Moving => (Target::Preview, 0),
            FrameKind::Still | FrameKind::Idle => (Target::Image, 1),
        };
        let (tw, th) = plan.target_size();
        let (tone_map, exposure_scale) =
            PresentParams::tone_of(self.integrator, &self.scene.scene().render);
        FrameWork {
            target,
            clear_pixels: plan.clear.then_some(tw as u64 * th as u64),
            pass,
            present: PresentParams {
                image_size: [plan.image.0, plan.image.1],
                target_size: [window.0, window.1],
                preview_size: [plan.preview.0, plan.preview.1],
                show_image,
                tone_map,
                exposure_scale,
                _pad: 0,
            },
        }
    }

    pub(super) fn update_title(&mut self, name: &str, force: bool) {
        let now = Instant::now();
        if !self.title.due(now, force) {
            return;
        }
        let progress = if self.refinement.is_moving(now) {
            Progress::Moving {
                scale: self.refinement.moving_scale(),
            }
        } else {
            Progress::Refining {
                passes: self.refinement.passes(),
                samples: self.refinement.samples(),
                path: self.integrator == Integrator::Path,
            }
        };
        let (frame_ms, mrays) = self.stats.smoothed();
        let text = self.title.text(&TitleFacts {
            name,
            progress,
            frame_ms,
            mrays,
            accel: self.accel,
            traversal: self.traversal,
            build: self.scene.strategy(),
            max_depth: self.max_depth,
            heatmap: self.viewer.heatmap_scale(),
            animation: self.playback.is_animated().then(|| {
                (
                    self.playback.frame(),
                    self.playback.frames(),
                    self.playback.is_playing(),
                )
            }),
            inspect: self.inspect.title(self.integrator == Integrator::Path),
            denoise: self.denoise_title(),
        });
        self.window.set_title(&text);
    }

    pub(super) fn save_screenshot(&self, path: &Path) -> Result<()> {
        let (width, height) = self.surface.size();
        let rgb = self.viewer.capture(self.ctx, width, height)?;
        crate::output::write_png_atomic(path, width, height, &rgb)
    }

    /// The frame figures: one line on stderr, and with `--stats` one JSON
    /// object on stdout.
    pub(super) fn report(&self, options: &WindowOptions, name: &str) -> Result<()> {
        let (width, height) = self.surface.size();
        let about = ReportContext {
            name: name.to_string(),
            adapter: self.ctx.info.name.clone(),
            backend: format!("{:?}", self.ctx.info.backend),
            width,
            height,
            samples: self.refinement.samples(),
            moving_scale: self.refinement.moving_scale(),
            refine_seconds: self.refinement.refine_seconds(),
        };
        let Some((line, stats)) = self.stats.report(Instant::now(), about) else {
            return Ok(());
        };
        eprintln!("{line}");
        if options.stats {
            println!("{}", serde_json::to_string(&stats)?);
        }
        Ok(())
    }
}
