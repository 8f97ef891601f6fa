#!/usr/bin/env bash
# Topology surgery table (issue 14): wraps the generated shapes with handles, necks and scan holes
# and the shared scans with the defaults (meshes also with `--start icosphere`), and prints one
# Markdown row each: start, genus, surgery events (steps), SI, vertices, mean distances both ways
# and Hausdorff (% of the target's diagonal, `lsw metrics --target`), wall time.
#
# Usage: benches/surgery.sh LSW_BIN DATA_DIR OUT_DIR   (needs jq and GNU /usr/bin/time)
set -u -o pipefail
[ $# -eq 3 ] || { sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
LSW=$1 DATA=$2 OUT=$3
mkdir -p "$OUT"
row() { # FILE LABEL [wrap args...]
    local f=$1 lab=$2; shift 2
    /usr/bin/time -f %e -o "$OUT/$lab.time" "$LSW" wrap "$f" -o "$OUT/$lab.ply" "$@" >"$OUT/$lab.json" 2>"$OUT/$lab.err"
    "$LSW" metrics "$OUT/$lab.ply" --target "$f" >"$OUT/$lab.metrics.json" 2>/dev/null
    jq -r --arg lab "$lab" --arg t "$(tail -1 "$OUT/$lab.time")" --slurpfile m "$OUT/$lab.metrics.json" '
      ($m[0].distances.percent_of_target_diagonal // {}) as $d |
      def r3: if . == null then "–" else (. * 1000 | round / 1000) end;
      "| \($lab) | \(.start) | \(.certificate.genus) | \(.surgery | length) (\([.surgery[].step] | map(tostring) | join(", "))) | \(.certificate.self_intersections) | \(.vertices) | \($d.mesh_to_target.mean | r3) / \($d.target_to_mesh.mean | r3) | \($d.hausdorff | r3) | \($t) |"' "$OUT/$lab.json"
}
echo "| input | start | genus | surgery events (steps) | SI | vertices | mean mesh→target / target→mesh | Hausdorff | time (s) |"
echo "|---|---|---|---|---|---|---|---|---|"
for n in torus-g1-cloud torus-g2-cloud torus-g3-cloud torus-g4-cloud torus-g5-cloud torus-sparse-cloud sphere-cut-cloud thin-plate-cloud two-spheres-apart-cloud; do
    "$LSW" demo "$n" -o "$OUT/$n.in.ply" >/dev/null && row "$OUT/$n.in.ply" "$n"
done
for f in "$DATA/bunnyPts_3.ply" "$DATA/spotPts_4.ply"; do
    [ -f "$f" ] && row "$f" "$(basename "${f%.*}")"
done
for n in torus-g4 torus-g5 cube-hole dumbbell; do
    "$LSW" demo "$n" -o "$OUT/$n.in.obj" >/dev/null
    row "$OUT/$n.in.obj" "$n-auto"
    row "$OUT/$n.in.obj" "$n-ico" --start icosphere
done
for f in "$DATA/1Torus.obj" "$DATA/2Torus.obj" "$DATA/3Torus.obj" "$DATA/bunny.ply" "$DATA/spot.obj"; do
    [ -f "$f" ] || continue
    b=$(basename "${f%.*}")
    row "$f" "$b-auto"
    row "$f" "$b-ico" --start icosphere
done
