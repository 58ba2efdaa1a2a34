//! Textured test models written on the fly: a unit quad facing +z with its
//! texture coordinates at the corners, as an OBJ + MTL + PNG and as a glTF
//! with its buffer and image in data URIs; and the image they use.

use std::path::{Path, PathBuf};

/// The quad's corners (x, y in [-1, 1], z = 0), counter-clockwise from the
/// bottom left; its texture coordinates in the image's convention (v down
/// from the top row): the bottom left corner is the image's bottom left.
pub const CORNERS: [[f32; 3]; 4] = [
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
];
pub const IMAGE_UVS: [[f32; 2]; 4] = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];

/// A `width` x `height` RGB image whose every texel differs: red grows
/// along x, green along y, blue is fixed.
pub fn gradient(width: u32, height: u32) -> image::RgbaImage {
    image::RgbaImage::from_fn(width, height, |x, y| {
        let r = (40 + x * 200 / width.max(2).saturating_sub(1).max(1)) as u8;
        let g = (30 + y * 200 / height.max(2).saturating_sub(1).max(1)) as u8;
        image::Rgba([r, g, 90, 255])
    })
}

/// The image's bytes as a PNG file.
pub fn png_bytes(image: &image::RgbaImage) -> Vec<u8> {
    let mut out = std::io::Cursor::new(Vec::new());
    image.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

/// Writes `quad.obj`, `quad.mtl` (Kd `kd`, Ka 0.1, `map_Kd` with
/// `map_options` before the file name) and `tex.png` into `dir`; the
/// OBJ's path. The OBJ's texture coordinates are OBJ's (v up from the
/// bottom row), written so that in the image's convention they are
/// `uv_scale` times [`IMAGE_UVS`].
pub fn write_obj_quad(
    dir: &Path,
    image: &image::RgbaImage,
    kd: f32,
    map_options: &str,
    uv_scale: f32,
) -> PathBuf {
    std::fs::write(dir.join("tex.png"), png_bytes(image)).unwrap();
    std::fs::write(
        dir.join("quad.mtl"),
        format!(
            "newmtl t\nKa 0.1 0.1 0.1\nKd {kd} {kd} {kd}\nKs 0 0 0\nmap_Kd {map_options} tex.png\n"
        ),
    )
    .unwrap();
    let mut obj = String::from("mtllib quad.mtl\n");
    for c in CORNERS {
        obj += &format!("v {} {} {}\n", c[0], c[1], c[2]);
    }
    for uv in IMAGE_UVS {
        obj += &format!("vt {} {}\n", uv[0] * uv_scale, 1.0 - uv[1] * uv_scale);
    }
    obj += "usemtl t\nf 1/1 2/2 3/3 4/4\n";
    let path = dir.join("quad.obj");
    std::fs::write(&path, obj).unwrap();
    path
}

/// Standard base64 with padding.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}

/// Writes `quad.gltf` into `dir`: the quad, its texture coordinates
/// (glTF's, the image's convention) times `uv_scale`, a material with
/// `baseColorFactor` `factor` and the image with a sampler of `mag_filter`
/// (9728 NEAREST, 9729 LINEAR) and wraps `wrap` (33071 CLAMP_TO_EDGE,
/// 33648 MIRRORED_REPEAT, 10497 REPEAT). Its path.
pub fn write_gltf_quad(
    dir: &Path,
    image: &image::RgbaImage,
    factor: [f32; 4],
    mag_filter: u32,
    wrap: [u32; 2],
    uv_scale: f32,
) -> PathBuf {
    let material = format!(
        r#"{{"pbrMetallicRoughness":{{"baseColorFactor":[{},{},{},{}],"metallicFactor":0,"roughnessFactor":1,"baseColorTexture":{{"index":0}}}}}}"#,
        factor[0], factor[1], factor[2], factor[3],
    );
    let sampler = (mag_filter, wrap);
    let images = std::slice::from_ref(image);
    write_quad_gltf(
        &dir.join("quad.gltf"),
        &material,
        images,
        sampler,
        uv_scale,
        &[],
    )
}

/// Writes `name` into `dir`: the quad as in [`write_gltf_quad`] with the
/// material `material` (a glTF material's JSON, whose textures i are
/// `images[i]`, nearest, clamped) and, if given, the vertex normal `normal`
/// at every corner. Its path.
pub fn write_gltf_quad_material(
    dir: &Path,
    name: &str,
    material: &str,
    images: &[image::RgbaImage],
    normal: Option<[f32; 3]>,
) -> PathBuf {
    let normals: Vec<Vec<f32>> = normal.iter().flat_map(|n| vec![n.to_vec(); 4]).collect();
    let attributes: Vec<(&str, Vec<Vec<f32>>)> = match normal {
        Some(_) => vec![("NORMAL", normals)],
        None => Vec::new(),
    };
    write_gltf_quad_attributes(dir, name, material, images, &attributes)
}

/// Writes `name` into `dir` as [`write_gltf_quad_material`] does, with the
/// vertex attributes `attributes` (a name such as `COLOR_0` or `TANGENT`,
/// and per corner, in [`CORNERS`]' order, its 2, 3 or 4 floats). Its path.
pub fn write_gltf_quad_attributes(
    dir: &Path,
    name: &str,
    material: &str,
    images: &[image::RgbaImage],
    attributes: &[(&str, Vec<Vec<f32>>)],
) -> PathBuf {
    const NEAREST_CLAMPED: (u32, [u32; 2]) = (9728, [33071, 33071]);
    write_quad_gltf(
        &dir.join(name),
        material,
        images,
        NEAREST_CLAMPED,
        1.0,
        attributes,
    )
}

/// Writes `path`: the quad with texture coordinates [`IMAGE_UVS`] times
/// `uv_scale`, one primitive of material `material` (a glTF material's
/// JSON, whose textures i are `images[i]`), one sampler (filter, [wrapS,
/// wrapT]) for every texture and the float vertex attributes `attributes`;
/// buffer and images in data URIs. `path`, returned.
fn write_quad_gltf(
    path: &Path,
    material: &str,
    images: &[image::RgbaImage],
    (filter, wrap): (u32, [u32; 2]),
    uv_scale: f32,
    attributes: &[(&str, Vec<Vec<f32>>)],
) -> PathBuf {
    let mut data = Vec::new();
    for c in CORNERS {
        for x in c {
            data.extend_from_slice(&x.to_le_bytes());
        }
    }
    for uv in IMAGE_UVS {
        for x in uv {
            data.extend_from_slice(&(x * uv_scale).to_le_bytes());
        }
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        data.extend_from_slice(&i.to_le_bytes());
    }
    data.extend_from_slice(&[0, 0]); // the floats' 4-byte alignment
    let (mut extra_attributes, mut extra_views, mut extra_accessors) =
        (String::new(), String::new(), String::new());
    for (k, (name, corners)) in attributes.iter().enumerate() {
        let offset = data.len();
        for c in corners {
            for x in c {
                data.extend_from_slice(&x.to_le_bytes());
            }
        }
        let kind = ["", "SCALAR", "VEC2", "VEC3", "VEC4"][corners[0].len()];
        extra_attributes += &format!(r#","{name}":{}"#, 3 + k);
        extra_views += &format!(
            r#",{{"buffer":0,"byteOffset":{offset},"byteLength":{}}}"#,
            data.len() - offset
        );
        extra_accessors += &format!(
            r#",{{"bufferView":{},"componentType":5126,"count":4,"type":"{kind}"}}"#,
            3 + k
        );
    }
    let (normal_attribute, normal_view, normal_accessor) =
        (extra_attributes, extra_views, extra_accessors);
    let textures: Vec<String> = (0..images.len())
        .map(|i| format!(r#"{{"source":{i},"sampler":0}}"#))
        .collect();
    let image_list: Vec<String> = images
        .iter()
        .map(|im| {
            format!(
                r#"{{"uri":"data:image/png;base64,{}"}}"#,
                base64(&png_bytes(im))
            )
        })
        .collect();
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0,"TEXCOORD_0":1{normal_attribute}}},"indices":2,"material":0}}]}}],
"materials":[{material}],
"textures":[{}],
"samplers":[{{"magFilter":{filter},"minFilter":{filter},"wrapS":{},"wrapT":{}}}],
"images":[{}],
"buffers":[{{"byteLength":{},"uri":"data:application/octet-stream;base64,{}"}}],
"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":48}},{{"buffer":0,"byteOffset":48,"byteLength":32}},{{"buffer":0,"byteOffset":80,"byteLength":12}}{normal_view}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":4,"type":"VEC3","min":[-1,-1,0],"max":[1,1,0]}},
{{"bufferView":1,"componentType":5126,"count":4,"type":"VEC2"}},
{{"bufferView":2,"componentType":5123,"count":6,"type":"SCALAR"}}{normal_accessor}]}}"#,
        textures.join(","),
        wrap[0],
        wrap[1],
        image_list.join(","),
        data.len(),
        base64(&data),
    );
    std::fs::write(path, json).unwrap();
    path.to_path_buf()
}
