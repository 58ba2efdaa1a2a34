// The path tracer's random numbers: one PCG32 stream (O'Neill 2014, the
// RXS-M-XS output) per sample, seeded from the pixel's index in the image,
// the sample's index and `params.seed`, so a sample's numbers depend on
// nothing else (not the tile, the band or the dispatch it runs in).

var<private> rng_state: u32;

// PCG's RXS-M-XS permutation of one LCG step: a 32-bit hash.
fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn seed_random(pixel_index: u32, sample: u32) {
    rng_state = pcg_hash(pixel_index ^ pcg_hash(sample ^ pcg_hash(params.seed)));
}

// Uniform in [0, 1): 24 bits.
fn random() -> f32 {
    rng_state = rng_state * 747796405u + 2891336453u;
    let s = rng_state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return f32(((word >> 22u) ^ word) >> 8u) * (1.0 / 16777216.0);
}
