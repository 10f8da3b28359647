!> Finite-strain kernels of an integration cell (total Lagrangian, formulation 2.7).
!>
!> With the cell's reference gradients G_I (smoothed for ME-FEM) and nodal displacements u_I:
!>   F = I + sum_I u_I (x) G_I          (plane strain: 3x3 with F_33 = 1)
!>   f_I = w P G_I,  P = tau F^-T        (tau the Kirchhoff stress of the material)
!>   K_IJ(i,k) = w [ a_j^I c_ijkl a_l^J + delta_ik a_j^I tau_jl a_l^J ],  a^I = F^-T G_I,
!> with c the spatial tangent of the Kirchhoff stress (L_v tau = c : d): material plus geometric
!> stiffness, the same code for ME-FEM domains and standard elements. Free of allocation.
module mefem_cell_finite_strain
  use mefem_kinds, only: wp
  implicit none
  private

  public :: cell_deformation_gradient, cell_internal_force, cell_tangent, inverse_3x3

contains

  !> F = I + sum_I u_I (x) G_I (3x3; the out-of-plane row and column stay identity in 2D).
  !> The 3D case sums in scalars (no stores in the node loop); both add the nodes in order,
  !> so the result is the same bits.
  pure subroutine cell_deformation_gradient(dim, nn, grad, u, f)
    integer, intent(in) :: dim, nn          !< dimension (2 plane strain, 3), nodes of the cell
    real(wp), intent(in), contiguous :: grad(:,:)  !< (dim, >= nn) reference gradients
    real(wp), intent(in) :: u(:,:)                 !< (dim, >= nn) displacements
    real(wp), intent(out) :: f(3, 3)               !< deformation gradient
    real(wp) :: f11, f21, f31, f12, f22, f32, f13, f23, f33, u1, u2, u3, g1, g2, g3
    integer :: a, i, j
    f = 0.0_wp
    do i = 1, 3
      f(i, i) = 1.0_wp
    end do
    if (dim == 3) then
      ! scalar accumulators (registers), starting from the identity
      f11 = 1.0_wp
      f21 = 0.0_wp
      f31 = 0.0_wp
      f12 = 0.0_wp
      f22 = 1.0_wp
      f32 = 0.0_wp
      f13 = 0.0_wp
      f23 = 0.0_wp
      f33 = 1.0_wp
      do a = 1, nn
        u1 = u(1, a)
        u2 = u(2, a)
        u3 = u(3, a)
        g1 = grad(1, a)
        g2 = grad(2, a)
        g3 = grad(3, a)
        f11 = f11 + u1*g1
        f21 = f21 + u2*g1
        f31 = f31 + u3*g1
        f12 = f12 + u1*g2
        f22 = f22 + u2*g2
        f32 = f32 + u3*g2
        f13 = f13 + u1*g3
        f23 = f23 + u2*g3
        f33 = f33 + u3*g3
      end do
      f(:, 1) = [f11, f21, f31]
      f(:, 2) = [f12, f22, f32]
      f(:, 3) = [f13, f23, f33]
      return
    end if
    do a = 1, nn
      do j = 1, dim
        do i = 1, dim
          f(i, j) = f(i, j) + u(i, a)*grad(j, a)
        end do
      end do
    end do
  end subroutine cell_deformation_gradient

  !> Inverse and determinant of a 3x3 matrix (det <= 0 is the caller's to check).
  pure subroutine inverse_3x3(m, inv, det)
    real(wp), intent(in) :: m(3, 3)       !< matrix
    real(wp), intent(out) :: inv(3, 3)    !< its inverse (zero if singular)
    real(wp), intent(out) :: det          !< its determinant
    call adjugate_3x3(m, inv, det)
    if (det /= 0.0_wp) then
      inv = inv/det
    else
      inv = 0.0_wp
    end if
  end subroutine inverse_3x3

  !> Nodal internal forces f_I = w tau F^-T G_I (first dim components), evaluated as
  !> (w/J) (tau adj(F)^T) G_I with the adjugate adj(F) = J F^-1: no matrix inverse, one
  !> division, no array temporaries. Zero forces if det F = 0.
  pure subroutine cell_internal_force(dim, nn, grad, weight, f, tau, force)
    integer, intent(in) :: dim, nn                    !< dimension, nodes of the cell
    real(wp), intent(in), contiguous :: grad(:,:)     !< (dim, >= nn) reference gradients
    real(wp), intent(in) :: weight                    !< reference area (unit thickness) or volume
    real(wp), intent(in) :: f(3, 3)                   !< deformation gradient
    real(wp), intent(in) :: tau(3, 3)                 !< Kirchhoff stress
    real(wp), intent(out) :: force(:,:)               !< (dim, >= nn) nodal forces
    real(wp) :: adj(3, 3), det, p(3, 3), factor, g1, g2, g3
    integer :: a, i, j
    call adjugate_3x3(f, adj, det)
    if (det == 0.0_wp) then
      force(1:dim, 1:nn) = 0.0_wp
      return
    end if
    factor = weight/det
    do j = 1, 3                                       ! J times the first Piola-Kirchhoff stress
      do i = 1, 3
        p(i, j) = tau(i, 1)*adj(j, 1) + tau(i, 2)*adj(j, 2) + tau(i, 3)*adj(j, 3)
      end do
    end do
    if (dim == 3) then
      do a = 1, nn
        g1 = grad(1, a)
        g2 = grad(2, a)
        g3 = grad(3, a)
        force(1, a) = factor*(p(1, 1)*g1 + p(1, 2)*g2 + p(1, 3)*g3)
        force(2, a) = factor*(p(2, 1)*g1 + p(2, 2)*g2 + p(2, 3)*g3)
        force(3, a) = factor*(p(3, 1)*g1 + p(3, 2)*g2 + p(3, 3)*g3)
      end do
    else
      do a = 1, nn
        do i = 1, dim
          force(i, a) = factor*(p(i, 1)*grad(1, a) + p(i, 2)*grad(2, a))
        end do
      end do
    end if
  end subroutine cell_internal_force

  !> Adjugate (transposed cofactor matrix, m adj = det 1) and determinant of a 3x3 matrix.
  pure subroutine adjugate_3x3(m, adj, det)
    real(wp), intent(in) :: m(3, 3)       !< matrix
    real(wp), intent(out) :: adj(3, 3)    !< its adjugate
    real(wp), intent(out) :: det          !< its determinant
    adj(1, 1) = m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)
    adj(1, 2) = m(1, 3)*m(3, 2) - m(1, 2)*m(3, 3)
    adj(1, 3) = m(1, 2)*m(2, 3) - m(1, 3)*m(2, 2)
    adj(2, 1) = m(2, 3)*m(3, 1) - m(2, 1)*m(3, 3)
    adj(2, 2) = m(1, 1)*m(3, 3) - m(1, 3)*m(3, 1)
    adj(2, 3) = m(1, 3)*m(2, 1) - m(1, 1)*m(2, 3)
    adj(3, 1) = m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1)
    adj(3, 2) = m(1, 2)*m(3, 1) - m(1, 1)*m(3, 2)
    adj(3, 3) = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
    det = m(1, 1)*adj(1, 1) + m(1, 2)*adj(2, 1) + m(1, 3)*adj(3, 1)
  end subroutine adjugate_3x3

  !> Consistent tangent stiffness (material + geometric), dof order node 1: x y [z], ...
  pure subroutine cell_tangent(dim, nn, grad, weight, f, tau, c, ke)
    integer, intent(in) :: dim, nn            !< dimension, nodes of the cell
    real(wp), intent(in) :: grad(:,:)         !< (dim, >= nn) reference gradients
    real(wp), intent(in) :: weight            !< reference area or volume
    real(wp), intent(in) :: f(3, 3)           !< deformation gradient
    real(wp), intent(in) :: tau(3, 3)         !< Kirchhoff stress
    real(wp), intent(in) :: c(3, 3, 3, 3)     !< spatial tangent of tau
    real(wp), intent(out) :: ke(:,:)          !< (dim*nn, dim*nn)
    real(wp) :: finv(3, 3), det, a(3, nn), g(3), ca(3, 3, 3), geo
    integer :: ia, ib, i, k, j
    call inverse_3x3(f, finv, det)
    do ia = 1, nn                             ! a^I = F^-T G_I (spatial gradients times J)
      g = 0.0_wp
      g(1:dim) = grad(1:dim, ia)
      a(:, ia) = matmul(transpose(finv), g)
    end do
    do ib = 1, nn
      ! ca(i,j,k) = sum_l c_ijkl a_l^J
      do k = 1, 3
        do j = 1, 3
          do i = 1, 3
            ca(i, j, k) = dot_product(c(i, j, k, :), a(:, ib))
          end do
        end do
      end do
      do ia = 1, nn
        geo = dot_product(a(:, ia), matmul(tau, a(:, ib)))
        do k = 1, dim
          do i = 1, dim
            ke(dim*(ia-1) + i, dim*(ib-1) + k) = weight*dot_product(a(:, ia), ca(i, :, k))
          end do
          ke(dim*(ia-1) + k, dim*(ib-1) + k) = ke(dim*(ia-1) + k, dim*(ib-1) + k) + weight*geo
        end do
      end do
    end do
  end subroutine cell_tangent

end module mefem_cell_finite_strain
