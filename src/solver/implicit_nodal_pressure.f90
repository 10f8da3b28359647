!> The nodal-pressure tetrahedron (solid ELFORM 13) in the nonlinear implicit analysis: the
!> explicit analysis' forces (doc/theory.md 2.7) with their consistent tangent (2.7.1).
!>
!> Element e of the patch set sees Fbar = (Jbar_e/J_e)^(1/3) F_e and carries
!>   f_e = V0_e (dev(tau_bar_e) + pbar_e J_e 1) F_e^-T g_a,
!> tau_bar the material's Kirchhoff stress at Fbar, with the means Jbar_e = sum_h c_eh J_h and
!> pbar_e = sum_h c_eh p_h (p_h = tr(tau_bar_h)/(3 Jbar_h), the Cauchy pressure) over the ELFORM 13
!> elements h that share a node with e: c_eh = 1/4 sum over the nodes I shared by e and h of
!> (V0_h/4)/V0_I, V0_I the sum of V0/4 of the node's ELFORM 13 elements; at a node where
!> ELFORM 13 elements of different materials meet, e takes its own J and p (c_ee gets 1/4).
!> Since V0_e c_eh = V0_h c_he, the tangent is, element by element,
!>   K_e = k(tau_eff, c_eff) + V0_e (t_e (x) b_e + b_e (x) q_e + r_e b_e (x) b_e),
!> k the element's own tangent (cell_tangent) with tau_eff = dev(tau_bar) + pbar J 1 and the
!> spatial tangent of F-bar at fixed Jbar and pbar,
!>   c_eff = P c_bar P + 2/3 tr(tau_bar) (I - 1 (x) 1/3) - 2/3 (1 (x) dev tau_bar + dev tau_bar (x) 1)
!>           + pbar J (1 (x) 1 - 2 I),
!> b_e = d Jbar_e / dx = sum_h c_eh J_h F_h^-T g_h on the nodes of e's patch, t_e = T F_e^-T g,
!> q_e = M F_e^-T g, T = dev(c_bar : 1 + 2 tau_bar)/(3 Jbar), M = dev(1 : c_bar + 2 tau_bar)/
!> (3 Jbar) and r_e = d p_e / d Jbar_e = (1 : c_bar : 1 - tr tau_bar)/(9 Jbar^2). T = M = 0 for
!> a material whose volumetric response is uncoupled (the J2 laws, Mooney-Rivlin); the
!> compressible neo-Hookean of *MAT_ELASTIC has them. Every rank evaluates every ELFORM 13
!> element's material in the patch order (the means are then the same bits on any number of
!> ranks); each rank assembles the forces and tangents of the cells it owns.
module mefem_implicit_nodal_pressure
  use mefem_kinds, only: wp
  use mefem_cells, only: cells_t
  use mefem_cell_finite_strain, only: cell_deformation_gradient, inverse_3x3
  use mefem_tensor_algebra, only: inverse_cube_root
  use mefem_index_lists, only: counts_to_starts, sort_small
  implicit none
  private

  public :: np_patches_build, np_pairs_build, np_prepare, np_pressures, np_fbar, &
            np_cell_terms, np_add_to_pairs

  !> The ELFORM 13 cells, the coefficients of their means and their patches' nodes.
  type, public :: np_patches_t
    integer :: n = 0                            !< ELFORM 13 cells
    integer :: max_patch = 0                    !< most nodes in a patch
    integer, allocatable :: index_of(:)         !< (cells) position among them, 0 if none
    integer, allocatable :: cell(:)             !< (n) their cells, ascending
    integer, allocatable :: term_start(:)       !< (n + 1) CSR: the terms of e's means
    integer, allocatable :: term(:)             !< their elements h (positions)
    real(wp), allocatable :: coef(:)            !< c_eh
    integer, allocatable :: patch_start(:)      !< (n + 1) CSR: the nodes of e's patch
    integer, allocatable :: patch_node(:)       !< the nodes, ascending
    ! the node pairs that the blocks of this rank's cells touch (np_pairs_build): the blocks
    ! are summed into them (np_add_to_pairs) and the matrix gets each pair once
    integer, allocatable :: pair_start(:)       !< (nodes + 1) CSR: the pairs of node i
    integer, allocatable :: pair_node(:)        !< their nodes j, ascending
  end type np_patches_t

  !> One evaluation's values of the ELFORM 13 cells (all of them, on every rank).
  type, public :: np_values_t
    real(wp), allocatable :: f(:,:,:)           !< (3, 3, n) F
    real(wp), allocatable :: det(:)             !< (n) J = det F
    real(wp), allocatable :: a(:,:,:)           !< (3, 4, n) F^-T g_a
    real(wp), allocatable :: jbar(:)            !< (n) Jbar
    real(wp), allocatable :: tau(:,:,:)         !< (3, 3, n) tau_bar (the caller's update)
    real(wp), allocatable :: c(:,:,:,:,:)       !< (3, 3, 3, 3, n) its spatial tangent
    real(wp), allocatable :: pressure(:)        !< (n) p = tr(tau_bar)/(3 Jbar)
    real(wp), allocatable :: pbar(:)            !< (n) pbar
  end type np_values_t

contains

  !> The ELFORM 13 cells of `cells` (nodal_pressure), the coefficients c_eh of their means and
  !> the nodes of their patches (the nodes of every ELFORM 13 element sharing a node with e).
  subroutine np_patches_build(cells, patches)
    type(cells_t), intent(in) :: cells                !< all cells
    type(np_patches_t), intent(out) :: patches        !< the patches
    integer, allocatable :: node_start(:), node_cell(:), fill(:), mark_h(:), mark_node(:)
    integer, allocatable :: h_list(:)
    real(wp), allocatable :: volume(:), m_min(:), m_max(:), coef_h(:)
    integer :: e, k, a, node, nnode, nh, count_nodes
    patches%n = count(cells%nodal_pressure(1:cells%n))
    allocate(patches%index_of(cells%n), patches%cell(patches%n))
    patches%index_of = 0
    patches%cell = pack([(k, k = 1, cells%n)], cells%nodal_pressure(1:cells%n))
    do e = 1, patches%n
      patches%index_of(patches%cell(e)) = e
    end do
    nnode = 0
    if (patches%n > 0) nnode = maxval(cells%nodes(1:4, patches%cell))
    ! the nodes' ELFORM 13 elements (CSR), reference volumes and materials
    allocate(node_start(nnode + 1), fill(nnode), volume(nnode), m_min(nnode), m_max(nnode))
    fill = 0
    volume = 0.0_wp
    m_min = huge(1.0_wp)
    m_max = -huge(1.0_wp)
    do e = 1, patches%n
      do a = 1, 4
        node = cells%nodes(a, patches%cell(e))
        fill(node) = fill(node) + 1
        volume(node) = volume(node) + 0.25_wp*cells%weight(patches%cell(e))
        m_min(node) = min(m_min(node), real(cells%material(patches%cell(e)), wp))
        m_max(node) = max(m_max(node), real(cells%material(patches%cell(e)), wp))
      end do
    end do
    call counts_to_starts(fill, node_start, 1)
    allocate(node_cell(max(node_start(nnode + 1) - 1, 0)))
    do e = 1, patches%n
      do a = 1, 4
        node = cells%nodes(a, patches%cell(e))
        node_cell(fill(node)) = e
        fill(node) = fill(node) + 1
      end do
    end do
    ! the terms c_eh (h ascending) and the patch nodes (ascending): counted, then stored
    allocate(mark_h(patches%n), mark_node(nnode), coef_h(patches%n), h_list(patches%n))
    mark_h = 0
    mark_node = 0
    coef_h = 0.0_wp
    nh = 0
    allocate(patches%term_start(patches%n + 1), patches%patch_start(patches%n + 1))
    patches%term_start(1) = 1
    patches%patch_start(1) = 1
    do e = 1, patches%n
      call element_terms(e)
      patches%term_start(e + 1) = patches%term_start(e) + nh
      patches%patch_start(e + 1) = patches%patch_start(e) + count_nodes
      patches%max_patch = max(patches%max_patch, count_nodes)
    end do
    allocate(patches%term(patches%term_start(patches%n + 1) - 1), &
             patches%coef(patches%term_start(patches%n + 1) - 1), &
             patches%patch_node(patches%patch_start(patches%n + 1) - 1))
    do e = 1, patches%n
      call element_terms(e)
      k = patches%term_start(e)
      patches%term(k:k + nh - 1) = h_list(1:nh)
      patches%coef(k:k + nh - 1) = coef_h(h_list(1:nh))
      k = patches%patch_start(e)
      patches%patch_node(k:k + count_nodes - 1) = fill(1:count_nodes)
    end do

  contains

    !> Element e's terms (h_list(1:nh) ascending, coef_h) and patch nodes (fill(1:count_nodes),
    !> ascending); the marks are left clear.
    subroutine element_terms(e)
      integer, intent(in) :: e                       !< position among the ELFORM 13 cells
      integer :: a, b, k, node
      coef_h(h_list(1:nh)) = 0.0_wp
      nh = 0
      do a = 1, 4
        node = cells%nodes(a, patches%cell(e))
        if (m_min(node) /= m_max(node)) then         ! mixed: the element's own J and p
          call add_term(e, 0.25_wp)
          cycle
        end if
        do k = node_start(node), node_start(node + 1) - 1
          call add_term(node_cell(k), &
                        0.0625_wp*cells%weight(patches%cell(node_cell(k)))/volume(node))
        end do
      end do
      call sort_small(h_list(1:nh))
      mark_h(h_list(1:nh)) = 0
      count_nodes = 0
      do k = 1, nh
        do b = 1, 4
          node = cells%nodes(b, patches%cell(h_list(k)))
          if (mark_node(node) /= 0) cycle
          mark_node(node) = 1
          count_nodes = count_nodes + 1
          fill(count_nodes) = node
        end do
      end do
      mark_node(fill(1:count_nodes)) = 0
      call sort_small(fill(1:count_nodes))
    end subroutine element_terms

    !> Add w to c_eh (h first met: listed).
    subroutine add_term(h_new, w)
      integer, intent(in) :: h_new                   !< the element h
      real(wp), intent(in) :: w                      !< its share
      if (mark_h(h_new) == 0) then
        mark_h(h_new) = 1
        nh = nh + 1
        h_list(nh) = h_new
        coef_h(h_new) = 0.0_wp
      end if
      coef_h(h_new) = coef_h(h_new) + w
    end subroutine add_term

  end subroutine np_patches_build

  !> The node pairs (i, j) of the patches of the cells this rank owns: j in row i when both are
  !> nodes of one such patch (rows ascending, each sorted).
  subroutine np_pairs_build(patches, owned)
    type(np_patches_t), intent(inout) :: patches      !< the patches (pairs set)
    logical, intent(in) :: owned(:)                   !< (cells) the cells this rank owns
    integer, allocatable :: row_start(:), row_patch(:), fill(:), mark(:), list(:)
    integer :: nnode, e, k, i, node, count_row, pass, total
    nnode = 0
    if (size(patches%patch_node) > 0) nnode = maxval(patches%patch_node)
    ! the owned patches holding each node (CSR)
    allocate(row_start(nnode + 1), fill(nnode), mark(nnode), list(nnode))
    fill = 0
    do e = 1, patches%n
      if (.not. owned(patches%cell(e))) cycle
      do k = patches%patch_start(e), patches%patch_start(e + 1) - 1
        fill(patches%patch_node(k)) = fill(patches%patch_node(k)) + 1
      end do
    end do
    call counts_to_starts(fill, row_start, 1)
    allocate(row_patch(row_start(nnode + 1) - 1))
    do e = 1, patches%n
      if (.not. owned(patches%cell(e))) cycle
      do k = patches%patch_start(e), patches%patch_start(e + 1) - 1
        row_patch(fill(patches%patch_node(k))) = e
        fill(patches%patch_node(k)) = fill(patches%patch_node(k)) + 1
      end do
    end do
    ! each row: the union of its patches' nodes; counted, then stored
    mark = 0
    allocate(patches%pair_start(nnode + 1))
    patches%pair_start(1) = 1
    total = 0
    do pass = 1, 2
      if (pass == 2) allocate(patches%pair_node(total))
      do i = 1, nnode
        count_row = 0
        do k = row_start(i), row_start(i + 1) - 1
          e = row_patch(k)
          do node = patches%patch_start(e), patches%patch_start(e + 1) - 1
            if (mark(patches%patch_node(node)) /= 0) cycle
            mark(patches%patch_node(node)) = 1
            count_row = count_row + 1
            list(count_row) = patches%patch_node(node)
          end do
        end do
        mark(list(1:count_row)) = 0
        if (pass == 1) then
          patches%pair_start(i + 1) = patches%pair_start(i) + count_row
          total = total + count_row
        else
          call sort_small(list(1:count_row))
          patches%pair_node(patches%pair_start(i):patches%pair_start(i + 1) - 1) = &
              list(1:count_row)
        end if
      end do
    end do
  end subroutine np_pairs_build

  !> Add cell position e's block (np_cell_terms) into the pair sums pair_values(:, :, k) of
  !> the pairs (patches%pair_node(k)): each row's pairs are merged with the sorted patch.
  pure subroutine np_add_to_pairs(patches, e, block, pair_values)
    type(np_patches_t), intent(in) :: patches         !< the patches, pairs built
    integer, intent(in) :: e                          !< position among the ELFORM 13 cells
    real(wp), intent(in) :: block(:,:)                !< its block on its patch's nodes
    real(wp), intent(inout) :: pair_values(:,:,:)     !< (3, 3, pairs) the sums
    integer :: first, np, a, b, k, node
    first = patches%patch_start(e)
    np = patches%patch_start(e + 1) - first
    do a = 1, np
      node = patches%patch_node(first + a - 1)
      k = patches%pair_start(node)
      do b = 1, np
        do while (patches%pair_node(k) < patches%patch_node(first + b - 1))
          k = k + 1
        end do
        pair_values(:, :, k) = pair_values(:, :, k) + block(3*a-2:3*a, 3*b-2:3*b)
      end do
    end do
  end subroutine np_add_to_pairs

  !> F, J and F^-T g_a of every ELFORM 13 cell at displacements u, and their Jbar; ok is
  !> .false. (and bad the first such cell) where a J is not positive.
  subroutine np_prepare(cells, patches, u, values, ok, bad)
    type(cells_t), intent(in) :: cells                !< all cells
    type(np_patches_t), intent(in) :: patches         !< the patches
    real(wp), intent(in) :: u(:,:)                    !< (3, nodes) displacements
    type(np_values_t), intent(inout) :: values        !< filled: f, det, a, jbar
    logical, intent(out) :: ok                        !< every J > 0
    integer, intent(out) :: bad                       !< the first cell with J <= 0 (else 0)
    real(wp) :: ue(3, 4), finv(3, 3)
    integer :: e, l, a
    if (.not. allocated(values%det)) then
      allocate(values%f(3, 3, patches%n), values%det(patches%n), values%a(3, 4, patches%n), &
               values%jbar(patches%n), values%tau(3, 3, patches%n), &
               values%c(3, 3, 3, 3, patches%n), values%pressure(patches%n), &
               values%pbar(patches%n))
    end if
    ok = .true.
    bad = 0
    do e = 1, patches%n
      l = patches%cell(e)
      ue = u(:, cells%nodes(1:4, l))
      call cell_deformation_gradient(3, 4, cells%grad(:, :, l), ue, values%f(:, :, e))
      call inverse_3x3(values%f(:, :, e), finv, values%det(e))
      if (.not. values%det(e) > 0.0_wp .and. ok) then
        ok = .false.
        bad = l
      end if
      do a = 1, 4
        values%a(:, a, e) = matmul(transpose(finv), cells%grad(1:3, a, l))
      end do
    end do
    ! Jbar = 1 + sum_h c_eh (J_h - 1) (the coefficients sum to 1): exactly 1 at J = 1, and
    ! no cancellation near it (nearly incompressible flow)
    call patch_means(patches, values%det - 1.0_wp, values%jbar)
    values%jbar = 1.0_wp + values%jbar
  end subroutine np_prepare

  !> Fbar = (Jbar/J)^(1/3) F of ELFORM 13 cell position e (the caller's material update).
  pure function np_fbar(values, e) result(fbar)
    type(np_values_t), intent(in) :: values           !< np_prepare's values
    integer, intent(in) :: e                          !< position among the ELFORM 13 cells
    real(wp) :: fbar(3, 3)
    fbar = values%f(:, :, e)*inverse_cube_root(values%det(e)/values%jbar(e))
  end function np_fbar

  !> After the material updates (values%tau, values%c): the Cauchy pressures and their means.
  subroutine np_pressures(patches, values)
    type(np_patches_t), intent(in) :: patches         !< the patches
    type(np_values_t), intent(inout) :: values        !< pressure, pbar filled
    integer :: e
    do e = 1, patches%n
      values%pressure(e) = (values%tau(1, 1, e) + values%tau(2, 2, e) + values%tau(3, 3, e))/ &
                           (3.0_wp*values%jbar(e))
    end do
    call patch_means(patches, values%pressure, values%pbar)
  end subroutine np_pressures

  !> means(e) = sum_h c_eh values(h), in the patches' fixed order.
  pure subroutine patch_means(patches, per_cell, means)
    type(np_patches_t), intent(in) :: patches         !< the patches
    real(wp), intent(in) :: per_cell(:)               !< (n) a value per ELFORM 13 cell
    real(wp), intent(out) :: means(:)                 !< (n) their means
    integer :: e, k
    do e = 1, patches%n
      means(e) = 0.0_wp
      do k = patches%term_start(e), patches%term_start(e + 1) - 1
        means(e) = means(e) + patches%coef(k)*per_cell(patches%term(k))
      end do
    end do
  end subroutine patch_means

  !> ELFORM 13 cell position e: its Kirchhoff-like stress tau_eff = dev(tau_bar) + pbar J 1 (the
  !> nodal forces are V0 tau_eff F^-T g_a, cell_internal_force's), the spatial tangent c_eff
  !> of its own tangent (cell_tangent), and, on the nodes of its patch (patches%patch_node
  !> from patch_start(e)), the block V0 (t (x) b + b (x) q + r b (x) b) of the means
  !> (module header). block(3*(i-1)+k, 3*(j-1)+l): patch nodes i, j, components k, l.
  pure subroutine np_cell_terms(cells, patches, values, e, tau_eff, c_eff, block)
    type(cells_t), intent(in) :: cells                !< all cells
    type(np_patches_t), intent(in) :: patches         !< the patches
    type(np_values_t), intent(in) :: values           !< after np_pressures
    integer, intent(in) :: e                          !< position among the ELFORM 13 cells
    real(wp), intent(out) :: tau_eff(3, 3)            !< dev(tau_bar) + pbar J 1
    real(wp), intent(out) :: c_eff(3, 3, 3, 3)        !< its spatial tangent
    real(wp), intent(out) :: block(:,:)               !< (>= 3 np, >= 3 np), np patch nodes
    real(wp) :: tmat(3, 3), mmat(3, 3), r, b(3, patches%max_patch), t(3, 4), q(3, 4)
    integer :: first, np, k, h, a, i, j, slot(4), m
    call fbar_tangent(values%tau(:, :, e), values%c(:, :, :, :, e), values%jbar(e), &
                      values%det(e), values%pbar(e), tau_eff, c_eff, tmat, mmat, r)
    first = patches%patch_start(e)
    np = patches%patch_start(e + 1) - first
    ! b = sum_h c_eh J_h F_h^-T g_h on the patch's nodes
    b(:, 1:np) = 0.0_wp
    do k = patches%term_start(e), patches%term_start(e + 1) - 1
      h = patches%term(k)
      call patch_slots(cells%nodes(1:4, patches%cell(h)), slot)
      do a = 1, 4
        b(:, slot(a)) = b(:, slot(a)) + patches%coef(k)*values%det(h)*values%a(:, a, h)
      end do
    end do
    do a = 1, 4
      t(:, a) = matmul(tmat, values%a(:, a, e))
      q(:, a) = matmul(mmat, values%a(:, a, e))
    end do
    call patch_slots(cells%nodes(1:4, patches%cell(e)), slot)
    associate (w => cells%weight(patches%cell(e)))
      do j = 1, np
        do i = 1, np
          do m = 1, 3
            block(3*(i-1)+1:3*i, 3*(j-1)+m) = w*r*b(:, i)*b(m, j)
          end do
        end do
      end do
      do a = 1, 4                     ! t (x) b: rows of e's nodes; b (x) q: columns
        do j = 1, np
          do m = 1, 3
            block(3*(slot(a)-1)+1:3*slot(a), 3*(j-1)+m) = &
                block(3*(slot(a)-1)+1:3*slot(a), 3*(j-1)+m) + w*t(:, a)*b(m, j)
            block(3*(j-1)+m, 3*(slot(a)-1)+1:3*slot(a)) = &
                block(3*(j-1)+m, 3*(slot(a)-1)+1:3*slot(a)) + w*b(m, j)*q(:, a)
          end do
        end do
      end do
    end associate

  contains

    !> The places of 4 nodes in e's patch (binary search of the ascending list).
    pure subroutine patch_slots(nodes, places)
      integer, intent(in) :: nodes(4)                 !< the nodes
      integer, intent(out) :: places(4)               !< their places 1..np
      integer :: n, lo, hi, mid
      do n = 1, 4
        lo = 1
        hi = np
        do while (lo < hi)
          mid = (lo + hi)/2
          if (patches%patch_node(first + mid - 1) < nodes(n)) then
            lo = mid + 1
          else
            hi = mid
          end if
        end do
        places(n) = lo
      end do
    end subroutine patch_slots

  end subroutine np_cell_terms

  !> The F-bar algebra of one element (module header): tau_eff, c_eff, T, M and r from the
  !> material's tau_bar and c_bar at Fbar, Jbar, J and pbar.
  pure subroutine fbar_tangent(tau_bar, c_bar, jbar, det, pbar, tau_eff, c_eff, tmat, mmat, r)
    real(wp), intent(in) :: tau_bar(3, 3)             !< Kirchhoff stress at Fbar
    real(wp), intent(in) :: c_bar(3, 3, 3, 3)         !< its spatial tangent
    real(wp), intent(in) :: jbar, det, pbar           !< Jbar, J, mean pressure
    real(wp), intent(out) :: tau_eff(3, 3)            !< dev(tau_bar) + pbar J 1
    real(wp), intent(out) :: c_eff(3, 3, 3, 3)        !< spatial tangent at fixed Jbar, pbar
    real(wp), intent(out) :: tmat(3, 3), mmat(3, 3)   !< T and M
    real(wp), intent(out) :: r                        !< d p / d Jbar
    real(wp), parameter :: ONE_THIRD = 1.0_wp/3.0_wp
    real(wp) :: unit(3, 3), dev(3, 3), trace, c_one(3, 3), one_c(3, 3), one_c_one, pj
    integer :: i, j, k, l
    unit = 0.0_wp
    do i = 1, 3
      unit(i, i) = 1.0_wp
    end do
    trace = tau_bar(1, 1) + tau_bar(2, 2) + tau_bar(3, 3)
    dev = tau_bar - ONE_THIRD*trace*unit
    do j = 1, 3
      do i = 1, 3
        c_one(i, j) = c_bar(i, j, 1, 1) + c_bar(i, j, 2, 2) + c_bar(i, j, 3, 3)   ! c : 1
        one_c(i, j) = c_bar(1, 1, i, j) + c_bar(2, 2, i, j) + c_bar(3, 3, i, j)   ! 1 : c
      end do
    end do
    one_c_one = c_one(1, 1) + c_one(2, 2) + c_one(3, 3)
    pj = pbar*det
    do l = 1, 3
      do k = 1, 3
        do j = 1, 3
          do i = 1, 3
            ! P c P (c with the minor symmetries), then the stress terms
            c_eff(i, j, k, l) = c_bar(i, j, k, l) - ONE_THIRD*unit(i, j)*one_c(k, l) &
                - ONE_THIRD*c_one(i, j)*unit(k, l) + one_c_one/9.0_wp*unit(i, j)*unit(k, l) &
                + 2.0_wp*ONE_THIRD*trace*(0.5_wp*(unit(i, k)*unit(j, l) + unit(i, l)*unit(j, k)) &
                                          - ONE_THIRD*unit(i, j)*unit(k, l)) &
                - 2.0_wp*ONE_THIRD*(unit(i, j)*dev(k, l) + dev(i, j)*unit(k, l)) &
                + pj*(unit(i, j)*unit(k, l) - (unit(i, k)*unit(j, l) + unit(i, l)*unit(j, k)))
          end do
        end do
      end do
    end do
    tau_eff = dev + pj*unit
    tmat = c_one + 2.0_wp*tau_bar
    tmat = (tmat - ONE_THIRD*(tmat(1, 1) + tmat(2, 2) + tmat(3, 3))*unit)/(3.0_wp*jbar)
    mmat = one_c + 2.0_wp*tau_bar
    mmat = (mmat - ONE_THIRD*(mmat(1, 1) + mmat(2, 2) + mmat(3, 3))*unit)/(3.0_wp*jbar)
    r = (one_c_one - trace)/(9.0_wp*jbar**2)
  end subroutine fbar_tangent

end module mefem_implicit_nodal_pressure
