//! The scene flattened into GPU arrays (host side) and uploaded as storage
//! buffers. Bindings as declared in shaders/types.wgsl.

use super::GpuContext;
use crate::geometry::Primitives;
use crate::kdtree::KdTree;
use crate::layout::{GpuLight, GpuMaterial, GpuSphere, GpuTriangle, KdNode};
use crate::scene::Scene;

/// Host copies of every storage buffer, in the GPU layout.
pub struct SceneArrays {
    pub spheres: Vec<GpuSphere>,
    pub triangles: Vec<GpuTriangle>,
    pub object_materials: Vec<u32>,
    pub materials: Vec<GpuMaterial>,
    pub lights: Vec<GpuLight>,
    pub nodes: Vec<KdNode>,
    pub leaf_objects: Vec<u32>,
}

fn f32x3(v: glam::DVec3) -> [f32; 3] {
    v.as_vec3().to_array()
}

impl SceneArrays {
    pub fn new(scene: &Scene, prims: &Primitives, tree: &KdTree) -> Self {
        SceneArrays {
            spheres: prims
                .spheres
                .iter()
                .map(|s| GpuSphere {
                    center: s.center.to_array(),
                    radius: s.radius,
                })
                .collect(),
            triangles: prims
                .triangles
                .iter()
                .map(|t| GpuTriangle {
                    v0: t.v[0].to_array(),
                    v1: t.v[1].to_array(),
                    v2: t.v[2].to_array(),
                    ..bytemuck::Zeroable::zeroed()
                })
                .collect(),
            object_materials: scene
                .spheres
                .iter()
                .map(|s| s.material)
                .chain(scene.triangles.iter().map(|t| t.material))
                .collect(),
            materials: scene
                .materials
                .iter()
                .map(|m| GpuMaterial {
                    ambient: f32x3(m.ambient),
                    shininess: m.shininess as f32,
                    diffuse: f32x3(m.diffuse),
                    reflection: m.reflection as f32,
                    specular: f32x3(m.specular),
                    _pad: 0.0,
                })
                .collect(),
            lights: scene
                .lights
                .iter()
                .map(|l| GpuLight {
                    position: f32x3(l.position),
                    ambient: f32x3(l.ambient),
                    diffuse: f32x3(l.diffuse),
                    specular: f32x3(l.specular),
                    ..bytemuck::Zeroable::zeroed()
                })
                .collect(),
            nodes: tree.nodes.clone(),
            leaf_objects: tree.leaf_objects.clone(),
        }
    }

    /// (binding name, bytes) of every storage buffer, in binding order 1..=7.
    fn buffers(&self) -> [(&'static str, &[u8]); 7] {
        [
            ("spheres", bytemuck::cast_slice(&self.spheres)),
            ("triangles", bytemuck::cast_slice(&self.triangles)),
            (
                "object_materials",
                bytemuck::cast_slice(&self.object_materials),
            ),
            ("materials", bytemuck::cast_slice(&self.materials)),
            ("lights", bytemuck::cast_slice(&self.lights)),
            ("kd_nodes", bytemuck::cast_slice(&self.nodes)),
            ("leaf_objects", bytemuck::cast_slice(&self.leaf_objects)),
        ]
    }

    /// Total bytes the scene needs on the GPU (storage buffers only).
    pub fn byte_size(&self) -> u64 {
        self.buffers().iter().map(|(_, b)| b.len() as u64).sum()
    }

    /// The largest single buffer: (name, bytes).
    pub fn largest_buffer(&self) -> (&'static str, u64) {
        self.buffers()
            .iter()
            .map(|(n, b)| (*n, b.len() as u64))
            .max_by_key(|(_, s)| *s)
            .unwrap_or(("", 0))
    }

    /// Refuses, before anything is uploaded, a scene one of whose buffers
    /// exceeds what the adapter can bind (`max_storage_buffer_binding_size`,
    /// `max_buffer_size`): the message names the buffer, its size and the limit.
    pub fn check_fits(&self, limits: &wgpu::Limits) -> crate::Result<()> {
        let limit = super::max_binding_bytes(limits);
        for (name, bytes) in self.buffers() {
            if bytes.len() as u64 > limit {
                return Err(crate::Error::Gpu(format!(
                    "the scene is too large for this adapter: its {name} buffer needs {} but the adapter binds at most {} \
                     per storage buffer ({} spheres, {} triangles, {} k-d nodes, {} leaf references)",
                    human_bytes(bytes.len() as u64),
                    human_bytes(limit),
                    self.spheres.len(),
                    self.triangles.len(),
                    self.nodes.len(),
                    self.leaf_objects.len()
                )));
            }
        }
        Ok(())
    }
}

/// Bytes for people: B, KiB or MiB.
pub(crate) fn human_bytes(bytes: u64) -> String {
    match bytes {
        b if b < 1024 => format!("{b} B"),
        b if b < 1024 * 1024 => format!("{:.1} KiB", b as f64 / 1024.0),
        b => format!("{:.1} MiB", b as f64 / (1024.0 * 1024.0)),
    }
}

/// The scene's storage buffers on the device (bindings 1..=7).
pub struct SceneBuffers {
    pub(crate) buffers: Vec<wgpu::Buffer>,
    pub sphere_count: u32,
    pub object_count: u32,
    pub light_count: u32,
    pub node_count: u32,
}

impl SceneBuffers {
    /// Uploads `arrays` to the device. A scene with a buffer beyond the
    /// adapter's binding limits is refused before anything is allocated; one
    /// the device has no memory for fails with the size it needed. Either
    /// way the error is one line.
    pub fn upload(ctx: &GpuContext, arrays: &SceneArrays) -> crate::Result<Self> {
        arrays.check_fits(&ctx.device.limits())?;
        let what = format!(
            "uploading the scene ({} of GPU memory)",
            human_bytes(arrays.byte_size())
        );
        ctx.checked(&what, |device| Self::create(device, arrays))
    }

    /// Creates the buffers; errors go to the caller's error scopes.
    fn create(device: &wgpu::Device, arrays: &SceneArrays) -> Self {
        let buffers = arrays
            .buffers()
            .iter()
            .map(|(name, bytes)| {
                // Bindings may not be empty: an empty array gets one zeroed
                // element (64 bytes covers the largest element type).
                let padded = [0u8; 64];
                let contents = if bytes.is_empty() { &padded[..] } else { bytes };
                // Not create_buffer_init: it panics when the device is lost.
                // A failed mapping leaves an invalid buffer, which the caller's
                // error scope reports as one error line.
                let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                    label: Some(name),
                    size: contents.len() as u64,
                    usage: wgpu::BufferUsages::STORAGE,
                    mapped_at_creation: true,
                });
                if let Ok(mut view) = buffer.slice(..).get_mapped_range_mut() {
                    view.copy_from_slice(contents);
                }
                buffer.unmap();
                buffer
            })
            .collect();
        SceneBuffers {
            buffers,
            sphere_count: arrays.spheres.len() as u32,
            object_count: arrays.object_materials.len() as u32,
            light_count: arrays.lights.len() as u32,
            node_count: arrays.nodes.len() as u32,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Primitives;
    use crate::scene::{parse_scene, SceneFormat};

    fn arrays(spheres: usize) -> SceneArrays {
        let mut text = String::from(
            "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [1, 1, 1]\n[materials.m]\ndiffuse = [1, 1, 1]\n",
        );
        for i in 0..spheres {
            text += &format!("[[spheres]]\ncenter = [{i}, 0, 0]\nradius = 0.4\nmaterial = \"m\"\n");
        }
        let scene = parse_scene(&text, std::path::Path::new("t.toml"), SceneFormat::Toml).unwrap();
        let prims = Primitives::from_scene(&scene);
        SceneArrays::new(&scene, &prims, &KdTree::for_primitives(&prims))
    }

    #[test]
    fn a_scene_within_the_limits_fits() {
        assert!(arrays(100).check_fits(&wgpu::Limits::default()).is_ok());
    }

    /// Limits lowered artificially (rather than gigabytes of scene): the
    /// refusal names the buffer, its size and the limit.
    #[test]
    fn a_scene_beyond_one_binding_is_refused_with_its_size_and_the_limit() {
        let a = arrays(100); // 100 spheres * 16 B = 1600 B of spheres
        let limits = wgpu::Limits {
            max_storage_buffer_binding_size: 1024,
            ..wgpu::Limits::default()
        };
        let message = a.check_fits(&limits).unwrap_err().to_string();
        assert!(
            message.contains("spheres buffer needs 1.6 KiB"),
            "{message}"
        );
        assert!(message.contains("at most 1.0 KiB"), "{message}");
        assert!(message.contains("100 spheres"), "{message}");
        assert_eq!(message.lines().count(), 1);
        let limits = wgpu::Limits {
            max_buffer_size: 1024,
            ..wgpu::Limits::default()
        };
        assert!(a.check_fits(&limits).is_err());
    }
}
