//! Playing a scene's animation in the window: which frame is shown, by the
//! wall clock while playing, held while paused. Free of winit and the GPU:
//! `app.rs` asks it for the frame and moves the camera there.

use std::time::Instant;

/// The shown frame of an animation of `frames` frames at `fps`, looping.
#[derive(Debug, Clone)]
pub struct Playback {
    frames: u32,
    fps: f64,
    frame: u32,
    /// While playing: when it started and the frame it started from.
    playing_since: Option<(Instant, u32)>,
}

impl Playback {
    /// Paused at frame 0. A still scene is one frame, which never changes.
    pub fn new(frames: u32, fps: f64) -> Self {
        Playback {
            frames: frames.max(1),
            fps: if fps.is_finite() && fps > 0.0 {
                fps
            } else {
                24.0
            },
            frame: 0,
            playing_since: None,
        }
    }

    /// Whether there is anything to play (more than one frame).
    pub fn is_animated(&self) -> bool {
        self.frames > 1
    }

    pub fn is_playing(&self) -> bool {
        self.playing_since.is_some()
    }

    /// The frame shown, 0-based.
    pub fn frame(&self) -> u32 {
        self.frame
    }

    pub fn frames(&self) -> u32 {
        self.frames
    }

    /// Play from the shown frame, or pause on it. A still scene stays paused.
    pub fn toggle(&mut self, now: Instant) {
        self.playing_since = match self.playing_since {
            Some(_) => None,
            None if self.is_animated() => Some((now, self.frame)),
            None => None,
        };
    }

    /// A reloaded scene's animation: the frame is kept where it still
    /// exists, else it goes back to 0; playing goes on from it.
    pub fn set_animation(&mut self, frames: u32, fps: f64, now: Instant) {
        let playing = self.is_playing();
        *self = Playback {
            frame: if self.frame < frames.max(1) {
                self.frame
            } else {
                0
            },
            ..Playback::new(frames, fps)
        };
        if playing {
            self.toggle(now);
        }
    }

    /// Moves the shown frame to where the clock says while playing
    /// (`fps` frames a second, wrapping after the last); whether it changed.
    pub fn advance(&mut self, now: Instant) -> bool {
        let Some((since, from)) = self.playing_since else {
            return false;
        };
        let elapsed = now.saturating_duration_since(since).as_secs_f64();
        let steps = (elapsed * self.fps).floor() as u64;
        let frame = ((from as u64 + steps) % self.frames as u64) as u32;
        let changed = frame != self.frame;
        self.frame = frame;
        changed
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn at(start: Instant, seconds: f64) -> Instant {
        start + Duration::from_secs_f64(seconds)
    }

    #[test]
    fn playing_shows_fps_frames_a_second_and_wraps_after_the_last() {
        let t0 = Instant::now();
        let mut p = Playback::new(48, 24.0);
        assert!(!p.advance(at(t0, 1.0)), "paused: the frame holds");
        assert_eq!(p.frame(), 0);
        p.toggle(t0);
        assert!(p.is_playing());
        assert!(!p.advance(at(t0, 0.02)), "still frame 0 before 1/24 s");
        assert!(p.advance(at(t0, 0.5)));
        assert_eq!(p.frame(), 12);
        p.advance(at(t0, 2.0 + 0.01));
        assert_eq!(p.frame(), 0, "48 frames at 24 fps wrap after 2 s");
        p.advance(at(t0, 2.5 + 0.01));
        assert_eq!(p.frame(), 12);
    }

    #[test]
    fn pausing_holds_the_frame_and_playing_again_goes_on_from_it() {
        let t0 = Instant::now();
        let mut p = Playback::new(10, 10.0);
        p.toggle(t0);
        p.advance(at(t0, 0.35));
        assert_eq!(p.frame(), 3);
        p.toggle(at(t0, 0.35));
        assert!(!p.is_playing());
        assert!(!p.advance(at(t0, 5.0)));
        assert_eq!(p.frame(), 3);
        p.toggle(at(t0, 5.0));
        p.advance(at(t0, 5.25));
        assert_eq!(p.frame(), 5);
    }

    #[test]
    fn a_still_scene_never_plays() {
        let t0 = Instant::now();
        let mut p = Playback::new(1, 24.0);
        assert!(!p.is_animated());
        p.toggle(t0);
        assert!(!p.is_playing());
        assert!(!p.advance(at(t0, 3.0)));
        assert_eq!(p.frame(), 0);
    }

    #[test]
    fn a_reload_keeps_the_frame_where_it_still_exists() {
        let t0 = Instant::now();
        let mut p = Playback::new(48, 24.0);
        p.toggle(t0);
        p.advance(at(t0, 1.0));
        assert_eq!(p.frame(), 24);
        p.set_animation(30, 24.0, at(t0, 1.0));
        assert_eq!(p.frame(), 24);
        assert!(p.is_playing());
        p.set_animation(10, 24.0, at(t0, 1.0));
        assert_eq!(p.frame(), 0, "frame 24 is gone: back to the first");
        p.set_animation(1, 24.0, at(t0, 1.0));
        assert!(!p.is_playing(), "a still scene does not play");
    }
}
