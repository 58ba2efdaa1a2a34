//! Meshes past one storage binding (issue 10 §3): the triangles and the
//! leaf ropes may spread over several bindings (shaders/chunks.wgsl). A
//! small chunk size forces the split path on small scenes, whose images
//! must equal the unsplit ones bit for bit, for every walk.

mod common;

use common::*;
use kdray::gpu::{Accel, PreparedScene, RenderedImage, Renderer, SceneBuffers, TilePlan};
use kdray::kdtree::Traversal;

fn render_with_chunks(
    prepared: &PreparedScene,
    walk: Traversal,
    chunk_bytes: u64,
) -> RenderedImage {
    let ctx = gpu();
    let buffers = SceneBuffers::upload_split(ctx, &prepared.arrays, chunk_bytes)
        .unwrap_or_else(|e| panic!("{e}"));
    // The renderer picks its pipeline by this: the split path must run.
    assert_eq!(buffers.split, chunk_bytes != u64::MAX);
    let renderer = Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let params = prepared
        .frame_params(&buffers, Accel::Kdtree)
        .with_traversal(walk);
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

/// The torus scene (4,610 smooth and flat triangles, mirrors) with the
/// triangles and the leaf ropes in two bindings each renders exactly as
/// with one binding each; so does a chunk size that is no whole number of
/// elements.
#[test]
fn split_bindings_give_the_unsplit_image() {
    let scene = small_scene(&repo_path("scenes/torus.toml"));
    let prepared = PreparedScene::new(scene, Accel::Kdtree);
    let a = &prepared.arrays;
    let triangles = a.triangles.len() as u64;
    let leaves = a.leaf_ropes.len() as u64;
    // Two chunks of the larger array, the last one partial; the smaller
    // must need two as well (both arrays are 48 B an element).
    let most = triangles.max(leaves);
    let chunk = (most / 2 + 7) * 48;
    for (name, n) in [("triangles", triangles), ("leaf ropes", leaves)] {
        assert!(
            n * 48 > chunk && n * 48 <= 2 * chunk,
            "the {name} ({n}) should need two chunks of {chunk} B"
        );
    }
    let odd = (most * 3 / 5) * 48 + 7; // not a whole number of elements
    for walk in Traversal::ALL {
        let whole = render_with_chunks(&prepared, walk, u64::MAX);
        for chunk_bytes in [chunk, odd] {
            let split = render_with_chunks(&prepared, walk, chunk_bytes);
            assert_eq!(whole.rays, split.rays, "{walk}, chunks of {chunk_bytes} B");
            let d = compare(&whole.rgb, &split.rgb, whole.width, whole.height, 0);
            assert_eq!(d.pixels_over, 0, "{walk}, chunks of {chunk_bytes} B: {d:?}");
        }
    }
}

/// More than two chunks' worth is refused with one line naming the buffer.
#[test]
fn a_mesh_beyond_two_chunks_is_refused() {
    let scene = small_scene(&repo_path("scenes/torus.toml"));
    let prepared = PreparedScene::new(scene, Accel::Kdtree);
    let chunk = (prepared.arrays.triangles.len() as u64).div_ceil(3) * 48;
    let message = SceneBuffers::upload_split(gpu(), &prepared.arrays, chunk)
        .err()
        .expect("refused")
        .to_string();
    assert!(message.contains("triangles buffer needs"), "{message}");
    assert!(message.contains("(2 bindings for it)"), "{message}");
    assert_eq!(message.lines().count(), 1);
}
