//! Clicks for inspection mode: a left press and release with the cursor
//! kept still (a drag orbits instead), and the image pixel under a window
//! position, as the present pass shows the image (shaders/present.wgsl's
//! `image_index`). Pure: fed the camera controller's [`Input`]s.

use glam::DVec2;

use super::camera_controller::{Button, Input};

/// How far (physical pixels, summed) the cursor may move between press and
/// release for the two to be a click.
pub const CLICK_SLOP: f64 = 3.0;

/// Watches the cursor and the left button for clicks.
#[derive(Debug, Clone, Default)]
pub struct ClickTracker {
    cursor: Option<DVec2>,
    /// Where the left button went down, and how far the cursor moved since.
    press: Option<(DVec2, f64)>,
}

impl ClickTracker {
    /// Applies one input; the cursor position of a click it completes.
    pub fn handle(&mut self, input: Input) -> Option<DVec2> {
        match input {
            Input::CursorMoved { x, y } => {
                let now = DVec2::new(x, y);
                if let (Some(before), Some((_, moved))) = (self.cursor, &mut self.press) {
                    *moved += (now - before).length();
                }
                self.cursor = Some(now);
                None
            }
            Input::Button {
                button: Button::Left,
                pressed: true,
            } => {
                self.press = self.cursor.map(|c| (c, 0.0));
                None
            }
            Input::Button {
                button: Button::Left,
                pressed: false,
            } => {
                let (at, moved) = self.press.take()?;
                (moved <= CLICK_SLOP).then_some(at)
            }
            Input::CursorLeft => {
                self.cursor = None;
                self.press = None;
                None
            }
            Input::FocusLost => {
                self.press = None;
                None
            }
            _ => None,
        }
    }
}

/// The pixel of an `image`-sized image that window position `at` (physical
/// pixels from the top-left corner) shows in a `window`-sized window: the
/// window pixel it falls in, scaled as the present pass scales; None
/// outside the window (or for an empty one).
pub fn image_pixel(at: DVec2, window: (u32, u32), image: (u32, u32)) -> Option<(u32, u32)> {
    let (w, h) = window;
    let (iw, ih) = image;
    if w == 0 || h == 0 || iw == 0 || ih == 0 || !at.is_finite() {
        return None;
    }
    if at.x < 0.0 || at.y < 0.0 || at.x >= w as f64 || at.y >= h as f64 {
        return None;
    }
    let (px, py) = (at.x.floor() as u64, at.y.floor() as u64);
    let x = (px * iw as u64 / w as u64).min(iw as u64 - 1);
    let y = (py * ih as u64 / h as u64).min(ih as u64 - 1);
    Some((x as u32, y as u32))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moved(x: f64, y: f64) -> Input {
        Input::CursorMoved { x, y }
    }

    fn left(pressed: bool) -> Input {
        Input::Button {
            button: Button::Left,
            pressed,
        }
    }

    fn feed(t: &mut ClickTracker, inputs: &[Input]) -> Vec<DVec2> {
        inputs.iter().filter_map(|&i| t.handle(i)).collect()
    }

    #[test]
    fn a_still_press_and_release_is_a_click_and_a_drag_is_not() {
        let mut t = ClickTracker::default();
        let clicks = feed(&mut t, &[moved(10.5, 20.0), left(true), left(false)]);
        assert_eq!(clicks, [DVec2::new(10.5, 20.0)]);
        // A jitter within the slop is still a click, where it was pressed.
        let clicks = feed(&mut t, &[left(true), moved(12.0, 21.0), left(false)]);
        assert_eq!(clicks, [DVec2::new(10.5, 20.0)]);
        // A drag (it orbits) is not, even back to where it started.
        let clicks = feed(
            &mut t,
            &[
                left(true),
                moved(40.0, 21.0),
                moved(12.0, 21.0),
                left(false),
            ],
        );
        assert!(clicks.is_empty());
        // Other buttons, a release without a press, and a press with no
        // known cursor are not clicks.
        let other = Input::Button {
            button: Button::Right,
            pressed: true,
        };
        assert!(feed(&mut t, &[other, left(false)]).is_empty());
        let mut fresh = ClickTracker::default();
        assert!(feed(&mut fresh, &[left(true), left(false)]).is_empty());
        // Leaving the window or losing focus in between cancels it.
        assert!(feed(&mut t, &[left(true), Input::FocusLost, left(false)]).is_empty());
        assert!(feed(&mut t, &[left(true), Input::CursorLeft, left(false)]).is_empty());
    }

    #[test]
    fn window_positions_map_to_the_image_pixel_shown_there() {
        // Image and window of one size: the pixel under the cursor.
        assert_eq!(
            image_pixel(DVec2::new(0.0, 0.0), (96, 64), (96, 64)),
            Some((0, 0))
        );
        assert_eq!(
            image_pixel(DVec2::new(40.9, 12.2), (96, 64), (96, 64)),
            Some((40, 12))
        );
        assert_eq!(
            image_pixel(DVec2::new(95.99, 63.5), (96, 64), (96, 64)),
            Some((95, 63))
        );
        // A smaller image (the device's limit): as the present pass scales.
        assert_eq!(
            image_pixel(DVec2::new(7.0, 5.0), (100, 50), (50, 25)),
            Some((3, 2))
        );
        assert_eq!(
            image_pixel(DVec2::new(99.5, 49.5), (100, 50), (34, 17)),
            Some((33, 16))
        );
        // Outside the window, or nothing to show.
        for at in [
            (-0.5, 3.0),
            (3.0, -0.01),
            (96.0, 3.0),
            (3.0, 64.0),
            (f64::NAN, 1.0),
        ] {
            let at = DVec2::new(at.0, at.1);
            assert_eq!(image_pixel(at, (96, 64), (96, 64)), None, "{at}");
        }
        assert_eq!(image_pixel(DVec2::ZERO, (0, 64), (96, 64)), None);
        assert_eq!(image_pixel(DVec2::ZERO, (96, 64), (0, 0)), None);
    }
}
