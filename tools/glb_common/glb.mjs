// GLB (binary glTF) writing shared by the asset tools: header, JSON chunk, BIN chunk, and the
// accessor bounds glTF requires. Deterministic: the same document and bytes give the same file.
export const GLB_MAGIC = 0x46546c67; // "glTF"
export const CHUNK_JSON = 0x4e4f534a; // "JSON"
export const CHUNK_BIN = 0x004e4942; // "BIN\0"

export function float32Bounds(vectors) {
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  for (const v of vectors) {
    for (let i = 0; i < 3; i++) {
      const f = Math.fround(v[i]); // glTF requires min/max to equal the stored float32 values
      min[i] = Math.min(min[i], f);
      max[i] = Math.max(max[i], f);
    }
  }
  return { min, max };
}

export function padTo4(buffer, fill) {
  const padded = Buffer.alloc(Math.ceil(buffer.length / 4) * 4, fill);
  buffer.copy(padded);
  return padded;
}

function chunk(type, payload) {
  const header = Buffer.alloc(8);
  header.writeUInt32LE(payload.length, 0);
  header.writeUInt32LE(type, 4);
  return Buffer.concat([header, payload]);
}

// The GLB of a glTF document whose buffer 0 is `bin`.
export function glbBytes(gltf, bin) {
  const jsonChunk = chunk(CHUNK_JSON, padTo4(Buffer.from(JSON.stringify(gltf), 'utf8'), 0x20));
  const binChunk = chunk(CHUNK_BIN, padTo4(bin, 0));
  const header = Buffer.alloc(12);
  header.writeUInt32LE(GLB_MAGIC, 0);
  header.writeUInt32LE(2, 4);
  header.writeUInt32LE(12 + jsonChunk.length + binChunk.length, 8);
  return Buffer.concat([header, jsonChunk, binChunk]);
}

// The JSON document and BIN chunk of a GLB (as the tools write them: JSON first, then BIN).
export function readGlb(bytes) {
  if (bytes.readUInt32LE(0) !== GLB_MAGIC) throw new Error('not a GLB file');
  const jsonLength = bytes.readUInt32LE(12);
  if (bytes.readUInt32LE(16) !== CHUNK_JSON) throw new Error('GLB: first chunk is not JSON');
  const gltf = JSON.parse(bytes.subarray(20, 20 + jsonLength).toString('utf8'));
  const binStart = 20 + jsonLength;
  if (bytes.readUInt32LE(binStart + 4) !== CHUNK_BIN) throw new Error('GLB: second chunk is not BIN');
  const bin = bytes.subarray(binStart + 8, binStart + 8 + bytes.readUInt32LE(binStart));
  return { gltf, bin };
}
