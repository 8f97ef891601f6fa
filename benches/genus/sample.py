#!/usr/bin/env python3
"""Samples N points uniformly (by area) on an OBJ mesh, with optional Gaussian noise (sigma as a
fraction of the bounding-box diagonal) and an optional random rotation: the unseen inputs of
the genus sweep (sweep.sh). Binary little-endian PLY, no normals; deterministic for a seed.
Usage: sample.py IN.obj N OUT.ply SEED NOISE_FRACTION ROTATE(0|1)"""
import math
import os
import random
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers"))
from sample_obj import area_table, read_obj, sample_point, write_ply  # noqa: E402


def main():
    src, n, dst = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    seed, noise, rotate = int(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
    rng = random.Random(seed)
    verts, tris = read_obj(src)
    cum, total = area_table(verts, tris)
    lo = [min(p[i] for p in verts) for i in range(3)]
    hi = [max(p[i] for p in verts) for i in range(3)]
    sigma = noise * math.dist(lo, hi)
    if rotate:
        q = [rng.gauss(0, 1) for _ in range(4)]
        norm = math.sqrt(sum(x * x for x in q))
        w, x, y, z = (t / norm for t in q)
        rot = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
               [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
               [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    else:
        rot = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
    out = bytearray()
    for _ in range(n):
        p = sample_point(rng, verts, tris, cum, total)
        if sigma > 0:
            p = [x + rng.gauss(0, sigma) for x in p]
        out += struct.pack("<3f", *(sum(rot[i][j] * p[j] for j in range(3)) for i in range(3)))
    write_ply(dst, n, out)


if __name__ == "__main__":
    main()
