//! Textured models of another project, read as users open them: Debian's
//! assimp-testmodels (Khronos' BoxTextured in its three glTF containers,
//! Khronos' AnimatedMorphCube with its tangents, and an OBJ whose MTL file
//! names its images Windows-style). The README's
//! test command installs the package.

use std::path::{Path, PathBuf};

use crate::common;

use common::{compare, gpu};
use kdray::gpu::{Accel, TilePlan};
use kdray::scene::{Scene, TextureWrap, Warning};

const MODELS: &str = "/usr/share/assimp/models";

fn model(relative: &str) -> PathBuf {
    let path = Path::new(MODELS).join(relative);
    assert!(
        path.exists(),
        "{} is missing: these tests need Debian's assimp-testmodels (scripts/test.sh installs it)",
        path.display()
    );
    path
}

/// The model opened alone, with the warnings its files raise.
fn open(relative: &str) -> (Scene, Vec<Warning>) {
    let mut warnings = Vec::new();
    let mut scene =
        kdray::scene::load_scene_with(&model(relative), &mut |_| {}, &mut |w| warnings.push(w))
            .unwrap_or_else(|e| panic!("{e}"));
    scene.render.width = 160;
    scene.render.height = 120;
    (scene, warnings)
}

fn image(scene: &Scene) -> Vec<u8> {
    kdray::render::render_scene(
        gpu(),
        scene,
        Accel::Kdtree,
        TilePlan::DEFAULT_MAX_TILE_PIXELS,
    )
    .unwrap_or_else(|e| panic!("{e}"))
    .0
    .rgb
}

/// The three containers of BoxTextured (a .bin and .png beside the .gltf;
/// one .glb; data URIs) give the same texture: the .glb's and the embedded
/// file's images are equal, and the box is painted by its texture (without
/// it a clear share of the pixels changes). The file-beside variant's own
/// sampler mirrors along u and clamps along v, and is read so.
#[test]
fn box_textured_reads_its_texture_from_a_file_a_glb_and_a_data_uri() {
    let (glb, warnings) = open("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb");
    assert!(warnings.is_empty(), "{warnings:?}");
    let (embedded, _) = open("glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf");
    let (beside, _) = open("glTF2/BoxTextured-glTF/BoxTextured.gltf");
    for scene in [&glb, &embedded, &beside] {
        assert_eq!(scene.textures.len(), 1);
        let t = &scene.textures[0];
        assert_eq!((t.width, t.height), (211, 211), "CesiumLogoFlat.png");
    }
    assert_eq!(glb.textures[0].texels, embedded.textures[0].texels);
    assert_eq!(glb.textures[0].texels, beside.textures[0].texels);
    assert_eq!(glb.textures[0].wrap, [TextureWrap::Repeat; 2]);
    assert_eq!(
        beside.textures[0].wrap,
        [TextureWrap::MirroredRepeat, TextureWrap::ClampToEdge]
    );

    let (w, h) = (glb.render.width, glb.render.height);
    let from_glb = image(&glb);
    let d = compare(&from_glb, &image(&embedded), w, h, 0);
    assert_eq!(d.pixels_over, 0, "glb against data URIs: {d:?}");

    let mut plain = glb.clone();
    for m in &mut plain.materials {
        m.texture = None;
    }
    let d = compare(&from_glb, &image(&plain), w, h, 8);
    assert!(
        d.pixels_over > (w * h / 20) as usize,
        "the texture should paint the box: {d:?}"
    );
}

/// spider.mtl names its images `.\SpiderTex.jpg` and the like: each is
/// found and decoded, none is warned about, and the spider renders.
#[test]
fn an_mtl_naming_its_images_with_backslashes_finds_them() {
    let (scene, warnings) = open("OBJ/spider.obj");
    let about_images: Vec<&Warning> = warnings
        .iter()
        .filter(|w| w.message.contains("texture"))
        .collect();
    assert!(about_images.is_empty(), "{about_images:?}");
    // Four of its five textured materials are used by faces (Skin,
    // HLeibTex, BeinTex, Augentex); Brusttex is not.
    assert_eq!(scene.textures.len(), 4, "the used materials' images");
    assert!(scene.textures.iter().all(|t| t.width > 0 && t.height > 0));
    let rgb = image(&scene);
    assert!(rgb.chunks(3).any(|p| p != &rgb[0..3]), "a blank image");
}

/// Khronos' AnimatedMorphCube gives `TANGENT`s (and no normal map): every
/// one is (1, 0, 0) with w = 1 in the file, and its node turns x half a
/// turn about (0, 1, -1) into -x and scales by 100: every tangent read is
/// (-100, 0, 0) with w = 1 (a rotation mirrors nothing).
#[test]
fn a_khronos_samples_tangents_are_read_and_carried_by_the_node() {
    let path = model("glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf");
    let mesh =
        kdray::scene::gltf::load_gltf(&path, true, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(mesh.tangents.len(), mesh.positions.len());
    let expected = glam::DVec4::new(-100.0, 0.0, 0.0, 1.0);
    for t in &mesh.tangents {
        assert!((*t - expected).abs().max_element() < 1e-3, "{t}");
    }
}
