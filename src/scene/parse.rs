//! Scene files (TOML, or the same schema as JSON) to a validated [`Scene`].
//!
//! Two stages: serde reads the document into `Raw*` structs that mirror the
//! file exactly (unknown keys rejected), then `Validator` checks every rule
//! of docs/scene-format.md and builds the world-space scene, loading meshes.
//! Every error names the file, the line (via [`SourceMap`]) and the key.

use std::cell::{OnceCell, RefCell};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;
use std::path::Path;

use glam::{DMat3, DVec3};
use rayon::prelude::*;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use super::mesh::{self, Mesh, MeshTriangle};
use super::normals::{self, unit};
use super::source_map::SourceMap;
use super::{
    Camera, Light, Material, RenderSettings, Scene, SceneError, ShadowMode, Sphere, Triangle,
};

/// Largest accepted image side, in pixels.
pub const MAX_IMAGE_SIDE: u32 = 16384;
/// Largest coordinate or radius accepted: the GPU computes in f32 and squares
/// distances, which must stay below f32::MAX (3.4e38).
pub const MAX_COORDINATE: f64 = 1e15;
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

/// Reads and validates a scene file; mesh paths are relative to its folder.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    load_scene_observed(path, &mut |_| {})
}

/// [`load_scene`], calling `on_read` with every file it reads (the scene
/// file first, then each mesh and its MTL or buffer files), just before
/// reading it, and also for a file that then fails: the list of files a
/// reload must watch, the file that broke included.
pub fn load_scene_observed(
    path: &Path,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Scene, SceneError> {
    on_read(path);
    let bytes = super::read_input_file(path).map_err(|e| {
        SceneError::new(path, None, None, format!("cannot read scene file: {e}")).with_source(e)
    })?;
    let text = String::from_utf8(bytes).map_err(|e| {
        SceneError::new(
            path,
            None,
            None,
            format!("cannot read scene file: not UTF-8 text ({e})"),
        )
        .with_source(e)
    })?;
    parse_observed(&text, path, SceneFormat::from_path(path), on_read)
}

/// Parses scene text; `path` names the file in errors and anchors mesh paths.
pub fn parse_scene(text: &str, path: &Path, format: SceneFormat) -> Result<Scene, SceneError> {
    parse_observed(text, path, format, &mut |_| {})
}

fn parse_observed(
    text: &str,
    path: &Path,
    format: SceneFormat,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Scene, SceneError> {
    let map = LazySourceMap {
        text,
        format,
        map: OnceCell::new(),
    };
    let raw = match format {
        SceneFormat::Toml => toml::from_str::<TableOf<RawScene>>(text)
            .map_err(|e| toml_error(e, text, map.get(), path))?,
        SceneFormat::Json => serde_json::from_str::<TableOf<RawScene>>(text)
            .map_err(|e| json_error(e, text, map.get(), path))?,
    };
    Validator {
        file: path,
        map,
        on_read: RefCell::new(on_read),
    }
    .scene(raw.0)
}

/// Where each key of the text is, for error messages. Made on the first
/// error only: a scene that loads never needs it, and for a big scene it
/// would cost a second parse and an entry per key (100 MB of TOML with a
/// million spheres: seconds, and gigabytes of memory).
struct LazySourceMap<'a> {
    text: &'a str,
    format: SceneFormat,
    map: OnceCell<Option<SourceMap>>,
}

impl LazySourceMap<'_> {
    /// The map; None if the text does not parse as TOML or JSON.
    fn get(&self) -> Option<&SourceMap> {
        self.map
            .get_or_init(|| match self.format {
                SceneFormat::Toml => SourceMap::toml(self.text),
                SceneFormat::Json => SourceMap::json(self.text),
            })
            .as_ref()
    }
}

/// A syntax or schema error from the toml crate, located by its byte span.
fn toml_error(e: toml::de::Error, text: &str, map: Option<&SourceMap>, path: &Path) -> SceneError {
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
    SceneError::new(path, line, key, message).with_source(e)
}

/// The run of letters, digits, `+`, `-` and `.` around byte `offset`.
fn word_at(text: &str, offset: usize) -> &str {
    let bytes = text.as_bytes();
    let is_word = |b: u8| b.is_ascii_alphanumeric() || b"+-.".contains(&b);
    let offset = offset.min(bytes.len());
    let start = bytes[..offset]
        .iter()
        .rposition(|&b| !is_word(b))
        .map_or(0, |i| i + 1);
    let end = bytes[offset..]
        .iter()
        .position(|&b| !is_word(b))
        .map_or(bytes.len(), |i| offset + i);
    // `offset` itself may be inside a multi-byte character.
    text.get(start..end).unwrap_or("")
}

fn span_text(text: &str, span: Option<std::ops::Range<usize>>) -> Option<&str> {
    let name = text.get(span?)?.trim();
    (!name.is_empty() && !name.contains('\n')).then_some(name)
}

/// A syntax or schema error from serde_json, located by its line and column
/// (the column of the last character it read).
fn json_error(
    e: serde_json::Error,
    text: &str,
    map: Option<&SourceMap>,
    path: &Path,
) -> SceneError {
    // The byte serde_json stopped at (its column counts bytes, from 1).
    let line_start = match e.line() {
        0 | 1 => Some(0),
        n => text.match_indices('\n').nth(n - 2).map(|(i, _)| i + 1),
    };
    let mut offset = line_start.map(|start| start + e.column().saturating_sub(1));
    // For an array or object of the wrong type serde_json has not yet read
    // its `[` or `{`: it reports the byte before it. Name the value itself.
    let message = e.to_string();
    if message.starts_with("invalid type: sequence") || message.starts_with("invalid type: map") {
        offset = offset.map(|o| {
            let rest = text.as_bytes().get(o + 1..).unwrap_or_default();
            o + 1 + rest.iter().take_while(|b| b.is_ascii_whitespace()).count()
        });
    }
    let key = map
        .zip(offset)
        .and_then(|(m, o)| m.path_at(o))
        .map(str::to_string);
    // serde_json appends " at line L column C"; the line is ours to print.
    let mut message = message
        .rsplit_once(" at line ")
        .map_or(message.as_str(), |(m, _)| m)
        .to_string();
    if message == "number out of range" {
        // 1e999 and the like: JSON has no inf, and serde_json will not round.
        message.push_str(": must be a finite number");
    } else if e.is_syntax() {
        // NaN and Infinity are not JSON; say so rather than just "expected value".
        let word = offset.map_or("", |o| word_at(text, o));
        if ["nan", "infinity", "-infinity", "inf", "-inf"]
            .contains(&word.to_ascii_lowercase().as_str())
        {
            message.push_str(&format!(
                ": `{word}` is not a JSON number (JSON has no NaN or infinity; numbers must be finite)"
            ));
        }
    }
    // A schema error outside every key is about the whole document (a
    // missing top-level table); serde_json puts it at the closing brace,
    // which is no help, so name no line.
    let whole_document = e.is_data() && key.is_none();
    let line = (e.line() > 0 && !whole_document).then_some(e.line());
    SceneError::new(path, line, key, message).with_source(e)
}

// ---------------------------------------------------------------- raw file

/// `[x, y, z]` (or `[r, g, b]`).
type Vec3 = Exact<f64, 3>;

/// An array of exactly `N` items. serde's own `[T; N]` leaves the length
/// check to the format, and the toml crate does not make it: `[1, 2, 3, 4]`
/// would be read as `[1, 2, 3]`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Exact<T, const N: usize>([T; N]);

impl<T: Default + Copy, const N: usize> Default for Exact<T, N> {
    fn default() -> Self {
        Exact([T::default(); N])
    }
}

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ExactVisitor<T, const N: usize>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for ExactVisitor<T, N> {
            type Value = Exact<T, N>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "an array of length {N}")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut items = Vec::with_capacity(N);
                while let Some(item) = seq.next_element()? {
                    items.push(item);
                    if items.len() > N {
                        let mut len = items.len();
                        while seq.next_element::<de::IgnoredAny>()?.is_some() {
                            len += 1;
                        }
                        return Err(de::Error::invalid_length(len, &self));
                    }
                }
                let len = items.len();
                let items: [T; N] = items
                    .try_into()
                    .map_err(|_| de::Error::invalid_length(len, &self))?;
                Ok(Exact(items))
            }
        }
        deserializer.deserialize_seq(ExactVisitor(PhantomData))
    }
}

impl<T: Serialize, const N: usize> Serialize for Exact<T, N> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.0.as_slice().serialize(serializer)
    }
}

/// A struct read only from a table (a JSON object). serde's derive would
/// also take a struct as an array of its fields in order, which is no part of
/// the format: `camera = [[0, 0, 1], [0, 0, 0]]` must be a type error.
#[derive(Default)]
struct TableOf<T>(T);

/// What a table is called in "invalid type: ..., expected ..." errors.
trait Described {
    const WHAT: &'static str;
}

impl Described for RawScene {
    const WHAT: &'static str = "a scene (a table of [camera], [render], [[lights]], [materials], [[spheres]], [[triangles]], [[meshes]])";
}
impl Described for RawCamera {
    const WHAT: &'static str = "a [camera] table";
}
impl Described for RawRender {
    const WHAT: &'static str = "a [render] table";
}
impl Described for RawLight {
    const WHAT: &'static str = "a [[lights]] table";
}
impl Described for RawMaterial {
    const WHAT: &'static str = "a material table";
}
impl Described for RawSphere {
    const WHAT: &'static str = "a [[spheres]] table";
}
impl Described for RawTriangle {
    const WHAT: &'static str = "a [[triangles]] table";
}
impl Described for RawMesh {
    const WHAT: &'static str = "a [[meshes]] table";
}

impl<T: Serialize> Serialize for TableOf<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.0.serialize(serializer)
    }
}

impl<T> std::ops::Deref for TableOf<T> {
    type Target = T;
    fn deref(&self) -> &T {
        &self.0
    }
}

impl<'de, T: Deserialize<'de> + Described> Deserialize<'de> for TableOf<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct TableVisitor<T>(PhantomData<T>);
        impl<'de, T: Deserialize<'de> + Described> Visitor<'de> for TableVisitor<T> {
            type Value = TableOf<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str(T::WHAT)
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<Self::Value, A::Error> {
                T::deserialize(de::value::MapAccessDeserializer::new(map)).map(TableOf)
            }
        }
        deserializer.deserialize_map(TableVisitor(PhantomData))
    }
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawScene {
    camera: TableOf<RawCamera>,
    #[serde(default)]
    render: TableOf<RawRender>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    lights: Vec<TableOf<RawLight>>,
    #[serde(
        default,
        deserialize_with = "unique_names",
        skip_serializing_if = "BTreeMap::is_empty"
    )]
    materials: BTreeMap<String, TableOf<RawMaterial>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    spheres: Vec<TableOf<RawSphere>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    triangles: Vec<TableOf<RawTriangle>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    meshes: Vec<TableOf<RawMesh>>,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawCamera {
    position: Vec3,
    look_at: Vec3,
    /// None: the default [0, 1, 0] (kept apart so that an error can say so).
    #[serde(skip_serializing_if = "Option::is_none")]
    up: Option<Vec3>,
    #[serde(default = "default_vfov")]
    vfov: f64,
}

const DEFAULT_UP: Vec3 = Exact([0.0, 1.0, 0.0]);
fn default_vfov() -> f64 {
    60.0
}
fn white() -> Vec3 {
    Exact([1.0; 3])
}

#[derive(Deserialize, Serialize, Default)]
#[serde(deny_unknown_fields)]
struct RawRender {
    #[serde(skip_serializing_if = "Option::is_none")]
    width: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    height: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    min_intensity: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_depth: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    background: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    shadow_mode: Option<RawShadowMode>,
    #[serde(skip_serializing_if = "Option::is_none")]
    samples: Option<u32>,
}

/// `"ambient"` or `"seed"`. Read as a plain string: the toml crate's own
/// enum errors ("wanted string or table") would not say what is expected.
enum RawShadowMode {
    Ambient,
    Seed,
}

impl Serialize for RawShadowMode {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(match self {
            RawShadowMode::Ambient => "ambient",
            RawShadowMode::Seed => "seed",
        })
    }
}

impl<'de> Deserialize<'de> for RawShadowMode {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct ModeVisitor;
        impl Visitor<'_> for ModeVisitor {
            type Value = RawShadowMode;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("\"ambient\" or \"seed\"")
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<RawShadowMode, E> {
                match v {
                    "ambient" => Ok(RawShadowMode::Ambient),
                    "seed" => Ok(RawShadowMode::Seed),
                    _ => Err(de::Error::unknown_variant(v, &["ambient", "seed"])),
                }
            }
        }
        deserializer.deserialize_str(ModeVisitor)
    }
}

#[derive(Deserialize, Serialize)]
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

#[derive(Deserialize, Serialize)]
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

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawSphere {
    center: Vec3,
    radius: f64,
    material: String,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawTriangle {
    vertices: Exact<Vec3, 3>,
    material: String,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
struct RawMesh {
    path: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    material: Option<String>,
    /// true: smooth normals (the file's, else computed); false: flat; None:
    /// the file's normals where it has them, else flat.
    #[serde(skip_serializing_if = "Option::is_none")]
    smooth: Option<bool>,
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

impl Serialize for RawScale {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            RawScale::Uniform(x) => serializer.serialize_f64(*x),
            RawScale::PerAxis(v) => v.serialize(serializer),
        }
    }
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
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<RawScale, A::Error> {
                Vec3::deserialize(de::value::SeqAccessDeserializer::new(seq)).map(RawScale::PerAxis)
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

// ---------------------------------------------------------------- writing

/// `scene` as the text of a scene file that [`parse_scene`] reads back as an
/// equal `Scene`, provided its material names are distinct and sort in index
/// order (materials are a table keyed by name, read back in name order), and
/// its triangles are flat: `[[triangles]]` entries carry no normals, and the
/// mesh files a scene was loaded from are not named (their triangles are
/// written out). Written through the same serde types the reader uses.
pub fn scene_text(scene: &Scene, format: SceneFormat) -> Result<String, String> {
    let v = |d: DVec3| Exact(d.to_array());
    let mut materials = BTreeMap::new();
    for m in &scene.materials {
        let raw = RawMaterial {
            ambient: v(m.ambient),
            diffuse: v(m.diffuse),
            specular: v(m.specular),
            shininess: m.shininess,
            reflection: m.reflection,
        };
        if materials.insert(m.name.clone(), TableOf(raw)).is_some() {
            return Err(format!("two materials are named \"{}\"", m.name));
        }
    }
    let name = |i: u32| {
        scene
            .materials
            .get(i as usize)
            .map(|m| m.name.clone())
            .ok_or_else(|| format!("material index {i} is out of range"))
    };
    let r = &scene.render;
    let raw = RawScene {
        camera: TableOf(RawCamera {
            position: v(scene.camera.position),
            look_at: v(scene.camera.look_at),
            up: Some(v(scene.camera.up)),
            vfov: scene.camera.vfov_degrees,
        }),
        render: TableOf(RawRender {
            width: Some(r.width),
            height: Some(r.height),
            min_intensity: Some(r.min_intensity),
            max_depth: Some(r.max_depth),
            background: Some(v(r.background)),
            shadow_mode: Some(match r.shadow_mode {
                ShadowMode::Ambient => RawShadowMode::Ambient,
                ShadowMode::Seed => RawShadowMode::Seed,
            }),
            samples: Some(r.samples),
        }),
        lights: scene
            .lights
            .iter()
            .map(|l| {
                TableOf(RawLight {
                    position: v(l.position),
                    ambient: v(l.ambient),
                    diffuse: v(l.diffuse),
                    specular: v(l.specular),
                })
            })
            .collect(),
        materials,
        spheres: scene
            .spheres
            .iter()
            .map(|s| {
                Ok(TableOf(RawSphere {
                    center: v(s.center),
                    radius: s.radius,
                    material: name(s.material)?,
                }))
            })
            .collect::<Result<_, String>>()?,
        triangles: scene
            .triangles
            .iter()
            .map(|t| {
                Ok(TableOf(RawTriangle {
                    vertices: Exact(t.vertices.map(v)),
                    material: name(t.material)?,
                }))
            })
            .collect::<Result<_, String>>()?,
        meshes: Vec::new(),
    };
    match format {
        SceneFormat::Toml => toml::to_string(&raw).map_err(|e| e.to_string()),
        SceneFormat::Json => serde_json::to_string(&raw)
            .map(|mut text| {
                text.push('\n');
                text
            })
            .map_err(|e| e.to_string()),
    }
}

// ---------------------------------------------------------------- validation

struct Validator<'a> {
    file: &'a Path,
    map: LazySourceMap<'a>,
    /// Told of each file just before it is read.
    on_read: RefCell<&'a mut dyn FnMut(&Path)>,
}

/// The path of a key, made only when an error names it: made for every
/// number and material name, a million spheres' seven million paths, that
/// no error read, were 0.53 s of their JSON file's 1.0 s load.
type KeyPath<'a> = &'a dyn Fn() -> String;

impl Validator<'_> {
    /// An error at `key`, on the line of the key or, when the file leaves it
    /// out (a default is at fault), of the nearest enclosing table it has.
    fn error(&self, key: &str, message: impl Into<String>) -> SceneError {
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

    fn number(&self, key: KeyPath, x: f64) -> Result<f64, SceneError> {
        if x.is_finite() {
            Ok(x)
        } else {
            Err(self.error(&key(), format!("must be a finite number, got {x:?}")))
        }
    }

    /// A finite vector; a bad component is named by its index, `key[i]`.
    fn vector(&self, key: KeyPath, v: Vec3) -> Result<DVec3, SceneError> {
        for (i, x) in v.0.into_iter().enumerate() {
            self.number(&|| format!("{}[{i}]", key()), x)?;
        }
        Ok(DVec3::from_array(v.0))
    }

    /// A point in space: finite, and within ±MAX_COORDINATE so that the
    /// GPU's f32 arithmetic (which squares distances) cannot overflow.
    fn position(&self, key: KeyPath, v: Vec3) -> Result<DVec3, SceneError> {
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

    fn colour(&self, key: KeyPath, v: Vec3) -> Result<DVec3, SceneError> {
        let c = self.vector(key, v)?;
        if c.min_element() < 0.0 {
            return Err(self.error(
                &key(),
                format!("colour components must be >= 0, got {:?}", v.0),
            ));
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
                    position: self.position(&|| key("position"), l.position)?,
                    ambient: self.colour(&|| key("ambient"), l.ambient)?,
                    diffuse: self.colour(&|| key("diffuse"), l.diffuse)?,
                    specular: self.colour(&|| key("specular"), l.specular)?,
                })
            })
            .collect::<Result<Vec<_>, SceneError>>()?;

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
            material_index.insert(name.clone(), materials.len() as u32);
            materials.push(Material {
                name: name.clone(),
                ambient: self.colour(&|| key("ambient"), m.ambient)?,
                diffuse: self.colour(&|| key("diffuse"), m.diffuse)?,
                specular: self.colour(&|| key("specular"), m.specular)?,
                shininess,
                reflection,
            });
        }
        let lookup = |key: KeyPath, name: &str| {
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
        };

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
                material: lookup(&|| key("material"), &s.material)?,
            });
        }

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
                lookup(&|| key("material"), &t.material)?,
            ));
        }

        let mut triangle_normals = Vec::new();
        for (i, m) in raw.meshes.iter().enumerate() {
            let override_material = match &m.material {
                Some(name) => Some(lookup(&|| format!("meshes[{i}].material"), name)?),
                None => None,
            };
            self.mesh(
                i,
                m,
                override_material,
                &mut materials,
                &mut triangles,
                &mut triangle_normals,
            )?;
        }

        Ok(Scene {
            camera,
            render,
            lights,
            materials,
            spheres,
            triangles,
            triangle_normals,
        })
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
        if unit(up).is_none_or(|up| forward.cross(up).length() < 1e-9) {
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
        let samples = r.samples.unwrap_or(1);
        check_samples(samples).map_err(|m| self.error("render.samples", m))?;
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
        normals: &mut Vec<[DVec3; 3]>,
    ) -> Result<(), SceneError> {
        let key = |k: &str| format!("meshes[{i}].{k}");
        let scale = match m.scale {
            RawScale::Uniform(s) => DVec3::splat(self.number(&|| key("scale"), s)?),
            RawScale::PerAxis(v) => self.vector(&|| key("scale"), v)?,
        };
        if scale.abs().min_element() == 0.0 {
            return Err(self.error(&key("scale"), "must be non-zero on every axis"));
        }
        let rotate = self.vector(&|| key("rotate"), m.rotate)?;
        let translate = self.position(&|| key("translate"), m.translate)?;
        let transform = mesh_transform(scale, rotate);

        let base = self.file.parent().unwrap_or(Path::new(""));
        let mesh_path = base.join(&m.path);
        let mesh = {
            let mut on_read = self.on_read.borrow_mut();
            mesh::load_mesh(&mesh_path, override_material.is_none(), &mut **on_read)
        }
        .map_err(|e| {
            if e.line.is_some() {
                return e;
            }
            // A mesh file at fault as a whole: also say which entry asked for it.
            let at = match self.map.get().and_then(|m| m.line_of_path(&key("path"))) {
                Some(line) => format!("{}:{line}", self.file.display()),
                None => self.file.display().to_string(),
            };
            let message = format!("{} (from {} in {at})", e.message, key("path"));
            e.reworded(message)
        })?;

        let first_material = materials.len() as u32;
        if override_material.is_none() {
            let file_name = Path::new(&m.path)
                .file_name()
                .map_or(m.path.clone(), |f| f.to_string_lossy().into_owned());
            // The mesh readers check that colours are finite; the scene's
            // rule that colours are >= 0 holds for them too.
            for mm in &mesh.materials {
                let colours = [("Ka", mm.ambient), ("Kd", mm.diffuse), ("Ks", mm.specular)];
                if let Some((statement, c)) = colours.iter().find(|(_, c)| c.min_element() < 0.0) {
                    let (kind, what) = match mesh::MeshFormat::of_path(&mesh_path) {
                        Some(mesh::MeshFormat::Gltf) => ("glTF", "colour"),
                        _ => ("MTL", *statement),
                    };
                    return Err(self.error(
                        &key("path"),
                        format!(
                            "{kind} material \"{}\" has a negative {what} colour {:?}; colour components must be >= 0",
                            mm.name,
                            c.to_array()
                        ),
                    ));
                }
            }
            materials.extend(mesh.materials.iter().map(|mm| Material {
                name: format!("{file_name}:{}", mm.name),
                ambient: mm.ambient,
                diffuse: mm.diffuse,
                specular: mm.specular,
                shininess: mm.shininess,
                reflection: mm.reflection,
            }));
        }
        let world = self.place(i, &mesh, transform, translate)?;
        let shading = MeshNormals::new(m.smooth, &mesh, &world, transform);
        let material_of = |t: &MeshTriangle| match (override_material, t.material()) {
            (Some(m), _) => Some(m),
            (None, Some(local)) => Some(first_material + local as u32),
            (None, None) => None,
        };
        // Usually every triangle is kept (none collapsed, every index in
        // range): then they are built on all threads, straight into the
        // scene's vector (rayon writes an indexed iterator in place), which
        // on two cores also halves the wait for its fresh pages. Built first
        // and checked on the way (a separate pass of checks took 15 ms of
        // the 1.1 M-triangle bunny's 0.22 s load); where one is not kept,
        // they are dropped and built again below.
        let (first, first_normals) = (triangles.len(), normals.len());
        let all_kept = std::sync::atomic::AtomicBool::new(true);
        let kept = |t: &MeshTriangle| {
            let vertices = t.corners_in(&world).filter(has_area);
            let kept = vertices.zip(material_of(t));
            if kept.is_none() {
                all_kept.store(false, std::sync::atomic::Ordering::Relaxed);
            }
            kept.unwrap_or_default()
        };
        triangles.reserve(mesh.triangles.len());
        crate::huge_pages::advise(triangles);
        if let MeshNormals::Flat = shading {
            triangles.par_extend(mesh.triangles.par_iter().map(|t| {
                let (vertices, material) = kept(t);
                Triangle::flat(vertices, material)
            }));
        } else {
            // Triangle i's normals at `first_normals + i` (left unused,
            // zero, for the rare triangle shaded flat): so each triangle
            // knows its index, and both vectors are written in place. (An
            // index past u32 cannot arise: the tree holds at most 2^30
            // objects.)
            normals.reserve(mesh.triangles.len());
            crate::huge_pages::advise(normals);
            let pairs = mesh.triangles.par_iter().enumerate().map(|(i, t)| {
                let (vertices, material) = kept(t);
                let n = shading.of(t, &vertices);
                let index = u32::try_from(first_normals + i)
                    .ok()
                    .filter(|_| n.is_some());
                let triangle = Triangle {
                    vertices,
                    material,
                    normals: index.unwrap_or(Triangle::FLAT),
                };
                (triangle, n.unwrap_or_default())
            });
            let mut both = (std::mem::take(triangles), std::mem::take(normals));
            both.par_extend(pairs);
            (*triangles, *normals) = both;
        }
        if all_kept.into_inner() {
            crate::huge_pages::free_in_background((mesh, world, shading));
            return Ok(());
        }
        triangles.truncate(first);
        normals.truncate(first_normals);
        // Otherwise one by one: collapsed triangles skipped, the first fault
        // reported.
        for t in &mesh.triangles {
            let Some(vertices) = t.corners_in(&world) else {
                // The readers write only indices in range.
                return Err(self.error(&key("path"), "a face has a vertex index out of range"));
            };
            if !has_area(&vertices) {
                continue; // collapsed by an extreme scale: it can never be hit
            }
            let Some(material) = material_of(t) else {
                // The readers guarantee a material when asked for them.
                return Err(self.error(&key("path"), "a face has no material"));
            };
            let mut triangle = Triangle::flat(vertices, material);
            if let Some(n) = shading.of(t, &vertices) {
                triangle.normals = u32::try_from(normals.len()).unwrap_or(Triangle::FLAT);
                normals.push(n);
            }
            triangles.push(triangle);
        }
        Ok(())
    }

    /// The mesh's shared vertices in world space, each transformed once.
    /// A vertex that lands beyond the GPU's range is an error only where a
    /// triangle uses it (an OBJ file may define vertices no face uses).
    fn place(
        &self,
        i: usize,
        mesh: &Mesh,
        transform: DMat3,
        translate: DVec3,
    ) -> Result<Vec<DVec3>, SceneError> {
        let world: Vec<DVec3> = mesh
            .positions
            .par_iter()
            .map(|&v| transform * v + translate)
            .collect();
        let in_range = |v: &DVec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
        // Usually every vertex is in range, and the triangles need no look.
        if !world.par_iter().all(in_range) {
            let uses_one_out_of_range = mesh.triangles.iter().any(|t| {
                t.corners
                    .iter()
                    .any(|&c| world.get(c as usize).is_some_and(|v| !in_range(v)))
            });
            if uses_one_out_of_range {
                return Err(self.error(
                    &format!("meshes[{i}].scale"),
                    "the transformed mesh has a non-finite vertex, or one beyond ±1e15 (the GPU computes in f32)",
                ));
            }
        }
        Ok(world)
    }
}

/// How a mesh entry's triangles are shaded: flat, or with normals from the
/// file (carried to world space) and/or computed from the faces.
enum MeshNormals {
    Flat,
    /// The file's normals where all three corners of a triangle have one.
    FromFile {
        /// Each of the file's normals in world space, of unit length; None
        /// where it cannot be normalised.
        file: Vec<Option<DVec3>>,
    },
    /// The file's normals where a corner has one, else the angle-weighted
    /// normal of its shared vertex (computed in world space).
    Smooth {
        file: Vec<Option<DVec3>>,
        computed: Vec<DVec3>,
    },
}

impl MeshNormals {
    /// `world`: the mesh's vertices in world space.
    fn new(smooth: Option<bool>, mesh: &Mesh, world: &[DVec3], transform: DMat3) -> Self {
        // Each file normal carried once (not once per corner that names it).
        let file_normals = || {
            let normal_matrix = normals::normal_matrix(transform);
            mesh.normals
                .iter()
                .map(|&n| unit(normal_matrix * n))
                .collect()
        };
        match smooth {
            Some(false) => MeshNormals::Flat,
            // A file without normals is flat unless asked otherwise.
            None if mesh.normals.is_empty() => MeshNormals::Flat,
            None => MeshNormals::FromFile {
                file: file_normals(),
            },
            Some(true) => MeshNormals::Smooth {
                file: file_normals(),
                computed: normals::angle_weighted(world, &mesh.triangles, |t| {
                    t.corners.map(|c| c as usize)
                }),
            },
        }
    }

    /// The world-space unit normals of `t` (placed at `vertices`), or None
    /// for flat shading. A normal that cannot be normalised (zero in the
    /// file, or a vertex whose faces cancel) is the face's own normal.
    fn of(&self, t: &MeshTriangle, vertices: &[DVec3; 3]) -> Option<[DVec3; 3]> {
        let face = || unit((vertices[1] - vertices[0]).cross(vertices[2] - vertices[0]));
        let from_file = |file: &[Option<DVec3>], k: usize| {
            t.normal(k).and_then(|n| file.get(n).copied().flatten())
        };
        match self {
            MeshNormals::Flat => None,
            MeshNormals::FromFile { file } => {
                if (0..3).any(|k| t.normal(k).is_none()) {
                    return None;
                }
                let face = face()?;
                Some([0, 1, 2].map(|k| from_file(file, k).unwrap_or(face)))
            }
            MeshNormals::Smooth { file, computed } => {
                let face = face()?;
                Some([0, 1, 2].map(|k| {
                    from_file(file, k)
                        .or_else(|| computed.get(t.corners[k] as usize).copied().and_then(unit))
                        .unwrap_or(face)
                }))
            }
        }
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

fn has_area(v: &[DVec3; 3]) -> bool {
    (v[1] - v[0]).cross(v[2] - v[0]).length_squared() > 0.0
}

#[cfg(test)]
mod tests {
    //! Meshes through the whole load: the scene's triangles and normals
    //! against coordinates worked out here from the files' numbers, so that
    //! a wrong vertex, normal or offset index shows.
    use super::*;
    use std::path::PathBuf;

    /// A fresh folder under the temp dir, unique per process and test.
    fn temp_dir(tag: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("kdray-parse-test-{}-{tag}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// A scene of one mesh entry (`mesh` is the rest of its table), material `m`.
    fn mesh_scene(dir: &Path, mesh: &str) -> Scene {
        let path = dir.join("scene.toml");
        let text = format!(
            "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
             [[lights]]\nposition = [0, 10, 0]\n[materials.m]\ndiffuse = [1, 1, 1]\n\
             [[meshes]]\nmaterial = \"m\"\n{mesh}\n"
        );
        std::fs::write(&path, text).unwrap();
        load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
    }

    fn assert_near(got: DVec3, want: DVec3) {
        assert!(
            (got - want).abs().max_element() < 1e-9,
            "got {got}, want {want}"
        );
    }

    fn assert_triangle(scene: &Scene, i: usize, vertices: [DVec3; 3], normals: Option<[DVec3; 3]>) {
        let t = &scene.triangles[i];
        for (got, want) in t.vertices.iter().zip(vertices) {
            assert_near(*got, want);
        }
        match (scene.normals_of(t), normals) {
            (Some(got), Some(want)) => {
                for (g, w) in got.iter().zip(want) {
                    assert_near(*g, w);
                }
            }
            (got, want) => assert_eq!(got, want),
        }
        assert_eq!(t.material, 0);
    }

    #[test]
    fn obj_indices_in_every_form_reach_the_right_vertices_and_normals() {
        let dir = temp_dir("obj-indices");
        // Vertex 3 is used by no face; placed, it lies at 1.8e15, beyond
        // the GPU's range, which only matters for vertices faces use.
        std::fs::write(
            dir.join("m.obj"),
            "v 0 0 0\nv 2 0 0\nv 9e14 9 9\nv 0 3 0\nvt 0 0\n\
             vn 0 0 1\nvn 1 0 0\nv 1 1 2\nvn 0 1 0\n\
             f 1//1 2//2 4//3\n\
             f -1/1/-1 -4/1/-3 -2/1/-2\n\
             f 5 1/1 -4\n",
        )
        .unwrap();
        let scene = mesh_scene(
            &dir,
            "path = \"m.obj\"\nscale = [2, 1, 0.5]\nrotate = [0, 0, 90]\ntranslate = [1, 2, 3]",
        );
        // Scaled by (2, 1, 0.5), turned 90 degrees about z, then moved.
        let place = |x: f64, y: f64, z: f64| DVec3::new(1.0 - y, 2.0 + 2.0 * x, 3.0 + 0.5 * z);
        let v = [
            place(0.0, 0.0, 0.0),
            place(2.0, 0.0, 0.0),
            place(9e14, 9.0, 9.0),
            place(0.0, 3.0, 0.0),
            place(1.0, 1.0, 2.0),
        ];
        // Normals go through the inverse scale, then the same turn.
        let turn = |x: f64, y: f64, z: f64| {
            let n = DVec3::new(x / 2.0, y, z * 2.0);
            DVec3::new(-n.y, n.x, n.z).normalize()
        };
        let n = [
            turn(0.0, 0.0, 1.0),
            turn(1.0, 0.0, 0.0),
            turn(0.0, 1.0, 0.0),
        ];
        assert_eq!(scene.triangles.len(), 3);
        assert_triangle(&scene, 0, [v[0], v[1], v[3]], Some([n[0], n[1], n[2]]));
        // -1 is the fifth vertex and the third normal, as defined so far.
        assert_triangle(&scene, 1, [v[4], v[1], v[3]], Some([n[2], n[0], n[1]]));
        // Corners without normals: flat shading from the file.
        assert_triangle(&scene, 2, [v[4], v[0], v[1]], None);
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn triangles_a_scale_collapses_are_skipped_and_the_others_kept_in_order() {
        let dir = temp_dir("collapse");
        std::fs::write(
            dir.join("m.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf 1 2 3\nf 1 3 4\n",
        )
        .unwrap();
        // The face in z = 0 keeps an area of 1e-320, whose square is 0 in
        // f64; the two upright ones keep 1e-160.
        let scene = mesh_scene(&dir, "path = \"m.obj\"\nscale = [1e-160, 1e-160, 1]");
        let (o, x, y, z) = (
            DVec3::ZERO,
            DVec3::new(1e-160, 0.0, 0.0),
            DVec3::new(0.0, 1e-160, 0.0),
            DVec3::Z,
        );
        let got: Vec<_> = scene.triangles.iter().map(|t| t.vertices).collect();
        assert_eq!(got, [[o, x, z], [o, y, z]]);
        // With a normal per face (its own face's, on the axes, which the
        // normal matrix keeps), each kept triangle keeps its own.
        std::fs::write(
            dir.join("n.obj"),
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 -1 0\nvn 0 0 1\nvn 2 0 0\n\
             f 1//1 2//1 4//1\nf 1//2 2//2 3//2\nf 1//3 3//3 4//3\n",
        )
        .unwrap();
        let scene = mesh_scene(&dir, "path = \"n.obj\"\nscale = [1e-160, 1e-160, 1]");
        let got: Vec<_> = scene
            .triangles
            .iter()
            .map(|t| (t.vertices, scene.normals_of(t)))
            .collect();
        let want = [
            ([o, x, z], Some([DVec3::NEG_Y; 3])),
            ([o, y, z], Some([DVec3::X; 3])),
        ];
        assert_eq!(got, want);
        let _ = std::fs::remove_dir_all(&dir);
    }

    /// `floats` as little-endian f32 bytes.
    fn f32_bytes(floats: &[f32]) -> Vec<u8> {
        floats.iter().flat_map(|f| f.to_le_bytes()).collect()
    }

    #[test]
    fn gltf_primitives_are_offset_into_one_mesh_under_a_node_transform() {
        let dir = temp_dir("gltf-offsets");
        // Primitive 0: five vertices (the fifth unused), no normals, two
        // indexed triangles. Primitive 1: three vertices with normals, not
        // indexed. So primitive 1's vertices start at 5 and its normals at 0.
        let first: [[f32; 3]; 5] = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [7.0, 7.0, 7.0],
        ];
        let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
        let second: [[f32; 3]; 3] = [[0.0, 0.0, 1.0], [0.0, 2.0, 1.0], [0.0, 0.0, 3.0]];
        let normals: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let mut bin = f32_bytes(first.as_flattened());
        bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
        bin.extend(f32_bytes(second.as_flattened()));
        bin.extend(f32_bytes(normals.as_flattened()));
        assert_eq!(bin.len(), 144);
        std::fs::write(dir.join("m.bin"), &bin).unwrap();
        // The parent turns 90 degrees about z (quaternion) and moves; the
        // child scales x by 2.
        let h = std::f32::consts::FRAC_1_SQRT_2;
        let gltf = format!(
            r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
            "nodes": [{{"translation": [1, 2, 3], "rotation": [0, 0, {h}, {h}], "children": [1]}},
                      {{"scale": [2, 1, 1], "mesh": 0}}],
            "meshes": [{{"primitives": [
                {{"attributes": {{"POSITION": 0}}, "indices": 1}},
                {{"attributes": {{"POSITION": 2, "NORMAL": 3}}}}]}}],
            "buffers": [{{"byteLength": 144, "uri": "m.bin"}}],
            "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 60}},
                            {{"buffer": 0, "byteOffset": 60, "byteLength": 12}},
                            {{"buffer": 0, "byteOffset": 72, "byteLength": 36}},
                            {{"buffer": 0, "byteOffset": 108, "byteLength": 36}}],
            "accessors": [
                {{"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3", "min": [0, 0, 0], "max": [7, 7, 7]}},
                {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}},
                {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 1], "max": [0, 2, 3]}},
                {{"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#
        );
        std::fs::write(dir.join("m.gltf"), gltf).unwrap();
        let scene = mesh_scene(&dir, "path = \"m.gltf\"");
        // Scaled by (2, 1, 1), turned 90 degrees about z, then moved (the
        // f32 quaternion is within 1e-7 of the exact turn).
        let place = |p: [f32; 3]| {
            let [x, y, z] = p.map(f64::from);
            DVec3::new(1.0 - y, 2.0 + 2.0 * x, 3.0 + z)
        };
        let turn = |n: [f32; 3]| {
            let [x, y, z] = n.map(f64::from);
            DVec3::new(-y, x / 2.0, z).normalize()
        };
        let near = |got: DVec3, want: DVec3| (got - want).abs().max_element() < 1e-6;
        let check = |t: &Triangle, vertices: [DVec3; 3], normals: Option<[DVec3; 3]>| {
            for (got, want) in t.vertices.iter().zip(vertices) {
                assert!(near(*got, want), "got {got}, want {want}");
            }
            let got_normals = scene.normals_of(t);
            assert_eq!(got_normals.is_some(), normals.is_some(), "{t:?}");
            if let (Some(got), Some(want)) = (got_normals, normals) {
                for (g, w) in got.iter().zip(want) {
                    assert!(near(*g, w), "normal {g}, want {w}");
                }
            }
        };
        assert_eq!(scene.triangles.len(), 3);
        let p = first.map(place);
        check(&scene.triangles[0], [p[0], p[1], p[2]], None);
        check(&scene.triangles[1], [p[0], p[2], p[3]], None);
        check(
            &scene.triangles[2],
            second.map(place),
            Some(normals.map(turn)),
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
