// Times the kdray page in headless Chromium (WebGPU on SwiftShader) for
// scripts/web_bench.sh. Usage: node bench_page.mjs URL...; each URL is a
// page of an exported site with its width, height and samples in the
// query. Prints one JSON array on stdout: per URL its adapter (the
// overlay's last line) and every image pass's time in ms
// (window.kdray.state.passMs; the first pass also compiles the pipeline).

import { chromium } from 'playwright-core';

// As drive_page.mjs (docs/web.md, "Browser flags").
const FLAGS = ['--headless=new', '--no-sandbox', '--enable-unsafe-webgpu', '--enable-features=Vulkan',
  '--use-vulkan=swiftshader', '--use-angle=swiftshader'];
const TIMEOUT_MS = 300000;

const browser = await chromium.launch({
  executablePath: process.env.KDRAY_CHROMIUM ?? '/usr/bin/chromium', headless: false, args: FLAGS,
});
const results = [];
for (const url of process.argv.slice(2)) {
  const page = await browser.newPage({ viewport: { width: 800, height: 500 } });
  const result = { url };
  try {
    await page.goto(url);
    await page.waitForFunction(() => /^kdray: (done|error)/.test(document.title), null,
      { timeout: TIMEOUT_MS, polling: 50 });
    result.title = await page.title();
    result.adapter = await page.evaluate(() => document.getElementById('overlay').textContent.split('\n').pop());
    result.pass_ms = await page.evaluate(() => window.kdray.state.passMs);
  } catch (e) {
    result.failure = String(e);
  }
  results.push(result);
  await page.close();
}
await browser.close();
console.log(JSON.stringify(results));
