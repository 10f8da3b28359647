#!/usr/bin/env bash
# Reader benchmark (`make bench`): time `bin/mefem --check` on generated decks of a structured
# block of tetrahedra, from about 100 000 to 5 000 000 tets, and print deck size, lines, nodes,
# elements, read+check wall time, peak memory and throughput.
#
# Uses bin/mefem as built by `make bench` (builds nothing itself). Decks go to tests/out/bench/
# and are regenerated only when their parameters or the generator change.
# Environment:
#   BENCH_SIZES="27 58 100"   cells per side of the cubic blocks (5 tets per cell)
#   BENCH_LAYOUT=current      *ELEMENT_SOLID layout: current (two lines) or legacy (one line)
#   BENCH_LEGACY=1            also time the largest deck in the legacy one-line layout
#   BENCH_PROFILE=1           also profile reading a 200k-tet deck with valgrind's callgrind
set -u
cd "$(dirname "$0")/../.."
PY=/usr/bin/python3
EXE=bin/mefem
OUT=tests/out/bench
GEN=tests/bench/generate_block_deck.py
SIZES=${BENCH_SIZES:-"27 58 100"}
LAYOUT=${BENCH_LAYOUT:-current}
mkdir -p "$OUT"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

if [ ! -x "$EXE" ]; then
  echo "run_bench: $EXE is missing (run 'make bench', which builds it)" >&2
  exit 1
fi

# Generate deck $1 with generator arguments $2... unless it exists with the same parameters.
make_deck() {
  local deck=$1; shift
  local stamp="$deck.params" want
  want="$* $(md5sum "$GEN" | cut -c1-32)"
  if [ -f "$deck" ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$want" ]; then
    echo "  $deck: present (same parameters)"
    return 0
  fi
  rm -f "$deck" "$stamp"
  "$PY" "$GEN" "$@" "$deck" | sed 's/^/  /' || return 1
  echo "$want" > "$stamp"
}

# Time one check run of deck $1 and print its figures.
time_deck() {
  local deck=$1 log="$1.log" bytes lines nodes elems read_s mem rss wall
  bytes=$(stat -c %s "$deck")
  lines=$(wc -l < "$deck")
  if [ -x /usr/bin/time ]; then
    /usr/bin/time -v "$EXE" --check "$deck" > "$log" 2>&1
  else
    { time -p "$EXE" --check "$deck"; } > "$log" 2>&1
  fi
  local rc=$?
  if [ $rc -ne 0 ] || ! grep -q 'deck accepted' "$log"; then
    echo "  FAILED: $EXE --check $deck (exit $rc):"; tail -n 8 "$log" | sed 's/^/    /'
    return 1
  fi
  nodes=$(grep -oP '^model: \K[0-9]+(?= nodes)' "$log")
  elems=$(grep -oP '^model: [0-9]+ nodes, \K[0-9]+(?= elements)' "$log")
  read_s=$(grep -oP 'deck read and checked in \K[0-9.eE+-]+' "$log")
  mem=$(grep -oP 'peak memory \K[0-9.eE+-]+' "$log")
  rss=$(grep -oP 'Maximum resident set size \(kbytes\): \K[0-9]+' "$log")
  wall=$(grep -oP 'Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): \K.*' "$log")
  [ -n "$wall" ] || wall=$(grep -oP '^real \K[0-9.]+' "$log")
  echo "  $(grep -m1 'deck read and checked' "$log")"
  awk -v f="$deck" -v b="$bytes" -v l="$lines" -v n="$nodes" -v e="$elems" -v t="$read_s" \
      -v m="$mem" -v r="${rss:-}" -v w="$wall" 'BEGIN {
    printf "  %-36s %8.1f MB %10d lines %9d nodes %9d elements\n", f, b/1e6, l, n, e
    printf "  read+check %.2f s (process wall %s), peak memory %.0f MiB (VmHWM)", t, w, m
    if (r != "") printf ", max RSS %.0f MiB", r/1024
    printf "\n  throughput %.2f M lines/s, %.1f MB/s, %.2f M elements/s, %.0f bytes/element\n",
      l/t/1e6, b/t/1e6, e/t/1e6, m*1048576/e
  }'
}

cpu=$(lscpu | grep -m1 'Model name' | sed 's/.*: *//')
echo "== mefem reader benchmark ($(nproc) cores: $cpu)"
status=0
largest=""
for n in $SIZES; do
  deck="$OUT/block_${n}_${LAYOUT}.k"
  echo "-- block ${n}x${n}x${n} cells x 5 tets, $LAYOUT layout"
  make_deck "$deck" "$n" "$n" "$n" --tets 5 --layout "$LAYOUT" || { status=1; continue; }
  time_deck "$deck" || status=1
  largest=$n
done
if [ "${BENCH_LEGACY:-0}" = 1 ] && [ -n "$largest" ] && [ "$LAYOUT" != legacy ]; then
  deck="$OUT/block_${largest}_legacy.k"
  echo "-- block ${largest}x${largest}x${largest} cells x 5 tets, legacy one-line layout"
  make_deck "$deck" "$largest" "$largest" "$largest" --tets 5 --layout legacy || status=1
  [ -f "$deck" ] && { time_deck "$deck" || status=1; }
fi
if [ "${BENCH_PROFILE:-0}" = 1 ]; then
  if command -v valgrind > /dev/null; then
    deck="$OUT/block_34_${LAYOUT}.k"
    echo "-- callgrind profile of reading a 34x34x34 x 5 = 196 520-tet deck"
    make_deck "$deck" 34 34 34 --tets 5 --layout "$LAYOUT"
    valgrind --tool=callgrind --callgrind-out-file="$OUT/callgrind.out" "$EXE" --check "$deck" \
      > "$OUT/callgrind.log" 2>&1
    grep -m1 'refs' "$OUT/callgrind.log" | sed 's/^==[0-9]*== */  instructions: /'
    callgrind_annotate "$OUT/callgrind.out" 2>/dev/null | grep -E '^ *[0-9,]+ +\(' | \
      sed -n '2,16p' | sed -E 's/ \[[^]]*\]$//; s/^/  /'
  else
    echo "  valgrind not installed: no profile"
  fi
fi
exit $status
