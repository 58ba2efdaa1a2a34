//! Scene files (TOML, or the same schema as JSON) to a validated [`Scene`].
//!
//! Two stages: serde reads the document into `Raw*` structs that mirror the
//! file exactly (unknown keys rejected), then `Validator` checks every rule
//! of docs/scene-format.md and builds the world-space scene, loading meshes.
//! Every error names the file, the line (via [`SourceMap`]) and the key.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DMat3, DVec3};
use serde::Deserialize;

use super::obj;
use super::source_map::SourceMap;
use super::{
    Camera, Light, Material, RenderSettings, Scene, SceneError, ShadowMode, Sphere, Triangle,
};

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Range of `render.max_depth`.
pub const MAX_DEPTH_RANGE: std::ops::RangeInclusive<u32> = 1..=64;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneFormat {
    Toml,
    Json,
}

impl SceneFormat {
    /// `.json` files are JSON; everything else is read as TOML.
    pub fn from_path(path: &Path) -> Self {
        match path.extension().and_then(|e| e.to_str()) {
            Some(ext) if ext.eq_ignore_ascii_case("json") => SceneFormat::Json,
            _ => SceneFormat::Toml,
        }
    }
}

/// Reads and validates a scene file; OBJ paths are relative to its folder.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| SceneError::new(path, None, None, format!("cannot read scene file: {e}")))?;
    parse_scene(&text, path, SceneFormat::from_path(path))
}

/// Parses scene text; `path` names the file in errors and anchors mesh paths.
pub fn parse_scene(text: &str, path: &Path, format: SceneFormat) -> Result<Scene, SceneError> {
    let (raw, map) = match format {
        SceneFormat::Toml => {
            let raw: Result<RawScene, _> = toml::from_str(text);
            let map = SourceMap::toml(text);
            match raw {
                Ok(raw) => (raw, map),
                Err(e) => {
                    let offset = e.span().map(|s| s.start);
                    let line = match (&map, offset) {
                        (Some(m), Some(o)) => Some(m.line_of_offset(o)),
                        (None, Some(o)) => {
                            Some(text[..o.min(text.len())].matches('\n').count() + 1)
                        }
                        _ => None,
                    };
                    let key = map
                        .as_ref()
                        .zip(offset)
                        .and_then(|(m, o)| m.path_at(o))
                        .map(str::to_string);
                    return Err(SceneError::new(path, line, key, e.message()));
                }
            }
        }
        SceneFormat::Json => {
            let raw: Result<RawScene, _> = serde_json::from_str(text);
            let map = SourceMap::json(text);
            match raw {
                Ok(raw) => (raw, map),
                Err(e) => {
                    let key = map
                        .as_ref()
                        .and_then(|m| m.path_at(m.offset_of(e.line(), e.column())))
                        .map(str::to_string);
                    // serde_json appends " at line L column C"; the line is ours to print.
                    let message = e.to_string();
                    let message = message
                        .rsplit_once(" at line ")
                        .map_or(message.as_str(), |(m, _)| m);
                    let line = (e.line() > 0).then_some(e.line());
                    return Err(SceneError::new(path, line, key, message));
                }
            }
        }
    };
    Validator { file: path, map }.scene(raw)
}

// ---------------------------------------------------------------- raw file

type Vec3 = [f64; 3];

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    camera: RawCamera,
    #[serde(default)]
    render: RawRender,
    #[serde(default)]
    lights: Vec<RawLight>,
    #[serde(default)]
    materials: BTreeMap<String, RawMaterial>,
    #[serde(default)]
    spheres: Vec<RawSphere>,
    #[serde(default)]
    triangles: Vec<RawTriangle>,
    #[serde(default)]
    meshes: Vec<RawMesh>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    position: Vec3,
    look_at: Vec3,
    #[serde(default = "default_up")]
    up: Vec3,
    #[serde(default = "default_vfov")]
    vfov: f64,
}

fn default_up() -> Vec3 {
    [0.0, 1.0, 0.0]
}
fn default_vfov() -> f64 {
    60.0
}
fn white() -> Vec3 {
    [1.0; 3]
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct RawRender {
    width: Option<u32>,
    height: Option<u32>,
    min_intensity: Option<f64>,
    max_depth: Option<u32>,
    background: Option<Vec3>,
    shadow_mode: Option<RawShadowMode>,
    samples: Option<u32>,
}

#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
enum RawShadowMode {
    Ambient,
    Seed,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLight {
    position: Vec3,
    #[serde(default = "white")]
    ambient: Vec3,
    #[serde(default = "white")]
    diffuse: Vec3,
    #[serde(default = "white")]
    specular: Vec3,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMaterial {
    #[serde(default)]
    ambient: Vec3,
    diffuse: Vec3,
    #[serde(default)]
    specular: Vec3,
    #[serde(default)]
    shininess: f64,
    #[serde(default)]
    reflection: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSphere {
    center: Vec3,
    radius: f64,
    material: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTriangle {
    vertices: [Vec3; 3],
    material: String,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMesh {
    path: String,
    material: Option<String>,
    #[serde(default)]
    scale: RawScale,
    #[serde(default)]
    rotate: Vec3,
    #[serde(default)]
    translate: Vec3,
}

#[derive(Deserialize)]
#[serde(untagged, expecting = "a number or an array of 3 numbers")]
enum RawScale {
    Uniform(f64),
    PerAxis(Vec3),
}

impl Default for RawScale {
    fn default() -> Self {
        RawScale::Uniform(1.0)
    }
}

// ---------------------------------------------------------------- validation

struct Validator<'a> {
    file: &'a Path,
    map: Option<SourceMap>,
}

impl Validator<'_> {
    fn error(&self, key: &str, message: impl Into<String>) -> SceneError {
        let line = self.map.as_ref().and_then(|m| m.line_of_path(key));
        SceneError::new(self.file, line, Some(key.to_string()), message)
    }

    fn number(&self, key: &str, x: f64) -> Result<f64, SceneError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(key, format!("must be a finite number, got {x}")))
        }
    }

    fn vector(&self, key: &str, v: Vec3) -> Result<DVec3, SceneError> {
        for x in v {
            self.number(key, x)?;
        }
        Ok(DVec3::from_array(v))
    }

    fn colour(&self, key: &str, v: Vec3) -> Result<DVec3, SceneError> {
        let c = self.vector(key, v)?;
        if c.min_element() < 0.0 {
            return Err(self.error(key, format!("colour components must be >= 0, got {v:?}")));
        }
        Ok(c)
    }

    fn scene(&self, raw: RawScene) -> Result<Scene, SceneError> {
        let camera = self.camera(&raw.camera)?;
        let render = self.render(&raw.render)?;

        if raw.lights.is_empty() {
            return Err(SceneError::new(
                self.file,
                None,
                Some("lights".into()),
                "a scene needs at least one [[lights]] entry",
            ));
        }
        let lights = raw
            .lights
            .iter()
            .enumerate()
            .map(|(i, l)| {
                let key = |k: &str| format!("lights[{i}].{k}");
                Ok(Light {
                    position: self.vector(&key("position"), l.position)?,
                    ambient: self.colour(&key("ambient"), l.ambient)?,
                    diffuse: self.colour(&key("diffuse"), l.diffuse)?,
                    specular: self.colour(&key("specular"), l.specular)?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;

        let mut materials = Vec::with_capacity(raw.materials.len());
        let mut material_index = BTreeMap::new();
        for (name, m) in &raw.materials {
            let key = |k: &str| format!("materials.{name}.{k}");
            let shininess = self.number(&key("shininess"), m.shininess)?;
            if shininess < 0.0 {
                return Err(self.error(&key("shininess"), format!("must be >= 0, got {shininess}")));
            }
            let reflection = self.number(&key("reflection"), m.reflection)?;
            if !(0.0..=1.0).contains(&reflection) {
                return Err(self.error(
                    &key("reflection"),
                    format!("must be in [0, 1], got {reflection}"),
                ));
            }
            material_index.insert(name.clone(), materials.len() as u32);
            materials.push(Material {
                name: name.clone(),
                ambient: self.colour(&key("ambient"), m.ambient)?,
                diffuse: self.colour(&key("diffuse"), m.diffuse)?,
                specular: self.colour(&key("specular"), m.specular)?,
                shininess,
                reflection,
            });
        }
        let lookup = |key: &str, name: &str| {
            material_index.get(name).copied().ok_or_else(|| {
                let known: Vec<&str> = material_index.keys().map(String::as_str).collect();
                self.error(
                    key,
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
        };

        let mut spheres = Vec::with_capacity(raw.spheres.len());
        for (i, s) in raw.spheres.iter().enumerate() {
            let key = |k: &str| format!("spheres[{i}].{k}");
            let radius = self.number(&key("radius"), s.radius)?;
            if radius <= 0.0 {
                return Err(self.error(&key("radius"), format!("must be > 0, got {radius}")));
            }
            spheres.push(Sphere {
                center: self.vector(&key("center"), s.center)?,
                radius,
                material: lookup(&key("material"), &s.material)?,
            });
        }

        let mut triangles = Vec::with_capacity(raw.triangles.len());
        for (i, t) in raw.triangles.iter().enumerate() {
            let key = |k: &str| format!("triangles[{i}].{k}");
            let mut vertices = [DVec3::ZERO; 3];
            for (v, raw_v) in vertices.iter_mut().zip(t.vertices) {
                *v = self.vector(&key("vertices"), raw_v)?;
            }
            if !has_area(&vertices) {
                return Err(self.error(&key("vertices"), "triangle has zero area"));
            }
            triangles.push(Triangle {
                vertices,
                material: lookup(&key("material"), &t.material)?,
            });
        }

        for (i, m) in raw.meshes.iter().enumerate() {
            let override_material = match &m.material {
                Some(name) => Some(lookup(&format!("meshes[{i}].material"), name)?),
                None => None,
            };
            self.mesh(i, m, override_material, &mut materials, &mut triangles)?;
        }

        Ok(Scene {
            camera,
            render,
            lights,
            materials,
            spheres,
            triangles,
        })
    }

    fn camera(&self, c: &RawCamera) -> Result<Camera, SceneError> {
        let position = self.vector("camera.position", c.position)?;
        let look_at = self.vector("camera.look_at", c.look_at)?;
        let up = self.vector("camera.up", c.up)?;
        let vfov_degrees = self.number("camera.vfov", c.vfov)?;
        if !(vfov_degrees > 0.0 && vfov_degrees < 180.0) {
            return Err(self.error(
                "camera.vfov",
                format!("must be in (0, 180) degrees, got {vfov_degrees}"),
            ));
        }
        let forward = look_at - position;
        if forward.length_squared() == 0.0 {
            return Err(self.error("camera.look_at", "must differ from camera.position"));
        }
        if up.length_squared() == 0.0 || forward.normalize().cross(up.normalize()).length() < 1e-9 {
            return Err(self.error(
                "camera.up",
                format!(
                    "must not be zero or parallel to look_at - position, got {:?}",
                    c.up
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
        let min_intensity = self.number("render.min_intensity", r.min_intensity.unwrap_or(0.05))?;
        if !(0.0..=1.0).contains(&min_intensity) {
            return Err(self.error(
                "render.min_intensity",
                format!("must be in [0, 1], got {min_intensity}"),
            ));
        }
        let max_depth = r.max_depth.unwrap_or(10);
        if !MAX_DEPTH_RANGE.contains(&max_depth) {
            return Err(self.error(
                "render.max_depth",
                format!("must be in 1..=64, got {max_depth}"),
            ));
        }
        let samples = r.samples.unwrap_or(1);
        check_samples(samples).map_err(|m| self.error("render.samples", m))?;
        Ok(RenderSettings {
            width,
            height,
            min_intensity,
            max_depth,
            background: self.colour("render.background", r.background.unwrap_or([0.0; 3]))?,
            shadow_mode: match r.shadow_mode {
                None | Some(RawShadowMode::Ambient) => ShadowMode::Ambient,
                Some(RawShadowMode::Seed) => ShadowMode::Seed,
            },
            samples,
        })
    }

    /// Loads mesh `i`, transforms it to world space and appends its triangles
    /// (and, without an override, its MTL materials).
    fn mesh(
        &self,
        i: usize,
        m: &RawMesh,
        override_material: Option<u32>,
        materials: &mut Vec<Material>,
        triangles: &mut Vec<Triangle>,
    ) -> Result<(), SceneError> {
        let key = |k: &str| format!("meshes[{i}].{k}");
        let scale = match m.scale {
            RawScale::Uniform(s) => self.vector(&key("scale"), [s; 3])?,
            RawScale::PerAxis(v) => self.vector(&key("scale"), v)?,
        };
        if scale.abs().min_element() == 0.0 {
            return Err(self.error(&key("scale"), "must be non-zero on every axis"));
        }
        let rotate = self.vector(&key("rotate"), m.rotate)?;
        let translate = self.vector(&key("translate"), m.translate)?;
        let transform = mesh_transform(scale, rotate);

        let base = self.file.parent().unwrap_or(Path::new(""));
        let obj_path = base.join(&m.path);
        let mesh = obj::load_obj(&obj_path, override_material.is_none())?;

        let first_material = materials.len() as u32;
        if override_material.is_none() {
            let file_name = Path::new(&m.path)
                .file_name()
                .map_or(m.path.clone(), |f| f.to_string_lossy().into_owned());
            materials.extend(mesh.materials.iter().map(|mm| Material {
                name: format!("{file_name}:{}", mm.name),
                ambient: mm.ambient,
                diffuse: mm.diffuse,
                specular: mm.specular,
                shininess: mm.shininess,
                reflection: 0.0,
            }));
        }
        for t in &mesh.triangles {
            let vertices = t.vertices.map(|v| transform * v + translate);
            if !vertices.iter().all(|v| v.is_finite()) {
                return Err(self.error(
                    &key("scale"),
                    "the transformed mesh has a non-finite vertex",
                ));
            }
            if !has_area(&vertices) {
                continue; // collapsed by an extreme scale: it can never be hit
            }
            let material = match (override_material, t.material) {
                (Some(m), _) => m,
                (None, Some(local)) => first_material + local as u32,
                // load_obj guarantees a material when asked for them.
                (None, None) => return Err(self.error(&key("path"), "a face has no material")),
            };
            triangles.push(Triangle { vertices, material });
        }
        Ok(())
    }
}

/// `samples` must be a perfect square k * k with k >= 1.
pub fn check_samples(samples: u32) -> Result<(), String> {
    let k = (samples as f64).sqrt().round() as u32;
    if samples == 0 || k * k != samples {
        return Err(format!(
            "must be a perfect square (1, 4, 9, 16, ...), got {samples}"
        ));
    }
    Ok(())
}

/// Rz * Ry * Rx * diag(scale), angles in degrees about the world axes.
pub fn mesh_transform(scale: DVec3, rotate_degrees: DVec3) -> DMat3 {
    let r = rotate_degrees * (std::f64::consts::PI / 180.0);
    DMat3::from_rotation_z(r.z)
        * DMat3::from_rotation_y(r.y)
        * DMat3::from_rotation_x(r.x)
        * DMat3::from_diagonal(scale)
}

fn has_area(v: &[DVec3; 3]) -> bool {
    (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0
}
