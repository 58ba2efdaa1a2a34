//! Numbers: NaN, infinity and out-of-range values are errors anywhere;
//! integers, exponents and signs are numbers.

use super::*;

/// (key set, value with `X` for the bad number, key reported).
const NUMBER_SITES: &[(&str, &str, &str)] = &[
    ("camera.position", "[0, X, 1]", "camera.position[1]"),
    ("camera.look_at", "[X, 0, 0]", "camera.look_at[0]"),
    ("camera.up", "[0, 1, X]", "camera.up[2]"),
    ("camera.vfov", "X", "camera.vfov"),
    ("render.min_intensity", "X", "render.min_intensity"),
    ("render.background", "[0, X, 0]", "render.background[1]"),
    ("lights[0].position", "[X, 5, 5]", "lights[0].position[0]"),
    ("lights[0].ambient", "[1, 1, X]", "lights[0].ambient[2]"),
    ("lights[0].diffuse", "[1, X, 1]", "lights[0].diffuse[1]"),
    ("lights[0].specular", "[X, 1, 1]", "lights[0].specular[0]"),
    (
        "materials.red.ambient",
        "[X, 0, 0]",
        "materials.red.ambient[0]",
    ),
    (
        "materials.red.diffuse",
        "[0, X, 0]",
        "materials.red.diffuse[1]",
    ),
    (
        "materials.red.specular",
        "[0, 0, X]",
        "materials.red.specular[2]",
    ),
    ("materials.red.shininess", "X", "materials.red.shininess"),
    ("materials.red.reflection", "X", "materials.red.reflection"),
    ("spheres[0].center", "[0, 0, X]", "spheres[0].center[2]"),
    ("spheres[0].radius", "X", "spheres[0].radius"),
    (
        "triangles[0].vertices",
        "[[0, 0, -2], [1, X, -2], [0, 1, -2]]",
        "triangles[0].vertices[1][1]",
    ),
    ("meshes[0].scale", "X", "meshes[0].scale"),
    ("meshes[0].scale", "[1, X, 1]", "meshes[0].scale[1]"),
    ("meshes[0].rotate", "[X, 0, 0]", "meshes[0].rotate[0]"),
    ("meshes[0].translate", "[0, 0, X]", "meshes[0].translate[2]"),
];

#[test]
fn nan_and_inf_are_errors_anywhere_in_toml() {
    for &(set, value, key) in NUMBER_SITES {
        for bad in [
            "nan", "+nan", "-nan", "inf", "+inf", "-inf", "1e999", "-1e999",
        ] {
            let text = with_mesh().set(set, &value.replace('X', bad)).toml();
            assert_rejected_text(&text, key, &["finite"]);
        }
    }
}

#[test]
fn out_of_range_numbers_are_errors_anywhere_in_json() {
    // JSON has no NaN or infinity; a number too large for f64 is how one
    // would try, and serde_json rejects it.
    for &(set, value, key) in NUMBER_SITES {
        for bad in ["1e999", "-1e999", "1.5e400"] {
            let text = with_mesh().set(set, &value.replace('X', bad)).json();
            assert_rejected_text(&text, key, &["out of range", "finite"]);
        }
    }
}

#[test]
fn integers_are_accepted_wherever_a_number_is_expected() {
    let ints = base()
        .set("camera.position", "[0, 0, 4]")
        .set("camera.up", "[0, 2, 0]")
        .set("camera.vfov", "90")
        .set("render.min_intensity", "1")
        .set("render.background", "[0, 0, 1]")
        .set("lights[0].ambient", "[0, 0, 0]")
        .set("lights[0].diffuse", "[1, 1, 1]")
        .set("lights[0].specular", "[2, 2, 2]")
        .set("materials.red.diffuse", "[1, 0, 0]")
        .set("materials.red.specular", "[1, 1, 1]")
        .set("materials.red.shininess", "100")
        .set("materials.red.reflection", "1")
        .set("spheres[0].center", "[0, 0, -3]")
        .set("spheres[0].radius", "2");
    let floats = base()
        .set("camera.position", "[0.0, 0.0, 4.0]")
        .set("camera.up", "[0.0, 2.0, 0.0]")
        .set("camera.vfov", "90.0")
        .set("render.min_intensity", "1.0")
        .set("render.background", "[0.0, 0.0, 1.0]")
        .set("lights[0].ambient", "[0.0, 0.0, 0.0]")
        .set("lights[0].diffuse", "[1.0, 1.0, 1.0]")
        .set("lights[0].specular", "[2.0, 2.0, 2.0]")
        .set("materials.red.diffuse", "[1.0, 0.0, 0.0]")
        .set("materials.red.specular", "[1.0, 1.0, 1.0]")
        .set("materials.red.shininess", "100.0")
        .set("materials.red.reflection", "1.0")
        .set("spheres[0].center", "[0.0, 0.0, -3.0]")
        .set("spheres[0].radius", "2.0");
    let scene = assert_accepted(&ints);
    assert_eq!(scene, assert_accepted(&floats));
    assert_eq!(scene.camera.vfov_degrees, 90.0);
    assert_eq!(scene.spheres[0].radius, 2.0);
    assert_eq!(scene.lights[0].specular, DVec3::splat(2.0));
}

#[test]
fn exponents_and_signs_are_numbers() {
    let doc = base()
        .set("spheres[0].radius", "5e-1")
        .set("spheres[0].center", "[-0.0, 1E1, -1.25e+2]");
    let scene = assert_accepted(&doc);
    assert_eq!(scene.spheres[0].radius, 0.5);
    assert_eq!(scene.spheres[0].center, DVec3::new(0.0, 10.0, -125.0));
}
