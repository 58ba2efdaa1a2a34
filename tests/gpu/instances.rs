//! Instanced scenes on the GPU: the kernels trace the instances
//! flattened, so a scene written with `[shapes.NAME]` and `[[instances]]`
//! renders as the same scene written with `[[meshes]]`, with both
//! integrators; and the forest generator (scripts/make_forest.py) writes a
//! scene, and a glTF file of `EXT_mesh_gpu_instancing`, that load and
//! render.

use crate::common::*;
use kdray::gpu::Accel;
use kdray::scene::load_scene;

/// The torus placed mirrored and non-uniformly scaled with its file's
/// materials, and turned with `red`: as instances, or as meshes.
fn torus_scene(dir: &TempDir, instanced: bool, integrator: &str) -> kdray::scene::Scene {
    let torus = repo_path("scenes/models/torus.obj");
    let torus = torus.display();
    let placements = [
        "scale = [1, -2, 0.5]\nrotate = [10, 20, 30]\ntranslate = [1, 0.5, -1]\n",
        "scale = 0.5\nrotate = [0, 90, 0]\nmaterial = \"red\"\n",
    ];
    let mut text = format!(
        "[render]\nwidth = 64\nheight = 48\nintegrator = \"{integrator}\"\nsamples = 4\n\
         [camera]\nposition = [0, 2, 8]\nlook_at = [0, 0, 0]\n\
         [[lights]]\nposition = [4, 6, 5]\n\
         [materials.red]\ndiffuse = [0.7, 0.1, 0.1]\nemission = [0.5, 0.5, 0.5]\n"
    );
    if instanced {
        text.push_str(&format!(
            "[shapes.torus]\npath = \"{torus}\"\nsmooth = true\n"
        ));
    }
    for p in placements {
        match instanced {
            true => text.push_str(&format!("[[instances]]\nshape = \"torus\"\n{p}")),
            false => text.push_str(&format!(
                "[[meshes]]\npath = \"{torus}\"\nsmooth = true\n{p}"
            )),
        }
    }
    let path = dir.write(&format!("{instanced}-{integrator}.toml"), &text);
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn an_instanced_scene_renders_as_the_same_scene_with_placed_meshes() {
    let dir = TempDir::new("gpu-instances");
    for integrator in ["whitted", "path"] {
        let instanced = torus_scene(&dir, true, integrator);
        assert_eq!(instanced.instances.len(), 2);
        let placed = torus_scene(&dir, false, integrator);
        let a = render(&instanced, Accel::Kdtree);
        let b = render(&placed, Accel::Kdtree);
        assert!(a.rgb == b.rgb, "{integrator}: the images differ");
        let background = &a.rgb[..3];
        let drawn = a.rgb.chunks(3).filter(|p| *p != background).count();
        assert!(
            drawn > 50,
            "{integrator}: only {drawn} pixels show the tori"
        );
    }
}

#[test]
fn the_forest_generator_writes_a_scene_that_loads_and_renders() {
    let dir = TempDir::new("gpu-forest");
    let out = dir.join("forest.toml");
    let torus = repo_path("scenes/models/torus.obj");
    let status = std::process::Command::new("python3")
        .arg(repo_path("scripts/make_forest.py"))
        .args(["--count", "6", "--lift", "0.4", "--mesh"])
        .arg(&torus)
        .arg("-o")
        .arg(&out)
        .status()
        .expect("python3 runs");
    assert!(status.success());
    let mut scene = load_scene(&out).unwrap_or_else(|e| panic!("{e}"));
    // The ground, then the six.
    assert_eq!(scene.instances.len(), 7);
    assert_eq!(scene.shapes.len(), 2);
    let mirrored = scene
        .instances
        .iter()
        .filter(|i| i.transform.matrix3.determinant() < 0.0)
        .count();
    assert!(mirrored < 6);
    (scene.render.width, scene.render.height) = (64, 36);
    let image = render(&scene, Accel::Kdtree);
    let first = &image.rgb[..3];
    assert!(image.rgb.chunks(3).any(|p| p != first), "a blank image");

    // As one glTF file: the mesh by one node's EXT_mesh_gpu_instancing.
    let glb = dir.join("forest.glb");
    let status = std::process::Command::new("python3")
        .arg(repo_path("scripts/make_forest.py"))
        .args(["--count", "6", "--lift", "0.4", "--mesh"])
        .arg(&torus)
        .arg("-o")
        .arg(&glb)
        .status()
        .expect("python3 runs");
    assert!(status.success());
    let mut model = kdray::scene::model_scene(&glb).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        model.instances.len(),
        6,
        "the six copies; the ground is placed"
    );
    assert_eq!(model.shapes.len(), 1);
    (model.render.width, model.render.height) = (64, 36);
    let image = render(&model, Accel::Kdtree);
    let first = &image.rgb[..3];
    assert!(image.rgb.chunks(3).any(|p| p != first), "a blank image");
}
