// Inspection mode's drawing (X, then a click): an inspected pixel's rays,
// the k-d cells its walks visited (the hit leaf in its own colour) and the
// split planes they crossed, as lines in the scene's space, projected with
// the page's camera onto a 2D canvas over the image. Mirrors the window's
// src/window/inspect_lines.rs (cells, lines) and projection.rs; the
// colours are contract.json's `inspect.colours`.

const sub = (a, b) => a.map((x, i) => x - b[i]);
const add = (a, b) => a.map((x, i) => x + b[i]);
const scale = (a, s) => a.map((x) => x * s);
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];

// Each node's cell [min, max], from the root's box down the splits.
export function nodeCells(tree, bounds) {
  const cells = new Array(tree.nodes.length).fill(null);
  const stack = [[0, bounds]];
  while (stack.length) {
    const [i, cell] = stack.pop();
    if (i >= cells.length || cells[i]) continue;
    cells[i] = cell;
    const n = tree.nodes[i];
    if (n.leaf) continue;
    const a = ['x', 'y', 'z'].indexOf(n.axis);
    const s = Math.min(Math.max(n.split, cell[0][a]), cell[1][a]);
    const below = [cell[0], cell[1].map((v, k) => (k === a ? s : v))];
    const above = [cell[0].map((v, k) => (k === a ? s : v)), cell[1]];
    stack.push([i + 1, below], [n.upper, above]);
  }
  return cells;
}

// The 12 edges of box [min, max].
function boxEdges([lo, hi]) {
  const corner = (m) => [0, 1, 2].map((k) => ((m >> k) & 1 ? hi[k] : lo[k]));
  const edges = [];
  for (let m = 0; m < 8; m++) {
    for (let k = 0; k < 3; k++) if (!((m >> k) & 1)) edges.push([corner(m), corner(m | (1 << k))]);
  }
  return edges;
}

// The 4 edges of the plane `axis` = `at` inside box [min, max].
function planeEdges([lo, hi], axis, at) {
  const [u, v] = [0, 1, 2].filter((k) => k !== axis);
  const p = (a, b) => { const q = [0, 0, 0]; q[axis] = at; q[u] = a; q[v] = b; return q; };
  const c = [p(lo[u], lo[v]), p(hi[u], lo[v]), p(hi[u], hi[v]), p(lo[u], hi[v])];
  return [[c[0], c[1]], [c[1], c[2]], [c[2], c[3]], [c[3], c[0]]];
}

// The lines of inspection document `doc` ({ a, b, kind }): each ray from
// its origin to its hit (a miss: to its limit, else the end of its
// segment, else `far`), each visited leaf's cell ('hit_leaf' for the leaf
// whose tests found a ray's hit, else 'leaf') and each crossed plane.
export function overlayLines(doc, cells, far) {
  const lines = [];
  const drawn = new Map(); // node -> kind (a hit leaf wins over a visited one)
  for (const ray of doc.rays) {
    const end = ray.hit ? ray.hit.point
      : add(ray.origin, scale(ray.direction, ray.t_limit ?? ray.t_interval?.[1] ?? far));
    lines.push({ a: ray.origin, b: end, kind: ray.kind });
    for (const step of ray.walk) {
      if ('leaf' in step && !step.skipped) {
        const hit = ray.hit && step.tested.some((t) => t.hit && t.object === ray.hit.object && t.t === ray.hit.t);
        if (hit || !drawn.has(step.leaf)) drawn.set(step.leaf, hit ? 'hit_leaf' : drawn.get(step.leaf) ?? 'leaf');
      } else if ('node' in step && step.t_split !== undefined && cells[step.node]) {
        for (const [a, b] of planeEdges(cells[step.node], ['x', 'y', 'z'].indexOf(step.axis), step.split)) {
          lines.push({ a, b, kind: 'split_plane' });
        }
      }
    }
  }
  for (const [node, kind] of drawn) {
    if (cells[node]) for (const [a, b] of boxEdges(cells[node])) lines.push({ a, b, kind });
  }
  return lines;
}

// Segment a-b in image pixels ([x, y] from the top-left of a width x
// height image) as the camera `basis` (controls.js) sees it, clipped at
// `near` in front of it; null when none of it is in front.
export function projectSegment(basis, aspect, near, size, a, b) {
  const clip = (p) => {
    const d = sub(p, basis.position);
    const w = dot(d, basis.forward);
    return [dot(d, basis.right) / (basis.tanHalfVfov * aspect), dot(d, basis.up) / basis.tanHalfVfov, w - near, w];
  };
  let [ca, cb] = [clip(a), clip(b)];
  if (ca[2] < 0 && cb[2] < 0) return null;
  const cut = (p, q) => { const f = p[2] / (p[2] - q[2]); const r = p.map((x, i) => x + (q[i] - x) * f); r[2] = 0; return r; };
  if (ca[2] < 0) ca = cut(ca, cb); else if (cb[2] < 0) cb = cut(cb, ca);
  const image = (c) => (c[3] > 0 ? [((c[0] / c[3] + 1) / 2) * size[0], ((1 - c[1] / c[3]) / 2) * size[1]] : null);
  const [pa, pb] = [image(ca), image(cb)];
  return pa && pb ? [pa, pb] : null;
}

// Where an image of `size` shows in `element` (object-fit: contain):
// { x, y, scale } in CSS pixels.
export function shownRect(element, size) {
  const r = element.getBoundingClientRect();
  const s = Math.min(r.width / size[0], r.height / size[1]);
  return { x: r.left + (r.width - s * size[0]) / 2, y: r.top + (r.height - s * size[1]) / 2, scale: s };
}

// Draws `lines` on the 2D canvas `layer` over `view` (the image canvas);
// returns what it drew: { kind, a, b } with a, b in CSS pixels.
export function drawLines(layer, view, lines, basis, near, size, colours) {
  const ratio = window.devicePixelRatio || 1;
  const [cw, ch] = [Math.round(window.innerWidth * ratio), Math.round(window.innerHeight * ratio)];
  if (layer.width !== cw || layer.height !== ch) { layer.width = cw; layer.height = ch; }
  const g = layer.getContext('2d');
  g.clearRect(0, 0, layer.width, layer.height);
  const rect = shownRect(view, size);
  g.lineWidth = Math.max(1, ratio);
  const drawn = [];
  for (const line of lines) {
    const s = projectSegment(basis, size[0] / size[1], near, size, line.a, line.b);
    if (!s) continue;
    const css = (p) => [rect.x + p[0] * rect.scale, rect.y + p[1] * rect.scale];
    drawn.push({ kind: line.kind, a: css(s[0]), b: css(s[1]) });
    const [pa, pb] = [css(s[0]).map((v) => v * ratio), css(s[1]).map((v) => v * ratio)];
    const c = colours[line.kind] ?? colours.primary;
    g.strokeStyle = `rgb(${c.map((x) => Math.round(255 * x)).join(',')})`;
    g.beginPath();
    g.moveTo(pa[0], pa[1]);
    g.lineTo(pb[0], pb[1]);
    g.stroke();
  }
  return drawn;
}
