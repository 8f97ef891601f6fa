# Sourced by compare.sh and accuracy.sh: builds the CGAL driver once into
# target/peers/alpha_wrap (never part of LSW), sets BIN and a temporary TMP removed on exit, and
# defines `median` (of the numbers on stdin, one per line).
HERE=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
BIN=$HERE/../../target/peers/alpha_wrap
if [ ! -x "$BIN" ] || [ "$HERE/alpha_wrap.cpp" -nt "$BIN" ]; then
    mkdir -p "$(dirname "$BIN")"
    echo "building the CGAL driver (about a minute)…" >&2
    g++ -O3 -DNDEBUG -std=c++17 "$HERE/alpha_wrap.cpp" -o "$BIN" -lgmp -lmpfr
fi
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
median() { sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
