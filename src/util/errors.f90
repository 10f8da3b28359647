!> Error handling for all of mefem: three verbs and a counter.
!>
!> - input_error: a problem in the user's deck; printed as `file:line: *KEYWORD: message`,
!>   counted, and reading goes on so that all problems are reported in one pass;
!> - warn / warn_once: questionable but usable input;
!> - fatal: an unrecoverable error; printed, then every rank stops with a non-zero code.
!> Only rank 0 prints input messages (every rank reads the same deck and finds the same
!> problems). status_t carries a failure out of a kernel to the driver that can react.
module mefem_errors
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use, intrinsic :: iso_c_binding, only: c_int
  use mefem_comm, only: comm_is_root, comm_abort, comm_finalize, comm_barrier
  use mefem_text_file, only: text_put_stdout
  implicit none
  private

  public :: input_error, input_error_count, reset_input_errors
  public :: warn, warn_once, fatal, fatal_local, fatal_abort, say, terminate
  public :: status_t

  integer, parameter :: MAX_PRINTED = 500   !< input errors printed before the rest is only counted
  integer, parameter :: MAX_WARN_KEYS = 200 !< distinct warn_once keys remembered

  integer :: n_input_errors = 0
  integer :: n_warn_keys = 0
  character(len=80) :: warn_keys(MAX_WARN_KEYS)

  !> Outcome of an operation that can fail because of the user's data.
  interface
    !> The C library's exit: ends the process with a status and no extra text.
    subroutine c_exit(status) bind(C, name='exit')
      import :: c_int
      integer(c_int), value :: status
    end subroutine c_exit
  end interface

  type, public :: status_t
    logical :: ok = .true.                   !< false after a failure
    character(len=:), allocatable :: message !< what failed, where (element, node, time)
  end type status_t

contains

  !> Record one problem of the input deck; `where` is "file:line: *KEYWORD".
  subroutine input_error(where, message)
    character(len=*), intent(in) :: where    !< location prefix built by the reader
    character(len=*), intent(in) :: message  !< what is wrong, quoting the offending text
    n_input_errors = n_input_errors + 1
    if (.not. comm_is_root()) return
    if (n_input_errors <= MAX_PRINTED) then
      if (len_trim(where) > 0) then
        write(error_unit, '(a)') trim(where)//': '//trim(message)
      else
        write(error_unit, '(a)') 'mefem: '//trim(message)
      end if
    else if (n_input_errors == MAX_PRINTED + 1) then
      write(error_unit, '(a)') 'mefem: further input errors are counted but not printed'
    end if
    ! unbuffered in effect: a log redirected to a file keeps every message in order with the
    ! standard output's, and keeps it if the run is killed
    if (n_input_errors <= MAX_PRINTED + 1) then
      call flush_output()
    end if
  end subroutine input_error

  !> Number of input errors recorded so far.
  integer function input_error_count()
    input_error_count = n_input_errors
  end function input_error_count

  !> Forget recorded input errors and warnings (used by unit tests).
  subroutine reset_input_errors()
    n_input_errors = 0
    n_warn_keys = 0
  end subroutine reset_input_errors

  !> Print a warning on rank 0.
  subroutine warn(message)
    character(len=*), intent(in) :: message  !< the warning text
    if (comm_is_root()) then
      write(error_unit, '(a)') 'warning: '//trim(message)
      call flush_output()
    end if
  end subroutine warn

  !> Print a warning once per key (e.g. once per ignored keyword name).
  subroutine warn_once(key, message)
    character(len=*), intent(in) :: key      !< what makes two warnings the same
    character(len=*), intent(in) :: message  !< the warning text
    integer :: i
    do i = 1, n_warn_keys
      if (warn_keys(i) == key) return
    end do
    if (n_warn_keys < MAX_WARN_KEYS) then
      n_warn_keys = n_warn_keys + 1
      warn_keys(n_warn_keys) = key
    end if
    call warn(message)
  end subroutine warn_once

  !> Print a line of progress or information on rank 0 (the run's log, standard output,
  !> through the C library: a write the system refuses, e.g. a log on a full disk, stops the
  !> run with the reason on standard error; gfortran's units do not report it).
  subroutine say(message)
    character(len=*), intent(in) :: message  !< the text
    logical :: ok
    character(len=:), allocatable :: reason
    if (comm_is_root()) then
      call text_put_stdout(trim(message), ok, reason)
      if (.not. ok) then
        write(error_unit, '(a)') 'mefem: error: cannot write the log (standard output): '// &
                                 reason
        flush(error_unit)
        call comm_abort(1)
      end if
    end if
  end subroutine say

  !> An error every rank detects alike: print on rank 0, finish MPI, exit with code 1.
  subroutine fatal(message)
    character(len=*), intent(in) :: message  !< what went wrong and where
    if (comm_is_root()) write(error_unit, '(a)') 'mefem: error: '//trim(message)
    call terminate(1)
  end subroutine fatal

  !> An error every rank detects alike, when finishing MPI is not safe (the HDF5 file after a
  !> failed write: MPI_Finalize lets HDF5 close it, which crashed on a full disk): print on
  !> rank 0, abort all ranks (exit code 1). Files flushed before stay as they are.
  subroutine fatal_abort(message)
    character(len=*), intent(in) :: message  !< what went wrong and where
    if (comm_is_root()) then
      write(error_unit, '(a)') 'mefem: error: '//trim(message)
      call flush_output()
    end if
    call comm_barrier()
    call comm_abort(1)
  end subroutine fatal_abort

  !> An error found on one rank only: print it from this rank and abort all ranks.
  subroutine fatal_local(message)
    character(len=*), intent(in) :: message  !< what went wrong and where
    write(error_unit, '(a)') 'mefem: error: '//trim(message)
    flush(error_unit)
    call comm_abort(1)
  end subroutine fatal_local

  !> Flush standard output and standard error (rank 0's messages reach a redirected log at
  !> once and in the order they were written).
  subroutine flush_output()
    flush(output_unit)
    flush(error_unit)
  end subroutine flush_output

  !> Finish MPI and end the program with the given exit code (0 = success).
  subroutine terminate(code)
    integer, intent(in) :: code   !< process exit code
    flush(output_unit)
    flush(error_unit)
    call comm_finalize()
    call c_exit(int(code, c_int))
  end subroutine terminate

end module mefem_errors
