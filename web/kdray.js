// The page: loads contract.json, the kernel and the bundle, checks them,
// and refines the image progressively (one sample per pixel per pass, a
// reduced-resolution preview while the camera moves), as the native window,
// with the Whitted integrator or path traced (URL `integrator`, key I);
// plays an animated scene's frames (Space) from the bundle's cameras and
// frame lights, shows the cost heatmap (C), and denoises the path-traced
// image (URL `denoise=1`, key N; denoise.js). docs/web.md states its
// contract: URL parameters, document.title, window.kdray.png() and
// window.kdray.inspect(x, y), keys.

import { parseBundle } from './bundle.js';
import { Camera, attachPointer } from './controls.js';
import { Tracer, PageError, openGpu, setField } from './tracer.js';
import { decodeLog, inspectionDocument, treeOf } from './inspect.js';
import { drawLines, nodeCells, overlayLines, shownRect } from './overlay.js';
import { Denoiser, autoexposure, featureImages } from './denoise.js';

const WALKS = ['restart', 'ropes', 'short-stack'];
const INTEGRATORS = ['whitted', 'path'];
// Path samples the page refines to when toggled to path tracing (I) and
// neither the URL nor a path-traced scene says how many, as the window.
const DEFAULT_PATH_SAMPLES = 256;
const canvas = document.getElementById('view');
const linesLayer = document.getElementById('lines');
const overlay = document.getElementById('overlay');
const message = document.getElementById('message');
const query = new URLSearchParams(location.search);

const state = {
  tracer: null, bundle: null, camera: null, contract: null,
  width: 0, height: 0, samples: 1, walk: 'short-stack', brute: false, maxDepth: 0,
  // The integrator traced, and the samples each refines to.
  integrator: 'whitted', samplesOf: { whitted: 1, path: 1 },
  sample: 0, restart: true, lastMove: -Infinity, frameMs: 0, error: null, done: false,
  // The shown animation frame of `cameras` (null for a still scene); while
  // playing, `playing` holds the time (ms) and the frame it started from.
  cameras: null, frame: 0, playing: null,
  // Each frame's lights (null unless a light has keys): frameLightsFrom.
  frameLights: null,
  // Show the cost heatmap instead of the image (C toggles it).
  heatmap: false,
  // Inspection mode (X): on, and the pixel inspected last with its
  // document and lines ({ pixel, doc, lines }), or null.
  inspecting: false, inspected: null,
  // The lines drawn last: { kind, a, b } in CSS pixels of the page.
  drawn: [],
  // Each image pass's time (ms) since the refinement began, from its
  // submission to the GPU's done, present included; the first one also
  // compiles the pipeline (scripts/web_bench.sh reports the rest).
  passMs: [],
  // Denoising (denoise=1, N): wanted, the denoiser's promise once loading
  // began, the denoise under way (a promise) or null, the image shown
  // ({ sample, scale, ms }) or null, when the last one ended, the reason
  // it cannot run (shown in the overlay) or null, and the refinement's
  // generation (a denoise of an older one is dropped).
  denoise: false, denoiser: null, denoising: null, denoised: null, denoisedAt: 0, denoiseNote: null,
  generation: 0,
};

// The first denoise waits for this many samples (or all of them, if fewer).
const FIRST_DENOISE_SAMPLES = 4;
// A denoise refreshes once the samples have doubled or this long has
// passed (ms), and takes at most this share of the time between
// refreshes: on SwiftShader or lavapipe a denoise takes seconds.
const DENOISE_REFRESH_MS = 2000;
const DENOISE_SHARE = 0.25;

function showError(e) {
  const text = e instanceof Error ? e.message : String(e);
  state.error = text;
  document.title = `kdray: error: ${text}`;
  message.textContent = text;
  message.hidden = false;
  console.error(e);
}

async function fetchOk(url) {
  const response = await fetch(url);
  if (!response.ok) throw new PageError(`cannot load ${url}: HTTP ${response.status}`);
  return response;
}

// A URL parameter as a positive integer, or `fallback`.
function intParam(name, fallback) {
  const text = query.get(name);
  if (text === null) return fallback;
  const n = Number(text);
  if (!Number.isInteger(n) || n < 1) throw new PageError(`URL parameter ${name}=${text} is not a positive integer`);
  return n;
}

// The bundle's `cameras` section: { frames, fps, at(k): the camera of
// frame k as the scene section's camera }, or null without one.
function camerasFrom(bundle, format) {
  const bytes = bundle.sections.get(format.section);
  if (!bytes) return null;
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const frames = view.getUint32(0, true);
  const fps = view.getFloat64(8, true);
  const per = format.values_per_frame;
  if (frames < 1 || bytes.byteLength !== format.header_bytes + 8 * per * frames) {
    throw new PageError(`the bundle's ${format.section} section is ${bytes.byteLength} bytes, not ${frames} frames`);
  }
  const at = (k) => {
    const v = (i) => view.getFloat64(format.header_bytes + 8 * (per * k + i), true);
    return { position: [v(0), v(1), v(2)], look_at: [v(3), v(4), v(5)], up: [v(6), v(7), v(8)], vfov_degrees: v(9) };
  };
  return { frames, fps: fps > 0 && Number.isFinite(fps) ? fps : 24, at };
}

// The scene's settings with the URL's overrides.
function settingsFrom(info) {
  const width = intParam('width', info.width);
  const height = intParam('height', info.height);
  const integrator = query.get('integrator') ?? info.integrator;
  if (!INTEGRATORS.includes(integrator)) throw new PageError(`integrator=${integrator} is not one of ${INTEGRATORS.join(', ')}`);
  const samples = intParam('samples', info.samples);
  const frameText = query.get('frame');
  const frame = frameText === null ? 0 : Number(frameText);
  if (!Number.isInteger(frame) || frame < 0) throw new PageError(`URL parameter frame=${frameText} is not a frame number (0, 1, ...)`);
  const k = Math.round(Math.sqrt(samples));
  if (integrator === 'whitted' && k * k !== samples) {
    throw new PageError(`samples=${samples} is not a perfect square (as the Whitted integrator needs)`);
  }
  // The other integrator's count, for I: the scene's own where it fits.
  const whitted = integrator === 'whitted' ? samples : (Math.round(Math.sqrt(info.samples)) ** 2 || 1);
  const path = integrator === 'path' ? samples
    : info.integrator === 'path' ? info.samples : Math.max(info.samples, DEFAULT_PATH_SAMPLES);
  const traversal = query.get('traversal') ?? info.traversal;
  if (!WALKS.includes(traversal)) throw new PageError(`traversal=${traversal} is not one of ${WALKS.join(', ')}`);
  const denoiseText = query.get('denoise') ?? '0';
  if (!['0', '1'].includes(denoiseText)) throw new PageError(`denoise=${denoiseText} is not 0 or 1`);
  const accel = query.get('accel') ?? 'kdtree';
  if (!['kdtree', 'brute'].includes(accel)) throw new PageError(`accel=${accel} is not kdtree or brute`);
  return {
    width, height, samples, walk: traversal, brute: accel === 'brute', frame, denoise: denoiseText === '1',
    integrator, samplesOf: { whitted, path },
  };
}

// The kernel's uniform for one pass of `width` x `height`, sample `k`.
function frameParams(width, height, k) {
  const { contract, bundle, camera } = state;
  const layout = contract.frame_params;
  const c = contract.constants;
  const bytes = bundle.frameParams.slice(0);
  if (camera.moved) {
    const b = camera.basis();
    setField(layout, bytes, 'camera_position', b.position);
    setField(layout, bytes, 'camera_forward', b.forward);
    setField(layout, bytes, 'camera_right', b.right);
    setField(layout, bytes, 'camera_up', b.up);
    setField(layout, bytes, 'tan_half_vfov', b.tanHalfVfov);
  }
  // As the host: (width as f64 / height as f64) as f32.
  setField(layout, bytes, 'aspect', width / height);
  setField(layout, bytes, 'width', width);
  setField(layout, bytes, 'height', height);
  const path = state.integrator === 'path';
  setField(layout, bytes, 'integrator', path ? c.INTEGRATOR_PATH : c.INTEGRATOR_WHITTED);
  setField(layout, bytes, 'samples', state.samples);
  setField(layout, bytes, 'samples_per_axis', path ? 1 : Math.round(Math.sqrt(state.samples)));
  setField(layout, bytes, 'tile_origin', [0, 0]);
  setField(layout, bytes, 'tile_size', [width, height]);
  setField(layout, bytes, 'max_depth', state.maxDepth);
  setField(layout, bytes, 'sample_index', k);
  setField(layout, bytes, 'accel', state.brute ? c.ACCEL_BRUTE : c.ACCEL_KDTREE);
  const traversal = { restart: c.TRAVERSAL_RESTART, ropes: c.TRAVERSAL_ROPES, 'short-stack': c.TRAVERSAL_SHORT_STACK };
  setField(layout, bytes, 'traversal', traversal[state.walk]);
  return bytes;
}

function walkName() { return state.brute ? 'brute' : state.walk; }

// I: the other integrator, refined to its own samples.
function toggleIntegrator() {
  state.integrator = state.integrator === 'path' ? 'whitted' : 'path';
  state.samples = state.samplesOf[state.integrator];
  restart();
}

function restart() {
  state.restart = true; state.sample = 0; state.done = false; state.passMs = [];
  state.generation += 1;
  state.denoised = null;
  if (state.tracer) state.tracer.features = denoiseOn();
}

// Whether the image shown is denoised: denoising wanted, path traced,
// the image (not the heatmap) shown, and nothing refusing it.
function denoiseOn() {
  return state.denoise && state.integrator === 'path' && !state.heatmap && !state.denoiseNote;
}

// The denoiser, loaded once: the weights file and the kernels.
function loadDenoiser() {
  state.denoiser ??= (async () => {
    const spec = state.contract.denoise;
    const shaders = Object.entries(spec.shaders);
    const [weights, ...sources] = await Promise.all([
      fetchOk(spec.weights_file).then((r) => r.arrayBuffer()),
      ...shaders.map(([, file]) => fetchOk(file).then((r) => r.text())),
    ]);
    const code = Object.fromEntries(shaders.map(([name], i) => [name, sources[i]]));
    return Denoiser.create(state.tracer.device, spec, code, weights);
  })();
  return state.denoiser;
}

// Whether the loop should denoise now: the camera still, samples since
// the last denoise, and either the last sample, or the first few, or
// (doubled samples or a while since) with the denoise's share of time kept.
function denoiseDue() {
  if (!denoiseOn() || state.denoising || performance.now() - state.lastMove < MOVE_SETTLE_MS) return false;
  const n = state.sample;
  const last = state.denoised?.sample ?? 0;
  if (n === 0 || n === last) return false;
  if (n >= state.samples) return true;
  if (n < Math.min(FIRST_DENOISE_SAMPLES, state.samples)) return false;
  if (!state.denoised) return true;
  const since = performance.now() - state.denoisedAt;
  return (n >= 2 * last || since >= DENOISE_REFRESH_MS) && since * DENOISE_SHARE >= state.denoised.ms;
}

// Denoises the image as it stands (state.sample samples), and shows it
// unless the refinement restarted meanwhile; the promise of the denoise
// under way if there is one.
function denoiseNow() {
  if (state.denoising) return state.denoising;
  const { tracer, width, height } = state;
  const n = state.sample;
  const generation = state.generation;
  // The sums of exactly the n samples submitted so far.
  const sums = tracer.readFeatures();
  state.denoising = (async () => {
    const denoiser = await loadDenoiser();
    // Timed from here: the first denoise also loads the network.
    const started = performance.now();
    const images = featureImages(await sums, width * height, n, state.contract.features);
    const scale = autoexposure(width, height, images.subarray(0, 3 * width * height));
    let rgb;
    try {
      rgb = await denoiser.denoise(width, height, images, scale);
    } catch (e) {
      if (!(e instanceof PageError)) throw e;
      // Too large to denoise here: said in the overlay, the image kept.
      state.denoiseNote = e.message;
      tracer.features = false;
      return;
    }
    if (generation !== state.generation || !denoiseOn()) return;
    tracer.showDenoised(rgb);
    state.denoised = { sample: n, scale, ms: performance.now() - started };
    state.denoisedAt = performance.now();
  })().finally(() => { state.denoising = null; });
  return state.denoising;
}

// N: denoising on or off (on, the refinement restarts: the denoiser's
// feature sums need every sample).
function toggleDenoise() {
  state.denoise = !state.denoise;
  state.denoiseNote = null;
  if (state.denoise) {
    loadDenoiser().catch(showError);
    restart();
  } else {
    state.denoised = null;
    state.tracer.features = false;
    state.tracer.showImage();
  }
}

function denoiseLine() {
  if (!state.denoise) return null;
  if (state.integrator !== 'path') return 'denoise: off with the Whitted integrator (the denoiser needs the path tracer: I)';
  if (state.heatmap) return 'denoise: off while the heatmap is shown';
  if (state.denoiseNote) return `denoise: off: ${state.denoiseNote}`;
  const d = state.denoised;
  if (state.denoising) return `denoise: denoising ${d ? `(shown: ${d.sample} samples)` : ''}`;
  if (!d) return `denoise: after ${Math.min(FIRST_DENOISE_SAMPLES, state.samples)} samples`;
  return `denoise: ${d.sample} samples denoised in ${(d.ms / 1000).toFixed(1)} s, input scale ${d.scale.toPrecision(4)}`;
}

function moved() { state.lastMove = performance.now(); restart(); }

// The bundle's `frame_lights` section: { write(k): puts frame k's lights
// in the lights buffer }, or null when no light has keys.
function frameLightsFrom(bundle, format, frames) {
  const bytes = bundle.sections.get(format.section);
  if (!bytes) return null;
  const per = format.bytes_per_light * bundle.info.lights;
  if (bytes.byteLength !== per * frames) {
    throw new PageError(`the bundle's ${format.section} section is ${bytes.byteLength} bytes, not ${frames} frames of ${bundle.info.lights} lights`);
  }
  const write = (k) => {
    const buffer = state.tracer.sceneBuffers.get(format.binding);
    state.tracer.device.queue.writeBuffer(buffer, 0, bytes, per * k, per);
  };
  return { write };
}

// Shows frame `k` of the animation: its camera and lights, refinement restarted.
function showFrame(k) {
  state.frame = k;
  state.camera.setHome(state.cameras.at(k));
  state.frameLights?.write(k);
  restart();
}

// Space: play from the shown frame, or pause on it (a still scene stays).
function togglePlay() {
  if (!state.cameras || state.cameras.frames < 2) return;
  state.playing = state.playing ? null : { since: performance.now(), from: state.frame };
}

// While playing, moves to the frame the clock says (fps, looping).
function advanceFrame() {
  if (!state.playing) return;
  const { frames, fps } = state.cameras;
  const elapsed = Math.floor(((performance.now() - state.playing.since) * fps) / 1000);
  const k = (state.playing.from + elapsed) % frames;
  if (k !== state.frame) showFrame(k);
}

function updateOverlay() {
  const { width, height, sample, samples, frameMs } = state;
  const mrays = frameMs > 0 ? (width * height) / (frameMs * 1e3) : 0;
  const lines = [
    `${state.bundle.info.name}  ${width} x ${height}`,
    `samples ${sample}/${samples}${state.integrator === 'path' ? ' path traced' : ''}`,
    `frame ${frameMs.toFixed(1)} ms  ${mrays.toFixed(2)} Mrays/s primary`,
    `walk ${walkName()}  max_depth ${state.maxDepth}`,
  ];
  if (state.cameras) {
    lines.push(`frame ${state.frame}/${state.cameras.frames} ${state.playing ? 'playing' : 'paused'}`);
  }
  const denoise = denoiseLine();
  if (denoise) lines.push(denoise);
  if (state.inspecting) lines.push(inspectLine());
  const scale = state.tracer.heatScale;
  if (state.heatmap && scale !== null) lines.push(`heatmap: nodes + objects per sample, 0 to ${scale}`);
  lines.push(`adapter ${state.tracer.gpu.name}`);
  overlay.textContent = lines.join('\n');
}

const MOVE_SETTLE_MS = 150;

// One step of the loop: a preview pass while the camera moves, else the
// next sample of the image, else nothing.
async function step() {
  const { tracer, width, height } = state;
  advanceFrame();
  const started = performance.now();
  if (started - state.lastMove < MOVE_SETTLE_MS) {
    const { pw, ph } = tracer.size;
    await tracer.pass('preview', frameParams(pw, ph, 0), walkName(), true, false, state.heatmap, state.integrator);
  } else if (state.sample < state.samples) {
    await tracer.pass('image', frameParams(width, height, state.sample), walkName(), state.restart, true, state.heatmap, state.integrator);
    state.restart = false;
    state.sample += 1;
    state.passMs.push(performance.now() - started);
  } else {
    return false;
  }
  state.frameMs = performance.now() - started;
  return true;
}

async function loop() {
  for (;;) {
    if (state.error) return;
    let worked = false;
    try {
      worked = await step();
    } catch (e) {
      showError(e);
      return;
    }
    if (denoiseDue()) denoiseNow().catch(showError);
    // An error meanwhile (an uncaptured GPU error, say) keeps its title.
    if (state.error) return;
    updateOverlay();
    drawInspection();
    // Denoising, the image is done once its last sample is denoised.
    const denoised = !denoiseOn() || (state.denoised?.sample === state.samples && !state.denoising);
    if (state.sample >= state.samples && !state.done && denoised && performance.now() - state.lastMove >= MOVE_SETTLE_MS) {
      state.done = true;
      document.title = `kdray: done (${state.samples} samples)`;
    } else if (!state.done) {
      document.title = `kdray: tracing ${state.sample}/${state.samples}`;
    }
    // Playing, a finished frame waits for the clock's next one.
    await new Promise((resolve) => (worked ? setTimeout(resolve, 0) : requestAnimationFrame(resolve)));
  }
}

// Loads a bundle's bytes and starts tracing it.
function loadBundle(bytes) {
  const bundle = parseBundle(bytes, state.contract);
  const settings = settingsFrom(bundle.info);
  state.tracer.load(bundle);
  const cameras = camerasFrom(bundle, state.contract.bundle.cameras);
  const frames = cameras ? cameras.frames : 1;
  if (settings.frame >= frames) throw new PageError(`frame=${settings.frame}: the scene has frames 0..${frames}`);
  const frameLights = frameLightsFrom(bundle, state.contract.bundle.frame_lights, frames);
  Object.assign(state, settings, {
    bundle, cameras, frameLights, playing: null, camera: new Camera(bundle.info), maxDepth: bundle.info.max_depth,
    tree: null,
  });
  if (cameras) state.camera.setHome(cameras.at(state.frame));
  frameLights?.write(state.frame);
  // The preview: a quarter of the width and height (at least 1).
  state.tracer.resize(state.width, state.height, Math.max(1, state.width >> 2), Math.max(1, state.height >> 2));
  state.tracer.pipelineFor(walkName(), false, state.integrator);
  if (state.denoise) loadDenoiser().catch(showError);
  restart();
}

// A PNG data URL of the traced image at its own size, read from the GPU;
// while denoising, the denoised image of every sample traced so far.
async function png() {
  if (denoiseOn()) {
    await state.denoising;
    if (state.denoised?.sample !== state.sample && state.sample > 0) await denoiseNow();
  }
  const rgba = await state.tracer.readImage();
  const out = document.createElement('canvas');
  out.width = state.width; out.height = state.height;
  out.getContext('2d').putImageData(new ImageData(rgba, state.width, state.height), 0, 0);
  return out.toDataURL('image/png');
}

// Pixel (column x, row y) of the image as it stands (camera, frame, walk,
// integrator): every ray its first sample traces and the k-d walk of each,
// logged by the inspect kernel, as the document `kdray inspect` prints.
async function inspect(x, y) {
  const { width, height, contract, bundle } = state;
  const inside = [x, y].every(Number.isInteger) && x >= 0 && y >= 0 && x < width && y < height;
  if (!inside) throw new PageError(`inspect(${x}, ${y}): the pixel is outside the ${width} x ${height} image`);
  const params = frameParams(width, height, 0);
  setField(contract.frame_params, params, 'tile_origin', [x, y]);
  setField(contract.frame_params, params, 'tile_size', [1, 1]);
  setField(contract.frame_params, params, 'sample_count', 1);
  const words = await state.tracer.inspectPixel(params, walkName(), state.integrator);
  state.tree ??= treeOf(bundle.arrays, contract.constants);
  const meta = {
    scene: bundle.info.name, pixel: [x, y], frame: state.frame, width, height, samples: state.samples,
    integrator: state.integrator, accel: state.brute ? 'brute' : 'kdtree', traversal: state.walk,
    build: bundle.info.build, spheres: bundle.info.spheres,
  };
  return inspectionDocument(decodeLog(words, contract.constants), state.tree, meta, contract);
}

// The overlay's line of inspection mode: the pixel and its rays' work.
function inspectLine() {
  if (!state.inspected) return 'inspect: click a pixel';
  const { pixel, doc } = state.inspected;
  const sum = (k) => doc.rays.reduce((t, r) => t + r.counts[k], 0);
  return `inspect ${pixel[0]},${pixel[1]}: ${doc.rays.length} rays, ${sum('nodes')} nodes, ` +
    `${sum('leaves')} leaves, ${sum('tests')} tests, ${sum('restarts')} restarts`;
}

// A click at (clientX, clientY) in inspection mode: inspects the image
// pixel shown there and keeps its lines.
async function inspectAt(clientX, clientY) {
  const { width, height, bundle, contract } = state;
  const rect = shownRect(canvas, [width, height]);
  const x = Math.floor((clientX - rect.x) / rect.scale);
  const y = Math.floor((clientY - rect.y) / rect.scale);
  if (x < 0 || y < 0 || x >= width || y >= height) return;
  const doc = await inspect(x, y);
  const cells = state.brute ? [] : nodeCells(state.tree, bundle.info.bounds);
  const [lo, hi] = bundle.info.bounds;
  const far = 2 * Math.hypot(...hi.map((v, i) => v - lo[i]));
  state.inspected = { pixel: [x, y], doc, lines: overlayLines(doc, cells, far) };
  updateOverlay();
  drawInspection();
}

// Draws the inspected lines with the camera as it is now.
function drawInspection() {
  const g = linesLayer.getContext('2d');
  if (!state.inspecting || !state.inspected) {
    g.clearRect(0, 0, linesLayer.width, linesLayer.height);
    state.drawn = [];
    return;
  }
  const b = state.camera.basis();
  const near = 1e-3 * Math.hypot(...b.position.map((v, i) => v - state.camera.target[i]));
  state.drawn = drawLines(linesLayer, canvas, state.inspected.lines, b, near, [state.width, state.height],
    state.contract.inspect.colours);
}

function toggleInspecting() {
  state.inspecting = !state.inspecting;
  state.inspected = null;
  drawInspection();
  updateOverlay();
}

async function screenshot() {
  const link = document.createElement('a');
  link.href = await png();
  link.download = `${state.bundle.info.name.replace(/\.[^.]*$/, '')}.png`;
  link.click();
}

const KEYS = {
  f: () => { state.camera.frameAll(); moved(); },
  r: () => { state.camera.reset(); moved(); },
  p: () => screenshot(),
  b: () => { state.brute = !state.brute; restart(); },
  t: () => { state.walk = WALKS[(WALKS.indexOf(state.walk) + 1) % WALKS.length]; restart(); },
  '[': () => { state.maxDepth = Math.max(0, state.maxDepth - 1); restart(); },
  ']': () => { state.maxDepth += 1; restart(); },
  w: () => { state.camera.fly(1, 0, 0); moved(); },
  s: () => { state.camera.fly(-1, 0, 0); moved(); },
  a: () => { state.camera.fly(0, -1, 0); moved(); },
  d: () => { state.camera.fly(0, 1, 0); moved(); },
  q: () => { state.camera.fly(0, 0, -1); moved(); },
  e: () => { state.camera.fly(0, 0, 1); moved(); },
  h: () => { document.getElementById('help').hidden ^= true; },
  ' ': () => togglePlay(),
  // The costs accumulate with the colours: refine again to show the other.
  c: () => { state.heatmap = !state.heatmap; restart(); },
  i: () => toggleIntegrator(),
  n: () => toggleDenoise(),
  x: () => toggleInspecting(),
};

async function main() {
  window.kdray = { png, inspect, state };
  const contract = await (await fetchOk('contract.json')).json();
  state.contract = contract;
  const [kernel, present, inspectKernel, bundle] = await Promise.all([
    fetchOk(contract.files.kernel).then((r) => r.text()),
    fetchOk(contract.files.present).then((r) => r.text()),
    fetchOk(contract.files.inspect).then((r) => r.text()),
    fetchOk(query.get('bundle') ?? contract.files.bundle).then((r) => r.arrayBuffer()),
  ]);
  const gpu = await openGpu();
  gpu.device.lost.then((info) => showError(new PageError(`the GPU device was lost: ${info.message}`)));
  gpu.device.onuncapturederror = (e) => showError(new PageError(`WebGPU: ${e.error.message}`));
  state.tracer = new Tracer(gpu, contract, kernel, present, canvas, inspectKernel);
  loadBundle(bundle);
  attachPointer(canvas, { // every move of the camera restarts refinement
    orbit: (x, y) => state.camera.orbit(x, y), pan: (x, y) => state.camera.pan(x, y),
    zoom: (f) => state.camera.zoom(f),
  }, moved);
  // A click (a press and release within 3 pixels) inspects in inspection mode.
  let pressed = null;
  canvas.addEventListener('pointerdown', (e) => { pressed = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', (e) => {
    const still = pressed && Math.hypot(e.clientX - pressed[0], e.clientY - pressed[1]) <= 3;
    pressed = null;
    if (still && state.inspecting) inspectAt(e.clientX, e.clientY).catch(showError);
  });
  window.addEventListener('keydown', (e) => {
    if (e.ctrlKey || e.metaKey || e.altKey) return;
    const action = KEYS[e.key.toLowerCase()];
    if (action) { e.preventDefault(); action(); }
  });
  document.body.addEventListener('dragover', (e) => e.preventDefault());
  document.body.addEventListener('drop', async (e) => {
    e.preventDefault();
    const file = e.dataTransfer.files[0];
    if (!file) return;
    try {
      message.hidden = true;
      state.error = null;
      loadBundle(await file.arrayBuffer());
      loop();
    } catch (err) {
      showError(err);
    }
  });
  loop();
}

main().catch(showError);
