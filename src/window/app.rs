//! The winit application behind `kdray render SCENE --window`: owns the
//! window, its surface, the device, the scene's tree and buffers, the
//! accumulation buffer and the present pass, and turns input into frames.
//!
//! Each frame is one submission and one present. While the camera moves
//! (and for [`SETTLE`] after its last change) a frame traces the *preview*:
//! a fresh single-sample image at 1/s of the resolution, `s` adapted so a
//! frame takes about [`MOVING_BUDGET_MS`]. While it is still, each frame adds
//! stratified samples to the *image* (sample `n` of the k x k grid in pass
//! `n`, the headless kernel's order) until every pixel holds all k * k; then
//! the window idles. A pass that would take longer than [`STILL_BUDGET_MS`]
//! is spread over several frames, a band of rows each, and the present pass
//! shows the preview where the image has no sample yet. Any change restarts
//! the refinement after one preview frame.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde::Serialize;
use winit::application::ApplicationHandler;
use winit::dpi::{LogicalSize, PhysicalSize, Size};
use winit::event::{ElementState, KeyEvent, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, OwnedDisplayHandle};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};
use winit::window::{Window, WindowId};

use super::camera_controller::{Bounds, Button, CameraController, ControlKey, Input};
use super::reload::{LatestJob, SceneWatcher, WatchList};
use super::view::{FrameWork, PresentParams, Target, Viewer};
use super::{signals, WindowOptions, DEFAULT_WINDOW_SAMPLES};
use crate::error::{Error, Result};
use crate::geometry::Primitives;
use crate::gpu::{frame_params, Accel, GpuContext, SceneArrays, SceneBuffers};
use crate::kdtree::KdTree;
use crate::layout::FrameParams;
use crate::scene::Scene;

/// The camera counts as moving until this long after its last change.
const SETTLE: Duration = Duration::from_millis(150);
/// How often the window manager is asked whether the window is minimised.
const STATE_CHECK_INTERVAL: Duration = Duration::from_millis(100);
/// Title bar refresh interval.
const TITLE_INTERVAL: Duration = Duration::from_millis(250);
/// Frame time aimed at while the camera moves.
const MOVING_BUDGET_MS: f64 = 50.0;
/// Longest frame while refining: a sample pass that would take longer is
/// spread over several frames, a band of rows each, so the window stays
/// responsive (the accumulation counts samples per pixel, so a partly
/// finished pass shows correctly).
const STILL_BUDGET_MS: f64 = 80.0;
/// Coarsest resolution divisor while moving.
const MAX_MOVING_SCALE: u32 = 8;
/// Default window: the scene's aspect ratio fitted into this (logical pixels).
const DEFAULT_WINDOW: (f64, f64) = (960.0, 720.0);
/// Benchmark aid: a left-drag of this many pixels per frame, so frame rates
/// while moving can be measured without a person.
const AUTO_ORBIT_ENV: &str = "KDRAY_AUTO_ORBIT";

pub const HELP: &str = "\
kdray window controls:
  left drag          orbit around the target point
  right/middle drag  pan
  wheel              zoom toward the target
  W A S D, Q E       fly forward, left, back, right; down, up
  F                  frame the whole scene
  R                  reset to the scene's camera
  P                  save a screenshot (PNG in the current folder)
  B                  toggle k-d tree / brute force
  [ ]                max_depth down / up
  H                  this help
  Esc                quit";

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
    let (files, scene) = WatchList::record(|seen| PreparedScene::load(&options.scene, seen));
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
            if session.presented > 0 {
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
        // The mesh list may have changed: the job also lists what to watch.
        self.reloads
            .request(move || WatchList::record(|seen| PreparedScene::load(&path, seen)));
        if let Some(session) = &mut self.session {
            session.reloading = true;
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
            session.reload_error = message;
            session.reloading = self.reloads.busy();
            session.update_title(&self.name, true);
        }
    }

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
                    session.invalidate();
                }
            }
            Action::Screenshot if session.presented == 0 => {
                eprintln!("kdray: nothing shown yet, no screenshot saved");
            }
            Action::Screenshot => {
                let path = next_screenshot_path(&self.options.scene);
                match session.save_screenshot(&path) {
                    Ok(()) => eprintln!(
                        "kdray: saved {} ({} of {} samples per pixel)",
                        path.display(),
                        session.passes,
                        session.samples
                    ),
                    Err(e) => eprintln!("kdray: {e}"),
                }
            }
            Action::ToggleAccel => {
                session.accel = match session.accel {
                    Accel::Kdtree => Accel::Brute,
                    Accel::Brute => Accel::Kdtree,
                };
                session.invalidate();
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
                session.invalidate();
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
        if session.presented == 1 {
            eprintln!(
                "kdray: {}: {}x{} window on {}, refining to {} samples per pixel; press H for the controls",
                self.name,
                session.config.width,
                session.config.height,
                session.ctx.adapter_line(),
                session.samples
            );
        }
        session.update_title(&self.name, false);
        if self.options.frames.is_some_and(|n| session.presented >= n) {
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
            WindowEvent::Occluded(occluded) => session.occluded = occluded,
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
                session.last_frame = None;
                if session.title_stale {
                    session.update_title(&self.name, true);
                }
            }
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.watcher.next_poll()));
    }
}

/// What a key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Action {
    /// W A S D Q E: move while held.
    Fly(ControlKey),
    /// F, R: one camera jump.
    Camera(ControlKey),
    Screenshot,
    ToggleAccel,
    DepthDown,
    DepthUp,
    Help,
    Quit,
}

/// The action of a key: the fly keys by position (W A S D Q E of a US
/// keyboard, on any layout), the others by the character they type.
fn key_action(physical: PhysicalKey, logical: &Key) -> Option<Action> {
    if let PhysicalKey::Code(code) = physical {
        let fly = match code {
            KeyCode::KeyW => Some(ControlKey::Forward),
            KeyCode::KeyS => Some(ControlKey::Backward),
            KeyCode::KeyA => Some(ControlKey::Left),
            KeyCode::KeyD => Some(ControlKey::Right),
            KeyCode::KeyQ => Some(ControlKey::Down),
            KeyCode::KeyE => Some(ControlKey::Up),
            _ => None,
        };
        if let Some(key) = fly {
            return Some(Action::Fly(key));
        }
    }
    let ch = match logical {
        Key::Named(NamedKey::Escape) => return Some(Action::Quit),
        Key::Character(c) => c.to_lowercase(),
        _ => return None,
    };
    Some(match ch.as_str() {
        "f" => Action::Camera(ControlKey::FrameAll),
        "r" => Action::Camera(ControlKey::Reset),
        "p" => Action::Screenshot,
        "b" => Action::ToggleAccel,
        "[" => Action::DepthDown,
        "]" => Action::DepthUp,
        "h" => Action::Help,
        _ => return None,
    })
}

/// The camera controller's input for a window event (sizes and positions
/// in physical pixels, as the controller expects).
fn controller_input(event: &WindowEvent) -> Option<Input> {
    Some(match event {
        WindowEvent::Resized(size) => Input::Resized {
            width: size.width,
            height: size.height,
        },
        WindowEvent::CursorMoved { position, .. } => Input::CursorMoved {
            x: position.x,
            y: position.y,
        },
        WindowEvent::CursorLeft { .. } => Input::CursorLeft,
        WindowEvent::MouseInput { state, button, .. } => Input::Button {
            button: match button {
                MouseButton::Left => Button::Left,
                MouseButton::Right => Button::Right,
                MouseButton::Middle => Button::Middle,
                _ => return None,
            },
            pressed: *state == ElementState::Pressed,
        },
        WindowEvent::MouseWheel { delta, .. } => match delta {
            MouseScrollDelta::LineDelta(_, y) => Input::WheelLines(*y as f64),
            MouseScrollDelta::PixelDelta(p) => Input::WheelPixels(p.y),
        },
        WindowEvent::Focused(false) => Input::FocusLost,
        _ => return None,
    })
}

/// Which work a frame did, for the figures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FrameKind {
    /// A full-resolution sample added to the still image.
    Still,
    /// A reduced-resolution image of a moving camera.
    Moving,
    /// The finished image presented again.
    Idle,
}

#[derive(Debug, Clone, Copy, Default)]
struct KindStats {
    frames: u32,
    seconds: f64,
    primary_rays: u64,
    /// The longest of these frames (a stall shows here), ms.
    longest_ms: f64,
}

impl KindStats {
    fn fps(&self) -> f64 {
        self.frames as f64 / self.seconds.max(1e-9)
    }
    fn ms(&self) -> f64 {
        self.seconds * 1e3 / (self.frames.max(1) as f64)
    }
    fn mrays(&self) -> f64 {
        self.primary_rays as f64 / self.seconds.max(1e-9) * 1e-6
    }
}

/// What `--window --stats` prints on exit.
#[derive(Debug, Serialize)]
struct WindowStats {
    adapter: String,
    backend: String,
    width: u32,
    height: u32,
    samples: u32,
    frames: u32,
    seconds: f64,
    still_frames: u32,
    still_fps: f64,
    still_ms: f64,
    still_mrays_per_s: f64,
    still_longest_ms: f64,
    moving_frames: u32,
    moving_fps: f64,
    moving_ms: f64,
    moving_mrays_per_s: f64,
    moving_longest_ms: f64,
    /// Resolution divisor while moving, at exit.
    moving_scale: u32,
    idle_frames: u32,
    /// Seconds the last full refinement took (from the restart to the
    /// submission of its last pass), if one finished.
    refine_seconds: Option<f64>,
}

/// Everything that exists once the window is open.
struct Session {
    window: Arc<Window>,
    surface: wgpu::Surface<'static>,
    config: wgpu::SurfaceConfiguration,
    /// The format the present pass writes (never sRGB).
    view_format: wgpu::TextureFormat,
    ctx: GpuContext,
    viewer: Viewer,
    /// The last good scene; its camera and render size are overwritten for
    /// each pass.
    scene: Scene,
    /// `render.max_depth` as the file said it (a reload that changes it wins
    /// over [ and ]).
    file_max_depth: u32,
    tree: KdTree,
    buffers: SceneBuffers,
    controller: CameraController,
    accel: Accel,
    max_depth: u32,
    /// Samples per pixel of the finished image, k * k.
    samples: u32,
    max_pixels: u64,
    /// Size of the image in the accumulation buffer.
    image: (u32, u32),
    /// Size of the preview, and whether it shows the current view.
    preview: (u32, u32),
    preview_fresh: bool,
    /// Samples per pixel accumulated in the still image (complete passes).
    passes: u32,
    /// First row of the current pass still to trace.
    row: u32,
    /// When the still image was last restarted, and how long its last full
    /// refinement took (to the submission of its last pass).
    refine_started: Instant,
    refine_seconds: Option<f64>,
    /// Smoothed time per traced pixel of still frames (0: not measured yet).
    ms_per_pixel: f64,
    /// Rows a still frame can trace within [`STILL_BUDGET_MS`], as measured
    /// (0: not measured yet).
    band_rows: u32,
    restart: bool,
    last_change: Option<Instant>,
    last_update: Instant,
    moving_scale: u32,
    /// The window system says the window cannot be seen.
    occluded: bool,
    /// The surface said so: no frames before this.
    retry_at: Option<Instant>,
    /// A zero-size window.
    minimized: bool,
    /// The window manager says the window is minimised (checked every
    /// [`STATE_CHECK_INTERVAL`]).
    wm_minimized: bool,
    next_state_check: Instant,
    presented: u32,
    opened: Instant,
    /// When the previous frame of an uninterrupted stream was made, and
    /// its kind.
    last_frame: Option<(Instant, FrameKind)>,
    still: KindStats,
    moving: KindStats,
    idle: KindStats,
    /// Smoothed frame time and primary rays per second, for the title bar.
    frame_ms: f64,
    mrays: f64,
    title_at: Instant,
    /// A frame was made since the title was last set.
    title_stale: bool,
    reload_error: Option<String>,
    /// A reload is being prepared on the worker thread.
    reloading: bool,
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

/// A scene ready for the device: its tree (over all objects; brute force
/// only changes a flag the shader reads) and its GPU arrays. All CPU work,
/// so reloads make it on a worker thread.
struct PreparedScene {
    scene: Scene,
    tree: KdTree,
    arrays: SceneArrays,
}

impl PreparedScene {
    fn load(path: &Path, seen: &mut dyn FnMut(&Path)) -> Result<Self> {
        let scene = crate::scene::load_scene_observed(path, seen)?;
        let prims = Primitives::from_scene(&scene);
        let tree = KdTree {
            bounds: prims.scene_bounds(),
            ..KdTree::for_primitives(&prims)
        };
        let arrays = SceneArrays::new(&scene, &prims, &tree);
        Ok(PreparedScene {
            scene,
            tree,
            arrays,
        })
    }
}

fn bounds(tree: &KdTree) -> Bounds {
    Bounds {
        min: tree.bounds.min.as_dvec3(),
        max: tree.bounds.max.as_dvec3(),
    }
}

fn window_samples(options: &WindowOptions, scene: &Scene) -> u32 {
    options
        .samples
        .unwrap_or_else(|| scene.render.samples.max(DEFAULT_WINDOW_SAMPLES))
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
        let PreparedScene {
            scene,
            tree,
            arrays,
        } = prepared;
        let attributes = Window::default_attributes()
            .with_title(format!("{name} - kdray"))
            .with_inner_size(window_size(options, &scene));
        let window = Arc::new(
            event_loop
                .create_window(attributes)
                .map_err(|e| Error::Gpu(format!("cannot open a window: {e}")))?,
        );
        let (surface, ctx) = open_gpu(display, &window)?;
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
        let buffers = SceneBuffers::upload(&ctx, &arrays)?;
        drop(arrays);
        let max_pixels = Viewer::max_pixels(&ctx);
        let pixels = (config.width as u64 * config.height as u64).min(max_pixels);
        let viewer = Viewer::new(&ctx, &buffers, view_format, pixels)?;
        let controller =
            CameraController::new(scene.camera, bounds(&tree), config.width, config.height);
        let now = Instant::now();
        Ok(Session {
            window,
            surface,
            view_format,
            ctx,
            viewer,
            file_max_depth: scene.render.max_depth,
            max_depth: scene.render.max_depth,
            samples: window_samples(options, &scene),
            scene,
            tree,
            buffers,
            controller,
            accel: options.accel,
            max_pixels,
            image: (0, 0),
            preview: (0, 0),
            preview_fresh: false,
            passes: 0,
            row: 0,
            refine_started: now,
            refine_seconds: None,
            ms_per_pixel: 0.0,
            band_rows: 0,
            restart: true,
            last_change: None,
            last_update: now,
            moving_scale: 2,
            occluded: false,
            retry_at: None,
            wm_minimized: false,
            next_state_check: now,
            minimized: size.width == 0 || size.height == 0,
            presented: 0,
            opened: now,
            last_frame: None,
            still: KindStats::default(),
            moving: KindStats::default(),
            idle: KindStats::default(),
            frame_ms: 0.0,
            mrays: 0.0,
            title_at: now,
            title_stale: false,
            reload_error: None,
            reloading: false,
            config,
        })
    }

    /// Shows `prepared` from now on (a reload).
    fn set_scene(&mut self, prepared: PreparedScene, options: &WindowOptions) -> Result<()> {
        let PreparedScene {
            scene,
            tree,
            arrays,
        } = prepared;
        let buffers = SceneBuffers::upload(&self.ctx, &arrays)?;
        self.viewer.set_scene(&self.ctx, &buffers)?;
        self.controller.set_scene(scene.camera, bounds(&tree));
        if scene.render.max_depth != self.file_max_depth {
            self.file_max_depth = scene.render.max_depth;
            self.max_depth = scene.render.max_depth;
        }
        self.samples = window_samples(options, &scene);
        self.scene = scene;
        self.tree = tree;
        self.buffers = buffers;
        self.invalidate();
        Ok(())
    }

    /// Something that changes the image (not the camera's motion):
    /// refinement restarts, after one preview frame.
    fn invalidate(&mut self) {
        self.restart = true;
        self.preview_fresh = false;
    }

    fn camera_moved(&mut self, now: Instant) {
        if !self.is_moving(now) && self.ms_per_pixel > 0.0 {
            // Starting to move: the resolution divisor that the still
            // frames' speed predicts fits the moving budget.
            let pixels = self.config.width as f64 * self.config.height as f64;
            let s = (pixels * self.ms_per_pixel / MOVING_BUDGET_MS)
                .sqrt()
                .ceil();
            self.moving_scale = (s as u32).clamp(1, MAX_MOVING_SCALE);
        }
        self.last_change = Some(now);
        self.invalidate();
    }

    fn is_moving(&self, now: Instant) -> bool {
        self.last_change
            .is_some_and(|t| now.duration_since(t) < SETTLE)
    }

    fn resize(&mut self, size: PhysicalSize<u32>) -> Result<()> {
        self.minimized = size.width == 0 || size.height == 0;
        if self.minimized || (size.width, size.height) == (self.config.width, self.config.height) {
            return Ok(());
        }
        self.config.width = size.width;
        self.config.height = size.height;
        self.surface.configure(&self.ctx.device, &self.config);
        let (iw, ih) = self.still_image(size.width, size.height);
        self.viewer
            .reserve(&self.ctx, &self.buffers, iw as u64 * ih as u64)?;
        self.invalidate();
        Ok(())
    }

    /// Whether the event loop should ask for another frame now.
    fn wants_frame(&mut self, now: Instant, auto_orbit: f64, frames: Option<u32>) -> bool {
        if now >= self.next_state_check {
            // A round trip to the window system: not every frame.
            self.next_state_check = now + STATE_CHECK_INTERVAL;
            self.wm_minimized = self.window.is_minimized() == Some(true);
        }
        if self.minimized || self.wm_minimized {
            return false;
        }
        if self.occluded || self.retry_at.is_some_and(|t| now < t) {
            return false;
        }
        let refining = self.restart || self.passes < self.samples;
        let camera = self.is_moving(now) || self.controller.is_flying() || auto_orbit != 0.0;
        let counted = frames.is_some_and(|n| self.presented < n);
        refining || camera || counted
    }

    /// The shader's parameters for an image of `iw` x `ih` pixels shown in
    /// the `w` x `h` window, sample `index` of a k x k grid.
    fn params(
        &mut self,
        (iw, ih): (u32, u32),
        (w, h): (u32, u32),
        k: u32,
        index: u32,
    ) -> FrameParams {
        self.scene.camera = self.controller.camera();
        self.scene.render.width = iw;
        self.scene.render.height = ih;
        self.scene.render.max_depth = self.max_depth;
        let mut p = frame_params(&self.scene, &self.tree, &self.buffers, self.accel);
        p.aspect = (w as f64 / h as f64) as f32;
        p.samples_per_axis = k;
        p.sample_index = index;
        p.tile_origin = [0, 0];
        p.tile_size = [iw, ih];
        p
    }

    /// The still image's size: the window's, or smaller if the device
    /// cannot hold that many pixels in one buffer.
    fn still_image(&self, w: u32, h: u32) -> (u32, u32) {
        let mut s = 1;
        while (w.div_ceil(s) as u64) * (h.div_ceil(s) as u64) > self.max_pixels {
            s += 1;
        }
        (w.div_ceil(s), h.div_ceil(s))
    }

    /// Rows of the still image one frame traces: all of them, or a band
    /// (a multiple of the workgroup's height) sized so that the pass's
    /// frames share it evenly within [`STILL_BUDGET_MS`].
    fn rows_per_frame(&self, (iw, ih): (u32, u32)) -> u32 {
        let step = crate::gpu::shaders::TRACE_WORKGROUP.1;
        // Not measured yet: a first band of about 64k pixels.
        let band = if self.band_rows == 0 {
            65536 / iw.max(1)
        } else {
            self.band_rows
        };
        if band >= ih {
            return ih;
        }
        let frames = ih.div_ceil(band.max(1));
        ih.div_ceil(frames)
            .next_multiple_of(step)
            .clamp(step.min(ih), ih)
    }

    /// Renders and presents one frame; None if the surface had no image.
    fn frame(&mut self, now: Instant, auto_orbit: f64) -> Result<Option<FrameKind>> {
        if self.minimized {
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
        let (texture, suboptimal) = match self.surface.get_current_texture() {
            wgpu::CurrentSurfaceTexture::Success(t) => (t, false),
            wgpu::CurrentSurfaceTexture::Suboptimal(t) => (t, true),
            wgpu::CurrentSurfaceTexture::Timeout => return Ok(None),
            wgpu::CurrentSurfaceTexture::Occluded => {
                self.retry_at = Some(now + Duration::from_millis(250));
                return Ok(None);
            }
            wgpu::CurrentSurfaceTexture::Outdated | wgpu::CurrentSurfaceTexture::Lost => {
                let size = self.window.inner_size();
                self.resize(size)?;
                if !self.minimized {
                    self.surface.configure(&self.ctx.device, &self.config);
                }
                return Ok(None);
            }
            wgpu::CurrentSurfaceTexture::Validation => {
                self.ctx.check_health()?;
                return Err(Error::Gpu("the window's surface failed validation".into()));
            }
        };
        let (w, h) = (self.config.width, self.config.height);
        let k = crate::scene::RenderSettings {
            samples: self.samples,
            ..self.scene.render
        }
        .samples_per_axis();
        let (kind, work) = if self.is_moving(now) || (self.restart && !self.preview_fresh) {
            // The preview: while moving, and once after any other change
            // (so that rows the first sample pass has not reached yet show
            // the new view, not the old one).
            let s = self.moving_scale;
            let full = self.still_image(w, h);
            let preview = (full.0.div_ceil(s), full.1.div_ceil(s));
            let pass = self.params(preview, (w, h), 1, 0);
            self.preview = preview;
            self.preview_fresh = true;
            self.restart = true;
            (
                FrameKind::Moving,
                FrameWork {
                    target: Target::Preview,
                    clear_pixels: Some(preview.0 as u64 * preview.1 as u64),
                    pass: Some(pass),
                    present: PresentParams {
                        image_size: [self.image.0, self.image.1],
                        target_size: [w, h],
                        preview_size: [preview.0, preview.1],
                        show_image: 0,
                        _pad: 0,
                    },
                },
            )
        } else {
            let image = self.still_image(w, h);
            let mut clear_pixels = None;
            if self.restart || self.image != image {
                self.restart = false;
                self.image = image;
                self.passes = 0;
                self.row = 0;
                self.refine_started = now;
                clear_pixels = Some(image.0 as u64 * image.1 as u64);
            }
            let pass = (self.passes < k * k).then(|| {
                let y = self.row;
                let rows = self.rows_per_frame(image).min(image.1 - y);
                let mut p = self.params(image, (w, h), k, self.passes);
                p.tile_origin = [0, y];
                p.tile_size = [image.0, rows];
                self.row += rows;
                if self.row >= image.1 {
                    self.row = 0;
                    self.passes += 1;
                    if self.passes == k * k {
                        self.refine_seconds =
                            Some(now.duration_since(self.refine_started).as_secs_f64());
                    }
                }
                p
            });
            let kind = if pass.is_some() {
                FrameKind::Still
            } else {
                FrameKind::Idle
            };
            (
                kind,
                FrameWork {
                    target: Target::Image,
                    clear_pixels,
                    pass,
                    present: PresentParams {
                        image_size: [image.0, image.1],
                        target_size: [w, h],
                        preview_size: [self.preview.0, self.preview.1],
                        show_image: 1,
                        _pad: 0,
                    },
                },
            )
        };
        let view = texture.texture.create_view(&wgpu::TextureViewDescriptor {
            format: Some(self.view_format),
            ..Default::default()
        });
        let mut encoder = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.viewer.encode(&self.ctx, &mut encoder, &view, &work);
        self.ctx.queue.submit([encoder.finish()]);
        self.window.pre_present_notify();
        self.ctx.queue.present(texture);
        if suboptimal {
            self.surface.configure(&self.ctx.device, &self.config);
        }
        self.ctx.check_health()?;
        self.presented += 1;
        let rays = work
            .pass
            .map_or(0, |p| p.tile_size[0] as u64 * p.tile_size[1] as u64);
        self.record(now, kind, rays);
        Ok(Some(kind))
    }

    /// Frame figures: the interval since the previous frame is this frame's
    /// time (frames are paced by the swapchain, so in a steady stream it is
    /// the GPU's time per frame).
    fn record(&mut self, now: Instant, kind: FrameKind, rays: u64) {
        if let Some((before, previous)) = self.last_frame {
            let seconds = now.duration_since(before).as_secs_f64();
            // Estimates learn from a stream of frames of one kind only.
            let steady = previous == kind;
            let stats = match kind {
                FrameKind::Still => &mut self.still,
                FrameKind::Moving => &mut self.moving,
                FrameKind::Idle => &mut self.idle,
            };
            stats.frames += 1;
            stats.seconds += seconds;
            stats.primary_rays += rays;
            let ms = seconds * 1e3;
            stats.longest_ms = stats.longest_ms.max(ms);
            let mrays = rays as f64 / seconds.max(1e-9) * 1e-6;
            let a = if self.frame_ms == 0.0 { 1.0 } else { 0.2 };
            self.frame_ms += a * (ms - self.frame_ms);
            if kind != FrameKind::Idle {
                self.mrays += a * (mrays - self.mrays);
            }
            if steady && kind == FrameKind::Still && rays > 0 {
                let per_pixel = ms / rays as f64;
                let b = if self.ms_per_pixel == 0.0 { 1.0 } else { 0.3 };
                self.ms_per_pixel += b * (per_pixel - self.ms_per_pixel);
                // Band height: scale the rows just traced toward the budget
                // (frame overheads included), at most doubling or halving.
                let rows = (rays / self.image.0.max(1) as u64) as f64;
                let target = rows * STILL_BUDGET_MS / ms.max(1e-3);
                self.band_rows = target.clamp(rows * 0.5, rows * 2.0).max(1.0) as u32;
            }
            if steady && kind == FrameKind::Moving {
                // Coarser when over budget; finer when the finer image would
                // still fit in it (pixels grow as the square of 1/s).
                let s = self.moving_scale as f64;
                if ms > 1.3 * MOVING_BUDGET_MS && self.moving_scale < MAX_MOVING_SCALE {
                    self.moving_scale += 1;
                } else if self.moving_scale > 1
                    && ms * (s / (s - 1.0)).powi(2) < 0.8 * MOVING_BUDGET_MS
                {
                    self.moving_scale -= 1;
                }
            }
        }
        self.last_frame = Some((now, kind));
    }

    fn update_title(&mut self, name: &str, force: bool) {
        let now = Instant::now();
        if !force && now < self.title_at {
            self.title_stale = true;
            return;
        }
        self.title_at = now + TITLE_INTERVAL;
        self.title_stale = false;
        let progress = if self.is_moving(now) {
            format!("moving, 1/{} resolution", self.moving_scale)
        } else {
            format!("{}/{} spp", self.passes, self.samples)
        };
        let accel = match self.accel {
            Accel::Kdtree => "kdtree",
            Accel::Brute => "brute",
        };
        let mut title = format!(
            "{name} - {progress} - {:.1} ms - {:.2} Mrays/s - {accel} - depth {}",
            self.frame_ms, self.mrays, self.max_depth
        );
        if self.reloading {
            title.push_str(" - reloading");
        }
        if let Some(e) = &self.reload_error {
            title.push_str(" - RELOAD FAILED: ");
            title.push_str(e);
        }
        self.window.set_title(&title);
    }

    fn save_screenshot(&self, path: &Path) -> Result<()> {
        let rgb = self
            .viewer
            .capture(&self.ctx, self.config.width, self.config.height)?;
        crate::output::write_png_atomic(path, self.config.width, self.config.height, &rgb)
    }

    /// The frame figures: one line on stderr, and with `--stats` one JSON
    /// object on stdout.
    fn report(&self, options: &WindowOptions, name: &str) -> Result<()> {
        if self.presented == 0 {
            return Ok(());
        }
        let seconds = self.opened.elapsed().as_secs_f64();
        let mut line = format!("kdray: {name}: {} frames in {seconds:.1} s", self.presented);
        for (label, k) in [("still", &self.still), ("moving", &self.moving)] {
            if k.frames > 0 {
                line.push_str(&format!(
                    "; {label}: {} frames at {:.1} fps ({:.1} ms, {:.2} Mrays/s)",
                    k.frames,
                    k.fps(),
                    k.ms(),
                    k.mrays()
                ));
            }
        }
        if let Some(t) = self.refine_seconds {
            line.push_str(&format!("; {} samples per pixel in {t:.1} s", self.samples));
        }
        eprintln!("{line}");
        if options.stats {
            let stats = WindowStats {
                adapter: self.ctx.info.name.clone(),
                backend: format!("{:?}", self.ctx.info.backend),
                width: self.config.width,
                height: self.config.height,
                samples: self.samples,
                frames: self.presented,
                seconds,
                still_frames: self.still.frames,
                still_fps: self.still.fps(),
                still_ms: self.still.ms(),
                still_mrays_per_s: self.still.mrays(),
                still_longest_ms: self.still.longest_ms,
                moving_frames: self.moving.frames,
                moving_fps: self.moving.fps(),
                moving_ms: self.moving.ms(),
                moving_mrays_per_s: self.moving.mrays(),
                moving_longest_ms: self.moving.longest_ms,
                moving_scale: self.moving_scale,
                idle_frames: self.idle.frames,
                refine_seconds: self.refine_seconds,
            };
            println!(
                "{}",
                serde_json::to_string(&stats).map_err(|e| Error::Output(e.to_string()))?
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;
    use glam::DVec3;
    use winit::dpi::PhysicalPosition;
    use winit::event::DeviceId;

    fn controller() -> CameraController {
        let home = Camera {
            position: DVec3::new(0.0, 0.0, 1.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 90.0,
        };
        let bounds = Bounds {
            min: DVec3::splat(-1.0),
            max: DVec3::splat(1.0),
        };
        CameraController::new(home, bounds, 200, 100)
    }

    /// Feeds winit events through the event loop's mapping to the controller.
    fn feed(c: &mut CameraController, events: &[WindowEvent]) -> bool {
        let mut changed = false;
        for e in events {
            if let Some(input) = controller_input(e) {
                changed |= c.handle(input);
            }
        }
        changed
    }

    fn moved(x: f64, y: f64) -> WindowEvent {
        WindowEvent::CursorMoved {
            device_id: DeviceId::dummy(),
            position: PhysicalPosition::new(x, y),
        }
    }

    fn button(button: MouseButton, pressed: bool) -> WindowEvent {
        WindowEvent::MouseInput {
            device_id: DeviceId::dummy(),
            state: if pressed {
                ElementState::Pressed
            } else {
                ElementState::Released
            },
            button,
        }
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    #[test]
    fn winit_mouse_events_orbit_pan_and_zoom() {
        let mut c = controller();
        let left_drag = [
            moved(100.0, 50.0),
            button(MouseButton::Left, true),
            moved(150.0, 50.0),
            button(MouseButton::Left, false),
        ];
        assert!(feed(&mut c, &left_drag));
        assert!(close(c.camera().position, DVec3::new(1.0, 0.0, 0.0)));

        let mut c = controller();
        let right_drag = [
            moved(100.0, 50.0),
            button(MouseButton::Right, true),
            moved(150.0, 50.0),
            button(MouseButton::Right, false),
            // Released: moving does nothing.
            moved(10.0, 10.0),
        ];
        assert!(feed(&mut c, &right_drag));
        assert!(close(c.camera().position, DVec3::new(-1.0, 0.0, 1.0)));

        let mut c = controller();
        let wheel = WindowEvent::MouseWheel {
            device_id: DeviceId::dummy(),
            delta: MouseScrollDelta::LineDelta(0.0, 1.0),
            phase: winit::event::TouchPhase::Moved,
        };
        assert!(feed(&mut c, &[wheel]));
        assert!(close(c.camera().position, DVec3::new(0.0, 0.0, 0.9)));

        // A resize changes the orbit's pixels-per-turn.
        let mut c = controller();
        let events = [
            WindowEvent::Resized(PhysicalSize::new(400, 200)),
            moved(0.0, 0.0),
            button(MouseButton::Left, true),
            moved(100.0, 0.0),
        ];
        assert!(feed(&mut c, &events));
        assert!(close(c.camera().position, DVec3::new(1.0, 0.0, 0.0)));
        // Losing focus releases the button.
        assert!(!feed(
            &mut c,
            &[WindowEvent::Focused(false), moved(300.0, 0.0)]
        ));
    }

    #[test]
    fn keys_map_to_actions() {
        let ch = |s: &str| Key::Character(s.into());
        let none = PhysicalKey::Code(KeyCode::F13);
        let cases = [
            (
                PhysicalKey::Code(KeyCode::KeyW),
                ch("z"),
                Some(Action::Fly(ControlKey::Forward)),
            ),
            (
                PhysicalKey::Code(KeyCode::KeyA),
                ch("q"),
                Some(Action::Fly(ControlKey::Left)),
            ),
            (
                PhysicalKey::Code(KeyCode::KeyQ),
                ch("a"),
                Some(Action::Fly(ControlKey::Down)),
            ),
            (
                PhysicalKey::Code(KeyCode::KeyE),
                ch("e"),
                Some(Action::Fly(ControlKey::Up)),
            ),
            (none, ch("F"), Some(Action::Camera(ControlKey::FrameAll))),
            (none, ch("r"), Some(Action::Camera(ControlKey::Reset))),
            (none, ch("p"), Some(Action::Screenshot)),
            (none, ch("b"), Some(Action::ToggleAccel)),
            (none, ch("["), Some(Action::DepthDown)),
            (none, ch("]"), Some(Action::DepthUp)),
            (none, ch("h"), Some(Action::Help)),
            (none, Key::Named(NamedKey::Escape), Some(Action::Quit)),
            (none, ch("x"), None),
        ];
        for (physical, logical, action) in cases {
            assert_eq!(key_action(physical, &logical), action, "{logical:?}");
        }
    }
}
