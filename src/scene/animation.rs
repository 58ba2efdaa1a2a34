//! Animation: the validated `[animation]` table ([`Animation`] and its
//! [`CameraKey`]s) and the camera at each frame ([`CameraPath`],
//! [`Scene::camera_at`]). The math follows docs/scene-format.md's
//! "Animation" section formula for formula, so that another program can
//! compute the same cameras: each camera field has a track through the
//! scene's `[camera]` (at frame 0) and the keys that set that field; points
//! and the up vector follow a uniform Catmull-Rom spline, vfov a straight
//! line, and every field holds its last value after its last key; then the
//! orbit turns the position about the up axis through look_at.
//!
//! Angles are in degrees, as in the scene file; frames count from 0.

use glam::DVec3;

use super::normals::unit;
use super::{Camera, Scene};

/// Most frames an animation may have.
pub const MAX_FRAMES: u32 = 100_000;
/// Frames per second when the file gives none.
pub const DEFAULT_FPS: f64 = 24.0;

/// A scene's `[animation]`: what changes from frame to frame (the camera
/// only; the objects and lights stay put, so one k-d tree serves every frame).
#[derive(Debug, Clone, PartialEq)]
pub struct Animation {
    /// Number of frames, `1..=MAX_FRAMES`; the frames are `0..frames`.
    pub frames: u32,
    /// Frames per second, finite and > 0: for players and video files; the
    /// camera depends on the frame number only.
    pub fps: f64,
    /// Degrees the camera turns about its up axis through look_at over
    /// `frames` frames: `orbit_degrees * f / frames` at frame `f`, so that
    /// a 360-degree orbit's frame `frames` would be frame 0 again.
    pub orbit_degrees: f64,
    /// In strictly increasing frame order, every frame below `frames`; each
    /// sets at least one field.
    pub keys: Vec<CameraKey>,
}

/// One `[[animation.keys]]` entry: the camera fields it sets at its frame
/// (None: the field is interpolated there from the other keys that set it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraKey {
    pub frame: u32,
    pub position: Option<DVec3>,
    pub look_at: Option<DVec3>,
    pub up: Option<DVec3>,
    /// Degrees, in (0, 180).
    pub vfov_degrees: Option<f64>,
}

/// The values one camera field takes: `(frame, value)` in strictly
/// increasing frame order, the first at frame 0.
#[derive(Debug, Clone)]
struct Track<T>(Vec<(u32, T)>);

/// Where a frame lies on a track.
enum Place<T> {
    /// Between points `i` and `i + 1`, a fraction `t` in [0, 1) of the way.
    Between(usize, f64),
    /// At or after the last point: its value, held.
    Held(T),
}

impl<T: Copy> Track<T> {
    /// `start` at frame 0 (unless a key at frame 0 sets the field), then
    /// each key's value of the field, where it sets it.
    fn new(start: T, keys: &[CameraKey], field: impl Fn(&CameraKey) -> Option<T>) -> Self {
        let mut points = vec![(0, start)];
        for key in keys {
            if let Some(value) = field(key) {
                if key.frame == 0 {
                    points[0].1 = value;
                } else {
                    points.push((key.frame, value));
                }
            }
        }
        Track(points)
    }

    fn place(&self, frame: u32) -> Place<T> {
        // The last point at or before `frame` (the first is at frame 0).
        let i = self.0.partition_point(|&(f, _)| f <= frame).max(1) - 1;
        match self.0.get(i + 1) {
            None => Place::Held(self.0[i].1),
            Some(&(end, _)) => {
                let start = self.0[i].0;
                let t = (f64::from(frame) - f64::from(start)) / (f64::from(end) - f64::from(start));
                Place::Between(i, t)
            }
        }
    }

    fn value(&self, i: usize) -> T {
        self.0[i].1
    }
}

impl Track<DVec3> {
    /// Uniform Catmull-Rom through the points, the end points doubled.
    fn at(&self, frame: u32) -> DVec3 {
        match self.place(frame) {
            Place::Held(v) => v,
            Place::Between(i, t) => {
                let last = self.0.len() - 1;
                catmull_rom(
                    self.value(i.saturating_sub(1)),
                    self.value(i),
                    self.value(i + 1),
                    self.value((i + 2).min(last)),
                    t,
                )
            }
        }
    }
}

impl Track<f64> {
    /// Straight lines between the points.
    fn at(&self, frame: u32) -> f64 {
        match self.place(frame) {
            Place::Held(v) => v,
            Place::Between(i, t) => {
                let (a, b) = (self.value(i), self.value(i + 1));
                a + (b - a) * t
            }
        }
    }
}

/// The uniform Catmull-Rom segment from `p1` (t = 0) to `p2` (t = 1):
/// `0.5 * (2 p1 + (p2 - p0) t + (2 p0 - 5 p1 + 4 p2 - p3) t^2 + (-p0 + 3 p1 - 3 p2 + p3) t^3)`,
/// evaluated in Horner form; at t = 0 it is `p1` exactly.
fn catmull_rom(p0: DVec3, p1: DVec3, p2: DVec3, p3: DVec3, t: f64) -> DVec3 {
    let cubic = -p0 + 3.0 * p1 - 3.0 * p2 + p3;
    let square = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3;
    let linear = p2 - p0;
    0.5 * (((cubic * t + square) * t + linear) * t + 2.0 * p1)
}

/// `v` turned by `radians` about the unit axis `k`, counter-clockwise seen
/// from the tip of `k` (Rodrigues' formula).
fn rotate(v: DVec3, k: DVec3, radians: f64) -> DVec3 {
    let (sin, cos) = radians.sin_cos();
    v * cos + k.cross(v) * sin + k * k.dot(v) * (1.0 - cos)
}

/// The camera at every frame of a scene, made once ([`Scene::camera_path`])
/// and then asked frame by frame in O(log keys).
#[derive(Debug, Clone)]
pub struct CameraPath {
    position: Track<DVec3>,
    look_at: Track<DVec3>,
    up: Track<DVec3>,
    vfov_degrees: Track<f64>,
    /// Degrees of orbit and the frames they span; None: no orbit.
    orbit: Option<(f64, u32)>,
}

impl CameraPath {
    /// The path of `camera` (the scene's `[camera]`, frame 0's values) under
    /// `animation`, whose keys are in increasing frame order (as validated);
    /// without an animation every frame is `camera`.
    pub fn new(camera: &Camera, animation: Option<&Animation>) -> Self {
        let keys = animation.map_or(&[][..], |a| &a.keys[..]);
        CameraPath {
            position: Track::new(camera.position, keys, |k| k.position),
            look_at: Track::new(camera.look_at, keys, |k| k.look_at),
            up: Track::new(camera.up, keys, |k| k.up),
            vfov_degrees: Track::new(camera.vfov_degrees, keys, |k| k.vfov_degrees),
            orbit: animation
                .filter(|a| a.orbit_degrees != 0.0)
                .map(|a| (a.orbit_degrees, a.frames.max(1))),
        }
    }

    /// The camera at `frame`: the keys' interpolation, then the orbit.
    /// Frames past the animation's last follow the same formulas (every
    /// field held, the orbit going on).
    pub fn camera_at(&self, frame: u32) -> Camera {
        let mut camera = Camera {
            position: self.position.at(frame),
            look_at: self.look_at.at(frame),
            up: self.up.at(frame),
            vfov_degrees: self.vfov_degrees.at(frame),
        };
        if let Some((degrees, frames)) = self.orbit {
            let turn = degrees * f64::from(frame) / f64::from(frames);
            // At a turn of 0 the position is kept exactly (look_at + (position
            // - look_at) may differ from it in the last bit).
            if turn != 0.0 {
                // up / |up|, robust to huge up vectors; a validated frame's
                // up is never zero.
                let axis = unit(camera.up).unwrap_or(DVec3::ZERO);
                let offset = camera.position - camera.look_at;
                camera.position = camera.look_at + rotate(offset, axis, turn.to_radians());
            }
        }
        camera
    }
}

impl Scene {
    /// Number of frames: the animation's, or 1 for a still scene.
    pub fn frame_count(&self) -> u32 {
        self.animation.as_ref().map_or(1, |a| a.frames)
    }

    /// The camera of every frame, for asking about many frames.
    pub fn camera_path(&self) -> CameraPath {
        CameraPath::new(&self.camera, self.animation.as_ref())
    }

    /// The camera at `frame` (0-based): `self.camera` for a still scene, and
    /// at frame 0 of an animation without a key at frame 0. Builds the path
    /// anew (O(keys)); use [`Scene::camera_path`] for many frames.
    pub fn camera_at(&self, frame: u32) -> Camera {
        self.camera_path().camera_at(frame)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).abs().max_element() < 1e-12
    }

    /// The spline goes through its two middle points and, with the ends
    /// doubled along a straight line of evenly spaced points, stays on it.
    #[test]
    fn catmull_rom_passes_through_its_middle_points() {
        let p = [DVec3::ZERO, DVec3::X, DVec3::new(2.0, 1.0, 0.0), DVec3::Y];
        assert_eq!(catmull_rom(p[0], p[1], p[2], p[3], 0.0), p[1]);
        assert!(close(catmull_rom(p[0], p[1], p[2], p[3], 1.0), p[2]));
        let line = |x: f64| DVec3::new(x, 2.0 * x, -x);
        for t in [0.25, 0.5, 0.75] {
            let got = catmull_rom(line(0.0), line(1.0), line(2.0), line(3.0), t);
            assert!(close(got, line(1.0 + t)), "t = {t}: {got}");
        }
    }

    #[test]
    fn rotation_is_counter_clockwise_about_the_axis() {
        let got = rotate(DVec3::Z, DVec3::Y, 90f64.to_radians());
        assert!(close(got, DVec3::X), "{got}");
    }

    /// A track with a single point (no key sets the field) holds it.
    #[test]
    fn a_track_without_keys_holds_its_start() {
        let track = Track::new(3.0, &[], |k: &CameraKey| k.vfov_degrees);
        for frame in [0, 1, 1000] {
            assert_eq!(track.at(frame), 3.0);
        }
    }
}
