!> Essential boundary conditions and external loads at a given time, on nodal arrays.
!>
!> Fixed degrees of freedom come from *BOUNDARY_SPC_NODE/_SET and the TC codes of *NODE;
!> prescribed displacements from *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET with VAD = 2.
!> External forces come from *LOAD_NODE_POINT/_SET and the pressures of *LOAD_SEGMENT(_SET):
!> a positive pressure pushes into the body, against the outward normal of the segment
!> (right-hand rule N1-N2-N3 in 3D; in 2D plane strain, a segment N1-N2 runs with the body
!> on its left, counter-clockwise, and its outward normal is (t_y, -t_x)).
module mefem_boundary_conditions
  use mefem_kinds, only: wp
  use mefem_vector_math, only: cross
  use mefem_model, only: model_t, source_t, box_holds, TC_FIXED, ON_NODE, ON_NODE_SET, ON_ALL_NODES, ON_PART, &
                         ON_PART_SET
  use mefem_errors, only: warn
  use mefem_strings, only: itoa
  use mefem_deck_source, only: location
  use mefem_curves, only: curve_value
  implicit none
  private

  public :: fixed_dofs, prescribed_displacements, external_forces, target_nodes
  public :: initial_velocities, warn_loads_on_free_nodes

contains

  !> Nodes a condition applies to: one node, a node set, all nodes, or the nodes of the
  !> elements of a part or of the parts of a part set (ascending, each once).
  subroutine target_nodes(model, kind, target, nodes)
    type(model_t), intent(in) :: model                !< resolved model
    integer, intent(in) :: kind, target               !< ON_* and index
    integer, allocatable, intent(out) :: nodes(:)     !< node indices
    logical, allocatable :: in_part(:), marked(:)
    integer :: i, e
    select case (kind)
    case (ON_NODE)
      nodes = [target]
    case (ON_NODE_SET)
      nodes = pack(model%sets(target)%members, model%sets(target)%members > 0)
    case (ON_ALL_NODES)
      nodes = [(i, i = 1, model%nodes%n)]
    case (ON_PART, ON_PART_SET)
      allocate(in_part(model%n_parts), marked(model%nodes%n))
      in_part = .false.
      if (kind == ON_PART) then
        in_part(target) = .true.
      else
        do i = 1, size(model%sets(target)%members)
          if (model%sets(target)%members(i) > 0) in_part(model%sets(target)%members(i)) = .true.
        end do
      end if
      marked = .false.
      do e = 1, model%elements%n
        if (.not. in_part(model%elements%part(e))) cycle
        do i = 1, size(model%elements%conn, 1)
          if (model%elements%conn(i, e) > 0) marked(model%elements%conn(i, e)) = .true.
        end do
      end do
      nodes = pack([(i, i = 1, model%nodes%n)], marked)
    case default
      allocate(nodes(0))
    end select
  end subroutine target_nodes

  !> Warn about loads and initial velocities given to nodes that no element has: the analyses
  !> compute the nodes of elements only, so these are not applied (LS-DYNA would move such a
  !> node on its own). One warning per card, with the number of such nodes and the first.
  subroutine warn_loads_on_free_nodes(model)
    type(model_t), intent(in) :: model                !< resolved model
    logical, allocatable :: attached(:)
    integer, allocatable :: nodes(:)
    integer :: e, k, lonely
    allocate(attached(model%nodes%n))
    attached = .false.
    do e = 1, model%elements%n
      do k = 1, size(model%elements%conn, 1)
        if (model%elements%conn(k, e) > 0) attached(model%elements%conn(k, e)) = .true.
      end do
    end do
    do k = 1, model%n_nodal_loads
      associate (load => model%nodal_loads(k))
        if (load%target <= 0) cycle
        call target_nodes(model, load%target_kind, load%target, nodes)
        call report(load%src, 'load')
      end associate
    end do
    do k = 1, model%n_initial_velocities
      associate (iv => model%initial_velocities(k))
        if (iv%target_kind /= ON_NODE .and. iv%target_kind /= ON_NODE_SET) cycle
        if (iv%target <= 0) cycle
        call target_nodes(model, iv%target_kind, iv%target, nodes)
        call report(iv%src, 'initial velocity')
      end associate
    end do

  contains

    !> The warning for one card whose target nodes are `nodes`.
    subroutine report(src, what)
      type(source_t), intent(in) :: src               !< where the card was read
      character(len=*), intent(in) :: what            !< 'load' or 'initial velocity'
      integer :: first
      lonely = count(.not. attached(nodes))
      if (lonely == 0) return
      first = nodes(findloc(attached(nodes), .false., dim=1))
      call warn(location(src%file, src%line)//': '//itoa(lonely)//' node(s) of this '// &
          what//' belong to no element (the first: node '//itoa(model%nodes%id(first))// &
          '): mefem computes the nodes of elements only, so the '//what//' is not applied there')
    end subroutine report

  end subroutine warn_loads_on_free_nodes

  !> Initial velocities of the mesh nodes (*INITIAL_VELOCITY, _NODE, _GENERATION), applied
  !> in deck order (a later card overrides an earlier one at the same node); v(dim, nnode).
  !> _GENERATION: v + omega n x (x - centre). *INITIAL_VELOCITY: VX.. plus the rotational
  !> velocities VXR.. about the origin are not used for solids (translational nodes only).
  subroutine initial_velocities(model, v)
    type(model_t), intent(in) :: model       !< resolved model
    real(wp), intent(out) :: v(:,:)          !< (dim, nnode) velocities
    integer, allocatable :: nodes(:), exempt(:)
    real(wp) :: w(3), r(3), spin(3)
    integer :: k, n, dim
    dim = size(v, 1)
    v = 0.0_wp
    do k = 1, model%n_initial_velocities
      associate (iv => model%initial_velocities(k))
        call target_nodes(model, iv%target_kind, iv%target, nodes)
        w = iv%omega*iv%axis
        do n = 1, size(nodes)
          if (iv%box > 0) then                  ! BOXID: the nodes inside the box only
            if (.not. box_holds(model%boxes(iv%box), model%nodes%x(:, nodes(n)))) cycle
          end if
          r = model%nodes%x(:, nodes(n)) - iv%center
          if (iv%generation) then
            spin = cross(w, r)
            v(:, nodes(n)) = iv%v(1:dim) + spin(1:dim)
          else
            v(:, nodes(n)) = iv%v(1:dim)
          end if
        end do
        if (iv%exempt_set > 0) then
          call target_nodes(model, ON_NODE_SET, iv%exempt_set, exempt)
          do n = 1, size(exempt)
            v(:, exempt(n)) = iv%v_exempt(1:dim)
          end do
        end if
      end associate
    end do
  end subroutine initial_velocities

  !> Degrees of freedom held fixed (zero displacement) at time t; fixed(dim, nnode).
  subroutine fixed_dofs(model, t, fixed)
    type(model_t), intent(in) :: model       !< resolved model
    real(wp), intent(in) :: t                !< time
    logical, intent(inout) :: fixed(:,:)     !< (dim, nnode) set true where fixed
    integer :: k, n, dim
    integer, allocatable :: nodes(:)
    dim = size(fixed, 1)
    do n = 1, model%nodes%n
      fixed(:, n) = fixed(:, n) .or. TC_FIXED(1:dim, model%nodes%tc(n))
    end do
    do k = 1, model%n_spcs
      associate (spc => model%spcs(k))
        if (t < spc%birth .or. t > spc%death) cycle
        call target_nodes(model, spc%target_kind, spc%target, nodes)
        do n = 1, size(nodes)
          fixed(:, nodes(n)) = fixed(:, nodes(n)) .or. spc%dof(1:dim)
        end do
      end associate
    end do
  end subroutine fixed_dofs

  !> Prescribed displacements (VAD = 2) at time t: fixed(i,n) set and value(i,n) given.
  subroutine prescribed_displacements(model, t, fixed, value)
    type(model_t), intent(in) :: model       !< resolved model
    real(wp), intent(in) :: t                !< time
    logical, intent(inout) :: fixed(:,:)     !< (dim, nnode) set true where prescribed
    real(wp), intent(inout) :: value(:,:)    !< (dim, nnode) prescribed displacement
    integer :: k, n, dof
    integer, allocatable :: nodes(:)
    real(wp) :: amount
    do k = 1, model%n_motions
      associate (pm => model%motions(k))
        if (pm%vad /= 2) cycle
        if (t < pm%birth .or. t > pm%death) cycle
        dof = abs(pm%dof)
        if (dof < 1 .or. dof > size(fixed, 1)) cycle
        amount = pm%scale*curve_value(model%curves(pm%curve), t)
        call target_nodes(model, pm%target_kind, pm%target, nodes)
        do n = 1, size(nodes)
          fixed(dof, nodes(n)) = .true.
          value(dof, nodes(n)) = amount
        end do
      end associate
    end do
  end subroutine prescribed_displacements

  !> External forces at time t in the reference configuration; force(dim, nnode) is added to.
  subroutine external_forces(model, t, force)
    type(model_t), intent(in) :: model       !< resolved model
    real(wp), intent(in) :: t                !< time
    real(wp), intent(inout) :: force(:,:)    !< (dim, nnode)
    integer :: k, n, s, dof
    integer, allocatable :: nodes(:)
    real(wp) :: amount
    do k = 1, model%n_nodal_loads
      associate (load => model%nodal_loads(k))
        dof = load%dof
        if (dof < 1 .or. dof > size(force, 1)) cycle
        amount = load%scale*curve_value(model%curves(load%curve), t)
        call target_nodes(model, load%target_kind, load%target, nodes)
        if (any(load%direction /= 0.0_wp)) then    ! CID: along the local axis DOF
          do n = 1, size(nodes)
            force(:, nodes(n)) = force(:, nodes(n)) + amount*load%direction(1:size(force, 1))
          end do
        else
          do n = 1, size(nodes)
            force(dof, nodes(n)) = force(dof, nodes(n)) + amount
          end do
        end if
      end associate
    end do
    do k = 1, model%n_pressure_loads
      associate (load => model%pressure_loads(k))
        if (t < load%arrival) cycle
        amount = load%scale*curve_value(model%curves(load%curve), t)
        if (load%set > 0) then
          do s = 1, size(model%sets(load%set)%members)/4
            call segment_pressure(model, model%sets(load%set)%members(4*s-3:4*s), amount, force)
          end do
        else
          call segment_pressure(model, load%nodes, amount, force)
        end if
      end associate
    end do
  end subroutine external_forces

  !> Consistent nodal forces of a uniform pressure p on one segment (2-node line in 2D,
  !> triangle or bilinear quadrilateral in 3D, by 2x2 Gauss points).
  subroutine segment_pressure(model, seg, p, force)
    type(model_t), intent(in) :: model       !< resolved model
    integer, intent(in) :: seg(4)            !< node indices (N4 = N3 for triangles)
    real(wp), intent(in) :: p                !< pressure
    real(wp), intent(inout) :: force(:,:)    !< (dim, nnode)
    real(wp) :: x(3, 4), tangent(3), area(3), dxi(3), deta(3), shape(4), xi, eta
    real(wp), parameter :: GAUSS = 1.0_wp/sqrt(3.0_wp)
    integer :: i, j, a, nn
    if (size(force, 1) == 2 .or. seg(3) == seg(2) .or. seg(3) == 0) then
      ! 2D line segment N1-N2: outward normal (t_y, -t_x), half the force to each node
      tangent = model%nodes%x(:, seg(2)) - model%nodes%x(:, seg(1))
      area = [tangent(2), -tangent(1), 0.0_wp]
      do a = 1, 2
        force(1:2, seg(a)) = force(1:2, seg(a)) - 0.5_wp*p*area(1:2)
      end do
      return
    end if
    nn = 4
    if (seg(4) == seg(3) .or. seg(4) == 0) nn = 3
    x(:, 1:nn) = model%nodes%x(:, seg(1:nn))
    if (nn == 3) then
      area = 0.5_wp*cross(x(:, 2) - x(:, 1), x(:, 3) - x(:, 1))
      do a = 1, 3
        force(:, seg(a)) = force(:, seg(a)) - p*area/3.0_wp
      end do
      return
    end if
    do j = -1, 1, 2
      do i = -1, 1, 2
        xi = i*GAUSS
        eta = j*GAUSS
        shape = 0.25_wp*[(1 - xi)*(1 - eta), (1 + xi)*(1 - eta), (1 + xi)*(1 + eta), &
                         (1 - xi)*(1 + eta)]
        dxi = 0.25_wp*(-(1 - eta)*x(:, 1) + (1 - eta)*x(:, 2) + (1 + eta)*x(:, 3) &
                       - (1 + eta)*x(:, 4))
        deta = 0.25_wp*(-(1 - xi)*x(:, 1) - (1 + xi)*x(:, 2) + (1 + xi)*x(:, 3) &
                        + (1 - xi)*x(:, 4))
        area = cross(dxi, deta)
        do a = 1, 4
          force(:, seg(a)) = force(:, seg(a)) - p*shape(a)*area
        end do
      end do
    end do
  end subroutine segment_pressure


end module mefem_boundary_conditions
