//! Mesh shading normals: flat, from the file, or computed smooth; carried
//! to world space with the mesh.

use super::*;

/// A mesh's triangle as loaded, its normals looked up in the scene.
#[derive(Debug, Clone, Copy)]
struct Shaded {
    vertices: [DVec3; 3],
    normals: Option<[DVec3; 3]>,
}

fn load(dir: &TempDir, obj: &str, keys: &[(&str, &str)]) -> Vec<Shaded> {
    dir.write("m.obj", obj);
    let mut all = vec![("path", "\"m.obj\""), ("material", "\"red\"")];
    all.extend_from_slice(keys);
    let (scene, _) = scene_with_mesh(dir, &all);
    let scene = load_ok(&scene);
    scene.triangles[1..]
        .iter()
        .map(|t| Shaded {
            vertices: t.vertices,
            normals: scene.normals_of(t),
        })
        .collect()
}

const WITH_NORMALS: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 2\nvn 0 1 1\nvn 1 0 0\n\
                            f 1//1 2//2 3//3\nf 1/1/1 3/1/2 2/1/3\n";

#[test]
fn obj_normals_are_kept_per_corner_and_normalised() {
    let dir = TempDir::new("vn");
    let t = load(&dir, WITH_NORMALS, &[]);
    let s = 0.5f64.sqrt();
    // Corners in face order; both faces give normals 1, 2, 3 in that order.
    for t in &t[..2] {
        let want = [DVec3::Z, DVec3::new(0.0, s, s), DVec3::X];
        for (got, want) in t.normals.unwrap().into_iter().zip(want) {
            assert_close(got, want);
        }
    }
}

#[test]
fn smooth_false_is_flat_and_a_file_without_normals_is_flat_by_default() {
    let dir = TempDir::new("flat");
    assert!(load(&dir, WITH_NORMALS, &[("smooth", "false")])
        .iter()
        .all(|t| t.normals.is_none()));
    assert!(load(&dir, ONE_TRIANGLE_OBJ, &[])
        .iter()
        .all(|t| t.normals.is_none()));
    // A face with normals on only some corners is flat by default.
    let partial = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2 3\n";
    assert_eq!(load(&dir, partial, &[])[0].normals, None);
    // With smooth = true the missing corners are computed (one face: its normal).
    assert_eq!(
        load(&dir, partial, &[("smooth", "true")])[0].normals,
        Some([DVec3::Z; 3])
    );
}

/// The unit cube [0, 1]^3 as an OBJ of 12 outward-wound triangles sharing 8 vertices.
const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nv 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n\
                    f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";

#[test]
fn smooth_true_computes_angle_weighted_normals_of_shared_vertices() {
    let dir = TempDir::new("cube");
    let triangles = load(&dir, CUBE, &[("smooth", "true")]);
    assert_eq!(triangles.len(), 12);
    for t in &triangles {
        for (v, n) in t.vertices.iter().zip(t.normals.unwrap()) {
            // Each corner's three faces meet at right angles: the diagonal.
            let want = (*v - DVec3::splat(0.5)).normalize();
            assert_close(n, want);
        }
    }
}

#[test]
fn normals_follow_the_entry_transform_by_the_inverse_transpose() {
    let dir = TempDir::new("xform-n");
    // A plane x = z (normal (1, 0, -1)) stretched by 2 along x is the plane
    // x = 2z, whose normal is (1, 0, -2); then rotated 90 degrees about z.
    let obj = "v 0 0 0\nv 1 0 1\nv 0 1 0\nvn 1 0 -1\nf 1//1 2//1 3//1\n";
    let t = load(
        &dir,
        obj,
        &[("scale", "[2, 1, 1]"), ("rotate", "[0, 0, 90]")],
    );
    let want = DVec3::new(0.0, 1.0, -2.0) / 5f64.sqrt();
    for n in t[0].normals.unwrap() {
        assert_close(n, want);
    }
    // The normal is perpendicular to the transformed triangle.
    let [a, b, c] = t[0].vertices;
    assert!((b - a).dot(want).abs() < 1e-12 && (c - a).dot(want).abs() < 1e-12);
    // Computed normals are computed on the transformed mesh.
    let smooth = load(&dir, CUBE, &[("smooth", "true"), ("scale", "[1, 1, 4]")]);
    for t in &smooth {
        for (v, n) in t.vertices.iter().zip(t.normals.unwrap()) {
            // Still a box, so still the diagonal (1, 1, 1) / sqrt(3), not
            // the unscaled cube's normal carried through the scale.
            let want = (*v - DVec3::new(0.5, 0.5, 2.0)).signum().normalize();
            assert_close(n, want);
        }
    }
}

#[test]
fn bad_normal_statements_name_their_line() {
    let dir = TempDir::new("badvn");
    for (obj, line, key) in [
        ("vn 0 0\n", 1, "vn"),
        ("v 0 0 0\nvn 0 nan 1\n", 2, "vn"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1//1 2//1 3//1\n", 4, "f"),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//0 2//1 3//1\n",
            5,
            "f",
        ),
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//x 2//1 3//1\n",
            5,
            "f",
        ),
    ] {
        let obj_path = dir.write("m.obj", obj);
        let (scene, _) = scene_with_mesh(&dir, &[("path", "\"m.obj\""), ("material", "\"red\"")]);
        assert_error(&load_err(&scene), &obj_path, Some(line), Some(key), &[]);
    }
    let e = parse_err(
        &with_mesh().set("meshes[0].smooth", "\"yes\"").toml().text,
        SceneFormat::Toml,
    );
    assert_eq!(e.key.as_deref(), Some("meshes[0].smooth"), "{e}");
}
