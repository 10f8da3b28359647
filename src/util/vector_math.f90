!> Small vector helpers shared by the geometry code.
module mefem_vector_math
  use mefem_kinds, only: wp
  implicit none
  private

  public :: cross

contains

  !> Cross product of two 3-vectors.
  pure function cross(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)   !< vectors
    real(wp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross

end module mefem_vector_math
