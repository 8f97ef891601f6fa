#!/usr/bin/env bash
# Two builds side by side on the shape suite: every `lsw demo` shape and the shared files, wrapped
# with the defaults by build A then build B in the same minute, input by input. Prints a Markdown
# table: whether the result hashes agree, B's certificate (valid, genus), B's Hausdorff (% of the
# target's diagonal, `lsw metrics --target`), vertices, and both wall times and peak memories.
#
# Usage: benches/builds.sh LSW_A LSW_B DATA_DIR OUT_DIR
# Environment: BUILDS_ONLY (a regex: only inputs whose name matches), BUILDS_TIMEOUT (s, default 120).
# Needs: bash, jq, GNU coreutils `timeout`, GNU `/usr/bin/time`.
set -u -o pipefail

if [ $# -lt 4 ]; then
    sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
A=$1
B=$2
DATA=$3
OUT=$4
ONLY=${BUILDS_ONLY:-.}
LIMIT=${BUILDS_TIMEOUT:-120}
mkdir -p "$OUT"
DATA_FILES="bunnyPts_3.ply bunny.ply spot.obj 1Torus.obj 2Torus.obj 3Torus.obj CubeSphere.obj DoubleWedge.stl gm_half.nrrd"

inputs=()
for name in $("$B" demo --list | jq -r '.[].name'); do
    [[ $name =~ $ONLY ]] || continue
    kind=$("$B" demo "$name" -o "$OUT/$name.ply" | jq -r .kind) || continue
    if [ "$kind" = mesh ]; then
        rm -f "$OUT/$name.ply"
        "$B" demo "$name" -o "$OUT/$name.obj" >/dev/null
        inputs+=("$OUT/$name.obj")
    else
        inputs+=("$OUT/$name.ply")
    fi
done
for f in $DATA_FILES; do
    [[ ${f%.*} =~ $ONLY ]] && [ -f "$DATA/$f" ] && inputs+=("$DATA/$f")
done

# Wraps IN with BIN; prints "hash seconds peak_MB" (hash "-" when the wrap failed).
run() {
    local bin=$1 in=$2 tag=$3 base
    base=$(basename "$in")
    /usr/bin/time -f "%e %M" -o "$OUT/$tag-$base.time" timeout -k 5 "$LIMIT" \
        "$bin" wrap "$in" -o "$OUT/$tag-$base.ply" --keep-invalid >"$OUT/$tag-$base.json" 2>/dev/null
    local hash
    hash=$(jq -r '.result_hash // "-"' "$OUT/$tag-$base.json" 2>/dev/null || echo -)
    read -r secs kb < <(tail -n 1 "$OUT/$tag-$base.time")
    echo "${hash:--} $secs $((kb / 1024))"
}

echo "| input | same mesh | valid | genus (target) | H % | vertices | time A s | time B s | peak A MB | peak B MB |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for in in "${inputs[@]}"; do
    base=$(basename "$in")
    read -r ha ta ma <<<"$(run "$A" "$in" a)"
    read -r hb tb mb <<<"$(run "$B" "$in" b)"
    same=no
    [ "$ha" = "$hb" ] && same=yes
    row="– | – | – | –"
    if "$B" metrics "$OUT/b-$base.ply" --target "$in" >"$OUT/b-$base.metrics.json" 2>/dev/null; then
        row=$(jq -r --slurpfile w "$OUT/b-$base.json" '[
            (.certificate.valid | tostring),
            ((.topology.genus // "–" | tostring) + " (" + ($w[0].certificate.target_genus // "–" | tostring) + ")"),
            (.distances.percent_of_target_diagonal.hausdorff // null | if . == null then "–" else (. * 1000 | round / 1000 | tostring) end),
            (.vertices | tostring)] | join(" | ")' "$OUT/b-$base.metrics.json")
    fi
    echo "| ${base%.*} | $same | $row | $ta | $tb | $ma | $mb |"
done
