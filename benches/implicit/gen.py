#!/usr/bin/env python3
"""Implicit test shapes as NRRD intensity volumes (inside 1, outside 0, a one-cell ramp between),
for run.sh. Usage: gen.py NAME N OUT.nrrd (an N³ grid over the shape's box), or gen.py --list
(each name and the genus of its surface). Pure Python, deterministic."""
import math, struct, sys

def sd_box(x, y, z, a, b, c):
    qx, qy, qz = abs(x) - a, abs(y) - b, abs(z) - c
    out = math.sqrt(max(qx, 0) ** 2 + max(qy, 0) ** 2 + max(qz, 0) ** 2)
    return out + min(max(qx, qy, qz), 0)

def sd_torus(x, y, z, R, r):
    q = math.hypot(x, y) - R
    return math.hypot(q, z) - r

def sd_cyl_z(x, y, z, r, h):
    dx, dz = math.hypot(x, y) - r, abs(z) - h
    return min(max(dx, dz), 0) + math.hypot(max(dx, 0), max(dz, 0))

def seg(x, y, z, a, b, r):
    px, py, pz = x - a[0], y - a[1], z - a[2]
    bx, by, bz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    t = max(0, min(1, (px * bx + py * by + pz * bz) / (bx * bx + by * by + bz * bz)))
    return math.dist((px, py, pz), (t * bx, t * by, t * bz)) - r

def smin(a, b, k):
    h = max(k - abs(a - b), 0) / k
    return min(a, b) - h * h * k * 0.25

def gear(x, y, z):
    r = math.hypot(x, y); th = math.atan2(y, x)
    tooth = 0.08 if math.cos(16 * th) > 0 else -0.02
    return max(abs(z) - 0.1, r - (0.85 + tooth), 0.3 - r)

def pipe(x, y, z):
    r = math.hypot(x, y)
    return max(abs(z) - 1.0, r - 0.5, 0.35 - r)

def bottle(x, y, z):
    # capsule shell with an open neck on top
    body = seg(x, y, z, (0, 0, -0.5), (0, 0, 0.3), 0.5)
    shell = max(body, -(body + 0.05))
    neck = sd_cyl_z(x, y, z - 0.75, 0.2, 0.3)
    neckshell = max(neck, -sd_cyl_z(x, y, z - 0.75, 0.15, 0.5))
    s = min(shell, neckshell)
    return max(s, -sd_cyl_z(x, y, z - 0.6, 0.15, 0.6))

def ribbon(x, y, z):
    a = 0.5 * math.pi * (x + 1.0) / 2.0 * 2  # half turn over [-1, 1]
    c, s = math.cos(a), math.sin(a)
    yy, zz = c * y + s * z, -s * y + c * z
    return sd_box(x, yy, zz, 1.0, 0.3, 0.02)

def washer(x, y, z):
    r = math.hypot(x, y)
    return max(abs(z) - 0.02, r - 0.9, 0.35 - r)

def hourglass(x, y, z):
    r = math.hypot(x, y)
    cone = r - (0.04 + 0.6 * abs(z))
    return max(cone, abs(z) - 0.8)

def spiky(x, y, z):
    d = math.sqrt(x * x + y * y + z * z) - 0.5
    n = 24
    ga = math.pi * (3 - math.sqrt(5))
    for i in range(n):
        zz = 1 - 2 * (i + 0.5) / n
        rr = math.sqrt(1 - zz * zz)
        dx, dy, dz = rr * math.cos(ga * i), rr * math.sin(ga * i), zz
        t = x * dx + y * dy + z * dz
        if t <= 0:
            continue
        px, py, pz = x - t * dx, y - t * dy, z - t * dz
        radial = math.sqrt(px * px + py * py + pz * pz)
        cone = radial - 0.18 * max(0.0, 1.0 - t / 0.95)
        d = min(d, max(cone, t - 0.95, 0.3 - t))
    return d

def thin_torus(x, y, z):
    return sd_torus(x, y, z, 0.8, 0.05)

def var_torus(x, y, z):
    th = math.atan2(y, x)
    return sd_torus(x, y, z, 0.6, 0.08 + 0.18 * (1 + math.cos(th)) / 2)

def pits(x, y, z):
    d = sd_box(x, y, z, 0.6, 0.6, 0.6)
    for ax in range(3):
        for s in (-1, 1):
            p = [x, y, z]
            c = [0, 0, 0]; c[ax] = s * 0.6
            q = [p[i] - c[i] for i in range(3)]
            # cylinder along ax, radius .15, depth .4 into the box
            rad = math.hypot(*[q[i] for i in range(3) if i != ax])
            d = max(d, -max(rad - 0.15, abs(q[ax]) - 0.4))
    return d

def bowl(x, y, z):
    r = math.sqrt(x * x + y * y + z * z)
    shell = abs(r - 0.8) - 0.03
    return max(shell, z)

def tripod(x, y, z):
    d = 1e9
    for k in range(3):
        a = 2 * math.pi * k / 3
        d = smin(d, seg(x, y, z, (0, 0, 0.2), (0.9 * math.cos(a), 0.9 * math.sin(a), -0.6), 0.08), 0.1)
    return d

def utunnel(x, y, z):
    ball = math.sqrt(x * x + y * y + z * z) - 0.8
    # U-shaped tunnel: two vertical legs joined by a bend near the bottom, entering the top
    t = min(seg(x, y, z, (-0.3, 0, 1.0), (-0.3, 0, -0.2), 0.12),
            seg(x, y, z, (0.3, 0, 1.0), (0.3, 0, -0.2), 0.12),
            seg(x, y, z, (-0.3, 0, -0.2), (0.3, 0, -0.2), 0.12))
    return max(ball, -t)

def small_hole(x, y, z):
    return sd_torus(x, y, z, 0.5, 0.44)

def linked(x, y, z):
    a = sd_torus(x + 0.25, y, z, 0.5, 0.12)
    b = sd_torus(x - 0.25, z, y, 0.5, 0.12)
    return min(a, b)

def bead(x, y, z):
    return max(math.sqrt(x * x + y * y + z * z) - 0.8, -(math.hypot(x, y) - 0.07))

def cube_with(x, y, z, holes):
    """A cube of half-side 0.7 less `holes`, each (axis, cut) with cut(u, v) the distance in the
    plane across that axis (negative inside the hole)."""
    q = (x, y, z)
    d = max(abs(x), abs(y), abs(z)) - 0.7
    for ax, cut in holes:
        u, v = (q[i] for i in range(3) if i != ax)
        d = max(d, -cut(u, v))
    return d

def square_tunnels(w):
    """Square tunnels 2w wide along all three axes (w 0.58: a frame of bars 0.12 thick)."""
    cut = lambda u, v: max(abs(u), abs(v)) - w
    return lambda x, y, z: cube_with(x, y, z, [(a, cut) for a in range(3)])

def round_bores(r, axes):
    cut = lambda u, v: math.hypot(u, v) - r
    return lambda x, y, z: cube_with(x, y, z, [(a, cut) for a in axes])

def sieve(x, y, z):
    """A spherical shell (radius 0.75, 0.12 thick) with six round holes (radius 0.25)."""
    q = (x, y, z)
    d = abs(math.sqrt(x * x + y * y + z * z) - 0.75) - 0.06
    for ax in range(3):
        u, v = (q[i] for i in range(3) if i != ax)
        d = max(d, -(math.hypot(u, v) - 0.25))
    return d

SHAPES = {
    "gear": (gear, 1.2, 1), "pipe": (pipe, 1.2, 1), "bottle": (bottle, 1.2, 0),
    "ribbon": (ribbon, 1.2, 0), "washer": (washer, 1.2, 1), "hourglass": (hourglass, 1.0, 0),
    "spiky": (spiky, 1.1, 0), "thin-torus": (thin_torus, 1.0, 1), "var-torus": (var_torus, 1.0, 1),
    "pits": (pits, 0.8, 0), "bowl": (bowl, 1.0, 0), "tripod": (tripod, 1.1, 0),
    "u-tunnel": (utunnel, 1.0, 1), "small-hole": (small_hole, 1.0, 1),
    "linked": (linked, 1.0, 2), "bead": (bead, 1.0, 1),
    # Holes that meet inside the shape (thirty-third session).
    "frame": (square_tunnels(0.58), 0.85, 5), "tunnels-0.6": (square_tunnels(0.3), 0.85, 5),
    "tunnels-0.9": (square_tunnels(0.45), 0.85, 5), "tunnels-1.1": (square_tunnels(0.55), 0.85, 5),
    "bores-2": (round_bores(0.3, [0, 2]), 0.85, 3), "bores-3": (round_bores(0.3, [0, 1, 2]), 0.85, 5),
    "sieve": (sieve, 0.9, 5),
}

def main():
    name, n, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
    f, ext, _ = SHAPES[name]
    h = 2 * ext / (n - 1)
    vals = bytearray()
    for k in range(n):
        z = -ext + k * h
        for j in range(n):
            y = -ext + j * h
            row = []
            for i in range(n):
                x = -ext + i * h
                d = f(x, y, z)
                row.append(min(1.0, max(0.0, 0.5 - d / (2 * h))))
            vals += struct.pack("<%df" % n, *row)
    write_nrrd(out, n, ext, vals)

def write_nrrd(out, n, ext, vals):
    """An n³ float volume over [-ext, ext]³ (`vals`: little-endian f32 bytes, x fastest)."""
    h = 2 * ext / (n - 1)
    hdr = ("NRRD0004\ntype: float\ndimension: 3\nsizes: %d %d %d\nspace: left-posterior-superior\n"
           "space directions: (%g,0,0) (0,%g,0) (0,0,%g)\nspace origin: (%g,%g,%g)\nencoding: raw\nendian: little\n\n"
           % (n, n, n, h, h, h, -ext, -ext, -ext))
    open(out, "wb").write(hdr.encode() + vals)

if __name__ == "__main__":
    if sys.argv[1] == "--list":
        for k, v in SHAPES.items():
            print(k, v[2])
    else:
        main()
