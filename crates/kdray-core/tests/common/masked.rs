//! Scenes with alpha-masked triangles for the walks' tests: the objects of
//! a [`Primitives`] (f32 -> f64 -> f32 is exact) with every second
//! triangle in a MASK material whose base-colour texture is a small alpha
//! pattern, read nearest and repeated, and whose vertex colours' alphas
//! multiply it, so rays meet holes and solid texels alike. Shared by the CPU walks' property tests and the GPU query tests.
#![allow(dead_code)]

use std::path::Path;

use glam::{DVec2, Vec3};
use kdray_core::geometry::Primitives;
use kdray_core::scene::{
    parse_scene, Alpha, AlphaMode, MinFilter, Scene, SceneFormat, Sphere, Texture, TextureFilter,
    TextureWrap, Triangle,
};

/// The alpha pattern's side, in texels.
pub const SIDE: u32 = 4;

/// A scene of exactly `prims` (spheres and even triangles white and
/// opaque; odd triangles in MASK with cutoff 0.5 and the `SIDE` x `SIDE`
/// alpha bytes `alphas`, their corners at texture coordinates (0, 0),
/// (`uv_scale`, 0), (0, `uv_scale`)), for `integrator` ("whitted" or
/// "path"), to be walked as `Primitives::from_scene` gives it.
pub fn masked_scene(prims: &Primitives, alphas: &[u8], uv_scale: f64, integrator: &str) -> Scene {
    assert_eq!(alphas.len(), (SIDE * SIDE) as usize);
    let text = format!(
        "[camera]\nposition = [0, 0, 30]\nlook_at = [0, 0, 0]\n\
         [render]\nintegrator = \"{integrator}\"\n\
         [[lights]]\nposition = [0, 20, 0]\n\
         [materials.solid]\ndiffuse = [1, 1, 1]\n[materials.masked]\ndiffuse = [1, 1, 1]\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"solid\"\n\
         [[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"masked\"\n"
    );
    let mut scene = parse_scene(&text, Path::new("masked.toml"), SceneFormat::Toml)
        .unwrap_or_else(|e| panic!("{e}"));
    let index = |name: &str| scene.materials.iter().position(|m| m.name == name).unwrap() as u32;
    let (solid, masked) = (index("solid"), index("masked"));
    let texels = alphas
        .iter()
        .map(|&a| u32::from_le_bytes([200, 200, 200, a]))
        .collect();
    scene.textures = vec![Texture::new(
        "alpha",
        (SIDE, SIDE),
        texels,
        TextureFilter::Nearest,
        MinFilter {
            filter: TextureFilter::Nearest,
            mip: kdray_core::scene::MipMode::None,
        },
        [TextureWrap::Repeat; 2],
    )];
    let m = &mut scene.materials[masked as usize];
    m.texture = Some(0);
    m.alpha = Alpha {
        mode: AlphaMode::Mask,
        cutoff: 0.5,
        factor: 1.0,
    };
    scene.spheres = prims
        .spheres
        .iter()
        .map(|s| Sphere {
            center: s.center.as_dvec3(),
            radius: s.radius as f64,
            material: solid,
        })
        .collect();
    let corners = [
        DVec2::ZERO,
        DVec2::new(uv_scale, 0.0),
        DVec2::new(0.0, uv_scale),
    ];
    // Vertex colours' alphas, which multiply the texture's: some corners
    // cut more holes.
    let colour_alphas = [[1.0, 1.0, 1.0], [0.2, 1.0, 0.6], [1.0, 0.4, 0.9]];
    scene.triangle_uvs.clear();
    scene.triangle_colours.clear();
    scene.triangles = Vec::new();
    for (i, t) in prims.triangles.iter().enumerate() {
        let mut tri = Triangle::flat(t.v.map(|v: Vec3| v.as_dvec3()), solid);
        if i % 2 == 1 {
            tri.material = masked;
            tri.uvs = scene.triangle_uvs.len() as u32;
            scene.triangle_uvs.push(corners);
            let a: [f64; 3] = colour_alphas[(i / 2) % 3];
            scene
                .triangle_colours
                .push(a.map(|a| glam::DVec4::new(1.0, 1.0, 1.0, a)));
        }
        scene.triangles.push(tri);
    }
    scene
}

/// A checkerboard of holes (alpha 0) and solid texels (255), with one
/// texel at 128 (solid: 128 / 255 is above 0.5) and one at 127 (a hole).
pub fn checker_alphas() -> Vec<u8> {
    let mut a: Vec<u8> = (0..SIDE * SIDE)
        .map(|i| {
            if (i % SIDE + i / SIDE).is_multiple_of(2) {
                255
            } else {
                0
            }
        })
        .collect();
    a[0] = 128;
    a[1] = 127;
    a
}
