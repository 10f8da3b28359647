!> The signals a batch system sends before it kills a job: SIGTERM (at the wall-clock limit,
!> SLURM's KillWait before its SIGKILL), SIGINT (Ctrl-C) and SIGUSR1 (what schedulers are told
!> to send ahead of the limit; mpirun passes it on to every rank). Once the analysis runs, a
!> handler records the signal; the time loops ask signal_caught at points where all ranks are,
!> agree over the ranks, finish the cycle or step, write the state reached, close every file
!> and leave with exit code 128 + the signal's number (signal_exit_code), what a shell reports
!> for a process the signal ended. Further signals change nothing: a scheduler signals every
!> process of a job, mpirun too, which passes the signal on, so each rank gets it twice (a
!> second signal that ended the process would undo the clean stop). SIGKILL ends a run at
!> once. Signal numbers are Linux's (x86-64 and arm64).
module mefem_signals
  use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc
  implicit none
  private

  public :: signals_install, signal_caught, signal_name, signal_record_stop, signal_exit_code

  integer(c_int), parameter :: SIGINT_NUMBER = 2      !< interrupt (Ctrl-C)
  integer(c_int), parameter :: SIGUSR1_NUMBER = 10    !< user signal 1
  integer(c_int), parameter :: SIGTERM_NUMBER = 15    !< termination request
  integer, parameter :: SIGNAL_EXIT_BASE = 128        !< exit code = base + signal number

  integer(c_int), volatile :: caught = 0              !< the last signal caught (0: none)
  integer :: stopped_by = 0                           !< the signal that stopped the analysis

  interface
    !> C library signal(): install a handler, return the previous one.
    function c_signal(signum, handler) bind(C, name='signal') result(previous)
      import :: c_int, c_funptr
      integer(c_int), value :: signum
      type(c_funptr), value :: handler
      type(c_funptr) :: previous
    end function c_signal
  end interface

contains

  !> Catch SIGTERM, SIGINT and SIGUSR1 from now on (called when the analysis starts: before
  !> it, the default action ends the process and nothing has been written).
  subroutine signals_install()
    type(c_funptr) :: previous
    previous = c_signal(SIGTERM_NUMBER, c_funloc(on_signal))
    previous = c_signal(SIGINT_NUMBER, c_funloc(on_signal))
    previous = c_signal(SIGUSR1_NUMBER, c_funloc(on_signal))
  end subroutine signals_install

  !> The handler: record the first signal (only an assignment: async-signal-safe).
  subroutine on_signal(signum) bind(C)
    integer(c_int), value, intent(in) :: signum  !< the signal
    if (caught == 0) caught = signum
  end subroutine on_signal

  !> The signal caught on this rank since signals_install (0: none).
  integer function signal_caught()
    signal_caught = int(caught)
  end function signal_caught

  !> Name of a signal number, for messages.
  function signal_name(signum) result(name)
    integer, intent(in) :: signum              !< signal number
    character(len=:), allocatable :: name
    select case (signum)
    case (SIGTERM_NUMBER)
      name = 'SIGTERM'
    case (SIGINT_NUMBER)
      name = 'SIGINT'
    case (SIGUSR1_NUMBER)
      name = 'SIGUSR1'
    case default
      name = 'a signal'
    end select
  end function signal_name

  !> Record that the analysis stopped because of signal signum (its exit code follows).
  subroutine signal_record_stop(signum)
    integer, intent(in) :: signum              !< the signal (agreed over the ranks)
    stopped_by = signum
  end subroutine signal_record_stop

  !> Exit code of the run: 128 + the signal that stopped the analysis, 0 when none did.
  integer function signal_exit_code()
    signal_exit_code = 0
    if (stopped_by > 0) signal_exit_code = SIGNAL_EXIT_BASE + stopped_by
  end function signal_exit_code

end module mefem_signals
