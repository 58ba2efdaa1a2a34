// Prints the page's tile plans (the site's denoise.js, tilePlan) for
// tests/external/web.rs. Usage: node tile_plan.mjs DENOISE_JS SPEC_JSON
// SIZES_JSON: SPEC_JSON holds contract.json's `denoise`, SIZES_JSON an
// array of [width, height, max tensor bytes]; prints a JSON array of the
// plans. DENOISE_JS must be in a folder whose package.json says "type":
// "module", beside tracer.js.

import { readFileSync } from 'node:fs';
import { pathToFileURL } from 'node:url';

const { tilePlan } = await import(pathToFileURL(process.argv[2]).href);
const spec = JSON.parse(readFileSync(process.argv[3], 'utf8'));
const sizes = JSON.parse(readFileSync(process.argv[4], 'utf8'));
console.log(JSON.stringify(sizes.map(([w, h, limit]) => tilePlan(w, h, spec, limit))));
