!> The one-point hexahedron (solid ELFORM 1, Flanagan-Belytschko uniform gradient) and its
!> hourglass control (doc/theory.md 2.8).
!>
!> Reference geometry (hexahedron_reference), exact for any trilinear hexahedron, degenerate
!> ones included (2 x 2 x 2 Gauss points integrate every term below exactly):
!>   V = int dV,   B_I = (1/V) int grad_X N_I dV   (the uniform gradient: F = I + sum u_I (x) B_I
!>   is the volume mean of the deformation gradient),   V_I = int N_I dV   (lumped mass rho V_I),
!>   gamma_aI = h_aI - (sum_J h_aJ X_J) . B_I   (Flanagan-Belytschko hourglass shape vectors:
!>   orthogonal to the linear fields, sum_I gamma_aI X_I = 0 and sum_I gamma_aI = 0),
!> with h_a the base vectors xi eta, eta zeta, zeta xi, xi eta zeta at the nodes.
!>
!> Hourglass control, per cell, with q_a = sum_I gamma_aI u_I the hourglass displacements:
!> - stiffness: the energy W = 1/2 sum_a Q_a . K Q_a of the pulled-back hourglass vectors
!>   Q_a = F^-1 q_a (objective: a rigid rotation leaves it unchanged) with the reference tensor
!>   K; the forces are its exact derivative, f_I = sum_a F^-T K Q_a (gamma_aI - B_I . Q_a);
!> - viscous: f_I = c sum_a gamma_aI qdot_a, qdot_a = sum_I gamma_aI v_I, dissipating
!>   c sum_a |qdot_a|^2.
!> Node order is LS-DYNA's: N1-N4 the bottom face, N5-N8 the top, N1-N2-N3 counter-clockwise
!> seen from N5.
module mefem_hexahedron
  use mefem_kinds, only: wp, i1
  use mefem_material_state, only: BLOCK_POINTS
  use mefem_cell_finite_strain, only: adjugate_3x3
  implicit none
  private

  public :: hexahedron_reference, hourglass_mode_metric, block_hourglass_forces, &
            hourglass_stiffness_cell, block_hexahedron_frequency

  integer, parameter, public :: HOURGLASS_MODES = 4      !< hourglass base vectors per direction
  !> Faces of the hexahedron (corners, each a cycle around the face).
  integer, parameter :: HEX_FACES(4, 6) = reshape([1, 2, 3, 4,  5, 6, 7, 8,  1, 2, 6, 5, &
                                                   2, 3, 7, 6,  3, 4, 8, 7,  4, 1, 5, 8], [4, 6])

  !> The hourglass base vectors h_a at the corners (xi eta, eta zeta, zeta xi, xi eta zeta),
  !> corner by corner.
  integer(i1), parameter, public :: HOURGLASS_VECTORS(8, HOURGLASS_MODES) = reshape(int([ &
       1, -1,  1, -1,  1, -1,  1, -1,    1,  1, -1, -1, -1, -1,  1,  1, &
       1, -1, -1,  1, -1,  1,  1, -1,   -1,  1, -1,  1,  1, -1,  1, -1], i1), &
      [8, HOURGLASS_MODES])

  !> Natural coordinates of the nodes (xi, eta, zeta), node by node.
  real(wp), parameter :: NODE_XI(3, 8) = reshape([ &
      -1.0_wp, -1.0_wp, -1.0_wp,   1.0_wp, -1.0_wp, -1.0_wp,   1.0_wp, 1.0_wp, -1.0_wp, &
      -1.0_wp, 1.0_wp, -1.0_wp,   -1.0_wp, -1.0_wp, 1.0_wp,    1.0_wp, -1.0_wp, 1.0_wp, &
       1.0_wp, 1.0_wp, 1.0_wp,    -1.0_wp, 1.0_wp, 1.0_wp], [3, 8])

contains

  !> Reference geometry of a (possibly degenerate) hexahedron from its 8 corners in LS-DYNA
  !> order: volume, uniform gradients, nodal volumes and hourglass shape vectors (module
  !> header). A corner given twice (a collapsed hexahedron) gets one entry per occurrence;
  !> the caller adds those of one node together.
  pure subroutine hexahedron_reference(x, volume, grad, node_volume, gamma)
    real(wp), intent(in) :: x(3, 8)             !< corner coordinates
    real(wp), intent(out) :: volume             !< V
    real(wp), intent(out) :: grad(3, 8)         !< B_I
    real(wp), intent(out) :: node_volume(8)     !< V_I = int N_I dV
    real(wp), intent(out) :: gamma(8, HOURGLASS_MODES)  !< gamma_aI, node by node
    real(wp), parameter :: G = 0.577350269189625764509148780502_wp   ! 1/sqrt(3)
    real(wp) :: dn(3, 8), n(8), jac(3, 3), adj(3, 3), det, xi(3), hx(3)
    integer :: p, a, k, m
    volume = 0.0_wp
    grad = 0.0_wp
    node_volume = 0.0_wp
    do p = 1, 8                                  ! the Gauss points: the corners scaled by G
      xi = G*NODE_XI(:, p)
      do a = 1, 8
        n(a) = 0.125_wp*(1.0_wp + NODE_XI(1, a)*xi(1))*(1.0_wp + NODE_XI(2, a)*xi(2))* &
               (1.0_wp + NODE_XI(3, a)*xi(3))
        dn(1, a) = 0.125_wp*NODE_XI(1, a)*(1.0_wp + NODE_XI(2, a)*xi(2))* &
                   (1.0_wp + NODE_XI(3, a)*xi(3))
        dn(2, a) = 0.125_wp*NODE_XI(2, a)*(1.0_wp + NODE_XI(1, a)*xi(1))* &
                   (1.0_wp + NODE_XI(3, a)*xi(3))
        dn(3, a) = 0.125_wp*NODE_XI(3, a)*(1.0_wp + NODE_XI(1, a)*xi(1))* &
                   (1.0_wp + NODE_XI(2, a)*xi(2))
      end do
      ! jac(i, k) = dx_i/dxi_k; det grad_X N = adj(jac)^T grad_xi N (valid where det = 0 too)
      do k = 1, 3
        do m = 1, 3
          jac(m, k) = sum(x(m, :)*dn(k, :))
        end do
      end do
      call adjugate_3x3(jac, adj, det)
      volume = volume + det
      do a = 1, 8
        node_volume(a) = node_volume(a) + n(a)*det
        do m = 1, 3
          grad(m, a) = grad(m, a) + adj(1, m)*dn(1, a) + adj(2, m)*dn(2, a) + adj(3, m)*dn(3, a)
        end do
      end do
    end do
    if (volume > 0.0_wp) grad = grad/volume
    do k = 1, HOURGLASS_MODES
      do m = 1, 3
        hx(m) = sum(HOURGLASS_VECTORS(:, k)*x(m, :))
      end do
      do a = 1, 8
        gamma(a, k) = HOURGLASS_VECTORS(a, k) - (hx(1)*grad(1, a) + hx(2)*grad(2, a) + &
                                                 hx(3)*grad(3, a))
      end do
    end do
  end subroutine hexahedron_reference

  !> Bound of the largest eigenvalue of the hourglass modes' inverse-mass metric G_ab =
  !> sum_I gamma_aI gamma_bI / m_I (4 x 4, symmetric): its largest absolute row sum
  !> (Gershgorin; exact for a parallelepiped, whose G is diagonal with equal entries). The
  !> hourglass stiffness K then gives omega^2 <= (K : C^-1) lambda_max(G) (doc/theory.md 2.8).
  pure real(wp) function hourglass_mode_metric(nn, gamma, mass) result(bound)
    integer, intent(in) :: nn                              !< nodes of the cell
    real(wp), intent(in) :: gamma(:, :)                    !< (>= nn, HOURGLASS_MODES)
    real(wp), intent(in) :: mass(:)                        !< (>= nn) nodal masses (> 0)
    real(wp) :: row
    integer :: a, b
    bound = 0.0_wp
    do a = 1, HOURGLASS_MODES
      row = 0.0_wp
      do b = 1, HOURGLASS_MODES
        row = row + abs(sum(gamma(1:nn, a)*gamma(1:nn, b)/mass(1:nn)))
      end do
      bound = max(bound, row)
    end do
  end function hourglass_mode_metric

  !> Hourglass forces of n hexahedral cells (structure of arrays, entry i cell i): the
  !> stiffness and viscous forces of the module header added to force; per cell the stored
  !> energy W and the dissipated power c sum |qdot|^2. Cells with J <= 0 get none (their
  !> step bound stops the run). The shape vectors are formed here from the cells' base
  !> vectors and hX (gamma_aI = h_aI - hX_a . B_I: the module header), which streams 128
  !> bytes per cell where the vectors themselves would be 256. Without viscous forms (every
  !> c = 0) v is not read: the stiffness forms need no velocities.
  pure subroutine block_hourglass_forces(n, nn, u, viscous, v, grad, h, hx, stiffness, &
                                         viscosity, adj, det, force, energy, power)
    integer, intent(in) :: n, nn                  !< cells (<= BLOCK_POINTS), nodes per cell
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: u(ld, 3, nn)          !< displacements of the cells' nodes
    logical, intent(in) :: viscous                !< some cell has a viscous form (c > 0)
    real(wp), intent(in) :: v(ld, 3, nn)          !< their velocities (read if viscous)
    real(wp), intent(in) :: grad(ld, 3, nn)       !< uniform gradients B_I
    integer(i1), intent(in) :: h(ld, nn, HOURGLASS_MODES)  !< base vectors h_aI (a repeated
                                                  !< corner's added into its node)
    real(wp), intent(in) :: hx(ld, 3, HOURGLASS_MODES)     !< hX_a = sum_I h_aI X_I
    real(wp), intent(in) :: stiffness(ld, 6)      !< K (XX YY ZZ XY YZ ZX)
    real(wp), intent(in) :: viscosity(ld)         !< c
    real(wp), intent(in) :: adj(ld, 9)            !< adj(F), column by column
    real(wp), intent(in) :: det(ld)               !< J = det F
    real(wp), intent(inout) :: force(ld, 3, nn)   !< nodal forces, hourglass forces added
    real(wp), intent(out) :: energy(ld)           !< W of each cell
    real(wp), intent(out) :: power(ld)            !< c sum |qdot|^2 of each cell
    real(wp), dimension(ld) :: s1, s2, s3, inverse_det, r
    real(wp) :: finv(ld, 9), gamma(ld, nn, HOURGLASS_MODES), q(ld, 3, HOURGLASS_MODES), &
                d(ld, 3, HOURGLASS_MODES), big(ld, 3, HOURGLASS_MODES), t(ld, 3, HOURGLASS_MODES)
    integer :: i, a, k, c
    ! gamma_aI = h_aI - hX_a . B_I
    do k = 1, HOURGLASS_MODES
      do a = 1, nn
        do i = 1, n
          gamma(i, a, k) = real(h(i, a, k), wp) - (grad(i, 1, a)*hx(i, 1, k) + &
                                                   grad(i, 2, a)*hx(i, 2, k) + &
                                                   grad(i, 3, a)*hx(i, 3, k))
        end do
      end do
    end do
    ! F^-1 = adj/J (cells with J <= 0: zero, so they get no forces); the loops run over the
    ! cells innermost (vectorised), selects and divisions in loops of their own
    do i = 1, n
      inverse_det(i) = merge(det(i), 1.0_wp, det(i) > 0.0_wp)
    end do
    do i = 1, n
      inverse_det(i) = 1.0_wp/inverse_det(i)
    end do
    do i = 1, n
      inverse_det(i) = merge(inverse_det(i), 0.0_wp, det(i) > 0.0_wp)
    end do
    do k = 1, 9
      do i = 1, n
        finv(i, k) = adj(i, k)*inverse_det(i)
      end do
    end do
    ! hourglass displacements q_a and velocities qdot_a, every mode in one pass over the nodes
    call mode_sums(u, q)
    d(1:n, :, :) = 0.0_wp
    if (viscous) call mode_sums(v, d)
    do i = 1, n
      energy(i) = 0.0_wp
      power(i) = 0.0_wp
    end do
    do k = 1, HOURGLASS_MODES
      do i = 1, n
        ! Q = F^-1 q, s = K Q, t = F^-T s
        big(i, 1, k) = finv(i, 1)*q(i, 1, k) + finv(i, 4)*q(i, 2, k) + finv(i, 7)*q(i, 3, k)
        big(i, 2, k) = finv(i, 2)*q(i, 1, k) + finv(i, 5)*q(i, 2, k) + finv(i, 8)*q(i, 3, k)
        big(i, 3, k) = finv(i, 3)*q(i, 1, k) + finv(i, 6)*q(i, 2, k) + finv(i, 9)*q(i, 3, k)
        s1(i) = stiffness(i, 1)*big(i, 1, k) + stiffness(i, 4)*big(i, 2, k) + &
                stiffness(i, 6)*big(i, 3, k)
        s2(i) = stiffness(i, 4)*big(i, 1, k) + stiffness(i, 2)*big(i, 2, k) + &
                stiffness(i, 5)*big(i, 3, k)
        s3(i) = stiffness(i, 6)*big(i, 1, k) + stiffness(i, 5)*big(i, 2, k) + &
                stiffness(i, 3)*big(i, 3, k)
        t(i, 1, k) = finv(i, 1)*s1(i) + finv(i, 2)*s2(i) + finv(i, 3)*s3(i)
        t(i, 2, k) = finv(i, 4)*s1(i) + finv(i, 5)*s2(i) + finv(i, 6)*s3(i)
        t(i, 3, k) = finv(i, 7)*s1(i) + finv(i, 8)*s2(i) + finv(i, 9)*s3(i)
        energy(i) = energy(i) + 0.5_wp*(big(i, 1, k)*s1(i) + big(i, 2, k)*s2(i) + &
                                        big(i, 3, k)*s3(i))
        power(i) = power(i) + viscosity(i)*(d(i, 1, k)**2 + d(i, 2, k)**2 + d(i, 3, k)**2)
      end do
      do c = 1, 3
        do i = 1, n
          d(i, c, k) = viscosity(i)*d(i, c, k)
        end do
      end do
    end do
    ! f_I = sum_a (gamma_aI - B_I . Q_a) t_a + gamma_aI c qdot_a, every mode in one pass
    do a = 1, nn
      do k = 1, HOURGLASS_MODES
        do i = 1, n
          r(i) = gamma(i, a, k) - (grad(i, 1, a)*big(i, 1, k) + grad(i, 2, a)*big(i, 2, k) + &
                                   grad(i, 3, a)*big(i, 3, k))
        end do
        do c = 1, 3
          do i = 1, n
            force(i, c, a) = force(i, c, a) + r(i)*t(i, c, k) + gamma(i, a, k)*d(i, c, k)
          end do
        end do
      end do
    end do

  contains

    !> sums(:, :, k) = sum_I gamma_kI field_I of every cell and mode k.
    pure subroutine mode_sums(field, sums)
      real(wp), intent(in) :: field(ld, 3, nn)                !< a nodal field
      real(wp), intent(out) :: sums(ld, 3, HOURGLASS_MODES)   !< its hourglass components
      integer :: p, node, mode, comp
      sums(1:n, :, :) = 0.0_wp
      do node = 1, nn
        do mode = 1, HOURGLASS_MODES
          do comp = 1, 3
            do p = 1, n
              sums(p, comp, mode) = sums(p, comp, mode) + gamma(p, node, mode)*field(p, comp, node)
            end do
          end do
        end do
      end do
    end subroutine mode_sums

  end subroutine block_hourglass_forces

  !> The stable-step frequency of n hexahedral cells by LS-DYNA's rule for solids: the
  !> characteristic length L = V / (largest face area) in the current configuration and the
  !> elastic wave speed c = sqrt((lambda + 2 mu)/rho) at the current density rho = rho0/J give
  !> omega^2 = (2 c / L)^2, so that the step 2/omega is L/c (doc/theory.md 2.8). V = J V0 with
  !> J = det F of the cell; face areas from the corners' current positions (a quadrilateral's
  !> area vector is half the cross product of its diagonals; a collapsed face has zero area).
  !> Cells with J <= 0 get huge. The loops run over the cells innermost (vectorised).
  pure subroutine block_hexahedron_frequency(n, x, weight, det, modulus, density, &
                                             omega_squared)
    integer, intent(in) :: n                      !< cells (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: x(ld, 3, 8)           !< current positions of the 8 corners
    real(wp), intent(in) :: weight(ld)            !< reference volumes V0
    real(wp), intent(in) :: det(ld)               !< J = det F
    real(wp), intent(in) :: modulus               !< lambda + 2 mu (elastic)
    real(wp), intent(in) :: density               !< rho0
    real(wp), intent(out) :: omega_squared(ld)    !< (2 c / L)^2
    real(wp), dimension(ld) :: largest, volume
    real(wp) :: d1(3), d2(3), a(3)
    integer :: i, f
    do i = 1, n
      largest(i) = 0.0_wp
    end do
    do f = 1, 6
      do i = 1, n
        d1 = x(i, :, HEX_FACES(3, f)) - x(i, :, HEX_FACES(1, f))
        d2 = x(i, :, HEX_FACES(4, f)) - x(i, :, HEX_FACES(2, f))
        a(1) = d1(2)*d2(3) - d1(3)*d2(2)
        a(2) = d1(3)*d2(1) - d1(1)*d2(3)
        a(3) = d1(1)*d2(2) - d1(2)*d2(1)
        largest(i) = max(largest(i), a(1)*a(1) + a(2)*a(2) + a(3)*a(3))     ! (2 A)^2
      end do
    end do
    ! (2 c / L)^2 = 4 (lambda + 2 mu) J / rho0 * (A / V)^2, A^2 = largest/4
    do i = 1, n
      volume(i) = merge(det(i)*weight(i), 1.0_wp, det(i) > 0.0_wp)
    end do
    do i = 1, n
      omega_squared(i) = modulus*det(i)/density*largest(i)/(volume(i)*volume(i))
    end do
    do i = 1, n
      omega_squared(i) = merge(omega_squared(i), huge(1.0_wp), det(i) > 0.0_wp)
    end do
  end subroutine block_hexahedron_frequency

  !> One cell's stiffness-form hourglass forces (as block_hourglass_forces, K given) and
  !> their exact tangent, for the implicit analyses: with t_a = F^-T K Q_a, r_aI = gamma_aI -
  !> B_I . Q_a, b_I = F^-T B_I and A = F^-T K F^-1,
  !>   f_I = sum_a r_aI t_a,
  !>   df_I/dx_J = sum_a [ r_aI r_aJ A - r_aI b_J (x) t_a - r_aJ t_a (x) b_I ]
  !> (symmetric: the Hessian of W). A cell with J <= 0 gets zeros.
  pure subroutine hourglass_stiffness_cell(nn, grad, gamma, stiffness, u, f, force, ke, energy)
    integer, intent(in) :: nn                                 !< nodes of the cell
    real(wp), intent(in) :: grad(:, :)                        !< (3, >= nn) B_I
    real(wp), intent(in) :: gamma(:, :)                       !< (>= nn, HOURGLASS_MODES)
    real(wp), intent(in) :: stiffness(6)                      !< K (XX YY ZZ XY YZ ZX)
    real(wp), intent(in) :: u(:, :)                           !< (3, >= nn) displacements
    real(wp), intent(in) :: f(3, 3)                           !< F of the cell
    real(wp), intent(out) :: force(3, nn)                     !< f_I
    real(wp), intent(out) :: ke(3*nn, 3*nn)                   !< df/dx
    real(wp), intent(out) :: energy                           !< W
    real(wp) :: adj(3, 3), det, finv(3, 3), k(3, 3), a(3, 3), q(3), big_q(3), t(3)
    real(wp) :: r(nn), b(3, nn), block(3, 3)
    integer :: m, i, j, c, d
    force = 0.0_wp
    ke = 0.0_wp
    energy = 0.0_wp
    call adjugate_3x3(f, adj, det)
    if (.not. det > 0.0_wp) return
    finv = adj/det
    k = reshape([stiffness(1), stiffness(4), stiffness(6), stiffness(4), stiffness(2), &
                 stiffness(5), stiffness(6), stiffness(5), stiffness(3)], [3, 3])
    a = matmul(transpose(finv), matmul(k, finv))
    do i = 1, nn
      b(:, i) = matmul(transpose(finv), grad(:, i))
    end do
    do m = 1, HOURGLASS_MODES
      q = matmul(u(:, 1:nn), gamma(1:nn, m))
      big_q = matmul(finv, q)
      t = matmul(transpose(finv), matmul(k, big_q))
      energy = energy + 0.5_wp*dot_product(big_q, matmul(k, big_q))
      do i = 1, nn
        r(i) = gamma(i, m) - dot_product(grad(:, i), big_q)
        force(:, i) = force(:, i) + r(i)*t
      end do
      do j = 1, nn
        do i = 1, nn
          do d = 1, 3
            do c = 1, 3
              block(c, d) = r(i)*r(j)*a(c, d) - r(i)*b(c, j)*t(d) - r(j)*t(c)*b(d, i)
            end do
          end do
          ke(3*i-2:3*i, 3*j-2:3*j) = ke(3*i-2:3*i, 3*j-2:3*j) + block
        end do
      end do
    end do
  end subroutine hourglass_stiffness_cell

end module mefem_hexahedron
