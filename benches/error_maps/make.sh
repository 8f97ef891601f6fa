#!/usr/bin/env bash
# Before/after error maps of the crease fit (issue 15): each CAD shape (and the clouds sampled
# from two of them) wrapped with the crease fit off (fit.crease_angle_deg=0, "before") and on
# (the default, "after"), measured against 300 000 points sampled on the shape's mesh, rendered
# with the colour scale 0–1 % of the diagonal.
# Usage: benches/error_maps/make.sh LSW_BIN OUT_DIR
set -euo pipefail
LSW=$1
OUT=$2
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
# input:the mesh it samples (the same shape for meshes)
for pair in cube-hole:cube-hole cad-part:cad-part cube-cloud:cube cad-part-cloud:cad-part; do
    s=${pair%%:*}
    ref=${pair##*:}
    "$LSW" demo "$s" -o "$OUT/$s.ply" >/dev/null
    "$LSW" demo "$ref" -o "$OUT/$ref.obj" >/dev/null
    [ -f "$OUT/$ref-dense.ply" ] || python3 "$HERE/../peers/sample_obj.py" "$OUT/$ref.obj" 300000 "$OUT/$ref-dense.ply" 1 >/dev/null
    for mode in before after; do
        angle=40
        [ "$mode" = before ] && angle=0
        "$LSW" wrap "$OUT/$s.ply" -o "$OUT/$s-$mode.ply" --set "fit.crease_angle_deg=$angle" >/dev/null
        "$LSW" metrics "$OUT/$s-$mode.ply" --target "$OUT/$ref-dense.ply" \
            --target-error-map "$OUT/$s-$mode.vtk" >/dev/null
        python3 "$HERE/render_points.py" "$OUT/$s-$mode.vtk" "$OUT/$s-$mode.png" 1.0
    done
done
