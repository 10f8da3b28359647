!> Rigid walls (*RIGIDWALL_PLANAR, *RIGIDWALL_GEOMETRIC_FLAT/_PRISM/_CYLINDER/_SPHERE, fixed
!> or moving with _MOTION) as a kinematic constraint on nodes, the default (non-penalty)
!> treatment of LS-DYNA (doc/theory.md, "Rigid bodies and rigid walls").
!>
!> Each wall gives a node position x its signed gap g(x) (> 0 on the allowed side) and the
!> unit normal n at the nearest wall point, pointing into the allowed side (wall_gap): a plane
!> through the tail point (XT, YT, ZT) with n from the tail to the head (finite: the rectangle
!> LENL x LENM spanned from the tail along the l edge XHEV and m = n x l); a prism (the box
!> LENL x LENM x LENP over that rectangle, along n: nodes kept outside); a cylinder (axis from
!> the tail towards the head, radius RADCYL, length LENCYL or infinite; nodes kept outside);
!> a sphere (centre at the tail, radius RADSPH; nodes kept outside). After the displacement
!> update, a tested node whose new position is behind the wall, g^{n+1} < 0, is put back on it
!> and its half-step velocity corrected, relative to the wall's velocity w:
!>   normal:      v_n = -g^n/dt with g^n the old position's gap from the tangent plane at the
!>                nearest point (x^n + dt v lies on it; for planes the plane itself),
!>                dv_n = v_n - v.n > 0
!>   tangential:  v_t - w_t: FRIC = 0 unchanged; 0 < FRIC < 1 Coulomb: |dv_t| =
!>                min(FRIC dv_n, |v_t - w_t|) against it; FRIC = 1 no sliding: v_t = w_t
!>   u^{n+1} = u^n + dt v (tangential part) with the normal part exactly on the wall.
!> The wall receives -m dv/dt from each node. Nodes in front of the plane are not touched
!> (the wall pulls nothing); a node released from the wall just moves on.
!> The routines take one rank's local nodes; every rank treats its copies of shared nodes
!> identically, and only owned nodes count in the force and work (the driver sums those).
module mefem_rigid_walls
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, rigid_wall_t, box_holds, ON_NODE_SET, WALL_PLANE, WALL_FLAT, &
                         WALL_PRISM, WALL_CYLINDER, WALL_SPHERE
  use mefem_vector_math, only: cross
  use mefem_boundary_conditions, only: target_nodes
  implicit none
  private

  public :: rigid_wall_nodes, rigid_wall_constrain, rigid_wall_normal, wall_gap

  !> FRIC at and above which a node in contact does not slide.
  real(wp), parameter :: NO_SLIDING = 1.0_wp

contains

  !> Unit normal of a wall in the first dim components (tail to head; zero when the head
  !> and tail coincide in those components, e.g. a wall normal to z in a 2D model).
  pure function rigid_wall_normal(wall, dim) result(normal)
    type(rigid_wall_t), intent(in) :: wall        !< the wall
    integer, intent(in) :: dim                    !< 2 or 3
    real(wp) :: normal(3)
    real(wp) :: length
    normal = 0.0_wp
    normal(1:dim) = wall%head(1:dim) - wall%tail(1:dim)
    length = norm2(normal)
    if (length > 0.0_wp) then
      normal = normal/length
    else
      normal = 0.0_wp
    end if
  end function rigid_wall_normal

  !> Local nodes tested against wall w: local mesh nodes (node_global(i) <= n_mesh_nodes)
  !> that are in NSID (all nodes when NSID = 0) or, when OFFSET > 0, within OFFSET of the
  !> plane in the reference configuration, minus those of NSIDEX and those marked in skip
  !> (e.g. nodes of rigid bodies). None when the wall normal is undefined in the model's
  !> dimension.
  subroutine rigid_wall_nodes(model, w, node_global, n_mesh_nodes, nodes, skip)
    type(model_t), intent(in) :: model            !< resolved model
    integer, intent(in) :: w                      !< wall index
    integer, intent(in) :: node_global(:)         !< (n_local) local -> global node
    integer, intent(in) :: n_mesh_nodes           !< mesh nodes in the global model
    integer, allocatable, intent(out) :: nodes(:) !< local nodes tested, ascending
    logical, intent(in), optional :: skip(:)      !< (n_mesh_nodes) global nodes left out
    logical, allocatable :: tested(:)
    integer, allocatable :: members(:)
    real(wp) :: normal(3)
    integer :: g, i, dim
    dim = model%dimension
    associate (wall => model%rigid_walls(w))
      normal = rigid_wall_normal(wall, dim)
      allocate(tested(n_mesh_nodes))
      if (all(normal == 0.0_wp) .and. wall%shape /= WALL_SPHERE) then
        allocate(nodes(0))
        return
      end if
      if (wall%node_set > 0) then
        tested = .false.
        call target_nodes(model, ON_NODE_SET, wall%node_set, members)
        do i = 1, size(members)        ! a loop: a set may name a node twice
          tested(members(i)) = .true.
        end do
        if (wall%offset > 0.0_wp) then
          do g = 1, n_mesh_nodes
            if (abs(dot_product(model%nodes%x(1:dim, g) - wall%tail(1:dim), normal(1:dim))) &
                <= wall%offset) tested(g) = .true.
          end do
        end if
      else
        tested = .true.
      end if
      if (wall%exempt_set > 0) then
        call target_nodes(model, ON_NODE_SET, wall%exempt_set, members)
        do i = 1, size(members)
          tested(members(i)) = .false.
        end do
      end if
      if (wall%box > 0) then                    ! BOXID: the nodes inside the box only
        do g = 1, n_mesh_nodes
          if (tested(g)) tested(g) = box_holds(model%boxes(wall%box), model%nodes%x(:, g))
        end do
      end if
    end associate
    if (present(skip)) tested = tested .and. .not. skip(1:n_mesh_nodes)
    nodes = pack([(i, i = 1, size(node_global))], node_global <= n_mesh_nodes)
    nodes = pack(nodes, tested(node_global(nodes)))
  end subroutine rigid_wall_nodes

  !> Tested nodes behind wall `wall` (at the displacement `shift` of its motion at t^{n+1},
  !> moving at `wall_velocity`) are put on it and their v_half corrected (module header).
  !> force(3) is the force the owned nodes exert on the wall, -sum m dv/dt_velocity (pointing
  !> into the wall for an impact), dt_velocity the step of the velocity update that v_half
  !> came from (dt_avg = (dt_old + dt)/2 of the central difference; default dt), so that a
  !> node held on the wall gives its force f = m a whatever the step lengths (a shortened last
  !> step does not inflate it). work (optional) is the work of the wall on the owned nodes in
  !> this step, sum m/2 (|v_after|^2 - |v_before|^2): the jump of the half-step kinetic energy
  !> the wall causes, to be booked like external work in the energy balance.
  subroutine rigid_wall_constrain(wall, dim, x0, u_new, v_half, u_old, mass, dt, time, &
                                  nodes, owned, force, work, dt_velocity, shift, wall_velocity)
    type(rigid_wall_t), intent(in) :: wall        !< the wall
    integer, intent(in) :: dim                    !< 2 or 3
    real(wp), intent(in) :: x0(:,:)               !< (>= dim, n_local) reference positions
    real(wp), intent(inout) :: u_new(:,:)         !< (dim, n_local) displacement at t^{n+1}
    real(wp), intent(inout) :: v_half(:,:)        !< (dim, n_local) velocity at t^{n+1/2}
    real(wp), intent(in) :: u_old(:,:)            !< (dim, n_local) displacement at t^n
    real(wp), intent(in) :: mass(:)               !< (n_local) nodal masses
    real(wp), intent(in) :: dt                    !< t^{n+1} - t^n
    real(wp), intent(in) :: time                  !< t^{n+1}
    integer, intent(in) :: nodes(:)               !< local nodes tested (rigid_wall_nodes)
    logical, intent(in) :: owned(:)               !< (n_local) this rank owns the node
    real(wp), intent(out) :: force(3)             !< force of the owned nodes on the wall
    real(wp), intent(out), optional :: work       !< work of the wall on the owned nodes
    real(wp), intent(in), optional :: dt_velocity !< step of the velocity update (default dt)
    real(wp), intent(in), optional :: shift(3)    !< the wall's displacement at t^{n+1}
    real(wp), intent(in), optional :: wall_velocity(3) !< its velocity over the step
    real(wp) :: normal(3), gap_new, gap_old, v_before(3), v_after(3), vn_before, vn_after
    real(wp) :: v_t(3), speed, dvn, dv(3), dt_force, x_new(3), x_old(3), moved(3), w(3)
    real(wp) :: w_t(3), surface(3), normal_old(3)
    logical :: active, active_old
    integer :: k, i
    force = 0.0_wp
    dt_force = dt
    if (present(dt_velocity)) then
      if (dt_velocity > 0.0_wp) dt_force = dt_velocity
    end if
    if (present(work)) work = 0.0_wp
    if (time < wall%birth .or. time > wall%death .or. dt <= 0.0_wp) return
    if (wall%shape /= WALL_SPHERE .and. all(rigid_wall_normal(wall, dim) == 0.0_wp)) return
    moved = 0.0_wp
    if (present(shift)) moved = shift
    w = 0.0_wp
    if (present(wall_velocity)) w = wall_velocity
    v_before = 0.0_wp
    x_new = 0.0_wp
    x_old = 0.0_wp
    do k = 1, size(nodes)
      i = nodes(k)
      x_new(1:dim) = x0(1:dim, i) + u_new(1:dim, i)
      call wall_gap(wall, dim, x_new, moved, gap_new, normal, active)
      if (.not. active .or. gap_new >= 0.0_wp) cycle
      x_old(1:dim) = x0(1:dim, i) + u_old(1:dim, i)
      if (wall%shape == WALL_PLANE .or. wall%shape == WALL_FLAT) then
        call wall_gap(wall, dim, x_old, moved, gap_old, normal_old, active_old)
      else                                  ! from the tangent plane at the nearest point
        surface = x_new - gap_new*normal
        gap_old = dot_product(x_old - surface, normal)
      end if
      v_before(1:dim) = v_half(1:dim, i)
      vn_before = dot_product(v_before, normal)
      vn_after = -gap_old/dt
      dvn = vn_after - vn_before
      w_t = w - dot_product(w, normal)*normal
      v_t = v_before - vn_before*normal - w_t       ! tangential, relative to the wall
      speed = norm2(v_t)
      if (wall%friction >= NO_SLIDING) then
        v_t = 0.0_wp
      else if (wall%friction > 0.0_wp .and. speed > 0.0_wp) then
        v_t = v_t*max(0.0_wp, 1.0_wp - wall%friction*max(dvn, 0.0_wp)/speed)
      end if
      v_after = vn_after*normal + v_t + w_t
      dv = v_after - v_before
      ! tangential: by the velocity change; normal: exactly onto the wall
      u_new(1:dim, i) = u_new(1:dim, i) + dt*(dv(1:dim) - dot_product(dv, normal)*normal(1:dim)) &
                        - gap_new*normal(1:dim)
      v_half(1:dim, i) = v_after(1:dim)
      if (.not. owned(i)) cycle
      force = force - mass(i)*dv/dt_force
      if (present(work)) work = work + 0.5_wp*mass(i)*(dot_product(v_after, v_after) - &
                                                       dot_product(v_before, v_before))
    end do
  end subroutine rigid_wall_constrain

  !> Signed gap of point x from the wall (moved by shift; > 0 on the allowed side) and the
  !> unit normal at the nearest wall point, pointing into the allowed side; active = .false.
  !> where the wall does not act on x (off a finite flat wall's rectangle, beyond a finite
  !> cylinder's ends, at a sphere's or cylinder's centre line).
  pure subroutine wall_gap(wall, dim, x, shift, gap, normal, active)
    type(rigid_wall_t), intent(in) :: wall        !< the wall
    integer, intent(in) :: dim                    !< 2 or 3
    real(wp), intent(in) :: x(3)                  !< the point (3 components; z 0 in 2D)
    real(wp), intent(in) :: shift(3)              !< the wall's displacement
    real(wp), intent(out) :: gap                  !< signed gap
    real(wp), intent(out) :: normal(3)            !< unit normal into the allowed side
    logical, intent(out) :: active                !< the wall acts on x
    real(wp) :: axis(3), l(3), m(3), d(3), along, radial(3), r, a, b, c, depth(6)
    integer :: face
    integer, parameter :: FACE_SIGN(6) = [-1, 1, -1, 1, -1, 1]
    active = .true.
    gap = 0.0_wp
    normal = 0.0_wp
    d = 0.0_wp
    d(1:dim) = x(1:dim) - wall%tail(1:dim) - shift(1:dim)
    if (wall%shape == WALL_SPHERE) then
      r = norm2(d)
      active = r > 0.0_wp
      if (.not. active) return
      normal = d/r
      gap = r - wall%radius
      return
    end if
    axis = rigid_wall_normal(wall, dim)
    select case (wall%shape)
    case (WALL_PLANE)
      normal = axis
      gap = dot_product(d(1:dim), normal(1:dim))
    case (WALL_FLAT, WALL_PRISM)
      l = wall%edge - dot_product(wall%edge, axis)*axis
      l = l/norm2(l)
      m = cross(axis, l)
      a = dot_product(d, l)
      b = dot_product(d, m)
      c = dot_product(d, axis)
      if (wall%shape == WALL_FLAT) then
        active = (wall%length_l <= 0.0_wp .or. (a >= 0.0_wp .and. a <= wall%length_l)) .and. &
                 (wall%length_m <= 0.0_wp .or. (b >= 0.0_wp .and. b <= wall%length_m))
        normal = axis
        gap = c
        return
      end if
      ! prism: outside the box [0, LENL] x [0, LENM] x [0, LENP] (l, m, n); inside, the
      ! nearest face's depth
      depth = [a, wall%length_l - a, b, wall%length_m - b, c, wall%length_p - c]
      if (any(depth < 0.0_wp)) then
        gap = -maxval(-depth, mask=depth < 0.0_wp)  ! (> 0: outside; only its sign is used)
        gap = max(gap, tiny(1.0_wp))
        normal = axis
        return
      end if
      face = minloc(depth, dim=1)
      gap = -depth(face)
      select case ((face + 1)/2)
      case (1)
        normal = FACE_SIGN(face)*l
      case (2)
        normal = FACE_SIGN(face)*m
      case default
        normal = FACE_SIGN(face)*axis
      end select
    case (WALL_CYLINDER)
      along = dot_product(d, axis)
      active = wall%length <= 0.0_wp .or. (along >= 0.0_wp .and. along <= wall%length)
      radial = d - along*axis
      r = norm2(radial)
      active = active .and. r > 0.0_wp
      if (.not. active) return
      normal = radial/r
      gap = r - wall%radius
    end select
  end subroutine wall_gap

end module mefem_rigid_walls
