//! glTF instancing (tests/models/instanced.gltf): a mesh that several
//! nodes place, and a node's `EXT_mesh_gpu_instancing`, become one shape
//! and its instances, which flatten to the triangles the file's copies are
//! placed as one by one; a bad instancing accessor is an error.

use super::*;

/// A scene placing `path` by one `[[meshes]]` entry.
fn entry_scene(dir: &TempDir) -> PathBuf {
    let text = "[camera]\nposition = [0, 0, 20]\nlook_at = [0, 0, 0]\n\
        [[lights]]\nposition = [0, 10, 10]\n\
        [[meshes]]\npath = \"instanced.gltf\"\nscale = [1, 2, 1]\ntranslate = [0, 1, 0]\n";
    dir.write("entry.toml", text)
}

#[test]
fn a_gltf_mesh_placed_several_times_becomes_one_shape_and_its_instances() {
    let dir = TempDir::new("gltf-instances");
    copy_model(&dir, "instanced.gltf");
    let scene = load_ok(&entry_scene(&dir));
    // Mesh 0: two nodes and three copies of a third; mesh 1: one node.
    assert_eq!(scene.shapes.len(), 1);
    assert_eq!(scene.instances.len(), 5);
    assert_eq!(scene.triangles.len(), 4, "mesh 1 is placed as before");
    assert_eq!(
        scene.shapes[0].mesh.triangles.len(),
        4,
        "mesh 0 is read once"
    );
    let mirrored = scene
        .instances
        .iter()
        .filter(|i| i.transform.matrix3.determinant() < 0.0)
        .count();
    assert_eq!(mirrored, 2, "the mirrored node and the mirrored copy");

    // The same file as a shape is read copy by copy (a shape's copies are
    // placed into it), and placed by the entry's transform.
    let text = "[camera]\nposition = [0, 0, 20]\nlook_at = [0, 0, 0]\n\
        [[lights]]\nposition = [0, 10, 10]\n\
        [shapes.copies]\npath = \"instanced.gltf\"\n\
        [[instances]]\nshape = \"copies\"\nscale = [1, 2, 1]\ntranslate = [0, 1, 0]\n";
    let copies = load_ok(&dir.write("copies.toml", text));
    assert_eq!(copies.shapes[0].mesh.triangles.len(), 24);
    assert!(copies.shapes[0].mesh.instanced.is_empty());

    let instanced = scene.flattened();
    let copies = copies.flattened();
    assert_eq!(instanced.triangles.len(), 24);
    assert_eq!(copies.triangles.len(), 24);
    assert_eq!(instanced.materials, copies.materials);
    // The copies come in the walk's order, mesh 1's node last; the
    // instanced scene has mesh 1's triangles first, then the instances'.
    let reordered = instanced.triangles[4..]
        .iter()
        .chain(&instanced.triangles[..4]);
    for (a, b) in reordered.zip(&copies.triangles) {
        assert_eq!(a.material, b.material);
        for (p, q) in a.vertices.iter().zip(b.vertices) {
            assert!((*p - q).abs().max_element() < 1e-12, "{p} {q}");
        }
        let (na, nb) = (instanced.normals_of(a), copies.normals_of(b));
        assert_eq!(na.is_some(), nb.is_some());
        for (p, q) in na.into_iter().flatten().zip(nb.into_iter().flatten()) {
            assert!((p - q).abs().max_element() < 1e-12, "normal {p} {q}");
        }
    }
}

#[test]
fn a_model_opened_alone_keeps_its_instances_and_frames_them() {
    let dir = TempDir::new("gltf-instances-model");
    let path = copy_model(&dir, "instanced.gltf");
    let scene = kdray_core::scene::model_scene(&path).unwrap();
    assert_eq!(scene.instances.len(), 5);
    // The camera frames every copy: it sees the mesh-1 node at x = 5 and
    // the mirrored copy at x = -3 alike (the view is centred between).
    let centre = scene.camera.look_at;
    assert!(centre.x > -3.0 && centre.x < 5.0, "{centre}");
    let flat = scene.flattened();
    assert_eq!(flat.triangles.len(), 24 + 2, "the copies and the ground");
}

/// A change to a glTF document's JSON.
type Edit = Box<dyn Fn(&mut serde_json::Value)>;

/// instanced.gltf with `edit` applied to its JSON, written to `dir`.
fn edited(dir: &TempDir, edit: impl Fn(&mut serde_json::Value)) -> PathBuf {
    let text = std::fs::read_to_string(test_models_dir().join("instanced.gltf")).unwrap();
    let mut doc: serde_json::Value = serde_json::from_str(&text).unwrap();
    edit(&mut doc);
    dir.write("instanced.gltf", &doc.to_string())
}

#[test]
fn an_instancing_accessor_of_the_wrong_type_or_count_is_an_error() {
    let attributes = |doc: &mut serde_json::Value| -> serde_json::Value {
        doc["nodes"][3]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"].clone()
    };
    let cases: [(&str, Edit, &[&str]); 3] = [
        (
            "wrong type",
            Box::new(move |doc| {
                let mut a = attributes(doc);
                a["TRANSLATION"] = 4.into(); // the VEC4 rotations
                doc["nodes"][3]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = a;
            }),
            &[
                "node 3 EXT_mesh_gpu_instancing",
                "TRANSLATION",
                "Vec3",
                "Vec4",
            ],
        ),
        (
            "wrong count",
            Box::new(|doc| doc["accessors"][4]["count"] = 2.into()),
            &["node 3 EXT_mesh_gpu_instancing", "ROTATION has 2", "3"],
        ),
        (
            "no accessor",
            Box::new(move |doc| {
                let mut a = attributes(doc);
                a["SCALE"] = 99.into();
                doc["nodes"][3]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = a;
            }),
            &["SCALE", "no accessor 99"],
        ),
    ];
    for (what, edit, words) in cases {
        let dir = TempDir::new("gltf-instances-bad");
        let gltf = edited(&dir, edit);
        let scene = entry_scene(&dir);
        let e = load_err(&scene);
        assert_eq!(e.file, gltf, "{what}");
        assert_eq!(e.line, None, "{what}");
        let shown = e.to_string();
        assert!(!shown.contains('\n'), "{what}: {shown}");
        for word in words {
            assert!(shown.contains(word), "{what}: {shown} should say {word:?}");
        }
        assert!(
            shown.contains("(from meshes[0].path in "),
            "{what}: {shown}"
        );
    }
}
