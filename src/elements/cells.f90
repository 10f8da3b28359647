!> Integration cells: the one representation of every deformable element formulation.
!>
!> A cell is where the (smoothed) deformation gradient, the stress and the material history
!> live: for the ME-FEM elements (ELFORM 43) a smoothing domain (one per edge in 2D, per face
!> in 3D), for the linear elements (tetrahedra 10 and 13, triangle 13) the element itself: a
!> cell of the nodal-pressure tetrahedron (solid ELFORM 13) is flagged (nodal_pressure), and
!> the explicit solver averages its volume change at the nodes (doc/theory.md 2.7). Each cell
!> holds its nodes (mesh nodes and the enriched nodes the code creates, one per ME-FEM element,
!> numbered after the mesh nodes), the gradients of their shape functions in the reference
!> configuration, smoothed over the cell (formulation 2.6), and its weight (area or volume).
!> Then F = I + sum_I u_I (x) grad_I and every analysis runs the same cell loop, whatever
!> the formulation: the dispatch on formulation happens here, once, at set-up.
!>
!> ME-FEM in hierarchical form (doc/theory.md 2.1): u = sum_I N_I u_I + Psi_e b_e, with u_I
!> the corner displacements (N_I linear) and b_e = u_e - mean of the corners' u the bubble
!> amplitude, the degree of freedom of the enriched node (the same field as sum Psi_I u_I +
!> Psi_e u_e, since Psi_I = N_I - Psi_e/(dim+1)). Gradients at the integration point of side
!> k of element e:
!>   grad Psi_e = ((dim+1) kappa / H_k) n_k (enriched node),   grad N_I = n_I / H_I (corners),
!> with n_k the inward unit normal of side k, H_k the altitude; the cell of a side averages
!> them over its one or two elements with weights A_e/(dim+1).
module mefem_cells
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t, say
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t, MAT_RIGID, ELEM_SOLID, ELEM_SHELL
  use mefem_model_resolve, only: ELFORM_MEFEM, ELFORM_TET_NODAL_PRESSURE
  use mefem_enrichment, only: enrichment_t, enrichment_setup
  use mefem_smoothing_domains, only: smoothing_domains_t, smoothing_domains_build
  implicit none
  private

  public :: cells_build, cells_summary

  integer, parameter, public :: CELL_MAX_NODES = 7   !< 3D interior face: 5 corners + 2 enriched

  !> All integration cells of the model's deformable parts.
  type, public :: cells_t
    integer :: dim = 3                        !< 2 (plane strain) or 3
    integer :: n = 0                          !< number of cells
    integer :: n_mesh_nodes = 0               !< nodes of the deck (numbered first)
    integer :: n_enriched = 0                 !< enriched nodes (numbered after the mesh nodes)
    integer, allocatable :: nnodes(:)         !< (n) nodes of each cell
    integer, allocatable :: nodes(:,:)        !< (CELL_MAX_NODES, n) node numbers
    real(wp), allocatable :: grad(:,:,:)      !< (dim, CELL_MAX_NODES, n) reference gradients
    real(wp), allocatable :: weight(:)        !< (n) area (2D, unit thickness) or volume
    integer, allocatable :: material(:)       !< (n) material index
    logical, allocatable :: nodal_pressure(:) !< (n) a nodal-pressure tetrahedron (ELFORM 13)
    integer, allocatable :: elements(:,:)     !< (2, n) model elements sharing the cell (0 none)
    integer, allocatable :: enriched_of(:)    !< (model elements) enriched node, 0 if none
    integer, allocatable :: enriched_element(:) !< (n_enriched) its model element
    type(enrichment_t) :: enrichment          !< constants used by the ME-FEM cells
  end type cells_t

contains

  !> Build the cells of every deformable part, part by part (smoothing domains do not cross
  !> part boundaries, so every cell has one material).
  subroutine cells_build(model, cells, status)
    type(model_t), intent(in) :: model       !< resolved model
    type(cells_t), intent(out) :: cells      !< the cells
    type(status_t), intent(out) :: status    !< failure (bad mesh) and its reason
    integer :: p, e, count_cells, count_enriched, dim, nv
    logical :: mefem
    dim = model%dimension
    nv = dim + 1
    cells%dim = dim
    cells%n_mesh_nodes = model%nodes%n
    allocate(cells%enriched_of(model%elements%n))
    cells%enriched_of = 0
    if (any(is_mefem_part(model, [(p, p = 1, model%n_parts)]))) then
      call enrichment_setup(dim, model%controls%gmf_basis, model%controls%support_radius, &
                            model%controls%bubble_mass, cells%enrichment, status)
      if (.not. status%ok) return
    end if
    ! upper bound of the cell count: sides per element (ME-FEM) or one per element
    count_cells = 0
    count_enriched = 0
    do e = 1, model%elements%n
      if (.not. is_deformable(model, e)) cycle
      if (is_mefem_part(model, model%elements%part(e))) then
        count_cells = count_cells + nv
        count_enriched = count_enriched + 1
        cells%enriched_of(e) = model%nodes%n + count_enriched
      else
        count_cells = count_cells + 1
      end if
    end do
    cells%n_enriched = count_enriched
    allocate(cells%enriched_element(count_enriched))
    do e = 1, model%elements%n
      if (cells%enriched_of(e) > 0) cells%enriched_element(cells%enriched_of(e) - model%nodes%n) = e
    end do
    allocate(cells%nnodes(count_cells), cells%nodes(CELL_MAX_NODES, count_cells), &
             cells%grad(dim, CELL_MAX_NODES, count_cells), cells%weight(count_cells), &
             cells%material(count_cells), cells%elements(2, count_cells), &
             cells%nodal_pressure(count_cells))
    cells%nodal_pressure = .false.
    cells%nodes = 0
    cells%grad = 0.0_wp
    cells%elements = 0
    do p = 1, model%n_parts
      mefem = is_mefem_part(model, p)
      call add_part_cells(model, p, mefem, cells, status)
      if (.not. status%ok) return
    end do
  end subroutine cells_build

  !> Print the cell counts and, for ME-FEM, the enrichment constants (run log, rank 0).
  subroutine cells_summary(cells)
    type(cells_t), intent(in) :: cells   !< cells
    if (cells%n_enriched > 0) then
      call say('ME-FEM enrichment: a/L = '//rtoa(cells%enrichment%support_ratio)// &
          ', kappa = '//rtoa(cells%enrichment%kappa)//', mass fraction = '// &
          rtoa(cells%enrichment%mass_fraction)//', bubble inertia (explicit) = '// &
          rtoa(cells%enrichment%bubble_mass_ratio)//' rho V, '//itoa(cells%n_enriched)// &
          ' enriched nodes, '//itoa(cells%n)//' cells (smoothing domains and elements)')
    else
      call say('elements: '//itoa(cells%n)//' cells')
    end if
  end subroutine cells_summary

  !> True for an element of a deformable (non-rigid) part.
  logical function is_deformable(model, e)
    type(model_t), intent(in) :: model   !< resolved model
    integer, intent(in) :: e             !< element index
    integer :: p
    p = model%elements%part(e)
    is_deformable = .false.
    if (p == 0) return
    if (model%parts(p)%material == 0) return
    is_deformable = model%materials(model%parts(p)%material)%kind /= MAT_RIGID
    if (model%dimension == 3) then
      is_deformable = is_deformable .and. model%elements%keyword(e) == ELEM_SOLID
    else
      is_deformable = is_deformable .and. model%elements%keyword(e) == ELEM_SHELL
    end if
  end function is_deformable

  !> True for parts with the ME-FEM formulation (and a deformable material).
  elemental logical function is_mefem_part(model, p)
    type(model_t), intent(in) :: model   !< resolved model
    integer, intent(in) :: p             !< part index
    is_mefem_part = .false.
    if (model%parts(p)%section == 0 .or. model%parts(p)%material == 0) return
    if (model%materials(model%parts(p)%material)%kind == MAT_RIGID) return
    is_mefem_part = model%sections(model%parts(p)%section)%elform == ELFORM_MEFEM
  end function is_mefem_part

  !> Append the cells of part p.
  subroutine add_part_cells(model, p, mefem, cells, status)
    type(model_t), intent(in) :: model        !< resolved model
    integer, intent(in) :: p                  !< part index
    logical, intent(in) :: mefem              !< ME-FEM (else standard) formulation
    type(cells_t), intent(inout) :: cells     !< cells appended to
    type(status_t), intent(out) :: status     !< failure and its reason
    integer, allocatable :: elems(:), conn(:,:)
    type(smoothing_domains_t) :: domains
    integer :: dim, nv, ne, i, e, m, k, slot, c, local
    real(wp) :: grad_n(cells%dim, cells%dim + 1), grad_enr(cells%dim), share
    dim = cells%dim
    nv = dim + 1
    elems = pack([(e, e = 1, model%elements%n)], model%elements%part(1:model%elements%n) == p)
    ne = 0
    do i = 1, size(elems)
      if (is_deformable(model, elems(i))) ne = ne + 1
    end do
    if (ne == 0) return
    elems = pack(elems, [(is_deformable(model, elems(i)), i = 1, size(elems))])
    conn = model%elements%conn(1:nv, elems)
    call smoothing_domains_build(conn, model%nodes%x, domains, status, &
                                 element_ids=model%elements%id(elems))
    if (.not. status%ok) then
      status%message = 'part '//itoa(model%parts(p)%id)//': '//status%message
      return
    end if
    if (.not. mefem) then
      ! standard linear element: one cell per element, gradients of the linear functions
      do i = 1, ne
        c = cells%n + 1
        cells%n = c
        call linear_gradients(domains, i, grad_n)
        cells%nnodes(c) = nv
        cells%nodes(1:nv, c) = conn(:, i)
        cells%grad(:, 1:nv, c) = grad_n
        cells%weight(c) = domains%elem_measure(i)
        cells%material(c) = model%parts(p)%material
        cells%nodal_pressure(c) = dim == 3 .and. &
            model%sections(model%parts(p)%section)%elform == ELFORM_TET_NODAL_PRESSURE
        cells%elements(1, c) = elems(i)
      end do
      return
    end if
    do m = 1, domains%ndomain
      c = cells%n + 1
      cells%n = c
      cells%weight(c) = domains%domain_weight(m)
      cells%material(c) = model%parts(p)%material
      cells%nnodes(c) = 0
      do slot = 1, 2
        i = domains%domain_elem(slot, m)
        if (i == 0) cycle
        e = elems(i)
        cells%elements(slot, c) = e
        k = domains%domain_local(slot, m)
        call linear_gradients(domains, i, grad_n)
        grad_enr = real(nv, wp)*cells%enrichment%kappa/domains%altitude(k, i)* &
                   domains%inward_normal(1:dim, k, i)
        share = domains%elem_measure(i)/real(nv, wp)/domains%domain_weight(m)
        do local = 1, nv          ! hierarchical: the corners carry P1 alone (no - Psi_e/(dim+1))
          call add_gradient(cells, c, conn(local, i), share*grad_n(:, local))
        end do
        call add_gradient(cells, c, cells%enriched_of(e), share*grad_enr)
      end do
    end do
  end subroutine add_part_cells

  !> Gradients of the linear shape functions of element i: grad N_I = n_I / H_I.
  pure subroutine linear_gradients(domains, i, grad_n)
    type(smoothing_domains_t), intent(in) :: domains   !< geometry
    integer, intent(in) :: i                           !< element within the part
    real(wp), intent(out) :: grad_n(:,:)               !< (dim, dim+1)
    integer :: local
    do local = 1, size(grad_n, 2)
      grad_n(:, local) = domains%inward_normal(1:size(grad_n, 1), local, i)/ &
                         domains%altitude(local, i)
    end do
  end subroutine linear_gradients

  !> Add a gradient contribution of node to cell c (appending the node if new).
  pure subroutine add_gradient(cells, c, node, g)
    type(cells_t), intent(inout) :: cells   !< cells
    integer, intent(in) :: c                !< cell
    integer, intent(in) :: node             !< node number
    real(wp), intent(in) :: g(:)            !< contribution
    integer :: j
    do j = 1, cells%nnodes(c)
      if (cells%nodes(j, c) == node) then
        cells%grad(:, j, c) = cells%grad(:, j, c) + g
        return
      end if
    end do
    j = cells%nnodes(c) + 1
    cells%nnodes(c) = j
    cells%nodes(j, c) = node
    cells%grad(:, j, c) = g
  end subroutine add_gradient

end module mefem_cells
