//! [`DenoiseRun`]: one image's denoise as a sequence of units of work,
//! tile after tile ([`super::work_units`]). [`super::Denoiser::denoise`]
//! runs each tile's units in one submission (`render --denoise`, the
//! farm); the window runs a few units between frames
//! ([`DenoiseRun::advance`]). Both run the same units in the same order,
//! so their outputs are equal.

use kdray_core::denoise::transfer::pu_forward_raw;
use kdray_core::denoise::transfer::HDR_Y_MAX;
use kdray_core::denoise::{DenoiseImages, TilePlan};

use super::tile_run::{PackParams, TileRun};
use crate::error::{Error, Result};
use crate::gpu::GpuContext;

pub struct DenoiseRun {
    width: usize,
    height: usize,
    input_channels: usize,
    plan: TilePlan,
    run: TileRun,
    /// OIDN's input scale (autoexposure, or the caller's).
    scale: f32,
    /// The tile in progress, and its next unit.
    tile: usize,
    unit: usize,
    /// Cost of the units run so far, and of the whole run.
    done_cost: u64,
    total_cost: u64,
    /// The denoised image so far: three floats a pixel.
    out: Vec<f32>,
}

impl DenoiseRun {
    /// A run over `plan`'s tiles of a `width` x `height` image through
    /// `run`'s network, at input scale `scale`; nothing run yet.
    pub(super) fn new(
        (width, height): (usize, usize),
        input_channels: usize,
        plan: TilePlan,
        run: TileRun,
        scale: f32,
    ) -> Self {
        let per_tile: u64 = run.units().iter().map(|u| u.cost).sum();
        DenoiseRun {
            width,
            height,
            input_channels,
            total_cost: per_tile * plan.tiles.len() as u64,
            plan,
            run,
            scale,
            tile: 0,
            unit: 0,
            done_cost: 0,
            out: vec![0.0; width * height * 3],
        }
    }

    /// Whether every unit of every tile has run.
    pub fn is_finished(&self) -> bool {
        self.tile >= self.plan.tiles.len()
    }

    /// Cost of the units run so far and of the whole run (see
    /// [`super::work_units`]).
    pub fn progress(&self) -> (u64, u64) {
        (self.done_cost, self.total_cost)
    }

    /// Costs of the units left in the tile in progress, in order (an
    /// [`Self::advance`] runs some of them).
    pub fn next_costs(&self) -> impl Iterator<Item = u64> + '_ {
        let units = if self.is_finished() {
            &[][..]
        } else {
            &self.run.units()[self.unit..]
        };
        units.iter().map(|u| u.cost)
    }

    /// Runs the next `units` units (at least one, at most the rest of the
    /// tile in progress) of the denoise of `images` (the images the run
    /// was made for) in one submission, and waits for them. Returns their
    /// cost.
    pub fn advance(
        &mut self,
        ctx: &GpuContext,
        images: &DenoiseImages<'_>,
        units: usize,
    ) -> Result<u64> {
        if self.is_finished() {
            return Ok(0);
        }
        if (images.width, images.height, images.input_channels())
            != (self.width, self.height, self.input_channels)
        {
            return Err(Error::Usage(
                "a denoise went on with other images than it began with".into(),
            ));
        }
        let tile = self.plan.tiles[self.tile];
        let pu_max = pu_forward_raw(HDR_Y_MAX);
        let params = PackParams {
            tile_width: self.plan.tile_width as u32,
            tile_height: self.plan.tile_height as u32,
            src_width: tile.src_width as u32,
            src_height: tile.src_height as u32,
            offset_x: tile.offset_x as u32,
            offset_y: tile.offset_y as u32,
            channels: self.input_channels as u32,
            out_x: (tile.out_x - tile.src_x) as u32,
            out_y: (tile.out_y - tile.src_y) as u32,
            out_width: tile.out_width as u32,
            out_height: tile.out_height as u32,
            input_scale: self.scale,
            output_scale: if self.scale != 0.0 {
                1.0 / self.scale
            } else {
                0.0
            },
            pu_norm: 1.0 / pu_max,
            pu_max,
            pad: 0,
        };
        let mut region = Vec::new();
        if self.unit == 0 {
            let sources = std::iter::once(images.color)
                .chain(images.albedo)
                .chain(images.normal);
            for source in sources {
                for y in tile.src_y..tile.src_y + tile.src_height {
                    let row = (y * self.width + tile.src_x) * 3;
                    region.extend_from_slice(&source[row..row + tile.src_width * 3]);
                }
            }
        }
        let all = self.run.units().len();
        let end = self.unit + units.clamp(1, all - self.unit);
        let range = self.unit..end;
        let cost: u64 = self.run.units()[range.clone()].iter().map(|u| u.cost).sum();
        let rect = self.run.run_units(ctx, range, &region, &params)?;
        self.done_cost += cost;
        self.unit = end;
        if let Some(rect) = rect {
            let row_floats = tile.out_width * 3;
            for (r, row) in rect.chunks_exact(row_floats).enumerate() {
                let at = ((tile.out_y + r) * self.width + tile.out_x) * 3;
                self.out[at..at + row_floats].copy_from_slice(row);
            }
        }
        if self.unit == all {
            self.tile += 1;
            self.unit = 0;
        }
        Ok(cost)
    }

    /// The denoised image (three floats a pixel), once finished.
    pub fn into_output(self) -> Result<Vec<f32>> {
        match self.is_finished() {
            true => Ok(self.out),
            false => Err(Error::Gpu("an unfinished denoise has no output".into())),
        }
    }
}
