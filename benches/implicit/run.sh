#!/usr/bin/env bash
# Implicit test shapes unlike the demo's (a gear, a pipe, an open-necked bottle, a twisted
# ribbon, a washer, an hourglass, a spiky ball, thin and uneven tori, a cube with blind pits, a
# bowl, a tripod, a ball with a U-shaped tunnel, a fat torus with a narrow hole, two linked tori,
# a ball with a narrow bore; and holes that meet inside: a cube's frame, cubes with square
# tunnels 0.6 / 0.9 / 1.1 wide, with two and three crossing round bores, a shell with six
# holes), each wrapped
# four ways: as a volume (NRRD, 120³), as that volume's iso-surface mesh, and as clouds sampled
# from it (30 000 points; 8 000 with 0.2 % noise, turned). Prints one TSV line per wrap: shape,
# input kind, expected genus, then valid, genus, components, wall ms, vertices, largest distance
# to the data, self-intersections.
#
# Usage: benches/implicit/run.sh LSW_BIN OUT_DIR [shape ...]
# GEN=benches/implicit/more.py runs that script's shapes instead (a knot, a spring, a lattice…).
# Needs: python3 (numpy for more.py).
set -u -o pipefail
if [ $# -lt 2 ]; then
    sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
BIN=$1
OUT=$2
shift 2
HERE=$(cd "$(dirname "$0")" && pwd)
GEN=${GEN:-$HERE/gen.py}
SAMPLE="$HERE/../genus/sample.py"
mkdir -p "$OUT"
shapes=${*:-$(python3 "$GEN" --list | cut -d' ' -f1)}
for s in $shapes; do
    g=$(python3 "$GEN" --list | awk -v s="$s" '$1 == s { print $2 }')
    [ -f "$OUT/$s.nrrd" ] || python3 "$GEN" "$s" 120 "$OUT/$s.nrrd"
    [ -f "$OUT/$s.obj" ] || "$BIN" wrap "$OUT/$s.nrrd" -o "$OUT/$s-vol.ply" --isosurface-out "$OUT/$s.obj" >/dev/null 2>&1
    [ -f "$OUT/$s-30k.ply" ] || python3 "$SAMPLE" "$OUT/$s.obj" 30000 "$OUT/$s-30k.ply" 1 0 0
    [ -f "$OUT/$s-8kn.ply" ] || python3 "$SAMPLE" "$OUT/$s.obj" 8000 "$OUT/$s-8kn.ply" 2 0.002 1
    for kind in vol mesh 30k 8kn; do
        case $kind in
        vol) in=$OUT/$s.nrrd ;;
        mesh) in=$OUT/$s.obj ;;
        *) in=$OUT/$s-$kind.ply ;;
        esac
        r=$("$BIN" wrap "$in" -o "$OUT/result.ply" 2>/dev/null | python3 -c "
import json, sys
j = json.load(sys.stdin); c = j.get('certificate') or {}
if j.get('error'): print('ERROR', str(j['error'])[:80]); sys.exit()
print(c.get('valid'), c.get('genus'), c.get('components'), round(j['times_ms']['total']), j['vertices'],
      round(c.get('distance_max', -1), 4), c.get('self_intersections'))" 2>/dev/null || echo "FAILED")
        printf '%s\t%s\t%s\t%s\n' "$s" "$kind" "$g" "$r"
    done
done
