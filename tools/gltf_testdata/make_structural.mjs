// Writes the small hand-laid glTF files of tests/data/gltf/ that exercise the glTF structure
// rather than compression (see tests/data/gltf/README.md):
//   tetra_sparse_scenes.gltf     sparse accessors (over a bufferView and over zeros), two scenes,
//                                an extension that does not affect geometry
//   gpu_instancing.gltf          EXT_mesh_gpu_instancing (required): a tetrahedron placed three times
//                                by float translations and scales and normalized int16 rotations
//   textured_grid.gltf           a textured square of 4 x 4 vertices with TEXCOORD_0 unlike its
//                                positions (the plain original of textured_grid_draco.glb)
// Usage: node make_structural.mjs <output folder>
import { writeFileSync } from 'node:fs';
import { join } from 'node:path';

const out = process.argv[2];
if (!out) {
  console.error('usage: node make_structural.mjs <output folder>');
  process.exit(2);
}

// A tetrahedron with one vertex at the origin, so that a sparse accessor over zeros can rebuild
// it from its three other vertices.
const tetra = [
  [0, 0, 0],
  [1, 0, 0],
  [0, 1, 0],
  [0, 0, 1],
];
const indices = [0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3];  // counter-clockwise seen from outside

class BufferWriter {
  constructor() {
    this.chunks = [];
    this.length = 0;
  }
  // Appends `bytes` 4-byte aligned; returns its offset.
  add(bytes) {
    const offset = this.length;
    this.chunks.push(Buffer.from(bytes.buffer, bytes.byteOffset, bytes.byteLength));
    this.length += bytes.byteLength;
    const pad = (4 - (this.length % 4)) % 4;
    if (pad) {
      this.chunks.push(Buffer.alloc(pad));
      this.length += pad;
    }
    return offset;
  }
  dataUri() {
    return 'data:application/octet-stream;base64,' + Buffer.concat(this.chunks).toString('base64');
  }
}

function bounds(points) {
  const min = [0, 1, 2].map((c) => Math.min(...points.map((p) => p[c])));
  const max = [0, 1, 2].map((c) => Math.max(...points.map((p) => p[c])));
  return { min, max };
}

function writeTetraSparseScenes() {
  const bin = new BufferWriter();
  const views = [];
  const view = (bytes, target) => {
    const byteOffset = bin.add(bytes);
    views.push({ buffer: 0, byteOffset, byteLength: bytes.byteLength, ...(target ? { target } : {}) });
    return views.length - 1;
  };
  const plainView = view(new Float32Array(tetra.flat()), 34962);
  const indexView = view(new Uint16Array(indices), 34963);
  // Base of the first sparse accessor: the tetrahedron with vertices 1 and 3 swapped; the sparse
  // part writes them back (indices 1 and 3).
  const swapped = [tetra[0], tetra[3], tetra[2], tetra[1]];
  const swappedView = view(new Float32Array(swapped.flat()), 34962);
  const sparseIndexView = view(new Uint8Array([1, 3]));
  const sparseValueView = view(new Float32Array([...tetra[1], ...tetra[3]]));
  // Second sparse accessor: no bufferView (all zeros), vertices 1, 2, 3 written by the sparse part.
  const zeroIndexView = view(new Uint16Array([1, 2, 3]));
  const zeroValueView = view(new Float32Array([...tetra[1], ...tetra[2], ...tetra[3]]));

  const { min, max } = bounds(tetra);
  const position = (extra) => ({ componentType: 5126, count: 4, type: 'VEC3', min, max, ...extra });
  const accessors = [
    position({ bufferView: plainView }),
    { bufferView: indexView, componentType: 5123, count: indices.length, type: 'SCALAR' },
    position({
      bufferView: swappedView,
      sparse: {
        count: 2,
        indices: { bufferView: sparseIndexView, componentType: 5121 },
        values: { bufferView: sparseValueView },
      },
    }),
    position({
      sparse: {
        count: 3,
        indices: { bufferView: zeroIndexView, componentType: 5123 },
        values: { bufferView: zeroValueView },
      },
    }),
  ];
  const mesh = (name, positionAccessor) => ({
    name,
    primitives: [{ attributes: { POSITION: positionAccessor }, indices: 1, material: 0 }],
  });
  const doc = {
    asset: { version: '2.0', generator: 'hermite_sdf tools/gltf_testdata/make_structural.mjs' },
    extensionsUsed: ['KHR_materials_emissive_strength'],
    scene: 1,
    scenes: [
      { name: 'plain only', nodes: [0] },
      { name: 'all three', nodes: [1, 2, 3] },
    ],
    nodes: [
      { name: 'plain (scene 0)', mesh: 0 },
      { name: 'plain', mesh: 0 },
      { name: 'sparse over a bufferView', mesh: 1, translation: [2, 0, 0] },
      { name: 'sparse over zeros', mesh: 2, translation: [4, 0, 0] },
    ],
    meshes: [mesh('plain', 0), mesh('sparse over a bufferView', 2), mesh('sparse over zeros', 3)],
    materials: [
      {
        name: 'glowing',
        emissiveFactor: [1, 0.5, 0.2],
        extensions: { KHR_materials_emissive_strength: { emissiveStrength: 4 } },
      },
    ],
    accessors,
    bufferViews: views,
    buffers: [{ byteLength: bin.length, uri: bin.dataUri() }],
  };
  writeFileSync(join(out, 'tetra_sparse_scenes.gltf'), JSON.stringify(doc, null, 1) + '\n');
}

function writeGpuInstancing() {
  const bin = new BufferWriter();
  const positions = bin.add(new Float32Array(tetra.flat()));
  const triangles = bin.add(new Uint16Array(indices));
  const translations = bin.add(new Float32Array([0, 0, 0, 2, 0, 0, 0, 3, 0]));
  // Quaternions x, y, z, w as normalized int16: the identity, 90 degrees about z, the identity.
  const q = Math.round(Math.SQRT1_2 * 32767);
  const rotations = bin.add(new Int16Array([0, 0, 0, 32767, 0, 0, q, q, 0, 0, 0, 32767]));
  const scales = bin.add(new Float32Array([1, 1, 1, 1, 1, 1, 2, 2, 2]));
  const { min, max } = bounds(tetra);
  const doc = {
    asset: { version: '2.0', generator: 'hermite_sdf tools/gltf_testdata/make_structural.mjs' },
    extensionsUsed: ['EXT_mesh_gpu_instancing'],
    extensionsRequired: ['EXT_mesh_gpu_instancing'],
    scene: 0,
    scenes: [{ nodes: [0] }],
    nodes: [
      {
        name: 'tetras',
        translation: [0, 0, -1],
        mesh: 0,
        extensions: { EXT_mesh_gpu_instancing: { attributes: { TRANSLATION: 1, ROTATION: 3, SCALE: 4 } } },
      },
    ],
    meshes: [{ primitives: [{ attributes: { POSITION: 0 }, indices: 2 }] }],
    accessors: [
      { bufferView: 0, componentType: 5126, count: 4, type: 'VEC3', min, max },
      { bufferView: 1, componentType: 5126, count: 3, type: 'VEC3' },
      { bufferView: 2, componentType: 5123, count: indices.length, type: 'SCALAR' },
      { bufferView: 3, componentType: 5122, normalized: true, count: 3, type: 'VEC4' },
      { bufferView: 4, componentType: 5126, count: 3, type: 'VEC3' },
    ],
    bufferViews: [
      { buffer: 0, byteOffset: positions, byteLength: 48, target: 34962 },
      { buffer: 0, byteOffset: translations, byteLength: 36 },
      { buffer: 0, byteOffset: triangles, byteLength: 2 * indices.length, target: 34963 },
      { buffer: 0, byteOffset: rotations, byteLength: 24 },
      { buffer: 0, byteOffset: scales, byteLength: 36 },
    ],
    buffers: [{ byteLength: bin.length, uri: bin.dataUri() }],
  };
  writeFileSync(join(out, 'gpu_instancing.gltf'), JSON.stringify(doc, null, 1) + '\n');
}

// A 2 x 2 RGBA PNG (red, green / blue, white), as quad_textured.gltf's fuzz seed holds it.
const checkerPng =
  'iVBORw0KGgoAAAANSUhEUgAAAAIAAAACCAYAAABytg0kAAAAE0lEQVR4nGP4z8DwHwyBNAg0AABJSQl4KKDbdwAAAABJRU5ErkJggg==';

function writeTexturedGrid() {
  const side = 4;
  const points = [];
  const uvs = [];
  for (let j = 0; j < side; ++j) {
    for (let i = 0; i < side; ++i) {
      points.push([i / (side - 1), j / (side - 1), 0]);
      // Not a function of the position alone: a decoder that drops or swaps them is seen.
      const k = j * side + i;
      uvs.push([((k * 5) % 16) / 16 + 0.03, ((k * 11) % 16) / 16 + 0.01]);
    }
  }
  const triangles = [];
  for (let j = 0; j + 1 < side; ++j) {
    for (let i = 0; i + 1 < side; ++i) {
      const a = j * side + i;
      triangles.push(a, a + 1, a + side + 1, a, a + side + 1, a + side);  // counter-clockwise seen from +z
    }
  }
  const bin = new BufferWriter();
  const positions = bin.add(new Float32Array(points.flat()));
  const normals = bin.add(new Float32Array(points.flatMap(() => [0, 0, 1])));
  const texcoords = bin.add(new Float32Array(uvs.flat()));
  const triangleBytes = bin.add(new Uint16Array(triangles));
  const image = bin.add(new Uint8Array(Buffer.from(checkerPng, 'base64')));
  const { min, max } = bounds(points);
  const count = points.length;
  const doc = {
    asset: { version: '2.0', generator: 'hermite_sdf tools/gltf_testdata/make_structural.mjs' },
    scene: 0,
    scenes: [{ nodes: [0] }],
    nodes: [{ name: 'grid', mesh: 0 }],
    meshes: [{ name: 'grid', primitives: [{ attributes: { POSITION: 0, NORMAL: 1, TEXCOORD_0: 2 }, indices: 3, material: 0 }] }],
    materials: [{ name: 'checker', pbrMetallicRoughness: { baseColorTexture: { index: 0 } } }],
    textures: [{ source: 0, sampler: 0 }],
    samplers: [{ magFilter: 9728, minFilter: 9728 }],
    images: [{ name: 'checker', bufferView: 4, mimeType: 'image/png' }],
    accessors: [
      { bufferView: 0, componentType: 5126, count, type: 'VEC3', min, max },
      { bufferView: 1, componentType: 5126, count, type: 'VEC3' },
      { bufferView: 2, componentType: 5126, count, type: 'VEC2' },
      { bufferView: 3, componentType: 5123, count: triangles.length, type: 'SCALAR' },
    ],
    bufferViews: [
      { buffer: 0, byteOffset: positions, byteLength: 12 * count, target: 34962 },
      { buffer: 0, byteOffset: normals, byteLength: 12 * count, target: 34962 },
      { buffer: 0, byteOffset: texcoords, byteLength: 8 * count, target: 34962 },
      { buffer: 0, byteOffset: triangleBytes, byteLength: 2 * triangles.length, target: 34963 },
      { buffer: 0, byteOffset: image, byteLength: Buffer.from(checkerPng, 'base64').length },
    ],
    buffers: [{ byteLength: bin.length, uri: bin.dataUri() }],
  };
  writeFileSync(join(out, 'textured_grid.gltf'), JSON.stringify(doc, null, 1) + '\n');
}

writeTetraSparseScenes();
writeGpuInstancing();
writeTexturedGrid();
