// Arrays split over several bindings, so that a scene may exceed one storage
// binding (128 MiB on lavapipe): the triangles, the k-d nodes, the leaf
// object lists, the leaf ropes, the rope index and the vertex normals lie in
// up to TRIANGLES_CHUNKS, KD_NODES_CHUNKS, ... bindings each (the adapter
// decides how many: bindings::scene_chunks), every one but the last full.
// The first binding's length is the chunk length (a scene that fits has one
// chunk, and every index is below it); `<array>_length()`, generated with
// the declaration, gives it. Every walk, the shading and the query
// kernel read these six arrays through the functions below, never directly.
// The bindings, the counts and the `<array>_chunk(k, j)` readers are
// generated (src/gpu/bindings/); the host cuts the arrays in
// src/gpu/scene_buffers.rs (`split`).

// Whether the scene's arrays may be split is SPLIT_SCENE (variant.wgsl): the
// renderer's pipeline for scenes that fit one binding each has none of the
// chunk selection.

// Element `index` of chunk `chunk` of a split array.
struct ChunkIndex {
    chunk: u32,
    index: u32,
}

// Where element `i` of a split array of `chunks` bindings lies when each
// holds `chunk_length` elements. Comparisons and subtractions only: no
// integer division (llvmpipe runs it one lane at a time), no product that
// could overflow; `chunks` is a generated constant at every call, so the
// loop unrolls.
fn chunk_index(i: u32, chunk_length: u32, chunks: u32) -> ChunkIndex {
    var at = ChunkIndex(0u, i);
    for (var c = 1u; c < chunks; c++) {
        let past = at.index >= chunk_length;
        at.chunk += select(0u, 1u, past);
        at.index -= select(0u, chunk_length, past);
    }
    return at;
}

// The bindings hold triangles and k-d nodes as vectors (one load each
// on llvmpipe, where a struct's members are loaded one by one); these unpack
// them into the structs of types.wgsl.
fn unpack_triangle(w: array<vec4<f32>, 3>) -> Triangle {
    return Triangle(w[0].xyz, bitcast<u32>(w[0].w), w[1].xyz, bitcast<u32>(w[1].w), w[2].xyz);
}

fn triangle(i: u32) -> Triangle {
    if (!SPLIT_SCENE) {
        return unpack_triangle(triangles[i]);
    }
    let at = chunk_index(i, triangles_length(), TRIANGLES_CHUNKS);
    return unpack_triangle(triangles_chunk(at.chunk, at.index));
}

fn unpack_kd_node(v: vec2<u32>) -> KdNode {
    let p = PackedKdNode(v.x, v.y);
    let kind = p.tag_and_index & 3u;
    let above = p.tag_and_index >> 2u;
    if (kind == KD_LEAF) {
        return KdNode(kind, 0.0, p.split_or_first, above);
    }
    return KdNode(kind, bitcast<f32>(p.split_or_first), above, 0u);
}

fn kd_node(i: u32) -> KdNode {
    if (!SPLIT_SCENE) {
        return unpack_kd_node(kd_nodes[i]);
    }
    let at = chunk_index(i, kd_nodes_length(), KD_NODES_CHUNKS);
    return unpack_kd_node(kd_nodes_chunk(at.chunk, at.index));
}

// Entry `i` of the leaves' object lists: an object id.
fn leaf_object(i: u32) -> u32 {
    if (!SPLIT_SCENE) {
        return leaf_objects[i];
    }
    let at = chunk_index(i, leaf_objects_length(), LEAF_OBJECTS_CHUNKS);
    return leaf_objects_chunk(at.chunk, at.index);
}

// Leaf record `r`'s face `face`: its plane coordinate (infinite on the
// scene's boundary), and the node beyond it. Two readers, so that the walk
// loads the planes of the three faces ahead and only the rope it follows.
fn rope_plane(r: u32, face: u32) -> f32 {
    if (!SPLIT_SCENE) {
        return leaf_ropes[r].faces[face];
    }
    let at = chunk_index(r, leaf_ropes_length(), LEAF_ROPES_CHUNKS);
    return bitcast<f32>(leaf_ropes_chunk(at.chunk, at.index, face, false));
}

fn rope_target(r: u32, face: u32) -> u32 {
    if (!SPLIT_SCENE) {
        return leaf_ropes[r].ropes[face];
    }
    let at = chunk_index(r, leaf_ropes_length(), LEAF_ROPES_CHUNKS);
    return leaf_ropes_chunk(at.chunk, at.index, face, true);
}

// The rope walk's record of k-d node `i` (leaves only).
fn leaf_rope_record(i: u32) -> u32 {
    if (!SPLIT_SCENE) {
        return leaf_rope_index[i];
    }
    let at = chunk_index(i, leaf_rope_index_length(), LEAF_ROPE_INDEX_CHUNKS);
    return leaf_rope_index_chunk(at.chunk, at.index);
}

// Vertex normals record `i` (`Triangle::normals` of a smooth triangle).
fn triangle_normals_record(i: u32) -> TriangleNormals {
    if (!SPLIT_SCENE) {
        return triangle_normals[i];
    }
    let at = chunk_index(i, triangle_normals_length(), TRIANGLE_NORMALS_CHUNKS);
    return triangle_normals_chunk(at.chunk, at.index);
}
