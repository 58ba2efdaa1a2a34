// The page: loads contract.json, the kernel and the bundle, checks them,
// and refines the image progressively (one sample per pixel per pass, a
// reduced-resolution preview while the camera moves), as the native window.
// docs/web.md states its contract: URL parameters, document.title,
// window.kdray.png(), keys.

import { parseBundle } from './bundle.js';
import { Camera, attachPointer } from './controls.js';
import { Tracer, PageError, openGpu, setField } from './tracer.js';

const WALKS = ['restart', 'ropes', 'short-stack'];
const canvas = document.getElementById('view');
const overlay = document.getElementById('overlay');
const message = document.getElementById('message');
const query = new URLSearchParams(location.search);

const state = {
  tracer: null, bundle: null, camera: null, contract: null,
  width: 0, height: 0, samples: 1, walk: 'short-stack', brute: false, maxDepth: 0,
  sample: 0, restart: true, lastMove: -Infinity, frameMs: 0, error: null, done: false,
  // Each image pass's time (ms) since the refinement began, from its
  // submission to the GPU's done, present included; the first one also
  // compiles the pipeline (scripts/web_bench.sh reports the rest).
  passMs: [],
};

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

// The scene's settings with the URL's overrides.
function settingsFrom(info) {
  const width = intParam('width', info.width);
  const height = intParam('height', info.height);
  const samples = intParam('samples', info.samples);
  const k = Math.round(Math.sqrt(samples));
  if (k * k !== samples) throw new PageError(`samples=${samples} is not a perfect square`);
  const traversal = query.get('traversal') ?? info.traversal;
  if (!WALKS.includes(traversal)) throw new PageError(`traversal=${traversal} is not one of ${WALKS.join(', ')}`);
  const accel = query.get('accel') ?? 'kdtree';
  if (!['kdtree', 'brute'].includes(accel)) throw new PageError(`accel=${accel} is not kdtree or brute`);
  return { width, height, samples, walk: traversal, brute: accel === 'brute' };
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
  setField(layout, bytes, 'samples_per_axis', Math.round(Math.sqrt(state.samples)));
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

function restart() { state.restart = true; state.sample = 0; state.done = false; state.passMs = []; }

function moved() { state.lastMove = performance.now(); restart(); }

function updateOverlay() {
  const { width, height, sample, samples, frameMs } = state;
  const mrays = frameMs > 0 ? (width * height) / (frameMs * 1e3) : 0;
  overlay.textContent = [
    `${state.bundle.info.name}  ${width} x ${height}`,
    `samples ${sample}/${samples}`,
    `frame ${frameMs.toFixed(1)} ms  ${mrays.toFixed(2)} Mrays/s primary`,
    `walk ${walkName()}  max_depth ${state.maxDepth}`,
    `adapter ${state.tracer.gpu.name}`,
  ].join('\n');
}

const MOVE_SETTLE_MS = 150;

// One step of the loop: a preview pass while the camera moves, else the
// next sample of the image, else nothing.
async function step() {
  const { tracer, width, height } = state;
  const started = performance.now();
  if (started - state.lastMove < MOVE_SETTLE_MS) {
    const { pw, ph } = tracer.size;
    await tracer.pass('preview', frameParams(pw, ph, 0), walkName(), true, false);
  } else if (state.sample < state.samples) {
    await tracer.pass('image', frameParams(width, height, state.sample), walkName(), state.restart, true);
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
    updateOverlay();
    if (state.sample >= state.samples && !state.done && performance.now() - state.lastMove >= MOVE_SETTLE_MS) {
      state.done = true;
      document.title = `kdray: done (${state.samples} samples)`;
    } else if (!state.done) {
      document.title = `kdray: tracing ${state.sample}/${state.samples}`;
    }
    await new Promise((resolve) => (worked ? setTimeout(resolve, 0) : requestAnimationFrame(resolve)));
  }
}

// Loads a bundle's bytes and starts tracing it.
function loadBundle(bytes) {
  const bundle = parseBundle(bytes, state.contract);
  const settings = settingsFrom(bundle.info);
  state.tracer.load(bundle);
  Object.assign(state, settings, { bundle, camera: new Camera(bundle.info), maxDepth: bundle.info.max_depth });
  // The preview: a quarter of the width and height (at least 1).
  state.tracer.resize(state.width, state.height, Math.max(1, state.width >> 2), Math.max(1, state.height >> 2));
  state.tracer.pipelineFor(walkName());
  restart();
}

// A PNG data URL of the traced image at its own size, read from the GPU.
async function png() {
  const rgba = await state.tracer.readImage();
  const out = document.createElement('canvas');
  out.width = state.width; out.height = state.height;
  out.getContext('2d').putImageData(new ImageData(rgba, state.width, state.height), 0, 0);
  return out.toDataURL('image/png');
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
};

async function main() {
  window.kdray = { png, state };
  const contract = await (await fetchOk('contract.json')).json();
  state.contract = contract;
  const [kernel, present, bundle] = await Promise.all([
    fetchOk(contract.files.kernel).then((r) => r.text()),
    fetchOk(contract.files.present).then((r) => r.text()),
    fetchOk(query.get('bundle') ?? contract.files.bundle).then((r) => r.arrayBuffer()),
  ]);
  const gpu = await openGpu();
  gpu.device.lost.then((info) => showError(new PageError(`the GPU device was lost: ${info.message}`)));
  gpu.device.onuncapturederror = (e) => showError(new PageError(`WebGPU: ${e.error.message}`));
  state.tracer = new Tracer(gpu, contract, kernel, present, canvas);
  loadBundle(bundle);
  attachPointer(canvas, { // every move of the camera restarts refinement
    orbit: (x, y) => state.camera.orbit(x, y), pan: (x, y) => state.camera.pan(x, y),
    zoom: (f) => state.camera.zoom(f),
  }, moved);
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
