//! The tables the scene keeps beside its triangles (vertex normals, texture
//! coordinates, colours, tangents, textures), filled as the meshes add
//! triangles.

use glam::{DVec2, DVec3, DVec4};

use super::objects::Triangle;
use super::texture::Texture;

/// What the scene keeps beside its triangles, as the meshes add them:
/// [`Scene::triangle_normals`](super::Scene::triangle_normals),
/// [`Scene::triangle_uvs`](super::Scene::triangle_uvs) and
/// [`Scene::textures`](super::Scene::textures).
#[derive(Default)]
pub(super) struct TriangleParts {
    pub(super) normals: Vec<[DVec3; 3]>,
    pub(super) uvs: Vec<[DVec2; 3]>,
    pub(super) second_uvs: Vec<[DVec2; 3]>,
    pub(super) colours: Vec<[DVec4; 3]>,
    pub(super) tangents: Vec<[DVec4; 3]>,
    pub(super) textures: Vec<Texture>,
}

/// What one triangle keeps beside its corners in
/// [`Scene::triangle_uvs`](super::Scene::triangle_uvs)
/// and its neighbours.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct SurfaceRecord {
    pub uvs: Option<[DVec2; 3]>,
    pub second_uvs: Option<[DVec2; 3]>,
    pub colours: Option<[DVec4; 3]>,
    pub tangents: Option<[DVec4; 3]>,
}

impl TriangleParts {
    /// White: the colour of a vertex without `COLOR_0`.
    const WHITE: [DVec4; 3] = [DVec4::ONE; 3];

    /// Gives `triangle` the record `r` (texture coordinates, colours,
    /// tangents) at the end of the tables, if it has texture coordinates or
    /// colours; the colour and tangent tables are filled in (white, none)
    /// for the entries before the first that has them.
    pub(super) fn add_record(&mut self, triangle: &mut Triangle, r: SurfaceRecord) {
        if r.uvs.is_none() && r.colours.is_none() {
            return;
        }
        let Ok(index) = u32::try_from(self.uvs.len()) else {
            return;
        };
        triangle.uvs = index;
        self.uvs.push(r.uvs.unwrap_or([DVec2::ZERO; 3]));
        let n = self.uvs.len();
        if r.second_uvs.is_some() || !self.second_uvs.is_empty() {
            self.second_uvs.resize(n - 1, [DVec2::ZERO; 3]);
            self.second_uvs
                .push(r.second_uvs.unwrap_or([DVec2::ZERO; 3]));
        }
        if r.colours.is_some() || !self.colours.is_empty() {
            self.colours.resize(n - 1, Self::WHITE);
            self.colours.push(r.colours.unwrap_or(Self::WHITE));
        }
        if r.tangents.is_some() || !self.tangents.is_empty() {
            self.tangents.resize(n - 1, [DVec4::ZERO; 3]);
            self.tangents.push(r.tangents.unwrap_or([DVec4::ZERO; 3]));
        }
    }

    /// The tables filled to one entry per record (after the last triangle).
    pub(super) fn finish(&mut self) {
        let n = self.uvs.len();
        if !self.second_uvs.is_empty() {
            self.second_uvs.resize(n, [DVec2::ZERO; 3]);
        }
        if !self.colours.is_empty() {
            self.colours.resize(n, Self::WHITE);
        }
        if !self.tangents.is_empty() {
            self.tangents.resize(n, [DVec4::ZERO; 3]);
        }
    }
}
