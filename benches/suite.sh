#!/usr/bin/env bash
# The shape suite: wraps every `lsw demo` shape and the shared scans with each preset, measures
# the results with `lsw metrics --target`, and prints one Markdown table per preset.
#
# Usage: benches/suite.sh LSW_BIN DATA_DIR OUT_DIR [PRESET ...]
#   LSW_BIN   the lsw binary (build it with `cargo build --release --bin lsw`)
#   DATA_DIR  the shared test data (bunnyPts_3.ply, bunny.ply, spot.obj, …); missing files are skipped
#   OUT_DIR   where the inputs (OUT_DIR/NAME.ply|obj), results, stats and logs go
#   PRESET    presets to run (default: full-wrap isosurface)
# Environment: SUITE_TIMEOUT (s per wrap, default 120), SUITE_SLOW_TIMEOUT (s for inputs known to
# run for minutes, default 60), SUITE_ONLY (a regex: only inputs whose name matches), SUITE_ARGS
# (extra `lsw wrap` arguments, e.g. "--set remesh.trigger=\"quality_band\"").
# Needs: bash, jq, GNU coreutils `timeout`, GNU `/usr/bin/time`.
#
# Columns: kind (points|mesh), target genus (expected), result genus and components (from the
# certificate of `lsw metrics`: null unless closed and manifold), SI (self-intersecting face
# pairs), H % (Hausdorff), mean % result→target and target→result (all in % of the target's
# bounding-box diagonal), wall time and peak RSS of `lsw wrap`.
set -u -o pipefail

if [ $# -lt 3 ]; then
    sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
LSW=$1
DATA=$2
OUT=$3
shift 3
PRESETS=("$@")
[ ${#PRESETS[@]} -eq 0 ] && PRESETS=(full-wrap isosurface)
TIMEOUT=${SUITE_TIMEOUT:-120}
SLOW_TIMEOUT=${SUITE_SLOW_TIMEOUT:-60}
ONLY=${SUITE_ONLY:-.}
read -r -a EXTRA <<<"${SUITE_ARGS:-}"
for tool in jq timeout /usr/bin/time; do
    command -v "$tool" >/dev/null || { echo "suite.sh: $tool is required" >&2; exit 2; }
done
mkdir -p "$OUT"
# Binaries that refuse to write invalid results get --keep-invalid, so every result is measured.
KEEP=()
"$LSW" wrap --help 2>/dev/null | grep -q -- --keep-invalid && KEEP=(--keep-invalid)

# Inputs known to run for minutes and take gigabytes with the current evolver.
SLOW="spotPts_4"
DATA_FILES="bunnyPts_3.ply bunny.ply spot.obj spotPts_4.ply 1Torus.obj 2Torus.obj 3Torus.obj CubeSphere.obj DoubleWedge.stl"

# Expected genus of the wrap, by input name (closed mesh inputs use their own genus instead).
expected_genus() {
    case $1 in
        torus-g[0-9]*) local g=${1#torus-g}; echo "${g%%-*}" ;;
        torus-sparse-cloud | torus-curves | cube-hole | 1Torus) echo 1 ;;
        2Torus) echo 2 ;;
        3Torus) echo 3 ;;
        *) echo 0 ;;
    esac
}

# 1. Inputs: the demo shapes (meshes as OBJ, clouds as PLY), then the shared files.
inputs=()
for name in $("$LSW" demo --list | jq -r '.[].name'); do
    [[ $name =~ $ONLY ]] || continue
    kind=$("$LSW" demo "$name" -o "$OUT/$name.ply" | jq -r .kind) || { echo "demo $name failed" >&2; continue; }
    if [ "$kind" = mesh ]; then
        rm -f "$OUT/$name.ply"
        "$LSW" demo "$name" -o "$OUT/$name.obj" >/dev/null
        inputs+=("$OUT/$name.obj")
    else
        inputs+=("$OUT/$name.ply")
    fi
done
for f in $DATA_FILES; do
    [[ ${f%.*} =~ $ONLY ]] || continue
    if [ -f "$DATA/$f" ]; then inputs+=("$DATA/$f"); else echo "suite.sh: skipping missing $DATA/$f" >&2; fi
done

# 2. Wrap and measure.
for preset in "${PRESETS[@]}"; do
    dir="$OUT/out-$preset"
    mkdir -p "$dir"
    echo
    echo "### preset \`$preset\`"
    echo
    echo "| input | kind | target genus | result genus (comp.) | SI pairs | H % | mean % res→tgt | mean % tgt→res | time s | peak MB | status |"
    echo "|---|---|---|---|---|---|---|---|---|---|---|"
    for in in "${inputs[@]}"; do
        base=$(basename "$in")
        name=${base%.*}
        limit=$TIMEOUT
        [[ " $SLOW " == *" $name "* ]] && limit=$SLOW_TIMEOUT
        info=$("$LSW" metrics "$in" 2>/dev/null)
        if [ -n "$info" ] && [ "$(jq -r '.faces' <<<"$info")" != 0 ]; then
            kind=mesh
            tgenus=$(jq -r '.topology.genus // empty' <<<"$info")
        else
            kind=points
            tgenus=""
        fi
        [ -z "$tgenus" ] && tgenus=$(expected_genus "$name")
        res="$dir/$name.ply"
        rm -f "$res" "$dir/$name.json"
        refused=""
        # time outside timeout: wait4 on timeout reports the wrap's peak RSS as well.
        /usr/bin/time -v -o "$dir/$name.time" timeout -k 5 "$limit" \
            "$LSW" wrap "$in" -o "$res" --preset "$preset" --stats "$dir/$name.json" "${KEEP[@]}" "${EXTRA[@]}" \
            >"$dir/$name.wrap.json" 2>"$dir/$name.log"
        rc=$?
        wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; i++) s = s * 60 + t[i]; printf "%.1f", s}' "$dir/$name.time")
        rss=$(awk -F': ' '/Maximum resident set size/ {printf "%.0f", $2 / 1024}' "$dir/$name.time")
        if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then
            status="timeout ${limit} s"
        elif [ $rc -ne 0 ] && [ -s "$res" ]; then
            # Written with --keep-invalid: measure it, and say why it was refused.
            status=ok
            refused="refused: $(grep -m1 'lsw: error' "$dir/$name.log" | cut -c13-80 | tr '|' '/')"
        elif [ $rc -ne 0 ]; then
            status="error: $(grep -m1 'lsw: error' "$dir/$name.log" | cut -c13-90 | tr '|' '/')"
            [ "$status" = "error: " ] && status="exit $rc"
        else
            status=ok
        fi
        if [ "$status" = ok ] && "$LSW" metrics "$res" --target "$in" >"$dir/$name.metrics.json" 2>>"$dir/$name.log"; then
            row=$(jq -r '[(.topology.genus // "–" | tostring) + " (" + (.topology.components // "–" | tostring) + ")",
                          .self_intersections,
                          (.distances.percent_of_target_diagonal | .hausdorff, .mesh_to_target.mean, .target_to_mesh.mean
                           | if . == null then "–" else (. * 1000 | round / 1000 | tostring) end)]
                         | join(" | ")' "$dir/$name.metrics.json")
            problem=$(jq -r '.topology.problem // empty' "$dir/$name.metrics.json" | cut -c1-70 | tr '|' '/')
            [ -z "$problem" ] || status="ok, invalid: $problem"
            [ -z "${refused:-}" ] || status="$refused"
        else
            row="– | – | – | – | –"
        fi
        echo "| $name | $kind | $tgenus | $row | $wall | $rss | $status |"
    done
done
