//! Meshes past one storage binding: the triangles, the k-d
//! nodes, the leaf object lists, the leaf ropes, the rope index and the
//! vertex normals may each spread over several bindings
//! (shaders/chunks.wgsl). Small chunk sizes force the split path on small
//! scenes, whose images and ray query answers must equal the unsplit ones
//! bit for bit, for every walk.

use crate::common;

use common::*;
use kdray::geometry::Ray;
use kdray::gpu::bindings::{self, SPLIT_ARRAY_COUNT};
use kdray::gpu::scene_buffers::{ChunkBytes, WHOLE};
use kdray::gpu::{
    Accel, FrameParams, PreparedScene, RayQueries, RayQuery, RenderedImage, Renderer, SceneBuffers,
    TilePlan,
};
use kdray::kdtree::Traversal;

fn upload(prepared: &PreparedScene, chunk_bytes: ChunkBytes) -> SceneBuffers {
    let buffers = SceneBuffers::upload_split(gpu(), &prepared.arrays, chunk_bytes)
        .unwrap_or_else(|e| panic!("{e}"));
    // The renderer picks its pipeline by this: the split path must run.
    assert_eq!(buffers.split, chunk_bytes != WHOLE);
    buffers
}

fn render_with_chunks(
    prepared: &PreparedScene,
    walk: Traversal,
    chunk_bytes: ChunkBytes,
) -> RenderedImage {
    let ctx = gpu();
    let buffers = upload(prepared, chunk_bytes);
    let renderer = Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let params = FrameParams::for_prepared(prepared, &buffers).with_traversal(walk);
    let scene = &prepared.scene;
    let plan = TilePlan::new(
        scene.render.width,
        scene.render.height,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
        kdray::gpu::max_binding_bytes(&ctx.device.limits()),
    );
    renderer
        .render(ctx, &buffers, params, plan)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The bindings of each split array on this adapter (lavapipe: 6, 3, 3, 8,
/// 2, 2).
fn chunks() -> [u64; SPLIT_ARRAY_COUNT] {
    bindings::scene_chunks(&gpu().device.limits()).map(|k| k as u64)
}

/// (elements, bytes per element) of each split array, in the order of
/// `bindings::SPLIT_ARRAYS`.
fn split_arrays(prepared: &PreparedScene) -> [(u64, u64); SPLIT_ARRAY_COUNT] {
    let a = &prepared.arrays;
    let lengths = [
        a.triangles.len(),
        a.nodes.len(),
        a.leaf_objects.len(),
        a.leaf_ropes.len(),
        a.leaf_rope_index.len(),
        a.triangle_normals.len(),
    ];
    std::array::from_fn(|i| {
        (
            lengths[i] as u64,
            bindings::SPLIT_ARRAYS[i].element_bytes as u64,
        )
    })
}

/// Chunk sizes of `elements(n, pieces)` elements per array (`n` its
/// length), plus `extra_bytes`; each array must then need exactly its
/// `pieces` bindings.
fn chunk_bytes_of(
    prepared: &PreparedScene,
    pieces: [u64; SPLIT_ARRAY_COUNT],
    elements: impl Fn(u64, u64) -> u64,
    extra_bytes: u64,
) -> ChunkBytes {
    let arrays = split_arrays(prepared);
    std::array::from_fn(|i| {
        let (n, size) = arrays[i];
        let bytes = elements(n, pieces[i]) * size + extra_bytes;
        let per_chunk = bytes / size;
        assert_eq!(
            n.div_ceil(per_chunk),
            pieces[i],
            "{} ({n} elements) in chunks of {bytes} B",
            bindings::SPLIT_ARRAYS[i].chunks[0].name
        );
        bytes
    })
}

/// Every split array in two bindings, the second partial.
fn two_chunks(prepared: &PreparedScene) -> ChunkBytes {
    chunk_bytes_of(prepared, [2; SPLIT_ARRAY_COUNT], |n, _| n / 2 + 7, 0)
}

/// The torus scene (4,610 smooth and flat triangles, mirrors).
fn torus() -> PreparedScene {
    PreparedScene::new(small_scene(&repo_path("scenes/torus.toml")), Accel::Kdtree)
}

/// The chunk sizes the tests run: every split array in two bindings, the
/// last one partial; in as many as the adapter gives each; in two bindings
/// of a size that is no whole number of elements; and a leaf-object chunk
/// that ends inside a leaf's list.
fn chunkings(prepared: &PreparedScene) -> Vec<(&'static str, ChunkBytes)> {
    assert!(
        chunks().iter().all(|&k| k >= 2),
        "this adapter gives a split array one binding: nothing to test"
    );
    vec![
        ("two chunks", two_chunks(prepared)),
        (
            "all chunks",
            chunk_bytes_of(prepared, chunks(), |n, k| n.div_ceil(k), 0),
        ),
        (
            "odd bytes",
            chunk_bytes_of(prepared, [2; SPLIT_ARRAY_COUNT], |n, _| n * 3 / 5, 7),
        ),
        ("inside a leaf", chunk_inside_a_leaf(prepared)),
    ]
}

/// Chunk sizes whose leaf-object chunk boundary falls strictly inside one
/// leaf's object list (that leaf then reads from two bindings), the other
/// arrays in two chunks.
fn chunk_inside_a_leaf(prepared: &PreparedScene) -> ChunkBytes {
    let a = &prepared.arrays;
    let references = a.leaf_objects.len() as u64;
    let k = chunks()[2];
    // A boundary at `index + 1` of a leaf of two or more objects, with a
    // chunk length that needs no more than the adapter's bindings.
    let leaf = a
        .nodes
        .iter()
        .map(|n| n.unpack())
        .filter(|n| n.is_leaf() && n.count >= 2)
        .find(|n| (n.index as u64 + 1) * k >= references && (n.index as u64 + 1) < references)
        .expect("a leaf of two or more objects in the right place");
    let chunk = leaf.index as u64 + 1;
    assert!(leaf.index < chunk as u32 && (chunk as u32) < leaf.index + leaf.count);
    let mut bytes = two_chunks(prepared);
    bytes[2] = chunk * 4;
    bytes
}

/// Every walk renders the same image with the arrays split as unsplit.
#[test]
fn split_bindings_give_the_unsplit_image() {
    let prepared = torus();
    let cases = chunkings(&prepared);
    for walk in Traversal::ALL {
        let whole = render_with_chunks(&prepared, walk, WHOLE);
        for (case, chunk_bytes) in &cases {
            let split = render_with_chunks(&prepared, walk, *chunk_bytes);
            assert_eq!(whole.rays, split.rays, "{walk}, {case}");
            let d = compare(&whole.rgb, &split.rgb, whole.width, whole.height, 0);
            assert_eq!(d.pixels_over, 0, "{walk}, {case}: {d:?}");
        }
    }
}

/// Deterministic rays over the scene's box: from points around it towards
/// points inside it, nearest-hit and any-hit (to half the distance).
fn rays(prepared: &PreparedScene, count: usize) -> Vec<RayQuery> {
    let b = prepared.arrays.bounds;
    let (lo, hi) = (b.min, b.max);
    let size = hi - lo;
    let mut state = 0x9e37_79b9_u32;
    let mut unit = move || {
        // xorshift32
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state as f32 / u32::MAX as f32
    };
    (0..count)
        .map(|i| {
            let mut point = |spread: f32| {
                let u = glam::Vec3::new(unit(), unit(), unit());
                lo + size * (u * (1.0 + 2.0 * spread) - spread)
            };
            let origin = point(0.5);
            let target = point(0.0);
            let dir = (target - origin).normalize();
            let any_hit = i % 2 == 1;
            RayQuery {
                ray: Ray { origin, dir },
                t_limit: if any_hit {
                    (target - origin).length() * 0.5
                } else {
                    kdray::geometry::T_INFINITY
                },
                any_hit,
            }
        })
        .collect()
}

/// The ray-query kernel (always the general pipeline) gives the same hits
/// and the same walk costs split as unsplit, for brute force and every walk.
#[test]
fn split_bindings_give_the_unsplit_ray_queries() {
    let prepared = torus();
    let ctx = gpu();
    let queries = RayQueries::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let rays = rays(&prepared, 4096);
    let ids = &prepared.arrays.scene_ids;
    let whole = upload(&prepared, WHOLE);
    let runs = [(Accel::Brute, Traversal::Restart)]
        .into_iter()
        .chain(Traversal::ALL.map(|walk| (Accel::Kdtree, walk)));
    for (accel, walk) in runs {
        let expected = queries
            .trace_counted(ctx, &whole, ids, accel, walk, &rays)
            .unwrap_or_else(|e| panic!("{e}"));
        let hits = expected.iter().filter(|(hit, _)| hit.is_some()).count();
        assert!(
            hits > rays.len() / 8,
            "{hits} hits: the rays test too little"
        );
        for (case, chunk_bytes) in chunkings(&prepared) {
            let split = upload(&prepared, chunk_bytes);
            let got = queries
                .trace_counted(ctx, &split, ids, accel, walk, &rays)
                .unwrap_or_else(|e| panic!("{e}"));
            for (i, (e, g)) in expected.iter().zip(&got).enumerate() {
                assert_eq!(e, g, "{accel:?} {walk}, {case}: ray {i} {:?}", rays[i]);
            }
        }
    }
}

/// More chunks' worth than the adapter's bindings is refused with one line
/// naming the buffer, for each split array.
#[test]
fn an_array_beyond_its_bindings_is_refused() {
    let prepared = torus();
    for (i, (n, size)) in split_arrays(&prepared).into_iter().enumerate() {
        let k = chunks()[i];
        let mut bytes = two_chunks(&prepared);
        bytes[i] = n.div_ceil(k + 1) * size;
        let message = SceneBuffers::upload_split(gpu(), &prepared.arrays, bytes)
            .err()
            .expect("refused")
            .to_string();
        let name = bindings::SPLIT_ARRAYS[i].chunks[0].name;
        assert!(
            message.contains(&format!("{name} buffer needs")),
            "{message}"
        );
        assert!(
            message.contains(&format!("({k} bindings for it)")),
            "{message}"
        );
        assert_eq!(message.lines().count(), 1);
    }
}
