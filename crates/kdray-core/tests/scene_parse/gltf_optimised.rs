//! The glTF files the web's optimisers write load as their originals do:
//! quantized attributes (`KHR_mesh_quantization`), meshopt- and
//! Draco-compressed geometry, WebP textures (tests/models/optimised/, made
//! with glTF Transform from Khronos' BoxTextured; the quantized tetrahedra
//! of tests/models/make_models.py), and what cannot load is refused by name.

use super::*;
use kdray_core::scene::mesh::{Mesh, MeshTriangle};

fn load(relative: &str) -> Result<Mesh, SceneError> {
    let path = common::repo_path("tests/models").join(relative);
    kdray_core::scene::gltf::load_gltf(&path, true, &mut |_| {})
}

/// A triangle's corners: placed position, normal and texture coordinates.
type Corner = (DVec3, DVec3, glam::DVec2);

fn corners(mesh: &Mesh, t: &MeshTriangle) -> [Corner; 3] {
    std::array::from_fn(|k| {
        (
            mesh.positions[t.corners[k] as usize],
            mesh.normals[t.normals[k] as usize],
            mesh.uvs[t.uvs[k] as usize],
        )
    })
}

/// Every triangle of `a` is one of `b`'s (the same corners, in the same
/// winding, from any first corner) within the tolerances, and both have
/// as many: vertex and triangle order may differ (the compressors reorder).
fn assert_same_triangles(a: &Mesh, b: &Mesh, position: f64, normal: f64, uv: f64, what: &str) {
    assert_eq!(a.triangles.len(), b.triangles.len(), "{what}");
    let close = |x: &Corner, y: &Corner| {
        (x.0 - y.0).abs().max_element() <= position
            && (x.1.normalize() - y.1.normalize()).abs().max_element() <= normal
            && (x.2 - y.2).abs().max_element() <= uv
    };
    let theirs: Vec<[Corner; 3]> = b.triangles.iter().map(|t| corners(b, t)).collect();
    for t in &a.triangles {
        let ours = corners(a, t);
        let found = theirs
            .iter()
            .any(|other| (0..3).any(|r| (0..3).all(|k| close(&ours[k], &other[(k + r) % 3]))));
        assert!(found, "{what}: triangle {ours:?} is not in the original");
    }
}

#[test]
fn quantized_meshopt_and_draco_boxes_have_the_original_triangles() {
    let original = load("optimised/box.glb").unwrap();
    assert_eq!(original.triangles.len(), 12);
    // Positions: 16-bit (quantize, meshopt) or 14-bit (Draco) over a unit
    // box; normals: 8-bit or Draco's 10-bit octahedra; uvs: float or 12-bit.
    for name in ["box_quantized.glb", "box_meshopt.glb", "box_draco.glb"] {
        let mesh = load(&format!("optimised/{name}")).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(mesh.warnings.is_empty(), "{name}: {:?}", mesh.warnings);
        assert_same_triangles(&mesh, &original, 2e-4, 0.02, 1e-3, name);
        assert_same_triangles(&original, &mesh, 2e-4, 0.02, 1e-3, name);
        assert!(mesh.materials[0].texture.is_some(), "{name}");
    }
}

#[test]
fn a_webp_texture_decodes_to_the_png_within_lossy_tolerance() {
    let png = load("optimised/box.glb").unwrap();
    let webp = load("optimised/box_webp.glb").unwrap();
    assert!(webp.warnings.is_empty(), "{:?}", webp.warnings);
    let (a, b) = (
        png.materials[0].texture.as_ref().unwrap(),
        webp.materials[0].texture.as_ref().unwrap(),
    );
    assert_eq!((a.width, a.height), (b.width, b.height));
    let channels = |t: u32| t.to_le_bytes().map(f64::from);
    let mut total = 0.0;
    for (x, y) in a.texels.iter().zip(&b.texels) {
        let (x, y) = (channels(*x), channels(*y));
        total += (0..3).map(|c| (x[c] - y[c]).abs()).sum::<f64>() / 3.0;
    }
    let mean = total / a.texels.len() as f64;
    // Lossy WebP: a few levels of 255 on average.
    assert!(mean < 4.0, "mean absolute difference {mean}");
}

#[test]
fn quantized_integer_attributes_read_as_the_float_tetrahedron() {
    let float = load("tetra_embedded.gltf").unwrap();
    for (name, normal_error) in [
        ("tetra_quantized_i16.gltf", 0.5 / 127.0),
        ("tetra_quantized_u8.gltf", 0.5 / 32767.0),
    ] {
        let mesh = load(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(mesh.warnings.is_empty(), "{name}: {:?}", mesh.warnings);
        assert_eq!(mesh.positions.len(), float.positions.len(), "{name}");
        for (p, q) in mesh.positions.iter().zip(&float.positions) {
            assert!((*p - *q).abs().max_element() < 1e-6, "{name}: {p} vs {q}");
        }
        // Normals are carried by the node's inverse transpose (scales up
        // to 2): compare directions.
        for (n, m) in mesh.normals.iter().zip(&float.normals) {
            let d = (n.normalize() - m.normalize()).abs().max_element();
            assert!(d < 4.0 * normal_error, "{name}: {n} vs {m}");
        }
        let uvs: Vec<[f64; 2]> = mesh.uvs.iter().map(|u| u.to_array()).collect();
        assert_eq!(
            uvs,
            [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]],
            "{name}"
        );
        assert_eq!(mesh.triangles.len(), float.triangles.len(), "{name}");
        for (t, u) in mesh.triangles.iter().zip(&float.triangles) {
            assert_eq!(t.corners, u.corners, "{name}");
        }
    }
}

#[test]
fn a_required_extension_kdray_cannot_read_is_an_error_naming_it_and_a_conversion() {
    let e = load("requires_basisu.gltf").unwrap_err().to_string();
    assert!(e.contains("requires_basisu.gltf"), "{e}");
    for word in ["KHR_texture_basisu", "gltf-transform ktxdecompress"] {
        assert!(e.contains(word), "{e} lacks {word}");
    }
    assert!(!e.contains('\n') && !e.contains("accessor"), "{e}");
}
