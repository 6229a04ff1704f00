# Writes a GLB of a closed box in two materials (as tests/support/two_material_box.h): the upper
# part (top and sides above y = 0.1) red, the lower part blue; one mesh of two primitives.
import json, struct, sys
H = (1.0, 0.8, 0.6); SPLIT = 0.1
def quads(y0, y1, cap):
    ring = [(-H[0], -H[2]), (H[0], -H[2]), (H[0], H[2]), (-H[0], H[2])]
    out = []
    for s in range(4):
        p, q = ring[s], ring[(s + 1) % 4]
        out.append([(p[0], y0, p[1]), (q[0], y0, q[1]), (q[0], y1, q[1]), (p[0], y1, p[1])])
    out.append([(x, cap, z) for x, z in ring])
    return out
def sub(a, b): return tuple(x - y for x, y in zip(a, b))
def cross(a, b): return (a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0])
def dot(a, b): return sum(x*y for x, y in zip(a, b))
def primitive(qs):
    pos, nrm, idx = [], [], []
    for a, b, c, d in qs:
        n = cross(sub(b, a), sub(c, a)); centre = tuple(sum(v) for v in zip(a, b, c, d))
        out = dot(n, centre) > 0
        base = len(pos); pos += [a, b, c, d]
        l = dot(n, n) ** 0.5; n = tuple((x if out else -x) / l for x in n); nrm += [n] * 4
        idx += [base + i for i in ((0, 1, 2, 0, 2, 3) if out else (0, 2, 1, 0, 3, 2))]
    return pos, nrm, idx
prims = [primitive(quads(SPLIT, H[1], H[1])), primitive(quads(-H[1], SPLIT, -H[1]))]
binary = b""; views = []; accessors = []
def add(data, target, comp, count, typ, mn=None, mx=None):
    global binary
    while len(binary) % 4: binary += b"\0"
    views.append({"buffer": 0, "byteOffset": len(binary), "byteLength": len(data), "target": target})
    binary += data
    acc = {"bufferView": len(views) - 1, "componentType": comp, "count": count, "type": typ}
    if mn is not None: acc["min"], acc["max"] = mn, mx
    accessors.append(acc); return len(accessors) - 1
gltf_prims = []
for m, (pos, nrm, idx) in enumerate(prims):
    p = add(b"".join(struct.pack("<fff", *v) for v in pos), 34962, 5126, len(pos), "VEC3",
            [min(v[i] for v in pos) for i in range(3)], [max(v[i] for v in pos) for i in range(3)])
    n = add(b"".join(struct.pack("<fff", *v) for v in nrm), 34962, 5126, len(nrm), "VEC3")
    i = add(b"".join(struct.pack("<I", v) for v in idx), 34963, 5125, len(idx), "SCALAR")
    gltf_prims.append({"attributes": {"POSITION": p, "NORMAL": n}, "indices": i, "material": m})
while len(binary) % 4: binary += b"\0"
doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
       "nodes": [{"name": "box", "mesh": 0}], "meshes": [{"name": "two_material_box", "primitives": gltf_prims}],
       "materials": [{"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.08, 0.05, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.35}},
                     {"name": "blue", "pbrMetallicRoughness": {"baseColorFactor": [0.05, 0.1, 0.9, 1.0], "metallicFactor": 0.0, "roughnessFactor": 0.7}}],
       "buffers": [{"byteLength": len(binary)}], "bufferViews": views, "accessors": accessors}
js = json.dumps(doc, separators=(",", ":")).encode()
while len(js) % 4: js += b" "
glb = struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(binary))
glb += struct.pack("<II", len(js), 0x4E4F534A) + js + struct.pack("<II", len(binary), 0x004E4942) + binary
open(sys.argv[1], "wb").write(glb)
