!> Integration cells: the one representation of every deformable element formulation.
!>
!> A cell is where the (smoothed) deformation gradient, the stress and the material history
!> live: for the ME-FEM elements (ELFORM 43) a smoothing domain (one per edge in 2D, per face
!> in 3D), for the linear elements (tetrahedra 10 and 13, triangle 13) the element itself: a
!> cell of the nodal-pressure tetrahedron (solid ELFORM 13) is flagged (nodal_pressure), and
!> the explicit solver averages its volume change at the nodes (doc/theory.md 2.7); a cell of
!> the one-point hexahedron (solid ELFORM 1, a pentahedron as a collapsed hexahedron) holds
!> its uniform gradients and, in the hexahedron arrays (hex_of), its hourglass shape vectors
!> and hourglass coefficients (doc/theory.md 2.8; a tetrahedron in such a part is the linear
!> tetrahedron, which is what the collapsed hexahedron's uniform gradient gives). Each cell
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
  use mefem_model, only: model_t, MAT_RIGID, ELEM_SOLID, ELEM_SHELL, TOPO_TET4, TOPO_PENTA6
  use mefem_model_resolve, only: ELFORM_MEFEM, ELFORM_TET_NODAL_PRESSURE, part_hourglass, &
                                 hexahedral_formulation
  use mefem_hexahedron, only: HOURGLASS_MODES, hexahedron_reference, hourglass_mode_metric
  use mefem_material_update, only: material_elastic_moduli
  use mefem_cell_finite_strain, only: inverse_3x3
  use mefem_enrichment, only: enrichment_t, enrichment_setup
  use mefem_smoothing_domains, only: smoothing_domains_t, smoothing_domains_build, &
                                      smoothing_domains_count, simplex_geometry
  implicit none
  private

  public :: cells_build, cells_summary, cell_grad_column, cells_subset, cells_release_topology

  integer, parameter, public :: CELL_MAX_NODES = 8   !< a hexahedron
  integer, parameter, public :: MEFEM_FACE_NODES = 7 !< 3D interior face: 5 corners + 2 enriched
  ! hourglass forms (HOURGLASS_FORM by IHQ 1..10) and the stiffness forms' scale of the
  ! elastic bending stiffness at QM = 1 (doc/theory.md 2.8)
  integer, parameter :: HOURGLASS_VISCOUS = 1, HOURGLASS_STIFFNESS = 2
  integer, parameter :: HOURGLASS_FORM(10) = [HOURGLASS_VISCOUS, HOURGLASS_VISCOUS, &
      HOURGLASS_VISCOUS, HOURGLASS_STIFFNESS, HOURGLASS_STIFFNESS, HOURGLASS_STIFFNESS, &
      HOURGLASS_STIFFNESS, HOURGLASS_STIFFNESS, HOURGLASS_STIFFNESS, HOURGLASS_STIFFNESS]
  real(wp), parameter :: BENDING_SCALE(10) = [0.0_wp, 0.0_wp, 0.0_wp, 2.5_wp, 2.5_wp, &
      1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp, 1.0_wp]
  integer, parameter :: STATIC_IHQ = 6   !< the static analyses' form in place of a viscous one

  !> All integration cells of the model's deformable parts.
  type, public :: cells_t
    integer :: dim = 3                        !< 2 (plane strain) or 3
    integer :: n = 0                          !< number of cells
    integer :: n_mesh_nodes = 0               !< nodes of the deck (numbered first)
    integer :: n_enriched = 0                 !< enriched nodes (numbered after the mesh nodes)
    integer, allocatable :: nnodes(:)         !< (n) nodes of each cell
    integer, allocatable :: nodes(:,:)        !< (CELL_MAX_NODES, n) node numbers
    real(wp), allocatable :: grad(:,:,:)      !< (dim, CELL_MAX_NODES, :) reference gradients:
                                              !< column c for cell c, or, when cells_build was
                                              !< given the elements wanted, column
                                              !< grad_column(c) (cell_grad_column)
    integer, allocatable :: grad_column(:)    !< (n) with elements wanted: the column of a
                                              !< cell whose first element is wanted, else 0
    real(wp), allocatable :: weight(:)        !< (n) area (2D, unit thickness) or volume
    integer, allocatable :: material(:)       !< (n) material index
    logical, allocatable :: nodal_pressure(:) !< (n) a nodal-pressure tetrahedron (ELFORM 13)
    integer, allocatable :: elements(:,:)     !< (2, n) model elements sharing the cell (0 none)
    integer, allocatable :: enriched_of(:)    !< (model elements) enriched node, 0 if none
    integer, allocatable :: enriched_element(:) !< (n_enriched) its model element
    type(enrichment_t) :: enrichment          !< constants used by the ME-FEM cells
    ! one-point hexahedra (ELFORM 1; doc/theory.md 2.8)
    integer :: n_hex = 0                      !< hexahedral cells
    integer, allocatable :: hex_of(:)         !< (n) index in the arrays below, 0 if none
    real(wp), allocatable :: hg_gamma(:,:,:)  !< (CELL_MAX_NODES, HOURGLASS_MODES, n_hex)
                                              !< hourglass shape vectors at the cell's nodes
    real(wp), allocatable :: hg_stiffness(:,:) !< (6, n_hex) K (XX YY ZZ XY YZ ZX), force
                                              !< per length
    real(wp), allocatable :: hg_viscosity(:)  !< (n_hex) c, force per velocity
    real(wp), allocatable :: hg_metric(:)     !< (n_hex) bound of lambda_max(G), G the modes'
                                              !< inverse-mass metric (hourglass_mode_metric)
    real(wp), allocatable :: node_volume(:,:) !< (CELL_MAX_NODES, n_hex) int N_I dV
    integer, allocatable :: hg_corner(:,:)    !< (8, n_hex) the node slot of each corner (a
                                              !< pentahedron's repeated corners share one)
  end type cells_t

  ! while cells_build runs with elements wanted: which, and the gradient columns given out
  logical, allocatable :: want(:)             !< (model elements) the gradients kept
  integer :: n_kept = 0                       !< columns of grad given out so far

contains

  !> Build the cells of every deformable part, part by part (smoothing domains do not cross
  !> part boundaries, so every cell has one material). With `wanted` (the explicit analysis:
  !> this rank's elements) every cell is built, numbered as without it, but the reference
  !> gradients, the largest array of the cells, are kept only for the cells whose first
  !> element is wanted (the cells this rank computes; cell_grad_column).
  subroutine cells_build(model, cells, status, static, wanted)
    type(model_t), intent(in) :: model       !< resolved model
    type(cells_t), intent(out) :: cells      !< the cells
    type(status_t), intent(out) :: status    !< failure (bad mesh) and its reason
    logical, intent(in), optional :: static  !< for a static analysis: hexahedra with a viscous
                                             !< hourglass form (no static resistance) get the
                                             !< physical stiffness form IHQ 6 at their QM, as
                                             !< LS-DYNA's implicit analyses switch to type 6
    logical, intent(in), optional :: wanted(:)  !< (model elements) the gradients kept
    integer :: p, e, count_cells, count_enriched, dim, nv, count_kept
    integer, allocatable :: elems(:), conn(:,:)
    real(wp), allocatable :: kept(:,:,:)
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
    ! the cell count: the smoothing domains of each ME-FEM part (its distinct sides, about
    ! 2.1 per tetrahedron, counted without building them: the arrays below are the largest of
    ! the set-up, every rank holds them) or one per element
    count_cells = 0
    count_enriched = 0
    do e = 1, model%elements%n
      if (.not. is_deformable(model, e)) cycle
      if (is_mefem_part(model, model%elements%part(e))) then
        count_enriched = count_enriched + 1
        cells%enriched_of(e) = model%nodes%n + count_enriched
      else
        count_cells = count_cells + 1
      end if
    end do
    do p = 1, model%n_parts
      if (.not. is_mefem_part(model, p) .or. is_hexahedral_part(model, p)) cycle
      call part_simplices(model, p, elems, conn)
      if (size(elems) > 0) count_cells = count_cells + smoothing_domains_count(conn, &
                                                                                model%nodes%n)
    end do
    cells%n_enriched = count_enriched
    allocate(cells%hex_of(count_cells))
    cells%hex_of = 0
    call count_hexahedra(model, cells%n_hex)
    allocate(cells%hg_gamma(CELL_MAX_NODES, HOURGLASS_MODES, cells%n_hex), &
             cells%hg_stiffness(6, cells%n_hex), cells%hg_viscosity(cells%n_hex), &
             cells%hg_metric(cells%n_hex), cells%node_volume(CELL_MAX_NODES, cells%n_hex), &
             cells%hg_corner(8, cells%n_hex))
    cells%n_hex = 0                 ! counted again as they are added
    allocate(cells%enriched_element(count_enriched))
    do e = 1, model%elements%n
      if (cells%enriched_of(e) > 0) cells%enriched_element(cells%enriched_of(e) - model%nodes%n) = e
    end do
    count_kept = count_cells
    if (present(wanted)) then            ! (at most the sides of each wanted element)
      count_kept = 0
      do e = 1, model%elements%n
        if (.not. (wanted(e) .and. is_deformable(model, e))) cycle
        count_kept = count_kept + merge(nv, 1, is_mefem_part(model, model%elements%part(e)))
      end do
      allocate(cells%grad_column(count_cells))
      cells%grad_column = 0
      allocate(want(model%elements%n))
      want = wanted(1:model%elements%n)
      n_kept = 0
    end if
    allocate(cells%nnodes(count_cells), cells%nodes(CELL_MAX_NODES, count_cells), &
             cells%grad(dim, CELL_MAX_NODES, count_kept), cells%weight(count_cells), &
             cells%material(count_cells), cells%elements(2, count_cells), &
             cells%nodal_pressure(count_cells))
    cells%nodal_pressure = .false.
    cells%nodes = 0
    cells%grad = 0.0_wp
    cells%elements = 0
    do p = 1, model%n_parts
      if (is_hexahedral_part(model, p)) then
        call add_hexahedral_part_cells(model, p, cells, static)
        cycle
      end if
      mefem = is_mefem_part(model, p)
      call add_part_cells(model, p, mefem, cells, status)
      if (.not. status%ok) return
    end do
    if (present(wanted)) then            ! the kept columns, to their number
      kept = cells%grad(:, :, 1:n_kept)
      call move_alloc(kept, cells%grad)
      deallocate(want)
    end if
  end subroutine cells_build

  !> The topology (nodes, weight, elements, material) of the cells `list` (global cell
  !> numbers) as cells of their own, numbered 1..size(list) in the list's order: what the
  !> explicit analysis keeps for its output piece once the global cells are released.
  subroutine cells_subset(cells, list, subset)
    type(cells_t), intent(in) :: cells        !< all cells (topology)
    integer, intent(in) :: list(:)            !< the cells kept
    type(cells_t), intent(out) :: subset      !< their topology, no gradients
    subset%dim = cells%dim
    subset%n = size(list)
    subset%n_mesh_nodes = cells%n_mesh_nodes
    subset%n_enriched = cells%n_enriched
    subset%nnodes = cells%nnodes(list)
    subset%nodes = cells%nodes(:, list)
    subset%weight = cells%weight(list)
    subset%material = cells%material(list)
    subset%nodal_pressure = cells%nodal_pressure(list)
    subset%elements = cells%elements(:, list)
    allocate(subset%grad(cells%dim, CELL_MAX_NODES, 0))
  end subroutine cells_subset

  !> Free the per-cell arrays of the global cells (the explicit analysis, after its set-up:
  !> every rank held them for the whole model); the counts stay.
  subroutine cells_release_topology(cells)
    type(cells_t), intent(inout) :: cells     !< all cells: their counts only from now on
    if (allocated(cells%nnodes)) deallocate(cells%nnodes)
    if (allocated(cells%nodes)) deallocate(cells%nodes)
    if (allocated(cells%grad)) deallocate(cells%grad)
    if (allocated(cells%grad_column)) deallocate(cells%grad_column)
    if (allocated(cells%weight)) deallocate(cells%weight)
    if (allocated(cells%material)) deallocate(cells%material)
    if (allocated(cells%nodal_pressure)) deallocate(cells%nodal_pressure)
    if (allocated(cells%elements)) deallocate(cells%elements)
    if (allocated(cells%enriched_of)) deallocate(cells%enriched_of)
    if (allocated(cells%enriched_element)) deallocate(cells%enriched_element)
    if (allocated(cells%hex_of)) deallocate(cells%hex_of)
  end subroutine cells_release_topology

  !> The column of cells%grad that holds cell c's reference gradients (0: not kept, the cells
  !> were built with elements wanted and c's first element is not one of them).
  pure integer function cell_grad_column(cells, c) result(column)
    type(cells_t), intent(in) :: cells        !< cells
    integer, intent(in) :: c                  !< cell
    column = c
    if (allocated(cells%grad_column)) column = cells%grad_column(c)
  end function cell_grad_column

  !> Start cell c of model element e (its first): its gradient column, if kept.
  subroutine start_cell(cells, c, e)
    type(cells_t), intent(inout) :: cells     !< cells
    integer, intent(in) :: c                  !< the new cell
    integer, intent(in) :: e                  !< its first element
    cells%elements(1, c) = e
    cells%nnodes(c) = 0
    if (.not. allocated(cells%grad_column)) return
    if (.not. want(e)) return
    n_kept = n_kept + 1
    cells%grad_column(c) = n_kept
    cells%grad(:, :, n_kept) = 0.0_wp
  end subroutine start_cell

  !> Number of hexahedral cells: the non-tetrahedral elements of hexahedral parts.
  subroutine count_hexahedra(model, n_hex)
    type(model_t), intent(in) :: model   !< resolved model
    integer, intent(out) :: n_hex        !< their number
    integer :: e
    n_hex = 0
    do e = 1, model%elements%n
      if (.not. is_deformable(model, e)) cycle
      if (.not. is_hexahedral_part(model, model%elements%part(e))) cycle
      if (model%elements%topology(e) /= TOPO_TET4) n_hex = n_hex + 1
    end do
  end subroutine count_hexahedra

  !> True for parts computed as one-point hexahedra (ELFORM 1, 2, -1, -2; deformable).
  logical function is_hexahedral_part(model, p)
    type(model_t), intent(in) :: model   !< resolved model
    integer, intent(in) :: p             !< part index
    is_hexahedral_part = .false.
    if (model%parts(p)%section == 0 .or. model%parts(p)%material == 0) return
    if (model%materials(model%parts(p)%material)%kind == MAT_RIGID) return
    is_hexahedral_part = hexahedral_formulation(model%sections(model%parts(p)%section)%elform)
  end function is_hexahedral_part

  !> Append the cells of hexahedral part p: one per element. A hexahedron or a pentahedron
  !> (a collapsed hexahedron, its repeated corners merged) is a hexahedral cell with its
  !> hourglass data; a tetrahedron the linear tetrahedron's cell (as LS-DYNA's ESORT = 1: one
  !> point integrates it exactly and it has no hourglass modes).
  subroutine add_hexahedral_part_cells(model, p, cells, static)
    type(model_t), intent(in) :: model        !< resolved model
    integer, intent(in) :: p                  !< part index
    type(cells_t), intent(inout) :: cells     !< cells appended to
    logical, intent(in), optional :: static   !< a static analysis (cells_build)
    integer :: e, c, h, a, k, nn, corners(8), ihq, material
    real(wp) :: x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: lambda, mu, young, rho, wave_speed, sum_bb(6), node_mass(CELL_MAX_NODES), qm
    real(wp) :: cell_grad(3, CELL_MAX_NODES)
    material = model%parts(p)%material
    rho = model%materials(material)%density
    call material_elastic_moduli(model%materials(material), lambda, mu)
    young = mu*(3.0_wp*lambda + 2.0_wp*mu)/(lambda + mu)
    wave_speed = sqrt((lambda + 2.0_wp*mu)/rho)
    call part_hourglass(model, p, ihq, qm)
    if (present(static)) then
      if (static .and. HOURGLASS_FORM(ihq) == HOURGLASS_VISCOUS) ihq = STATIC_IHQ
    end if
    do e = 1, model%elements%n
      if (model%elements%part(e) /= p) cycle
      if (.not. is_deformable(model, e)) cycle
      associate (conn => model%elements%conn(:, e))
        select case (model%elements%topology(e))
        case (TOPO_TET4)       ! LS-DYNA's N1 N2 N3 N4 N4 N4 N4 N4
          corners = [conn(1), conn(2), conn(3), conn(4), conn(4), conn(4), conn(4), conn(4)]
        case (TOPO_PENTA6)     ! LS-DYNA's N1 N2 N3 N4 N5 N5 N6 N6 (classify's wedge order)
          corners = [conn(1), conn(2), conn(5), conn(4), conn(3), conn(3), conn(6), conn(6)]
        case default
          corners = conn(1:8)
        end select
      end associate
      do a = 1, 8
        x(:, a) = model%nodes%x(:, corners(a))
      end do
      if (model%elements%topology(e) == TOPO_TET4) then
        call tetrahedron_gradients(x(:, 1:4), volume, grad(:, 1:4))
        corners(5:8) = corners(4)          ! (merged into N4 with zero gradients below)
        grad(:, 5:8) = 0.0_wp
      else
        call hexahedron_reference(x, volume, grad, node_volume, gamma)
      end if
      c = cells%n + 1
      cells%n = c
      cells%weight(c) = volume
      cells%material(c) = material
      call start_cell(cells, c, e)
      cell_grad = 0.0_wp
      h = 0
      if (model%elements%topology(e) /= TOPO_TET4) then
        cells%n_hex = cells%n_hex + 1
        h = cells%n_hex
        cells%hex_of(c) = h
        cells%hg_gamma(:, :, h) = 0.0_wp
        cells%node_volume(:, h) = 0.0_wp
      end if
      do a = 1, 8                       ! the corners, a repeated one merged into its first
        call add_gradient(cells, c, corners(a), grad(:, a))
        k = findloc(cells%nodes(1:cells%nnodes(c), c), corners(a), dim=1)
        cell_grad(:, k) = cell_grad(:, k) + grad(:, a)
        if (h == 0) cycle
        cells%hg_corner(a, h) = k
        cells%hg_gamma(k, :, h) = cells%hg_gamma(k, :, h) + gamma(a, :)
        cells%node_volume(k, h) = cells%node_volume(k, h) + node_volume(a)
      end do
      if (h == 0) cycle
      nn = cells%nnodes(c)
      ! K = s QM E V sum_I B_I (x) B_I / 24 (stiffness forms), c = QM rho c V^(2/3) / 4
      ! (viscous forms): doc/theory.md 2.8
      sum_bb = 0.0_wp
      do a = 1, nn
        associate (b => cell_grad(:, a))
          sum_bb = sum_bb + [b(1)*b(1), b(2)*b(2), b(3)*b(3), b(1)*b(2), b(2)*b(3), b(1)*b(3)]
        end associate
      end do
      cells%hg_stiffness(:, h) = 0.0_wp
      cells%hg_viscosity(h) = 0.0_wp
      if (HOURGLASS_FORM(ihq) == HOURGLASS_STIFFNESS) then
        cells%hg_stiffness(:, h) = BENDING_SCALE(ihq)*qm*young*volume*sum_bb/24.0_wp
      else
        cells%hg_viscosity(h) = 0.25_wp*qm*rho*wave_speed*volume**(2.0_wp/3.0_wp)
      end if
      node_mass(1:nn) = rho*cells%node_volume(1:nn, h)
      cells%hg_metric(h) = hourglass_mode_metric(nn, cells%hg_gamma(:, :, h), node_mass)
    end do
  end subroutine add_hexahedral_part_cells

  !> Volume and gradients of the linear shape functions of a tetrahedron (corners N1-N4).
  pure subroutine tetrahedron_gradients(x, volume, grad)
    real(wp), intent(in) :: x(3, 4)            !< corner coordinates
    real(wp), intent(out) :: volume            !< its volume
    real(wp), intent(out) :: grad(3, 4)        !< grad N_I
    real(wp) :: edges(3, 3), inv(3, 3), det
    integer :: k
    do k = 1, 3
      edges(:, k) = x(:, k + 1) - x(:, 1)
    end do
    call inverse_3x3(edges, inv, det)           ! rows: the gradients of N2, N3, N4
    volume = abs(det)/6.0_wp
    grad(:, 2:4) = transpose(inv)
    grad(:, 1) = -(grad(:, 2) + grad(:, 3) + grad(:, 4))
  end subroutine tetrahedron_gradients

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
    integer :: dim, nv, ne, i, e, m, k, slot, c, local, column
    real(wp) :: grad_n(cells%dim, cells%dim + 1), grad_enr(cells%dim), share
    real(wp) :: altitude(cells%dim + 1), normal(3, cells%dim + 1)
    dim = cells%dim
    nv = dim + 1
    call part_simplices(model, p, elems, conn)
    ne = size(elems)
    if (ne == 0) return
    call smoothing_domains_build(conn, model%nodes%x, domains, status, &
                                 element_ids=model%elements%id(elems), lean=.true.)
    if (.not. status%ok) then
      status%message = 'part '//itoa(model%parts(p)%id)//': '//status%message
      return
    end if
    if (.not. mefem) then
      ! standard linear element: one cell per element, gradients of the linear functions
      do i = 1, ne
        c = cells%n + 1
        cells%n = c
        call start_cell(cells, c, elems(i))
        cells%nnodes(c) = nv
        cells%nodes(1:nv, c) = conn(:, i)
        column = cell_grad_column(cells, c)
        if (column > 0) then
          call element_gradients(i, grad_n, altitude, normal)
          cells%grad(:, 1:nv, column) = grad_n
        end if
        cells%weight(c) = domains%elem_measure(i)
        cells%material(c) = model%parts(p)%material
        cells%nodal_pressure(c) = dim == 3 .and. &
            model%sections(model%parts(p)%section)%elform == ELFORM_TET_NODAL_PRESSURE
      end do
      return
    end if
    do m = 1, domains%ndomain
      c = cells%n + 1
      cells%n = c
      cells%weight(c) = domains%domain_weight(m)
      cells%material(c) = model%parts(p)%material
      call start_cell(cells, c, elems(domains%domain_elem(1, m)))
      column = cell_grad_column(cells, c)
      do slot = 1, 2
        i = domains%domain_elem(slot, m)
        if (i == 0) cycle
        e = elems(i)
        cells%elements(slot, c) = e
        k = domains%domain_local(slot, m)
        grad_n = 0.0_wp                   ! (the nodes alone where the gradients are not kept)
        grad_enr = 0.0_wp
        if (column > 0) then
          call element_gradients(i, grad_n, altitude, normal)
          grad_enr = real(nv, wp)*cells%enrichment%kappa/altitude(k)*normal(1:dim, k)
        end if
        share = domains%elem_measure(i)/real(nv, wp)/domains%domain_weight(m)
        do local = 1, nv          ! hierarchical: the corners carry P1 alone (no - Psi_e/(dim+1))
          call add_gradient(cells, c, conn(local, i), share*grad_n(:, local))
        end do
        call add_gradient(cells, c, cells%enriched_of(e), share*grad_enr)
      end do
    end do

  contains

    !> Gradients of the linear shape functions of element i of the part, grad N_I = n_I/H_I,
    !> with its altitudes and inward normals (computed here: the domains are built lean).
    subroutine element_gradients(i, grad_n, altitude, normal)
      integer, intent(in) :: i                        !< element within the part
      real(wp), intent(out) :: grad_n(:,:)            !< (dim, dim+1)
      real(wp), intent(out) :: altitude(:)            !< (dim+1) altitude over side k
      real(wp), intent(out) :: normal(:,:)            !< (3, dim+1) inward normal of side k
      real(wp) :: measure, side(cells%dim + 1)
      integer :: corner
      call simplex_geometry(model%nodes%x(:, conn(:, i)), measure, altitude, normal, side)
      do corner = 1, size(grad_n, 2)
        grad_n(:, corner) = normal(1:size(grad_n, 1), corner)/altitude(corner)
      end do
    end subroutine element_gradients

  end subroutine add_part_cells

  !> The deformable elements of part p (model indices, ascending) and their corners (the
  !> simplices' dim + 1 corners).
  subroutine part_simplices(model, p, elems, conn)
    type(model_t), intent(in) :: model                !< resolved model
    integer, intent(in) :: p                          !< part index
    integer, allocatable, intent(out) :: elems(:)     !< its deformable elements
    integer, allocatable, intent(out) :: conn(:,:)    !< (dim + 1, size(elems)) their corners
    integer :: e, i
    elems = pack([(e, e = 1, model%elements%n)], model%elements%part(1:model%elements%n) == p)
    elems = pack(elems, [(is_deformable(model, elems(i)), i = 1, size(elems))])
    conn = model%elements%conn(1:model%dimension + 1, elems)
  end subroutine part_simplices


  !> Add a gradient contribution of node to cell c (appending the node if new; the gradient
  !> is kept only where the cell's column is).
  pure subroutine add_gradient(cells, c, node, g)
    type(cells_t), intent(inout) :: cells   !< cells
    integer, intent(in) :: c                !< cell
    integer, intent(in) :: node             !< node number
    real(wp), intent(in) :: g(:)            !< contribution
    integer :: j, column
    column = cell_grad_column(cells, c)
    do j = 1, cells%nnodes(c)
      if (cells%nodes(j, c) == node) then
        if (column > 0) cells%grad(:, j, column) = cells%grad(:, j, column) + g
        return
      end if
    end do
    j = cells%nnodes(c) + 1
    cells%nnodes(c) = j
    cells%nodes(j, c) = node
    if (column > 0) cells%grad(:, j, column) = g
  end subroutine add_gradient

end module mefem_cells
