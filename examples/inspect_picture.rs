//! One pixel's rays crossing the k-d tree, seen from the side: inspects a
//! pixel of a scene with the kernel (as `kdray inspect` does), renders the
//! scene from a camera turned about its target, and draws over that image
//! what the window's inspection mode draws (the rays, the leaf cells the
//! walks visited, the hit leaf, the split planes crossed), projected as the
//! window projects them. README.md's picture comes from it:
//!
//! ```sh
//! cargo run --release --example inspect_picture -- [SCENE [OUT.png [X,Y [DEGREES [DISTANCE]]]]]
//! ```
//!
//! SCENE defaults to scenes/seed.toml, OUT.png to docs/images/inspect_seed.png,
//! X,Y (of the scene's view at 640 x 360) to 250,200, DEGREES (the turn of
//! the side view about the vertical through the target) to 70, DISTANCE (the
//! side view's distance from the target, in the scene camera's) to 2.

use std::path::{Path, PathBuf};

use glam::{DQuat, DVec3};
use kdray::gpu::{Accel, GpuContext, GpuScene, PreparedScene, TilePlan, WalkRecorder};
use kdray::kdtree::Traversal;
use kdray::scene::Camera;
use kdray::window::inspect_lines::{miss_length, node_cells, overlay_lines};
use kdray::window::projection::{near_plane, ViewProjection};

const WIDTH: u32 = 640;
const HEIGHT: u32 = 360;

/// `camera` turned by `degrees` about the vertical through its target,
/// moved to `distance` times its distance and raised, to see its rays from
/// aside.
fn side_view(camera: &Camera, degrees: f64, distance: f64) -> Camera {
    let turn = DQuat::from_axis_angle(camera.up.normalize(), degrees.to_radians());
    let offset = turn * (camera.position - camera.look_at) * distance;
    Camera {
        position: camera.look_at + offset + camera.up.normalize() * offset.length() * 0.4,
        ..*camera
    }
}

/// Draws the segment a-b (image pixels) in `colour` into `rgb`, a pixel
/// wide.
fn draw_line(rgb: &mut [u8], a: glam::DVec2, b: glam::DVec2, colour: [u8; 3]) {
    let steps = (b - a).abs().max_element().ceil().clamp(1.0, 20_000.0) as usize;
    for i in 0..=steps {
        let p = a + (b - a) * (i as f64 / steps as f64);
        let (x, y) = (p.x.floor(), p.y.floor());
        if x >= 0.0 && y >= 0.0 && x < WIDTH as f64 && y < HEIGHT as f64 {
            let at = 3 * (y as usize * WIDTH as usize + x as usize);
            rgb[at..at + 3].copy_from_slice(&colour);
        }
    }
}

/// The side view of the scene at `path` with and without the lines of
/// pixel `pixel`'s inspection.
pub struct Picture {
    pub inspection: kdray::inspect::Inspection,
    pub plain: Vec<u8>,
    pub with_lines: Vec<u8>,
    /// Lines drawn (some may lie outside the view).
    pub lines: usize,
}

/// Inspects `pixel` of the scene at `path` (at 640 x 360, one sample, the
/// restart walk) on `ctx` and draws its lines over the scene rendered from
/// [`side_view`]`(degrees, distance)`.
pub fn picture(
    ctx: &GpuContext,
    path: &Path,
    pixel: (u32, u32),
    degrees: f64,
    distance: f64,
) -> kdray::Result<Picture> {
    let mut scene = kdray::scene::load_scene(path)?;
    (
        scene.render.width,
        scene.render.height,
        scene.render.samples,
    ) = (WIDTH, HEIGHT, 1);
    let uploaded = GpuScene::upload(ctx, PreparedScene::new(scene.clone(), Accel::Kdtree))?;
    let recorder = WalkRecorder::new(ctx)?;
    let inspection =
        kdray::inspect::inspect_on_gpu(ctx, &recorder, &uploaded, Traversal::Restart, pixel)?;
    let tree = &uploaded.prepared().tree;
    let lines = overlay_lines(
        &inspection,
        &node_cells(&tree.nodes, tree.bounds),
        miss_length(&tree.bounds),
    );

    let mut side = scene.clone();
    side.camera = side_view(&scene.camera, degrees, distance);
    let (image, _) =
        kdray::render::render_scene(ctx, &side, Accel::Kdtree, TilePlan::DEFAULT_MAX_TILE_PIXELS)?;
    let plain = image.rgb;
    let mut rgb = plain.clone();
    let view = ViewProjection::new(
        &side.camera,
        WIDTH as f64 / HEIGHT as f64,
        near_plane(&side.camera),
    );
    for line in &lines {
        let (a, b): (DVec3, DVec3) = (line.a.as_dvec3(), line.b.as_dvec3());
        if let Some((pa, pb)) = view.segment_to_image(a, b, (WIDTH, HEIGHT)) {
            let colour = line
                .kind
                .colour()
                .map(|c| (255.0 * c.clamp(0.0, 1.0)).round() as u8);
            draw_line(&mut rgb, pa, pb, colour);
        }
    }
    Ok(Picture {
        inspection,
        plain,
        with_lines: rgb,
        lines: lines.len(),
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut args = std::env::args().skip(1);
    let scene_path = args
        .next()
        .map_or(root.join("scenes/seed.toml"), PathBuf::from);
    let out = args
        .next()
        .map_or(root.join("docs/images/inspect_seed.png"), PathBuf::from);
    let pixel = kdray::inspect::parse_pixel(&args.next().unwrap_or("250,200".into()))?;
    let degrees: f64 = args.next().map_or(Ok(70.0), |d| d.parse())?;
    let distance: f64 = args.next().map_or(Ok(2.0), |d| d.parse())?;

    let gpu = GpuContext::new()?;
    let picture = picture(&gpu, &scene_path, pixel, degrees, distance)?;
    let (inspection, rgb) = (&picture.inspection, &picture.with_lines);
    kdray::output::write_png_atomic(&out, WIDTH, HEIGHT, rgb)?;
    let c = inspection.rays.iter().fold([0; 3], |t, r| {
        [
            t[0] + r.counts.nodes,
            t[1] + r.counts.leaves,
            t[2] + r.counts.tests,
        ]
    });
    println!(
        "pixel {},{}: {} rays, {} nodes, {} leaves, {} tests; {} lines drawn into {}",
        pixel.0,
        pixel.1,
        inspection.rays.len(),
        c[0],
        c[1],
        c[2],
        picture.lines,
        out.display()
    );
    Ok(())
}
