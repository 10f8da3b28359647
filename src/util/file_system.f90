!> File-system helpers: create a directory (with its parents), as `mkdir -p` does, and say what
!> is in the way when it cannot be made or written.
module mefem_file_system
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_ptr, c_associated, &
                                         c_long
  use mefem_kinds, only: i8
  implicit none
  private

  public :: make_directory, canonical_path, remove_file, truncate_file, rename_file

  integer, parameter :: PATH_BUFFER = 4096                 !< PATH_MAX of Linux

  integer(c_int), parameter :: MODE_RWX = int(o'755', c_int)  !< rwxr-xr-x for new directories

  interface
    !> POSIX mkdir(2).
    integer(c_int) function c_mkdir(path, mode) bind(C, name='mkdir')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
    end function c_mkdir
    !> C remove(3).
    integer(c_int) function c_remove(path) bind(C, name='remove')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
    end function c_remove
    !> POSIX truncate(2) (off_t is a long on the 64-bit Linux targets).
    integer(c_int) function c_truncate(path, length) bind(C, name='truncate')
      import :: c_int, c_char, c_long
      character(kind=c_char), intent(in) :: path(*)
      integer(c_long), value :: length
    end function c_truncate
    !> C rename(3): atomically replaces the new path on POSIX systems.
    integer(c_int) function c_rename(old_path, new_path) bind(C, name='rename')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: old_path(*), new_path(*)
    end function c_rename
    !> POSIX realpath(3) into a caller's buffer of PATH_BUFFER bytes.
    type(c_ptr) function c_realpath(path, resolved) bind(C, name='realpath')
      import :: c_ptr, c_char
      character(kind=c_char), intent(in) :: path(*)
      character(kind=c_char), intent(out) :: resolved(*)
    end function c_realpath
  end interface

contains

  !> Remove a file if it exists and is not a symbolic link (a link a user put there, e.g. to
  !> /dev/null, is kept); removed says whether one was removed.
  subroutine remove_file(path, removed)
    character(len=*), intent(in) :: path                 !< the file
    logical, intent(out) :: removed                      !< it existed and is gone
    logical :: exists
    integer :: slash
    inquire(file=path, exist=exists)
    removed = .false.
    if (.not. exists) return
    ! a link resolves elsewhere than its directory's own entry of its name
    slash = index(path, '/', back=.true.)
    if (slash > 0) then
      if (canonical_path(path) /= canonical_path(path(1:slash - 1))//path(slash:)) return
    else
      if (canonical_path(path) /= canonical_path('.')//'/'//path) return
    end if
    removed = c_remove(path//c_null_char) == 0
  end subroutine remove_file

  !> The absolute path of an existing file with every link, '.' and '..' resolved (two names
  !> of one file give the same text); the path as given when that fails.
  function canonical_path(path) result(canonical)
    character(len=*), intent(in) :: path                 !< existing file
    character(len=:), allocatable :: canonical
    character(kind=c_char) :: resolved(PATH_BUFFER)
    integer :: n, k
    if (.not. c_associated(c_realpath(path//c_null_char, resolved))) then
      canonical = path
      return
    end if
    n = 0
    do while (n < PATH_BUFFER)
      if (resolved(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate(character(len=n) :: canonical)
    do k = 1, n
      canonical(k:k) = resolved(k)
    end do
  end function canonical_path

  !> Create directory path and any missing parents; ok is false when it cannot be made or its
  !> files cannot be created, and reason (if present) then names the part of the path that is
  !> in the way: a file where a directory should be, a directory that could not be created in
  !> its parent, or a directory that is not writable.
  subroutine make_directory(path, ok, reason)
    character(len=*), intent(in) :: path                          !< directory to create
    logical, intent(out) :: ok                                    !< usable afterwards
    character(len=:), allocatable, intent(out), optional :: reason !< why not (ok false)
    character(len=:), allocatable :: why
    integer :: k, rc, last
    last = len_trim(path)
    do k = 2, last
      if (path(k:k) == '/') rc = c_mkdir(path(1:k-1)//c_null_char, MODE_RWX)
    end do
    rc = c_mkdir(path(1:last)//c_null_char, MODE_RWX)
    why = ''
    do k = 2, last + 1                    ! the first prefix that is not a directory
      if (k <= last) then
        if (path(k:k) /= '/') cycle
      end if
      if (is_directory(path(1:k-1))) cycle
      if (exists(path(1:k-1))) then
        why = '"'//path(1:k-1)//'" is a file, not a directory'
      else
        why = 'the directory "'//path(1:k-1)//'" could not be created (no permission in its '// &
              'parent, a read-only file system, or no space left)'
      end if
      exit
    end do
    if (len(why) == 0) call probe_writable(path(1:last), why)
    ok = len(why) == 0
    if (present(reason)) reason = why
  end subroutine make_directory

  !> Create and delete a file in directory path: why is empty when that works, else says
  !> what the system answered (e.g. permission denied, read-only file system).
  subroutine probe_writable(path, why)
    character(len=*), intent(in) :: path                 !< an existing directory
    character(len=:), allocatable, intent(inout) :: why  !< the reason, or unchanged
    character(len=256) :: message
    integer :: unit, ios
    open(newunit=unit, file=path//'/.mefem_write_probe', status='replace', action='write', &
         iostat=ios, iomsg=message)
    if (ios /= 0) then
      why = 'files cannot be created in "'//path//'": '//trim(message)
      return
    end if
    close(unit, status='delete')
  end subroutine probe_writable

  !> Whether path names a directory.
  logical function is_directory(path)
    character(len=*), intent(in) :: path   !< path to test
    inquire(file=path//'/.', exist=is_directory)
  end function is_directory

  !> Whether anything (file or directory) is at path.
  logical function exists(path)
    character(len=*), intent(in) :: path   !< path to test
    inquire(file=path, exist=exists)
  end function exists

  !> Cut a file to its first nbytes bytes (a history file back to where a restart file left
  !> it); ok = .false. when it cannot be done.
  subroutine truncate_file(path, nbytes, ok)
    character(len=*), intent(in) :: path                 !< the file
    integer(i8), intent(in) :: nbytes                !< bytes kept
    logical, intent(out) :: ok                           !< done
    ok = c_truncate(path//c_null_char, int(nbytes, c_long)) == 0
  end subroutine truncate_file

  !> Rename a file over another (atomic on POSIX file systems); ok = .false. on failure.
  subroutine rename_file(old_path, new_path, ok)
    character(len=*), intent(in) :: old_path, new_path   !< from, to
    logical, intent(out) :: ok                           !< done
    ok = c_rename(old_path//c_null_char, new_path//c_null_char) == 0
  end subroutine rename_file

end module mefem_file_system
