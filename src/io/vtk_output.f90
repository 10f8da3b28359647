!> VTK XML result writer: one UnstructuredGrid piece per rank, a parallel index, a time collection.
!>
!> Every rank writes its own piece as `dir/basename_SSSSSS_RRRR.vtu` (step SSSSSS, rank RRRR) and
!> rank 0 writes `dir/basename_SSSSSS.pvtu` that lists the pieces by relative file name. On one
!> rank the piece is `dir/basename_SSSSSS.vtu` and there is no .pvtu. Rank 0 then rewrites
!> `dir/basename.pvd` (a Collection of every state written so far, with its time), so that the
!> .pvd opens in ParaView at any moment of a run. The .pvd is written to a temporary file in `dir`
!> and renamed over the old one, so that a run that dies while writing leaves the previous,
!> complete collection in place.
!>
!> Piece files use raw appended binary data (header_type UInt64: each block is preceded by its
!> byte count) and are written with one unformatted stream write per array: points Float64 (3),
!> connectivity and offsets Int64, cell types UInt8, ids Int32, fields Float64. Point data holds
!> "node_id", "GlobalNodeIds" (the node ids again, Int64, named the point data's GlobalIds:
!> ParaView joins the copies of a node on the pieces' cuts) and the given point fields, cell
!> data "element_id", "part_id", "GlobalCellIds" (the cell's global position, Int64, the cell
!> data's GlobalIds) and the given cell fields; the grid's field data "TimeValue" the time. The connectivity is written in the order of output_mesh_t%conn: a PENTA6 cell must
!> therefore list its nodes in VTK wedge order (nodes 1-3 one triangle, 4-6 the opposite one,
!> node 3+k above node k, with 1-2-3 turning clockwise when seen from the 4-5-6 side).
module mefem_vtk_output
  use, intrinsic :: iso_fortran_env, only: int8, int32
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_rank, comm_size, comm_is_root, comm_barrier
  use mefem_errors, only: fatal_local
  use mefem_output_mesh, only: output_mesh_t, output_field_t, vtk_cell_type, NODES_OF_TOPO
  implicit none
  private

  public :: vtk_write_state, vtk_reset_collection, vtk_collection_states, vtk_collection_restore

  character(len=*), parameter :: LF = achar(10)   !< line end in the XML text
  character(len=*), parameter :: CALLER = 'vtk_write_state'   !< prefix of error messages

  !> A file name of any length (element of an array of names).
  type :: file_name_t
    character(len=:), allocatable :: name        !< the name, relative to the .pvd's directory
  end type file_name_t

  !> One time collection (.pvd file): the states written so far, in the order written.
  type :: collection_t
    character(len=:), allocatable :: path        !< dir/basename.pvd
    integer :: nstate = 0                        !< states recorded
    real(wp), allocatable :: time(:)             !< (capacity) time of each state
    type(file_name_t), allocatable :: file(:)    !< (capacity) .vtu/.pvtu of each state
  end type collection_t

  !> Description of one appended data array: its XML attributes and its size in bytes.
  type :: array_info_t
    character(len=:), allocatable :: name        !< Name attribute ('' for the points)
    character(len=:), allocatable :: vtk_type    !< Int32, Int64, UInt8, Float64
    integer :: ncomp = 1                         !< NumberOfComponents
    integer(i8) :: nbytes = 0_i8                 !< bytes of data (without the UInt64 header)
  end type array_info_t

  integer :: ncollection = 0
  type(collection_t), allocatable :: collections(:)

  interface
    !> C library rename(): atomically replaces `new_path` with `old_path` on POSIX systems.
    function c_rename(old_path, new_path) bind(C, name='rename') result(status)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: old_path(*)   !< NUL-terminated source name
      character(kind=c_char), intent(in) :: new_path(*)   !< NUL-terminated target name
      integer(c_int) :: status
    end function c_rename
  end interface

  !> The point array ParaView and VTK take as the points' global ids (the node ids, Int64 as
  !> vtkIdType): the copies of a node in several ranks' pieces are known as one node
  character(len=*), parameter :: GLOBAL_NODE_IDS = 'GlobalNodeIds'
  !> the cells' global ids: their position in the rank-independent global cell order (0-based,
  !> as the rows of the HDF5 file's cell datasets): unique where element ids are not (solids
  !> and shells may share ids, as in LS-DYNA)
  character(len=*), parameter :: GLOBAL_CELL_IDS = 'GlobalCellIds'

contains

  !> Write one output state: every rank its piece, rank 0 the .pvtu index and the .pvd collection.
  !> Collective: every rank calls it with the same dir, basename, step, time and field names.
  subroutine vtk_write_state(dir, basename, step, time, mesh, point_fields, cell_fields)
    character(len=*), intent(in) :: dir                      !< existing output directory
    character(len=*), intent(in) :: basename                 !< file name stem
    integer, intent(in) :: step                              !< output step number
    real(wp), intent(in) :: time                             !< simulation time of the state
    type(output_mesh_t), intent(in) :: mesh                  !< this rank's piece
    type(output_field_t), intent(in) :: point_fields(:)      !< values(ncomp, mesh%nnode)
    type(output_field_t), intent(in) :: cell_fields(:)       !< values(ncomp, mesh%ncell)
    character(len=:), allocatable :: stem, piece_name, index_name
    integer :: nranks, rank

    nranks = comm_size()
    rank = comm_rank()
    call check_piece(mesh, point_fields, cell_fields)
    stem = trim(basename)//'_'//padded(step, 6)
    if (nranks > 1) then
      piece_name = stem//'_'//padded(rank, 4)//'.vtu'
      index_name = stem//'.pvtu'
    else
      piece_name = stem//'.vtu'
      index_name = piece_name
    end if
    call write_piece(join_path(dir, piece_name), mesh, time, point_fields, cell_fields)
    if (nranks > 1 .and. comm_is_root()) then
      call write_parallel_index(join_path(dir, index_name), stem, nranks, point_fields, &
                                cell_fields)
    end if
    ! the collection must only name states whose pieces are all complete
    if (nranks > 1) call comm_barrier()
    call record_state(join_path(dir, trim(basename)//'.pvd'), time, index_name)
  end subroutine vtk_write_state

  !> The states a collection (.pvd) lists: their times and files, the files joined by line
  !> feeds (a restart file keeps them).
  subroutine vtk_collection_states(pvd_path, times, files)
    character(len=*), intent(in) :: pvd_path             !< dir/basename.pvd
    real(wp), allocatable, intent(out) :: times(:)       !< time of each state
    character(len=:), allocatable, intent(out) :: files  !< their files, one per line
    integer :: ic, k
    ic = find_collection(pvd_path)
    associate (col => collections(ic))
      times = col%time(1:col%nstate)
      files = ''
      do k = 1, col%nstate
        files = files//col%file(k)%name//LF
      end do
    end associate
  end subroutine vtk_collection_states

  !> Make a collection list the states given (as vtk_collection_states returned them) and
  !> rewrite its .pvd: a restarted run goes on from the states written before its restart
  !> file.
  subroutine vtk_collection_restore(pvd_path, times, files)
    character(len=*), intent(in) :: pvd_path             !< dir/basename.pvd
    real(wp), intent(in) :: times(:)                     !< time of each state
    character(len=*), intent(in) :: files                !< their files, one per line
    integer :: ic, k, start, finish
    ic = find_collection(pvd_path)
    associate (col => collections(ic))
      col%nstate = 0
      start = 1
      do k = 1, size(times)
        finish = index(files(start:), LF) + start - 1
        if (col%nstate == size(col%time)) call grow_collection(col)
        col%nstate = col%nstate + 1
        col%time(k) = times(k)
        col%file(k)%name = files(start:finish - 1)
        start = finish + 1
      end do
      if (comm_is_root()) call write_collection(col)
    end associate
  end subroutine vtk_collection_restore

  !> Forget all recorded states: the next write of a basename starts a new .pvd (tests, restarts).
  subroutine vtk_reset_collection()
    if (allocated(collections)) deallocate(collections)
    ncollection = 0
  end subroutine vtk_reset_collection

  !> Stop with a message when the piece or the fields are inconsistent (a programming error).
  subroutine check_piece(mesh, point_fields, cell_fields)
    type(output_mesh_t), intent(in) :: mesh                  !< this rank's piece
    type(output_field_t), intent(in) :: point_fields(:)      !< fields on nodes
    type(output_field_t), intent(in) :: cell_fields(:)       !< fields on cells
    integer :: c, k, first, last
    character(len=:), allocatable :: bad

    bad = ''
    if (mesh%nnode < 0 .or. mesh%ncell < 0) bad = 'negative node or cell count'
    if (mesh%nnode > 0 .and. len(bad) == 0) then
      if (.not. (allocated(mesh%x) .and. allocated(mesh%node_id))) then
        bad = 'x or node_id not allocated'
      else if (size(mesh%x, 1) /= 3 .or. size(mesh%x, 2) < mesh%nnode .or. &
               size(mesh%node_id) < mesh%nnode) then
        bad = 'x or node_id too small for nnode'
      end if
    end if
    if (mesh%ncell > 0 .and. len(bad) == 0) then
      if (.not. (allocated(mesh%topology) .and. allocated(mesh%cell_start) .and. &
                 allocated(mesh%conn) .and. allocated(mesh%cell_id) .and. &
                 allocated(mesh%cell_part))) then
        bad = 'topology, cell_start, conn, cell_id or cell_part not allocated'
      else if (size(mesh%topology) < mesh%ncell .or. size(mesh%cell_start) < mesh%ncell + 1 &
               .or. size(mesh%cell_id) < mesh%ncell .or. size(mesh%cell_part) < mesh%ncell) then
        bad = 'cell arrays too small for ncell'
      else if (mesh%cell_start(1) < 1 .or. mesh%cell_start(mesh%ncell + 1) - 1 > &
               size(mesh%conn)) then
        bad = 'cell_start outside conn'
      end if
    end if
    if (len(bad) == 0) then
      do c = 1, mesh%ncell
        if (vtk_cell_type(mesh%topology(c)) == 0) then
          bad = 'cell '//itoa(c)//' has unknown topology '//itoa(mesh%topology(c))
          exit
        end if
        first = mesh%cell_start(c)
        last = mesh%cell_start(c + 1) - 1
        if (last - first + 1 /= NODES_OF_TOPO(mesh%topology(c))) then
          bad = 'cell '//itoa(c)//' has '//itoa(last - first + 1)//' nodes for its topology'
          exit
        end if
        if (any(mesh%conn(first:last) < 1) .or. any(mesh%conn(first:last) > mesh%nnode)) then
          bad = 'cell '//itoa(c)//' refers to a node outside 1..nnode'
          exit
        end if
      end do
    end if
    do k = 1, size(point_fields)
      if (len(bad) > 0) exit
      if (.not. field_fits(point_fields(k), mesh%nnode)) bad = 'point field '//itoa(k)// &
        ' "'//trim(point_fields(k)%name)//'" is unnamed or not sized (ncomp, nnode)'
    end do
    do k = 1, size(cell_fields)
      if (len(bad) > 0) exit
      if (.not. field_fits(cell_fields(k), mesh%ncell)) bad = 'cell field '//itoa(k)// &
        ' "'//trim(cell_fields(k)%name)//'" is unnamed or not sized (ncomp, ncell)'
    end do
    if (len(bad) > 0) call fatal_local(CALLER//': rank '//itoa(comm_rank())//': '//bad)
  end subroutine check_piece

  !> True when a field has a name and holds exactly (ncomp, n) values, ncomp >= 1.
  logical function field_fits(field, n)
    type(output_field_t), intent(in) :: field   !< the field
    integer, intent(in) :: n                     !< number of entities (nodes or cells)
    field_fits = .false.
    if (field%ncomp < 1 .or. len_trim(field%name) == 0) return
    if (.not. allocated(field%values)) then
      field_fits = (n == 0)
      return
    end if
    field_fits = size(field%values, 1) == field%ncomp .and. size(field%values, 2) == n
  end function field_fits

  !> Write this rank's piece as a .vtu file with raw appended data.
  subroutine write_piece(path, mesh, time, point_fields, cell_fields)
    character(len=*), intent(in) :: path                     !< file to write
    type(output_mesh_t), intent(in) :: mesh                  !< this rank's piece
    real(wp), intent(in) :: time                             !< the state's time (TimeValue)
    type(output_field_t), intent(in) :: point_fields(:)      !< fields on nodes
    type(output_field_t), intent(in) :: cell_fields(:)       !< fields on cells
    type(array_info_t), allocatable :: point_arrays(:), cell_arrays(:)
    type(array_info_t) :: points, connectivity, offsets, types
    integer(i8), allocatable :: conn64(:), offsets64(:)
    integer(int8), allocatable :: types8(:)
    character(len=:), allocatable :: text
    integer(i8) :: offset
    integer :: unit, ios, k, c, nnode, ncell, nconn
    character(len=256) :: message
    character(len=32) :: time_text

    write(time_text, '(es25.17e3)') time
    nnode = mesh%nnode
    ncell = mesh%ncell
    nconn = 0
    if (ncell > 0) nconn = mesh%cell_start(ncell + 1) - mesh%cell_start(1)

    ! cell arrays in VTK form: 0-based connectivity, cumulative end offsets, UInt8 types
    allocate(conn64(nconn), offsets64(ncell), types8(ncell))
    if (ncell > 0) then
      conn64 = int(mesh%conn(mesh%cell_start(1):mesh%cell_start(ncell + 1) - 1), i8) - 1_i8
      offsets64 = int(mesh%cell_start(2:ncell + 1) - mesh%cell_start(1), i8)
      do c = 1, ncell
        types8(c) = int(vtk_cell_type(mesh%topology(c)), int8)
      end do
    end if

    ! what is written, in order: point data, cell data, points, cells
    allocate(point_arrays(2 + size(point_fields)), cell_arrays(3 + size(cell_fields)))
    point_arrays(1) = info('node_id', integer_type(), 1, nnode, storage_size(1) / 8)
    point_arrays(2) = info(GLOBAL_NODE_IDS, 'Int64', 1, nnode, 8)
    do k = 1, size(point_fields)
      point_arrays(2 + k) = info(trim(point_fields(k)%name), 'Float64', point_fields(k)%ncomp, &
                                 nnode, storage_size(1.0_wp) / 8)
    end do
    cell_arrays(1) = info('element_id', integer_type(), 1, ncell, storage_size(1) / 8)
    cell_arrays(2) = info('part_id', integer_type(), 1, ncell, storage_size(1) / 8)
    cell_arrays(3) = info(GLOBAL_CELL_IDS, 'Int64', 1, ncell, 8)
    do k = 1, size(cell_fields)
      cell_arrays(3 + k) = info(trim(cell_fields(k)%name), 'Float64', cell_fields(k)%ncomp, &
                                ncell, storage_size(1.0_wp) / 8)
    end do
    points = info('', 'Float64', 3, nnode, storage_size(1.0_wp) / 8)
    connectivity = info('connectivity', 'Int64', 1, nconn, 8)
    offsets = info('offsets', 'Int64', 1, ncell, 8)
    types = info('types', 'UInt8', 1, ncell, 1)

    ! XML header; offsets count from the byte after the '_' that opens the appended data
    offset = 0_i8
    text = '<?xml version="1.0"?>'//LF// &
           '<VTKFile type="UnstructuredGrid" version="1.0" byte_order="'//byte_order()// &
           '" header_type="UInt64">'//LF//'  <UnstructuredGrid>'//LF// &
           '    <FieldData>'//LF//'      <DataArray type="Float64" Name="TimeValue" '// &
           'NumberOfTuples="1" format="ascii">'//trim(adjustl(time_text))//'</DataArray>'//LF// &
           '    </FieldData>'//LF// &
           '    <Piece NumberOfPoints="'//itoa(nnode)//'" NumberOfCells="'//itoa(ncell)//'">'//LF
    text = text//'      <PointData GlobalIds="'//GLOBAL_NODE_IDS//'">'//LF
    do k = 1, size(point_arrays)
      text = text//data_array_tag(point_arrays(k), offset)
    end do
    text = text//'      </PointData>'//LF//'      <CellData GlobalIds="'//GLOBAL_CELL_IDS//'">'//LF
    do k = 1, size(cell_arrays)
      text = text//data_array_tag(cell_arrays(k), offset)
    end do
    text = text//'      </CellData>'//LF//'      <Points>'//LF// &
           data_array_tag(points, offset)//'      </Points>'//LF//'      <Cells>'//LF// &
           data_array_tag(connectivity, offset)//data_array_tag(offsets, offset)// &
           data_array_tag(types, offset)//'      </Cells>'//LF//'    </Piece>'//LF// &
           '  </UnstructuredGrid>'//LF//'  <AppendedData encoding="raw">'//LF//'_'

    call open_stream(path, unit)
    write(unit, iostat=ios, iomsg=message) text
    ! point data
    if (ios == 0) write(unit, iostat=ios, iomsg=message) point_arrays(1)%nbytes
    if (ios == 0 .and. nnode > 0) write(unit, iostat=ios, iomsg=message) mesh%node_id(1:nnode)
    if (ios == 0) write(unit, iostat=ios, iomsg=message) point_arrays(2)%nbytes
    if (ios == 0 .and. nnode > 0) write(unit, iostat=ios, iomsg=message) &
      int(mesh%node_id(1:nnode), i8)
    do k = 1, size(point_fields)
      if (ios == 0) write(unit, iostat=ios, iomsg=message) point_arrays(2 + k)%nbytes
      if (ios == 0 .and. nnode > 0) write(unit, iostat=ios, iomsg=message) point_fields(k)%values
    end do
    ! cell data
    if (ios == 0) write(unit, iostat=ios, iomsg=message) cell_arrays(1)%nbytes
    if (ios == 0 .and. ncell > 0) write(unit, iostat=ios, iomsg=message) mesh%cell_id(1:ncell)
    if (ios == 0) write(unit, iostat=ios, iomsg=message) cell_arrays(2)%nbytes
    if (ios == 0 .and. ncell > 0) write(unit, iostat=ios, iomsg=message) mesh%cell_part(1:ncell)
    if (ios == 0) write(unit, iostat=ios, iomsg=message) cell_arrays(3)%nbytes
    if (ios == 0 .and. ncell > 0) write(unit, iostat=ios, iomsg=message) &
      int(mesh%global_cell(1:ncell) - 1, i8)
    do k = 1, size(cell_fields)
      if (ios == 0) write(unit, iostat=ios, iomsg=message) cell_arrays(3 + k)%nbytes
      if (ios == 0 .and. ncell > 0) write(unit, iostat=ios, iomsg=message) cell_fields(k)%values
    end do
    ! points and cells
    if (ios == 0) write(unit, iostat=ios, iomsg=message) points%nbytes
    if (ios == 0 .and. nnode > 0) write(unit, iostat=ios, iomsg=message) mesh%x(:, 1:nnode)
    if (ios == 0) write(unit, iostat=ios, iomsg=message) connectivity%nbytes, conn64
    if (ios == 0) write(unit, iostat=ios, iomsg=message) offsets%nbytes, offsets64
    if (ios == 0) write(unit, iostat=ios, iomsg=message) types%nbytes, types8
    if (ios == 0) write(unit, iostat=ios, iomsg=message) &
      LF//'  </AppendedData>'//LF//'</VTKFile>'//LF
    call close_stream(path, unit, ios, message)
  end subroutine write_piece

  !> Write the .pvtu file that gathers the pieces of all ranks (rank 0 only).
  subroutine write_parallel_index(path, stem, nranks, point_fields, cell_fields)
    character(len=*), intent(in) :: path                     !< file to write
    character(len=*), intent(in) :: stem                     !< basename_SSSSSS of the pieces
    integer, intent(in) :: nranks                            !< number of pieces
    type(output_field_t), intent(in) :: point_fields(:)      !< fields on nodes
    type(output_field_t), intent(in) :: cell_fields(:)       !< fields on cells
    character(len=:), allocatable :: text
    integer :: unit, ios, k, r
    character(len=256) :: message

    text = '<?xml version="1.0"?>'//LF// &
           '<VTKFile type="PUnstructuredGrid" version="1.0" byte_order="'//byte_order()// &
           '" header_type="UInt64">'//LF//'  <PUnstructuredGrid GhostLevel="0">'//LF// &
           '    <PPointData GlobalIds="'//GLOBAL_NODE_IDS//'">'//LF// &
           parallel_tag('node_id', integer_type(), 1)//parallel_tag(GLOBAL_NODE_IDS, 'Int64', 1)
    do k = 1, size(point_fields)
      text = text//parallel_tag(trim(point_fields(k)%name), 'Float64', point_fields(k)%ncomp)
    end do
    text = text//'    </PPointData>'//LF//'    <PCellData GlobalIds="'//GLOBAL_CELL_IDS//'">'// &
           LF//parallel_tag('element_id', integer_type(), 1)// &
           parallel_tag('part_id', integer_type(), 1)//parallel_tag(GLOBAL_CELL_IDS, 'Int64', 1)
    do k = 1, size(cell_fields)
      text = text//parallel_tag(trim(cell_fields(k)%name), 'Float64', cell_fields(k)%ncomp)
    end do
    text = text//'    </PCellData>'//LF//'    <PPoints>'//LF// &
           '      <PDataArray type="Float64" NumberOfComponents="3"/>'//LF//'    </PPoints>'//LF
    do r = 0, nranks - 1
      text = text//'    <Piece Source="'//xml_escape(stem//'_'//padded(r, 4)//'.vtu')//'"/>'//LF
    end do
    text = text//'  </PUnstructuredGrid>'//LF//'</VTKFile>'//LF

    call open_stream(path, unit)
    write(unit, iostat=ios, iomsg=message) text
    call close_stream(path, unit, ios, message)
  end subroutine write_parallel_index

  !> Add (or update) a state of a collection and rewrite its .pvd file (rank 0 writes).
  subroutine record_state(pvd_path, time, file_name)
    character(len=*), intent(in) :: pvd_path    !< dir/basename.pvd
    real(wp), intent(in) :: time                 !< time of the state
    character(len=*), intent(in) :: file_name    !< .vtu/.pvtu of the state, relative to dir
    integer :: ic, k

    ic = find_collection(pvd_path)
    associate (col => collections(ic))
      ! a state written again (same file) replaces the earlier entry
      do k = 1, col%nstate
        if (col%file(k)%name == file_name) exit
      end do
      if (k > col%nstate) then
        if (col%nstate == size(col%time)) call grow_collection(col)
        col%nstate = col%nstate + 1
        k = col%nstate
      end if
      col%time(k) = time
      col%file(k)%name = file_name
      if (comm_is_root()) call write_collection(col)
    end associate
  end subroutine record_state

  !> Index of the collection of a .pvd path, created empty when new.
  integer function find_collection(pvd_path) result(ic)
    character(len=*), intent(in) :: pvd_path    !< dir/basename.pvd
    type(collection_t), allocatable :: larger(:)
    do ic = 1, ncollection
      if (collections(ic)%path == pvd_path) return
    end do
    if (.not. allocated(collections)) allocate(collections(4))
    if (ncollection == size(collections)) then
      allocate(larger(2 * ncollection))
      larger(1:ncollection) = collections(1:ncollection)
      call move_alloc(larger, collections)
    end if
    ncollection = ncollection + 1
    ic = ncollection
    collections(ic)%path = pvd_path
    collections(ic)%nstate = 0
    allocate(collections(ic)%time(16), collections(ic)%file(16))
  end function find_collection

  !> Double the capacity of a collection's state list.
  subroutine grow_collection(col)
    type(collection_t), intent(inout) :: col    !< the collection
    real(wp), allocatable :: time(:)
    type(file_name_t), allocatable :: file(:)
    allocate(time(2 * size(col%time)), file(2 * size(col%time)))
    time(1:col%nstate) = col%time(1:col%nstate)
    file(1:col%nstate) = col%file(1:col%nstate)
    call move_alloc(time, col%time)
    call move_alloc(file, col%file)
  end subroutine grow_collection

  !> Write the whole .pvd of a collection to a temporary file, then rename it over the old one.
  subroutine write_collection(col)
    type(collection_t), intent(in) :: col       !< the collection
    character(len=:), allocatable :: text, temporary
    character(len=32) :: time_text
    integer :: unit, ios, k
    character(len=256) :: message

    text = '<?xml version="1.0"?>'//LF// &
           '<VTKFile type="Collection" version="1.0" byte_order="'//byte_order()//'">'//LF// &
           '  <Collection>'//LF
    do k = 1, col%nstate
      write(time_text, '(es25.17e3)') col%time(k)
      text = text//'    <DataSet timestep="'//trim(adjustl(time_text))// &
             '" group="" part="0" file="'//xml_escape(col%file(k)%name)//'"/>'//LF
    end do
    text = text//'  </Collection>'//LF//'</VTKFile>'//LF

    temporary = col%path//'.tmp'
    call open_stream(temporary, unit)
    write(unit, iostat=ios, iomsg=message) text
    call close_stream(temporary, unit, ios, message)
    if (c_rename(temporary//c_null_char, col%path//c_null_char) /= 0) then
      call fatal_local(CALLER//': cannot rename '//temporary//' to '//col%path)
    end if
  end subroutine write_collection

  !> Open a file for unformatted stream writing; fatal error (with the reason) if impossible.
  subroutine open_stream(path, unit)
    character(len=*), intent(in) :: path        !< file to create or replace
    integer, intent(out) :: unit                !< the unit opened
    integer :: ios
    character(len=256) :: message
    message = ''
    open(newunit=unit, file=path, access='stream', form='unformatted', status='replace', &
         action='write', iostat=ios, iomsg=message)
    if (ios /= 0) call fatal_local(CALLER//': cannot open '//path//' for writing: '// &
                                   trim(message))
  end subroutine open_stream

  !> Close a file written with open_stream; fatal error if a write or the close failed.
  subroutine close_stream(path, unit, write_status, write_message)
    character(len=*), intent(in) :: path            !< the file's name, for the message
    integer, intent(in) :: unit                     !< its unit
    integer, intent(in) :: write_status             !< iostat of the writes (0 = fine)
    character(len=*), intent(in) :: write_message   !< iomsg of the failed write
    integer :: ios, position, on_disk
    character(len=256) :: message
    if (write_status /= 0) then
      close(unit, iostat=ios)
      call fatal_local(CALLER//': cannot write '//path//': '//trim(write_message))
    end if
    inquire(unit=unit, pos=position)
    message = ''
    close(unit, iostat=ios, iomsg=message)
    if (ios /= 0) call fatal_local(CALLER//': cannot close '//path//': '//trim(message))
    ! gfortran does not report a write the system refused (a full disk: the writes and the
    ! close return 0): the file's size on disk, once closed, tells (mefem_text_file)
    inquire(file=path, size=on_disk)
    if (on_disk /= position - 1) call fatal_local(CALLER//': cannot write '//path//': '// &
        itoa(max(on_disk, 0))//' of its '//itoa(position - 1)//' bytes reached the disk '// &
        '(is the file system full?)')
  end subroutine close_stream

  !> Describe one appended array of n tuples of ncomp values of the given byte size.
  function info(name, vtk_type, ncomp, n, value_bytes) result(array)
    character(len=*), intent(in) :: name        !< Name attribute ('' for none)
    character(len=*), intent(in) :: vtk_type    !< VTK type name
    integer, intent(in) :: ncomp                !< components per tuple
    integer, intent(in) :: n                    !< number of tuples
    integer, intent(in) :: value_bytes          !< bytes per value
    type(array_info_t) :: array
    array%name = name
    array%vtk_type = vtk_type
    array%ncomp = ncomp
    array%nbytes = int(n, i8) * int(ncomp, i8) * int(value_bytes, i8)
  end function info

  !> DataArray tag of an appended array at `offset`; advances offset past its block.
  function data_array_tag(array, offset) result(tag)
    type(array_info_t), intent(in) :: array     !< the array
    integer(i8), intent(inout) :: offset        !< its offset; on return the next array's
    character(len=:), allocatable :: tag
    tag = '        <DataArray type="'//array%vtk_type//'"'
    if (len(array%name) > 0) tag = tag//' Name="'//xml_escape(array%name)//'"'
    if (array%ncomp /= 1) tag = tag//' NumberOfComponents="'//itoa(array%ncomp)//'"'
    tag = tag//' format="appended" offset="'//itoa8(offset)//'"/>'//LF
    offset = offset + 8_i8 + array%nbytes
  end function data_array_tag

  !> PDataArray tag of the parallel index.
  function parallel_tag(name, vtk_type, ncomp) result(tag)
    character(len=*), intent(in) :: name        !< array name
    character(len=*), intent(in) :: vtk_type    !< VTK type name
    integer, intent(in) :: ncomp                !< components per tuple
    character(len=:), allocatable :: tag
    tag = '      <PDataArray type="'//vtk_type//'" Name="'//xml_escape(name)//'"'
    if (ncomp /= 1) tag = tag//' NumberOfComponents="'//itoa(ncomp)//'"'
    tag = tag//'/>'//LF
  end function parallel_tag

  !> VTK type name of a default integer (Int32 unless the compiler is told otherwise).
  function integer_type() result(name)
    character(len=:), allocatable :: name
    if (storage_size(1) == 64) then
      name = 'Int64'
    else
      name = 'Int32'
    end if
  end function integer_type

  !> Byte order of this machine, as VTK names it.
  function byte_order() result(name)
    character(len=:), allocatable :: name
    integer(int8) :: bytes(4)
    bytes = transfer(1_int32, bytes)
    if (bytes(1) == 1_int8) then
      name = 'LittleEndian'
    else
      name = 'BigEndian'
    end if
  end function byte_order

  !> Text with the five XML special characters replaced by entities.
  function xml_escape(text) result(escaped)
    character(len=*), intent(in) :: text        !< raw text
    character(len=:), allocatable :: escaped
    integer :: i
    escaped = ''
    do i = 1, len(text)
      select case (text(i:i))
      case ('&')
        escaped = escaped//'&amp;'
      case ('<')
        escaped = escaped//'&lt;'
      case ('>')
        escaped = escaped//'&gt;'
      case ('"')
        escaped = escaped//'&quot;'
      case ("'")
        escaped = escaped//'&apos;'
      case default
        escaped = escaped//text(i:i)
      end select
    end do
  end function xml_escape

  !> dir/name (no separator added when dir is empty or already ends with '/').
  function join_path(dir, name) result(path)
    character(len=*), intent(in) :: dir         !< directory
    character(len=*), intent(in) :: name        !< file name
    character(len=:), allocatable :: path
    integer :: n
    n = len_trim(dir)
    if (n == 0) then
      path = name
    else if (dir(n:n) == '/') then
      path = dir(1:n)//name
    else
      path = dir(1:n)//'/'//name
    end if
  end function join_path

  !> Non-negative integer with leading zeros to at least `width` digits.
  function padded(value, width) result(text)
    integer, intent(in) :: value                !< the number
    integer, intent(in) :: width                !< minimum number of digits
    character(len=:), allocatable :: text
    text = itoa(value)
    if (value >= 0 .and. len(text) < width) text = repeat('0', width - len(text))//text
  end function padded

  !> Decimal text of a default integer.
  function itoa(value) result(text)
    integer, intent(in) :: value                !< the number
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0)') value
    text = trim(buffer)
  end function itoa

  !> Decimal text of an 8-byte integer.
  function itoa8(value) result(text)
    integer(i8), intent(in) :: value            !< the number
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0)') value
    text = trim(buffer)
  end function itoa8

end module mefem_vtk_output
