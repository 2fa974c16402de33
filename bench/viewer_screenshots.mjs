// The pictures of docs/viewer.md: each run served by `starnav view`, opened in headless chromium
// at 1280 x 720, brought to a time, and captured.
//
//   node viewer_screenshots.mjs STARNAV OUT_DIR NAME=RUN_DIR@TIME[:overview|:close|:first|:top] ...
//
// first: the camera the page opens with (on the robot); top: that camera looking straight down.
import { spawn } from 'node:child_process';
import { createRequire } from 'node:module';
import path from 'node:path';
import url from 'node:url';

const here = path.dirname(url.fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const [starnav, outDir, ...shots] = process.argv.slice(2);
if (!shots.length) {
  console.error('usage: node viewer_screenshots.mjs STARNAV OUT_DIR NAME=RUN_DIR@TIME[:overview|:close|:first|:top] ...');
  process.exit(2);
}
const browser = await chromium.launch({
  executablePath: process.env.STARNAV_CHROMIUM || '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking', '--no-first-run'],
});
const context = await browser.newContext({ viewport: { width: 1280, height: 720 } });
for (const shot of shots) {
  const [, name, run, time, view] = shot.match(/^([^=]+)=(.+)@([0-9.]+|end)(?::(overview|close|first|top))?$/) || [];
  if (!name) throw new Error(`bad shot ${shot}`);
  const child = spawn(starnav, ['view', run, '--port', '0'], { stdio: ['ignore', 'pipe', 'inherit'] });
  const address = await new Promise((resolve, reject) => {
    let text = '';
    child.stdout.on('data', (d) => {
      text += d;
      const m = text.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve(m[0]);
    });
    child.on('exit', (code) => reject(new Error(`starnav view ${run} exited (${code})`)));
  });
  const page = await context.newPage();
  await page.goto(address);
  await page.waitForFunction(() => window.starnav && window.starnav.state.loaded, null, { timeout: 120000 });
  await page.evaluate(([t, v]) => {
    window.starnav.setTime(t === 'end' ? window.starnav.state.duration : Number(t));
    if (v === 'close') window.starnav.closeUp();
    else if (v === 'top') window.starnav.setTopDown(true);
    else if (v !== 'first') window.starnav.overview();
  }, [time, view || 'overview']);
  await page.waitForTimeout(200);
  await page.screenshot({ path: path.join(outDir, `${name}.png`) });
  console.log(`wrote ${path.join(outDir, `${name}.png`)}`);
  await page.close();
  child.kill('SIGTERM');
}
await browser.close();
