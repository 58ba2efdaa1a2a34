// The camera the page traces from, and how the mouse, touch, wheel and keys
// move it: orbit around the look-at point, pan, zoom, fly. The camera basis is
// made as the host makes it (crates/kdray-core/src/scene/camera_basis.rs):
// forward to the target, right = forward x up, up = right x forward.

const sub = (a, b) => a.map((x, i) => x - b[i]);
const add = (a, b) => a.map((x, i) => x + b[i]);
const scale = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const normalize = (a) => scale(a, 1 / Math.hypot(...a));

// Rotates `v` by `angle` radians around the unit axis `k` (Rodrigues).
function rotate(v, k, angle) {
  const c = Math.cos(angle), s = Math.sin(angle);
  return add(add(scale(v, c), scale(cross(k, v), s)), scale(k, dot(k, v) * (1 - c)));
}

export class Camera {
  constructor(info) {
    this.scene = info.camera;
    this.initial = info.camera;
    this.bounds = info.bounds;
    this.reset();
  }

  // Makes `camera` (as the scene section's) the one R resets to, and goes there.
  setHome(camera) {
    this.initial = camera;
    this.reset();
  }

  reset() {
    this.position = [...this.initial.position];
    this.target = [...this.initial.look_at];
    this.up = normalize(this.initial.up);
    this.vfov = this.initial.vfov_degrees;
    // The bundle's own frame parameters hold for the scene's camera until
    // the camera moves; another home camera (an animation's frame) has its
    // basis made here.
    const same = (a, b) => a.every((x, i) => x === b[i]);
    const s = this.scene, c = this.initial;
    this.moved = !(same(c.position, s.position) && same(c.look_at, s.look_at) && same(c.up, s.up)
      && c.vfov_degrees === s.vfov_degrees);
  }

  // forward, right, up and tan(vfov / 2), in f64 (the page rounds to f32).
  basis() {
    const forward = normalize(sub(this.target, this.position));
    const right = normalize(cross(forward, this.up));
    return { position: this.position, forward, right, up: cross(right, forward),
      tanHalfVfov: Math.tan((this.vfov * Math.PI) / 360) };
  }

  orbit(dx, dy) {
    const b = this.basis();
    let offset = sub(this.position, this.target);
    offset = rotate(offset, this.up, -dx);
    const pitched = rotate(offset, b.right, -dy);
    // Stop short of the poles, where right = forward x up degenerates.
    if (Math.abs(dot(normalize(pitched), this.up)) < 0.995) offset = pitched;
    this.position = add(this.target, offset);
    this.moved = true;
  }

  // Moves position and target by (dx, dy) of the image's height at the target.
  pan(dx, dy) {
    const b = this.basis();
    const h = 2 * b.tanHalfVfov * Math.hypot(...sub(this.target, this.position));
    const shift = add(scale(b.right, -dx * h), scale(b.up, dy * h));
    this.position = add(this.position, shift);
    this.target = add(this.target, shift);
    this.moved = true;
  }

  zoom(factor) {
    this.position = add(this.target, scale(sub(this.position, this.target), factor));
    this.moved = true;
  }

  // Steps along the view (forward), right and up, by `step` of the distance to the target.
  fly(forward, right, up, step = 0.05) {
    const b = this.basis();
    const d = Math.hypot(...sub(this.target, this.position)) * step;
    const shift = add(add(scale(b.forward, forward * d), scale(b.right, right * d)), scale(b.up, up * d));
    this.position = add(this.position, shift);
    this.target = add(this.target, shift);
    this.moved = true;
  }

  // Looks at the scene's box from the current direction, all of it in view.
  frameAll() {
    const [min, max] = this.bounds;
    const center = scale(add(min, max), 0.5);
    const radius = Math.max(Math.hypot(...sub(max, min)) / 2, 1e-3);
    const back = scale(this.basis().forward, -radius / Math.sin((this.vfov * Math.PI) / 360));
    this.target = center;
    this.position = add(center, back);
    this.moved = true;
  }
}

// Mouse (left: orbit, right or shift: pan, wheel: zoom) and touch (one
// finger: orbit, two: pinch zoom and pan) on `element`; `onChange` after
// each move.
export function attachPointer(element, camera, onChange) {
  const pointers = new Map();
  let pinch = null;
  element.addEventListener('contextmenu', (e) => e.preventDefault());
  element.addEventListener('pointerdown', (e) => {
    element.setPointerCapture(e.pointerId);
    pointers.set(e.pointerId, { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey });
    pinch = null;
  });
  const end = (e) => { pointers.delete(e.pointerId); pinch = null; };
  element.addEventListener('pointerup', end);
  element.addEventListener('pointercancel', end);
  element.addEventListener('pointermove', (e) => {
    const p = pointers.get(e.pointerId);
    if (!p) return;
    const size = element.getBoundingClientRect();
    const dx = (e.clientX - p.x) / size.height, dy = (e.clientY - p.y) / size.height;
    p.x = e.clientX; p.y = e.clientY;
    if (pointers.size === 2) {
      const [a, b] = [...pointers.values()];
      const spread = Math.hypot(a.x - b.x, a.y - b.y);
      if (pinch) camera.zoom(pinch / Math.max(spread, 1));
      camera.pan(dx / 2, dy / 2);
      pinch = spread;
    } else if (p.pan) {
      camera.pan(dx, dy);
    } else {
      camera.orbit(dx * Math.PI, dy * Math.PI);
    }
    onChange();
  });
  element.addEventListener('wheel', (e) => {
    e.preventDefault();
    camera.zoom(Math.exp(Math.sign(e.deltaY) * 0.1));
    onChange();
  }, { passive: false });
}
