#!/usr/bin/env bash
# Print make rules "object: objects-of-modules-it-uses" for the Fortran sources given.
# Usage: fortran_deps.sh BUILD_DIR file.f90 ...   (src/X/y.f90 -> BUILD/X/y.o,
# tests/unit/z.f90 -> BUILD/tests/z.o). Modules not defined in the sources (mpi_f08, hdf5,
# iso_c_binding, ...) are ignored.
set -eu
build=$1; shift
obj_of() {
  case $1 in
    src/*) f=${1#src/}; echo "$build/${f%.f90}.o" ;;
    tests/unit/*) f=${1#tests/unit/}; echo "$build/tests/${f%.f90}.o" ;;
  esac
}
declare -A provider
for f in "$@"; do
  for m in $(grep -iE '^\s*module\s+[a-z0-9_]+\s*$' "$f" | awk '{print tolower($2)}'); do
    provider[$m]=$(obj_of "$f")
  done
done
for f in "$@"; do
  o=$(obj_of "$f")
  deps=""
  for m in $(grep -iE '^\s*use\s*(,\s*non_intrinsic\s*)?(::)?\s*[a-z0-9_]+' "$f" \
             | sed -E 's/^\s*use\s*(,\s*non_intrinsic\s*)?(::)?\s*//I' | awk -F'[ ,]' '{print tolower($1)}' | sort -u); do
    p=${provider[$m]:-}
    if [ -n "$p" ] && [ "$p" != "$o" ]; then deps="$deps $p"; fi
  done
  [ -n "$deps" ] && echo "$o:$deps"
done
exit 0
