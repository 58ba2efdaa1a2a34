// Reads a kdray bundle (docs/web.md, "The bundle"): checks the magic, the
// format version and that every section lies inside the file, with the
// sizes and names from contract.json. Throws BundleError with a sentence
// for the page.

export class BundleError extends Error {}

// { info (the scene section's JSON), frameParams (ArrayBuffer), arrays
// (Map of binding name to Uint8Array), sections (every section by name,
// the optional `cameras` too) } of the bundle in `buffer`.
export function parseBundle(buffer, contract) {
  const format = contract.bundle;
  const bytes = new Uint8Array(buffer);
  const view = new DataView(buffer);
  if (bytes.length < format.header_bytes) {
    throw new BundleError(
      `truncated bundle: ${bytes.length} bytes, shorter than its ${format.header_bytes}-byte header`);
  }
  const magic = String.fromCharCode(...bytes.subarray(0, format.magic.length));
  if (magic !== format.magic) {
    throw new BundleError(`not a kdray bundle: bad magic ${JSON.stringify(magic)} (expected ${format.magic})`);
  }
  const version = view.getUint32(8, true);
  if (version > format.version) {
    throw new BundleError(
      `bundle format version ${version} is newer than this page reads (${format.version}): ` +
      'export the scene again with this kdray, or serve the page of the kdray that wrote it');
  }
  const count = view.getUint32(12, true);
  const tableEnd = format.header_bytes + format.section_entry_bytes * count;
  if (tableEnd > bytes.length) {
    throw new BundleError(`truncated bundle: its table of ${count} sections runs past the end (${bytes.length} bytes)`);
  }
  const sections = new Map();
  for (let i = 0; i < count; i++) {
    const at = format.header_bytes + format.section_entry_bytes * i;
    const nameBytes = bytes.subarray(at, at + format.section_name_bytes);
    const end = nameBytes.indexOf(0);
    const name = String.fromCharCode(...nameBytes.subarray(0, end < 0 ? nameBytes.length : end));
    const offset = Number(view.getBigUint64(at + 16, true));
    const size = Number(view.getBigUint64(at + 24, true));
    if (offset + size > bytes.length) {
      throw new BundleError(
        `truncated bundle: section ${name} needs bytes ${offset} to ${offset + size} but the file has ${bytes.length}`);
    }
    sections.set(name, bytes.subarray(offset, offset + size));
  }
  const required = ['scene', 'frame_params', ...format.scene_arrays];
  const missing = required.filter((name) => !sections.has(name));
  if (missing.length) throw new BundleError(`bundle lacks its ${missing.join(', ')} section(s)`);
  const params = sections.get('frame_params');
  if (params.length !== contract.frame_params.size) {
    throw new BundleError(`bundle's frame_params is ${params.length} bytes, the kernel's ${contract.frame_params.size}`);
  }
  const info = JSON.parse(new TextDecoder().decode(sections.get('scene')));
  const arrays = new Map(format.scene_arrays.map((name) => [name, sections.get(name)]));
  return { info, frameParams: params.slice().buffer, arrays, sections };
}
