//! glTF and GLB meshes through the scene: node hierarchies against the
//! same OBJ, embedded, external and binary buffers, the PBR material rule,
//! non-indexed primitives, sparse accessors, the warnings for extensions and
//! textures, and glTF 1.0 named.

use super::*;
use glam::{DMat3, DMat4, DQuat};

// The tetrahedron of tests/models/make_models.py, as written there.
const TETRA_POSITIONS: [[f32; 3]; 4] = [[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]];
const TETRA_NORMALS: [[f32; 3]; 4] = [
    [-0.57735026, -0.57735026, -0.57735026],
    [1., 0., 0.],
    [0., 1., 0.],
    [0., 0., 1.],
];
const TETRA_TRIANGLES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
const TETRA_TRANSLATION: [f32; 3] = [1.0, 2.0, 3.0];
const TETRA_ROTATION: [f32; 4] = [0.0, 0.38268343, 0.0, 0.923_879_5];
const TETRA_SCALE: [f32; 3] = [2.0, 1.0, 0.5];

/// The tetrahedron's node transform (root T * R, child S), in f64.
fn node_matrix() -> DMat4 {
    let v = |a: [f32; 3]| DVec3::from_array(a.map(f64::from));
    let [x, y, z, w] = TETRA_ROTATION.map(f64::from);
    DMat4::from_translation(v(TETRA_TRANSLATION))
        * DMat4::from_quat(DQuat::from_xyzw(x, y, z, w))
        * DMat4::from_scale(v(TETRA_SCALE))
}

/// The tetrahedron placed by its nodes, as an OBJ with `v//vn` faces.
fn tetra_obj() -> String {
    let m = node_matrix();
    let n = DMat3::from_mat4(m).inverse().transpose();
    let mut text = String::new();
    for p in TETRA_POSITIONS {
        let p = m.transform_point3(DVec3::from_array(p.map(f64::from)));
        text.push_str(&format!("v {:?} {:?} {:?}\n", p.x, p.y, p.z));
    }
    for normal in TETRA_NORMALS {
        let v = n * DVec3::from_array(normal.map(f64::from));
        text.push_str(&format!("vn {:?} {:?} {:?}\n", v.x, v.y, v.z));
    }
    for t in TETRA_TRIANGLES {
        let [a, b, c] = t.map(|i| i + 1);
        text.push_str(&format!("f {a}//{a} {b}//{b} {c}//{c}\n"));
    }
    text
}

/// The mesh triangles of a scene whose one mesh entry is `name` in `dir`,
/// with `keys` added.
fn mesh_triangles(dir: &TempDir, name: &str, keys: &[(&str, &str)]) -> Scene {
    let path = format!("\"{name}\"");
    let mut all = vec![("path", path.as_str())];
    all.extend_from_slice(keys);
    let (scene, _) = scene_with_mesh(dir, &all);
    load_ok(&scene)
}

const ENTRY: [(&str, &str); 4] = [
    ("material", "\"red\""),
    ("scale", "1.5"),
    ("rotate", "[10, 20, 30]"),
    ("translate", "[0.5, 0, -1]"),
];

#[test]
fn obj_and_glb_under_a_node_hierarchy_give_the_same_triangles_and_normals() {
    let dir = TempDir::new("glb-vs-obj");
    copy_model(&dir, "tetra.glb");
    dir.write("tetra.obj", &tetra_obj());
    let from_glb = mesh_triangles(&dir, "tetra.glb", &ENTRY);
    let from_obj = mesh_triangles(&dir, "tetra.obj", &ENTRY);
    // triangles[0] is the base scene's own triangle.
    assert_eq!(from_glb.triangles.len(), 1 + 4);
    assert_eq!(from_obj.triangles.len(), 1 + 4);
    for (g, o) in from_glb.triangles[1..].iter().zip(&from_obj.triangles[1..]) {
        for k in 0..3 {
            // glTF positions and node transforms are f32.
            let d = (g.vertices[k] - o.vertices[k]).abs().max_element();
            assert!(d < 1e-5, "{:?} vs {:?}", g.vertices, o.vertices);
            let (gn, on) = (
                from_glb.normals_of(g).unwrap()[k],
                from_obj.normals_of(o).unwrap()[k],
            );
            assert!((gn - on).abs().max_element() < 1e-5, "{gn} vs {on}");
            assert!((gn.length() - 1.0).abs() < 1e-12);
        }
        assert_eq!(g.material, o.material);
    }
    // The transforms really moved it: the node translation alone is 1..3 away.
    let centre = from_glb.triangles[1..]
        .iter()
        .flat_map(|t| t.vertices)
        .sum::<DVec3>()
        / 12.0;
    assert!(centre.length() > 2.0, "{centre}");
}

#[test]
fn embedded_external_and_binary_buffers_give_one_mesh() {
    let dir = TempDir::new("buffers");
    for name in [
        "tetra.glb",
        "tetra_embedded.gltf",
        "tetra_external.gltf",
        "tetra.bin",
    ] {
        copy_model(&dir, name);
    }
    let glb = mesh_triangles(&dir, "tetra.glb", &ENTRY);
    assert_eq!(mesh_triangles(&dir, "tetra_embedded.gltf", &ENTRY), glb);
    assert_eq!(mesh_triangles(&dir, "tetra_external.gltf", &ENTRY), glb);
    // The loader reports the buffer file among the files it read.
    let (scene, _) = scene_with_mesh(&dir, &[("path", "\"tetra_external.gltf\"")]);
    let mut read = Vec::new();
    kdray_core::scene::load_scene_observed(&scene, &mut |p| read.push(p.to_path_buf())).unwrap();
    assert_eq!(
        read,
        [
            scene.clone(),
            dir.join("tetra_external.gltf"),
            dir.join("tetra.bin")
        ]
    );
}

#[test]
fn pbr_materials_follow_the_documented_rule() {
    let dir = TempDir::new("pbr");
    copy_model(&dir, "tetra.glb");
    copy_model(&dir, "plain.gltf");
    let scene = mesh_triangles(&dir, "tetra.glb", &[]);
    let gold = scene
        .materials
        .iter()
        .position(|m| m.name == "tetra.glb:gold")
        .unwrap();
    let m = &scene.materials[gold];
    // baseColorFactor (1, 0.75, 0.25), metallic 1, roughness 0.5.
    let base = DVec3::new(1.0, 0.75, 0.25);
    assert_eq!(m.diffuse, base);
    assert_close(m.ambient, 0.1 * base);
    assert_eq!(m.specular, DVec3::splat(0.5));
    assert_eq!(m.reflection, 0.5, "metallic x (1 - roughness)");
    let alpha = 0.5f64 * 0.5;
    assert!((m.shininess - 4.0 * (2.0 / (alpha * alpha) - 2.0)).abs() < 1e-9);
    assert!(scene.triangles[1..]
        .iter()
        .all(|t| t.material == gold as u32));
    // No material: glTF's default (white, metallic 1, roughness 1) is a
    // rough white surface, not a mirror.
    let scene = mesh_triangles(&dir, "plain.gltf", &[]);
    let m = scene.materials.last().unwrap();
    assert_eq!(m.name, "plain.gltf:default");
    assert_eq!((m.diffuse, m.specular), (DVec3::ONE, DVec3::ZERO));
    assert_close(m.ambient, DVec3::splat(0.1));
    assert_eq!((m.shininess, m.reflection), (0.0, 0.0));
    // A `material` key replaces them all, and no glTF material is added.
    let scene = mesh_triangles(&dir, "tetra.glb", &[("material", "\"blue\"")]);
    assert_eq!(scene.materials.len(), 2);
    assert!(scene.triangles[1..]
        .iter()
        .all(|t| scene.materials[t.material as usize].name == "blue"));
}

#[test]
fn a_non_indexed_primitive_without_normals_is_flat() {
    let dir = TempDir::new("plain");
    copy_model(&dir, "plain.gltf");
    let scene = mesh_triangles(&dir, "plain.gltf", &[("material", "\"red\"")]);
    assert_eq!(scene.triangles.len(), 2);
    let node = node_matrix();
    let want = [0, 1, 2]
        .map(|i| node.transform_point3(DVec3::from_array(TETRA_POSITIONS[i].map(f64::from))));
    for (g, w) in scene.triangles[1].vertices.iter().zip(want) {
        assert!((*g - w).abs().max_element() < 1e-5, "{g} vs {w}");
    }
    assert_eq!(scene.normals_of(&scene.triangles[1]), None);
    // smooth = true: no vertex is shared, so every corner gets the face's normal.
    let scene = mesh_triangles(
        &dir,
        "plain.gltf",
        &[("material", "\"red\""), ("smooth", "true")],
    );
    let [a, b, c] = scene.triangles[1].vertices;
    let face = (b - a).cross(c - a).normalize();
    for n in scene.normals_of(&scene.triangles[1]).unwrap() {
        assert!((n - face).abs().max_element() < 1e-12, "{n} vs {face}");
    }
}

/// A model of tests/models read by the glTF reader alone.
fn read_model(
    name: &str,
    with_materials: bool,
) -> Result<kdray_core::scene::mesh::Mesh, SceneError> {
    let path = common::repo_path("tests/models").join(name);
    kdray_core::scene::gltf::load_gltf(&path, with_materials, &mut |_| {})
}

#[test]
fn a_sparse_accessor_moves_a_vertex_and_its_normal_as_the_dense_file_does() {
    let dir = TempDir::new("sparse");
    for name in ["sparse.gltf", "sparse_dense.gltf", "tetra_embedded.gltf"] {
        copy_model(&dir, name);
    }
    let sparse = mesh_triangles(&dir, "sparse.gltf", &ENTRY);
    assert_eq!(sparse, mesh_triangles(&dir, "sparse_dense.gltf", &ENTRY));
    // The sparse part changed something: the plain tetrahedron differs.
    assert_ne!(sparse, mesh_triangles(&dir, "tetra_embedded.gltf", &ENTRY));
    // In the file's own coordinates: vertex 3 is at (0, 0, 2) before the
    // node transforms, so it lies where the transforms take that point.
    let mesh = read_model("sparse.gltf", false).unwrap();
    let moved = node_matrix().transform_point3(DVec3::new(0.0, 0.0, 2.0));
    assert!(
        mesh.positions.iter().any(|p| (*p - moved).length() < 1e-6),
        "{:?}",
        mesh.positions
    );
}

#[test]
fn extensions_and_missing_images_each_get_one_warning() {
    let mesh = read_model("wild.gltf", true).unwrap();
    let shown: Vec<String> = mesh.warnings.iter().map(|w| w.to_string()).collect();
    assert_eq!(shown.len(), 2, "{shown:?}");
    for w in &mesh.warnings {
        assert!(w.file.ends_with("wild.gltf") && w.line.is_none(), "{w}");
    }
    // KHR_texture_transform is read; KHR_materials_sheen is not.
    assert!(
        shown[0].contains("KHR_materials_sheen") && !shown[0].contains("KHR_texture_transform"),
        "{}",
        shown[0]
    );
    // The base colour's image (the normal map's too) is missing, and
    // named once.
    for word in ["baseColorTexture", "wood.png", "factors"] {
        assert!(shown[1].contains(word), "{} lacks {word}", shown[1]);
    }
    assert!(mesh
        .materials
        .iter()
        .all(|m| m.texture.is_none() && !m.maps.any()));
    // With the scene's material instead, the textures do not matter.
    let mesh = read_model("wild.gltf", false).unwrap();
    assert_eq!(mesh.warnings.len(), 1, "{:?}", mesh.warnings);
    // A plain file has nothing to warn about.
    assert!(read_model("tetra_embedded.gltf", true)
        .unwrap()
        .warnings
        .is_empty());
}

#[test]
fn a_gltf_1_file_is_named_as_such() {
    for name in ["gltf1.gltf", "gltf1_no_asset.gltf"] {
        let e = read_model(name, true).unwrap_err();
        assert!(
            e.message
                .starts_with("glTF 1.0 is not supported; convert it to 2.0"),
            "{name}: {e}"
        );
        assert!(e.file.ends_with(name), "{e}");
    }
}
