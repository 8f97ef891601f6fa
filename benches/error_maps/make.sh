#!/usr/bin/env bash
# Before/after error maps (issue 15), measured against 300 000 points sampled on the shape's
# mesh, rendered with the colour scale 0–1 % of the diagonal:
# - the crease fit: each CAD shape (and the clouds sampled from two of them) wrapped with it off
#   (fit.crease_angle_deg=0, "before") and on (the default, "after");
# - curved splits: clouds wrapped with chord-midpoint splits (remesh.curved_splits=false,
#   "chord") and with the default curved ones ("curved");
# - reaching into concavities: the bust's face, seen from the front, with fit.reach off
#   ("before") and on (the default, "after").
# Usage: benches/error_maps/make.sh LSW_BIN OUT_DIR  (optional: LSW_BEFORE=… SHARED=… for the fold maps,
# LSW_BEFORE_FLAP=… for the turned bust's flap)
set -euo pipefail
LSW=$1
OUT=$2
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
# input:the mesh it samples (the same shape for meshes)
# wrap_and_map INPUT REF MODE SETTING [BOX VIEW]: wraps $OUT/INPUT.ply with SETTING, maps its
# error (only the points in BOX, seen from VIEW: see render_points.py).
wrap_and_map() {
    local s=$1 ref=$2 mode=$3 setting=$4 view=("${@:5}")
    "$LSW" demo "$s" -o "$OUT/$s.ply" >/dev/null
    "$LSW" demo "$ref" -o "$OUT/$ref.obj" >/dev/null
    [ -f "$OUT/$ref-dense.ply" ] || python3 "$HERE/../peers/sample_obj.py" "$OUT/$ref.obj" 300000 "$OUT/$ref-dense.ply" 1 >/dev/null
    "$LSW" wrap "$OUT/$s.ply" -o "$OUT/$s-$mode.ply" --set "$setting" >/dev/null
    "$LSW" metrics "$OUT/$s-$mode.ply" --target "$OUT/$ref-dense.ply" \
        --target-error-map "$OUT/$s-$mode.vtk" >/dev/null
    python3 "$HERE/render_points.py" "$OUT/$s-$mode.vtk" "$OUT/$s-$mode.png" 1.0 "${view[@]}"
}
for pair in cube-hole:cube-hole cad-part:cad-part cube-cloud:cube cad-part-cloud:cad-part; do
    wrap_and_map "${pair%%:*}" "${pair##*:}" before fit.crease_angle_deg=0
    wrap_and_map "${pair%%:*}" "${pair##*:}" after fit.crease_angle_deg=40
done
for pair in thin-plate-cloud:thin-plate cube-cloud:cube; do
    wrap_and_map "${pair%%:*}" "${pair##*:}" chord remesh.curved_splits=false
    wrap_and_map "${pair%%:*}" "${pair##*:}" curved remesh.curved_splits=true
done
FACE=-0.2,0.2,-0.4,0.0,-0.05,0.4
wrap_and_map bust bust reach-before fit.reach=false "$FACE" front
wrap_and_map bust bust reach-after fit.reach=true "$FACE" front
# The fit's crease sizing and remesh retries (2026-11-26, fifth session): LSW_BEFORE_FIT = an
# lsw built at 8206345, against LSW: cube-hole on a coarser grid (32 cells per side), and the
# bust's face.
if [ -n "${LSW_BEFORE_FIT:-}" ]; then
    for side in before after; do
        if [ "$side" = before ]; then LSW_NOW=$LSW; LSW=$LSW_BEFORE_FIT; fi
        wrap_and_map cube-hole cube-hole "fit-$side" field.cells_per_min_dimension=32
        wrap_and_map bust bust "fit-$side" fit.reach=true "$FACE" front
        if [ "$side" = before ]; then LSW=$LSW_NOW; fi
    done
fi
# The fit's fold rule (2026-11-26): LSW_BEFORE = an lsw built at fbe6c32 (moves that fold a
# face undone with those of all its vertices), against LSW (halved, one vertex blamed). No
# setting selects the old rule, hence the second binary. DoubleWedge.stl from $SHARED (the
# shared data folder), converted to OBJ for the sampler.
if [ -n "${LSW_BEFORE:-}" ] && [ -n "${SHARED:-}" ]; then
    python3 - "$SHARED/DoubleWedge.stl" "$OUT/DoubleWedge.obj" <<'PY'
import struct, sys
d = open(sys.argv[1], 'rb').read(); n = struct.unpack('<I', d[80:84])[0]
index, verts, faces = {}, [], []
for i in range(n):
    v = struct.unpack('<12f', d[84 + 50 * i:84 + 50 * i + 48])
    face = []
    for k in range(3):
        p = v[3 + 3 * k:6 + 3 * k]
        if p not in index:
            index[p] = len(verts) + 1
            verts.append(p)
        face.append(index[p])
    faces.append(face)
with open(sys.argv[2], 'w') as f:
    f.writelines('v %r %r %r\n' % p for p in verts)
    f.writelines('f %d %d %d\n' % tuple(t) for t in faces)
PY
    "$LSW" demo cube -o "$OUT/cube.obj" >/dev/null
    "$LSW" demo cube-cloud -o "$OUT/cube-cloud.ply" >/dev/null
    for ref in cube DoubleWedge; do
        [ -f "$OUT/$ref-dense.ply" ] || python3 "$HERE/../peers/sample_obj.py" "$OUT/$ref.obj" 300000 "$OUT/$ref-dense.ply" 1 >/dev/null
    done
    for mode in before after; do
        bin=$LSW; [ "$mode" = before ] && bin=$LSW_BEFORE
        "$bin" wrap "$OUT/cube-cloud.ply" -o "$OUT/cube-cloud-fold-$mode.ply" >/dev/null
        "$bin" wrap "$SHARED/DoubleWedge.stl" -o "$OUT/DoubleWedge-fold-$mode.ply" >/dev/null
        for pair in cube-cloud:cube DoubleWedge:DoubleWedge; do
            s=${pair%%:*}; ref=${pair##*:}
            "$LSW" metrics "$OUT/$s-fold-$mode.ply" --target "$OUT/$ref-dense.ply" \
                --target-error-map "$OUT/$s-fold-$mode.vtk" >/dev/null
            python3 "$HERE/render_points.py" "$OUT/$s-fold-$mode.vtk" "$OUT/$s-fold-$mode.png" 1.0
        done
    done
fi
# The fit's last round, partial moves (2026-11-26, seventh session): LSW_BEFORE_FLAP = an lsw
# built at 820e643 (a move the contact guard put back stayed put), against LSW (moved half, a
# quarter, an eighth of the way). The bust turned 30° about z, then 45° about x; the wrap's own
# vertices coloured by their distance to the target, around the flap that stayed off it.
if [ -n "${LSW_BEFORE_FLAP:-}" ]; then
    "$LSW" demo bust -o "$OUT/bust.ply" >/dev/null
    python3 "$HERE/turn_ply.py" "$OUT/bust.ply" "$OUT/bust-30-45.ply" 30 45
    for mode in before after; do
        bin=$LSW; [ "$mode" = before ] && bin=$LSW_BEFORE_FLAP
        "$bin" wrap "$OUT/bust-30-45.ply" -o "$OUT/bust-30-45-$mode.ply" >/dev/null
        "$LSW" metrics "$OUT/bust-30-45-$mode.ply" --target "$OUT/bust-30-45.ply" \
            --error-map "$OUT/bust-30-45-$mode.vtk" >/dev/null
        SPLAT=5 python3 "$HERE/render_points.py" "$OUT/bust-30-45-$mode.vtk" \
            "$OUT/bust-turned-flap-$mode.png" 1.0 0.05,0.32,-0.42,-0.18,-0.05,0.22
    done
fi
# The whole of issue 15 (2026-11-27, thirteenth session): LSW_BEFORE_ISSUE = an lsw built at
# 46b8202 (before the issue's work), against LSW, both at their defaults: the bust and the fish,
# their targets sampled with 300 000 points ("issue-before" / "issue-after").
if [ -n "${LSW_BEFORE_ISSUE:-}" ]; then
    for s in bust fish; do
        "$LSW" demo "$s" -o "$OUT/$s.ply" >/dev/null
        "$LSW" demo "$s" -o "$OUT/$s.obj" >/dev/null
        [ -f "$OUT/$s-dense.ply" ] || python3 "$HERE/../peers/sample_obj.py" "$OUT/$s.obj" 300000 "$OUT/$s-dense.ply" 1 >/dev/null
        for mode in before after; do
            bin=$LSW; [ "$mode" = before ] && bin=$LSW_BEFORE_ISSUE
            "$bin" wrap "$OUT/$s.ply" -o "$OUT/$s-issue-$mode.ply" >/dev/null
            "$LSW" metrics "$OUT/$s-issue-$mode.ply" --target "$OUT/$s-dense.ply" \
                --target-error-map "$OUT/$s-issue-$mode.vtk" >/dev/null
            python3 "$HERE/render_points.py" "$OUT/$s-issue-$mode.vtk" "$OUT/$s-issue-$mode.png" 1.0
        done
    done
fi
