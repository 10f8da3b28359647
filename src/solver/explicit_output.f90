!> Output of the explicit analysis: what is due when (the schedule of result states and ASCII
!> histories, write_outputs), the result states (displacement, velocity, acceleration, stresses
!> and the fields of contact and erosion) and the histories glstat, rwforc, rcforc, rbdout and
!> nodout (mefem_history_output writes their files). The sums they need run over owned nodes
!> and cells and are combined over the ranks here; rank 0 writes the files.
module mefem_explicit_output
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_sum, comm_min, comm_wtime
  use mefem_errors, only: status_t
  use mefem_strings, only: itoa
  use mefem_model, only: model_t, MAT_RIGID, RIGID_NODAL
  use mefem_decomposition, only: decomposition_t
  use mefem_explicit_layout, only: explicit_layout_t, explicit_layout_local_node
  use mefem_halo, only: halo_gather_cell_results
  use mefem_cells, only: cells_t, CELL_MAX_NODES
  use mefem_material_state, only: NHIST, HIST_ALPHA
  use mefem_material_update, only: material_update
  use mefem_cell_finite_strain, only: cell_deformation_gradient, inverse_3x3
  use mefem_explicit_cell_forces, only: block_cell_data, volume_scale
  use mefem_output_mesh, only: output_field_t
  use mefem_results, only: results_write_state, results_directory, append_node_set_fields
  use mefem_solver_common, only: cell_result_fields, schedule_after, title_or_default, &
                                 first_dump_time
  use mefem_history_output, only: glstat_record_t, glstat_open, glstat_write, glstat_close, &
                                  glstat_total_energy, glstat_energy_ratio, nodout_open, &
                                  nodout_write, nodout_close, rbdout_open, rbdout_write, &
                                  rbdout_close, rcforc_open, rcforc_write, rcforc_close, &
                                  rwforc_open, rwforc_write, rwforc_close
  use mefem_rigid_walls, only: rigid_wall_normal
  use mefem_rigid_bodies, only: rigid_bodies_kinetic_energy
  use mefem_explicit_state, only: explicit_state_t
  implicit none
  private

  public :: write_outputs, open_histories, close_histories, step_controlled_by, &
            explicit_analysis, explicit_writes_initial_state

  !> Output schedule and counters.
  type, public :: schedule_t
    real(wp) :: plot_interval = 0.0_wp, next_plot = 0.0_wp
    real(wp) :: glstat_interval = 0.0_wp, next_glstat = 0.0_wp
    real(wp) :: nodout_interval = 0.0_wp, next_nodout = 0.0_wp
    real(wp) :: rcforc_interval = 0.0_wp, next_rcforc = 0.0_wp
    real(wp) :: last_plot = -1.0_wp, last_glstat = -1.0_wp, last_nodout = -1.0_wp
    real(wp) :: last_rcforc = -1.0_wp
    real(wp) :: next_dump = huge(1.0_wp)       !< next restart file by time (D3DUMP NPLTC)
    integer :: plot_state = 0                  !< next output state number (0: t = 0)
    real(wp) :: initial_energy = 0.0_wp        !< total energy at t = 0
    logical :: have_initial_energy = .false.
  end type schedule_t

contains

  !> Write what is due at time t: result states (d3plot interval), glstat, nodout.
  !> final = .true. writes all of them whatever the schedule (end of run, failure).
  subroutine write_outputs(model, decomp, cells, layout, s, schedule, cycle, t, dt, final, seconds)
    type(model_t), intent(in) :: model                !< resolved model
    type(decomposition_t), intent(in) :: decomp       !< this rank's output piece
    type(cells_t), intent(in) :: cells                !< the cells of the output piece, in the
                                                      !< order of layout%result_cell
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(explicit_state_t), intent(in) :: s           !< local state
    type(schedule_t), intent(inout) :: schedule       !< what is due when
    integer, intent(in) :: cycle                      !< cycle just completed
    real(wp), intent(in) :: t                         !< time reached
    real(wp), intent(in) :: dt                        !< the step that reached it
    logical, intent(in) :: final                      !< write everything now
    real(wp), intent(inout) :: seconds                !< wall time spent in the output, summed
    real(wp) :: clock, dt_velocity
    logical :: plot
    clock = comm_wtime()
    plot = due(schedule%plot_interval, schedule%next_plot, schedule%last_plot, t, final)
    if (final .and. t /= schedule%last_plot) then       ! the last state, whatever the interval
      plot = .true.
      schedule%last_plot = t
    end if
    ! the velocities of the output are v^{n+1/2} + dt/2 a^{n+1}; before the first cycle v holds
    ! v^0 itself (the initial velocity), so nothing is added then (a load at t = 0, e.g.
    ! gravity, would otherwise show a velocity and kinetic energy at t = 0)
    dt_velocity = merge(0.0_wp, dt, cycle == 0)
    if (plot) then
      call write_state(model, decomp, cells, layout, s, schedule%plot_state, t, dt_velocity)
      schedule%plot_state = schedule%plot_state + 1
    end if
    if (due(schedule%glstat_interval, schedule%next_glstat, schedule%last_glstat, t, final)) &
        then
      call write_glstat(model, s, schedule, cycle, t, dt)
      if (s%nwall > 0) call write_rwforc(model, s, t)
      if (s%bodies%n > 0) call write_rbdout(s, t)
    end if
    if (due(schedule%rcforc_interval, schedule%next_rcforc, schedule%last_rcforc, t, final)) &
      call write_rcforc(s, t)
    if (due(schedule%nodout_interval, schedule%next_nodout, schedule%last_nodout, t, final)) &
      call write_nodout(model, layout, s, cycle, t, dt_velocity)
    seconds = seconds + (comm_wtime() - clock)
  end subroutine write_outputs

  !> Is an output of this interval due at time t? Advances its next time; never writes the
  !> same time twice.
  logical function due(interval, next, last, t, final)
    real(wp), intent(in) :: interval                  !< output interval (<= 0: never)
    real(wp), intent(inout) :: next                   !< next time it is due
    real(wp), intent(inout) :: last                   !< time last written
    real(wp), intent(in) :: t                         !< time reached
    logical, intent(in) :: final                      !< write now whatever the schedule
    due = .false.
    if (interval <= 0.0_wp .or. t == last) return
    if (final .or. t >= next - 1.0e-9_wp*interval) then
      due = .true.
      last = t
      next = schedule_after(next, interval, t)
    end if
  end function due

  !> One result state: displacement and velocity at the nodes; stress, pressure, von Mises
  !> and plastic strain at nodes and elements (each rank evaluates its cells; the output
  !> piece's means read the cells the layout's output plan gathers); state 0 (t = 0) also
  !> carries the node sets, as the model-only state 0 of the other analyses does.
  subroutine write_state(model, decomp, cells, layout, s, state, t, dt)
    type(model_t), intent(in) :: model                !< resolved model
    type(decomposition_t), intent(in) :: decomp       !< this rank's output piece
    type(cells_t), intent(in) :: cells                !< the cells of the output piece, in the
                                                      !< order of layout%result_cell
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(explicit_state_t), intent(in) :: s           !< local state
    integer, intent(in) :: state                      !< output state number
    real(wp), intent(in) :: t, dt                     !< time, the step that reached it (0
                                                      !< before the first cycle)
    type(output_field_t), allocatable :: point_fields(:)
    type(output_field_t) :: cell_fields(4)
    real(wp), allocatable :: results(:,:), gathered(:,:)
    real(wp) :: ue(3, CELL_MAX_NODES), f(3, 3), tau(3, 3), scratch(NHIST), sound, finv(3, 3), det
    real(wp) :: grad(3, CELL_MAX_NODES), w0(3, 3), hist(NHIST), fbar(3, 3), mean
    type(status_t) :: status
    integer :: l, nn, k, local
    logical :: averaged
    allocate(results(7, s%ncell))            ! Cauchy stress (Voigt), equivalent plastic strain
    results = 0.0_wp
    do l = 1, s%ncell
      nn = s%nnodes(l)
      ue(1:s%dim, 1:nn) = s%u(:, s%nodes(1:nn, l))
      if (s%nblock > 0) then
        call block_cell_data(s, l, grad, w0, hist)
        call cell_deformation_gradient(s%dim, nn, grad, ue(1:s%dim, 1:nn), f)
      else
        hist = s%hist(:, l)
        call cell_deformation_gradient(s%dim, nn, s%grad(:, :, l), ue(1:s%dim, 1:nn), f)
      end if
      if (hist(HIST_ALPHA) < 0.0_wp) then       ! eroded: no stress, its plastic strain
        results(7, l) = -hist(HIST_ALPHA)
        cycle
      end if
      ! the history is this F's already: re-evaluating returns the committed stress
      averaged = s%nodal_pressure
      if (averaged) averaged = s%np_cell(l)
      if (averaged) then
        ! ELFORM 13: the material's deviatoric stress at Fbar with the forces' pressure
        call inverse_3x3(f, finv, det)
        fbar = f*volume_scale(s%np_jbar(l), det)
        call material_update(model%materials(s%material(l)), model%curves, fbar, hist, &
                             scratch, tau, sound_speed=sound, status=status, committed=.true., &
                             spall=.true.)
        if (.not. status%ok) cycle
        mean = (tau(1, 1) + tau(2, 2) + tau(3, 3))/3.0_wp
        do k = 1, 3
          tau(k, k) = tau(k, k) - mean + det*s%np_force_pressure(l)
        end do
      else
        call material_update(model%materials(s%material(l)), model%curves, f, hist, &
                             scratch, tau, sound_speed=sound, status=status, committed=.true., &
                             spall=.true.)
        if (.not. status%ok) cycle
        call inverse_3x3(f, finv, det)
      end if
      results(1:6, l) = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), tau(3, 1)]/det
      results(7, l) = hist(HIST_ALPHA)
    end do
    call halo_gather_cell_results(layout, results, gathered)
    allocate(point_fields(merge(8, 6, s%contact%n > 0)))
    do k = 1, 2
      point_fields(k)%ncomp = 3
      allocate(point_fields(k)%values(3, decomp%nnode_local))
      point_fields(k)%values = 0.0_wp
    end do
    point_fields(1)%name = 'displacement'
    point_fields(2)%name = 'velocity'
    do k = 1, decomp%nnode_local
      local = explicit_layout_local_node(layout, decomp%node_global(k))
      if (local == 0) cycle
      point_fields(1)%values(1:s%dim, k) = s%u(:, local)
      point_fields(2)%values(1:s%dim, k) = s%v(:, local) + 0.5_wp*dt*s%a(:, local)
    end do
    call cell_result_fields(model, decomp, cells, gathered(1:6, :), gathered(7, :), &
                            point_fields(3:6), cell_fields)
    if (s%contact%n > 0) then             ! contact data are replicated: any rank fills any node
      point_fields(7)%name = 'contact_pressure'
      point_fields(8)%name = 'contact_gap'
      do k = 7, 8
        allocate(point_fields(k)%values(1, decomp%nnode_local))
        point_fields(k)%values = 0.0_wp
      end do
      do k = 1, decomp%nnode_local
        local = s%contact%node_index(decomp%node_global(k))
        if (local == 0) cycle
        point_fields(7)%values(1, k) = s%contact%pressure(local)
        point_fields(8)%values(1, k) = s%contact%gap(local)
      end do
    end if
    if (state == 0) call append_node_set_fields(model, decomp, point_fields)   ! state 0: the node sets
    call results_write_state(state, t, point_fields, cell_fields)
  end subroutine write_state

  !> One glstat record: energies summed over ranks, the added mass, the centre-of-mass
  !> velocity and the element that controls the time step.
  subroutine write_glstat(model, s, schedule, cycle, t, dt)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(in) :: s           !< local state
    type(schedule_t), intent(inout) :: schedule       !< holds the initial energy
    integer, intent(in) :: cycle                      !< cycle just completed
    real(wp), intent(in) :: t, dt                     !< time, the step that reached it
    type(glstat_record_t) :: rec
    real(wp) :: sums(13), v_full(3)
    integer :: n, b
    sums = 0.0_wp
    do n = 1, s%nnode
      if (.not. s%owned(n)) cycle
      if (.not. s%active(n)) cycle          ! rigid-body nodes: their body counts
      v_full = 0.0_wp
      v_full(1:s%dim) = s%v(:, n) + merge(0.0_wp, 0.5_wp*dt, cycle == 0)*s%a(:, n)
      sums(1) = sums(1) + 0.5_wp*s%mass(n)*dot_product(v_full, v_full)
      if (s%bubble(n)) cycle                ! a bubble's inertia is no translational mass
      sums(4) = sums(4) + s%mass(n) - s%physical_mass(n)
      sums(5) = sums(5) + s%physical_mass(n)
      sums(6:8) = sums(6:8) + s%mass(n)*v_full
      sums(9) = sums(9) + s%mass(n)
    end do
    sums(2) = s%internal_energy
    sums(3) = s%external_work + pending_reaction_work(s, dt)
    sums(10) = 0.0_wp - s%wall_work                ! (+0, not -0, without walls)
    sums(11) = s%contact_energy
    sums(12) = s%hourglass_stored + s%hourglass_dissipated
    sums(13) = s%eroded_energy
    call comm_sum(sums)
    do b = 1, s%bodies%n                    ! replicated: added once, after the sum
      associate (body => s%bodies%body(b))
        sums(6:8) = sums(6:8) + body%mass*body%velocity
        sums(9) = sums(9) + body%mass
        ! booked reaction work, and the half not booked yet (as pending_reaction_work: the
        ! static part -F of the reaction on the constrained components; the body load is left
        ! out: its work is booked to the half step, as the reaction's)
        sums(3) = sums(3) + body%reaction_work - 0.5_wp*dt*dot_product(merge(s%body_force(:, b) &
            - s%body_load(:, b), 0.0_wp, body%reaction_force /= 0.0_wp), body%velocity)
      end associate
    end do
    sums(3) = sums(3) + s%body_load_work
    sums(1) = sums(1) + rigid_bodies_kinetic_energy(s%bodies)
    rec%cycle = cycle
    rec%time = t
    rec%time_step = dt
    rec%kinetic_energy = sums(1)
    ! the work of the internal forces holds the hourglass forces' (their energy apart) and
    ! the eroded elements' (their energy apart, as LS-DYNA's glstat has it)
    rec%eroded_internal_energy = sums(13)
    rec%internal_energy = sums(2) - sums(12) - sums(13)
    rec%hourglass_energy = sums(12)
    rec%external_work = sums(3)
    rec%rigidwall_energy = sums(10)
    rec%contact_energy = sums(11)
    rec%added_mass = sums(4)
    rec%percent_mass_increase = 100.0_wp*sums(4)/max(sums(5), tiny(1.0_wp))
    rec%global_velocity = sums(6:8)/max(sums(9), tiny(1.0_wp))
    rec%total_energy = glstat_total_energy(rec)
    if (.not. schedule%have_initial_energy) then
      schedule%initial_energy = rec%total_energy
      schedule%have_initial_energy = .true.
    end if
    rec%energy_ratio = glstat_energy_ratio(rec%total_energy, schedule%initial_energy, &
                                           rec%external_work)
    rec%energy_ratio_uneroded = glstat_energy_ratio(rec%total_energy + &
        rec%eroded_internal_energy, schedule%initial_energy, rec%external_work)
    rec%controlled_by = step_controlled_by(model, s)
    call glstat_write(rec)
  end subroutine write_glstat

  !> The element that sets the stable step, as glstat names it ("solid 484 of part 1"): the
  !> lowest element id among the ranks whose minimum is the global one (collective).
  function step_controlled_by(model, s) result(text)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(in) :: s           !< local state
    character(len=:), allocatable :: text
    real(wp) :: dt_min
    integer :: element, part, my_element
    dt_min = s%dt_stable
    call comm_min(dt_min)
    my_element = huge(1)
    part = huge(1)
    if (s%dt_element > 0) then
      if (s%dt_stable == dt_min) my_element = model%elements%id(s%dt_element)
    end if
    element = my_element
    call comm_min(element)
    if (my_element == element .and. element /= huge(1)) &
      part = model%parts(model%elements%part(s%dt_element))%id
    call comm_min(part)
    if (element == huge(1)) then
      text = 'no element (rigid parts only: DTINIT or LCTM)'
    else
      text = trim(element_kind(s%dim))//' '//itoa(element)//' of part '//itoa(part)
    end if
  end function step_controlled_by

  !> The part of the prescribed-motion reactions' work not booked yet at an output time:
  !> update_velocities books r^n . (du^{n-1/2} + du^{n+1/2})/2 when v^{n+1/2} is known, so at
  !> t^n the half r^n . du^{n-1/2}/2 is missing while the internal energy already holds
  !> f_int^n . du^{n-1/2}/2. It is estimated with the static part of the reaction,
  !> f_int - f_ext (the inertial part is of higher order), so the balance stays O(dt^2).
  real(wp) function pending_reaction_work(s, dt) result(work)
    type(explicit_state_t), intent(in) :: s           !< local state, forces at t^n
    real(wp), intent(in) :: dt                        !< the step that reached t^n
    integer :: k, n, i
    work = 0.0_wp
    do k = 1, s%nprescribed
      n = s%prescribed_node(k)
      i = s%prescribed_dof(k)
      if (s%owned(n) .and. s%driven(i, n)) work = work + (s%f_int(i, n) - s%f_ext(i, n) - &
          s%f_con(i, n))*0.5_wp*dt*s%v(i, n)
    end do
  end function pending_reaction_work

  !> Rigid wall forces (rwforc, at the glstat interval): each wall's force from the last
  !> cycle summed over ranks, and its normal component.
  subroutine write_rwforc(model, s, t)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(in) :: s           !< local state
    real(wp), intent(in) :: t                         !< time
    real(wp) :: force(3, s%nwall), normal(s%nwall)
    integer :: k
    force = s%wall_force
    call comm_sum(force)
    do k = 1, s%nwall
      normal(k) = dot_product(force(:, k), rigid_wall_normal(model%rigid_walls(k), s%dim))
    end do
    call rwforc_write(t, model%rigid_walls(1:s%nwall)%id, normal, force)
  end subroutine write_rwforc

  !> Contact resultants (rcforc, at *DATABASE_RCFORC DT): per interface the forces on the
  !> slave and master sides (replicated data: rank 0 writes) and their normal and tangential
  !> magnitudes.
  subroutine write_rcforc(s, t)
    type(explicit_state_t), intent(in) :: s           !< local state
    real(wp), intent(in) :: t                         !< time
    real(wp) :: force(3)
    integer :: k, i
    do k = 1, s%contact%n
      associate (it => s%contact%interfaces(k))
        call rcforc_write(t, it%id, it%force_slave, it%force_master, it%normal_force, &
                          it%tangential_force)
      end associate
    end do
    ! force transducers: the contact forces on their nodes, summed in ascending node order
    ! (the forces are the same on every rank), as the slave side; master, normal and
    ! tangential zero
    do k = 1, size(s%transducer_id)
      force = 0.0_wp
      do i = 1, size(s%transducer_nodes(k)%nodes)
        force = force + s%contact%force(:, s%transducer_nodes(k)%nodes(i))
      end do
      call rcforc_write(t, s%transducer_id(k), force, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, 0.0_wp)
    end do
  end subroutine write_rcforc

  !> Rigid-body histories (rbdout, at the glstat interval): centre displacement and velocity,
  !> reaction force and moment of every body (replicated data: rank 0 writes).
  subroutine write_rbdout(s, t)
    type(explicit_state_t), intent(in) :: s           !< local state
    real(wp), intent(in) :: t                         !< time
    real(wp) :: values(12, s%bodies%n)
    integer :: ids(s%bodies%n), b
    do b = 1, s%bodies%n
      associate (body => s%bodies%body(b))
        ids(b) = body%id
        values(:, b) = [body%centre - body%centre0, body%velocity, body%reaction_force, &
                        body%reaction_moment]
      end associate
    end do
    call rbdout_write(t, ids, values)
  end subroutine write_rbdout

  !> Element keyword word of glstat's "controlled by" line.
  pure function element_kind(dim) result(word)
    integer, intent(in) :: dim          !< 2 or 3
    character(len=8) :: word
    word = 'solid'
    if (dim == 2) word = 'shell'
  end function element_kind

  !> One nodout block: the owner of each history node fills its row, summed over ranks.
  subroutine write_nodout(model, layout, s, cycle, t, dt)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(explicit_state_t), intent(in) :: s           !< local state
    integer, intent(in) :: cycle                      !< cycle just completed
    real(wp), intent(in) :: t, dt                     !< time, the step that reached it (0
                                                      !< before the first cycle)
    integer, allocatable :: nodes(:)
    real(wp), allocatable :: rows(:,:)
    integer :: k, l, d
    call history_nodes(model, nodes)
    allocate(rows(12, size(nodes)))            ! displacement, velocity, acceleration, position
    rows = 0.0_wp
    d = s%dim
    do k = 1, size(nodes)
      l = explicit_layout_local_node(layout, nodes(k))
      if (l == 0) cycle
      if (.not. s%owned(l)) cycle
      rows(1:d, k) = s%u(:, l)
      rows(4:3+d, k) = s%v(:, l) + 0.5_wp*dt*s%a(:, l)
      rows(7:6+d, k) = s%a(:, l)
      rows(10:9+d, k) = s%x0(:, l) + s%u(:, l)
    end do
    call comm_sum(rows)
    call nodout_write(cycle, t, rows(1:3, :), rows(4:6, :), rows(7:9, :), rows(10:12, :))
  end subroutine write_nodout

  !> Global indices of the history nodes: *DATABASE_HISTORY_NODE, then _SET members.
  subroutine history_nodes(model, nodes)
    type(model_t), intent(in) :: model                !< resolved model
    integer, allocatable, intent(out) :: nodes(:)     !< node indices in output order
    integer :: k
    nodes = model%controls%history_nodes(1:model%controls%n_history_nodes)
    do k = 1, model%controls%n_history_sets
      nodes = [nodes, pack(model%sets(model%controls%history_sets(k))%members, &
                           model%sets(model%controls%history_sets(k))%members > 0)]
    end do
  end subroutine history_nodes

  !> Open glstat and nodout when the deck asks for them; set the output schedule.
  !> With resume (a restart), the next times and the state counter the restart file gave
  !> stay, and the files are continued.
  subroutine open_histories(model, schedule, resume)
    type(model_t), intent(in) :: model                !< resolved model
    type(schedule_t), intent(inout) :: schedule       !< what is due when
    logical, intent(in), optional :: resume           !< continue after a restart
    integer, allocatable :: nodes(:)
    character(len=:), allocatable :: dir, title
    logical :: continuing
    continuing = .false.
    if (present(resume)) continuing = resume
    dir = results_directory()
    title = title_or_default(model%controls%title)
    schedule%plot_interval = model%controls%plot_interval
    if (model%controls%plot_count > 0) schedule%plot_interval = model%controls%end_time/ &
        real(model%controls%plot_count, wp)
    schedule%glstat_interval = model%controls%glstat_interval
    schedule%rcforc_interval = 0.0_wp
    if (model%n_contacts + model%n_transducers > 0) &
      schedule%rcforc_interval = model%controls%rcforc_interval
    call history_nodes(model, nodes)
    schedule%nodout_interval = 0.0_wp
    if (size(nodes) > 0) schedule%nodout_interval = model%controls%nodout_interval
    if (.not. continuing) then
      schedule%next_plot = 0.0_wp                     ! state 0 at t = 0, then every interval
      ! (without an interval the model's state 0 is written before the run, the final state
      ! after it is state 1)
      schedule%plot_state = merge(0, 1, explicit_writes_initial_state(model))
      schedule%next_glstat = 0.0_wp
      schedule%next_rcforc = 0.0_wp
      schedule%next_nodout = 0.0_wp
      schedule%next_dump = first_dump_time(model)
    end if
    if (schedule%glstat_interval > 0.0_wp) call glstat_open(dir, title, continuing)
    if (schedule%glstat_interval > 0.0_wp .and. model%n_rigid_walls > 0) &
      call rwforc_open(dir, title, continuing)
    if (schedule%glstat_interval > 0.0_wp .and. (any(is_rigid_part(model)) .or. &
        any(model%rigid_constraints(1:model%n_rigid_constraints)%kind == RIGID_NODAL))) &
      call rbdout_open(dir, title, continuing)
    if (schedule%rcforc_interval > 0.0_wp) call rcforc_open(dir, title, continuing)
    if (schedule%nodout_interval > 0.0_wp) call nodout_open(dir, model%nodes%id(nodes), &
                                                            title, continuing)
  end subroutine open_histories

  !> Close the history files (no-op where none is open).
  subroutine close_histories()
    call glstat_close()
    call nodout_close()
    call rwforc_close()
    call rbdout_close()
    call rcforc_close()
  end subroutine close_histories

  !> Parts of *MAT_RIGID.
  function is_rigid_part(model) result(mask)
    type(model_t), intent(in) :: model                !< resolved model
    logical :: mask(model%n_parts)
    integer :: p, m
    do p = 1, model%n_parts
      m = model%parts(p)%material
      mask(p) = .false.
      if (m > 0) mask(p) = model%materials(m)%kind == MAT_RIGID
    end do
  end function is_rigid_part


  !> Whether the deck asks for the explicit analysis (not implicit, and a termination).
  logical function explicit_analysis(model)
    type(model_t), intent(in) :: model                !< resolved model
    explicit_analysis = model%controls%imflag /= 1 .and. model%controls%have_termination
  end function explicit_analysis

  !> Whether the explicit analysis of this model writes the output's state 0 (at t = 0, with
  !> its fields and the node sets) itself: when it runs and writes result states at all.
  logical function explicit_writes_initial_state(model)
    type(model_t), intent(in) :: model                !< resolved model
    explicit_writes_initial_state = explicit_analysis(model) .and. &
        (model%controls%plot_interval > 0.0_wp .or. model%controls%plot_count > 0)
  end function explicit_writes_initial_state

end module mefem_explicit_output
