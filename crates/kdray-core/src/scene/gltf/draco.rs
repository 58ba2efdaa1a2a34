//! `KHR_draco_mesh_compression`: a primitive whose triangles and
//! attributes are one Draco stream in a buffer view, decoded with the
//! pure-Rust `draco-core` decoder. The extension's `attributes` map glTF
//! names (POSITION, NORMAL, TEXCOORD_n, COLOR_0, TANGENT) to the stream's attribute ids; the
//! stream's faces are the indices. The primitive's accessors give only
//! the component type (a normalized integer is scaled as `accessors` does)
//! and the counts, which bound the decode: at most twice the POSITION
//! count in points and the index count / 3 in faces (the extension says
//! they match), on top of draco-core's own refusal to reserve memory the
//! stream's bytes cannot fill.

use std::collections::HashMap;

use draco_core::{DecodeLimits, DecoderBuffer, Mesh as DracoMesh, MeshDecoder};
use glam::{DVec2, DVec3, DVec4};
use serde_json::Value;

use super::accessors::Component;

pub(super) const DRACO: &str = "KHR_draco_mesh_compression";

/// A Draco primitive's vertices, indexed by `indices` (three a triangle).
pub(super) struct DracoPrimitive {
    pub positions: Vec<DVec3>,
    pub normals: Option<Vec<DVec3>>,
    /// TEXCOORD_n by n.
    pub tex_coords: HashMap<u32, Vec<DVec2>>,
    /// COLOR_0 (RGB given alpha 1) and TANGENT, if the stream has them.
    pub colours: Option<Vec<DVec4>>,
    pub tangents: Option<Vec<DVec4>>,
    pub indices: Vec<usize>,
}

impl super::Reader<'_, '_> {
    /// The decoded primitive, if it is Draco-compressed.
    pub(super) fn draco_primitive(
        &self,
        primitive: &gltf::Primitive,
    ) -> Result<Option<DracoPrimitive>, String> {
        let Some(ext) = primitive.extension_value(DRACO) else {
            return Ok(None);
        };
        let view = ext
            .get("bufferView")
            .and_then(Value::as_u64)
            .and_then(|v| self.document.views().nth(usize::try_from(v).ok()?))
            .ok_or_else(|| format!("{DRACO}: bufferView is not a buffer view of the file"))?;
        let ids = ext
            .get("attributes")
            .and_then(Value::as_object)
            .ok_or_else(|| format!("{DRACO}: no attributes"))?;
        let bytes = self
            .view_bytes(&view)
            .map_err(|e| format!("{DRACO}: {e}"))?;
        let at = |m: String| format!("{DRACO} (buffer view {}): {m}", view.index());
        let mesh = decode_stream(bytes, decode_limits(primitive)).map_err(at)?;
        let stream = Stream {
            mesh: &mesh,
            ids,
            primitive,
            view: view.index(),
        };
        let positions = stream
            .read("POSITION", gltf::Semantic::Positions, 3)?
            .map(vec3)
            .ok_or_else(|| at("no POSITION attribute".to_string()))?;
        let normals = stream.read("NORMAL", gltf::Semantic::Normals, 3)?.map(vec3);
        let mut tex_coords = HashMap::new();
        for name in ids.keys() {
            if let Some(n) = name
                .strip_prefix("TEXCOORD_")
                .and_then(|n| n.parse::<u32>().ok())
            {
                if let Some(v) = stream.read(name, gltf::Semantic::TexCoords(n), 2)? {
                    let uvs = v.chunks_exact(2).map(|c| DVec2::new(c[0], c[1])).collect();
                    tex_coords.insert(n, uvs);
                }
            }
        }
        let indices = mesh
            .faces()
            .iter()
            .flat_map(|f| f.map(|p| p.0 as usize))
            .collect();
        Ok(Some(DracoPrimitive {
            positions,
            normals,
            tex_coords,
            colours: stream.colours()?,
            tangents: stream
                .read("TANGENT", gltf::Semantic::Tangents, 4)?
                .map(vec4),
            indices,
        }))
    }
}

/// What a primitive's accessors allow its Draco stream: at most twice the
/// POSITION count in points and the index count / 3 in faces (the
/// extension says they match), at most 64 decoded bytes a point, each under
/// draco-core's own defaults.
fn decode_limits(primitive: &gltf::Primitive) -> DecodeLimits {
    let position_count = primitive
        .get(&gltf::Semantic::Positions)
        .map_or(0, |a| a.count());
    let index_count = primitive.indices().map_or(position_count, |a| a.count());
    let defaults = DecodeLimits::default();
    let max_points = (position_count as u64)
        .saturating_mul(2)
        .min(defaults.max_points);
    defaults
        .with_max_points(max_points)
        .with_max_faces((index_count as u64 / 3).min(defaults.max_faces))
        // Four bytes a component, at most 16 components a point.
        .with_max_decoded_bytes(
            max_points
                .saturating_mul(64)
                .min(defaults.max_decoded_bytes),
        )
}

/// A decoded Draco stream and what names its attributes.
struct Stream<'a> {
    mesh: &'a DracoMesh,
    /// The extension's `attributes`: glTF name -> the stream's attribute id.
    ids: &'a serde_json::Map<String, Value>,
    primitive: &'a gltf::Primitive<'a>,
    view: usize,
}

impl Stream<'_> {
    fn error(&self, m: String) -> String {
        format!("{DRACO} (buffer view {}): {m}", self.view)
    }

    /// The stream's attribute of glTF name `name`, if the extension maps it.
    fn attribute(&self, name: &str) -> Result<Option<&draco_core::PointAttribute>, String> {
        let Some(id) = self.ids.get(name) else {
            return Ok(None);
        };
        let id = id
            .as_u64()
            .and_then(|i| u32::try_from(i).ok())
            .ok_or_else(|| {
                self.error(format!("attribute {name}: id {id} is not an attribute id"))
            })?;
        let attribute = self.mesh.attribute_by_unique_id(id).ok_or_else(|| {
            self.error(format!(
                "attribute {name}: the stream has no attribute {id}"
            ))
        })?;
        Ok(Some(attribute))
    }

    /// Attribute `name`'s first `components` values a point, scaled as its
    /// accessor (`semantic`) says an integer is meant, every one finite.
    fn read(
        &self,
        name: &str,
        semantic: gltf::Semantic,
        components: usize,
    ) -> Result<Option<Vec<f64>>, String> {
        let Some(attribute) = self.attribute(name)? else {
            return Ok(None);
        };
        if usize::from(attribute.num_components()) < components {
            return Err(self.error(format!(
                "attribute {name} has {} components, not {components}",
                attribute.num_components()
            )));
        }
        let component = self.primitive.get(&semantic).map(|a| Component::of(&a));
        let values: Vec<f64> = attribute
            .read_f32s(self.mesh.num_points(), components)
            .into_iter()
            .map(|v| component.map_or(f64::from(v), |c| c.scale(f64::from(v))))
            .collect();
        if let Some(i) = values.iter().position(|v| !v.is_finite()) {
            return Err(self.error(format!(
                "attribute {name}: element {} is not finite",
                i / components
            )));
        }
        Ok(Some(values))
    }

    /// COLOR_0, RGB (alpha 1) or RGBA as the stream stores it.
    fn colours(&self) -> Result<Option<Vec<DVec4>>, String> {
        let components = self
            .attribute("COLOR_0")?
            .map_or(4, |a| usize::from(a.num_components()).min(4));
        let semantic = gltf::Semantic::Colors(0);
        Ok(match components {
            3 => self.read("COLOR_0", semantic, 3)?.map(|v| {
                v.chunks_exact(3)
                    .map(|c| DVec4::new(c[0], c[1], c[2], 1.0))
                    .collect()
            }),
            _ => self.read("COLOR_0", semantic, 4)?.map(vec4),
        })
    }
}

fn vec3(v: Vec<f64>) -> Vec<DVec3> {
    v.chunks_exact(3)
        .map(|c| DVec3::new(c[0], c[1], c[2]))
        .collect()
}

fn vec4(v: Vec<f64>) -> Vec<DVec4> {
    v.chunks_exact(4)
        .map(|c| DVec4::new(c[0], c[1], c[2], c[3]))
        .collect()
}

/// One Draco mesh stream decoded under `limits`, the decoder's error in
/// one line. A panic inside the decoder (a bug there, on a hostile stream)
/// is reported as an error too, not passed on.
fn decode_stream(bytes: &[u8], limits: DecodeLimits) -> Result<DracoMesh, String> {
    std::panic::catch_unwind(|| {
        let mut buffer = DecoderBuffer::new(bytes).with_limits(limits);
        let mut mesh = DracoMesh::new();
        MeshDecoder::new()
            .decode(&mut buffer, &mut mesh)
            .map(|()| mesh)
            .map_err(|e| format!("corrupt or unsupported Draco stream: {e}"))
    })
    .unwrap_or_else(|_| Err("corrupt Draco stream (the decoder failed)".to_string()))
}
