// Test vectors for kdray's EXT_meshopt_compression decoder: meshoptimizer's
// encoder writes each stream, its decoder gives the expected bytes.
import { MeshoptEncoder } from 'meshoptimizer/encoder';
import { MeshoptDecoder } from 'meshoptimizer/decoder';
await MeshoptEncoder.ready; await MeshoptDecoder.ready;
let seed = 12345;
const rnd = () => { seed = (seed * 1103515245 + 12345) & 0x7fffffff; return seed / 0x7fffffff; };
const hex = (u) => Buffer.from(u.buffer, u.byteOffset, u.byteLength).toString('hex');
const out = [];
function attr(name, count, stride, make, filter = 'NONE', rawFloats = null, bits = 0) {
  let src;
  if (filter === 'NONE') {
    src = new Uint8Array(count * stride);
    for (let i = 0; i < count; i++) for (let k = 0; k < stride; k++) src[i * stride + k] = make(i, k);
  } else if (filter === 'OCTAHEDRAL') src = MeshoptEncoder.encodeFilterOct(rawFloats, count, stride, bits);
  else if (filter === 'QUATERNION') src = MeshoptEncoder.encodeFilterQuat(rawFloats, count, stride, bits);
  else src = MeshoptEncoder.encodeFilterExp(rawFloats, count, stride, bits);
  const enc = MeshoptEncoder.encodeGltfBuffer(src, count, stride, 'ATTRIBUTES');
  const dec = new Uint8Array(count * stride);
  MeshoptDecoder.decodeGltfBuffer(dec, count, stride, enc, 'ATTRIBUTES', filter);
  out.push({ name, mode: 'ATTRIBUTES', filter, count, stride, encoded: hex(enc), decoded: hex(dec) });
}
// smooth ramps, noise (all four group encodings), over several blocks
attr('ramp_stride4', 40, 4, (i, k) => (i * (k + 1)) & 255);
attr('noise_stride12', 300, 12, (i, k) => k < 4 ? Math.floor(rnd() * 256) : k < 8 ? (i + Math.floor(rnd() * 6)) & 255 : (i >> 3) & 255);
attr('constant_stride8', 17, 8, (i, k) => 7 * k);
const nrm = new Float32Array(20 * 4);
for (let i = 0; i < 20; i++) { const a = i * 0.7, b = i * 0.3 - 3; const v = [Math.cos(a) * Math.sin(b), Math.sin(a) * Math.sin(b), Math.cos(b)]; nrm.set([...v, 1], i * 4); }
attr('octahedral_stride4', 20, 4, null, 'OCTAHEDRAL', nrm, 8);
attr('octahedral_stride8', 20, 8, null, 'OCTAHEDRAL', nrm, 12);
const q = new Float32Array(10 * 4);
for (let i = 0; i < 10; i++) { const h = i * 0.31; const v = [Math.sin(h) * 0.6, Math.cos(h) * 0.3, 0.2, 0]; v[3] = Math.sqrt(1 - v[0] ** 2 - v[1] ** 2 - v[2] ** 2); q.set(v, i * 4); }
attr('quaternion_stride8', 10, 8, null, 'QUATERNION', q, 12);
const f = new Float32Array(12 * 3);
for (let i = 0; i < f.length; i++) f[i] = (i - 17) * 13.25 + 0.001 * i;
attr('exponential_stride12', 12, 12, null, 'EXPONENTIAL', f, 15);
function idx(name, mode, stride, indices) {
  const src = stride === 2 ? new Uint16Array(indices) : new Uint32Array(indices);
  const enc = MeshoptEncoder.encodeGltfBuffer(new Uint8Array(src.buffer), indices.length, stride, mode);
  const dec = new Uint8Array(indices.length * stride);
  MeshoptDecoder.decodeGltfBuffer(dec, indices.length, stride, enc, mode);
  out.push({ name, mode, filter: 'NONE', count: indices.length, stride, encoded: hex(enc), decoded: hex(dec) });
}
// a 6x5 grid of quads, and a shuffled soup reaching explicit indices
const grid = [];
for (let y = 0; y < 5; y++) for (let x = 0; x < 6; x++) { const a = y * 7 + x; grid.push(a, a + 1, a + 7, a + 1, a + 8, a + 7); }
idx('grid_triangles_u16', 'TRIANGLES', 2, grid);
const soup = [];
for (let t = 0; t < 30; t++) soup.push(Math.floor(rnd() * 70000), Math.floor(rnd() * 50), t * 3 + 100000);
idx('soup_triangles_u32', 'TRIANGLES', 4, soup);
const strip = [];
for (let i = 0; i < 50; i++) strip.push(i % 2 ? 1000 - i : i * 3);
idx('bimodal_indices_u32', 'INDICES', 4, strip);
idx('sequence_indices_u16', 'INDICES', 2, [0, 1, 2, 2, 1, 3, 60000, 4, 5]);
console.log(JSON.stringify(out, null, 1));
