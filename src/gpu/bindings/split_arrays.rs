//! The scene's arrays that may lie in several bindings, each but the last
//! full (shaders/chunks.wgsl): their bindings, the WGSL reader the contract
//! generates for each, and how many bindings each gets on an adapter
//! ([`scene_chunks`]). Part of the contract in gpu/bindings/, which
//! re-exports all of it.

use super::{
    binding, scene, Access, Binding, ENTRY_POINTS, KD_NODES, LEAF_OBJECTS, LEAF_ROPES,
    LEAF_ROPE_INDEX, TRIANGLES, TRIANGLE_NORMALS,
};

/// The most bindings one split array may spread over (shaders/chunks.wgsl);
/// the adapter's storage buffers per stage decide how many each gets
/// ([`scene_chunks`]). Eight x 128 MiB holds 22 million triangles.
pub const MAX_CHUNKS: usize = 8;

/// An array of the scene that may lie in several bindings: its bindings,
/// first chunk first, and what its generated reader returns.
pub struct SplitArray {
    /// The array's own binding, then `<name>_1` ... `<name>_7`, of its type.
    pub chunks: [Binding; MAX_CHUNKS],
    /// Bytes per element (the WGSL array's stride).
    pub element_bytes: usize,
    /// Its bytes per triangle of a large mesh (the bunny subdivided twice,
    /// 1.1 million triangles, smooth: 2.94 nodes, 1.47 leaves and 5.8 leaf
    /// references per triangle): [`scene_chunks`] shares the bindings out
    /// by these.
    pub bytes_per_triangle: u32,
    /// What the reader returns, where not the whole element.
    pub part: Option<ElementPart>,
}

/// A reader that returns part of an element: `fn <reader>(k: u32, j:
/// u32<params>) -> <returns>` returns `read` of element `j` of chunk `k`
/// (`@` in `read` stands for the chunk's binding).
pub struct ElementPart {
    pub params: &'static str,
    pub returns: &'static str,
    pub read: &'static str,
}

/// Chunk `name` (`<array>_<k>`) of a split array whose first binding is
/// `first`, at binding `index`.
const fn chunk(first: Binding, name: &'static str, index: u32) -> Binding {
    binding(index, name, first.wgsl_type, Access::StorageRead)
}

/// A split array whose first binding is `$first` (named `$name`) and whose
/// other chunks are `$name_1` ... `$name_7` at bindings `$base` ...
/// `$base + 6`; its reader returns the whole element.
macro_rules! split_array {
    ($first:expr, $name:literal, $base:literal,
     element_bytes: $element_bytes:expr, bytes_per_triangle: $bytes_per_triangle:expr) => {
        SplitArray {
            chunks: [
                $first,
                chunk($first, concat!($name, "_1"), $base),
                chunk($first, concat!($name, "_2"), $base + 1),
                chunk($first, concat!($name, "_3"), $base + 2),
                chunk($first, concat!($name, "_4"), $base + 3),
                chunk($first, concat!($name, "_5"), $base + 4),
                chunk($first, concat!($name, "_6"), $base + 5),
                chunk($first, concat!($name, "_7"), $base + 6),
            ],
            element_bytes: $element_bytes,
            bytes_per_triangle: $bytes_per_triangle,
            part: None,
        }
    };
}

/// How many arrays may be split.
pub const SPLIT_ARRAY_COUNT: usize = 6;

/// Every array that passes one binding as a mesh grows (12 to 72 bytes a
/// triangle, so between 1.9 and 11 million triangles; docs/design.md has the
/// arithmetic). The others stay whole: `objects` (8 B an object)
/// passes 128 MiB at 16.7 million objects, past what the split arrays hold;
/// spheres, materials and lights do not grow with a mesh.
#[rustfmt::skip]
pub const SPLIT_ARRAYS: [SplitArray; SPLIT_ARRAY_COUNT] = [
    split_array!(TRIANGLES, "triangles", 30, element_bytes: 48, bytes_per_triangle: 48),
    split_array!(KD_NODES, "kd_nodes", 37, element_bytes: 8, bytes_per_triangle: 24),
    split_array!(LEAF_OBJECTS, "leaf_objects", 44, element_bytes: 4, bytes_per_triangle: 23),
    SplitArray {
        // One word of one face (its plane's bits, or its rope when `rope`;
        // every call passes a constant, so only that load remains), not the
        // whole 48-byte record: a record copied to a local and indexed by a
        // variable face lives in memory on llvmpipe, which made the split
        // rope walk 4-6x slower than the unsplit one (bunny, 1.1 million
        // triangles).
        part: Some(ElementPart {
            params: ", face: u32, rope: bool",
            returns: "u32",
            read: "select(bitcast<u32>(@[j].faces[face]), @[j].ropes[face], rope)",
        }),
        ..split_array!(LEAF_ROPES, "leaf_ropes", 51, element_bytes: 48, bytes_per_triangle: 71)
    },
    split_array!(LEAF_ROPE_INDEX, "leaf_rope_index", 58, element_bytes: 4, bytes_per_triangle: 12),
    split_array!(TRIANGLE_NORMALS, "triangle_normals", 65, element_bytes: 12, bytes_per_triangle: 12),
];

/// How many bindings each split array has, in the order of
/// [`SPLIT_ARRAYS`] (1 to [`MAX_CHUNKS`] each).
pub type SceneChunks = [usize; SPLIT_ARRAY_COUNT];

/// One binding per split array: what a kernel without splitting declares.
pub const UNSPLIT: SceneChunks = [1; SPLIT_ARRAY_COUNT];

impl SplitArray {
    /// The array's name: its first binding's.
    pub fn name(&self) -> &'static str {
        self.chunks[0].name
    }

    /// The WGSL for `chunks` bindings: `const <NAME>_CHUNKS: u32` (the
    /// bindings it has in this kernel) and its reader, `fn <name>_chunk(k:
    /// u32, j: u32) -> <element>`, which reads element `j` of chunk `k`
    /// (chunks past the declared ones read the first; shaders/chunks.wgsl
    /// never asks for them).
    pub fn wgsl_reader(&self, chunks: usize) -> String {
        let (params, returns, read) = match &self.part {
            Some(part) => (part.params, part.returns, part.read),
            None => ("", self.chunks[0].element_type(), "@[j]"),
        };
        let mut text = format!(
            "const {}_CHUNKS: u32 = {chunks}u;\n",
            self.name().to_uppercase()
        );
        text += &format!(
            "fn {}_chunk(k: u32, j: u32{params}) -> {returns} {{\n    switch k {{\n",
            self.name()
        );
        let read = |b: &Binding| read.replace('@', b.name);
        for (k, b) in self.chunks[..chunks].iter().enumerate().skip(1) {
            text += &format!("        case {k}u: {{ return {}; }}\n", read(b));
        }
        text += &format!(
            "        default: {{ return {}; }}\n    }}\n}}\n",
            read(&self.chunks[0])
        );
        text
    }
}

/// How many bindings each split array gets on a device with `limits`: the
/// storage buffers per stage left by the whole arrays and the entry point
/// with the most buffers of its own, shared out one at a time to the array
/// with the most bytes per triangle per binding so far
/// ([`SplitArray::bytes_per_triangle`]), at least 1 and at most
/// [`MAX_CHUNKS`] each. Lavapipe (Vulkan, 32 per stage, 24 left):
/// triangles 6, nodes 3, leaf references 3, leaf ropes 8, rope index 2,
/// normals 2; llvmpipe's GL (16 per stage, 8 left): 2, 1, 1, 2, 1, 1. (The
/// optional `textures` binding takes one: triangles had 7 on lavapipe, but
/// `objects`, whole, already caps a scene at 16.7 million objects, which 6
/// triangle bindings hold.)
pub fn scene_chunks(limits: &wgpu::Limits) -> SceneChunks {
    let per_stage = limits.max_storage_buffers_per_shader_stage as usize;
    let whole_arrays = scene(UNSPLIT).len() - SPLIT_ARRAYS.len();
    let own = ENTRY_POINTS
        .iter()
        .map(|e| e.outputs.len())
        .max()
        .unwrap_or(0);
    let mut left = per_stage
        .saturating_sub(whole_arrays + own)
        .saturating_sub(SPLIT_ARRAYS.len());
    let mut chunks = UNSPLIT;
    while left > 0 {
        let share = |i: usize| SPLIT_ARRAYS[i].bytes_per_triangle as f64 / chunks[i] as f64;
        let Some(next) = (0..chunks.len())
            .filter(|&i| chunks[i] < MAX_CHUNKS)
            .reduce(|a, b| if share(b) > share(a) { b } else { a })
        else {
            break;
        };
        chunks[next] += 1;
        left -= 1;
    }
    chunks
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gpu::bindings::{
        entry_point_bindings, ACCUMULATE_OUTPUTS, QUERY_OUTPUTS, RENDER_OUTPUTS,
    };

    /// The chunk counts fit the adapter: every entry point's bindings with
    /// them stay within the storage buffers per stage, and one more binding
    /// for any array below MAX_CHUNKS would not; lavapipe's Vulkan (32) and
    /// llvmpipe's GL (16) get what the docs say.
    #[test]
    fn scene_chunks_fit_the_storage_buffers_per_stage() {
        let storage = |b: &[Binding]| b.iter().filter(|b| b.access != Access::Uniform).count();
        let with = |per_stage| {
            scene_chunks(&wgpu::Limits {
                max_storage_buffers_per_shader_stage: per_stage,
                ..wgpu::Limits::default()
            })
        };
        assert_eq!(with(32), [6, 3, 3, 8, 2, 2]);
        assert_eq!(with(16), [2, 1, 1, 2, 1, 1]);
        assert_eq!(with(8), UNSPLIT, "WebGPU's default: no split");
        assert_eq!(with(1000), [MAX_CHUNKS; SPLIT_ARRAY_COUNT]);
        let most = |chunks| {
            [&RENDER_OUTPUTS[..], &ACCUMULATE_OUTPUTS, &QUERY_OUTPUTS]
                .iter()
                .map(|outputs| storage(&entry_point_bindings(chunks, outputs)))
                .max()
                .unwrap()
        };
        // From 14, the most any entry point binds with one binding per array
        // (every scene array, the textures included, and three of its own).
        for per_stage in 14..64u32 {
            let chunks = with(per_stage);
            assert!(most(chunks) <= per_stage as usize, "{per_stage} per stage");
            for i in 0..chunks.len() {
                let mut more = chunks;
                more[i] += 1;
                assert!(
                    chunks[i] == MAX_CHUNKS || most(more) > per_stage as usize,
                    "{per_stage} per stage: {chunks:?} leaves room"
                );
            }
        }
    }
}
