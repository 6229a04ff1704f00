// Converts the Stanford bunny of the npm package `bunny` (1.0.1, public domain) into a binary glTF
// (GLB) with POSITION, smooth NORMAL, uint32 indices, one mesh, one node and one material.
//
//   npm ci && node convert.mjs ../../samples/assets/bunny.glb
//
// The GLB is written by hand (12-byte header, JSON chunk, BIN chunk) so the tool needs nothing but
// the bunny data. Before writing it checks that the mesh is watertight and that its triangles wind
// counter-clockwise seen from outside (glTF's convention), flipping them if the signed volume says
// they wind the other way. The output is deterministic: same input, same bytes.
import { createHash } from 'node:crypto';
import { writeFileSync } from 'node:fs';
import bunny from 'bunny';
import { float32Bounds, glbBytes } from '../glb_common/glb.mjs';

const FLOAT = 5126;
const UNSIGNED_INT = 5125;
const ARRAY_BUFFER = 34962;
const ELEMENT_ARRAY_BUFFER = 34963;
const TRIANGLES = 4;

function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// Volume enclosed by a closed mesh, positive when its triangles wind counter-clockwise seen from
// outside (sum of the signed volumes of the tetrahedra spanned by the origin and each triangle).
function signedVolume(positions, cells) {
  let sixTimesVolume = 0;
  for (const [a, b, c] of cells) sixTimesVolume += dot(positions[a], cross(positions[b], positions[c]));
  return sixTimesVolume / 6;
}

// Watertight: every undirected edge is shared by exactly two triangles. Consistently oriented:
// those two triangles traverse it in opposite directions, i.e. no directed edge appears twice.
function edgeReport(cells) {
  const undirected = new Map();
  const directed = new Set();
  let repeatedDirected = 0;
  for (const cell of cells) {
    for (let k = 0; k < 3; k++) {
      const from = cell[k];
      const to = cell[(k + 1) % 3];
      const key = Math.min(from, to) + ':' + Math.max(from, to);
      undirected.set(key, (undirected.get(key) ?? 0) + 1);
      const directedKey = from + '>' + to;
      if (directed.has(directedKey)) repeatedDirected++;
      directed.add(directedKey);
    }
  }
  let notShared = 0;
  for (const count of undirected.values()) if (count !== 2) notShared++;
  return { edges: undirected.size, notShared, repeatedDirected };
}

// Smooth vertex normals: each triangle adds its unnormalised face normal (length = twice its area)
// to its three corners, so large triangles weigh more than slivers.
function smoothNormals(positions, cells) {
  const sums = positions.map(() => [0, 0, 0]);
  for (const [a, b, c] of cells) {
    const n = cross(sub(positions[b], positions[a]), sub(positions[c], positions[a]));
    for (const v of [a, b, c]) for (let i = 0; i < 3; i++) sums[v][i] += n[i];
  }
  return sums.map((n) => {
    const length = Math.hypot(n[0], n[1], n[2]);
    if (length === 0) throw new Error('a vertex has no adjacent triangle area; cannot give it a normal');
    return [n[0] / length, n[1] / length, n[2] / length];
  });
}

function buildGlb(positions, normals, cells) {
  const vertexBytes = positions.length * 12;
  const bin = Buffer.alloc(2 * vertexBytes + cells.length * 12);
  positions.forEach((p, v) => p.forEach((x, i) => bin.writeFloatLE(x, v * 12 + i * 4)));
  normals.forEach((n, v) => n.forEach((x, i) => bin.writeFloatLE(x, vertexBytes + v * 12 + i * 4)));
  cells.forEach((cell, t) => cell.forEach((index, k) => bin.writeUInt32LE(index, 2 * vertexBytes + t * 12 + k * 4)));

  const gltf = {
    asset: { version: '2.0', generator: 'hermite_sdf tools/bunny_to_glb from npm bunny@1.0.1' },
    scene: 0,
    scenes: [{ name: 'bunny', nodes: [0] }],
    nodes: [{ name: 'bunny', mesh: 0 }],
    meshes: [{
      name: 'bunny',
      primitives: [{ attributes: { POSITION: 0, NORMAL: 1 }, indices: 2, material: 0, mode: TRIANGLES }],
    }],
    materials: [{
      name: 'terracotta',
      pbrMetallicRoughness: { baseColorFactor: [0.8, 0.45, 0.3, 1.0], metallicFactor: 0.0, roughnessFactor: 0.6 },
    }],
    buffers: [{ byteLength: bin.length }],
    bufferViews: [
      { buffer: 0, byteOffset: 0, byteLength: vertexBytes, target: ARRAY_BUFFER },
      { buffer: 0, byteOffset: vertexBytes, byteLength: vertexBytes, target: ARRAY_BUFFER },
      { buffer: 0, byteOffset: 2 * vertexBytes, byteLength: cells.length * 12, target: ELEMENT_ARRAY_BUFFER },
    ],
    accessors: [
      { bufferView: 0, componentType: FLOAT, count: positions.length, type: 'VEC3', ...float32Bounds(positions) },
      { bufferView: 1, componentType: FLOAT, count: normals.length, type: 'VEC3' },
      { bufferView: 2, componentType: UNSIGNED_INT, count: cells.length * 3, type: 'SCALAR' },
    ],
  };

  return glbBytes(gltf, bin);
}

function main() {
  const outPath = process.argv[2];
  if (!outPath) {
    console.error('usage: node convert.mjs OUTPUT.glb');
    process.exit(2);
  }
  const positions = bunny.positions;
  let cells = bunny.cells.map((c) => [...c]);
  console.log(`bunny@1.0.1: ${positions.length} vertices, ${cells.length} triangles`);

  const edges = edgeReport(cells);
  const watertight = edges.notShared === 0;
  console.log(`watertight: ${watertight ? 'yes' : 'NO'} (${edges.edges} edges, ${edges.notShared} not shared by exactly two triangles)`);
  console.log(`consistently oriented: ${edges.repeatedDirected === 0 ? 'yes' : 'NO'} (${edges.repeatedDirected} repeated directed edges)`);
  if (!watertight || edges.repeatedDirected !== 0) {
    console.error('refusing to write: the winding test below is only meaningful for a closed, oriented mesh');
    process.exit(1);
  }

  const volume = signedVolume(positions, cells);
  console.log(`signed volume as stored: ${volume.toFixed(4)} (${volume > 0 ? 'counter-clockwise from outside' : 'clockwise from outside: flipping'})`);
  if (volume < 0) cells = cells.map(([a, b, c]) => [a, c, b]);
  console.log(`signed volume as written: ${signedVolume(positions, cells).toFixed(4)}`);

  const normals = smoothNormals(positions, cells);
  const glb = buildGlb(positions, normals, cells);
  writeFileSync(outPath, glb);
  console.log(`wrote ${outPath}: ${glb.length} bytes, sha256 ${createHash('sha256').update(glb).digest('hex')}`);
}

main();
