// The WebGPU side: the adapter and device (with the adapter's own limits),
// the scene's buffers, the trace kernel's accumulate entry point (one
// stratified sample per pixel per pass, as the native window) with only the
// bindings the scene and walk read, the present pass, and the readback of
// the traced image. With `costs` on, the kernel also counts each pixel's
// walk work (COUNT_COSTS) and the present pass shows the cost heatmap made
// from it (heatmap.js). The inspect kernel's entry point traces one pixel's
// sample and logs its rays and walks (inspectPixel). While the page
// denoises, each image pass also adds its sample to render_tile's radiance
// and feature sums (the `features` entry point of the contract, as
// `render --denoise` traces them), and the present pass can show the
// denoised image instead of the accumulation. Every binding, layout
// and constant comes from contract.json, and the kernel's overrides from
// the bundle (those of the scene, as the native host sets them) and the
// contract (those of the walk, costs, integrator and entry point); the WGSL
// is the site's kernel.wgsl, inspect.wgsl and present.wgsl.

import { heatmapTexels } from './heatmap.js';

export class PageError extends Error {}

export const NO_WEBGPU =
  'This browser has no WebGPU, which kdray needs to trace in the page. It is on by default in ' +
  'Chrome and Edge 113+ (Windows, macOS, ChromeOS; on Linux start Chrome with ' +
  '--enable-unsafe-webgpu --enable-features=Vulkan), Safari 26+ and Firefox 141+ (Windows); ' +
  'in Firefox elsewhere set dom.webgpu.enabled in about:config.';

// The adapter and a device with its storage limits.
export async function openGpu() {
  if (!navigator.gpu) throw new PageError(NO_WEBGPU);
  const adapter = await navigator.gpu.requestAdapter();
  if (!adapter) throw new PageError(`${NO_WEBGPU} (navigator.gpu gave no adapter)`);
  const wanted = ['maxStorageBuffersPerShaderStage', 'maxStorageBufferBindingSize', 'maxBufferSize'];
  const requiredLimits = Object.fromEntries(wanted.map((k) => [k, adapter.limits[k]]));
  const device = await adapter.requestDevice({ requiredLimits });
  const info = adapter.info || {};
  const name = [info.vendor, info.architecture, info.description].filter((s) => s).join(' ') || 'WebGPU adapter';
  return { adapter, device, name };
}

const MiB = (n) => `${(n / 1048576).toFixed(1)} MiB`;

// Writes `values` into the struct field `name` of a uniform's bytes.
export function setField(layout, bytes, name, values) {
  const field = layout.fields[name];
  const view = new DataView(bytes);
  [].concat(values).forEach((v, i) => {
    const at = field.offset + 4 * i;
    if (field.type === 'f32') view.setFloat32(at, v, true);
    else view.setUint32(at, v, true);
  });
}

export function getField(layout, bytes, name) {
  const field = layout.fields[name];
  const view = new DataView(bytes);
  const values = [];
  for (let i = 0; i < field.count; i++) {
    const at = field.offset + 4 * i;
    values.push(field.type === 'f32' ? view.getFloat32(at, true) : view.getUint32(at, true));
  }
  return field.count === 1 ? values[0] : values;
}

export class Tracer {
  constructor(gpu, contract, kernelSource, presentSource, canvas, inspectSource) {
    this.gpu = gpu;
    this.device = gpu.device;
    this.contract = contract;
    this.kernelSource = kernelSource;
    this.inspectSource = inspectSource;
    this.canvas = canvas;
    this.context = canvas.getContext('webgpu');
    this.format = navigator.gpu.getPreferredCanvasFormat();
    this.context.configure({ device: this.device, format: this.format, alphaMode: 'opaque' });
    this.modules = new Map();
    this.pipelines = new Map();
    const present = contract.present;
    const module = this.device.createShaderModule({ label: 'present', code: presentSource });
    this.presentLayout = this.device.createBindGroupLayout({
      entries: present.bindings.map((b) => ({
        binding: b.index, visibility: GPUShaderStage.FRAGMENT, buffer: { type: b.access },
      })),
    });
    this.presentPipeline = this.device.createRenderPipeline({
      layout: this.device.createPipelineLayout({ bindGroupLayouts: [this.presentLayout] }),
      vertex: { module, entryPoint: present.vertex },
      fragment: { module, entryPoint: present.fragment, targets: [{ format: this.format }] },
      primitive: { topology: 'triangle-list' },
    });
    this.presentParams = this.device.createBuffer({
      size: present.params.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
    });
    this.frameParams = this.device.createBuffer({
      size: contract.frame_params.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
    });
    this.featureParams = this.device.createBuffer({
      size: contract.frame_params.size, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST,
    });
    // Whether image passes add to the feature sums (the page denoises).
    this.features = false;
  }

  // Uploads `bundle`'s arrays (refused with the limit named when one is
  // past what the adapter binds).
  load(bundle) {
    const limit = this.device.limits.maxStorageBufferBindingSize;
    for (const [name, bytes] of bundle.arrays) {
      if (bytes.length > limit) {
        throw new PageError(
          `the scene is too large for this browser: its ${name} buffer needs ${MiB(bytes.length)} but ` +
          `the adapter binds at most ${MiB(limit)} per storage buffer (maxStorageBufferBindingSize)`);
      }
    }
    for (const b of this.sceneBuffers?.values() ?? []) b.destroy();
    this.sceneBuffers = new Map();
    for (const [name, bytes] of bundle.arrays) {
      // An empty array gets one zeroed element, as the native host does.
      const size = Math.max(this.contract.bundle.empty_array_bytes, Math.ceil(bytes.length / 4) * 4);
      const buffer = this.device.createBuffer({ label: name, size, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_DST });
      if (bytes.length) this.device.queue.writeBuffer(buffer, 0, bytes, 0, bytes.length & ~3);
      this.sceneBuffers.set(name, buffer);
    }
    this.needs = new Set(bundle.info.needs);
    // The overrides that follow from the scene, as the native host sets them.
    this.sceneOverrides = bundle.info.overrides ?? {};
    // How path radiance is shown ([render] tone_map and exposure).
    this.pathToneMap = bundle.info.path_tone_map;
    this.exposureScale = bundle.info.exposure_scale;
    this.toneMap = this.contract.constants.PRESENT_QUANTISE;
    this.groups = new Map();
  }

  // The contract's pipeline choices for `walk`, `costs`, `integrator` and
  // `entry`: each the overrides it sets and the bindings it needs.
  choicesFor(walk, costs, integrator, entry) {
    const all = this.contract.pipeline_choices;
    const picked = [['walk', walk], ['costs', costs ? 'on' : 'off'], ['integrator', integrator], ['entry', entry]];
    return picked.map(([choice, value]) => {
      const made = all[choice][value];
      if (!made) throw new PageError(`contract.json has no ${choice} ${value}`);
      return made;
    });
  }

  // The accumulate bindings for `walk` ('brute', 'restart', 'ropes',
  // 'short-stack'), counting costs or not: every one of the contract's but
  // the optional ones the scene and the choices do not need.
  // The inspect kernel's (`entry` 'inspect') are its own, chosen alike.
  bindingsFor(walk, costs, integrator = 'whitted', entry = 'accumulate') {
    const needs = new Set(this.needs);
    for (const made of this.choicesFor(walk, costs, integrator, entry)) {
      for (const need of made.needs) needs.add(need);
    }
    const omitted = this.contract.optional_bindings.filter((o) => !needs.has(o.need));
    const names = new Set(omitted.map((o) => o.name));
    const bindings = this.contract[entry].bindings.filter((b) => !names.has(b.name));
    const storage = bindings.filter((b) => b.access !== 'uniform').length;
    const most = this.device.limits.maxStorageBuffersPerShaderStage;
    if (storage > most) {
      throw new PageError(
        `this scene's kernel binds ${storage} storage buffers per shader stage but the adapter allows ` +
        `${most} (maxStorageBuffersPerShaderStage)`);
    }
    return { omitted, bindings, key: [...names].sort().join(',') };
  }

  // The kernel with `omitted` swapped for their placeholders, as
  // src/gpu/bindings/ generates it.
  moduleFor(omitted, key, entry = 'accumulate') {
    // The accumulate and features entry points share the trace kernel.
    const id = `${entry === 'inspect' ? 'inspect' : 'trace'}|${key}`;
    if (!this.modules.has(id)) {
      let code = entry === 'inspect' ? this.inspectSource : this.kernelSource;
      for (const o of omitted) {
        if (code.split(o.declaration).length !== 2) {
          throw new PageError(`the ${entry} kernel does not hold ${o.name}'s declaration once: it and contract.json disagree`);
        }
        code = code.replace(o.declaration, o.placeholder);
      }
      this.modules.set(id, this.device.createShaderModule({ label: `${entry} ${key}`, code }));
    }
    return this.modules.get(id);
  }

  // The pipeline and its layout for `walk` on the loaded scene, counting
  // the walks' work if `costs`, tracing `integrator` ('whitted' or 'path').
  // `entry`: 'accumulate', or 'inspect' (the inspect kernel's entry point).
  pipelineFor(walk, costs = false, integrator = 'whitted', entry = 'accumulate') {
    const { omitted, bindings, key } = this.bindingsFor(walk, costs, integrator, entry);
    const id = `${entry}|${walk}|${key}|${costs}|${integrator}`;
    if (!this.pipelines.has(id)) {
      // The scene's overrides from the bundle, the choices' from the contract.
      const constants = { ...this.sceneOverrides };
      for (const made of this.choicesFor(walk, costs, integrator, entry)) {
        for (const [name, value] of Object.entries(made.overrides)) {
          if (name in constants) throw new PageError(`the override ${name} is set twice: contract.json and the bundle disagree`);
          constants[name] = value;
        }
      }
      for (const name of this.contract.overrides) {
        if (!(name in constants)) throw new PageError(`the kernel has an override ${name} this page does not set`);
      }
      const layout = this.device.createBindGroupLayout({
        entries: bindings.map((b) => ({ binding: b.index, visibility: GPUShaderStage.COMPUTE, buffer: { type: b.access } })),
      });
      const pipeline = this.device.createComputePipeline({
        layout: this.device.createPipelineLayout({ bindGroupLayouts: [layout] }),
        compute: { module: this.moduleFor(omitted, key, entry), entryPoint: this.contract[entry].entry_point, constants },
      });
      this.pipelines.set(id, { pipeline, layout, bindings, key, entry, walk, costs, integrator, constants });
    }
    return this.pipelines.get(id);
  }

  // The inspect kernel's log for the pixel and sample `params` (the frame's
  // uniform bytes, its tile the pixel) say, traced with `walk` and
  // `integrator` as a pass would trace them, counting the walks' work: the
  // log's words (a log that runs out of room is traced again with the room
  // it asked for, up to the adapter's binding size).
  async inspectPixel(params, walk, integrator) {
    const p = this.pipelineFor(walk, true, integrator, 'inspect');
    const c = this.contract.constants;
    const uniform = this.device.createBuffer({ size: params.byteLength, usage: GPUBufferUsage.UNIFORM | GPUBufferUsage.COPY_DST });
    this.device.queue.writeBuffer(uniform, 0, params);
    const limit = Math.floor(this.device.limits.maxStorageBufferBindingSize / 4);
    let room = Math.min(this.contract.inspect.first_log_words, limit);
    try {
      for (;;) {
        const log = this.device.createBuffer({ size: 4 * room, usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC });
        const entries = p.bindings.map((b) => ({
          binding: b.index,
          resource: { buffer: b.name === this.contract.accumulate.params ? uniform
            : b.name === this.contract.inspect.log ? log : this.sceneBuffers.get(b.name) },
        }));
        const encoder = this.device.createCommandEncoder();
        const compute = encoder.beginComputePass();
        compute.setPipeline(p.pipeline);
        compute.setBindGroup(0, this.device.createBindGroup({ layout: p.layout, entries }));
        compute.dispatchWorkgroups(1);
        compute.end();
        this.device.queue.submit([encoder.finish()]);
        const [data] = await this.readBuffers([log], [4 * room]);
        log.destroy();
        const words = new Uint32Array(data);
        const used = words[c.INSPECT_WORDS_USED];
        if (used <= room || room >= limit) return words;
        room = Math.min(used, limit);
      }
    } finally {
      uniform.destroy();
    }
  }

  // Makes room for an image of width x height and a preview of pw x ph:
  // their colour sums, their walk costs and their heatmap texels.
  resize(width, height, pw, ph) {
    const texel = this.contract.accumulate.texel_bytes;
    const costTexel = 4 * this.contract.accumulate.cost_words;
    const make = (label, pixels, bytes) => this.device.createBuffer({
      label, size: Math.max(1, pixels) * bytes,
      usage: GPUBufferUsage.STORAGE | GPUBufferUsage.COPY_SRC | GPUBufferUsage.COPY_DST,
    });
    for (const b of Object.values(this.buffers ?? {})) b.destroy();
    this.buffers = {
      image: make('accumulation', width * height, texel),
      preview: make('preview', pw * ph, texel),
      imageCosts: make('costs', width * height, costTexel),
      previewCosts: make('preview costs', pw * ph, costTexel),
      imageHeat: make('heatmap', width * height, texel),
      previewHeat: make('preview heatmap', pw * ph, texel),
      // render_tile's output with FEATURE_OUTPUT: the ray counters, then
      // each pixel's radiance, albedo and normal sums.
      features: make('features', 1, this.contract.features.header_bytes + 4 * this.contract.features.words_per_pixel * width * height),
      // The denoised image as accumulation texels (sum, count 1).
      denoised: make('denoised', width * height, texel),
    };
    this.image = this.buffers.image;
    this.preview = this.buffers.preview;
    this.size = { width, height, pw, ph };
    this.canvas.width = width; this.canvas.height = height;
    this.groups = new Map();
    const presentGroup = (image, preview) => this.device.createBindGroup({
      layout: this.presentLayout,
      entries: [this.presentParams, image, preview].map((buffer, i) => ({
        binding: this.contract.present.bindings[i].index, resource: { buffer },
      })),
    });
    this.presentGroup = presentGroup(this.image, this.preview);
    this.heatGroup = presentGroup(this.buffers.imageHeat, this.buffers.previewHeat);
    this.denoisedGroup = presentGroup(this.buffers.denoised, this.preview);
    // The denoised image shown (three floats a pixel), or null.
    this.denoisedRgb = null;
    // The heatmap's scale's top while it is shown, else null.
    this.heatScale = null;
  }

  bindGroup(p, target) {
    const id = `${p.entry}|${p.key}|${target}`;
    if (!this.groups.has(id) && p.entry === 'features') {
      const f = this.contract.features;
      const entries = p.bindings.map((b) => ({
        binding: b.index,
        resource: { buffer: b.name === f.params ? this.featureParams
          : b.name === f.output ? this.buffers.features : this.sceneBuffers.get(b.name) },
      }));
      this.groups.set(id, this.device.createBindGroup({ layout: p.layout, entries }));
    }
    if (!this.groups.has(id)) {
      const [colours, costs] = this.contract.accumulate.outputs;
      const outputs = {
        [colours]: target === 'image' ? this.image : this.preview,
        [costs]: target === 'image' ? this.buffers.imageCosts : this.buffers.previewCosts,
      };
      const entries = p.bindings.map((b) => ({
        binding: b.index,
        resource: { buffer: b.name === this.contract.accumulate.params ? this.frameParams
          : this.sceneBuffers.get(b.name) ?? outputs[b.name] },
      }));
      this.groups.set(id, this.device.createBindGroup({ layout: p.layout, entries }));
    }
    return this.groups.get(id);
  }

  // One pass: clears `target` (and its costs) first if `clear`, adds one
  // sample with `params` (the frame's uniform bytes) of `integrator`, then
  // presents the image (path radiance tone-mapped), or with `costs` the
  // cost heatmap.
  async pass(target, params, walk, clear, showImage, costs = false, integrator = 'whitted') {
    const p = this.pipelineFor(walk, costs, integrator);
    this.toneMap = integrator === 'path' ? this.pathToneMap : this.contract.constants.PRESENT_QUANTISE;
    this.device.queue.writeBuffer(this.frameParams, 0, params);
    const pp = new ArrayBuffer(this.contract.present.params.size);
    const layout = this.contract.present.params;
    setField(layout, pp, 'image_size', [this.size.width, this.size.height]);
    setField(layout, pp, 'target_size', [this.canvas.width, this.canvas.height]);
    setField(layout, pp, 'preview_size', [this.size.pw, this.size.ph]);
    setField(layout, pp, 'show_image', showImage ? 1 : 0);
    // The heatmap's texels are levels already: quantised, never tone mapped.
    setField(layout, pp, 'tone_map', costs ? this.contract.constants.PRESENT_QUANTISE : this.toneMap);
    setField(layout, pp, 'exposure_scale', this.exposureScale);
    this.device.queue.writeBuffer(this.presentParams, 0, pp);
    const encoder = this.device.createCommandEncoder();
    const buffer = target === 'image' ? this.image : this.preview;
    const features = target === 'image' && this.features && integrator === 'path';
    if (clear) {
      encoder.clearBuffer(buffer);
      encoder.clearBuffer(target === 'image' ? this.buffers.imageCosts : this.buffers.previewCosts);
      if (target === 'image') {
        encoder.clearBuffer(this.buffers.features);
        this.denoisedRgb = null;
      }
    }
    const [wx, wy] = this.contract.accumulate.workgroup;
    const tile = getField(this.contract.frame_params, params, 'tile_size');
    const compute = encoder.beginComputePass();
    compute.setPipeline(p.pipeline);
    compute.setBindGroup(0, this.bindGroup(p, target));
    compute.dispatchWorkgroups(Math.ceil(tile[0] / wx), Math.ceil(tile[1] / wy));
    if (features) {
      // The same sample added to the feature sums: samples sample_index ..
      // sample_index + 1 of the whole image.
      const fp = this.pipelineFor(walk, false, integrator, 'features');
      const one = params.slice(0);
      setField(this.contract.frame_params, one, 'sample_count', 1);
      this.device.queue.writeBuffer(this.featureParams, 0, one);
      const [fx, fy] = this.contract.features.workgroup;
      compute.setPipeline(fp.pipeline);
      compute.setBindGroup(0, this.bindGroup(fp, 'image'));
      compute.dispatchWorkgroups(Math.ceil(tile[0] / fx), Math.ceil(tile[1] / fy));
    }
    compute.end();
    if (!costs) {
      this.heatScale = null;
      this.encodePresent(encoder, this.shownGroup());
      this.device.queue.submit([encoder.finish()]);
      return this.device.queue.onSubmittedWorkDone();
    }
    this.device.queue.submit([encoder.finish()]);
    this.heatScale = await this.updateHeatmap(showImage);
    const present = this.device.createCommandEncoder();
    this.encodePresent(present, this.heatGroup);
    this.device.queue.submit([present.finish()]);
    return this.device.queue.onSubmittedWorkDone();
  }

  // The present pass's bind group: the denoised image while one is shown.
  shownGroup() { return this.denoisedRgb ? this.denoisedGroup : this.presentGroup; }

  // Shows `rgb` (the denoised image, three floats a pixel) instead of the
  // accumulation, until the next restart or showImage.
  showDenoised(rgb) {
    const { width, height } = this.size;
    const texels = new Float32Array(4 * width * height);
    for (let i = 0; i < width * height; i++) {
      texels.set(rgb.subarray(3 * i, 3 * i + 3), 4 * i);
      texels[4 * i + 3] = 1;
    }
    this.device.queue.writeBuffer(this.buffers.denoised, 0, texels);
    this.denoisedRgb = rgb;
    this.present();
  }

  // Shows the accumulation again.
  showImage() {
    this.denoisedRgb = null;
    this.present();
  }

  present() {
    if (this.heatScale !== null) return;
    const encoder = this.device.createCommandEncoder();
    this.encodePresent(encoder, this.shownGroup());
    this.device.queue.submit([encoder.finish()]);
  }

  // The feature sums as they stand (a Float32Array of the whole output,
  // ray counters first). The copy is submitted before this returns its
  // promise, so it holds exactly the passes submitted before the call.
  async readFeatures() {
    const [data] = await this.readBuffers([this.buffers.features], [this.buffers.features.size]);
    return new Float32Array(data);
  }

  // Reads back the colours and costs of the image (if `showImage`) and the
  // preview, and writes their heatmap texels, as the window does
  // (src/window/view.rs); the scale's top: the image's, or the preview's
  // when only it is shown.
  async updateHeatmap(showImage) {
    const { width, height, pw, ph } = this.size;
    const sources = [
      [this.image, this.buffers.imageCosts, this.buffers.imageHeat, showImage ? width * height : 0],
      [this.preview, this.buffers.previewCosts, this.buffers.previewHeat, pw * ph],
    ];
    let scale = null;
    for (const [colours, costs, heat, n] of sources) {
      if (n === 0) continue;
      const [sums, words] = await this.readBuffers([colours, costs],
        [n * this.contract.accumulate.texel_bytes, n * 4 * this.contract.accumulate.cost_words]);
      const { texels, max } = heatmapTexels(new Uint32Array(words), new Float32Array(sums),
        this.contract.accumulate.cost_words, this.contract.heatmap_stops);
      this.device.queue.writeBuffer(heat, 0, texels);
      scale ??= max;
    }
    return scale ?? 1;
  }

  // The first `sizes[i]` bytes of each of `buffers`, read back from the GPU.
  async readBuffers(buffers, sizes) {
    const total = sizes.reduce((a, b) => a + b, 0);
    const readback = this.device.createBuffer({ size: total, usage: GPUBufferUsage.MAP_READ | GPUBufferUsage.COPY_DST });
    const encoder = this.device.createCommandEncoder();
    let at = 0;
    buffers.forEach((b, i) => { encoder.copyBufferToBuffer(b, 0, readback, at, sizes[i]); at += sizes[i]; });
    this.device.queue.submit([encoder.finish()]);
    await readback.mapAsync(GPUMapMode.READ);
    const all = readback.getMappedRange().slice(0);
    readback.destroy();
    at = 0;
    return sizes.map((size) => { const part = all.slice(at, at + size); at += size; return part; });
  }

  encodePresent(encoder, group) {
    const render = encoder.beginRenderPass({
      colorAttachments: [{ view: this.context.getCurrentTexture().createView(), loadOp: 'clear', storeOp: 'store', clearValue: [0, 0, 0, 1] }],
    });
    render.setPipeline(this.presentPipeline);
    render.setBindGroup(0, group);
    render.draw(3);
    render.end();
  }

  // The image's pixels (or, while the heatmap is shown, the heatmap's) read
  // back from the GPU as RGBA8, quantised as the present pass and
  // render_tile quantise: floor(255 * clamp(sum / n) + 0.5), path radiance
  // first through the present pass's curve (toneMapped).
  async readImage() {
    const { width, height } = this.size;
    if (this.denoisedRgb && this.heatScale === null) return this.rgba(this.denoisedRgb, 3, null);
    const bytes = width * height * this.contract.accumulate.texel_bytes;
    const source = this.heatScale === null ? this.image : this.buffers.imageHeat;
    const [data] = await this.readBuffers([source], [bytes]);
    return this.rgba(new Float32Array(data), 4, 3);
  }

  // RGBA8 of `values` (`stride` floats a pixel, the sample count at
  // `count` or 1 when null), tone mapped as the present pass shows them.
  rgba(values, stride, count) {
    const { width, height } = this.size;
    const rgba = new Uint8ClampedArray(width * height * 4);
    const f = Math.fround;
    const tone = this.heatScale === null ? this.toneMap : this.contract.constants.PRESENT_QUANTISE;
    for (let i = 0; i < width * height; i++) {
      const n = count === null ? 1 : values[stride * i + count];
      for (let c = 0; c < 3; c++) {
        const v = n > 0 ? this.toneMapped(f(values[stride * i + c] / n), tone) : 0;
        rgba[4 * i + c] = Math.floor(f(f(255 * v) + 0.5));
      }
      rgba[4 * i + 3] = 255;
    }
    return rgba;
  }

  // present.wgsl's tone_mapped for one channel's mean (f32 steps).
  toneMapped(mean, tone) {
    const f = Math.fround;
    const c = this.contract.constants;
    const clamp01 = (x) => Math.min(Math.max(x, 0), 1);
    if (tone === c.PRESENT_QUANTISE) return clamp01(mean);
    let v = f(mean * this.exposureScale);
    if (tone === c.PRESENT_ACES) {
      v = Math.max(v, 0);
      v = f(f(v * f(f(2.51 * v) + 0.03)) / f(f(v * f(f(2.43 * v) + 0.59)) + 0.14));
    }
    const x = clamp01(v);
    return x <= f(0.0031308) ? f(12.92 * x) : f(f(1.055 * f(Math.pow(x, f(1 / 2.4)))) - 0.055);
  }
}
