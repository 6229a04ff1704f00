// Writes samples/assets/grid_scene.glb: a glTF scene of several meshes, each placed by many nodes,
// for the scene runner's per-mesh SDF objects (issue 22). Meshes: the bunny (read from the
// committed samples/assets/bunny.glb, bytes unchanged), and three generated closed meshes of about
// the bunny's size: a torus (genus 1), a box (flat faces, sharp edges) and a rock (an icosphere
// with deterministic radial noise). Nodes: a 12 x 10 grid (120 instances) under one root node, each
// rotated about Y and scaled; a few carry "extras": {"hermite_sdf": {"draw": "triangles"}} (drawn as
// triangles) and a few {"draw": "sdf"}. Deterministic: no randomness, same bytes each run.
//
//   node make_scene.mjs ../../samples/assets/bunny.glb ../../samples/assets/grid_scene.glb
import { createHash } from 'node:crypto';
import { readFileSync, writeFileSync } from 'node:fs';
import { float32Bounds, glbBytes, readGlb } from '../glb_common/glb.mjs';

const FLOAT = 5126;
const UNSIGNED_INT = 5125;
const ARRAY_BUFFER = 34962;
const ELEMENT_ARRAY_BUFFER = 34963;
const TRIANGLES = 4;
// The grid's size: 12 x 10 for the committed asset; larger grids (COLUMNS ROWS on the command line)
// for scale tests, not committed.
let COLUMNS = 12;
let ROWS = 10;
const SPACING = 14;

function normalize(v) {
  const length = Math.hypot(v[0], v[1], v[2]);
  return [v[0] / length, v[1] / length, v[2] / length];
}

// The bunny's POSITION, NORMAL and indices as the bunny tool wrote them (accessors 0, 1, 2).
function readBunny(path) {
  const { gltf, bin } = readGlb(readFileSync(path));
  const floats = (accessor) => {
    const view = gltf.bufferViews[gltf.accessors[accessor].bufferView];
    const out = [];
    for (let i = 0; i < gltf.accessors[accessor].count; i++)
      out.push([0, 1, 2].map((k) => bin.readFloatLE(view.byteOffset + i * 12 + k * 4)));
    return out;
  };
  const indexView = gltf.bufferViews[gltf.accessors[2].bufferView];
  const indices = [];
  for (let i = 0; i < gltf.accessors[2].count; i++) indices.push(bin.readUInt32LE(indexView.byteOffset + i * 4));
  return { name: 'bunny', positions: floats(0), normals: floats(1), indices };
}

function torus(major, minor, segments, sides) {
  const positions = [], normals = [], indices = [];
  for (let i = 0; i < segments; i++) {
    const u = (2 * Math.PI * i) / segments;
    for (let j = 0; j < sides; j++) {
      const v = (2 * Math.PI * j) / sides;
      const n = [Math.cos(v) * Math.cos(u), Math.sin(v), Math.cos(v) * Math.sin(u)];
      positions.push([(major + minor * Math.cos(v)) * Math.cos(u), minor * Math.sin(v), (major + minor * Math.cos(v)) * Math.sin(u)]);
      normals.push(n);
    }
  }
  for (let i = 0; i < segments; i++) {
    for (let j = 0; j < sides; j++) {
      const a = i * sides + j, b = ((i + 1) % segments) * sides + j;
      const c = ((i + 1) % segments) * sides + ((j + 1) % sides), d = i * sides + ((j + 1) % sides);
      indices.push(a, d, b, b, d, c); // counter-clockwise seen from outside
    }
  }
  return { name: 'torus', positions, normals, indices };
}

// Four vertices per face so that each face has its flat normal.
function box(half) {
  const positions = [], normals = [], indices = [];
  for (let axis = 0; axis < 3; axis++) {
    for (const sign of [-1, 1]) {
      const n = [0, 0, 0];
      n[axis] = sign;
      const u = (axis + 1) % 3, w = (axis + 2) % 3;
      const base = positions.length;
      for (const [a, b] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
        const p = [0, 0, 0];
        p[axis] = sign * half[axis];
        p[u] = a * half[u];
        p[w] = b * half[w];
        positions.push(p);
        normals.push(n);
      }
      if (sign > 0) indices.push(base, base + 1, base + 2, base, base + 2, base + 3);
      else indices.push(base, base + 2, base + 1, base, base + 3, base + 2);
    }
  }
  return { name: 'box', positions, normals, indices };
}

// Icosphere (shared vertices, so closed) pushed in and out by a smooth deterministic function.
function rock(radius, levels) {
  const t = (1 + Math.sqrt(5)) / 2;
  let positions = [[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
    [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]].map(normalize);
  let faces = [[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6],
    [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]];
  for (let level = 0; level < levels; level++) {
    const midpoints = new Map();
    const midpoint = (a, b) => {
      const key = Math.min(a, b) + ':' + Math.max(a, b);
      if (!midpoints.has(key)) {
        positions.push(normalize(positions[a].map((x, k) => x + positions[b][k])));
        midpoints.set(key, positions.length - 1);
      }
      return midpoints.get(key);
    };
    faces = faces.flatMap(([a, b, c]) => {
      const ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      return [[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]];
    });
  }
  const bump = (p) => 1 + 0.12 * Math.sin(3.1 * p[0] + 1.3) * Math.cos(2.3 * p[1]) + 0.08 * Math.sin(4.7 * p[2] + 2 * p[0]);
  positions = positions.map((p) => p.map((x) => x * radius * bump(p)));
  const sums = positions.map(() => [0, 0, 0]);
  for (const [a, b, c] of faces) {
    const e1 = positions[b].map((x, k) => x - positions[a][k]), e2 = positions[c].map((x, k) => x - positions[a][k]);
    const n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]];
    for (const v of [a, b, c]) for (let k = 0; k < 3; k++) sums[v][k] += n[k];
  }
  return { name: 'rock', positions, normals: sums.map(normalize), indices: faces.flat() };
}

const MATERIALS = [
  { name: 'terracotta', color: [0.8, 0.45, 0.3, 1.0], roughness: 0.6 },
  { name: 'teal', color: [0.2, 0.6, 0.65, 1.0], roughness: 0.4 },
  { name: 'sand', color: [0.85, 0.75, 0.5, 1.0], roughness: 0.7 },
  { name: 'slate', color: [0.45, 0.47, 0.55, 1.0], roughness: 0.9 },
];

// Per grid cell: which mesh, its turn about Y, its scale and its draw choice (none: the default).
function placement(row, column) {
  const index = row * COLUMNS + column;
  const mesh = (column + 2 * row) % 4;
  const angle = 0.37 * index;
  const scale = 0.75 + 0.05 * ((index * 7) % 10);
  let draw;
  if (row % 3 === 0 && column % 4 === 3) draw = 'triangles';
  else if (row === 4 && column % 4 === 1) draw = 'sdf';
  return { mesh, angle, scale, draw };
}

function buildScene(meshes) {
  const parts = [];
  let offset = 0;
  const bufferViews = [], accessors = [];
  const addView = (buffer, target) => {
    bufferViews.push({ buffer: 0, byteOffset: offset, byteLength: buffer.length, target });
    parts.push(buffer);
    offset += buffer.length;
    return bufferViews.length - 1;
  };
  const gltfMeshes = meshes.map((mesh, m) => {
    const vec3 = (vectors) => {
      const bytes = Buffer.alloc(vectors.length * 12);
      vectors.forEach((v, i) => v.forEach((x, k) => bytes.writeFloatLE(x, i * 12 + k * 4)));
      return bytes;
    };
    const indexBytes = Buffer.alloc(mesh.indices.length * 4);
    mesh.indices.forEach((x, i) => indexBytes.writeUInt32LE(x, i * 4));
    accessors.push({ bufferView: addView(vec3(mesh.positions), ARRAY_BUFFER), componentType: FLOAT,
      count: mesh.positions.length, type: 'VEC3', ...float32Bounds(mesh.positions) });
    accessors.push({ bufferView: addView(vec3(mesh.normals), ARRAY_BUFFER), componentType: FLOAT,
      count: mesh.normals.length, type: 'VEC3' });
    accessors.push({ bufferView: addView(indexBytes, ELEMENT_ARRAY_BUFFER), componentType: UNSIGNED_INT,
      count: mesh.indices.length, type: 'SCALAR' });
    const first = accessors.length - 3;
    return { name: mesh.name, primitives: [{ attributes: { POSITION: first, NORMAL: first + 1 }, indices: first + 2,
      material: m, mode: TRIANGLES }] };
  });
  const lowest = meshes.map((mesh) => float32Bounds(mesh.positions).min[1]);
  const nodes = [{ name: 'grid', translation: [0, 0.5, 0], children: [] }];
  for (let row = 0; row < ROWS; row++) {
    for (let column = 0; column < COLUMNS; column++) {
      const { mesh, angle, scale, draw } = placement(row, column);
      const node = {
        name: `${meshes[mesh].name}_${row}_${column}`,
        mesh,
        translation: [(column - (COLUMNS - 1) / 2) * SPACING, -scale * lowest[mesh], (row - (ROWS - 1) / 2) * SPACING],
        rotation: [0, Math.sin(angle / 2), 0, Math.cos(angle / 2)],
        scale: [scale, scale, scale],
      };
      if (draw) node.extras = { hermite_sdf: { draw } };
      nodes[0].children.push(nodes.length);
      nodes.push(node);
    }
  }
  const bin = Buffer.concat(parts);
  const gltf = {
    asset: { version: '2.0', generator: 'hermite_sdf tools/scene_to_glb' },
    scene: 0,
    scenes: [{ name: 'grid', nodes: [0] }],
    nodes,
    meshes: gltfMeshes,
    materials: MATERIALS.map((m) => ({ name: m.name,
      pbrMetallicRoughness: { baseColorFactor: m.color, metallicFactor: 0.0, roughnessFactor: m.roughness } })),
    buffers: [{ byteLength: bin.length }],
    bufferViews,
    accessors,
  };
  return glbBytes(gltf, bin);
}

function main() {
  const [bunnyPath, outPath, columns, rows] = process.argv.slice(2);
  const size = (text) => (/^[1-9][0-9]{0,3}$/.test(text) ? Number(text) : NaN);
  if (columns !== undefined || rows !== undefined) {
    COLUMNS = size(columns);
    ROWS = size(rows);
  }
  if (!bunnyPath || !outPath || !(COLUMNS > 0) || !(ROWS > 0)) {
    console.error('usage: node make_scene.mjs BUNNY.glb OUTPUT.glb [COLUMNS ROWS]  (each 1..9999; default 12 10)');
    process.exit(2);
  }
  const meshes = [readBunny(bunnyPath), torus(3.5, 1.5, 48, 24), box([3.5, 3.5, 3.5]), rock(4.0, 3)];
  for (const mesh of meshes)
    console.log(`${mesh.name}: ${mesh.positions.length} vertices, ${mesh.indices.length / 3} triangles`);
  const glb = buildScene(meshes);
  writeFileSync(outPath, glb);
  console.log(`${ROWS * COLUMNS} instances; wrote ${outPath}: ${glb.length} bytes, sha256 ${createHash('sha256').update(glb).digest('hex')}`);
}

main();
