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
    // glTF Transform's AVIF box: its texture's only image is AVIF.
    let e = load("optimised/box_avif.glb").unwrap_err().to_string();
    for word in [
        "box_avif.glb",
        "EXT_texture_avif",
        "gltf-transform png in.glb out.glb --formats avif",
    ] {
        assert!(e.contains(word), "{e} lacks {word}");
    }
}

/// A GLB's JSON text and where its binary chunk's bytes start.
fn glb_parts(glb: &[u8]) -> (String, usize) {
    let json_length = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let json = String::from_utf8(glb[20..20 + json_length].to_vec()).unwrap();
    (json, 20 + json_length + 8)
}

/// `glb` with its JSON's `from` replaced by `to`, of the same length.
fn with_json_edit(glb: &[u8], from: &str, to: &str) -> Vec<u8> {
    assert_eq!(from.len(), to.len());
    let (json, _) = glb_parts(glb);
    assert!(json.contains(from), "{from}");
    let edited = json.replacen(from, to, 1);
    let mut out = glb.to_vec();
    out[20..20 + edited.len()].copy_from_slice(edited.as_bytes());
    out
}

fn parse(bytes: &[u8], name: &str) -> Result<Mesh, String> {
    let path = std::path::Path::new("models").join(name);
    kdray_core::scene::gltf::parse_gltf(bytes, &path, true, &mut |_| {
        Err(std::io::Error::from(std::io::ErrorKind::NotFound))
    })
    .map_err(|e| e.to_string())
}

/// A clean error: one line naming the file, the extension and the view.
fn assert_clean_error(result: Result<Mesh, String>, name: &str, words: &[&str], what: &str) {
    let e = match result {
        Ok(_) => panic!("{what}: loads"),
        Err(e) => e,
    };
    assert!(!e.contains('\n'), "{what}: {e}");
    for word in [name].iter().chain(words) {
        assert!(e.contains(word), "{what}: {e} lacks {word}");
    }
}

#[test]
fn corrupt_draco_and_meshopt_streams_are_one_line_errors_naming_the_view() {
    let dir = common::repo_path("tests/models/optimised");
    let draco = std::fs::read(dir.join("box_draco.glb")).unwrap();
    let meshopt = std::fs::read(dir.join("box_meshopt.glb")).unwrap();
    let (draco_name, meshopt_name) = ("box_draco.glb", "box_meshopt.glb");
    let draco_words = ["KHR_draco_mesh_compression", "buffer view 1"];
    // The Draco stream is buffer view 1 (bytes 2440..+233 of the binary
    // chunk); the meshopt NORMAL stream is view 2's (2472..+61).
    let (_, bin) = glb_parts(&draco);
    let mut zeroed = draco.clone();
    zeroed[bin + 2440..bin + 2440 + 233].fill(0);
    assert_clean_error(
        parse(&zeroed, draco_name),
        draco_name,
        &draco_words,
        "zeroed",
    );
    let cut = with_json_edit(&draco, "\"byteLength\":233", "\"byteLength\":133");
    assert_clean_error(
        parse(&cut, draco_name),
        draco_name,
        &draco_words,
        "truncated",
    );
    let meshopt_words = ["EXT_meshopt_compression", "buffer view 2"];
    let cut = with_json_edit(&meshopt, "\"byteLength\":61", "\"byteLength\":31");
    assert_clean_error(
        parse(&cut, meshopt_name),
        meshopt_name,
        &meshopt_words,
        "truncated",
    );
    let (_, bin) = glb_parts(&meshopt);
    let mut bad_header = meshopt.clone();
    bad_header[bin + 2472] = 0xa7;
    assert_clean_error(
        parse(&bad_header, meshopt_name),
        meshopt_name,
        &meshopt_words,
        "bad header",
    );
    // Every bit flip in either stream loads or is a clean error, quickly.
    let started = std::time::Instant::now();
    for (glb, name, range) in [
        (&draco, draco_name, 2440..2440 + 233),
        (&meshopt, meshopt_name, 2440..2440 + 344),
    ] {
        let (_, bin) = glb_parts(glb);
        for at in range {
            for bit in [0, 2, 5, 7] {
                let mut input = glb.clone();
                input[bin + at] ^= 1 << bit;
                if let Err(e) = parse(&input, name) {
                    assert!(!e.contains('\n') && e.contains(name), "{e}");
                }
            }
        }
    }
    assert!(started.elapsed().as_secs() < 60, "{:?}", started.elapsed());
}
