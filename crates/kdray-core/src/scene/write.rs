//! A [`Scene`] back to scene file text (TOML or JSON), through the same
//! serde schema the reader uses: the tests and benchmarks write generated
//! scenes with it. An `[animation]` is written back key for key.

use std::collections::BTreeMap;

use glam::DVec3;

use super::scene_format::SceneFormat;
use super::schema::{
    Exact, Named, RawAnimation, RawCamera, RawCameraKey, RawEnvironment, RawLight, RawLightKey,
    RawMaterial, RawRender, RawScene, RawShadowMode, RawSphere, RawTriangle, TableOf,
};
use super::{LightKind, LightShape, Scene, ShadowMode};

/// `scene` as the text of a scene file that [`parse_scene`](super::parse_scene) reads back as an
/// equal `Scene`, provided its material names are distinct and sort in index
/// order (materials are a table keyed by name, read back in name order), and
/// its triangles are flat: `[[triangles]]` entries carry no normals, and the
/// mesh files a scene was loaded from are not named (their triangles are
/// written out). Written through the same serde types the reader uses.
pub fn scene_text(scene: &Scene, format: SceneFormat) -> Result<String, String> {
    let v = |d: DVec3| Exact(d.to_array());
    let mut materials = BTreeMap::new();
    for m in &scene.materials {
        let raw = RawMaterial {
            ambient: v(m.ambient),
            diffuse: m.physical.metal_rough.is_none().then(|| v(m.diffuse)),
            base_color: m.physical.metal_rough.map(|_| v(m.diffuse)),
            metallic: m.physical.metal_rough.map(|p| p.metallic),
            roughness: m.physical.metal_rough.map(|p| p.roughness),
            emission: (m.physical.emission != DVec3::ZERO).then(|| v(m.physical.emission)),
            specular: v(m.specular),
            shininess: m.shininess,
            reflection: m.reflection,
            transmission: m.transmission,
            ior: m.ior,
        };
        if materials.insert(m.name.clone(), TableOf(raw)).is_some() {
            return Err(format!("two materials are named \"{}\"", m.name));
        }
    }
    let name = |i: u32| {
        scene
            .materials
            .get(i as usize)
            .map(|m| m.name.clone())
            .ok_or_else(|| format!("material index {i} is out of range"))
    };
    let r = &scene.render;
    let raw = RawScene {
        camera: TableOf(RawCamera {
            position: v(scene.camera.position),
            look_at: v(scene.camera.look_at),
            up: Some(v(scene.camera.up)),
            vfov: scene.camera.vfov_degrees,
        }),
        render: TableOf(RawRender {
            width: Some(r.width),
            height: Some(r.height),
            min_intensity: Some(r.min_intensity),
            max_depth: Some(r.max_depth),
            background: Some(v(r.background)),
            shadow_mode: Some(match r.shadow_mode {
                ShadowMode::Ambient => RawShadowMode::Ambient,
                ShadowMode::Seed => RawShadowMode::Seed,
            }),
            samples: Some(r.samples),
            integrator: Some(Named(r.integrator)),
            seed: Some(r.seed),
            tone_map: Some(Named(r.tone_map)),
            exposure: Some(r.exposure),
        }),
        lights: scene
            .lights
            .iter()
            .map(|l| {
                let shape = l.kind.shape();
                let (inner_cone, outer_cone) = match l.kind {
                    LightKind::Spot {
                        inner_degrees,
                        outer_degrees,
                        ..
                    } => (Some(inner_degrees), Some(outer_degrees)),
                    _ => (None, None),
                };
                TableOf(RawLight {
                    kind: (shape != LightShape::Point).then_some(Named(shape)),
                    position: (shape != LightShape::Directional).then(|| v(l.position)),
                    direction: l.kind.direction().map(v),
                    inner_cone,
                    outer_cone,
                    ambient: v(l.ambient),
                    diffuse: v(l.diffuse),
                    specular: v(l.specular),
                })
            })
            .collect(),
        materials,
        environment: scene.environment.as_ref().map(|e| {
            TableOf(RawEnvironment {
                color: None,
                image: Some(e.path.clone()),
                intensity: Some(e.intensity),
                rotation: Some(e.rotation_degrees),
            })
        }),
        spheres: scene
            .spheres
            .iter()
            .map(|s| {
                Ok(TableOf(RawSphere {
                    center: v(s.center),
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
                    vertices: Exact(t.vertices.map(v)),
                    material: name(t.material)?,
                }))
            })
            .collect::<Result<_, String>>()?,
        meshes: Vec::new(),
        animation: scene.animation.as_ref().map(|a| {
            TableOf(RawAnimation {
                frames: a.frames,
                fps: a.fps,
                orbit: a.orbit_degrees,
                keys: a
                    .keys
                    .iter()
                    .map(|k| {
                        TableOf(RawCameraKey {
                            frame: k.frame,
                            position: k.position.map(v),
                            look_at: k.look_at.map(v),
                            up: k.up.map(v),
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
                            position: k.position.map(v),
                            color: k.color.map(v),
                        })
                    })
                    .collect(),
            })
        }),
    };
    match format {
        SceneFormat::Toml => toml::to_string(&raw).map_err(|e| e.to_string()),
        SceneFormat::Json => serde_json::to_string(&raw)
            .map(|mut text| {
                text.push('\n');
                text
            })
            .map_err(|e| e.to_string()),
    }
}
