//! The winit application behind `kdray render SCENE --window`: the event
//! handler, and the wiring of the window's parts. Each frame is one
//! submission and one present: [`Refinement`] plans it, `pass_params` turns
//! its pass over the [`GpuScene`] into the shader's parameters, [`Viewer`] records it,
//! [`WindowSurface`] shows it and [`FrameStats`] counts it.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use winit::application::ApplicationHandler;
use winit::dpi::{LogicalSize, PhysicalSize, Size};
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, OwnedDisplayHandle};
use winit::window::{Window, WindowId};

use super::camera_controller::Bounds;
use super::camera_controller::{CameraController, Input};
use super::frame_stats::{FrameStats, ReportContext};
use super::input::{controller_input, key_action, Action, HELP};
use super::playback::Playback;
use super::refinement::{FrameKind, FramePlan, Pass, Refinement};
use super::reload::{self, LatestJob, SceneWatcher, WatchList};
use super::surface::{Acquired, WindowSurface};
use super::title::{Progress, TitleBar, TitleFacts};
use super::view::{FrameWork, PresentParams, Target, Viewer};
use super::{signals, WindowOptions, DEFAULT_WINDOW_SAMPLES};
use crate::error::{Error, Result};
use crate::gpu::{Accel, GpuContext, GpuScene, PreparedScene};
use crate::kdtree::Traversal;
use crate::layout::FrameParams;
use crate::scene::{Camera, CameraPath, RenderSettings, Scene};

/// Default window: the scene's aspect ratio fitted into this (logical pixels).
const DEFAULT_WINDOW: (f64, f64) = (960.0, 720.0);
/// Benchmark aid: a left-drag of this many pixels per frame, so frame rates
/// while moving can be measured without a person.
const AUTO_ORBIT_ENV: &str = "KDRAY_AUTO_ORBIT";

pub fn run(options: WindowOptions) -> Result<()> {
    let auto_orbit = match std::env::var(AUTO_ORBIT_ENV) {
        Ok(v) => v
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| {
                Error::Usage(format!(
                    "{AUTO_ORBIT_ENV}: expected a number of pixels per frame, got {v:?}"
                ))
            })?,
        Err(_) => 0.0,
    };
    // Watch first, so a change made while the scene loads is not missed.
    let (files, scene) =
        WatchList::record(|seen| reload::load(&options.scene, options.build, seen));
    let watcher = SceneWatcher::new(files);
    let scene = scene?;
    let event_loop = EventLoop::new().map_err(|e| {
        Error::Gpu(format!(
            "cannot open a window: {e} (is DISPLAY or WAYLAND_DISPLAY set?)"
        ))
    })?;
    signals::install();
    let mut app = App {
        name: options
            .scene
            .file_name()
            .map_or_else(|| "scene".into(), |n| n.to_string_lossy().into_owned()),
        display: event_loop.owned_display_handle(),
        options,
        pending: Some(scene),
        watcher,
        reloads: LatestJob::default(),
        session: None,
        error: None,
        auto_orbit,
        exiting: false,
    };
    let run = event_loop.run_app(&mut app);
    if let Some(session) = &app.session {
        session.report(&app.options, &app.name)?;
    }
    if let Some(e) = app.error {
        return Err(e);
    }
    run.map_err(|e| Error::Gpu(format!("the window's event loop failed: {e}")))
}

struct App {
    options: WindowOptions,
    /// The scene's file name, for the title bar.
    name: String,
    display: OwnedDisplayHandle,
    /// The scene loaded at start (or reloaded since), until the window exists.
    pending: Option<PreparedScene>,
    watcher: SceneWatcher,
    /// Reloads in flight on a worker thread: the files to watch from then
    /// on, and the scene.
    reloads: LatestJob<(WatchList, Result<PreparedScene>)>,
    session: Option<Session>,
    error: Option<Error>,
    auto_orbit: f64,
    exiting: bool,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: Error) {
        self.error.get_or_insert(e);
        self.exiting = true;
        event_loop.exit();
    }

    /// Closes the window, saving `--screenshot` first.
    fn quit(&mut self, event_loop: &ActiveEventLoop) {
        if self.exiting {
            return;
        }
        if let (Some(path), Some(session)) = (&self.options.screenshot, &self.session) {
            if session.stats.presented() > 0 {
                if let Err(e) = session.save_screenshot(path) {
                    self.error.get_or_insert(e);
                }
            }
        }
        self.exiting = true;
        event_loop.exit();
    }

    /// Starts loading the scene again on a worker thread; the window keeps
    /// drawing the current one meanwhile.
    fn start_reload(&mut self) {
        let path = self.options.scene.clone();
        let build = self.options.build;
        // The mesh list may have changed: the job also lists what to watch.
        self.reloads
            .request(move || WatchList::record(|seen| reload::load(&path, build, seen)));
        if let Some(session) = &mut self.session {
            session.title.reloading = true;
            session.update_title(&self.name, true);
        }
    }

    /// Shows a finished reload, or reports why it failed (keeping the last
    /// good scene).
    fn finish_reload(
        &mut self,
        outcome: std::result::Result<(WatchList, Result<PreparedScene>), String>,
    ) {
        // The thread's failure (it could not start, or panicked) is a
        // message, like the scene's own errors.
        let result = match outcome {
            Ok((files, loaded)) => {
                self.watcher.watch(files);
                loaded
                    .and_then(|prepared| match &mut self.session {
                        Some(session) => session.set_scene(prepared, &self.options),
                        None => {
                            self.pending = Some(prepared);
                            Ok(())
                        }
                    })
                    .map_err(|e| e.to_string())
            }
            Err(message) => {
                self.watcher.rescan();
                Err(message)
            }
        };
        let message = match result {
            Ok(()) => {
                eprintln!("kdray: reloaded {}", self.options.scene.display());
                None
            }
            Err(message) => {
                eprintln!("kdray: {message}");
                Some(message)
            }
        };
        if let Some(session) = &mut self.session {
            session.title.reload_error = message;
            session.title.reloading = self.reloads.busy();
            session.update_title(&self.name, true);
        }
    }

    /// Carries out a key's [`Action`] (the mapping is in `input.rs`).
    fn handle_key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) {
        let Some(session) = &mut self.session else {
            return;
        };
        let pressed = event.state == ElementState::Pressed;
        let Some(action) = key_action(event.physical_key, &event.logical_key) else {
            return;
        };
        if let Action::Fly(key) = action {
            session.controller.handle(Input::Key { key, pressed });
            return;
        }
        if !pressed || event.repeat {
            return;
        }
        match action {
            Action::Fly(_) => {}
            Action::Quit => self.quit(event_loop),
            Action::Camera(key) => {
                if session.controller.handle(Input::Key { key, pressed: true }) {
                    session.refinement.invalidate();
                }
            }
            Action::Screenshot if session.stats.presented() == 0 => {
                eprintln!("kdray: nothing shown yet, no screenshot saved");
            }
            Action::Screenshot => {
                let path = next_screenshot_path(&self.options.scene);
                match session.save_screenshot(&path) {
                    Ok(()) => eprintln!(
                        "kdray: saved {} ({} of {} samples per pixel)",
                        path.display(),
                        session.refinement.passes(),
                        session.refinement.samples()
                    ),
                    Err(e) => eprintln!("kdray: {e}"),
                }
            }
            Action::ToggleAccel => {
                session.accel = match session.accel {
                    Accel::Kdtree => Accel::Brute,
                    Accel::Brute => Accel::Kdtree,
                };
                session.refinement.invalidate();
                session.update_title(&self.name, true);
            }
            Action::CycleTraversal => {
                // Same picture, other work: start over so the frame times
                // and the heatmap are the new walk's.
                session.traversal = session.traversal.next();
                session.refinement.invalidate();
                session.update_title(&self.name, true);
            }
            Action::CycleBuild => {
                // A new tree: prepared on the worker like a reload, shown
                // when ready (the title says "reloading" meanwhile).
                self.options.build = self.options.build.next();
                eprintln!("kdray: building the {} tree", self.options.build);
                self.start_reload();
            }
            Action::ToggleHeatmap => {
                // The costs accumulate with the colours; refining again
                // makes the frames that show the other view.
                session.heatmap = !session.heatmap;
                session.refinement.invalidate();
                session.update_title(&self.name, true);
            }
            Action::DepthDown | Action::DepthUp => {
                let depth = if action == Action::DepthDown {
                    session.max_depth.saturating_sub(1)
                } else {
                    session.max_depth + 1
                };
                // The scene format's range of render.max_depth.
                session.max_depth = depth.clamp(1, 64);
                session.refinement.invalidate();
                session.update_title(&self.name, true);
            }
            Action::TogglePlay => {
                if !session.playback.is_animated() {
                    eprintln!("kdray: the scene has no [animation] to play");
                }
                session.playback.toggle(Instant::now());
                session.update_title(&self.name, true);
            }
            Action::Help => eprintln!("{HELP}"),
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let Some(session) = &mut self.session else {
            return;
        };
        let now = Instant::now();
        match session.frame(now, self.auto_orbit) {
            Ok(Some(_)) => {}
            Ok(None) => return,
            Err(e) => return self.fail(event_loop, e),
        }
        let presented = session.stats.presented();
        if presented == 1 {
            let (width, height) = session.surface.size();
            eprintln!(
                "kdray: {}: {width}x{height} window on {}, refining to {} samples per pixel; press H for the controls",
                self.name,
                session.ctx.adapter_line(),
                session.refinement.samples()
            );
        }
        session.update_title(&self.name, false);
        if self.options.frames.is_some_and(|n| presented >= n) {
            self.quit(event_loop);
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.session.is_some() || self.exiting {
            return;
        }
        let Some(scene) = self.pending.take() else {
            return;
        };
        match Session::open(event_loop, &self.display, scene, &self.options, &self.name) {
            Ok(session) => {
                self.session = Some(session);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        if self.exiting {
            return;
        }
        let now = Instant::now();
        match event {
            WindowEvent::CloseRequested => return self.quit(event_loop),
            WindowEvent::RedrawRequested => return self.redraw(event_loop),
            WindowEvent::KeyboardInput { event, .. } => return self.handle_key(event_loop, &event),
            _ => {}
        }
        let Some(session) = &mut self.session else {
            return;
        };
        match event {
            WindowEvent::Resized(size) => {
                if let Err(e) = session.resize(size) {
                    return self.fail(event_loop, e);
                }
            }
            WindowEvent::Occluded(occluded) => session.surface.set_occluded(occluded),
            _ => {}
        }
        let Some(input) = controller_input(&event) else {
            return;
        };
        if session.controller.handle(input) {
            session.camera_moved(now);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if self.exiting {
            return;
        }
        if signals::quit_requested() {
            return self.quit(event_loop);
        }
        let now = Instant::now();
        if self.watcher.poll(now) {
            self.start_reload();
        }
        if let Some(outcome) = self.reloads.poll() {
            self.finish_reload(outcome);
        }
        if let Some(session) = &mut self.session {
            if session.wants_frame(now, self.auto_orbit, self.options.frames) {
                session.window.request_redraw();
            } else {
                // Idle: the next frame's interval is not a frame time.
                session.stats.pause();
                if session.title.is_stale() {
                    session.update_title(&self.name, true);
                }
            }
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.watcher.next_poll()));
    }
}

/// Everything that exists once the window is open.
struct Session {
    window: Arc<Window>,
    surface: WindowSurface,
    ctx: GpuContext,
    viewer: Viewer,
    /// The last good scene.
    scene: GpuScene,
    /// `render.max_depth` as the file said it (a reload that changes it wins
    /// over [ and ]).
    file_max_depth: u32,
    controller: CameraController,
    accel: Accel,
    /// The k-d walk (T cycles them).
    traversal: Traversal,
    /// Show the cost heatmap instead of the image (C toggles it).
    heatmap: bool,
    max_depth: u32,
    refinement: Refinement,
    /// The scene's animation: the frame shown, played by Space.
    playback: Playback,
    /// The scene's camera at every frame of its animation.
    path: CameraPath,
    /// When the camera's fly keys were last applied.
    last_update: Instant,
    stats: FrameStats,
    title: TitleBar,
}

/// Window size: --width/--height in physical pixels; one of them alone keeps
/// the scene's aspect ratio; neither fits the scene into [`DEFAULT_WINDOW`].
fn window_size(options: &WindowOptions, scene: &Scene) -> Size {
    let (sw, sh) = (scene.render.width as f64, scene.render.height as f64);
    let side = |v: f64| (v.round() as u32).clamp(1, crate::scene::MAX_IMAGE_SIDE);
    match (options.width, options.height) {
        (Some(w), Some(h)) => PhysicalSize::new(w, h).into(),
        (Some(w), None) => PhysicalSize::new(w, side(w as f64 * sh / sw)).into(),
        (None, Some(h)) => PhysicalSize::new(side(h as f64 * sw / sh), h).into(),
        (None, None) => {
            let scale = (DEFAULT_WINDOW.0 / sw).min(DEFAULT_WINDOW.1 / sh).min(1.0);
            LogicalSize::new((sw * scale).round().max(1.0), (sh * scale).round().max(1.0)).into()
        }
    }
}

/// k of the k x k samples per pixel the window refines to.
fn window_samples_per_axis(options: &WindowOptions, scene: &Scene) -> u32 {
    let samples = options
        .samples
        .unwrap_or_else(|| scene.render.samples.max(DEFAULT_WINDOW_SAMPLES));
    RenderSettings {
        samples,
        ..scene.render
    }
    .samples_per_axis()
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
fn pass_params(
    scene: &GpuScene,
    camera: &Camera,
    max_depth: u32,
    accel: Accel,
    pass: &Pass,
    (w, h): (u32, u32),
) -> FrameParams {
    let (iw, ih) = pass.image;
    let render = RenderSettings {
        width: iw,
        height: ih,
        max_depth,
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
fn next_screenshot_path(scene: &Path) -> PathBuf {
    let stem = scene
        .file_stem()
        .map_or_else(|| "kdray".into(), |s| s.to_string_lossy().into_owned());
    (1..u32::MAX)
        .map(|n| PathBuf::from(format!("{stem}-{n:03}.png")))
        .find(|p| !p.exists())
        .unwrap_or_else(|| PathBuf::from(format!("{stem}-latest.png")))
}

impl Session {
    fn open(
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
        let scene = GpuScene::upload(&ctx, prepared)?;
        let max_pixels = Viewer::max_pixels(&ctx);
        let (width, height) = surface.size();
        let pixels = (width as u64 * height as u64).min(max_pixels);
        let viewer = Viewer::new(&ctx, scene.buffers(), surface.view_format(), pixels)?;
        let playback = Playback::new(scene.scene().frame_count(), animation_fps(scene.scene()));
        let path = scene.scene().camera_path();
        let home = path.camera_at(playback.frame());
        let controller = CameraController::new(home, bounds(&scene), width, height);
        let file_max_depth = scene.scene().render.max_depth;
        let k = window_samples_per_axis(options, scene.scene());
        let now = Instant::now();
        Ok(Session {
            window,
            surface,
            ctx,
            viewer,
            scene,
            file_max_depth,
            controller,
            accel: options.accel,
            traversal: options.traversal,
            heatmap: false,
            max_depth: file_max_depth,
            refinement: Refinement::new(k, max_pixels),
            playback,
            path,
            last_update: now,
            stats: FrameStats::new(now),
            title: TitleBar::new(now),
        })
    }

    /// Shows `prepared` from now on (a reload).
    fn set_scene(&mut self, prepared: PreparedScene, options: &WindowOptions) -> Result<()> {
        let scene = GpuScene::upload(&self.ctx, prepared)?;
        self.viewer.set_scene(&self.ctx, scene.buffers())?;
        self.playback.set_animation(
            scene.scene().frame_count(),
            animation_fps(scene.scene()),
            Instant::now(),
        );
        self.path = scene.scene().camera_path();
        self.controller
            .set_scene(self.path.camera_at(self.playback.frame()), bounds(&scene));
        let max_depth = scene.scene().render.max_depth;
        if max_depth != self.file_max_depth {
            self.file_max_depth = max_depth;
            self.max_depth = max_depth;
        }
        self.refinement
            .set_samples_per_axis(window_samples_per_axis(options, scene.scene()));
        self.scene = scene;
        self.refinement.invalidate();
        Ok(())
    }

    /// Moves the camera to the animation's shown frame (the frame's camera
    /// becomes the home that R returns to).
    fn show_frame(&mut self, now: Instant) {
        let home = self.path.camera_at(self.playback.frame());
        self.controller.set_scene(home, bounds(&self.scene));
        self.camera_moved(now);
        self.refinement.invalidate();
    }

    fn camera_moved(&mut self, now: Instant) {
        self.refinement.camera_moved(now, self.surface.size());
    }

    fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        if !self.surface.resize(&self.ctx, size) {
            return Ok(());
        }
        let (iw, ih) = self.refinement.image_size(self.surface.size());
        self.viewer
            .reserve(&self.ctx, self.scene.buffers(), iw as u64 * ih as u64)?;
        self.refinement.invalidate();
        Ok(())
    }

    /// Whether the event loop should ask for another frame now.
    fn wants_frame(&mut self, now: Instant, auto_orbit: f64, frames: Option<u32>) -> bool {
        if !self.surface.can_draw(now, &self.window) {
            return false;
        }
        let camera = self.controller.is_flying() || auto_orbit != 0.0 || self.playback.is_playing();
        let counted = frames.is_some_and(|n| self.stats.presented() < n);
        self.refinement.has_work(now) || camera || counted
    }

    /// Renders and presents one frame; None if the surface had no image.
    fn frame(&mut self, now: Instant, auto_orbit: f64) -> Result<Option<FrameKind>> {
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
        let frame = match self.surface.acquire(&self.ctx, now)? {
            Acquired::Frame(frame) => frame,
            Acquired::Skipped => return Ok(None),
            Acquired::Outdated => {
                let size = self.window.inner_size();
                self.resize(size)?;
                self.surface.reconfigure(&self.ctx);
                return Ok(None);
            }
        };
        let window = self.surface.size();
        let plan = self.refinement.plan(now, window);
        let work = self.frame_work(&plan, window);
        self.viewer
            .frame(&self.ctx, &frame.view, &work, self.heatmap)?;
        self.surface.present(&self.ctx, &self.window, frame);
        self.ctx.check_health()?;
        let rays = plan.pass.map_or(0, |p| p.pixels());
        if let Some(ms) = self.stats.record(now, plan.kind, rays) {
            self.refinement.learn(plan.kind, ms, rays);
        }
        Ok(Some(plan.kind))
    }

    /// The GPU work of `plan` in a `window`-sized window.
    fn frame_work(&mut self, plan: &FramePlan, window: (u32, u32)) -> FrameWork {
        let camera = self.controller.camera();
        let pass = plan.pass.map(|p| {
            pass_params(&self.scene, &camera, self.max_depth, self.accel, &p, window)
                .with_traversal(self.traversal)
        });
        let (target, show_image) = match plan.kind {
            FrameKind::Moving => (Target::Preview, 0),
            FrameKind::Still | FrameKind::Idle => (Target::Image, 1),
        };
        let (tw, th) = plan.target_size();
        FrameWork {
            target,
            clear_pixels: plan.clear.then_some(tw as u64 * th as u64),
            pass,
            present: PresentParams {
                image_size: [plan.image.0, plan.image.1],
                target_size: [window.0, window.1],
                preview_size: [plan.preview.0, plan.preview.1],
                show_image,
                _pad: 0,
            },
        }
    }

    fn update_title(&mut self, name: &str, force: bool) {
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
        });
        self.window.set_title(&text);
    }

    fn save_screenshot(&self, path: &Path) -> Result<()> {
        let (width, height) = self.surface.size();
        let rgb = self.viewer.capture(&self.ctx, width, height)?;
        crate::output::write_png_atomic(path, width, height, &rgb)
    }

    /// The frame figures: one line on stderr, and with `--stats` one JSON
    /// object on stdout.
    fn report(&self, options: &WindowOptions, name: &str) -> Result<()> {
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
