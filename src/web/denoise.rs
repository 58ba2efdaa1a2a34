//! What the page denoises with (`denoise=1`, key N): OIDN's
//! `rt_hdr_alb_nrm` network as native `render --denoise` runs it. The site
//! carries the network's weights in the GPU layout the native denoiser
//! uploads ([`WEIGHTS_FILE`], fetched only when the page denoises), the
//! denoise kernels' WGSL files as they are, and in contract.json the table
//! of the network's dispatches that native records its pass from
//! (`denoise::network_dispatches`), the kernels' uniform layouts and the
//! transfer function's constants, and the tiles' alignment and overlap.
//! The page reads all of it and derives nothing but sizes from its image
//! (its tiles by native's rule, `TilePlan`).

use kdray_core::denoise::network::{
    tensor_floats, Slot, ALIGNMENT, OUTPUT_CHANNELS, OUTPUT_SLOT, TILE_OVERLAP,
};
use kdray_core::denoise::transfer::{pu_forward_raw, HDR_Y_MAX};
use serde_json::{json, Value};

use crate::denoise::{
    network_dispatches, shipped_weights, StepDispatch, WeightsLayout, BLOCK_BYTES, CONV_WGSL,
    PACK_WGSL, RESAMPLE_WGSL, WORKGROUP,
};
use crate::error::Result;

/// The site's file of the network's weights.
pub const WEIGHTS_FILE: &str = "denoise.bin";
/// The site's copies of shaders/denoise/, by the kernel's name.
pub const SHADER_FILES: [(&str, &str, &str); 3] = [
    ("conv", "denoise_conv.wgsl", CONV_WGSL),
    ("resample", "denoise_resample.wgsl", RESAMPLE_WGSL),
    ("pack", "denoise_pack.wgsl", PACK_WGSL),
];
/// The page's network reads colour, albedo and normal (the page traces
/// the features as `render --denoise` does).
pub const INPUT_CHANNELS: usize = 9;
/// The weights' blocks start at multiples of this: WebGPU's largest
/// `minUniformBufferOffsetAlignment` (the specification caps the limit at
/// 256), so every adapter binds them.
pub const WEB_UNIFORM_OFFSET_ALIGNMENT: u64 = 256;

/// The page's network: its weights as the site ships them.
pub struct SiteDenoiser {
    pub layout: WeightsLayout,
}

impl SiteDenoiser {
    /// The shipped network laid out for WebGPU.
    pub fn new() -> Result<Self> {
        let weights = shipped_weights(INPUT_CHANNELS)?;
        Ok(SiteDenoiser {
            layout: WeightsLayout::new(&weights.convs, WEB_UNIFORM_OFFSET_ALIGNMENT)?,
        })
    }

    /// The dispatches the page runs for each tile.
    pub fn dispatches(&self) -> Vec<StepDispatch> {
        network_dispatches(&self.layout.layers, INPUT_CHANNELS)
    }

    /// contract.json's `denoise`.
    pub fn contract(&self) -> Value {
        let slot_name = |s: Slot| format!("{s:?}");
        // Each slot's floats for a tile are this times the tile's pixels
        // (exact: tiles are multiples of 16 and the deepest level is 4).
        let unit = ALIGNMENT * ALIGNMENT;
        let (_, per_slot) = tensor_floats(INPUT_CHANNELS, ALIGNMENT, ALIGNMENT);
        let steps: Vec<Value> = self
            .dispatches()
            .iter()
            .map(|d| {
                json!({
                    "shader": d.kernel.shader(),
                    "entry_point": d.kernel.entry_point(),
                    "workgroups_z": d.workgroups(ALIGNMENT, ALIGNMENT)[2],
                    "step": d.step,
                    "level": d.level,
                    "src": slot_name(d.src),
                    "skip": d.skip.map(slot_name),
                    "dst": slot_name(d.dst),
                    "src_channels": d.src_channels,
                    "skip_channels": d.skip_channels,
                    "out_channels": d.out_channels,
                    "first_output": d.first_output,
                    "weights_offsets": d.weights_offsets,
                    "columns_per_invocation": d.columns_per_invocation(),
                    "relu": d.relu,
                })
            })
            .collect();
        let pu_max = pu_forward_raw(HDR_Y_MAX);
        let shaders: serde_json::Map<String, Value> = SHADER_FILES
            .iter()
            .map(|(kernel, file, _)| (kernel.to_string(), json!(file)))
            .collect();
        json!({
            "weights_file": WEIGHTS_FILE,
            "weights_bytes": self.layout.bytes.len(),
            "input_channels": INPUT_CHANNELS,
            "shaders": shaders,
            "pack_entry_point": "pack_tile",
            "unpack_entry_point": "unpack_tile",
            "workgroup": WORKGROUP,
            "alignment": ALIGNMENT,
            // The tiles' overlap: the page cuts native's tile plan.
            "tile_overlap": TILE_OVERLAP,
            "block_bytes": BLOCK_BYTES,
            "weights_alignment": WEB_UNIFORM_OFFSET_ALIGNMENT,
            "slots": Slot::ALL.map(slot_name),
            "input_slot": slot_name(Slot::Input),
            "output_slot": slot_name(OUTPUT_SLOT),
            "output_channels": OUTPUT_CHANNELS,
            "slot_floats_per_pixel": per_slot.map(|f| f as f64 / unit as f64),
            "steps": steps,
            "params": super::contract::denoise_params_json(),
            // As the native denoiser sets them: PU(65504) and its inverse.
            "pu_max": pu_max,
            "pu_norm": 1.0 / pu_max,
        })
    }
}
