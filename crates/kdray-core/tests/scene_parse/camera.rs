//! The `[camera]` table: its defaults and its rules (a field of view in
//! (0, 180), a look-at point apart from the position, an up vector that is
//! not parallel to the view).

use super::*;

#[test]
fn defaults() {
    let scene = assert_accepted(&base());
    assert_eq!(
        scene.camera,
        Camera {
            position: DVec3::new(0.0, 0.0, 1.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 60.0,
        }
    );
}

#[test]
fn vfov_must_be_inside_0_180() {
    for bad in ["0", "0.0", "-10", "180", "180.0", "200"] {
        assert_rejected(
            &base().set("camera.vfov", bad),
            "camera.vfov",
            &["(0, 180)"],
        );
    }
    for (good, value) in [
        ("0.001", 0.001),
        ("1", 1.0),
        ("58.7155", 58.7155),
        ("179.999", 179.999),
    ] {
        let scene = assert_accepted(&base().set("camera.vfov", good));
        assert_eq!(scene.camera.vfov_degrees, value);
    }
}

#[test]
fn up_must_not_be_parallel_to_the_view_direction() {
    // The view direction is -z.
    for bad in [
        "[0, 0, -1]",
        "[0, 0, 1]",
        "[0, 0, 7.5]",
        "[0, 0, 0]",
        "[0, 1e-12, 1]",
    ] {
        assert_rejected(
            &base().set("camera.up", bad),
            "camera.up",
            &["parallel", "look_at - position"],
        );
    }
    // Any other up is fine; it need not be unit length or perpendicular.
    for good in [
        "[0, 1, 0]",
        "[1, 0, 0]",
        "[0, 3, 3]",
        "[0, 1e-6, 1]",
        "[0, -2, 0]",
    ] {
        assert_accepted(&base().set("camera.up", good));
    }
    let scene = assert_accepted(&base().set("camera.up", "[0, 3, 3]"));
    assert_eq!(scene.camera.up, DVec3::new(0.0, 3.0, 3.0));
}

#[test]
fn the_default_up_is_checked_too_and_says_so() {
    // Looking straight down: the default up [0, 1, 0] is parallel. The
    // file has no camera.up, so the error is on the [camera] line.
    let doc = base().set("camera.position", "[0, 5, 0]");
    for text in doc.both() {
        let e = text.parse_err();
        let line = text.line("camera");
        assert_error(
            &e,
            text.file(),
            Some(line),
            Some("camera.up"),
            &["parallel", "default"],
        );
    }
    assert_accepted(&doc.set("camera.up", "[0, 0, -1]"));
}

#[test]
fn look_at_must_differ_from_position() {
    let doc = base().set("camera.look_at", "[0, 0, 1]");
    assert_rejected(&doc, "camera.look_at", &["differ", "position"]);
    // A tiny or a large view direction is fine.
    assert_accepted(&base().set("camera.position", "[0, 0, 1e-300]"));
    assert_accepted(&base().set("camera.position", "[0, 0, 1e15]"));
}

/// The GPU computes in f32 and squares distances: coordinates beyond
/// ±1e15 (and radii above 1e15) are refused, naming the component.
#[test]
fn coordinates_beyond_f32_range_are_rejected() {
    assert_rejected(
        &base().set("camera.position", "[0, 0, 1e300]"),
        "camera.position[2]",
        &["1e15", "f32"],
    );
    assert_rejected(
        &base().set("camera.look_at", "[-2e15, 0, 0]"),
        "camera.look_at[0]",
        &["1e15"],
    );
}
