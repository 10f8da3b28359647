!> Stable time step of the explicit central-difference solver, per integration cell
!> (formulation 2.9, doc/theory.md "Explicit stable time step").
!>
!> Element-eigenvalue bound applied to cells: every element's lumped nodal masses (mefem_
!> lumped_mass) are split equally among its dim+1 sides, so the cell of a side (shared by one
!> or two elements, holding all their nodes) gets m_I^e/(dim+1) at each node I of each of its
!> elements e; a standard element is its own cell and keeps its full nodal masses. Then
!> M = sum_c M_c and K = sum_c K_c, K_c = A_c B_c^T C B_c, and
!>   omega_max^2 <= max_c omega_c^2,   omega_c^2 = lambda_max(K_c, M_c).
!> For one cell with gradients g_I and mass shares m_I, W = sum_I g_I g_I^T / m_I (dim x dim):
!>   omega_c^2 <= A (max(lambda, 0) tr W + 2 mu lambda_max(W))
!>            <= A (dim max(lambda, 0) + 2 mu) lambda_max(W)
!> (K_c depends on u only through H = sum_I u_I (x) g_I, and min sum m_I |u_I|^2 over the u
!> giving H is tr(H W^-1 H^T); with H = Z W^1/2 that is |Z|^2, while (tr H)^2 = <Z, W^1/2>^2
!> <= |Z|^2 tr W and |sym H|^2 <= |Z W^1/2|^2 <= lambda_max(W) |Z|^2). Both are equalities for
!> an isotropic W (regular simplex); the first, used here, is much closer for the anisotropic
!> W of ME-FEM cells (doc/theory.md). In the current configuration g_I -> F^-T g_I, A -> J A,
!> the masses are unchanged: W = F^-T W0 F^-1, and dt_c = 2/omega_c.
!> Every rank computes the shares from the global model in cell order (same bits everywhere).
module mefem_stable_time_step
  use mefem_kinds, only: wp
  use mefem_model, only: model_t
  use mefem_cells, only: cells_t, CELL_MAX_NODES, cell_grad_column
  use mefem_lumped_mass, only: simplex_measure
  use mefem_material_state, only: BLOCK_POINTS
  use mefem_cell_finite_strain, only: adjugate_3x3
  implicit none
  private

  public :: cell_mass_shares, cell_inverse_mass_metric, cell_critical_omega_squared, &
            symmetric_max_eigenvalue, block_critical_omega_squared, cell_split_weights, &
            inverse_mass_metric, cell_rebalance_weights, metric_packed, metric_unpacked, &
            cell_reference_bound, block_quick_omega_squared

  !> Entries of a packed symmetric 3x3 metric (metric_packed): 11 22 33 12 23 13.
  integer, parameter, public :: METRIC_ENTRIES = 6

  !> Chebyshev coefficients of y(x) = cos(acos(r)/3) = cos(2/3 acos(t)), t = sqrt((1 + r)/2),
  !> x = 2 t - 1 in [-1, 1] (y is analytic there: no square-root singularity at r = -1 or 1),
  !> degree 20: interpolation at 200 Chebyshev nodes in extended precision (numpy long
  !> double). Clenshaw's sum in double precision is within 2 ulp of cos(acos(r)/3) of libm
  !> over r in [-1, 1] (measured at 200 001 points); the coefficients fall by about 6.4 per
  !> degree, the last is 3e-18.
  integer, parameter :: COS_THIRD_DEGREE = 20
  real(wp), parameter :: COS_THIRD_ACOS(0:COS_THIRD_DEGREE) = [ &
    7.58091165435129111e-1_wp, &
    2.49336021027088517e-1_wp, &
    -8.02117454879531719e-3_wp, &
    6.55646818891165019e-4_wp, &
    -6.89243563279822499e-5_wp, &
    8.18887717312905114e-6_wp, &
    -1.04660554608263512e-6_wp, &
    1.40433228461435231e-7_wp, &
    -1.95103261907848130e-8_wp, &
    2.78232037527904160e-9_wp, &
    -4.04939122136249000e-10_wp, &
    5.99038651885944231e-11_wp, &
    -8.98095774831686481e-12_wp, &
    1.36154514312342160e-12_wp, &
    -2.08373611334383711e-13_wp, &
    3.21494198450567034e-14_wp, &
    -4.99523816407942992e-15_wp, &
    7.80933477606549092e-16_wp, &
    -1.22733854329704071e-16_wp, &
    1.94007136744556161e-17_wp, &
    -3.02058725254461529e-18_wp]

contains

  !> Nodal mass shares of the cells in `list`: share(j, k) is the mass of node
  !> cells%nodes(j, list(k)) that cell list(k) carries. ME-FEM: each element's corner mass
  !> rho V/(dim+1) and the inertia of its bubble dof rho V bubble_mass_ratio, divided by dim+1
  !> (one share per side); standard: rho V/(dim+1) per corner. Summed over all cells they give
  !> lumped_mass with inertia (same formulas; up to round-off). Each cell's shares depend on that cell alone, so a
  !> rank asks for its own cells only (the same bits as from the list of all cells).
  subroutine cell_mass_shares(model, cells, list, share)
    type(model_t), intent(in) :: model                 !< resolved model (densities, geometry)
    type(cells_t), intent(in) :: cells                 !< cells built from the same model
    integer, intent(in) :: list(:)                     !< cells wanted
    real(wp), allocatable, intent(out) :: share(:,:)   !< (CELL_MAX_NODES, size(list)) shares
    integer :: nv, k, c, slot, e, local, material
    real(wp) :: rho, volume, bubble, corner_share, enriched_share

    nv = cells%dim + 1
    bubble = cells%enrichment%bubble_mass_ratio
    allocate(share(CELL_MAX_NODES, size(list)))
    share = 0.0_wp
    do k = 1, size(list)
      c = list(k)
      if (cells%enriched_of(cells%elements(1, c)) == 0) then
        ! standard element = its own cell: the element's nodal masses
        rho = model%materials(cells%material(c))%density
        if (cells%hex_of(c) > 0) then
          share(1:cells%nnodes(c), k) = rho*cells%node_volume(1:cells%nnodes(c), cells%hex_of(c))
        else
          share(1:nv, k) = rho*cells%weight(c)/real(nv, wp)
        end if
        cycle
      end if
      do slot = 1, 2
        e = cells%elements(slot, c)
        if (e == 0) cycle
        material = model%parts(model%elements%part(e))%material
        rho = model%materials(material)%density
        volume = simplex_measure(cells%dim, model%nodes%x(:, model%elements%conn(1:nv, e)))
        corner_share = rho*volume/real(nv, wp)
        enriched_share = rho*volume*bubble
        do local = 1, nv
          call add_share(cells, c, model%elements%conn(local, e), corner_share/real(nv, wp), &
                         share(:, k))
        end do
        call add_share(cells, c, cells%enriched_of(e), enriched_share/real(nv, wp), share(:, k))
      end do
    end do
  end subroutine cell_mass_shares

  !> Add a mass share to the slot of node in cell c (every node of the cell's elements is
  !> one of its nodes, by construction in mefem_cells).
  pure subroutine add_share(cells, c, node, m, share)
    type(cells_t), intent(in) :: cells        !< cells
    integer, intent(in) :: c                  !< cell
    integer, intent(in) :: node               !< node number
    real(wp), intent(in) :: m                 !< mass to add
    real(wp), intent(inout) :: share(:)       !< (CELL_MAX_NODES) cell c's shares
    integer :: j
    do j = 1, cells%nnodes(c)
      if (cells%nodes(j, c) == node) then
        share(j) = share(j) + m
        return
      end if
    end do
  end subroutine add_share

  !> Inverse-mass metric of the cells in `list` in the reference configuration:
  !> w0(:,:,k) = sum_I g_I g_I^T / m_I over the nodes of cell list(k), m_I its shares
  !> share(:, k) (cell_mass_shares of the same list; nodes with zero share skipped: such a
  !> node must have a zero gradient for the bound to hold).
  subroutine cell_inverse_mass_metric(cells, list, share, w0)
    type(cells_t), intent(in) :: cells                 !< cells
    integer, intent(in) :: list(:)                     !< cells wanted
    real(wp), intent(in) :: share(:,:)                 !< (CELL_MAX_NODES, size(list)) shares
    real(wp), allocatable, intent(out) :: w0(:,:,:)    !< (dim, dim, size(list)) metric
    integer :: dim, k, c
    dim = cells%dim
    allocate(w0(dim, dim, size(list)))
    do k = 1, size(list)
      c = list(k)
      call inverse_mass_metric(dim, cells%nnodes(c), cells%grad(:, :, cell_grad_column(cells, &
                               c)), share(:, k), w0(:, :, k))
    end do
  end subroutine cell_inverse_mass_metric

  !> Inverse-mass metric of one cell: w0 = sum_a g_a g_a^T / m_a over its nn nodes (a node
  !> with zero share skipped: its gradient must be zero for the bound to hold).
  pure subroutine inverse_mass_metric(dim, nn, grad, share, w0)
    integer, intent(in) :: dim                   !< 2 or 3
    integer, intent(in) :: nn                    !< nodes of the cell
    real(wp), intent(in) :: grad(:,:)            !< (>= dim, >= nn) reference gradients
    real(wp), intent(in) :: share(:)             !< (>= nn) mass shares
    real(wp), intent(out) :: w0(:,:)             !< (dim, dim) metric
    integer :: j, a, b
    w0(1:dim, 1:dim) = 0.0_wp
    do j = 1, nn
      if (.not. (share(j) > 0.0_wp)) cycle
      do b = 1, dim
        do a = 1, dim
          w0(a, b) = w0(a, b) + grad(a, j)*grad(b, j)/share(j)
        end do
      end do
    end do
  end subroutine inverse_mass_metric

  !> A symmetric 3x3 metric packed as METRIC_ENTRIES entries, 11 22 33 12 23 13 (the explicit
  !> blocks store W0 so: the step bound streams 48 bytes per cell instead of 72). W0 from
  !> inverse_mass_metric is symmetric to the bit (the products g_a g_b commute and are summed
  !> in one order), so packing loses nothing.
  pure function metric_packed(w0) result(packed)
    real(wp), intent(in) :: w0(3, 3)              !< the metric
    real(wp) :: packed(METRIC_ENTRIES)
    packed = [w0(1, 1), w0(2, 2), w0(3, 3), w0(1, 2), w0(2, 3), w0(1, 3)]
  end function metric_packed

  !> The symmetric 3x3 metric of a packed one (metric_packed).
  pure function metric_unpacked(packed) result(w0)
    real(wp), intent(in) :: packed(METRIC_ENTRIES) !< 11 22 33 12 23 13
    real(wp) :: w0(3, 3)
    w0 = reshape([packed(1), packed(4), packed(6), packed(4), packed(2), packed(5), &
                  packed(6), packed(5), packed(3)], [3, 3])
  end function metric_unpacked

  !> Weights of the stiffness-weighted mass split (doc/theory.md 7) of one cell at the
  !> deformation gradient f: node a takes k_a = sqrt(J A |F^-T g_a|^2), the square root of
  !> its diagonal stiffness in the cell per unit modulus. A node's mass m is then shared among
  !> its cells in proportion to these weights, m k_a / sum over its cells of k. Any split
  !> that sums to m keeps the element-eigenvalue bound valid; this one gives the stiff cells
  !> more of the mass and so bounds the true step more closely. Evaluated as
  !> sqrt(A/J) |adj(F)^T g_a| (adj(F) = J F^-1); plane strain with the in-plane adjugate and
  !> J = J2 F_33. J <= 0: the reference weights sqrt(A) |g_a| (the cell fails anyway).
  pure subroutine cell_split_weights(dim, nn, weight, grad, f, k)
    integer, intent(in) :: dim                   !< 2 (plane strain) or 3
    integer, intent(in) :: nn                    !< nodes of the cell
    real(wp), intent(in) :: weight               !< reference area (unit thickness) or volume
    real(wp), intent(in) :: grad(:,:)            !< (>= dim, >= nn) reference gradients
    real(wp), intent(in) :: f(3, 3)              !< deformation gradient (F33 = 1 in 2D)
    real(wp), intent(out) :: k(:)                !< (>= nn) the weights
    real(wp) :: adj(3, 3), det, scale, q(3)
    integer :: a
    adj = 0.0_wp
    if (dim == 3) then
      call adjugate_3x3(f, adj, det)
      scale = weight/det
    else
      adj(1, 1) = f(2, 2)
      adj(1, 2) = -f(1, 2)
      adj(2, 1) = -f(2, 1)
      adj(2, 2) = f(1, 1)
      det = f(1, 1)*f(2, 2) - f(1, 2)*f(2, 1)
      scale = weight*f(3, 3)/det
    end if
    if (.not. (det > 0.0_wp)) then
      do a = 1, nn
        k(a) = sqrt(weight)*norm2(grad(1:dim, a))
      end do
      return
    end if
    scale = sqrt(scale)
    do a = 1, nn
      q(1:dim) = matmul(grad(1:dim, a), adj(1:dim, 1:dim))       ! (adj^T g)^T = g^T adj
      k(a) = scale*norm2(q(1:dim))
    end do
  end subroutine cell_split_weights

  !> Weights of one rebalancing pass of the mass split (doc/theory.md 7) for one cell at the
  !> deformation gradient f: its present shares times its bound omega_c^2 with them, so that
  !> the nodes' mass moves towards the cells that set the step (the shares alone where the
  !> bound is not finite, det F <= 0: the material update stops the run there).
  pure subroutine cell_rebalance_weights(dim, nn, weight, grad, share, f, lambda, mu, k)
    integer, intent(in) :: dim                   !< 2 (plane strain) or 3
    integer, intent(in) :: nn                    !< nodes of the cell
    real(wp), intent(in) :: weight               !< reference area (unit thickness) or volume
    real(wp), intent(in) :: grad(:,:)            !< (>= dim, >= nn) reference gradients
    real(wp), intent(in) :: share(:)             !< (>= nn) the present mass shares
    real(wp), intent(in) :: f(3, 3)              !< deformation gradient (F33 = 1 in 2D)
    real(wp), intent(in) :: lambda, mu           !< Lame constants of the cell's material
    real(wp), intent(out) :: k(:)                !< (>= nn) the new weights
    real(wp) :: w0(3, 3), omega2
    call inverse_mass_metric(dim, nn, grad, share, w0)
    omega2 = cell_critical_omega_squared(dim, weight, w0(1:dim, 1:dim), f, lambda, mu)
    if (omega2 < huge(1.0_wp)) then
      k(1:nn) = share(1:nn)*omega2
    else
      k(1:nn) = share(1:nn)
    end if
  end subroutine cell_rebalance_weights

  !> Upper bound of omega^2 of one cell at the deformation gradient f:
  !>   J weight (max(lambda, 0) tr W + 2 mu lambda_max(W)),  W = F^-T W0 F^-1,  J = det F,
  !> with the small-strain Lame constants of the cell's material (material_elastic_moduli;
  !> plane strain: the same lambda, mu with dim = 2). Returns huge() for det F <= 0 (the
  !> material update reports the failure). Allocation-free; the cell's stable step is
  !> 2/sqrt(result). Evaluated as weight/J (max(lambda, 0) tr W' + 2 mu lambda_max(W')) with
  !> W' = adj(F)^T W0 adj(F) = J^2 W (adj(F) = J F^-1): no matrix inverse, one division
  !> (plane strain likewise with the in-plane 2x2 adjugate).
  pure real(wp) function cell_critical_omega_squared(dim, weight, w0, f, lambda, mu) &
      result(omega_squared)
    integer, intent(in) :: dim           !< 2 (plane strain) or 3
    real(wp), intent(in) :: weight       !< reference area (unit thickness) or volume
    real(wp), intent(in), contiguous :: w0(:,:)  !< (dim, dim) reference inverse-mass metric
    real(wp), intent(in) :: f(3, 3)      !< deformation gradient (F33 = 1 in plane strain)
    real(wp), intent(in) :: lambda       !< Lame's first constant (lambda < 0 counts as 0)
    real(wp), intent(in) :: mu           !< shear modulus
    real(wp) :: adj(3, 3), det, y(3, 3), w(3, 3), trace_w, lambda_max
    integer :: a, b
    call adjugate_3x3(f, adj, det)         ! adj(F) (transposed cofactors) and J
    if (.not. (det > 0.0_wp)) then
      omega_squared = huge(1.0_wp)
      return
    end if
    if (dim == 3) then
      ! y = W0 adj, w = adj^T y (upper triangle; W0 symmetric)
      do b = 1, 3
        do a = 1, 3
          y(a, b) = w0(a, 1)*adj(1, b) + w0(a, 2)*adj(2, b) + w0(a, 3)*adj(3, b)
        end do
      end do
      do b = 1, 3
        do a = 1, b
          w(a, b) = adj(1, a)*y(1, b) + adj(2, a)*y(2, b) + adj(3, a)*y(3, b)
        end do
      end do
      trace_w = w(1, 1) + w(2, 2) + w(3, 3)
      lambda_max = max_eigenvalue_3(w(1, 1), w(2, 2), w(3, 3), w(1, 2), w(2, 3), w(1, 3))
      omega_squared = weight/det*(max(lambda, 0.0_wp)*trace_w + 2.0_wp*mu*lambda_max)
    else
      ! plane strain: the in-plane block, F^-1 = adj2/J2 with the 2x2 adjugate adj2 and
      ! J2 = J/F_33, so J W = (F_33/J2) adj2^T W0 adj2
      adj(1, 1) = f(2, 2)
      adj(1, 2) = -f(1, 2)
      adj(2, 1) = -f(2, 1)
      adj(2, 2) = f(1, 1)
      do b = 1, 2
        do a = 1, 2
          y(a, b) = w0(a, 1)*adj(1, b) + w0(a, 2)*adj(2, b)
        end do
      end do
      do b = 1, 2
        do a = 1, b
          w(a, b) = adj(1, a)*y(1, b) + adj(2, a)*y(2, b)
        end do
      end do
      w(2, 1) = w(1, 2)
      trace_w = w(1, 1) + w(2, 2)
      lambda_max = symmetric_max_eigenvalue(2, w)
      omega_squared = weight*f(3, 3)/(f(1, 1)*f(2, 2) - f(1, 2)*f(2, 1))* &
                      (max(lambda, 0.0_wp)*trace_w + 2.0_wp*mu*lambda_max)
    end if
  end function cell_critical_omega_squared

  !> Block form (3D) of cell_critical_omega_squared for n cells of one material, structure of
  !> arrays (entry i is cell i), with adj(F) and J = det F from mefem_cell_finite_strain's
  !> block_adjugate (the same expressions): the same arithmetic per cell except the
  !> trigonometric step cos(acos(r)/3) of the eigenvalue, here a Chebyshev series (within 2
  !> ulp of libm's; the bound differs from cell_critical_omega_squared's in the last bits).
  !> Every stage vectorises across cells.
  pure subroutine block_critical_omega_squared(n, weight, w0, adj, det, lambda, mu, &
                                               omega_squared)
    integer, intent(in) :: n                      !< cells (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: weight(ld)            !< reference volumes
    real(wp), intent(in) :: w0(ld, METRIC_ENTRIES) !< reference inverse-mass metrics, packed
                                                  !< (metric_packed)
    real(wp), intent(in) :: adj(ld, 9)            !< adj(F), column by column
    real(wp), intent(in) :: det(ld)               !< J = det F
    real(wp), intent(in) :: lambda                !< Lame's first constant (< 0 counts as 0)
    real(wp), intent(in) :: mu                    !< shear modulus
    real(wp), intent(out) :: omega_squared(ld)    !< bounds of omega^2 (huge for J <= 0)
    real(wp), parameter :: ONE_THIRD = 1.0_wp/3.0_wp, ONE_SIXTH = 1.0_wp/6.0_wp
    real(wp) :: y(9), w11, w22, w33, w12, w23, w13, p1, d11, d22, d33, lambda_plus
    real(wp) :: x, b0, b1, b2
    real(wp), dimension(ld) :: trace_w, q, p2, root, r, lambda_max
    integer :: i, b, k
    do i = 1, n
      ! y = W0 adj (y(a, b) at a + 3(b-1)), w = adj^T y (upper triangle)
      do b = 0, 2
        y(1 + 3*b) = w0(i, 1)*adj(i, 1 + 3*b) + w0(i, 4)*adj(i, 2 + 3*b) + w0(i, 6)*adj(i, 3 + 3*b)
        y(2 + 3*b) = w0(i, 4)*adj(i, 1 + 3*b) + w0(i, 2)*adj(i, 2 + 3*b) + w0(i, 5)*adj(i, 3 + 3*b)
        y(3 + 3*b) = w0(i, 6)*adj(i, 1 + 3*b) + w0(i, 5)*adj(i, 2 + 3*b) + w0(i, 3)*adj(i, 3 + 3*b)
      end do
      w11 = adj(i, 1)*y(1) + adj(i, 2)*y(2) + adj(i, 3)*y(3)
      w12 = adj(i, 1)*y(4) + adj(i, 2)*y(5) + adj(i, 3)*y(6)
      w22 = adj(i, 4)*y(4) + adj(i, 5)*y(5) + adj(i, 6)*y(6)
      w13 = adj(i, 1)*y(7) + adj(i, 2)*y(8) + adj(i, 3)*y(9)
      w23 = adj(i, 4)*y(7) + adj(i, 5)*y(8) + adj(i, 6)*y(9)
      w33 = adj(i, 7)*y(7) + adj(i, 8)*y(8) + adj(i, 9)*y(9)
      trace_w(i) = w11 + w22 + w33
      ! largest eigenvalue (max_eigenvalue_3), in stages: selects, square roots and divisions
      ! in loops of their own (gfortran vectorises neither a division of a selected value nor
      ! a select of a quotient)
      q(i) = (w11 + w22 + w33)*ONE_THIRD
      p1 = w12**2 + w13**2 + w23**2
      d11 = w11 - q(i)
      d22 = w22 - q(i)
      d33 = w33 - q(i)
      p2(i) = d11**2 + d22**2 + d33**2 + 2.0_wp*p1
      r(i) = 0.5_wp*(d11*(d22*d33 - w23*w23) - w12*(w12*d33 - w23*w13) + w13*(w12*w23 - &
             d22*w13))
    end do
    do i = 1, n               ! p2 = 0 (a multiple of the identity): 6 only avoids 0/0 below
      root(i) = merge(p2(i), 6.0_wp, p2(i) > 0.0_wp)
    end do
    do i = 1, n
      root(i) = sqrt(root(i)*ONE_SIXTH)
      r(i) = r(i)/(root(i)*root(i)*root(i))
    end do
    do i = 1, n                                   ! min(1, max(-1, r)), a NaN -> -1 as with max
      r(i) = merge(r(i), -1.0_wp, r(i) >= -1.0_wp)
      r(i) = merge(1.0_wp, r(i), r(i) > 1.0_wp)
      root(i) = merge(root(i), 0.0_wp, p2(i) > 0.0_wp)      ! then q + 2 p cos(phi) = q
    end do
    ! cos(acos(r)/3) by its Chebyshev series (COS_THIRD_ACOS): only +, * and sqrt, so the loop
    ! vectorises and a cell's bits do not depend on its place in the block (libmvec's acos and
    ! cos, which gfortran would use for pairs of cells, differ from libm's in the last bits)
    do i = 1, n
      x = 2.0_wp*sqrt(0.5_wp*(1.0_wp + r(i))) - 1.0_wp
      b1 = 0.0_wp
      b2 = 0.0_wp
      ! (20 = COS_THIRD_DEGREE: the directive takes a literal; fully unrolled, the loop over
      ! the cells vectorises)
      !GCC$ unroll 20
      do k = COS_THIRD_DEGREE, 1, -1
        b0 = 2.0_wp*x*b1 - b2 + COS_THIRD_ACOS(k)
        b2 = b1
        b1 = b0
      end do
      lambda_max(i) = x*b1 - b2 + COS_THIRD_ACOS(0)
    end do
    lambda_plus = max(lambda, 0.0_wp)
    do i = 1, n
      lambda_max(i) = q(i) + 2.0_wp*root(i)*lambda_max(i)
      p2(i) = merge(det(i), 1.0_wp, det(i) > 0.0_wp)       ! (p2 reused: J or 1)
    end do
    do i = 1, n
      omega_squared(i) = weight(i)/p2(i)*(lambda_plus*trace_w(i) + 2.0_wp*mu*lambda_max(i))
    end do
    do i = 1, n
      omega_squared(i) = merge(omega_squared(i), huge(1.0_wp), det(i) > 0.0_wp)
    end do
  end subroutine block_critical_omega_squared

  !> The cell bound's factor at F = I per unit weight, omega_0 = max(lambda, 0) tr W0 +
  !> 2 mu lambda_max(W0) (3D), which block_quick_omega_squared scales by the deformation.
  pure real(wp) function cell_reference_bound(w0, lambda, mu) result(omega0)
    real(wp), intent(in) :: w0(3, 3)              !< reference inverse-mass metric
    real(wp), intent(in) :: lambda, mu            !< Lame constants (lambda < 0 counts as 0)
    omega0 = max(lambda, 0.0_wp)*(w0(1, 1) + w0(2, 2) + w0(3, 3)) + &
             2.0_wp*mu*symmetric_max_eigenvalue(3, w0)
  end function cell_reference_bound

  !> A quick upper bound of block_critical_omega_squared's bound for n cells (doc/theory.md 7):
  !> with A = adj(F) and W = A^T W0 A, tr W <= tr W0 lambda_max(A^T A) and lambda_max(W) <=
  !> lambda_max(W0) lambda_max(A^T A), so omega^2 <= (w/J) s omega_0 for any s >=
  !> lambda_max(A^T A); s = q + 2 sqrt(p2/6), the largest-eigenvalue formula with its cosine
  !> at 1 (q the mean eigenvalue, p2 the squared norm of the deviator), exact at F = I and
  !> for two equal eigenvalues below the largest. 24 multiply-adds and a square root per
  !> cell, against W's 45 and the eigenvalue's series; no W0. huge for J <= 0.
  pure subroutine block_quick_omega_squared(n, weight, omega0, adj, det, omega_squared)
    integer, intent(in) :: n                      !< cells (<= BLOCK_POINTS)
    integer, parameter :: ld = BLOCK_POINTS       !< leading dimension
    real(wp), intent(in) :: weight(ld)            !< reference volumes
    real(wp), intent(in) :: omega0(ld)            !< cell_reference_bound of each cell
    real(wp), intent(in) :: adj(ld, 9)            !< adj(F), column by column
    real(wp), intent(in) :: det(ld)               !< J = det F
    real(wp), intent(out) :: omega_squared(ld)    !< bounds of omega^2 (huge for J <= 0)
    real(wp), parameter :: ONE_THIRD = 1.0_wp/3.0_wp, ONE_SIXTH = 1.0_wp/6.0_wp
    real(wp) :: m11, m22, m33, m12, m23, m13, d11, d22, d33
    real(wp), dimension(ld) :: q, root
    integer :: i
    do i = 1, n                         ! M = A^T A: the columns' dot products
      m11 = adj(i, 1)**2 + adj(i, 2)**2 + adj(i, 3)**2
      m22 = adj(i, 4)**2 + adj(i, 5)**2 + adj(i, 6)**2
      m33 = adj(i, 7)**2 + adj(i, 8)**2 + adj(i, 9)**2
      m12 = adj(i, 1)*adj(i, 4) + adj(i, 2)*adj(i, 5) + adj(i, 3)*adj(i, 6)
      m23 = adj(i, 4)*adj(i, 7) + adj(i, 5)*adj(i, 8) + adj(i, 6)*adj(i, 9)
      m13 = adj(i, 1)*adj(i, 7) + adj(i, 2)*adj(i, 8) + adj(i, 3)*adj(i, 9)
      q(i) = (m11 + m22 + m33)*ONE_THIRD
      d11 = m11 - q(i)
      d22 = m22 - q(i)
      d33 = m33 - q(i)
      root(i) = (d11**2 + d22**2 + d33**2 + 2.0_wp*(m12**2 + m23**2 + m13**2))*ONE_SIXTH
    end do
    do i = 1, n
      root(i) = sqrt(root(i))
    end do
    do i = 1, n               ! (q reused: J or 1, selects and divisions in loops of their own)
      root(i) = q(i) + 2.0_wp*root(i)
      q(i) = merge(det(i), 1.0_wp, det(i) > 0.0_wp)
    end do
    do i = 1, n
      omega_squared(i) = weight(i)/q(i)*root(i)*omega0(i)
    end do
    do i = 1, n
      omega_squared(i) = merge(omega_squared(i), huge(1.0_wp), det(i) > 0.0_wp)
    end do
  end subroutine block_quick_omega_squared

  !> Largest eigenvalue of a symmetric n x n matrix, n = 1, 2, 3, in closed form (2x2: mean
  !> plus the radius; 3x3: the trigonometric solution of the characteristic cubic, Smith 1961).
  !> Only a(1:n, 1:n) is read (the upper triangle for n = 3). Round-off: ~1e-15 relative of
  !> the spectral radius, up to ~1e-8 when the two largest eigenvalues (nearly) coincide (the
  !> cubic's double root; measured in tests/unit/test_stable_time_step.f90).
  pure real(wp) function symmetric_max_eigenvalue(n, a) result(lambda_max)
    integer, intent(in) :: n             !< 1, 2 or 3
    real(wp), intent(in) :: a(:,:)       !< (>= n, >= n) symmetric matrix
    select case (n)
    case (1)
      lambda_max = a(1, 1)
    case (2)
      lambda_max = 0.5_wp*(a(1, 1) + a(2, 2)) + hypot(0.5_wp*(a(1, 1) - a(2, 2)), a(1, 2))
    case default
      lambda_max = max_eigenvalue_3(a(1, 1), a(2, 2), a(3, 3), a(1, 2), a(2, 3), a(1, 3))
    end select
  end function symmetric_max_eigenvalue

  !> Largest eigenvalue of the symmetric 3x3 matrix [a11 a12 a13; a12 a22 a23; a13 a23 a33]:
  !> with q = tr/3, p = sqrt(|A - q 1|^2/6) and r = det(A - q 1)/(2 p^3) (= det(B)/2 of
  !> Smith's B = (A - q 1)/p, without forming B), lambda_max = q + 2 p cos(acos(r)/3).
  pure real(wp) function max_eigenvalue_3(a11, a22, a33, a12, a23, a13) result(lambda_max)
    real(wp), intent(in) :: a11, a22, a33, a12, a23, a13   !< the six entries
    real(wp), parameter :: ONE_THIRD = 1.0_wp/3.0_wp, ONE_SIXTH = 1.0_wp/6.0_wp
    real(wp) :: q, p1, p2, p, d11, d22, d33, r, phi
    q = (a11 + a22 + a33)*ONE_THIRD
    p1 = a12**2 + a13**2 + a23**2
    d11 = a11 - q
    d22 = a22 - q
    d33 = a33 - q
    p2 = d11**2 + d22**2 + d33**2 + 2.0_wp*p1
    if (.not. (p2 > 0.0_wp)) then
      lambda_max = q                     ! a multiple of the identity
      return
    end if
    p = sqrt(p2*ONE_SIXTH)
    r = 0.5_wp*(d11*(d22*d33 - a23*a23) - a12*(a12*d33 - a23*a13) + a13*(a12*a23 - d22*a13)) &
        /(p*p*p)
    r = min(1.0_wp, max(-1.0_wp, r))
    phi = acos(r)*ONE_THIRD                ! in [0, pi/3]: cos(phi) gives the largest root
    lambda_max = q + 2.0_wp*p*cos(phi)
  end function max_eigenvalue_3

end module mefem_stable_time_step
