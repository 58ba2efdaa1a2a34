//! The schema of instancing: `[shapes.NAME]`, a mesh declared once (a mesh
//! file or inline triangles), and `[[instances]]`, each placing a shape by
//! its own transform. Like [`schema`](super::schema), only the document's
//! shape: [`validate_instances`](super::validate_instances) checks the values.

use std::collections::BTreeMap;

use serde::{Deserialize, Deserializer, Serialize};

use super::schema::{Described, Exact, RawScale, Vec3};

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
    super::schema::unique_names_of(deserializer, "shape")
}
