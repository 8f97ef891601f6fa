#!/usr/bin/env python3
"""More implicit test shapes for run.sh (`GEN=benches/implicit/more.py`), as NRRD intensity
volumes like gen.py's: a trefoil knot whose strands pass 0.12 apart, a coil spring, a wheel with
five spokes, a mug, two overlapping balls, a grate with nine square holes, a thick Moebius band,
and a 2 x 2 x 2 lattice of bars (genus 28). Usage: more.py NAME N OUT.nrrd, or more.py --list
(each name and the genus of its surface). Needs numpy (the curves' distances by segment)."""
import os, sys, numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gen import write_nrrd  # noqa: E402

def seg_d(P, a, b, r):
    a = np.asarray(a, float); b = np.asarray(b, float)
    ba = b - a; pa = P - a
    t = np.clip((pa @ ba) / (ba @ ba), 0, 1)
    return np.linalg.norm(pa - t[..., None] * ba, axis=-1) - r

def poly_d(P, pts, r, closed):
    d = np.full(P.shape[:-1], 1e9)
    n = len(pts)
    for i in range(n if closed else n - 1):
        d = np.minimum(d, seg_d(P, pts[i], pts[(i + 1) % n], 0))
    return d - r

def torus(P, R, r, c=(0, 0, 0)):
    Q = P - np.asarray(c, float)
    q = np.hypot(Q[..., 0], Q[..., 1]) - R
    return np.hypot(q, Q[..., 2]) - r

def box(P, h, c=(0, 0, 0)):
    q = np.abs(P - np.asarray(c, float)) - np.asarray(h, float)
    out = np.linalg.norm(np.maximum(q, 0), axis=-1)
    return out + np.minimum(q.max(axis=-1), 0)

def trefoil(P):
    t = np.linspace(0, 2 * np.pi, 240, endpoint=False)
    c = np.stack([np.sin(t) + 2 * np.sin(2 * t), np.cos(t) - 2 * np.cos(2 * t), -np.sin(3 * t)], -1) * 0.3
    return poly_d(P, c, 0.12, True)

def spring(P):
    t = np.linspace(0, 4 * 2 * np.pi, 320)
    c = np.stack([0.5 * np.cos(t), 0.5 * np.sin(t), -0.8 + 1.6 * t / t[-1]], -1)
    return poly_d(P, c, 0.08, False)

def wheel(P):
    d = torus(P, 0.8, 0.08)
    hub = np.maximum(np.hypot(P[..., 0], P[..., 1]) - 0.15, np.abs(P[..., 2]) - 0.1)
    d = np.minimum(d, hub)
    for k in range(5):
        a = 2 * np.pi * k / 5
        d = np.minimum(d, seg_d(P, (0.1 * np.cos(a), 0.1 * np.sin(a), 0), (0.8 * np.cos(a), 0.8 * np.sin(a), 0), 0.05))
    return d

def mug(P):
    r = np.hypot(P[..., 0], P[..., 1]); z = P[..., 2]
    outer = np.maximum(r - 0.5, np.abs(z) - 0.45)
    inner = np.maximum(r - 0.44, -(z + 0.39))
    cup = np.maximum(outer, -inner)
    Q = P.copy(); Q[..., 0] -= 0.55
    Q2 = np.stack([Q[..., 0], Q[..., 2], Q[..., 1]], -1)
    handle = np.maximum(torus(Q2, 0.25, 0.05), -Q[..., 0] - 0.0)
    return np.minimum(cup, handle)

def kissing(P):
    a = np.linalg.norm(P - [0.46, 0, 0], axis=-1) - 0.5
    b = np.linalg.norm(P - [-0.46, 0, 0], axis=-1) - 0.5
    return np.minimum(a, b)

def grate(P):
    d = box(P, (0.8, 0.8, 0.1))
    for i in (-1, 0, 1):
        for j in (-1, 0, 1):
            d = np.maximum(d, -box(P, (0.14, 0.14, 1.0), (0.5 * i, 0.5 * j, 0)))
    return d

def mobius(P):
    # a thick band whose cross-section (0.5 x 0.1 rectangle) turns half a turn round the loop
    x, y, z = P[..., 0], P[..., 1], P[..., 2]
    th = np.arctan2(y, x); rr = np.hypot(x, y) - 0.7
    a = th / 2
    u = np.cos(a) * rr + np.sin(a) * z
    v = -np.sin(a) * rr + np.cos(a) * z
    return np.maximum(np.abs(u) - 0.25, np.abs(v) - 0.05) * 0.8

def lattice(P):
    # a 2x2x2 cell cubic lattice of bars (genus: 3x3x3 nodes, 54 bars -> 54 - 27 + 1 = 28)
    d = np.full(P.shape[:-1], 1e9)
    g = (-0.7, 0.0, 0.7)
    for a in g:
        for b in g:
            d = np.minimum(d, seg_d(P, (-0.7, a, b), (0.7, a, b), 0.07))
            d = np.minimum(d, seg_d(P, (a, -0.7, b), (a, 0.7, b), 0.07))
            d = np.minimum(d, seg_d(P, (a, b, -0.7), (a, b, 0.7), 0.07))
    return d

SHAPES = {"trefoil": (trefoil, 1.1, 1), "spring": (spring, 1.0, 0), "wheel": (wheel, 1.0, 5),
          "mug": (mug, 0.95, 1), "kissing": (kissing, 1.05, 0), "grate": (grate, 1.0, 9),
          "mobius": (mobius, 1.1, 1), "lattice": (lattice, 0.9, 28)}

def main():
    name, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    f, ext, _ = SHAPES[name]
    h = 2 * ext / (n - 1)
    ax = -ext + h * np.arange(n)
    Z, Y, X = np.meshgrid(ax, ax, ax, indexing="ij")
    P = np.stack([X, Y, Z], -1)
    d = f(P)
    vals = np.clip(0.5 - d / (2 * h), 0, 1).astype("<f4")
    write_nrrd(out, n, ext, vals.tobytes())

if __name__ == "__main__":
    if sys.argv[1] == "--list":
        for k, v in SHAPES.items():
            print(k, v[2])
    else:
        main()
