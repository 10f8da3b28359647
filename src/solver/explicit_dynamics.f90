!> Explicit dynamics: central difference with lumped mass (seed section 3.2; formulation 2.8,
!> 2.9), domain-decomposed.
!>
!> Cycle n, from t^n to t^{n+1} = t^n + dt^{n+1/2}, with LS-DYNA's half-step velocities:
!>   v^{n+1/2} = v^{n-1/2} + dt_avg a^n,           dt_avg = (dt^{n-1/2} + dt^{n+1/2})/2
!>   essential conditions on v^{n+1/2}: SPC and TC codes (0), prescribed motion
!>     (VAD 0 velocity, 1 acceleration, 2 displacement);
!>   u^{n+1} = u^n + dt^{n+1/2} v^{n+1/2}
!>   f_int^{n+1}: per cell the smoothed F, the material update and f = w P grad, assembled
!>     in ascending global cell order (bit-identical for any number of ranks): the cell loop
!>     of mefem_explicit_cell_forces (3D cells in blocks, structure-of-arrays kernels, with
!>     the pushed assembly); the state it works on is mefem_explicit_state's;
!>   a^{n+1} = (f_ext^{n+1} - f_int^{n+1}) / m
!>   dt^{n+3/2} = TSSFAC min over cells of 2/omega_cell (global minimum), optionally with
!>     mass scaling (DT2MS < 0: mass added only to cells whose step is below TSSFAC |DT2MS|).
!>
!> Parallel layout (mefem_explicit_layout): each rank computes the cells of its own elements
!> (METIS partition) and holds every node they touch; the nodal forces of shared nodes are
!> completed by a halo exchange of the cells' contributions, started after the cell loop (2D:
!> after the outer cells, overlapping the inner ones). Every rank then updates all its local
!> nodes, shared ones included, with identical data, so copies never drift and no second
!> exchange is needed.
!> Reductions: the time step (one per cycle), energies and histories (at output times).
!>
!> Energies (glstat): internal energy by the trapezoidal rule on the nodal forces,
!> E_int += (f_int^n + f_int^{n+1})/2 . du (the same as the cells' stress power, F being
!> linear in u); external work likewise from f_ext and the reactions of prescribed motions;
!> kinetic energy with v^{n+1} = v^{n+1/2} + dt/2 a^{n+1}. Sums run over owned nodes.
!> Body loads (*LOAD_BODY_) are external forces -m a(t) with the physical lumped masses
!> (mefem_body_loads); a rigid body takes -M a(t) at its centre of mass.
module mefem_explicit_dynamics
  use, intrinsic :: iso_fortran_env, only: error_unit
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_sum, comm_min, comm_max, comm_wtime, comm_size, comm_rank, &
                        comm_min_start, &
                        comm_allgatherv_int, comm_min_progress, comm_min_finish
  use mefem_errors, only: status_t, fatal, say, warn
  use mefem_signals, only: signals_install, signal_caught, signal_name, signal_record_stop
  use mefem_strings, only: itoa, rtoa
  use mefem_sense_switch, only: sense_switch, sense_switch_warn_leftover, SENSE_STOP, &
                                SENSE_STATUS, SENSE_STATE, SENSE_RESTART
  use mefem_model, only: model_t, VAD_VELOCITY, VAD_ACCELERATION, VAD_DISPLACEMENT, ON_NODE, &
                         ON_NODE_SET, MAT_RIGID
  use mefem_decomposition, only: decomposition_t
  use mefem_model_partition, only: element_csr
  use mefem_explicit_layout, only: explicit_layout_t, explicit_layout_build, &
                                   explicit_layout_local_node, explicit_layout_release_plan
  use mefem_halo, only: halo_t, halo_build, halo_assemble_finish, halo_assemble, &
                        halo_assembly_share_on_node, halo_free
  use mefem_cells, only: cells_t, cells_build, cells_summary, CELL_MAX_NODES, cell_grad_column, &
                         cells_subset, cells_release_topology
  use mefem_lumped_mass, only: lumped_mass
  use mefem_stable_time_step, only: cell_mass_shares, cell_inverse_mass_metric
  use mefem_material_state, only: NHIST, material_state_init
  use mefem_material_update, only: material_elastic_moduli, material_fails
  use mefem_curves, only: curve_value
  use mefem_boundary_conditions, only: fixed_dofs, external_forces, target_nodes, &
                                       initial_velocities
  use mefem_solver_common, only: warn_output_every_step, restart_files_due
  use mefem_progress, only: progress_start, progress_update, progress_finish
  use mefem_rigid_walls, only: rigid_wall_nodes
  use mefem_rigid_bodies, only: rigid_bodies_build, rigid_bodies_set_velocity, &
                                rigid_body_velocity_fit, rigid_body_point_motion
  use mefem_explicit_rigid, only: move_rigid_bodies, rigid_body_resultants, rigid_body_loads, &
                                  apply_rigid_walls
  use mefem_contact_surfaces, only: contact_surface_t, contact_surface_build, exterior_nodes
  use mefem_mortar_contact, only: mortar_contact_setup, mortar_contact_forces, &
                                  mortar_contact_erode, mortar_contact_set_masses
  use mefem_explicit_ties, only: explicit_ties_set_up, tie_accelerations
  use mefem_explicit_skew, only: skew_conditions_set_up, apply_skew_conditions, &
                                 skew_accelerations, update_moving_frames
  use mefem_explicit_state, only: explicit_state_t, set_to_zero, state_arena_create
  use mefem_explicit_cell_forces, only: explicit_cells_set_up, explicit_cell_loop, &
                                        explicit_mass_split, explicit_blocks_group, &
                                        explicit_steal_set_up, explicit_steal_tear_down, &
                                        nodal_reference_volumes
  use mefem_body_loads, only: body_acceleration, body_load_parts, body_load_nodes, add_body_forces
  use mefem_explicit_output, only: schedule_t, write_outputs, open_histories, close_histories, &
                                   step_controlled_by, explicit_analysis, &
                                   explicit_writes_initial_state
  use mefem_explicit_restart, only: run_point_t, explicit_restart_put, explicit_restart_get
  use mefem_restart_file, only: restart_file_t, restart_create, restart_commit, restart_open, &
                                restart_close, restart_dump_name
  use mefem_results, only: results_directory
  implicit none
  private

  public :: explicit_dynamics_run, explicit_writes_initial_state, explicit_analysis

  integer, parameter :: SENSE_INTERVAL = 100   !< cycles between looks for a d3kil file
  !> what a rank puts into the cycle's minimum of the stable step instead of its step: a cell
  !> failed (wins), a signal was caught (mefem_signals); steps are positive
  real(wp), parameter :: STEP_FAILED = -1.0_wp, STEP_SIGNALLED = -0.5_wp
  !> cycles between two stiffness-weighted mass splits of the step bound (explicit_mass_split:
  !> any split is safe, a fresh one follows the geometry). Measured on the copper Taylor bar
  !> (4 860 ME-FEM tets): the splits take 2 % of the run every 200 cycles, and the run needs
  !> 7 647 cycles (7 636 every 100 cycles, 7 714 every 500)
  integer, parameter :: MASS_SPLIT_INTERVAL = 200

  real(wp), parameter :: SPC_FOREVER = 1.0e20_wp   !< DEATH default of *BOUNDARY_SPC

  !> Wall time spent in the phases of the cycle (for the run summary).
  type :: timing_t
    real(wp) :: forces = 0.0_wp                !< cells: F, material, forces, time step
    real(wp) :: exchange = 0.0_wp              !< halo assembly (waiting and summing)
    real(wp) :: reduction = 0.0_wp             !< the time-step reduction (waits for the
                                               !< slowest rank)
    real(wp) :: update = 0.0_wp                !< nodal update, conditions, energies
    real(wp) :: output = 0.0_wp                !< states and histories
    real(wp) :: contact = 0.0_wp               !< contact: gather, search, mortar, forces
  end type timing_t

contains

  !> Run the explicit analysis from t = 0 to ENDTIM (or ENDCYC cycles).
  !> With restart_path, the run continues from that restart file instead (the results of
  !> the run that wrote it are continued: results_open with resume).
  subroutine explicit_dynamics_run(model, decomp, element_rank, element_chunk, restart_path)
    type(model_t), intent(in) :: model                !< resolved model
    type(decomposition_t), intent(in) :: decomp       !< this rank's output piece
    integer, intent(in) :: element_rank(:)            !< rank of every element
    integer, intent(in) :: element_chunk(:)           !< chunk of every element (assembly)
    character(len=*), intent(in), optional :: restart_path  !< restart file to continue from
    type(cells_t) :: cells, result_cells
    type(explicit_layout_t) :: layout
    type(halo_t) :: halo
    type(explicit_state_t) :: s
    type(schedule_t) :: schedule
    type(timing_t) :: timing
    type(status_t) :: status
    type(restart_file_t) :: restart
    type(run_point_t) :: point
    real(wp) :: t, dt, dt_old, dt_first, end_time, clock, t_start, dt_floor, dt_full
    integer :: cycle, end_cycle, action, signum, dumps, dump_cycle
    logical :: printed, dump_due, runrsf_due

    t_start = comm_wtime()
    call check_supported(model)
    ! every cell is built on every rank, but with its gradients only on the rank that
    ! computes it (that of its first element)
    call cells_build(model, cells, status, wanted=element_rank == comm_rank())
    if (.not. status%ok) call fatal('element set-up: '//status%message)
    call cells_summary(cells)
    call set_up(model, decomp, element_rank, element_chunk, cells, layout, halo, s)
    ! the set-up was the last reader of the global cells: the output keeps the topology of
    ! the cells its piece reads, the rest (per cell, the whole model on every rank) goes
    call cells_subset(cells, layout%result_cell, result_cells)
    call cells_release_topology(cells)
    call say('explicit: '//itoa(layout%nnode_global)//' nodes (with enriched), '// &
             itoa(cells%n)//' cells on '//itoa(comm_size())//' rank(s)')
    call report_chunks(layout, halo, max(-1, maxval(element_chunk)) + 1)

    t = 0.0_wp
    cycle = 0
    dumps = 0
    dump_cycle = -1
    end_time = model%controls%end_time
    end_cycle = model%controls%end_cycle
    if (present(restart_path)) then
      ! the state at the end of the cycle the restart file was written at
      clock = comm_wtime()
      call restart_open(restart, restart_path)
      call explicit_restart_get(restart, model, cells, layout, halo, s, point, schedule)
      call restart_close(restart)
      t = point%t
      cycle = point%cycle
      dt = point%dt
      dt_old = point%dt_old
      dt_first = point%dt_first
      dumps = point%dumps
      dt_floor = model%controls%dt_min_fraction*dt_first
      call open_histories(model, schedule, resume=.true.)
      call say('explicit: restarted from '//restart_path//' at cycle '//itoa(cycle)// &
               ', t = '//rtoa(t)//'; next step '//rtoa(dt)//' s (read in '// &
               rtoa(comm_wtime() - clock)//' s)')
    else
      call initial_state()
    end if
    call progress_start('explicit', end_time, end_cycle)
    call sense_switch_warn_leftover()
    call signals_install()

    do while ((end_time <= 0.0_wp .or. t < end_time*(1.0_wp - 1.0e-12_wp)) .and. &
              (end_cycle <= 0 .or. cycle < end_cycle))
      dt_full = dt                     ! the stable step, before landing on ENDTIM: the contact
                                       ! penalty's limit uses it (a short last step must not
                                       ! stiffen the contact)
      if (end_time > 0.0_wp) dt = min(dt, end_time - t)
      if (s%spc_in_time) call update_fixed_dofs(model, s, t + dt)
      cycle = cycle + 1
      clock = comm_wtime()
      call update_velocities(model, s, t, dt_old, dt)
      if (s%nwall > 0) s%u_old = s%u
      call advance_displacements(s%dim*s%nnode, dt, s%v, s%u)
      if (s%bodies%n > 0) call move_rigid_bodies(model, s, t, dt_old, dt)
      if (s%nwall > 0) call apply_rigid_walls(model, s, t + dt, dt_old, dt)
      if (mod(cycle, MASS_SPLIT_INTERVAL) == 0) call explicit_mass_split(s, halo)
      timing%update = timing%update + (comm_wtime() - clock)
      t = t + dt
      s%dt_step = dt
      call compute_forces(model, s, halo, t, dt_full, timing)
      clock = comm_wtime()
      call energies_and_accelerations(s, dt)
      if (s%nskew > 0) call skew_accelerations(model, s, t)
      if (s%tied%n > 0) call tie_accelerations(s, s%contact%n > 0, t)
      if (s%bodies%n > 0) then
        call rigid_body_resultants(s)
        call rigid_body_loads(model, s, t)
      end if
      timing%update = timing%update + (comm_wtime() - clock)
      dt_old = dt
      clock = comm_wtime()
      call next_time_step(s, dt)
      timing%reduction = timing%reduction + (comm_wtime() - clock)
      if (dt == STEP_SIGNALLED) then                  ! SIGTERM, SIGINT or SIGUSR1 on a rank
        signum = signal_caught()
        call comm_max(signum)
        call signal_record_stop(signum)
        call say('explicit: '//signal_name(signum)//': stopped at cycle '//itoa(cycle)// &
                 ', t = '//rtoa(t)//'; the state reached and a restart file are written')
        dt = s%dt_stable                              ! the step the reduction would have given
        call comm_min(dt)
        call bound_step(model, t, .false., dt)
        if (dt > 0.0_wp) then
          call write_outputs(model, decomp, result_cells, layout, s, schedule, cycle, t, dt_old, &
                             .false., timing%output)
          call write_restart_file(next_dump_name())
        end if
        exit
      end if
      if (s%erosion .and. dt >= huge(1.0_wp) .and. model%controls%dt_init <= 0.0_wp .and. &
          model%controls%lctm_curve == 0) then
        call say('explicit: every deformable element has eroded at cycle '//itoa(cycle)// &
                 ', t = '//rtoa(t)//': nothing is left to bound the time step; the state '// &
                 'reached is written and the run ends')
        exit
      end if
      call bound_step(model, t, .false., dt)
      if (dt < 0.0_wp) call stop_on_failure(model, decomp, result_cells, layout, s, schedule, cycle, &
                                            t, dt_old, timing)
      call write_outputs(model, decomp, result_cells, layout, s, schedule, cycle, t, dt_old, .false., &
                         timing%output)
      call progress_update(cycle, t, dt_old, printed)
      call restart_files_due(model, cycle, t, schedule%next_dump, dump_due, runrsf_due)
      if (dump_due) call write_restart_file(next_dump_name())
      if (runrsf_due) call write_restart_file('runrsf')
      if (mod(cycle, SENSE_INTERVAL) == 0) then        ! LS-DYNA's d3kil file
        action = sense_switch()
        if (iand(action, ior(SENSE_RESTART, SENSE_STOP)) /= 0) &
          call write_restart_file(next_dump_name())
        if (iand(action, SENSE_STATUS) /= 0) call say('explicit: d3kil (sw2): cycle '// &
            itoa(cycle)//', t = '//rtoa(t)//', dt = '//rtoa(dt)//', wall '// &
            rtoa(comm_wtime() - t_start)//' s')
        if (iand(action, SENSE_STATE) /= 0 .and. iand(action, SENSE_STOP) == 0) then
          call write_outputs(model, decomp, result_cells, layout, s, schedule, cycle, t, dt_old, &
                             .true., timing%output)
          call say('explicit: d3kil (sw4): result state written at cycle '//itoa(cycle)// &
                   ', t = '//rtoa(t))
        end if
        if (iand(action, SENSE_STOP) /= 0) then
          call say('explicit: d3kil (sw1): stopped at cycle '//itoa(cycle)//', t = '// &
                   rtoa(t)//'; the state reached and a restart file are written')
          exit
        end if
      end if
      if (dt < dt_floor) then
        call write_outputs(model, decomp, result_cells, layout, s, schedule, cycle, t, dt_old, .true., &
                           timing%output)
        call close_histories()
        call fatal('explicit: the time step '//rtoa(dt)//' fell below DTMIN x the initial '// &
                   'step = '//rtoa(dt_floor)//' at cycle '//itoa(cycle)//', t = '//rtoa(t)// &
                   ' (the step is set by '//step_controlled_by(model, s)//'); the state at '// &
                   'that time was written')
      end if
    end do
    if (model%controls%d3dump_cycles > 0 .and. dump_cycle /= cycle) &
      call write_restart_file(next_dump_name())       ! (at the end, as LS-DYNA does)
    call write_outputs(model, decomp, result_cells, layout, s, schedule, cycle, t, dt_old, .true., &
                       timing%output)
    call close_histories()
    call progress_finish()
    call report_timing(model, s, cycle, timing, halo%assembly_wait, comm_wtime() - t_start)
    call explicit_steal_tear_down(s)
    call halo_free(halo)
  contains

    !> The forces and accelerations at t = 0, the first stable step, state 0 and the
    !> histories' first records.
    subroutine initial_state()
      call compute_forces(model, s, halo, 0.0_wp, 0.0_wp, timing)
      s%f_int = s%f_int_new
      s%f_ext = s%f_ext_new
      call accelerations(s)
      if (s%n_moving > 0) call update_moving_frames(model, s, 0.0_wp)
      if (s%nskew > 0) call skew_accelerations(model, s, 0.0_wp)
      if (s%tied%n > 0) call tie_accelerations(s, s%contact%n > 0, t)
      if (s%bodies%n > 0) then
        call rigid_body_resultants(s)
        call rigid_body_loads(model, s, t)
      end if
      call next_time_step(s, dt)
      if (dt < 0.0_wp) call stop_on_failure(model, decomp, result_cells, layout, s, schedule, cycle, t, &
                                            0.0_wp, timing)
      call bound_step(model, t, .true., dt)
      dt_first = dt
      call say('explicit: first time step '//rtoa(dt_first)//' s')
      if (s%mass_scaling) call report_added_mass(s)
      call warn_output_every_step(model, dt_first, 'the first time step', 'cycle', .true.)
      dt_floor = model%controls%dt_min_fraction*dt_first
      dt_old = 0.0_wp
      call open_histories(model, schedule)
      call write_outputs(model, decomp, result_cells, layout, s, schedule, cycle, t, dt, .false., &
                         timing%output)
    end subroutine initial_state

    !> The name of the next restart file of the series: d3dump01, d3dump02, ...
    function next_dump_name() result(name)
      character(len=:), allocatable :: name
      dumps = dumps + 1
      name = restart_dump_name(dumps)
    end function next_dump_name

    !> Write a restart file of the state at the end of this cycle into the output directory
    !> (collective; a failure to write it is warned about and the run goes on).
    subroutine write_restart_file(name)
      character(len=*), intent(in) :: name            !< file name (d3dump01, runrsf)
      logical :: ok
      clock = comm_wtime()
      point = run_point_t(cycle=cycle, t=t, dt=dt, dt_old=dt_old, dt_first=dt_first, &
                          dumps=dumps)
      call restart_create(restart, results_directory()//'/'//name)
      call explicit_restart_put(restart, model, cells, layout, s, point, schedule)
      call restart_commit(restart, ok)
      if (name(1:min(6, len(name))) == 'd3dump') dump_cycle = cycle
      clock = comm_wtime() - clock
      if (ok) call say('explicit: restart file '//name//' written at cycle '//itoa(cycle)// &
                       ', t = '//rtoa(t)//' in '//rtoa(clock)//' s (mefem r='// &
                       results_directory()//'/'//name//' continues from it)')
      timing%output = timing%output + clock
    end subroutine write_restart_file
  end subroutine explicit_dynamics_run

  !> What the explicit solver takes (anything else is reported before the run starts).
  subroutine check_supported(model)
    type(model_t), intent(in) :: model   !< resolved model
    integer :: k
    logical :: bad
    bad = .false.
    if (model%controls%end_time <= 0.0_wp .and. model%controls%end_cycle <= 0) then
      call say('explicit analysis needs *CONTROL_TERMINATION ENDTIM (or ENDCYC)')
      bad = .true.
    end if
    if (model%controls%dt2ms > 0.0_wp) then
      call say('*CONTROL_TIMESTEP DT2MS > 0 (uniform mass scaling) is not supported: use a '// &
               'negative DT2MS (mass added only where the step is too small)')
      bad = .true.
    end if
    do k = 1, model%n_motions
      associate (pm => model%motions(k))
        if (pm%target_kind /= ON_NODE .and. pm%target_kind /= ON_NODE_SET) then
          cycle                       ! _RIGID: checked by the rigid bodies' set-up
        else if ((abs(pm%dof) < 1 .or. abs(pm%dof) > model%dimension) .and. &
                 abs(pm%dof) /= 4 .or. pm%vad < 0 .or. pm%vad > 2) then
          call say('line '//itoa(pm%src%line)//': *BOUNDARY_PRESCRIBED_MOTION: the explicit '// &
                   'solver takes DOF 1..'//itoa(model%dimension)//', 4, -4 and VAD 0, 1, 2 (got DOF '// &
                   itoa(pm%dof)//', VAD '//itoa(pm%vad)//')')
          bad = .true.
        end if
      end associate
    end do
    if (bad) call fatal('explicit: the model asks for what the explicit solver does not do '// &
                        '(see above); nothing was run')
  end subroutine check_supported

  !> This rank's layout, halo, local cells and nodes, masses, conditions and initial state.
  subroutine set_up(model, decomp, element_rank, element_chunk, cells, layout, halo, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(decomposition_t), intent(in) :: decomp       !< this rank's decomposition
    integer, intent(in) :: element_rank(:)            !< rank of every element
    integer, intent(in) :: element_chunk(:)           !< chunk of every element
    type(cells_t), intent(in) :: cells                !< all cells
    type(explicit_layout_t), intent(out) :: layout    !< this rank's share
    type(halo_t), intent(out) :: halo                 !< force exchange
    type(explicit_state_t), intent(inout) :: s        !< local state
    integer, allocatable :: elem_start(:), elem_nodes(:)
    real(wp), allocatable :: mass_global(:), share(:,:), v_global(:,:)
    real(wp), allocatable :: w0(:,:,:)
    logical, allocatable :: fixed_global(:,:)
    real(wp) :: lambda, mu
    type(status_t) :: status
    integer :: dim, n, g, l, c, e, nv, k, count_entries, pass, i, nblock
    integer, allocatable :: nodes(:), block_starts(:), block_nodes_of(:), block_order(:)
    character(len=8) :: value
    integer :: length, env_status

    dim = cells%dim
    s%dim = dim
    nv = dim + 1
    call element_csr(model, elem_start, elem_nodes)
    call explicit_layout_build(decomp, element_rank, element_chunk, elem_start, elem_nodes, &
                               cells, layout)
    call halo_build(halo, layout, dim)
    ! the ranks of a node exchange their contributions through shared memory, not messages
    ! (MEFEM_HALO_MESSAGES=1: messages with every neighbour, for the tests of that path)
    call get_environment_variable('MEFEM_HALO_MESSAGES', value, length, env_status)
    if (.not. (env_status == 0 .and. value == '1')) call halo_assembly_share_on_node(halo)
    s%nnode = layout%nnode_local
    s%ncell = layout%ncell_local

    ! nodes: reference positions (an enriched node: its element's centroid), masses (an
    ! enriched node: the inertia of its bubble dof)
    allocate(s%x0(dim, s%nnode))
    do l = 1, s%nnode
      g = layout%node_global(l)
      if (g <= cells%n_mesh_nodes) then
        s%x0(:, l) = model%nodes%x(1:dim, g)
      else
        e = cells%enriched_element(g - cells%n_mesh_nodes)
        s%x0(:, l) = 0.0_wp
        do k = 1, nv
          s%x0(:, l) = s%x0(:, l) + model%nodes%x(1:dim, model%elements%conn(k, e))/real(nv, wp)
        end do
      end if
    end do
    call lumped_mass(model, cells, .true., mass_global)
    s%physical_mass = mass_global(layout%node_global)
    s%mass = s%physical_mass
    s%owned = layout%node_owned
    s%active = s%mass > 0.0_wp
    s%bubble = layout%node_global > cells%n_mesh_nodes

    ! cells: local copies in the layout's order; the arrays of the cell loop (and the
    ! displacements) in the node-shared arena, which needs the number of 3D blocks first
    allocate(s%cell_global(s%ncell))
    s%cell_global = layout%cell_global(1:s%ncell)
    s%mass_scaling = model%controls%dt2ms < 0.0_wp
    nblock = 0
    if (dim == 3) then
      call explicit_blocks_group(cells%material(s%cell_global), cells%nnodes(s%cell_global), &
                                 cells%nodal_pressure(s%cell_global), &
                                 cells%hex_of(s%cell_global) > 0, block_starts, &
                                 block_nodes_of, block_order)
      nblock = size(block_nodes_of)
    end if
    call state_arena_create(s, nblock)
    if (dim == 2) allocate(s%grad(dim, CELL_MAX_NODES, s%ncell), s%w0(dim, dim, s%ncell), &
                           s%hist(NHIST, s%ncell))      ! 3D: in the blocks (build_blocks)
    s%cell_element = cells%elements(1, s%cell_global)
    s%node_global = layout%node_global
    s%nodes = layout%cell_nodes(:, 1:s%ncell)
    ! the local cells' mass shares and inverse-mass metrics (time step; the shares again
    ! for the mass added by scaling)
    call cell_mass_shares(model, cells, s%cell_global, share)
    call cell_inverse_mass_metric(cells, s%cell_global, share, w0)
    do l = 1, s%ncell
      c = s%cell_global(l)
      s%nnodes(l) = cells%nnodes(c)
      s%weight(l) = cells%weight(c)
      s%material(l) = cells%material(c)
      call material_elastic_moduli(model%materials(s%material(l)), lambda, mu)
      s%lame(:, l) = [lambda, mu]
      if (dim == 2) then
        s%grad(:, :, l) = cells%grad(:, :, cell_grad_column(cells, c))
        s%w0(:, :, l) = w0(:, :, l)
        call material_state_init(s%hist(:, l))
      end if
    end do
    s%cell_force = 0.0_wp
    call erosion_set_up(model, cells, s)
    if (dim == 3) call explicit_cells_set_up(s, cells, w0, halo, block_starts, block_nodes_of, &
                                             block_order)
    if (dim == 3) call hexahedra_under_the_rule(model, cells, s)
    if (s%mass_scaling) then
      s%share = share
      s%added = 0.0_wp
    end if

    ! essential conditions: fixed dofs and the prescribed motions of local mesh nodes
    s%spc_in_time = any(model%spcs(1:model%n_spcs)%birth > 0.0_wp) .or. &
                    any(model%spcs(1:model%n_spcs)%death < SPC_FOREVER)
    allocate(fixed_global(dim, cells%n_mesh_nodes), s%driven(dim, s%nnode))
    s%driven = .false.
    fixed_global = .false.
    call fixed_dofs(model, 0.0_wp, fixed_global)
    allocate(s%fixed(dim, s%nnode))
    s%fixed = .false.
    do l = 1, s%nnode
      g = layout%node_global(l)
      if (g <= cells%n_mesh_nodes) s%fixed(:, l) = fixed_global(:, g)
    end do
    do pass = 1, 2                      ! count, then fill
      count_entries = 0
      do k = 1, model%n_motions
        ! node and node-set motions only (_RIGID moves bodies: mefem_rigid_bodies)
        if (model%motions(k)%target_kind /= ON_NODE .and. &
            model%motions(k)%target_kind /= ON_NODE_SET) cycle
        if (abs(model%motions(k)%dof) == 4) cycle        ! along a vector: skew conditions
        call target_nodes(model, model%motions(k)%target_kind, model%motions(k)%target, nodes)
        do i = 1, size(nodes)
          l = explicit_layout_local_node(layout, nodes(i))
          if (l == 0) cycle
          count_entries = count_entries + 1
          if (pass == 2) then
            s%prescribed_node(count_entries) = l
            s%prescribed_dof(count_entries) = abs(model%motions(k)%dof)
            s%prescribed_motion(count_entries) = k
          end if
        end do
      end do
      if (pass == 1) allocate(s%prescribed_node(count_entries), &
                              s%prescribed_dof(count_entries), s%prescribed_motion(count_entries))
    end do
    s%nprescribed = count_entries
    allocate(s%prescribed_v_old(count_entries))
    allocate(s%was_driven(count_entries))
    s%was_driven = .false.
    call skew_conditions_set_up(model, layout, fixed_global, cells%n_mesh_nodes, s)

    ! initial velocities: mesh nodes from the deck, zero at the dofs SPCs fix; the bubbles
    ! start at rest (the deck's field is linear in each element, which the corners carry)
    allocate(v_global(dim, cells%n_mesh_nodes))
    call initial_velocities(model, v_global)
    where (fixed_global) v_global = 0.0_wp
    allocate(s%v(dim, s%nnode), s%a(dim, s%nnode), &
             s%f_int(dim, halo%ntarget), s%f_int_new(dim, halo%ntarget), s%f_ext(dim, s%nnode), &
             s%f_ext_new(dim, s%nnode), s%f_con(dim, s%nnode), s%f_con_new(dim, s%nnode))
    s%f_con = 0.0_wp                   ! without loads or contact these stay zero: they are
    s%f_con_new = 0.0_wp               ! neither written nor read in the cycle
    s%f_ext = 0.0_wp
    s%f_ext_new = 0.0_wp
    s%with_external = model%n_nodal_loads + model%n_pressure_loads + model%n_body_loads > 0
    ! body loads: the physical lumped mass of the mesh nodes they act on (rigid-body nodes:
    ! below). A body load is a uniform acceleration, which the corners carry alone: with the
    ! diagonal (hierarchical) masses the bubbles take none of it and stay at rest in a
    ! uniformly accelerated body
    allocate(s%body_mass(s%nnode))
    s%body_mass = 0.0_wp
    if (model%n_body_loads > 0) then
      block
        logical, allocatable :: loaded(:)
        call body_load_nodes(model, cells, loaded)
        where (loaded(layout%node_global) .and. .not. s%bubble) s%body_mass = s%physical_mass
      end block
    end if
    s%u = 0.0_wp
    s%a = 0.0_wp
    do l = 1, s%nnode
      g = layout%node_global(l)
      s%v(:, l) = 0.0_wp
      if (g <= cells%n_mesh_nodes) s%v(:, l) = v_global(:, g)
    end do
    do k = 1, s%nskew                      ! (SPCs in local systems: their components too)
      if (s%skew_source(k) < 0) s%v(:, s%skew_node(k)) = s%v(:, s%skew_node(k)) - &
          dot_product(s%v(:, s%skew_node(k)), s%skew_dir(1:dim, k))*s%skew_dir(1:dim, k)
    end do
    where (s%fixed) s%v = 0.0_wp
    do n = 1, s%nnode
      if (.not. s%active(n)) s%v(:, n) = 0.0_wp
    end do

    ! rigid bodies: the deformable masses at their nodes are merged into them; their nodes
    ! are moved with them (not integrated, no SPC), starting with the mean initial velocity
    ! of their nodes
    call rigid_bodies_build(model, mass_global(1:cells%n_mesh_nodes), s%bodies, status)
    if (.not. status%ok) call fatal('explicit: '//status%message)
    allocate(s%body_force(3, s%bodies%n), s%body_moment(3, s%bodies%n), &
             s%body_load(3, s%bodies%n), s%body_load_mass(s%bodies%n))
    s%body_force = 0.0_wp
    s%body_moment = 0.0_wp
    s%body_load = 0.0_wp
    ! the mass body loads act on: the rigid elements' when the body's part takes them, plus
    ! the merged deformable masses of the nodes that take them (a deformable part in
    ! *LOAD_BODY_PARTS keeps its weight where it is merged into a rigid part that is not)
    s%body_load_mass = 0.0_wp
    if (model%n_body_loads > 0) then
      block
        logical :: parts(model%n_parts)
        logical, allocatable :: loaded(:)
        real(wp) :: merged(s%bodies%n)
        parts = body_load_parts(model)
        call body_load_nodes(model, cells, loaded)
        merged = 0.0_wp
        do g = 1, cells%n_mesh_nodes                ! ascending: the same sum on every rank
          k = s%bodies%node_body(g)
          if (k == 0) cycle
          merged(k) = merged(k) + mass_global(g)
          if (loaded(g)) s%body_load_mass(k) = s%body_load_mass(k) + mass_global(g)
        end do
        do k = 1, s%bodies%n
          if (s%bodies%body(k)%part == 0) cycle        ! (a body of nodes: no elements)
          if (model%parts(s%bodies%body(k)%part)%has_inertia) then
            ! the mass of *PART_INERTIA is the whole body's
            s%body_load_mass(k) = merge(s%bodies%body(k)%mass, 0.0_wp, &
                                        parts(s%bodies%body(k)%part))
          else if (parts(s%bodies%body(k)%part)) then
            s%body_load_mass(k) = s%body_load_mass(k) + (s%bodies%body(k)%mass - merged(k))
          end if
        end do
      end block
    end if
    do k = 1, s%bodies%n
      block
        real(wp), allocatable :: x_body(:,:), v_body(:,:), m_body(:)
        real(wp) :: v_centre(3), spin(3)
        integer :: members
        members = count(s%bodies%node_body(1:cells%n_mesh_nodes) == k)
        allocate(x_body(3, members), v_body(3, members), m_body(members))
        x_body = 0.0_wp
        v_body = 0.0_wp
        members = 0
        do g = 1, cells%n_mesh_nodes
          if (s%bodies%node_body(g) /= k) cycle
          members = members + 1
          x_body(1:dim, members) = model%nodes%x(1:dim, g)
          v_body(1:dim, members) = v_global(:, g)
          m_body(members) = 1.0_wp
        end do
        ! the nodes' initial velocities as a rigid field (translation and spin; the nodes
        ! weigh alike: a rigid field is recovered exactly with any weights, and a body's
        ! own nodes carry no lumped mass)
        if (members > 0) then
          call rigid_body_velocity_fit(s%bodies%body(k)%centre0, x_body, v_body, m_body, &
                                       v_centre, spin)
          call rigid_bodies_set_velocity(s%bodies, k, v_centre, spin)
        end if
        ! *PART_INERTIA: its velocities VTX VTY VTZ (of the centre) and VRX VRY VRZ (spin),
        ! when given, replace the nodes' mean
        if (s%bodies%body(k)%part > 0) then
          associate (part => model%parts(s%bodies%body(k)%part))
            if (part%has_inertia) then
              if (any(part%inertia_velocity /= 0.0_wp)) call rigid_bodies_set_velocity( &
                  s%bodies, k, part%inertia_velocity(1:3), part%inertia_velocity(4:6))
            end if
          end associate
        end if
      end block
    end do
    s%nrigid = 0
    if (s%bodies%n > 0) then
      s%rigid_node = pack([(l, l = 1, s%nnode)], [(rigid_of(l) > 0, l = 1, s%nnode)])
      s%nrigid = size(s%rigid_node)
      s%rigid_body = [(rigid_of(s%rigid_node(k)), k = 1, s%nrigid)]
      ! every rigid-body node of the model in ascending global order: the resultants are
      ! summed in that order on every rank (rigid_body_resultants)
      block
        integer, allocatable :: slot_of(:)
        integer :: nslot
        allocate(slot_of(size(s%bodies%node_body)))
        nslot = 0
        do g = 1, size(s%bodies%node_body)
          slot_of(g) = 0
          if (s%bodies%node_body(g) == 0) cycle
          nslot = nslot + 1
          slot_of(g) = nslot
        end do
        s%slot_body = pack(s%bodies%node_body, s%bodies%node_body > 0)
        s%rigid_slot = [(slot_of(s%node_global(s%rigid_node(k))), k = 1, s%nrigid)]
        allocate(s%rigid_buffer(6, nslot), s%rigid_present(nslot), s%rigid_send(7*s%nrigid))
        s%rigid_buffer = 0.0_wp
        s%rigid_present = .false.
      end block
      ! node motions on rigid-body nodes have no effect: dropped
      block
        logical :: keep(s%nprescribed)
        keep = [(rigid_of(s%prescribed_node(k)) == 0, k = 1, s%nprescribed)]
        s%prescribed_node = pack(s%prescribed_node, keep)
        s%prescribed_dof = pack(s%prescribed_dof, keep)
        s%prescribed_motion = pack(s%prescribed_motion, keep)
        s%nprescribed = count(keep)
      end block
      block
        logical :: keep(s%nskew)
        keep = [(rigid_of(s%skew_node(k)) == 0, k = 1, s%nskew)]
        s%skew_node = pack(s%skew_node, keep)
        s%skew_source = pack(s%skew_source, keep)
        s%skew_whole = pack(s%skew_whole, keep)
        s%skew_dir = s%skew_dir(:, pack([(k, k = 1, s%nskew)], keep))
        s%skew_system = pack(s%skew_system, keep)
        s%skew_axis = pack(s%skew_axis, keep)
        s%nskew = count(keep)
      end block
      do k = 1, s%nrigid
        l = s%rigid_node(k)
        s%active(l) = .false.
        s%fixed(:, l) = .false.
        s%body_mass(l) = 0.0_wp         ! (its mass is the body's, loaded there)
        call rigid_body_point_motion(s%bodies, s%rigid_body(k), s%x0(:, l), s%u(:, l), &
                                     s%v(:, l))
      end do
    end if

    ! mortar contact: every rank holds all surfaces (the mortar kernels are divided among
    ! the ranks); its local and owned contact nodes
    if (model%n_contacts > 0) then
      call mortar_contact_setup(model, mass_global(1:cells%n_mesh_nodes), s%contact, &
                                distribute=.true.)
      ! (with mass scaling a 4th row carries the nodes' current masses, for the penalty)
      allocate(s%contact_local(s%contact%nnode), s%contact_owned(s%contact%nnode), &
               s%contact_buffer(merge(4, 3, s%mass_scaling), s%contact%nnode))
      do k = 1, s%contact%nnode
        s%contact_local(k) = explicit_layout_local_node(layout, s%contact%node_global(k))
        s%contact_owned(k) = .false.
        if (s%contact_local(k) > 0) s%contact_owned(k) = s%owned(s%contact_local(k))
      end do
    end if

    ! force transducers: the contact nodes of each SURFA (the forces every rank holds)
    allocate(s%transducer_nodes(model%n_transducers), s%transducer_id(model%n_transducers))
    do k = 1, model%n_transducers
      call transducer_set_up(model, k, s)
    end do

    ! tied contacts: every rank holds all ties; their local nodes
    if (model%n_ties > 0) call explicit_ties_set_up(model, layout, v_global, s)

    ! rigid walls: the local nodes each one tests (not those of rigid bodies)
    s%nwall = model%n_rigid_walls
    allocate(s%wall_nodes(s%nwall), s%wall_force(3, s%nwall), s%wall_shift(3, s%nwall))
    s%wall_force = 0.0_wp
    s%wall_shift = 0.0_wp
    do k = 1, s%nwall
      call rigid_wall_nodes(model, k, s%node_global, cells%n_mesh_nodes, s%wall_nodes(k)%nodes, &
                            skip=s%bodies%node_body > 0)
    end do
    ! (u^n, v^{n-1/2} and the velocities before the walls act: copied each cycle)
    if (s%nwall > 0) allocate(s%u_old(dim, s%nnode), s%v_old(dim, s%nnode), &
                              s%v_trial(dim, s%nnode))
    call explicit_mass_split(s, halo)      ! the step bound's mass split at t = 0
    ! the other ranks of this node, whose cell blocks this rank may compute (3D)
    call explicit_steal_set_up(s)
    call explicit_layout_release_plan(layout)   ! the halo and s hold what the cycles read
  contains

    !> Body of local node l (0: none).
    integer function rigid_of(l)
      integer, intent(in) :: l                        !< local node
      rigid_of = 0
      if (s%node_global(l) <= cells%n_mesh_nodes) rigid_of = s%bodies%node_body(s%node_global(l))
    end function rigid_of

  end subroutine set_up

  !> Mass scaling (DT2MS < 0): the mass it adds at the start, on the run log (glstat's
  !> "added mass" and "percentage increase" follow it over the run).
  subroutine report_added_mass(s)
    type(explicit_state_t), intent(in) :: s           !< local state (first cell loop done)
    real(wp) :: sums(2)
    integer :: n
    sums = 0.0_wp
    do n = 1, s%nnode
      if (.not. s%owned(n) .or. .not. s%active(n) .or. s%bubble(n)) cycle
      sums(1) = sums(1) + s%mass(n) - s%physical_mass(n)
      sums(2) = sums(2) + s%physical_mass(n)
    end do
    call comm_sum(sums)
    call say('explicit: mass scaling adds '//rtoa(sums(1))//' at the start ('// &
             rtoa(100.0_wp*sums(1)/max(sums(2), tiny(1.0_wp)))//' % of the deformable mass)')
  end subroutine report_added_mass

  !> SPCs with BIRTH/DEATH: the fixed dofs at time t (only when some SPC has them; O(model)).
  subroutine update_fixed_dofs(model, s, t)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< time of the new positions
    logical :: fixed_global(s%dim, model%nodes%n)
    integer :: l, g
    fixed_global = .false.
    call fixed_dofs(model, t, fixed_global)
    do l = 1, s%nnode
      g = s%node_global(l)
      if (g > model%nodes%n) cycle
      if (s%active(l)) s%fixed(:, l) = fixed_global(:, g)
      if (allocated(s%tied_node)) then
        if (s%tied_node(l)) s%fixed(:, l) = .false.   ! (it follows its master facet)
      end if
    end do
  end subroutine update_fixed_dofs

  !> v^{n+1/2} from v^{n-1/2} and a^n, then the essential conditions.
  subroutine update_velocities(model, s, t, dt_old, dt)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< t^n
    real(wp), intent(in) :: dt_old, dt                !< dt^{n-1/2} (0 at the start), dt^{n+1/2}
    real(wp) :: dt_avg, amount, work
    integer :: k, n, i, m
    dt_avg = 0.5_wp*(dt_old + dt)
    ! v^{n-1/2} where it is read: all nodes for the rigid walls, the prescribed dofs (whose
    ! driven flags, the only ones ever set, are cleared here)
    if (s%nwall > 0) s%v_old = s%v
    do k = 1, s%nprescribed
      n = s%prescribed_node(k)
      i = s%prescribed_dof(k)
      s%prescribed_v_old(k) = s%v(i, n)
      s%was_driven(k) = s%driven(i, n)
    end do
    do k = 1, s%nskew
      s%skew_v_old(:, k) = s%v(:, s%skew_node(k))
    end do
    do k = 1, s%nprescribed
      s%driven(s%prescribed_dof(k), s%prescribed_node(k)) = .false.
    end do
    call advance_velocities(s%dim, s%nnode, dt_avg, s%active, s%fixed, s%a, s%v)
    work = 0.0_wp
    ! a dof whose motion ended at t^n (DEATH passed) is free from t^n on: a^n was set to zero
    ! there while it was driven, so its velocity takes the force at t^n now (else the motion
    ! would hold it one more step, with work nobody books); a motion still active on the
    ! same dof overrides this below
    do k = 1, s%nprescribed
      n = s%prescribed_node(k)
      i = s%prescribed_dof(k)
      if (.not. s%was_driven(k) .or. s%fixed(i, n) .or. .not. s%active(n)) cycle
      if (s%mass(n) <= 0.0_wp) cycle
      s%a(i, n) = (s%f_ext(i, n) + s%f_con(i, n) - s%f_int(i, n))/s%mass(n)
      s%v(i, n) = s%prescribed_v_old(k) + dt_avg*s%a(i, n)
    end do
    do k = 1, s%nprescribed
      n = s%prescribed_node(k)
      i = s%prescribed_dof(k)
      m = s%prescribed_motion(k)
      associate (pm => model%motions(m))
        if (t + dt < pm%birth .or. t > pm%death) cycle
        select case (pm%vad)
        case (VAD_VELOCITY)
          amount = pm%scale*curve_value(model%curves(pm%curve), t + 0.5_wp*dt)
          s%v(i, n) = amount
        case (VAD_ACCELERATION)
          amount = pm%scale*curve_value(model%curves(pm%curve), t)
          s%v(i, n) = s%prescribed_v_old(k) + dt_avg*amount
        case (VAD_DISPLACEMENT)
          amount = pm%scale*curve_value(model%curves(pm%curve), t + dt)
          s%v(i, n) = (amount - s%u(i, n))/dt
        end select
        s%driven(i, n) = .true.
        ! work of the reaction at t^n over the half steps around it (owned nodes)
        if (s%owned(n) .and. dt_avg > 0.0_wp) work = work + &
            (s%mass(n)*(s%v(i, n) - s%prescribed_v_old(k))/dt_avg - s%f_ext(i, n) - &
             s%f_con(i, n) + s%f_int(i, n))* &
            0.5_wp*(dt_old*s%prescribed_v_old(k) + dt*s%v(i, n))
      end associate
    end do
    ! SPCs in moving systems: the frame at t^{n+1/2}, x^n + v^{n+1/2} dt/2 (the free velocities)
    if (s%n_moving > 0) call update_moving_frames(model, s, 0.5_wp*dt)
    if (s%nskew > 0) call apply_skew_conditions(model, s, t, dt_old, dt, work)
    s%external_work = s%external_work + work
  end subroutine update_velocities

  !> One-point hexahedra whose step LS-DYNA's characteristic-length rule may set: those with a
  !> node inside the body (on no exterior face). The rule (L/c, L = V/A_max) is the exact limit
  !> of a mesh of cubes, where the neighbours hold an element's corners; an element without
  !> an interior node (a free element, a layer one element thick) has a dilatation mode of
  !> frequency 2 sqrt(3K/rho)/L: its own bound, 2/omega = 0.73 L/c at PR 0.3, is the limit
  !> (doc/theory.md 2.8). The same on every rank (global mesh).
  subroutine hexahedra_under_the_rule(model, cells, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(cells_t), intent(in) :: cells                !< all cells
    type(explicit_state_t), intent(inout) :: s        !< local state (hexahedra set up)
    logical, allocatable :: on_surface(:)
    integer :: l, hb, e, k
    logical :: inside
    if (.not. s%hourglass) return
    call exterior_nodes(model, on_surface)
    do l = 1, s%ncell
      hb = s%block_hex(s%cell_block(l))
      if (hb == 0) cycle
      e = cells%elements(1, s%cell_global(l))
      inside = .false.
      do k = 1, size(model%elements%conn, 1)
        if (model%elements%conn(k, e) <= 0) cycle
        if (.not. on_surface(model%elements%conn(k, e))) inside = .true.
      end do
      s%hex_rule(s%cell_slot(l), hb) = inside
    end do
  end subroutine hexahedra_under_the_rule

  !> Internal and external forces at time t (into f_int_new, f_ext_new) and the local stable
  !> time step; the cell loop starts the halo exchange of the contributions to shared nodes,
  !> finished here.
  subroutine compute_forces(model, s, halo, t, dt, timing)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    type(halo_t), intent(inout) :: halo               !< force exchange
    real(wp), intent(in) :: t                         !< time of the forces
    real(wp), intent(in) :: dt                        !< the stable step of the cycle that
                                                      !< reached t (0 at t = 0): penalty limit
    type(timing_t), intent(inout) :: timing           !< phase times
    real(wp) :: clock
    clock = comm_wtime()
    s%time = t
    call explicit_cell_loop(model, s, halo, dt)
    timing%forces = timing%forces + (comm_wtime() - clock)
    ! the next step depends on the cells only: its minimum over the ranks runs while the
    ! forces are assembled and the accelerations computed (next_time_step waits for it)
    if (s%failed) then
      call comm_min_start(s%dt_reduction, STEP_FAILED)
    else if (signal_caught() /= 0) then          ! (a failure elsewhere, smaller, wins)
      call comm_min_start(s%dt_reduction, STEP_SIGNALLED)
    else
      call comm_min_start(s%dt_reduction, s%dt_stable)
    end if
    clock = comm_wtime()
    call halo_assemble_finish(halo, s%f_int_new)
    call comm_min_progress(s%dt_reduction)     ! (the others' steps have come by now)
    if (s%erosion) call erosion_update(s, halo)
    if (s%mass_scaling) then
      block
        real(wp) :: added(1, halo%ntarget)
        call halo_assemble(halo, s%added, added)
        s%mass = s%physical_mass + added(1, 1:s%nnode)
      end block
    end if
    timing%exchange = timing%exchange + (comm_wtime() - clock)
    call external_nodal_forces(model, s, t)
    if (s%contact%n > 0) call set_to_zero(size(s%f_con_new), s%f_con_new)
    if (s%contact%n > 0 .and. dt > 0.0_wp) then
      clock = comm_wtime()
      call contact_forces(s, t, dt)
      timing%contact = timing%contact + (comm_wtime() - clock)
    end if
  end subroutine compute_forces

  !> Erosion (a material with a failure strain): the cells' elements and how many cells of
  !> each element are left (elements without cells, rigid ones: -1, they never erode).
  subroutine erosion_set_up(model, cells, s)
    type(model_t), intent(in) :: model                !< resolved model
    type(cells_t), intent(in) :: cells                !< all cells
    type(explicit_state_t), intent(inout) :: s        !< local state (cells set up)
    integer :: c, j, e
    s%erosion = .false.
    do c = 1, cells%n
      if (material_fails(model%materials(cells%material(c)))) s%erosion = .true.
    end do
    if (.not. s%erosion) return
    allocate(s%cell_counted(s%ncell), s%new_eroded(16), s%eroded_all(16))
    s%cell_counted = .false.
    s%cell_elements = cells%elements(:, 1:cells%n)
    allocate(s%live_cells(model%elements%n))
    s%live_cells = -1
    do c = 1, cells%n
      do j = 1, 2
        e = cells%elements(j, c)
        if (e <= 0) cycle
        s%live_cells(e) = max(s%live_cells(e), 0) + 1
      end do
    end do
  end subroutine erosion_set_up

  !> Erosion, after the cell loop: the cells that failed this cycle on every rank (collective:
  !> one allgather, a second when some failed), each element's count of cells left; an element
  !> with none left has eroded: its faces leave the contacts, and the nodal-pressure means
  !> leave out the failed cells from now on.
  subroutine erosion_update(s, halo)
    type(explicit_state_t), intent(inout) :: s        !< local state
    type(halo_t), intent(inout) :: halo               !< the force assembly's halo (idle)
    integer :: n_all, k, j, e
    call comm_allgatherv_int(s%new_eroded, s%n_new_eroded, s%eroded_all, n_all)
    s%n_new_eroded = 0
    if (n_all == 0) return
    s%eroded_cells = s%eroded_cells + n_all
    do k = 1, n_all
      do j = 1, 2
        e = s%cell_elements(j, s%eroded_all(k))
        if (e > 0) s%live_cells(e) = s%live_cells(e) - 1
      end do
    end do
    if (s%contact%n > 0) call mortar_contact_erode(s%contact, s%live_cells)
    if (s%nodal_pressure) call nodal_reference_volumes(s, halo)
  end subroutine erosion_update

  !> Mortar contact forces at the current positions: the contact nodes' positions gathered on
  !> every rank (owners fill, one sum), the mortar kernels divided among the ranks and the
  !> rest of every interface computed on every rank alike (mefem_mortar_contact), the forces
  !> taken at this rank's local nodes.
  subroutine contact_forces(s, t, dt)
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< time of the positions (BT/DT)
    real(wp), intent(in) :: dt                        !< the step that reached the positions
    integer :: k, l
    s%contact_buffer = 0.0_wp
    do k = 1, s%contact%nnode
      l = s%contact_local(k)
      if (l > 0) then
        if (s%contact_owned(k)) then
          s%contact_buffer(1:s%dim, k) = s%x0(:, l) + s%u(:, l)
          if (s%mass_scaling) s%contact_buffer(4, k) = s%mass(l)
        end if
      end if
    end do
    call comm_sum(s%contact_buffer)
    s%contact%x(:, s%contact%node_global) = s%contact_buffer(1:3, :)
    if (s%mass_scaling) call mortar_contact_set_masses(s%contact, s%contact_buffer(4, :))
    call mortar_contact_forces(s%contact, dt, time=t)
    do k = 1, s%contact%nnode
      l = s%contact_local(k)
      if (l > 0) s%f_con_new(:, l) = s%contact%force(1:s%dim, k)
    end do
  end subroutine contact_forces

  !> External nodal forces at time t of the local nodes: the nodal and pressure loads of the
  !> global model at the mesh nodes, then the body loads -m a(t) at every loaded node (mesh
  !> and enriched; per node, so the same bits on any number of ranks).
  subroutine external_nodal_forces(model, s, t)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: t                         !< time
    real(wp), allocatable :: force(:,:)
    integer :: l, g
    if (.not. s%with_external) return                 ! f_ext_new stays zero
    call set_to_zero(size(s%f_ext_new), s%f_ext_new)
    if (model%n_nodal_loads + model%n_pressure_loads > 0) then
      allocate(force(s%dim, model%nodes%n))
      force = 0.0_wp
      call external_forces(model, t, force)
      do l = 1, s%nnode
        g = s%node_global(l)
        if (g <= model%nodes%n) s%f_ext_new(:, l) = force(:, g)
      end do
    end if
    if (model%n_body_loads > 0) call add_body_forces(body_acceleration(model, t), s%body_mass, &
                                                     s%f_ext_new)
  end subroutine external_nodal_forces

  !> A cell failed (inverted, return map, NaN): write the state reached and stop, naming the
  !> element (printed by the rank that found it), the cycle and the time.
  subroutine stop_on_failure(model, decomp, cells, layout, s, schedule, cycle, t, dt, timing)
    type(model_t), intent(in) :: model                !< resolved model
    type(decomposition_t), intent(in) :: decomp       !< this rank's output piece
    type(cells_t), intent(in) :: cells                !< the cells of the output piece
                                                      !< (layout%result_cell)
    type(explicit_layout_t), intent(in) :: layout     !< this rank's share
    type(explicit_state_t), intent(in) :: s           !< local state
    type(schedule_t), intent(inout) :: schedule       !< what is due when
    integer, intent(in) :: cycle                      !< cycle just completed
    real(wp), intent(in) :: t, dt                     !< time, the step that reached it
    type(timing_t), intent(inout) :: timing           !< phase times
    call write_outputs(model, decomp, cells, layout, s, schedule, cycle, t, dt, .true., &
                       timing%output)
    call close_histories()
    call fatal('explicit: a cell failed at cycle '//itoa(cycle)//', t = '//rtoa(t)// &
               ' (element named above); the state at that time was written')
  end subroutine stop_on_failure

  !> a = (f_ext + f_con - f_int)/m at the integrated nodes (the forces of t^0, before the
  !> first step); zero at fixed dofs and at dofs a motion drives in this cycle (a is then used
  !> only for the full-step velocity of the output; a motion outside its BIRTH..DEATH window
  !> leaves its dof free).
  subroutine accelerations(s)
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp) :: internal, external, sliding
    call nodal_balance(s%dim, s%nnode, .false., 0.0_wp, s%with_external, s%contact%n > 0, &
                       s%owned, s%active, s%fixed, s%driven, s%mass, s%v, s%f_int, s%f_int, &
                       s%f_ext, s%f_ext, s%f_con, s%f_con, s%a, internal, external, sliding)
  end subroutine accelerations

  !> The step from the cells' stable bound (huge when no deformable cell bounds it, negative
  !> when a cell failed: left as it is) and *CONTROL_TIMESTEP: DTINIT caps the first step and
  !> is every step of a model of rigid parts only; LCTM caps the step at time t where its
  !> curve is positive. A step still unbounded stops the run with a message (every rank alike).
  subroutine bound_step(model, t, first, dt)
    type(model_t), intent(in) :: model                !< resolved model
    real(wp), intent(in) :: t                         !< current time
    logical, intent(in) :: first                      !< the first step
    real(wp), intent(inout) :: dt                     !< the next step
    real(wp) :: cap
    if (dt < 0.0_wp) return
    if (model%controls%dt_init > 0.0_wp .and. (first .or. dt >= huge(1.0_wp))) &
      dt = min(dt, model%controls%dt_init)
    if (model%controls%lctm_curve > 0) then
      cap = curve_value(model%curves(model%controls%lctm_curve), t)
      if (cap > 0.0_wp) dt = min(dt, cap)              ! (a value <= 0 sets no cap)
    end if
    if (dt >= huge(1.0_wp)) call fatal('explicit: no deformable element bounds the time '// &
        'step at t = '//rtoa(t)//' (the model has rigid parts only); give the step with '// &
        '*CONTROL_TIMESTEP DTINIT (or a curve LCTM, positive at all times)')
  end subroutine bound_step

  !> After a step: the trapezoidal internal energy, external work and contact energy of the
  !> step (owned nodes) and the accelerations a^{n+1} (as accelerations does) in one pass
  !> over the nodes; then the new forces become the current ones (array swap, no copy).
  subroutine energies_and_accelerations(s, dt)
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(in) :: dt                        !< dt^{n+1/2}
    real(wp), allocatable :: scratch(:,:)
    real(wp) :: internal, external, sliding
    call nodal_balance(s%dim, s%nnode, .true., dt, s%with_external, s%contact%n > 0, s%owned, &
                       s%active, s%fixed, s%driven, s%mass, s%v, s%f_int, s%f_int_new, s%f_ext, &
                       s%f_ext_new, s%f_con, s%f_con_new, s%a, internal, external, sliding)
    s%internal_energy = s%internal_energy + internal
    s%hourglass_dissipated = s%hourglass_dissipated + s%hourglass_power*dt
    s%external_work = s%external_work + external
    s%contact_energy = s%contact_energy + sliding
    call move_alloc(s%f_con, scratch)
    call move_alloc(s%f_con_new, s%f_con)
    call move_alloc(scratch, s%f_con_new)
    call move_alloc(s%f_int, scratch)
    call move_alloc(s%f_int_new, s%f_int)
    call move_alloc(scratch, s%f_int_new)
    call move_alloc(s%f_ext, scratch)
    call move_alloc(s%f_ext_new, s%f_ext)
    call move_alloc(scratch, s%f_ext_new)
  end subroutine energies_and_accelerations

  !> The loop of accelerations and energies_and_accelerations on plain arrays (the compiler
  !> keeps the addresses in registers and takes the flags' tests out of the loop): with
  !> energies, the work of the forces over the step, 0.5 dt (f^n + f^{n+1}) . v^{n+1/2}, summed
  !> over owned nodes (internal, external, minus contact); a = (f_ext + f_con - f_int)/m from
  !> the new forces. Zero external or contact forces are not read (no loads, no contact):
  !> the same bits, as 0 + x = x.
  pure subroutine nodal_balance(dim, nnode, energies, dt, with_external, with_contact, owned, &
                                active, fixed, driven, mass, v, f_int, f_int_new, f_ext, &
                                f_ext_new, f_con, f_con_new, a, internal, external, sliding)
    integer, intent(in) :: dim, nnode                 !< dimension, local nodes
    logical, intent(in) :: energies                   !< accumulate the energies of the step
    real(wp), intent(in) :: dt                        !< dt^{n+1/2} (energies)
    logical, intent(in) :: with_external, with_contact !< f_ext, f_con may be nonzero
    logical, intent(in) :: owned(nnode)               !< owned nodes (energies)
    logical, intent(in) :: active(nnode)              !< integrated nodes
    logical, intent(in) :: fixed(dim, nnode), driven(dim, nnode) !< dofs with a = 0
    real(wp), intent(in) :: mass(nnode)               !< lumped masses
    real(wp), intent(in) :: v(dim, nnode)             !< v^{n+1/2} (energies)
    real(wp), intent(in) :: f_int(dim, nnode), f_int_new(dim, nnode) !< internal f^n, f^{n+1}
    real(wp), intent(in) :: f_ext(dim, nnode), f_ext_new(dim, nnode) !< external
    real(wp), intent(in) :: f_con(dim, nnode), f_con_new(dim, nnode) !< contact
    real(wp), intent(out) :: a(dim, nnode)            !< a^{n+1}
    real(wp), intent(out) :: internal, external, sliding !< the step's energies (owned)
    real(wp) :: dot_int, dot_ext, dot_con, net
    integer :: n, d
    internal = 0.0_wp
    external = 0.0_wp
    sliding = 0.0_wp
    do n = 1, nnode
      if (energies .and. owned(n)) then
        dot_int = 0.0_wp                     ! the dot products summed as dot_product does
        dot_ext = 0.0_wp
        dot_con = 0.0_wp
        do d = 1, dim
          dot_int = dot_int + (f_int(d, n) + f_int_new(d, n))*v(d, n)
          if (with_external) dot_ext = dot_ext + (f_ext(d, n) + f_ext_new(d, n))*v(d, n)
          if (with_contact) dot_con = dot_con + (f_con(d, n) + f_con_new(d, n))*v(d, n)
        end do
        internal = internal + 0.5_wp*dt*dot_int
        if (with_external) external = external + 0.5_wp*dt*dot_ext
        if (with_contact) sliding = sliding - 0.5_wp*dt*dot_con
      end if
      do d = 1, dim
        if (active(n) .and. .not. (fixed(d, n) .or. driven(d, n))) then
          net = 0.0_wp
          if (with_external) net = f_ext_new(d, n)
          if (with_contact) net = net + f_con_new(d, n)
          a(d, n) = (net - f_int_new(d, n))/mass(n)
        else
          a(d, n) = 0.0_wp
        end if
      end do
    end do
  end subroutine nodal_balance

  !> v^{n+1/2} = v^{n-1/2} + dt_avg a^n at the integrated nodes, 0 at fixed dofs (first part
  !> of update_velocities, on plain arrays).
  pure subroutine advance_velocities(dim, nnode, dt_avg, active, fixed, a, v)
    integer, intent(in) :: dim, nnode                 !< dimension, local nodes
    real(wp), intent(in) :: dt_avg                    !< (dt^{n-1/2} + dt^{n+1/2})/2
    logical, intent(in) :: active(nnode)              !< integrated nodes
    logical, intent(in) :: fixed(dim, nnode)          !< SPC / TC fixed dofs
    real(wp), intent(in) :: a(dim, nnode)             !< a^n
    real(wp), intent(inout) :: v(dim, nnode)          !< v^{n-1/2} -> v^{n+1/2}
    integer :: n, d
    do n = 1, nnode
      do d = 1, dim
        if (active(n)) v(d, n) = v(d, n) + dt_avg*a(d, n)
        if (fixed(d, n)) v(d, n) = 0.0_wp
      end do
    end do
  end subroutine advance_velocities

  !> u^{n+1} = u^n + dt v^{n+1/2} over all dofs (plain arrays).
  pure subroutine advance_displacements(ndof, dt, v, u)
    integer, intent(in) :: ndof                       !< dim x local nodes
    real(wp), intent(in) :: dt                        !< dt^{n+1/2}
    real(wp), intent(in) :: v(ndof)                   !< v^{n+1/2}
    real(wp), intent(inout) :: u(ndof)                !< u^n -> u^{n+1}
    integer :: k
    do k = 1, ndof
      u(k) = u(k) + dt*v(k)
    end do
  end subroutine advance_displacements

  !> The next time step: the global minimum of the cells' stable steps (one reduction per
  !> cycle, started by compute_forces). A failed cell anywhere gives -1; the rank that found
  !> it prints what happened.
  subroutine next_time_step(s, dt)
    type(explicit_state_t), intent(inout) :: s        !< local state
    real(wp), intent(out) :: dt                       !< the step (STEP_FAILED: a cell failed;
                                                      !< STEP_SIGNALLED: a rank caught a signal)
    call comm_min_finish(s%dt_reduction, dt)
    if (dt < 0.0_wp .and. s%failed) write(error_unit, '(a)') 'mefem: error: '//trim(s%failure)
  end subroutine next_time_step

  !> The assembly's chunks in the log: how many (the rank counts that give the same bits),
  !> the partial sums they take (columns over all ranks) and the sums exchanged per cycle.
  subroutine report_chunks(layout, halo, nchunk)
    type(explicit_layout_t), intent(in) :: layout     !< this rank's layout (plan released)
    type(halo_t), intent(in) :: halo                  !< its force exchange
    integer, intent(in) :: nchunk                     !< chunks of the model
    integer :: npartial, nsent
    npartial = layout%npartial
    nsent = halo%nsent
    call comm_sum(npartial)
    call comm_sum(nsent)
    call say('explicit: forces summed in '//itoa(nchunk)//' chunks (the same bits on 1 to '// &
             itoa(nchunk)//' ranks): '//itoa(npartial)//' partial sums at nodes on chunk '// &
             'cuts, '//itoa(nsent)//' sums exchanged per cycle')
  end subroutine report_chunks

  !> Force transducer k: the contact nodes (contact-node numbering) of its SURFA's facets
  !> (those on no contact surface feel no contact force and are left out), its rcforc number
  !> (ID, else the contacts' count plus its position).
  subroutine transducer_set_up(model, k, s)
    type(model_t), intent(in) :: model                !< resolved model
    integer, intent(in) :: k                          !< the transducer
    type(explicit_state_t), intent(inout) :: s        !< local state (contact set up)
    type(contact_surface_t) :: surface
    type(status_t) :: status
    integer, allocatable :: nodes(:)
    associate (c => model%transducers(k))
      s%transducer_id(k) = merge(c%id, model%n_contacts + k, c%id > 0)
      call contact_surface_build(model, c%surf_a_type, c%surf_a, surface, status, &
                                 'contact '//itoa(s%transducer_id(k))//' SURFA')
      if (.not. status%ok) call fatal('explicit: '//status%message)
    end associate
    allocate(nodes(0))
    if (s%contact%n > 0) nodes = s%contact%node_index(surface%nodes)
    s%transducer_nodes(k)%nodes = pack(nodes, nodes > 0)
    if (size(s%transducer_nodes(k)%nodes) == 0) call warn('contact '// &
        itoa(s%transducer_id(k))//': the force transducer''s SURFA has no node on a contact '// &
        'surface: its rcforc forces are zero')
  end subroutine transducer_set_up

  !> Run summary: cycles, and where the time went per element and cell cycle; with several
  !> ranks, the spread over ranks (min / max) of the cells and of the phase times, which
  !> tells load imbalance (forces) from communication (halo wait, time-step reduction).
  subroutine report_timing(model, s, cycle, timing, halo_wait, wall)
    type(model_t), intent(in) :: model                !< resolved model
    type(explicit_state_t), intent(in) :: s           !< local state
    integer, intent(in) :: cycle                      !< cycles run
    type(timing_t), intent(in) :: timing              !< phase times (this rank)
    real(wp), intent(in) :: halo_wait                 !< time waiting in the halo assembly
    real(wp), intent(in) :: wall                      !< wall time of the whole analysis
    real(wp) :: loop, counts(2), ranks, spread(2, 5), shared_blocks(3)
    integer :: k
    counts = [real(count(deformable_element(model)), wp), real(s%ncell, wp)]
    counts(2) = real(s%ncell, wp)
    call comm_sum(counts(2))
    loop = timing%forces + timing%exchange + timing%reduction + timing%update + timing%output + &
           timing%contact
    spread(1, :) = [real(s%ncell, wp), timing%forces, halo_wait, timing%reduction, &
                    timing%update]
    spread(2, :) = spread(1, :)
    do k = 1, size(spread, 2)
      call comm_min(spread(1, k))
      call comm_max(spread(2, k))
    end do
    call comm_max(loop)
    ranks = real(comm_size(), wp)
    call say('explicit: '//itoa(cycle)//' cycles, '//rtoa(wall)//' s')
    if (s%erosion) call say('explicit: eroded '//itoa(s%eroded_cells)//' cells, '// &
        itoa(count(s%live_cells == 0))//' elements (failure strain, *MAT_ADD_EROSION)')
    if (cycle > 0 .and. loop > 0.0_wp .and. counts(1) > 0.0_wp) then
      call say('explicit: '//rtoa(1.0e9_wp*loop*ranks/(counts(1)*cycle))// &
               ' ns per element-cycle, '//rtoa(1.0e9_wp*loop*ranks/(counts(2)*cycle))// &
               ' ns per cell-cycle (core time = wall x '//itoa(comm_size())//' ranks)')
      call say('explicit: rank 0 time in forces '//rtoa(100.0_wp*timing%forces/loop)// &
               ' %, halo exchange and reductions '// &
               rtoa(100.0_wp*(timing%exchange + timing%reduction)/loop)// &
               ' %, nodal update '//rtoa(100.0_wp*timing%update/loop)//' %, output '// &
               rtoa(100.0_wp*timing%output/loop)//' %, contact '// &
               rtoa(100.0_wp*timing%contact/loop)//' %')
      if (comm_size() > 1) call say('explicit: min / max over ranks: cells '// &
          itoa(nint(spread(1, 1)))//' / '//itoa(nint(spread(2, 1)))//', forces '// &
          rtoa(spread(1, 2))//' / '//rtoa(spread(2, 2))//' s, halo wait '// &
          rtoa(spread(1, 3))//' / '//rtoa(spread(2, 3))//' s, time-step reduction '// &
          rtoa(spread(1, 4))//' / '//rtoa(spread(2, 4))//' s, nodal update '// &
          rtoa(spread(1, 5))//' / '//rtoa(spread(2, 5))//' s')
      if (s%dim == 3) then
        shared_blocks(1:2) = [real(s%exact_bound_blocks, wp), real(s%bound_blocks, wp)]
        call comm_sum(shared_blocks(1:2))
        call say('explicit: step bound: exact in '// &
                 rtoa(100.0_wp*shared_blocks(1)/max(shared_blocks(2), 1.0_wp))// &
                 ' % of the cell blocks, the quick bound in the others')
      end if
      if (comm_size() > 1 .and. s%dim == 3) then
        shared_blocks = [real(s%blocks_for_others, wp), real(s%blocks_by_others, wp), &
                         real(s%nblock, wp)*cycle]
        call comm_sum(shared_blocks)
        call say('explicit: cell blocks computed by another rank of the node: '// &
                 itoa(nint(shared_blocks(1)))//' of '//itoa(nint(shared_blocks(3)))//' ('// &
                 rtoa(100.0_wp*shared_blocks(1)/max(shared_blocks(3), 1.0_wp))//' %)')
      end if
      if (timing%contact > 0.0_wp) call say('explicit: contact '// &
          rtoa(timing%contact/cycle)//' s per cycle on rank 0')
    end if
  end subroutine report_timing

  !> Elements of deformable (not rigid) parts.
  function deformable_element(model) result(mask)
    type(model_t), intent(in) :: model                !< resolved model
    logical :: mask(model%elements%n)
    integer :: e, m
    do e = 1, model%elements%n
      m = model%parts(model%elements%part(e))%material
      mask(e) = .false.
      if (m > 0) mask(e) = model%materials(m)%kind /= MAT_RIGID
    end do
  end function deformable_element

end module mefem_explicit_dynamics
