// Reading a run record (docs/run-records.md) into compact typed arrays: a run of 10,000 sensor
// cycles must load by chunks and stay small in memory.

export const SUPPORTED_VERSION = 1;

// Where the run's files come from: the server (`starnav view`), or the page itself (`--export`).
export class RunSource {
  constructor() {
    const embedded = document.getElementById('starnav-run');
    this.embedded = embedded ? JSON.parse(embedded.textContent) : null;
  }
  has(name) {
    return this.embedded ? name in this.embedded : true;
  }
  async text(name) {
    if (this.embedded) {
      if (!(name in this.embedded)) throw new Error(`${name}: not in the exported page`);
      return this.embedded[name];
    }
    const r = await fetch(`run/${name}`);
    if (!r.ok) throw new Error(`${name}: HTTP ${r.status}`);
    return r.text();
  }
  async json(name) {
    return JSON.parse(await this.text(name));
  }
  // Calls onLines(lines) with whole lines as they arrive (a stream from the server; the embedded
  // text in slices), so a long run shows before it has all loaded.
  async lines(name, onLines) {
    if (this.embedded) {
      const text = this.embedded[name] || '';
      let start = 0;
      const slice = 1 << 20;
      while (start < text.length) {
        let end = Math.min(text.length, start + slice);
        const nl = text.indexOf('\n', end);
        end = nl < 0 ? text.length : nl + 1;
        onLines(text.slice(start, end).split('\n').filter((l) => l.length > 0));
        start = end;
        await new Promise((resolve) => setTimeout(resolve, 0));
      }
      return;
    }
    const r = await fetch(`run/${name}`);
    if (!r.ok) throw new Error(`${name}: HTTP ${r.status}`);
    const reader = r.body.getReader();
    const decoder = new TextDecoder();
    let rest = '';
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      rest += decoder.decode(value, { stream: true });
      const nl = rest.lastIndexOf('\n');
      if (nl >= 0) {
        onLines(rest.slice(0, nl).split('\n').filter((l) => l.length > 0));
        rest = rest.slice(nl + 1);
      }
    }
    rest += decoder.decode();
    if (rest.length > 0) onLines([rest]);
  }
}

// A growable typed array.
class Pool {
  constructor(Type, capacity = 1024) {
    this.Type = Type;
    this.data = new Type(capacity);
    this.length = 0;
  }
  reserve(n) {
    if (this.length + n <= this.data.length) return;
    let cap = this.data.length;
    while (cap < this.length + n) cap *= 2;
    const next = new this.Type(cap);
    next.set(this.data.subarray(0, this.length));
    this.data = next;
  }
  push(v) {
    this.reserve(1);
    this.data[this.length++] = v;
  }
  view() {
    return this.data.subarray(0, this.length);
  }
}

// trajectory.csv: t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,vx_mps,vy_mps,wz_radps
export function parseTrajectory(text) {
  const lines = text.split('\n');
  const header = lines[0].split(',');
  const col = (name) => header.indexOf(name);
  // A simulation's (t_s,x_m,y_m,z_m,roll_rad,pitch_rad,yaw_rad,vx_mps,vy_mps,wz_radps) or a SLAM
  // run's (t_s,x_m,y_m,yaw_rad): what is missing is zero.
  // Without t_s,x_m,y_m,yaw_rad it is not a base trajectory (3D SLAM's holds the sensor's poses as
  // quaternions): null, and the steps' poses are drawn instead.
  const cols = ['t_s', 'x_m', 'y_m', 'z_m', 'roll_rad', 'pitch_rad', 'yaw_rad', 'vx_mps', 'vy_mps', 'wz_radps'].map(col);
  if ([0, 1, 2, 6].some((i) => cols[i] < 0)) return null;
  const n = lines.length - 1;
  const t = new Float64Array(n);
  const pose = new Float32Array(n * 6);
  const speed = new Float32Array(n * 3);
  let k = 0;
  for (let i = 1; i < lines.length; ++i) {
    if (lines[i].length === 0) continue;
    const f = lines[i].split(',');
    t[k] = +f[cols[0]];
    for (let j = 0; j < 6; ++j) pose[k * 6 + j] = cols[1 + j] >= 0 ? +f[cols[1 + j]] : 0;
    for (let j = 0; j < 3; ++j) speed[k * 3 + j] = cols[7 + j] >= 0 ? +f[cols[7 + j]] : 0;
    ++k;
  }
  return { count: k, t: t.subarray(0, k), pose, speed };
}

// The per-cycle records of steps.jsonl, appended line by line.
export class Steps {
  constructor() {
    this.count = 0;
    this.t = new Pool(Float64Array);
    this.pose = new Pool(Float32Array);
    this.pathId = new Pool(Int32Array);
    this.hitStart = new Pool(Uint32Array);
    this.hits = new Pool(Float32Array, 1 << 16);
    this.changedStart = new Pool(Uint32Array);
    this.changed = new Pool(Int32Array, 1 << 14);
    this.estimate = new Pool(Float32Array);
    this.hasEstimate = false;
    this.reference = new Pool(Float32Array); // a log's corrected pose (localization on logs)
    this.hasReference = false;
    this.particleStart = new Pool(Uint32Array);
    this.particles = new Pool(Float32Array, 1 << 14);
    this.paths = []; // {id, t, points: Float32Array}
    this.loops = []; // {t, segment: [x1, y1, x2, y2]} (SLAM runs' loop closures)
    this.maxHits = 0;
    this.maxParticles = 0;
  }
  add(line) {
    const s = JSON.parse(line);
    this.t.push(s.t_s);
    const p = s.pose || [0, 0, 0, 0, 0, 0];
    for (let j = 0; j < 6; ++j) this.pose.push(p[j]);
    this.pathId.push(s.path_id || 0);
    this.hitStart.push(this.hits.length);
    const hits = s.hits || [];
    this.hits.reserve(hits.length * 3);
    for (const h of hits) {
      this.hits.data[this.hits.length++] = h[0];
      this.hits.data[this.hits.length++] = h[1];
      this.hits.data[this.hits.length++] = h[2];
    }
    this.maxHits = Math.max(this.maxHits, hits.length);
    this.changedStart.push(this.changed.length);
    const changed = s.changed || [];
    this.changed.reserve(changed.length * 3);
    for (const c of changed) {
      this.changed.data[this.changed.length++] = c[0];
      this.changed.data[this.changed.length++] = c[1];
      this.changed.data[this.changed.length++] = c[2];
    }
    const e = s.estimate;
    if (e) this.hasEstimate = true;
    this.estimate.push(e ? e[0] : NaN);
    this.estimate.push(e ? e[1] : NaN);
    this.estimate.push(e ? e[2] : NaN);
    const ref = s.reference;
    if (ref) this.hasReference = true;
    this.reference.push(ref ? ref[0] : NaN);
    this.reference.push(ref ? ref[1] : NaN);
    this.reference.push(ref ? ref[2] : NaN);
    this.particleStart.push(this.particles.length);
    const particles = s.particles || [];
    this.particles.reserve(particles.length * 3);
    for (const q of particles) {
      this.particles.data[this.particles.length++] = q[0];
      this.particles.data[this.particles.length++] = q[1];
      this.particles.data[this.particles.length++] = q[2];
    }
    this.maxParticles = Math.max(this.maxParticles, particles.length);
    for (const l of s.loop_closures || []) this.loops.push({ t: s.t_s, segment: l });
    if (s.path) {
      const pts = new Float32Array(s.path.length * 2);
      s.path.forEach((v, i) => {
        pts[2 * i] = v[0];
        pts[2 * i + 1] = v[1];
      });
      this.paths.push({ id: s.path_id, t: s.t_s, points: pts });
    }
    ++this.count;
  }
  time(i) {
    return this.t.data[i];
  }
  // The last step at or before time t (-1 before the first).
  indexAt(t) {
    let lo = 0;
    let hi = this.count - 1;
    if (this.count === 0 || t < this.t.data[0]) return -1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (this.t.data[mid] <= t) lo = mid;
      else hi = mid - 1;
    }
    return lo;
  }
  hitsOf(i) {
    const a = this.hitStart.data[i];
    const b = i + 1 < this.count ? this.hitStart.data[i + 1] : this.hits.length;
    return this.hits.data.subarray(a, b);
  }
  changedOf(i) {
    const a = this.changedStart.data[i];
    const b = i + 1 < this.count ? this.changedStart.data[i + 1] : this.changed.length;
    return this.changed.data.subarray(a, b);
  }
  particlesOf(i) {
    const a = this.particleStart.data[i];
    const b = i + 1 < this.count ? this.particleStart.data[i + 1] : this.particles.length;
    return this.particles.data.subarray(a, b);
  }
}

// The navigator's occupancy at any step: the initial grid, the changes replayed forward, and
// sparse checkpoints (the cells that differ from the initial grid) to go back cheaply.
export class OccupancyTimeline {
  constructor(navMap, steps) {
    this.width = navMap.width;
    this.height = navMap.height;
    this.initial = new Int8Array(this.width * this.height);
    const rle = navMap.initial || [];
    let k = 0;
    for (let i = 0; i + 1 < rle.length; i += 2) {
      this.initial.fill(rle[i], k, k + rle[i + 1]);
      k += rle[i + 1];
    }
    this.cells = this.initial.slice();
    this.steps = steps;
    this.at = -1; // the cells hold the state after step `at`
    this.checkpoints = []; // {step, diff: Int32Array of index,value pairs}
    this.every = 256;
    this.changedSince = []; // indices touched since the last draw
  }
  // Checkpoints as steps arrive (only where replay would go far).
  checkpoint() {
    const last = this.checkpoints.length ? this.checkpoints[this.checkpoints.length - 1].step : -1;
    const target = last + this.every;
    if (this.steps.count <= target) return;
    this.seek(target);
    const diff = [];
    for (let i = 0; i < this.cells.length; ++i) if (this.cells[i] !== this.initial[i]) diff.push(i, this.cells[i]);
    this.checkpoints.push({ step: target, diff: Int32Array.from(diff) });
  }
  apply(step) {
    const c = this.steps.changedOf(step);
    for (let j = 0; j < c.length; j += 3) {
      const idx = c[j + 1] * this.width + c[j];
      this.cells[idx] = c[j + 2];
      this.changedSince.push(idx);
    }
  }
  // Brings the grid to the state after step s (-1: the initial grid): back, or forward far past
  // a checkpoint (more than two intervals: replaying is cheaper for less), from the last
  // checkpoint at or before s; forward otherwise by replaying.
  seek(s) {
    if (s === this.at) return;
    let cp = null;
    for (const c of this.checkpoints) if (c.step <= s) cp = c;
    if (s < this.at || (cp && cp.step - this.at > 2 * this.every)) {
      // Back to the checkpoint (or the initial grid): every cell that differs is reset.
      for (let i = 0; i < this.cells.length; ++i) {
        if (this.cells[i] !== this.initial[i]) {
          this.cells[i] = this.initial[i];
          this.changedSince.push(i);
        }
      }
      this.at = -1;
      if (cp) {
        for (let j = 0; j < cp.diff.length; j += 2) {
          this.cells[cp.diff[j]] = cp.diff[j + 1];
          this.changedSince.push(cp.diff[j]);
        }
        this.at = cp.step;
      }
    }
    for (let k = this.at + 1; k <= s; ++k) this.apply(k);
    this.at = s;
  }
}

export function checkVersion(doc, name) {
  if (!doc || typeof doc.version !== 'number') throw new Error(`${name}: no schema version`);
  if (doc.version > SUPPORTED_VERSION)
    throw new Error(`${name}: schema version ${doc.version} is newer than this viewer's (${SUPPORTED_VERSION})`);
}
