!> Skew conditions of the explicit analysis (doc/theory.md 6.7): an SPC whose local axis (CID)
!> is not a global axis, and a node motion along a vector (DOF 4 / -4, VID), act on a node's
!> velocity along a unit vector e after the free update and the axis conditions: an SPC removes
!> the component along e; a motion sets it (and with DOF -4 zeroes the normal components), its
!> reaction's work booked as the axis motions' is. The accelerations lose the same components.
!> Each condition is local to its node: the same bits on any number of ranks. An SPC in a
!> moving system (*DEFINE_COORDINATE_NODES FLAG 1) takes its direction from the system's axes
!> at the middle of each step (update_moving_frames: the three nodes' positions summed over
!> the ranks, the frame built from them as at t = 0).
module mefem_explicit_skew
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, ON_NODE, ON_NODE_SET, VAD_VELOCITY, VAD_ACCELERATION
  use mefem_curves, only: curve_value
  use mefem_explicit_state, only: explicit_state_t
  use mefem_explicit_layout, only: explicit_layout_t, explicit_layout_local_node
  use mefem_boundary_conditions, only: target_nodes
  use mefem_vector_math, only: frame_from_vectors
  use mefem_comm, only: comm_sum
  use mefem_errors, only: fatal
  use mefem_strings, only: itoa
  implicit none
  private

  public :: skew_conditions_set_up, apply_skew_conditions, skew_accelerations
  public :: update_moving_frames

contains

  !> The skew conditions of the local nodes: SPCs in a local system (their fixed local axes
  !> that are not global ones; spc%skew) and node motions along a vector (DOF 4, -4). An SPC's
  !> directions are made orthonormal at each node to the global dofs fixed there at t = 0 and
  !> to the node's earlier SPC directions, so that projecting them out one after the other
  !> leaves every condition met (a direction that the others already hold is dropped).
  subroutine skew_conditions_set_up(model, layout, fixed_global, n_mesh_nodes, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_layout_t), intent(in) :: layout     !< local numbering
    logical, intent(in) :: fixed_global(:,:)          !< (dim, n_mesh_nodes) fixed at t = 0
    integer, intent(in) :: n_mesh_nodes               !< mesh nodes
    type(explicit_state_t), intent(inout) :: s        !< local state
    !> length below which an orthogonalised direction is held by the others already
    real(wp), parameter :: DEPENDENT = 1.0e-8_wp
    integer, allocatable :: nodes(:)
    integer, allocatable :: latest(:), earlier(:)    !< per node, its SPC entries (a list)
    real(wp) :: e(3)
    integer :: pass, k, i, j, m, l, g, n_entries
    do pass = 1, 2                         ! count, then fill
      n_entries = 0
      do k = 1, model%n_spcs
        associate (spc => model%spcs(k))
          if (spc%n_skew == 0 .or. spc%target <= 0) cycle
          call target_nodes(model, spc%target_kind, spc%target, nodes)
          do i = 1, size(nodes)
            l = explicit_layout_local_node(layout, nodes(i))
            if (l == 0) cycle
            do j = 1, spc%n_skew
              if (pass == 1) then
                n_entries = n_entries + 1
                cycle
              end if
              e = spc%skew(:, j)
              g = nodes(i)
              do m = 1, s%dim                ! against the global dofs fixed there
                if (g <= n_mesh_nodes) then
                  if (fixed_global(m, g)) e(m) = 0.0_wp
                end if
              end do
              m = latest(l)                  ! against the node's earlier directions
              do while (m > 0)
                e = e - dot_product(e, s%skew_dir(:, m))*s%skew_dir(:, m)
                m = earlier(m)
              end do
              if (norm2(e) < DEPENDENT) cycle
              n_entries = n_entries + 1
              earlier(n_entries) = latest(l)
              latest(l) = n_entries
              s%skew_node(n_entries) = l
              s%skew_source(n_entries) = -k
              s%skew_dir(:, n_entries) = e/norm2(e)
              s%skew_whole(n_entries) = .false.
              s%skew_system(n_entries) = spc%moving_system
              s%skew_axis(n_entries) = spc%skew_axis(j)
            end do
          end do
        end associate
      end do
      do k = 1, model%n_motions
        associate (pm => model%motions(k))
          if (pm%target_kind /= ON_NODE .and. pm%target_kind /= ON_NODE_SET) cycle
          if (abs(pm%dof) /= 4) cycle
          call target_nodes(model, pm%target_kind, pm%target, nodes)
          do i = 1, size(nodes)
            l = explicit_layout_local_node(layout, nodes(i))
            if (l == 0) cycle
            n_entries = n_entries + 1
            if (pass == 1) cycle
            s%skew_node(n_entries) = l
            s%skew_source(n_entries) = k
            s%skew_dir(:, n_entries) = pm%direction
            s%skew_whole(n_entries) = pm%dof < 0
            s%skew_system(n_entries) = 0
            s%skew_axis(n_entries) = 0
          end do
        end associate
      end do
      if (pass == 1) then
        allocate(s%skew_node(n_entries), s%skew_source(n_entries), &
                 s%skew_dir(3, n_entries), s%skew_whole(n_entries), &
                 s%skew_system(n_entries), s%skew_axis(n_entries))
        allocate(latest(s%nnode), earlier(n_entries))
        latest = 0
      end if
    end do
    s%nskew = n_entries
    s%skew_node = s%skew_node(1:n_entries)
    s%skew_source = s%skew_source(1:n_entries)
    s%skew_dir = s%skew_dir(:, 1:n_entries)
    s%skew_whole = s%skew_whole(1:n_entries)
    s%skew_system = s%skew_system(1:n_entries)
    s%skew_axis = s%skew_axis(1:n_entries)
    allocate(s%skew_v_old(s%dim, n_entries))
    ! the moving systems of the model's SPCs (from the model: the same list on every rank)
    block
      logical :: used(model%n_systems)
      used = .false.
      do k = 1, model%n_spcs
        if (model%spcs(k)%moving_system > 0 .and. model%spcs(k)%n_skew > 0) &
          used(model%spcs(k)%moving_system) = .true.
      end do
      s%moving_system = pack([(k, k = 1, model%n_systems)], used)
      s%n_moving = size(s%moving_system)
      allocate(s%moving_local(3, s%n_moving), s%moving_x(3, 3*s%n_moving))
      s%moving_first_axis = model%systems(s%moving_system)%first_axis
      do k = 1, s%n_moving
        do j = 1, 3
          s%moving_local(j, k) = explicit_layout_local_node(layout, &
                                     model%systems(s%moving_system(k))%nodes(j))
        end do
      end do
    end block
  end subroutine skew_conditions_set_up

  !> The directions of the SPCs in moving systems from the systems' axes at x0 + u + ahead v
  !> (the velocity update: ahead = dt/2 with the free v^{n+1/2}, so that the condition holds
  !> at the middle of the step, second order; t = 0: ahead = 0): N1 N2 N3's positions (their
  !> owners fill, one sum over the ranks), the frame built from them
  !> as at t = 0 (N1 N2 the first axis, N1 N3 in its plane with the next), then each
  !> direction made orthogonal to the global dofs fixed at its node and to the node's earlier
  !> conditions, as at set-up (a direction they hold already is left out: zero). Collective
  !> (every rank has the same n_moving). A frame that degenerates stops the run.
  subroutine update_moving_frames(model, s, ahead)
    type(model_t), intent(in) :: model                !< resolved model (messages)
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: ahead                     !< time ahead of x0 + u along v
    !> length below which an orthogonalised direction is held by the others already
    real(wp), parameter :: DEPENDENT = 1.0e-8_wp
    real(wp) :: axes(3, 3, s%n_moving), e(3)
    integer :: k, j, l, m, d
    logical :: ok
    integer, allocatable :: latest(:)
    d = s%dim
    if (.not. allocated(s%skew_earlier)) then       ! (after the set-up's last changes)
      allocate(s%skew_earlier(s%nskew), latest(s%nnode))
      latest = 0
      do k = 1, s%nskew
        s%skew_earlier(k) = latest(s%skew_node(k))
        latest(s%skew_node(k)) = k
      end do
    end if
    s%moving_x = 0.0_wp
    do k = 1, s%n_moving
      do j = 1, 3
        l = s%moving_local(j, k)
        if (l == 0) cycle
        if (s%owned(l)) s%moving_x(1:d, 3*(k - 1) + j) = s%x0(:, l) + s%u(:, l) + ahead*s%v(:, l)
      end do
    end do
    call comm_sum(s%moving_x)
    do k = 1, s%n_moving
      axes(:, :, k) = 0.0_wp
      associate (p => s%moving_x(:, 3*k - 2:3*k))
        call frame_from_vectors(s%moving_first_axis(k), p(:, 2) - p(:, 1), p(:, 3) - p(:, 1), &
                                axes(:, :, k), ok)
      end associate
      if (.not. ok) call fatal('explicit: coordinate system '// &
          itoa(model%systems(s%moving_system(k))%id)//' (FLAG 1, moving with its nodes): '// &
          'nodes N1 N2 N3 no longer define a frame (two coincide or all three are in line)')
    end do
    do k = 1, s%nskew
      if (s%skew_system(k) == 0) cycle
      m = findloc(s%moving_system, s%skew_system(k), dim=1)
      e = axes(:, s%skew_axis(k), m)
      l = s%skew_node(k)
      do j = 1, d
        if (s%fixed(j, l)) e(j) = 0.0_wp
      end do
      j = s%skew_earlier(k)
      do while (j > 0)
        e(1:d) = e(1:d) - dot_product(e(1:d), s%skew_dir(1:d, j))*s%skew_dir(1:d, j)
        j = s%skew_earlier(j)
      end do
      if (norm2(e(1:d)) < DEPENDENT) then
        s%skew_dir(:, k) = 0.0_wp
      else
        s%skew_dir(1:d, k) = e(1:d)/norm2(e(1:d))
      end if
    end do
  end subroutine update_moving_frames

  !> Accelerations a^{n+1} along the active skew conditions are zero (the reaction cancels
  !> them, as at fixed and driven dofs): the component along e removed, the whole with DOF -4.
  subroutine skew_accelerations(model, s, t)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< t^{n+1}
    real(wp) :: e(3)
    integer :: k, n, d
    d = s%dim
    do k = 1, s%nskew
      n = s%skew_node(k)
      if (s%skew_source(k) < 0) then
        associate (spc => model%spcs(-s%skew_source(k)))
          if (t < spc%birth .or. t > spc%death) cycle
        end associate
      else
        associate (pm => model%motions(s%skew_source(k)))
          if (t < pm%birth .or. t > pm%death) cycle
        end associate
        if (s%skew_whole(k)) then
          s%a(:, n) = 0.0_wp
          cycle
        end if
      end if
      e(1:d) = s%skew_dir(1:d, k)
      s%a(:, n) = s%a(:, n) - dot_product(s%a(:, n), e(1:d))*e(1:d)
    end do
  end subroutine skew_accelerations

  !> The skew conditions on v^{n+1/2} (after the free update and the axis motions): an
  !> active SPC direction e removes the component (v.e) e; a motion along e sets the
  !> component to its velocity (VAD 0: the curve at t^{n+1/2}; 1: v^{n-1/2}.e + dt_avg a(t^n);
  !> 2: (d(t^{n+1}) - u^n.e)/dt), with DOF -4 the whole velocity. The reaction of a motion,
  !> m (v - v_old)/dt_avg - f (its component along e; the whole with DOF -4), works over the
  !> half steps around t^n (owned nodes) as the axis motions' reactions do.
  subroutine apply_skew_conditions(model, s, t, dt_old, dt, work)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< t^n
    real(wp), intent(in) :: dt_old, dt                !< dt^{n-1/2}, dt^{n+1/2}
    real(wp), intent(inout) :: work                   !< the reactions' work, added to
    real(wp) :: e(3), reaction(3), amount, dt_avg
    integer :: k, n, d
    d = s%dim
    dt_avg = 0.5_wp*(dt_old + dt)
    do k = 1, s%nskew
      n = s%skew_node(k)
      if (.not. s%active(n)) cycle
      e(1:d) = s%skew_dir(1:d, k)
      if (s%skew_source(k) < 0) then
        associate (spc => model%spcs(-s%skew_source(k)))
          if (t + dt < spc%birth .or. t + dt > spc%death) cycle
        end associate
        s%v(:, n) = s%v(:, n) - dot_product(s%v(:, n), e(1:d))*e(1:d)
        cycle
      end if
      associate (pm => model%motions(s%skew_source(k)))
        if (t + dt < pm%birth .or. t > pm%death) cycle
        select case (pm%vad)
        case (VAD_VELOCITY)
          amount = pm%scale*curve_value(model%curves(pm%curve), t + 0.5_wp*dt)
        case (VAD_ACCELERATION)
          amount = dot_product(s%skew_v_old(:, k), e(1:d)) + &
                   dt_avg*pm%scale*curve_value(model%curves(pm%curve), t)
        case default
          amount = (pm%scale*curve_value(model%curves(pm%curve), t + dt) - &
                    dot_product(s%u(:, n), e(1:d)))/dt
        end select
      end associate
      if (s%skew_whole(k)) then
        s%v(:, n) = amount*e(1:d)
      else
        s%v(:, n) = s%v(:, n) + (amount - dot_product(s%v(:, n), e(1:d)))*e(1:d)
      end if
      ! the reaction m (v - v_old)/dt_avg - (f_ext + f_con - f_int) (a^n is zero along the
      ! condition, as at driven dofs)
      if (s%owned(n) .and. dt_avg > 0.0_wp) then
        reaction(1:d) = s%mass(n)*(s%v(:, n) - s%skew_v_old(:, k))/dt_avg - s%f_ext(:, n) - &
                        s%f_con(:, n) + s%f_int(:, n)
        if (.not. s%skew_whole(k)) reaction(1:d) = dot_product(reaction(1:d), e(1:d))*e(1:d)
        work = work + dot_product(reaction(1:d), 0.5_wp*(dt_old*s%skew_v_old(:, k) + &
                                                         dt*s%v(:, n)))
      end if
    end do
  end subroutine apply_skew_conditions

end module mefem_explicit_skew
