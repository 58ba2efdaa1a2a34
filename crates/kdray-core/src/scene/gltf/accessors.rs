//! Reading an accessor's elements: its buffer view (as stored, or as
//! `EXT_meshopt_compression` decoded it), offset, stride and sparse part,
//! every offset checked against the bytes present; and the component types
//! `KHR_mesh_quantization` allows, each turned into a number by glTF 2.0's
//! rules (a normalized signed integer c of n bits is max(c / (2^(n-1) - 1),
//! -1), an unsigned one c / (2^n - 1); a plain integer is its value).

use glam::{DVec2, DVec3, DVec4};
use gltf::accessor::{DataType, Dimensions};

/// An accessor's component type and normalization.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Component {
    pub data_type: DataType,
    pub normalized: bool,
}

impl Component {
    pub(super) fn of(accessor: &gltf::Accessor) -> Self {
        Component {
            data_type: accessor.data_type(),
            normalized: accessor.normalized(),
        }
    }

    /// Bytes a component takes.
    fn size(self) -> usize {
        match self.data_type {
            DataType::I8 | DataType::U8 => 1,
            DataType::I16 | DataType::U16 => 2,
            DataType::U32 | DataType::F32 => 4,
        }
    }

    /// A component stored little-endian at the start of `b`.
    fn read(self, b: &[u8]) -> f64 {
        let raw = match self.data_type {
            DataType::F32 => return f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            DataType::I8 => f64::from(b[0] as i8),
            DataType::U8 => f64::from(b[0]),
            DataType::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            DataType::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            DataType::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
        };
        self.scale(raw)
    }

    /// An integer component's value as the accessor means it: divided by
    /// the type's largest value when normalized (signed ones at least -1).
    pub(super) fn scale(self, raw: f64) -> f64 {
        if !self.normalized {
            return raw;
        }
        match self.data_type {
            DataType::I8 => (raw / 127.0).max(-1.0),
            DataType::U8 => raw / 255.0,
            DataType::I16 => (raw / 32767.0).max(-1.0),
            DataType::U16 => raw / 65535.0,
            DataType::U32 => raw / 4294967295.0,
            DataType::F32 => raw,
        }
    }
}

/// Which vertex attribute is read: each allows its own component types.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Attribute {
    Position,
    Normal,
    TexCoord,
    /// COLOR_n: FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT (core glTF).
    Colour,
    /// TANGENT: FLOAT, or (KHR_mesh_quantization) normalized BYTE or SHORT.
    Tangent,
}

impl Attribute {
    /// The components glTF 2.0 with `KHR_mesh_quantization` allows.
    pub(super) fn allows(self, c: Component) -> bool {
        use DataType::*;
        match (self, c.data_type) {
            (_, F32) => !c.normalized,
            (Attribute::Normal | Attribute::Tangent, I8 | I16) => c.normalized,
            (Attribute::Colour, U8 | U16) => c.normalized,
            (Attribute::Position | Attribute::TexCoord, I8 | U8 | I16 | U16) => true,
            _ => false,
        }
    }

    fn types(self) -> &'static str {
        match self {
            Attribute::Normal | Attribute::Tangent => {
                "FLOAT, or (KHR_mesh_quantization) normalized BYTE or SHORT"
            }
            Attribute::Colour => "FLOAT, or normalized UNSIGNED_BYTE or UNSIGNED_SHORT",
            _ => "FLOAT, or (KHR_mesh_quantization) BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT, normalized or not",
        }
    }
}

/// The element reading, done where the reader walks the primitives.
impl super::Reader<'_, '_> {
    /// The bytes of a buffer view, checked to lie inside its buffer.
    pub(super) fn view_bytes(&self, view: &gltf::buffer::View) -> Result<&[u8], String> {
        if let Some(Some(decoded)) = self.decoded_views.get(view.index()) {
            return Ok(decoded);
        }
        let buffer = &self.buffers[view.buffer().index()];
        let view_end = view
            .offset()
            .checked_add(view.length())
            .filter(|&end| end <= buffer.len())
            .ok_or_else(|| {
                format!(
                    "buffer view {} (bytes {}..+{}) lies outside its buffer of {} bytes",
                    view.index(),
                    view.offset(),
                    view.length(),
                    buffer.len()
                )
            })?;
        Ok(&buffer[view.offset()..view_end])
    }

    /// Where an accessor's dense elements are, every element checked to lie
    /// inside its buffer view and the view inside its buffer. None for an
    /// accessor without a view (all zeros, or what its sparse part sets).
    fn elements(
        &self,
        accessor: &gltf::Accessor,
        size: usize,
    ) -> Result<Option<Elements<'_>>, String> {
        if accessor.count() == 0 {
            return Err("has no elements".to_string());
        }
        let Some(view) = accessor
            .view()
            .filter(|_| !self.viewless.contains(&accessor.index()))
        else {
            return Ok(None);
        };
        let view_bytes = self.view_bytes(&view)?;
        let stride = view.stride().unwrap_or(size);
        if stride < size {
            return Err(format!(
                "byteStride {stride} is smaller than an element ({size} bytes)"
            ));
        }
        let last_end = (accessor.count() - 1)
            .checked_mul(stride)
            .and_then(|x| x.checked_add(accessor.offset()))
            .and_then(|x| x.checked_add(size));
        if last_end.is_none_or(|end| end > view_bytes.len()) {
            return Err(format!(
                "{} elements of {size} bytes (stride {stride}, offset {}) do not fit in buffer view {} of {} bytes",
                accessor.count(),
                accessor.offset(),
                view.index(),
                view_bytes.len()
            ));
        }
        Ok(Some(Elements {
            bytes: view_bytes,
            offset: accessor.offset(),
            stride,
        }))
    }

    /// The elements a sparse accessor replaces: (element index, its new
    /// `size` bytes), every index and value checked to lie in its view and
    /// every index below the accessor's count. Empty for a dense accessor.
    fn sparse_elements(
        &self,
        accessor: &gltf::Accessor,
        size: usize,
    ) -> Result<Vec<(usize, &[u8])>, String> {
        let Some(sparse) = accessor.sparse() else {
            return Ok(Vec::new());
        };
        let count = sparse.count();
        let indices = sparse.indices();
        let index_size = match indices.index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        let values = sparse.values();
        let fits = |bytes: &[u8], offset: usize, element: usize, what: &str| {
            let end = count
                .checked_mul(element)
                .and_then(|x| x.checked_add(offset));
            if end.is_none_or(|end| end > bytes.len()) {
                return Err(format!(
                    "sparse {what}: {count} elements of {element} bytes (offset {offset}) do not fit in their buffer view of {} bytes",
                    bytes.len()
                ));
            }
            Ok(())
        };
        let index_view = self.view_bytes(&indices.view())?;
        fits(index_view, indices.offset(), index_size, "indices")?;
        let index_bytes = &index_view[indices.offset()..];
        let value_view = self.view_bytes(&values.view())?;
        fits(value_view, values.offset(), size, "values")?;
        let value_bytes = &value_view[values.offset()..];
        (0..count)
            .map(|k| {
                let b = &index_bytes[k * index_size..];
                let index = match index_size {
                    1 => b[0] as usize,
                    2 => u16::from_le_bytes([b[0], b[1]]) as usize,
                    _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
                };
                if index >= accessor.count() {
                    return Err(format!(
                        "sparse index {index} is out of range: {} elements",
                        accessor.count()
                    ));
                }
                Ok((index, &value_bytes[k * size..k * size + size]))
            })
            .collect()
    }

    /// Every element of an accessor of `size`-byte elements, decoded: the
    /// dense elements (zeros without a view), then the sparse ones in place.
    fn read_elements<T: Clone>(
        &self,
        accessor: &gltf::Accessor,
        size: usize,
        zero: T,
        decode: impl Fn(&[u8]) -> T,
    ) -> Result<Vec<T>, String> {
        let mut out = match self.elements(accessor, size)? {
            Some(Elements {
                bytes,
                offset,
                stride,
            }) => (0..accessor.count())
                .map(|i| decode(&bytes[offset + i * stride..]))
                .collect(),
            None => {
                // Zeros but for the sparse elements. At most one element per
                // byte of the buffers (a real file holds that many elements
                // densely elsewhere, as a morph target's base positions): a
                // file of a few bytes must not fill gigabytes with zeros.
                let buffer_bytes: usize = self.buffers.iter().map(Vec::len).sum();
                if accessor.count() > buffer_bytes {
                    return Err(format!(
                        "{} elements without a bufferView, more than the {buffer_bytes} bytes of the file's buffers",
                        accessor.count()
                    ));
                }
                vec![zero; accessor.count()]
            }
        };
        for (index, bytes) in self.sparse_elements(accessor, size)? {
            out[index] = decode(bytes);
        }
        Ok(out)
    }

    /// `N` components per element of the types `attribute` allows, every
    /// value finite.
    fn read_vectors<const N: usize>(
        &self,
        accessor: &gltf::Accessor,
        attribute: Attribute,
        dimensions: Dimensions,
    ) -> Result<Vec<[f64; N]>, String> {
        let component = Component::of(accessor);
        if accessor.dimensions() != dimensions || !attribute.allows(component) {
            let normalized = if component.normalized {
                "normalized "
            } else {
                ""
            };
            return Err(format!(
                "must be {dimensions:?} of {}; is {:?} of {normalized}{:?}",
                attribute.types(),
                accessor.dimensions(),
                component.data_type
            ));
        }
        let size = component.size();
        let out = self.read_elements(accessor, N * size, [0.0; N], |b| {
            std::array::from_fn(|k| component.read(&b[k * size..]))
        })?;
        if let Some((i, v)) = out
            .iter()
            .enumerate()
            .find(|(_, v)| v.iter().any(|x| !x.is_finite()))
        {
            return Err(format!("element {i} is not finite: {v:?}"));
        }
        Ok(out)
    }

    /// Positions or normals: VEC3.
    pub(super) fn read_vec3(
        &self,
        accessor: &gltf::Accessor,
        attribute: Attribute,
    ) -> Result<Vec<DVec3>, String> {
        let out = self.read_vectors::<3>(accessor, attribute, Dimensions::Vec3)?;
        Ok(out.into_iter().map(DVec3::from_array).collect())
    }

    /// Vertex colours: VEC3 (alpha 1) or VEC4, linear RGBA.
    pub(super) fn read_colours(&self, accessor: &gltf::Accessor) -> Result<Vec<DVec4>, String> {
        if accessor.dimensions() == Dimensions::Vec3 {
            let out = self.read_vectors::<3>(accessor, Attribute::Colour, Dimensions::Vec3)?;
            return Ok(out
                .into_iter()
                .map(|[r, g, b]| DVec4::new(r, g, b, 1.0))
                .collect());
        }
        let out = self.read_vectors::<4>(accessor, Attribute::Colour, Dimensions::Vec4)?;
        Ok(out.into_iter().map(DVec4::from_array).collect())
    }

    /// Tangents: VEC4, w the bitangent's sign.
    pub(super) fn read_tangents(&self, accessor: &gltf::Accessor) -> Result<Vec<DVec4>, String> {
        let out = self.read_vectors::<4>(accessor, Attribute::Tangent, Dimensions::Vec4)?;
        Ok(out.into_iter().map(DVec4::from_array).collect())
    }

    /// Texture coordinates: VEC2.
    pub(super) fn read_vec2(&self, accessor: &gltf::Accessor) -> Result<Vec<DVec2>, String> {
        let out = self.read_vectors::<2>(accessor, Attribute::TexCoord, Dimensions::Vec2)?;
        Ok(out.into_iter().map(DVec2::from_array).collect())
    }

    /// Unsigned byte, short or int scalars.
    pub(super) fn read_indices(&self, accessor: &gltf::Accessor) -> Result<Vec<usize>, String> {
        let size = match accessor.data_type() {
            DataType::U8 => 1,
            DataType::U16 => 2,
            DataType::U32 => 4,
            other => return Err(format!("must be unsigned integers, are {other:?}")),
        };
        if accessor.dimensions() != Dimensions::Scalar {
            return Err(format!("must be SCALAR, are {:?}", accessor.dimensions()));
        }
        self.read_elements(accessor, size, 0, |b| match size {
            1 => b[0] as usize,
            2 => u16::from_le_bytes([b[0], b[1]]) as usize,
            _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
        })
    }
}

/// An accessor's elements: element i starts at `bytes[offset + i * stride]`.
pub(super) struct Elements<'a> {
    /// The buffer view's bytes.
    bytes: &'a [u8],
    offset: usize,
    stride: usize,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn c(data_type: DataType, normalized: bool) -> Component {
        Component {
            data_type,
            normalized,
        }
    }

    #[test]
    fn normalized_integers_follow_the_gltf_rules() {
        let i8n = c(DataType::I8, true);
        assert_eq!(i8n.read(&[127]), 1.0);
        assert_eq!(i8n.read(&[0x81]), -1.0); // -127
        assert_eq!(i8n.read(&[0x80]), -1.0); // -128 clamps to -1
        assert_eq!(c(DataType::U8, true).read(&[255]), 1.0);
        assert_eq!(c(DataType::U8, true).read(&[51]), 0.2);
        let i16n = c(DataType::I16, true);
        assert_eq!(i16n.read(&32767i16.to_le_bytes()), 1.0);
        assert_eq!(i16n.read(&(-32768i16).to_le_bytes()), -1.0);
        assert_eq!(i16n.read(&(-16384i16).to_le_bytes()), -16384.0 / 32767.0);
        assert_eq!(c(DataType::U16, true).read(&65535u16.to_le_bytes()), 1.0);
    }

    #[test]
    fn plain_integers_are_their_values() {
        assert_eq!(c(DataType::I8, false).read(&[0xfe]), -2.0);
        assert_eq!(c(DataType::U8, false).read(&[200]), 200.0);
        assert_eq!(
            c(DataType::I16, false).read(&(-300i16).to_le_bytes()),
            -300.0
        );
        assert_eq!(
            c(DataType::U16, false).read(&60000u16.to_le_bytes()),
            60000.0
        );
        assert_eq!(c(DataType::F32, false).read(&1.5f32.to_le_bytes()), 1.5);
    }

    #[test]
    fn each_attribute_allows_what_mesh_quantization_allows() {
        use Attribute::*;
        for t in [DataType::I8, DataType::U8, DataType::I16, DataType::U16] {
            for n in [false, true] {
                assert!(Position.allows(c(t, n)));
                assert!(TexCoord.allows(c(t, n)));
            }
        }
        assert!(Normal.allows(c(DataType::I8, true)));
        assert!(Normal.allows(c(DataType::I16, true)));
        assert!(!Normal.allows(c(DataType::I8, false)));
        assert!(!Normal.allows(c(DataType::U8, true)));
        assert!(!Position.allows(c(DataType::U32, false)));
        assert!(!Position.allows(c(DataType::F32, true)));
        assert!(Tangent.allows(c(DataType::I16, true)));
        assert!(!Tangent.allows(c(DataType::U16, true)));
        assert!(Colour.allows(c(DataType::U8, true)) && Colour.allows(c(DataType::U16, true)));
        assert!(!Colour.allows(c(DataType::U8, false)));
        assert!(!Colour.allows(c(DataType::I16, true)));
    }
}
