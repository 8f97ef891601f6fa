#!/usr/bin/env python3
"""Simulated scans of an OBJ mesh: what a structured-light or laser scanner on a turntable hands
over, unlike the uniform samplings of the genus sweep. Each of VIEWS cameras (around the object,
none from below unless FROM_BELOW) sees the surface through a depth buffer, so concavities it
cannot see into, the underside and faces at grazing angles (> 75° from the ray) are missing; it
samples what it sees on its own pixel grid (density falls with distance and slant), with depth
noise along its rays; each view is registered with a small rigid error; a few flying pixels
(points along a ray, between a silhouette edge and what lies behind it) and stray points in the
box are added. Binary little-endian PLY, no normals; deterministic for a seed.

Usage: scan.py IN.obj OUT.ply [--points N] [--views V] [--noise F] [--misregister F]
               [--outliers F] [--below] [--seed S]
  N: about how many points in all (default 200 000); F: fractions of the bounding-box
  diagonal (noise sigma 0.0005, misregistration 0.0005) or of N (outliers 0.001).
Needs: numpy."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "peers"))
from sample_obj import read_obj, write_ply  # noqa: E402

GRAZING_COS = np.cos(np.radians(75.0))


def dense_samples(verts, tris, n, rng):
    """n points uniformly by area, with their faces' unit normals."""
    a, b, c = verts[tris[:, 0]], verts[tris[:, 1]], verts[tris[:, 2]]
    cross = np.cross(b - a, c - a)
    area = 0.5 * np.linalg.norm(cross, axis=1)
    normal = cross / np.maximum(2.0 * area, 1e-300)[:, None]
    face = rng.choice(len(tris), size=n, p=area / area.sum())
    u, v = rng.random(n), rng.random(n)
    flip = u + v > 1.0
    u[flip], v[flip] = 1.0 - u[flip], 1.0 - v[flip]
    p = a[face] + u[:, None] * (b - a)[face] + v[:, None] * (c - a)[face]
    return p, normal[face]


def rotation(axis, angle):
    axis = axis / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * k @ k


def cameras(views, below, centre, diag):
    """Camera positions: a ring at two elevations (and one below, if asked), 1.5 diagonals out."""
    out = []
    for i in range(views):
        az = 2 * np.pi * i / views
        el = np.radians(-35.0 if below and i % 4 == 3 else (15.0 if i % 2 == 0 else 45.0))
        d = np.array([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)])
        out.append(centre + 1.5 * diag * d)
    return out


def view(p, n, eye, centre, diag, pixels, depth_tol, noise, rng):
    """The points one camera at `eye` keeps: front-most within a pixel of its depth buffer, not
    at a grazing angle, one per scan pixel, moved along the ray by the depth noise."""
    fwd = centre - eye
    fwd /= np.linalg.norm(fwd)
    up = np.array([0.0, 0.0, 1.0]) if abs(fwd[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    up = np.cross(right, fwd)
    rel = p - eye
    depth = rel @ fwd
    ray = rel / np.linalg.norm(rel, axis=1)[:, None]
    facing = -(n * ray).sum(axis=1)
    fov = 0.55 / 1.5  # tangent of the half angle: the object (half a diagonal across) fills it
    x = (rel @ right) / depth / fov
    y = (rel @ up) / depth / fov
    ok = (depth > 0) & (np.abs(x) < 1) & (np.abs(y) < 1)

    def pixel(res):
        ix = ((x + 1) * 0.5 * res).astype(np.int64).clip(0, res - 1)
        iy = ((y + 1) * 0.5 * res).astype(np.int64).clip(0, res - 1)
        return iy * res + ix

    # Depth buffer from the dense samples, at a resolution where each pixel on the object gets
    # several; a point is seen when no sample in its pixel or the ones beside it lies in front
    # by more than the depth a slanted face spans over those pixels (a back point behind a gap
    # in the dense samples would otherwise show through).
    zres = int(np.sqrt(len(p) / 40.0))
    zpix = pixel(zres)
    zbuf = np.full(zres * zres, np.inf)
    np.minimum.at(zbuf, zpix[ok], depth[ok])
    zb = zbuf.reshape(zres, zres)
    near = zb.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near = np.minimum(near, np.roll(np.roll(zb, dy, 0), dx, 1))
    width = 2.0 * fov * depth / zres
    slant = np.sqrt(np.maximum(1.0 - facing**2, 0.0)) / np.maximum(facing, GRAZING_COS)
    front = depth <= near.reshape(-1)[zpix] + depth_tol + 3.0 * width * slant
    seen = ok & front & (facing > GRAZING_COS)
    pix = pixel(pixels)
    idx = np.nonzero(seen)[0]
    # One point per pixel (the first of a random order: any visible sample of the pixel).
    idx = idx[rng.permutation(len(idx))]
    _, first = np.unique(pix[idx], return_index=True)
    idx = idx[first]
    q = p[idx] + ray[idx] * rng.normal(0.0, noise * diag, len(idx))[:, None]
    return q, ray[idx]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("src")
    ap.add_argument("dst")
    ap.add_argument("--points", type=int, default=200_000)
    ap.add_argument("--views", type=int, default=8)
    ap.add_argument("--noise", type=float, default=0.0005)
    ap.add_argument("--misregister", type=float, default=0.0005)
    ap.add_argument("--outliers", type=float, default=0.001)
    ap.add_argument("--below", action="store_true")
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    verts, tris = read_obj(a.src)
    verts, tris = np.asarray(verts, float), np.asarray(tris, np.int64)
    lo, hi = verts.min(axis=0), verts.max(axis=0)
    centre, diag = 0.5 * (lo + hi), float(np.linalg.norm(hi - lo))
    # Enough dense samples that each scan pixel on the object gets several; the pixel grid set
    # by a trial view so that the views give about N points in all.
    p, n = dense_samples(verts, tris, 16 * a.points, rng)
    eyes = cameras(a.views, a.below, centre, diag)
    trial = 256
    got = sum(len(view(p, n, e, centre, diag, trial, 0.002 * diag, 0.0, rng)[0]) for e in eyes)
    pixels = int(trial * np.sqrt(a.points / max(got, 1)))
    clouds = []
    for eye in eyes:
        q, ray = view(p, n, eye, centre, diag, pixels, 0.002 * diag, a.noise, rng)
        # Flying pixels: 0.2 % of a view's points pulled back along their ray by up to 5 %.
        k = max(1, len(q) // 500)
        pick = rng.choice(len(q), size=k, replace=False)
        q[pick] += ray[pick] * (rng.random(k) * 0.05 * diag)[:, None]
        # Registration error: a small turn about a random axis through the centre, and a shift.
        turn = rotation(rng.normal(size=3), a.misregister * rng.normal())
        shift = a.misregister * diag * rng.normal(size=3) / np.sqrt(3)
        clouds.append((q - centre) @ turn.T + centre + shift)
    cloud = np.concatenate(clouds)
    k = int(a.outliers * len(cloud))
    box = lo - 0.1 * (hi - lo), hi + 0.1 * (hi - lo)
    cloud = np.concatenate([cloud, box[0] + rng.random((k, 3)) * (box[1] - box[0])])
    cloud = cloud[rng.permutation(len(cloud))]
    write_ply(a.dst, len(cloud), cloud.astype("<f4").tobytes())
    print(f"{a.dst}: {len(cloud)} points, {a.views} views, {k} outliers", file=sys.stderr)


if __name__ == "__main__":
    main()
