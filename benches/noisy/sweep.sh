#!/usr/bin/env bash
# The noisy-volume sweep: wraps the 18 volumes of make.py (blob and ring, noise 0.3–1.0 of the
# contrast, 20–48 voxels) with the defaults and prints one TSV line per volume: name, exit
# status, wall time, and valid / genus / vertices from the certificate (or the error).
#
# Usage: benches/noisy/sweep.sh LSW_BIN OUT_DIR [lsw wrap arguments ...]
# Needs: python3.
set -u -o pipefail
if [ $# -lt 2 ]; then
    sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
fi
BIN=$1
OUT=$2
shift 2
HERE=$(cd "$(dirname "$0")" && pwd)
[ -f "$OUT/n48_a1.0_s2.nii" ] || python3 "$HERE/make.py" "$OUT"
valid=0
total=0
for f in "$OUT"/n*.nii; do
    b=$(basename "$f" .nii)
    s=$(date +%s.%N)
    timeout 300 "$BIN" wrap "$f" -o "$OUT/$b.wrap.ply" "$@" >"$OUT/$b.json" 2>"$OUT/$b.err"
    rc=$?
    e=$(date +%s.%N)
    line=$(python3 - "$OUT/$b.json" "$OUT/$b.err" "$rc" <<'P'
import json, sys
j, err, rc = sys.argv[1:]
try:
    d = json.load(open(j))
    c = d["certificate"]
    if d.get("error"):
        raise ValueError(d["error"])  # refused: its report is on stdout too
    print(f"valid={c['valid']} genus={c['genus']} V={d.get('vertices')}")
except Exception:
    lines = [l for l in open(err).read().splitlines() if l.startswith("lsw: error")]
    print(lines[0][:160] if lines else f"exit {rc}, no report")
P
)
    total=$((total + 1))
    case "$line" in valid=True*) valid=$((valid + 1)) ;; esac
    printf '%s\trc=%s\t%.1f s\t%s\n' "$b" "$rc" "$(awk -v a="$s" -v b="$e" "BEGIN {print b - a}")" "$line"
done
echo "valid: $valid of $total"
