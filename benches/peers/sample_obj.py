#!/usr/bin/env python3
"""Samples N points uniformly (by area) on the triangles of an OBJ mesh and writes them as a
binary little-endian PLY point cloud: the stand-in for a dense scan (issue 16's 1 M-point
cloud). Deterministic for a given seed. Usage: sample_obj.py IN.obj N OUT.ply [seed]"""
import bisect
import random
import struct
import sys


def read_obj(src):
    """The vertices and triangles (fans of the faces) of an OBJ file."""
    verts, tris = [], []
    with open(src) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(tuple(map(float, line.split()[1:4])))
            elif line.startswith("f "):
                idx = [int(t.split("/")[0]) - 1 for t in line.split()[1:]]
                tris += [(idx[0], idx[k], idx[k + 1]) for k in range(1, len(idx) - 1)]
    return verts, tris


def area_table(verts, tris):
    """The running sums of the triangles' areas, and the total: pick a triangle by area with
    `bisect_left(table, r * total)`."""
    cum, total = [], 0.0
    for a, b, c in tris:
        pa, pb, pc = verts[a], verts[b], verts[c]
        u = [pb[i] - pa[i] for i in range(3)]
        v = [pc[i] - pa[i] for i in range(3)]
        cx = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
        total += 0.5 * (cx[0] ** 2 + cx[1] ** 2 + cx[2] ** 2) ** 0.5
        cum.append(total)
    return cum, total


def main():
    src, n, dst = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    rng = random.Random(int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    verts, tris = read_obj(src)
    cum, total = area_table(verts, tris)
    out = bytearray()
    for _ in range(n):
        out += struct.pack("<3f", *sample_point(rng, verts, tris, cum, total))
    write_ply(dst, n, out)


def sample_point(rng, verts, tris, cum, total):
    """One point uniform by area (three draws of `rng`)."""
    a, b, c = tris[min(bisect.bisect_left(cum, rng.random() * total), len(tris) - 1)]
    r1, r2 = rng.random(), rng.random()
    if r1 + r2 > 1.0:
        r1, r2 = 1.0 - r1, 1.0 - r2
    pa, pb, pc = verts[a], verts[b], verts[c]
    return [pa[i] + r1 * (pb[i] - pa[i]) + r2 * (pc[i] - pa[i]) for i in range(3)]


def write_ply(dst, n, xyz):
    """A binary little-endian PLY of `n` points whose packed float32 coordinates are `xyz`."""
    header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {n}\n"
              "property float x\nproperty float y\nproperty float z\nend_header\n")
    with open(dst, "wb") as f:
        f.write(header.encode() + xyz)


if __name__ == "__main__":
    main()
