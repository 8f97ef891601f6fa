#!/usr/bin/env bash
# Time against accuracy: `lsw wrap` (defaults) and CGAL's 3D Alpha Wrapping at several
# alpha / offset settings, each result measured against a reference mesh with `lsw metrics`
# (two-sided distances in % of its diagonal, mean radius ratio, genus, validity). compare.sh
# times the coarse setting only; this says what CGAL needs to be as close to the surface.
#
# Usage: benches/peers/accuracy.sh LSW_BIN INPUT REFERENCE [ALPHA_DIV/OFFSET_DIV ...]
#   (default settings: 20/600 30/600 50/600 30/1500 50/1500 100/600; RUNS=N times each N times,
#   median, interleaved with LSW)
# Needs what compare.sh needs (g++, libcgal-dev, jq); builds the same driver.
set -eu -o pipefail
LSW=$1
IN=$2
REF=$3
shift 3
SETTINGS=${*:-20/600 30/600 50/600 30/1500 50/1500 100/600}
RUNS=${RUNS:-1}
. "$(dirname "$0")/common.sh"
timed() { # timed OUTFILE CMD...: seconds of CMD's wall time appended to OUTFILE
    local out=$1 s
    shift
    s=$(date +%s.%N)
    "$@" >/dev/null
    echo "$(date +%s.%N) - $s" | bc >>"$out"
}
row() { # row NAME SECONDS MESH
    "$LSW" metrics "$3" --target "$REF" | jq -r --arg n "$1" --arg t "$2" '
      .distances.percent_of_target_diagonal as $d |
      [$n, ($t | tonumber * 100 | round / 100), .faces, ($d.mesh_to_target.mean * 1000 | round / 1000),
       ($d.target_to_mesh.mean * 1000 | round / 1000), ($d.hausdorff * 100 | round / 100),
       (.quality.radius_ratio.mean * 1000 | round / 1000), .certificate.genus,
       .certificate.valid] | @tsv'
}
echo "input: $IN, reference: $REF ($RUNS run(s) each, median; $(nproc) cores, load $(cut -d' ' -f1 /proc/loadavg))"
printf 'wrap\ts\tfaces\tresult→ref mean %%\tref→result mean %%\tHausdorff %%\tradius ratio\tgenus\tvalid\n'
for setting in $SETTINGS; do
    a=${setting%/*}
    o=${setting#*/}
    for _ in $(seq "$RUNS"); do
        timed "$TMP/lsw.t" "$LSW" wrap "$IN" -o "$TMP/lsw.ply"
        timed "$TMP/aw-$a-$o.t" "$BIN" "$IN" "$TMP/aw-$a-$o.off" "$a" "$o"
    done
    row "CGAL alpha d/$a offset d/$o" "$(median <"$TMP/aw-$a-$o.t")" "$TMP/aw-$a-$o.off"
done
row "lsw wrap (defaults)" "$(median <"$TMP/lsw.t")" "$TMP/lsw.ply"
