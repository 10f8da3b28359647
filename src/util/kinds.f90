!> Kind parameters used everywhere in mefem: one real kind, three integer kinds.
module mefem_kinds
  use, intrinsic :: iso_fortran_env, only: real64, int8, int32, int64
  implicit none
  private

  integer, parameter, public :: wp = real64   !< working precision for all reals
  integer, parameter, public :: i1 = int8     !< small tables of signs and codes
  integer, parameter, public :: i4 = int32    !< default integer (ids, indices)
  integer, parameter, public :: i8 = int64    !< large counts (nnz, byte sizes)
end module mefem_kinds
