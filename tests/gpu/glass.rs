//! Glass: materials' `transmission` and `ior` read from scene files, MTL and
//! glTF; Snell's law, the exact dielectric Fresnel reflectance and total
//! internal reflection (CPU reference and GPU kernel); a clear ball of index
//! 1 is invisible; a slab shifts a ray by the analytic amount.

use crate::common;

use std::path::Path;

use common::*;
use glam::Vec3;
use kdray::geometry::Ray;
use kdray::gpu::Accel;
use kdray::scene::{load_scene_with, parse_scene, SceneFormat};
use kdray_core::reference::{refract_fresnel, ReferenceTracer, WhittedStep};

// ---- the scene format --------------------------------------------------

#[test]
fn transmission_defaults_to_0_and_ior_to_1_5() {
    let scene = scene_from_toml(&seed_like(""));
    let m = &scene.materials[0];
    assert_eq!((m.transmission, m.ior), (0.0, 1.5));
    let scene = scene_from_toml(&seed_like("transmission = 0.25\nior = 1.33"));
    let m = &scene.materials[0];
    assert_eq!((m.transmission, m.ior), (0.25, 1.33));
}

#[test]
fn transmission_outside_0_1_and_ior_not_above_0_are_refused_by_key() {
    for (line, key) in [
        ("transmission = 1.5", "materials.m.transmission"),
        ("transmission = -0.1", "materials.m.transmission"),
        ("ior = 0.0", "materials.m.ior"),
        ("ior = -1.5", "materials.m.ior"),
    ] {
        let err = parse_scene(&seed_like(line), Path::new("t.toml"), SceneFormat::Toml)
            .expect_err(line)
            .to_string();
        assert!(err.contains(key), "{line}: {err}");
    }
}

#[test]
fn written_scenes_read_back_their_glass() {
    let scene = scene_from_toml(&seed_like("transmission = 0.75\nior = 2.0"));
    let text = kdray::scene::scene_text(&scene, SceneFormat::Toml).unwrap();
    assert!(
        text.contains("transmission") && text.contains("ior"),
        "{text}"
    );
    assert_eq!(scene_from_toml(&text).materials, scene.materials);
    // Defaults are left out, so scenes without glass are written as before.
    let plain = scene_from_toml(&seed_like(""));
    let text = kdray::scene::scene_text(&plain, SceneFormat::Toml).unwrap();
    assert!(
        !text.contains("transmission") && !text.contains("ior"),
        "{text}"
    );
}

#[test]
fn mtl_d_tr_and_ni_give_transmission_and_ior() {
    let dir = tempdir("mtl");
    std::fs::write(
        dir.join("m.mtl"),
        "newmtl dissolve\nKd 1 1 1\nd 0.25\nNi 1.33\n\
         newmtl tr\nKd 1 1 1\nTr 0.6\nNi 0\n\
         newmtl halo\nKd 1 1 1\nd -halo 0.5\n\
         newmtl opaque\nKd 1 1 1\nd 1\n",
    )
    .unwrap();
    let mut obj = String::from("mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n");
    for name in ["dissolve", "tr", "halo", "opaque"] {
        obj += &format!("usemtl {name}\nf 1 2 3\n");
    }
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    let scene = scene_with_mesh(&dir, "m.obj");
    let glass = |name: &str| {
        let m = scene
            .materials
            .iter()
            .find(|m| m.name == format!("m.obj:{name}"))
            .unwrap();
        (m.transmission, m.ior)
    };
    assert_eq!(glass("dissolve"), (0.75, 1.33));
    assert_eq!(glass("tr"), (0.6, 1.5)); // Ni 0: the default index
    assert_eq!(glass("halo"), (0.5, 1.5));
    assert_eq!(glass("opaque"), (0.0, 1.5));
}

#[test]
fn gltf_transmission_and_ior_extensions_are_read_without_a_warning() {
    let dir = tempdir("gltf");
    let mut json: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(repo_path("tests/models/plain.gltf")).unwrap(),
    )
    .unwrap();
    json["extensionsUsed"] = serde_json::json!(["KHR_materials_transmission", "KHR_materials_ior"]);
    json["materials"] = serde_json::json!([{
        "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0},
        "extensions": {
            "KHR_materials_transmission": {"transmissionFactor": 0.8},
            "KHR_materials_ior": {"ior": 1.33}
        }
    }]);
    json["meshes"][0]["primitives"][0]["material"] = serde_json::json!(0);
    std::fs::write(dir.join("glass.gltf"), json.to_string()).unwrap();
    let mut warnings = Vec::new();
    let scene_path = dir.join("scene.toml");
    std::fs::write(&scene_path, scene_text_with_mesh("glass.gltf")).unwrap();
    let scene = load_scene_with(&scene_path, &mut |_| {}, &mut |w| {
        warnings.push(w.to_string())
    })
    .unwrap_or_else(|e| panic!("{e}"));
    let m = scene.materials.last().unwrap();
    assert_eq!((m.transmission, m.ior), (0.8f32 as f64, 1.33f32 as f64));
    assert!(
        warnings.iter().all(|w| !w.contains("KHR_materials")),
        "{warnings:?}"
    );
}

// ---- Fresnel, Snell, total internal reflection -------------------------

#[test]
fn fresnel_reflectance_at_normal_incidence_is_4_percent_for_ior_1_5() {
    let n = Vec3::Z;
    let r = refract_fresnel(-Vec3::Z, n, 1.0, 1.5);
    assert!((r.fresnel - 0.04).abs() < 1e-6, "{}", r.fresnel);
    assert!((r.dir - -Vec3::Z).length() < 1e-6, "{:?}", r.dir);
    // Leaving the glass, the same.
    let r = refract_fresnel(-Vec3::Z, n, 1.5, 1.0);
    assert!((r.fresnel - 0.04).abs() < 1e-6, "{}", r.fresnel);
}

#[test]
fn refraction_follows_snells_law_and_equal_indices_change_nothing() {
    let n = Vec3::Y;
    for degrees in [10.0f32, 30.0, 60.0, 85.0] {
        let a = degrees.to_radians();
        let d = Vec3::new(a.sin(), -a.cos(), 0.0);
        let r = refract_fresnel(d, n, 1.0, 1.5);
        let sin_t = r.dir.x;
        assert!(
            (a.sin() - 1.5 * sin_t).abs() < 1e-6,
            "{degrees}: {:?}",
            r.dir
        );
        assert!(r.dir.y < 0.0 && r.fresnel > 0.0 && r.fresnel < 1.0);
        assert_eq!(refract_fresnel(d, n, 1.3, 1.3).dir, d);
        assert_eq!(refract_fresnel(d, n, 1.3, 1.3).fresnel, 0.0);
    }
}

#[test]
fn total_internal_reflection_past_the_critical_angle() {
    let critical = (1.0f32 / 1.5).asin();
    let n = Vec3::Y;
    let at = |a: f32| refract_fresnel(Vec3::new(a.sin(), -a.cos(), 0.0), n, 1.5, 1.0);
    assert_eq!(at(critical + 1e-3).fresnel, 1.0);
    assert_eq!(at(1.2).fresnel, 1.0);
    let below = at(critical - 1e-3);
    assert!(
        below.fresnel < 1.0 && below.fresnel > 0.5,
        "{}",
        below.fresnel
    );
    assert!(at(0.3).fresnel < 0.1);
    // From outside there is no critical angle.
    let outside = refract_fresnel(Vec3::new(1.2f32.sin(), -1.2f32.cos(), 0.0), n, 1.0, 1.5);
    assert!(outside.fresnel < 1.0);
}

/// A right-angle prism of glass: a ray entering a leg face head on meets
/// the hypotenuse at 45 degrees, past glass's critical angle (41.8), is
/// reflected whole and leaves through the other leg, turned 90 degrees.
#[test]
fn a_prism_reflects_totally_at_its_hypotenuse() {
    // Legs on x = 0 and z = 0, hypotenuse x + z = 1, from y = -1 to 1.
    let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
        format!("[[triangles]]\nvertices = [{a:?}, {b:?}, {c:?}]\nmaterial = \"glass\"\n")
    };
    let (p0, p1, p2) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]);
    let up = |p: [f32; 3], y: f32| [p[0], y, p[2]];
    let mut text = String::from(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 30\n\
         [render]\nwidth = 8\nheight = 8\nmin_intensity = 0.0\nmax_depth = 8\n\
         [[lights]]\nposition = [0, 10, 0]\n\
         [materials.glass]\ndiffuse = [0, 0, 0]\ntransmission = 1.0\nior = 1.5\n",
    );
    for (a, b) in [(p0, p1), (p1, p2), (p2, p0)] {
        text += &tri(up(a, -1.0), up(b, -1.0), up(b, 1.0));
        text += &tri(up(a, -1.0), up(b, 1.0), up(a, 1.0));
    }
    text += &tri(up(p0, -1.0), up(p1, -1.0), up(p2, -1.0));
    text += &tri(up(p0, 1.0), up(p1, 1.0), up(p2, 1.0));
    let scene = scene_from_toml(&text);
    let tracer = ReferenceTracer::new(&scene, true);
    // Into the z = 0 leg, head on, at x = 0.3.
    let (_, steps) = tracer.whitted_steps(Ray {
        origin: Vec3::new(0.3, 0.0, -2.0),
        dir: Vec3::Z,
    });
    let inside: Vec<&WhittedStep> = steps.iter().filter(|s| s.ray.inside).collect();
    // The refracted ray, then the one reflected at the hypotenuse: all of
    // what entered (1 - F at normal incidence), none of it transmitted.
    assert!(inside.len() >= 2, "{steps:#?}");
    let (first, second) = (inside[0], inside[1]);
    assert!((first.ray.ray.dir - Vec3::Z).length() < 1e-5);
    assert!(
        (first.ray.weight - 0.96).abs() < 1e-5,
        "{}",
        first.ray.weight
    );
    assert!(
        (second.ray.ray.dir - -Vec3::X).length() < 1e-5,
        "{second:?}"
    );
    assert_eq!(second.ray.weight, first.ray.weight);
    // It then leaves through the x = 0 leg, head on.
    let out = steps
        .iter()
        .find(|s| !s.ray.inside && s.ray.hits == 3)
        .expect("a ray out of the x = 0 leg");
    assert!((out.ray.ray.dir - -Vec3::X).length() < 1e-5, "{out:?}");
    assert!(out.ray.ray.origin.x < 0.0);
}

/// A slab of thickness h shifts a ray entering at angle a sideways by
/// h sin(a - t) / cos(t), t the refracted angle, and the ray leaves
/// parallel to how it came.
#[test]
fn a_glass_slab_shifts_a_ray_sideways_by_the_analytic_amount() {
    let h = 1.0f32;
    let ior = 1.5f32;
    let scene = scene_from_toml(&format!(
        "[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nvfov = 30\n\
         [render]\nwidth = 8\nheight = 8\nmin_intensity = 0.0\nmax_depth = 8\n\
         [[lights]]\nposition = [0, 10, 0]\n\
         [materials.glass]\ndiffuse = [0, 0, 0]\ntransmission = 1.0\nior = {ior}\n{}",
        box_triangles([-50.0, -h, -50.0], [50.0, 0.0, 50.0], "glass")
    ));
    let tracer = ReferenceTracer::new(&scene, true);
    for degrees in [15.0f32, 30.0, 50.0] {
        let a = degrees.to_radians();
        let dir = Vec3::new(a.sin(), -a.cos(), 0.0);
        let origin = Vec3::new(0.0, 1.0, 0.3) - dir * (1.0 / a.cos());
        let (_, steps) = tracer.whitted_steps(Ray { origin, dir });
        let out = steps
            .iter()
            .find(|s| s.ray.hits == 2 && !s.ray.inside)
            .unwrap_or_else(|| panic!("{degrees}: no ray out of the slab: {steps:#?}"));
        let exit = out.ray.ray;
        assert!(
            (exit.dir - dir).length() < 1e-5,
            "{degrees}: {:?}",
            exit.dir
        );
        // Distance between the two parallel lines.
        let w = exit.origin - origin;
        let shift = (w - w.dot(dir) * dir).length();
        let t = (a.sin() / ior).asin();
        let expected = h * (a - t).sin() / t.cos();
        assert!(
            (shift - expected).abs() < 1e-3,
            "{degrees}: shift {shift}, expected {expected}"
        );
    }
}

// ---- images ------------------------------------------------------------

/// A clear ball of index 1 (transmission 1) bends, reflects and shades
/// nothing, and casts no shadow: the image is the scene's without it, on
/// the GPU and in the CPU reference.
#[test]
fn a_clear_sphere_of_index_1_is_invisible() {
    let without = scene_from_toml(&std::fs::read_to_string(repo_path("scenes/seed.toml")).unwrap());
    let without = shrunk(without);
    let with = {
        let mut text = std::fs::read_to_string(repo_path("scenes/seed.toml")).unwrap();
        text += "\n[materials.clear]\ndiffuse = [1, 1, 1]\nspecular = [1, 1, 1]\n\
                 shininess = 50\ntransmission = 1.0\nior = 1.0\n\
                 [[spheres]]\ncenter = [0.25, -0.1, -0.3]\nradius = 0.3\nmaterial = \"clear\"\n";
        shrunk(scene_from_toml(&text))
    };
    let a = render(&without, Accel::Kdtree);
    let b = render(&with, Accel::Kdtree);
    let d = compare(&a.rgb, &b.rgb, a.width, a.height, 0);
    assert_eq!(d.pixels_over, 0, "GPU: {d:?}");
    let a = ReferenceTracer::new(&without, true).image();
    let b = ReferenceTracer::new(&with, true).image();
    let d = compare(&a, &b, without.render.width, without.render.height, 0);
    assert_eq!(d.pixels_over, 0, "CPU reference: {d:?}");
}

/// Head on through a glass slab in front of a black wall, with a white
/// background: the light reflected back is the two faces' Fresnel
/// reflectance summed over every internal bounce, 2F / (1 + F) with
/// F = 0.04, on the GPU as in the formula.
#[test]
fn a_slab_seen_head_on_reflects_2f_over_1_plus_f() {
    let scene = scene_from_toml(&format!(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 10\n\
         [render]\nwidth = 9\nheight = 9\nmin_intensity = 0.0\nmax_depth = 32\n\
         background = [1, 1, 1]\nshadow_mode = \"ambient\"\n\
         [[lights]]\nposition = [0, 0, 100]\nambient = [0, 0, 0]\ndiffuse = [0, 0, 0]\nspecular = [0, 0, 0]\n\
         [materials.glass]\ndiffuse = [0, 0, 0]\ntransmission = 1.0\nior = 1.5\n\
         [materials.black]\ndiffuse = [0, 0, 0]\n{}{}",
        box_triangles([-20.0, -20.0, -1.0], [20.0, 20.0, 0.0], "glass"),
        box_triangles([-50.0, -50.0, -3.0], [50.0, 50.0, -2.5], "black"),
    ));
    let f = 0.04f64;
    let expected = quantize([2.0 * f / (1.0 + f); 3]);
    assert_eq!(expected, [20, 20, 20]);
    let image = render(&scene, Accel::Kdtree);
    assert_eq!(pixel(&image, 4, 4), expected);
    assert_eq!(ReferenceTracer::new(&scene, true).pixel(4, 4), expected);
}

/// A glass ball between a light and the floor: the floor behind it gets
/// the light times the ball's transmission squared (two surfaces), so a
/// clear ball casts no shadow and a transmission-0.5 ball a quarter-light
/// one.
#[test]
fn shadow_rays_through_glass_are_attenuated_by_each_surfaces_transmission() {
    let text = |transmission: f32| {
        format!(
            "[camera]\nposition = [0, 5, 0]\nlook_at = [0, 0, 0]\nup = [0, 0, -1]\nvfov = 2\n\
             [render]\nwidth = 3\nheight = 3\nshadow_mode = \"ambient\"\n\
             [[lights]]\nposition = [0, 10, 0]\nambient = [0, 0, 0]\ndiffuse = [1, 1, 1]\nspecular = [0, 0, 0]\n\
             [materials.floor]\ndiffuse = [0.8, 0.8, 0.8]\n\
             [materials.glass]\ndiffuse = [0, 0, 0]\ntransmission = {transmission}\n\
             [[triangles]]\nvertices = [[-10, 0, -10], [10, 0, -10], [0, 0, 10]]\nmaterial = \"floor\"\n\
             [[spheres]]\ncenter = [0, 7, 0]\nradius = 0.5\nmaterial = \"glass\"\n"
        )
    };
    // The camera sees the floor under the ball (the ball is behind it).
    for (transmission, expected) in [(1.0f32, 0.8f64), (0.5, 0.2), (0.0, 0.0)] {
        let scene = scene_from_toml(&text(transmission));
        let image = render(&scene, Accel::Kdtree);
        assert_eq!(
            pixel(&image, 1, 1),
            quantize([expected; 3]),
            "{transmission}"
        );
        assert_eq!(
            ReferenceTracer::new(&scene, true).pixel(1, 1),
            quantize([expected; 3]),
            "{transmission}"
        );
    }
}

// ---- helpers -----------------------------------------------------------

/// One material `m` with `extra` lines, one sphere, one light.
fn seed_like(extra: &str) -> String {
    format!(
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = 4\nheight = 4\n[[lights]]\nposition = [5, 5, 5]\n\
         [materials.m]\ndiffuse = [0.5, 0.5, 0.5]\n{extra}\n\
         [[spheres]]\ncenter = [0, 0, -1]\nradius = 0.5\nmaterial = \"m\"\n"
    )
}

fn scene_text_with_mesh(file: &str) -> String {
    format!(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nvfov = 60\n\
         [render]\nwidth = 4\nheight = 4\n[[lights]]\nposition = [5, 5, 5]\n\
         [[meshes]]\npath = \"{file}\"\n"
    )
}

fn scene_with_mesh(dir: &Path, file: &str) -> kdray::scene::Scene {
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene_text_with_mesh(file)).unwrap();
    load_scene_with(&path, &mut |_| {}, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"))
}

fn tempdir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("kdray-glass-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn shrunk(mut scene: kdray::scene::Scene) -> kdray::scene::Scene {
    scene.render.width = 96;
    scene.render.height = 54;
    scene
}

/// The 12 triangles of the box from `lo` to `hi`, as scene text.
fn box_triangles(lo: [f32; 3], hi: [f32; 3], material: &str) -> String {
    let corner = |i: usize| {
        [
            if i & 1 == 0 { lo[0] } else { hi[0] },
            if i & 2 == 0 { lo[1] } else { hi[1] },
            if i & 4 == 0 { lo[2] } else { hi[2] },
        ]
    };
    let faces = [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ];
    let mut text = String::new();
    for f in faces {
        for [a, b, c] in [[f[0], f[1], f[2]], [f[0], f[2], f[3]]] {
            text += &format!(
                "[[triangles]]\nvertices = [{:?}, {:?}, {:?}]\nmaterial = \"{material}\"\n",
                corner(a),
                corner(b),
                corner(c)
            );
        }
    }
    text
}
