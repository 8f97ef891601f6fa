#!/usr/bin/env bash
# Unevenly sampled clouds: eight demo clouds (tori of genus 1, 3 and 5, a cut sphere, a thin
# plate, a cube, a CAD part, two spheres apart) thinned along x to 5 %, 10 % and 30 % at the low
# end (`thin.py`), wrapped with the defaults. Prints one TSV line per wrap: shape, low end,
# expected genus and components, then valid, genus, components, vertices, wall ms (or FAILED),
# and a count of the wraps that are valid with the shape's genus and components.
#
# Usage: benches/uneven/run.sh LSW_BIN OUT_DIR [lsw wrap arguments ...]
# Needs: python3, jq.
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
for spec in torus-g1-cloud:1:1 torus-g3-cloud:3:1 torus-g5-cloud:5:1 sphere-cut-cloud:0:1 \
    thin-plate-cloud:0:1 cube-cloud:0:1 cad-part-cloud:0:1 two-spheres-apart-cloud:0:2; do
    IFS=: read -r shape genus parts <<<"$spec"
    [ -f "$OUT/$shape.obj" ] || "$BIN" demo "$shape" -o "$OUT/$shape.obj" >/dev/null
    for low in 0.05 0.1 0.3; do
        f="$OUT/$shape-$low.obj"
        [ -f "$f" ] || python3 "$HERE/thin.py" "$OUT/$shape.obj" "$f" "$low"
        r=$("$BIN" wrap "$f" -o "$OUT/result.ply" "$@" 2>/dev/null |
            jq -r '[.certificate.valid, .certificate.genus, .certificate.components, .vertices,
                    (.times_ms.total | round)] | @tsv' 2>/dev/null || echo FAILED)
        printf '%s\t%s\t%s\t%s\t%s\n' "$shape" "$low" "$genus" "$parts" "$r"
        total=$((total + 1))
        read -r valid g c _ <<<"$r"
        [ "$valid" = true ] && [ "$g" = "$genus" ] && [ "$c" = "$parts" ] && right=$((right + 1))
    done
done
echo "valid with the shape's genus and parts: $right of $total"
