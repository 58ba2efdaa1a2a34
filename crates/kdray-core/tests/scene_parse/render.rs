//! The `[render]` table: its defaults and the range of each setting.

use super::*;

const DEFAULTS: RenderSettings = RenderSettings {
    width: 800,
    height: 600,
    min_intensity: 0.05,
    max_depth: 10,
    background: DVec3::ZERO,
    shadow_mode: ShadowMode::Ambient,
    samples: 1,
    integrator: kdray_core::scene::Integrator::Whitted,
    seed: 0,
    tone_map: kdray_core::scene::ToneMap::Aces,
    exposure: 0.0,
    denoise: false,
};

#[test]
fn a_missing_or_empty_render_table_gives_the_defaults() {
    assert_eq!(assert_accepted(&base()).render, DEFAULTS);
    let toml = format!("[render]\n\n{}", base().toml().text);
    assert_eq!(parse_ok(&toml, SceneFormat::Toml).render, DEFAULTS);
    let json = base().json().text.replacen('{', "{\n  \"render\": {},", 1);
    assert_eq!(parse_ok(&json, SceneFormat::Json).render, DEFAULTS);
    assert_eq!(DEFAULTS.samples_per_axis(), 1);
}

#[test]
fn every_render_key_is_read() {
    let doc = base()
        .set("render.width", "1920")
        .set("render.height", "1080")
        .set("render.min_intensity", "0.25")
        .set("render.max_depth", "3")
        .set("render.background", "[0.1, 0.2, 0.3]")
        .set("render.shadow_mode", "\"seed\"")
        .set("render.samples", "16");
    let render = assert_accepted(&doc).render;
    assert_eq!(
        render,
        RenderSettings {
            width: 1920,
            height: 1080,
            min_intensity: 0.25,
            max_depth: 3,
            background: DVec3::new(0.1, 0.2, 0.3),
            shadow_mode: ShadowMode::Seed,
            samples: 16,
            integrator: kdray_core::scene::Integrator::Whitted,
            seed: 0,
            tone_map: kdray_core::scene::ToneMap::Aces,
            exposure: 0.0,
            denoise: false,
        }
    );
    assert_eq!(render.samples_per_axis(), 4);
    let doc = base().set("render.shadow_mode", "\"ambient\"");
    assert_eq!(
        assert_accepted(&doc).render.shadow_mode,
        ShadowMode::Ambient
    );
}

#[test]
fn width_and_height_must_be_1_to_16384() {
    for key in ["render.width", "render.height"] {
        for bad in ["0", "16385", "100000"] {
            assert_rejected(&base().set(key, bad), key, &["1..=16384", bad]);
        }
        for good in ["1", "16384"] {
            assert_accepted(&base().set(key, good));
        }
    }
    // Larger than a u32: a type error, still on the key.
    let doc = base().set("render.width", "5000000000");
    assert_rejected(&doc, "render.width", &["invalid value"]);
}

#[test]
fn min_intensity_must_be_in_0_1() {
    for bad in ["-0.1", "1.01", "2", "-1e-9"] {
        assert_rejected(
            &base().set("render.min_intensity", bad),
            "render.min_intensity",
            &["[0, 1]"],
        );
    }
    for (good, value) in [("0", 0.0), ("1", 1.0), ("0.5", 0.5)] {
        let scene = assert_accepted(&base().set("render.min_intensity", good));
        assert_eq!(scene.render.min_intensity, value);
    }
}

#[test]
fn max_depth_must_be_1_to_64() {
    for bad in ["0", "65", "1000"] {
        assert_rejected(
            &base().set("render.max_depth", bad),
            "render.max_depth",
            &["1..=64", bad],
        );
    }
    for good in [1, 64] {
        let scene = assert_accepted(&base().set("render.max_depth", &good.to_string()));
        assert_eq!(scene.render.max_depth, good);
    }
}

#[test]
fn samples_must_be_a_perfect_square() {
    for bad in ["0", "2", "3", "5", "8", "15", "17", "99", "4294967295"] {
        assert_rejected(
            &base().set("render.samples", bad),
            "render.samples",
            &["perfect square", bad],
        );
    }
    for k in [1u32, 2, 3, 4, 5, 8, 16] {
        let samples = k * k;
        let scene = assert_accepted(&base().set("render.samples", &samples.to_string()));
        assert_eq!(scene.render.samples, samples);
        assert_eq!(scene.render.samples_per_axis(), k);
    }
}

#[test]
fn background_is_a_colour() {
    assert_rejected(
        &base().set("render.background", "[0, -0.5, 0]"),
        "render.background",
        &[">= 0"],
    );
    let scene = assert_accepted(&base().set("render.background", "[0, 0, 2]"));
    assert_eq!(scene.render.background, DVec3::new(0.0, 0.0, 2.0));
}
