// The viewer in a real browser: Debian's chromium, headless with software WebGL (SwiftShader),
// driven by playwright-core. CTest runs it on E4's run (a fixture that simulates it first).
//
//   node browser_test.mjs STARNAV_BINARY RUN_DIR SCENARIO WORK_DIR
//
// Checks, each against what the run's own files say (read here, not by the viewer):
//   first look (E4 and a SLAM run made here): the page opens on t = 0 with only the paths planned
//   by then, the map as the steps up to then leave it (cells replayed here), the camera on the
//   robot, a legend of the layers, and a top-down toggle that looks straight down, north up;
//   served: the canvas shows the terrain and the robot (pixels), scrubbing to the end puts the
//   robot at the goal, the page counts as many paths as metrics.json has plans, hiding a layer
//   changes the picture, every path is drawn by the end;
//   live: `sim --live` streams steps to the page while the simulation runs, and its records are
//   the same bytes as the fixture's (timing.json aside);
//   exported: `view --export` opens from a file URL with the same paths.
import { spawn } from 'node:child_process';
import fs from 'node:fs';
import { createRequire } from 'node:module';
import path from 'node:path';
import url from 'node:url';

const here = path.dirname(url.fileURLToPath(import.meta.url));
const require = createRequire(path.join(here, '..', '..', 'viewer', 'package.json'));
const { chromium } = require('playwright-core');

const [starnav, runDir, scenario, work] = process.argv.slice(2);
if (!work) {
  console.error('usage: node browser_test.mjs STARNAV RUN_DIR SCENARIO WORK_DIR');
  process.exit(2);
}
fs.mkdirSync(work, { recursive: true });

let failures = 0;
function check(ok, what, detail = '') {
  console.log(`${ok ? 'ok  ' : 'FAIL'} ${what}${detail ? `: ${detail}` : ''}`);
  if (!ok) failures += 1;
}

// Starts a starnav command and resolves with the first URL it prints on stdout or stderr.
function startWithUrl(args) {
  const child = spawn(starnav, args, { stdio: ['ignore', 'pipe', 'pipe'] });
  let out = '';
  const urlOf = new Promise((resolve, reject) => {
    const look = (chunk) => {
      out += chunk.toString();
      const m = out.match(/http:\/\/127\.0\.0\.1:\d+\//);
      if (m) resolve(m[0]);
    };
    child.stdout.on('data', look);
    child.stderr.on('data', look);
    child.on('exit', (code) => reject(new Error(`starnav ${args.join(' ')} exited (${code}) before printing a URL:\n${out}`)));
  });
  const exited = new Promise((resolve) => child.on('exit', (code) => resolve(code)));
  return { child, urlOf, exited, output: () => out };
}

async function waitFor(page, predicate, what, timeoutMs = 60000) {
  try {
    await page.waitForFunction(predicate, null, { timeout: timeoutMs, polling: 50 });
  } catch (e) {
    const error = await page.evaluate(() => window.starnav && window.starnav.state.error);
    throw new Error(`timed out waiting for ${what}${error ? ` (page error: ${error})` : ''}`);
  }
}

// How many pixels of two RGB arrays differ visibly (by more than 30 over the three channels).
function pixelsChanged(a, b) {
  let n = 0;
  for (let i = 0; i < a.length; i += 3) if (Math.abs(a[i] - b[i]) + Math.abs(a[i + 1] - b[i + 1]) + Math.abs(a[i + 2] - b[i + 2]) > 30) n += 1;
  return n;
}

function differs(a, b) {
  let sum = 0;
  for (let i = 0; i < a.length; ++i) sum += Math.abs(a[i] - b[i]);
  return sum / a.length;
}

const metrics = JSON.parse(fs.readFileSync(path.join(runDir, 'metrics.json'), 'utf8'));
const world = JSON.parse(fs.readFileSync(path.join(runDir, 'world.json'), 'utf8'));
const stepLines = fs.readFileSync(path.join(runDir, 'steps.jsonl'), 'utf8').split('\n').filter((l) => l);
const goal = world.goals[world.goals.length - 1];

// The paths planned and the map's known cells at time t (the run's clock), replayed from its files.
function stateAt(worldDoc, lines, t) {
  let paths = 0;
  const m = worldDoc.nav_map;
  const cells = new Int8Array(m ? m.width * m.height : 0);
  if (m) {
    let k = 0;
    for (let i = 0; i + 1 < m.initial.length; i += 2) {
      cells.fill(m.initial[i], k, k + m.initial[i + 1]);
      k += m.initial[i + 1];
    }
  }
  for (const line of lines) {
    const step = JSON.parse(line);
    if (step.t_s > t) break;
    if (step.path) paths += 1;
    for (const [ix, iy, v] of step.changed || []) cells[iy * m.width + ix] = v;
  }
  return { paths, known: cells.reduce((n, v) => n + (v >= 0 ? 1 : 0), 0) };
}

// The first look of a page just opened: t = 0, the paths and map cells of then, the camera on the
// robot and closer than the overview, the legend's layers, the top-down toggle.
async function checkFirstLook(page, name, runFolder, legendLayers) {
  const manifest = JSON.parse(fs.readFileSync(path.join(runFolder, 'run.json'), 'utf8'));
  const worldDoc = JSON.parse(fs.readFileSync(path.join(runFolder, 'world.json'), 'utf8'));
  const lines = fs.readFileSync(path.join(runFolder, 'steps.jsonl'), 'utf8').split('\n').filter((l) => l);
  const expected = stateAt(worldDoc, lines, manifest.start_s || 0);
  await page.screenshot({ path: path.join(work, `${name.toLowerCase()}_first_look.png`) });
  const first = await page.evaluate(() => window.starnav.state);
  check(first.time === 0 && first.pathsShown === expected.paths && first.pathCount >= first.pathsShown,
    `${name}: opens at t = 0 with only the paths planned by then`, `t ${first.time}, ${first.pathsShown} shown (${expected.paths} planned by then) of ${first.pathCount}`);
  check(worldDoc.nav_map && first.mapCells === expected.known && expected.known > 0,
    `${name}: the map is drawn as it stands at t = 0`, `${first.mapCells} cells drawn, ${expected.known} known then`);
  const view = await page.evaluate(() => {
    const s = window.starnav.state;
    const [x, y] = window.starnav.project(s.robot.x, s.robot.y, s.robot.z);
    const c = s.camera;
    return { x, y, w: window.innerWidth, h: window.innerHeight, follow: s.follow,
      distance: Math.hypot(c.x - s.robot.x, c.y - s.robot.y, c.z - s.robot.z) };
  });
  check(view.follow && Math.abs(view.x - view.w / 2) < 0.1 * view.w && Math.abs(view.y - view.h / 2) < 0.1 * view.h && view.distance < 40,
    `${name}: the camera is on the robot`, `robot at (${view.x.toFixed(0)}, ${view.y.toFixed(0)}) px, camera ${view.distance.toFixed(1)} m away`);
  // Hiding the map changes the picture around the robot (a thin wall is a few pixels wide: count
  // the pixels that change on a 320 x 180 copy; at least 0.5 % of them).
  const withMap = await page.evaluate(() => window.starnav.thumbnail(320, 180));
  await page.evaluate(() => window.starnav.setLayer('map', false));
  const withoutMap = await page.evaluate(() => window.starnav.thumbnail(320, 180));
  await page.evaluate(() => window.starnav.setLayer('map', true));
  const changed = pixelsChanged(withMap, withoutMap);
  check(changed > 0.005 * 320 * 180, `${name}: the map is on screen`, `${changed} of ${320 * 180} pixels change when it is hidden`);
  const legend = await page.evaluate(() => [...document.querySelectorAll('#legend .legend-entry')].map((e) => e.dataset.layer));
  check(legendLayers.every((l) => legend.includes(l)), `${name}: the legend names the layers`, legend.join(', '));
  // Top-down: the button looks straight down at the robot, +x to the right and +y up the screen.
  await page.click('#top-down');
  const top = await page.evaluate(() => {
    window.starnav.renderNow();
    const s = window.starnav.state;
    const r = s.robot;
    const o = window.starnav.project(r.x, r.y, r.z);
    const ex = window.starnav.project(r.x + 1, r.y, r.z);
    const ey = window.starnav.project(r.x, r.y + 1, r.z);
    const c = s.camera;
    return { on: s.topDown, level: Math.hypot(c.x - c.target.x, c.y - c.target.y) / Math.max(1e-9, c.z - c.target.z),
      ex: [ex[0] - o[0], ex[1] - o[1]], ey: [ey[0] - o[0], ey[1] - o[1]] };
  });
  check(top.on && top.level < 0.01 && top.ex[0] > 5 && Math.abs(top.ex[1]) < 0.05 * top.ex[0] && top.ey[1] < -5 && Math.abs(top.ey[0]) < 0.05 * -top.ey[1],
    `${name}: top-down looks straight down, north up`, `tilt ${top.level.toFixed(4)}, +x -> (${top.ex.map((v) => v.toFixed(1))}) px, +y -> (${top.ey.map((v) => v.toFixed(1))}) px`);
  await page.click('#top-down');
  const back = await page.evaluate(() => {
    window.starnav.renderNow();
    const c = window.starnav.state.camera;
    return { on: window.starnav.state.topDown, level: Math.hypot(c.x - c.target.x, c.y - c.target.y) / Math.max(1e-9, c.z - c.target.z) };
  });
  check(!back.on && back.level > 0.3, `${name}: the toggle goes back to the 3D view`, `tilt ${back.level.toFixed(2)}`);
}

const browser = await chromium.launch({
  executablePath: process.env.STARNAV_CHROMIUM || '/usr/bin/chromium',
  args: ['--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--disable-background-networking', '--disable-component-update',
    '--disable-sync', '--no-first-run', '--disable-quic'],
});
const context = await browser.newContext({ viewport: { width: 1280, height: 720 } });

async function openViewer(address) {
  const page = await context.newPage();
  page.on('pageerror', (e) => console.log(`page error: ${e.message}`));
  await page.goto(address);
  await waitFor(page, () => window.starnav && (window.starnav.state.ready || window.starnav.state.error), 'the first picture');
  const error = await page.evaluate(() => window.starnav.state.error);
  if (error) throw new Error(`the viewer failed: ${error}`);
  return page;
}

try {
  // ---- served ---------------------------------------------------------------------------------
  const server = startWithUrl(['view', runDir, '--port', '0']);
  const address = await server.urlOf;
  const page = await openViewer(address);
  await waitFor(page, () => window.starnav.state.loaded, 'all steps');
  await checkFirstLook(page, 'E4', runDir, ['robot', 'trajectory', 'paths', 'map', 'terrain', 'obstacles', 'hits']);
  const state = await page.evaluate(() => window.starnav.state);
  check(state.stepsLoaded === stepLines.length, 'every step loaded', `${state.stepsLoaded} of ${stepLines.length}`);
  check(state.pathCount === metrics.plans, 'paths counted equal the run\'s plans', `${state.pathCount} vs ${metrics.plans}`);

  // Terrain: from above with only the terrain layer, the ground fills the middle of the canvas in
  // the terrain's colours, not the sky's.
  await page.evaluate(() => {
    window.starnav.overview();
    for (const l of ['map', 'obstacles', 'robot', 'hits', 'paths', 'trajectory', 'particles', 'estimate']) window.starnav.setLayer(l, false);
  });
  const sky = [0xdd, 0xe6, 0xee];
  const centre = await page.evaluate(() => window.starnav.sample(640, 400, 6));
  check(differs(centre, sky) > 20, 'the terrain fills the view', `centre RGB ${centre.map((v) => v.toFixed(0))}`);
  const terrainOnly = await page.evaluate(() => window.starnav.thumbnail());
  await page.evaluate(() => window.starnav.setLayer('terrain', false));
  const nothing = await page.evaluate(() => window.starnav.thumbnail());
  check(differs(terrainOnly, nothing) > 5, 'hiding the terrain changes the picture', `mean change ${differs(terrainOnly, nothing).toFixed(1)}`);
  await page.evaluate(() => window.starnav.setLayer('terrain', true));

  // The robot: its body's colour (yellow) at its projected position, gone when hidden.
  await page.evaluate(() => {
    window.starnav.setLayer('robot', true);
    window.starnav.setTime(0);
    window.starnav.setFollow(true);
  });
  const robotAt = await page.evaluate(() => {
    const r = window.starnav.state.robot;
    return window.starnav.project(r.x, r.y, r.z + 0.25);
  });
  const withRobot = await page.evaluate(([x, y]) => window.starnav.sample(x, y, 2), robotAt);
  await page.evaluate(() => window.starnav.setLayer('robot', false));
  const withoutRobot = await page.evaluate(([x, y]) => window.starnav.sample(x, y, 2), robotAt);
  const yellow = withRobot[0] > 120 && withRobot[1] > 90 && withRobot[2] < 0.7 * withRobot[0];
  check(yellow && differs(withRobot, withoutRobot) > 30, 'the robot is drawn where it stands',
    `RGB ${withRobot.map((v) => v.toFixed(0))} with, ${withoutRobot.map((v) => v.toFixed(0))} without`);

  // Scrubbing to the end puts the robot at the goal (the run arrived there).
  await page.evaluate(() => {
    for (const l of ['map', 'obstacles', 'robot', 'hits', 'paths', 'trajectory']) window.starnav.setLayer(l, true);
    window.starnav.setTime(window.starnav.state.duration);
  });
  const end = await page.evaluate(() => window.starnav.state);
  const toGoal = Math.hypot(end.robot.x - goal[0], end.robot.y - goal[1]);
  check(metrics.outcome === 'arrived' && Math.abs(toGoal - metrics.goal_distance_m) < 0.01,
    'scrubbed to the end, the robot is at the goal', `${toGoal.toFixed(3)} m from it (metrics.json: ${metrics.goal_distance_m.toFixed(3)} m)`);
  check(end.pathsShown === metrics.plans, 'every path is shown at the end', `${end.pathsShown}`);
  check(end.obstaclesShown === world.obstacles.filter((o) => o.disappear_s === null || o.disappear_s > end.time).length,
    'the obstacles alive at the end are shown', `${end.obstaclesShown}`);

  // Hiding a layer changes the picture.
  await page.evaluate(() => window.starnav.overview());
  const all = await page.evaluate(() => window.starnav.thumbnail());
  await page.evaluate(() => window.starnav.setLayer('obstacles', false));
  const noObstacles = await page.evaluate(() => window.starnav.thumbnail());
  check(differs(all, noObstacles) > 0.5, 'hiding the obstacles changes the picture', `mean change ${differs(all, noObstacles).toFixed(2)}`);
  await page.evaluate(() => window.starnav.setLayer('obstacles', true));
  await page.screenshot({ path: path.join(work, 'e4_end.png') });
  await page.close();
  server.child.kill('SIGTERM');
  check((await server.exited) === 0, 'starnav view exits 0 on SIGTERM');

  // ---- a SLAM run's first look ----------------------------------------------------------------
  const run = (args) => new Promise((resolve) => spawn(starnav, args, { stdio: 'inherit' }).on('exit', resolve));
  const indoor = path.join(work, 'indoor');
  const slamOut = path.join(work, 'slam');
  const made = (await run(['sim', path.join(path.dirname(scenario), 'indoor_slam.yaml'), '--out', indoor, '--duration', '20', '--force', '--quiet'])) === 0 &&
    (await run(['slam', 'run', path.join(indoor, 'log.clf'), '--out', slamOut, '--force', '--quiet'])) === 0;
  check(made, 'a SLAM run to view');
  if (made) {
    const slamServer = startWithUrl(['view', slamOut, '--port', '0']);
    const slamPage = await openViewer(await slamServer.urlOf);
    await waitFor(slamPage, () => window.starnav.state.loaded, 'the SLAM run\'s steps');
    await checkFirstLook(slamPage, 'SLAM', slamOut, ['robot', 'trajectory', 'map', 'hits']);
    await slamPage.close();
    slamServer.child.kill('SIGTERM');
    await slamServer.exited;
  }

  // ---- live -----------------------------------------------------------------------------------
  const liveOut = path.join(work, 'live');
  const live = startWithUrl(['sim', scenario, '--out', liveOut, '--force', '--quiet', '--live', '--port', '0']);
  const liveAddress = await live.urlOf;
  const livePage = await openViewer(liveAddress);
  await waitFor(livePage, () => window.starnav.state.liveSteps >= 20, 'live steps', 120000);
  const stillRunning = live.child.exitCode === null;
  const got = await livePage.evaluate(() => window.starnav.state.liveSteps);
  check(stillRunning && got >= 20, 'live steps arrive while the simulation runs', `${got} steps`);
  const liveCode = await live.exited;
  check(liveCode === 0, 'sim --live exits 0', live.output().slice(-300));
  await waitFor(livePage, () => window.starnav.state.liveEnded, 'the end event', 30000);
  const liveState = await livePage.evaluate(() => window.starnav.state);
  check(liveState.liveSteps === stepLines.length, 'the live page received every step', `${liveState.liveSteps} of ${stepLines.length}`);
  await livePage.close();
  const files = fs.readdirSync(runDir).filter((f) => f !== 'timing.json' && fs.statSync(path.join(runDir, f)).isFile()).sort();
  const liveFiles = fs.readdirSync(liveOut).filter((f) => f !== 'timing.json' && fs.statSync(path.join(liveOut, f)).isFile()).sort();
  const same = files.length === liveFiles.length &&
    files.every((f, i) => f === liveFiles[i] && fs.readFileSync(path.join(runDir, f)).equals(fs.readFileSync(path.join(liveOut, f))));
  check(same, 'the records of the live run are the same bytes', `${files.length} files vs ${liveFiles.length}`);

  // ---- exported -------------------------------------------------------------------------------
  const html = path.join(work, 'e4.html');
  const exported = spawn(starnav, ['view', runDir, '--export', html, '--force'], { stdio: 'inherit' });
  const exportCode = await new Promise((resolve) => exported.on('exit', resolve));
  check(exportCode === 0, 'view --export exits 0');
  const filePage = await openViewer(url.pathToFileURL(html).href);
  await waitFor(filePage, () => window.starnav.state.loaded, 'the exported steps');
  const exportedState = await filePage.evaluate(() => window.starnav.state);
  check(exportedState.pathCount === metrics.plans && exportedState.stepsLoaded === stepLines.length,
    'the exported page opens from a file URL with every path and step', `${exportedState.pathCount} paths, ${exportedState.stepsLoaded} steps`);
  await filePage.close();
} catch (e) {
  check(false, 'browser test', e.stack || String(e));
} finally {
  await browser.close();
}
console.log(failures === 0 ? 'all browser checks passed' : `${failures} browser check(s) failed`);
process.exit(failures === 0 ? 0 : 1);
