//! Scenes: the validated, world-space description that everything downstream
//! consumes. Parsing (TOML or JSON), validation and mesh loading (OBJ/MTL,
//! glTF 2.0) live in the submodules; nothing here knows about the GPU or the
//! k-d tree.
//!
//! Units: positions in scene units, angles in degrees in files and radians
//! nowhere in this module (the camera keeps `vfov_degrees`), colours linear.

mod camera_basis;
mod error;
pub mod gltf;
pub mod mesh;
mod normals;
pub mod obj;
mod obj_chunks;
mod parse;
mod source_map;

pub use camera_basis::CameraBasis;
pub use error::SceneError;
pub use parse::{
    check_samples, load_scene, load_scene_observed, parse_scene, scene_text, SceneFormat,
    MAX_IMAGE_SIDE,
};

use glam::DVec3;

/// A fully validated scene. All values are finite; materials are referred
/// to by index into `materials`.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub camera: Camera,
    pub render: RenderSettings,
    pub lights: Vec<Light>,
    pub materials: Vec<Material>,
    pub spheres: Vec<Sphere>,
    pub triangles: Vec<Triangle>,
    /// The vertex normals of the smooth-shaded triangles, which
    /// [`Triangle::normals`] indexes ([`Scene::normals_of`]).
    pub triangle_normals: Vec<[DVec3; 3]>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    pub position: DVec3,
    pub look_at: DVec3,
    pub up: DVec3,
    /// Vertical field of view in degrees, in (0, 180).
    pub vfov_degrees: f64,
}

/// What happens at a hit from which no light is visible.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShadowMode {
    /// The hit still gets its ambient term and the path goes on.
    Ambient,
    /// The path ends and adds nothing (the seed's Algorithm 1).
    Seed,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    /// The seed's ind_ref: a path stops once its weight falls below this.
    pub min_intensity: f64,
    /// Most hits evaluated along one path, primary hit included (1..=64).
    pub max_depth: u32,
    pub background: DVec3,
    pub shadow_mode: ShadowMode,
    /// Samples per pixel, a perfect square k * k.
    pub samples: u32,
}

impl RenderSettings {
    /// k for samples = k * k.
    pub fn samples_per_axis(&self) -> u32 {
        (self.samples as f64).sqrt().round() as u32
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    pub position: DVec3,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    /// The name in the scene file, or `mesh-file.obj:mtl-name` for MTL materials.
    pub name: String,
    pub ambient: DVec3,
    pub diffuse: DVec3,
    pub specular: DVec3,
    /// >= 0; the Blinn-Phong exponent is shininess / 4.
    pub shininess: f64,
    /// 0 = opaque .. 1 = perfect mirror.
    pub reflection: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: DVec3,
    pub radius: f64,
    pub material: u32,
}

/// A two-sided triangle, from `[[triangles]]` or a mesh (already
/// transformed). 80 bytes: its vertex normals, where it has them, lie in
/// [`Scene::triangle_normals`] (with the normals in it, a triangle took 160
/// bytes, and building the 1.1 M-triangle bunny's took 34 ms of its load,
/// 26 ms since; temporary timers, two threads).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    pub vertices: [DVec3; 3],
    pub material: u32,
    /// Index into [`Scene::triangle_normals`] of its unit shading normals at
    /// the three vertices, in world space, for smooth shading;
    /// [`Triangle::FLAT`]: the geometric normal everywhere.
    pub normals: u32,
}

impl Triangle {
    /// [`Triangle::normals`] of a flat-shaded triangle.
    pub const FLAT: u32 = u32::MAX;

    /// A flat-shaded triangle (no vertex normals).
    pub fn flat(vertices: [DVec3; 3], material: u32) -> Self {
        Triangle {
            vertices,
            material,
            normals: Triangle::FLAT,
        }
    }
}

impl Scene {
    /// Number of objects, spheres first then triangles: the object ids used by
    /// the k-d tree and the shader are `0..object_count()`.
    pub fn object_count(&self) -> usize {
        self.spheres.len() + self.triangles.len()
    }

    /// The shading normals of `t`, a triangle of this scene, or None for a
    /// flat one.
    pub fn normals_of(&self, t: &Triangle) -> Option<[DVec3; 3]> {
        self.triangle_normals.get(t.normals as usize).copied()
    }
}

/// Largest scene, mesh, MTL or glTF buffer file read (bytes).
pub const MAX_INPUT_BYTES: u64 = 2 << 30;

/// Reads an input file: only regular files (a path like /dev/zero would be
/// read forever), at most MAX_INPUT_BYTES, into a vector of its size (one
/// byte more, where `read_to_end` sees the end) on huge pages.
pub(crate) fn read_input_file(path: &std::path::Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    use std::io::{Error, ErrorKind};
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(Error::new(ErrorKind::InvalidInput, "not a regular file"));
    }
    if meta.len() > MAX_INPUT_BYTES {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("larger than {} GiB", MAX_INPUT_BYTES >> 30),
        ));
    }
    let mut file = std::fs::File::open(path)?;
    let room = usize::try_from(meta.len() + 1).unwrap_or(usize::MAX);
    let mut bytes = crate::huge_pages::try_with_capacity(room)
        .map_err(|e| Error::new(ErrorKind::OutOfMemory, e.to_string()))?;
    #[cfg(unix)]
    if meta.len() >= PARALLEL_READ_BYTES {
        use std::io::{Seek, SeekFrom};
        let len = room - 1;
        read_on_threads(&file, &mut bytes.spare_capacity_mut()[..len])?;
        // SAFETY: `read_on_threads` returned Ok, so it wrote all of the
        // first `len` bytes of the spare capacity.
        unsafe { bytes.set_len(len) };
        // Then on, as for any file: what it has past that size, if it grew.
        file.seek(SeekFrom::Start(meta.len()))?;
    }
    file.read_to_end(&mut bytes)?;
    Ok(bytes)
}

/// Files of at least this many bytes are read in parts on all cores: the
/// kernel's copy from its cache into fresh memory runs at about 1.5 GB/s
/// on one core of the project's machine (the 43 MB OBJ of the 1.1
/// M-triangle bunny took 28 ms).
#[cfg_attr(not(unix), allow(dead_code))]
const PARALLEL_READ_BYTES: u64 = 8 << 20;

/// Fills `room` with the file's first bytes, one part per core, each part
/// written by its own thread. An error where the file is shorter than
/// `room` (it shrank since its size was read).
#[cfg(unix)]
fn read_on_threads(
    file: &std::fs::File,
    room: &mut [std::mem::MaybeUninit<u8>],
) -> std::io::Result<()> {
    use std::os::unix::fs::FileExt;
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let part = room.len().div_ceil(cores).max(1);
    let read_part = |(i, part_room): (usize, &mut [std::mem::MaybeUninit<u8>])| {
        part_room.fill(std::mem::MaybeUninit::new(0));
        // SAFETY: every byte of the part was just written.
        let part_bytes =
            unsafe { &mut *(part_room as *mut [std::mem::MaybeUninit<u8>] as *mut [u8]) };
        file.read_exact_at(part_bytes, (i * part) as u64)
    };
    let mut parts = room.chunks_mut(part).enumerate();
    let first = parts.next();
    std::thread::scope(|scope| {
        let others: Vec<_> = parts.map(|p| scope.spawn(move || read_part(p))).collect();
        let first_result = first.map_or(Ok(()), read_part);
        others.into_iter().try_fold(first_result?, |(), handle| {
            handle
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
        })
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file of `len` bytes, each telling its position apart from its
    /// neighbours' (so that a part read to the wrong place shows).
    fn numbered_file(name: &str, len: usize) -> (std::path::PathBuf, Vec<u8>) {
        let bytes: Vec<u8> = (0..len)
            .map(|i| (i % 251) as u8 ^ (i >> 16) as u8)
            .collect();
        let path = std::env::temp_dir().join(format!("kdray-read-{}-{name}", std::process::id()));
        std::fs::write(&path, &bytes).unwrap();
        (path, bytes)
    }

    /// A file past the size read on threads comes back byte for byte, the
    /// last byte included (a size not a multiple of the parts'); so do the
    /// small ones read in one piece, and an empty one.
    #[test]
    fn input_files_are_read_whole_on_threads_or_not() {
        for (name, len) in [
            ("big", PARALLEL_READ_BYTES as usize + 12_345),
            ("small", 1000),
            ("empty", 0),
        ] {
            let (path, want) = numbered_file(name, len);
            let got = read_input_file(&path).unwrap();
            std::fs::remove_file(&path).unwrap();
            assert!(got == want, "{name}: {} bytes read of {len}", got.len());
        }
    }

    /// The parts, whatever their number, cover the room exactly; a file
    /// shorter than the room is an error, not bytes left unwritten.
    #[cfg(unix)]
    #[test]
    fn reading_in_parts_fills_the_room_or_fails() {
        let (path, want) = numbered_file("parts", 10_007);
        let file = std::fs::File::open(&path).unwrap();
        for len in [1, 2, 3, 10_006, 10_007] {
            let mut v: Vec<u8> = Vec::with_capacity(len);
            read_on_threads(&file, &mut v.spare_capacity_mut()[..len]).unwrap();
            // SAFETY: read_on_threads filled the first `len` bytes.
            unsafe { v.set_len(len) };
            assert!(v[..] == want[..len], "{len} bytes");
        }
        let mut v: Vec<u8> = Vec::with_capacity(10_008);
        assert!(read_on_threads(&file, &mut v.spare_capacity_mut()[..10_008]).is_err());
        std::fs::remove_file(&path).unwrap();
    }
}
