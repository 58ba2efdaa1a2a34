// The cost heatmap's texels, as the window makes them
// (src/window/heatmap_view.rs): per pixel the work per sample (k-d nodes
// visited plus objects tested, over its rays, divided by its sample count)
// in the colour map of src/output/heatmap.rs (its control points come from
// contract.json), scaled to the image's largest work per sample.

// The colour map's level [r, g, b] (0..255) of `x` in [0, 1] (clamped):
// linear between the control points `stops` ([at, [r, g, b]], increasing).
export function colour(x, stops) {
  x = Number.isNaN(x) ? 0 : Math.min(Math.max(x, 0), 1);
  let i = 0;
  for (let k = 0; k < stops.length; k++) if (stops[k][0] <= x) i = k;
  i = Math.min(i, stops.length - 2);
  const [x0, c0] = stops[i];
  const [x1, c1] = stops[i + 1];
  const f = (x - x0) / (x1 - x0);
  return c0.map((c, k) => Math.round(c + f * (c1[k] - c)));
}

// { texels (Float32Array, 4 per pixel: a colour level / 255 and count 1, so
// the present pass gives back the colour map's levels; a pixel without
// samples stays empty), max (the scale's top: the largest work per sample,
// rounded up, at least 1) } of `costs` (`costWords` u32 per pixel: nodes,
// leaves, objects) over `sums` (4 f32 per pixel: colour sums and count).
export function heatmapTexels(costs, sums, costWords, stops) {
  const pixels = sums.length / 4;
  const work = new Float64Array(pixels);
  let max = 0;
  for (let i = 0; i < pixels; i++) {
    const n = sums[4 * i + 3];
    work[i] = n > 0 ? (costs[costWords * i] + costs[costWords * i + 2]) / n : -1;
    max = Math.max(max, work[i]);
  }
  max = Math.max(Math.ceil(max), 1);
  const texels = new Float32Array(4 * pixels);
  for (let i = 0; i < pixels; i++) {
    if (work[i] < 0) continue;
    const c = colour(work[i] / max, stops);
    texels.set([c[0] / 255, c[1] / 255, c[2] / 255, 1], 4 * i);
  }
  return { texels, max };
}
