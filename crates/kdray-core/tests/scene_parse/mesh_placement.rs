//! Meshes through the whole load: the scene's triangles and normals
//! against coordinates worked out here from the files' numbers, so that
//! a wrong vertex, normal or offset index shows.

use super::*;

/// A fresh folder under the temp dir, unique per process and test.
fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kdray-parse-test-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A scene of one mesh entry (`mesh` is the rest of its table), material `m`.
fn mesh_scene(dir: &Path, mesh: &str) -> Scene {
    let path = dir.join("scene.toml");
    let text = format!(
        "[camera]\nposition = [0, 0, 10]\nlook_at = [0, 0, 0]\n\
         [[lights]]\nposition = [0, 10, 0]\n[materials.m]\ndiffuse = [1, 1, 1]\n\
         [[meshes]]\nmaterial = \"m\"\n{mesh}\n"
    );
    std::fs::write(&path, text).unwrap();
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn assert_near(got: DVec3, want: DVec3) {
    assert!(
        (got - want).abs().max_element() < 1e-9,
        "got {got}, want {want}"
    );
}

fn assert_triangle(scene: &Scene, i: usize, vertices: [DVec3; 3], normals: Option<[DVec3; 3]>) {
    let t = &scene.triangles[i];
    for (got, want) in t.vertices.iter().zip(vertices) {
        assert_near(*got, want);
    }
    match (scene.normals_of(t), normals) {
        (Some(got), Some(want)) => {
            for (g, w) in got.iter().zip(want) {
                assert_near(*g, w);
            }
        }
        (got, want) => assert_eq!(got, want),
    }
    assert_eq!(t.material, 0);
}

#[test]
fn obj_indices_in_every_form_reach_the_right_vertices_and_normals() {
    let dir = temp_dir("obj-indices");
    // Vertex 3 is used by no face; placed, it lies at 1.8e15, beyond
    // the GPU's range, which only matters for vertices faces use.
    std::fs::write(
        dir.join("m.obj"),
        "v 0 0 0\nv 2 0 0\nv 9e14 9 9\nv 0 3 0\nvt 0 0\n\
         vn 0 0 1\nvn 1 0 0\nv 1 1 2\nvn 0 1 0\n\
         f 1//1 2//2 4//3\n\
         f -1/1/-1 -4/1/-3 -2/1/-2\n\
         f 5 1/1 -4\n",
    )
    .unwrap();
    let scene = mesh_scene(
        &dir,
        "path = \"m.obj\"\nscale = [2, 1, 0.5]\nrotate = [0, 0, 90]\ntranslate = [1, 2, 3]",
    );
    // Scaled by (2, 1, 0.5), turned 90 degrees about z, then moved.
    let place = |x: f64, y: f64, z: f64| DVec3::new(1.0 - y, 2.0 + 2.0 * x, 3.0 + 0.5 * z);
    let v = [
        place(0.0, 0.0, 0.0),
        place(2.0, 0.0, 0.0),
        place(9e14, 9.0, 9.0),
        place(0.0, 3.0, 0.0),
        place(1.0, 1.0, 2.0),
    ];
    // Normals go through the inverse scale, then the same turn.
    let turn = |x: f64, y: f64, z: f64| {
        let n = DVec3::new(x / 2.0, y, z * 2.0);
        DVec3::new(-n.y, n.x, n.z).normalize()
    };
    let n = [
        turn(0.0, 0.0, 1.0),
        turn(1.0, 0.0, 0.0),
        turn(0.0, 1.0, 0.0),
    ];
    assert_eq!(scene.triangles.len(), 3);
    assert_triangle(&scene, 0, [v[0], v[1], v[3]], Some([n[0], n[1], n[2]]));
    // -1 is the fifth vertex and the third normal, as defined so far.
    assert_triangle(&scene, 1, [v[4], v[1], v[3]], Some([n[2], n[0], n[1]]));
    // Corners without normals: flat shading from the file.
    assert_triangle(&scene, 2, [v[4], v[0], v[1]], None);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn triangles_a_scale_collapses_are_skipped_and_the_others_kept_in_order() {
    let dir = temp_dir("collapse");
    std::fs::write(
        dir.join("m.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 4\nf 1 2 3\nf 1 3 4\n",
    )
    .unwrap();
    // The face in z = 0 keeps an area of 1e-320, whose square is 0 in
    // f64; the two upright ones keep 1e-160.
    let scene = mesh_scene(&dir, "path = \"m.obj\"\nscale = [1e-160, 1e-160, 1]");
    let (o, x, y, z) = (
        DVec3::ZERO,
        DVec3::new(1e-160, 0.0, 0.0),
        DVec3::new(0.0, 1e-160, 0.0),
        DVec3::Z,
    );
    let got: Vec<_> = scene.triangles.iter().map(|t| t.vertices).collect();
    assert_eq!(got, [[o, x, z], [o, y, z]]);
    // With a normal per face (its own face's, on the axes, which the
    // normal matrix keeps), each kept triangle keeps its own.
    std::fs::write(
        dir.join("n.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 -1 0\nvn 0 0 1\nvn 2 0 0\n\
         f 1//1 2//1 4//1\nf 1//2 2//2 3//2\nf 1//3 3//3 4//3\n",
    )
    .unwrap();
    let scene = mesh_scene(&dir, "path = \"n.obj\"\nscale = [1e-160, 1e-160, 1]");
    let got: Vec<_> = scene
        .triangles
        .iter()
        .map(|t| (t.vertices, scene.normals_of(t)))
        .collect();
    let want = [
        ([o, x, z], Some([DVec3::NEG_Y; 3])),
        ([o, y, z], Some([DVec3::X; 3])),
    ];
    assert_eq!(got, want);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `floats` as little-endian f32 bytes.
fn f32_bytes(floats: &[f32]) -> Vec<u8> {
    floats.iter().flat_map(|f| f.to_le_bytes()).collect()
}

#[test]
fn gltf_primitives_are_offset_into_one_mesh_under_a_node_transform() {
    let dir = temp_dir("gltf-offsets");
    // Primitive 0: five vertices (the fifth unused), no normals, two
    // indexed triangles. Primitive 1: three vertices with normals, not
    // indexed. So primitive 1's vertices start at 5 and its normals at 0.
    let first: [[f32; 3]; 5] = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
        [7.0, 7.0, 7.0],
    ];
    let indices: [u16; 6] = [0, 1, 2, 0, 2, 3];
    let second: [[f32; 3]; 3] = [[0.0, 0.0, 1.0], [0.0, 2.0, 1.0], [0.0, 0.0, 3.0]];
    let normals: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut bin = f32_bytes(first.as_flattened());
    bin.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    bin.extend(f32_bytes(second.as_flattened()));
    bin.extend(f32_bytes(normals.as_flattened()));
    assert_eq!(bin.len(), 144);
    std::fs::write(dir.join("m.bin"), &bin).unwrap();
    // The parent turns 90 degrees about z (quaternion) and moves; the
    // child scales x by 2.
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let gltf = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
        "nodes": [{{"translation": [1, 2, 3], "rotation": [0, 0, {h}, {h}], "children": [1]}},
                  {{"scale": [2, 1, 1], "mesh": 0}}],
        "meshes": [{{"primitives": [
            {{"attributes": {{"POSITION": 0}}, "indices": 1}},
            {{"attributes": {{"POSITION": 2, "NORMAL": 3}}}}]}}],
        "buffers": [{{"byteLength": 144, "uri": "m.bin"}}],
        "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 60}},
                        {{"buffer": 0, "byteOffset": 60, "byteLength": 12}},
                        {{"buffer": 0, "byteOffset": 72, "byteLength": 36}},
                        {{"buffer": 0, "byteOffset": 108, "byteLength": 36}}],
        "accessors": [
            {{"bufferView": 0, "componentType": 5126, "count": 5, "type": "VEC3", "min": [0, 0, 0], "max": [7, 7, 7]}},
            {{"bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR"}},
            {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 1], "max": [0, 2, 3]}},
            {{"bufferView": 3, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#
    );
    std::fs::write(dir.join("m.gltf"), gltf).unwrap();
    let scene = mesh_scene(&dir, "path = \"m.gltf\"");
    // Scaled by (2, 1, 1), turned 90 degrees about z, then moved (the
    // f32 quaternion is within 1e-7 of the exact turn).
    let place = |p: [f32; 3]| {
        let [x, y, z] = p.map(f64::from);
        DVec3::new(1.0 - y, 2.0 + 2.0 * x, 3.0 + z)
    };
    let turn = |n: [f32; 3]| {
        let [x, y, z] = n.map(f64::from);
        DVec3::new(-y, x / 2.0, z).normalize()
    };
    let near = |got: DVec3, want: DVec3| (got - want).abs().max_element() < 1e-6;
    let check = |t: &Triangle, vertices: [DVec3; 3], normals: Option<[DVec3; 3]>| {
        for (got, want) in t.vertices.iter().zip(vertices) {
            assert!(near(*got, want), "got {got}, want {want}");
        }
        let got_normals = scene.normals_of(t);
        assert_eq!(got_normals.is_some(), normals.is_some(), "{t:?}");
        if let (Some(got), Some(want)) = (got_normals, normals) {
            for (g, w) in got.iter().zip(want) {
                assert!(near(*g, w), "normal {g}, want {w}");
            }
        }
    };
    assert_eq!(scene.triangles.len(), 3);
    let p = first.map(place);
    check(&scene.triangles[0], [p[0], p[1], p[2]], None);
    check(&scene.triangles[1], [p[0], p[2], p[3]], None);
    check(
        &scene.triangles[2],
        second.map(place),
        Some(normals.map(turn)),
    );
    let _ = std::fs::remove_dir_all(&dir);
}
