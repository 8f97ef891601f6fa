#!/usr/bin/env bash
# Before/after error maps (issue 15), measured against 300 000 points sampled on the shape's
# mesh, rendered with the colour scale 0–1 % of the diagonal:
# - the crease fit: each CAD shape (and the clouds sampled from two of them) wrapped with it off
#   (fit.crease_angle_deg=0, "before") and on (the default, "after");
# - curved splits: clouds wrapped with chord-midpoint splits (remesh.curved_splits=false,
#   "chord") and with the default curved ones ("curved").
# Usage: benches/error_maps/make.sh LSW_BIN OUT_DIR
set -euo pipefail
LSW=$1
OUT=$2
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
# input:the mesh it samples (the same shape for meshes)
# wrap_and_map INPUT REF MODE SETTING: wraps $OUT/INPUT.ply with SETTING, maps its error.
wrap_and_map() {
    local s=$1 ref=$2 mode=$3 setting=$4
    "$LSW" demo "$s" -o "$OUT/$s.ply" >/dev/null
    "$LSW" demo "$ref" -o "$OUT/$ref.obj" >/dev/null
    [ -f "$OUT/$ref-dense.ply" ] || python3 "$HERE/../peers/sample_obj.py" "$OUT/$ref.obj" 300000 "$OUT/$ref-dense.ply" 1 >/dev/null
    "$LSW" wrap "$OUT/$s.ply" -o "$OUT/$s-$mode.ply" --set "$setting" >/dev/null
    "$LSW" metrics "$OUT/$s-$mode.ply" --target "$OUT/$ref-dense.ply" \
        --target-error-map "$OUT/$s-$mode.vtk" >/dev/null
    python3 "$HERE/render_points.py" "$OUT/$s-$mode.vtk" "$OUT/$s-$mode.png" 1.0
}
for pair in cube-hole:cube-hole cad-part:cad-part cube-cloud:cube cad-part-cloud:cad-part; do
    wrap_and_map "${pair%%:*}" "${pair##*:}" before fit.crease_angle_deg=0
    wrap_and_map "${pair%%:*}" "${pair##*:}" after fit.crease_angle_deg=40
done
for pair in thin-plate-cloud:thin-plate cube-cloud:cube; do
    wrap_and_map "${pair%%:*}" "${pair##*:}" chord remesh.curved_splits=false
    wrap_and_map "${pair%%:*}" "${pair##*:}" curved remesh.curved_splits=true
done
