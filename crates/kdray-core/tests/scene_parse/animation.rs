//! The `[animation]` table: the camera at each frame (`Scene::camera_at`)
//! against the formulas of docs/scene-format.md worked out by hand, the
//! lights at each frame (`Scene::frame`) under `[[animation.light_keys]]`,
//! the table's rules (each error at its key and line, per-frame faults
//! naming the frame), and the scene writer's round trip.

use super::*;
use kdray_core::scene::Animation;

/// The base scene (camera at (0, 0, 1) looking at the origin, up +y,
/// vfov 60) with an animation of `frames` frames.
fn animated(frames: &str) -> Doc {
    base().set("animation.frames", frames)
}

#[track_caller]
fn assert_camera_close(got: Camera, want: Camera) {
    assert_close(got.position, want.position);
    assert_close(got.look_at, want.look_at);
    assert_close(got.up, want.up);
    assert!(
        (got.vfov_degrees - want.vfov_degrees).abs() < 1e-12,
        "vfov {} != {}",
        got.vfov_degrees,
        want.vfov_degrees
    );
}

// ============================================================== camera_at

#[test]
fn a_scene_without_animation_has_one_frame_and_its_camera_at_every_frame() {
    let scene = assert_accepted(&base());
    assert_eq!(scene.animation, None);
    assert_eq!(scene.frame_count(), 1);
    for frame in [0, 1, 99] {
        assert_eq!(scene.camera_at(frame), scene.camera);
    }
}

#[test]
fn the_defaults_are_24_fps_no_orbit_and_no_keys() {
    let scene = assert_accepted(&animated("10"));
    let a = scene.animation.as_ref().unwrap();
    assert_eq!(
        *a,
        Animation {
            frames: 10,
            fps: 24.0,
            orbit_degrees: 0.0,
            keys: Vec::new(),
            light_keys: Vec::new(),
        }
    );
    assert_eq!(scene.frame_count(), 10);
    for frame in 0..10 {
        assert_eq!(scene.camera_at(frame), scene.camera);
    }
}

#[test]
fn frame_0_without_keys_is_the_scene_camera_exactly() {
    let doc = base()
        .set("camera.position", "[0.1, 0.7, 2.3]")
        .set("camera.look_at", "[0.3, -0.2, 0.9]")
        .set("animation.frames", "7")
        .set("animation.orbit", "123.4");
    let scene = assert_accepted(&doc);
    assert_eq!(scene.camera_at(0), scene.camera);
}

/// Looking at (1, 2, 3) from (0, 0, 1), up +y: the offset (-1, -2, -2)
/// turns counter-clockwise seen from above, a quarter turn a frame.
#[test]
fn an_orbit_of_360_over_4_frames_turns_the_camera_in_quarter_turns() {
    let doc = base()
        .set("camera.look_at", "[1, 2, 3]")
        .set("animation.frames", "4")
        .set("animation.orbit", "360");
    let scene = assert_accepted(&doc);
    let look_at = DVec3::new(1.0, 2.0, 3.0);
    let offsets = [
        DVec3::new(-1.0, -2.0, -2.0),
        DVec3::new(-2.0, -2.0, 1.0),
        DVec3::new(1.0, -2.0, 2.0),
        DVec3::new(2.0, -2.0, -1.0),
    ];
    for (frame, offset) in offsets.into_iter().enumerate() {
        let camera = scene.camera_at(frame as u32);
        assert_camera_close(
            camera,
            Camera {
                position: look_at + offset,
                ..scene.camera
            },
        );
    }
    // A negative orbit turns the other way.
    let scene = assert_accepted(&doc.set("animation.orbit", "-360"));
    assert_close(scene.camera_at(1).position, look_at + offsets[3]);
}

/// The orbit's axis is the frame's up vector: here a key at frame 0 sets
/// up to +x, so the camera at (0, 0, 1) turns towards -y.
#[test]
fn the_orbit_turns_about_the_frames_own_up_axis() {
    let doc = animated("4")
        .set("animation.orbit", "360")
        .set("animation.keys[0].frame", "0")
        .set("animation.keys[0].up", "[2, 0, 0]");
    let scene = assert_accepted(&doc);
    assert_eq!(scene.camera_at(0).up, DVec3::new(2.0, 0.0, 0.0));
    assert_close(scene.camera_at(1).position, DVec3::new(0.0, -1.0, 0.0));
    assert_close(scene.camera_at(2).position, DVec3::new(0.0, 0.0, -1.0));
}

/// Four keys setting different fields; at its frame each key's fields are
/// exactly what it says.
#[test]
fn keys_are_passed_through_exactly_at_their_frames() {
    let doc = animated("40")
        .set("animation.keys[0].frame", "5")
        .set("animation.keys[0].position", "[0.3, 0.1, 2.7]")
        .set("animation.keys[0].vfov", "35.5")
        .set("animation.keys[1].frame", "12")
        .set("animation.keys[1].look_at", "[0.25, -0.5, 0.125]")
        .set("animation.keys[1].up", "[0.1, 1, 0.3]")
        .set("animation.keys[2].frame", "13")
        .set("animation.keys[2].position", "[-1.7, 0.9, 1.1]")
        .set("animation.keys[3].frame", "39")
        .set("animation.keys[3].position", "[2, 2, 2]")
        .set("animation.keys[3].look_at", "[0.5, 0.5, 0.5]")
        .set("animation.keys[3].vfov", "80");
    let scene = assert_accepted(&doc);
    let at = |f| scene.camera_at(f);
    assert_eq!(at(5).position, DVec3::new(0.3, 0.1, 2.7));
    assert_eq!(at(5).vfov_degrees, 35.5);
    assert_eq!(at(12).look_at, DVec3::new(0.25, -0.5, 0.125));
    assert_eq!(at(12).up, DVec3::new(0.1, 1.0, 0.3));
    assert_eq!(at(13).position, DVec3::new(-1.7, 0.9, 1.1));
    assert_eq!(at(39).position, DVec3::new(2.0, 2.0, 2.0));
    assert_eq!(at(39).look_at, DVec3::new(0.5, 0.5, 0.5));
    assert_eq!(at(39).vfov_degrees, 80.0);
    // And at frame 0 the scene camera, for every field.
    assert_eq!(at(0), scene.camera);
}

/// vfov: 60 at frame 0 ([camera]), 30 at frame 10, 90 at frame 20, then held.
#[test]
fn vfov_is_linear_between_keys_and_held_after_the_last() {
    let doc = animated("30")
        .set("animation.keys[0].frame", "10")
        .set("animation.keys[0].vfov", "30")
        .set("animation.keys[1].frame", "20")
        .set("animation.keys[1].vfov", "90");
    let scene = assert_accepted(&doc);
    for (frame, want) in [
        (0, 60.0),
        (5, 45.0),
        (8, 36.0),
        (10, 30.0),
        (15, 60.0),
        (19, 84.0),
        (20, 90.0),
        (29, 90.0),
    ] {
        let got = scene.camera_at(frame).vfov_degrees;
        assert!((got - want).abs() < 1e-12, "frame {frame}: {got} != {want}");
    }
}

/// Positions x = 0 ([camera]), 1, 2, 3 at frames 0, 10, 20, 30: uniform
/// Catmull-Rom is linear where both neighbours exist (x = 1.5 at frame
/// 15), and eases in and out of the doubled end points: on the first
/// segment, with p0 = p1 = 0, p2 = 1, p3 = 2, at t = 1/2 the formula gives
/// 0.5 (2*0 + 1/2 + 2/4 - 1/8) = 0.4375; after the last key x is held.
#[test]
fn positions_follow_uniform_catmull_rom_with_doubled_ends() {
    let doc = base()
        .set("camera.position", "[0, 0, 5]")
        .set("animation.frames", "40")
        .set("animation.keys[0].frame", "10")
        .set("animation.keys[0].position", "[1, 0, 5]")
        .set("animation.keys[1].frame", "20")
        .set("animation.keys[1].position", "[2, 0, 5]")
        .set("animation.keys[2].frame", "30")
        .set("animation.keys[2].position", "[3, 0, 5]");
    let scene = assert_accepted(&doc);
    let x = |f| scene.camera_at(f).position;
    assert_close(x(15), DVec3::new(1.5, 0.0, 5.0));
    assert_close(x(12), DVec3::new(1.2, 0.0, 5.0));
    assert_close(x(5), DVec3::new(0.4375, 0.0, 5.0));
    assert_close(x(25), DVec3::new(3.0 - 0.4375, 0.0, 5.0));
    assert_eq!(x(35), DVec3::new(3.0, 0.0, 5.0));
    // A bend: the general formula, checked against an independent evaluation.
    let doc = doc.set("animation.keys[1].position", "[2, 1, 4]");
    let scene = assert_accepted(&doc);
    let p = [
        DVec3::new(0.0, 0.0, 5.0),
        DVec3::new(1.0, 0.0, 5.0),
        DVec3::new(2.0, 1.0, 4.0),
        DVec3::new(3.0, 0.0, 5.0),
    ];
    let t: f64 = 0.3;
    let want = 0.5
        * (2.0 * p[1]
            + (p[2] - p[0]) * t
            + (2.0 * p[0] - 5.0 * p[1] + 4.0 * p[2] - p[3]) * t.powi(2)
            + (-p[0] + 3.0 * p[1] - 3.0 * p[2] + p[3]) * t.powi(3));
    assert_close(scene.camera_at(13).position, want);
}

/// Each field is interpolated over the keys that set it alone: a key that
/// sets only vfov leaves the position's spline alone.
#[test]
fn a_field_a_key_leaves_out_is_interpolated_from_the_keys_that_set_it() {
    let doc = base()
        .set("camera.position", "[0, 0, 5]")
        .set("animation.frames", "21")
        .set("animation.keys[0].frame", "10")
        .set("animation.keys[0].vfov", "20")
        .set("animation.keys[1].frame", "20")
        .set("animation.keys[1].position", "[2, 0, 5]");
    let scene = assert_accepted(&doc);
    // x runs from 0 to 2 over frames 0..20 with both ends doubled: at the
    // middle (t = 1/2) the ease-in-out curve is halfway.
    assert_close(scene.camera_at(10).position, DVec3::new(1.0, 0.0, 5.0));
    assert_eq!(scene.camera_at(10).vfov_degrees, 20.0);
    assert_eq!(scene.camera_at(20).vfov_degrees, 20.0);
}

#[test]
fn a_key_at_frame_0_replaces_the_camera_fields_it_sets() {
    let doc = animated("3")
        .set("animation.keys[0].frame", "0")
        .set("animation.keys[0].position", "[0, 1, 3]");
    let scene = assert_accepted(&doc);
    for frame in 0..3 {
        assert_eq!(
            scene.camera_at(frame),
            Camera {
                position: DVec3::new(0.0, 1.0, 3.0),
                ..scene.camera
            }
        );
    }
}

#[test]
fn the_camera_path_answers_as_camera_at_does() {
    let doc = animated("30")
        .set("animation.orbit", "90")
        .set("animation.keys[0].frame", "10")
        .set("animation.keys[0].position", "[1, 1, 2]")
        .set("animation.keys[1].frame", "25")
        .set("animation.keys[1].vfov", "40");
    let scene = assert_accepted(&doc);
    let path = scene.camera_path();
    for frame in 0..30 {
        assert_eq!(path.camera_at(frame), scene.camera_at(frame));
    }
}

// ============================================================== rules

#[test]
fn frames_is_required() {
    let doc = base().set("animation.fps", "30");
    for text in doc.both() {
        let e = text.parse_err();
        let line = text.table_line("animation");
        assert_error(
            &e,
            text.file(),
            Some(line),
            Some("animation"),
            &["missing field `frames`"],
        );
    }
}

#[test]
fn frames_must_be_in_1_to_100000() {
    for bad in ["0", "100001", "4000000000"] {
        assert_rejected(&animated(bad), "animation.frames", &["1..=100000"]);
    }
    for good in ["1", "100000"] {
        assert_accepted(&animated(good));
    }
}

#[test]
fn fps_must_be_a_finite_positive_number() {
    for bad in ["0", "-24", "0.0"] {
        assert_rejected(
            &animated("10").set("animation.fps", bad),
            "animation.fps",
            &["> 0"],
        );
    }
    for bad in ["nan", "inf", "-inf"] {
        let text = animated("10").set("animation.fps", bad).toml();
        assert_rejected_text(&text, "animation.fps", &["finite"]);
    }
    let scene = assert_accepted(&animated("10").set("animation.fps", "29.97"));
    assert_eq!(scene.animation.unwrap().fps, 29.97);
}

#[test]
fn orbit_must_be_finite() {
    let text = animated("10").set("animation.orbit", "nan").toml();
    assert_rejected_text(&text, "animation.orbit", &["finite"]);
}

#[test]
fn unknown_keys_in_the_animation_are_rejected() {
    assert_rejected(
        &animated("10").set("animation.loop", "1"),
        "animation.loop",
        &["unknown field `loop`"],
    );
    assert_rejected(
        &animated("10")
            .set("animation.keys[0].frame", "1")
            .set("animation.keys[0].fov", "30"),
        "animation.keys[0].fov",
        &["unknown field `fov`"],
    );
}

#[test]
fn a_key_frame_must_lie_inside_the_animation() {
    for bad in ["4", "5", "1000"] {
        assert_rejected(
            &animated("4")
                .set("animation.keys[0].frame", bad)
                .set("animation.keys[0].vfov", "30"),
            "animation.keys[0].frame",
            &["0..4", bad],
        );
    }
    assert_accepted(
        &animated("4")
            .set("animation.keys[0].frame", "3")
            .set("animation.keys[0].vfov", "30"),
    );
}

fn two_keys(first: &str, second: &str) -> Doc {
    animated("20")
        .set("animation.keys[0].frame", first)
        .set("animation.keys[0].vfov", "30")
        .set("animation.keys[1].frame", second)
        .set("animation.keys[1].vfov", "40")
}

#[test]
fn keys_must_be_in_increasing_frame_order() {
    assert_rejected(
        &two_keys("7", "3"),
        "animation.keys[1].frame",
        &["increasing", "animation.keys[0] is at frame 7"],
    );
}

#[test]
fn a_frame_must_not_be_keyed_twice() {
    assert_rejected(
        &two_keys("7", "7"),
        "animation.keys[1].frame",
        &["frame 7 is keyed twice", "animation.keys[0]"],
    );
}

#[test]
fn a_key_must_set_a_camera_field() {
    assert_rejected(
        &animated("10").set("animation.keys[0].frame", "2"),
        "animation.keys[0]",
        &["none of position, look_at, up, vfov"],
    );
}

#[test]
fn key_values_follow_the_camera_rules() {
    let key = |field: &str, value: &str| {
        animated("10")
            .set("animation.keys[0].frame", "1")
            .set(&format!("animation.keys[0].{field}"), value)
    };
    for bad in ["0", "180", "-5"] {
        assert_rejected(&key("vfov", bad), "animation.keys[0].vfov", &["(0, 180)"]);
    }
    assert_rejected(
        &key("position", "[0, 2e15, 0]"),
        "animation.keys[0].position[1]",
        &["1e15"],
    );
    assert_rejected_text(
        &key("look_at", "[0, 0, inf]").toml(),
        "animation.keys[0].look_at[2]",
        &["finite"],
    );
    assert_rejected_text(
        &key("up", "[nan, 1, 0]").toml(),
        "animation.keys[0].up[0]",
        &["finite"],
    );
}

/// up turns from +y (frame 0) to -y (frame 10); with both ends doubled the
/// spline is symmetric and passes through zero at frame 5, the middle.
#[test]
fn an_interpolated_up_that_vanishes_or_meets_the_view_names_its_frame() {
    let doc = animated("20")
        .set("animation.keys[0].frame", "10")
        .set("animation.keys[0].up", "[0, -1, 0]");
    assert_rejected(
        &doc,
        "animation.keys[0]",
        &["at frame 5", "up [0.0, 0.0, 0.0]", "parallel"],
    );
    // At a key's own frame: the key's segment is its own.
    let doc = two_keys("3", "9").set("animation.keys[1].up", "[0, 0, -4]");
    assert_rejected(
        &doc,
        "animation.keys[1]",
        &["at frame 9", "parallel", "view direction"],
    );
    // Turning up through +x instead never meets the view (-z).
    let doc = animated("20")
        .set("animation.keys[0].frame", "10")
        .set("animation.keys[0].up", "[1, 0, 0]")
        .set("animation.keys[1].frame", "19")
        .set("animation.keys[1].up", "[0, -1, 0]");
    assert_accepted(&doc);
}

#[test]
fn a_camera_that_reaches_its_look_at_point_names_the_frame() {
    let doc = animated("20")
        .set("animation.keys[0].frame", "4")
        .set("animation.keys[0].vfov", "50")
        .set("animation.keys[1].frame", "12")
        .set("animation.keys[1].position", "[0, 0, 0]");
    assert_rejected(
        &doc,
        "animation.keys[1]",
        &["at frame 12", "look_at equals its position"],
    );
}

/// An orbit keeps the distance to look_at but can carry the camera past
/// ±1e15: half a turn takes it from 1e15 behind look_at to 3e15.
#[test]
fn an_orbit_beyond_the_coordinate_range_is_blamed_on_the_orbit() {
    let doc = base()
        .set("camera.position", "[-1e15, 0, 0]")
        .set("camera.look_at", "[1e15, 0, 0]")
        .set("animation.frames", "2")
        .set("animation.orbit", "360");
    assert_rejected(&doc, "animation.orbit", &["at frame 1", "position", "1e15"]);
}

// ============================================================== light keys

/// The base scene with a second light and an animation of 20 frames.
fn two_lights() -> Doc {
    animated("20")
        .set("lights[1].position", "[-4, 2, 0]")
        .set("lights[1].diffuse", "[0.5, 0.5, 0.5]")
}

/// `two_lights` with one key of `light` at `frame` setting `field`.
fn light_key(light: &str, frame: &str, field: &str, value: &str) -> Doc {
    two_lights()
        .set("animation.light_keys[0].frame", frame)
        .set("animation.light_keys[0].light", light)
        .set(&format!("animation.light_keys[0].{field}"), value)
}

/// A light's track starts at its `[[lights]]` entry at frame 0 (a factor of
/// 1 on its colours), as a camera field's starts at `[camera]`. With one key
/// at frame 10 the position runs on the spline with both ends doubled,
/// which between two points is (t + 3 t^2 - 2 t^3) / 2 of the way (1/2 at
/// t = 1/2, 38/250 at t = 1/5), the colour factor on a straight line; after
/// the key both are held, and the other light stays as written.
#[test]
fn a_light_runs_from_its_entry_to_its_keys_and_holds_the_last() {
    let doc = two_lights()
        .set("animation.light_keys[0].frame", "10")
        .set("animation.light_keys[0].light", "1")
        .set("animation.light_keys[0].position", "[4, 2, 0]")
        .set("animation.light_keys[0].color", "[0, 2, 1]");
    let scene = assert_accepted(&doc);
    let first = scene.lights[1];
    assert_eq!(scene.frame(0).lights, scene.lights);
    let half = scene.frame(5).lights[1];
    assert_eq!(half.position, DVec3::new(0.0, 2.0, 0.0));
    assert_eq!(half.diffuse, DVec3::new(0.25, 0.75, 0.5));
    assert_eq!(half.ambient, DVec3::new(0.5, 1.5, 1.0));
    let x = scene.frame(2).lights[1].position.x;
    assert!((x - (-4.0 + 8.0 * 38.0 / 250.0)).abs() < 1e-12, "{x}");
    for frame in [10, 11, 19] {
        let held = scene.frame(frame).lights[1];
        assert_eq!(held.position, DVec3::new(4.0, 2.0, 0.0), "frame {frame}");
        assert_eq!(held.diffuse, DVec3::new(0.0, 1.0, 0.5), "frame {frame}");
        assert_eq!(held.specular, DVec3::new(0.0, 2.0, 1.0), "frame {frame}");
        assert_eq!(scene.frame(frame).lights[0], scene.lights[0]);
    }
    assert_eq!(scene.lights[1], first, "the scene keeps its [[lights]]");
    // Lights do not change the camera, and the orbit does not move lights.
    let orbiting = assert_accepted(&doc.clone().set("animation.orbit", "90"));
    for frame in [0, 5, 12] {
        assert_eq!(orbiting.frame(frame).lights, scene.frame(frame).lights);
        assert_eq!(orbiting.frame(frame).camera, orbiting.camera_at(frame));
    }
}

/// A key at frame 0 replaces the `[[lights]]` value from the start; a key
/// that sets only the colour leaves the position where it is.
#[test]
fn a_light_key_at_frame_0_replaces_the_entry() {
    let scene = assert_accepted(
        &light_key("0", "0", "position", "[1, 2, 3]")
            .set("animation.light_keys[1].frame", "4")
            .set("animation.light_keys[1].light", "0")
            .set("animation.light_keys[1].color", "[0.5, 0.5, 0.5]"),
    );
    for frame in [0, 2, 4, 19] {
        assert_eq!(
            scene.frame(frame).lights[0].position,
            DVec3::new(1.0, 2.0, 3.0)
        );
    }
    assert_eq!(scene.frame(2).lights[0].diffuse, DVec3::splat(0.75));
    assert_eq!(scene.frame(0).lights[0].diffuse, DVec3::ONE);
}

#[test]
fn a_light_key_names_an_existing_light() {
    for bad in ["2", "7"] {
        assert_rejected(
            &light_key(bad, "3", "position", "[0, 1, 0]"),
            "animation.light_keys[0].light",
            &["0..2", "[[lights]]", bad],
        );
    }
    assert_accepted(&light_key("1", "3", "position", "[0, 1, 0]"));
}

#[test]
fn a_light_key_frame_must_lie_inside_the_animation() {
    for bad in ["20", "21", "1000"] {
        assert_rejected(
            &light_key("0", bad, "position", "[0, 1, 0]"),
            "animation.light_keys[0].frame",
            &["0..20", bad],
        );
    }
    assert_accepted(&light_key("0", "19", "position", "[0, 1, 0]"));
}

fn two_light_keys(first: (&str, &str), second: (&str, &str)) -> Doc {
    two_lights()
        .set("animation.light_keys[0].light", first.0)
        .set("animation.light_keys[0].frame", first.1)
        .set("animation.light_keys[0].color", "[1, 0, 0]")
        .set("animation.light_keys[1].light", second.0)
        .set("animation.light_keys[1].frame", second.1)
        .set("animation.light_keys[1].color", "[0, 1, 0]")
}

/// The order rules hold per light: keys of different lights may come in
/// any order.
#[test]
fn each_lights_keys_are_in_increasing_frame_order_and_keyed_once() {
    assert_rejected(
        &two_light_keys(("1", "7"), ("1", "3")),
        "animation.light_keys[1].frame",
        &[
            "increasing",
            "animation.light_keys[0] (light 1) is at frame 7",
        ],
    );
    assert_rejected(
        &two_light_keys(("0", "7"), ("0", "7")),
        "animation.light_keys[1].frame",
        &[
            "light 0's frame 7 is keyed twice",
            "animation.light_keys[0]",
        ],
    );
    let scene = assert_accepted(&two_light_keys(("1", "7"), ("0", "3")));
    assert_eq!(scene.frame(7).lights[1].diffuse, DVec3::new(0.5, 0.0, 0.0));
    assert_eq!(scene.frame(3).lights[0].diffuse, DVec3::new(0.0, 1.0, 0.0));
    assert_accepted(&two_light_keys(("1", "7"), ("0", "7")));
}

#[test]
fn a_light_key_must_set_a_position_or_a_color() {
    assert_rejected(
        &two_lights()
            .set("animation.light_keys[0].frame", "2")
            .set("animation.light_keys[0].light", "0"),
        "animation.light_keys[0]",
        &["neither position nor color"],
    );
    assert_rejected(
        &light_key("0", "2", "intensity", "3"),
        "animation.light_keys[0].intensity",
        &["unknown field"],
    );
}

#[test]
fn light_key_values_follow_the_light_rules() {
    assert_rejected(
        &light_key("0", "1", "position", "[0, 2e15, 0]"),
        "animation.light_keys[0].position[1]",
        &["1e15"],
    );
    assert_rejected_text(
        &light_key("0", "1", "position", "[0, 0, inf]").toml(),
        "animation.light_keys[0].position[2]",
        &["finite"],
    );
    assert_rejected_text(
        &light_key("1", "1", "color", "[nan, 1, 0]").toml(),
        "animation.light_keys[0].color[0]",
        &["finite"],
    );
    assert_rejected(
        &light_key("1", "1", "color", "[0, -0.5, 1]"),
        "animation.light_keys[0].color",
        &[">= 0"],
    );
}

/// Keys far apart on a spline overshoot: from x = 0 to 9e14 and back to 0
/// over two keys the spline passes x = 9e14 * 1.125 > 1e15 between them.
/// A colour factor times a huge colour may overflow. Either names the frame.
#[test]
fn a_light_that_leaves_the_coordinate_range_or_overflows_names_its_frame() {
    let doc = two_lights()
        .set("lights[0].position", "[0, 0, 0]")
        .set("animation.light_keys[0].frame", "4")
        .set("animation.light_keys[0].light", "0")
        .set("animation.light_keys[0].position", "[9e14, 0, 0]")
        .set("animation.light_keys[1].frame", "8")
        .set("animation.light_keys[1].light", "0")
        .set("animation.light_keys[1].position", "[9e14, 0, 0]")
        .set("animation.light_keys[2].frame", "12")
        .set("animation.light_keys[2].light", "0")
        .set("animation.light_keys[2].position", "[0, 0, 0]");
    assert_rejected(
        &doc,
        "animation.light_keys[0]",
        &["at frame 6", "light 0's position", "1e15"],
    );
    let huge = light_key("1", "5", "color", "[2, 1, 1]").set("lights[1].specular", "[1e308, 0, 0]");
    // 1e308 * (1 + f / 5) passes f64::MAX (1.8e308) at frame 4.
    assert_rejected(
        &huge,
        "animation.light_keys[0]",
        &["at frame 4", "light 1's specular", "not finite"],
    );
}

#[test]
fn the_writer_writes_the_animation_back() {
    let doc = animated("48")
        .set("animation.fps", "30")
        .set("animation.orbit", "-90.5")
        .set("animation.keys[0].frame", "0")
        .set("animation.keys[0].up", "[0.1, 1, 0]")
        .set("animation.keys[1].frame", "17")
        .set("animation.keys[1].position", "[0.3, 0.2, 1.5]")
        .set("animation.keys[1].look_at", "[0.1, 0, 0]")
        .set("animation.keys[2].frame", "47")
        .set("animation.keys[2].vfov", "75")
        .set("animation.light_keys[0].frame", "20")
        .set("animation.light_keys[0].light", "0")
        .set("animation.light_keys[0].position", "[1.5, 2, -0.25]")
        .set("animation.light_keys[1].frame", "30")
        .set("animation.light_keys[1].light", "0")
        .set("animation.light_keys[1].color", "[0.5, 0.1, 2]");
    let scene = assert_accepted(&doc);
    assert_eq!(scene.animation.as_ref().unwrap().light_keys.len(), 2);
    for format in [SceneFormat::Toml, SceneFormat::Json] {
        let text = kdray_core::scene::scene_text(&scene, format).unwrap();
        assert!(text.contains("animation"), "{text}");
        assert_eq!(parse_ok(&text, format), scene, "{format:?}:\n{text}");
    }
    // A still scene writes no animation.
    let still = assert_accepted(&base());
    let text = kdray_core::scene::scene_text(&still, SceneFormat::Toml).unwrap();
    assert!(!text.contains("animation"), "{text}");
}

// ============================================================== shipped scene

/// scenes/orbit.toml: 48 frames of one turn, so frame 24 looks from the
/// far side: the offset from look_at reversed in x and z.
#[test]
fn the_orbit_scene_circles_its_look_at_point() {
    let path = common::repo_path("scenes/orbit.toml");
    let scene = load_ok(&path);
    assert_eq!(scene.frame_count(), 48);
    assert_eq!(scene.animation.as_ref().unwrap().orbit_degrees, 360.0);
    let c = scene.camera;
    let offset = c.position - c.look_at;
    let half = scene.camera_at(24);
    assert_close(
        half.position - c.look_at,
        DVec3::new(-offset.x, offset.y, -offset.z),
    );
    assert_eq!(half.look_at, c.look_at);
}
