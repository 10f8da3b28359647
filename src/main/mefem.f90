!> mefem: large-deformation metal forming with the meshfree-enriched finite element method
!> and mortar contact (Hu & Wu). The main program reads like the run it performs:
!> read the deck, check it, split the mesh over the ranks, run the analysis, write results.
program mefem
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_init, comm_size, comm_wtime
  use mefem_errors, only: say, terminate, fatal, warn
  use mefem_signals, only: signal_exit_code
  use mefem_strings, only: itoa, rtoa
  use mefem_command_line, only: run_options_t, parse_command_line, MEFEM_VERSION
  use mefem_model, only: model_t
  use mefem_keyword_reader, only: read_deck
  use mefem_model_resolve, only: model_resolve
  use mefem_model_summary, only: print_model_summary, deck_stem
  use mefem_decomposition, only: decomposition_t
  use mefem_model_partition, only: partition_model
  use mefem_output_mesh, only: output_field_t
  use mefem_results, only: results_open, results_write_state, results_close, node_set_fields, &
                           results_restart_peek
  use mefem_progress, only: peak_memory_mib
  use mefem_linear_static, only: linear_static_run
  use mefem_implicit_static, only: implicit_static_run, implicit_writes_initial_state
  use mefem_explicit_dynamics, only: explicit_dynamics_run, explicit_writes_initial_state, &
                                     explicit_analysis
  use mefem_boundary_conditions, only: warn_loads_on_free_nodes
  use mefem_errors, only: input_error_count, unprinted_error_summary
  implicit none

  type(run_options_t) :: options
  type(model_t) :: model
  type(decomposition_t) :: decomp
  type(output_field_t), allocatable :: point_fields(:), cell_fields(:)
  integer, allocatable :: element_rank(:), element_chunk(:)
  integer :: n_errors
  real(wp) :: t_start, t_read
  character(len=:), allocatable :: restart_deck, restart_dir, stem

  ! start MPI and read the command line
  call comm_init()
  t_start = comm_wtime()
  call parse_command_line(options)
  if (allocated(options%restart)) then       ! the deck and results of the run it continues
    call results_restart_peek(options%restart, restart_deck, restart_dir, stem)
    if (.not. allocated(options%deck)) options%deck = restart_deck
    if (.not. allocated(options%output_dir)) options%output_dir = directory_of(options%restart)
  end if
  call say('mefem '//MEFEM_VERSION//' on '//itoa(comm_size())//' rank(s): '//options%deck)

  ! read the deck (every rank reads it) and check every reference; stop on any problem
  call read_deck(options%deck, model, n_errors)
  call model_resolve(model)
  n_errors = input_error_count()
  if (n_errors > 0) then
    call unprinted_error_summary()
    call say(options%deck//': '//itoa(n_errors)//' input error(s); no analysis was run')
    call terminate(1)
  end if
  t_read = comm_wtime() - t_start
  call print_model_summary(model, t_read, peak_memory_mib())
  call warn_loads_on_free_nodes(model)
  if (options%check_only) then
    call say(options%deck//': deck accepted')
    call terminate(0)
  end if
  if (allocated(options%restart) .and. .not. restartable(model)) call fatal( &
      options%restart//': the explicit and the nonlinear implicit analyses restart; '// &
      options%deck//' asks for another analysis')
  if (.not. restartable(model) .and. &
      model%controls%d3dump_cycles + model%controls%runrsf_cycles > 0) call warn( &
      '*DATABASE_BINARY_D3DUMP / _RUNRSF: the explicit and the nonlinear implicit analyses '// &
      'write restart files; this analysis writes none')

  ! split the mesh over the ranks (METIS; the explicit solver in whole chunks of elements)
  if (explicit_analysis(model)) then
    call partition_model(model, decomp, element_rank, element_chunk)
  else
    call partition_model(model, decomp, element_rank)
  end if

  ! write the model as read: the mesh, its parts and node sets (state 0; the explicit and
  ! the nonlinear implicit analyses write state 0 themselves, with their fields at t = 0)
  if (.not. allocated(stem)) stem = deck_stem(options%deck)   ! (a restart: its run's stem)
  call results_open(options%output_dir, stem, model, decomp, options%deck, &
                    allocated(options%restart))
  if (.not. (explicit_writes_initial_state(model) .or. implicit_writes_initial_state(model) &
             .or. allocated(options%restart))) then
    call node_set_fields(model, decomp, point_fields)
    allocate(cell_fields(0))
    call results_write_state(0, 0.0_wp, point_fields, cell_fields)
  end if

  ! the analysis the deck asks for
  if (model%controls%imflag == 1 .and. model%controls%nsolvr == 1) then
    call linear_static_run(model, decomp)
  else if (model%controls%imflag == 1 .and. allocated(options%restart)) then
    call implicit_static_run(model, decomp, options%restart)
  else if (model%controls%imflag == 1) then
    call implicit_static_run(model, decomp)
  else if (explicit_analysis(model) .and. allocated(options%restart)) then
    call explicit_dynamics_run(model, decomp, element_rank, element_chunk, options%restart)
  else if (explicit_analysis(model)) then
    call explicit_dynamics_run(model, decomp, element_rank, element_chunk)
  else
    call say('no *CONTROL_TERMINATION: nothing to run; the model was read, checked and written')
  end if
  call results_close()
  call say('results: '//options%output_dir//'/'//stem//'.pvd (ParaView), '// &
           options%output_dir//'/'//stem//'.h5 (HDF5)')
  call say('wall time '//rtoa(comm_wtime() - t_start)//' s, peak memory '// &
           rtoa(peak_memory_mib())//' MiB per rank')
  call terminate(signal_exit_code())    ! 0, or 128 + the signal that stopped the analysis
contains

  !> Whether the deck's analysis writes restart files and continues from them: the explicit
  !> and the nonlinear implicit analyses.
  logical function restartable(deck_model)
    type(model_t), intent(in) :: deck_model           !< resolved model
    restartable = explicit_analysis(deck_model) .or. (deck_model%controls%imflag == 1 .and. &
                                                      deck_model%controls%nsolvr /= 1)
  end function restartable

  !> The directory a file is in ('.' for a bare name): a restart file's results are beside it.
  function directory_of(path) result(dir)
    character(len=*), intent(in) :: path              !< the file
    character(len=:), allocatable :: dir
    integer :: slash
    slash = index(path, '/', back=.true.)
    dir = '.'
    if (slash > 1) dir = path(1:slash - 1)
    if (slash == 1) dir = '/'
  end function directory_of
end program mefem
