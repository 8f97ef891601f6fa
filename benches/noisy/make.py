"""Noisy synthetic volumes for benches/noisy/sweep.sh: a blob (two ellipsoids) joined to a ring
(a torus), smooth edges, and uniform noise of 0.3, 0.6 or 1.0 times the contrast, on grids of
20, 32 and 48 voxels (2 mm), two seeds each: 18 NIfTI-1 float32 files written to OUT_DIR.
Small noisy scans like these (nibabel's example_nifti2) are where evolutions came apart.

Usage: python3 make.py OUT_DIR
"""
import math
import os
import random
import struct
import sys

OUT = sys.argv[1]
os.makedirs(OUT, exist_ok=True)


def nifti(path, dims, spacing, vals):
    hdr = bytearray(348)
    struct.pack_into('<i', hdr, 0, 348)
    struct.pack_into('<8h', hdr, 40, 3, dims[0], dims[1], dims[2], 1, 1, 1, 1)
    struct.pack_into('<h', hdr, 70, 16)   # float32
    struct.pack_into('<h', hdr, 72, 32)
    struct.pack_into('<8f', hdr, 76, 1.0, spacing, spacing, spacing, 1, 1, 1, 1)
    struct.pack_into('<f', hdr, 108, 352.0)
    struct.pack_into('<f', hdr, 112, 1.0)
    struct.pack_into('<h', hdr, 254, 1)  # sform code
    struct.pack_into('<4f', hdr, 280, spacing, 0, 0, 0)
    struct.pack_into('<4f', hdr, 296, 0, spacing, 0, 0)
    struct.pack_into('<4f', hdr, 312, 0, 0, spacing, 0)
    hdr[344:348] = b'n+1\0'
    with open(path, 'wb') as f:
        f.write(hdr); f.write(b'\0\0\0\0'); f.write(struct.pack(f'<{len(vals)}f', *vals))


def step(d, w):
    return 0.5 - 0.5 * math.tanh(d / w)


for n in (20, 32, 48):
    for amp in (0.3, 0.6, 1.0):
        for seed in (1, 2):
            rnd = random.Random(1000 * n + int(10 * amp) + seed)
            vals = []
            for z in range(n):
                for y in range(n):
                    for x in range(n):
                        u, v, w = (2 * x / (n - 1) - 1, 2 * y / (n - 1) - 1, 2 * z / (n - 1) - 1)
                        e1 = math.sqrt((u / 0.6) ** 2 + (v / 0.45) ** 2 + (w / 0.4) ** 2) - 1
                        e2 = math.sqrt(((u - 0.3) / 0.3) ** 2 + ((v - 0.35) / 0.3) ** 2 + (w / 0.3) ** 2) - 1
                        rr = math.hypot(u + 0.2, w + 0.1) - 0.45
                        tor = math.hypot(rr, v + 0.5) - 0.14
                        d = min(0.4 * e1, 0.3 * e2, tor)
                        vals.append(step(d, 0.04) + amp * (rnd.random() - 0.5))
            nifti(os.path.join(OUT, f'n{n}_a{amp}_s{seed}.nii'), (n, n, n), 2.0, vals)
