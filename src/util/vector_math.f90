!> Small vector helpers shared by the geometry code.
module mefem_vector_math
  use mefem_kinds, only: wp
  implicit none
  private

  public :: cross, frame_from_vectors

contains

  !> Cross product of two 3-vectors.
  pure function cross(a, b) result(c)
    real(wp), intent(in) :: a(3), b(3)   !< vectors
    real(wp) :: c(3)
    c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
  end function cross

  !> The unit axes (columns) of a Cartesian frame from the direction of one axis and a vector
  !> in its plane with the next: axis first_axis (1 x, 2 y, 3 z) = along/|along|, the third
  !> = along x in_plane normalised, the next = third x first (DIR X: x y z; Y: y z x; Z: z x y).
  !> ok is false, axes unset, when along is 0 or in_plane is parallel to it (sine below
  !> PARALLEL_SINE).
  pure subroutine frame_from_vectors(first_axis, along, in_plane, axes, ok)
    integer, intent(in) :: first_axis             !< 1, 2 or 3
    real(wp), intent(in) :: along(3), in_plane(3) !< global vectors
    real(wp), intent(inout) :: axes(3, 3)         !< the axes (columns)
    logical, intent(out) :: ok                    !< the frame is defined
    !> sin of the least angle between the axis and the in-plane vector
    real(wp), parameter :: PARALLEL_SINE = 1.0e-10_wp
    real(wp) :: x(3), z(3)
    ok = norm2(along) > 0.0_wp .and. norm2(in_plane) > 0.0_wp
    if (.not. ok) return
    x = along/norm2(along)
    z = cross(x, in_plane)
    ok = norm2(z) > PARALLEL_SINE*norm2(in_plane)
    if (.not. ok) return
    z = z/norm2(z)
    axes(:, first_axis) = x
    axes(:, modulo(first_axis + 1, 3) + 1) = z
    axes(:, modulo(first_axis, 3) + 1) = cross(z, x)
  end subroutine frame_from_vectors

end module mefem_vector_math
