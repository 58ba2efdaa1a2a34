//! A model file opened on its own (`kdray render bunny.obj`), as a model
//! viewer would show it: the model as its file places it, seen through the
//! file's camera (a glTF's first) or else framed from a three-quarter view
//! to fit its bounding box, under the file's lights (a glTF's
//! `KHR_lights_punctual`) or else a three-point light rig
//! (key, fill, rim) placed relative to the box, standing on a ground plane
//! (two large triangles) just below its lowest point.
//!
//! Everything is scaled by the model's bounding sphere, so a model in
//! millimetres and one in kilometres look alike. The model keeps its own
//! materials (the default grey where an OBJ face has none) and its own
//! normals where the file gives them, else it is shaded flat.

use std::cell::RefCell;
use std::path::Path;

use glam::DVec3;

use super::camera::Camera;
use super::error::SceneError;
use super::light::Light;
use super::material::Material;
use super::objects::Triangle;
use super::render_settings::{RenderSettings, ShadowMode};
use super::scene_format::SceneFormat;
use super::schema::{RawMesh, RawScale};
use super::source_map::LazySourceMap;
use super::validate::Validator;
use super::validated_scene::Scene;
use super::warning::{print_warning, Warning};

/// Vertical field of view of the model camera, in degrees.
pub const MODEL_VFOV_DEGREES: f64 = 40.0;
/// Default image size of a model scene (the CLI's --width/--height override
/// it; the framing holds for any image at least as wide as it is tall).
pub const MODEL_IMAGE: (u32, u32) = (800, 600);
/// The three-quarter view: the camera sits 35 degrees round from the
/// model's front (+z) towards +x, and 25 degrees above it.
const AZIMUTH_DEGREES: f64 = 35.0;
const ELEVATION_DEGREES: f64 = 25.0;
/// Room left round the bounding sphere: its silhouette fills 1 / 1.1 of
/// the image's height.
const MARGIN: f64 = 1.1;
/// The ground's half-width, in bounding-sphere radii: wide enough to reach
/// past the image's edges from the framing distance.
const GROUND_HALF_WIDTH: f64 = 40.0;
/// The ground lies this many radii below the model's lowest point, so that
/// a flat underside does not coincide with it.
const GROUND_GAP: f64 = 1e-3;
/// A dark blue-grey behind the model.
const BACKGROUND: DVec3 = DVec3::new(0.05, 0.06, 0.09);

/// Which camera a model scene looks through.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ModelCamera {
    /// The file's own (a glTF's first perspective camera) where it has one,
    /// else the three-quarter view.
    #[default]
    File,
    /// The three-quarter view, whatever the file says.
    Default,
}

impl crate::choice::Choice for ModelCamera {
    const ALL: &'static [Self] = &[Self::File, Self::Default];

    fn name(self) -> &'static str {
        match self {
            Self::File => "file",
            Self::Default => "default",
        }
    }

    fn help(self) -> &'static str {
        match self {
            Self::File => "the model file's camera (a glTF's first), else the three-quarter view",
            Self::Default => "the three-quarter view framing the model, whatever the file says",
        }
    }
}

/// The scene of a model file (`.obj`, `.gltf`, `.glb`); warnings are
/// printed on stderr.
pub fn model_scene(path: &Path) -> Result<Scene, SceneError> {
    model_scene_with(path, &mut |_| {}, &mut print_warning)
}

/// [`model_scene`], calling `on_read` with every file it reads and handing
/// each warning to `warn`.
pub fn model_scene_with(
    path: &Path,
    on_read: &mut dyn FnMut(&Path),
    warn: &mut dyn FnMut(Warning),
) -> Result<Scene, SceneError> {
    model_scene_viewed(path, ModelCamera::File, on_read, warn)
}

/// [`model_scene_with`], through the camera `view` picks.
pub fn model_scene_viewed(
    path: &Path,
    view: ModelCamera,
    on_read: &mut dyn FnMut(&Path),
    warn: &mut dyn FnMut(Warning),
) -> Result<Scene, SceneError> {
    // The model is loaded and placed as a scene file's one `[[meshes]]`
    // entry would be, with no transform.
    let file_name = path
        .file_name()
        .map_or_else(|| path.to_string_lossy(), |f| f.to_string_lossy())
        .into_owned();
    let raw = RawMesh {
        path: file_name,
        material: None,
        smooth: None,
        scale: RawScale::default(),
        rotate: Default::default(),
        translate: Default::default(),
    };
    let validator = Validator {
        file: path,
        map: LazySourceMap::empty(SceneFormat::Toml),
        on_read: RefCell::new(on_read),
        warn: RefCell::new(warn),
    };
    let mut materials = Vec::new();
    let mut triangles = Vec::new();
    let mut parts = super::triangle_parts::TriangleParts::default();
    let placed = validator.mesh(0, &raw, None, &mut materials, &mut triangles, &mut parts)?;
    parts.finish();

    let (mut min, mut max) = bounds(&triangles);
    // The copies of a mesh placed several times frame the view too.
    for i in &placed.instances {
        if let Some(shape) = placed.shapes.get(i.shape as usize) {
            let [lo, hi] = super::instances::transformed_box(&i.transform, &shape.bounds);
            (min, max) = (min.min(lo), max.max(hi));
        }
    }
    let (width, height) = MODEL_IMAGE;
    let ground_material = materials.len() as u32;
    materials.push(ground());
    triangles.extend(ground_triangles(min, max, ground_material));
    Ok(Scene {
        camera: match (view, placed.camera) {
            (ModelCamera::File, Some(camera)) => file_camera(path, camera)?,
            _ => framing_camera(min, max),
        },
        render: RenderSettings {
            width,
            height,
            min_intensity: 0.05,
            max_depth: 4,
            background: BACKGROUND,
            shadow_mode: ShadowMode::Ambient,
            samples: 1,
            integrator: Default::default(),
            seed: 0,
            tone_map: Default::default(),
            exposure: 0.0,
            denoise: false,
        },
        lights: if placed.lights.is_empty() {
            light_rig(min, max)
        } else {
            file_lights(path, placed.lights)?
        },
        environment: None,
        animation: None,
        materials,
        spheres: Vec::new(),
        triangles,
        triangle_normals: parts.normals,
        triangle_uvs: parts.uvs,
        triangle_second_uvs: parts.second_uvs,
        triangle_colours: parts.colours,
        triangle_tangents: parts.tangents,
        textures: parts.textures,
        shapes: placed.shapes,
        instances: placed.instances,
    })
}

/// The file's camera, its eye (and the point it looks at) within the
/// coordinates the GPU can take, like a scene file's.
fn file_camera(path: &Path, camera: Camera) -> Result<Camera, SceneError> {
    let within = |p: DVec3| p.abs().max_element() <= super::validate::MAX_COORDINATE;
    if !(within(camera.position) && within(camera.look_at)) {
        return Err(SceneError::new(
            path,
            None,
            None,
            format!(
                "the file's camera sits at {}, beyond ±{:e} (the GPU computes in f32); use --camera default",
                camera.position,
                super::validate::MAX_COORDINATE
            ),
        ));
    }
    Ok(camera)
}

/// The file's lights (a glTF's `KHR_lights_punctual`), in place of the
/// rig, their positions within the coordinates the GPU can take.
fn file_lights(path: &Path, lights: Vec<Light>) -> Result<Vec<Light>, SceneError> {
    let limit = super::validate::MAX_COORDINATE;
    match lights
        .iter()
        .find(|l| l.position.abs().max_element() > limit)
    {
        Some(far) => Err(SceneError::new(
            path,
            None,
            None,
            format!(
                "a light of the file sits at {}, beyond ±{limit:e} (the GPU computes in f32)",
                far.position
            ),
        )),
        None => Ok(lights),
    }
}

/// The box round every triangle's vertices (a loaded model has at least one).
fn bounds(triangles: &[Triangle]) -> (DVec3, DVec3) {
    triangles
        .iter()
        .flat_map(|t| t.vertices)
        .fold((DVec3::MAX, DVec3::MIN), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        })
}

/// The centre and bounding-sphere radius of a box (the radius never zero: a
/// model has a triangle with an area).
fn sphere(min: DVec3, max: DVec3) -> (DVec3, f64) {
    let centre = (min + max) / 2.0;
    let radius = ((max - min).length() / 2.0).max(f64::MIN_POSITIVE);
    (centre, radius)
}

/// The unit direction from the model's centre towards the camera.
fn view_direction() -> DVec3 {
    let (azimuth, elevation) = (AZIMUTH_DEGREES.to_radians(), ELEVATION_DEGREES.to_radians());
    DVec3::new(
        azimuth.sin() * elevation.cos(),
        elevation.sin(),
        azimuth.cos() * elevation.cos(),
    )
}

/// A camera looking at the box's centre from the three-quarter view, far
/// enough that the box's bounding sphere fits the vertical field of view
/// with [`MARGIN`] to spare (so every corner projects inside any image at
/// least as wide as it is tall).
pub(super) fn framing_camera(min: DVec3, max: DVec3) -> Camera {
    let (centre, radius) = sphere(min, max);
    let half_fov = (MODEL_VFOV_DEGREES / 2.0).to_radians();
    let distance = MARGIN * radius / half_fov.sin();
    Camera {
        position: centre + distance * view_direction(),
        look_at: centre,
        up: DVec3::Y,
        vfov_degrees: MODEL_VFOV_DEGREES,
    }
}

/// Key (bright, above and to the camera's right), fill (dim, low on the
/// left) and rim (behind and above, for an outline), at a few radii from the
/// centre. Only the key adds ambient light. Each light's reference distance
/// is its distance to the centre, so that the path tracer, whose lights
/// fall off, lights the model as brightly as the Whitted integrator at any
/// scale.
pub(super) fn light_rig(min: DVec3, max: DVec3) -> Vec<Light> {
    let (centre, radius) = sphere(min, max);
    let toward_camera = view_direction();
    let right = toward_camera.cross(DVec3::Y).normalize() * -1.0;
    let light = |offset: DVec3, ambient: f64, diffuse: f64, specular: f64| Light {
        position: centre + radius * offset,
        ambient: DVec3::splat(ambient),
        diffuse: DVec3::splat(diffuse),
        specular: DVec3::splat(specular),
        kind: Default::default(),
        reference_distance: Some(radius * offset.length()),
    };
    vec![
        light(
            3.0 * toward_camera + 2.0 * right + 4.0 * DVec3::Y,
            0.25,
            0.8,
            0.8,
        ),
        light(
            3.0 * toward_camera - 3.0 * right + 1.0 * DVec3::Y,
            0.0,
            0.3,
            0.0,
        ),
        light(-4.0 * toward_camera + 4.0 * DVec3::Y, 0.0, 0.4, 0.3),
    ]
}

/// The ground's material: a matte blue-grey, told apart from the default
/// grey of a model (and from the background) by its hue.
fn ground() -> Material {
    Material {
        name: "ground".to_string(),
        ambient: DVec3::new(0.30, 0.33, 0.40),
        diffuse: DVec3::new(0.45, 0.50, 0.60),
        specular: DVec3::ZERO,
        shininess: 0.0,
        reflection: 0.0,
        transmission: 0.0,
        texture: None,
        ior: Material::DEFAULT_IOR,
        physical: super::material::Physical::LAMBERTIAN,
        maps: super::material::MaterialMaps::NONE,
        alpha: super::alpha::Alpha::OPAQUE,
    }
}

/// A square of two triangles at y just below `min.y`, centred under the box.
pub(super) fn ground_triangles(min: DVec3, max: DVec3, material: u32) -> [Triangle; 2] {
    let (centre, radius) = sphere(min, max);
    let y = min.y - GROUND_GAP * radius;
    let h = GROUND_HALF_WIDTH * radius;
    let corner = |dx: f64, dz: f64| DVec3::new(centre.x + dx, y, centre.z + dz);
    let (a, b, c, d) = (corner(-h, -h), corner(h, -h), corner(h, h), corner(-h, h));
    [
        Triangle::flat([a, c, b], material),
        Triangle::flat([a, d, c], material),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where `p` lands in a `width` x `height` image seen by `camera` (through
    /// the frame the renderer uses), in pixels from the top left; None
    /// behind the camera.
    fn project(camera: &Camera, width: u32, height: u32, p: DVec3) -> Option<(f64, f64)> {
        let basis = camera.basis();
        let (forward, right, up) = (basis.forward, basis.right, basis.up);
        let d = p - camera.position;
        let depth = d.dot(forward);
        if depth <= 0.0 {
            return None;
        }
        let half_height = basis.tan_half_vfov;
        let half_width = half_height * f64::from(width) / f64::from(height);
        let x = d.dot(right) / depth / half_width;
        let y = d.dot(up) / depth / half_height;
        Some((
            (x + 1.0) / 2.0 * f64::from(width),
            (1.0 - y) / 2.0 * f64::from(height),
        ))
    }

    fn corners(min: DVec3, max: DVec3) -> Vec<DVec3> {
        (0..8)
            .map(|i| {
                DVec3::new(
                    if i & 1 == 0 { min.x } else { max.x },
                    if i & 2 == 0 { min.y } else { max.y },
                    if i & 4 == 0 { min.z } else { max.z },
                )
            })
            .collect()
    }

    #[test]
    fn every_corner_of_the_box_projects_inside_the_image() {
        let boxes = [
            (DVec3::splat(-1.0), DVec3::splat(1.0)),
            // The bunny's bounds, a flat slab, a tall pole, far from the origin.
            (
                DVec3::new(-1.0, -0.991, -0.775),
                DVec3::new(1.0, 1.0, 0.775),
            ),
            (DVec3::new(0.0, 0.0, 0.0), DVec3::new(100.0, 0.01, 50.0)),
            (
                DVec3::new(5e3, -2.0, 7e3),
                DVec3::new(5e3 + 0.1, 40.0, 7e3 + 0.1),
            ),
        ];
        for (min, max) in boxes {
            let camera = framing_camera(min, max);
            for (width, height) in [MODEL_IMAGE, (64, 36), (100, 100)] {
                for corner in corners(min, max) {
                    let (x, y) = project(&camera, width, height, corner)
                        .unwrap_or_else(|| panic!("{corner} is behind the camera"));
                    assert!(
                        (0.0..=f64::from(width)).contains(&x)
                            && (0.0..=f64::from(height)).contains(&y),
                        "box {min}..{max}: corner {corner} lands at ({x}, {y}) in {width}x{height}"
                    );
                }
            }
            // The centre lands in the middle, and the box is not a speck.
            let (cx, cy) = project(&camera, 800, 600, (min + max) / 2.0).unwrap();
            assert!((cx - 400.0).abs() < 1e-6 && (cy - 300.0).abs() < 1e-6);
            let xs: Vec<f64> = corners(min, max)
                .into_iter()
                .map(|c| project(&camera, 800, 600, c).unwrap().1)
                .collect();
            let span = xs.iter().cloned().fold(f64::MIN, f64::max)
                - xs.iter().cloned().fold(f64::MAX, f64::min);
            assert!(span > 0.3 * 600.0, "box {min}..{max} spans {span} pixels");
        }
    }

    #[test]
    fn the_ground_lies_just_below_the_model_and_under_its_centre() {
        let (min, max) = (DVec3::new(-1.0, 2.0, -1.0), DVec3::new(1.0, 4.0, 3.0));
        let ground = ground_triangles(min, max, 7);
        let (centre, radius) = sphere(min, max);
        for t in &ground {
            assert_eq!(t.material, 7);
            for v in t.vertices {
                assert!(v.y < min.y && v.y > min.y - 0.01 * radius);
                assert!((v.x - centre.x).abs() > 10.0 * radius);
                assert!((v.z - centre.z).abs() > 10.0 * radius);
            }
            let normal = (t.vertices[1] - t.vertices[0]).cross(t.vertices[2] - t.vertices[0]);
            assert!(normal.length() > 0.0 && normal.x == 0.0 && normal.z == 0.0);
        }
    }

    #[test]
    fn the_lights_surround_the_model_above_the_ground() {
        let (min, max) = (DVec3::new(-1.0, 0.0, -1.0), DVec3::new(1.0, 2.0, 1.0));
        let (centre, radius) = sphere(min, max);
        let lights = light_rig(min, max);
        assert_eq!(lights.len(), 3);
        for light in &lights {
            assert!(light.position.y > max.y);
            assert!((light.position - centre).length() > 2.0 * radius);
        }
        // The key is in front (the camera's side), the rim behind.
        let toward_camera = view_direction();
        assert!((lights[0].position - centre).dot(toward_camera) > 0.0);
        assert!((lights[2].position - centre).dot(toward_camera) < 0.0);
    }
}
