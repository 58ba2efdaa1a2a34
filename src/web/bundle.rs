//! The bundle: one little-endian binary file with everything the page needs
//! of a prepared scene (docs/web.md has the format).
//!
//! ```text
//! offset  size     field
//! 0       8        magic, the bytes "KDRAYWEB"
//! 8       4        format version (u32), FORMAT_VERSION
//! 12      4        section count N (u32)
//! 16      32 * N   section table: name (16 bytes, ASCII, NUL-padded),
//!                  offset (u64, from the file's start), size (u64, bytes)
//! ...              the sections, each at a multiple of 16 bytes
//! ```
//!
//! Sections: `scene` (UTF-8 JSON: camera, render settings, counts, the
//! bindings the scene needs and the kernel overrides that follow from the
//! scene, as the native host sets them), `frame_params` (the kernel's
//! `FrameParams` for the scene's own view), then every scene array by its
//! binding name (`spheres`, `triangles`, `objects`, ... in the order of
//! `gpu::bindings::scene`), each in the GPU layout, and for an animated
//! scene `cameras` (every frame's camera, computed here from
//! `Scene::frame_path`, so the page interpolates nothing) and, where some
//! light has keys, `frame_lights` (every frame's `lights` array in the GPU
//! layout, which the page writes into its lights buffer on a frame change).
//! A reader refuses a file with another magic, a newer version, or a
//! section past its end; it skips sections it does not know, so `cameras`
//! and `frame_lights` are optional and need no new version (the page and
//! its bundle are written together by `kdray web`).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::gpu::bindings::OPTIONAL_BINDINGS;
use crate::gpu::kernel_variant::{Walk, SCENE_OVERRIDES};
use crate::gpu::{Accel, ArrayBindings, KernelVariant, PreparedScene};
use crate::gpu::{FrameParams, PresentParams};
use crate::kdtree::Traversal;
use crate::scene::Integrator;

/// The first 8 bytes of every bundle.
pub const MAGIC: &[u8; 8] = b"KDRAYWEB";
/// The bundle format this kdray writes (and the newest the page reads).
pub const FORMAT_VERSION: u32 = 1;
/// Bytes of the header before the section table.
pub const HEADER_BYTES: usize = 16;
/// Bytes of one entry of the section table.
pub const SECTION_ENTRY_BYTES: usize = 32;
/// Bytes of a section's name in the table.
pub const SECTION_NAME_BYTES: usize = 16;
/// Sections start at multiples of this.
pub const SECTION_ALIGN: usize = 16;
/// Bytes before the first frame in the `cameras` section: frame count
/// (u32), a zero word, frames per second (f64).
pub const CAMERAS_HEADER_BYTES: usize = 16;
/// f64 values per frame in the `cameras` section: position (3), look_at
/// (3), up (3), vfov in degrees (1).
pub const CAMERA_VALUES: usize = 10;

/// The section of every frame's lights: `frames` runs of the scene's
/// `lights` array (`layout::GpuLight`, `lights` entries each), frame 0 first.
pub const FRAME_LIGHTS_SECTION: &str = "frame_lights";

/// What the page reads of the scene besides its arrays (the `scene` section).
#[derive(Debug, Serialize)]
pub struct SceneInfo {
    /// The scene file's name, shown in the overlay.
    pub name: String,
    pub camera: CameraInfo,
    pub width: u32,
    pub height: u32,
    /// Samples per pixel: a perfect square for the Whitted integrator, any
    /// count path traced.
    pub samples: u32,
    /// The scene's integrator, `whitted` or `path` (the page's `integrator`
    /// URL parameter and the I key change it).
    pub integrator: &'static str,
    /// How the present pass shows path radiance: `PRESENT_ACES` or
    /// `PRESENT_CLAMP_SRGB` (`[render] tone_map`), and 2^exposure.
    pub path_tone_map: u32,
    pub exposure_scale: f32,
    pub max_depth: u32,
    /// The tree's root cell, `[min, max]`: where the page frames the view.
    pub bounds: [[f32; 3]; 2],
    pub spheres: u32,
    pub triangles: u32,
    pub smooth_triangles: u32,
    /// Point lights: the first entries of the lights buffer, the ones a
    /// `frame_lights` frame replaces; the emitters follow them.
    pub lights: u32,
    pub emitters: u32,
    pub kd_nodes: u32,
    pub leaf_references: u32,
    /// The storage buffers the scene's kernel reads whatever the walk:
    /// `gpu::bindings::Need` names (spheres, triangles, smooth_triangles,
    /// textures), those its variant reads.
    pub needs: Vec<&'static str>,
    /// The walk `frame_params` holds (`render`'s default).
    pub traversal: &'static str,
    /// How the k-d tree was built (`sah`, ...).
    pub build: &'static str,
    /// The kernel's overrides that follow from the scene
    /// (`kernel_variant::SCENE_OVERRIDES`), by name, as the native host sets
    /// them (`KernelVariant::for_arrays`, the arrays in one binding each).
    pub overrides: BTreeMap<&'static str, f64>,
}

/// The scene's camera as written (the page orbits around `look_at`).
#[derive(Debug, Serialize)]
pub struct CameraInfo {
    pub position: [f64; 3],
    pub look_at: [f64; 3],
    pub up: [f64; 3],
    pub vfov_degrees: f64,
}

/// The bundle of `prepared` (a scene prepared for the k-d walk), its frame
/// parameters those of `render` with the default walk.
pub fn encode(prepared: &PreparedScene, name: &str) -> Vec<u8> {
    let scene = &prepared.scene;
    let arrays = &prepared.arrays;
    let params =
        FrameParams::for_arrays(&scene.camera.basis(), &scene.render, arrays, Accel::Kdtree)
            .with_traversal(Traversal::default());
    let spheres = arrays.spheres.len() as u32;
    let triangles = arrays.triangles.len() as u32;
    // The page binds every array whole.
    let variant = KernelVariant::for_arrays(arrays, false);
    let c = &scene.camera;
    let info = SceneInfo {
        name: name.to_string(),
        camera: CameraInfo {
            position: c.position.to_array(),
            look_at: c.look_at.to_array(),
            up: c.up.to_array(),
            vfov_degrees: c.vfov_degrees,
        },
        width: scene.render.width,
        height: scene.render.height,
        samples: scene.render.samples,
        integrator: crate::choice::Choice::name(scene.render.integrator),
        path_tone_map: PresentParams::tone_of(Integrator::Path, &scene.render).0,
        exposure_scale: PresentParams::tone_of(Integrator::Path, &scene.render).1,
        max_depth: scene.render.max_depth,
        bounds: [arrays.bounds.min.to_array(), arrays.bounds.max.to_array()],
        spheres,
        triangles,
        smooth_triangles: arrays.triangle_normals.len() as u32,
        lights: arrays.point_light_count(),
        emitters: arrays.emitter_count,
        kd_nodes: arrays.nodes.len() as u32,
        leaf_references: arrays.leaf_objects.len() as u32,
        needs: scene_needs(variant),
        traversal: crate::choice::Choice::name(Traversal::default()),
        build: prepared.strategy.name(),
        overrides: scene_overrides(variant),
    };
    let info = serde_json::to_vec(&info).expect("the scene's figures serialise");
    let mut sections: Vec<(&str, &[u8])> = vec![
        ("scene", &info),
        ("frame_params", bytemuck::bytes_of(&params)),
    ];
    sections.extend(arrays.whole_buffers());
    let cameras = scene
        .animation
        .as_ref()
        .map(|a| cameras_section(scene, a.fps));
    if let Some(cameras) = &cameras {
        sections.push(("cameras", cameras));
    }
    let frame_lights = frame_lights_section(scene, arrays);
    if let Some(frame_lights) = &frame_lights {
        sections.push((FRAME_LIGHTS_SECTION, frame_lights));
    }
    write_sections(&sections)
}

/// The needs of the optional bindings that `variant`'s scene reads with
/// any walk, counting costs or not.
fn scene_needs(variant: KernelVariant) -> Vec<&'static str> {
    let least = KernelVariant {
        walk: Walk::Brute,
        count_costs: false,
        ..variant
    };
    let mut needs = Vec::new();
    for (_, need) in OPTIONAL_BINDINGS {
        if least.reads(need) && !needs.contains(&need.name()) {
            needs.push(need.name());
        }
    }
    needs
}

/// `variant`'s constants of [`SCENE_OVERRIDES`].
fn scene_overrides(variant: KernelVariant) -> BTreeMap<&'static str, f64> {
    variant
        .constants()
        .into_iter()
        .filter(|(name, _)| SCENE_OVERRIDES.contains(name))
        .collect()
}

/// The `cameras` section: the frame count, `fps`, then each frame's camera
/// as `CAMERA_VALUES` f64 (little-endian), frame 0 first.
pub fn cameras_section(scene: &crate::scene::Scene, fps: f64) -> Vec<u8> {
    let frames = scene.frame_count();
    let path = scene.frame_path();
    let mut out = Vec::with_capacity(CAMERAS_HEADER_BYTES + frames as usize * CAMERA_VALUES * 8);
    out.extend_from_slice(&frames.to_le_bytes());
    out.extend_from_slice(&0u32.to_le_bytes());
    out.extend_from_slice(&fps.to_le_bytes());
    for frame in 0..frames {
        let c = path.camera_at(frame);
        let values = [c.position.to_array(), c.look_at.to_array(), c.up.to_array()];
        for v in values.iter().flatten().chain([&c.vfov_degrees]) {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out
}

/// The `frame_lights` section ([`FRAME_LIGHTS_SECTION`]) of `scene`, whose
/// arrays are `arrays`, or None when no light has keys (every frame's
/// lights are the `lights` array). Each frame's lights carry their picks,
/// rebuilt for that frame.
pub fn frame_lights_section(
    scene: &crate::scene::Scene,
    arrays: &crate::gpu::SceneArrays,
) -> Option<Vec<u8>> {
    let path = scene.frame_path();
    if !path.lights_move() {
        return None;
    }
    let mut out = Vec::new();
    for frame in 0..scene.frame_count() {
        let lights = arrays.frame_lights(&path.lights_at(frame));
        out.extend_from_slice(bytemuck::cast_slice(&lights));
    }
    Some(out)
}

/// The header, the table and `sections`, each aligned.
pub fn write_sections(sections: &[(&str, &[u8])]) -> Vec<u8> {
    let table_end = HEADER_BYTES + SECTION_ENTRY_BYTES * sections.len();
    let mut out = Vec::with_capacity(table_end);
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(sections.len() as u32).to_le_bytes());
    let mut offset = table_end.next_multiple_of(SECTION_ALIGN);
    let mut placed = Vec::new();
    for (name, bytes) in sections {
        assert!(
            name.len() <= SECTION_NAME_BYTES && name.is_ascii(),
            "{name}"
        );
        let mut field = [0u8; SECTION_NAME_BYTES];
        field[..name.len()].copy_from_slice(name.as_bytes());
        out.extend_from_slice(&field);
        out.extend_from_slice(&(offset as u64).to_le_bytes());
        out.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
        placed.push(offset);
        offset = (offset + bytes.len()).next_multiple_of(SECTION_ALIGN);
    }
    for ((_, bytes), at) in sections.iter().zip(placed) {
        out.resize(at, 0);
        out.extend_from_slice(bytes);
    }
    out
}

/// A bundle's sections by name, checked as the page checks them: the
/// magic, a version this kdray reads, and every section inside the file.
pub fn read_sections(bytes: &[u8]) -> Result<Vec<(String, &[u8])>, String> {
    if bytes.len() < HEADER_BYTES || &bytes[..8] != MAGIC {
        return Err("not a kdray bundle (bad magic)".into());
    }
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    let u64_at = |at: usize| u64::from_le_bytes(bytes[at..at + 8].try_into().unwrap());
    let version = u32_at(8);
    if version > FORMAT_VERSION {
        return Err(format!(
            "bundle format version {version} is newer than this reader's {FORMAT_VERSION}"
        ));
    }
    let count = u32_at(12) as usize;
    if HEADER_BYTES + SECTION_ENTRY_BYTES * count > bytes.len() {
        return Err("truncated bundle: the section table runs past the end".into());
    }
    (0..count)
        .map(|i| {
            let at = HEADER_BYTES + SECTION_ENTRY_BYTES * i;
            let name = &bytes[at..at + SECTION_NAME_BYTES];
            let name: String = name
                .iter()
                .take_while(|&&b| b != 0)
                .map(|&b| b as char)
                .collect();
            let (offset, size) = (u64_at(at + 16), u64_at(at + 24));
            let end = offset
                .checked_add(size)
                .filter(|&e| e <= bytes.len() as u64);
            match end {
                Some(end) => Ok((name, &bytes[offset as usize..end as usize])),
                None => Err(format!(
                    "truncated bundle: section {name} runs past the end"
                )),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sections_read_back_aligned_and_in_order() {
        let bundle = write_sections(&[("a", b"xyz"), ("bb", &[1, 2, 3, 4, 5]), ("empty", b"")]);
        let sections = read_sections(&bundle).unwrap();
        let names: Vec<&str> = sections.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["a", "bb", "empty"]);
        assert_eq!(sections[1].1, &[1, 2, 3, 4, 5]);
        for (_, bytes) in &sections {
            let offset = bytes.as_ptr() as usize - bundle.as_ptr() as usize;
            assert_eq!(offset % SECTION_ALIGN, 0);
        }
    }

    /// An animated scene's bundle holds every frame's camera as
    /// `Scene::camera_at` gives it; a still scene's has no `cameras`.
    #[test]
    fn animated_scenes_carry_every_frame_camera() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let orbit = crate::scene::load_scene(&root.join("scenes/orbit.toml")).unwrap();
        let section = cameras_section(&orbit, 24.0);
        let frames = orbit.frame_count();
        assert!(frames > 1);
        assert_eq!(u32::from_le_bytes(section[..4].try_into().unwrap()), frames);
        assert_eq!(f64::from_le_bytes(section[8..16].try_into().unwrap()), 24.0);
        let value = |frame: usize, k: usize| {
            let at = CAMERAS_HEADER_BYTES + 8 * (CAMERA_VALUES * frame + k);
            f64::from_le_bytes(section[at..at + 8].try_into().unwrap())
        };
        assert_eq!(
            section.len(),
            CAMERAS_HEADER_BYTES + 8 * CAMERA_VALUES * frames as usize
        );
        for frame in [0, 5, frames - 1] {
            let c = orbit.camera_at(frame);
            let f = frame as usize;
            assert_eq!(
                [value(f, 0), value(f, 1), value(f, 2)],
                c.position.to_array()
            );
            assert_eq!(
                [value(f, 3), value(f, 4), value(f, 5)],
                c.look_at.to_array()
            );
            assert_eq!([value(f, 6), value(f, 7), value(f, 8)], c.up.to_array());
            assert_eq!(value(f, 9), c.vfov_degrees);
        }
        assert_ne!(value(5, 0), value(0, 0), "the orbit moves the camera");

        let prepared = PreparedScene::new(orbit, Accel::Kdtree);
        let bundle = encode(&prepared, "orbit.toml");
        let sections = read_sections(&bundle).unwrap();
        assert!(sections
            .iter()
            .any(|(n, b)| n == "cameras" && *b == &section[..]));
        let seed = crate::scene::load_scene(&root.join("scenes/seed.toml")).unwrap();
        let bundle = encode(&PreparedScene::new(seed, Accel::Kdtree), "seed.toml");
        assert!(read_sections(&bundle)
            .unwrap()
            .iter()
            .all(|(n, _)| n != "cameras"));
    }

    /// A scene whose light has keys carries every frame's lights as the
    /// lights buffer holds them, their picks rebuilt for each frame; one
    /// whose lights stay carries none.
    #[test]
    fn moving_lights_carry_every_frame_lights() {
        let text = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n\
            [[lights]]\nposition = [1, 1, 1]\n[[lights]]\nposition = [-1, 1, 1]\n\
            [materials.m]\ndiffuse = [1, 1, 1]\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n\
            [animation]\nframes = 3\n\
            [[animation.light_keys]]\nframe = 2\nlight = 1\nposition = [3, 1, 1]\ncolor = [0.5, 0.5, 0.5]\n";
        let path = std::path::Path::new("lights.toml");
        let scene = crate::scene::parse_scene(text, path, crate::scene::SceneFormat::Toml).unwrap();
        let prepared = PreparedScene::new(scene.clone(), Accel::Kdtree);
        let section = frame_lights_section(&scene, &prepared.arrays).unwrap();
        let per_frame = 2 * std::mem::size_of::<crate::layout::GpuLight>();
        assert_eq!(section.len(), 3 * per_frame);
        for frame in 0..3u32 {
            let want = prepared.arrays.frame_lights(&scene.frame(frame).lights);
            let at = frame as usize * per_frame;
            assert_eq!(
                &section[at..at + per_frame],
                bytemuck::cast_slice::<_, u8>(&want)
            );
        }
        assert_ne!(
            section[..per_frame],
            section[2 * per_frame..],
            "the light moves"
        );
        // Dimmed to half at frame 2, the second light is picked a third of
        // the time instead of half.
        let second: crate::layout::GpuLight =
            bytemuck::pod_read_unaligned(&section[5 * per_frame / 2..]);
        assert!((second.pick - 1.0 / 3.0).abs() < 1e-6, "{}", second.pick);
        let bundle = encode(&prepared, "lights.toml");
        assert!(read_sections(&bundle)
            .unwrap()
            .iter()
            .any(|(n, b)| n == FRAME_LIGHTS_SECTION && *b == &section[..]));
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let orbit = PreparedScene::new(
            crate::scene::load_scene(&root.join("scenes/orbit.toml")).unwrap(),
            Accel::Kdtree,
        );
        assert!(frame_lights_section(&orbit.scene, &orbit.arrays).is_none());
    }

    #[test]
    fn bad_magic_newer_versions_and_truncation_are_refused() {
        let bundle = write_sections(&[("a", &[7; 40])]);
        let mut bad = bundle.clone();
        bad[0] = b'X';
        assert!(read_sections(&bad).unwrap_err().contains("magic"));
        let mut newer = bundle.clone();
        newer[8..12].copy_from_slice(&(FORMAT_VERSION + 1).to_le_bytes());
        assert!(read_sections(&newer).unwrap_err().contains("newer"));
        let cut = &bundle[..bundle.len() - 1];
        assert!(read_sections(cut).unwrap_err().contains("section a"));
        assert!(read_sections(&bundle[..20]).unwrap_err().contains("table"));
    }
}
