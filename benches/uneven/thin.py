#!/usr/bin/env python3
"""Thins a point cloud along x, as a scanner samples a part it sees at a growing angle: each
point is kept with a chance rising linearly from LOW at the lowest x to 1 at the highest.

Usage: thin.py IN.obj OUT.obj LOW [SEED=5]   (reads and writes OBJ `v` lines only)
"""
import random
import sys

src, out, low = sys.argv[1], sys.argv[2], float(sys.argv[3])
seed = int(sys.argv[4]) if len(sys.argv) > 4 else 5
pts = [l.split()[1:4] for l in open(src) if l.startswith("v ")]
xs = [float(p[0]) for p in pts]
lo, hi = min(xs), max(xs)
rng = random.Random(seed)
with open(out, "w") as f:
    for p, x in zip(pts, xs):
        if rng.random() < low + (1 - low) * (x - lo) / (hi - lo):
            f.write("v %s %s %s\n" % tuple(p))
