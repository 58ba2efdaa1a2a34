//! glTF's `doubleSided` where it changes a path-traced picture: an emissive
//! triangle of a double-sided material emits from both sides, one of a
//! single-sided material from its front only. A horizontal emissive quad
//! above a grey floor, facing up: double-sided it lights the floor below
//! (and shows bright from below) as the same quad single-sided and turned
//! to face down does; single-sided and facing up, it leaves the floor dark.

use crate::common;

use common::{gpu, render, TempDir};
use kdray::gpu::Accel;
use kdray::scene::{load_scene, Scene};

const SIDE: u32 = 48;

/// The emissive quad (`double_sided`), made horizontal by the entry's
/// rotation about x (-90: its front up; 90: down) 1 above a grey floor,
/// seen from the side and below it; 64 paths a pixel, no other light.
fn scene(dir: &TempDir, double_sided: bool, rotate_x: i32) -> Scene {
    let material = format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1],"metallicFactor":0,"roughnessFactor":1}},
        "emissiveFactor":[1,1,1],"doubleSided":{double_sided}}}"#
    );
    let name = format!("quad_{double_sided}_{rotate_x}.gltf");
    common::textured::write_gltf_quad_attributes(&dir.path, &name, &material, &[], &[]);
    let text = format!(
        "[camera]\nposition = [0, -0.4, 5]\nlook_at = [0, -0.7, 0]\nvfov = 40\n\
         [render]\nwidth = {SIDE}\nheight = {SIDE}\nintegrator = \"path\"\nsamples = 64\nmax_depth = 3\n\
         background = [0, 0, 0]\ntone_map = \"clamp\"\n\
         [materials.floor]\ndiffuse = [0.8, 0.8, 0.8]\n\
         [[triangles]]\nvertices = [[-20, -1, -20], [20, -1, 20], [20, -1, -20]]\nmaterial = \"floor\"\n\
         [[triangles]]\nvertices = [[-20, -1, -20], [-20, -1, 20], [20, -1, 20]]\nmaterial = \"floor\"\n\
         [[meshes]]\npath = \"{name}\"\nrotate = [{rotate_x}, 0, 0]\n"
    );
    let path = dir.join("scene.toml");
    std::fs::write(&path, text).unwrap();
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The mean of the image's bytes (its floor and the quad's underside).
fn mean(rgb: &[u8]) -> f64 {
    rgb.iter().map(|&b| f64::from(b)).sum::<f64>() / rgb.len() as f64
}

#[test]
fn a_double_sided_emitter_lights_both_sides_and_a_single_sided_one_its_front() {
    let _ = gpu();
    let dir = TempDir::new("double-sided");
    let both = mean(&render(&scene(&dir, true, -90), Accel::Kdtree).rgb);
    let facing_down = mean(&render(&scene(&dir, false, 90), Accel::Kdtree).rgb);
    let facing_up = mean(&render(&scene(&dir, false, -90), Accel::Kdtree).rgb);
    assert!(
        (both - facing_down).abs() < 0.03 * facing_down,
        "double-sided facing up {both:.2}, single-sided facing down {facing_down:.2}"
    );
    assert!(
        facing_up < 0.2 * facing_down,
        "single-sided facing up {facing_up:.2} against facing down {facing_down:.2}"
    );
}
