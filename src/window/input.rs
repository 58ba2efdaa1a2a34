//! Input mapping: winit events in, the camera controller's inputs and the
//! window's own actions out. Nothing here acts; `app.rs` feeds the inputs
//! to the controller and carries out the actions.

use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};

use super::camera_controller::{Button, ControlKey, Input};

pub const HELP: &str = "\
kdray window controls:
  left drag          orbit around the target point
  right/middle drag  pan
  wheel              zoom toward the target
  W A S D, Q E       fly forward, left, back, right; down, up
  F                  frame the whole scene
  R                  reset to the scene's camera
  P                  save a screenshot (PNG in the current folder)
  B                  toggle k-d tree / brute force
  T                  cycle the k-d walk: restart, ropes, short stack
  K                  cycle the k-d build: sah, median (rebuilds the tree)
  C                  toggle the cost heatmap (work per sample, false colour)
  I                  toggle the integrator: whitted / path (progressive)
  N                  toggle denoising (path tracer only): the still image is
                     shown denoised once it has a few samples per pixel
  [ ]                max_depth down / up
  X                  inspection mode: a left click (no drag) on a pixel draws
                     its rays and the k-d cells their walks visited
  Space              play / pause the scene's animation
  H                  this help
  Esc                quit";

/// What a key does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Action {
    /// W A S D Q E: move while held.
    Fly(ControlKey),
    /// F, R: one camera jump.
    Camera(ControlKey),
    Screenshot,
    ToggleAccel,
    /// T: the next k-d walk (`Traversal::next`).
    CycleTraversal,
    /// K: the next k-d build (`BuildStrategy::next`), rebuilt like a reload.
    CycleBuild,
    /// C: the cost heatmap instead of the shaded image, or back.
    ToggleHeatmap,
    /// I: the other integrator (Whitted or path tracing).
    ToggleIntegrator,
    /// N: denoising on or off (path tracing only; D is a fly key).
    ToggleDenoise,
    DepthDown,
    DepthUp,
    /// Space: play or pause the scene's animation.
    TogglePlay,
    /// X: inspection mode on or off (a click inspects a pixel).
    ToggleInspect,
    Help,
    Quit,
}

/// The window's own keys, by the character they type (lower case), each
/// acting once per press. A new key is one line here, one in [`HELP`] and
/// one arm in `App::handle_key`.
const WINDOW_KEYS: [(&str, Action); 13] = [
    ("f", Action::Camera(ControlKey::FrameAll)),
    ("r", Action::Camera(ControlKey::Reset)),
    ("p", Action::Screenshot),
    ("b", Action::ToggleAccel),
    ("t", Action::CycleTraversal),
    ("k", Action::CycleBuild),
    ("c", Action::ToggleHeatmap),
    ("i", Action::ToggleIntegrator),
    ("n", Action::ToggleDenoise),
    ("[", Action::DepthDown),
    ("]", Action::DepthUp),
    ("x", Action::ToggleInspect),
    ("h", Action::Help),
];

/// The fly keys, by position (W A S D Q E of a US keyboard, on any layout).
fn fly_key(physical: PhysicalKey) -> Option<ControlKey> {
    let PhysicalKey::Code(code) = physical else {
        return None;
    };
    Some(match code {
        KeyCode::KeyW => ControlKey::Forward,
        KeyCode::KeyS => ControlKey::Backward,
        KeyCode::KeyA => ControlKey::Left,
        KeyCode::KeyD => ControlKey::Right,
        KeyCode::KeyQ => ControlKey::Down,
        KeyCode::KeyE => ControlKey::Up,
        _ => return None,
    })
}

/// The action of a key: the fly keys by position, the others by the
/// character they type.
pub fn key_action(physical: PhysicalKey, logical: &Key) -> Option<Action> {
    if let Some(key) = fly_key(physical) {
        return Some(Action::Fly(key));
    }
    let typed = match logical {
        Key::Named(NamedKey::Escape) => return Some(Action::Quit),
        Key::Named(NamedKey::Space) => return Some(Action::TogglePlay),
        Key::Character(c) => c.to_lowercase(),
        _ => return None,
    };
    WINDOW_KEYS
        .iter()
        .find(|(key, _)| *key == typed)
        .map(|&(_, action)| action)
}

/// The camera controller's input for a window event (sizes and positions
/// in physical pixels, as the controller expects).
pub fn controller_input(event: &WindowEvent) -> Option<Input> {
    Some(match event {
        WindowEvent::Resized(size) => Input::Resized {
            width: size.width,
            height: size.height,
        },
        WindowEvent::CursorMoved { position, .. } => Input::CursorMoved {
            x: position.x,
            y: position.y,
        },
        WindowEvent::CursorLeft { .. } => Input::CursorLeft,
        WindowEvent::MouseInput { state, button, .. } => Input::Button {
            button: match button {
                MouseButton::Left => Button::Left,
                MouseButton::Right => Button::Right,
                MouseButton::Middle => Button::Middle,
                _ => return None,
            },
            pressed: *state == ElementState::Pressed,
        },
        WindowEvent::MouseWheel { delta, .. } => match delta {
            MouseScrollDelta::LineDelta(_, y) => Input::WheelLines(*y as f64),
            MouseScrollDelta::PixelDelta(p) => Input::WheelPixels(p.y),
        },
        WindowEvent::Focused(false) => Input::FocusLost,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;
    use crate::window::camera_controller::{Bounds, CameraController};
    use glam::DVec3;
    use winit::dpi::{PhysicalPosition, PhysicalSize};
    use winit::event::DeviceId;

    fn controller() -> CameraController {
        let home = Camera {
            position: DVec3::new(0.0, 0.0, 1.0),
            look_at: DVec3::ZERO,
            up: DVec3::Y,
            vfov_degrees: 90.0,
        };
        let bounds = Bounds {
            min: DVec3::splat(-1.0),
            max: DVec3::splat(1.0),
        };
        CameraController::new(home, bounds, 200, 100)
    }

    /// Feeds winit events through the event loop's mapping to the controller.
    fn feed(c: &mut CameraController, events: &[WindowEvent]) -> bool {
        let mut changed = false;
        for e in events {
            if let Some(input) = controller_input(e) {
                changed |= c.handle(input);
            }
        }
        changed
    }

    fn moved(x: f64, y: f64) -> WindowEvent {
        WindowEvent::CursorMoved {
            device_id: DeviceId::dummy(),
            position: PhysicalPosition::new(x, y),
        }
    }

    fn button(button: MouseButton, pressed: bool) -> WindowEvent {
        WindowEvent::MouseInput {
            device_id: DeviceId::dummy(),
            state: if pressed {
                ElementState::Pressed
            } else {
                ElementState::Released
            },
            button,
        }
    }

    /// A drag of 50 pixels to the right with `b`.
    fn drag(b: MouseButton) -> [WindowEvent; 4] {
        [
            moved(100.0, 50.0),
            button(b, true),
            moved(150.0, 50.0),
            button(b, false),
        ]
    }

    fn close(a: DVec3, b: DVec3) -> bool {
        (a - b).length() < 1e-9
    }

    #[test]
    fn winit_mouse_events_orbit_pan_and_zoom() {
        let mut c = controller();
        assert!(feed(&mut c, &drag(MouseButton::Left)));
        assert!(close(c.camera().position, DVec3::new(1.0, 0.0, 0.0)));

        let mut c = controller();
        assert!(feed(&mut c, &drag(MouseButton::Right)));
        assert!(close(c.camera().position, DVec3::new(-1.0, 0.0, 1.0)));
        // Released: moving does nothing.
        assert!(!feed(&mut c, &[moved(10.0, 10.0)]));

        let mut c = controller();
        let wheel = WindowEvent::MouseWheel {
            device_id: DeviceId::dummy(),
            delta: MouseScrollDelta::LineDelta(0.0, 1.0),
            phase: winit::event::TouchPhase::Moved,
        };
        assert!(feed(&mut c, &[wheel]));
        assert!(close(c.camera().position, DVec3::new(0.0, 0.0, 0.9)));

        // A resize changes the orbit's pixels-per-turn.
        let mut c = controller();
        let events = [
            WindowEvent::Resized(PhysicalSize::new(400, 200)),
            moved(0.0, 0.0),
            button(MouseButton::Left, true),
            moved(100.0, 0.0),
        ];
        assert!(feed(&mut c, &events));
        assert!(close(c.camera().position, DVec3::new(1.0, 0.0, 0.0)));
        // Losing focus releases the button.
        assert!(!feed(
            &mut c,
            &[WindowEvent::Focused(false), moved(300.0, 0.0)]
        ));
    }

    #[test]
    fn keys_map_to_actions() {
        let ch = |s: &str| Key::Character(s.into());
        let none = PhysicalKey::Code(KeyCode::F13);
        // The fly keys by position: W A Q E of a US keyboard type z q a e
        // on a French one.
        let fly = |code, typed, key| (PhysicalKey::Code(code), ch(typed), Some(Action::Fly(key)));
        let cases = [
            fly(KeyCode::KeyW, "z", ControlKey::Forward),
            fly(KeyCode::KeyA, "q", ControlKey::Left),
            fly(KeyCode::KeyQ, "a", ControlKey::Down),
            fly(KeyCode::KeyE, "e", ControlKey::Up),
            (none, ch("F"), Some(Action::Camera(ControlKey::FrameAll))),
            (none, ch("r"), Some(Action::Camera(ControlKey::Reset))),
            (none, ch("p"), Some(Action::Screenshot)),
            (none, ch("b"), Some(Action::ToggleAccel)),
            (none, ch("T"), Some(Action::CycleTraversal)),
            (none, ch("k"), Some(Action::CycleBuild)),
            (none, ch("c"), Some(Action::ToggleHeatmap)),
            (none, ch("N"), Some(Action::ToggleDenoise)),
            // D is the fly key "right" by position, whatever it types: N,
            // not D, toggles denoising.
            fly(KeyCode::KeyD, "d", ControlKey::Right),
            (
                PhysicalKey::Code(KeyCode::KeyN),
                ch("n"),
                Some(Action::ToggleDenoise),
            ),
            (none, ch("["), Some(Action::DepthDown)),
            (none, ch("]"), Some(Action::DepthUp)),
            (none, ch("h"), Some(Action::Help)),
            (none, ch("X"), Some(Action::ToggleInspect)),
            (none, Key::Named(NamedKey::Escape), Some(Action::Quit)),
            (none, ch("v"), None),
            (none, ch("fr"), None),
            (none, Key::Named(NamedKey::Enter), None),
        ];
        for (physical, logical, action) in cases {
            assert_eq!(key_action(physical, &logical), action, "{logical:?}");
        }
    }

    #[test]
    fn every_window_key_is_in_the_help() {
        let keys: Vec<&str> = HELP
            .lines()
            .skip(1)
            .filter_map(|line| line.get(2..19))
            .flat_map(|column| column.split([' ', ',']))
            .filter(|k| !k.is_empty())
            .collect();
        for (key, action) in WINDOW_KEYS {
            assert!(
                keys.contains(&key.to_uppercase().as_str()),
                "{key:?} ({action:?}) is not in HELP's key column: {keys:?}"
            );
        }
    }
}
