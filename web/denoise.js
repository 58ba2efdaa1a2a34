// The page's denoiser (denoise=1, key N): OIDN's rt_hdr_alb_nrm network as
// `kdray render --denoise` runs it, in the site's copies of
// shaders/denoise/ (contract.json's `denoise.shaders`). Everything it runs
// comes from contract.json's `denoise`: the weights file in the layout the
// native denoiser uploads, the table of dispatches native records its pass
// from (kernel, slots, channels, group, weights block, level), the
// kernels' uniform layouts, the tiles' alignment and overlap and the
// transfer function's constants. The page derives only sizes from its
// image: the tiles of native's plan (tilePlan, kdray_core's
// denoise::tiling, which tests/external/web.rs holds it to), each no
// larger than the adapter's storage binding allows, run one after the
// other as native runs them.

import { PageError, setField } from './tracer.js';

const f = Math.fround;
const MiB = (n) => `${(n / 1048576).toFixed(1)} MiB`;

// OIDN's autoexposure of `rgb` (three floats a pixel, row-major) in the
// steps of kdray_core's denoise::transfer::autoexposure: blocks of about
// 16 x 16 pixels, each block's mean Rec. 709 luminance (f32 terms summed
// in f64), the mean log2 of those above 1e-8, and the scale that brings
// their geometric mean to 0.18 (1 when no block is bright enough).
export function autoexposure(width, height, rgb) {
  const KEY = f(0.18);
  const EPS = f(1e-8);
  const K = 16;
  const [lr, lg, lb] = [f(0.212671), f(0.71516), f(0.072169)];
  const F32_MAX = 3.4028234663852886e38;
  const clean = (v) => (Number.isNaN(v) ? 0 : Math.min(Math.max(v, 0), F32_MAX));
  const hk = Math.floor((height + K / 2) / K);
  const wk = Math.floor((width + K / 2) / K);
  let sum = 0;
  let count = 0;
  for (let i = 0; i < hk; i++) {
    const y0 = Math.floor((i * height) / hk);
    const y1 = Math.floor(((i + 1) * height) / hk);
    for (let j = 0; j < wk; j++) {
      const x0 = Math.floor((j * width) / wk);
      const x1 = Math.floor(((j + 1) * width) / wk);
      let l = 0;
      for (let y = y0; y < y1; y++) {
        for (let x = x0; x < x1; x++) {
          const at = (y * width + x) * 3;
          const r = clean(rgb[at]);
          const g = clean(rgb[at + 1]);
          const b = clean(rgb[at + 2]);
          l += f(f(f(lr * r) + f(lg * g)) + f(lb * b));
        }
      }
      const mean = f(l / ((y1 - y0) * (x1 - x0)));
      if (mean > EPS) {
        sum += f(Math.log2(mean));
        count += 1;
      }
    }
  }
  return count > 0 ? f(KEY / f(2 ** f(sum / count))) : 1;
}

// The colour, albedo and normal images (three floats a pixel each, one
// after the other) from render_tile's feature output `words` (a
// Float32Array of the whole buffer) of `pixels` pixels and `samples`
// samples: each sum divided by the samples in f32, as the native renderer
// divides them (src/gpu/renderer.rs).
export function featureImages(words, pixels, samples, format) {
  const images = new Float32Array(9 * pixels);
  const head = format.header_bytes / 4;
  const per = format.words_per_pixel;
  const starts = [0, format.albedo_word, format.normal_word];
  for (let i = 0; i < pixels; i++) {
    const at = head + i * per;
    starts.forEach((start, k) => {
      for (let c = 0; c < 3; c++) images[k * 3 * pixels + 3 * i + c] = f(words[at + start + c] / samples);
    });
  }
  return images;
}

// Native's tile plan (kdray_core::denoise::TilePlan::new) of a `width` x
// `height` image for `spec` (contract.json's `denoise`), each tensor at
// most `maxTensorBytes` where the minimum tile allows: the tile size
// starts at the image rounded up to the alignment and, while the largest
// tensor exceeds the limit, the longer side is cut into one more tile,
// never below three overlaps. Tiles overlap by `tile_overlap` on inner
// sides; a smaller last tile is zero-padded at the top and left.
// Returns { tileWidth, tileHeight, largestBytes, tiles }, each tile as
// native's Tile (src_*, offset_*, out_*).
export function tilePlan(width, height, spec, maxTensorBytes) {
  const a = spec.alignment;
  const o = spec.tile_overlap;
  const roundUp = (n, to) => Math.ceil(n / to) * to;
  const minTile = 3 * o;
  const side = (n, count) => (count === 1 ? roundUp(n, a)
    : Math.max(roundUp(Math.ceil(Math.max(n - 2 * o, 0) / count), a) + 2 * o, minTile));
  const floatsPerPixel = Math.max(...spec.slot_floats_per_pixel);
  const bytes = (h, w) => 4 * floatsPerPixel * h * w;
  let [countH, countW] = [1, 1];
  let [tileH, tileW] = [side(height, 1), side(width, 1)];
  while (bytes(tileH, tileW) > maxTensorBytes) {
    if (tileH > minTile && tileH > tileW) {
      countH += 1;
      tileH = side(height, countH);
    } else if (tileW > minTile) {
      countW += 1;
      tileW = side(width, countW);
    } else {
      break;
    }
  }
  const spans = (n, tile) => {
    const count = n > tile ? Math.ceil((n - 2 * o) / (tile - 2 * o)) : 1;
    return Array.from({ length: count }, (_, i) => {
      const start = i === 0 ? 0 : i * (tile - 2 * o);
      const begin = i > 0 ? o : 0;
      const end = i + 1 < count ? o : 0;
      const size = Math.min(n - start, tile);
      return [start, size, tile - roundUp(size, a), start + begin, size - begin - end];
    });
  };
  const tiles = [];
  for (const [src_y, src_height, offset_y, out_y, out_height] of spans(height, tileH)) {
    for (const [src_x, src_width, offset_x, out_x, out_width] of spans(width, tileW)) {
      tiles.push({ src_y, src_x, src_height, src_width, offset_y, offset_x, out_y, out_x, out_height, out_width });
    }
  }
  return { tileWidth: tileW, tileHeight: tileH, largestBytes: bytes(tileH, tileW), tiles };
}

export class Denoiser {
  // A Denoiser, its pipelines checked: a kernel the browser refuses is a
  // PageError with the browser's message.
  static async create(device, spec, sources, weights) {
    device.pushErrorScope('validation');
    const denoiser = new Denoiser(device, spec, sources, weights);
    const error = await device.popErrorScope();
    if (error) throw new PageError(`the denoiser's kernels: ${error.message}`);
    return denoiser;
  }

  // The network on `device`: `spec` is contract.json's `denoise`,
  // `sources` the WGSL of each of its shader files by name, `weights` the
  // weights file's bytes.
  constructor(device, spec, sources, weights) {
    this.device = device;
    this.spec = spec;
    const { limits } = device;
    if (limits.maxUniformBufferBindingSize < spec.block_bytes) {
      throw new PageError(`the denoiser binds ${spec.block_bytes}-byte uniform buffers; the adapter allows ` +
        `${limits.maxUniformBufferBindingSize} (maxUniformBufferBindingSize)`);
    }
    if (spec.weights_alignment % limits.minUniformBufferOffsetAlignment !== 0) {
      throw new PageError(`the denoiser's weights blocks are ${spec.weights_alignment}-byte aligned; the adapter ` +
        `needs ${limits.minUniformBufferOffsetAlignment} (minUniformBufferOffsetAlignment)`);
    }
    if (weights.byteLength !== spec.weights_bytes) {
      throw new PageError(`${spec.weights_file} is ${weights.byteLength} bytes, not the ${spec.weights_bytes} contract.json says`);
    }
    const modules = new Map(Object.entries(sources).map(([name, code]) => [name,
      device.createShaderModule({ label: `denoise ${name}`, code })]));
    this.pipelines = new Map();
    const pipeline = (shader, entryPoint) => {
      const id = `${shader}|${entryPoint}`;
      if (!this.pipelines.has(id)) {
        this.pipelines.set(id, device.createComputePipeline({
          label: `denoise ${entryPoint}`, layout: 'auto', compute: { module: modules.get(shader), entryPoint },
        }));
      }
      return this.pipelines.get(id);
    };
    this.pipeline = pipeline;
    this.pack = pipeline('pack', spec.pack_entry_point);
    this.unpack = pipeline('pack', spec.unpack_entry_point);
    for (const s of spec.steps) pipeline(s.shader, s.entry_point);
    this.weights = device.createBuffer({ label: 'denoise weights', size: weights.byteLength, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    device.queue.writeBuffer(this.weights, 0, weights);
    this.run = null;
  }

  // The buffers and bind groups for a `width` x `height` image: its
  // tile plan's, every tile the same size.
  prepare(width, height) {
    if (this.run && this.run.width === width && this.run.height === height) return this.run;
    this.release();
    const { device, spec } = this;
    const limit = device.limits.maxStorageBufferBindingSize;
    const plan = tilePlan(width, height, spec, limit);
    const tw = plan.tileWidth;
    const th = plan.tileHeight;
    if (plan.largestBytes > limit) {
      throw new PageError(`denoising needs a ${MiB(plan.largestBytes)} tensor even in the smallest tiles ` +
        `(${tw} x ${th}), over the adapter's ${MiB(limit)} storage binding`);
    }
    const slotBytes = spec.slot_floats_per_pixel.map((floats) => 4 * floats * tw * th);
    const storage = (label, bytes, extra = 0) => device.createBuffer({ label, size: Math.max(4, bytes), usage: GPUBufferUsage.STORAGE | extra });
    const slots = new Map(spec.slots.map((name, i) => [name, storage(`denoise ${name}`, slotBytes[i])]));
    const images = storage('denoise images', 4 * spec.input_channels * tw * th, GPUBufferUsage.COPY_DST);
    const outBytes = 4 * spec.output_channels * tw * th;
    const out = storage('denoise output', outBytes, GPUBufferUsage.COPY_SRC);
    const readback = device.createBuffer({ size: outBytes, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
    const packParams = device.createBuffer({ size: spec.params.pack.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    const uniforms = [];
    const uniform = (layout, values) => {
      const bytes = new ArrayBuffer(layout.size);
      for (const [name, v] of Object.entries(values)) setField(layout, bytes, name, v);
      const buffer = device.createBuffer({ size: layout.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
      device.queue.writeBuffer(buffer, 0, bytes);
      uniforms.push(buffer);
      return buffer;
    };
    const group = (pipeline, resources) => device.createBindGroup({
      layout: pipeline.getBindGroupLayout(0),
      entries: resources.map((resource, binding) => ({ binding, resource })),
    });
    const whole = (buffer) => ({ buffer });
    const groupsOf = (n) => Math.ceil(n / spec.workgroup);
    const dispatches = spec.steps.map((s) => {
      const w = tw >> s.level;
      const h = th >> s.level;
      const pipeline = this.pipeline(s.shader, s.entry_point);
      let resources;
      if (s.entry_point === 'conv3x3') {
        const params = uniform(spec.params.conv, {
          width: w, height: h, src_channels: s.src_channels, skip_channels: s.skip_channels,
          out_channels: s.out_channels, first_output: s.first_output, relu: s.relu ? 1 : 0,
        });
        const block = (offset) => ({ buffer: this.weights, offset, size: spec.block_bytes });
        resources = [whole(params), ...s.weights_offsets.map(block),
          whole(slots.get(s.src)), whole(slots.get(s.skip ?? s.src)), whole(slots.get(s.dst))];
      } else {
        const params = uniform(spec.params.resample, { width: w, height: h, channels: s.out_channels });
        resources = [whole(params), whole(slots.get(s.src)), whole(slots.get(s.dst))];
      }
      const columns = Math.ceil(w / (spec.workgroup * s.columns_per_invocation));
      return { pipeline, group: group(pipeline, resources), workgroups: [columns, groupsOf(h), s.workgroups_z] };
    });
    const pack = { pipeline: this.pack, group: group(this.pack, [packParams, images, slots.get(spec.input_slot)].map(whole)),
      workgroups: [groupsOf(tw), groupsOf(th), 1] };
    // The unpacking's workgroups are each tile's output rectangle's.
    const unpack = { pipeline: this.unpack, group: group(this.unpack, [packParams, slots.get(spec.output_slot), out].map(whole)) };
    this.run = {
      width, height, tw, th, plan, images, out, readback, packParams, pack, dispatches, unpack,
      buffers: [...slots.values(), images, out, readback, packParams, ...uniforms],
    };
    return this.run;
  }

  release() {
    for (const b of this.run?.buffers ?? []) b.destroy();
    this.run = null;
  }

  // The denoised image (three floats a pixel) of `images` (colour, albedo
  // and normal of a `width` x `height` image, as featureImages gives
  // them), colour scaled by `scale` on the way in and back by its inverse:
  // tile after tile of the plan, each tile's source rectangle of the three
  // images uploaded, packed, run through the network, and its output
  // rectangle unpacked, read back and put in place.
  async denoise(width, height, images, scale) {
    const { device, spec } = this;
    const run = this.prepare(width, height);
    const pixels = width * height;
    const rgb = new Float32Array(3 * pixels);
    const groupsOf = (n) => Math.ceil(n / spec.workgroup);
    for (const t of run.plan.tiles) {
      const params = new ArrayBuffer(spec.params.pack.size);
      const set = (name, v) => setField(spec.params.pack, params, name, v);
      set('tile_width', run.tw); set('tile_height', run.th);
      set('src_width', t.src_width); set('src_height', t.src_height);
      set('offset_x', t.offset_x); set('offset_y', t.offset_y);
      set('channels', spec.input_channels);
      set('out_x', t.out_x - t.src_x); set('out_y', t.out_y - t.src_y);
      set('out_width', t.out_width); set('out_height', t.out_height);
      set('input_scale', scale);
      set('output_scale', scale !== 0 ? f(1 / scale) : 0);
      set('pu_norm', spec.pu_norm); set('pu_max', spec.pu_max);
      const region = new Float32Array(3 * 3 * t.src_width * t.src_height);
      let at = 0;
      for (let k = 0; k < 3; k++) {
        for (let y = t.src_y; y < t.src_y + t.src_height; y++) {
          const row = 3 * (k * pixels + y * width + t.src_x);
          region.set(images.subarray(row, row + 3 * t.src_width), at);
          at += 3 * t.src_width;
        }
      }
      device.queue.writeBuffer(run.packParams, 0, params);
      device.queue.writeBuffer(run.images, 0, region);
      const encoder = device.createCommandEncoder();
      const pass = encoder.beginComputePass();
      const unpack = { ...run.unpack, workgroups: [groupsOf(t.out_width), groupsOf(t.out_height), 1] };
      for (const d of [run.pack, ...run.dispatches, unpack]) {
        pass.setPipeline(d.pipeline);
        pass.setBindGroup(0, d.group);
        pass.dispatchWorkgroups(...d.workgroups);
      }
      pass.end();
      const bytes = 4 * spec.output_channels * t.out_width * t.out_height;
      encoder.copyBufferToBuffer(run.out, 0, run.readback, 0, bytes);
      device.queue.submit([encoder.finish()]);
      await run.readback.mapAsync(GPUMapMode.READ, 0, bytes);
      const rect = new Float32Array(run.readback.getMappedRange(0, bytes).slice(0));
      run.readback.unmap();
      const rowFloats = 3 * t.out_width;
      for (let r = 0; r < t.out_height; r++) {
        rgb.set(rect.subarray(r * rowFloats, (r + 1) * rowFloats), 3 * ((t.out_y + r) * width + t.out_x));
      }
    }
    return rgb;
  }
}
