#!/usr/bin/env python3
"""Clouds sampled uniformly on the surface of a union of boxes: the twelve edge bars of a unit
cube (a frame, or with thick bars a cube drilled along three axes) or the ladder-back chair of
tests/valid_wraps.rs. Points inside another box are dropped. ASCII PLY; deterministic for a seed.
Usage: bars.py frame:H|chair OUT.ply N SEED   (H: the bars' half-width)"""
import random
import sys


def frame(h):
    c, out = 0.5 - h, []
    for axis in range(3):
        for s, t in ((-1, -1), (-1, 1), (1, -1), (1, 1)):
            centre, half = [0.0] * 3, [h] * 3
            centre[(axis + 1) % 3], centre[(axis + 2) % 3], half[axis] = s * c, t * c, 0.5
            out.append((centre, half))
    return out


def chair():
    out = [((0, 0, 0.5), (0.5, 0.5, 0.04))]
    out += [((x, y, 0.23), (0.03, 0.03, 0.23)) for x, y in ((-0.44, -0.44), (-0.44, 0.44), (0.44, -0.44), (0.44, 0.44))]
    out += [((x, 0.46, 0.95), (0.03, 0.03, 0.45)) for x in (-0.44, 0.44)]
    out += [((0, 0.46, z), (0.44, 0.025, 0.025)) for z in (0.85, 1.1, 1.35)]
    return out


def main():
    shape, dst, n, seed = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
    boxes = frame(float(shape.split(":")[1])) if shape.startswith("frame:") else chair()
    rng = random.Random(seed)
    faces = [(b, f) for b in range(len(boxes)) for f in range(3)]
    area = [boxes[b][1][(f + 1) % 3] * boxes[b][1][(f + 2) % 3] for b, f in faces]
    inside = lambda q, c, h: max(abs(q[i] - c[i]) - h[i] for i in range(3)) < -1e-12
    points = []
    while len(points) < n:
        b, f = rng.choices(faces, weights=area)[0]
        c, h = boxes[b]
        q = [c[i] + (2 * rng.random() - 1) * h[i] for i in range(3)]
        q[f] = c[f] + rng.choice((-1, 1)) * h[f]
        if not any(inside(q, c2, h2) for c2, h2 in boxes):
            points.append(q)
    with open(dst, "w") as out:
        out.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                  "property float z\nend_header\n" % n)
        out.writelines("%f %f %f\n" % tuple(q) for q in points)


if __name__ == "__main__":
    main()
