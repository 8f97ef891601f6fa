#!/usr/bin/env bash
# The genus sweep: clouds unlike the demo's (3 000, 30 000 and 150 000 points; clean or with
# Gaussian noise of 0.2 % of the diagonal; as generated or turned at random) sampled from every
# demo mesh with handles, wrapped with the defaults, and the result's genus set against the
# mesh's. Prints one TSV line per wrap: shape, expected genus, points, noise, seed (2 = turned),
# then valid, genus, result hash, wall ms, vertices, largest distance to the data; and a count.
#
# Usage: benches/genus/sweep.sh LSW_BIN OUT_DIR [lsw wrap arguments ...]
# Needs: python3.
set -u -o pipefail
if [ $# -lt 2 ]; then
    sed -n '2,9p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
BIN=$1
OUT=$2
shift 2
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
right=0
total=0
for m in torus-g1 torus-g2 torus-g3 torus-g4 torus-g5 cube-hole plate-holes cad-part; do
    [ -f "$OUT/$m.obj" ] || "$BIN" demo "$m" -o "$OUT/$m.obj" >/dev/null
    g=$("$BIN" info "$OUT/$m.obj" | python3 -c "import json,sys; print((2 - json.load(sys.stdin)['euler_characteristic']) // 2)")
    for n in 3000 30000 150000; do
        for noise in 0 0.002; do
            for seed in 1 2; do
                f="$OUT/c-$m-$n-$noise-$seed.ply"
                [ -f "$f" ] || python3 "$HERE/sample.py" "$OUT/$m.obj" "$n" "$f" "$seed" "$noise" $((seed - 1))
                r=$("$BIN" wrap "$f" -o "$OUT/result.ply" "$@" 2>/dev/null | python3 -c "
import json, sys
j = json.load(sys.stdin); c = j['certificate']
if j.get('error'): sys.exit(1)  # refused (its report is on stdout too): FAILED
print(c['valid'], c['genus'], j['result_hash'], round(j['times_ms']['total']), j['vertices'], round(c['distance_max'], 4))" 2>/dev/null || echo "FAILED")
                printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$m" "$g" "$n" "$noise" "$seed" "$r"
                total=$((total + 1))
                read -r valid genus _ <<<"$r"
                [ "$valid" = True ] && [ "$genus" = "$g" ] && right=$((right + 1))
            done
        done
    done
done
echo "right genus and valid: $right of $total"
