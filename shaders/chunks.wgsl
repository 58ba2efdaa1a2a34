// Arrays split over several bindings, so that a scene may exceed one storage
// binding (128 MiB on lavapipe): the triangles and the leaf ropes lie in up
// to two bindings each (bindings::CHUNKS), the first one full when there
// are two. The first binding's
// length is the chunk length (a scene that fits has one chunk, and every
// index is below it). See SceneArrays::split in src/gpu/scene_buffers.rs.

// Whether the scene's arrays may be split: a pipeline-overridable constant,
// so that the renderer's pipeline for scenes that fit one binding each has
// none of the chunk selection. Measured on lavapipe (torus scene, release
// build), selecting the chunk at run time cost 25-45% of the frame even
// when the branch was uniform; pipelines made without the constant (the
// window, the debug entry point) take the general path.
override SPLIT_SCENE: bool = true;

fn triangle(i: u32) -> Triangle {
    if (!SPLIT_SCENE) {
        return triangles[i];
    }
    let chunk = arrayLength(&triangles);
    if (i < chunk) {
        return triangles[i];
    }
    return triangles_1[i - chunk];
}

// Leaf record `r`'s face `face`: its plane coordinate and its rope.
struct RopeFace {
    plane: f32,
    rope: u32,
}

fn rope_face(r: u32, face: u32) -> RopeFace {
    if (!SPLIT_SCENE) {
        return RopeFace(leaf_ropes[r].faces[face], leaf_ropes[r].ropes[face]);
    }
    let chunk = arrayLength(&leaf_ropes);
    if (r < chunk) {
        return RopeFace(leaf_ropes[r].faces[face], leaf_ropes[r].ropes[face]);
    }
    let j = r - chunk;
    return RopeFace(leaf_ropes_1[j].faces[face], leaf_ropes_1[j].ropes[face]);
}
