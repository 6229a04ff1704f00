#!/usr/bin/env bash
# Makes the glTF test files of tests/data/gltf/ that come from npm tools, then validates every valid
# glTF file there with the Khronos validator and writes tests/data/gltf/validation.json.
#   cd tools/gltf_testdata && npm ci && ./make_testdata.sh
set -euo pipefail
cd "$(dirname "$0")"
src=../../samples/assets/bunny.glb
out=../../tests/data/gltf
bin=node_modules/.bin

# A small closed bunny (292 triangles, 148 vertices): meshoptimizer's simplifier via glTF-Transform.
$bin/gltf-transform simplify "$src" "$out/bunny_small.glb" --ratio 0.08 --error 0.02
# The same mesh compressed / quantized as web-delivered files are.
$bin/gltf-pipeline -i "$out/bunny_small.glb" -o "$out/bunny_small_draco.glb" -d
$bin/gltf-transform meshopt "$out/bunny_small.glb" "$out/bunny_small_meshopt.glb"
$bin/gltf-transform quantize "$out/bunny_small.glb" "$out/bunny_small_quantized.glb"
# Sparse accessors, two scenes, an ignored extension; an unsupported required extension.
node make_structural.mjs "$out"
# A textured mesh through Draco (TEXCOORD_0 compressed with the positions and normals).
$bin/gltf-pipeline -i "$out/textured_grid.gltf" -o "$out/textured_grid_draco.glb" -d
# The same through gltfpack (Debian's gltfpack 0.18, `apt-get install gltfpack`: not an npm tool):
# quantized texture coordinates undone by KHR_texture_transform.
gltfpack -i "$out/textured_grid.gltf" -o "$out/textured_grid_gltfpack.glb"
# A red cube behind a glass pane (alphaMode BLEND), and the pane alone: see-through meshes in a
# scene drawn as one SDF.
python3 make_panes.py "$out"
# A door node swung by a translation and a rotation channel (animation 'swing').
python3 make_animated.py "$out"

# Every valid file of the folder (the deliberately broken ones are listed in the README).
valid=(hierarchy.gltf flat_square.gltf tilted_cube.gltf tilted_cube_2e-17.gltf tilted_cube_2e100.gltf
       bunny_small.glb bunny_small_draco.glb bunny_small_meshopt.glb bunny_small_quantized.glb
       tetra_sparse_scenes.gltf gpu_instancing.gltf thin_slab.gltf camera_cube.gltf textured_grid.gltf
       textured_grid_draco.glb textured_grid_gltfpack.glb pane_before_cube.gltf pane_only.gltf swinging_door.gltf)
node validate.mjs "$out/validation.json" "${valid[@]/#/$out/}"
