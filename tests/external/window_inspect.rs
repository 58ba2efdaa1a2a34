//! Inspection mode in the real window under Xvfb, driven through the X
//! server's XTest extension as a person would: X turns it on, a left click
//! inspects the pixel under the cursor, F (frame the whole scene) moves the
//! camera back, and P saves screenshots. From the new viewpoint the
//! inspected primary ray, a point from the viewpoint it was traced from,
//! projects to a segment: the window with the inspection differs from the
//! same window without it along that segment, and equals it away from every
//! drawn line. The lines, the cells and the projection are
//! `kdray::window::inspect_lines` and `kdray::window::projection` (unit
//! tests beside them hold the projection to the kernel's camera rays).
//! Denoising is driven the same way: N toggles it, P saves what is shown.

use crate::common;

use std::ffi::CString;
use std::path::{Path, PathBuf};

use std::time::{Duration, Instant};

use glam::DVec2;
use x11_dl::{keysym, xlib, xtest};

use super::x_window::{read, temp_dir, RunningWindow, Xvfb, H, SAMPLES, TIMEOUT, W};
use kdray::gpu::Accel;
use kdray::inspect::{build_tree, inspect_file, InspectRequest, WalkSource};
use kdray::kdtree::{BuildStrategy, Traversal};
use kdray::render::RenderFlags;
use kdray::window::camera_controller::{Bounds, CameraController, ControlKey, Input};
use kdray::window::inspect_lines::{miss_length, node_cells, overlay_lines, LineKind};
use kdray::window::projection::{near_plane, ViewProjection};

/// Spheres spread over the scene, so that its tree has several cells, seen
/// from inside the box that F frames (F then moves the camera back).
const SCENE: &str = r#"[camera]
position = [0.0, 0.0, 3.0]
look_at  = [0.0, 0.0, 0.0]
vfov     = 40.0

[render]
background = [0.1, 0.1, 0.1]

[[lights]]
position = [2.0, 3.0, 4.0]

[materials.paint]
ambient = [0.1, 0.1, 0.1]
diffuse = [0.8, 0.3, 0.2]

[[spheres]]
center   = [-1.0, 0.0, 0.0]
radius   = 0.5
material = "paint"

[[spheres]]
center   = [1.0, 0.0, 0.0]
radius   = 0.5
material = "paint"

[[spheres]]
center   = [0.0, 1.0, -0.5]
radius   = 0.4
material = "paint"

[[spheres]]
center   = [0.3, -0.6, 0.2]
radius   = 0.3
material = "paint"
"#;

/// The pixel clicked: on the left sphere.
const PIXEL: (u32, u32) = (19, 32);

/// A connection to the test's X server that moves the pointer, clicks and
/// types through XTest.
struct XInput {
    xlib: xlib::Xlib,
    xtest: xtest::Xf86vmode,
    display: *mut xlib::Display,
}

impl XInput {
    fn open(name: &str) -> XInput {
        let xlib = xlib::Xlib::open().unwrap_or_else(|e| panic!("libX11: {e}"));
        let xtest = xtest::Xf86vmode::open().unwrap_or_else(|e| {
            panic!("the inspection test needs libXtst: apt-get install libxtst6 ({e})")
        });
        let c = CString::new(name).unwrap();
        // SAFETY: a valid C string; the display is closed on drop.
        let display = unsafe { (xlib.XOpenDisplay)(c.as_ptr()) };
        assert!(!display.is_null(), "cannot open X display {name}");
        XInput {
            xlib,
            xtest,
            display,
        }
    }

    /// A mapped top-level window of `w` x `h` and its root position (the
    /// only such window on the test's server is kdray's; without a window
    /// manager it is not reparented).
    fn window_of_size(&self, w: u32, h: u32) -> Option<(xlib::Window, i32, i32)> {
        // SAFETY: Xlib calls on an open display; the child list is freed.
        unsafe {
            let root = (self.xlib.XDefaultRootWindow)(self.display);
            let (mut r, mut parent) = (0, 0);
            let mut children: *mut xlib::Window = std::ptr::null_mut();
            let mut n = 0;
            if (self.xlib.XQueryTree)(
                self.display,
                root,
                &mut r,
                &mut parent,
                &mut children,
                &mut n,
            ) == 0
            {
                return None;
            }
            let list: Vec<xlib::Window> = if children.is_null() {
                Vec::new()
            } else {
                let list = std::slice::from_raw_parts(children, n as usize).to_vec();
                (self.xlib.XFree)(children.cast());
                list
            };
            list.into_iter().find_map(|window| {
                let mut a: xlib::XWindowAttributes = std::mem::zeroed();
                let ok = (self.xlib.XGetWindowAttributes)(self.display, window, &mut a) != 0;
                (ok && a.map_state == xlib::IsViewable
                    && (a.width, a.height) == (w as i32, h as i32))
                    .then_some((window, a.x, a.y))
            })
        }
    }

    /// Gives `window` the keyboard focus (there is no window manager to).
    fn focus(&self, window: xlib::Window) {
        // SAFETY: an open display and a window of its server.
        unsafe {
            (self.xlib.XSetInputFocus)(
                self.display,
                window,
                xlib::RevertToParent,
                xlib::CurrentTime,
            )
        };
        self.sync();
    }

    fn sync(&self) {
        // SAFETY: an open display.
        unsafe { (self.xlib.XSync)(self.display, 0) };
    }

    fn move_to(&self, x: i32, y: i32) {
        // SAFETY: an open display; screen -1 is the pointer's.
        unsafe { (self.xtest.XTestFakeMotionEvent)(self.display, -1, x, y, 0) };
        self.sync();
    }

    /// Presses and releases the left button where the pointer is.
    fn click(&self) {
        // SAFETY: an open display.
        unsafe {
            (self.xtest.XTestFakeButtonEvent)(self.display, 1, 1, 0);
            (self.xtest.XTestFakeButtonEvent)(self.display, 1, 0, 0);
        }
        self.sync();
    }

    /// Presses and releases the key that types `sym`.
    fn key(&self, sym: u32) {
        // SAFETY: an open display.
        unsafe {
            let code = (self.xlib.XKeysymToKeycode)(self.display, sym as _) as u32;
            assert_ne!(code, 0, "no key types keysym {sym:#x}");
            (self.xtest.XTestFakeKeyEvent)(self.display, code, 1, 0);
            (self.xtest.XTestFakeKeyEvent)(self.display, code, 0, 0);
        }
        self.sync();
    }
}

impl Drop for XInput {
    fn drop(&mut self) {
        // SAFETY: opened in `open`, closed once.
        unsafe { (self.xlib.XCloseDisplay)(self.display) };
    }
}

/// The window process and the folder its screenshots go to.
struct Window {
    process: RunningWindow,
    dir: PathBuf,
}

impl Window {
    /// Waits for a line with `needle` on stderr and returns it.
    fn line_with(&mut self, needle: &str) -> String {
        self.process.line_with(needle)
    }

    /// P: a screenshot of what the window shows, and how many of the
    /// pixels' samples it held.
    fn screenshot(&mut self, x: &XInput) -> (Vec<u8>, u32) {
        x.key(keysym::XK_p);
        let line = self.line_with("kdray: saved ");
        let rest = line.strip_prefix("kdray: saved ").unwrap();
        let (path, counts) = rest.rsplit_once(" (").unwrap();
        let passes: u32 = counts.split(' ').next().unwrap().parse().unwrap();
        (read(&self.dir.join(path)), passes)
    }

    /// Screenshots until two in a row show all the samples, the same
    /// picture, other than `not`: the refined image (a screenshot taken
    /// between a change's preview frame and its first sample may show the
    /// preview with the samples of the image before).
    fn refined_screenshot(&mut self, x: &XInput, not: Option<&[u8]>) -> Vec<u8> {
        let deadline = Instant::now() + TIMEOUT;
        let mut last: Option<Vec<u8>> = None;
        loop {
            let (shot, passes) = self.screenshot(x);
            let refined = passes.to_string() == SAMPLES && not.is_none_or(|n| n != shot.as_slice());
            if refined && last.as_ref() == Some(&shot) {
                return shot;
            }
            last = refined.then_some(shot);
            assert!(
                Instant::now() < deadline,
                "the window did not refine: {}",
                self.process.seen.join("\n")
            );
            std::thread::sleep(Duration::from_millis(150));
        }
    }
}

/// Opens the window on `server` showing `scene`, optionally turns inspection on and clicks
/// [`PIXEL`], then presses F; the refined screenshot after F.
fn window_after_f(x: &XInput, server: &Xvfb, dir: &Path, scene: &Path, inspect: bool) -> Vec<u8> {
    let run = dir.join(if inspect { "inspected" } else { "plain" });
    std::fs::create_dir_all(&run).unwrap();
    let mut command = server.kdray(dir);
    command
        .current_dir(&run)
        .arg("render")
        .arg(scene)
        .args([
            "--window",
            "--width",
            &W.to_string(),
            "--height",
            &H.to_string(),
        ])
        .args([
            "--samples",
            SAMPLES,
            "--traversal",
            "ropes",
            "--build",
            "sah",
        ]);
    let mut window = Window {
        process: RunningWindow::spawn(command),
        dir: run,
    };
    window.line_with("window on");
    let deadline = Instant::now() + TIMEOUT;
    let (id, wx, wy) = loop {
        if let Some(at) = x.window_of_size(W, H) {
            break at;
        }
        assert!(
            Instant::now() < deadline,
            "no {W}x{H} window on {}",
            server.display
        );
        std::thread::sleep(Duration::from_millis(50));
    };
    x.focus(id);
    x.move_to(wx + PIXEL.0 as i32, wy + PIXEL.1 as i32);
    if inspect {
        x.key(keysym::XK_x);
        x.click();
        let line = window.line_with("kdray: inspected pixel");
        let (px, py) = PIXEL;
        assert!(line.contains(&format!("pixel {px},{py}:")), "{line}");
    }
    let before = window.refined_screenshot(x, None);
    x.key(keysym::XK_f);
    let after = window.refined_screenshot(x, Some(&before));
    let (status, stderr) = window.process.close();
    assert!(status.success(), "{stderr}");
    after
}

/// Distance from `p` to segment `a`-`b`.
fn distance(p: DVec2, (a, b): (DVec2, DVec2)) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).length()
}

fn differs(a: &[u8], b: &[u8], pixel: usize) -> bool {
    (0..3).any(|c| a[3 * pixel + c].abs_diff(b[3 * pixel + c]) > 2)
}

#[test]
fn an_inspected_pixels_rays_are_drawn_where_the_camera_projects_them() {
    let x11 = Xvfb::start();
    let dir = temp_dir("inspect");
    let scene = dir.join("spheres.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let x = XInput::open(&x11.display);
    let plain = window_after_f(&x, &x11, &dir, &scene, false);
    let inspected = window_after_f(&x, &x11, &dir, &scene, true);

    // What the window drew: the pixel's lines, seen from the camera that F
    // moved to.
    let flags = RenderFlags {
        width: Some(W),
        height: Some(H),
        samples: Some(SAMPLES.parse().unwrap()),
        accel: Accel::Kdtree,
        traversal: Traversal::Ropes,
        build: BuildStrategy::Sah,
        integrator: None,
        seed: None,
    };
    let request = InspectRequest {
        pixel: PIXEL,
        frame: 0,
        flags: flags.clone(),
        source: WalkSource::Kernel,
    };
    let inspection = inspect_file(&scene, &request).unwrap();
    let mut loaded = kdray::scene::load_scene(&scene).unwrap();
    flags.apply(&mut loaded).unwrap();
    let tree = build_tree(&loaded, BuildStrategy::Sah);
    let cells = node_cells(&tree.nodes, tree.bounds);
    let lines = overlay_lines(&inspection, &cells, miss_length(&tree.bounds));
    let bounds = Bounds {
        min: tree.bounds.min.as_dvec3(),
        max: tree.bounds.max.as_dvec3(),
    };
    let mut controller = CameraController::new(loaded.camera, bounds, W, H);
    controller.handle(Input::Key {
        key: ControlKey::FrameAll,
        pressed: true,
    });
    let camera = controller.camera();
    let projection = ViewProjection::new(&camera, W as f64 / H as f64, near_plane(&camera));
    let segment = |l: &kdray::window::inspect_lines::Line| {
        projection.segment_to_image(l.a.as_dvec3(), l.b.as_dvec3(), (W, H))
    };
    let primary = lines
        .iter()
        .find(|l| l.kind == LineKind::Primary)
        .and_then(segment)
        .expect("the primary ray is in front of the camera after F");
    assert!(
        (primary.1 - primary.0).length() > 8.0,
        "the primary ray projects to {primary:?}: too short to test"
    );
    let drawn: Vec<(DVec2, DVec2)> = lines.iter().filter_map(segment).collect();

    assert!(common::compare(&plain, &inspected, W, H, 2).pixels_over > 0);
    let (mut along, mut along_differ, mut far, mut far_differ) = (0, 0, 0, Vec::new());
    for py in 0..H {
        for px in 0..W {
            let p = DVec2::new(px as f64 + 0.5, py as f64 + 0.5);
            let i = (py * W + px) as usize;
            if distance(p, primary) <= 0.5 {
                along += 1;
                along_differ += differs(&plain, &inspected, i) as usize;
            }
            if drawn.iter().all(|&s| distance(p, s) > 2.5) {
                far += 1;
                if differs(&plain, &inspected, i) {
                    far_differ.push((px, py));
                }
            }
        }
    }
    assert!(
        along >= 8 && along_differ * 10 >= along * 6,
        "{along_differ} of the {along} pixels along the primary ray {primary:?} differ"
    );
    assert!(
        far * 5 >= (W * H) as usize,
        "only {far} pixels lie away from the {} lines",
        drawn.len()
    );
    assert!(
        far_differ.is_empty(),
        "{} of {far} pixels away from every line differ: {:?}",
        far_differ.len(),
        &far_differ[..far_differ.len().min(20)]
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `kdray render SCENE --samples 4 -o OUT` at the tests' size, with
/// `extra` flags.
fn headless(dir: &Path, scene: &Path, out: &Path, extra: &[&str]) -> Vec<u8> {
    let output = super::x_window::kdray(dir)
        .arg("render")
        .arg(scene)
        .args(extra)
        .args(["--width", &W.to_string(), "--height", &H.to_string()])
        .args(["--samples", SAMPLES, "-o"])
        .arg(out)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "headless render failed: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    read(out)
}

/// Whether `a` is `b` within the golden tests' budget: a mean FLIP error
/// of at most 0.01 and at most 1 pixel in 1,000 off by more than 2 levels.
fn matches(a: &[u8], b: &[u8]) -> Result<(), String> {
    let d = common::compare(a, b, W, H, 2);
    let budget = (W * H) as usize / 1000;
    match d.mean_flip <= 0.01 && d.pixels_over <= budget {
        true => Ok(()),
        false => Err(format!("{d:?} (budget: FLIP 0.01, {budget} pixels)")),
    }
}

/// P until two screenshots in a row whose lines end with `counts` (the
/// samples shown, and whether denoised) are the same picture: that one (a
/// screenshot taken between a change's preview frame and its first sample
/// may show the preview with the counts of the image before).
fn screenshot_saying(window: &mut Window, x: &XInput, counts: &str) -> Vec<u8> {
    // The first denoise compiles the denoiser's pipelines: about 20 s on
    // a loaded lavapipe.
    let deadline = Instant::now() + 2 * TIMEOUT;
    let mut last: Option<Vec<u8>> = None;
    loop {
        x.key(keysym::XK_p);
        let line = window.line_with("kdray: saved ");
        let rest = line.strip_prefix("kdray: saved ").unwrap();
        let (path, said) = rest.rsplit_once(" (").unwrap();
        let shot = (said == counts).then(|| read(&window.dir.join(path)));
        if shot.is_some() && shot == last {
            return last.unwrap();
        }
        last = shot;
        assert!(
            Instant::now() < deadline,
            "no screenshot of ({counts}: {}",
            window.process.seen.join("\n")
        );
        std::thread::sleep(Duration::from_millis(150));
    }
}

/// Denoising in the real window on the path-traced Cornell box, driven by
/// keys under Xvfb (XTest): started by `--denoise`, the screenshot P saves
/// once the 4 samples are in is the denoised image, `kdray render
/// --denoise`'s of the same size and samples within the golden tests'
/// budget, and P's line says "denoised at 4"; the denoise ran over several
/// frames; N turns denoising off, and P saves the noisy image, the plain
/// render's; N turns it on again.
#[test]
fn the_windows_denoised_image_is_the_headless_one_and_n_toggles_it() {
    let server = Xvfb::start();
    let dir = temp_dir("denoise");
    let scene = common::repo_path("scenes/cornell_box.toml");
    let noisy = headless(&dir, &scene, &dir.join("noisy.png"), &[]);
    let denoised = headless(&dir, &scene, &dir.join("denoised.png"), &["--denoise"]);
    assert!(
        common::compare(&noisy, &denoised, W, H, 2).pixels_over > (W * H) as usize / 100,
        "the denoiser changes the image"
    );

    let run = dir.join("window");
    std::fs::create_dir_all(&run).unwrap();
    let mut command = server.kdray(&dir);
    command
        .current_dir(&run)
        .arg("render")
        .arg(&scene)
        .args(["--window", "--denoise"])
        .args(["--width", &W.to_string(), "--height", &H.to_string()])
        .args(["--samples", SAMPLES]);
    let mut window = Window {
        process: RunningWindow::spawn(command),
        dir: run,
    };
    window.line_with("window on");
    let x = XInput::open(&server.display);
    let deadline = Instant::now() + TIMEOUT;
    let (id, _, _) = loop {
        if let Some(at) = x.window_of_size(W, H) {
            break at;
        }
        assert!(Instant::now() < deadline, "no {W}x{H} window");
        std::thread::sleep(Duration::from_millis(50));
    };
    x.focus(id);
    let all = format!("{SAMPLES} of {SAMPLES} samples per pixel");
    let says_denoised = format!("{all}, denoised at {SAMPLES})");
    let shot = screenshot_saying(&mut window, &x, &says_denoised);
    matches(&shot, &denoised).unwrap_or_else(|e| panic!("denoised: {e}"));
    // The denoise ran a few units a frame: the window presented frames
    // while it was in progress.
    let done = format!("kdray: denoised at {SAMPLES} spp in ");
    let line = window.process.seen.iter().find(|l| l.starts_with(&done));
    let line = line.unwrap_or_else(|| panic!("no line {done:?}"));
    let frames: u32 = line
        .split(" over ")
        .nth(1)
        .and_then(|rest| rest.split(' ').next())
        .and_then(|n| n.parse().ok())
        .unwrap_or_else(|| panic!("no frame count in {line:?}"));
    assert!(frames >= 2, "the denoise ran in {frames} frame: {line}");
    x.key(keysym::XK_n);
    window.line_with("kdray: denoising off");
    let shot = screenshot_saying(&mut window, &x, &format!("{all})"));
    matches(&shot, &noisy).unwrap_or_else(|e| panic!("noisy: {e}"));
    x.key(keysym::XK_n);
    window.line_with("kdray: denoising on");
    let shot = screenshot_saying(&mut window, &x, &says_denoised);
    matches(&shot, &denoised).unwrap_or_else(|e| panic!("denoised again: {e}"));
    let (status, stderr) = window.process.close();
    assert!(status.success(), "{stderr}");
    std::fs::remove_dir_all(&dir).unwrap();
}
