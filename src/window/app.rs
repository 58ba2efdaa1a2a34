//! The winit application behind `kdray render SCENE --window`: the event
//! loop, keys, reloads and signals. What is open while the window is (the
//! surface, the scene, the controls, one frame's work) is a
//! [`Session`](super::session::Session), in `session.rs`.

use std::time::Instant;

use winit::application::ApplicationHandler;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop, OwnedDisplayHandle};
use winit::window::WindowId;

use super::camera_controller::Input;
use super::input::{controller_input, key_action, Action, HELP};
use super::reload::{self, LatestJob, SceneWatcher, WatchList};
use super::session::{next_screenshot_path, Session};
use super::{signals, WindowOptions};
use crate::error::{Error, Result};
use crate::gpu::{Accel, PreparedScene};
use crate::scene::Integrator;

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
        WatchList::record(|seen| reload::load(&options.scene, &options.flags, seen));
    let watcher = SceneWatcher::new(files);
    let scene = scene?;
    if options.denoise == Some(true) && scene.scene.render.integrator != Integrator::Path {
        return Err(Error::Usage(
            "--denoise: the denoiser needs the path tracer (--integrator path or [render] integrator = \"path\")".into(),
        ));
    }
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
        let flags = self.options.flags.clone();
        // The mesh list may have changed: the job also lists what to watch.
        self.reloads
            .request(move || WatchList::record(|seen| reload::load(&path, &flags, seen)));
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
                        "kdray: saved {} ({} of {} samples per pixel{}{})",
                        path.display(),
                        session.refinement.passes(),
                        session.refinement.samples(),
                        session
                            .shown_denoised()
                            .map_or_else(String::new, |n| format!(", denoised at {n}")),
                        session
                            .denoising
                            .progress()
                            .map_or_else(String::new, |(_, p)| format!(", denoising {p}%"))
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
                session.reinspect();
                session.update_title(&self.name, true);
            }
            Action::CycleTraversal => {
                // Same picture, other work: start over so the frame times
                // and the heatmap are the new walk's.
                session.traversal = session.traversal.next();
                session.refinement.invalidate();
                session.reinspect();
                session.update_title(&self.name, true);
            }
            Action::CycleBuild => {
                // A new tree: prepared on the worker like a reload, shown
                // when ready (the title says "reloading" meanwhile).
                self.options.flags.build = self.options.flags.build.next();
                eprintln!("kdray: building the {} tree", self.options.flags.build);
                self.start_reload();
            }
            Action::ToggleHeatmap => {
                // The costs accumulate with the colours; refining again
                // makes the frames that show the other view.
                session.heatmap = !session.heatmap;
                session.refinement.invalidate();
                session.update_title(&self.name, true);
            }
            Action::ToggleDenoise => {
                session.toggle_denoise();
                session.update_title(&self.name, true);
            }
            Action::ToggleIntegrator => {
                session.toggle_integrator(&self.options);
                session.reinspect();
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
                session.reinspect();
                session.update_title(&self.name, true);
            }
            Action::TogglePlay => {
                if !session.playback.is_animated() {
                    eprintln!("kdray: the scene has no [animation] to play");
                }
                session.playback.toggle(Instant::now());
                session.update_title(&self.name, true);
            }
            Action::ToggleInspect => {
                session.toggle_inspect();
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
        // A click (no drag) inspects in inspection mode; a drag orbits.
        if let Some(at) = session.clicks.handle(input) {
            if session.inspect.on {
                session.inspect_click(at);
                session.update_title(&self.name, true);
            }
        }
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
