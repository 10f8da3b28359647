#!/usr/bin/env bash
# The code rules (check_code_rules.sh) hold for src/ and tests/unit/, and the checker catches
# each kind of violation in a file written to break them all.
set -u
cd "$(dirname "$0")/../.."
bash tests/style/check_code_rules.sh

bad_dir=tests/out/style
mkdir -p "$bad_dir"
bad=$bad_dir/bad_rules.f90
cat > "$bad" <<'F90'
module bad_rules
  use mpi_f08
  real :: shared_value
  common /block/ shared_value
contains
  subroutine legacy(x)
    real, intent(inout) :: x
    integer :: u
    open(unit=10, file='x.txt')
    go to 20
20  x = x + 1.0
    call METIS_PartMeshDual()
    call h5open_f(u)
  end subroutine legacy
end module bad_rules

module bad_private_type
  implicit none
  type :: hidden_t
    private
    integer :: n = 0
  end type hidden_t
contains
  subroutine noop()
    implicit none
  end subroutine noop
end module bad_private_type

program bad_program
  use bad_private_type
  interface
    subroutine external_routine()
      implicit none
    end subroutine external_routine
  end interface
end program bad_program
F90
out=$(bash tests/style/check_code_rules.sh "$bad")
for rule in "implicit none in every module" "private by default" "no COMMON, EQUIVALENCE, GOTO" \
            "OPEN takes its unit" "MPI, MUMPS, METIS and HDF5"; do
  if echo "$out" | grep -q "^FAIL: code rules: $rule"; then
    echo "PASS: code rules: the checker catches a file that breaks \"$rule\""
  else
    echo "FAIL: code rules: the checker missed a file that breaks \"$rule\""
  fi
done
# a type's own private, or an interface body's implicit none, is not the unit's
for unit in "module bad_private_type is not private by default" \
            "program bad_program has no implicit none"; do
  if echo "$out" | grep -q "$unit"; then
    echo "PASS: code rules: the checker reports \"$unit\""
  else
    echo "FAIL: code rules: the checker missed \"$unit\""
  fi
done
for library in MPI METIS HDF5; do
  if echo "$out" | grep -q "bad_rules.f90: $library:"; then
    echo "PASS: code rules: the checker names the $library call outside its module"
  else
    echo "FAIL: code rules: the checker missed the $library call outside its module"
  fi
done
