!> Error handling for all of mefem: three verbs and a counter.
!>
!> - input_error: a problem in the user's deck; printed as `file:line: *KEYWORD: message`,
!>   counted, and reading goes on so that all problems are reported in one pass;
!> - warn / warn_once: questionable but usable input;
!> - fatal: an unrecoverable error; printed, then every rank stops with a non-zero code.
!> Only rank 0 prints input messages (every rank reads the same deck and finds the same
!> problems). status_t carries a failure out of a kernel to the driver that can react.
!> Every line printed on rank 0 (say, warn, input_error, fatal) also goes to the run's log
!> file once log_open has named it (<output>/mefem.log); the lines printed before that are
!> kept and written first, so the file holds the whole run, deck checks included.
module mefem_errors
  use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
  use, intrinsic :: iso_c_binding, only: c_int
  use mefem_comm, only: comm_is_root, comm_abort, comm_finalize, comm_barrier
  use mefem_text_file, only: text_put_stdout, text_open, text_put, text_flush, text_close
  implicit none
  private

  public :: input_error, input_error_count, reset_input_errors, unprinted_error_summary
  public :: warn, warn_once, fatal, fatal_local, fatal_abort, say, terminate, log_open
  public :: status_t

  integer, parameter :: MAX_PRINTED = 500   !< input errors printed before the rest is only counted
  integer, parameter :: MAX_WARN_KEYS = 200 !< distinct warn_once keys remembered
  integer, parameter :: MAX_UNPRINTED_KINDS = 50 !< keywords whose unprinted errors are counted

  integer :: n_input_errors = 0
  integer :: n_warn_keys = 0
  integer :: log_handle = 0                 !< the log file (mefem_text_file), 0: not open
  character(len=:), allocatable :: early_log !< lines printed before the log file opened
  character(len=80) :: warn_keys(MAX_WARN_KEYS)
  !> Input errors beyond MAX_PRINTED, counted per keyword (the "*KEYWORD" of their location;
  !> the last slot takes every keyword beyond the table)
  integer :: n_unprinted_kinds = 0
  character(len=64) :: unprinted_keyword(MAX_UNPRINTED_KINDS)
  integer :: unprinted_count(MAX_UNPRINTED_KINDS) = 0

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
        call log_line(trim(where)//': '//trim(message))
      else
        write(error_unit, '(a)') 'mefem: '//trim(message)
        call log_line('mefem: '//trim(message))
      end if
    else
      if (n_input_errors == MAX_PRINTED + 1) then
        write(error_unit, '(a)') 'mefem: further input errors are counted but not printed'
        call log_line('mefem: further input errors are counted but not printed')
      end if
      call count_unprinted(where)
    end if
    ! unbuffered in effect: a log redirected to a file keeps every message in order with the
    ! standard output's, and keeps it if the run is killed
    if (n_input_errors <= MAX_PRINTED + 1) then
      call flush_output()
    end if
  end subroutine input_error

  !> Count an unprinted input error under its keyword (the text from the last '*' of where).
  subroutine count_unprinted(where)
    character(len=*), intent(in) :: where    !< "file:line: *KEYWORD" (or empty)
    character(len=64) :: keyword
    integer :: k, star
    star = index(where, '*', back=.true.)
    keyword = '(no keyword)'
    if (star > 0) keyword = where(star:)
    do k = 1, n_unprinted_kinds
      if (unprinted_keyword(k) == keyword) exit
    end do
    if (k > n_unprinted_kinds) then
      if (n_unprinted_kinds < MAX_UNPRINTED_KINDS) then
        n_unprinted_kinds = n_unprinted_kinds + 1
        unprinted_keyword(n_unprinted_kinds) = keyword
      else
        unprinted_keyword(MAX_UNPRINTED_KINDS) = '(other keywords)'
      end if
      k = n_unprinted_kinds
    end if
    unprinted_count(k) = unprinted_count(k) + 1
  end subroutine count_unprinted

  !> The input errors that were counted but not printed, per keyword, on rank 0 (nothing
  !> when every error was printed).
  subroutine unprinted_error_summary()
    integer :: k
    character(len=12) :: number
    if (n_unprinted_kinds == 0) return
    call say('mefem: input errors not printed, by keyword:')
    do k = 1, n_unprinted_kinds
      write(number, '(i12)') unprinted_count(k)
      call say('  '//trim(adjustl(number))//' at '//trim(unprinted_keyword(k)))
    end do
  end subroutine unprinted_error_summary

  !> Number of input errors recorded so far.
  integer function input_error_count()
    input_error_count = n_input_errors
  end function input_error_count

  !> Forget recorded input errors and warnings (used by unit tests).
  subroutine reset_input_errors()
    n_input_errors = 0
    n_warn_keys = 0
    n_unprinted_kinds = 0
    unprinted_count = 0
  end subroutine reset_input_errors

  !> Print a warning on rank 0.
  subroutine warn(message)
    character(len=*), intent(in) :: message  !< the warning text
    if (comm_is_root()) then
      write(error_unit, '(a)') 'warning: '//trim(message)
      call flush_output()
      call log_line('warning: '//trim(message))
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
      call log_line(trim(message))
    end if
  end subroutine say

  !> An error every rank detects alike: print on rank 0, finish MPI, exit with code 1.
  subroutine fatal(message)
    character(len=*), intent(in) :: message  !< what went wrong and where
    if (comm_is_root()) then
      write(error_unit, '(a)') 'mefem: error: '//trim(message)
      call log_line('mefem: error: '//trim(message))
    end if
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
      call log_line('mefem: error: '//trim(message))
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
    logical :: ok
    character(len=:), allocatable :: reason
    flush(output_unit)
    flush(error_unit)
    if (log_handle > 0) call text_close(log_handle, ok, reason)
    log_handle = 0
    call comm_finalize()
    call c_exit(int(code, c_int))
  end subroutine terminate

  !> The run's log file (rank 0): open path, write the lines printed so far, and tee every
  !> later line into it. A log that cannot be written stops the run (as the histories do).
  subroutine log_open(path, append)
    character(len=*), intent(in) :: path     !< e.g. <output>/mefem.log
    logical, intent(in), optional :: append  !< keep what it holds (a restarted run)
    logical :: ok, appending
    character(len=:), allocatable :: reason
    integer :: start, finish
    if (.not. comm_is_root()) return
    if (log_handle > 0) call text_close(log_handle, ok, reason)
    appending = .false.
    if (present(append)) appending = append
    call text_open(path, appending, log_handle, ok, reason)
    if (.not. ok) call log_failed(path, reason)
    if (allocated(early_log)) then
      start = 1
      do while (start <= len(early_log))
        finish = index(early_log(start:), new_line('a')) + start - 1
        call text_put(log_handle, early_log(start:finish - 1), ok, reason)
        if (.not. ok) call log_failed(path, reason)
        start = finish + 1
      end do
      deallocate(early_log)
    end if
    call text_flush(log_handle, ok, reason)
    if (.not. ok) call log_failed(path, reason)
  contains
    !> Stop: the log file is not writable.
    subroutine log_failed(where, why)
      character(len=*), intent(in) :: where, why   !< file and the system's reason
      log_handle = 0
      write(error_unit, '(a)') 'mefem: error: cannot write the log file '//where//': '//why
      flush(error_unit)
      call comm_abort(1)
    end subroutine log_failed
  end subroutine log_open

  !> One line of rank 0's output into the log file (kept in memory until it opens).
  subroutine log_line(text)
    character(len=*), intent(in) :: text     !< the line
    logical :: ok
    character(len=:), allocatable :: reason
    if (log_handle > 0) then
      call text_put(log_handle, text, ok, reason)
      if (ok) call text_flush(log_handle, ok, reason)
      if (.not. ok) then
        log_handle = 0
        write(error_unit, '(a)') 'mefem: error: cannot write the log file: '//reason
        flush(error_unit)
        call comm_abort(1)
      end if
    else
      if (.not. allocated(early_log)) early_log = ''
      early_log = early_log//text//new_line('a')
    end if
  end subroutine log_line

end module mefem_errors
