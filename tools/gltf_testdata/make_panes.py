# Writes pane_before_cube.gltf and pane_only.gltf into the folder given (tests/data/gltf/README.md):
#   python3 make_panes.py ../../tests/data/gltf
import base64, json, struct, sys

def box(lo, hi):
    faces = [((0, -1), 'x'), ((0, 1), 'x'), ((1, -1), 'y'), ((1, 1), 'y'), ((2, -1), 'z'), ((2, 1), 'z')]
    pos, nrm, idx = [], [], []
    for (axis, sign), _ in faces:
        u, v = [a for a in range(3) if a != axis]
        base = len(pos)
        for du, dv in ((0, 0), (1, 0), (1, 1), (0, 1)):
            p = [0.0] * 3
            p[axis] = hi[axis] if sign > 0 else lo[axis]
            p[u] = hi[u] if du else lo[u]
            p[v] = hi[v] if dv else lo[v]
            n = [0.0] * 3
            n[axis] = float(sign)
            pos.append(p)
            nrm.append(n)
        # counter-clockwise seen from outside: (u x v) points along +axis for cyclic (axis, u, v)
        cyclic = (u - axis) % 3 == 1
        quad = [0, 1, 2, 0, 2, 3] if (sign > 0) == cyclic else [0, 2, 1, 0, 3, 2]
        idx += [base + i for i in quad]
    return pos, nrm, idx

def write(path, parts):
    blob, views, accessors, meshes, nodes, materials = b'', [], [], [], [], []
    for name, lo, hi, colour, blend in parts:
        pos, nrm, idx = box(lo, hi)
        entries = []
        for data, fmt, kind, target in ((pos, 'f', 'VEC3', 34962), (nrm, 'f', 'VEC3', 34962), (idx, 'H', 'SCALAR', 34963)):
            flat = [c for row in data for c in row] if kind == 'VEC3' else data
            raw = struct.pack('<%d%s' % (len(flat), fmt), *flat)
            raw += b'\0' * (-len(raw) % 4)
            views.append({'buffer': 0, 'byteOffset': len(blob), 'byteLength': len(raw), 'target': target})
            blob += raw
            acc = {'bufferView': len(views) - 1, 'componentType': 5126 if fmt == 'f' else 5123,
                   'count': len(data), 'type': kind}
            if data is pos:
                acc['min'] = [min(p[a] for p in pos) for a in range(3)]
                acc['max'] = [max(p[a] for p in pos) for a in range(3)]
            accessors.append(acc)
            entries.append(len(accessors) - 1)
        material = {'name': name + '_material', 'pbrMetallicRoughness': {'baseColorFactor': colour, 'metallicFactor': 0.0}}
        if blend: material['alphaMode'] = 'BLEND'
        materials.append(material)
        meshes.append({'name': name, 'primitives': [{'attributes': {'POSITION': entries[0], 'NORMAL': entries[1]},
                                                     'indices': entries[2], 'material': len(materials) - 1}]})
        nodes.append({'name': name, 'mesh': len(meshes) - 1})
    gltf = {'asset': {'version': '2.0', 'generator': 'hermite_sdf tools/gltf_testdata/make_panes.py'},
            'scene': 0, 'scenes': [{'nodes': list(range(len(nodes)))}], 'nodes': nodes, 'meshes': meshes,
            'materials': materials, 'accessors': accessors, 'bufferViews': views,
            'buffers': [{'byteLength': len(blob),
                         'uri': 'data:application/octet-stream;base64,' + base64.b64encode(blob).decode()}]}
    with open(path, 'w') as f:
        json.dump(gltf, f, indent=1)
        f.write('\n')

if __name__ == '__main__':  # make_animated.py imports box()
    out = sys.argv[1]
    cube = ('cube', [-1, -1, -1], [1, 1, 1], [0.9, 0.05, 0.05, 1.0], False)
    pane = ('pane', [-1.5, -1.5, 2.9], [1.5, 1.5, 3.1], [0.6, 0.8, 1.0, 0.3], True)
    write(out + '/pane_before_cube.gltf', [cube, pane])
    write(out + '/pane_only.gltf', [pane])
