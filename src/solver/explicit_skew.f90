!> Skew conditions of the explicit analysis (doc/theory.md 6.7): an SPC whose local axis (CID)
!> is not a global axis, and a node motion along a vector (DOF 4 / -4, VID), act on a node's
!> velocity along a unit vector e after the free update and the axis conditions: an SPC removes
!> the component along e; a motion sets it (and with DOF -4 zeroes the normal components), its
!> reaction's work booked as the axis motions' is. The accelerations lose the same components.
!> Each condition is local to its node: the same bits on any number of ranks.
module mefem_explicit_skew
  use mefem_kinds, only: wp
  use mefem_model, only: model_t, ON_NODE, ON_NODE_SET, VAD_VELOCITY, VAD_ACCELERATION
  use mefem_curves, only: curve_value
  use mefem_explicit_state, only: explicit_state_t
  use mefem_explicit_layout, only: explicit_layout_t, explicit_layout_local_node
  use mefem_boundary_conditions, only: target_nodes
  implicit none
  private

  public :: skew_conditions_set_up, apply_skew_conditions, skew_accelerations

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
          end do
        end associate
      end do
      if (pass == 1) then
        allocate(s%skew_node(n_entries), s%skew_source(n_entries), &
                 s%skew_dir(3, n_entries), s%skew_whole(n_entries))
        allocate(latest(s%nnode), earlier(n_entries))
        latest = 0
      end if
    end do
    s%nskew = n_entries
    s%skew_node = s%skew_node(1:n_entries)
    s%skew_source = s%skew_source(1:n_entries)
    s%skew_dir = s%skew_dir(:, 1:n_entries)
    s%skew_whole = s%skew_whole(1:n_entries)
    allocate(s%skew_v_old(s%dim, n_entries))
  end subroutine skew_conditions_set_up

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
