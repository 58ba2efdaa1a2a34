// Drives the kdray page in headless Chromium (WebGPU on SwiftShader) for
// tests/external/web.rs. Usage: node drive_page.mjs JOBS.json; prints one JSON
// object of results on stdout. Each job: { url, png (a path to write the
// page's PNG to, or null), drag (a path for the PNG after a drag, or
// null), screenshot (a path, or null), play (bool: press Space, wait for
// the next frame, press Space again), heatmap ({ png, restored }: press C,
// save the heatmap's PNG, press C again, save the image's), toggle (a path:
// press I, wait for the other integrator's image, save its PNG), inspect
// ([[x, y], ...]: window.kdray.inspect's document of each pixel, and the
// error of a pixel outside the image), click ({ pixel: [x, y], before,
// after }: press X, click the image pixel, wait for its lines, drag to orbit
// the camera, screenshot when refined (`after`; the lines drawn come back
// in `drawn`), press X (lines off), screenshot (`before`)) }.
// Every result has `pipelines`: the entry point, walk, costs, integrator
// and override constants of each kernel pipeline the page made, and
// `denoised`: the denoised image's { sample, scale, ms } (or null). A
// job's `denoise_off` (a path): press N, wait for the image, save its PNG;
// its `timeout_ms`: how long the page may take to finish (TIMEOUT_MS).
// The page's contract (docs/web.md): document.title starts with
// "kdray: done" or "kdray: error"; window.kdray.png() is a PNG data URL.

import { readFileSync, writeFileSync } from 'node:fs';
import { chromium } from 'playwright-core';

// Measured: without --enable-unsafe-webgpu there is no adapter; without the
// Vulkan and ANGLE SwiftShader flags a WebGPU canvas crashes the GPU process.
const FLAGS = ['--headless=new', '--no-sandbox', '--enable-unsafe-webgpu', '--enable-features=Vulkan',
  '--use-vulkan=swiftshader', '--use-angle=swiftshader'];
const TIMEOUT_MS = 120000;

const jobs = JSON.parse(readFileSync(process.argv[2], 'utf8'));
const browser = await chromium.launch({
  executablePath: process.env.KDRAY_CHROMIUM ?? '/usr/bin/chromium', headless: false, args: FLAGS,
});

const finished = (page, timeout = TIMEOUT_MS) => page.waitForFunction(
  () => /^kdray: (done|error)/.test(document.title), null, { timeout, polling: 50 });
// Refinement finished with the heatmap shown or not.
const settled = (page, heatmap) => page.waitForFunction(
  (h) => window.kdray.state.done && window.kdray.state.heatmap === h && (window.kdray.state.tracer.heatScale !== null) === h,
  heatmap, { timeout: TIMEOUT_MS, polling: 50 });
const overlayText = (page) => page.evaluate(() => document.getElementById('overlay').textContent);
const savePng = async (page, path) => {
  const url = await page.evaluate(() => window.kdray.png());
  writeFileSync(path, Buffer.from(url.slice(url.indexOf(',') + 1), 'base64'));
};

const results = [];
for (const job of jobs) {
  const page = await browser.newPage({ viewport: { width: 800, height: 500 } });
  const result = { url: job.url };
  try {
    await page.goto(job.url);
    await finished(page, job.timeout_ms ?? TIMEOUT_MS);
    result.title = await page.title();
    result.message = await page.evaluate(() => {
      const m = document.getElementById('message');
      return m.hidden ? null : m.textContent;
    });
    result.overlay = await page.evaluate(() => document.getElementById('overlay').textContent);
    if (job.png && result.title.startsWith('kdray: done')) await savePng(page, job.png);
    if (job.screenshot) await page.screenshot({ path: job.screenshot });
    if (job.drag && result.title.startsWith('kdray: done')) {
      const box = await page.locator('#view').boundingBox();
      const [x, y] = [box.x + box.width / 2, box.y + box.height / 2];
      await page.mouse.move(x, y);
      await page.mouse.down();
      await page.mouse.move(x + box.width / 4, y + box.height / 8, { steps: 5 });
      await page.mouse.up();
      result.after_drag_title = await page.title();
      result.after_drag_sample = await page.evaluate(() => window.kdray.state.sample);
      await finished(page);
      result.drag_title = await page.title();
      await savePng(page, job.drag);
    }
    if (job.play && result.title.startsWith('kdray: done')) {
      result.before_play_overlay = await overlayText(page);
      const from = await page.evaluate(() => window.kdray.state.frame);
      await page.keyboard.press(' ');
      await page.waitForFunction((f) => window.kdray.state.frame !== f, from, { timeout: TIMEOUT_MS, polling: 20 });
      // The overlay is written after each pass: wait for one with the new frame.
      await page.waitForFunction((f) => !document.getElementById('overlay').textContent.includes(`frame ${f}/`),
        from, { timeout: TIMEOUT_MS, polling: 20 });
      result.playing_overlay = await overlayText(page);
      await page.keyboard.press(' ');
      await page.waitForFunction(() => document.getElementById('overlay').textContent.includes(' paused'),
        null, { timeout: TIMEOUT_MS, polling: 20 });
      result.paused_overlay = await overlayText(page);
    }
    if (job.toggle && result.title.startsWith('kdray: done')) {
      const from = await page.evaluate(() => window.kdray.state.integrator);
      await page.keyboard.press('i');
      await page.waitForFunction((f) => window.kdray.state.integrator !== f && window.kdray.state.done,
        from, { timeout: TIMEOUT_MS, polling: 50 });
      result.toggled_overlay = await overlayText(page);
      await savePng(page, job.toggle);
    }
    result.denoised = await page.evaluate(() => window.kdray.state.denoised);
    if (job.denoise_off && result.title.startsWith('kdray: done')) {
      await page.keyboard.press('n');
      await page.waitForFunction(() => !window.kdray.state.denoise && window.kdray.state.done &&
        !document.getElementById('overlay').textContent.includes('denoise:'), null, { timeout: TIMEOUT_MS, polling: 50 });
      result.denoise_off_overlay = await overlayText(page);
      await savePng(page, job.denoise_off);
    }
    if (job.inspect && result.title.startsWith('kdray: done')) {
      result.inspections = [];
      for (const pixel of job.inspect) {
        result.inspections.push(await page.evaluate(([x, y]) => window.kdray.inspect(x, y), pixel));
      }
      result.inspect_outside = await page.evaluate(
        () => window.kdray.inspect(-1, 0).then(() => null, (e) => String(e.message)));
    }
    if (job.click && result.title.startsWith('kdray: done')) {
      await page.keyboard.press('x');
      await page.waitForFunction(() => window.kdray.state.inspecting, null, { timeout: TIMEOUT_MS });
      const at = await page.evaluate(([x, y]) => {
        const r = document.getElementById('view').getBoundingClientRect();
        const { width, height } = window.kdray.state;
        const s = Math.min(r.width / width, r.height / height);
        return [r.left + (r.width - s * width) / 2 + (x + 0.5) * s, r.top + (r.height - s * height) / 2 + (y + 0.5) * s];
      }, job.click.pixel);
      await page.mouse.click(at[0], at[1]);
      await page.waitForFunction(() => window.kdray.state.drawn.length > 0, null, { timeout: TIMEOUT_MS, polling: 50 });
      result.clicked = await page.evaluate(() => window.kdray.state.inspected.pixel);
      await page.mouse.move(at[0], at[1]);
      await page.mouse.down();
      await page.mouse.move(at[0] + 120, at[1] + 30, { steps: 5 });
      await page.mouse.up();
      await page.waitForTimeout(300);
      await finished(page);
      await page.waitForFunction(() => window.kdray.state.done, null, { timeout: TIMEOUT_MS, polling: 50 });
      await page.waitForTimeout(300);
      await page.screenshot({ path: job.click.after });
      result.drawn = await page.evaluate(() => window.kdray.state.drawn);
      result.inspect_overlay = await overlayText(page);
      await page.keyboard.press('x');
      await page.waitForFunction(() => window.kdray.state.drawn.length === 0, null, { timeout: TIMEOUT_MS, polling: 50 });
      await page.waitForTimeout(300);
      await page.screenshot({ path: job.click.before });
    }
    if (job.heatmap && result.title.startsWith('kdray: done')) {
      await page.keyboard.press('c');
      await settled(page, true);
      result.heatmap_overlay = await overlayText(page);
      await savePng(page, job.heatmap.png);
      await page.keyboard.press('c');
      await settled(page, false);
      result.restored_overlay = await overlayText(page);
      await savePng(page, job.heatmap.restored);
    }
    result.pipelines = await page.evaluate(() => [...(window.kdray.state.tracer?.pipelines.values() ?? [])]
      .map(({ entry, walk, costs, integrator, constants }) => ({ entry, walk, costs, integrator, constants })));
  } catch (e) {
    result.failure = String(e);
    result.title = await page.title().catch(() => null);
  }
  results.push(result);
  await page.close();
}
await browser.close();
console.log(JSON.stringify(results));
