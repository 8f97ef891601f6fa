#!/usr/bin/env python3
"""Samples N points uniformly (by area) on an OBJ mesh, with optional Gaussian noise (sigma as a
fraction of the bounding-box diagonal) and an optional random rotation: the unseen inputs of
the genus sweep (sweep.sh). Binary little-endian PLY, no normals; deterministic for a seed.
Usage: sample.py IN.obj N OUT.ply SEED NOISE_FRACTION ROTATE(0|1)"""
import bisect
import math
import random
import struct
import sys


def main():
    src, n, dst = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    seed, noise, rotate = int(sys.argv[4]), float(sys.argv[5]), int(sys.argv[6])
    rng = random.Random(seed)
    verts, tris = [], []
    for line in open(src):
        if line.startswith("v "):
            verts.append(tuple(map(float, line.split()[1:4])))
        elif line.startswith("f "):
            idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
            tris += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    cum, total = [], 0.0
    for a, b, c in tris:
        pa, pb, pc = verts[a], verts[b], verts[c]
        u = [pb[i] - pa[i] for i in range(3)]
        v = [pc[i] - pa[i] for i in range(3)]
        cx = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        total += 0.5 * math.sqrt(sum(x * x for x in cx))
        cum.append(total)
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
        a, b, c = (verts[i] for i in tris[bisect.bisect_left(cum, rng.random() * total)])
        r1, r2 = rng.random(), rng.random()
        if r1 + r2 > 1:
            r1, r2 = 1 - r1, 1 - r2
        p = [a[i] + r1 * (b[i] - a[i]) + r2 * (c[i] - a[i]) + (rng.gauss(0, sigma) if sigma > 0 else 0)
             for i in range(3)]
        out += struct.pack("<3f", *(sum(rot[i][j] * p[j] for j in range(3)) for i in range(3)))
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\n"
              "property float x\nproperty float y\nproperty float z\nend_header\n")
    with open(dst, "wb") as f:
        f.write(header.encode() + out)


if __name__ == "__main__":
    main()
