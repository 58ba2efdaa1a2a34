//! A glTF material's `baseColorTexture` and the texture coordinates of
//! its primitives (TEXCOORD_n, n its texCoord; FLOAT or normalized
//! UNSIGNED_BYTE/SHORT, sparse too); its image (in a buffer view, as
//! in a `.glb`; a `data:` URI; or a file named by a relative path) decoded
//! once per image and sampler, and its sampler in kdray's terms: magFilter
//! NEAREST is point sampling, LINEAR or unset bilinear; minFilter NEAREST
//! or LINEAR reads the base level only, *_MIPMAP_NEAREST the nearest mip
//! level, *_MIPMAP_LINEAR (and unset: LINEAR_MIPMAP_LINEAR) blends two
//! (see [`min_filter`]); wrapS and wrapT REPEAT,
//! CLAMP_TO_EDGE or MIRRORED_REPEAT. An image that cannot be read or
//! decoded is a warning naming it; the material keeps its colour factor.

use std::collections::HashMap;
use std::path::Path;
use std::sync::Arc;

use glam::DVec2;
use gltf::texture::{MagFilter, MinFilter as GltfMinFilter, WrappingMode};

use super::buffers::{buffer_path, decode_data_uri};
use super::texture_transform::UvChoice;
use crate::scene::texture::{MinFilter, MipMode, Texture, TextureFilter, TextureWrap};
use crate::scene::warning::Warning;

/// The textures decoded so far, by (image, sampler); None: it could not
/// be (warned about once).
#[derive(Default)]
pub(super) struct DecodedImages {
    by_source: HashMap<(usize, Option<usize>), Option<Arc<Texture>>>,
}

/// A primitive's texture coordinates: the first channel, and the second
/// where its material reads one (texture_transform.rs).
pub(super) struct PrimitiveUvs {
    pub first: Vec<DVec2>,
    pub second: Option<Vec<DVec2>>,
}

/// The texture coordinates, read where the reader walks the primitives.
impl super::Reader<'_, '_> {
    /// The texture coordinates of a primitive whose material has a texture
    /// that decoded (the channels of texture_transform.rs), one per
    /// position; None otherwise. Coordinates that cannot be read leave the
    /// primitive untextured, with a warning.
    pub(super) fn texture_coordinates(
        &mut self,
        primitive: &gltf::Primitive,
        draco: Option<&super::draco::DracoPrimitive>,
        count: usize,
        at: &str,
    ) -> Option<PrimitiveUvs> {
        let material = primitive.material();
        let local = *self.material_of.get(&material.index())?;
        let read = self.mesh.materials.get(local)?;
        if read.texture.is_none() && !read.maps.any() {
            return None;
        }
        let channels = super::texture_transform::uv_channels(&material)?;
        if let Some(slot) = channels.unmatched {
            let name = material.index().map_or_else(
                || "the default material".to_string(),
                |i| format!("materials[{i}]"),
            );
            let warning = crate::scene::warning::Warning::new(
                self.files.path,
                None,
                format!(
                    "{name}: its textures ask for more than two texture coordinate sets or \
                     KHR_texture_transform transforms; kdray reads its {slot} with its {}'s",
                    channels.first.slot
                ),
            );
            // One line per material, however many primitives use it.
            if !self.mesh.warnings.contains(&warning) {
                self.mesh.warnings.push(warning);
            }
        }
        let mut channel = |choice: UvChoice| {
            self.channel(primitive, draco, count, choice)
                .map_err(|m| {
                    let set = choice.set;
                    self.mesh.warnings.push(crate::scene::warning::Warning::new(
                        self.files.path,
                        None,
                        format!("{at}: TEXCOORD_{set} {m}; the primitive is drawn untextured"),
                    ))
                })
                .ok()
        };
        let first = channel(channels.first)?;
        let second = match channels.second {
            Some(choice) => Some(channel(choice)?),
            None => None,
        };
        Some(PrimitiveUvs { first, second })
    }

    /// One channel's coordinates: the set `choice` names (from the Draco
    /// stream or the accessor), one per position, with its transform.
    fn channel(
        &self,
        primitive: &gltf::Primitive,
        draco: Option<&super::draco::DracoPrimitive>,
        count: usize,
        choice: UvChoice,
    ) -> Result<Vec<DVec2>, String> {
        let set = choice.set;
        let uvs = match (draco, primitive.get(&gltf::Semantic::TexCoords(set))) {
            (Some(d), _) => d
                .tex_coords
                .get(&set)
                .cloned()
                .ok_or_else(|| "missing".to_string())?,
            (None, Some(a)) => self.read_vec2(&a)?,
            (None, None) => return Err("missing".to_string()),
        };
        if uvs.len() != count {
            return Err(format!("{} coordinates for {count} positions", uvs.len()));
        }
        Ok(match choice.transform {
            Some(t) => uvs.into_iter().map(|uv| t.apply(uv)).collect(),
            None => uvs,
        })
    }
}

/// What an image is read from: the buffers and the glTF file's reader.
pub(super) struct ImageFiles<'a, 'r> {
    pub buffers: &'a [Vec<u8>],
    pub path: &'a Path,
    pub read_file: &'r mut dyn FnMut(&Path) -> std::io::Result<Vec<u8>>,
}

impl DecodedImages {
    /// The base-colour texture of `material`, if it has one that decodes;
    /// a warning on `warnings` the first time one does not.
    pub(super) fn base_colour(
        &mut self,
        material: &gltf::Material,
        document: &gltf::Document,
        files: &mut ImageFiles,
        warnings: &mut Vec<Warning>,
    ) -> Option<Arc<Texture>> {
        let info = material.pbr_metallic_roughness().base_color_texture()?;
        self.texture(
            info.texture(),
            "baseColorTexture",
            document,
            files,
            warnings,
        )
    }

    /// The metallicRoughnessTexture, emissiveTexture, normalTexture and
    /// occlusionTexture of `material`, each where it has one that decodes (a warning the first
    /// time one does not).
    pub(super) fn maps(
        &mut self,
        material: &gltf::Material,
        document: &gltf::Document,
        files: &mut ImageFiles,
        warnings: &mut Vec<Warning>,
    ) -> crate::scene::material::MaterialMaps<Arc<Texture>> {
        let pbr = material.pbr_metallic_roughness();
        let mut decode = |texture: Option<gltf::texture::Texture>, role: &str| {
            self.texture(texture?, role, document, files, warnings)
        };
        crate::scene::material::MaterialMaps {
            metal_rough: decode(
                pbr.metallic_roughness_texture().map(|i| i.texture()),
                "metallicRoughnessTexture",
            ),
            emissive: decode(
                material.emissive_texture().map(|i| i.texture()),
                "emissiveTexture",
            ),
            normal: decode(
                material.normal_texture().map(|i| i.texture()),
                "normalTexture",
            ),
            normal_scale: material
                .normal_texture()
                .map_or(1.0, |n| f64::from(n.scale())),
            occlusion: decode(
                material.occlusion_texture().map(|i| i.texture()),
                "occlusionTexture",
            ),
            occlusion_strength: material
                .occlusion_texture()
                .map_or(1.0, |o| f64::from(o.strength()).clamp(0.0, 1.0)),
            second_uv: 0,
        }
    }

    /// `texture` decoded with its sampler, once per image and sampler.
    fn texture(
        &mut self,
        texture: gltf::texture::Texture,
        role: &str,
        document: &gltf::Document,
        files: &mut ImageFiles,
        warnings: &mut Vec<Warning>,
    ) -> Option<Arc<Texture>> {
        let image = texture.source();
        let sampler = texture.sampler();
        let key = (image.index(), sampler.index());
        if let Some(done) = self.by_source.get(&key) {
            return done.clone();
        }
        let name = match image.name() {
            Some(name) if !name.is_empty() => format!("image {} ({name})", image.index()),
            _ => format!("image {}", image.index()),
        };
        let filter = match sampler.mag_filter() {
            Some(MagFilter::Nearest) => TextureFilter::Nearest,
            _ => TextureFilter::Bilinear,
        };
        let wrap = [sampler.wrap_s(), sampler.wrap_t()].map(|w| match w {
            WrappingMode::ClampToEdge => TextureWrap::ClampToEdge,
            WrappingMode::MirroredRepeat => TextureWrap::MirroredRepeat,
            WrappingMode::Repeat => TextureWrap::Repeat,
        });
        let decoded = image_bytes(image.index(), document, files)
            .and_then(|(shown, bytes)| {
                Texture::decode(
                    &shown,
                    &bytes,
                    filter,
                    min_filter(sampler.min_filter()),
                    wrap,
                )
                .map_err(|e| format!("{shown}: {e}"))
            })
            .map(Arc::new);
        let out = match decoded {
            Ok(t) => Some(t),
            Err(e) => {
                warnings.push(Warning::new(
                    files.path,
                    None,
                    format!("cannot read the {role} {name}: {e}; its materials show their factors"),
                ));
                None
            }
        };
        self.by_source.insert(key, out.clone());
        out
    }
}

/// A glTF sampler's minFilter in kdray's terms: the filter within a level
/// (the part before _MIPMAP_) and the mip mode (the part after); unset is
/// LINEAR_MIPMAP_LINEAR.
pub(crate) fn min_filter(gltf: Option<GltfMinFilter>) -> MinFilter {
    use TextureFilter::{Bilinear, Nearest};
    let (filter, mip) = match gltf {
        Some(GltfMinFilter::Nearest) => (Nearest, MipMode::None),
        Some(GltfMinFilter::Linear) => (Bilinear, MipMode::None),
        Some(GltfMinFilter::NearestMipmapNearest) => (Nearest, MipMode::Nearest),
        Some(GltfMinFilter::LinearMipmapNearest) => (Bilinear, MipMode::Nearest),
        Some(GltfMinFilter::NearestMipmapLinear) => (Nearest, MipMode::Linear),
        Some(GltfMinFilter::LinearMipmapLinear) | None => (Bilinear, MipMode::Linear),
    };
    MinFilter { filter, mip }
}

/// The encoded bytes of image `index` and how to name it (its file, or
/// where it lies).
fn image_bytes(
    index: usize,
    document: &gltf::Document,
    files: &mut ImageFiles,
) -> Result<(String, Vec<u8>), String> {
    let json = document
        .as_json()
        .images
        .get(index)
        .ok_or("no such image")?;
    if let Some(view) = &json.buffer_view {
        let view = document
            .views()
            .nth(view.value())
            .ok_or("its buffer view does not exist")?;
        let buffer = files
            .buffers
            .get(view.buffer().index())
            .ok_or("its buffer does not exist")?;
        let bytes = view
            .offset()
            .checked_add(view.length())
            .and_then(|end| buffer.get(view.offset()..end))
            .ok_or("its buffer view does not fit in its buffer")?;
        return Ok((format!("buffer view {}", view.index()), bytes.to_vec()));
    }
    let uri = json
        .uri
        .as_deref()
        .ok_or("it has neither a uri nor a bufferView")?;
    if let Some(data) = uri.strip_prefix("data:") {
        return Ok(("a data URI".to_string(), decode_data_uri(data)?));
    }
    let base = files.path.parent().unwrap_or(Path::new(""));
    let file = buffer_path(base, uri)?;
    let bytes = (files.read_file)(&file).map_err(|e| format!("{}: {e}", file.display()))?;
    Ok((file.display().to_string(), bytes))
}
