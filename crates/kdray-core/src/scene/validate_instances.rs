//! The rules of `[shapes.NAME]` and `[[instances]]` (docs/scene-format.md):
//! each shape loaded once (a mesh file, through the same reader as
//! `[[meshes]]`, or inline triangles), each instance's shape, transform
//! (scale, rotate and translate, or a 4x4 matrix: affine, finite and
//! invertible) and material checked, and its shape's box placed within the
//! coordinates the GPU takes.

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

use glam::{DAffine3, DMat3, DVec3};

use super::error::SceneError;
use super::instances::{mesh_bounds, transformed_box, Instance, Shape, MAX_FLATTENED_OBJECTS};
use super::material::Material;
use super::mesh::{has_area, Mesh, MeshTriangle, NO_INDEX};
use super::schema::RawScene;
use super::schema::{RawInstance, RawMatrix, RawShape};
use super::triangle_parts::TriangleParts;
use super::validate::{Validator, MAX_COORDINATE};

impl Validator<'_> {
    /// `[shapes.NAME]`, in name order: each a mesh file (`path`) or inline
    /// `triangles`, not both; the file's materials (unless the shape names
    /// one) appended to `materials`, their images to `parts.textures`.
    pub(super) fn shapes(
        &self,
        raw: &RawScene,
        material_index: &BTreeMap<String, u32>,
        materials: &mut Vec<Material>,
        parts: &mut TriangleParts,
    ) -> Result<Vec<Shape>, SceneError> {
        let mut shapes = Vec::with_capacity(raw.shapes.len());
        for (name, s) in &raw.shapes {
            shapes.push(self.shape(name, s, material_index, materials, parts)?);
        }
        Ok(shapes)
    }

    fn shape(
        &self,
        name: &str,
        s: &RawShape,
        material_index: &BTreeMap<String, u32>,
        materials: &mut Vec<Material>,
        parts: &mut TriangleParts,
    ) -> Result<Shape, SceneError> {
        let key = |k: &str| format!("shapes.{name}.{k}");
        let material = match &s.material {
            Some(m) => Some(self.material_named(material_index, &|| key("material"), m)?),
            None => None,
        };
        let first_material = materials.len() as u32;
        let mesh = match (&s.path, &s.triangles) {
            (Some(path), None) => {
                let mesh_path = self.file.parent().unwrap_or(Path::new("")).join(path);
                // A shape's own copies are placed into it: instances of
                // instances are not kept.
                let mesh =
                    self.load_entry_mesh(&key("path"), &mesh_path, material.is_none(), false)?;
                if material.is_none() {
                    self.add_mesh_materials(
                        &key("path"),
                        path,
                        &mesh_path,
                        &mesh,
                        materials,
                        &mut parts.textures,
                    )?;
                }
                mesh
            }
            (None, Some(triangles)) => {
                if material.is_none() {
                    return Err(self.error(
                        &key("material"),
                        "inline triangles need a material (the name of a [materials.NAME])",
                    ));
                }
                self.inline_mesh(&key("triangles"), triangles)?
            }
            (Some(_), Some(_)) => {
                return Err(self.error(
                    &key("triangles"),
                    "give path (a mesh file) or triangles (inline), not both",
                ))
            }
            (None, None) => {
                return Err(self.error(
                    &format!("shapes.{name}"),
                    "missing field `path` (a mesh file) or `triangles` (inline)",
                ))
            }
        };
        let bounds = mesh_bounds(&mesh);
        Ok(Shape {
            name: name.to_string(),
            mesh: Arc::new(mesh),
            smooth: s.smooth,
            material,
            first_material,
            bounds,
        })
    }

    /// Inline triangles (the value of `key`) as a mesh: three positions
    /// each, with area, none shared.
    fn inline_mesh(
        &self,
        key: &str,
        triangles: &[super::schema::Exact<super::schema::Vec3, 3>],
    ) -> Result<Mesh, SceneError> {
        if triangles.is_empty() {
            return Err(self.error(key, "must hold at least one triangle"));
        }
        let mut mesh = Mesh::default();
        for (j, t) in triangles.iter().enumerate() {
            let mut vertices = [DVec3::ZERO; 3];
            for (k, (v, raw_v)) in vertices.iter_mut().zip(t.0).enumerate() {
                *v = self.position(&|| format!("{key}[{j}][{k}]"), raw_v)?;
            }
            if !has_area(&vertices) {
                return Err(self.error(&format!("{key}[{j}]"), "triangle has zero area"));
            }
            let first = mesh.positions.len() as u32;
            mesh.positions.extend(vertices);
            mesh.triangles.push(MeshTriangle {
                corners: [first, first + 1, first + 2],
                normals: [NO_INDEX; 3],
                uvs: [NO_INDEX; 3],
                material: NO_INDEX,
            });
        }
        Ok(mesh)
    }

    /// `[[instances]]`: each names a shape of `shapes`, places it by a
    /// 4x4 `matrix` or by `scale`, `rotate` and `translate` (not both),
    /// and may name a material.
    pub(super) fn instances(
        &self,
        raw: &RawScene,
        shapes: &[Shape],
        material_index: &BTreeMap<String, u32>,
    ) -> Result<Vec<Instance>, SceneError> {
        let shape_index: BTreeMap<&str, u32> = shapes
            .iter()
            .enumerate()
            .map(|(i, s)| (s.name.as_str(), i as u32))
            .collect();
        let mut instances = Vec::with_capacity(raw.instances.len());
        for (i, inst) in raw.instances.iter().enumerate() {
            let key = |k: &str| format!("instances[{i}].{k}");
            let Some(&shape) = shape_index.get(inst.shape.as_str()) else {
                let known: Vec<&str> = shape_index.keys().copied().collect();
                return Err(self.error(
                    &key("shape"),
                    format!(
                        "unknown shape \"{}\" (defined: {})",
                        inst.shape,
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                ));
            };
            let (transform, at) = self.instance_transform(i, inst)?;
            let material = match &inst.material {
                Some(m) => Some(self.material_named(material_index, &|| key("material"), m)?),
                None => None,
            };
            let instance = Instance {
                shape,
                transform,
                material,
            };
            if let Some(s) = shapes.get(shape as usize) {
                let [lo, hi] = transformed_box(&transform, &s.bounds);
                let in_range = |v: DVec3| v.is_finite() && v.abs().max_element() <= MAX_COORDINATE;
                if !(in_range(lo) && in_range(hi)) {
                    return Err(self.error(
                        &key(at),
                        format!(
                            "the placed shape \"{}\" reaches beyond ±{MAX_COORDINATE:e} or out of the 64-bit floats (its box from {:?} to {:?}; the GPU computes in f32)",
                            inst.shape,
                            lo.to_array(),
                            hi.to_array()
                        ),
                    ));
                }
            }
            instances.push(instance);
        }
        Ok(instances)
    }

    /// That the scene, its `objects` and the triangles its instances place,
    /// fits the k-d tree once flattened (as the renderers trace it).
    pub(super) fn flattened_size(
        &self,
        objects: usize,
        shapes: &[Shape],
        instances: &[Instance],
    ) -> Result<(), SceneError> {
        let placed: usize = instances
            .iter()
            .filter_map(|i| shapes.get(i.shape as usize))
            .map(|s| s.mesh.triangles.len())
            .sum();
        if objects.saturating_add(placed) > MAX_FLATTENED_OBJECTS {
            return Err(self.error(
                "instances",
                format!(
                    "the instances place {placed} triangles; with the scene's other {objects} objects that is more than the {MAX_FLATTENED_OBJECTS} the renderer traces (it flattens instances into triangles)"
                ),
            ));
        }
        Ok(())
    }

    /// Instance `i`'s transform, and the key that gave it (`matrix`, or
    /// `scale` for scale, rotate and translate).
    fn instance_transform(
        &self,
        i: usize,
        inst: &RawInstance,
    ) -> Result<(DAffine3, &'static str), SceneError> {
        let key = |k: &str| format!("instances[{i}].{k}");
        let by_parts = inst.scale.is_some() || inst.rotate.is_some() || inst.translate.is_some();
        let (matrix3, translation, at) = match &inst.matrix {
            Some(_) if by_parts => {
                return Err(self.error(
                    &key("matrix"),
                    "give matrix, or scale, rotate and translate, not both",
                ))
            }
            Some(m) => {
                let (matrix3, translation) = self.matrix(&key("matrix"), m)?;
                (matrix3, translation, "matrix")
            }
            None => {
                let (matrix3, translation) = self.scale_rotate_translate(
                    &format!("instances[{i}]"),
                    inst.scale.as_ref().unwrap_or(&Default::default()),
                    inst.rotate.unwrap_or_default(),
                    inst.translate.unwrap_or_default(),
                )?;
                (matrix3, translation, "scale")
            }
        };
        let det = matrix3.determinant();
        if !(det.is_finite() && det != 0.0 && matrix3.inverse().is_finite()) {
            return Err(self.error(
                &key(at),
                format!(
                    "the transform is singular (determinant {det:e}): it would flatten the shape"
                ),
            ));
        }
        Ok((
            DAffine3 {
                matrix3,
                translation,
            },
            at,
        ))
    }

    /// A row-major 4x4 matrix at `key`: every entry finite, the last row
    /// `[0, 0, 0, 1]`, the translation (last column) a position.
    fn matrix(&self, key: &str, m: &RawMatrix) -> Result<(DMat3, DVec3), SceneError> {
        let mut rows = [[0.0; 4]; 4];
        for (r, row) in m.0.iter().enumerate() {
            for (c, &x) in row.0.iter().enumerate() {
                rows[r][c] = self.number(&|| format!("{key}[{r}][{c}]"), x)?;
            }
        }
        if rows[3] != [0.0, 0.0, 0.0, 1.0] {
            return Err(self.error(
                &format!("{key}[3]"),
                format!(
                    "must be [0, 0, 0, 1] (an instance's transform is affine), got {:?}",
                    rows[3]
                ),
            ));
        }
        let translation = DVec3::new(rows[0][3], rows[1][3], rows[2][3]);
        for (r, x) in translation.to_array().into_iter().enumerate() {
            if x.abs() > MAX_COORDINATE {
                return Err(self.error(
                    &format!("{key}[{r}][3]"),
                    format!(
                        "must be within ±{MAX_COORDINATE:e} (the GPU computes in f32), got {x:e}"
                    ),
                ));
            }
        }
        let column = |c: usize| DVec3::new(rows[0][c], rows[1][c], rows[2][c]);
        Ok((
            DMat3::from_cols(column(0), column(1), column(2)),
            translation,
        ))
    }
}
