//! `[animation]` checked key by key and then frame by frame: the camera of
//! every frame must be as valid as `[camera]`, every keyed light as valid
//! as its `[[lights]]` entry (the rules of docs/scene-format.md,
//! "Animation").

use std::collections::BTreeMap;

use super::animation::{Animation, CameraKey, CameraPath, FramePath, LightKey, MAX_FRAMES};
use super::camera::Camera;
use super::error::SceneError;
use super::light::Light;
use super::schema::{RawAnimation, RawCameraKey, RawLightKey};
use super::validate::{camera_fault, light_fault, Validator};

impl Validator<'_> {
    /// `[animation]`: its keys one by one, then the camera of every frame
    /// (`camera` is the validated `[camera]`).
    pub(super) fn animation(
        &self,
        a: &RawAnimation,
        camera: &Camera,
    ) -> Result<Animation, SceneError> {
        let frames = a.frames;
        if !(1..=MAX_FRAMES).contains(&frames) {
            return Err(self.error(
                "animation.frames",
                format!("must be in 1..={MAX_FRAMES}, got {frames}"),
            ));
        }
        let fps = self.number(&|| "animation.fps".into(), a.fps)?;
        if fps <= 0.0 {
            return Err(self.error("animation.fps", format!("must be > 0, got {fps:?}")));
        }
        let orbit_degrees = self.number(&|| "animation.orbit".into(), a.orbit)?;
        let mut keys: Vec<CameraKey> = Vec::with_capacity(a.keys.len());
        for (i, k) in a.keys.iter().enumerate() {
            let camera_key = self.camera_key(i, k, frames, keys.last())?;
            keys.push(camera_key);
        }
        let animation = Animation {
            frames,
            fps,
            orbit_degrees,
            keys,
            light_keys: Vec::new(),
        };
        self.check_frame_cameras(camera, &animation)?;
        Ok(animation)
    }

    /// `[[animation.keys]]` entry `i`, `k`, checked against the animation's
    /// `frames` and the `previous` key (frames strictly increasing).
    fn camera_key(
        &self,
        i: usize,
        k: &RawCameraKey,
        frames: u32,
        previous: Option<&CameraKey>,
    ) -> Result<CameraKey, SceneError> {
        let key = |field: &str| format!("animation.keys[{i}].{field}");
        if k.frame >= frames {
            return Err(self.error(
                &key("frame"),
                format!(
                    "must be in 0..{frames} (animation.frames = {frames}), got {}",
                    k.frame
                ),
            ));
        }
        if let Some(previous) = previous {
            if k.frame <= previous.frame {
                let message = if k.frame == previous.frame {
                    format!(
                        "frame {} is keyed twice (animation.keys[{}] is at frame {} too)",
                        k.frame,
                        i - 1,
                        previous.frame
                    )
                } else {
                    format!(
                        "keys must be in increasing frame order: animation.keys[{}] is at frame {}, this one at {}",
                        i - 1,
                        previous.frame,
                        k.frame
                    )
                };
                return Err(self.error(&key("frame"), message));
            }
        }
        let vfov_degrees = match k.vfov {
            Some(v) => {
                let v = self.number(&|| key("vfov"), v)?;
                if !(v > 0.0 && v < 180.0) {
                    return Err(self.error(
                        &key("vfov"),
                        format!("must be in (0, 180) degrees, got {v:?}"),
                    ));
                }
                Some(v)
            }
            None => None,
        };
        let camera_key = CameraKey {
            frame: k.frame,
            position: k
                .position
                .map(|p| self.position(&|| key("position"), p))
                .transpose()?,
            look_at: k
                .look_at
                .map(|p| self.position(&|| key("look_at"), p))
                .transpose()?,
            up: k.up.map(|u| self.vector(&|| key("up"), u)).transpose()?,
            vfov_degrees,
        };
        if camera_key.position.is_none()
            && camera_key.look_at.is_none()
            && camera_key.up.is_none()
            && camera_key.vfov_degrees.is_none()
        {
            return Err(self.error(
                &format!("animation.keys[{i}]"),
                "sets none of position, look_at, up, vfov",
            ));
        }
        Ok(camera_key)
    }

    /// The camera of every frame of `animation` (keyed from `camera`) as
    /// valid as `[camera]`.
    fn check_frame_cameras(
        &self,
        camera: &Camera,
        animation: &Animation,
    ) -> Result<(), SceneError> {
        let path = CameraPath::new(camera, Some(animation));
        for frame in 0..animation.frames {
            if let Some(message) = camera_fault(&path.camera_at(frame)) {
                // Blame the key whose segment holds the frame (the first key
                // before it), or the orbit when there are no keys.
                let keys = &animation.keys;
                let key = if keys.is_empty() {
                    "animation.orbit".to_string()
                } else {
                    let i = keys.partition_point(|k| k.frame <= frame).max(1) - 1;
                    format!("animation.keys[{i}]")
                };
                return Err(self.error(&key, format!("at frame {frame} {message}")));
            }
        }
        Ok(())
    }

    /// `[[animation.light_keys]]`: each key against `lights` (the
    /// validated `[[lights]]`) and `animation`'s frames, then every keyed
    /// light at every frame (its position within the coordinate range, its
    /// colours finite).
    pub(super) fn light_keys(
        &self,
        raw: &RawAnimation,
        animation: &Animation,
        camera: &Camera,
        lights: &[Light],
    ) -> Result<Vec<LightKey>, SceneError> {
        let mut keys: Vec<LightKey> = Vec::with_capacity(raw.light_keys.len());
        // Each light's latest key so far, by its index in `keys`.
        let mut latest: BTreeMap<u32, usize> = BTreeMap::new();
        for (i, k) in raw.light_keys.iter().enumerate() {
            let previous = latest.get(&k.light).map(|&j| (j, keys[j].frame));
            let light_key = self.light_key(i, k, animation.frames, lights, previous)?;
            latest.insert(k.light, keys.len());
            keys.push(light_key);
        }
        if keys.is_empty() {
            return Ok(keys);
        }
        let keyed = Animation {
            light_keys: keys,
            ..animation.clone()
        };
        self.check_keyed_lights(camera, lights, &keyed)?;
        Ok(keyed.light_keys)
    }

    /// `[[animation.light_keys]]` entry `i`, `k`: a light of `lights`, a
    /// frame of the animation's `frames` after its `previous` key (index
    /// in the keys, frame) of the same light, no position for a
    /// directional light, and something set.
    fn light_key(
        &self,
        i: usize,
        k: &RawLightKey,
        frames: u32,
        lights: &[Light],
        previous: Option<(usize, u32)>,
    ) -> Result<LightKey, SceneError> {
        let count = lights.len();
        let key = |field: &str| format!("animation.light_keys[{i}].{field}");
        if k.light as usize >= count {
            return Err(self.error(
                &key("light"),
                format!(
                    "must be in 0..{count} (the index of one of the scene's {count} [[lights]]), got {}",
                    k.light
                ),
            ));
        }
        if k.frame >= frames {
            return Err(self.error(
                &key("frame"),
                format!(
                    "must be in 0..{frames} (animation.frames = {frames}), got {}",
                    k.frame
                ),
            ));
        }
        if let Some((j, previous)) = previous {
            if k.frame <= previous {
                let message = if k.frame == previous {
                    format!(
                        "light {}'s frame {previous} is keyed twice (animation.light_keys[{j}] is at frame {previous} too)",
                        k.light
                    )
                } else {
                    format!(
                        "the keys of a light must be in increasing frame order: animation.light_keys[{j}] (light {}) is at frame {previous}, this one at {}",
                        k.light, k.frame
                    )
                };
                return Err(self.error(&key("frame"), message));
            }
        }
        let directional = matches!(
            lights[k.light as usize].kind,
            super::light_kind::LightKind::Directional { .. }
        );
        if k.position.is_some() && directional {
            return Err(self.error(
                &key("position"),
                format!(
                    "light {} is directional: it has no position to key",
                    k.light
                ),
            ));
        }
        let light_key = LightKey {
            frame: k.frame,
            light: k.light,
            position: k
                .position
                .map(|p| self.position(&|| key("position"), p))
                .transpose()?,
            color: k
                .color
                .map(|c| self.colour(&|| key("color"), c))
                .transpose()?,
        };
        if light_key.position.is_none() && light_key.color.is_none() {
            return Err(self.error(
                &format!("animation.light_keys[{i}]"),
                "sets neither position nor color",
            ));
        }
        Ok(light_key)
    }

    /// Every light keyed in `keyed` (the animation with its light keys), at
    /// every frame: its position within the coordinate range, its colours
    /// finite.
    fn check_keyed_lights(
        &self,
        camera: &Camera,
        lights: &[Light],
        keyed: &Animation,
    ) -> Result<(), SceneError> {
        let path = FramePath::new(camera, lights, Some(keyed));
        for frame in 0..keyed.frames {
            for (l, light) in path.lights_at(frame).iter().enumerate() {
                if let Some(message) = light_fault(light) {
                    // Blame the light's key whose segment holds the frame
                    // (its first key, for frames before it).
                    let own: Vec<usize> = (0..keyed.light_keys.len())
                        .filter(|&i| keyed.light_keys[i].light as usize == l)
                        .collect();
                    let before = own
                        .iter()
                        .rev()
                        .find(|&&i| keyed.light_keys[i].frame <= frame);
                    let i = before.or(own.first()).copied().unwrap_or(0);
                    return Err(self.error(
                        &format!("animation.light_keys[{i}]"),
                        format!("at frame {frame} light {l}'s {message}"),
                    ));
                }
            }
        }
        Ok(())
    }
}
