//! glTF 2.0 meshes (`.gltf` with external or embedded base64 buffers, and
//! binary `.glb`), read with the `gltf` crate.
//!
//! What is kept: every mesh the default scene (or, without one, the first
//! scene) places through its node hierarchy, with the nodes' transforms
//! applied; TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN primitives, indexed or
//! not; NORMAL attributes, carried by the inverse transpose of the node
//! transforms, TANGENT and COLOR_0 beside the positions; each material's
//! PBR factors mapped to kdray's model ([`pbr_material`]); its textures
//! (base colour, metallic-roughness, normal, emissive, occlusion) with up
//! to two channels of texture coordinates (`images`,
//! `texture_transform`); the files the web's optimisers write:
//! quantized attributes (`accessors`), meshopt-compressed buffer views
//! (`extensions`, `meshopt`), Draco-compressed primitives (`draco`) and
//! WebP textures; the first perspective camera the walk meets and the
//! `KHR_lights_punctual` lights (`placed`), for a model opened on its own.
//! Skins, morph targets and animations are ignored; points and lines are
//! an error (they are not surfaces, and a file of them would draw nothing). Sparse accessors are
//! read wherever accessors are. An extension the file requires that kdray
//! does not read is an error naming it. What a file asks for that kdray
//! ignores (an extension, a third set of texture coordinates) gets one
//! [`Warning`](crate::scene::Warning) each on
//! [`Mesh::warnings`](super::mesh::Mesh::warnings); a glTF 1.0 file is
//! named as such.
//!
//! The crate parses and validates the document; kdray reads the buffers
//! itself (regular files named by a path, relative to the glTF file's
//! folder, or `data:` URIs; never a URI with another scheme; each file
//! reported to the caller before it is read) and the accessors too, with
//! every offset, stride and count checked against the bytes present, so a
//! truncated or hostile file is an error and never a panic.

use std::collections::HashMap;
use std::path::Path;

use glam::{DMat3, DMat4, DVec2, DVec3, DVec4};
use gltf::mesh::Mode;

use crate::scene::error::SceneError;
use crate::scene::mesh::{mesh_index, Mesh, MeshMaterial, MeshTriangle, NO_INDEX};

mod accessors;
mod alpha;
mod buffers;
mod draco;
mod extensions;
mod images;
mod instancing;
mod meshopt;
mod placed;
mod texture_transform;
mod unsupported;

use accessors::Attribute;
use alpha::alpha;
use buffers::load_buffers;
use unsupported::{extensions_warning, is_gltf_1, GLTF_1_UNSUPPORTED};

/// Reads a `.gltf` or `.glb` file (told apart by content: a GLB starts with
/// `glTF`), calling `on_read` with it and each external buffer file just
/// before reading it.
pub fn load_gltf(
    path: &Path,
    with_materials: bool,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Mesh, SceneError> {
    load_gltf_with(path, with_materials, false, on_read)
}

/// [`load_gltf`], with `instancing`: each mesh placed several times (by
/// several nodes, or by `EXT_mesh_gpu_instancing`) read once into
/// [`Mesh::instanced`] instead of placed copy by copy.
pub fn load_gltf_with(
    path: &Path,
    with_materials: bool,
    instancing: bool,
    on_read: &mut dyn FnMut(&Path),
) -> Result<Mesh, SceneError> {
    on_read(path);
    let bytes = crate::scene::input_file::read_input_file(path).map_err(|e| {
        SceneError::new(path, None, None, format!("cannot read glTF file: {e}")).with_source(e)
    })?;
    parse_gltf_with(&bytes, path, with_materials, instancing, &mut |uri_path| {
        on_read(uri_path);
        crate::scene::input_file::read_input_file(uri_path)
    })
}

/// Parses glTF bytes already read; `read_buffer` reads an external buffer
/// file (given its path, resolved against `path`'s folder). For tests and
/// fuzzing, which pass a reader that finds nothing.
pub fn parse_gltf(
    bytes: &[u8],
    path: &Path,
    with_materials: bool,
    read_buffer: &mut dyn FnMut(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Mesh, SceneError> {
    parse_gltf_with(bytes, path, with_materials, false, read_buffer)
}

/// [`parse_gltf`], with instancing as [`load_gltf_with`] says.
pub fn parse_gltf_with(
    bytes: &[u8],
    path: &Path,
    with_materials: bool,
    instancing: bool,
    read_buffer: &mut dyn FnMut(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<Mesh, SceneError> {
    let err = |message: String| SceneError::new(path, None, None, message);
    let (gltf, prepared, mut warnings) = parse_document(bytes, path)?;
    let document = &gltf.document;
    let buffers = load_buffers(
        document,
        gltf.blob.as_deref(),
        path,
        read_buffer,
        &prepared.placeholders,
    )?;
    let decoded_views = extensions::decode_meshopt_views(document, &buffers).map_err(err)?;

    let Some(scene) = document
        .default_scene()
        .or_else(|| document.scenes().next())
    else {
        return Err(err(
            "no scene: the file defines no scene to place its meshes, so it would draw nothing"
                .to_string(),
        ));
    };

    let mut reader = Reader {
        buffers: &buffers,
        decoded_views: &decoded_views,
        viewless: &prepared.viewless,
        document,
        images: images::DecodedImages::default(),
        files: images::ImageFiles {
            buffers: &buffers,
            path,
            read_file: read_buffer,
        },
        with_materials,
        mesh: Mesh::default(),
        material_of: HashMap::new(),
        triangles_seen: 0,
        instancing,
        uses: instancing::mesh_uses(document, &scene),
    };
    let orthographic_cameras = reader.place_nodes(&scene).map_err(err)?;
    let mut mesh = reader.mesh;
    if orthographic_cameras > 0 {
        warnings.push(crate::scene::warning::Warning::new(
            path,
            None,
            format!(
                "ignores {orthographic_cameras} orthographic camera{}: kdray's camera is a pinhole (perspective)",
                if orthographic_cameras == 1 { "" } else { "s" }
            ),
        ));
    }
    let instanced_triangles = mesh
        .instanced
        .iter()
        .any(|i| !i.mesh.triangles.is_empty() && !i.transforms.is_empty());
    if mesh.triangles.is_empty() && !instanced_triangles {
        return Err(err(if reader.triangles_seen == 0 {
            "no triangles: the scene's nodes place no mesh with triangles, so it would draw nothing"
                .to_string()
        } else {
            format!(
                "all {} triangles have zero area, so the mesh would draw nothing",
                reader.triangles_seen
            )
        }));
    }
    if !with_materials {
        mesh.materials.clear();
    }
    warnings.append(&mut mesh.warnings);
    mesh.warnings = warnings;
    Ok(mesh)
}

/// The document of glTF bytes, validated, with the extensions kdray reads
/// prepared (extensions.rs) and the warning for those it does not, if any.
fn parse_document(
    bytes: &[u8],
    path: &Path,
) -> Result<
    (
        gltf::Gltf,
        extensions::Prepared,
        Vec<crate::scene::warning::Warning>,
    ),
    SceneError,
> {
    let err = |message: String| SceneError::new(path, None, None, message);
    check_glb_header(bytes).map_err(err)?;
    let invalid = |e: gltf::Error| {
        if is_gltf_1(bytes) {
            return err(GLTF_1_UNSUPPORTED.to_string());
        }
        if let Some(message) = alpha::cutoff_type_error(bytes) {
            return err(message);
        }
        err(format!(
            "not a valid glTF 2.0 file: {}",
            gltf_error_text(&e)
        ))
        .with_source(e)
    };
    // Parse, check what the crate's validation would index unchecked, then
    // validate (gltf-json 1.4 panics on a POSITION accessor index out of
    // range, found by crates/kdray-core/tests/fuzz_regressions.rs's bit flips).
    let gltf = gltf::Gltf::from_slice_without_validation(bytes).map_err(invalid)?;
    let mut root = gltf.document.into_json();
    if root.asset.version.starts_with('1') {
        return Err(err(GLTF_1_UNSUPPORTED.to_string()));
    }
    check_attribute_indices(&root).map_err(err)?;
    alpha::check_cutoffs(&root).map_err(err)?;
    // The extensions kdray reads rewrite what the crate would refuse; one
    // it does not read is an error if required, a warning if used.
    let prepared = extensions::prepare(&mut root).map_err(err)?;
    let warnings = extensions_warning(&root, path).into_iter().collect();
    root.extensions_required.clear();
    let gltf = gltf::Gltf {
        document: gltf::Document::from_json(root).map_err(invalid)?,
        blob: gltf.blob,
    };
    Ok((gltf, prepared, warnings))
}

/// The crate subtracts the 12-byte header from a GLB's declared length
/// without checking it: refuse such a header first.
fn check_glb_header(bytes: &[u8]) -> Result<(), String> {
    if let Some(header) = bytes.strip_prefix(b"glTF") {
        let Some(length) = header.get(4..8) else {
            return Err(format!(
                "truncated GLB: {} bytes, less than its 12-byte header",
                bytes.len()
            ));
        };
        let length = u32::from_le_bytes([length[0], length[1], length[2], length[3]]);
        if length < 12 {
            return Err(format!(
                "corrupt GLB: its header declares {length} bytes, less than the 12-byte header"
            ));
        }
        if length as usize > bytes.len() {
            return Err(format!(
                "truncated GLB: its header declares {length} bytes, the file has {}",
                bytes.len()
            ));
        }
    }
    Ok(())
}

/// Every primitive attribute names an accessor that exists.
fn check_attribute_indices(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            for index in primitive.attributes.values() {
                if index.value() >= root.accessors.len() {
                    return Err(format!(
                        "not a valid glTF 2.0 file: meshes[{m}].primitives[{p}].attributes: accessor {} does not exist ({} accessors)",
                        index.value(),
                        root.accessors.len()
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The crate's error in one line; validation errors name the JSON path.
fn gltf_error_text(e: &gltf::Error) -> String {
    match e {
        gltf::Error::Validation(errors) => {
            let shown: Vec<String> = errors
                .iter()
                .take(3)
                .map(|(path, error)| format!("{path}: {error}"))
                .collect();
            let more = errors.len().saturating_sub(3);
            if more > 0 {
                format!("{} (and {more} more)", shown.join("; "))
            } else {
                shown.join("; ")
            }
        }
        other => other.to_string(),
    }
}

/// The walk's state: the triangles and materials gathered so far.
struct Reader<'a, 'r> {
    buffers: &'a [Vec<u8>],
    /// Buffer views as `EXT_meshopt_compression` decoded them (None: as stored).
    decoded_views: &'a [Option<Vec<u8>>],
    /// Accessors that have no buffer view (the one the crate sees is a placeholder).
    viewless: &'a std::collections::HashSet<usize>,
    document: &'a gltf::Document,
    /// The base-colour textures, decoded at their first use.
    images: images::DecodedImages,
    files: images::ImageFiles<'a, 'r>,
    with_materials: bool,
    mesh: Mesh,
    /// glTF material index (None: the default material) -> index in `mesh.materials`.
    material_of: HashMap<Option<usize>, usize>,
    /// Triangles read, zero-area ones included.
    triangles_seen: usize,
    /// Whether meshes placed several times go to `Mesh::instanced`.
    instancing: bool,
    /// The copies of each mesh the scene's nodes place
    /// (`instancing::mesh_uses`).
    uses: Vec<usize>,
}

/// One primitive's vertices as the file gives them, before placement.
struct PrimitiveVertices {
    positions: Vec<DVec3>,
    normals: Option<Vec<DVec3>>,
    colours: Option<Vec<DVec4>>,
    tangents: Option<Vec<DVec4>>,
    /// Three per triangle for TRIANGLES; as the mode says otherwise.
    indices: Vec<usize>,
}

impl Reader<'_, '_> {
    /// Walks `scene`'s node tree depth first, each node with its world
    /// transform, adding its mesh, its light and (the first) its perspective
    /// camera; the number of orthographic cameras met. A node reached twice
    /// (a cycle, or a node with two parents, both invalid glTF) is an
    /// error: it could make the walk endless or exponential.
    fn place_nodes(&mut self, scene: &gltf::Scene) -> Result<usize, String> {
        let mut visited = vec![false; self.document.nodes().count()];
        let mut orthographic_cameras = 0usize;
        let mut instanced_of = HashMap::new();
        let mut stack: Vec<(gltf::Node, DMat4)> =
            scene.nodes().map(|n| (n, DMat4::IDENTITY)).collect();
        stack.reverse();
        while let Some((node, parent)) = stack.pop() {
            let index = node.index();
            if std::mem::replace(&mut visited[index], true) {
                return Err(format!(
                    "node {index} is reached twice from the scene (glTF nodes must form a tree)"
                ));
            }
            let local = node.transform().matrix().map(|c| c.map(f64::from));
            let world = parent * DMat4::from_cols_array_2d(&local);
            if !world.is_finite() {
                return Err(format!(
                    "node {index}: the node transforms give a non-finite matrix"
                ));
            }
            if let Some(mesh) = node.mesh() {
                let copies = self.gpu_instances(&node)?;
                let several = self.uses.get(mesh.index()).is_some_and(|&n| n > 1);
                match copies {
                    Some(copies) => {
                        let worlds = copies.into_iter().map(|c| world * c).collect();
                        self.place_copies(&mesh, worlds, &mut instanced_of)?;
                    }
                    None if several => self.place_copies(&mesh, vec![world], &mut instanced_of)?,
                    None => self.mesh(&mesh, world)?,
                }
            }
            if let Some(light) = node.light() {
                let light = placed::punctual_light(&light, index, world)?;
                self.mesh.lights.push(light);
            }
            if let Some(camera) = node.camera().filter(|_| self.mesh.camera.is_none()) {
                match placed::perspective_camera(&camera, index, world)? {
                    Some(c) => self.mesh.camera = Some(c),
                    None => orthographic_cameras += 1,
                }
            }
            let children: Vec<_> = node.children().collect();
            stack.extend(children.into_iter().rev().map(|c| (c, world)));
        }
        Ok(orthographic_cameras)
    }

    /// Appends the triangles of `mesh` placed by `world`.
    fn mesh(&mut self, mesh: &gltf::Mesh, world: DMat4) -> Result<(), String> {
        for primitive in mesh.primitives() {
            let at = format!("mesh {} primitive {}", mesh.index(), primitive.index());
            self.primitive(&primitive, world, &at)?;
        }
        Ok(())
    }

    /// Appends the triangles of `primitive` placed by `world`; `at` names
    /// it in messages.
    fn primitive(
        &mut self,
        primitive: &gltf::Primitive,
        world: DMat4,
        at: &str,
    ) -> Result<(), String> {
        let mode = primitive.mode();
        if !matches!(
            mode,
            Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan
        ) {
            return Err(format!(
                "{at}: mode {mode:?} is not a surface; kdray draws TRIANGLES, TRIANGLE_STRIP and TRIANGLE_FAN only"
            ));
        }
        let draco = self
            .draco_primitive(primitive)
            .map_err(|m| format!("{at}: {m}"))?;
        let vertices = self.primitive_vertices(primitive, draco.as_ref(), at)?;
        let corners =
            triangle_corners(mode, &vertices.indices).map_err(|m| format!("{at}: {m}"))?;
        let material = self.primitive_material(primitive, at)?;
        let uvs = self.texture_coordinates(primitive, draco.as_ref(), vertices.positions.len(), at);
        self.append(vertices, uvs, &corners, material, world, at)
    }

    /// The positions, normals, colours, tangents and indices (0, 1, 2, ...
    /// where the primitive has none) of `primitive`, from its Draco stream
    /// or its accessors, every count and index checked.
    fn primitive_vertices(
        &self,
        primitive: &gltf::Primitive,
        draco: Option<&draco::DracoPrimitive>,
        at: &str,
    ) -> Result<PrimitiveVertices, String> {
        let mut v = match draco {
            Some(d) => PrimitiveVertices {
                positions: d.positions.clone(),
                normals: d.normals.clone(),
                colours: d.colours.clone(),
                tangents: d.tangents.clone(),
                indices: d.indices.clone(),
            },
            None => self.plain_primitive(primitive, at)?,
        };
        let count = v.positions.len();
        let lengths = [
            ("normals", v.normals.as_ref().map(Vec::len)),
            ("COLOR_0 colours", v.colours.as_ref().map(Vec::len)),
            ("tangents", v.tangents.as_ref().map(Vec::len)),
        ];
        for (what, n) in lengths {
            if let Some(n) = n.filter(|&n| n != count) {
                return Err(format!("{at}: {n} {what} for {count} positions"));
            }
        }
        if let Some(bad) = v.indices.iter().find(|&&i| i >= count) {
            return Err(format!(
                "{at}: index {bad} is out of range: {count} vertices"
            ));
        }
        if v.indices.is_empty() && primitive.indices().is_none() && draco.is_none() {
            v.indices = (0..count).collect();
        }
        Ok(v)
    }

    /// The index in the mesh's materials of `primitive`'s material, read
    /// (with its textures) the first time a primitive uses it; NO_INDEX
    /// when materials were not asked for.
    fn primitive_material(&mut self, primitive: &gltf::Primitive, at: &str) -> Result<u32, String> {
        if !self.with_materials {
            return Ok(NO_INDEX);
        }
        let key = primitive.material().index();
        let next = self.mesh.materials.len();
        let local = *self.material_of.entry(key).or_insert(next);
        if local == next {
            let mut material = pbr_material(&primitive.material());
            if material.alpha.mode == crate::scene::alpha::AlphaMode::Blend {
                let warning = alpha::blend_warning(self.files.path);
                if !self.mesh.warnings.contains(&warning) {
                    self.mesh.warnings.push(warning);
                }
            }
            material.texture = self.images.base_colour(
                &primitive.material(),
                self.document,
                &mut self.files,
                &mut self.mesh.warnings,
            );
            material.maps = self.images.maps(
                &primitive.material(),
                self.document,
                &mut self.files,
                &mut self.mesh.warnings,
            );
            material.maps.second_uv =
                texture_transform::uv_channels(&primitive.material()).map_or(0, |c| c.second_slots);
            self.mesh.materials.push(material);
        }
        mesh_index(local).ok_or_else(|| format!("{at}: more materials than a mesh can index"))
    }

    /// Appends a primitive's vertices (normals, colours, tangents and
    /// texture coordinates) to the mesh's, placed by `world`, and its
    /// triangles (`corners`, zero-area ones skipped) with their indices
    /// offset by what was there before. The bases are checked so that every
    /// index fits below NO_INDEX.
    fn append(
        &mut self,
        v: PrimitiveVertices,
        uvs: Option<images::PrimitiveUvs>,
        corners: &[[usize; 3]],
        material: u32,
        world: DMat4,
        at: &str,
    ) -> Result<(), String> {
        let too_many = || {
            format!(
                "{at}: the scene places more than {NO_INDEX} vertices, more than a mesh can index"
            )
        };
        let linear = DMat3::from_mat4(world);
        let normal_matrix = crate::scene::normals::normal_matrix(linear);
        let uv_base = self.mesh.uvs.len();
        if let Some(uvs) = &uvs {
            mesh_index(uv_base + uvs.first.len()).ok_or_else(too_many)?;
            self.mesh.uvs.extend_from_slice(&uvs.first);
        }
        let vertex_base = self.mesh.positions.len();
        let count = v.positions.len();
        // The second channel lies beside the positions, once any primitive
        // has one (zero for the others').
        let second = uvs.as_ref().and_then(|u| u.second.as_ref());
        if second.is_some() || !self.mesh.second_uvs.is_empty() {
            self.mesh.second_uvs.resize(vertex_base, DVec2::ZERO);
            match second {
                Some(s) => self.mesh.second_uvs.extend_from_slice(s),
                None => self
                    .mesh
                    .second_uvs
                    .resize(vertex_base + count, DVec2::ZERO),
            }
        }
        mesh_index(vertex_base + count).ok_or_else(too_many)?;
        let normal_base = self.mesh.normals.len();
        if let Some(normals) = &v.normals {
            mesh_index(normal_base + normals.len()).ok_or_else(too_many)?;
            self.mesh
                .normals
                .extend(normals.iter().map(|&n| normal_matrix * n));
        }
        // Colours and tangents lie beside the positions, once any
        // primitive has them (white, and none, for the others').
        if v.colours.is_some() || !self.mesh.colours.is_empty() {
            let colours = v.colours.unwrap_or_else(|| vec![DVec4::ONE; count]);
            self.mesh.colours.resize(vertex_base, DVec4::ONE);
            self.mesh.colours.extend(colours);
        }
        if v.tangents.is_some() || !self.mesh.tangents.is_empty() {
            let tangents = v.tangents.unwrap_or_else(|| vec![DVec4::ZERO; count]);
            self.mesh.tangents.resize(vertex_base, DVec4::ZERO);
            let mirror = linear.determinant().signum();
            self.mesh.tangents.extend(tangents.iter().map(|t| {
                let xyz = linear * t.truncate();
                // A zero sign or direction is no tangent.
                let w = if t.w == 0.0 {
                    0.0
                } else {
                    t.w.signum() * mirror
                };
                xyz.extend(if xyz.length_squared() > 0.0 { w } else { 0.0 })
            }));
        }
        self.mesh
            .positions
            .extend(v.positions.iter().map(|&p| world.transform_point3(p)));
        let placed = &self.mesh.positions[vertex_base..];
        for c in corners {
            self.triangles_seen += 1;
            let vertices = c.map(|i| placed[i]);
            if !crate::scene::mesh::has_area(&vertices) {
                continue; // cannot be hit, has no normal
            }
            // In range: the bases plus a count were checked above.
            self.mesh.triangles.push(MeshTriangle {
                corners: c.map(|i| (vertex_base + i) as u32),
                normals: if v.normals.is_some() {
                    c.map(|i| (normal_base + i) as u32)
                } else {
                    [NO_INDEX; 3]
                },
                uvs: if uvs.is_some() {
                    c.map(|i| (uv_base + i) as u32)
                } else {
                    [NO_INDEX; 3]
                },
                material,
            });
        }
        Ok(())
    }

    /// An uncompressed primitive's attributes and indices (empty: not
    /// indexed), from its accessors.
    fn plain_primitive(
        &self,
        primitive: &gltf::Primitive,
        at: &str,
    ) -> Result<PrimitiveVertices, String> {
        let Some(positions) = primitive.get(&gltf::Semantic::Positions) else {
            return Err(format!("{at}: no POSITION attribute"));
        };
        let positions = self
            .read_vec3(&positions, Attribute::Position)
            .map_err(|m| format!("{at}: POSITION {m}"))?;
        let read = |semantic: gltf::Semantic| primitive.get(&semantic);
        let normals = read(gltf::Semantic::Normals)
            .map(|a| self.read_vec3(&a, Attribute::Normal))
            .transpose()
            .map_err(|m| format!("{at}: NORMAL {m}"))?;
        let colours = read(gltf::Semantic::Colors(0))
            .map(|a| self.read_colours(&a))
            .transpose()
            .map_err(|m| format!("{at}: COLOR_0 {m}"))?;
        let tangents = read(gltf::Semantic::Tangents)
            .map(|a| self.read_tangents(&a))
            .transpose()
            .map_err(|m| format!("{at}: TANGENT {m}"))?;
        let indices = primitive
            .indices()
            .map(|a| self.read_indices(&a))
            .transpose()
            .map_err(|m| format!("{at}: indices {m}"))?
            .unwrap_or_default();
        Ok(PrimitiveVertices {
            positions,
            normals,
            colours,
            tangents,
            indices,
        })
    }
}

/// The vertex indices of each triangle of a primitive. Strips alternate
/// their winding so all triangles face one way, as the glTF spec orders them.
fn triangle_corners(mode: Mode, indices: &[usize]) -> Result<Vec<[usize; 3]>, String> {
    let n = indices.len();
    Ok(match mode {
        Mode::Triangles => {
            if !n.is_multiple_of(3) {
                return Err(format!("TRIANGLES with {n} vertices, not a multiple of 3"));
            }
            indices
                .chunks_exact(3)
                .map(|t| [t[0], t[1], t[2]])
                .collect()
        }
        Mode::TriangleStrip => (0..n.saturating_sub(2))
            .map(|i| {
                if i % 2 == 0 {
                    [indices[i], indices[i + 1], indices[i + 2]]
                } else {
                    [indices[i], indices[i + 2], indices[i + 1]]
                }
            })
            .collect(),
        Mode::TriangleFan => (1..n.saturating_sub(1))
            .map(|i| [indices[i], indices[i + 1], indices[0]])
            .collect(),
        _ => Vec::new(),
    })
}

/// Fraction of the base colour used as the ambient colour.
pub const PBR_AMBIENT_FRACTION: f64 = 0.1;
/// Largest shininess from a roughness near 0 (a Blinn-Phong exponent of 4096).
pub const PBR_MAX_SHININESS: f64 = 4.0 * 4096.0;

/// glTF's metallic-roughness material in kdray's model (docs/scene-format.md):
/// - diffuse = baseColorFactor (rgb), ambient = 0.1 x that; its alpha,
///   alphaMode and alphaCutoff are the material's [`Alpha`](crate::scene::Alpha);
/// - reflection = metallic x (1 - roughness): a polished metal is a mirror,
///   a rough one (glTF's default material is metallic 1, roughness 1) is not;
/// - specular = white x (1 - roughness);
/// - shininess = 4 x (2 / alpha^2 - 2), alpha = roughness^2, the Blinn-Phong
///   exponent whose lobe matches the GGX width (kdray's exponent is
///   shininess / 4), at most [`PBR_MAX_SHININESS`].
///
/// - transmission = `KHR_materials_transmission`'s transmissionFactor (0
///   without the extension), ior = `KHR_materials_ior`'s ior (1.5, glTF's
///   default, without it; glTF's ior 0 would mean "no refraction" there, and
///   is read as 1, an index that bends nothing); the transmission's
///   roughness is the material's roughness, and it is thin-walled (light
///   passes unbent) unless `KHR_materials_volume` gives a thickness > 0.
///
/// The path tracer reads glTF's own model: base colour, metallic and
/// roughness as they are, and `emissiveFactor` (times
/// `KHR_materials_emissive_strength`'s strength) as emitted radiance. The
/// base-colour texture is the reader's (`images`), here None.
pub fn pbr_material(material: &gltf::Material) -> MeshMaterial {
    let pbr = material.pbr_metallic_roughness();
    let [r, g, b, _alpha] = pbr.base_color_factor().map(f64::from);
    let base = DVec3::new(r, g, b);
    let metallic = f64::from(pbr.metallic_factor()).clamp(0.0, 1.0);
    let roughness = f64::from(pbr.roughness_factor()).clamp(0.0, 1.0);
    let alpha_squared = roughness.powi(4);
    let shininess = if alpha_squared > 0.0 {
        (4.0 * (2.0 / alpha_squared - 2.0)).min(PBR_MAX_SHININESS)
    } else {
        PBR_MAX_SHININESS
    };
    let name = match (material.index(), material.name()) {
        (_, Some(name)) if !name.is_empty() => name.to_string(),
        (Some(i), _) => format!("material{i}"),
        (None, _) => "default".to_string(),
    };
    MeshMaterial {
        name,
        ambient: PBR_AMBIENT_FRACTION * base,
        diffuse: base,
        specular: DVec3::splat(1.0 - roughness),
        shininess: shininess.max(0.0),
        reflection: metallic * (1.0 - roughness),
        transmission: material
            .transmission()
            .map_or(0.0, |t| f64::from(t.transmission_factor()).clamp(0.0, 1.0)),
        ior: match material.ior().map(f64::from) {
            Some(ior) if ior > 0.0 && ior.is_finite() => ior,
            Some(_) => 1.0,
            None => crate::scene::material::Material::DEFAULT_IOR,
        },
        texture: None,
        physical: crate::scene::material::Physical {
            metal_rough: Some(crate::scene::material::MetalRough {
                metallic,
                roughness,
            }),
            emission: emission(material),
            two_sided: material.double_sided(),
            volume: volume(material),
            transmission_roughness: roughness,
            thin_walled: material
                .volume()
                .is_none_or(|v| v.thickness_factor() <= 0.0),
        },
        maps: crate::scene::material::MaterialMaps::NONE,
        alpha: alpha(material),
    }
}

/// `KHR_materials_volume`'s medium: its attenuation colour (clamped into
/// [0, 1]) and distance (glTF's default, infinity, where it is not a
/// positive number); None without the extension. A path tracer meets the
/// mesh's real walls, so `thicknessFactor` (a rasteriser's stand-in for
/// them) is not read.
fn volume(material: &gltf::Material) -> Option<crate::scene::material::Volume> {
    let v = material.volume()?;
    let colour = DVec3::from_array(v.attenuation_color().map(f64::from));
    let distance = f64::from(v.attenuation_distance());
    Some(crate::scene::material::Volume {
        attenuation_color: if colour.is_finite() {
            colour.clamp(DVec3::ZERO, DVec3::ONE)
        } else {
            DVec3::ONE
        },
        attenuation_distance: if distance > 0.0 {
            distance
        } else {
            f64::INFINITY
        },
    })
}

/// A material's emitted radiance: emissiveFactor times
/// `KHR_materials_emissive_strength`'s emissiveStrength (1 without the
/// extension; glTF clamps the factor to [0, 1], the strength lifts it past 1).
/// A negative or non-finite product is read as 0.
fn emission(material: &gltf::Material) -> DVec3 {
    let factor = DVec3::from_array(material.emissive_factor().map(f64::from));
    let strength = material.emissive_strength().map_or(1.0, f64::from);
    let e = factor * strength;
    if e.is_finite() {
        e.max(DVec3::ZERO)
    } else {
        DVec3::ZERO
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_make_consistently_wound_triangles() {
        let strip = triangle_corners(Mode::TriangleStrip, &[0, 1, 2, 3, 4]).unwrap();
        assert_eq!(strip, [[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
        let fan = triangle_corners(Mode::TriangleFan, &[0, 1, 2, 3]).unwrap();
        assert_eq!(fan, [[1, 2, 0], [2, 3, 0]]);
        assert!(triangle_corners(Mode::Triangles, &[0, 1, 2, 3]).is_err());
        assert!(triangle_corners(Mode::TriangleStrip, &[0, 1])
            .unwrap()
            .is_empty());
    }

    #[test]
    fn glb_headers_that_lie_about_their_length_are_refused() {
        assert!(check_glb_header(b"glTF\x02\0\0\0").is_err());
        assert!(check_glb_header(b"glTF\x02\0\0\0\x04\0\0\0").is_err());
        assert!(check_glb_header(b"glTF\x02\0\0\0\xff\0\0\0").is_err());
        assert!(check_glb_header(b"{\"asset\": {}}").is_ok());
    }
}
