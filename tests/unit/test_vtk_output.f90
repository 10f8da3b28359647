!> Unit test of the VTK XML writer: every rank writes a small mixed piece for two steps.
! ranks: 1 3
!>
!> Output goes to $MEFEM_ROOT/tests/out/vtk_unit/np<ranks>/ (MEFEM_ROOT defaults to ../.., the
!> project root seen from tests/unit where the runner starts unit tests). Besides the VTK files,
!> every rank writes truth_rank<r>.txt with the numbers it handed to the writer, in VTK terms;
!> tests/output/test_vtk_roundtrip.py reads the .pvd with VTK and compares with these files.
!> Called with the argument --bad-dir, the program instead writes into a missing directory and
!> must stop with an error message (that test is also driven by test_vtk_roundtrip.py).
program test_vtk_output
  use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, project_root
  use mefem_comm, only: comm_rank, comm_size, comm_is_root, comm_barrier, comm_any, comm_bcast
  use mefem_errors, only: say, terminate
  use mefem_output_mesh, only: output_mesh_t, output_field_t, TOPO_TRI3, TOPO_QUAD4, &
                               TOPO_TET4, TOPO_PENTA6, TOPO_HEX8
  use mefem_vtk_output, only: vtk_write_state, vtk_reset_collection
  implicit none

  interface
    !> C library mkdir(); the test creates its output directory (the writer never does).
    function c_mkdir(path, mode) bind(C, name='mkdir') result(status)
      import :: c_char, c_int
      character(kind=c_char), intent(in) :: path(*)   !< NUL-terminated directory name
      integer(c_int), value :: mode                    !< permission bits
      integer(c_int) :: status
    end function c_mkdir
  end interface

  integer, parameter :: NNODE = 16, NCELL = 7, NSTEP = 2
  integer, parameter :: STEPS(NSTEP) = [0, 10]                 !< output step numbers
  real(wp), parameter :: TIMES(NSTEP) = [0.0_wp, 2.5e-4_wp]    !< their times
  !> VTK codes expected for the cells below (written out, not taken from the writer's module)
  integer, parameter :: EXPECTED_VTK_TYPE(NCELL) = [10, 12, 5, 13, 9, 10, 5]

  type(output_mesh_t) :: mesh
  type(output_field_t), allocatable :: point_fields(:, :), cell_fields(:, :)
  type(output_field_t) :: no_fields(0)
  character(len=:), allocatable :: root, out_dir, stem_suffix
  character(len=512) :: argument
  integer :: rank, nranks, istep
  logical :: ok

  call test_start('vtk_output')
  rank = comm_rank()
  nranks = comm_size()
  root = project_root()
  out_dir = root//'/tests/out/vtk_unit/np'//itoa(nranks)

  call build_piece(rank, nranks, mesh)
  allocate(point_fields(2, NSTEP), cell_fields(2, NSTEP))
  do istep = 1, NSTEP
    call build_fields(rank, istep, point_fields(:, istep), cell_fields(:, istep))
  end do

  call get_command_argument(1, argument)
  if (argument == '--bad-dir') then
    ! must stop inside the writer with "cannot open <path> for writing"
    call vtk_write_state(root//'/tests/out/vtk_unit/missing_directory', 'mesh', 1, 0.0_wp, &
                         mesh, point_fields(:, 1), cell_fields(:, 1))
    call say('vtk_write_state returned after writing into a missing directory')
    call terminate(0)
  end if

  ! fresh output directory; remove what a previous run left that the checks rely on
  if (comm_is_root()) then
    call make_directory(root//'/tests/out')
    call make_directory(root//'/tests/out/vtk_unit')
    call make_directory(out_dir)
    call delete_file(out_dir//'/mesh.pvd')
    call delete_file(out_dir//'/second.pvd')
  end if
  call comm_barrier()
  call delete_file(out_dir//'/truth_rank'//itoa(rank)//'.txt')
  call vtk_reset_collection()

  ! two states of "mesh"; a state of another collection in between; the last state twice
  call vtk_write_state(out_dir, 'mesh', STEPS(1), TIMES(1), mesh, point_fields(:, 1), &
                       cell_fields(:, 1))
  call vtk_write_state(out_dir, 'second', 3, 1.0_wp, mesh, no_fields, cell_fields(1:1, 1))
  call vtk_write_state(out_dir, 'mesh', STEPS(2), -1.0_wp, mesh, point_fields(:, 2), &
                       cell_fields(:, 2))
  call vtk_write_state(out_dir, 'mesh', STEPS(2), TIMES(2), mesh, point_fields(:, 2), &
                       cell_fields(:, 2))

  ! files of both steps exist, in binary, with the naming of 1 rank or of several ranks
  if (nranks > 1) then
    stem_suffix = '_'//padded(rank, 4)//'.vtu'
  else
    stem_suffix = '.vtu'
  end if
  do istep = 1, NSTEP
    ok = file_size(out_dir//'/mesh_'//padded(STEPS(istep), 6)//stem_suffix) > &
         appended_bytes(mesh, point_fields(:, istep), cell_fields(:, istep))
    call check(.not. comm_any(.not. ok), 'piece of every rank written at step '// &
               itoa(STEPS(istep)), 'a piece is missing or shorter than its binary data')
    ok = file_size(out_dir//'/mesh_'//padded(STEPS(istep), 6)//'.pvtu') > 0
    call check(ok .eqv. (nranks > 1), '.pvtu written exactly when there are several ranks')
    if (nranks > 1) then
      ok = file_size(out_dir//'/mesh_'//padded(STEPS(istep), 6)//'.vtu') < 0
      call check(ok, 'no single .vtu when there are several ranks')
    end if
  end do

  ! the collections: states listed once each, in order, separately per basename
  if (nranks > 1) then
    stem_suffix = '.pvtu'
  else
    stem_suffix = '.vtu'
  end if
  call check_collection(out_dir//'/mesh.pvd', ['mesh_000000'//stem_suffix, &
                        'mesh_000010'//stem_suffix], 'mesh.pvd lists steps 0 and 10 once each')
  call check_collection(out_dir//'/second.pvd', ['second_000003'//stem_suffix], &
                        'second.pvd is a separate collection')
  ok = file_size(out_dir//'/mesh.pvd.tmp') < 0
  call check(ok, 'no temporary .pvd left behind')
  call vtk_reset_collection()
  call vtk_write_state(out_dir, 'second', 4, 2.0_wp, mesh, no_fields, no_fields)
  call check_collection(out_dir//'/second.pvd', ['second_000004'//stem_suffix], &
                        'vtk_reset_collection starts a new collection')

  call write_truth(out_dir//'/truth_rank'//itoa(rank)//'.txt', rank, nranks, mesh, &
                   point_fields, cell_fields, stem_suffix)
  call test_finish()

contains

  !> This rank's piece: a tet, a hex, a triangle, a wedge, a quad, a tet, a triangle (16 nodes).
  subroutine build_piece(rank, nranks, mesh)
    integer, intent(in) :: rank                 !< this rank
    integer, intent(in) :: nranks               !< number of ranks
    type(output_mesh_t), intent(out) :: mesh    !< the piece
    real(wp), parameter :: corners(3, NNODE) = reshape([ &
      0, 0, 0,  1, 0, 0,  1, 1, 0,  0, 1, 0,  0, 0, 1,  1, 0, 1,  1, 1, 1,  0, 1, 1, &
      0, 0, 2,  1, 0, 2,  0, 1, 2,  2, 0, 0,  2, 1, 0,  0, -1, 0,  1, -1, 0,  0, -2, 0] &
      * 1.0_wp, [3, NNODE])
    integer, parameter :: topology(NCELL) = [TOPO_TET4, TOPO_HEX8, TOPO_TRI3, TOPO_PENTA6, &
                                             TOPO_QUAD4, TOPO_TET4, TOPO_TRI3]
    integer, parameter :: conn(32) = [2, 12, 3, 6,  1, 2, 3, 4, 5, 6, 7, 8,  1, 2, 15, &
                                      5, 8, 6, 9, 11, 10,  2, 12, 13, 3,  12, 13, 3, 6, &
                                      14, 15, 16]
    integer :: i, c
    mesh%nnode = NNODE
    mesh%ncell = NCELL
    mesh%nnode_global = NNODE * nranks
    mesh%ncell_global = NCELL * nranks
    allocate(mesh%x(3, NNODE), mesh%node_id(NNODE), mesh%global_node(NNODE), &
             mesh%node_owned(NNODE))
    do i = 1, NNODE
      ! coordinates depend on the rank and are not exact in decimal
      mesh%x(1, i) = (corners(1, i) + 3.0_wp * rank) / 3.0_wp
      mesh%x(2, i) = corners(2, i) / 7.0_wp
      mesh%x(3, i) = 1.1_wp * corners(3, i) + 0.01_wp * rank
      mesh%node_id(i) = 1000 * (rank + 1) + 10 * i + 7
      mesh%global_node(i) = NNODE * rank + i
    end do
    mesh%node_owned = .true.
    allocate(mesh%topology(NCELL), mesh%cell_start(NCELL + 1), mesh%conn(size(conn)), &
             mesh%cell_id(NCELL), mesh%cell_part(NCELL), mesh%global_cell(NCELL))
    mesh%topology = topology
    mesh%conn = conn
    mesh%cell_start(1) = 1
    do c = 1, NCELL
      mesh%cell_start(c + 1) = mesh%cell_start(c) + nodes_of(topology(c))
      mesh%cell_id(c) = 100000 + 1000 * rank + 3 * c
      mesh%global_cell(c) = NCELL * rank + c
      if (topology(c) == TOPO_TRI3 .or. topology(c) == TOPO_QUAD4) then
        mesh%cell_part(c) = 2 + 10 * rank
      else
        mesh%cell_part(c) = 1 + 10 * rank
      end if
    end do
  end subroutine build_piece

  !> Corner nodes of a topology, written out independently of the module's table.
  integer function nodes_of(topology)
    integer, intent(in) :: topology   !< TOPO_* code
    select case (topology)
    case (TOPO_TRI3)
      nodes_of = 3
    case (TOPO_QUAD4, TOPO_TET4)
      nodes_of = 4
    case (TOPO_PENTA6)
      nodes_of = 6
    case default
      nodes_of = 8
    end select
  end function nodes_of

  !> Fields of one state: displacement (3) and temperature (1) on nodes, stress (6) and
  !> plastic strain (1) on cells; values depend on rank, entity, component and state.
  subroutine build_fields(rank, istep, point_fields, cell_fields)
    integer, intent(in) :: rank                             !< this rank
    integer, intent(in) :: istep                            !< state index 1..NSTEP
    type(output_field_t), intent(out) :: point_fields(2)    !< displacement, temperature
    type(output_field_t), intent(out) :: cell_fields(2)     !< stress, plastic_strain
    integer :: i, j
    point_fields(1)%name = 'displacement'
    point_fields(1)%ncomp = 3
    point_fields(2)%name = 'temperature'
    point_fields(2)%ncomp = 1
    cell_fields(1)%name = 'stress'
    cell_fields(1)%ncomp = 6
    cell_fields(2)%name = 'plastic_strain'
    cell_fields(2)%ncomp = 1
    allocate(point_fields(1)%values(3, NNODE), point_fields(2)%values(1, NNODE))
    allocate(cell_fields(1)%values(6, NCELL), cell_fields(2)%values(1, NCELL))
    do i = 1, NNODE
      do j = 1, 3
        point_fields(1)%values(j, i) = 1.0e-3_wp * istep * sin(1.3_wp * i + 0.7_wp * j + rank)
      end do
      point_fields(2)%values(1, i) = 293.15_wp + i + istep / 7.0_wp
    end do
    do i = 1, NCELL
      do j = 1, 6
        cell_fields(1)%values(j, i) = 2.0e8_wp * cos(0.9_wp * i + 0.4_wp * j + rank + &
                                                     0.1_wp * istep)
      end do
      cell_fields(2)%values(1, i) = 0.01_wp * i * (istep - 1) / 3.0_wp
    end do
  end subroutine build_fields

  !> Bytes of the appended binary data of a piece (each block: 8-byte count + values).
  integer function appended_bytes(mesh, point_fields, cell_fields)
    type(output_mesh_t), intent(in) :: mesh                 !< the piece
    type(output_field_t), intent(in) :: point_fields(:)     !< fields on nodes
    type(output_field_t), intent(in) :: cell_fields(:)      !< fields on cells
    integer :: k
    ! node_id, element_id, part_id (Int32), points (3 Float64), conn and offsets (Int64), types
    appended_bytes = 8 + 4 * mesh%nnode + 2 * (8 + 4 * mesh%ncell) + 8 + 24 * mesh%nnode + &
                     8 + 8 * size(mesh%conn) + 8 + 8 * mesh%ncell + 8 + mesh%ncell
    do k = 1, size(point_fields)
      appended_bytes = appended_bytes + 8 + 8 * point_fields(k)%ncomp * mesh%nnode
    end do
    do k = 1, size(cell_fields)
      appended_bytes = appended_bytes + 8 + 8 * cell_fields(k)%ncomp * mesh%ncell
    end do
  end function appended_bytes

  !> Check (on rank 0, result shared) that a .pvd lists exactly these files, in this order.
  subroutine check_collection(path, files, name)
    character(len=*), intent(in) :: path        !< the .pvd file
    character(len=*), intent(in) :: files(:)    !< expected file attributes
    character(len=*), intent(in) :: name        !< what is checked
    character(len=512) :: line
    character(len=:), allocatable :: detail
    integer :: unit, ios, n
    logical :: ok
    ok = .true.
    detail = ''
    if (comm_is_root()) then
      n = 0
      open(newunit=unit, file=path, status='old', action='read', iostat=ios)
      if (ios /= 0) then
        ok = .false.
        detail = 'cannot open '//path
      else
        do
          read(unit, '(a)', iostat=ios) line
          if (ios /= 0) exit
          if (index(line, '<DataSet') == 0) cycle
          n = n + 1
          if (n > size(files)) then
            ok = .false.
          else if (index(line, 'file="'//files(n)//'"') == 0) then
            ok = .false.
            detail = 'entry '//itoa(n)//': '//trim(adjustl(line))
          end if
        end do
        close(unit)
        if (n /= size(files)) then
          ok = .false.
          detail = itoa(n)//' entries, want '//itoa(size(files))
        end if
      end if
    end if
    call comm_bcast(ok)
    call check(ok, name, detail)
  end subroutine check_collection

  !> Write what this rank handed to the writer, in VTK terms, for the Python round-trip test.
  !> Format: "array <name> <i|r> <ncomp> <n>" then n lines of ncomp values; "state" lines.
  subroutine write_truth(path, rank, nranks, mesh, point_fields, cell_fields, suffix)
    character(len=*), intent(in) :: path                    !< file to write
    integer, intent(in) :: rank, nranks                     !< this rank, number of ranks
    type(output_mesh_t), intent(in) :: mesh                 !< the piece
    type(output_field_t), intent(in) :: point_fields(:, :)  !< (field, state)
    type(output_field_t), intent(in) :: cell_fields(:, :)   !< (field, state)
    character(len=*), intent(in) :: suffix                  !< .vtu or .pvtu
    integer :: unit, c, k, istep
    integer :: offsets(NCELL)
    open(newunit=unit, file=path, status='replace', action='write')
    write(unit, '(a, 1x, i0)') 'nranks', nranks
    write(unit, '(a, 1x, i0)') 'rank', rank
    call write_real(unit, 'points', mesh%x)
    call write_int(unit, 'node_id', mesh%node_id)
    call write_int(unit, 'element_id', mesh%cell_id)
    call write_int(unit, 'part_id', mesh%cell_part)
    call write_int(unit, 'types', EXPECTED_VTK_TYPE)
    call write_int(unit, 'connectivity', mesh%conn - 1)
    offsets(1) = nodes_of(mesh%topology(1))
    do c = 2, NCELL
      offsets(c) = offsets(c - 1) + nodes_of(mesh%topology(c))
    end do
    call write_int(unit, 'offsets', offsets)
    do istep = 1, NSTEP
      write(unit, '(a, 1x, i0, 1x, es25.17e3, 1x, a)') 'state', STEPS(istep), TIMES(istep), &
        'mesh_'//padded(STEPS(istep), 6)//suffix
      do k = 1, size(point_fields, 1)
        call write_real(unit, 'point:'//trim(point_fields(k, istep)%name)//':'// &
                        itoa(STEPS(istep)), point_fields(k, istep)%values)
      end do
      do k = 1, size(cell_fields, 1)
        call write_real(unit, 'cell:'//trim(cell_fields(k, istep)%name)//':'// &
                        itoa(STEPS(istep)), cell_fields(k, istep)%values)
      end do
    end do
    close(unit)
  end subroutine write_truth

  !> Truth file: one real array (ncomp, n) in full precision.
  subroutine write_real(unit, name, values)
    integer, intent(in) :: unit                   !< open truth file
    character(len=*), intent(in) :: name          !< array name
    real(wp), intent(in) :: values(:, :)          !< (ncomp, n)
    integer :: i
    write(unit, '(a, 1x, a, 1x, i0, 1x, i0)') 'array '//name, 'r', size(values, 1), &
      size(values, 2)
    do i = 1, size(values, 2)
      write(unit, '(*(1x, es25.17e3))') values(:, i)
    end do
  end subroutine write_real

  !> Truth file: one integer array, one value per line.
  subroutine write_int(unit, name, values)
    integer, intent(in) :: unit                   !< open truth file
    character(len=*), intent(in) :: name          !< array name
    integer, intent(in) :: values(:)              !< values
    integer :: i
    write(unit, '(a, 1x, a, 1x, i0, 1x, i0)') 'array '//name, 'i', 1, size(values)
    do i = 1, size(values)
      write(unit, '(i0)') values(i)
    end do
  end subroutine write_int

  !> Size of a file in bytes, -1 when it does not exist.
  integer function file_size(path)
    character(len=*), intent(in) :: path   !< the file
    logical :: exists
    inquire(file=path, exist=exists, size=file_size)
    if (.not. exists) file_size = -1
  end function file_size

  !> Create a directory unless it exists.
  subroutine make_directory(path)
    character(len=*), intent(in) :: path   !< the directory
    integer(c_int) :: status
    status = c_mkdir(path//c_null_char, int(o'755', c_int))
  end subroutine make_directory

  !> Delete a file if it exists.
  subroutine delete_file(path)
    character(len=*), intent(in) :: path   !< the file
    integer :: unit, ios
    open(newunit=unit, file=path, status='old', iostat=ios)
    if (ios == 0) close(unit, status='delete')
  end subroutine delete_file

  !> Decimal text of an integer.
  function itoa(value) result(text)
    integer, intent(in) :: value           !< the number
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0)') value
    text = trim(buffer)
  end function itoa

  !> Integer with leading zeros to `width` digits.
  function padded(value, width) result(text)
    integer, intent(in) :: value           !< the number
    integer, intent(in) :: width           !< digits
    character(len=:), allocatable :: text
    character(len=24) :: buffer
    write(buffer, '(i0.'//itoa(width)//')') value
    text = trim(buffer)
  end function padded

end program test_vtk_output
