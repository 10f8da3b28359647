#!/usr/bin/env bash
# Run every mefem test and print the total as the last line: "N passed, N failed".
#
# Kinds of tests (each prints lines "PASS: ..." or "FAIL: ..."; those lines are counted):
#  1. unit tests: build/debug/tests/test_* (Fortran, debug build). A line "! ranks: 1 2 3" in
#     the test's source runs it under mpirun with each of those rank counts.
#  2. deck tests: every deck in input/ and tests/decks/good/ must pass `mefem --check` (and
#     print each warning given on its "$ expect-warning: ..." lines); every deck in
#     tests/decks/broken/ must fail with a non-zero exit and print each message given on its
#     "$ expect: ..." lines.
#  3. script tests: tests/*/test_*.sh and tests/*/test_*.py (output round trips, MPI runs).
# A program that exits non-zero without printing a FAIL line counts as one failure.
set -u
cd "$(dirname "$0")/.."
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMPI_MCA_rmaps_base_oversubscribe=1 OPENBLAS_NUM_THREADS=1
export MEFEM_ROOT=$PWD
MPIRUN="mpirun --oversubscribe"
PY=/usr/bin/python3
pass=0; fail=0
log=tests/out/test.log
mkdir -p tests/out; : > "$log"

# Count PASS/FAIL lines of one run's output; a non-zero exit with no FAIL is a failure.
tally() {  # tally NAME RC OUTPUT-FILE
  local name=$1 rc=$2 out=$3 p f
  cat "$out" >> "$log"
  p=$(grep -c '^PASS' "$out"); f=$(grep -c '^FAIL' "$out")
  grep '^FAIL' "$out"
  if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
    echo "FAIL: $name: exited with code $rc"; tail -n 5 "$out" | sed 's/^/    /'
    f=1
  fi
  pass=$((pass + p)); fail=$((fail + f))
}

echo "== unit tests"
for exe in build/debug/tests/test_*; do
  [ -x "$exe" ] || continue
  name=$(basename "$exe")
  ranks=$(grep -m1 -oP '^!\s*ranks:\s*\K[0-9 ]+' "tests/unit/$name.f90" 2>/dev/null || echo 1)
  for np in $ranks; do
    out=$(mktemp)
    if [ "$np" = 1 ]; then (cd tests/unit && "../../$exe") > "$out" 2>&1; rc=$?
    else (cd tests/unit && $MPIRUN -np "$np" "../../$exe") > "$out" 2>&1; rc=$?; fi
    tally "$name (np=$np)" $rc "$out"; rm -f "$out"
  done
done

# the block kernels' placement checks on the release build, whose vector loops they concern
exe=build/release/tests/test_block_kernels
if [ -x "$exe" ]; then
  out=$(mktemp)
  (cd tests/unit && "../../$exe" placement) > "$out" 2>&1; rc=$?
  tally "test_block_kernels placement (release build)" $rc "$out"; rm -f "$out"
fi

echo "== deck tests"
out=$(mktemp)
for deck in input/*.k tests/decks/good/*.k; do
  [ -f "$deck" ] || continue
  if bin/mefem_debug --check "$deck" > "$out.o" 2>&1; then echo "PASS: check accepts $deck"
  else echo "FAIL: check rejects $deck:"; sed 's/^/    /' "$out.o" | head -20; fi
  # a good deck may name warnings it must get ("$ expect-warning: text")
  while IFS= read -r want; do
    if grep -qF -- "$want" "$out.o"; then echo "PASS: $deck warns: $want"
    else echo "FAIL: $deck: missing warning: $want"; fi
  done < <(grep -aoP '^\$ expect-warning: \K.*' "$deck")
done > "$out"
tally "good decks" 0 "$out"
# broken decks with both builds: the debug build traps floating-point exceptions, so a check
# that overflows shows here; the release build is what users run
for deck in tests/decks/broken/*.k; do
  [ -f "$deck" ] || continue
  for exe in mefem_debug mefem; do
    bin/$exe --check "$deck" > "$out.o" 2>&1; rc=$?
    {
      if [ $rc -eq 0 ]; then echo "FAIL: $deck: accepted by $exe (exit 0)"
      elif [ $rc -gt 1 ]; then echo "FAIL: $deck: $exe crashed (exit $rc)"
        sed 's/^/    /' "$out.o" | head
      else
        ok=1
        while IFS= read -r want; do
          grep -qF -- "$want" "$out.o" || { ok=0; echo "FAIL: $deck ($exe): missing message: $want"; }
        done < <(grep -aoP '^\$ expect: \K.*' "$deck")
        # and messages it must not get ("$ expect-not: text": a misleading suggestion)
        while IFS= read -r unwanted; do
          grep -qF -- "$unwanted" "$out.o" && { ok=0; echo "FAIL: $deck ($exe): unwanted message: $unwanted"; }
        done < <(grep -aoP '^\$ expect-not: \K.*' "$deck")
        grep -aq '^\$ expect: ' "$deck" || { ok=0; echo "FAIL: $deck: has no '\$ expect:' line"; }
        [ $ok = 1 ] && echo "PASS: $exe rejects $deck"
        [ $ok = 1 ] || { echo "    got:"; sed 's/^/    /' "$out.o" | head -20; }
      fi
    } > "$out"
    tally "$deck ($exe)" 0 "$out"
  done
done
rm -f "$out" "$out.o"

echo "== script tests"
for t in tests/*/test_*.sh tests/*/test_*.py; do
  [ -f "$t" ] || continue
  out=$(mktemp)
  case $t in
    *.sh) bash "$t" > "$out" 2>&1 ;;
    *.py) $PY "$t" > "$out" 2>&1 ;;
  esac
  tally "$t" $? "$out"; rm -f "$out"
done

echo "$pass passed, $fail failed"
[ "$fail" -eq 0 ]
