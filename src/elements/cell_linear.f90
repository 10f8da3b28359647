!> Small-strain kernels of an integration cell: strain, isotropic elastic stress, stiffness.
!>
!> With cell gradients g_I (reference configuration) the small strain is
!> eps = sym(sum_I u_I (x) g_I) and the isotropic stiffness block of nodes I, J is
!>   K_IJ(i,k) = w [ lambda g_Ii g_Jk + mu ( g_Ik g_Ji + delta_ik g_I . g_J ) ].
!> In plane strain (dim = 2) the same formulas hold in the plane, with eps_zz = 0 and
!> sigma_zz = lambda tr(eps). Stresses are returned in Voigt order xx yy zz xy yz zx.
module mefem_cell_linear
  use mefem_kinds, only: wp
  implicit none
  private

  public :: lame_parameters, cell_strain, isotropic_stress, cell_stiffness

contains

  !> Lame parameters from Young's modulus and Poisson's ratio.
  pure subroutine lame_parameters(young, poisson, lambda, mu)
    real(wp), intent(in) :: young, poisson   !< E, nu
    real(wp), intent(out) :: lambda, mu      !< Lame's first parameter, shear modulus
    mu = young/(2.0_wp*(1.0_wp + poisson))
    lambda = young*poisson/((1.0_wp + poisson)*(1.0_wp - 2.0_wp*poisson))
  end subroutine lame_parameters

  !> Small strain (Voigt, engineering shear doubled: xx yy zz 2xy 2yz 2zx) of a cell.
  pure subroutine cell_strain(dim, nn, grad, u, strain)
    integer, intent(in) :: dim, nn          !< dimension, nodes of the cell
    real(wp), intent(in) :: grad(:,:)       !< (dim, >= nn) gradients
    real(wp), intent(in) :: u(:,:)          !< (dim, >= nn) nodal displacements
    real(wp), intent(out) :: strain(6)      !< strain, engineering shears
    real(wp) :: h(3, 3)
    integer :: i
    h = 0.0_wp
    do i = 1, nn
      h(1:dim, 1:dim) = h(1:dim, 1:dim) + spread(u(1:dim, i), 2, dim)*spread(grad(1:dim, i), 1, dim)
    end do
    strain = [h(1, 1), h(2, 2), h(3, 3), h(1, 2) + h(2, 1), h(2, 3) + h(3, 2), h(3, 1) + h(1, 3)]
  end subroutine cell_strain

  !> Isotropic linear elastic stress from a strain with engineering shears.
  pure subroutine isotropic_stress(lambda, mu, strain, stress)
    real(wp), intent(in) :: lambda, mu      !< Lame parameters
    real(wp), intent(in) :: strain(6)       !< xx yy zz 2xy 2yz 2zx
    real(wp), intent(out) :: stress(6)      !< xx yy zz xy yz zx
    real(wp) :: trace
    trace = strain(1) + strain(2) + strain(3)
    stress(1:3) = lambda*trace + 2.0_wp*mu*strain(1:3)
    stress(4:6) = mu*strain(4:6)
  end subroutine isotropic_stress

  !> Stiffness matrix of a cell, dof order (node 1: x y [z], node 2: ...).
  pure subroutine cell_stiffness(dim, nn, grad, weight, lambda, mu, ke)
    integer, intent(in) :: dim, nn              !< dimension, nodes of the cell
    real(wp), intent(in) :: grad(:,:)           !< (dim, >= nn) gradients
    real(wp), intent(in) :: weight              !< area or volume
    real(wp), intent(in) :: lambda, mu          !< Lame parameters
    real(wp), intent(out) :: ke(:,:)            !< (dim*nn, dim*nn)
    integer :: a, b, i, k
    real(wp) :: gg
    do b = 1, nn
      do a = 1, nn
        gg = dot_product(grad(1:dim, a), grad(1:dim, b))
        do k = 1, dim
          do i = 1, dim
            ke(dim*(a-1) + i, dim*(b-1) + k) = weight*(lambda*grad(i, a)*grad(k, b) &
                + mu*grad(k, a)*grad(i, b))
          end do
          ke(dim*(a-1) + k, dim*(b-1) + k) = ke(dim*(a-1) + k, dim*(b-1) + k) + weight*mu*gg
        end do
      end do
    end do
  end subroutine cell_stiffness

end module mefem_cell_linear
