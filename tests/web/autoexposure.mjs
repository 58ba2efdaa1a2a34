// Prints the page's autoexposure (the site's denoise.js) of an image, for
// tests/external/web.rs. Usage: node autoexposure.mjs DENOISE_JS WIDTH
// HEIGHT FILE, FILE holding three little-endian f32 a pixel, row-major;
// prints the scale's f32 bits as a decimal integer. DENOISE_JS must be in
// a folder whose package.json says "type": "module", beside tracer.js.

import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const { autoexposure } = await import(pathToFileURL(process.argv[2]).href);
const [width, height] = process.argv.slice(3, 5).map(Number);
const bytes = readFileSync(process.argv[5]);
const rgb = new Float32Array(bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength));
const bits = new Uint32Array(new Float32Array([autoexposure(width, height, rgb)]).buffer)[0];
console.log(bits);
