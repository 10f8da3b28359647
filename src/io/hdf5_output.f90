!> HDF5 result file: the mesh once, then one group per output state, written in parallel.
!>
!> The only module of mefem that calls HDF5. One file per run is created on all ranks with the
!> MPI-IO driver. Datasets hold the whole mesh in the rank-independent global order of
!> output_mesh_t (global_node, global_cell), so files written on any number of ranks hold the
!> same data. Each rank writes only its own rows (the nodes it owns, the cells of its piece)
!> through a selection of the global dataset made of one hyperslab per run of consecutive
!> global positions, with collective MPI-IO transfers. The selections are built once, in
!> h5_output_write_mesh, and reused for every state. The file is flushed after each state's
!> data and again after /time_history lists it, so it stays readable up to the last listed
!> state if the run dies later.
!> Layout (names, shapes, types): doc/hdf5_layout.md. Every public routine is collective.
module mefem_hdf5_output
  use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_int, c_int64_t
  use hdf5, only: HID_T, HSIZE_T, SIZE_T, H5_INTEGER_KIND, H5_REAL_KIND, &
                  h5open_f, h5close_f, h5eset_auto_f, h5kind_to_type, &
                  h5pcreate_f, h5pclose_f, h5pset_fapl_mpio_f, h5pset_dxpl_mpio_f, &
                  h5pset_fill_time_f, h5pset_chunk_f, &
                  h5fcreate_f, h5fopen_f, h5fclose_f, h5fflush_f, h5ldelete_f, h5gcreate_f, h5gclose_f, h5lexists_f, &
                  h5screate_f, h5screate_simple_f, h5sclose_f, h5sselect_hyperslab_f, &
                  h5sselect_none_f, h5sget_simple_extent_dims_f, &
                  h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, &
                  h5dset_extent_f, h5dget_space_f, h5acreate_f, h5aclose_f, h5awrite_f, &
                  h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5tclose_f, &
                  H5P_FILE_ACCESS_F, H5P_DATASET_XFER_F, H5P_DATASET_CREATE_F, &
                  H5FD_MPIO_COLLECTIVE_F, H5F_ACC_TRUNC_F, H5F_ACC_RDWR_F, H5F_SCOPE_GLOBAL_F, &
                  H5D_FILL_TIME_NEVER_F, H5S_SCALAR_F, H5S_SELECT_SET_F, H5S_SELECT_OR_F, &
                  H5S_UNLIMITED_F, H5T_STD_I32LE, H5T_STD_I64LE, H5T_IEEE_F64LE, H5T_C_S1, &
                  H5T_STR_NULLPAD_F
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_fortran_handle, comm_info_null_handle, comm_any, comm_sum, &
                        comm_min, comm_max, comm_bcast, comm_is_root, comm_barrier
  use mefem_file_system, only: remove_file
  use mefem_errors, only: fatal, fatal_abort
  use mefem_output_mesh, only: output_mesh_t, output_field_t, vtk_cell_type, xdmf_cell_type
  implicit none
  private

  public :: h5_output_open, h5_output_write_mesh, h5_output_write_state, h5_output_close
  public :: h5_output_topology_length, h5_output_resume

  integer, parameter :: FORMAT_VERSION = 1          !< bumped when the layout changes
  integer, parameter :: ENTITY_NODE = 1, ENTITY_CELL = 2
  integer(HSIZE_T), parameter :: HISTORY_CHUNK = 1024  !< rows per chunk of /time_history
  integer, parameter :: LEAF_RUNS = 64   !< runs added one by one before halves are merged

  interface
    !> HDF5 C API H5Smodify_select (since 1.10.6, no Fortran wrapper in 1.10): combine the
    !> hyperslab selection of space2 into space1 with the operation (H5S_SELECT_OR_F).
    integer(c_int) function h5s_modify_select(space1, operation, space2) &
        bind(C, name='H5Smodify_select')
      import :: c_int, c_int64_t
      integer(c_int64_t), value :: space1   !< dataspace whose selection is changed (hid_t)
      integer(c_int), value :: operation    !< H5S_seloper_t code
      integer(c_int64_t), value :: space2   !< dataspace whose selection is combined in
    end function h5s_modify_select
  end interface

  !> The rows one rank writes into a global dataset of one entity (nodes or cells).
  type :: row_map_t
    integer :: nlocal = 0                            !< rows of this rank's piece
    integer :: nglobal = 0                           !< rows of the global dataset
    integer, allocatable :: order(:)                 !< written local rows, by global position
    integer(HSIZE_T), allocatable :: run_start(:)    !< 0-based global start of each run
    integer(HSIZE_T), allocatable :: run_length(:)   !< rows in each run
  end type row_map_t

  !> This rank's selection in a global dataset of one shape, kept for reuse.
  type :: selection_t
    integer :: entity = 0                  !< ENTITY_NODE or ENTITY_CELL
    integer :: ncomp = 0                   !< 0: dataset (nglobal); else (ncomp, nglobal)
    integer(HID_T) :: file_space = -1      !< global dataspace with this rank's rows selected
    integer(HID_T) :: memory_space = -1    !< the packed rows in memory
  end type selection_t

  logical :: library_open = .false.
  logical :: file_open = .false.
  logical :: mesh_written = .false.
  character(len=:), allocatable :: file_path
  integer(HID_T) :: file_id = -1
  integer(HID_T) :: transfer_list = -1       !< dataset transfer: collective MPI-IO
  integer(HID_T) :: create_list = -1         !< dataset creation: never write fill values
  type(row_map_t) :: maps(2)                 !< indexed by ENTITY_NODE, ENTITY_CELL
  type(selection_t), allocatable :: selections(:)
  integer :: nselections = 0
  integer :: nstates = 0                     !< states written to this file
  integer(i8) :: topology_length = 0         !< entries of /mesh/xdmf_topology

contains

  !> Create the result file (truncating it) on all ranks, with parallel MPI-IO access.
  subroutine h5_output_open(path)
    character(len=*), intent(in) :: path   !< file name, the same on every rank
    integer(HID_T) :: access_list, group_id
    integer :: hdferr
    call open_library(path, access_list)
    call h5fcreate_f(file_path, H5F_ACC_TRUNC_F, file_id, hdferr, access_prp=access_list)
    call check(hdferr, 'cannot create the file (does the directory exist and is it writable?)')
    call h5pclose_f(access_list, hdferr)
    file_open = .true.
    mesh_written = .false.
    nstates = 0
    call create_property_lists()

    call write_attribute_text(file_id, 'format', 'mefem')
    call write_attribute_int(file_id, 'format_version', FORMAT_VERSION)
    call create_group(file_id, '/states', group_id)
    call h5gclose_f(group_id, hdferr)
    call create_group(file_id, '/time_history', group_id)
    call create_history_dataset(group_id, 'time', H5T_IEEE_F64LE)
    call create_history_dataset(group_id, 'step', H5T_STD_I32LE)
    call h5gclose_f(group_id, hdferr)
    call check(hdferr, 'cannot create /time_history')
  end subroutine h5_output_open

  !> Open the result file of the run a restart continues (on all ranks), keep its first
  !> nkept states (those its restart file lists), drop the states from step first_dropped on
  !> (a later state of the stopped run is written again by the restarted one) and get ready
  !> to write further states for this rank's piece (the mesh is in the file already).
  subroutine h5_output_resume(path, mesh, nkept, first_dropped, topology)
    character(len=*), intent(in) :: path       !< file name, the same on every rank
    type(output_mesh_t), intent(in) :: mesh    !< this rank's piece, with global positions
    integer, intent(in) :: nkept               !< states kept (/time_history's first rows)
    integer, intent(in) :: first_dropped       !< first step number dropped
    integer(i8), intent(in) :: topology        !< entries of /mesh/xdmf_topology
    character(len=*), parameter :: HISTORY(2) = [character(len=18) :: '/time_history/time', &
                                                 '/time_history/step']
    integer(HID_T) :: access_list, dataset_id
    character(len=32) :: group_name
    logical :: exists
    integer :: hdferr, step, k
    call open_library(path, access_list)
    call h5fopen_f(file_path, H5F_ACC_RDWR_F, file_id, hdferr, access_prp=access_list)
    call check(hdferr, 'cannot open it to continue the run its restart file belongs to (a '// &
               'restart needs that run''s results in the output directory)')
    call h5pclose_f(access_list, hdferr)
    file_open = .true.
    call create_property_lists()
    call build_maps(mesh)
    mesh_written = .true.
    topology_length = topology
    step = first_dropped
    do
      write(group_name, '(a,i0.6)') '/states/', step
      call h5lexists_f(file_id, trim(group_name), exists, hdferr)
      call check(hdferr, 'cannot look for '//trim(group_name))
      if (.not. exists) exit
      call h5ldelete_f(file_id, trim(group_name), hdferr)
      call check(hdferr, 'cannot drop '//trim(group_name)//' of the stopped run')
      step = step + 1
    end do
    nstates = nkept
    do k = 1, size(HISTORY)
      call h5dopen_f(file_id, HISTORY(k), dataset_id, hdferr)
      call check(hdferr, 'cannot open '//HISTORY(k))
      call h5dset_extent_f(dataset_id, [int(nstates, HSIZE_T)], hdferr)
      call check(hdferr, 'cannot cut '//HISTORY(k)//' back to the restart file''s states')
      call h5dclose_f(dataset_id, hdferr)
    end do
    call flush_file()
  end subroutine h5_output_resume

  !> Start the HDF5 library (once) and make the file access list of the MPI-IO driver.
  subroutine open_library(path, access_list)
    character(len=*), intent(in) :: path              !< the file, the same on every rank
    integer(HID_T), intent(out) :: access_list        !< file access property list
    integer :: hdferr
    if (file_open) call fatal('HDF5 output: cannot open '''//trim(path)// &
                              ''': '''//file_path//''' is still open')
    file_path = trim(path)
    if (.not. library_open) then
      call h5open_f(hdferr)
      call check(hdferr, 'cannot initialise the HDF5 library')
      call h5eset_auto_f(0, hdferr)   ! errors are reported by check(), not by HDF5
      library_open = .true.
    end if
    call h5pcreate_f(H5P_FILE_ACCESS_F, access_list, hdferr)
    call check(hdferr, 'cannot create a file access property list')
    call h5pset_fapl_mpio_f(access_list, comm_fortran_handle(), comm_info_null_handle(), hdferr)
    call check(hdferr, 'cannot select the MPI-IO driver')
  end subroutine open_library

  !> The transfer (collective MPI-IO) and dataset creation (no fill values) property lists.
  subroutine create_property_lists()
    integer :: hdferr
    call h5pcreate_f(H5P_DATASET_XFER_F, transfer_list, hdferr)
    call check(hdferr, 'cannot create a transfer property list')
    call h5pset_dxpl_mpio_f(transfer_list, H5FD_MPIO_COLLECTIVE_F, hdferr)
    call check(hdferr, 'cannot select collective MPI-IO transfers')
    call h5pcreate_f(H5P_DATASET_CREATE_F, create_list, hdferr)
    call check(hdferr, 'cannot create a dataset creation property list')
    call h5pset_fill_time_f(create_list, H5D_FILL_TIME_NEVER_F, hdferr)
    call check(hdferr, 'cannot switch off fill values')
  end subroutine create_property_lists

  !> The rows this rank writes of the node and cell datasets (its owned nodes, its cells).
  subroutine build_maps(mesh)
    type(output_mesh_t), intent(in) :: mesh   !< this rank's piece, with global positions
    logical, allocatable :: every_cell(:)
    call check_mesh_piece(mesh)
    call build_row_map(maps(ENTITY_NODE), mesh%global_node, mesh%node_owned, &
                       mesh%nnode_global, 'node')
    allocate(every_cell(mesh%ncell), source=.true.)
    call build_row_map(maps(ENTITY_CELL), mesh%global_cell, every_cell, &
                       mesh%ncell_global, 'cell')
  end subroutine build_maps

  !> Write the mesh (group /mesh) once; every rank gives its piece.
  subroutine h5_output_write_mesh(mesh)
    type(output_mesh_t), intent(in) :: mesh   !< this rank's piece, with global positions
    integer, allocatable :: cell_types(:)
    integer(HID_T) :: group_id
    integer :: hdferr, c
    call require_open('write the mesh')
    if (mesh_written) call fatal('HDF5 output '''//file_path//''': the mesh is written twice')
    call build_maps(mesh)

    call create_group(file_id, '/mesh', group_id)
    call write_attribute_int(group_id, 'nnode', mesh%nnode_global)
    call write_attribute_int(group_id, 'ncell', mesh%ncell_global)
    call h5gclose_f(group_id, hdferr)
    call write_real_rows('/mesh/coordinates', ENTITY_NODE, mesh%x)
    call write_int_rows('/mesh/node_ids', ENTITY_NODE, mesh%node_id)
    call write_int_rows('/mesh/cell_ids', ENTITY_CELL, mesh%cell_id)
    call write_int_rows('/mesh/cell_part', ENTITY_CELL, mesh%cell_part)
    allocate(cell_types(mesh%ncell))
    do c = 1, mesh%ncell
      cell_types(c) = vtk_cell_type(mesh%topology(c))
    end do
    call write_int_rows('/mesh/cell_types', ENTITY_CELL, cell_types)
    call write_connectivity(mesh)
    mesh_written = .true.
    call flush_file()
  end subroutine h5_output_write_mesh

  !> Write one output state: group /states/<step, 6 digits> with its point and cell fields.
  subroutine h5_output_write_state(step, time, point_fields, cell_fields)
    integer, intent(in) :: step                            !< step number (>= 0), names the group
    real(wp), intent(in) :: time                           !< simulation time of the state
    type(output_field_t), intent(in) :: point_fields(:)    !< fields on this piece's nodes
    type(output_field_t), intent(in) :: cell_fields(:)     !< fields on this piece's cells
    character(len=32) :: group_name
    integer(HID_T) :: group_id, sub_id
    logical :: exists
    integer :: hdferr, f
    call require_open('write a state')
    if (.not. mesh_written) call fatal('HDF5 output '''//file_path// &
                                       ''': a state is written before the mesh')
    if (step < 0) call fatal('HDF5 output '''//file_path//''': negative step number')
    call check_fields(point_fields, ENTITY_NODE, 'point')
    call check_fields(cell_fields, ENTITY_CELL, 'cell')
    write(group_name, '(a,i0.6)') '/states/', step
    call h5lexists_f(file_id, trim(group_name), exists, hdferr)
    call check(hdferr, 'cannot look for '//trim(group_name))
    if (exists) call fatal('HDF5 output '''//file_path//''': state '//trim(group_name)// &
                           ' is written twice')

    call create_group(file_id, trim(group_name), group_id)
    call write_attribute_real(group_id, 'time', time)
    call write_attribute_int(group_id, 'step', step)
    call create_group(group_id, 'point', sub_id)
    call h5gclose_f(sub_id, hdferr)
    call create_group(group_id, 'cell', sub_id)
    call h5gclose_f(sub_id, hdferr)
    call h5gclose_f(group_id, hdferr)
    do f = 1, size(point_fields)
      call write_real_rows(trim(group_name)//'/point/'//trim(point_fields(f)%name), &
                           ENTITY_NODE, point_fields(f)%values)
    end do
    do f = 1, size(cell_fields)
      call write_real_rows(trim(group_name)//'/cell/'//trim(cell_fields(f)%name), &
                           ENTITY_CELL, cell_fields(f)%values)
    end do
    ! the state's data on disk before /time_history lists it: a run killed in between leaves
    ! an index of complete states only
    call flush_file()
    call append_history(step, time)
    call flush_file()
  end subroutine h5_output_write_state

  !> Close the result file and the HDF5 library.
  subroutine h5_output_close()
    integer :: hdferr, s
    if (.not. file_open) return
    do s = 1, nselections
      call h5sclose_f(selections(s)%file_space, hdferr)
      call h5sclose_f(selections(s)%memory_space, hdferr)
    end do
    nselections = 0
    if (allocated(selections)) deallocate(selections)
    maps(ENTITY_NODE) = row_map_t()
    maps(ENTITY_CELL) = row_map_t()
    call h5pclose_f(transfer_list, hdferr)
    call h5pclose_f(create_list, hdferr)
    call h5fclose_f(file_id, hdferr)
    call check(hdferr, 'cannot close the file')
    file_open = .false.
    mesh_written = .false.
    call h5close_f(hdferr)
    library_open = .false.
  end subroutine h5_output_close

  ! ---- checks ------------------------------------------------------------------------------

  !> Stop all ranks with a message naming the file if an HDF5 call failed on any rank. A
  !> failure before the mesh is complete (e.g. a full disk) leaves a file that holds no state
  !> and that HDF5 cannot open: it is removed first.
  subroutine check(hdferr, what)
    integer, intent(in) :: hdferr          !< error code of the HDF5 call (< 0: failure)
    character(len=*), intent(in) :: what   !< what was being done
    logical :: removed
    if (.not. comm_any(hdferr < 0)) return
    removed = .false.
    if (.not. mesh_written .and. comm_is_root()) call remove_file(file_path, removed)
    call comm_barrier()
    if (removed) call fatal_abort('HDF5 output '''//file_path//''': '//what// &
                                  '; the file held no result state yet and is removed')
    call fatal_abort('HDF5 output '''//file_path//''': '//what)
  end subroutine check

  !> Stop if no file is open.
  subroutine require_open(action)
    character(len=*), intent(in) :: action   !< what the caller wanted to do
    if (.not. file_open) call fatal('HDF5 output: cannot '//action//': no file is open')
  end subroutine require_open

  !> Check the sizes and indices of a mesh piece (on every rank; stop if any rank is wrong).
  subroutine check_mesh_piece(mesh)
    type(output_mesh_t), intent(in) :: mesh   !< this rank's piece
    logical :: bad
    integer :: c, lowest, highest
    bad = mesh%nnode < 0 .or. mesh%ncell < 0 .or. .not. (allocated(mesh%x) .and. &
        allocated(mesh%node_id) .and. allocated(mesh%global_node) .and. &
        allocated(mesh%node_owned) .and. allocated(mesh%topology) .and. &
        allocated(mesh%cell_start) .and. allocated(mesh%conn) .and. &
        allocated(mesh%cell_id) .and. allocated(mesh%cell_part) .and. &
        allocated(mesh%global_cell))
    if (.not. bad) bad = size(mesh%x, 1) /= 3 .or. size(mesh%x, 2) /= mesh%nnode &
        .or. size(mesh%node_id) /= mesh%nnode .or. size(mesh%global_node) /= mesh%nnode &
        .or. size(mesh%node_owned) /= mesh%nnode .or. size(mesh%topology) /= mesh%ncell &
        .or. size(mesh%cell_start) /= mesh%ncell + 1 .or. size(mesh%cell_id) /= mesh%ncell &
        .or. size(mesh%cell_part) /= mesh%ncell .or. size(mesh%global_cell) /= mesh%ncell
    if (.not. bad) then
      do c = 1, mesh%ncell
        bad = bad .or. vtk_cell_type(mesh%topology(c)) == 0 &
            .or. mesh%cell_start(c+1) <= mesh%cell_start(c)
      end do
      bad = bad .or. mesh%cell_start(1) /= 1 .or. &
            mesh%cell_start(mesh%ncell+1) - 1 > size(mesh%conn)
      if (.not. bad .and. mesh%ncell > 0) then
        bad = minval(mesh%conn(1:mesh%cell_start(mesh%ncell+1)-1)) < 1 .or. &
              maxval(mesh%conn(1:mesh%cell_start(mesh%ncell+1)-1)) > mesh%nnode
      end if
    end if
    if (comm_any(bad)) call fatal('HDF5 output '''//file_path// &
        ''': inconsistent mesh piece (array sizes, topology codes or connectivity)')
    lowest = mesh%nnode_global
    highest = mesh%nnode_global
    call comm_min(lowest)
    call comm_max(highest)
    bad = lowest /= highest
    lowest = mesh%ncell_global
    highest = mesh%ncell_global
    call comm_min(lowest)
    call comm_max(highest)
    if (bad .or. lowest /= highest) call fatal('HDF5 output '''//file_path// &
        ''': ranks disagree on the global node or cell count')
  end subroutine check_mesh_piece

  !> Check that the fields fit the mesh piece and are the same list on every rank.
  subroutine check_fields(fields, entity, kind_name)
    type(output_field_t), intent(in) :: fields(:)   !< fields to write
    integer, intent(in) :: entity                   !< ENTITY_NODE or ENTITY_CELL
    character(len=*), intent(in) :: kind_name       !< 'point' or 'cell', for messages
    character(len=len(fields%name)) :: name
    integer :: f, lowest, highest
    logical :: bad
    lowest = size(fields)
    highest = size(fields)
    call comm_min(lowest)
    call comm_max(highest)
    if (lowest /= highest) call fatal('HDF5 output '''//file_path//''': ranks give different '// &
                                      'numbers of '//kind_name//' fields')
    do f = 1, size(fields)
      bad = len_trim(fields(f)%name) == 0 .or. index(fields(f)%name, '/') > 0 .or. &
            fields(f)%ncomp < 1 .or. .not. allocated(fields(f)%values)
      if (.not. bad) bad = size(fields(f)%values, 1) /= fields(f)%ncomp .or. &
                           size(fields(f)%values, 2) /= maps(entity)%nlocal
      name = fields(f)%name
      call comm_bcast(name)
      bad = bad .or. name /= fields(f)%name .or. any(fields(1:f-1)%name == fields(f)%name)
      lowest = fields(f)%ncomp
      highest = fields(f)%ncomp
      call comm_min(lowest)
      call comm_max(highest)
      if (comm_any(bad) .or. lowest /= highest) call fatal('HDF5 output '''//file_path// &
          ''': bad '//kind_name//' field '''//trim(fields(f)%name)//''' (empty, repeated or '// &
          'slashed name, wrong array shape, or not the same on every rank)')
    end do
  end subroutine check_fields

  ! ---- selections --------------------------------------------------------------------------

  !> Find the rows this rank writes, sorted by global position, and their runs of consecutive
  !> global positions; check that the ranks' rows cover every global position exactly once.
  subroutine build_row_map(map, global_position, written, nglobal, entity_name)
    type(row_map_t), intent(out) :: map             !< the result
    integer, intent(in) :: global_position(:)       !< (nlocal) 1-based global position of rows
    logical, intent(in) :: written(:)               !< (nlocal) true for rows this rank writes
    integer, intent(in) :: nglobal                  !< rows of the global dataset
    character(len=*), intent(in) :: entity_name     !< 'node' or 'cell', for messages
    integer, allocatable :: positions(:), cover(:)
    integer :: nwritten, k, nruns
    logical :: bad
    map%nlocal = size(global_position)
    map%nglobal = nglobal
    nwritten = count(written)
    map%order = pack([(k, k = 1, map%nlocal)], written)
    positions = global_position(map%order)
    bad = any(positions < 1 .or. positions > nglobal)
    if (comm_any(bad)) call fatal('HDF5 output '''//file_path//''': '//entity_name// &
                                  ' global position out of range')
    call sort_by_key(positions, map%order)

    ! Every global position must be written by exactly one rank.
    allocate(cover(nglobal), source=0)
    do k = 1, nwritten
      cover(positions(k)) = cover(positions(k)) + 1
    end do
    call comm_sum(cover)
    if (any(cover /= 1)) call fatal('HDF5 output '''//file_path//''': the ranks'' '// &
        entity_name//'s do not cover every global position exactly once (ownership error)')
    deallocate(cover)

    nruns = 0
    do k = 1, nwritten
      if (k == 1) then
        nruns = nruns + 1
      else if (positions(k) /= positions(k-1) + 1) then
        nruns = nruns + 1
      end if
    end do
    allocate(map%run_start(nruns), map%run_length(nruns))
    nruns = 0
    do k = 1, nwritten
      if (k > 1) then
        if (positions(k) == positions(k-1) + 1) then
          map%run_length(nruns) = map%run_length(nruns) + 1
          cycle
        end if
      end if
      nruns = nruns + 1
      map%run_start(nruns) = int(positions(k) - 1, HSIZE_T)
      map%run_length(nruns) = 1
    end do
  end subroutine build_row_map

  !> Select runs of rows in a dataspace of shape (n) or (ncomp, n); none if there is no run.
  !>
  !> HDF5 1.10 adds a block to a hyperslab union (H5S_SELECT_OR) in time proportional to the
  !> blocks already selected, so adding 1e5 runs one by one takes minutes. Runs are therefore
  !> selected in small groups and the groups merged pairwise (H5Smodify_select), which costs
  !> O(n log n): 5e5 runs per rank select in about 1 s (measured, doc/hdf5_layout.md).
  subroutine select_runs(space, ncomp, run_start, run_length)
    integer(HID_T), intent(in) :: space               !< dataspace to select in
    integer, intent(in) :: ncomp                      !< 0 for one dimension, else components
    integer(HSIZE_T), intent(in) :: run_start(:)      !< 0-based first row of each run
    integer(HSIZE_T), intent(in) :: run_length(:)     !< rows of each run
    integer :: hdferr
    if (size(run_start) == 0) then
      call h5sselect_none_f(space, hdferr)
    else
      hdferr = 0
      call select_run_range(space, ncomp, run_start, run_length, 1, size(run_start), hdferr)
    end if
    call check(hdferr, 'cannot select rows')
  end subroutine select_runs

  !> Select runs first..last in a dataspace (replacing its selection), merging halves.
  !> Errors are accumulated in hdferr and checked by the caller (ranks recurse differently).
  recursive subroutine select_run_range(space, ncomp, run_start, run_length, first, last, &
                                        hdferr)
    integer(HID_T), intent(in) :: space               !< dataspace to select in
    integer, intent(in) :: ncomp                      !< 0 for one dimension, else components
    integer(HSIZE_T), intent(in) :: run_start(:)      !< 0-based first row of each run
    integer(HSIZE_T), intent(in) :: run_length(:)     !< rows of each run
    integer, intent(in) :: first, last                !< runs to select
    integer, intent(inout) :: hdferr                  !< stays >= 0 unless a call failed
    integer(HSIZE_T) :: start(2), counts(2), dims(2), maxdims(2)
    integer(HID_T) :: other
    integer :: r, operation, middle, rank, status
    if (last - first < LEAF_RUNS) then
      do r = first, last
        operation = H5S_SELECT_OR_F
        if (r == first) operation = H5S_SELECT_SET_F
        if (ncomp == 0) then
          call h5sselect_hyperslab_f(space, operation, run_start(r:r), run_length(r:r), &
                                     status)
        else
          start = [0_HSIZE_T, run_start(r)]
          counts = [int(ncomp, HSIZE_T), run_length(r)]
          call h5sselect_hyperslab_f(space, operation, start, counts, status)
        end if
        hdferr = min(hdferr, status)
      end do
      return
    end if
    middle = (first + last)/2
    call select_run_range(space, ncomp, run_start, run_length, first, middle, hdferr)
    rank = merge(1, 2, ncomp == 0)
    call h5sget_simple_extent_dims_f(space, dims(1:rank), maxdims(1:rank), status)
    call h5screate_simple_f(rank, dims(1:rank), other, status)
    hdferr = min(hdferr, status)
    call select_run_range(other, ncomp, run_start, run_length, middle + 1, last, hdferr)
    status = h5s_modify_select(int(space, c_int64_t), int(H5S_SELECT_OR_F, c_int), &
                               int(other, c_int64_t))
    hdferr = min(hdferr, status)
    call h5sclose_f(other, status)
  end subroutine select_run_range

  !> Dataspaces of this rank's rows for an entity and component count, built on first use.
  subroutine get_selection(entity, ncomp, file_space, memory_space)
    integer, intent(in) :: entity                   !< ENTITY_NODE or ENTITY_CELL
    integer, intent(in) :: ncomp                    !< 0: one-dimensional; else components
    integer(HID_T), intent(out) :: file_space       !< global dataspace, this rank's rows selected
    integer(HID_T), intent(out) :: memory_space     !< packed rows (none selected if no row)
    type(selection_t), allocatable :: grown(:)
    integer :: s, hdferr, nrows
    do s = 1, nselections
      if (selections(s)%entity == entity .and. selections(s)%ncomp == ncomp) then
        file_space = selections(s)%file_space
        memory_space = selections(s)%memory_space
        return
      end if
    end do
    nrows = size(maps(entity)%order)
    call create_space(ncomp, int(maps(entity)%nglobal, i8), file_space)
    call select_runs(file_space, ncomp, maps(entity)%run_start, maps(entity)%run_length)
    call create_space(ncomp, int(max(nrows, 1), i8), memory_space)
    hdferr = 0
    if (nrows == 0) call h5sselect_none_f(memory_space, hdferr)
    call check(hdferr, 'cannot clear a selection')
    if (.not. allocated(selections)) allocate(selections(4))
    if (nselections == size(selections)) then
      allocate(grown(2*nselections))
      grown(1:nselections) = selections
      call move_alloc(grown, selections)
    end if
    nselections = nselections + 1
    selections(nselections) = selection_t(entity, ncomp, file_space, memory_space)
  end subroutine get_selection

  !> Create a simple dataspace of shape (n) if ncomp == 0, else (ncomp, n).
  subroutine create_space(ncomp, n, space)
    integer, intent(in) :: ncomp            !< 0 for one dimension, else components
    integer(i8), intent(in) :: n            !< rows
    integer(HID_T), intent(out) :: space    !< the new dataspace
    integer :: hdferr
    if (ncomp == 0) then
      call h5screate_simple_f(1, [int(n, HSIZE_T)], space, hdferr)
    else
      call h5screate_simple_f(2, [int(ncomp, HSIZE_T), int(n, HSIZE_T)], space, hdferr)
    end if
    call check(hdferr, 'cannot create a dataspace')
  end subroutine create_space

  ! ---- datasets ----------------------------------------------------------------------------

  !> Write real rows (ncomp, nlocal) of an entity as dataset (ncomp, nglobal), float64.
  subroutine write_real_rows(name, entity, values)
    character(len=*), intent(in) :: name      !< full dataset path
    integer, intent(in) :: entity             !< ENTITY_NODE or ENTITY_CELL
    real(wp), intent(in) :: values(:,:)       !< (ncomp, nlocal) values of this piece's rows
    real(wp), allocatable, target :: buffer(:,:)
    integer(HID_T) :: file_space, memory_space
    integer :: k, ncomp
    ncomp = size(values, 1)
    call get_selection(entity, ncomp, file_space, memory_space)
    allocate(buffer(ncomp, max(size(maps(entity)%order), 1)), source=0.0_wp)
    do k = 1, size(maps(entity)%order)
      buffer(:, k) = values(:, maps(entity)%order(k))
    end do
    call write_dataset(name, H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), ncomp, &
                       int(maps(entity)%nglobal, i8), c_loc(buffer), file_space, memory_space)
  end subroutine write_real_rows

  !> Write integer rows (nlocal) of an entity as dataset (nglobal), int32.
  subroutine write_int_rows(name, entity, values)
    character(len=*), intent(in) :: name      !< full dataset path
    integer, intent(in) :: entity             !< ENTITY_NODE or ENTITY_CELL
    integer, intent(in) :: values(:)          !< (nlocal) values of this piece's rows
    integer, allocatable, target :: buffer(:)
    integer(HID_T) :: file_space, memory_space
    integer :: k
    call get_selection(entity, 0, file_space, memory_space)
    allocate(buffer(max(size(maps(entity)%order), 1)), source=0)
    do k = 1, size(maps(entity)%order)
      buffer(k) = values(maps(entity)%order(k))
    end do
    call write_dataset(name, H5T_STD_I32LE, h5kind_to_type(kind(buffer), H5_INTEGER_KIND), 0, &
                       int(maps(entity)%nglobal, i8), c_loc(buffer), file_space, memory_space)
  end subroutine write_int_rows

  !> Write /mesh/cell_offsets and /mesh/connectivity (0-based global node positions, int64).
  !>
  !> Offsets come from a global array of node counts per cell: every rank fills its cells'
  !> counts, a global sum completes it, and a prefix sum gives every cell's start. Simple and
  !> rank-independent; memory is O(ncell_global) on every rank.
  subroutine write_connectivity(mesh)
    type(output_mesh_t), intent(in) :: mesh   !< this rank's piece
    integer, allocatable :: counts(:)
    integer(i8), allocatable, target :: offsets(:), nodes(:), mixed(:)
    integer(HSIZE_T), allocatable :: run_start(:), run_length(:)
    integer(HID_T) :: file_space, memory_space
    integer(i8) :: total
    integer :: ncell_global, k, c, j, r, nruns, hdferr
    integer(HSIZE_T) :: first, last
    ncell_global = mesh%ncell_global
    allocate(counts(ncell_global), source=0)
    do c = 1, mesh%ncell
      counts(mesh%global_cell(c)) = mesh%cell_start(c+1) - mesh%cell_start(c)
    end do
    call comm_sum(counts)
    allocate(offsets(0:ncell_global))
    offsets(0) = 0_i8
    do k = 1, ncell_global
      offsets(k) = offsets(k-1) + int(counts(k), i8)
    end do
    total = offsets(ncell_global)
    deallocate(counts)

    ! Offsets: rank 0 writes the whole dataset (every rank holds it), the others nothing.
    call create_space(0, ncell_global + 1_i8, file_space)
    call create_space(0, ncell_global + 1_i8, memory_space)
    hdferr = 0
    if (.not. comm_is_root()) then
      call h5sselect_none_f(file_space, hdferr)
      if (hdferr >= 0) call h5sselect_none_f(memory_space, hdferr)
    end if
    call check(hdferr, 'cannot clear a selection')
    call write_dataset('/mesh/cell_offsets', H5T_STD_I64LE, &
                       h5kind_to_type(i8, H5_INTEGER_KIND), 0, ncell_global + 1_i8, &
                       c_loc(offsets), file_space, memory_space)
    call h5sclose_f(file_space, hdferr)
    call h5sclose_f(memory_space, hdferr)

    ! Connectivity: the node lists of this rank's cells, in global cell order; a run of
    ! consecutive cells is a run of consecutive connectivity entries.
    associate(map => maps(ENTITY_CELL))
      nruns = size(map%run_start)
      allocate(run_start(nruns), run_length(nruns))
      do r = 1, nruns
        first = int(offsets(map%run_start(r)), HSIZE_T)
        last = int(offsets(map%run_start(r) + map%run_length(r)), HSIZE_T)
        run_start(r) = first
        run_length(r) = last - first
      end do
      allocate(nodes(max(mesh%cell_start(mesh%ncell+1) - 1, 1)), source=0_i8)
      j = 0
      do k = 1, size(map%order)
        c = map%order(k)
        nodes(j+1:j+mesh%cell_start(c+1)-mesh%cell_start(c)) = &
            int(mesh%global_node(mesh%conn(mesh%cell_start(c):mesh%cell_start(c+1)-1)) - 1, i8)
        j = j + mesh%cell_start(c+1) - mesh%cell_start(c)
      end do
    end associate
    call write_int64_runs('/mesh/connectivity', total, run_start, run_length, nodes, j)

    ! XDMF's mixed topology: per cell its XDMF type code, then its nodes; cell k (0-based)
    ! starts at offsets(k) + k. The same runs as the connectivity, one entry longer per cell.
    associate(map => maps(ENTITY_CELL))
      do r = 1, nruns
        first = int(offsets(map%run_start(r)) + map%run_start(r), HSIZE_T)
        last = int(offsets(map%run_start(r) + map%run_length(r)) + map%run_start(r) + &
                   map%run_length(r), HSIZE_T)
        run_start(r) = first
        run_length(r) = last - first
      end do
      allocate(mixed(max(j + size(map%order), 1)), source=0_i8)
      j = 0
      do k = 1, size(map%order)
        c = map%order(k)
        mixed(j+1) = int(xdmf_cell_type(mesh%topology(c)), i8)
        mixed(j+2:j+1+mesh%cell_start(c+1)-mesh%cell_start(c)) = &
            int(mesh%global_node(mesh%conn(mesh%cell_start(c):mesh%cell_start(c+1)-1)) - 1, i8)
        j = j + 1 + mesh%cell_start(c+1) - mesh%cell_start(c)
      end do
    end associate
    topology_length = total + int(ncell_global, i8)
    call write_int64_runs('/mesh/xdmf_topology', topology_length, run_start, run_length, &
                          mixed, j)
  end subroutine write_connectivity

  !> Write the int64 dataset name of n entries, of which this rank holds the runs (run_start
  !> 0-based, run_length) packed in values(1:nvalues) (collective).
  subroutine write_int64_runs(name, n, run_start, run_length, values, nvalues)
    character(len=*), intent(in) :: name                    !< dataset path
    integer(i8), intent(in) :: n                             !< entries of the dataset
    integer(HSIZE_T), intent(in) :: run_start(:)             !< 0-based start of each run
    integer(HSIZE_T), intent(in) :: run_length(:)            !< entries in each run
    integer(i8), intent(in), target, contiguous :: values(:) !< this rank's entries, packed
    integer, intent(in) :: nvalues                           !< how many (0: none)
    integer(HID_T) :: file_space, memory_space
    integer :: hdferr
    call create_space(0, n, file_space)
    call select_runs(file_space, 0, run_start, run_length)
    call create_space(0, int(max(nvalues, 1), i8), memory_space)
    hdferr = 0
    if (nvalues == 0) call h5sselect_none_f(memory_space, hdferr)
    call check(hdferr, 'cannot clear a selection')
    call write_dataset(name, H5T_STD_I64LE, h5kind_to_type(i8, H5_INTEGER_KIND), 0, n, &
                       c_loc(values), file_space, memory_space)
    call h5sclose_f(file_space, hdferr)
    call h5sclose_f(memory_space, hdferr)
  end subroutine write_int64_runs

  !> Entries of /mesh/xdmf_topology (the mixed topology the XDMF file points to).
  integer(i8) function h5_output_topology_length()
    h5_output_topology_length = topology_length
  end function h5_output_topology_length

  !> Create a dataset of shape (n) or (ncomp, n) and write this rank's selection collectively.
  subroutine write_dataset(name, file_type, memory_type, ncomp, n, buffer, file_space, &
                           memory_space)
    character(len=*), intent(in) :: name             !< full dataset path
    integer(HID_T), intent(in) :: file_type          !< type stored in the file
    integer(HID_T), intent(in) :: memory_type        !< type of the buffer
    integer, intent(in) :: ncomp                     !< 0 for one dimension, else components
    integer(i8), intent(in) :: n                     !< global rows
    type(c_ptr), intent(in) :: buffer                !< packed values of the selected rows
    integer(HID_T), intent(in) :: file_space         !< global dataspace with selection
    integer(HID_T), intent(in) :: memory_space       !< memory dataspace with selection
    integer(HID_T) :: dataset_id, shape_space
    integer :: hdferr
    call create_space(ncomp, n, shape_space)
    call h5dcreate_f(file_id, name, file_type, shape_space, dataset_id, hdferr, &
                     dcpl_id=create_list)
    call check(hdferr, 'cannot create dataset '//name)
    call h5sclose_f(shape_space, hdferr)
    call h5dwrite_f(dataset_id, memory_type, buffer, hdferr, memory_space, file_space, &
                    transfer_list)
    call check(hdferr, 'cannot write dataset '//name)
    call h5dclose_f(dataset_id, hdferr)
    call check(hdferr, 'cannot close dataset '//name)
  end subroutine write_dataset

  ! ---- time history ------------------------------------------------------------------------

  !> Create an empty, extendible one-dimensional dataset in /time_history.
  subroutine create_history_dataset(group_id, name, file_type)
    integer(HID_T), intent(in) :: group_id    !< the /time_history group
    character(len=*), intent(in) :: name      !< dataset name
    integer(HID_T), intent(in) :: file_type   !< stored type
    integer(HID_T) :: space, chunked_list, dataset_id
    integer :: hdferr
    call h5screate_simple_f(1, [0_HSIZE_T], space, hdferr, maxdims=[H5S_UNLIMITED_F])
    call check(hdferr, 'cannot create a dataspace')
    call h5pcreate_f(H5P_DATASET_CREATE_F, chunked_list, hdferr)
    call h5pset_chunk_f(chunked_list, 1, [HISTORY_CHUNK], hdferr)
    call check(hdferr, 'cannot set the chunk size of /time_history/'//name)
    call h5dcreate_f(group_id, name, file_type, space, dataset_id, hdferr, dcpl_id=chunked_list)
    call check(hdferr, 'cannot create /time_history/'//name)
    call h5dclose_f(dataset_id, hdferr)
    call h5pclose_f(chunked_list, hdferr)
    call h5sclose_f(space, hdferr)
  end subroutine create_history_dataset

  !> Append one state's step and time to /time_history/step and /time_history/time.
  subroutine append_history(step, time)
    integer, intent(in) :: step     !< step number
    real(wp), intent(in) :: time    !< simulation time
    integer, target :: step_value(1)
    real(wp), target :: time_value(1)
    nstates = nstates + 1
    step_value(1) = step
    time_value(1) = time
    call append_value('/time_history/step', h5kind_to_type(kind(step_value), H5_INTEGER_KIND), &
                      c_loc(step_value))
    call append_value('/time_history/time', h5kind_to_type(wp, H5_REAL_KIND), c_loc(time_value))
  end subroutine append_history

  !> Grow a /time_history dataset to nstates entries and write the last one (from rank 0).
  subroutine append_value(name, memory_type, value)
    character(len=*), intent(in) :: name           !< dataset path
    integer(HID_T), intent(in) :: memory_type      !< type of the value
    type(c_ptr), intent(in) :: value               !< one value, the same on every rank
    integer(HID_T) :: dataset_id, file_space, memory_space
    integer :: hdferr
    call h5dopen_f(file_id, name, dataset_id, hdferr)
    call check(hdferr, 'cannot open '//name)
    call h5dset_extent_f(dataset_id, [int(nstates, HSIZE_T)], hdferr)
    call check(hdferr, 'cannot extend '//name)
    call h5dget_space_f(dataset_id, file_space, hdferr)
    call select_runs(file_space, 0, [int(nstates - 1, HSIZE_T)], [1_HSIZE_T])
    call create_space(0, 1_i8, memory_space)
    hdferr = 0
    if (.not. comm_is_root()) then
      call h5sselect_none_f(file_space, hdferr)
      if (hdferr >= 0) call h5sselect_none_f(memory_space, hdferr)
    end if
    call check(hdferr, 'cannot clear a selection')
    call h5dwrite_f(dataset_id, memory_type, value, hdferr, memory_space, file_space, &
                    transfer_list)
    call check(hdferr, 'cannot write '//name)
    call h5sclose_f(memory_space, hdferr)
    call h5sclose_f(file_space, hdferr)
    call h5dclose_f(dataset_id, hdferr)
  end subroutine append_value

  ! ---- groups, attributes, flushing --------------------------------------------------------

  !> Create a group (collectively).
  subroutine create_group(location, name, group_id)
    integer(HID_T), intent(in) :: location     !< file or parent group
    character(len=*), intent(in) :: name       !< group name or path
    integer(HID_T), intent(out) :: group_id    !< the new group, to be closed by the caller
    integer :: hdferr
    call h5gcreate_f(location, name, group_id, hdferr)
    call check(hdferr, 'cannot create group '//name)
  end subroutine create_group

  !> Attach a scalar double attribute.
  subroutine write_attribute_real(location, name, value)
    integer(HID_T), intent(in) :: location   !< object carrying the attribute
    character(len=*), intent(in) :: name     !< attribute name
    real(wp), intent(in) :: value            !< the value, the same on every rank
    real(wp), target :: stored
    stored = value
    call write_attribute(location, name, H5T_IEEE_F64LE, h5kind_to_type(wp, H5_REAL_KIND), &
                         c_loc(stored))
  end subroutine write_attribute_real

  !> Attach a scalar int32 attribute.
  subroutine write_attribute_int(location, name, value)
    integer(HID_T), intent(in) :: location   !< object carrying the attribute
    character(len=*), intent(in) :: name     !< attribute name
    integer, intent(in) :: value             !< the value, the same on every rank
    integer, target :: stored
    stored = value
    call write_attribute(location, name, H5T_STD_I32LE, &
                         h5kind_to_type(kind(stored), H5_INTEGER_KIND), c_loc(stored))
  end subroutine write_attribute_int

  !> Attach a fixed-length ASCII string attribute.
  subroutine write_attribute_text(location, name, text)
    integer(HID_T), intent(in) :: location   !< object carrying the attribute
    character(len=*), intent(in) :: name     !< attribute name
    character(len=*), intent(in) :: text     !< the value, the same on every rank
    character(kind=c_char), target :: stored(max(len(text), 1))
    integer(HID_T) :: text_type
    integer :: hdferr, k
    stored = c_char_' '
    do k = 1, len(text)
      stored(k) = text(k:k)
    end do
    call h5tcopy_f(H5T_C_S1, text_type, hdferr)
    call h5tset_size_f(text_type, int(size(stored), SIZE_T), hdferr)
    call h5tset_strpad_f(text_type, H5T_STR_NULLPAD_F, hdferr)
    call check(hdferr, 'cannot make a string type')
    call write_attribute(location, name, text_type, text_type, c_loc(stored))
    call h5tclose_f(text_type, hdferr)
  end subroutine write_attribute_text

  !> Create a scalar attribute and write its value.
  subroutine write_attribute(location, name, file_type, memory_type, value)
    integer(HID_T), intent(in) :: location      !< object carrying the attribute
    character(len=*), intent(in) :: name        !< attribute name
    integer(HID_T), intent(in) :: file_type     !< stored type
    integer(HID_T), intent(in) :: memory_type   !< type of the value
    type(c_ptr), intent(in) :: value            !< the value
    integer(HID_T) :: space, attribute_id
    integer :: hdferr
    call h5screate_f(H5S_SCALAR_F, space, hdferr)
    call h5acreate_f(location, name, file_type, space, attribute_id, hdferr)
    call check(hdferr, 'cannot create attribute '//name)
    call h5awrite_f(attribute_id, memory_type, value, hdferr)
    call check(hdferr, 'cannot write attribute '//name)
    call h5aclose_f(attribute_id, hdferr)
    call h5sclose_f(space, hdferr)
  end subroutine write_attribute

  !> Push everything written so far to the file, so that it is readable if the run dies.
  subroutine flush_file()
    integer :: hdferr
    call h5fflush_f(file_id, H5F_SCOPE_GLOBAL_F, hdferr)
    call check(hdferr, 'cannot flush the file')
  end subroutine flush_file

  ! ---- sorting -----------------------------------------------------------------------------

  !> Reorder `order` so that key(k) ascends, where key(k) is the k-th entry of keys; keys are
  !> given in the current order of `order` and permuted with it (stable merge sort).
  subroutine sort_by_key(keys, order)
    integer, intent(inout) :: keys(:)    !< sort keys, one per entry of order
    integer, intent(inout) :: order(:)   !< the values to reorder
    integer, allocatable :: key_work(:), order_work(:)
    integer :: n, width, left, middle, right, i, j, k
    n = size(keys)
    if (n < 2) return
    if (all(keys(2:n) >= keys(1:n-1))) return
    allocate(key_work(n), order_work(n))
    width = 1
    do while (width < n)
      left = 1
      do while (left <= n)
        middle = min(left + width, n + 1)
        right = min(left + 2*width, n + 1)
        i = left
        j = middle
        do k = left, right - 1
          if (i < middle .and. (j >= right .or. keys(min(i, n)) <= keys(min(j, n)))) then
            key_work(k) = keys(i)
            order_work(k) = order(i)
            i = i + 1
          else
            key_work(k) = keys(j)
            order_work(k) = order(j)
            j = j + 1
          end if
        end do
        left = right
      end do
      keys = key_work
      order = order_work
      width = 2*width
    end do
  end subroutine sort_by_key

end module mefem_hdf5_output
