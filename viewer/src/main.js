// starnav's viewer: a run record (docs/run-records.md) in 3D with a timeline. Served by
// `starnav view RUN_DIR`, exported into one page by `starnav view RUN_DIR --export`, or fed live
// by `starnav sim SCENARIO --live`. window.starnav is the page's state for tests and scripts.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

import { checkVersion, OccupancyTimeline, parseTrajectory, RunSource, Steps } from './data.js';
import {
  COLOURS, cssColour, DynamicPoints, goalMarker, groundOf, lineOf, NavMapLayer, obstacleColour, Obstacles, pathColour, poseArrow, Robot,
  Terrain,
} from './scene.js';

const LAYERS = ['terrain', 'map', 'obstacles', 'robot', 'hits', 'paths', 'trajectory', 'particles', 'estimate', 'loops'];

const state = {
  ready: false,
  error: null,
  live: false,
  liveSteps: 0,
  time: 0,
  duration: 0,
  playing: false,
  speed: 1,
  follow: true,
  topDown: false,
  camera: null,
  legend: [],
  stepIndex: -1,
  robot: null,
  pathCount: 0,
  pathsShown: 0,
  mapCells: 0,
  obstaclesShown: 0,
  hitsShown: 0,
  particlesShown: 0,
  stepsLoaded: 0,
  layers: Object.fromEntries(LAYERS.map((l) => [l, true])),
  firstFrameMs: null,
  frames: 0,
  lastFrameMs: 0,
};

function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'style') e.style.cssText = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else e.setAttribute(k, v);
  }
  for (const c of children) e.append(c);
  return e;
}

function fmt(v, d = 2) {
  return Number.isFinite(v) ? v.toFixed(d) : '-';
}

class Viewer {
  constructor(root) {
    this.root = root;
    this.source = new RunSource();
    // No multisampling: with software GL (SwiftShader, the usual case headless and on machines
    // without a GPU) it multiplies the cost of every pixel.
    this.renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0xdde6ee);
    this.canvas = this.renderer.domElement;
    this.canvas.id = 'view';
    root.append(this.canvas);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(50, 1, 0.05, 5000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.canvas);
    this.controls.addEventListener('start', () => {
      // Dragging the view lets the robot go.
      this.setFollow(false);
    });
    this.controls.addEventListener('change', () => {
      this.dirty = true;
    });
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667755, 1.6));
    const sun = new THREE.DirectionalLight(0xffffff, 1.4);
    sun.position.set(30, -40, 80);
    this.scene.add(sun);
    this.layers = Object.fromEntries(LAYERS.map((l) => [l, new THREE.Group()]));
    for (const g of Object.values(this.layers)) this.scene.add(g);
    this.pathLines = [];
    this.dirty = true;
    this.lastTick = performance.now();
    window.addEventListener('resize', () => this.resize());
  }

  resize() {
    const w = this.root.clientWidth;
    const h = this.root.clientHeight;
    this.renderer.setSize(w, h, false);
    this.canvas.style.width = `${w}px`;
    this.canvas.style.height = `${h}px`;
    this.camera.aspect = w / Math.max(1, h);
    this.camera.updateProjectionMatrix();
    this.dirty = true;
  }

  async load() {
    const t0 = performance.now();
    this.manifest = await this.source.json('run.json');
    checkVersion(this.manifest, 'run.json');
    state.live = !!this.manifest.live;
    this.world = await this.source.json('world.json');
    checkVersion(this.world, 'world.json');
    const files = new Set(this.manifest.files || []);
    this.metrics = files.has('metrics.json') ? await this.source.json('metrics.json') : null;
    this.buildWorld();
    // A trajectory.csv without the base's columns (3D SLAM writes the sensor's) is not drawn: the
    // steps' poses are.
    if (files.has('trajectory.csv')) this.trajectory = parseTrajectory(await this.source.text('trajectory.csv'));
    this.steps = new Steps();
    if (this.world.nav_map) {
      this.occupancy = new OccupancyTimeline(this.world.nav_map, this.steps);
      this.navMap = new NavMapLayer(this.world.nav_map, this.baseZ);
      this.navMap.update(this.occupancy.cells, null);
      this.layers.map.add(this.navMap.mesh);
    }
    // Times in the record are the run's clock (a log's for SLAM runs, from start_s); the
    // timeline and the page's state count from the start.
    state.start = this.manifest.start_s || 0;
    state.duration = this.manifest.duration_s || 0;
    this.buildUi();
    this.resize();
    this.frameCamera();
    this.buildTrajectory();
    this.setTime(0);
    this.firstLook();
    this.updateLegend();
    this.render();
    state.firstFrameMs = performance.now() - t0;
    state.ready = true;
    this.loop();
    if (files.has('steps.jsonl')) {
      await this.source.lines('steps.jsonl', (lines) => this.addSteps(lines));
    }
    if (state.live) this.connectLive();
    state.stepsLoaded = this.steps.count;
    state.loaded = true;
    this.dirty = true;
  }

  addSteps(lines) {
    for (const l of lines) this.steps.add(l);
    if (!this.hits || this.hits.capacity < this.steps.maxHits) {
      if (this.hits) this.layers.hits.remove(this.hits.points);
      this.hits = new DynamicPoints('hits', COLOURS.hits, 3, Math.max(1024, this.steps.maxHits * 2));
      this.layers.hits.add(this.hits.points);
    }
    if (this.steps.maxParticles > 0 && (!this.particles || this.particles.capacity < this.steps.maxParticles)) {
      if (this.particles) this.layers.particles.remove(this.particles.points);
      this.particles = new DynamicPoints('particles', COLOURS.particles, 3, this.steps.maxParticles);
      this.layers.particles.add(this.particles.points);
    }
    for (const p of this.steps.paths.slice(this.pathLines.length)) {
      const line = lineOf(p.points, (x, y) => this.groundZ(x, y) + 0.05, pathColour(p.id));
      line.name = `P${p.id}`;
      line.userData = p;
      this.layers.paths.add(line);
      this.pathLines.push(line);
    }
    if (this.steps.loops.length !== (this.loopCount || 0)) this.buildLoops();
    if (!this.trajectory && this.steps.count > 0) this.buildStepTrajectory();
    if (this.steps.hasEstimate && !this.estimateArrow) {
      this.estimateArrow = poseArrow(COLOURS.estimate);
      this.layers.estimate.add(this.estimateArrow);
    }
    if (this.steps.hasReference && !this.referenceArrow) {
      this.referenceArrow = poseArrow(COLOURS.reference);
      this.layers.estimate.add(this.referenceArrow);
    }
    if (this.occupancy) this.occupancy.checkpoint();
    state.pathCount = this.pathLines.length;
    state.stepsLoaded = this.steps.count;
    if (!this.trajectory && this.steps.count > 0) {
      const last = this.steps.time(this.steps.count - 1) - state.start;
      state.duration = Math.max(state.duration, last);
      this.scrubber.max = String(state.duration);
    }
    if (state.live) {
      state.liveSteps = this.steps.count;
      this.setTime(this.steps.time(this.steps.count - 1) - state.start);
    } else {
      // The page shows the state at its time: paths planned later, the map's later changes and
      // later loop closures stay hidden as the steps arrive.
      this.setTime(state.time);
    }
    this.updateLegend();
    this.dirty = true;
  }

  // Loop closures (SLAM runs): one segment set in time order, drawn up to the current time.
  buildLoops() {
    const loops = this.steps.loops;
    const pos = new Float32Array(loops.length * 6);
    loops.forEach((l, i) => pos.set([l.segment[0], l.segment[1], 0.05, l.segment[2], l.segment[3], 0.05], 6 * i));
    if (this.loopLines) this.layers.loops.remove(this.loopLines);
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    this.loopLines = new THREE.LineSegments(geo, new THREE.LineBasicMaterial({ color: COLOURS.loops, transparent: true, opacity: 0.5 }));
    this.loopLines.name = 'loop_closures';
    this.loopLines.frustumCulled = false;
    this.layers.loops.add(this.loopLines);
    this.loopCount = loops.length;
  }

  // Without trajectory.csv (a live run): the executed path from the steps' poses, appended as
  // they arrive into a buffer that doubles when full (a live run adds one step at a time).
  buildStepTrajectory() {
    const n = this.steps.count;
    if (!this.trajLine || this.trajCapacity < n) {
      this.trajCapacity = Math.max(1024, 2 * n);
      this.trajFilled = 0;
      if (this.trajLine) this.layers.trajectory.remove(this.trajLine);
      const geo = new THREE.BufferGeometry();
      geo.setAttribute('position', new THREE.BufferAttribute(new Float32Array(this.trajCapacity * 3), 3));
      this.trajLine = new THREE.Line(geo, new THREE.LineBasicMaterial({ color: COLOURS.trajectory }));
      this.trajLine.name = 'trajectory';
      this.trajLine.frustumCulled = false;
      this.trajFromSteps = true;
      this.layers.trajectory.add(this.trajLine);
    }
    const attr = this.trajLine.geometry.getAttribute('position');
    const p = this.steps.pose.data;
    for (let i = this.trajFilled; i < n; ++i) attr.setXYZ(i, p[6 * i], p[6 * i + 1], p[6 * i + 2] + 0.03);
    this.trajFilled = n;
    attr.needsUpdate = true;
  }

  groundZ(x, y) {
    if (this.terrain) {
      const z = this.terrain.heightAt(x, y);
      if (Number.isFinite(z)) return z;
    }
    return this.baseZ;
  }

  buildWorld() {
    const w = this.world;
    this.baseZ = 0;
    this.span = 10;
    if (w.terrain) {
      this.terrain = new Terrain(w.terrain);
      this.baseZ = this.terrain.lo;
      this.layers.terrain.add(this.terrain.mesh);
    } else {
      this.layers.terrain.add(groundOf(this.worldBox()));
    }
    this.obstacles = new Obstacles(w.obstacles || []);
    this.layers.obstacles.add(this.obstacles.group);
    this.robot = new Robot(w.robot);
    this.layers.robot.add(this.robot.group);
    for (const g of w.goals || []) this.layers.paths.add(goalMarker(g[0], g[1], this.groundZ(g[0], g[1])));
  }

  buildTrajectory() {
    const tr = this.trajectory;
    if (!tr) return;
    const pts = new Float32Array(tr.count * 2);
    for (let i = 0; i < tr.count; ++i) {
      pts[2 * i] = tr.pose[6 * i];
      pts[2 * i + 1] = tr.pose[6 * i + 1];
    }
    const zs = new Float32Array(tr.count);
    for (let i = 0; i < tr.count; ++i) zs[i] = tr.pose[6 * i + 2];
    let k = 0;
    this.trajLine = lineOf(pts, () => zs[k++] + 0.03, COLOURS.trajectory, 2);
    this.trajLine.name = 'trajectory';
    this.layers.trajectory.add(this.trajLine);
  }

  // The region the run is about: start, goals, the trajectory (once read), obstacles and the
  // navigator's grid. A terrain larger than that does not widen it.
  worldBox() {
    const box = new THREE.Box3();
    const add = (x, y, z = this.baseZ || 0) => box.expandByPoint(new THREE.Vector3(x, y, z));
    const w = this.world;
    add(w.start[0], w.start[1], this.groundZ(w.start[0], w.start[1]));
    for (const g of w.goals || []) add(g[0], g[1], this.groundZ(g[0], g[1]));
    const tr = this.trajectory;
    if (tr) for (let i = 0; i < tr.count; i += Math.max(1, Math.floor(tr.count / 2000))) add(tr.pose[6 * i], tr.pose[6 * i + 1], tr.pose[6 * i + 2]);
    for (const o of w.obstacles || []) {
      for (const p of o.parts.length > 2000 ? o.parts.filter((_, i) => i % Math.ceil(o.parts.length / 2000) === 0) : o.parts) {
        add(p[1], p[2], p[3]);
      }
    }
    if (w.nav_map) {
      const m = w.nav_map;
      const [ox, oy, yaw] = m.origin;
      const sx = m.width * m.resolution_m;
      const sy = m.height * m.resolution_m;
      for (const [gx, gy] of [[0, 0], [sx, 0], [0, sy], [sx, sy]])
        add(ox + Math.cos(yaw) * gx - Math.sin(yaw) * gy, oy + Math.sin(yaw) * gx + Math.cos(yaw) * gy);
    }
    return box;
  }

  // The overview: the whole region from the south-south-west, looking down at about 40 degrees.
  frameCamera() {
    const box = this.worldBox();
    const size = box.getSize(new THREE.Vector3());
    const c = box.getCenter(new THREE.Vector3());
    const r = Math.max(size.x, size.y, 4) * 1.05;
    this.span = r;
    this.overview = { target: c, position: new THREE.Vector3(c.x - 0.2 * r, c.y - 0.85 * r, c.z + 0.75 * r) };
    this.camera.position.copy(this.overview.position);
    this.controls.target.copy(c);
    this.camera.far = Math.max(100, 10 * r);
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  // The first look: on the robot where the run starts, following it, from the south-south-west
  // and above, close enough to see what it sees (half the region, 4 to 15 m across the view's
  // height), so that the first thing on screen is the robot in the state at t = 0.
  firstLook() {
    const r = state.robot;
    if (!r) return;
    const half = Math.min(15, Math.max(4, 0.5 * this.span)) / 2;
    const d = half / Math.tan((this.camera.fov * Math.PI) / 360);
    this.controls.target.set(r.x, r.y, r.z);
    this.camera.position.copy(this.controls.target).add(new THREE.Vector3(-0.15, -0.6, 0.85).setLength(d));
    this.setFollow(true);
    this.controls.update();
  }

  // Straight down on the current target, north up (x to the right, y up the screen, as a map is
  // read), at the same distance; the view can still be turned about the vertical and zoomed. Off:
  // back to the oblique view it came from.
  setTopDown(on) {
    const target = this.controls.target.clone();
    const d = this.camera.position.distanceTo(target);
    if (on && !state.topDown) {
      this.obliqueOffset = this.camera.position.clone().sub(target);
      this.camera.position.set(target.x, target.y - 1e-4 * d, target.z + d);
      this.controls.minPolarAngle = 0;
      this.controls.maxPolarAngle = 0;
    } else if (!on && state.topDown) {
      const offset = (this.obliqueOffset || new THREE.Vector3(-0.15, -0.6, 0.85)).clone().setLength(d);
      this.controls.minPolarAngle = 0;
      this.controls.maxPolarAngle = Math.PI;
      this.camera.position.copy(target).add(offset);
    }
    state.topDown = on;
    if (this.topDownButton) {
      this.topDownButton.textContent = on ? '3D view' : 'top-down view';
      this.topDownButton.setAttribute('aria-pressed', String(on));
    }
    this.controls.update();
    this.dirty = true;
  }

  // The legend: a swatch and a name for every layer this run draws (what the steps bring is added
  // as they arrive).
  updateLegend() {
    if (!this.legend) return;
    const entries = [];
    // colour: one colour, or for a ramp or a set a list drawn side by side in the swatch.
    const add = (layer, label, colour, style = 'box') =>
      entries.push({ layer, label, colour: (style === 'ramp' || style === 'set' ? colour : [colour]).map(cssColour), style });
    const slam = this.manifest.kind === 'slam' || this.manifest.kind === 'slam3d';
    add('robot', this.manifest.log ? 'robot (the estimated pose)' : 'robot (true pose)', COLOURS.robot);
    if (this.trajLine) add('trajectory', slam ? 'trajectory (optimised)' : 'executed trajectory', COLOURS.trajectory, 'line');
    if (this.pathLines.length)
      add('paths', this.pathLines.length === 1 ? 'planned path P1' : `planned paths P1..P${this.pathLines.length} (current solid, earlier faded)`,
        pathColour(1), 'line');
    if ((this.world.goals || []).length) add('paths', 'goal', COLOURS.goal);
    if (this.navMap) {
      const occupied = { navigation: 'map: blocked for planning', localization: 'known map: occupied' }[this.manifest.kind] || 'map: occupied';
      add('map', occupied, COLOURS.blocked);
      add('map', 'map: observed free (unknown: clear)', COLOURS.free);
    }
    if (this.terrain) add('terrain', 'terrain, low to high', [COLOURS.terrainLow, COLOURS.terrainHigh], 'ramp');
    const obstacles = this.world.obstacles || [];
    if (obstacles.some((o) => o.parts.filter((p) => p[0] === 'box').length > 32)) add('obstacles', 'walls (the map\'s occupied cells)', COLOURS.walls);
    if (obstacles.some((o) => o.parts.filter((p) => p[0] === 'box').length <= 32))
      add('obstacles', 'obstacles, each its colour', [0, 1, 2].map(obstacleColour), 'set');
    if (this.hits && this.steps.maxHits > 0) add('hits', 'LiDAR returns, current scan', COLOURS.hits, 'dot');
    if (this.particles) add('particles', 'particles', COLOURS.particles, 'dot');
    if (this.estimateArrow) add('estimate', 'estimate', COLOURS.estimate, 'arrow');
    if (this.referenceArrow) add('estimate', 'corrected pose (reference)', COLOURS.reference, 'arrow');
    if (this.loopLines) add('loops', 'loop closures', COLOURS.loops, 'line');
    const key = entries.map((e) => e.label).join('|');
    if (key === this.legendKey) return;
    this.legendKey = key;
    state.legend = entries.map(({ layer, label, colour }) => ({ layer, label, colours: colour }));
    const swatch = (e) => {
      const css = { box: 'width:12px;height:12px', ramp: 'width:24px;height:12px', set: 'width:24px;height:12px', line: 'width:16px;height:3px',
        dot: 'width:6px;height:6px;border-radius:3px;margin:0 5px', arrow: 'width:14px;height:4px' }[e.style];
      const stops = e.style === 'set' ? e.colour.map((c, i) => `${c} ${(100 * i) / e.colour.length}% ${(100 * (i + 1)) / e.colour.length}%`) : e.colour;
      const background = e.colour.length > 1 ? `linear-gradient(90deg,${stops.join(',')})` : e.colour[0];
      return el('span', { class: 'swatch', style: `display:inline-block;vertical-align:middle;margin-right:6px;${css};background:${background}` });
    };
    this.legend.replaceChildren(
      el('b', {}, 'legend'),
      ...entries.map((e) => el('div', { class: 'legend-entry', 'data-layer': e.layer }, swatch(e), e.label)),
    );
  }

  // A close view behind and above the robot, following it.
  closeUp() {
    const r = state.robot;
    if (!r) return;
    this.setTopDown(false);
    const d = Math.max(2.5, 6 * (this.world.robot.body_length_m || 0.5));
    this.controls.target.set(r.x, r.y, r.z);
    this.camera.position.set(r.x - d * Math.cos(r.yaw) * 0.8, r.y - d * Math.sin(r.yaw) * 0.8 - 0.3 * d, r.z + d);
    this.setFollow(true);
  }

  // The robot's true pose at time t: the trajectory (interpolated), or the steps' poses.
  poseAt(t) {
    const tr = this.trajectory;
    if (tr && tr.count > 0) {
      let lo = 0;
      let hi = tr.count - 1;
      if (t <= tr.t[0]) hi = 0;
      while (lo < hi) {
        const mid = (lo + hi + 1) >> 1;
        if (tr.t[mid] <= t) lo = mid;
        else hi = mid - 1;
      }
      const i = lo;
      const p = Array.from(tr.pose.subarray(6 * i, 6 * i + 6));
      const v = Array.from(tr.speed.subarray(3 * i, 3 * i + 3));
      return { index: i, pose: p, speed: v };
    }
    const k = this.steps ? this.steps.indexAt(t) : -1;
    if (k < 0) {
      const s = this.world.start;
      return { index: -1, pose: [s[0], s[1], this.groundZ(s[0], s[1]), 0, 0, s[2]], speed: [0, 0, 0] };
    }
    return { index: k, pose: Array.from(this.steps.pose.data.subarray(6 * k, 6 * k + 6)), speed: [NaN, NaN, NaN] };
  }

  setTime(tau) {
    tau = Math.max(0, Math.min(state.duration || 0, tau));
    state.time = tau;
    const t = tau + state.start;
    const { index, pose, speed } = this.poseAt(t);
    this.robot.set(...pose);
    state.robot = { x: pose[0], y: pose[1], z: pose[2], roll: pose[3], pitch: pose[4], yaw: pose[5] };
    state.speed_mps = Math.hypot(speed[0], speed[1]);
    state.obstaclesShown = this.obstacles.update(t);
    if (this.trajLine) this.trajLine.geometry.setDrawRange(0, (this.trajFromSteps ? this.steps.indexAt(t) : index) + 1);
    if (this.loopLines) {
      let n = 0;
      while (n < this.steps.loops.length && this.steps.loops[n].t <= t) ++n;
      this.loopLines.geometry.setDrawRange(0, 2 * n);
      state.loopsShown = n;
    }
    const k = this.steps ? this.steps.indexAt(t) : -1;
    state.stepIndex = k;
    if (this.hits) state.hitsShown = k >= 0 ? this.hits.set(this.steps.hitsOf(k)) : this.hits.set([]);
    if (this.particles)
      state.particlesShown = k >= 0 ? this.particles.set(this.steps.particlesOf(k), 3, (x, y) => this.groundZ(x, y) + 0.04) : 0;
    if (this.estimateArrow && k >= 0) {
      const e = this.steps.estimate.data.subarray(3 * k, 3 * k + 3);
      this.estimateArrow.visible = Number.isFinite(e[0]);
      if (this.estimateArrow.visible) {
        this.estimateArrow.position.set(e[0], e[1], this.groundZ(e[0], e[1]) + 0.45);
        this.estimateArrow.rotation.z = e[2];
        state.estimate = { x: e[0], y: e[1], yaw: e[2] };
      }
    }
    if (this.referenceArrow && k >= 0) {
      const e = this.steps.reference.data.subarray(3 * k, 3 * k + 3);
      this.referenceArrow.visible = Number.isFinite(e[0]);
      state.reference = this.referenceArrow.visible ? { x: e[0], y: e[1], yaw: e[2] } : null;
      if (this.referenceArrow.visible) {
        this.referenceArrow.position.set(e[0], e[1], this.groundZ(e[0], e[1]) + 0.5);
        this.referenceArrow.rotation.z = e[2];
      }
    }
    // Paths planned so far; the current one bold, the earlier ones faded.
    const current = k >= 0 ? this.steps.pathId.data[k] : 0;
    let shown = 0;
    for (const line of this.pathLines) {
      const p = line.userData;
      line.visible = p.t <= t;
      if (line.visible) ++shown;
      line.material.opacity = p.id === current ? 1 : 0.45;
      line.material.transparent = p.id !== current;
    }
    state.pathsShown = shown;
    state.currentPath = current;
    if (this.occupancy) {
      this.occupancy.seek(k);
      if (this.occupancy.changedSince.length) {
        this.navMap.update(this.occupancy.cells, this.occupancy.changedSince);
        this.occupancy.changedSince = [];
      }
      state.mapCells = this.navMap.known;
    }
    if (this.scrubber && document.activeElement !== this.scrubber) this.scrubber.value = String(tau);
    this.updatePanel();
    this.dirty = true;
  }

  setFollow(on) {
    state.follow = on;
    if (this.followBox) this.followBox.checked = on;
    this.dirty = true;
  }

  setLayer(name, on) {
    if (!(name in this.layers)) throw new Error(`no layer ${name}`);
    state.layers[name] = on;
    this.layers[name].visible = on;
    const box = document.getElementById(`layer-${name}`);
    if (box) box.checked = on;
    this.dirty = true;
  }

  updatePanel() {
    if (!this.panel) return;
    const r = state.robot;
    const m = this.metrics || {};
    const rows = [
      ['run', `${this.manifest.scenario ? this.manifest.scenario.name : this.manifest.log ? `${this.manifest.log.name}, ${this.manifest.log.method}` : ''} (${this.manifest.kind})`],
      ['time', `${fmt(state.time)} / ${fmt(state.duration)} s`],
      ['pose', r ? `x ${fmt(r.x)} y ${fmt(r.y)} z ${fmt(r.z)} m, yaw ${fmt((r.yaw * 180) / Math.PI, 1)}°` : '-'],
      ['speed', `${fmt(state.speed_mps)} m/s`],
      ['step', `${state.stepIndex + 1} / ${this.steps ? this.steps.count : 0}`],
      ['path', state.currentPath ? `P${state.currentPath} (${state.pathsShown} of ${state.pathCount} planned)` : '-'],
    ];
    // Against the truth: the simulator's pose, or on a log the corrected pose where there is one.
    const truth = this.steps && this.steps.hasReference ? state.reference : r;
    if (state.estimate && truth) rows.push(['estimate error', `${fmt(Math.hypot(state.estimate.x - truth.x, state.estimate.y - truth.y), 3)} m`]);
    if (m.outcome !== undefined) rows.push(['outcome', `${m.outcome}, ${fmt(m.distance_m)} m, ${m.plans} plans, ${m.collisions} collisions`]);
    if (this.steps && this.steps.loops.length) rows.push(['loop closures', `${state.loopsShown || 0} of ${this.steps.loops.length}`]);
    if (state.live) rows.push(['live', `${state.liveSteps} steps received${state.liveEnded ? ' (ended)' : ''}`]);
    this.panel.replaceChildren(
      ...rows.map(([k, v]) => el('div', {}, el('b', {}, `${k}: `), v)),
    );
  }

  buildUi() {
    const css = 'position:absolute;background:rgba(255,255,255,0.85);font:12px sans-serif;padding:6px;border-radius:4px';
    this.panel = el('div', { id: 'panel', style: `${css};left:8px;top:8px;max-width:420px` });
    const layerBoxes = LAYERS.map((name) =>
      el('label', { style: 'margin-right:6px;white-space:nowrap' },
        el('input', { type: 'checkbox', id: `layer-${name}`, checked: '', onchange: (e) => this.setLayer(name, e.target.checked) }),
        name),
    );
    this.followBox = el('input', { type: 'checkbox', id: 'follow', checked: '', onchange: (e) => this.setFollow(e.target.checked) });
    this.topDownButton = el('button', { id: 'top-down', 'aria-pressed': 'false', title: 'look straight down, north up (key T)', onclick: () => this.setTopDown(!state.topDown) }, 'top-down view');
    const overviewButton = el('button', { id: 'overview', title: 'the whole run from above and aside', onclick: () => window.starnav.overview() }, 'overview');
    const layers = el('div', { id: 'layers', style: `${css};right:8px;top:8px;max-width:260px` },
      ...layerBoxes, el('br'), el('label', {}, this.followBox, 'camera follows the robot'), el('br'), this.topDownButton, ' ', overviewButton);
    this.legend = el('div', { id: 'legend', style: `${css};left:8px;bottom:52px;max-width:320px;line-height:18px` });
    window.addEventListener('keydown', (e) => {
      if ((e.key === 't' || e.key === 'T') && !(e.target instanceof HTMLInputElement || e.target instanceof HTMLSelectElement)) this.setTopDown(!state.topDown);
    });
    this.playButton = el('button', { id: 'play', onclick: () => this.togglePlay() }, 'play');
    const speed = el('select', { id: 'speed', onchange: (e) => { state.speed = +e.target.value; } },
      ...[0.25, 0.5, 1, 2, 5, 10, 20].map((v) => {
        const o = el('option', { value: String(v) }, `${v}x`);
        if (v === 1) o.selected = true;
        return o;
      }));
    const stepBy = (d) => () => {
      const k = Math.max(0, Math.min((this.steps ? this.steps.count : 1) - 1, state.stepIndex + d));
      this.setTime(this.steps && this.steps.count ? this.steps.time(k) - state.start : state.time + d * 0.1);
    };
    this.scrubber = el('input', {
      type: 'range', id: 'scrubber', min: '0', max: String(state.duration), step: 'any', value: '0',
      style: 'flex:1', oninput: (e) => this.setTime(+e.target.value),
    });
    const bar = el('div', { id: 'timeline', style: `${css};left:8px;right:8px;bottom:8px;display:flex;gap:6px;align-items:center` },
      el('button', { id: 'step-back', onclick: stepBy(-1) }, '◀'), this.playButton,
      el('button', { id: 'step-forward', onclick: stepBy(1) }, '▶'), speed, this.scrubber);
    this.root.append(this.panel, layers, this.legend, bar);
  }

  togglePlay() {
    state.playing = !state.playing;
    if (state.playing && state.time >= state.duration) this.setTime(0);
    this.playButton.textContent = state.playing ? 'pause' : 'play';
    this.lastTick = performance.now();
  }

  connectLive() {
    const source = new EventSource('events');
    source.addEventListener('step', (e) => this.addSteps([e.data]));
    source.addEventListener('end', () => {
      state.liveEnded = true;
      source.close();
      this.updatePanel();
    });
  }

  // The camera for the current state: over the robot when following it.
  updateCamera() {
    if (state.follow && state.robot) {
      const r = state.robot;
      const target = new THREE.Vector3(r.x, r.y, r.z);
      const offset = this.camera.position.clone().sub(this.controls.target);
      this.controls.target.copy(target);
      this.camera.position.copy(target).add(offset);
    }
    this.controls.update();
    this.camera.updateMatrixWorld();
  }

  render() {
    this.updateCamera();
    const p = this.camera.position;
    const t = this.controls.target;
    state.camera = { x: p.x, y: p.y, z: p.z, target: { x: t.x, y: t.y, z: t.z } };
    const t0 = performance.now();
    this.renderer.render(this.scene, this.camera);
    state.lastFrameMs = performance.now() - t0;
    state.frames += 1;
    this.dirty = false;
  }

  loop() {
    const tick = (now) => {
      const dt = (now - this.lastTick) / 1000;
      this.lastTick = now;
      if (state.playing) {
        const next = state.time + dt * state.speed;
        this.setTime(next);
        if (next >= state.duration && !state.live) this.togglePlay();
      }
      // Only when something changed: an idle page costs nothing (software GL renders on the CPU).
      if (this.dirty) this.render();
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  }
}

async function main() {
  const root = document.getElementById('app');
  const viewer = new Viewer(root);
  window.starnav = {
    state,
    setTime: (t) => viewer.setTime(t),
    setLayer: (name, on) => viewer.setLayer(name, on),
    setFollow: (on) => viewer.setFollow(on),
    setTopDown: (on) => {
      viewer.setTopDown(on);
      viewer.render();
    },
    play: () => { if (!state.playing) viewer.togglePlay(); },
    pause: () => { if (state.playing) viewer.togglePlay(); },
    // Renders now and returns the frame's time in ms (benchmarks and tests).
    renderNow: () => {
      const t0 = performance.now();
      viewer.render();
      return performance.now() - t0;
    },
    // Screen position (CSS pixels) of a world point, seen by the camera the next frame draws with
    // (not the last frame's: a follow set since then has not moved it yet).
    project: (x, y, z) => {
      viewer.updateCamera();
      const v = new THREE.Vector3(x, y, z).project(viewer.camera);
      return [((v.x + 1) / 2) * viewer.canvas.clientWidth, ((1 - v.y) / 2) * viewer.canvas.clientHeight];
    },
    // The canvas scaled to w x h pixels, as flat RGB (pixel checks in tests).
    thumbnail: (w = 64, h = 36) => {
      viewer.render();
      const c = document.createElement('canvas');
      c.width = w;
      c.height = h;
      const g = c.getContext('2d');
      g.drawImage(viewer.canvas, 0, 0, w, h);
      const d = g.getImageData(0, 0, w, h).data;
      const out = [];
      for (let i = 0; i < d.length; i += 4) out.push(d[i], d[i + 1], d[i + 2]);
      return out;
    },
    // Mean RGB of the canvas in a square of side 2r + 1 around (x, y) CSS pixels.
    sample: (x, y, r = 2) => {
      viewer.render();
      const scale = viewer.canvas.width / viewer.canvas.clientWidth;
      const c = document.createElement('canvas');
      const side = Math.max(1, Math.round((2 * r + 1) * scale));
      c.width = side;
      c.height = side;
      const g = c.getContext('2d');
      g.drawImage(viewer.canvas, Math.round((x - r) * scale), Math.round((y - r) * scale), side, side, 0, 0, side, side);
      const d = g.getImageData(0, 0, side, side).data;
      const m = [0, 0, 0];
      for (let i = 0; i < d.length; i += 4) for (let j = 0; j < 3; ++j) m[j] += d[i + j];
      return m.map((v) => v / (d.length / 4));
    },
    // Frame times (ms) of scrubbing to each time in `times`: the step's layers updated, drawn,
    // and the picture finished (a pixel read back waits for the GPU, here SwiftShader).
    scrubFrames: (times) => {
      const gl = viewer.renderer.getContext();
      const pixel = new Uint8Array(4);
      return times.map((t) => {
        const t0 = performance.now();
        viewer.setTime(t);
        viewer.render();
        gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
        return performance.now() - t0;
      });
    },
    overview: () => {
      viewer.setFollow(false);
      viewer.setTopDown(false);
      viewer.camera.position.copy(viewer.overview.position);
      viewer.controls.target.copy(viewer.overview.target);
      viewer.render();
    },
    closeUp: () => {
      viewer.closeUp();
      viewer.render();
    },
  };
  try {
    await viewer.load();
  } catch (e) {
    state.error = String(e.message || e);
    root.append(el('div', { id: 'error', style: 'position:absolute;left:20px;top:20px;color:#b00;font:16px sans-serif' }, state.error));
  }
}

main();
