//! Input events in, camera out: the window's camera controls, free of winit
//! and wgpu so that tests drive them through the same path as the event loop.
//!
//! The camera orbits a target point (the scene camera's `look_at` at first)
//! around the scene camera's `up` axis, which stays the world's up.
//! Conventions ("grab the scene"): dragging right with the left button turns
//! the scene right (the camera moves left around the target), dragging down
//! tilts it down (the camera rises); a right- or middle-drag moves the scene
//! with the cursor, exactly at the target's depth; each wheel line up brings
//! the camera [`ZOOM_PER_LINE`] of the way nearer the target; WASD fly along
//! the view direction and the camera's right axis, Q and E down and up, at
//! one target distance per second.

use std::f64::consts::PI;

use glam::{DQuat, DVec2, DVec3};

use crate::scene::Camera;

/// Each wheel line (or 40 pixels of a touchpad scroll) multiplies the
/// distance to the target by this (zooming in for positive lines).
pub const ZOOM_PER_LINE: f64 = 0.9;
/// Touchpad pixels per wheel line.
pub const PIXELS_PER_LINE: f64 = 40.0;
/// How close to straight up or down the camera may orbit (radians).
pub const POLE_MARGIN: f64 = 0.5 * PI / 180.0;
/// Longest time step of one fly update, so a stalled frame does not jump.
pub const MAX_FLY_STEP_S: f64 = 0.1;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Button {
    Left,
    Right,
    Middle,
}

/// Keys that move the camera (the window handles the others itself).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ControlKey {
    /// W: forward.
    Forward,
    /// S: backward.
    Backward,
    /// A: left.
    Left,
    /// D: right.
    Right,
    /// Q: down (along the world's up).
    Down,
    /// E: up.
    Up,
    /// F: frame the whole scene.
    FrameAll,
    /// R: back to the scene's camera.
    Reset,
}

/// One input event, in physical pixels (origin top left, y down).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Input {
    Resized {
        width: u32,
        height: u32,
    },
    CursorMoved {
        x: f64,
        y: f64,
    },
    CursorLeft,
    Button {
        button: Button,
        pressed: bool,
    },
    /// Wheel lines, positive away from the user (zoom in).
    WheelLines(f64),
    /// Touchpad scroll in pixels, positive away from the user.
    WheelPixels(f64),
    Key {
        key: ControlKey,
        pressed: bool,
    },
    /// The window lost focus: every button and key counts as released.
    FocusLost,
}

/// The scene's box, for framing and scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bounds {
    pub min: DVec3,
    pub max: DVec3,
}

impl Bounds {
    fn is_empty(&self) -> bool {
        !(self.min.cmple(self.max).all() && self.min.is_finite() && self.max.is_finite())
    }
}

#[derive(Debug, Clone)]
pub struct CameraController {
    position: DVec3,
    target: DVec3,
    /// Unit world up (the scene camera's up).
    up: DVec3,
    /// The scene camera's up as given, which the camera keeps (so an
    /// unmoved camera is exactly the scene's).
    up_given: DVec3,
    vfov_degrees: f64,
    home: Camera,
    bounds: Bounds,
    viewport: (u32, u32),
    cursor: Option<DVec2>,
    left: bool,
    right: bool,
    middle: bool,
    /// Held fly keys: forward, backward, left, right, down, up.
    fly: [bool; 6],
}

impl CameraController {
    /// A controller showing `home` (the scene's camera) in a viewport of
    /// `width` x `height` physical pixels.
    pub fn new(home: Camera, bounds: Bounds, width: u32, height: u32) -> Self {
        let mut c = CameraController {
            position: home.position,
            target: home.look_at,
            up: DVec3::Y,
            up_given: DVec3::Y,
            vfov_degrees: home.vfov_degrees,
            home,
            bounds,
            viewport: (width.max(1), height.max(1)),
            cursor: None,
            left: false,
            right: false,
            middle: false,
            fly: [false; 6],
        };
        c.reset();
        c
    }

    /// The camera to render.
    pub fn camera(&self) -> Camera {
        Camera {
            position: self.position,
            look_at: self.target,
            up: self.up_given,
            vfov_degrees: self.vfov_degrees,
        }
    }

    pub fn target(&self) -> DVec3 {
        self.target
    }

    /// A new scene (after a reload): new bounds; a new home camera, which
    /// the view jumps to only if it differs from the old one.
    pub fn set_scene(&mut self, home: Camera, bounds: Bounds) {
        self.bounds = bounds;
        if home != self.home {
            self.home = home;
            self.reset();
        }
    }

    /// Whether a fly key is held (the camera moves every frame).
    pub fn is_flying(&self) -> bool {
        self.fly.iter().any(|&k| k)
    }

    /// Applies one event; true if the camera changed.
    pub fn handle(&mut self, input: Input) -> bool {
        match input {
            Input::Resized { width, height } => {
                self.viewport = (width.max(1), height.max(1));
                false
            }
            Input::CursorMoved { x, y } => {
                let now = DVec2::new(x, y);
                let before = self.cursor.replace(now);
                let Some(before) = before else { return false };
                let d = now - before;
                if d == DVec2::ZERO {
                    false
                } else if self.left {
                    self.orbit(d.x, d.y)
                } else if self.right || self.middle {
                    self.pan(d.x, d.y)
                } else {
                    false
                }
            }
            Input::CursorLeft => {
                self.cursor = None;
                false
            }
            Input::Button { button, pressed } => {
                match button {
                    Button::Left => self.left = pressed,
                    Button::Right => self.right = pressed,
                    Button::Middle => self.middle = pressed,
                }
                false
            }
            Input::WheelLines(lines) => self.zoom(lines),
            Input::WheelPixels(pixels) => self.zoom(pixels / PIXELS_PER_LINE),
            Input::Key { key, pressed } => {
                let slot = match key {
                    ControlKey::Forward => 0,
                    ControlKey::Backward => 1,
                    ControlKey::Left => 2,
                    ControlKey::Right => 3,
                    ControlKey::Down => 4,
                    ControlKey::Up => 5,
                    ControlKey::FrameAll => return pressed && self.frame_all(),
                    ControlKey::Reset => return pressed && self.reset(),
                };
                self.fly[slot] = pressed;
                false
            }
            Input::FocusLost => {
                self.left = false;
                self.right = false;
                self.middle = false;
                self.fly = [false; 6];
                false
            }
        }
    }

    /// Advances the fly keys by `dt` seconds (at most [`MAX_FLY_STEP_S`]);
    /// true if the camera moved.
    pub fn update(&mut self, dt: f64) -> bool {
        if !self.is_flying() {
            return false;
        }
        let axis = |plus: usize, minus: usize| {
            self.fly[plus] as i32 as f64 - self.fly[minus] as i32 as f64
        };
        let (forward, right, _) = self.basis();
        let step = forward * axis(0, 1) + right * axis(3, 2) + self.up * axis(5, 4);
        if step == DVec3::ZERO {
            return false;
        }
        let speed = self.distance();
        let delta = step * speed * dt.clamp(0.0, MAX_FLY_STEP_S);
        self.position += delta;
        self.target += delta;
        delta != DVec3::ZERO
    }

    /// Turns the camera around the target by a drag of (dx, dy) pixels: a
    /// drag across the viewport's height is half a turn.
    pub fn orbit(&mut self, dx: f64, dy: f64) -> bool {
        let per_pixel = PI / self.viewport.1 as f64;
        let offset = self.position - self.target;
        let distance = offset.length();
        if distance == 0.0 {
            return false;
        }
        // Around the up axis: dragging right turns the scene right.
        let offset = DQuat::from_axis_angle(self.up, dx * per_pixel) * offset;
        // Then the polar angle from up, kept off the poles.
        let dir = offset / distance;
        let polar = dir.dot(self.up).clamp(-1.0, 1.0).acos();
        let new_polar = (polar - dy * per_pixel).clamp(POLE_MARGIN, PI - POLE_MARGIN);
        let horizontal = dir - self.up * dir.dot(self.up);
        let horizontal = if horizontal.length_squared() > 1e-24 {
            horizontal.normalize()
        } else {
            self.up.any_orthonormal_vector()
        };
        let new_dir = horizontal * new_polar.sin() + self.up * new_polar.cos();
        let position = self.target + new_dir * distance;
        let changed = position != self.position;
        self.position = position;
        changed
    }

    /// Moves camera and target so the scene follows a drag of (dx, dy)
    /// pixels at the target's depth.
    pub fn pan(&mut self, dx: f64, dy: f64) -> bool {
        let (_, right, cam_up) = self.basis();
        let per_pixel = self.world_per_pixel();
        let delta = -right * dx * per_pixel + cam_up * dy * per_pixel;
        self.position += delta;
        self.target += delta;
        delta != DVec3::ZERO
    }

    /// Wheel: `lines` > 0 moves the camera toward the target.
    pub fn zoom(&mut self, lines: f64) -> bool {
        let offset = self.position - self.target;
        let distance = offset.length();
        if distance == 0.0 || lines == 0.0 {
            return false;
        }
        let new_distance = (distance * ZOOM_PER_LINE.powf(lines)).max(self.min_distance());
        self.position = self.target + offset * (new_distance / distance);
        new_distance != distance
    }

    /// Keeps the view direction and moves the camera so the scene's
    /// bounding sphere fits the view; the target becomes the scene's centre.
    pub fn frame_all(&mut self) -> bool {
        if self.bounds.is_empty() {
            return false;
        }
        let centre = (self.bounds.min + self.bounds.max) * 0.5;
        let radius = ((self.bounds.max - self.bounds.min) * 0.5).length();
        let (forward, _, _) = self.basis();
        let half_v = (self.vfov_degrees.to_radians() * 0.5).min(PI * 0.5 - 1e-6);
        let aspect = self.viewport.0 as f64 / self.viewport.1 as f64;
        let half_h = (half_v.tan() * aspect).atan();
        let half = half_v.min(half_h);
        let distance = (radius / half.sin()).max(self.min_distance());
        self.target = centre;
        self.position = centre - forward * distance;
        true
    }

    /// Back to the scene's camera.
    pub fn reset(&mut self) -> bool {
        self.position = self.home.position;
        self.target = self.home.look_at;
        self.up = self.home.up.try_normalize().unwrap_or(DVec3::Y);
        self.up_given = self.home.up;
        self.vfov_degrees = self.home.vfov_degrees;
        true
    }

    fn distance(&self) -> f64 {
        (self.position - self.target).length()
    }

    /// Forward, right and the camera's up, as the shader builds them
    /// (from the controller's own up vector, which orbits keep level).
    fn basis(&self) -> (DVec3, DVec3, DVec3) {
        let b = Camera {
            up: self.up,
            ..self.camera()
        }
        .basis();
        (b.forward, b.right, b.up)
    }

    /// World units per pixel at the target's depth.
    fn world_per_pixel(&self) -> f64 {
        let half = (self.vfov_degrees.to_radians() * 0.5).tan();
        2.0 * self.distance() * half / self.viewport.1 as f64
    }

    fn min_distance(&self) -> f64 {
        let size = if self.bounds.is_empty() {
            1.0
        } else {
            (self.bounds.max - self.bounds.min).length()
        };
        1e-6 * size.max(1e-3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn home() -> Camera {
        Camera {
            position: DVec3::new(0.0, 0.0, 1.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 90.0,
        }
    }

    fn bounds() -> Bounds {
        Bounds {
            min: DVec3::splat(-1.0),
            max: DVec3::splat(1.0),
        }
    }

    /// A 200 x 100 viewport: half a turn per 100 pixels of orbit drag,
    /// 0.02 world units per pixel of pan at distance 1 (vfov 90).
    fn controller() -> CameraController {
        CameraController::new(home(), bounds(), 200, 100)
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    fn drag(c: &mut CameraController, button: Button, from: (f64, f64), to: (f64, f64)) -> bool {
        c.handle(Input::CursorMoved {
            x: from.0,
            y: from.1,
        });
        c.handle(Input::Button {
            button,
            pressed: true,
        });
        let changed = c.handle(Input::CursorMoved { x: to.0, y: to.1 });
        c.handle(Input::Button {
            button,
            pressed: false,
        });
        changed
    }

    #[test]
    fn starts_at_the_scene_camera() {
        assert_eq!(controller().camera(), home());
    }

    #[test]
    fn left_drag_right_orbits_a_quarter_turn() {
        let mut c = controller();
        // 50 pixels of a 100-pixel-high viewport: 90 degrees around +y.
        assert!(drag(&mut c, Button::Left, (100.0, 50.0), (150.0, 50.0)));
        let cam = c.camera();
        assert!(close(cam.position, DVec3::new(1.0, 0.0, 0.0)), "{cam:?}");
        assert_eq!(cam.look_at, DVec3::ZERO);
        assert_eq!(cam.up, DVec3::Y);
    }

    #[test]
    fn left_drag_down_raises_the_camera() {
        let mut c = controller();
        // 25 pixels: 45 degrees up from the horizon, distance kept.
        assert!(drag(&mut c, Button::Left, (100.0, 50.0), (100.0, 75.0)));
        let h = 0.5f64.sqrt();
        assert!(
            close(c.camera().position, DVec3::new(0.0, h, h)),
            "{:?}",
            c.camera()
        );
        // Far past the pole: stops half a degree short of straight down.
        drag(&mut c, Button::Left, (100.0, 0.0), (100.0, 1000.0));
        let p = c.camera().position;
        assert!((p.length() - 1.0).abs() < 1e-12);
        assert!((p.y - POLE_MARGIN.cos()).abs() < 1e-12, "{p:?}");
    }

    #[test]
    fn moving_without_a_button_does_nothing() {
        let mut c = controller();
        c.handle(Input::CursorMoved { x: 10.0, y: 10.0 });
        assert!(!c.handle(Input::CursorMoved { x: 90.0, y: 60.0 }));
        assert_eq!(c.camera(), home());
    }

    #[test]
    fn right_and_middle_drags_pan_with_the_cursor() {
        let mut c = controller();
        // 50 pixels right at 0.02 units per pixel: the scene moves 1 right,
        // so the camera and target move 1 left.
        assert!(drag(&mut c, Button::Right, (100.0, 50.0), (150.0, 50.0)));
        assert!(close(c.camera().position, DVec3::new(-1.0, 0.0, 1.0)));
        assert!(close(c.camera().look_at, DVec3::new(-1.0, 0.0, 0.0)));
        // 25 pixels down with the middle button: camera and target rise 0.5.
        assert!(drag(&mut c, Button::Middle, (100.0, 50.0), (100.0, 75.0)));
        assert!(close(c.camera().position, DVec3::new(-1.0, 0.5, 1.0)));
        assert!(close(c.camera().look_at, DVec3::new(-1.0, 0.5, 0.0)));
    }

    #[test]
    fn wheel_zooms_toward_the_target() {
        let mut c = controller();
        assert!(c.handle(Input::WheelLines(1.0)));
        assert!(close(c.camera().position, DVec3::new(0.0, 0.0, 0.9)));
        assert!(c.handle(Input::WheelLines(-2.0)));
        assert!(close(c.camera().position, DVec3::new(0.0, 0.0, 0.9 / 0.81)));
        // 80 touchpad pixels are two lines.
        assert!(c.handle(Input::WheelPixels(80.0)));
        assert!(close(c.camera().position, DVec3::new(0.0, 0.0, 0.9)));
        assert_eq!(c.camera().look_at, DVec3::ZERO);
    }

    #[test]
    fn f_frames_the_whole_scene() {
        let mut c = controller();
        c.handle(Input::WheelLines(5.0));
        assert!(c.handle(Input::Key {
            key: ControlKey::FrameAll,
            pressed: true
        }));
        // Box [-1, 1]^3: bounding sphere radius sqrt(3). The vertical fov (90)
        // is the narrower one in a 2:1 viewport, so distance = r / sin(45).
        let d = 3f64.sqrt() / (PI / 4.0).sin();
        assert!(
            close(c.camera().position, DVec3::new(0.0, 0.0, d)),
            "{:?}",
            c.camera()
        );
        assert_eq!(c.camera().look_at, DVec3::ZERO);
        // In a tall viewport the horizontal fov limits it.
        c.handle(Input::Resized {
            width: 100,
            height: 200,
        });
        c.frame_all();
        let half_h = (0.5f64).atan();
        let d = 3f64.sqrt() / half_h.sin();
        assert!(
            close(c.camera().position, DVec3::new(0.0, 0.0, d)),
            "{:?}",
            c.camera()
        );
    }

    #[test]
    fn frame_all_centres_an_offset_scene() {
        let mut c = CameraController::new(
            home(),
            Bounds {
                min: DVec3::new(9.0, -1.0, -1.0),
                max: DVec3::new(11.0, 1.0, 1.0),
            },
            200,
            100,
        );
        c.frame_all();
        let d = 3f64.sqrt() / (PI / 4.0).sin();
        assert!(close(c.camera().look_at, DVec3::new(10.0, 0.0, 0.0)));
        assert!(close(c.camera().position, DVec3::new(10.0, 0.0, d)));
    }

    #[test]
    fn r_resets_to_the_scene_camera() {
        let mut c = controller();
        drag(&mut c, Button::Left, (0.0, 0.0), (37.0, 11.0));
        c.handle(Input::WheelLines(3.0));
        assert_ne!(c.camera(), home());
        assert!(c.handle(Input::Key {
            key: ControlKey::Reset,
            pressed: true
        }));
        assert_eq!(c.camera(), home());
        // Key releases do nothing.
        assert!(!c.handle(Input::Key {
            key: ControlKey::Reset,
            pressed: false
        }));
    }

    #[test]
    fn wasd_qe_fly_one_target_distance_per_second() {
        let mut c = controller();
        c.handle(Input::Key {
            key: ControlKey::Forward,
            pressed: true,
        });
        assert!(c.is_flying());
        assert!(c.update(0.05));
        assert!(close(c.camera().position, DVec3::new(0.0, 0.0, 0.95)));
        assert!(close(c.camera().look_at, DVec3::new(0.0, 0.0, -0.05)));
        c.handle(Input::Key {
            key: ControlKey::Forward,
            pressed: false,
        });
        c.handle(Input::Key {
            key: ControlKey::Right,
            pressed: true,
        });
        c.handle(Input::Key {
            key: ControlKey::Up,
            pressed: true,
        });
        // A long stall moves at most MAX_FLY_STEP_S.
        assert!(c.update(5.0));
        assert!(close(c.camera().position, DVec3::new(0.1, 0.1, 0.95)));
        c.handle(Input::FocusLost);
        assert!(!c.is_flying());
        assert!(!c.update(0.05));
    }

    #[test]
    fn a_reload_moves_the_view_only_if_the_scene_camera_changed() {
        let mut c = controller();
        c.handle(Input::WheelLines(1.0));
        let moved = c.camera();
        c.set_scene(home(), bounds());
        assert_eq!(c.camera(), moved);
        let other = Camera {
            position: DVec3::new(0.0, 2.0, 5.0),
            ..home()
        };
        c.set_scene(other, bounds());
        assert_eq!(c.camera(), other);
    }
}
