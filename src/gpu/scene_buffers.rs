//! The scene flattened into GPU arrays (host side) and uploaded as storage
//! buffers. Bindings as declared in shaders/types.wgsl.

use wgpu::util::DeviceExt;

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
    pub fn upload(device: &wgpu::Device, arrays: &SceneArrays) -> Self {
        let buffers = arrays
            .buffers()
            .iter()
            .map(|(name, bytes)| {
                // Bindings may not be empty: an empty array gets one zeroed
                // element (64 bytes covers the largest element type).
                let padded = [0u8; 64];
                let contents = if bytes.is_empty() { &padded[..] } else { bytes };
                device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some(name),
                    contents,
                    usage: wgpu::BufferUsages::STORAGE,
                })
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
