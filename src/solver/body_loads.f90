!> Body loads of *LOAD_BODY_X/_Y/_Z and *LOAD_BODY_PARTS (doc/theory.md, "Body loads").
!>
!> The keywords give a base acceleration a(t) = sum over the keywords of SF curve(t) along
!> their global axis; the body force on a node of lumped mass m is f = -m a (LS-DYNA's
!> convention: gravity is *LOAD_BODY_Z with SF curve = +g, and pulls towards -z). The masses
!> are the lumped masses of mefem_lumped_mass (mesh and enriched nodes alike; with mass
!> scaling the physical ones), so the forces of a uniform acceleration sum to -M a exactly
!> as the masses do. The loads act on the nodes of the elements of the parts of the
!> *LOAD_BODY_PARTS set, or of every part without it; rigid parts take theirs as one force
!> -M a at the centre of mass (the explicit solver's rigid bodies). Every value is computed
!> per node from replicated data, so it is the same bits on any number of ranks.
module mefem_body_loads
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, MAT_RIGID
  use mefem_cells, only: cells_t
  use mefem_curves, only: curve_value
  implicit none
  private

  public :: body_acceleration, body_load_parts, body_load_nodes, add_body_forces

contains

  !> Base acceleration a(t) along the global axes: SF curve(t) of each *LOAD_BODY_ keyword.
  function body_acceleration(model, t) result(a)
    type(model_t), intent(in) :: model       !< resolved model
    real(wp), intent(in) :: t                !< time
    real(wp) :: a(3)
    integer :: k
    a = 0.0_wp
    do k = 1, model%n_body_loads
      associate (load => model%body_loads(k))
        a(load%direction) = a(load%direction) + &
            load%scale*curve_value(model%curves(load%curve), t)
      end associate
    end do
  end function body_acceleration

  !> The parts the body loads act on: those of the *LOAD_BODY_PARTS set, or all parts (none
  !> when the deck has no body load).
  function body_load_parts(model) result(on)
    type(model_t), intent(in) :: model       !< resolved model
    logical :: on(model%n_parts)
    integer :: i
    on = model%n_body_loads > 0
    if (model%n_body_loads == 0 .or. model%body_part_set <= 0) return
    on = .false.
    associate (members => model%sets(model%body_part_set)%members)
      do i = 1, size(members)
        if (members(i) > 0) on(members(i)) = .true.
      end do
    end associate
  end function body_load_parts

  !> The nodes that carry a nodal body force (cells' numbering: mesh nodes, then enriched
  !> nodes): the corners and enriched nodes of the elements of the deformable parts the body
  !> loads act on. Nodes of rigid parts only have no lumped mass (their body carries it).
  subroutine body_load_nodes(model, cells, on)
    type(model_t), intent(in) :: model              !< resolved model
    type(cells_t), intent(in) :: cells              !< cells of the same model
    logical, allocatable, intent(out) :: on(:)      !< (n_mesh_nodes + n_enriched)
    logical :: parts(model%n_parts)
    integer :: e, i, p, node
    allocate(on(cells%n_mesh_nodes + cells%n_enriched))
    on = .false.
    parts = body_load_parts(model)
    do e = 1, model%elements%n
      p = model%elements%part(e)
      if (p <= 0) cycle
      if (.not. parts(p)) cycle
      if (model%parts(p)%material > 0) then
        if (model%materials(model%parts(p)%material)%kind == MAT_RIGID) cycle
      end if
      do i = 1, size(model%elements%conn, 1)
        node = model%elements%conn(i, e)
        if (node > 0) on(node) = .true.
      end do
      if (cells%enriched_of(e) > 0) on(cells%enriched_of(e)) = .true.
    end do
  end subroutine body_load_nodes

  !> force(:, n) = force(:, n) - mass(n) a at every node with a nonzero (loaded) mass; a has
  !> 3 components, the first size(force, 1) are used (2D: x, y).
  pure subroutine add_body_forces(a, mass, force)
    real(wp), intent(in) :: a(3)               !< base acceleration
    real(wp), intent(in) :: mass(:)            !< (nnode) loaded mass (0: no body force)
    real(wp), intent(inout) :: force(:,:)      !< (dim, nnode) added to
    integer :: n, d
    do n = 1, size(mass)
      if (mass(n) == 0.0_wp) cycle
      do d = 1, size(force, 1)
        force(d, n) = force(d, n) - mass(n)*a(d)
      end do
    end do
  end subroutine add_body_forces

end module mefem_body_loads
