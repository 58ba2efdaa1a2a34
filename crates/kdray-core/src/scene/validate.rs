//! The rules of docs/scene-format.md: a deserialised scene file
//! ([`schema`](super::schema)) checked value by value and turned into the
//! world-space [`Scene`]. Each error names its key and, through the source
//! map, its line. Meshes are loaded and placed by
//! [`mesh_placement`](super::mesh_placement), an `[animation]` by
//! [`validate_animation`](super::validate_animation).

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;

use glam::DVec3;

use super::camera::Camera;
use super::environment::EnvironmentMap;
use super::error::SceneError;
use super::integrator::{Integrator, ToneMap};
use super::light::Light;
use super::material::{Material, MetalRough, Physical, Volume};
use super::mesh::has_area;
use super::normals::unit;
use super::objects::{Sphere, Triangle};
use super::render_settings::{RenderSettings, ShadowMode};
use super::schema::{
    RawCamera, RawEnvironment, RawMaterial, RawRender, RawScene, RawShadowMode, Vec3, DEFAULT_UP,
};
use super::source_map::LazySourceMap;
use super::validated_scene::Scene;
use crate::choice::Choice;

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest coordinate or radius accepted: the GPU computes in f32 and squares
/// distances, which must stay below f32::MAX (3.4e38).
pub const MAX_COORDINATE: f64 = 1e15;
/// Range of `render.max_depth`.
pub const MAX_DEPTH_RANGE: std::ops::RangeInclusive<u32> = 1..=64;

pub(super) struct Validator<'a> {
    pub(super) file: &'a Path,
    pub(super) map: LazySourceMap<'a>,
    /// Told of each file just before it is read.
    pub(super) on_read: RefCell<&'a mut dyn FnMut(&Path)>,
    /// Given each warning of the mesh files.
    pub(super) warn: RefCell<&'a mut dyn FnMut(super::warning::Warning)>,
}

/// The path of a key, made only when an error names it: made for every
/// number and material name, a million spheres' seven million paths, that
/// no error read, were 0.53 s of their JSON file's 1.0 s load.
pub(super) type KeyPath<'a> = &'a dyn Fn() -> String;

impl Validator<'_> {
    /// An error at `key`, on the line of the key or, when the file leaves it
    /// out (a default is at fault), of the nearest enclosing table it has.
    pub(super) fn error(&self, key: &str, message: impl Into<String>) -> SceneError {
        let line = self.map.get().and_then(|m| {
            let mut path = key;
            loop {
                if let Some(line) = m.line_of_path(path) {
                    return Some(line);
                }
                path = &path[..path.rfind(['.', '['])?];
            }
        });
        SceneError::new(self.file, line, Some(key.to_string()), message)
    }

    pub(super) fn number(&self, key: KeyPath, x: f64) -> Result<f64, SceneError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(&key(), format!("must be a finite number, got {x:?}")))
        }
    }

    /// A finite vector; a bad component is named by its index, `key[i]`.
    pub(super) fn vector(&self, key: KeyPath, v: Vec3) -> Result<DVec3, SceneError> {
        for (i, x) in v.0.into_iter().enumerate() {
            self.number(&|| format!("{}[{i}]", key()), x)?;
        }
        Ok(DVec3::from_array(v.0))
    }

    /// A point in space: finite, and within ±MAX_COORDINATE so that the
    /// GPU's f32 arithmetic (which squares distances) cannot overflow.
    pub(super) fn position(&self, key: KeyPath, v: Vec3) -> Result<DVec3, SceneError> {
        let p = self.vector(key, v)?;
        for (i, x) in p.to_array().into_iter().enumerate() {
            if x.abs() > MAX_COORDINATE {
                return Err(self.error(
                    &format!("{}[{i}]", key()),
                    format!(
                        "must be within ±{MAX_COORDINATE:e} (the GPU computes in f32), got {x:e}"
                    ),
                ));
            }
        }
        Ok(p)
    }

    pub(super) fn colour(&self, key: KeyPath, v: Vec3) -> Result<DVec3, SceneError> {
        let c = self.vector(key, v)?;
        if c.min_element() < 0.0 {
            return Err(self.error(
                &key(),
                format!("colour components must be >= 0, got {:?}", v.0),
            ));
        }
        Ok(c)
    }

    /// The whole file, checked in the order its errors are reported:
    /// camera, render, sky, animation, lights, materials, spheres,
    /// triangles, meshes, shapes, instances.
    pub(super) fn scene(&self, raw: RawScene) -> Result<Scene, SceneError> {
        let camera = self.camera(&raw.camera)?;
        let mut render = self.render(&raw.render)?;
        let environment = self.environment(&raw, &mut render)?;
        let mut animation = match &raw.animation {
            Some(a) => Some(self.animation(a, &camera)?),
            None => None,
        };
        let lights = self.lights(&raw, &render)?;
        if let (Some(raw), Some(animation)) = (&raw.animation, &mut animation) {
            animation.light_keys = self.light_keys(raw, animation, &camera, &lights)?;
        }

        let mut materials = Vec::with_capacity(raw.materials.len());
        let mut material_index = BTreeMap::new();
        for (name, m) in &raw.materials {
            let key = |k: &str| format!("materials.{name}.{k}");
            let shininess = self.number(&|| key("shininess"), m.shininess)?;
            if shininess < 0.0 {
                return Err(self.error(
                    &key("shininess"),
                    format!("must be >= 0, got {shininess:?}"),
                ));
            }
            let reflection = self.number(&|| key("reflection"), m.reflection)?;
            if !(0.0..=1.0).contains(&reflection) {
                return Err(self.error(
                    &key("reflection"),
                    format!("must be in [0, 1], got {reflection:?}"),
                ));
            }
            let transmission = self.number(&|| key("transmission"), m.transmission)?;
            if !(0.0..=1.0).contains(&transmission) {
                return Err(self.error(
                    &key("transmission"),
                    format!("must be in [0, 1], got {transmission:?}"),
                ));
            }
            let ior = self.number(&|| key("ior"), m.ior)?;
            if ior <= 0.0 {
                return Err(self.error(&key("ior"), format!("must be > 0, got {ior:?}")));
            }
            let (diffuse, physical) = self.physical(name, m)?;
            material_index.insert(name.clone(), materials.len() as u32);
            materials.push(Material {
                name: name.clone(),
                ambient: self.colour(&|| key("ambient"), m.ambient)?,
                diffuse,
                specular: self.colour(&|| key("specular"), m.specular)?,
                shininess,
                reflection,
                transmission,
                ior,
                texture: None,
                physical,
                maps: crate::scene::material::MaterialMaps::NONE,
                alpha: crate::scene::alpha::Alpha::OPAQUE,
            });
        }
        let spheres = self.spheres(&raw, &material_index)?;
        let mut triangles = self.triangles(&raw, &material_index)?;

        let mut parts = super::triangle_parts::TriangleParts::default();
        let mut shapes = Vec::new();
        let mut instances = Vec::new();
        for (i, m) in raw.meshes.iter().enumerate() {
            let override_material = match &m.material {
                Some(name) => Some(self.material_named(
                    &material_index,
                    &|| format!("meshes[{i}].material"),
                    name,
                )?),
                None => None,
            };
            let placed = self.mesh(
                i,
                m,
                override_material,
                &mut materials,
                &mut triangles,
                &mut parts,
            )?;
            add_shapes(&mut shapes, &mut instances, placed.shapes, placed.instances);
        }
        let declared = self.shapes(&raw, &material_index, &mut materials, &mut parts)?;
        let declared_instances = self.instances(&raw, &declared, &material_index)?;
        add_shapes(&mut shapes, &mut instances, declared, declared_instances);
        parts.finish();
        self.flattened_size(spheres.len() + triangles.len(), &shapes, &instances)?;

        Ok(Scene {
            camera,
            render,
            lights,
            environment,
            materials,
            spheres,
            triangles,
            triangle_normals: parts.normals,
            triangle_uvs: parts.uvs,
            triangle_second_uvs: parts.second_uvs,
            triangle_colours: parts.colours,
            triangle_tangents: parts.tangents,
            textures: parts.textures,
            animation,
            shapes,
            instances,
        })
    }

    /// The sky: `[environment]` (a uniform colour, which becomes
    /// `render.background`, or an image) or none; not both it and
    /// `render.background`.
    fn environment(
        &self,
        raw: &RawScene,
        render: &mut RenderSettings,
    ) -> Result<Option<EnvironmentMap>, SceneError> {
        let Some(env) = &raw.environment else {
            return Ok(None);
        };
        if raw.render.background.is_some() {
            return Err(self.error(
                "environment",
                "give the sky as [environment] or as render.background, not both",
            ));
        }
        match (env.color, &env.image) {
            (Some(c), None) => {
                render.background = self.colour(&|| "environment.color".into(), c)?;
                Ok(None)
            }
            (None, Some(image)) => Ok(Some(self.environment_map(env, image)?)),
            _ => Err(self.error(
                "environment",
                "give one of color (a uniform sky) and image (an HDR or EXR file)",
            )),
        }
    }

    /// The index of the material `name` (the value of `key`) in
    /// `material_index` (the scene's materials' indices by name); for an
    /// unknown name, an error listing the defined ones.
    pub(super) fn material_named(
        &self,
        material_index: &BTreeMap<String, u32>,
        key: KeyPath,
        name: &str,
    ) -> Result<u32, SceneError> {
        material_index.get(name).copied().ok_or_else(|| {
            let known: Vec<&str> = material_index.keys().map(String::as_str).collect();
            self.error(
                &key(),
                format!(
                    "unknown material \"{name}\" (defined: {})",
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            )
        })
    }

    /// `[[spheres]]`: radius in (0, MAX_COORDINATE], centre a position,
    /// material one of `material_index` (indices by name).
    fn spheres(
        &self,
        raw: &RawScene,
        material_index: &BTreeMap<String, u32>,
    ) -> Result<Vec<Sphere>, SceneError> {
        let mut spheres = Vec::with_capacity(raw.spheres.len());
        for (i, s) in raw.spheres.iter().enumerate() {
            let key = |k: &str| format!("spheres[{i}].{k}");
            let radius = self.number(&|| key("radius"), s.radius)?;
            if radius <= 0.0 {
                return Err(self.error(&key("radius"), format!("must be > 0, got {radius:?}")));
            }
            if radius > MAX_COORDINATE {
                return Err(self.error(
                    &key("radius"),
                    format!("must be at most {MAX_COORDINATE:e} (the GPU computes in f32), got {radius:e}"),
                ));
            }
            spheres.push(Sphere {
                center: self.position(&|| key("center"), s.center)?,
                radius,
                material: self.material_named(material_index, &|| key("material"), &s.material)?,
            });
        }
        Ok(spheres)
    }

    /// `[[triangles]]`: three positions with area, material one of
    /// `material_index` (indices by name); shaded flat.
    fn triangles(
        &self,
        raw: &RawScene,
        material_index: &BTreeMap<String, u32>,
    ) -> Result<Vec<Triangle>, SceneError> {
        let mut triangles = Vec::with_capacity(raw.triangles.len());
        for (i, t) in raw.triangles.iter().enumerate() {
            let key = |k: &str| format!("triangles[{i}].{k}");
            let mut vertices = [DVec3::ZERO; 3];
            for (j, (v, raw_v)) in vertices.iter_mut().zip(t.vertices.0).enumerate() {
                *v = self.position(&|| format!("{}[{j}]", key("vertices")), raw_v)?;
            }
            if !has_area(&vertices) {
                return Err(self.error(&key("vertices"), "triangle has zero area"));
            }
            triangles.push(Triangle::flat(
                vertices,
                self.material_named(material_index, &|| key("material"), &t.material)?,
            ));
        }
        Ok(triangles)
    }

    fn camera(&self, c: &RawCamera) -> Result<Camera, SceneError> {
        let position = self.position(&|| "camera.position".into(), c.position)?;
        let look_at = self.position(&|| "camera.look_at".into(), c.look_at)?;
        let up = self.vector(&|| "camera.up".into(), c.up.unwrap_or(DEFAULT_UP))?;
        let vfov_degrees = self.number(&|| "camera.vfov".into(), c.vfov)?;
        if !(vfov_degrees > 0.0 && vfov_degrees < 180.0) {
            return Err(self.error(
                "camera.vfov",
                format!("must be in (0, 180) degrees, got {vfov_degrees:?}"),
            ));
        }
        let forward = look_at - position;
        if !forward.is_finite() {
            return Err(self.error(
                "camera.look_at",
                "look_at - position is too large to represent",
            ));
        }
        let Some(forward) = unit(forward) else {
            return Err(self.error("camera.look_at", "must differ from camera.position"));
        };
        if up_is_parallel(forward, up) {
            return Err(self.error(
                "camera.up",
                format!(
                    "must not be zero or parallel to look_at - position, got {:?}{}",
                    c.up.unwrap_or(DEFAULT_UP).0,
                    if c.up.is_none() { " (the default)" } else { "" }
                ),
            ));
        }
        Ok(Camera {
            position,
            look_at,
            up,
            vfov_degrees,
        })
    }

    fn render(&self, r: &RawRender) -> Result<RenderSettings, SceneError> {
        let width = r.width.unwrap_or(800);
        let height = r.height.unwrap_or(600);
        for (key, side) in [("render.width", width), ("render.height", height)] {
            if !(1..=MAX_IMAGE_SIDE).contains(&side) {
                return Err(self.error(key, format!("must be in 1..={MAX_IMAGE_SIDE}, got {side}")));
            }
        }
        let min_intensity = self.number(
            &|| "render.min_intensity".into(),
            r.min_intensity.unwrap_or(0.05),
        )?;
        if !(0.0..=1.0).contains(&min_intensity) {
            return Err(self.error(
                "render.min_intensity",
                format!("must be in [0, 1], got {min_intensity:?}"),
            ));
        }
        let max_depth = r.max_depth.unwrap_or(10);
        if !MAX_DEPTH_RANGE.contains(&max_depth) {
            return Err(self.error(
                "render.max_depth",
                format!("must be in 1..=64, got {max_depth}"),
            ));
        }
        let integrator = r.integrator.as_ref().map_or(Integrator::default(), |n| n.0);
        let samples = r.samples.unwrap_or(1);
        check_samples(samples, integrator).map_err(|m| self.error("render.samples", m))?;
        let exposure = self.number(&|| "render.exposure".into(), r.exposure.unwrap_or(0.0))?;
        let denoise = r.denoise.unwrap_or(false);
        if denoise && integrator != Integrator::Path {
            return Err(self.error(
                "render.denoise",
                format!(
                    "the denoiser needs the path tracer (integrator = \"path\"), got integrator = \"{}\"",
                    integrator.name()
                ),
            ));
        }
        Ok(RenderSettings {
            width,
            height,
            min_intensity,
            max_depth,
            background: self.colour(
                &|| "render.background".into(),
                r.background.unwrap_or_default(),
            )?,
            shadow_mode: match r.shadow_mode {
                None | Some(RawShadowMode::Ambient) => ShadowMode::Ambient,
                Some(RawShadowMode::Seed) => ShadowMode::Seed,
            },
            samples,
            integrator,
            seed: r.seed.unwrap_or(0),
            tone_map: r.tone_map.as_ref().map_or(ToneMap::default(), |n| n.0),
            exposure,
            denoise,
        })
    }

    /// `[environment] image`: the file read (relative to the scene's folder)
    /// and decoded, its intensity (>= 0) and rotation (degrees) checked.
    fn environment_map(
        &self,
        env: &RawEnvironment,
        image: &str,
    ) -> Result<EnvironmentMap, SceneError> {
        let intensity = self.number(
            &|| "environment.intensity".into(),
            env.intensity.unwrap_or(1.0),
        )?;
        if intensity < 0.0 {
            return Err(self.error(
                "environment.intensity",
                format!("must be >= 0, got {intensity:?}"),
            ));
        }
        let rotation = self.number(
            &|| "environment.rotation".into(),
            env.rotation.unwrap_or(0.0),
        )?;
        let path = self.file.parent().unwrap_or(Path::new("")).join(image);
        (self.on_read.borrow_mut())(&path);
        let decoded = super::input_file::read_input_file(&path)
            .map_err(|e| e.to_string())
            .and_then(|bytes| EnvironmentMap::decode(&bytes));
        let (width, height, texels) = decoded.map_err(|e| {
            self.error(
                "environment.image",
                format!("{}: not a sky image: {e}", path.display()),
            )
        })?;
        Ok(EnvironmentMap {
            path: image.to_string(),
            width,
            height,
            texels,
            intensity,
            rotation_degrees: rotation,
        })
    }

    /// A material's albedo (`diffuse`, or `base_color`) and its physical
    /// part: exactly one of `diffuse` and `base_color`; `metallic` and
    /// `roughness` (in [0, 1]; 0 and 0.5 by default) only with
    /// `base_color`; `emission` a colour of any size;
    /// `transmission_roughness` in [0, 1].
    fn physical(&self, name: &str, m: &RawMaterial) -> Result<(DVec3, Physical), SceneError> {
        let key = |k: &str| format!("materials.{name}.{k}");
        let unit = |k: &str, v: Option<f64>, default: f64| -> Result<f64, SceneError> {
            let x = self.number(&|| key(k), v.unwrap_or(default))?;
            if !(0.0..=1.0).contains(&x) {
                return Err(self.error(&key(k), format!("must be in [0, 1], got {x:?}")));
            }
            Ok(x)
        };
        let (albedo, metal_rough) = match (m.diffuse, m.base_color) {
            (Some(d), None) => {
                for (k, v) in [("metallic", m.metallic), ("roughness", m.roughness)] {
                    if v.is_some() {
                        return Err(self.error(
                            &key(k),
                            format!("{k} belongs to the metal/rough model: give base_color instead of diffuse"),
                        ));
                    }
                }
                (self.colour(&|| key("diffuse"), d)?, None)
            }
            (None, Some(b)) => (
                self.colour(&|| key("base_color"), b)?,
                Some(MetalRough {
                    metallic: unit("metallic", m.metallic, 0.0)?,
                    roughness: unit("roughness", m.roughness, 0.5)?,
                }),
            ),
            (Some(_), Some(_)) => {
                return Err(self.error(
                    &key("base_color"),
                    "give diffuse (Lambertian) or base_color (metal/rough), not both",
                ))
            }
            (None, None) => {
                return Err(self.error(
                    &format!("materials.{name}"),
                    "missing field `diffuse` (or `base_color`)",
                ))
            }
        };
        let emission = match m.emission {
            Some(e) => self.colour(&|| key("emission"), e)?,
            None => DVec3::ZERO,
        };
        let volume = match (m.attenuation_color, m.attenuation_distance) {
            (None, None) => None,
            (colour, distance) => {
                let attenuation_color = match colour {
                    Some(c) => self.colour(&|| key("attenuation_color"), c)?,
                    None => DVec3::ONE,
                };
                if attenuation_color.max_element() > 1.0 {
                    return Err(self.error(
                        &key("attenuation_color"),
                        format!(
                            "components must be in [0, 1], got {:?}",
                            attenuation_color.to_array()
                        ),
                    ));
                }
                let attenuation_distance = match distance {
                    Some(d) => {
                        let d = self.number(&|| key("attenuation_distance"), d)?;
                        if d <= 0.0 {
                            return Err(self.error(
                                &key("attenuation_distance"),
                                format!("must be > 0, got {d:?}"),
                            ));
                        }
                        d
                    }
                    None => f64::INFINITY,
                };
                Some(Volume {
                    attenuation_color,
                    attenuation_distance,
                })
            }
        };
        let transmission_roughness = unit(
            "transmission_roughness",
            Some(m.transmission_roughness),
            0.0,
        )?;
        Ok((
            albedo,
            Physical {
                metal_rough,
                emission,
                two_sided: false,
                volume,
                transmission_roughness,
                thin_walled: m.thin_walled,
            },
        ))
    }
}

/// Appends `more` shapes and their instances (whose `shape` indexes
/// `more`) to the scene's.
pub(super) fn add_shapes(
    shapes: &mut Vec<super::instances::Shape>,
    instances: &mut Vec<super::instances::Instance>,
    more: Vec<super::instances::Shape>,
    more_instances: Vec<super::instances::Instance>,
) {
    let first = shapes.len() as u32;
    shapes.extend(more);
    instances.extend(more_instances.into_iter().map(|mut i| {
        i.shape += first;
        i
    }));
}

/// Whether `up` is zero or parallel to the unit view direction `forward`:
/// then the camera has no "right".
fn up_is_parallel(forward: DVec3, up: DVec3) -> bool {
    unit(up).is_none_or(|up| forward.cross(up).length() < 1e-9)
}

/// What is wrong with an animated frame's camera, if anything: the rules
/// of `[camera]` (vfov needs no check: it lies between valid ones).
pub(super) fn camera_fault(c: &Camera) -> Option<String> {
    for (name, p) in [("position", c.position), ("look_at", c.look_at)] {
        if !(p.is_finite() && p.abs().max_element() <= MAX_COORDINATE) {
            return Some(format!(
                "the camera's {name} {:?} is not within ±{MAX_COORDINATE:e} (the GPU computes in f32)",
                p.to_array()
            ));
        }
    }
    let Some(forward) = unit(c.look_at - c.position) else {
        return Some(format!(
            "the camera's look_at equals its position {:?}",
            c.position.to_array()
        ));
    };
    if up_is_parallel(forward, c.up) {
        return Some(format!(
            "the camera's up {:?} is zero or parallel to its view direction (look_at - position = {:?})",
            c.up.to_array(),
            (c.look_at - c.position).to_array()
        ));
    }
    None
}

/// What is wrong with an animated frame's light, if anything: its
/// position must stay within the coordinate range (a spline may overshoot
/// its keys), its colours finite (a factor times a huge colour may not be).
pub(super) fn light_fault(l: &Light) -> Option<String> {
    if !(l.position.is_finite() && l.position.abs().max_element() <= MAX_COORDINATE) {
        return Some(format!(
            "position {:?} is not within ±{MAX_COORDINATE:e} (the GPU computes in f32)",
            l.position.to_array()
        ));
    }
    for (name, c) in [
        ("ambient", l.ambient),
        ("diffuse", l.diffuse),
        ("specular", l.specular),
    ] {
        if !c.is_finite() {
            return Some(format!("{name} {:?} is not finite", c.to_array()));
        }
    }
    None
}

/// `samples` must be at least 1, and for the Whitted integrator a perfect
/// square k * k (its k x k grid).
pub fn check_samples(samples: u32, integrator: Integrator) -> Result<(), String> {
    if integrator == Integrator::Path {
        return match samples {
            0 => Err("must be at least 1, got 0".into()),
            _ => Ok(()),
        };
    }
    // In u64: for samples near u32::MAX, k rounds up to 65536 and k * k
    // would overflow a u32.
    let k = (samples as f64).sqrt().round() as u64;
    if samples == 0 || k * k != u64::from(samples) {
        return Err(format!(
            "must be a perfect square (1, 4, 9, 16, ...), got {samples}"
        ));
    }
    Ok(())
}
