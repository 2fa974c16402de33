// The 3D layers of a run: terrain, the navigator's map, obstacles over time, the robot, LiDAR hits,
// planned paths, the executed trajectory, particles and the estimate beside the truth. World frame
// as in starnav (REP-103): x east, y north, z up.
import * as THREE from 'three';

const PATH_COLOURS = [0x1f77b4, 0xff7f0e, 0x2ca02c, 0x9467bd, 0x8c564b, 0xe377c2, 0x17becf, 0xbcbd22];

// Every colour a layer draws in, in one place: the layers and the legend read them from here.
export const COLOURS = {
  robot: 0xf2c200,
  trajectory: 0x111111,
  goal: 0xd62728,
  hits: 0xc51b7d, // magenta: distinct from the map's red blocked cells the hits often lie on
  blocked: 0xc82828,
  free: 0xdeded0,
  walls: 0x8c8c96,
  estimate: 0x1f77b4,
  reference: 0xff7f0e,
  particles: 0x1f77b4,
  loops: 0xd55e00,
  ground: 0xc9c9bd,
  grid: 0xb4b4aa,
  terrainLow: [0.22, 0.45, 0.25],
  terrainHigh: [0.85, 0.82, 0.78],
};

// A CSS colour of a colour here: 0xRRGGBB or [r, g, b] in 0..1.
export function cssColour(c) {
  if (Array.isArray(c)) return `rgb(${c.map((v) => Math.round(255 * v)).join(',')})`;
  return `#${c.toString(16).padStart(6, '0')}`;
}

// The colour of the k-th obstacle of a world (walls of a map_server map are COLOURS.walls).
export function obstacleColour(k) {
  return new THREE.Color().setHSL((0.08 + 0.13 * k) % 1, 0.35, 0.55).getHex();
}

function heightColour(h, lo, hi, out) {
  // Green lowlands to brown and pale highs, as hypsometric maps colour them.
  const u = hi > lo ? Math.min(1, Math.max(0, (h - lo) / (hi - lo))) : 0.5;
  const stops = [
    [0.0, COLOURS.terrainLow],
    [0.5, [0.62, 0.58, 0.38]],
    [1.0, COLOURS.terrainHigh],
  ];
  let a = stops[0];
  let b = stops[stops.length - 1];
  for (let i = 0; i + 1 < stops.length; ++i)
    if (u >= stops[i][0] && u <= stops[i + 1][0]) {
      a = stops[i];
      b = stops[i + 1];
    }
  const f = b[0] > a[0] ? (u - a[0]) / (b[0] - a[0]) : 0;
  for (let j = 0; j < 3; ++j) out[j] = a[1][j] + f * (b[1][j] - a[1][j]);
}

// Grid (ix, iy) -> world of a starnav grid geometry {origin: [x, y, yaw], resolution_m}.
function gridToWorld(g, gx, gy) {
  const [ox, oy, yaw] = g.origin;
  const c = Math.cos(yaw);
  const s = Math.sin(yaw);
  return [ox + c * gx - s * gy, oy + s * gx + c * gy];
}

// The most mesh vertices per side: software GL draws every triangle on the CPU, and a finer mesh
// than the screen shows costs frame time for nothing (heights are still read at full detail).
const MESH_MAX_SIDE = 128;

export class Terrain {
  constructor(t) {
    this.t = t;
    const k = Math.max(1, Math.ceil(Math.max(t.samples_x, t.samples_y) / MESH_MAX_SIDE));
    const w = Math.ceil(t.samples_x / k);
    const h = Math.ceil(t.samples_y / k);
    const heights = [];
    for (let iy = 0; iy < h; ++iy) for (let ix = 0; ix < w; ++ix) heights.push(t.heights[iy * k * t.samples_x + ix * k]);
    let lo = Infinity;
    let hi = -Infinity;
    for (const v of t.heights)
      if (v !== null) {
        lo = Math.min(lo, v);
        hi = Math.max(hi, v);
      }
    if (!Number.isFinite(lo)) lo = hi = 0;
    this.lo = lo;
    this.hi = hi;
    const pos = new Float32Array(w * h * 3);
    const col = new Float32Array(w * h * 3);
    const rgb = [0, 0, 0];
    for (let iy = 0; iy < h; ++iy)
      for (let ix = 0; ix < w; ++ix) {
        const k = iy * w + ix;
        // Sample (ix k, iy k) is cell (ix k stride, iy k stride): its centre.
        const [x, y] = gridToWorld(t, (ix * k * t.stride + 0.5) * t.resolution_m, (iy * k * t.stride + 0.5) * t.resolution_m);
        const z = heights[k] === null ? lo : heights[k];
        pos.set([x, y, z], 3 * k);
        heightColour(z, lo, hi, rgb);
        col.set(rgb, 3 * k);
      }
    const index = [];
    for (let iy = 0; iy + 1 < h; ++iy)
      for (let ix = 0; ix + 1 < w; ++ix) {
        const a = iy * w + ix;
        const b = a + 1;
        const c = a + w;
        const d = c + 1;
        // Unobserved samples leave holes.
        if ([a, b, c, d].some((q) => heights[q] === null)) continue;
        index.push(a, b, d, a, d, c);
      }
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geo.setAttribute('color', new THREE.BufferAttribute(col, 3));
    geo.setIndex(index.length > 65535 ? new THREE.Uint32BufferAttribute(index, 1) : new THREE.Uint16BufferAttribute(index, 1));
    geo.computeVertexNormals();
    // Hill shading baked into the vertex colours under a fixed sun: an unlit material then costs
    // a software renderer a fraction of a lit one per pixel, and the light never moves anyway.
    const normals = geo.getAttribute('normal');
    const sun = new THREE.Vector3(0.3, -0.4, 0.87).normalize();
    for (let i = 0; i < w * h; ++i) {
      const lambert = Math.max(0, normals.getX(i) * sun.x + normals.getY(i) * sun.y + normals.getZ(i) * sun.z);
      const shade = 0.45 + 0.6 * lambert;
      for (let j = 0; j < 3; ++j) col[3 * i + j] = Math.min(1, col[3 * i + j] * shade);
    }
    this.mesh = new THREE.Mesh(geo, new THREE.MeshBasicMaterial({ vertexColors: true, side: THREE.DoubleSide }));
    this.mesh.name = 'terrain';
  }
  // Bilinear height at world (x, y) (NaN off the terrain).
  heightAt(x, y) {
    const t = this.t;
    const [ox, oy, yaw] = t.origin;
    const c = Math.cos(yaw);
    const s = Math.sin(yaw);
    const dx = x - ox;
    const dy = y - oy;
    // Sample s sits at the centre of cell s * stride.
    const gx = ((c * dx + s * dy) / t.resolution_m - 0.5) / t.stride;
    const gy = ((-s * dx + c * dy) / t.resolution_m - 0.5) / t.stride;
    const w = t.samples_x;
    const h = t.samples_y;
    const ix = Math.max(0, Math.min(w - 1, Math.floor(gx)));
    const iy = Math.max(0, Math.min(h - 1, Math.floor(gy)));
    if (gx < -1 || gy < -1 || gx > w || gy > h) return NaN;
    const ix1 = Math.min(w - 1, ix + 1);
    const iy1 = Math.min(h - 1, iy + 1);
    const fx = Math.max(0, Math.min(1, gx - ix));
    const fy = Math.max(0, Math.min(1, gy - iy));
    const v = (i, j) => {
      const z = t.heights[j * w + i];
      return z === null ? this.lo : z;
    };
    return (v(ix, iy) * (1 - fx) + v(ix1, iy) * fx) * (1 - fy) + (v(ix, iy1) * (1 - fx) + v(ix1, iy1) * fx) * fy;
  }
}

const rgbaOf = (c) => [(c >> 16) & 255, (c >> 8) & 255, c & 255, 255];
const BLOCKED_RGBA = rgbaOf(COLOURS.blocked);
const FREE_RGBA = rgbaOf(COLOURS.free);

// The navigator's grid as a texture on a plane (unknown clear, free pale, blocked red), over the
// ground or draped just above the terrain's lowest point.
export class NavMapLayer {
  constructor(navMap, baseZ) {
    this.g = navMap;
    const w = navMap.width;
    const h = navMap.height;
    this.rgba = new Uint8Array(w * h * 4);
    this.known = 0; // cells drawn (not unknown)
    this.texture = new THREE.DataTexture(this.rgba, w, h, THREE.RGBAFormat);
    this.texture.magFilter = THREE.NearestFilter;
    this.texture.minFilter = THREE.NearestFilter;
    const size = [w * navMap.resolution_m, h * navMap.resolution_m];
    const geo = new THREE.PlaneGeometry(size[0], size[1]);
    // Unknown cells are cut out (alpha test) rather than blended: blending a plane over the whole
    // view doubles a software renderer's work per pixel.
    const mat = new THREE.MeshBasicMaterial({ map: this.texture, alphaTest: 0.5, depthWrite: false });
    this.mesh = new THREE.Mesh(geo, mat);
    const [cx, cy] = gridToWorld(navMap, size[0] / 2, size[1] / 2);
    this.mesh.position.set(cx, cy, baseZ + 0.01);
    this.mesh.rotation.z = navMap.origin[2];
    this.mesh.renderOrder = 1;
    this.mesh.name = 'nav_map';
  }
  setCell(i, v) {
    const o = 4 * i;
    if (this.rgba[o + 3] !== 0) --this.known;
    if (v < 0) {
      this.rgba[o + 3] = 0;
    } else {
      this.rgba.set(v >= 65 ? BLOCKED_RGBA : FREE_RGBA, o);
      ++this.known;
    }
  }
  update(cells, indices) {
    if (indices === null) {
      for (let i = 0; i < cells.length; ++i) this.setCell(i, cells[i]);
    } else {
      for (const i of indices) this.setCell(i, cells[i]);
    }
    this.texture.needsUpdate = true;
  }
}

function partMesh(part, material, unitBox) {
  const kind = part[0];
  if (kind === 'cylinder') {
    const [, bx, by, bz, r, h] = part;
    const m = new THREE.Mesh(new THREE.CylinderGeometry(r, r, h, 24), material);
    m.rotation.x = Math.PI / 2;
    m.position.set(bx, by, bz + h / 2);
    return m;
  }
  if (kind === 'sphere') {
    const [, cx, cy, cz, r] = part;
    const m = new THREE.Mesh(new THREE.SphereGeometry(r, 24, 16), material);
    m.position.set(cx, cy, cz);
    return m;
  }
  if (kind === 'prism') {
    const [, bx, by, bz, yaw, base, h, apex, len] = part;
    // The triangle in the prism's x-z plane, extruded along its y axis.
    const v = [
      [-base / 2, -len / 2, 0], [base / 2, -len / 2, 0], [apex, -len / 2, h],
      [-base / 2, len / 2, 0], [base / 2, len / 2, 0], [apex, len / 2, h],
    ];
    const tri = [0, 2, 1, 3, 4, 5, 0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4, 2, 0, 3, 2, 3, 5];
    const pos = [];
    for (const i of tri) pos.push(...v[i]);
    const geo = new THREE.BufferGeometry();
    geo.setAttribute('position', new THREE.Float32BufferAttribute(pos, 3));
    geo.computeVertexNormals();
    const m = new THREE.Mesh(geo, material);
    m.rotation.z = yaw;
    m.position.set(bx, by, bz);
    return m;
  }
  // box
  const [, cx, cy, cz, sx, sy, sz, roll, pitch, yaw] = part;
  const m = new THREE.Mesh(unitBox, material);
  m.scale.set(sx, sy, sz);
  m.rotation.set(roll, pitch, yaw, 'ZYX');
  m.position.set(cx, cy, cz);
  return m;
}

// Obstacles: each a group posed at its anchor's offset and shown during its lifetime. Boxes of
// an obstacle with many (a map_server map's walls) are drawn as one instanced mesh.
export class Obstacles {
  constructor(list) {
    this.group = new THREE.Group();
    this.group.name = 'obstacles';
    this.items = [];
    const unitBox = new THREE.BoxGeometry(1, 1, 1);
    list.forEach((o, k) => {
      const material = new THREE.MeshLambertMaterial({ color: obstacleColour(k) });
      const g = new THREE.Group();
      g.name = o.name;
      const boxes = o.parts.filter((p) => p[0] === 'box');
      if (boxes.length > 32) {
        const inst = new THREE.InstancedMesh(unitBox, new THREE.MeshLambertMaterial({ color: COLOURS.walls }), boxes.length);
        const m = new THREE.Matrix4();
        const q = new THREE.Quaternion();
        const e = new THREE.Euler();
        boxes.forEach((b, i) => {
          const [, cx, cy, cz, sx, sy, sz, roll, pitch, yaw] = b;
          e.set(roll, pitch, yaw, 'ZYX');
          q.setFromEuler(e);
          m.compose(new THREE.Vector3(cx, cy, cz), q, new THREE.Vector3(sx, sy, sz));
          inst.setMatrixAt(i, m);
        });
        g.add(inst);
        for (const p of o.parts) if (p[0] !== 'box') g.add(partMesh(p, material, unitBox));
      } else {
        for (const p of o.parts) g.add(partMesh(p, material, unitBox));
      }
      this.group.add(g);
      this.items.push({ o, g });
    });
  }
  // The anchor's offset at time t (obstacles.hpp: constant velocity or piecewise-linear waypoints).
  static offset(o, t) {
    if (o.waypoints && o.waypoints.length) {
      const w = o.waypoints;
      let p;
      if (t <= w[0][0]) p = w[0];
      else if (t >= w[w.length - 1][0]) p = w[w.length - 1];
      else {
        let i = 0;
        while (w[i + 1][0] < t) ++i;
        const f = (t - w[i][0]) / (w[i + 1][0] - w[i][0]);
        p = [t, w[i][1] + f * (w[i + 1][1] - w[i][1]), w[i][2] + f * (w[i + 1][2] - w[i][2]), w[i][3] + f * (w[i + 1][3] - w[i][3])];
      }
      return [p[1] - o.anchor[0], p[2] - o.anchor[1], p[3] - o.anchor[2]];
    }
    if (o.velocity) {
      const dt = t - (o.appear_s || 0);
      return [o.velocity[0] * dt, o.velocity[1] * dt, o.velocity[2] * dt];
    }
    return [0, 0, 0];
  }
  update(t) {
    let shown = 0;
    for (const { o, g } of this.items) {
      const alive = (o.appear_s === null || o.appear_s <= t) && (o.disappear_s === null || t < o.disappear_s);
      g.visible = alive;
      if (alive) {
        ++shown;
        const d = Obstacles.offset(o, t);
        g.position.set(d[0], d[1], d[2]);
      }
    }
    return shown;
  }
}

export class Robot {
  constructor(r) {
    this.group = new THREE.Group();
    this.group.name = 'robot';
    const body = new THREE.Mesh(
      new THREE.BoxGeometry(r.body_length_m, r.body_width_m, r.body_height_m),
      new THREE.MeshLambertMaterial({ color: COLOURS.robot }),
    );
    body.position.set(r.body_center_x_m || 0, 0, r.ground_clearance_m + r.body_height_m / 2);
    this.group.add(body);
    // A nose so the heading reads at a glance.
    const nose = new THREE.Mesh(
      new THREE.ConeGeometry(r.body_width_m * 0.18, r.body_length_m * 0.3, 12),
      new THREE.MeshLambertMaterial({ color: 0x202020 }),
    );
    nose.rotation.z = -Math.PI / 2;
    nose.position.set((r.body_center_x_m || 0) + r.body_length_m / 2, 0, r.ground_clearance_m + r.body_height_m);
    this.group.add(nose);
    const wheelGeo = new THREE.CylinderGeometry(r.wheel_radius_m, r.wheel_radius_m, Math.max(0.02, r.wheel_radius_m * 0.7), 20);
    const wheelMat = new THREE.MeshLambertMaterial({ color: 0x303030 });
    const x0 = r.drive === 'ackermann' ? 0 : -r.half_wheelbase_m;
    const x1 = r.drive === 'ackermann' ? 2 * r.half_wheelbase_m : r.half_wheelbase_m;
    for (const x of [x0, x1])
      for (const y of [-r.half_track_m, r.half_track_m]) {
        const w = new THREE.Mesh(wheelGeo, wheelMat);
        w.position.set(x, y, r.wheel_radius_m);
        this.group.add(w);
      }
  }
  set(x, y, z, roll, pitch, yaw) {
    this.group.position.set(x, y, z);
    this.group.rotation.set(roll, pitch, yaw, 'ZYX');
  }
}

// A point cloud whose contents change every frame (LiDAR hits, particles).
export class DynamicPoints {
  constructor(name, colour, size, capacity) {
    this.capacity = Math.max(1, capacity);
    this.positions = new Float32Array(this.capacity * 3);
    this.geo = new THREE.BufferGeometry();
    this.attr = new THREE.BufferAttribute(this.positions, 3);
    this.attr.setUsage(THREE.DynamicDrawUsage);
    this.geo.setAttribute('position', this.attr);
    this.geo.setDrawRange(0, 0);
    this.points = new THREE.Points(this.geo, new THREE.PointsMaterial({ color: colour, size, sizeAttenuation: false }));
    this.points.frustumCulled = false;
    this.points.name = name;
  }
  // xyz: flat [x, y, z, ...]; zOf: for planar samples [x, y, yaw, ...] the height to draw at.
  set(values, stride = 3, zOf = null) {
    const n = Math.min(this.capacity, Math.floor(values.length / stride));
    for (let i = 0; i < n; ++i) {
      const x = values[i * stride];
      const y = values[i * stride + 1];
      this.positions[3 * i] = x;
      this.positions[3 * i + 1] = y;
      this.positions[3 * i + 2] = zOf ? zOf(x, y) : values[i * stride + 2];
    }
    this.attr.needsUpdate = true;
    this.geo.setDrawRange(0, n);
    return n;
  }
}

export function lineOf(points2, zOf, colour, width = 1) {
  const n = points2.length / 2;
  const pos = new Float32Array(n * 3);
  for (let i = 0; i < n; ++i) {
    const x = points2[2 * i];
    const y = points2[2 * i + 1];
    pos.set([x, y, zOf(x, y)], 3 * i);
  }
  const geo = new THREE.BufferGeometry();
  geo.setAttribute('position', new THREE.BufferAttribute(pos, 3));
  return new THREE.Line(geo, new THREE.LineBasicMaterial({ color: colour, linewidth: width }));
}

// The ground of a world without terrain: a plain plane over the region the run is about (a
// margin around it), with a grid of 1, 5 or 10 m by its size. A plane and grid far larger than
// the world alias into stripes at a distance.
export function groundOf(box) {
  const group = new THREE.Group();
  group.name = 'ground';
  const cx = (box.min.x + box.max.x) / 2;
  const cy = (box.min.y + box.max.y) / 2;
  const extent = Math.max(box.max.x - box.min.x, box.max.y - box.min.y, 10);
  const spacing = extent <= 60 ? 1 : extent <= 300 ? 5 : 10;
  const side = spacing * Math.ceil((extent * 1.4) / spacing);
  const plane = new THREE.Mesh(new THREE.PlaneGeometry(3 * side, 3 * side), new THREE.MeshBasicMaterial({ color: COLOURS.ground }));
  plane.position.set(cx, cy, -0.002);
  group.add(plane);
  const grid = new THREE.GridHelper(side, side / spacing, COLOURS.grid, COLOURS.grid);
  grid.rotation.x = Math.PI / 2;
  grid.position.set(spacing * Math.round(cx / spacing), spacing * Math.round(cy / spacing), 0);
  group.add(grid);
  return group;
}

export function pathColour(id) {
  return PATH_COLOURS[(id - 1) % PATH_COLOURS.length];
}

export function goalMarker(x, y, z) {
  const m = new THREE.Mesh(new THREE.ConeGeometry(0.15, 0.5, 16), new THREE.MeshLambertMaterial({ color: COLOURS.goal }));
  m.rotation.x = -Math.PI / 2;
  m.position.set(x, y, z + 0.25);
  m.name = 'goal';
  return m;
}

export function poseArrow(colour) {
  const g = new THREE.Group();
  const shaft = new THREE.Mesh(new THREE.CylinderGeometry(0.03, 0.03, 0.4, 8), new THREE.MeshBasicMaterial({ color: colour }));
  shaft.rotation.z = -Math.PI / 2;
  shaft.position.x = 0.2;
  const head = new THREE.Mesh(new THREE.ConeGeometry(0.08, 0.16, 12), new THREE.MeshBasicMaterial({ color: colour }));
  head.rotation.z = -Math.PI / 2;
  head.position.x = 0.48;
  g.add(shaft, head);
  return g;
}
