# Writes swinging_door.gltf into the folder given (tests/data/gltf/README.md):
#   python3 make_animated.py ../../tests/data/gltf
# A grey floor slab, and a door (a 2 x 1 x 0.2 box from its hinge at x = 0 to x = 2) whose one
# animation 'swing' slides it along x (LINEAR: 0 -> 1 over 2 s) and turns it about y (LINEAR:
# 0 -> 170 degrees over 2 s, far from 180 so that slerp and a normalized lerp disagree by ~7
# degrees at a quarter of the way).
import base64, json, math, struct, sys

from make_panes import box

def pack(fmt, values):
    return b''.join(struct.pack(fmt, *v) if isinstance(v, (list, tuple)) else struct.pack(fmt, v) for v in values)

def main(folder):
    blob, views, accessors, meshes, nodes = b'', [], [], [], []

    def add(data, count, type_, component=5126, target=None, minmax=None):
        nonlocal blob
        while len(blob) % 4:
            blob += b'\0'
        view = {'buffer': 0, 'byteOffset': len(blob), 'byteLength': len(data)}
        if target:
            view['target'] = target
        views.append(view)
        blob += data
        accessor = {'bufferView': len(views) - 1, 'componentType': component, 'count': count, 'type': type_}
        if minmax:
            accessor['min'], accessor['max'] = minmax
        accessors.append(accessor)
        return len(accessors) - 1

    for name, lo, hi in (('floor', (-3, -0.2, -3), (3, 0, 3)), ('door', (0, 0, -0.1), (2, 1, 0.1))):
        pos, nrm, idx = box(lo, hi)
        p = add(pack('<3f', pos), len(pos), 'VEC3', target=34962,
                minmax=([min(v[i] for v in pos) for i in range(3)], [max(v[i] for v in pos) for i in range(3)]))
        n = add(pack('<3f', nrm), len(nrm), 'VEC3', target=34962)
        i = add(pack('<H', idx), len(idx), 'SCALAR', component=5123, target=34963)
        meshes.append({'name': name, 'primitives': [{'attributes': {'POSITION': p, 'NORMAL': n}, 'indices': i}]})
        nodes.append({'name': name, 'mesh': len(meshes) - 1})

    times = add(pack('<f', [0.0, 2.0]), 2, 'SCALAR', minmax=([0.0], [2.0]))
    slide = add(pack('<3f', [(0, 0, 0), (1, 0, 0)]), 2, 'VEC3')
    half = math.radians(170) / 2
    turn = add(pack('<4f', [(0, 0, 0, 1), (0, math.sin(half), 0, math.cos(half))]), 2, 'VEC4')
    animation = {'name': 'swing',
                 'samplers': [{'input': times, 'output': slide, 'interpolation': 'LINEAR'},
                              {'input': times, 'output': turn, 'interpolation': 'LINEAR'}],
                 'channels': [{'sampler': 0, 'target': {'node': 1, 'path': 'translation'}},
                              {'sampler': 1, 'target': {'node': 1, 'path': 'rotation'}}]}
    doc = {'asset': {'version': '2.0', 'generator': 'tools/gltf_testdata/make_animated.py'},
           'scene': 0, 'scenes': [{'nodes': [0, 1]}], 'nodes': nodes, 'meshes': meshes,
           'animations': [animation], 'accessors': accessors, 'bufferViews': views,
           'buffers': [{'byteLength': len(blob),
                        'uri': 'data:application/octet-stream;base64,' + base64.b64encode(blob).decode()}]}
    with open(f'{folder}/swinging_door.gltf', 'w') as f:
        json.dump(doc, f, indent=1)
        f.write('\n')

if __name__ == '__main__':
    main(sys.argv[1])
