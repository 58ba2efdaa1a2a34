//! Scene files (TOML, or the same schema as JSON) to a validated [`Scene`].
//!
//! Two stages: serde reads the document into `Raw*` structs that mirror the
//! file exactly (unknown keys rejected), then `Validator` checks every rule
//! of docs/scene-format.md and builds the world-space scene, loading meshes.
//! Every error names the file, the line (via [`SourceMap`]) and the key.

use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;
use std::path::Path;

use glam::{DMat3, DVec3};
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
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
            let map = SourceMap::toml(text);
            match toml::from_str::<RawScene>(text) {
                Ok(raw) => (raw, map),
                Err(e) => return Err(toml_error(&e, text, map.as_ref(), path)),
            }
        }
        SceneFormat::Json => {
            let map = SourceMap::json(text);
            match serde_json::from_str::<RawScene>(text) {
                Ok(raw) => (raw, map),
                Err(e) => return Err(json_error(&e, map.as_ref(), path)),
            }
        }
    };
    Validator { file: path, map }.scene(raw)
}

/// A syntax or schema error from the toml crate, located by its byte span.
fn toml_error(e: &toml::de::Error, text: &str, map: Option<&SourceMap>, path: &Path) -> SceneError {
    let span = e.span();
    let (line, key) = match (map, span) {
        // The document parsed, so this is a schema error. An empty span is
        // how the toml crate reports one about the whole document (a missing
        // top-level table): it has no line and no key.
        (Some(_), Some(s)) if s.is_empty() => (None, None),
        (Some(m), Some(s)) => (
            Some(m.line_of_offset(s.start)),
            m.path_at_span(s).map(str::to_string),
        ),
        // A syntax error: count lines ourselves (no map without a parse).
        (None, Some(s)) => {
            let before = &text.as_bytes()[..s.start.min(text.len())];
            (
                Some(before.iter().filter(|&&b| b == b'\n').count() + 1),
                None,
            )
        }
        (_, None) => (None, None),
    };
    let mut message = e.message().to_string();
    if message == "floating-point number overflowed" {
        // 1e999: the same rule as nan and inf.
        message.push_str(": must be a finite number");
    } else if message == "duplicate key" {
        // Say which: the span is the repeated key.
        if let Some(name) = span_text(text, e.span()) {
            message = format!("duplicate key `{name}`");
        }
    }
    SceneError::new(path, line, key, message)
}

fn span_text(text: &str, span: Option<std::ops::Range<usize>>) -> Option<&str> {
    let name = text.get(span?)?.trim();
    (!name.is_empty() && !name.contains('\n')).then_some(name)
}

/// A syntax or schema error from serde_json, located by its line and column
/// (the column of the last character it read).
fn json_error(e: &serde_json::Error, map: Option<&SourceMap>, path: &Path) -> SceneError {
    let key = map
        .and_then(|m| m.path_at(m.offset_of(e.line(), e.column())))
        .map(str::to_string);
    // serde_json appends " at line L column C"; the line is ours to print.
    let message = e.to_string();
    let mut message = message
        .rsplit_once(" at line ")
        .map_or(message.as_str(), |(m, _)| m)
        .to_string();
    if message == "number out of range" {
        // 1e999 and the like: JSON has no inf, and serde_json will not round.
        message.push_str(": must be a finite number");
    }
    // A schema error outside every key is about the whole document (a
    // missing top-level table); serde_json puts it at the closing brace,
    // which is no help, so name no line.
    let whole_document = e.is_data() && key.is_none();
    let line = (e.line() > 0 && !whole_document).then_some(e.line());
    SceneError::new(path, line, key, message)
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
    #[serde(default, deserialize_with = "unique_names")]
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
    /// None: the default [0, 1, 0] (kept apart so that an error can say so).
    up: Option<Vec3>,
    #[serde(default = "default_vfov")]
    vfov: f64,
}

const DEFAULT_UP: Vec3 = [0.0, 1.0, 0.0];
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

/// `scale = 2` or `scale = [x, y, z]`. Written by hand rather than as an
/// untagged enum so that serde_json reports a bad value at the value itself
/// (an untagged enum's error only surfaces at the end of the enclosing table).
enum RawScale {
    Uniform(f64),
    PerAxis(Vec3),
}

impl<'de> Deserialize<'de> for RawScale {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ScaleVisitor;
        impl<'de> Visitor<'de> for ScaleVisitor {
            type Value = RawScale;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a number or an array of 3 numbers")
            }
            fn visit_f64<E: de::Error>(self, x: f64) -> Result<RawScale, E> {
                Ok(RawScale::Uniform(x))
            }
            fn visit_i64<E: de::Error>(self, x: i64) -> Result<RawScale, E> {
                Ok(RawScale::Uniform(x as f64))
            }
            fn visit_u64<E: de::Error>(self, x: u64) -> Result<RawScale, E> {
                Ok(RawScale::Uniform(x as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RawScale, A::Error> {
                let mut v = [0.0; 3];
                for (i, x) in v.iter_mut().enumerate() {
                    *x = seq
                        .next_element()?
                        .ok_or_else(|| de::Error::invalid_length(i, &self))?;
                }
                if seq.next_element::<de::IgnoredAny>()?.is_some() {
                    return Err(de::Error::invalid_length(4, &self));
                }
                Ok(RawScale::PerAxis(v))
            }
        }
        deserializer.deserialize_any(ScaleVisitor)
    }
}

/// A map whose keys must be unique: TOML rejects a repeated key itself, but
/// serde_json would silently keep the last of two `"red"` materials.
fn unique_names<'de, D, V>(deserializer: D) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct MapVisitor<V>(PhantomData<V>);
    impl<'de, V: Deserialize<'de>> Visitor<'de> for MapVisitor<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            f.write_str("a table of named materials")
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(name) = map.next_key::<String>()? {
                if out.contains_key(&name) {
                    return Err(de::Error::custom(format!(
                        "material \"{name}\" is defined twice"
                    )));
                }
                let value = map.next_value()?;
                out.insert(name, value);
            }
            Ok(out)
        }
    }
    deserializer.deserialize_map(MapVisitor(PhantomData))
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
    /// An error at `key`, on the line of the key or, when the file leaves it
    /// out (a default is at fault), of the nearest enclosing table it has.
    fn error(&self, key: &str, message: impl Into<String>) -> SceneError {
        let line = self.map.as_ref().and_then(|m| {
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

    fn number(&self, key: &str, x: f64) -> Result<f64, SceneError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(key, format!("must be a finite number, got {x:?}")))
        }
    }

    /// A finite vector; a bad component is named by its index, `key[i]`.
    fn vector(&self, key: &str, v: Vec3) -> Result<DVec3, SceneError> {
        for (i, x) in v.into_iter().enumerate() {
            self.number(&format!("{key}[{i}]"), x)?;
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
            // Names the line of `lights = []` when there is one.
            return Err(self.error("lights", "a scene needs at least one [[lights]] entry"));
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
                return Err(self.error(
                    &key("shininess"),
                    format!("must be >= 0, got {shininess:?}"),
                ));
            }
            let reflection = self.number(&key("reflection"), m.reflection)?;
            if !(0.0..=1.0).contains(&reflection) {
                return Err(self.error(
                    &key("reflection"),
                    format!("must be in [0, 1], got {reflection:?}"),
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
                return Err(self.error(&key("radius"), format!("must be > 0, got {radius:?}")));
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
            for (j, (v, raw_v)) in vertices.iter_mut().zip(t.vertices).enumerate() {
                *v = self.vector(&format!("{}[{j}]", key("vertices")), raw_v)?;
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
        let up = self.vector("camera.up", c.up.unwrap_or(DEFAULT_UP))?;
        let vfov_degrees = self.number("camera.vfov", c.vfov)?;
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
        if unit(up).is_none_or(|up| forward.cross(up).length() < 1e-9) {
            return Err(self.error(
                "camera.up",
                format!(
                    "must not be zero or parallel to look_at - position, got {:?}{}",
                    c.up.unwrap_or(DEFAULT_UP),
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
        let min_intensity = self.number("render.min_intensity", r.min_intensity.unwrap_or(0.05))?;
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
            RawScale::Uniform(s) => DVec3::splat(self.number(&key("scale"), s)?),
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
        let mesh = obj::load_obj(&obj_path, override_material.is_none()).map_err(|e| {
            if e.line.is_some() {
                return e;
            }
            // An OBJ that cannot be read at all: also say which entry asked for it.
            let at = match self.map.as_ref().and_then(|m| m.line_of_path(&key("path"))) {
                Some(line) => format!("{}:{line}", self.file.display()),
                None => self.file.display().to_string(),
            };
            let message = format!("{} (from {} in {at})", e.message, key("path"));
            SceneError::new(&e.file, e.line, e.key, message)
        })?;

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

/// Rz * Ry * Rx * diag(scale), angles in degrees about the world axes.
pub fn mesh_transform(scale: DVec3, rotate_degrees: DVec3) -> DMat3 {
    let r = rotate_degrees * (std::f64::consts::PI / 180.0);
    DMat3::from_rotation_z(r.z)
        * DMat3::from_rotation_y(r.y)
        * DMat3::from_rotation_x(r.x)
        * DMat3::from_diagonal(scale)
}

/// `v` scaled to length 1, or None for the zero vector. Safe for finite
/// vectors of any size (no overflow or underflow in the length).
fn unit(v: DVec3) -> Option<DVec3> {
    let largest = v.abs().max_element();
    (largest > 0.0).then(|| (v / largest).normalize())
}

fn has_area(v: &[DVec3; 3]) -> bool {
    (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0
}
