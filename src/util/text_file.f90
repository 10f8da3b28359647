!> Text files whose every write is checked, through the C library's buffered streams (and
!> the run's log on standard output, text_put_stdout).
!>
!> Why not Fortran units: gfortran's run-time library does not report a failed write(2) of a
!> formatted or stream unit. On a full file system (a 64 KiB tmpfs) or on /dev/full, WRITE,
!> FLUSH and CLOSE all return IOSTAT = 0 while the kernel answers ENOSPC, and INQUIRE(SIZE=)
!> returns the library's count, not the file's (measured with gfortran 12, Debian 12): a run
!> would end "successfully" with truncated histories. fputs/fflush/fclose do return the error,
!> and errno names it. The files are named by small integer handles (text_open), so callers keep
!> the shape of unit numbers. Every routine returns ok and the system's reason; the caller
!> decides (the history writers stop the run with the path and the reason).
module mefem_text_file
  use, intrinsic :: iso_c_binding, only: c_ptr, c_char, c_int, c_null_ptr, c_null_char, &
                                         c_associated, c_f_pointer, c_size_t
  implicit none
  private

  public :: text_open, text_put, text_flush, text_close, text_put_stdout

  integer, parameter :: MAX_FILES = 32           !< files open at the same time
  type(c_ptr), save :: streams(MAX_FILES) = c_null_ptr   !< FILE* of each handle
  type(c_ptr), save :: log_stream = c_null_ptr           !< standard output (file 1), opened
                                                         !< by text_put_stdout at first use

  interface
    function c_fopen(path, mode) bind(C, name='fopen') result(stream)
      import :: c_ptr, c_char
      character(kind=c_char), intent(in) :: path(*), mode(*)
      type(c_ptr) :: stream
    end function c_fopen
    function c_fdopen(descriptor, mode) bind(C, name='fdopen') result(stream)
      import :: c_ptr, c_char, c_int
      integer(c_int), value :: descriptor
      character(kind=c_char), intent(in) :: mode(*)
      type(c_ptr) :: stream
    end function c_fdopen
    function c_fputs(text, stream) bind(C, name='fputs') result(status)
      import :: c_ptr, c_char, c_int
      character(kind=c_char), intent(in) :: text(*)
      type(c_ptr), value :: stream
      integer(c_int) :: status
    end function c_fputs
    function c_fflush(stream) bind(C, name='fflush') result(status)
      import :: c_ptr, c_int
      type(c_ptr), value :: stream
      integer(c_int) :: status
    end function c_fflush
    function c_fclose(stream) bind(C, name='fclose') result(status)
      import :: c_ptr, c_int
      type(c_ptr), value :: stream
      integer(c_int) :: status
    end function c_fclose
    function c_errno_location() bind(C, name='__errno_location') result(location)
      import :: c_ptr
      type(c_ptr) :: location
    end function c_errno_location
    function c_strerror(number) bind(C, name='strerror') result(text)
      import :: c_ptr, c_int
      integer(c_int), value :: number
      type(c_ptr) :: text
    end function c_strerror
    function c_strlen(text) bind(C, name='strlen') result(length)
      import :: c_ptr, c_size_t
      type(c_ptr), value :: text
      integer(c_size_t) :: length
    end function c_strlen
  end interface

contains

  !> Open path for writing, replacing it (or appending to it); handle > 0 when ok.
  subroutine text_open(path, append, handle, ok, message)
    character(len=*), intent(in) :: path            !< file to write
    logical, intent(in) :: append                   !< keep its content and write after it
    integer, intent(out) :: handle                  !< the file's handle (0 on failure)
    logical, intent(out) :: ok                      !< opened
    character(len=:), allocatable, intent(out) :: message  !< the reason when not
    integer :: k
    handle = 0
    ok = .false.
    message = ''
    do k = 1, MAX_FILES
      if (.not. c_associated(streams(k))) then
        handle = k
        exit
      end if
    end do
    if (handle == 0) then
      message = 'too many text files open'
      return
    end if
    streams(handle) = c_fopen(path//c_null_char, merge('a', 'w', append)//c_null_char)
    ok = c_associated(streams(handle))
    if (.not. ok) then
      message = system_error()
      handle = 0
    end if
  end subroutine text_open

  !> Write text and a newline (buffered: a failure may show at the next flush).
  subroutine text_put(handle, text, ok, message)
    integer, intent(in) :: handle                   !< open file
    character(len=*), intent(in) :: text            !< the line, without its newline
    logical, intent(out) :: ok                      !< written
    character(len=:), allocatable, intent(out) :: message  !< the reason when not
    call check_handle(handle, ok, message)
    if (.not. ok) return
    ok = c_fputs(text//new_line('a')//c_null_char, streams(handle)) >= 0
    if (.not. ok) message = system_error()
  end subroutine text_put

  !> Hand the buffered lines to the system (they are in the file afterwards).
  subroutine text_flush(handle, ok, message)
    integer, intent(in) :: handle                   !< open file
    logical, intent(out) :: ok                      !< flushed
    character(len=:), allocatable, intent(out) :: message  !< the reason when not
    call check_handle(handle, ok, message)
    if (.not. ok) return
    ok = c_fflush(streams(handle)) == 0
    if (.not. ok) message = system_error()
  end subroutine text_flush

  !> Flush and close; the handle is free afterwards, whatever the outcome.
  subroutine text_close(handle, ok, message)
    integer, intent(in) :: handle                   !< open file
    logical, intent(out) :: ok                      !< closed with everything written
    character(len=:), allocatable, intent(out) :: message  !< the reason when not
    call check_handle(handle, ok, message)
    if (.not. ok) return
    ok = c_fclose(streams(handle)) == 0
    streams(handle) = c_null_ptr
    if (.not. ok) message = system_error()
  end subroutine text_close

  !> Write text and a newline to standard output (the run's log) and flush it: ok is false when
  !> the system refused it (a log on a full disk).
  subroutine text_put_stdout(text, ok, message)
    character(len=*), intent(in) :: text            !< the line, without its newline
    logical, intent(out) :: ok                      !< written
    character(len=:), allocatable, intent(out) :: message  !< the reason when not
    message = ''
    if (.not. c_associated(log_stream)) log_stream = c_fdopen(1_c_int, 'a'//c_null_char)
    ok = c_associated(log_stream)
    if (ok) ok = c_fputs(text//new_line('a')//c_null_char, log_stream) >= 0
    if (ok) ok = c_fflush(log_stream) == 0
    if (.not. ok) message = system_error()
  end subroutine text_put_stdout

  !> ok when handle names an open file (else the message says it does not).
  subroutine check_handle(handle, ok, message)
    integer, intent(in) :: handle                   !< handle
    logical, intent(out) :: ok                      !< an open file
    character(len=:), allocatable, intent(out) :: message  !< '' or why not
    message = ''
    ok = .false.
    if (handle >= 1 .and. handle <= MAX_FILES) ok = c_associated(streams(handle))
    if (.not. ok) message = 'not an open text file'
  end subroutine check_handle

  !> The C library's text for the current errno (e.g. "No space left on device").
  function system_error() result(text)
    character(len=:), allocatable :: text
    integer(c_int), pointer :: errno
    type(c_ptr) :: message
    character(kind=c_char), pointer :: chars(:)
    integer :: n, k
    call c_f_pointer(c_errno_location(), errno)
    message = c_strerror(errno)
    n = int(c_strlen(message))
    call c_f_pointer(message, chars, [n])
    allocate(character(len=n) :: text)
    do k = 1, n
      text(k:k) = chars(k)
    end do
  end function system_error

end module mefem_text_file
