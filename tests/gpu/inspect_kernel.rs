//! The inspect kernel (`inspect_pixel`, shaders/walk_record.wgsl) against
//! the renderer and the CPU mirror: the sample it logs is the rendered
//! pixel's (colour or radiance, and the walk cost `--stats` counts for it),
//! in both integrators; its rays and walks are the CPU mirror's, step
//! for step, on random pixels of the inspect tests' scenes with every walk;
//! and each path-traced shadow ray names its light with the probability the
//! CPU reference's `LightChoice` gives it from the shading point (by power,
//! and for an emitter the light tree's walk).

use crate::common;
use crate::inspect::pixels;

use kdray::gpu::{Accel, GpuScene, PreparedScene, TilePlan, WalkRecorder};
use kdray::inspect::{inspect_on_gpu, inspect_scene, Inspection};
use kdray::kdtree::traverse::WalkCost;
use kdray::kdtree::{BuildStrategy, Traversal};
use kdray::scene::{load_scene, parse_scene, Scene, SceneFormat};
use kdray_core::reference::{LightChoice, LightId};

use glam::Vec3;
use std::path::Path;

/// The scenes of tests/gpu/inspect.rs.
const SCENES: [&str; 6] = [
    "scenes/seed.toml",
    "scenes/mirrors.toml",
    "scenes/torus.toml",
    "scenes/glass.toml",
    "tests/scenes/rays_on_split_planes.toml",
    "tests/scenes/thin_triangles.toml",
];

fn scene_at(path: &str, width: u32, height: u32) -> Scene {
    let full = format!("{}/{path}", env!("CARGO_MANIFEST_DIR"));
    let mut scene = load_scene(full.as_ref()).unwrap_or_else(|e| panic!("{e}"));
    (scene.render.width, scene.render.height) = (width, height);
    scene
}

fn upload(scene: &Scene) -> GpuScene {
    let prepared = PreparedScene::built_by(scene.clone(), Accel::Kdtree, BuildStrategy::Sah);
    GpuScene::upload(common::gpu(), prepared).unwrap_or_else(|e| panic!("{e}"))
}

/// The inspected rays' counted work, added up.
fn total_cost(inspection: &Inspection) -> WalkCost {
    let mut total = WalkCost::default();
    for r in &inspection.rays {
        total.nodes_visited += r.counts.nodes;
        total.leaves_visited += r.counts.leaves;
        total.objects_tested += r.counts.tests;
    }
    total
}

/// Each pixel's 8-bit colour, radiance (path frames) and walk cost as the
/// renderer writes them for `scene`'s frame.
struct Rendered {
    rgb: Vec<u8>,
    radiance: Vec<f32>,
    costs: Vec<WalkCost>,
}

fn render_with_costs(scene: &GpuScene, traversal: Traversal) -> Rendered {
    let ctx = common::gpu();
    let renderer = kdray::gpu::Renderer::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let params = scene.frame_params().with_traversal(traversal);
    let (w, h) = (params.width, params.height);
    let limits = ctx.device.limits();
    let plan = TilePlan::new(
        w,
        h,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
        kdray::gpu::max_binding_bytes(&limits),
    );
    let mut out = Rendered {
        rgb: Vec::new(),
        radiance: Vec::new(),
        costs: Vec::new(),
    };
    renderer
        .render_bands_with_cost(ctx, scene.buffers(), params, plan, true, &mut |band| {
            out.rgb.extend_from_slice(band.rgb);
            out.costs
                .extend_from_slice(band.costs.expect("asked for costs"));
            if let Some(r) = band.radiance {
                out.radiance.extend_from_slice(r);
            }
            Ok(())
        })
        .unwrap_or_else(|e| panic!("{e}"));
    out
}

/// With one sample per pixel, the sample the inspect kernel logs is the
/// rendered pixel: its colour (Whitted: the same 8-bit level; path: the
/// same radiance, bit for bit) and the walk cost the renderer counts for
/// it (`--stats`, the heatmap) is the sum of the logged rays' counts.
#[test]
fn the_inspected_sample_is_the_rendered_pixel_with_its_counted_cost() {
    let ctx = common::gpu();
    let recorder = WalkRecorder::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let cases = [
        ("scenes/seed.toml", Traversal::Restart),
        ("scenes/glass.toml", Traversal::ShortStack),
        ("scenes/mirrors.toml", Traversal::Ropes),
        ("scenes/cornell_box.toml", Traversal::ShortStack),
        ("scenes/bunny_sky.toml", Traversal::Restart),
    ];
    let (width, height) = (32, 24);
    let mut bounces = 0;
    for (salt, (path, traversal)) in cases.into_iter().enumerate() {
        let mut scene = scene_at(path, width, height);
        scene.render.samples = 1;
        let uploaded = upload(&scene);
        let rendered = render_with_costs(&uploaded, traversal);
        let is_path = !rendered.radiance.is_empty();
        for (x, y) in pixels(salt as u64, width, height, 8) {
            let what = format!("{path} {traversal} pixel {x},{y}");
            let inspection = inspect_on_gpu(ctx, &recorder, &uploaded, traversal, (x, y))
                .unwrap_or_else(|e| panic!("{what}: {e}"));
            let i = (y * width + x) as usize;
            assert_eq!(
                total_cost(&inspection),
                rendered.costs[i],
                "{what}: the logged rays' work is the pixel's"
            );
            let sample = inspection.sample.expect("the kernel logs its sample");
            if is_path {
                assert_eq!(inspection.integrator, "path", "{what}");
                let rendered_radiance = &rendered.radiance[3 * i..3 * i + 3];
                assert_eq!(
                    sample.map(f32::to_bits),
                    [0, 1, 2].map(|c| rendered_radiance[c].to_bits()),
                    "{what}: radiance {sample:?} against {rendered_radiance:?}"
                );
                bounces += inspection
                    .rays
                    .iter()
                    .filter(|r| r.kind == "bounce")
                    .count();
            } else {
                let level = common::quantize(sample.map(f64::from));
                assert_eq!(
                    level[..],
                    rendered.rgb[3 * i..3 * i + 3],
                    "{what}: colour {sample:?}"
                );
            }
        }
    }
    assert!(bounces > 0, "the path-traced pixels logged no bounce");
}

/// The kernel's log and the CPU mirror tell the same story: the same rays
/// in the same order (kind, query, origin, direction), each with the same
/// walk, step for step (nodes, leaves, tests, pushes, pops, restarts,
/// ropes), the same hit and the same counted work, on random pixels of six
/// scenes with every walk.
#[test]
fn the_kernels_logged_walks_are_the_cpu_mirrors_step_for_step() {
    let ctx = common::gpu();
    let recorder = WalkRecorder::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let (width, height) = (64, 48);
    let (mut rays, mut agreeing, mut steps) = (0usize, 0usize, 0usize);
    let mut first_difference = None;
    for (salt, path) in SCENES.iter().enumerate() {
        let scene = scene_at(path, width, height);
        let uploaded = upload(&scene);
        let tree = uploaded.prepared().tree.clone();
        for traversal in Traversal::ALL {
            for (x, y) in pixels(salt as u64, width, height, 11) {
                let what = format!("{path} {traversal} pixel {x},{y}");
                let cpu = inspect_scene(&scene, Some(tree.clone()), traversal, (x, y))
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                let gpu = inspect_on_gpu(ctx, &recorder, &uploaded, traversal, (x, y))
                    .unwrap_or_else(|e| panic!("{what}: {e}"));
                assert_eq!(gpu.walk_source, "kernel");
                assert_eq!(
                    gpu.rays.len(),
                    cpu.rays.len(),
                    "{what}: the kernel traced {} rays, the CPU mirror {}",
                    gpu.rays.len(),
                    cpu.rays.len()
                );
                for (i, (g, c)) in gpu.rays.iter().zip(&cpu.rays).enumerate() {
                    let to_json = |r| serde_json::to_value(r).expect("a ray serialises");
                    rays += 1;
                    steps += c.walk.len();
                    assert_eq!((g.kind, g.query), (c.kind, c.query), "{what} ray {i}");
                    match common::json_disagreement(
                        &to_json(g),
                        &to_json(c),
                        &format!("{what} ray {i}"),
                    ) {
                        None => agreeing += 1,
                        Some(d) => {
                            first_difference.get_or_insert(d);
                        }
                    }
                }
            }
        }
    }
    // Measured on lavapipe: all 576 rays (6,355 steps) agree. A ray whose
    // hit lies an ulp from a cell's face may be tested in one leaf more or
    // less on another GPU; allow one ray in a hundred, and show the first.
    assert!(
        agreeing * 100 >= rays * 99,
        "{agreeing} of {rays} rays agree ({steps} steps); first difference: {first_difference:?}"
    );
    assert!(rays >= 6 * 3 * 11, "only {rays} rays");
}

/// A path-traced scene lit by lights of different power: a point light
/// (`[[lights]]` 0), a sun (1), an emissive quad facing down (triangles 2
/// and 3, objects 3 and 4) and an emissive sphere (object 0). Powers (light_picks):
/// about 25, 27, 2 x 12.6 and 21.
const LIGHTS_SCENE: &str = r#"
[camera]
position = [0.0, 3.2, 2.6]
look_at  = [0.0, 0.0, 0.0]
vfov     = 60.0

[render]
width      = 24
height     = 16
integrator = "path"
samples    = 1
max_depth  = 3

[materials.floor]
diffuse = [0.8, 0.8, 0.8]

[materials.lamp]
diffuse  = [0.0, 0.0, 0.0]
emission = [8.0, 8.0, 8.0]

[materials.glow]
diffuse  = [0.0, 0.0, 0.0]
emission = [6.0, 6.0, 6.0]

[[spheres]]
center   = [1.0, 0.3, 0.0]
radius   = 0.3
material = "glow"

[[triangles]]
vertices = [[-2.0, 0.0, -2.0], [-2.0, 0.0, 2.0], [2.0, 0.0, 2.0]]
material = "floor"
[[triangles]]
vertices = [[-2.0, 0.0, -2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0]]
material = "floor"
[[triangles]]
vertices = [[-0.5, 1.5, -0.5], [0.5, 1.5, -0.5], [0.5, 1.5, 0.5]]
material = "lamp"
[[triangles]]
vertices = [[-0.5, 1.5, -0.5], [0.5, 1.5, 0.5], [-0.5, 1.5, 0.5]]
material = "lamp"

[[lights]]
position = [-1.5, 2.0, 1.0]
diffuse  = [2.0, 2.0, 2.0]

[[lights]]
kind      = "directional"
direction = [0.3, -1.0, -0.2]
diffuse   = [1.0, 1.0, 1.0]
"#;

/// The probability the kernel's light table gives scene light `light`
/// (the host's `light_picks`): its pick. None for the others, whose
/// probability depends on the shading point.
fn table_pick(arrays: &kdray::layout::SceneArrays, light: LightId) -> Option<f32> {
    match light {
        LightId::Scene(i) => arrays.lights.get(i as usize).map(|l| l.pick),
        _ => None,
    }
}

/// Each shadow ray of next-event estimation names the light it aims at
/// and the probability it was picked with: computed on the CPU from the
/// scene (the reference's `LightChoice`: a scene light's share of the
/// power; an emitter's, the emitters' share times the light tree's walk
/// from the shading point), and for a scene light bit for bit the
/// probability the host's light table gives it; the ray aims at that
/// light (a point light's position at its limit, the sun's direction, a
/// point of the emitter at its limit) and an emitter's logged density is
/// the one sampling it by area or cone gives from the shading point, its
/// pick included. Every light of the scene is picked on some pixel; no
/// other ray names a light.
#[test]
fn path_traced_shadow_rays_name_their_light_and_the_probability_it_was_picked_with() {
    let ctx = common::gpu();
    let recorder = WalkRecorder::new(ctx).unwrap_or_else(|e| panic!("{e}"));
    let scene = parse_scene(LIGHTS_SCENE, Path::new("lights.toml"), SceneFormat::Toml)
        .unwrap_or_else(|e| panic!("{e}"));
    let choice = LightChoice::of(&scene);
    let uploaded = upload(&scene);
    let arrays = &uploaded.prepared().arrays;
    let ids = [
        LightId::Scene(0),
        LightId::Scene(1),
        LightId::Emitter(0),
        LightId::Emitter(3),
        LightId::Emitter(4),
    ];
    assert_eq!(choice.lights.len(), ids.len(), "{:?}", choice.lights);
    // Every other pixel of the floor's middle (24 x 16 image): its first
    // light picks fall on every light (the pseudo-random pixels of the
    // other tests picked no sphere: their draws in its range were pixels
    // of the sky).
    let grid = (6..=14)
        .step_by(2)
        .flat_map(|y| (4..=20).step_by(2).map(move |x| (x, y)));
    let mut picked = std::collections::BTreeSet::new();
    let mut shadow_rays = 0;
    for (x, y) in grid {
        let what = format!("pixel {x},{y}");
        let inspection = inspect_on_gpu(ctx, &recorder, &uploaded, Traversal::Restart, (x, y))
            .unwrap_or_else(|e| panic!("{what}: {e}"));
        let mut shading_point = None;
        for (i, r) in inspection.rays.iter().enumerate() {
            let what = format!("{what} ray {i}");
            let Some(light) = &r.light else {
                assert_ne!(r.kind, "shadow", "{what}: a shadow ray without its light");
                shading_point = r
                    .hit
                    .as_ref()
                    .map(|h| (Vec3::from(h.point), Vec3::from(h.normal)));
                continue;
            };
            assert_eq!(r.kind, "shadow", "{what}: a light on a {} ray", r.kind);
            shadow_rays += 1;
            let id = light.id();
            picked.insert(id);
            let (p, normal) = shading_point.expect("a shadow ray leaves a hit");
            let expected = choice.probability(id, p, normal);
            assert!(expected > 0.0, "{what}: {light:?} is no light of the scene");
            let pick = light.pick as f64;
            assert!(
                (pick - expected).abs() <= 1e-4 * expected,
                "{what}: {light:?} picked with {pick} at {p}, the reference's is {expected}"
            );
            if let Some(table) = table_pick(arrays, id) {
                assert_eq!(
                    light.pick.to_bits(),
                    table.to_bits(),
                    "{what}: {light:?} against the light table"
                );
            }
            let origin = Vec3::from(r.origin);
            let dir = Vec3::from(r.direction);
            let end = r.t_limit.map(|t| origin + t * dir);
            match id {
                LightId::Scene(0) => {
                    assert_eq!((light.kind, light.pdf), (Some("point"), None), "{what}");
                    let at = end.expect("a point light's shadow ray ends at it");
                    let light_at = scene.lights[0].position.as_vec3();
                    assert!(
                        (at - light_at).length() < 1e-3,
                        "{what}: {at} not at {light_at}"
                    );
                }
                LightId::Scene(_) => {
                    assert_eq!(
                        (light.kind, light.pdf),
                        (Some("directional"), None),
                        "{what}"
                    );
                    assert_eq!(r.t_limit, None, "{what}: the sun's shadow ray is unbounded");
                    let towards = -Vec3::new(0.3, -1.0, -0.2).normalize();
                    assert!((dir - towards).length() < 1e-5, "{what}: {dir}");
                }
                LightId::Emitter(object) => {
                    let kind = if object == 0 { "sphere" } else { "triangle" };
                    assert_eq!(light.kind, Some(kind), "{what}");
                    assert_eq!(light.triangle, object.checked_sub(1), "{what}");
                    let q = end.expect("an emitter's shadow ray ends at it");
                    let density = choice
                        .emitter_density(&scene, object, p, normal, q)
                        .unwrap_or_else(|| {
                            panic!("{what}: {q} is no point {object} lights {p} from")
                        });
                    let logged = light.pdf.expect("an emitter's direction has a density") as f64;
                    assert!(
                        (logged - density).abs() <= 1e-3 * density,
                        "{what}: density {logged}, sampling {object} gives {density}"
                    );
                }
                LightId::Sky => panic!("{what}: the scene has no sky image"),
            }
        }
    }
    assert_eq!(
        picked.into_iter().collect::<Vec<_>>(),
        ids,
        "of {shadow_rays} shadow rays, some light was never picked"
    );
}
