// The viewer in headless chromium at 1280 x 720 with software WebGL (SwiftShader): time to first
// picture of a run (page load to the first drawn frame, median over loads), and frame times while
// scrubbing a long run (each frame: the layers of a step updated, drawn and finished).
//
//   node viewer_bench.mjs STARNAV FIRST_PICTURE_RUN SCRUB_RUN OUT.json [LOADS] [FRAMES]
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import url from 'node:url';

const here = path.dirname(url.fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const [starnav, firstRun, scrubRun, out, loadsArg, framesArg] = process.argv.slice(2);
if (!out) {
  console.error('usage: node viewer_bench.mjs STARNAV FIRST_PICTURE_RUN SCRUB_RUN OUT.json [LOADS] [FRAMES]');
  process.exit(2);
}
const loads = Number(loadsArg || 7);
const frames = Number(framesArg || 300);

function serve(run) {
  const child = spawn(starnav, ['view', run, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  return new Promise((resolve, reject) => {
    let text = '';
    child.stdout.on('data', (d) => {
      text += d;
      const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve({ child, address: m[0] });
    });
    child.on('exit', (code) => reject(new Error(`starnav view ${run} exited (${code})`)));
  });
}

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length % 2 ? s[(s.length - 1) / 2] : (s[s.length / 2 - 1] + s[s.length / 2]) / 2;
};
const quantile = (xs, q) => [...xs].sort((a, b) => a - b)[Math.min(xs.length - 1, Math.floor(q * xs.length))];

const browser = await chromium.launch({
  executablePath: process.env.STARNAV_CHROMIUM || '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run', '--disable-quic'],
});
const result = { viewport: '1280x720', gl: null };
try {
  const context = await browser.newContext({ viewport: { width: 1280, height: 720 } });
  // First picture: navigation start to the first frame drawn, a fresh page each time.
  const first = await serve(firstRun);
  const firstMs = [];
  for (let i = 0; i < loads; ++i) {
    const page = await context.newPage();
    const t0 = Date.now();
    await page.goto(first.address);
    await page.waitForFunction(() => window.starnav && (window.starnav.state.ready || window.starnav.state.error), null, { polling: 10 });
    firstMs.push(Date.now() - t0);
    if (!result.gl) result.gl = await page.evaluate(() => {
      const gl = document.querySelector('canvas').getContext('webgl2');
      const ext = gl && gl.getExtension('WEBGL_debug_renderer_info');
      return ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : 'unknown';
    });
    await page.close();
  }
  first.child.kill('SIGTERM');
  result.first_picture = { run: firstRun, loads, median_ms: median(firstMs), all_ms: firstMs };

  // Scrubbing: times spread over the run in a fixed shuffled order (forward and backward jumps).
  const scrub = await serve(scrubRun);
  const page = await context.newPage();
  const t0 = Date.now();
  await page.goto(scrub.address);
  await page.waitForFunction(() => window.starnav && window.starnav.state.loaded, null, { polling: 50, timeout: 300000 });
  const loadMs = Date.now() - t0;
  const info = await page.evaluate(() => ({ steps: window.starnav.state.stepsLoaded, duration: window.starnav.state.duration,
    heap: performance.memory ? performance.memory.usedJSHeapSize : null }));
  let seed = 12345;
  const rand = () => {
    seed = (seed * 1103515245 + 12345) % 2147483648;
    return seed / 2147483648;
  };
  const times = Array.from({ length: frames }, () => rand() * info.duration);
  // The whole run in view (the page opens on the robot, closer: the overview is what the frame
  // time has always been measured on).
  await page.evaluate(() => window.starnav.overview());
  const ms = await page.evaluate((ts) => window.starnav.scrubFrames(ts), times);
  result.scrub = {
    run: scrubRun, steps: info.steps, duration_s: info.duration, load_ms: loadMs, js_heap_mb: info.heap ? info.heap / 1048576 : null,
    frames, median_ms: median(ms), p95_ms: quantile(ms, 0.95), max_ms: Math.max(...ms),
  };
  scrub.child.kill('SIGTERM');
} finally {
  await browser.close();
}
fs.writeFileSync(out, `${JSON.stringify(result, null, 2)}\n`);
console.log(JSON.stringify(result, null, 2));
