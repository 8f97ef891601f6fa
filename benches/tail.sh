#!/usr/bin/env bash
# The tail: every `lsw demo` shape and every shared input wrapped at the defaults, one after
# another, with wall time, peak memory and the phase that dominates, as one Markdown table
# (issue 70's profile). The bunny cloud runs first and last; the ratio column is against the
# mean of its two times in the same run.
#
# Usage: benches/tail.sh LSW_BIN DATA_DIR OUT_DIR
# Environment: TAIL_TIMEOUT (s per wrap, default 120), TAIL_ONLY (a regex over input names).
# Needs: bash, jq, GNU coreutils `timeout`, GNU `/usr/bin/time`.
#
# Columns: input, size (points or faces), wall time (s) and its ratio to the bunny cloud's, peak
# RSS (MB), the CLI's phases (setup = read + field + start; steps; final fit; certificate, in
# ms) and the largest of them.
set -u -o pipefail
if [ $# -lt 3 ]; then
    sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
LSW=$1
DATA=$2
OUT=$3
TIMEOUT=${TAIL_TIMEOUT:-120}
ONLY=${TAIL_ONLY:-.}
mkdir -p "$OUT"

inputs=()
for f in "$DATA"/*.{ply,obj,stl,nii,nii.gz,nrrd,mha,vti}; do
    [ -f "$f" ] && inputs+=("$f")
done
for name in $("$LSW" demo --list | jq -r '.[].name'); do
    case $name in coplanar-*) continue ;; esac # refused by design: no wrap to time
    "$LSW" demo "$name" -o "$OUT/$name.ply" >/dev/null 2>&1 && inputs+=("$OUT/$name.ply")
done
bunny="$DATA/bunnyPts_3.ply"

# One wrap: prints "wall_s peak_mb size setup steps fit certify".
run() {
    local in=$1 base
    base=$(basename "$in")
    /usr/bin/time -f '%e %M' -o "$OUT/$base.time" timeout "$TIMEOUT" \
        "$LSW" wrap "$in" -o "$OUT/$base.wrapped.ply" --keep-invalid >"$OUT/$base.json" 2>"$OUT/$base.log"
    read -r wall kb <"$OUT/$base.time" || { wall=nan; kb=0; }
    # (A volume's size is its iso-surface's faces.)
    size=$("$LSW" info "$in" 2>/dev/null | jq -r 'if .faces > 0 then "\(.faces) f" else "\(.vertices) p" end')
    jq -r --arg w "$wall" --arg kb "$kb" --arg size "${size:-?}" '
        [$w, (($kb | tonumber) / 1024 | floor), $size,
         ((.times_ms.read + .times_ms.setup) | floor), ((.times_ms.evolve - (.evolve_ms.fit // 0)) | floor),
         ((.evolve_ms.fit // 0) | floor), (.times_ms.certify | floor)] | @tsv' "$OUT/$base.json" 2>/dev/null ||
        echo "$wall $((kb / 1024)) ? ? ? ? ?"
}

b1=$(run "$bunny" | cut -f1)
rows=()
for in in "${inputs[@]}"; do
    base=$(basename "$in")
    [[ $base =~ $ONLY ]] || continue
    rows+=("$base	$(run "$in")")
done
b2=$(run "$bunny" | cut -f1)
ref=$(echo "$b1 $b2" | awk '{ print ($1 + $2) / 2 }')

echo "bunny cloud: $b1 s, $b2 s (reference $ref s)"
echo
echo "| input | size | wall s | × bunny | peak MB | setup ms | steps ms | fit ms | certify ms | largest |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---|"
for r in "${rows[@]}"; do
    IFS=$'\t' read -r name wall mb size setup steps fit cert <<<"$r"
    largest=$(printf 'setup %s\nsteps %s\nfit %s\ncertify %s\n' "$setup" "$steps" "$fit" "$cert" |
        sort -k2 -n -r | head -1 | cut -d' ' -f1)
    ratio=$(awk -v w="$wall" -v r="$ref" 'BEGIN { if (r > 0 && w == w + 0) printf "%.1f", w / r; else print "?" }')
    echo "| $name | $size | $wall | $ratio | $mb | $setup | $steps | $fit | $cert | $largest |"
done
