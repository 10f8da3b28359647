!> Planar rigid walls (*RIGIDWALL_PLANAR) as a kinematic constraint on nodes, the default
!> (non-penalty) treatment of LS-DYNA (doc/theory.md, "Rigid bodies and rigid walls").
!>
!> The wall is the plane through the tail point (XT, YT, ZT) with unit normal n from the tail
!> to the head; the allowed side is the one n points into. After the displacement update, a
!> tested node whose new position is behind the plane, g^{n+1} = (x^{n+1} - x_T).n < 0, is
!> put back on it and its half-step velocity corrected:
!>   normal:      v_n = -g^n/dt  (x^n + dt v lies on the plane),    dv_n = v_n - v.n > 0
!>   tangential:  FRIC = 0 unchanged; 0 < FRIC < 1 Coulomb: |dv_t| = min(FRIC dv_n, |v_t|)
!>                against v_t; FRIC = 1 no sliding: v_t = 0
!>   u^{n+1} = u^n + dt v (tangential part) with the normal part exactly on the plane.
!> The wall receives -m dv/dt from each node. Nodes in front of the plane are not touched
!> (the wall pulls nothing); a node released from the wall just moves on.
!> The routines take one rank's local nodes; every rank treats its copies of shared nodes
!> identically, and only owned nodes count in the force and work (the driver sums those).
module mefem_rigid_walls
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, rigid_wall_t, ON_NODE_SET
  use mefem_boundary_conditions, only: target_nodes
  implicit none
  private

  public :: rigid_wall_nodes, rigid_wall_constrain, rigid_wall_normal

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
      if (all(normal == 0.0_wp)) then
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
    end associate
    if (present(skip)) tested = tested .and. .not. skip(1:n_mesh_nodes)
    nodes = pack([(i, i = 1, size(node_global))], node_global <= n_mesh_nodes)
    nodes = pack(nodes, tested(node_global(nodes)))
  end subroutine rigid_wall_nodes

  !> Enforce wall `wall` at time `time` (= t^{n+1}; nothing outside BIRTH..DEATH) on the
  !> listed local nodes after the displacement update u_new = u_old + dt v_half: penetrating
  !> nodes are put on the plane and their v_half corrected (module header). force(3) is the
  !> force the owned nodes exert on the wall, -sum m dv/dt_velocity (pointing into the wall
  !> for an impact), dt_velocity the step of the velocity update that v_half came from
  !> (dt_avg = (dt_old + dt)/2 of the central difference; default dt), so that a node held
  !> on the wall gives its force f = m a whatever the step lengths (a shortened last step
  !> does not inflate it). work (optional) is the work of the wall on the owned nodes in this step,
  !> sum m/2 (|v_after|^2 - |v_before|^2) <= 0: the jump of the half-step kinetic energy the
  !> wall causes, to be booked like external work in the energy balance.
  subroutine rigid_wall_constrain(wall, dim, x0, u_new, v_half, u_old, mass, dt, time, &
                                  nodes, owned, force, work, dt_velocity)
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
    real(wp) :: normal(3), gap_new, gap_old, v_before(3), v_after(3), vn_before, vn_after
    real(wp) :: v_t(3), speed, dvn, dv(3), dt_force
    integer :: k, i
    force = 0.0_wp
    dt_force = dt
    if (present(dt_velocity)) then
      if (dt_velocity > 0.0_wp) dt_force = dt_velocity
    end if
    if (present(work)) work = 0.0_wp
    if (time < wall%birth .or. time > wall%death .or. dt <= 0.0_wp) return
    normal = rigid_wall_normal(wall, dim)
    if (all(normal == 0.0_wp)) return
    v_before = 0.0_wp
    do k = 1, size(nodes)
      i = nodes(k)
      gap_new = dot_product(x0(1:dim, i) + u_new(1:dim, i) - wall%tail(1:dim), normal(1:dim))
      if (gap_new >= 0.0_wp) cycle
      gap_old = dot_product(x0(1:dim, i) + u_old(1:dim, i) - wall%tail(1:dim), normal(1:dim))
      v_before(1:dim) = v_half(1:dim, i)
      vn_before = dot_product(v_before, normal)
      vn_after = -gap_old/dt
      dvn = vn_after - vn_before
      v_t = v_before - vn_before*normal
      speed = norm2(v_t)
      if (wall%friction >= NO_SLIDING) then
        v_t = 0.0_wp
      else if (wall%friction > 0.0_wp .and. speed > 0.0_wp) then
        v_t = v_t*max(0.0_wp, 1.0_wp - wall%friction*max(dvn, 0.0_wp)/speed)
      end if
      v_after = vn_after*normal + v_t
      dv = v_after - v_before
      ! tangential: by the velocity change; normal: exactly onto the plane
      u_new(1:dim, i) = u_new(1:dim, i) + dt*(dv(1:dim) - dot_product(dv, normal)*normal(1:dim)) &
                        - gap_new*normal(1:dim)
      v_half(1:dim, i) = v_after(1:dim)
      if (.not. owned(i)) cycle
      force = force - mass(i)*dv/dt_force
      if (present(work)) work = work + 0.5_wp*mass(i)*(dot_product(v_after, v_after) - &
                                                       dot_product(v_before, v_before))
    end do
  end subroutine rigid_wall_constrain

end module mefem_rigid_walls
