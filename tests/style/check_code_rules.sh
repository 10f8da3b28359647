#!/usr/bin/env bash
# Code rules of mefem's Fortran (README "Code"; `make lint`, and tests/style/test_code_rules.sh
# in `make test`), checked on the files given (default: src/*/*.f90 tests/unit/*.f90):
#   implicit-none   every module and program has `implicit none` in its specification part
#   private         every module has a bare `private` there (private by default); a type's own
#                   `private` or an interface body's `implicit none` does not count
#   legacy          no COMMON, EQUIVALENCE, GOTO, implicit typing, include of mpif.h
#   newunit         every OPEN statement takes its unit from newunit=
#   libraries       MPI only in src/comm/comm.f90, MUMPS only in src/linalg/mumps_solver.f90,
#                   METIS only in src/partition/metis_partition.f90, HDF5 only in
#                   src/io/hdf5_output.f90
# Prints "PASS: code rules: <rule>" or "FAIL: code rules: <rule>" with file:line of each
# violation; exits 1 if a rule fails.
set -u
cd "$(dirname "$0")/../.."
if [ $# -gt 0 ]; then files=("$@"); else files=(src/*/*.f90 tests/unit/*.f90); fi
status=0

# report RULE VIOLATIONS: PASS when VIOLATIONS (file:line lines) is empty
report() {
  if [ -z "$2" ]; then
    echo "PASS: code rules: $1"
  else
    echo "FAIL: code rules: $1"
    echo "$2" | sed 's/^/    /'
    status=1
  fi
}

# comments stripped (a ! outside quotes ends the code; good enough for these patterns)
code() { sed -e 's/!.*$//' "$1"; }

units=""; private=""; legacy=""; opens=""; libraries=""
for f in "${files[@]}"; do
  # each module and program: `implicit none` (and, for a module, a bare `private`) in its
  # specification part, i.e. before its `contains`, outside type and interface blocks (a
  # type's own `private` or an interface body's `implicit none` does not count)
  missing=$(code "$f" | awk -v file="$f" '
    function report() {
      if (unit != "" && !implicit) printf "%s: %s %s has no implicit none\n", file, kind, unit
      if (unit != "" && kind == "module" && !private) \
        printf "%s: module %s is not private by default\n", file, unit
      unit = ""
    }
    { line = tolower($0) }
    line ~ /^[ \t]*(module|program)[ \t]+[a-z_0-9]+[ \t]*$/ && line !~ /procedure/ {
      report(); kind = $1; unit = $2; implicit = 0; private = 0; depth = 0; spec = 1; next
    }
    !spec { next }
    line ~ /^[ \t]*contains[ \t]*$/ || line ~ /^[ \t]*end[ \t]+(module|program)/ {
      report(); spec = 0; next
    }
    line ~ /^[ \t]*(abstract[ \t]+)?interface([ \t]|$)/ || \
      line ~ /^[ \t]*type[ \t]*(,|::|[ \t]+[a-z])/ { depth++; next }
    line ~ /^[ \t]*end[ \t]+(interface|type)/ { depth--; next }
    depth == 0 && line ~ /^[ \t]*implicit[ \t]+none/ { implicit = 1 }
    depth == 0 && line ~ /^[ \t]*private[ \t]*$/ { private = 1 }
    END { if (spec) report() }')
  units+=$(echo "$missing" | grep 'implicit none' || true)$'\n'
  private+=$(echo "$missing" | grep 'private by default' || true)$'\n'
  legacy+=$(code "$f" | grep -niE '^\s*(common\s*/|equivalence\b|go\s*to\b|include\s+.mpif|implicit\s+(real|integer|double|logical|complex|character|type))|\bgo\s*to\s+[0-9]' \
    | sed "s|^|$f:|")$'\n'
  opens+=$(code "$f" | grep -niE '^\s*open\s*\(' | grep -viE 'newunit\s*=' | sed "s|^|$f:|")$'\n'
  case $f in
    src/comm/comm.f90) ;;
    *) libraries+=$(code "$f" | grep -niE '^\s*use\s+mpi(_f08)?\b|\bcall\s+mpi_' | sed "s|^|$f: MPI:|")$'\n' ;;
  esac
  case $f in
    src/linalg/mumps_solver.f90) ;;
    *) libraries+=$(code "$f" | grep -niE '\bdmumps|\bmumps_struc' | sed "s|^|$f: MUMPS:|")$'\n' ;;
  esac
  case $f in
    src/partition/metis_partition.f90) ;;
    *) libraries+=$(code "$f" | grep -nE '\bMETIS_[A-Za-z]+' | sed "s|^|$f: METIS:|")$'\n' ;;
  esac
  case $f in
    src/io/hdf5_output.f90) ;;
    *) libraries+=$(code "$f" | grep -niE '^\s*use\s+hdf5\b|\bcall\s+h5[a-z]*_f\b' \
         | sed "s|^|$f: HDF5:|")$'\n' ;;
  esac
done
trim() { printf '%s' "$1" | sed '/^$/d'; }
report "implicit none in every module and program" "$(trim "$units")"
report "private by default in every module" "$(trim "$private")"
report "no COMMON, EQUIVALENCE, GOTO or implicit typing" "$(trim "$legacy")"
report "OPEN takes its unit from newunit=" "$(trim "$opens")"
report "MPI, MUMPS, METIS and HDF5 each called from their one module" "$(trim "$libraries")"
exit $status
