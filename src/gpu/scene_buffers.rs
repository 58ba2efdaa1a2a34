//! The scene's arrays ([`SceneArrays`],
//! crates/kdray-core/src/layout/scene_arrays.rs) as storage buffers at the
//! bindings of [`super::bindings::scene`]: each split array cut into chunks
//! for its bindings, the check that everything fits the adapter, and the
//! upload ([`SceneBuffers`]).

use super::bindings;
use super::context::buffer_holding;
use super::{GpuContext, SceneArrays};
use crate::geometry::Aabb;
use crate::layout::GpuKdNode;

/// The arrays as the bindings hold them: in binding order, split arrays cut
/// into chunks, checked against the adapter's limits.
/// Bytes of the zeroed element an empty array is bound with: the largest
/// element of any array (the material, then the light).
pub const EMPTY_ARRAY_BYTES: usize = {
    let material = std::mem::size_of::<crate::layout::GpuMaterial>();
    let light = std::mem::size_of::<crate::layout::GpuLight>();
    if material > light {
        material
    } else {
        light
    }
};

/// The scene's arrays as the kernel's bindings hold them
/// ([`bindings::scene`]): the web export's bundle, and the check against
/// the adapter's limits.
pub trait ArrayBindings {
    /// (binding name, bytes) of every storage buffer, each array in one
    /// binding, in the order of [`bindings::scene`] (the web export's
    /// bundle holds them so).
    fn whole_buffers(&self) -> Vec<(&'static str, &[u8])>;

    /// Refuses, before anything is uploaded, a scene one of whose buffers
    /// exceeds what the adapter can bind (`max_storage_buffer_binding_size`,
    /// `max_buffer_size`), even split over the bindings the kernel has for
    /// it on this adapter ([`bindings::scene_chunks`]): the message names
    /// the buffer, its size and the limit.
    fn check_fits(&self, limits: &wgpu::Limits) -> crate::Result<()>;
}

impl ArrayBindings for SceneArrays {
    fn whole_buffers(&self) -> Vec<(&'static str, &[u8])> {
        buffers(self, WHOLE, bindings::UNSPLIT).unwrap_or_default()
    }

    fn check_fits(&self, limits: &wgpu::Limits) -> crate::Result<()> {
        let limit = super::max_binding_bytes(limits);
        check_fits_in(
            self,
            limit,
            [limit; bindings::SPLIT_ARRAY_COUNT],
            bindings::scene_chunks(limits),
        )
    }
}

/// The bytes of each split array, in the order of
/// [`bindings::SPLIT_ARRAYS`].
fn split_arrays(arrays: &SceneArrays) -> [&[u8]; bindings::SPLIT_ARRAY_COUNT] {
    [
        bytemuck::cast_slice(&arrays.triangles),
        bytemuck::cast_slice(&arrays.nodes),
        bytemuck::cast_slice(&arrays.leaf_objects),
        bytemuck::cast_slice(&arrays.leaf_ropes),
        bytemuck::cast_slice(&arrays.leaf_rope_index),
        bytemuck::cast_slice(&arrays.triangle_normals),
    ]
}

/// (binding name, bytes) of every storage buffer, in the order of
/// [`bindings::scene`] with `chunks` bindings per split array: each
/// split array cut into pieces of at most its `chunk_bytes` (`split`;
/// the pieces past the data are empty), the other arrays whole. Err
/// names the first split array that needs more than `chunks` pieces.
fn buffers(
    arrays: &SceneArrays,
    chunk_bytes: ChunkBytes,
    chunks: bindings::SceneChunks,
) -> Result<Vec<(&'static str, &[u8])>, &'static str> {
    let split_arrays = split_arrays(arrays);
    let mut pieces: [Vec<&[u8]>; bindings::SPLIT_ARRAY_COUNT] = Default::default();
    for (i, array) in bindings::SPLIT_ARRAYS.iter().enumerate() {
        pieces[i] = split(
            split_arrays[i],
            array.element_bytes,
            chunk_bytes[i],
            chunks[i],
        )
        .ok_or(array.chunks[0].name)?;
    }
    let [triangles, nodes, leaf_objects, ropes, rope_index, normals] = pieces;
    let bytes: Vec<&[u8]> = [bytemuck::cast_slice(&arrays.spheres)]
        .into_iter()
        .chain(triangles)
        .chain([
            bytemuck::cast_slice(&arrays.objects),
            bytemuck::cast_slice(&arrays.materials),
            bytemuck::cast_slice(&arrays.lights),
        ])
        .chain(nodes)
        .chain(leaf_objects)
        .chain(ropes)
        .chain(rope_index)
        .chain(normals)
        .chain([bytemuck::cast_slice(&arrays.textures)])
        .collect();
    let names = bindings::scene(chunks);
    debug_assert_eq!(bytes.len(), names.len());
    Ok(names.iter().map(|b| b.name).zip(bytes).collect())
}

/// Every buffer within `limit` bytes, the split ones cut into at most
/// `chunks` pieces of at most their `chunk_bytes` (<= `limit`).
fn check_fits_in(
    arrays: &SceneArrays,
    limit: u64,
    chunk_bytes: ChunkBytes,
    chunks: bindings::SceneChunks,
) -> crate::Result<()> {
    packed_nodes_fit(arrays.nodes.len(), arrays.leaf_objects.len())?;
    let whole = buffers(arrays, WHOLE, bindings::UNSPLIT).unwrap_or_default();
    let split_array =
        |name: &str| (0..chunks.len()).find(|&i| bindings::SPLIT_ARRAYS[i].chunks[0].name == name);
    // The first buffer, in binding order, that no binding (or none of a
    // split array's bindings) can hold.
    let too_big = whole.iter().find(|(name, bytes)| match split_array(name) {
        Some(i) => split(
            bytes,
            bindings::SPLIT_ARRAYS[i].element_bytes,
            chunk_bytes[i],
            chunks[i],
        )
        .is_none(),
        None => bytes.len() as u64 > limit,
    });
    let Some(&(name, bytes)) = too_big else {
        return Ok(());
    };
    let bytes = bytes.len() as u64;
    let split_note = match split_array(name).map(|i| chunks[i]) {
        None => String::new(),
        Some(1) => " (1 binding for it on this adapter)".to_string(),
        Some(n) => format!(" ({n} bindings for it)"),
    };
    Err(crate::Error::Gpu(format!(
        "the scene is too large for this adapter: its {name} buffer needs {} but the adapter binds at most {} \
         per storage buffer{split_note} ({} spheres, {} triangles, {} k-d nodes, {} leaf references)",
        human_bytes(bytes),
        human_bytes(limit),
        arrays.spheres.len(),
        arrays.triangles.len(),
        arrays.nodes.len(),
        arrays.leaf_objects.len()
    )))
}

/// Whether a tree of `nodes` nodes and `leaf_references` leaf references
/// packs into [`GpuKdNode`]s: every child index and leaf count within the 30
/// bits it has. (2^30 leaf references are some 160 million triangles' worth
/// at 6.7 a triangle, more than the split bindings hold on lavapipe.)
fn packed_nodes_fit(nodes: usize, leaf_references: usize) -> crate::Result<()> {
    let most = GpuKdNode::MAX_INDEX as usize;
    if nodes > most + 1 || leaf_references > most {
        return Err(crate::Error::Gpu(format!(
            "the scene is too large for the kernel: its k-d tree has {nodes} nodes and {leaf_references} \
             leaf references, and a node holds child indices and leaf counts of at most {most}"
        )));
    }
    Ok(())
}

/// `bytes` (whole elements of `element` bytes) cut into `chunks` pieces for
/// bindings of at most `binding_bytes`: all of it in the first when it fits,
/// else pieces of as many whole elements as a binding holds, every one but
/// the last full (the kernel takes the first piece's length as the chunk
/// length, shaders/chunks.wgsl), then empty ones. None when it needs more
/// pieces.
fn split(bytes: &[u8], element: usize, binding_bytes: u64, chunks: usize) -> Option<Vec<&[u8]>> {
    let chunk = if bytes.len() as u64 <= binding_bytes {
        bytes.len().max(element)
    } else {
        (binding_bytes / element as u64) as usize * element
    };
    if chunk == 0 || bytes.len().div_ceil(chunk) > chunks {
        return None;
    }
    Some(
        (0..chunks)
            .map(|k| {
                let start = (k * chunk).min(bytes.len());
                &bytes[start..(start + chunk).min(bytes.len())]
            })
            .collect(),
    )
}

/// The most bytes of each split array one binding holds, in the order of
/// [`bindings::SPLIT_ARRAYS`] (triangles, k-d nodes, leaf objects, leaf
/// ropes, rope index, vertex normals); the device's limit caps each.
pub type ChunkBytes = [u64; bindings::SPLIT_ARRAY_COUNT];

/// Each split array in one binding if the device allows it.
pub const WHOLE: ChunkBytes = [u64::MAX; bindings::SPLIT_ARRAY_COUNT];

/// Bytes for people: B, KiB or MiB.
pub(crate) fn human_bytes(bytes: u64) -> String {
    match bytes {
        b if b < 1024 => format!("{b} B"),
        b if b < 1024 * 1024 => format!("{:.1} KiB", b as f64 / 1024.0),
        b => format!("{:.1} MiB", b as f64 / (1024.0 * 1024.0)),
    }
}

/// The scene's storage buffers on the device (the bindings of
/// [`bindings::scene`]) and what the kernel's parameters say of them.
pub struct SceneBuffers {
    /// The bindings of `buffers`, one each.
    bindings: Vec<bindings::Binding>,
    buffers: Vec<wgpu::Buffer>,
    /// The box the walk clips rays to.
    pub bounds: Aabb,
    pub sphere_count: u32,
    pub object_count: u32,
    /// Point lights, first in the lights buffer.
    pub light_count: u32,
    /// Emissive objects, after the point lights in the lights buffer.
    pub emitter_count: u32,
    /// Where the sky image lies in the textures buffer, if any.
    pub environment: crate::layout::EnvironmentWords,
    pub node_count: u32,
    /// Whether a split array (triangles, k-d nodes, leaf object lists, leaf
    /// ropes, rope index, vertex normals) lies in more than one binding (the kernel must then select
    /// the chunk: `gpu::KernelVariant::split_scene`).
    pub split: bool,
    /// The scene's kernel variant (`KernelVariant::for_arrays`): its kinds
    /// of object, material and light, and `split`.
    pub variant: super::KernelVariant,
}

impl SceneBuffers {
    /// Uploads `arrays` to the device, each split array over as many
    /// bindings as it needs (up to [`bindings::scene_chunks`] each). A scene
    /// with a buffer beyond the adapter's binding limits is refused before
    /// anything is allocated; one
    /// the device has no memory for fails with the size it needed. Either
    /// way the error is one line.
    pub fn upload(ctx: &GpuContext, arrays: &SceneArrays) -> crate::Result<Self> {
        Self::upload_split(ctx, arrays, WHOLE)
    }

    /// [`Self::upload`] with each split array cut into bindings of at most
    /// its `chunk_bytes` (capped at the device's limit), so that tests run
    /// the split path on small scenes.
    pub fn upload_split(
        ctx: &GpuContext,
        arrays: &SceneArrays,
        chunk_bytes: ChunkBytes,
    ) -> crate::Result<Self> {
        let limits = ctx.device.limits();
        let limit = super::max_binding_bytes(&limits);
        let chunks = bindings::scene_chunks(&limits);
        let chunk_bytes = chunk_bytes.map(|b| b.min(limit));
        check_fits_in(arrays, limit, chunk_bytes, chunks)?;
        // check_fits_in names what does not fit; this only guards the split.
        let parts = buffers(arrays, chunk_bytes, chunks).map_err(|name| {
            crate::Error::Gpu(format!("the scene's {name} do not fit in their bindings"))
        })?;
        let what = format!(
            "uploading the scene ({} of GPU memory)",
            human_bytes(arrays.byte_size())
        );
        ctx.checked(&what, |device| Self::create(device, arrays, &parts, chunks))
    }

    /// The scene's binding numbers, each with its buffer (a handle: the
    /// buffer is shared, not copied).
    pub fn bound_buffers(&self) -> impl Iterator<Item = (u32, wgpu::Buffer)> + '_ {
        self.bindings
            .iter()
            .zip(&self.buffers)
            .map(|(b, buffer)| (b.index, buffer.clone()))
    }

    /// Rewrites the lights buffer with `lights`, one per light of the scene
    /// (an animation's frame moves its lights; the tree stays). Callers pass
    /// the same scene's frame, so the counts agree; any surplus is not written.
    pub fn write_lights(&self, queue: &wgpu::Queue, lights: &[crate::layout::GpuLight]) {
        debug_assert_eq!(
            lights.len(),
            self.light_count as usize,
            "one value per light"
        );
        let lights = &lights[..lights.len().min(self.light_count as usize)];
        let buffer = self
            .bindings
            .iter()
            .zip(&self.buffers)
            .find(|(b, _)| b.name == bindings::LIGHTS.name);
        if let (Some((_, buffer)), false) = (buffer, lights.is_empty()) {
            queue.write_buffer(buffer, 0, bytemuck::cast_slice(lights));
        }
    }

    /// Creates the buffers; errors go to the caller's error scopes.
    fn create(
        device: &wgpu::Device,
        arrays: &SceneArrays,
        parts: &[(&'static str, &[u8])],
        chunks: bindings::SceneChunks,
    ) -> Self {
        // Any piece past a split array's first that holds data.
        let later_chunks: Vec<&str> = bindings::SPLIT_ARRAYS
            .iter()
            .flat_map(|a| a.chunks[1..].iter().map(|b| b.name))
            .collect();
        let split = parts
            .iter()
            .any(|(name, bytes)| later_chunks.contains(name) && !bytes.is_empty());
        let buffers = parts
            .iter()
            .map(|(name, bytes)| {
                // Bindings may not be empty: an empty array gets one zeroed
                // element of the largest element type.
                let padded = [0u8; EMPTY_ARRAY_BYTES];
                let contents = if bytes.is_empty() { &padded[..] } else { bytes };
                // The lights are rewritten per frame of an animation.
                let usage = if *name == bindings::LIGHTS.name {
                    wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST
                } else {
                    wgpu::BufferUsages::STORAGE
                };
                buffer_holding(device, name, contents, usage)
            })
            .collect();
        SceneBuffers {
            bindings: bindings::scene(chunks),
            buffers,
            bounds: arrays.bounds,
            sphere_count: arrays.spheres.len() as u32,
            object_count: arrays.objects.len() as u32,
            light_count: arrays.point_light_count(),
            emitter_count: arrays.emitter_count,
            environment: arrays.environment,
            node_count: arrays.nodes.len() as u32,
            split,
            variant: super::KernelVariant::for_arrays(arrays, split),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Primitives;
    use crate::kdtree::KdTree;
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
    fn trees_past_the_packed_index_are_refused() {
        let most = GpuKdNode::MAX_INDEX as usize;
        assert!(packed_nodes_fit(most + 1, most).is_ok());
        for (nodes, refs) in [(most + 2, 0), (1, most + 1)] {
            let message = packed_nodes_fit(nodes, refs).unwrap_err().to_string();
            assert!(message.contains("too large for the kernel"), "{message}");
            assert!(message.contains(&format!("{nodes} nodes")), "{message}");
        }
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

    /// `split` keeps every byte in order, in whole elements, each piece
    /// within the binding; all pieces but the last non-empty one are full;
    /// it refuses what needs more pieces than it has.
    #[test]
    fn split_cuts_whole_elements_in_order() {
        let bytes: Vec<u8> = (0..100u8).collect(); // 25 elements of 4 B
        for binding in [4u64, 7, 10, 24, 99, 100, 1000] {
            for chunks in 1..=6 {
                let per_chunk = (binding.min(100) / 4) as usize;
                let needed = 25usize.div_ceil(per_chunk);
                let Some(pieces) = split(&bytes, 4, binding, chunks) else {
                    assert!(needed > chunks, "{binding} B x {chunks} was refused");
                    continue;
                };
                assert!(needed <= chunks, "{binding} B x {chunks}");
                assert_eq!(pieces.len(), chunks);
                assert_eq!(pieces.concat(), bytes, "{binding} B x {chunks}");
                let used = pieces.iter().filter(|p| !p.is_empty()).count();
                for (k, p) in pieces.iter().enumerate() {
                    assert!(p.len() as u64 <= binding && p.len() % 4 == 0);
                    if k + 1 < used {
                        assert_eq!(p.len(), per_chunk * 4, "{binding} B x {chunks}: piece {k}");
                    }
                }
            }
        }
        assert!(split(&bytes, 4, 3, 5).is_none(), "no element fits");
    }
}
