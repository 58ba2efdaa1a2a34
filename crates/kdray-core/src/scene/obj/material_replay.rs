//! The fast path's material statements replayed in file order, on one
//! thread between parsing the chunks and resolving their faces: `mtllib`
//! reads MTL files, `usemtl` names the material of the faces after it.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use super::chunk::{Chunk, Event};
use super::mtl::parse_mtl;
use super::tokens::rest_of_line;
use crate::scene::mesh::MeshMaterial;

/// Where the materials of a file come from: the OBJ's path (MTL files are
/// relative to its folder) and the observer told of each MTL file just
/// before it is read.
pub(super) struct MaterialFiles<'p> {
    pub path: &'p Path,
    pub on_read: &'p mut dyn FnMut(&Path),
}

/// The materials of a chunk's faces: (first face, material) for each run of
/// faces with one material, the first run at face 0.
pub(super) type MaterialRuns = Vec<(usize, Option<usize>)>;

/// The reference parser's material statements replayed in file order:
/// `mtllib` reads MTL files into the library, `usemtl` names the material
/// of the faces after it, which becomes used at the first such face.
pub(super) struct MaterialState<'p, 't> {
    pub(super) files: MaterialFiles<'p>,
    pub(super) library: HashMap<String, MeshMaterial>,
    pub(super) loaded: Vec<PathBuf>,
    /// Index in `used` of each material used so far, by name.
    pub(super) used_index: HashMap<String, usize>,
    pub(super) used: Vec<MeshMaterial>,
    /// The last `usemtl`'s name, from the text.
    pub(super) current: Option<&'t str>,
    pub(super) current_index: Option<usize>,
    /// MTL files the observer was told of.
    pub(super) reads: usize,
}

impl<'p, 't> MaterialState<'p, 't> {
    pub(super) fn new(files: MaterialFiles<'p>) -> Self {
        MaterialState {
            files,
            library: HashMap::new(),
            loaded: Vec::new(),
            used_index: HashMap::new(),
            used: Vec::new(),
            current: None,
            current_index: None,
            reads: 0,
        }
    }

    /// Per chunk, the runs of its faces' material: (first face, material).
    /// None where the reference parser refuses a statement or warns (a face
    /// with no material, an undefined material, an MTL file unread or with
    /// textures): it words both, with lines.
    pub(super) fn runs(&mut self, chunks: &[Chunk<'t>]) -> Option<Vec<MaterialRuns>> {
        let mut all = Vec::with_capacity(chunks.len());
        for chunk in chunks {
            let mut runs = Vec::new();
            let mut next_face = 0usize;
            for &(faces_before, event) in &chunk.events {
                if faces_before > next_face {
                    runs.push((next_face, Some(self.face_material()?)));
                    next_face = faces_before;
                }
                match event {
                    Event::Mtllib(line) => self.mtllib(line)?,
                    Event::Usemtl(line) => {
                        let name = rest_of_line(line, "usemtl");
                        if name.is_empty() {
                            return None;
                        }
                        self.current = Some(name);
                        self.current_index = None;
                    }
                }
            }
            if chunk.faces.len() > next_face {
                runs.push((next_face, Some(self.face_material()?)));
            }
            all.push(runs);
        }
        Some(all)
    }

    /// The material of a face: the last `usemtl`'s, in order of first use.
    fn face_material(&mut self) -> Option<usize> {
        if let Some(index) = self.current_index {
            return Some(index);
        }
        let name = self.current?;
        let found = self.library.get(name)?;
        let index = *self.used_index.entry(name.to_string()).or_insert_with(|| {
            self.used.push(found.clone());
            self.used.len() - 1
        });
        self.current_index = Some(index);
        Some(index)
    }

    /// Reads the MTL files of an `mtllib` statement not read yet.
    fn mtllib(&mut self, line: &str) -> Option<()> {
        let mut any = false;
        for name in line.split_ascii_whitespace().skip(1) {
            any = true;
            let folder = self.files.path.parent().unwrap_or_else(|| Path::new(""));
            let mtl_path = folder.join(name);
            if self.loaded.contains(&mtl_path) {
                continue;
            }
            (self.files.on_read)(&mtl_path);
            self.reads += 1;
            let text = crate::scene::input_file::read_input_file(&mtl_path).ok()?;
            let mut warnings = Vec::new();
            parse_mtl(
                &super::text_of(&text),
                &mtl_path,
                &mut self.library,
                &mut warnings,
            )
            .ok()?;
            // Warnings carry lines, which only the reference parser counts.
            if !warnings.is_empty() {
                return None;
            }
            self.loaded.push(mtl_path);
        }
        // A material that was undefined before may be defined now.
        self.current_index = None;
        any.then_some(())
    }
}
