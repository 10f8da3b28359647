!> The rigid parts' side of the explicit cycle: the resultants of the forces at the rigid
!> bodies' nodes (summed in an order that does not depend on the rank count), the body loads
!> on them, their motion from t^n to t^{n+1} and that of their nodes, and the planar rigid
!> walls that put penetrating nodes back onto their planes. The bodies' and walls' own
!> mechanics are mefem_rigid_bodies and mefem_rigid_walls; their set-up is the driver's.
module mefem_explicit_rigid
  use mefem_kinds, only: wp
  use mefem_model, only: model_t
  use mefem_comm, only: comm_allgatherv_real
  use mefem_explicit_state, only: explicit_state_t
  use mefem_rigid_bodies, only: rigid_bodies_accumulate, rigid_bodies_advance, &
                                rigid_body_point_motion
  use mefem_rigid_walls, only: rigid_wall_constrain
  use mefem_body_loads, only: body_acceleration
  use mefem_curves, only: curve_value
  implicit none
  private

  public :: move_rigid_bodies, rigid_body_resultants, rigid_body_loads, apply_rigid_walls

contains

  !> Rigid bodies from t^n to t^{n+1} with the resultants at t^n, then their nodes: u^{n+1}
  !> and v^{n+1/2} on the body (after the deformable nodes' update, which they override).
  !> The body loads' work is booked as the reactions' (mefem_rigid_bodies):
  !> dt_avg F^n . (v^{n-1/2} + v^{n+1/2})/2, the change of the half-step kinetic energy it
  !> causes (replicated on every rank; glstat adds it once).
  subroutine move_rigid_bodies(model, s, t, dt_old, dt)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< t^n
    real(wp), intent(in) :: dt_old, dt                !< dt^{n-1/2} (0 at the start), dt^{n+1/2}
    real(wp) :: v_old(3, s%bodies%n)
    integer :: k, l, b
    do b = 1, s%bodies%n
      v_old(:, b) = s%bodies%body(b)%velocity
    end do
    call rigid_bodies_advance(model, s%bodies, t + 0.5_wp*dt, t + dt, 0.5_wp*(dt_old + dt), dt, &
                              s%body_force, s%body_moment)
    if (model%n_body_loads > 0) then
      do b = 1, s%bodies%n
        s%body_load_work = s%body_load_work + 0.5_wp*(dt_old + dt)* &
            dot_product(s%body_load(:, b), 0.5_wp*(v_old(:, b) + s%bodies%body(b)%velocity))
      end do
    end if
    do k = 1, s%nrigid
      l = s%rigid_node(k)
      call rigid_body_point_motion(s%bodies, s%rigid_body(k), s%x0(:, l), s%u(:, l), s%v(:, l))
    end do
  end subroutine move_rigid_bodies

  !> Resultant force and moment on every rigid body at the current time: f_ext + f_con -
  !> f_int at its nodes, added in ascending global node order on every rank, so that a body
  !> moved by these forces takes the same bits on any number of ranks. The owners send the
  !> nodes that carry a force (place, position, force; one allgatherv: the contact zone, not
  !> the whole tool); a node without force would add exact zeros, so leaving it out keeps
  !> the bits.
  subroutine rigid_body_resultants(s)
    type(explicit_state_t), intent(inout) :: s        !< local state (forces current)
    integer, parameter :: RECORD = 7                  !< place, position (3), force (3)
    real(wp) :: f(3)
    integer :: k, l, slot, d, nrecord, nall, r
    d = s%dim
    nrecord = 0
    do k = 1, s%nrigid
      l = s%rigid_node(k)
      if (.not. s%owned(l)) cycle
      f = 0.0_wp
      f(1:d) = s%f_ext(:, l) + s%f_con(:, l) - s%f_int(:, l)
      if (all(f == 0.0_wp)) cycle
      s%rigid_send(RECORD*nrecord + 1) = real(s%rigid_slot(k), wp)
      s%rigid_send(RECORD*nrecord + 2:RECORD*nrecord + 4) = 0.0_wp
      s%rigid_send(RECORD*nrecord + 2:RECORD*nrecord + 1 + d) = s%x0(:, l) + s%u(:, l)
      s%rigid_send(RECORD*nrecord + 5:RECORD*nrecord + 7) = f
      nrecord = nrecord + 1
    end do
    call comm_allgatherv_real(s%rigid_send, RECORD*nrecord, s%rigid_all, nall)
    do r = 0, nall/RECORD - 1
      slot = nint(s%rigid_all(RECORD*r + 1))
      s%rigid_buffer(:, slot) = s%rigid_all(RECORD*r + 2:RECORD*r + 7)
      s%rigid_present(slot) = .true.
    end do
    s%body_force = 0.0_wp
    s%body_moment = 0.0_wp
    do slot = 1, size(s%slot_body)
      if (.not. s%rigid_present(slot)) cycle
      call rigid_bodies_accumulate(s%bodies, s%slot_body(slot), s%rigid_buffer(1:d, slot), &
                                   s%rigid_buffer(4:3 + d, slot), s%body_force, s%body_moment)
      s%rigid_present(slot) = .false.
    end do
  end subroutine rigid_body_resultants

  !> Body loads on the rigid bodies: -a(t) times the mass they act on (body_load_mass: the
  !> body's elements if its part takes them, plus the merged masses of nodes that take them)
  !> at the centre of mass (no moment), added to the resultants of time t (their work:
  !> move_rigid_bodies). A prescribed or held component keeps its motion; its reaction takes
  !> the load.
  subroutine rigid_body_loads(model, s, t)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state (resultants of t)
    real(wp), intent(in) :: t                         !< time of the resultants
    real(wp) :: a(3)
    integer :: b
    if (model%n_body_loads == 0) return
    a = body_acceleration(model, t)
    a(s%dim + 1:) = 0.0_wp                            ! (2D: no z)
    do b = 1, s%bodies%n
      s%body_load(:, b) = -s%body_load_mass(b)*a
      s%body_force(:, b) = s%body_force(:, b) + s%body_load(:, b)
    end do
  end subroutine rigid_body_loads

  !> Rigid walls after the displacement update: penetrating nodes back onto the plane, their
  !> velocities corrected; the walls' forces on the owned nodes are kept. The wall's work is
  !> booked like a prescribed motion's: its reaction r^n = m dv/dt_avg times the mean
  !> displacement (du^{n-1/2} + du^{n+1/2})/2 (a node stopped on the wall loses 1/2 m v^2;
  !> a node held there does no work).
  subroutine apply_rigid_walls(model, s, t_new, dt_old, dt)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t_new                     !< t^{n+1}
    real(wp), intent(in) :: dt_old, dt                !< dt^{n-1/2}, dt^{n+1/2}
    real(wp) :: dt_avg, shift(3), velocity(3)
    integer :: k, j, n
    dt_avg = 0.5_wp*(dt_old + dt)
    do k = 1, s%nwall
      associate (nodes => s%wall_nodes(k)%nodes, wall => model%rigid_walls(k))
        ! a moving wall (_MOTION): its displacement at t^{n+1} (OPT 1: the curve's value; OPT
        ! 0: advanced with the curve's velocity at t^{n+1/2}) and its velocity over the step
        shift = s%wall_shift(:, k)
        if (wall%motion_curve > 0) then
          if (wall%motion_option == 1) then
            shift = curve_value(model%curves(wall%motion_curve), t_new)*wall%motion_direction
          else
            shift = shift + dt*curve_value(model%curves(wall%motion_curve), &
                                           t_new - 0.5_wp*dt)*wall%motion_direction
          end if
        end if
        velocity = 0.0_wp
        if (dt > 0.0_wp) velocity = (shift - s%wall_shift(:, k))/dt
        s%wall_shift(:, k) = shift
        s%v_trial(:, nodes) = s%v(:, nodes)
        call rigid_wall_constrain(wall, s%dim, s%x0, s%u, s%v, s%u_old, s%mass, dt, t_new, &
                                  nodes, s%owned, s%wall_force(:, k), dt_velocity=dt_avg, &
                                  shift=shift, wall_velocity=velocity)
        do j = 1, size(nodes)
          n = nodes(j)
          if (.not. s%owned(n)) cycle
          if (dt_old > 0.0_wp) then
            s%wall_work = s%wall_work + s%mass(n)*dot_product(s%v(:, n) - s%v_trial(:, n), &
                0.5_wp*(dt_old*s%v_old(:, n) + dt*s%v(:, n)))/dt_avg
          else
            ! first step (no half step before t^0): the change of the node's kinetic energy
            ! the wall causes, so that a node stopped at once loses 1/2 m v0^2 here too
            s%wall_work = s%wall_work + s%mass(n)*dot_product(s%v(:, n) - s%v_trial(:, n), &
                0.5_wp*(s%v_trial(:, n) + s%v(:, n)))
          end if
        end do
      end associate
    end do
  end subroutine apply_rigid_walls

end module mefem_explicit_rigid
