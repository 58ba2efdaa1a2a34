//! The path tracer's keys in scene files: `[render] integrator`, `seed`,
//! `tone_map`, `exposure`, `denoise`; materials' `base_color`, `metallic`,
//! `roughness`, `emission`; `[environment]`; and what each refuses, in one
//! line naming the file, line and key.

use std::path::Path;

use glam::DVec3;

use super::integrator::{Integrator, ToneMap};
use super::load::parse_scene;
use super::material::MetalRough;
use super::scene_format::SceneFormat;

const CAMERA: &str = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n";

fn parse(text: &str) -> Result<super::validated_scene::Scene, String> {
    parse_scene(text, Path::new("s.toml"), SceneFormat::Toml).map_err(|e| e.to_string())
}

fn refused(text: &str) -> String {
    match parse(text) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => {
            assert!(!e.contains('\n'), "not one line: {e}");
            e
        }
    }
}

fn path_scene(render: &str, material: &str) -> String {
    format!(
        "{CAMERA}[render]\nintegrator = \"path\"\n{render}\n[materials.m]\n{material}\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n"
    )
}

#[test]
fn the_path_keys_are_read_with_their_defaults() {
    let s = parse(&path_scene(
        "samples = 7\nseed = 3\ntone_map = \"clamp\"\nexposure = -1.5",
        "base_color = [0.9, 0.5, 0.1]\nmetallic = 1\nroughness = 0.25\nemission = [2, 0, 8]",
    ))
    .unwrap();
    assert_eq!(s.render.integrator, Integrator::Path);
    assert_eq!((s.render.samples, s.render.seed), (7, 3));
    assert_eq!(s.render.tone_map, ToneMap::Clamp);
    assert_eq!(s.render.exposure, -1.5);
    assert!(s.lights.is_empty(), "the path tracer needs no [[lights]]");
    let m = &s.materials[0];
    assert_eq!(m.diffuse, DVec3::new(0.9, 0.5, 0.1));
    assert_eq!(
        m.physical.metal_rough,
        Some(MetalRough {
            metallic: 1.0,
            roughness: 0.25
        })
    );
    assert_eq!(m.physical.emission, DVec3::new(2.0, 0.0, 8.0));

    let d = parse(&path_scene("", "base_color = [1, 1, 1]")).unwrap();
    assert_eq!(
        d.materials[0].physical.metal_rough,
        Some(MetalRough {
            metallic: 0.0,
            roughness: 0.5
        })
    );
    assert_eq!(d.render.samples, 1);
    assert_eq!(d.render.tone_map, ToneMap::Aces);
    let lambert = parse(&path_scene("", "diffuse = [1, 1, 1]")).unwrap();
    assert_eq!(
        lambert.materials[0].physical,
        super::material::Physical::LAMBERTIAN
    );
}

#[test]
fn the_environment_colour_is_the_background() {
    let text = format!(
        "{}[environment]\ncolor = [0.25, 0.5, 1]\n",
        path_scene("", "diffuse = [1, 1, 1]")
    );
    let s = parse(&text).unwrap();
    assert_eq!(s.render.background, DVec3::new(0.25, 0.5, 1.0));
    let both = text.replace("[render]\n", "[render]\nbackground = [1, 0, 0]\n");
    assert!(refused(&both).contains("environment"), "{}", refused(&both));
}

/// Any sample count for the path tracer, a perfect square for Whitted's
/// grid; and the Whitted integrator still needs a light.
#[test]
fn samples_and_lights_follow_the_integrator() {
    assert!(parse(&path_scene("samples = 5", "diffuse = [1, 1, 1]")).is_ok());
    let e = refused(&path_scene("samples = 0", "diffuse = [1, 1, 1]"));
    assert!(
        e.starts_with("s.toml:") && e.contains("render.samples"),
        "{e}"
    );
    let whitted = path_scene("samples = 5", "diffuse = [1, 1, 1]")
        .replace("integrator = \"path\"", "integrator = \"whitted\"");
    let e = refused(&whitted);
    assert!(
        e.contains("render.samples") && e.contains("perfect square"),
        "{e}"
    );
    let e = refused(&whitted.replace("samples = 5", "samples = 4"));
    assert!(e.contains("lights") && e.contains("path"), "{e}");
}

#[test]
fn bad_path_keys_are_refused_naming_their_key() {
    for (render, material, key) in [
        (
            "integrator = \"photon\"",
            "diffuse = [1, 1, 1]",
            "integrator",
        ),
        ("tone_map = \"filmic\"", "diffuse = [1, 1, 1]", "tone_map"),
        ("exposure = nan", "diffuse = [1, 1, 1]", "render.exposure"),
        (
            "",
            "diffuse = [1, 1, 1]\nbase_color = [1, 1, 1]",
            "materials.m.base_color",
        ),
        (
            "",
            "diffuse = [1, 1, 1]\nmetallic = 0.5",
            "materials.m.metallic",
        ),
        (
            "",
            "base_color = [1, 1, 1]\nroughness = 1.5",
            "materials.m.roughness",
        ),
        (
            "",
            "base_color = [1, 1, 1]\nmetallic = -0.1",
            "materials.m.metallic",
        ),
        (
            "",
            "diffuse = [1, 1, 1]\nemission = [1, inf, 1]",
            "materials.m.emission",
        ),
        (
            "",
            "diffuse = [1, 1, 1]\nemission = [1, -1, 1]",
            "materials.m.emission",
        ),
        ("", "ambient = [1, 1, 1]", "materials.m"),
    ] {
        let e = refused(&path_scene(render, material));
        assert!(e.starts_with("s.toml:"), "{e}");
        assert!(e.contains(key), "want {key}: {e}");
    }
}

/// `[render] denoise`: off by default, on when true, refused with the
/// Whitted integrator and when not a boolean, in one line naming the key.
#[test]
fn denoise_is_read_and_needs_the_path_tracer() {
    let off = parse(&path_scene("", "diffuse = [1, 1, 1]")).unwrap();
    assert!(!off.render.denoise);
    let on = parse(&path_scene("denoise = true", "diffuse = [1, 1, 1]")).unwrap();
    assert!(on.render.denoise);
    let no = parse(&path_scene("denoise = false", "diffuse = [1, 1, 1]")).unwrap();
    assert!(!no.render.denoise);
    let whitted = format!(
        "{CAMERA}[render]\ndenoise = true\n[[lights]]\nposition = [0, 5, 5]\n[materials.m]\ndiffuse = [1, 1, 1]\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n"
    );
    let e = refused(&whitted);
    assert!(
        e.starts_with("s.toml:5:") && e.contains("render.denoise") && e.contains("path"),
        "{e}"
    );
    assert!(parse(&whitted.replace("denoise = true", "denoise = false")).is_ok());
    let e = refused(&path_scene("denoise = 1", "diffuse = [1, 1, 1]"));
    assert!(e.contains("denoise"), "{e}");
}

/// A scene written back as text reads back equal, the path keys included.
#[test]
fn path_scenes_round_trip_through_scene_text() {
    let s = parse(&path_scene(
        "samples = 3\nseed = 9\nexposure = 1\ndenoise = true",
        "base_color = [0.9, 0.5, 0.1]\nmetallic = 0.5\nemission = [1, 2, 3]",
    ))
    .unwrap();
    let text = super::write::scene_text(&s, SceneFormat::Toml).unwrap();
    assert_eq!(parse(&text).unwrap(), s);
}
