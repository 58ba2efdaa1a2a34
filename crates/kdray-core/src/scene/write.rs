//! A [`Scene`] back to scene file text (TOML or JSON), through the same
//! serde schema the reader uses: the tests and benchmarks write generated
//! scenes with it. An `[animation]` is written back key for key.

use std::collections::BTreeMap;

use glam::DVec3;

use super::animation::Animation;
use super::camera::Camera;
use super::environment::EnvironmentMap;
use super::light::Light;
use super::light_kind::LightKind;
use super::light_shape::LightShape;
use super::material::Material;
use super::render_settings::{RenderSettings, ShadowMode};
use super::scene_format::SceneFormat;
use super::schema::{
    Exact, Named, RawAnimation, RawCamera, RawCameraKey, RawEnvironment, RawLight, RawLightKey,
    RawMaterial, RawRender, RawScene, RawShadowMode, RawSphere, RawTriangle, TableOf, Vec3,
};
use super::validated_scene::Scene;

/// `scene` as the text of a scene file that [`parse_scene`](super::parse_scene) reads back as an
/// equal `Scene`, provided its material names are distinct and sort in index
/// order (materials are a table keyed by name, read back in name order), and
/// its triangles are flat: `[[triangles]]` entries carry no normals, and the
/// mesh files a scene was loaded from are not named (their triangles are
/// written out). Written through the same serde types the reader uses.
pub fn scene_text(scene: &Scene, format: SceneFormat) -> Result<String, String> {
    if !scene.instances.is_empty() || !scene.shapes.is_empty() {
        // Instances are written as the triangles they place.
        return scene_text(&scene.clone().flattened(), format);
    }
    let materials = raw_materials(&scene.materials)?;
    let name = |i: u32| {
        scene
            .materials
            .get(i as usize)
            .map(|m| m.name.clone())
            .ok_or_else(|| format!("material index {i} is out of range"))
    };
    let raw = RawScene {
        camera: TableOf(raw_camera(&scene.camera)),
        render: TableOf(raw_render(&scene.render)),
        lights: scene.lights.iter().map(|l| TableOf(raw_light(l))).collect(),
        materials,
        environment: scene
            .environment
            .as_ref()
            .map(|e| TableOf(raw_environment(e))),
        spheres: scene
            .spheres
            .iter()
            .map(|s| {
                Ok(TableOf(RawSphere {
                    center: exact(s.center),
                    radius: s.radius,
                    material: name(s.material)?,
                }))
            })
            .collect::<Result<_, String>>()?,
        triangles: scene
            .triangles
            .iter()
            .map(|t| {
                Ok(TableOf(RawTriangle {
                    vertices: Exact(t.vertices.map(exact)),
                    material: name(t.material)?,
                }))
            })
            .collect::<Result<_, String>>()?,
        meshes: Vec::new(),
        shapes: Default::default(),
        instances: Vec::new(),
        animation: scene.animation.as_ref().map(|a| TableOf(raw_animation(a))),
    };
    encode(&raw, format)
}

/// A vector written with every bit of its components.
fn exact(d: DVec3) -> Vec3 {
    Exact(d.to_array())
}

/// The `[materials]` table, keyed by name; two materials of one name are
/// an error (the table could not hold both).
fn raw_materials(materials: &[Material]) -> Result<BTreeMap<String, TableOf<RawMaterial>>, String> {
    let mut table = BTreeMap::new();
    for m in materials {
        let raw = RawMaterial {
            ambient: exact(m.ambient),
            diffuse: m.physical.metal_rough.is_none().then(|| exact(m.diffuse)),
            base_color: m.physical.metal_rough.map(|_| exact(m.diffuse)),
            metallic: m.physical.metal_rough.map(|p| p.metallic),
            roughness: m.physical.metal_rough.map(|p| p.roughness),
            emission: (m.physical.emission != DVec3::ZERO).then(|| exact(m.physical.emission)),
            specular: exact(m.specular),
            shininess: m.shininess,
            reflection: m.reflection,
            transmission: m.transmission,
            ior: m.ior,
            attenuation_color: m.physical.volume.map(|v| exact(v.attenuation_color)),
            attenuation_distance: m
                .physical
                .volume
                .map(|v| v.attenuation_distance)
                .filter(|d| d.is_finite()),
            transmission_roughness: m.physical.transmission_roughness,
            thin_walled: m.physical.thin_walled,
        };
        if table.insert(m.name.clone(), TableOf(raw)).is_some() {
            return Err(format!("two materials are named \"{}\"", m.name));
        }
    }
    Ok(table)
}

fn raw_camera(camera: &Camera) -> RawCamera {
    RawCamera {
        position: exact(camera.position),
        look_at: exact(camera.look_at),
        up: Some(exact(camera.up)),
        vfov: camera.vfov_degrees,
    }
}

/// `[render]` with every key written, defaults included.
fn raw_render(r: &RenderSettings) -> RawRender {
    RawRender {
        width: Some(r.width),
        height: Some(r.height),
        min_intensity: Some(r.min_intensity),
        max_depth: Some(r.max_depth),
        background: Some(exact(r.background)),
        shadow_mode: Some(match r.shadow_mode {
            ShadowMode::Ambient => RawShadowMode::Ambient,
            ShadowMode::Seed => RawShadowMode::Seed,
        }),
        samples: Some(r.samples),
        integrator: Some(Named(r.integrator)),
        seed: Some(r.seed),
        tone_map: Some(Named(r.tone_map)),
        exposure: Some(r.exposure),
        denoise: Some(r.denoise),
    }
}

/// A `[[lights]]` entry: `kind` left out for a point light, `position`
/// for a directional one.
fn raw_light(l: &Light) -> RawLight {
    let shape = l.kind.shape();
    let (inner_cone, outer_cone) = match l.kind {
        LightKind::Spot {
            inner_degrees,
            outer_degrees,
            ..
        } => (Some(inner_degrees), Some(outer_degrees)),
        _ => (None, None),
    };
    RawLight {
        kind: (shape != LightShape::Point).then_some(Named(shape)),
        position: (shape != LightShape::Directional).then(|| exact(l.position)),
        direction: l.kind.direction().map(exact),
        inner_cone,
        outer_cone,
        ambient: exact(l.ambient),
        diffuse: exact(l.diffuse),
        specular: exact(l.specular),
        reference_distance: l.reference_distance,
    }
}

/// `[environment]`: the image's path as the scene file gave it.
fn raw_environment(e: &EnvironmentMap) -> RawEnvironment {
    RawEnvironment {
        color: None,
        image: Some(e.path.clone()),
        intensity: Some(e.intensity),
        rotation: Some(e.rotation_degrees),
    }
}

/// `[animation]`, its camera and light keys in order.
fn raw_animation(a: &Animation) -> RawAnimation {
    RawAnimation {
        frames: a.frames,
        fps: a.fps,
        orbit: a.orbit_degrees,
        keys: a
            .keys
            .iter()
            .map(|k| {
                TableOf(RawCameraKey {
                    frame: k.frame,
                    position: k.position.map(exact),
                    look_at: k.look_at.map(exact),
                    up: k.up.map(exact),
                    vfov: k.vfov_degrees,
                })
            })
            .collect(),
        light_keys: a
            .light_keys
            .iter()
            .map(|k| {
                TableOf(RawLightKey {
                    frame: k.frame,
                    light: k.light,
                    position: k.position.map(exact),
                    color: k.color.map(exact),
                })
            })
            .collect(),
    }
}

/// `raw` as TOML, or as JSON ending in a newline.
fn encode(raw: &RawScene, format: SceneFormat) -> Result<String, String> {
    match format {
        SceneFormat::Toml => toml::to_string(raw).map_err(|e| e.to_string()),
        SceneFormat::Json => serde_json::to_string(raw)
            .map(|mut text| {
                text.push('\n');
                text
            })
            .map_err(|e| e.to_string()),
    }
}
