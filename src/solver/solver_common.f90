!> Pieces shared by the implicit analyses: equation numbering and stress output fields.
module mefem_solver_common
  use mefem_kinds, only: wp
  use mefem_cells, only: cells_t
  use mefem_output_mesh, only: output_field_t
  implicit none
  private

  public :: number_equations, stress_fields

contains

  !> Equation numbers of the free degrees of freedom of the nodes that cells use (0 = fixed
  !> or unused), in node order.
  subroutine number_equations(cells, fixed, equation, n_equations)
    type(cells_t), intent(in) :: cells                   !< cells
    logical, intent(in) :: fixed(:,:)                    !< (dim, nodes) fixed dofs
    integer, allocatable, intent(out) :: equation(:,:)   !< (dim, nodes) equation numbers
    integer, intent(out) :: n_equations                  !< number of equations
    logical, allocatable :: used(:)
    integer :: c, n, i
    allocate(used(size(fixed, 2)), equation(size(fixed, 1), size(fixed, 2)))
    used = .false.
    do c = 1, cells%n
      used(cells%nodes(1:cells%nnodes(c), c)) = .true.
    end do
    equation = 0
    n_equations = 0
    do n = 1, size(fixed, 2)
      if (.not. used(n)) cycle
      do i = 1, size(fixed, 1)
        if (fixed(i, n)) cycle
        n_equations = n_equations + 1
        equation(i, n) = n_equations
      end do
    end do
  end subroutine number_equations

  !> Output fields 'stress' (6), 'pressure' = -tr/3 and 'von_mises' from summed stresses and
  !> their weights (entities with zero weight get zeros).
  subroutine stress_fields(stress_sum, weight, fields)
    real(wp), intent(in) :: stress_sum(:,:)            !< (6, n) weighted sums
    real(wp), intent(in) :: weight(:)                  !< (n) sums of the weights
    type(output_field_t), intent(inout) :: fields(3)   !< stress, pressure, von_mises
    integer :: k, n
    real(wp) :: s(6)
    n = size(weight)
    fields(1)%name = 'stress'
    fields(1)%ncomp = 6
    fields(2)%name = 'pressure'
    fields(3)%name = 'von_mises'
    allocate(fields(1)%values(6, n), fields(2)%values(1, n), fields(3)%values(1, n))
    do k = 1, n
      s = 0.0_wp
      if (weight(k) > 0.0_wp) s = stress_sum(:, k)/weight(k)
      fields(1)%values(:, k) = s
      fields(2)%values(1, k) = -(s(1) + s(2) + s(3))/3.0_wp
      fields(3)%values(1, k) = sqrt(0.5_wp*((s(1) - s(2))**2 + (s(2) - s(3))**2 + &
          (s(3) - s(1))**2) + 3.0_wp*(s(4)**2 + s(5)**2 + s(6)**2))
    end do
  end subroutine stress_fields

end module mefem_solver_common
