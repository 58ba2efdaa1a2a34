//! `[[lights]]` kinds: point (the default), spot (`direction`, `inner_cone`,
//! `outer_cone` in degrees) and directional (`direction`, no position); each
//! bad key is a one-line error naming its file, line and key; a point or
//! spot light's `reference_distance`.

use super::*;

#[test]
fn spot_and_directional_lights_keep_their_keys() {
    let doc = base()
        .set("lights[1].kind", "\"spot\"")
        .set("lights[1].position", "[0, 4, 0]")
        .set("lights[1].direction", "[0, -2, 0]")
        .set("lights[1].inner_cone", "10")
        .set("lights[1].outer_cone", "30")
        .set("lights[2].kind", "\"directional\"")
        .set("lights[2].direction", "[1, -1, 0]")
        .set("lights[3].kind", "\"spot\"")
        .set("lights[3].position", "[1, 1, 1]")
        .set("lights[3].direction", "[0, 0, -1]");
    let lights = assert_accepted(&doc).lights;
    assert_eq!(lights[0].kind, LightKind::Point);
    assert_eq!(
        lights[1].kind,
        LightKind::Spot {
            direction: DVec3::NEG_Y,
            inner_degrees: 10.0,
            outer_degrees: 30.0
        }
    );
    assert_eq!(lights[1].position, DVec3::new(0.0, 4.0, 0.0));
    let LightKind::Directional { direction } = lights[2].kind else {
        panic!("{:?}", lights[2].kind);
    };
    assert!((direction - DVec3::new(1.0, -1.0, 0.0).normalize()).length() < 1e-15);
    // glTF's default cone: inner 0, outer 45 degrees.
    assert_eq!(
        lights[3].kind,
        LightKind::Spot {
            direction: DVec3::NEG_Z,
            inner_degrees: 0.0,
            outer_degrees: 45.0
        }
    );
}

#[test]
fn light_kinds_write_back_as_they_were_read() {
    let doc = base()
        .set("lights[1].kind", "\"spot\"")
        .set("lights[1].position", "[0, 4, 0]")
        .set("lights[1].direction", "[0, -1, 0]")
        .set("lights[1].outer_cone", "60")
        .set("lights[2].kind", "\"directional\"")
        .set("lights[2].direction", "[0, 0, -1]");
    let scene = assert_accepted(&doc);
    for format in [SceneFormat::Toml, SceneFormat::Json] {
        let text = kdray_core::scene::scene_text(&scene, format).unwrap();
        assert_eq!(parse_ok(&text, format).lights, scene.lights, "{format:?}");
    }
}

#[test]
fn bad_light_kind_keys_are_refused_naming_the_key() {
    let spot = || {
        base()
            .set("lights[1].kind", "\"spot\"")
            .set("lights[1].position", "[0, 4, 0]")
            .set("lights[1].direction", "[0, -1, 0]")
    };
    let directional = || {
        base()
            .set("lights[1].kind", "\"directional\"")
            .set("lights[1].direction", "[0, -1, 0]")
    };
    assert_rejected(
        &spot().set("lights[1].outer_cone", "95"),
        "lights[1].outer_cone",
        &["between 0 and 90"],
    );
    assert_rejected(
        &spot().set("lights[1].inner_cone", "-1"),
        "lights[1].inner_cone",
        &["between 0 and 90"],
    );
    assert_rejected(
        &spot().set("lights[1].inner_cone", "50"),
        "lights[1].inner_cone",
        &["inner_cone must be less than outer_cone"],
    );
    assert_rejected(
        &spot().set("lights[1].direction", "[0, 0, 0]"),
        "lights[1].direction",
        &["zero"],
    );
    assert_rejected(
        &directional().set("lights[1].direction", "[0, 0, 0]"),
        "lights[1].direction",
        &["zero"],
    );
    assert_rejected(
        &directional().set("lights[1].position", "[1, 2, 3]"),
        "lights[1].position",
        &["directional light has no position"],
    );
    assert_rejected(
        &base().set("lights[0].direction", "[0, -1, 0]"),
        "lights[0].direction",
        &["point light has no direction"],
    );
    assert_rejected(
        &base().set("lights[1].kind", "\"directional\""),
        "lights[1]",
        &["missing field `direction`", "directional light"],
    );
    assert_rejected(
        &base()
            .set("lights[1].kind", "\"spot\"")
            .set("lights[1].direction", "[0, -1, 0]"),
        "lights[1]",
        &["missing field `position`", "spot light"],
    );
    assert_rejected(
        &base().set("lights[1].kind", "\"area\""),
        "lights[1].kind",
        &["spot", "directional"],
    );
    // An animation may key a directional light's colour, not a position.
    let keyed = directional()
        .set("animation.frames", "4")
        .set("animation.light_keys[0].frame", "2")
        .set("animation.light_keys[0].light", "1");
    assert_accepted(
        &keyed
            .clone()
            .set("animation.light_keys[0].color", "[0.5, 0.5, 0.5]"),
    );
    assert_rejected(
        &keyed.set("animation.light_keys[0].position", "[1, 2, 3]"),
        "animation.light_keys[0].position",
        &["light 1 is directional"],
    );
}

/// `reference_distance`: kept for point and spot lights (the path tracer's
/// intensity scale `pi r^2`), written back, refused for a directional
/// light and when not a positive distance, naming the key.
#[test]
fn a_reference_distance_is_read_written_back_and_checked() {
    let doc = base()
        .set("lights[0].reference_distance", "2.5")
        .set("lights[1].kind", "\"spot\"")
        .set("lights[1].position", "[0, 4, 0]")
        .set("lights[1].direction", "[0, -1, 0]")
        .set("lights[1].reference_distance", "4");
    let scene = assert_accepted(&doc);
    assert_eq!(scene.lights[0].reference_distance, Some(2.5));
    assert_eq!(scene.lights[1].reference_distance, Some(4.0));
    let plain = assert_accepted(&base()).lights[0];
    assert_eq!(plain.reference_distance, None);
    let pi = std::f64::consts::PI;
    assert_eq!(scene.lights[0].path_intensity_scale(), pi * 6.25);
    assert_eq!(plain.path_intensity_scale(), 1.0);
    for format in [SceneFormat::Toml, SceneFormat::Json] {
        let text = kdray_core::scene::scene_text(&scene, format).unwrap();
        assert_eq!(parse_ok(&text, format).lights, scene.lights, "{format:?}");
    }
    for bad in ["0", "-1", "2e15"] {
        assert_rejected(
            &base().set("lights[0].reference_distance", bad),
            "lights[0].reference_distance",
            &["greater than 0"],
        );
    }
    assert_rejected(
        &base()
            .set("lights[1].kind", "\"directional\"")
            .set("lights[1].direction", "[0, -1, 0]")
            .set("lights[1].reference_distance", "3"),
        "lights[1].reference_distance",
        &["directional light has no reference_distance"],
    );
}
