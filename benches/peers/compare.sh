#!/usr/bin/env bash
# Side-by-side timing of `lsw wrap` (defaults) and CGAL's 3D Alpha Wrapping at the "coarse"
# setting (alpha = diagonal/20, offset = diagonal/600), interleaved run by run so both see the
# same machine load; prints the median of N runs of each and LSW's per-phase times.
#
# Usage: benches/peers/compare.sh LSW_BIN INPUT [N=3]
# Needs: g++ and Debian's libcgal-dev (header-only; `apt-get install libcgal-dev`), jq.
# The driver is built once into target/peers/alpha_wrap (never part of LSW).
set -eu -o pipefail
LSW=$1
IN=$2
N=${3:-3}
. "$(dirname "$0")/common.sh"
for i in $(seq "$N"); do
    s=$(date +%s.%N)
    "$LSW" wrap "$IN" -o "$TMP/lsw.ply" >"$TMP/lsw$i.json"
    echo "$(date +%s.%N) - $s" | bc >>"$TMP/lsw.t"
    s=$(date +%s.%N)
    "$BIN" "$IN" "$TMP/aw.off" >"$TMP/aw$i.json"
    echo "$(date +%s.%N) - $s" | bc >>"$TMP/aw.t"
done
l=$(median <"$TMP/lsw.t")
a=$(median <"$TMP/aw.t")
echo "input: $IN ($N runs each, interleaved; $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
echo "lsw wrap (defaults):        median $l s, $(jq .vertices "$TMP/lsw1.json") vertices, valid $(jq .certificate.valid "$TMP/lsw1.json")"
echo "CGAL alpha wrap (coarse):   median $a s, $(jq .vertices "$TMP/aw1.json") vertices"
echo "ratio lsw / alpha wrap:     $(echo "scale=2; $l / $a" | bc)"
echo "lsw phases of run 1 (ms):   $(jq -c '.times_ms | map_values(round)' "$TMP/lsw1.json")"
echo "lsw evolve parts (ms):      $(jq -c '.evolve_ms | map_values(round)' "$TMP/lsw1.json")"
echo "lsw field parts (ms):       $(jq -c '.field_ms | map_values(round)' "$TMP/lsw1.json")"
