//! The page's denoise tiles (web/denoise.js, `tilePlan`) are native's
//! (`kdray_core::denoise::TilePlan`), computed by node from the contract
//! the site ships: one tile for small images, native's overlapping tiles
//! for 4K within lavapipe's 128 MiB binding, many tiles under small
//! budgets, odd sizes and a square image.

use crate::common;

use kdray::web::denoise::{SiteDenoiser, INPUT_CHANNELS};
use kdray_core::denoise::TilePlan;
use serde_json::{json, Value};

/// Native's plan as the JSON the page's tilePlan returns.
fn native(width: usize, height: usize, limit: u64) -> Value {
    let plan = TilePlan::new(width, height, INPUT_CHANNELS, limit);
    let tiles: Vec<Value> = plan
        .tiles
        .iter()
        .map(|t| {
            json!({
                "src_y": t.src_y, "src_x": t.src_x,
                "src_height": t.src_height, "src_width": t.src_width,
                "offset_y": t.offset_y, "offset_x": t.offset_x,
                "out_y": t.out_y, "out_x": t.out_x,
                "out_height": t.out_height, "out_width": t.out_width,
            })
        })
        .collect();
    json!({
        "tileWidth": plan.tile_width,
        "tileHeight": plan.tile_height,
        "largestBytes": plan.largest_tensor_bytes(INPUT_CHANNELS),
        "tiles": tiles,
    })
}

#[test]
fn the_pages_tile_plan_is_natives() {
    let sizes: [(usize, usize, u64); 9] = [
        (64, 48, 128 << 20),
        (640, 360, 128 << 20),
        (1920, 1080, 128 << 20),
        (3840, 2160, 128 << 20),
        (1000, 700, 20 << 20),
        (333, 1201, 1 << 20),
        (17, 5, 1),
        (600, 290, 30 << 20),
        // A square image.
        (2000, 2000, 64 << 20),
    ];
    let dir = std::env::temp_dir().join(format!("kdray-web-tiles-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for file in ["denoise.js", "tracer.js", "heatmap.js"] {
        std::fs::copy(common::repo_path(&format!("web/{file}")), dir.join(file)).unwrap();
    }
    std::fs::write(dir.join("package.json"), r#"{"type": "module"}"#).unwrap();
    let spec = SiteDenoiser::new().unwrap().contract();
    std::fs::write(dir.join("spec.json"), spec.to_string()).unwrap();
    let list: Vec<Value> = sizes.iter().map(|&(w, h, l)| json!([w, h, l])).collect();
    std::fs::write(dir.join("sizes.json"), Value::from(list).to_string()).unwrap();
    let run = std::process::Command::new("node")
        .arg(common::repo_path("tests/web/tile_plan.mjs"))
        .arg(dir.join("denoise.js"))
        .arg(dir.join("spec.json"))
        .arg(dir.join("sizes.json"))
        .output()
        .expect("node runs (apt-get install nodejs)");
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let page: Vec<Value> = serde_json::from_slice(&run.stdout).unwrap();
    assert_eq!(page.len(), sizes.len());
    for (&(w, h, limit), page) in sizes.iter().zip(&page) {
        let native = native(w, h, limit);
        assert_eq!(page, &native, "{w}x{h} within {limit} bytes");
    }
    // 4K within 128 MiB is several tiles, each within the binding.
    let four_k = &page[3];
    assert!(four_k["tiles"].as_array().unwrap().len() > 1);
    assert!(four_k["largestBytes"].as_u64().unwrap() <= 128 << 20);
    std::fs::remove_dir_all(&dir).unwrap();
}
