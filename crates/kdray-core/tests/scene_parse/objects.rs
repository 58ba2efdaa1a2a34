//! Lights, materials, spheres and triangles: their defaults, their rules
//! (positive radius, triangles with an area, colours >= 0, reflection in
//! [0, 1]), and materials referred to by name.

use super::*;

#[test]
fn light_colours_default_to_one() {
    let scene = assert_accepted(&base());
    assert_eq!(
        scene.lights,
        vec![Light {
            position: DVec3::splat(5.0),
            ambient: DVec3::ONE,
            diffuse: DVec3::ONE,
            specular: DVec3::ONE,
            kind: LightKind::Point,
            reference_distance: None,
        }]
    );
    let doc = base()
        .set("lights[0].diffuse", "[0.5, 0.5, 0.5]")
        .set("lights[1].position", "[-5, 5, 5]")
        .set("lights[1].ambient", "[0, 0, 0]");
    let lights = assert_accepted(&doc).lights;
    assert_eq!(lights.len(), 2);
    assert_eq!(lights[0].diffuse, DVec3::splat(0.5));
    assert_eq!(lights[0].ambient, DVec3::ONE);
    assert_eq!(lights[1].position, DVec3::new(-5.0, 5.0, 5.0));
    assert_eq!(lights[1].ambient, DVec3::ZERO);
    assert_eq!(lights[1].specular, DVec3::ONE);
}

#[test]
fn material_defaults_and_values() {
    let doc = base()
        .set("materials.red.ambient", "[0.1, 0, 0]")
        .set("materials.red.specular", "[1, 1, 1]")
        .set("materials.red.shininess", "100.0")
        .set("materials.red.reflection", "0.5");
    let scene = assert_accepted(&doc);
    let find = |name: &str| {
        scene
            .materials
            .iter()
            .find(|m| m.name == name)
            .unwrap()
            .clone()
    };
    assert_eq!(
        find("red"),
        Material {
            name: "red".into(),
            ambient: DVec3::new(0.1, 0.0, 0.0),
            diffuse: DVec3::new(0.7, 0.0, 0.0),
            specular: DVec3::ONE,
            shininess: 100.0,
            reflection: 0.5,
            transmission: 0.0,
            ior: 1.5,
            texture: None,
            physical: kdray_core::scene::Physical::LAMBERTIAN,
            maps: kdray_core::scene::MaterialMaps::NONE,
            alpha: kdray_core::scene::Alpha::OPAQUE,
        }
    );
    assert_eq!(
        find("blue"),
        Material {
            name: "blue".into(),
            ambient: DVec3::ZERO,
            diffuse: DVec3::new(0.0, 0.0, 0.7),
            specular: DVec3::ZERO,
            shininess: 0.0,
            reflection: 0.0,
            transmission: 0.0,
            ior: 1.5,
            texture: None,
            physical: kdray_core::scene::Physical::LAMBERTIAN,
            maps: kdray_core::scene::MaterialMaps::NONE,
            alpha: kdray_core::scene::Alpha::OPAQUE,
        }
    );
    assert_eq!(scene.materials.len(), 2);
}

#[test]
fn objects_refer_to_materials_by_name() {
    let scene = assert_accepted(&two_spheres());
    let name = |index: u32| scene.materials[index as usize].name.as_str();
    assert_eq!(
        scene.spheres[0],
        Sphere {
            center: DVec3::new(0.0, 0.0, -1.0),
            radius: 0.5,
            material: scene.spheres[0].material,
        }
    );
    assert_eq!(name(scene.spheres[0].material), "red");
    assert_eq!(name(scene.spheres[1].material), "blue");
    assert_eq!(
        scene.triangles,
        vec![Triangle::flat(
            [
                DVec3::new(0.0, 0.0, -2.0),
                DVec3::new(1.0, 0.0, -2.0),
                DVec3::new(0.0, 1.0, -2.0)
            ],
            scene.triangles[0].material,
        )]
    );
    assert_eq!(name(scene.triangles[0].material), "blue");
    assert_eq!(scene.object_count(), 3);
}

#[test]
fn material_names_may_need_quoting() {
    // TOML needs `[materials."brushed steel"]`; the Doc writer does not
    // quote, so this one is written by hand.
    let toml =
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[[lights]]\nposition = [1, 1, 1]\n\
                [materials.\"brushed steel\"]\ndiffuse = [0.5, 0.5, 0.5]\n\
                [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"brushed steel\"\n";
    let scene = parse_ok(toml, SceneFormat::Toml);
    assert_eq!(scene.materials[0].name, "brushed steel");
    assert_eq!(scene.spheres[0].material, 0);
}

#[test]
fn unknown_materials_are_errors() {
    let cases = [
        two_spheres().set("spheres[1].material", "\"green\""),
        two_triangles().set("triangles[1].material", "\"green\""),
        with_mesh().set("meshes[0].material", "\"green\""),
    ];
    let keys = [
        "spheres[1].material",
        "triangles[1].material",
        "meshes[0].material",
    ];
    for (doc, key) in cases.iter().zip(keys) {
        assert_rejected(doc, key, &["unknown material", "\"green\"", "blue, red"]);
    }
    // Names are case-sensitive.
    let doc = two_spheres().set("spheres[1].material", "\"Red\"");
    assert_rejected(
        &doc,
        "spheres[1].material",
        &["unknown material", "\"Red\""],
    );
    // With no materials at all the message says so.
    let doc = base()
        .remove("materials")
        .remove("triangles")
        .set("spheres[0].material", "\"red\"");
    assert_rejected(&doc, "spheres[0].material", &["unknown material", "none"]);
}

#[test]
fn radius_must_be_positive() {
    for bad in ["0", "0.0", "-0.5", "-1e-300"] {
        let doc = two_spheres().set("spheres[1].radius", bad);
        assert_rejected(&doc, "spheres[1].radius", &["> 0"]);
    }
    let scene = assert_accepted(&two_spheres().set("spheres[1].radius", "1e-9"));
    assert_eq!(scene.spheres[1].radius, 1e-9);
}

#[test]
fn zero_area_triangles_are_errors() {
    for bad in [
        "[[0, 0, 0], [1, 1, 1], [2, 2, 2]]",           // collinear
        "[[0, 0, 0], [1, 0, 0], [1, 0, 0]]",           // a repeated vertex
        "[[3, 3, 3], [3, 3, 3], [3, 3, 3]]",           // a point
        "[[0, 0, 0], [1e-200, 0, 0], [0, 1e-200, 0]]", // too small for f64 to see any area
    ] {
        let doc = two_triangles().set("triangles[1].vertices", bad);
        assert_rejected(&doc, "triangles[1].vertices", &["zero area"]);
    }
    // Thin is not zero.
    assert_accepted(&two_triangles().set(
        "triangles[1].vertices",
        "[[0, 0, 0], [1, 0, 0], [2, 1e-9, 0]]",
    ));
}

#[test]
fn colours_must_not_be_negative() {
    let keys = [
        "lights[0].ambient",
        "lights[0].diffuse",
        "lights[0].specular",
        "materials.red.ambient",
        "materials.red.diffuse",
        "materials.red.specular",
        "render.background",
    ];
    for key in keys {
        let doc = base().set(key, "[0.5, -0.01, 0.5]");
        assert_rejected(&doc, key, &["colour", ">= 0"]);
    }
    // No upper limit: colours are linear and may exceed 1.
    let scene = assert_accepted(&base().set("lights[0].diffuse", "[4, 4, 4]"));
    assert_eq!(scene.lights[0].diffuse, DVec3::splat(4.0));
}

#[test]
fn reflection_must_be_in_0_1_and_shininess_non_negative() {
    for bad in ["-0.1", "1.5"] {
        let doc = base().set("materials.blue.reflection", bad);
        assert_rejected(&doc, "materials.blue.reflection", &["[0, 1]"]);
    }
    for good in ["0", "1", "0.25"] {
        assert_accepted(&base().set("materials.blue.reflection", good));
    }
    let doc = base().set("materials.blue.shininess", "-1");
    assert_rejected(&doc, "materials.blue.shininess", &[">= 0"]);
    assert_accepted(&base().set("materials.blue.shininess", "0"));
    assert_accepted(&base().set("materials.blue.shininess", "10000"));
}
