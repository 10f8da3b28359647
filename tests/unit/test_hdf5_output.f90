!> HDF5 result writer: every rank writes its piece of a small chain mesh and two states.
!>
!> The global mesh is a chain of 400 cells (hex8, penta6, tet4 in turn) between 401 square
!> sections of 4 nodes. Cells are split among the ranks in contiguous chunks; the nodes of a
!> section shared by two pieces are owned by the lower rank. Global positions are permuted
!> (position = 5*index + shift modulo the count, 7*index for cells), so on 2 and 3 ranks one
!> rank's rows form hundreds of separate runs in the file (more than the writer adds one by
!> one, so its merging of partial selections is exercised too). Rows this rank does not own
!> hold garbage (-999), so writing them would show.
!> Rank 0 also writes the expected global arrays, computed directly from the chain without the
!> pieces, to tests/out/h5_unit/np<N>_truth.txt; tests/output/test_hdf5_roundtrip.py compares.
!> With the argument `bad-path` or `die-after-state` the program exercises the failure paths
!> (driven by tests/output/test_hdf5_failures.py).
! ranks: 1 2 3
program test_hdf5_output
  use mefem_kinds, only: wp
  use mefem_comm, only: comm_rank, comm_size, comm_is_root, comm_barrier, comm_any
  use mefem_errors, only: fatal_local
  use mefem_output_mesh, only: output_mesh_t, output_field_t, TOPO_TET4, TOPO_PENTA6, &
                               TOPO_HEX8, vtk_cell_type
  use mefem_hdf5_output, only: h5_output_open, h5_output_write_mesh, h5_output_write_state, &
                               h5_output_close
  use mefem_testing, only: test_start, test_finish, check
  implicit none

  integer, parameter :: NCELL = 400                !< cells of the chain
  integer, parameter :: NSECTION = NCELL + 1       !< sections of 4 nodes
  integer, parameter :: NNODE = 4*NSECTION         !< nodes of the chain
  integer, parameter :: NSTATE = 2
  integer, parameter :: STEPS(NSTATE) = [0, 125]
  real(wp), parameter :: TIMES(NSTATE) = [0.0_wp, 2.5e-3_wp/3.0_wp]
  real(wp), parameter :: GARBAGE = -999.0_wp
  character(len=*), parameter :: POINT_NAMES(2) = ['displacement  ', 'temperature   ']
  character(len=*), parameter :: CELL_NAMES(2) = ['stress        ', 'plastic_strain']

  type(output_mesh_t) :: mesh
  type(output_field_t) :: point_fields(2), cell_fields(2)
  character(len=:), allocatable :: directory, h5_path, truth_path
  character(len=32) :: mode, suffix
  logical :: exists
  integer :: state, unit, file_size

  call test_start('hdf5_output')
  call get_command_argument(1, mode)
  directory = output_directory()
  write(suffix, '(a,i0)') 'np', comm_size()
  if (comm_is_root()) call execute_command_line('mkdir -p '//directory)
  call comm_barrier()

  if (mode == 'bad-path') then
    ! Must stop all ranks through mefem_errors with exit code 1, naming the path.
    call h5_output_open(directory//'/no_such_directory/'//trim(suffix)//'.h5')
    call check(.false., 'opening a file in a missing directory stops the run')
    call test_finish()
  end if

  call make_piece(mesh)
  if (mode == 'die-after-state') then
    ! Both states must be readable although the file is never closed.
    call h5_output_open(directory//'/died_'//trim(suffix)//'.h5')
    call h5_output_write_mesh(mesh)
    do state = 1, NSTATE
      call make_fields(mesh, state, point_fields, cell_fields)
      call h5_output_write_state(STEPS(state), TIMES(state), point_fields, cell_fields)
    end do
    call fatal_local('simulated crash after the last state (expected by the test)')
  end if

  h5_path = directory//'/'//trim(suffix)//'.h5'
  truth_path = directory//'/'//trim(suffix)//'_truth.txt'
  if (comm_is_root()) then
    ! A stale file at the path must be truncated by h5_output_open.
    open(newunit=unit, file=h5_path, status='replace', action='write')
    write(unit, '(a)') 'stale content that is not HDF5'
    close(unit)
    call write_truth(truth_path)
  end if
  call comm_barrier()

  call h5_output_open(h5_path)
  call h5_output_write_mesh(mesh)
  do state = 1, NSTATE
    call make_fields(mesh, state, point_fields, cell_fields)
    call h5_output_write_state(STEPS(state), TIMES(state), point_fields, cell_fields)
  end do
  call h5_output_close()

  inquire(file=h5_path, exist=exists, size=file_size)
  call check(exists .and. file_size > 1000, 'result file written: '//h5_path)
  inquire(file=truth_path, exist=exists)
  call check(exists, 'truth file written: '//truth_path)
  call check(comm_any(count(mesh%node_owned) < mesh%nnode) .eqv. comm_size() > 1, &
             'pieces share nodes exactly when there are several ranks')
  call test_finish()

contains

  !> tests/out/h5_unit under $MEFEM_ROOT, or under ../.. (the runner starts in tests/unit).
  function output_directory() result(path)
    character(len=:), allocatable :: path
    character(len=4096) :: root
    integer :: length, stat
    call get_environment_variable('MEFEM_ROOT', root, length, stat)
    if (stat /= 0 .or. length == 0) root = '../..'
    path = trim(root)//'/tests/out/h5_unit'
  end function output_directory

  !> Global (1-based) file position of chain node i: a permutation of 1..NNODE (gcd 1).
  pure integer function node_position(i)
    integer, intent(in) :: i   !< chain node index
    node_position = mod(5*(i - 1) + 3, NNODE) + 1
  end function node_position

  !> Global (1-based) file position of chain cell k: a permutation of 1..NCELL (gcd 1).
  pure integer function cell_position(k)
    integer, intent(in) :: k   !< chain cell index
    cell_position = mod(7*(k - 1) + 2, NCELL) + 1
  end function cell_position

  !> Chain index of corner j (1..4) of section s.
  pure integer function chain_node(s, j)
    integer, intent(in) :: s, j   !< section and corner
    chain_node = 4*(s - 1) + j
  end function chain_node

  !> Topology of chain cell k.
  pure integer function cell_topology(k)
    integer, intent(in) :: k   !< chain cell index
    select case (mod(k, 3))
    case (1)
      cell_topology = TOPO_HEX8
    case (2)
      cell_topology = TOPO_PENTA6
    case default
      cell_topology = TOPO_TET4
    end select
  end function cell_topology

  !> Chain node indices of chain cell k (between sections k and k+1).
  pure function cell_nodes(k) result(nodes)
    integer, intent(in) :: k   !< chain cell index
    integer, allocatable :: nodes(:)
    select case (cell_topology(k))
    case (TOPO_HEX8)
      nodes = [chain_node(k, 1), chain_node(k, 2), chain_node(k, 3), chain_node(k, 4), &
               chain_node(k+1, 1), chain_node(k+1, 2), chain_node(k+1, 3), chain_node(k+1, 4)]
    case (TOPO_PENTA6)
      nodes = [chain_node(k, 1), chain_node(k, 2), chain_node(k, 3), &
               chain_node(k+1, 1), chain_node(k+1, 2), chain_node(k+1, 3)]
    case default
      nodes = [chain_node(k, 1), chain_node(k, 2), chain_node(k, 3), chain_node(k+1, 1)]
    end select
  end function cell_nodes

  !> Reference coordinates of chain node i.
  pure function coordinate(i) result(x)
    integer, intent(in) :: i   !< chain node index
    real(wp) :: x(3)
    integer :: s, j
    s = (i - 1)/4 + 1
    j = i - 4*(s - 1)
    x(1) = 0.1_wp*(s - 1) + 1.0_wp/3.0_wp
    x(2) = merge(0.7_wp, 0.0_wp, j == 2 .or. j == 3) + 1.0e-3_wp*sin(real(i, wp))
    x(3) = merge(0.7_wp, 0.0_wp, j >= 3) - 1.0e-3_wp*cos(real(i, wp))
  end function coordinate

  !> Nodal field values of chain node i in a state: displacement (3) or temperature (1).
  pure function point_value(field, i, state) result(v)
    integer, intent(in) :: field, i, state   !< field number, chain node, state number
    real(wp), allocatable :: v(:)
    integer :: c
    if (field == 1) then
      v = [(1.5_wp*state + 0.25_wp*c + cos(real(i*c, wp)), c = 1, 3)]
    else
      v = [293.15_wp + 0.5_wp*i + state/7.0_wp]
    end if
  end function point_value

  !> Cell field values of chain cell k in a state: stress (6) or plastic strain (1).
  pure function cell_value(field, k, state) result(v)
    integer, intent(in) :: field, k, state   !< field number, chain cell, state number
    real(wp), allocatable :: v(:)
    integer :: c
    if (field == 1) then
      v = [(10.0_wp*k + c + 1.0e-3_wp*state*sin(real(k + c, wp)), c = 1, 6)]
    else
      v = [1.0e-4_wp*k*state/3.0_wp]
    end if
  end function cell_value

  !> First and last chain cell of a rank: contiguous chunks.
  subroutine cell_range(rank, first, last)
    integer, intent(in) :: rank            !< rank
    integer, intent(out) :: first, last    !< its chain cells
    first = rank*NCELL/comm_size() + 1
    last = (rank + 1)*NCELL/comm_size()
  end subroutine cell_range

  !> This rank's piece: its cells and all nodes of their sections, numbered in reverse.
  subroutine make_piece(piece)
    type(output_mesh_t), intent(out) :: piece   !< the piece
    integer :: first, last, first_node, last_node, i, l, k, c, first_owned
    integer, allocatable :: nodes(:)
    call cell_range(comm_rank(), first, last)
    first_node = chain_node(first, 1)
    last_node = chain_node(last + 1, 4)
    first_owned = first_node
    if (comm_rank() > 0) first_owned = chain_node(first + 1, 1)   ! lower rank owns section
    piece%nnode = last_node - first_node + 1
    piece%ncell = last - first + 1
    piece%nnode_global = NNODE
    piece%ncell_global = NCELL
    allocate(piece%x(3, piece%nnode), piece%node_id(piece%nnode), &
             piece%global_node(piece%nnode), piece%node_owned(piece%nnode))
    do i = first_node, last_node
      l = last_node - i + 1      ! local nodes in reverse chain order
      piece%node_owned(l) = i >= first_owned
      piece%global_node(l) = node_position(i)
      if (piece%node_owned(l)) then
        piece%x(:, l) = coordinate(i)
        piece%node_id(l) = 1000 + 3*i
      else
        piece%x(:, l) = GARBAGE
        piece%node_id(l) = -1
      end if
    end do
    allocate(piece%topology(piece%ncell), piece%cell_start(piece%ncell + 1), &
             piece%cell_id(piece%ncell), piece%cell_part(piece%ncell), &
             piece%global_cell(piece%ncell), piece%conn(0))
    piece%cell_start(1) = 1
    do c = 1, piece%ncell          ! local cells in reverse chain order
      k = last - c + 1
      nodes = cell_nodes(k)
      piece%topology(c) = cell_topology(k)
      piece%cell_id(c) = 500 + 7*k
      piece%cell_part(c) = 1 + mod(k, 3)
      piece%global_cell(c) = cell_position(k)
      piece%conn = [piece%conn, last_node - nodes + 1]
      piece%cell_start(c + 1) = size(piece%conn) + 1
    end do
  end subroutine make_piece

  !> Fields of a state on the piece; rows of nodes this rank does not own hold garbage.
  subroutine make_fields(piece, state, point, cell)
    type(output_mesh_t), intent(in) :: piece          !< this rank's piece
    integer, intent(in) :: state                      !< state number
    type(output_field_t), intent(out) :: point(2)     !< displacement, temperature
    type(output_field_t), intent(out) :: cell(2)      !< stress, plastic_strain
    integer :: first, last, last_node, l, c, f
    call cell_range(comm_rank(), first, last)
    last_node = chain_node(last + 1, 4)
    do f = 1, 2
      point(f)%name = POINT_NAMES(f)
      point(f)%ncomp = size(point_value(f, 1, 0))
      cell(f)%name = CELL_NAMES(f)
      cell(f)%ncomp = size(cell_value(f, 1, 0))
      allocate(point(f)%values(point(f)%ncomp, piece%nnode))
      do l = 1, piece%nnode
        if (piece%node_owned(l)) then
          point(f)%values(:, l) = point_value(f, last_node - l + 1, state)
        else
          point(f)%values(:, l) = GARBAGE
        end if
      end do
      allocate(cell(f)%values(cell(f)%ncomp, piece%ncell))
      do c = 1, piece%ncell
        cell(f)%values(:, c) = cell_value(f, last - c + 1, state)
      end do
    end do
  end subroutine make_fields

  !> Write the expected file content, built from the chain directly (rank 0 only).
  !> Format: `dataset <path> <dtype> <h5py shape>` followed by the values row by row;
  !> `attribute <object> <name> <dtype> <value>`.
  subroutine write_truth(path)
    character(len=*), intent(in) :: path   !< truth file
    real(wp), allocatable :: x(:,:), point(:,:), cell(:,:)
    integer :: ids(NNODE), cell_ids(NCELL), parts(NCELL), types(NCELL), counts(NCELL)
    integer :: offsets(0:NCELL), i, k, g, state, f, ncomp, truth
    integer, allocatable :: connectivity(:), nodes(:)
    character(len=64) :: group
    allocate(x(3, NNODE), point(6, NNODE), cell(6, NCELL))
    do i = 1, NNODE
      x(:, node_position(i)) = coordinate(i)
      ids(node_position(i)) = 1000 + 3*i
    end do
    do k = 1, NCELL
      g = cell_position(k)
      cell_ids(g) = 500 + 7*k
      parts(g) = 1 + mod(k, 3)
      types(g) = vtk_cell_type(cell_topology(k))
      counts(g) = size(cell_nodes(k))
    end do
    offsets(0) = 0
    do g = 1, NCELL
      offsets(g) = offsets(g - 1) + counts(g)
    end do
    allocate(connectivity(offsets(NCELL)))
    do k = 1, NCELL
      g = cell_position(k)
      nodes = cell_nodes(k)
      do i = 1, size(nodes)
        connectivity(offsets(g - 1) + i) = node_position(nodes(i)) - 1
      end do
    end do

    open(newunit=truth, file=path, status='replace', action='write')
    write(truth, '(a,i0)') 'attribute / format_version int32 ', 1
    write(truth, '(a,i0)') 'attribute /mesh nnode int32 ', NNODE
    write(truth, '(a,i0)') 'attribute /mesh ncell int32 ', NCELL
    call put_real(truth, '/mesh/coordinates', x, .false.)
    call put_int(truth, '/mesh/node_ids', 'int32', ids)
    call put_int(truth, '/mesh/cell_ids', 'int32', cell_ids)
    call put_int(truth, '/mesh/cell_part', 'int32', parts)
    call put_int(truth, '/mesh/cell_types', 'int32', types)
    call put_int(truth, '/mesh/cell_offsets', 'int64', offsets)
    call put_int(truth, '/mesh/connectivity', 'int64', connectivity)
    do state = 1, NSTATE
      write(group, '(a,i0.6)') '/states/', STEPS(state)
      write(truth, '(a,es25.17)') 'attribute '//trim(group)//' time float64 ', TIMES(state)
      write(truth, '(a,i0)') 'attribute '//trim(group)//' step int32 ', STEPS(state)
      do f = 1, 2
        ncomp = size(point_value(f, 1, 0))
        do i = 1, NNODE
          point(1:ncomp, node_position(i)) = point_value(f, i, state)
        end do
        call put_real(truth, trim(group)//'/point/'//trim(POINT_NAMES(f)), point(1:ncomp, :), &
                      .false.)
        ncomp = size(cell_value(f, 1, 0))
        do k = 1, NCELL
          cell(1:ncomp, cell_position(k)) = cell_value(f, k, state)
        end do
        call put_real(truth, trim(group)//'/cell/'//trim(CELL_NAMES(f)), cell(1:ncomp, :), &
                      .false.)
      end do
    end do
    call put_real(truth, '/time_history/time', reshape(TIMES, [1, NSTATE]), .true.)
    call put_int(truth, '/time_history/step', 'int32', STEPS)
    close(truth)
  end subroutine write_truth

  !> Truth entry of a real dataset: h5py shape (n, ncomp), or (n) if one_dimensional.
  subroutine put_real(truth, name, values, one_dimensional)
    integer, intent(in) :: truth                  !< truth file unit
    character(len=*), intent(in) :: name          !< dataset path
    real(wp), intent(in) :: values(:,:)           !< (ncomp, n)
    logical, intent(in) :: one_dimensional        !< h5py shape (n) instead of (n, ncomp)
    integer :: row
    if (one_dimensional) then
      write(truth, '(a,1x,i0)') 'dataset '//name//' float64', size(values, 2)
    else
      write(truth, '(a,2(1x,i0))') 'dataset '//name//' float64', size(values, 2), &
          size(values, 1)
    end if
    do row = 1, size(values, 2)
      write(truth, '(*(es25.17))') values(:, row)
    end do
  end subroutine put_real

  !> Truth entry of an integer dataset of shape (n).
  subroutine put_int(truth, name, dtype, values)
    integer, intent(in) :: truth            !< truth file unit
    character(len=*), intent(in) :: name    !< dataset path
    character(len=*), intent(in) :: dtype   !< int32 or int64
    integer, intent(in) :: values(:)        !< values
    integer :: row
    write(truth, '(a,1x,i0)') 'dataset '//name//' '//dtype, size(values)
    do row = 1, size(values)
      write(truth, '(i0)') values(row)
    end do
  end subroutine put_int

end program test_hdf5_output
