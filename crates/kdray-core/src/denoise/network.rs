//! The U-Net of Open Image Denoise 1.4.3's RT filter, as a list of steps
//! over a few tensor slots: the CPU reference (`cpu_net`) and the GPU run
//! the same list, so they cannot disagree on the wiring.
//!
//! Five levels (full resolution, then halved four times by 2x2 max
//! pooling); sixteen 3x3 convolutions with bias, all but the last followed
//! by ReLU; the decoder upsamples (2x nearest) and concatenates the
//! encoder's pooled tensor of the same level after the upsampled one, and
//! at full resolution the network's own input. Concatenation is never
//! stored: a convolution reads its two inputs in turn.
//!
//! Slots: `Input` (the packed input, kept for the last concatenation),
//! `Skip1..Skip3` (the pooled tensors the decoder concatenates) and `A`, `B`
//! (two scratch tensors the other steps alternate between). No step reads
//! the slot it writes.

/// Where a step reads or writes a tensor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Slot {
    Input,
    A,
    B,
    Skip1,
    Skip2,
    Skip3,
}

impl Slot {
    pub const ALL: [Slot; 6] = [
        Slot::Input,
        Slot::A,
        Slot::B,
        Slot::Skip1,
        Slot::Skip2,
        Slot::Skip3,
    ];
}

/// One step of the network. `level` is the resolution of what it writes:
/// the tile's size divided by 2^level.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// 3x3 convolution of `src` (then `skip`'s channels, if any) with the
    /// weights of [`CONV_LAYERS`]`[layer]`, plus bias, then ReLU if `relu`.
    Conv {
        layer: usize,
        src: Slot,
        skip: Option<Slot>,
        dst: Slot,
        relu: bool,
        level: u32,
    },
    /// 2x2 max pooling, stride 2.
    Pool { src: Slot, dst: Slot, level: u32 },
    /// 2x nearest-neighbour upsampling.
    Upsample { src: Slot, dst: Slot, level: u32 },
}

impl Step {
    pub fn dst(self) -> Slot {
        match self {
            Step::Conv { dst, .. } | Step::Pool { dst, .. } | Step::Upsample { dst, .. } => dst,
        }
    }

    pub fn level(self) -> u32 {
        match self {
            Step::Conv { level, .. } | Step::Pool { level, .. } | Step::Upsample { level, .. } => {
                level
            }
        }
    }
}

/// A convolution's name in the weights and its output channels.
#[derive(Clone, Copy, Debug)]
pub struct ConvLayer {
    pub name: &'static str,
    pub out_channels: usize,
}

const fn conv(name: &'static str, out_channels: usize) -> ConvLayer {
    ConvLayer { name, out_channels }
}

/// The sixteen convolutions in the order they run (OIDN's training
/// model.py: ec1 32, ec2 48, ec3 64, ec4 80, ec5 96, dc4 112, dc3 96,
/// dc2 64, dc1a 64, dc1b 32, output 3).
pub const CONV_LAYERS: [ConvLayer; 16] = [
    conv("enc_conv0", 32),
    conv("enc_conv1", 32),
    conv("enc_conv2", 48),
    conv("enc_conv3", 64),
    conv("enc_conv4", 80),
    conv("enc_conv5a", 96),
    conv("enc_conv5b", 96),
    conv("dec_conv4a", 112),
    conv("dec_conv4b", 112),
    conv("dec_conv3a", 96),
    conv("dec_conv3b", 96),
    conv("dec_conv2a", 64),
    conv("dec_conv2b", 64),
    conv("dec_conv1a", 64),
    conv("dec_conv1b", 32),
    conv("dec_conv0", 3),
];

/// The output channels of the network: linear RGB in the transfer
/// function's space.
pub const OUTPUT_CHANNELS: usize = 3;

/// Images are padded to a multiple of this (four 2x2 poolings).
pub const ALIGNMENT: usize = 16;

/// OIDN's receptive field of the network, in pixels; tiles overlap by half
/// of it rounded up to the alignment (96), so a tiled image equals the
/// whole one.
pub const RECEPTIVE_FIELD: usize = 174;
pub const TILE_OVERLAP: usize = (RECEPTIVE_FIELD / 2).div_ceil(ALIGNMENT) * ALIGNMENT;

const fn c(layer: usize, src: Slot, dst: Slot, level: u32) -> Step {
    Step::Conv {
        layer,
        src,
        skip: None,
        dst,
        relu: true,
        level,
    }
}

const fn cat(layer: usize, src: Slot, skip: Slot, dst: Slot, level: u32) -> Step {
    Step::Conv {
        layer,
        src,
        skip: Some(skip),
        dst,
        relu: true,
        level,
    }
}

const fn pool(src: Slot, dst: Slot, level: u32) -> Step {
    Step::Pool { src, dst, level }
}

const fn up(src: Slot, dst: Slot, level: u32) -> Step {
    Step::Upsample { src, dst, level }
}

use Slot::{Input, Skip1, Skip2, Skip3, A, B};

/// The whole network; the output is in [`OUTPUT_SLOT`].
pub const STEPS: [Step; 24] = [
    c(0, Input, A, 0),
    c(1, A, B, 0),
    pool(B, Skip1, 1),
    c(2, Skip1, A, 1),
    pool(A, Skip2, 2),
    c(3, Skip2, A, 2),
    pool(A, Skip3, 3),
    c(4, Skip3, A, 3),
    pool(A, B, 4),
    c(5, B, A, 4),
    c(6, A, B, 4),
    up(B, A, 3),
    cat(7, A, Skip3, B, 3),
    c(8, B, A, 3),
    up(A, B, 2),
    cat(9, B, Skip2, A, 2),
    c(10, A, B, 2),
    up(B, A, 1),
    cat(11, A, Skip1, B, 1),
    c(12, B, A, 1),
    up(A, B, 0),
    cat(13, B, Input, A, 0),
    c(14, A, B, 0),
    Step::Conv {
        layer: 15,
        src: B,
        skip: None,
        dst: A,
        relu: false,
        level: 0,
    },
];

pub const OUTPUT_SLOT: Slot = A;

/// The channels each step writes, for a network reading `input_channels`
/// (3 colour, plus 3 albedo, plus 3 normal).
pub fn step_channels(input_channels: usize) -> [usize; STEPS.len()] {
    let mut held = [0usize; Slot::ALL.len()];
    held[slot_index(Input)] = input_channels;
    let mut out = [0; STEPS.len()];
    for (i, step) in STEPS.iter().enumerate() {
        let channels = match *step {
            Step::Conv { layer, .. } => CONV_LAYERS[layer].out_channels,
            Step::Pool { src, .. } | Step::Upsample { src, .. } => held[slot_index(src)],
        };
        held[slot_index(step.dst())] = channels;
        out[i] = channels;
    }
    out
}

/// The input channels of each convolution (its source's, then its skip's).
pub fn conv_input_channels(input_channels: usize) -> [usize; CONV_LAYERS.len()] {
    let written = step_channels(input_channels);
    let mut held = [0usize; Slot::ALL.len()];
    held[slot_index(Input)] = input_channels;
    let mut out = [0; CONV_LAYERS.len()];
    for (step, channels) in STEPS.iter().zip(written) {
        if let Step::Conv {
            layer, src, skip, ..
        } = *step
        {
            out[layer] = held[slot_index(src)] + skip.map_or(0, |s| held[slot_index(s)]);
        }
        held[slot_index(step.dst())] = channels;
    }
    out
}

/// The position of `slot` in [`Slot::ALL`] (which lists the slots in
/// their declared order).
pub fn slot_index(slot: Slot) -> usize {
    slot as usize
}

/// The most floats any one tensor of the network holds for a tile of
/// `height` x `width` (multiples of [`ALIGNMENT`]), and for each slot the
/// most floats it ever holds (what to allocate for it).
pub fn tensor_floats(input_channels: usize, height: usize, width: usize) -> (usize, [usize; 6]) {
    let mut per_slot = [0usize; Slot::ALL.len()];
    per_slot[slot_index(Input)] = input_channels * height * width;
    for (step, channels) in STEPS.iter().zip(step_channels(input_channels)) {
        let floats = channels * (height >> step.level()) * (width >> step.level());
        let slot = &mut per_slot[slot_index(step.dst())];
        *slot = (*slot).max(floats);
    }
    (per_slot.iter().copied().max().unwrap_or(0), per_slot)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_slots_index_is_its_place_in_all() {
        for (i, &slot) in Slot::ALL.iter().enumerate() {
            assert_eq!(slot_index(slot), i, "{slot:?}");
        }
    }

    /// The wiring is a U-Net: each convolution reads what OIDN's model
    /// gives it (enc_conv0 the input, dec_conv4a 96 + 64, dec_conv1a 64 +
    /// the input), levels go down by one per pooling and up by one per
    /// upsampling, and every step reads a slot written before at its level.
    #[test]
    fn the_steps_wire_oidns_unet() {
        let ic = conv_input_channels(9);
        assert_eq!(ic[0], 9);
        assert_eq!(ic[7], 96 + 64);
        assert_eq!(ic[9], 112 + 48);
        assert_eq!(ic[11], 96 + 32);
        assert_eq!(ic[13], 64 + 9);
        assert_eq!(conv_input_channels(3)[13], 64 + 3);
        let mut level_of = std::collections::HashMap::from([(Input, 0u32)]);
        for step in STEPS {
            let (reads, expected_level): (Vec<Slot>, u32) = match step {
                Step::Conv {
                    src, skip, level, ..
                } => (std::iter::once(src).chain(skip).collect(), level),
                Step::Pool { src, level, .. } => (vec![src], level - 1),
                Step::Upsample { src, level, .. } => (vec![src], level + 1),
            };
            for slot in reads {
                assert_ne!(slot, step.dst(), "{step:?} reads what it writes");
                assert_eq!(level_of.get(&slot), Some(&expected_level), "{step:?}");
            }
            level_of.insert(step.dst(), step.level());
        }
        assert_eq!(level_of[&OUTPUT_SLOT], 0);
        assert_eq!(step_channels(9)[STEPS.len() - 1], OUTPUT_CHANNELS);
    }

    #[test]
    fn the_largest_tensor_is_the_full_resolution_64_channel_one() {
        let (largest, per_slot) = tensor_floats(9, 32, 48);
        assert_eq!(largest, 64 * 32 * 48);
        assert_eq!(per_slot[slot_index(Input)], 9 * 32 * 48);
        assert_eq!(per_slot[slot_index(Skip3)], 64 * 4 * 6);
        assert_eq!(TILE_OVERLAP, 96);
    }
}
