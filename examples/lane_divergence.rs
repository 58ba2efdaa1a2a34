//! How much llvmpipe's lockstep execution multiplies a walk's work: it runs
//! the 8 invocations of a row of 8 pixels in a workgroup as one SIMD group,
//! and a loop runs while any of them needs it, so a group costs about 8
//! times its busiest pixel rather than the sum of its pixels. Renders a
//! scene with the per-pixel walk costs (nodes visited plus objects tested,
//! over every ray of the pixel) for the k-d tree and for brute force, and
//! prints each one's total work, its work in lockstep (8 x the group's
//! maximum, summed) and their ratio. Counts, not times: the figures do not
//! depend on the machine's load.
//! `cargo run --release --example lane_divergence -- SCENE [WIDTH HEIGHT [ropes|restart|short-stack]]`
use kdray::choice::Choice;
use kdray::gpu::{Accel, GpuContext, PreparedScene};
use kdray::kdtree::Traversal;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .ok_or("usage: lane_divergence SCENE [WIDTH HEIGHT [TRAVERSAL]]")?;
    let mut scene = kdray::scene::load_scene(std::path::Path::new(&path))?;
    if let (Some(w), Some(h)) = (args.next(), args.next()) {
        scene.render.width = w.parse()?;
        scene.render.height = h.parse()?;
    }
    let traversal = match args.next() {
        None => Traversal::Ropes,
        Some(name) => {
            Traversal::from_name(&name).ok_or_else(|| format!("unknown traversal {name:?}"))?
        }
    };
    let width = scene.render.width as usize;
    let ctx = GpuContext::new()?;
    let mut totals = Vec::new();
    for accel in [Accel::Kdtree, Accel::Brute] {
        let prepared = PreparedScene::new(scene.clone(), accel);
        let mut work: Vec<u64> = Vec::new();
        let (stats, _) = kdray::render::render_scene_streaming(
            &ctx,
            &prepared,
            accel,
            traversal,
            kdray::gpu::TilePlan::DEFAULT_MAX_TILE_PIXELS,
            true,
            &mut |band| {
                if let Some(costs) = band.costs {
                    work.extend(costs.iter().map(|c| c.work() as u64));
                }
                Ok(())
            },
        )?;
        let sum: u64 = work.iter().sum();
        // Rows of 8 pixels aligned to the 8 x 8 workgroups.
        let lockstep = lockstep_work(&work, width, 8, 1);
        let lockstep_4x2 = lockstep_work(&work, width, 4, 2);
        println!(
            "{accel:?}: work {sum}, in lockstep {lockstep} ({:.2}x; 4x2 blocks {:.2}x), GPU {:.0} ms",
            lockstep as f64 / sum.max(1) as f64,
            lockstep_4x2 as f64 / sum.max(1) as f64,
            stats.gpu_ms
        );
        totals.push((sum, lockstep, stats.gpu_ms));
    }
    let (kd, brute) = (totals[0], totals[1]);
    println!(
        "brute / k-d tree: work {:.1}x, work in lockstep {:.1}x, GPU time {:.1}x",
        brute.0 as f64 / kd.0.max(1) as f64,
        brute.1 as f64 / kd.1.max(1) as f64,
        brute.2 / kd.2
    );
    Ok(())
}

/// Work in lockstep when each SIMD group of 8 lanes covers a `bw` x `bh`
/// block of pixels: 8 times the block's busiest pixel, summed.
fn lockstep_work(work: &[u64], width: usize, bw: usize, bh: usize) -> u64 {
    let height = work.len() / width.max(1);
    let mut total = 0;
    for by in (0..height).step_by(bh) {
        for bx in (0..width).step_by(bw) {
            let mut most = 0;
            for y in by..(by + bh).min(height) {
                for x in bx..(bx + bw).min(width) {
                    most = most.max(work[y * width + x]);
                }
            }
            total += 8 * most;
        }
    }
    total
}
