//! Animation: the validated `[animation]` table ([`Animation`], its
//! [`CameraKey`]s and [`LightKey`]s) and what each frame shows ([`Frame`]:
//! the camera and the lights, from [`FramePath`] or `Scene::frame`).
//! The math follows docs/scene-format.md's "Animation" section formula for
//! formula, so that another program can compute the same frames: each
//! camera field, and each keyed light's position and colour, has a track
//! through its frame-0 value (the scene's `[camera]`, the `[[lights]]`
//! entry) and the keys that set it; points and the up vector follow a
//! uniform Catmull-Rom spline, vfov and colours a straight line, and every
//! track holds its last value after its last key; then the orbit turns the
//! camera's position about the up axis through look_at (lights do not
//! orbit).
//!
//! Angles are in degrees, as in the scene file; frames count from 0.

use std::ops::{Add, Mul, Sub};

use glam::DVec3;

use super::camera::Camera;
use super::light::Light;
use super::normals::unit;

/// Most frames an animation may have.
pub const MAX_FRAMES: u32 = 100_000;
/// Frames per second when the file gives none.
pub const DEFAULT_FPS: f64 = 24.0;

/// A scene's `[animation]`: what changes from frame to frame (the camera
/// and the lights; the objects stay put, so one k-d tree serves every frame).
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
    /// In file order; the keys of each light in strictly increasing frame
    /// order, every frame below `frames`, every light an index into
    /// `Scene::lights`; each sets at least one field.
    pub light_keys: Vec<LightKey>,
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

/// One `[[animation.light_keys]]` entry: the fields of light `light` it
/// sets at its frame (None: interpolated there from that light's other keys).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightKey {
    pub frame: u32,
    /// Index into `Scene::lights`.
    pub light: u32,
    pub position: Option<DVec3>,
    /// A factor, components >= 0, on the light's ambient, diffuse and
    /// specular colours (1 at frame 0 unless a key there sets it).
    pub color: Option<DVec3>,
}

/// The values one camera or light field takes: `(frame, value)` in strictly
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
    /// each key's value of the field, where it sets it: `keys` gives
    /// `(frame, value)` in increasing frame order.
    fn new(start: T, keys: impl IntoIterator<Item = (u32, Option<T>)>) -> Self {
        let mut points = vec![(0, start)];
        for (frame, value) in keys {
            if let Some(value) = value {
                if frame == 0 {
                    points[0].1 = value;
                } else {
                    points.push((frame, value));
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
    fn spline_at(&self, frame: u32) -> DVec3 {
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

impl<T: Copy + Add<Output = T> + Sub<Output = T> + Mul<f64, Output = T>> Track<T> {
    /// Straight lines between the points.
    fn linear_at(&self, frame: u32) -> T {
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

/// The camera at every frame of a scene, made once (`Scene::camera_path`)
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
            position: Track::new(camera.position, keys.iter().map(|k| (k.frame, k.position))),
            look_at: Track::new(camera.look_at, keys.iter().map(|k| (k.frame, k.look_at))),
            up: Track::new(camera.up, keys.iter().map(|k| (k.frame, k.up))),
            vfov_degrees: Track::new(
                camera.vfov_degrees,
                keys.iter().map(|k| (k.frame, k.vfov_degrees)),
            ),
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
            position: self.position.spline_at(frame),
            look_at: self.look_at.spline_at(frame),
            up: self.up.spline_at(frame),
            vfov_degrees: self.vfov_degrees.linear_at(frame),
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

/// One light at every frame: the `[[lights]]` entry, and for a light with
/// keys its position track (a spline, as the camera's position) and its
/// colour-factor track (straight lines, starting at 1).
#[derive(Debug, Clone)]
struct LightPath {
    light: Light,
    tracks: Option<(Track<DVec3>, Track<DVec3>)>,
}

impl LightPath {
    /// Light `index`'s path under `keys` (in file order, each light's in
    /// increasing frame order, as validated).
    fn new(light: &Light, index: usize, keys: &[LightKey]) -> Self {
        let own = || keys.iter().filter(move |k| k.light as usize == index);
        let tracks = own().next().is_some().then(|| {
            (
                Track::new(light.position, own().map(|k| (k.frame, k.position))),
                Track::new(DVec3::ONE, own().map(|k| (k.frame, k.color))),
            )
        });
        LightPath {
            light: *light,
            tracks,
        }
    }

    /// The light at `frame`: the `[[lights]]` entry itself when it has no
    /// keys; else at the interpolated position, each colour times the
    /// interpolated factor.
    fn light_at(&self, frame: u32) -> Light {
        let Some((position, color)) = &self.tracks else {
            return self.light;
        };
        let factor = color.linear_at(frame);
        Light {
            position: position.spline_at(frame),
            ambient: self.light.ambient * factor,
            diffuse: self.light.diffuse * factor,
            specular: self.light.specular * factor,
            ..self.light
        }
    }
}

/// What one frame shows that changes from frame to frame: the camera and
/// the lights (the objects are the same in every frame).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub camera: Camera,
    /// One per `Scene::lights`, in its order.
    pub lights: Vec<Light>,
}

/// The camera and lights at every frame of a scene, made once
/// (`Scene::frame_path`) and then asked frame by frame.
#[derive(Debug, Clone)]
pub struct FramePath {
    camera: CameraPath,
    lights: Vec<LightPath>,
}

impl FramePath {
    /// The path of a scene's `camera` and `lights` (frame 0's values unless
    /// keys at frame 0 say otherwise) under `animation`, validated.
    pub fn new(camera: &Camera, lights: &[Light], animation: Option<&Animation>) -> Self {
        let keys = animation.map_or(&[][..], |a| &a.light_keys[..]);
        FramePath {
            camera: CameraPath::new(camera, animation),
            lights: lights
                .iter()
                .enumerate()
                .map(|(i, l)| LightPath::new(l, i, keys))
                .collect(),
        }
    }

    /// The camera and lights at `frame`.
    pub fn frame(&self, frame: u32) -> Frame {
        Frame {
            camera: self.camera_at(frame),
            lights: self.lights_at(frame),
        }
    }

    /// The camera at `frame` ([`CameraPath::camera_at`]).
    pub fn camera_at(&self, frame: u32) -> Camera {
        self.camera.camera_at(frame)
    }

    /// The lights at `frame`, in `Scene::lights` order.
    pub fn lights_at(&self, frame: u32) -> Vec<Light> {
        self.lights.iter().map(|l| l.light_at(frame)).collect()
    }

    /// Whether some light has keys: otherwise every frame's lights are the
    /// scene's `[[lights]]`.
    pub fn lights_move(&self) -> bool {
        self.lights.iter().any(|l| l.tracks.is_some())
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
        let track = Track::new(3.0, []);
        for frame in [0, 1, 1000] {
            assert_eq!(track.linear_at(frame), 3.0);
        }
    }

    fn light(position: DVec3) -> Light {
        Light {
            position,
            ambient: DVec3::splat(0.25),
            diffuse: DVec3::new(0.5, 1.0, 1.0),
            specular: DVec3::ONE,
            kind: Default::default(),
            reference_distance: None,
        }
    }

    /// Light 0 from (0, 0, 0) through keys (4, 0, 0) at frame 2 and
    /// (4, 4, 0) at frame 4, its colour factor from 1 to (0, 1, 2) at frame
    /// 4; light 1 has no keys. By hand, with P(t) of the Catmull-Rom
    /// segment, `0.5 * (2 p1 + (p2 - p0)/2 + (2 p0 - 5 p1 + 4 p2 - p3)/4 +
    /// (-p0 + 3 p1 - 3 p2 + p3)/8)` at t = 1/2: frame 1 (between v0 and v1,
    /// p0 = v0 doubled) is (2, -0.25, 0); frame 3 (p3 = v2 doubled) is
    /// (4.25, 2, 0); the factor at frame 1 is 1 + (f - 1) / 4 =
    /// (0.75, 1, 1.25).
    #[test]
    fn light_keys_move_and_tint_their_light_only() {
        let keys = [
            LightKey {
                frame: 2,
                light: 0,
                position: Some(DVec3::new(4.0, 0.0, 0.0)),
                color: None,
            },
            LightKey {
                frame: 4,
                light: 0,
                position: Some(DVec3::new(4.0, 4.0, 0.0)),
                color: Some(DVec3::new(0.0, 1.0, 2.0)),
            },
        ];
        let animation = Animation {
            frames: 8,
            fps: DEFAULT_FPS,
            orbit_degrees: 90.0,
            keys: Vec::new(),
            light_keys: keys.to_vec(),
        };
        let camera = Camera {
            position: DVec3::Z,
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 60.0,
        };
        let lights = [light(DVec3::ZERO), light(DVec3::new(1.0, 2.0, 3.0))];
        let path = FramePath::new(&camera, &lights, Some(&animation));
        assert!(path.lights_move());
        let at = |frame| path.lights_at(frame);
        assert_eq!(at(0), lights, "frame 0 is [[lights]] exactly");
        assert_eq!(at(1)[0].position, DVec3::new(2.0, -0.25, 0.0));
        assert_eq!(at(2)[0].position, DVec3::new(4.0, 0.0, 0.0));
        assert_eq!(at(3)[0].position, DVec3::new(4.25, 2.0, 0.0));
        assert_eq!(at(1)[0].diffuse, DVec3::new(0.375, 1.0, 1.25));
        assert_eq!(at(1)[0].ambient, DVec3::new(0.1875, 0.25, 0.3125));
        assert_eq!(at(1)[0].specular, DVec3::new(0.75, 1.0, 1.25));
        for frame in [4, 5, 7, 100] {
            let held = at(frame)[0];
            assert_eq!(held.position, DVec3::new(4.0, 4.0, 0.0), "frame {frame}");
            assert_eq!(held.diffuse, DVec3::new(0.0, 1.0, 2.0), "frame {frame}");
        }
        // The orbit turns the camera, never a light; unkeyed lights stay.
        for frame in 0..8 {
            assert_eq!(at(frame)[1], lights[1]);
            assert_eq!(
                path.camera_at(frame),
                CameraPath::new(&camera, Some(&animation)).camera_at(frame)
            );
        }
        assert_ne!(path.camera_at(4).position, camera.position);
        let still = FramePath::new(&camera, &lights, None);
        assert!(!still.lights_move());
        assert_eq!(
            still.frame(3),
            Frame {
                camera,
                lights: lights.to_vec()
            }
        );
    }
}
