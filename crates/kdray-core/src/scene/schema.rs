//! The scene file's schema: `Raw*` structs that mirror a TOML or JSON
//! scene document exactly (unknown keys rejected, arrays of exactly three
//! numbers, tables only where the format has tables), read and written by
//! serde. Nothing here checks a value's meaning: that is
//! [`validate`](super::validate)'s job.

use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Serialize, Serializer};

use super::light_shape::LightShape;

/// `[x, y, z]` (or `[r, g, b]`).
pub(super) type Vec3 = Exact<f64, 3>;

/// An array of exactly `N` items. serde's own `[T; N]` leaves the length
/// check to the format, and the toml crate does not make it: `[1, 2, 3, 4]`
/// would be read as `[1, 2, 3]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Exact<T, const N: usize>(pub(super) [T; N]);

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
pub(super) struct TableOf<T>(pub(super) T);

/// What a table is called in "invalid type: ..., expected ..." errors.
pub(super) trait Described {
    const WHAT: &'static str;
}

/// Names each table for [`Described`], one line a table.
macro_rules! described {
    ($($table:ty => $what:literal,)*) => {
        $(impl Described for $table {
            const WHAT: &'static str = $what;
        })*
    };
}

described! {
    RawScene => "a scene (a table of [camera], [render], [[lights]], [materials], [[spheres]], [[triangles]], [[meshes]], [shapes], [[instances]], [animation], [environment])",
    RawCamera => "a [camera] table",
    RawRender => "a [render] table",
    RawLight => "a [[lights]] table",
    RawMaterial => "a material table",
    RawSphere => "a [[spheres]] table",
    RawTriangle => "a [[triangles]] table",
    RawMesh => "a [[meshes]] table",
    RawAnimation => "an [animation] table",
    RawEnvironment => "an [environment] table",
    RawCameraKey => "an [[animation.keys]] table",
    RawLightKey => "an [[animation.light_keys]] table",
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
pub(super) struct RawScene {
    pub(super) camera: TableOf<RawCamera>,
    #[serde(default)]
    pub(super) render: TableOf<RawRender>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) lights: Vec<TableOf<RawLight>>,
    #[serde(
        default,
        deserialize_with = "unique_names",
        skip_serializing_if = "BTreeMap::is_empty"
    )]
    pub(super) materials: BTreeMap<String, TableOf<RawMaterial>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) spheres: Vec<TableOf<RawSphere>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) triangles: Vec<TableOf<RawTriangle>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) meshes: Vec<TableOf<RawMesh>>,
    /// `[shapes.NAME]`: meshes declared once, placed by `[[instances]]`.
    #[serde(
        default,
        deserialize_with = "unique_shape_names",
        skip_serializing_if = "BTreeMap::is_empty"
    )]
    pub(super) shapes: BTreeMap<String, TableOf<RawShape>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) instances: Vec<TableOf<RawInstance>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) animation: Option<TableOf<RawAnimation>>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) environment: Option<TableOf<RawEnvironment>>,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCamera {
    pub(super) position: Vec3,
    pub(super) look_at: Vec3,
    /// None: the default [0, 1, 0] (kept apart so that an error can say so).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) up: Option<Vec3>,
    #[serde(default = "default_vfov")]
    pub(super) vfov: f64,
}

pub(super) const DEFAULT_UP: Vec3 = Exact([0.0, 1.0, 0.0]);
fn default_vfov() -> f64 {
    60.0
}
fn white() -> Vec3 {
    Exact([1.0; 3])
}

#[derive(Deserialize, Serialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct RawRender {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) width: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) height: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) min_intensity: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) max_depth: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) background: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) shadow_mode: Option<RawShadowMode>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) samples: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) integrator: Option<Named<super::integrator::Integrator>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) seed: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) tone_map: Option<Named<super::integrator::ToneMap>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) exposure: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) denoise: Option<bool>,
}

/// `[environment]`: the radiance of the sky that escaping rays see.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawEnvironment {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) color: Option<Vec3>,
    /// An equirectangular HDR or EXR file, relative to the scene's folder.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) image: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) intensity: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) rotation: Option<f64>,
}

/// A [`Choice`](crate::choice::Choice) spelled by its name. Read as a plain
/// string, so that a wrong name's error lists the right ones.
pub(super) struct Named<T>(pub(super) T);

impl<T: crate::choice::Choice> Serialize for Named<T> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_str(self.0.name())
    }
}

impl<'de, T: crate::choice::Choice> Deserialize<'de> for Named<T> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct NameVisitor<T>(std::marker::PhantomData<T>);
        impl<T: crate::choice::Choice> Visitor<'_> for NameVisitor<T> {
            type Value = Named<T>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                let names: Vec<String> =
                    T::ALL.iter().map(|c| format!("\"{}\"", c.name())).collect();
                f.write_str(&names.join(" or "))
            }
            fn visit_str<E: de::Error>(self, v: &str) -> Result<Named<T>, E> {
                T::from_name(v).map(Named).ok_or_else(|| {
                    let names: Vec<String> =
                        T::ALL.iter().map(|c| format!("`{}`", c.name())).collect();
                    E::custom(format!(
                        "unknown variant `{v}`, expected {}",
                        names.join(" or ")
                    ))
                })
            }
        }
        deserializer.deserialize_str(NameVisitor(std::marker::PhantomData))
    }
}

/// `"ambient"` or `"seed"`. Read as a plain string: the toml crate's own
/// enum errors ("wanted string or table") would not say what is expected.
pub(super) enum RawShadowMode {
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
pub(super) struct RawLight {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) kind: Option<Named<LightShape>>,
    /// Required for point and spot lights; a directional light has none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) position: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) direction: Option<Vec3>,
    /// Degrees off `direction` (spot lights).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) inner_cone: Option<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) outer_cone: Option<f64>,
    #[serde(default = "white")]
    pub(super) ambient: Vec3,
    #[serde(default = "white")]
    pub(super) diffuse: Vec3,
    #[serde(default = "white")]
    pub(super) specular: Vec3,
    /// Point and spot lights: where the path tracer matches the Whitted
    /// integrator's brightness.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) reference_distance: Option<f64>,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMaterial {
    #[serde(default)]
    pub(super) ambient: Vec3,
    /// `diffuse` or `base_color`: one of the two (validate says so).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) diffuse: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) base_color: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) metallic: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) roughness: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) emission: Option<Vec3>,
    #[serde(default)]
    pub(super) specular: Vec3,
    #[serde(default)]
    pub(super) shininess: f64,
    #[serde(default)]
    pub(super) reflection: f64,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub(super) transmission: f64,
    #[serde(default = "default_ior", skip_serializing_if = "is_default_ior")]
    pub(super) ior: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) attenuation_color: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) attenuation_distance: Option<f64>,
    #[serde(default, skip_serializing_if = "is_zero")]
    pub(super) transmission_roughness: f64,
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub(super) thin_walled: bool,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn default_ior() -> f64 {
    super::material::Material::DEFAULT_IOR
}

fn is_default_ior(x: &f64) -> bool {
    *x == super::material::Material::DEFAULT_IOR
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawSphere {
    pub(super) center: Vec3,
    pub(super) radius: f64,
    pub(super) material: String,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawTriangle {
    pub(super) vertices: Exact<Vec3, 3>,
    pub(super) material: String,
}

#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawMesh {
    pub(super) path: String,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) material: Option<String>,
    /// true: smooth normals (the file's, else computed); false: flat; None:
    /// the file's normals where it has them, else flat.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) smooth: Option<bool>,
    #[serde(default)]
    pub(super) scale: RawScale,
    #[serde(default)]
    pub(super) rotate: Vec3,
    #[serde(default)]
    pub(super) translate: Vec3,
}

/// `[animation]`: the frames, and how the camera and lights move over them.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawAnimation {
    pub(super) frames: u32,
    #[serde(default = "default_fps")]
    pub(super) fps: f64,
    /// Degrees; 0: no orbit.
    #[serde(default)]
    pub(super) orbit: f64,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) keys: Vec<TableOf<RawCameraKey>>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub(super) light_keys: Vec<TableOf<RawLightKey>>,
}

fn default_fps() -> f64 {
    super::animation::DEFAULT_FPS
}

/// `[[animation.keys]]`: a frame and any of the camera's fields.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCameraKey {
    pub(super) frame: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) position: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) look_at: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) up: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) vfov: Option<f64>,
}

/// `[[animation.light_keys]]`: a frame, a light's index in `[[lights]]`,
/// and its position and/or colour factor.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawLightKey {
    pub(super) frame: u32,
    pub(super) light: u32,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) position: Option<Vec3>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) color: Option<Vec3>,
}

/// `scale = 2` or `scale = [x, y, z]`. Written by hand rather than as an
/// untagged enum so that serde_json reports a bad value at the value itself
/// (an untagged enum's error only surfaces at the end of the enclosing table).
pub(super) enum RawScale {
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
    unique_names_of(deserializer, "material")
}

/// [`unique_names`] for a table of named `what`s.
pub(super) fn unique_names_of<'de, D, V>(
    deserializer: D,
    what: &'static str,
) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    struct MapVisitor<V>(PhantomData<V>, &'static str);
    impl<'de, V: Deserialize<'de>> Visitor<'de> for MapVisitor<V> {
        type Value = BTreeMap<String, V>;
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            write!(f, "a table of named {}s", self.1)
        }
        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
            let mut out = BTreeMap::new();
            while let Some(name) = map.next_key::<String>()? {
                if out.contains_key(&name) {
                    return Err(de::Error::custom(format!(
                        "{} \"{name}\" is defined twice",
                        self.1
                    )));
                }
                let value = map.next_value()?;
                out.insert(name, value);
            }
            Ok(out)
        }
    }
    deserializer.deserialize_map(MapVisitor(PhantomData, what))
}

impl Default for RawScale {
    fn default() -> Self {
        RawScale::Uniform(1.0)
    }
}

// Instancing: `[shapes.NAME]`, a mesh declared once (a mesh file or inline
// triangles), and `[[instances]]`, each placing a shape by its own
// transform; validate_instances.rs checks the values.

/// `[shapes.NAME]`: a mesh file (`path`) or inline `triangles`, declared
/// once and placed by `[[instances]]`.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawShape {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) path: Option<String>,
    /// Inline triangles, three corners each, in the shape's own space.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) triangles: Option<Vec<Exact<Vec3, 3>>>,
    /// Every triangle's material (required for inline triangles); an
    /// instance's own `material` overrides it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) material: Option<String>,
    /// As `[[meshes]]`' `smooth`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) smooth: Option<bool>,
}

/// A row-major 4x4 matrix: `[[a, b, c, tx], [d, e, f, ty], [g, h, i, tz],
/// [0, 0, 0, 1]]`.
pub(super) type RawMatrix = Exact<Exact<f64, 4>, 4>;

/// `[[instances]]`: a shape placed by `scale`, `rotate` and `translate`
/// (as a `[[meshes]]` entry), or by a 4x4 `matrix`.
#[derive(Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawInstance {
    pub(super) shape: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) material: Option<String>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) scale: Option<RawScale>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) rotate: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) translate: Option<Vec3>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub(super) matrix: Option<RawMatrix>,
}

impl Described for RawShape {
    const WHAT: &'static str = "a [shapes.NAME] table";
}

impl Described for RawInstance {
    const WHAT: &'static str = "an [[instances]] table";
}

/// `[shapes]`, whose names must be unique (serde_json would keep the last).
pub(super) fn unique_shape_names<'de, D, V>(
    deserializer: D,
) -> Result<BTreeMap<String, V>, D::Error>
where
    D: Deserializer<'de>,
    V: Deserialize<'de>,
{
    unique_names_of(deserializer, "shape")
}
