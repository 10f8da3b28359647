!> File-system helpers: create a directory (with its parents), as `mkdir -p` does.
module mefem_file_system
  use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
  implicit none
  private

  public :: make_directory

  interface
    !> POSIX mkdir(2).
    integer(c_int) function c_mkdir(path, mode) bind(C, name='mkdir')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int), value :: mode
    end function c_mkdir
  end interface

contains

  !> Create directory path and any missing parents; ok is false when it cannot be made.
  subroutine make_directory(path, ok)
    character(len=*), intent(in) :: path   !< directory to create
    logical, intent(out) :: ok             !< the directory exists afterwards
    integer :: k, rc
    integer(c_int), parameter :: MODE_RWX = int(o'755', c_int)
    logical :: exists
    do k = 2, len_trim(path)
      if (path(k:k) == '/') rc = c_mkdir(path(1:k-1)//c_null_char, MODE_RWX)
    end do
    rc = c_mkdir(trim(path)//c_null_char, MODE_RWX)
    inquire(file=trim(path)//'/.', exist=exists)
    ok = exists
  end subroutine make_directory

end module mefem_file_system
