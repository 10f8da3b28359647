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
  use mefem_material_state, only: BLOCK_POINTS
  implicit none
  private

  public :: cell_deformation_gradient, cell_internal_force, cell_tangent, inverse_3x3, &
            adjugate_3x3
  public :: block_deformation_gradient, block_adjugate, block_internal_force, block_strain_rate
  public :: block_face_deformation_gradient, block_face_internal_force, face_gradients_compact, &
            face_gradients_expanded

  !> Compact gradients of an ME-FEM face cell (doc/theory.md 2.2): its MEFEM_FACE_NODES = 7
  !> slots are the first element's 4 corners (1-4), its enriched node (5), the second
  !> element's far corner (6) and enriched node (7). The 5 corners' gradients sum to zero (the
  !> two elements' P1 gradients each do) and the two enriched nodes' gradients are opposite
  !> (2.6: F_cell = F_P1 + c (b_1 - b_2) (x) n), so the 15 numbers G_1..G_4, g = G_5 hold the
  !> cell: G_6 = -(G_1 + .. + G_4), G_7 = -g. A boundary cell (5 nodes) has G_6 = G_7 = 0;
  !> the blocks give its missing slots zero displacements instead (the same F).
  integer, parameter, public :: FACE_COMPACT_COLUMNS = 5

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

  !> Block form (3D) of cell_deformation_gradient for n cells of nn nodes each, structure of
  !> arrays (entry i is cell i; the loops over cells are innermost and vectorise): the same
  !> sums in the same order, so the same bits. f(i, 1:9) is F column by column.
  pure subroutine block_deformation_gradient(n, nn, u, grad, f)
    integer, intent(in) :: n, nn                  !< cells (<= BLOCK_POINTS), nodes per cell
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: u(ld, 3, nn)          !< displacements of the cells' nodes
    real(wp), intent(in) :: grad(ld, 3, nn)       !< reference gradients
    real(wp), intent(out) :: f(ld, 9)             !< deformation gradients
    integer :: i, a
    do i = 1, n
      f(i, 1) = 1.0_wp
      f(i, 2:4) = 0.0_wp
      f(i, 5) = 1.0_wp
      f(i, 6:8) = 0.0_wp
      f(i, 9) = 1.0_wp
    end do
    do a = 1, nn
      do i = 1, n
        f(i, 1) = f(i, 1) + u(i, 1, a)*grad(i, 1, a)
        f(i, 2) = f(i, 2) + u(i, 2, a)*grad(i, 1, a)
        f(i, 3) = f(i, 3) + u(i, 3, a)*grad(i, 1, a)
        f(i, 4) = f(i, 4) + u(i, 1, a)*grad(i, 2, a)
        f(i, 5) = f(i, 5) + u(i, 2, a)*grad(i, 2, a)
        f(i, 6) = f(i, 6) + u(i, 3, a)*grad(i, 2, a)
        f(i, 7) = f(i, 7) + u(i, 1, a)*grad(i, 3, a)
        f(i, 8) = f(i, 8) + u(i, 2, a)*grad(i, 3, a)
        f(i, 9) = f(i, 9) + u(i, 3, a)*grad(i, 3, a)
      end do
    end do
  end subroutine block_deformation_gradient

  !> Block form of F for ME-FEM face cells with compact gradients (FACE_COMPACT_COLUMNS):
  !> F = I + sum_{a=1..4} (u_a - u_6) (x) G_a + (u_5 - u_7) (x) g, the same field as the
  !> 7-node sum (G_6 = -(G_1 + .. + G_4), G_7 = -g) with 15 gradients streamed instead of 21
  !> and differences of displacements instead of their sum. A boundary cell's slots 6 and 7
  !> must hold zero displacements.
  pure subroutine block_face_deformation_gradient(n, u, grad, f)
    integer, intent(in) :: n                      !< cells (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: u(ld, 3, 7)           !< displacements of the cells' 7 slots
    real(wp), intent(in) :: grad(ld, 3, FACE_COMPACT_COLUMNS) !< compact gradients
    real(wp), intent(out) :: f(ld, 9)             !< deformation gradients, by column
    real(wp) :: d(ld, 3, FACE_COMPACT_COLUMNS)
    integer :: i, k, a, p
    do a = 1, FACE_COMPACT_COLUMNS
      ! slot pairs: the corners 1-4 relative to the far corner 6, then the bubble jump 5 - 7
      p = merge(6, 7, a < FACE_COMPACT_COLUMNS)
      do k = 1, 3
        do i = 1, n
          d(i, k, a) = u(i, k, a) - u(i, k, p)
        end do
      end do
    end do
    call block_deformation_gradient(n, FACE_COMPACT_COLUMNS, d, grad, f)
  end subroutine block_face_deformation_gradient

  !> The compact gradients (FACE_COMPACT_COLUMNS columns) of an ME-FEM face cell from its
  !> full ones (slots as above).
  pure function face_gradients_compact(grad) result(compact)
    real(wp), intent(in) :: grad(3, 7)            !< gradients of the 7 slots
    real(wp) :: compact(3, FACE_COMPACT_COLUMNS)
    compact = grad(:, 1:FACE_COMPACT_COLUMNS)
  end function face_gradients_compact

  !> The 7 slots' gradients of an ME-FEM face cell of nn nodes (7, or 5 on the boundary)
  !> from its compact ones (G_6 = -(G_1 + .. + G_4), G_7 = -g; a boundary cell's zero).
  pure function face_gradients_expanded(nn, compact) result(grad)
    integer, intent(in) :: nn                     !< nodes of the cell
    real(wp), intent(in) :: compact(3, FACE_COMPACT_COLUMNS)  !< G_1..G_4, g
    real(wp) :: grad(3, 7)
    grad = 0.0_wp
    grad(:, 1:FACE_COMPACT_COLUMNS) = compact
    if (nn == 7) then
      grad(:, 6) = -(compact(:, 1) + compact(:, 2) + compact(:, 3) + compact(:, 4))
      grad(:, 7) = -compact(:, 5)
    end if
  end function face_gradients_expanded

  !> Effective strain rates of n cells (block form, as block_deformation_gradient): Fdot =
  !> sum_a v_a (x) grad_a, l = Fdot F^-1 = Fdot adj(F)/J, d = sym(l), and the rate sqrt(d : d)
  !> (deviatoric: sqrt(dev d : dev d)), LS-DYNA's measure for the Cowper-Symonds scale
  !> (doc/theory.md section 4). Cells with J <= 0 get 0.
  pure subroutine block_strain_rate(n, nn, face, v, grad, adj, det, deviatoric, rate)
    integer, intent(in) :: n, nn                  !< cells (<= BLOCK_POINTS), nodes per cell
    logical, intent(in) :: face                   !< ME-FEM face cells, compact gradients
                                                  !< (block_face_deformation_gradient)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: v(ld, 3, nn)          !< velocities of the cells' nodes
    real(wp), intent(in) :: grad(ld, 3, nn)       !< reference gradients
    real(wp), intent(in) :: adj(ld, 9)            !< adj(F), column by column
    real(wp), intent(in) :: det(ld)               !< J = det F
    logical, intent(in) :: deviatoric             !< the deviatoric rate (VP = -1)
    real(wp), intent(out) :: rate(ld)             !< effective strain rates
    real(wp) :: fdot(ld, 9), l(9), d(6), mean
    integer :: i, r, c
    if (face) then                                ! (I + Fdot: the identity taken off)
      call block_face_deformation_gradient(n, v, grad, fdot)
    else
      call block_deformation_gradient(n, nn, v, grad, fdot)
    end if
    do i = 1, n
      fdot(i, 1) = fdot(i, 1) - 1.0_wp
      fdot(i, 5) = fdot(i, 5) - 1.0_wp
      fdot(i, 9) = fdot(i, 9) - 1.0_wp
    end do
    do i = 1, n
      rate(i) = 0.0_wp
      if (.not. det(i) > 0.0_wp) cycle
      do c = 1, 3                               ! l(r, c) = sum_k Fdot(r, k) adj(k, c) / J
        do r = 1, 3
          l(r + 3*(c - 1)) = (fdot(i, r)*adj(i, 1 + 3*(c - 1)) + fdot(i, r + 3)* &
              adj(i, 2 + 3*(c - 1)) + fdot(i, r + 6)*adj(i, 3 + 3*(c - 1)))/det(i)
        end do
      end do
      d = [l(1), l(5), l(9), 0.5_wp*(l(4) + l(2)), 0.5_wp*(l(8) + l(6)), 0.5_wp*(l(3) + l(7))]
      if (deviatoric) then
        mean = (d(1) + d(2) + d(3))/3.0_wp
        d(1:3) = d(1:3) - mean
      end if
      rate(i) = sqrt(d(1)**2 + d(2)**2 + d(3)**2 + 2.0_wp*(d(4)**2 + d(5)**2 + d(6)**2))
    end do
  end subroutine block_strain_rate

  !> Adjugates and determinants of n 3x3 matrices (block form of adjugate_3x3, the same
  !> expressions); m(i, :) and adj(i, :) column by column.
  pure subroutine block_adjugate(n, m, adj, det)
    integer, intent(in) :: n                      !< matrices (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: m(ld, 9)              !< the matrices
    real(wp), intent(out) :: adj(ld, 9)           !< their adjugates
    real(wp), intent(out) :: det(ld)              !< their determinants
    integer :: i
    do i = 1, n
      adj(i, 1) = m(i, 5)*m(i, 9) - m(i, 8)*m(i, 6)
      adj(i, 4) = m(i, 7)*m(i, 6) - m(i, 4)*m(i, 9)
      adj(i, 7) = m(i, 4)*m(i, 8) - m(i, 7)*m(i, 5)
      adj(i, 2) = m(i, 8)*m(i, 3) - m(i, 2)*m(i, 9)
      adj(i, 5) = m(i, 1)*m(i, 9) - m(i, 7)*m(i, 3)
      adj(i, 8) = m(i, 7)*m(i, 2) - m(i, 1)*m(i, 8)
      adj(i, 3) = m(i, 2)*m(i, 6) - m(i, 5)*m(i, 3)
      adj(i, 6) = m(i, 4)*m(i, 3) - m(i, 1)*m(i, 6)
      adj(i, 9) = m(i, 1)*m(i, 5) - m(i, 4)*m(i, 2)
      det(i) = m(i, 1)*adj(i, 1) + m(i, 4)*adj(i, 2) + m(i, 7)*adj(i, 3)
    end do
  end subroutine block_adjugate

  !> Block form (3D) of cell_internal_force: f_I = (w/J) (tau adj(F)^T) G_I for n cells of nn
  !> nodes, with adj(F) and J from block_adjugate and tau symmetric (XX YY ZZ XY YZ ZX); the
  !> same expressions, so the same bits. Cells with J = 0 get zero forces.
  pure subroutine block_internal_force(n, nn, grad, weight, adj, det, tau, force)
    integer, intent(in) :: n, nn                  !< cells (<= BLOCK_POINTS), nodes per cell
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: grad(ld, 3, nn)       !< reference gradients
    real(wp), intent(in) :: weight(ld)            !< reference volumes
    real(wp), intent(in) :: adj(ld, 9)            !< adj(F), column by column
    real(wp), intent(in) :: det(ld)               !< J = det F
    real(wp), intent(in) :: tau(ld, 6)            !< Kirchhoff stresses
    real(wp), intent(out) :: force(ld, 3, nn)     !< nodal forces
    real(wp) :: p(ld, 9), factor(ld)
    integer :: i, a
    ! selects and divisions in loops of their own (gfortran vectorises neither a division
    ! of a selected value nor a select of a quotient)
    do i = 1, n
      factor(i) = merge(det(i), 1.0_wp, det(i) /= 0.0_wp)
    end do
    do i = 1, n
      factor(i) = weight(i)/factor(i)
    end do
    do i = 1, n
      factor(i) = merge(factor(i), 0.0_wp, det(i) /= 0.0_wp)
    end do
    do i = 1, n
      ! p(r, c) = sum_k tau(r, k) adj(c, k) (J times the first Piola-Kirchhoff stress)
      p(i, 1) = tau(i, 1)*adj(i, 1) + tau(i, 4)*adj(i, 4) + tau(i, 6)*adj(i, 7)
      p(i, 2) = tau(i, 4)*adj(i, 1) + tau(i, 2)*adj(i, 4) + tau(i, 5)*adj(i, 7)
      p(i, 3) = tau(i, 6)*adj(i, 1) + tau(i, 5)*adj(i, 4) + tau(i, 3)*adj(i, 7)
      p(i, 4) = tau(i, 1)*adj(i, 2) + tau(i, 4)*adj(i, 5) + tau(i, 6)*adj(i, 8)
      p(i, 5) = tau(i, 4)*adj(i, 2) + tau(i, 2)*adj(i, 5) + tau(i, 5)*adj(i, 8)
      p(i, 6) = tau(i, 6)*adj(i, 2) + tau(i, 5)*adj(i, 5) + tau(i, 3)*adj(i, 8)
      p(i, 7) = tau(i, 1)*adj(i, 3) + tau(i, 4)*adj(i, 6) + tau(i, 6)*adj(i, 9)
      p(i, 8) = tau(i, 4)*adj(i, 3) + tau(i, 2)*adj(i, 6) + tau(i, 5)*adj(i, 9)
      p(i, 9) = tau(i, 6)*adj(i, 3) + tau(i, 5)*adj(i, 6) + tau(i, 3)*adj(i, 9)
    end do
    do a = 1, nn
      do i = 1, n
        force(i, 1, a) = factor(i)*(p(i, 1)*grad(i, 1, a) + p(i, 4)*grad(i, 2, a) + &
                                    p(i, 7)*grad(i, 3, a))
        force(i, 2, a) = factor(i)*(p(i, 2)*grad(i, 1, a) + p(i, 5)*grad(i, 2, a) + &
                                    p(i, 8)*grad(i, 3, a))
        force(i, 3, a) = factor(i)*(p(i, 3)*grad(i, 1, a) + p(i, 6)*grad(i, 2, a) + &
                                    p(i, 9)*grad(i, 3, a))
      end do
    end do
  end subroutine block_internal_force

  !> Block form of the nodal forces of ME-FEM face cells with compact gradients
  !> (FACE_COMPACT_COLUMNS): f_a = (w/J) (tau adj(F)^T) G_a for the 4 corners and the first
  !> enriched node as in block_internal_force, then f_6 = -(f_1 + .. + f_4) and f_7 = -f_5
  !> (a boundary cell's slots 6 and 7 get these too and are not assembled).
  pure subroutine block_face_internal_force(n, grad, weight, adj, det, tau, force)
    integer, intent(in) :: n                      !< cells (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: grad(ld, 3, FACE_COMPACT_COLUMNS) !< compact gradients
    real(wp), intent(in) :: weight(ld)            !< reference volumes
    real(wp), intent(in) :: adj(ld, 9)            !< adj(F), column by column
    real(wp), intent(in) :: det(ld)               !< J = det F
    real(wp), intent(in) :: tau(ld, 6)            !< Kirchhoff stresses
    real(wp), intent(out) :: force(ld, 3, 7)      !< nodal forces of the 7 slots
    integer :: i, k
    call block_internal_force(n, FACE_COMPACT_COLUMNS, grad, weight, adj, det, tau, &
                              force(:, :, 1:FACE_COMPACT_COLUMNS))
    do k = 1, 3
      do i = 1, n
        force(i, k, 6) = -(force(i, k, 1) + force(i, k, 2) + force(i, k, 3) + force(i, k, 4))
        force(i, k, 7) = -force(i, k, 5)
      end do
    end do
  end subroutine block_face_internal_force

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
