#!/usr/bin/env bash
# Simulated scans (scan.py) of the demo shapes, wrapped with the defaults: one TSV line per wrap
# with the shape, its genus, the scan's variant and points, then valid, genus, parts, target
# points left outside, the farthest vertex from the data (% of the diagonal), wall ms, vertices
# and warnings; then a count of the valid wraps of the shape's genus. Regions no camera saw
# (the underside, deep concavities) have no data, so distances to the scanned mesh say little
# there: the farthest vertex is measured to the data.
#
# Usage: benches/scans/run.sh LSW_BIN OUT_DIR [SHAPE ...]
# Needs: python3 with numpy.
set -u -o pipefail
if [ $# -lt 2 ]; then
    sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
BIN=$1
OUT=$2
shift 2
SHAPES=${*:-torus-g1 torus-g2 torus-g3 torus-g5 cube-hole plate-holes cad-part fish creature bust dumbbell thin-plate}
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
right=0
total=0
for m in $SHAPES; do
    [ -f "$OUT/$m.obj" ] || "$BIN" demo "$m" -o "$OUT/$m.obj" >/dev/null
    read -r g diag <<<"$("$BIN" info "$OUT/$m.obj" | python3 -c "
import json, sys
j = json.load(sys.stdin); print((2 - j['euler_characteristic']) // 2, j['bbox']['diagonal'])")"
    # variant: points, views, seed, extra scan.py arguments
    for v in "200000 8 1" "200000 8 2 --below" "50000 6 3" "50000 12 4 --below --noise 0.001"; do
        read -r n views seed extra <<<"$v"
        name="$m-$n-$views-$seed${extra:+-x}"
        f="$OUT/$name.ply"
        # shellcheck disable=SC2086
        [ -f "$f" ] || python3 "$HERE/scan.py" "$OUT/$m.obj" "$f" --points "$n" --views "$views" --seed "$seed" $extra 2>/dev/null
        r=$("$BIN" wrap "$f" -o "$OUT/result.ply" 2>/dev/null | python3 -c "
import json, sys
j = json.load(sys.stdin); c = j['certificate']
if j.get('error'): sys.exit(1)
print(c['valid'], c['genus'], c['components'], c.get('target_points_outside'),
      round(100 * c['distance_max'] / $diag, 2),
      round(j['times_ms']['total']), j['vertices'], len(j.get('warnings') or []))" 2>/dev/null || echo "FAILED")
        printf '%s\t%s\t%s\t%s\n' "$m" "$g" "$name" "$r"
        total=$((total + 1))
        read -r valid genus _ <<<"$r"
        [ "$valid" = True ] && [ "$genus" = "$g" ] && right=$((right + 1))
    done
done
echo "valid with the shape's genus: $right of $total"
