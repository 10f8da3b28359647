!> Restart files (d3dump01, d3dump02, ..., runrsf): a binary stream of named records, written
!> by rank 0 and read by every rank. A record is its name (32 characters), its kind (real,
!> integer or text), its length (64-bit) and its values; the reader names the record it wants
!> and gets a clear message when the file holds another one or another length (a file of
!> another deck, or of another mefem version). The records hold global, rank-independent data
!> (nodal values in global node order, cell values in global cell order), so a file restarts
!> on any number of ranks.
!>
!> Writing goes to <path>.part, renamed over <path> only when complete, so that a run killed
!> while writing keeps its previous file.
module mefem_restart_file
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_is_root
  use mefem_errors, only: fatal, warn
  use mefem_strings, only: itoa
  use mefem_file_system, only: rename_file
  implicit none
  private

  public :: restart_create, restart_commit, restart_open, restart_close
  public :: restart_put_reals, restart_put_ints, restart_put_logicals, restart_put_text
  public :: restart_get_reals, restart_get_ints, restart_get_logicals, restart_get_text
  public :: restart_get_reals_alloc, restart_get_ints_alloc, restart_checksum, restart_dump_name

  character(len=16), parameter :: MAGIC = 'MEFEM RESTART   '  !< the file's first bytes
  integer, parameter :: FORMAT_VERSION = 1                    !< bumped when records change
  integer, parameter :: NAME_LENGTH = 32                      !< characters of a record name
  integer, parameter :: KIND_REAL = 1, KIND_INT = 2, KIND_TEXT = 3  !< record kinds

  !> An open restart file: on rank 0 for writing, on every rank for reading.
  type, public :: restart_file_t
    integer :: unit = 0                         !< its unit (when open here)
    logical :: open_here = .false.              !< open on this rank
    logical :: writing = .false.                !< opened by restart_create
    logical :: failed = .false.                 !< a write failed (warned once)
    character(len=:), allocatable :: path       !< the file's path
  end type restart_file_t


contains

  !> Start writing a restart file (rank 0; on the other ranks the file stays closed and
  !> the put routines do nothing).
  subroutine restart_create(f, path)
    type(restart_file_t), intent(out) :: f            !< the file
    character(len=*), intent(in) :: path              !< where it goes
    integer :: ios
    f%path = path
    f%writing = .true.
    if (.not. comm_is_root()) return
    open(newunit=f%unit, file=path//'.part', access='stream', form='unformatted', &
         status='replace', action='write', iostat=ios)
    f%open_here = ios == 0
    if (ios /= 0) then
      call write_failed(f)
      return
    end if
    write(f%unit, iostat=ios) MAGIC, FORMAT_VERSION
    if (ios /= 0) call write_failed(f)
  end subroutine restart_create

  !> Close a file being written and put it in place (rename over an older one). ok: the file
  !> is complete (rank 0's answer; .true. on the other ranks).
  subroutine restart_commit(f, ok)
    type(restart_file_t), intent(inout) :: f          !< the file
    logical, intent(out) :: ok                        !< written and in place
    integer :: ios
    ok = .true.
    if (.not. f%open_here) then
      ok = .not. f%failed
      return
    end if
    close(f%unit, iostat=ios)
    f%open_here = .false.
    if (ios /= 0) call write_failed(f)
    if (.not. f%failed) then
      call rename_file(f%path//'.part', f%path, ok)
      if (.not. ok) then
        call warn('restart: cannot rename '//f%path//'.part to '//f%path)
        f%failed = .true.
      end if
    end if
    ok = .not. f%failed
  end subroutine restart_commit

  !> Open a restart file for reading (every rank); stops with a message if it cannot be read
  !> or is not a mefem restart file of this version.
  subroutine restart_open(f, path)
    type(restart_file_t), intent(out) :: f            !< the file
    character(len=*), intent(in) :: path              !< its path
    character(len=16) :: magic_read
    integer :: ios, version
    logical :: found
    f%path = path
    f%writing = .false.
    inquire(file=path, exist=found)
    if (.not. found) call fatal('restart file "'//path//'" does not exist')
    open(newunit=f%unit, file=path, access='stream', form='unformatted', status='old', &
         action='read', iostat=ios)
    if (ios /= 0) call fatal('cannot open the restart file "'//path//'"')
    f%open_here = .true.
    read(f%unit, iostat=ios) magic_read, version
    if (ios /= 0 .or. magic_read /= MAGIC) &
      call fatal('"'//path//'" is not a mefem restart file (d3dump, runrsf)')
    if (version /= FORMAT_VERSION) call fatal('restart file "'//path//'" has format '// &
        itoa(version)//'; this mefem reads format '//itoa(FORMAT_VERSION))
  end subroutine restart_open

  !> Close a file opened for reading.
  subroutine restart_close(f)
    type(restart_file_t), intent(inout) :: f          !< the file
    integer :: ios
    if (f%open_here) close(f%unit, iostat=ios)
    f%open_here = .false.
  end subroutine restart_close

  ! ------------------------------------------------------------------ writing

  !> Write n reals as record `name`.
  subroutine restart_put_reals(f, name, n, values)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: n                          !< number of values
    real(wp), intent(in) :: values(n)                 !< the values
    integer :: ios
    if (.not. put_header(f, name, KIND_REAL, int(n, i8))) return
    write(f%unit, iostat=ios) values
    if (ios /= 0) call write_failed(f)
  end subroutine restart_put_reals

  !> Write n integers as record `name`.
  subroutine restart_put_ints(f, name, n, values)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: n                          !< number of values
    integer, intent(in) :: values(n)                  !< the values
    integer :: ios
    if (.not. put_header(f, name, KIND_INT, int(n, i8))) return
    write(f%unit, iostat=ios) values
    if (ios /= 0) call write_failed(f)
  end subroutine restart_put_ints

  !> Write n logicals (as integers 0 / 1) as record `name`.
  subroutine restart_put_logicals(f, name, n, values)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: n                          !< number of values
    logical, intent(in) :: values(n)                  !< the values
    call restart_put_ints(f, name, n, merge(1, 0, values))
  end subroutine restart_put_logicals

  !> Write a text as record `name`.
  subroutine restart_put_text(f, name, text)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    character(len=*), intent(in) :: text              !< the text
    integer :: ios
    if (.not. put_header(f, name, KIND_TEXT, int(len(text), i8))) return
    write(f%unit, iostat=ios) text
    if (ios /= 0) call write_failed(f)
  end subroutine restart_put_text

  !> Write a record's header; .false. where nothing is to be written (not rank 0, failed).
  logical function put_header(f, name, kind, n)
    type(restart_file_t), intent(inout) :: f          !< file being written
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: kind                       !< KIND_*
    integer(i8), intent(in) :: n                      !< number of values
    character(len=NAME_LENGTH) :: padded
    integer :: ios
    put_header = .false.
    if (.not. f%open_here .or. f%failed) return
    padded = name
    write(f%unit, iostat=ios) padded, kind, n
    if (ios /= 0) then
      call write_failed(f)
      return
    end if
    put_header = .true.
  end function put_header

  !> A write failed: warn once, drop the partial file.
  subroutine write_failed(f)
    type(restart_file_t), intent(inout) :: f          !< the file
    integer :: ios
    if (f%failed) return
    f%failed = .true.
    call warn('restart: cannot write '//f%path//' (disk full or not writable?); the run '// &
              'goes on without this restart file')
    if (f%open_here) close(f%unit, status='delete', iostat=ios)
    f%open_here = .false.
  end subroutine write_failed

  ! ------------------------------------------------------------------ reading

  !> Read record `name` of n reals.
  subroutine restart_get_reals(f, name, n, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: n                          !< number of values the model needs
    real(wp), intent(out) :: values(n)                !< the values
    integer :: ios
    call get_header(f, name, KIND_REAL, int(n, i8))
    read(f%unit, iostat=ios) values
    if (ios /= 0) call read_failed(f, name)
  end subroutine restart_get_reals

  !> Read record `name` of n integers.
  subroutine restart_get_ints(f, name, n, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: n                          !< number of values the model needs
    integer, intent(out) :: values(n)                 !< the values
    integer :: ios
    call get_header(f, name, KIND_INT, int(n, i8))
    read(f%unit, iostat=ios) values
    if (ios /= 0) call read_failed(f, name)
  end subroutine restart_get_ints

  !> Read record `name` of n logicals.
  subroutine restart_get_logicals(f, name, n, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    integer, intent(in) :: n                          !< number of values the model needs
    logical, intent(out) :: values(n)                 !< the values
    integer :: numbers(n)
    call restart_get_ints(f, name, n, numbers)
    values = numbers /= 0
  end subroutine restart_get_logicals

  !> Read record `name`, a text of any length.
  subroutine restart_get_text(f, name, text)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    character(len=:), allocatable, intent(out) :: text  !< the text
    integer(i8) :: n
    integer :: ios
    call get_header(f, name, KIND_TEXT, -1_i8, n)
    allocate(character(len=n) :: text)
    read(f%unit, iostat=ios) text
    if (ios /= 0) call read_failed(f, name)
  end subroutine restart_get_text

  !> Read record `name` of reals, whatever its length.
  subroutine restart_get_reals_alloc(f, name, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    real(wp), allocatable, intent(out) :: values(:)   !< the values
    integer(i8) :: n
    integer :: ios
    call get_header(f, name, KIND_REAL, -1_i8, n)
    allocate(values(n))
    read(f%unit, iostat=ios) values
    if (ios /= 0) call read_failed(f, name)
  end subroutine restart_get_reals_alloc

  !> Read record `name` of integers, whatever its length.
  subroutine restart_get_ints_alloc(f, name, values)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< record name
    integer, allocatable, intent(out) :: values(:)    !< the values
    integer(i8) :: n
    integer :: ios
    call get_header(f, name, KIND_INT, -1_i8, n)
    allocate(values(n))
    read(f%unit, iostat=ios) values
    if (ios /= 0) call read_failed(f, name)
  end subroutine restart_get_ints_alloc

  !> Read and check a record's header: its name, kind and (n >= 0) length.
  subroutine get_header(f, name, kind, n, n_found)
    type(restart_file_t), intent(inout) :: f          !< file being read
    character(len=*), intent(in) :: name              !< the record wanted
    integer, intent(in) :: kind                       !< its kind
    integer(i8), intent(in) :: n                      !< its length (-1: any)
    integer(i8), intent(out), optional :: n_found     !< the length found
    character(len=NAME_LENGTH) :: name_read
    integer :: kind_read, ios
    integer(i8) :: n_read
    read(f%unit, iostat=ios) name_read, kind_read, n_read
    if (ios /= 0) call read_failed(f, name)
    if (name_read /= name) call fatal('restart file "'//f%path//'": record "'//trim(name_read)// &
        '" where "'//name//'" was expected: the file was written for another model or by '// &
        'another mefem version')
    if (kind_read /= kind .or. (n >= 0 .and. n_read /= n)) call fatal('restart file "'// &
        f%path//'": record "'//name//'" has '//itoa(int(n_read))//' values, the model '// &
        'needs '//itoa(int(n))//': the deck is not the one the file was written with')
    if (present(n_found)) n_found = n_read
  end subroutine get_header

  !> A read failed (a truncated file).
  subroutine read_failed(f, name)
    type(restart_file_t), intent(in) :: f             !< the file
    character(len=*), intent(in) :: name              !< the record being read
    call fatal('restart file "'//f%path//'" ends or cannot be read at record "'//name// &
               '" (a truncated file?)')
  end subroutine read_failed

  !> LS-DYNA's name of the k-th restart file of a run: d3dump01, d3dump02, ..., d3dump100.
  pure function restart_dump_name(k) result(name)
    integer, intent(in) :: k                          !< its number
    character(len=:), allocatable :: name
    character(len=12) :: number
    write(number, '(i2.2)') k
    if (k > 99) write(number, '(i0)') k
    name = 'd3dump'//trim(number)
  end function restart_dump_name

  !> A sum of the reference coordinates (every rank alike), kept in a restart file so that a
  !> file of another mesh with the same sizes is told apart.
  pure real(wp) function restart_checksum(x)
    real(wp), intent(in) :: x(:,:)                    !< (3, nodes) coordinates
    integer :: n
    restart_checksum = 0.0_wp
    do n = 1, size(x, 2)
      restart_checksum = restart_checksum + real(mod(n, 7) + 1, wp)*sum(abs(x(:, n)))
    end do
  end function restart_checksum

end module mefem_restart_file
