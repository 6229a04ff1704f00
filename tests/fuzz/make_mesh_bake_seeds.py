#!/usr/bin/env python3
"""Writes the seed corpus of mesh_bake_fuzz (tests/data/fuzz/mesh_bake_fuzz/) in the layout
mesh_bake_fuzz.cpp decodes: K, padding, flags, vertex count, float vertices, indices.
Run from the repository root: python3 tests/fuzz/make_mesh_bake_seeds.py"""
import struct

OUT = "tests/data/fuzz/mesh_bake_fuzz/"


def seed(name, k, padding, flags, vertices, triangles, wide=False):
    data = bytes([k - 4, padding, flags | (8 if wide else 0), len(vertices) - 1])
    for v in vertices:
        data += struct.pack("<3f", *v)
    for t in triangles:
        for i in t:
            data += struct.pack("<I", i) if wide else bytes([i])
    with open(OUT + name, "wb") as f:
        f.write(data)


tet = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)]
tet_t = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
cube = [(x, y, z) for z in (0, 1) for y in (0, 1) for x in (0, 1)]
cube_t = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
          (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
seed("tetrahedron_k8.bin", 8, 1, 0, tet, tet_t)
seed("cube_k10_narrow_refine2.bin", 10, 2, 1 | 4, cube, cube_t)  # narrow band, refinement depth 2
seed("tetrahedron_k6_wide_indices.bin", 6, 0, 0, tet, tet_t, wide=True)
seed("open_triangle_k5.bin", 5, 1, 0, tet[:3], [(0, 1, 2)])  # an open sheet: no volume
seed("open_triangle_shell_k6.bin", 6, 1, 32 | 64, tet[:3], [(0, 1, 2)])  # a shell 2^-4 thick: bakes
# A triangle 1e-45 across in a shell 16 thick: grid points 1e46 of its sizes away overflowed the
# closest-point tree's float coordinates (a crash, found by the replay's mutations).
seed("denormal_triangle_thick_shell_k5.bin", 5, 1, 1 | 32 | 128, [(1.4e-45, 0, 0), (0, 1.4e-45, 0), (0, 0, 1.4e-45)],
     [(0, 1, 2)])
