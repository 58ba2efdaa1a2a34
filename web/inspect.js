// window.kdray.inspect(x, y): the inspect kernel's log (the words
// shaders/walk_record.wgsl writes, tags and kinds from contract.json's
// constants) read into the document `kdray inspect` prints (docs/inspect.md,
// version 1), with the tree's nodes and leaves from the bundle's arrays.
// Mirrors src/gpu/walk_log.rs (decode) and src/inspect/document.rs (the document).

const AXES = ['x', 'y', 'z'];
const FACES = ['x-', 'x+', 'y-', 'y+', 'z-', 'z+'];

// The log's words as { rays, sample }: each ray { kind, any, origin, dir,
// tLimit, walk (events), hit ({ object, t, point, normal } or null), cost,
// light ({ entry, kind, object, pick, density }: a shadow ray's; else null) }.
export function decodeLog(words, c) {
  const used = words[c.INSPECT_WORDS_USED];
  if (used > words.length) throw new Error(`the inspect log needs ${used} words but has room for ${words.length}`);
  const bits = new DataView(words.buffer, words.byteOffset, words.byteLength);
  let at = c.INSPECT_HEADER_WORDS;
  const word = () => {
    if (at >= used) throw new Error(`the inspect log is malformed at word ${at}: it ends inside a record`);
    return words[at++];
  };
  const float = () => { word(); return bits.getFloat32(4 * (at - 1), true); };
  const vec3 = () => [float(), float(), float()];
  const kinds = {
    [c.RAY_PRIMARY]: 'primary', [c.RAY_SHADOW]: 'shadow', [c.RAY_REFLECTED]: 'reflected',
    [c.RAY_REFRACTED]: 'refracted', [c.RAY_BOUNCE]: 'bounce',
  };
  const rays = [];
  for (;;) {
    const tag = word();
    if (tag === c.INSPECT_SAMPLE) return { rays, sample: vec3() };
    if (tag === c.INSPECT_RAY) {
      const kind = kinds[word()];
      if (!kind) throw new Error(`the inspect log is malformed at word ${at - 1}: a ray kind`);
      const ray = { kind, any: word() !== 0, origin: vec3(), dir: vec3(), tLimit: float(), walk: [], hit: null, cost: null };
      const light = { entry: word(), kind: word(), object: word(), pick: float(), density: float() };
      ray.light = light.entry === c.NO_OBJECT ? null : light;
      if ((ray.light !== null) !== (kind === 'shadow')) {
        throw new Error(`the inspect log is malformed at word ${at}: a light on a ray that is not a shadow ray, or none on one`);
      }
      rays.push(ray);
      continue;
    }
    const ray = rays[rays.length - 1];
    if (!ray) throw new Error(`the inspect log is malformed at word ${at - 1}: a walk step before any ray`);
    switch (tag) {
      case c.INSPECT_HIT: {
        const object = word();
        const hit = { object, t: float(), point: vec3(), normal: vec3() };
        ray.hit = object === c.NO_OBJECT ? null : hit;
        ray.cost = { nodes: word(), leaves: word(), tests: word() };
        break;
      }
      case c.INSPECT_SEGMENT: ray.walk.push({ segment: [float(), float()] }); break;
      case c.INSPECT_NODE:
        ray.walk.push({ node: word(), tMin: float(), tMax: float(), near: word(), far: word(), tSplit: float(), crosses: word() !== 0 });
        break;
      case c.INSPECT_LEAF: ray.walk.push({ leaf: word(), tMin: float(), tMax: float() }); break;
      case c.INSPECT_SKIPPED: ray.walk.push({ skipped: word() }); break;
      case c.INSPECT_TESTED: {
        const object = word();
        const met = word() !== 0;
        const t = float();
        ray.walk.push({ tested: object, t: met ? t : null });
        break;
      }
      case c.INSPECT_PUSH: ray.walk.push({ push: { node: word(), t_max: float() } }); break;
      case c.INSPECT_POP: ray.walk.push({ pop: { node: word(), t_max: float() } }); break;
      case c.INSPECT_RESTART: ray.walk.push({ restart: { node: word(), t_min: float() } }); break;
      case c.INSPECT_ROPE: ray.walk.push({ rope: { face: FACES[Math.min(word(), 5)], node: word(), t_min: float() } }); break;
      default: throw new Error(`the inspect log is malformed at word ${at - 1}: tag ${tag}`);
    }
  }
}

// The tree as the document names it, from the bundle's kd_nodes,
// leaf_objects and objects arrays: each node's axis and split or its
// objects (scene ids), and its depth.
export function treeOf(arrays, c) {
  const u32 = (name) => {
    const b = arrays.get(name);
    return new Uint32Array(b.buffer.slice(b.byteOffset, b.byteOffset + (b.byteLength & ~3)));
  };
  const packed = u32('kd_nodes');
  const leafObjects = u32('leaf_objects');
  const objects = u32('objects');
  const splits = new DataView(packed.buffer);
  const count = packed.length / 2;
  const depths = new Uint32Array(count);
  const nodes = [];
  for (let i = 0; i < count; i++) {
    const kind = packed[2 * i] & 3;
    const above = packed[2 * i] >>> 2;
    if (kind === c.KD_LEAF) {
      const first = packed[2 * i + 1];
      const ids = Array.from(leafObjects.subarray(first, first + above), (id) => objects[2 * id + 1]);
      nodes.push({ leaf: true, objects: ids });
    } else {
      nodes.push({ leaf: false, axis: AXES[Math.min(kind, 2)], split: splits.getFloat32(8 * i + 4, true), upper: above });
      for (const child of [i + 1, above]) if (child < count) depths[child] = depths[i] + 1;
    }
  }
  return { nodes, depths };
}

// A shadow ray's light as the document names it (src/inspect/inspected_rays.rs,
// `light_named`): a scene light by its index in [[lights]] and kind, an
// emitter by its object (and triangle), the sky; its pick and density.
function documentLight(light, spheres, c) {
  const named = { source: 'light' };
  if (light.kind === c.LIGHT_SKY) {
    named.source = 'sky';
  } else if (light.kind === c.LIGHT_EMITTER) {
    Object.assign(named, { source: 'emitter', kind: light.object < spheres ? 'sphere' : 'triangle', object: light.object });
    if (light.object >= spheres) named.triangle = light.object - spheres;
  } else {
    const kinds = { [c.LIGHT_SPOT]: 'spot', [c.LIGHT_DIRECTIONAL]: 'directional' };
    Object.assign(named, { index: light.entry, kind: kinds[light.kind] ?? 'point' });
  }
  return { ...named, pick: light.pick, pdf: light.density > 0 ? light.density : null };
}

// One logged ray as the document's ray.
function documentRay(ray, tree, spheres, c) {
  const walk = [];
  let interval = null;
  let restarts = 0;
  for (const e of ray.walk) {
    if (e.segment) {
      interval = e.segment;
    } else if ('node' in e) {
      const n = tree.nodes[e.node];
      const step = { node: e.node, depth: tree.depths[e.node], axis: n.axis, split: n.split, t: [e.tMin, e.tMax], near: e.near };
      if (e.crosses) Object.assign(step, { t_split: e.tSplit, far: e.far });
      walk.push(step);
    } else if ('leaf' in e) {
      const n = tree.nodes[e.leaf];
      walk.push({ leaf: e.leaf, depth: tree.depths[e.leaf], objects: n.objects, t: [e.tMin, e.tMax], tested: [] });
    } else if ('skipped' in e) {
      const last = walk[walk.length - 1];
      if (last && 'leaf' in last) last.skipped = true;
    } else if ('tested' in e) {
      const last = walk[walk.length - 1];
      if (last && 'leaf' in last) {
        last.tested.push(e.t === null ? { object: e.tested, hit: false } : { object: e.tested, hit: true, t: e.t });
      }
    } else {
      if (e.restart) restarts += 1;
      walk.push(e);
    }
  }
  const hit = ray.hit && {
    object: ray.hit.object, kind: ray.hit.object < spheres ? 'sphere' : 'triangle',
    t: ray.hit.t, point: ray.hit.point, normal: ray.hit.normal,
  };
  const doc = {
    kind: ray.kind,
    query: ray.any ? 'any' : 'nearest',
    origin: ray.origin,
    direction: ray.dir,
    t_limit: ray.tLimit < c.T_INFINITY ? ray.tLimit : null,
    t_interval: interval,
    walk,
    hit,
    counts: { ...ray.cost, restarts },
  };
  if (ray.light) doc.light = documentLight(ray.light, spheres, c);
  return doc;
}

// The document: `meta` holds its fields that are not the log's (scene,
// pixel, frame, width, height, samples, integrator, accel, traversal,
// build, spheres).
export function inspectionDocument(log, tree, meta, contract) {
  const c = contract.constants;
  return {
    version: contract.inspect.version,
    scene: meta.scene,
    pixel: meta.pixel,
    frame: meta.frame,
    width: meta.width,
    height: meta.height,
    samples: meta.samples,
    integrator: meta.integrator,
    accel: meta.accel,
    traversal: meta.traversal,
    build: meta.build,
    walk_source: 'kernel',
    rays: log.rays.map((r) => documentRay(r, meta.accel === 'brute' ? { nodes: [], depths: [] } : tree, meta.spheres, c)),
    sample: log.sample,
  };
}
