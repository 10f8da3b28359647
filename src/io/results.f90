!> Result output of a run: VTK XML (ParaView) and HDF5 (scripts), written together.
!>
!> results_open builds this rank's output piece from the decomposition, creates the output
!> directory and the HDF5 file and writes the mesh; results_write_state writes one state to
!> both formats and lists it in the XDMF file through which ParaView and VisIt read the HDF5
!> file. Files are complete after every state (the .pvd and the .xdmf are rewritten, the HDF5
!> file flushed), so a run that stops early leaves readable results.
module mefem_results
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_is_root, comm_barrier, comm_any
  use mefem_errors, only: fatal
  use mefem_kinds, only: i8
  use mefem_file_system, only: make_directory, remove_file, canonical_path
  use mefem_errors, only: say, log_open
  use mefem_strings, only: itoa
  use mefem_model, only: model_t, SET_NODE
  use mefem_output_mesh, only: output_mesh_t, output_field_t
  use mefem_decomposition, only: decomposition_t, fill_output_mesh
  use mefem_vtk_output, only: vtk_write_state, vtk_collection_states, vtk_collection_restore
  use mefem_hdf5_output, only: h5_output_open, h5_output_write_mesh, h5_output_write_state, &
                               h5_output_close, h5_output_topology_length, h5_output_resume
  use mefem_xdmf_output, only: xdmf_open, xdmf_add_state, xdmf_states, xdmf_restore_states
  use mefem_history_output, only: HISTORY_FILES, history_restart_put, history_restart_get
  use mefem_restart_file, only: restart_file_t, restart_open, restart_close, &
                                restart_put_text, restart_put_reals, restart_get_text, &
                                restart_get_reals, restart_get_reals_alloc
  implicit none
  private

  public :: results_open, results_write_state, results_close, node_set_fields, results_directory
  public :: append_node_set_fields
  public :: results_restart_header_put, results_restart_header_skip, results_restart_peek, &
            results_restart_put, results_restart_get

  type(output_mesh_t), save :: piece               !< this rank's output mesh
  character(len=:), allocatable :: out_dir, stem   !< output directory and file stem
  character(len=:), allocatable :: deck_path       !< the deck (for restart files)

contains

  !> Create the output directory and files, and write the mesh.
  !> With resume (a restart), the results of the run being continued stay: the files are
  !> opened by results_restart_get, which knows from the restart file what to keep.
  subroutine results_open(dir, basename, model, decomp, deck, resume)
    character(len=*), intent(in) :: dir              !< output directory
    character(len=*), intent(in) :: basename         !< stem of the file names
    type(model_t), intent(in) :: model               !< resolved model
    type(decomposition_t), intent(in) :: decomp      !< this rank's share
    character(len=*), intent(in) :: deck             !< the deck's path
    logical, intent(in) :: resume                    !< continue the results of a restart file
    character(len=:), allocatable :: reason
    logical :: ok
    out_dir = dir
    stem = basename
    deck_path = canonical_path(deck)
    ok = .true.
    if (comm_is_root()) call make_directory(dir, ok, reason)
    if (comm_any(.not. ok)) then
      if (comm_is_root()) call fatal('cannot use the output directory "'//dir//'": '//reason)
      call fatal('cannot use the output directory "'//dir//'"')
    end if
    if (comm_is_root() .and. .not. resume) call remove_earlier_results(dir, basename, 0, .true.)
    call log_open(dir//'/mefem.log', append=resume)
    call comm_barrier()
    call fill_output_mesh(decomp, model%nodes%x, model%nodes%id, model%elements%topology, &
                          model%elements%id, model%elements%part_id, piece)
    if (resume) return
    call h5_output_open(dir//'/'//basename//'.h5')
    call h5_output_write_mesh(piece)
    call xdmf_open(dir//'/'//basename//'.xdmf', basename//'.h5', piece%nnode_global, &
                   piece%ncell_global, h5_output_topology_length())
  end subroutine results_open

  !> Write one state: point fields sized (ncomp, local nodes), cell fields (ncomp, local cells).
  subroutine results_write_state(step, time, point_fields, cell_fields)
    integer, intent(in) :: step                          !< output state number
    real(wp), intent(in) :: time                         !< analysis time
    type(output_field_t), intent(in) :: point_fields(:)  !< fields on this piece's nodes
    type(output_field_t), intent(in) :: cell_fields(:)   !< fields on this piece's cells
    call vtk_write_state(out_dir, stem, step, time, piece, point_fields, cell_fields)
    call h5_output_write_state(step, time, point_fields, cell_fields)
    call xdmf_add_state(step, time, point_fields, cell_fields)
  end subroutine results_write_state

  !> Remove the result files an earlier run of the same stem left in dir, so that the
  !> directory holds this run's results only (a state of an earlier, longer or wider run would
  !> otherwise stay beside them): the states stem_SSSSSS.vtu, .pvtu and their pieces
  !> stem_SSSSSS_RRRR.vtu (SSSSSS from 0 up to the first state without any file), stem.pvd,
  !> stem.h5, and the histories glstat, nodout, rcforc, rwforc, rbdout. Says how many it
  !> removed. A restart removes only the states from first_step on (whole = .false.).
  subroutine remove_earlier_results(dir, basename, first_step, whole)
    character(len=*), intent(in) :: dir              !< output directory
    character(len=*), intent(in) :: basename         !< stem of the file names
    integer, intent(in) :: first_step                !< first state removed
    logical, intent(in) :: whole                     !< the collections and histories too
    character(len=:), allocatable :: state
    integer :: step, rank, count
    logical :: removed, any_file
    count = 0
    step = first_step
    do
      state = dir//'/'//basename//'_'//padded(step, 6)
      any_file = .false.
      call remove_file(state//'.vtu', removed)
      call tally()
      call remove_file(state//'.pvtu', removed)
      call tally()
      rank = 0
      do
        call remove_file(state//'_'//padded(rank, 4)//'.vtu', removed)
        if (.not. removed) exit
        call tally()
        rank = rank + 1
      end do
      if (.not. any_file) exit
      step = step + 1
    end do
    if (.not. whole) then
      if (count > 0) call say('results: removed '//itoa(count)//' files of states the run '// &
                              'wrote after its restart file')
      return
    end if
    call remove_file(dir//'/'//basename//'.pvd', removed)
    call tally()
    call remove_file(dir//'/'//basename//'.h5', removed)
    call tally()
    call remove_file(dir//'/'//basename//'.xdmf', removed)
    call tally()
    do step = 1, size(HISTORY_FILES)
      call remove_file(dir//'/'//trim(HISTORY_FILES(step)), removed)
      call tally()
    end do
    if (count > 0) call say('results: removed '//itoa(count)//' files of an earlier run '// &
                            'from '//dir)
  contains
    !> Count a removed file.
    subroutine tally()
      if (.not. removed) return
      count = count + 1
      any_file = .true.
    end subroutine tally
    !> n with leading zeros to width digits.
    function padded(n, width) result(text)
      integer, intent(in) :: n, width              !< number, digits
      character(len=width) :: text
      character(len=16) :: format
      write(format, '(a,i0,a,i0,a)') '(i', width, '.', width, ')'
      write(text, format) n
    end function padded
  end subroutine remove_earlier_results

  !> The first records of a restart file: the deck and the output directory, so that
  !> `mefem r=FILE` finds both (results_restart_peek).
  subroutine results_restart_header_put(f)
    type(restart_file_t), intent(inout) :: f          !< file being written
    call restart_put_text(f, 'run.deck', deck_path)
    call restart_put_text(f, 'run.output', canonical_path(out_dir))
    call restart_put_text(f, 'run.stem', stem)
  end subroutine results_restart_header_put

  !> Read past the first records of a restart file (results_restart_peek gave them).
  subroutine results_restart_header_skip(f)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=:), allocatable :: text
    call restart_get_text(f, 'run.deck', text)
    call restart_get_text(f, 'run.output', text)
    call restart_get_text(f, 'run.stem', text)
  end subroutine results_restart_header_skip

  !> The deck, output directory and result files' stem a restart file was written for (every
  !> rank reads it): the continued run writes on into the files of that stem, whatever the
  !> name of the deck it is given.
  subroutine results_restart_peek(path, deck, dir, basename)
    character(len=*), intent(in) :: path              !< the restart file
    character(len=:), allocatable, intent(out) :: deck  !< its deck
    character(len=:), allocatable, intent(out) :: dir   !< its output directory
    character(len=:), allocatable, intent(out) :: basename  !< its result files' stem
    type(restart_file_t) :: f
    call restart_open(f, path)
    call restart_get_text(f, 'run.deck', deck)
    call restart_get_text(f, 'run.output', dir)
    call restart_get_text(f, 'run.stem', basename)
    call restart_close(f)
  end subroutine results_restart_peek

  !> What the result files hold at a restart file's moment: the states of the .pvd and the
  !> .xdmf, the length of the HDF5 file's topology and of every history file.
  subroutine results_restart_put(f)
    type(restart_file_t), intent(inout) :: f          !< file being written
    real(wp), allocatable :: times(:)
    character(len=:), allocatable :: files
    call vtk_collection_states(out_dir//'/'//stem//'.pvd', times, files)
    call restart_put_reals(f, 'results.times', size(times), times)
    call restart_put_text(f, 'results.files', files)
    call restart_put_text(f, 'results.xdmf', xdmf_states())
    call restart_put_reals(f, 'results.topology', 1, [real(h5_output_topology_length(), wp)])
    call history_restart_put(f, out_dir)
  end subroutine results_restart_put

  !> Continue the result files from a restart file's moment (after results_open with
  !> resume): the states written until then stay, those of the stopped run after it go, and
  !> the histories are cut back to their lengths then.
  subroutine results_restart_get(f)
    type(restart_file_t), intent(inout) :: f          !< file being read
    real(wp), allocatable :: times(:)
    real(wp) :: topology(1)
    character(len=:), allocatable :: files, xml
    call restart_get_reals_alloc(f, 'results.times', times)
    call restart_get_text(f, 'results.files', files)
    call restart_get_text(f, 'results.xdmf', xml)
    call restart_get_reals(f, 'results.topology', 1, topology)
    call history_restart_get(f, out_dir)
    if (comm_is_root()) call remove_earlier_results(out_dir, stem, size(times), .false.)
    call comm_barrier()
    call h5_output_resume(out_dir//'/'//stem//'.h5', piece, size(times), size(times), &
                          int(topology(1), i8))
    call xdmf_open(out_dir//'/'//stem//'.xdmf', stem//'.h5', piece%nnode_global, &
                   piece%ncell_global, int(topology(1), i8))
    call xdmf_restore_states(xml)
    call vtk_collection_restore(out_dir//'/'//stem//'.pvd', times, files)
  end subroutine results_restart_get


  !> The output directory given to results_open (for the time-history files).
  function results_directory() result(dir)
    character(len=:), allocatable :: dir
    dir = out_dir
  end function results_directory

  !> Close the files.
  subroutine results_close()
    call h5_output_close()
  end subroutine results_close

  !> State 0 of every analysis carries the node sets: node_set_fields appended to fields.
  subroutine append_node_set_fields(model, decomp, fields)
    type(model_t), intent(in) :: model                            !< resolved model
    type(decomposition_t), intent(in) :: decomp                   !< this rank's share
    type(output_field_t), allocatable, intent(inout) :: fields(:) !< the state's point fields
    type(output_field_t), allocatable :: sets(:)
    call node_set_fields(model, decomp, sets)
    fields = [fields, sets]
  end subroutine append_node_set_fields

  !> One point field per node set ("node_set_<id>": 1 on members, 0 elsewhere), on this
  !> rank's piece, so that sets can be checked in ParaView.
  subroutine node_set_fields(model, decomp, fields)
    type(model_t), intent(in) :: model                            !< resolved model
    type(decomposition_t), intent(in) :: decomp                   !< this rank's share
    type(output_field_t), allocatable, intent(out) :: fields(:)   !< the fields
    integer :: s, k, nfield, i
    integer, allocatable :: local_of(:)
    nfield = 0
    do s = 1, model%n_sets
      if (model%sets(s)%kind == SET_NODE) nfield = nfield + 1
    end do
    allocate(fields(nfield))
    if (nfield == 0) return
    allocate(local_of(model%nodes%n))
    local_of = 0
    do i = 1, decomp%nnode_local
      local_of(decomp%node_global(i)) = i
    end do
    k = 0
    do s = 1, model%n_sets
      if (model%sets(s)%kind /= SET_NODE) cycle
      k = k + 1
      fields(k)%name = 'node_set_'//itoa(model%sets(s)%id)
      fields(k)%ncomp = 1
      allocate(fields(k)%values(1, decomp%nnode_local))
      fields(k)%values = 0.0_wp
      do i = 1, size(model%sets(s)%members)
        if (model%sets(s)%members(i) <= 0) cycle
        if (local_of(model%sets(s)%members(i)) > 0) &
          fields(k)%values(1, local_of(model%sets(s)%members(i))) = 1.0_wp
      end do
    end do
  end subroutine node_set_fields

end module mefem_results
