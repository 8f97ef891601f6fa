#!/usr/bin/env python3
"""Writes a point list (x y z per line, or an ASCII PLY's vertices) as PCD, LAS/LAZ and E57 files
the way other tools write them: PCD in ascii, binary and binary_compressed (LZF from liblzf
through `python-lzf`, as PCL does), also as an organized cloud with NaN pixels; LAS 1.4 and LAZ
through `laspy` + `lazrs`; E57 through `pye57` (libE57Format), once as one scan and once as two
scans with poses (each half stored in its scanner's frame) and invalid points; PTX as two scans
with empty grid cells, once with identity matrices and once with the second scan posed. The wraps
of the PCD files, the one-scan E57 and the identity PTX must equal the wrap of the same float32
points.

usage: convert.py INPUT OUT_DIR     (pip install numpy python-lzf laspy lazrs pye57)
"""
import os
import struct
import sys

import lzf
import laspy
import numpy as np


def read_points(path):
    with open(path, "rb") as f:
        data = f.read().decode("ascii", "replace").splitlines()
    if data and data[0].strip() == "ply":
        end = next(i for i, l in enumerate(data) if l.strip() == "end_header")
        data = data[end + 1 :]
    rows = [l.split()[:3] for l in data if l.strip() and not l.startswith("#")]
    return np.array(rows, dtype=np.float64).astype(np.float32)


def pcd_header(n, data, width=None, height=1):
    width = n if width is None else width
    return (
        "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb\n"
        "SIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\n"
        f"WIDTH {width}\nHEIGHT {height}\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {n}\nDATA {data}\n"
    ).encode()


def write_pcd(p, path, data):
    n = len(p)
    rgb = np.full(n, 0x00FF8040, dtype=np.uint32)
    if data == "ascii":
        body = "".join(f"{x!r} {y!r} {z!r} {c}\n" for (x, y, z), c in zip(p.tolist(), rgb.tolist()))
        body = body.encode()
    else:
        rec = np.zeros(n, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4")])
        rec["x"], rec["y"], rec["z"], rec["rgb"] = p[:, 0], p[:, 1], p[:, 2], rgb
        if data == "binary":
            body = rec.tobytes()
        else:
            raw = b"".join(rec[f].tobytes() for f in ("x", "y", "z", "rgb"))
            packed = lzf.compress(raw)
            body = struct.pack("<II", len(packed), len(raw)) + packed
    with open(path, "wb") as f:
        f.write(pcd_header(n, data) + body)


def write_organized(p, path):
    """A 2-row image of every point and a NaN pixel after each: HEIGHT 2, dense false."""
    n = len(p)
    img = np.full((2 * n, 3), np.nan, dtype=np.float32)
    img[0::2] = p
    rec = np.zeros(2 * n, dtype=[("x", "<f4"), ("y", "<f4"), ("z", "<f4"), ("rgb", "<u4")])
    rec["x"], rec["y"], rec["z"] = img[:, 0], img[:, 1], img[:, 2]
    with open(path, "wb") as f:
        f.write(pcd_header(2 * n, "binary", width=n, height=2) + rec.tobytes())


def write_las(p, path):
    header = laspy.LasHeader(point_format=3, version="1.4")
    lo = p.min(axis=0).astype(np.float64)
    header.offsets = lo
    header.scales = np.array([1e-7, 1e-7, 1e-7])
    las = laspy.LasData(header)
    las.x, las.y, las.z = p[:, 0], p[:, 1], p[:, 2]
    las.write(path)


def quat_matrix(w, x, y, z):
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
        ]
    )


def write_e57(p, path, posed):
    import pye57

    p = p.astype(np.float64)
    e = pye57.E57(path, mode="w")
    if not posed:
        e.write_scan_raw({"cartesianX": p[:, 0], "cartesianY": p[:, 1], "cartesianZ": p[:, 2]})
    else:
        half = len(p) // 2
        poses = [((0.9238795325112867, 0.0, 0.0, 0.3826834323650898), (1.0, -2.0, 0.5)),
                 ((0.7071067811865476, 0.7071067811865476, 0.0, 0.0), (-3.0, 0.0, 4.0))]
        for part, (q, t) in zip((p[:half], p[half:]), poses):
            r = quat_matrix(*q)
            local = (part - np.array(t)) @ r  # the inverse pose: R^T (p - t)
            # One invalid point per scan (state 2) far away, which must be left out.
            local = np.vstack([local, [[1e3, 1e3, 1e3]]])
            state = np.zeros(len(local), dtype=np.int8)
            state[-1] = 2
            e.write_scan_raw(
                {"cartesianX": local[:, 0], "cartesianY": local[:, 1], "cartesianZ": local[:, 2],
                 "cartesianInvalidState": state},
                rotation=np.array(q), translation=np.array(t))
    e.close()


def write_ptx(p, path, posed):
    """Leica PTX: each half of the points as a scan of a 2-row grid with an empty cell (0 0 0 0)
    after every point; the row-vector matrix [x y z 1]·M takes the scan to the common frame."""
    p = p.astype(np.float64)
    half = len(p) // 2
    lines = []
    for k, part in enumerate((p[:half], p[half:])):
        q, t = ((0.9238795325112867, 0.0, 0.0, 0.3826834323650898), (1.0, -2.0, 0.5)) if posed and k == 1 else ((1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        r = quat_matrix(*q)  # column vectors: p = r @ local + t, so M's rows are r's columns
        local = (part - np.array(t)) @ r if posed and k == 1 else part
        lines += [str(len(part)), "2", "0 0 0", "1 0 0", "0 1 0", "0 0 1"]
        lines += [" ".join(repr(float(c)) for c in r[:, i]) + " 0" for i in range(3)]
        lines += [" ".join(repr(float(c)) for c in t) + " 1"]
        for x, y, z in local.tolist():
            lines += [f"{x!r} {y!r} {z!r} 0.5 10 20 30", "0 0 0 0 0 0 0"]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def main():
    src, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    p = read_points(src)
    stem = os.path.splitext(os.path.basename(src))[0]
    with open(os.path.join(out, f"{stem}-f32.xyz"), "w") as f:
        f.writelines(f"{x!r} {y!r} {z!r}\n" for x, y, z in p.tolist())
    for data in ("ascii", "binary", "binary_compressed"):
        write_pcd(p, os.path.join(out, f"{stem}-{data}.pcd"), data)
    write_organized(p, os.path.join(out, f"{stem}-organized.pcd"))
    write_las(p, os.path.join(out, f"{stem}.las"))
    write_las(p, os.path.join(out, f"{stem}.laz"))
    write_e57(p, os.path.join(out, f"{stem}.e57"), posed=False)
    write_e57(p, os.path.join(out, f"{stem}-posed.e57"), posed=True)
    write_ptx(p, os.path.join(out, f"{stem}.ptx"), posed=False)
    write_ptx(p, os.path.join(out, f"{stem}-posed.ptx"), posed=True)


if __name__ == "__main__":
    main()
