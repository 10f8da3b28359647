!> Nonlinear quasi-static analysis: load/time stepping with Newton-Raphson on MUMPS
!> (*CONTROL_IMPLICIT_GENERAL IMFLAG=1 with a nonlinear *CONTROL_IMPLICIT_SOLUTION NSOLVR).
!>
!> Per step t_n -> t_{n+1} = t_n + dt (Simo & Hughes; formulation 2.7 and 6):
!>   u_{n+1}^0 = u_n + (dt_{n+1}/dt_n)(u_n - u_{n-1}) (the last increment extrapolated) with
!>   the prescribed displacements of t_{n+1};
!>   repeat: R = f_ext(t_{n+1}) - f_int(u),  K = dR/du (consistent: material + geometric),
!>           K du = R (free dofs),  u = u + s du  (s from a line search when LSTOL is violated);
!>   until the displacement (DCTOL) and energy (ECTOL) norms, and the residual (RCTOL, ABSTOL),
!>   say converged, at most MAXREF iterations. A step that diverges, exceeds the iteration
!>   limit or inverts a cell (det F <= 0) is cut in half and redone from the last converged
!>   state (*CONTROL_IMPLICIT_AUTO); easy steps grow again. The material history is committed
!>   only when a step converges. Every rank computes the cells of its own elements; the
!>   residual is summed over ranks and MUMPS solves on all of them.
!> Body loads (*LOAD_BODY_) are external nodal forces -m a(t_{n+1}) with the lumped masses of
!> the mesh and enriched nodes (mefem_body_loads), like the other loads of the step.
module mefem_implicit_static
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_sum, comm_max, comm_is_root, comm_wtime, comm_any
  use mefem_errors, only: status_t, fatal, say, warn
  use mefem_signals, only: signals_install, signal_caught, signal_name, signal_record_stop
  use mefem_progress, only: progress_start, progress_update
  use mefem_strings, only: itoa, rtoa
  use mefem_model, only: model_t, ON_PART, MAT_RIGID, TIEBREAK_NONE, RIGID_EXTRA_NODES
  use mefem_decomposition, only: decomposition_t
  use mefem_cells, only: cells_t, cells_build, cells_summary, CELL_MAX_NODES
  use mefem_cell_finite_strain, only: cell_deformation_gradient, cell_internal_force, &
                                      cell_tangent, inverse_3x3
  use mefem_hexahedron, only: hourglass_stiffness_cell
  use mefem_material_state, only: NHIST, HIST_ALPHA, material_state_init
  use mefem_material_update, only: material_update, rate_dependent, material_fails, &
                                   spall_active
  use mefem_boundary_conditions, only: fixed_dofs, prescribed_displacements, external_forces
  use mefem_sparse_assembly, only: coo_matrix_t, coo_init, coo_add_block, coo_reset_values, &
                                   coo_free, coo_add_rectangle
  use mefem_implicit_constraints, only: node_constraints_t, constraints_set_up, &
                                        constraints_activate, constraints_residual, &
                                        constraints_matrix, constraints_increment, &
                                        constraints_prescribe, constraints_reaction
  use mefem_tied_contact, only: tied_nodes_t, tied_contact_build
  use mefem_mumps, only: mumps_solver_t, mumps_init, mumps_factorise, mumps_solve, &
                         mumps_free, MUMPS_UNSYMMETRIC, mumps_stats, mumps_stats_t, &
                         ordering_name
  use mefem_progress, only: peak_memory_mib
  use mefem_output_mesh, only: output_field_t
  use mefem_results, only: results_write_state, append_node_set_fields, results_directory, &
                           results_restart_header_put, results_restart_header_skip, &
                           results_restart_put, results_restart_get
  use mefem_sense_switch, only: sense_switch, sense_switch_warn_leftover, SENSE_STOP, &
                                SENSE_STATUS, SENSE_STATE, SENSE_RESTART
  use mefem_restart_file, only: restart_file_t, restart_create, restart_commit, restart_open, &
                                restart_close, restart_put_text, restart_put_ints, &
                                restart_put_reals, restart_get_text, restart_get_ints, &
                                restart_get_reals, restart_checksum, restart_dump_name
  use mefem_solver_common, only: number_equations, cell_result_fields, schedule_after, &
                                 warn_output_every_step, title_or_default, restart_files_due, &
                                 first_dump_time
  use mefem_mortar_contact, only: mortar_contact_restart_put, mortar_contact_restart_get
  use mefem_history_output, only: rcforc_open, rcforc_close, glstat_record_t, &
                                  glstat_open, glstat_write, glstat_close, &
                                  glstat_total_energy, glstat_energy_ratio, rbdout_open, &
                                  rbdout_write, rbdout_close
  use mefem_implicit_tools, only: tools, set_up_tools, tool_displacement, extra_nodes_follow, &
                                  tool_contact, report_contact
  use mefem_lumped_mass, only: lumped_mass
  use mefem_body_loads, only: body_acceleration, body_load_nodes, add_body_forces
  use mefem_implicit_nodal_pressure, only: np_patches_t, np_values_t, np_patches_build, &
                                           np_pairs_build, np_prepare, np_pressures, np_fbar, &
                                           np_cell_terms, np_add_to_pairs
  implicit none
  private

  public :: implicit_static_run, implicit_writes_initial_state

  !> Wall time spent in the phases of the Newton iterations (for the run summary).
  type :: timing_t
    real(wp) :: assembly = 0.0_wp        !< material updates, forces, tangent assembly
    real(wp) :: factorisation = 0.0_wp   !< MUMPS analysis + numerical factorisation
    real(wp) :: solve = 0.0_wp           !< MUMPS solves
    integer :: iterations = 0            !< Newton iterations in total
  end type timing_t
  type(timing_t) :: timing


  !> Lumped masses of the nodes the body loads act on (mesh, then enriched nodes; 0 at the
  !> others), set once by implicit_static_run: the body force of a node is -m a(t).
  real(wp), allocatable :: loaded_mass(:)
  !> SPCs in turned local systems and tied contacts: the change of unknowns u = T u'
  !> (mefem_implicit_constraints) and the transformed tangent the solver takes
  type(node_constraints_t) :: skew
  type(coo_matrix_t) :: skew_tangent

  !> Energies of the quasi-static run for glstat (doc/theory.md 5), summed step by step by
  !> the trapezoidal rule over the converged states: internal energy int f_int . du (all
  !> degrees of freedom, enriched ones included), external work int (f_int - f_contact) . du
  !> on the deformable nodes (the loads and the reactions of SPCs and prescribed motions, in
  !> equilibrium) plus the work of the tools' drives, int -F_tool . dx_tool, and the sliding
  !> interface energy -int F . dx over both sides of every contact (the penalty springs'
  !> energy and the friction's dissipation). Kinetic energy is 0 (statics).
  type :: energy_t
    real(wp) :: internal = 0.0_wp                  !< internal energy
    real(wp) :: external = 0.0_wp                  !< external work
    real(wp) :: contact = 0.0_wp                   !< sliding interface energy
    real(wp), allocatable :: f_int(:,:)            !< (dim, all nodes) f_int, last state
    real(wp), allocatable :: u(:,:)                !< (dim, all nodes) u, last state
    real(wp), allocatable :: g(:,:)                !< (dim, all nodes) external forces, last
    real(wp), allocatable :: f_contact(:,:)        !< (3, contact nodes) contact forces, last
    real(wp), allocatable :: x_contact(:,:)        !< (3, contact nodes) their positions, last
    real(wp) :: glstat_interval = 0.0_wp           !< *DATABASE_GLSTAT DT (0: no glstat)
    real(wp) :: next_glstat = 0.0_wp               !< next glstat (and rbdout) time
    logical :: rbdout = .false.                    !< tools written to rbdout
    real(wp), allocatable :: tool_centre(:,:)      !< (3, parts) centroid of each tool's nodes
    real(wp), allocatable :: tool_d(:,:)           !< (3, parts) tool translation, last state
  end type energy_t
  type(energy_t) :: energy

  !> Nodal-pressure tetrahedra (ELFORM 13): their patches (set up once) and one evaluation's
  !> values (mefem_implicit_nodal_pressure; every rank evaluates all of them).
  type(np_patches_t) :: patches
  type(np_values_t) :: np_values
  real(wp), allocatable :: np_pair_values(:,:,:)   !< (3, 3, pairs) the patch blocks' sums

  !> What one evaluation of the cells gives.
  type :: cell_state_t
    real(wp), allocatable :: hist_new(:,:)   !< (NHIST, cells) trial history
    real(wp), allocatable :: cauchy(:,:)     !< (6, cells) Cauchy stress (Voigt)
  end type cell_state_t

contains

  !> Run the nonlinear quasi-static analysis and write output states along the way.
  !> With restart_path, the run continues after the step its restart file was written at (the
  !> results of the run that wrote it are continued: results_open with resume).
  subroutine implicit_static_run(model, decomp, restart_path)
    type(model_t), intent(in) :: model              !< resolved model
    type(decomposition_t), intent(in) :: decomp     !< this rank's share
    character(len=*), intent(in), optional :: restart_path  !< restart file to continue from
    type(cells_t) :: cells
    type(status_t) :: status
    type(tied_nodes_t) :: tied
    type(coo_matrix_t) :: tangent
    type(mumps_solver_t) :: solver
    type(cell_state_t) :: trial
    integer, allocatable :: equation(:,:)
    logical, allocatable :: fixed(:,:), owned(:)
    real(wp), allocatable :: prescribed(:,:), force(:,:), u(:,:), u_step(:,:), hist(:,:)
    real(wp), allocatable :: u_last(:,:), internal(:,:)
    real(wp) :: dt_last
    real(wp) :: t, dt, dt_min, dt_max, end_time, next_output, t0, dt_planned, next_dump
    integer :: dim, n_all, n_equations, step, iterations, output_step, c, cuts, action, signum, k
    integer :: dumps, dump_step
    logical :: converged, written, resume, dump_due, runrsf_due
    type(restart_file_t) :: restart

    t0 = comm_wtime()
    resume = present(restart_path)
    call cells_build(model, cells, status, static=.true.)
    if (.not. status%ok) call fatal('element set-up: '//status%message)
    call check_supported(model)
    call cells_summary(cells)
    call np_patches_build(cells, patches)
    if (patches%n > 0) call say('implicit: '//itoa(patches%n)//' nodal-pressure tetrahedra '// &
        '(ELFORM 13), up to '//itoa(patches%max_patch)//' nodes in a patch')
    dim = cells%dim
    n_all = cells%n_mesh_nodes + cells%n_enriched
    allocate(owned(cells%n))
    block
      logical :: owned_element(model%elements%n)
      owned_element = .false.
      owned_element(decomp%elem_global(1:decomp%nelem_local)) = .true.
      owned = owned_element(cells%elements(1, 1:cells%n))
    end block
    call np_pairs_build(patches, owned)
    allocate(np_pair_values(3, 3, size(patches%pair_node)))
    allocate(hist(NHIST, cells%n))
    do c = 1, cells%n
      call material_state_init(hist(:, c))
    end do
    allocate(fixed(dim, n_all), prescribed(dim, n_all), force(dim, n_all), u(dim, n_all), &
             internal(dim, n_all))
    u = 0.0_wp
    ! the fixed set is the same in every step (SPCs, TC codes, VAD=2 motions)
    fixed = .false.
    prescribed = 0.0_wp
    call fixed_dofs(model, 0.0_wp, fixed(:, 1:cells%n_mesh_nodes))
    call prescribed_displacements(model, 0.0_wp, fixed(:, 1:cells%n_mesh_nodes), &
                                  prescribed(:, 1:cells%n_mesh_nodes))
    call extra_nodes_follow(model, 0.0_wp, fixed(:, 1:cells%n_mesh_nodes), &
                            prescribed(:, 1:cells%n_mesh_nodes))
    ! tied contacts: a tied node's SPCs are overridden (it follows its masters)
    if (model%n_ties > 0) then
      call tied_contact_build(model, tied, status)
      if (.not. status%ok) call fatal('implicit: '//status%message)
      block                                   ! driven tied nodes or masters: refused
        logical, allocatable :: spc_fixed(:,:), driven(:,:)
        integer :: g
        allocate(spc_fixed(dim, cells%n_mesh_nodes))
        spc_fixed = .false.
        call fixed_dofs(model, 0.0_wp, spc_fixed)
        driven = fixed(:, 1:cells%n_mesh_nodes) .and. .not. spc_fixed
        do g = 1, cells%n_mesh_nodes
          if (any(driven(:, g)) .and. (any(tied%slave == g) .or. &
                                       any(tied%master_node == g))) call fatal('implicit: '// &
              'node '//itoa(model%nodes%id(g))//' of a tied contact has a prescribed '// &
              'motion: a tied node moves with its master facet; drive the bodies elsewhere')
        end do
      end block
      fixed(:, tied%slave) = .false.
      call say('implicit: tied contacts hold '//itoa(tied%n)//' nodes ('// &
               itoa(count(tied%dual))//' by dual mortar weights)')
    end if
    call number_equations(cells, fixed, equation, n_equations)
    if (model%n_ties > 0 .or. any([(model%spcs(k)%n_skew > 0, k = 1, model%n_spcs)]) .or. &
        any([(abs(model%motions(k)%dof) == 4 .and. model%motions(k)%target_kind /= ON_PART, &
              k = 1, model%n_motions)])) then
      block
        logical, allocatable :: spc_fixed(:,:)
        allocate(spc_fixed(dim, cells%n_mesh_nodes))
        spc_fixed = .false.
        call fixed_dofs(model, 0.0_wp, spc_fixed)
        if (model%n_ties > 0) spc_fixed(:, tied%slave) = .false.
        call constraints_set_up(model, equation, n_equations, &
                                fixed(:, 1:cells%n_mesh_nodes) .and. .not. spc_fixed, tied, skew)
      end block
      if (skew%n > 0) call say('implicit: '//itoa(skew%n)//' nodes with SPCs in turned '// &
                               'systems or motions along vectors (node frames)')
    end if
    call say('implicit: '//itoa(n_equations)//' equations, '//itoa(cells%n)//' cells')
    do k = 1, model%n_materials
      if (material_fails(model%materials(k))) call warn('implicit: material '// &
          itoa(model%materials(k)%id)//': its failure criteria are not used: the implicit '// &
          'analysis erodes no elements (the explicit analysis does)')
      if (spall_active(model%materials(k))) call warn('implicit: material '// &
          itoa(model%materials(k)%id)//': PC/SPALL and EROD are not used: the implicit '// &
          'analysis neither limits tension nor keeps failed points (the explicit analysis does)')
    end do
    if (n_equations == 0) call fatal('implicit: nothing to solve: every degree of freedom is '// &
        'fixed or belongs to a rigid part (the analysis needs deformable elements with free '// &
        'degrees of freedom)')
    call set_up_tools(model, cells, resume)
    call set_up_body_loads(model, cells)
    call set_up_histories(model, cells, equation, resume)
    if (.not. resume) call write_state(model, decomp, cells, u, hist, equation, 0.0_wp, 0)
    call mumps_init(solver, MUMPS_UNSYMMETRIC, status)
    if (.not. status%ok) call fatal('implicit: '//status%message)

    end_time = model%controls%end_time
    dt = model%controls%dt0
    if (dt <= 0.0_wp) dt = end_time/10.0_wp
    dt_max = model%controls%auto_dtmax
    if (dt_max <= 0.0_wp) dt_max = end_time
    dt_min = model%controls%auto_dtmin
    if (dt_min <= 0.0_wp) dt_min = 1.0e-6_wp*end_time
    call warn_output_every_step(model, dt_min, 'the smallest step, DTMIN,', 'step', &
                                .false.)
    next_output = output_interval(model)
    output_step = 1
    t = 0.0_wp
    step = 0
    cuts = 0
    dt_last = 0.0_wp
    u_last = u
    dumps = 0
    dump_step = -1
    next_dump = first_dump_time(model)
    if (resume) call read_restart_file()
    call sense_switch_warn_leftover()
    call signals_install()
    ! progress lines (% of ENDTIM, wall time, ETA) at every tenth of the run or every 5 s;
    ! the run's summary follows the loop (its own, with the solver's figures)
    call progress_start('implicit', end_time, 0, word='step')
    do while (t < end_time*(1.0_wp - 1.0e-12_wp))
      dt = min(dt, end_time - t)
      ! land on the next output time rather than step over it (then go on with the planned
      ! dt); an output interval below the smallest step the analysis may take (DTMIN) writes
      ! every step instead of cutting the steps down to it (a deck's DT of 1e-12 made 1e12
      ! steps)
      dt_planned = dt
      if (next_output > t .and. next_output - t < dt*(1.0_wp + 1.0e-9_wp) .and. &
          output_interval(model) >= dt_min) dt = next_output - t
      step = step + 1
      u_step = u
      ! predictor: the last converged increment extrapolated to this step (free dofs; the
      ! prescribed ones are set by newton_step). Starting each step from u_n alone puts the
      ! whole increment of a driven boundary into the cells next to it.
      if (dt_last > 0.0_wp) where (equation > 0) u = u + (dt/dt_last)*(u_step - u_last)
      ! the step's Newton iterations follow this line; the converged step's summary after them
      call say('step '//itoa(step)//': from t = '//rtoa(t)//' to '//rtoa(t + dt)//', dt = '// &
               rtoa(dt))
      call newton_step(model, cells, owned, equation, n_equations, t + dt, hist, u, &
                       tangent, solver, trial, iterations, converged, dt, u_step, internal)
      if (converged .and. tools%interfaces%n > 0) then
        call report_contact(t + dt, model%controls%rcforc_interval > 0.0_wp)
        if (tools%friction) tools%committed = tools%interfaces
      end if
      if (.not. converged) then
        u = u_step
        cuts = cuts + 1
        dt = 0.5_wp*dt
        call say('  step '//itoa(step)//' not converged: cut back to dt = '//rtoa(dt))
        if (dt < dt_min) then
          call write_state(model, decomp, cells, u, hist, equation, t, output_step)
          call fatal('implicit: the time step fell below its minimum '//rtoa(dt_min)// &
              ' at t = '//rtoa(t)//'; the last converged state (t = '//rtoa(t)// &
              ') was written')
        end if
        step = step - 1
        cycle
      end if
      t = t + dt
      u_last = u_step
      dt_last = dt
      ! commit the history: each cell's from the rank that computed it, known on every rank
      ! (output and reactions use all cells)
      do c = 1, cells%n
        if (.not. owned(c)) trial%hist_new(:, c) = 0.0_wp
      end do
      call comm_sum(trial%hist_new)
      hist = trial%hist_new
      call say('step '//itoa(step)//': t = '//rtoa(t)//', dt = '//rtoa(dt)//', '// &
               itoa(iterations)//' iterations')
      call progress_update(step, t, dt, final=t >= end_time*(1.0_wp - 1.0e-12_wp))
      call account_energy(model, cells, equation, u, t, internal)
      if (energy%glstat_interval > 0.0_wp .and. (t >= energy%next_glstat*(1.0_wp - 1.0e-9_wp) &
          .or. t >= end_time*(1.0_wp - 1.0e-12_wp))) then
        call write_histories(model, step, t, dt)
        energy%next_glstat = schedule_after(energy%next_glstat, energy%glstat_interval, t)
      end if
      if (dt < dt_planned) dt = dt_planned
      ! step growth when the Newton loop was easy (*CONTROL_IMPLICIT_AUTO ITEOPT/ITEWIN): the
      ! next step's size, as a restart file written after this step keeps it
      if (model%controls%iauto /= 0 .and. iterations <= max(1, model%controls%iteopt - &
          model%controls%itewin)) dt = min(dt_max, 1.5_wp*dt)
      written = .false.
      if (t >= next_output*(1.0_wp - 1.0e-9_wp) .or. t >= end_time*(1.0_wp - 1.0e-12_wp)) then
        call write_state(model, decomp, cells, u, hist, equation, t, output_step)
        output_step = output_step + 1
        next_output = schedule_after(next_output, output_interval(model), t)
        written = .true.
      end if
      ! restart files every CYCL steps (*DATABASE_BINARY_D3DUMP, _RUNRSF)
      call restart_files_due(model, step, t, next_dump, dump_due, runrsf_due)
      if (dump_due) call write_restart_file(next_dump_name())
      if (runrsf_due) call write_restart_file('runrsf')
      ! a signal caught on any rank (mefem_signals): stop, the state reached and a restart
      ! file written
      signum = signal_caught()
      call comm_max(signum)
      if (signum /= 0) then
        if (dump_step /= step) call write_restart_file(next_dump_name())
        if (.not. written) call write_state(model, decomp, cells, u, hist, equation, t, &
                                            output_step)
        call signal_record_stop(signum)
        call say('implicit: '//signal_name(signum)//': stopped after step '//itoa(step)// &
                 ', t = '//rtoa(t)//'; the state reached and a restart file are written')
        exit
      end if
      ! LS-DYNA's d3kil file: stop (the state reached and a restart file written), status, a
      ! restart file or a state now
      action = sense_switch()
      if (iand(action, ior(SENSE_STOP, SENSE_RESTART)) /= 0 .and. dump_step /= step) &
        call write_restart_file(next_dump_name())
      if (iand(action, SENSE_STOP + SENSE_STATE) /= 0 .and. .not. written) then
        call write_state(model, decomp, cells, u, hist, equation, t, output_step)
        output_step = output_step + 1
      end if
      if (iand(action, SENSE_STATUS) /= 0) call say('implicit: d3kil (sw2): step '// &
          itoa(step)//', t = '//rtoa(t)//' of '//rtoa(end_time)//', dt = '//rtoa(dt))
      if (iand(action, SENSE_STATE) /= 0 .and. iand(action, SENSE_STOP) == 0) &
        call say('implicit: d3kil (sw4): result state written at t = '//rtoa(t))
      if (iand(action, SENSE_STOP) /= 0) then
        call say('implicit: d3kil (sw1): stopped after step '//itoa(step)//', t = '//rtoa(t)// &
                 '; the state reached and a restart file are written')
        exit
      end if
    end do
    if (model%controls%d3dump_cycles > 0 .and. dump_step /= step) &
      call write_restart_file(next_dump_name())         ! (at the end, as LS-DYNA does)
    call report_solver_memory(solver)
    call mumps_free(solver)
    call coo_free(tangent)
    call rcforc_close()
    call glstat_close()
    call rbdout_close()
    call say('implicit: '//itoa(step)//' steps, '//itoa(cuts)//' cut-backs, '// &
             itoa(timing%iterations)//' Newton iterations, '//rtoa(comm_wtime() - t0)//' s')
    if (timing%iterations > 0) call say('implicit: per iteration: assembly '// &
        rtoa(timing%assembly/timing%iterations)//' s, MUMPS factorisation '// &
        rtoa(timing%factorisation/timing%iterations)//' s, solve '// &
        rtoa(timing%solve/timing%iterations)//' s')
  contains

    !> The name of the next restart file of the series: d3dump01, d3dump02, ...
    function next_dump_name() result(name)
      character(len=:), allocatable :: name
      dumps = dumps + 1
      name = restart_dump_name(dumps)
    end function next_dump_name

    !> Write a restart file of the state after this converged step into the output directory
    !> (collective; the state is on every rank, rank 0 writes it): the time and step sizes, u
    !> of this and of the last step (the predictor's), the cells' histories, the energy sums,
    !> the tools' contact (and its committed copy with friction), the output schedule.
    subroutine write_restart_file(name)
      character(len=*), intent(in) :: name            !< file name (d3dump01, runrsf)
      real(wp) :: clock
      logical :: ok
      clock = comm_wtime()
      call restart_create(restart, results_directory()//'/'//name)
      call results_restart_header_put(restart)
      call restart_put_text(restart, 'analysis', 'implicit')
      call restart_put_ints(restart, 'model.sizes', 5, restart_sizes())
      call restart_put_reals(restart, 'model.coordinates', 1, &
                             [restart_checksum(model%nodes%x(:, 1:model%nodes%n))])
      call restart_put_ints(restart, 'run.steps', 4, [step, cuts, output_step, dumps])
      call restart_put_reals(restart, 'run.times', 6, [t, dt, dt_last, next_output, &
                             energy%next_glstat, next_dump])
      call restart_put_reals(restart, 'nodes.u', size(u), u)
      call restart_put_reals(restart, 'nodes.u_last', size(u_last), u_last)
      call restart_put_reals(restart, 'cells.history', size(hist), hist)
      call restart_put_reals(restart, 'energies', 3, [energy%internal, energy%external, &
                                                      energy%contact])
      call restart_put_reals(restart, 'energy.f_int', size(energy%f_int), energy%f_int)
      call restart_put_reals(restart, 'energy.u', size(energy%u), energy%u)
      call restart_put_reals(restart, 'energy.g', size(energy%g), energy%g)
      if (tools%interfaces%n > 0) then
        call restart_put_reals(restart, 'energy.f_contact', size(energy%f_contact), &
                               energy%f_contact)
        call restart_put_reals(restart, 'energy.x_contact', size(energy%x_contact), &
                               energy%x_contact)
      end if
      if (allocated(energy%tool_d)) call restart_put_reals(restart, 'energy.tool_d', &
          size(energy%tool_d), energy%tool_d)
      call mortar_contact_restart_put(tools%interfaces, restart)
      if (tools%friction) call mortar_contact_restart_put(tools%committed, restart)
      call results_restart_put(restart)
      call restart_commit(restart, ok)
      dump_step = step
      if (ok) call say('implicit: restart file '//name//' written after step '//itoa(step)// &
                       ', t = '//rtoa(t)//' in '//rtoa(comm_wtime() - clock)//' s (mefem r='// &
                       results_directory()//'/'//name//' continues from it)')
    end subroutine write_restart_file

    !> Continue from a restart file of this model (every rank reads it all), and open the
    !> histories after it (cut back to where the file left them).
    subroutine read_restart_file()
      character(len=:), allocatable :: text
      integer :: sizes(5), steps(4)
      real(wp) :: times(6), sums(3), checksum(1)
      call restart_open(restart, restart_path)
      call results_restart_header_skip(restart)
      call restart_get_text(restart, 'analysis', text)
      if (text /= 'implicit') call fatal('restart file "'//restart_path//'" was written by '// &
          'the '//text//' analysis; this deck runs the nonlinear implicit analysis')
      call restart_get_ints(restart, 'model.sizes', 5, sizes)
      call restart_get_reals(restart, 'model.coordinates', 1, checksum)
      if (any(sizes /= restart_sizes()) .or. &
          checksum(1) /= restart_checksum(model%nodes%x(:, 1:model%nodes%n))) &
        call fatal('restart file "'//restart_path//'" was written for another model (nodes, '// &
                   'elements, cells, contacts or coordinates differ): restart with the deck '// &
                   'it was written with')
      call restart_get_ints(restart, 'run.steps', 4, steps)
      step = steps(1)
      cuts = steps(2)
      output_step = steps(3)
      dumps = steps(4)
      call restart_get_reals(restart, 'run.times', 6, times)
      t = times(1)
      dt = times(2)
      dt_last = times(3)
      next_output = times(4)
      energy%next_glstat = times(5)
      next_dump = times(6)
      call restart_get_reals(restart, 'nodes.u', size(u), u)
      call restart_get_reals(restart, 'nodes.u_last', size(u_last), u_last)
      call restart_get_reals(restart, 'cells.history', size(hist), hist)
      call restart_get_reals(restart, 'energies', 3, sums)
      energy%internal = sums(1)
      energy%external = sums(2)
      energy%contact = sums(3)
      call restart_get_reals(restart, 'energy.f_int', size(energy%f_int), energy%f_int)
      call restart_get_reals(restart, 'energy.u', size(energy%u), energy%u)
      call restart_get_reals(restart, 'energy.g', size(energy%g), energy%g)
      if (tools%interfaces%n > 0) then
        call restart_get_reals(restart, 'energy.f_contact', size(energy%f_contact), &
                               energy%f_contact)
        call restart_get_reals(restart, 'energy.x_contact', size(energy%x_contact), &
                               energy%x_contact)
      end if
      if (allocated(energy%tool_d)) call restart_get_reals(restart, 'energy.tool_d', &
          size(energy%tool_d), energy%tool_d)
      call mortar_contact_restart_get(tools%interfaces, restart)
      if (tools%friction) call mortar_contact_restart_get(tools%committed, restart)
      call results_restart_get(restart)
      call restart_close(restart)
      dump_step = step
      ! the histories, continued
      if (energy%glstat_interval > 0.0_wp) call glstat_open(results_directory(), &
          title_or_default(model%controls%title), append=.true.)
      if (energy%glstat_interval > 0.0_wp .and. energy%rbdout) call rbdout_open( &
          results_directory(), title_or_default(model%controls%title), append=.true.)
      if (tools%interfaces%n > 0 .and. model%controls%rcforc_interval > 0.0_wp) &
        call rcforc_open(results_directory(), title_or_default(model%controls%title), &
                         append=.true.)
      call say('implicit: restarted from '//restart_path//' after step '//itoa(step)// &
               ', t = '//rtoa(t)//'; next step '//rtoa(dt))
    end subroutine read_restart_file

    !> Sizes that identify the model a restart file belongs to.
    function restart_sizes() result(sizes)
      integer :: sizes(5)
      sizes = [model%nodes%n, model%elements%n, n_all, cells%n, tools%interfaces%n]
    end function restart_sizes
  end subroutine implicit_static_run

  !> The implicit analyses (this one and the linear static one) write their state 0
  !> themselves: every array of the later states, at t = 0, and the node sets.
  logical function implicit_writes_initial_state(model)
    type(model_t), intent(in) :: model                 !< resolved model
    implicit_writes_initial_state = model%controls%imflag == 1
  end function implicit_writes_initial_state

  !> glstat and rbdout of the quasi-static run (at *DATABASE_GLSTAT's interval, as the explicit
  !> analysis writes them): the files opened, the first record at t = 0, the energies' start
  !> (energy_t) and each tool's reference centroid (rbdout's moments are taken about it).
  subroutine set_up_histories(model, cells, equation, resume)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    integer, intent(in) :: equation(:,:)               !< equation numbers
    logical, intent(in) :: resume                      !< a restart: the files are continued
                                                       !< (opened by open_histories_again)
    real(wp), allocatable :: zero(:,:)
    integer, allocatable :: count(:)
    integer :: n, p
    energy%glstat_interval = model%controls%glstat_interval
    allocate(zero(cells%dim, cells%n_mesh_nodes + cells%n_enriched))
    zero = 0.0_wp
    call account_energy(model, cells, equation, zero, 0.0_wp, zero)
    if (energy%glstat_interval <= 0.0_wp) return
    if (.not. resume) call glstat_open(results_directory(), title_or_default(model%controls%title))
    allocate(energy%tool_centre(3, model%n_parts), energy%tool_d(3, model%n_parts), &
             count(model%n_parts))
    energy%tool_centre = 0.0_wp
    energy%tool_d = 0.0_wp
    count = 0
    do n = 1, model%nodes%n
      p = tools%rigid_part(n)
      if (p == 0) cycle
      energy%tool_centre(:, p) = energy%tool_centre(:, p) + model%nodes%x(:, n)
      count(p) = count(p) + 1
    end do
    do p = 1, model%n_parts
      if (count(p) > 0) energy%tool_centre(:, p) = energy%tool_centre(:, p)/count(p)
    end do
    energy%rbdout = any(count > 0)
    if (resume) return
    if (energy%rbdout) call rbdout_open(results_directory(), &
                                        title_or_default(model%controls%title))
    call write_histories(model, 0, 0.0_wp, 0.0_wp)
    energy%next_glstat = schedule_after(0.0_wp, energy%glstat_interval, 0.0_wp)
  end subroutine set_up_histories

  !> The energies (energy_t) from the last converged state to this one (u, t, its internal
  !> forces f_int): the trapezoidal rule on the forces of both states. The first call (at
  !> t = 0, u = 0, f_int = 0) only stores the start.
  subroutine account_energy(model, cells, equation, u, t, internal)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    integer, intent(in) :: equation(:,:)               !< equation numbers (0: fixed dof)
    real(wp), intent(in) :: u(:,:)                     !< (dim, all nodes) converged u
    real(wp), intent(in) :: t                          !< its time
    real(wp), intent(in) :: internal(:,:)              !< (dim, all nodes) its f_int
    real(wp), allocatable :: g(:,:), f_contact(:,:), x_contact(:,:)
    real(wp) :: work
    integer :: dim, n, k, p
    dim = cells%dim
    ! external forces on the deformable body: the loads where the dof is free, f_int minus the
    ! contact force (the load and the reaction together) where it is fixed
    allocate(g(dim, size(u, 2)))
    g = 0.0_wp
    call external_forces(model, t, g(:, 1:cells%n_mesh_nodes))
    if (model%n_body_loads > 0) call add_body_forces(body_acceleration(model, t), &
                                                     loaded_mass, g)
    where (equation == 0) g = internal
    if (skew%n > 0) call constraints_reaction(skew, internal, g)    ! (motions along vectors)
    allocate(f_contact(3, tools%interfaces%nnode), x_contact(3, tools%interfaces%nnode))
    do k = 1, tools%interfaces%nnode
      n = tools%interfaces%node_global(k)
      f_contact(:, k) = 0.0_wp
      if (allocated(tools%interfaces%force) .and. t > 0.0_wp) &
        f_contact(:, k) = tools%interfaces%force(:, k)
      x_contact(:, k) = model%nodes%x(:, n)
      p = tools%rigid_part(n)
      if (p > 0) then
        x_contact(:, k) = x_contact(:, k) + tool_displacement(model, p, t)
      else
        x_contact(1:dim, k) = x_contact(1:dim, k) + u(:, n)
        where (equation(:, n) == 0) g(:, n) = g(:, n) - f_contact(1:dim, k)
      end if
    end do
    do n = 1, cells%n_mesh_nodes
      if (tools%rigid_part(n) > 0) g(:, n) = 0.0_wp     ! a tool's drive: from x_contact
    end do
    if (allocated(energy%u)) then
      energy%internal = energy%internal + 0.5_wp*sum((energy%f_int + internal)*(u - energy%u))
      energy%external = energy%external + 0.5_wp*sum((energy%g + g)*(u - energy%u))
      do k = 1, tools%interfaces%nnode
        work = 0.5_wp*dot_product(energy%f_contact(:, k) + f_contact(:, k), &
                                  x_contact(:, k) - energy%x_contact(:, k))
        energy%contact = energy%contact - work
        if (tools%rigid_part(tools%interfaces%node_global(k)) > 0) &
          energy%external = energy%external - work
      end do
    end if
    energy%u = u
    energy%f_int = internal
    energy%g = g
    energy%f_contact = f_contact
    energy%x_contact = x_contact
  end subroutine account_energy

  !> One glstat record of the energies and, with tools, one rbdout row per tool: its
  !> translation, velocity (the last step's mean), the force its drive applies (minus the
  !> contact forces on it) and that force's moment about its reference centroid, moved.
  subroutine write_histories(model, step, t, dt)
    type(model_t), intent(in) :: model                 !< resolved model
    integer, intent(in) :: step                        !< step number (0: the start)
    real(wp), intent(in) :: t                          !< time
    real(wp), intent(in) :: dt                         !< the last step
    type(glstat_record_t) :: rec
    real(wp), allocatable :: values(:,:)
    real(wp) :: d(3), arm(3), force(3)
    integer, allocatable :: ids(:)
    integer :: p, k, n, m
    rec%cycle = step
    rec%time = t
    rec%time_step = dt
    rec%controlled_by = merge('*CONTROL_IMPLICIT_AUTO   ', '*CONTROL_IMPLICIT_GENERAL', &
                              model%controls%iauto /= 0)
    rec%internal_energy = energy%internal
    rec%external_work = energy%external
    rec%contact_energy = energy%contact
    rec%total_energy = glstat_total_energy(rec)
    rec%energy_ratio = glstat_energy_ratio(rec%total_energy, 0.0_wp, rec%external_work)
    rec%energy_ratio_uneroded = rec%energy_ratio
    call glstat_write(rec)
    if (.not. energy%rbdout) return
    allocate(ids(model%n_parts), values(12, model%n_parts))
    m = 0
    do p = 1, model%n_parts
      if (.not. any(tools%rigid_part == p)) cycle
      m = m + 1
      ids(m) = model%parts(p)%id
      d = tool_displacement(model, p, t)
      values(1:3, m) = d
      values(4:6, m) = 0.0_wp
      if (dt > 0.0_wp) values(4:6, m) = (d - energy%tool_d(:, p))/dt
      energy%tool_d(:, p) = d
      values(7:12, m) = 0.0_wp
      do k = 1, tools%interfaces%nnode
        n = tools%interfaces%node_global(k)
        if (tools%rigid_part(n) /= p) cycle
        force = -energy%f_contact(:, k)
        arm = energy%x_contact(:, k) - (energy%tool_centre(:, p) + d)
        values(7:9, m) = values(7:9, m) + force
        values(10:12, m) = values(10:12, m) + [arm(2)*force(3) - arm(3)*force(2), &
            arm(3)*force(1) - arm(1)*force(3), arm(1)*force(2) - arm(2)*force(1)]
      end do
    end do
    call rbdout_write(t, ids(1:m), values(:, 1:m))
  end subroutine write_histories

  !> The last factorisation's size and memory (MUMPS INFOG) and the peak resident memory of
  !> the run (VmHWM) in the log: what a user needs to size a larger model.
  subroutine report_solver_memory(solver)
    type(mumps_solver_t), intent(in) :: solver   !< the factorised solver
    type(mumps_stats_t) :: stats
    real(wp) :: memory, memory_max
    stats = mumps_stats(solver)
    memory = peak_memory_mib()
    memory_max = memory
    call comm_max(memory_max)
    if (stats%n_factorisations > 0) call say('implicit: MUMPS ('// &
        ordering_name(stats%ordering_used)//' ordering): '// &
        rtoa(real(stats%factor_entries, wp))//' entries in the factors, '// &
        itoa(stats%memory_max_mb)//' MB max per rank, '//itoa(stats%memory_total_mb)// &
        ' MB on all ranks; analysis '//rtoa(stats%time_analysis)//' s')
    call say('implicit: peak memory '//rtoa(memory)//' MiB on rank 0, '//rtoa(memory_max)// &
             ' MiB max over ranks')
  end subroutine report_solver_memory

  !> Time between output states: *DATABASE_BINARY_D3PLOT DT (or ENDTIM/NPLTC), else the end.
  real(wp) function output_interval(model)
    type(model_t), intent(in) :: model   !< resolved model
    output_interval = model%controls%plot_interval
    if (model%controls%plot_count > 0) output_interval = model%controls%end_time/ &
        real(model%controls%plot_count, wp)
    if (output_interval <= 0.0_wp) output_interval = model%controls%end_time
  end function output_interval

  !> Nonlinear statics takes deformable parts, displacement-type motions on nodes, and
  !> frictionless contact with rigid tools (rigid parts moved by translations, VAD=2 DOF 1-3).
  subroutine check_supported(model)
    type(model_t), intent(in) :: model   !< resolved model
    integer :: k, e, p
    logical, allocatable :: rigid(:), in_rigid(:), in_deformable(:)
    allocate(rigid(model%n_parts), in_rigid(model%nodes%n), in_deformable(model%nodes%n))
    do p = 1, model%n_parts
      rigid(p) = .false.
      if (model%parts(p)%material > 0) rigid(p) = &
          model%materials(model%parts(p)%material)%kind == MAT_RIGID
    end do
    do k = 1, model%n_motions
      associate (pm => model%motions(k))
        if (pm%vad /= 2) call fatal('implicit analysis takes prescribed displacements '// &
            '(VAD=2) only; see *BOUNDARY_PRESCRIBED_MOTION at line '//itoa(pm%src%line))
        if (pm%target_kind == ON_PART .and. (pm%dof < 1 .or. pm%dof > 3)) call fatal( &
            'implicit analysis moves rigid tools by translations (DOF 1-3) only; see '// &
            '*BOUNDARY_PRESCRIBED_MOTION_RIGID at line '//itoa(pm%src%line))

      end associate
    end do
    do k = 1, model%n_spcs
      if (model%spcs(k)%n_skew > 0 .and. model%spcs(k)%moving_system > 0) call fatal( &
          'implicit analysis takes SPCs in fixed systems only; CID '// &
          itoa(model%spcs(k)%cid)//' moves with its nodes (FLAG 1: explicit only); see '// &
          '*BOUNDARY_SPC at line '//itoa(model%spcs(k)%src%line))
    end do
    if (model%n_rigid_walls > 0) call fatal('implicit analysis does not take rigid walls '// &
        '(use a rigid part as a contact tool)')
    do k = 1, model%n_rigid_constraints
      if (model%rigid_constraints(k)%kind /= RIGID_EXTRA_NODES) call fatal('implicit '// &
          'analysis does not take *CONSTRAINED_RIGID_BODIES, *CONSTRAINED_NODAL_RIGID_BODY '// &
          'or *CONSTRAINED_SPOTWELD (rigid parts are driven tools there; their extra nodes '// &
          'follow them); see line '//itoa(model%rigid_constraints(k)%src%line))
    end do
    if (model%n_transducers > 0) call warn('implicit: force transducers '// &
        '(*CONTACT_FORCE_TRANSDUCER_PENALTY) are written by the explicit analysis only; '// &
        'rcforc has the contacts'' own forces')
    do k = 1, model%n_ties
      if (model%ties(k)%tiebreak /= TIEBREAK_NONE) call fatal('implicit analysis takes tied '// &
          'contacts that do not fail: a tiebreak is explicit only; see the contact at line '// &
          itoa(model%ties(k)%src%line))
    end do
    do k = 1, model%n_contacts
      if (model%contacts(k)%single_surface) call fatal('implicit analysis takes contact with '// &
          'rigid tools only: a single-surface contact is explicit only; see '// &
          '*CONTACT_AUTOMATIC_SINGLE_SURFACE at line '//itoa(model%contacts(k)%src%line))
      if (model%contacts(k)%ignore /= 0) call fatal('implicit analysis takes IGNORE = 0 only '// &
          '(initial penetrations are pushed out); see the contact at line '// &
          itoa(model%contacts(k)%src%line))
    end do
    if (model%controls%end_time <= 0.0_wp) call fatal('implicit analysis needs '// &
        '*CONTROL_TERMINATION ENDTIM')
    ! rigid parts are tools: their nodes may not be shared with deformable elements
    in_rigid = .false.
    in_deformable = .false.
    do e = 1, model%elements%n
      associate (conn => model%elements%conn(:, e))
        if (rigid(model%elements%part(e))) then
          where (conn > 0) in_rigid(max(conn, 1)) = .true.
        else
          where (conn > 0) in_deformable(max(conn, 1)) = .true.
        end if
      end associate
    end do
    if (any(in_rigid .and. in_deformable)) call fatal('implicit analysis takes rigid parts as '// &
        'contact tools only: a rigid part shares nodes with deformable elements')
  end subroutine check_supported

  !> One load step by Newton-Raphson; u holds the converged displacements on success.
  subroutine newton_step(model, cells, owned, equation, n_equations, t_new, hist, u, tangent, &
                         solver, trial, iterations, converged, dt, u_committed, internal)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    logical, intent(in) :: owned(:)                    !< cells this rank computes
    integer, intent(in) :: equation(:,:)               !< equation numbers
    integer, intent(in) :: n_equations                 !< number of equations
    real(wp), intent(in) :: t_new                      !< time at the end of the step
    real(wp), intent(in) :: hist(:,:)                  !< converged history
    real(wp), intent(inout) :: u(:,:)                  !< displacements
    type(coo_matrix_t), intent(inout) :: tangent       !< tangent matrix (pattern kept)
    type(mumps_solver_t), intent(inout) :: solver      !< linear solver
    type(cell_state_t), intent(inout) :: trial         !< trial history and stress
    integer, intent(out) :: iterations                 !< iterations used
    logical, intent(out) :: converged                  !< the step converged
    real(wp), intent(in) :: dt                         !< the step (strain rates)
    real(wp), intent(in) :: u_committed(:,:)           !< the converged u of the step's start
    real(wp), intent(out) :: internal(:,:)             !< (dim, all nodes) f_int at the
                                                       !< converged u (when converged)
    real(wp), allocatable :: residual(:), du(:), force(:,:), fixed_u(:,:), u_start(:,:)
    real(wp), allocatable :: du_global(:)
    logical, allocatable :: fixed(:,:)
    type(status_t) :: status
    real(wp) :: energy0, energy, norm_du, norm_step, norm_r, norm_r0, ratio
    real(wp) :: last_energy, slope, step_length, clock, force_scale
    !> a residual this small against the internal forces is round-off: converged
    real(wp), parameter :: ROUNDOFF_FLOOR = 1.0e-9_wp
    integer :: k, dim
    logical :: ok
    dim = cells%dim
    allocate(residual(n_equations), du(n_equations), force(dim, size(u, 2)), &
             fixed_u(dim, size(u, 2)), fixed(dim, size(u, 2)))
    internal = 0.0_wp
    ! prescribed displacements of the new time
    fixed = .false.
    fixed_u = u
    call prescribed_displacements(model, t_new, fixed(:, 1:cells%n_mesh_nodes), &
                                  fixed_u(:, 1:cells%n_mesh_nodes))
    call extra_nodes_follow(model, t_new, fixed(:, 1:cells%n_mesh_nodes), &
                            fixed_u(:, 1:cells%n_mesh_nodes))
    where (fixed) u = fixed_u
    ! skew conditions and motions along vectors: the frames of the new time, the driven nodes
    ! moved along their vectors
    if (skew%n > 0) then
      call constraints_activate(model, t_new, skew)
      call constraints_prescribe(skew, u)
    end if
    u_start = u
    force = 0.0_wp
    call external_forces(model, t_new, force(:, 1:cells%n_mesh_nodes))
    if (model%n_body_loads > 0) call add_body_forces(body_acceleration(model, t_new), &
                                                     loaded_mass, force)
    converged = .false.
    energy0 = 0.0_wp
    norm_r0 = 0.0_wp
    do k = 1, max(1, model%controls%maxref)
      iterations = k
      clock = comm_wtime()
      if (k == 1) then                   ! (f_int of the first iterate: the forces' scale)
        call evaluate_cells(model, cells, owned, equation, u, hist, force, residual, tangent, &
                            trial, ok, t_new, u_committed, dt, internal)
        force_scale = norm2(internal)
      else
        call evaluate_cells(model, cells, owned, equation, u, hist, force, residual, tangent, &
                            trial, ok, t_new, u_committed, dt)
      end if
      timing%assembly = timing%assembly + (comm_wtime() - clock)
      timing%iterations = timing%iterations + 1
      if (.not. ok) return                                  ! a cell inverted: cut the step
      if (skew%active) call constraints_residual(skew, residual)
      ! line search (LSTOL): if the last increment left too much energy, g(1) = du.R(u), take
      ! the secant step s = g(0)/(g(0) - g(1)) in [0.1, 1] along it and re-evaluate
      if (k > 1 .and. model%controls%lstol > 0.0_wp) then
        slope = dot_product(du, residual)
        if (abs(slope) > model%controls%lstol*last_energy .and. last_energy - slope > 0.0_wp) then
          step_length = min(1.0_wp, max(0.1_wp, last_energy/(last_energy - slope)))
          if (step_length < 1.0_wp) then
            call add_global_increment(step_length - 1.0_wp)
            call evaluate_cells(model, cells, owned, equation, u, hist, force, residual, &
                                tangent, trial, ok, t_new, u_committed, dt)
            if (.not. ok) return
            if (skew%active) call constraints_residual(skew, residual)
            if (model%controls%nlprint > 0) call say('  line search: step length '// &
                rtoa(step_length))
          end if
        end if
      end if
      norm_r = norm2(residual)
      if (k == 1) norm_r0 = max(norm_r, tiny(1.0_wp))
      clock = comm_wtime()
      if (skew%active) then
        call constraints_matrix(skew, tangent, skew_tangent)
        call mumps_factorise(solver, skew_tangent, status)
      else
        call mumps_factorise(solver, tangent, status)
      end if
      timing%factorisation = timing%factorisation + (comm_wtime() - clock)
      clock = comm_wtime()
      if (status%ok) call mumps_solve(solver, residual, du, status)
      timing%solve = timing%solve + (comm_wtime() - clock)
      if (.not. status%ok) then
        call say('  iteration '//itoa(k)//': '//status%message)
        return
      end if
      last_energy = dot_product(du, residual)
      energy = abs(last_energy)
      if (k == 1) energy0 = max(energy, tiny(1.0_wp))
      call add_global_increment(1.0_wp)
      norm_du = norm2(du)
      norm_step = norm2(u - u_start)
      ratio = norm_r/norm_r0
      if (k == 1) then                 ! (the energy ratio is 1 by definition)
        call say('  iteration 1: |R| = '//rtoa(norm_r)//' (1)')
      else
        call say('  iteration '//itoa(k)//': |R| = '//rtoa(norm_r)//' ('//rtoa(ratio)// &
                 '), |du|/|u_step| = '//rtoa(norm_du/max(norm_step, tiny(1.0_wp)))// &
                 ', energy ratio '//rtoa(energy/energy0))
      end if
      if (norm_r /= norm_r) return                          ! NaN: cut the step
      ! converged: the residual at round-off (ROUNDOFF_FLOOR of the internal forces, reactions
      ! included: e.g. a linear step the predictor already solved), below ABSTOL, or all the
      ! relative criteria met
      if (norm_r <= ROUNDOFF_FLOOR*force_scale .or. norm_r < model%controls%abstol .or. &
          (k > 1 .and. &
          norm_du <= model%controls%dctol*norm_step .and. &
          energy <= model%controls%ectol*energy0 .and. ratio <= model%controls%rctol)) then
        ! one more evaluation so that history, stress and f_int belong to the final u
        call evaluate_cells(model, cells, owned, equation, u, hist, force, residual, &
                            tangent, trial, ok, t_new, u_committed, dt, internal)
        converged = ok
        return
      end if
      if (k > 2 .and. norm_r > 1.0e6_wp*norm_r0) return     ! diverging
    end do
  contains
    !> u += factor du, du taken back from the constraints' unknowns (T du).
    subroutine add_global_increment(factor)
      real(wp), intent(in) :: factor                 !< multiple of du
      if (.not. skew%active) then
        call add_increment(u, equation, du, factor)
        return
      end if
      du_global = du
      call constraints_increment(skew, du_global)
      call add_increment(u, equation, du_global, factor)
    end subroutine add_global_increment
  end subroutine newton_step

  !> The loaded masses of the body loads: lumped masses of the nodes of the parts they act on
  !> (the same on every rank; the loads are added to the residual once, on rank 0).
  subroutine set_up_body_loads(model, cells)
    type(model_t), intent(in) :: model              !< resolved model
    type(cells_t), intent(in) :: cells              !< cells
    logical, allocatable :: loaded(:)
    if (allocated(loaded_mass)) deallocate(loaded_mass)
    call lumped_mass(model, cells, .false., loaded_mass)
    if (model%n_body_loads == 0) then
      loaded_mass = 0.0_wp
      return
    end if
    call body_load_nodes(model, cells, loaded)
    where (.not. loaded) loaded_mass = 0.0_wp
  end subroutine set_up_body_loads

  !> u = u + factor du at the free degrees of freedom.
  pure subroutine add_increment(u, equation, du, factor)
    real(wp), intent(inout) :: u(:,:)        !< (dim, nodes) displacements
    integer, intent(in) :: equation(:,:)     !< equation numbers
    real(wp), intent(in) :: du(:)            !< increment of the free dofs
    real(wp), intent(in) :: factor           !< multiple of du to add
    integer :: n, i
    do n = 1, size(u, 2)
      do i = 1, size(u, 1)
        if (equation(i, n) > 0) u(i, n) = u(i, n) + factor*du(equation(i, n))
      end do
    end do
  end subroutine add_increment

  !> Residual f_ext - f_int and tangent of all owned cells at displacements u.
  subroutine evaluate_cells(model, cells, owned, equation, u, hist, force_ext, residual, &
                            tangent, trial, ok, t, u_old, dt, internal)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    logical, intent(in) :: owned(:)                    !< cells this rank computes
    integer, intent(in) :: equation(:,:)               !< equation numbers
    real(wp), intent(in) :: u(:,:)                     !< displacements
    real(wp), intent(in) :: hist(:,:)                  !< converged history
    real(wp), intent(in) :: force_ext(:,:)             !< external forces
    real(wp), intent(out) :: residual(:)               !< free-dof residual, summed over ranks
    type(coo_matrix_t), intent(inout) :: tangent       !< tangent matrix
    type(cell_state_t), intent(inout) :: trial         !< trial history and Cauchy stress
    logical, intent(out) :: ok                         !< no cell failed (on every rank)
    real(wp), intent(in) :: t                          !< time of u (tool positions)
    real(wp), intent(in) :: u_old(:,:)                 !< displacements at the step's start
    real(wp), intent(in) :: dt                         !< the step (strain rates)
    real(wp), intent(out), optional :: internal(:,:)   !< (dim, all nodes) internal forces
                                                       !< f_int of all cells, summed over ranks
    real(wp) :: f(3, 3), finv(3, 3), tau(3, 3), c(3, 3, 3, 3), fc(3, CELL_MAX_NODES), det, sound
    real(wp) :: f_old(3, 3), rate, d(3, 3)
    real(wp) :: ke(3*CELL_MAX_NODES, 3*CELL_MAX_NODES), ue(3, CELL_MAX_NODES)
    real(wp) :: kh(3*CELL_MAX_NODES, 3*CELL_MAX_NODES), fh(3, CELL_MAX_NODES), energy
    integer :: dofs(3*CELL_MAX_NODES), cell, nn, nd, dim, a, i, n
    type(status_t) :: status
    logical :: failed
    dim = cells%dim
    if (.not. allocated(trial%hist_new)) then
      allocate(trial%hist_new(NHIST, cells%n), trial%cauchy(6, cells%n))
      call coo_init(tangent, maxval(equation), int(count(owned), kind(1))*(dim*6)**2)
    else
      call coo_reset_values(tangent)
    end if
    trial%hist_new = hist
    trial%cauchy = 0.0_wp
    residual = 0.0_wp
    if (present(internal)) internal = 0.0_wp
    failed = .false.
    if (patches%n > 0) call nodal_pressure_materials(model, cells, u, hist, trial%hist_new, &
                                                     .false., failed, u_old, dt)
    np_pair_values = 0.0_wp
    do cell = 1, cells%n
      if (.not. owned(cell)) cycle
      nn = cells%nnodes(cell)
      nd = dim*nn
      if (patches%n > 0) then
        if (patches%index_of(cell) > 0) then         ! ELFORM 13: the means' forces, tangent
          if (failed) cycle
          call nodal_pressure_cell(cell, residual, tangent, internal)
          cycle
        end if
      end if
      ue(1:dim, 1:nn) = u(:, cells%nodes(1:nn, cell))
      call cell_deformation_gradient(dim, nn, cells%grad(:, :, cell), ue, f)
      ! rate effects: the effective strain rate sqrt(d : d) of the step, d = sym((F - F_n)
      ! F^-1)/dt (doc/theory.md section 4; its dependence on u is left out of the tangent)
      rate = 0.0_wp
      if (rate_dependent(model%materials(cells%material(cell))) .and. dt > 0.0_wp) then
        ue(1:dim, 1:nn) = u_old(:, cells%nodes(1:nn, cell))
        call cell_deformation_gradient(dim, nn, cells%grad(:, :, cell), ue, f_old)
        ue(1:dim, 1:nn) = u(:, cells%nodes(1:nn, cell))
        call inverse_3x3(f, finv, det)
        d = matmul(f - f_old, finv)/dt
        rate = sqrt(sum((0.5_wp*(d + transpose(d)))**2))
      end if
      call material_update(model%materials(cells%material(cell)), model%curves, f, &
                           hist(:, cell), trial%hist_new(:, cell), tau, c, sound, status, &
                           strain_rate=rate, dt=dt)
      if (.not. status%ok) then
        if (.not. failed) call say('  cell '//itoa(cell)//' (element '// &
            itoa(model%elements%id(cells%elements(1, cell)))//'): '//status%message)
        failed = .true.
        cycle
      end if
      call inverse_3x3(f, finv, det)
      trial%cauchy(:, cell) = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), &
                               tau(3, 1)]/det
      call cell_internal_force(dim, nn, cells%grad(:, :, cell), cells%weight(cell), f, tau, &
                               fc(1:dim, 1:nn))
      call cell_tangent(dim, nn, cells%grad(:, :, cell), cells%weight(cell), f, tau, c, &
                        ke(1:nd, 1:nd))
      if (cells%hex_of(cell) > 0) then          ! one-point hexahedron: its hourglass forces
        call hourglass_stiffness_cell(nn, cells%grad(:, :, cell), &
            cells%hg_gamma(:, :, cells%hex_of(cell)), cells%hg_stiffness(:, cells%hex_of(cell)), &
            ue, f, fh(:, 1:nn), kh(1:nd, 1:nd), energy)
        fc(:, 1:nn) = fc(:, 1:nn) + fh(:, 1:nn)
        ke(1:nd, 1:nd) = ke(1:nd, 1:nd) + kh(1:nd, 1:nd)
      end if
      if (present(internal)) internal(:, cells%nodes(1:nn, cell)) = &
          internal(:, cells%nodes(1:nn, cell)) + fc(1:dim, 1:nn)
      do a = 1, nn
        do i = 1, dim
          dofs(dim*(a-1) + i) = equation(i, cells%nodes(a, cell))
          if (dofs(dim*(a-1) + i) > 0) residual(dofs(dim*(a-1) + i)) = &
              residual(dofs(dim*(a-1) + i)) - fc(i, a)
        end do
      end do
      call coo_add_block(tangent, dofs(1:nd), ke(1:nd, 1:nd), .false.)
    end do
    ! ELFORM 13: the patch blocks' sums, each node pair once
    do n = 1, size(patches%pair_start) - 1
      do a = patches%pair_start(n), patches%pair_start(n + 1) - 1
        call coo_add_rectangle(tangent, equation(:, n), equation(:, patches%pair_node(a)), &
                               np_pair_values(:, :, a), .false.)
      end do
    end do
    ok = .not. comm_any(failed)
    if (tools%interfaces%n > 0) call tool_contact(model, cells, equation, u, t, residual, tangent)
    if (comm_is_root()) then
      do n = 1, size(u, 2)
        do i = 1, dim
          if (equation(i, n) > 0) residual(equation(i, n)) = residual(equation(i, n)) + &
              force_ext(i, n)
        end do
      end do
    end if
    call comm_sum(residual)
    call comm_sum(trial%cauchy)
    if (present(internal)) call comm_sum(internal)

  contains

    !> ELFORM 13 cell: forces V0 tau_eff F^-T g_a, the element's tangent and the block of the
    !> means on its patch's nodes (mefem_implicit_nodal_pressure).
    subroutine nodal_pressure_cell(cell, residual, tangent, internal)
      integer, intent(in) :: cell                      !< the cell
      real(wp), intent(inout) :: residual(:)           !< free-dof residual
      type(coo_matrix_t), intent(inout) :: tangent     !< tangent matrix
      real(wp), intent(inout), optional :: internal(:,:) !< internal forces
      real(wp) :: block(3*patches%max_patch, 3*patches%max_patch)
      integer :: e
      e = patches%index_of(cell)
      call np_cell_terms(cells, patches, np_values, e, tau, c, block)
      f = np_values%f(:, :, e)
      trial%cauchy(:, cell) = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), &
                               tau(3, 1)]/np_values%det(e)
      call cell_internal_force(3, 4, cells%grad(:, :, cell), cells%weight(cell), f, tau, &
                               fc(:, 1:4))
      call cell_tangent(3, 4, cells%grad(:, :, cell), cells%weight(cell), f, tau, c, &
                        ke(1:12, 1:12))
      if (present(internal)) internal(:, cells%nodes(1:4, cell)) = &
          internal(:, cells%nodes(1:4, cell)) + fc(:, 1:4)
      do a = 1, 4
        do i = 1, 3
          dofs(3*(a-1) + i) = equation(i, cells%nodes(a, cell))
          if (dofs(3*(a-1) + i) > 0) residual(dofs(3*(a-1) + i)) = &
              residual(dofs(3*(a-1) + i)) - fc(i, a)
        end do
      end do
      call coo_add_block(tangent, dofs(1:12), ke(1:12, 1:12), .false.)
      call np_add_to_pairs(patches, e, block, np_pair_values)
    end subroutine nodal_pressure_cell

  end subroutine evaluate_cells

  !> ELFORM 13, every cell on every rank (the means need its neighbours'): F, Jbar, the
  !> material at Fbar from the converged history (hist_new, np_values' tau and c; committed:
  !> the output's re-evaluation) and the mean pressures. failed: a J <= 0 or a material
  !> failure (the first reported).
  subroutine nodal_pressure_materials(model, cells, u, hist, hist_new, committed, failed, &
                                      u_old, dt)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    real(wp), intent(in) :: u(:,:)                     !< displacements
    real(wp), intent(in) :: hist(:,:)                  !< converged history
    real(wp), intent(inout) :: hist_new(:,:)           !< (ELFORM 13 columns set) new history
    logical, intent(in) :: committed                   !< re-evaluate the committed state
    logical, intent(inout) :: failed                   !< some cell failed
    real(wp), intent(in), optional :: u_old(:,:)       !< displacements at the step's start
    real(wp), intent(in), optional :: dt               !< the step (strain rates)
    real(wp) :: ue(3, 4), f_old(3, 3), finv(3, 3), det, d(3, 3), rate, sound
    type(status_t) :: status
    logical :: ok
    integer :: e, cell, bad
    call np_prepare(cells, patches, u, np_values, ok, bad)
    if (.not. ok) then
      if (.not. failed .and. .not. committed) call say('  cell '//itoa(bad)//' (element '// &
          itoa(model%elements%id(cells%elements(1, bad)))//'): det F <= 0')
      failed = .true.
      return
    end if
    do e = 1, patches%n
      cell = patches%cell(e)
      rate = 0.0_wp
      if (present(dt) .and. present(u_old)) then
        if (rate_dependent(model%materials(cells%material(cell))) .and. dt > 0.0_wp) then
          ue = u_old(:, cells%nodes(1:4, cell))
          call cell_deformation_gradient(3, 4, cells%grad(:, :, cell), ue, f_old)
          call inverse_3x3(np_values%f(:, :, e), finv, det)
          d = matmul(np_values%f(:, :, e) - f_old, finv)/dt
          rate = sqrt(sum((0.5_wp*(d + transpose(d)))**2))
        end if
      end if
      if (committed) then
        call material_update(model%materials(cells%material(cell)), model%curves, &
                             np_fbar(np_values, e), hist(:, cell), hist_new(:, cell), &
                             np_values%tau(:, :, e), np_values%c(:, :, :, :, e), sound, status, &
                             committed=.true.)
      else
        call material_update(model%materials(cells%material(cell)), model%curves, &
                             np_fbar(np_values, e), hist(:, cell), hist_new(:, cell), &
                             np_values%tau(:, :, e), np_values%c(:, :, :, :, e), sound, status, &
                             strain_rate=rate, dt=dt)
      end if
      if (.not. status%ok) then
        if (.not. failed .and. .not. committed) call say('  cell '//itoa(cell)//' (element '// &
            itoa(model%elements%id(cells%elements(1, cell)))//'): '//status%message)
        failed = .true.
        return
      end if
    end do
    call np_pressures(patches, np_values)
  end subroutine nodal_pressure_materials

  !> Output state: displacement, Cauchy stress, pressure, von Mises and plastic strain
  !> at nodes (cell-weighted means) and elements (means of their cells), reaction forces;
  !> state 0 (t = 0, written at the start, every array of the later states) also the node sets.
  subroutine write_state(model, decomp, cells, u, hist, equation, time, step)
    type(model_t), intent(in) :: model              !< resolved model
    type(decomposition_t), intent(in) :: decomp     !< this rank's share
    type(cells_t), intent(in) :: cells              !< cells
    real(wp), intent(in) :: u(:,:)                  !< displacements
    real(wp), intent(in) :: hist(:,:)               !< committed history
    integer, intent(in) :: equation(:,:)            !< equation numbers (0: fixed dof)
    real(wp), intent(in) :: time                    !< analysis time
    integer, intent(in) :: step                     !< output state number
    real(wp), allocatable :: stress(:,:), internal(:,:), force_ext(:,:)
    type(output_field_t), allocatable :: point_fields(:)
    type(output_field_t) :: cell_fields(4)
    integer :: node, local
    allocate(point_fields(6))
    call final_stresses(model, cells, u, hist, stress, internal)
    point_fields(1)%name = 'displacement'
    point_fields(1)%ncomp = 3
    allocate(point_fields(1)%values(3, decomp%nnode_local))
    point_fields(1)%values = 0.0_wp
    do local = 1, decomp%nnode_local
      point_fields(1)%values(1:cells%dim, local) = u(:, decomp%node_global(local))
    end do
    call cell_result_fields(model, decomp, cells, stress, hist(HIST_ALPHA, :), &
                            point_fields(2:5), cell_fields)
    ! reaction forces: internal minus external force at the fixed degrees of freedom
    allocate(force_ext(cells%dim, cells%n_mesh_nodes))
    force_ext = 0.0_wp
    call external_forces(model, time, force_ext)
    if (model%n_body_loads > 0) call add_body_forces(body_acceleration(model, time), &
                                                     loaded_mass(1:cells%n_mesh_nodes), force_ext)
    point_fields(6)%name = 'reaction_force'
    point_fields(6)%ncomp = 3
    allocate(point_fields(6)%values(3, decomp%nnode_local))
    point_fields(6)%values = 0.0_wp
    do local = 1, decomp%nnode_local
      node = decomp%node_global(local)
      where (equation(:, node) == 0) point_fields(6)%values(1:cells%dim, local) = &
          internal(:, node) - force_ext(:, node)
    end do
    if (step == 0) call append_node_set_fields(model, decomp, point_fields)   ! state 0: the node sets
    call results_write_state(step, time, point_fields, cell_fields)
  end subroutine write_state

  !> Cauchy stress of every cell in the committed state: the material is evaluated with the
  !> committed history, which holds F_{n+1} itself, so the increment is the identity and the
  !> update returns the committed stress without further plastic flow.
  subroutine final_stresses(model, cells, u, hist, stress, internal)
    type(model_t), intent(in) :: model                 !< resolved model
    type(cells_t), intent(in) :: cells                 !< cells
    real(wp), intent(in) :: u(:,:)                     !< displacements
    real(wp), intent(in) :: hist(:,:)                  !< committed history
    real(wp), allocatable, intent(out) :: stress(:,:)  !< (6, cells) Cauchy stress
    real(wp), allocatable, intent(out) :: internal(:,:) !< (dim, nodes) internal forces
    real(wp) :: f(3, 3), finv(3, 3), tau(3, 3), c(3, 3, 3, 3), sound, det
    real(wp) :: ue(3, CELL_MAX_NODES)
    real(wp) :: scratch(NHIST), fc(3, CELL_MAX_NODES), fh(3, CELL_MAX_NODES), energy
    real(wp) :: kh(3*CELL_MAX_NODES, 3*CELL_MAX_NODES)
    real(wp), allocatable :: scratch_np(:,:), block(:,:)
    type(status_t) :: status
    integer :: cell, nn, a, e
    logical :: failed
    allocate(stress(6, cells%n), internal(cells%dim, size(u, 2)))
    allocate(block(3*patches%max_patch, 3*patches%max_patch))
    stress = 0.0_wp
    internal = 0.0_wp
    failed = .false.
    if (patches%n > 0) then
      allocate(scratch_np(NHIST, cells%n))
      call nodal_pressure_materials(model, cells, u, hist, scratch_np, .true., failed)
    end if
    do cell = 1, cells%n
      nn = cells%nnodes(cell)
      if (patches%n > 0) then
        if (patches%index_of(cell) > 0) then         ! ELFORM 13: tau_eff and its forces
          if (failed) cycle
          e = patches%index_of(cell)
          call np_cell_terms(cells, patches, np_values, e, tau, c, block)
          stress(:, cell) = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), &
                             tau(3, 1)]/np_values%det(e)
          call cell_internal_force(3, 4, cells%grad(:, :, cell), cells%weight(cell), &
                                   np_values%f(:, :, e), tau, fc(:, 1:4))
          internal(:, cells%nodes(1:4, cell)) = internal(:, cells%nodes(1:4, cell)) + fc(:, 1:4)
          cycle
        end if
      end if
      ue(1:cells%dim, 1:nn) = u(:, cells%nodes(1:nn, cell))
      call cell_deformation_gradient(cells%dim, nn, cells%grad(:, :, cell), ue, f)
      ! the committed history already holds F_{n+1}: re-evaluating from it is elastic (no
      ! yield check: a rate-hardened stress lies outside the quasi-static surface)
      call material_update(model%materials(cells%material(cell)), model%curves, f, &
                           hist(:, cell), scratch, tau, c, sound, status, committed=.true.)
      if (.not. status%ok) cycle
      call inverse_3x3(f, finv, det)
      stress(:, cell) = [tau(1, 1), tau(2, 2), tau(3, 3), tau(1, 2), tau(2, 3), tau(3, 1)]/det
      call cell_internal_force(cells%dim, nn, cells%grad(:, :, cell), cells%weight(cell), f, &
                               tau, fc(1:cells%dim, 1:nn))
      if (cells%hex_of(cell) > 0) then          ! one-point hexahedron: its hourglass forces
        call hourglass_stiffness_cell(nn, cells%grad(:, :, cell), &
            cells%hg_gamma(:, :, cells%hex_of(cell)), cells%hg_stiffness(:, cells%hex_of(cell)), &
            ue, f, fh(:, 1:nn), kh(1:3*nn, 1:3*nn), energy)
        fc(:, 1:nn) = fc(:, 1:nn) + fh(:, 1:nn)
      end if
      do a = 1, nn
        internal(:, cells%nodes(a, cell)) = internal(:, cells%nodes(a, cell)) + fc(1:cells%dim, a)
      end do
    end do
  end subroutine final_stresses

end module mefem_implicit_static
