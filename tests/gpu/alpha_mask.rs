//! glTF alphaMode MASK on the GPU: a black quad whose texture has a hole
//! in its middle stands between the camera and a wall, with a point light
//! between the camera and the quad. Through the hole the camera sees the
//! wall as it is without the quad (primary rays pass), lit (shadow rays
//! pass), in the Whitted integrator and the path tracer; beside the quad
//! the wall lies in the solid part's shadow. The same quad OPAQUE hides
//! the wall. The kernel's walks and brute force agree with the CPU
//! mirror's brute force, hit for hit, on random masked scenes.

use crate::common;

use common::masked::{checker_alphas, masked_scene};
use common::strategies::{direction, ray_for, scene, traversal_cost, tree_for, vec3};
use common::textured::{write_gltf_quad_attributes, write_gltf_quad_material};
use common::{compare, gpu, pixel, render, TempDir};
use kdray::geometry::{Primitives, Ray, T_INFINITY};
use kdray::gpu::{Accel, GpuScene, PreparedScene, RayQueries, RayQuery};
use kdray::kdtree::traverse::{any_hit_brute, closest_hit_brute};
use kdray::kdtree::Traversal;
use kdray::scene::{load_scene, Scene};
use kdray_core::reference::ReferenceTracer;
use proptest::prelude::*;

const SIDE: u32 = 64;

/// An 8 x 8 black texture, alpha 0 in its middle 4 x 4 texels (texture
/// coordinates 0.25 - 0.75: the quad's x, y in [-0.5, 0.5]), 255 elsewhere.
fn holed() -> image::RgbaImage {
    image::RgbaImage::from_fn(8, 8, |x, y| {
        let inside = (2..6).contains(&x) && (2..6).contains(&y);
        image::Rgba([0, 0, 0, if inside { 0 } else { 255 }])
    })
}

/// The camera at z = 3 facing a grey wall at z = -4 (two triangles), a
/// point light at (0, 0, 2); with `material` (glTF JSON), the quad at
/// z = 0 (x, y in [-1, 1]) textured by [`holed`]; `integrator` "whitted"
/// or "path". Through the hole the camera sees the wall within |x| < 1.17
/// (the light's footprint through it reaches 1.5); beside the quad (|x| >
/// 2.33) the wall up to |x| = 3 lies in the quad's shadow.
fn wall_scene(dir: &TempDir, material: Option<&str>, integrator: &str) -> Scene {
    wall_scene_with(dir, material, integrator, &[])
}

/// [`wall_scene`] with the quad's vertex attributes `attributes`.
fn wall_scene_with(
    dir: &TempDir,
    material: Option<&str>,
    integrator: &str,
    attributes: &[(&str, Vec<Vec<f32>>)],
) -> Scene {
    let mesh = match material {
        Some(m) => {
            write_gltf_quad_attributes(&dir.path, "quad.gltf", m, &[holed()], attributes);
            "[[meshes]]\npath = \"quad.gltf\"\n"
        }
        None => "",
    };
    // The path tracer's point light falls off with the squared distance
    // (6 to the wall); the Whitted integrator's does not.
    let power = if integrator == "path" { 60 } else { 2 };
    let text = format!(
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\nintegrator = \"{integrator}\"\nsamples = 4\nmax_depth = 3\n\
         background = [0, 0, 0]\n\
         [[lights]]\nposition = [0, 0, 2]\nambient = [0.05, 0.05, 0.05]\ndiffuse = [{power}, {power}, {power}]\nspecular = [0, 0, 0]\n\
         [materials.wall]\ndiffuse = [0.8, 0.8, 0.8]\nambient = [0.2, 0.2, 0.2]\n\
         [[triangles]]\nvertices = [[-20, -20, -4], [20, -20, -4], [20, 20, -4]]\nmaterial = \"wall\"\n\
         [[triangles]]\nvertices = [[-20, -20, -4], [20, 20, -4], [-20, 20, -4]]\nmaterial = \"wall\"\n\
         {mesh}"
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

const MASK: &str = r#"{"alphaMode":"MASK","pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0,"roughnessFactor":1}}"#;
const OPAQUE: &str = r#"{"pbrMetallicRoughness":{"baseColorTexture":{"index":0},"metallicFactor":0,"roughnessFactor":1}}"#;

/// The wall through the hole: the middle 11 x 11 pixels (|x| < 0.5 at the
/// quad is 9.2 pixels from the centre).
fn through_hole() -> impl Iterator<Item = (u32, u32)> {
    let c = SIDE / 2;
    (c - 5..c + 6).flat_map(move |r| (c - 5..c + 6).map(move |col| (r, col)))
}

/// Through the hole the masked scene shows the wall as the scene without
/// the quad does (within `levels`); the quad's solid part, and the OPAQUE
/// quad's middle, show something else than the wall; the wall beside the quad (columns 54, 55 of
/// the middle row: x = 2.6 - 2.8 on the wall) is in shadow.
fn assert_hole_shows_the_wall(integrator: &str, levels: u8) -> (Scene, Scene) {
    let _ = gpu();
    let dir = TempDir::new(&format!("alpha-mask-{integrator}"));
    let masked = wall_scene(&dir, Some(MASK), integrator);
    let bare = wall_scene(&dir, None, integrator);
    let (im, ib) = (render(&masked, Accel::Kdtree), render(&bare, Accel::Kdtree));
    for (r, c) in through_hole() {
        let (a, b) = (pixel(&im, r, c), pixel(&ib, r, c));
        let d = a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).max().unwrap();
        assert!(
            d <= levels,
            "{integrator}: pixel ({r}, {c}): {a:?} with the quad, {b:?} without"
        );
        assert!(b[0] > 40, "{integrator}: the wall is lit there: {b:?}");
    }
    let apart =
        |a: [u8; 3], b: [u8; 3]| a.iter().zip(&b).map(|(x, y)| x.abs_diff(*y)).max().unwrap() > 30;
    let (solid, wall) = (
        pixel(&im, SIDE / 2, SIDE / 2 + 14),
        pixel(&ib, SIDE / 2, SIDE / 2 + 14),
    );
    assert!(
        apart(solid, wall),
        "{integrator}: the quad's solid part {solid:?}, the wall {wall:?}"
    );
    for c in [54, 55] {
        let (a, b) = (pixel(&im, SIDE / 2, c), pixel(&ib, SIDE / 2, c));
        assert!(
            a[0] + 20 < b[0],
            "{integrator}: column {c} shadowed {a:?}, unshadowed {b:?}"
        );
    }
    let opaque = render(&wall_scene(&dir, Some(OPAQUE), integrator), Accel::Kdtree);
    let (centre, wall) = (
        pixel(&opaque, SIDE / 2, SIDE / 2),
        pixel(&ib, SIDE / 2, SIDE / 2),
    );
    assert!(
        apart(centre, wall),
        "{integrator}: the OPAQUE quad {centre:?} hides the wall {wall:?}"
    );
    (masked, bare)
}

#[test]
fn a_masked_quad_shows_and_lights_the_wall_through_its_hole_whitted() {
    let (masked, _) = assert_hole_shows_the_wall("whitted", 0);
    // Brute force and the CPU reference see the same holes.
    let kd = render(&masked, Accel::Kdtree);
    let brute = render(&masked, Accel::Brute);
    assert!(kd.rgb == brute.rgb, "the k-d walk and brute force differ");
    let reference = ReferenceTracer::new(&masked, true).image();
    let d = compare(&kd.rgb, &reference, SIDE, SIDE, 1);
    assert_eq!(d.pixels_over, 0, "GPU against the CPU reference: {d:?}");
}

#[test]
fn a_masked_quad_shows_and_lights_the_wall_through_its_hole_path_traced() {
    // Through the hole what differs is the paths that bounce off the
    // quad's black (only glossy) back: noise of a few levels.
    assert_hole_shows_the_wall("path", 3);
}

/// `COLOR_0`'s alpha multiplies the texture's: at 0.3 on every corner the
/// masked quad (cutoff 0.5) is a hole everywhere, and the scene looks as it
/// does without it (on the GPU and in the CPU reference); at 1 it is the
/// masked quad.
#[test]
fn vertex_colour_alpha_multiplies_the_mask() {
    let _ = gpu();
    let dir = TempDir::new("alpha-colour");
    let colour = |a: f32| vec![("COLOR_0", vec![vec![1.0, 1.0, 1.0, a]; 4])];
    let faint_scene = wall_scene_with(&dir, Some(MASK), "whitted", &colour(0.3));
    let faint = render(&faint_scene, Accel::Kdtree);
    // The CPU mirror cuts the same holes.
    let reference = ReferenceTracer::new(&faint_scene, true).image();
    let d = compare(&faint.rgb, &reference, SIDE, SIDE, 1);
    assert_eq!(d.pixels_over, 0, "GPU against the CPU reference: {d:?}");
    let whole = render(
        &wall_scene_with(&dir, Some(MASK), "whitted", &colour(1.0)),
        Accel::Kdtree,
    );
    let masked = render(&wall_scene(&dir, Some(MASK), "whitted"), Accel::Kdtree);
    let bare = render(&wall_scene(&dir, None, "whitted"), Accel::Kdtree);
    assert!(
        faint.rgb == bare.rgb,
        "alpha 0.3 left something of the quad"
    );
    assert!(whole.rgb == masked.rgb, "alpha 1 changed the masked quad");
    assert!(masked.rgb != bare.rgb);
}

/// BLEND in the path tracer: a black quad of alpha 0.25 before a wall
/// that emits 1 (a black sky, no lights, no glossy part) lets 3 of 4
/// camera paths through. The mean radiance over the middle 20 x 20 pixels
/// (64 paths each, decoded from the clamped sRGB bytes) is 0.75 within
/// 0.02: five standard deviations of that mean, plus the bytes' rounding.
#[test]
fn a_blended_quad_passes_paths_at_one_minus_its_alpha() {
    let _ = gpu();
    let dir = TempDir::new("alpha-blend-rate");
    let blend = r#"{"alphaMode":"BLEND","pbrMetallicRoughness":{"baseColorFactor":[0,0,0,0.25],
        "baseColorTexture":{"index":0},"metallicFactor":0,"roughnessFactor":1}}"#;
    let white = image::RgbaImage::from_pixel(1, 1, image::Rgba([255, 255, 255, 255]));
    write_gltf_quad_material(&dir.path, "quad.gltf", blend, &[white], None);
    let text = format!(
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\nintegrator = \"path\"\nsamples = 64\nmax_depth = 2\n\
         background = [0, 0, 0]\ntone_map = \"clamp\"\n\
         [materials.wall]\ndiffuse = [0, 0, 0]\nemission = [1, 1, 1]\n\
         [[triangles]]\nvertices = [[-20, -20, -4], [20, -20, -4], [20, 20, -4]]\nmaterial = \"wall\"\n\
         [[triangles]]\nvertices = [[-20, -20, -4], [20, 20, -4], [-20, 20, -4]]\nmaterial = \"wall\"\n\
         [[meshes]]\npath = \"quad.gltf\"\n"
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let image = render(&scene, Accel::Kdtree);
    let decode = |byte: u8| {
        let c = byte as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let c = SIDE / 2;
    let (mut sum, mut n) = (0.0, 0.0);
    for r in c - 10..c + 10 {
        for col in c - 10..c + 10 {
            sum += decode(pixel(&image, r, col)[1]);
            n += 1.0;
        }
    }
    let mean = sum / n;
    assert!(
        (mean - 0.75).abs() < 0.02,
        "mean radiance {mean}, expected 0.75"
    );
    // Beside the quad the wall shows whole.
    assert_eq!(pixel(&image, 1, 1), [255, 255, 255]);
}

fn queries() -> &'static RayQueries {
    static QUERIES: std::sync::OnceLock<RayQueries> = std::sync::OnceLock::new();
    QUERIES.get_or_init(|| RayQueries::new(gpu()).unwrap_or_else(|e| panic!("{e}")))
}

proptest! {
    #![proptest_config(common::proptest_config(12))]

    /// Every walk of the kernel, and its brute-force loop, against the CPU
    /// mirror's brute force on scenes whose odd triangles are masked by a
    /// checker: a hit at the same t (within rounding), and the
    /// same any-hit answers on segments.
    #[test]
    fn gpu_walks_on_masked_scenes_match_the_cpu_brute_force(
        prims in scene(),
        cost in traversal_cost(),
        uv_scale in 0.5f64..6.0,
        rays in prop::collection::vec((vec3(14.0), direction(), prop::option::of(any::<usize>()), 0.01f32..30.0), 1..64),
    ) {
        let scene = masked_scene(&prims, &checker_alphas(), uv_scale, "whitted");
        let cpu = Primitives::from_scene(&scene);
        let tree = tree_for(&cpu, cost);
        let mut queries_of = Vec::new();
        for (origin, dir, on_plane, length) in rays {
            let ray: Ray = ray_for(&tree, origin, dir, on_plane);
            let first = closest_hit_brute(&cpu, &ray, T_INFINITY);
            queries_of.push((RayQuery { ray, t_limit: T_INFINITY, any_hit: false }, first.map(|h| (h.object, h.t))));
            if !first.is_some_and(|h| (h.t - length).abs() <= 1e-4 * length.max(1.0)) {
                let blocked = any_hit_brute(&cpu, &ray, length);
                queries_of.push((RayQuery { ray, t_limit: length, any_hit: true }, blocked.then_some((u32::MAX, 0.0))));
            }
        }
        let rays: Vec<RayQuery> = queries_of.iter().map(|(q, _)| *q).collect();
        let uploaded = GpuScene::upload(gpu(), PreparedScene::with_tree(scene, tree))
            .unwrap_or_else(|e| panic!("{e}"));
        let (buffers, prepared) = (uploaded.buffers(), uploaded.prepared());
        let walks = [(Accel::Brute, Traversal::Restart)]
            .into_iter()
            .chain(Traversal::ALL.map(|t| (Accel::Kdtree, t)));
        for (accel, walk) in walks {
            let hits = queries()
                .trace_counted(gpu(), buffers, &prepared.arrays.scene_ids, accel, walk, &rays)
                .unwrap_or_else(|e| panic!("{e}"));
            for ((hit, _), (q, expected)) in hits.iter().zip(&queries_of) {
                match (hit, expected) {
                    (None, None) => {}
                    (Some(_), Some(_)) if q.any_hit => {}
                    // Another object only at a tie (coincident copies).
                    (Some(h), Some((object, t))) => prop_assert!(
                        (h.t - t).abs() <= 1e-4 * t.max(1.0),
                        "{:?} {}: GPU {:?}, CPU {:?} {:?}", accel, walk, h, (object, t), q
                    ),
                    (h, e) => prop_assert!(false, "{:?} {}: GPU {:?}, CPU {:?} {:?}", accel, walk, h, e, q),
                }
            }
        }
    }
}
